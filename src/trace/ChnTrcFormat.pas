{ ChnTrcFormat - the text format of the trace layer (NAM=TRC, unit ChnTrc):
  writing an entry and reading a whole log back. Pure: no I/O, no objects,
  so a decoder tool can use it without the channel machinery.

  The format is the one of the RACOM line captures in the DF1 note
  (RACOM note, chapter 3; docs/REFERENCES.md):

    13:33:33.058 rx;i  60 | S00
    1002 0300 0B00 7E00 0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100
    8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401 1003 15C6
    13:33:33.065 tx   2 | S00
    1006

  Header line: local time of day with milliseconds, direction ('tx' or 'rx';
  RACOM appends tags such as ';i'), the chunk length in bytes, '|' and a tag
  (RACOM: the port 'S00'; the trace layer writes its name). Then the bytes in
  hex, two bytes (four digits) per group, 15 groups (30 bytes) per line as in
  the capture; an odd last byte is a group of two digits. The direction is
  padded to three characters and followed by two blanks, which reproduces
  the capture's 'tx   2' and 'rx;i  60'. With MOD=DEC each byte is written
  as three decimal digits ('016 002 255'), 20 per line.

  The reader is liberal in what it accepts:
  * bytes may follow the '|' on the header line ('13:33:33.058 rx 2 | 1006');
    text after '|' that is not all byte groups is the tag;
  * data tokens are 4 hex digits (two bytes), 2 hex digits (one byte) or
    3 decimal digits (one byte, 0..255), upper or lower case;
  * a line starting with the RACOM prompt '>>' is read without it;
  * the time may carry 1 to 6 fraction digits (kept to milliseconds);
  * any other line (prose around a pasted capture, a stray hex line that
    follows no header) is counted in Skipped and otherwise ignored.
  A frame ends when it has the announced number of bytes. A header, a
  non-data line or the end of the input before that gives res_TrcShort; a
  data line that overshoots gives res_TrcLong (all bytes kept). }
unit ChnTrcFormat;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  TrcHexPerLine = 30;        {< bytes per line, HEX: 15 groups as in the capture }
  TrcDecPerLine = 20;        {< bytes per line, DEC: 79 characters }
  TrcMsPerDay   = 86400000;
  TrcMaxLen     = 65535;     {< longest chunk the Ch* API can carry (Word) }

  { the trace layer's name (ChnTrc.cName): the reader's result texts are
    registered for it, ChResultText(R, TrcLayer) }
  TrcLayer = 'TRC';

  {- results of the reader, per frame (texts registered for TrcLayer) }
  res_TrcShort = res_Proto;      {< fewer bytes than the header announces }
  res_TrcLong  = res_Proto + 1;  {< more bytes than the header announces }

type
  tTrcDir  = (trcTx, trcRx);
  tTrcMode = (trcHex, trcDec);
  tTrcBytes = array of Byte;

  tTrcFrame = record
    Line   : LongInt;        {< line number of the header, 1-based }
    TimeMs : LongInt;        {< milliseconds since midnight }
    Dir    : tTrcDir;
    DirText: string[15];     {< as written, e.g. 'rx;i' }
    Tag    : string[63];     {< text after '|' when it is not data ('S00') }
    Len    : LongInt;        {< length the header announces }
    Data   : tTrcBytes;      {< the bytes found, Length(Data) of them }
    Status : tChResult;      {< res_Ok, res_TrcShort or res_TrcLong }
  end;
  tTrcFrames = array of tTrcFrame;

  { Incremental reader: TrcReaderInit, TrcReadLine per line, TrcReadEnd.
    Finished frames are appended to Frames[0..Count-1]; a streaming caller
    may take them and set Count := 0 between lines. }
  tTrcReader = record
    LineNo : LongInt;
    Count  : LongInt;
    Frames : tTrcFrames;
    Skipped: LongInt;        {< non-blank lines that were neither header nor data }
    Pending: Boolean;        {< Cur still waits for bytes }
    Cur    : tTrcFrame;
    CurFill: LongInt;        {< bytes in Cur.Data so far }
  end;

{ Writer. MsOfDay is taken modulo one day. }
function TrcTimeText(MsOfDay: LongInt): ShortString;
function TrcHeader(MsOfDay: LongInt; Dir: tTrcDir; Len: LongInt; const Tag: ShortString): ShortString;
function TrcLineCount(Len: LongInt; Mode: tTrcMode): LongInt;
{ Data line Index (0-based) of a chunk of Len bytes at Buf. }
function TrcDataLine(const Buf; Len, Index: LongInt; Mode: tTrcMode): ShortString;
{ A whole entry: header and data lines, each ended by LineEnding. }
function TrcFormat(MsOfDay: LongInt; Dir: tTrcDir; const Buf; Len: LongInt;
  Mode: tTrcMode; const Tag: ShortString): AnsiString;

