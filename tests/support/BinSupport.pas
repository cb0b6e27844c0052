{ BinSupport - running the programs of $BUILD/bin (examples, tools) from
  tests: with a deadline, so a hanging program fails a test instead of
  stopping the suite, and tools/df1sim on a pty of its own. }
unit BinSupport;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, Pipes;

{ $BUILD/bin/Name (BUILD defaults to build; Name.exe on Windows). }
function BinPath(const Name: string): string;
{ $BUILD/test-bin/, where make test puts the test builds of programs
  (heaptrc, run-time checks). }
function TestBinDir: string;
{ Make P run Exe: directly, or, when the environment names an emulator in
  CHN_EXEC (make crosstest: qemu-aarch64, qemu-arm - a process under
  qemu-user cannot start another target program by itself), programs of
  $BUILD/bin through it; host programs (sh, socat, tshark) directly.
  Parameters added afterwards go to Exe. }
procedure BinExecutable(P: TProcess; const Exe: string);
{ BinPath(Name) as a /bin/sh command word (with CHN_EXEC in front). }
function BinShellWord(const Name: string): string;
{ Run a program to its end; its exit code, or -1 when it did not end
  within TimeoutMs (it is killed then). Output gets standard output and
  standard error. }
function RunBin(const Name: string; const Args: array of string; TimeoutMs: Integer;
  out Output: string): Integer;
{ The same for any executable (e.g. /bin/sh -c, to pass an empty argument,
  which TProcess drops). }
function RunExe(const Exe: string; const Args: array of string; TimeoutMs: Integer;
  out Output: string): Integer;
{ Run P, set up (executable, parameters, environment, poStderrToOutPut
  or not), to its end: what it writes to standard output in Output, to
  standard error in Errors (apart) or Output too (poStderrToOutPut); its
  exit code, or -1 when it still ran after TimeoutMs (it is killed then).
  The caller frees P. }
function RunProcess(P: TProcess; TimeoutMs: Integer; out Output, Errors: string): Integer;
{ P's environment this program's, with heaptrc's report going to the file
  HeapLog instead. }
procedure HeapLogTo(P: TProcess; const HeapLog: string);
{ Move what P's output pipe holds to Output (never waits). }
procedure Drain(P: TProcess; var Output: string);
{ What a pipe of a process (P.Output, P.Stderr) holds now (never waits). }
function PipeText(S: TInputPipeStream): string;
{ The end of a program a test started: ended if it still runs (asked to,
  then killed after 3 s), waited for, freed; P is nil afterwards. }
procedure StopProcess(var P: TProcess);
{$IFDEF UNIX}
{ The same with signal Sig first (SIGCONT before it: the test may have
  stopped P). Never waits for ever: a test that failed half-way must not
  hang the suite in its clean-up. }
procedure StopProcessWith(var P: TProcess; Sig: LongInt);
{$ENDIF}
{ Start tools/df1sim --pty with Args; Pty gets the device it printed on its
  first line ('' if none came within 3 s). The caller frees the process. }
function StartSimPty(const Args: array of string; out Pty: string): TProcess;

implementation

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF} ChnVirt, ChildLine;

function BinPath(const Name: string): string;
begin
  Result := GetEnvironmentVariable('BUILD');
  if Result = '' then
    Result := 'build';
  Result := Result + '/bin/' + Name {$IFDEF WINDOWS} + '.exe'{$ENDIF};
end;

{ $BUILD/test-bin/, where make test puts the test builds of programs. }
function TestBinDir: string;
begin
  Result := GetEnvironmentVariable('BUILD');
  if Result = '' then
    Result := 'build';
  Result := Result + '/test-bin/';
end;

procedure BinExecutable(P: TProcess; const Exe: string);
var
  Emu: string;
