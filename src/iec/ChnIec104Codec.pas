{ ChnIec104Codec - the APCI of IEC 60870-5-104 (clause 5): bytes <-> APDUs.
  Pure: no objects, no I/O; the layer ChnIec104 drives it, chndecode and
  the fuzzer call it directly.

  An APDU is the start octet 68h, the length of the APDU (the four octets
  of the control field plus the ASDU: 4..253) and the control field:
    I format  octet 1 bit 0 = 0: N(S) = octets 1..2 shr 1, N(R) = octets
              3..4 shr 1 (octet 3 bit 0 = 0), an ASDU follows;
    S format  octet 1 = 01h, octet 2 = 0: N(R) as in I, no ASDU;
    U format  octet 1 = 03h + exactly one function bit (STARTDT act 04h,
              con 08h, STOPDT act 10h, con 20h, TESTFR act 40h, con 80h),
              octets 2..4 = 0, no ASDU.
  Sequence numbers count modulo 32768 (15 bits).

  Apci104Feed hunts for the start octet and collects one APDU; a wrong
  start octet or length is reported at once (the connection is closed
  then: the stream has lost its framing and 104 has no way to find it
  again). Apci104Decode checks the control field of a whole APDU. }
unit ChnIec104Codec;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  Apci104Start   = $68;
  Apci104MinLen  = 4;             {< the length octet: control field only }
  Apci104MaxLen  = 253;
  Apci104MaxAsdu = Apci104MaxLen - 4;   {< 249 }
  Apci104MaxApdu = Apci104MaxLen + 2;   {< 255 octets on the wire }
  Apci104SeqMod  = 32768;

  { U format functions (octet 1) }
  U104StartDtAct = $07;
  U104StartDtCon = $0B;
  U104StopDtAct  = $13;
  U104StopDtCon  = $23;
  U104TestFrAct  = $43;
  U104TestFrCon  = $83;

  {- result codes of the codec (and of NAM=IEC104) }
  res_ApciStart   = res_Proto + 0;   {< an octet other than 68h where an APDU starts }
  res_ApciLength  = res_Proto + 1;   {< length below 4 or above 253, or wrong for the format }
  res_ApciControl = res_Proto + 2;   {< control field of no format (U with 0 or 2 functions ...) }
  res_ApciSeq     = res_Proto + 3;   {< N(S) or N(R) the standard does not allow }
  res_ApciNotStarted = res_Proto + 4; {< an I frame while data transfer is stopped }
  res_ApciTimeout = res_Proto + 5;   {< t1 ran out: no acknowledgement }

type
  tApci104Format = (af104I, af104S, af104U);

  { The control field of one APDU, decoded. }
  tApci104 = record
    Format : tApci104Format;
    Ns, Nr : Word;        {< I: both, S: Nr }
    UFunc  : Byte;        {< U: octet 1 (U104StartDtAct ...) }
  end;

  tApci104FeedEvent = (fe104None, fe104Apdu, fe104Error);

  { The receive automaton: Buf[0 .. Pos - 1] collected so far. }
  tApci104Feed = record
    Buf  : array[0..Apci104MaxApdu - 1] of Byte;
    Pos  : Word;
    Error: tChResult;     {< fe104Error: res_ApciStart or res_ApciLength }
    Bad  : Byte;          {< ... and the octet at fault }
  end;

procedure Apci104FeedReset(var F: tApci104Feed);
{ One received octet: fe104Apdu when F.Buf[0 .. F.Pos - 1] holds a whole
  APDU (call Apci104FeedReset before the next), fe104Error for a wrong
  start or length octet. }
function Apci104Feed(var F: tApci104Feed; B: Byte): tApci104FeedEvent;
{ The control field of the APDU Buf[0 .. Len - 1] (start and length
  octets included). res_ApciControl (U with no or several functions, S
  with octet 2 <> 0, octet 3 bit 0 set), res_ApciLength (S or U with an
  ASDU, I without one); Err says what is wrong. }
function Apci104Decode(const Buf: array of Byte; Len: Word; out A: tApci104;
  out Err: ShortString): tChResult;
{ An I frame around Asdu (1..249 octets) into Out (Len + 6 octets). }
function Apci104EncodeI(Ns, Nr: Word; const Asdu: array of Byte; AsduLen: Word;
  var Out: array of Byte; out OutLen: Word): tChResult;
{ An S frame (6 octets). }
procedure Apci104EncodeS(Nr: Word; var Out: array of Byte; out OutLen: Word);
{ A U frame (6 octets); Func one of U104StartDtAct .. U104TestFrCon. }
procedure Apci104EncodeU(Func: Byte; var Out: array of Byte; out OutLen: Word);
{ 'STARTDT act', 'TESTFR con' ...; '' for no single function. }
function Apci104UName(Func: Byte): ShortString;
{ The con of a U act (STARTDT act -> STARTDT con ...). }
function Apci104ConOf(Act: Byte): Byte;
{ (A - B) mod 32768: how far sequence number A is ahead of B. }
function Seq104Diff(A, B: Word): Word;
{ One line for a trace or chndecode: 'I N(S)=3 N(R)=5', 'S N(R)=5',
  'U STARTDT act'. }
function Apci104Text(const A: tApci104): ShortString;

implementation

uses
  SysUtils;

procedure Apci104FeedReset(var F: tApci104Feed);
begin
  F.Pos := 0;
  F.Error := res_Ok;
  F.Bad := 0;
end;

