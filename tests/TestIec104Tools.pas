{ The tools over IEC 104: iec101slave serving on loopback with a
  'NAM=IEC104 NAM=TCP LISTEN=...' string, iec101master asking it with a
  'NAM=IEC104 NAM=TCP HOST=... PORT=...' string: the same commands and the
  same JSON as over FT 1.2; the file commands (log, delete, dir) against
  iec101slave --files. }
unit TestIec104Tools;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnSock,
  BinSupport, TestSupport, TestTempDir;

type
  TTestIec104Tools = class(TTestCase)
  published
    procedure TestMasterToolAgainstSlaveTool;
    procedure TestFileCommandsAgainstSlaveTool;
  end;

implementation

{ Wait until something listens on Port (3 s at most). }
function Listening(Port: Word): Boolean;
var
  Err: string;
  C: pChnVirt;
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + 3000;
  repeat
    C := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
    Result := C <> nil;
    if Result then
    begin
      Dispose(C, Done);
      Exit;
    end;
    Sleep(20);
  until GetTickCount64 > Deadline;
end;

{ What the slave tool wrote on stderr once it ended by itself (12 s at most). }
function SlaveEnded(S: TProcess): string;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + 12000;
  while S.Running and (GetTickCount64 < Deadline) do
    Sleep(20);
  TAssert.AssertFalse('the slave ended', S.Running);
  Result := '';
  SetLength(Result, S.Stderr.NumBytesAvailable);
  if Length(Result) > 0 then
    S.Stderr.Read(Result[1], Length(Result));
end;

procedure TTestIec104Tools.TestMasterToolAgainstSlaveTool;
var
  Port: Word;
  S: TProcess;
  Out, Errs: string;
  Rc: Integer;
  Deadline: QWord;
begin
  AssertTrue(FileExists(BinPath('iec101slave')));
  Port := SockFreeLoopbackPort;
  S := TProcess.Create(nil);
  try
    BinExecutable(S, BinPath('iec101slave'));
    S.Parameters.Add('--json');
    S.Parameters.Add('--seconds=8');
    S.Parameters.Add('NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:' + IntToStr(Port));
    S.Options := [poUsePipes];
    S.Execute;
    AssertTrue('the slave listens', Listening(Port));
    Rc := RunBin('iec101master', ['--json', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' +
      IntToStr(Port), 'gi', 'ci', 'sc', '5000=1', 'clock'], 15000, Out);
    AssertEquals(Out, 0, Rc);
    { lib60870's cs101_slave points (the tool's default table) }
    AssertTrue(Out, Pos('{"type":"C_IC_NA_1","ti":100,"cot":7,', Out) > 0);
    AssertTrue(Out, Pos('{"type":"M_ME_NB_1","ti":11,"cot":20,"negative":false,"test":false,"oa":0,"ca":1,"ioa":100,"value":-1,', Out) > 0);
    AssertTrue(Out, Pos('{"type":"C_IC_NA_1","ti":100,"cot":10,', Out) > 0);
    AssertTrue(Out, Pos('{"type":"C_CI_NA_1","ti":101,"cot":10,', Out) > 0);
    AssertTrue(Out, Pos('{"type":"C_SC_NA_1","ti":45,"cot":7,"negative":false', Out) > 0);
    AssertTrue(Out, Pos('{"type":"C_CS_NA_1","ti":103,"cot":7,"negative":false', Out) > 0);
    Errs := SlaveEnded(S);
    { the interrogation after its end of initialisation is the one asked for }
    AssertTrue(Errs, Pos('1 interrogations, 1 counter interrogations, 0 reads, 1 commands (0 refused), 1 clock syncs', Errs) > 0);
    AssertEquals(Errs, 0, S.ExitCode);
  finally
    StopProcess(S);
  end;
end;

{ iec101slave --files DIR with 30000 made 2026-12-04 10:00 and 30001 the
  5th 08:00 (their modification times, local): iec101master's query log
  of the 4th 09:00..12:30 lists 30000 only, delete 30001 removes it from
  DIR, dir then lists 30000; a second delete is refused (exit 3). }
procedure TTestIec104Tools.TestFileCommandsAgainstSlaveTool;
var
  Port: Word;
  S: TProcess;
  Dir, Out, Errs, Host: string;
  Rc: Integer;
  Deadline: QWord;
begin
  Dir := MakeTempDir('iec104files');
  S := TProcess.Create(nil);
  try
    WriteFileText(Dir + '/30000', 'ten octets');
    WriteFileText(Dir + '/30001', 'eleven octs');
    AssertEquals(0, FileSetDate(Dir + '/30000', DateTimeToFileDate(EncodeDate(2026, 12, 4) + EncodeTime(10, 0, 0, 0))));
    AssertEquals(0, FileSetDate(Dir + '/30001', DateTimeToFileDate(EncodeDate(2026, 12, 5) + EncodeTime(8, 0, 0, 0))));
    Port := SockFreeLoopbackPort;
    Host := 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port);
    BinExecutable(S, BinPath('iec101slave'));
    S.Parameters.Add('--seconds=8');
    S.Parameters.Add('--files=' + Dir);
    S.Parameters.Add('NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:' + IntToStr(Port));
    S.Options := [poUsePipes];
    S.Execute;
    AssertTrue('the slave listens', Listening(Port));
    Rc := RunBin('iec101master', [Host, 'log', '2026-12-04T09:00', '2026-12-04T12:30:00.000',
      'delete', '30001', 'dir'], 15000, Out);
    AssertEquals(Out, 0, Rc);
    AssertTrue(Out, Pos('file IOA 30000 NOF 1 10 octets SOF 0x20 2026-12-04T10:00:00.000', Out) > 0);
    AssertTrue(Out, Pos('file IOA 30001 deleted', Out) > 0);
    AssertEquals('the log and the directory list 30000 alone', 2, CountOf('file IOA 30000 NOF 1', Out));
    AssertEquals(0, CountOf('file IOA 30001 NOF', Out));
    AssertFalse(FileExists(Dir + '/30001'));
    Rc := RunBin('iec101master', [Host, 'delete', '30001'], 15000, Out);
    AssertEquals(Out, 3, Rc);
    AssertTrue(Out, Pos('iec101master: delete of file IOA 30001 on slave 0: the slave has no such file ' +
      '(F_FR_NA_1 negative) (delete 30001)', Out) > 0);
    Rc := RunBin('iec101master', [Host, 'log', '2026-12-04', 'tomorrow'], 15000, Out);
    AssertEquals(Out, 2, Rc);
    AssertTrue(Out, Pos('iec101master: log wants TO as 2026-12-04T09:30:00 (tomorrow)', Out) > 0);
    Errs := SlaveEnded(S);
    AssertTrue(Errs, Pos('1 refused, 1 deleted', Errs) > 0);
  finally
    StopProcess(S);
    RemoveTempDir(Dir);
  end;
end;

initialization
  RegisterTest(TTestIec104Tools);
end.
