{ Tests of ChnPcap (pcap files of link type 250, RTAC serial) and of the
  trace layer's MOD=PCAP: record layouts, the bytes written against bytes
  worked out by hand from the pcap and RTAC-serial header definitions,
  the reader on hand-made files of both byte orders and with every kind of
  damage, a DF1 text trace through pcap and back unchanged, and an FT 1.2
  exchange of the library's master and slave over a pty, traced with
  MOD=PCAP and dissected by tshark as IEC 60870-5-101 (skipped, with the
  reason, when tshark is not installed). }
unit TestChnPcap;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTrcFormat,
  ChnPcap, ChnTrc, ChnLoop, TestSupport, TestTempDir;

type
  TTestChnPcap = class(TTestCase)
  private
    Dir: string;
    function Bytes(const Hex: string): AnsiString;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestLayout;
    procedure TestFileHeaderBytes;
    procedure TestRecordBytes;
    procedure TestReadOwnFile;
    procedure TestReadBigEndianAndNano;
    procedure TestReadBigEndianNano;
    procedure TestReadOtherEventsAndShortRecords;
    procedure TestReadDamagedFiles;
    procedure TestDf1TextTraceRoundTrip;
    procedure TestChndecodeTextToPcapToText;
    procedure TestChndecodeBadPcap;
    procedure TestFilesRewrittenByEditcap;
    procedure TestTrcParams;
    procedure TestTrcWritesPcap;
    procedure TestTrcAppendsOnlyToOwnPcap;
    {$IFDEF UNIX}
    procedure TestFT12ExchangeDissectedByTshark;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, ChnCom, ChnPty, ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnFT12Station,{$ENDIF}
  BinSupport,
  DateUtils, uString;

const
  { A DF1 conversation as the trace layer wrote it (README, make demo) }
  Df1Trace =
    '23:53:29.438 tx   17 | TRC'#10 +
    '1002 0100 0600 0000 0041 686F 6A10 0363 0F'#10 +
    '23:53:29.439 rx   18 | TRC'#10 +
    '1006 1002 0001 4600 0000 4168 6F6A 1003 3575'#10 +
    '23:53:29.439 tx   2 | TRC'#10 +
    '1006'#10 +
    '23:53:29.442 tx   18 | TRC'#10 +
    '1002 0100 0F00 0100 A214 0789 0000 1003 6046'#10 +
    '23:53:29.442 rx   34 | TRC'#10 +
    '1006 1002 0001 4F00 0100 0000 0A00 1400 1E00 2800 3200 3C00 4600 5000 5A00'#10 +
    '1003 3B0C'#10 +
    '23:59:59.999 tx   2 | TRC'#10 +
    '1006'#10 +
    '00:00:00.004 rx   2 | TRC'#10 +
    '1006'#10;

function TTestChnPcap.Bytes(const Hex: string): AnsiString;
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  SetLength(Result, Length(B));
  if Length(B) > 0 then
    Move(B[0], Result[1], Length(B));
end;

procedure TTestChnPcap.SetUp;
begin
  Dir := MakeTempDir('chnpcap');
end;

procedure TTestChnPcap.TearDown;
begin
  RemoveTempDir(Dir);
end;

procedure TTestChnPcap.TestLayout;
var
  F: tPcapFileHeader;
  R: tPcapRecHeader;
  T: tRtacHeader;
begin
  AssertEquals(24, SizeOf(tPcapFileHeader));
  AssertEquals(16, SizeOf(tPcapRecHeader));
  AssertEquals(12, SizeOf(tRtacHeader));
  AssertEquals(4, PtrUInt(@F.VerMajor) - PtrUInt(@F));
  AssertEquals(8, PtrUInt(@F.ThisZone) - PtrUInt(@F));
  AssertEquals(16, PtrUInt(@F.SnapLen) - PtrUInt(@F));
  AssertEquals(20, PtrUInt(@F.LinkType) - PtrUInt(@F));
  AssertEquals(8, PtrUInt(@R.InclLen) - PtrUInt(@R));
  AssertEquals(12, PtrUInt(@R.OrigLen) - PtrUInt(@R));
  AssertEquals(4, PtrUInt(@T.TsUSec) - PtrUInt(@T));
  AssertEquals(8, PtrUInt(@T.Event) - PtrUInt(@T));
  AssertEquals(9, PtrUInt(@T.Lines) - PtrUInt(@T));
  AssertEquals(10, PtrUInt(@T.Footer) - PtrUInt(@T));
