{ Tests of unit ChnPccc: addresses (good ones and every kind of bad one),
  request bytes worked out by hand from the 0F A2 / AA / AB layouts of
  Rockwell 1770-6.5.16, plans split over several requests, reply decoding,
  and the requests compared byte for byte with the ones the Python DF1
  client (df1py3) put on the wire (tests/data/df1py3-requests.txt, captured
  from that program on a pty; our frame is encoded with the captured TNS). }
unit TestChnPccc;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnDF1Codec, ChnPcccNames,
  ChnPccc, TestSupport;

type
  TTestChnPccc = class(TTestCase)
  private
    function Addr(const S: string): tPcccAddr;
    procedure BadAddr(const S, Part: string);
    function ReadReq(const S: string; Count: LongInt; Index: LongInt = 0): string;
  published
    procedure TestRecordLayout;
    procedure TestGoodAddresses;
    procedure TestBadAddresses;
    procedure TestReadRequests;
    procedure TestLargeFieldsEscaped;
    procedure TestWriteRequests;
    procedure TestBitWrites;
    procedure TestValueRanges;
    procedure TestPlanSplitsLongReads;
    procedure TestCountThatDoesNotFit;
    procedure TestDecodeInts;
    procedure TestDecodeFloatsAndLongs;
    procedure TestDecodeBitsAcrossWords;
    procedure TestDecodeRefusesWrongLength;
    procedure TestStrings;
    procedure TestCheckReply;
    procedure TestLocalStsTexts;
    procedure TestSameRequestsAsPythonClient;
  end;

implementation

function Hex(const R: tSendRecord; Len: Word): string;
begin
  Result := BytesToHex(R.Data, Len - cSizeHead);
end;

function TTestChnPccc.Addr(const S: string): tPcccAddr;
var
  Err: ShortString;
begin
  AssertEquals('parse ' + S + ': ' + Err, res_Ok, PcccParseAddress(S, Result, Err));
end;

procedure TTestChnPccc.BadAddr(const S, Part: string);
var
  A: tPcccAddr;
  Err: ShortString;
begin
  AssertEquals('"' + S + '" refused', res_PcccAddress, PcccParseAddress(S, A, Err));
  AssertTrue('"' + S + '": the text names ' + Part + ': ' + Err, Pos(Part, Err) > 0);
end;

function TTestChnPccc.ReadReq(const S: string; Count: LongInt; Index: LongInt): string;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len, Expect: Word;
begin
  AssertEquals('plan ' + S + ' ' + Err, res_Ok, PcccPlan(Addr(S), Count, False, MaxDataLen, P, Err));
  AssertEquals('build', res_Ok, PcccBuildPlanRead(P, Index, 7, Req, Len, Expect));
  AssertEquals('CF', $0FA2, Req.CF);
  AssertEquals('TNS', 7, Req.Tns);
  Result := Hex(Req, Len);
end;

procedure TTestChnPccc.TestRecordLayout;
var
  A: tPcccAddr;
begin
  AssertEquals('SizeOf(tPcccAddr)', 8, SizeOf(tPcccAddr));
  AssertEquals('FileType@0', 0, PtrUInt(@A.FileType) - PtrUInt(@A));
  AssertEquals('FileNo@1', 1, PtrUInt(@A.FileNo) - PtrUInt(@A));
  AssertEquals('Elem@3', 3, PtrUInt(@A.Elem) - PtrUInt(@A));
  AssertEquals('Sub@5', 5, PtrUInt(@A.Sub) - PtrUInt(@A));
  AssertEquals('HasSub@6', 6, PtrUInt(@A.HasSub) - PtrUInt(@A));
  AssertEquals('Bit@7', 7, PtrUInt(@A.Bit) - PtrUInt(@A));
  AssertEquals('SizeOf(tPcccPlan)', 25, SizeOf(tPcccPlan));
end;

procedure TTestChnPccc.TestGoodAddresses;
var
  A: tPcccAddr;
