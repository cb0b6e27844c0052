{ Tests of unit ChnPlc5: PLC-5 addresses (octal I/O, direct bits, D
  files) and the request bytes of typed read/write (0F 68/67), word range
  read/write (0F 01/00) and read-modify-write (0F 26), worked out by hand
  from Rockwell 1770-6.5.16: the logical binary address of chapter 13 (its
  own examples N7:30 = 07 00 07 1E and T4:2.ACC = 0F 00 04 02 02), the
  PACKET OFFSET / TOTAL TRANS / SIZE fields of chapter 7 and the
  type/data parameter (flag byte: type nibble, size nibble; a nibble with
  bit 3 set counts the bytes that follow; 4 integer, 5 timer, 8 float, 9
  array, 16 BCD). Replies decoded from hand-made bytes, among them the
  escaped size a ControlLogix sends (99 09 03 42 ...). }
unit TestChnPlc5;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnDF1Codec, ChnPccc, ChnPlc5, TestSupport;

type
  TLongIntArray = array of LongInt;

  TTestChnPlc5 = class(TTestCase)
  private
    function Addr(const S: string): tPcccAddr;
    procedure BadAddr(const S, Part: string);
    function ReadReq(const S: string; Count: LongInt; Cmd: tPlc5Command; Index: LongInt = 0): string;
    function WriteInts(const S: string; const V: array of LongInt; Cmd: tPlc5Command;
      Index: LongInt = 0): string;
    function Reply(const S: string; Count: LongInt; const Hex: string; out Values: TLongIntArray): tChResult;
  published
    procedure TestAddresses;
    procedure TestBadAddresses;
    procedure TestManualAddressExamples;
    procedure TestTypedReadRequests;
    procedure TestWordRangeReadRequests;
    procedure TestTypedWriteRequests;
    procedure TestWordRangeWriteRequests;
    procedure TestBitsByReadModifyWrite;
    procedure TestTypeParameter;
    procedure TestPlanSplits;
    procedure TestDecodeReplies;
    procedure TestBcd;
  end;

implementation

function TTestChnPlc5.Addr(const S: string): tPcccAddr;
var
  Err: ShortString;
begin
  Err := '';
  AssertEquals('parse ' + S + ': ' + Err, res_Ok, Plc5ParseAddress(S, Result, Err));
end;

procedure TTestChnPlc5.BadAddr(const S, Part: string);
var
  A: tPcccAddr;
  Err: ShortString;
begin
  AssertEquals('"' + S + '" refused', res_PcccAddress, Plc5ParseAddress(S, A, Err));
  AssertTrue('"' + S + '": the text names ' + Part + ': ' + Err, Pos(Part, Err) > 0);
end;

function TTestChnPlc5.ReadReq(const S: string; Count: LongInt; Cmd: tPlc5Command;
  Index: LongInt): string;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len, Expect: Word;
begin
  AssertEquals('plan ' + S + ' ' + Err, res_Ok, Plc5Plan(Addr(S), Count, False, MaxDataLen, P, Err));
  AssertEquals('build', res_Ok, Plc5BuildPlanRead(P, Index, Cmd, 7, Req, Len, Expect));
  AssertEquals('TNS', 7, Req.Tns);
  Result := Format('%.4x: ', [Req.CF]) + BytesToHex(Req.Data, Len - cSizeHead);
end;

function TTestChnPlc5.WriteInts(const S: string; const V: array of LongInt; Cmd: tPlc5Command;
  Index: LongInt): string;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len: Word;
  A: tPcccAddr;
  Items: LongInt;
begin
  A := Addr(S);
  Items := Length(V);
  if (A.FileType in [pft_Timer, pft_Counter, pft_Control]) and not A.HasSub then
    Items := Items div 3;
  AssertEquals('plan ' + S + ' ' + Err, res_Ok, Plc5Plan(A, Items, True, MaxDataLen, P, Err));
  AssertEquals('build ' + S + ' ' + Err, res_Ok, Plc5BuildPlanWriteInts(P, Index, V, Cmd, 7, Req, Len, Err));
  Result := Format('%.4x: ', [Req.CF]) + BytesToHex(Req.Data, Len - cSizeHead);
end;

function TTestChnPlc5.Reply(const S: string; Count: LongInt; const Hex: string;
  out Values: TLongIntArray): tChResult;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Rep: tRecRecord;
  D: TBytes;
  Len, Expect, First: Word;
