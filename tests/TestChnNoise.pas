{ Tests of tChnNoise (unit ChnNoise, NAM=NOISE) over NAM=LOOP: parameters,
  damage at the rates asked for, replay of a seed whatever the chunk
  sizes, one direction only, and the babbling line without a layer below. }
unit TestChnNoise;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnNoise, ChnWait, TestSupport,
  StackCase;

type
  TTestChnNoise = class(TStackCase)
  private
    FNoise, FRaw: pChnVirt;
    procedure OpenPair(const NoiseParams, Pair: string);
    { send Data through the noise layer in chunks of Chunk bytes; what
      the other end of the line received }
    function Through(const Data: TBytes; Chunk: Integer): TBytes;
    { Data sent by the raw end, received through the noise layer }
    function Received(const Data: TBytes; Chunk: Integer): TBytes;
  published
    procedure TestParameters;
    procedure TestBadParametersNameTheToken;
    procedure TestCleanLineChangesNothing;
    procedure TestRatesAsAsked;
    procedure TestBitErrorsFlipOneBitEach;
    procedure TestSeedReplaysWhateverTheChunks;
    procedure TestReceiveDirection;
    procedure TestOneDirectionOnly;
    procedure TestBabblingLine;
    procedure TestLostChunks;
    procedure TestStallHoldsBothDirectionsInOrder;
    procedure TestReorderSwapsTwoChunks;
    procedure TestChunkFaultsParameters;
  end;

implementation

function Pattern(N: Integer): TBytes;
var
  I: Integer;
begin
  SetLength(Result, N);
  for I := 0 to N - 1 do
    Result[I] := Byte(I * 7 + I div 256);
end;

function Same(const A, B: TBytes): Boolean;
begin
  Result := (Length(A) = Length(B)) and
    ((Length(A) = 0) or CompareMem(@A[0], @B[0], Length(A)));
end;

procedure Append(var R: TBytes; const Got: TBytes);
begin
  if Length(Got) = 0 then
    Exit;
  SetLength(R, Length(R) + Length(Got));
  Move(Got[0], R[Length(R) - Length(Got)], Length(Got));
end;

procedure TTestChnNoise.OpenPair(const NoiseParams, Pair: string);
begin
  CloseStacks;
  FNoise := Stack('NOISE', 'NAM=NOISE ' + NoiseParams + ' NAM=LOOP PAIR=' + Pair +
    ' END=1 LRB=65000 IDL=0');
  FRaw := Stack('LOOP', 'NAM=LOOP PAIR=' + Pair + ' END=2 LRB=65000 IDL=0');
end;

{ everything C has (an in-memory line delivers at once) }
function Drain(C: pChnVirt): TBytes;
var
  Buf: array[0..4095] of Byte;
  Len: Word;
  N, Idle: Integer;
begin
  SetLength(Result, 0);
  C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Idle := 0;
  N := 0;
  while Idle < 5 do
  begin
    if C^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      C^.ChReceive(Len);
      if Len > 0 then
      begin
        SetLength(Result, N + Len);
        Move(Buf, Result[N], Len);
        Inc(N, Len);
        Idle := 0;
        Continue;
      end;
    end;
    Inc(Idle);
  end;
end;

function SendAll(From, Into: pChnVirt; const Data: TBytes; Chunk: Integer): TBytes;
var
  P, N: Integer;
begin
  SetLength(Result, 0);
  P := 0;
  while P < Length(Data) do
  begin
    N := Length(Data) - P;
    if N > Chunk then
      N := Chunk;
    if not WaitSent(From, 2000) then
      raise Exception.Create('send never ready');
    From^.ChSend(@Data[P], N);
    if From^.ChSendResult <> res_Ok then
      raise Exception.Create('send failed: ' + From^.ChResultStr(From^.ChSendResult));
    Inc(P, N);
    Append(Result, Drain(Into));
  end;
end;

function TTestChnNoise.Through(const Data: TBytes; Chunk: Integer): TBytes;
begin
  Result := SendAll(FNoise, FRaw, Data, Chunk);
end;

function TTestChnNoise.Received(const Data: TBytes; Chunk: Integer): TBytes;
begin
  Result := SendAll(FRaw, FNoise, Data, Chunk);
