{ Tests of ChnIec101Asdu. The octets are worked out by hand from the
  layouts of IEC 60870-5-101 clause 7 (TI VSQ COT [OA] CA IOA element
  [time], little-endian) and the element table below is written out from
  the standard, not taken from the unit. }
unit TestChnIec101Asdu;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, DateUtils, Math, fpcunit, testregistry, ChnTypes, ChnIec101Asdu, TestSupport;

type
  TTestChnIec101Asdu = class(TTestCase)
  private
    function Enc(const P: tIecParams; Ti, Cot: Byte; Ca: Word; const O: tIecObject): string;
    procedure DecodeOne(const P: tIecParams; const Hex: string; out H: tIecAsdu; out O: tIecObject);
    procedure CheckRefused(const P: tIecParams; const Hex: string; R: tChResult; const Part: string);
  published
    procedure TestLayouts;
    procedure TestParams;
    procedure TestNamesAndSizes;
    procedure TestScaledAsTheExamples;
    procedure TestInterrogationAndCounterInterrogation;
    procedure TestClockSyncCP56;
    procedure TestSequenceOfSinglePoints;
    procedure TestSmallParams;
    procedure TestElementValues;
    procedure TestCommands;
    procedure TestTimeTaggedMonitoring;
    procedure TestEveryTypeRoundTrips;
    procedure TestMalformedAreRefused;
    procedure TestImpossibleEncodesAreRefused;
    procedure TestTimeConversion;
    procedure TestNaNFromTheLineDoesNotTrap;
    procedure TestSequenceUpToTheLargestIoa;
    procedure TestReservedTimeBitsIgnored;
    procedure TestSetCotKeepsTheTestBit;
  end;

implementation

const
  { TI, element octets after the IOA (time tag included), from the standard }
  StdSizes: array[0..58, 0..1] of Byte = (
    (1, 1), (2, 4), (3, 1), (4, 4), (5, 2), (6, 5), (7, 5), (8, 8), (9, 3), (10, 6),
    (11, 3), (12, 6), (13, 5), (14, 8), (15, 5), (16, 8), (17, 6), (18, 7), (19, 7),
    (20, 5), (21, 2), (30, 8), (31, 8), (32, 9), (33, 12), (34, 10), (35, 10), (36, 12),
    (37, 12), (38, 10), (39, 11), (40, 11), (45, 1), (46, 1), (47, 1), (48, 3), (49, 3),
    (50, 5), (51, 4), (58, 8), (59, 8), (60, 8), (61, 10), (62, 10), (63, 12), (64, 11),
    (70, 1), (100, 1), (101, 1), (102, 0), (103, 7), (104, 2), (105, 1), (106, 2),
    (107, 9), (110, 3), (111, 3), (112, 5), (113, 1));

function Params(Cot, Ca, Ioa: Byte): tIecParams;
begin
  Result.CotSize := Cot;
  Result.CaSize := Ca;
  Result.IoaSize := Ioa;
end;

function TTestChnIec101Asdu.Enc(const P: tIecParams; Ti, Cot: Byte; Ca: Word; const O: tIecObject): string;
var
  B: array[0..255] of Byte;
  L: Word;
  E: ShortString;
begin
  AssertEquals('encode ' + IecTypeName(Ti) + ': ' + E, res_Ok, IecEncodeOne(P, Ti, Cot, Ca, O, B, L, E));
  Result := BytesToHex(B, L);
end;

procedure TTestChnIec101Asdu.DecodeOne(const P: tIecParams; const Hex: string; out H: tIecAsdu;
  out O: tIecObject);
var
  B: TBytes;
  E: ShortString;
begin
  B := HexToBytes(Hex);
  AssertEquals('decode ' + Hex + ': ' + E, res_Ok, IecDecodeHeader(P, B, Length(B), H, E));
  AssertEquals('object 1', res_Ok, IecDecodeObject(P, H, B, 0, O));
end;

procedure TTestChnIec101Asdu.CheckRefused(const P: tIecParams; const Hex: string; R: tChResult;
  const Part: string);
var
  B: TBytes;
  H: tIecAsdu;
  E: ShortString;
begin
  B := HexToBytes(Hex);
  AssertEquals(Hex, R, IecDecodeHeader(P, B, Length(B), H, E));
  AssertTrue(Hex + ': "' + E + '" names ' + Part, Pos(Part, E) > 0);
end;

procedure TTestChnIec101Asdu.TestLayouts;
var
  O: tIecObject;
  T: tIecTime;
  H: tIecAsdu;
