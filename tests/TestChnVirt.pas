{ Tests of ChnVirt: registry, parameter strings, stacking, life cycle.
  Uses the pass-through test layer NAM=TSTP (tests/support/ChnTestLayer)
  over the in-memory null modem NAM=LOOP. }
unit TestChnVirt;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnTestLayer,
  TestSupport;

type
  TTestChnVirt = class(TTestCase)
  private
    Chn: pChnVirt;
    procedure SetParamExpect(const S: string; Expected: tChResult; const BadToken: string);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestMicrosecondClock;
    procedure TestEveryRegisteredNameCreatesItsLayer;
    procedure TestUnknownNameGivesNil;
    procedure TestNumNameIsStableAndCaseBlind;
    procedure TestGeneralKeys;
    procedure TestMalformedNumbers;
    procedure TestOutOfRange;
    procedure TestUnknownKey;
    procedure TestDuplicatedKey;
    procedure TestEmptyStringChangesNothing;
    procedure TestMaximumLengthString;
    procedure TestFusedTokenIsAnError;
    procedure TestTokenWithoutValue;
    procedure TestBadTokenKeepsPreviousConfiguration;
    procedure TestBadTokenInLowerLayerKeepsStack;
    procedure TestUnknownLowerLayer;
    procedure TestPhysicalLayerCannotHaveLower;
    procedure TestStackTwoLayersAndRoundTrip;
    procedure TestSameTypeTwiceMakesTwoLayers;
    procedure TestGetParamKeyFilter;
    procedure TestGetParamLongerThan255;
    procedure TestChInitParamConstructor;
    procedure TestSwapStackWhileOpenIsRefused;
    procedure TestChangeOwnParamWhileOpenKeepsStack;
    procedure TestLifeCycleWrongOrder;
    procedure TestOpenWithoutLowerLayer;
    procedure TestDisposeOpenStack;
    procedure TestResultTextOfLayer;
    procedure TestMiddleLayerHandsAddressingDown;
  end;

implementation

procedure TTestChnVirt.SetUp;
begin
  Chn := ChnCollection^.ChNewInit('TSTP');
end;

procedure TTestChnVirt.TearDown;
begin
  if Chn <> nil then
    Dispose(Chn, Done);
  Chn := nil;
end;

procedure TTestChnVirt.SetParamExpect(const S: string; Expected: tChResult;
  const BadToken: string);
begin
  Chn^.ChSetParam(S);
  AssertEquals('result of "' + S + '"', Expected, Chn^.ChResult);
  AssertEquals('offending token of "' + S + '"', BadToken, Chn^.ChParamError);
end;

procedure TTestChnVirt.TestEveryRegisteredNameCreatesItsLayer;
var
  I: Integer;
  P: pChnVirt;
  Name: string;
begin
  AssertTrue('LOOP and TSTP at least', ChnCollection^.Count >= 2);
  for I := 1 to ChnCollection^.Count do
  begin
    Name := ChnCollection^.Items[I]^.Name;
    P := ChnCollection^.ChNewInit(LowerCase(Name));
    AssertNotNull(Name, P);
    AssertEquals(Name, P^.CH_Type);
    AssertEquals(Name, P^.CH_Name);
    AssertEquals(Name, ChNumName(Name), P^.CH_NumName);
    AssertEquals(Name + ' starts closed', CHS_Close, P^.ChReady);
    Dispose(P, Done);
  end;
end;

procedure TTestChnVirt.TestUnknownNameGivesNil;
begin
  AssertNull(ChnCollection^.ChNewInit('NOSUCH'));
  AssertNull(ChnCollection^.ChNewInit(''));
  AssertNull(ChnCollection^.Search('LOOPX'));
end;

procedure TTestChnVirt.TestNumNameIsStableAndCaseBlind;
var
  I, J: Integer;
begin
  { CRC-16/MODBUS of the upper-cased name, values computed outside Pascal }
  AssertEquals($61C2, ChNumName('DF1'));
  AssertEquals($6F13, ChNumName('loop'));
  AssertEquals($1174, ChNumName('Com'));
  for I := 1 to ChnCollection^.Count do
    for J := I + 1 to ChnCollection^.Count do
      AssertTrue('distinct', ChNumName(ChnCollection^.Items[I]^.Name) <>
        ChNumName(ChnCollection^.Items[J]^.Name));