begin
  AssertEquals(res_Ok, Plc5Plan(Addr(S), Count, False, MaxDataLen, P, Err));
  AssertEquals(res_Ok, Plc5BuildPlanRead(P, 0, p5Typed, 7, Req, Len, Expect));
  FillChar(Rep, SizeOf(Rep), 0);
  Rep.MessType := tpDataMess;
  Rep.CF := $4F00;
  D := HexToBytes(Hex);
  if Length(D) > 0 then
    Move(D[0], Rep.Data[0], Length(D));
  SetLength(Values, PcccPlanValues(P));
  Result := Plc5CheckReadReply(P, p5Typed, Rep, cSizeHead + Length(D), Expect, First, Err);
  if Result = res_Ok then
  begin
    D := Copy(D, First, Expect);
    Result := Plc5DecodePlanInts(P, 0, D, Expect, Values);
  end;
end;

procedure TTestChnPlc5.TestAddresses;
var
  A: tPcccAddr;
begin
  A := Addr('I:012/05');
  AssertEquals('I file', pft_Input, A.FileType);
  AssertEquals('I is file 1', 1, A.FileNo);
  AssertEquals('octal 012 = 10', 10, A.Elem);
  AssertEquals('octal bit 05', 5, A.Bit);
  AssertEquals('I:012/05', Plc5AddressText(A));
  A := Addr('i1:17/17');
  AssertEquals('octal 17 = 15', 15, A.Elem);
  AssertEquals('octal bit 17 = 15', 15, A.Bit);
  AssertEquals('I:017/17', Plc5AddressText(A));
  A := Addr('O:001');
  AssertEquals(pft_Output, A.FileType);
  AssertEquals(0, A.FileNo);
  AssertEquals(1, A.Elem);
  AssertEquals('O:001', Plc5AddressText(A));
  A := Addr('B3/17');
  AssertEquals('B3/17 is B3:1/1: element', 1, A.Elem);
  AssertEquals('B3/17 is B3:1/1: bit', 1, A.Bit);
  A := Addr('T4:1.ACC');
  AssertTrue(A.HasSub);
  AssertEquals('ACC is word 2', 2, A.Sub);
  AssertEquals('T4:1.ACC', Plc5AddressText(A));
  A := Addr('C5:0.PRE');
  AssertEquals('PRE is word 1', 1, A.Sub);
  A := Addr('T4:0.DN');
  AssertEquals('DN: control word', 0, A.Sub);
  AssertEquals('DN: bit 13', 13, A.Bit);
  A := Addr('D10:0');
  AssertEquals('D: BCD', pft_Bcd, A.FileType);
  AssertEquals(10, A.FileNo);
  AssertEquals('D10:0', Plc5AddressText(A));
  A := Addr('ST9:0');
  AssertEquals(pft_String, A.FileType);
  A := Addr('F8:3');
  AssertEquals(pft_Float, A.FileType);
  AssertEquals(3, A.Elem);
  A := Addr('N999:999');
  AssertEquals(999, A.FileNo);
  AssertEquals(999, A.Elem);
  A := Addr('S:1');
  AssertEquals(2, A.FileNo);
end;

procedure TTestChnPlc5.TestBadAddresses;
var
  A: tPcccAddr;
  Err: ShortString;
begin
  BadAddr('L10:0', 'none of O I S B T C R N F ST A D');
  BadAddr('X7:0', 'none of');
  BadAddr('I:018', 'octal');
  BadAddr('I:300', 'octal 0..277');
  BadAddr('I:012/18', 'octal 00..17');
  BadAddr('N7:0/16', 'not 0..15');
  BadAddr('N1000:0', 'not 0..999');
  BadAddr('N2:0', '3..999');
  BadAddr('N7:1000', '0..999');
  BadAddr('I2:0', 'I is file 1');
  BadAddr('N7/3', 'only for B files');
  BadAddr('N7:0.ACC', 'no sub-elements');
  BadAddr('T4:0/3', 'name a word');
  BadAddr('F8:0/1', 'no addressable bits');
  BadAddr('N7', '":element" missing');
  BadAddr('N7:1x', '"X" after the element');
  { the SLC parser does not take D files }
  AssertEquals(res_PcccAddress, PcccParseAddress('D10:0', A, Err));
end;

procedure TTestChnPlc5.TestManualAddressExamples;

  function Enc(const S: string): string;
  var
    B: array[0..15] of Byte;
    N: Integer;
  begin
    N := 0;
    Plc5PutAddress(Addr(S), B, N);
    Result := BytesToHex(B, N);
  end;

