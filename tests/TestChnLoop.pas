{ Tests of ChnLoop, the in-memory null modem: bytes both ways, a 64 KiB
  burst, flow control, pairing rules. }
unit TestChnLoop;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnPort,
  ChnWait, TestSupport, StackCase;

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
    procedure TestCharacterTimes;
    procedure TestLineParameters;
    procedure TestTimedLineDeliversAtLineSpeed;
    procedure TestTimedLineWakesTheWaitInTime;
    procedure TestMultidropEveryEndHearsEveryOther;
    procedure TestCollisionGarblesBoth;
    procedure TestNoCollisionOneAfterTheOther;
    procedure TestNullModemIsFullDuplex;
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

{ Character times worked out by hand: start + data + parity + stop bits,
  times 1e6 / BD, rounded up. }
procedure TTestChnLoop.TestCharacterTimes;
var
  S: tPortSettings;
begin
  S := DefaultPortSettings;
  S.Baud := 9600;                       { 8N1: 10 bits, 1041.67 us }
  AssertEquals('9600 8N1', 1042, LoopCharUs(S));
  S.Parity := ppEven;                   { 8E1: 11 bits, 1145.83 us }
  AssertEquals('9600 8E1', 1146, LoopCharUs(S));
  S.Baud := 1200;
  S.StopBits := 2;                      { 8E2: 12 bits, 10000 us }
  AssertEquals('1200 8E2', 10000, LoopCharUs(S));
  S.Baud := 19200;
  S.DataBits := 7;
  S.StopBits := 1;                      { 7E1: 10 bits, 520.83 us }
  AssertEquals('19200 7E1', 521, LoopCharUs(S));
  S.Baud := 0;
  AssertEquals('no speed', 0, LoopCharUs(S));
end;

procedure TTestChnLoop.TestLineParameters;
begin
  A := Stack('LOOP', 'PAIR=PRM END=32 BD=19200 BIT=7 PAR=E STOP=2');
  AssertEquals('BD=19200', A^.ChGetParam('BD'));
  AssertEquals('PAR=E', A^.ChGetParam('PAR'));
  AssertEquals('BIT=7', A^.ChGetParam('BIT'));
  AssertEquals('STOP=2', A^.ChGetParam('STOP'));
  A^.ChSetParam('END=33');
  AssertEquals('END=33', res_BadParam, A^.ChResult);
  A^.ChClose;
  A^.ChSetParam('BD=49');
  AssertEquals('BD=49', res_BadParam, A^.ChResult);
  A^.ChSetParam('BD=0');
  AssertEquals('BD=0: no speed', res_Ok, A^.ChResult);
  AssertEquals('no speed, no line keys', '', A^.ChGetParam('BD'));
  A^.ChSetParam('BUS=ON');
  AssertEquals('BUS=ON', A^.ChGetParam('BUS'));
  A^.ChSetParam('BUS=2');
  AssertEquals('BUS=2', res_BadParam, A^.ChResult);
  A^.ChSetParam('PAR=X');
  AssertEquals('PAR=X', res_BadParam, A^.ChResult);
end;

{ Receive from R until Count bytes came, waiting in ChnWaitAny between
  polls; Wakes counts the waits. }
function TimedDrain(R: pChnVirt; var Dst: array of Byte; Count: Integer;
  out Wakes: Integer): Integer;
var
  Buf: array[0..999] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  Result := 0;
  Wakes := 0;
  R^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := GetTickCount64 + 5000;
  while (Result < Count) and (GetTickCount64 < Deadline) do
    if R^.ChReceiveReady = CHS_ReceiveReady then
    begin
      R^.ChReceive(Len);
      if Result + Len > Count then
        Break;
      Move(Buf, Dst[Result], Len);
      Inc(Result, Len);
    end
    else
    begin
      ChnWaitAny(1000);
      Inc(Wakes);
    end;
end;

{ 200 characters at 9600 8N1 take 208 ms: none of them is there at once,
  the sender is busy until then, and all of them come by then. }
