{ Tests of tChnFT1_2 (NAM=FT1_2): manual's constants and layout,
  parameters, wire bytes against hand-worked IEC 60870-5-101 frames, every
  receive error through the layer, an unbalanced master polling two slaves
  on a shared line (LoopHub), a balanced exchange and the line-idle gap. }
unit TestChnFT1_2;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnFT1_2,
  TestSupport, LoopHub, ChnBaudTestLayer, ChnWait;

type
  TTestChnFT1_2 = class(TTestCase)
  private
    FChn: array[1..4] of pChnVirt;
    FHub: TLoopHub;
    function Open(Slot: Integer; const Params: string): pChnVirt;
    function OpenRaw(Slot: Integer; const Pair: string): pChnVirt;
    procedure SendRec(Chn: pChnVirt; const Rec: tSendRecord; Len: Word);
    procedure RawSend(Raw: pChnVirt; const Hex: string);
    function RawRead(Raw: pChnVirt): string;
    function Recv(Chn, Other: pChnVirt; var Rec: tRecRecord): Word;
  protected
    procedure TearDown; override;
  published
    procedure TestLayoutAndManualConstants;
    procedure TestInitDefaultsOfTheManual;
    procedure TestParamsRoleAndRoundTrip;
    procedure TestBalancedRoleGivesTheDirBit;
    procedure TestParamErrors;
    procedure TestAdrAndNodeRangeInAnyOrder;
    procedure TestWireBytesIec101;
    procedure TestSendErrorsSendNothing;
    procedure TestRoundTripAllTypesBothModes;
    procedure TestReceiveErrorsThenResync;
    procedure TestReceiveBufferTooSmall;
    procedure TestSlaveAddressFilterAndBroadcast;
    procedure TestUnbalancedMasterPollsTwoSlaves;
    procedure TestBalancedExchange;
    procedure TestBalancedBothDirectionsOnOneChannel;
    procedure TestBalancedBadInputIsReported;
    procedure TestUnbalancedSendAsKeepsTheRole;
    procedure TestGapDiscardsHalfFrame;
    procedure TestGapUsesBaudRateBelow;
    procedure TestSetParamKeepsWaitingFrame;
    procedure TestFlushAndDisConnect;
    procedure TestChInitParam;
    procedure TestResultTexts;
    procedure TestLineIdleBetweenFramesOnATimedLine;
  end;

implementation

function MakeRec(T: tMessType; FCB, FCV: Boolean; FC: Byte): tSendRecord;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.MessType := T;
  Result.FCB_ACD := FCB;
  Result.FCV_DFC := FCV;
  Result.FC := FC;
end;

procedure TTestChnFT1_2.TearDown;
var
  I: Integer;
begin
  for I := Low(FChn) to High(FChn) do
    if FChn[I] <> nil then
    begin
      Dispose(FChn[I], Done);
      FChn[I] := nil;
    end;
  FreeAndNil(FHub);
end;

function TTestChnFT1_2.Open(Slot: Integer; const Params: string): pChnVirt;
var
  Err: string;
begin
  Result := OpenStack(ChnFT1_2.cName, Params, Err);
  AssertTrue(Err, Result <> nil);
  FChn[Slot] := Result;
end;

function TTestChnFT1_2.OpenRaw(Slot: Integer; const Pair: string): pChnVirt;
var
  Err: string;
begin
  Result := OpenStack(ChnLoop.cName, 'PAIR=' + Pair + ' END=2', Err);
  AssertTrue(Err, Result <> nil);
  FChn[Slot] := Result;
end;

procedure TTestChnFT1_2.SendRec(Chn: pChnVirt; const Rec: tSendRecord; Len: Word);
begin
  AssertTrue('send ready', WaitSent(Chn, 1000));
  Chn^.ChSend(@Rec, Len);
  AssertEquals('ChSendResult', res_Ok, Chn^.ChSendResult);
end;

procedure TTestChnFT1_2.RawSend(Raw: pChnVirt; const Hex: string);
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  Raw^.ChSend(@B[0], Length(B));
  AssertEquals('raw send', res_Ok, Raw^.ChSendResult);
end;

function TTestChnFT1_2.RawRead(Raw: pChnVirt): string;
var
  Buf: array[0..1023] of Byte;
  N: Word;
begin
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  N := 0;
  if Raw^.ChReceiveReady = CHS_ReceiveReady then
    Raw^.ChReceive(N);
  Result := BytesToHex(Buf, N);
end;

function TTestChnFT1_2.Recv(Chn, Other: pChnVirt; var Rec: tRecRecord): Word;
begin
  FillChar(Rec, SizeOf(Rec), $CC);
  Chn^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  AssertTrue('a message arrives', WaitReceive(Chn, 1000, Other));
  Result := 0;
  Chn^.ChReceive(Result);
  AssertEquals('ChReceiveResult', res_Ok, Chn^.ChReceiveResult);
end;

procedure TTestChnFT1_2.TestLayoutAndManualConstants;
var
  R: tSendRecord;
begin
  AssertEquals('SizeOf(tSendRecord)', 251, SizeOf(tSendRecord));
  AssertEquals('SizeOf(tRecRecord)', 251, SizeOf(tRecRecord));
  AssertEquals('SizeOf(tMaSendRecord)', 251, SizeOf(tMaSendRecord));
  AssertEquals('SizeOf(tSlRecRecord)', 251, SizeOf(tSlRecRecord));
  AssertEquals('SizeOf(tMessType)', 1, SizeOf(tMessType));
  AssertEquals('SizeOf(tRec)', 1, SizeOf(tRec));
  AssertEquals('MessType@0', 0, PtrUInt(@R.MessType) - PtrUInt(@R));
  AssertEquals('FCB_ACD@1', 1, PtrUInt(@R.FCB_ACD) - PtrUInt(@R));
  AssertEquals('FCV_DFC@2', 2, PtrUInt(@R.FCV_DFC) - PtrUInt(@R));
  AssertEquals('FC@3', 3, PtrUInt(@R.FC) - PtrUInt(@R));
  AssertEquals('Data[1]@4', 4, PtrUInt(@R.Data[1]) - PtrUInt(@R));
  AssertEquals('Data[247]@250', 250, PtrUInt(@R.Data[247]) - PtrUInt(@R));
  AssertEquals('FT1_2', ChnFT1_2.cName);
  AssertEquals(65500, MaxTBuf);
  AssertEquals(247, MaxDataLen);
  AssertEquals($10, SD1); AssertEquals($68, SD2); AssertEquals($16, ED);
  AssertEquals($E5, SACK); AssertEquals($A2, SNAK);
  AssertEquals(0, FCM_1stSetTransmit); AssertEquals(1, FCM_1stSetUserFun);
  AssertEquals(2, FCM_CheckLink); AssertEquals(3, FCM_UserDataReply);
  AssertEquals(4, FCM_UserDataNoRep); AssertEquals(8, FCM_ReqReplyAcces);
  AssertEquals(9, FCM_ReqLinkState); AssertEquals(10, FCM_ReqUserData1);
  AssertEquals(11, FCM_ReqUserData2);
  AssertEquals(0, FCS_Ack); AssertEquals(1, FCS_NackBusy);
  AssertEquals(8, FCS_UserData); AssertEquals(9, FCS_DataNotAcces);
  AssertEquals(11, FCS_LinkSAccesReq);
  AssertEquals($20, res_ErrSum); AssertEquals($21, res_ErrLen);
  AssertEquals($22, res_ErrCode); AssertEquals($23, res_ErrFrame);
  AssertEquals(4, cSizeHeadSndMsg); AssertEquals(4, cSizeHeadRecMsg);
  AssertEquals(4, cSizeHeadMaSndMsg); AssertEquals(4, cSizeHeadSlSndMsg);
  AssertEquals(0, Ord(tpSACK)); AssertEquals(1, Ord(tpSNAK));
  AssertEquals(2, Ord(tpShortM)); AssertEquals(3, Ord(tpLongM));
  AssertEquals(2, Ord(Err));