begin
  AssertEquals('SizeOf(tIecParams)', 3, SizeOf(tIecParams));
  AssertEquals('SizeOf(tIecTime)', 10, SizeOf(tIecTime));
  AssertEquals('Msec@0', 0, PtrUInt(@T.Msec) - PtrUInt(@T));
  AssertEquals('Minute@2', 2, PtrUInt(@T.Minute) - PtrUInt(@T));
  AssertEquals('DayOfWeek@5', 5, PtrUInt(@T.DayOfWeek) - PtrUInt(@T));
  AssertEquals('Summer@9', 9, PtrUInt(@T.Summer) - PtrUInt(@T));
  AssertEquals('SizeOf(tIecObject)', 37, SizeOf(tIecObject));
  AssertEquals('Int@4', 4, PtrUInt(@O.Int) - PtrUInt(@O));
  AssertEquals('Bits@8', 8, PtrUInt(@O.Bits) - PtrUInt(@O));
  AssertEquals('Number@12', 12, PtrUInt(@O.Number) - PtrUInt(@O));
  AssertEquals('Quality@20', 20, PtrUInt(@O.Quality) - PtrUInt(@O));
  AssertEquals('Qu@24', 24, PtrUInt(@O.Qu) - PtrUInt(@O));
  AssertEquals('Elapsed@25', 25, PtrUInt(@O.Elapsed) - PtrUInt(@O));
  AssertEquals('Time@27', 27, PtrUInt(@O.Time) - PtrUInt(@O));
  AssertEquals('SizeOf(tIecAsdu)', 13, SizeOf(tIecAsdu));
  AssertEquals('Cot@3', 3, PtrUInt(@H.Cot) - PtrUInt(@H));
  AssertEquals('Ca@7', 7, PtrUInt(@H.Ca) - PtrUInt(@H));
  AssertEquals('Len@11', 11, PtrUInt(@H.Len) - PtrUInt(@H));
end;

procedure TTestChnIec101Asdu.TestParams;
var
  E: ShortString;
begin
  AssertEquals(2, IecDefaultParams.CotSize);
  AssertEquals(2, IecDefaultParams.CaSize);
  AssertEquals(3, IecDefaultParams.IoaSize);
  AssertEquals(6, IecHeadLen(IecDefaultParams));
  AssertEquals(4, IecHeadLen(Params(1, 1, 1)));
  AssertEquals(res_Ok, IecCheckParams(Params(1, 2, 2), E));
  AssertEquals(res_AsduParam, IecCheckParams(Params(3, 2, 3), E));
  AssertTrue(E, Pos('COT size 3', E) > 0);
  AssertEquals(res_AsduParam, IecCheckParams(Params(2, 0, 3), E));
  AssertTrue(E, Pos('common address size 0', E) > 0);
  AssertEquals(res_AsduParam, IecCheckParams(Params(2, 2, 4), E));
  AssertTrue(E, Pos('IOA size 4', E) > 0);
  AssertEquals(255, IecMaxIoa(Params(1, 1, 1)));
  AssertEquals(65535, IecMaxIoa(Params(1, 1, 2)));
  AssertEquals(16777215, IecMaxIoa(Params(1, 1, 3)));
  AssertTrue(Pos('impossible application parameters', ChResultText(res_AsduParam, Iec101Layer)) > 0);
end;

procedure TTestChnIec101Asdu.TestNamesAndSizes;
var
  I, N: Integer;
begin
  for I := Low(StdSizes) to High(StdSizes) do
  begin
    AssertEquals('size of TI ' + IntToStr(StdSizes[I, 0]), StdSizes[I, 1], IecElementSize(StdSizes[I, 0]));
    AssertTrue('name of TI ' + IntToStr(StdSizes[I, 0]), IecTypeName(StdSizes[I, 0]) <> '');
    AssertEquals('by name', StdSizes[I, 0], IecTypeByName(IecTypeName(StdSizes[I, 0])));
  end;
  N := 0;
  for I := 0 to 255 do
    if IecTypeName(I) <> '' then
      Inc(N);
  AssertEquals('types known', Length(StdSizes), N);
  AssertEquals(-1, IecElementSize(22));
  AssertEquals('', IecTypeName(127));
  AssertEquals('M_ME_TF_1', IecTypeName(36));
  AssertEquals('C_SE_TC_1', IecTypeName(63));
  AssertEquals(36, IecTypeByName(' m_me_tf_1 '));
  AssertEquals(0, IecTypeByName('M_XX_NA_1'));
  AssertTrue(IecIsMonitor(M_EI_NA_1));
  AssertFalse(IecIsMonitor(C_SC_NA_1));
  AssertTrue(IecTypeTime(M_SP_TA_1) = tkCP24);
  AssertTrue(IecTypeTime(C_SC_TA_1) = tkCP56);
  AssertTrue(IecTypeKind(M_IT_TB_1) = ikCounter);
  AssertEquals('ACTIVATION_CON', IecCotName(7));
  AssertEquals('INTERROGATED_BY_GROUP_3', IecCotName(23));
  AssertEquals('UNKNOWN_INFORMATION_OBJECT_ADDRESS', IecCotName(47));
  AssertEquals('COT_50', IecCotName(50));
end;

procedure TTestChnIec101Asdu.TestScaledAsTheExamples;
var
  O: tIecObject;
  H: tIecAsdu;
begin
  O := IecObject(110);
  O.Int := -2;
  AssertEquals('0B 01 03 00 02 01 6E 00 00 FE FF 00', Enc(IecDefaultParams, M_ME_NB_1, Cot_Spontaneous, $0102, O));
  DecodeOne(IecDefaultParams, '0B 01 03 00 02 01 6E 00 00 FE FF 00', H, O);
  AssertEquals(M_ME_NB_1, H.Ti);
  AssertEquals(Cot_Spontaneous, H.Cot);
  AssertEquals($0102, H.Ca);
  AssertEquals(110, O.Ioa);
  AssertEquals(-2, O.Int);
  AssertEquals(0, O.Quality);
