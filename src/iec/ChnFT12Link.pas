{ ChnFT12Link - the IEC 60870-5-2 unbalanced link procedures that SofCon's
  ChnFT1_2 leaves to the application (manual 4.4: "evaluating FCB and
  repeating a message with unchanged FCB is the job of the application";
  docs/PROTOCOLS.md section 5: "or the optional helpers"), for both ends, on top of a
  tChnFT1_2 channel with MS=ON:

  * FT12Transact, the primary (master): one SEND/CONFIRM, REQUEST/RESPOND
    or SEND/NO REPLY service to one secondary, with the frame count bit
    kept per secondary in a tFT12Link record:
      - FCV = 1 for FC 2, 3, 10, 11, else 0 (IEC 60870-5-2 function table;
        the manual's FCM_* comments say the same);
      - every new FCV = 1 transmission to a secondary carries the opposite
        FCB of the previous one; a repetition after a missing or garbled
        reply carries the same FCB;
      - reset of remote link (FC 0) is sent with FCB = 0, FCV = 0; after
        its ACK the next FCV = 1 frame carries FCB = 1;
      - an FCV = 1 service to a link not reset (new record, or after a
        service failed) is preceded by a reset of remote link;
      - SEND/NO REPLY (FC 4) and the broadcast address expect no reply.
    FT12PrimaryStart / FT12PrimaryStep are the same service stepped by the
    program's own loop (many lines, one ChnWaitAny); FT12Transact is them
    with the program-wide wait (or the caller's Idle) between the steps.
  * tFT12Station / FT12StationStep, the secondary (slave): answers the
    unbalanced functions, and when an FCV = 1 frame carries the same FCB
    as the last one it accepted it sends the last reply again without
    executing the frame a second time (a repetition by the primary).

  Both poll the channel; nothing blocks for longer than the timeouts given.
  A caller that runs both ends in one thread passes an Idle procedure that
  steps the other end while the primary waits (as ChnDF1Link does).

  * tFT12Balanced / FT12BalancedStep, a station of a balanced link (MS=OFF):
    primary and secondary at once on one channel - link set-up (FC 9,
    FC 0), user data from a queue (FC 3/4), test function for link (FC 2)
    when quiet, repetitions with the same FCB; answers to the peer's
    requests at once, also while a request of its own is out, with the
    cached answer for a repeated FCB. On a lost frame station B (DIR=0)
    repeats half a timeout later than station A, so the two do not meet
    again (docs/ChnFT1_2.md, balanced mode).

  Late answers (both primaries). An answer carries nothing that says which
  transmission it answers, so after a repetition the answer to the first
  transmission, held up on the line longer than the timeout, and the
  answer to the repetition may both arrive - the second while the next
  request is out, where it would confirm a frame the secondary never got
  (issue 24). The primary therefore keeps count: after a request that was
  sent more than once (or not answered at all) answers to it may still
  come (Suspect), and before its next request it sends a fence, request
  status of link (FC 9). Its answer, status of link (FC 11), fits no other
  request, and on a line that keeps order it arrives after every answer
  the secondary sent before; every other answer meanwhile is late and
  ignored (Stale). Status answers owed by earlier FC 9 transmissions are
  counted too (OwedStatus; forgotten after 4 timeouts without one) and
  skipped by the next FC 9. A fresh answer to any other request proves
  that nothing older is still on the way.

  Not covered: DFC flow control beyond holding back after DFC = 1, the
  "link service not functioning" (FC 14) state. }
unit ChnFT12Link;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2;

const
  FT12LinkTimeoutMs = 1000;
  FT12LinkRetries   = 3;
  { frames one step takes at most: all that was received, but a peer that
    never stops sending cannot keep a step from running the timers }
  FT12MaxFramesPerStep = 64;

  {- secondary function codes of IEC 60870-5-2 that the manual does not name }
  FCS_NotFunctioning  = 14;  {< link service not functioning }
  FCS_NotImplemented  = 15;  {< link service not implemented }

type
  tFT12Idle = procedure(Data: Pointer);

  { What the primary keeps per secondary. }
  tFT12Link = record
    Addr    : Word;      {< link address of the secondary (DNO) }
    Fcb     : Boolean;   {< FCB for the next new FCV = 1 transmission }
    Reset   : Boolean;   {< reset of remote link acknowledged, no failure since }
    Acd     : Boolean;   {< ACD of the last reply: class 1 data waiting }
    Dfc     : Boolean;   {< DFC of the last reply: secondary cannot take more }
    Repeats : LongInt;   {< repetitions sent after a missing reply }
    Ignored : LongInt;   {< frames ignored while waiting (other address, broken) }
    {- late answers (unit header): }
    Suspect   : Boolean; {< answers to earlier transmissions may still come: fence first }
    OwedStatus: LongInt; {< status of link answers (FC 11) that may still come }
    StatusAt  : QWord;   {< when a status request last went out }
    Fences    : LongInt; {< fences (FC 9) sent before a service }
    Stale     : LongInt; {< late answers recognised and ignored }
    OtherAddr : LongInt; {< of Ignored: answers from another link address }
    OtherLast : Word;    {< the address the last of them carried }
  end;

  { Secondary callbacks; Data is tFT12Station.Data.
    UserData: user data of FC 3 (Confirm = True) or FC 4 / broadcast
      (Confirm = False); Len data octets in Buf^. True accepts it (ACK),
      False refuses it (NACK, FC 1); the result of FC 4 is not sent.
    ClassData: data of class 1 or 2 for the reply; put up to MaxDataLen
      octets in Rep.Data and their count in Len; False: none (FC 9).
    Class1Waiting: ACD of every reply; nil = never. }
  tFT12UserDataFunc = function(Data: Pointer; Buf: PByte; Len: Word;
    Confirm: Boolean): Boolean;
  tFT12ClassDataFunc = function(Data: Pointer; ClassNo: Byte;
    var Rep: tSendRecord; var Len: Word): Boolean;
  tFT12Class1Func = function(Data: Pointer): Boolean;

  tFT12Station = record
    Chn        : pChnVirt;
    RMess      : tFT12MaxRecord; {< any frame, L up to 255 }
    Reply      : tSendRecord;  {< last reply to an FCV = 1 frame or a reset }
    ReplyLen   : Word;
    HasReply   : Boolean;
    LinkReset  : Boolean;      {< a reset of remote link was received }
    LastFcb    : Boolean;      {< FCB of the last accepted FCV = 1 frame (0 after reset) }
    Dfc        : Boolean;      {< DFC sent in every reply (set by the application) }
    SingleAck  : Boolean;      {< ACK as E5 when no class 1 data is waiting }
    OnUserData : tFT12UserDataFunc;
    OnClassData: tFT12ClassDataFunc;
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

procedure FT12LinkInit(var Link: tFT12Link; Addr: Word);

{ One service of the primary to Link.Addr. Req/ReqLen as for ChSend (the
  FCB_ACD and FCV_DFC fields are set here from Link and Req.FC); the reply
  goes to Rep/RepLen (RepLen = 0 when none is expected). The channel's
  receive buffer and DNO are the caller's again afterwards.
  Results: res_Ok (a reply that fits the function: FC 0/1/3 -> ACK, NACK
  or E5; FC 8/9 -> status of link; FC 10/11 -> user data, no data or E5;
  FC 2 -> ACK/NACK); res_Timeout (no fitting reply after 1 + Retries
  transmissions); res_BadMessage (a reply whose function does not fit, the
  broadcast address with a function other than FC 4, SACK/SNAK as request,
  a tChnFT1_2 not in unbalanced master mode); res_WrongLayer (Chn is no
  tChnFT1_2 stack: nothing is sent); res_BadParam
  (Retries < 0, TimeoutMs < 1); a send error of the channel, or its
  ChResult when the line fails while waiting (res_DeviceLost ...), at once.
  Any result but res_Ok for an FCV = 1 or reset service clears Link.Reset. }
function FT12Transact(Chn: pChnVirt; var Link: tFT12Link; constref Req: tSendRecord;
  ReqLen: Word; var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt;
  Retries: LongInt; Idle: tFT12Idle = nil; IdleData: Pointer = nil): tChResult;

{ The same service stepped by the caller's loop (a program that must keep
  serving other lines): FT12PrimaryStart checks and sends (False: nothing
  sent, P.Result says why - the results of FT12Transact), then each
  FT12PrimaryStep takes everything the channel has received, without
  waiting, runs the timer and returns True when the service is over;
  P.Result, P.Rep/P.RepLen are then what FT12Transact returns. P and Link
  must stay where they are until then (the channel receives into P.Rep);
  the channel's receive buffer and DNO are given back at the end. }
type
  tFT12PrimaryState = (fpWaiting, fpDraining, fpDone);
  tFT12Primary = record
    Chn      : pChnVirt;
    Link     : ^tFT12Link;
    Req      : tSendRecord;
    ReqLen   : Word;
    Out      : tSendRecord;     {< what goes on the line: the reset or the service }
    OutLen   : Word;
    Rep      : tFT12MaxRecord;  {< any answer, L up to 255 }
    RepLen   : Word;
    State    : tFT12PrimaryState;
    Result   : tChResult;
    Fcv      : Boolean;
    NoReply  : Boolean;
    Resetting: Boolean;         {< the reset in front of an FCV = 1 service is out }
    Fencing  : Boolean;         {< the fence in front of them is out (FC 9) }
    StatusSkip: LongInt;        {< status answers owed from before: not this one's }
    Try_     : LongInt;         {< repetitions of Out so far }
    Retries  : LongInt;
    TimeoutMs: LongInt;
    Until_   : QWord;           {< end of the wait for this transmission }
    OldBuf   : Pointer;
    OldSize  : Word;
    OldDNode : tNode;
  end;

function FT12PrimaryStart(var P: tFT12Primary; Chn: pChnVirt; var Link: tFT12Link;
  constref Req: tSendRecord; ReqLen: Word; TimeoutMs: LongInt; Retries: LongInt): Boolean;
function FT12PrimaryStep(var P: tFT12Primary): Boolean;
{ The tick (ChMsTick) at which P's timer runs out: how long a caller with
  nothing else to do may wait (ChnWaitUntil) before the next step. }
function FT12PrimaryWaitEnd(const P: tFT12Primary): QWord;
{ Abandon a service under way (P.Result res_Timeout; the link counts as
  not reset). }
procedure FT12PrimaryCancel(var P: tFT12Primary);

{ True when Chn is the top of a tChnFT1_2 stack (by the registry's number
  of the layer type). }
function IsFT12Channel(Chn: pChnVirt): Boolean;

{ Reset of remote link (FC 0) as a fixed frame. }
function FT12ResetLink(Chn: pChnVirt; var Link: tFT12Link; TimeoutMs: LongInt;
  Retries: LongInt; Idle: tFT12Idle = nil; IdleData: Pointer = nil): tChResult;

{ Request user data of class 1 (FC 10) or 2 (FC 11) as a fixed frame;
  res_BadParam for another ClassNo. Rep.FC tells FCS_UserData or
  FCS_DataNotAcces (E5 arrives as tpSACK). }
function FT12RequestClass(Chn: pChnVirt; var Link: tFT12Link; ClassNo: Byte;
  var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt; Retries: LongInt;
  Idle: tFT12Idle = nil; IdleData: Pointer = nil): tChResult;

{ FCV the standard gives a primary function code. }
function FT12FcvOf(FC: Byte): Boolean;
{ What the line showed besides the answers awaited, for an error text:
  ' — 12 frames from link address 1 ignored', ' — 3 frames with this
  station's own DIR bit ignored' (both when both), '' when none. }
function FT12IgnoredText(OtherAddr: LongInt; OtherLast: Word; OwnDir: LongInt): ShortString;

procedure FT12StationInit(var S: tFT12Station; Chn: pChnVirt);
{ Take at most one frame and act on it; False when none was waiting, or
  when S.Chn is not a tChnFT1_2 (then nothing is read). }
function FT12StationStep(var S: tFT12Station): Boolean;

{- ------------------------------------------------------------ balanced }

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
    Data   : tData;
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
    Out        : tSendRecord; {< that request, for repetitions }
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
  is full, res_TooLong above MaxDataLen, res_BadLen for 0. }
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

var
  FT12NumName: Word;   { ChNumName(ChnFT1_2.cName) }

function IsFT12Channel(Chn: pChnVirt): Boolean;
begin
  Result := (Chn <> nil) and (Chn^.CH_NumName = FT12NumName);
end;

function FT12FcvOf(FC: Byte): Boolean;
begin
  Result := FC in [FCM_CheckLink, FCM_UserDataReply, FCM_ReqUserData1,
    FCM_ReqUserData2];
end;

function FT12IgnoredText(OtherAddr: LongInt; OtherLast: Word; OwnDir: LongInt): ShortString;
begin
  Result := '';
  if OtherAddr > 0 then
    Result := ' — ' + IntToStr(OtherAddr) + ' frames from link address ' + IntToStr(OtherLast) + ' ignored';
  if OwnDir > 0 then
    Result := Result + ' — ' + IntToStr(OwnDir) + ' frames with this station''s own DIR bit ignored';
end;

{ Frames the channel dropped for another link address since the last look. }
procedure NoteForeign(Chn: pChnVirt; var Seen: LongWord; var Count: LongInt; var Last: Word);
var
  F: pChnFT1_2;
begin
  F := pChnFT1_2(Chn);
  if F^.CH_Rx.Foreign <> Seen then
  begin
    Inc(Count, LongInt(F^.CH_Rx.Foreign - Seen));
    Seen := F^.CH_Rx.Foreign;
    Last := F^.CH_Rx.ForeignAddr;
  end;
end;

procedure FT12LinkInit(var Link: tFT12Link; Addr: Word);
begin
  FillChar(Link, SizeOf(Link), 0);
  Link.Addr := Addr;
end;

{ Octets of a fixed frame on this channel (LEN=), as a record length. }
function FixedLen(Chn: pChnVirt): Word;
begin
  Result := cSizeHeadSndMsg + pChnFT1_2(Chn)^.CH_LenShortM;
end;

{ Send once the transmitter is free (bounded wait). }
function SendNow(Chn: pChnVirt; constref R: tSendRecord; Len: Word): tChResult;
begin
  Result := ChSendWhenFree(Chn, @R, Len, FT12LinkTimeoutMs);
end;

{- ------------------------------------------------------------- primary }

{ Does a secondary's reply of type T and function FC answer primary
  function Req? (IEC 60870-5-2 table of services) }
function ReplyFits(Req: Byte; T: tMessType; FC: Byte): Boolean;
begin
  if T = tpSNAK then
    Exit(False);                           { not an IEC 60870-5-2 reply }
  case Req of
    FCM_1stSetTransmit, FCM_1stSetUserFun, FCM_UserDataReply, FCM_CheckLink:
      Result := (T = tpSACK) or (FC in [FCS_Ack, FCS_NackBusy]);
    FCM_ReqReplyAcces, FCM_ReqLinkState:
      Result := (T <> tpSACK) and (FC = FCS_LinkSAccesReq);
    FCM_ReqUserData1, FCM_ReqUserData2:
      Result := (T = tpSACK) or (FC in [FCS_UserData, FCS_DataNotAcces]);
  else
    Result := T <> tpSACK;                { not a standard function: any frame }
  end;
  { "not functioning" / "not implemented" answer anything }
  if (T in [tpShortM, tpLongM]) and (FC in [FCS_NotFunctioning, FCS_NotImplemented]) then
    Result := True;
end;

procedure PrimaryPhaseEnd(var P: tFT12Primary; R: tChResult); forward;

{ Requests answered by status of link (FC 11). }
function IsStatusRequest(FC: Byte): Boolean;
begin
  Result := FC in [FCM_ReqReplyAcces, FCM_ReqLinkState];
end;

{ The phase that starts now: Out built from the service (or the reset in
  front of it), sent for the first time. }
procedure PrimarySendOut(var P: tFT12Primary);
var
  R: tChResult;
begin
  if P.Try_ > 0 then
    Inc(P.Link^.Repeats);
  if IsStatusRequest(P.Out.FC) then
  begin
    Inc(P.Link^.OwedStatus);            { the status answer it may bring }
    P.Link^.StatusAt := ChMsTick;
  end;
  R := SendNow(P.Chn, P.Out, P.OutLen);   { a repetition: same FCB }
  if R <> res_Ok then
  begin
    PrimaryPhaseEnd(P, R);
    Exit;
  end;
  P.Until_ := ChMsTick + QWord(P.TimeoutMs);
  if P.NoReply and not P.Resetting and not P.Fencing then
    P.State := fpDraining
  else
    P.State := fpWaiting;
end;

procedure PrimaryFinish(var P: tFT12Primary; R: tChResult);
begin
  P.Result := R;
  P.State := fpDone;
  P.Chn^.ChReceiveBuffer(P.OldBuf, P.OldSize);   { the caller's again }
  P.Chn^.ChDestNode(P.OldDNode);
end;

{ Build Out for the reset in front of the service (Resetting) or for the
  service, drop what came late for an earlier service, send. }
procedure PrimaryBegin(var P: tFT12Primary);
var
  Len: Word;
begin
  FillChar(P.Out, SizeOf(P.Out), 0);
  if P.Fencing then
  begin
    Inc(P.Link^.Fences);
    P.Out.MessType := tpShortM;
    P.Out.FC := FCM_ReqLinkState;
    P.OutLen := FixedLen(P.Chn);
  end
  else if P.Resetting then
  begin
    P.Out.MessType := tpShortM;
    P.Out.FC := FCM_1stSetTransmit;
    P.OutLen := FixedLen(P.Chn);
  end
  else
  begin
    Move(P.Req, P.Out, P.ReqLen);
    P.OutLen := P.ReqLen;
    P.Out.FCV_DFC := P.Fcv;
    P.Out.FCB_ACD := P.Fcv and P.Link^.Fcb;   { FCB = 0 whenever FCV = 0 }
  end;
  P.Chn^.ChDestNode(P.Link^.Addr);
  { a late frame from before is no answer to this service }
  P.Chn^.ChReceiveBuffer(@P.Rep, SizeOf(P.Rep));
  while P.Chn^.ChReceiveReady = CHS_ReceiveReady do
  begin
    Len := 0;
    P.Chn^.ChReceive(Len);
    if (P.Chn^.ChReceiveResult = res_Ok) and (P.Rep.MessType in [tpShortM, tpLongM]) and
       (P.Chn^.CH_RSNode = P.Link^.Addr) then
    begin
      Inc(P.Link^.Stale);
      if (P.Rep.FC = FCS_LinkSAccesReq) and (P.Link^.OwedStatus > 0) then
        Dec(P.Link^.OwedStatus);        { one status answer less on the way }
    end;
  end;
  P.RepLen := 0;
  P.Try_ := 0;
  if IsStatusRequest(P.Out.FC) then
  begin
    { status answers of earlier transmissions may still come: the first
      that many to arrive are not this request's }
    if ChMsTick - P.Link^.StatusAt > QWord(4 * P.TimeoutMs) then
      P.Link^.OwedStatus := 0;
    P.StatusSkip := P.Link^.OwedStatus;
  end;
  PrimarySendOut(P);
end;

{ The phase (reset or service) is over with R: keep what the reply says
  in Link, then the service after its reset, or the end. }
procedure PrimaryPhaseEnd(var P: tFT12Primary; R: tChResult);
var
  Fcv: Boolean;
begin
  if (R <> res_Ok) and (R <> res_BadMessage) and not IsStatusRequest(P.Out.FC) then
    P.Link^.Suspect := True;            { no answer came: it may still be on the way }
  if P.Fencing then
  begin
    P.Fencing := False;
    if R = res_Ok then
      PrimaryBegin(P)                   { late answers flushed: the reset or service }
    else
    begin
      if P.Fcv or P.Resetting then
        P.Link^.Reset := False;
      PrimaryFinish(P, R);
    end;
    Exit;
  end;
  Fcv := P.Out.FCV_DFC;
  if R = res_Ok then
  begin
    if P.Rep.MessType in [tpShortM, tpLongM] then
    begin
      P.Link^.Acd := P.Rep.FCB_ACD;
      P.Link^.Dfc := P.Rep.FCV_DFC;
    end
    else
    begin
      P.Link^.Acd := False;             { E5: nothing waiting }
      P.Link^.Dfc := False;
    end;
    if P.Out.FC = FCM_1stSetTransmit then
    begin
      P.Link^.Reset := True;
      P.Link^.Fcb := True;              { first FCV = 1 frame after a reset }
    end
    else if Fcv then
      P.Link^.Fcb := not P.Link^.Fcb;
  end
  else if Fcv or (P.Out.FC = FCM_1stSetTransmit) then
    P.Link^.Reset := False;             { FCB state unknown: reset next time }
  if (R = res_Ok) and P.Resetting then
  begin
    P.Resetting := False;               { the link is reset: now the service }
    PrimaryBegin(P);
  end
  else
  begin
    if P.Resetting then
      P.RepLen := 0;
    PrimaryFinish(P, R);
  end;
end;

function FT12PrimaryStart(var P: tFT12Primary; Chn: pChnVirt; var Link: tFT12Link;
  constref Req: tSendRecord; ReqLen: Word; TimeoutMs: LongInt; Retries: LongInt): Boolean;
var
  F: pChnFT1_2;
  R: tChResult;
begin
  FillChar(P, SizeOf(P), 0);
  P.State := fpDone;
  R := res_Ok;
  if (Retries < 0) or (TimeoutMs < 1) then
    R := res_BadParam
  else if not IsFT12Channel(Chn) then
    R := res_WrongLayer
  else if not pChnFT1_2(Chn)^.CH_MaSl or not pChnFT1_2(Chn)^.CH_Master then
    R := res_BadMessage
  else if (ReqLen = 0) or (ReqLen > SizeOf(tSendRecord)) or
     (PByte(@Req)^ > Ord(tpLongM)) or (Req.MessType in [tpSACK, tpSNAK]) then
    R := res_BadMessage;
  if R = res_Ok then
  begin
    F := pChnFT1_2(Chn);
    P.Fcv := FT12FcvOf(Req.FC);
    P.NoReply := (Req.FC = FCM_UserDataNoRep) or
      ((F^.CH_AdrLen > 0) and (Link.Addr = FT12Broadcast(F^.CH_AdrLen)));
    if P.NoReply and (Req.FC <> FCM_UserDataNoRep) then
      R := res_BadMessage;              { broadcast is SEND/NO REPLY only }
  end;
  if R <> res_Ok then
  begin
    P.Result := R;
    Exit(False);
  end;
  P.Chn := Chn;
  P.Link := @Link;
  P.Req := Req;
  P.ReqLen := ReqLen;
  P.TimeoutMs := TimeoutMs;
  P.Retries := Retries;
  { the caller's receive buffer and DNO come back at the end }
  Chn^.ChGetReceiveBuffer(P.OldBuf, P.OldSize);
  P.OldDNode := Chn^.ChGetDestNode;
  { the secondary's FCB memory is unknown: reset it first }
  P.Resetting := P.Fcv and not Link.Reset;
  { answers to earlier transmissions may still come: a fence before
    anything that an ACK, E5 or user data would answer }
  P.Fencing := Link.Suspect and not P.NoReply and
    (P.Resetting or not IsStatusRequest(Req.FC));
  PrimaryBegin(P);
  Result := P.State <> fpDone;
end;

{ A good frame is in P.Rep: the answer of this phase, or one to ignore. }
function PrimaryTake(var P: tFT12Primary; Len: Word): Boolean;
var
  F: pChnFT1_2;
  Status: Boolean;
begin
  F := pChnFT1_2(P.Chn);
  if (P.Chn^.ChReceiveResult <> res_Ok) or
     ((P.Rep.MessType in [tpShortM, tpLongM]) and (F^.CH_AdrLen > 0) and
      (P.Chn^.CH_RSNode <> P.Link^.Addr)) then
  begin
    Inc(P.Link^.Ignored);               { garbled, or another station's }
    if P.Chn^.ChReceiveResult = res_Ok then
    begin
      Inc(P.Link^.OtherAddr);
      P.Link^.OtherLast := P.Chn^.CH_RSNode;
    end;
    Exit(False);
  end;
  Status := (P.Rep.MessType in [tpShortM, tpLongM]) and (P.Rep.FC = FCS_LinkSAccesReq);
  if Status and (P.Link^.OwedStatus > 0) then
    Dec(P.Link^.OwedStatus);
  { "not functioning" / "not implemented" answer anything }
  if (Status <> IsStatusRequest(P.Out.FC)) and not ((P.Rep.MessType in [tpShortM, tpLongM]) and
     (P.Rep.FC in [FCS_NotFunctioning, FCS_NotImplemented])) then
  begin
    Inc(P.Link^.Stale);                 { late: the answer to an earlier request }
    Exit(False);
  end;
  if Status and (P.StatusSkip > 0) then
  begin
    Dec(P.StatusSkip);                  { owed by an earlier FC 9 }
    Inc(P.Link^.Stale);
    Exit(False);
  end;
  { a fresh answer: everything the secondary answered before it has arrived }
  if Status then
  begin
    P.Link^.Suspect := False;
    P.Link^.OwedStatus := P.Try_;       { this request's other transmissions }
  end
  else
  begin
    P.Link^.OwedStatus := 0;
    if P.Try_ > 0 then
      P.Link^.Suspect := True;          { the answer to another transmission may follow }
  end;
  P.RepLen := Len;
  if not ReplyFits(P.Out.FC, P.Rep.MessType, P.Rep.FC) or
     { a refused reset leaves the link not reset }
     ((P.Out.FC = FCM_1stSetTransmit) and (P.Rep.MessType <> tpSACK) and
      (P.Rep.FC <> FCS_Ack)) then
    PrimaryPhaseEnd(P, res_BadMessage)
  else
    PrimaryPhaseEnd(P, res_Ok);
  Result := True;
end;

function FT12PrimaryStep(var P: tFT12Primary): Boolean;
var
  Len: Word;
  N: LongInt;
begin
  if P.State = fpDraining then
  begin
    { SEND/NO REPLY: done once the frame is on the line }
    if (P.Chn^.ChSendReady = CHS_SendReady) or (P.Chn^.ChResult <> res_Ok) or
       (ChMsTick > P.Until_) then
      PrimaryFinish(P, P.Chn^.ChResult);
  end;
  { everything already received, in one step }
  N := 0;
  while (P.State = fpWaiting) and (N < FT12MaxFramesPerStep) and
        ((N = 0) or P.Chn^.ChHoldsInput) and (P.Chn^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(N);
    Len := 0;
    P.Chn^.ChReceive(Len);
    PrimaryTake(P, Len);
  end;
  if P.State = fpWaiting then
    if P.Chn^.ChResult <> res_Ok then
      PrimaryPhaseEnd(P, P.Chn^.ChResult)   { the line is gone: no reply can come }
    else if ChMsTick > P.Until_ then
    begin
      if P.Try_ < P.Retries then
      begin
        Inc(P.Try_);
        PrimarySendOut(P);
      end
      else
        PrimaryPhaseEnd(P, res_Timeout);
    end;
  Result := P.State = fpDone;
end;

function FT12PrimaryWaitEnd(const P: tFT12Primary): QWord;
begin
  Result := P.Until_ + 1;
end;

procedure FT12PrimaryCancel(var P: tFT12Primary);
begin
  if P.State <> fpDone then
  begin
    if P.Fcv or P.Resetting then
      P.Link^.Reset := False;           { FCB state unknown: reset next time }
    PrimaryFinish(P, res_Timeout);
  end;
end;

function FT12Transact(Chn: pChnVirt; var Link: tFT12Link; constref Req: tSendRecord;
  ReqLen: Word; var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt;
  Retries: LongInt; Idle: tFT12Idle; IdleData: Pointer): tChResult;
var
  P: tFT12Primary;
begin
  RepLen := 0;
  if FT12PrimaryStart(P, Chn, Link, Req, ReqLen, TimeoutMs, Retries) then
    repeat
      if Assigned(Idle) then
        Idle(IdleData)
      else
        ChnWaitUntil(FT12PrimaryWaitEnd(P));   { the program-wide wait }
    until FT12PrimaryStep(P);
  Result := P.Result;
  if P.RepLen > SizeOf(Rep) then
    Result := res_ErrLen                { longer than the manual's record holds }
  else
  begin
    if P.RepLen > 0 then
      Move(P.Rep, Rep, P.RepLen);
    RepLen := P.RepLen;
  end;
end;

{ A fixed frame with function FC and the channel's LEN= zero octets. }
function FixedService(Chn: pChnVirt; var Link: tFT12Link; FC: Byte;
  var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt; Retries: LongInt;
  Idle: tFT12Idle; IdleData: Pointer): tChResult;
var
  Req: tSendRecord;
begin
  RepLen := 0;
  if not IsFT12Channel(Chn) then
    Exit(res_WrongLayer);
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpShortM;
  Req.FC := FC;
  Result := FT12Transact(Chn, Link, Req, FixedLen(Chn), Rep, RepLen, TimeoutMs,
    Retries, Idle, IdleData);
end;

function FT12ResetLink(Chn: pChnVirt; var Link: tFT12Link; TimeoutMs: LongInt;
  Retries: LongInt; Idle: tFT12Idle; IdleData: Pointer): tChResult;
var
  Rep: tRecRecord;
  Len: Word;
begin
  Result := FixedService(Chn, Link, FCM_1stSetTransmit, Rep, Len, TimeoutMs,
    Retries, Idle, IdleData);
end;

function FT12RequestClass(Chn: pChnVirt; var Link: tFT12Link; ClassNo: Byte;
  var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt; Retries: LongInt;
  Idle: tFT12Idle; IdleData: Pointer): tChResult;
begin
  RepLen := 0;
  case ClassNo of
    1: Result := FixedService(Chn, Link, FCM_ReqUserData1, Rep, RepLen,
         TimeoutMs, Retries, Idle, IdleData);
    2: Result := FixedService(Chn, Link, FCM_ReqUserData2, Rep, RepLen,
         TimeoutMs, Retries, Idle, IdleData);
  else
    Result := res_BadParam;
  end;
end;

{- ----------------------------------------------------------- secondary }

{ The answer to SEND/CONFIRM user data (FC 3) of Len record octets: ACK
  when the application takes it, NACK when it refuses or has no callback. }
function UserDataAnswer(F: tFT12UserDataFunc; Data: Pointer;
  constref R: tFT12MaxRecord; Len: Word): Byte;
begin
  if Assigned(F) and F(Data, @R.Data[1], Len - cSizeHeadRecMsg, True) then
    Result := FCS_Ack
  else
    Result := FCS_NackBusy;
end;

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
    S.ReplyLen := FixedLen(S.Chn);
  end;
end;

procedure ClassReply(var S: tFT12Station; ClassNo: Byte);
var
  Len: Word;
  Got: Boolean;
begin
  FillChar(S.Reply, SizeOf(S.Reply), 0);
  Len := 0;
  Got := Assigned(S.OnClassData) and S.OnClassData(S.Data, ClassNo, S.Reply, Len);
  if Got and (Len <= MaxDataLen) then
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
  NoteForeign(S.Chn, S.RxForeign, S.OtherAddr, S.OtherLast);
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
    SendNow(S.Chn, S.Reply, S.ReplyLen);
    Exit;
  end;
  if Fcv then
  begin
    if not S.LinkReset then
    begin
      { the FCB memory is not set up: refuse until the primary resets }
      Inc(S.Refused);
      FixedReply(S, FCS_NackBusy);
      SendNow(S.Chn, S.Reply, S.ReplyLen);
      S.HasReply := False;
      Exit;
    end;
    if S.HasReply and (S.RMess.FCB_ACD = S.LastFcb) then
    begin
      { same FCB as the last accepted frame: the primary lost our reply }
      Inc(S.Repeats);
      SendNow(S.Chn, S.Reply, S.ReplyLen);
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
        FixedReply(S, UserDataAnswer(S.OnUserData, S.Data, S.RMess, Len));
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
  SendNow(S.Chn, S.Reply, S.ReplyLen);
end;

{- ------------------------------------------------------------ balanced }

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
  if pChnFT1_2(Chn)^.CH_MaSl then
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
  if Len > MaxDataLen then
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

{ Send R in the given direction once the transmitter is free (bounded). }
function SendDir(var B: tFT12Balanced; Primary: Boolean; constref R: tSendRecord;
  Len: Word): tChResult;
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(FT12LinkTimeoutMs);
  while (B.Chn^.ChSendReady <> CHS_SendReady) and (ChMsTick <= Deadline) do
    ChnWaitUntil(Deadline + 1, 10);    { as ChSendWhenFree }
  pChnFT1_2(B.Chn)^.ChSendAs(Primary, @R, Len);
  Result := B.Chn^.ChSendResult;
end;

{ Send Out (again), counting the status answer it may bring. }
procedure BalTransmit(var B: tFT12Balanced);
begin
  if B.Out.FC = FCM_ReqLinkState then
  begin
    Inc(B.OwedStatus);
    B.StatusAt := ChMsTick;
  end;
  SendDir(B, True, B.Out, B.OutLen);
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
    B.OutLen := FixedLen(B.Chn)
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
  if not ReplyFits(B.Out.FC, B.RMess.MessType, B.RMess.FC) then
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
  B.ReplyLen := FixedLen(B.Chn);
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
    SendDir(B, False, B.Reply, B.ReplyLen);
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
        BalReply(B, UserDataAnswer(B.OnUserData, B.Data, B.RMess, Len));
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
  SendDir(B, False, B.Reply, B.ReplyLen);
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
    if not pChnFT1_2(B.Chn)^.CH_Dir then
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
    else if pChnFT1_2(B.Chn)^.CH_RPrm then
      TakeRequest(B, Len)
    else
      TakeAnswer(B);
    { the next request goes out before the next look, which may wait IDL }
    RunPrimary(B);
  end;
  NoteForeign(B.Chn, B.RxForeign, B.OtherAddr, B.OtherLast);
  if not Result then
    RunPrimary(B);
end;

initialization
  FT12NumName := ChNumName(ChnFT1_2.cName);
end.
