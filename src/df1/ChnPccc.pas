{ ChnPccc - the PCCC requests that read and write SLC 500 / MicroLogix
  data table addresses ('N7:0', 'B3:1/4', 'T4:0.ACC': their syntax is
  ChnPcccAddr's, its names are here too), without I/O: plan a read or
  write of COUNT items as one or more requests; build each request record
  (tSendRecord of ChnDF1Codec) and decode its reply.

  Commands (Rockwell publication 1770-6.5.16, "DF1 Protocol and Command Set
  Reference Manual", chapter 7; docs/PROTOCOLS.md):
    CMD 0F FNC A2  protected typed logical read, three address fields
                   SIZE FILE TYPE ELEMENT SUBELEMENT
    CMD 0F FNC AA  protected typed logical write, three address fields
                   SIZE FILE TYPE ELEMENT SUBELEMENT data
    CMD 0F FNC AB  protected typed logical masked write, three address fields
                   SIZE FILE TYPE ELEMENT SUBELEMENT MASK(2) data(2)
  FILE, ELEMENT and SUBELEMENT are one byte, or $FF and a word low first
  for values of 255 and above. Data travel little-endian; a string (ST) is
  LEN(2) and 82 characters with the two characters of each word swapped, as
  SLC processors store them.

  Every refusal is a result code (res_Pccc*, texts registered for the layer
  name PcccLayer) and a text that names the culprit. Nothing here reads or
  writes past the arrays it is given. }
unit ChnPccc;

{$I chn.inc}

interface

uses
  ChnTypes, ChnDF1Codec, ChnPcccAddr;

const
  PcccLayer = ChnPcccAddr.PcccLayer;   {< ChResultText(R, PcccLayer) }

  res_PcccAddress = ChnPcccAddr.res_PcccAddress;   {< malformed or impossible address }
  res_PcccCount   = res_Proto + 1;   {< count does not fit (file, array, frame) }
  res_PcccValue   = res_Proto + 2;   {< value out of range for the element }
  res_PcccReply   = res_Proto + 3;   {< reply length or content does not match }
  res_PcccStatus  = res_Proto + 4;   {< the PLC answered with STS <> 0 }
  res_PcccNak     = res_Proto + 5;   {< the command was NAKed on every try }
  res_PcccUsage   = res_Proto + 6;   {< the address holds another kind of value }

  { PCCC file type codes (ChnPcccAddr) }
  pft_Status = ChnPcccAddr.pft_Status;
  pft_Bit = ChnPcccAddr.pft_Bit;
  pft_Timer = ChnPcccAddr.pft_Timer;
  pft_Counter = ChnPcccAddr.pft_Counter;
  pft_Control = ChnPcccAddr.pft_Control;
  pft_Integer = ChnPcccAddr.pft_Integer;
  pft_Float = ChnPcccAddr.pft_Float;
  pft_Output = ChnPcccAddr.pft_Output;
  pft_Input = ChnPcccAddr.pft_Input;
  pft_String = ChnPcccAddr.pft_String;
  pft_Ascii = ChnPcccAddr.pft_Ascii;
  pft_Long = ChnPcccAddr.pft_Long;
  pft_Bcd = ChnPcccAddr.pft_Bcd;

  CF_PcccRead3      = $0FA2;   {< = ChnDF1.CF_ProtectRead3Addr }
  CF_PcccWrite3     = $0FAA;   {< = ChnDF1.CF_ProtectWrite3Addr }
  CF_PcccMaskWrite3 = $0FAB;

  PcccStringChars = 82;        {< characters of an ST element }
  PcccMaxItems    = 4096;      {< items of one read or write }

type
  { ChnPcccAddr's, for programs that use this unit alone }
  tPcccAddr = ChnPcccAddr.tPcccAddr;
  tPcccValueKind = ChnPcccAddr.tPcccValueKind;
  tPcccDialect = ChnPcccAddr.tPcccDialect;

const
  pvInt = ChnPcccAddr.pvInt;
  pvFloat = ChnPcccAddr.pvFloat;
  pvString = ChnPcccAddr.pvString;
  pdSlc = ChnPcccAddr.pdSlc;
  pdPlc5 = ChnPcccAddr.pdPlc5;

type
  { How a read or write of Count items at Addr travels: requests of
    PerReq units (elements, or words for bits) each. }
  tPcccMode = (pmElems, pmSubs, pmBits);
  tPcccPlan = packed record
    Addr     : tPcccAddr;
    Count    : LongInt;    {< items }
    Mode     : tPcccMode;
    UnitBytes: Word;       {< bytes of one unit on the wire }
    Units    : LongInt;    {< units in all }
    PerReq   : LongInt;    {< units per request }
    PerItem  : Byte;       {< LongInt values per item (3 for a whole T/C/R) }
    Write    : Boolean;
  end;

{ ChnPcccAddr's, for programs that use this unit alone (what each does:
  there): PcccParseAddress, PcccParseAddressAs (by a family's rules),
  PcccAddressText, PcccAddressTextAs, PcccFileLetter, PcccElemSize,
  PcccValueKind, PcccFileByLetter, PcccFindSub, PcccSubName. }
function PcccParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
function PcccParseAddressAs(Dialect: tPcccDialect; const S: ShortString; out A: tPcccAddr;
  out Err: ShortString): tChResult;
function PcccAddressTextAs(Dialect: tPcccDialect; const A: tPcccAddr): ShortString;
function PcccAddressText(const A: tPcccAddr): ShortString;
function PcccFileLetter(FileType: Byte): ShortString;
function PcccElemSize(FileType: Byte): Word;
function PcccValueKind(const A: tPcccAddr): tPcccValueKind;
function PcccFileByLetter(const Letters: ShortString; out Fixed: SmallInt): Byte;
function PcccFindSub(FileType: Byte; const Name: ShortString; out Sub: Byte; out Bit: ShortInt): Boolean;
function PcccSubName(const A: tPcccAddr): ShortString;

{ Plan a read (Write False) or write of Count items at A, at most MaxBytes
  data bytes per request (1..244). An item is an element; a word for
  .PRE/.ACC/.LEN/.POS; a bit for '/n' and .DN-like addresses (consecutive
  bits from there on a word file, the same bit of consecutive elements for
  timers, counters and controls); a whole T, C or R element is three ints
  (control word, PRE or LEN, ACC or POS). res_PcccCount when Count is 0,
  above PcccMaxItems, runs past element 65535 or an element does not fit
  in MaxBytes. }
function PcccPlan(const A: tPcccAddr; Count: LongInt; Write: Boolean; MaxBytes: Word;
  out P: tPcccPlan; out Err: ShortString): tChResult;
{ The address of item Item (0-based) of a plan: B3:1/15 is followed by
  B3:2/0, T4:0.ACC by T4:1.ACC, N7:0 by N7:1. }
function PcccItemAddress(const P: tPcccPlan; Item: LongInt): tPcccAddr;
{ Number of requests of a plan. }
function PcccPlanRequests(const P: tPcccPlan): LongInt;
{ Where request Index of a plan starts (the word of a bit, the element of
  a sub-element) and how many units it covers; False when Index is out of
  range. }
function PcccPlanChunk(const P: tPcccPlan; Index: LongInt; out At: tPcccAddr; out Units: LongInt): Boolean;
{ The values (LongInt) the items of a plan fill: Count * PerItem. }
function PcccPlanValues(const P: tPcccPlan): LongInt;

{ Request Index (0-based) of a read plan: Req/ReqLen to send, Expect the
  reply's data bytes. }
function PcccBuildPlanRead(const P: tPcccPlan; Index: LongInt; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Expect: Word): tChResult;
{ Decode the reply data of read request Index into Values (as many as
  PcccPlanValues, ints: 16-bit signed for N/T/C/R words, unsigned for
  B/O/I/S/A, 32-bit for L, 0/1 for bits; floats for F). res_PcccReply when
  DataLen is not what the request asked for, res_PcccCount when Values is
  too short. Strings: PcccDecodeString. }
function PcccDecodePlanInts(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of LongInt): tChResult;
function PcccDecodePlanFloats(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of Single): tChResult;

{ The data of request Index of a write plan, whatever command carries it:
  At is where it starts; Bytes bytes in Data (little-endian words, longs,
  floats), or for bits Bytes 0 and the word's Mask (bits written) and
  Bits (their values). res_PcccValue with Err naming the value and its
  range when one does not fit the element. }
function PcccPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  out At: tPcccAddr; var Data: array of Byte; out Bytes: Word; out Mask, Bits: Word;
  out Err: ShortString): tChResult;
function PcccPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  out At: tPcccAddr; var Data: array of Byte; out Bytes: Word; out Err: ShortString): tChResult;

{ Request Index of a write plan with the values given (ints for word, long
  and bit addresses, floats for F). res_PcccValue with Err naming the
  value and its range when one does not fit the element. Bits become
  masked writes (0F AB), one per word. }
function PcccBuildPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
function PcccBuildPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;

{ The single requests. Bytes 1..244 (a write: as many as fit after the
  address fields, else res_PcccCount). }
function PcccBuildRead(const A: tPcccAddr; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
function PcccBuildWrite(const A: tPcccAddr; const Data: array of Byte; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
function PcccBuildMaskedWrite(const A: tPcccAddr; Mask, Value: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;

{ The data bytes of an ST element (84) for S; res_PcccValue when S is
  longer than 82 characters. }
function PcccEncodeString(const S: ShortString; var Data: array of Byte; out Err: ShortString): tChResult;
{ An ST element from Data[Offset..Offset+83]; res_PcccReply when it does
  not fit in Data or its LEN is above 82. }
function PcccDecodeString(const Data: array of Byte; Offset: LongInt; out S: ShortString): tChResult;

{ res_Ok for a reply with STS 0 and DataLen = Expect data bytes; else
  res_PcccStatus (Err: STS and EXT STS with their meanings) or
  res_PcccReply (Err: the lengths). }
function PcccCheckReply(const Rep: tRecRecord; RepLen: Word; Expect: Word; out Err: ShortString): tChResult;

implementation

uses
  SysUtils, ChnPcccNames;

{- ------------------------------------------------------------ addresses }

function PcccParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
begin
  Result := ChnPcccAddr.PcccParseAddress(S, A, Err);
end;

function PcccParseAddressAs(Dialect: tPcccDialect; const S: ShortString; out A: tPcccAddr;
  out Err: ShortString): tChResult;
begin
  Result := ChnPcccAddr.PcccParseAddressAs(Dialect, S, A, Err);
end;

function PcccAddressTextAs(Dialect: tPcccDialect; const A: tPcccAddr): ShortString;
begin
  Result := ChnPcccAddr.PcccAddressTextAs(Dialect, A);
end;

function PcccAddressText(const A: tPcccAddr): ShortString;
begin
  Result := ChnPcccAddr.PcccAddressText(A);
end;

function PcccFileLetter(FileType: Byte): ShortString;
begin
  Result := ChnPcccAddr.PcccFileLetter(FileType);
end;

function PcccElemSize(FileType: Byte): Word;
begin
  Result := ChnPcccAddr.PcccElemSize(FileType);
end;

function PcccValueKind(const A: tPcccAddr): tPcccValueKind;
begin
  Result := ChnPcccAddr.PcccValueKind(A);
end;

function PcccFileByLetter(const Letters: ShortString; out Fixed: SmallInt): Byte;
begin
  Result := ChnPcccAddr.PcccFileByLetter(Letters, Fixed);
end;

function PcccFindSub(FileType: Byte; const Name: ShortString; out Sub: Byte; out Bit: ShortInt): Boolean;
begin
  Result := ChnPcccAddr.PcccFindSub(FileType, Name, Sub, Bit);
end;

function PcccSubName(const A: tPcccAddr): ShortString;
begin
  Result := ChnPcccAddr.PcccSubName(A);
end;

{- ------------------------------------------------------------- requests }

{ A three-address field: one byte, or $FF and a word low first. }
procedure PutField(var Req: tSendRecord; var N: Integer; V: Word);
begin
  if V < 255 then
  begin
    Req.Data[N] := V;
    Inc(N);
  end
  else
  begin
    Req.Data[N] := $FF;
    Req.Data[N + 1] := Lo(V);
    Req.Data[N + 2] := Hi(V);
    Inc(N, 3);
  end;
end;

{ Header and SIZE FILE TYPE ELEMENT SUBELEMENT; N = data bytes so far. }
procedure PutHead(const A: tPcccAddr; CF: Word; Size: Byte; Tns: Word;
  var Req: tSendRecord; out N: Integer);
begin
  FillChar(Req, cSizeHead, 0);
  Req.MessType := tpDataMess;
  Req.CF := CF;
  Req.Tns := Tns;
  N := 0;
  Req.Data[N] := Size;
  Inc(N);
  PutField(Req, N, A.FileNo);
  Req.Data[N] := A.FileType;
  Inc(N);
  PutField(Req, N, A.Elem);
  if A.HasSub then
    PutField(Req, N, A.Sub)
  else
    PutField(Req, N, 0);
end;

function HeadBytes(const A: tPcccAddr): Integer;
var
  Req: tSendRecord;
begin
  PutHead(A, 0, 0, 0, Req, Result);
end;

function PcccBuildRead(const A: tPcccAddr; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
var
  N: Integer;
begin
  ReqLen := 0;
  if (Bytes < 1) or (Bytes > MaxDataLen) then
    Exit(res_PcccCount);
  PutHead(A, CF_PcccRead3, Bytes, Tns, Req, N);
  ReqLen := cSizeHead + N;
  Result := res_Ok;
end;

function PcccBuildWrite(const A: tPcccAddr; const Data: array of Byte; Bytes: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
var
  N: Integer;
begin
  ReqLen := 0;
  if (Bytes < 1) or (Bytes > Length(Data)) or (HeadBytes(A) + Bytes > MaxDataLen) then
    Exit(res_PcccCount);
  PutHead(A, CF_PcccWrite3, Bytes, Tns, Req, N);
  Move(Data[0], Req.Data[N], Bytes);
  ReqLen := cSizeHead + N + Bytes;
  Result := res_Ok;
end;

function PcccBuildMaskedWrite(const A: tPcccAddr; Mask, Value: Word; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word): tChResult;
var
  N: Integer;
begin
  PutHead(A, CF_PcccMaskWrite3, 2, Tns, Req, N);
  Req.Data[N] := Lo(Mask);
  Req.Data[N + 1] := Hi(Mask);
  Req.Data[N + 2] := Lo(Value);
  Req.Data[N + 3] := Hi(Value);
  ReqLen := cSizeHead + N + 4;
  Result := res_Ok;
end;

{- ---------------------------------------------------------------- plans }

function PcccPlan(const A: tPcccAddr; Count: LongInt; Write: Boolean; MaxBytes: Word;
  out P: tPcccPlan; out Err: ShortString): tChResult;
var
  Room: LongInt;
begin
  FillChar(P, SizeOf(P), 0);
  Err := '';
  P.Addr := A;
  P.Count := Count;
  P.Write := Write;
  P.PerItem := 1;
  if (Count < 1) or (Count > PcccMaxItems) then
  begin
    Err := 'count ' + IntToStr(Count) + ' is not 1..' + IntToStr(PcccMaxItems);
    Exit(res_PcccCount);
  end;
  if (MaxBytes < 2) or (MaxBytes > MaxDataLen) then
  begin
    Err := 'bytes per request ' + IntToStr(MaxBytes) + ' is not 2..' + IntToStr(MaxDataLen);
    Exit(res_PcccCount);
  end;
  if PcccElemSize(A.FileType) = 0 then
  begin
    Err := 'file type $' + IntToHex(A.FileType, 2) + ' is unknown';
    Exit(res_PcccAddress);
  end;
  { room for data: a write also carries the address fields (at most 9) }
  Room := MaxBytes;
  if Write and (Room > MaxDataLen - 9) then
    Room := MaxDataLen - 9;
  if PcccHasSubs(A.FileType) and A.HasSub then
  begin
    P.Mode := pmSubs;         { one word of each element, one request each }
    P.UnitBytes := 2;
    P.Units := Count;
    P.PerReq := 1;
  end
  else if A.Bit >= 0 then
  begin
    P.Mode := pmBits;         { consecutive bits of a word file }
    P.UnitBytes := 2;
    P.Units := (A.Bit + Count + 15) div 16;
    P.PerReq := Room div 2;
    if Write then
      P.PerReq := 1;          { a masked write per word }
  end
  else
  begin
    P.Mode := pmElems;
    P.UnitBytes := PcccElemSize(A.FileType);
    P.Units := Count;
    P.PerReq := Room div P.UnitBytes;
    if PcccHasSubs(A.FileType) then
      P.PerItem := 3;
    if P.PerReq = 0 then
    begin
      Err := Format('a %s element (%d bytes) does not fit in %d bytes per request',
        [PcccFileLetter(A.FileType), P.UnitBytes, MaxBytes]);
      Exit(res_PcccCount);
    end;
  end;
  if LongInt(A.Elem) + P.Units - 1 > 65535 then
  begin
    Err := Format('%d items from %s run past element 65535', [Count, PcccAddressText(A)]);
    Exit(res_PcccCount);
  end;
  Result := res_Ok;
end;

function PcccItemAddress(const P: tPcccPlan; Item: LongInt): tPcccAddr;
var
  Abs_: LongInt;
begin
  Result := P.Addr;
  if P.Mode = pmBits then
  begin
    Abs_ := LongInt(P.Addr.Elem) * 16 + P.Addr.Bit + Item;
    Result.Elem := Word(Abs_ div 16);
    Result.Bit := Abs_ mod 16;
  end
  else
    Result.Elem := Word(P.Addr.Elem + Item);
end;

function PcccPlanRequests(const P: tPcccPlan): LongInt;
begin
  if P.PerReq <= 0 then
    Result := 0
  else
    Result := (P.Units + P.PerReq - 1) div P.PerReq;
end;

function PcccPlanValues(const P: tPcccPlan): LongInt;
begin
  Result := P.Count * P.PerItem;
end;

{ First unit and number of units of request Index; False when out of range. }
function Chunk(const P: tPcccPlan; Index: LongInt; out First, N: LongInt): Boolean;
begin
  First := 0;
  N := 0;
  Result := (Index >= 0) and (Index < PcccPlanRequests(P));
  if not Result then
    Exit;
  First := Index * P.PerReq;
  N := P.Units - First;
  if N > P.PerReq then
    N := P.PerReq;
end;

{ The address where request Index starts. }
function ChunkAddr(const P: tPcccPlan; First: LongInt): tPcccAddr;
begin
  Result := P.Addr;
  Result.Elem := P.Addr.Elem + First;
  if P.Mode = pmBits then
    Result.HasSub := False;
  if P.Mode <> pmSubs then
    Result.Sub := 0;
end;

function PcccPlanChunk(const P: tPcccPlan; Index: LongInt; out At: tPcccAddr; out Units: LongInt): Boolean;
var
  First: LongInt;
begin
  Result := Chunk(P, Index, First, Units);
  At := ChunkAddr(P, First);
end;

function PcccBuildPlanRead(const P: tPcccPlan; Index: LongInt; Tns: Word;
  var Req: tSendRecord; out ReqLen: Word; out Expect: Word): tChResult;
var
  First, N: LongInt;
begin
  ReqLen := 0;
  Expect := 0;
  if P.Write or not Chunk(P, Index, First, N) then
    Exit(res_PcccCount);
  Expect := N * P.UnitBytes;
  Result := PcccBuildRead(ChunkAddr(P, First), Expect, Tns, Req, ReqLen);
end;

function GetWord(const Data: array of Byte; At: LongInt): Word; inline;
begin
  Result := Data[At] or (Word(Data[At + 1]) shl 8);
end;

{ A 16-bit word as the address's type reads: signed for N, T, C, R (and
  their words), unsigned bit patterns for B, O, I, S, A. }
function WordValue(FileType: Byte; W: Word): LongInt;
begin
  if FileType in [pft_Integer, pft_Timer, pft_Counter, pft_Control] then
    Result := SmallInt(W)
  else
    Result := W;
end;

function PcccDecodePlanInts(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of LongInt): tChResult;
var
  First, N, I, K, Item, At: LongInt;
  W: Word;
begin
  if P.Write or not Chunk(P, Index, First, N) or (PcccValueKind(P.Addr) <> pvInt) then
    Exit(res_PcccUsage);
  if (DataLen <> N * P.UnitBytes) or (DataLen > Length(Data)) then
    Exit(res_PcccReply);
  if Length(Values) < PcccPlanValues(P) then
    Exit(res_PcccCount);
  for I := 0 to N - 1 do
  begin
    At := I * P.UnitBytes;
    case P.Mode of
      pmSubs:
        begin
          W := GetWord(Data, At);
          if P.Addr.Bit >= 0 then
            Values[First + I] := (W shr P.Addr.Bit) and 1
          else
            Values[First + I] := WordValue(P.Addr.FileType, W);
        end;
      pmBits:
        begin
          W := GetWord(Data, At);
          for K := 0 to 15 do
          begin
            Item := (First + I) * 16 + K - P.Addr.Bit;
            if (Item >= 0) and (Item < P.Count) then
              Values[Item] := (W shr K) and 1;
          end;
        end;
      pmElems:
        if P.Addr.FileType = pft_Long then
          Values[First + I] := LongInt(LongWord(GetWord(Data, At)) or
            (LongWord(GetWord(Data, At + 2)) shl 16))
        else
          for K := 0 to P.PerItem - 1 do
            Values[(First + I) * P.PerItem + K] :=
              WordValue(P.Addr.FileType, GetWord(Data, At + 2 * K));
    end;
  end;
  Result := res_Ok;
end;

function PcccDecodePlanFloats(const P: tPcccPlan; Index: LongInt; const Data: array of Byte;
  DataLen: Word; var Values: array of Single): tChResult;
var
  First, N, I: LongInt;
  L: LongWord;
begin
  if P.Write or not Chunk(P, Index, First, N) or (PcccValueKind(P.Addr) <> pvFloat) then
    Exit(res_PcccUsage);
  if (DataLen <> N * 4) or (DataLen > Length(Data)) then
    Exit(res_PcccReply);
  if Length(Values) < P.Count then
    Exit(res_PcccCount);
  for I := 0 to N - 1 do
  begin
    L := LongWord(GetWord(Data, I * 4)) or (LongWord(GetWord(Data, I * 4 + 2)) shl 16);
    Move(L, Values[First + I], 4);
  end;
  Result := res_Ok;
end;

{ The range of an int written to an address. }
procedure IntRange(const A: tPcccAddr; out Lo, Hi: LongInt);
begin
  if (A.Bit >= 0) then
  begin
    Lo := 0;
    Hi := 1;
  end
  else if A.FileType = pft_Long then
  begin
    Lo := Low(LongInt);
    Hi := High(LongInt);
  end
  else if A.FileType in [pft_Integer, pft_Timer, pft_Counter, pft_Control] then
  begin
    Lo := -32768;
    Hi := 32767;
  end
  else
  begin
    Lo := 0;
    Hi := 65535;
  end;
end;

function PcccPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  out At: tPcccAddr; var Data: array of Byte; out Bytes: Word; out Mask, Bits: Word;
  out Err: ShortString): tChResult;
var
  First, N, I, K, Item, Lo, Hi: LongInt;
  V: LongInt;
begin
  Bytes := 0;
  Mask := 0;
  Bits := 0;
  Err := '';
  At := P.Addr;
  if not P.Write or not Chunk(P, Index, First, N) or (PcccValueKind(P.Addr) <> pvInt) then
  begin
    Err := PcccAddressText(P.Addr) + ' does not take integer values';
    Exit(res_PcccUsage);
  end;
  if Length(Values) < PcccPlanValues(P) then
  begin
    Err := Format('%d values given, %d needed', [Length(Values), PcccPlanValues(P)]);
    Exit(res_PcccCount);
  end;
  At := ChunkAddr(P, First);
  IntRange(P.Addr, Lo, Hi);
  if P.Mode = pmBits then
  begin
    for K := 0 to 15 do
    begin
      Item := First * 16 + K - P.Addr.Bit;
      if (Item >= 0) and (Item < P.Count) then
      begin
        V := Values[Item];
        if (V < 0) or (V > 1) then
        begin
          Err := Format('value %d for %s is not 0 or 1',
            [V, PcccAddressText(PcccItemAddress(P, Item))]);
          Exit(res_PcccValue);
        end;
        Mask := Mask or Word(1 shl K);
        if V = 1 then
          Bits := Bits or Word(1 shl K);
      end;
    end;
    Exit(res_Ok);
  end;
  if (P.Mode = pmSubs) and (P.Addr.Bit >= 0) then
  begin
    V := Values[First];
    if (V < 0) or (V > 1) then
    begin
      Err := Format('value %d for %s is not 0 or 1',
        [V, PcccAddressText(PcccItemAddress(P, First))]);
      Exit(res_PcccValue);
    end;
    Mask := Word(1 shl P.Addr.Bit);
    Bits := Word(V shl P.Addr.Bit);
    Exit(res_Ok);
  end;
  if N * P.UnitBytes > Length(Data) then
    Exit(res_PcccCount);
  for I := 0 to N * P.PerItem - 1 do
  begin
    V := Values[First * P.PerItem + I];
    if (V < Lo) or (V > Hi) then
    begin
      Err := Format('value %d for %s is not %d..%d',
        [V, PcccAddressText(PcccItemAddress(P, First + I div P.PerItem)), Lo, Hi]);
      Exit(res_PcccValue);
    end;
    if P.Addr.FileType = pft_Long then
    begin
      Data[I * 4] := LongWord(V) and $FF;
      Data[I * 4 + 1] := (LongWord(V) shr 8) and $FF;
      Data[I * 4 + 2] := (LongWord(V) shr 16) and $FF;
      Data[I * 4 + 3] := LongWord(V) shr 24;
    end
    else
    begin
      Data[I * 2] := V and $FF;
      Data[I * 2 + 1] := (V shr 8) and $FF;
    end;
  end;
  Bytes := N * P.UnitBytes;
  Result := res_Ok;
end;

function PcccBuildPlanWriteInts(const P: tPcccPlan; Index: LongInt; const Values: array of LongInt;
  Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
var
  Buf: array[0..MaxDataLen - 1] of Byte;
  At: tPcccAddr;
  Bytes, Mask, Bits: Word;
begin
  ReqLen := 0;
  Result := PcccPlanWriteInts(P, Index, Values, At, Buf, Bytes, Mask, Bits, Err);
  if Result <> res_Ok then
    Exit;
  if Bytes = 0 then
    Result := PcccBuildMaskedWrite(At, Mask, Bits, Tns, Req, ReqLen)
  else
    Result := PcccBuildWrite(At, Buf, Bytes, Tns, Req, ReqLen);
end;

function PcccPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  out At: tPcccAddr; var Data: array of Byte; out Bytes: Word; out Err: ShortString): tChResult;
var
  First, N, I: LongInt;
  L: LongWord;
begin
  Bytes := 0;
  Err := '';
  At := P.Addr;
  if not P.Write or not Chunk(P, Index, First, N) or (PcccValueKind(P.Addr) <> pvFloat) then
  begin
    Err := PcccAddressText(P.Addr) + ' does not take float values';
    Exit(res_PcccUsage);
  end;
  if Length(Values) < P.Count then
  begin
    Err := Format('%d values given, %d needed', [Length(Values), P.Count]);
    Exit(res_PcccCount);
  end;
  if N * 4 > Length(Data) then
    Exit(res_PcccCount);
  for I := 0 to N - 1 do
  begin
    Move(Values[First + I], L, 4);
    if (L and $7F800000) = $7F800000 then
    begin
      Err := 'value for ' + PcccAddressText(PcccItemAddress(P, First + I)) + ' is not a finite number';
      Exit(res_PcccValue);
    end;
    Data[I * 4] := L and $FF;
    Data[I * 4 + 1] := (L shr 8) and $FF;
    Data[I * 4 + 2] := (L shr 16) and $FF;
    Data[I * 4 + 3] := L shr 24;
  end;
  At := ChunkAddr(P, First);
  Bytes := N * 4;
  Result := res_Ok;
end;

function PcccBuildPlanWriteFloats(const P: tPcccPlan; Index: LongInt; const Values: array of Single;
  Tns: Word; var Req: tSendRecord; out ReqLen: Word; out Err: ShortString): tChResult;
var
  Buf: array[0..MaxDataLen - 1] of Byte;
  At: tPcccAddr;
  Bytes: Word;
begin
  ReqLen := 0;
  Result := PcccPlanWriteFloats(P, Index, Values, At, Buf, Bytes, Err);
  if Result = res_Ok then
    Result := PcccBuildWrite(At, Buf, Bytes, Tns, Req, ReqLen);
end;

{- -------------------------------------------------------------- strings }

function PcccEncodeString(const S: ShortString; var Data: array of Byte; out Err: ShortString): tChResult;
var
  I: Integer;
  Ch: array[0..PcccStringChars - 1] of Byte;
begin
  Err := '';
  if Length(S) > PcccStringChars then
  begin
    Err := Format('string of %d characters is longer than %d', [Length(S), PcccStringChars]);
    Exit(res_PcccValue);
  end;
  if Length(Data) < 2 + PcccStringChars then
  begin
    Err := 'buffer smaller than an ST element';
    Exit(res_PcccCount);
  end;
  FillChar(Ch, SizeOf(Ch), 0);
  for I := 1 to Length(S) do
    Ch[I - 1] := Ord(S[I]);
  Data[0] := Length(S);
  Data[1] := 0;
  for I := 0 to PcccStringChars div 2 - 1 do
  begin
    { each word holds its first character in the high byte }
    Data[2 + 2 * I] := Ch[2 * I + 1];
    Data[3 + 2 * I] := Ch[2 * I];
  end;
  Result := res_Ok;
end;

function PcccDecodeString(const Data: array of Byte; Offset: LongInt; out S: ShortString): tChResult;
var
  Len, I: Integer;
begin
  S := '';
  if (Offset < 0) or (LongInt(Length(Data)) - Offset < 2 + PcccStringChars) then
    Exit(res_PcccReply);
  Len := GetWord(Data, Offset);
  if Len > PcccStringChars then
    Exit(res_PcccReply);
  SetLength(S, Len);
  for I := 0 to Len - 1 do
    S[I + 1] := Chr(Data[Offset + 2 + (I xor 1)]);
  Result := res_Ok;
end;

{- ---------------------------------------------------------------- reply }

function PcccCheckReply(const Rep: tRecRecord; RepLen: Word; Expect: Word; out Err: ShortString): tChResult;
begin
  Err := '';
  if RepLen < cSizeHead then
  begin
    Err := 'reply shorter than its header';
    Exit(res_PcccReply);
  end;
  if Rep.Sts <> sts_Ok then
  begin
    Err := PcccStatusText(Rep.Sts, Rep.Data[0], RepLen > cSizeHead);
    Exit(res_PcccStatus);
  end;
  if RepLen - cSizeHead <> Expect then
  begin
    Err := Format('reply has %d data bytes, %d expected', [RepLen - cSizeHead, Expect]);
    Exit(res_PcccReply);
  end;
  Result := res_Ok;
end;

initialization
  ChRegisterResultText(PcccLayer, res_PcccCount, 'count does not fit');
  ChRegisterResultText(PcccLayer, res_PcccValue, 'value out of range for the element');
  ChRegisterResultText(PcccLayer, res_PcccReply, 'reply does not match the request');
  ChRegisterResultText(PcccLayer, res_PcccStatus, 'error reply from the PLC');
  ChRegisterResultText(PcccLayer, res_PcccNak, 'command refused (NAK) on every try');
  ChRegisterResultText(PcccLayer, res_PcccUsage, 'wrong kind of value for the address');
end.