end;

procedure TTestChnIec101Asdu.TestInterrogationAndCounterInterrogation;
var
  O: tIecObject;
  H: tIecAsdu;
begin
  O := IecObject(0);
  O.Int := Qoi_Station;
  AssertEquals('64 01 06 00 01 00 00 00 00 14', Enc(IecDefaultParams, C_IC_NA_1, Cot_Activation, 1, O));
  O.Int := Qoi_Station + 3;   { group 3 }
  AssertEquals('64 01 06 00 01 00 00 00 00 17', Enc(IecDefaultParams, C_IC_NA_1, Cot_Activation, 1, O));
  O.Int := Qcc_General or Qcc_Freeze;
  AssertEquals('65 01 06 00 01 00 00 00 00 45', Enc(IecDefaultParams, C_CI_NA_1, Cot_Activation, 1, O));
  { negative ACT_CON with test bit and originator 3 }
  DecodeOne(IecDefaultParams, '64 01 C7 03 01 00 00 00 00 14', H, O);
  AssertEquals(Cot_ActCon, H.Cot);
  AssertTrue(H.Negative);
  AssertTrue(H.Test);
  AssertEquals(3, H.Oa);
  AssertEquals(20, O.Int);
  { read: the IOA alone }
  O := IecObject($030201);
  AssertEquals('66 01 05 00 01 00 01 02 03', Enc(IecDefaultParams, C_RD_NA_1, Cot_Request, 1, O));
end;

procedure TTestChnIec101Asdu.TestClockSyncCP56;
var
  O: tIecObject;
  H: tIecAsdu;
begin
  { Tuesday 2026-12-01 22:15:30.250 summer time: ms 30250 = $762A }
  O := IecObject(0);
  O.Time := IecTimeFromDateTime(EncodeDateTime(2026, 12, 1, 22, 15, 30, 250));
  AssertEquals(2, O.Time.DayOfWeek);
  O.Time.Summer := True;
  AssertEquals('67 01 06 00 01 00 00 00 00 2A 76 0F 96 41 0C 1A',
    Enc(IecDefaultParams, C_CS_NA_1, Cot_Activation, 1, O));
  DecodeOne(IecDefaultParams, '67 01 07 00 01 00 00 00 00 2A 76 8F 96 41 0C 1A', H, O);
  AssertEquals(30250, O.Time.Msec);
  AssertEquals(15, O.Time.Minute);
  AssertEquals(22, O.Time.Hour);
  AssertEquals(1, O.Time.Day);
  AssertEquals(2, O.Time.DayOfWeek);
  AssertEquals(12, O.Time.Month);
  AssertEquals(26, O.Time.Year);
  AssertTrue('IV', O.Time.Invalid);
  AssertTrue('SU', O.Time.Summer);
end;

procedure TTestChnIec101Asdu.TestSequenceOfSinglePoints;
var
  Objs: array[0..2] of tIecObject;
  Back: array[0..2] of tIecObject;
  Small: array[0..1] of tIecObject;
  H: tIecAsdu;
  B: array[0..63] of Byte;
  L: Word;
  E: ShortString;
  I: Integer;
begin
  for I := 0 to 2 do
  begin
    Objs[I] := IecObject(300 + I);
    Objs[I].Int := Ord(I <> 1);
  end;
  Objs[1].Quality := Q_Invalid;
  FillChar(H, SizeOf(H), 0);
  H.Ti := M_SP_NA_1;
  H.Sq := True;
  H.Count := 3;
  H.Cot := Cot_Interrogated;
  H.Ca := 1;
  AssertEquals(E, res_Ok, IecEncodeAsdu(IecDefaultParams, H, Objs, B, L, E));
  AssertEquals('01 83 14 00 01 00 2C 01 00 01 80 01', BytesToHex(B, L));
  AssertEquals(E, res_Ok, IecDecodeAsdu(IecDefaultParams, B, L, H, Back, E));
  AssertTrue(H.Sq);
  AssertEquals(3, H.Count);
  for I := 0 to 2 do
  begin
    AssertEquals('IOA', 300 + I, Back[I].Ioa);
    AssertEquals('value', Ord(I <> 1), Back[I].Int);
  end;
  AssertEquals(Q_Invalid, Back[1].Quality);
  AssertEquals('array too short', res_AsduCount, IecDecodeAsdu(IecDefaultParams, B, L, H, Small, E));
  { the same without SQ: every object its IOA }
  H.Sq := False;
  AssertEquals(E, res_Ok, IecEncodeAsdu(IecDefaultParams, H, Objs, B, L, E));
  AssertEquals('01 03 14 00 01 00 2C 01 00 01 2D 01 00 80 2E 01 00 01', BytesToHex(B, L));
  { a sequence whose IOAs do not follow }
  H.Sq := True;
  Objs[2].Ioa := 310;
  AssertEquals(res_AsduIoa, IecEncodeAsdu(IecDefaultParams, H, Objs, B, L, E));
  AssertTrue(E, Pos('object 3: IOA 310 does not follow', E) > 0);
end;

procedure TTestChnIec101Asdu.TestSmallParams;
var
  O: tIecObject;
  H: tIecAsdu;
  P: tIecParams;
