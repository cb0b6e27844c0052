{ Tests of ChnRing, the byte ring of the physical layers. }
unit TestChnRing;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Math, fpcunit, testregistry, ChnRing;

type
  TTestChnRing = class(TTestCase)
  published
    procedure TestPutGetWrapsAround;
    procedure TestPutStopsWhenFull;
    procedure TestTailSpanNeverCrossesTheEnd;
    procedure TestAgainstAQueueModel;
    procedure TestIndexQueueInOrderAndGivenBack;
  end;

implementation

procedure TTestChnRing.TestPutGetWrapsAround;
const
  { 5 6 left from the first put, then 5..10 }
  Expected: array[0..7] of Byte = (5, 6, 5, 6, 7, 8, 9, 10);
var
  R: tByteRing;
  S, D: array[0..9] of Byte;
  I: Integer;
begin
  FillChar(R, SizeOf(R), 0);
  RingAlloc(R, 8);
  for I := 0 to 9 do
    S[I] := I + 1;
  AssertEquals(6, RingPut(R, @S[0], 6));
  AssertEquals(4, RingGet(R, @D[0], 4));
  AssertEquals(1, D[0]);
  AssertEquals(4, D[3]);
  { 2 bytes held at index 4..5; 6 more wrap past the end }
  AssertEquals(6, RingPut(R, @S[4], 6));
  AssertEquals(8, R.Count);
  AssertEquals(8, RingGet(R, @D[0], 10));
  for I := 0 to 7 do
    AssertEquals('byte ' + IntToStr(I), Expected[I], D[I]);
  AssertEquals(0, R.Count);
  RingFree(R);
  AssertNull(R.Buf);
end;

procedure TTestChnRing.TestPutStopsWhenFull;
var
  R: tByteRing;
  S: array[0..15] of Byte;
begin
  FillChar(R, SizeOf(R), 0);
  FillChar(S, SizeOf(S), 9);
  RingAlloc(R, 10);
  AssertEquals(10, RingPut(R, @S[0], 16));
  AssertEquals(0, RingRoom(R));
  AssertEquals(0, RingPut(R, @S[0], 1));
  RingClear(R);
  AssertEquals(10, RingRoom(R));
  RingFree(R);
end;

procedure TTestChnRing.TestTailSpanNeverCrossesTheEnd;
var
  R: tByteRing;
  S: array[0..9] of Byte;
  P: PByte;
begin
  FillChar(R, SizeOf(R), 0);
  FillChar(S, SizeOf(S), 1);
  RingAlloc(R, 10);
  RingPut(R, @S[0], 7);
  RingGet(R, @S[0], 5);        { head at 5, 2 bytes held, tail at 7 }
  AssertEquals('up to the end of the buffer', 3, RingTailSpan(R, P));
  AssertTrue(P = @R.Buf[7]);
  RingCommit(R, 3);
  AssertEquals('then from the start', 5, RingTailSpan(R, P));
  AssertTrue(P = @R.Buf[0]);
  RingFree(R);
end;

procedure TTestChnRing.TestAgainstAQueueModel;
var
  R: tByteRing;
  Model: array of Byte;
  Buf: array[0..63] of Byte;
  I, J, N, Got: Integer;
  Next: Byte;
begin
  { random puts and gets; the ring must behave like an unbounded queue
    truncated at its capacity }
  FillChar(R, SizeOf(R), 0);
  RingAlloc(R, 37);
  RandSeed := 99;
  Next := 0;
  SetLength(Model, 0);
  for I := 1 to 20000 do
    if Random(2) = 0 then
    begin
      N := Random(64);
      for J := 0 to N - 1 do
        Buf[J] := Byte(Next + J);
      Got := RingPut(R, @Buf[0], N);
      AssertEquals('put', Min(N, 37 - Length(Model)), Got);
      for J := 0 to Got - 1 do
      begin
        SetLength(Model, Length(Model) + 1);
        Model[High(Model)] := Buf[J];
      end;
      Next := Byte(Next + Got);
    end
    else
    begin
      N := Random(64);
      Got := RingGet(R, @Buf[0], N);
      AssertEquals('get', Min(N, Length(Model)), Got);
      for J := 0 to Got - 1 do
        AssertEquals('content', Model[J], Buf[J]);
      Model := Copy(Model, Got, Length(Model));
    end;
  AssertEquals(Length(Model), R.Count);
  RingFree(R);
end;

{ The index queue keeps order through growth while it is taken from, and
  gives its storage back once it ran empty. }
procedure TTestChnRing.TestIndexQueueInOrderAndGivenBack;
var
  Q: tIndexQueue;
  I, V: LongInt;
begin
  IndexQueueClear(Q);
  for I := 1 to 10 do
    IndexQueuePut(Q, I);
  for I := 1 to 4 do
  begin
    AssertTrue('taken', IndexQueueTake(Q, V));
    AssertEquals('oldest first', I, V);
  end;
  for I := 11 to 100 do
    IndexQueuePut(Q, I);
  AssertEquals('waiting', 96, IndexQueueCount(Q));
  AssertTrue('room for them', Length(Q.Items) >= 100);
  for I := 5 to 100 do
  begin
    AssertTrue('taken', IndexQueueTake(Q, V));
    AssertEquals('in order', I, V);
  end;
  AssertFalse('empty', IndexQueueTake(Q, V));
  AssertEquals('none', -1, V);
  AssertEquals('storage given back', 0, Length(Q.Items));
  AssertEquals('count', 0, IndexQueueCount(Q));
  IndexQueuePut(Q, 7);
  AssertTrue('again', IndexQueueTake(Q, V) and (V = 7));
  IndexQueueClear(Q);
end;

initialization
  RegisterTest(TTestChnRing);
end.