{ Reader. }
procedure TrcReaderInit(var R: tTrcReader);
procedure TrcReadLine(var R: tTrcReader; const Line: AnsiString);
procedure TrcReadEnd(var R: tTrcReader);
{ Read a whole text (LF or CR LF line ends); returns the number of frames,
  Frames holds exactly that many. Skipped, if given, gets the count of
  ignored lines. }
function TrcReadText(const Text: AnsiString; var Frames: tTrcFrames): LongInt;
function TrcReadText(const Text: AnsiString; var Frames: tTrcFrames;
  var Skipped: LongInt): LongInt;

implementation

uses
  uString;

const
  HexChars: array[0..15] of Char = '0123456789ABCDEF';
  DirName: array[tTrcDir] of string[2] = ('tx', 'rx');

{- ------------------------------------------------------------------ writer }

function Dec2(N: LongInt): ShortString;
begin
  Result := Chr(Ord('0') + N div 10) + Chr(Ord('0') + N mod 10);
end;

function TrcTimeText(MsOfDay: LongInt): ShortString;
var
  Ms: LongInt;
begin
  Ms := MsOfDay mod TrcMsPerDay;
  if Ms < 0 then
    Inc(Ms, TrcMsPerDay);
  Result := Dec2(Ms div 3600000) + ':' + Dec2(Ms div 60000 mod 60) + ':' +
    Dec2(Ms div 1000 mod 60) + '.' + Chr(Ord('0') + Ms mod 1000 div 100) +
    Dec2(Ms mod 100);
end;

