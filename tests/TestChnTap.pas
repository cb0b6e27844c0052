{ Tests of tools/chntap, the software Y-cable, run as a program between two
  pty pairs the test creates (A = slave of pair 1, B = slave of pair 2; the
  test plays both devices on the masters):
  * 1 MiB of DF1 frames each way at the same time arrives unchanged and in
    order, while chntap decodes every frame (its summary counts them all
    and no error), and its pcap holds both streams byte for byte;
  * a frame is printed live with time and direction;
  * side A going away is reported, B stays open, SIGINT ends the tap with
    both sides closed and exit code 0;
  * usage errors and a side that cannot be opened: exit code 2. }
unit TestChnTap;

{$MODE OBJFPC}{$H+}

interface

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnTrcFormat,
  ChnPcap, ChnDF1Codec, TestSupport, TestTempDir, BinSupport{$IFDEF UNIX}, PtyPair{$ENDIF};

type
  TTestChnTap = class(TTestCase)
  private
    Dir: string;
    {$IFDEF UNIX}
    P1, P2: TPtyPair;
    Tap: TProcess;
    Output: string;
    procedure StartTap(const Args: array of string);
    function StopTap(Sig: cint): Integer;
    procedure DrainTap;
    function WaitOutput(const Sub: string; TimeoutMs: Integer): Boolean;
    {$ENDIF}
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    {$IFDEF UNIX}
    procedure TestMiBBothWaysWhileDecoding;
    procedure TestFramePrintedLive;
    procedure TestDf1CheckFoundLive;
    procedure TestSideLostThenSigint;
    {$ENDIF}
    procedure TestUsageErrors;
  end;

implementation

uses
  uString, ChnVirt;

{ DF1 frames (full duplex, CRC) of 1 to 244 data bytes, Count of them from
  Seed on, as one stream; Frames gets how many. }
function Df1Stream(Seed, MinBytes: LongInt; out Frames: LongInt): AnsiString;
var
  Cfg: tDF1Config;
  Rec: tSendRecord;
  Out: array[0..1023] of Byte;
  OutLen: Word;
  N, I, Pos: LongInt;
begin
  FillChar(Cfg, SizeOf(Cfg), 0);
  Cfg.FullDup := True;
  Cfg.Crc := True;
  Cfg.Node := Seed and 7;
  Cfg.DNode := 1;
  SetLength(Result, MinBytes + 2048);
  Pos := 0;
  Frames := 0;
  while Pos < MinBytes do
  begin
    FillChar(Rec, SizeOf(Rec), 0);
    Rec.MessType := tpDataMess;
    Rec.CF := $0F00 or ((Frames + Seed) and $FF);
    Rec.Tns := Frames;
    N := 1 + (Frames * 37 + Seed) mod MaxDataLen;
    for I := 0 to N - 1 do
      Rec.Data[I] := (I * 13 + Frames + Seed) and $FF;   { $10 too: stuffed }
    OutLen := 0;
    if DF1Encode(Cfg, Rec, 8 + N, Out, SizeOf(Out), OutLen) <> res_Ok then
      raise Exception.Create('DF1Encode failed');
    Move(Out, Result[Pos + 1], OutLen);
    Inc(Pos, OutLen);
    Inc(Frames);
  end;
  SetLength(Result, Pos);
end;

procedure TTestChnTap.SetUp;
begin
  Dir := MakeTempDir('chntap');
  {$IFDEF UNIX}
  P1 := nil;
  P2 := nil;
  Tap := nil;
  Output := '';
  {$ENDIF}
end;

procedure TTestChnTap.TearDown;
begin
  {$IFDEF UNIX}
  if Tap <> nil then
  begin
    StopProcess(Tap);
  end;
  FreeAndNil(P1);
  FreeAndNil(P2);
  {$ENDIF}
  RemoveTempDir(Dir);
end;

{$IFDEF UNIX}
procedure TTestChnTap.StartTap(const Args: array of string);
var
  A: string;
begin
  P1 := TPtyPair.Create;
  P2 := TPtyPair.Create;
  { the tap must not inherit the masters: closing one here must hang its
    slave up, as a device that goes away }
  FpFcntl(P1.Master, F_SETFD, 1);   { FD_CLOEXEC }
  FpFcntl(P2.Master, F_SETFD, 1);   { FD_CLOEXEC }
  Tap := TProcess.Create(nil);
  BinExecutable(Tap, BinPath('chntap'));
  for A in Args do
    Tap.Parameters.Add(A);
  Tap.Parameters.Add('NAM=COM DEV=' + P1.SlavePath);
  Tap.Parameters.Add('NAM=COM DEV=' + P2.SlavePath);
  Tap.Options := [poUsePipes, poStderrToOutPut];
  Tap.Execute;
  AssertTrue('chntap starts: ' + Output, WaitOutput('B: NAM=', 5000));
end;

procedure TTestChnTap.DrainTap;
begin
  Drain(Tap, Output);
end;

