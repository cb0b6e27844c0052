{ ft12slave - an unbalanced FT 1.2 slave (secondary station) that answers
  the link services of IEC 60870-5-101 / -2:
    reset of remote link (FC 0)      -> ACK (FC 0), FCB expected next: 1
    reset of user process (FC 1)     -> ACK
    user data, confirm (FC 3)        -> single character ACK ($E5)
    user data, no reply (FC 4)       -> nothing
    request status of link (FC 9)    -> status of link (FC 11)
    test function for link (FC 2)    -> ACK (balanced mode, MS=OFF PRI=OFF);
                                        unbalanced: single character ACK ($E5)
    request class 1 data (FC 10)     -> "data not available" (FC 9)
    request class 2 data (FC 11)     -> user data (FC 8): a measured value,
                                        scaled (M_ME_NB_1, IOA 110, common
                                        address 1, COT periodic) that
                                        counts up with every request
  A repeated request (FCV = 1 and the same FCB as the last one) gets the
  last answer again, as the standard wants; the library leaves this to the
  application. Broken frames are printed with ChResultStr and not answered.

  Usage:  ft12slave [--seconds=S] 'parameter string' [SECONDS]   (default 60 s)
  e.g.    ft12slave 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E'
  Without arguments it prints its usage and opens nothing. A string
  without GAP= gets the tools' default (ChnFT12Gap): one corrupted length
  byte then costs one request, not the ~240 bytes after it. ChnLayers
  links every layer; the command line is unit ChnCli's (docs/TOOLS.md). }
program ft12slave;

{$MODE OBJFPC}{$H-}

uses
  SysUtils,
  ChnTypes,
  ChnVirt, ChnWait,
  uString,
  ChnLayers,
  ChnFT12Codec,
  ChnFT12Gap,
  ChnCli,
  ChnFT1_2,
  ChnIec101Asdu;

const
  DefaultParams: tParamStr =
    'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 ' +
    'NAM=COM COM=1 BD=9600 BIT=8 STOP=1 PAR=E';

var
  Cli: tCli;
  Chn: pChnVirt;
  Req: tRecRecord;
  Ans: tSendRecord;
  LReq, LAns: Word;
  HaveAns: Boolean;
  NextFcb: Boolean;       { FCB the next new request must carry }
  Counter: SmallInt;
  Obj: tIecObject;
  AsduLen: Word;
  AsduErr: ShortString;
  Params: tParamStr;
  Seconds: LongInt;
  EndTime: QWord;
  SNode, DNode: tNode;

procedure Fail(const What: string; R: tChResult);
begin
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'ft12slave: ', What, ': ', Chn^.ChErrorText)
  else
    WriteLn(StdErr, 'ft12slave: ', What, ': ', Chn^.ChResultStr(R));
  Dispose(Chn, Done);
  Halt(1);
end;

procedure Answer(T: tMessType; FC: Byte; DataLen: Word);
begin
  FillChar(Ans, cSizeHeadSlSndMsg, 0);
  Ans.MessType := T;
  Ans.FC := FC;
  LAns := cSizeHeadSlSndMsg + DataLen;
  HaveAns := True;
end;