begin
  A := Addr('N7:0');
  AssertEquals($89, A.FileType); AssertEquals(7, A.FileNo); AssertEquals(0, A.Elem);
  AssertEquals(-1, A.Bit); AssertFalse(A.HasSub);
  A := Addr(' f8:2 ');
  AssertEquals($8A, A.FileType); AssertEquals(8, A.FileNo); AssertEquals(2, A.Elem);
  A := Addr('B3:1/4');
  AssertEquals($85, A.FileType); AssertEquals(1, A.Elem); AssertEquals(4, A.Bit);
  A := Addr('B3/20');                    { bit 20 of the file = word 1, bit 4 }
  AssertEquals(1, A.Elem); AssertEquals(4, A.Bit);
  AssertEquals('B3:1/4', PcccAddressText(A));
  A := Addr('T4:0.ACC');
  AssertEquals($86, A.FileType); AssertTrue(A.HasSub); AssertEquals(2, A.Sub); AssertEquals(-1, A.Bit);
  AssertEquals('T4:0.ACC', PcccAddressText(A));
  A := Addr('T4:1.PRE'); AssertEquals(1, A.Sub);
  A := Addr('T4:1.DN'); AssertEquals(0, A.Sub); AssertEquals(13, A.Bit);
  AssertEquals('T4:1.DN', PcccAddressText(A));
  A := Addr('T4:1.EN'); AssertEquals(15, A.Bit);
  A := Addr('T4:1.TT'); AssertEquals(14, A.Bit);
  A := Addr('C5:0.PRE'); AssertEquals($87, A.FileType); AssertEquals(1, A.Sub);
  A := Addr('C5:0.CU'); AssertEquals(15, A.Bit);
  A := Addr('C5:0.CD'); AssertEquals(14, A.Bit);
  A := Addr('C5:0.OV'); AssertEquals(12, A.Bit);
  A := Addr('C5:0.UN'); AssertEquals(11, A.Bit);
  A := Addr('C5:0.UA'); AssertEquals(10, A.Bit);
  A := Addr('R6:0.IN'); AssertEquals(9, A.Bit);
  A := Addr('R6:0.FD'); AssertEquals(8, A.Bit); AssertEquals('R6:0.FD', PcccAddressText(A));
  A := Addr('R6:0.EN'); AssertEquals(15, A.Bit);
  A := Addr('R6:0.UL'); AssertEquals(10, A.Bit);
  A := Addr('R6:2.LEN'); AssertEquals($88, A.FileType); AssertEquals(1, A.Sub);
  A := Addr('R6:2.POS'); AssertEquals(2, A.Sub);
  A := Addr('R6:2.POS/3'); AssertEquals(2, A.Sub); AssertEquals(3, A.Bit);
  AssertEquals('R6:2.POS/3', PcccAddressText(A));
  A := Addr('ST9:0'); AssertEquals($8D, A.FileType); AssertEquals(9, A.FileNo);
  A := Addr('L10:3'); AssertEquals($91, A.FileType); AssertEquals(3, A.Elem);
  A := Addr('A11:0'); AssertEquals($8E, A.FileType);
  A := Addr('S:1'); AssertEquals($84, A.FileType); AssertEquals(2, A.FileNo);
  A := Addr('S2:1/5'); AssertEquals(5, A.Bit);
  A := Addr('O0:0'); AssertEquals($8B, A.FileType); AssertEquals(0, A.FileNo);
  A := Addr('I:0'); AssertEquals($8C, A.FileType); AssertEquals(1, A.FileNo);
  A := Addr('N255:65535'); AssertEquals(255, A.FileNo); AssertEquals(65535, A.Elem);
  A := Addr('N7:0/15'); AssertEquals(15, A.Bit);
end;

