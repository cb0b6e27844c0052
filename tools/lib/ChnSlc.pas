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
    CMD 01         Unprotected Read  (PLC-2 style) ADDR(2) SIZE(1)
    CMD 08         Unprotected Write (PLC-2 style) ADDR(2) data
                   ADDR is a byte offset into the common interface file
                   (CIF, default N9), as SLC processors map PLC-2 commands

  Replies: CMD or $40, the request's TNS, STS; a reply to CMD 0F with
  STS $F0 carries EXT STS as its first data byte (1770-6.5.16 p. 8-4):
    STS $10          illegal command or format: unknown command, a request
                     too short for its fields, write data not matching SIZE,
                     CMD 01/08 with an odd address, SIZE 0, odd or > 244
    STS $50          CMD 01/08: the CIF is missing or the address lies
                     outside it (1770-6.5.16 p. 8-7, "DST file does not
                     exist / too small")
    STS $F0 EXT $01  a field has an illegal value: SIZE 0, above 244 or not
                     a whole number of elements
    STS $F0 EXT $06  address does not point to something usable: no such
                     file, a file type other than the file's, an element
                     past the end, a sub-element other than 0
    STS $F0 EXT $07  file is wrong size: the transfer runs past the end
  What a real SLC answers may differ in detail for the corner cases; the
  codes above are the documented meanings and are covered by tests.

  Data files: N (integer, PCCC type $89), B (bit, $85), S (status, $84),
  each element a 16-bit word; F (float, $8A), each element an IEEE single.
  All stored little-endian, as they travel. File numbers 0..255.

  Configuration text (tools/df1sim.conf; '#' starts a comment):
    N7 100              file N7 with 100 elements, all 0
    N7:0 = 1 2 3 $FF    start values from element 0 (decimal or $hex)
    F8 10
    F8:2 = 1.5 -2.25
    CIF 9               the file CMD 01/08 address (an N file)
  A file is declared before values are given for it; values past its end,
  a number out of range, an unknown line: SlcLoadConfig fails with the line
  number and a message. }
unit ChnSlc;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnDF1Codec, ChnPcccNames, ChnDF1Link;

