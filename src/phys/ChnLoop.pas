{ ChnLoop - in-memory line (NAM=LOOP), a physical layer.

  Channel stacks in one process talk to each other with no OS device:
    'NAM=DF1 NOD=1 NAM=LOOP PAIR=A END=1'   and   '... NAM=LOOP PAIR=A END=2'
  Each end is a tChnLoop: a tChnPhys (the physical base, unit ChnPhys)
  whose port is TChnPortLoop, so the receive ring, LRB=, IDL=, the transmit
  buffer and the program-wide wait are the base's. The ends of one PAIR are one line: what an end sends, every
  other open end of the pair receives (two ends: a null modem; more: a
  multidrop line such as RS-485, END=1..32; BUS=ON makes two ends one too).
  Bytes sent while nobody else
  is open are lost, as on a cable with nobody listening.

  Without BD= the line has no speed: a message goes at once into the
  receivers' rings (each LRB bytes); what does not fit stays pending at
  the sender (the base's transmit buffer) and moves on as the receivers read,
  so the transfer is flow-controlled and never loses bytes (ChSendReady
  reports CHS_Sending meanwhile).

  With BD= (and BIT=, STOP=, PAR= for the character: start bit, data,
  parity, stop bits; default 8N1) the line runs at that speed: each
  character reaches the other ends when its last bit would have, one
  character time after the one before, and ChSendReady says CHS_Sending
  until the last one has left. Nothing sleeps: the time is looked at when
  a poll comes, and the program-wide wait (ChnWaitAny, IDL=) is told when
  the next characters fall due (ChnWaitDue), so it wakes then. A
  receiver whose ring is full loses what comes (counted, res_Overrun, as
  a UART overrun). On a multidrop line (half duplex: more than two ends
  open, or BUS=ON) two ends sending at the same time collide, as on an
  RS-485 bus: the collision is counted (LoopLineStats) and the characters
  that overlapped reach every receiver garbled (each bit inverted), both
  ends' alike.

  Parameters: PAIR=name (default A), END=1..32 (default 1; PAIR= and END=
  cannot change while the end is open: res_WrongState), BUS=OFF|ON
  (default OFF), BD=50..4000000 or
  0 (default 0: no speed; reported with the character only when given), BIT=5..8, STOP=1|2, PAR=N|E|O|M|S,
  IFG=0..10000 bit times of idle line before a send, at BD= (as COM's),
  LRB=receive
  ring size (default 4096, taken at the next ChOpen), IDL=ms to wait in
  ChReceiveReady when nothing is waiting (default 0: the peer usually runs
  in the same thread, where waiting only adds latency; give IDL when the
  peer runs in another thread). BD= and the character take effect at the
  next ChOpen. COM's device keys mean nothing here. Each open end is a
  wkSignal source of the program-wide wait (unit ChnWait): bytes put into
  its ring, or room made for its pending send, wake the waits of the
  process. Safe for several threads when the program uses cthreads. }
unit ChnLoop;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnRing, ChnWait, ChnPort, ChnPhys;

const
  cName = 'LOOP';
  LoopDefaultLRB = 4096;
  LoopMaxEnds = 32;
  { characters a receiver is woken for at most at once (a UART's FIFO):
    a long message is handed over while it comes, not only at its end }
  LoopWakeChars = 16;

type
  pLoopPair = ^tLoopPair;

  pChnLoop = ^tChnLoop;
  tChnLoop = object(tChnPhys)
    CH_Pair   : string[31];   {< PAIR= }
    CH_End    : Byte;         {< END=, 1..LoopMaxEnds }
    CH_LoopBaud: LongInt;     {< BD= of the loop, 0: no speed }
    CH_Bus    : Boolean;      {< BUS=ON: half duplex even with two ends }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    { CHS_Sending also while the port still holds part of the message. }
    function  ChSendReady: tChState; virtual;
    { While the base's ring is empty, input is taken straight from the pair's
      ring (one copy instead of two); otherwise as COM. }
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
  protected
    { LRB= IDL= of the base }
    function  PhysKeys: ShortString; virtual;
    function  ComOpenPort(out Port: TChnPort): tChResult; virtual;
    function  ComDropsWhenFull: Boolean; virtual;
  end;

  { One end of a line. }
  tLoopEnd = record
    Open: Boolean;
    Ring: tByteRing;            {< what this end received; Buf nil while closed }
    Wait: pChnWaitSource;       {< this end in the shared wait }
    Wire: PByte;                {< what this end sent and nobody got yet }
    WireCap, WireLen, WirePos: LongInt;
    CharUs: LongInt;            {< microseconds per character; 0: no speed }
    WireAt: QWord;              {< ChnClockUs when character WirePos begins }
    LastEnd: QWord;             {< when this end's last character ended }
    GarbleTo: QWord;            {< characters begun before this collided }
    Overruns: LongWord;         {< characters lost at this end's full ring }
    Bus: Boolean;               {< opened with BUS=ON }
  end;

  tLoopPair = record
    Name: string[31];
    Ends: array[1..LoopMaxEnds] of tLoopEnd;
    OpenCount: LongInt;
    Paced: LongInt;             {< open ends with a speed (PairNow reads the clock) }
    OnWire: LongInt;            {< ends with characters on their wire (Pump's work) }
    Top: LongInt;               {< the highest end opened so far: the loops stop there }
    Collisions: LongWord;       {< two ends began sending over each other }
    Garbled: LongWord;          {< characters that reached the ends garbled }
    Chars: QWord;               {< characters the line carried }
    LineUs: QWord;              {< microseconds they took on the line (at a speed) }
    Next: pLoopPair;
  end;

  { One end of a line as a port: Write puts the bytes on the wire, Read
    takes what reached this end. }
  TChnPortLoop = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    { Without a speed: takes a whole message or nothing (0 while the last
      one is still on its way); it moves on as the other ends read, also
      when this end is not polled. With a speed: takes it all, behind what
      is still on the wire. }
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FPair: pLoopPair;
    FEnd: Byte;
    FMe: ^tLoopEnd;             {< FPair^.Ends[FEnd] while open: the polls' path }
  public
    PairName: ShortString;      {< set before Open }
    EndNo: Byte;
    RingSize: LongInt;
    CharUs: LongInt;            {< microseconds per character, 0: no speed }
    Bus: Boolean;               {< BUS=ON }
    { Path is ignored: the pair is PairName, the end EndNo. res_CannotOpen
      when that end is open in another stack. }
    function Open(const Path: tWordString): tChResult; override;
    { Bytes of what was sent not yet at the other ends. }
    function OutQueue(out N: LongInt): tChResult; override;
    { Whether bytes wait; never sleeps (the shared wait does that). }
    function WaitInput(Ms: LongInt): Boolean; override;
    { Whether the line can take a message now. }
    function WaitOutput(Ms: LongInt): Boolean; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    { Characters lost at this end's full ring (with a speed). }
    function OsOverruns(out N: LongWord): tChResult; override;
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    procedure WaitJoined(Src: pChnWaitSource); override;
    procedure Close; override;
  end;

  pAddChnLoop = ^tAddChnLoop;
  tAddChnLoop = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ Microseconds one character takes at Baud with the character format of S
  (start bit, data bits, parity, stop bits); 0 when Baud is 0. }
function LoopCharUs(const S: tPortSettings): LongInt;
{ What the line PAIR= Pair did since its first end opened: collisions
  (two ends sending at once) and characters delivered garbled by them.
  False when no end of that pair is open. }
function LoopLineStats(const Pair: ShortString; out Collisions, Garbled: LongWord): Boolean;
{ Characters the line PAIR= Pair carried since its first end opened, and
  the microseconds they took at its speed (the line's busy time, for a
  share of the line used); False when no end of that pair is open. }
function LoopLineLoad(const Pair: ShortString; out Chars, BusyUs: QWord): Boolean;

implementation

uses
  SysUtils, uString;

var
  Pairs: pLoopPair = nil;
  Lock: TRTLCriticalSection;    { guards Pairs and everything in them }

function LoopCharUs(const S: tPortSettings): LongInt;
begin
  Result := LineTime(S, 1, 1000000);
end;

function FindPair(const Name: ShortString): pLoopPair;
begin
  Result := Pairs;
  while (Result <> nil) and (Result^.Name <> Name) do
    Result := Result^.Next;
end;

function LoopLineStats(const Pair: ShortString; out Collisions, Garbled: LongWord): Boolean;
var
  P: pLoopPair;
begin
  Collisions := 0;
  Garbled := 0;
  EnterCriticalSection(Lock);
  P := FindPair(UpStr(Pair));
  Result := P <> nil;
  if Result then
  begin
    Collisions := P^.Collisions;
    Garbled := P^.Garbled;
  end;
  LeaveCriticalSection(Lock);
end;

function LoopLineLoad(const Pair: ShortString; out Chars, BusyUs: QWord): Boolean;
var
  P: pLoopPair;
begin
  Chars := 0;
  BusyUs := 0;
  EnterCriticalSection(Lock);
  P := FindPair(UpStr(Pair));
  Result := P <> nil;
  if Result then
  begin
    Chars := P^.Chars;
    BusyUs := P^.LineUs;
  end;
  LeaveCriticalSection(Lock);
end;

{ Put N characters from Src, sent by end E, into every other open end's
  ring; at a full ring they are lost there (Overruns). }
procedure HandOver(P: pLoopPair; E: LongInt; Src: PByte; N: LongInt); inline;
var
  L, Put: LongInt;
begin
  for L := 1 to P^.Top do
    if (L <> E) and P^.Ends[L].Open then
    begin
      Put := RingPut(P^.Ends[L].Ring, Src, N);
      Inc(P^.Ends[L].Overruns, N - Put);
    end;
  Inc(P^.Chars, N);
  Inc(P^.LineUs, QWord(N) * QWord(P^.Ends[E].CharUs));
end;

{ Wake the ends after end E's characters moved: input for the others;
  for E, room (no speed) or its send done - not for the end whose own
  call moved them (Caller). }
procedure SignalEnds(P: pLoopPair; E, Caller: LongInt); inline;
var
  L: LongInt;
begin
  for L := 1 to P^.Top do
    if (L <> Caller) and P^.Ends[L].Open and
      ((L <> E) or (P^.Ends[E].CharUs = 0) or (P^.Ends[E].WireLen = 0)) then
      ChnWaitSignal(P^.Ends[L].Wait);
end;

{ N characters of end E's wire have left it: the wire moves on, and is
  empty at its end. }
procedure WireMoved(P: pLoopPair; E, N: LongInt); inline;
begin
  with P^.Ends[E] do
  begin
    Inc(WirePos, N);
    WireAt := WireAt + QWord(N) * QWord(CharUs);
    if WirePos >= WireLen then
    begin
      WirePos := 0;
      WireLen := 0;
      LastEnd := WireAt;
      Dec(P^.OnWire);
    end;
  end;
end;

{ Hand N > 0 characters of end E's wire to every other open end (a
  garbled one inverted). Caller: the end whose call this is. }
procedure Deliver(P: pLoopPair; E, N, Caller: LongInt);
var
  I, Garbled: LongInt;
begin
  with P^.Ends[E] do
  begin
    { the characters begun before GarbleTo are a prefix: invert them in
      place, then hand the whole run to each end in one copy (a byte at a
      time made an unpaced LOOP some hundred times slower) }
    Garbled := 0;
    if CharUs > 0 then
      while (Garbled < N) and
        (WireAt + QWord(Garbled) * QWord(CharUs) < GarbleTo) do
        Inc(Garbled);
    for I := 0 to Garbled - 1 do
      Wire[WirePos + I] := not Wire[WirePos + I];
    Inc(P^.Garbled, Garbled);
    HandOver(P, E, @Wire[WirePos], N);
  end;
  WireMoved(P, E, N);
  SignalEnds(P, E, Caller);
end;

{ How much of Len characters end E writes now Pump would move at once:
  on an unpaced pair with every wire empty, what fits into every other
  end's ring; 0 otherwise. }
function GoesStraight(P: pLoopPair; E, Len: LongInt): LongInt; inline;
var
  L: LongInt;
begin
  Result := 0;
  if (P^.Paced > 0) or (P^.OnWire > 0) then
    Exit;
  Result := Len;
  for L := 1 to P^.Top do
    if (L <> E) and P^.Ends[L].Open and (RingRoom(P^.Ends[L].Ring) < Result) then
      Result := RingRoom(P^.Ends[L].Ring);
end;

{ The common line: two ends without a speed (a null modem without BD=),
  end E writing Len characters at Src while every wire is empty. They go
  into the other end's ring as far as they fit, as GoesStraight, HandOver
  and SignalEnds would put them, without those loops over the ends: the
  number put, or -1 when the line is not that one (or nobody listens). }
function StraightToPeer(P: pLoopPair; E: LongInt; Src: PByte; Len: LongInt): LongInt; inline;
var
  O: LongInt;
begin
  Result := -1;
  if (P^.Paced > 0) or (P^.OnWire > 0) or (P^.Top > 2) then
    Exit;
  O := 3 - E;
  if not P^.Ends[O].Open then
    Exit;
  Result := RingPut(P^.Ends[O].Ring, Src, Len);
  Inc(P^.Chars, Result);
  if Result > 0 then
    ChnWaitSignal(P^.Ends[O].Wait);
end;

{ PumpWires on the common line, two ends without a speed: each end's
  wire moves into the other end's ring as far as it fits, as Deliver
  would move it, without its loops over the ends. }
procedure PumpPair(P: pLoopPair; Caller: LongInt);
var
  E, O, N: LongInt;
begin
  for E := 1 to 2 do
    with P^.Ends[E] do
      if WirePos < WireLen then
      begin
        O := 3 - E;
        N := WireLen - WirePos;
        if P^.Ends[O].Open then
        begin
          if RingRoom(P^.Ends[O].Ring) < N then
            N := RingRoom(P^.Ends[O].Ring);
          if N = 0 then
            Continue;
          RingPut(P^.Ends[O].Ring, @Wire[WirePos], N);
        end;
        Inc(P^.Chars, N);
        WireMoved(P, E, N);
        if E <> Caller then
          ChnWaitSignal(Wait);
        if (O <> Caller) and P^.Ends[O].Open then
          ChnWaitSignal(P^.Ends[O].Wait);
      end;
end;

{ Move what has reached the other ends by Now (with a speed), or what
  fits into every other end's ring (without), and tell the shared wait
  when the next characters fall due: the receivers when the next ones
  (up to LoopWakeChars) arrive, the sender when its last one has left.
  Caller: the end whose call this is. Caller holds Lock. }
procedure PumpWires(P: pLoopPair; Now: QWord; Caller: LongInt);
var
  E, L: LongInt;
  N, Room: LongInt;
  Due: QWord;
begin
  for E := 1 to P^.Top do
    with P^.Ends[E] do
    begin
      if WirePos >= WireLen then
        Continue;
      if CharUs = 0 then
      begin
        N := WireLen - WirePos;
        for L := 1 to P^.Top do
          if (L <> E) and P^.Ends[L].Open then
          begin
            Room := RingRoom(P^.Ends[L].Ring);
            if Room < N then
              N := Room;
          end;
      end
      else if Now < WireAt + QWord(CharUs) then
        N := 0
      else
      begin
        N := (Now - WireAt) div QWord(CharUs);
        if N > WireLen - WirePos then
          N := WireLen - WirePos;
      end;
      if N > 0 then
        Deliver(P, E, N, Caller);
      if (WirePos < WireLen) and (CharUs > 0) then
      begin
        ChnWaitDue(Wait, WireAt + QWord(WireLen - WirePos) * QWord(CharUs));
        N := WireLen - WirePos;
        if N > LoopWakeChars then
          N := LoopWakeChars;
        Due := WireAt + QWord(N) * QWord(CharUs);
        for L := 1 to P^.Top do
          if (L <> E) and P^.Ends[L].Open then
            ChnWaitDue(P^.Ends[L].Wait, Due);
      end;
    end;
end;

{ Pump's calls come with every read, write and poll of an end; most find
  every wire empty (a message is delivered whole as it is written). Two
  ends without a speed, the common line, take PumpPair's short way. }
procedure Pump(P: pLoopPair; Now: QWord; Caller: LongInt); inline;
begin
  if P^.OnWire = 0 then
    Exit;
  if (P^.Paced = 0) and (P^.Top <= 2) then
    PumpPair(P, Caller)
  else
    PumpWires(P, Now, Caller);
end;

{ The time for Pump: the clock only when an open end has a speed - an
  unpaced pair needs none, and a clock read is a system call here. }
function PairNow(P: pLoopPair): QWord; inline;
begin
  if P^.Paced > 0 then
    Result := ChnClockUs
  else
    Result := 0;
end;

{ Pump at this time (the clock read only when characters are on a wire
  of a line with a speed). }
procedure PumpNow(P: pLoopPair; Caller: LongInt); inline;
begin
  if P^.OnWire > 0 then
    Pump(P, PairNow(P), Caller);
end;

{ Pump for a poll (a read's start, OutQueue, WaitInput, WaitOutput): with
  a speed characters fall due as time passes; without, every write, read,
  flush and close has pumped already, so nothing can be due. }
procedure PumpDue(P: pLoopPair; Caller: LongInt); inline;
begin
  if P^.Paced > 0 then
    Pump(P, ChnClockUs, Caller);
end;

{- ---------------------------------------------------------------- port }

function TChnPortLoop.Open(const Path: tWordString): tChResult;
var
  P: pLoopPair;
begin
  if FOpen then
    Exit(res_WrongState);
  FDevice := PairName;
  FVirtual := True;
  EnterCriticalSection(Lock);
  try
    P := FindPair(PairName);
    if P = nil then
    begin
      New(P);
      FillChar(P^, SizeOf(P^), 0);
      P^.Name := PairName;
      P^.Next := Pairs;
      Pairs := P;
    end;
    if P^.Ends[EndNo].Open then
      Exit(res_CannotOpen);         { this end is in use by another stack }
    with P^.Ends[EndNo] do
    begin
      Open := True;
      RingAlloc(Ring, RingSize, True);   { input held here ends ChnWaitAny }
      WireLen := 0;
      WirePos := 0;
      LastEnd := 0;
      GarbleTo := 0;
      Overruns := 0;
    end;
    P^.Ends[EndNo].CharUs := CharUs;
    if CharUs > 0 then
      Inc(P^.Paced);
    P^.Ends[EndNo].Bus := Bus;
    Inc(P^.OpenCount);
    if EndNo > P^.Top then
      P^.Top := EndNo;
    FPair := P;
    FEnd := EndNo;
    FMe := @P^.Ends[EndNo];
    FOpen := True;
  finally
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

procedure TChnPortLoop.Close;
var
  Link: ^pLoopPair;
begin
  if FPair <> nil then
  begin
    EnterCriticalSection(Lock);
    try
      with FPair^.Ends[FEnd] do
      begin
        if CharUs > 0 then
          Dec(FPair^.Paced);
        if WirePos < WireLen then
          Dec(FPair^.OnWire);
        Open := False;
        Wait := nil;
        RingFree(Ring);
        WireLen := 0;               { what was still on the wire is gone }
        WirePos := 0;
        if Wire <> nil then
          FreeMem(Wire);
        Wire := nil;
        WireCap := 0;
      end;
      Dec(FPair^.OpenCount);
      if FPair^.OpenCount > 0 then
        PumpNow(FPair, FEnd);          { this end's full ring held nobody back now }
      if FPair^.OpenCount = 0 then
      begin
        Link := @Pairs;
        while Link^ <> FPair do
          Link := @Link^^.Next;
        Link^ := FPair^.Next;
        Dispose(FPair);
      end;
      FPair := nil;
      FMe := nil;
    finally
      LeaveCriticalSection(Lock);
    end;
  end;
  inherited Close;
end;

function TChnPortLoop.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  { no try..finally, as in the polls below: nothing here raises, and the
    frame was a good part of a short read's cost }
  EnterCriticalSection(Lock);
  PumpDue(FPair, FEnd);
  Got := RingGet(FMe^.Ring, @Buf, Size);
  if Got > 0 then
    PumpNow(FPair, FEnd);              { room again for a held sender }
  LeaveCriticalSection(Lock);
  Result := res_Ok;
end;

{ Half duplex: more than two ends open, or one of them opened BUS=ON.
  Two ends alone are a null modem: each sends on its own wire. }
function IsBus(P: pLoopPair): Boolean;
var
  L: LongInt;
begin
  Result := P^.OpenCount > 2;
  for L := 1 to P^.Top do
    if P^.Ends[L].Open and P^.Ends[L].Bus then
      Result := True;
end;

{ Another end sends now (its wire holds characters not yet delivered):
  on a bus the new message collides with it; both are garbled where they
  overlap. Caller holds Lock, after Pump. }
procedure Collide(P: pLoopPair; E: LongInt);
var
  L: LongInt;
  Ends, OtherEnds: QWord;
begin
  if not IsBus(P) then
    Exit;
  with P^.Ends[E] do
    Ends := WireAt + QWord(WireLen - WirePos) * QWord(CharUs);
  for L := 1 to P^.Top do
    if (L <> E) and P^.Ends[L].Open and (P^.Ends[L].CharUs > 0) and
      (P^.Ends[L].WirePos < P^.Ends[L].WireLen) then
      with P^.Ends[L] do
      begin
        OtherEnds := WireAt + QWord(WireLen - WirePos) * QWord(CharUs);
        if OtherEnds > Ends then
          OtherEnds := Ends;          { the overlap ends with the shorter }
        if OtherEnds > GarbleTo then
          GarbleTo := OtherEnds;
        if OtherEnds > P^.Ends[E].GarbleTo then
          P^.Ends[E].GarbleTo := OtherEnds;
        Inc(P^.Collisions);
      end;
end;

function TChnPortLoop.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  Now: QWord;
  Idle: Boolean;
  Straight, Rest: LongInt;
begin
  Result := res_Ok;
  EnterCriticalSection(Lock);
  try
    { what the wire and Pump would move at once goes into the other
      ends' rings without the copy onto the wire (the null modem: one
      message at a time); the rest waits on the wire }
    Now := 0;                       { StraightToPeer: a line without a speed }
    Straight := StraightToPeer(FPair, FEnd, @Buf, Len);
    if Straight < 0 then
    begin
      Now := PairNow(FPair);
      Pump(FPair, Now, FEnd);
      Straight := GoesStraight(FPair, FEnd, Len);
      if Straight > 0 then
      begin
        HandOver(FPair, FEnd, @Buf, Straight);
        SignalEnds(FPair, FEnd, FEnd);
      end;
    end;
    if Straight > 0 then
    begin
      Done := Len;
      if Straight = Len then
        Exit;
    end;
    Rest := Len - Straight;
    with FMe^ do
    begin
      Idle := WirePos >= WireLen;
      if not Idle and (CharUs = 0) then
        Exit;                       { the last message is still on its way }
      if WirePos > 0 then
      begin
        Move(Wire[WirePos], Wire^, WireLen - WirePos);
        Dec(WireLen, WirePos);
        WirePos := 0;
      end;
      if WireLen + Rest > WireCap then
      begin
        WireCap := WireLen + Rest;
        ReAllocMem(Wire, WireCap);
      end;
      Move(PByte(@Buf)[Straight], Wire[WireLen], Rest);
      Inc(WireLen, Rest);
      if Idle and (WirePos < WireLen) then
        Inc(FPair^.OnWire);
      if Idle then
      begin
        WireAt := Now;              { the line is free: it starts now }
        if WireAt < LastEnd then
          WireAt := LastEnd;
      end;
    end;
    Done := Len;
    if FMe^.CharUs > 0 then
      Collide(FPair, FEnd);
    Pump(FPair, Now, FEnd);
  finally
    LeaveCriticalSection(Lock);
  end;
end;

function TChnPortLoop.OutQueue(out N: LongInt): tChResult;
begin
  { nothing on this end's wire: only its own DoWrite puts characters
    there, so no lock and no Pump (the sender polls this for every send) }
  with FMe^ do
    if WirePos >= WireLen then
    begin
      N := 0;
      Exit(res_Ok);
    end;
  EnterCriticalSection(Lock);
  PumpDue(FPair, FEnd);
  with FMe^ do
    N := WireLen - WirePos;
  LeaveCriticalSection(Lock);
  Result := res_Ok;
end;

function TChnPortLoop.WaitInput(Ms: LongInt): Boolean;
begin
  { input already here stays until this end reads it; without a speed
    nothing falls due (PumpDue): no lock, no Pump }
  if FMe^.Ring.Count > 0 then
    Exit(True);
  if FPair^.Paced = 0 then
    Exit(False);
  EnterCriticalSection(Lock);
  PumpDue(FPair, FEnd);
  Result := FMe^.Ring.Count > 0;
  LeaveCriticalSection(Lock);
end;

function TChnPortLoop.WaitOutput(Ms: LongInt): Boolean;
begin
  EnterCriticalSection(Lock);
  PumpDue(FPair, FEnd);
  with FPair^.Ends[FEnd] do
    Result := (CharUs > 0) or (WirePos >= WireLen);
  LeaveCriticalSection(Lock);
end;

function TChnPortLoop.Flush(Input, Output: Boolean): tChResult;
begin
  if Input then
  begin
    EnterCriticalSection(Lock);
    RingClear(FPair^.Ends[FEnd].Ring);
    PumpNow(FPair, FEnd);              { room again for a held sender }
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

function TChnPortLoop.OsOverruns(out N: LongWord): tChResult;
begin
  EnterCriticalSection(Lock);
  N := FPair^.Ends[FEnd].Overruns;
  LeaveCriticalSection(Lock);
  Result := res_Ok;
end;

{ wkSignal (TChnPort's answer, but True): the ends signal each other. }
function TChnPortLoop.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  inherited WaitSource(Kind, Os, Rearm, Data);
  Result := True;
end;

procedure TChnPortLoop.WaitJoined(Src: pChnWaitSource);
begin
  EnterCriticalSection(Lock);
  FPair^.Ends[FEnd].Wait := Src;
  PumpNow(FPair, FEnd);               { characters already on their way }
  LeaveCriticalSection(Lock);
end;

{- --------------------------------------------------------------- layer }

constructor tChnLoop.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Pair := 'A';
  CH_End := 1;
  CH_LoopBaud := 0;
  CH_LRB := LoopDefaultLRB;
  CH_Idle := 0;
end;

constructor tChnLoop.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

function tChnLoop.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key, Value: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  Value := ParamValue(S);
  N := 0;
  if Key = 'PAIR' then
  begin
    Result := res_Ok;
    if Length(Value) > 31 then
      Result := res_BadParam;
    for I := 1 to Length(Value) do
      if not (Value[I] in ['A'..'Z', 'a'..'z', '0'..'9', '_', '-', '.']) then
        Result := res_BadParam;
    { an open end holds the rings of its pair: they cannot change under it }
    if (Result = res_Ok) and (CH_State <> CHS_Close) and (UpStr(Value) <> CH_Pair) then
      Result := res_WrongState;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Pair := UpStr(Value);
  end
  else if Key = 'END' then
  begin
    Result := ParamNum(S, 1, LoopMaxEnds, N);
    if (Result = res_Ok) and (CH_State <> CHS_Close) and (N <> CH_End) then
      Result := res_WrongState;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_End := N;
  end
  else if Key = 'BD' then
  begin
    Result := ParamNum(S, 0, 4000000, N);
    if (Result = res_Ok) and (N > 0) and (N < 50) then
      Result := res_BadParam;       { COM's lowest rate }
    if (Result = res_Ok) and (CmdL = cmd_Set) then
    begin
      CH_LoopBaud := N;
      if N > 0 then
        CH_Set.Baud := N;           { the line time of a send (IFG=) }
    end;
  end
  else if Key = 'BUS' then
  begin
    Result := ParamChoice(S, 'OFF|ON', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Bus := I = 1;
  end
  else if (Key = 'BIT') or (Key = 'STOP') or (Key = 'PAR') or (Key = 'IFG') then
    Result := PhysLineParam(S, CmdL)  { the serial line's ranges }
  else
    Result := inherited ChSetOneParam(S, CmdL);   { LRB= IDL= }
end;

function tChnLoop.PhysKeys: ShortString;
begin
  Result := 'LRB IDL';              { an in-memory line is never lost, its messages never too long }
end;

function tChnLoop.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + ' PAIR=' + CH_Pair + ParamText('END', CH_End);
  if CH_LoopBaud > 0 then          { a line without speed reads as before }
    Result := Result + ParamText('BD', CH_LoopBaud) + ComCharText(CH_Set);
  if CH_Ifg > 0 then
    Result := Result + ParamText('IFG', CH_Ifg);
  if CH_Bus then
    Result := Result + ' BUS=ON';
  Result := Result + ParamText('LRB', CH_LRB) + ParamText('IDL', CH_Idle);
end;

function tChnLoop.ComOpenPort(out Port: TChnPort): tChResult;
var
  P: TChnPortLoop;
  Line: tPortSettings;
begin
  P := TChnPortLoop.Create;
  P.PairName := CH_Pair;
  P.EndNo := CH_End;
  P.RingSize := CH_LRB;
  Line := CH_Set;
  Line.Baud := CH_LoopBaud;
  P.CharUs := LoopCharUs(Line);
  P.Bus := CH_Bus;
  Result := P.Open('');
  if Result <> res_Ok then
  begin
    CH_ParamErr := ChGetParam('END');
    FreeAndNil(P);
  end;
  Port := P;
end;

procedure tChnLoop.ChSend(Buff: Pointer; Len: Word);
begin
  { at a speed the line queues it behind what is still on its way, as a
    UART does; without, the last message must have gone on first }
  if (CH_LoopBaud = 0) and (ChSendReady <> CHS_SendReady) then
    CH_SResult := res_Busy
  else
    inherited ChSend(Buff, Len);
end;

function tChnLoop.ChSendReady: tChState;
var
  N: LongInt;
begin
  Result := inherited ChSendReady;
  if (Result = CHS_SendReady) and (CH_Port <> nil) and (ComPortUsable = res_Ok) and
    (CH_Port.OutQueue(N) = res_Ok) and (N > 0) then
    Result := CHS_Sending;
end;

function tChnLoop.ChReceiveReady: tChState;
begin
  if (CH_State = CHS_Connect) and (CH_RCtrl <> CHS_ReceiveReady) and
    (CH_Ring.Count = 0) and (CH_Port <> nil) and CH_Port.WaitInput(0) then
  begin
    ComPumpTx;                    { a long message keeps moving meanwhile }
    CH_RCtrl := CHS_ReceiveReady;
    Exit(CH_RCtrl);
  end;
  Result := inherited ChReceiveReady;
end;

procedure tChnLoop.ChReceive(var Len: Word);
var
  Got: LongInt;
begin
  if (CH_Ring.Count > 0) or (CH_Port = nil) or (CH_Lost <> CH_LostShown) then
  begin
    inherited ChReceive(Len);
    Exit;
  end;
  if not ChReceiveAllowed(Len) then
    Exit;
  CH_Port.Read(PByte(CH_RBuff)^, CH_RSize, Got);
  ChnWaitServed(CH_Wait, True);   { looked: the next input wakes the waits }
  Len := Got;
  if Len = 0 then
    CH_RResult := res_NoMessage
  else
    CH_RResult := res_Ok;
  CH_RCtrl := CHS_Receiving;     { the next ChReceiveReady looks again }
end;

{ Without a speed the sender waits for room: nothing is lost. With one,
  the port itself counts what a full ring lost (OsOverruns). }
function tChnLoop.ComDropsWhenFull: Boolean;
begin
  Result := False;
end;

function tAddChnLoop.ChInit: pChnVirt;
begin
  Result := New(pChnLoop, Init);
end;

initialization
  InitCriticalSection(Lock);
  ChnCollection^.Insert(New(pAddChnLoop, Init(cName)));
finalization
  DoneCriticalSection(Lock);
end.