end;

procedure TTestChnVirt.TestGeneralKeys;
begin
  SetParamExpect('NOD=7 DNO=254', res_Ok, '');
  AssertEquals(7, Chn^.CH_Node);
  AssertEquals(254, Chn^.CH_DNode);
  SetParamExpect('nod=0 dno=$10', res_Ok, '');
  AssertEquals(0, Chn^.CH_Node);
  AssertEquals(16, Chn^.CH_DNode);
  Chn^.ChDestNode(99);
  AssertEquals(99, Chn^.CH_DNode);
  SetParamExpect('MOD=c CNT=1000 FLG=on', res_Ok, '');
  AssertEquals(2, pChnTestLayer(Chn)^.CH_Mode);
  AssertEquals(1000, pChnTestLayer(Chn)^.CH_Count);
  AssertTrue(pChnTestLayer(Chn)^.CH_Flag);
end;

procedure TTestChnVirt.TestMalformedNumbers;
begin
  SetParamExpect('NOD=1x', res_BadParam, 'NOD=1x');
  SetParamExpect('NOD=--1', res_BadParam, 'NOD=--1');
  SetParamExpect('CNT=1.5', res_BadParam, 'CNT=1.5');
  SetParamExpect('NOD=2 DNO=$', res_BadParam, 'DNO=$');
  SetParamExpect('DNO=0x10', res_BadParam, 'DNO=0x10');
  AssertEquals('nothing applied', 0, Chn^.CH_Node);
end;

procedure TTestChnVirt.TestOutOfRange;
begin
  SetParamExpect('NOD=255', res_BadParam, 'NOD=255');
  SetParamExpect('DNO=-1', res_BadParam, 'DNO=-1');
  SetParamExpect('CNT=1001', res_BadParam, 'CNT=1001');
  SetParamExpect('MOD=D', res_BadParam, 'MOD=D');
  SetParamExpect('FLG=YES', res_BadParam, 'FLG=YES');
  SetParamExpect('NAM=LOOP END=33', res_BadParam, 'END=33');
  SetParamExpect('NAM=LOOP LRB=0', res_BadParam, 'LRB=0');
  SetParamExpect('NAM=LOOP IDL=1001', res_BadParam, 'IDL=1001');
  SetParamExpect('NAM=LOOP PAIR=a/b', res_BadParam, 'PAIR=a/b');
end;

procedure TTestChnVirt.TestUnknownKey;
begin
  SetParamExpect('NOD=1 XYZ=1', res_UnknownParam, 'XYZ=1');
  SetParamExpect('NAM=LOOP NOD=1', res_UnknownParam, 'NOD=1');  { LOOP has no address }
  AssertEquals('unknown parameter key', ChResultText(res_UnknownParam));
end;

procedure TTestChnVirt.TestDuplicatedKey;
begin
  SetParamExpect('NOD=1 CNT=2 nod=1', res_DupParam, 'nod=1');
  SetParamExpect('NAM=LOOP END=1 END=2', res_DupParam, 'END=2');
  { the same key in two different layers is not a duplicate }
  SetParamExpect('NOD=1 NAM=TSTP NOD=2 NAM=LOOP', res_Ok, '');
  AssertEquals(1, Chn^.CH_Node);
  AssertEquals(2, Chn^.CH_Low^.CH_Node);
end;

procedure TTestChnVirt.TestEmptyStringChangesNothing;
begin
  SetParamExpect('NOD=5 NAM=LOOP', res_Ok, '');
  SetParamExpect('', res_Ok, '');
  SetParamExpect('   ', res_Ok, '');
  SetParamExpect('NAM=TSTP', res_Ok, '');
  AssertEquals(5, Chn^.CH_Node);
  AssertNotNull('lower layer kept', Chn^.CH_Low);
end;

procedure TTestChnVirt.TestMaximumLengthString;
var
  S: tParamStr;