function Apci104Feed(var F: tApci104Feed; B: Byte): tApci104FeedEvent;
begin
  Result := fe104None;
  if (F.Pos = 0) and (B <> Apci104Start) then
  begin
    F.Error := res_ApciStart;
    F.Bad := B;
    Exit(fe104Error);
  end;
  if (F.Pos = 1) and ((B < Apci104MinLen) or (B > Apci104MaxLen)) then
  begin
    F.Error := res_ApciLength;
    F.Bad := B;
    Exit(fe104Error);
  end;
  F.Buf[F.Pos] := B;
  Inc(F.Pos);
  if (F.Pos >= 2) and (F.Pos = F.Buf[1] + 2) then
    Result := fe104Apdu;
end;

function Seq104Diff(A, B: Word): Word;
begin
  Result := (LongInt(A) - LongInt(B) + Apci104SeqMod) mod Apci104SeqMod;
end;

function Apci104ConOf(Act: Byte): Byte;
begin
  Result := ((Act and $FC) shl 1) or 3;
end;

function Apci104UName(Func: Byte): ShortString;
begin
  case Func of
    U104StartDtAct: Result := 'STARTDT act';
    U104StartDtCon: Result := 'STARTDT con';
    U104StopDtAct : Result := 'STOPDT act';
    U104StopDtCon : Result := 'STOPDT con';
    U104TestFrAct : Result := 'TESTFR act';
    U104TestFrCon : Result := 'TESTFR con';
  else
    Result := '';
  end;
end;

function Apci104Decode(const Buf: array of Byte; Len: Word; out A: tApci104;
  out Err: ShortString): tChResult;
var
  C1, C2, C3, C4: Byte;
begin
  FillChar(A, SizeOf(A), 0);
  Err := '';
  if (Len < 6) or (Len > High(Buf) + 1) or (Buf[0] <> Apci104Start) or (Buf[1] + 2 <> Len) then
  begin
    Err := 'APDU of ' + IntToStr(Len) + ' octets';
    Exit(res_ApciLength);
  end;
  C1 := Buf[2];
  C2 := Buf[3];
  C3 := Buf[4];
  C4 := Buf[5];
  Result := res_Ok;
  if C1 and 1 = 0 then
  begin
    A.Format := af104I;
    A.Ns := (C1 shr 1) or (Word(C2) shl 7);
    A.Nr := (C3 shr 1) or (Word(C4) shl 7);
    if C3 and 1 <> 0 then
    begin
      Err := 'I format with bit 0 of control octet 3 set';
      Result := res_ApciControl;
    end
    else if Len = 6 then
    begin
      Err := 'I format without an ASDU';
      Result := res_ApciLength;
    end;
  end
  else if C1 = $01 then
  begin
    A.Format := af104S;
    A.Nr := (C3 shr 1) or (Word(C4) shl 7);
    if (C2 <> 0) or (C3 and 1 <> 0) then
    begin
      Err := 'S format with control octets ' + IntToHex(C2, 2) + ' ' + IntToHex(C3, 2);
      Result := res_ApciControl;
    end
    else if Len <> 6 then
    begin
      Err := 'S format with ' + IntToStr(Len - 6) + ' octets after the control field';
      Result := res_ApciLength;
    end;
  end
  else
  begin
    A.Format := af104U;
    A.UFunc := C1;
    if (C1 and 3 <> 3) or (Apci104UName(C1) = '') or (C2 <> 0) or (C3 <> 0) or (C4 <> 0) then
    begin
      Err := 'control field ' + IntToHex(C1, 2) + ' ' + IntToHex(C2, 2) + ' ' +
        IntToHex(C3, 2) + ' ' + IntToHex(C4, 2) + ' (U format needs exactly one function)';
      Result := res_ApciControl;
    end
    else if Len <> 6 then
    begin
      Err := 'U format with ' + IntToStr(Len - 6) + ' octets after the control field';
      Result := res_ApciLength;
    end;
  end;
end;

procedure PutHead(var Out: array of Byte; L, C1, C2, C3, C4: Byte);
begin
  Out[0] := Apci104Start;
  Out[1] := L;
  Out[2] := C1;
  Out[3] := C2;
  Out[4] := C3;
  Out[5] := C4;
end;

function Apci104EncodeI(Ns, Nr: Word; const Asdu: array of Byte; AsduLen: Word;
  var Out: array of Byte; out OutLen: Word): tChResult;
begin
  OutLen := 0;
  if (AsduLen = 0) or (AsduLen > Apci104MaxAsdu) or (AsduLen > High(Asdu) + 1) then
    Exit(res_BadLen);
  if AsduLen + 6 > High(Out) + 1 then
    Exit(res_TooLong);
  Ns := Ns mod Apci104SeqMod;
  Nr := Nr mod Apci104SeqMod;
  PutHead(Out, AsduLen + 4, (Ns shl 1) and $FF, Ns shr 7, (Nr shl 1) and $FF, Nr shr 7);
  Move(Asdu[0], Out[6], AsduLen);
  OutLen := AsduLen + 6;
  Result := res_Ok;
end;

procedure Apci104EncodeS(Nr: Word; var Out: array of Byte; out OutLen: Word);
begin
  Nr := Nr mod Apci104SeqMod;
  PutHead(Out, 4, $01, 0, (Nr shl 1) and $FF, Nr shr 7);
  OutLen := 6;
end;

procedure Apci104EncodeU(Func: Byte; var Out: array of Byte; out OutLen: Word);
begin
  PutHead(Out, 4, Func, 0, 0, 0);
  OutLen := 6;
end;

function Apci104Text(const A: tApci104): ShortString;
begin
  case A.Format of
    af104I: Result := 'I N(S)=' + IntToStr(A.Ns) + ' N(R)=' + IntToStr(A.Nr);
    af104S: Result := 'S N(R)=' + IntToStr(A.Nr);
  else
    Result := 'U ' + Apci104UName(A.UFunc);
  end;
end;

end.
