{ Tests of tools/chnline: ptys joined as a line at a real speed, spoken to
  over NAM=COM DEV=<pty> as a program on this machine would; character
  times worked out by hand (docs/ChnLoop.md). }
unit TestChnLine;

{$MODE OBJFPC}{$H+}

interface

{$IFDEF UNIX}
uses
  BaseUnix, SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt,
  ChnWait, TestSupport, BinSupport, ChildLine, StackCase;

type
  TTestChnLine = class(TStackCase)
  private
    Proc: TProcess;
    Paths: TStringList;
    procedure Start(const Args: array of string);
    { SIGTERM, then its output after the first line }
    function Finish: string;
    function Collect(R: pChnVirt; Count: Integer; MaxMs: Integer): string;
  protected
    procedure TearDown; override;
  published
    procedure TestNullModemAt9600Even;
    procedure TestBusOfThreeCollides;
    procedure TestBadOptions;
  end;
{$ENDIF}

implementation

{$IFDEF UNIX}
procedure TTestChnLine.Start(const Args: array of string);
var
  A, Line: string;
begin
  AssertTrue(BinPath('chnline') + ' missing (make tools)', FileExists(BinPath('chnline')));
  Proc := TProcess.Create(nil);
  BinExecutable(Proc, BinPath('chnline'));
  for A in Args do
    Proc.Parameters.Add(A);
  Proc.Options := [poUsePipes];
  Proc.Execute;
  Line := ReadFirstLine(Proc, 3000);
  AssertEquals('first line: PTY ...', 'PTY ', Copy(Line, 1, 4));
  Paths := TStringList.Create;
  Paths.Delimiter := ' ';
  Paths.DelimitedText := Copy(Line, 5, MaxInt);
end;

function TTestChnLine.Finish: string;
var
  Deadline: QWord;
begin
  Result := '';
  FpKill(Proc.ProcessID, SIGTERM);
  Deadline := ChMsTick + 3000;
  while Proc.Running and (ChMsTick < Deadline) do
  begin
    Drain(Proc, Result);
    Sleep(5);
  end;
  Drain(Proc, Result);
  AssertFalse('chnline ended on SIGTERM', Proc.Running);
  AssertEquals('exit code', 0, Proc.ExitCode);
end;

procedure TTestChnLine.TearDown;
begin
  inherited TearDown;
  if Proc <> nil then
  begin
    StopProcess(Proc);
  end;
  FreeAndNil(Paths);
end;

{ What R receives within MaxMs (or until Count bytes), as hex. }
function TTestChnLine.Collect(R: pChnVirt; Count: Integer; MaxMs: Integer): string;
var
  Buf: array[0..999] of Byte;
  All: array of Byte;
  Len: Word;
  Got: Integer;
  Deadline: QWord;
begin
  All := nil;
  Got := 0;
  R^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := ChMsTick + QWord(MaxMs);
  while (Got < Count) and (ChMsTick < Deadline) do
    if R^.ChReceiveReady = CHS_ReceiveReady then
    begin
      R^.ChReceive(Len);
      SetLength(All, Got + Len);
      Move(Buf, All[Got], Len);
      Inc(Got, Len);
    end
    else
      ChnWaitAny(50);
  Result := BytesToHex(All, Got);
end;

{ 100 characters at 9600 8E1 (11 bits, 1146 us each) take 115 ms: none of
  them can be there before, all are there soon after. }
procedure TTestChnLine.TestNullModemAt9600Even;
var
  A, B: pChnVirt;
  S: array[0..99] of Byte;
  I: Integer;
  T0, Took: QWord;
  Got, Summary: string;
begin
  Start(['--bd=9600', '--par=E']);
  AssertEquals('two ptys', 2, Paths.Count);
  A := Stack('COM', 'DEV=' + Paths[0] + ' IDL=0');
  B := Stack('COM', 'DEV=' + Paths[1] + ' IDL=0');
  for I := 0 to High(S) do
    S[I] := I;
  T0 := ChMsTick;
  A^.ChSend(@S, SizeOf(S));
  Got := Collect(B, 100, 5000);
  Took := ChMsTick - T0;
  AssertEquals('all of it, in order', BytesToHex(S, 100), Got);
  AssertTrue('took ' + IntToStr(Took) + ' ms of 115', Took >= 113);
  AssertTrue('took ' + IntToStr(Took) + ' ms of 115', Took < 3000);
  { and back: full duplex }
  S[0] := $55;
  B^.ChSend(@S, 1);
  AssertEquals('55', Collect(A, 1, 3000));
  Summary := Finish;
  AssertTrue(Summary, Pos('end 1 ' + Paths[0] + ': 100 bytes sent, 1 received', Summary) > 0);
  AssertTrue(Summary, Pos('line: 0 collisions, 0 characters garbled', Summary) > 0);
end;

{ Three ends: the third hears both others; the first two writing at once
  collide, and every character arrives inverted ($11 -> EE, $22 -> DD). }
procedure TTestChnLine.TestBusOfThreeCollides;
var
  E: array[0..2] of pChnVirt;
  S1, S2: array[0..9] of Byte;
  I: Integer;
  Got, Summary: string;
begin
  { 1200 Bd: ten characters last 92 ms, so the two sends overlap on the
    line even when each process runs emulated (make crosstest) }
  Start(['--ends=3', '--bd=1200']);
  AssertEquals('three ptys', 3, Paths.Count);
  for I := 0 to 2 do
    E[I] := Stack('COM', 'DEV=' + Paths[I] + ' IDL=0');
  S1[0] := $A1;
  E[0]^.ChSend(@S1, 1);
  AssertEquals('end 2 hears end 1', 'A1', Collect(E[1], 1, 3000));
  AssertEquals('end 3 hears end 1', 'A1', Collect(E[2], 1, 3000));
  FillChar(S1, SizeOf(S1), $11);
  FillChar(S2, SizeOf(S2), $22);
  E[0]^.ChSend(@S1, 10);
  E[1]^.ChSend(@S2, 10);
  Got := Collect(E[2], 20, 3000);
  AssertEquals('20 characters', 59, Length(Got));
  AssertEquals('none of them intact', 0, Pos('11', Got) + Pos('22', Got));
  AssertEquals('only inverted ones', '', StringReplace(StringReplace(StringReplace(Got,
    'EE', '', [rfReplaceAll]), 'DD', '', [rfReplaceAll]), ' ', '', [rfReplaceAll]));
  Summary := Finish;
  AssertTrue(Summary, Pos('line: 1 collisions, 20 characters garbled', Summary) > 0);
end;

procedure TTestChnLine.TestBadOptions;
var
  Output: string;
begin
  AssertEquals('--ends=33', 2, RunBin('chnline', ['--ends=33'], 5000, Output));
  AssertTrue(Output, Pos('--ends', Output) > 0);
  AssertEquals('--bd=10', 2, RunBin('chnline', ['--bd=10'], 5000, Output));
  AssertEquals('--par=X', 2, RunBin('chnline', ['--par=X'], 5000, Output));
  AssertEquals('an argument', 2, RunBin('chnline', ['BD=9600'], 5000, Output));
  AssertEquals('--help', 0, RunBin('chnline', ['--help'], 5000, Output));
  AssertTrue(Output, Pos('RS-485', Output) > 0);
end;

initialization
  RegisterTest(TTestChnLine);
{$ENDIF}
end.
