{ Tests of ChnICS: the manual's constants and Init defaults, parameters,
  the bytes on the line, broken frames through ChReceive, refused records,
  small receive buffers, and master/slave dialogues RD/DB, RL/LB, WD/OK
  over NAM=LOOP (manual ChnICS sections 4-6, docs/PROTOCOLS.md section 6). }
unit TestChnICS;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnICS, TestSupport;

type
  TTestChnICS = class(TTestCase)
  private
    Master, Slave, Raw: pChnVirt;
    MRec, SRec: tRecRecord;
    RawBuf: array[0..1023] of Byte;
    procedure OpenPair(const Pair: string);
    procedure OpenRaw(const Pair, IcsParams: string);
    function RawReceived: string;
    procedure RawSend(const S: string);
    procedure Request(Chn, Peer: pChnVirt; var Rec: tSendRecord; Count: Integer);
    function Receive(Chn, Peer: pChnVirt; var Len: Word): Boolean;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestConstants;
    procedure TestRecordLayout;
    procedure TestInitDefaults;
    procedure TestRegistry;
    procedure TestParameters;
    procedure TestNodeParameterRange;
    procedure TestGetParamRoundTrip;
    procedure TestResultTexts;
    procedure TestBytesOnTheLine;
    procedure TestReceiveFromTheLine;
    procedure TestBrokenFrameThroughChReceive;
    procedure TestEveryReceiveErrorThroughChReceive;
    procedure TestInvalidRecordSendsNothing;
    procedure TestSendBufferTooSmall;
    procedure TestSmallReceiveBuffer;
    procedure TestReceiveWithoutMessageOrBuffer;
    procedure TestSendWhenClosed;
    procedure TestFlushDropsPartialFrame;
    procedure TestReadData;
    procedure TestReadParams;
    procedure TestWriteData;
  end;

implementation

const
  { the hand-worked frame of TestChnICSCodec: 2 <- 1 'RD' 0, numbers 0 10 15 }
  FrameA = #1#1#1'2'#2'1RD0,0,10,15'#3#$3C#4;

procedure TTestChnICS.SetUp;
begin
  Master := nil;
  Slave := nil;
  Raw := nil;
  FillChar(MRec, SizeOf(MRec), 0);
  FillChar(SRec, SizeOf(SRec), 0);
end;

procedure TTestChnICS.TearDown;
begin
  if Master <> nil then
    Dispose(Master, Done);
  if Slave <> nil then
    Dispose(Slave, Done);
  if Raw <> nil then
    Dispose(Raw, Done);
end;

procedure TTestChnICS.OpenPair(const Pair: string);
var
  Err: string;
begin
  Master := OpenStack(cName, 'NAM=ICS MAS=MASTER NOD=1 DNO=2 NAM=LOOP PAIR=' + Pair + ' END=1', Err);
  AssertTrue(Err, Master <> nil);
  Slave := OpenStack(cName, 'NAM=ICS MAS=SLAVE NOD=2 DNO=1 NAM=LOOP PAIR=' + Pair + ' END=2', Err);
  AssertTrue(Err, Slave <> nil);
  Master^.ChReceiveBuffer(@MRec, SizeOf(MRec));
  Slave^.ChReceiveBuffer(@SRec, SizeOf(SRec));
end;

{ An ICS stack (Master) against a bare LOOP end (Raw) that shows the bytes. }
procedure TTestChnICS.OpenRaw(const Pair, IcsParams: string);
var
  Err: string;
begin
  Master := OpenStack(cName, IcsParams + ' NAM=LOOP PAIR=' + Pair + ' END=1', Err);
  AssertTrue(Err, Master <> nil);
  Raw := OpenStack(ChnLoop.cName, 'PAIR=' + Pair + ' END=2', Err);
  AssertTrue(Err, Raw <> nil);
  Raw^.ChReceiveBuffer(@RawBuf, SizeOf(RawBuf));
  Master^.ChReceiveBuffer(@MRec, SizeOf(MRec));
