{ Tests of the balanced link helper of ChnFT12Link (tFT12Balanced): two
  stations on NAM=LOOP joined by a LoopTap, each primary and secondary at
  once. Station A: DIR=1 NOD=1 DNO=2; station B: DIR=0 NOD=2 DNO=1;
  ADR=1, LEN=0. Expected wire bytes are worked out by hand: CODE = DIR
  ($80) + PRM ($40) + FCB/ACD ($20) + FCV/DFC ($10) + FC, SUM = CODE +
  ADDR + DATA mod 256; a request carries the address of the station it
  goes to, an answer the address of the station that answers. }
unit TestChnFT12LinkBalanced;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnFT1_2,
  ChnFT12Balanced, TestSupport, LoopTap;

type
  PSink = ^TSink;
  TSink = record
    Text  : string;    { user data the station's secondary took }
    Accept: Boolean;   { its answer: ACK or NACK }
  end;

  TTestChnFT12LinkBalanced = class(TTestCase)
  private
    FA, FB: pChnVirt;
    FTap: TLoopTap;
    FLa, FLb: tFT12Balanced;
    FSinkA, FSinkB: TSink;
    procedure SetUpPair(TimeoutMs: LongInt = 1000; TestMs: LongInt = 0);
    { step A, pump, step B, pump; Rounds times }
    procedure Run(Rounds: Integer);
    { run until both links are available (bounded) }
    procedure BringUp;
    procedure RunFor(Ms: LongInt);
    { run (1 ms apart) until Counter reaches Value, at most 3 s }
    procedure RunUntil(var Counter: LongInt; Value: LongInt);
    procedure Queue(var L: tFT12Balanced; const Hex: string);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestInitRefusesOtherChannels;
    procedure TestLinkComesUpInBothDirections;
    procedure TestUserDataCollisionBothConfirmed;
    procedure TestLostAckRepeatedWithSameFcbExecutedOnce;
    procedure TestAnswerFromAnotherAddressIgnored;
    procedure TestLateAnswerToARepetitionConfirmsNothingElse;
    procedure TestOneStepTakesEverythingReceived;
    procedure TestSingleCharacterInsideABrokenFrameConfirmsNothing;
    procedure TestTestFunctionWhenIdle;
    procedure TestBadInputNeverStopsTheLink;
    procedure TestLinkLostIsEstablishedAgain;
    procedure TestStationBRepeatsLater;
    procedure TestNackKeepsDataQueued;
    procedure TestSendNoReplyAndQueueLimits;
  end;

implementation

{ Data points to the TSink of one station: what it took, and its answer. }
function OnUser(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  S: PSink;
begin
  S := Data;
  if S^.Text <> '' then
    S^.Text := S^.Text + ' | ';
  if not Confirm then
    S^.Text := S^.Text + 'noreply ';
  S^.Text := S^.Text + BytesToHex(Buf[0], Len);
  Result := S^.Accept;
end;

procedure TTestChnFT12LinkBalanced.SetUp;
begin
  FA := nil;
  FB := nil;
  FTap := nil;
  FSinkA.Text := '';
  FSinkB.Text := '';
  FSinkA.Accept := True;
  FSinkB.Accept := True;
end;

procedure TTestChnFT12LinkBalanced.TearDown;
begin
  if FA <> nil then
    Dispose(FA, Done);
  if FB <> nil then
    Dispose(FB, Done);
  FreeAndNil(FTap);
end;

procedure TTestChnFT12LinkBalanced.SetUpPair(TimeoutMs: LongInt; TestMs: LongInt);
var
  Err: string;
begin
  FA := OpenStack(ChnFT1_2.cName,
    'NAM=FT1_2 MS=OFF PRI=ON DIR=1 LEN=0 NOD=1 DNO=2 NAM=LOOP PAIR=BLA END=1', Err);
  AssertTrue(Err, FA <> nil);
  FB := OpenStack(ChnFT1_2.cName,
    'NAM=FT1_2 MS=OFF PRI=OFF DIR=0 LEN=0 NOD=2 DNO=1 NAM=LOOP PAIR=BLB END=1', Err);
  AssertTrue(Err, FB <> nil);
  FTap := TLoopTap.Create('BLA', 'BLB');
  AssertTrue('tap open', FTap.Ok);
  AssertEquals(res_Ok, FT12BalancedInit(FLa, FA));
  AssertEquals(res_Ok, FT12BalancedInit(FLb, FB));
  FLa.TimeoutMs := TimeoutMs;
  FLb.TimeoutMs := TimeoutMs;
  FLa.TestMs := TestMs;
  FLb.TestMs := TestMs;
  FLa.OnUserData := @OnUser;
  FLb.OnUserData := @OnUser;
  FLa.Data := @FSinkA;
  FLb.Data := @FSinkB;
end;

procedure TTestChnFT12LinkBalanced.Run(Rounds: Integer);
var
  I: Integer;
begin
  for I := 1 to Rounds do
  begin
    FT12BalancedStep(FLa);
    FTap.Pump;
    FT12BalancedStep(FLb);
    FTap.Pump;
  end;
end;

procedure TTestChnFT12LinkBalanced.BringUp;
var
  I: Integer;
begin
  for I := 1 to 50 do
  begin
    Run(1);
    if (FLa.State = bsAvailable) and (FLb.State = bsAvailable) and
       FT12BalancedQuiet(FLa) and FT12BalancedQuiet(FLb) then
      Break;
  end;
  AssertTrue('A available', FLa.State = bsAvailable);
  AssertTrue('B available', FLb.State = bsAvailable);
  Run(3);     { answers still on the line }
end;

procedure TTestChnFT12LinkBalanced.RunFor(Ms: LongInt);
var
  Until_: QWord;
begin
  Until_ := GetTickCount64 + QWord(Ms);
  repeat
    Run(1);
    Sleep(1);
  until GetTickCount64 > Until_;
end;

procedure TTestChnFT12LinkBalanced.RunUntil(var Counter: LongInt; Value: LongInt);
var
  Until_: QWord;
begin
  Until_ := GetTickCount64 + 3000;
  while (Counter < Value) and (GetTickCount64 < Until_) do
  begin
    Run(1);
    Sleep(1);
  end;
end;

procedure TTestChnFT12LinkBalanced.Queue(var L: tFT12Balanced; const Hex: string);
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  AssertEquals('queued', res_Ok, FT12BalancedSend(L, @B[0], Length(B), True));
end;

procedure TTestChnFT12LinkBalanced.TestInitRefusesOtherChannels;
var
  L: tFT12Balanced;
  C, Loop: pChnVirt;
  Err: string;
begin
  Loop := OpenStack(ChnLoop.cName, 'PAIR=BLX END=1', Err);
  try
    AssertEquals(res_WrongLayer, FT12BalancedInit(L, Loop));
    AssertFalse('a bound-less record does nothing', FT12BalancedStep(L));
  finally
    Dispose(Loop, Done);
  end;
  AssertEquals(res_WrongLayer, FT12BalancedInit(L, nil));
  C := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON LEN=0 NAM=LOOP PAIR=BLY END=1', Err);
  try
    AssertEquals('unbalanced channel', res_BadMessage, FT12BalancedInit(L, C));
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnFT12LinkBalanced.TestLinkComesUpInBothDirections;
begin
  SetUpPair;
  BringUp;
  { A: request status of link to 2 (C9+02 = CB); reset of remote link to 2
    (C0+02 = C2) and, in the same step (one chunk for the tap: a step
    takes every frame received), status of link from 1 to B's request
    (80+0B = 8B, +01 = 8C); ACK from 1 to B's reset (80+01 = 81) }
  AssertEquals('10 C9 02 CB 16 | 10 C0 02 C2 16 10 8B 01 8C 16 | 10 80 01 81 16',
    FTap.Lines('A'));
  { B: status of link from 2 (0B+02 = 0D) answering A first, then its own
    request status (49+01 = 4A) in the same step (one chunk for the tap),
    ACK from 2 (00+02) and reset to 1 (40+01), again in one step }
  AssertEquals('10 0B 02 0D 16 10 49 01 4A 16 | 10 00 02 02 16 10 40 01 41 16',
    FTap.Lines('B'));
  AssertTrue(FLa.PeerReset and FLb.PeerReset);
  AssertTrue('first FCB after a reset is 1', FLa.Fcb and FLb.Fcb);
  AssertEquals(0, FLa.Unexpected + FLa.Ignored + FLa.Broken + FLa.BadDir);
  AssertEquals(0, FLb.Unexpected + FLb.Ignored + FLb.Broken + FLb.BadDir);
  AssertEquals('REQUEST STATUS', FT12BalStateName(bsRequestStatus));
  AssertEquals('AVAILABLE', FT12BalStateName(FLa.State));
end;

procedure TTestChnFT12LinkBalanced.TestUserDataCollisionBothConfirmed;
begin
  SetUpPair;
  BringUp;
  FTap.Log.Clear;
  { both send at once: each takes the other's request while its own waits }
  Queue(FLa, '01 02');
  Queue(FLb, '03 04');
  FT12BalancedStep(FLa);
  FT12BalancedStep(FLb);
  FTap.Pump;
  Run(4);
  { A: F3 = 80+40+20+10+3, sum F3+02+01+02 = F8; ACK from 1 }
  AssertEquals('68 04 04 68 F3 02 01 02 F8 16 | 10 80 01 81 16', FTap.Lines('A'));
  { B: 73 = 40+20+10+3, sum 73+01+03+04 = 7B; ACK from 2 }
  AssertEquals('68 04 04 68 73 01 03 04 7B 16 | 10 00 02 02 16', FTap.Lines('B'));
  AssertEquals('03 04', FSinkA.Text);
  AssertEquals('01 02', FSinkB.Text);
  AssertEquals(1, FLa.Confirmed);
  AssertEquals(1, FLb.Confirmed);
  AssertTrue(FT12BalancedQuiet(FLa) and FT12BalancedQuiet(FLb));
  AssertFalse('next FCB 0', FLa.Fcb);
  { the next ones carry FCB 0: D3 (sum D3+02+05 = DA) }
  FTap.Log.Clear;
  Queue(FLa, '05');
  Run(3);
  AssertEquals('68 03 03 68 D3 02 05 DA 16', FTap.Lines('A'));
  AssertEquals('01 02 | 05', FSinkB.Text);
end;

procedure TTestChnFT12LinkBalanced.TestLostAckRepeatedWithSameFcbExecutedOnce;
begin
  SetUpPair(40);
  BringUp;
  FTap.Log.Clear;
  Queue(FLa, 'AA');
  FTap.DropB := 1;              { B's ACK is lost }
  RunUntil(FLa.Confirmed, 1);
  Run(2);
  { F3 02 AA: sum F3+02+AA = 9F, sent twice with the same FCB }
  AssertEquals('68 03 03 68 F3 02 AA 9F 16 | 68 03 03 68 F3 02 AA 9F 16', FTap.Lines('A'));
  AssertEquals('10 00 02 02 16 lost | 10 00 02 02 16', FTap.Lines('B'));
  AssertEquals('executed once', 'AA', FSinkB.Text);
  AssertEquals(1, FLb.Repeats);
  AssertEquals(1, FLa.Retransmits);
  AssertEquals(1, FLa.Confirmed);
end;

{ Late answers, on the wire: the line stalls longer than the timeout, so A
  repeats its user data; the stall ends and A gets the answer to the first
  transmission, and sends the next user data at once - which the line
  loses. The answer to the repetition comes after it: taken for the new
  frame's, it confirmed data B never got (and B then took the frame after
  it for a repetition). Now A first asks for the status of link (its
  answer, FC 11, cannot be mistaken for an ACK, and comes after every
  earlier answer), then sends the data: confirmed only once B took it. }
procedure TTestChnFT12LinkBalanced.TestLateAnswerToARepetitionConfirmsNothingElse;
var
  Until_: QWord;
begin
  SetUpPair(40);
  BringUp;
  FTap.Log.Clear;
  Queue(FLa, 'AA');
  Queue(FLa, 'BB');
  FT12BalancedStep(FLa);          { AA goes out }
  FTap.Pump;
  FTap.HoldA := True;             { the line stalls both ways }
  FTap.HoldB := True;
  FT12BalancedStep(FLb);          { B takes AA and ACKs: held }
  FTap.Pump;
  Sleep(60);
  FT12BalancedStep(FLa);          { no answer: AA again, same FCB: held }
  FTap.Pump;
  AssertEquals('AA repeated', 1, FLa.Retransmits);
  FTap.HoldA := False;
  FTap.HoldB := False;
  FTap.Release;                   { the stall ends: ACK to A, repetition to B }
  FT12BalancedStep(FLa);          { AA confirmed; the next frame goes out ... }
  AssertEquals('AA confirmed', 1, FLa.Confirmed);
  FTap.DropA := 1;                { ... and is lost }
  FTap.Pump;
  FT12BalancedStep(FLb);          { the repetition of AA: the cached ACK again }
  FTap.Pump;
  FT12BalancedStep(FLa);          { that late ACK }
  AssertEquals('a late answer confirms nothing', 1, FLa.Confirmed);
  Until_ := GetTickCount64 + 3000;
  while (FLa.Confirmed < 2) and (GetTickCount64 < Until_) do
  begin
    Run(1);
    Sleep(1);
  end;
  Run(3);
  AssertEquals('both confirmed', 2, FLa.Confirmed);
  AssertEquals('and both delivered, once each', 'AA | BB', FSinkB.Text);
end;

{ Two frames in one chunk (an answer and a request of B): one step takes
  both, so a program stepping from ChnWaitAny never waits for the second. }
procedure TTestChnFT12LinkBalanced.TestOneStepTakesEverythingReceived;
var
  Frames: LongInt;
begin
  SetUpPair;
  BringUp;
  FTap.Log.Clear;
  Frames := FLa.Frames;
  { status of link from 2 (0B+02 = 0D), request status of link to 1 (49+01 = 4A) }
  FTap.InjectToA('10 0B 02 0D 16 10 49 01 4A 16');
  AssertTrue(FT12BalancedStep(FLa));
  AssertEquals('both frames in one step', Frames + 2, FLa.Frames);
  FTap.Pump;
  AssertEquals('and B''s request answered (8B+01 = 8C)', '10 8B 01 8C 16', FTap.Lines('A'));
end;

{ While A's user data waits for its answer, an ACK from link address 3
  (00+03 = 03) is no answer of station 2: counted as ignored, the request
  stays pending and is repeated, and only B's own ACK confirms it. }
procedure TTestChnFT12LinkBalanced.TestAnswerFromAnotherAddressIgnored;
begin
  SetUpPair(40);
  BringUp;
  FTap.Log.Clear;
  Queue(FLa, 'AA');
  FTap.DropB := 1;              { B's ACK is lost }
  FT12BalancedStep(FLa);
  FTap.Pump;
  FT12BalancedStep(FLb);
  FTap.Pump;
  AssertEquals('B took it', 'AA', FSinkB.Text);
  FTap.InjectToA('10 00 03 03 16');
  FT12BalancedStep(FLa);
  AssertEquals('counted as ignored', 1, FLa.Ignored);
  AssertEquals('nothing confirmed', 0, FLa.Confirmed);
  AssertTrue('still pending', FLa.Pending);
  RunUntil(FLa.Confirmed, 1);
  Run(2);
  AssertEquals('confirmed by B''s own ACK', 1, FLa.Confirmed);
  AssertEquals('after a repetition', 1, FLa.Retransmits);
  AssertEquals('executed once', 'AA', FSinkB.Text);
  AssertEquals(1, FLb.Repeats);
end;

{ A single character met while hunting after a broken frame may be a byte of
  that frame: in '68 07 08 E5' (L1 <> L2) the E5 is no ACK of B. It must
  not confirm A's user data, which B never got (soak ft12bal-ber1e-5 lost
  two confirmed messages so); the repetition then gets B's real ACK. }
procedure TTestChnFT12LinkBalanced.TestSingleCharacterInsideABrokenFrameConfirmsNothing;
begin
  SetUpPair(40);
  BringUp;
  Queue(FLa, 'AA');
  FTap.DropA := 1;              { A's user data is lost }
  FT12BalancedStep(FLa);
  FTap.Pump;
  FTap.InjectToA('68 07 08 E5');
  FT12BalancedStep(FLa);
  AssertEquals('nothing confirmed', 0, FLa.Confirmed);
  AssertTrue('still pending', FLa.Pending);
  RunUntil(FLa.Confirmed, 1);
  Run(2);
  AssertEquals('confirmed by B''s own ACK', 1, FLa.Confirmed);
  AssertEquals('after a repetition', 1, FLa.Retransmits);
  AssertEquals('B took it', 'AA', FSinkB.Text);
end;

procedure TTestChnFT12LinkBalanced.TestTestFunctionWhenIdle;
begin
  SetUpPair(1000, 60);
  BringUp;
  FTap.Log.Clear;
  RunFor(100);
  { A: test function F2 = 80+40+20+10+2 to 2, sum F4; B: 72 to 1, sum 73.
    Whose idle time runs out first depends on the scheduler: A's line may
    begin with its ACK of B's test. }
  AssertTrue(FTap.Lines('A'), Pos('10 F2 02 F4 16', FTap.Lines('A')) > 0);
  AssertTrue(FTap.Lines('B'), Pos('10 72 01 73 16', FTap.Lines('B')) > 0);
  { and each ACKs the other's: 80+01 = 81 from A, 00+02 from B }
  AssertTrue(Pos('10 80 01 81 16', FTap.Lines('A')) > 0);
  AssertTrue(Pos('10 00 02 02 16', FTap.Lines('B')) > 0);
  AssertTrue('A tested', FLa.Tests >= 1);
  AssertTrue('B tested', FLb.Tests >= 1);
  AssertTrue(FLa.State = bsAvailable);
  AssertEquals(0, FLa.Retransmits + FLb.Retransmits);
end;

procedure TTestChnFT12LinkBalanced.TestBadInputNeverStopsTheLink;
begin
  SetUpPair;
  BringUp;
  FTap.Log.Clear;
  { to B: a request with B's own DIR (0): 49+02 = 4B -> BadDir, no answer }
  FTap.InjectToB('10 49 02 4B 16');
  { an ACK with nothing of B's outstanding (80+01 = 81) -> Unexpected }
  FTap.InjectToB('10 80 01 81 16');
  { garbage, then a broken checksum -> Broken, skipped }
  FTap.InjectToB('00 FF 13 10 C9 02 00 16');
  Run(6);
  AssertEquals(1, FLb.BadDir);
  AssertEquals(1, FLb.Unexpected);
  AssertEquals(1, FLb.Broken);
  AssertEquals('nothing answered', '', FTap.Lines('B'));
  { a test function with FCB 1 twice: the second is a repetition and gets
    the ACK from memory (F2 02 F4) }
  FTap.InjectToB('10 F2 02 F4 16');
  Run(2);
  FTap.InjectToB('10 F2 02 F4 16');
  Run(2);
  AssertEquals(1, FLb.Repeats);
  AssertEquals('10 00 02 02 16 | 10 00 02 02 16', FTap.Lines('B'));
  { user data with a repeated FCB is not handed over twice:
    F3 02 07, sum FC (FCB 0 -> D3 02 07 = DC is new, then again) }
  FTap.InjectToB('68 03 03 68 D3 02 07 DC 16');
  Run(2);
  FTap.InjectToB('68 03 03 68 D3 02 07 DC 16');
  Run(2);
  AssertEquals('07', FSinkB.Text);
  AssertEquals(2, FLb.Repeats);
  { the link still works both ways }
  Queue(FLb, '11');
  Queue(FLa, '22');
  Run(6);
  AssertEquals('22', Copy(FSinkB.Text, Length(FSinkB.Text) - 1, 2));
  AssertEquals('11', FSinkA.Text);
  AssertTrue(FLa.State = bsAvailable);
  AssertTrue(FLb.State = bsAvailable);
end;

procedure TTestChnFT12LinkBalanced.TestLinkLostIsEstablishedAgain;
begin
  SetUpPair(20);
  FLa.Retries := 1;
  BringUp;
  FTap.Log.Clear;
  Queue(FLa, '33');
  FTap.DropB := 2;              { B's ACK is lost twice: A gives up }
  RunUntil(FLa.LinkLost, 1);
  AssertEquals(1, FLa.LinkLost);
  AssertEquals(1, FLa.Retransmits);
  { A establishes the link again (C9, C0) and sends the data once more }
  RunUntil(FLa.Confirmed, 1);
  AssertEquals(1, FLa.Confirmed);
  AssertTrue(FLa.State = bsAvailable);
  AssertEquals('68 03 03 68 F3 02 33 28 16 | 68 03 03 68 F3 02 33 28 16 | ' +
    '10 C9 02 CB 16 | 10 C0 02 C2 16 | 68 03 03 68 F3 02 33 28 16', FTap.Lines('A'));
  { B took it twice: once before and once after the reset (the standard's
    known window: a reset forgets the FCB) }
  AssertEquals('33 | 33', FSinkB.Text);
end;

procedure TTestChnFT12LinkBalanced.TestStationBRepeatsLater;
var
  I: Integer;
  A0, B0: QWord;
begin
  SetUpPair(300);
  FTap.DropA := 1000;           { nothing gets through: both repeat }
  FTap.DropB := 1000;
  Run(1);
  A0 := FLa.SentAt;
  B0 := FLb.SentAt;
  for I := 1 to 2000 do
  begin
    FT12BalancedStep(FLa);
    FT12BalancedStep(FLb);
    FTap.Pump;
    Sleep(1);
    if FLb.Retransmits = 1 then
      Break;
  end;
  AssertEquals(1, FLa.Retransmits);
  AssertEquals(1, FLb.Retransmits);
  { A repeats after its timeout, B (DIR = 0) after one and a half }
  AssertTrue('A waited the timeout', FLa.SentAt - A0 > 300);
  AssertTrue('B waited half a timeout more', FLb.SentAt - B0 > 450);
end;

procedure TTestChnFT12LinkBalanced.TestNackKeepsDataQueued;
begin
  SetUpPair(30);
  BringUp;
  FTap.Log.Clear;
  FSinkB.Accept := False;
  Queue(FLa, '44');
  Run(3);
  { B refuses: NACK from 2 (01+02 = 03); the data stays queued }
  AssertEquals('10 01 02 03 16', FTap.Lines('B'));
  AssertEquals(0, FLa.Confirmed);
  AssertEquals(1, FLa.QCount);
  FSinkB.Accept := True;
  RunUntil(FLa.Confirmed, 1);
  { sent again after the hold, as a new frame: FCB 0 (D3 02 44, sum 19) }
  AssertEquals('68 03 03 68 F3 02 44 39 16 | 68 03 03 68 D3 02 44 19 16', FTap.Lines('A'));
  AssertEquals('44 | 44', FSinkB.Text);
  AssertEquals(0, FLa.QCount);
end;

procedure TTestChnFT12LinkBalanced.TestSendNoReplyAndQueueLimits;
var
  I: Integer;
  Big: array[0..FT12MaxUserData] of Byte;
begin
  SetUpPair;
  BringUp;
  FillChar(Big, SizeOf(Big), 0);
  AssertEquals(res_BadLen, FT12BalancedSend(FLa, @Big, 0, True));
  { L = 255 counts the control octet and the one address octet: 253 data
    octets at most (more than the manual's records hold, 247) }
  AssertEquals(res_TooLong, FT12BalancedSend(FLa, @Big, 254, True));
  Big[0] := $55;
  AssertEquals(res_Ok, FT12BalancedSend(FLa, @Big, 1, False));
  for I := 2 to FT12BalQueueLen do
    AssertEquals(res_Ok, FT12BalancedSend(FLa, @Big, 1, True));
  AssertEquals('queue full', res_Busy, FT12BalancedSend(FLa, @Big, 1, True));
  FTap.Log.Clear;
  Run(3);
  { SEND/NO REPLY: C4 = 80+40+4 to 2, sum C4+02+55 = 1B; no answer }
  AssertEquals('68 03 03 68 C4 02 55 1B 16', Copy(FTap.Lines('A'), 1, 26));
  AssertEquals('noreply 55', Copy(FSinkB.Text, 1, 10));
  Run(30);
  AssertEquals(FT12BalQueueLen, FLa.Confirmed);
  AssertTrue(FT12BalancedQuiet(FLa));
end;

initialization
  RegisterTest(TTestChnFT12LinkBalanced);
end.
