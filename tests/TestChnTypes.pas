{ Tests of ChnTypes: checksums against known values and real DF1 line
  captures (docs/PROTOCOLS.md section 4, RACOM note), result texts. }
unit TestChnTypes;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, TestSupport;

type
  TTestChnTypes = class(TTestCase)
  published
    procedure TestCrc16KnownValues;
    procedure TestCrc16OfEveryRacomFrame;
    procedure TestBcc8OfRacomNakFrame;
    procedure TestBcc8IsTwosComplement;
    procedure TestSum8Ft12LinkStatusFrame;
    procedure TestXor8;
    procedure TestEveryGeneralResultHasText;
    procedure TestProtocolResultTextsPerLayer;
    procedure TestTypeSizes;
  end;

implementation

{ Bytes between DLE STX and DLE ETX with DLE DLE reduced to one DLE. This
  is deliberately naive test code, independent of the DF1 codec. }
function Unstuff(const F: TBytes): TBytes;
var
  I, N: Integer;
begin
  SetLength(Result, Length(F));
  N := 0;
  I := 2;
  while I < Length(F) - 4 do
  begin
    Result[N] := F[I];
    Inc(N);
    if F[I] = $10 then
      Inc(I, 2)
    else
      Inc(I);
  end;
  SetLength(Result, N);
end;

procedure TTestChnTypes.TestCrc16KnownValues;
var
  S: string;
begin
  { CRC-16/ARC of '123456789' is $BB3D (poly $8005 reflected = $A001, init 0) }
  S := '123456789';
  AssertEquals('CRC-16/ARC check value', $BB3D, Crc16Block(S[1], 9, 0));
  AssertEquals('empty', 0, Crc16Block(S[1], 0, 0));
  AssertEquals('single byte $01', $C0C1, Crc16Add(0, 1));
end;

procedure TTestChnTypes.TestCrc16OfEveryRacomFrame;
var
  I: Integer;
  F, D: TBytes;
  Crc: tCrc16;
begin
  for I := Low(RacomFrames) to High(RacomFrames) do
  begin
    F := HexToBytes(RacomFrames[I]);
    D := Unstuff(F);
    Crc := Crc16Block(D[0], Length(D), 0);
    Crc := Crc16Add(Crc, $03);         { the ETX byte is part of the CRC }
    AssertEquals('frame ' + IntToStr(I),
      F[Length(F) - 2] or (F[Length(F) - 1] shl 8), Crc);
  end;
  { frame 3 is the one docs/PROTOCOLS.md quotes: CRC $99B6 }
  D := Unstuff(HexToBytes(RacomFrames[3]));
  AssertEquals('frame 3 unstuffed length', 32, Length(D));
  AssertEquals($99B6, Crc16Add(Crc16Block(D[0], Length(D), 0), 3));
end;

procedure TTestChnTypes.TestBcc8OfRacomNakFrame;
var
  D: TBytes;
begin
  { '10 02 0E 0D AA AA 10 03 91' from the failed exchange in the RACOM note }
  D := HexToBytes('0E 0D AA AA');
  AssertEquals($91, Bcc8Block(D[0], 4));
end;

procedure TTestChnTypes.TestBcc8IsTwosComplement;
var
  Sum: tBcc8;
  I: Integer;
begin
  Sum := 0;
  for I := 1 to 300 do
    Sum := Bcc8Add(Sum, Byte(I * 7));
  { sum of data plus BCC is 0 modulo 256 }
  AssertEquals(0, Byte(Sum + Bcc8Final(Sum)));
  AssertEquals('poll BCC of station 1', $FF, Bcc8Final(1));
  AssertEquals('BCC of nothing', 0, Bcc8Final(0));
end;

procedure TTestChnTypes.TestSum8Ft12LinkStatusFrame;
var
  D: TBytes;
begin
  { IEC 60870-5-101 request link status to address 1: 10 49 01 4A 16 }
  D := HexToBytes('49 01');
  AssertEquals($4A, Sum8Block(D[0], 2));
  D := HexToBytes('FF FF 03');
  AssertEquals('modulo 256', $01, Sum8Block(D[0], 3));
end;

procedure TTestChnTypes.TestXor8;
var
  S: string;
begin
  S := #1'1'#2'0RD0,'#3;
  AssertEquals(1 xor Ord('1') xor 2 xor Ord('0') xor Ord('R') xor Ord('D') xor
    Ord('0') xor Ord(',') xor 3, Xor8Block(S[1], Length(S)));
  AssertEquals($5A xor $A5, Xor8Add($5A, $A5));
  { bits both have cancel ($5A or $A5 would look the same as xor) }
  AssertEquals($55, Xor8Add($5A, $0F));
  AssertEquals(0, Xor8Add($3C, $3C));
end;

procedure TTestChnTypes.TestEveryGeneralResultHasText;
var
  R: tChResult;
  T: string;
begin
  for R := res_Ok to res_Proto - 1 do
  begin
    T := ChResultText(R);
    if R <= res_LastGeneral then
      AssertFalse('text of ' + IntToStr(R), Pos('unknown result', T) > 0)
    else
      AssertTrue('unused code ' + IntToStr(R) + ' says unknown', Pos('unknown result', T) > 0);
  end;
  AssertEquals('ok', ChResultText(res_Ok));
  AssertEquals('device lost', ChResultText(res_DeviceLost));
end;

procedure TTestChnTypes.TestProtocolResultTextsPerLayer;
begin
  ChRegisterResultText('XA', res_Proto, 'frame error');
  ChRegisterResultText('XB', res_Proto, 'checksum error');
  AssertEquals('XA: frame error', ChResultText(res_Proto, 'XA'));
  AssertEquals('XB: checksum error', ChResultText(res_Proto, 'xb'));
  AssertTrue(Pos('unknown result code', ChResultText(res_Proto + 90, 'XA')) > 0);
end;

procedure TTestChnTypes.TestTypeSizes;
begin
  AssertEquals(256, SizeOf(tParamStr));
  AssertEquals(256, SizeOf(tWordString));
  AssertEquals(2, SizeOf(tNode));
  AssertEquals(1, SizeOf(tBcc8));
  AssertEquals(2, SizeOf(tCrc16));
  AssertEquals(1, SizeOf(tSum8));
  AssertEquals(1, SizeOf(tXor8));
end;

initialization
  RegisterTest(TTestChnTypes);
end.