function TrcHeader(MsOfDay: LongInt; Dir: tTrcDir; Len: LongInt; const Tag: ShortString): ShortString;
begin
  { 'tx' padded to three plus two blanks: the capture's 'tx   2' }
  Result := TrcTimeText(MsOfDay) + ' ' + DirName[Dir] + '   ' + NumStr(Len) + ' |';
  if Tag <> '' then
    Result := Result + ' ' + Tag;
end;

function PerLine(Mode: tTrcMode): LongInt;
begin
  if Mode = trcHex then
    Result := TrcHexPerLine
  else
    Result := TrcDecPerLine;
end;

function TrcLineCount(Len: LongInt; Mode: tTrcMode): LongInt;
begin
  if Len <= 0 then
    Result := 0
  else
    Result := (Len + PerLine(Mode) - 1) div PerLine(Mode);
end;

function TrcDataLine(const Buf; Len, Index: LongInt; Mode: tTrcMode): ShortString;
var
  P: PByte;
  I, First, Last: LongInt;
  B: Byte;
begin
  Result := '';
  P := @Buf;
  First := Index * PerLine(Mode);
  Last := First + PerLine(Mode) - 1;
  if Last > Len - 1 then
    Last := Len - 1;
  for I := First to Last do
  begin
    B := P[I];
    if Mode = trcDec then
    begin
      if I > First then
        Result := Result + ' ';
      Result := Result + Chr(Ord('0') + B div 100) + Dec2(B mod 100);
    end
    else
    begin
      if (I > First) and ((I - First) mod 2 = 0) then
        Result := Result + ' ';        { a blank between groups of two bytes }
      Result := Result + HexChars[B shr 4] + HexChars[B and 15];
    end;
  end;
end;

function TrcFormat(MsOfDay: LongInt; Dir: tTrcDir; const Buf; Len: LongInt;
  Mode: tTrcMode; const Tag: string): AnsiString;
var
  Pos, I, Lines: LongInt;
  Text: AnsiString;

  procedure Put(const S: ShortString);
  var
    T: string;
  begin
    T := S + LineEnding;
    Move(T[1], Text[Pos], Length(T));
    Inc(Pos, Length(T));
  end;

begin
  Lines := TrcLineCount(Len, Mode);
  { one allocation: every line is shorter than 255 + LineEnding }
  Text := '';
  SetLength(Text, (Lines + 1) * (256 + Length(LineEnding)));
  Pos := 1;
  Put(TrcHeader(MsOfDay, Dir, Len, Tag));
  for I := 0 to Lines - 1 do
    Put(TrcDataLine(Buf, Len, I, Mode));
  SetLength(Text, Pos - 1);
  Result := Text;
end;

{- ------------------------------------------------------------------ reader }

{ Next blank-separated token of Line from Pos (1-based). }
function NextWord(const Line: AnsiString; var Pos: LongInt; var W: AnsiString): Boolean;
var
  Start: LongInt;
begin
  while (Pos <= Length(Line)) and (Line[Pos] in [#9, ' ']) do
    Inc(Pos);
  Start := Pos;
  while (Pos <= Length(Line)) and not (Line[Pos] in [#9, ' ']) do
    Inc(Pos);
  W := Copy(Line, Start, Pos - Start);
  Result := W <> '';
end;

function AllDigits(const S: AnsiString): Boolean;
var
  I: LongInt;
begin
  Result := S <> '';
  for I := 1 to Length(S) do
    if not (S[I] in ['0'..'9']) then
      Result := False;
end;


{ Bytes of one data token into Out (up to 2); False if W is not one. }
function DataToken(const W: AnsiString; var Out: array of Byte; var N: Integer): Boolean;
var
  I: Integer;
  V: LongInt;
begin
  Result := False;
  N := 0;
  V := 0;
  case Length(W) of
    2, 4:
      begin
        for I := 1 to Length(W) do
          if HexDigit(W[I]) < 0 then
            Exit;
        for I := 0 to Length(W) div 2 - 1 do
          Out[I] := HexDigit(W[2 * I + 1]) * 16 + HexDigit(W[2 * I + 2]);
        N := Length(W) div 2;
      end;
    3:
      begin
        if not AllDigits(W) or not StrToNum(W, 0, 255, V) then
          Exit;
        Out[0] := V;
        N := 1;
      end;
  else
    Exit;
  end;
  Result := True;
end;

{ The data tokens of Line from Pos on, appended to Bytes/Fill. False (and
  nothing appended) when there is no token or any token is not data. }
function DataTokens(const Line: AnsiString; Pos: LongInt; var Bytes: tTrcBytes;
  var Fill: LongInt): Boolean;
var
  P, Count: LongInt;
  W: AnsiString;
  Tmp: array[0..1] of Byte;
  N: Integer;
begin
  Result := False;
  W := '';
  N := 0;
  Tmp[0] := 0;
  Count := 0;
  P := Pos;
  while NextWord(Line, P, W) do    { validate first, so a bad line adds nothing }
  begin
    if not DataToken(W, Tmp, N) then
      Exit;
    Inc(Count, N);
  end;
  if Count = 0 then
    Exit;
  if Fill + Count > Length(Bytes) then
  begin
    if Fill + Count > 2 * Length(Bytes) then
      SetLength(Bytes, Fill + Count + 64)
    else
      SetLength(Bytes, 2 * Length(Bytes));
  end;
  P := Pos;
  while NextWord(Line, P, W) do
  begin
    DataToken(W, Tmp, N);
    Move(Tmp, Bytes[Fill], N);
    Inc(Fill, N);
  end;
  Result := True;
end;

{ 'HH:MM:SS.fff' -> milliseconds since midnight. }
function ParseTime(const W: AnsiString; var Ms: LongInt): Boolean;
var
  H, M, S, F: LongInt;
  Frac: AnsiString;
begin
  Result := False;
  H := 0;
  M := 0;
  S := 0;
  F := 0;
  if (Length(W) < 10) or (Length(W) > 15) or (W[3] <> ':') or (W[6] <> ':') or
     (W[9] <> '.') then
    Exit;
  Frac := Copy(W, 10, Length(W) - 9);
  if not AllDigits(Copy(W, 1, 2)) or not AllDigits(Copy(W, 4, 2)) or
     not AllDigits(Copy(W, 7, 2)) or not AllDigits(Frac) then
    Exit;
  Frac := Copy(Frac + '00', 1, 3);      { to milliseconds }
  if not StrToNum(Copy(W, 1, 2), 0, 23, H) or not StrToNum(Copy(W, 4, 2), 0, 59, M) or
     not StrToNum(Copy(W, 7, 2), 0, 59, S) or not StrToNum(Frac, 0, 999, F) then
    Exit;
  Ms := ((H * 60 + M) * 60 + S) * 1000 + F;
  Result := True;
end;

procedure ClearFrame(var F: tTrcFrame);
begin
  F.Line := 0;
  F.TimeMs := 0;
  F.Dir := trcTx;
  F.DirText := '';
  F.Tag := '';
  F.Len := 0;
  SetLength(F.Data, 0);
  F.Status := res_Ok;
end;

procedure TrcReaderInit(var R: tTrcReader);
begin
  R.LineNo := 0;
  R.Count := 0;
  SetLength(R.Frames, 0);
  R.Skipped := 0;
  R.Pending := False;
  ClearFrame(R.Cur);
  R.CurFill := 0;
end;

{ Move Cur to Frames with the right status. }
procedure FinishFrame(var R: tTrcReader);
begin
  SetLength(R.Cur.Data, R.CurFill);
  if R.CurFill < R.Cur.Len then
    R.Cur.Status := res_TrcShort
  else if R.CurFill > R.Cur.Len then
    R.Cur.Status := res_TrcLong
  else
    R.Cur.Status := res_Ok;
  if R.Count >= Length(R.Frames) then
    SetLength(R.Frames, 2 * R.Count + 16);
  R.Frames[R.Count] := R.Cur;
  Inc(R.Count);
  R.Pending := False;
  ClearFrame(R.Cur);
  R.CurFill := 0;
end;

{ A header starts a new frame in R.Cur; False (R.Cur untouched) if Line
  is not a header. }
function ReadHeader(var R: tTrcReader; const Line: AnsiString): Boolean;
var
  P, Ms, Len, RestPos: LongInt;
  W, D, Rest: AnsiString;
  Dir: tTrcDir;
begin
  Result := False;
  P := 1;
  W := '';
  Ms := 0;
  Len := 0;
  if not NextWord(Line, P, W) or not ParseTime(W, Ms) then
    Exit;
  if not NextWord(Line, P, D) or (Length(D) > 15) then
    Exit;
  if UpStr(Copy(D, 1, 2)) = 'TX' then
    Dir := trcTx
  else if UpStr(Copy(D, 1, 2)) = 'RX' then
    Dir := trcRx
  else
    Exit;
  if (Length(D) > 2) and (D[3] <> ';') then
    Exit;                              { 'txt' is no direction }
  if not NextWord(Line, P, W) or not AllDigits(W) or (Length(W) > 5) or
     not StrToNum(W, 0, TrcMaxLen, Len) then
    Exit;
  { what follows the optional '|' is data or the tag }
  RestPos := P;
  if NextWord(Line, RestPos, W) and (W = '|') then
    P := RestPos;
  R.Cur.Line := R.LineNo;
  R.Cur.TimeMs := Ms;
  R.Cur.Dir := Dir;
  R.Cur.DirText := D;
  R.Cur.Len := Len;
  R.CurFill := 0;
  if not DataTokens(Line, P, R.Cur.Data, R.CurFill) then
  begin
    Rest := Copy(Line, P, Length(Line) - P + 1);
    while (Rest <> '') and (Rest[1] in [#9, ' ']) do
      Delete(Rest, 1, 1);
    R.Cur.Tag := Copy(Rest, 1, High(R.Cur.Tag));
  end;
  R.Pending := True;
  if R.CurFill >= Len then
    FinishFrame(R);
  Result := True;
end;

procedure TrcReadLine(var R: tTrcReader; const Line: AnsiString);
var
  L: AnsiString;
  P: LongInt;
  W: AnsiString;
begin
  Inc(R.LineNo);
  L := Line;
  while (L <> '') and (L[Length(L)] in [#10, #13, #9, ' ']) do
    SetLength(L, Length(L) - 1);
  while (L <> '') and (L[1] in [#9, ' ']) do
    Delete(L, 1, 1);
  if Copy(L, 1, 2) = '>>' then
    Delete(L, 1, 2);                   { RACOM console prompt }
  P := 1;
  W := '';
  if not NextWord(L, P, W) then
    Exit;                              { blank lines never end a frame }
  if R.Pending and DataTokens(L, 1, R.Cur.Data, R.CurFill) then
  begin
    if R.CurFill >= R.Cur.Len then
      FinishFrame(R);
    Exit;
  end;
  if R.Pending then
    FinishFrame(R);                    { cut short by a header or by prose }
  if not ReadHeader(R, L) then
    Inc(R.Skipped);
end;

procedure TrcReadEnd(var R: tTrcReader);
begin
  if R.Pending then
    FinishFrame(R);
  SetLength(R.Frames, R.Count);
end;

function TrcReadText(const Text: AnsiString; var Frames: tTrcFrames;
  var Skipped: LongInt): LongInt;
var
  R: tTrcReader;
  Start, I: LongInt;
begin
  TrcReaderInit(R);
  Start := 1;
  for I := 1 to Length(Text) + 1 do
    if (I > Length(Text)) or (Text[I] = #10) then
    begin
      if (I <= Length(Text)) or (Start <= Length(Text)) then
        TrcReadLine(R, Copy(Text, Start, I - Start));
      Start := I + 1;
    end;
  TrcReadEnd(R);
  Frames := R.Frames;
  Skipped := R.Skipped;
  Result := R.Count;
end;

function TrcReadText(const Text: AnsiString; var Frames: tTrcFrames): LongInt;
var
  Skipped: LongInt;
begin
  Skipped := 0;
  Result := TrcReadText(Text, Frames, Skipped);
end;

initialization
  ChRegisterResultText(TrcLayer, res_TrcShort, 'trace frame has fewer bytes than its header says');
  ChRegisterResultText(TrcLayer, res_TrcLong, 'trace frame has more bytes than its header says');
end.