const
  { PCCC file type codes }
  SlcTypeStatus  = $84;
  SlcTypeBit     = $85;
  SlcTypeInteger = $89;
  SlcTypeFloat   = $8A;

  SlcMaxElements = 4096;   { per file }
  SlcDefaultCif  = 9;

  { The table tools/df1sim, examples/df1slave and examples/df1demo answer
    from when given no configuration (docs/df1sim.md). }
  SlcDefaultConfig =
    'S2 32'#10 +
    'B3 8'#10'B3:0 = $0001 $8000 $00FF'#10 +
    'N7 50'#10'N7:0 = 0 10 20 30 40 50 60 70 80 90'#10 +
    'F8 10'#10'F8:0 = 1.5 -2.25 3.14159 1000000'#10 +
    'N9 64'#10'CIF 9'#10;

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
    Kind : Char;           { 'N', 'B', 'S', 'F'; #0 = no such file }
    Elems: LongInt;
    Data : array of Byte;  { Elems * element size bytes }
  end;

  pSlcTable = ^tSlcTable;
  tSlcTable = record
    Files : array[0..255] of tSlcFile;
    Cif   : Byte;
    Diag  : array[0..dgCount - 1] of Word;
    Name  : string[15];    { in the diagnostic status block }
  end;

function SlcElemSize(Kind: Char): LongInt;
function SlcTypeCode(Kind: Char): Byte;

procedure SlcClear(var T: tSlcTable);
{ Add (or replace) a file; False for a bad kind or size. }
function SlcAddFile(var T: tSlcTable; Kind: Char; Num: Byte; Elems: LongInt): Boolean;
{ Load a configuration text (see the header) into a cleared table. On
  failure ErrLine/Err tell where and why; the table is then undefined. }
function SlcLoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
{ Load SlcDefaultConfig (it is valid: a test loads it). }
procedure SlcLoadDefault(var T: tSlcTable);

{ Element access for tools and tests (word files / float files). }
function SlcGetWord(const T: tSlcTable; Num: Byte; Elem: LongInt): Word;
procedure SlcSetWord(var T: tSlcTable; Num: Byte; Elem: LongInt; V: Word);
function SlcGetFloat(const T: tSlcTable; Num: Byte; Elem: LongInt): Single;

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
  SysUtils, uString;

const
  MskReply  = $4000;   { CMD bit 6: a reply (ChnDF1.MskCF_Reply) }
  CmdEcho   = $06;
  CmdTyped  = $0F;
  CmdURead  = $01;
  CmdUWrite = $08;
  FncEcho = $00; FncReadDiag = $01; FncDiagSts = $03; FncResetDiag = $07;
  FncTRead3 = $A2; FncTWrite3 = $AA;

function SlcElemSize(Kind: Char): LongInt;
begin
  case Kind of
    'N', 'B', 'S': Result := 2;
    'F': Result := 4;
  else
    Result := 0;
  end;
end;

function SlcTypeCode(Kind: Char): Byte;
begin
  case Kind of
    'N': Result := SlcTypeInteger;
    'B': Result := SlcTypeBit;
    'S': Result := SlcTypeStatus;
    'F': Result := SlcTypeFloat;
  else
    Result := 0;
  end;
end;

procedure SlcClear(var T: tSlcTable);
var
  I: Integer;
begin
  for I := 0 to 255 do
  begin
    T.Files[I].Kind := #0;
    T.Files[I].Elems := 0;
    SetLength(T.Files[I].Data, 0);
  end;
  T.Cif := SlcDefaultCif;
  FillChar(T.Diag, SizeOf(T.Diag), 0);
  T.Name := 'df1sim';
end;

function SlcAddFile(var T: tSlcTable; Kind: Char; Num: Byte; Elems: LongInt): Boolean;
begin
  Result := (SlcElemSize(Kind) > 0) and (Elems >= 1) and (Elems <= SlcMaxElements);
  if not Result then
    Exit;
  T.Files[Num].Kind := Kind;
  T.Files[Num].Elems := Elems;
  SetLength(T.Files[Num].Data, 0);   { zero-filled anew }
  SetLength(T.Files[Num].Data, Elems * SlcElemSize(Kind));
end;

function SlcGetWord(const T: tSlcTable; Num: Byte; Elem: LongInt): Word;
begin
  with T.Files[Num] do
    if (SlcElemSize(Kind) = 2) and (Elem >= 0) and (Elem < Elems) then
      Result := Data[Elem * 2] or (Data[Elem * 2 + 1] shl 8)
    else
      Result := 0;
end;

procedure SlcSetWord(var T: tSlcTable; Num: Byte; Elem: LongInt; V: Word);
begin
  with T.Files[Num] do
    if (SlcElemSize(Kind) = 2) and (Elem >= 0) and (Elem < Elems) then
    begin
      Data[Elem * 2] := Lo(V);
      Data[Elem * 2 + 1] := Hi(V);
    end;
end;

function SlcGetFloat(const T: tSlcTable; Num: Byte; Elem: LongInt): Single;
var
  L: LongWord;
begin
  Result := 0;
  with T.Files[Num] do
    if (Kind = 'F') and (Elem >= 0) and (Elem < Elems) then
    begin
      L := LongWord(Data[Elem * 4]) or (LongWord(Data[Elem * 4 + 1]) shl 8) or
           (LongWord(Data[Elem * 4 + 2]) shl 16) or (LongWord(Data[Elem * 4 + 3]) shl 24);
      Move(L, Result, 4);
    end;
end;

{ ------------------------------------------------------------ config text }

{ 'N7' -> Kind, Num }
function ParseFileName(const S: AnsiString; out Kind: Char; out Num: Byte): Boolean;
var
  N: LongInt;
begin
  Result := False;
  Kind := #0;
  Num := 0;
  if Length(S) < 2 then
    Exit;
  Kind := UpCase(S[1]);
  if SlcElemSize(Kind) = 0 then
    Exit;
  N := 0;
  if not StrToNum(Copy(S, 2, 255), 0, 255, N) then
    Exit;
  Num := N;
  Result := True;
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

function SlcLoadConfig(var T: tSlcTable; const Text: AnsiString;
  out ErrLine: LongInt; out Err: AnsiString): Boolean;
var
  Lines: array of AnsiString;
  Line, Tok, Head: AnsiString;
  I, P, Colon, Count: Integer;
  Kind: Char;
  Num: Byte;
  Elem, V: LongInt;
  F: Single;
  L: LongWord;

  procedure Split;
  var
    S: AnsiString;
    K, Start: Integer;
  begin
    SetLength(Lines, 0);
    S := Text;
    Start := 1;
    for K := 1 to Length(S) + 1 do
      if (K > Length(S)) or (S[K] = #10) then
      begin
        SetLength(Lines, Length(Lines) + 1);
        Lines[High(Lines)] := Copy(S, Start, K - Start);
        Start := K + 1;
      end;
  end;

  { next blank-separated word of Line from P }
  function Next(out W: AnsiString): Boolean;
  var
    Q: Integer;
  begin
    while (P <= Length(Line)) and (Line[P] in [' ', #9, #13]) do
      Inc(P);
    Q := P;
    while (P <= Length(Line)) and not (Line[P] in [' ', #9, #13]) do
      Inc(P);
    W := Copy(Line, Q, P - Q);
    Result := W <> '';
  end;

  function Bad(const Why: AnsiString): Boolean;
  begin
    ErrLine := I + 1;
    Err := Why;
    Result := False;
  end;

begin
  ErrLine := 0;
  Err := '';
  SlcClear(T);
  Split;
  for I := 0 to High(Lines) do
  begin
    Line := Lines[I];
    P := Pos('#', Line);
    if P > 0 then
      SetLength(Line, P - 1);
    P := 1;
    if not Next(Head) then
      Continue;
    if UpperCase(Head) = 'CIF' then
    begin
      V := 0;
      if not Next(Tok) or not StrToNum(Tok, 0, 255, V) or Next(Tok) then
        Exit(Bad('CIF wants one file number 0..255'));
      T.Cif := V;
      Continue;
    end;
    Colon := Pos(':', Head);
    if Colon = 0 then
    begin
      { declaration: N7 100 }
      V := 0;
      if not ParseFileName(Head, Kind, Num) then
        Exit(Bad('"' + Head + '" is no file name (N, B, S or F and 0..255)'));
      if not Next(Tok) or not StrToNum(Tok, 1, SlcMaxElements, V) or Next(Tok) then
        Exit(Bad('a file wants its element count 1..' + IntToStr(SlcMaxElements)));
      SlcAddFile(T, Kind, Num, V);
      Continue;
    end;
    { values: N7:0 = 1 2 3 }
    Elem := 0;
    if not ParseFileName(Copy(Head, 1, Colon - 1), Kind, Num) or
       not StrToNum(Copy(Head, Colon + 1, 255), 0, SlcMaxElements - 1, Elem) then
      Exit(Bad('"' + Head + '" is no element address (N7:0)'));
    if T.Files[Num].Kind <> Kind then
      Exit(Bad(Copy(Head, 1, Colon - 1) + ' is not declared (or declared with another type)'));
    if not Next(Tok) or (Tok <> '=') then
      Exit(Bad('"=" expected after ' + Head));
    Count := 0;
    while Next(Tok) do
    begin
      if Elem + Count >= T.Files[Num].Elems then
        Exit(Bad('more values than ' + Copy(Head, 1, Colon - 1) + ' has elements'));
      if Kind = 'F' then
      begin
        if not ParseFloat(Tok, F) then
          Exit(Bad('"' + Tok + '" is no float'));
        Move(F, L, 4);
        T.Files[Num].Data[(Elem + Count) * 4] := L and $FF;
        T.Files[Num].Data[(Elem + Count) * 4 + 1] := (L shr 8) and $FF;
        T.Files[Num].Data[(Elem + Count) * 4 + 2] := (L shr 16) and $FF;
        T.Files[Num].Data[(Elem + Count) * 4 + 3] := L shr 24;
      end
      else
      begin
        V := 0;
        if not StrToNum(Tok, -32768, 65535, V) then
          Exit(Bad('"' + Tok + '" is no 16-bit value'));
        SlcSetWord(T, Num, Elem + Count, Word(V and $FFFF));
      end;
      Inc(Count);
    end;
    if Count = 0 then
      Exit(Bad('no values after "="'));
  end;
  Result := True;
end;

procedure SlcLoadDefault(var T: tSlcTable);
var
  ErrLine: Integer;
  Err: AnsiString;
begin
  if not SlcLoadConfig(T, SlcDefaultConfig, ErrLine, Err) then
    SlcClear(T);   { not reached; TestChnSlc.TestDefaultTable checks it }
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

procedure SetSts(var Rep: tSendRecord; var N: Integer; Sts, Ext: Byte);
begin
  Rep.Sts := Sts;
  N := 0;
  if Sts = sts_ExtSts then
  begin
    Rep.Data[0] := Ext;
    N := 1;
  end;
end;

{ Protected typed logical read/write with three address fields. }
procedure TypedRW(var T: tSlcTable; constref Req: tRecRecord; DataLen: Integer;
  Write: Boolean; var Rep: tSendRecord; var N: Integer);
var
  C: tCursor;
  Size, FType: Byte;
  FileNo, Elem, Sub: LongInt;
  ES, At: LongInt;
begin
  C.P := @Req.Data[0];
  C.Len := DataLen;
  C.Pos := 0;
  if not (TakeByte(C, Size) and TakeField(C, FileNo) and TakeByte(C, FType) and
          TakeField(C, Elem) and TakeField(C, Sub)) then
  begin
    SetSts(Rep, N, sts_IllegalCmd, 0);       { fields missing }
    Exit;
  end;
  if Write and (C.Len - C.Pos <> Size) then
  begin
    SetSts(Rep, N, sts_IllegalCmd, 0);       { data does not match SIZE }
    Exit;
  end;
  if (FileNo > 255) or (T.Files[FileNo].Kind = #0) or
     (SlcTypeCode(T.Files[FileNo].Kind) <> FType) or (Sub <> 0) or
     (Elem >= T.Files[FileNo].Elems) then
  begin
    SetSts(Rep, N, sts_ExtSts, ext_NotUsable);
    Exit;
  end;
  ES := SlcElemSize(T.Files[FileNo].Kind);
  if (Size = 0) or (Size > MaxDataLen) or (Size mod ES <> 0) then
  begin
    SetSts(Rep, N, sts_ExtSts, ext_IllegalVal);
    Exit;
  end;
  if Elem + Size div ES > T.Files[FileNo].Elems then
  begin
    SetSts(Rep, N, sts_ExtSts, ext_WrongSize);
    Exit;
  end;
  At := Elem * ES;
  if Write then
  begin
    Move(Req.Data[C.Pos], T.Files[FileNo].Data[At], Size);
    N := 0;
  end
  else
  begin
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
    SetSts(Rep, N, sts_IllegalCmd, 0);
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
      SetSts(Rep, N, sts_IllegalCmd, 0);
      Exit;
    end;
  end;
  if Odd(Addr) or (Size = 0) or Odd(Size) or (Size > MaxDataLen) then
  begin
    SetSts(Rep, N, sts_IllegalCmd, 0);
    Exit;
  end;
  with T.Files[T.Cif] do
    if (Kind <> 'N') or (Addr + Size > Elems * 2) then
    begin
      SetSts(Rep, N, sts_Address, 0);
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
            SetSts(Rep, N, sts_IllegalCmd, 0)
          else
          begin
            Addr := Req.Data[0] or (Req.Data[1] shl 8);
            Size := Req.Data[2];
            if Addr + Size > SizeOf(T.Diag) then
              SetSts(Rep, N, sts_IllegalCmd, 0)
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
        SetSts(Rep, N, sts_IllegalCmd, 0);
      end;
    CmdTyped:
      case Fnc of
        FncTRead3: TypedRW(T, Req, DataLen, False, Rep, N);
        FncTWrite3: TypedRW(T, Req, DataLen, True, Rep, N);
      else
        SetSts(Rep, N, sts_IllegalCmd, 0);
      end;
    CmdURead: UnprotRW(T, Req, DataLen, False, Rep, N);
    CmdUWrite: UnprotRW(T, Req, DataLen, True, Rep, N);
  else
    SetSts(Rep, N, sts_IllegalCmd, 0);
  end;
  if Rep.Sts <> sts_Ok then
    SlcCount(T, dgErrReplies);
  SlcCount(T, dgCommands);
  RepLen := cSizeHead + N;
end;

end.
