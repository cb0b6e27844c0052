{ ChnSlc - the data table and command handler of a simulated Allen-Bradley
  SLC 5/0x, for tools/df1sim. Pure: a request record in, a reply record
  out (tSendRecord of unit ChnDF1Codec), no I/O; the link dialogue (ACK,
  NAK, ENQ, polls) is in unit ChnDF1Link.

  Commands (Rockwell publication 1770-6.5.16, "DF1 Protocol and Command Set
  Reference Manual", October 1996, chapters 7 and 8; SofCon ChnDF1 manual
  section 6.3):
    CMD 06 FNC 00  Echo                       data echoed
    CMD 06 FNC 03  Diagnostic Status          a status block (see SlcDiagStatus)
    CMD 06 FNC 01  Read Diagnostic Counters   ADDR(2) SIZE(1) -> SIZE bytes
    CMD 06 FNC 07  Reset Diagnostic Counters
    CMD 0F FNC A2  Protected Typed Logical Read, three address fields
    CMD 0F FNC AA  Protected Typed Logical Write, three address fields
                   SIZE(1) FILE TYPE(1) ELEMENT SUBELEMENT [data]; FILE,
                   ELEMENT and SUBELEMENT are one byte, or $FF and two bytes
                   low first for values above 254
    CMD 0F FNC AB  Protected Typed Logical Masked Write, three address
                   fields: SIZE FILE TYPE ELEMENT SUBELEMENT, then SIZE
                   bytes of mask and SIZE bytes of data; the bits set in the
                   mask take the data's, the others stay
    CMD 01         Unprotected Read  (PLC-2 style) ADDR(2) SIZE(1)
    CMD 08         Unprotected Write (PLC-2 style) ADDR(2) data
                   ADDR is a byte offset into the common interface file
                   (CIF, default N9), as SLC processors map PLC-2 commands

  Replies: CMD or $40, the request's TNS, STS; a reply to CMD 0F with
  STS $F0 carries EXT STS as its first data byte (1770-6.5.16 p. 8-4):
    STS $10          illegal command or format: unknown command, a request
                     too short for its fields, write data not matching SIZE
                     (masked write: not 2 * SIZE), CMD 01/08 with an odd
                     address, SIZE 0, odd or > 244
    STS $50          CMD 01/08: the CIF is missing or the address lies
                     outside it (1770-6.5.16 p. 8-7, "DST file does not
                     exist / too small")
    STS $F0 EXT $01  a field has an illegal value: SIZE 0, above 244 or not
                     a whole number of units (4 bytes for F and L, else 2)
    STS $F0 EXT $06  address does not point to something usable: no such
                     file, a file type other than the file's, an element
                     past the end, a sub-element other than 0 (0..2 in T, C
                     and R files: control word, PRE or LEN, ACC or POS)
    STS $F0 EXT $07  file is wrong size: the transfer runs past the end
  What a real SLC answers may differ in detail for the corner cases; the
  codes above are the documented meanings and are covered by tests.

  Data files, with the PCCC type codes and element sizes of unit ChnPccc
  (which also parses the addresses of the configuration): O, I, S, B, N, A
  (a 16-bit word each), T, C, R (three words: control bits, PRE or LEN,
  ACC or POS), F (IEEE single), L (32-bit), ST (LEN word and 82 characters,
  each word's two characters swapped). All stored as they travel. File
  numbers as the addresses allow: O0, I1, S2, the others 3..255.

  Configuration text (tools/df1sim.conf; '#' starts a comment):
    N7 100              file N7 with 100 elements, all 0
    N7:0 = 1 2 3 $FF    start values from element 0 (decimal or $hex)
    F8 10
    F8:2 = 1.5 -2.25
    T4 5
    T4:0 = $2000 100 42 a whole timer: control word, PRE, ACC
    T4:1.PRE = 10 20    one word each of T4:1, T4:2
    L11:0 = 100000      32-bit values
    ST10:0 = "hello"    one string (no '#' in it)
    CIF 9               the file CMD 01/08 address (an N file)
  A file is declared before values are given for it; values past its end,
  a number out of range, an unknown line: SlcLoadConfig fails with the line
  number and a message. }
unit ChnSlc;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnDF1Codec, ChnPcccNames, ChnPccc, ChnDF1Link;

const
  SlcMaxElements = 4096;   { per file }
  SlcDefaultCif  = 9;

  { The table tools/df1sim, examples/df1slave and examples/df1demo answer
    from when given no configuration (docs/df1sim.md), in two parts: a
    constant is at most 255 characters. }
  SlcDefaultConfig1 =
    'S2 32'#10 +
    'B3 8'#10'B3:0 = $0001 $8000 $00FF'#10 +
    'N7 50'#10'N7:0 = 0 10 20 30 40 50 60 70 80 90'#10 +
    'F8 10'#10'F8:0 = 1.5 -2.25 3.14159 1000000'#10 +
    'N9 64'#10'CIF 9'#10;
  { The PLC-5 table of df1sim --plc5 (PLC-5 addresses: octal I/O, D as
    decimal values stored in BCD). }
  Plc5DefaultConfig1 =
    'O0 16'#10'O:001 = $00FF'#10'I1 16'#10'I:012 = $0020'#10'S2 32'#10 +
    'B3 8'#10'B3:0 = $0001 $0002 $00FF'#10 +
    'T4 4'#10'T4:0 = $2000 100 100'#10'T4:1.PRE = 50'#10'T4:1.ACC = 7'#10 +
    'C5 4'#10'C5:0 = $8000 10 3'#10'R6 2'#10'R6:0.LEN = 8'#10;
  Plc5DefaultConfig2 =
    'N7 50'#10'N7:0 = 0 10 20 30 40 50 60 70 80 90'#10 +
    'F8 10'#10'F8:0 = 1.5 -2.25 3.14159 1000000'#10 +
    'ST9 2'#10'ST9:0 = "hello"'#10'D10 4'#10'D10:0 = 1234 9999'#10;
  SlcDefaultConfig2 =
    'T4 4'#10'T4:0 = $2000 100 100'#10'T4:1.PRE = 50'#10'T4:1.ACC = 7'#10 +
    'C5 4'#10'C5:0 = $8000 10 3'#10 +
    'R6 2'#10'R6:0.LEN = 8'#10'R6:0.POS = 2'#10 +
    'ST10 2'#10'ST10:0 = "hello"'#10 +
    'L11 4'#10'L11:0 = 100000 -2'#10;

  { diagnostic counters: indexes of tSlcTable.Diag (16-bit, sent low first) }
  dgFramesIn   = 0;   { good frames received }
  dgFramesOut  = 1;   { frames sent }
  dgNaksOut    = 2;   { broken frames answered with NAK }
  dgEnqsIn     = 3;   { ENQs received }
  dgNaksIn     = 4;   { NAKs received }
  dgErrReplies = 5;   { replies with STS <> 0 }
  dgDupsIn     = 6;   { repeated commands ACKed and not executed (DUP=ON) }
  dgCommands   = 7;   { commands executed (answered by SlcHandle) }
  dgCount      = 8;

type
  tSlcFile = record
    FType: Byte;           { pft_* of unit ChnPccc; 0 = no such file }
    Elems: LongInt;
    Data : array of Byte;  { Elems * element size bytes }
  end;

  pSlcTable = ^tSlcTable;
  tSlcTable = record
    Files : array[0..255] of tSlcFile;
    Cif   : Byte;
    Diag  : array[0..dgCount - 1] of Word;
    Name  : string[15];    { in the diagnostic status block }
    Plc5  : Boolean;       { a PLC-5: its addresses in the configuration and its
                             commands (unit ChnPlc5Sim); set by Plc5LoadConfig }
  end;

procedure SlcClear(var T: tSlcTable);
{ Add (or replace) a file of type FType (pft_*); False for an unknown
  type or a bad size. }
function SlcAddFile(var T: tSlcTable; FType: Byte; Num: Byte; Elems: LongInt): Boolean;
{ Load a configuration text (see the header) into a cleared table. On
  failure ErrLine/Err tell where and why; the table is then undefined. }
function SlcLoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
{ The same for a PLC-5 (df1sim --plc5): PLC-5 addresses ('I:012 = $20',
  'D10:0 = 1234', files 0..255 of the table), and the table answers the
  PLC-5 commands too (unit ChnPlc5Sim). }
function Plc5LoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
{ A reply's status: STS, and EXT STS as its first data byte when STS is
  $F0; N becomes the reply's data bytes (0 or 1). }
procedure SlcSetSts(var Rep: tSendRecord; var N: LongInt; Sts, Ext: Byte);
{ Load Plc5DefaultConfig (a test loads it). }
procedure Plc5LoadDefault(var T: tSlcTable);
{ SlcDefaultConfig1 and SlcDefaultConfig2, the built-in table. }
function SlcDefaultConfig: AnsiString;
{ The built-in table of a PLC-5 (df1sim --plc5; T.Plc5 set). }
function Plc5DefaultConfig: AnsiString;
{ Load SlcDefaultConfig (it is valid: a test loads it). }
procedure SlcLoadDefault(var T: tSlcTable);

{ Element access for tools and tests: a word of a word-based element (Sub
  0..2 in T, C, R; 0 elsewhere), an F element; 0 when there is none. }
function SlcGetWord(const T: tSlcTable; Num: Byte; Elem: LongInt; Sub: LongInt = 0): Word;
procedure SlcSetWord(var T: tSlcTable; Num: Byte; Elem: LongInt; V: Word);
function SlcGetFloat(const T: tSlcTable; Num: Byte; Elem: LongInt): Single;

{ The free-running clock of an SLC: S:4 counts up by one every 10 ms and
  wraps at 65535. Ms is the time since the processor started; S2:4 gets
  Ms div 10 (nothing when the table has no S2 file with element 4). }
procedure SlcClock(var T: tSlcTable; Ms: QWord);

{ Answer one command. Req/ReqLen as received (Len = 8 + data bytes); Rep
  gets the reply, RepLen its Len. Replies to replies are not made: the
  function returns False for a message with the reply bit set. }
function SlcHandle(var T: tSlcTable; constref Req: tRecRecord; ReqLen: Word;
  var Rep: tSendRecord; var RepLen: Word): Boolean;

{ Count one event in a diagnostic counter; it wraps at 65535 like the
  PLC's 16-bit counters (and never trips an overflow check). }
procedure SlcCount(var T: tSlcTable; Index: LongInt);

{ A link station (unit ChnDF1Link) on the DF1 channel Chn that answers
  from table T and counts its link events in T's diagnostic counters. }
function SlcStationInit(var S: tDF1Station; Chn: pChnVirt; T: pSlcTable): tChResult;

implementation

uses
  SysUtils, uString, ChnPlc5, ChnPlc5Sim;

const
  MskReply  = $4000;   { CMD bit 6: a reply (ChnDF1.MskCF_Reply) }
  CmdEcho   = $06;
  CmdTyped  = $0F;
  CmdURead  = $01;
  CmdUWrite = $08;
  FncEcho = $00; FncReadDiag = $01; FncDiagSts = $03; FncResetDiag = $07;
  FncTRead3 = $A2; FncTWrite3 = $AA; FncTMaskWrite3 = $AB;

{ Files whose elements are 16-bit words (T, C, R: three of them). }
function WordBased(FType: Byte): Boolean;
begin
  Result := not (FType in [0, pft_Float, pft_Long]);
end;

function IsTcr(FType: Byte): Boolean;
begin
  Result := FType in [pft_Timer, pft_Counter, pft_Control];
end;

procedure SlcClear(var T: tSlcTable);
var
  I: Integer;
begin
  for I := 0 to 255 do
  begin
    T.Files[I].FType := 0;
    T.Files[I].Elems := 0;
    SetLength(T.Files[I].Data, 0);
  end;
  T.Cif := SlcDefaultCif;
  FillChar(T.Diag, SizeOf(T.Diag), 0);
  T.Name := 'df1sim';
  T.Plc5 := False;
end;

function SlcAddFile(var T: tSlcTable; FType: Byte; Num: Byte; Elems: LongInt): Boolean;
begin
  Result := (PcccElemSize(FType) > 0) and (Elems >= 1) and (Elems <= SlcMaxElements);
  if not Result then
    Exit;
  T.Files[Num].FType := FType;
  T.Files[Num].Elems := Elems;
  SetLength(T.Files[Num].Data, 0);   { zero-filled anew }
  SetLength(T.Files[Num].Data, Elems * PcccElemSize(FType));
end;

{ Byte offset of word Sub of element Elem, or -1 when there is none. }
function WordAt(const F: tSlcFile; Elem, Sub: LongInt): LongInt;
var
  ES: LongInt;
begin
  Result := -1;
  ES := PcccElemSize(F.FType);
  if WordBased(F.FType) and (Elem >= 0) and (Elem < F.Elems) and (Sub >= 0) and
     (Sub * 2 < ES) then
    Result := Elem * ES + Sub * 2;
end;

function SlcGetWord(const T: tSlcTable; Num: Byte; Elem: LongInt; Sub: LongInt): Word;
var
  At: LongInt;
begin
  At := WordAt(T.Files[Num], Elem, Sub);
  if At < 0 then
    Result := 0
  else
    Result := T.Files[Num].Data[At] or (T.Files[Num].Data[At + 1] shl 8);
end;

procedure SlcSetWord(var T: tSlcTable; Num: Byte; Elem: LongInt; V: Word);
var
  At: LongInt;
begin
  At := WordAt(T.Files[Num], Elem, 0);
  if At >= 0 then
  begin
    T.Files[Num].Data[At] := Lo(V);
    T.Files[Num].Data[At + 1] := Hi(V);
  end;
end;

function SlcGetFloat(const T: tSlcTable; Num: Byte; Elem: LongInt): Single;
var
  L: LongWord;
begin
  Result := 0;
  with T.Files[Num] do
    if (FType = pft_Float) and (Elem >= 0) and (Elem < Elems) then
    begin
      L := LongWord(Data[Elem * 4]) or (LongWord(Data[Elem * 4 + 1]) shl 8) or
           (LongWord(Data[Elem * 4 + 2]) shl 16) or (LongWord(Data[Elem * 4 + 3]) shl 24);
      Move(L, Result, 4);
    end;
end;

{ ------------------------------------------------------------ config text }

{ An address by the rules of the table's PLC (SLC or PLC-5); a PLC-5 file
  above 255 is refused: the table holds 0..255. }
function ParseAddr(const T: tSlcTable; const S: ShortString; out A: tPcccAddr; out Err: ShortString): tChResult;
begin
  if not T.Plc5 then
    Exit(PcccParseAddress(S, A, Err));
  Result := Plc5ParseAddress(S, A, Err);
  if (Result = res_Ok) and (A.FileNo > 255) then
  begin
    Err := 'address "' + S + '": df1sim holds files 0..255';
    Result := res_PcccAddress;
  end;
end;

function AddrText(const T: tSlcTable; const A: tPcccAddr): ShortString;
begin
  if T.Plc5 then
    Result := Plc5AddressText(A)
  else
    Result := PcccAddressText(A);
end;

{ 'N7' -> type code and number, by the library's address rules }
function ParseFileName(const T: tSlcTable; const S: AnsiString; out FType: Byte; out Num: Byte): Boolean;
var
  A: tPcccAddr;
  Err: ShortString;
begin
  FType := 0;
  Num := 0;
  Result := (Length(S) < 200) and (S <> '') and (S[Length(S)] in ['0'..'9']) and
    (ParseAddr(T, S + ':0', A, Err) = res_Ok);
  if Result then
  begin
    FType := A.FileType;
    Num := A.FileNo;
  end;
end;

function ParseFloat(const S: AnsiString; out F: Single): Boolean;
var
  D: Double;
  Code: Integer;
begin
  Val(S, D, Code);
  Result := (Code = 0) and (Abs(D) <= 3.4e38);
  if Result then
    F := D
  else
    F := 0;
end;

procedure PutBytes(var F: tSlcFile; At: LongInt; V: LongWord; N: LongInt);
var
  K: LongInt;
begin
  for K := 0 to N - 1 do
    F.Data[At + K] := (V shr (8 * K)) and $FF;
end;

type
  { One line of the configuration and how far it has been read. }
  tCfgLine = record
    Text: AnsiString;
    P: Integer;
  end;

{ The next blank-separated word of the line. }
function NextWord(var L: tCfgLine; out W: AnsiString): Boolean;
var
  Q: Integer;
begin
  while (L.P <= Length(L.Text)) and (L.Text[L.P] in [' ', #9, #13]) do
    Inc(L.P);
  Q := L.P;
  while (L.P <= Length(L.Text)) and not (L.Text[L.P] in [' ', #9, #13]) do
    Inc(L.P);
  W := Copy(L.Text, Q, L.P - Q);
  Result := W <> '';
end;

{ CIF 9: the file the common interface commands use. }
function TakeCif(var T: tSlcTable; var L: tCfgLine; out Err: AnsiString): Boolean;
var
  Tok: AnsiString;
  V: LongInt;
begin
  V := 0;
  Result := NextWord(L, Tok) and StrToNum(Tok, 0, 255, V) and not NextWord(L, Tok);
  if Result then
    T.Cif := V
  else
    Err := 'CIF wants one file number 0..255';
end;

{ N7 100: a file and its element count. }
function TakeDeclaration(var T: tSlcTable; const Head: AnsiString; var L: tCfgLine;
  out Err: AnsiString): Boolean;
var
  Tok: AnsiString;
  FType, Num: Byte;
  V: LongInt;
begin
  Result := False;
  V := 0;
  if not ParseFileName(T, Head, FType, Num) then
  begin
    if T.Plc5 then
      Err := '"' + Head + '" is no file name (O0 I1 S2, B T C R N F ST A D 3..255)'
    else
      Err := '"' + Head + '" is no file name (O0 I1 S2, B T C R N F ST A L 3..255)';
    Exit;
  end;
  if not NextWord(L, Tok) or not StrToNum(Tok, 1, SlcMaxElements, V) or NextWord(L, Tok) then
  begin
    Err := 'a file wants its element count 1..' + IntToStr(SlcMaxElements);
    Exit;
  end;
  SlcAddFile(T, FType, Num, V);
  Result := True;
end;

{ ST10:0 = "text": the rest of the line, in double quotes. }
function TakeString(var T: tSlcTable; const A: tPcccAddr; const Head: AnsiString;
  const L: tCfgLine; out Err: AnsiString): Boolean;
var
  Str: AnsiString;
  Q: Integer;
  PErr: ShortString;
  Buf: array[0..2 + PcccStringChars - 1] of Byte;
begin
  Result := False;
  Str := Trim(Copy(L.Text, L.P, MaxInt));
  Q := Length(Str);
  if (Q < 2) or (Str[1] <> '"') or (Str[Q] <> '"') then
  begin
    Err := Head + ' wants one string in double quotes';
    Exit;
  end;
  if PcccEncodeString(Copy(Str, 2, Q - 2), Buf, PErr) <> res_Ok then
  begin
    Err := PErr;
    Exit;
  end;
  Move(Buf, T.Files[A.FileNo].Data[A.Elem * PcccElemSize(pft_String)], SizeOf(Buf));
  Result := True;
end;

{ One start value of a file of type FType, as the bytes it is stored as. }
function ParseValue(FType: Byte; const Tok: AnsiString; out L: LongWord; out Err: AnsiString): Boolean;
var
  F: Single;
  V: LongInt;
  W: Word;
begin
  L := 0;
  V := 0;
  if FType = pft_Float then
  begin
    Result := ParseFloat(Tok, F);
    if Result then
      Move(F, L, 4)
    else
      Err := '"' + Tok + '" is no float';
  end
  else if FType = pft_Long then
  begin
    Result := StrToNum(Tok, Low(LongInt), High(LongInt), V);
    if Result then
      L := LongWord(V)
    else
      Err := '"' + Tok + '" is no 32-bit value';
  end
  else if FType = pft_Bcd then
  begin
    Result := StrToNum(Tok, 0, 9999, V) and Plc5ToBcd(V, W);
    if Result then
      L := W
    else
      Err := '"' + Tok + '" is not 0..9999 (a D element holds four BCD digits)';
  end
  else
  begin
    Result := StrToNum(Tok, -32768, 65535, V);
    if Result then
      L := LongWord(V) and $FFFF
    else
      Err := '"' + Tok + '" is no 16-bit value';
  end;
end;

{ N7:0 = 1 2 3, T4:0.PRE = 5: consecutive words (or 4-byte values), or the
  same word of consecutive elements for .PRE/.ACC/.LEN/.POS. }
function TakeNumbers(var T: tSlcTable; const A: tPcccAddr; var L: tCfgLine;
  out Err: AnsiString): Boolean;
var
  Tok: AnsiString;
  At, Stride, Size, Count: LongInt;
  V: LongWord;
begin
  Result := False;
  Size := 2;
  if A.FileType in [pft_Float, pft_Long] then
    Size := 4;
  Stride := Size;
  At := A.Elem * PcccElemSize(A.FileType);
  if A.HasSub then
  begin
    At := At + 2 * A.Sub;
    Stride := PcccElemSize(A.FileType);
  end;
  Count := 0;
  while NextWord(L, Tok) do
  begin
    if At + Count * Stride + Size > Length(T.Files[A.FileNo].Data) then
    begin
      Err := 'more values than ' + PcccFileLetter(A.FileType) + IntToStr(A.FileNo) +
        ' has elements';
      Exit;
    end;
    if not ParseValue(A.FileType, Tok, V, Err) then
      Exit;
    PutBytes(T.Files[A.FileNo], At + Count * Stride, V, Size);
    Inc(Count);
  end;
  if Count = 0 then
  begin
    Err := 'no values after "="';
    Exit;
  end;
  Result := True;
end;

{ ADDRESS = values: start values of a declared file. }
function TakeValues(var T: tSlcTable; Head: AnsiString; var L: tCfgLine;
  out Err: AnsiString): Boolean;
var
  Tok: AnsiString;
  A: tPcccAddr;
  PErr: ShortString;
begin
  Result := False;
  if Length(Head) > 200 then
    Err := 'address too long'
  else if ParseAddr(T, Head, A, PErr) <> res_Ok then
    Err := PErr
  else
  begin
    Head := AddrText(T, A);
    if (T.Files[A.FileNo].FType <> A.FileType) or (A.FileType = 0) then
      Err := PcccFileLetter(A.FileType) + IntToStr(A.FileNo) +
        ' is not declared (or declared with another type)'
    else if A.Bit >= 0 then
      Err := Head + ': a bit address takes no start values'
    else if not NextWord(L, Tok) or (Tok <> '=') then
      Err := '"=" expected after ' + Head
    else if A.Elem >= T.Files[A.FileNo].Elems then
      Err := Head + ' lies past the end of its file'
    else if A.FileType = pft_String then
      Result := TakeString(T, A, Head, L, Err)
    else
      Result := TakeNumbers(T, A, L, Err);
  end;
end;

{ One line, its comment cut off: a CIF, a declaration or start values. }
function TakeLine(var T: tSlcTable; const Line: AnsiString; out Err: AnsiString): Boolean;
var
  L: tCfgLine;
  Head: AnsiString;
  P: Integer;
begin
  L.Text := Line;
  P := Pos('#', L.Text);
  if P > 0 then
    SetLength(L.Text, P - 1);
  L.P := 1;
  if not NextWord(L, Head) then
    Result := True
  else if UpperCase(Head) = 'CIF' then
    Result := TakeCif(T, L, Err)
  else if Pos(':', Head) = 0 then
    Result := TakeDeclaration(T, Head, L, Err)
  else
    Result := TakeValues(T, Head, L, Err);
end;

function LoadConfig(var T: tSlcTable; Plc5: Boolean; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
var
  Start, K, LineNo: LongInt;
begin
  ErrLine := 0;
  Err := '';
  SlcClear(T);
  T.Plc5 := Plc5;
  Start := 1;
  LineNo := 0;
  for K := 1 to Length(Text) + 1 do
    if (K > Length(Text)) or (Text[K] = #10) then
    begin
      Inc(LineNo);
      if not TakeLine(T, Copy(Text, Start, K - Start), Err) then
      begin
        ErrLine := LineNo;
        Exit(False);
      end;
      Start := K + 1;
    end;
  Result := True;
end;

function SlcLoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
begin
  Result := LoadConfig(T, False, Text, ErrLine, Err);
end;

function Plc5LoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
begin
  Result := LoadConfig(T, True, Text, ErrLine, Err);
end;

procedure Plc5LoadDefault(var T: tSlcTable);
var
  ErrLine: Integer;
  Err: AnsiString;
begin
  if not Plc5LoadConfig(T, Plc5DefaultConfig, ErrLine, Err) then
    SlcClear(T);   { not reached; TestChnPlc5Sim checks it }
end;

function SlcDefaultConfig: AnsiString;
begin
  Result := SlcDefaultConfig1 + SlcDefaultConfig2;
end;

function Plc5DefaultConfig: AnsiString;
begin
  Result := Plc5DefaultConfig1 + Plc5DefaultConfig2;
end;

procedure SlcLoadDefault(var T: tSlcTable);
var
  ErrLine: Integer;
  Err: AnsiString;
begin
  if not SlcLoadConfig(T, SlcDefaultConfig, ErrLine, Err) then
    SlcClear(T);   { not reached; TestChnSlc.TestDefaultTable checks it }
end;

procedure SlcClock(var T: tSlcTable; Ms: QWord);
begin
  if (T.Files[2].FType = pft_Status) and (T.Files[2].Elems > 4) then
    SlcSetWord(T, 2, 4, Word((Ms div 10) and $FFFF));
end;

{ ------------------------------------------------------------- commands }

type
  { reading the request's data field by field }
  tCursor = record
    P  : PByte;
    Len: Integer;
    Pos: Integer;
  end;

function TakeByte(var C: tCursor; out B: Byte): Boolean;
begin
  Result := C.Pos < C.Len;
  B := 0;
  if Result then
  begin
    B := C.P[C.Pos];
    Inc(C.Pos);
  end;
end;

{ A 3-address field: one byte, or $FF and a word low first. }
function TakeField(var C: tCursor; out V: LongInt): Boolean;
var
  B, Lo8, Hi8: Byte;
begin
  V := 0;
  Result := TakeByte(C, B);
  if not Result then
    Exit;
  if B <> $FF then
    V := B
  else
  begin
    Result := TakeByte(C, Lo8) and TakeByte(C, Hi8);
    V := Lo8 or (Hi8 shl 8);
  end;
end;

procedure SlcSetSts(var Rep: tSendRecord; var N: LongInt; Sts, Ext: Byte);
begin
  Rep.Sts := Sts;
  N := 0;
  if Sts = sts_ExtSts then
  begin
    Rep.Data[0] := Ext;
    N := 1;
  end;
end;

type
  tTypedOp = (twRead, twWrite, twMasked);

{ Protected typed logical read, write and masked write with three address
  fields. }
procedure TypedRW(var T: tSlcTable; constref Req: tRecRecord; DataLen: Integer;
  Op: tTypedOp; var Rep: tSendRecord; var N: Integer);
var
  C: tCursor;
  Size, FType, Unit_: Byte;
  FileNo, Elem, Sub, MaxSub: LongInt;
  ES, At, K: LongInt;
  Want: Integer;
begin
  C.P := @Req.Data[0];
  C.Len := DataLen;
  C.Pos := 0;
  if not (TakeByte(C, Size) and TakeField(C, FileNo) and TakeByte(C, FType) and
          TakeField(C, Elem) and TakeField(C, Sub)) then
  begin
    SlcSetSts(Rep, N, sts_IllegalCmd, 0);       { fields missing }
    Exit;
  end;
  case Op of
    twWrite: Want := Size;
    twMasked: Want := 2 * Size;              { mask, then data }
  else
    Want := 0;
  end;
  if C.Len - C.Pos <> Want then
  begin
    SlcSetSts(Rep, N, sts_IllegalCmd, 0);       { data does not match SIZE }
    Exit;
  end;
  MaxSub := 0;
  if (FileNo <= 255) and IsTcr(T.Files[FileNo].FType) then
    MaxSub := 2;                             { control word, PRE/LEN, ACC/POS }
  if (FileNo > 255) or (T.Files[FileNo].FType = 0) or
     (T.Files[FileNo].FType <> FType) or (Sub > MaxSub) or
     (Elem >= T.Files[FileNo].Elems) then
  begin
    SlcSetSts(Rep, N, sts_ExtSts, ext_NotUsable);
    Exit;
  end;
  ES := PcccElemSize(FType);
  Unit_ := 2;
  if not WordBased(FType) then
    Unit_ := 4;
  if (Size = 0) or (Size > MaxDataLen) or (Size mod Unit_ <> 0) then
  begin
    SlcSetSts(Rep, N, sts_ExtSts, ext_IllegalVal);
    Exit;
  end;
  At := Elem * ES + Sub * 2;
  if At + Size > T.Files[FileNo].Elems * ES then
  begin
    SlcSetSts(Rep, N, sts_ExtSts, ext_WrongSize);
    Exit;
  end;
  N := 0;
  case Op of
    twWrite:
      Move(Req.Data[C.Pos], T.Files[FileNo].Data[At], Size);
    twMasked:
      for K := 0 to Size - 1 do
        T.Files[FileNo].Data[At + K] :=
          (T.Files[FileNo].Data[At + K] and not Req.Data[C.Pos + K]) or
          (Req.Data[C.Pos + Size + K] and Req.Data[C.Pos + K]);
  else
    Move(T.Files[FileNo].Data[At], Rep.Data[0], Size);
    N := Size;
  end;
end;

{ PLC-2 style unprotected read/write into the CIF. }
procedure UnprotRW(var T: tSlcTable; constref Req: tRecRecord; DataLen: Integer;
  Write: Boolean; var Rep: tSendRecord; var N: Integer);
var
  Addr, Size: LongInt;
begin
  N := 0;
  if DataLen < 3 then
  begin
    SlcSetSts(Rep, N, sts_IllegalCmd, 0);
    Exit;
  end;
  Addr := Req.Data[0] or (Req.Data[1] shl 8);
  if Write then
    Size := DataLen - 2
  else
  begin
    Size := Req.Data[2];
    if DataLen <> 3 then
    begin
      SlcSetSts(Rep, N, sts_IllegalCmd, 0);
      Exit;
    end;
  end;
  if Odd(Addr) or (Size = 0) or Odd(Size) or (Size > MaxDataLen) then
  begin
    SlcSetSts(Rep, N, sts_IllegalCmd, 0);
    Exit;
  end;
  with T.Files[T.Cif] do
    if (FType <> pft_Integer) or (Addr + Size > Elems * 2) then
    begin
      SlcSetSts(Rep, N, sts_Address, 0);
      Exit;
    end;
  if Write then
    Move(Req.Data[2], T.Files[T.Cif].Data[Addr], Size)
  else
  begin
    Move(T.Files[T.Cif].Data[Addr], Rep.Data[0], Size);
    N := Size;
  end;
end;

procedure SlcCount(var T: tSlcTable; Index: LongInt);
begin
  T.Diag[Index] := Word(T.Diag[Index] + 1);
end;

{ The Diagnostic Status reply: shaped like an SLC's (mode/status byte,
  type code $EE, extended type, series/revision, name), not byte-exact
  with any real processor. }
procedure DiagStatus(const T: tSlcTable; var Rep: tSendRecord; var N: Integer);
var
  I: Integer;
begin
  Rep.Data[0] := $06;   { run mode }
  Rep.Data[1] := $EE;   { extended interface type }
  Rep.Data[2] := $49;   { SLC 5/03 }
  Rep.Data[3] := $00;
  Rep.Data[4] := $21;   { series B, revision 1 }
  N := 5;
  for I := 1 to Length(T.Name) do
  begin
    Rep.Data[N] := Ord(T.Name[I]);
    Inc(N);
  end;
end;

function SlcStationHandler(Data: Pointer; constref Cmd: tRecRecord; CmdLen: Word;
  var Reply: tSendRecord; var ReplyLen: Word): Boolean;
begin
  Result := SlcHandle(pSlcTable(Data)^, Cmd, CmdLen, Reply, ReplyLen);
end;

procedure SlcStationEvent(Data: Pointer; Event: tDF1LinkEvent);
const
  Counter: array[tDF1LinkEvent] of Integer =
    (dgFramesIn, dgFramesOut, dgNaksOut, dgEnqsIn, dgNaksIn, dgDupsIn);
begin
  SlcCount(pSlcTable(Data)^, Counter[Event]);
end;

function SlcStationInit(var S: tDF1Station; Chn: pChnVirt; T: pSlcTable): tChResult;
begin
  Result := DF1StationInit(S, Chn, @SlcStationHandler, T);
  S.OnEvent := @SlcStationEvent;
end;

function SlcHandle(var T: tSlcTable; constref Req: tRecRecord; ReqLen: Word;
  var Rep: tSendRecord; var RepLen: Word): Boolean;
var
  Cmd, Fnc: Byte;
  DataLen, N, I, Addr, Size: Integer;
begin
  Result := (Req.MessType = tpDataMess) and (Req.CF and MskReply = 0) and
            (ReqLen >= cSizeHead) and (ReqLen <= cSizeHead + MaxDataLen);
  if not Result then
    Exit;
  DataLen := ReqLen - cSizeHead;
  Cmd := Hi(Req.CF);
  Fnc := Lo(Req.CF);
  FillChar(Rep, cSizeHead, 0);
  Rep.MessType := tpDataMess;
  Rep.CF := Word(Cmd shl 8) or MskReply;   { replies carry no FNC }
  Rep.Tns := Req.Tns;
  N := 0;
  case Cmd of
    CmdEcho:
      case Fnc of
        FncEcho:
          begin
            N := DataLen;
            Move(Req.Data[0], Rep.Data[0], N);
          end;
        FncDiagSts:
          DiagStatus(T, Rep, N);
        FncReadDiag:
          if DataLen <> 3 then
            SlcSetSts(Rep, N, sts_IllegalCmd, 0)
          else
          begin
            Addr := Req.Data[0] or (Req.Data[1] shl 8);
            Size := Req.Data[2];
            if Addr + Size > SizeOf(T.Diag) then
              SlcSetSts(Rep, N, sts_IllegalCmd, 0)
            else
            begin
              for I := 0 to Size - 1 do
                if Odd(Addr + I) then
                  Rep.Data[I] := Hi(T.Diag[(Addr + I) div 2])
                else
                  Rep.Data[I] := Lo(T.Diag[(Addr + I) div 2]);
              N := Size;
            end;
          end;
        FncResetDiag:
          FillChar(T.Diag, SizeOf(T.Diag), 0);
      else
        SlcSetSts(Rep, N, sts_IllegalCmd, 0);
      end;
    CmdTyped:
      if T.Plc5 and Plc5SimHandle(T, Fnc, Req, DataLen, Rep, N) then
        { a PLC-5 command }
      else case Fnc of
        FncTRead3: TypedRW(T, Req, DataLen, twRead, Rep, N);
        FncTWrite3: TypedRW(T, Req, DataLen, twWrite, Rep, N);
        FncTMaskWrite3: TypedRW(T, Req, DataLen, twMasked, Rep, N);
      else
        SlcSetSts(Rep, N, sts_IllegalCmd, 0);
      end;
    CmdURead: UnprotRW(T, Req, DataLen, False, Rep, N);
    CmdUWrite: UnprotRW(T, Req, DataLen, True, Rep, N);
  else
    SlcSetSts(Rep, N, sts_IllegalCmd, 0);
  end;
  if Rep.Sts <> sts_Ok then
    SlcCount(T, dgErrReplies);
  SlcCount(T, dgCommands);
  RepLen := cSizeHead + N;
end;

end.