begin
  CliInit(Cli, 'ft12slave', '[OPTION]... PARAMETER-STRING [SECONDS]',
    'An unbalanced FT 1.2 slave (secondary station) answering the link services of ' +
    'IEC 60870-5-101: reset, status of link, user data, class 1 and 2 data (a ' +
    'measured value that counts up), for SECONDS (default 60). A string without ' +
    'GAP= gets GAP= for ' + IntToStr(FT12DefaultGapMs) + ' ms at its BD=.');
  CliOption(Cli, 'seconds', 's', 'S', 'run for S seconds (default 60; also the second argument)');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  ft12slave ''NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E''' +
    LineEnding);
  CliExit(Cli, 0, 'the time is over');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliParse(Cli);
  if (CliArgCount(Cli) < 1) or (CliArgCount(Cli) > 2) then
    CliUsageError(Cli, 'PARAMETER-STRING [SECONDS] wanted', CliRest(Cli, 0));
  Seconds := CliNum(Cli, 'seconds', 1, 86400 * 366, 60);
  if (CliArgCount(Cli) = 2) and not StrToNum(Cli.Args[1], 1, 86400 * 366, Seconds) then
    CliUsageError(Cli, 'SECONDS wants 1..31622400', Cli.Args[1]);
  Params := Cli.Args[0];
  CliCheckParams(Cli, Params, ChnFT1_2.cName);
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam(Params);
  if Chn^.ChResult <> res_Ok then Fail('ChSetParam', Chn^.ChResult);
  FT12SetDefaultGap(Chn, Params);
  Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then Fail('ChOpen', Chn^.ChResult);
  Chn^.ChReceiveBuffer(@Req, SizeOf(Req));
  Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then Fail('ChConnect', Chn^.ChResult);
  HaveAns := False;
  NextFcb := True;
  Counter := 0;
  LAns := 0;
  EndTime := ChMsTick + QWord(Seconds) * 1000;
  WriteLn('ft12slave: ', Chn^.ChGetParam(''));
  while ChMsTick < EndTime do
  begin
    if Chn^.ChResult <> res_Ok then Fail('line', Chn^.ChResult);
    if Chn^.ChReceiveReady <> CHS_ReceiveReady then
    begin
      ChnWaitAny(20);   { until the line has something, at most 20 ms }
      Continue;
    end;
    Chn^.ChReceive(LReq);
    if Chn^.ChReceiveResult <> res_Ok then
    begin
      WriteLn('broken frame: ', Chn^.ChResultStr(Chn^.ChReceiveResult));
      Continue;
    end;
    Chn^.ChGetNode(SNode, DNode);
    Write('FC ', Req.FC, ' to ', DNode);
    if Req.FCV_DFC and HaveAns and (Req.FCB_ACD <> NextFcb) then
      WriteLn(' (repeated: last answer again)')
    else
    begin
      WriteLn;
      if Req.FCV_DFC then
        NextFcb := not Req.FCB_ACD;
      HaveAns := False;
      case Req.FC of
        FCM_1stSetTransmit:
          begin
            NextFcb := True;
            Answer(tpShortM, FCS_Ack, 0);
          end;
        FCM_1stSetUserFun: Answer(tpShortM, FCS_Ack, 0);
        FCM_UserDataReply: Answer(tpSACK, 0, 0);
        FCM_UserDataNoRep: ;
        FCM_CheckLink:
          if not pChnFT1_2(Chn)^.ChFT12Config.Balanced then
            Answer(tpSACK, 0, 0)      { unbalanced: E5, whatever LEN= is }
          else
            Answer(tpShortM, FCS_Ack, 0);
        FCM_ReqLinkState: Answer(tpShortM, FCS_LinkSAccesReq, 0);
        FCM_ReqUserData1: Answer(tpShortM, FCS_DataNotAcces, 0);
        FCM_ReqUserData2:
          begin
            Inc(Counter);
            Obj := IecObject(110);
            Obj.Int := Counter;
            IecEncodeOne(IecDefaultParams, M_ME_NB_1, Cot_Periodic, 1, Obj, Ans.Data, AsduLen, AsduErr);
            Answer(tpLongM, FCS_UserData, AsduLen);
          end;
      else
        Answer(tpShortM, FCS_NackBusy, 0);
      end;
    end;
    { no answer to a broadcast }
    if HaveAns and (DNode <> FT12Broadcast(pChnFT1_2(Chn)^.ChFT12Config.AddrLen)) then
    begin
      if Chn^.ChSendReady = CHS_SendReady then
        Chn^.ChSend(@Ans, LAns);
      if Chn^.ChSendResult <> res_Ok then
        WriteLn('send: ', Chn^.ChResultStr(Chn^.ChSendResult));
    end;
  end;
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