procedure TTestChnPccc.TestBadAddresses;
begin
  BadAddr('', 'empty');
  BadAddr('X7:0', 'file type "X"');
  BadAddr('7:0', 'file type ""');
  BadAddr('N:0', 'file number missing');
  BadAddr('N7', '":element" missing');
  BadAddr('N7:', 'element ""');
  BadAddr('N7:x', 'element ""');
  BadAddr('N7:65536', 'element "65536"');
  BadAddr('N256:0', 'file number "256"');
  BadAddr('N2:0', 'file number 2');
  BadAddr('O1:0', 'O is file 0');
  BadAddr('I0:0', 'I is file 1');
  BadAddr('S3:0', 'S is file 2');
  BadAddr('N7;0', '":" expected');
  BadAddr('N7:0/16', 'bit "16"');
  BadAddr('N7:0/', 'bit ""');
  BadAddr('N7:0.ACC', '".ACC"');
  BadAddr('T4:0.XYZ', '".XYZ"');
  BadAddr('C5:0.TT', '".TT"');
  BadAddr('T4:0/3', 'whole T element');
  BadAddr('T4:0.DN/3', 'after a bit sub-element');
  BadAddr('F8:0/1', 'no addressable bits');
  BadAddr('L9:0/1', 'no addressable bits');
  BadAddr('ST9:0/1', 'no addressable bits');
  BadAddr('N7/20', 'only for B files');
  BadAddr('B3/65536', 'bit number "65536"');
  BadAddr('N7:0x', '"X" after the element');
  BadAddr('N7:0.', '"."');
end;

procedure TTestChnPccc.TestReadRequests;
begin
  { SIZE FILE TYPE ELEMENT SUBELEMENT }
  AssertEquals('N7:0 x10', '14 07 89 00 00', ReadReq('N7:0', 10));
  AssertEquals('F8:2 x2', '08 08 8A 02 00', ReadReq('F8:2', 2));
  AssertEquals('B3:1/4: the word', '02 03 85 01 00', ReadReq('B3:1/4', 1));
  AssertEquals('B3:1/14 x4: two words', '04 03 85 01 00', ReadReq('B3:1/14', 4));
  AssertEquals('T4:0.ACC', '02 04 86 00 02', ReadReq('T4:0.ACC', 1));
  AssertEquals('T4:3.DN: the control word', '02 04 86 03 00', ReadReq('T4:3.DN', 1));
  AssertEquals('T4:0 whole', '06 04 86 00 00', ReadReq('T4:0', 1));
  AssertEquals('C5:1.PRE', '02 05 87 01 01', ReadReq('C5:1.PRE', 1));
  AssertEquals('R6:0.POS', '02 06 88 00 02', ReadReq('R6:0.POS', 1));
  AssertEquals('ST9:1', '54 09 8D 01 00', ReadReq('ST9:1', 1));
  AssertEquals('L10:2 x3', '0C 0A 91 02 00', ReadReq('L10:2', 3));
  AssertEquals('S:0', '02 02 84 00 00', ReadReq('S:0', 1));
  AssertEquals('O0:1', '02 00 8B 01 00', ReadReq('O0:1', 1));
  AssertEquals('I1:0', '02 01 8C 00 00', ReadReq('I1:0', 1));
  AssertEquals('A12:0', '02 0C 8E 00 00', ReadReq('A12:0', 1));
  { T4:0.ACC x3: one request per element }
  AssertEquals('T4:0.ACC #2', '02 04 86 02 02', ReadReq('T4:0.ACC', 3, 2));
end;

procedure TTestChnPccc.TestLargeFieldsEscaped;
begin
  { a field of 255 or more: $FF and the word, low byte first }
  AssertEquals('N255:300', '02 FF FF 00 89 FF 2C 01 00', ReadReq('N255:300', 1));
  AssertEquals('N254:254', '02 FE 89 FE 00', ReadReq('N254:254', 1));
  AssertEquals('N7:255', '02 07 89 FF FF 00 00', ReadReq('N7:255', 1));
end;

