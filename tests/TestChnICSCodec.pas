{ Tests of ChnICSCodec: record layout, frames worked out by hand, every
  delimiter class, every receive error and every refused record, and a
  random round-trip property (manual ChnICS section 6, docs/PROTOCOLS.md section 6). }
unit TestChnICSCodec;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnICSCodec;

type
  TTestChnICSCodec = class(TTestCase)
  published
    procedure TestRecordLayout;
    procedure TestCountOfLen;
    procedure TestEncodeManualRequest;
    procedure TestEncodeReplyWithText;
    procedure TestEncodeNoDataHighestNode;
    procedure TestEncodeLowestNumber;
    procedure TestDecodeHandFrames;
    procedure TestAnyNumberOfLeadingSOH;
    procedure TestNoiseBeforeFrame;
    procedure TestExtraCommasAccepted;
    procedure TestNumberForms;
    procedure TestRoundTripCounts;
    procedure TestEveryDelimiter;
    procedure TestEveryInnerTextCharacter;
    procedure TestErrSum;
    procedure TestErrFrame;
    procedure TestErrLen;
    procedure TestErrVal;
    procedure TestErrETX;
    procedure TestErrEOT;
    procedure TestSOHInsideFrameStartsNextFrame;
    procedure TestEncodeRefusesBadRecords;
    procedure TestEncodeSmallBuffer;
    procedure TestRandomRoundTrip;
    procedure TestRandomCorruptionNeverAccepted;
  end;

implementation