function TTestChnTap.WaitOutput(const Sub: string; TimeoutMs: Integer): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + TimeoutMs;
  repeat
    DrainTap;
    if Pos(Sub, Output) > 0 then
      Exit(True);
    Sleep(5);
  until GetTickCount64 > Deadline;
  Result := Pos(Sub, Output) > 0;
end;

{ Send Sig, wait up to 5 s for the end; the exit code, -1 if it hung. }
function TTestChnTap.StopTap(Sig: cint): Integer;
var
  Deadline: QWord;
begin
  FpKill(Tap.ProcessID, Sig);
  Deadline := GetTickCount64 + 5000;
  while Tap.Running and (GetTickCount64 < Deadline) do
  begin
    DrainTap;
    Sleep(5);
  end;
  DrainTap;
  if Tap.Running then
    Exit(-1);
  Result := Tap.ExitCode;
  DrainTap;
end;

procedure TTestChnTap.TestMiBBothWaysWhileDecoding;
const
  MiB = 1024 * 1024;
var
  AB, BA, GotB, GotA: AnsiString;
  FramesAB, FramesBA, SentA, SentB, N: LongInt;
  Buf: array[0..65535] of Byte;
  Deadline: QWord;
  F: tTrcFrames;
  Info: tPcapInfo;
  PcapAB, PcapBA: AnsiString;
  I: Integer;
begin
  AB := Df1Stream(1, MiB, FramesAB);
  BA := Df1Stream(2, MiB, FramesBA);
  StartTap(['--df1', '--crc', '--quiet', '--pcap', Dir + 'tap.pcap']);
  GotA := '';
  GotB := '';
  SentA := 0;
  SentB := 0;
  Deadline := GetTickCount64 + 120000;
  { both devices talk at once, as fast as the ptys take it }
  while ((Length(GotA) < Length(BA)) or (Length(GotB) < Length(AB))) and
        (GetTickCount64 < Deadline) do
  begin
    if SentA < Length(AB) then
    begin
      N := P1.MasterWrite(AB[SentA + 1], Length(AB) - SentA);
      if N > 0 then
        Inc(SentA, N);
    end;
    if SentB < Length(BA) then
    begin
      N := P2.MasterWrite(BA[SentB + 1], Length(BA) - SentB);
      if N > 0 then
        Inc(SentB, N);
    end;
    N := P2.MasterRead(Buf, SizeOf(Buf));
    if N > 0 then
    begin
      SetLength(GotB, Length(GotB) + N);
      Move(Buf, GotB[Length(GotB) - N + 1], N);
    end;
    N := P1.MasterRead(Buf, SizeOf(Buf));
    if N > 0 then
    begin
      SetLength(GotA, Length(GotA) + N);
      Move(Buf, GotA[Length(GotA) - N + 1], N);
    end;
    DrainTap;
    if N <= 0 then
      Sleep(0);
  end;
  DrainTap;
  AssertEquals('A>B bytes; chntap said: ' + Output, Length(AB), Length(GotB));
  AssertEquals('B>A bytes; chntap said: ' + Output, Length(BA), Length(GotA));
  AssertTrue('A>B unchanged', AB = GotB);
  AssertTrue('B>A unchanged', BA = GotA);
  AssertEquals('exit code after SIGINT', 0, StopTap(SIGINT));
  AssertTrue(Output, Pos(Format('A>B: %d bytes, %d frames, 0 errors; 0 bytes for B dropped',
    [Length(AB), FramesAB]), Output) > 0);
  AssertTrue(Output, Pos(Format('B>A: %d bytes, %d frames, 0 errors; 0 bytes for A dropped',
    [Length(BA), FramesBA]), Output) > 0);
  AssertTrue('at least 1 MiB each way', (Length(AB) >= MiB) and (Length(BA) >= MiB));
  { the pcap: tx is A to B, rx B to A, every byte }
  AssertEquals(res_Ok, PcapReadBytes(ReadFileText(Dir + 'tap.pcap'), 0, F, Info));
  PcapBA := '';
  PcapAB := '';
  for I := 0 to High(F) do
  begin
    if F[I].Dir = trcTx then
    begin
      SetLength(PcapAB, Length(PcapAB) + Length(F[I].Data));
      Move(F[I].Data[0], PcapAB[Length(PcapAB) - Length(F[I].Data) + 1], Length(F[I].Data));
    end
    else
    begin
      SetLength(PcapBA, Length(PcapBA) + Length(F[I].Data));
      Move(F[I].Data[0], PcapBA[Length(PcapBA) - Length(F[I].Data) + 1], Length(F[I].Data));
    end;
  end;
  AssertTrue('pcap A>B', PcapAB = AB);
  AssertTrue('pcap B>A', PcapBA = BA);
end;

procedure TTestChnTap.TestFramePrintedLive;
const
  Echo = '1002 0100 0600 0000 0041 686F 6A10 0363 0F';
var
  B: TBytes;
  Got: array[0..63] of Byte;
