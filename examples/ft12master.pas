{ ft12master - the example of the ChnFT1_2 manual (chapter 7), corrected.

  Sends one variable-length message from a master to a slave and decodes
  the answer. Corrections to the printed example (docs/PROTOCOLS.md section 7):
  MAS=MASTER instead of MASTER=ON, a blank between the concatenated
  parameter strings, "while not (ChReceiveReady = CHS_ReceiveReady)",
  missing semicolons; and FCM_UserDataReply with FCV = True instead of
  FCM_CheckLink with FCV = False (the manual marks FC 2 "balanced only" and
  wants FCV = True for it). Every wait has a timeout and every error is
  printed with ChResultStr, so the program never hangs.

  Usage:  ft12master [--timeout=MS] 'parameter string' [timeout-ms]
  e.g.    ft12master 'NAM=FT1_2 MS=ON MAS=MASTER LSB=500 NOD=1 DNO=2 NAM=COM COM=1 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000'

  Without arguments it prints its usage and opens nothing (it never
  transmits on a COM1 nobody named). The physical layer is chosen by NAM=
  in the string; ChnLayers links every layer. A string without GAP= gets
  the tools' default (ChnFT12Gap). A line lost while waiting ends the
  program at once. The command line is unit ChnCli's (docs/TOOLS.md). }
program ft12master;

{$MODE OBJFPC}{$H-}

uses
  SysUtils,
  uString,
  ChnTypes,
  ChnVirt,
  ChnLayers,
  ChnFT1_2,
  ChnFT12Gap,
  ChnCli;

const
  DefaultParams: tParamStr =
    'NAM=FT1_2 MS=ON MAS=MASTER LSB=500 NOD=1 DNO=2 ' +
    'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Cli   : tCli;
  Chn   : pChnVirt;
  SMess : pSendRecord;
  RMess : pRecRecord;
  LSMess: Word;
  LRMess: Word;
  I     : Integer;
  Params: tParamStr;
  TimeoutMs: LongInt;
  Deadline: QWord;

{ Print what went wrong, clean up and stop with exit code 1. }
procedure Fail(const What: string; R: tChResult);
begin
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'ft12master: ', What, ': ', Chn^.ChErrorText)  { token, OS reason }
  else
    WriteLn(StdErr, 'ft12master: ', What, ': ', Chn^.ChResultStr(R));
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
  if R = res_Timeout then
    Halt(4);
  Halt(1);
end;

begin
  CliInit(Cli, 'ft12master', '[OPTION]... PARAMETER-STRING [TIMEOUT-MS]',
    'The example of the ChnFT1_2 manual (chapter 7), corrected: send one ' +
    'variable-length message (user data, FC 3) from an unbalanced master to a ' +
    'slave and print the answer. TIMEOUT-MS (default 2000) bounds every wait. A ' +
    'string without GAP= gets GAP= for ' + IntToStr(FT12DefaultGapMs) + ' ms at its BD=.');
  CliOption(Cli, 'timeout', 't', 'MS', 'wait at most MS ms for each step (default 2000)');
  CliEpilog(Cli, 'Example (the manual''s string):' + LineEnding + '  ft12master ''' +
    DefaultParams + '''' + LineEnding);
  CliExit(Cli, 0, 'an answer came and was printed');
  CliExit(Cli, 1, 'the line could not be opened, was lost, or the answer was broken');
  CliExit(Cli, 4, 'no answer in time');
  CliParse(Cli);
  if (CliArgCount(Cli) < 1) or (CliArgCount(Cli) > 2) then
    CliUsageError(Cli, 'PARAMETER-STRING [TIMEOUT-MS] wanted', CliRest(Cli, 0));
  TimeoutMs := CliNum(Cli, 'timeout', 1, 600000, 2000);
  if (CliArgCount(Cli) = 2) and not StrToNum(Cli.Args[1], 1, 600000, TimeoutMs) then
    CliUsageError(Cli, 'TIMEOUT-MS wants 1..600000', Cli.Args[1]);
  Params := Cli.Args[0];
  CliCheckParams(Cli, Params, ChnFT1_2.cName);
  New(SMess);
  New(RMess);
  { create the channel }
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  with Chn^ do
  begin
    { communication parameters }
    ChSetParam(Params);
    if ChResult <> res_Ok then Fail('ChSetParam', ChResult);
    FT12SetDefaultGap(Chn, Params);
    ChOpen;
    if ChResult <> res_Ok then Fail('ChOpen', ChResult);
    { where received messages go }
    ChReceiveBuffer(RMess, SizeOf(RMess^));
    if ChReceiveResult <> res_Ok then Fail('ChReceiveBuffer', ChReceiveResult);
    ChConnect;
    if ChResult <> res_Ok then Fail('ChConnect', ChResult);
    { fill the message }
    with SMess^ do
    begin
      MessType := tpLongM;
      FCB_ACD  := False;
      FCV_DFC  := True;
      FC       := FCM_UserDataReply;
      Data[1]  := $10;
      Data[2]  := $20;
      Data[3]  := $30;
      Data[4]  := $40;
      Data[5]  := $50;
      LSMess := cSizeHeadSndMsg + 5; { 5 is the length of Data }
    end;
    { send it and wait until it is out }
    Deadline := ChMsTick + QWord(TimeoutMs);
    while ChSendReady <> CHS_SendReady do
      if ChMsTick > Deadline then Fail('transmitter busy', res_Timeout);
    ChSend(SMess, LSMess);
    if ChSendResult <> res_Ok then Fail('ChSend', ChSendResult);
    while ChSendReady <> CHS_SendReady do
    begin
      if ChSendResult <> res_Ok then Fail('sending', ChSendResult);
      if ChMsTick > Deadline then Fail('sending', res_Timeout);
    end;
    { wait for the answer }
    Deadline := ChMsTick + QWord(TimeoutMs);
    while not (ChReceiveReady = CHS_ReceiveReady) do
    begin
      if ChResult <> res_Ok then Fail('line lost', ChResult);
      if ChMsTick > Deadline then Fail('no answer', res_Timeout);
    end;
    ChReceive(LRMess);
    if ChReceiveResult <> res_Ok then
      Fail('received a broken frame', ChReceiveResult)
    else
      { decode the answer }
      with RMess^ do
        case MessType of
          tpSACK:
            WriteLn('SACK received');
          tpSNAK:
            WriteLn('SNAK received');
          tpShortM, tpLongM:
            begin
              if MessType = tpShortM then
                Write('Fixed-length message')
              else
                Write('Variable-length message');
              Write(', FC ', FC, ', ACD ', FCB_ACD, ', DFC ', FCV_DFC, ', data:');
              for I := 1 to LRMess - cSizeHeadRecMsg do
                Write(' ', IntToHex(Data[I], 2));
              WriteLn;
            end;
        end;
    { done }
    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
end.
