{ Tests of NAM=IEC104 on loopback TCP against a raw NAM=TCP peer that
  sends and checks APDUs written out by hand (IEC 60870-5-104 clause 5):
  STARTDT on connect, I frames with their numbers, the k and w windows,
  S acknowledgements, TESTFR, t1/t3, the queue across a reconnect, and
  every check that closes the connection with its reason. }
unit TestChnIec104;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnIec104, ChnIec104Codec,
  TestSupport;

type
  TTestChnIec104 = class(TTestCase)
  private
    Layer, Peer: pChnVirt;
    PeerBuf: array[0..4095] of Byte;
    Got: string;                   { what the peer received, hex }
    LBuf: array[0..255] of Byte;
    function L: pChnIec104;
    function OpenServerLayer(const Extra: string): Word;
    procedure OpenPeerClient(Port: Word);
    function OpenPeerServer: Word;
    procedure OpenClientLayer(Port: Word; const Extra: string; const TcpExtra: string = '');
    procedure PeerSend(const HexText: string);
    { poll both until the peer has received Want (hex) after what it had;
      False after TimeoutMs }
    function PeerGets(const Want: string; TimeoutMs: Integer = 3000): Boolean;
    { poll both until the layer delivers an ASDU; its hex ('' none) }
    function LayerGets(TimeoutMs: Integer = 3000): string;
    procedure Poll(Ms: Integer);
    { the layer closed the connection once, saying Why in its reason }
    procedure AssertClosedFor(const Why: string);
    procedure StartServer;
  protected
    procedure TearDown; override;
  published
    procedure TestParameters;
    procedure TestClientSendsStartDtAndQueuedAsdus;
    procedure TestServerStartsOnStartDt;
    procedure TestAcknowledgesAfterW;
    procedure TestKWindowHoldsTheRest;
    procedure TestTestFrAnswered;
    procedure TestT3SendsTestFrAndT1Closes;
    procedure TestIFrameBeforeStartDtCloses;
    procedure TestWrongNsCloses;
    procedure TestNrOutOfWindowCloses;
    procedure TestUWithTwoFunctionsCloses;
    procedure TestBadLengthCloses;
    procedure TestQueueDropsOldestAndNoneTwice;
    procedure TestQueueGrowsInOrder;
    procedure TestNeedsTcpBelow;
    procedure TestHalfFrameThenSilenceCloses;
    procedure TestSilentClientClosed;
    procedure TestHundredClientsLeaveTheStartedOneAlone;
    procedure TestStandbyTakesOverWithStartDt;
    procedure TestClientReconnectsAndSendsWhatWaited;
  end;

implementation

function tTestChnIec104.L: pChnIec104;
begin
  Result := pChnIec104(Layer);
end;

procedure TTestChnIec104.TearDown;
begin
  if Layer <> nil then Dispose(Layer, Done);
  if Peer <> nil then Dispose(Peer, Done);
  Layer := nil;
  Peer := nil;
end;

function TTestChnIec104.OpenServerLayer(const Extra: string): Word;
begin
  Layer := OpenListening('IEC104', Extra + ' NAM=TCP LISTEN=127.0.0.1:0', Result);
  Layer^.ChReceiveBuffer(@LBuf, SizeOf(LBuf));
end;

procedure TTestChnIec104.OpenPeerClient(Port: Word);
var
  Err: string;
begin
  Peer := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  AssertNotNull(Err, Peer);
  Peer^.ChReceiveBuffer(@PeerBuf, SizeOf(PeerBuf));
  Got := '';
end;

function TTestChnIec104.OpenPeerServer: Word;
begin
  Peer := OpenListening('TCP', 'LISTEN=127.0.0.1:0', Result);
  Peer^.ChReceiveBuffer(@PeerBuf, SizeOf(PeerBuf));
  Got := '';
end;

procedure TTestChnIec104.OpenClientLayer(Port: Word; const Extra: string; const TcpExtra: string);
var
  Err: string;