begin
  StartTap(['--df1', '--trace=' + Dir + 'tap.log']);
  B := HexToBytes(Echo);
  AssertTrue(P1.MasterWriteAll(B[0], Length(B), 2000));
  AssertEquals(Length(B), P2.MasterReadAll(Got, Length(B), 3000));
  { printed while the tap runs, before it ends }
  AssertTrue(Output, WaitOutput('A>B DF1 DST=1 SRC=0 CMD=$06 FNC=$00 STS=$00 TNS=$0000 (Echo)', 3000));
  Got[0] := $10;
  Got[1] := $06;
  AssertTrue(P2.MasterWriteAll(Got, 2, 2000));
  AssertTrue(Output, WaitOutput('B>A DF1 ACK (DLE ACK)', 3000));
  AssertEquals(0, StopTap(SIGTERM));
  { the text trace, from A's point of view }
  AssertTrue(ReadFileText(Dir + 'tap.log'), Pos('tx   17 | TRC', ReadFileText(Dir + 'tap.log')) > 0);
  AssertTrue(Pos('rx   2 | TRC', ReadFileText(Dir + 'tap.log')) > 0);
end;

{ Without --crc or --bcc the first data frame decides: a BCC frame (BCC
  $B7 = -(01+00+06+00+01+00+00+41), worked out by hand) is decoded as BCC,
  and the choice is printed. }
procedure TTestChnTap.TestDf1CheckFoundLive;
const
  EchoBcc = '1002 0100 0600 0100 0041 1003 B7';
  ReplyBcc = '1002 0001 4600 0100 4110 0377';
var
  B: TBytes;
  Got: array[0..63] of Byte;
begin
  StartTap(['--df1']);
  B := HexToBytes(EchoBcc);
  AssertTrue(P1.MasterWriteAll(B[0], Length(B), 2000));
  AssertEquals(Length(B), P2.MasterReadAll(Got, Length(B), 3000));
  AssertTrue(Output, WaitOutput('DF1 check: BCC, found from the first frames', 3000));
  AssertTrue(Output, WaitOutput('A>B DF1 DST=1 SRC=0 CMD=$06 FNC=$00 STS=$00 TNS=$0001 (Echo), ' +
    '1 data bytes: 41, BCC $B7 ok', 3000));
  B := HexToBytes(ReplyBcc);
  AssertTrue(P2.MasterWriteAll(B[0], Length(B), 2000));
  AssertTrue(Output, WaitOutput('BCC $77 ok', 3000));
  AssertEquals(0, StopTap(SIGTERM));
  AssertTrue(Output, Pos('A>B: 13 bytes, 1 frames, 0 errors', Output) > 0);
end;

procedure TTestChnTap.TestSideLostThenSigint;
var
  Got: array[0..15] of Byte;
begin
  StartTap(['--raw']);
  P1.CloseMaster;                       { device A gone }
  AssertTrue(Output, WaitOutput('A: device lost', 3000));
  AssertTrue(Output, Pos('B keeps its settings', Output) > 0);
  { B is still open: what it sends is taken (and dropped, A is away) }
  Got[0] := $41;
  AssertTrue(P2.MasterWriteAll(Got, 1, 2000));
  Sleep(100);
  AssertTrue('still running', Tap.Running);
  AssertEquals(0, StopTap(SIGINT));
  AssertTrue(Output, Pos('B>A: 1 bytes, 0 frames, 0 errors; 1 bytes for A dropped', Output) > 0);
end;
{$ENDIF}

procedure TTestChnTap.TestUsageErrors;
var
  Out: string;
begin
  AssertEquals(2, RunBin('chntap', ['NAM=LOOP PAIR=T1 END=1'], 10000, Out));
  AssertTrue(Out, Pos('two parameter strings needed', Out) > 0);
  AssertEquals(2, RunBin('chntap', ['--bogus', 'NAM=LOOP PAIR=T1 END=1', 'NAM=LOOP PAIR=T2 END=1'], 10000, Out));
  AssertTrue(Out, Pos('unknown option (--bogus)', Out) > 0);
  { a side that cannot be opened is no command-line error: exit 1 }
  AssertEquals(1, RunBin('chntap', ['NAM=COM DEV=' + Dir + 'nothere', 'NAM=LOOP PAIR=T2 END=1'], 10000, Out));
  AssertTrue(Out, Pos('cannot be opened', Out) > 0);
  AssertEquals(2, RunBin('chntap', ['NAM=XYZ', 'NAM=LOOP PAIR=T2 END=1'], 10000, Out));
  AssertTrue(Out, Pos('unknown layer name (NAM=XYZ)', Out) > 0);
  AssertEquals(2, RunBin('chntap', ['NAM=COM BD=7', 'NAM=LOOP PAIR=T2 END=1'], 10000, Out));
  AssertTrue(Out, Pos('BD=7', Out) > 0);
end;

initialization
  RegisterTest(TTestChnTap);
end.
