{ benchtrc - what the trace layer (NAM=TRC) costs: formatting and reading
  the log, the time per chunk with and without TRC on both ends of a LOOP
  pair, and a 64 KiB burst. Run with "make bench"; the log goes to a temp
  file that is deleted at the end. Figures are for comparison between
  builds on one machine, not assertions. }
program benchtrc;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnLoop, ChnTrc, ChnTrcFormat;

var
  Block: array[0..65535] of Byte;
  LogPath: string;

function Elapsed(T: QWord): QWord;
begin
  Result := GetTickCount64 - T;
  if Result = 0 then
    Result := 1;
end;

procedure BenchFormat;
const
  Rounds = 200;
  ModeName: array[tTrcMode] of string = ('HEX', 'DEC');
var
  I: Integer;
  T: QWord;
  S: AnsiString;
  F: tTrcFrames;
  Mode: tTrcMode;
begin
  F := nil;
  for Mode := trcHex to trcDec do
  begin
    T := GetTickCount64;
    for I := 1 to Rounds do
      S := TrcFormat(0, trcTx, Block, 65535, Mode, 'TRC');
    WriteLn(Format('%-38s %8.1f MB/s', ['TrcFormat, MOD=' + ModeName[Mode],
      Rounds * 65535 / 1e6 / (Elapsed(T) / 1000)]));
    T := GetTickCount64;
    for I := 1 to Rounds do
      TrcReadText(S, F);
    WriteLn(Format('%-38s %8.1f MB/s', ['TrcReadText, bytes read back',
      Rounds * 65535 / 1e6 / (Elapsed(T) / 1000)]));
  end;
end;

{ Chunks of Len bytes from A to B, one at a time; microseconds per chunk. }
function PingPong(const Top, ParA, ParB: string; Len, Count: Integer): Double;
var
  A, B: pChnVirt;
  Buf: array[0..4095] of Byte;
  I: Integer;
  Got: LongInt;
  L: Word;
  T: QWord;
begin
  A := ChnCollection^.ChNewInit(Top);
  A^.ChSetParam(ParA);
  B := ChnCollection^.ChNewInit(Top);
  B^.ChSetParam(ParB);
  A^.ChOpen; A^.ChConnect;
  B^.ChOpen; B^.ChConnect;
  if (A^.ChResult <> res_Ok) or (B^.ChResult <> res_Ok) then
  begin
    WriteLn('cannot open ', ParA, ' / ', ParB);
    Halt(1);
  end;
  B^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  L := 0;
  T := GetTickCount64;
  for I := 1 to Count do
  begin
    A^.ChSend(@Block, Len);
    Got := 0;
    while Got < Len do
      if B^.ChReceiveReady = CHS_ReceiveReady then
      begin
        B^.ChReceive(L);
        Inc(Got, L);
      end;
  end;
  Result := Elapsed(T) * 1000.0 / Count;
  Dispose(A, Done);
  Dispose(B, Done);
end;

procedure BenchChunks;
const
  Count = 20000;
  Lens: array[0..2] of Integer = (2, 60, 1000);
var
  Plain, Traced: Double;
  Len: Integer;
begin
  for Len in Lens do
  begin
    Plain := PingPong('LOOP', 'NAM=LOOP PAIR=BP END=1', 'NAM=LOOP PAIR=BP END=2', Len, Count);
    Traced := PingPong('TRC', 'NAM=TRC FILE=' + LogPath + ' NAM=LOOP PAIR=BT END=1',
      'NAM=TRC FILE=' + LogPath + ' NAM=LOOP PAIR=BT END=2', Len, Count);
    WriteLn(Format('%4d-byte chunk: %7.2f us plain, %7.2f us with TRC on both ends',
      [Len, Plain, Traced]));
  end;
end;

procedure BenchBurst;
var
  Plain, Traced: Double;
begin
  Plain := PingPong('LOOP', 'NAM=LOOP PAIR=BB END=1 LRB=4096', 'NAM=LOOP PAIR=BB END=2', 65535, 50);
  Traced := PingPong('TRC', 'NAM=TRC FILE=' + LogPath + ' NAM=LOOP PAIR=BC END=1',
    'NAM=TRC FILE=' + LogPath + ' NAM=LOOP PAIR=BC END=2', 65535, 50);
  WriteLn(Format('64 KiB burst: %7.2f ms plain, %7.2f ms with TRC on both ends',
    [Plain / 1000, Traced / 1000]));
end;

var
  I: Integer;
begin
  for I := 0 to High(Block) do
    Block[I] := Byte(I * 31 + 7);
  LogPath := IncludeTrailingPathDelimiter(GetTempDir(False)) + 'benchtrc-' +
    IntToStr(GetProcessID) + '.log';
  BenchFormat;
  BenchChunks;
  BenchBurst;
  DeleteFile(LogPath);
end.
