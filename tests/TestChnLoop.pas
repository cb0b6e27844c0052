{ Tests of ChnLoop, the in-memory null modem: bytes both ways, a 64 KiB
  burst, flow control, pairing rules. }
unit TestChnLoop;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, TestSupport,
  StackCase;

type
  TTestChnLoop = class(TStackCase)
  private
    A, B: pChnVirt;
    procedure OpenPair(const Pair: string; const Extra: string = '');
  published
    procedure TestBytesBothWays;
    procedure TestBurst64KiBWithoutLoss;
    procedure TestLargeMessageIsFlowControlled;
    procedure TestSendWhileBusy;
    procedure TestSmallReceiveBufferGivesChunks;
    procedure TestSameEndTwiceCannotOpen;
    procedure TestPairAndEndFixedWhileOpen;
    procedure TestBytesToClosedPeerAreLost;
    procedure TestReceiverAloneTakesALargeMessage;
    procedure TestReceiveFlush;
    procedure TestTwoThreadsWithIdleWait;
  end;

implementation

procedure TTestChnLoop.OpenPair(const Pair: string; const Extra: string);
begin
  A := Stack('LOOP', 'PAIR=' + Pair + ' END=1 ' + Extra);
  B := Stack('LOOP', 'PAIR=' + Pair + ' END=2 ' + Extra);
end;

{ Read from R until Count bytes arrived (or a deadline), keeping W moving. }
function Drain(R, W: pChnVirt; var Dst: array of Byte; Count: Integer): Integer;
var
  Buf: array[0..999] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  Result := 0;
  R^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := GetTickCount64 + 5000;
  while (Result < Count) and (GetTickCount64 < Deadline) do
  begin
    W^.ChSendReady;
    if R^.ChReceiveReady = CHS_ReceiveReady then
    begin
      R^.ChReceive(Len);
      if Result + Len > Count then
        Break;                            { more than sent: a bug }
      Move(Buf, Dst[Result], Len);
      Inc(Result, Len);
    end;
  end;
end;

procedure TTestChnLoop.TestBytesBothWays;
var
  S, D: array[0..255] of Byte;
  I: Integer;
begin
  OpenPair('BW');
  for I := 0 to 255 do
    S[I] := I;
  A^.ChSend(@S, 256);
  AssertEquals(res_Ok, A^.ChSendResult);
  FillChar(D, SizeOf(D), 0);
  AssertEquals(256, Drain(B, A, D, 256));
  AssertTrue('A->B content', CompareMem(@S, @D, 256));
  for I := 0 to 255 do
    S[I] := 255 - I;
  B^.ChSend(@S, 100);
  FillChar(D, SizeOf(D), 0);
  AssertEquals(100, Drain(A, B, D, 100));
  AssertTrue('B->A content', CompareMem(@S, @D, 100));
  AssertEquals('nothing more', CHS_Receiving, A^.ChReceiveReady);
end;

procedure TTestChnLoop.TestBurst64KiBWithoutLoss;
var
  S, D: array of Byte;
  I, Sent, N: Integer;
  Deadline: QWord;
  Got: Integer;
  Buf: array[0..4095] of Byte;
  Len: Word;
begin
  OpenPair('BURST');
  SetLength(S, 65536);
  SetLength(D, 65536);
  RandSeed := 4711;
  for I := 0 to High(S) do
    S[I] := Random(256);
  { send in chunks of up to 65535 bytes (Word Len) and read concurrently }
  Sent := 0;
  Got := 0;
  B^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := GetTickCount64 + 10000;
  while ((Sent < 65536) or (Got < 65536)) and (GetTickCount64 < Deadline) do
  begin
    if (Sent < 65536) and (A^.ChSendReady = CHS_SendReady) then
    begin
      N := 65536 - Sent;
      if N > 65535 then
        N := 65535;
      A^.ChSend(@S[Sent], N);
      AssertEquals(res_Ok, A^.ChSendResult);
      Inc(Sent, N);
    end;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      AssertTrue('no more than was sent', Got + Len <= 65536);
      Move(Buf, D[Got], Len);
      Inc(Got, Len);
    end;
  end;
  AssertEquals(65536, Got);
  AssertTrue('content', CompareMem(@S[0], @D[0], 65536));
  AssertEquals(res_Ok, B^.ChReceiveResult);
