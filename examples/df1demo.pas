{ df1demo - a DF1 echo exchange with no hardware (make demo): the master
  of df1echo and the slave of df1slave in one process, joined by the
  in-memory null modem NAM=LOOP, first in full duplex with CRC, then in half
  duplex with BCC (poll / EOT / data / ACK). Prints every message and its
  wire bytes; exit code 0 when both exchanges succeed. }
program df1demo;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnDF1;

{$I df1common.inc}

var
  Slave: tResponder;
  Failures: Integer;

{ the slave runs while the master waits }
procedure RunSlave;
begin
  ResponderStep(Slave);
end;

function Open(const Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(ChnDF1.cName);
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    WriteLn('df1demo: ', Params, ': ', Result^.ChResultStr(Result^.ChResult));
    Halt(ex_Setup);
  end;
end;

procedure Run(const Title, MasterParams, SlaveParams, Text: string; Tns: Word);
var
  M, S: pChnVirt;
  Code: Integer;
begin
  WriteLn;
  WriteLn('== ', Title);
  M := Open(MasterParams);
  S := Open(SlaveParams);
  WriteLn('master: ', M^.ChGetParam(''));
  WriteLn('slave : ', S^.ChGetParam(''));
  ResponderInit(Slave, S, 'slave ');
  Code := EchoExchange(M, Text, Tns, @RunSlave);
  { let the slave take the master's last ACK }
  WaitMessage(S, 100, nil);
  RunSlave;
  if Code = ex_Ok then
    WriteLn('echo ok')
  else
  begin
    WriteLn('echo FAILED (', Code, ')');
    Inc(Failures);
  end;
  Dispose(M, Done);
  Dispose(S, Done);
end;

begin
  Failures := 0;
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
  Halt(Failures);
end.
