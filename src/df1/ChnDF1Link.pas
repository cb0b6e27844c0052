{ ChnDF1Link - the DF1 link dialogue that SofCon's ChnDF1 leaves to the
  application (manual section 5; Rockwell 1770-6.5.16 chapters 2-4), for
  both ends, on top of any tChnDF1 channel:

  * tDF1Station, a slave/responder: full duplex - ACK a good command, NAK a
    broken frame, repeat the last ACK/NAK on ENQ, send the reply and send it
    again on a NAK of it; half duplex - ACK, keep the reply for the
    master's poll, EOT when there is nothing to send, and stay silent on a
    broken frame (a half-duplex slave never NAKs). Commands are answered by
    a handler the application gives (tools/df1sim plugs in its data table);
    link events (frames in and out, NAKs, ENQs, repeated commands) can be
    counted through an optional callback. The last reply to each of a few
    source stations stays cached: on a channel with DUP=ON a repeated
    command (the master missed our ACK or the reply) never reaches the
    handler again, and the master gets the cached reply again instead
    (half duplex: at its next poll).
  * DF1Transact, a master: send a command, up to three tries (NAK or
    no answer -> again; full duplex asks with ENQ first), then wait for the
    reply (half duplex: poll for it), ACK it.

  * DF1OpenStack, a tChnDF1 stack built from a parameter string, opened and
    connected within a deadline.

  Both poll the channel; nothing blocks for longer than the timeouts given.
  A caller that runs both ends in one thread (tests over NAM=LOOP) passes
  an Idle procedure that steps the other end while one waits. Both can log
  each message as a line ('-> ' sent, '<- ' received, DF1Describe), the
  sent ones with their wire bytes if asked (DF1WireText). }
unit ChnDF1Link;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnDF1, ChnPcccNames;

