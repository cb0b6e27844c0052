{ icsread - the ChnICS manual's example (section 7), corrected: send one
  ReadData request (RD, block 0, numbers 0 10 15 and a text) and print the
  answer.

    icsread [-t MS] 'NAM=ICS LSB=500 NOD=1 DNO=2 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E'

  The parameter string comes from the command line (all remaining
  arguments, joined with blanks). Every wait has a deadline (-t or
  --timeout, default 2000 ms) and every error is printed with
  ChResultStr. The command line is unit ChnCli's (docs/TOOLS.md). Exit
  code: 0 good answer, 1 channel error (open, line lost), 2 command-line
  error, 3 broken or unexpected answer, 4 no answer in time.

  Corrections to the manual's text (docs/PROTOCOLS.md section 7): the constant is not
  called ParamStr (that hides System.ParamStr), "while not ChReceiveReady =
  CHS_ReceiveReady" became a bounded wait, the typographic quotes around
  the text became '"' (a delimiter must be one identical byte on both
  ends), and errors say what went wrong instead of 'Chyba'.

  Physical layers are found through the registry, so a layer is available
  when its unit is in the uses clause below (ChnLayers: all of them). }
program icsread;

{$MODE OBJFPC}{$H+}

uses
  SysUtils,
  uString,
  ChnTypes,
  ChnVirt, ChnWait,
  ChnLayers,
  ChnICS,
  ChnCli;

const
  DefaultParams = 'NAM=ICS LSB=500 NOD=1 DNO=2 NAM=COM COM=1 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Cli    : tCli;
  Chn    : pChnVirt;
  SMess  : pSendRecord;
  RMess  : pRecRecord;
  LSMess : Word;
  LRMess : Word;
  Params : string;
  Timeout: LongInt;
  ArgI   : Integer;
  I      : Integer;
  SNode, DNode: tNode;

{ Print the error, tear the channel down and stop. }
procedure Fail(const What: string; R: tChResult; Code: Integer);
begin
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'icsread: ', What, ': ', Chn^.ChErrorText)  { token, OS reason }
  else
    WriteLn(StdErr, 'icsread: ', What, ': ', Chn^.ChResultStr(R));
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
  Halt(Code);
end;

function Expired(Deadline: QWord): Boolean;
begin
  Result := ChMsTick > Deadline;
  if not Result then
    ChnWaitAny(10);   { the line, NAM=LOOP's too; at most 10 ms }
end;

var
  Deadline: QWord;
  N: LongInt;

begin
  CliInit(Cli, 'icsread', '[OPTION]... PARAMETER-STRING...',
    'The ChnICS manual''s example (section 7), corrected: send one ReadData request ' +
    '(RD, block 0, numbers 0 10 15 and a text) to an ICSlink station and print the ' +
    'answer. All arguments after the options form the parameter string.');
  CliOption(Cli, 'timeout', 't', 'MS', 'wait at most MS ms for each step (default 2000)');
  CliEpilog(Cli, 'Example:' + LineEnding + '  icsread -t 1000 ''' + DefaultParams + '''' + LineEnding);
  CliExit(Cli, 0, 'a good answer (DB with 3 numbers)');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliExit(Cli, 3, 'a broken or unexpected answer');
  CliExit(Cli, 4, 'no answer in time');
  CliParse(Cli);
  Timeout := CliNum(Cli, 'timeout', 1, 600000, 2000);
  Params := CliRest(Cli, 0);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string', '');
  CliCheckParams(Cli, Params, ChnICS.cName);

  New(SMess);
  New(RMess);
  FillChar(SMess^, SizeOf(SMess^), 0);
  Chn := ChnCollection^.ChNewInit(ChnICS.cName);
  with Chn^ do
  begin
    ChSetParam(Params);
    if ChResult <> res_Ok then
      Fail('parameters', ChResult, 1);
    ChOpen;
    Deadline := ChMsTick + QWord(Timeout);
    while ChReady <> CHS_Open do
    begin
      if ChResult <> res_Ok then
        Fail('open', ChResult, 1);
      if Expired(Deadline) then
        Fail('open', res_Timeout, 4);
    end;
    ChReceiveBuffer(RMess, SizeOf(RMess^));
    ChConnect;
    if ChResult <> res_Ok then
      Fail('connect', ChResult, 1);

    with SMess^ do
    begin
      OpCode   := OCM_ReadData;
      BlockNum := 0;
      Text     := '"Pozadavek na cteni dat"';
      Data[0]  := 0;
      Data[1]  := 10;
      Data[2]  := 15;
      LSMess   := 4 + 3 * SizeOf(tData);
    end;

    Deadline := ChMsTick + QWord(Timeout);
    while ChSendReady <> CHS_SendReady do
      if Expired(Deadline) then
        Fail('transmitter busy', res_Timeout, 4);
    ChSend(SMess, LSMess);
    if ChSendResult <> res_Ok then
      Fail('send', ChSendResult, 1);
    while ChSendReady <> CHS_SendReady do
    begin
      if ChSendResult <> res_Ok then
        Fail('send', ChSendResult, 1);
      if Expired(Deadline) then
        Fail('send', res_Timeout, 4);
    end;

    { wait for the answer }
    Deadline := ChMsTick + QWord(Timeout);
    while ChReceiveReady <> CHS_ReceiveReady do
    begin
      if not (ChReceiveResult in [res_Ok, res_NoMessage]) then
        Fail('receive', ChReceiveResult, 1);
      if ChResult <> res_Ok then
        Fail('line lost', ChResult, 1);
      if Expired(Deadline) then
        Fail('no answer within ' + IntToStr(Timeout) + ' ms', res_Timeout, 4);
    end;
    ChReceive(LRMess);
    if ChReceiveResult <> res_Ok then
      Fail('broken answer', ChReceiveResult, 3);

    ChGetNode(SNode, DNode);
    with RMess^ do
    begin
      Write('from ', SNode, ' to ', DNode, ': ', OpCode, ' block ', BlockNum, ' data');
      for I := 0 to (LRMess - 4) div SizeOf(tData) - 1 do
        Write(' ', Data[I]);
      if Text <> '' then
        Write(' text ', Text);
      WriteLn;
      if (OpCode <> OCS_ReadData) or (LRMess <> 4 + 3 * SizeOf(tData)) then
      begin
        WriteLn(StdErr, 'icsread: expected DB with 3 numbers');
        ExitCode := 3;
      end;
    end;

    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
end.
