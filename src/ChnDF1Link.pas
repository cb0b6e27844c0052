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
    counted through an optional callback. The last reply stays cached: on
    a channel with DUP=ON a repeated command (the master missed our ACK or
    the reply) never reaches the handler again, and the master gets the
    cached reply again instead (half duplex: at its next poll).
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
  DF1LinkTimeoutMs = 1000;   { the RACOM note's link timeout }
  DF1LinkTries     = 3;

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

  pDF1Station = ^tDF1Station;
  tDF1Station = record
    Chn      : pChnVirt;
    Handler  : tDF1Handler;
    Data     : Pointer;       { given to Handler and OnEvent }
    OnEvent  : tDF1EventProc; { nil: nothing counted }
    FullDup  : Boolean;
    RMess    : tRecRecord;
    Reply    : tSendRecord;   { the last reply, kept for a repeated command }
    ReplyLen : Word;          { 0: no reply yet }
    HasReply : Boolean;       { a reply not yet ACKed by the master }
    AwaitAck : Boolean;       { half duplex: the reply just went out }
    LastLink : tSendRecord;   { last ACK/NAK sent, repeated on ENQ }
    Requests : LongInt;       { commands answered }
    Messages : LongInt;       { messages taken, good or broken }
    Repeats  : LongInt;       { repeated commands answered from the cache }
    DupSeen  : LongInt;       { the DF1 layer's CH_DupCount already acted on }
    Log      : tDF1LogProc;   { nil: quiet }
    LogWire  : Boolean;       { lines of sent frames end with the wire bytes }
  end;

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
  (a reply with another TNS or command); res_WrongLayer (Chn is not a
  tChnDF1 stack: nothing is sent); a send error of the channel, or
  its ChResult when the line fails (res_DeviceLost ...) while waiting for
  the reply. Idle and Log may be nil; LogWire as in tDF1Station. }
function DF1Transact(Chn: pChnVirt; constref Req: tSendRecord; ReqLen: Word;
  var Rep: tRecRecord; var RepLen: Word; Idle: tDF1Idle; IdleData: Pointer;
  TimeoutMs: LongInt; Log: tDF1LogProc = nil; LogWire: Boolean = False): tChResult;

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
  SysUtils, uString;

function IsDF1Channel(Chn: pChnVirt): Boolean;
begin
  Result := (Chn <> nil) and (Chn^.CH_Type = ChnDF1.cName);
end;

function DF1WireText(Chn: pChnVirt): AnsiString;
begin
  if IsDF1Channel(Chn) then
    Result := HexBytes(pChnDF1(Chn)^.CH_SBuff, pChnDF1(Chn)^.CH_SLen)
  else
    Result := '';
end;

{ Wait until Chn reaches Want, an error result or the deadline. }
function WaitState(Chn: pChnVirt; Want: tChState; Deadline: QWord): Boolean;
begin
  while (Chn^.ChReady <> Want) and (Chn^.ChResult = res_Ok) and (ChMsTick <= Deadline) do
    Sleep(1);
  Result := Chn^.ChReady = Want;
end;

function DF1OpenStack(const Params: AnsiString; TimeoutMs: LongInt; out Err: AnsiString): pChnVirt;
var
  Step: AnsiString;
  R: tChResult;
begin
  Err := '';
  if Length(Params) > High(tParamStr) then
  begin
    Err := 'parameter string longer than ' + IntToStr(High(tParamStr)) + ' characters';
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
  Err := Step + ': ' + Result^.ChResultStr(R);
  if Result^.ChParamError <> '' then
    Err := Err + ' (' + Result^.ChParamError + ')';
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

{ ------------------------------------------------------------- station }

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
  S.FullDup := pChnDF1(Chn)^.CH_FullDup;
  S.DupSeen := pChnDF1(Chn)^.CH_DupCount;
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
begin
  D := pChnDF1(S.Chn);
  if D^.CH_DupCount = S.DupSeen then
    Exit;
  S.DupSeen := D^.CH_DupCount;
  Count(S, leDupIn);
  Say(S, '<- repeated command TNS=' + IntToStr(D^.CH_DupTns) + ' (ACKed by the layer)');
  if (S.ReplyLen = 0) or (S.Reply.Tns <> D^.CH_DupTns) then
    Exit;
  Inc(S.Repeats);
  S.HasReply := True;
  S.AwaitAck := False;
  if S.FullDup then
    StationSend(S, S.Reply, S.ReplyLen);   { half duplex: at the next poll }
end;

function DF1StationStep(var S: tDF1Station): Boolean;
var
  Len: Word;
  R: tChResult;
  Eot: tSendRecord;
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
      begin
        if not S.RMess.FlAck then
          Count(S, leNakIn);
        if S.HasReply and (S.FullDup or S.AwaitAck) then
          if S.RMess.FlAck then
            S.HasReply := False            { the master has the reply }
          else if S.FullDup then
            StationSend(S, S.Reply, S.ReplyLen);
        { half duplex NAK: the reply waits for the next poll }
        S.AwaitAck := False;
      end;
    tpEnq:
      begin
        Count(S, leEnqIn);
        StationSend(S, S.LastLink, 2);
      end;
    tpPoll:
      if S.HasReply then
      begin
        StationSend(S, S.Reply, S.ReplyLen);
        S.AwaitAck := True;
      end
      else
      begin
        FillChar(Eot, SizeOf(Eot), 0);
        Eot.MessType := tpNoPollRep;
        StationSend(S, Eot, 1);
      end;
    tpDataMess:
      begin
        Count(S, leFrameIn);
        SendLink(S, True);
        if Assigned(S.Handler) and S.Handler(S.Data, S.RMess, Len, S.Reply, S.ReplyLen) then
        begin
          Inc(S.Requests);
          S.HasReply := True;
          S.AwaitAck := False;
          if S.FullDup then
            StationSend(S, S.Reply, S.ReplyLen);
        end;
      end;
  end;
end;

{ -------------------------------------------------------------- master }

function Transact(Chn: pChnVirt; constref Req: tSendRecord; ReqLen: Word;
  var Rep: tRecRecord; var RepLen: Word; Idle: tDF1Idle; IdleData: Pointer;
  TimeoutMs: LongInt; Log: tDF1LogProc; LogWire: Boolean): tChResult;
var
  Link: tSendRecord;
  Tries: Integer;
  FullDup, Acked, Got: Boolean;
  Deadline: QWord;

  procedure Say(const Line: AnsiString);
  begin
    if Assigned(Log) then
      Log(Line);
  end;

  function Send(constref R: tSendRecord; Len: Word): tChResult;
  begin
    Result := SendNow(Chn, R, Len);
    if Result <> res_Ok then
      Say('-> send failed: ' + Chn^.ChResultStr(Result))
    else if Assigned(Log) then
      Log(SentLine(Chn, R, Len, LogWire));
  end;

  { wait up to Ms for a message; Got = a good one is in Rep }
  function Next(Ms: LongInt): Boolean;
  var
    Until_: QWord;
  begin
    Got := False;
    Result := False;
    Until_ := ChMsTick + QWord(Ms);
    repeat
      if Assigned(Idle) then
        Idle(IdleData);
      if Chn^.ChReceiveReady = CHS_ReceiveReady then
      begin
        RepLen := 0;
        Chn^.ChReceive(RepLen);
        Got := Chn^.ChReceiveResult = res_Ok;
        if Got then
          Say('<- ' + DF1Describe(Rep, RepLen))
        else
          Say('<- broken frame: ' + Chn^.ChResultStr(Chn^.ChReceiveResult));
        Exit(True);
      end;
      if Chn^.ChResult <> res_Ok then
        Exit;
      if not Assigned(Idle) then
        Sleep(1);
    until ChMsTick > Until_;
  end;

begin
  FullDup := pChnDF1(Chn)^.CH_FullDup;
  Chn^.ChReceiveBuffer(@Rep, SizeOf(Rep));
  FillChar(Link, SizeOf(Link), 0);
  Acked := False;
  Got := False;
  Tries := 0;
  while not Acked and (Tries < DF1LinkTries) do
  begin
    Inc(Tries);
    Result := Send(Req, ReqLen);
    if Result <> res_Ok then
      Exit;
    if not Next(TimeoutMs) and FullDup then
    begin
      Link.MessType := tpEnq;
      Result := Send(Link, 1);
      if Result <> res_Ok then
        Exit;
      Next(TimeoutMs);
    end;
    if Got and (Rep.MessType = tpAckNak) then
      Acked := Rep.FlAck
    else if Got and (Rep.MessType = tpDataMess) then
      Acked := True;               { the reply overtook the ACK }
  end;
  if not Acked then
  begin
    Say('-- no ACK after ' + IntToStr(Tries) + ' tries');
    Exit(res_Timeout);
  end;
  Deadline := ChMsTick + QWord(3 * TimeoutMs);
  while not (Got and (Rep.MessType = tpDataMess)) do
  begin
    if Chn^.ChResult <> res_Ok then
    begin
      Say('-- line lost: ' + Chn^.ChResultStr(Chn^.ChResult));
      Exit(Chn^.ChResult);          { no reply can come any more }
    end;
    if ChMsTick > Deadline then
    begin
      Say('-- no reply');
      Exit(res_Timeout);
    end;
    if FullDup then
      Next(TimeoutMs)
    else
    begin
      Link.MessType := tpPoll;     { half duplex: the slave speaks when polled }
      Result := Send(Link, 1);
      if Result <> res_Ok then
        Exit;
      Next(TimeoutMs);
    end;
  end;
  Link.MessType := tpAckNak;
  Link.FlAck := True;
  Result := Send(Link, 2);
  if Result <> res_Ok then
    Exit;
  if (Rep.CF and $FF00 <> (Req.CF and $FF00) or MskCF_Reply) or (Rep.Tns <> Req.Tns) then
  begin
    Say('-- the reply is not the one to this command');
    Result := res_BadMessage;
  end;
end;

function DF1Transact(Chn: pChnVirt; constref Req: tSendRecord; ReqLen: Word;
  var Rep: tRecRecord; var RepLen: Word; Idle: tDF1Idle; IdleData: Pointer;
  TimeoutMs: LongInt; Log: tDF1LogProc; LogWire: Boolean): tChResult;
var
  OldBuf: Pointer;
  OldSize: Word;
begin
  if not IsDF1Channel(Chn) then
    Exit(res_WrongLayer);
  { Rep is often a local of the caller: the channel must not keep pointing
    at it afterwards, so the caller's own receive buffer comes back }
  OldBuf := Chn^.CH_RBuff;
  OldSize := Chn^.CH_RSize;
  Result := Transact(Chn, Req, ReqLen, Rep, RepLen, Idle, IdleData, TimeoutMs,
    Log, LogWire);
  Chn^.CH_RBuff := OldBuf;
  Chn^.CH_RSize := OldSize;
end;

end.
