{ Replay of two captures of examples/ft12balanced against lib60870-C
  (tests/data/ft12bal-lib60870-*.trc, written by the NAM=TRC layer under
  ft12balanced; how they were made: docs/ChnFT1_2.md). CI has no
  lib60870: the captures stand in for it, in both directions.

  * peer -> us: lib60870's requests, in order, go to a tFT12Balanced set
    up as our station was; its answers must be the bytes our station sent
    then (the secondary is deterministic: same requests, same answers).
  * us -> peer: our requests go to a tFT12Balanced set up as lib60870 was;
    its answers must be of the kind lib60870 gave (ACK as E5 or fixed
    FC 0, status of link FC 11, ...).
  * every frame of either side is taken by the receiving configuration
    without a broken frame, a wrong DIR or an ignored answer;
  * the capture holds what the interoperability check asked for: more
    than a minute of traffic, test functions, a general interrogation
    confirmed (COT 7) and terminated (COT 10), user data acknowledged. }
unit TestFT12Lib60870Replay;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnFT1_2,
  ChnFT12Codec, ChnFT12Balanced, ChnTrcFormat, TestSupport, TestTempDir, Ft12Capture;

type
  TTestFT12Lib60870Replay = class(TTestCase)
  private
    FUs, FRaw: pChnVirt;
    FL: tFT12Balanced;
    function Load(const Name: string): TCapFrames;
    { feed the requests of one side to a station set up with Params; the
      answers it gives, as hex or (Kinds) as kinds }
    function Answers(const F: TCapFrames; FromUs: Boolean; const Params: string;
      Kinds: Boolean): string;
    procedure CheckCapture(const Name, OurParams, PeerParams: string;
      WeConfirmGI: Boolean);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestBalancedMasterExample;
    procedure TestBalancedSlaveExample;
  end;

implementation

const
  DataDir = 'tests/data/';

