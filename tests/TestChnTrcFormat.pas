{ Tests of ChnTrcFormat, the trace text format: the writer reproduces the
  RACOM capture (docs/REFERENCES.md) line for line, the reader reads that capture
  (copied below verbatim, with the prose around it) and every malformed
  input gives its documented result. }
unit TestChnTrcFormat;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnTrcFormat, TestSupport;

type
  TTestChnTrcFormat = class(TTestCase)
  private
    function Read(const Lines: array of string; var F: tTrcFrames; var Skipped: LongInt): LongInt;
  published
    procedure TestTimeText;
    procedure TestHeaderMatchesCapture;
    procedure TestHexLinesMatchCapture;
    procedure TestDecLines;
    procedure TestLineCount;
    procedure TestReadSeedCapture;
    procedure TestSeedCrcFramesCheckOut;
    procedure TestBytesOnHeaderLine;
    procedure TestShortFrameCutByHeader;
    procedure TestShortFrameCutByProse;
    procedure TestShortFrameAtEnd;
    procedure TestLongFrame;
    procedure TestNotAHeader;
    procedure TestBadDataTokens;
    procedure TestDecimalLowerCaseAndCrLf;
    procedure TestTimeFraction;
    procedure TestZeroLength;
    procedure TestStrayDataIsSkipped;
    procedure TestStreamingReader;
    procedure TestRoundTrip;
    procedure TestResultTexts;
  end;

implementation

const
  { RACOM note (DF1 for MORSE), chapter 3, from the first capture
    line on: the capture lines verbatim, the Czech prose between them with
    its diacritics dropped, the '>>' prompts as they are }
  Seed: array[0..58] of string = (
    '13:33:33.058 rx;i  60 | S00',
    '1002 0300 0B00 7E00 0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100',
    '8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401 1003 15C6',
    '13:33:33.065 tx   2 | S00',
    '1006',
    '13:33:33.252 tx   44 | S00',
    '1002 0003 4B00 7E00 0000 D400 0000 3D7F 0080 827F 0080 E943 0100 8D91 1300',
    'E070 7200 E070 7200 0000 1003 0FC9',
    '13:33:33.267 rx;i  2 | S00',
    '1006',
    '13:33:33.299 rx;i  39 | S00',
    '1002 0300 0A00 7F00 0000 3D7F 7F00 4C08 910B 546F 5472 616E 7370 6F72 7400',
    '2800 1010 0010 03B6 99',
    '13:33:33.304 tx   2 | S00',
    '1006',
    '13:33:33.482 tx   56 | S00',
    '1002 0003 4A00 7F00 0000 827F 7F00 CC00 0000 C300 0A1A 0200 0300 0400 0500',
    '0600 0700 0800 0000 0000 0000 0000 0000 0000 0000 0000 1003 854D',
    '13:33:33.500 rx;i  2 | S00',
    '1006',
    '13:33:33.540 rx;i  39 | S00',
    '1002 0300 0B00 8F00 0000 4E02 2006 2401 07E9 E943 0100 8D91 1300 0200 2002',
    '2401 1010 0010 03A3 C4',
    '13:33:33.545 tx   2 | S00',
    '1006',
    '13:33:33.720 tx   28 | S00',
    '1002 0003 4B00 8F00 0000 CE00 0000 E943 0100 8D91 1300 0000 1003 B56A',
    '13:33:33.731 rx;i  2 | S00',
    '1006',
    '',
    'V nasledujicim prikladu neuspesne komunikace je sekvence dodavana z',
    'PLC nahrazena znaky AAAA.',
    '',
    '>>',
    '06:22:58.798 tx   9 | S00',
    '1002 0E0D AAAA 1003 91',
    '06:22:58.813 rx;i  2 | S00',
    '1015',
    '06:22:58.814 tx   9 | S00',
    '1002 0E0D AAAA 1003 91',
    '06:22:58.829 rx;i  2 | S00',
    '1015',
    '',
    'Komunikacni jednotka CU (radiovy modem) vyslala data',
    '',
    '1002 0E0D AAAA 1003 91',
    'do PLC a dostala',
    'odpoved',
    '1015 = NAK (nerozumim)',
    'Proto',
    'je vysilani dat opakovano, v tomto prikladu se stejnym vysledkem.',
    '',
    'Ve druhem prikladu je linka RS232 rozpojena:',
    '',
    '>>',
    '06:23:21.694 tx   9 | S00',
    '1002 0E0D AAAA 1003 91',
    '06:23:22.694 tx   2 | S00',
    '1005');
  SeedProse = 10;   { prose lines above, the stray '1002 0E0D ...' included }