end;

function TTestChnICS.RawReceived: string;
var
  Len: Word;
begin
  Result := '';
  { NAM=LOOP moves bytes during ChSend, so what was sent is there now }
  while Raw^.ChReceiveReady = CHS_ReceiveReady do
  begin
    Len := 0;
    Raw^.ChReceive(Len);
    SetLength(Result, Length(Result) + Len);
    Move(RawBuf, Result[Length(Result) - Len + 1], Len);
  end;
end;

procedure TTestChnICS.RawSend(const S: string);
begin
  AssertTrue('raw end idle', WaitSent(Raw, 1000, Master));
  Raw^.ChSend(@S[1], Length(S));
  AssertEquals(res_Ok, Raw^.ChSendResult);
end;

procedure TTestChnICS.Request(Chn, Peer: pChnVirt; var Rec: tSendRecord; Count: Integer);
begin
  AssertTrue('transmitter idle', WaitSent(Chn, 1000, Peer));
  Chn^.ChSend(@Rec, 4 + Count * SizeOf(tData));
  AssertEquals('ChSend', res_Ok, Chn^.ChSendResult);
end;

function TTestChnICS.Receive(Chn, Peer: pChnVirt; var Len: Word): Boolean;
begin
  Len := 0;
  Result := WaitReceive(Chn, 2000, Peer);
  if Result then
    Chn^.ChReceive(Len);
end;

procedure TTestChnICS.TestConstants;
begin
  AssertEquals('ICS', cName);
  AssertEquals(32, MaxDataLen);
  AssertEquals(200, MaxTextLen);
  AssertEquals(65500, MaxTBuf);
  AssertEquals(MaxTBuf, MaxTBuff);
  AssertEquals(1, SOH);
  AssertEquals(2, STX);
  AssertEquals(3, ETX);
  AssertEquals(4, EOT);
  AssertEquals('RD', OCM_ReadData);
  AssertEquals('RL', OCM_ReadParams);
  AssertEquals('WD', OCM_WriteData);
  AssertEquals('DB', OCS_ReadData);
  AssertEquals('LB', OCS_ReadParams);
  AssertEquals('OK', OCS_WriteData);
  AssertEquals(OCM_ReadData, OPM_ReadData);
  AssertEquals(OCM_ReadParams, OPM_ReadParams);
  AssertEquals(OCM_WriteData, OPM_WriteData);
  AssertEquals($20, res_ErrFrame);
  AssertEquals($21, res_ErrSum);
  AssertEquals($22, res_ErrLen);
  AssertEquals($23, res_ErrVal);
  AssertEquals($24, res_ErrETX);
  AssertEquals($25, res_ErrEOT);
  AssertEquals(2, SizeOf(tData));
  AssertEquals(-32768, Low(tData));
end;

procedure TTestChnICS.TestRecordLayout;
var
  R: tSendRecord;
begin
  AssertEquals(269, SizeOf(tSendRecord));
  AssertEquals(269, SizeOf(tRecRecord));
  AssertEquals(0, PtrUInt(@R.OpCode) - PtrUInt(@R));
  AssertEquals(3, PtrUInt(@R.BlockNum) - PtrUInt(@R));
  AssertEquals(4, PtrUInt(@R.Data) - PtrUInt(@R));
  AssertEquals(68, PtrUInt(@R.Text) - PtrUInt(@R));
  AssertEquals(3, SizeOf(R.OpCode));
  AssertEquals(64, SizeOf(R.Data));
  AssertEquals(201, SizeOf(R.Text));
end;

procedure TTestChnICS.TestInitDefaults;
var
  C: pChnICS;
