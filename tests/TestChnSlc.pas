{ Tests of ChnSlc, ChnPccc, the simulated SLC 5/0x data table and command handler
  behind tools/df1sim: the configuration text (values, every error with its
  line) and each command's reply bytes, worked out by hand from the
  request layouts of Rockwell 1770-6.5.16 (typed logical read/write with
  three address fields, PLC-2 unprotected read/write, diagnostics) and the
  STS / EXT STS codes documented in ChnSlc's header. }
unit TestChnSlc;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, StrUtils, fpcunit, testregistry, ChnTypes, ChnDF1Codec, ChnSlc, ChnPccc, TestSupport, SlcAsk;

type
  TTestChnSlc = class(TTestCase)
  private
    T: tSlcTable;
    { 'STS=xx' + ' ' + reply data in hex, from CF and request data in hex }
    function Ask(CF: Word; const DataHex: string; Tns: Word = 7): string;
    function ConfigError(const Text: string): string;
  protected
    procedure SetUp; override;
  published
    procedure TestConfigValues;
    procedure TestConfigErrors;
    procedure TestDefaultTable;
    procedure TestFreeRunningClock;
    procedure TestExampleConfigLoads;
    procedure TestEchoAndTns;
    procedure TestTypedReadIntegerAndFloat;
    procedure TestTypedReadExtendedFields;
    procedure TestTypedWriteThenRead;
    procedure TestTypedErrors;
    procedure TestUnprotectedReadWrite;
    procedure TestTimerCounterControl;
    procedure TestLongAndString;
    procedure TestMaskedWrite;
    procedure TestUnprotectedErrors;
    procedure TestDiagnostics;
    procedure TestCounterWrapsLikeThePlc;
    procedure TestUnknownCommandAndReplies;
  end;

implementation

const
  Config =
    '# test table'#10 +
    'N7 20'#10 +
    'N7:0 = 1 2 3 -1 $1234   # five values'#13#10 +
    'B3 4'#10 +
    'F8 2'#10 +
    'F8:0 = 1.5 -2.25'#10 +
    'N9 8'#10 +
    'N9:0 = $0102 $0304'#10 +
    'CIF 9'#10 +
    'N10 400'#10 +
    'N10:300 = 77'#10 +
    'T4 3'#10'T4:0 = $A000 100 42'#10'T4:1.PRE = 10 20'#10 +
    'C5 2'#10'C5:1.ACC = 5'#10 +
    'R6 2'#10'R6:0.POS = 3'#10 +
    'ST12 2'#10'ST12:1 = "Hi there"'#10 +
    'L13 2'#10'L13:0 = 100000 -2'#10;

procedure TTestChnSlc.TestCounterWrapsLikeThePlc;
begin
  { this build has overflow checks on: a plain Inc would stop the test }
  T.Diag[dgFramesIn] := 65535;
  SlcCount(T, dgFramesIn);
  AssertEquals(0, T.Diag[dgFramesIn]);
  SlcCount(T, dgFramesIn);
  AssertEquals(1, T.Diag[dgFramesIn]);
end;

procedure TTestChnSlc.SetUp;
var
  Line: Integer;
  Err: string;
begin
  AssertTrue('config', SlcLoadConfig(T, Config, Line, Err));
end;

function TTestChnSlc.Ask(CF: Word; const DataHex: string; Tns: Word): string;
begin
  Result := SlcAskText(T, CF, DataHex, Tns);
end;

function TTestChnSlc.ConfigError(const Text: string): string;
var
  Line: Integer;
  Err: string;
  X: tSlcTable;
begin
  if SlcLoadConfig(X, Text, Line, Err) then
    Result := 'ok'
  else
    Result := IntToStr(Line);
end;

{ S:4 of an SLC counts every 10 ms and wraps at 65535 }
procedure TTestChnSlc.TestFreeRunningClock;
var
  Small: tSlcTable;
  Line: Integer;
  Err: string;
begin
  SlcLoadDefault(T);
  SlcClock(T, 0);
  AssertEquals('S2:4 at start', 0, SlcGetWord(T, 2, 4));
  SlcClock(T, 12349);
  AssertEquals('S2:4 after 12.349 s', 1234, SlcGetWord(T, 2, 4));
  SlcClock(T, 655359);
  AssertEquals('S2:4 just before the wrap', 65535, SlcGetWord(T, 2, 4));
  SlcClock(T, 655360 + 25);
  AssertEquals('S2:4 wrapped', 2, SlcGetWord(T, 2, 4));
  AssertEquals('S2:3 untouched', 0, SlcGetWord(T, 2, 3));
  AssertEquals('S2:5 untouched', 0, SlcGetWord(T, 2, 5));
  { a table whose S2 has no element 4 is left alone }
  AssertTrue(Err, SlcLoadConfig(Small, 'S2 4'#10'N7 2'#10, Line, Err));
  SlcClock(Small, 5000);
  AssertEquals('S2:3 of a short S2', 0, SlcGetWord(Small, 2, 3));
end;

procedure TTestChnSlc.TestDefaultTable;
var
  Line: Integer;
  Err: string;
begin
  AssertTrue('SlcDefaultConfig loads: ' + Err,
    SlcLoadConfig(T, SlcDefaultConfig, Line, Err));
  SlcClear(T);
  SlcLoadDefault(T);
  { the values docs/df1sim.md lists for the built-in table }
  AssertEquals('S2 elements', 32, T.Files[2].Elems);
  AssertEquals('S2 type', pft_Status, T.Files[2].FType);
  AssertEquals('B3 elements', 8, T.Files[3].Elems);
  AssertEquals('B3:1', $8000, SlcGetWord(T, 3, 1));
  AssertEquals('N7 elements', 50, T.Files[7].Elems);
  AssertEquals('N7:0', 0, SlcGetWord(T, 7, 0));
  AssertEquals('N7:9', 90, SlcGetWord(T, 7, 9));
  AssertEquals('N7:10', 0, SlcGetWord(T, 7, 10));
  AssertEquals('F8 elements', 10, T.Files[8].Elems);
  AssertEquals('F8:1', -2.25, SlcGetFloat(T, 8, 1), 0);
  AssertEquals('F8:3', 1000000, SlcGetFloat(T, 8, 3), 0);
  AssertEquals('N9 elements', 64, T.Files[9].Elems);
  AssertEquals('CIF', 9, T.Cif);
  AssertEquals('T4:0 control word: DN', $2000, SlcGetWord(T, 4, 0, 0));
  AssertEquals('T4:0.PRE', 100, SlcGetWord(T, 4, 0, 1));
  AssertEquals('T4:1.PRE', 50, SlcGetWord(T, 4, 1, 1));
  AssertEquals('T4:1.ACC', 7, SlcGetWord(T, 4, 1, 2));
  AssertEquals('C5:0.ACC', 3, SlcGetWord(T, 5, 0, 2));
  AssertEquals('R6:0.LEN', 8, SlcGetWord(T, 6, 0, 1));
  AssertEquals('ST10:0 LEN', 5, SlcGetWord(T, 10, 0));
  AssertEquals('L11 type', pft_Long, T.Files[11].FType);
  AssertEquals('nothing else: N12', 0, T.Files[12].FType);
end;

procedure TTestChnSlc.TestExampleConfigLoads;
var
  Text: AnsiString;
  F: TextFile;
  Line: AnsiString;
  ErrLine: LongInt;
  Err: AnsiString;
begin
  { tools/df1sim.conf, the example the docs point to, is valid }
  Text := '';
  AssignFile(F, 'tools/df1sim.conf');
  Reset(F);
  while not Eof(F) do
  begin
    ReadLn(F, Line);
    Text := Text + Line + #10;
  end;
  CloseFile(F);
  ErrLine := 0;
  Err := '';
  if not SlcLoadConfig(T, Text, ErrLine, Err) then
    Fail('tools/df1sim.conf line ' + IntToStr(ErrLine) + ': ' + Err);
  AssertEquals('T4:0.PRE', 100, SlcGetWord(T, 4, 0, 1));
  AssertEquals('ST10:0 LEN', 5, SlcGetWord(T, 10, 0));
end;

procedure TTestChnSlc.TestConfigValues;
begin
  AssertEquals('N7:0', 1, SlcGetWord(T, 7, 0));
  AssertEquals('N7:3 = -1', $FFFF, SlcGetWord(T, 7, 3));
  AssertEquals('N7:4 = $1234', $1234, SlcGetWord(T, 7, 4));
  AssertEquals('N7:5 untouched', 0, SlcGetWord(T, 7, 5));
  AssertEquals('N10:300', 77, SlcGetWord(T, 10, 300));
  AssertEquals('F8:1', -2.25, SlcGetFloat(T, 8, 1), 0);
  AssertEquals('N7 elements', 20, T.Files[7].Elems);
  AssertEquals('B3 type', pft_Bit, T.Files[3].FType);
  AssertEquals('no N11', 0, T.Files[11].FType);
  { T4:0 = control word, PRE, ACC; T4:1.PRE = 10 20: the PRE of T4:1, T4:2 }
  AssertEquals('T4:0 control', $A000, SlcGetWord(T, 4, 0, 0));
  AssertEquals('T4:0.PRE', 100, SlcGetWord(T, 4, 0, 1));
  AssertEquals('T4:0.ACC', 42, SlcGetWord(T, 4, 0, 2));
  AssertEquals('T4:1.PRE', 10, SlcGetWord(T, 4, 1, 1));
  AssertEquals('T4:2.PRE', 20, SlcGetWord(T, 4, 2, 1));
  AssertEquals('T4:1.ACC untouched', 0, SlcGetWord(T, 4, 1, 2));
  AssertEquals('no word 3 in a timer', 0, SlcGetWord(T, 4, 0, 3));
  AssertEquals('C5:1.ACC', 5, SlcGetWord(T, 5, 1, 2));
  AssertEquals('R6:0.POS', 3, SlcGetWord(T, 6, 0, 2));
  AssertEquals('CIF', 9, T.Cif);
end;

procedure TTestChnSlc.TestConfigErrors;
begin
  AssertEquals('unknown type', '2', ConfigError('N7 5'#10'X7 5'));
  AssertEquals('file number too large', '1', ConfigError('N256 5'));
  AssertEquals('no element count', '1', ConfigError('N7'));
  AssertEquals('zero elements', '1', ConfigError('N7 0'));
  AssertEquals('too many elements', '1', ConfigError('N7 4097'));
  AssertEquals('values before the declaration', '1', ConfigError('N7:0 = 1'#10'N7 5'));
  AssertEquals('values past the end', '2', ConfigError('N7 2'#10'N7:1 = 1 2'));
  AssertEquals('no =', '2', ConfigError('N7 2'#10'N7:0 1'));
  AssertEquals('no values', '2', ConfigError('N7 2'#10'N7:0 ='));
  AssertEquals('out of 16 bits', '2', ConfigError('N7 2'#10'N7:0 = 65536'));
  AssertEquals('not a float', '3', ConfigError('#'#10'F8 2'#10'F8:0 = x'));
  AssertEquals('type differs', '2', ConfigError('N7 2'#10'F7:0 = 1'));
  AssertEquals('bad CIF', '1', ConfigError('CIF'));
  AssertEquals('CIF with two numbers', '1', ConfigError('CIF 9 10'));
  AssertEquals('element count then more', '2', ConfigError('N7 5'#10'N8 5 6'));
  AssertEquals('below -32768', '2', ConfigError('N7 2'#10'N7:0 = -32769'));
  AssertEquals('-32768 fits', 'ok', ConfigError('N7 2'#10'N7:0 = -32768 65535'));
  { 3.4e38 is about the largest Single; 1e39 would become +Inf }
  AssertEquals('float out of range', '2', ConfigError('F8 2'#10'F8:0 = 1e39'));
  AssertEquals('float out of range, negative', '2', ConfigError('F8 2'#10'F8:0 = -1e39'));
  AssertEquals('good', 'ok', ConfigError('  # only a comment'#10#10'B3 1  '));
  { the addresses of unit ChnPccc }
  AssertEquals('N2 is no N file', '1', ConfigError('N2 5'));
  AssertEquals('S3', '1', ConfigError('S3 5'));
  AssertEquals('S means S2', 'ok', ConfigError('S2 4'#10'S:1 = 5'));
  AssertEquals('a bit takes no start values', '2', ConfigError('B3 2'#10'B3:0/1 = 1'));
  AssertEquals('PRE past the end', '2', ConfigError('T4 2'#10'T4:0.PRE = 1 2 3'));
  AssertEquals('PRE of every timer', 'ok', ConfigError('T4 2'#10'T4:0.PRE = 1 2'));
  AssertEquals('whole timers past the end', '2', ConfigError('T4 1'#10'T4:0 = 1 2 3 4'));
  AssertEquals('element past the end', '2', ConfigError('T4 1'#10'T4:1.ACC = 1'));
  AssertEquals('no such sub-element', '2', ConfigError('T4 1'#10'T4:0.LEN = 1'));
  AssertEquals('32 bits', 'ok', ConfigError('L9 2'#10'L9:0 = 2147483647 -2147483648'));
  AssertEquals('beyond 32 bits', '2', ConfigError('L9 2'#10'L9:0 = 2147483648'));
  AssertEquals('string without quotes', '2', ConfigError('ST9 1'#10'ST9:0 = hello'));
  AssertEquals('string of 82', 'ok', ConfigError('ST9 1'#10'ST9:0 = "' + StringOfChar('x', 82) + '"'));
  AssertEquals('string of 83', '2', ConfigError('ST9 1'#10'ST9:0 = "' + StringOfChar('x', 83) + '"'));
end;

procedure TTestChnSlc.TestEchoAndTns;
begin
  AssertEquals('STS=00 41 68 6F 6A', Ask($0600, '41 68 6F 6A', $1234));
  AssertEquals('empty echo', 'STS=00', Ask($0600, ''));
end;

procedure TTestChnSlc.TestTypedReadIntegerAndFloat;
begin
  { SIZE 10, FILE 7, TYPE $89, ELEMENT 0, SUB 0 }
  AssertEquals('N7:0..4', 'STS=00 01 00 02 00 03 00 FF FF 34 12', Ask($0FA2, '0A 07 89 00 00'));
  AssertEquals('N7:3', 'STS=00 FF FF', Ask($0FA2, '02 07 89 03 00'));
  { 1.5 = $3FC00000, -2.25 = $C0100000, low byte first }
  AssertEquals('F8:0..1', 'STS=00 00 00 C0 3F 00 00 10 C0', Ask($0FA2, '08 08 8A 00 00'));
  AssertEquals('B3:0', 'STS=00 00 00', Ask($0FA2, '02 03 85 00 00'));
end;

procedure TTestChnSlc.TestTypedReadExtendedFields;
begin
  { ELEMENT 300 = $FF $2C $01; FILE 10 also as $FF $0A $00 }
  AssertEquals('N10:300', 'STS=00 4D 00', Ask($0FA2, '02 0A 89 FF 2C 01 00'));
  AssertEquals('N10:300 long file field', 'STS=00 4D 00', Ask($0FA2, '02 FF 0A 00 89 FF 2C 01 00'));
  AssertEquals('file 256 does not exist', 'STS=F0 06', Ask($0FA2, '02 FF 00 01 89 00 00'));
  AssertEquals('cut inside an extended field', 'STS=10', Ask($0FA2, '02 0A 89 FF 2C'));
end;

procedure TTestChnSlc.TestTypedWriteThenRead;
begin
  AssertEquals('write N7:5..6', 'STS=00', Ask($0FAA, '04 07 89 05 00 39 30 C7 CF'));
  AssertEquals('N7:5', 12345, SlcGetWord(T, 7, 5));
  AssertEquals('N7:6 = -12345', $CFC7, SlcGetWord(T, 7, 6));
  AssertEquals('read back', 'STS=00 39 30 C7 CF', Ask($0FA2, '04 07 89 05 00'));
  AssertEquals('write F8:1', 'STS=00', Ask($0FAA, '04 08 8A 01 00 00 00 C0 3F'));
  AssertEquals('F8:1', 1.5, SlcGetFloat(T, 8, 1), 0);
end;

procedure TTestChnSlc.TestTypedErrors;
begin
  AssertEquals('missing file N11', 'STS=F0 06', Ask($0FA2, '02 0B 89 00 00'));
  AssertEquals('N7 asked as float', 'STS=F0 06', Ask($0FA2, '04 07 8A 00 00'));
  AssertEquals('element 20 of 20', 'STS=F0 06', Ask($0FA2, '02 07 89 14 00'));
  AssertEquals('sub-element 1', 'STS=F0 06', Ask($0FA2, '02 07 89 00 01'));
  AssertEquals('N7:19 + 2 elements', 'STS=F0 07', Ask($0FA2, '04 07 89 13 00'));
  AssertEquals('N7:19 one element is fine', 'STS=00 00 00', Ask($0FA2, '02 07 89 13 00'));
  AssertEquals('size 0', 'STS=F0 01', Ask($0FA2, '00 07 89 00 00'));
  AssertEquals('odd size for words', 'STS=F0 01', Ask($0FA2, '03 07 89 00 00'));
  AssertEquals('size 246', 'STS=F0 01', Ask($0FA2, 'F6 0A 89 00 00'));
  AssertEquals('fields missing', 'STS=10', Ask($0FA2, '02 07 89'));
  AssertEquals('write: data shorter than SIZE', 'STS=10', Ask($0FAA, '04 07 89 00 00 01 00'));
  AssertEquals('write: data longer than SIZE', 'STS=10', Ask($0FAA, '02 07 89 00 00 01 00 02'));
  AssertEquals('write to a missing file', 'STS=F0 06', Ask($0FAA, '02 0B 89 00 00 01 00'));
  AssertEquals('write past the end', 'STS=F0 07', Ask($0FAA, '04 07 89 13 00 01 00 02 00'));
  AssertEquals('nothing written by the refused write', 0, SlcGetWord(T, 7, 19));
end;

procedure TTestChnSlc.TestTimerCounterControl;
begin
  { sub-element 0 control word, 1 PRE, 2 ACC; a whole timer is 6 bytes }
  AssertEquals('T4:0.ACC', 'STS=00 2A 00', Ask($0FA2, '02 04 86 00 02'));
  AssertEquals('T4:0.PRE', 'STS=00 64 00', Ask($0FA2, '02 04 86 00 01'));
  AssertEquals('T4:0', 'STS=00 00 A0 64 00 2A 00', Ask($0FA2, '06 04 86 00 00'));
  AssertEquals('T4:0..1', 'STS=00 00 A0 64 00 2A 00 00 00 0A 00 00 00', Ask($0FA2, '0C 04 86 00 00'));
  AssertEquals('sub-element 3', 'STS=F0 06', Ask($0FA2, '02 04 86 00 03'));
  AssertEquals('timer file asked as counter', 'STS=F0 06', Ask($0FA2, '02 04 87 00 02'));
  AssertEquals('T4:2.ACC + 2 bytes runs past', 'STS=F0 07', Ask($0FA2, '04 04 86 02 02'));
  AssertEquals('write T4:1.ACC', 'STS=00', Ask($0FAA, '02 04 86 01 02 E8 03'));
  AssertEquals('T4:1.ACC', 1000, SlcGetWord(T, 4, 1, 2));
  AssertEquals('C5:1.ACC', 'STS=00 05 00', Ask($0FA2, '02 05 87 01 02'));
  AssertEquals('R6:0.POS', 'STS=00 03 00', Ask($0FA2, '02 06 88 00 02'));
  AssertEquals('write R6:1.LEN', 'STS=00', Ask($0FAA, '02 06 88 01 01 10 00'));
  AssertEquals('R6:1.LEN', 16, SlcGetWord(T, 6, 1, 1));
end;

procedure TTestChnSlc.TestLongAndString;
begin
  { 100000 = $000186A0, -2 = $FFFFFFFE }
  AssertEquals('L13:0..1', 'STS=00 A0 86 01 00 FE FF FF FF', Ask($0FA2, '08 0D 91 00 00'));
  AssertEquals('half an L', 'STS=F0 01', Ask($0FA2, '02 0D 91 00 00'));
  AssertEquals('write L13:1', 'STS=00', Ask($0FAA, '04 0D 91 01 00 01 02 03 04'));
  AssertEquals('read back', 'STS=00 01 02 03 04', Ask($0FA2, '04 0D 91 01 00'));
  { LEN 8, 'Hi there' with the characters of each word swapped }
  AssertEquals('ST12:1', 'STS=00 08 00 69 48 74 20 65 68 65 72' + DupeString(' 00', 74),
    Ask($0FA2, '54 0C 8D 01 00'));
  AssertEquals('ST12:0 empty', 'STS=00' + DupeString(' 00', 84), Ask($0FA2, '54 0C 8D 00 00'));
end;

procedure TTestChnSlc.TestMaskedWrite;
begin
  { SIZE 2, B3:1, mask $0010, data $0010: bit 4 set, the others stay }
  AssertEquals('write B3:1', 'STS=00', Ask($0FAA, '02 03 85 01 00 01 80'));
  AssertEquals('set B3:1/4', 'STS=00', Ask($0FAB, '02 03 85 01 00 10 00 10 00'));
  AssertEquals('B3:1', $8011, SlcGetWord(T, 3, 1));
  AssertEquals('clear B3:1/15 and /0 at once', 'STS=00', Ask($0FAB, '02 03 85 01 00 01 80 00 00'));
  AssertEquals('B3:1', $0010, SlcGetWord(T, 3, 1));
  AssertEquals('data outside the mask is ignored', 'STS=00', Ask($0FAB, '02 03 85 01 00 00 01 FF FF'));
  AssertEquals('B3:1', $0110, SlcGetWord(T, 3, 1));
  AssertEquals('T4:0.DN through the control word', 'STS=00', Ask($0FAB, '02 04 86 00 00 00 20 00 00'));
  AssertEquals('T4:0 control', $8000, SlcGetWord(T, 4, 0, 0));
  AssertEquals('mask without data', 'STS=10', Ask($0FAB, '02 03 85 01 00 10 00'));
  AssertEquals('masked write past the end', 'STS=F0 07', Ask($0FAB, '04 03 85 03 00 FF FF FF FF 00 00 00 00'));
  AssertEquals('to a missing file', 'STS=F0 06', Ask($0FAB, '02 0B 85 00 00 01 00 01 00'));
end;

procedure TTestChnSlc.TestUnprotectedReadWrite;
begin
  { ADDR is a byte offset into the CIF N9, low byte first; SIZE in bytes }
  AssertEquals('read N9:0..1', 'STS=00 02 01 04 03', Ask($0100, '00 00 04'));
  AssertEquals('read N9:1', 'STS=00 04 03', Ask($0100, '02 00 02'));
  AssertEquals('write N9:7', 'STS=00', Ask($0800, '0E 00 AA 55'));
  AssertEquals('N9:7', $55AA, SlcGetWord(T, 9, 7));
end;

procedure TTestChnSlc.TestUnprotectedErrors;
var
  Line: Integer;
  Err: string;
begin
  AssertEquals('odd address', 'STS=10', Ask($0100, '01 00 02'));
  AssertEquals('size 0', 'STS=10', Ask($0100, '00 00 00'));
  AssertEquals('odd size', 'STS=10', Ask($0100, '00 00 03'));
  AssertEquals('ADDR+SIZE missing', 'STS=10', Ask($0100, '00 00'));
  AssertEquals('extra byte', 'STS=10', Ask($0100, '00 00 02 00'));
  AssertEquals('past the CIF (16 bytes)', 'STS=50', Ask($0100, '0E 00 04'));
  AssertEquals('write past the CIF', 'STS=50', Ask($0800, '10 00 01 00'));
  AssertEquals('write, odd data', 'STS=10', Ask($0800, '00 00 01'));
  { a table without the CIF file }
  AssertTrue(SlcLoadConfig(T, 'N7 5'#10'CIF 20', Line, Err));
  AssertEquals('no CIF', 'STS=50', Ask($0100, '00 00 02'));
end;

procedure TTestChnSlc.TestDiagnostics;
var
  S: string;
begin
  T.Diag[dgFramesIn] := $0102;
  T.Diag[dgNaksOut] := 5;
  { ADDR 0, SIZE 6: counters 0..2, low byte first }
  AssertEquals('read counters', 'STS=00 02 01 00 00 05 00', Ask($0601, '00 00 06'));
  AssertEquals('read from byte 1', 'STS=00 01 00', Ask($0601, '01 00 02'));
  AssertEquals('past the block', 'STS=10', Ask($0601, '0F 00 02'));
  AssertEquals('no ADDR/SIZE', 'STS=10', Ask($0601, ''));
  AssertEquals('reset', 'STS=00', Ask($0607, ''));
  AssertEquals('zero after reset', 'STS=00 00 00 00 00', Ask($0601, '00 00 04'));
  S := Ask($0603, '');
  { the simulator's own identity (no real SLC's block, see ChnSlc):
    mode $06 (run), type $EE, $49 (5/03), $00, $21 (series B rev 1), then
    the table name 'df1sim' = 64 66 31 73 69 6D }
  AssertEquals('diagnostic status block', 'STS=00 06 EE 49 00 21 64 66 31 73 69 6D', S);
end;

procedure TTestChnSlc.TestUnknownCommandAndReplies;
var
  Req: tRecRecord;
  Rep: tSendRecord;
  RepLen: Word;
begin
  AssertEquals('CMD 06 FNC 09', 'STS=10', Ask($0609, ''));
  AssertEquals('CMD 0F FNC 68', 'STS=10', Ask($0F68, '00'));
  AssertEquals('CMD 02', 'STS=10', Ask($0200, '00'));
  AssertEquals('error replies counted', 3, T.Diag[dgErrReplies]);
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := $4600;
  RepLen := 99;
  AssertFalse('a reply is not answered', SlcHandle(T, Req, 8, Rep, RepLen));
  Req.MessType := tpAckNak;
  AssertFalse('an ACK is not answered', SlcHandle(T, Req, 2, Rep, RepLen));
  Req.MessType := tpDataMess;
  Req.CF := $0600;
  AssertFalse('Len below 8', SlcHandle(T, Req, 7, Rep, RepLen));
  AssertFalse('Len above 252', SlcHandle(T, Req, 253, Rep, RepLen));
end;

initialization
  RegisterTest(TTestChnSlc);
end.
