{ ChnRing - a byte ring buffer, the receive queue of the physical layers
  (ChnLoop, ChnCom). A plain record and procedures: no locking, no I/O;
  the caller holds whatever lock its threads need. A ring allocated with
  ReportHeld tells the program-wide wait (ChnWaitHeld) while it holds
  bytes: input a layer has pulled in that the program has not taken, for
  which ChnWaitAny returns at once. And a queue of indices (the points or
  tags whose change waits to be taken, oldest first). }
unit ChnRing;

{$I chn.inc}

interface

type
  tByteRing = record
    Buf  : PByte;     {< Cap bytes; nil until RingAlloc }
    Cap  : LongInt;
    Head : LongInt;   {< index of the oldest byte }
    Count: LongInt;   {< bytes held }
    Report: Boolean;  {< tell ChnWaitHeld while Count > 0 }
    Held : Boolean;   {< the flag ChnWaitHeld keeps for this ring }
  end;

  { Indices in the order they were put; Items[Head..Tail - 1] wait. Items
    doubles as it fills (growing it by one moved it on every put). }
  tIndexQueue = record
    Items: array of LongInt;
    Head : LongInt;
    Tail : LongInt;
  end;

{ (Re)allocate for Cap bytes and empty the ring; ReportHeld as above. }
procedure RingAlloc(var R: tByteRing; Cap: LongInt; ReportHeld: Boolean = False);
{ Add I at the end of Q. }
procedure IndexQueuePut(var Q: tIndexQueue; I: LongInt);
{ The oldest index of Q, taken; False (I = -1) when Q is empty, and its
  storage is given back. }
function  IndexQueueTake(var Q: tIndexQueue; out I: LongInt): Boolean;
{ Indices that wait in Q. }
function  IndexQueueCount(const Q: tIndexQueue): LongInt;
{ Q empty, its storage given back. }
procedure IndexQueueClear(var Q: tIndexQueue);
{ Free the memory; the ring holds nothing afterwards. }
procedure RingFree(var R: tByteRing);
procedure RingClear(var R: tByteRing);
function  RingRoom(const R: tByteRing): LongInt; inline;
{ Copy up to N bytes in; returns how many fitted. }
function  RingPut(var R: tByteRing; Src: PByte; N: LongInt): LongInt;
{ Copy up to N bytes out (oldest first); returns how many. }
function  RingGet(var R: tByteRing; Dst: PByte; N: LongInt): LongInt;
{ For a reader that fills the ring in place (e.g. from read(2)): the free
  space directly after the last byte, without wrapping; RingCommit then
  counts what was written there. }
function  RingTailSpan(var R: tByteRing; var P: PByte): LongInt;
procedure RingCommit(var R: tByteRing; N: LongInt);

implementation

uses
  ChnWait;

procedure NoteHeld(var R: tByteRing); inline;
begin
  if R.Report or R.Held then
    ChnWaitHeld(R.Held, R.Report and (R.Count > 0));
end;

procedure RingAlloc(var R: tByteRing; Cap: LongInt; ReportHeld: Boolean);
begin
  ReAllocMem(R.Buf, Cap);
  R.Cap := Cap;
  RingClear(R);
  R.Report := ReportHeld;
end;

procedure RingFree(var R: tByteRing);
begin
  if R.Buf <> nil then
    FreeMem(R.Buf);
  R.Buf := nil;
  R.Cap := 0;
  RingClear(R);
end;

procedure RingClear(var R: tByteRing);
begin
  R.Head := 0;
  R.Count := 0;
  NoteHeld(R);
end;

function RingRoom(const R: tByteRing): LongInt;
begin
  Result := R.Cap - R.Count;
end;

function RingTailSpan(var R: tByteRing; var P: PByte): LongInt;
var
  Tail: LongInt;
begin
  P := nil;
  Result := 0;
  if R.Count >= R.Cap then
    Exit;
  Tail := (R.Head + R.Count) mod R.Cap;
  P := @R.Buf[Tail];
  Result := R.Cap - R.Count;
  if Result > R.Cap - Tail then
    Result := R.Cap - Tail;
end;

procedure RingCommit(var R: tByteRing; N: LongInt);
begin
  Inc(R.Count, N);
  NoteHeld(R);
end;

function RingPut(var R: tByteRing; Src: PByte; N: LongInt): LongInt;
var
  Span: LongInt;
  P: PByte;
begin
  Result := 0;
  while Result < N do
  begin
    Span := RingTailSpan(R, P);
    if Span = 0 then
      Break;
    if Span > N - Result then
      Span := N - Result;
    Move(Src[Result], P^, Span);
    RingCommit(R, Span);
    Inc(Result, Span);
  end;
end;

function RingGet(var R: tByteRing; Dst: PByte; N: LongInt): LongInt;
var
  Chunk: LongInt;
begin
  Result := 0;
  if N > R.Count then
    N := R.Count;
  while Result < N do
  begin
    Chunk := N - Result;
    if Chunk > R.Cap - R.Head then
      Chunk := R.Cap - R.Head;
    Move(R.Buf[R.Head], Dst[Result], Chunk);
    R.Head := (R.Head + Chunk) mod R.Cap;
    Dec(R.Count, Chunk);
    Inc(Result, Chunk);
  end;
  if R.Count = 0 then
    R.Head := 0;          { keeps the next read in one piece }
  NoteHeld(R);
end;

procedure IndexQueuePut(var Q: tIndexQueue; I: LongInt);
begin
  if Q.Tail >= Length(Q.Items) then
    SetLength(Q.Items, 2 * Length(Q.Items) + 16);
  Q.Items[Q.Tail] := I;
  Inc(Q.Tail);
end;

function IndexQueueTake(var Q: tIndexQueue; out I: LongInt): Boolean;
begin
  Result := Q.Head < Q.Tail;
  if not Result then
  begin
    I := -1;
    IndexQueueClear(Q);
    Exit;
  end;
  I := Q.Items[Q.Head];
  Inc(Q.Head);
end;

function IndexQueueCount(const Q: tIndexQueue): LongInt;
begin
  Result := Q.Tail - Q.Head;
end;

procedure IndexQueueClear(var Q: tIndexQueue);
begin
  Q.Items := nil;
  Q.Head := 0;
  Q.Tail := 0;
end;

end.
