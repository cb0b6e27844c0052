{ Tests of tools/lib/Iec101Asdu, the ASDU helper of the FT 1.2 examples;
  octets worked out by hand from the IEC 60870-5-101 layout TI VSQ COT OA
  CA(2) IOA(3) element, little-endian. }
unit TestIec101Asdu;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, Iec101Asdu, TestSupport;

type
  TTestIec101Asdu = class(TTestCase)
  published
    procedure TestMeasuredScaled;
    procedure TestInterrogationAndMirror;
    procedure TestTextOfOthersAndShort;
  end;

implementation

procedure TTestIec101Asdu.TestMeasuredScaled;
var
  B: array[0..15] of Byte;
begin
  { IOA 110 = 6E 00 00, value -2 = FE FF, common address $0102 }
  AssertEquals(12, AsduMeasuredScaled(@B, CotSpontaneous, $0102, 110, -2));
  AssertEquals('0B 01 03 00 02 01 6E 00 00 FE FF 00', BytesToHex(B, 12));
  AssertEquals('M_ME_NB_1 (11) COT 3 CA 258: IOA 110 = -2', AsduText(@B, 12));
end;

procedure TTestIec101Asdu.TestInterrogationAndMirror;
var
  A, C: array[0..15] of Byte;
begin
  AssertEquals(10, AsduInterrogation(@A, 1));
  AssertEquals('64 01 06 00 01 00 00 00 00 14', BytesToHex(A, 10));
  AssertEquals('C_IC_NA_1 (100) COT 6 CA 1: IOA 0 = 20', AsduText(@A, 10));
  { ACT_CON keeps the negative and test bits: $C6 -> $C7 }
  A[2] := $C6;
  AsduMirror(@A, @C, 10, CotActCon);
  AssertEquals('64 01 C7 00 01 00 00 00 00 14', BytesToHex(C, 10));
  AssertEquals('C_IC_NA_1 (100) COT 7 CA 1 negative: IOA 0 = 20', AsduText(@C, 10));
end;

procedure TTestIec101Asdu.TestTextOfOthersAndShort;
var
  B: TBytes;
begin
  B := HexToBytes('07 01 14 00 01 00 F4 01 00 AA AA 00 00 00');
  AssertEquals('type (7) COT 20 CA 1, 1 objects: F4 01 00 AA AA 00 00 00',
    AsduText(@B[0], Length(B)));
  B := HexToBytes('0B 01 03');
  AssertEquals('short ASDU: 0B 01 03', AsduText(@B[0], Length(B)));
end;

initialization
  RegisterTest(TTestIec101Asdu);
end.