begin
  Layer := OpenStack('IEC104', Extra + ' NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port) + ' ' +
    TcpExtra, Err);
  AssertNotNull(Err, Layer);
  Layer^.ChReceiveBuffer(@LBuf, SizeOf(LBuf));
end;

procedure TTestChnIec104.PeerSend(const HexText: string);
var
  B: TBytes;
begin
  B := HexToBytes(HexText);
  Peer^.ChSend(@B[0], Length(B));
  AssertEquals('peer send', res_Ok, Peer^.ChSendResult);
  AssertTrue('peer sent', WaitSent(Peer, 2000));
end;

procedure TTestChnIec104.Poll(Ms: Integer);
var
  Deadline: QWord;
  Len: Word;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    Layer^.ChReceiveReady;
    if Peer^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Peer^.ChReceive(Len);
      if Len > 0 then
      begin
        if Got <> '' then
          Got := Got + ' ';
        Got := Got + BytesToHex(PeerBuf, Len);
      end;
    end;
  until GetTickCount64 >= Deadline;
end;

function TTestChnIec104.PeerGets(const Want: string; TimeoutMs: Integer): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  repeat
    Poll(1);
    if Pos(Want, Got) > 0 then
    begin
      Delete(Got, 1, Pos(Want, Got) + Length(Want));
      Exit(True);
    end;
  until GetTickCount64 >= Deadline;
  Result := False;
end;

function TTestChnIec104.LayerGets(TimeoutMs: Integer): string;
var
  Deadline: QWord;
  Len: Word;
begin
  Result := '';
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  repeat
    Poll(1);
    Len := 0;
    Layer^.ChReceive(Len);
    if (Layer^.ChReceiveResult = res_Ok) and (Len > 0) then
      Exit(BytesToHex(LBuf, Len));
  until GetTickCount64 >= Deadline;
end;

procedure TTestChnIec104.AssertClosedFor(const Why: string);
begin
  AssertEquals('closed', 1, L^.ChClosings);
  AssertTrue(L^.ChCloseReason, Pos(Why, L^.ChCloseReason) > 0);
end;

procedure TTestChnIec104.StartServer;
begin
  PeerSend('68 04 07 00 00 00');
  AssertTrue('STARTDT con', PeerGets('68 04 0B 00 00 00'));
  AssertTrue('started', L^.ChDataStarted);
end;