begin
  New(C, Init);
  try
    AssertEquals('ICS', C^.CH_Type);
    AssertEquals('ICS', C^.CH_Name);
    AssertEquals(ChNumName('ICS'), C^.CH_NumName);
    AssertFalse(C^.CH_RTick);
    AssertTrue(C^.CH_SBuff = nil);
    AssertEquals(0, C^.CH_MSBuff);
    AssertEquals(0, C^.CH_LRMess);
    AssertTrue(C^.CH_Master);
    AssertEquals(0, C^.CH_DataI);
    AssertEquals('', C^.CH_PomS);
    AssertEquals(207, C^.ChMaxNode);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnICS.TestRegistry;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit(ChnICS.cName);
  try
    AssertTrue(C <> nil);
    AssertTrue(TypeOf(C^) = TypeOf(tChnICS));
    AssertEquals('ICS', C^.CH_Type);
  finally
    Dispose(C, Done);
  end;
  C := ChnCollection^.ChNewInit('ics');
  AssertTrue('names are not case sensitive', C <> nil);
  Dispose(C, Done);
end;

procedure TTestChnICS.TestParameters;
var
  C: pChnICS;
begin
  New(C, Init);
  try
    C^.ChSetParam('MAS=SLAVE LSB=500 NOD=3 DNO=4 NAM=LOOP PAIR=ICSP');
    AssertEquals(C^.ChParamError, res_Ok, C^.ChResult);
    AssertFalse(C^.CH_Master);
    AssertEquals(500, C^.CH_MSBuff);
    AssertTrue(C^.CH_SBuff <> nil);
    AssertEquals(3, C^.CH_Node);
    AssertEquals(4, C^.CH_DNode);
    C^.ChSetParam('MAS=master LSB=0');
    AssertEquals(res_Ok, C^.ChResult);
    AssertTrue(C^.CH_Master);
    AssertTrue(C^.CH_SBuff = nil);
    C^.ChSetParam('MAS=BOTH');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('MAS=BOTH', C^.ChParamError);
    C^.ChSetParam('LSB=65501');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('LSB=-1');
    AssertEquals(res_BadParam, C^.ChResult);
    C^.ChSetParam('XYZ=1');
    AssertEquals(res_UnknownParam, C^.ChResult);
    { a bad token changes nothing }
    C^.ChSetParam('MAS=SLAVE NOD=208');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertTrue(C^.CH_Master);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnICS.TestNodeParameterRange;
var
  C: pChnICS;
begin
  New(C, Init);
  try
    C^.ChSetParam('NOD=207 DNO=0');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(207, C^.CH_Node);
    C^.ChSetParam('NOD=208');
    AssertEquals('NOD=208', res_BadParam, C^.ChResult);
    C^.ChSetParam('DNO=208');
    AssertEquals('DNO=208', res_BadParam, C^.ChResult);
    C^.ChSetParam('DNO=-1');
    AssertEquals('DNO=-1', res_BadParam, C^.ChResult);
    C^.ChSetParam('NOD=x');
    AssertEquals('NOD=x', res_BadParam, C^.ChResult);
    AssertEquals(207, C^.CH_Node);
    AssertEquals(0, C^.CH_DNode);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnICS.TestGetParamRoundTrip;
var
  A, B: pChnVirt;
  P: tParamStr;
begin
  A := ChnCollection^.ChNewInit(cName);
  B := ChnCollection^.ChNewInit(cName);
  try
    A^.ChSetParam('NAM=ICS MAS=SLAVE LSB=321 NOD=7 DNO=9 NAM=LOOP PAIR=ICSG END=2');
    AssertEquals(res_Ok, A^.ChResult);
    P := A^.ChGetParam('');
    AssertTrue(P, Pos('NAM=ICS NOD=7 DNO=9 MAS=SLAVE LSB=321 NAM=LOOP', P) = 1);
    B^.ChSetParam(P);
    AssertEquals(B^.ChParamError, res_Ok, B^.ChResult);
    AssertEquals(P, B^.ChGetParam(''));
    AssertEquals('MAS=SLAVE', A^.ChGetParam('MAS'));
  finally
    Dispose(A, Done);
    Dispose(B, Done);
  end;
end;

procedure TTestChnICS.TestResultTexts;
var
  C: pChnVirt;
  R: tChResult;