begin
  { 255 characters: valid tokens padded with blanks in between }
  S := 'NOD=3' + StringOfChar(' ', 255 - Length('NOD=3') - Length('NAM=LOOP PAIR=MAX'))
    + 'NAM=LOOP PAIR=MAX';
  AssertEquals(255, Length(S));
  SetParamExpect(S, res_Ok, '');
  AssertEquals('MAX', pChnLoop(Chn^.CH_Low)^.CH_Pair);
  { one token of 255 characters is too long a pair name: an error, no crash }
  S := 'PAIR=' + StringOfChar('X', 250);
  AssertEquals(255, Length(S));
  Chn^.CH_Low^.ChSetParam(S);
  AssertEquals(res_BadParam, Chn^.CH_Low^.ChResult);
  AssertEquals(S, Chn^.CH_Low^.ChParamError);
end;

{ A stack whose configuration text passes 255 characters (long DEV= or
  FILE= paths): ChGetParam is a getter and must not leave a fault in
  ChResult (polling loops take that for a lost line), and what it returns
  is cut at a whole token, so that it still parses. }
procedure TTestChnVirt.TestGetParamLongerThan255;
const
  Tstp = 'NAM=TSTP NOD=0 DNO=0 MOD=A CNT=0 FLG=OFF';
var
  Full, G: string;
begin
  SetParamExpect('MOD=A NAM=TSTP MOD=A NAM=TSTP MOD=A NAM=TSTP MOD=A NAM=TSTP MOD=A ' +
    'NAM=TSTP MOD=A NAM=LOOP PAIR=LONG', res_Ok, '');
  Full := Tstp + ' ' + Tstp + ' ' + Tstp + ' ' + Tstp + ' ' + Tstp + ' ' + Tstp +
    ' NAM=LOOP PAIR=LONG END=1 LRB=4096 IDL=0';
  AssertTrue(Length(Full) > 255);
  Chn^.ChOpen;
  Chn^.ChConnect;
  AssertEquals(res_Ok, Chn^.ChResult);
  G := Chn^.ChGetParam('');
  AssertEquals('a getter leaves no fault behind', res_Ok, Chn^.ChResult);
  AssertTrue('at most 255', Length(G) <= 255);
  AssertEquals('a prefix of the whole text', G, Copy(Full, 1, Length(G)));
  AssertEquals('cut between tokens: ' + G, ' ', Full[Length(G) + 1]);
  AssertTrue('not shorter than needed', Length(G) > 255 - Length(' FLG=OFF'));
  AssertEquals('a key still finds lower layers', 'PAIR=LONG', Chn^.ChGetParam('PAIR'));
end;

