{ ChnPlc5 - PLC-5 data table addresses and the PCCC requests that read and
  write them, without I/O: parse 'N7:0', 'F8:3', 'B3/17', 'I:012/05'
  (octal I/O), 'O:001', 'T4:1.ACC', 'C5:0.PRE', 'ST9:0', 'D10:0' (BCD);
  plan a read or write of COUNT items as one or more requests (the plans
  and the item rules of unit ChnPccc); build each request and decode its
  reply.

  Commands (Rockwell publication 1770-6.5.16, "DF1 Protocol and Command Set
  Reference Manual", chapter 7, and its chapter 13 for the address):
    CMD 0F FNC 68  typed read:  PACKET OFFSET(2) TOTAL TRANS(2) address SIZE(2)
                   reply: type/data parameter, data
    CMD 0F FNC 67  typed write: PACKET OFFSET(2) TOTAL TRANS(2) address
                   type/data parameter, data
    CMD 0F FNC 01  word range read:  PACKET OFFSET(2) TOTAL TRANS(2) address
                   SIZE(1, bytes); reply: data
    CMD 0F FNC 00  word range write: PACKET OFFSET(2) TOTAL TRANS(2) address data
    CMD 0F FNC 26  read-modify-write: address AND(2) OR(2) (bits)
  The address is the PLC-5 logical binary address: a mask byte (bit n set:
  level n+1 follows), then the levels - 0 (the data table), the file, the
  element, the sub-element (T/C/R word: 0 control, 1 PRE/LEN, 2 ACC/POS);
  a level of 255 and above is $FF and a word low first. We always send
  level 1 (mask $07, or $0F with a sub-element), as the manual's N7:30
  example does (07 00 07 1E).
  The type/data parameter is a flag byte - high nibble the type, low
  nibble the size; a nibble with bit 3 set gives the number of bytes that
  follow (type first, then size, low first) - with types 4 integer, 5
  timer, 6 counter, 7 control, 8 float, 9 array of similar elements, 16
  BCD. Data travel as arrays: 9x 09 [size] element-parameter data, e.g.
  three integers 97 09 42 then six bytes.

  Every offset is 0: each request names its own first element and is a
  whole transaction (TOTAL TRANS = its SIZE). Strings (ST, LEN and 82
  characters, the two of each word swapped as in ChnPccc) always travel by
  word range: no type code is needed for them. Bits of a word are read as
  the word and written with read-modify-write, so other bits stay.
  Every refusal is a res_Pccc* code and a text naming the culprit. }
unit ChnPlc5;

{$I chn.inc}

interface

uses
  ChnTypes, ChnDF1Codec, ChnPccc;

const
  CF_Plc5TypedRead  = $0F68;
  CF_Plc5TypedWrite = $0F67;
  CF_Plc5WordRead   = $0F01;
  CF_Plc5WordWrite  = $0F00;
  CF_Plc5ReadModify = $0F26;

  { type/data parameter type IDs (1770-6.5.16, typed read/write) }
  p5t_Integer = 4;
  p5t_Timer   = 5;
  p5t_Counter = 6;
  p5t_Control = 7;
  p5t_Float   = 8;
  p5t_Array   = 9;
  p5t_Bcd     = 16;


type
  { how data travel: typed read/write (0F 68/67) or word range (0F 01/00) }
  tPlc5Command = (p5Typed, p5WordRange);

{ Parse a PLC-5 address (case and surrounding blanks ignored); res_Ok or
  res_PcccAddress with Err naming the wrong part. O, I, S are files 0, 1,
  2 (the number may be left out: 'I:012/05'); B T C R N F ST A D take
  3..999; elements 0..999, of O and I octal 0..277 with octal bits 00..17;
  'B3/17' is bit 17 of file B3 (= B3:1/1). }
function Plc5ParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
{ The canonical text: 'I:012/05', 'O:001', 'N7:0', 'T4:1.ACC', 'D10:0'. }
function Plc5AddressText(const A: tPcccAddr): ShortString;

{ The logical binary address of A into Data[N..], N moved past it. }
procedure Plc5PutAddress(const A: tPcccAddr; var Data: array of Byte; var N: LongInt);
{ Read a logical binary address from Data[N..Len-1]: Levels[0..3] (absent
  levels 0); False when it is cut short or names more than four levels. }
function Plc5TakeAddress(const Data: array of Byte; Len: LongInt; var N: LongInt;
  out Levels: array of LongInt): Boolean;
{ A type/data parameter into Data[N..]. }
procedure Plc5PutTypeParam(TypeId: Byte; Size: Word; var Data: array of Byte; var N: LongInt);
{ Read one from Data[N..Len-1]; False when cut short or wider than two bytes. }
function Plc5TakeTypeParam(const Data: array of Byte; Len: LongInt; var N: LongInt;
  out TypeId: Word; out Size: Word): Boolean;
{ The type ID a PLC-5 file's elements travel as (a T/C/R word: integer). }
function Plc5ElemType(const A: tPcccAddr): Byte;

{ Plan as PcccPlan, with the room the PLC-5 commands leave in a frame:
  238 data bytes per read reply (after the type parameter), 221 per write
  (after offset, total, address and type parameter). L files are refused. }
function Plc5Plan(const A: tPcccAddr; Count: LongInt; Write: Boolean; MaxBytes: Word;
  out P: tPcccPlan; out Err: ShortString): tChResult;
{ Request Index of a read plan; Expect: the data bytes of its reply after
  any type parameter. }
function Plc5BuildPlanRead(const P: tPcccPlan; Index: LongInt; Cmd: tPlc5Command; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Expect: Word): tChResult;
{ A word range read (0F 01) of Bytes (even, 2..244) from A, PACKET
  OFFSET 0: the tag engine's block reads (ChnPcccTags). }
function Plc5BuildWordRead(const A: tPcccAddr; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
{ Check a reply to read request Index (STS, length, type parameter) and
  find its data: Data[First..First+Expect-1]. res_PcccStatus, res_PcccReply
  with Err saying what is wrong. }
function Plc5CheckReadReply(const P: tPcccPlan; Cmd: tPlc5Command; const Rep: tRecRecord;
  RepLen: Word; Expect: Word; out First: Word; out Err: ShortString): tChResult;
{ Decode the data of read request Index as PcccDecodePlanInts does; the
  words of a D element become 0..9999 (res_PcccReply when a digit is not
  BCD). Data starts at offset 0. }
function Plc5DecodePlanInts(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of LongInt): tChResult;
{ Request Index of a write plan. A D element takes 0..9999. }
function Plc5BuildPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  Cmd: tPlc5Command; Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
function Plc5BuildPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  Cmd: tPlc5Command; Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
{ A string element written by word range (0F 00). }
function Plc5BuildWriteString(const A: tPcccAddr; const S: ShortString; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;

{ BCD: 0..9999 to the word of four digits and back; False when out of
  range or a nibble is above 9. }
function Plc5ToBcd(V: LongInt; out W: Word): Boolean;
function Plc5FromBcd(W: Word; out V: LongInt): Boolean;

implementation

uses
  SysUtils;

const
  ReadRoom  = MaxDataLen - 6;    { reply: 99 09 size and up to 3 bytes of element parameter }
  WriteRoom = MaxDataLen - 23;   { offset, total, address (<= 13), type parameter (<= 6) }

function IsIo(FileType: Byte): Boolean;
begin
  Result := FileType in [pft_Output, pft_Input];
end;

function Plc5AddressText(const A: tPcccAddr): ShortString;
begin
  Result := PcccAddressTextAs(pdPlc5, A);
end;

function Plc5ParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
begin
  Result := PcccParseAddressAs(pdPlc5, S, A, Err);
end;

{- ------------------------------------------------------------ encoding }

procedure PutLevel(V: LongInt; var Data: array of Byte; var N: LongInt);
begin
  if V < 255 then
  begin
    Data[N] := V;
    Inc(N);
  end
  else
  begin
    Data[N] := $FF;
    Data[N + 1] := V and $FF;
    Data[N + 2] := (V shr 8) and $FF;
    Inc(N, 3);
  end;
end;

procedure Plc5PutAddress(const A: tPcccAddr; var Data: array of Byte; var N: LongInt);
begin
  if A.HasSub then
    Data[N] := $0F
  else
    Data[N] := $07;
  Inc(N);
  PutLevel(0, Data, N);              { level 1: the data table }
  PutLevel(A.FileNo, Data, N);
  PutLevel(A.Elem, Data, N);
  if A.HasSub then
    PutLevel(A.Sub, Data, N);
end;

function Plc5TakeAddress(const Data: array of Byte; Len: LongInt; var N: LongInt;
  out Levels: array of LongInt): Boolean;
var
  Mask: Byte;
  L: LongInt;
begin
  for L := 0 to High(Levels) do
    Levels[L] := 0;
  Result := (N < Len) and (Length(Levels) >= 4);
  if not Result then
    Exit;
  Mask := Data[N];
  Inc(N);
  if (Mask and $F0 <> 0) or (Mask = 0) then
    Exit(False);
  for L := 0 to 3 do
    if Mask and (1 shl L) <> 0 then
    begin
      if N >= Len then
        Exit(False);
      if Data[N] <> $FF then
      begin
        Levels[L] := Data[N];
        Inc(N);
      end
      else
      begin
        if N + 2 >= Len then
          Exit(False);
        Levels[L] := Data[N + 1] or (Data[N + 2] shl 8);
        Inc(N, 3);
      end;
    end;
end;

{ The nibble for V, and how many bytes follow it (0 when V fits). }
function Nibble(V: Word; out Extra: LongInt): Byte;
begin
  if V <= 7 then
  begin
    Extra := 0;
    Result := V;
  end
  else if V <= 255 then
  begin
    Extra := 1;
    Result := $08 or 1;
  end
  else
  begin
    Extra := 2;
    Result := $08 or 2;
  end;
end;

procedure PutExtra(V: Word; Extra: LongInt; var Data: array of Byte; var N: LongInt);
var
  K: LongInt;
begin
  for K := 0 to Extra - 1 do
  begin
    Data[N] := (V shr (8 * K)) and $FF;
    Inc(N);
  end;
end;

procedure Plc5PutTypeParam(TypeId: Byte; Size: Word; var Data: array of Byte; var N: LongInt);
var
  TX, SX: LongInt;
  TN, SN: Byte;
begin
  TN := Nibble(TypeId, TX);
  SN := Nibble(Size, SX);
  Data[N] := (TN shl 4) or SN;
  Inc(N);
  PutExtra(TypeId, TX, Data, N);
  PutExtra(Size, SX, Data, N);
end;

function Plc5TakeTypeParam(const Data: array of Byte; Len: LongInt; var N: LongInt;
  out TypeId: Word; out Size: Word): Boolean;

  function Part(Nib: Byte; out V: Word): Boolean;
  var
    K, Extra: LongInt;
  begin
    V := Nib;
    Result := True;
    if Nib and $08 = 0 then
      Exit;
    Extra := Nib and $07;
    V := 0;
    if (Extra < 1) or (Extra > 2) or (N + Extra > Len) then
      Exit(False);
    for K := 0 to Extra - 1 do
      V := V or (Word(Data[N + K]) shl (8 * K));
    Inc(N, Extra);
  end;

var
  Flag: Byte;
begin
  TypeId := 0;
  Size := 0;
  Result := N < Len;
  if not Result then
    Exit;
  Flag := Data[N];
  Inc(N);
  Result := Part(Flag shr 4, TypeId) and Part(Flag and $0F, Size);
end;

function Plc5ElemType(const A: tPcccAddr): Byte;
begin
  if A.HasSub then
    Exit(p5t_Integer);
  case A.FileType of
    pft_Float: Result := p5t_Float;
    pft_Bcd: Result := p5t_Bcd;
    pft_Timer: Result := p5t_Timer;
    pft_Counter: Result := p5t_Counter;
    pft_Control: Result := p5t_Control;
  else
    Result := p5t_Integer;
  end;
end;

function Plc5ToBcd(V: LongInt; out W: Word): Boolean;
var
  K: LongInt;
begin
  W := 0;
  Result := (V >= 0) and (V <= 9999);
  if not Result then
    Exit;
  for K := 0 to 3 do
  begin
    W := W or Word((V mod 10) shl (4 * K));
    V := V div 10;
  end;
end;

function Plc5FromBcd(W: Word; out V: LongInt): Boolean;
var
  K, D: LongInt;
begin
  V := 0;
  for K := 3 downto 0 do
  begin
    D := (W shr (4 * K)) and $F;
    if D > 9 then
      Exit(False);
    V := V * 10 + D;
  end;
  Result := True;
end;

{- --------------------------------------------------------------- plans }

function Plc5Plan(const A: tPcccAddr; Count: LongInt; Write: Boolean; MaxBytes: Word;
  out P: tPcccPlan; out Err: ShortString): tChResult;
var
  Room: Word;
begin
  if A.FileType = pft_Long then
  begin
    FillChar(P, SizeOf(P), 0);
    Err := PcccAddressText(A) + ': a PLC-5 has no L files';
    Exit(res_PcccAddress);
  end;
  Room := MaxBytes;
  if Write and (Room > WriteRoom) then
    Room := WriteRoom
  else if not Write and (Room > ReadRoom) then
    Room := ReadRoom;
  Result := PcccPlan(A, Count, Write, Room, P, Err);
end;

{ Command head: CF, TNS, PACKET OFFSET 0, TOTAL TRANS. }
procedure PutHead(CF: Word; Tns: Word; Total: Word; var Req: tSendRecord; out N: LongInt);
begin
  FillChar(Req, cSizeHead, 0);
  Req.MessType := tpDataMess;
  Req.CF := CF;
  Req.Tns := Tns;
  Req.Data[0] := 0;
  Req.Data[1] := 0;
  Req.Data[2] := Lo(Total);
  Req.Data[3] := Hi(Total);
  N := 4;
end;

function ByWords(const P: tPcccPlan; Cmd: tPlc5Command): Boolean;
begin
  Result := (Cmd = p5WordRange) or (P.Addr.FileType = pft_String);
end;

function Plc5BuildPlanRead(const P: tPcccPlan; Index: LongInt; Cmd: tPlc5Command; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Expect: Word): tChResult;
var
  At: tPcccAddr;
  Units: LongInt;
  N: LongInt;
begin
  ReqLen := 0;
  Expect := 0;
  if P.Write or not PcccPlanChunk(P, Index, At, Units) then
    Exit(res_PcccCount);
  Expect := Units * P.UnitBytes;
  if ByWords(P, Cmd) then
    Exit(Plc5BuildWordRead(At, Expect, Tns, Req, ReqLen))
  else
  begin
    PutHead(CF_Plc5TypedRead, Tns, Units, Req, N);
    Plc5PutAddress(At, Req.Data, N);
    Req.Data[N] := Lo(Units);
    Req.Data[N + 1] := Hi(Units);
    Inc(N, 2);
  end;
  ReqLen := cSizeHead + N;
  Result := res_Ok;
end;

function Plc5BuildWordRead(const A: tPcccAddr; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
var
  N: LongInt;
begin
  ReqLen := 0;
  if (Bytes < 2) or Odd(Bytes) or (Bytes > MaxDataLen) then
    Exit(res_PcccCount);
  PutHead(CF_Plc5WordRead, Tns, Bytes div 2, Req, N);
  Plc5PutAddress(A, Req.Data, N);
  Req.Data[N] := Bytes;
  ReqLen := cSizeHead + N + 1;
  Result := res_Ok;
end;

function Plc5CheckReadReply(const P: tPcccPlan; Cmd: tPlc5Command; const Rep: tRecRecord;
  RepLen: Word; Expect: Word; out First: Word; out Err: ShortString): tChResult;
var
  N, Len, ElemAt: LongInt;
  TypeId, Size, ElemType, ElemSize: Word;
  Want: Byte;
begin
  First := 0;
  if ByWords(P, Cmd) or (RepLen < cSizeHead) or (Rep.Sts <> 0) then
    Exit(PcccCheckReply(Rep, RepLen, Expect, Err));
  Err := '';
  Len := RepLen - cSizeHead;
  N := 0;
  Result := res_PcccReply;
  Err := 'reply type parameter is cut short';
  if not Plc5TakeTypeParam(Rep.Data, Len, N, TypeId, Size) then
    Exit;
  ElemType := TypeId;
  ElemSize := Size;
  if TypeId = p5t_Array then
  begin
    ElemAt := N;
    if not Plc5TakeTypeParam(Rep.Data, Len, N, ElemType, ElemSize) then
      Exit;
    if Size <> Len - ElemAt then
    begin
      Err := Format('reply array of %d bytes, %d follow', [Size, Len - ElemAt]);
      Exit;
    end;
  end;
  if Len - N <> Expect then
  begin
    Err := Format('reply has %d data bytes, %d expected', [Len - N, Expect]);
    Exit;
  end;
  Want := Plc5ElemType(P.Addr);
  if (ElemType = p5t_Float) <> (Want = p5t_Float) then
  begin
    Err := Format('reply holds data of type %d, %d expected', [ElemType, Want]);
    Exit;
  end;
  if (TypeId = p5t_Array) and (ElemSize <> P.UnitBytes) or
     (TypeId <> p5t_Array) and (Size <> Expect) then
  begin
    Err := Format('reply elements of %d bytes, %d expected', [ElemSize, P.UnitBytes]);
    Exit;
  end;
  Err := '';
  First := N;
  Result := res_Ok;
end;

function Plc5DecodePlanInts(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of LongInt): tChResult;
var
  At: tPcccAddr;
  Units, I, V: LongInt;
begin
  Result := PcccDecodePlanInts(P, Index, Data, DataLen, Values);
  if (Result <> res_Ok) or (P.Addr.FileType <> pft_Bcd) or (P.Mode <> pmElems) then
    Exit;
  PcccPlanChunk(P, Index, At, Units);
  for I := Index * P.PerReq to Index * P.PerReq + Units - 1 do
  begin
    if not Plc5FromBcd(Word(Values[I]), V) then
      Exit(res_PcccReply);
    Values[I] := V;
  end;
end;

{ A write request for data already laid out (Bytes of them at At). }
function BuildWrite(const P: tPcccPlan; const At: tPcccAddr; const Buf: array of Byte; Bytes: Word;
  Cmd: tPlc5Command; Tns: Word; var Req: tSendRecord; out ReqLen: Word): tChResult;
var
  N, EN: LongInt;
  Elems: Word;
  ElemParam: array[0..5] of Byte;
begin
  if ByWords(P, Cmd) then
  begin
    PutHead(CF_Plc5WordWrite, Tns, Bytes div 2, Req, N);
    Plc5PutAddress(At, Req.Data, N);
  end
  else
  begin
    Elems := Bytes div P.UnitBytes;
    PutHead(CF_Plc5TypedWrite, Tns, Elems, Req, N);
    Plc5PutAddress(At, Req.Data, N);
    { the array's size counts the element parameter and the data }
    EN := 0;
    Plc5PutTypeParam(Plc5ElemType(At), P.UnitBytes, ElemParam, EN);
    Plc5PutTypeParam(p5t_Array, EN + Bytes, Req.Data, N);
    Move(ElemParam, Req.Data[N], EN);
    Inc(N, EN);
  end;
  if N + Bytes > MaxDataLen then
    Exit(res_PcccCount);
  Move(Buf[0], Req.Data[N], Bytes);
  ReqLen := cSizeHead + N + Bytes;
  Result := res_Ok;
end;

function Plc5BuildPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  Cmd: tPlc5Command; Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
var
  Buf: array[0..MaxDataLen - 1] of Byte;
  At: tPcccAddr;
  Bytes, Mask, Bits, W: Word;
  Bcd: array of LongInt;
  I: LongInt;
  N: LongInt;
begin
  ReqLen := 0;
  Err := '';
  if (P.Addr.FileType = pft_Bcd) and (P.Mode = pmElems) then
  begin
    { D elements take 0..9999 and travel as four BCD digits }
    SetLength(Bcd, Length(Values));
    for I := 0 to High(Values) do
    begin
      if not Plc5ToBcd(Values[I], W) then
      begin
        Err := Format('value %d for %s is not 0..9999',
          [Values[I], PcccAddressText(PcccItemAddress(P, I))]);
        Exit(res_PcccValue);
      end;
      Bcd[I] := W;
    end;
    Result := PcccPlanWriteInts(P, Index, Bcd, At, Buf, Bytes, Mask, Bits, Err);
  end
  else
    Result := PcccPlanWriteInts(P, Index, Values, At, Buf, Bytes, Mask, Bits, Err);
  if Result <> res_Ok then
  begin
    if IsIo(P.Addr.FileType) then
      Err := StringReplace(Err, PcccAddressText(P.Addr), Plc5AddressText(P.Addr), []);
    Exit;
  end;
  if Bytes = 0 then
  begin
    { bits: the word's other bits stay (AND keeps them, OR sets ours) }
    FillChar(Req, cSizeHead, 0);
    Req.MessType := tpDataMess;
    Req.CF := CF_Plc5ReadModify;
    Req.Tns := Tns;
    N := 0;
    Plc5PutAddress(At, Req.Data, N);
    Req.Data[N] := Lo(not Mask);
    Req.Data[N + 1] := Hi(not Mask);
    Req.Data[N + 2] := Lo(Bits);
    Req.Data[N + 3] := Hi(Bits);
    ReqLen := cSizeHead + N + 4;
    Exit(res_Ok);
  end;
  Result := BuildWrite(P, At, Buf, Bytes, Cmd, Tns, Req, ReqLen);
end;

function Plc5BuildPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  Cmd: tPlc5Command; Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
var
  Buf: array[0..MaxDataLen - 1] of Byte;
  At: tPcccAddr;
  Bytes: Word;
begin
  ReqLen := 0;
  Result := PcccPlanWriteFloats(P, Index, Values, At, Buf, Bytes, Err);
  if Result = res_Ok then
    Result := BuildWrite(P, At, Buf, Bytes, Cmd, Tns, Req, ReqLen);
end;

function Plc5BuildWriteString(const A: tPcccAddr; const S: ShortString; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
var
  Buf: array[0..2 + PcccStringChars - 1] of Byte;
  N: LongInt;
begin
  ReqLen := 0;
  Result := PcccEncodeString(S, Buf, Err);
  if Result <> res_Ok then
    Exit;
  PutHead(CF_Plc5WordWrite, Tns, SizeOf(Buf) div 2, Req, N);
  Plc5PutAddress(A, Req.Data, N);
  Move(Buf, Req.Data[N], SizeOf(Buf));
  ReqLen := cSizeHead + N + SizeOf(Buf);
end;

end.
