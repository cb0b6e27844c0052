{ ChnPlc5Sim - the PLC-5 commands of tools/df1sim (--plc5), answered from
  the data table of unit ChnSlc. Pure: a request record in, a reply out.

  Commands (Rockwell publication 1770-6.5.16, chapter 7; the address and
  type/data parameter as unit ChnPlc5 writes them):
    CMD 0F FNC 68  typed read   PACKET OFFSET(2) TOTAL(2) address SIZE(2)
                   -> 9x 09 [size] element-parameter data
    CMD 0F FNC 67  typed write  PACKET OFFSET(2) TOTAL(2) address
                   type/data parameter (an array, or one element) data
    CMD 0F FNC 01  word range read  PACKET OFFSET(2) TOTAL(2) address SIZE(1)
    CMD 0F FNC 00  word range write PACKET OFFSET(2) TOTAL(2) address data
    CMD 0F FNC 26  read-modify-write (address AND(2) OR(2))...
  PACKET OFFSET counts elements (typed) or words (word range) from the
  address. The element type: 4 integer for O I S B N A and for a T/C/R
  word, 16 BCD for D, 8 float for F, 5 6 7 whole timers, counters,
  controls; ST only by word range. A typed write must send the file's type.
  Refusals (STS $F0 and EXT STS, 1770-6.5.16 chapter 8):
    STS $10          fields cut short or left over, SIZE 0 or odd (word range)
    EXT $02 / $03    the address names fewer than file and element / more
                     than four levels
    EXT $06          level 1 not 0 (the data table), no such file (df1sim
                     holds files 0..255), an element past the end, a
                     sub-element other than 0 (0..2 in T, C, R)
    EXT $07          the transfer runs past the end of the file
    EXT $09          more than a frame holds
    EXT $11          a typed read of an ST file, a typed write of another type }
unit ChnPlc5Sim;

{$I chn.inc}

interface

uses
  ChnDF1Codec, ChnSlc;

{ Answer CMD 0F with FNC 68, 67, 01, 00 or 26 (DataLen bytes of Req.Data)
  into Rep (its STS and, on error, EXT STS); N the reply's data bytes.
  False when Fnc is none of them. }
function Plc5SimHandle(var T: tSlcTable; Fnc: Byte; constref Req: tRecRecord; DataLen: LongInt;
  var Rep: tSendRecord; var N: LongInt): Boolean;

implementation

uses
  ChnPcccNames, ChnPccc, ChnPlc5;

const
  ext_FewLevels  = $02;
  ext_ManyLevels = $03;
  ext_TooLarge   = $09;
  ext_BadType    = $11;

