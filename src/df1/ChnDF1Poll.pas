{ ChnDF1Poll - a DF1 half-duplex master for a multidrop line (radio
  modems, RS-485): one channel, many slave stations, as Allen-Bradley's
  half-duplex master does it (Rockwell 1770-6.5.16 chapter 5; the
  MicroLogix/SLC channel configuration "DF1 Half-Duplex Master").

  On the wire (BCC = two's complement of the byte sum; the poll's BCC is
  that of STN alone, also with CRC=ON):
    poll           DLE ENQ STN BCC         the slave answers with one of
    nothing to say DLE EOT                  ... or
    slave message  DLE STX DST SRC CMD STS TNS ... DLE ETX BCC/CRC, ACKed
                   by the master with DLE ACK
    master message DLE SOH STN DLE STX DST SRC ... DLE ETX BCC/CRC, ACKed
                   by the slave with DLE ACK (NAK or nothing: sent again)

  The poll list has priority and normal stations. Each poll cycle polls
  every priority station, then the next NormalGroup of the normal ones
  (rotating), as AB's "priority and normal poll ranges" with a "normal
  poll group size". Modes:
    dpStandard  every station of the cycle is polled; with MultiPerScan a
                station that sends a message is polled again at once,
                until it says EOT (at most DF1PollMaxPerTurn messages), else
                once per cycle;
    dpMessage   a station is polled only while a reply to one of the
                master's commands is due from it (message-based polling:
                the line is quiet otherwise).
  The master's own commands (DF1PollSend) go out between two polls, first
  in first out; their station is polled for the reply at once (in both
  modes). A message a slave sends on its own (an SLC's MSG instruction)
  is ACKed; when its DST is the master's own address (NOD= of the DF1
  stack) it is for the program (DF1PollReceive, with its SRC); when it is
  another station of the list, the master sends it on to that station
  with the SRC of the sender (slave-to-slave routing), and that station's
  answer comes back the same way. A station that does not answer
  DeadAfter polls or messages in a row is dead: it is polled only once
  every DeadEvery cycles, and a command to it gets one try, so it slows
  the others by one poll timeout per DeadEvery cycles; its first answer
  makes it alive again. Each station counts what it did (tDF1PollStation).

  Stepped, never waiting except to hand a frame to a busy transmitter
  (ChSendWhenFree): the program calls DF1PollStep from its loop and waits
  in the program-wide wait until DF1PollWaitEnd (ChnWaitUntil).
  DF1PollRun does that until a command's reply is in, for blocking use;
  unit ChnPcccClient's requests go through a poller with PcccClientPoller. }
unit ChnDF1Poll;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnDF1, ChnDF1Link;

const
  DF1PollMaxStations = 64;
  DF1PollMaxJobs     = 16;
  DF1PollInboxSize   = 16;
  DF1PollMaxPerTurn  = 8;      {< messages one station may send in one turn }

