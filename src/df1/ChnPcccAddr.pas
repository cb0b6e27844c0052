{ ChnPcccAddr - the data table addresses of SLC 500 / MicroLogix and
  PLC-5 processors as text, without I/O: parse 'N7:0', 'F8:2', 'B3:1/4',
  'B3/20', 'T4:0.ACC', 'C5:0.DN', 'ST9:0', 'L10:3' (and a PLC-5's
  'I:012/05', octal I/O, and 'D10:0') into a tPcccAddr, print one back;
  the file types, their letters and element sizes, the sub-elements of
  timers, counters and controls.

  Address syntax, as the programming software writes it:
  FILE-LETTER[FILE-NUMBER]:ELEMENT[.SUB][/BIT], or
  FILE-LETTER[FILE-NUMBER]/BIT for a bit counted from the file's start.

  ChnPccc builds the requests on these addresses and gives the same names
  to programs that use it alone. A malformed address is res_PcccAddress
  (its text registered for the layer name PcccLayer) and a text naming
  the part that is wrong. }
unit ChnPcccAddr;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  PcccLayer = 'PCCC';   {< ChResultText(R, PcccLayer) }

  res_PcccAddress = res_Proto;       {< malformed or impossible address }

  { PCCC file type codes (1770-6.5.16, protected typed logical read) }
  pft_Status  = $84;
  pft_Bit     = $85;
  pft_Timer   = $86;
  pft_Counter = $87;
  pft_Control = $88;
  pft_Integer = $89;
  pft_Float   = $8A;
  pft_Output  = $8B;
  pft_Input   = $8C;
  pft_String  = $8D;
  pft_Ascii   = $8E;
  pft_Long    = $91;
  pft_Bcd     = $8F;   {< PLC-5 D files (unit ChnPlc5): a word of four BCD digits }

type
  { A parsed address. Sub is the word of a timer, counter or control element
    (0 control bits, 1 PRE/LEN, 2 ACC/POS) when HasSub; Bit -1 when none. }
  tPcccAddr = packed record
    FileType: Byte;      {< pft_* }
    FileNo  : Word;
    Elem    : Word;
    Sub     : Byte;
    HasSub  : Boolean;
    Bit     : ShortInt;
  end;

  tPcccValueKind = (pvInt, pvFloat, pvString);

  { whose address rules: SLC 500 / MicroLogix, or PLC-5 }
  tPcccDialect = (pdSlc, pdPlc5);


{ Parse an address (case and surrounding blanks ignored). res_Ok, or
  res_PcccAddress with Err naming the part that is wrong. }
function PcccParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
{ The same by the rules of a family: pdSlc (SLC 500 / MicroLogix: files
  up to 255, elements up to 65535, L files) or pdPlc5 (PLC-5, unit
  ChnPlc5: files 3..999, elements 0..999, O and I elements octal 0..277
  with octal bits 00..17, D files, no L). }