begin
  { 1770-6.5.16 chapter 13: mask (levels 1..3, or 1..4), then data table 0,
    file, element, sub-element; 255 and above as FF and the word }
  AssertEquals('N7:30', '07 00 07 1E', Enc('N7:30'));
  AssertEquals('T4:2.ACC', '0F 00 04 02 02', Enc('T4:2.ACC'));
  AssertEquals('B3:300', '07 00 03 FF 2C 01', Enc('B3:300'));
  AssertEquals('N300:256', '07 00 FF 2C 01 FF 00 01', Enc('N300:256'));
end;

procedure TTestChnPlc5.TestTypedReadRequests;
begin
  { PACKET OFFSET(2) TOTAL TRANS(2) address SIZE(2, elements) }
  AssertEquals('N7:0 x3', '0F68: 00 00 03 00 07 00 07 00 03 00', ReadReq('N7:0', 3, p5Typed));
  AssertEquals('F8:3', '0F68: 00 00 01 00 07 00 08 03 01 00', ReadReq('F8:3', 1, p5Typed));
  AssertEquals('B3/17: the word B3:1', '0F68: 00 00 01 00 07 00 03 01 01 00', ReadReq('B3/17', 1, p5Typed));
  AssertEquals('I:012/05: the word I:012', '0F68: 00 00 01 00 07 00 01 0A 01 00', ReadReq('I:012/05', 1, p5Typed));
  AssertEquals('O:001', '0F68: 00 00 01 00 07 00 00 01 01 00', ReadReq('O:001', 1, p5Typed));
  AssertEquals('T4:1.ACC', '0F68: 00 00 01 00 0F 00 04 01 02 01 00', ReadReq('T4:1.ACC', 1, p5Typed));
  AssertEquals('C5:0.PRE', '0F68: 00 00 01 00 0F 00 05 00 01 01 00', ReadReq('C5:0.PRE', 1, p5Typed));
  AssertEquals('D10:0 x2', '0F68: 00 00 02 00 07 00 0A 00 02 00', ReadReq('D10:0', 2, p5Typed));
  AssertEquals('T4:0 x2 whole', '0F68: 00 00 02 00 07 00 04 00 02 00', ReadReq('T4:0', 2, p5Typed));
  { ST: no type code of its own, always by word range: 42 words, 84 bytes }
  AssertEquals('ST9:0', '0F01: 00 00 2A 00 07 00 09 00 54', ReadReq('ST9:0', 1, p5Typed));
end;

procedure TTestChnPlc5.TestWordRangeReadRequests;
begin
  { PACKET OFFSET(2) TOTAL TRANS(2, words) address SIZE(1, bytes) }
  AssertEquals('N7:0 x3', '0F01: 00 00 03 00 07 00 07 00 06', ReadReq('N7:0', 3, p5WordRange));
  AssertEquals('F8:3 x2: 4 words', '0F01: 00 00 04 00 07 00 08 03 08', ReadReq('F8:3', 2, p5WordRange));
  AssertEquals('T4:1 whole: 3 words', '0F01: 00 00 03 00 07 00 04 01 06', ReadReq('T4:1', 1, p5WordRange));
  AssertEquals('T4:1.ACC', '0F01: 00 00 01 00 0F 00 04 01 02 02', ReadReq('T4:1.ACC', 1, p5WordRange));
end;

procedure TTestChnPlc5.TestTypedWriteRequests;
var
  P: tPcccPlan;
  Err: ShortString;
  Req: tSendRecord;
  Len: Word;
