{ ft12codec - throughput of the FT 1.2 codec (ChnFT12Codec), no I/O:
  encode and byte-by-byte decode of a fixed IEC 101 frame and of a full
  variable frame (247 data octets). Prints frames/s and MB/s. }
program ft12codec;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnFT12Codec;

function MakeCfg(Primary: Boolean): tFT12Config;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Primary := Primary;
  Result.AddrLen := 1;
  Result.CheckPrm := True;
end;

procedure Run(const Name: string; DataLen: Word; MessType: tMessType; Rounds: LongInt);
var
  Rec: tFT12Record;
  Buf: array[0..cFT12MaxFrame - 1] of Byte;
  N: Word;
  I, J, Frames: LongInt;
  Rx: tFT12Rx;
  T0, TEnc, TDec: QWord;
begin
  FillChar(Rec, SizeOf(Rec), 0);
  Rec.MessType := MessType;
  Rec.FC := 3;
  for I := 1 to DataLen do
    Rec.Data[I] := I;
  N := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    FT12Encode(MakeCfg(True), Rec, cSizeHeadSndMsg + DataLen, 1, @Buf, SizeOf(Buf), N);
  TEnc := ChMsTick - T0;
  FillChar(Rx, SizeOf(Rx), 0);
  Rx.Cfg := MakeCfg(False);
  FT12RxReset(Rx);
  Frames := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    for J := 0 to N - 1 do
      if FT12Feed(Rx, Buf[J], 0) = fe_Frame then
        Inc(Frames);
  TDec := ChMsTick - T0;
  if Frames <> Rounds then
    WriteLn('decode error: ', Frames, ' frames');
  if TEnc = 0 then TEnc := 1;
  if TDec = 0 then TDec := 1;
  WriteLn(Format('%-28s %3d bytes  encode %9.0f frames/s  decode %9.0f frames/s (%6.1f MB/s)',
    [Name, N, Rounds * 1000.0 / TEnc, Rounds * 1000.0 / TDec,
     Rounds * N / 1048.576 / TDec]));
end;

begin
  Run('fixed frame 10 C A CS 16', 0, tpShortM, 10000000);
  Run('variable frame, 247 data', MaxDataLen, tpLongM, 400000);
end.
