{ icsread - the ChnICS manual's example (section 7), corrected: send one
  ReadData request (RD, block 0, numbers 0 10 15 and a text) and print the
  answer.

    icsread [-t ms] 'NAM=ICS LSB=500 NOD=1 DNO=2 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E'

  The parameter string comes from the command line (all remaining
  arguments, joined with blanks). Every wait has a deadline (-t, default
  2000 ms) and every error is printed with ChResultStr. Exit code: 0 good
  answer, 1 usage, 2 channel error, 3 no answer in time, 4 broken or
  unexpected answer.

  Corrections to the manual's text (docs/PROTOCOLS.md section 7): the constant is not
  called ParamStr (that hides System.ParamStr), "while not ChReceiveReady =
  CHS_ReceiveReady" became a bounded wait, the typographic quotes around
  the text became '"' (a delimiter must be one identical byte on both
  ends), and errors say what went wrong instead of 'Chyba'.

  Physical layers are found through the registry, so a layer is available
  when its unit is in the uses clause below (ChnLoop and ChnCom). }
program icsread;

{$MODE OBJFPC}{$H+}

uses
  SysUtils,
  uString,
  ChnTypes,
  ChnVirt,
  ChnLoop,
  ChnCom, ChnTcp,
  ChnICS;

const
  DefaultParams = 'NAM=ICS LSB=500 NOD=1 DNO=2 NAM=COM COM=1 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
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
  WriteLn(StdErr, 'icsread: ', What, ': ', Chn^.ChResultStr(R));
  if Chn^.ChParamError <> '' then
    WriteLn(StdErr, '  offending parameter: ', Chn^.ChParamError);
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
  Halt(Code);
end;

function Expired(Deadline: QWord): Boolean;
begin
  Result := ChMsTick > Deadline;
  if not Result then
    Sleep(1);     { the layer below may not wait by itself (NAM=LOOP) }
end;

var
  Deadline: QWord;
  N: LongInt;

begin
  Timeout := 2000;
  ArgI := 1;
  if (ParamCount >= 2) and (ParamStr(1) = '-t') then
  begin
    N := 0;
    if not StrToNum(ParamStr(2), 1, 600000, N) then
    begin
      WriteLn(StdErr, 'icsread: -t wants milliseconds, 1..600000');
      Halt(1);
    end;
    Timeout := N;
    ArgI := 3;
  end;
  Params := '';
  for I := ArgI to ParamCount do
    Params := Trim(Params + ' ' + ParamStr(I));
  if Params = '' then
  begin
    WriteLn('usage: icsread [-t ms] ''', DefaultParams, '''');
    Halt(1);
  end;

  New(SMess);
  New(RMess);
  FillChar(SMess^, SizeOf(SMess^), 0);
  Chn := ChnCollection^.ChNewInit(ChnICS.cName);
  with Chn^ do
  begin
    ChSetParam(Params);
    if ChResult <> res_Ok then
      Fail('parameters', ChResult, 2);
    ChOpen;
    Deadline := ChMsTick + QWord(Timeout);
    while ChReady <> CHS_Open do
    begin
      if ChResult <> res_Ok then
        Fail('open', ChResult, 2);
      if Expired(Deadline) then
        Fail('open', res_Timeout, 3);
    end;
    ChReceiveBuffer(RMess, SizeOf(RMess^));
    ChConnect;
    if ChResult <> res_Ok then
      Fail('connect', ChResult, 2);

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
        Fail('transmitter busy', res_Timeout, 3);
    ChSend(SMess, LSMess);
    if ChSendResult <> res_Ok then
      Fail('send', ChSendResult, 2);
    while ChSendReady <> CHS_SendReady do
    begin
      if ChSendResult <> res_Ok then
        Fail('send', ChSendResult, 2);
      if Expired(Deadline) then
        Fail('send', res_Timeout, 3);
    end;

    { wait for the answer }
    Deadline := ChMsTick + QWord(Timeout);
    while ChReceiveReady <> CHS_ReceiveReady do
    begin
      if not (ChReceiveResult in [res_Ok, res_NoMessage]) then
        Fail('receive', ChReceiveResult, 2);
      if Expired(Deadline) then
        Fail('no answer within ' + IntToStr(Timeout) + ' ms', res_Timeout, 3);
    end;
    ChReceive(LRMess);
    if ChReceiveResult <> res_Ok then
      Fail('broken answer', ChReceiveResult, 4);

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
        ExitCode := 4;
      end;
    end;

    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Dispose(SMess);
  Dispose(RMess);
end.