procedure TTestChnLoop.TestTimedLineDeliversAtLineSpeed;
var
  S, D: array[0..199] of Byte;
  I, Wakes: Integer;
  T0, Took: QWord;
  Len: Word;
begin
  OpenPair('SPEED', 'BD=9600');
  for I := 0 to High(S) do
    S[I] := I;
  T0 := GetTickCount64;
  A^.ChSend(@S, SizeOf(S));
  AssertEquals(res_Ok, A^.ChSendResult);
  AssertEquals('the line is busy', CHS_Sending, A^.ChSendReady);
  B^.ChReceiveBuffer(@D, SizeOf(D));
  Len := 0;
  if B^.ChReceiveReady = CHS_ReceiveReady then
  begin
    B^.ChReceive(Len);    { a loaded machine may come here a character late }
    AssertTrue('not all at once: ' + IntToStr(Len), Len < 100);
  end;
  AssertEquals(SizeOf(S) - Len, TimedDrain(B, D[Len..High(D)], SizeOf(S) - Len, Wakes));
  Took := GetTickCount64 - T0;
  AssertTrue('content', CompareMem(@S, @D, SizeOf(S)));
  AssertTrue('took ' + IntToStr(Took) + ' ms of 208', Took >= 206);
  AssertTrue('took ' + IntToStr(Took) + ' ms of 208', Took < 2000);
  AssertTrue('woken ' + IntToStr(Wakes) + ' times', Wakes <= 40);
  AssertEquals('sent', CHS_SendReady, A^.ChSendReady);
end;

{ A wait with nothing but characters on their way ends when they arrive,
  not at its timeout: 12 characters at 1200 8N1 (8333 us each) take
  100 ms. }
procedure TTestChnLoop.TestTimedLineWakesTheWaitInTime;
var
  S: array[0..11] of Byte;
  D: array[0..19] of Byte;
  T0, Took: QWord;
  Len: Word;
begin
  OpenPair('WAKE', 'BD=1200');
  FillChar(S, SizeOf(S), $5A);
  B^.ChReceiveBuffer(@D, SizeOf(D));
  AssertEquals(CHS_Receiving, B^.ChReceiveReady);
  T0 := GetTickCount64;
  A^.ChSend(@S, SizeOf(S));
  while (B^.ChReceiveReady <> CHS_ReceiveReady) and (GetTickCount64 - T0 < 3000) do
    ChnWaitAny(3000);
  Took := GetTickCount64 - T0;
  AssertTrue('woke after ' + IntToStr(Took) + ' ms', Took >= 99);
  AssertTrue('woke after ' + IntToStr(Took) + ' ms', Took < 1500);
  B^.ChReceive(Len);
  AssertEquals('all 12 (woken for the last)', 12, Len);
end;

procedure TTestChnLoop.TestMultidropEveryEndHearsEveryOther;
var
  C: pChnVirt;
  S, D: array[0..2] of Byte;
  Speed: Integer;
  Wakes: Integer;
begin
  for Speed := 0 to 1 do
  begin
    CloseStacks;
    A := Stack('LOOP', 'PAIR=BUS END=1 BD=' + IntToStr(Speed * 19200));
    B := Stack('LOOP', 'PAIR=BUS END=2 BD=' + IntToStr(Speed * 19200));
    C := Stack('LOOP', 'PAIR=BUS END=7 BD=' + IntToStr(Speed * 19200));
    S[0] := 1; S[1] := 2; S[2] := 3;
    A^.ChSend(@S, 3);
    AssertEquals('B hears A', 3, TimedDrain(B, D, 3, Wakes));
    AssertEquals(2, D[1]);
    AssertEquals('C hears A', 3, TimedDrain(C, D, 3, Wakes));
    AssertEquals(3, D[2]);
    AssertEquals('A does not hear itself', CHS_Receiving, A^.ChReceiveReady);
    S[0] := 9;
    C^.ChSend(@S, 1);
    AssertEquals('A hears C', 1, TimedDrain(A, D, 1, Wakes));
    AssertEquals(9, D[0]);
    AssertEquals('B hears C', 1, TimedDrain(B, D, 1, Wakes));
    AssertEquals(9, D[0]);
  end;
