{ ChnWait - the program-wide idle wait: one set of wait sources for every
  open physical layer of the process (docs/LAYERS.md, "The shared wait").

  A physical layer (COM on every backend, LOOP, a network layer ...) joins
  the set when it opens, with only what it can be waited on:
    wkDescriptor  a Unix file descriptor that polls readable on input
    wkHandle      a Windows event handle that is signalled on input
    wkSignal      nothing the OS can wait on: the layer (or its peer in
                  another thread) calls ChnWaitSignal when input arrives
  and leaves it when it closes. A poll that finds nothing calls
  ChnWaitIdle(Src, IDL): the wait covers every source of the process and
  ends at the first input on any of them, so a program polling many lines
  round-robin answers each as fast as one line, and idle CPU does not grow
  with the number of lines. ChnWaitAny(TimeoutMs) is the same wait for new
  programs that block instead of polling.

  No spinning on input nobody reads: a source that ended a wait (it
  "fired") is taken out of the OS wait until its owner has looked at the
  device again (ChnWaitServed). Until then the waits of other channels
  return at once, so a round-robin loop reaches the owner without sleeping
  on every idle line before it - but only for a budget of about two polls
  per open source; after that the fired source is ignored until served. A
  channel whose ring already holds input, or that its program never reads,
  thus costs at most one short burst of polls, never a busy loop.

  Threads: the set is guarded by a lock and may be changed and waited on
  from several threads. A wait only wakes; it never reads a channel's
  bytes, which stay where they are until their own channel is polled. A
  thread that took events out of the OS wait while other threads were
  blocked in it wakes them too, so none of them misses its own input.

  OS parts: Linux epoll (a fired descriptor of another channel leaves the
  wait until served: one-shot, put back with one call; the caller's own
  stays in, level-triggered, at no call) plus a pipe for wake-ups;
  Windows WaitForMultipleObjects over the armed handles plus a
  manual-reset event for wake-ups (63 handles per wait: with more, each
  wait takes the caller's own handle and a rotating window of the others).
  Other Unixes: no shared set, ChnWaitIdle answers False at once and the
  layer waits on its own device as before. The OS parts are include files
  (unix/chnwait.inc, win/chnwait.inc) with one contract: every Os* routine
  is called with Lock held and returns with it held; OsWait alone lets it
  go while it blocks (and counts itself in Blocked meanwhile). }
unit ChnWait;

{$I chn.inc}

interface

type
  tChnWaitKind = (wkDescriptor, wkHandle, wkSignal);

  { Called (under the set's lock) when a fired wkHandle source is to be
    armed again: the layer restarts whatever signals its handle (Windows:
    a new overlapped WaitCommEvent). nil: the set only resets the event. }
  tChnWaitRearm = procedure(Data: Pointer);

  pChnWaitSource = ^tChnWaitSource;
  { Opaque to layers: only the procedures below touch it. }
  tChnWaitSource = record
    Used   : Boolean;
    Kind   : tChnWaitKind;
    Os     : PtrInt;          {< descriptor or handle }
    Armed  : Boolean;         {< in the OS wait now }
    InSet  : Boolean;         {< in the OS set, armed or (one-shot, fired) not }
    OneShot: Boolean;         {< the OS takes it out of the wait when it fires }
    Fired  : Boolean;         {< ended a wait; its owner has not looked since }
    Hungry : Boolean;         {< the owner can take input now }
    WantOut: Boolean;         {< the owner waits for room to send }
    Rearm  : tChnWaitRearm;
    RearmData: Pointer;
    Due    : QWord;           {< ChnClockUs at which it fires by itself; 0: never }
    Index  : LongInt;         {< slot in the set }
    Gen    : LongWord;        {< bumped on every reuse of the slot }
  end;

{ Join the set: a physical layer calls this when it opens. Os is the
  descriptor or handle (ignored for wkSignal). Never fails; on a system
  without a shared set the source is still returned, and ChnWaitIdle then
  answers False so the layer waits on its own. }
function  ChnWaitJoin(Kind: tChnWaitKind; Os: PtrInt; Rearm: tChnWaitRearm;
  RearmData: Pointer): pChnWaitSource;
{ Leave the set (when the layer closes); Src becomes nil. }
procedure ChnWaitLeave(var Src: pChnWaitSource);
{ The owner has just looked at its device (read what there was). Hungry =
  False when it cannot take more now (ring full with flow control): the
  source then stays out of the OS wait, since its input could only wake
  waits for nothing. }
procedure ChnWaitServed(Src: pChnWaitSource; Hungry: Boolean);
{ Input arrived for Src without an OS object to show it (wkSignal: a LOOP
  peer's bytes, a layer's own worker thread). Any thread may call it. }
procedure ChnWaitSignal(Src: pChnWaitSource);
{ The owner has a send pending (True) or not (False): while True the
  source also ends waits when the device can take more bytes. Call it
  whenever the layer has tried to send (with True it also puts a fired
  source back into the wait, as ChnWaitServed does for input). }
procedure ChnWaitOutput(Src: pChnWaitSource; Want: Boolean);
{ A poll of Src found nothing: wait at most Ms ms for input on any source
  of the process. True when Src itself fired (its input may be waiting:
  look again); False when the wait ended for another source, after the
  full Ms, or at once when the system has no shared set (ChnWaitShared
  False: the caller waits on its own device). Ms <= 0 never waits. }
function  ChnWaitIdle(Src: pChnWaitSource; Ms: LongInt): Boolean;
{ For new programs: block until any open channel has new input or a
  pending send can go on, or TimeoutMs passes (0: only look). True when
  woken by a channel, False on timeout. Poll the channels afterwards. }
function  ChnWaitAny(TimeoutMs: LongInt): Boolean;
{ True while the set watches Src's device for input (armed, not fired): any
  input that came since the owner last read would end a wait at once, so a
  poll about to wait may skip reading first and read only when
  ChnWaitIdle says Src fired - one call less per idle poll. }
function  ChnWaitWatching(Src: pChnWaitSource): Boolean;
{ True while Src's device is in the OS wait, fired or not: what comes next
  will end a wait (ComPull then need not read until EAGAIN). }
function  ChnWaitArmed(Src: pChnWaitSource): Boolean;
{ True where ChnWaitIdle really waits on the whole set (Linux, Windows). }
function  ChnWaitShared: Boolean;
{ A monotonic clock in microseconds (the time base of ChnWaitDue). }
function  ChnClockUs: QWord;
{ Src fires by itself at AtUs (ChnClockUs) as if input had come: a layer
  whose input arrives at a known time (a line at a given speed) makes the
  waits of the process end then instead of polling for it. The earliest
  time given since Src last fired is kept; firing clears it. Any thread. }
procedure ChnWaitDue(Src: pChnWaitSource; AtUs: QWord);
{ Number of sources in the set now (open physical layers). }
function  ChnWaitCount: LongInt;
{ Calls this process made to change the OS wait (Linux: epoll_ctl; 0
  where the wait has no kernel set): what arming and re-arming the
  sources cost, for tests and benchmarks. }
function  ChnWaitOsChanges: LongWord;
{ A layer holds input that has arrived but that the program has not taken
  (bytes in its buffer, a decoded message waiting for ChReceive). Held is
  the layer's own flag (False when it is created); the call keeps one
  process-wide count of the layers holding input. While the count is
  above zero ChnWaitAny returns True at once, so a program that steps its
  clients from one wait never sleeps on input it already has. }
procedure ChnWaitHeld(var Held: Boolean; Holds: Boolean);
{ Number of layers that hold input not yet taken. }
function  ChnWaitHeldCount: LongInt;
{ For a helper that blocks on its own channel (DF1Transact, FT12Transact,
  PcccFinish, ChSendWhenFree) after it has taken everything that channel
  holds: the program-wide wait of ChnWaitAny, but input that other layers
  hold does not end it at once - the blocked helper could not take it (it
  stays held for the program's next ChnWaitAny), and waking for it would
  make the helper spin until its deadline. Where the system has no shared
  set (ChnWaitShared False) it sleeps 1 ms at most. }
function  ChnWaitNew(TimeoutMs: LongInt): Boolean;
{ Milliseconds from now to Deadline (a ChMsTick-style GetTickCount64
  value), 0 when it has passed: the wait a helper gives ChnWaitNew. }
function  ChnWaitLeft(Deadline: QWord): LongInt;
{ ChnWaitNew until Deadline, at most MaxMs: the one wait of every helper
  loop (step, then ChnWaitUntil, until done or the deadline). MaxMs bounds
  the wait for what cannot end it (a state change such as a TCP connect,
  a peer stepped by nobody's input). }
function  ChnWaitUntil(Deadline: QWord; MaxMs: LongInt = High(LongInt)): Boolean;

implementation

uses
  SysUtils
  {$IFDEF LINUX}, BaseUnix, Linux, ChnUnix{$ENDIF}
  {$IFDEF WINDOWS}, Windows{$ENDIF};

var
  Lock: TRTLCriticalSection;
  Slots: array of pChnWaitSource;   { records never move: layers hold pointers }
  SlotCount: LongInt = 0;            { used entries of Slots }
  Members: LongInt = 0;              { sources in use }
  FiredCount: LongInt = 0;           { sources with Fired }
  SkipBudget: LongInt = 0;           { waits that may still return at once }
  Blocked: LongInt = 0;              { threads inside the OS wait now }
  HeldCount: LongInt = 0;            { layers holding input not yet taken }
  DueCount: LongInt = 0;             { sources with a Due time }
  OsChanges: LongWord = 0;           { calls that changed the OS wait }

{$IFDEF UNIX}{$I unix/chnwait.inc}{$ENDIF}
{$IFDEF WINDOWS}{$I win/chnwait.inc}{$ENDIF}

{- ------------------------------------------------------------------ set }


function ChnWaitShared: Boolean;
begin
  Result := OsKernelWait;
end;

function ChnWaitWatching(Src: pChnWaitSource): Boolean;
begin
  Result := (Src <> nil) and ChnWaitShared and (Src^.Kind <> wkSignal) and
    Src^.Armed and not Src^.Fired;
end;

function ChnWaitArmed(Src: pChnWaitSource): Boolean;
begin
  Result := (Src <> nil) and ChnWaitShared and (Src^.Kind <> wkSignal) and Src^.Armed;
end;

function ChnWaitCount: LongInt;
begin
  EnterCriticalSection(Lock);
  Result := Members;
  LeaveCriticalSection(Lock);
end;

procedure ChnWaitHeld(var Held: Boolean; Holds: Boolean);
begin
  if Held = Holds then
    Exit;
  Held := Holds;
  if Holds then
    InterLockedIncrement(HeldCount)
  else
    InterLockedDecrement(HeldCount);
end;

function ChnWaitOsChanges: LongWord;
begin
  Result := OsChanges;
end;

function ChnWaitHeldCount: LongInt;
begin
  Result := HeldCount;
end;

{ Caller holds Lock. }
procedure MarkFired(Src: pChnWaitSource);
begin
  if Src^.Kind = wkSignal then
    Src^.Armed := False;            { like a one-shot descriptor }
  if not Src^.Fired then
  begin
    Src^.Fired := True;
    Inc(FiredCount);
  end;
  SkipBudget := 2 * Members + 2;
end;

{ Caller holds Lock. }
procedure ClearDue(Src: pChnWaitSource);
begin
  if Src^.Due <> 0 then
  begin
    Src^.Due := 0;
    Dec(DueCount);
  end;
end;

{ Fire the sources whose time has come; Left := microseconds to the next
  due time (High(QWord) when none). True when one fired. Caller holds Lock. }
function FireDue(out Left: QWord): Boolean;
var
  I: LongInt;
  Now: QWord;
begin
  Result := False;
  Left := High(QWord);
  if DueCount = 0 then
    Exit;
  Now := ChnClockUs;
  for I := 0 to SlotCount - 1 do
    with Slots[I]^ do
      if Used and (Due <> 0) then
        if Due <= Now then
        begin
          ClearDue(Slots[I]);
          MarkFired(Slots[I]);
          Result := True;
        end
        else if Due - Now < Left then
          Left := Due - Now;
end;

procedure ChnWaitDue(Src: pChnWaitSource; AtUs: QWord);
begin
  if Src = nil then
    Exit;
  if AtUs = 0 then
    AtUs := 1;
  EnterCriticalSection(Lock);
  try
    if Src^.Used and ((Src^.Due = 0) or (AtUs < Src^.Due)) then
    begin
      if Src^.Due = 0 then
        Inc(DueCount);
      Src^.Due := AtUs;
      if Blocked > 0 then
        OsWake(Blocked);            { they wait with the old timeout }
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

{ Caller holds Lock. }
procedure ClearFired(Src: pChnWaitSource);
begin
  if Src^.Fired then
  begin
    Src^.Fired := False;
    Dec(FiredCount);
  end;
end;

function ChnWaitJoin(Kind: tChnWaitKind; Os: PtrInt; Rearm: tChnWaitRearm;
  RearmData: Pointer): pChnWaitSource;
var
  I: LongInt;
  S: pChnWaitSource;
begin
  EnterCriticalSection(Lock);
  try
    S := nil;
    for I := 0 to SlotCount - 1 do
      if not Slots[I]^.Used then
      begin
        S := Slots[I];
        Break;
      end;
    if S = nil then
    begin
      if SlotCount >= Length(Slots) then
        SetLength(Slots, 2 * SlotCount + 16);
      New(S);
      FillChar(S^, SizeOf(S^), 0);
      S^.Index := SlotCount;
      Slots[SlotCount] := S;
      Inc(SlotCount);
    end;
    Inc(S^.Gen);
    S^.Used := True;
    S^.Kind := Kind;
    S^.Os := Os;
    S^.Armed := False;
    S^.InSet := False;
    S^.OneShot := True;               { most fire in another's wait: OsWait }
    S^.Fired := False;
    S^.Hungry := True;
    S^.WantOut := False;
    S^.Rearm := Rearm;
    S^.RearmData := RearmData;
    Inc(Members);
    OsReady;                          { the set itself, on first use }
    OsArm(S, True);
    Result := S;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

procedure ChnWaitLeave(var Src: pChnWaitSource);
begin
  if Src = nil then
    Exit;
  EnterCriticalSection(Lock);
  try
    if Src^.Used then
    begin
      ClearFired(Src);
      ClearDue(Src);
      OsForget(Src);
      Src^.Used := False;
      Src^.Armed := False;
      Dec(Members);
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
  Src := nil;
end;

procedure ChnWaitServed(Src: pChnWaitSource; Hungry: Boolean);
begin
  if Src = nil then
    Exit;
  { the common case - armed, nothing fired - costs no lock and no call }
  if Src^.Armed and not Src^.Fired and (Src^.Hungry = Hungry) then
    Exit;
  EnterCriticalSection(Lock);
  try
    if Src^.Used then
    begin
      ClearFired(Src);
      Src^.Hungry := Hungry;
      if Hungry and not Src^.Armed then
        OsArm(Src, False)
      else if not Hungry and Src^.Armed then
        OsDisarm(Src);
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

procedure ChnWaitSignal(Src: pChnWaitSource);
begin
  if Src = nil then
    Exit;
  EnterCriticalSection(Lock);
  try
    if Src^.Used and Src^.Armed then
    begin
      MarkFired(Src);
      if Blocked > 0 then
        OsWake(Blocked);
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

procedure ChnWaitOutput(Src: pChnWaitSource; Want: Boolean);
begin
  if Src = nil then
    Exit;
  { the common case - nothing changes - costs no lock and no call }
  if (Src^.WantOut = Want) and (not Want or (Src^.Armed and not Src^.Fired)) then
    Exit;
  EnterCriticalSection(Lock);
  try
    if Src^.Used then
    begin
      Src^.WantOut := Want;
      if Want then
        ClearFired(Src);            { the owner is looking at its send }
      if Src^.Armed or (Want and Src^.Hungry) then
        OsArm(Src, False);          { the new event mask, or back into the wait }
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

{ The common part of ChnWaitIdle and ChnWaitAny. }
function WaitSet(Own: pChnWaitSource; Ms: LongInt): Boolean;
var
  I: LongInt;
  Left: QWord;
begin
  Result := False;
  if not OsKernelWait then
    Exit;                            { nothing to wait in: a poll loop }
  EnterCriticalSection(Lock);
  FireDue(Left);
  if FiredCount > 0 then
  begin
    { another channel has input its owner has not looked at yet: do not
      sleep before the loop gets there - within a budget, see the header }
    if SkipBudget > 0 then
    begin
      Dec(SkipBudget);
      LeaveCriticalSection(Lock);
      Exit(True);
    end;
    { budget spent: nobody reads them; they stay out of the OS wait
      until their owners look (ChnWaitServed) }
    for I := 0 to SlotCount - 1 do
      Slots[I]^.Fired := False;
    FiredCount := 0;
  end;
  if Ms <= 0 then
  begin
    LeaveCriticalSection(Lock);
    Exit(False);
  end;
  if not OsCanWait then
  begin
    LeaveCriticalSection(Lock);
    Exit(False);
  end;
  if (Left < High(QWord)) and ((Left + 999) div 1000 < QWord(Ms)) then
    Ms := (Left + 999) div 1000;     { a source falls due before then }
  Result := OsWait(Ms, Own);         { returns with Lock held, as it came }
  if FireDue(Left) then
    Result := True;
  LeaveCriticalSection(Lock);
end;

function ChnWaitIdle(Src: pChnWaitSource; Ms: LongInt): Boolean;
begin
  if (Src = nil) or not ChnWaitShared or (Ms <= 0) then
    Exit(False);
  WaitSet(Src, Ms);
  Result := Src^.Fired;
end;

function ChnWaitAny(TimeoutMs: LongInt): Boolean;
begin
  if HeldCount > 0 then
    Exit(True);                      { input is waiting in a layer: take it }
  Result := ChnWaitNew(TimeoutMs);
end;

function ChnWaitNew(TimeoutMs: LongInt): Boolean;
begin
  if not ChnWaitShared then
  begin
    { nothing can wake a wait here: a short nap, so the helper polls its
      channel again soon instead of going deaf until its deadline }
    if TimeoutMs > 0 then
      Sleep(1);
    Exit(False);
  end;
  Result := WaitSet(nil, TimeoutMs);
end;

function ChnWaitLeft(Deadline: QWord): LongInt;
var
  Now: QWord;
begin
  Now := GetTickCount64;
  if Now >= Deadline then
    Result := 0
  else if Deadline - Now > High(LongInt) then
    Result := High(LongInt)
  else
    Result := LongInt(Deadline - Now);
end;

function ChnWaitUntil(Deadline: QWord; MaxMs: LongInt): Boolean;
var
  Ms: LongInt;
begin
  Ms := ChnWaitLeft(Deadline);
  if Ms > MaxMs then
    Ms := MaxMs;
  Result := ChnWaitNew(Ms);
end;

procedure FreeSlots;
var
  I: LongInt;
begin
  for I := 0 to SlotCount - 1 do
    Dispose(Slots[I]);
  SlotCount := 0;
  Slots := nil;
  OsDone;
end;

initialization
  InitCriticalSection(Lock);
finalization
  FreeSlots;
  DoneCriticalSection(Lock);
end.