type
  tDF1PollMode = (dpStandard, dpMessage);

  pDF1PollStation = ^tDF1PollStation;
  tDF1PollStation = record
    Addr     : Byte;
    Priority : Boolean;
    Dead     : Boolean;
    Misses   : LongInt;      {< polls or messages unanswered in a row }
    SkipLeft : LongInt;      {< dead: cycles left until it is polled again }
    { counters }
    Polls, Eots, MsgsIn, MsgsOut, Naks, Timeouts, Routed, Deaths: LongWord;
  end;

  tDF1PollJobState = (pjFree, pjQueued, pjWaitAck, pjWaitReply, pjDone);
  tDF1PollJob = record
    State   : tDF1PollJobState;
    Own     : Boolean;       {< the program's: kept until DF1PollResult }
    Src, Dst: Byte;          {< Src: the master, or the slave it came from }
    Req     : tSendRecord;
    ReqLen  : Word;
    Rep     : tRecRecord;
    RepLen  : Word;
    Result  : tChResult;
    Tries   : LongInt;
    Deadline: QWord;         {< the reply's }
  end;

  tDF1PollMsg = record
    Src, Dst: Byte;
    Msg     : tRecRecord;
    Len     : Word;
  end;

  tDF1PollState = (psIdle, psWaitAck, psWaitPoll);

  pDF1Poller = ^tDF1Poller;
  tDF1Poller = record
    Chn         : pChnVirt;
    Node        : Byte;          {< the master's own address (NOD=) }
    Mode        : tDF1PollMode;
    MultiPerScan: Boolean;       {< standard: poll a talking station again }
    NormalGroup : LongInt;       {< normal stations per cycle, default 1 }
    AckMs       : LongInt;       {< ACK of a master message (default 1000) }
    PollMs      : LongInt;       {< answer to a poll (default 1000) }
    ReplyMs     : LongInt;       {< a command's reply (default 3000) }
    DeadAfter   : LongInt;       {< misses in a row that make a station dead (3) }
    DeadEvery   : LongInt;       {< a dead station is polled every so many cycles (10) }
    Stations    : array[0..DF1PollMaxStations - 1] of tDF1PollStation;
    Count       : LongInt;
    Jobs        : array[0..DF1PollMaxJobs - 1] of tDF1PollJob;
    Inbox       : array[0..DF1PollInboxSize - 1] of tDF1PollMsg;
    InHead, InCount: LongInt;
    InLost      : LongWord;      {< messages for the program lost: inbox full }
    Cycles      : LongWord;      {< poll cycles begun }
    { the cycle under way: station indexes }
    Seq         : array[0..DF1PollMaxStations - 1] of LongInt;
    SeqLen, SeqPos, NextNormal: LongInt;
    State       : tDF1PollState;
    Cur         : LongInt;       {< station polled or sent to }
    CurJob      : LongInt;       {< job waiting for its ACK }
    Turn        : LongInt;       {< messages the current station sent this turn }
    Until_      : QWord;
    RMess       : tRecRecord;
    Log         : tDF1LogProc;
  end;

{ Set P up on Chn, a DF1 stack with FHD=HALF MAS=MASTER; res_WrongLayer
  (nothing set up) otherwise. Mode standard, one normal station per
  cycle, the timeouts above. }
function DF1PollInit(var P: tDF1Poller; Chn: pChnVirt): tChResult;
{ Put station Addr on the poll list (res_BadParam: already there, the
  master's own address, or the list full). }
function DF1PollAdd(var P: tDF1Poller; Addr: Byte; Priority: Boolean): tChResult;
{ The station record of Addr, nil when it is not on the list. }
function DF1PollStationOf(var P: tDF1Poller; Addr: Byte): pDF1PollStation;
{ Queue a message of the program to station Dst; Job names it for
  DF1PollResult. A command waits for its reply; a reply (CF with
  MskCF_Reply: the answer to a slave's message) only for its ACK.
  res_Busy when DF1PollMaxJobs are under way. }
function DF1PollSend(var P: tDF1Poller; Dst: Byte; constref Req: tSendRecord;
  ReqLen: Word; out Job: LongInt): tChResult;
{ True when Job is over: Res is res_Ok (Rep/RepLen the reply; for a reply
  sent, nothing), res_Timeout (no ACK after the tries, or no reply in
  ReplyMs) or the channel's fault; the job's slot is free again. }
function DF1PollResult(var P: tDF1Poller; Job: LongInt; var Rep: tRecRecord;
  var RepLen: Word; out Res: tChResult): Boolean;
{ Forget Job (the program no longer waits for it). }
procedure DF1PollCancel(var P: tDF1Poller; Job: LongInt);
{ The next message a slave sent to the master on its own, with its SRC. }
function DF1PollReceive(var P: tDF1Poller; out M: tDF1PollMsg): Boolean;
{ Take what the line brought, run the timers, start the next poll or
  message; True when anything happened. Never waits for an answer. }
function DF1PollStep(var P: tDF1Poller): Boolean;
{ When the poller's current wait runs out (ChMsTick): ChnWaitUntil it
  between steps. }
function DF1PollWaitEnd(const P: tDF1Poller): QWord;
{ Step (waiting in the program-wide wait) until Job is over; its result.
  For programs that do one thing at a time. }
function DF1PollRun(var P: tDF1Poller; Job: LongInt; var Rep: tRecRecord;
  var RepLen: Word): tChResult;

implementation

uses
  SysUtils, uString, ChnWait;

function DF1PollInit(var P: tDF1Poller; Chn: pChnVirt): tChResult;
var
  N: LongInt;
begin
  FillChar(P, SizeOf(P), 0);
  P.Cur := -1;
  P.CurJob := -1;
  if not IsDF1Channel(Chn) or (Chn^.ChGetParam('FHD') <> 'FHD=HALF') or
    (Chn^.ChGetParam('MAS') <> 'MAS=MASTER') then
    Exit(res_WrongLayer);
  P.Chn := Chn;
  N := 0;
  StrToNum(ParamValue(Chn^.ChGetParam('NOD')), 0, 255, N);
  P.Node := N;
  P.Mode := dpStandard;
  P.MultiPerScan := True;
  P.NormalGroup := 1;
  P.AckMs := DF1LinkTimeoutMs;
  P.PollMs := DF1LinkTimeoutMs;
  P.ReplyMs := 3 * DF1LinkTimeoutMs;
  P.DeadAfter := 3;
  P.DeadEvery := 10;
  Chn^.ChReceiveBuffer(@P.RMess, SizeOf(P.RMess));
  Result := res_Ok;
end;

function DF1PollStationOf(var P: tDF1Poller; Addr: Byte): pDF1PollStation;
var
  I: LongInt;
begin
  for I := 0 to P.Count - 1 do
    if P.Stations[I].Addr = Addr then
      Exit(@P.Stations[I]);
  Result := nil;
end;

function IndexOf(const P: tDF1Poller; Addr: Byte): LongInt;
begin
  for Result := 0 to P.Count - 1 do
    if P.Stations[Result].Addr = Addr then
      Exit;
  Result := -1;
end;

function DF1PollAdd(var P: tDF1Poller; Addr: Byte; Priority: Boolean): tChResult;
begin
  if (P.Chn = nil) or (P.Count >= DF1PollMaxStations) or (Addr = P.Node) or
    (Addr = 255) or (IndexOf(P, Addr) >= 0) then
    Exit(res_BadParam);
  FillChar(P.Stations[P.Count], SizeOf(tDF1PollStation), 0);
  P.Stations[P.Count].Addr := Addr;
  P.Stations[P.Count].Priority := Priority;
  Inc(P.Count);
  Result := res_Ok;
end;

procedure Say(var P: tDF1Poller; const Line: AnsiString);
begin
  if Assigned(P.Log) then
    P.Log(Line);
end;

function NewJob(var P: tDF1Poller): LongInt;
begin
  for Result := 0 to DF1PollMaxJobs - 1 do
    if P.Jobs[Result].State = pjFree then
      Exit;
  Result := -1;
end;

{ Queue Req for Dst with SRC Src (the master's own, or routed); the job's
  index, -1 when every slot is taken. }
function Queue(var P: tDF1Poller; Src, Dst: Byte; constref Req: tSendRecord;
  ReqLen: Word; Own: Boolean): LongInt;
var
  J: LongInt;
begin
  J := NewJob(P);
  Result := J;
  if J < 0 then
    Exit;
  FillChar(P.Jobs[J], SizeOf(tDF1PollJob), 0);
  P.Jobs[J].State := pjQueued;
  P.Jobs[J].Own := Own;
  P.Jobs[J].Src := Src;
  P.Jobs[J].Dst := Dst;
  P.Jobs[J].Req := Req;
  P.Jobs[J].ReqLen := ReqLen;
  P.Jobs[J].Result := res_Ok;
end;

function IsReply(constref R: tSendRecord): Boolean;
begin
  Result := R.CF and MskCF_Reply <> 0;
end;

function DF1PollSend(var P: tDF1Poller; Dst: Byte; constref Req: tSendRecord;
  ReqLen: Word; out Job: LongInt): tChResult;
begin
  Job := -1;
  if P.Chn = nil then
    Exit(res_WrongLayer);
  if (Req.MessType <> tpDataMess) or (ReqLen < 8) or (ReqLen > SizeOf(tSendRecord)) then
    Exit(res_BadLen);
  Job := Queue(P, P.Node, Dst, Req, ReqLen, True);
  if Job < 0 then
    Exit(res_Busy);
  Result := res_Ok;
end;

function DF1PollResult(var P: tDF1Poller; Job: LongInt; var Rep: tRecRecord;
  var RepLen: Word; out Res: tChResult): Boolean;
begin
  Res := res_Ok;
  Result := (Job >= 0) and (Job < DF1PollMaxJobs) and (P.Jobs[Job].State = pjDone);
  if not Result then
    Exit;
  Res := P.Jobs[Job].Result;
  Rep := P.Jobs[Job].Rep;
  RepLen := P.Jobs[Job].RepLen;
  P.Jobs[Job].State := pjFree;
end;

procedure DF1PollCancel(var P: tDF1Poller; Job: LongInt);
begin
  if (Job >= 0) and (Job < DF1PollMaxJobs) and (P.Jobs[Job].State <> pjFree) then
  begin
    if P.CurJob = Job then
      P.CurJob := -1;            { its ACK, if it comes, ends nothing }
    P.Jobs[Job].State := pjFree;
  end;
end;

function DF1PollReceive(var P: tDF1Poller; out M: tDF1PollMsg): Boolean;
begin
  Result := P.InCount > 0;
  if not Result then
    Exit;
  M := P.Inbox[P.InHead];
  P.InHead := (P.InHead + 1) mod DF1PollInboxSize;
  Dec(P.InCount);
end;

{ A job is over: the program's stays until DF1PollResult, a routed one
  is forgotten. }
procedure JobDone(var P: tDF1Poller; J: LongInt; R: tChResult);
begin
  P.Jobs[J].Result := R;
  if P.Jobs[J].Own then
    P.Jobs[J].State := pjDone
  else
    P.Jobs[J].State := pjFree;
  if P.CurJob = J then
    P.CurJob := -1;
end;

{ Station I answered: alive. }
procedure Alive(var P: tDF1Poller; I: LongInt);
begin
  if I < 0 then
    Exit;
  with P.Stations[I] do
  begin
    if Dead then
      Say(P, Format('-- station %d answers again', [Addr]));
    Dead := False;
    Misses := 0;
  end;
end;

{ Station I did not answer. }
procedure Missed(var P: tDF1Poller; I: LongInt);
begin
  if I < 0 then
    Exit;
  with P.Stations[I] do
  begin
    Inc(Timeouts);
    Inc(Misses);
    if not Dead and (Misses >= P.DeadAfter) then
    begin
      Dead := True;
      Inc(Deaths);
      SkipLeft := P.DeadEvery;
      Say(P, Format('-- station %d dead after %d misses: polled every %d cycles',
        [Addr, Misses, P.DeadEvery]));
    end;
  end;
end;

{ Hand R to the line for station Dst with SRC Src (ChDestNode, and NOD=
  for a routed message: the layer's own methods). False on a send error
  (the channel's result then tells). }
function Put(var P: tDF1Poller; Src, Dst: Byte; constref R: tSendRecord; Len: Word): Boolean;
var
  Res: tChResult;
begin
  P.Chn^.ChDestNode(Dst);
  if Src <> P.Node then
    P.Chn^.ChSetParam('NOD=' + IntToStr(Src));
  Res := ChSendWhenFree(P.Chn, @R, Len, DF1LinkTimeoutMs);
  if Src <> P.Node then
    P.Chn^.ChSetParam('NOD=' + IntToStr(P.Node));
  Result := Res = res_Ok;
  if Result then
  begin
    if Assigned(P.Log) then
      P.Log(Format('-> %d: %s', [Dst, DF1Describe(R, Len)]))
  end
  else
    Say(P, '-> send failed: ' + P.Chn^.ChResultStr(Res));
end;

function Link(var P: tDF1Poller; Dst: Byte; T: tMessType; Ack: Boolean): Boolean;
var
  R: tSendRecord;
  Len: Word;
begin
  FillChar(R, 8, 0);
  R.MessType := T;
  R.FlAck := Ack;
  Len := 1;
  if T = tpAckNak then
    Len := 2;
  Result := Put(P, P.Node, Dst, R, Len);
end;

procedure Poll(var P: tDF1Poller; I: LongInt);
begin
  P.Cur := I;
  P.State := psWaitPoll;
  P.Until_ := ChMsTick + QWord(P.PollMs);
  Inc(P.Stations[I].Polls);
  Link(P, P.Stations[I].Addr, tpPoll, False);
end;

{ Send job J (its next try). }
procedure SendJob(var P: tDF1Poller; J: LongInt);
begin
  with P.Jobs[J] do
  begin
    Inc(Tries);
    State := pjWaitAck;
  end;
  P.CurJob := J;
  P.Cur := IndexOf(P, P.Jobs[J].Dst);
  P.State := psWaitAck;
  P.Until_ := ChMsTick + QWord(P.AckMs);
  if P.Cur >= 0 then
    Inc(P.Stations[P.Cur].MsgsOut);
  if not Put(P, P.Jobs[J].Src, P.Jobs[J].Dst, P.Jobs[J].Req, P.Jobs[J].ReqLen) then
  begin
    P.State := psIdle;
    JobDone(P, J, P.Chn^.ChResult);
  end;
end;

{ The tries a message to station I gets: one when it is dead. }
function TriesFor(const P: tDF1Poller; I: LongInt): LongInt;
begin
  if (I >= 0) and P.Stations[I].Dead then
    Result := 1
  else
    Result := DF1LinkTries;
end;

{ A message from station I (SRC Src, DST Dst) in P.RMess. }
procedure TakeMessage(var P: tDF1Poller; I: LongInt; Len: Word);
var
  Src, Dst: tNode;
  J, K: LongInt;
begin
  Src := 0;
  Dst := 0;
  P.Chn^.ChGetNode(Src, Dst);
  if I >= 0 then
    Inc(P.Stations[I].MsgsIn);
  if Dst = P.Node then
  begin
    if IsReply(P.RMess) then
      for J := 0 to DF1PollMaxJobs - 1 do
        if (P.Jobs[J].State = pjWaitReply) and (P.Jobs[J].Dst = Src) and
          (P.Jobs[J].Req.Tns = P.RMess.Tns) and
          (Hi(P.RMess.CF) = Hi(P.Jobs[J].Req.CF) or $40) then
        begin
          P.Jobs[J].Rep := P.RMess;
          P.Jobs[J].RepLen := Len;
          JobDone(P, J, res_Ok);
          Exit;
        end;
    { a message of the slave's own (or a late reply): for the program }
    if P.InCount >= DF1PollInboxSize then
    begin
      Inc(P.InLost);
      Say(P, '-- inbox full: message from ' + IntToStr(Src) + ' lost');
      Exit;
    end;
    K := (P.InHead + P.InCount) mod DF1PollInboxSize;
    P.Inbox[K].Src := Src;
    P.Inbox[K].Dst := Dst;
    P.Inbox[K].Msg := P.RMess;
    P.Inbox[K].Len := Len;
    Inc(P.InCount);
  end
  else
  begin
    { for another station: on to it, SRC kept (its answer comes back so) }
    J := Queue(P, Src, Dst, P.RMess, Len, False);
    if J < 0 then
      Say(P, Format('-- no room to route %d -> %d', [Src, Dst]))
    else if I >= 0 then
      Inc(P.Stations[I].Routed);
  end;
end;

{ One message off the line (Got: a good one) in P.RMess. }
procedure Take(var P: tDF1Poller; Got: Boolean; Len: Word);
var
  J: LongInt;
begin
  case P.State of
    psWaitAck:
      if Got and (P.RMess.MessType = tpAckNak) then
      begin
        J := P.CurJob;
        P.State := psIdle;
        Alive(P, P.Cur);
        if J < 0 then
          Exit;                        { cancelled meanwhile }
        if P.RMess.FlAck then
        begin
          if P.Jobs[J].Own and not IsReply(P.Jobs[J].Req) then
          begin
            P.Jobs[J].State := pjWaitReply;
            P.Jobs[J].Deadline := ChMsTick + QWord(P.ReplyMs);
            P.CurJob := -1;
          end
          else
            JobDone(P, J, res_Ok);
        end
        else
        begin
          if P.Cur >= 0 then
            Inc(P.Stations[P.Cur].Naks);
          if P.Jobs[J].Tries >= TriesFor(P, P.Cur) then
            JobDone(P, J, res_Timeout)
          else
            P.Jobs[J].State := pjQueued;   { again, before anything else }
        end;
      end;
    psWaitPoll:
      if not Got then
      begin
        { a broken slave message: NAK; the slave sends it again when polled }
        Inc(P.Stations[P.Cur].Naks);
        Link(P, P.Stations[P.Cur].Addr, tpAckNak, False);
        P.State := psIdle;
      end
      else if P.RMess.MessType = tpNoPollRep then
      begin
        Inc(P.Stations[P.Cur].Eots);
        Alive(P, P.Cur);
        P.State := psIdle;
      end
      else if P.RMess.MessType = tpDataMess then
      begin
        Alive(P, P.Cur);
        Link(P, P.Stations[P.Cur].Addr, tpAckNak, True);
        TakeMessage(P, P.Cur, Len);
        Inc(P.Turn);
        if (P.Mode = dpStandard) and P.MultiPerScan and (P.Turn < DF1PollMaxPerTurn) then
          Poll(P, P.Cur)                 { more to say? }
        else
          P.State := psIdle;
      end;
  end;
end;

{ The stations of a new cycle: every priority one, then the next
  NormalGroup normal ones; a dead one only every DeadEvery cycles. }
procedure NewCycle(var P: tDF1Poller);
var
  I, N, Taken, Normals: LongInt;

  function Due(K: LongInt): Boolean;
  begin
    with P.Stations[K] do
    begin
      Result := not Dead or (SkipLeft <= 0);
      if Dead then
        if SkipLeft <= 0 then
          SkipLeft := P.DeadEvery
        else
          Dec(SkipLeft);
    end;
  end;

begin
  Inc(P.Cycles);
  P.SeqLen := 0;
  P.SeqPos := 0;
  Normals := 0;
  for I := 0 to P.Count - 1 do
    if P.Stations[I].Priority then
    begin
      if Due(I) then
      begin
        P.Seq[P.SeqLen] := I;
        Inc(P.SeqLen);
      end;
    end
    else
      Inc(Normals);
  { the next normal stations in turn; a dead one skipped costs no place }
  Taken := 0;
  N := 0;
  while (Taken < P.NormalGroup) and (N < P.Count) and (Normals > 0) do
  begin
    I := P.NextNormal mod P.Count;
    P.NextNormal := (I + 1) mod P.Count;
    Inc(N);
    if P.Stations[I].Priority then
      Continue;
    if Due(I) then
    begin
      P.Seq[P.SeqLen] := I;
      Inc(P.SeqLen);
      Inc(Taken);
    end;
  end;
end;

{ The line is free: the next message, the next poll. }
procedure Next(var P: tDF1Poller);
var
  J, I, Tries: LongInt;
begin
  { a message queued (the program's, a routed one, one to send again) }
  for J := 0 to DF1PollMaxJobs - 1 do
    if P.Jobs[J].State = pjQueued then
    begin
      SendJob(P, J);
      Exit;
    end;
  { a reply due: poll its station }
  for J := 0 to DF1PollMaxJobs - 1 do
    if P.Jobs[J].State = pjWaitReply then
    begin
      I := IndexOf(P, P.Jobs[J].Dst);
      if I >= 0 then
      begin
        P.Turn := 0;
        Poll(P, I);
        Exit;
      end;
    end;
  if (P.Mode <> dpStandard) or (P.Count = 0) then
    Exit;
  Tries := 0;
  while (P.SeqPos >= P.SeqLen) and (Tries < 2) do
  begin
    NewCycle(P);                       { every station may be dead: twice at most }
    Inc(Tries);
  end;
  if P.SeqPos < P.SeqLen then
  begin
    I := P.Seq[P.SeqPos];
    Inc(P.SeqPos);
    P.Turn := 0;
    Poll(P, I);
  end;
end;

procedure Timers(var P: tDF1Poller);
var
  J: LongInt;
  Now: QWord;
begin
  Now := ChMsTick;
  for J := 0 to DF1PollMaxJobs - 1 do
    if (P.Jobs[J].State = pjWaitReply) and (Now > P.Jobs[J].Deadline) then
    begin
      Say(P, Format('-- no reply from %d', [P.Jobs[J].Dst]));
      Missed(P, IndexOf(P, P.Jobs[J].Dst));
      JobDone(P, J, res_Timeout);
    end;
  if (P.State = psIdle) or (Now <= P.Until_) then
    Exit;
  if P.State = psWaitPoll then
  begin
    Say(P, Format('-- no answer to the poll of %d', [P.Stations[P.Cur].Addr]));
    Missed(P, P.Cur);
  end
  else
  begin
    Missed(P, P.Cur);
    J := P.CurJob;
    if J >= 0 then
      if P.Jobs[J].Tries >= TriesFor(P, P.Cur) then
      begin
        Say(P, Format('-- no ACK from %d', [P.Jobs[J].Dst]));
        JobDone(P, J, res_Timeout);
      end
      else
        P.Jobs[J].State := pjQueued;
  end;
  P.State := psIdle;
end;

function DF1PollStep(var P: tDF1Poller): Boolean;
var
  N: LongInt;
  Len: Word;
  Got: Boolean;
begin
  Result := False;
  if P.Chn = nil then
    Exit;
  N := 0;
  while (N < DF1MaxFramesPerStep) and ((N = 0) or P.Chn^.ChHoldsInput) and
    (P.Chn^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(N);
    Result := True;
    Len := 0;
    P.Chn^.ChReceive(Len);
    Got := P.Chn^.ChReceiveResult = res_Ok;
    if Got then
      Say(P, '<- ' + DF1Describe(P.RMess, Len))
    else
      Say(P, '<- broken frame: ' + P.Chn^.ChResultStr(P.Chn^.ChReceiveResult));
    Take(P, Got, Len);
  end;
  Timers(P);
  if P.State = psIdle then
  begin
    Next(P);
    Result := Result or (P.State <> psIdle);
  end;
end;

function DF1PollWaitEnd(const P: tDF1Poller): QWord;
var
  J: LongInt;
begin
  if P.State <> psIdle then
    Result := P.Until_ + 1
  else
    Result := ChMsTick + 1000;         { idle (message-based): until something comes }
  for J := 0 to DF1PollMaxJobs - 1 do
    if (P.Jobs[J].State = pjWaitReply) and (P.Jobs[J].Deadline + 1 < Result) then
      Result := P.Jobs[J].Deadline + 1;
end;

function DF1PollRun(var P: tDF1Poller; Job: LongInt; var Rep: tRecRecord;
  var RepLen: Word): tChResult;
begin
  if (Job < 0) or (Job >= DF1PollMaxJobs) or (P.Jobs[Job].State = pjFree) then
    Exit(res_BadParam);
  while not DF1PollResult(P, Job, Rep, RepLen, Result) do
    if not DF1PollStep(P) then
      ChnWaitUntil(DF1PollWaitEnd(P));
end;

end.