end;

procedure TTestChnNoise.TestParameters;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('NOISE');
  try
    AssertEquals('defaults', 'NAM=NOISE BER=0 DRP=0 INS=0 BYTE=RND CNT=0 DIR=BOTH SEED=1',
      C^.ChGetParam(''));
    C^.ChSetParam('NAM=NOISE BER=1E-5 DRP=0.01 INS=.5 BYTE=16 CNT=7 DIR=RX SEED=42');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('NAM=NOISE BER=0.00001 DRP=0.01 INS=0.5 BYTE=16 CNT=7 DIR=RX SEED=42',
      C^.ChGetParam(''));
    C^.ChSetParam(C^.ChGetParam(''));
    AssertEquals('round trip', 'NAM=NOISE BER=0.00001 DRP=0.01 INS=0.5 BYTE=16 CNT=7 DIR=RX SEED=42',
      C^.ChGetParam(''));
    C^.ChSetParam('NAM=NOISE DIR=TX BYTE=rnd BER=1');
    AssertEquals('DIR=TX', C^.ChGetParam('DIR'));
    AssertEquals('BYTE=RND', C^.ChGetParam('BYTE'));
    AssertEquals('BER=1', C^.ChGetParam('BER'));
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnNoise.TestBadParametersNameTheToken;
const
  Bad: array[0..9] of string = ('BER=2', 'BER=-0.1', 'DRP=abc', 'INS=1E-5x',
    'BER=1E', 'BYTE=256', 'DIR=UP', 'SEED=-1', 'CNT=-1', 'BER=$10');
var
  C: pChnVirt;
  I: Integer;
begin
  C := ChnCollection^.ChNewInit('NOISE');
  try
    for I := Low(Bad) to High(Bad) do
    begin
      C^.ChSetParam('NAM=NOISE ' + Bad[I]);
      AssertTrue(Bad[I] + ' refused', C^.ChResult <> res_Ok);
      AssertEquals(Bad[I] + ' named', Bad[I], C^.ChParamError);
      AssertEquals(Bad[I] + ' changed nothing', 'BER=0', C^.ChGetParam('BER'));
    end;
    { a rate says what it takes }
    C^.ChSetParam('NAM=NOISE DRP=2');
    AssertEquals('bad parameter (DRP=2): a probability 0..1 (0.01, 1E-5)', C^.ChErrorText);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnNoise.TestCleanLineChangesNothing;
var
  D: TBytes;
begin
  OpenPair('SEED=3', 'NZC');
  D := Pattern(5000);
  AssertTrue('sent unchanged', Same(D, Through(D, 300)));
  AssertTrue('received unchanged', Same(D, Received(D, 300)));
end;

procedure TTestChnNoise.TestRatesAsAsked;
const
  N = 200000;
var
  D, Got: TBytes;
  Z: pChnNoise;
begin
  OpenPair('SEED=11 BER=1E-3 DRP=0.01 INS=0.02', 'NZR');
  D := Pattern(N);
  Got := Through(D, 4000);
  Z := pChnNoise(FNoise);
  AssertTrue('dropped ' + IntToStr(Z^.CH_Dropped), (Z^.CH_Dropped > N * 0.008) and (Z^.CH_Dropped < N * 0.012));
  AssertTrue('inserted ' + IntToStr(Z^.CH_Inserted), (Z^.CH_Inserted > N * 0.017) and (Z^.CH_Inserted < N * 0.023));
  AssertTrue('bits flipped ' + IntToStr(Z^.CH_Flipped),
    (Z^.CH_Flipped > N * 8 * 0.0008) and (Z^.CH_Flipped < N * 8 * 0.0012));
  AssertEquals('what arrived', Int64(N - Z^.CH_Dropped + Z^.CH_Inserted), Int64(Length(Got)));
end;

{ BER is per bit: each of a byte's 8 bits flips on its own, so at 1E-3
  about N * 8 * BER bytes are damaged, nearly all of them in exactly one
  bit. (The flip count alone cannot tell: 8 bits flipping together as
  often as one flips alone gives the same count, in 8 times fewer bytes.) }
procedure TTestChnNoise.TestBitErrorsFlipOneBitEach;
const
  N = 200000;
  Ber = 1E-3;
