{ ChnFT12Balanced - a station of a balanced IEC 60870-5-2 link (MS=OFF;
  unit ChnFT12Link tells the rules): primary and secondary at once on one
  channel - link set-up (FC 9, FC 0), user data from a queue (FC 3/4),
  test function for link (FC 2) when quiet, repetitions with the same
  FCB; answers to the peer's requests at once, also while a request of
  its own is out, with the cached answer for a repeated FCB. On a lost
  frame station B (DIR=0) repeats half a timeout later than station A, so
  the two do not meet again (docs/ChnFT1_2.md, balanced mode). }
unit ChnFT12Balanced;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link;


const
  FT12BalQueueLen = 8;        {< user data frames waiting to be sent }
  FT12BalTestMs   = 5000;     {< default: test function after 5 s of quiet }

type
  { What the primary half of a balanced link is doing. }
  tFT12BalState = (
    bsIdle,           {< link not established: request status of link next }
    bsRequestStatus,  {< FC 9 sent, waiting for status of link (FC 11) }
    bsResetting,      {< FC 0 sent, waiting for ACK }
    bsAvailable);     {< reset acknowledged: user data and test functions }

  tFT12BalUserData = record
    Len    : Word;
    Confirm: Boolean;         {< FC 3 (SEND/CONFIRM) or FC 4 (SEND/NO REPLY) }
    Data   : array[1..FT12MaxUserData] of Byte;   {< up to the longest frame }
  end;

  { One balanced link (IEC 60870-5-2 balanced transmission): both
    procedures of this station on one tChnFT1_2 with MS=OFF. Init with
    FT12BalancedInit, then call FT12BalancedStep often; it never blocks
    longer than one bounded send. The record must not move after Init
    (the channel writes into RMess). }
  tFT12Balanced = record
    Chn        : pChnVirt;
    RMess      : tFT12MaxRecord; {< any frame, L up to 255 }
    {- settings (FT12BalancedInit gives the defaults) }
    TimeoutMs  : LongInt;     {< wait for an answer (FT12LinkTimeoutMs) }
    Retries    : SmallInt;    {< repetitions before the link counts as lost }
    TestMs     : LongInt;     {< test function after this long without a
                                request of ours; 0 = never }
    Dfc        : Boolean;     {< DFC sent in every answer (set by the application) }
    { primary }
    State      : tFT12BalState;
    Pending    : Boolean;     {< a request is out and its answer awaited }
    Out        : tFT12MaxRecord; {< that request, for repetitions }
    OutLen     : Word;
    Fcb        : Boolean;     {< FCB of the next new FCV = 1 transmission }
    Tries      : SmallInt;    {< transmissions of Out so far }
    SentAt     : QWord;       {< when Out went out the last time }
    LastRequest: QWord;       {< when a request of ours last went out }
    HoldUntil  : QWord;       {< no new request before (NACK, DFC) }
    PeerDfc    : Boolean;     {< DFC of the peer's last answer }
    Queue      : array[0..FT12BalQueueLen - 1] of tFT12BalUserData;
    QHead, QCount: SmallInt;
    {- secondary }
    HasReply   : Boolean;     {< an FCV = 1 frame was accepted since the reset }
    LastFcb    : Boolean;     {< its FCB }
    Reply      : tSendRecord; {< the answer it got, sent again on a repetition }
    ReplyLen   : Word;
    PeerReset  : Boolean;     {< the peer reset this station's secondary }
    OnUserData : tFT12UserDataFunc;   {< FC 3 (Confirm) / FC 4 user data }
    Data       : Pointer;
    {- counters }
    Frames     : LongInt;     {< frames taken, good or broken }
    Executed   : LongInt;     {< FC 3/4 frames handed to OnUserData }
    Repeats    : LongInt;     {< repetitions answered from memory }
    Retransmits: LongInt;     {< our requests sent again after a timeout }
    Confirmed  : LongInt;     {< our user data confirmed (or sent, FC 4) }
    Tests      : LongInt;     {< test functions of ours confirmed }
    LinkLost   : LongInt;     {< times the link had to be established anew }
    Unexpected : LongInt;     {< answers with no request of ours outstanding }
    Ignored    : LongInt;     {< answers that do not fit, or from another address }
    BadDir     : LongInt;     {< frames with the DIR of this station's side }
    Broken     : LongInt;     {< other broken frames (checksum, length, ...) }
    {- answers that may still come for earlier transmissions (see "Late
      answers" in the unit header) }
    Suspect    : Boolean;     {< other than status of link: fence first }
    OwedStatus : LongInt;     {< status of link answers (FC 11) }
    StatusSkip : LongInt;     {< of those, to skip for the request now out }
    StatusAt   : QWord;       {< when a status request last went out }
    Fencing    : Boolean;     {< Out is a fence: FC 9 to flush late answers }
    Fences     : LongInt;     {< fences sent }
    Stale      : LongInt;     {< late answers recognised and ignored }
    OtherAddr  : LongInt;     {< frames from or for another link address
                                (answers here, requests dropped by the channel) }
    OtherLast  : Word;        {< the address the last of them carried }
    RxForeign  : LongWord;    {< the channel's count when last looked at }
  end;

{ Bind B to a balanced tChnFT1_2 and set the defaults; the channel's
  receive buffer becomes B.RMess. Results: res_Ok, res_WrongLayer (no
  tChnFT1_2), res_BadMessage (MS=ON). }
function FT12BalancedInit(var B: tFT12Balanced; Chn: pChnVirt): tChResult;
{ Queue Len octets of user data for SEND/CONFIRM (Confirm) or SEND/NO
  REPLY; sent in order once the link is available. res_Busy when the queue
  is full, res_TooLong above what the longest frame carries (L = 255:
  FT12MaxData, 254 octets less the link address), res_BadLen for 0. }
function FT12BalancedSend(var B: tFT12Balanced; Buf: PByte; Len: Word;
  Confirm: Boolean): tChResult;
{ Take every frame already received (at most FT12MaxFramesPerStep) and act
  on each, then run the primary's timers. True when a frame was taken. }
function FT12BalancedStep(var B: tFT12Balanced): Boolean;
{ Nothing queued and no request outstanding. }
function FT12BalancedQuiet(const B: tFT12Balanced): Boolean;
function FT12BalStateName(S: tFT12BalState): ShortString;

implementation

uses
  SysUtils, ChnFT12Codec, ChnWait;

function FT12BalStateName(S: tFT12BalState): ShortString;
begin
  case S of
    bsIdle:          Result := 'IDLE';
    bsRequestStatus: Result := 'REQUEST STATUS';
    bsResetting:     Result := 'RESETTING';
  else
    Result := 'AVAILABLE';
  end;
end;

function FT12BalancedInit(var B: tFT12Balanced; Chn: pChnVirt): tChResult;
begin
  FillChar(B, SizeOf(B), 0);
  if not IsFT12Channel(Chn) then
    Exit(res_WrongLayer);
  if not pChnFT1_2(Chn)^.ChFT12Config.Balanced then
    Exit(res_BadMessage);
  B.Chn := Chn;
  B.TimeoutMs := FT12LinkTimeoutMs;
  B.Retries := FT12LinkRetries;
  B.TestMs := FT12BalTestMs;
  B.State := bsIdle;
  Chn^.ChReceiveBuffer(@B.RMess, SizeOf(B.RMess));
  Result := res_Ok;
end;

function FT12BalancedSend(var B: tFT12Balanced; Buf: PByte; Len: Word;
  Confirm: Boolean): tChResult;
var
  Slot: Integer;
begin
  if Len = 0 then
    Exit(res_BadLen);
  if Len > FT12MaxData(B.Chn) then
    Exit(res_TooLong);
  if B.QCount >= FT12BalQueueLen then
    Exit(res_Busy);
  Slot := (B.QHead + B.QCount) mod FT12BalQueueLen;
  B.Queue[Slot].Len := Len;
  B.Queue[Slot].Confirm := Confirm;
  Move(Buf^, B.Queue[Slot].Data[1], Len);
  Inc(B.QCount);
  Result := res_Ok;
end;

function FT12BalancedQuiet(const B: tFT12Balanced): Boolean;
begin
  Result := (B.QCount = 0) and not B.Pending;
end;

{ Send Out (again), counting the status answer it may bring. }
procedure BalTransmit(var B: tFT12Balanced);
begin
  if B.Out.FC = FCM_ReqLinkState then
  begin
    Inc(B.OwedStatus);
    B.StatusAt := ChMsTick;
  end;
  pChnFT1_2(B.Chn)^.ChSendAsWhenFree(True, @B.Out, B.OutLen, FT12LinkTimeoutMs);
end;

{ Start a request: FCV from the function, FCB alternating for FCV = 1. }
procedure StartRequest(var B: tFT12Balanced; T: tMessType; FC: Byte;
  Buf: PByte; Len: Word);
var
  Fcv: Boolean;
begin
  Fcv := FT12FcvOf(FC);
  FillChar(B.Out, SizeOf(B.Out), 0);
  B.Out.MessType := T;
  B.Out.FC := FC;
  B.Out.FCV_DFC := Fcv;
  B.Out.FCB_ACD := Fcv and B.Fcb;
  if T = tpShortM then
    B.OutLen := FT12FixedLen(B.Chn)
  else
  begin
    Move(Buf^, B.Out.Data[1], Len);
    B.OutLen := cSizeHeadSndMsg + Len;
  end;
  B.Tries := 1;
  B.SentAt := ChMsTick;
  B.LastRequest := B.SentAt;
  B.Pending := FC <> FCM_UserDataNoRep;
  if FC = FCM_ReqLinkState then
  begin
    { status answers of earlier FC 9 transmissions may still come: the
      first that many to arrive are not this request's }
    if B.SentAt - B.StatusAt > QWord(4 * B.TimeoutMs) then
      B.OwedStatus := 0;
    B.StatusSkip := B.OwedStatus;
  end;
  BalTransmit(B);
end;

procedure LinkLost(var B: tFT12Balanced);
begin
  Inc(B.LinkLost);
  if B.Out.FC <> FCM_ReqLinkState then
    B.Suspect := True;            { its answers may still be on the way }
  B.State := bsIdle;
  B.Pending := False;
  B.Fencing := False;
end;

procedure Dequeue(var B: tFT12Balanced);
begin
  B.QHead := (B.QHead + 1) mod FT12BalQueueLen;
  Dec(B.QCount);
end;

{ The primary's side of the peer's answer (PRM = 0, or E5). }
procedure TakeAnswer(var B: tFT12Balanced);
var
  F: pChnFT1_2;
  Nack, Status: Boolean;
begin
  F := pChnFT1_2(B.Chn);
  if (B.RMess.MessType in [tpShortM, tpLongM]) and (F^.CH_AdrLen > 0) and
     (B.Chn^.CH_RSNode <> B.Chn^.ChGetDestNode) then
  begin
    Inc(B.Ignored);               { another station's }
    Inc(B.OtherAddr);
    B.OtherLast := B.Chn^.CH_RSNode;
    Exit;
  end;
  Status := (B.RMess.MessType in [tpShortM, tpLongM]) and (B.RMess.FC = FCS_LinkSAccesReq);
  if Status and (B.OwedStatus > 0) then
    Dec(B.OwedStatus);
  if not B.Pending then
  begin
    Inc(B.Unexpected);            { nothing of ours is waiting for it }
    Exit;
  end;
  if not FT12ReplyFits(B.Out.FC, B.RMess.MessType, B.RMess.FC) then
  begin
    if Status or (B.Out.FC = FCM_ReqLinkState) then
      Inc(B.Stale)                { late: the answer to an earlier request }
    else
      Inc(B.Ignored);
    Exit;
  end;
  if (B.Out.FC = FCM_ReqLinkState) and (B.StatusSkip > 0) then
  begin
    Dec(B.StatusSkip);            { owed by an earlier FC 9 }
    Inc(B.Stale);
    Exit;
  end;
  { a fresh answer: everything the peer answered before it has arrived }
  if B.Out.FC = FCM_ReqLinkState then
  begin
    B.Suspect := False;
    B.OwedStatus := B.Tries - 1;  { this request's other transmissions }
  end
  else
  begin
    B.OwedStatus := 0;
    if B.Tries > 1 then
      B.Suspect := True;          { the answer to another transmission may follow }
  end;
  B.Pending := False;
  B.PeerDfc := (B.RMess.MessType in [tpShortM, tpLongM]) and B.RMess.FCV_DFC;
  Nack := (B.RMess.MessType in [tpShortM, tpLongM]) and (B.RMess.FC = FCS_NackBusy);
  if B.Out.FCV_DFC then
    B.Fcb := not B.Fcb;           { the service is complete, whatever its outcome }
  { the peer cannot take more now: wait a timeout before the next request }
  if B.PeerDfc or Nack then
    B.HoldUntil := ChMsTick + QWord(B.TimeoutMs);
  case B.Out.FC of
    FCM_ReqLinkState:
      if B.Fencing then
        B.Fencing := False        { late answers flushed: the data can go }
      else
      begin
        { status of link: reset the peer's secondary }
        B.State := bsResetting;
        StartRequest(B, tpShortM, FCM_1stSetTransmit, nil, 0);
      end;
    FCM_1stSetTransmit:
      if Nack then
        LinkLost(B)
      else
      begin
        B.State := bsAvailable;
        B.Fcb := True;            { the first FCV = 1 frame after a reset }
      end;
    FCM_CheckLink:
      Inc(B.Tests);
    FCM_UserDataReply:
      if not Nack then
      begin
        Inc(B.Confirmed);
        Dequeue(B);               { a NACK keeps it queued for later }
      end;
  end;
end;

{ Fill B.Reply as a fixed answer with function FC. }
procedure BalReply(var B: tFT12Balanced; FC: Byte);
begin
  FillChar(B.Reply, SizeOf(B.Reply), 0);
  B.Reply.MessType := tpShortM;
  B.Reply.FCV_DFC := B.Dfc;
  B.Reply.FC := FC;
  B.ReplyLen := FT12FixedLen(B.Chn);
end;

{ The secondary's side of the peer's request (PRM = 1). }
procedure TakeRequest(var B: tFT12Balanced; Len: Word);
var
  Fcv: Boolean;
begin
  Fcv := B.RMess.FCV_DFC;
  if B.RMess.FC = FCM_UserDataNoRep then
  begin
    Inc(B.Executed);
    if Assigned(B.OnUserData) then
      B.OnUserData(B.Data, @B.RMess.Data[1], Len - cSizeHeadRecMsg, False);
    Exit;                         { SEND/NO REPLY: never answered }
  end;
  if Fcv and B.HasReply and (B.RMess.FCB_ACD = B.LastFcb) then
  begin
    { the same FCB as the last accepted frame: the peer lost our answer }
    Inc(B.Repeats);
    pChnFT1_2(B.Chn)^.ChSendAsWhenFree(False, @B.Reply, B.ReplyLen, FT12LinkTimeoutMs);
    Exit;
  end;
  case B.RMess.FC of
    FCM_1stSetTransmit:
      begin
        B.PeerReset := True;
        BalReply(B, FCS_Ack);
      end;
    FCM_1stSetUserFun, FCM_CheckLink:
      BalReply(B, FCS_Ack);
    FCM_UserDataReply:
      begin
        Inc(B.Executed);
        BalReply(B, FT12UserDataAnswer(B.OnUserData, B.Data, B.RMess, Len));
      end;
    FCM_ReqLinkState:
      BalReply(B, FCS_LinkSAccesReq);
  else
    BalReply(B, FCS_NotImplemented);   { FC 8, 10, 11 are unbalanced only }
  end;
  { after a reset no FCV = 1 frame was accepted yet, so the next one is new
    whatever its FCB; after that a repeated FCB is a repetition }
  if B.RMess.FC = FCM_1stSetTransmit then
    B.HasReply := False
  else if Fcv then
  begin
    B.HasReply := True;
    B.LastFcb := B.RMess.FCB_ACD;
  end;
  pChnFT1_2(B.Chn)^.ChSendAsWhenFree(False, @B.Reply, B.ReplyLen, FT12LinkTimeoutMs);
end;

{ The primary's timers: repetitions, establishing the link, user data and
  test functions. }
procedure RunPrimary(var B: tFT12Balanced);
var
  Now, Wait: QWord;
  Q: ^tFT12BalUserData;
begin
  Now := ChMsTick;
  if B.Pending then
  begin
    { collision rule: station B (DIR = 0) waits half a timeout more than
      station A before each repetition, so the two repeat at different
      times }
    Wait := QWord(B.TimeoutMs);
    if not pChnFT1_2(B.Chn)^.ChFT12Config.Dir then
      Inc(Wait, QWord(B.TimeoutMs) div 2);
    if Now - B.SentAt <= Wait then
      Exit;
    if B.Tries > B.Retries then
    begin
      LinkLost(B);                { the queued data waits for the new link }
      Exit;
    end;
    Inc(B.Tries);
    Inc(B.Retransmits);
    B.SentAt := Now;
    BalTransmit(B);               { a repetition: the same FCB }
    Exit;
  end;
  if Now < B.HoldUntil then
    Exit;
  case B.State of
    bsIdle, bsRequestStatus, bsResetting:
      begin
        B.State := bsRequestStatus;
        StartRequest(B, tpShortM, FCM_ReqLinkState, nil, 0);
      end;
    bsAvailable:
      if B.Suspect and ((B.QCount > 0) or
         ((B.TestMs > 0) and (Now - B.LastRequest >= QWord(B.TestMs)))) then
      begin
        { late answers may still come: flush them before the next request }
        Inc(B.Fences);
        B.Fencing := True;
        StartRequest(B, tpShortM, FCM_ReqLinkState, nil, 0);
      end
      else if B.QCount > 0 then
      begin
        Q := @B.Queue[B.QHead];
        if Q^.Confirm then
          StartRequest(B, tpLongM, FCM_UserDataReply, @Q^.Data[1], Q^.Len)
        else
        begin
          StartRequest(B, tpLongM, FCM_UserDataNoRep, @Q^.Data[1], Q^.Len);
          Inc(B.Confirmed);
          Dequeue(B);
        end;
      end
      else if (B.TestMs > 0) and (Now - B.LastRequest >= QWord(B.TestMs)) then
        StartRequest(B, tpShortM, FCM_CheckLink, nil, 0);
  end;
end;

function FT12BalancedStep(var B: tFT12Balanced): Boolean;
var
  Len: Word;
  R: tChResult;
  N: LongInt;
begin
  Result := False;
  if (B.Chn = nil) or (B.Chn^.CH_State <> CHS_Connect) then
    Exit;
  { everything already received: after the first look only while the
    channel holds input it has pulled in (a look may wait IDL ms for new
    input), and a bounded number of frames, so a peer that never stops
    cannot hold the timers and the application up }
  N := 0;
  while (N < FT12MaxFramesPerStep) and ((N = 0) or B.Chn^.ChHoldsInput) and
        (B.Chn^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(N);
    Result := True;
    Inc(B.Frames);
    Len := 0;
    B.Chn^.ChReceive(Len);
    R := B.Chn^.ChReceiveResult;
    if R = res_ErrDir then
      Inc(B.BadDir)               { an echo or a twin: never answered }
    else if R <> res_Ok then
      Inc(B.Broken)               { garbled: the peer repeats }
    else if pChnFT1_2(B.Chn)^.ChReceivedPrm then
      TakeRequest(B, Len)
    else
      TakeAnswer(B);
    { the next request goes out before the next look, which may wait IDL }
    RunPrimary(B);
  end;
  FT12NoteForeign(B.Chn, B.RxForeign, B.OtherAddr, B.OtherLast);
  if not Result then
    RunPrimary(B);
end;

end.
