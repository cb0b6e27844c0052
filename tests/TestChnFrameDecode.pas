{ Tests of ChnFrameDecode, the logic of tools/chndecode: the RACOM captures
  of the RACOM note (chapter 3, copied below as they are printed), frames that
  span chunks, checksum verdicts, half-duplex DF1, FT1.2 and ICS frames
  worked out by hand, hex text input, and a log written by the trace layer
  during a real exchange with the df1sim station, read back. }
unit TestChnFrameDecode;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnTrc,
  ChnTrcFormat, ChnDF1, ChnSlc, ChnDF1Link, ChnFrameDecode, TestSupport, TestTempDir;

type
  TTestChnFrameDecode = class(TTestCase)
  private
    Lines: TStringList;
    Stats: tDecStats;
    procedure Run(const Opt: tDecOptions; const Text: AnsiString);
    procedure RunHex(const Opt: tDecOptions; const Hex: string);
    function Has(const Part: string): Boolean;
    function Count(const Part: string): Integer;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestSeedCrcCapture;
    procedure TestSeedBccCapture;
    procedure TestLineRange;
    procedure TestFrameAcrossChunks;
    procedure TestChecksumMismatch;
    procedure TestHalfDuplex;
    procedure TestShortChunkReported;
    procedure TestHexText;
    procedure TestFT12;
    procedure TestFT12AsduDecoded;
    procedure TestICS;
    procedure TestTraceLogReadsBack;
  end;

implementation

const
  NL = #10;
  { RACOM note, chapter 3: full duplex, CRC, PLC 00 and 03 }
  SeedCrc =
    'Příklad komunikace protokolem DF1 v režimu FULL DUPLEX' + NL +
    '13:33:33.058 rx;i  60 | S00' + NL +
    '1002 0300 0B00 7E00 0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100' + NL +
    '8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401 1003 15C6' + NL +
    '13:33:33.065 tx   2 | S00' + NL +
    '1006' + NL +
    '13:33:33.252 tx   44 | S00' + NL +
    '1002 0003 4B00 7E00 0000 D400 0000 3D7F 0080 827F 0080 E943 0100 8D91 1300' + NL +
    'E070 7200 E070 7200 0000 1003 0FC9' + NL +
    '13:33:33.267 rx;i  2 | S00' + NL +
    '1006' + NL +
    '13:33:33.299 rx;i  39 | S00' + NL +
    '1002 0300 0A00 7F00 0000 3D7F 7F00 4C08 910B 546F 5472 616E 7370 6F72 7400' + NL +
    '2800 1010 0010 03B6 99' + NL +
    '13:33:33.304 tx   2 | S00' + NL +
    '1006' + NL +
    '13:33:33.482 tx   56 | S00' + NL +
    '1002 0003 4A00 7F00 0000 827F 7F00 CC00 0000 C300 0A1A 0200 0300 0400 0500' + NL +
    '0600 0700 0800 0000 0000 0000 0000 0000 0000 0000 0000 1003 854D' + NL +
    '13:33:33.500 rx;i  2 | S00' + NL +
    '1006' + NL +
    '13:33:33.540 rx;i  39 | S00' + NL +
    '1002 0300 0B00 8F00 0000 4E02 2006 2401 07E9 E943 0100 8D91 1300 0200 2002' + NL +
    '2401 1010 0010 03A3 C4' + NL +
    '13:33:33.545 tx   2 | S00' + NL +
    '1006' + NL +
    '13:33:33.720 tx   28 | S00' + NL +
    '1002 0003 4B00 8F00 0000 CE00 0000 E943 0100 8D91 1300 0000 1003 B56A' + NL +
    '13:33:33.731 rx;i  2 | S00' + NL +
    '1006' + NL;
  { RACOM note: the unsuccessful exchanges (BCC), with the prose around them }
  SeedBcc =
    'V následujícím příkladu neúspěšné komunikace je sekvence dodávaná z' + NL +
    'PLC nahrazena znaky AAAA.' + NL + NL +
    '>>' + NL +
    '06:22:58.798 tx   9 | S00' + NL +
    '1002 0E0D AAAA 1003 91' + NL +
    '06:22:58.813 rx;i  2 | S00' + NL +
    '1015' + NL +
    '06:22:58.814 tx   9 | S00' + NL +
    '1002 0E0D AAAA 1003 91' + NL +
    '06:22:58.829 rx;i  2 | S00' + NL +
    '1015' + NL + NL +
    'Komunikační jednotka CU (rádiový modem) vyslala data' + NL + NL +
    '1002 0E0D AAAA 1003 91' + NL +
    'do PLC a dostala' + NL +
    '1015 = NAK (nerozumím)' + NL +
    '>>' + NL +
    '06:23:21.694 tx   9 | S00' + NL +
    '1002 0E0D AAAA 1003 91' + NL +
    '06:23:22.694 tx   2 | S00' + NL +
    '1005' + NL;

