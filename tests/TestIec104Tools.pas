{ The tools over IEC 104: iec101slave serving on loopback with a
  'NAM=IEC104 NAM=TCP LISTEN=...' string, iec101master asking it with a
  'NAM=IEC104 NAM=TCP HOST=... PORT=...' string: the same commands and the
  same JSON as over FT 1.2. }
unit TestIec104Tools;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp,
  BinSupport, TestSupport;

type
  TTestIec104Tools = class(TTestCase)
  published
    procedure TestMasterToolAgainstSlaveTool;
  end;

implementation

{ A loopback port nothing listens on now. }
function FreePort: Word;
var
  Err: string;
  C: pChnVirt;
begin
  C := OpenStack('TCP', 'LISTEN=127.0.0.1:0', Err);
  Result := pChnTcp(C)^.ChLocalPort;
  Dispose(C, Done);
end;

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

procedure TTestIec104Tools.TestMasterToolAgainstSlaveTool;
var
  Port: Word;
  S: TProcess;
  Out, Errs: string;
  Rc: Integer;
  Deadline: QWord;
begin
  AssertTrue(FileExists(BinPath('iec101slave')));
  Port := FreePort;
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
    Deadline := GetTickCount64 + 12000;
    while S.Running and (GetTickCount64 < Deadline) do
      Sleep(20);
    AssertFalse('the slave ended', S.Running);
    Errs := '';
    SetLength(Errs, S.Stderr.NumBytesAvailable);
    if Length(Errs) > 0 then
      S.Stderr.Read(Errs[1], Length(Errs));
    { the interrogation after its end of initialisation is the one asked for }
    AssertTrue(Errs, Pos('1 interrogations, 1 counter interrogations, 0 reads, 1 commands (0 refused), 1 clock syncs', Errs) > 0);
    AssertEquals(Errs, 0, S.ExitCode);
  finally
    StopProcess(S);
  end;
end;

initialization
  RegisterTest(TTestIec104Tools);
end.