const
  DF1LinkTimeoutMs = 1000;   {< the RACOM note's link timeout }
  DF1LinkTries     = 3;
  { messages one DF1MasterStep takes at most: all that was received, but a
    peer that never stops (50 ENQs a millisecond) cannot keep the step
    from running the timers }
  DF1MaxFramesPerStep = 64;

type
  tDF1Idle = procedure(Data: Pointer);
  tDF1LogProc = procedure(const Line: AnsiString);

  { Answer one command (Cmd/CmdLen as received, Len = 8 + data bytes):
    fill Reply/ReplyLen and return True, or False to send no reply. }
  tDF1Handler = function(Data: Pointer; constref Cmd: tRecRecord; CmdLen: Word;
    var Reply: tSendRecord; var ReplyLen: Word): Boolean;
  { What a station counts: a good frame in, a frame out, a broken frame
    NAKed, an ENQ in, a NAK in, a repeated command the DF1 layer ACKed
    and did not deliver (DUP=ON). }
  tDF1LinkEvent = (leFrameIn, leFrameOut, leNakOut, leEnqIn, leNakIn, leDupIn);
  tDF1EventProc = procedure(Data: Pointer; Event: tDF1LinkEvent);

  { A reply kept for a repeated command: the last one to each of a few
    source stations (a frame damaged into another SRC must not push out
    the real master's reply). }
  tDF1CachedReply = record
    Used : Boolean;
    Src  : Byte;
    Tns  : Word;
    Len  : Word;
    Stamp: LongInt;       {< S.Requests when it was kept: the oldest goes }
    Rep  : tSendRecord;
  end;

const
  DF1ReplyCacheSize = 4;

type
  pDF1Station = ^tDF1Station;
  tDF1Station = record
    Chn      : pChnVirt;
    Handler  : tDF1Handler;
    Data     : Pointer;       {< given to Handler and OnEvent }
    OnEvent  : tDF1EventProc; {< nil: nothing counted }
    FullDup  : Boolean;
    RMess    : tRecRecord;
    Reply    : tSendRecord;   {< the last reply, kept for a repeated command }
    ReplyLen : Word;          {< 0: no reply yet }
    HasReply : Boolean;       {< a reply not yet ACKed by the master }
    AwaitAck : Boolean;       {< half duplex: the reply just went out }
    LastLink : tSendRecord;   {< last ACK/NAK sent, repeated on ENQ }
    Requests : LongInt;       {< commands answered }
    Messages : LongInt;       {< messages taken, good or broken }
    Repeats  : LongInt;       {< repeated commands answered from the cache }
    DupSeen  : LongInt;       {< the DF1 layer's CH_DupCount already acted on }
    Cache    : array[0..DF1ReplyCacheSize - 1] of tDF1CachedReply;
    Log      : tDF1LogProc;   {< nil: quiet }
    LogWire  : Boolean;       {< lines of sent frames end with the wire bytes }
    ReplyDst : Byte;          {< SRC of the command the reply answers }
    { a message of the station's own (an SLC's MSG instruction), half
      duplex: sent at a poll instead of EOT, again until ACKed }
    Own      : tSendRecord;
    OwnLen   : Word;
    OwnDst   : Byte;
    HasOwn   : Boolean;       {< queued, not yet ACKed }
    OwnAwait : Boolean;       {< it just went out: the next ACK is its }
    OwnSent  : LongInt;       {< own messages ACKed }
    OwnReplies: LongInt;      {< replies to them received }
    LastReply: tRecRecord;    {< the last of those replies }
    LastReplyLen: Word;
    LastReplySrc: Byte;
  end;

{ Queue a message of the station's own to station Dst (half duplex: it
  goes out at the next poll, instead of EOT, and again at later polls
  until the master ACKs it; a reply to it is counted in OwnReplies and
  kept in LastReply). res_Busy while the last one is not yet ACKed. }
function DF1StationQueue(var S: tDF1Station; Dst: Byte; constref Msg: tSendRecord;
  Len: Word): tChResult;

{ Set S up on Chn (a tChnDF1 stack) with the command handler and its data.
  res_WrongLayer (and a station that reads nothing) when Chn is not DF1. }
function DF1StationInit(var S: tDF1Station; Chn: pChnVirt; Handler: tDF1Handler;
  Data: Pointer): tChResult;
{ Take at most one message and act on it; False when none was waiting (or
  the station has no DF1 channel). }
function DF1StationStep(var S: tDF1Station): Boolean;

{ One command/reply exchange as a master. Req/ReqLen the command; the reply
  goes to Rep (RepLen); the channel's receive buffer is the caller's again
  afterwards (ChReceiveBuffer before the call stays in force). Results:
  res_Ok; res_Timeout (no ACK after the tries, or no reply); res_BadMessage
  (only replies with another TNS or command came: each is ACKed and
  ignored, as a late copy of an earlier reply, and the wait goes on until
  the tries or the reply's deadline are used up); res_WrongLayer (Chn is not a
  tChnDF1 stack: nothing is sent); a send error of the channel, or
  its ChResult when the line fails (res_DeviceLost ...) while waiting for
  the reply. Idle and Log may be nil; LogWire as in tDF1Station. }
function DF1Transact(Chn: pChnVirt; constref Req: tSendRecord; ReqLen: Word;
  var Rep: tRecRecord; var RepLen: Word; Idle: tDF1Idle; IdleData: Pointer;
  TimeoutMs: LongInt; Log: tDF1LogProc = nil; LogWire: Boolean = False): tChResult;

{ The same exchange stepped by the caller's poll loop (a program that must
  keep serving other lines): DF1MasterStart sends the command, then each
  DF1MasterStep takes everything the channel has received, without
  waiting, runs the timers and returns True when the exchange is over; M.Result is then what DF1Transact would
  return, M.Rep/M.RepLen the reply, M.Naks the NAKs the command got. M
  must stay where it is until then (the channel receives into M.Rep); the
  channel's receive buffer is given back at the end. }
type
  tDF1MasterState = (dmWaitAck, dmWaitReply, dmDone);
  tDF1Master = record
    Chn      : pChnVirt;
    Req      : tSendRecord;
    ReqLen   : Word;
    Rep      : tRecRecord;
    RepLen   : Word;
    State    : tDF1MasterState;
    Result   : tChResult;
    Tries    : LongInt;
    Naks     : LongInt;
    NaksOut  : LongInt;        {< broken replies NAKed (full duplex) }
    Stale    : LongInt;        {< replies to other commands, ACKed and ignored }
    Ignored  : LongInt;        {< broken frames and stray symbols while waiting for the ACK }
    EnqsIn   : LongInt;        {< ENQs of the peer, answered with LastAck }
    LastAck  : Boolean;        {< the last ACK/NAK this master sent was an ACK (none: NAK) }
    Acked    : Boolean;        {< the command was ACKed (or answered) }
    EnqSent  : Boolean;
    FullDup  : Boolean;
    TimeoutMs: LongInt;
    Until_   : QWord;          {< end of the current wait }
    Deadline : QWord;          {< end of the wait for the reply }
    OldBuf   : Pointer;
    OldSize  : Word;
    Log      : tDF1LogProc;
    LogWire  : Boolean;
  end;

{ Start an exchange; False (M.Result says why, M.State = dmDone) when
  nothing could be sent. }
function DF1MasterStart(var M: tDF1Master; Chn: pChnVirt; constref Req: tSendRecord;
  ReqLen: Word; TimeoutMs: LongInt; Log: tDF1LogProc = nil; LogWire: Boolean = False): Boolean;
{ One look at the channel; True when the exchange is over (M.State = dmDone). }
function DF1MasterStep(var M: tDF1Master): Boolean;
{ The tick (ChMsTick) at which M's next timer runs out: how long a
  caller with nothing else to do may wait (ChnWaitUntil) before the next
  DF1MasterStep. }
function DF1MasterWaitEnd(const M: tDF1Master): QWord;
{ Abandon an exchange under way (M.Result res_Timeout): the channel's
  receive buffer is given back; a reply that comes later is the caller's. }
procedure DF1MasterCancel(var M: tDF1Master);

{ True when Chn is the top of a tChnDF1 stack. }

function IsDF1Channel(Chn: pChnVirt): Boolean;
{ One line describing a record, for logs. }
function DF1Describe(const R: tRecRecord; Len: Word): AnsiString;
{ The wire bytes of the frame Chn (a tChnDF1) sent last, as hex
  ('10 02 ... 10 03 E3 88'): framing, DLE doubling and checksum included;
  '' for a channel that is no tChnDF1. }
function DF1WireText(Chn: pChnVirt): AnsiString;

{ A new tChnDF1 stack (its lower layers' units must be linked in) with
  Params set, opened and connected, waiting at most TimeoutMs for each
  state. nil on failure, with Err saying which step failed and why. }
function DF1OpenStack(const Params: AnsiString; TimeoutMs: LongInt; out Err: AnsiString): pChnVirt;

implementation

uses
  SysUtils, uString, ChnWait;

var
  DF1NumName: Word;    { ChNumName(ChnDF1.cName), the registry's number of DF1 }

function IsDF1Channel(Chn: pChnVirt): Boolean;
begin
  Result := (Chn <> nil) and (Chn^.CH_NumName = DF1NumName);
end;

function DF1WireText(Chn: pChnVirt): AnsiString;
var
  Len: Word;
begin
  if IsDF1Channel(Chn) then
    Result := HexBytes(pChnDF1(Chn)^.ChSentFrame(Len), Len)
  else
    Result := '';
end;

{ Wait until Chn reaches Want, an error result or the deadline. }
function WaitState(Chn: pChnVirt; Want: tChState; Deadline: QWord): Boolean;
begin
  { a state change need not end the program-wide wait: look every 10 ms }
  while (Chn^.ChReady <> Want) and (Chn^.ChResult = res_Ok) and (ChMsTick <= Deadline) do
    ChnWaitUntil(Deadline + 1, 10);
  Result := Chn^.ChReady = Want;
end;

function DF1OpenStack(const Params: AnsiString; TimeoutMs: LongInt; out Err: AnsiString): pChnVirt;
var
  Step: AnsiString;
  R: tChResult;
  Why: ShortString;
begin
  Err := '';
  Why := '';
  if ParamLengthCheck(Length(Params), Why) <> res_Ok then
  begin
    Err := 'parameter string too long: ' + Why;   { refused, never cut }
    Exit(nil);
  end;
  Result := ChnCollection^.ChNewInit(ChnDF1.cName);
  Result^.ChSetParam(Params);
  Step := 'parameters "' + Params + '"';
  if Result^.ChResult = res_Ok then
  begin
    Step := 'open "' + Params + '"';
    Result^.ChOpen;
    if WaitState(Result, CHS_Open, ChMsTick + QWord(TimeoutMs)) then
    begin
      Step := 'connect "' + Params + '"';
      Result^.ChConnect;
      if WaitState(Result, CHS_Connect, ChMsTick + QWord(TimeoutMs)) then
        Exit;
    end;
  end;
  R := Result^.ChResult;
  if R = res_Ok then
    R := res_Timeout;            { the state never came }
  if R = Result^.ChResult then
    Err := Step + ': ' + Result^.ChErrorText   { with the token and the OS reason }
  else
    Err := Step + ': ' + Result^.ChResultStr(R);
  Dispose(Result, Done);
  Result := nil;
end;

{ '-> ' + the record [+ its wire bytes] }
function SentLine(Chn: pChnVirt; constref R: tSendRecord; Len: Word; Wire: Boolean): AnsiString;
begin
  Result := '-> ' + DF1Describe(R, Len);
  if Wire then
    Result := Result + '   [' + DF1WireText(Chn) + ']';
end;

function DF1Describe(const R: tRecRecord; Len: Word): AnsiString;
var
  Name: AnsiString;
begin
  case R.MessType of
    tpAckNak:
      if R.FlAck then
        Result := 'ACK'
      else
        Result := 'NAK';
    tpEnq: Result := 'ENQ';
    tpPoll: Result := 'poll';
    tpNoPollRep: Result := 'EOT';
    tpDataMess:
      begin
        if R.CF and MskCF_Reply <> 0 then
          Name := 'reply CMD=$' + IntToHex(Hi(R.CF), 2)   { replies carry no FNC }
        else
        begin
          Name := PcccCommandName(Hi(R.CF), Lo(R.CF));
          if Name = '' then
            Name := 'CF=$' + IntToHex(R.CF, 4);
        end;
        Result := Format('%s STS=$%.2x TNS=%d', [Name, R.Sts, R.Tns]);
        if Len > 8 then
          Result := Result + ' data: ' + HexBytes(@R.Data[0], Len - 8);
      end;
  else
    Result := '?';
  end;
end;

{ Send once the transmitter is free (bounded wait). }
function SendNow(Chn: pChnVirt; constref R: tSendRecord; Len: Word): tChResult;
begin
  Result := ChSendWhenFree(Chn, @R, Len, DF1LinkTimeoutMs);
end;

{- ------------------------------------------------------------- station }

function DF1StationInit(var S: tDF1Station; Chn: pChnVirt; Handler: tDF1Handler;
  Data: Pointer): tChResult;
begin
  FillChar(S, SizeOf(S), 0);
  S.LastLink.MessType := tpAckNak;
  S.LastLink.FlAck := False;    { ENQ before anything: NAK }
  if not IsDF1Channel(Chn) then
    Exit(res_WrongLayer);       { S.Chn stays nil: the station reads nothing }
  S.Chn := Chn;
  S.Handler := Handler;
  S.Data := Data;
  S.FullDup := pChnDF1(Chn)^.ChDF1Config.FullDup;
  S.DupSeen := pChnDF1(Chn)^.ChDupCount;
  Chn^.ChReceiveBuffer(@S.RMess, SizeOf(S.RMess));
  Result := res_Ok;
end;

procedure Say(var S: tDF1Station; const Line: AnsiString);
begin
  if Assigned(S.Log) then
    S.Log(Line);
end;

procedure Count(var S: tDF1Station; Event: tDF1LinkEvent);
begin
  if Assigned(S.OnEvent) then
    S.OnEvent(S.Data, Event);
end;

procedure StationSend(var S: tDF1Station; constref R: tSendRecord; Len: Word);
var
  Res: tChResult;
begin
  Res := SendNow(S.Chn, R, Len);
  if Res = res_Ok then
  begin
    Count(S, leFrameOut);
    if Assigned(S.Log) then
      S.Log(SentLine(S.Chn, R, Len, S.LogWire));
  end
  else
    Say(S, '-> send failed: ' + S.Chn^.ChResultStr(Res));
end;

{ A data message to Dst (DST of the frame; ChDestNode, then DNO= again). }
procedure StationSendTo(var S: tDF1Station; Dst: Byte; constref R: tSendRecord; Len: Word);
var
  Was: tNode;
begin
  Was := S.Chn^.CH_DNode;
  S.Chn^.ChDestNode(Dst);
  StationSend(S, R, Len);
  S.Chn^.ChDestNode(Was);
end;

procedure SendLink(var S: tDF1Station; Ack: Boolean);
begin
  FillChar(S.LastLink, SizeOf(S.LastLink), 0);
  S.LastLink.MessType := tpAckNak;
  S.LastLink.FlAck := Ack;
  StationSend(S, S.LastLink, 2);
end;

{ DUP=ON: the layer ACKed a repeated command and kept it from us. If it
  repeats the command our cached reply answers, that reply goes again. }
procedure AnswerRepeats(var S: tDF1Station);
var
  D: pChnDF1;
  I: LongInt;
begin
  D := pChnDF1(S.Chn);
  if D^.CH_DupCount = S.DupSeen then
    Exit;
  S.DupSeen := D^.CH_DupCount;
  Count(S, leDupIn);
  Say(S, '<- repeated command TNS=' + IntToStr(D^.CH_DupTns) + ' (ACKed by the layer)');
  for I := 0 to DF1ReplyCacheSize - 1 do
    with S.Cache[I] do
      if Used and (Src = D^.CH_DupSrc) and (Tns = D^.CH_DupTns) then
      begin
        Inc(S.Repeats);
        S.Reply := Rep;
        S.ReplyLen := Len;
        S.HasReply := True;
        S.AwaitAck := False;
        if S.FullDup then
          StationSend(S, S.Reply, S.ReplyLen);   { half duplex: at the next poll }
        Exit;
      end;
end;

{ Keep the reply to a command from Src: in the slot of that source, else
  in the slot used longest ago (a real master, asking all the time, keeps
  its slot against frames damaged into other sources). }
procedure CacheReply(var S: tDF1Station; Src: Byte);
var
  I, Slot: LongInt;
begin
  Slot := -1;
  for I := 0 to DF1ReplyCacheSize - 1 do
    if S.Cache[I].Used and (S.Cache[I].Src = Src) then
      Slot := I;
  if Slot < 0 then
  begin
    Slot := 0;
    for I := 0 to DF1ReplyCacheSize - 1 do
    begin
      if not S.Cache[I].Used then
      begin
        Slot := I;
        Break;
      end;
      if S.Cache[I].Stamp < S.Cache[Slot].Stamp then
        Slot := I;
    end;
  end;
  S.Cache[Slot].Stamp := S.Requests;
  S.Cache[Slot].Used := True;
  S.Cache[Slot].Src := Src;
  S.Cache[Slot].Tns := S.Reply.Tns;
  S.Cache[Slot].Len := S.ReplyLen;
  S.Cache[Slot].Rep := S.Reply;
end;

{ The master's ACK or NAK: of our reply or our own message. }
procedure TakeAckNak(var S: tDF1Station);
begin
  if not S.RMess.FlAck then
    Count(S, leNakIn);
  if S.HasReply and (S.FullDup or S.AwaitAck) then
    if S.RMess.FlAck then
      S.HasReply := False            { the master has the reply }
    else if S.FullDup then
      StationSendTo(S, S.ReplyDst, S.Reply, S.ReplyLen);
  if S.OwnAwait and S.RMess.FlAck then
  begin
    S.HasOwn := False;               { the master has our message }
    Inc(S.OwnSent);
  end;
  { half duplex NAK: the reply (or our message) waits for the next poll }
  S.AwaitAck := False;
  S.OwnAwait := False;
end;

{ Half duplex: the master's poll gets the reply, else our own message,
  else EOT. }
procedure AnswerPoll(var S: tDF1Station);
var
  Eot: tSendRecord;
begin
  if S.HasReply then
  begin
    StationSendTo(S, S.ReplyDst, S.Reply, S.ReplyLen);
    S.AwaitAck := True;
    S.OwnAwait := False;
  end
  else if S.HasOwn then
  begin
    StationSendTo(S, S.OwnDst, S.Own, S.OwnLen);
    S.OwnAwait := True;
  end
  else
  begin
    FillChar(Eot, SizeOf(Eot), 0);
    Eot.MessType := tpNoPollRep;
    StationSend(S, Eot, 1);
  end;
end;

{ A message of Len octets: ACKed; the reply to one of our own kept, a
  command handed to Handler and its reply kept and sent (full duplex). }
procedure TakeMessage(var S: tDF1Station; Len: Word);
begin
  Count(S, leFrameIn);
  SendLink(S, True);
  if S.RMess.CF and MskCF_Reply <> 0 then
  begin
    { the answer to a message of our own, not a command }
    Inc(S.OwnReplies);
    S.LastReply := S.RMess;
    S.LastReplyLen := Len;
    S.LastReplySrc := Byte(S.Chn^.CH_RSNode);
    Exit;
  end;
  { half duplex (a multidrop line): the reply goes to the command's
    SRC, which is another slave when the master routed it; full
    duplex keeps DNO= (point to point) }
  if S.FullDup then
    S.ReplyDst := Byte(S.Chn^.CH_DNode)
  else
    S.ReplyDst := Byte(S.Chn^.CH_RSNode);
  if Assigned(S.Handler) and S.Handler(S.Data, S.RMess, Len, S.Reply, S.ReplyLen) then
  begin
    Inc(S.Requests);
    CacheReply(S, Byte(S.Chn^.CH_RSNode));
    S.HasReply := True;
    S.AwaitAck := False;
    if S.FullDup then
      StationSendTo(S, S.ReplyDst, S.Reply, S.ReplyLen);
  end;
end;

function DF1StationStep(var S: tDF1Station): Boolean;
var
  Len: Word;
  R: tChResult;
  Ready: Boolean;
begin
  Result := False;
  if S.Chn = nil then
    Exit;
  Ready := S.Chn^.ChReceiveReady = CHS_ReceiveReady;
  AnswerRepeats(S);
  if not Ready then
    Exit;
  Result := True;
  Inc(S.Messages);
  Len := 0;
  S.Chn^.ChReceive(Len);
  R := S.Chn^.ChReceiveResult;
  if R <> res_Ok then
  begin
    Say(S, '<- broken frame: ' + S.Chn^.ChResultStr(R));
    if S.FullDup then
    begin
      Count(S, leNakOut);
      SendLink(S, False);
    end;
    Exit;
  end;
  Say(S, '<- ' + DF1Describe(S.RMess, Len));
  case S.RMess.MessType of
    tpAckNak:
      TakeAckNak(S);
    tpEnq:
      begin
        Count(S, leEnqIn);
        StationSend(S, S.LastLink, 2);
      end;
    tpPoll:
      AnswerPoll(S);
    tpDataMess:
      TakeMessage(S, Len);
  end;
end;

function DF1StationQueue(var S: tDF1Station; Dst: Byte; constref Msg: tSendRecord;
  Len: Word): tChResult;
begin
  if S.Chn = nil then
    Exit(res_WrongLayer);
  if S.HasOwn then
    Exit(res_Busy);
  S.Own := Msg;
  S.OwnLen := Len;
  S.OwnDst := Dst;
  S.HasOwn := True;
  S.OwnAwait := False;
  Result := res_Ok;
end;

{- -------------------------------------------------------------- master }

procedure MasterSay(var M: tDF1Master; const Line: AnsiString);
begin
  if Assigned(M.Log) then
    M.Log(Line);
end;

procedure MasterFinish(var M: tDF1Master; R: tChResult);
begin
  M.Result := R;
  M.State := dmDone;
  M.Chn^.ChReceiveBuffer(M.OldBuf, M.OldSize);
end;

function MasterSend(var M: tDF1Master; constref R: tSendRecord; Len: Word): Boolean;
var
  Res: tChResult;
begin
  Res := SendNow(M.Chn, R, Len);
  Result := Res = res_Ok;
  if not Result then
  begin
    MasterSay(M, '-> send failed: ' + M.Chn^.ChResultStr(Res));
    MasterFinish(M, Res);
  end
  else if Assigned(M.Log) then
    M.Log(SentLine(M.Chn, R, Len, M.LogWire));
end;

function MasterLink(var M: tDF1Master; T: tMessType; Ack: Boolean): Boolean;
var
  Link: tSendRecord;
  Len: Word;
begin
  FillChar(Link, SizeOf(Link), 0);
  Link.MessType := T;
  Len := 1;
  if T = tpAckNak then
  begin
    Link.FlAck := Ack;
    Len := 2;
    M.LastAck := Ack;           { what a peer's ENQ gets again }
  end;
  Result := MasterSend(M, Link, Len);
end;

{ Out of time or tries: res_BadMessage when only other replies came. }
procedure MasterGiveUp(var M: tDF1Master);
begin
  if M.Stale > 0 then
    MasterFinish(M, res_BadMessage)
  else
    MasterFinish(M, res_Timeout);
end;

{ (Re)send the command: the next try, or a timeout after the last. }
procedure MasterTry(var M: tDF1Master);
begin
  if M.Tries >= DF1LinkTries then
  begin
    MasterSay(M, '-- no ACK after ' + IntToStr(M.Tries) + ' tries');
    MasterGiveUp(M);
    Exit;
  end;
  Inc(M.Tries);
  M.EnqSent := False;
  M.State := dmWaitAck;
  M.Until_ := ChMsTick + QWord(M.TimeoutMs);
  MasterSend(M, M.Req, M.ReqLen);
end;

{ Half duplex: ask the slave for the reply. }
procedure MasterPoll(var M: tDF1Master);
begin
  M.Until_ := ChMsTick + QWord(M.TimeoutMs);
  MasterLink(M, tpPoll, False);
end;

procedure MasterAcked(var M: tDF1Master);
begin
  M.Acked := True;
  M.State := dmWaitReply;
  M.Deadline := ChMsTick + QWord(3 * M.TimeoutMs);
  if M.FullDup then
    M.Until_ := ChMsTick + QWord(M.TimeoutMs)
  else
    MasterPoll(M);     { half duplex: the slave speaks when polled }
end;

{ A reply is in M.Rep: ACK it. The one to this command ends the exchange;
  another (a late copy of an earlier reply: the slave sent it again after a
  repeated command or a NAK) is ignored, and the wait goes on. }
procedure MasterReply(var M: tDF1Master);
var
  Ours: Boolean;
begin
  Ours := (M.Rep.CF and $FF00 = (M.Req.CF and $FF00) or MskCF_Reply) and (M.Rep.Tns = M.Req.Tns);
  if Ours then
    M.Acked := True;            { a late reply to another command is no ACK of ours }
  if not MasterLink(M, tpAckNak, True) then
    Exit;
  if not Ours then
  begin
    MasterSay(M, '-- the reply is not the one to this command: ignored');
    Inc(M.Stale);
  end
  else
    MasterFinish(M, res_Ok);
end;


function DF1MasterStart(var M: tDF1Master; Chn: pChnVirt; constref Req: tSendRecord;
  ReqLen: Word; TimeoutMs: LongInt; Log: tDF1LogProc; LogWire: Boolean): Boolean;
begin
  FillChar(M, SizeOf(M), 0);
  M.State := dmDone;
  M.Log := Log;
  M.LogWire := LogWire;
  if not IsDF1Channel(Chn) then
  begin
    M.Result := res_WrongLayer;
    Exit(False);
  end;
  M.Chn := Chn;
  M.Req := Req;
  M.ReqLen := ReqLen;
  M.TimeoutMs := TimeoutMs;
  M.FullDup := pChnDF1(Chn)^.ChDF1Config.FullDup;
  { the caller's receive buffer comes back at the end: M.Rep is often a
    local of the caller, the channel must not keep pointing at it }
  Chn^.ChGetReceiveBuffer(M.OldBuf, M.OldSize);
  Chn^.ChReceiveBuffer(@M.Rep, SizeOf(M.Rep));
  MasterTry(M);
  Result := M.State <> dmDone;
end;

procedure DF1MasterCancel(var M: tDF1Master);
begin
  if M.State <> dmDone then
  begin
    MasterSay(M, '-- cancelled');
    MasterFinish(M, res_Timeout);
  end;
end;

{ One message from the channel is in M.Rep (Got: good): act on it. }
procedure MasterTake(var M: tDF1Master; Got: Boolean);
begin
  if Got and (M.Rep.MessType = tpDataMess) then
    MasterReply(M)                     { in dmWaitAck: the reply overtook the ACK }
  else if Got and (M.Rep.MessType = tpEnq) then
  begin
    Inc(M.EnqsIn);                     { the peer missed our ACK/NAK: again }
    MasterLink(M, tpAckNak, M.LastAck);
  end
  else if not Got and (M.State = dmWaitReply) and M.FullDup then
  begin
    Inc(M.NaksOut);                    { a broken reply: ask for it again }
    MasterLink(M, tpAckNak, False);
  end
  else if M.State = dmWaitAck then
  begin
    if Got and (M.Rep.MessType = tpAckNak) and M.Rep.FlAck then
      MasterAcked(M)
    else if Got and (M.Rep.MessType = tpAckNak) then
    begin
      Inc(M.Naks);
      MasterTry(M);                    { NAK: the next try }
    end
    else
      Inc(M.Ignored);                  { noise, EOT ...: no try is used up; the
                                         timeout (ENQ, then again) still runs }
  end
  else if not M.FullDup then
    MasterPoll(M);                     { half duplex: EOT, a stray ACK ... }
end;

{ Nothing (more) received: the line and the timers. }
procedure MasterTimers(var M: tDF1Master);
begin
  if M.Chn^.ChResult <> res_Ok then
  begin
    MasterSay(M, '-- line lost: ' + M.Chn^.ChResultStr(M.Chn^.ChResult));
    MasterFinish(M, M.Chn^.ChResult);  { no answer can come any more }
  end
  else if (M.State = dmWaitReply) and (ChMsTick > M.Deadline) then
  begin
    MasterSay(M, '-- no reply');
    MasterGiveUp(M);
  end
  else if ChMsTick > M.Until_ then
    if M.State = dmWaitAck then
    begin
      if M.FullDup and not M.EnqSent then
      begin
        M.EnqSent := True;             { full duplex: ask for the lost ACK }
        M.Until_ := ChMsTick + QWord(M.TimeoutMs);
        MasterLink(M, tpEnq, False);
      end
      else
        MasterTry(M);
    end
    else if M.FullDup then
      M.Until_ := ChMsTick + QWord(M.TimeoutMs)
    else
      MasterPoll(M);
end;

function DF1MasterStep(var M: tDF1Master): Boolean;
var
  Got: Boolean;
  N: LongInt;
begin
  { everything already received, in one step: the ACK and the reply often
    come in one chunk, and the program's wait would not wake for the
    second. After the first look only while the channel holds input it
    has pulled in: a look may wait IDL ms for new input }
  N := 0;
  while (M.State <> dmDone) and (N < DF1MaxFramesPerStep) and
        ((N = 0) or M.Chn^.ChHoldsInput) and (M.Chn^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(N);
    M.RepLen := 0;
    M.Chn^.ChReceive(M.RepLen);
    Got := M.Chn^.ChReceiveResult = res_Ok;
    if Got then
      MasterSay(M, '<- ' + DF1Describe(M.Rep, M.RepLen))
    else
      MasterSay(M, '<- broken frame: ' + M.Chn^.ChResultStr(M.Chn^.ChReceiveResult));
    MasterTake(M, Got);
  end;
  if M.State <> dmDone then
    MasterTimers(M);                   { also on a line that never stops babbling }
  Result := M.State = dmDone;
end;

{ When what M waits for now runs out (the next timer). }
function DF1MasterWaitEnd(const M: tDF1Master): QWord;
begin
  Result := M.Until_;
  if (M.State = dmWaitReply) and (M.Deadline < Result) then
    Result := M.Deadline;
  Inc(Result);                         { the timers fire after it }
end;

function DF1Transact(Chn: pChnVirt; constref Req: tSendRecord; ReqLen: Word;
  var Rep: tRecRecord; var RepLen: Word; Idle: tDF1Idle; IdleData: Pointer;
  TimeoutMs: LongInt; Log: tDF1LogProc; LogWire: Boolean): tChResult;
var
  M: tDF1Master;
begin
  if not IsDF1Channel(Chn) then
    Exit(res_WrongLayer);
  if DF1MasterStart(M, Chn, Req, ReqLen, TimeoutMs, Log, LogWire) then
    repeat
      if Assigned(Idle) then
        Idle(IdleData)
      else
        ChnWaitUntil(DF1MasterWaitEnd(M));  { the program-wide wait, to the next timer }
    until DF1MasterStep(M);
  Rep := M.Rep;
  RepLen := M.RepLen;
  Result := M.Result;
end;

initialization
  DF1NumName := ChNumName(ChnDF1.cName);
end.
