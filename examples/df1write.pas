{ df1write - write SLC 500 / MicroLogix data (or tools/df1sim's) by address.

    df1write ADDRESS VALUE... PARAMETER-STRING...
    df1write N7:0 1 2 3 NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=19200
    df1write B3:1/4 1 ...        a bit: 0 or 1 (a masked write, the other
                                 bits of the word stay)
    df1write F8:0 1.5 -2.25 ...  floats;  T4:0.PRE 100 ...  timer preset
    df1write ST9:0 'some text' ...

  One value per item from ADDRESS on (three for a whole T, C or R element:
  control word, PRE or LEN, ACC or POS); the parameter string starts at the
  first argument with '='. The address and the values are checked (a dry
  run on an in-memory line) before the device is opened. A negative value is a value, not an option
  ("--" is not needed). The command line is unit ChnCli's; --help lists
  the exit codes (docs/TOOLS.md). }
program df1write;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, ChnTypes, ChnLayers, ChnDF1, ChnPccc, ChnPlc5, ChnPcccClient, ChnCli;

var
  Cli: tCli;
  C: tPcccClient;
  R: tPcccRequest;
  Params, Addr: string;
  Values: array of ShortString;
  I, First: LongInt;

procedure Log(const Line: AnsiString);
begin
  WriteLn('df1write: ', Line);
end;

{ --plc5, --word-range: the PLC-5's addresses and commands }
procedure Family(var C: tPcccClient);
begin
  if CliHas(Cli, 'word-range') then
    PcccClientPlc5(C, p5WordRange)
  else if CliHas(Cli, 'plc5') then
    PcccClientPlc5(C, p5Typed);
end;

procedure Fail(const What: string; Code: Integer);
begin
  WriteLn(StdErr, 'df1write: ', What);
  PcccClose(C);
  Halt(Code);
end;

begin
  CliInit(Cli, 'df1write', '[OPTION]... ADDRESS VALUE... PARAMETER-STRING...',
    'Write SLC 500 / MicroLogix data (or df1sim''s) by address over DF1: one ' +
    'VALUE per item from ADDRESS on (three for a whole T, C or R element), a bit ' +
    'as 0 or 1, floats for F, a text for ST. The parameter string starts at the ' +
    'first argument with "=".');
  CliEpilog(Cli, 'Examples:' + LineEnding +
    '  df1write N7:0 1 2 3 NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=19200' + LineEnding +
    '  df1write B3:1/4 1 NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=19200' + LineEnding);
  CliExit(Cli, 0, 'the values were written');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliExit(Cli, 3, 'an error reply (STS <> 0) or a reply that does not fit');
  CliExit(Cli, 4, 'no answer in time');
  { "-1" is a value: no short option may take it }
  CliOption(Cli, 'plc5', #0, '', 'a PLC-5: its addresses (I:012/05, D10:0) and typed ' +
    'read/write (0F 68/67)');
  CliOption(Cli, 'word-range', #0, '', 'a PLC-5 with word range read/write (0F 01/00) instead');
  CliParse(Cli);
  First := 1;
  while (First < CliArgCount(Cli)) and (Pos('=', Cli.Args[First]) = 0) do
    Inc(First);
  if CliArgCount(Cli) = 0 then
    CliUsageError(Cli, 'no ADDRESS', '');
  Addr := Cli.Args[0];
  SetLength(Values, 0);
  for I := 1 to First - 1 do
  begin
    SetLength(Values, Length(Values) + 1);
    Values[High(Values)] := Cli.Args[I];
  end;
  if Length(Values) = 0 then
    CliUsageError(Cli, 'no VALUE after the address', Addr);
  Params := CliRest(Cli, First);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string (e.g. NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0)', '');
  { the values against the address before any device is opened: a dry run
    on an in-memory line (NAM=LOOP, nobody at the other end) }
  PcccClientInit(C, nil);
  Family(C);
  if PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 NAM=LOOP PAIR=DF1WRITE-DRY-RUN END=1') = res_Ok then
  begin
    Family(C);
    if PcccStartWriteText(R, C, Addr, Values) then
      PcccCancel(R)
    else if (R.Result = res_PcccAddress) or (R.Result = res_PcccCount) or
            (R.Result = res_PcccValue) or (R.Result = res_PcccUsage) then
      CliUsageError(Cli, R.Err, Addr);
    PcccClose(C);
  end;
  PcccClientInit(C, nil);
  Family(C);
  CliCheckParams(Cli, Params, ChnDF1.cName);
  if PcccOpen(C, Params) <> res_Ok then
    Fail(C.Err, 1);
  Family(C);
  C.Log := @Log;
  if PcccStartWriteText(R, C, Addr, Values) then
    PcccFinish(R);
  if R.Result <> res_Ok then
    Fail(R.Err + ' (' + ChResultText(R.Result, PcccLayer) + ')', PcccExitCode(R.Result));
  WriteLn('df1write: ', Length(Values), ' value(s) written from ', Addr);
  PcccClose(C);
end.