procedure TTestChnFrameDecode.SetUp;
begin
  Lines := TStringList.Create;
end;

procedure TTestChnFrameDecode.TearDown;
begin
  Lines.Free;
end;

procedure TTestChnFrameDecode.Run(const Opt: tDecOptions; const Text: AnsiString);
var
  F: tTrcFrames;
  N: LongInt;
begin
  Lines.Clear;
  N := TrcReadText(Text, F);
  DecodeRun(Opt, F, N, Lines, Stats);
end;

procedure TTestChnFrameDecode.RunHex(const Opt: tDecOptions; const Hex: string);
var
  F: tTrcFrames;
  D: tTrcBytes;
  Err: string;
begin
  Lines.Clear;
  AssertTrue('hex', DecodeHexText(Hex, D, Err));
  DecodeBytesAsChunk(D, F);
  DecodeRun(Opt, F, 1, Lines, Stats);
end;

function TTestChnFrameDecode.Count(const Part: string): Integer;
var
  I: Integer;
begin
  Result := 0;
  for I := 0 to Lines.Count - 1 do
    if Pos(Part, Lines[I]) > 0 then
      Inc(Result);
end;

function TTestChnFrameDecode.Has(const Part: string): Boolean;
begin
  Result := Count(Part) > 0;
  if not Result then
    WriteLn(StdErr, 'not found: ', Part, LineEnding, Lines.Text);
end;

procedure TTestChnFrameDecode.TestSeedCrcCapture;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);          { --df1 --crc }
  Run(Opt, SeedCrc);
  AssertEquals('chunks', 12, Stats.Chunks);
  AssertEquals('frames: 6 data frames, 6 ACKs', 12, Stats.Frames);
  AssertEquals('errors', 0, Stats.Errors);
  AssertEquals('incomplete', 0, Stats.Incomplete);
  AssertEquals('ACKs', 6, Count('DF1 ACK'));
  AssertTrue('first command', Has('rx DF1 DST=3 SRC=0 CMD=$0B STS=$00 TNS=$007E (command), 48 data bytes: 00 00 54 02'));
  AssertTrue('its CRC, low byte first on the wire', Has('CRC $C615 ok'));
  AssertTrue('its reply', Has('tx DF1 DST=0 SRC=3 CMD=$4B STS=$00 TNS=$007E (reply), 32 data bytes'));
  { DLE DLE in the data is one $10 byte: ... 28 00 10 00 }
  AssertTrue('stuffed DLE', Has('74 00 28 00 10 00, CRC $99B6 ok'));
  AssertTrue('last reply', Has('CMD=$4B STS=$00 TNS=$008F (reply), 16 data bytes'));
end;

