{ df1demo - a DF1 echo exchange with no hardware: a master (DF1Transact,
  as in df1echo) and a slave (tDF1Station answering from the default SLC
  table, as in df1slave) in one process, joined by the in-memory null modem
  NAM=LOOP, first in full duplex with CRC, then in half duplex with BCC
  (poll / EOT / data / ACK). Prints every message and the wire bytes of
  each frame sent; exit code 0 when both exchanges succeed. It takes no
  arguments (but --help and --version, unit ChnCli). }
program df1demo;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnDF1, ChnSlc, ChnDF1Link, ChnCli;

var
  Cli: tCli;
  Table: tSlcTable;
  Slave: tDF1Station;
  Failures: Integer;

procedure MasterLog(const Line: string);
begin
  WriteLn('master ', Line);
end;

procedure SlaveLog(const Line: string);
begin
  WriteLn('slave  ', Line);
end;

{ the slave runs while the master waits }
procedure RunSlave(Data: Pointer);
begin
  DF1StationStep(pDF1Station(Data)^);
end;

function Open(const Params: string): pChnVirt;
var
  Err: string;
begin
  Result := DF1OpenStack(Params, 1000, Err);
  if Result = nil then
  begin
    WriteLn(StdErr, 'df1demo: ', Err);
    Halt(1);
  end;
end;

procedure Run(const Title, MasterParams, SlaveParams, Text: string; Tns: Word);
var
  M, S: pChnVirt;
  Req: tSendRecord;
  Rep: tRecRecord;
  ReqLen, RepLen: Word;
  R: tChResult;
  Deadline: QWord;
begin
  WriteLn;
  WriteLn('== ', Title);
  M := Open(MasterParams);
  S := Open(SlaveParams);
  WriteLn('master: ', M^.ChGetParam(''));
  WriteLn('slave : ', S^.ChGetParam(''));
  SlcStationInit(Slave, S, @Table);
  Slave.Log := @SlaveLog;
  Slave.LogWire := True;
  { the Echo command of manual section 6.3.1 }
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_Echo;
  Req.Tns := Tns;
  Move(Text[1], Req.Data[0], Length(Text));
  ReqLen := 8 + Length(Text);
  RepLen := 0;
  R := DF1Transact(M, Req, ReqLen, Rep, RepLen, @RunSlave, @Slave, DF1LinkTimeoutMs,
    @MasterLog, True);
  { let the slave take the master's last ACK }
  Deadline := ChMsTick + 100;
  while not DF1StationStep(Slave) and (ChMsTick <= Deadline) do
    ChnWaitAny(10);                { the slave's line, at most 10 ms }
  { an echo: the same TNS (DF1Transact checked it), STS 0 and the data back }
  if (R = res_Ok) and (Rep.Sts = 0) and (RepLen = ReqLen) and
     (CompareByte(Rep.Data, Req.Data, ReqLen - 8) = 0) then
    WriteLn('echo ok')
  else
  begin
    WriteLn('echo FAILED: ', M^.ChResultStr(R));
    Inc(Failures);
  end;
  Dispose(M, Done);
  Dispose(S, Done);
end;

begin
  CliInit(Cli, 'df1demo', '[OPTION]',
    'A DF1 echo exchange with no hardware: a master and a slave in one process, ' +
    'joined by the in-memory null modem NAM=LOOP, first in full duplex with CRC, ' +
    'then in half duplex with BCC; every message and the wire bytes of each frame ' +
    'are printed. It takes no arguments.');
  CliNoArgsOk(Cli);
  CliExit(Cli, 0, 'both exchanges succeeded');
  CliExit(Cli, 1, 'one exchange failed (3: both; the number of failures, never 2)');
  CliParse(Cli);
  if CliArgCount(Cli) > 0 then
    CliUsageError(Cli, 'no arguments wanted', Cli.Args[0]);
  Failures := 0;
  SlcLoadDefault(Table);
  Run('full duplex, CRC (manual section 7)',
      'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON NAM=LOOP PAIR=DEMO1 END=1',
      'NAM=DF1 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=DEMO1 END=2',
      'Ahoj', 10);
  Run('half duplex, BCC, station 16 ($10 is stuffed), data with DLE bytes',
      'NAM=DF1 NOD=1 DNO=16 MAS=MASTER FHD=HALF CRC=OFF NAM=LOOP PAIR=DEMO2 END=1',
      'NAM=DF1 NOD=16 DNO=1 MAS=SLAVE FHD=HALF CRC=OFF NAM=LOOP PAIR=DEMO2 END=2',
      'A'#$10'B', 11);
  WriteLn;
  if Failures = 0 then
    WriteLn('df1demo: all exchanges ok')
  else
    WriteLn('df1demo: ', Failures, ' exchange(s) failed');
  if Failures = 2 then
    Failures := 3;               { 2 is a usage error }
  Halt(Failures);
end.