end;

procedure TTestChnPcap.TestFileHeaderBytes;
begin
  { magic A1B2C3D4 little-endian, 2.4, zone 0, sigfigs 0, snaplen 65547
    ($1000B), link type 250 ($FA) }
  AssertEquals(HexBytes(PByte(Bytes('D4C3B2A102000400000000000000000' +
    '00B000100FA000000')), 24),
    HexBytes(PByte(PcapFileHeaderBytes), Length(PcapFileHeaderBytes)));
  AssertTrue(PcapIsOwnHeader(PcapFileHeaderBytes));
end;

procedure TTestChnPcap.TestRecordBytes;
var
  Ack: array[0..1] of Byte = ($10, $06);
  R: AnsiString;
begin
  { 2023-11-14 22:13:20 UTC = 1700000000 = $6553F100, 123456 us = $01E240;
    length 12 + 2 = 14; RTAC header big-endian, event 3 (DATA_TX_END) }
  R := PcapRecordBytes(1700000000, 123456, trcTx, Ack, 2);
  AssertEquals(HexBytes(PByte(Bytes('00F15365 40E20100 0E000000 0E000000' +
    ' 6553F100 0001E240 03 00 0000 1006')), 30), HexBytes(PByte(R), Length(R)));
  R := PcapRecordBytes(1700000000, 123456, trcRx, Ack, 2);
  AssertEquals('rx is DATA_RX_END', 4, Ord(R[16 + 9]));
end;

procedure TTestChnPcap.TestReadOwnFile;
var
  Data: array[0..2] of Byte = ($10, $05, $AA);
  F: tTrcFrames;
  Info: tPcapInfo;
  S: AnsiString;
begin
  S := PcapFileHeaderBytes + PcapRecordBytes(86400 + 3600, 5000, trcTx, Data, 3) +
    PcapRecordBytes(86400 + 3601, 999999, trcRx, Data, 1);
  AssertEquals(res_Ok, PcapReadBytes(S, 0, F, Info));
  AssertEquals(2, Length(F));
  AssertEquals(2, Info.Records);
  AssertEquals(0, Info.Skipped);
  AssertEquals('01:00:00.005', TrcTimeText(F[0].TimeMs));
  AssertTrue(F[0].Dir = trcTx);
  AssertEquals('tx', F[0].DirText);
  AssertEquals(3, F[0].Len);
  AssertEquals('10 05 AA', HexBytes(@F[0].Data[0], 3));
  AssertEquals(1, F[0].Line);
  AssertEquals(2, F[1].Line);
  AssertTrue(F[1].Dir = trcRx);
  AssertEquals('01:00:01.999', TrcTimeText(F[1].TimeMs));
  { the offset moves UTC to local time, across midnight }
  AssertEquals(res_Ok, PcapReadBytes(S, -7200, F, Info));
  AssertEquals('23:00:00.005', TrcTimeText(F[0].TimeMs));
end;

procedure TTestChnPcap.TestReadBigEndianAndNano;
var
  F: tTrcFrames;
  Info: tPcapInfo;
begin
  { big-endian, microseconds: header, one record of 12 + 1 bytes, event 2 }
  AssertEquals(res_Ok, PcapReadBytes(Bytes('A1B2C3D4 0002 0004 00000000 00000000 00010000 000000FA' +
    '00000E10 00000007 0000000D 0000000D  00000E10 00000007 02 1F 0000 E5'), 0, F, Info));
  AssertTrue(Info.Swapped);
  AssertEquals(1, Length(F));
  AssertTrue('RX_START is rx', F[0].Dir = trcRx);
  AssertEquals('01:00:00.000', TrcTimeText(F[0].TimeMs));
  AssertEquals('E5', HexBytes(@F[0].Data[0], 1));
  { little-endian nanoseconds: 2500000 ns = 2 ms; TX_START is tx }
  AssertEquals(res_Ok, PcapReadBytes(Bytes('4D3CB2A1 0200 0400 00000000 00000000 00000100 FA000000' +
    '100E0000 A0252600 0D000000 0D000000  00000E10 00000002 01 00 0000 A2'), 0, F, Info));
  AssertFalse(Info.Swapped);
  AssertEquals('01:00:00.002', TrcTimeText(F[0].TimeMs));
  AssertTrue(F[0].Dir = trcTx);