begin
  P := Params(1, 1, 1);
  O := IecObject(7);
  O.Int := 1;
  O.Select := True;
  AssertEquals('2D 01 06 05 07 81', Enc(P, C_SC_NA_1, Cot_Activation, 5, O));
  DecodeOne(P, '2D 01 47 05 07 81', H, O);
  AssertEquals(0, H.Oa);
  AssertTrue(H.Negative);
  AssertEquals(5, H.Ca);
  AssertEquals(7, O.Ioa);
  AssertTrue(O.Select);
  P := Params(2, 1, 2);
  O := IecObject($1234);
  O.Int := 2;
  AssertEquals('2E 01 06 00 09 34 12 02', Enc(P, C_DC_NA_1, Cot_Activation, 9, O));
end;

procedure TTestChnIec101Asdu.TestElementValues;
var
  O: tIecObject;
  H: tIecAsdu;
  P: tIecParams;
begin
  P := IecDefaultParams;
  { step position -64, transient, QDS IV }
  DecodeOne(P, '05 01 03 00 01 00 01 00 00 C0 80', H, O);
  AssertEquals(-64, O.Int);
  AssertTrue(O.Transient);
  AssertEquals($80, O.Quality);
  O := IecObject(1);
  O.Int := 63;
  AssertEquals('05 01 03 00 01 00 01 00 00 3F 00', Enc(P, M_ST_NA_1, Cot_Spontaneous, 1, O));
  { bitstring $AAAA5555 }
  DecodeOne(P, '07 01 14 00 01 00 F4 01 00 55 55 AA AA 00', H, O);
  AssertEquals(500, O.Ioa);
  AssertEquals(LongWord($AAAA5555), O.Bits);
  { normalized -1 and 0.5 with overflow }
  DecodeOne(P, '09 01 03 00 01 00 01 00 00 00 80 00', H, O);
  AssertEquals(-1.0, O.Number, 0);
  AssertEquals(-32768, O.Int);
  O := IecObject(1);
  O.Number := 0.5;
  O.Quality := Q_Overflow;
  AssertEquals('09 01 03 00 01 00 01 00 00 00 40 01', Enc(P, M_ME_NA_1, Cot_Spontaneous, 1, O));
  O.Number := 0.99999;
  AssertEquals('just below 1', '15 01 03 00 01 00 01 00 00 FF 7F', Enc(P, M_ME_ND_1, Cot_Spontaneous, 1, O));
  { short float 12.5 = $41480000 }
  O := IecObject(700);
  O.Number := 12.5;
  AssertEquals('0D 01 03 00 01 00 BC 02 00 00 00 48 41 00', Enc(P, M_ME_NC_1, Cot_Spontaneous, 1, O));
  DecodeOne(P, '0D 01 03 00 01 00 BC 02 00 00 00 48 C1 10', H, O);
  AssertEquals(-12.5, O.Number, 0);
  AssertEquals(Q_Blocked, O.Quality);
  { integrated totals -2, sequence 5, carry and invalid }
  DecodeOne(P, '0F 01 25 00 01 00 01 00 00 FE FF FF FF A5', H, O);
  AssertEquals(-2, O.Int);
  AssertEquals(5, O.Seq);
  AssertEquals(Q_Invalid or Q_Substituted, O.Quality);
  AssertEquals(37, H.Cot);
  { double point state 2 (on), not topical }
  DecodeOne(P, '03 01 14 00 01 00 01 00 00 42', H, O);
  AssertEquals(2, O.Int);
  AssertEquals(Q_NotTopical, O.Quality);
  { packed single points: status $00FF, change $0F00 }
  DecodeOne(P, '14 01 14 00 01 00 01 00 00 FF 00 00 0F 00', H, O);
  AssertEquals(LongWord($0F0000FF), O.Bits);
  { end of initialisation, local change, cause 2 }
  DecodeOne(P, '46 01 04 00 01 00 00 00 00 82', H, O);
  AssertEquals($82, O.Int);
  { parameter of scaled value 100, QPM 1 (threshold) }
  O := IecObject(11);
  O.Int := 100;
  O.Qu := 1;
  AssertEquals('6F 01 06 00 01 00 0B 00 00 64 00 01', Enc(P, P_ME_NB_1, Cot_Activation, 1, O));
  { test command with its fixed pattern, delay acquisition 1500 ms }
  O := IecObject(0);
  O.Int := Fbp_Test;
  AssertEquals('68 01 06 00 01 00 00 00 00 AA 55', Enc(P, C_TS_NA_1, Cot_Activation, 1, O));
  O := IecObject(0);
  O.Elapsed := 1500;
  AssertEquals('6A 01 03 00 01 00 00 00 00 DC 05', Enc(P, C_CD_NA_1, Cot_Spontaneous, 1, O));
end;

procedure TTestChnIec101Asdu.TestCommands;
var
  O: tIecObject;
  H: tIecAsdu;
  P: tIecParams;
