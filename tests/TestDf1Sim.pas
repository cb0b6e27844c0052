{ Tests of the DF1 simulator: the station of unit ChnDF1Link answering from
  a ChnSlc table, against a master built on tChnDF1 (DF1Transact) over the
  in-memory null modem NAM=LOOP, in full and half duplex with CRC and BCC;
  its link behaviour byte by byte against a raw LOOP end (frames and
  checksums worked out by hand); and tools/df1sim itself, started with
  --pty through TProcess and spoken to over NAM=COM. }
unit TestDf1Sim;

{$MODE OBJFPC}{$H+}

interface

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt,
  ChnLoop, ChnCom, ChnDF1, ChnSlc, ChnDF1Link, ChnWait, ChnPcccClient, TestSupport, BinSupport, Df1Pair, SlcAsk
  {$IFDEF UNIX}, PtyPair, ProcStat{$ENDIF};

type
  TTestDf1Sim = class(TDf1PairCase)
  private
    { one exchange through DF1Transact; 'STS=xx data...' }
    function Ask(CF: Word; const DataHex: string; Tns: Word): string;
    procedure AllCommands(Full, Crc: Boolean; const Pair: string);
    { raw end: send hex, collect what comes back within Ms (stepping the station) }
    function RawSay(const Hex: string; Ms: Integer): string;
    function Scripted(const Answer: string; TimeoutMs: LongInt; var Rep: tRecRecord): tChResult;
  protected
    procedure SetUp; override;
  published
    procedure TestFullDuplexCrc;
    procedure TestFullDuplexBcc;
    procedure TestHalfDuplexCrc;
    procedure TestHalfDuplexBcc;
    procedure TestFullDuplexLinkBytes;
    procedure TestHalfDuplexLinkBytes;
    procedure TestNakOfReplySendsItAgain;
    procedure TestRepeatedCommandFullDuplex;
    procedure TestRepeatedCommandHalfDuplex;
    procedure TestRepeatedCommandWithoutDup;
    procedure TestRepeatedCommandAfterAnotherSource;
    {$IFDEF UNIX}
    procedure TestBinaryOverPty;   { df1sim --pty: a Unix pty }
    procedure TestPtyTakesBdAndPar;
    procedure TestFreeRunningClockOverPty;
    procedure TestIdleSimWaitsForTheLine;
    {$ENDIF}
    procedure TestLogLines;
    procedure TestLogNoAck;
    procedure TestOpenStack;
    procedure TestTransactGivesBackTheReceiveBuffer;
    {$IFDEF UNIX}
    procedure TestTransactReportsLostLine;   { a pty that is hung up }
    {$ENDIF}
    procedure TestTransactChecksTheReply;
    procedure TestTransactSkipsALateReply;
    procedure TestTransactNaksABrokenReply;
    procedure TestHelpersRefuseAnotherLayer;
  end;

implementation

const
  Config = 'N7 20'#10'N7:0 = 1 2 3 -1 $1234'#10'F8 2'#10'F8:0 = 1.5'#10 +
           'B3 2'#10'S2 4'#10'N9 8'#10'N9:0 = $0102 $0304'#10;

var
  LogText: string;   { what MasterLog and StationLog were given }

procedure MasterLog(const Line: string);
begin
  LogText := LogText + 'M ' + Line + #10;
end;

procedure StationLog(const Line: string);
begin
  LogText := LogText + 'S ' + Line + #10;
end;

{ Echo of 'A' (send 9 bytes, or 8 for no data) }
procedure EchoA(out Req: tSendRecord; Tns: Word);
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_Echo;
  Req.Tns := Tns;
  Req.Data[0] := $41;
end;

procedure StepStation(Data: Pointer);
begin
  DF1StationStep(pDF1Station(Data)^);
end;

procedure TTestDf1Sim.SetUp;
begin
  inherited SetUp;
  LoadTable(Config);
end;

function TTestDf1Sim.Ask(CF: Word; const DataHex: string; Tns: Word): string;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  N: Integer;
  R: tChResult;
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF;
  Req.Tns := Tns;
  N := PutHex(DataHex, Req.Data);
  RepLen := 0;
  R := DF1Transact(Master, Req, 8 + N, Rep, RepLen, @StepStation, @Station, 500);
  AssertEquals('transaction result', res_Ok, R);
  AssertEquals('reply CF: the command''s, FNC included', CF or $4000, Rep.CF);
  AssertEquals('reply TNS', Tns, Rep.Tns);
  Result := ReplyText(Rep.Sts, Rep.Data, RepLen - 8);
end;

