{ waitany - a new-style program that blocks instead of polling: it watches
  several lines at once and prints what arrives on each, in hex.

    waitany SECONDS 'DEV=/dev/ttyUSB0 BD=9600' 'NAM=TCP HOST=nport1 PORT=4001' ...

  Every argument after the first is the parameter string of one line: the
  COM layer's (docs/ChnCom.md), or any layer's after its NAM=. A line that
  cannot be opened or goes away ends the program (exit code 1). The
  command line is unit ChnCli's (docs/TOOLS.md). The channels are opened with IDL=0, so a poll never
  waits; the program waits once, in ChnWaitAny, for the first byte on any
  line (or one second), then polls every line once. Idle, it takes no CPU;
  a byte on any line wakes it at once (docs/LAYERS.md, "The shared wait"). }
program waitany;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnCom, uString, ChnCli;

const
  MaxLines = 32;

var
  Cli: tCli;
  Chn: array[1..MaxLines] of pChnVirt;
  Buf: array[0..255] of Byte;
  N, I: Integer;
  Len: Word;
  Seconds: LongInt;
  Deadline: QWord;
begin
  CliInit(Cli, 'waitany', 'SECONDS PARAMETER-STRING...',
    'Watch several lines at once and print what arrives on each, in hex, for ' +
    'SECONDS: every further argument is the parameter string of one line (the COM ' +
    'layer''s, or any layer''s after its NAM=), opened with IDL=0; the program ' +
    'blocks in ChnWaitAny until a byte arrives on any line.');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  waitany 60 ''DEV=/dev/ttyUSB0 BD=9600'' ''DEV=/dev/ttyUSB1 BD=19200''' + LineEnding);
  CliExit(Cli, 0, 'the time is over');
  CliExit(Cli, 1, 'a line could not be opened, or was lost');
  CliParse(Cli);
  if CliArgCount(Cli) < 2 then
    CliUsageError(Cli, 'SECONDS and at least one parameter string wanted', CliRest(Cli, 0));
  Seconds := 0;
  if not StrToNum(Cli.Args[0], 1, 86400, Seconds) then
    CliUsageError(Cli, 'SECONDS wants 1..86400', Cli.Args[0]);
  if CliArgCount(Cli) - 1 > MaxLines then
    CliUsageError(Cli, 'at most ' + IntToStr(MaxLines) + ' lines', Cli.Args[MaxLines + 1]);
  N := CliArgCount(Cli) - 1;
  { every string is checked before any line is opened }
  for I := 1 to N do
    Chn[I] := CliChannel(Cli, Cli.Args[I] + ' IDL=0', ChnCom.cName);   { never wait in a poll }
  for I := 1 to N do
  begin
    Chn[I]^.ChOpen;
    if Chn[I]^.ChResult <> res_Ok then
    begin
      WriteLn(StdErr, 'waitany: line ', I, ': ', Chn[I]^.ChErrorText);
      for Len := 1 to N do
        Dispose(Chn[Len], Done);
      Halt(1);
    end;
    Chn[I]^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    Chn[I]^.ChConnect;
    WriteLn('line ', I, ': ', Chn[I]^.ChGetParam(''));
  end;
  Deadline := GetTickCount64 + QWord(Seconds) * 1000;
  while (N > 0) and (GetTickCount64 < Deadline) do
  begin
    { sleep until a byte arrives on any line, at most a second }
    ChnWaitAny(1000);
    for I := 1 to N do
      while Chn[I]^.ChReceiveReady = CHS_ReceiveReady do
      begin
        Chn[I]^.ChReceive(Len);
        if Chn[I]^.ChReceiveResult = res_Overrun then
          WriteLn('line ', I, ': bytes were lost');
        WriteLn('line ', I, ': ', HexBytes(@Buf, Len));
      end;
    for I := 1 to N do
      if Chn[I]^.ChResult <> res_Ok then
      begin
        WriteLn(StdErr, 'waitany: line ', I, ' lost: ', Chn[I]^.ChResultStr(Chn[I]^.ChResult));
        for Len := 1 to N do
          Dispose(Chn[Len], Done);
        Halt(1);
      end;
  end;
  for I := 1 to N do
    Dispose(Chn[I], Done);
end.