begin
  Emu := GetEnvironmentVariable('CHN_EXEC');
  { the tools (build/bin) and the heap-checked builds of them the suite
    makes (build/test-bin) are target programs; anything else is the host's }
  if (Emu = '') or ((Copy(Exe, 1, Length(BinPath(''))) <> BinPath('')) and
    (Copy(Exe, 1, Length(TestBinDir)) <> TestBinDir)) then
    P.Executable := Exe
  else
  begin
    P.Executable := Emu;
    P.Parameters.Add(Exe);
  end;
end;

function BinShellWord(const Name: string): string;
begin
  Result := BinPath(Name);
  if GetEnvironmentVariable('CHN_EXEC') <> '' then
    Result := GetEnvironmentVariable('CHN_EXEC') + ' ' + Result;
end;

function PipeText(S: TInputPipeStream): string;
var
  Buf: array[0..4095] of Char;
  N: Integer;
begin
  Result := '';
  while S.NumBytesAvailable > 0 do
  begin
    N := S.Read(Buf, SizeOf(Buf));
    if N <= 0 then
      Break;
    Result := Result + Copy(Buf, 0, N);
  end;
end;

procedure StopProcess(var P: TProcess);
begin
  {$IFDEF UNIX}
  StopProcessWith(P, SIGTERM);
  {$ELSE}
  if P = nil then
    Exit;
  if P.Running then
  begin
    P.Terminate(255);
    P.WaitOnExit;
  end;
  FreeAndNil(P);
  {$ENDIF}
end;

{$IFDEF UNIX}
procedure StopProcessWith(var P: TProcess; Sig: LongInt);
var
  Deadline: QWord;
begin
  if P = nil then
    Exit;
  if P.Running then
  begin
    FpKill(P.ProcessID, SIGCONT);
    FpKill(P.ProcessID, Sig);
    Deadline := ChMsTick + 3000;
    while P.Running and (ChMsTick < Deadline) do
      Sleep(5);
    if P.Running then
    begin
      FpKill(P.ProcessID, SIGKILL);
      Deadline := ChMsTick + 10000;
      while P.Running and (ChMsTick < Deadline) do   { Running reaps it }
        Sleep(5);
      if P.Running then
        WriteLn(StdErr, 'process ', P.ProcessID, ' (', P.Executable, ') did not end after SIGKILL');
    end;
  end;
  FreeAndNil(P);
end;
{$ENDIF}

procedure Drain(P: TProcess; var Output: string);
begin
  Output := Output + PipeText(P.Output);
end;

function RunBin(const Name: string; const Args: array of string; TimeoutMs: Integer;
  out Output: string): Integer;
begin
  Result := RunExe(BinPath(Name), Args, TimeoutMs, Output);
end;

function RunProcess(P: TProcess; TimeoutMs: Integer; out Output, Errors: string): Integer;
var
  Deadline: QWord;
  Apart: Boolean;
begin
  Output := '';
  Errors := '';
  Apart := not (poStderrToOutPut in P.Options);
  P.Options := P.Options + [poUsePipes];
  P.Execute;
  Deadline := ChMsTick + QWord(TimeoutMs);
  while P.Running and (ChMsTick < Deadline) do
  begin
    Output := Output + PipeText(P.Output);
    if Apart then
      Errors := Errors + PipeText(P.Stderr);
    Sleep(2);
  end;
  if P.Running then
  begin
    P.Terminate(255);
    P.WaitOnExit;
    Result := -1;
  end
  else
    Result := P.ExitCode;
  Output := Output + PipeText(P.Output);
  if Apart then
    Errors := Errors + PipeText(P.Stderr);
end;

procedure HeapLogTo(P: TProcess; const HeapLog: string);
var
  I: Integer;
begin
  for I := 1 to GetEnvironmentVariableCount do
    if Pos('HEAPTRC=', GetEnvironmentString(I)) <> 1 then
      P.Environment.Add(GetEnvironmentString(I));
  P.Environment.Add('HEAPTRC=log=' + HeapLog);
end;

function RunExe(const Exe: string; const Args: array of string; TimeoutMs: Integer;
  out Output: string): Integer;
var
  P: TProcess;
  A, Errors: string;
begin
  P := TProcess.Create(nil);
  try
    BinExecutable(P, Exe);
    for A in Args do
      P.Parameters.Add(A);
    P.Options := [poStderrToOutPut];
    Result := RunProcess(P, TimeoutMs, Output, Errors);
  finally
    P.Free;
  end;
end;

function StartSimPty(const Args: array of string; out Pty: string): TProcess;
var
  A, Line: string;
begin
  Pty := '';
  Result := TProcess.Create(nil);
  BinExecutable(Result, BinPath('df1sim'));
  Result.Parameters.Add('--pty');
  for A in Args do
    Result.Parameters.Add(A);
  Result.Options := [poUsePipes];
  Result.Execute;
  Line := ReadFirstLine(Result, 3000);
  if Copy(Line, 1, 4) = 'PTY ' then
    Pty := Copy(Line, 5, 255);
end;

end.