procedure TTestDf1Sim.AllCommands(Full, Crc: Boolean; const Pair: string);
begin
  StartPair(Full, Crc, Pair);
  AssertEquals('echo', 'STS=00 41 68 6F 6A', Ask(CF_Echo, '41 68 6F 6A', 1));
  { mode, type, series/revision and 'df1sim' (TestChnSlc.TestDiagnostics) }
  AssertEquals('diagnostic status', 'STS=00 06 EE 49 00 21 64 66 31 73 69 6D',
    Ask(CF_DiagnosticSts, '', 2));
  { good frames in: echo, status and this one; ADDR 0 SIZE 2 }
  AssertEquals('read counters', 'STS=00 03 00', Ask(CF_ReadDiagnCounts, '00 00 02', 3));
  AssertEquals('reset counters', 'STS=00', Ask(CF_ResetDiagnCounts, '', 4));
  AssertEquals('read counters after reset: this command', 'STS=00 01 00',
    Ask(CF_ReadDiagnCounts, '00 00 02', 5));
  AssertEquals('typed read N7:0..4', 'STS=00 01 00 02 00 03 00 FF FF 34 12',
    Ask(CF_ProtectRead3Addr, '0A 07 89 00 00', 6));
  AssertEquals('typed write N7:10', 'STS=00', Ask(CF_ProtectWrite3Addr, '02 07 89 0A 00 39 30', 7));
  AssertEquals('table written', 12345, SlcGetWord(Table, 7, 10));
  AssertEquals('typed read F8:0', 'STS=00 00 00 C0 3F', Ask(CF_ProtectRead3Addr, '04 08 8A 00 00', 8));
  AssertEquals('unprotected read', 'STS=00 02 01 04 03', Ask(CF_UnProtectRead, '00 00 04', 9));
  AssertEquals('unprotected write', 'STS=00', Ask(CF_UnProtectWrite, '04 00 CD AB', 10));
  AssertEquals('N9:2', $ABCD, SlcGetWord(Table, 9, 2));
  AssertEquals('missing file N11', 'STS=F0 06', Ask(CF_ProtectRead3Addr, '02 0B 89 00 00', 11));
  AssertEquals('N7:30 out of range', 'STS=F0 06', Ask(CF_ProtectRead3Addr, '02 07 89 1E 00', 12));
  AssertEquals('N7:18 + 4 elements', 'STS=F0 07', Ask(CF_ProtectRead3Addr, '08 07 89 12 00', 13));
  AssertEquals('unprotected past the CIF', 'STS=50', Ask(CF_UnProtectRead, '10 00 02', 14));
  AssertEquals('unknown command', 'STS=10', Ask($0609, '', 15));
  AssertEquals('requests answered', 15, Station.Requests);
end;

procedure TTestDf1Sim.TestFullDuplexCrc;
begin
  AllCommands(True, True, 'SIMFC');
end;

procedure TTestDf1Sim.TestFullDuplexBcc;
begin
  AllCommands(True, False, 'SIMFB');
end;

procedure TTestDf1Sim.TestHalfDuplexCrc;
begin
  AllCommands(False, True, 'SIMHC');
end;

procedure TTestDf1Sim.TestHalfDuplexBcc;
begin
  AllCommands(False, False, 'SIMHB');
end;

function TTestDf1Sim.RawSay(const Hex: string; Ms: Integer): string;
var
  D: TBytes;
  Buf: array[0..511] of Byte;
  Len: Word;
  Got: AnsiString;
  Deadline: QWord;
  Polls: Integer;
begin
  D := HexToBytes(Hex);
  if Length(D) > 0 then
  begin
    Raw^.ChSend(@D[0], Length(D));
    AssertEquals('raw send', res_Ok, Raw^.ChSendResult);
  end;
  Got := '';
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := ChMsTick + QWord(Ms);
  Polls := 0;
  { Ms of wall time and at least 100 rounds (100 rounds alone get every
    answer here): a loaded machine that takes the CPU away for Ms must not
    cut an answer short }
  repeat
    Inc(Polls);
    DF1StationStep(Station);
    if Raw^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      Raw^.ChReceive(Len);
      if Got <> '' then
        Got := Got + ' ';
      Got := Got + BytesToHex(Buf, Len);
    end;
  until (ChMsTick > Deadline) and (Polls >= 100);
  Result := Got;
end;