begin
  C := ChnCollection^.ChNewInit(cName);
  try
    for R := res_ErrFrame to res_ErrEOT do
      AssertTrue(C^.ChResultStr(R), Pos('ICS: ', C^.ChResultStr(R)) = 1);
    AssertEquals('ICS: checksum error', C^.ChResultStr(res_ErrSum));
    AssertTrue(Pos('unknown', C^.ChResultStr(res_ErrEOT + 1)) > 0);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnICS.TestBytesOnTheLine;
var
  R: tSendRecord;
  Expected, Got: string;
begin
  OpenRaw('ICSL', 'NAM=ICS NOD=1 DNO=2');
  FillChar(R, SizeOf(R), 0);
  with R do
  begin
    OpCode := OCM_ReadData;
    BlockNum := 0;
    Data[0] := 0;
    Data[1] := 10;
    Data[2] := 15;
  end;
  Master^.ChSend(@R, 4 + 3 * SizeOf(tData));
  AssertEquals(res_Ok, Master^.ChSendResult);
  AssertEquals(FrameA, RawReceived);
  AssertEquals('CH_SSum', $3C, pChnICS(Master)^.CH_SSum);
  { the same with the manual's text: the text follows the last number }
  R.Text := '"Pozadavek"';
  Master^.ChSend(@R, 4 + 3 * SizeOf(tData));
  Got := RawReceived;
  Expected := #1#1#1'2'#2'1RD0,0,10,15"Pozadavek"'#3;
  AssertEquals(Expected, Copy(Got, 1, Length(Expected)));
  AssertEquals(Length(Expected) + 2, Length(Got));
end;

procedure TTestChnICS.TestReceiveFromTheLine;
var
  Len: Word;
  SNode, DNode: tNode;
begin
  OpenRaw('ICSR', 'NAM=ICS MAS=SLAVE NOD=2 DNO=1');
  RawSend('noise' + FrameA);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(4 + 3 * SizeOf(tData), Len);
  AssertEquals(Len, pChnICS(Master)^.CH_LRMess);
  AssertEquals(OCM_ReadData, MRec.OpCode);
  AssertEquals(15, MRec.Data[2]);
  AssertEquals('', MRec.Text);
  Master^.ChGetNode(SNode, DNode);
  AssertEquals('SNode', 1, SNode);
  AssertEquals('DNode', 2, DNode);
  { nothing more waiting }
  AssertFalse(WaitReceive(Master, 20, Raw));
end;

procedure TTestChnICS.TestBrokenFrameThroughChReceive;
var
  Bad: string;
  Len: Word;
begin
  OpenRaw('ICSB', 'NAM=ICS MAS=SLAVE NOD=2 DNO=1');
  Bad := FrameA;
  Bad[Length(Bad) - 1] := #$3D;
  { broken frame and a good one in one chunk: both come out, in order }
  RawSend(Bad + FrameA);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals('broken frame: Len', 0, Len);
  AssertEquals(res_ErrSum, Master^.ChReceiveResult);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(10, Len);
  AssertEquals(10, MRec.Data[1]);
end;

procedure TTestChnICS.TestEveryReceiveErrorThroughChReceive;
const
  Bad: array[0..5] of string = (
    #1'2X',                                    { missing STX }
    #1#1#1'2'#2'1RD0,0,10,15'#3#$3D#4,          { checksum }
    '',                                        { 33 numbers, filled in below }
    #1'2'#2'1RD0,--5',                         { malformed number }
    #1'2'#2'1RD0,"t"X',                        { no ETX }
    #1#1#1'2'#2'1RD0,0,10,15'#3#$3C'X');       { no EOT }
  Codes: array[0..5] of tChResult = (res_ErrFrame, res_ErrSum, res_ErrLen,
    res_ErrVal, res_ErrETX, res_ErrEOT);
var
  I, J: Integer;
  S: string;
  Len: Word;
begin
  OpenRaw('ICSE', 'NAM=ICS MAS=SLAVE NOD=2 DNO=1');
  for I := Low(Bad) to High(Bad) do
  begin
    S := Bad[I];
    if I = 2 then
    begin
      S := #1'2'#2'1RD0,';
      for J := 1 to 33 do
        S := S + '1,';
    end;
    RawSend(S + FrameA);
    AssertTrue(Receive(Master, Raw, Len));
    AssertEquals('Len of broken frame ' + IntToStr(I), 0, Len);
    AssertEquals('code of broken frame ' + IntToStr(I), Codes[I], Master^.ChReceiveResult);
    AssertTrue(Receive(Master, Raw, Len));
    AssertEquals('frame after ' + IntToStr(I), res_Ok, Master^.ChReceiveResult);
    AssertEquals(10, Len);
  end;
end;

procedure TTestChnICS.TestInvalidRecordSendsNothing;
var
  R: tSendRecord;
  Expected: tChResult;
  Step: Integer;
begin
  OpenRaw('ICSI', 'NAM=ICS NOD=1 DNO=2');
  for Step := 0 to 8 do
  begin
    FillChar(R, SizeOf(R), 0);
    R.OpCode := OCM_ReadData;
    R.Text := '"t"';
    Expected := res_BadMessage;
    case Step of
      0: Master^.ChDestNode(208);
      1: PByte(@R.BlockNum)^ := 10;
      2: R.Text := '5t5';          { digit as delimiter }
      3: R.Text := '"t'#10'"';      { control character inside }
      4: R.Text := '"t''';          { delimiters differ }
      5: R.OpCode := 'R';
      6: begin R.Text := ''; Expected := res_ErrLen; end;   { Len for 33 numbers }
      7: begin PByte(@R.Text)^ := 201; Expected := res_ErrLen; end;
      8: R.OpCode := #9'D';
    end;
    if Step = 6 then
      Master^.ChSend(@R, 4 + 33 * SizeOf(tData))
    else
      Master^.ChSend(@R, 4);
    AssertEquals('step ' + IntToStr(Step), Expected, Master^.ChSendResult);
    AssertEquals('step ' + IntToStr(Step) + ' sent nothing', '', RawReceived);
    Master^.ChDestNode(2);
  end;
  { and the channel still works }
  FillChar(R, SizeOf(R), 0);
  R.OpCode := OCM_ReadData;
  R.Data[1] := 10;
  R.Data[2] := 15;
  Master^.ChSend(@R, 10);
  AssertEquals(res_Ok, Master^.ChSendResult);
  AssertEquals(FrameA, RawReceived);
end;

procedure TTestChnICS.TestSendBufferTooSmall;
var
  R: tSendRecord;
begin
  OpenRaw('ICSS', 'NAM=ICS NOD=1 DNO=2 LSB=20');
  FillChar(R, SizeOf(R), 0);
  R.OpCode := OCM_ReadData;
  R.Data[1] := 10;
  R.Data[2] := 15;
  { FrameA is exactly 20 bytes }
  Master^.ChSend(@R, 10);
  AssertEquals(res_Ok, Master^.ChSendResult);
  AssertEquals(FrameA, RawReceived);
  R.Data[2] := 150;
  Master^.ChSend(@R, 10);
  AssertEquals(res_TooLong, Master^.ChSendResult);
  AssertEquals('', RawReceived);
  { LSB cannot change while the channel is open }
  Master^.ChSetParam('LSB=500');
  AssertEquals(res_WrongState, Master^.ChResult);
end;

procedure TTestChnICS.TestSmallReceiveBuffer;
type
  tGuarded = record
    Rec  : array[0..71] of Byte;
    Guard: array[0..15] of Byte;
  end;
var
  G: tGuarded;
  Len: Word;

  procedure CheckGuard;
  var
    K: Integer;
  begin
    for K := 0 to High(G.Guard) do
      AssertEquals('guard byte ' + IntToStr(K), $5A, G.Guard[K]);
  end;

begin
  OpenRaw('ICSM', 'NAM=ICS MAS=SLAVE NOD=2 DNO=1');
  FillChar(G, SizeOf(G), $5A);
  { room for the header and three numbers only }
  Master^.ChReceiveBuffer(@G, 10);
  RawSend(FrameA);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(10, Len);
  AssertEquals(15, PSmallInt(@G.Rec[8])^);
  AssertEquals('byte 10 untouched', $5A, G.Rec[10]);
  { ... ^2C=0A (as in FrameA) ^31=3B ^2C=17 ^32=25 ^2C=09 ^33=3A ^2C=16
    ^34=22 ^03=21 }
  RawSend(#1'2'#2'1RD0,1,2,3,4'#3#$21#4);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals('four numbers into 10 bytes', 0, Len);
  AssertEquals(res_ErrLen, Master^.ChReceiveResult);
  AssertEquals('byte 10 still untouched', $5A, G.Rec[10]);
  { 72 bytes hold a text of up to 3 characters (68 + 1 + 3) }
  FillChar(G, SizeOf(G), $5A);
  Master^.ChReceiveBuffer(@G, 72);
  { 01^32^02^31^52^44^30^2C^22^61^22^03: 01 33 31 00 52 16 26 0A 28 49 6B 68 }
  RawSend(#1'2'#2'1RD0,"a"'#3#$68#4);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(4, Len);
  AssertEquals(3, G.Rec[68]);
  AssertEquals(Ord('"'), G.Rec[71]);
  CheckGuard;
  { 01^32^02^31^52^44^30^2C^22^61^62^22^03: ... 28 49 2B 09 0A }
  RawSend(#1'2'#2'1RD0,"ab"'#3#$0A#4);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals('text of 4 into 72 bytes', 0, Len);
  AssertEquals(res_ErrLen, Master^.ChReceiveResult);
  CheckGuard;
end;

procedure TTestChnICS.TestReceiveWithoutMessageOrBuffer;
var
  Len: Word;
begin
  OpenPair('ICSN');
  Len := 99;
  Master^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals(res_NoMessage, Master^.ChReceiveResult);
  Master^.ChReceiveBuffer(nil, 0);
  AssertEquals(res_NoRecBuff, Master^.ChReceiveResult);
  Master^.ChReceive(Len);
  AssertEquals(res_NoRecBuff, Master^.ChReceiveResult);
end;

procedure TTestChnICS.TestSendWhenClosed;
var
  C: pChnVirt;
  R: tSendRecord;
begin
  C := ChnCollection^.ChNewInit(cName);
  try
    FillChar(R, SizeOf(R), 0);
    R.OpCode := OCM_ReadData;
    C^.ChSend(@R, 4);
    AssertEquals(res_WrongState, C^.ChSendResult);
    C^.ChOpen;
    AssertEquals('no lower layer', res_NoLowLayer, C^.ChResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnICS.TestFlushDropsPartialFrame;
var
  Len: Word;
begin
  OpenRaw('ICSF', 'NAM=ICS MAS=SLAVE NOD=2 DNO=1');
  RawSend(Copy(FrameA, 1, 12));           { up to '0,0,' }
  AssertFalse(WaitReceive(Master, 20, Raw));
  AssertEquals('one number received', 1, pChnICS(Master)^.CH_DataI);
  Master^.ChReceiveFlush;
  AssertEquals(0, pChnICS(Master)^.CH_Codec.Count);
  { the rest of the frame alone has no SOH: nothing comes out }
  RawSend(Copy(FrameA, 13, Length(FrameA)));
  AssertFalse(WaitReceive(Master, 20, Raw));
  RawSend(FrameA);
  AssertTrue(Receive(Master, Raw, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(10, Len);
end;

procedure TTestChnICS.TestReadData;
var
  Q: tSendRecord;
  Len: Word;
  SNode, DNode: tNode;
  I: Integer;
begin
  OpenPair('ICSRD');
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCM_ReadData;
  Q.BlockNum := 3;
  Q.Data[0] := 100;     { first register }
  Q.Data[1] := 32;      { how many }
  Request(Master, Slave, Q, 2);
  AssertTrue('slave got the request', Receive(Slave, Master, Len));
  AssertEquals(res_Ok, Slave^.ChReceiveResult);
  AssertEquals(8, Len);
  AssertEquals(OCM_ReadData, SRec.OpCode);
  AssertEquals(3, SRec.BlockNum);
  AssertEquals(100, SRec.Data[0]);
  AssertEquals(32, SRec.Data[1]);
  Slave^.ChGetNode(SNode, DNode);
  AssertEquals(1, SNode);
  AssertEquals(2, DNode);
  { the answer: 32 numbers including both 16-bit extremes }
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCS_ReadData;
  Q.BlockNum := SRec.BlockNum;
  for I := 0 to MaxDataLen - 1 do
    Q.Data[I] := I * 2000 - 32768 + SRec.Data[0];
  Q.Data[31] := 32767;
  Request(Slave, Master, Q, MaxDataLen);
  AssertTrue('master got the answer', Receive(Master, Slave, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(4 + MaxDataLen * SizeOf(tData), Len);
  AssertEquals(OCS_ReadData, MRec.OpCode);
  AssertEquals(3, MRec.BlockNum);
  for I := 0 to MaxDataLen - 1 do
    AssertEquals('number ' + IntToStr(I), Q.Data[I], MRec.Data[I]);
  Master^.ChGetNode(SNode, DNode);
  AssertEquals(2, SNode);
  AssertEquals(1, DNode);
end;

procedure TTestChnICS.TestReadParams;
var
  Q: tSendRecord;
  Len: Word;
begin
  OpenPair('ICSRL');
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCM_ReadParams;
  Q.BlockNum := 9;
  Request(Master, Slave, Q, 0);
  AssertTrue(Receive(Slave, Master, Len));
  AssertEquals(4, Len);
  AssertEquals(OCM_ReadParams, SRec.OpCode);
  AssertEquals('', SRec.Text);
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCS_ReadParams;
  Q.BlockNum := 9;
  Q.Data[0] := -5;
  Q.Text := '/PLC DACS v2/';
  Request(Slave, Master, Q, 1);
  AssertTrue(Receive(Master, Slave, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(6, Len);
  AssertEquals(OCS_ReadParams, MRec.OpCode);
  AssertEquals(-5, MRec.Data[0]);
  AssertEquals('the text arrives in Text, with its delimiters', '/PLC DACS v2/', MRec.Text);
end;

procedure TTestChnICS.TestWriteData;
var
  Q: tSendRecord;
  Len: Word;
begin
  OpenPair('ICSWD');
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCM_WriteData;
  Q.BlockNum := 1;
  Q.Data[0] := -32768;
  Q.Data[1] := 0;
  Q.Data[2] := 32767;
  Q.Text := '#' + StringOfChar('w', MaxTextLen - 2) + '#';
  Request(Master, Slave, Q, 3);
  AssertTrue(Receive(Slave, Master, Len));
  AssertEquals(res_Ok, Slave^.ChReceiveResult);
  AssertEquals(10, Len);
  AssertEquals(OCM_WriteData, SRec.OpCode);
  AssertEquals(-32768, SRec.Data[0]);
  AssertEquals(32767, SRec.Data[2]);
  AssertEquals(MaxTextLen, Length(SRec.Text));
  AssertEquals(Q.Text, SRec.Text);
  FillChar(Q, SizeOf(Q), 0);
  Q.OpCode := OCS_WriteData;
  Q.BlockNum := 1;
  Request(Slave, Master, Q, 0);
  AssertTrue(Receive(Master, Slave, Len));
  AssertEquals(res_Ok, Master^.ChReceiveResult);
  AssertEquals(4, Len);
  AssertEquals(OCS_WriteData, MRec.OpCode);
  AssertEquals(1, MRec.BlockNum);
end;

initialization
  RegisterTest(TTestChnICS);
end.