procedure TTestChnIec104.TestParameters;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('IEC104');
  try
    C^.ChSetParam('NAM=IEC104 K=20 W=10 T1=20 T2=5 T3=30 QUE=50 NAM=TCP HOST=h PORT=2404');
    AssertEquals(res_Ok, C^.ChResult);
    AssertTrue(C^.ChGetParam(''), Pos('NAM=IEC104 K=20 W=10 T0=30 T1=20 T2=5 T3=30 QUE=50', C^.ChGetParam('')) = 1);
    C^.ChSetParam('NAM=IEC104 K=4 W=5 NAM=TCP HOST=h PORT=2404');
    AssertEquals('w above k', res_BadParam, C^.ChResult);
    AssertEquals('W=5', C^.ChParamError);
    C^.ChSetParam('NAM=IEC104 T2=20 NAM=TCP HOST=h PORT=2404');
    AssertEquals('t2 not below t1 (20 in force)', res_BadParam, C^.ChResult);
    AssertEquals('T2=20', C^.ChParamError);
    C^.ChSetParam('NAM=IEC104 K=0 NAM=TCP HOST=h PORT=2404');
    AssertEquals('k 0', res_BadParam, C^.ChResult);
    C^.ChSetParam('NAM=IEC104 T1=256 NAM=TCP HOST=h PORT=2404');
    AssertEquals('t1 256', res_BadParam, C^.ChResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnIec104.TestNeedsTcpBelow;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('IEC104');
  try
    C^.ChSetParam('NAM=IEC104 NAM=LOOP');
    AssertEquals(res_Ok, C^.ChResult);
    C^.ChOpen;
    AssertEquals(res_WrongLayer, C^.ChResult);
    AssertTrue(C^.ChParamError, Pos('NAM=TCP', C^.ChParamError) > 0);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnIec104.TestClientSendsStartDtAndQueuedAsdus;
var
  Port: Word;
  A: TBytes;
begin
  Port := OpenPeerServer;
  OpenClientLayer(Port, 'NAM=IEC104');
  A := HexToBytes('64 01 06 00 01 00 00 00 00 14');
  Layer^.ChSend(@A[0], Length(A));            { queued until STARTDT con }
  AssertEquals(res_Ok, Layer^.ChSendResult);
  AssertTrue('STARTDT act', PeerGets('68 04 07 00 00 00'));
  Poll(50);
  AssertEquals('nothing before STARTDT con', '', Got);
  PeerSend('68 04 0B 00 00 00');
  AssertTrue('the interrogation as I frame 0', PeerGets('68 0E 00 00 00 00 64 01 06 00 01 00 00 00 00 14'));
  { the peer's ACT_CON, N(S)=0 N(R)=1 }
  PeerSend('68 0E 00 00 02 00 64 01 07 00 01 00 00 00 00 14');
  AssertEquals('delivered', '64 01 07 00 01 00 00 00 00 14', LayerGets);
  { the next I frame acknowledges it: N(S)=1 N(R)=1 }
  Layer^.ChSend(@A[0], Length(A));
  AssertTrue('I frame 1', PeerGets('68 0E 02 00 02 00 64'));
end;

procedure TTestChnIec104.TestServerStartsOnStartDt;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  Poll(30);
  AssertFalse('not started', L^.ChDataStarted);
  StartServer;
  PeerSend('68 04 13 00 00 00');
  AssertTrue('STOPDT con', PeerGets('68 04 23 00 00 00'));
  AssertFalse('stopped', L^.ChDataStarted);
end;

procedure TTestChnIec104.TestAcknowledgesAfterW;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104 K=4 W=2'));
  StartServer;
  PeerSend('68 05 00 00 00 00 AA');
  AssertEquals('first', 'AA', LayerGets);
  Poll(30);
  AssertEquals('no S after one', '', Got);
  PeerSend('68 05 02 00 00 00 BB');
  AssertEquals('second', 'BB', LayerGets);
  AssertTrue('S N(R)=2 after w = 2', PeerGets('68 04 01 00 04 00'));
end;

procedure TTestChnIec104.TestKWindowHoldsTheRest;
var
  B: Byte;
  I: Integer;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104 K=2 W=2'));
  StartServer;
  for I := 1 to 3 do
  begin
    B := I;
    Layer^.ChSend(@B, 1);
  end;
  AssertTrue('two I frames', PeerGets('68 05 00 00 00 00 01 68 05 02 00 00 00 02'));
  Poll(50);
  AssertEquals('the third waits for k', '', Got);
  AssertEquals('queued', 1, L^.ChQueued);
  PeerSend('68 04 01 00 02 00');                { S N(R)=1 }
  AssertTrue('the third', PeerGets('68 05 04 00 00 00 03'));
end;

procedure TTestChnIec104.TestTestFrAnswered;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  PeerSend('68 04 43 00 00 00');
  AssertTrue('TESTFR con', PeerGets('68 04 83 00 00 00'));
end;

procedure TTestChnIec104.TestT3SendsTestFrAndT1Closes;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104 T1=2 T2=1 T3=1'));
  Poll(50);
  AssertTrue('TESTFR act after t3', PeerGets('68 04 43 00 00 00', 2500));
  { unanswered: closed after t1 }
  Poll(2500);
  AssertClosedFor('no TESTFR con within t1');
end;

procedure TTestChnIec104.TestIFrameBeforeStartDtCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  PeerSend('68 05 00 00 00 00 AA');
  Poll(100);
  AssertClosedFor('before STARTDT');
  AssertEquals('nothing delivered', '', LayerGets(50));
  Poll(50);
  AssertEquals('the peer sees the close', res_DeviceLost, Peer^.ChReceiveResult);
end;

procedure TTestChnIec104.TestWrongNsCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  StartServer;
  PeerSend('68 05 02 00 00 00 AA');              { N(S)=1, expected 0 }
  Poll(100);
  AssertClosedFor('N(S)=1, expected 0');
end;

procedure TTestChnIec104.TestNrOutOfWindowCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  StartServer;
  PeerSend('68 04 01 00 02 00');                { S N(R)=1: nothing was sent }
  Poll(100);
  AssertClosedFor('N(R)=1 outside 0..0');
end;

procedure TTestChnIec104.TestUWithTwoFunctionsCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  PeerSend('68 04 47 00 00 00');
  Poll(100);
  AssertClosedFor('control field');
end;

procedure TTestChnIec104.TestBadLengthCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104'));
  PeerSend('68 03 07 00 00');
  Poll(100);
  AssertClosedFor('length octet 3');
  Dispose(Peer, Done);
  Peer := nil;
  OpenPeerClient(pChnTcp(Layer^.CH_Low)^.ChLocalPort);
  PeerSend('68 FE');
  Poll(100);
  AssertEquals('closed again', 2, L^.ChClosings);
  AssertTrue(L^.ChCloseReason, Pos('length octet 254', L^.ChCloseReason) > 0);
end;

procedure TTestChnIec104.TestQueueDropsOldestAndNoneTwice;
var
  Port: Word;
  B: Byte;
  I: Integer;
begin
  Port := OpenPeerServer;
  OpenClientLayer(Port, 'NAM=IEC104 K=12 QUE=3');
  for I := 1 to 5 do
  begin
    B := I;
    Layer^.ChSend(@B, 1);
  end;
  AssertTrue('STARTDT act', PeerGets('68 04 07 00 00 00'));
  PeerSend('68 04 0B 00 00 00');
  AssertTrue('the newest three', PeerGets('68 05 00 00 00 00 03 68 05 02 00 00 00 04 68 05 04 00 00 00 05'));
  AssertEquals('two dropped', 2, L^.CH_Dropped);
end;

{ The queue grows as ASDUs wait (QUE= is its bound, not what it holds
  from the start): with k = 2 eleven ASDUs wait past the first growth
  while the ring has wrapped round (two sent, six more queued), and all
  go out in order, none dropped. }
procedure TTestChnIec104.TestQueueGrowsInOrder;
var
  Port: Word;
  B: Byte;
  I: Integer;

  procedure Send(N: Byte);
  begin
    B := N;
    Layer^.ChSend(@B, 1);
    AssertEquals('queued', res_Ok, Layer^.ChSendResult);
  end;

  { I frame N (0-based: V(S) = N) carrying the octet N + 1 }
  function IFrame(N: Integer): string;
  begin
    Result := Format('68 05 %.2X %.2X 00 00 %.2X', [(2 * N) and $FF, (2 * N) shr 8, N + 1]);
  end;

begin
  Port := OpenPeerServer;
  OpenClientLayer(Port, 'NAM=IEC104 K=2 W=1 QUE=100');
  AssertTrue('STARTDT act', PeerGets('68 04 07 00 00 00'));
  PeerSend('68 04 0B 00 00 00');
  Poll(50);
  for I := 1 to 6 do
    Send(I);
  AssertTrue('two sent (k = 2)', PeerGets(IFrame(0) + ' ' + IFrame(1)));
  for I := 7 to 11 do
    Send(I);
  for I := 1 to 5 do
  begin
    PeerSend(Format('68 04 01 00 %.2X 00', [4 * I]));      { S frame: N(R) = 2 I }
    AssertTrue(Format('frames %d and %d', [2 * I, 2 * I + 1]),
      PeerGets(IFrame(2 * I) + Copy(' ' + IFrame(2 * I + 1), 1, 100 * Ord(I < 5))));
  end;
  AssertEquals('none dropped', 0, L^.CH_Dropped);
end;

procedure TTestChnIec104.TestHalfFrameThenSilenceCloses;
begin
  OpenPeerClient(OpenServerLayer('NAM=IEC104 T1=2 T2=1 T3=1'));
  StartServer;
  PeerSend('68 0E 00 00 00 00 64');             { 3 of 16 octets, then nothing }
  AssertTrue('TESTFR act after t3', PeerGets('68 04 43 00 00 00', 2500));
  Poll(2500);
  AssertEquals('closed after t1', 1, L^.ChClosings);
  AssertTrue(L^.ChCloseReason, Pos('no TESTFR con within t1', L^.ChCloseReason) > 0);
  AssertEquals('nothing delivered', '', LayerGets(20));
end;

{ a client that connects and sends nothing: TESTFR act after t3, closed
  after t1 without TESTFR con; the next client is served }
procedure TTestChnIec104.TestSilentClientClosed;
var
  Port: Word;
begin
  Port := OpenServerLayer('NAM=IEC104 T1=2 T2=1 T3=1');
  OpenPeerClient(Port);
  AssertTrue('TESTFR act after t3', PeerGets('68 04 43 00 00 00', 2500));
  Poll(2500);
  AssertEquals('closed', 1, L^.ChClosings);
  Dispose(Peer, Done);
  Peer := nil;
  OpenPeerClient(Port);
  StartServer;
end;

{ A started connection, then 100 connections at once: the one-client TCP
  server turns them away; the started connection goes on, nothing lost,
  and the heap is where it was. }
procedure TTestChnIec104.TestHundredClientsLeaveTheStartedOneAlone;
var
  Others: array[1..100] of pChnVirt;
  Err: string;
  I: Integer;
  B: Byte;
  Heap, Queue0: PtrUInt;
  Port: Word;
begin
  Port := OpenServerLayer('NAM=IEC104');
  OpenPeerClient(Port);
  StartServer;
  B := 0;
  Layer^.ChSend(@B, 1);                          { every buffer in use once }
  AssertTrue('first', PeerGets('68 05 00 00 00 00 00'));
  { a first hundred sizes the tables that grow to a high-water mark (the
    program-wide wait's); the second must not add to the heap }
  for I := 1 to 100 do
    Others[I] := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  Poll(20);
  for I := 1 to 100 do
    if Others[I] <> nil then
      Dispose(Others[I], Done);
  Poll(20);
  Heap := GetHeapStatus.TotalAllocated;
  Queue0 := Length(L^.CH_Queue);
  for I := 1 to 100 do
    Others[I] := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  try
    for I := 1 to 20 do
    begin
      B := I;
      Layer^.ChSend(@B, 1);
      Poll(5);
    end;
    AssertTrue('k = 12 sent', PeerGets('68 05 16 00 00 00 0B'));
    PeerSend('68 05 00 00 18 00 AA');              { N(R) = 12 }
    AssertEquals('the started peer is still served', 'AA', LayerGets);
    AssertTrue('all 21 in order', PeerGets('68 05 28 00 02 00 14'));
    AssertEquals('no closing', 0, L^.ChClosings);
  finally
    for I := 1 to 100 do
      if Others[I] <> nil then
        Dispose(Others[I], Done);
  end;
  Poll(50);
  { the send queue grows as ASDUs wait (8 waited past k here): that is
    its own growth, not the hundred clients' }
  Heap := Heap + (Length(L^.CH_Queue) - Queue0) * SizeOf(tIec104Slot);
  AssertTrue('heap flat: ' + IntToStr(GetHeapStatus.TotalAllocated) + ' after ' + IntToStr(Heap),
    GetHeapStatus.TotalAllocated <= Heap + 1024);
end;

{ A client with RECON=: the connection is lost with one I frame
  unacknowledged; ASDUs given meanwhile wait; after the reconnect STARTDT
  act, and once confirmed the waiting ASDUs go with numbers from 0 - the
  unacknowledged one is counted, not sent again. }
procedure TTestChnIec104.TestClientReconnectsAndSendsWhatWaited;
var
  Port: Word;
  X: Byte;
begin
  Port := OpenPeerServer;
  OpenClientLayer(Port, 'NAM=IEC104', 'RECON=100');
  AssertTrue('STARTDT act', PeerGets('68 04 07 00 00 00'));
  PeerSend('68 04 0B 00 00 00');
  X := 1;
  Layer^.ChSend(@X, 1);
  AssertTrue('first', PeerGets('68 05 00 00 00 00 01'));
  pChnTcp(Peer)^.ChHangUp;                       { the server drops the client }
  Poll(50);
  X := 2;
  Layer^.ChSend(@X, 1);
  X := 3;
  Layer^.ChSend(@X, 1);
  AssertEquals('waiting', 2, L^.ChQueued);
  AssertTrue('STARTDT act again', PeerGets('68 04 07 00 00 00', 5000));
  Poll(50);
  AssertEquals('nothing before STARTDT con', '', Got);
  PeerSend('68 04 0B 00 00 00');
  AssertTrue('the two that waited, from 0', PeerGets('68 05 00 00 00 00 02 68 05 02 00 00 00 03'));
  AssertEquals('the unacknowledged one counted', 1, L^.CH_Unconfirmed);
  Poll(50);
  AssertEquals('none twice', '', Got);
end;

{ Redundancy, CON=2: A carries data; B is kept, answered and tested with
  TESTFR, gets no data; B's STARTDT act makes it the one (numbers from 0),
  A is a standby one from then; a third client is turned away. }
procedure TTestChnIec104.TestStandbyTakesOverWithStartDt;
var
  Port: Word;
  B, C: pChnVirt;
  BBuf: array[0..1023] of Byte;
  BGot, Err: string;
  X: Byte;

  function BGets(const Want: string; Ms: Integer = 3000): Boolean;
  var
    Deadline: QWord;
    Len: Word;
  begin
    Deadline := GetTickCount64 + QWord(Ms);
    repeat
      Poll(1);
      if B^.ChReceiveReady = CHS_ReceiveReady then
      begin
        B^.ChReceive(Len);
        if Len > 0 then
          BGot := BGot + ' ' + BytesToHex(BBuf, Len);
      end;
      if Pos(Want, BGot) > 0 then
      begin
        Delete(BGot, 1, Pos(Want, BGot) + Length(Want));
        Exit(True);
      end;
    until GetTickCount64 >= Deadline;
    Result := Want = '';
  end;

  procedure BSend(const HexText: string);
  var
    D: TBytes;
  begin
    D := HexToBytes(HexText);
    B^.ChSend(@D[0], Length(D));
    AssertTrue('B sent', WaitSent(B, 2000));
  end;

begin
  Port := OpenServerLayer('NAM=IEC104 CON=2');
  OpenPeerClient(Port);
  StartServer;
  B := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  AssertNotNull(Err, B);
  C := nil;
  try
    B^.ChReceiveBuffer(@BBuf, SizeOf(BBuf));
    BGot := '';
    BSend('68 04 43 00 00 00');
    AssertTrue('standby B: TESTFR con', BGets('68 04 83 00 00 00'));
    X := 1;
    Layer^.ChSend(@X, 1);
    AssertTrue('A carries data', PeerGets('68 05 00 00 00 00 01'));
    BGets('', 100);
    AssertEquals('B gets none', '', BGot);
    { a third client: CON=2 is full }
    C := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
    Poll(100);
    BSend('68 04 07 00 00 00');
    AssertTrue('B: STARTDT con', BGets('68 04 0B 00 00 00'));
    AssertEquals('taken over', 1, L^.ChTakeOvers);
    X := 2;
    Layer^.ChSend(@X, 1);
    AssertTrue('B carries data, numbers from 0', BGets('68 05 00 00 00 00 02'));
    Poll(50);
    AssertEquals('A gets no more data', '', Got);
    PeerSend('68 04 43 00 00 00');
    AssertTrue('A, standby now, is answered', PeerGets('68 04 83 00 00 00'));
    AssertEquals('A sent one unacknowledged frame: dropped, not sent again', 1, L^.CH_Unconfirmed);
    if C <> nil then
    begin
      C^.ChReceiveReady;
      AssertEquals('the third one turned away', res_DeviceLost, C^.ChReceiveResult);
    end;
  finally
    Dispose(B, Done);
    if C <> nil then
      Dispose(C, Done);
  end;
end;

initialization
  RegisterTest(TTestChnIec104);
end.