begin
  P := IecDefaultParams;
  { single command on, select, QU 0 to IOA 5000 = $001388 }
  O := IecObject(5000);
  O.Int := 1;
  O.Select := True;
  AssertEquals('2D 01 06 00 01 00 88 13 00 81', Enc(P, C_SC_NA_1, Cot_Activation, 1, O));
  { execute with QU 1 (short pulse) }
  O.Select := False;
  O.Qu := 1;
  AssertEquals('2D 01 06 00 01 00 88 13 00 05', Enc(P, C_SC_NA_1, Cot_Activation, 1, O));
  { regulating step higher }
  O := IecObject(1);
  O.Int := 2;
  AssertEquals('2F 01 06 00 01 00 01 00 00 02', Enc(P, C_RC_NA_1, Cot_Activation, 1, O));
  { set point scaled -300 select, QL 0 }
  O := IecObject(2);
  O.Int := -300;
  O.Select := True;
  AssertEquals('31 01 06 00 01 00 02 00 00 D4 FE 80', Enc(P, C_SE_NB_1, Cot_Activation, 1, O));
  { set point float 1.5 = $3FC00000 }
  O := IecObject(3);
  O.Number := 1.5;
  AssertEquals('32 01 06 00 01 00 03 00 00 00 00 C0 3F 00', Enc(P, C_SE_NC_1, Cot_Activation, 1, O));
  { bitstring command }
  O := IecObject(4);
  O.Bits := $01020304;
  AssertEquals('33 01 06 00 01 00 04 00 00 04 03 02 01', Enc(P, C_BO_NA_1, Cot_Activation, 1, O));
  { single command with time tag, decoded }
  DecodeOne(P, '3A 01 07 00 01 00 88 13 00 01 10 27 05 0A 41 0C 1A', H, O);
  AssertEquals(1, O.Int);
  AssertFalse(O.Select);
  AssertEquals(10000, O.Time.Msec);
  AssertEquals(5, O.Time.Minute);
  AssertEquals(10, O.Time.Hour);
  { double command: state and QU }
  DecodeOne(P, '2E 01 06 00 01 00 01 00 00 8E', H, O);
  AssertEquals(2, O.Int);
  AssertEquals(3, O.Qu);
  AssertTrue(O.Select);
end;

procedure TTestChnIec101Asdu.TestTimeTaggedMonitoring;
var
  O: tIecObject;
  H: tIecAsdu;
  P: tIecParams;
