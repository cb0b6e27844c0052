{ File transfer of IEC 60870-5-101/104 (types 120..127): the codec
  (ChnIecFile) against octets worked out by hand from the standard; two
  captures of our master against lib60870-C's file servers
  (tests/data/iec101-lib60870-files.trc over FT 1.2, iec104-lib60870-
  files.trc over IEC 104) decoded, their octets and checksums checked by
  hand, and our server fed the same requests answering as lib60870's did;
  our master (ChnIecFileClient) against our slave (ChnIecFileServer) on a
  pty (FT 1.2 unbalanced) and on loopback TCP (IEC 104): directory, a file
  of several sections and segments both ways, an unknown file, a hostile
  line flipping an octet (the section asked again, then the transfer
  failed), an interrupted transfer on both sides; and, when lib60870's
  examples are there (CHN_LIB60870 = its build directory), the live run
  against them. One thread: the master's Idle steps the slave. }
unit TestIecFile;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnPty,
  ChnFT1_2, ChnIec104, ChnIec104Codec, ChnIec101Asdu, ChnIec101Master, ChnIec101Slave, ChnIecFile,
  ChnIecFileServer, ChnIecFileClient, ChnWait, TestSupport, TestTempDir, BinSupport,
  Ft12Capture, Iec104Capture;

type
  tPair = (pPty, p104);
  TBoolArray = array of Boolean;
  TByteArrays = array of TBytes;

  TTestIecFile = class(TTestCase)
  private
    SChn, MChn: pChnVirt;
    FDir: string;
    Addr: Word;
    procedure OpenPair(K: tPair);
    procedure StepSlave;
    procedure PutFile(const Name: string; const Content: AnsiString);
    function CaptureAsdus(const Name: string; Is104: Boolean; out Tx: TBoolArray): TByteArrays;
    procedure CheckCapture(const Name: string; Is104: Boolean);
    procedure DirGetPut(K: tPair);
    procedure WaitSlaveIdle;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    M: tIecMaster;
    S: tIecSlaveStation;
    F: tIecFileServer;
    C: tIecFileClient;
    Mute: Boolean;          { the slave stops answering }
    MuteAfterSegment: Boolean;
    FlipSegments: Integer;  { octets of received segments to corrupt (master side) }
    FlipPutSegments: Integer;  { the same on the slave side }
    FlipFileChs, FlipPutFileChs: Boolean;   { the CHS of the last section (LSQ 1), master / slave side }
    DropAfterSegment: Boolean;   { the master hears no file ASDU after the first segment }
    Dropping: Boolean;
    SlaveHeard: string;     { the last file ASDU the slave received, in hex }
    SlaveLog: string;       { all of them but segments, ' | ' between }
    Refuse: string;         { OnDelete: the reason to keep a file ('' deletes) }
    Received: TStringList;
    OrigFile: tIecFileAsduFunc;
  published
    procedure TestCodecOctets;
    procedure TestCodecRefusals;
    procedure TestChecksum;
    procedure TestLib60870CaptureFt12;
    procedure TestLib60870Capture104;
    procedure TestDirGetPutPty;
    procedure TestDirGetPut104;
    procedure TestUnknownFileAndEmptyDirectory;
    procedure TestFlippedOctetSectionAskedAgain;
    procedure TestFlippedOctetEveryTimeFails;
    procedure TestFlippedOctetOnPutFails;
    procedure TestWrongFileChecksum;
    procedure TestServerSequence;
    procedure TestClientSequence;
    procedure TestInterruptedGet;
    procedure TestServerAbandonsALeftTransfer;
    procedure TestServerQueryLogOctets;
    procedure TestServerDeleteOctets;
    procedure TestServerSectionsOctets;
    procedure TestDeleteAndQueryLogPty;
    procedure TestGiveUpFreesTheSlave;
    procedure TestGetOneSection;
    procedure TestLiveLib60870;
  end;

implementation

{ The file of lib60870's file server examples: 800 octets in two sections
  of 400, section 1 octet i = i mod 256, section 2 octet i = (i + 1) mod 256. }
function Lib60870File: AnsiString;
var
  I: Integer;
begin
  SetLength(Result, 800);
  for I := 0 to 399 do
  begin
    Result[I + 1] := Chr(I mod 256);
    Result[I + 401] := Chr((I + 1) mod 256);
  end;
end;

{ The file we sent to lib60870: 600 octets, octet i = (7 i + 3) mod 256. }
function PutContent: AnsiString;
var
  I: Integer;
begin
  SetLength(Result, 600);
  for I := 0 to 599 do
    Result[I + 1] := Chr((7 * I + 3) mod 256);
end;

{ A file of N octets that no section boundary repeats: octet i = (i * 31 + i div 256) mod 256. }
function Pattern(N: Integer): AnsiString;
var
  I: Integer;
begin
  SetLength(Result, N);
  for I := 0 to N - 1 do
    Result[I + 1] := Chr((I * 31 + I div 256) mod 256);
end;

function Hex(const B: array of Byte; Len: Integer): string;
begin
  Result := BytesToHex(B, Len);
end;

procedure IdleSlave(Data: Pointer);
begin
  TTestIecFile(Data).StepSlave;
end;

{ The slave's view of each ASDU: a received segment may be corrupted in
  place before the slave takes it (a hostile line). }
procedure OnSlaveAsdu(Data: Pointer; Sent: Boolean; Buf: PByte; Len: Word);
var
  T: TTestIecFile;
begin
  T := TTestIecFile(Data);
  if not Sent and (Len > 0) and IecIsFileType(Buf[0]) and (Buf[0] <> F_SG_NA_1) then
  begin
    T.SlaveHeard := Hex(Buf[0..Len - 1], Len);
    if T.SlaveLog <> '' then
      T.SlaveLog := T.SlaveLog + ' | ';
    T.SlaveLog := T.SlaveLog + T.SlaveHeard;
  end;
  if not Sent and T.FlipPutFileChs and (Len = 14) and (Buf[0] = F_LS_NA_1) and (Buf[12] = Lsq_File) then
    Buf[13] := Buf[13] xor $01;
  if (Len > 20) and (Buf[0] = F_SG_NA_1) then
    if not Sent and (T.FlipPutSegments > 0) then
    begin
      Dec(T.FlipPutSegments);
      Buf[20] := Buf[20] xor $01;
    end;
end;

{ The master's view: a segment with one octet flipped, FlipSegments times;
  after the first segment the slave may fall silent. }
procedure OnMasterFile(Data: Pointer; Addr: Word; const Buf: array of Byte; Len: Word);
var
  T: TTestIecFile;
  B: array[0..IecMaxAsdu - 1] of Byte;
begin
  T := TTestIecFile(Data);
  Move(Buf[0], B[0], Len);
  if (Len > 20) and (B[0] = F_SG_NA_1) and (T.FlipSegments > 0) then
  begin
    Dec(T.FlipSegments);
    B[20] := B[20] xor $80;
  end;
  if T.FlipFileChs and (Len = 14) and (B[0] = F_LS_NA_1) and (B[12] = Lsq_File) then
    B[13] := B[13] xor $01;
  if (B[0] = F_SG_NA_1) and T.MuteAfterSegment then
    T.Mute := True;
  if T.Dropping then
    Exit;                                { lost on the way }
  T.Dropping := T.DropAfterSegment and (B[0] = F_SG_NA_1);
  T.OrigFile(@T.C, Addr, B, Len);
end;

{ Refuse: the reason to keep the file; 'steal': yes, but the file goes
  elsewhere first (the OS then fails to delete it, whoever runs the test). }
function OnDelete(Data: Pointer; Ioa: LongWord; Nof: Word; out Why: ShortString): Boolean;
var
  T: TTestIecFile;
begin
  T := TTestIecFile(Data);
  Why := T.Refuse;
  if Why = 'steal' then
  begin
    RenameFile(T.FDir + '/' + IntToStr(Ioa), T.FDir + '/stolen');
    Why := '';
  end;
  Result := Why = '';
end;

procedure OnReceived(Data: Pointer; Ioa: LongWord; Nof: Word; const Content: AnsiString);
begin
  TTestIecFile(Data).Received.Add(Format('%d %d %d', [Ioa, Nof, Length(Content)]));
end;

procedure TTestIecFile.StepSlave;
begin
  if not Mute then
    IecSlaveStep(S);
  ChnWaitAny(2);
end;

procedure TTestIecFile.SetUp;
begin
  SChn := nil;
  MChn := nil;
  Mute := False;
  MuteAfterSegment := False;
  FlipSegments := 0;
  FlipPutSegments := 0;
  DropAfterSegment := False;
  Dropping := False;
  SlaveHeard := '';
  Refuse := '';
  FDir := MakeTempDir('iecfile');
  Received := TStringList.Create;
end;

procedure TTestIecFile.TearDown;
begin
  if MChn <> nil then Dispose(MChn, Done);
  if SChn <> nil then Dispose(SChn, Done);
  Finalize(F);
  Finalize(C);
  Received.Free;
  RemoveTempDir(FDir);
end;

procedure TTestIecFile.PutFile(const Name: string; const Content: AnsiString);
begin
  WriteFileText(FDir + '/' + Name, Content);
end;

procedure TTestIecFile.OpenPair(K: tPair);
var
  Err: string;
  E: ShortString;
  Port: Word;
begin
  if K = pPty then
  begin
    Addr := 1;
    MChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DRV=PTY BD=115200', Err);
    AssertNotNull(Err, MChn);
    SChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=' + PtyLastSlave +
      ' BD=115200', Err);
  end
  else
  begin
    Addr := 0;
    SChn := OpenListening('IEC104', 'NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0', Port);
    MChn := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port) + ' RECON=200', Err);
  end;
  AssertNotNull(Err, SChn);
  AssertNotNull(Err, MChn);
  AssertEquals('slave', res_Ok, IecSlaveInit(S, SChn, IecDefaultParams, 1, E));
  S.OnAsdu := @OnSlaveAsdu;
  S.Data := Self;
  IecFileServerInit(F, IecDefaultParams, 1);
  F.Dir := FDir;
  F.SectionSize := 1000;
  F.OnReceived := @OnReceived;
  F.Data := Self;
  IecSlaveServeFiles(S, @F);
  AssertEquals('master', res_Ok, IecMasterInit(M, MChn, IecDefaultParams));
  if K = pPty then
  begin
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
    M.CycleMs := 10;
  end;
  M.CommandMs := 3000;
  M.Idle := @IdleSlave;
  M.IdleData := Self;
  IecFileClientInit(C, M);
  C.TimeoutMs := 3000;
  C.SectionSize := 700;
  { the hostile line's hook in front of the client's (OnSlaveAsdu: the
    slave's side) }
  OrigFile := M.OnFileAsdu;
  M.OnFileAsdu := @OnMasterFile;
  M.FileData := Self;
end;

{- ------------------------------------------------------------ codec }

procedure TTestIecFile.TestCodecOctets;
var
  O: tIecFileObj;
  Objs: array[0..1] of tIecFileObj;
  B: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  E: ShortString;
  H: tIecAsdu;
  P: tIecParams;
begin
  P := IecDefaultParams;     { COT 2 octets, CA 2, IOA 3 }
  { select file: TI 122 = 7A, VSQ 01, COT 13 = 0D, OA 00, CA 01 00,
    IOA 30000 = 30 75 00, NOF 1 = 01 00, NOS 00, SCQ 1 }
  FillChar(O, SizeOf(O), 0);
  O.Ioa := 30000;
  O.Nof := Nof_Transparent;
  O.Q := Scq_SelectFile;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_SC_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('7A 01 0D 00 01 00 30 75 00 01 00 00 01', Hex(B, Len));
  { file ready: TI 120 = 78, NOF 01 00, LOF 800 = 20 03 00, FRQ 00 }
  O.Q := 0;
  O.Lof := 800;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_FR_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('78 01 0D 00 01 00 30 75 00 01 00 20 03 00 00', Hex(B, Len));
  { section ready: TI 121 = 79, NOF, NOS 01, LOF 400 = 90 01 00, SRQ 00 }
  O.Nos := 1;
  O.Lof := 400;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_SR_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('79 01 0D 00 01 00 30 75 00 01 00 01 90 01 00 00', Hex(B, Len));
  { segment: TI 125 = 7D, NOF, NOS 01, LOS 03, the octets 00 01 02 }
  O.SegLen := 3;
  O.Seg[0] := 0; O.Seg[1] := 1; O.Seg[2] := 2;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_SG_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('7D 01 0D 00 01 00 30 75 00 01 00 01 03 00 01 02', Hex(B, Len));
  AssertEquals(res_Ok, IecFileDecode(P, B, Len, 0, H, O, E));
  AssertEquals(3, O.SegLen);
  AssertEquals(2, O.Seg[2]);
  { last segment: TI 123 = 7B, NOF, NOS 01, LSQ 3, CHS B8 }
  O.Q := Lsq_Section;
  O.Chs := $B8;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_LS_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('7B 01 0D 00 01 00 30 75 00 01 00 01 03 B8', Hex(B, Len));
  { negative section ack: TI 124 = 7C, NOS 01, AFQ 4 + cause 2 << 4 = 24 }
  O.Q := Afq_SectionBad or (Fe_Checksum shl 4);
  AssertEquals(E, res_Ok, IecFileEncode(P, F_AF_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals('7C 01 0D 00 01 00 30 75 00 01 00 01 24', Hex(B, Len));
  { a directory of two entries (SQ = 0), COT 5: TI 126 = 7E, VSQ 02;
    entry: IOA, NOF, LOF 800, SOF 00, CP56Time2a of 2026-12-04 23:30:00.000
    Friday: ms 00 00, minute 30 = 1E, hour 23 = 17, day 4 + weekday 5 << 5
    = A4, month 0C, year 26 = 1A; the second: IOA 30001, LOF 1 = 01 00 00,
    SOF 20 (LFD: last file), the same time }
  FillChar(Objs, SizeOf(Objs), 0);
  Objs[0].Ioa := 30000;
  Objs[0].Nof := 1;
  Objs[0].Lof := 800;
  Objs[0].Time.Minute := 30;
  Objs[0].Time.Hour := 23;
  Objs[0].Time.Day := 4;
  Objs[0].Time.DayOfWeek := 5;
  Objs[0].Time.Month := 12;
  Objs[0].Time.Year := 26;
  Objs[1] := Objs[0];
  Objs[1].Ioa := 30001;
  Objs[1].Lof := 1;
  Objs[1].Q := Sof_LastFile;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_DR_TA_1, Cot_Request, False, 1, Objs, 2, B, Len, E));
  AssertEquals('7E 02 05 00 01 00 30 75 00 01 00 20 03 00 00 00 00 1E 17 A4 0C 1A ' +
    '31 75 00 01 00 01 00 00 20 00 00 1E 17 A4 0C 1A', Hex(B, Len));
  AssertEquals(res_Ok, IecFileDecode(P, B, Len, 1, H, O, E));
  AssertEquals(30001, O.Ioa);
  AssertEquals(Sof_LastFile, O.Q);
  AssertEquals(12, O.Time.Month);
  { the same directory as a sequence (SQ = 1): the second entry's IOA is
    the first's + 1 }
  B[1] := $82;
  Move(B[25], B[22], 13);
  AssertEquals(E, res_Ok, IecFileDecode(P, B, 35, 1, H, O, E));
  AssertEquals(30001, O.Ioa);
  AssertEquals(1, O.Lof);
  { query log (127 = 7F): NOF, start and stop CP56Time2a }
  FillChar(O, SizeOf(O), 0);
  O.Ioa := 5;
  O.Nof := Nof_Disturbance;
  O.Time := Objs[0].Time;
  O.Stop := Objs[0].Time;
  O.Stop.Hour := 0;
  AssertEquals(E, res_Ok, IecFileEncode(P, F_SC_NB_1, Cot_Request, False, 1, [O], 1, B, Len, E));
  AssertEquals('7F 01 05 00 01 00 05 00 00 02 00 00 00 1E 17 A4 0C 1A 00 00 1E 00 A4 0C 1A', Hex(B, Len));
  AssertEquals(res_Ok, IecFileDecode(P, B, Len, 0, H, O, E));
  AssertEquals(0, O.Stop.Hour);
  AssertEquals(23, O.Time.Hour);
end;

procedure TTestIecFile.TestCodecRefusals;
var
  O: tIecFileObj;
  B: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  E: ShortString;
  H: tIecAsdu;
  P: tIecParams;
  Seg: array[0..2] of Byte = ($7D, $01, $0D);
begin
  P := IecDefaultParams;
  FillChar(O, SizeOf(O), 0);
  AssertEquals(res_AsduType, IecFileEncode(P, 45, Cot_File, False, 1, [O], 1, B, Len, E));
  O.Lof := $1000000;
  AssertEquals(res_AsduValue, IecFileEncode(P, F_FR_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertTrue(E, Pos('16777215', E) > 0);
  O.Lof := 0;
  O.SegLen := 240;           { 6 + 3 + 4 + 240 = 253 octets: fits IecMaxAsdu }
  AssertEquals(E, res_Ok, IecFileEncode(P, F_SG_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  O.SegLen := 241;
  AssertEquals(res_AsduLength, IecFileEncode(P, F_SG_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  { a segment whose LOS says more than is there }
  O.SegLen := 3;
  AssertEquals(res_Ok, IecFileEncode(P, F_SG_NA_1, Cot_File, False, 1, [O], 1, B, Len, E));
  AssertEquals(res_AsduLength, IecFileDecode(P, B, Len - 1, 0, H, O, E));
  AssertTrue(E, Pos('F_SG_NA_1', E) > 0);
  AssertEquals(res_AsduShort, IecFileDecode(P, Seg, 3, 0, H, O, E));
  { two objects of a type that has one }
  B[1] := 2;
  AssertEquals(res_AsduCount, IecFileDecode(P, B, Len, 0, H, O, E));
  AssertEquals(236, IecFileMaxSegment(P, 249));
  AssertEquals(234, IecFileMaxSegment(P, 247));
end;

procedure TTestIecFile.TestChecksum;
var
  Txt: AnsiString;
begin
  { CHS: arithmetic sum modulo 256. lib60870's section 1 (i mod 256, i <
    400): 0 + .. + 255 = 32640, 0 + .. + 143 = 10296, 42936 mod 256 = 184
    = B8; section 2 ((i + 1) mod 256): 32640 + (1 + .. + 144 = 10440) =
    43080, mod 256 = 72 = 48; the file: B8 + 48 = 100 -> 00. Our 600
    octets (7 i + 3): 7 * 179700 + 1800 = 1259700, mod 256 = 180 = B4. }
  Txt := Lib60870File;
  AssertEquals($B8, IecFileChecksum(0, PByteArray(@Txt[1])^[0..399], 400));
  AssertEquals($48, IecFileChecksum(0, PByteArray(@Txt[401])^[0..399], 400));
  AssertEquals($00, IecFileChecksum(0, PByteArray(@Txt[1])^[0..799], 800));
  { a running sum: the file's from section 1's }
  AssertEquals($00, IecFileChecksum($B8, PByteArray(@Txt[401])^[0..399], 400));
  Txt := PutContent;
  AssertEquals($B4, IecFileChecksum(0, PByteArray(@Txt[1])^[0..599], 600));
end;

{- ------------------------------------------------------------ captures }

function TTestIecFile.CaptureAsdus(const Name: string; Is104: Boolean; out Tx: TBoolArray): TByteArrays;
var
  A: TApdus104;
  Fr: TCapFrames;
  I, N: Integer;
  B: TBytes;
begin
  Result := nil;
  Tx := nil;
  if Is104 then
  begin
    A := Cap104Load('tests/data/' + Name);
    for I := 0 to High(A) do
      if (A[I].Apci.Format = af104I) and (Length(A[I].Bytes) > 6) and IecIsFileType(A[I].Bytes[6]) then
      begin
        N := Length(Result);
        SetLength(Result, N + 1);
        SetLength(Tx, N + 1);
        Result[N] := Copy(A[I].Bytes, 6, MaxInt);
        Tx[N] := A[I].Tx;
      end;
  end
  else
  begin
    Fr := CapLoad('tests/data/' + Name);
    for I := 0 to High(Fr) do
    begin
      B := Fr[I].Data;
      if (Fr[I].Kind = tpLongM) and (Length(B) > 6) and IecIsFileType(B[0]) then
      begin
        N := Length(Result);
        SetLength(Result, N + 1);
        SetLength(Tx, N + 1);
        Result[N] := B;
        Tx[N] := Fr[I].Tx;
      end;
    end;
  end;
end;

{ The file transfer ASDUs of a capture of examples/iec101master against
  lib60870's file server (get IOA 30000, then put IOA 30001; how it was
  made: tests/data/README). Worked out by hand: our select, call file,
  call section (7A .. 00 01 / 00 02 / 01 06), its file ready (LOF 800 = 20
  03 00), section ready (NOS 1 and 2, LOF 400 = 90 01 00), last segments
  with CHS B8 and 48, its last section (LSQ 1, CHS 00; lib60870 names it
  NOS 3, one past the last), our acks (7C ... 03 and ... 01); our offer
  (78 ... 31 75 00 01 00 58 02 00 00: LOF 600), its call file and call
  section, our last segment and last section with CHS B4, its acks. The
  segments put together are the files (computed, not captured). Then our
  server, set up as lib60870's example (the file, 400-octet sections, ASDUs
  of 249), fed our requests, answers each as lib60870 did, octet for octet
  (but for that NOS). }
procedure TTestIecFile.CheckCapture(const Name: string; Is104: Boolean);
const
  Want: array[0..15] of string = (
    'tx 7A 01 0D 00 01 00 30 75 00 01 00 00 01',
    'rx 78 01 0D 00 01 00 30 75 00 01 00 20 03 00 00',
    'tx 7A 01 0D 00 01 00 30 75 00 01 00 00 02',
    'rx 79 01 0D 00 01 00 30 75 00 01 00 01 90 01 00 00',
    'tx 7A 01 0D 00 01 00 30 75 00 01 00 01 06',
    'rx 7B 01 0D 00 01 00 30 75 00 01 00 01 03 B8',
    'tx 7C 01 0D 00 01 00 30 75 00 01 00 01 03',
    'rx 79 01 0D 00 01 00 30 75 00 01 00 02 90 01 00 00',
    'tx 7A 01 0D 00 01 00 30 75 00 01 00 02 06',
    'rx 7B 01 0D 00 01 00 30 75 00 01 00 02 03 48',
    'tx 7C 01 0D 00 01 00 30 75 00 01 00 02 03',
    'rx 7B 01 0D 00 01 00 30 75 00 01 00 03 01 00',
    'tx 7C 01 0D 00 01 00 30 75 00 01 00 03 01',
    'tx 78 01 0D 00 01 00 31 75 00 01 00 58 02 00 00',
    'rx 7A 01 0D 00 01 00 31 75 00 01 00 00 02',
    'tx 79 01 0D 00 01 00 31 75 00 01 00 01 58 02 00 00');
  WantPut: array[0..4] of string = (
    'rx 7A 01 0D 00 01 00 31 75 00 01 00 01 06',
    'tx 7B 01 0D 00 01 00 31 75 00 01 00 01 03 B4',
    'rx 7C 01 0D 00 01 00 31 75 00 01 00 01 03',
    'tx 7B 01 0D 00 01 00 31 75 00 01 00 01 01 B4',
    'rx 7C 01 0D 00 01 00 31 75 00 01 00 01 01');
var
  A: TByteArrays;
  Tx: TBoolArray;
  Lines: TStringList;
  I, J: Integer;
  H: tIecAsdu;
  O: tIecFileObj;
  E: ShortString;
  Got, Put: AnsiString;
  Srv: tIecFileServer;
  Out: array[0..IecMaxAsdu - 1] of Byte;
  OutLen: Word;
  Answers: TStringList;
  Dir: string;
begin
  A := CaptureAsdus(Name, Is104, Tx);
  Lines := TStringList.Create;
  Answers := TStringList.Create;
  try
    Got := '';
    Put := '';
    for I := 0 to High(A) do
    begin
      AssertEquals('ASDU ' + IntToStr(I) + ' decodes', res_Ok,
        IecFileDecode(IecDefaultParams, A[I], Length(A[I]), 0, H, O, E));
      if H.Ti = F_SG_NA_1 then
      begin
        SetLength(Got, Length(Got) + Ord(O.Ioa = 30000) * O.SegLen);
        SetLength(Put, Length(Put) + Ord(O.Ioa = 30001) * O.SegLen);
        if O.Ioa = 30000 then
          Move(O.Seg[0], Got[Length(Got) - O.SegLen + 1], O.SegLen)
        else
          Move(O.Seg[0], Put[Length(Put) - O.SegLen + 1], O.SegLen);
        Continue;                          { the segments: put together below }
      end;
      Lines.Add(BoolToStr(Tx[I], 'tx ', 'rx ') + Hex(A[I], Length(A[I])));
    end;
    for I := 0 to High(Want) do
      AssertEquals(Name + ' ASDU ' + IntToStr(I), Want[I], Lines[I]);
    for I := 0 to High(WantPut) do
      AssertEquals(Name + ' ASDU ' + IntToStr(I + 16), WantPut[I], Lines[16 + I]);
    AssertEquals(21, Lines.Count);
    AssertTrue('the file got is lib60870''s', Got = Lib60870File);
    AssertTrue('the file put is ours', Put = PutContent);
    { our server, fed our requests, answers as lib60870 }
    Dir := FDir;
    IecFileServerInit(Srv, IecDefaultParams, 1);
    try
      Srv.SectionSize := 400;
      Srv.MaxAsdu := 249;
      Srv.Dir := Dir;                      { the file put lands here }
      AssertEquals(res_Ok, IecFileServerAdd(Srv, 30000, Nof_Transparent, Lib60870File, IecTimeFromDateTime(Now)));
      for I := 0 to High(A) do
        if Tx[I] then
        begin
          IecFileServerTake(Srv, A[I], Length(A[I]));
          while IecFileServerNext(Srv, Out, OutLen) do
            Answers.Add(Hex(Out, OutLen));
        end;
      J := 0;
      for I := 0 to High(A) do
        if not Tx[I] then
        begin
          if (A[I][0] = F_LS_NA_1) and (A[I][12] = Lsq_File) then
            A[I][11] := 2;                 { lib60870: NOS 3, one past the last section; ours: 2 }
          AssertTrue(Name + ': our server answered ' + IntToStr(Answers.Count) + ' times', J < Answers.Count);
          AssertEquals(Name + ' answer ' + IntToStr(J), Hex(A[I], Length(A[I])), Answers[J]);
          Inc(J);
        end;
      AssertEquals('as many answers', J, Answers.Count);
      AssertEquals('file sent', 1, Srv.Sent);
      AssertEquals('file received', 1, Srv.Received);
      AssertTrue('and kept as ' + Dir + '/30001', ReadFileText(Dir + '/30001') = PutContent);
    finally
      Finalize(Srv);
    end;
  finally
    Lines.Free;
    Answers.Free;
  end;
end;

procedure TTestIecFile.TestLib60870CaptureFt12;
begin
  CheckCapture('iec101-lib60870-files.trc', False);
end;

procedure TTestIecFile.TestLib60870Capture104;
begin
  CheckCapture('iec104-lib60870-files.trc', True);
end;

{- ------------------------------------------------------------ on the wire }

procedure TTestIecFile.DirGetPut(K: tPair);
var
  Got: AnsiString;
  T: tIecTime;
  T0: QWord;
begin
  PutFile('30000', Pattern(800));
  PutFile('30001.dat', Pattern(3000));    { three sections of 1000, 5 segments each }
  PutFile('notes.txt', 'not a file of an IOA');
  OpenPair(K);
  T := IecTimeFromDateTime(EncodeDate(2026, 12, 4));
  { a disturbance record the program keeps in memory }
  AssertEquals(res_Ok, IecFileServerAdd(F, 40000, Nof_Disturbance, Pattern(10), T));
  AssertEquals(C.Err, res_Ok, IecFileDir(C, Addr, 1));
  AssertEquals('entries', 3, C.DirCount);
  AssertEquals(40000, C.Dir[0].Ioa);
  AssertEquals(Nof_Disturbance, C.Dir[0].Nof);
  AssertEquals(10, C.Dir[0].Lof);
  AssertEquals(4, C.Dir[0].Time.Day);
  AssertEquals(30000, C.Dir[1].Ioa);
  AssertEquals(800, C.Dir[1].Lof);
  AssertEquals(30001, C.Dir[2].Ioa);
  AssertEquals(3000, C.Dir[2].Lof);
  AssertEquals('only the last has LFD', Sof_LastFile, C.Dir[2].Sof and Sof_LastFile);
  AssertEquals(0, C.Dir[1].Sof and Sof_LastFile);
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertEquals(3000, Length(Got));
  AssertTrue('the file as it is', Got = Pattern(3000));
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 40000, Nof_Disturbance, Got));
  AssertTrue('the record as it is', Got = Pattern(10));
  { the slave counts a file sent at the master's last acknowledgement,
    which the master's call does not wait for }
  T0 := ChMsTick;
  while (F.Sent < 2) and (ChMsTick - T0 < 3000) do
    IecPollFor(M, 20);
  AssertEquals(2, F.Sent);
  { put: 2500 octets in sections of 700 (4 sections) }
  AssertEquals(C.Err, res_Ok, IecFilePut(C, Addr, 1, 30002, Nof_Transparent, Pattern(2500)));
  AssertEquals('told the program', '30002 1 2500', Received.Text.Trim);
  AssertTrue('kept in the directory', ReadFileText(FDir + '/30002') = Pattern(2500));
  AssertEquals(0, C.BadChecksums);
  AssertEquals(0, F.BadChecksums);
  AssertEquals('no ASDU was bad', 0, M.BadAsdus);
end;

procedure TTestIecFile.TestDirGetPutPty;
begin
  DirGetPut(pPty);
end;

procedure TTestIecFile.TestDirGetPut104;
begin
  DirGetPut(p104);
end;

procedure TTestIecFile.TestUnknownFileAndEmptyDirectory;
var
  Got: AnsiString;
begin
  OpenPair(p104);
  AssertEquals(C.Err, res_Ok, IecFileDir(C, Addr, 1));
  AssertEquals('an empty directory', 0, C.DirCount);
  AssertEquals(res_IecFileRefused, IecFileGet(C, Addr, 1, 12345, Nof_Transparent, Got));
  AssertEquals('file IOA 12345 from slave 0: the slave has no such file (F_FR_NA_1 negative)', C.Err);
  AssertEquals('', Got);
  { another common address: mirrored with COT 46, negative }
  AssertEquals(res_IecFileRefused, IecFileGet(C, Addr, 7, 12345, Nof_Transparent, Got));
  AssertTrue(C.Err, Pos('COT 46 UNKNOWN_COMMON_ADDRESS, negative', C.Err) > 0);
  { a slave without a file server: COT 44 }
  IecSlaveServeFiles(S, nil);
  AssertEquals(res_IecFileRefused, IecFileGet(C, Addr, 1, 1, Nof_Transparent, Got));
  AssertTrue(C.Err, Pos('COT 44', C.Err) > 0);
end;

procedure TTestIecFile.TestFlippedOctetSectionAskedAgain;
var
  Got: AnsiString;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(pPty);
  FlipSegments := 1;
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue('the file as it is', Got = Pattern(3000));
  AssertEquals('one section failed its checksum', 1, C.BadChecksums);
  AssertEquals('sent once more', 1, F.Sent);
end;

procedure TTestIecFile.TestFlippedOctetEveryTimeFails;
var
  Got: AnsiString;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(p104);
  FlipSegments := 1000;
  AssertEquals(res_IecFileChecksum, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue(C.Err, Pos('file IOA 30001 from slave 0: section 1: checksum ', C.Err) = 1);
  AssertTrue(C.Err, Pos('(asked 2 times)', C.Err) > 0);
  AssertEquals('', Got);
  AssertEquals(2, C.BadChecksums);
  { the slave was told (AFQ 2, checksum): it counts the file failed }
  IecPollFor(M, 200);
  AssertEquals(1, F.Failed);
  AssertEquals(0, F.Sent);
  AssertTrue('free at once', F.State = fsIdle);
  FlipSegments := 0;
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
end;

procedure TTestIecFile.TestFlippedOctetOnPutFails;
begin
  OpenPair(p104);
  FlipPutSegments := 1000;
  AssertEquals(res_IecFileChecksum, IecFilePut(C, Addr, 1, 30002, Nof_Transparent, Pattern(2500)));
  AssertEquals('file IOA 30002 to slave 0: section 1 refused by the slave (checksum failed)', C.Err);
  AssertEquals('the slave saw it twice', 2, F.BadChecksums);
  AssertEquals('nothing kept', 0, Received.Count);
  AssertFalse(FileExists(FDir + '/30002'));
  { once: the section again, then the file }
  FlipPutSegments := 1;
  AssertEquals(C.Err, res_Ok, IecFilePut(C, Addr, 1, 30002, Nof_Transparent, Pattern(2500)));
  AssertTrue(ReadFileText(FDir + '/30002') = Pattern(2500));
end;

{ Every section right, the file's checksum not: refused both ways. }
procedure TTestIecFile.TestWrongFileChecksum;
var
  Got: AnsiString;
  T0: QWord;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(p104);
  FlipFileChs := True;
  AssertEquals(res_IecFileChecksum, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue(C.Err, Pos('file IOA 30001 from slave 0: file checksum ', C.Err) = 1);
  AssertTrue(C.Err, Pos('; 3000 octets of 3000 announced', C.Err) > 0);
  AssertEquals(1, C.BadChecksums);
  T0 := ChMsTick;
  while (F.Failed = 0) and (ChMsTick - T0 < 3000) do
    IecPollFor(M, 20);
  AssertEquals('the slave heard AFQ 2', 1, F.Failed);
  FlipFileChs := False;
  FlipPutFileChs := True;
  AssertEquals(res_IecFileChecksum, IecFilePut(C, Addr, 1, 30002, Nof_Transparent, Pattern(1500)));
  AssertEquals('file IOA 30002 to slave 0: the slave refused the file: checksum failed', C.Err);
  AssertTrue(F.LastError, Pos('file IOA 30002: file checksum ', F.LastError) = 1);
  AssertFalse('not kept', FileExists(FDir + '/30002'));
  AssertEquals(0, Received.Count);
end;

{ The controlled station's sequence: what does not follow is refused
  (mirrored, P/N = 1) and changes nothing. }
procedure TTestIecFile.TestServerSequence;
var
  Srv: tIecFileServer;
  O: tIecFileObj;
  B, Out: array[0..IecMaxAsdu - 1] of Byte;
  Len, OutLen: Word;
  E: ShortString;

  function Ask(Ti, Q, Nos: Byte): string;
  begin
    O.Q := Q;
    O.Nos := Nos;
    AssertEquals(E, res_Ok, IecFileEncode(IecDefaultParams, Ti, Cot_File, False, 1, [O], 1, B, Len, E));
    IecFileServerTake(Srv, B, Len);
    Result := '';
    if IecFileServerNext(Srv, Out, OutLen) then
      if Out[0] = F_SG_NA_1 then
        Result := Hex(Out, 14)           { a segment: its head and first octet }
      else
        Result := Hex(Out, OutLen);
  end;

begin
  IecFileServerInit(Srv, IecDefaultParams, 1);
  try
    Srv.SectionSize := 100;
    AssertEquals(res_Ok, IecFileServerAdd(Srv, 7, Nof_Transparent, Pattern(250), IecTimeFromDateTime(Now)));
    FillChar(O, SizeOf(O), 0);
    O.Ioa := 7;
    O.Nof := Nof_Transparent;
    { call file when no file is selected (the selection deactivated):
      mirrored negative (COT 13 + P/N = 4D) }
    AssertEquals('78 01 0D 00 01 00 07 00 00 01 00 FA 00 00 00', Ask(F_SC_NA_1, Scq_SelectFile, 0));
    AssertEquals('', Ask(F_SC_NA_1, Scq_DeactFile, 0));
    AssertEquals('7A 01 4D 00 01 00 07 00 00 01 00 00 02', Ask(F_SC_NA_1, Scq_CallFile, 0));
    { select: file ready, 250 = FA 00 00 }
    AssertEquals('78 01 0D 00 01 00 07 00 00 01 00 FA 00 00 00', Ask(F_SC_NA_1, Scq_SelectFile, 0));
    { call section before the call file: refused }
    AssertEquals('7A 01 4D 00 01 00 07 00 00 01 00 01 06', Ask(F_SC_NA_1, Scq_CallSection, 1));
    { call file: section 1 of 100 = 64 00 00 ready }
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 01 64 00 00 00', Ask(F_SC_NA_1, Scq_CallFile, 0));
    { a call of section 2 when 1 is ready: refused, nothing sent }
    AssertEquals('7A 01 4D 00 01 00 07 00 00 01 00 02 06', Ask(F_SC_NA_1, Scq_CallSection, 2));
    AssertTrue(Srv.State = fsSectionReady);
    { an acknowledgement of a section not sent: nothing }
    AssertEquals('', Ask(F_AF_NA_1, Afq_SectionOk, 1));
    AssertTrue(Srv.State = fsSectionReady);
    { the right call: segments }
    AssertEquals('7D 01 0D 00 01 00 07 00 00 01 00 01 64 00', Ask(F_SC_NA_1, Scq_CallSection, 1));
    AssertTrue(Srv.State = fsSending);
    { deactivation: over }
    AssertEquals('', Ask(F_SC_NA_1, Scq_DeactFile, 0));
    AssertTrue(Srv.State = fsIdle);
    AssertEquals(2, Srv.Aborted);
    AssertEquals(3, Srv.Refused);
  finally
    Finalize(Srv);
  end;
end;

{ The controlling station's sequence, its answers fed one by one: each
  request worked out by hand; an answer out of turn ends the transfer. }
procedure TTestIecFile.TestClientSequence;
var
  O: tIecFileObj;
  B: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  E: ShortString;

  procedure Answer(Ti, Q, Nos: Byte; Lof: LongWord);
  begin
    O.Q := Q;
    O.Nos := Nos;
    O.Lof := Lof;
    AssertEquals(E, res_Ok, IecFileEncode(IecDefaultParams, Ti, Cot_File, False, 1, [O], 1, B, Len, E));
    M.OnFileAsdu(M.FileData, Addr, B, Len);
  end;

  function Pending: string;
  begin
    Result := Hex(C.Pend, C.PendLen);
    C.PendLen := 0;                      { as if sent }
  end;

begin
  OpenPair(p104);
  FillChar(O, SizeOf(O), 0);
  O.Ioa := 9;
  O.Nof := Nof_Transparent;
  AssertTrue(IecFileStartGet(C, Addr, 1, 9, Nof_Transparent));
  AssertEquals('select', '7A 01 0D 00 01 00 09 00 00 01 00 00 01', Pending);
  Answer(F_FR_NA_1, 0, 0, 5);
  AssertEquals('call file', '7A 01 0D 00 01 00 09 00 00 01 00 00 02', Pending);
  Answer(F_SR_NA_1, 0, 1, 5);
  AssertEquals('call section', '7A 01 0D 00 01 00 09 00 00 01 00 01 06', Pending);
  { the last segment before any segment: 0 of 5 octets, checksum 0 -
    not whole: asked again }
  Answer(F_LS_NA_1, Lsq_Section, 1, 0);
  AssertEquals('section refused (AFQ 4, cause 2)', '7C 01 0D 00 01 00 09 00 00 01 00 01 24', Pending);
  { a file ready now is out of turn }
  Answer(F_FR_NA_1, 0, 0, 5);
  AssertEquals(res_IecFileSequence, C.Result);
  AssertEquals('file IOA 9 from slave 0: F_FR_NA_1 (qualifier 0) while waiting for section ready (F_SR_NA_1)', C.Err);
  { given up: the slave told, deactivate file (SCQ 3) }
  AssertEquals('deactivate file', '7A 01 0D 00 01 00 09 00 00 01 00 00 03', Pending);
  { a segment while a file ready is awaited is no file ready }
  AssertTrue(IecFileStartGet(C, Addr, 1, 9, Nof_Transparent));
  Pending;
  O.SegLen := 1;
  Answer(F_SG_NA_1, 0, 1, 0);
  AssertEquals(res_IecFileSequence, C.Result);
  AssertEquals('deactivate file', '7A 01 0D 00 01 00 09 00 00 01 00 00 03', Pending);
  { a delete: select, then delete file (SCQ 4) once the file is ready;
    the slave's positive file acknowledgement ends it }
  AssertTrue(IecFileStartDelete(C, Addr, 1, 9, Nof_Transparent));
  AssertEquals('select', '7A 01 0D 00 01 00 09 00 00 01 00 00 01', Pending);
  Answer(F_FR_NA_1, 0, 0, 5);
  AssertEquals('delete file', '7A 01 0D 00 01 00 09 00 00 01 00 00 04', Pending);
  Answer(F_AF_NA_1, Afq_FileBad or (Fe_Unexpected shl 4), 0, 0);
  AssertEquals(res_IecFileRefused, C.Result);
  AssertEquals('delete of file IOA 9 on slave 0: the slave did not delete it (F_AF_NA_1 negative: ' +
    'unexpected communication service)', C.Err);
  { a query log: NOF 2, 2026-12-04 09:00 to 12:30 (CP56Time2a: ms 00 00,
    minute, hour, day 4 + Friday 5 << 5 = A4, month 0C, year 1A) }
  AssertTrue(IecFileStartQueryLog(C, Addr, 1, 0, Nof_Disturbance,
    IecTimeFromDateTime(EncodeDate(2026, 12, 4) + EncodeTime(9, 0, 0, 0)),
    IecTimeFromDateTime(EncodeDate(2026, 12, 4) + EncodeTime(12, 30, 0, 0))));
  AssertEquals('query log', '7F 01 05 00 01 00 00 00 00 02 00 00 00 00 09 A4 0C 1A 00 00 1E 0C A4 0C 1A', Pending);
end;

procedure TTestIecFile.TestInterruptedGet;
var
  Got: AnsiString;
  T0: QWord;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(pPty);
  C.TimeoutMs := 1000;
  MuteAfterSegment := True;
  T0 := ChMsTick;
  AssertEquals(res_Timeout, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  { one segment came: an F_SG_NA_1 of 249 octets (the server's longest;
    the FT 1.2 frame takes up to 253) less head 6, IOA 3, NOF 2, NOS 1,
    LOS 1 = 236 octets of file }
  AssertTrue(C.Err, Pos('file IOA 30001 from slave 1: interrupted: no segments (F_SG_NA_1) in 1000 ms (236 of 3000 octets received)', C.Err) = 1);
  AssertTrue('not before its timeout', ChMsTick - T0 >= 1000);
  AssertTrue('and not much after it', ChMsTick - T0 < 5000);
  AssertEquals('', Got);
end;

procedure TTestIecFile.TestServerAbandonsALeftTransfer;
var
  T0: QWord;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(p104);
  F.TimeoutMs := 300;
  { the master selects and calls the file, then goes away }
  AssertTrue(IecFileStartGet(C, Addr, 1, 30001, Nof_Transparent));
  T0 := ChMsTick;
  while (C.Wait <> fwSegments) and (ChMsTick - T0 < 3000) do
    if not IecFileStep(C) then
      IecMasterWait(M, ChMsTick + 10);
  AssertTrue('the section called', C.Wait = fwSegments);
  Dispose(MChn, Done);
  MChn := nil;
  T0 := ChMsTick;
  while (F.Aborted = 0) and (ChMsTick - T0 < 3000) do
    StepSlave;
  AssertEquals(1, F.Aborted);
  AssertTrue(F.LastError, Pos('file IOA 30001: abandoned, no message from the peer in 300 ms', F.LastError) = 1);
  AssertTrue(F.State = fsIdle);
end;

{- ------------------------------------------------------------ query log, delete, sections }

{ Each ASDU (hex, worked out by hand) to Srv; what it answers, ' | '
  between ASDUs, a segment as its head and first octet. }
function Feed(var Srv: tIecFileServer; const AsduHex: string): string;
var
  B: TBytes;
  Out: array[0..IecMaxAsdu - 1] of Byte;
  OutLen: Word;
begin
  B := HexToBytes(AsduHex);
  if Length(B) > 0 then
    IecFileServerTake(Srv, B, Length(B));
  Result := '';
  while IecFileServerNext(Srv, Out, OutLen) do
  begin
    if Result <> '' then
      Result := Result + ' | ';
    if Out[0] = F_SG_NA_1 then
    begin
      Result := Result + Hex(Out, 14);
      Exit;                              { one segment: the rest waits }
    end;
    Result := Result + Hex(Out, OutLen);
  end;
end;

function Dec4(H, Mi, S, Ms: Word): tIecTime;
begin
  Result := IecTimeFromDateTime(EncodeDate(2026, 12, 4) + EncodeTime(H, Mi, S, Ms));
end;

{ Three records: IOA 40001 NOF 2 of 10 octets made 2026-12-04 10:00:00
  (CP56Time2a 00 00 00 0A A4 0C 1A: ms, minute, hour, day 4 + Friday 5 <<
  5, month, year 26), 40002 NOF 2 of 20 at 12:30:00 (00 00 1E 0C A4 0C
  1A), 40003 NOF 1 of 30 on Saturday 5th at 08:00 (00 00 00 08 C5 0C 1A). }
procedure AddRecords(var Srv: tIecFileServer);
begin
  IecFileServerAdd(Srv, 40001, Nof_Disturbance, Pattern(10), Dec4(10, 0, 0, 0));
  IecFileServerAdd(Srv, 40002, Nof_Disturbance, Pattern(20), Dec4(12, 30, 0, 0));
  IecFileServerAdd(Srv, 40003, Nof_Transparent, Pattern(30),
    IecTimeFromDateTime(EncodeDate(2026, 12, 5) + EncodeTime(8, 0, 0, 0)));
end;

procedure TTestIecFile.TestServerQueryLogOctets;
var
  Srv: tIecFileServer;
begin
  IecFileServerInit(Srv, IecDefaultParams, 1);
  try
    AddRecords(Srv);
    { F_SC_NB_1 (7F) COT 5, IOA 0, NOF 2, 09:00:00.000 to 12:30:00.000 on
      the 4th: the two records of NOF 2, 12:30 itself included; F_DR_TA_1
      (7E) with two entries, COT 5: IOA 40001 = 41 9C 00, NOF 02 00, LOF 10
      = 0A 00 00, SOF 00, its time; 40002, LOF 14 00 00, SOF 20 (LFD) }
    AssertEquals('7E 02 05 00 01 00 41 9C 00 02 00 0A 00 00 00 00 00 00 0A A4 0C 1A ' +
      '42 9C 00 02 00 14 00 00 20 00 00 1E 0C A4 0C 1A',
      Feed(Srv, '7F 01 05 00 01 00 00 00 00 02 00 00 00 00 09 A4 0C 1A 00 00 1E 0C A4 0C 1A'));
    { NOF 0 (any), from 12:30:00.001 (ms 01 00) to Saturday 08:00: only 40003 }
    AssertEquals('7E 01 05 00 01 00 43 9C 00 01 00 1E 00 00 20 00 00 00 08 C5 0C 1A',
      Feed(Srv, '7F 01 05 00 01 00 00 00 00 00 00 01 00 1E 0C A4 0C 1A 00 00 00 08 C5 0C 1A'));
    { NOF 1 from the 4th 00:00 to the 5th 23:00 (17): 40003 alone, the
      two of NOF 2 in the range left out }
    AssertEquals('7E 01 05 00 01 00 43 9C 00 01 00 1E 00 00 20 00 00 00 08 C5 0C 1A',
      Feed(Srv, '7F 01 05 00 01 00 00 00 00 01 00 00 00 00 00 A4 0C 1A 00 00 00 17 C5 0C 1A'));
    { nothing on the 6th (Sunday 7 << 5 + 6 = E6): the query mirrored, P/N = 1 (45) }
    AssertEquals('7F 01 45 00 01 00 00 00 00 00 00 00 00 00 00 E6 0C 1A 00 00 00 17 E6 0C 1A',
      Feed(Srv, '7F 01 05 00 01 00 00 00 00 00 00 00 00 00 00 E6 0C 1A 00 00 00 17 E6 0C 1A'));
    { a range that is no date (month 13 = 0D): empty, mirrored }
    AssertEquals('7F 01 45 00 01 00 00 00 00 00 00 00 00 00 00 E6 0D 1A 00 00 00 17 E6 0C 1A',
      Feed(Srv, '7F 01 05 00 01 00 00 00 00 00 00 00 00 00 00 E6 0D 1A 00 00 00 17 E6 0C 1A'));
    AssertEquals('query log: the range is no date', Srv.LastError);
    { COT 13 is no cause of a query: COT 45 + P/N = 6D }
    AssertEquals('7F 01 6D 00 01 00 00 00 00 00 00 00 00 00 00 E6 0C 1A 00 00 00 17 E6 0C 1A',
      Feed(Srv, '7F 01 0D 00 01 00 00 00 00 00 00 00 00 00 00 E6 0C 1A 00 00 00 17 E6 0C 1A'));
    { the plain directory after a query: every file again }
    AssertTrue(Pos('7E 03 05 00', Feed(Srv, '7A 01 05 00 01 00 00 00 00 00 00 00 00')) = 1);
  finally
    Finalize(Srv);
  end;
end;

procedure TTestIecFile.TestServerDeleteOctets;
var
  Srv: tIecFileServer;
begin
  PutFile('30000', Pattern(5));
  PutFile('30001', Pattern(5));
  IecFileServerInit(Srv, IecDefaultParams, 1);
  try
    Srv.Dir := FDir;
    AddRecords(Srv);
    { select IOA 40001 NOF 2 (file ready, LOF 10), delete file (SCQ 4):
      F_AF_NA_1 (7C) AFQ 1, positive acknowledgement of the file }
    AssertEquals('78 01 0D 00 01 00 41 9C 00 02 00 0A 00 00 00',
      Feed(Srv, '7A 01 0D 00 01 00 41 9C 00 02 00 00 01'));
    AssertEquals('7C 01 0D 00 01 00 41 9C 00 02 00 00 01',
      Feed(Srv, '7A 01 0D 00 01 00 41 9C 00 02 00 00 04'));
    AssertTrue(Srv.State = fsIdle);
    { once more: AFQ 2 + cause 4 (unexpected name of file) << 4 = 42 }
    AssertEquals('7C 01 0D 00 01 00 41 9C 00 02 00 00 42',
      Feed(Srv, '7A 01 0D 00 01 00 41 9C 00 02 00 00 04'));
    AssertEquals('delete of file IOA 40001: no such file', Srv.LastError);
    { a file of the directory, without a select: gone from the disk }
    AssertEquals('7C 01 0D 00 01 00 30 75 00 01 00 00 01',
      Feed(Srv, '7A 01 0D 00 01 00 30 75 00 01 00 00 04'));
    AssertFalse(FileExists(FDir + '/30000'));
    { the program says no: AFQ 2 + cause 3 (unexpected communication
      service) = 32, its reason in LastError; the file stays }
    Srv.OnDelete := @OnDelete;
    Srv.Data := Self;
    Refuse := 'kept for the audit';
    AssertEquals('7C 01 0D 00 01 00 31 75 00 01 00 00 32',
      Feed(Srv, '7A 01 0D 00 01 00 31 75 00 01 00 00 04'));
    AssertEquals('delete of file IOA 30001: kept for the audit', Srv.LastError);
    AssertTrue(FileExists(FDir + '/30001'));
    { the file gone when the server deletes it: the OS's reason }
    Refuse := 'steal';
    PutFile('30002', Pattern(5));
    AssertEquals('7C 01 0D 00 01 00 32 75 00 01 00 00 32',
      Feed(Srv, '7A 01 0D 00 01 00 32 75 00 01 00 00 04'));
    AssertEquals('delete of file IOA 30002: ' + FDir + '30002: No such file or directory', Srv.LastError);
    Refuse := '';
    Srv.NoDelete := True;
    AssertEquals('7C 01 0D 00 01 00 31 75 00 01 00 00 32',
      Feed(Srv, '7A 01 0D 00 01 00 31 75 00 01 00 00 04'));
    AssertEquals('delete of file IOA 30001: this station deletes no file', Srv.LastError);
    Srv.NoDelete := False;
    { the OS says no (a directory it may not write; root may, whatever
      the mode: there only the rest is checked) }
    FpChmod(FDir, &555);
    try
      if FpGetEUid <> 0 then
      begin
        AssertEquals('7C 01 0D 00 01 00 31 75 00 01 00 00 32',
          Feed(Srv, '7A 01 0D 00 01 00 31 75 00 01 00 00 04'));
        AssertEquals('delete of file IOA 30001: ' + FDir + '30001: Permission denied', Srv.LastError);
        AssertTrue(FileExists(FDir + '/30001'));
      end;
    finally
      FpChmod(FDir, &755);
    end;
    AssertEquals('7C 01 0D 00 01 00 31 75 00 01 00 00 01',
      Feed(Srv, '7A 01 0D 00 01 00 31 75 00 01 00 00 04'));
    AssertEquals(3, Srv.Deleted);
    AssertEquals('the records left', 2, Srv.FileCount);
  finally
    Finalize(Srv);
  end;
end;

{ Select section (SCQ 5), deactivate section (SCQ 7) while sending; a
  section deactivated by the sender (LSQ 4) while receiving. }
procedure TTestIecFile.TestServerSectionsOctets;
var
  Srv: tIecFileServer;
begin
  IecFileServerInit(Srv, IecDefaultParams, 1);
  try
    Srv.SectionSize := 100;
    Srv.Dir := FDir;
    AssertEquals(res_Ok, IecFileServerAdd(Srv, 7, Nof_Transparent, Pattern(250), Dec4(0, 0, 0, 0)));
    { select (LOF 250 = FA 00 00), call file: section 1 of 100 = 64 00 00 }
    AssertEquals('78 01 0D 00 01 00 07 00 00 01 00 FA 00 00 00', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 00 01'));
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 01 64 00 00 00', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 00 02'));
    { select section 3: ready, its 50 octets (32 00 00); called: its
      segment, the first octet that of 200: 200 * 31 mod 256 = 38 }
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 03 32 00 00 00', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 03 05'));
    AssertEquals('7D 01 0D 00 01 00 07 00 00 01 00 03 32 38', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 03 06'));
    { deactivate section: the rest of it (its last segment) does not go }
    AssertEquals('', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 03 07'));
    AssertTrue(Srv.State = fsFileCalled);
    AssertFalse(IecFileServerBusy(Srv));
    { a section the file has not: section ready with SRQ bit 7 (80) }
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 09 00 00 00 80', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 09 05'));
    { section 2: its segment (100 * 31 mod 256 = 1C first), its last
      segment with CHS = 31 (100 + .. + 199) = 463450 mod 256 = 5A }
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 02 64 00 00 00', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 02 05'));
    AssertEquals('7D 01 0D 00 01 00 07 00 00 01 00 02 64 1C', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 02 06'));
    AssertEquals('7B 01 0D 00 01 00 07 00 00 01 00 02 03 5A', Feed(Srv, ''));
    { acknowledged: section 3 is next; deactivate file: over }
    AssertEquals('79 01 0D 00 01 00 07 00 00 01 00 03 32 00 00 00', Feed(Srv, '7C 01 0D 00 01 00 07 00 00 01 00 02 03'));
    AssertEquals('', Feed(Srv, '7A 01 0D 00 01 00 07 00 00 01 00 00 03'));
    AssertTrue(Srv.State = fsIdle);
    AssertEquals(1, Srv.Aborted);
    { receiving IOA 8 (3 octets): file ready -> call file; section ready ->
      call section; two octets, then the sender's LSQ 4 (section with
      deactivation): dropped, the section offered again and sent whole:
      AA + BB + CC = 561 mod 256 = 31 }
    AssertEquals('7A 01 0D 00 01 00 08 00 00 01 00 00 02', Feed(Srv, '78 01 0D 00 01 00 08 00 00 01 00 03 00 00 00'));
    AssertEquals('7A 01 0D 00 01 00 08 00 00 01 00 01 06', Feed(Srv, '79 01 0D 00 01 00 08 00 00 01 00 01 03 00 00 00'));
    AssertEquals('', Feed(Srv, '7D 01 0D 00 01 00 08 00 00 01 00 01 02 AA BB'));
    AssertEquals('', Feed(Srv, '7B 01 0D 00 01 00 08 00 00 01 00 01 04 00'));
    AssertTrue(Srv.State = fsReceiveReady);
    AssertEquals('7A 01 0D 00 01 00 08 00 00 01 00 01 06', Feed(Srv, '79 01 0D 00 01 00 08 00 00 01 00 01 03 00 00 00'));
    AssertEquals('', Feed(Srv, '7D 01 0D 00 01 00 08 00 00 01 00 01 03 AA BB CC'));
    AssertEquals('7C 01 0D 00 01 00 08 00 00 01 00 01 03', Feed(Srv, '7B 01 0D 00 01 00 08 00 00 01 00 01 03 31'));
    AssertEquals('7C 01 0D 00 01 00 08 00 00 01 00 01 01', Feed(Srv, '7B 01 0D 00 01 00 08 00 00 01 00 01 01 31'));
    AssertTrue(ReadFileText(FDir + '/8') = #$AA#$BB#$CC);
    AssertEquals(1, Srv.Aborted);
  finally
    Finalize(Srv);
  end;
end;

{ Master and slave on a pty: a query log, a delete, the directory after. }
procedure TTestIecFile.TestDeleteAndQueryLogPty;
var
  Got: AnsiString;
begin
  PutFile('30000', Pattern(800));
  OpenPair(pPty);
  AddRecords(F);
  AssertEquals(C.Err, res_Ok, IecFileQueryLog(C, Addr, 1, 0, Nof_Disturbance, Dec4(9, 0, 0, 0), Dec4(12, 30, 0, 0)));
  AssertEquals('two records then', 2, C.DirCount);
  AssertEquals(40001, C.Dir[0].Ioa);
  AssertEquals(10, C.Dir[0].Lof);
  AssertEquals(10, C.Dir[0].Time.Hour);
  AssertEquals(40002, C.Dir[1].Ioa);
  AssertEquals(Sof_LastFile, C.Dir[1].Sof);
  AssertEquals(C.Err, res_Ok, IecFileQueryLog(C, Addr, 1, 0, 0, Dec4(13, 0, 0, 0), Dec4(13, 1, 0, 0)));
  AssertEquals('none then', 0, C.DirCount);
  { delete a record and a file of the directory }
  AssertEquals(C.Err, res_Ok, IecFileDelete(C, Addr, 1, 40002, Nof_Disturbance));
  AssertEquals(C.Err, res_Ok, IecFileDelete(C, Addr, 1, 30000, Nof_Transparent));
  AssertFalse(FileExists(FDir + '/30000'));
  AssertEquals(2, F.Deleted);
  AssertEquals(res_IecFileRefused, IecFileDelete(C, Addr, 1, 30000, Nof_Transparent));
  AssertEquals('delete of file IOA 30000 on slave 1: the slave has no such file (F_FR_NA_1 negative)', C.Err);
  F.OnDelete := @OnDelete;
  F.Data := Self;
  Refuse := 'kept for the audit';
  AssertEquals(res_IecFileRefused, IecFileDelete(C, Addr, 1, 40001, Nof_Disturbance));
  AssertEquals('delete of file IOA 40001 on slave 1: the slave did not delete it (F_AF_NA_1 negative: ' +
    'unexpected communication service)', C.Err);
  AssertEquals('delete of file IOA 40001: kept for the audit', F.LastError);
  AssertEquals(C.Err, res_Ok, IecFileDir(C, Addr, 1));
  AssertEquals('40001 and 40003 left', 2, C.DirCount);
  AssertEquals(40001, C.Dir[0].Ioa);
  AssertEquals(40003, C.Dir[1].Ioa);
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 40001, Nof_Disturbance, Got));
  AssertTrue(Got = Pattern(10));
end;

{ Poll until the slave's file server is idle (3 s at most). }
procedure TTestIecFile.WaitSlaveIdle;
var
  T0: QWord;
begin
  T0 := ChMsTick;
  while (F.State <> fsIdle) and (ChMsTick - T0 < 3000) do
    IecPollFor(M, 20);
end;

{ A master that gives up tells the slave: the slave is free for the next
  transfer at once, not after its own timeout (30 s here). }
procedure TTestIecFile.TestGiveUpFreesTheSlave;
var
  Got: AnsiString;
  T0: QWord;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(p104);
  AssertEquals(30000, F.TimeoutMs);
  { fetching: the master hears nothing after the first segment, gives up
    after its 1 s and deactivates the file (F_SC_NA_1 SCQ 3) }
  C.TimeoutMs := 1000;
  DropAfterSegment := True;
  AssertEquals(res_Timeout, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue(C.Err, Pos('file IOA 30001 from slave 0: interrupted: no ', C.Err) = 1);
  WaitSlaveIdle;
  AssertTrue('the slave is free at once: ' + IecFileServerStateName(F.State), F.State = fsIdle);
  AssertEquals('deactivate file', '7A 01 0D 00 01 00 31 75 00 01 00 00 03', SlaveHeard);
  AssertEquals(1, F.Aborted);
  AssertEquals('file IOA 30001: transfer deactivated by the peer', F.LastError);
  DropAfterSegment := False;
  Dropping := False;
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue(Got = Pattern(3000));
  { sending: the program aborts after the first segment; the last section
    with deactivation (F_LS_NA_1 LSQ 2, NOS 1, CHS 0) ends it }
  AssertTrue(IecFileStartPut(C, Addr, 1, 30002, Nof_Transparent, Pattern(2500)));
  T0 := ChMsTick;
  while (C.X.SecDone = 0) and (ChMsTick - T0 < 5000) do
    if not IecFileStep(C) then
      IecMasterWait(M, ChMsTick + 10);
  IecFileAbort(C);
  AssertEquals(res_IecFileAborted, IecFileFinish(C));
  AssertTrue(C.Err, Pos('file IOA 30002 to slave 0: aborted by the program (', C.Err) = 1);
  WaitSlaveIdle;
  AssertTrue(F.State = fsIdle);
  AssertEquals('7B 01 0D 00 01 00 32 75 00 01 00 01 02 00', SlaveHeard);
  AssertEquals(2, F.Aborted);
  AssertFalse('nothing kept', FileExists(FDir + '/30002'));
  AssertEquals(C.Err, res_Ok, IecFilePut(C, Addr, 1, 30002, Nof_Transparent, Pattern(2500)));
  AssertTrue(ReadFileText(FDir + '/30002') = Pattern(2500));
  { nothing under way: an abort changes nothing }
  IecFileAbort(C);
  AssertEquals(res_Ok, C.Result);
end;

{ One section of a file of three (1000 octets each): select, call file,
  section 1 ready, select section 2 (SCQ 5), its section ready, call
  section 2, the segments and the section's acknowledgement, then the
  slave's section 3 ready answered by deactivate file. A section the file
  has not: the slave's SRQ bit 7, the transfer deactivated. }
procedure TTestIecFile.TestGetOneSection;
var
  Got: AnsiString;
  T0: QWord;
begin
  PutFile('30001', Pattern(3000));
  OpenPair(pPty);
  AssertEquals(C.Err, res_Ok, IecFileGetSection(C, Addr, 1, 30001, Nof_Transparent, 2, Got));
  AssertTrue('section 2 as it is', Got = Copy(Pattern(3000), 1001, 1000));
  WaitSlaveIdle;
  AssertEquals('7A 01 0D 00 01 00 31 75 00 01 00 00 01 | 7A 01 0D 00 01 00 31 75 00 01 00 00 02 | ' +
    '7A 01 0D 00 01 00 31 75 00 01 00 02 05 | 7A 01 0D 00 01 00 31 75 00 01 00 02 06 | ' +
    '7C 01 0D 00 01 00 31 75 00 01 00 02 03 | 7A 01 0D 00 01 00 31 75 00 01 00 00 03', SlaveLog);
  AssertTrue(F.State = fsIdle);
  AssertEquals(1, F.Aborted);
  { section 1 needs no select }
  SlaveLog := '';
  AssertEquals(C.Err, res_Ok, IecFileGetSection(C, Addr, 1, 30001, Nof_Transparent, 1, Got));
  AssertTrue(Got = Copy(Pattern(3000), 1, 1000));
  AssertEquals(0, Pos(' 01 05 |', SlaveLog));
  AssertEquals(res_IecFileRefused, IecFileGetSection(C, Addr, 1, 30001, Nof_Transparent, 9, Got));
  AssertEquals('file IOA 30001 from slave 1: section 9 not ready', C.Err);
  WaitSlaveIdle;
  AssertTrue('deactivated at once', F.State = fsIdle);
  AssertEquals(res_BadParam, IecFileGetSection(C, Addr, 1, 30001, Nof_Transparent, 0, Got));
  { the whole file still comes }
  AssertEquals(C.Err, res_Ok, IecFileGet(C, Addr, 1, 30001, Nof_Transparent, Got));
  AssertTrue(Got = Pattern(3000));
end;

{- ------------------------------------------------------------ live }

{ lib60870's cs104_server_files and cs101_slave_files, built by hand
  (CHN_LIB60870 = its CMake build directory): our client fetches its file
  (IOA 30000) and sends it one (IOA 30001, it writes upload.dat in its
  working directory), over IEC 104 on port 2404 (its fixed port) and over
  FT 1.2 balanced on a pty (its link address 3, 9600 Bd 8E1). }
procedure TTestIecFile.TestLiveLib60870;
var
  Build, Err: string;
  P: TProcess;
  Got: AnsiString;
  Chn: pChnVirt;
  MM: tIecMaster;
  CC: tIecFileClient;
  Step: Integer;
begin
  Build := GetEnvironmentVariable('CHN_LIB60870');
  if (Build = '') or not FileExists(Build + '/examples/cs104_server_files/cs104_server_files') then
  begin
    Ignore('lib60870-C is not built here (CHN_LIB60870 = its build directory with ' +
      'examples/cs104_server_files and cs101_slave_files): the captures stand in for it');
    Exit;
  end;
  for Step := 0 to 1 do
  begin
    P := TProcess.Create(nil);
    Chn := nil;
    try
      { its chatter to /dev/null: a pipe nobody reads could stop it }
      P.CurrentDirectory := FDir;
      P.Executable := '/bin/sh';
      P.Parameters.Add('-c');
      if Step = 0 then
      begin
        P.Parameters.Add('exec ' + Build + '/examples/cs104_server_files/cs104_server_files >/dev/null 2>&1');
        P.Execute;
        Sleep(300);
        Chn := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=2404', Err);
      end
      else
      begin
        Chn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=OFF DIR=1 NOD=3 DNO=3 LEN=0 NAM=COM DRV=PTY BD=9600 PAR=E', Err);
        AssertNotNull(Err, Chn);
        P.Parameters.Add('exec ' + Build + '/examples/cs101_slave_files/cs101_slave_files ' + PtyLastSlave +
          ' >/dev/null 2>&1');
        P.Execute;
      end;
      AssertNotNull(Err, Chn);
      AssertEquals(res_Ok, IecMasterInit(MM, Chn, IecDefaultParams));
      MM.NoGiAfterInit := True;
      IecFileClientInit(CC, MM);
      try
        AssertEquals(CC.Err, res_Ok, IecFileGet(CC, MM.Slaves[0].Addr, 1, 30000, Nof_Transparent, Got));
        AssertTrue('lib60870''s file', Got = Lib60870File);
        AssertEquals(CC.Err, res_Ok, IecFilePut(CC, MM.Slaves[0].Addr, 1, 30001, Nof_Transparent, PutContent));
        AssertTrue('lib60870 wrote what we sent', ReadFileText(FDir + '/upload.dat') = PutContent);
        AssertEquals(res_IecFileRefused, IecFileGet(CC, MM.Slaves[0].Addr, 1, 30005, Nof_Transparent, Got));
      finally
        Finalize(CC);
      end;
    finally
      if P.Running then
        P.Terminate(0);
      P.WaitOnExit;
      P.Free;
      if Chn <> nil then
        Dispose(Chn, Done);
      DeleteFile(FDir + '/upload.dat');
    end;
  end;
end;

initialization
  RegisterTest(TTestIecFile);
end.
