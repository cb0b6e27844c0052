{ benchconc - the many-PLCs pattern of examples/plcconc against the legacy
  round robin over the same lines (Linux; "make bench", docs/LAYERS.md
  "The shared wait"):

  1. cycle: N = 8 and 32 tools/df1sim on ptys; plcconc reads N7:0 from
     every line at once, stepped from one ChnWaitAny (IDL=0), and then the
     same lines with --round-robin (no ChnWaitAny, every poll waits up to
     IDL=1 ms): the mean cycle of each and their ratio (goal: the stepped
     pattern no slower);
  2. idle: the same 8 lines silent (every df1sim stopped with SIGSTOP, so
     every read runs into its timeouts): CPU of plcconc in % of one core
     over a few seconds, both ways.

    benchconc          the full run (about half a minute)
    benchconc quick    fewer cycles, 2 s idle }
program benchconc;

{$MODE OBJFPC}{$H+}

uses
  Classes, SysUtils, BaseUnix, Unix, Process, ChildLine, ProcStat;

type
  tSims = array of TProcess;

var
  Quick: Boolean = False;
  Failed: Boolean = False;   { a row failed: exit code 1, after its simulators are stopped }

function Bin(const Name: string): string;
begin
  Result := ExtractFilePath(ParamStr(0)) + Name;
end;

{ df1sim --pty: its first line names the pty. }
function StartSim(out Pty: string): TProcess;
var
  Line: string;
begin
  Pty := '';
  Result := TProcess.Create(nil);
  Result.Executable := Bin('df1sim');
  Result.Parameters.Add('--pty');
  Result.Parameters.Add('--quiet');
  Result.Options := [poUsePipes];
  Result.Execute;
  Line := ReadFirstLine(Result, 3000);
  if Copy(Line, 1, 4) = 'PTY ' then
    Pty := Copy(Line, 5, 255);
end;

procedure StopSims(var Sims: tSims);
var
  I: LongInt;
begin
  for I := 0 to High(Sims) do
  begin
    if Sims[I].Running then
    begin
      FpKill(Sims[I].ProcessID, SIGCONT);
      Sims[I].Terminate(0);
    end;
    Sims[I].Free;
  end;
  Sims := nil;
end;

{ N simulators and the plcconc arguments for their lines. }
function StartSims(N: LongInt; var Sims: tSims; Args: TStrings): Boolean;
var
  I: LongInt;
  Pty: string;
begin
  SetLength(Sims, N);
  for I := 0 to N - 1 do
  begin
    Sims[I] := StartSim(Pty);
    if Pty = '' then
    begin
      WriteLn('benchconc: df1sim did not start');
      SetLength(Sims, I + 1);
      Exit(False);
    end;
    Args.Add('NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty);
  end;
  Result := True;
end;

{ Run plcconc to its end; its mean cycle in ms (-1 on failure). }
function MeanCycle(Lines: TStrings; Cycles: LongInt; RoundRobin: Boolean): Double;
var
  P: TProcess;
  Out_: TStringList;
  S: string;
  I, E, Code: Integer;
begin
  Result := -1;
  P := TProcess.Create(nil);
  Out_ := TStringList.Create;
  try
    P.Executable := Bin('plcconc');
    P.Parameters.Add('--quiet');
    P.Parameters.Add('--cycles');
    P.Parameters.Add(IntToStr(Cycles));
    if RoundRobin then
      P.Parameters.Add('--round-robin');
    P.Parameters.AddStrings(Lines);
    P.Options := [poUsePipes, poWaitOnExit];
    P.Execute;
    Out_.LoadFromStream(P.Output);
    S := Out_.Text;
    I := Pos('mean cycle ', S);
    if (P.ExitStatus <> 0) or (I = 0) then
    begin
      WriteLn('benchconc: plcconc failed: ', S);
      Exit;
    end;
    Inc(I, Length('mean cycle '));
    E := I;
    while S[E] in ['0'..'9', '.'] do
      Inc(E);
    Val(Copy(S, I, E - I), Result, Code);
  finally
    Out_.Free;
    P.Free;
  end;
end;

function IdleCpu(Lines: TStrings; Ms: LongInt; RoundRobin: Boolean): Double;
var
  P: TProcess;
  C0, C1: Double;
  T0, T1: QWord;
begin
  P := TProcess.Create(nil);
  try
    P.Executable := Bin('plcconc');
    P.Parameters.Add('--quiet');
    P.Parameters.Add('--cycles');
    P.Parameters.Add('0');
    if RoundRobin then
      P.Parameters.Add('--round-robin');
    P.Parameters.AddStrings(Lines);
    P.Options := [poUsePipes];
    P.Execute;
    Sleep(500);              { opened, every read under way }
    C0 := ProcCpu(P.ProcessID);
    T0 := GetTickCount64;
    Sleep(Ms);
    C1 := ProcCpu(P.ProcessID);
    T1 := GetTickCount64;
    Result := (C1 - C0) / ((T1 - T0) / 1000) * 100;
    P.Terminate(0);
  finally
    P.Free;
  end;
end;

{ One row of the table: N simulators (stopped with SIGSTOP when Silent),
  plcconc both ways over their lines; Cycles cycles, or Ms of idle CPU. }
procedure Row(N, Cycles, Ms: LongInt; Silent: Boolean);
var
  Sims: tSims;
  Lines: TStringList;
  I: LongInt;
  Stepped, Robin: Double;
begin
  Sims := nil;
  Lines := TStringList.Create;
  try
    if not StartSims(N, Sims, Lines) then
    begin
      Failed := True;             { not Halt: the finally below stops the simulators }
      Exit;
    end;
    if Silent then
    begin
      for I := 0 to High(Sims) do
        FpKill(Sims[I].ProcessID, SIGSTOP);      { the lines fall silent }
      Stepped := IdleCpu(Lines, Ms, False);
      Robin := IdleCpu(Lines, Ms, True);
      WriteLn(Format('  %3d silent lines, %d s: stepped+ChnWaitAny %.2f %% of a core, round robin %.2f %%',
        [N, Ms div 1000, Stepped, Robin]));
      Exit;
    end;
    Stepped := MeanCycle(Lines, Cycles, False);
    Robin := MeanCycle(Lines, Cycles, True);
    if (Stepped < 0) or (Robin < 0) then
    begin
      Failed := True;
      Exit;
    end;
    WriteLn(Format('  %3d lines  %5d cycles  stepped+ChnWaitAny %8.3f ms  round robin %8.3f ms  ratio %5.2f',
      [N, Cycles, Stepped, Robin, Stepped / Robin]));
  finally
    StopSims(Sims);
    Lines.Free;
  end;
end;

begin
  Quick := (ParamCount > 0) and (ParamStr(1) = 'quick');
  WriteLn('benchconc: examples/plcconc, N df1sim on ptys, one read of N7:0 per line and cycle');
  if Quick then
  begin
    Row(8, 100, 0, False);
    Row(8, 0, 2000, True);
  end
  else
  begin
    Row(8, 500, 0, False);
    Row(32, 200, 0, False);
    Row(8, 0, 5000, True);
  end;
  if Failed then
    Halt(1);
end.