begin
  P := IecDefaultParams;
  { single point with CP24Time2a: on, 12.345 s, minute 7, IV }
  DecodeOne(P, '02 01 03 00 01 00 68 00 00 01 39 30 87', H, O);
  AssertEquals(104, O.Ioa);
  AssertEquals(1, O.Int);
  AssertEquals(12345, O.Time.Msec);
  AssertEquals(7, O.Time.Minute);
  AssertTrue(O.Time.Invalid);
  { scaled with CP56Time2a as lib60870's slave sends in interrogation }
  O := IecObject(100);
  O.Int := 2300;
  O.Time.Msec := 1000;
  O.Time.Minute := 1;
  O.Time.Hour := 2;
  O.Time.Day := 3;
  O.Time.DayOfWeek := 4;
  O.Time.Month := 5;
  O.Time.Year := 6;
  AssertEquals('23 01 14 00 01 00 64 00 00 FC 08 00 E8 03 01 02 83 05 06',
    Enc(P, M_ME_TE_1, Cot_Interrogated, 1, O));
  { protection event: state 2, EI, elapsed 300 ms, CP24 }
  DecodeOne(P, '11 01 03 00 01 00 01 00 00 0A 2C 01 00 00 00', H, O);
  AssertEquals(2, O.Int);
  AssertEquals(Q_ElapsedInv, O.Quality);
  AssertEquals(300, O.Elapsed);
  { start events GS + SL1, QDP IV, duration 5 ms, CP56 }
  DecodeOne(P, '27 01 03 00 01 00 01 00 00 03 80 05 00 00 00 00 00 01 01 00', H, O);
  AssertEquals(3, O.Bits);
  AssertEquals(Q_Invalid, O.Quality);
  AssertEquals(5, O.Elapsed);
  AssertEquals(1, O.Time.Day);
  AssertEquals(1, O.Time.Month);
end;

{ Every type with a value of its kind encodes, decodes to the same object
  and encodes to the same octets again. }
procedure TTestChnIec101Asdu.TestEveryTypeRoundTrips;
var
  I: Integer;
  Ti: Byte;
  O, Back: tIecObject;
  H: tIecAsdu;
  B: array[0..255] of Byte;
  L: Word;
  E: ShortString;
  P: tIecParams;
  First: string;
begin
  P := IecDefaultParams;
  for I := Low(StdSizes) to High(StdSizes) do
  begin
    Ti := StdSizes[I, 0];
    O := IecObject(1000 + I);
    case IecTypeKind(Ti) of
      ikSingle, ikSingleCmd: O.Int := 1;
      ikDouble, ikDoubleCmd, ikStepCmd, ikProtection: O.Int := 2;
      ikStep: O.Int := -5;
      ikScaled, ikSetScaled, ikParScaled: O.Int := -1234;
      ikNormal, ikSetNormal, ikParNormal: O.Number := -0.25;
      ikFloat, ikSetFloat, ikParFloat: O.Number := 3.5;
      ikCounter: begin O.Int := -100000; O.Seq := 17; end;
      ikBits, ikBitsCmd, ikPacked: O.Bits := $DEADBEEF;
      ikStartEvents, ikOutputCircuit: O.Bits := 5;
      ikEndInit, ikQualifier: O.Int := 21;
      ikTest, ikTestTime: O.Int := $55AA;
    end;
    if IecTypeKind(Ti) in [ikNormal, ikSetNormal, ikParNormal] then
      O.Int := -8192;   { what decoding gives: the raw value }
    if IecTypeKind(Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat] then
    begin
      O.Select := True;
      O.Qu := 3;
    end;
    if IecTypeKind(Ti) in [ikParNormal, ikParScaled, ikParFloat] then
      O.Qu := $41;
    if IecTypeKind(Ti) in [ikSingle, ikDouble, ikStep, ikBits, ikScaled, ikFloat, ikPacked] then
      O.Quality := Q_Blocked;
    if (IecTypeKind(Ti) = ikNormal) and (StdSizes[I, 1] <> 2) then
      O.Quality := Q_Invalid or Q_Overflow;
    if IecTypeKind(Ti) = ikCounter then
      O.Quality := Q_Invalid;
    if IecTypeKind(Ti) in [ikProtection, ikStartEvents, ikOutputCircuit] then
    begin
      O.Quality := Q_ElapsedInv;
      O.Elapsed := 777;
    end;
    if IecTypeKind(Ti) = ikDelay then
      O.Elapsed := 321;
    if IecTypeTime(Ti) <> tkNone then
    begin
      O.Time.Msec := 59999;
      O.Time.Minute := 59;
      O.Time.Invalid := True;
      if IecTypeTime(Ti) = tkCP56 then
      begin
        O.Time.Hour := 23;
        O.Time.Day := 31;
        O.Time.DayOfWeek := 7;
        O.Time.Month := 12;
        O.Time.Year := 99;
        O.Time.Summer := True;
      end;
    end;
    AssertEquals(IecTypeName(Ti) + ': ' + E, res_Ok, IecEncodeOne(P, Ti, Cot_Spontaneous, 1, O, B, L, E));
    AssertEquals(IecTypeName(Ti) + ' length', 6 + 3 + StdSizes[I, 1], L);
    First := BytesToHex(B, L);
    AssertEquals(IecTypeName(Ti) + ': ' + E, res_Ok, IecDecodeHeader(P, B, L, H, E));
    AssertEquals(res_Ok, IecDecodeObject(P, H, B, 0, Back));
    AssertTrue(IecTypeName(Ti) + ' decodes to the object encoded', CompareMem(@O, @Back, SizeOf(O)));
    AssertEquals(res_Ok, IecEncodeOne(P, Ti, Cot_Spontaneous, 1, Back, B, L, E));
    AssertEquals(IecTypeName(Ti) + ' again', First, BytesToHex(B, L));
  end;
end;

procedure TTestChnIec101Asdu.TestMalformedAreRefused;
var
  P: tIecParams;
  B: TBytes;
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
begin
  P := IecDefaultParams;
  CheckRefused(P, '0B 01 03 00 02', res_AsduShort, 'shorter than its identifier');
  CheckRefused(P, '', res_AsduShort, '0 octets');
  CheckRefused(P, '16 01 03 00 01 00 01 00 00 00', res_AsduType, 'type identification 22');
  CheckRefused(P, '0B 00 03 00 01 00', res_AsduCount, 'VSQ number 0');
  CheckRefused(P, '0B 01 03 00 01 00 6E 00 00 FE FF', res_AsduLength, 'M_ME_NB_1 with 1 object(s) needs 12 octets, got 11');
  CheckRefused(P, '0B 01 03 00 01 00 6E 00 00 FE FF 00 00', res_AsduLength, 'got 13');
  CheckRefused(P, '01 83 14 00 01 00 2C 01 00 01 80', res_AsduLength, 'in a sequence needs 12');
  CheckRefused(P, '01 02 14 00 01 00 2C 01 00 01', res_AsduLength, 'needs 14');
  { a sequence of 3 from IOA 254 with one-octet IOAs runs past 255 }
  CheckRefused(Params(2, 2, 1), '01 83 14 00 01 00 FE 01 01 01', res_AsduIoa, 'runs past IOA 255');
  CheckRefused(Params(4, 2, 3), '01 01 14 00 01 00 01 00 00 01', res_AsduParam, 'COT size 4');
  { Len beyond the array given }
  B := HexToBytes('01 01 14 00 01 00 01 00 00 01');
  AssertEquals(res_AsduLength, IecDecodeHeader(P, B, 11, H, E));
  AssertTrue(E, Pos('beyond the buffer', E) > 0);
  { an object index outside the ASDU }
  AssertEquals(res_Ok, IecDecodeHeader(P, B, 10, H, E));
  AssertEquals(res_AsduCount, IecDecodeObject(P, H, B, 1, O));
  AssertEquals(res_AsduCount, IecDecodeObject(P, H, B, -1, O));
  { a header with a length that does not belong to this buffer }
  H.Len := 200;
  AssertEquals(res_AsduCount, IecDecodeObject(P, H, B, 0, O));
end;

procedure TTestChnIec101Asdu.TestImpossibleEncodesAreRefused;
var
  P: tIecParams;
  O: tIecObject;
  B: array[0..255] of Byte;
  Tiny: array[0..8] of Byte;
  L: Word;
  E: ShortString;
  H: tIecAsdu;
  Many: array[0..126] of tIecObject;
  I: Integer;

  procedure Refused(Ti: Byte; R: tChResult; const Part: string);
  begin
    AssertEquals(IecTypeName(Ti) + ' ' + Part, R, IecEncodeOne(P, Ti, Cot_Activation, 1, O, B, L, E));
    AssertTrue('"' + E + '" names ' + Part, Pos(Part, E) > 0);
    AssertEquals('nothing encoded', 0, L);
  end;

begin
  P := Params(2, 1, 1);
  O := IecObject(256);
  Refused(C_SC_NA_1, res_AsduIoa, 'IOA 256 too large for 1 octet(s)');
  O := IecObject(1);
  O.Int := 2;
  Refused(C_SC_NA_1, res_AsduValue, 'value 2 out of range (0..1)');
  O.Int := 4;
  Refused(C_DC_NA_1, res_AsduValue, 'state 4 out of range');
  O.Int := 1;
  O.Qu := 32;
  Refused(C_SC_NA_1, res_AsduValue, 'QU 32 out of range (0..31)');
  O := IecObject(1);
  O.Int := 40000;
  Refused(C_SE_NB_1, res_AsduValue, 'scaled value 40000 out of range (-32768..32767)');
  O.Int := 0;
  O.Number := 1.0;
  Refused(C_SE_NA_1, res_AsduValue, 'normalized value 1 out of range');
  O.Number := 1e39;
  Refused(C_SE_NC_1, res_AsduValue, 'out of range of a short float');
  O.Number := 0;
  O.Qu := 128;
  Refused(C_SE_NC_1, res_AsduValue, 'QL 128');
  O := IecObject(1);
  O.Int := 64;
  Refused(M_ST_NA_1, res_AsduValue, 'step position 64');
  O := IecObject(1);
  O.Seq := 32;
  Refused(M_IT_NA_1, res_AsduValue, 'sequence number 32');
  O := IecObject(1);
  O.Time.Month := 16;
  Refused(C_SC_TA_1, res_AsduValue, 'time tag month 16');
  O := IecObject(1);
  Refused(99, res_AsduType, 'unknown type identification 99');
  AssertEquals(res_AsduValue, IecEncodeOne(P, C_SC_NA_1, Cot_Activation, 256, O, B, L, E));
  AssertTrue(E, Pos('common address 256 too large for 1', E) > 0);
  AssertEquals(res_AsduValue, IecEncodeOne(P, C_SC_NA_1, 64, 1, O, B, L, E));
  AssertTrue(E, Pos('cause of transmission 64', E) > 0);
  { too small a buffer: refused, nothing written past it }
  AssertEquals(res_AsduLength, IecEncodeOne(IecDefaultParams, C_SC_NA_1, Cot_Activation, 1, O, Tiny, L, E));
  AssertTrue(E, Pos('needs 10 octets, room for 9', E) > 0);
  { originator address with one-octet COT }
  FillChar(H, SizeOf(H), 0);
  H.Ti := M_SP_NA_1;
  H.Count := 1;
  H.Oa := 5;
  P := Params(1, 1, 1);
  AssertEquals(res_AsduValue, IecEncodeAsdu(P, H, [O], B, L, E));
  AssertTrue(E, Pos('originator address 5', E) > 0);
  { count above the objects given, count 0, an ASDU above 253 octets }
  H.Oa := 0;
  H.Count := 2;
  AssertEquals(res_AsduCount, IecEncodeAsdu(P, H, [O], B, L, E));
  H.Count := 0;
  AssertEquals(res_AsduCount, IecEncodeAsdu(P, H, [O], B, L, E));
  for I := 0 to High(Many) do
    Many[I] := IecObject(I);
  H.Count := 127;
  H.Ti := M_ME_NC_1;
  AssertEquals(res_AsduLength, IecEncodeAsdu(IecDefaultParams, H, Many, B, L, E));
  AssertTrue(E, Pos('room for 253', E) > 0);
end;

procedure TTestChnIec101Asdu.TestTimeConversion;
var
  T: tIecTime;
  DT: TDateTime;
  E: ShortString;
begin
  T := IecTimeFromDateTime(EncodeDateTime(2027, 2, 28, 23, 59, 59, 999));
  AssertEquals(59999, T.Msec);
  AssertEquals(7, T.DayOfWeek);   { a Sunday }
  AssertEquals(27, T.Year);
  AssertTrue(IecTimeToDateTime(T, DT));
  AssertEquals('2027-02-28 23:59:59.999', FormatDateTime('yyyy-mm-dd hh:nn:ss.zzz', DT));
  T.Day := 29;
  AssertFalse(IecTimeToDateTime(T, DT));
  AssertEquals(res_AsduValue, IecTimeCheck(T, False, E));
  AssertTrue(E, Pos('day 29 (1..28)', E) > 0);
  AssertEquals('only minutes and ms in a CP24Time2a', res_Ok, IecTimeCheck(T, True, E));
  T.Msec := 60000;
  AssertEquals(res_AsduValue, IecTimeCheck(T, True, E));
  AssertTrue(E, Pos('milliseconds 60000', E) > 0);
end;

{ Found by fuzzasdu: a signalling NaN converted to Double raised
  EInvalidOp. Every NaN decodes to a quiet one and encodes as $7FC00000. }
procedure TTestChnIec101Asdu.TestNaNFromTheLineDoesNotTrap;
var
  O: tIecObject;
  H: tIecAsdu;
begin
  DecodeOne(IecDefaultParams, '0D 01 03 00 01 00 01 00 00 01 00 80 7F 00', H, O);
  AssertTrue('signalling NaN', IsNan(O.Number));
  DecodeOne(IecDefaultParams, '0D 01 03 00 01 00 01 00 00 00 00 C0 FF 00', H, O);
  AssertTrue('quiet NaN', IsNan(O.Number));
  AssertEquals('0D 01 03 00 01 00 01 00 00 00 00 C0 7F 00', Enc(IecDefaultParams, M_ME_NC_1, Cot_Spontaneous, 1, O));
  DecodeOne(IecDefaultParams, '0D 01 03 00 01 00 01 00 00 00 00 80 FF 00', H, O);
  AssertTrue('minus infinity', IsInfinite(O.Number) and (O.Number < 0));
  AssertEquals('0D 01 03 00 01 00 01 00 00 00 00 80 FF 00', Enc(IecDefaultParams, M_ME_NC_1, Cot_Spontaneous, 1, O));
end;

{ IOA of 2 octets: a sequence (SQ=1) of two single points from IOA 65534
  ends on 65535, the largest, and is taken; from 65535 its second object
  would be 65536, and it is refused.
  01 82 14 01 FE FF 01 00: M_SP_NA_1, SQ=1 N=2, COT 20, CA 1, IOA 65534, SIQ 1, 0. }
procedure TTestChnIec101Asdu.TestSequenceUpToTheLargestIoa;
var
  P: tIecParams;
  B: TBytes;
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
begin
  P := Params(1, 1, 2);
  B := HexToBytes('01 82 14 01 FE FF 01 00');
  AssertEquals(E, res_Ok, IecDecodeHeader(P, B, Length(B), H, E));
  AssertEquals(res_Ok, IecDecodeObject(P, H, B, 1, O));
  AssertEquals('last IOA', 65535, O.Ioa);
  AssertEquals('last value', 0, O.Int);
  CheckRefused(P, '01 82 14 01 FF FF 01 00', res_AsduIoa, 'runs past IOA 65535');
end;

{ CP56Time2a (IEC 60870-5-101 7.2.6.18): RES1 is bit 6 of the minute octet
  (the minute 0..59 in bits 0-5, IV in bit 7), RES2 bits 5-6 of the hour octet, RES3 bits 4-7 of the month, RES4 bit 7
  of the year: set on the line, none of them shows in the value.
  1E 01 03 00 01 00 | 2C 01 00 | 01 | E8 03 45 6A 21 3C 9A: M_SP_TB_1, COT
  3, CA 1, IOA 300, SIQ on, 1000 ms, minute 5 + RES1, hour 10 + RES2,
  Monday the 1st, month 12 + RES3, year 26 + RES4. }
procedure TTestChnIec101Asdu.TestReservedTimeBitsIgnored;
var
  H: tIecAsdu;
  O: tIecObject;
begin
  DecodeOne(IecDefaultParams, '1E 01 03 00 01 00 2C 01 00 01 E8 03 45 6A 21 3C 9A', H, O);
  AssertEquals('ms', 1000, O.Time.Msec);
  AssertEquals('minute without RES1', 5, O.Time.Minute);
  AssertFalse('IV', O.Time.Invalid);
  AssertEquals('hour without RES2', 10, O.Time.Hour);
  AssertFalse('SU', O.Time.Summer);
  AssertEquals('day', 1, O.Time.Day);
  AssertEquals('day of week', 1, O.Time.DayOfWeek);
  AssertEquals('month without RES3', 12, O.Time.Month);
  AssertEquals('year without RES4', 26, O.Time.Year);
end;

{ IecSetCot changes the cause and P/N, never T (bit 7 of the COT octet):
  86 (T, activation) -> 87 (T, ACT_CON); 86 -> CA (T, P/N, ACT_TERM 10);
  06 -> 47 (P/N, ACT_CON). }
procedure TTestChnIec101Asdu.TestSetCotKeepsTheTestBit;
var
  B: TBytes;
begin
  B := HexToBytes('2D 01 86 00 01 00 88 13 00 01');
  AssertTrue(IecSetCot(B, Length(B), Cot_ActCon, False));
  AssertEquals('2D 01 87 00 01 00 88 13 00 01', BytesToHex(B, Length(B)));
  B[2] := $86;
  AssertTrue(IecSetCot(B, Length(B), 10, True));
  AssertEquals('T and P/N', '2D 01 CA 00 01 00 88 13 00 01', BytesToHex(B, Length(B)));
  B[2] := $06;
  AssertTrue(IecSetCot(B, Length(B), Cot_ActCon, True));
  AssertEquals('no T', '2D 01 47 00 01 00 88 13 00 01', BytesToHex(B, Length(B)));
  AssertFalse('cause 64', IecSetCot(B, Length(B), 64, False));
end;

initialization
  RegisterTest(TTestChnIec101Asdu);
end.