type
  tExpect = record
    Time: string;
    Dir : string;
    Len : Integer;
    Hex : string;
  end;

const
  { the 18 frames of the seed, worked out by hand from the lines above }
  SeedFrames: array[0..17] of tExpect = (
    (Time: '13:33:33.058'; Dir: 'rx;i'; Len: 60; Hex:
      '1002 0300 0B00 7E00 0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100 ' +
      '8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401 1003 15C6'),
    (Time: '13:33:33.065'; Dir: 'tx'; Len: 2; Hex: '10 06'),
    (Time: '13:33:33.252'; Dir: 'tx'; Len: 44; Hex:
      '1002 0003 4B00 7E00 0000 D400 0000 3D7F 0080 827F 0080 E943 0100 8D91 1300 ' +
      'E070 7200 E070 7200 0000 1003 0FC9'),
    (Time: '13:33:33.267'; Dir: 'rx;i'; Len: 2; Hex: '10 06'),
    (Time: '13:33:33.299'; Dir: 'rx;i'; Len: 39; Hex:
      '1002 0300 0A00 7F00 0000 3D7F 7F00 4C08 910B 546F 5472 616E 7370 6F72 7400 ' +
      '2800 1010 0010 03B6 99'),
    (Time: '13:33:33.304'; Dir: 'tx'; Len: 2; Hex: '10 06'),
    (Time: '13:33:33.482'; Dir: 'tx'; Len: 56; Hex:
      '1002 0003 4A00 7F00 0000 827F 7F00 CC00 0000 C300 0A1A 0200 0300 0400 0500 ' +
      '0600 0700 0800 0000 0000 0000 0000 0000 0000 0000 0000 1003 854D'),
    (Time: '13:33:33.500'; Dir: 'rx;i'; Len: 2; Hex: '10 06'),
    (Time: '13:33:33.540'; Dir: 'rx;i'; Len: 39; Hex:
      '1002 0300 0B00 8F00 0000 4E02 2006 2401 07E9 E943 0100 8D91 1300 0200 2002 ' +
      '2401 1010 0010 03A3 C4'),
    (Time: '13:33:33.545'; Dir: 'tx'; Len: 2; Hex: '10 06'),
    (Time: '13:33:33.720'; Dir: 'tx'; Len: 28; Hex:
      '1002 0003 4B00 8F00 0000 CE00 0000 E943 0100 8D91 1300 0000 1003 B56A'),
    (Time: '13:33:33.731'; Dir: 'rx;i'; Len: 2; Hex: '10 06'),
    (Time: '06:22:58.798'; Dir: 'tx'; Len: 9; Hex: '10 02 0E 0D AA AA 10 03 91'),
    (Time: '06:22:58.813'; Dir: 'rx;i'; Len: 2; Hex: '10 15'),
    (Time: '06:22:58.814'; Dir: 'tx'; Len: 9; Hex: '10 02 0E 0D AA AA 10 03 91'),
    (Time: '06:22:58.829'; Dir: 'rx;i'; Len: 2; Hex: '10 15'),
    (Time: '06:23:21.694'; Dir: 'tx'; Len: 9; Hex: '10 02 0E 0D AA AA 10 03 91'),
    (Time: '06:23:22.694'; Dir: 'tx'; Len: 2; Hex: '10 05'));

function Ms(H, M, S, F: LongInt): LongInt;
begin
  Result := ((H * 60 + M) * 60 + S) * 1000 + F;
end;

function TimeOf(const S: string): LongInt;
begin
  Result := Ms(StrToInt(Copy(S, 1, 2)), StrToInt(Copy(S, 4, 2)),
    StrToInt(Copy(S, 7, 2)), StrToInt(Copy(S, 10, 3)));
end;

function Join(const Lines: array of string): AnsiString;
var
  I: Integer;
begin
  Result := '';
  for I := 0 to High(Lines) do
    Result := Result + Lines[I] + #10;
end;

procedure AssertBytes(const Msg: string; const Expected: TBytes; const Got: tTrcBytes);
begin
  TAssert.AssertEquals(Msg + ' length', Length(Expected), Length(Got));
  TAssert.AssertEquals(Msg, BytesToHex(Expected, Length(Expected)), BytesToHex(Got, Length(Got)));
end;

function TTestChnTrcFormat.Read(const Lines: array of string; var F: tTrcFrames;
  var Skipped: LongInt): LongInt;
