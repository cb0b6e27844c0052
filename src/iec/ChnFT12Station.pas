{ ChnFT12Station - the secondary (slave) of an unbalanced IEC 60870-5-2
  link (unit ChnFT12Link tells the rules): tFT12Station / FT12StationStep
  answer the unbalanced functions, and a repetition by the primary (an
  FCV = 1 frame with the FCB of the last one accepted) gets the last reply
  again without the frame being executed a second time. }
unit ChnFT12Station;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link;

type
  tFT12Station = record
    Chn        : pChnVirt;
    RMess      : tFT12MaxRecord; {< any frame, L up to 255 }
    Reply      : tFT12MaxRecord; {< last reply to an FCV = 1 frame or a reset (any length) }
    ReplyLen   : Word;
    HasReply   : Boolean;
    LinkReset  : Boolean;      {< a reset of remote link was received }
    LastFcb    : Boolean;      {< FCB of the last accepted FCV = 1 frame (0 after reset) }
    Dfc        : Boolean;      {< DFC sent in every reply (set by the application) }
    SingleAck  : Boolean;      {< ACK as E5 when no class 1 data is waiting }
    OnUserData : tFT12UserDataFunc;
    OnClassData: tFT12ClassDataFunc;       {< class data up to MaxDataLen octets }
    OnLongClassData: tFT12LongClassDataFunc; {< instead: up to the longest frame (L = 255) }
    OnClass1   : tFT12Class1Func;
    Data       : Pointer;
    {- counters }
    Frames     : LongInt;      {< frames taken, good or broken }
    Executed   : LongInt;      {< FC 3/4/10/11 frames handed to the callbacks }
    Repeats    : LongInt;      {< repetitions answered with the last reply }
    Refused    : LongInt;      {< FCV = 1 frames before a reset (NACK); FC 3, 10, 11
                                 without FCV (FC 15) }
    OtherAddr  : LongInt;      {< frames for another link address (the channel
                                 drops them: other stations' traffic on a bus) }
    OtherLast  : Word;         {< the address the last of them carried }
    RxForeign  : LongWord;     {< the channel's count when last looked at }
  end;

procedure FT12StationInit(var S: tFT12Station; Chn: pChnVirt);
{ Take at most one frame and act on it; False when none was waiting, or
  when S.Chn is not a tChnFT1_2 (then nothing is read). }
function FT12StationStep(var S: tFT12Station): Boolean;

implementation

uses
  ChnFT12Codec;

procedure FT12StationInit(var S: tFT12Station; Chn: pChnVirt);
begin
  FillChar(S, SizeOf(S), 0);
  S.Chn := Chn;
  Chn^.ChReceiveBuffer(@S.RMess, SizeOf(S.RMess));
end;

{ Fill S.Reply as a fixed frame with function FC (ACK, E5 if asked). }
procedure FixedReply(var S: tFT12Station; FC: Byte);
begin
  FillChar(S.Reply, SizeOf(S.Reply), 0);
  S.Reply.FCB_ACD := Assigned(S.OnClass1) and S.OnClass1(S.Data);
  S.Reply.FCV_DFC := S.Dfc;
  S.Reply.FC := FC;
  if S.SingleAck and (FC = FCS_Ack) and not S.Reply.FCB_ACD then
  begin
    S.Reply.MessType := tpSACK;
    S.ReplyLen := 1;
  end
  else
  begin
    S.Reply.MessType := tpShortM;
    S.ReplyLen := FT12FixedLen(S.Chn);
  end;
end;

procedure ClassReply(var S: tFT12Station; ClassNo: Byte);
var
  Len: Word;
  Got: Boolean;
begin
  FillChar(S.Reply, SizeOf(S.Reply), 0);
  Len := 0;
  if Assigned(S.OnLongClassData) then
    Got := S.OnLongClassData(S.Data, ClassNo, S.Reply, Len) and (Len <= FT12MaxData(S.Chn))
  else
    { the manual's record: MaxDataLen octets }
    Got := Assigned(S.OnClassData) and S.OnClassData(S.Data, ClassNo, tSendRecord(Pointer(@S.Reply)^), Len)
      and (Len <= MaxDataLen);
  if Got then
  begin
    S.Reply.MessType := tpLongM;
    S.Reply.FCB_ACD := Assigned(S.OnClass1) and S.OnClass1(S.Data);
    S.Reply.FCV_DFC := S.Dfc;
    S.Reply.FC := FCS_UserData;
    S.ReplyLen := cSizeHeadSndMsg + Len;
  end
  else
    FixedReply(S, FCS_DataNotAcces);
end;

function FT12StationStep(var S: tFT12Station): Boolean;
var
  Ready: Boolean;
  Len: Word;
  Broadcast, Fcv: Boolean;
  F: pChnFT1_2;
begin
  Result := False;
  if not IsFT12Channel(S.Chn) then
    Exit;                       { only a tChnFT1_2 has the fields used below }
  Ready := S.Chn^.ChReceiveReady = CHS_ReceiveReady;
  FT12NoteForeign(S.Chn, S.RxForeign, S.OtherAddr, S.OtherLast);
  if not Ready then
    Exit;
  Result := True;
  Inc(S.Frames);
  Len := 0;
  S.Chn^.ChReceive(Len);
  { a garbled frame is not answered (IEC 60870-5-2): the primary repeats }
  if (S.Chn^.ChReceiveResult <> res_Ok) or not (S.RMess.MessType in [tpShortM, tpLongM]) then
    Exit;
  F := pChnFT1_2(S.Chn);
  Broadcast := (F^.CH_AdrLen > 0) and (S.Chn^.CH_RDNode = FT12Broadcast(F^.CH_AdrLen));
  Fcv := S.RMess.FCV_DFC;
  if Broadcast or (S.RMess.FC = FCM_UserDataNoRep) then
  begin
    { SEND/NO REPLY: never answered; a broadcast can be nothing else }
    if S.RMess.FC = FCM_UserDataNoRep then
    begin
      Inc(S.Executed);
      if Assigned(S.OnUserData) then
        S.OnUserData(S.Data, @S.RMess.Data[1], Len - cSizeHeadRecMsg, False);
    end;
    Exit;
  end;
  if not Fcv and FT12FcvOf(S.RMess.FC) then
  begin
    { user data and class requests are FCV = 1 services (IEC 60870-5-2):
      without it the frame-count check is off, and a repetition would be
      taken twice - no such service, the data are not taken }
    Inc(S.Refused);
    FixedReply(S, FCS_NotImplemented);
    FT12SendNow(S.Chn, S.Reply, S.ReplyLen);
    Exit;
  end;
  if Fcv then
  begin
    if not S.LinkReset then
    begin
      { the FCB memory is not set up: refuse until the primary resets }
      Inc(S.Refused);
      FixedReply(S, FCS_NackBusy);
      FT12SendNow(S.Chn, S.Reply, S.ReplyLen);
      S.HasReply := False;
      Exit;
    end;
    if S.HasReply and (S.RMess.FCB_ACD = S.LastFcb) then
    begin
      { same FCB as the last accepted frame: the primary lost our reply }
      Inc(S.Repeats);
      FT12SendNow(S.Chn, S.Reply, S.ReplyLen);
      Exit;
    end;
    S.LastFcb := S.RMess.FCB_ACD;
  end;
  case S.RMess.FC of
    FCM_1stSetTransmit:
      begin
        S.LinkReset := True;
        S.LastFcb := False;     { the reset's FCB: the next frame needs FCB = 1 }
        FixedReply(S, FCS_Ack);
      end;
    FCM_1stSetUserFun:
      FixedReply(S, FCS_Ack);
    FCM_UserDataReply:
      begin
        Inc(S.Executed);
        FixedReply(S, FT12UserDataAnswer(S.OnUserData, S.Data, S.RMess, Len));
      end;
    FCM_ReqReplyAcces, FCM_ReqLinkState:
      FixedReply(S, FCS_LinkSAccesReq);
    FCM_ReqUserData1, FCM_ReqUserData2:
      begin
        Inc(S.Executed);
        ClassReply(S, S.RMess.FC - FCM_ReqUserData1 + 1);
      end;
  else
    FixedReply(S, FCS_NotImplemented);   { FC 2 is balanced only }
  end;
  { the reply to a reset or an FCV = 1 frame is what a repetition gets }
  S.HasReply := Fcv or (S.RMess.FC = FCM_1stSetTransmit);
  FT12SendNow(S.Chn, S.Reply, S.ReplyLen);
end;

end.
