{ ChnICSCodec - DACS ICSlink frames: record -> bytes and a byte-by-byte
  receive automaton. No objects, no I/O; tChnICS (unit ChnICS) glues it to
  ChnVirt, and tools or benchmarks can call it directly.

  Implements section 6 of the SofCon manual ChnICS v1.20 and
  docs/PROTOCOLS.md section 6:

    SOH [SOH ...] DNO STX SNO OP1 OP2 CBN ',' DATA TEXT ETX SUM EOT

  * DNO, SNO: chr(node + $30), node 0..207.  CBN: '0'..'9'.
  * DATA: up to 32 decimal 16-bit integers with an optional sign, separated
    by one or more ','.  TEXT: optional, enclosed in two identical delimiter
    characters that are not #0..#$1F, '+', '-', ',', '.', '0'..'9'; inner
    characters not #0..#$1F (nor the delimiter itself); at most 200
    characters including the delimiters; kept with its delimiters.
  * SUM: XOR of every byte from the last SOH through ETX, both included.

  Decisions where the manual is silent:
  * The encoder sends three SOH, no ',' between the last number and the
    text, and no '+' sign.
  * The receiver accepts extra ',' anywhere in the DATA field (",,1,,2,").
  * A broken frame is reported as soon as the error is seen; the automaton
    then hunts for the next SOH. An SOH that breaks a frame starts the next
    one, so a frame following a truncated one is not lost.
  * A number is at most ICSMaxNumText characters ('+', '-', '.', digits);
    longer text is res_ErrVal even if it is only leading zeros. }