procedure TTestChnPccc.TestWriteRequests;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len: Word;
begin
  AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 3, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [1, -2, 32767], 9, Req, Len, Err));
  AssertEquals('CF', $0FAA, Req.CF);
  AssertEquals('06 07 89 00 00 01 00 FE FF FF 7F', Hex(Req, Len));
  AssertEquals(res_Ok, PcccPlan(Addr('F8:1'), 2, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteFloats(P, 0, [1.5, -2.25], 9, Req, Len, Err));
  { 1.5 = $3FC00000, -2.25 = $C0100000 }
  AssertEquals('08 08 8A 01 00 00 00 C0 3F 00 00 10 C0', Hex(Req, Len));
  AssertEquals(res_Ok, PcccPlan(Addr('L10:0'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [-100000], 9, Req, Len, Err));
  { -100000 = $FFFE7960 }
  AssertEquals('04 0A 91 00 00 60 79 FE FF', Hex(Req, Len));
  AssertEquals(res_Ok, PcccPlan(Addr('T4:2.PRE'), 2, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 1, [100, 200], 9, Req, Len, Err));
  AssertEquals('T4:3.PRE', '02 04 86 03 01 C8 00', Hex(Req, Len));
  AssertEquals(res_Ok, PcccPlan(Addr('B3:0'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [$8001], 9, Req, Len, Err));
  AssertEquals('02 03 85 00 00 01 80', Hex(Req, Len));
  { floats to an N address, ints to an F address }
  AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_PcccUsage, PcccBuildPlanWriteFloats(P, 0, [1.0], 9, Req, Len, Err));
  AssertEquals(res_Ok, PcccPlan(Addr('F8:0'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_PcccUsage, PcccBuildPlanWriteInts(P, 0, [1], 9, Req, Len, Err));
end;

procedure TTestChnPccc.TestBitWrites;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len: Word;
begin
  { SIZE FILE TYPE ELEMENT SUBELEMENT MASK VALUE }
  AssertEquals(res_Ok, PcccPlan(Addr('B3:1/4'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [1], 9, Req, Len, Err));
  AssertEquals('CF', $0FAB, Req.CF);
  AssertEquals('02 03 85 01 00 10 00 10 00', Hex(Req, Len));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [0], 9, Req, Len, Err));
  AssertEquals('02 03 85 01 00 10 00 00 00', Hex(Req, Len));
  { three bits from B3:0/14: two masked writes }
  AssertEquals(res_Ok, PcccPlan(Addr('B3:0/14'), 3, True, MaxDataLen, P, Err));
  AssertEquals('requests', 2, PcccPlanRequests(P));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [1, 0, 1], 9, Req, Len, Err));
  AssertEquals('02 03 85 00 00 00 C0 00 40', Hex(Req, Len));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 1, [1, 0, 1], 9, Req, Len, Err));
  AssertEquals('02 03 85 01 00 01 00 01 00', Hex(Req, Len));
  { a timer's done bit: the control word, sub-element 0 }
  AssertEquals(res_Ok, PcccPlan(Addr('T4:1.DN'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccBuildPlanWriteInts(P, 0, [1], 9, Req, Len, Err));
  AssertEquals('02 04 86 01 00 00 20 00 20', Hex(Req, Len));
  AssertEquals(res_PcccValue, PcccBuildPlanWriteInts(P, 0, [2], 9, Req, Len, Err));
  AssertTrue(Err, Pos('value 2', Err) > 0);
end;

procedure TTestChnPccc.TestValueRanges;

  procedure Check(const S: string; V: LongInt; Want: tChResult);
  var
    P: tPcccPlan;
    Err: ShortString;
    Req: tSendRecord;
    Len: Word;
  begin
    AssertEquals(res_Ok, PcccPlan(Addr(S), 1, True, MaxDataLen, P, Err));
    AssertEquals(S + ' = ' + IntToStr(V), Want, PcccBuildPlanWriteInts(P, 0, [V], 1, Req, Len, Err));
    if Want = res_PcccValue then
      AssertTrue('text names the value: ' + Err, Pos(IntToStr(V), Err) > 0);
  end;

begin
  Check('N7:0', 32767, res_Ok);
  Check('N7:0', -32768, res_Ok);
  Check('N7:0', 32768, res_PcccValue);
  Check('N7:0', -32769, res_PcccValue);
  Check('B3:0', 65535, res_Ok);
  Check('B3:0', -1, res_PcccValue);
  Check('B3:0', 65536, res_PcccValue);
  Check('T4:0.PRE', 40000, res_PcccValue);
  Check('L9:0', High(LongInt), res_Ok);
  Check('B3:0/1', 2, res_PcccValue);
  Check('B3:0/1', -1, res_PcccValue);
end;

procedure TTestChnPccc.TestPlanSplitsLongReads;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len, Expect: Word;
begin
  { 200 integers: 122 + 78 }
  AssertEquals(res_Ok, PcccPlan(Addr('N7:10'), 200, False, MaxDataLen, P, Err));
  AssertEquals('requests', 2, PcccPlanRequests(P));
  AssertEquals(res_Ok, PcccBuildPlanRead(P, 0, 1, Req, Len, Expect));
  AssertEquals('F4 07 89 0A 00', Hex(Req, Len));
  AssertEquals(244, Expect);
  AssertEquals(res_Ok, PcccBuildPlanRead(P, 1, 2, Req, Len, Expect));
  AssertEquals('9C 07 89 84 00', Hex(Req, Len));      { 78 words from N7:132 }
  AssertEquals(156, Expect);
  AssertEquals('past the end', res_PcccCount, PcccBuildPlanRead(P, 2, 3, Req, Len, Expect));
  { at most 80 bytes a request: 20 floats each }
  AssertEquals(res_Ok, PcccPlan(Addr('F8:0'), 50, False, 80, P, Err));
  AssertEquals('requests', 3, PcccPlanRequests(P));
  AssertEquals(res_Ok, PcccBuildPlanRead(P, 2, 1, Req, Len, Expect));
  AssertEquals('28 08 8A 28 00', Hex(Req, Len));
  { strings: two of 84 bytes a request }
  AssertEquals(res_Ok, PcccPlan(Addr('ST9:0'), 3, False, MaxDataLen, P, Err));
  AssertEquals('requests', 2, PcccPlanRequests(P));
  { a write leaves room for the address fields: 117 words }
  AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 200, True, MaxDataLen, P, Err));
  AssertEquals('write requests', 2, PcccPlanRequests(P));
  AssertEquals(117, P.PerReq);
end;

procedure TTestChnPccc.TestCountThatDoesNotFit;
var
  P: tPcccPlan;
  Err: ShortString;
begin
  AssertEquals('0', res_PcccCount, PcccPlan(Addr('N7:0'), 0, False, MaxDataLen, P, Err));
  AssertTrue(Err, Pos('count 0', Err) > 0);
  AssertEquals('-1', res_PcccCount, PcccPlan(Addr('N7:0'), -1, False, MaxDataLen, P, Err));
  AssertEquals('too many', res_PcccCount, PcccPlan(Addr('N7:0'), PcccMaxItems + 1, False, MaxDataLen, P, Err));
  AssertEquals('past 65535', res_PcccCount, PcccPlan(Addr('N7:65535'), 2, False, MaxDataLen, P, Err));
  AssertTrue(Err, Pos('65535', Err) > 0);
  AssertEquals('N7:65535 x1', res_Ok, PcccPlan(Addr('N7:65535'), 1, False, MaxDataLen, P, Err));
  AssertEquals('ST in 80 bytes', res_PcccCount, PcccPlan(Addr('ST9:0'), 1, False, 80, P, Err));
  AssertEquals('MaxBytes 245', res_PcccCount, PcccPlan(Addr('N7:0'), 1, False, 245, P, Err));
end;

procedure TTestChnPccc.TestDecodeInts;
var
  P: tPcccPlan;
  Err: ShortString;
  V: array[0..8] of LongInt;
  Short: array[0..1] of LongInt;
begin
  AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 3, False, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 0, [1, 0, $FF, $FF, $00, $80], 6, V));
  AssertEquals(1, V[0]); AssertEquals(-1, V[1]); AssertEquals(-32768, V[2]);
  AssertEquals('array too short', res_PcccCount, PcccDecodePlanInts(P, 0, [1, 0, $FF, $FF, $00, $80], 6, Short));
  AssertEquals(res_Ok, PcccPlan(Addr('B3:0'), 1, False, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 0, [$FF, $FF], 2, V));
  AssertEquals('B unsigned', 65535, V[0]);
  { a whole timer: control word, PRE, ACC }
  AssertEquals(res_Ok, PcccPlan(Addr('T4:0'), 2, False, MaxDataLen, P, Err));
  AssertEquals('values', 6, PcccPlanValues(P));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 0, [0, $A0, 100, 0, 42, 0, 0, 0, 5, 0, 6, 0], 12, V));
  AssertEquals(SmallInt($A000), V[0]); AssertEquals(100, V[1]); AssertEquals(42, V[2]);
  AssertEquals(5, V[4]); AssertEquals(6, V[5]);
  { the done bit of T4:0.. T4:2, one request each }
  AssertEquals(res_Ok, PcccPlan(Addr('T4:0.DN'), 3, False, MaxDataLen, P, Err));
  AssertEquals(3, PcccPlanRequests(P));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 1, [0, $20], 2, V));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 2, [$FF, $DF], 2, V));
  AssertEquals(1, V[1]); AssertEquals(0, V[2]);
