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

  OS parts: Linux epoll (level-triggered; a fired descriptor of another
  channel is taken out of the set until served) plus a pipe for wake-ups;
  Windows WaitForMultipleObjects over the armed handles plus a
  manual-reset event for wake-ups (63 handles per wait: with more, each
  wait takes the caller's own handle and a rotating window of the others).
  Other Unixes: no shared set, ChnWaitIdle answers False at once and the
  layer waits on its own device as before. }
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
    Os     : PtrInt;          { descriptor or handle }
    Armed  : Boolean;         { in the OS wait now }
    Fired  : Boolean;         { ended a wait; its owner has not looked since }
    Hungry : Boolean;         { the owner can take input now }
    WantOut: Boolean;         { the owner waits for room to send }
    Rearm  : tChnWaitRearm;
    RearmData: Pointer;
    Index  : LongInt;         { slot in the set }
    Gen    : LongWord;        { bumped on every reuse of the slot }
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
{ Number of sources in the set now (open physical layers). }
function  ChnWaitCount: LongInt;
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
  {$IFDEF LINUX}, BaseUnix, Linux{$ENDIF}
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

{$IFDEF LINUX}
var
  EpFd: cint = -1;
  WakeRd: cint = -1;
  WakeWr: cint = -1;
  SetPid: TPid = 0;                  { process that made EpFd (fork check) }
  KickPending: Boolean = False;      { the wake pipe holds a byte }

const
  WakeTag = QWord($FFFFFFFFFFFFFFFF);
  FD_CLOEXEC = 1;

procedure CloseOnExec(Fd: cint);
begin
  FpFcntl(Fd, F_SETFD, FpFcntl(Fd, F_GETFD) or FD_CLOEXEC);
end;

