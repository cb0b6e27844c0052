{ df1icscodec - throughput of the DF1 and ICS codecs (ChnDF1Codec,
  ChnICSCodec), no I/O: encode and byte-by-byte decode of a short and a
  full frame. Prints frames/s and MB/s; ft12codec does the same for FT 1.2. }
program df1icscodec;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnDF1Codec, ChnICSCodec;

procedure Report(const Name: string; N: Word; Rounds: LongInt; TEnc, TDec: QWord);
begin
  if TEnc = 0 then TEnc := 1;
  if TDec = 0 then TDec := 1;
  WriteLn(Format('%-34s %3d bytes  encode %9.0f frames/s  decode %9.0f frames/s (%6.1f MB/s)',
    [Name, N, Rounds * 1000.0 / TEnc, Rounds * 1000.0 / TDec, Rounds * N / 1048.576 / TDec]));
end;

procedure RunDF1(const Name: string; DataLen: Word; Crc: Boolean; Fill: Byte; Rounds: LongInt);
var
  Cfg: tDF1Config;
  Rec: tSendRecord;
  Dec: tDF1Decoder;
  Buf: array[0..1023] of Byte;
  N: Word;
  I, J, Frames: LongInt;
  T0, TEnc: QWord;
begin
  FillChar(Cfg, SizeOf(Cfg), 0);
  Cfg.FullDup := True;
  Cfg.Master := True;
  Cfg.Crc := Crc;
  Cfg.Node := 1;
  Cfg.DNode := 2;
  Cfg.NakByte := NAK;
  FillChar(Rec, SizeOf(Rec), 0);
  Rec.MessType := tpDataMess;
  Rec.CF := $4F00;              { a reply: no FNC }
  Rec.Tns := 7;
  FillChar(Rec.Data, SizeOf(Rec.Data), Fill);
  N := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    DF1Encode(Cfg, Rec, 8 + DataLen, Buf, SizeOf(Buf), N);
  TEnc := ChMsTick - T0;
  Cfg.Node := 2;
  DF1DecoderInit(Dec, Cfg);
  Frames := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    for J := 0 to N - 1 do
      if DF1Feed(Dec, Buf[J]) = dfMessage then
        Inc(Frames);
  if Frames <> Rounds then
    WriteLn('DF1 decode error: ', Frames, ' frames');
  Report(Name, N, Rounds, TEnc, ChMsTick - T0);
end;

procedure RunICS(const Name: string; Count: Integer; const Text: string; Rounds: LongInt);
var
  Rec: tICSRecord;
  St: tICSState;
  Buf: array[0..1023] of Byte;
  N: Word;
  I, J, Frames: LongInt;
  T0, TEnc: QWord;
begin
  FillChar(Rec, SizeOf(Rec), 0);
  Rec.OpCode := 'DB';
  for I := 0 to Count - 1 do
    Rec.Data[I] := -32768 + I * 2047;
  Rec.Text := Text;
  N := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    ICSEncode(Rec, ICSLenOfCount(Count), 1, 2, Buf, SizeOf(Buf), N);
  TEnc := ChMsTick - T0;
  ICSReset(St);
  Frames := 0;
  T0 := ChMsTick;
  for I := 1 to Rounds do
    for J := 0 to N - 1 do
      if ICSFeed(St, Buf[J]) = icsFrame then
        Inc(Frames);
  if Frames <> Rounds then
    WriteLn('ICS decode error: ', Frames, ' frames');
  Report(Name, N, Rounds, TEnc, ChMsTick - T0);
end;

begin
  RunDF1('DF1 echo, 4 data, BCC', 4, False, $41, 2000000);
  RunDF1('DF1 244 data, CRC', MaxDataLen, True, $41, 200000);
  RunDF1('DF1 244 data all $10, CRC', MaxDataLen, True, $10, 200000);
  RunICS('ICS RD, no data', 0, '', 2000000);
  RunICS('ICS DB, 32 numbers + 60-char text', 32, '"' + StringOfChar('x', 58) + '"', 200000);
end.