const
  { Frames worked out by hand. SUM = XOR of the bytes from the last SOH
    through ETX; the running value is given after each byte. }

  { master 1 -> slave 2, 'RD', block 0, numbers 0, 10, 15 (manual example
    without its text): 01 32 02 31 52 44 30 2C 30 2C 31 30 2C 31 35 03
    01^32=33 ^02=31 ^31=00 ^52=52 ^44=16 ^30=26 ^2C=0A ^30=3A ^2C=16
    ^31=27 ^30=17 ^2C=3B ^31=0A ^35=3F ^03=3C }
  FrameA = #1#1#1'2'#2'1RD0,0,10,15'#3#$3C#4;
  BodyA  = '2'#2'1RD0,0,10,15'#3#$3C#4;       { FrameA after its SOHs }

  { slave 2 -> master 1, 'DB', block 0, numbers -1, 32767, text "ok":
    01 31 02 32 44 42 30 2C 2D 31 2C 33 32 37 36 37 22 6F 6B 22 03
    01^31=30 ^02=32 ^32=00 ^44=44 ^42=06 ^30=36 ^2C=1A ^2D=37 ^31=06
    ^2C=2A ^33=19 ^32=2B ^37=1C ^36=2A ^37=1D ^22=3F ^6F=50 ^6B=3B
    ^22=19 ^03=1A }
  FrameB = #1#1#1'1'#2'2DB0,-1,32767"ok"'#3#$1A#4;

  { station 207 -> 0, 'RL', block 9, no numbers, no text:
    01 30 02 FF 52 4C 39 2C 03
    01^30=31 ^02=33 ^FF=CC ^52=9E ^4C=D2 ^39=EB ^2C=C7 ^03=C4 }
  FrameC = #1#1#1'0'#2#$FF'RL9,'#3#$C4#4;

  { 1 -> 5, 'WD', block 1, number -32768:
    01 35 02 31 57 44 31 2C 2D 33 32 37 36 38 03
    01^35=34 ^02=36 ^31=07 ^57=50 ^44=14 ^31=25 ^2C=09 ^2D=24 ^33=17
    ^32=25 ^37=12 ^36=24 ^38=1C ^03=1F }
  FrameD = #1#1#1'5'#2'1WD1,-32768'#3#$1F#4;

  Forbidden = [#0..#$1F, '+', '-', ',', '.', '0'..'9'];  { manual section 6 }

function Hex(const S: string): string;
var
  I: Integer;
begin
  Result := '';
  for I := 1 to Length(S) do
    Result := Result + IntToHex(Ord(S[I]), 2) + ' ';
end;

function MakeRec(const Op: string; Block: Byte; const Data: array of SmallInt;
  const Text: string): tICSRecord;
var
  I: Integer;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.OpCode := Op;
  Result.BlockNum := Block;
  for I := 0 to High(Data) do
    Result.Data[I] := Data[I];
  Result.Text := Text;
end;

function Encode(const Rec: tICSRecord; Count: Integer; DNode, SNode: tNode;
  var Frame: string): tChResult;
var
  Buf: array[0..ICSMaxFrame - 1] of Byte;
  N: Word;
begin
  N := 0;
  Result := ICSEncode(Rec, ICSHeadLen + Count * 2, DNode, SNode, Buf, SizeOf(Buf), N);
  SetLength(Frame, N);
  if N > 0 then
    Move(Buf, Frame[1], N);
end;

{ Feed S to a fresh automaton: one word per event, 'F' for a frame,
  'E<hex code>' for an error, e.g. 'E22 F'. The last frame is left in St. }
function Events(const S: string; var St: tICSState): string;
var
  I: Integer;
begin
  ICSReset(St);
  Result := '';
  for I := 1 to Length(S) do
    case ICSFeed(St, Ord(S[I])) of
      icsFrame: Result := Result + ' F';
      icsError: Result := Result + ' E' + IntToHex(St.Error, 2);
    end;
  Result := Trim(Result);
end;

function Events(const S: string): string;
var
  St: tICSState;
begin
  Result := Events(S, St);
end;

{ A frame with header 2 <- 1 'RD' block 0 and the given field between
  ',' and ETX, with a correct SUM (Xor8Block from the foundation). }
function WithField(const Field: string): string;
var
  Body: string;
begin
  Body := #1'2'#2'1RD0,' + Field + #3;
  Result := #1#1 + Body + Chr(Xor8Block(Body[1], Length(Body))) + #4;
end;

function Sample(Count: Integer): string;
var
  I: Integer;
begin
  Result := '';
  for I := 1 to Count do
  begin
    if I > 1 then
      Result := Result + ',';
    Result := Result + IntToStr(I);
  end;
end;

procedure TTestChnICSCodec.TestRecordLayout;
var
  R: tICSRecord;
begin
  AssertEquals('SizeOf(tICSRecord)', 269, SizeOf(tICSRecord));
  AssertEquals('SizeOf(tICSData)', 2, SizeOf(tICSData));
  AssertEquals('OpCode', 0, PtrUInt(@R.OpCode) - PtrUInt(@R));
  AssertEquals('BlockNum', 3, PtrUInt(@R.BlockNum) - PtrUInt(@R));
  AssertEquals('Data', 4, PtrUInt(@R.Data) - PtrUInt(@R));
  AssertEquals('Text', 68, PtrUInt(@R.Text) - PtrUInt(@R));
  AssertEquals('SizeOf(BlockNum)', 1, SizeOf(R.BlockNum));
  AssertEquals('longest frame', 436, ICSMaxFrame);
end;

procedure TTestChnICSCodec.TestCountOfLen;
begin
  AssertEquals(0, ICSCountOfLen(4));
  AssertEquals(3, ICSCountOfLen(10));
  AssertEquals(32, ICSCountOfLen(68));
  AssertEquals('33 numbers', -1, ICSCountOfLen(70));
  AssertEquals('odd', -1, ICSCountOfLen(5));
  AssertEquals('short', -1, ICSCountOfLen(3));
  AssertEquals(-1, ICSCountOfLen(0));
  AssertEquals(10, ICSLenOfCount(3));
end;

procedure TTestChnICSCodec.TestEncodeManualRequest;
var
  F: string;
begin
  AssertEquals(res_Ok, Encode(MakeRec('RD', 0, [0, 10, 15], ''), 3, 2, 1, F));
  AssertEquals(Hex(FrameA), Hex(F));
end;

procedure TTestChnICSCodec.TestEncodeReplyWithText;
var
  F: string;
begin
  AssertEquals(res_Ok, Encode(MakeRec('DB', 0, [-1, 32767], '"ok"'), 2, 1, 2, F));
  AssertEquals(Hex(FrameB), Hex(F));
end;

procedure TTestChnICSCodec.TestEncodeNoDataHighestNode;
var
  F: string;
begin
  AssertEquals(res_Ok, Encode(MakeRec('RL', 9, [], ''), 0, 0, 207, F));
  AssertEquals(Hex(FrameC), Hex(F));
end;

procedure TTestChnICSCodec.TestEncodeLowestNumber;
var
  F: string;
begin
  AssertEquals(res_Ok, Encode(MakeRec('WD', 1, [-32768], ''), 1, 5, 1, F));
  AssertEquals(Hex(FrameD), Hex(F));
end;

procedure TTestChnICSCodec.TestDecodeHandFrames;
var
  St: tICSState;
begin
  AssertEquals('F', Events(FrameA, St));
  AssertEquals('RD', St.Rec.OpCode);
  AssertEquals(0, St.Rec.BlockNum);
  AssertEquals(3, St.Count);
  AssertEquals(10, ICSRecLen(St));
  AssertEquals(0, St.Rec.Data[0]);
  AssertEquals(10, St.Rec.Data[1]);
  AssertEquals(15, St.Rec.Data[2]);
  AssertEquals('unused numbers are 0', 0, St.Rec.Data[3]);
  AssertEquals('', St.Rec.Text);
  AssertEquals('DNO', 2, St.DNode);
  AssertEquals('SNO', 1, St.SNode);

  AssertEquals('F', Events(FrameB, St));
  AssertEquals('DB', St.Rec.OpCode);
  AssertEquals(2, St.Count);
  AssertEquals(-1, St.Rec.Data[0]);
  AssertEquals(32767, St.Rec.Data[1]);
  AssertEquals('text kept with its delimiters', '"ok"', St.Rec.Text);
  AssertEquals(1, St.DNode);
  AssertEquals(2, St.SNode);

  AssertEquals('F', Events(FrameC, St));
  AssertEquals('RL', St.Rec.OpCode);
  AssertEquals(9, St.Rec.BlockNum);
  AssertEquals(0, St.Count);
  AssertEquals(4, ICSRecLen(St));
  AssertEquals(0, St.DNode);
  AssertEquals(207, St.SNode);

  AssertEquals('F', Events(FrameD, St));
  AssertEquals(-32768, St.Rec.Data[0]);
  AssertEquals(5, St.DNode);
end;

procedure TTestChnICSCodec.TestAnyNumberOfLeadingSOH;
begin
  AssertEquals('one SOH', 'F', Events(#1 + BodyA));
  { with two SOH a sum taken from the first SOH would be 3C xor 01 = 3D }
  AssertEquals('two SOH, sum from the last one', 'F', Events(#1#1 + BodyA));
  AssertEquals('seven SOH', 'F', Events(#1#1#1#1#1#1#1 + BodyA));
  AssertEquals('no SOH: nothing', '', Events(BodyA));
  AssertEquals('two frames back to back', 'F F', Events(FrameA + FrameB));
end;

procedure TTestChnICSCodec.TestNoiseBeforeFrame;
begin
  AssertEquals('F', Events('xyz'#0#2#3#4#$FF + FrameA));
  AssertEquals('noise between frames', 'F F', Events(FrameA + 'garbage'#3#4 + FrameC));
end;

procedure TTestChnICSCodec.TestExtraCommasAccepted;
var
  St: tICSState;
begin
  AssertEquals('F', Events(WithField(',,1,,,2,'), St));
  AssertEquals(2, St.Count);
  AssertEquals(1, St.Rec.Data[0]);
  AssertEquals(2, St.Rec.Data[1]);
  AssertEquals('F', Events(WithField('7,''t'''), St));
  AssertEquals(1, St.Count);
  AssertEquals('''t''', St.Rec.Text);
  AssertEquals('F', Events(WithField(',,'), St));
  AssertEquals(0, St.Count);
end;

procedure TTestChnICSCodec.TestNumberForms;
var
  St: tICSState;
begin
  AssertEquals('F', Events(WithField('+7,-0,007,-32768,32767,+32767'), St));
  AssertEquals(6, St.Count);
  AssertEquals(7, St.Rec.Data[0]);
  AssertEquals(0, St.Rec.Data[1]);
  AssertEquals(7, St.Rec.Data[2]);
  AssertEquals(-32768, St.Rec.Data[3]);
  AssertEquals(32767, St.Rec.Data[4]);
  AssertEquals(32767, St.Rec.Data[5]);
  { 31 characters is the longest number text }
  AssertEquals('F', Events(WithField(StringOfChar('0', 30) + '9'), St));
  AssertEquals(9, St.Rec.Data[0]);
end;

procedure TTestChnICSCodec.TestRoundTripCounts;
const
  Counts: array[0..2] of Integer = (0, 1, 32);
  Texts: array[0..1] of string = ('', '#Pozadavek na cteni dat#');
var
  C, T, I: Integer;
  R: tICSRecord;
  F: string;
  St: tICSState;
begin
  for C := Low(Counts) to High(Counts) do
    for T := Low(Texts) to High(Texts) do
    begin
      R := MakeRec('WD', 7, [], Texts[T]);
      for I := 0 to Counts[C] - 1 do
        case I mod 4 of
          0: R.Data[I] := -32768;
          1: R.Data[I] := 32767;
          2: R.Data[I] := -I;
          3: R.Data[I] := I * 1000;
        end;
      AssertEquals(res_Ok, Encode(R, Counts[C], 3, 4, F));
      AssertEquals('count ' + IntToStr(Counts[C]), 'F', Events(F, St));
      AssertEquals(Counts[C], St.Count);
      AssertEquals(ICSLenOfCount(Counts[C]), ICSRecLen(St));
      AssertEquals('WD', St.Rec.OpCode);
      AssertEquals(7, St.Rec.BlockNum);
      AssertEquals(Texts[T], St.Rec.Text);
      for I := 0 to Counts[C] - 1 do
        AssertEquals('number ' + IntToStr(I), R.Data[I], St.Rec.Data[I]);
    end;
end;

procedure TTestChnICSCodec.TestEveryDelimiter;
var
  C: Char;
  Inner: Char;
  F, Ev: string;
  St: tICSState;
begin
  for C := #0 to #255 do
  begin
    if C = 'x' then Inner := 'y' else Inner := 'x';
    if C in Forbidden then
    begin
      AssertEquals('send refuses delimiter #' + IntToStr(Ord(C)), res_BadMessage,
        Encode(MakeRec('RD', 0, [1], C + Inner + C), 1, 2, 1, F));
      AssertEquals('nothing encoded', '', F);
      { the same bytes on the line never make a frame }
      Ev := Events(WithField('1' + C + Inner + C), St);
      AssertTrue('receive refuses delimiter #' + IntToStr(Ord(C)) + ': ' + Ev,
        (Ev <> '') and (Pos('F', Ev) = 0));
    end
    else
    begin
      AssertEquals('delimiter #' + IntToStr(Ord(C)), res_Ok,
        Encode(MakeRec('RD', 0, [1], C + Inner + C), 1, 2, 1, F));
      AssertEquals('delimiter #' + IntToStr(Ord(C)), 'F', Events(F, St));
      AssertEquals(C + Inner + C, St.Rec.Text);
      AssertEquals(1, St.Count);
      { an empty text (two delimiters) is a text too }
      AssertEquals(res_Ok, Encode(MakeRec('RD', 0, [], C + C), 0, 2, 1, F));
      AssertEquals('F', Events(F, St));
      AssertEquals(C + C, St.Rec.Text);
    end;
  end;
end;

procedure TTestChnICSCodec.TestEveryInnerTextCharacter;
var
  C: Char;
  F, Ev: string;
  St: tICSState;
begin
  for C := #0 to #255 do
    if C = '"' then
      AssertEquals('the delimiter inside', res_BadMessage,
        Encode(MakeRec('RD', 0, [], '"a"b"'), 0, 2, 1, F))
    else if C < #$20 then
    begin
      AssertEquals('send refuses inner #' + IntToStr(Ord(C)), res_BadMessage,
        Encode(MakeRec('RD', 0, [], '"a' + C + 'b"'), 0, 2, 1, F));
      Ev := Events(WithField('"a' + C + 'b"'), St);
      AssertTrue('receive refuses inner #' + IntToStr(Ord(C)) + ': ' + Ev,
        (Ev <> '') and (Pos('F', Ev) = 0));
    end
    else
    begin
      AssertEquals('inner #' + IntToStr(Ord(C)), res_Ok,
        Encode(MakeRec('RD', 0, [], '"a' + C + 'b"'), 0, 2, 1, F));
      AssertEquals('inner #' + IntToStr(Ord(C)), 'F', Events(F, St));
      AssertEquals('"a' + C + 'b"', St.Rec.Text);
    end;
end;

procedure TTestChnICSCodec.TestErrSum;
var
  Bad: string;
begin
  Bad := FrameA;
  Bad[Length(Bad) - 1] := #$3D;
  AssertEquals('E21', Events(Bad));
  AssertEquals('then the next frame', 'E21 F', Events(Bad + FrameB));
  { a changed data byte: same structure, wrong sum }
  Bad := FrameA;
  Bad[Pos('15', Bad)] := '2';
  AssertEquals('E21', Events(Bad));
  { a SUM byte of $01 is a SUM, not a new frame }
  AssertEquals('E21 F', Events(#1'2'#2'1RD0,'#3#1#4 + FrameA));
end;

procedure TTestChnICSCodec.TestErrFrame;
begin
  AssertEquals('missing STX', 'E20 F', Events(#1'2X1RD0,1'#3#0#4 + FrameA));
  AssertEquals('DNO below "0"', 'E20 F', Events(#1'/'#2'1RD0,1'#3#0#4 + FrameA));
  AssertEquals('SNO below "0"', 'E20 F', Events(#1'2'#2' RD0,1'#3#0#4 + FrameA));
  AssertEquals('SNO control', 'E20 F', Events(#1'2'#2#5'RD0,1'#3#0#4 + FrameA));
  AssertEquals('op code 1 control', 'E20 F', Events(#1'2'#2'1'#5'D0,1'#3#0#4 + FrameA));
  AssertEquals('op code 2 control', 'E20 F', Events(#1'2'#2'1R'#$1F'0,1'#3#0#4 + FrameA));
  AssertEquals('block not a digit', 'E20 F', Events(#1'2'#2'1RDA,1'#3#0#4 + FrameA));
  AssertEquals('two-digit block', 'E20 F', Events(#1'2'#2'1RD10,1'#3#0#4 + FrameA));
  AssertEquals('missing comma before ETX', 'E20 F', Events(#1'2'#2'1RD0'#3#0#4 + FrameA));
  AssertEquals('missing comma before text', 'E20 F', Events(#1'2'#2'1RD0"a"'#3#0#4 + FrameA));
  AssertEquals('control in text', 'E20 F', Events(WithField('"a'#5'b"') + FrameA));
  AssertEquals('ETX inside text', 'E20 F', Events(#1'2'#2'1RD0,"ab'#3#0#4 + FrameA));
end;

procedure TTestChnICSCodec.TestErrLen;
var
  Ev: string;
begin
  AssertEquals('32 numbers', 'F', Events(WithField(Sample(32))));
  AssertEquals('33 numbers', 'E22 F', Events(WithField(Sample(33)) + FrameA));
  AssertEquals('33 numbers, extra commas', 'E22', Events(WithField(Sample(32) + ',,0')));
  { reported at the 33rd number's first character, not when it ends }
  AssertEquals('33rd number cut short', 'E22', Events(#1'2'#2'1RD0,' + Sample(32) + ',7'));
  AssertEquals('200 characters of text', 'F',
    Events(WithField('"' + StringOfChar('t', 198) + '"')));
  Ev := Events(WithField('"' + StringOfChar('t', 199) + '"') + FrameA);
  AssertEquals('201 characters of text', 'E22 F', Ev);
  AssertEquals('long unterminated text', 'E22',
    Events(WithField('"' + StringOfChar('t', 250))));
end;

procedure TTestChnICSCodec.TestErrVal;
const
  Bad: array[0..11] of string = ('--5', '5-', '1+1', '+', '-', '.', '5.3',
    '32768', '-32769', '99999999999', '1,2,--5', '+-1');
var
  I: Integer;
begin
  AssertEquals('E23', Events(WithField(Bad[0])));
  for I := Low(Bad) to High(Bad) do
    AssertEquals(Bad[I], 'E23 F', Events(WithField(Bad[I]) + FrameA));
  AssertEquals('bad number before text', 'E23', Events(WithField('5-"t"')));
  AssertEquals('32 characters of number', 'E23',
    Events(WithField(StringOfChar('0', 31) + '9')));
end;

procedure TTestChnICSCodec.TestErrETX;
begin
  AssertEquals('byte after the text', 'E24 F', Events(WithField('"ab"X') + FrameA));
  AssertEquals('number after the text', 'E24', Events(WithField('"ab"5')));
  AssertEquals('control after a number', 'E24 F', Events(#1'2'#2'1RD0,12'#5#3#0#4 + FrameA));
  AssertEquals('control between numbers', 'E24', Events(#1'2'#2'1RD0,1,'#4#3#0#4));
  AssertEquals('EOT instead of ETX', 'E24', Events(#1'2'#2'1RD0,'#4));
end;

procedure TTestChnICSCodec.TestErrEOT;
var
  Bad: string;
begin
  Bad := FrameA;
  Bad[Length(Bad)] := 'X';
  AssertEquals('E25 F', Events(Bad + FrameB));
  Bad[Length(Bad)] := #3;
  AssertEquals('E25', Events(Bad));
  { EOT missing and SUM wrong: the EOT error is the one reported }
  Bad := FrameA;
  Bad[Length(Bad) - 1] := #0;
  Bad[Length(Bad)] := #0;
  AssertEquals('E25', Events(Bad));
  { an SOH where EOT belongs starts the next frame }
  Bad := Copy(FrameA, 1, Length(FrameA) - 1);
  AssertEquals('E25 F', Events(Bad + #1 + BodyA));
end;

procedure TTestChnICSCodec.TestSOHInsideFrameStartsNextFrame;
var
  F: string;
begin
  { one SOH only: the SOH that breaks a frame must itself start the next }
  AssertEquals('after DNO', 'E20 F', Events(#1'2' + #1 + BodyA));
  AssertEquals('in the op code', 'E20 F', Events(#1'2'#2'1R' + #1 + BodyA));
  AssertEquals('in the data', 'E24 F', Events(#1'2'#2'1RD0,12' + #1 + BodyA));
  AssertEquals('in the text', 'E20 F', Events(#1'2'#2'1RD0,"ab' + #1 + BodyA));
  AssertEquals('after the text', 'E24 F', Events(#1'2'#2'1RD0,"ab"' + #1 + BodyA));
  F := WithField(Sample(33));
  AssertEquals('33rd number, then SOH: one error', 'E22 F',
    Events(Copy(F, 1, Length(F) - 3) + #1 + BodyA));
end;

procedure TTestChnICSCodec.TestEncodeRefusesBadRecords;
var
  R: tICSRecord;
  F: string;
  Buf: array[0..ICSMaxFrame - 1] of Byte;
  N: Word;
begin
  R := MakeRec('RD', 0, [1, 2], '"t"');
  AssertEquals('valid', res_Ok, Encode(R, 2, 207, 207, F));
  AssertEquals('DNO 208', res_BadMessage, Encode(R, 2, 208, 1, F));
  AssertEquals('', F);
  AssertEquals('SNO 208', res_BadMessage, Encode(R, 2, 1, 208, F));
  AssertEquals('count 33', ICS_ErrLen, Encode(R, 33, 1, 2, F));
  AssertEquals('', F);
  N := 7;
  AssertEquals('Len 5', ICS_ErrLen, ICSEncode(R, 5, 1, 2, Buf, SizeOf(Buf), N));
  AssertEquals(0, N);
  AssertEquals('Len 3', ICS_ErrLen, ICSEncode(R, 3, 1, 2, Buf, SizeOf(Buf), N));
  R := MakeRec('RD', 0, [1, 2], '"t"');
  PByte(@R.BlockNum)^ := 10;
  AssertEquals('block 10', res_BadMessage, Encode(R, 2, 1, 2, F));
  R := MakeRec('R', 0, [], '');
  AssertEquals('one-letter op code', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec('', 0, [], '');
  AssertEquals('empty op code', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec('R'#3, 0, [], '');
  AssertEquals('op code with ETX', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec(#$1F'D', 0, [], '');
  AssertEquals('op code with $1F', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec(#$20#$FF, 0, [], '');
  AssertEquals('op code " " #$FF', res_Ok, Encode(R, 0, 1, 2, F));
  R := MakeRec('RD', 0, [], '"');
  AssertEquals('text of one delimiter', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec('RD', 0, [], '"ab''');
  AssertEquals('different delimiters', res_BadMessage, Encode(R, 0, 1, 2, F));
  R := MakeRec('RD', 0, [], '"' + StringOfChar('t', 198) + '"');
  AssertEquals('200 characters', res_Ok, Encode(R, 0, 1, 2, F));
  { a text length byte above 200, as a record from a file could hold }
  PByte(@R.Text)^ := 201;
  PChar(@R.Text)[200] := 't';
  PChar(@R.Text)[201] := '"';     { the byte after the record's Text field }
  AssertEquals('201 characters', ICS_ErrLen, Encode(R, 0, 1, 2, F));
  AssertEquals('', F);
end;

procedure TTestChnICSCodec.TestEncodeSmallBuffer;
var
  Buf: array[0..63] of Byte;
  N: Word;
  R: tICSRecord;
  I: Integer;
begin
  R := MakeRec('RD', 0, [0, 10, 15], '');
  FillChar(Buf, SizeOf(Buf), $AA);
  N := 99;
  AssertEquals(res_TooLong, ICSEncode(R, 10, 2, 1, Buf, Length(FrameA) - 1, N));
  AssertEquals(0, N);
  for I := 0 to High(Buf) do
    AssertEquals('buffer untouched', $AA, Buf[I]);
  AssertEquals(res_Ok, ICSEncode(R, 10, 2, 1, Buf, Length(FrameA), N));
  AssertEquals(Length(FrameA), N);
  AssertEquals('byte after the frame untouched', $AA, Buf[N]);
  { a refused record leaves the buffer alone as well }
  FillChar(Buf, SizeOf(Buf), $AA);
  AssertEquals(res_BadMessage, ICSEncode(R, 10, 208, 1, Buf, SizeOf(Buf), N));
  AssertEquals($AA, Buf[0]);
end;

function RandomRecord(var Count: Integer): tICSRecord;
var
  I, L: Integer;
  D: Char;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.OpCode := Chr(32 + Random(224)) + Chr(32 + Random(224));
  Result.BlockNum := Random(10);
  Count := Random(ICSMaxDataLen + 1);
  for I := 0 to Count - 1 do
    Result.Data[I] := Random(65536) - 32768;
  if Random(3) > 0 then
  begin
    repeat
      D := Chr(32 + Random(224));
    until not (D in Forbidden);
    L := Random(ICSMaxTextLen - 1);          { inner characters 0..198 }
    Result.Text := D;
    for I := 1 to L do
      repeat
        Result.Text := Result.Text + Chr(32 + Random(224));
        if Result.Text[Length(Result.Text)] = D then
          SetLength(Result.Text, Length(Result.Text) - 1);
      until Length(Result.Text) = I + 1;
    Result.Text := Result.Text + D;
  end;
end;

procedure TTestChnICSCodec.TestRandomRoundTrip;
var
  Iter, Count, I, DN, SN: Integer;
  R: tICSRecord;
  F, Noise, Ev: string;
  St: tICSState;
begin
  RandSeed := 20261121;
  for Iter := 1 to 3000 do
  begin
    R := RandomRecord(Count);
    DN := Random(ICSMaxNode + 1);
    SN := Random(ICSMaxNode + 1);
    AssertEquals(res_Ok, Encode(R, Count, DN, SN, F));
    { noise without SOH in front must be skipped }
    Noise := '';
    for I := 1 to Random(5) do
      Noise := Noise + Chr(2 + Random(254));
    Ev := Events(Noise + F, St);
    AssertEquals('iteration ' + IntToStr(Iter), 'F', Ev);
    AssertEquals(R.OpCode, St.Rec.OpCode);
    AssertEquals(R.BlockNum, St.Rec.BlockNum);
    AssertEquals(Count, St.Count);
    AssertEquals(R.Text, St.Rec.Text);
    AssertEquals(DN, St.DNode);
    AssertEquals(SN, St.SNode);
    for I := 0 to Count - 1 do
      AssertEquals(R.Data[I], St.Rec.Data[I]);
  end;
end;

procedure TTestChnICSCodec.TestRandomCorruptionNeverAccepted;
var
  Iter, Count, P: Integer;
  R: tICSRecord;
  F, Ev: string;
begin
  RandSeed := 4711;
  for Iter := 1 to 3000 do
  begin
    R := RandomRecord(Count);
    AssertEquals(res_Ok, Encode(R, Count, Random(208), Random(208), F));
    { any byte after the first two SOH changed to another value: the XOR
      sum, the structure or the EOT check must catch it }
    P := 3 + Random(Length(F) - 2);
    F[P] := Chr((Ord(F[P]) + 1 + Random(255)) and $FF);
    Ev := Events(F);
    AssertTrue('iteration ' + IntToStr(Iter) + ' byte ' + IntToStr(P) + ': ' + Ev,
      Pos('F', Ev) = 0);
  end;
end;

initialization
  RegisterTest(TTestChnICSCodec);
end.
