{ Tests of ChnPlc5Sim, the PLC-5 of tools/df1sim --plc5: the configuration
  with PLC-5 addresses (octal I/O, D values stored in BCD), each command's
  reply bytes worked out by hand from Rockwell 1770-6.5.16 (typed read and
  write 0F 68/67 with their type/data parameter, word range read and write
  0F 01/00, read-modify-write 0F 26, the EXT STS codes of ChnPlc5Sim's
  header); then df1sim --plc5 on a pty, read and written by the PCCC client
  in both command sets and by df1read/df1write --plc5. }
unit TestChnPlc5Sim;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Process, fpcunit, testregistry, ChnTypes, ChnDF1Codec, ChnSlc, ChnPccc, ChnPlc5,
  ChnPcccClient, TestSupport, SlcAsk, BinSupport;

type
  TTestChnPlc5Sim = class(TTestCase)
  private
    T: tSlcTable;
    function Ask(CF: Word; const DataHex: string): string;
    function ConfigError(const Text: string): string;
  protected
    procedure SetUp; override;
  published
    procedure TestDefaultTable;
    procedure TestConfigErrors;
    procedure TestTypedRead;
    procedure TestTypedWriteThenRead;
    procedure TestWordRange;
    procedure TestReadModifyWrite;
    procedure TestRefusals;
    procedure TestSlcTableRefusesPlc5Commands;
    {$IFDEF UNIX}
    procedure TestClientOverPty;
    procedure TestToolsOverPty;
    {$ENDIF}
  end;

implementation

procedure TTestChnPlc5Sim.SetUp;
begin
  Plc5LoadDefault(T);
  AssertTrue('the PLC-5 table', T.Plc5);
end;

function TTestChnPlc5Sim.Ask(CF: Word; const DataHex: string): string;
begin
  Result := SlcAskText(T, CF, DataHex, 7);
end;

function TTestChnPlc5Sim.ConfigError(const Text: string): string;
var
  X: tSlcTable;
  Line: Integer;
  Err: string;
begin
  if Plc5LoadConfig(X, Text, Line, Err) then
    Result := 'loaded'
  else
    Result := Format('line %d: %s', [Line, Err]);
end;

procedure TTestChnPlc5Sim.TestDefaultTable;
begin
  AssertEquals('N7:1', 10, SlcGetWord(T, 7, 1));
  AssertEquals('I:012 (element 10)', $0020, SlcGetWord(T, 1, 10));
  AssertEquals('O:001', $00FF, SlcGetWord(T, 0, 1));
  AssertEquals('B3:1: B3/17 set', $0002, SlcGetWord(T, 3, 1));
  AssertEquals('D10:0 in BCD', $1234, SlcGetWord(T, 10, 0));
  AssertEquals('D10:1 in BCD', $9999, SlcGetWord(T, 10, 1));
  AssertEquals('T4:1.ACC', 7, SlcGetWord(T, 4, 1, 2));
  AssertEquals('C5:0.PRE', 10, SlcGetWord(T, 5, 0, 1));
  AssertEquals('F8:3', 1000000, SlcGetFloat(T, 8, 3), 0);
end;

