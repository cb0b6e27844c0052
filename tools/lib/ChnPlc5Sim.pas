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

function Plc5SimHandle(var T: tSlcTable; Fnc: Byte; constref Req: tRecRecord; DataLen: LongInt;
  var Rep: tSendRecord; var N: LongInt): Boolean;
var
  P, Start, K: LongInt;
  Offset, Size, Unit_, Bytes, At, ES: LongInt;
  Levels: array[0..3] of LongInt;
  HasSub: Boolean;
  F: ^tSlcFile;
  TypeId, TSize, ElemType, ElemSize: Word;
  W, AndM, OrM: Word;
  Scratch: array[0..5] of Byte;

  function Fail(Sts, Ext: Byte): Boolean;
  begin
    SlcSetSts(Rep, N, Sts, Ext);
    Result := True;
  end;

  { the address at P: F, Levels, HasSub; False after refusing it }
  function TakeAddress: Boolean;
  var
    Mask: Byte;
  begin
    Result := False;
    if P >= DataLen then
      Exit(not Fail(sts_IllegalCmd, 0));
    Mask := Req.Data[P];
    if Mask and $F0 <> 0 then
      Exit(not Fail(sts_ExtSts, ext_ManyLevels));
    if Mask and $0C = 0 then
      Exit(not Fail(sts_ExtSts, ext_FewLevels));   { no element level }
    if not Plc5TakeAddress(Req.Data, DataLen, P, Levels) then
      Exit(not Fail(sts_IllegalCmd, 0));
    HasSub := Mask and $08 <> 0;
    if (Levels[0] <> 0) or (Levels[1] > 255) then
      Exit(not Fail(sts_ExtSts, ext_NotUsable));
    F := @T.Files[Levels[1]];
    if (F^.FType = 0) or (Levels[2] >= F^.Elems) or
       (Levels[3] > 0) and not (F^.FType in [pft_Timer, pft_Counter, pft_Control]) or
       (Levels[3] > 2) then
      Exit(not Fail(sts_ExtSts, ext_NotUsable));
    Result := True;
  end;

  function TakeWord(out V: LongInt): Boolean;
  begin
    Result := P + 1 < DataLen;
    V := 0;
    if Result then
    begin
      V := Req.Data[P] or (Req.Data[P + 1] shl 8);
      Inc(P, 2);
    end;
  end;

begin
  Result := Fnc in [$68, $67, $01, $00, $26];
  if not Result then
    Exit;
  N := 0;
  P := 0;
  if Fnc = $26 then
  begin
    { read-modify-write: as many (address, AND, OR) as the command holds }
    repeat
      if not TakeAddress then
        Exit;
      if (P + 4 > DataLen) or (PcccElemSize(F^.FType) mod 2 <> 0) or
         (F^.FType in [pft_Float, pft_Long, pft_String]) then
      begin
        Fail(sts_ExtSts, ext_BadType);
        Exit;
      end;
      At := Levels[2] * PcccElemSize(F^.FType) + Levels[3] * 2;
      AndM := Req.Data[P] or (Req.Data[P + 1] shl 8);
      OrM := Req.Data[P + 2] or (Req.Data[P + 3] shl 8);
      Inc(P, 4);
      W := F^.Data[At] or (F^.Data[At + 1] shl 8);
      W := (W and AndM) or OrM;
      F^.Data[At] := Lo(W);
      F^.Data[At + 1] := Hi(W);
    until P >= DataLen;
    Exit;
  end;
  if not TakeWord(Offset) or not TakeWord(Size) then   { Size: TOTAL TRANS, unused }
  begin
    Fail(sts_IllegalCmd, 0);
    Exit;
  end;
  if not TakeAddress then
    Exit;
  ES := PcccElemSize(F^.FType);
  At := Levels[2] * ES + Levels[3] * 2;
  case Fnc of
    $01, $00:
      begin
        At := At + 2 * Offset;
        if Fnc = $01 then
        begin
          if P + 1 <> DataLen then
          begin
            Fail(sts_IllegalCmd, 0);
            Exit;
          end;
          Bytes := Req.Data[P];
        end
        else
          Bytes := DataLen - P;
        if (Bytes = 0) or Odd(Bytes) or (Bytes > MaxDataLen) then
        begin
          Fail(sts_IllegalCmd, 0);
          Exit;
        end;
        if At + Bytes > Length(F^.Data) then
        begin
          Fail(sts_ExtSts, ext_WrongSize);
          Exit;
        end;
        if Fnc = $01 then
        begin
          Move(F^.Data[At], Rep.Data[0], Bytes);
          N := Bytes;
        end
        else
          Move(Req.Data[P], F^.Data[At], Bytes);
      end;
    $68:
      begin
        if not TakeWord(Size) or (P <> DataLen) or (Size = 0) then
        begin
          Fail(sts_IllegalCmd, 0);
          Exit;
        end;
        if F^.FType = pft_String then
        begin
          Fail(sts_ExtSts, ext_BadType);
          Exit;
        end;
        Unit_ := ES;
        if HasSub then
          Unit_ := 2;
        At := At + Offset * Unit_;
        Bytes := Size * Unit_;
        if Bytes > MaxDataLen - 6 then
        begin
          Fail(sts_ExtSts, ext_TooLarge);
          Exit;
        end;
        if At + Bytes > Length(F^.Data) then
        begin
          Fail(sts_ExtSts, ext_WrongSize);
          Exit;
        end;
        { 9x 09 [size] element-parameter, then the data }
        K := 0;
        ElemType := FileElemType(F^.FType, HasSub);
        Plc5PutTypeParam(ElemType, Unit_, Scratch, K);   { the array's size counts it }
        N := 0;
        Plc5PutTypeParam(p5t_Array, K + Bytes, Rep.Data, N);
        Plc5PutTypeParam(ElemType, Unit_, Rep.Data, N);
        Move(F^.Data[At], Rep.Data[N], Bytes);
        Inc(N, Bytes);
      end;
    $67:
      begin
        if not Plc5TakeTypeParam(Req.Data, DataLen, P, TypeId, TSize) then
        begin
          Fail(sts_IllegalCmd, 0);
          Exit;
        end;
        ElemType := TypeId;
        ElemSize := TSize;
        if TypeId = p5t_Array then
        begin
          Start := P;
          if not Plc5TakeTypeParam(Req.Data, DataLen, P, ElemType, ElemSize) or
             (TSize <> DataLen - Start) then
          begin
            Fail(sts_IllegalCmd, 0);
            Exit;
          end;
        end;
        Unit_ := ES;
        if HasSub then
          Unit_ := 2;
        Bytes := DataLen - P;
        if (F^.FType = pft_String) or (ElemType <> FileElemType(F^.FType, HasSub)) or
           (ElemSize <> Unit_) then
        begin
          Fail(sts_ExtSts, ext_BadType);
          Exit;
        end;
        if (Bytes = 0) or (Bytes mod Unit_ <> 0) or (TypeId <> p5t_Array) and (Bytes <> TSize) then
        begin
          Fail(sts_IllegalCmd, 0);
          Exit;
        end;
        At := At + Offset * Unit_;
        if At + Bytes > Length(F^.Data) then
        begin
          Fail(sts_ExtSts, ext_WrongSize);
          Exit;
        end;
        Move(Req.Data[P], F^.Data[At], Bytes);
      end;
  end;
end;

end.