function OnUser(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
begin
  Result := True;
end;

{ 'ACK' for E5 and a fixed FC 0 (both confirm), else 'FC n'. }
function KindOf(Kind: tMessType; FC: Byte): string;
begin
  if (Kind = tpSACK) or ((Kind = tpShortM) and (FC = 0)) then
    Result := 'ACK'
  else if Kind = tpSNAK then
    Result := 'NAK'
  else
    Result := 'FC ' + IntToStr(FC);
end;

procedure TTestFT12Lib60870Replay.SetUp;
begin
  FUs := nil;
  FRaw := nil;
end;

procedure TTestFT12Lib60870Replay.TearDown;
begin
  if FUs <> nil then
    Dispose(FUs, Done);
  if FRaw <> nil then
    Dispose(FRaw, Done);
  FUs := nil;
  FRaw := nil;
end;

function TTestFT12Lib60870Replay.Load(const Name: string): TCapFrames;
begin
  AssertTrue(DataDir + Name + ' missing', FileExists(DataDir + Name));
  Result := CapLoad(DataDir + Name);
  AssertTrue('frames', Length(Result) > 10);
end;

function TTestFT12Lib60870Replay.Answers(const F: TCapFrames; FromUs: Boolean;
  const Params: string; Kinds: Boolean): string;
var
  Err: string;
  I, K, N0: Integer;
  Buf: array[0..1023] of Byte;
  Got: TBytes;
  Ans: TCapFrames;
  B: TBytes;
begin
  Result := '';
  FUs := OpenStack(ChnFT1_2.cName, Params + ' NAM=LOOP PAIR=RPL END=1', Err);
  AssertTrue(Err, FUs <> nil);
  FRaw := OpenStack(ChnLoop.cName, 'PAIR=RPL END=2', Err);
  AssertTrue(Err, FRaw <> nil);
  AssertEquals(res_Ok, FT12BalancedInit(FL, FUs));
  FL.OnUserData := @OnUser;
  FL.TestMs := 0;
  FL.TimeoutMs := 60000;        { its own requests go unanswered: no repeats }
  FRaw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Got := nil;
  for I := 0 to High(F) do
    if (F[I].Tx = FromUs) and F[I].Prm then
    begin
      B := HexToBytes(F[I].Hex);
      FRaw^.ChSend(@B[0], Length(B));
      N0 := FL.Frames;
      for K := 1 to 200 do
      begin
        FT12BalancedStep(FL);
        if FL.Frames > N0 then
          Break;
        Sleep(1);
      end;
      AssertEquals('request taken: ' + F[I].Hex, N0 + 1, FL.Frames);
      ReceiveAllInto(FRaw, @Buf, Got);
    end;
  AssertEquals('broken', 0, FL.Broken);
  AssertEquals('wrong DIR', 0, FL.BadDir);
  Ans := nil;
  CapSplit(Got, True, [], Ans);
  for I := 0 to High(Ans) do
    if not Ans[I].Prm then
    begin
      if Result <> '' then
        Result := Result + ' | ';
      if Kinds then
        Result := Result + KindOf(Ans[I].Kind, Ans[I].FC)
      else
        Result := Result + Ans[I].Hex;
    end;
  Dispose(FUs, Done);
  Dispose(FRaw, Done);
  FUs := nil;
  FRaw := nil;
end;

procedure TTestFT12Lib60870Replay.CheckCapture(const Name, OurParams,
  PeerParams: string; WeConfirmGI: Boolean);
var
  F: TCapFrames;
  I: Integer;
  OurAns, PeerKinds, Cot: string;
  Tests, ActCon, ActTerm, Values: Integer;
begin
  F := Load(Name);
  { more than a minute of traffic }
  AssertTrue('a minute', F[High(F)].TimeMs - F[0].TimeMs > 60000);
  { what each side answered in the capture }
  OurAns := '';
  PeerKinds := '';
  Tests := 0;
  ActCon := 0;
  ActTerm := 0;
  Values := 0;
  for I := 0 to High(F) do
  begin
    if not F[I].Prm then
      if F[I].Tx then
      begin
        if OurAns <> '' then OurAns := OurAns + ' | ';
        OurAns := OurAns + F[I].Hex;
      end
      else
      begin
        if PeerKinds <> '' then PeerKinds := PeerKinds + ' | ';
        PeerKinds := PeerKinds + KindOf(F[I].Kind, F[I].FC);
      end;
    if F[I].Prm and (F[I].FC = FCM_CheckLink) then
      Inc(Tests);
    if F[I].Prm and (F[I].FC = FCM_UserDataReply) and (Length(F[I].Data) >= 10) then
    begin
      Cot := IntToStr(F[I].Data[2] and $3F);
      { the interrogation's confirmation and termination come from the
        side that was asked }
      if (F[I].Data[0] = 100) and (F[I].Tx = WeConfirmGI) then
      begin
        if Cot = '7' then Inc(ActCon);
        if Cot = '10' then Inc(ActTerm);
      end;
      { our measured values }
      if F[I].Tx and (F[I].Data[0] = 11) then
        Inc(Values);
    end;
  end;
  AssertTrue('test functions', Tests >= 5);
  AssertEquals('interrogation confirmed', 1, ActCon);
  AssertEquals('interrogation terminated', 1, ActTerm);
  AssertTrue('measured values sent', Values >= 5);
  { peer -> us: the same answers, byte for byte }
  AssertEquals('our answers', OurAns, Answers(F, False, OurParams, False));
  { us -> peer: answers of the same kind as lib60870's }
  AssertEquals('lib60870''s answers', PeerKinds, Answers(F, True, PeerParams, True));
end;

procedure TTestFT12Lib60870Replay.TestBalancedMasterExample;
begin
  { lib60870 cs101_master_balanced: own address 2, DIR = 1; we are 3, B }
  CheckCapture('ft12bal-lib60870-master.trc',
    'NAM=FT1_2 MS=OFF NOD=3 DNO=2 DIR=0 LEN=0',
    'NAM=FT1_2 MS=OFF NOD=2 DNO=3 DIR=1 LEN=0', True);
end;

procedure TTestFT12Lib60870Replay.TestBalancedSlaveExample;
begin
  { lib60870 cs101_slave in balanced mode: own address 1, DIR = 0; we are
    3, station A, and ask the general interrogation }
  CheckCapture('ft12bal-lib60870-slave.trc',
    'NAM=FT1_2 MS=OFF NOD=3 DNO=1 DIR=1 LEN=0',
    'NAM=FT1_2 MS=OFF NOD=1 DNO=3 DIR=0 LEN=0', False);
end;

initialization
  RegisterTest(TTestFT12Lib60870Replay);
end.