end;

procedure TTestChnLoop.TestLargeMessageIsFlowControlled;
var
  S: array[0..9999] of Byte;
  D: array[0..9999] of Byte;
begin
  OpenPair('FC', 'LRB=1000');
  FillChar(S, SizeOf(S), $A5);
  A^.ChSend(@S, SizeOf(S));
  AssertEquals(res_Ok, A^.ChSendResult);
  AssertEquals('more than LRB pending', CHS_Sending, A^.ChSendReady);
  AssertEquals(SizeOf(S), Drain(B, A, D, SizeOf(S)));
  AssertEquals(CHS_SendReady, A^.ChSendReady);
  AssertTrue(CompareMem(@S, @D, SizeOf(S)));
end;

procedure TTestChnLoop.TestSendWhileBusy;
var
  S: array[0..2999] of Byte;
begin
  OpenPair('BUSY', 'LRB=100');
  FillChar(S, SizeOf(S), 1);
  A^.ChSend(@S, SizeOf(S));
  A^.ChSend(@S, 10);
  AssertEquals(res_Busy, A^.ChSendResult);
end;

procedure TTestChnLoop.TestSmallReceiveBufferGivesChunks;
var
  S: array[0..9] of Byte;
  D: array[0..3] of Byte;
  Guard: array[0..3] of Byte;
  Len: Word;
  I: Integer;
begin
  OpenPair('SMALL');
  for I := 0 to 9 do
    S[I] := I + 1;
  FillChar(Guard, SizeOf(Guard), $EE);
  A^.ChSend(@S, 10);
  B^.ChReceiveBuffer(@D, 3);            { one byte less than D holds }
  D[3] := $EE;
  AssertEquals(CHS_ReceiveReady, B^.ChReceiveReady);
  B^.ChReceive(Len);
  AssertEquals(3, Len);
  AssertEquals('nothing written past the buffer', $EE, D[3]);
  AssertEquals(1, D[0]);
  AssertEquals(3, D[2]);
  B^.ChReceive(Len);
  AssertEquals(3, Len);
  AssertEquals(4, D[0]);
  AssertEquals($EE, Guard[0]);
end;

procedure TTestChnLoop.TestSameEndTwiceCannotOpen;
var
  C: pChnVirt;
begin
  OpenPair('TWICE');
  C := ChnCollection^.ChNewInit('LOOP');
  try
    C^.ChSetParam('PAIR=TWICE END=1');
    C^.ChOpen;
    AssertEquals(res_CannotOpen, C^.ChResult);
    AssertEquals(CHS_Close, C^.ChReady);
  finally
    Dispose(C, Done);
  end;
end;