end;

procedure TTestChnPccc.TestDecodeFloatsAndLongs;
var
  P: tPcccPlan;
  Err: ShortString;
  F: array[0..1] of Single;
  V: array[0..1] of LongInt;
begin
  AssertEquals(res_Ok, PcccPlan(Addr('F8:0'), 2, False, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccDecodePlanFloats(P, 0, [0, 0, $C0, $3F, 0, 0, $10, $C0], 8, F));
  AssertEquals(1.5, F[0], 0); AssertEquals(-2.25, F[1], 0);
  AssertEquals('ints of a float', res_PcccUsage, PcccDecodePlanInts(P, 0, [0, 0, $C0, $3F, 0, 0, $10, $C0], 8, V));
  AssertEquals(res_Ok, PcccPlan(Addr('L9:0'), 2, False, MaxDataLen, P, Err));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 0, [$60, $79, $FE, $FF, $FF, $FF, $FF, $7F], 8, V));
  AssertEquals(-100000, V[0]); AssertEquals(High(LongInt), V[1]);
end;

procedure TTestChnPccc.TestDecodeBitsAcrossWords;
var
  P: tPcccPlan;
  Err: ShortString;
  V: array[0..3] of LongInt;
begin
  { B3:0/14 .. B3:1/1 }
  AssertEquals(res_Ok, PcccPlan(Addr('B3:0/14'), 4, False, MaxDataLen, P, Err));
  AssertEquals(1, PcccPlanRequests(P));
  AssertEquals(res_Ok, PcccDecodePlanInts(P, 0, [$00, $80, $02, $00], 4, V));
  AssertEquals(0, V[0]); AssertEquals(1, V[1]); AssertEquals(0, V[2]); AssertEquals(1, V[3]);
