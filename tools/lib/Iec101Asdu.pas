{ Iec101Asdu - just enough of the IEC 60870-5-101 application layer for
  the FT 1.2 examples: build a measured value, mirror a command as its
  confirmation, describe any ASDU as one line of text.

  Fixed parameters, those of lib60870 and of most IEC 101 stations:
  type identification 1 octet, variable structure qualifier 1, cause of
  transmission 2 (cause, originator address), common address 2,
  information object address 3 (all little-endian):
    TI VSQ COT OA CA CA IOA IOA IOA element...
  Not a library unit: the Chn library ends at the link layer. }
unit Iec101Asdu;

{$MODE OBJFPC}{$H-}

interface

const
  AsduHeadLen = 6;          { TI VSQ COT OA CA(2) }
  AsduIoaLen  = 3;

  { type identifications used by the examples }
  M_ME_NB_1 = 11;           { measured value, scaled }
  C_SC_NA_1 = 45;           { single command }
  C_IC_NA_1 = 100;          { (general) interrogation command }
  C_CS_NA_1 = 103;          { clock synchronisation command }

  { causes of transmission }
  CotPeriodic   = 1;
  CotSpontaneous = 3;
  CotActivation = 6;
  CotActCon     = 7;
  CotActTerm    = 10;
  CotInterrogated = 20;     { interrogated by station interrogation }

{ A measured value, scaled (M_ME_NB_1), one object, into Buf (at least 12
  octets); returns its length (12). }
function AsduMeasuredScaled(Buf: PByte; Cot: Byte; CA: Word; Ioa: LongInt;
  Value: SmallInt): Word;
{ A station interrogation (C_IC_NA_1, activation, QOI 20) into Buf (at
  least 10 octets); returns its length (10). }
function AsduInterrogation(Buf: PByte; CA: Word): Word;
{ Copy Src (Len octets) to Dest with cause of transmission Cot (the P/N
  and test bits are kept): an activation mirrored as ACT_CON or ACT_TERM. }
procedure AsduMirror(Src, Dest: PByte; Len: Word; Cot: Byte);
{ 'C_IC_NA_1 (100) COT 6 CA 1: IOA 0 = 14' style text; a short or unknown
  ASDU gives its octets in hex. }
function AsduText(Buf: PByte; Len: Word): ShortString;

implementation

uses
  SysUtils;

function AsduMeasuredScaled(Buf: PByte; Cot: Byte; CA: Word; Ioa: LongInt;
  Value: SmallInt): Word;
begin
  Buf[0] := M_ME_NB_1;
  Buf[1] := 1;                      { one object, not a sequence }
  Buf[2] := Cot;
  Buf[3] := 0;                      { originator address }
  Buf[4] := Lo(CA);
  Buf[5] := Hi(CA);
  Buf[6] := Ioa and $FF;
  Buf[7] := (Ioa shr 8) and $FF;
  Buf[8] := (Ioa shr 16) and $FF;
  Buf[9] := Lo(Word(Value));
  Buf[10] := Hi(Word(Value));
  Buf[11] := 0;                     { quality descriptor: good }
  Result := 12;
end;

function AsduInterrogation(Buf: PByte; CA: Word): Word;
begin
  FillChar(Buf^, 10, 0);
  Buf[0] := C_IC_NA_1;
  Buf[1] := 1;
  Buf[2] := CotActivation;
  Buf[4] := Lo(CA);
  Buf[5] := Hi(CA);
  Buf[9] := 20;                     { QOI: station interrogation }
  Result := 10;
end;

procedure AsduMirror(Src, Dest: PByte; Len: Word; Cot: Byte);
begin
  Move(Src^, Dest^, Len);
  if Len > 2 then
    Dest[2] := (Src[2] and $C0) or (Cot and $3F);
end;

function TypeName(T: Byte): string;
begin
  case T of
    1: Result := 'M_SP_NA_1';
    3: Result := 'M_DP_NA_1';
    9: Result := 'M_ME_NA_1';
    M_ME_NB_1: Result := 'M_ME_NB_1';
    13: Result := 'M_ME_NC_1';
    30: Result := 'M_SP_TB_1';
    35: Result := 'M_ME_TE_1';
    C_SC_NA_1: Result := 'C_SC_NA_1';
    46: Result := 'C_DC_NA_1';
    70: Result := 'M_EI_NA_1';
    C_IC_NA_1: Result := 'C_IC_NA_1';
    C_CS_NA_1: Result := 'C_CS_NA_1';
  else
    Result := 'type';
  end;
end;

function HexOf(Buf: PByte; Len: Word): string;
var
  I: Integer;
begin
  Result := '';
  for I := 0 to Len - 1 do
  begin
    if I > 0 then
      Result := Result + ' ';
    Result := Result + IntToHex(Buf[I], 2);
  end;
end;

function AsduText(Buf: PByte; Len: Word): ShortString;
var
  Ioa: LongInt;
  S: string;
begin
  if Len < AsduHeadLen + AsduIoaLen then
    Exit('short ASDU: ' + HexOf(Buf, Len));
  S := Format('%s (%d) COT %d CA %d', [TypeName(Buf[0]), Buf[0], Buf[2] and $3F,
    Buf[4] or (Buf[5] shl 8)]);
  if Buf[2] and $40 <> 0 then
    S := S + ' negative';
  Ioa := Buf[6] or (Buf[7] shl 8) or (LongInt(Buf[8]) shl 16);
  if (Buf[0] = M_ME_NB_1) and (Buf[1] = 1) and (Len = 12) then
    S := S + Format(': IOA %d = %d', [Ioa, SmallInt(Buf[9] or (Buf[10] shl 8))])
  else if (Buf[0] in [C_SC_NA_1, C_IC_NA_1]) and (Len = 10) then
    S := S + Format(': IOA %d = %d', [Ioa, Buf[9]])
  else
    S := S + Format(', %d objects: %s', [Buf[1] and $7F,
      HexOf(@Buf[AsduHeadLen], Len - AsduHeadLen)]);
  Result := S;
end;

end.