procedure TTestDf1Sim.TestFullDuplexLinkBytes;
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=SIMLF END=2');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMLF END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('ENQ before anything: NAK', '10 15', RawSay('10 05', 50));
  { echo 'A', TNS 5, CRC $C1D7 by hand; one wrong CRC byte -> NAK }
  AssertEquals('bad CRC: NAK', '10 15', RawSay('10 02 01 00 06 00 05 00 00 41 10 03 D7 C2', 50));
  AssertEquals('ENQ repeats the NAK', '10 15', RawSay('10 05', 50));
  AssertEquals('nothing executed', 0, Station.Requests);
  AssertEquals('good frame: ACK, then the reply',
    '10 06 10 02 00 01 46 00 05 00 41 10 03 6E FB',
    StringReplace(RawSay('10 02 01 00 06 00 05 00 00 41 10 03 D7 C1', 50), '  ', ' ', [rfReplaceAll]));
  AssertEquals('ENQ repeats the ACK', '10 06', RawSay('10 05', 50));
  AssertEquals('ACK of the reply: silence', '', RawSay('10 06', 50));
  AssertEquals('NAKs sent counted', 1, Table.Diag[dgNaksOut]);
  AssertEquals('ENQs counted', 3, Table.Diag[dgEnqsIn]);
end;

