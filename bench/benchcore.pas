{ benchcore - throughput of the shared pieces: checksums, parameter
  parsing and the in-memory null modem. Run with "make bench"; figures are
  for comparison between builds on one machine, not assertions. }
program benchcore;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnLoop;

const
  BlockSize = 60000;   { checksum routines take a Word length }

var
  Block: array[0..BlockSize - 1] of Byte;

procedure Report(const What: string; Bytes: Int64; Ms: QWord);
begin
  if Ms = 0 then
    Ms := 1;
  WriteLn(Format('%-34s %10.1f MB/s', [What, Bytes / 1e6 / (Ms / 1000)]));
end;

procedure BenchChecksums;
const
  Rounds = 2000;
var
  I: Integer;
  T: QWord;
  C: LongWord;
begin
  C := 0;
  T := GetTickCount64;
  for I := 1 to Rounds do
    C := C + Crc16Block(Block, BlockSize, 0);
  Report('Crc16Block', Int64(Rounds) * BlockSize, GetTickCount64 - T);
  T := GetTickCount64;
  for I := 1 to Rounds do
    C := C + Bcc8Block(Block, BlockSize);
  Report('Bcc8Block', Int64(Rounds) * BlockSize, GetTickCount64 - T);
  T := GetTickCount64;
  for I := 1 to Rounds do
    C := C + Xor8Block(Block, BlockSize);
  Report('Xor8Block', Int64(Rounds) * BlockSize, GetTickCount64 - T);
  if C = 1 then
    WriteLn;    { keep C alive }
end;

procedure BenchParams;
const
  Rounds = 20000;
  S = 'NAM=LOOP PAIR=BENCH END=2 LRB=4096 IDL=0';
var
  P: pChnVirt;
  I: Integer;
  T, Ms: QWord;
begin
  P := ChnCollection^.ChNewInit('LOOP');
  T := GetTickCount64;
  for I := 1 to Rounds do
    P^.ChSetParam(S);
  Ms := GetTickCount64 - T;
  if Ms = 0 then
    Ms := 1;
  WriteLn(Format('%-34s %10.0f /s', ['ChSetParam (4 tokens)', Rounds / (Ms / 1000)]));
  Dispose(P, Done);
end;

procedure BenchLoop;
const
  Total = 64 * 1024 * 1024;
var
  A, B: pChnVirt;
  Buf: array[0..4095] of Byte;
  Sent, Got: Int64;
  Len: Word;
  T: QWord;
begin
  A := New(pChnLoop, ChInitParam('PAIR=BL END=1 LRB=65536'));
  B := New(pChnLoop, ChInitParam('PAIR=BL END=2 LRB=65536'));
  A^.ChOpen; A^.ChConnect;
  B^.ChOpen; B^.ChConnect;
  B^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Sent := 0;
  Got := 0;
  T := GetTickCount64;
  while Got < Total do
  begin
    if (Sent < Total) and (A^.ChSendReady = CHS_SendReady) then
    begin
      A^.ChSend(@Block, BlockSize - 1);
      Inc(Sent, BlockSize - 1);
    end;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      Inc(Got, Len);
    end;
  end;
  Report('LOOP transfer, 4 KiB reads', Got, GetTickCount64 - T);
  Dispose(A, Done);
  Dispose(B, Done);
end;

var
  I: Integer;
begin
  for I := 0 to BlockSize - 1 do
    Block[I] := Byte(I * 31 + 7);
  BenchChecksums;
  BenchParams;
  BenchLoop;
end.