end;

{ A and B start 10 characters each at the same moment (within far less
  than a character time): C gets all 20, each inverted ($11 -> $EE,
  $22 -> $DD); A gets B's garbled and B gets A's. }
procedure TTestChnLoop.TestCollisionGarblesBoth;
var
  C: pChnVirt;
  SA, SB: array[0..9] of Byte;
  D: array[0..19] of Byte;
  I, Wakes, NE, ND: Integer;
  Coll, Garb: LongWord;
begin
  A := Stack('LOOP', 'PAIR=COLL END=1 BD=9600');
  B := Stack('LOOP', 'PAIR=COLL END=2 BD=9600');
  C := Stack('LOOP', 'PAIR=COLL END=3 BD=9600');
  FillChar(SA, SizeOf(SA), $11);
  FillChar(SB, SizeOf(SB), $22);
  A^.ChSend(@SA, 10);
  B^.ChSend(@SB, 10);
  AssertEquals('C gets both', 20, TimedDrain(C, D, 20, Wakes));
  NE := 0;
  ND := 0;
  for I := 0 to 19 do
    if D[I] = $EE then
      Inc(NE)
    else if D[I] = $DD then
      Inc(ND);
  AssertEquals('A''s ten, garbled', 10, NE);
  AssertEquals('B''s ten, garbled', 10, ND);
  AssertEquals(10, TimedDrain(A, D, 10, Wakes));
  AssertEquals('A hears B garbled', $DD, D[9]);
  AssertEquals(10, TimedDrain(B, D, 10, Wakes));
  AssertEquals('B hears A garbled', $EE, D[0]);
  AssertTrue(LoopLineStats('coll', Coll, Garb));
  AssertEquals('one collision', 1, Coll);
  AssertEquals('20 characters garbled', 20, Garb);
end;

procedure TTestChnLoop.TestNoCollisionOneAfterTheOther;
var
  S: array[0..9] of Byte;
  D: array[0..9] of Byte;
  Wakes: Integer;
  Coll, Garb: LongWord;
begin
  OpenPair('TURN', 'BD=19200');
  FillChar(S, SizeOf(S), $11);
  A^.ChSend(@S, 10);
  AssertEquals(10, TimedDrain(B, D, 10, Wakes));
  AssertEquals($11, D[9]);
  AssertEquals(CHS_SendReady, A^.ChSendReady);
  FillChar(S, SizeOf(S), $22);
  B^.ChSend(@S, 10);
  AssertEquals(10, TimedDrain(A, D, 10, Wakes));
  AssertEquals($22, D[0]);
  AssertTrue(LoopLineStats('TURN', Coll, Garb));
  AssertEquals(0, Coll);
  AssertEquals(0, Garb);
  AssertFalse('no such line', LoopLineStats('NONE', Coll, Garb));
end;

{ Two ends without BUS=ON are a null modem: both send at once, nothing
  collides, each gets the other's bytes as sent. }
procedure TTestChnLoop.TestNullModemIsFullDuplex;
var
  SA, SB, D: array[0..9] of Byte;
  Wakes: Integer;
  Coll, Garb: LongWord;
begin
  OpenPair('FDX', 'BD=9600');
  FillChar(SA, SizeOf(SA), $11);
  FillChar(SB, SizeOf(SB), $22);
  A^.ChSend(@SA, 10);
  B^.ChSend(@SB, 10);
  AssertEquals(10, TimedDrain(B, D, 10, Wakes));
  AssertEquals($11, D[9]);
  AssertEquals(10, TimedDrain(A, D, 10, Wakes));
  AssertEquals($22, D[0]);
  AssertTrue(LoopLineStats('FDX', Coll, Garb));
  AssertEquals(0, Coll);
end;

initialization
  RegisterTest(TTestChnLoop);
end.