end;

procedure TTestChnFT1_2.TestInitDefaultsOfTheManual;
var
  C: pChnFT1_2;
begin
  New(C, Init);
  try
    AssertEquals('FT1_2', C^.CH_Type);
    AssertEquals('FT1_2', C^.CH_Name);
    AssertEquals(ChNumName('FT1_2'), C^.CH_NumName);
    AssertFalse(C^.CH_RTick);
    AssertTrue(C^.CH_SBuff = nil);
    AssertEquals(0, C^.CH_MSBuff);
    AssertEquals(0, C^.CH_LRMess);
    AssertTrue('MS=ON', C^.CH_MaSl);
    AssertTrue('master', C^.CH_Master);
    AssertEquals('LEN=4', 4, C^.CH_LenShortM);
    AssertEquals(0, C^.IData);
    AssertEquals('ADR=1', 1, C^.CH_AdrLen);
    AssertEquals(
      'NAM=FT1_2 NOD=0 DNO=0 MS=ON MAS=MASTER PRI=ON LEN=4 ADR=1 DIR=0 GAP=0',
      C^.ChGetParam(''));
  finally
    Dispose(C, Done);
  end;
  AssertTrue('registered', ChnCollection^.Search('ft1_2') <> nil);
end;

procedure TTestChnFT1_2.TestParamsRoleAndRoundTrip;
var
  C, D: pChnFT1_2;
  G: string;
begin
  New(C, Init);
  New(D, Init);
  try
    C^.ChSetParam('MS=ON MAS=SLAVE');
    AssertEquals(res_Ok, C^.ChResult);
    AssertFalse('MAS=SLAVE', C^.CH_Master);
    C^.ChSetParam('MS=OFF');
    AssertTrue('balanced: PRI=ON (default) decides', C^.CH_Master);
    C^.ChSetParam('PRI=OFF');
    AssertFalse('PRI=OFF', C^.CH_Master);
    C^.ChSetParam('MS=ON');
    AssertFalse('back to MAS=SLAVE', C^.CH_Master);
    C^.ChSetParam('NAM=FT1_2 MS=OFF PRI=OFF MAS=MASTER NOD=300 DNO=2 LEN=0 ADR=2 DIR=1 ' +
      'GAP=5 LSB=300 NAM=LOOP PAIR=RT END=2');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(300, C^.CH_MSBuff);
    AssertTrue(C^.CH_SBuff <> nil);
    G := C^.ChGetParam('');
    AssertEquals('NAM=FT1_2 NOD=300 DNO=2 MS=OFF MAS=MASTER PRI=OFF LSB=300 LEN=0 ' +
      'ADR=2 DIR=1 GAP=5 NAM=LOOP PAIR=RT END=2 LRB=4096 IDL=0', G);
    D^.ChSetParam(G);
    AssertEquals(res_Ok, D^.ChResult);
    AssertEquals(G, D^.ChGetParam(''));
    AssertFalse(D^.CH_Master);
    AssertFalse(D^.CH_MaSl);
    AssertEquals(300, D^.CH_Node);
  finally
    Dispose(C, Done);
    Dispose(D, Done);
  end;
end;

{ Balanced, no DIR=: a controlling station (PRI=ON or MAS=MASTER given)
  is station A and sends DIR = 1, as lib60870's balanced master; a
  controlled one (PRI=OFF, MAS=SLAVE), or no role given, DIR = 0; DIR=
  given wins; unbalanced has no DIR (RES = 0). }
procedure TTestChnFT1_2.TestBalancedRoleGivesTheDirBit;
const
  Cases: array[0..8] of record P: string; Dir: Boolean; end = (
    (P: 'MS=OFF'; Dir: False),
    (P: 'MS=OFF PRI=ON'; Dir: True),
    (P: 'MS=OFF MAS=MASTER'; Dir: True),
    (P: 'MAS=MASTER MS=OFF'; Dir: True),
    (P: 'MS=OFF PRI=OFF'; Dir: False),
    (P: 'MS=OFF MAS=SLAVE'; Dir: False),
    (P: 'MS=OFF PRI=ON DIR=0'; Dir: False),
    (P: 'MS=OFF DIR=0 MAS=MASTER'; Dir: False),
    (P: 'MS=ON MAS=MASTER'; Dir: False));
var
  C: pChnFT1_2;
  I: Integer;
begin
  for I := 0 to High(Cases) do
  begin
    New(C, Init);
    try
      C^.ChSetParam(Cases[I].P);
      AssertEquals(Cases[I].P, res_Ok, C^.ChResult);
      AssertEquals(Cases[I].P, Cases[I].Dir, C^.CH_Dir);
      AssertEquals(Cases[I].P, Cases[I].Dir, Pos('DIR=1', C^.ChGetParam('')) > 0);
    finally
      Dispose(C, Done);
    end;
  end;
end;

procedure TTestChnFT1_2.TestParamErrors;
var
  C: pChnFT1_2;
