{ df1read - read SLC 500 / MicroLogix data (or tools/df1sim's) by address
  and print it, one line per item.

    df1read [ADDRESS [COUNT]] PARAMETER-STRING...
    df1read N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200

  ADDRESS as unit ChnPccc reads it (N7:0, F8:2, B3:1/4, B3/20, T4:0.ACC,
  C5:0.DN, R6:0.POS, ST9:0, L10:0, S:1, O0:0, I1:0), default N7:0; COUNT
  items, default 10 (1 for a string). The requests and the link dialogue
  are unit ChnPcccClient's; each frame is shown as it goes. The command
  line is unit ChnCli's (docs/TOOLS.md); --help lists the exit codes. }
program df1read;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnLayers, ChnDF1, ChnPccc, ChnPlc5, ChnPcccClient, ChnCli;

var
  Cli: tCli;
  C: tPcccClient;
  R: tPcccRequest;
  Params, Addr: string;
  Count, I, First: LongInt;
  Err: ShortString;

procedure Log(const Line: AnsiString);
begin
  WriteLn('df1read: ', Line);
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
  WriteLn(StdErr, 'df1read: ', What);
  PcccClose(C);
  Halt(Code);
end;

begin
  CliInit(Cli, 'df1read', '[OPTION]... [ADDRESS [COUNT]] PARAMETER-STRING...',
    'Read SLC 500 / MicroLogix data (or df1sim''s) by address over DF1 and print ' +
    'it, one line per item. ADDRESS as N7:0, F8:2, B3:1/4, T4:0.ACC, ST9:0 ' +
    '(default N7:0); COUNT items (default 10, 1 for a string). The parameter ' +
    'string (the arguments from the first one with "=" on) names the DF1 stack.');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  df1read N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200' + LineEnding);
  CliExit(Cli, 0, 'the items were read and printed');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliExit(Cli, 3, 'an error reply (STS <> 0) or a reply that does not fit');
  CliExit(Cli, 4, 'no answer in time');
  CliOption(Cli, 'plc5', #0, '', 'a PLC-5: its addresses (I:012/05, D10:0) and typed ' +
    'read/write (0F 68/67)');
  CliOption(Cli, 'word-range', #0, '', 'a PLC-5 with word range read/write (0F 01/00) instead');
  CliParse(Cli);
  Addr := 'N7:0';
  Count := 10;
  First := 0;
  while (First < CliArgCount(Cli)) and (First < 2) and (Pos('=', Cli.Args[First]) = 0) do
    Inc(First);
  if First >= 1 then
    Addr := Cli.Args[0];
  if First = 2 then
  begin
    if not StrToNum(Cli.Args[1], 1, PcccMaxItems, Count) then
      CliUsageError(Cli, 'COUNT wants 1..' + IntToStr(PcccMaxItems), Cli.Args[1]);
  end
  else if Pos('ST', UpperCase(Trim(Addr))) = 1 then
    Count := 1;
  Params := CliRest(Cli, First);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string (e.g. NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0)', '');
  PcccClientInit(C, nil);
  Family(C);
  if PcccCheckRead(C, Addr, Count, Err) <> res_Ok then
    CliUsageError(Cli, Err, Addr);
  CliCheckParams(Cli, Params, ChnDF1.cName);
  if PcccOpen(C, Params) <> res_Ok then
    Fail(C.Err, 1);
  Family(C);
  WriteLn('df1read: ', C.Chn^.ChGetParam(''));
  C.Log := @Log;
  if PcccStartRead(R, C, Addr, Count) then
    PcccFinish(R);
  if R.Result <> res_Ok then
    Fail(R.Err + ' (' + ChResultText(R.Result, PcccLayer) + ')', PcccExitCode(R.Result));
  for I := 0 to Count - 1 do
    WriteLn(PcccItemText(R, I));
  PcccClose(C);
end.