end;

{ The fourth magic: big-endian nanoseconds, A1 B2 3C 4D on disk; the
  fraction 2,500,000 ns (00 26 25 A0) is 2 ms, not 2,500 s. }
procedure TTestChnPcap.TestReadBigEndianNano;
var
  F: tTrcFrames;
  Info: tPcapInfo;
begin
  AssertEquals(res_Ok, PcapReadBytes(Bytes('A1B23C4D 0002 0004 00000000 00000000 00010000 000000FA' +
    '00000E10 002625A0 0000000D 0000000D  00000E10 00000007 02 1F 0000 E5'), 0, F, Info));
  AssertTrue(Info.Swapped);
  AssertEquals(1, Length(F));
  AssertEquals('01:00:00.002', TrcTimeText(F[0].TimeMs));
  AssertEquals('E5', HexBytes(@F[0].Data[0], 1));
end;

procedure TTestChnPcap.TestReadOtherEventsAndShortRecords;
var
  F: tTrcFrames;
  Info: tPcapInfo;
begin
  AssertEquals(res_Ok, PcapReadBytes(PcapFileHeaderBytes +
    { a status change (event 0) with no data }
    Bytes('00000000 00000000 0C000000 0C000000 00000000 00000000 00 01 0000') +
    { a record of 4 bytes: no RTAC header }
    Bytes('00000000 00000000 04000000 04000000 01020304') +
    { a framing error (event 7) with a byte }
    Bytes('00000000 00000000 0D000000 0D000000 00000000 00000000 07 00 0000 55') +
    { data cut by the snap length: 2 of 5 bytes in the file }
    Bytes('00000000 00000000 0E000000 11000000 00000000 00000000 04 00 0000 1002'),
    0, F, Info));
  AssertEquals(4, Info.Records);
  AssertEquals(3, Info.Skipped);
  AssertEquals(1, Length(F));
  AssertEquals(4, F[0].Line);
  AssertEquals(5, F[0].Len);
  AssertEquals(2, Length(F[0].Data));
  AssertEquals(res_TrcShort, F[0].Status);
end;

procedure TTestChnPcap.TestReadDamagedFiles;
var
  F: tTrcFrames;
  Info: tPcapInfo;
  Ack: array[0..1] of Byte = ($10, $06);
  Good: AnsiString;
begin
  AssertEquals(res_PcapNotPcap, PcapReadBytes('', 0, F, Info));
  AssertEquals(res_PcapNotPcap, PcapReadBytes(Copy(PcapFileHeaderBytes, 1, 23), 0, F, Info));
  AssertEquals(res_PcapNotPcap, PcapReadBytes(Df1Trace, 0, F, Info));
  AssertTrue(Info.ErrText, Pos('no pcap magic', Info.ErrText) > 0);
  AssertEquals(res_PcapNotPcap, PcapReadBytes(Bytes('0A0D0D0A 1C000000 4D3C2B1A 01000000' +
    ' FFFFFFFF FFFFFFFF 1C000000'), 0, F, Info));
  AssertTrue(Info.ErrText, Pos('pcapng', Info.ErrText) > 0);
  { Ethernet (1) }
  AssertEquals(res_PcapLinkType, PcapReadBytes(Bytes('D4C3B2A1 0200 0400 00000000 00000000' +
    ' FFFF0000 01000000'), 0, F, Info));
  AssertTrue(Info.ErrText, Pos('link type 1,', Info.ErrText) > 0);
  AssertEquals(0, Length(F));
  Good := PcapFileHeaderBytes + PcapRecordBytes(0, 0, trcTx, Ack, 2);
  { a record header cut off: the frames before it are kept }
  AssertEquals(res_PcapCut, PcapReadBytes(Good + Bytes('00000000 00000000 0E00'), 0, F, Info));
  AssertEquals(1, Length(F));
  AssertEquals(24 + 30, Info.ErrPos);
  AssertTrue(Info.ErrText, Pos('record 2', Info.ErrText) > 0);
  { a length beyond the snap length }
  AssertEquals(res_PcapCut, PcapReadBytes(Good + Bytes('00000000 00000000 FFFFFF7F FFFFFF7F'),
    0, F, Info));
  AssertTrue(Info.ErrText, Pos('impossible length', Info.ErrText) > 0);
  { more in the file than on the line }
  AssertEquals(res_PcapCut, PcapReadBytes(Good + Bytes('00000000 00000000 0E000000 0D000000'),
    0, F, Info));
  { the last record cut inside its data: kept, short }
  AssertEquals(res_Ok, PcapReadBytes(Copy(Good, 1, Length(Good) - 1), 0, F, Info));
  AssertEquals(1, Length(F));
  AssertEquals(res_TrcShort, F[0].Status);
  AssertEquals(1, Length(F[0].Data));
  AssertEquals('TRC: pcap file of another link type than RTAC serial (250)',
    ChResultText(res_PcapLinkType, 'TRC'));
