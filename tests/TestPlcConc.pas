{ TestPlcConc - examples/plcconc, the many-lines pattern (every request in
  flight, one ChnWaitAny, the stepped client), against tools/df1sim on
  ptys: the cycle over 8 lines stays far below the 100 ms of the wait
  (with a step that takes one message, the ACK and the reply arriving in
  one chunk made it 80-100 ms), and the command line. Generous bounds only:
  make bench measures. }
unit TestPlcConc;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestPlcConc = class(TTestCase)
  published
    procedure TestCommandLine;
    {$IFDEF UNIX}
    procedure TestEightLinesCycleFarBelowTheWaitTimeout;
    procedure TestExitCodesOfFailedReads;
    {$ENDIF}
  end;

implementation

uses
  Process, BinSupport;

{ The number after Key in Output ('mean cycle 0.412 ms'), -1 if none. }
function NumberAfter(const Output, Key: string): Double;
var
  P, E: Integer;
  S: string;
  Code: Integer;
begin
  Result := -1;
  P := Pos(Key, Output);
  if P = 0 then
    Exit;
  P := P + Length(Key);
  E := P;
  while (E <= Length(Output)) and (Output[E] in ['0'..'9', '.']) do
    Inc(E);
  S := Copy(Output, P, E - P);
  Val(S, Result, Code);
  if Code <> 0 then
    Result := -1;
end;

procedure TTestPlcConc.TestCommandLine;
var
  Output: string;
  Code: Integer;
begin
  AssertTrue(BinPath('plcconc') + ' missing (make examples)', FileExists(BinPath('plcconc')));
  Code := RunBin('plcconc', [], 5000, Output);
  AssertEquals('no arguments: usage, exit 2'#10 + Output, 2, Code);
  AssertEquals('usage text'#10 + Output, 1, Pos('Usage: plcconc ', Output));
  Code := RunBin('plcconc', ['--help'], 5000, Output);
  AssertEquals('--help: exit 0'#10 + Output, 0, Code);
  AssertTrue('--help lists the exit codes'#10 + Output, Pos('  4   a read got no answer', Output) > 0);
  { command-line errors: exit 2, naming the token, nothing opened }
  Code := RunBin('plcconc', ['--cycles', 'x', 'NAM=DF1 NAM=LOOP'], 5000, Output);
  AssertEquals('bad number: exit 2'#10 + Output, 2, Code);
  AssertEquals('plcconc: --cycles wants a whole number 0..2147483647 (--cycles x)' + LineEnding, Output);
  Code := RunBin('plcconc', ['--bogus', 'NAM=DF1 NAM=LOOP'], 5000, Output);
  AssertEquals('unknown option: exit 2'#10 + Output, 2, Code);
  AssertEquals('plcconc: unknown option (--bogus)' + LineEnding, Output);
  Code := RunBin('plcconc', ['--addr=Q7:0', 'NAM=DF1 NAM=LOOP'], 5000, Output);
  AssertEquals('bad address: exit 2'#10 + Output, 2, Code);
  AssertTrue('names it'#10 + Output, Pos('(Q7:0)', Output) > 0);
  Code := RunBin('plcconc', ['--cycles=1', 'NAM=DF1 NAM=LOOP', 'NAM=DF1 NAM=NOSUCH'], 5000, Output);
  AssertEquals('an unknown layer: exit 2'#10 + Output, 2, Code);
  AssertTrue('names it'#10 + Output, Pos('bad parameter string: ', Output) > 0);
  AssertTrue('names it'#10 + Output, Pos('(NAM=NOSUCH)', Output) > 0);
  { a line that cannot be opened: exit 1, which line }
  Code := RunBin('plcconc', ['--cycles=1', 'NAM=DF1 NAM=LOOP', 'NAM=DF1 NAM=COM DEV=/nonexistent/tty'],
    5000, Output);
  AssertEquals('a line that cannot be opened: exit 1'#10 + Output, 1, Code);
  AssertTrue('says which line'#10 + Output, Pos('plcconc: line 2: ', Output) = 1);
end;

{$IFDEF UNIX}
procedure TTestPlcConc.TestEightLinesCycleFarBelowTheWaitTimeout;
const
  N = 8;
var
  Sims: array[0..N - 1] of TProcess;
  Args: array of string;
  Pty, Output: string;
  I, Code: Integer;
  Mean: Double;
begin
  FillChar(Sims, SizeOf(Sims), 0);
  SetLength(Args, N + 3);
  Args[0] := '--quiet';
  Args[1] := '--cycles';
  Args[2] := '40';
  try
    for I := 0 to N - 1 do
    begin
      Sims[I] := StartSimPty(['--timeout=20', '--quiet'], Pty);
      AssertTrue('df1sim ' + IntToStr(I) + ' printed its pty', Pty <> '');
      Args[3 + I] := 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty;
    end;
    Code := RunBin('plcconc', Args, 30000, Output);
    AssertEquals('every read answered'#10 + Output, 0, Code);
    Mean := NumberAfter(Output, 'mean cycle ');
    WriteLn(Format('info  plcconc: 8 df1sim lines, mean cycle %.3f ms', [Mean]));
    AssertTrue('a summary line'#10 + Output, Mean >= 0);
    { the reads of 8 lines over ptys take well under a millisecond each;
      a cycle that waits for its wait's timeout takes 100 ms }
    AssertTrue(Format('mean cycle %.3f ms far below the 100 ms wait', [Mean]), Mean < 25);
  finally
    for I := 0 to N - 1 do
      if Sims[I] <> nil then
      begin
        if Sims[I].Running then
          Sims[I].Terminate(0);
        Sims[I].Free;
      end;
  end;
end;

{ An error reply is 3, no answer 4; reads failing both ways: 3. A line
  with nobody on it is a pty nobody reads (DRV=PTY). }
procedure TTestPlcConc.TestExitCodesOfFailedReads;
var
  Sim: TProcess;
  Pty, Output, Line, Silent: string;
  Code: Integer;
begin
  Sim := StartSimPty(['--timeout=30', '--quiet'], Pty);
  try
    AssertTrue('df1sim printed its pty', Pty <> '');
    Line := 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty;
    Silent := 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DRV=PTY';
    Code := RunBin('plcconc', ['--cycles=1', '--addr=N7:0', Line], 10000, Output);
    AssertEquals('answered'#10 + Output, 0, Code);
    Code := RunBin('plcconc', ['--cycles=1', '--addr=N200:0', Line], 10000, Output);
    AssertEquals('an error reply'#10 + Output, 3, Code);
    AssertTrue(Output, Pos('1 failed reads', Output) > 0);
    Code := RunBin('plcconc', ['--cycles=1', '--addr=N7:0', Line, Silent], 20000, Output);
    AssertEquals('no answer on line 2'#10 + Output, 4, Code);
    AssertTrue(Output, Pos('| N7:0: no ACK', Output) > 0);
    Code := RunBin('plcconc', ['--cycles=1', '--addr=N200:0', Silent, Line], 20000, Output);
    AssertEquals('an error reply before no answer'#10 + Output, 3, Code);
    AssertTrue(Output, Pos('2 failed reads', Output) > 0);
  finally
    StopProcess(Sim);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestPlcConc);
end.