var
  D, Got: TBytes;
  I, Damaged, OneBit: Integer;
  X: Byte;
begin
  OpenPair('SEED=23 BER=1E-3', 'NZB');
  D := Pattern(N);
  Got := Through(D, 4000);
  AssertEquals('no byte lost or added', N, Length(Got));
  Damaged := 0;
  OneBit := 0;
  for I := 0 to N - 1 do
    if Got[I] <> D[I] then
    begin
      Inc(Damaged);
      X := Got[I] xor D[I];
      if X and (X - 1) = 0 then
        Inc(OneBit);
    end;
  AssertTrue(Format('%d damaged bytes, about %d expected', [Damaged, Round(N * 8 * Ber)]),
    (Damaged > N * 8 * Ber * 0.85) and (Damaged < N * 8 * Ber * 1.15));
  AssertTrue(Format('%d of %d damaged bytes differ in one bit', [OneBit, Damaged]),
    OneBit >= Damaged * 0.98);
end;

procedure TTestChnNoise.TestSeedReplaysWhateverTheChunks;
var
  D, A, B, C: TBytes;
begin
  D := Pattern(20000);
  OpenPair('SEED=99 BER=1E-3 DRP=0.01 INS=0.01', 'NZS');
  A := Through(D, 1);
  AssertFalse('damaged', Same(A, D));
  OpenPair('SEED=99 BER=1E-3 DRP=0.01 INS=0.01', 'NZS');
  B := Through(D, 3000);
  AssertTrue('same seed, other chunks: same bytes', Same(A, B));
  OpenPair('SEED=100 BER=1E-3 DRP=0.01 INS=0.01', 'NZS');
  C := Through(D, 3000);
  AssertFalse('another seed: other bytes', Same(A, C));
  { a reconnect starts the stream over }
  OpenPair('SEED=99 BER=1E-3 DRP=0.01 INS=0.01', 'NZS');
  Through(D, 500);
  FNoise^.ChDisConnect;
  FNoise^.ChConnect;
  AssertTrue('after ChConnect: the same again', Same(A, Through(D, 777)));
end;

procedure TTestChnNoise.TestReceiveDirection;
var
  D, A, B: TBytes;
begin
  D := Pattern(20000);
  OpenPair('SEED=5 DRP=0.05 INS=0.05 BER=1E-3', 'NZX');
  A := Received(D, 1000);
  AssertFalse('received damaged', Same(A, D));
  OpenPair('SEED=5 DRP=0.05 INS=0.05 BER=1E-3', 'NZX');
  B := Received(D, 37);
  AssertTrue('replayed', Same(A, B));
end;

procedure TTestChnNoise.TestOneDirectionOnly;
var
  D: TBytes;
begin
  D := Pattern(20000);
  OpenPair('SEED=5 DRP=0.05 DIR=RX', 'NZD');
  AssertTrue('DIR=RX: sent unchanged', Same(D, Through(D, 1000)));
  AssertFalse('DIR=RX: received damaged', Same(D, Received(D, 1000)));
  OpenPair('SEED=5 DRP=0.05 DIR=TX', 'NZD');
  AssertFalse('DIR=TX: sent damaged', Same(D, Through(D, 1000)));
  AssertTrue('DIR=TX: received unchanged', Same(D, Received(D, 1000)));
end;

procedure TTestChnNoise.TestBabblingLine;
var
  Got: TBytes;
  B: Byte;
  I: Integer;
begin
  FNoise := Stack('NOISE', 'NAM=NOISE BYTE=0 CNT=10');
  B := 1;
  FNoise^.ChSend(@B, 1);
  AssertEquals('a send is swallowed', res_Ok, FNoise^.ChSendResult);
  Got := Drain(FNoise);
  AssertEquals('CNT bytes', 10, Length(Got));
  for I := 0 to 9 do
    AssertEquals('BYTE=0', 0, Got[I]);
  AssertFalse('then silence', FNoise^.ChReceiveReady = CHS_ReceiveReady);
end;

{ text of the bytes, for messages }
function Txt(const B: TBytes): string;
var
  I: Integer;
begin
  Result := '';
  for I := 0 to High(B) do
    Result := Result + Chr(B[I]);
end;