begin
  Skipped := -1;
  Result := TrcReadText(Join(Lines), F, Skipped);
  AssertEquals('Frames holds exactly the frames', Result, Length(F));
end;

procedure TTestChnTrcFormat.TestTimeText;
begin
  AssertEquals('00:00:00.000', TrcTimeText(0));
  AssertEquals('13:33:33.058', TrcTimeText(Ms(13, 33, 33, 58)));
  AssertEquals('06:22:58.798', TrcTimeText(Ms(6, 22, 58, 798)));
  AssertEquals('23:59:59.999', TrcTimeText(TrcMsPerDay - 1));
  AssertEquals('a day later is midnight', '00:00:00.001', TrcTimeText(TrcMsPerDay + 1));
  AssertEquals('negative wraps', '23:59:59.999', TrcTimeText(-1));
end;

procedure TTestChnTrcFormat.TestHeaderMatchesCapture;
begin
  { the capture's own header lines }
  AssertEquals('13:33:33.065 tx   2 | S00', TrcHeader(Ms(13, 33, 33, 65), trcTx, 2, 'S00'));
  AssertEquals('13:33:33.252 tx   44 | S00', TrcHeader(Ms(13, 33, 33, 252), trcTx, 44, 'S00'));
  AssertEquals('06:22:58.798 tx   9 | S00', TrcHeader(Ms(6, 22, 58, 798), trcTx, 9, 'S00'));
  { rx has no ';i' tag of its own: padded like tx }
  AssertEquals('13:33:33.058 rx   60 | TRC', TrcHeader(Ms(13, 33, 33, 58), trcRx, 60, 'TRC'));
  AssertEquals('no tag', '00:00:01.000 rx   65535 |', TrcHeader(1000, trcRx, 65535, ''));
end;

procedure TTestChnTrcFormat.TestHexLinesMatchCapture;
var
  B: TBytes;
begin
  { 60 bytes: two full lines of 15 groups }
  B := HexToBytes(SeedFrames[0].Hex);
  AssertEquals(2, TrcLineCount(Length(B), trcHex));
  AssertEquals(Seed[1], TrcDataLine(B[0], Length(B), 0, trcHex));
  AssertEquals(Seed[2], TrcDataLine(B[0], Length(B), 1, trcHex));
  { 39 bytes: the odd last byte is a group of two digits }
  B := HexToBytes(SeedFrames[4].Hex);
  AssertEquals(2, TrcLineCount(Length(B), trcHex));
  AssertEquals(Seed[11], TrcDataLine(B[0], Length(B), 0, trcHex));
  AssertEquals(Seed[12], TrcDataLine(B[0], Length(B), 1, trcHex));
  { 56 and 9 bytes }
  B := HexToBytes(SeedFrames[6].Hex);
  AssertEquals(Seed[16], TrcDataLine(B[0], Length(B), 0, trcHex));
  AssertEquals(Seed[17], TrcDataLine(B[0], Length(B), 1, trcHex));
  B := HexToBytes(SeedFrames[12].Hex);
  AssertEquals(Seed[35], TrcDataLine(B[0], Length(B), 0, trcHex));
  { a whole entry }
  B := HexToBytes('10 06');
  AssertEquals('13:33:33.065 tx   2 | S00' + LineEnding + '1006' + LineEnding,
    TrcFormat(Ms(13, 33, 33, 65), trcTx, B[0], 2, trcHex, 'S00'));
  B := HexToBytes(SeedFrames[0].Hex);
  AssertEquals('the capture, but for the ;i tag',
    Seed[0] + LineEnding + Seed[1] + LineEnding + Seed[2] + LineEnding,
    StringReplace(TrcFormat(Ms(13, 33, 33, 58), trcRx, B[0], 60, trcHex, 'S00'),
      ' rx   60', ' rx;i  60', []));
end;

procedure TTestChnTrcFormat.TestDecLines;
var
  B: TBytes;
  I: Integer;
begin
  B := HexToBytes('00 01 09 0A 63 64 FF 10');
  AssertEquals('000 001 009 010 099 100 255 016', TrcDataLine(B[0], Length(B), 0, trcDec));
  SetLength(B, 21);
  for I := 0 to 20 do
    B[I] := 200 + I;
  AssertEquals(2, TrcLineCount(21, trcDec));
  AssertEquals('200 201 202 203 204 205 206 207 208 209 210 211 212 213 214 215 216 217 218 219',
    TrcDataLine(B[0], 21, 0, trcDec));
  AssertEquals('220', TrcDataLine(B[0], 21, 1, trcDec));
  AssertEquals('00:00:00.000 rx   1 | X' + LineEnding + '200' + LineEnding,
    TrcFormat(0, trcRx, B[0], 1, trcDec, 'X'));
end;

procedure TTestChnTrcFormat.TestLineCount;
begin
  AssertEquals(0, TrcLineCount(0, trcHex));
  AssertEquals(1, TrcLineCount(1, trcHex));
  AssertEquals(1, TrcLineCount(30, trcHex));
  AssertEquals(2, TrcLineCount(31, trcHex));
  AssertEquals(2185, TrcLineCount(65535, trcHex));
  AssertEquals(1, TrcLineCount(20, trcDec));
  AssertEquals(2, TrcLineCount(21, trcDec));
end;

procedure TTestChnTrcFormat.TestReadSeedCapture;
var
  F: tTrcFrames;
  N, Skipped: LongInt;
  I: Integer;
  Msg: string;
begin
  F := nil;
  N := Read(Seed, F, Skipped);
  AssertEquals('frames in the seed', 18, N);
  AssertEquals('prose lines skipped', SeedProse, Skipped);
  for I := 0 to N - 1 do
  begin
    Msg := 'frame ' + IntToStr(I) + ' ';
    AssertEquals(Msg + 'time', TimeOf(SeedFrames[I].Time), F[I].TimeMs);
    AssertEquals(Msg + 'dir text', SeedFrames[I].Dir, F[I].DirText);
    if SeedFrames[I].Dir = 'tx' then
      AssertTrue(Msg + 'dir', F[I].Dir = trcTx)
    else
      AssertTrue(Msg + 'dir', F[I].Dir = trcRx);
    AssertEquals(Msg + 'tag', 'S00', F[I].Tag);
    AssertEquals(Msg + 'len', SeedFrames[I].Len, F[I].Len);
    AssertEquals(Msg + 'status', res_Ok, F[I].Status);
    AssertBytes(Msg + 'bytes', HexToBytes(SeedFrames[I].Hex), F[I].Data);
  end;
  AssertEquals('header line numbers', 1, F[0].Line);
  AssertEquals('header line numbers', 35, F[12].Line);
  AssertEquals('the ENQ', 58, F[17].Line);
end;

{ Independent check of the bytes read: the six CRC frames carry a valid
  DF1 CRC-16 (over the unstuffed DST..DATA plus ETX), the BCC frame a valid
  BCC. }
procedure TTestChnTrcFormat.TestSeedCrcFramesCheckOut;
var
  F: tTrcFrames;
  Skipped: LongInt;
  I, J, K: Integer;
  D: array of Byte;
  Crc: tCrc16;
  CrcFrames: Integer;
begin
  F := nil;
  Read(Seed, F, Skipped);
  CrcFrames := 0;
  for I := 0 to 11 do
    if Length(F[I].Data) > 2 then
    begin
      SetLength(D, Length(F[I].Data));
      K := 0;
      J := 2;
      while J < Length(F[I].Data) - 4 do
      begin
        D[K] := F[I].Data[J];
        Inc(K);
        if F[I].Data[J] = $10 then
          Inc(J, 2)
        else
          Inc(J);
      end;
      D[K] := $03;                       { the CRC covers ETX }
      Crc := Crc16Block(D[0], K + 1, 0);
      AssertEquals('CRC of frame ' + IntToStr(I),
        F[I].Data[Length(F[I].Data) - 2] + 256 * F[I].Data[Length(F[I].Data) - 1], Crc);
      Inc(CrcFrames);
    end;
  AssertEquals(6, CrcFrames);
  AssertEquals('BCC frame', F[12].Data[8], Bcc8Block(F[12].Data[2], 4));
end;

procedure TTestChnTrcFormat.TestBytesOnHeaderLine;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  { the shape in the issue text: bytes right after '|' }
  AssertEquals(2, Read(['13:33:33.058 rx 2 | 1006',
    '13:33:33.060 tx 4 | 1002',
    '0300'], F, Skipped));
  AssertEquals(0, Skipped);
  AssertEquals('', F[0].Tag);
  AssertBytes('inline', HexToBytes('10 06'), F[0].Data);
  AssertEquals(res_Ok, F[0].Status);
  AssertBytes('inline + continuation', HexToBytes('10 02 03 00'), F[1].Data);
  AssertEquals(res_Ok, F[1].Status);
  { without '|' at all }
  AssertEquals(1, Read(['06:22:58.813 rx 2 1015'], F, Skipped));
  AssertBytes('no bar', HexToBytes('10 15'), F[0].Data);
end;

procedure TTestChnTrcFormat.TestShortFrameCutByHeader;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(2, Read([Seed[0], Seed[1], Seed[3], Seed[4]], F, Skipped));
  AssertEquals(res_TrcShort, F[0].Status);
  AssertEquals(60, F[0].Len);
  AssertEquals('the bytes that were there', 30, Length(F[0].Data));
  AssertEquals(res_Ok, F[1].Status);
  AssertBytes('next frame intact', HexToBytes('10 06'), F[1].Data);
end;

procedure TTestChnTrcFormat.TestShortFrameCutByProse;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(1, Read(['13:33:33.058 rx 4 | S00', '1002', 'hello world', '0300'], F, Skipped));
  AssertEquals(res_TrcShort, F[0].Status);
  AssertBytes('short', HexToBytes('10 02'), F[0].Data);
  AssertEquals('prose and the stray data line', 2, Skipped);
end;

procedure TTestChnTrcFormat.TestShortFrameAtEnd;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(1, Read([Seed[10], Seed[11]], F, Skipped));
  AssertEquals(res_TrcShort, F[0].Status);
  AssertEquals(30, Length(F[0].Data));
  { a header with no data line at all }
  AssertEquals(1, Read(['13:33:33.058 tx 2 | S00'], F, Skipped));
  AssertEquals(res_TrcShort, F[0].Status);
  AssertEquals(0, Length(F[0].Data));
end;

procedure TTestChnTrcFormat.TestLongFrame;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(2, Read(['13:33:33.058 tx 3 | S00', '1002 0300', Seed[3], Seed[4]], F, Skipped));
  AssertEquals(res_TrcLong, F[0].Status);
  AssertBytes('all bytes kept', HexToBytes('10 02 03 00'), F[0].Data);
  AssertEquals(res_Ok, F[1].Status);
end;

procedure TTestChnTrcFormat.TestNotAHeader;
const
  Bad: array[0..12] of string = (
    '24:00:00.000 tx 2 | S00',       { hour out of range }
    '13:60:00.000 tx 2 | S00',
    '13:33:60.000 tx 2 | S00',
    '13:33:33 tx 2 | S00',           { no fraction }
    '13:3:33.058 tx 2 | S00',
    '13:33:33.1234567 tx 2 | S00',   { more than 6 fraction digits }
    '13:33:33.058 tz 2 | S00',
    '13:33:33.058 txt 2 | S00',
    '13:33:33.058 tx 65536 | S00',   { longer than any chunk }
    '13:33:33.058 tx -2 | S00',
    '13:33:33.058 tx $10 | S00',
    '13:33:33.058 tx | S00',
    '13:33:33.058 tx;0123456789abc 2 | S00');  { 16 characters: DirText holds 15 }
var
  F: tTrcFrames;
  Skipped: LongInt;
  I: Integer;
begin
  F := nil;
  for I := 0 to High(Bad) do
  begin
    AssertEquals(Bad[I], 0, Read([Bad[I], '1006'], F, Skipped));
    AssertEquals(Bad[I] + ': header and data line skipped', 2, Skipped);
  end;
end;

procedure TTestChnTrcFormat.TestBadDataTokens;
const
  { '$0A', '+12', '-01' are numbers to StrToNum but no decimal data byte }
  Bad: array[0..8] of string = ('1002 0G00', '1002 256', '10020', '1 2', '1002 0300 x', '1002|0300',
    '016 $0A', '016 +12', '016 -01');
var
  F: tTrcFrames;
  Skipped: LongInt;
  I: Integer;
begin
  F := nil;
  for I := 0 to High(Bad) do
  begin
    AssertEquals(Bad[I], 1, Read(['13:33:33.058 tx 4 | S00', Bad[I]], F, Skipped));
    AssertEquals(Bad[I] + ' ends the frame', res_TrcShort, F[0].Status);
    AssertEquals(Bad[I] + ' adds no byte', 0, Length(F[0].Data));
    AssertEquals(Bad[I], 1, Skipped);
  end;
end;

procedure TTestChnTrcFormat.TestDecimalLowerCaseAndCrLf;
var
  F: tTrcFrames;
  N: LongInt;
begin
  F := nil;
  N := TrcReadText('13:33:33.058 tx 3 | TRC'#13#10'016 002 255'#13#10 +
    '>>13:33:33.059 RX 4 | TRC'#13#10'e070 ff'#13#10'0a', F);
  AssertEquals(2, N);
  AssertBytes('decimal', HexToBytes('10 02 FF'), F[0].Data);
  AssertEquals('TRC', F[0].Tag);
  AssertEquals(res_Ok, F[0].Status);
  AssertTrue(F[1].Dir = trcRx);
  AssertEquals('RX', F[1].DirText);
  AssertBytes('lower case, 2-digit groups', HexToBytes('E0 70 FF 0A'), F[1].Data);
  AssertEquals(res_Ok, F[1].Status);
end;

procedure TTestChnTrcFormat.TestTimeFraction;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  Read(['01:02:03.5 tx 0 |', '01:02:03.058123 tx 0 |', '1:02:03.500 tx 0 |'], F, Skipped);
  AssertEquals(2, Length(F));
  AssertEquals(Ms(1, 2, 3, 500), F[0].TimeMs);
  AssertEquals(Ms(1, 2, 3, 58), F[1].TimeMs);
  AssertEquals('one-digit hour is not the format', 1, Skipped);
end;

procedure TTestChnTrcFormat.TestZeroLength;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(1, Read(['13:33:33.058 rx 0 | S00', '1006'], F, Skipped));
  AssertEquals(res_Ok, F[0].Status);
  AssertEquals(0, Length(F[0].Data));
  AssertEquals('data after a complete frame is stray', 1, Skipped);
end;

procedure TTestChnTrcFormat.TestStrayDataIsSkipped;
var
  F: tTrcFrames;
  Skipped: LongInt;
begin
  F := nil;
  AssertEquals(1, Read(['1002 0E0D AAAA 1003 91', Seed[3], Seed[4], '1006', '', '   '], F, Skipped));
  AssertEquals(2, Skipped);
  AssertBytes('the frame', HexToBytes('10 06'), F[0].Data);
end;

procedure TTestChnTrcFormat.TestStreamingReader;
var
  R: tTrcReader;
  I, Total: Integer;
begin
  { a tool reading line by line takes frames as they finish }
  TrcReaderInit(R);
  Total := 0;
  for I := 0 to High(Seed) do
  begin
    TrcReadLine(R, Seed[I]);
    Inc(Total, R.Count);
    if I = 2 then
      AssertEquals('first frame done after its last line', 1, R.Count);
    R.Count := 0;
  end;
  TrcReadEnd(R);
  Inc(Total, R.Count);
  AssertEquals(18, Total);
end;

procedure TTestChnTrcFormat.TestRoundTrip;
var
  B: array of Byte;
  F: tTrcFrames;
  Mode: tTrcMode;
  Len, I, N: LongInt;
  Text: AnsiString;
begin
  F := nil;
  SetLength(B, 65535);
  for I := 0 to High(B) do
    B[I] := (I * 7 + I shr 8) and $FF;
  for Mode := trcHex to trcDec do
    for Len := 0 to 65 do
    begin
      Text := TrcFormat(Ms(9, 8, 7, Len), trcRx, B[0], Len, Mode, 'TRC');
      N := TrcReadText(Text, F);
      AssertEquals('frames', 1, N);
      AssertEquals(Len, F[0].Len);
      AssertEquals(res_Ok, F[0].Status);
      AssertEquals(Ms(9, 8, 7, Len), F[0].TimeMs);
      AssertEquals('TRC', F[0].Tag);
      AssertEquals(Len, Length(F[0].Data));
      if Len > 0 then
        AssertTrue('bytes', CompareByte(B[0], F[0].Data[0], Len) = 0);
    end;
  for Mode := trcHex to trcDec do
  begin
    Text := TrcFormat(0, trcTx, B[0], 65535, Mode, 'TRC') + TrcFormat(1, trcRx, B[1], 1, Mode, 'TRC');
    AssertEquals(2, TrcReadText(Text, F));
    AssertEquals(65535, Length(F[0].Data));
    AssertTrue('64 KiB chunk', CompareByte(B[0], F[0].Data[0], 65535) = 0);
    AssertEquals(res_Ok, F[0].Status);
    AssertEquals(B[1], F[1].Data[0]);
  end;
end;

procedure TTestChnTrcFormat.TestResultTexts;
begin
  AssertTrue(Pos('fewer', ChResultText(res_TrcShort, 'TRC')) > 0);
  AssertTrue(Pos('more', ChResultText(res_TrcLong, 'TRC')) > 0);
end;

initialization
  RegisterTest(TTestChnTrcFormat);
end.
