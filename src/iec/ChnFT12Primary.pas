{ ChnFT12Primary - the primary (master) of an unbalanced IEC 60870-5-2
  link (unit ChnFT12Link tells the rules): FT12Transact, one
  SEND/CONFIRM, REQUEST/RESPOND or SEND/NO REPLY service to one secondary
  with the frame count bit kept in its tFT12Link, repetitions, the reset
  in front of an FCV = 1 service and the fence against late answers;
  FT12PrimaryStart / FT12PrimaryStep are the same service stepped by the
  program's own loop. }
unit ChnFT12Primary;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link;

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

{ Reset of remote link (FC 0) as a fixed frame. }
function FT12ResetLink(Chn: pChnVirt; var Link: tFT12Link; TimeoutMs: LongInt;
  Retries: LongInt; Idle: tFT12Idle = nil; IdleData: Pointer = nil): tChResult;

{ Request user data of class 1 (FC 10) or 2 (FC 11) as a fixed frame;
  res_BadParam for another ClassNo. Rep.FC tells FCS_UserData or
  FCS_DataNotAcces (E5 arrives as tpSACK). }
function FT12RequestClass(Chn: pChnVirt; var Link: tFT12Link; ClassNo: Byte;
  var Rep: tRecRecord; var RepLen: Word; TimeoutMs: LongInt; Retries: LongInt;
  Idle: tFT12Idle = nil; IdleData: Pointer = nil): tChResult;

implementation

uses
  SysUtils, ChnFT12Codec, ChnWait;

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
  R := FT12SendNow(P.Chn, P.Out, P.OutLen);   { a repetition: same FCB }
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
    P.OutLen := FT12FixedLen(P.Chn);
  end
  else if P.Resetting then
  begin
    P.Out.MessType := tpShortM;
    P.Out.FC := FCM_1stSetTransmit;
    P.OutLen := FT12FixedLen(P.Chn);
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
  else if pChnFT1_2(Chn)^.ChFT12Config.Balanced or not pChnFT1_2(Chn)^.ChFT12Config.Primary then
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
  if not FT12ReplyFits(P.Out.FC, P.Rep.MessType, P.Rep.FC) or
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
  Result := FT12Transact(Chn, Link, Req, FT12FixedLen(Chn), Rep, RepLen, TimeoutMs,
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

end.