{ The element type a file's data travel as. }
function FileElemType(FType: Byte; Sub: Boolean): Byte;
var
  A: tPcccAddr;
begin
  FillChar(A, SizeOf(A), 0);
  A.FileType := FType;
  A.HasSub := Sub;
  Result := Plc5ElemType(A);
end;

type
  { One request being answered: where it is read (P) and what its
    address named (F, Levels, HasSub). }
  tPlc5Job = record
    T: ^tSlcTable;
    Req: ^tRecRecord;
    DataLen, P: LongInt;
    Rep: ^tSendRecord;
    N: LongInt;
    Levels: array[0..3] of LongInt;
    HasSub: Boolean;
    F: ^tSlcFile;
  end;

{ Refuse the request: STS (and EXT STS) into the reply. Always False, so a
  step can say Exit(Fail(..)). }
function Fail(var J: tPlc5Job; Sts, Ext: Byte): Boolean;
begin
  SlcSetSts(J.Rep^, J.N, Sts, Ext);
  Result := False;
end;

{ The address at J.P: F, Levels, HasSub; False after refusing it. }
function TakeAddress(var J: tPlc5Job): Boolean;
var
  Mask: Byte;
begin
  if J.P >= J.DataLen then
    Exit(Fail(J, sts_IllegalCmd, 0));
  Mask := J.Req^.Data[J.P];
  if Mask and $F0 <> 0 then
    Exit(Fail(J, sts_ExtSts, ext_ManyLevels));
  if Mask and $0C = 0 then
    Exit(Fail(J, sts_ExtSts, ext_FewLevels));   { no element level }
  if not Plc5TakeAddress(J.Req^.Data, J.DataLen, J.P, J.Levels) then
    Exit(Fail(J, sts_IllegalCmd, 0));
  J.HasSub := Mask and $08 <> 0;
  if (J.Levels[0] <> 0) or (J.Levels[1] > 255) then
    Exit(Fail(J, sts_ExtSts, ext_NotUsable));
  J.F := @J.T^.Files[J.Levels[1]];
  if (J.F^.FType = 0) or (J.Levels[2] >= J.F^.Elems) or
     (J.Levels[3] > 0) and not (J.F^.FType in [pft_Timer, pft_Counter, pft_Control]) or
     (J.Levels[3] > 2) then
    Exit(Fail(J, sts_ExtSts, ext_NotUsable));
  Result := True;
end;

function TakeWord(var J: tPlc5Job; out V: LongInt): Boolean;
begin
  Result := J.P + 1 < J.DataLen;
  V := 0;
  if Result then
  begin
    V := J.Req^.Data[J.P] or (J.Req^.Data[J.P + 1] shl 8);
    Inc(J.P, 2);
  end;
end;

{ The byte offset in the file of the address taken. }
function AddressAt(const J: tPlc5Job): LongInt;
begin
  Result := J.Levels[2] * PcccElemSize(J.F^.FType) + J.Levels[3] * 2;
end;

{ The size of one element as a typed command moves it: a word for a
  sub-element, else the file's element. }
function TypedUnit(const J: tPlc5Job): LongInt;
begin
  if J.HasSub then
    Result := 2
  else
    Result := PcccElemSize(J.F^.FType);
end;

{ True, the request refused, when Bytes from the file's byte At run past
  its end. }
function PastEnd(var J: tPlc5Job; At, Bytes: LongInt): Boolean;
begin
  Result := At + Bytes > Length(J.F^.Data);
  if Result then
    Fail(J, sts_ExtSts, ext_WrongSize);
end;

{ FNC 26: as many (address, AND, OR) as the command holds. }
procedure ReadModifyWrite(var J: tPlc5Job);
var
  At: LongInt;
  W, AndM, OrM: Word;
begin
  repeat
    if not TakeAddress(J) then
      Exit;
    if (J.P + 4 > J.DataLen) or (PcccElemSize(J.F^.FType) mod 2 <> 0) or
       (J.F^.FType in [pft_Float, pft_Long, pft_String]) then
    begin
      Fail(J, sts_ExtSts, ext_BadType);
      Exit;
    end;
    At := AddressAt(J);
    AndM := J.Req^.Data[J.P] or (J.Req^.Data[J.P + 1] shl 8);
    OrM := J.Req^.Data[J.P + 2] or (J.Req^.Data[J.P + 3] shl 8);
    Inc(J.P, 4);
    W := J.F^.Data[At] or (J.F^.Data[At + 1] shl 8);
    W := (W and AndM) or OrM;
    J.F^.Data[At] := Lo(W);
    J.F^.Data[At + 1] := Hi(W);
  until J.P >= J.DataLen;
end;

{ FNC 01 (read) and 00 (write): words from PACKET OFFSET words on. }
procedure WordRange(var J: tPlc5Job; Fnc: Byte; Offset: LongInt);
var
  At, Bytes: LongInt;
begin
  At := AddressAt(J) + 2 * Offset;
  if Fnc = $01 then
  begin
    if J.P + 1 <> J.DataLen then
    begin
      Fail(J, sts_IllegalCmd, 0);
      Exit;
    end;
    Bytes := J.Req^.Data[J.P];
  end
  else
    Bytes := J.DataLen - J.P;
  if (Bytes = 0) or Odd(Bytes) or (Bytes > MaxDataLen) then
  begin
    Fail(J, sts_IllegalCmd, 0);
    Exit;
  end;
  if PastEnd(J, At, Bytes) then
    Exit;
  if Fnc = $01 then
  begin
    Move(J.F^.Data[At], J.Rep^.Data[0], Bytes);
    J.N := Bytes;
  end
  else
    Move(J.Req^.Data[J.P], J.F^.Data[At], Bytes);
end;

{ FNC 68: SIZE elements from PACKET OFFSET elements on, behind their
  type/data parameter. }
procedure TypedRead(var J: tPlc5Job; Offset: LongInt);
var
  At, Size, Unit_, Bytes, K: LongInt;
  ElemType: Word;
  Scratch: array[0..5] of Byte;
begin
  if not TakeWord(J, Size) or (J.P <> J.DataLen) or (Size = 0) then
  begin
    Fail(J, sts_IllegalCmd, 0);
    Exit;
  end;
  if J.F^.FType = pft_String then
  begin
    Fail(J, sts_ExtSts, ext_BadType);
    Exit;
  end;
  Unit_ := TypedUnit(J);
  At := AddressAt(J) + Offset * Unit_;
  Bytes := Size * Unit_;
  if Bytes > MaxDataLen - 6 then
  begin
    Fail(J, sts_ExtSts, ext_TooLarge);
    Exit;
  end;
  if PastEnd(J, At, Bytes) then
    Exit;
  { 9x 09 [size] element-parameter, then the data }
  K := 0;
  ElemType := FileElemType(J.F^.FType, J.HasSub);
  Plc5PutTypeParam(ElemType, Unit_, Scratch, K);   { the array's size counts it }
  J.N := 0;
  Plc5PutTypeParam(p5t_Array, K + Bytes, J.Rep^.Data, J.N);
  Plc5PutTypeParam(ElemType, Unit_, J.Rep^.Data, J.N);
  Move(J.F^.Data[At], J.Rep^.Data[J.N], Bytes);
  Inc(J.N, Bytes);
end;

{ FNC 67: an array, or one element, of the file's own type from PACKET
  OFFSET elements on. }
procedure TypedWrite(var J: tPlc5Job; Offset: LongInt);
var
  Start, At, Unit_, Bytes: LongInt;
  TypeId, TSize, ElemType, ElemSize: Word;
begin
  if not Plc5TakeTypeParam(J.Req^.Data, J.DataLen, J.P, TypeId, TSize) then
  begin
    Fail(J, sts_IllegalCmd, 0);
    Exit;
  end;
  ElemType := TypeId;
  ElemSize := TSize;
  if TypeId = p5t_Array then
  begin
    Start := J.P;
    if not Plc5TakeTypeParam(J.Req^.Data, J.DataLen, J.P, ElemType, ElemSize) or
       (TSize <> J.DataLen - Start) then
    begin
      Fail(J, sts_IllegalCmd, 0);
      Exit;
    end;
  end;
  Unit_ := TypedUnit(J);
  Bytes := J.DataLen - J.P;
  if (J.F^.FType = pft_String) or (ElemType <> FileElemType(J.F^.FType, J.HasSub)) or
     (ElemSize <> Unit_) then
  begin
    Fail(J, sts_ExtSts, ext_BadType);
    Exit;
  end;
  if (Bytes = 0) or (Bytes mod Unit_ <> 0) or (TypeId <> p5t_Array) and (Bytes <> TSize) then
  begin
    Fail(J, sts_IllegalCmd, 0);
    Exit;
  end;
  At := AddressAt(J) + Offset * Unit_;
  if PastEnd(J, At, Bytes) then
    Exit;
  Move(J.Req^.Data[J.P], J.F^.Data[At], Bytes);
end;

function Plc5SimHandle(var T: tSlcTable; Fnc: Byte; constref Req: tRecRecord; DataLen: LongInt;
  var Rep: tSendRecord; var N: LongInt): Boolean;
var
  J: tPlc5Job;
  Offset, Total: LongInt;
begin
  Result := Fnc in [$68, $67, $01, $00, $26];
  if not Result then
    Exit;
  FillChar(J, SizeOf(J), 0);
  J.T := @T;
  J.Req := @Req;
  J.DataLen := DataLen;
  J.Rep := @Rep;
  if Fnc = $26 then
    ReadModifyWrite(J)
  else if not TakeWord(J, Offset) or not TakeWord(J, Total) then   { TOTAL TRANS: unused }
    Fail(J, sts_IllegalCmd, 0)
  else if TakeAddress(J) then
    case Fnc of
      $01, $00: WordRange(J, Fnc, Offset);
      $68: TypedRead(J, Offset);
      $67: TypedWrite(J, Offset);
    end;
  N := J.N;
end;

end.