end;

procedure TTestChnPccc.TestDecodeRefusesWrongLength;
var
  P: tPcccPlan;
  Err: ShortString;
  V: array[0..9] of LongInt;
  Data: array[0..3] of Byte;
begin
  FillChar(Data, SizeOf(Data), 0);
  AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 2, False, MaxDataLen, P, Err));
  AssertEquals('short', res_PcccReply, PcccDecodePlanInts(P, 0, Data, 2, V));
  AssertEquals('long', res_PcccReply, PcccDecodePlanInts(P, 0, Data, 6, V));
  AssertEquals('more than the data holds', res_PcccReply, PcccDecodePlanInts(P, 0, [1, 2, 3], 4, V));
  AssertEquals('right', res_Ok, PcccDecodePlanInts(P, 0, Data, 4, V));
  AssertEquals('index past the plan', res_PcccUsage, PcccDecodePlanInts(P, 1, Data, 4, V));
end;

procedure TTestChnPccc.TestStrings;
var
  B: array[0..83] of Byte;
  Small: array[0..10] of Byte;
  S: ShortString;
  Err: ShortString;
begin
  AssertEquals(res_Ok, PcccEncodeString('Hello', B, Err));
  { LEN 5, then 'eH' 'll' #0'o' ... }
  AssertEquals('05 00 65 48 6C 6C 00 6F 00 00', BytesToHex(B, 10));
  AssertEquals(res_Ok, PcccDecodeString(B, 0, S));
  AssertEquals('Hello', S);
  AssertEquals(res_PcccValue, PcccEncodeString(StringOfChar('x', 83), B, Err));
  AssertTrue(Err, Pos('83', Err) > 0);
  AssertEquals(res_Ok, PcccEncodeString(StringOfChar('x', 82), B, Err));
  AssertEquals(res_Ok, PcccDecodeString(B, 0, S));
  AssertEquals(82, Length(S));
  AssertEquals('small buffer', res_PcccCount, PcccEncodeString('a', Small, Err));
  AssertEquals('short data', res_PcccReply, PcccDecodeString(Small, 0, S));
  AssertEquals('offset past', res_PcccReply, PcccDecodeString(B, 1, S));
  B[0] := 83;
  AssertEquals('LEN 83', res_PcccReply, PcccDecodeString(B, 0, S));
end;

procedure TTestChnPccc.TestCheckReply;
var
  Rep: tRecRecord;
  Err: ShortString;
begin
  FillChar(Rep, SizeOf(Rep), 0);
  Rep.MessType := tpDataMess;
  Rep.CF := $4F00;
  AssertEquals(res_Ok, PcccCheckReply(Rep, 8 + 4, 4, Err));
  AssertEquals(res_PcccReply, PcccCheckReply(Rep, 8 + 3, 4, Err));
  AssertEquals('reply has 3 data bytes, 4 expected', Err);
  Rep.Sts := $F0;
  Rep.Data[0] := $06;
  AssertEquals(res_PcccStatus, PcccCheckReply(Rep, 9, 4, Err));
  AssertEquals('STS $F0, EXT STS $06: address doesn''t point to something usable', Err);
  Rep.Sts := $10;
  AssertEquals(res_PcccStatus, PcccCheckReply(Rep, 8, 4, Err));
  AssertEquals('STS $10: illegal command or format', Err);
  AssertEquals('texts', 'PCCC: bad PLC address', ChResultText(res_PcccAddress, PcccLayer));
  AssertEquals('texts', 'PCCC: command refused (NAK) on every try', ChResultText(res_PcccNak, PcccLayer));
end;

{ 1770-6.5.16 chapter 8: the low nibble of STS holds the local node's
  errors (01..08; 09..0F not used); they were named "success". }
procedure TTestChnPccc.TestLocalStsTexts;
var
  Rep: tRecRecord;
  Err: ShortString;
  C: Integer;
begin
  AssertEquals('success', PcccStsText($00));
  AssertEquals('DST node is out of buffer space', PcccStsText($01));
  AssertEquals('cannot guarantee delivery: the remote node does not ACK the command', PcccStsText($02));
  AssertEquals('duplicate token holder detected', PcccStsText($03));
  AssertEquals('local port is disconnected', PcccStsText($04));
  AssertEquals('application layer timed out waiting for a response', PcccStsText($05));
  AssertEquals('duplicate node detected', PcccStsText($06));
  AssertEquals('station is offline', PcccStsText($07));
  AssertEquals('hardware fault', PcccStsText($08));
  for C := $09 to $0F do
    AssertEquals('unused local STS code', PcccStsText(C));
  for C := $01 to $0F do
    AssertTrue(IntToHex(C, 2) + ' is not success', Pos('success', PcccStsText(C)) = 0);
  AssertEquals('remote codes unchanged', 'processor is in Program mode', PcccStsText($70));
  AssertEquals('both nibbles', 'local: station is offline; remote: illegal command or format',
    PcccStsText($17));
  { and in the text of a refused reply }
  FillChar(Rep, SizeOf(Rep), 0);
  Rep.MessType := tpDataMess;
  Rep.CF := $4F00;
  Rep.Sts := $02;
  AssertEquals(res_PcccStatus, PcccCheckReply(Rep, 8, 4, Err));
  AssertEquals('STS $02: cannot guarantee delivery: the remote node does not ACK the command', Err);
end;

procedure TTestChnPccc.TestSameRequestsAsPythonClient;
const
  DataFile = 'tests/data/df1py3-requests.txt';
var
  Lines: TStringList;
  I, Bar, Done: Integer;
  Call, Wire, Ours, S: string;
  Cfg: tDF1Config;
  D: tDF1Decoder;
  B: TBytes;
  K: Integer;
  Tns: Word;
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len, Expect, OutLen: Word;
  Out_: array[0..600] of Byte;
  R: tChResult;
  Ev: tDF1Event;
begin
  AssertTrue(DataFile + ' missing', FileExists(DataFile));
  Lines := TStringList.Create;
  try
    Lines.LoadFromFile(DataFile);
    Done := 0;
    FillChar(Cfg, SizeOf(Cfg), 0);
    Cfg.FullDup := True;
    Cfg.Crc := True;
    Cfg.NakByte := $15;
    for I := 0 to Lines.Count - 1 do
    begin
      S := Lines[I];
      if (S = '') or (S[1] = '#') then
        Continue;
      Bar := Pos(' | ', S);
      Call := Copy(S, 1, Bar - 1);
      Wire := Copy(S, Bar + 3, MaxInt);
      { the captured TNS: decode the frame as the PLC (node 1) would }
      Cfg.Node := 1;
      Cfg.DNode := 0;
      DF1DecoderInit(D, Cfg);
      B := HexToBytes(Wire);
      Ev := dfNone;
      for K := 0 to High(B) do
        Ev := DF1Feed(D, B[K]);
      AssertTrue(Call + ': the capture is one good frame', Ev = dfMessage);
      Tns := D.Msg.Tns;
      { our request for the same operation }
      if Pos('read_integer(file_table=7, start=0, total_int=10)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 10, False, MaxDataLen, P, Err));
        R := PcccBuildPlanRead(P, 0, Tns, Req, Len, Expect);
      end
      else if Pos('send_command(Command0FAA, table=7, file_type=INTEGER, start=0, data_to_write=[1, 2, 3])', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('N7:0'), 3, True, MaxDataLen, P, Err));
        R := PcccBuildPlanWriteInts(P, 0, [1, 2, 3], Tns, Req, Len, Err);
      end
      else if Pos('read_float(file_table=8, start=0, total_float=2)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('F8:0'), 2, False, MaxDataLen, P, Err));
        R := PcccBuildPlanRead(P, 0, Tns, Req, Len, Expect);
      end
      else if Pos('write_float(file_table=8, start=0, data=[1.5, -2.25])', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('F8:0'), 2, True, MaxDataLen, P, Err));
        R := PcccBuildPlanWriteFloats(P, 0, [1.5, -2.25], Tns, Req, Len, Err);
      end
      else if Pos('read_binary(file_table=3, start=0, total_int=2)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('B3:0'), 2, False, MaxDataLen, P, Err));
        R := PcccBuildPlanRead(P, 0, Tns, Req, Len, Expect);
      end
      else if Pos('write_binary(file_table=3, start=0, data=[0x1234])', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('B3:0'), 1, True, MaxDataLen, P, Err));
        R := PcccBuildPlanWriteInts(P, 0, [$1234], Tns, Req, Len, Err);
      end
      else if Pos('send_command(Command0FABSingleBit, table=3, file_type=BIT, start=1, bit_position=4, bit_value=1)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('B3:1/4'), 1, True, MaxDataLen, P, Err));
        R := PcccBuildPlanWriteInts(P, 0, [1], Tns, Req, Len, Err);
      end
      else if Pos('read_timer(file_table=4, start=0, category=TIMER.ACC, total_int=1)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('T4:0.ACC'), 1, False, MaxDataLen, P, Err));
        R := PcccBuildPlanRead(P, 0, Tns, Req, Len, Expect);
      end
      else if Pos('read_counter(file_table=5, start=0, category=COUNTER.PRE, total_int=1)', Call) = 1 then
      begin
        AssertEquals(res_Ok, PcccPlan(Addr('C5:0.PRE'), 1, False, MaxDataLen, P, Err));
        R := PcccBuildPlanRead(P, 0, Tns, Req, Len, Expect);
      end
      else
      begin
        Fail('no counterpart for the captured call ' + Call);
        R := res_BadParam;
      end;
      AssertEquals(Call + ': built', res_Ok, R);
      { encoded as a full-duplex CRC master, node 0 to node 1 }
      Cfg.Node := 0;
      Cfg.DNode := 1;
      AssertEquals(Call + ': encoded', res_Ok, DF1Encode(Cfg, Req, Len, Out_, SizeOf(Out_), OutLen));
      Ours := BytesToHex(Out_, OutLen);
      AssertEquals(Call, Wire, Ours);
      Inc(Done);
    end;
    AssertEquals('captured calls compared', 9, Done);
  finally
    Lines.Free;
  end;
end;

initialization
  RegisterTest(TTestChnPccc);
end.