procedure TTestChnPlc5Sim.TestConfigErrors;
begin
  AssertEquals('line 1: "L11" is no file name (O0 I1 S2, B T C R N F ST A D 3..255)',
    ConfigError('L11 4'));
  AssertEquals('line 2: "10000" is not 0..9999 (a D element holds four BCD digits)',
    ConfigError('D10 2'#10'D10:0 = 10000'));
  AssertTrue(ConfigError('I1 8'#10'I:018 = 1'), Pos('octal', ConfigError('I1 8'#10'I:018 = 1')) > 0);
  AssertTrue(ConfigError('N300 2'), Pos('3..255', ConfigError('N300 2')) > 0);
  AssertTrue(ConfigError('N300:0 = 1'), Pos('df1sim holds files 0..255', ConfigError('N300:0 = 1')) > 0);
  AssertEquals('loaded', ConfigError('I1 16'#10'I:017 = 5'));
end;

procedure TTestChnPlc5Sim.TestTypedRead;
begin
  { offset 0, total 3, N7:0, size 3 -> an array of three integers }
  AssertEquals('N7:0 x3', 'STS=00 97 09 42 00 00 0A 00 14 00',
    Ask($0F68, '00 00 03 00 07 00 07 00 03 00'));
  { PACKET OFFSET counts elements: from N7:0 + 2 }
  AssertEquals('N7:0 +2', 'STS=00 93 09 42 14 00', Ask($0F68, '02 00 01 00 07 00 07 00 01 00'));
  { mask 06: level 1 left at its default 0 }
  AssertEquals('N7:1 mask 06', 'STS=00 93 09 42 0A 00', Ask($0F68, '00 00 01 00 06 07 01 01 00'));
  AssertEquals('D10:0 x2, BCD', 'STS=00 96 09 92 10 34 12 99 99',
    Ask($0F68, '00 00 02 00 07 00 0A 00 02 00'));
  AssertEquals('F8:0', 'STS=00 96 09 94 08 00 00 C0 3F', Ask($0F68, '00 00 01 00 07 00 08 00 01 00'));
  AssertEquals('T4:0', 'STS=00 97 09 56 00 20 64 00 64 00', Ask($0F68, '00 00 01 00 07 00 04 00 01 00'));
  AssertEquals('T4:1.ACC', 'STS=00 93 09 42 07 00', Ask($0F68, '00 00 01 00 0F 00 04 01 02 01 00'));
  AssertEquals('I:012', 'STS=00 93 09 42 20 00', Ask($0F68, '00 00 01 00 07 00 01 0A 01 00'));
end;

procedure TTestChnPlc5Sim.TestTypedWriteThenRead;
begin
  AssertEquals('N7:5 <- 1 -2', 'STS=00', Ask($0F67, '00 00 02 00 07 00 07 05 95 09 42 01 00 FE FF'));
  AssertEquals('N7:5..6', 'STS=00 95 09 42 01 00 FE FF', Ask($0F68, '00 00 02 00 07 00 07 05 02 00'));
  AssertEquals('one element, no array', 'STS=00', Ask($0F67, '00 00 01 00 07 00 07 07 42 2A 00'));
  AssertEquals(42, SlcGetWord(T, 7, 7));
  AssertEquals('D10:2 <- 4321', 'STS=00', Ask($0F67, '00 00 01 00 07 00 0A 02 94 09 92 10 21 43'));
  AssertEquals($4321, SlcGetWord(T, 10, 2));
  AssertEquals('F8:1 <- 1.5', 'STS=00', Ask($0F67, '00 00 01 00 07 00 08 01 96 09 94 08 00 00 C0 3F'));
  AssertEquals(1.5, SlcGetFloat(T, 8, 1), 0);
  AssertEquals('T4:2.PRE <- 500', 'STS=00', Ask($0F67, '00 00 01 00 0F 00 04 02 01 93 09 42 F4 01'));
  AssertEquals(500, SlcGetWord(T, 4, 2, 1));
end;

procedure TTestChnPlc5Sim.TestWordRange;
begin
  AssertEquals('N7:0 x3', 'STS=00 00 00 0A 00 14 00', Ask($0F01, '00 00 03 00 07 00 07 00 06'));
  { PACKET OFFSET counts words }
  AssertEquals('T4:0 +1 word: PRE ACC', 'STS=00 64 00 64 00', Ask($0F01, '01 00 02 00 07 00 04 00 04'));
  AssertEquals('ST9:0, first 6 bytes', 'STS=00 05 00 65 68 6C 6C', Ask($0F01, '00 00 03 00 07 00 09 00 06'));
  AssertEquals('D10:3 <- raw', 'STS=00', Ask($0F00, '00 00 01 00 07 00 0A 03 99 00'));
  AssertEquals($0099, SlcGetWord(T, 10, 3));
  AssertEquals('odd size', 'STS=10', Ask($0F01, '00 00 03 00 07 00 07 00 05'));
  AssertEquals('past the end', 'STS=F0 07', Ask($0F01, '00 00 02 00 07 00 07 31 04'));
end;

procedure TTestChnPlc5Sim.TestReadModifyWrite;
begin
  { B3:1 = $0002: AND $FFFD clears bit 1, OR $8000 sets bit 15 }
  AssertEquals('STS=00', Ask($0F26, '07 00 03 01 FD FF 00 80'));
  AssertEquals($8000, SlcGetWord(T, 3, 1));
  { two in one command: I:012/05 cleared, T4:1.DN set }
  AssertEquals('STS=00', Ask($0F26, '07 00 01 0A DF FF 00 00 0F 00 04 01 00 FF DF 00 20'));
  AssertEquals(0, SlcGetWord(T, 1, 10));
  AssertEquals($2000, SlcGetWord(T, 4, 1, 0));
  AssertEquals('an F element has no bits', 'STS=F0 11', Ask($0F26, '07 00 08 00 FF FF 01 00'));
end;

procedure TTestChnPlc5Sim.TestRefusals;
begin
  AssertEquals('no such file', 'STS=F0 06', Ask($0F68, '00 00 01 00 07 00 32 00 01 00'));
  AssertEquals('level 1 not the data table', 'STS=F0 06', Ask($0F68, '00 00 01 00 07 01 07 00 01 00'));
  AssertEquals('element past the end', 'STS=F0 06', Ask($0F68, '00 00 01 00 07 00 07 32 01 00'));
  AssertEquals('transfer past the end', 'STS=F0 07', Ask($0F68, '00 00 0A 00 07 00 07 2D 0A 00'));
  AssertEquals('sub-element of N', 'STS=F0 06', Ask($0F68, '00 00 01 00 0F 00 07 00 01 01 00'));
  AssertEquals('five levels', 'STS=F0 03', Ask($0F68, '00 00 01 00 1F 00 07 00 00 00 01 00'));
  AssertEquals('no element level', 'STS=F0 02', Ask($0F68, '00 00 01 00 03 00 07 01 00'));
  AssertEquals('cut short', 'STS=10', Ask($0F68, '00 00 01 00 07 00'));
  AssertEquals('more than a frame', 'STS=F0 09', Ask($0F68, '00 00 78 00 07 00 07 00 78 00'));
  AssertEquals('typed read of ST', 'STS=F0 11', Ask($0F68, '00 00 01 00 07 00 09 00 01 00'));
  AssertEquals('a float into N', 'STS=F0 11', Ask($0F67, '00 00 01 00 07 00 07 00 96 09 94 08 00 00 C0 3F'));
  AssertEquals('array size wrong', 'STS=10', Ask($0F67, '00 00 01 00 07 00 07 00 94 09 42 01 00'));
end;

procedure TTestChnPlc5Sim.TestSlcTableRefusesPlc5Commands;
begin
  SlcLoadDefault(T);
  AssertFalse(T.Plc5);
  AssertEquals('STS=10', Ask($0F68, '00 00 03 00 07 00 07 00 03 00'));
end;

{$IFDEF UNIX}
procedure TTestChnPlc5Sim.TestClientOverPty;
var
  Proc: TProcess;
  PtyPath: string;
  S: ShortString;
  C: tPcccClient;
  V: array[0..9] of LongInt;
  F: array[0..0] of Single;
  Cmd: tPlc5Command;
begin
  Proc := StartSimPty(['--plc5', '--timeout=20', '--quiet'], PtyPath);
  try
    AssertTrue('PTY line', Copy(PtyPath, 1, 5) = '/dev/');
    for Cmd := Low(tPlc5Command) to High(tPlc5Command) do
    begin
      AssertEquals('open', res_Ok, PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=' + PtyPath));
      try
        PcccClientPlc5(C, Cmd);
        AssertEquals('N7:0 x3 ' + C.Err, res_Ok, PcccReadInts(C, 'N7:0', 3, V));
        AssertEquals(20, V[2]);
        AssertEquals('I:012/05 ' + C.Err, res_Ok, PcccReadInts(C, 'I:012/05', 1, V));
        AssertEquals(1, V[0]);
        AssertEquals('B3/17 ' + C.Err, res_Ok, PcccReadInts(C, 'B3/17', 1, V));
        AssertEquals(1, V[0]);
        AssertEquals('T4:1.ACC ' + C.Err, res_Ok, PcccReadInts(C, 'T4:1.ACC', 1, V));
        AssertEquals(7, V[0]);
        AssertEquals('C5:0.PRE ' + C.Err, res_Ok, PcccReadInts(C, 'C5:0.PRE', 1, V));
        AssertEquals(10, V[0]);
        AssertEquals('D10:0 ' + C.Err, res_Ok, PcccReadInts(C, 'D10:0', 2, V));
        AssertEquals(1234, V[0]);
        AssertEquals(9999, V[1]);
        AssertEquals('F8:3 ' + C.Err, res_Ok, PcccReadFloats(C, 'F8:3', 1, F));
        AssertEquals(1000000, F[0], 0);
        AssertEquals('ST9:0 ' + C.Err, res_Ok, PcccReadString(C, 'ST9:0', S));
        AssertEquals('hello', S);
        AssertEquals('O:001 ' + C.Err, res_Ok, PcccReadInts(C, 'O:001', 1, V));
        AssertEquals($FF, V[0]);
        { writes, read back }
        AssertEquals('write D10:2 ' + C.Err, res_Ok, PcccWriteInts(C, 'D10:2', [4321 + Ord(Cmd)]));
        AssertEquals(res_Ok, PcccReadInts(C, 'D10:2', 1, V));
        AssertEquals(4321 + Ord(Cmd), V[0]);
        AssertEquals('write O:001/03 ' + C.Err, res_Ok, PcccWriteInts(C, 'O:001/03', [0]));
        AssertEquals(res_Ok, PcccReadInts(C, 'O:001', 1, V));
        AssertEquals($F7, V[0]);
        AssertEquals(res_Ok, PcccWriteInts(C, 'O:001/03', [1]));
        AssertEquals('write ST9:1 ' + C.Err, res_Ok, PcccWriteString(C, 'ST9:1', 'PLC-5'));
        AssertEquals(res_Ok, PcccReadString(C, 'ST9:1', S));
        AssertEquals('PLC-5', S);
        AssertEquals('write F8:4 ' + C.Err, res_Ok, PcccWriteFloats(C, 'F8:4', [-0.5]));
        AssertEquals(res_Ok, PcccReadFloats(C, 'F8:4', 1, F));
        AssertEquals(-0.5, F[0], 0);
        AssertEquals('write T4:2 ' + C.Err, res_Ok, PcccWriteInts(C, 'T4:2', [0, 30, 4]));
        AssertEquals(res_Ok, PcccReadInts(C, 'T4:2.PRE', 1, V));
        AssertEquals(30, V[0]);
        { 60 integers from N7:0 in one request; past the end: an error reply }
        AssertEquals(res_PcccStatus, PcccReadInts(C, 'N7:45', 10, V));
        AssertTrue(C.Err, Pos('EXT STS $07', C.Err) > 0);
        AssertEquals(res_PcccValue, PcccWriteInts(C, 'D10:0', [10000]));
        AssertEquals(res_PcccAddress, PcccReadInts(C, 'L10:0', 1, V));
      finally
        PcccClose(C);
      end;
    end;
  finally
    Proc.Terminate(0);
    Proc.Free;
  end;
end;

procedure TTestChnPlc5Sim.TestToolsOverPty;
var
  Proc: TProcess;
  PtyPath, Out: string;
begin
  Proc := StartSimPty(['--plc5', '--timeout=20', '--quiet'], PtyPath);
  try
    AssertEquals(0, RunBin('df1read', ['--plc5', 'I:012/05', '1', 'NAM=DF1', 'NOD=0', 'DNO=1',
      'NAM=COM', 'DEV=' + PtyPath], 10000, Out));
    AssertTrue(Out, Pos('I:012/05 = 1', Out) > 0);
    AssertTrue('the typed read on the wire: ' + Out,
      Pos('Typed Read STS=$00', Out) > 0);
    AssertEquals(0, RunBin('df1write', ['--plc5', 'D10:3', '77', 'NAM=DF1', 'NOD=0', 'DNO=1',
      'NAM=COM', 'DEV=' + PtyPath], 10000, Out));
    AssertEquals(0, RunBin('df1read', ['--word-range', 'D10:3', '1', 'NAM=DF1', 'NOD=0', 'DNO=1',
      'NAM=COM', 'DEV=' + PtyPath], 10000, Out));
    AssertTrue(Out, Pos('D10:3 = 77', Out) > 0);
    AssertTrue('word range read on the wire: ' + Out, Pos('Word Range Read', Out) > 0);
    { an address the PLC-5 rules refuse: a command-line error, nothing opened }
    AssertEquals(2, RunBin('df1read', ['--plc5', 'I:019', 'NAM=DF1', 'NOD=0', 'DNO=1',
      'NAM=COM', 'DEV=' + PtyPath], 10000, Out));
    AssertTrue(Out, Pos('octal', Out) > 0);
  finally
    Proc.Terminate(0);
    Proc.Free;
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnPlc5Sim);
end.