end;

procedure TTestChnPcap.TestDf1TextTraceRoundTrip;
var
  F, G: tTrcFrames;
  Info: tPcapInfo;
  N, I: LongInt;
  P, Back: AnsiString;
begin
  N := TrcReadText(Df1Trace, F);
  AssertEquals(7, N);
  { 2026-12-01 00:00 local, at UTC+1 }
  P := PcapFromTrc(F, N, 1796079600);
  AssertEquals(24 + 7 * 28 + 17 + 18 + 2 + 18 + 34 + 2 + 2, Length(P));
  AssertEquals(res_Ok, PcapReadBytes(P, 3600, G, Info));
  AssertEquals(7, Length(G));
  Back := '';
  for I := 0 to High(G) do
    Back := Back + TrcFormat(G[I].TimeMs, G[I].Dir, G[I].Data[0], Length(G[I].Data),
      trcHex, 'TRC');
  AssertEquals(Df1Trace, StringReplace(Back, LineEnding, #10, [rfReplaceAll]));
  { the record after midnight is on the next day }
  AssertEquals(1796079600 + 86400 + 0, LEtoN(PLongWord(@P[24 + 6 * 28 + 17 + 18 + 2 + 18 + 34 + 2 + 1])^));
end;

{ S with every 'Prefix<digits>)' made '()'. }
function ChunkNumbersOut(const S, Prefix: string): string;
var
  P, Q: Integer;
begin
  Result := S;
  P := Pos(Prefix, Result);
  while P > 0 do
  begin
    Q := P + Length(Prefix);
    while (Q <= Length(Result)) and (Result[Q] in ['0'..'9']) do
      Inc(Q);
    Delete(Result, P + 1, Q - P - 1);
    P := Pos(Prefix, Result);
  end;
end;

procedure TTestChnPcap.TestChndecodeTextToPcapToText;
var
  Output, FromText, FromPcap: string;
  P: AnsiString;
  F: tTrcFrames;
  Info: tPcapInfo;
begin
  WriteFileText(Dir + 'df1.log', Df1Trace);
  AssertEquals(Output, 0, RunBin('chndecode', ['--to-pcap=' + Dir + 'df1.pcap',
    '--date=2026-12-01', Dir + 'df1.log'], 30000, Output));
  AssertTrue(Output, Pos('7 chunks written', Output) > 0);
  P := ReadFileText(Dir + 'df1.pcap');
  AssertEquals(res_Ok, PcapReadBytes(P, 0, F, Info));
  AssertEquals(7, Length(F));
  { 23:53:29 local time on 2026-12-01 }
  AssertEquals(DateTimeToUnix(LocalTimeToUniversal(EncodeDateTime(2026, 12, 1, 23, 53, 29, 0))),
    LEtoN(PLongWord(@P[25])^));
  AssertEquals(Output, 0, RunBin('chndecode', ['--to-text', Dir + 'df1.pcap'], 30000, Output));
  { (line ends are the system's: CR LF on Windows) }
  AssertEquals('text -> pcap -> text unchanged', Df1Trace,
    StringReplace(Output, #13#10, #10, [rfReplaceAll]));
  { the decoded frames are the same from either file }
  AssertEquals(0, RunBin('chndecode', ['--df1', Dir + 'df1.log'], 30000, FromText));
  AssertEquals(0, RunBin('chndecode', ['--df1', Dir + 'df1.pcap'], 30000, FromPcap));
  AssertTrue(FromPcap, Pos('(record 7)', FromPcap) > 0);
  AssertTrue(FromPcap, Pos('7 chunks, 93 bytes: 9 frames, 0 errors, 0 incomplete', FromPcap) > 0);
  { the same lines, but for the chunk numbers: header lines 1 3 5 ... of
    the text, records 1 2 3 ... of the pcap }
  AssertEquals(ChunkNumbersOut(FromText, '(line '), ChunkNumbersOut(FromPcap, '(record '));
end;

procedure TTestChnPcap.TestChndecodeBadPcap;
var
  Output: string;
begin
  WriteFileText(Dir + 'eth.pcap', Bytes('D4C3B2A1 0200 0400 00000000 00000000 FFFF0000 01000000'));
  AssertEquals(2, RunBin('chndecode', ['--pcap', Dir + 'eth.pcap'], 30000, Output));
  AssertTrue(Output, Pos('link type 1, RTAC serial is 250', Output) > 0);
  WriteFileText(Dir + 'text.log', Df1Trace);
  AssertEquals(2, RunBin('chndecode', ['--pcap', Dir + 'text.log'], 30000, Output));
  AssertTrue(Output, Pos('not a pcap file', Output) > 0);
  AssertEquals(2, RunBin('chndecode', ['--to-pcap=' + Dir + 'x.pcap', '--date=2026-02-30',
    Dir + 'text.log'], 30000, Output));
  AssertTrue(Output, Pos('--date wants YYYY-MM-DD', Output) > 0);
end;

{ Wireshark's own writer (editcap, package wireshark-common, which tshark
  pulls in) rewrites our file as microsecond pcap, nanosecond pcap and
  pcapng: the first two read back to the same chunks, the third is refused
  by name. }
procedure TTestChnPcap.TestFilesRewrittenByEditcap;
const
  Formats: array[0..1] of string = ('pcap', 'nsecpcap');
var
  Editcap, Output, Fmt: string;
  F, G: tTrcFrames;
  Info: tPcapInfo;
  N, I: LongInt;
begin
  Editcap := ExeSearch('editcap', GetEnvironmentVariable('PATH'));
  if Editcap = '' then
    Ignore('editcap is not installed (Debian package wireshark-common, with tshark): ' +
      'files written by Wireshark are not checked');
  N := TrcReadText(Df1Trace, F);
  WriteFileText(Dir + 'df1.pcap', PcapFromTrc(F, N, 1796079600));
  for Fmt in Formats do
  begin
    AssertEquals(Output, 0, RunExe(Editcap, ['-F', Fmt, Dir + 'df1.pcap', Dir + Fmt + '.out'],
      30000, Output));
    AssertEquals(Fmt, res_Ok, PcapReadBytes(ReadFileText(Dir + Fmt + '.out'), 3600, G, Info));
    AssertEquals(Fmt, N, Length(G));
    for I := 0 to N - 1 do
    begin
      AssertEquals(Fmt + ' time ' + IntToStr(I), F[I].TimeMs, G[I].TimeMs);
      AssertTrue(Fmt + ' direction ' + IntToStr(I), F[I].Dir = G[I].Dir);
      AssertEquals(Fmt + ' bytes ' + IntToStr(I), HexBytes(@F[I].Data[0], Length(F[I].Data)),
        HexBytes(@G[I].Data[0], Length(G[I].Data)));
    end;
  end;
  AssertEquals(Output, 0, RunExe(Editcap, ['-F', 'pcapng', Dir + 'df1.pcap', Dir + 'ng.out'],
    30000, Output));
  AssertEquals(res_PcapNotPcap, PcapReadBytes(ReadFileText(Dir + 'ng.out'), 0, G, Info));
  AssertTrue(Info.ErrText, Pos('pcapng', Info.ErrText) > 0);
end;

procedure TTestChnPcap.TestTrcParams;
var
  T: pChnVirt;
begin
  T := New(pChnTrc, Init);
  try
    T^.ChSetParam('NAM=TRC FILE=' + Dir + 'x.pcap MOD=pcap');
    AssertEquals(res_Ok, T^.ChResult);
    AssertEquals('NAM=TRC FILE=' + Dir + 'x.pcap MOD=PCAP', T^.ChGetParam(''));
    T^.ChSetParam('NAM=TRC MOD=DEC');
    AssertEquals('NAM=TRC FILE=' + Dir + 'x.pcap MOD=DEC', T^.ChGetParam(''));
    T^.ChSetParam('NAM=TRC MOD=PCAPX');
    AssertEquals(res_BadParam, T^.ChResult);
  finally
    Dispose(T, Done);
  end;
end;

procedure TTestChnPcap.TestTrcWritesPcap;
var
  A, B: pChnVirt;
  Err: string;
  Msg: array[0..299] of Byte;
  RBuf: array[0..999] of Byte;
  Len: Word;
  I: Integer;
  F: tTrcFrames;
  Info: tPcapInfo;
  Before, After: Int64;
begin
  for I := 0 to High(Msg) do
    Msg[I] := (I * 7) and $FF;
  Before := DateTimeToUnix(LocalTimeToUniversal(Now)) - 1;
  A := OpenStack('TRC', 'NAM=TRC FILE=' + Dir + 'a.pcap MOD=PCAP NAM=LOOP PAIR=PCA END=1', Err);
  AssertTrue(Err, A <> nil);
  B := OpenStack('LOOP', 'NAM=LOOP PAIR=PCA END=2', Err);
  try
    AssertTrue(Err, B <> nil);
    B^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    A^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    A^.ChSend(@Msg, 300);
    AssertEquals(res_Ok, A^.ChSendResult);
    AssertTrue(WaitReceive(B, 2000, A));
    B^.ChReceive(Len);
    B^.ChSend(@Msg[5], 2);
    AssertTrue(WaitReceive(A, 2000, B));
    A^.ChReceive(Len);
    AssertEquals(2, Len);
    A^.ChSetParam('NAM=TRC MOD=HEX');
    AssertEquals('no text into an open pcap', res_WrongState, A^.ChResult);
  finally
    Dispose(A, Done);
    if B <> nil then
      Dispose(B, Done);
  end;
  After := DateTimeToUnix(LocalTimeToUniversal(Now)) + 1;
  AssertEquals(res_Ok, PcapReadBytes(ReadFileText(Dir + 'a.pcap'), 0, F, Info));
  AssertEquals(2, Length(F));
  AssertTrue(F[0].Dir = trcTx);
  AssertEquals(300, Length(F[0].Data));
  AssertEquals(HexBytes(@Msg[0], 300), HexBytes(@F[0].Data[0], 300));
  AssertTrue(F[1].Dir = trcRx);
  AssertEquals(HexBytes(@Msg[5], 2), HexBytes(@F[1].Data[0], 2));
  { the record time is now, in UTC }
  Err := ReadFileText(Dir + 'a.pcap');
  I := LEtoN(PLongWord(@Err[25])^);
  AssertTrue(IntToStr(I), (I >= Before) and (I <= After));
end;

procedure TTestChnPcap.TestTrcAppendsOnlyToOwnPcap;
var
  A: pChnVirt;
  Err: string;
  F: tTrcFrames;
  Info: tPcapInfo;
  Msg: array[0..1] of Byte = ($10, $06);
  I: Integer;
begin
  WriteFileText(Dir + 'text.log', Df1Trace);
  A := OpenStack('TRC', 'NAM=TRC FILE=' + Dir + 'text.log MOD=PCAP NAM=LOOP PAIR=PCB END=1', Err);
  AssertTrue('a text log is no pcap to append to', A = nil);
  AssertTrue(Err, Pos('cannot be opened', Err) > 0);
  AssertEquals(Df1Trace, ReadFileText(Dir + 'text.log'));
  for I := 1 to 2 do
  begin
    A := OpenStack('TRC', 'NAM=TRC FILE=' + Dir + 'two.pcap MOD=PCAP NAM=LOOP PAIR=PCB END=1', Err);
    AssertTrue(Err, A <> nil);
    A^.ChSend(@Msg, 2);
    Dispose(A, Done);
  end;
  AssertEquals('one file header, two records', 24 + 2 * 30, Length(ReadFileText(Dir + 'two.pcap')));
  AssertEquals(res_Ok, PcapReadBytes(ReadFileText(Dir + 'two.pcap'), 0, F, Info));
  AssertEquals(2, Length(F));
end;

{$IFDEF UNIX}
type
  TFT12Pair = record
    St: tFT12Station;
  end;

function OnClassData(Data: Pointer; ClassNo: Byte; var Rep: tSendRecord; var Len: Word): Boolean;
begin
  { an ASDU of 4 octets for class 2 }
  Rep.Data[1] := $01;
  Rep.Data[2] := $01;
  Rep.Data[3] := $03;
  Rep.Data[4] := $07;
  Len := 4 + 4;
  Result := ClassNo = 2;
end;

function OnUserData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
begin
  Result := True;
end;

procedure StepSlave(Data: Pointer);
begin
  FT12StationStep(TFT12Pair(Data^).St);
end;

procedure TTestChnPcap.TestFT12ExchangeDissectedByTshark;
const
  { what the exchange must look like to tshark, frame by frame:
    event type, link address, PRM, primary FC, secondary FC }
  Expected: array[0..5] of string = (
    '0x03,7,1,0,',      { reset of remote link }
    '0x04,7,0,,0',      { ACK }
    '0x03,7,1,3,',      { user data, confirm expected }
    '0x04,7,0,,0',      { ACK }
    '0x03,7,1,11,',     { request class 2 data }
    '0x04,7,0,,8');     { user data }
var
  M, S: pChnVirt;
  Err, Tshark, Output: string;
  Pair: TFT12Pair;
  Link: tFT12Link;
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Lines: TStringList;
  I, Code: Integer;
begin
  Tshark := ExeSearch('tshark', GetEnvironmentVariable('PATH'));
  if Tshark = '' then
    Ignore('tshark is not installed (Debian package tshark): the pcap is not checked by Wireshark');
  M := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=7 ' +
    'NAM=TRC FILE=' + Dir + 'ft12.pcap MOD=PCAP NAM=COM DRV=PTY', Err);
  AssertTrue(Err, M <> nil);
  S := nil;
  Lines := TStringList.Create;
  try
    S := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=7 NAM=COM DEV=' +
      PtyLastSlave + '', Err);
    AssertTrue(Err, S <> nil);
    FT12StationInit(Pair.St, S);
    Pair.St.OnClassData := @OnClassData;
    Pair.St.OnUserData := @OnUserData;
    FT12LinkInit(Link, 7);
    AssertEquals(res_Ok, FT12ResetLink(M, Link, 2000, 1, @StepSlave, @Pair));
    FillChar(Req, SizeOf(Req), 0);
    Req.MessType := tpLongM;
    Req.FC := FCM_UserDataReply;
    Req.Data[1] := $2D;
    Req.Data[2] := $01;
    AssertEquals(res_Ok, FT12Transact(M, Link, Req, 6, Rep, RepLen, 2000, 1, @StepSlave, @Pair));
    AssertEquals(res_Ok, FT12RequestClass(M, Link, 2, Rep, RepLen, 2000, 1, @StepSlave, @Pair));
    Dispose(M, Done);
    M := nil;
    Code := RunExe(Tshark, ['-r', Dir + 'ft12.pcap', '-d', 'rtacser.data,iec60870_101',
      '-T', 'fields', '-E', 'separator=,', '-e', 'rtacser.eventtype',
      '-e', 'iec60870_101.linkaddr', '-e', 'iec60870_101.ctrl_prm',
      '-e', 'iec60870_101.ctrl_func_pri_to_sec', '-e', 'iec60870_101.ctrl_func_sec_to_pri'],
      30000, Output);
    AssertEquals(Output, 0, Code);
    Lines.Text := Output;
    for I := Lines.Count - 1 downto 0 do
      if Copy(Lines[I], 1, 2) <> '0x' then
        Lines.Delete(I);              { "Running as user root ..." }
    AssertEquals(Output, Length(Expected), Lines.Count);
    for I := 0 to High(Expected) do
      AssertEquals('frame ' + IntToStr(I + 1), Expected[I], Lines[I]);
    { and nothing is left as undissected data or malformed }
    Code := RunExe(Tshark, ['-r', Dir + 'ft12.pcap', '-d', 'rtacser.data,iec60870_101',
      '-Y', 'data or _ws.malformed or _ws.expert.severity >= warning'], 30000, Output);
    AssertEquals(Output, 0, Code);
    AssertEquals('no undissected or malformed frame', 0, Pos('RTAC', Output));
  finally
    Lines.Free;
    if M <> nil then
      Dispose(M, Done);
    if S <> nil then
      Dispose(S, Done);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnPcap);
end.