function PcccParseAddressAs(Dialect: tPcccDialect; const S: ShortString; out A: tPcccAddr;
  out Err: ShortString): tChResult;
{ The canonical text by a family's rules ('I:012/05' for a PLC-5). }
function PcccAddressTextAs(Dialect: tPcccDialect; const A: tPcccAddr): ShortString;
{ The canonical text of an address ('T4:0.ACC', 'B3:1/4'). }
function PcccAddressText(const A: tPcccAddr): ShortString;
{ The file letter(s) of a type code ('N', 'ST'); '' when unknown. }
function PcccFileLetter(FileType: Byte): ShortString;
{ Bytes of one element of a file type; 0 when unknown. }
function PcccElemSize(FileType: Byte): Word;
{ What kind of value an address reads and writes. }
function PcccValueKind(const A: tPcccAddr): tPcccValueKind;
{ The type code of file letter(s) ('N', 'ST', 'D'); 0 when unknown. Fixed
  is the file's only number (O 0, I 1, S 2), -1 for the others. }
function PcccFileByLetter(const Letters: ShortString; out Fixed: SmallInt): Byte;
{ The sub-element '.ACC', '.DN' ... of a T, C or R file: its word (Sub)
  and bit (-1: the whole word); False when the file has none of that name. }
function PcccFindSub(FileType: Byte; const Name: ShortString; out Sub: Byte; out Bit: ShortInt): Boolean;
{ The name of A's sub-element ('ACC', 'DN'); '' when none. }
function PcccSubName(const A: tPcccAddr): ShortString;
{ A timer, counter or control file (T, C, R): elements of three words
  with named sub-elements. }
function PcccHasSubs(FileType: Byte): Boolean;

implementation

uses
  SysUtils, uString;

type
  tFileInfo = record
    Letter: string[2];
    FType : Byte;
    Size  : Word;
    Fixed : SmallInt;   { the only file number allowed, -1: 3..255 }
  end;

const
  Files: array[0..12] of tFileInfo = (
    (Letter: 'O';  FType: pft_Output;  Size: 2;  Fixed: 0),
    (Letter: 'I';  FType: pft_Input;   Size: 2;  Fixed: 1),
    (Letter: 'S';  FType: pft_Status;  Size: 2;  Fixed: 2),
    (Letter: 'B';  FType: pft_Bit;     Size: 2;  Fixed: -1),
    (Letter: 'T';  FType: pft_Timer;   Size: 6;  Fixed: -1),
    (Letter: 'C';  FType: pft_Counter; Size: 6;  Fixed: -1),
    (Letter: 'R';  FType: pft_Control; Size: 6;  Fixed: -1),
    (Letter: 'N';  FType: pft_Integer; Size: 2;  Fixed: -1),
    (Letter: 'F';  FType: pft_Float;   Size: 4;  Fixed: -1),
    (Letter: 'ST'; FType: pft_String;  Size: 84; Fixed: -1),
    (Letter: 'A';  FType: pft_Ascii;   Size: 2;  Fixed: -1),
    (Letter: 'L';  FType: pft_Long;    Size: 4;  Fixed: -1),
    (Letter: 'D';  FType: pft_Bcd;     Size: 2;  Fixed: -1));

type
  tSubInfo = record
    Name : string[3];
    FType: Byte;
    Sub  : Byte;
    Bit  : ShortInt;
  end;

const
  { sub-elements: the word, and the bit of the control word }
  SubTable: array[0..22] of tSubInfo = (
    (Name: 'PRE'; FType: pft_Timer;   Sub: 1; Bit: -1),
    (Name: 'ACC'; FType: pft_Timer;   Sub: 2; Bit: -1),
    (Name: 'EN';  FType: pft_Timer;   Sub: 0; Bit: 15),
    (Name: 'TT';  FType: pft_Timer;   Sub: 0; Bit: 14),
    (Name: 'DN';  FType: pft_Timer;   Sub: 0; Bit: 13),
    (Name: 'PRE'; FType: pft_Counter; Sub: 1; Bit: -1),
    (Name: 'ACC'; FType: pft_Counter; Sub: 2; Bit: -1),
    (Name: 'CU';  FType: pft_Counter; Sub: 0; Bit: 15),
    (Name: 'CD';  FType: pft_Counter; Sub: 0; Bit: 14),
    (Name: 'DN';  FType: pft_Counter; Sub: 0; Bit: 13),
    (Name: 'OV';  FType: pft_Counter; Sub: 0; Bit: 12),
    (Name: 'UN';  FType: pft_Counter; Sub: 0; Bit: 11),
    (Name: 'UA';  FType: pft_Counter; Sub: 0; Bit: 10),
    (Name: 'LEN'; FType: pft_Control; Sub: 1; Bit: -1),
    (Name: 'POS'; FType: pft_Control; Sub: 2; Bit: -1),
    (Name: 'EN';  FType: pft_Control; Sub: 0; Bit: 15),
    (Name: 'EU';  FType: pft_Control; Sub: 0; Bit: 14),
    (Name: 'DN';  FType: pft_Control; Sub: 0; Bit: 13),
    (Name: 'EM';  FType: pft_Control; Sub: 0; Bit: 12),
    (Name: 'ER';  FType: pft_Control; Sub: 0; Bit: 11),
    (Name: 'UL';  FType: pft_Control; Sub: 0; Bit: 10),
    (Name: 'IN';  FType: pft_Control; Sub: 0; Bit: 9),
    (Name: 'FD';  FType: pft_Control; Sub: 0; Bit: 8));

function FileIndex(FileType: Byte): Integer;
var
  I: Integer;
begin
  for I := Low(Files) to High(Files) do
    if Files[I].FType = FileType then
      Exit(I);
  Result := -1;
end;

function PcccFileLetter(FileType: Byte): ShortString;
var
  I: Integer;
begin
  I := FileIndex(FileType);
  if I < 0 then
    Result := ''
  else
    Result := Files[I].Letter;
end;

function PcccElemSize(FileType: Byte): Word;
var
  I: Integer;
begin
  I := FileIndex(FileType);
  if I < 0 then
    Result := 0
  else
    Result := Files[I].Size;
end;

function IsWordFile(FileType: Byte): Boolean;
begin
  Result := PcccElemSize(FileType) = 2;
end;

function PcccHasSubs(FileType: Byte): Boolean;
begin
  Result := FileType in [pft_Timer, pft_Counter, pft_Control];
end;

function PcccValueKind(const A: tPcccAddr): tPcccValueKind;
begin
  if A.HasSub or (A.Bit >= 0) then
    Result := pvInt
  else if A.FileType = pft_Float then
    Result := pvFloat
  else if A.FileType = pft_String then
    Result := pvString
  else
    Result := pvInt;
end;

function PcccFileByLetter(const Letters: ShortString; out Fixed: SmallInt): Byte;
var
  I: Integer;
begin
  Result := 0;
  Fixed := -1;
  for I := Low(Files) to High(Files) do
    if Files[I].Letter = Letters then
    begin
      Fixed := Files[I].Fixed;
      Exit(Files[I].FType);
    end;
end;

function PcccFindSub(FileType: Byte; const Name: ShortString; out Sub: Byte; out Bit: ShortInt): Boolean;
var
  I: Integer;
begin
  Sub := 0;
  Bit := -1;
  for I := Low(SubTable) to High(SubTable) do
    if (SubTable[I].FType = FileType) and (SubTable[I].Name = Name) then
    begin
      Sub := SubTable[I].Sub;
      Bit := SubTable[I].Bit;
      Exit(True);
    end;
  Result := False;
end;

function PcccSubName(const A: tPcccAddr): ShortString;
var
  I: Integer;
begin
  Result := '';
  for I := Low(SubTable) to High(SubTable) do
    if (SubTable[I].FType = A.FileType) and (SubTable[I].Sub = A.Sub) and
       ((SubTable[I].Bit = -1) or (SubTable[I].Bit = A.Bit)) then
      Exit(SubTable[I].Name);
end;

function PcccAddressText(const A: tPcccAddr): ShortString;
var
  Name: ShortString;
begin
  Result := PcccFileLetter(A.FileType) + IntToStr(A.FileNo) + ':' + IntToStr(A.Elem);
  if A.HasSub then
  begin
    Name := PcccSubName(A);
    if Name = '' then
      Name := IntToStr(A.Sub);
    Result := Result + '.' + Name;
    if (A.Sub <> 0) and (A.Bit >= 0) then
      Result := Result + '/' + IntToStr(A.Bit);
  end
  else if A.Bit >= 0 then
    Result := Result + '/' + IntToStr(A.Bit);
end;

function PcccParseAddress(const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
begin
  Result := PcccParseAddressAs(pdSlc, S, A, Err);
end;

type
  tDialectRules = record
    Missing  : Byte;          { the file type this family has not }
    Letters  : string[27];
    MaxFile  : LongInt;
    MaxElem  : LongInt;
    MaxBit   : LongInt;       { of a bit counted from the start of a B file }
    OctalIo  : Boolean;       { O and I elements and bits in octal }
  end;

const
  Rules: array[tPcccDialect] of tDialectRules = (
    (Missing: pft_Bcd;  Letters: 'O I S B T C R N F ST A L'; MaxFile: 255; MaxElem: 65535;
     MaxBit: 65535; OctalIo: False),
    (Missing: pft_Long; Letters: 'O I S B T C R N F ST A D'; MaxFile: 999; MaxElem: 999;
     MaxBit: 15999; OctalIo: True));
  OctalIoMax = 191;           { 277 octal: the last rack/group of a PLC-5 }

function IsIo(FileType: Byte): Boolean;
begin
  Result := FileType in [pft_Output, pft_Input];
end;

{ Octal digits to a number up to Max; False when empty, not octal or above. }
function OctalToNum(const S: ShortString; Max: LongInt; out V: LongInt): Boolean;
var
  I: Integer;
begin
  V := 0;
  Result := (S <> '') and (Length(S) <= 7);
  if not Result then
    Exit;
  for I := 1 to Length(S) do
  begin
    if not (S[I] in ['0'..'7']) then
      Exit(False);
    V := V * 8 + Ord(S[I]) - Ord('0');
  end;
  Result := V <= Max;
end;

function OctalText(V: LongInt; Digits: Integer): ShortString;
begin
  Result := '';
  repeat
    Result := Chr(Ord('0') + V mod 8) + Result;
    V := V div 8;
  until V = 0;
  while Length(Result) < Digits do
    Result := '0' + Result;
end;

function PcccAddressTextAs(Dialect: tPcccDialect; const A: tPcccAddr): ShortString;
begin
  if Rules[Dialect].OctalIo and IsIo(A.FileType) then
  begin
    Result := PcccFileLetter(A.FileType) + ':' + OctalText(A.Elem, 3);
    if A.Bit >= 0 then
      Result := Result + '/' + OctalText(A.Bit, 2);
  end
  else
    Result := PcccAddressText(A);
end;

{ The steps of PcccParseAddressAs on the upper-case text T, from P: each
  takes its part (P past it) into A and returns '' or what is wrong. }

{ The file: its letters (one of the dialect's) and number (O, I and S
  may leave it out). }
function ParseFile(const T: ShortString; var P: Integer; const R: tDialectRules;
  var A: tPcccAddr; out Letters: ShortString): ShortString;
var
  Num: ShortString;
  Q, I, FI: Integer;
  V: LongInt;
  HaveFile: Boolean;
begin
  Result := '';
  P := 1;
  while (P <= Length(T)) and (T[P] in ['A'..'Z']) do
    Inc(P);
  Letters := Copy(T, 1, P - 1);
  FI := -1;
  for I := Low(Files) to High(Files) do
    if Files[I].Letter = Letters then
      FI := I;
  if (FI < 0) or (Files[FI].FType = R.Missing) then
    Exit('file type "' + Letters + '" is none of ' + R.Letters);
  A.FileType := Files[FI].FType;
  { the file number (may be left out for O, I and S) }
  Q := P;
  while (P <= Length(T)) and (T[P] in ['0'..'9']) do
    Inc(P);
  Num := Copy(T, Q, P - Q);
  HaveFile := Num <> '';
  V := 0;
  if HaveFile and not StrToNum(Num, 0, R.MaxFile, V) then
    Exit('file number "' + Num + '" is not 0..' + IntToStr(R.MaxFile));
  if Files[FI].Fixed >= 0 then
  begin
    if HaveFile and (V <> Files[FI].Fixed) then
      Exit(Letters + ' is file ' + IntToStr(Files[FI].Fixed) + ', not ' + Num);
    V := Files[FI].Fixed;
  end
  else if not HaveFile then
    Exit('file number missing after ' + Letters)
  else if V < 3 then
    Exit('file number ' + Num + ' is not 3..' + IntToStr(R.MaxFile) + ' (0, 1, 2 are O, I, S)');
  A.FileNo := V;
end;

{ B3/20: a bit number counted from the start of a B file (T[P] = '/'). }
function ParseFileBit(const T: ShortString; P: Integer; const R: tDialectRules;
  var A: tPcccAddr): ShortString;
var
  Num: ShortString;
  V: LongInt;
begin
  Result := '';
  if A.FileType <> pft_Bit then
    Exit('a bit number without an element ("/n") is only for B files');
  Num := Copy(T, P + 1, 255);
  V := 0;
  if not StrToNum(Num, 0, R.MaxBit, V) then
    Exit('bit number "' + Num + '" is not 0..' + IntToStr(R.MaxBit));
  A.Elem := V div 16;
  A.Bit := V mod 16;
end;

{ ":element"; Octal: O and I count in octal in this dialect. }
function ParseElement(const T: ShortString; var P: Integer; const R: tDialectRules;
  var A: tPcccAddr; out Octal: Boolean): ShortString;
var
  Num: ShortString;
  Q: Integer;
  V: LongInt;
begin
  Result := '';
  Octal := False;
  if T[P] <> ':' then
    Exit('":" expected after ' + Copy(T, 1, P - 1) + ', found "' + T[P] + '"');
  Inc(P);
  Q := P;
  while (P <= Length(T)) and (T[P] in ['0'..'9']) do
    Inc(P);
  Num := Copy(T, Q, P - Q);
  V := 0;
  Octal := R.OctalIo and IsIo(A.FileType);
  if Octal then
  begin
    if not OctalToNum(Num, OctalIoMax, V) then
      Exit('element "' + Num + '" is not octal 0..277 (I/O racks and groups)');
  end
  else if not StrToNum(Num, 0, R.MaxElem, V) then
    Exit('element "' + Num + '" is not 0..' + IntToStr(R.MaxElem));
  A.Elem := V;
end;

{ ".sub-element" of a timer, counter or control element (T[P] = '.'). }
function ParseSub(const T: ShortString; var P: Integer; const Letters: ShortString;
  var A: tPcccAddr): ShortString;
var
  SubS: ShortString;
  Q: Integer;
begin
  Result := '';
  Inc(P);
  Q := P;
  while (P <= Length(T)) and (T[P] in ['A'..'Z']) do
    Inc(P);
  SubS := Copy(T, Q, P - Q);
  if not PcccHasSubs(A.FileType) then
    Exit('".' + SubS + '": ' + Letters + ' elements have no sub-elements');
  A.HasSub := PcccFindSub(A.FileType, SubS, A.Sub, A.Bit);
  if not A.HasSub then
    Exit('sub-element ".' + SubS + '" is not one of a ' + Letters + ' element');
end;

{ "/bit" of a word (T[P] = '/'), in octal where the element is; the rest
  of T. }
function ParseBit(const T: ShortString; var P: Integer; const Letters: ShortString;
  Octal: Boolean; var A: tPcccAddr): ShortString;
var
  Num: ShortString;
  V: LongInt;
begin
  Result := '';
  Num := Copy(T, P + 1, 255);
  if A.Bit >= 0 then
    Exit('"/' + Num + '" after a bit sub-element');
  if PcccHasSubs(A.FileType) and not A.HasSub then
    Exit('"/' + Num + '" on a whole ' + Letters + ' element: name a word (.PRE, .ACC) or a bit (.DN)');
  if not IsWordFile(A.FileType) and not PcccHasSubs(A.FileType) then
    Exit('"/' + Num + '": ' + Letters + ' elements have no addressable bits');
  V := 0;
  if Octal then
  begin
    if not OctalToNum(Num, 15, V) then
      Exit('bit "' + Num + '" is not octal 00..17');
  end
  else if not StrToNum(Num, 0, 15, V) then
    Exit('bit "' + Num + '" is not 0..15');
  A.Bit := V;
  P := Length(T) + 1;
end;

function PcccParseAddressAs(Dialect: tPcccDialect; const S: ShortString; out A: tPcccAddr;
  out Err: ShortString): tChResult;
var
  T, Letters, Why: ShortString;
  P: Integer;
  Octal: Boolean;
begin
  FillChar(A, SizeOf(A), 0);
  A.Bit := -1;
  Err := '';
  T := UpperCase(Trim(S));
  P := 1;
  Letters := '';
  Octal := False;
  if T = '' then
    Why := 'empty'
  else
    Why := ParseFile(T, P, Rules[Dialect], A, Letters);
  if (Why = '') and (P > Length(T)) then
    Why := '":element" missing';
  if Why = '' then
    if T[P] = '/' then
      Why := ParseFileBit(T, P, Rules[Dialect], A)
    else
    begin
      Why := ParseElement(T, P, Rules[Dialect], A, Octal);
      if (Why = '') and (P <= Length(T)) and (T[P] = '.') then
        Why := ParseSub(T, P, Letters, A);
      if (Why = '') and (P <= Length(T)) and (T[P] = '/') then
        Why := ParseBit(T, P, Letters, Octal, A);
      if (Why = '') and (P <= Length(T)) then
        Why := '"' + Copy(T, P, 255) + '" after the element';
    end;
  if Why <> '' then
  begin
    Err := 'address "' + T + '": ' + Why;
    Exit(res_PcccAddress);
  end;
  Result := res_Ok;
end;

initialization
  ChRegisterResultText(PcccLayer, res_PcccAddress, 'bad PLC address');
end.