begin
  { offset, total, address, then an array: 9x 09 with the size of the
    element parameter and the data (7 fits the nibble: 97), 42 = integer
    of 2 bytes }
  AssertEquals('N7:0 <- 1 -2 32767', '0F67: 00 00 03 00 07 00 07 00 97 09 42 01 00 FE FF FF 7F',
    WriteInts('N7:0', [1, -2, 32767], p5Typed));
  { ten integers: 21 bytes, the size in a byte of its own: 99 09 15 }
  AssertEquals('N7:0 <- 0..9', '0F67: 00 00 0A 00 07 00 07 00 99 09 15 42 ' +
    '00 00 01 00 02 00 03 00 04 00 05 00 06 00 07 00 08 00 09 00',
    WriteInts('N7:0', [0, 1, 2, 3, 4, 5, 6, 7, 8, 9], p5Typed));
  { a whole timer: type 5, 6 bytes: 56 }
  AssertEquals('T4:1 <- 0 50 7', '0F67: 00 00 01 00 07 00 04 01 97 09 56 00 00 32 00 07 00',
    WriteInts('T4:1', [0, 50, 7], p5Typed));
  { one word of a timer: level 4, an integer }
  AssertEquals('T4:1.ACC <- 99', '0F67: 00 00 01 00 0F 00 04 01 02 93 09 42 63 00',
    WriteInts('T4:1.ACC', [99], p5Typed));
  { BCD: type 16 does not fit the nibble: 92 10; array of 4 bytes: 94 09 }
  AssertEquals('D10:0 <- 1234', '0F67: 00 00 01 00 07 00 0A 00 94 09 92 10 34 12',
    WriteInts('D10:0', [1234], p5Typed));
  AssertEquals(res_Ok, Plc5Plan(Addr('D10:0'), 1, True, MaxDataLen, P, Err));
  AssertEquals('D10:0 <- 10000 refused', res_PcccValue,
    Plc5BuildPlanWriteInts(P, 0, [10000], p5Typed, 7, Req, Len, Err));
  AssertTrue(Err, Pos('value 10000 for D10:0 is not 0..9999', Err) > 0);
  { float: type 8 escaped (94 08), array of 6 bytes (96 09); 1.5 = 3FC00000 }
  AssertEquals(res_Ok, Plc5Plan(Addr('F8:3'), 1, True, MaxDataLen, P, Err));
  AssertEquals(res_Ok, Plc5BuildPlanWriteFloats(P, 0, [1.5], p5Typed, 7, Req, Len, Err));
  AssertEquals('F8:3 <- 1.5', '0F67: 00 00 01 00 07 00 08 03 96 09 94 08 00 00 C0 3F',
    Format('%.4x: ', [Req.CF]) + BytesToHex(Req.Data, Len - cSizeHead));
end;

procedure TTestChnPlc5.TestWordRangeWriteRequests;
var
  Req: tSendRecord;
  Len: Word;
  Err: ShortString;
  Want: string;
  I: Integer;
begin
  AssertEquals('N7:0 <- 5 6', '0F00: 00 00 02 00 07 00 07 00 05 00 06 00',
    WriteInts('N7:0', [5, 6], p5WordRange));
  AssertEquals('D10:1 <- 4321, BCD', '0F00: 00 00 01 00 07 00 0A 01 21 43',
    WriteInts('D10:1', [4321], p5WordRange));
  { a string: LEN word, characters swapped in each word, 42 words in all }
  AssertEquals(res_Ok, Plc5BuildWriteString(Addr('ST9:1'), 'abc', 7, Req, Len, Err));
  AssertEquals('CF', $0F00, Req.CF);
  Want := '00 00 2A 00 07 00 09 01 03 00 62 61 00 63';
  for I := 1 to 78 do
    Want := Want + ' 00';
  AssertEquals('ST9:1 <- "abc"', Want, BytesToHex(Req.Data, Len - cSizeHead));
end;

procedure TTestChnPlc5.TestBitsByReadModifyWrite;
begin
  { address AND(2) OR(2): AND clears the bit written, OR sets it to 1 }
  AssertEquals('B3/17 <- 1', '0F26: 07 00 03 01 FD FF 02 00', WriteInts('B3/17', [1], p5Typed));
  AssertEquals('I:012/05 <- 0', '0F26: 07 00 01 0A DF FF 00 00', WriteInts('I:012/05', [0], p5Typed));
  AssertEquals('T4:1.DN <- 1: the control word', '0F26: 0F 00 04 01 00 FF DF 00 20',
    WriteInts('T4:1.DN', [1], p5Typed));
  { word range changes nothing for bits }
  AssertEquals('B3:0/15 <- 1', '0F26: 07 00 03 00 FF 7F 00 80', WriteInts('B3:0/15', [1], p5WordRange));
end;

procedure TTestChnPlc5.TestTypeParameter;

  function Put(T, S: Word): string;
  var
    B: array[0..7] of Byte;
    N: Integer;
  begin
    N := 0;
    Plc5PutTypeParam(T, S, B, N);
    Result := BytesToHex(B, N);
  end;

  function Take(const Hex: string; out T, S: Word): Integer;
  var
    D: TBytes;
    N: Integer;
  begin
    D := HexToBytes(Hex);
    N := 0;
    if Plc5TakeTypeParam(D, Length(D), N, T, S) then
      Result := N
    else
      Result := -1;
  end;

var
  T, S: Word;
