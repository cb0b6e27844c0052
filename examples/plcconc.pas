{ plcconc - a concentrator: reads the same address from N PLCs (SLC 500 /
  MicroLogix, or tools/df1sim) over N DF1 lines at once, one line of
  output per cycle. The documented pattern for many lines in one program
  (docs/LAYERS.md "The shared wait", docs/ChnPccc.md "Many PLCs"):

    start a request on every line (PcccStartRead), then
    repeat
      ChnWaitAny(100);               one wait for the whole program
      for every line: PcccStep        takes all that line has received
    until every request is done

  The channels are opened with IDL=0, so no poll waits; the program
  sleeps only in ChnWaitAny, which ends at the first byte on any line and
  returns at once while a layer holds input not yet taken.

    plcconc [options] 'DF1 stack parameters' ['...' ...]
    plcconc --cycles 10 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200' \
                        'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB1 BD=19200'

  Options (--opt VALUE or --opt=VALUE):
    --addr A        address to read (default N7:0)
    --count N       items per read (default 1)
    --cycles N      cycles, then a summary line and exit (default 10; 0: for ever)
    --round-robin   the legacy loop instead, for comparison: no ChnWaitAny,
                    every poll waits up to IDL=1 ms (the default of COM)
    --quiet         only the summary line
    --help, -h      this text
  Each parameter string is a whole DF1 stack ending in its physical layer
  (IDL= is appended to it). Output per cycle:
    cycle 3 0.412 ms: N7:0 = 12 | N7:0 = 7 | ...   (or the line's error)
  and at the end:
    plcconc: 8 lines, 10 cycles, mean cycle 0.401 ms, max 0.612 ms, 0 failed reads, 0 idle waits
  (idle waits: ChnWaitAny calls that ran into their 100 ms).
  Exit code: 0 every read answered, 1 bad command line or a line cannot be
  opened, 2 some read failed. }
program plcconc;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads, Unix,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnWait, ChnCom, ChnTcp, ChnTrc, ChnDF1,
  ChnPccc, ChnPcccClient;

const
  MaxLines = 64;
  WaitMs = 100;

var
  Lines: array of tPcccClient;
  Req: array of tPcccRequest;
  Params: array of string;
  Addr: string = 'N7:0';
  Count: LongInt = 1;
  Cycles: LongInt = 10;
  RoundRobin: Boolean = False;
  Quiet: Boolean = False;

procedure Usage(ToErr: Boolean);
const
  Text =
    'usage: plcconc [--addr A] [--count N] [--cycles N] [--round-robin] [--quiet]' + LineEnding +
    '               ''DF1 stack parameters'' [''...'' ...]' + LineEnding +
    'Reads A from every line at once, one line of output per cycle (see the' + LineEnding +
    'header of examples/plcconc.pas). Exit: 0 ok, 1 usage or open error, 2 a read failed.';
begin
  if ToErr then
    WriteLn(StdErr, Text)
  else
    WriteLn(Text);
end;

procedure Die(const What: string);
begin
  WriteLn(StdErr, 'plcconc: ', What);
  Halt(1);
end;

{ --opt VALUE and --opt=VALUE }
procedure ParseArgs;
var
  I: LongInt;
  A, Key, Value: string;
  N: LongInt;

  function TakeValue: string;
  begin
    if Value <> '' then
      Exit(Value);
    Inc(I);
    if I > ParamCount then
      Die('missing value (' + Key + ')');
    Result := ParamStr(I);
  end;

begin
  if ParamCount = 0 then
  begin
    Usage(True);
    Halt(2);
  end;
  I := 1;
  while I <= ParamCount do
  begin
    A := ParamStr(I);
    if (A = '--help') or (A = '-h') then
    begin
      Usage(False);
      Halt(0);
    end;
    if Copy(A, 1, 2) = '--' then
    begin
      Key := A;
      Value := '';
      if Pos('=', A) > 0 then
      begin
        Key := Copy(A, 1, Pos('=', A) - 1);
        Value := Copy(A, Pos('=', A) + 1, Length(A));
      end;
      if Key = '--addr' then
        Addr := TakeValue
      else if Key = '--count' then
      begin
        if not StrToNum(TakeValue, 1, 1000, N) then
          Die('bad count (' + A + ')');
        Count := N;
      end
      else if Key = '--cycles' then
      begin
        if not StrToNum(TakeValue, 0, High(LongInt), N) then
          Die('bad number of cycles (' + A + ')');
        Cycles := N;
      end
      else if Key = '--round-robin' then
        RoundRobin := True
      else if Key = '--quiet' then
        Quiet := True
      else
        Die('unknown option (' + A + ')');
    end
    else
    begin
      if Length(Params) = MaxLines then
        Die('more than ' + IntToStr(MaxLines) + ' lines (' + A + ')');
      SetLength(Params, Length(Params) + 1);
      Params[High(Params)] := A;
    end;
    Inc(I);
  end;
  if Length(Params) = 0 then
    Die('no line given (a DF1 parameter string)');
end;

procedure OpenLines;
var
  I: LongInt;
  Idle: string;
begin
  if RoundRobin then
    Idle := ' IDL=1'
  else
    Idle := ' IDL=0';
  SetLength(Lines, Length(Params));
  SetLength(Req, Length(Params));
  for I := 0 to High(Params) do
    if PcccOpen(Lines[I], Params[I] + Idle) <> res_Ok then
      Die('line ' + IntToStr(I + 1) + ': ' + Lines[I].Err);
end;

procedure CloseLines;
var
  I: LongInt;
begin
  for I := 0 to High(Lines) do
    PcccClose(Lines[I]);
end;

{ A clock in ms with microsecond steps where the system has one. }
function NowMs: Double;
{$IFDEF UNIX}
var
  T: TTimeVal;
begin
  fpgettimeofday(@T, nil);
  Result := T.tv_usec;                 { a Double: 1000.0 alone is a Single }
  Result := Double(T.tv_sec) * 1000 + Result / 1000;
end;
{$ELSE}
begin
  Result := GetTickCount64;
end;
{$ENDIF}

{ One cycle: a read on every line at once, stepped to the end of all. }
function Cycle(var Failed, IdleWaits: LongInt): Double;
var
  I, K: LongInt;
  Busy: Boolean;
begin
  Result := NowMs;
  for I := 0 to High(Lines) do
    PcccStartRead(Req[I], Lines[I], Addr, Count);   { a failed start is done at once }
  repeat
    if not RoundRobin then
      if not ChnWaitAny(WaitMs) then
        Inc(IdleWaits);
    Busy := False;
    for I := 0 to High(Lines) do
      if not PcccStep(Req[I]) then
        Busy := True;
  until not Busy;
  Result := NowMs - Result;
  for I := 0 to High(Lines) do
    if Req[I].Result <> res_Ok then
      Inc(Failed);
  if Quiet then
    Exit;
  Write(Format('%.3f ms:', [Result]));
  for I := 0 to High(Lines) do
  begin
    if I > 0 then
      Write(' |');
    if Req[I].Result <> res_Ok then
      Write(' ', Req[I].Err)
    else
      for K := 0 to Count - 1 do
        Write(' ', PcccItemText(Req[I], K));
  end;
  WriteLn;
end;

var
  N, Failed, IdleWaits: LongInt;
  Ms, Sum, Max: Double;
begin
  ParseArgs;
  OpenLines;
  N := 0;
  Failed := 0;
  IdleWaits := 0;
  Sum := 0;
  Max := 0;
  while (Cycles = 0) or (N < Cycles) do
  begin
    Inc(N);
    if not Quiet then
      Write('cycle ', N, ' ');
    Ms := Cycle(Failed, IdleWaits);
    Sum := Sum + Ms;
    if Ms > Max then
      Max := Ms;
  end;
  WriteLn(Format('plcconc: %d lines, %d cycles, mean cycle %.3f ms, max %.3f ms, %d failed reads, %d idle waits',
    [Length(Lines), N, Sum / N, Max, Failed, IdleWaits]));
  CloseLines;
  if Failed > 0 then
    Halt(2);
end.
