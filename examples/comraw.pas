{ comraw - raw use of a physical layer, no protocol: send some bytes, then
  show what arrives, in hex, for a few seconds.

    comraw [--seconds=S] 'DEV=/dev/ttyUSB0 BD=9600' ['01 02 FF']
    comraw 'NAM=TCP HOST=nport1 PORT=4001' ['01 02 FF'] [SECONDS]

  The first argument is the COM layer's parameter string (docs/ChnCom.md),
  or another physical layer's after its NAM= (docs/ChnTcp.md); the channel
  is opened exactly as a legacy program would open it. The command line is
  unit ChnCli's; --help lists the exit codes (docs/TOOLS.md). A device
  that goes away ends the program at once with exit code 1. }
program comraw;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnLayers, ChnCom, ChnCli;

var
  Cli: tCli;
  Chn: pChnVirt;
  Buf: array[0..255] of Byte;
  Out: array[0..255] of Byte;
  OutLen, I: Integer;
  Len: Word;
  Hex, Pair: string;
  Deadline: QWord;
  Seconds: LongInt;
begin
  CliInit(Cli, 'comraw', '[OPTION]... PARAMETER-STRING [HEX-BYTES [SECONDS]]',
    'Raw use of a physical layer, no protocol: open it from PARAMETER-STRING (the ' +
    'COM layer''s, or another physical layer''s after its NAM=), send HEX-BYTES, ' +
    'then print what arrives, in hex, for SECONDS (default 2).');
  CliOption(Cli, 'seconds', 's', 'S', 'listen for S seconds (default 2; also the third argument)');
  CliEpilog(Cli, 'Examples:' + LineEnding +
    '  comraw ''DEV=/dev/ttyUSB0 BD=9600'' ''01 02 FF''' + LineEnding +
    '  comraw ''NAM=TCP HOST=nport1 PORT=4001'' ''01 02 FF'' 5' + LineEnding);
  CliExit(Cli, 0, 'done: the bytes were sent and the time is over');
  CliExit(Cli, 1, 'the device could not be opened, a send failed, or the device was lost');
  CliParse(Cli);
  if (CliArgCount(Cli) < 1) or (CliArgCount(Cli) > 3) then
    CliUsageError(Cli, 'PARAMETER-STRING [HEX-BYTES [SECONDS]] wanted', CliRest(Cli, 0));
  Seconds := CliNum(Cli, 'seconds', 0, 86400, 2);
  if (CliArgCount(Cli) = 3) and not StrToNum(Cli.Args[2], 0, 86400, Seconds) then
    CliUsageError(Cli, 'SECONDS wants 0..86400', Cli.Args[2]);
  OutLen := 0;
  if CliArgCount(Cli) >= 2 then
  begin
    Hex := StringReplace(Cli.Args[1], ' ', '', [rfReplaceAll]);
    if Odd(Length(Hex)) then
      CliUsageError(Cli, 'HEX-BYTES wants pairs of hex digits', Cli.Args[1]);
    while (Hex <> '') do
    begin
      Pair := Copy(Hex, 1, 2);
      if (OutLen >= SizeOf(Out)) or not (Pair[1] in ['0'..'9', 'a'..'f', 'A'..'F']) or
         not (Pair[2] in ['0'..'9', 'a'..'f', 'A'..'F']) then
        CliUsageError(Cli, 'HEX-BYTES wants at most 256 pairs of hex digits', Pair);
      Out[OutLen] := StrToInt('$' + Pair);
      Inc(OutLen);
      Delete(Hex, 1, 2);
    end;
  end;
  Chn := CliChannel(Cli, Cli.Args[0], ChnCom.cName);
  if Chn^.ChResult = res_Ok then
    Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then
  begin
    WriteLn(StdErr, 'comraw: ', Chn^.ChErrorText);
    Dispose(Chn, Done);
    Halt(1);
  end;
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Chn^.ChConnect;
  WriteLn(Chn^.ChGetParam(''));
  if OutLen > 0 then
  begin
    Chn^.ChSend(@Out, OutLen);
    Deadline := GetTickCount64 + 5000;
    while (Chn^.ChSendReady <> CHS_SendReady) and (Chn^.ChSendResult = res_Ok) and
          (GetTickCount64 < Deadline) do ;   { IDL keeps this cheap }
    WriteLn('sent ', OutLen, ' bytes: ', Chn^.ChResultStr(Chn^.ChSendResult));
    if Chn^.ChSendResult <> res_Ok then
    begin
      WriteLn(StdErr, 'comraw: send: ', Chn^.ChResultStr(Chn^.ChSendResult));
      Dispose(Chn, Done);
      Halt(1);
    end;
  end;
  Deadline := GetTickCount64 + QWord(Seconds) * 1000;
  while (GetTickCount64 < Deadline) and (Chn^.ChResult = res_Ok) do
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Chn^.ChReceive(Len);
      Write(FormatDateTime('hh:nn:ss.zzz', Now), ' ', Len:3, ':');
      for I := 0 to Len - 1 do
        Write(' ', IntToHex(Buf[I], 2));
      if Chn^.ChReceiveResult <> res_Ok then
        Write('  (', Chn^.ChResultStr(Chn^.ChReceiveResult), ')');
      WriteLn;
      if Chn^.ChReceiveResult in [res_DeviceLost, res_IOError] then
        Break;
    end;
  if Chn^.ChResult = res_Ok then
    I := Chn^.ChReceiveResult
  else
    I := Chn^.ChResult;
  if (I = res_DeviceLost) or (I = res_IOError) or (Chn^.ChResult <> res_Ok) then
  begin
    WriteLn(StdErr, 'comraw: line lost: ', Chn^.ChResultStr(I));
    Dispose(Chn, Done);
    Halt(1);
  end;
  Dispose(Chn, Done);
end.
