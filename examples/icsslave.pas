{ icsslave - an ICSlink slave with a table of 1024 registers, the partner
  of icsread:

    RD n1 n2 ...          -> DB with the values of registers n1, n2, ...
    RL                    -> LB with the register count and a text
    WD first v1 v2 ...    -> OK (registers first, first+1, ... := v1, v2, ...)

  (Which registers the numbers of RD and WD name is this example's own
  convention; the manual defines only the frame.) Register i starts as
  i * 10. A request for a register outside 0..1023 is answered with its
  op code and the text '!bad register!' and no data. Broken frames are
  reported and not answered (ICSlink has no negative acknowledgement);
  frames for another station are ignored.

    icsslave [-t SECONDS] [-n REQUESTS] 'NAM=ICS MAS=SLAVE NOD=2 DNO=1 NAM=COM DEV=/dev/ttyUSB1'

  Runs until -n requests were answered or -t seconds passed (default 60),
  never endlessly. The command line is unit ChnCli's; --help lists the
  exit codes (docs/TOOLS.md). }
program icsslave;

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
  RegCount = 1024;
  BadRegister = '!bad register!';

var
  Cli     : tCli;
  Chn     : pChnVirt;
  Req, Ans: tRecRecord;
  Regs    : array[0..RegCount - 1] of tData;
  Params  : string;
  Seconds, MaxRequests, Answered: LongInt;

procedure ParseArgs;
begin
  CliInit(Cli, 'icsslave', '[OPTION]... PARAMETER-STRING...',
    'An ICSlink slave with a table of 1024 registers (register i starts as i * 10), ' +
    'the partner of icsread: RD -> DB with the values, RL -> LB with the register ' +
    'count, WD first v1 v2 ... -> OK. All arguments after the options form the ' +
    'parameter string.');
  CliOption(Cli, 'timeout', 't', 'SECONDS', 'run at most SECONDS (default 60)');
  CliOption(Cli, 'requests', 'n', 'N', 'end after answering N requests');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  icsslave -t 30 ''NAM=ICS MAS=SLAVE NOD=2 DNO=1 NAM=COM DEV=/dev/ttyUSB1''' + LineEnding);
  CliExit(Cli, 0, 'the time is over or N requests were answered');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliParse(Cli);
  Seconds := CliNum(Cli, 'timeout', 1, 86400, 60);
  MaxRequests := CliNum(Cli, 'requests', 1, 86400, 0);   { 0: no limit but the time }
  Params := CliRest(Cli, 0);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string', '');
  CliCheckParams(Cli, Params, ChnICS.cName);
end;

procedure Stop(const What: string; R: tChResult);
begin
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'icsslave: ', What, ': ', Chn^.ChErrorText)  { token, OS reason }
  else
    WriteLn(StdErr, 'icsslave: ', What, ': ', Chn^.ChResultStr(R));
  Dispose(Chn, Done);
  Halt(1);
end;

{ Fill Ans for the request in Req (Len bytes); False: no answer. }
function Answer(Len: Word; var ALen: Word): Boolean;
var
  Count, I, Reg: Integer;
begin
  Result := True;
  Count := (Len - 4) div SizeOf(tData);
  FillChar(Ans, SizeOf(Ans), 0);
  Ans.BlockNum := Req.BlockNum;
  ALen := 4;
  if Req.OpCode = OCM_ReadData then
  begin
    Ans.OpCode := OCS_ReadData;
    for I := 0 to Count - 1 do
      if (Req.Data[I] < 0) or (Req.Data[I] >= RegCount) then
      begin
        Ans.Text := BadRegister;
        Exit;
      end;
    for I := 0 to Count - 1 do
      Ans.Data[I] := Regs[Req.Data[I]];
    ALen := 4 + Count * SizeOf(tData);
  end
  else if Req.OpCode = OCM_ReadParams then
  begin
    Ans.OpCode := OCS_ReadParams;
    Ans.Data[0] := RegCount;
    Ans.Text := '"icsslave, ' + IntToStr(RegCount) + ' registers"';
    ALen := 4 + SizeOf(tData);
  end
  else if Req.OpCode = OCM_WriteData then
  begin
    Ans.OpCode := OCS_WriteData;
    if Count = 0 then
      Exit;
    Reg := Req.Data[0];
    if (Reg < 0) or (Reg + Count - 1 > RegCount) then
    begin
      Ans.Text := BadRegister;
      Exit;
    end;
    for I := 1 to Count - 1 do
      Regs[Reg + I - 1] := Req.Data[I];
  end
  else
  begin
    WriteLn('unknown op code ', Req.OpCode, ', not answered');
    Result := False;
  end;
end;

var
  I: Integer;
  Len, ALen: Word;
  SNode, DNode: tNode;
  Deadline: QWord;

begin
  ParseArgs;
  for I := 0 to RegCount - 1 do
    Regs[I] := I * 10;
  Chn := ChnCollection^.ChNewInit(ChnICS.cName);
  Chn^.ChSetParam(Params);
  if Chn^.ChResult <> res_Ok then
    Stop('parameters', Chn^.ChResult);
  Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then
    Stop('open', Chn^.ChResult);
  Chn^.ChReceiveBuffer(@Req, SizeOf(Req));
  Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then
    Stop('connect', Chn^.ChResult);
  WriteLn('icsslave: station ', Chn^.CH_Node, ' listening for ', Seconds, ' s');

  Answered := 0;
  Deadline := ChMsTick + QWord(Seconds) * 1000;
  while (ChMsTick < Deadline) and ((MaxRequests = 0) or (Answered < MaxRequests)) do
  begin
    if Chn^.ChReceiveReady <> CHS_ReceiveReady then
    begin
      if Chn^.ChResult <> res_Ok then
        Stop('line', Chn^.ChResult);         { device lost ... }
      ChnWaitAny(20);                         { until the line has something }
      Continue;
    end;
    Chn^.ChReceive(Len);
    if Chn^.ChReceiveResult <> res_Ok then
    begin
      WriteLn('broken frame: ', Chn^.ChResultStr(Chn^.ChReceiveResult));
      Continue;
    end;
    Chn^.ChGetNode(SNode, DNode);
    if DNode <> Chn^.CH_Node then
      Continue;                               { for another station }
    WriteLn('from ', SNode, ': ', Req.OpCode, ' block ', Req.BlockNum,
      ' with ', (Len - 4) div SizeOf(tData), ' numbers');
    if not Answer(Len, ALen) then
      Continue;
    Chn^.ChDestNode(SNode);
    while Chn^.ChSendReady <> CHS_SendReady do
      if ChMsTick > Deadline then
        Stop('transmitter busy', res_Timeout)
      else
        ChnWaitAny(10);
    Chn^.ChSend(@Ans, ALen);
    if Chn^.ChSendResult <> res_Ok then
      Stop('send', Chn^.ChSendResult);
    Inc(Answered);
  end;
  WriteLn('icsslave: ', Answered, ' requests answered');
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