procedure TTestChnVirt.TestFusedTokenIsAnError;
begin
  { docs/PROTOCOLS.md section 7: 'CRC=ON' + 'NAM=COM' glued together by the manual's example }
  SetParamExpect('NOD=1 FLG=ONNAM=LOOP PAIR=X', res_BadParam, 'FLG=ONNAM=LOOP');
  AssertNull('no layer created', Chn^.CH_Low);
  AssertEquals(0, Chn^.CH_Node);
end;

procedure TTestChnVirt.TestTokenWithoutValue;
begin
  SetParamExpect('NOD=', res_BadParam, 'NOD=');
  SetParamExpect('NOD', res_BadParam, 'NOD');
  SetParamExpect('=1', res_BadParam, '=1');
  SetParamExpect('NOD=1 NAM=', res_BadParam, 'NAM=');
end;

procedure TTestChnVirt.TestBadTokenKeepsPreviousConfiguration;
begin
  SetParamExpect('NOD=1 DNO=2 CNT=3 NAM=LOOP PAIR=OLD', res_Ok, '');
  SetParamExpect('NOD=9 DNO=9 CNT=9999', res_BadParam, 'CNT=9999');
  AssertEquals(1, Chn^.CH_Node);
  AssertEquals(2, Chn^.CH_DNode);
  AssertEquals(3, pChnTestLayer(Chn)^.CH_Count);
  AssertEquals('OLD', pChnLoop(Chn^.CH_Low)^.CH_Pair);
end;

procedure TTestChnVirt.TestBadTokenInLowerLayerKeepsStack;
var
  OldLow: pChnVirt;
begin
  SetParamExpect('NOD=1 NAM=LOOP PAIR=OLD END=2', res_Ok, '');
  OldLow := Chn^.CH_Low;
  SetParamExpect('NOD=4 NAM=LOOP PAIR=NEW END=77', res_BadParam, 'END=77');
  AssertEquals(1, Chn^.CH_Node);
  AssertTrue('same lower layer object', OldLow = Chn^.CH_Low);
  AssertEquals('OLD', pChnLoop(Chn^.CH_Low)^.CH_Pair);
  AssertEquals(2, pChnLoop(Chn^.CH_Low)^.CH_End);
end;

procedure TTestChnVirt.TestUnknownLowerLayer;
begin
  SetParamExpect('NOD=1 NAM=NOSUCH X=1', res_UnknownLayer, 'NAM=NOSUCH');
  AssertNull(Chn^.CH_Low);
  AssertEquals(0, Chn^.CH_Node);
  AssertEquals('unknown layer name', ChResultText(res_UnknownLayer));
end;

procedure TTestChnVirt.TestPhysicalLayerCannotHaveLower;
begin
  SetParamExpect('NAM=LOOP PAIR=P NAM=LOOP', res_BadParam, 'NAM=LOOP');
  AssertNull(Chn^.CH_Low);
end;

procedure TTestChnVirt.TestStackTwoLayersAndRoundTrip;
const
  S = 'NAM=TSTP NOD=12 DNO=3 MOD=B CNT=77 FLG=ON NAM=TSTP NOD=1 DNO=2 MOD=A CNT=0 FLG=OFF ' +
      'NAM=LOOP PAIR=RT END=2 LRB=100 IDL=5';
var
  Fresh: pChnVirt;
  Got: tParamStr;
begin
  SetParamExpect(S, res_Ok, '');
  AssertEquals('TSTP', Chn^.CH_Low^.CH_Type);
  AssertEquals('LOOP', Chn^.CH_Low^.CH_Low^.CH_Type);
  Got := Chn^.ChGetParam('');
  AssertEquals(S, Got);
  { a fresh object rebuilds the same stack from ChGetParam }
  Fresh := ChnCollection^.ChNewInit('TSTP');
  try
    Fresh^.ChSetParam(Got);
    AssertEquals(res_Ok, Fresh^.ChResult);
    AssertEquals(Got, Fresh^.ChGetParam(''));
    AssertEquals(100, pChnLoop(Fresh^.CH_Low^.CH_Low)^.CH_LRB);
  finally
    Dispose(Fresh, Done);
  end;
end;

procedure TTestChnVirt.TestSameTypeTwiceMakesTwoLayers;
begin
  { the first NAM=TSTP names this layer, the second starts one below }
  SetParamExpect('NAM=TSTP NAM=TSTP CNT=5 NAM=LOOP PAIR=TT', res_Ok, '');
  AssertNotNull(Chn^.CH_Low);
  AssertEquals('TSTP', Chn^.CH_Low^.CH_Type);
  AssertEquals(0, pChnTestLayer(Chn)^.CH_Count);
  AssertEquals(5, pChnTestLayer(Chn^.CH_Low)^.CH_Count);
  AssertEquals('LOOP', Chn^.CH_Low^.CH_Low^.CH_Type);
end;

procedure TTestChnVirt.TestGetParamKeyFilter;
begin
  SetParamExpect('NOD=12 NAM=LOOP PAIR=F', res_Ok, '');
  AssertEquals('NOD=12', Chn^.ChGetParam('nod'));
  AssertEquals('NAM=TSTP NAM=LOOP', Chn^.ChGetParam('NAM'));
  AssertEquals('', Chn^.ChGetParam('XYZ'));
end;

procedure TTestChnVirt.TestChInitParamConstructor;
var
  P: pChnTestLayer;
begin
  P := New(pChnTestLayer, ChInitParam('NOD=4 CNT=5 NAM=LOOP'));
  try
    AssertEquals(res_Ok, P^.ChResult);
    AssertEquals('TSTP', P^.CH_Type);
    AssertEquals(4, P^.CH_Node);
    AssertEquals(5, P^.CH_Count);
    AssertNotNull(P^.CH_Low);
  finally
    Dispose(P, Done);
  end;
end;

procedure TTestChnVirt.TestSwapStackWhileOpenIsRefused;
begin
  SetParamExpect('NAM=LOOP PAIR=SW', res_Ok, '');
  Chn^.ChOpen;
  AssertEquals(res_Ok, Chn^.ChResult);
  SetParamExpect('NAM=LOOP PAIR=SW2', res_WrongState, 'NAM=LOOP');
  AssertEquals('SW', pChnLoop(Chn^.CH_Low)^.CH_Pair);
end;

procedure TTestChnVirt.TestChangeOwnParamWhileOpenKeepsStack;
begin
  SetParamExpect('DNO=1 NAM=LOOP PAIR=CH', res_Ok, '');
  Chn^.ChOpen;
  SetParamExpect('DNO=9', res_Ok, '');
  AssertEquals(9, Chn^.CH_DNode);
  AssertEquals(CHS_Open, Chn^.ChReady);
end;

procedure TTestChnVirt.TestLifeCycleWrongOrder;
var
  Buf: array[0..15] of Byte;
  Len: Word;
begin
  FillChar(Buf, SizeOf(Buf), 0);
  SetParamExpect('NAM=LOOP PAIR=LC', res_Ok, '');
  { send before open }
  Chn^.ChSend(@Buf, 4);
  AssertEquals('send before open', res_WrongState, Chn^.ChSendResult);
  { connect before open }
  Chn^.ChConnect;
  AssertEquals('connect before open', res_WrongState, Chn^.ChResult);
  { close before open }
  Chn^.ChClose;
  AssertEquals('close before open', res_WrongState, Chn^.ChResult);
  { receive before open }
  Len := 99;
  Chn^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals('receive before open', res_WrongState, Chn^.ChReceiveResult);
  Chn^.ChOpen;
  AssertEquals(res_Ok, Chn^.ChResult);
  Chn^.ChOpen;
  AssertEquals('open twice', res_WrongState, Chn^.ChResult);
  Chn^.ChConnect;
  AssertEquals(CHS_Connect, Chn^.ChReady);
  { receive before ChReceiveBuffer }
  Len := 99;
  Chn^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals('receive without buffer', res_NoRecBuff, Chn^.ChReceiveResult);
  Chn^.ChReceiveBuffer(nil, 10);
  AssertEquals('nil buffer', res_NoRecBuff, Chn^.ChReceiveResult);
  Chn^.ChReceiveBuffer(@Buf, 0);
  AssertEquals('zero size', res_NoRecBuff, Chn^.ChReceiveResult);
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  AssertEquals(res_Ok, Chn^.ChReceiveResult);
  Chn^.ChReceive(Len);
  AssertEquals('nothing waiting', res_NoMessage, Chn^.ChReceiveResult);
  Chn^.ChSend(nil, 4);
  AssertEquals('nil send buffer', res_BadLen, Chn^.ChSendResult);
  Chn^.ChSend(@Buf, 0);
  AssertEquals('zero length', res_BadLen, Chn^.ChSendResult);
  Chn^.ChConnect;
  AssertEquals('connect twice', res_WrongState, Chn^.ChResult);
  Chn^.ChDisConnect;
  AssertEquals(CHS_DisConnect, Chn^.ChReady);
  Chn^.ChDisConnect;
  AssertEquals('disconnect twice', res_WrongState, Chn^.ChResult);
  Chn^.ChReceive(Len);
  AssertEquals('receive when disconnected', res_WrongState, Chn^.ChReceiveResult);
  Chn^.ChClose;
  AssertEquals(res_Ok, Chn^.ChResult);
  AssertEquals(CHS_Close, Chn^.ChReady);
  AssertEquals('lower closed too', CHS_Close, Chn^.CH_Low^.ChReady);
  Chn^.ChClose;
  AssertEquals('close twice', res_WrongState, Chn^.ChResult);
  { and it can be opened again }
  Chn^.ChOpen;
  AssertEquals(res_Ok, Chn^.ChResult);
end;

procedure TTestChnVirt.TestOpenWithoutLowerLayer;
begin
  Chn^.ChOpen;
  AssertEquals(res_NoLowLayer, Chn^.ChResult);
  AssertEquals(CHS_Close, Chn^.ChReady);
end;

procedure TTestChnVirt.TestDisposeOpenStack;
var
  A, B: pChnVirt;
  Err: string;
begin
  { an open, connected stack of three layers is freed whole by Dispose;
    heaptrc at the end of the suite proves nothing is left }
  A := OpenStack('TSTP', 'NAM=TSTP NAM=TSTP NAM=LOOP PAIR=DS END=1', Err);
  AssertNotNull(Err, A);
  B := OpenStack('LOOP', 'NAM=LOOP PAIR=DS END=2', Err);
  AssertNotNull(Err, B);
  Dispose(A, Done);
  Dispose(B, Done);
  { the pair is gone: the same ends can be opened again }
  A := OpenStack('LOOP', 'NAM=LOOP PAIR=DS END=1', Err);
  AssertNotNull(Err, A);
  Dispose(A, Done);
end;

procedure TTestChnVirt.TestResultTextOfLayer;
begin
  AssertEquals('bad parameter', Chn^.ChResultStr(res_BadParam));
  AssertTrue(Pos('unknown result code', Chn^.ChResultStr(res_Proto)) > 0);
end;

procedure TTestChnVirt.TestMiddleLayerHandsAddressingDown;
var
  M: pChnMiddle;
  SNode, DNode: tNode;
begin
  ChRegisterResultText('TSTP', res_Proto + 7, 'a code of the layer below');
  New(M, Init);
  try
    M^.ChSetType('MIDDLE');
    { nothing below: as tChnVirt }
    M^.ChDestNode(5);
    AssertEquals(5, M^.CH_DNode);
    M^.CH_RSNode := 3;
    M^.CH_RDNode := 4;
    M^.ChGetNode(SNode, DNode);
    AssertEquals(3, SNode);
    AssertEquals(4, DNode);
    AssertTrue(Pos('unknown result code', M^.ChResultStr(res_Proto + 7)) > 0);
    M^.ChReceiveTick;
    { a layer below: addresses and protocol codes are its }
    M^.CH_Low := ChnCollection^.ChNewInit('TSTP');
    M^.ChDestNode(9);
    AssertEquals('handed down', 9, M^.CH_Low^.CH_DNode);
    AssertEquals('and kept', 9, M^.CH_DNode);
    M^.CH_Low^.CH_RSNode := 7;
    M^.CH_Low^.CH_RDNode := 8;
    M^.ChGetNode(SNode, DNode);
    AssertEquals('from below', 7, SNode);
    AssertEquals('from below', 8, DNode);
    AssertEquals('TSTP: a code of the layer below', M^.ChResultStr(res_Proto + 7));
    AssertEquals('general codes are its own', 'device lost', M^.ChResultStr(res_DeviceLost));
  finally
    Dispose(M, Done);
  end;
end;

{ ChUsTick: a QWord (SizeOf 8 in every mode), never goes back, resolves
  less than a millisecond (a millisecond clock times 1000 moves in steps
  of 1000), and runs at ChMsTick's rate. }
procedure TTestChnVirt.TestMicrosecondClock;
var
  Prev, Now, Fine, U0, U1: QWord;
  M0, M1: QWord;
  I: LongInt;
begin
  AssertEquals('explicit size', 8, SizeOf(ChUsTick));
  Prev := ChUsTick;
  Fine := 0;
  for I := 1 to 200000 do
  begin
    Now := ChUsTick;
    AssertTrue(Format('monotonic: %d after %d', [Now, Prev]), Now >= Prev);
    if (Now > Prev) and (Now - Prev < 1000) and (Fine = 0) then
      Fine := Now - Prev;
    Prev := Now;
  end;
  {$IF DEFINED(LINUX) or DEFINED(WINDOWS)}
  AssertTrue('a step under a millisecond was seen', Fine > 0);
  {$ENDIF}
  M0 := ChMsTick;
  U0 := ChUsTick;
  Sleep(300);
  U1 := ChUsTick;
  M1 := ChMsTick;
  { the two reads of each clock bracket the same interval within the
    time of two calls; generous bounds for a loaded machine (a tick of
    GetTickCount64 on Windows is 16 ms) }
  AssertTrue(Format('us %d vs ms %d', [U1 - U0, M1 - M0]),
    Abs(Int64((U1 - U0) div 1000) - Int64(M1 - M0)) <= 20);
  AssertTrue(Format('300 ms slept: %d us', [U1 - U0]), U1 - U0 >= 290000);
end;

initialization
  RegisterTest(TTestChnVirt);
end.
