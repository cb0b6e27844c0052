{ Tests of tools/lib/ChnIec101Print, the one JSON and text form of IEC 101
  information objects: the lines expected are written out from the JSON
  format of docs/ChnIec101.md, from ASDUs given as octets. }
unit TestIec101Print;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnIec101Asdu, ChnIec101Print, TestSupport;

type
  TTestIec101Print = class(TTestCase)
  private
    function Json(const Hex: string; Index: Integer = 0): string;
  published
    procedure TestJsonOfMonitoringTypes;
    procedure TestJsonOfCommandsAndSystem;
    procedure TestTextLines;
  end;

implementation

function TTestIec101Print.Json(const Hex: string; Index: Integer): string;
var
  B: TBytes;
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
begin
  B := HexToBytes(Hex);
  AssertEquals(Hex + ': ' + E, 0, IecDecodeHeader(IecDefaultParams, B, Length(B), H, E));
  AssertEquals(0, IecDecodeObject(IecDefaultParams, H, B, Index, O));
  Result := IecObjectJson(H, O);
end;

procedure TTestIec101Print.TestJsonOfMonitoringTypes;
begin
  AssertEquals('{"type":"M_SP_NA_1","ti":1,"cot":20,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":301,"value":false,"quality":128}', Json('01 83 14 00 01 00 2C 01 00 01 80 01', 1));
  AssertEquals('{"type":"M_DP_NA_1","ti":3,"cot":3,"negative":false,"test":true,"oa":2,"ca":1,'
    + '"ioa":1,"value":2,"quality":64}', Json('03 01 83 02 01 00 01 00 00 42'));
  AssertEquals('{"type":"M_ST_NA_1","ti":5,"cot":3,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":1,"value":-64,"transient":true,"quality":128}', Json('05 01 03 00 01 00 01 00 00 C0 80'));
  AssertEquals('{"type":"M_BO_NA_1","ti":7,"cot":20,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":500,"value":2863311530,"quality":0}', Json('07 01 14 00 01 00 F4 01 00 AA AA AA AA 00'));
  AssertEquals('{"type":"M_ME_NA_1","ti":9,"cot":3,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":1,"value":-0.25,"quality":0}', Json('09 01 03 00 01 00 01 00 00 00 E0 00'));
  AssertEquals('{"type":"M_ME_NB_1","ti":11,"cot":20,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":100,"value":-1,"quality":0}', Json('0B 01 14 00 01 00 64 00 00 FF FF 00'));
  AssertEquals('{"type":"M_ME_TF_1","ti":36,"cot":3,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":700,"value":12.5,"quality":0,"time":"2026-12-01T22:15:30.250"}',
    Json('24 01 03 00 01 00 BC 02 00 00 00 48 41 00 2A 76 0F 16 41 0C 1A'));
  AssertEquals('{"type":"M_ME_NC_1","ti":13,"cot":3,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":1,"value":0.1,"quality":0}', Json('0D 01 03 00 01 00 01 00 00 CD CC CC 3D 00'));
  AssertEquals('{"type":"M_IT_NA_1","ti":15,"cot":37,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":1,"value":-2,"seq":5,"quality":160}', Json('0F 01 25 00 01 00 01 00 00 FE FF FF FF A5'));
  AssertEquals('{"type":"M_SP_TA_1","ti":2,"cot":3,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":104,"value":true,"quality":0,"time":"07:12.345"}', Json('02 01 03 00 01 00 68 00 00 01 39 30 87'));
  AssertEquals('{"type":"M_EI_NA_1","ti":70,"cot":4,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":0,"value":0,"quality":0}', Json('46 01 04 00 01 00 00 00 00 00'));
end;

procedure TTestIec101Print.TestJsonOfCommandsAndSystem;
begin
  AssertEquals('{"type":"C_SC_NA_1","ti":45,"cot":7,"negative":true,"test":false,"oa":0,"ca":1,'
    + '"ioa":5000,"value":true,"select":true,"quality":0}', Json('2D 01 47 00 01 00 88 13 00 81'));
  AssertEquals('{"type":"C_DC_NA_1","ti":46,"cot":6,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":1,"value":2,"select":false,"quality":0}', Json('2E 01 06 00 01 00 01 00 00 02'));
  AssertEquals('{"type":"C_IC_NA_1","ti":100,"cot":10,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":0,"value":20,"quality":0}', Json('64 01 0A 00 01 00 00 00 00 14'));
  AssertEquals('{"type":"C_CS_NA_1","ti":103,"cot":7,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":0,"value":null,"quality":0,"time":"2026-12-01T22:15:30.250"}',
    Json('67 01 07 00 01 00 00 00 00 2A 76 0F 16 41 0C 1A'));
  AssertEquals('{"type":"C_RD_NA_1","ti":102,"cot":5,"negative":false,"test":false,"oa":0,"ca":1,'
    + '"ioa":100,"value":null,"quality":0}', Json('66 01 05 00 01 00 64 00 00'));
end;

procedure TTestIec101Print.TestTextLines;
var
  B: TBytes;
begin
  B := HexToBytes('01 83 14 00 01 00 2C 01 00 01 80 01');
  AssertEquals('M_SP_NA_1 INTERROGATED_BY_STATION CA 1: IOA 300 = on, IOA 301 = off [IV], IOA 302 = on',
    IecAsduText(IecDefaultParams, B, Length(B)));
  B := HexToBytes('2D 01 47 00 01 00 88 13 00 81');
  AssertEquals('C_SC_NA_1 ACTIVATION_CON negative CA 1: IOA 5000 = on select',
    IecAsduText(IecDefaultParams, B, Length(B)));
  B := HexToBytes('0B 01 03 00 01 00 6E 00 00 FE FF');
  AssertEquals('bad ASDU: M_ME_NB_1 with 1 object(s) needs 12 octets, got 11: 0B 01 03 00 01 00 6E 00 00 FE FF',
    IecAsduText(IecDefaultParams, B, Length(B)));
  B := HexToBytes('24 01 03 00 01 00 BC 02 00 00 00 48 41 00 2A 76 8F 96 41 0C 1A');
  AssertEquals('M_ME_TF_1 SPONTANEOUS CA 1: IOA 700 = 12.5 2026-12-01T22:15:30.250 (time IV) SU',
    IecAsduText(IecDefaultParams, B, Length(B)));
end;

initialization
  RegisterTest(TTestIec101Print);
end.