begin
  New(C, Init);
  try
    { the manual example's MASTER=ON is not a parameter (docs/PROTOCOLS.md section 7) }
    C^.ChSetParam('MS=ON MASTER=ON LSB=500');
    AssertEquals(res_UnknownParam, C^.ChResult);
    AssertEquals('MASTER=ON', C^.ChParamError);
    AssertEquals('nothing applied', 0, C^.CH_MSBuff);
    C^.ChSetParam('LEN=248');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('ADR=3');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('MAS=BOSS');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('DIR=2');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('LSB=0');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('LSB=65501');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('GAP=10001');
    AssertEquals('GAP above 10000 character times', res_BadParam, C^.ChResult);
    AssertEquals('GAP=10001', C^.ChParamError);
    C^.ChSetParam('MS=ONNAM=LOOP');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('defaults kept', 4, C^.CH_LenShortM);
    AssertEquals(1, C^.CH_AdrLen);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnFT1_2.TestAdrAndNodeRangeInAnyOrder;
var
  C: pChnFT1_2;
begin
  New(C, Init);
  try
    C^.ChSetParam('NOD=300');
    AssertEquals('1 octet: 300 too large', res_BadParam, C^.ChResult);
    C^.ChSetParam('NOD=255 DNO=255');
    AssertEquals(res_Ok, C^.ChResult);
    { ADR= after NOD= in the same string counts }
    C^.ChSetParam('NOD=300 DNO=65535 ADR=2');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(300, C^.CH_Node);
    AssertEquals(65535, C^.CH_DNode);
    AssertEquals(2, C^.CH_AdrLen);
    C^.ChSetParam('ADR=2 NOD=65536');
    AssertEquals(res_BadParam, C^.ChResult);
    { going back to 1 octet while the kept NOD=300 would not fit }
    C^.ChSetParam('ADR=1');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('ADR=1', C^.ChParamError);
    AssertEquals(2, C^.CH_AdrLen);
    C^.ChSetParam('ADR=1 NOD=5');
    AssertEquals('DNO=65535 kept does not fit', res_BadParam, C^.ChResult);
    C^.ChSetParam('DNO=7 ADR=1 NOD=5');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(1, C^.CH_AdrLen);
    AssertEquals(5, C^.CH_Node);
    AssertEquals(7, C^.CH_DNode);
    { a failed string leaves the next check unaffected }
    C^.ChSetParam('ADR=2 NOD=1000 LEN=999');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('NOD=1000');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals(5, C^.CH_Node);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnFT1_2.TestWireBytesIec101;
var
  M, S, Raw: pChnVirt;
  R: tSendRecord;
begin
  M := Open(1, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=LOOP PAIR=FTW1 END=1');
  Raw := OpenRaw(2, 'FTW1');
  { request status of link to 1: CODE $49, CS $49 + $01 = $4A }
  SendRec(M, MakeRec(tpShortM, False, False, FCM_ReqLinkState), cSizeHeadMaSndMsg);
  AssertEquals('10 49 01 4A 16', RawRead(Raw));
  { request class 2 data, FCB = FCV = 1: CODE $7B, CS $7C }
  SendRec(M, MakeRec(tpShortM, True, True, FCM_ReqUserData2), 4);
  AssertEquals('10 7B 01 7C 16', RawRead(Raw));
  { ChDestNode changes the address: 3 -> CS $49 + $03 = $4C }
  M^.ChDestNode(3);
  SendRec(M, MakeRec(tpShortM, False, False, 9), 4);
  AssertEquals('10 49 03 4C 16', RawRead(Raw));
  { the slave side puts its own address (NOD) in the frame }
  S := Open(3, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 DNO=9 NAM=LOOP PAIR=FTW2 END=1');
  Raw := OpenRaw(4, 'FTW2');
  SendRec(S, MakeRec(tpShortM, False, False, FCS_LinkSAccesReq), 4);
  AssertEquals('10 0B 01 0C 16', RawRead(Raw));
  SendRec(S, MakeRec(tpSACK, False, False, 0), 1);
  AssertEquals('E5', RawRead(Raw));
  { the manual: Len is ignored for single characters, 0 included }
  SendRec(S, MakeRec(tpSACK, False, False, 0), 0);
  AssertEquals('SACK with Len 0', 'E5', RawRead(Raw));
  SendRec(S, MakeRec(tpSNAK, False, False, 0), 0);
  AssertEquals('SNAK with Len 0', 'A2', RawRead(Raw));
  R := MakeRec(tpLongM, False, False, FCS_UserData);
  R.Data[1] := $AA;
  { L = 1 + 1 + 1 = 3; CS = $08 + $01 + $AA = $B3 }
  SendRec(S, R, 5);
  AssertEquals('68 03 03 68 08 01 AA B3 16', RawRead(Raw));
  { 2 address octets }
  S^.ChSetParam('ADR=2 NOD=258');
  AssertEquals(res_Ok, S^.ChResult);
  { CODE $0B, address 02 01, CS = $0B + $02 + $01 = $0E }
  SendRec(S, MakeRec(tpShortM, False, False, 11), 4);
  AssertEquals('10 0B 02 01 0E 16', RawRead(Raw));
end;

procedure TTestChnFT1_2.TestSendErrorsSendNothing;
var
  C: pChnFT1_2;
  M, Raw: pChnVirt;
  R: tSendRecord;
  Big: tFT12MaxRecord;
begin
  FillChar(Big, SizeOf(Big), 0);
  Big.MessType := tpLongM;
  Big.FC := 3;
  New(C, Init);
  try
    R := MakeRec(tpShortM, False, False, 9);
    C^.ChSend(@R, 8);
    AssertEquals('before open', res_WrongState, C^.ChSendResult);
  finally
    Dispose(C, Done);
  end;
  M := Open(1, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 DNO=1 NAM=LOOP PAIR=FTSE END=1');
  Raw := OpenRaw(2, 'FTSE');
  R := MakeRec(tpSACK, False, False, 0);
  M^.ChSend(@R, 1);
  AssertEquals('master sends SACK', res_BadMessage, M^.ChSendResult);
  R := MakeRec(tpShortM, False, False, 16);
  M^.ChSend(@R, 4);
  AssertEquals('FC 16', res_BadMessage, M^.ChSendResult);
  R.FC := 9;
  M^.ChSend(@R, 5);
  AssertEquals('fixed frame, LEN=0, 1 data byte', res_BadLen, M^.ChSendResult);
  M^.ChSend(@R, 0);
  AssertEquals('Len 0', res_BadLen, M^.ChSendResult);
  M^.ChSend(nil, 4);
  AssertEquals('nil', res_BadLen, M^.ChSendResult);
  R.MessType := tpLongM;
  M^.ChSend(@Big, 4 + 254);
  AssertEquals('254 data bytes: L = 256', res_TooLong, M^.ChSendResult);
  M^.ChDestNode(256);
  R.MessType := tpShortM;
  M^.ChSend(@R, 4);
  AssertEquals('DNO does not fit 1 octet', res_BadMessage, M^.ChSendResult);
  M^.ChDestNode(1);
  M^.ChDisConnect;
  M^.ChClose;
  M^.ChSetParam('LSB=4');
  AssertEquals(res_Ok, M^.ChResult);
  M^.ChOpen;
  M^.ChConnect;
  M^.ChSend(@R, 4);
  AssertEquals('frame larger than LSB', res_TooLong, M^.ChSendResult);
  AssertEquals('nothing on the line', '', RawRead(Raw));
  { the layer below may still be sending from the buffer: LSB= is fixed
    while open (the same value is fine), as in DF1 and ICS }
  M^.ChSetParam('LSB=5');
  AssertEquals('LSB= while open', res_WrongState, M^.ChResult);
  M^.ChSetParam('LSB=4');
  AssertEquals('the same LSB= while open', res_Ok, M^.ChResult);
  M^.ChDisConnect;
  M^.ChClose;
  M^.ChSetParam('LSB=5');
  AssertEquals(res_Ok, M^.ChResult);
  M^.ChOpen;
  M^.ChConnect;
  M^.ChSend(@R, 4);
  AssertEquals(res_Ok, M^.ChSendResult);
  AssertEquals('10 49 01 4A 16', RawRead(Raw));
end;

procedure TTestChnFT1_2.TestRoundTripAllTypesBothModes;
const
  Modes: array[1..2] of string = ('MS=ON MAS=', 'MS=OFF PRI=');
  PrimaryWord: array[1..2] of string = ('MASTER', 'ON');
  SecondaryWord: array[1..2] of string = ('SLAVE', 'OFF');
  { balanced: the two stations are A (DIR = 1) and B }
  PrimaryDir: array[1..2] of string = ('', ' DIR=1');
var
  Mode, I, N: Integer;
  M, S: pChnVirt;
  R, Got: tSendRecord;
  Len: Word;
  SNode, DNode: tNode;
  Pair: string;
begin
  for Mode := 1 to 2 do
  begin
    Pair := 'FTRT' + IntToStr(Mode);
    { manual defaults: LEN=4, ADR=1 }
    M := Open(1, 'NAM=FT1_2 ' + Modes[Mode] + PrimaryWord[Mode] + PrimaryDir[Mode] +
      ' NOD=10 DNO=20 NAM=LOOP PAIR=' + Pair + ' END=1');
    S := Open(2, 'NAM=FT1_2 ' + Modes[Mode] + SecondaryWord[Mode] +
      ' NOD=20 DNO=10 NAM=LOOP PAIR=' + Pair + ' END=2');
    { primary -> secondary: fixed frame with 4 data, variable 0 and 247 }
    R := MakeRec(tpShortM, True, True, FCM_UserDataReply);
    R.Data[1] := 1; R.Data[2] := 2; R.Data[3] := 3; R.Data[4] := $FF;
    SendRec(M, R, 8);
    Len := Recv(S, M, Got);
    AssertEquals(8, Len);
    AssertTrue(Got.MessType = tpShortM);
    AssertTrue(Got.FCB_ACD and Got.FCV_DFC);
    AssertEquals(FCM_UserDataReply, Got.FC);
    AssertEquals($FF, Got.Data[4]);
    AssertEquals('no byte past Len', $CC, Got.Data[5]);
    S^.ChGetNode(SNode, DNode);
    AssertEquals('from primary: DNode = address', 20, DNode);
    AssertEquals('from primary: SNode = own DNO', 10, SNode);
    for N := 0 to 1 do
    begin
      R := MakeRec(tpLongM, False, False, FCM_UserDataNoRep);
      for I := 1 to MaxDataLen do
        R.Data[I] := I;
      SendRec(M, R, 4 + N * MaxDataLen);
      Len := Recv(S, M, Got);
      AssertEquals(4 + N * MaxDataLen, Len);
      AssertTrue(Got.MessType = tpLongM);
      AssertEquals(FCM_UserDataNoRep, Got.FC);
      if N = 1 then
        AssertTrue(CompareByte(R.Data, Got.Data, MaxDataLen) = 0);
    end;
    { secondary -> primary: fixed, variable, SACK, SNAK }
    R := MakeRec(tpShortM, True, False, FCS_NackBusy);
    SendRec(S, R, 8);
    Len := Recv(M, S, Got);
    AssertEquals(8, Len);
    AssertTrue(Got.FCB_ACD);
    AssertFalse(Got.FCV_DFC);
    AssertEquals(FCS_NackBusy, Got.FC);
    M^.ChGetNode(SNode, DNode);
    AssertEquals('from secondary: SNode = address', 20, SNode);
    AssertEquals('from secondary: DNode = own NOD', 10, DNode);
    R := MakeRec(tpLongM, False, True, FCS_UserData);
    R.Data[1] := $68;
    R.Data[2] := $16;
    SendRec(S, R, 6);
    Len := Recv(M, S, Got);
    AssertEquals(6, Len);
    AssertTrue(Got.FCV_DFC);
    AssertEquals($16, Got.Data[2]);
    SendRec(S, MakeRec(tpSACK, False, False, 0), 1);
    Len := Recv(M, S, Got);
    AssertEquals(1, Len);
    AssertTrue(Got.MessType = tpSACK);
    AssertEquals('only MessType written', $CC, Byte(Got.FC));
    SendRec(S, MakeRec(tpSNAK, False, False, 0), 1);
    Len := Recv(M, S, Got);
    AssertEquals(1, Len);
    AssertTrue(Got.MessType = tpSNAK);
    M^.ChGetNode(SNode, DNode);
    AssertEquals('single character: the addressed station', 20, SNode);
    TearDown;
  end;
end;

procedure TTestChnFT1_2.TestReceiveErrorsThenResync;
const
  { each broken frame, the result it must give; after each the good
    frame 10 49 01 4A 16 must still be received }
  Broken: array[1..7] of string = (
    '10 49 01 4B 16',                 { checksum }
    '68 03 04 68 49 01 AA F4 16',     { the two L bytes differ }
    '68 01 01 68 49 49 16',           { L too small for CODE + ADDR }
    '68 03 03 10 49 01 AA F4 16',     { wrong second start byte }
    '10 49 01 4A 00',                 { missing ED }
    '10 0B 01 0C 16',                 { PRM = 0 to a slave }
    '68 03 03 68 49 01 AA F4 17');    { variable frame, missing ED }
  Expect: array[1..7] of tChResult = (res_ErrSum, res_ErrLen, res_ErrLen,
    res_ErrFrame, res_ErrFrame, res_ErrCode, res_ErrFrame);
var
  S, Raw: pChnVirt;
  Rec: tRecRecord;
  Len: Word;
  I, Extra: Integer;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=LOOP PAIR=FTER END=1');
  Raw := OpenRaw(2, 'FTER');
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  for I := Low(Broken) to High(Broken) do
  begin
    RawSend(Raw, Broken[I] + ' 10 49 01 4A 16');
    AssertTrue('broken frame reported', WaitReceive(S, 1000));
    Len := 99;
    S^.ChReceive(Len);
    AssertEquals(Broken[I] + ': Len', 0, Len);
    AssertEquals(Broken[I] + ': result', Expect[I], S^.ChReceiveResult);
    { the rest of a broken frame may hold start characters and give
      further errors (as on a real line); the good frame must follow }
    Extra := 0;
    repeat
      AssertTrue('good frame after it', WaitReceive(S, 1000));
      S^.ChReceive(Len);
      if S^.ChReceiveResult <> res_Ok then
        Inc(Extra);
    until (S^.ChReceiveResult = res_Ok) or (Extra > 2);
    AssertEquals(Broken[I] + ': good frame', res_Ok, S^.ChReceiveResult);
    AssertEquals(4, Len);
    AssertEquals(FCM_ReqLinkState, Rec.FC);
  end;
  { nothing more waiting }
  S^.ChReceive(Len);
  AssertEquals(res_NoMessage, S^.ChReceiveResult);
  AssertEquals(0, Len);
end;

procedure TTestChnFT1_2.TestReceiveBufferTooSmall;
var
  S, Raw: pChnVirt;
  Buf: array[0..63] of Byte;
  Len: Word;
  I: Integer;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=LOOP PAIR=FTSB END=1');
  Raw := OpenRaw(2, 'FTSB');
  FillChar(Buf, SizeOf(Buf), $CC);
  S^.ChReceiveBuffer(@Buf, 6);
  { 3 data bytes need 4 + 3 = 7; L = 5, CS = $53 + $01 + 1 + 2 + 3 = $5A }
  RawSend(Raw, '68 05 05 68 53 01 01 02 03 5A 16');
  AssertTrue(WaitReceive(S, 1000));
  Len := 99;
  S^.ChReceive(Len);
  AssertEquals(res_ErrLen, S^.ChReceiveResult);
  AssertEquals(0, Len);
  for I := 0 to High(Buf) do
    AssertEquals('nothing written', $CC, Buf[I]);
  { 2 data bytes fit: CS = $53 + $01 + 1 + 2 = $57 }
  RawSend(Raw, '68 04 04 68 53 01 01 02 57 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals(6, Len);
  AssertEquals(2, Buf[5]);
  AssertEquals($CC, Buf[6]);
end;

procedure TTestChnFT1_2.TestSlaveAddressFilterAndBroadcast;
var
  S, Raw: pChnVirt;
  Rec: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 DNO=0 NAM=LOOP PAIR=FTBC END=1');
  Raw := OpenRaw(2, 'FTBC');
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  { to 2 (CS $4B), an answer of slave 2 (CS $0D), single characters of
    other slaves, then a broadcast FC 4 (CS = $44 + $FF = $43) }
  RawSend(Raw, '10 49 02 4B 16  10 0B 02 0D 16  E5 A2  10 44 FF 43 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals(FCM_UserDataNoRep, Rec.FC);
  S^.ChGetNode(SNode, DNode);
  AssertEquals('broadcast reported', 255, DNode);
  AssertEquals(0, SNode);
  RawSend(Raw, '10 49 01 4A 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  S^.ChGetNode(SNode, DNode);
  AssertEquals(1, DNode);
end;

{ A slave application of the test: answers as an IEC 101 secondary. }
type
  TSlaveLog = record
    Got: Integer;         { frames received }
    Broadcasts: Integer;
  end;

procedure ServeSlave(S: pChnVirt; HasData: Boolean; var Log: TSlaveLog);
var
  Rec: tRecRecord;
  Ans: tSendRecord;
  Len: Word;
  SNode, DNode: tNode;
begin
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  if S^.ChReceiveReady <> CHS_ReceiveReady then
    Exit;
  S^.ChReceive(Len);
  if (S^.ChReceiveResult <> res_Ok) or (Len < cSizeHeadRecMsg) then
    Exit;
  Inc(Log.Got);
  S^.ChGetNode(SNode, DNode);
  if DNode = 255 then
  begin
    Inc(Log.Broadcasts);   { never answered }
    Exit;
  end;
  FillChar(Ans, SizeOf(Ans), 0);
  Ans.MessType := tpShortM;
  Len := cSizeHeadSlSndMsg;
  case Rec.FC of
    FCM_ReqLinkState: Ans.FC := FCS_LinkSAccesReq;
    FCM_1stSetTransmit: Ans.FC := FCS_Ack;
    FCM_ReqUserData2:
      if HasData then
      begin
        Ans.MessType := tpLongM;
        Ans.FC := FCS_UserData;
        Ans.Data[1] := $2A;
        Ans.Data[2] := Byte(SNode);    { something from this station }
        Len := cSizeHeadSlSndMsg + 2;
      end
      else
        Ans.FC := FCS_DataNotAcces;
  else
    Ans.FC := FCS_NackBusy;
  end;
  S^.ChSend(@Ans, Len);
end;

procedure TTestChnFT1_2.TestUnbalancedMasterPollsTwoSlaves;
var
  M, S1, S2: pChnVirt;
  Log1, Log2: TSlaveLog;

  { send one request from the master, run the bus until the answer is in }
  procedure Ask(Node: tNode; FC: Byte; FCB, FCV: Boolean; var Ans: tRecRecord;
    var Len: Word);
  var
    Req: tSendRecord;
    Deadline: QWord;
  begin
    M^.ChDestNode(Node);
    Req := MakeRec(tpShortM, FCB, FCV, FC);
    SendRec(M, Req, cSizeHeadMaSndMsg);
    M^.ChReceiveBuffer(@Ans, SizeOf(Ans));
    Deadline := GetTickCount64 + 2000;
    repeat
      FHub.Pump;
      ServeSlave(S1, True, Log1);
      ServeSlave(S2, False, Log2);
      FHub.Pump;
      if M^.ChReceiveReady = CHS_ReceiveReady then
        Break;
    until GetTickCount64 > Deadline;
    Len := 0;
    M^.ChReceive(Len);
    AssertEquals('answer from ' + IntToStr(Node), res_Ok, M^.ChReceiveResult);
  end;

var
  Ans: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;
  Node: tNode;
  Bc: tSendRecord;
  I: Integer;
begin
  FillChar(Log1, SizeOf(Log1), 0);
  FillChar(Log2, SizeOf(Log2), 0);
  FHub := TLoopHub.Create;
  M := Open(1, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 NAM=LOOP PAIR=BUSM END=1');
  S1 := Open(2, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=LOOP PAIR=BUS1 END=1');
  S2 := Open(3, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=2 NAM=LOOP PAIR=BUS2 END=1');
  AssertTrue(FHub.AddPort('BUSM'));
  AssertTrue(FHub.AddPort('BUS1'));
  AssertTrue(FHub.AddPort('BUS2'));
  for Node := 1 to 2 do
  begin
    { request status of link -> status of link }
    Ask(Node, FCM_ReqLinkState, False, False, Ans, Len);
    AssertEquals(4, Len);
    AssertTrue(Ans.MessType = tpShortM);
    AssertEquals(FCS_LinkSAccesReq, Ans.FC);
    M^.ChGetNode(SNode, DNode);
    AssertEquals('answer comes from the polled slave', Node, SNode);
    AssertEquals(0, DNode);
    { reset of remote link -> ACK }
    Ask(Node, FCM_1stSetTransmit, False, False, Ans, Len);
    AssertEquals(FCS_Ack, Ans.FC);
    M^.ChGetNode(SNode, DNode);
    AssertEquals(Node, SNode);
    { request class 2 data (FCB = 1, FCV = 1) -> user data or no data }
    Ask(Node, FCM_ReqUserData2, True, True, Ans, Len);
    M^.ChGetNode(SNode, DNode);
    AssertEquals(Node, SNode);
    if Node = 1 then
    begin
      AssertTrue(Ans.MessType = tpLongM);
      AssertEquals(FCS_UserData, Ans.FC);
      AssertEquals(6, Len);
      AssertEquals($2A, Ans.Data[1]);
    end
    else
    begin
      AssertTrue(Ans.MessType = tpShortM);
      AssertEquals(FCS_DataNotAcces, Ans.FC);
      AssertEquals(4, Len);
    end;
  end;
  { each slave took only its own three requests, though it heard all
    twelve frames on the line }
  AssertEquals('slave 1 frames', 3, Log1.Got);
  AssertEquals('slave 2 frames', 3, Log2.Got);
  { broadcast: both take it, nobody answers }
  M^.ChDestNode(255);
  Bc := MakeRec(tpShortM, False, False, FCM_UserDataNoRep);
  SendRec(M, Bc, 4);
  for I := 1 to 50 do
  begin
    FHub.Pump;
    ServeSlave(S1, True, Log1);
    ServeSlave(S2, False, Log2);
  end;
  AssertEquals(1, Log1.Broadcasts);
  AssertEquals(1, Log2.Broadcasts);
  AssertTrue('no answer to a broadcast', M^.ChReceiveReady <> CHS_ReceiveReady);
  AssertTrue(FHub.Copied > 0);
end;

procedure TTestChnFT1_2.TestBalancedExchange;
var
  A, B: pChnVirt;
  Req, Rsp: tSendRecord;
  Got: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;
begin
  { station A (controlling, DIR = 1) as primary, station B as secondary }
  A := Open(1, 'NAM=FT1_2 MS=OFF PRI=ON DIR=1 LEN=0 NOD=1 DNO=2 NAM=LOOP PAIR=FTBAL END=1');
  B := Open(2, 'NAM=FT1_2 MS=OFF PRI=OFF DIR=0 LEN=0 NOD=2 DNO=1 NAM=LOOP PAIR=FTBAL END=2');
  { reset of remote link -> ACK }
  Req := MakeRec(tpShortM, False, False, FCM_1stSetTransmit);
  SendRec(A, Req, 4);
  Len := Recv(B, A, Got);
  AssertEquals(FCM_1stSetTransmit, Got.FC);
  B^.ChGetNode(SNode, DNode);
  AssertEquals(2, DNode);
  AssertEquals(1, SNode);
  Rsp := MakeRec(tpShortM, False, False, FCS_Ack);
  SendRec(B, Rsp, 4);
  Len := Recv(A, B, Got);
  AssertEquals(4, Len);
  AssertEquals(FCS_Ack, Got.FC);
  A^.ChGetNode(SNode, DNode);
  AssertEquals(2, SNode);
  AssertEquals(1, DNode);
  { user data with confirm (FCB = 1, FCV = 1) -> single character ACK }
  Req := MakeRec(tpLongM, True, True, FCM_UserDataReply);
  Req.Data[1] := $64;
  Req.Data[2] := $01;
  SendRec(A, Req, 6);
  Len := Recv(B, A, Got);
  AssertEquals(6, Len);
  AssertTrue(Got.FCB_ACD and Got.FCV_DFC);
  AssertEquals($64, Got.Data[1]);
  SendRec(B, MakeRec(tpSACK, False, False, 0), 1);
  Len := Recv(A, B, Got);
  AssertEquals(1, Len);
  AssertTrue(Got.MessType = tpSACK);
  { test function for link (FC 2, balanced only) -> ACK }
  SendRec(A, MakeRec(tpShortM, False, True, FCM_CheckLink), 4);
  Len := Recv(B, A, Got);
  AssertEquals(FCM_CheckLink, Got.FC);
  SendRec(B, MakeRec(tpShortM, False, False, FCS_Ack), 4);
  Len := Recv(A, B, Got);
  AssertEquals(FCS_Ack, Got.FC);
end;

{ Station B (DIR = 0, NOD = 2, DNO = 1) against a raw peer playing
  station A. Codes: DIR $80, PRM $40, FCB/ACD $20, FCV/DFC $10, FC. }
procedure TTestChnFT1_2.TestBalancedBothDirectionsOnOneChannel;
var
  B, Raw: pChnVirt;
  F: pChnFT1_2;
  Got: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;
  R: tSendRecord;
begin
  { PRI=OFF: the default direction of ChSend is secondary }
  B := Open(1, 'NAM=FT1_2 MS=OFF PRI=OFF LEN=0 NOD=2 DNO=1 NAM=LOOP PAIR=FTBD END=1');
  Raw := OpenRaw(2, 'FTBD');
  F := pChnFT1_2(B);
  B^.ChReceiveBuffer(@Got, SizeOf(Got));
  { A's request status of link to 2: C9 + 02 = CB }
  RawSend(Raw, '10 C9 02 CB 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_Ok, B^.ChReceiveResult);
  AssertEquals(FCM_ReqLinkState, Got.FC);
  AssertTrue('a request (PRM = 1)', F^.CH_RPrm);
  AssertTrue('DIR = 1: from station A', F^.CH_RDir);
  B^.ChGetNode(SNode, DNode);
  AssertEquals(2, DNode);
  AssertEquals(1, SNode);
  { A's ACK to B's request carries A's address 1: 80 + 01 = 81; a
    PRI=OFF channel takes it (it used to be res_ErrCode) }
  RawSend(Raw, '10 80 01 81 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_Ok, B^.ChReceiveResult);
  AssertEquals(FCS_Ack, Got.FC);
  AssertFalse('an answer (PRM = 0)', F^.CH_RPrm);
  AssertTrue(F^.CH_RDir);
  B^.ChGetNode(SNode, DNode);
  AssertEquals(1, SNode);
  AssertEquals(2, DNode);
  { E5 from A is an answer as well }
  RawSend(Raw, 'E5');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(1, Len);
  AssertTrue(Got.MessType = tpSACK);
  AssertFalse(F^.CH_RPrm);
  AssertFalse(F^.CH_RDir);
  { both directions sent without reconfiguring: B's answer (ChSend,
    address NOD = 2, DIR 0) and B's own request (address DNO = 1) }
  R := MakeRec(tpShortM, False, False, FCS_LinkSAccesReq);
  SendRec(B, R, 4);
  AssertEquals('status of link: 0B + 02', '10 0B 02 0D 16', RawRead(Raw));
  R := MakeRec(tpShortM, True, True, FCM_CheckLink);
  F^.ChSendAs(True, @R, 4);
  AssertEquals(res_Ok, B^.ChSendResult);
  AssertEquals('test function for link: 40+20+10+2 = 72, + 01', '10 72 01 73 16', RawRead(Raw));
  R := MakeRec(tpSACK, False, False, 0);
  F^.ChSendAs(False, @R, 1);
  AssertEquals(res_Ok, B^.ChSendResult);
  AssertEquals('E5', RawRead(Raw));
  { a primary sends no single character, in balanced mode too }
  F^.ChSendAs(True, @R, 1);
  AssertEquals(res_BadMessage, B^.ChSendResult);
  AssertEquals('', RawRead(Raw));
  AssertFalse('PRI= is unchanged', F^.CH_Master);
  { DIR=1 (station A) sends $80 on both directions }
  B^.ChSetParam('DIR=1');
  R := MakeRec(tpShortM, False, False, FCS_Ack);
  SendRec(B, R, 4);
  AssertEquals('10 80 02 82 16', RawRead(Raw));
  R := MakeRec(tpShortM, False, False, FCM_1stSetTransmit);
  F^.ChSendAs(True, @R, 4);
  AssertEquals('10 C0 01 C1 16', RawRead(Raw));
end;

procedure TTestChnFT1_2.TestBalancedBadInputIsReported;
var
  B, Raw: pChnVirt;
  F: pChnFT1_2;
  Got: tRecRecord;
  Len: Word;
begin
  B := Open(1, 'NAM=FT1_2 MS=OFF PRI=ON DIR=0 LEN=0 NOD=2 DNO=1 NAM=LOOP PAIR=FTBX END=1');
  Raw := OpenRaw(2, 'FTBX');
  F := pChnFT1_2(B);
  B^.ChReceiveBuffer(@Got, SizeOf(Got));
  { a request with DIR = 0, B's own side (an echo of B's line, or A
    configured as B): reported, not taken as the peer's }
  RawSend(Raw, '10 49 02 4B 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_ErrDir, B^.ChReceiveResult);
  AssertEquals(0, Len);
  AssertFalse(F^.CH_RPrm);
  AssertEquals('FT1_2: DIR bit says the frame came from this station''s own side',
    B^.ChResultStr(res_ErrDir));
  { an answer with DIR = 0 as well }
  RawSend(Raw, '10 00 01 01 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_ErrDir, B^.ChReceiveResult);
  { a request for another station (3) is ignored; garbage between frames
    is skipped; the next good frame comes through }
  RawSend(Raw, '10 C9 03 CC 16 00 FF 16 10 C9 02 CB 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_Ok, B^.ChReceiveResult);
  AssertEquals(FCM_ReqLinkState, Got.FC);
  AssertTrue(F^.CH_RPrm);
  AssertEquals(1, F^.CH_Rx.Ignored);
  { an answer from any address is taken and reported with it }
  RawSend(Raw, '10 80 07 87 16');
  AssertTrue(WaitReceive(B, 1000));
  B^.ChReceive(Len);
  AssertEquals(res_Ok, B^.ChReceiveResult);
  AssertFalse(F^.CH_RPrm);
  AssertEquals(7, B^.CH_RSNode);
end;

procedure TTestChnFT1_2.TestUnbalancedSendAsKeepsTheRole;
var
  M, Raw: pChnVirt;
  R: tSendRecord;
begin
  M := Open(1, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=LOOP PAIR=FTUS END=1');
  Raw := OpenRaw(2, 'FTUS');
  R := MakeRec(tpShortM, False, False, FCS_Ack);
  pChnFT1_2(M)^.ChSendAs(False, @R, 4);
  AssertEquals(res_BadMessage, M^.ChSendResult);
  AssertEquals('nothing sent', '', RawRead(Raw));
  pChnFT1_2(M)^.ChSendAs(True, @R, 4);
  AssertEquals(res_Ok, M^.ChSendResult);
  AssertEquals('RES stays 0: 40 + 01 = 41', '10 40 01 41 16', RawRead(Raw));
end;

procedure TTestChnFT1_2.TestGapDiscardsHalfFrame;
var
  S, Raw: pChnVirt;
  Rec: tRecRecord;
  Len: Word;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 GAP=10 NAM=LOOP PAIR=FTGAP END=1');
  Raw := OpenRaw(2, 'FTGAP');
  { no BD= below: 10 characters * 11 bits at 9600 Bd = 11.46 ms -> 12 ms }
  AssertEquals(12, pChnFT1_2(S)^.ChGapMs);
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  RawSend(Raw, '10 49');
  AssertTrue(S^.ChReceiveReady <> CHS_ReceiveReady);   { takes the 2 bytes }
  Sleep(40);
  { the rest of that frame, then request class 2 data (CS $7C) }
  RawSend(Raw, '01 4A 16 10 7B 01 7C 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals('the half frame was dropped', FCM_ReqUserData2, Rec.FC);
  AssertEquals(1, pChnFT1_2(S)^.CH_Rx.GapDrops);
  { GAP=0: the same split makes one frame }
  S^.ChSetParam('GAP=0');
  AssertEquals(0, pChnFT1_2(S)^.ChGapMs);
  RawSend(Raw, '10 49');
  AssertTrue(S^.ChReceiveReady <> CHS_ReceiveReady);
  Sleep(40);
  RawSend(Raw, '01 4A 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals(FCM_ReqLinkState, Rec.FC);
end;

procedure TTestChnFT1_2.TestGapUsesBaudRateBelow;
var
  C: pChnFT1_2;
begin
  New(C, Init);
  try
    { 10 characters * 11 bits at 1200 Bd = 91.7 ms -> 92 }
    C^.ChSetParam('NAM=FT1_2 GAP=10 NAM=BDT BD=1200 NAM=LOOP PAIR=FTBD');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(92, C^.ChGapMs);
    { 1 character at 115200 Bd = 0.095 ms: at least one tick }
    C^.ChSetParam('NAM=FT1_2 GAP=1 NAM=BDT BD=115200 NAM=LOOP PAIR=FTBD');
    AssertEquals(1, C^.ChGapMs);
    { 3 characters * 11 bits at 2400 Bd = 13.75 ms -> 14 }
    C^.ChSetParam('NAM=FT1_2 GAP=3 NAM=BDT BD=2400 NAM=LOOP PAIR=FTBD');
    AssertEquals(14, C^.ChGapMs);
    C^.ChOpen;
    C^.ChConnect;
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('the receiver uses it', 14, C^.CH_Rx.Cfg.GapMs);
    { the rate is taken when the stack is built and at ChConnect, not read
      again on every send: a rate changed below counts from the next
      ChConnect }
    pChnBaudTestLayer(C^.CH_Low)^.CH_Baud := 1200;
    AssertEquals(14, C^.ChGapMs);
    C^.ChDisConnect;
    C^.ChConnect;
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('3 characters * 11 bits at 1200 Bd = 27.5 ms -> 28', 28, C^.ChGapMs);
    AssertEquals(28, C^.CH_Rx.Cfg.GapMs);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnFT1_2.TestSetParamKeepsWaitingFrame;
var
  S, Raw: pChnVirt;
  Rec: tRecRecord;
  Len: Word;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=LOOP PAIR=FTKW END=1');
  Raw := OpenRaw(2, 'FTKW');
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  RawSend(Raw, '10 7B 01 7C 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChSetParam('GAP=3');
  AssertEquals(res_Ok, S^.ChResult);
  AssertEquals(CHS_ReceiveReady, S^.ChReceiveReady);
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals(4, Len);
  AssertTrue(Rec.MessType = tpShortM);
  AssertEquals(FCM_ReqUserData2, Rec.FC);
end;

procedure TTestChnFT1_2.TestFlushAndDisConnect;
var
  S, Raw: pChnVirt;
  Rec: tRecRecord;
  Len: Word;
begin
  S := Open(1, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=LOOP PAIR=FTFL END=1');
  Raw := OpenRaw(2, 'FTFL');
  S^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  RawSend(Raw, '10 49');
  AssertTrue(S^.ChReceiveReady <> CHS_ReceiveReady);   { half a frame taken }
  S^.ChReceiveFlush;
  RawSend(Raw, '01 4A 16 10 7B 01 7C 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals('the half frame was flushed', FCM_ReqUserData2, Rec.FC);
  S^.ChDisConnect;
  AssertEquals(res_Ok, S^.ChResult);
  AssertEquals(CHS_RecInactive, S^.ChReceiveReady);
  S^.ChReceive(Len);
  AssertEquals(res_WrongState, S^.ChReceiveResult);
  S^.ChConnect;
  AssertEquals(res_Ok, S^.ChResult);
  RawSend(Raw, '10 49 01 4A 16');
  AssertTrue(WaitReceive(S, 1000));
  S^.ChReceive(Len);
  AssertEquals(FCM_ReqLinkState, Rec.FC);
end;

procedure TTestChnFT1_2.TestChInitParam;
var
  C: pChnFT1_2;
begin
  New(C, ChInitParam('MS=OFF PRI=OFF LEN=0'));
  try
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('FT1_2', C^.CH_Type);
    AssertFalse(C^.CH_MaSl);
    AssertFalse(C^.CH_Master);
    AssertEquals(0, C^.CH_LenShortM);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnFT1_2.TestResultTexts;
var
  C: pChnFT1_2;
begin
  New(C, Init);
  try
    AssertTrue(Pos('checksum', C^.ChResultStr(res_ErrSum)) > 0);
    AssertTrue(Pos('length', C^.ChResultStr(res_ErrLen)) > 0);
    AssertTrue(Pos('PRM', C^.ChResultStr(res_ErrCode)) > 0);
    AssertTrue(Pos('frame', C^.ChResultStr(res_ErrFrame)) > 0);
  finally
    Dispose(C, Done);
  end;
end;

{ IEC 60870-5-1: at least 33 bit times of idle line between frames. On a
  line with a speed the FT 1.2 layer gives the line below IFG=33 unless a
  larger IFG= is given. Two 5-octet frames at 1200 Bd 8E1 (9.17 ms per
  character) sent one after the other reach the other end complete after
  10 characters (91.7 ms) plus the 33 bit times (27.5 ms): 119 ms, not 92. }
procedure TTestChnFT1_2.TestLineIdleBetweenFramesOnATimedLine;
var
  M, Raw: pChnVirt;
  Err, Got: string;
  T0, Took: QWord;
  Deadline: QWord;
begin
  M := Open(1, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=LOOP PAIR=FTIFG END=1 BD=1200 PAR=E');
  AssertTrue(M^.ChGetParam(''), Pos(' BD=1200 BIT=8 STOP=1 PAR=E IFG=33 ', M^.ChGetParam('')) > 0);
  Raw := OpenStack(ChnLoop.cName, 'PAIR=FTIFG END=2 BD=1200 PAR=E', Err);
  AssertTrue(Err, Raw <> nil);
  FChn[2] := Raw;
  Got := '';
  T0 := ChnClockUs;
  SendRec(M, MakeRec(tpShortM, False, False, FCM_ReqLinkState), 4);
  SendRec(M, MakeRec(tpShortM, False, False, FCM_ReqLinkState), 4);
  Deadline := ChMsTick + 2000;
  while (Length(Got) < 29) and (ChMsTick < Deadline) do
  begin
    M^.ChSendReady;                     { a held frame leaves at a poll when its time has come }
    Got := Trim(Got + ' ' + RawRead(Raw));
    if Length(Got) < 29 then
      ChnWaitAny(5);
  end;
  Took := ChnClockUs - T0;
  AssertEquals('10 49 01 4A 16 10 49 01 4A 16', Got);
  AssertTrue(Format('two frames took %d us', [Took]), Took >= 112000);
  { a larger IFG= given stays }
  M := Open(3, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=LOOP PAIR=FTIFH END=1 BD=1200 IFG=40');
  AssertTrue(M^.ChGetParam(''), Pos(' IFG=40', M^.ChGetParam('')) > 0);
  { no speed: nothing asked }
  M := Open(4, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=LOOP PAIR=FTIFI END=1');
  AssertEquals(M^.ChGetParam(''), 0, Pos('IFG', M^.ChGetParam('')));
end;

initialization
  RegisterTest(TTestChnFT1_2);
end.