{ PAIR=/END= name the rings an open end holds: changing them while open
  made ChClose free the peer's ring and leak its own. }
procedure TTestChnLoop.TestPairAndEndFixedWhileOpen;
var
  S, D: array[0..2] of Byte;
begin
  OpenPair('FIXED');
  A^.ChSetParam('END=2');
  AssertEquals('END= while open', res_WrongState, A^.ChResult);
  A^.ChSetParam('PAIR=OTHER');
  AssertEquals('PAIR= while open', res_WrongState, A^.ChResult);
  A^.ChOpen;
  AssertEquals('ChOpen while open', res_WrongState, A^.ChResult);
  AssertEquals('still connected', CHS_Connect, A^.ChReady);
  A^.ChSetParam('PAIR=fixed END=1 LRB=100');
  AssertEquals('the same values (and LRB) are fine', res_Ok, A^.ChResult);
  AssertEquals('END=1', 1, pChnLoop(A)^.CH_End);
  A^.ChClose;
  A^.ChOpen;
  A^.ChConnect;
  AssertEquals('reopens', res_Ok, A^.ChResult);
  S[0] := 1; S[1] := 2; S[2] := 3;
  B^.ChSend(@S, 3);
  AssertEquals(3, Drain(A, B, D, 3));
  A^.ChClose;
  A^.ChSetParam('END=2 PAIR=OTHER');
  AssertEquals('closed: anything goes', res_Ok, A^.ChResult);
  { but PAIR= is kept in a string[31] }
  A^.ChSetParam('PAIR=' + StringOfChar('P', 31));
  AssertEquals('PAIR= of 31 characters', res_Ok, A^.ChResult);
  A^.ChSetParam('PAIR=' + StringOfChar('Q', 32));
  AssertEquals('PAIR= of 32 characters', res_BadParam, A^.ChResult);
  AssertEquals('PAIR kept', 'PAIR=' + StringOfChar('P', 31), A^.ChGetParam('PAIR'));
end;

procedure TTestChnLoop.TestBytesToClosedPeerAreLost;
var
  S: array[0..9] of Byte;
  D: array[0..9] of Byte;
  Len: Word;
begin
  OpenPair('LOST');
  B^.ChClose;
  FillChar(S, SizeOf(S), 7);
  A^.ChSend(@S, 10);
  AssertEquals(res_Ok, A^.ChSendResult);
  AssertEquals('nothing pending', CHS_SendReady, A^.ChSendReady);
  B^.ChOpen;
  B^.ChConnect;
  B^.ChReceiveBuffer(@D, SizeOf(D));
  AssertEquals(CHS_Receiving, B^.ChReceiveReady);
  B^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals(res_NoMessage, B^.ChReceiveResult);
end;

{ A message larger than the ring reaches the receiver whole while only the
  receiver polls: the sender, having sent, may well poll nothing else. }
procedure TTestChnLoop.TestReceiverAloneTakesALargeMessage;
var
  S, D: array[0..2999] of Byte;
  Buf: array[0..99] of Byte;
  I, Got: Integer;
  Len: Word;
  Deadline: QWord;
begin
  OpenPair('ALONE', 'LRB=100');
  for I := 0 to High(S) do
    S[I] := I mod 253;
  A^.ChSend(@S, SizeOf(S));
  AssertEquals(res_Ok, A^.ChSendResult);
  B^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Got := 0;
  Deadline := GetTickCount64 + 5000;
  while (Got < SizeOf(S)) and (GetTickCount64 < Deadline) do
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      AssertTrue('no more than was sent', Got + Len <= SizeOf(S));
      Move(Buf, D[Got], Len);
      Inc(Got, Len);
    end;
  AssertEquals('all of it, A never polled', SizeOf(S), Got);
  AssertTrue(CompareMem(@S, @D, SizeOf(S)));
  AssertEquals(CHS_SendReady, A^.ChSendReady);
end;

procedure TTestChnLoop.TestReceiveFlush;
var
  S: array[0..9] of Byte;
begin
  OpenPair('FLUSH');
  FillChar(S, SizeOf(S), 7);
  A^.ChSend(@S, 10);
  AssertEquals(CHS_ReceiveReady, B^.ChReceiveReady);
  B^.ChReceiveFlush;
  AssertEquals(CHS_Receiving, B^.ChReceiveReady);
end;

type
  TEchoThread = class(TThread)
    Chn: pChnVirt;
    Echoed: Integer;
    procedure Execute; override;
  end;

procedure TEchoThread.Execute;
var
  Buf: array[0..255] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := GetTickCount64 + 5000;
  while (Echoed < 1000) and (GetTickCount64 < Deadline) do
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Chn^.ChReceive(Len);
      while Chn^.ChSendReady <> CHS_SendReady do ;
      Chn^.ChSend(@Buf, Len);
      Inc(Echoed, Len);
    end;
end;

procedure TTestChnLoop.TestTwoThreadsWithIdleWait;
var
  T: TEchoThread;
  S, D: array[0..999] of Byte;
  I: Integer;
begin
  { each end used from its own thread; IDL lets the reader wait }
  OpenPair('THR', 'IDL=2');
  for I := 0 to 999 do
    S[I] := I mod 251;
  T := TEchoThread.Create(True);
  try
    T.Chn := B;
    T.Start;
    for I := 0 to 9 do
    begin
      while A^.ChSendReady <> CHS_SendReady do ;
      A^.ChSend(@S[I * 100], 100);
    end;
    AssertEquals(1000, Drain(A, A, D, 1000));
    T.WaitFor;
    AssertTrue(CompareMem(@S, @D, 1000));
  finally
    T.Free;
  end;
end;

initialization
  RegisterTest(TTestChnLoop);
end.
