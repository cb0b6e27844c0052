{ Tests of ChnFT12Link: the IEC 60870-5-2 unbalanced link procedures over
  NAM=LOOP, master and slave joined by a LoopTap that logs every frame and
  can lose one. Expected wire bytes are worked out by hand (ADR=1, LEN=0,
  secondary address 5): CODE = RES(0) PRM($40) FCB/ACD($20) FCV/DFC($10)
  FC, SUM = CODE + ADDR + DATA mod 256. }
unit TestChnFT12Link;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnFT1_2,
  ChnFT12Link, ChnFT12Primary, ChnFT12Station, TestSupport, LoopTap;

type
  TTestChnFT12Link = class(TTestCase)
  private
    FM, FS: pChnVirt;
    FTap: TLoopTap;
    FSt: tFT12Station;
    FLink: tFT12Link;
    { the secondary's application: user data taken, class data queued }
    FUserData: string;
    FUserCalls: Integer;
    FClass1: array of string;
    FAcceptData: Boolean;
    { Idle: step the station, or answer by injecting bytes }
    FStepSlave: Boolean;
    FInject: string;
    FSeenA: Integer;
    FRepLen: Word;
    procedure SetUpPair;
    function ClassReq(ClassNo: Byte; out Rep: tRecRecord): tChResult;
    function SendData(const Hex: string; out Rep: tRecRecord): tChResult;
    function Fixed(FC: Byte; out Rep: tRecRecord; Retries: Integer = 2): tChResult;
    procedure Settle;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestFcvOfFunctions;
    procedure TestResetThenAlternatingFcb;
    procedure TestLostReplyIsRepeatedWithSameFcb;
    procedure TestLostAckOfUserDataNotExecutedTwice;
    procedure TestTimeoutAfterRetriesThenResetAgain;
    procedure TestLateAnswerToARepetitionConfirmsNothingElse;
    procedure TestOneStepTakesEverythingReceived;
    procedure TestReplyFromWrongAddressOrGarbledIgnored;
    procedure TestReplyNotFittingTheFunction;
    procedure TestBroadcastAndNoReply;
    procedure TestSlaveRefusesBeforeReset;
    procedure TestRepeatRightAfterResetGetsTheResetAck;
    procedure TestStatusOfLinkWithAcd;
    procedure TestUnknownFunctionAndGarbledFrame;
    procedure TestSingleCharacterAck;
    procedure TestErrorsReturnedAtOnce;
    procedure TestFcvServicesWithoutFcvRefused;
  end;

implementation

const
  TimeoutMs = 40;

function OnUser(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  T: TTestChnFT12Link;
  S: string;
begin
  T := TTestChnFT12Link(Data);
  Inc(T.FUserCalls);
  S := BytesToHex(Buf[0], Len);
  if not Confirm then
    S := 'noreply ' + S;
  if T.FUserData <> '' then
    T.FUserData := T.FUserData + ' | ';
  T.FUserData := T.FUserData + S;
  Result := T.FAcceptData;
end;

function OnClass(Data: Pointer; ClassNo: Byte; var Rep: tSendRecord; var Len: Word): Boolean;
var
  T: TTestChnFT12Link;
  B: TBytes;
  I: Integer;
begin
  T := TTestChnFT12Link(Data);
  Result := (ClassNo = 1) and (Length(T.FClass1) > 0);
  if not Result then
    Exit;
  B := HexToBytes(T.FClass1[0]);
  for I := 0 to High(B) do
    Rep.Data[I + 1] := B[I];
  Len := Length(B);
  for I := 1 to High(T.FClass1) do
    T.FClass1[I - 1] := T.FClass1[I];
  SetLength(T.FClass1, Length(T.FClass1) - 1);
end;

function OnClass1(Data: Pointer): Boolean;
begin
  Result := Length(TTestChnFT12Link(Data).FClass1) > 0;
end;

procedure Idle(Data: Pointer);
var
  T: TTestChnFT12Link;
  I, N: Integer;
begin
  T := TTestChnFT12Link(Data);
  T.FTap.Pump;
  if T.FStepSlave then
    FT12StationStep(T.FSt)
  else if T.FInject <> '' then
  begin
    { answer the first new master frame with the prepared bytes }
    N := 0;
    for I := 0 to T.FTap.Log.Count - 1 do
      if Copy(T.FTap.Log[I], 1, 3) = 'A> ' then
        Inc(N);
    if N > T.FSeenA then
    begin
      T.FSeenA := N;
      T.FTap.InjectToA(T.FInject);
      T.FInject := '';
    end;
  end;
  T.FTap.Pump;
end;

procedure TTestChnFT12Link.SetUp;
begin
  FM := nil;
  FS := nil;
  FTap := nil;
  FUserData := '';
  FUserCalls := 0;
  SetLength(FClass1, 0);
  FAcceptData := True;
  FStepSlave := True;
  FInject := '';
  FSeenA := 0;
end;

procedure TTestChnFT12Link.TearDown;
begin
  if FM <> nil then
    Dispose(FM, Done);
  if FS <> nil then
    Dispose(FS, Done);
  FreeAndNil(FTap);
end;

procedure TTestChnFT12Link.SetUpPair;
var
  Err: string;
begin
  FM := OpenStack(ChnFT1_2.cName,
    'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=9 NAM=LOOP PAIR=LKM END=1', Err);
  AssertTrue(Err, FM <> nil);
  FS := OpenStack(ChnFT1_2.cName,
    'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=5 NAM=LOOP PAIR=LKS END=1', Err);
  AssertTrue(Err, FS <> nil);
  FTap := TLoopTap.Create('LKM', 'LKS');
  AssertTrue('tap open', FTap.Ok);
  FT12StationInit(FSt, FS);
  FSt.OnUserData := @OnUser;
  FSt.OnClassData := @OnClass;
  FSt.OnClass1 := @OnClass1;
  FSt.Data := Self;
  FT12LinkInit(FLink, 5);
end;

function TTestChnFT12Link.ClassReq(ClassNo: Byte; out Rep: tRecRecord): tChResult;
var
  Len: Word;
begin
  Result := FT12RequestClass(FM, FLink, ClassNo, Rep, Len, TimeoutMs, 2, @Idle, Self);
end;

function TTestChnFT12Link.SendData(const Hex: string; out Rep: tRecRecord): tChResult;
var
  Req: tSendRecord;
  B: TBytes;
  I: Integer;
  Len: Word;
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpLongM;
  Req.FC := FCM_UserDataReply;
  B := HexToBytes(Hex);
  for I := 0 to High(B) do
    Req.Data[I + 1] := B[I];
  Result := FT12Transact(FM, FLink, Req, 4 + Length(B), Rep, Len, TimeoutMs, 2,
    @Idle, Self);
end;

function TTestChnFT12Link.Fixed(FC: Byte; out Rep: tRecRecord; Retries: Integer): tChResult;
var
  Req: tSendRecord;
  Len: Word;
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpShortM;
  Req.FC := FC;
  Result := FT12Transact(FM, FLink, Req, 4, Rep, Len, TimeoutMs, Retries, @Idle, Self);
  FRepLen := Len;
end;

{ let frames still in flight arrive and be handled }
procedure TTestChnFT12Link.Settle;
var
  I: Integer;
begin
  for I := 1 to 20 do
    Idle(Self);
end;

procedure TTestChnFT12Link.TestFcvOfFunctions;
var
  FC: Byte;
begin
  { IEC 60870-5-2 and the manual's FCM_* comments: FCV = 1 for 2, 3, 10, 11 }
  for FC := 0 to 15 do
    AssertEquals('FC ' + IntToStr(FC), FC in [2, 3, 10, 11], FT12FcvOf(FC));
end;

procedure TTestChnFT12Link.TestResetThenAlternatingFcb;
var
  Rep: tRecRecord;
  I: Integer;
begin
  SetUpPair;
  AssertFalse(FLink.Reset);
  for I := 1 to 3 do
  begin
    AssertEquals('class 2 #' + IntToStr(I), res_Ok, ClassReq(2, Rep));
    AssertTrue(Rep.MessType = tpShortM);
    AssertEquals(FCS_DataNotAcces, Rep.FC);
  end;
  AssertEquals(res_Ok, SendData('AA BB CC', Rep));
  AssertEquals(FCS_Ack, Rep.FC);
  AssertEquals(res_Ok, SendData('AA BB CC', Rep));
  { 10 40 05 45 16   reset of remote link: PRM, FCB 0, FCV 0, FC 0 (sent
                     first because the link was not reset)
    10 7B 05 80 16   class 2: $40+$20+$10+$0B, FCB = 1 first after reset
    10 5B 05 60 16   class 2: FCB = 0
    10 7B 05 80 16   class 2: FCB = 1
    68 05 05 68 53 05 AA BB CC 89 16   user data FC 3, FCB = 0:
                     L = 1+1+3; $53+$05+$AA+$BB+$CC = $289
    68 05 05 68 73 05 AA BB CC A9 16   FCB = 1: sum $2A9 }
  AssertEquals('10 40 05 45 16 | 10 7B 05 80 16 | 10 5B 05 60 16 | 10 7B 05 80 16 | ' +
    '68 05 05 68 53 05 AA BB CC 89 16 | 68 05 05 68 73 05 AA BB CC A9 16',
    FTap.Lines('A'));
  { ACK FC 0 (10 00 05 05 16), no data FC 9: $09+$05 = $0E }
  AssertEquals('10 00 05 05 16 | 10 09 05 0E 16 | 10 09 05 0E 16 | 10 09 05 0E 16 | ' +
    '10 00 05 05 16 | 10 00 05 05 16', FTap.Lines('B'));
  AssertEquals('AA BB CC | AA BB CC', FUserData);
  AssertEquals(5, FSt.Executed);
  AssertEquals(0, FSt.Repeats);
  AssertTrue('next FCB = 0', not FLink.Fcb);
  { the channel's own receive buffer and DNO are back }
  AssertTrue(FM^.CH_RBuff = nil);
  AssertEquals(9, FM^.CH_DNode);
end;

procedure TTestChnFT12Link.TestLostReplyIsRepeatedWithSameFcb;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  SetLength(FClass1, 2);
  FClass1[0] := '01 02';
  FClass1[1] := '03';
  FTap.Log.Clear;
  FTap.DropB := 1;
  AssertEquals(res_Ok, ClassReq(1, Rep));
  AssertTrue(Rep.MessType = tpLongM);
  AssertEquals(FCS_UserData, Rep.FC);
  AssertEquals(1, Rep.Data[1]);
  AssertEquals(2, Rep.Data[2]);
  AssertTrue('ACD: more class 1 data', FLink.Acd);
  { class 1 FCB 1: $40+$20+$10+$0A = $7A, sum $7F, sent twice; the reply
    68 04 04 68 28 05 01 02 30 16 (ACD $20 + FC 8; $28+$05+$01+$02 = $30)
    is lost once and comes again from the station's memory }
  AssertEquals('10 7A 05 7F 16 | 10 7A 05 7F 16', FTap.Lines('A'));
  AssertEquals('68 04 04 68 28 05 01 02 30 16 lost | 68 04 04 68 28 05 01 02 30 16',
    FTap.Lines('B'));
  AssertEquals('executed once', 1, FSt.Executed);
  AssertEquals(1, FSt.Repeats);
  AssertEquals(1, FLink.Repeats);
  AssertEquals('one item left in the queue', 1, Length(FClass1));
  { the request was sent twice, so the answer to the other transmission
    may still come: first a fence, request status of link ($49, sum $4E;
    answer 10 2B 05 30 16, ACD set), then the next request, new (FCB 0: $5A, sum
    $5F), which gets the next item: 68 03 03 68 08 05 03 10 16, ACD 0 now }
  FTap.Log.Clear;
  AssertEquals(res_Ok, ClassReq(1, Rep));
  AssertEquals('10 49 05 4E 16 | 10 5A 05 5F 16', FTap.Lines('A'));
  AssertEquals('10 2B 05 30 16 | 68 03 03 68 08 05 03 10 16', FTap.Lines('B'));
  AssertEquals('one fence', 1, FLink.Fences);
  AssertFalse(FLink.Acd);
  AssertEquals(2, FSt.Executed);
end;

procedure TTestChnFT12Link.TestLostAckOfUserDataNotExecutedTwice;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  FTap.Log.Clear;
  FTap.DropB := 2;       { the ACK is lost twice: third transmission gets it }
  AssertEquals(res_Ok, SendData('AA BB CC', Rep));
  AssertEquals(FCS_Ack, Rep.FC);
  AssertEquals('68 05 05 68 73 05 AA BB CC A9 16 | 68 05 05 68 73 05 AA BB CC A9 16 | ' +
    '68 05 05 68 73 05 AA BB CC A9 16', FTap.Lines('A'));
  AssertEquals('handed to the application once', 1, FUserCalls);
  AssertEquals('AA BB CC', FUserData);
  AssertEquals(2, FSt.Repeats);
  AssertEquals(2, FLink.Repeats);
end;

procedure TTestChnFT12Link.TestTimeoutAfterRetriesThenResetAgain;
var
  Rep: tRecRecord;
  T0, Took: QWord;
begin
  SetUpPair;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  FTap.Log.Clear;
  FTap.DropB := 100;
  T0 := GetTickCount64;
  AssertEquals(res_Timeout, ClassReq(2, Rep));
  Took := GetTickCount64 - T0;
  AssertTrue('waited 3 x 40 ms: ' + IntToStr(Took), Took >= 3 * TimeoutMs - 3);
  AssertTrue('but not much longer: ' + IntToStr(Took), Took < 2000);
  { 1 + Retries(2) transmissions, all with FCB = 1 }
  AssertEquals('10 7B 05 80 16 | 10 7B 05 80 16 | 10 7B 05 80 16', FTap.Lines('A'));
  AssertFalse('a failed service leaves the link not reset', FLink.Reset);
  AssertEquals(1, FSt.Executed);
  AssertEquals(2, FSt.Repeats);
  { line good again: the answers of the failed service may still come, so
    a fence (request status of link) goes first; then the next FCV = 1
    service resets the link }
  FTap.DropB := 0;
  Settle;
  FTap.Log.Clear;
  AssertEquals(res_Ok, ClassReq(2, Rep));
  AssertEquals('10 49 05 4E 16 | 10 40 05 45 16 | 10 7B 05 80 16', FTap.Lines('A'));
  AssertEquals(2, FSt.Executed);
end;

{ Late answers on the unbalanced link, stepped (FT12PrimaryStart/Step): the
  line stalls longer than the timeout, the primary repeats AA; when the
  stall ends it gets the answer to the first transmission, and the next
  service (BB) is lost on the line; the answer to the repetition arrives
  while BB is out. Taken for BB's, it confirmed BB, which the secondary
  never got. Now a fence goes before BB: the late answer is ignored, BB
  is confirmed only after the secondary took it. }
procedure TTestChnFT12Link.TestLateAnswerToARepetitionConfirmsNothingElse;
var
  P: tFT12Primary;
  Req: tSendRecord;
  Until_: QWord;

  procedure Data(B: Byte);
  begin
    FillChar(Req, SizeOf(Req), 0);
    Req.MessType := tpLongM;
    Req.FC := FCM_UserDataReply;
    Req.Data[1] := B;
  end;

begin
  SetUpPair;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  Settle;
  Data($AA);
  AssertTrue(FT12PrimaryStart(P, FM, FLink, Req, 5, TimeoutMs, 2));
  FTap.Pump;                           { AA reaches the secondary }
  FTap.HoldA := True;                  { the line stalls both ways }
  FTap.HoldB := True;
  FT12StationStep(FSt);                { executes AA and answers: held }
  FTap.Pump;
  Sleep(TimeoutMs + 20);
  FT12PrimaryStep(P);                  { no answer: AA again, same FCB: held }
  FTap.Pump;
  AssertEquals('AA repeated', 1, FLink.Repeats);
  FTap.HoldA := False;
  FTap.HoldB := False;
  FTap.Release;                        { the answer to the master, the repetition to the secondary }
  AssertTrue('AA answered', FT12PrimaryStep(P));
  AssertEquals(res_Ok, P.Result);
  Data($BB);
  AssertTrue(FT12PrimaryStart(P, FM, FLink, Req, 5, TimeoutMs, 2));
  FTap.DropA := 1;                     { what goes out now is lost }
  FTap.Pump;
  FT12StationStep(FSt);                { the repetition of AA: the cached answer }
  FTap.Pump;
  AssertFalse('a late answer confirms nothing', FT12PrimaryStep(P));
  AssertEquals('the late answer is recognised', 1, FLink.Stale);
  Until_ := GetTickCount64 + 3000;
  while not FT12PrimaryStep(P) and (GetTickCount64 < Until_) do
  begin
    Idle(Self);
    Sleep(1);
  end;
  AssertEquals('BB confirmed', res_Ok, P.Result);
  AssertEquals('only once the secondary took it; each once', 'AA | BB', FUserData);
  AssertEquals(1, FLink.Fences);
end;

{ Another station's frame and the answer in one chunk: one step of the
  stepped primary takes both and is done. }
procedure TTestChnFT12Link.TestOneStepTakesEverythingReceived;
var
  P: tFT12Primary;
  Req: tSendRecord;
begin
  SetUpPair;
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpShortM;
  Req.FC := FCM_ReqLinkState;
  AssertTrue(FT12PrimaryStart(P, FM, FLink, Req, 4, 1000, 0));
  FTap.Pump;
  { status of link from station 6 ($0B+$06 = $11), then from 5 }
  FTap.InjectToA('10 0B 06 11 16 10 0B 05 10 16');
  AssertTrue('done in one step', FT12PrimaryStep(P));
  AssertEquals(res_Ok, P.Result);
  AssertEquals(FCS_LinkSAccesReq, P.Rep.FC);
  AssertEquals(1, FLink.Ignored);
end;

procedure TTestChnFT12Link.TestReplyFromWrongAddressOrGarbledIgnored;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  FStepSlave := False;
  { status of link from station 6 ($0B+$06 = $11): not ours }
  FInject := '10 0B 06 11 16';
  AssertEquals(res_Timeout, Fixed(FCM_ReqLinkState, Rep, 0));
  AssertTrue(FLink.Ignored >= 1);
  AssertEquals('from another address', 1, FLink.OtherAddr);
  AssertEquals(6, FLink.OtherLast);
  AssertEquals(' — 1 frames from link address 6 ignored',
    FT12IgnoredText(FLink.OtherAddr, FLink.OtherLast, 0));
  { wrong station, a garbled frame (sum $11 for $10), then station 5; on
    a new link record (the old one waits for the first request's answer) }
  FT12LinkInit(FLink, 5);
  FInject := '10 0B 06 11 16 10 0B 05 11 16 10 0B 05 10 16';
  AssertEquals(res_Ok, Fixed(FCM_ReqLinkState, Rep, 0));
  AssertEquals(4, FRepLen);
  AssertEquals(FCS_LinkSAccesReq, Rep.FC);
  AssertEquals(2, FLink.Ignored);
  AssertEquals('the garbled one is not from another address', 1, FLink.OtherAddr);
  AssertEquals('', FT12IgnoredText(0, 0, 0));
  AssertEquals(' — 3 frames with this station''s own DIR bit ignored', FT12IgnoredText(0, 0, 3));
  AssertEquals(' — 2 frames from link address 65535 ignored — 1 frames with this station''s own DIR bit ignored',
    FT12IgnoredText(2, 65535, 1));
end;

procedure TTestChnFT12Link.TestReplyNotFittingTheFunction;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  FStepSlave := False;
  { status of link asked, ACK (10 00 05 05 16) comes: a late answer to an
    earlier request, not the answer to this one }
  FInject := '10 00 05 05 16';
  AssertEquals(res_Timeout, Fixed(FCM_ReqLinkState, Rep, 0));
  AssertEquals('taken for a late answer', 1, FLink.Stale);
  FT12LinkInit(FLink, 5);              { the status answer it waited for is not coming }
  { a reset answered by user data: not a reset, the link stays not reset }
  FInject := '68 03 03 68 08 05 03 10 16';
  AssertEquals(res_BadMessage, FT12ResetLink(FM, FLink, TimeoutMs, 0, @Idle, Self));
  AssertFalse(FLink.Reset);
  { a reset refused with NACK (10 01 05 06 16) }
  FInject := '10 01 05 06 16';
  AssertEquals(res_BadMessage, FT12ResetLink(FM, FLink, TimeoutMs, 0, @Idle, Self));
  AssertFalse(FLink.Reset);
end;

procedure TTestChnFT12Link.TestBroadcastAndNoReply;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  Len: Word;
  T0: QWord;
begin
  SetUpPair;
  FT12LinkInit(FLink, 255);
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpLongM;
  Req.FC := FCM_UserDataNoRep;
  Req.Data[1] := $11;
  T0 := GetTickCount64;
  Len := 99;
  AssertEquals(res_Ok, FT12Transact(FM, FLink, Req, 5, Rep, Len, 1000, 2, @Idle, Self));
  AssertTrue('does not wait for a reply', GetTickCount64 - T0 < 500);
  AssertEquals(0, Len);
  Settle;
  { $44 = PRM + FC 4, FCV 0 although the link was never reset; L = 1+1+1;
    $44+$FF+$11 = $154 }
  AssertEquals('68 03 03 68 44 FF 11 54 16', FTap.Lines('A'));
  AssertEquals('nobody answers a broadcast', '', FTap.Lines('B'));
  AssertEquals('noreply 11', FUserData);
  { broadcast is SEND/NO REPLY only: nothing goes out }
  FTap.Log.Clear;
  Req.FC := FCM_UserDataReply;
  AssertEquals(res_BadMessage, FT12Transact(FM, FLink, Req, 5, Rep, Len, TimeoutMs, 2, @Idle, Self));
  Req.MessType := tpShortM;
  Req.FC := FCM_ReqLinkState;
  AssertEquals(res_BadMessage, FT12Transact(FM, FLink, Req, 4, Rep, Len, TimeoutMs, 2, @Idle, Self));
  Settle;
  AssertEquals('', FTap.Lines('A'));
  { FC 4 to one station: no reply either ($44+$05+$22 = $6B) }
  FT12LinkInit(FLink, 5);
  Req.MessType := tpLongM;
  Req.FC := FCM_UserDataNoRep;
  Req.Data[1] := $22;
  AssertEquals(res_Ok, FT12Transact(FM, FLink, Req, 5, Rep, Len, TimeoutMs, 2, @Idle, Self));
  Settle;
  AssertEquals('68 03 03 68 44 05 22 6B 16', FTap.Lines('A'));
  AssertEquals('', FTap.Lines('B'));
  AssertEquals('noreply 11 | noreply 22', FUserData);
end;

procedure TTestChnFT12Link.TestSlaveRefusesBeforeReset;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  { pretend the master reset the link, so that it sends FC 3 straight on }
  FLink.Reset := True;
  FLink.Fcb := True;
  AssertEquals(res_Ok, SendData('AA BB CC', Rep));
  { NACK, message not accepted: 10 01 05 06 16 }
  AssertEquals('10 01 05 06 16', FTap.Lines('B'));
  AssertEquals(FCS_NackBusy, Rep.FC);
  AssertEquals(0, FUserCalls);
  AssertEquals(1, FSt.Refused);
  AssertFalse(FSt.LinkReset);
  { reset, then the same data is taken }
  FTap.Log.Clear;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  AssertEquals(res_Ok, SendData('AA BB CC', Rep));
  AssertEquals(FCS_Ack, Rep.FC);
  AssertEquals(1, FUserCalls);
  AssertEquals('10 00 05 05 16 | 10 00 05 05 16', FTap.Lines('B'));
end;

procedure TTestChnFT12Link.TestRepeatRightAfterResetGetsTheResetAck;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  FSt.Dfc := True;      { DFC in every reply: $10 }
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  AssertTrue(FLink.Dfc);
  { after a reset the secondary expects FCB = 1; FCB = 0 is a repetition
    of the reset and gets its ACK again (10 10 05 15 16), not executed }
  FLink.Fcb := False;
  FTap.Log.Clear;
  AssertEquals(res_Ok, SendData('AA', Rep));
  AssertEquals('68 03 03 68 53 05 AA 02 16', FTap.Lines('A'));
  AssertEquals('10 10 05 15 16', FTap.Lines('B'));
  AssertEquals(0, FUserCalls);
  AssertEquals(1, FSt.Repeats);
end;

procedure TTestChnFT12Link.TestStatusOfLinkWithAcd;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  { FC 9 needs no reset: $49+$05 = $4E; status of link $0B+$05 = $10 }
  AssertEquals(res_Ok, Fixed(FCM_ReqLinkState, Rep));
  AssertEquals(FCS_LinkSAccesReq, Rep.FC);
  AssertFalse(FLink.Acd);
  SetLength(FClass1, 1);
  FClass1[0] := '07';
  AssertEquals(res_Ok, Fixed(FCM_ReqLinkState, Rep));
  { ACD: $2B, sum $30 }
  AssertTrue(FLink.Acd);
  AssertEquals('10 49 05 4E 16 | 10 49 05 4E 16', FTap.Lines('A'));
  AssertEquals('10 0B 05 10 16 | 10 2B 05 30 16', FTap.Lines('B'));
  AssertEquals(0, FSt.Executed);
end;

procedure TTestChnFT12Link.TestUnknownFunctionAndGarbledFrame;
var
  Rep: tRecRecord;
  Frames: LongInt;
begin
  SetUpPair;
  { FC 5 is not a standard function: "link service not implemented",
    FC 15: $0F+$05 = $14 }
  AssertEquals(res_Ok, Fixed(5, Rep));
  AssertEquals(FCS_NotImplemented, Rep.FC);
  AssertEquals('10 45 05 4A 16', FTap.Lines('A'));
  AssertEquals('10 0F 05 14 16', FTap.Lines('B'));
  { a garbled request (sum $4F for $4E) is taken and not answered }
  FTap.Log.Clear;
  Frames := FSt.Frames;
  FTap.InjectToB('10 49 05 4F 16');
  Settle;
  AssertEquals(Frames + 1, FSt.Frames);
  AssertEquals('', FTap.Lines('B'));
end;

procedure TTestChnFT12Link.TestSingleCharacterAck;
var
  Rep: tRecRecord;
begin
  SetUpPair;
  FSt.SingleAck := True;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  AssertTrue(FLink.Reset);
  AssertEquals(res_Ok, SendData('AA', Rep));
  AssertTrue(Rep.MessType = tpSACK);
  { with class 1 data waiting the ACK must carry ACD: a fixed frame $20 }
  SetLength(FClass1, 1);
  FClass1[0] := '07';
  AssertEquals(res_Ok, SendData('AA', Rep));
  AssertTrue(Rep.MessType = tpShortM);
  AssertEquals('E5 | E5 | 10 20 05 25 16', FTap.Lines('B'));
  AssertTrue(FLink.Acd);
end;

procedure TTestChnFT12Link.TestErrorsReturnedAtOnce;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  Len: Word;
  T0: QWord;
  St: tFT12Station;
  L1, L2: pChnVirt;
  Err: string;
  B: array[0..0] of Byte;
begin
  SetUpPair;
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpShortM;
  Req.FC := FCM_ReqLinkState;
  AssertEquals(res_BadParam, FT12Transact(FM, FLink, Req, 4, Rep, Len, TimeoutMs, -1));
  AssertEquals(res_BadParam, FT12Transact(FM, FLink, Req, 4, Rep, Len, 0, 1));
  AssertEquals(res_BadParam, FT12RequestClass(FM, FLink, 3, Rep, Len, TimeoutMs, 1));
  { not an FT 1.2 master }
  AssertEquals(res_BadMessage, FT12Transact(FS, FLink, Req, 4, Rep, Len, TimeoutMs, 1));
  Req.MessType := tpSACK;
  AssertEquals(res_BadMessage, FT12Transact(FM, FLink, Req, 1, Rep, Len, TimeoutMs, 1));
  PByte(@Req)^ := 7;
  AssertEquals(res_BadMessage, FT12Transact(FM, FLink, Req, 4, Rep, Len, TimeoutMs, 1));
  Req.MessType := tpShortM;
  { a fixed frame of the wrong length: the channel's send error }
  AssertEquals(res_BadLen, FT12Transact(FM, FLink, Req, 5, Rep, Len, TimeoutMs, 1));
  { the channel cannot send: its result at once, no retries }
  { a station on a channel that is no tChnFT1_2 reads nothing, even with
    bytes waiting; and one without a channel does nothing }
  L1 := OpenStack(ChnLoop.cName, 'PAIR=LKX END=1', Err);
  L2 := OpenStack(ChnLoop.cName, 'PAIR=LKX END=2', Err);
  try
    AssertTrue(Err, (L1 <> nil) and (L2 <> nil));
    B[0] := $E5;
    L2^.ChSend(@B, 1);
    AssertEquals('a primary on a LOOP stack refuses it', res_WrongLayer,
      FT12Transact(L1, FLink, Req, 4, Rep, Len, TimeoutMs, 1));
    AssertEquals('so does a class request', res_WrongLayer,
      FT12RequestClass(L1, FLink, 1, Rep, Len, TimeoutMs, 1));
    FT12StationInit(St, L1);
    AssertFalse(FT12StationStep(St));
    AssertEquals(0, St.Frames);
    AssertTrue('the byte is still there', L1^.ChReceiveReady = CHS_ReceiveReady);
    St.Chn := nil;
    AssertFalse(FT12StationStep(St));
  finally
    if L1 <> nil then
      Dispose(L1, Done);
    if L2 <> nil then
      Dispose(L2, Done);
  end;
  FM^.ChClose;
  T0 := GetTickCount64;
  AssertEquals(res_WrongState, FT12Transact(FM, FLink, Req, 4, Rep, Len, 1000, 5, @Idle, Self));
  AssertTrue(GetTickCount64 - T0 < 500);
  Settle;
  AssertEquals('nothing sent', '', FTap.Lines('A'));
end;

{ FC 3, 10 and 11 are FCV = 1 services (IEC 60870-5-2 table 2): one
  with FCV = 0 has no frame count check, a repetition would be taken
  twice - no such service (FC 15), the data are not taken. }
procedure TTestChnFT12Link.TestFcvServicesWithoutFcvRefused;
begin
  SetUpPair;
  AssertEquals(res_Ok, FT12ResetLink(FM, FLink, TimeoutMs, 2, @Idle, Self));
  FTap.Log.Clear;
  { 68 03 03 68, CODE $43 (PRM, FC 3, FCB 0, FCV 0), A 5, AA; sum $F2 }
  FTap.InjectToB('68 03 03 68 43 05 AA F2 16');
  Settle;
  AssertEquals('10 0F 05 14 16', FTap.Lines('B'));
  AssertEquals('not taken', 0, FUserCalls);
  { class 2 request without FCV: $4B + $05 = $50 }
  FTap.Log.Clear;
  FTap.InjectToB('10 4B 05 50 16');
  Settle;
  AssertEquals('10 0F 05 14 16', FTap.Lines('B'));
  AssertEquals(2, FSt.Refused);
  { with FCV (CODE $73: FCB 1, FCV 1; sum $22) the data are taken }
  FTap.Log.Clear;
  FTap.InjectToB('68 03 03 68 73 05 AA 22 16');
  Settle;
  AssertEquals(1, FUserCalls);
end;

initialization
  RegisterTest(TTestChnFT12Link);
end.