{ Caller holds Lock. The epoll set is made on first use, and again in a
  child process after fork (the parent's set is shared with it). }
function OsReady: Boolean;
var
  P: TFilDes;
  E: EPoll_Event;
  Pid: TPid;
begin
  Pid := FpGetPid;
  if (EpFd >= 0) and (Pid = SetPid) then
    Exit(True);
  if EpFd >= 0 then
  begin
    { a forked child: drop the parent's set without touching it }
    FpClose(EpFd);
    FpClose(WakeRd);
    FpClose(WakeWr);
    EpFd := -1;
  end;
  KickPending := False;
  Result := False;
  EpFd := epoll_create(16);
  if EpFd < 0 then
    Exit;
  if FpPipe(P) <> 0 then
  begin
    FpClose(EpFd);
    EpFd := -1;
    Exit;
  end;
  WakeRd := P[0];
  WakeWr := P[1];
  FpFcntl(WakeRd, F_SETFL, FpFcntl(WakeRd, F_GETFL) or O_NONBLOCK);
  FpFcntl(WakeWr, F_SETFL, FpFcntl(WakeWr, F_GETFL) or O_NONBLOCK);
  CloseOnExec(EpFd);
  CloseOnExec(WakeRd);
  CloseOnExec(WakeWr);
  FillChar(E, SizeOf(E), 0);
  E.Events := EPOLLIN;
  E.Data.u64 := WakeTag;
  epoll_ctl(EpFd, EPOLL_CTL_ADD, WakeRd, @E);
  SetPid := Pid;
  Result := True;
end;

function Tag(Src: pChnWaitSource): QWord;
begin
  Result := (QWord(Src^.Gen) shl 32) or QWord(LongWord(Src^.Index));
end;

{ Put a descriptor source into the epoll set, or change its events.
  Level-triggered: input already there when it is armed counts too. A
  fired source of another channel is taken out (OsDisarm) rather than
  muted, since epoll reports a hang-up even for an entry with no events.
  Caller holds Lock. }
procedure OsArm(Src: pChnWaitSource; First: Boolean);
var
  E: EPoll_Event;
  Op: cint;
begin
  if Src^.Kind <> wkDescriptor then
  begin
    Src^.Armed := True;
    Exit;
  end;
  if EpFd < 0 then
    Exit;
  FillChar(E, SizeOf(E), 0);
  E.Events := EPOLLIN;
  if Src^.WantOut then
    E.Events := E.Events or EPOLLOUT;
  E.Data.u64 := Tag(Src);
  if Src^.Armed then
    Op := EPOLL_CTL_MOD
  else
    Op := EPOLL_CTL_ADD;
  Src^.Armed := epoll_ctl(EpFd, Op, Src^.Os, @E) = 0;
end;

procedure OsDisarm(Src: pChnWaitSource);
begin
  if (Src^.Kind = wkDescriptor) and Src^.Armed and (EpFd >= 0) then
    epoll_ctl(EpFd, EPOLL_CTL_DEL, Src^.Os, nil);
  Src^.Armed := False;
end;

procedure OsForget(Src: pChnWaitSource);
begin
  if SetPid = FpGetPid then        { never the set a parent process shares }
    OsDisarm(Src);
  Src^.Armed := False;
end;

{ Wake every thread blocked in the wait: the pipe stays readable (each
  blocked thread's epoll_wait returns) until the last of them has left,
  who empties it. A count of bytes instead would let one thread that
  loops quickly take another's wake-up. Caller holds Lock. }
procedure OsWake(N: LongInt);
var
  B: Byte;
begin
  if (WakeWr < 0) or KickPending then
    Exit;
  B := 0;
  KickPending := FpWrite(WakeWr, B, 1) = 1;
end;

const
  MaxEvents = 64;

{ Block up to Ms; mark what fired. The caller's own source stays in the
  set (it reads its device at once; taking it out and back in would cost
  two calls per message), every other fired source leaves it until its
  owner has looked. Called without Lock; takes it after. }
function OsWait(Ms: LongInt; Own: pChnWaitSource): Boolean;
var
  Ev: array[0..MaxEvents - 1] of EPoll_Event;
  N, I: cint;
  Idx: LongInt;
  S: pChnWaitSource;
  B: Byte;
  Got: Boolean;
begin
  N := epoll_wait(EpFd, @Ev[0], MaxEvents, Ms);
  Got := False;
  Result := N > 0;
  EnterCriticalSection(Lock);
  Dec(Blocked);
  if KickPending and (Blocked = 0) then
  begin
    FpRead(WakeRd, B, 1);           { the last woken thread ends the wake-up }
    KickPending := False;
  end;
  if N > 0 then
    for I := 0 to N - 1 do
      if Ev[I].Data.u64 <> WakeTag then
      begin
        Idx := LongInt(Ev[I].Data.u64 and $FFFFFFFF);
        if Idx >= SlotCount then
          Continue;
        S := Slots[Idx];
        if not S^.Used or (S^.Gen <> LongWord(Ev[I].Data.u64 shr 32)) then
          Continue;                 { left the set meanwhile }
        if S <> Own then
          OsDisarm(S);
        if not S^.Fired then
        begin
          S^.Fired := True;
          Inc(FiredCount);
        end;
        Got := True;
      end;
  if Got then
  begin
    SkipBudget := 2 * Members + 2;
    if Blocked > 0 then
      OsWake(Blocked);              { their own input may be among these }
  end;
  LeaveCriticalSection(Lock);
end;
{$ENDIF LINUX}

{$IFDEF WINDOWS}
var
  WakeEvt: THandle = 0;              { manual reset: wakes every blocked thread }
  KickPending: Boolean = False;
  Rotor: LongInt = 0;

function OsReady: Boolean;
begin
  if WakeEvt = 0 then
    WakeEvt := CreateEvent(nil, True, False, nil);
  Result := WakeEvt <> 0;
end;

procedure OsArm(Src: pChnWaitSource; First: Boolean);
begin
  if Src^.Kind = wkHandle then
  begin
    if not First or (Src^.Rearm <> nil) then
    begin
      if Src^.Rearm <> nil then
        Src^.Rearm(Src^.RearmData)
      else
        ResetEvent(THandle(Src^.Os));
    end;
  end;
  Src^.Armed := True;
end;

procedure OsDisarm(Src: pChnWaitSource);
begin
  Src^.Armed := False;
end;

procedure OsForget(Src: pChnWaitSource);
begin
end;

{ As on Linux: signalled until the last blocked thread has left. }
procedure OsWake(N: LongInt);
begin
  if (WakeEvt <> 0) and not KickPending then
    KickPending := SetEvent(WakeEvt);
end;

{ Called with Lock held; releases it while blocked. }
function OsWait(Ms: LongInt; Own: pChnWaitSource): Boolean;
var
  H: array[0..MAXIMUM_WAIT_OBJECTS - 1] of THandle;
  Who: array[0..MAXIMUM_WAIT_OBJECTS - 1] of pChnWaitSource;
  Gens: array[0..MAXIMUM_WAIT_OBJECTS - 1] of LongWord;
  N, I, K: LongInt;
  R: DWORD;
  S: pChnWaitSource;

  procedure Add(S: pChnWaitSource);
  begin
    if (N < MAXIMUM_WAIT_OBJECTS) and S^.Used and S^.Armed and (S^.Kind = wkHandle) then
    begin
      H[N] := THandle(S^.Os);
      Who[N] := S;
      Gens[N] := S^.Gen;
      Inc(N);
    end;
  end;

begin
  N := 1;
  H[0] := WakeEvt;
  Who[0] := nil;
  Gens[0] := 0;
  if Own <> nil then
    Add(Own);                        { the caller's own handle always }
  if SlotCount > 0 then
  begin
    Rotor := Rotor mod SlotCount;
    for K := 0 to SlotCount - 1 do
      if Slots[(Rotor + K) mod SlotCount] <> Own then
        Add(Slots[(Rotor + K) mod SlotCount]);
    Inc(Rotor, MAXIMUM_WAIT_OBJECTS - 2);
  end;
  Inc(Blocked);
  LeaveCriticalSection(Lock);
  R := WaitForMultipleObjects(N, @H[0], False, DWORD(Ms));
  EnterCriticalSection(Lock);
  Dec(Blocked);
  if KickPending and (Blocked = 0) then
  begin
    ResetEvent(WakeEvt);
    KickPending := False;
  end;
  Result := False;
  if R < WAIT_OBJECT_0 + DWORD(N) then   { WAIT_OBJECT_0 is 0 }
  begin
    Result := True;
    I := R - WAIT_OBJECT_0;
    if I > 0 then
    begin
      { several may be signalled: take every one that is, so one line
        cannot hide another }
      for K := I to N - 1 do
        if (K = I) or (WaitForSingleObject(H[K], 0) = WAIT_OBJECT_0) then
        begin
          S := Who[K];
          if S^.Used and (S^.Gen = Gens[K]) then
          begin
            S^.Armed := False;
            if not S^.Fired then
            begin
              S^.Fired := True;
              Inc(FiredCount);
            end;
          end;
        end;
      SkipBudget := 2 * Members + 2;
      if Blocked > 0 then
        OsWake(Blocked);
    end;
  end;
end;
{$ENDIF WINDOWS}

{ ------------------------------------------------------------------ set }

function ChnWaitShared: Boolean;
begin
  {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
  Result := True;
  {$ELSE}
  Result := False;
  {$ENDIF}
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

function ChnWaitHeldCount: LongInt;
begin
  Result := HeldCount;
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
    S^.Fired := False;
    S^.Hungry := True;
    S^.WantOut := False;
    S^.Rearm := Rearm;
    S^.RearmData := RearmData;
    Inc(Members);
    {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
    OsReady;                          { the set itself, on first use }
    OsArm(S, True);
    {$ENDIF}
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
      {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
      OsForget(Src);
      {$ENDIF}
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
      {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
      if Hungry and not Src^.Armed then
        OsArm(Src, False)
      else if not Hungry and Src^.Armed then
        OsDisarm(Src);
      {$ENDIF}
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
      if Src^.Kind = wkSignal then
        Src^.Armed := False;        { like a one-shot descriptor }
      if not Src^.Fired then
      begin
        Src^.Fired := True;
        Inc(FiredCount);
      end;
      SkipBudget := 2 * Members + 2;
      {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
      if Blocked > 0 then
        OsWake(Blocked);
      {$ENDIF}
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
      {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
      if Src^.Armed or (Want and Src^.Hungry) then
        OsArm(Src, False);          { the new event mask, or back into the wait }
      {$ENDIF}
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

{ The common part of ChnWaitIdle and ChnWaitAny. }
function WaitSet(Own: pChnWaitSource; Ms: LongInt): Boolean;
var
  I: LongInt;
begin
  Result := False;
  {$IF DEFINED(LINUX) OR DEFINED(WINDOWS)}
  EnterCriticalSection(Lock);
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
  {$IFDEF LINUX}
  if EpFd < 0 then                   { made by the first ChnWaitJoin }
  begin
    LeaveCriticalSection(Lock);
    Exit(False);
  end;
  Inc(Blocked);
  LeaveCriticalSection(Lock);
  Result := OsWait(Ms, Own);
  {$ELSE}
  if not OsReady then
  begin
    LeaveCriticalSection(Lock);
    Exit(False);
  end;
  Result := OsWait(Ms, Own);
  LeaveCriticalSection(Lock);
  {$ENDIF}
  {$ENDIF}
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
  {$IFDEF LINUX}
  if (EpFd >= 0) and (SetPid = FpGetPid) then
  begin
    FpClose(EpFd);
    FpClose(WakeRd);
    FpClose(WakeWr);
  end;
  EpFd := -1;
  {$ENDIF}
  {$IFDEF WINDOWS}
  if WakeEvt <> 0 then
    CloseHandle(WakeEvt);
  WakeEvt := 0;
  {$ENDIF}
end;

initialization
  InitCriticalSection(Lock);
finalization
  FreeSlots;
  DoneCriticalSection(Lock);
end.
