{ Tests of uString: tokenising, key/value splitting, strict numbers. }
unit TestUString;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, uString, ChnTypes, ChnVirt, ChnNoise;

type
  TTestUString = class(TTestCase)
  published
    procedure TestUpStr;
    procedure TestTokensSkipAnyBlanks;
    procedure TestTokenStartPositions;
    procedure TestSplitKeyValue;
    procedure TestFusedTokenIsRefused;
    procedure TestStrToRealNeverRaises;
    procedure TestNumbersOfEveryLayerNeverRaise;
    procedure TestStrToNumAccepts;
    procedure TestStrToNumRefusesMalformed;
    procedure TestStrToNumRange;
    procedure TestChoiceIndex;
    procedure TestChoiceWord;
    procedure TestHexDigit;
    procedure TestHexBytesPastShortString;
  end;

implementation

procedure TTestUString.TestUpStr;
begin
  AssertEquals('NAM=COM DEV=/DEV/TTYUSB0', UpStr('nam=Com dev=/dev/ttyUSB0'));
  AssertEquals('', UpStr(''));
  AssertEquals('non-ASCII bytes untouched', #$E9'A', UpStr(#$E9'a'));
end;

procedure TTestUString.TestTokensSkipAnyBlanks;
var
  P, N: Integer;
  Tok: ShortString;
  S: ShortString;
begin
  S := '  NAM=DF1'#9'NOD=1 '#13#10' CRC=ON  ';
  P := 1;
  N := 0;
  while NextToken(S, P, Tok) do
  begin
    Inc(N);
    case N of
      1: AssertEquals('NAM=DF1', Tok);
      2: AssertEquals('NOD=1', Tok);
      3: AssertEquals('CRC=ON', Tok);
    end;
  end;
  AssertEquals(3, N);
  P := 1;
  AssertFalse('empty string has no token', NextToken('', P, Tok));
  P := 1;
  AssertFalse('blanks only', NextToken('   ', P, Tok));
end;

procedure TTestUString.TestTokenStartPositions;
var
  P, Start: Integer;
  Tok: ShortString;
begin
  P := 1;
  NextTokenAt('A=1  B=2', P, Tok, Start);
  AssertEquals(1, Start);
  NextTokenAt('A=1  B=2', P, Tok, Start);
  AssertEquals(6, Start);
  AssertEquals('B=2', Tok);
end;

procedure TTestUString.TestSplitKeyValue;
var
  K, V: ShortString;
begin
  AssertTrue(SplitKeyValue('dev=/dev/serial/by-id/usb-FTDI_x-if00-port0', K, V));
  AssertEquals('DEV', K);
  AssertEquals('value keeps its case', '/dev/serial/by-id/usb-FTDI_x-if00-port0', V);
  AssertTrue('empty value splits', SplitKeyValue('BD=', K, V));
  AssertEquals('', V);
  AssertFalse('no =', SplitKeyValue('CRC', K, V));
  AssertFalse('empty key', SplitKeyValue('=5', K, V));
end;

procedure TTestUString.TestFusedTokenIsRefused;
var
  K, V: ShortString;
begin
  { the seed example's 'CRC=ON' + 'NAM=COM' without a blank }
  AssertFalse(SplitKeyValue('CRC=ONNAM=COM', K, V));
end;

procedure TTestUString.TestStrToNumAccepts;
var
  N: LongInt;
begin
  N := 0;
  AssertTrue(StrToNum('9600', 0, 4000000, N));
  AssertEquals(9600, N);
  AssertTrue(StrToNum('-32768', -32768, 32767, N));
  AssertEquals(-32768, N);
  AssertTrue(StrToNum('+5', 0, 10, N));
  AssertEquals(5, N);
  AssertTrue(StrToNum('$FF', 0, 255, N));
  AssertEquals(255, N);
  AssertTrue(StrToNum('007', 0, 10, N));
  AssertEquals(7, N);
end;

procedure TTestUString.TestStrToNumRefusesMalformed;
const
  Bad: array[1..12] of string = ('', '-', '+', '$', '12a', 'a12', ' 1', '1 ',
    '--5', '5-', '1.0', '99999999999999999999');
var
  I: Integer;
  N: LongInt;
begin
  for I := Low(Bad) to High(Bad) do
  begin
    N := 42;
    AssertFalse('"' + Bad[I] + '"', StrToNum(Bad[I], -MaxLongInt, MaxLongInt, N));
    AssertEquals('N unchanged for "' + Bad[I] + '"', 42, N);
  end;
  AssertFalse('hex digits need $', StrToNum('FF', 0, 255, N));
end;

procedure TTestUString.TestStrToNumRange;
var
  N: LongInt;
begin
  N := 0;
  AssertFalse(StrToNum('255', 0, 254, N));
  AssertTrue(StrToNum('254', 0, 254, N));
  AssertFalse(StrToNum('-1', 0, 254, N));
  AssertFalse('above LongWord', StrToNum('4294967296', 0, MaxLongInt, N));
end;

procedure TTestUString.TestChoiceIndex;
begin
  AssertEquals(0, ChoiceIndex('full', 'FULL|HALF'));
  AssertEquals(1, ChoiceIndex('HALF', 'FULL|HALF'));
  AssertEquals(-1, ChoiceIndex('HAL', 'FULL|HALF'));
  AssertEquals(-1, ChoiceIndex('', 'FULL|HALF'));
  AssertEquals(-1, ChoiceIndex('FULL|HALF', 'FULL|HALF'));
end;

procedure TTestUString.TestChoiceWord;
begin
  AssertEquals('OFF', ChoiceWord('OFF|ON', 0));
  AssertEquals('ON', ChoiceWord('OFF|ON', 1));
  AssertEquals('', ChoiceWord('OFF|ON', 2));
  AssertEquals('', ChoiceWord('OFF|ON', -1));
  AssertEquals('C', ChoiceWord('A|B|C', 2));
end;

procedure TTestUString.TestHexDigit;
begin
  AssertEquals(0, HexDigit('0'));
  AssertEquals(10, HexDigit('a'));
  AssertEquals(15, HexDigit('F'));
  AssertEquals(-1, HexDigit('G'));
  AssertEquals(-1, HexDigit(' '));
end;

procedure TTestUString.TestHexBytesPastShortString;
var
  B: array[0..299] of Byte;
  S: AnsiString;
  I: Integer;
begin
  for I := 0 to 299 do
    B[I] := Byte(I);
  AssertEquals('', HexBytes(@B[0], 0));
  AssertEquals('00 01 0A FF', HexBytes(@B[0], 2) + ' 0A ' + HexBytes(@B[255], 1));
  S := HexBytes(@B[0], 300);
  AssertEquals('300 bytes, no truncation at 255 characters', 899, Length(S));
  AssertEquals('2B', Copy(S, 898, 2));
end;

{ 2e308, 1E400 and friends ended a program with EOverflow (run-time error
  217) inside Val: now they are refused like any other bad number. }
procedure TTestUString.TestStrToRealNeverRaises;
const
  Bad: array[0..13] of string = ('2e308', '1E400', '-1E400', 'NaN', 'Inf', '-Inf',
    '1e', '1e+', '.', '+', '1..2', '1e1e1', ' 1', '$10');
var
  D: Double;
  I: Integer;
  Digits: string;
begin
  for I := 0 to High(Bad) do
  begin
    D := 42;
    AssertFalse(Bad[I], StrToReal(Bad[I], 0, 1e300, D));
    AssertEquals(Bad[I] + ' leaves D', 42, D, 0);
  end;
  Digits := StringOfChar('9', 250);
  AssertFalse('250 digits above Max', StrToReal(Digits, 0, 1, D));
  AssertTrue('250 digits within a huge Max', StrToReal(Digits, 0, 1e300, D));
  AssertTrue('1e-400 is 0 (underflow, no exception)', StrToReal('1e-400', 0, 1, D));
  AssertEquals(0, D, 0);
  AssertTrue(StrToReal('0.5', 0, 1, D));
  AssertEquals(0.5, D, 0);
  AssertTrue(StrToReal('1E-5', 0, 1, D));
  AssertTrue(StrToReal('-2.5e+2', -1000, 0, D));
  AssertEquals(-250, D, 0);
end;

{ The layer that parses reals: each bad number is res_BadParam naming the
  token (make fuzz tries every key of every layer). }
procedure TTestUString.TestNumbersOfEveryLayerNeverRaise;
const
  Tokens: array[0..5] of string = ('BER=2e308', 'DRP=1E400', 'INS=-1E400', 'BER=NaN',
    'CNT=99999999999999999999', 'BER=1' + '00000000000000000000000000000000000000');
var
  C: pChnVirt;
  I: Integer;
begin
  C := ChnCollection^.ChNewInit('NOISE');
  try
    for I := 0 to High(Tokens) do
    begin
      C^.ChSetParam(Tokens[I]);
      AssertEquals(Tokens[I], res_BadParam, C^.ChResult);
      AssertEquals(Tokens[I], C^.ChParamError);
    end;
  finally
    Dispose(C, Done);
  end;
end;

initialization
  RegisterTest(TTestUString);
end.