procedure TTestChnFrameDecode.TestSeedBccCapture;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.Crc := False;             { --df1 --bcc }
  Run(Opt, SeedBcc);
  AssertEquals('chunks (the stray line in the prose is no chunk)', 6, Stats.Chunks);
  AssertEquals('frames: NAK, NAK, ENQ', 3, Stats.Frames);
  AssertEquals('NAKs', 2, Count('rx DF1 NAK'));
  AssertEquals('ENQ', 1, Count('tx DF1 ENQ'));
  { 0E 0D AA AA: BCC $91 right, but no room for STS and TNS }
  AssertEquals('errors', 3, Stats.Errors);
  AssertEquals('each one a malformed frame with a good BCC', 3,
    Count('tx DF1 ERROR $20 DF1: malformed frame: BCC $91 ok, but only 4 bytes between DLE STX and DLE ETX (0E 0D AA AA)'));
end;

procedure TTestChnFrameDecode.TestLineRange;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.FirstLine := 5;           { headers on lines 5 (tx 2) and 7 (tx 44) }
  Opt.LastLine := 9;
  Run(Opt, SeedCrc);
  AssertEquals('chunks on lines 5..9', 2, Stats.Chunks);
  AssertEquals('frames', 2, Stats.Frames);
  AssertTrue(Has('13:33:33.065 tx 2 bytes (line 5)'));
  AssertTrue(Has('13:33:33.252 tx 44 bytes (line 7)'));
  AssertEquals('nothing from line 10 on', 0, Count('(line 10)'));
end;

procedure TTestChnFrameDecode.TestFrameAcrossChunks;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.Crc := False;
  { echo 'A' (BCC $B3) in two rx chunks, a tx ACK between them }
  Run(Opt, '10:00:00.000 rx 6 | x' + NL + '1002 0100 0600' + NL +
           '10:00:00.001 tx 2 | x' + NL + '1006' + NL +
           '10:00:00.002 rx 7 | x' + NL + '0500 0041 1003 B3' + NL +
           '10:00:00.003 rx 3 | x' + NL + '1002 01' + NL);
  AssertEquals('frames', 2, Stats.Frames);
  AssertEquals('the frame is printed under its last chunk', 'rx 7 bytes',
    Copy(Lines[Lines.IndexOf('  tx DF1 ACK (DLE ACK)') + 1], 14, 10));
  AssertTrue(Has('rx DF1 DST=1 SRC=0 CMD=$06 FNC=$00 STS=$00 TNS=$0005 (Echo), 1 data bytes: 41, BCC $B3 ok'));
  AssertEquals('ends inside a frame', 1, Stats.Incomplete);
  AssertTrue(Has('rx: input ends inside a frame'));
end;

procedure TTestChnFrameDecode.TestChecksumMismatch;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  RunHex(Opt, '10 02 01 00 06 00 05 00 00 41 10 03 D7 C2');
  AssertEquals('errors', 1, Stats.Errors);
  AssertTrue(Has('ERROR $21 DF1: checksum (BCC/CRC) error: received CRC $C2D7, computed $C1D7'));
  RunHex(Opt, '10 02 01 00 06 00 05 00 00 41 10 03 D7 C1');
  AssertEquals('good CRC', 0, Stats.Errors);
  AssertTrue(Has('CRC $C1D7 ok'));
end;

procedure TTestChnFrameDecode.TestHalfDuplex;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.Crc := False;
  Opt.Half := True;              { master = tx }
  Run(Opt, '10:00:00.000 tx 16 | x' + NL + '1001 0110 0201 0006 0005 0000 4110 03B2' + NL +
           '10:00:00.001 rx 2 | x' + NL + '1006' + NL +
           '10:00:00.002 tx 4 | x' + NL + '1005 01FF' + NL +
           '10:00:00.003 rx 12 | x' + NL + '1002 0001 4600 0500 4110 0373' + NL +
           '10:00:00.004 tx 2 | x' + NL + '1006' + NL +
           '10:00:00.005 tx 4 | x' + NL + '1005 02FE' + NL +
           '10:00:00.006 rx 2 | x' + NL + '1004' + NL);
  AssertEquals('errors', 0, Stats.Errors);
  AssertEquals('frames', 7, Stats.Frames);
  AssertTrue('master frame with STN', Has('tx DF1 STN=1 DST=1 SRC=0 CMD=$06 FNC=$00'));
  AssertTrue('poll of station 1', Has('tx DF1 poll STN=1'));
  AssertTrue('poll of station 2 too', Has('tx DF1 poll STN=2'));
  AssertTrue('reply named by TNS', Has('(reply to Echo), 1 data bytes: 41, BCC $73 ok'));
  AssertTrue('EOT', Has('rx DF1 EOT'));