unit ChnICSCodec;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  ICSMaxDataLen = 32;     {< numbers in one frame }
  ICSMaxTextLen = 200;    {< text length including both delimiters }
  ICSMaxNode    = 207;    {< chr(207 + $30) = #$FF }
  ICSNodeBase   = $30;

  ICS_SOH = $01;
  ICS_STX = $02;
  ICS_ETX = $03;
  ICS_EOT = $04;

  {- Receive results (manual section 4.3) }
  ICS_ErrFrame = res_Proto + 0;   {< $20 structure: STX, address, op code, CBN, ',' }
  ICS_ErrSum   = res_Proto + 1;   {< $21 checksum }
  ICS_ErrLen   = res_Proto + 2;   {< $22 too many numbers, text too long }
  ICS_ErrVal   = res_Proto + 3;   {< $23 malformed number or outside 16 bits }
  ICS_ErrETX   = res_Proto + 4;   {< $24 no ETX where it must come }
  ICS_ErrEOT   = res_Proto + 5;   {< $25 no EOT after SUM }

  ICSMaxNumText = 31;             {< characters of one number, see header }
  { Longest frame: 3 SOH, DNO STX SNO OP OP CBN ',' (7), 32 numbers of
    6 characters ('-32768') with 31 commas, 200 text, ETX SUM EOT. }
  ICSMaxFrame = 3 + 7 + ICSMaxDataLen * 6 + (ICSMaxDataLen - 1) + ICSMaxTextLen + 3;
  { Len of a record: 4 header bytes + 2 per number }
  ICSHeadLen = 4;

type
  tICSData = SmallInt;            {< Borland "integer" }

  { Byte-exact with the Borland record: OpCode@0, BlockNum@3, Data@4,
    Text@68, SizeOf = 269. }
  pICSRecord = ^tICSRecord;
  tICSRecord = record
    OpCode  : string[2];
    BlockNum: 0..9;
    Data    : array[0..ICSMaxDataLen - 1] of tICSData;
    Text    : string[ICSMaxTextLen];
  end;

  tICSEvent = (icsNone,    {< byte taken, frame not complete }
               icsFrame,   {< a good frame is in State.Rec }
               icsError);  {< a broken frame, code in State.Error }

  tICSPhase = (ipHunt, ipSOH, ipDNO, ipSNO, ipOp1, ipOp2, ipCBN, ipComma,
               ipData, ipNumber, ipText, ipTextEnd, ipSum, ipEOT);

  { Receive automaton. Only ICSFeed/ICSReset change it; fields may be read. }
  tICSState = record
    Phase  : tICSPhase;
    Sum    : tXor8;          {< running XOR since the last SOH }
    RecvSum: tXor8;          {< SUM byte of the frame }
    DNode  : tNode;          {< addresses of the frame being received }
    SNode  : tNode;
    Count  : SmallInt;       {< numbers stored in Rec.Data so far }
    NumText: string[ICSMaxNumText];   {< the number being received }
    Delim  : Char;           {< text delimiter }
    Rec    : tICSRecord;     {< the decoded frame }
    Error  : tChResult;      {< the code of the last icsError }
  end;

{ Number count of a record Len (ICSHeadLen + 2 * count), or -1 when Len is
  impossible (below 4, odd data part, more than 32 numbers). }
function ICSCountOfLen(Len: Word): SmallInt;
function ICSLenOfCount(Count: SmallInt): Word;

{ True for a character allowed as text delimiter / inside a text. }
function ICSIsDelimiter(C: Char): Boolean;
function ICSIsTextChar(C: Char): Boolean;

{ Encode Rec (Len = 4 + count * SizeOf(tICSData)) as one frame into Buf
  (BufSize bytes). Results: res_Ok; ICS_ErrLen for an impossible Len or
  text longer than 200; res_BadMessage for a node above 207, BlockNum
  above 9, an op code that is not two characters #$20..#$FF, a text that is
  not '' or properly delimited, a forbidden delimiter or inner character;
  res_TooLong when Buf is too small. On error Buf is not touched and
  OutLen = 0. }
function ICSEncode(const Rec: tICSRecord; Len: Word; DNode, SNode: tNode;
  var Buf; BufSize: Word; var OutLen: Word): tChResult;

{ Clear the state and hunt for SOH; a partial frame is dropped. Call it
  once before the first ICSFeed. }
procedure ICSReset(var State: tICSState);
{ One received byte. icsFrame: State.Rec, State.Count, State.DNode,
  State.SNode describe the frame; icsError: State.Error is one of the
  ICS_Err* codes. Either way the automaton already waits for the next
  frame. }
function ICSFeed(var State: tICSState; B: Byte): tICSEvent;
{ Len of the frame just decoded: 4 + 2 * State.Count. }
function ICSRecLen(const State: tICSState): Word;

implementation

uses
  uString;

function ICSCountOfLen(Len: Word): SmallInt;
begin
  if (Len < ICSHeadLen) or Odd(Len - ICSHeadLen) or
     ((Len - ICSHeadLen) div SizeOf(tICSData) > ICSMaxDataLen) then
    Result := -1
  else
    Result := (Len - ICSHeadLen) div SizeOf(tICSData);
end;

function ICSLenOfCount(Count: SmallInt): Word;
begin
  Result := ICSHeadLen + Count * SizeOf(tICSData);
end;

function ICSIsDelimiter(C: Char): Boolean;
begin
  Result := not (C in [#0..#$1F, '+', '-', ',', '.', '0'..'9']);
end;

function ICSIsTextChar(C: Char): Boolean;
begin
  Result := C >= #$20;
end;

{ '' is valid (no text); otherwise D...D with D a delimiter and neither a
  control character nor D inside. }
function TextValid(const T: ShortString): Boolean;
var
  I: Integer;
begin
  Result := True;
  if T = '' then
    Exit;
  Result := False;
  if (Length(T) < 2) or (T[1] <> T[Length(T)]) or not ICSIsDelimiter(T[1]) then
    Exit;
  for I := 2 to Length(T) - 1 do
    if not ICSIsTextChar(T[I]) or (T[I] = T[1]) then
      Exit;
  Result := True;
end;

function ICSEncode(const Rec: tICSRecord; Len: Word; DNode, SNode: tNode;
  var Buf; BufSize: Word; var OutLen: Word): tChResult;
var
  F: array[0..ICSMaxFrame - 1] of Byte;
  N, I, J, Count: Integer;
  Num: string[7];

  procedure Put(B: Byte);
  begin
    F[N] := B;     { cannot overflow: ICSMaxFrame is the longest frame }
    Inc(N);
  end;

begin
  OutLen := 0;
  Count := ICSCountOfLen(Len);
  { BlockNum and the text's length byte are read as plain bytes: a record
    filled by Move or read from a file may hold anything, and the compiler
    may assume a 0..9 or string[200] field stays in its range. }
  if (Count < 0) or (PByte(@Rec.Text)^ > ICSMaxTextLen) then
    Exit(ICS_ErrLen);
  if (DNode > ICSMaxNode) or (SNode > ICSMaxNode) or
     (PByte(@Rec.BlockNum)^ > 9) or (Length(Rec.OpCode) <> 2) or
     (Rec.OpCode[1] < #$20) or (Rec.OpCode[2] < #$20) or
     not TextValid(Rec.Text) then
    Exit(res_BadMessage);
  N := 0;
  Put(ICS_SOH);
  Put(ICS_SOH);
  Put(ICS_SOH);
  Put(Byte(DNode + ICSNodeBase));
  Put(ICS_STX);
  Put(Byte(SNode + ICSNodeBase));
  Put(Ord(Rec.OpCode[1]));
  Put(Ord(Rec.OpCode[2]));
  Put(Ord('0') + Byte(Rec.BlockNum));
  Put(Ord(','));
  for I := 0 to Count - 1 do
  begin
    if I > 0 then
      Put(Ord(','));
    Str(Rec.Data[I], Num);
    for J := 1 to Length(Num) do
      Put(Ord(Num[J]));
  end;
  for J := 1 to Length(Rec.Text) do
    Put(Ord(Rec.Text[J]));
  Put(ICS_ETX);
  Put(Xor8Block(F[2], N - 2));     { from the last SOH through ETX }
  Put(ICS_EOT);
  if N > BufSize then
    Exit(res_TooLong);
  Move(F, Buf, N);
  OutLen := N;
  Result := res_Ok;
end;

procedure ICSReset(var State: tICSState);
begin
  FillChar(State, SizeOf(State), 0);
  State.Phase := ipHunt;
  State.Error := res_Ok;
end;

function ICSRecLen(const State: tICSState): Word;
begin
  Result := ICSLenOfCount(State.Count);
end;

{ Store the number in State.NumText: res_Ok, ICS_ErrLen or ICS_ErrVal. }
function StoreNumber(var State: tICSState): tChResult;
var
  V: LongInt;
begin
  V := 0;
  if State.Count >= ICSMaxDataLen then
    Exit(ICS_ErrLen);
  { NumText holds only '+', '-', '.' and digits, so StrToNum's '$' hex
    form cannot occur; it refuses '--5', '5-', '5.3', '+' and values
    outside -32768..32767. }
  if not StrToNum(State.NumText, Low(tICSData), High(tICSData), V) then
    Exit(ICS_ErrVal);
  State.Rec.Data[State.Count] := V;
  Inc(State.Count);
  State.NumText := '';
  Result := res_Ok;
end;

{ A byte of the DATA field outside a number: ',', the first character of a
  number, a text delimiter or ETX. }
function DataByte(var State: tICSState; B: Byte): tChResult;
begin
  Result := res_Ok;
  if B = Ord(',') then
    { one more separator }
  else if Chr(B) in ['+', '-', '.', '0'..'9'] then
  begin
    if State.Count >= ICSMaxDataLen then
      Result := ICS_ErrLen            { a 33rd number }
    else
    begin
      State.NumText := Chr(B);
      State.Phase := ipNumber;
    end;
  end
  else if B >= $20 then
  begin
    { every other printable character is a valid delimiter }
    State.Delim := Chr(B);
    State.Rec.Text := Chr(B);
    State.Phase := ipText;
  end
  else if B = ICS_ETX then
    State.Phase := ipSum
  else
    Result := ICS_ErrETX;             { a control character before ETX }
end;

{ Between frames (ipHunt) and after SOH (ipSOH): SOH starts a frame (the
  last one seen counts), then the destination address. }
function FrameStart(var State: tICSState; B: Byte): tChResult;
begin
  Result := res_Ok;
  if B = ICS_SOH then
  begin
    State.Phase := ipSOH;
    State.Sum := ICS_SOH;          { the sum starts at the last SOH }
  end
  else if State.Phase = ipHunt then
    { noise between frames is skipped }
  else if B >= ICSNodeBase then
  begin
    FillChar(State.Rec, SizeOf(State.Rec), 0);
    State.Count := 0;
    State.NumText := '';
    State.DNode := B - ICSNodeBase;
    State.Phase := ipDNO;
  end
  else
    Result := ICS_ErrFrame;        { bad destination address }
end;

{ The head after the destination address: STX, the source address, the
  two characters of the op code, the block number, the comma. }
function HeadByte(var State: tICSState; B: Byte): tChResult; inline;
begin
  Result := res_Ok;
  case State.Phase of
    ipDNO:
      if B = ICS_STX then
        State.Phase := ipSNO
      else
        Result := ICS_ErrFrame;        { missing STX }
    ipSNO:
      if B >= ICSNodeBase then
      begin
        State.SNode := B - ICSNodeBase;
        State.Phase := ipOp1;
      end
      else
        Result := ICS_ErrFrame;        { bad source address }
    ipOp1, ipOp2:
      if B < $20 then
        Result := ICS_ErrFrame         { control character in the op code }
      else if State.Phase = ipOp1 then
      begin
        State.Rec.OpCode := Chr(B);
        State.Phase := ipOp2;
      end
      else
      begin
        State.Rec.OpCode := State.Rec.OpCode + Chr(B);
        State.Phase := ipCBN;
      end;
    ipCBN:
      if Chr(B) in ['0'..'9'] then
      begin
        State.Rec.BlockNum := B - Ord('0');
        State.Phase := ipComma;
      end
      else
        Result := ICS_ErrFrame;        { block number not a digit }
  else                                 { ipComma }
    if B = Ord(',') then
      State.Phase := ipData
    else
      Result := ICS_ErrFrame;          { missing ',' after CBN }
  end;
end;

{ A byte inside a number: one more character of it, or the byte after it. }
function NumberByte(var State: tICSState; B: Byte): tChResult; inline;
begin
  if Chr(B) in ['+', '-', '.', '0'..'9'] then
  begin
    Result := res_Ok;
    if Length(State.NumText) >= ICSMaxNumText then
      Result := ICS_ErrVal
    else
      State.NumText := State.NumText + Chr(B);
  end
  else
  begin
    { the number ends here; the byte is a separator, text or ETX }
    Result := StoreNumber(State);
    if Result = res_Ok then
    begin
      State.Phase := ipData;
      Result := DataByte(State, B);
    end;
  end;
end;

{ A byte inside the text: its closing delimiter, or one more character. }
function TextByte(var State: tICSState; B: Byte): tChResult; inline;
begin
  Result := res_Ok;
  if Chr(B) = State.Delim then
  begin
    State.Rec.Text := State.Rec.Text + Chr(B);
    State.Phase := ipTextEnd;
  end
  else if not ICSIsTextChar(Chr(B)) then
    Result := ICS_ErrFrame             { control character inside the text }
  else if Length(State.Rec.Text) + 2 > ICSMaxTextLen then
    Result := ICS_ErrLen               { no room left for the closing delimiter }
  else
    State.Rec.Text := State.Rec.Text + Chr(B);
end;

{ A frame broken by B (R says how): counted; an SOH starts the next one. }
function Broken(var State: tICSState; B: Byte; R: tChResult): tICSEvent;
begin
  State.Error := R;
  Result := icsError;
  if B = ICS_SOH then
  begin
    State.Phase := ipSOH;            { this SOH starts the next frame }
    State.Sum := ICS_SOH;
  end
  else
    State.Phase := ipHunt;
end;

function ICSFeed(var State: tICSState; B: Byte): tICSEvent;
var
  R: tChResult;
begin
  Result := icsNone;
  R := res_Ok;
  if State.Phase in [ipSOH..ipTextEnd] then
    State.Sum := Xor8Add(State.Sum, B);   { SUM covers SOH .. ETX only }
  case State.Phase of
    ipHunt, ipSOH:
      R := FrameStart(State, B);
    ipDNO..ipComma:
      R := HeadByte(State, B);
    ipData:
      R := DataByte(State, B);
    ipNumber:
      R := NumberByte(State, B);
    ipText:
      R := TextByte(State, B);
    ipTextEnd:
      if B = ICS_ETX then
        State.Phase := ipSum
      else
        R := ICS_ErrETX;               { something after the closing delimiter }
    ipSum:
      begin
        State.RecvSum := B;
        State.Phase := ipEOT;
      end;
    ipEOT:
      if B <> ICS_EOT then
        R := ICS_ErrEOT
      else if State.RecvSum <> State.Sum then
        R := ICS_ErrSum
      else
      begin
        Result := icsFrame;
        State.Phase := ipHunt;
      end;
  end;
  if R <> res_Ok then
    Result := Broken(State, B, R);
end;

end.