function Bytes(const S: string): TBytes;
begin
  SetLength(Result, Length(S));
  if S <> '' then
    Move(S[1], Result[0], Length(S));
end;

procedure TTestChnNoise.TestLostChunks;
var
  Got: TBytes;
  I: Integer;
begin
  OpenPair('LOS=1 SEED=5', 'NZLOS1');
  Got := Through(Bytes('frame one'), 100);
  AssertEquals('a lost chunk is lost whole', 0, Length(Got));
  AssertEquals(1, pChnNoise(FNoise)^.CH_ChunksLost);
  { a quarter of 400 chunks, each whole or not at all }
  OpenPair('LOS=0.25 SEED=6', 'NZLOS2');
  for I := 1 to 400 do
  begin
    Got := Through(Bytes('abcd'), 100);
    AssertTrue('whole or nothing', (Length(Got) = 0) or (Txt(Got) = 'abcd'));
  end;
  I := pChnNoise(FNoise)^.CH_ChunksLost;
  AssertTrue(Format('about 25 %% lost: %d of 400', [I]), (I > 60) and (I < 140));
end;

procedure TTestChnNoise.TestStallHoldsBothDirectionsInOrder;
var
  Got, Back: TBytes;
  T0: QWord;
  Len: Word;
  Buf: array[0..63] of Byte;
begin
  OpenPair('STL=1 STM=150 SEED=7', 'NZSTL');
  T0 := GetTickCount64;
  Got := Through(Bytes('first'), 100);     { the line stalls before it }
  AssertEquals('held by the stall', 0, Length(Got));
  Got := Through(Bytes('second'), 100);
  AssertEquals('still held', 0, Length(Got));
  SendAll(FRaw, FNoise, Bytes('reply'), 100);
  FNoise^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  AssertTrue('nothing arrives during a stall',
    FNoise^.ChReceiveReady <> CHS_ReceiveReady);
  while GetTickCount64 - T0 < 170 do
    Sleep(5);
  { the stall is over: what was held goes on, in order; the next chunk
    after the stall may stall again (STL=1), so look before sending more }
  Back := Drain(FNoise);
  AssertEquals('input held by the stall comes after it', 'reply', Txt(Back));
  FNoise^.ChSendReady;
  Got := Drain(FRaw);
  AssertEquals('sent chunks go on in order', 'firstsecond', Txt(Got));
  AssertTrue(pChnNoise(FNoise)^.CH_Stalls >= 1);
  Len := 0;
  FNoise^.ChReceive(Len);
  AssertEquals('nothing held any more', 0, ChnWaitHeldCount);
end;

procedure TTestChnNoise.TestReorderSwapsTwoChunks;
var
  Got: TBytes;
begin
  OpenPair('ROR=1 STM=5000 SEED=8', 'NZROR');
  Got := Through(Bytes('A'), 100);
  AssertEquals('held back', 0, Length(Got));
  Got := Through(Bytes('B'), 100);        { goes, then the held one }
  AssertEquals('B then A', 'BA', Txt(Got));
  AssertEquals(1, pChnNoise(FNoise)^.CH_Reordered);
  { a chunk held back with nothing after it goes at the latest STM later }
  OpenPair('ROR=1 STM=50 SEED=8', 'NZROR2');
  Got := Through(Bytes('C'), 100);
  AssertEquals(0, Length(Got));
  Sleep(70);
  FNoise^.ChSendReady;
  AssertEquals('C', Txt(Drain(FRaw)));
end;

procedure TTestChnNoise.TestChunkFaultsParameters;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('NOISE');
  try
    C^.ChSetParam('LOS=0.1 STL=0.01 STM=1300 ROR=0.02');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('reported when used', 'NAM=NOISE BER=0 DRP=0 INS=0 LOS=0.1 STL=0.01 ROR=0.02 STM=1300 ' +
      'BYTE=RND CNT=0 DIR=BOTH SEED=1', C^.ChGetParam(''));
    C^.ChSetParam('STM=0');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('STM=0', C^.ChParamError);
    C^.ChSetParam('ROR=2');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('ROR=2', C^.ChParamError);
  finally
    Dispose(C, Done);
  end;
end;

initialization
  RegisterTest(TTestChnNoise);
end.