end;

procedure TTestChnFrameDecode.TestShortChunkReported;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Run(Opt, '10:00:00.000 tx 4 | x' + NL + '1006' + NL + '10:00:00.001 rx 2 | x' + NL + '1006' + NL);
  AssertEquals('chunks', 2, Stats.Chunks);
  AssertEquals('bad chunks', 1, Stats.BadChunks);
  AssertTrue(Has('tx 4 bytes (line 1) - the capture holds 2 bytes'));
end;

procedure TTestChnFrameDecode.TestHexText;
var
  D: tTrcBytes;
  Err: string;
begin
  AssertTrue(DecodeHexText('0x10,0x02 1003'#10'ab', D, Err));
  AssertEquals('10 02 10 03 AB', BytesToHex(D, Length(D)));
  AssertTrue('0X as well', DecodeHexText('0X1F 0x0a', D, Err));
  AssertEquals('1F 0A', BytesToHex(D, Length(D)));
  AssertFalse('odd digits', DecodeHexText('10 020', D, Err));
  AssertTrue('says where', Pos('character 4', Err) > 0);
  AssertEquals('nothing kept', 0, Length(D));
  AssertTrue('empty', DecodeHexText('', D, Err));
  AssertEquals(0, Length(D));
end;

procedure TTestChnFrameDecode.TestFT12;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.Proto := dpFT12;
  Opt.AddrLen := 1;
  { fixed frame: CODE $49 ADDR 1, SUM $4A; a single E5; then SUM wrong }
  RunHex(Opt, '10 49 01 4A 16 E5 10 49 01 4B 16');
  AssertEquals('frames', 2, Stats.Frames);
  AssertTrue(Has('rx FT1.2 fixed frame CODE=$49 (PRM=1 FCB/ACD=0 FCV/DFC=0 FC=9) ADDR=1, 0 data bytes, checksum ok'));
  AssertTrue(Has('rx FT1.2 single character ACK ($E5)'));
  AssertEquals('errors', 1, Stats.Errors);
  AssertTrue(Has('FT1.2 ERROR $20'));
end;

{ A variable frame's user data is an ASDU, decoded with the field sizes of
  the options: lib60870's interrogation (CODE $73 ADDR 1, SUM = 73 + 01 +
  64 + 01 + 06 + 01 + 14 = F4) and the same with COT 1, CA 1, IOA 2
  (64 01 06 01 00 00 14, SUM = 73+01+64+01+06+01+14 = F4 again). }
procedure TTestChnFrameDecode.TestFT12AsduDecoded;
var
  Opt: tDecOptions;
  Err: AnsiString;
begin
  DecodeDefaults(Opt);
  Opt.Proto := dpFT12;
  RunHex(Opt, '68 0C 0C 68 73 01 64 01 06 00 01 00 00 00 00 14 F4 16');
  AssertTrue(Has('rx FT1.2 variable frame L=12 CODE=$73 (PRM=1 FCB/ACD=1 FCV/DFC=1 FC=3) ADDR=1, '
    + '10 data bytes: C_IC_NA_1 ACTIVATION CA 1: IOA 0 = 20, checksum ok'));
  AssertTrue(DecodeOption('--cot-size', '1', Opt, Err) and (Err = ''));
  AssertTrue(DecodeOption('--ca-size', '1', Opt, Err) and (Err = ''));
  AssertTrue(DecodeOption('--ioa-size', '2', Opt, Err) and (Err = ''));
  RunHex(Opt, '68 09 09 68 73 01 64 01 06 01 00 00 14 F4 16');
  AssertTrue(Has('7 data bytes: C_IC_NA_1 ACTIVATION CA 1: IOA 0 = 20, checksum ok'));
  { a malformed ASDU is said so, with its octets }
  RunHex(Opt, '68 06 06 68 73 01 64 01 06 01 E0 16');
  AssertTrue(Has('4 data bytes: bad ASDU: C_IC_NA_1 with 1 object(s) needs 7 octets, got 4: 64 01 06 01'));
  AssertTrue(DecodeOption('--ioa-size', '4', Opt, Err));
  AssertEquals('--ioa-size wants 1, 2 or 3', Err);
end;

procedure TTestChnFrameDecode.TestICS;
var
  Opt: tDecOptions;
begin
  DecodeDefaults(Opt);
  Opt.Proto := dpICS;
  { SOH SOH SOH '2' STX '1RD0,0,10,15' ETX SUM $3C EOT (TestChnICSCodec) }
  RunHex(Opt, '01 01 01 32 02 31 52 44 30 2C 30 2C 31 30 2C 31 35 03 3C 04');
  AssertEquals('errors', 0, Stats.Errors);
  AssertTrue(Has('rx ICS DNO=2 SNO=1 OP=RD BLOCK=0, 3 numbers: 0 10 15, SUM $3C ok'));
  RunHex(Opt, '01 01 01 32 02 31 52 44 30 2C 30 2C 31 30 2C 31 35 03 3D 04');
  AssertEquals('bad SUM', 1, Stats.Errors);
  AssertTrue(Has('ICS ERROR $21'));
end;

procedure StepStation(Data: Pointer);
begin
  DF1StationStep(pDF1Station(Data)^);
end;

procedure TTestChnFrameDecode.TestTraceLogReadsBack;
var
  Dir, Err, Log: string;
  M, S: pChnVirt;
  Table: tSlcTable;
  Station: tDF1Station;
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Line: Integer;
  Opt: tDecOptions;
begin
  Dir := MakeTempDir('decode');
  M := nil;
  S := nil;
  try
    Log := Dir + 'trace.log';
    AssertTrue(SlcLoadConfig(Table, 'N7 4'#10'N7:0 = 5 6', Line, Err));
    S := OpenStack('DF1', 'NAM=DF1 NOD=1 DNO=0 MAS=SLAVE CRC=ON NAM=LOOP PAIR=DECTRC END=2', Err);
    AssertTrue(Err, S <> nil);
    M := OpenStack('DF1', 'NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=TRC FILE=' + Log +
      ' NAM=LOOP PAIR=DECTRC END=1', Err);
    AssertTrue(Err, M <> nil);
    SlcStationInit(Station, S, @Table);
    FillChar(Req, SizeOf(Req), 0);
    Req.MessType := tpDataMess;
    Req.CF := CF_ProtectRead3Addr;
    Req.Tns := $0102;
    Req.Data[0] := 4; Req.Data[1] := 7; Req.Data[2] := $89;
    AssertEquals('exchange', res_Ok, DF1Transact(M, Req, 13, Rep, RepLen, @StepStation, @Station, 500));
    Dispose(M, Done);          { closes the log }
    M := nil;
    DecodeDefaults(Opt);
    Run(Opt, ReadFileText(Log));
    AssertEquals('errors', 0, Stats.Errors);
    AssertEquals('incomplete', 0, Stats.Incomplete);
    AssertEquals('command, ACK, reply, ACK', 4, Stats.Frames);
    AssertTrue(Has('tx DF1 DST=1 SRC=0 CMD=$0F FNC=$A2 STS=$00 TNS=$0102 (Protected Typed Logical Read (3 addr)), 5 data bytes: 04 07 89 00 00'));
    AssertTrue(Has('rx DF1 DST=0 SRC=1 CMD=$4F STS=$00 TNS=$0102 (reply to Protected Typed Logical Read (3 addr)), 4 data bytes: 05 00 06 00'));
  finally
    if M <> nil then Dispose(M, Done);
    if S <> nil then Dispose(S, Done);
    RemoveTempDir(Dir);
  end;
end;

initialization
  RegisterTest(TTestChnFrameDecode);
end.
