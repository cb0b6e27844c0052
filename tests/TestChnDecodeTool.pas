{ tools/chndecode as built, on files the test writes: the DF1 check found
  from the frames when neither --crc nor --bcc is given (a BCC trace whose
  checksums were worked out by hand - the two's complement of the byte
  sum - and df1py3's CRC frames of tests/data), exit code 2 for damaged
  input (a pcap damaged after its first record, a record announcing
  4 GiB), lengths never negative, and ChnPcap's reading of huge length
  fields under the test build's range checks. }
unit TestChnDecodeTool;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnTrcFormat, ChnPcap,
  ChnFrameDecode, BinSupport, TestTempDir;

type
  TTestChnDecodeTool = class(TTestCase)
  private
    Dir: string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestBccFoundFromTheFrames;
    procedure TestCrcFoundFromTheFrames;
    procedure TestGivenCheckIsKept;
    procedure TestPcapDamagedAfterFirstRecordExits2;
    procedure TestHugeLengthFieldsUnsigned;
    procedure TestIec104Capture;
    procedure TestIec104BrokenStream;
  end;

implementation

const
  NL = #10;
  { DF1 full duplex with BCC: Echo (CMD 06 FNC 00, 'A') from 0 to 1, TNS 1,
    BCC $B7 = -(01+00+06+00+01+00+00+41); the reply 46, BCC $77 }
  BccTrace =
    '10:00:00.000 tx   13 | TRC' + NL +
    '1002 0100 0600 0100 0041 1003 B7' + NL +
    '10:00:00.010 rx   2 | TRC' + NL +
    '1006' + NL +
    '10:00:00.020 rx   12 | TRC' + NL +
    '1002 0001 4600 0100 4110 0377' + NL +
    '10:00:00.030 tx   2 | TRC' + NL +
    '1006' + NL;

{ IEC 104 worked out by hand: STARTDT act (68 04 07 00 00 00); an I frame
  N(S) = 0, N(R) = 1 (02 00 = 2 shr 1) holding C_IC_NA_1, COT 6, CA 1,
  IOA 0, QOI 20; its answer N(S) = 1 (02 00), N(R) = 1, COT 7; an S frame
  N(R) = 2 (04 00). }
const
  Iec104Trace =
    '10:00:00.000 tx   6 | TRC' + NL +
    '6804 0700 0000' + NL +
    '10:00:00.010 tx   16 | TRC' + NL +
    '680E 0000 0200 6401 0600 0100 0000 0014' + NL +
    '10:00:00.020 rx   22 | TRC' + NL +
    '680E 0200 0200 6401 0700 0100 0000 0014 6804 0100 0400' + NL;

procedure TTestChnDecodeTool.TestIec104Capture;
var
  Output: string;
begin
  WriteFileText(Dir + '104.log', Iec104Trace);
  AssertEquals(Output, 0, RunBin('chndecode', ['--iec104', Dir + '104.log'], 10000, Output));
  AssertTrue(Output, Pos('tx IEC104 U STARTDT act', Output) > 0);
  AssertTrue(Output, Pos('tx IEC104 I N(S)=0 N(R)=1: C_IC_NA_1 ACTIVATION CA 1: IOA 0 = 20', Output) > 0);
  AssertTrue(Output, Pos('rx IEC104 I N(S)=1 N(R)=1: C_IC_NA_1 ACTIVATION_CON CA 1: IOA 0 = 20', Output) > 0);
  AssertTrue(Output, Pos('rx IEC104 S N(R)=2', Output) > 0);
  AssertTrue(Output, Pos('3 chunks, 44 bytes: 4 frames, 0 errors, 0 incomplete', Output) > 0);
end;

{ a wrong start octet, a length octet of 3 and a U frame with two
  functions (STARTDT act + TESTFR act = 47h) are errors; the decoder finds
  the next 68h and goes on }
procedure TTestChnDecodeTool.TestIec104BrokenStream;
var
  Output: string;
begin
  WriteFileText(Dir + 'bad.hex', '67 68 03 00 68 04 47 00 00 00 68 04 0B 00 00 00');
  RunBin('chndecode', ['--iec104', '--hex', Dir + 'bad.hex'], 10000, Output);
  AssertTrue(Output, Pos('ERROR octet $67 where an APDU starts', Output) > 0);
  AssertTrue(Output, Pos('ERROR length octet 3 (4..253)', Output) > 0);
  AssertTrue(Output, Pos('ERROR control field 47 00 00 00', Output) > 0);
  AssertTrue(Output, Pos('IEC104 U STARTDT con', Output) > 0);
  AssertTrue(Output, Pos('1 frames, 3 errors', Output) > 0);
end;

procedure TTestChnDecodeTool.SetUp;
begin
  Dir := MakeTempDir('chndecode');
end;

procedure TTestChnDecodeTool.TearDown;
begin
  RemoveTempDir(Dir);
end;

procedure TTestChnDecodeTool.TestBccFoundFromTheFrames;
var
  Output: string;
  F: tTrcFrames;
  N: LongInt;
  Opt: tDecOptions;
  Why: AnsiString;
begin
  WriteFileText(Dir + 'bcc.log', BccTrace);
  AssertEquals('0 errors:'#10 + Output, 0, RunBin('chndecode', ['--df1', Dir + 'bcc.log'], 10000, Output));
  AssertTrue('says which it chose:'#10 + Output, Pos('DF1 check: BCC, found from the frames', Output) > 0);
  AssertTrue(Output, Pos('BCC $B7 ok', Output) > 0);
  AssertTrue(Output, Pos('BCC $77 ok', Output) > 0);
  AssertTrue(Output, Pos('4 chunks, 29 bytes: 4 frames, 0 errors, 0 incomplete', Output) > 0);
  { the unit's verdict and its reason }
  N := TrcReadText(BccTrace, F);
  DecodeDefaults(Opt);
  AssertFalse('BCC', DecodeGuessDF1Check(Opt, F, N, Why));
  AssertTrue(Why, Pos('BCC: 4 good, 0 broken', Why) > 0);
  AssertTrue('read as CRC a frame breaks: ' + Why, Pos('broken; BCC', Why) > 0);
end;

procedure TTestChnDecodeTool.TestCrcFoundFromTheFrames;
var
  Output, Hex, Line: string;
  L: TStringList;
begin
  { df1py3's requests, all CRC, as one hex stream }
  L := TStringList.Create;
  try
    L.LoadFromFile('tests/data/df1py3-requests.txt');
    Hex := '';
    for Line in L do
      if (Line <> '') and (Line[1] <> '#') and (Pos('|', Line) > 0) then
        Hex := Hex + Copy(Line, Pos('|', Line) + 1, MaxInt) + ' ';
  finally
    L.Free;
  end;
  WriteFileText(Dir + 'crc.hex', Hex);
  AssertEquals('0 errors:'#10 + Output, 0, RunBin('chndecode', ['--hex', Dir + 'crc.hex'], 10000, Output));
  AssertTrue('says which it chose:'#10 + Output, Pos('DF1 check: CRC, found from the frames', Output) > 0);
  AssertTrue(Output, Pos(' 0 errors, 0 incomplete', Output) > 0);
end;

procedure TTestChnDecodeTool.TestGivenCheckIsKept;
var
  Output: string;
begin
  WriteFileText(Dir + 'bcc.log', BccTrace);
  { told CRC, it decodes CRC: the frames are broken, and nothing is guessed }
  AssertEquals(1, RunBin('chndecode', ['--crc', Dir + 'bcc.log'], 10000, Output));
  AssertEquals(Output, 0, Pos('found from the frames', Output));
  AssertEquals(0, RunBin('chndecode', ['--bcc', Dir + 'bcc.log'], 10000, Output));
  AssertEquals(Output, 0, Pos('found from the frames', Output));
end;

procedure TTestChnDecodeTool.TestPcapDamagedAfterFirstRecordExits2;
var
  Output: string;
  F: tTrcFrames;
  N: LongInt;
  Pcap: AnsiString;
  Bad: array[0..15] of Byte;
begin
  N := TrcReadText(BccTrace, F);
  Pcap := PcapFromTrc(F, N, 1796079600);
  WriteFileText(Dir + 'good.pcap', Pcap);
  AssertEquals('the whole file'#10 + Output, 0, RunBin('chndecode', [Dir + 'good.pcap'], 10000, Output));
  { after the first record (24 + 16 + 12 + 13 bytes) a record header
    announcing 100000 bytes: impossible, the rest is lost }
  FillChar(Bad, SizeOf(Bad), 0);
  Bad[8] := $A0; Bad[9] := $86; Bad[10] := $01;      { incl_len 100000 }
  Bad[12] := $A0; Bad[13] := $86; Bad[14] := $01;    { orig_len 100000 }
  Move(Bad, Pcap[24 + 16 + 12 + 13 + 1], SizeOf(Bad));
  WriteFileText(Dir + 'damaged.pcap', Pcap);
  AssertEquals('damaged: exit 2'#10 + Output, 2, RunBin('chndecode', ['--bcc', Dir + 'damaged.pcap'], 10000, Output));
  AssertTrue('names the record:'#10 + Output, Pos('record 2: impossible length 100000', Output) > 0);
  AssertTrue('what could be read is decoded:'#10 + Output, Pos('BCC $B7 ok', Output) > 0);
  { cut off inside the second record's header }
  WriteFileText(Dir + 'cut.pcap', Copy(Pcap, 1, 24 + 16 + 12 + 13 + 7));
  AssertEquals('cut: exit 2'#10 + Output, 2, RunBin('chndecode', ['--bcc', Dir + 'cut.pcap'], 10000, Output));
end;

procedure TTestChnDecodeTool.TestHugeLengthFieldsUnsigned;
var
  Output: string;
  F, G: tTrcFrames;
  N: LongInt;
  Pcap: AnsiString;
  Info: tPcapInfo;
  V: LongWord;
begin
  N := TrcReadText(BccTrace, F);
  Pcap := PcapFromTrc(F, 1, 1796079600);
  { the first record's orig_len: $FFFFFFF0 (incl_len stays the real 25) }
  V := NtoLE(LongWord($FFFFFFF0));
  Move(V, Pcap[24 + 12 + 1], 4);
  AssertEquals('read, flagged short', res_Ok, PcapReadBytes(Pcap, 0, G, Info));
  AssertEquals(1, Length(G));
  AssertTrue('length not negative', G[0].Len > 0);
  AssertEquals('flagged short', res_TrcShort, G[0].Status);
  WriteFileText(Dir + 'huge.pcap', Pcap);
  AssertEquals('a short record is damage: exit 2'#10 + Output, 2,
    RunBin('chndecode', ['--bcc', Dir + 'huge.pcap'], 10000, Output));
  AssertEquals('no negative length:'#10 + Output, 0, Pos(' -', Copy(Output, 1, Pos('bytes', Output))));
  AssertTrue(Output, Pos('the capture holds 13 bytes', Output) > 0);
  { a link type above 2^31 is named as it is (a range error before) }
  Pcap := PcapFromTrc(F, N, 1796079600);
  V := NtoLE(LongWord($FFFFFFFF));
  Move(V, Pcap[21], 4);
  AssertEquals(res_PcapLinkType, PcapReadBytes(Pcap, 0, G, Info));
  AssertEquals('link type 4294967295, RTAC serial is 250', Info.ErrText);
  { incl_len above 2^31: impossible, named unsigned }
  Pcap := PcapFromTrc(F, N, 1796079600);
  V := NtoLE(LongWord($90000000));
  Move(V, Pcap[24 + 8 + 1], 4);
  Move(V, Pcap[24 + 12 + 1], 4);
  AssertEquals(res_PcapCut, PcapReadBytes(Pcap, 0, G, Info));
  AssertEquals('record 1: impossible length 2415919104', Info.ErrText);
end;

initialization
  RegisterTest(TTestChnDecodeTool);
end.