procedure TTestDf1Sim.TestHalfDuplexLinkBytes;
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=HALF CRC=OFF NAM=LOOP PAIR=SIMLH END=2');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMLH END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('poll, nothing to send: EOT', '10 04', RawSay('10 05 01 FF', 50));
  AssertEquals('poll for station 2: silence', '', RawSay('10 05 02 FE', 50));
  { master frame: DLE SOH STN DLE STX body DLE ETX BCC over STN+body = $B2 }
  AssertEquals('bad BCC: a half-duplex slave stays silent', '',
    RawSay('10 01 01 10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('good frame: ACK only', '10 06',
    RawSay('10 01 01 10 02 01 00 06 00 05 00 00 41 10 03 B2', 50));
  AssertEquals('poll: the reply', '10 02 00 01 46 00 05 00 41 10 03 73', RawSay('10 05 01 FF', 50));
  AssertEquals('poll before the ACK: the reply again', '10 02 00 01 46 00 05 00 41 10 03 73',
    RawSay('10 05 01 FF', 50));
  AssertEquals('ACK: silence', '', RawSay('10 06', 50));
  AssertEquals('poll after the ACK: EOT', '10 04', RawSay('10 05 01 FF', 50));
end;

procedure TTestDf1Sim.TestNakOfReplySendsItAgain;
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=OFF NAM=LOOP PAIR=SIMLN END=2');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMLN END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('ACK + reply', '10 06 10 02 00 01 46 00 05 00 41 10 03 73',
    RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('NAK of the reply: sent again', '10 02 00 01 46 00 05 00 41 10 03 73',
    RawSay('10 15', 50));
  AssertEquals('ACK: done', '', RawSay('10 06', 50));
  AssertEquals('a late NAK: nothing to repeat', '', RawSay('10 15', 50));
  AssertEquals('executed once', 1, Station.Requests);
end;

{ DUP=ON: a master that missed the ACK repeats the command (same SRC, CMD,
  FNC, TNS). The layer ACKs it, the table never sees it, and the master
  gets the reply the first execution made. BCC frames by hand: echo 'A'
  from SRC 0, TNS 5 = sum $4D -> BCC $B3; from SRC 2 = $4F -> $B1. }
procedure TTestDf1Sim.TestRepeatedCommandFullDuplex;
const
  Reply = '10 06 10 02 00 01 46 00 05 00 41 10 03 73';
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=OFF DUP=ON NAM=LOOP PAIR=SIMDF END=2');
  AssertEquals('DUP reported', 'DUP=ON', Slave^.ChGetParam('DUP'));
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMDF END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('ACK + reply', Reply, RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('repeated before our ACK: ACK + the same reply', Reply,
    RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('ACK: done', '', RawSay('10 06', 50));
  AssertEquals('repeated after our ACK: ACK + the same reply', Reply,
    RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('ACK', '', RawSay('10 06', 50));
  AssertEquals('executed once', 1, Station.Requests);
  AssertEquals('commands counted by the table', 1, Table.Diag[dgCommands]);
  AssertEquals('repetitions counted', 2, Table.Diag[dgDupsIn]);
  AssertEquals('answered from the cache', 2, Station.Repeats);
  AssertEquals('the layer counted them', 2, pChnDF1(Slave)^.CH_DupCount);
  { the same TNS from another station is a new command }
  AssertEquals('other SRC: executed', '10 06 10 02 00 01 46 00 05 00 41 10 03 73',
    RawSay('10 02 01 02 06 00 05 00 00 41 10 03 B1', 50));
  AssertEquals('ACK', '', RawSay('10 06', 50));
  AssertEquals('executed twice now', 2, Station.Requests);
  { a new TNS from SRC 0: executed }
  AssertEquals('next TNS: executed', '10 06 10 02 00 01 46 00 06 00 41 10 03 72',
    RawSay('10 02 01 00 06 00 06 00 00 41 10 03 B2', 50));
  AssertEquals('executed three times now', 3, Station.Requests);
end;

procedure TTestDf1Sim.TestRepeatedCommandHalfDuplex;
const
  Cmd = '10 01 01 10 02 01 00 06 00 05 00 00 41 10 03 B2';
  Reply = '10 02 00 01 46 00 05 00 41 10 03 73';
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=HALF CRC=OFF DUP=ON NAM=LOOP PAIR=SIMDH END=2');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMDH END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('good frame: ACK only', '10 06', RawSay(Cmd, 50));
  AssertEquals('poll: the reply', Reply, RawSay('10 05 01 FF', 50));
  AssertEquals('ACK: silence', '', RawSay('10 06', 50));
  AssertEquals('repeated: ACK only', '10 06', RawSay(Cmd, 50));
  AssertEquals('poll: the cached reply', Reply, RawSay('10 05 01 FF', 50));
  AssertEquals('ACK: silence', '', RawSay('10 06', 50));
  AssertEquals('poll: EOT', '10 04', RawSay('10 05 01 FF', 50));
  AssertEquals('executed once', 1, Station.Requests);
end;

{ The soak found it: the master's command is executed and its reply lost;
  before the master repeats it, a frame damaged into a command from another
  SRC (BCC let it through) is executed too. The repetition is still a
  repeated command for the layer (it remembers per SRC), so the station
  must still have the reply to it - it kept only the last reply, of the
  damaged frame, and stayed silent for good. Echo from SRC 2 with TNS 9:
  sum $53 -> BCC $AD; its reply (TNS 9) sum $91 -> $6F. }
procedure TTestDf1Sim.TestRepeatedCommandAfterAnotherSource;
const
  Reply5 = '10 06 10 02 00 01 46 00 05 00 41 10 03 73';
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=OFF DUP=ON NAM=LOOP PAIR=SIMDS END=2');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMDS END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  AssertEquals('SRC 0, TNS 5: ACK + reply', Reply5, RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('SRC 2, TNS 9: ACK + reply', '10 06 10 02 00 01 46 00 09 00 41 10 03 6F',
    RawSay('10 02 01 02 06 00 09 00 00 41 10 03 AD', 50));
  AssertEquals('SRC 0 repeats TNS 5: ACK + its reply', Reply5,
    RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50));
  AssertEquals('executed twice, once per command', 2, Station.Requests);
  { four more sources (echo TNS 9 from SRC 3..6: BCC $AC..$A9): the real
    master's reply, the most recent one, must not be the one pushed out }
  AssertEquals('SRC 0, TNS 6', '10 06 10 02 00 01 46 00 06 00 41 10 03 72',
    RawSay('10 02 01 00 06 00 06 00 00 41 10 03 B2', 50));
  RawSay('10 02 01 03 06 00 09 00 00 41 10 03 AC', 50);
  RawSay('10 02 01 04 06 00 09 00 00 41 10 03 AB', 50);
  RawSay('10 02 01 05 06 00 09 00 00 41 10 03 AA', 50);
  AssertEquals('SRC 0 repeats TNS 6 after three other sources', '10 06 10 02 00 01 46 00 06 00 41 10 03 72',
    RawSay('10 02 01 00 06 00 06 00 00 41 10 03 B2', 50));
  AssertEquals('executed six times', 6, Station.Requests);
end;

{ DUP=OFF (the default, the manual's behaviour): a repeated command is
  delivered and executed again. }
procedure TTestDf1Sim.TestRepeatedCommandWithoutDup;
var
  Err: string;
begin
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=OFF NAM=LOOP PAIR=SIMDO END=2');
  AssertEquals('DUP off by default', 'DUP=OFF', Slave^.ChGetParam('DUP'));
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMDO END=1', Err);
  AssertTrue(Err, Raw <> nil);
  SlcStationInit(Station, Slave, @Table);
  RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50);
  RawSay('10 02 01 00 06 00 05 00 00 41 10 03 B3', 50);
  AssertEquals('executed twice', 2, Station.Requests);
  AssertEquals('no repetition seen', 0, Table.Diag[dgDupsIn]);
end;

{$IFDEF UNIX}
procedure TTestDf1Sim.TestBinaryOverPty;
var
  PtyPath: string;
  Deadline: QWord;
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
begin
  AssertTrue(BinPath('df1sim') + ' missing (make tools)', FileExists(BinPath('df1sim')));
  Proc := StartSimPty(['--bcc', '--node=3', '--timeout=10', '--quiet'], PtyPath);
  AssertTrue('first line: PTY /dev/...', Copy(PtyPath, 1, 5) = '/dev/');
  Master := Open('NAM=DF1 NOD=0 DNO=3 MAS=MASTER FHD=FULL CRC=OFF NAM=COM DEV=' + PtyPath);
  EchoA(Req, 77);
  RepLen := 0;
  AssertEquals('echo over the pty', res_Ok, DF1Transact(Master, Req, 9, Rep, RepLen, nil, nil, 1000));
  AssertEquals('echo data', 9, RepLen);
  AssertEquals('echo byte', $41, Rep.Data[0]);
  { the built-in table: N7:0..2 = 0 10 20 }
  Req.CF := CF_ProtectRead3Addr;
  Req.Tns := 78;
  Move(PByte(HexToBytes('06 07 89 00 00'))^, Req.Data[0], 5);
  AssertEquals('typed read over the pty', res_Ok, DF1Transact(Master, Req, 13, Rep, RepLen, nil, nil, 1000));
  AssertEquals('N7:0..2', '00 00 0A 00 14 00', BytesToHex(Rep.Data, RepLen - 8));
  { SIGTERM: a clean exit with code 0 }
  FpKill(Proc.ProcessID, SIGTERM);
  Deadline := ChMsTick + 3000;
  while Proc.Running and (ChMsTick < Deadline) do
    Sleep(5);
  AssertFalse('df1sim ended on SIGTERM', Proc.Running);
  AssertEquals('exit code', 0, Proc.ExitCode);
end;
{$ENDIF}

{$IFDEF UNIX}
{ S2:4 counts every 10 ms, as on an SLC: two reads 300 ms apart differ by
  about 30 (at least 25: the reads themselves take time, at most 200 under
  any load the suite meets) }
procedure TTestDf1Sim.TestFreeRunningClockOverPty;
var
  PtyPath: string;
  C: tPcccClient;
  A, B: array[0..0] of LongInt;
  Deadline: QWord;
  Steps: LongInt;
begin
  Proc := StartSimPty(['--timeout=10', '--quiet'], PtyPath);
  AssertEquals('open', res_Ok, PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=' + PtyPath));
  try
    AssertEquals('first read: ' + C.Err, res_Ok, PcccReadInts(C, 'S2:4', 1, A));
    Deadline := ChMsTick + 300;
    while ChMsTick < Deadline do
      ChnWaitAny(ChnWaitLeft(Deadline));
    AssertEquals('second read: ' + C.Err, res_Ok, PcccReadInts(C, 'S2:4', 1, B));
    Steps := (B[0] - A[0]) and $FFFF;
    AssertTrue(Format('S2:4 went from %d to %d in 300 ms', [A[0], B[0]]), (Steps >= 25) and (Steps <= 200));
  finally
    PcccClose(C);
  end;
end;

{ With nothing to answer df1sim waits for the line instead of waking every
  millisecond: over one idle second with a master connected it wakes far
  fewer than 1000 times (about 100: its own 10 ms timers). }
procedure TTestDf1Sim.TestIdleSimWaitsForTheLine;
var
  PtyPath: string;
  C: tPcccClient;
  A: array[0..0] of LongInt;
  W0, W1: Int64;
  Deadline: QWord;
begin
  Proc := StartSimPty(['--timeout=10', '--quiet'], PtyPath);
  AssertEquals('open', res_Ok, PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=' + PtyPath));
  try
    AssertEquals('a read: ' + C.Err, res_Ok, PcccReadInts(C, 'S2:4', 1, A));
    W0 := ProcSleeps(Proc.ProcessID);
    Deadline := ChMsTick + 1000;
    while ChMsTick < Deadline do
      ChnWaitAny(ChnWaitLeft(Deadline));
    W1 := ProcSleeps(Proc.ProcessID);
    AssertTrue('/proc/PID/status has voluntary_ctxt_switches', (W0 >= 0) and (W1 >= W0));
    AssertTrue(Format('df1sim woke %d times in an idle second', [W1 - W0]), W1 - W0 < 400);
    { and it still answers at once }
    AssertEquals('a read after: ' + C.Err, res_Ok, PcccReadInts(C, 'S2:4', 1, A));
  finally
    PcccClose(C);
  end;
end;

procedure TTestDf1Sim.TestPtyTakesBdAndPar;
var
  Out: string;
begin
  AssertTrue(BinPath('df1sim') + ' missing (make tools)', FileExists(BinPath('df1sim')));
  { --bd/--par reach the pty (a virtual line takes them as given) }
  AssertEquals(0, RunBin('df1sim', ['--pty', '--bd=38400', '--par=N', '--timeout=1'], 5000, Out));
  AssertTrue(Out, Pos('DRV=PTY', Out) > 0);
  AssertTrue(Out, Pos(' BD=38400 ', Out) > 0);
  { PAR=E: taken as given where the pty driver keeps it, else refused
    with the COM layer's text; never dropped in silence }
  if RunBin('df1sim', ['--pty', '--par=E', '--timeout=1'], 5000, Out) = 0 then
    AssertTrue(Out, Pos(' PAR=E ', Out) > 0)
  else
    AssertTrue(Out, Pos('PAR=E": device refuses the setting', Out) > 0);
  { a bad one is refused by the COM layer, naming the token: a
    command-line error (exit 2), found before anything is opened }
  AssertEquals(2, RunBin('df1sim', ['--pty', '--par=X', '--timeout=1'], 5000, Out));
  AssertTrue(Out, Pos('PAR=X', Out) > 0);
  { with a parameter string they would be lost: refused }
  AssertEquals(2, RunBin('df1sim', ['--pty', '--bd=9600', 'NAM=DF1', 'MAS=SLAVE',
    'NAM=COM', 'DRV=PTY'], 5000, Out));
  AssertTrue(Out, Pos('--bd/--par with a parameter string', Out) > 0);
end;
{$ENDIF}

procedure TTestDf1Sim.TestLogLines;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
begin
  StartPair(True, True, 'SIMLOG');
  Station.Log := @StationLog;
  LogText := '';
  EchoA(Req, 5);
  RepLen := 0;
  AssertEquals('exchange', res_Ok, DF1Transact(Master, Req, 9, Rep, RepLen,
    @StepStation, @Station, 500, @MasterLog, True));
  WaitReceive(Slave, 100);
  DF1StationStep(Station);
  { frames as in TestFullDuplexLinkBytes (CRC worked out by hand); the
    station logs no wire bytes (LogWire off), the master does }
  AssertEquals('log',
    'M -> Echo STS=$00 TNS=5 data: 41   [10 02 01 00 06 00 05 00 00 41 10 03 D7 C1]'#10 +
    'S <- Echo STS=$00 TNS=5 data: 41'#10 +
    'S -> ACK'#10 +
    'S -> reply CMD=$46 STS=$00 TNS=5 data: 41'#10 +
    'M <- ACK'#10 +
    'M <- reply CMD=$46 STS=$00 TNS=5 data: 41'#10 +
    'M -> ACK   [10 06]'#10 +
    'S <- ACK'#10, LogText);
  { and the station's wire bytes: ENQ repeats the last ACK }
  Station.LogWire := True;
  LogText := '';
  Req.MessType := tpEnq;
  Master^.ChSend(@Req, 1);
  WaitReceive(Slave, 100);
  DF1StationStep(Station);
  AssertEquals('station wire', 'S <- ENQ'#10'S -> ACK   [10 06]'#10, LogText);
  AssertEquals('DF1WireText of the master: the ENQ', '10 05', DF1WireText(Master));
end;

procedure TTestDf1Sim.TestLogNoAck;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Err: string;
begin
  { nobody answers: three tries, each followed by an ENQ (full duplex) }
  Master := Open('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=OFF NAM=LOOP PAIR=SIMNA END=1');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMNA END=2', Err);
  AssertTrue(Err, Raw <> nil);
  EchoA(Req, 5);
  RepLen := 0;
  LogText := '';
  AssertEquals('result', res_Timeout, DF1Transact(Master, Req, 8, Rep, RepLen,
    nil, nil, 20, @MasterLog));
  AssertEquals('log',
    'M -> Echo STS=$00 TNS=5'#10'M -> ENQ'#10 +
    'M -> Echo STS=$00 TNS=5'#10'M -> ENQ'#10 +
    'M -> Echo STS=$00 TNS=5'#10'M -> ENQ'#10 +
    'M -- no ACK after 3 tries'#10, LogText);
end;

{ DF1Transact receives into its Rep, often a local of the caller: the
  channel kept pointing at it, and the next ChReceive wrote into a dead
  stack frame. The caller's buffer (or none) must be in force afterwards. }
procedure TTestDf1Sim.TestTransactGivesBackTheReceiveBuffer;
var
  Mine: tRecRecord;
begin
  StartPair(True, True, 'SIMRB');
  AssertEquals('echo', 'STS=00 41', Ask(CF_Echo, '41', 1));
  AssertTrue('no buffer before, none after', Master^.CH_RBuff = nil);
  AssertEquals(0, Master^.CH_RSize);
  Master^.ChReceiveBuffer(@Mine, 100);
  AssertEquals('echo again', 'STS=00 42', Ask(CF_Echo, '42', 2));
  AssertTrue('the caller''s buffer again', Master^.CH_RBuff = @Mine);
  AssertEquals('and its size', 100, Master^.CH_RSize);
end;

{$IFDEF UNIX}
var
  HangAcked: Boolean;

{ Idle of TestTransactReportsLostLine: ACK the command, then hang up. }
procedure AckThenHangUp(Data: Pointer);
var
  P: TPtyPair;
  B: array[0..63] of Byte;
  Ack: array[0..1] of Byte;
begin
  P := TPtyPair(Data);
  if P.Master < 0 then
    Exit;
  if HangAcked then
    P.CloseMaster                   { the adapter is pulled }
  else if P.MasterRead(B, SizeOf(B)) > 0 then
  begin
    Ack[0] := $10;
    Ack[1] := $06;
    P.MasterWrite(Ack, 2);
    HangAcked := True;
  end;
end;

{ The line goes away while the master waits for the reply: DF1Transact
  says so at once (res_DeviceLost), not res_Timeout after 3 timeouts. }
procedure TTestDf1Sim.TestTransactReportsLostLine;
var
  P: TPtyPair;
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  R: tChResult;
  T0: QWord;
begin
  P := TPtyPair.Create;
  try
    Master := Open('NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + P.SlavePath);
    EchoA(Req, 3);
    HangAcked := False;
    RepLen := 0;
    T0 := ChMsTick;
    R := DF1Transact(Master, Req, 9, Rep, RepLen, @AckThenHangUp, P, 300);
    AssertTrue('the command was ACKed first', HangAcked);
    AssertEquals('result', res_DeviceLost, R);
    { the reply may take 3 timeouts (900 ms) before res_Timeout; well
      below that, with room for a loaded machine }
    AssertTrue('at once, not after the timeouts: ' + IntToStr(ChMsTick - T0) + ' ms',
      ChMsTick - T0 < 800);
  finally
    P.Free;
  end;
end;
{$ENDIF}

var
  ScriptRaw: pChnVirt;       { the slave side of TestTransactChecksTheReply }
  ScriptAnswer: string;      { hex it sends when the command has come }
  ScriptCommand: string;     { hex of the command it got }
  ScriptLater: string;       { hex of what the master sent after it }

{ Idle of TestTransactChecksTheReply: answer the first frame with
  ScriptAnswer; later ones (the master's ACK of the reply) are read and
  dropped. }
procedure ScriptedSlave(Data: Pointer);
var
  Buf: array[0..255] of Byte;
  Len: Word;
  D: TBytes;
begin
  ScriptRaw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  if ScriptRaw^.ChReceiveReady <> CHS_ReceiveReady then
    Exit;
  Len := 0;
  ScriptRaw^.ChReceive(Len);
  if ScriptCommand <> '' then
  begin
    ScriptLater := Trim(ScriptLater + ' ' + BytesToHex(Buf, Len));
    Exit;
  end;
  ScriptCommand := BytesToHex(Buf, Len);
  D := HexToBytes(ScriptAnswer);
  ScriptRaw^.ChSend(@D[0], Length(D));
end;

{ DF1Transact checks that the reply belongs to the command, and takes a
  reply that comes before (instead of) the ACK as the ACK. Full duplex,
  BCC, master 0 -> slave 1, echo of 'A' with TNS 3. BCCs by hand:
    command 01 00 06 00 03 00 00 41: sum $4B -> $B5
    reply   00 01 46 00 03 00 41:    sum $8B -> $75
    TNS 4   00 01 46 00 04 00 41:    sum $8C -> $74
    CMD $41 00 01 41 00 03 00 41:    sum $86 -> $7A }
procedure TTestDf1Sim.TestTransactChecksTheReply;
const
  Answers: array[0..3] of string = (
    '10 06 10 02 00 01 46 00 03 00 41 10 03 75',   { ACK, the reply }
    '10 02 00 01 46 00 03 00 41 10 03 75',         { the reply, no ACK }
    '10 06 10 02 00 01 46 00 04 00 41 10 03 74',   { another TNS }
    '10 06 10 02 00 01 41 00 03 00 41 10 03 7A');  { another command }
  Want: array[0..3] of tChResult = (res_Ok, res_Ok, res_BadMessage, res_BadMessage);
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Err: string;
  I: Integer;
begin
  for I := 0 to High(Answers) do
  begin
    Master := Open('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=OFF NAM=LOOP PAIR=SIMTR END=1');
    Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMTR END=2', Err);
    AssertTrue(Err, Raw <> nil);
    ScriptRaw := Raw;
    ScriptAnswer := Answers[I];
    ScriptCommand := '';
    EchoA(Req, 3);
    RepLen := 0;
    FillChar(Rep, SizeOf(Rep), 0);
    AssertEquals(Answers[I], Want[I],
      DF1Transact(Master, Req, 9, Rep, RepLen, @ScriptedSlave, nil, 200));
    AssertEquals('command ' + IntToStr(I), '10 02 01 00 06 00 03 00 00 41 10 03 B5', ScriptCommand);
    AssertEquals('reply TNS ' + IntToStr(I), 3 + Ord(I = 2), Rep.Tns);
    Dispose(Master, Done);
    Master := nil;
    Dispose(Raw, Done);
    Raw := nil;
  end;
end;

function TTestDf1Sim.Scripted(const Answer: string; TimeoutMs: LongInt;
  var Rep: tRecRecord): tChResult;
var
  Req: tSendRecord;
  RepLen: Word;
  Err: string;
begin
  Master := Open('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=OFF NAM=LOOP PAIR=SIMTL END=1');
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMTL END=2', Err);
  AssertTrue(Err, Raw <> nil);
  ScriptRaw := Raw;
  ScriptAnswer := Answer;
  ScriptCommand := '';
  ScriptLater := '';
  EchoA(Req, 3);
  RepLen := 0;
  FillChar(Rep, SizeOf(Rep), 0);
  Result := DF1Transact(Master, Req, 9, Rep, RepLen, @ScriptedSlave, nil, TimeoutMs);
  ScriptedSlave(nil);                 { what the master sent last }
end;

{ A late copy of the reply to an earlier command (TNS 2: sum $8A -> $76)
  before the reply to this one: both are ACKed, the late one is ignored
  (it once ended the exchange with res_BadMessage, and the master sent
  the command again although its reply was on the way). }
procedure TTestDf1Sim.TestTransactSkipsALateReply;
var
  Rep: tRecRecord;
begin
  AssertEquals('result', res_Ok, Scripted('10 06 10 02 00 01 46 00 02 00 41 10 03 76 ' +
    '10 02 00 01 46 00 03 00 41 10 03 75', 200, Rep));
  AssertEquals('the reply to this command', 3, Rep.Tns);
  AssertEquals('both replies ACKed', '10 06 10 06', ScriptLater);
end;

{ A reply with a wrong checksum: the master NAKs it so the slave sends it
  again at once (it used to wait for the reply's deadline in silence). }
procedure TTestDf1Sim.TestTransactNaksABrokenReply;
var
  Rep: tRecRecord;
begin
  AssertEquals('no good reply came', res_Timeout,
    Scripted('10 06 10 02 00 01 46 00 03 00 41 10 03 76', 100, Rep));
  AssertEquals('NAK of the broken reply', '10 15', ScriptLater);
end;

{ The link helpers on a stack whose top is no tChnDF1 (here a bare LOOP):
  res_WrongLayer, and not one byte reaches the line (they once cast the
  channel and sent the raw record three times). }
procedure TTestDf1Sim.TestHelpersRefuseAnotherLayer;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Err: string;
  Peer: pChnVirt;
begin
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMWL END=1', Err);
  AssertTrue(Err, Raw <> nil);
  Peer := OpenStack('LOOP', 'NAM=LOOP PAIR=SIMWL END=2', Err);
  AssertTrue(Err, Peer <> nil);
  try
    EchoA(Req, 5);
    RepLen := 0;
    AssertEquals('DF1Transact', res_WrongLayer,
      DF1Transact(Raw, Req, 9, Rep, RepLen, nil, nil, 20));
    AssertEquals('nothing was sent', CHS_Receiving, Peer^.ChReceiveReady);
    AssertEquals('DF1StationInit', res_WrongLayer, SlcStationInit(Station, Raw, @Table));
    AssertFalse('the station reads nothing', DF1StationStep(Station));
    AssertEquals('DF1WireText', '', DF1WireText(Raw));
  finally
    Dispose(Peer, Done);
  end;
end;

procedure TTestDf1Sim.TestOpenStack;
var
  Err: string;
  Long: string;
begin
  Master := DF1OpenStack('NAM=DF1 NOD=0 DNO=1 NAM=LOOP PAIR=SIMOS END=1', 1000, Err);
  AssertTrue('opened: ' + Err, Master <> nil);
  AssertEquals('no error text', '', Err);
  AssertTrue('connected', Master^.ChReady = CHS_Connect);
  AssertTrue('a tChnDF1 on top', pChnDF1(Master)^.CH_Master);
  AssertTrue('bad parameter: nil', DF1OpenStack('NAM=DF1 XYZ=1 NAM=LOOP PAIR=SIMOS2 END=1',
    1000, Err) = nil);
  AssertEquals('says which step', 'parameters "', Copy(Err, 1, 12));
  AssertTrue('says which parameter: ' + Err, Pos('XYZ', Err) > 0);
  AssertTrue('no such device: nil', DF1OpenStack('NAM=DF1 NAM=COM DEV=/nonexistent/ttyX',
    1000, Err) = nil);
  AssertEquals('open failed: ' + Err, 'open "', Copy(Err, 1, 6));
  Long := 'NAM=DF1 NOD=0 DNO=1 NAM=LOOP PAIR=SIMOS3 END=1' + StringOfChar(' ', 250);
  AssertTrue('too long: nil', DF1OpenStack(Long, 1000, Err) = nil);
  AssertTrue('too long: says so: ' + Err, Pos('too long: 296 characters, the limit is 255', Err) > 0);
end;

initialization
  RegisterTest(TTestDf1Sim);
end.