begin
  AssertEquals('integer, 2', '42', Put(4, 2));
  AssertEquals('float, 4', '94 08', Put(8, 4));
  AssertEquals('BCD, 2', '92 10', Put(16, 2));
  AssertEquals('array, 21', '99 09 15', Put(9, 21));
  AssertEquals('array, 300', '9A 09 2C 01', Put(9, 300));
  AssertEquals('99 09 03: 3 bytes', 3, Take('99 09 03', T, S));
  AssertEquals('type', 9, T);
  AssertEquals('size', 3, S);
  AssertEquals('9A 09 2C 01', 4, Take('9A 09 2C 01', T, S));
  AssertEquals(300, S);
  AssertEquals('cut short', -1, Take('99 09', T, S));
  AssertEquals('three size bytes refused', -1, Take('9B 09 01 02 03', T, S));
end;

procedure TTestChnPlc5.TestPlanSplits;
var
  P: tPcccPlan;
  Err: ShortString;
  L: tPcccAddr;
begin
  { 238 data bytes per typed read reply: 119 integers, then 81 from N7:119 }
  AssertEquals(res_Ok, Plc5Plan(Addr('N7:0'), 200, False, MaxDataLen, P, Err));
  AssertEquals('requests', 2, PcccPlanRequests(P));
  AssertEquals('#1', '0F68: 00 00 51 00 07 00 07 77 51 00', ReadReq('N7:0', 200, p5Typed, 1));
  { 221 per write: 110 integers }
  AssertEquals(res_Ok, Plc5Plan(Addr('N7:0'), 200, True, MaxDataLen, P, Err));
  AssertEquals('write requests', 2, PcccPlanRequests(P));
  AssertEquals('per request', 110, P.PerReq);
  FillChar(L, SizeOf(L), 0);
  L.FileType := pft_Long;
  L.FileNo := 10;
  L.Bit := -1;
  AssertEquals('no L files', res_PcccAddress, Plc5Plan(L, 1, False, MaxDataLen, P, Err));
  AssertTrue(Err, Pos('no L files', Err) > 0);
end;

procedure TTestChnPlc5.TestDecodeReplies;
var
  V: TLongIntArray;
begin
  AssertEquals('compact', res_Ok, Reply('N7:0', 3, '97 09 42 00 00 0A 00 14 00', V));
  AssertEquals(10, V[1]);
  AssertEquals(20, V[2]);
  { the size escaped though it fits (as a ControlLogix answers) }
  AssertEquals('escaped size', res_Ok, Reply('N7:0', 1, '99 09 03 42 FF FF', V));
  AssertEquals('signed', -1, V[0]);
  { one element without an array }
  AssertEquals('single', res_Ok, Reply('N7:0', 1, '42 05 00', V));
  AssertEquals(5, V[0]);
  AssertEquals('bit of I:012', res_Ok, Reply('I:012/05', 1, '93 09 42 20 00', V));
  AssertEquals(1, V[0]);
  AssertEquals('timer', res_Ok, Reply('T4:0', 1, '97 09 56 00 20 64 00 2A 00', V));
  AssertEquals($2000, V[0]);
  AssertEquals(100, V[1]);
  AssertEquals(42, V[2]);
  AssertEquals('BCD', res_Ok, Reply('D10:0', 2, '96 09 92 10 34 12 99 99', V));
  AssertEquals(1234, V[0]);
  AssertEquals(9999, V[1]);
  AssertEquals('not BCD', res_PcccReply, Reply('D10:0', 1, '94 09 92 10 AB 12', V));
  AssertEquals('one byte short', res_PcccReply, Reply('N7:0', 2, '95 09 42 01 00 02', V));
  AssertEquals('array size wrong', res_PcccReply, Reply('N7:0', 1, '94 09 42 01 00', V));
  AssertEquals('a float for N', res_PcccReply, Reply('N7:0', 2, '96 09 94 08 00 00 C0 3F', V));
  AssertEquals('elements of 4 bytes', res_PcccReply, Reply('N7:0', 2, '95 09 44 01 00 02 00', V));
  AssertEquals('cut short', res_PcccReply, Reply('N7:0', 1, '99', V));
end;

procedure TTestChnPlc5.TestBcd;
var
  W: Word;
  V: LongInt;
begin
  AssertTrue(Plc5ToBcd(1234, W));
  AssertEquals($1234, W);
  AssertTrue(Plc5ToBcd(9999, W));
  AssertEquals($9999, W);
  AssertFalse(Plc5ToBcd(10000, W));
  AssertFalse(Plc5ToBcd(-1, W));
  AssertTrue(Plc5FromBcd($0042, V));
  AssertEquals(42, V);
  AssertFalse(Plc5FromBcd($00A0, V));
end;

initialization
  RegisterTest(TTestChnPlc5);
end.
