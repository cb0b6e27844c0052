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

    plcconc [OPTION]... 'DF1 stack parameters' ['...' ...]
    plcconc --cycles 10 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200' \
                        'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB1 BD=19200'

  Each parameter string is a whole DF1 stack ending in its physical layer
  (IDL= is appended to it). The options (--addr, --count, --cycles,
  --round-robin: the legacy loop, for comparison; --quiet), the output
  and the exit codes are in --help; the command line is unit ChnCli's
  (docs/TOOLS.md), and all of it - every parameter string, the address -
  is checked before a line is opened. }
program plcconc;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads, Unix,{$ENDIF}
  SysUtils, ChnTypes, ChnWait, ChnLayers, ChnDF1, ChnPccc, ChnPcccClient, ChnCli;

const
  MaxLines = 64;
  WaitMs = 100;

var
  Cli: tCli;
  Lines: array of tPcccClient;
  Req: array of tPcccRequest;
  Params: array of string;
  Addr: string;
  Count, Cycles: LongInt;
  RoundRobin, Quiet: Boolean;

procedure ParseArgs;
var
  I: LongInt;
  C: tPcccClient;
  R: tPcccRequest;
begin
  CliInit(Cli, 'plcconc', '[OPTION]... ''DF1 stack parameters'' [''...'' ...]',
    'A concentrator: reads the same address from every line at once (one DF1 ' +
    'stack per parameter string, each a line to an SLC 500 / MicroLogix or ' +
    'df1sim), all requests stepped from one ChnWaitAny, and prints one line per ' +
    'cycle and a summary line at the end. Up to ' + IntToStr(MaxLines) +
    ' lines; IDL= is appended to each parameter string.');
  CliOption(Cli, 'addr', #0, 'A', 'address to read (default N7:0)');
  CliOption(Cli, 'count', #0, 'N', 'items per read, 1..1000 (default 1)');
  CliOption(Cli, 'cycles', #0, 'N', 'cycles, then the summary line and exit (default 10; 0: for ever)');
  CliOption(Cli, 'round-robin', #0, '', 'the legacy loop instead, for comparison: no ChnWaitAny, ' +
    'every poll waits up to IDL=1 ms (the default of COM)');
  CliOption(Cli, 'quiet', #0, '', 'only the summary line');
  CliEpilog(Cli, 'Output, per cycle and at the end:' + LineEnding +
    '  cycle 3 0.412 ms: N7:0 = 12 | N7:0 = 7 | ...   (or the line''s error)' + LineEnding +
    '  plcconc: 8 lines, 10 cycles, mean cycle 0.401 ms, max 0.612 ms, 0 failed reads, 0 idle waits' +
    LineEnding + '(idle waits: ChnWaitAny calls that ran into their 100 ms).' + LineEnding +
    LineEnding + 'Example:' + LineEnding +
    '  plcconc --cycles 10 ''NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200'' \' +
    LineEnding +
    '                      ''NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB1 BD=19200''' +
    LineEnding);
  CliExit(Cli, 0, 'every read was answered');
  CliExit(Cli, 1, 'a line could not be opened, or a read found it lost (reads that failed ' +
    'in different ways: 1 before 3 before 4)');
  CliExit(Cli, 3, 'a read got an error reply (STS <> 0) or a reply that does not fit');
  CliExit(Cli, 4, 'a read got no answer in time');
  CliParse(Cli);
  Addr := CliValue(Cli, 'addr', 'N7:0');
  Count := CliNum(Cli, 'count', 1, 1000, 1);
  Cycles := CliNum(Cli, 'cycles', 0, High(LongInt), 10);
  RoundRobin := CliHas(Cli, 'round-robin');
  Quiet := CliHas(Cli, 'quiet');
  if CliArgCount(Cli) = 0 then
    CliUsageError(Cli, 'no line given (a DF1 parameter string)', '');
  if CliArgCount(Cli) > MaxLines then
    CliUsageError(Cli, 'more than ' + IntToStr(MaxLines) + ' lines', Cli.Args[MaxLines]);
  { the address and the count, refused without a channel as on one }
  PcccClientInit(C, nil);
  if not PcccStartRead(R, C, Addr, Count) and (R.Result <> res_WrongLayer) and
     (R.Result <> res_WrongState) then
    CliUsageError(Cli, R.Err, Addr);
  SetLength(Params, CliArgCount(Cli));
  for I := 0 to High(Params) do
  begin
    Params[I] := Cli.Args[I];
    CliCheckParams(Cli, Params[I], ChnDF1.cName);
  end;
end;

procedure CloseLines;
var
  I: LongInt;
begin
  for I := 0 to High(Lines) do
    PcccClose(Lines[I]);
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
    PcccClientInit(Lines[I], nil);
  for I := 0 to High(Params) do
    if PcccOpen(Lines[I], Params[I] + Idle) <> res_Ok then
    begin
      WriteLn(StdErr, 'plcconc: line ', I + 1, ': ', Lines[I].Err);
      CloseLines;
      Halt(1);
    end;
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

{ The exit code of the failed reads so far and one more result: a lost
  line (1) before an error answer (3) before no answer (4). }
function Worse(Code: LongInt; R: tChResult): LongInt;
const
  Rank: array[0..4] of LongInt = (0, 3, 0, 2, 1);
var
  C: LongInt;
begin
  C := CliExitOf(R);
  if Rank[C] > Rank[Code] then
    Result := C
  else
    Result := Code;
end;

{ One cycle: a read on every line at once, stepped to the end of all. }
function Cycle(var Failed, IdleWaits, Code: LongInt): Double;
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
    begin
      Inc(Failed);
      Code := Worse(Code, Req[I].Result);
    end;
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
  N, Failed, IdleWaits, Code: LongInt;
  Ms, Sum, Max: Double;
begin
  ParseArgs;
  OpenLines;
  N := 0;
  Failed := 0;
  IdleWaits := 0;
  Code := 0;
  Sum := 0;
  Max := 0;
  while (Cycles = 0) or (N < Cycles) do
  begin
    Inc(N);
    if not Quiet then
      Write('cycle ', N, ' ');
    Ms := Cycle(Failed, IdleWaits, Code);
    Sum := Sum + Ms;
    if Ms > Max then
      Max := Ms;
  end;
  WriteLn(Format('plcconc: %d lines, %d cycles, mean cycle %.3f ms, max %.3f ms, %d failed reads, %d idle waits',
    [Length(Lines), N, Sum / N, Max, Failed, IdleWaits]));
  CloseLines;
  Halt(Code);
end.
