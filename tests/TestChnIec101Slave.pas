{ Tests of ChnIec101Slave: the slave on one end of a LOOP pair, a bare
  FT 1.2 primary (ChnFT12Link's FT12Transact, FT12RequestClass) on the
  other, sending ASDUs given as octets and checking the octets that come
  back. Every expected ASDU is worked out by hand from IEC 60870-5-101
  (COT 2 octets, CA 2, IOA 3, little-endian): TI VSQ COT OA CA CA IOA IOA
  IOA element. The balanced case runs a tFT12Balanced as the peer. One
  thread: the primary's Idle steps the slave. }
unit TestChnIec101Slave;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, DateUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop,
  ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnFT12Balanced, ChnIec101Asdu, ChnIec101Slave, TestSupport;

type
  TTestChnIec101Slave = class(TTestCase)
  private
    FM, FS: pChnVirt;
    FLink: tFT12Link;
    FAcd: Boolean;
    procedure Open(Balanced: Boolean = False);
    procedure AddStd;
    procedure Add(Ti: Byte; Ioa: LongWord; Int: LongInt; Group: Byte = 0);
    { user data to the slave (FC 3), ACK expected }
    procedure Send(const Hex: string);
    procedure UpdateInt(Ioa: LongWord; V: LongInt; Quality: Byte = 0);
    procedure Confirmed(const Req: string);
    { class 1 or 2 data: the ASDU in hex, '-' when none; FAcd set }
    function Poll(ClassNo: Byte): string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    S: tIecSlaveStation;
    Cmds, Clocks, Bads: TStringList;
    Accept: Boolean;
    Peer: tFT12Balanced;
    PeerGot: TStringList;
  published
    procedure TestInitRefusesOtherChannels;
    procedure TestAddPointRefusals;
    procedure TestTableGrowsToItsMaximum;
    procedure TestStationInterrogation;
    procedure TestGroupInterrogation;
    procedure TestSpontaneousEventsInClass1WithAcd;
    procedure TestCounterInterrogationFreezeReset;
    procedure TestCommandsDirectAndRefused;
    procedure TestSelectBeforeOperateTimeout;
    procedure TestClockSyncAppliedAsOffset;
    procedure TestReadOneIoa;
    procedure TestNegativeCauses44To47;
    procedure TestMalformedCountedNeverStops;
    procedure TestBalancedInterrogationInOrder;
    procedure TestRandomAsdusNeverStopIt;
    procedure TestResetOfTaggedEventsKeepsConfirmations;
    procedure TestTestBitAndPnBitNeverExecuted;
    procedure TestExecuteMustCarryTheSelection;
    procedure TestQoiCountAndCauseOfCommands;
    procedure TestEndOfInitOctets;
    procedure TestParameterLoadingOctets;
    procedure TestThresholdIsADeadband;
    procedure TestSmoothingFactor;
    procedure TestLimitsReportAZoneChange;
    procedure TestEveryCommandTypeConfirmed;
  end;

implementation

procedure StepSlave(Data: Pointer);
begin
  IecSlaveStep(TTestChnIec101Slave(Data).S);
end;

function OnCmd(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
var
  T: TTestChnIec101Slave;
begin
  T := TTestChnIec101Slave(Data);
  T.Cmds.Add(Format('%s %d %d select=%s', [IecTypeName(H.Ti), O.Ioa, O.Int, BoolToStr(O.Select, True)]));
  Result := T.Accept;
end;

procedure OnClock(Data: Pointer; const T: tIecTime; OffsetMs: Int64);
begin
  TTestChnIec101Slave(Data).Clocks.Add(IntToStr(OffsetMs));
end;

procedure OnBad(Data: Pointer; const Err: ShortString);
begin
  TTestChnIec101Slave(Data).Bads.Add(Err);
end;

function PeerUser(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
begin
  TTestChnIec101Slave(Data).PeerGot.Add(BytesToHex(Buf[0], Len));
  Result := True;
end;

procedure TTestChnIec101Slave.SetUp;
begin
  FM := nil;
  FS := nil;
  Cmds := TStringList.Create;
  Clocks := TStringList.Create;
  Bads := TStringList.Create;
  PeerGot := TStringList.Create;
  Accept := True;
end;

procedure TTestChnIec101Slave.TearDown;
begin
  if FM <> nil then
    Dispose(FM, Done);
  if FS <> nil then
    Dispose(FS, Done);
  FM := nil;
  FS := nil;
  Cmds.Free;
  Clocks.Free;
  Bads.Free;
  PeerGot.Free;
end;

procedure TTestChnIec101Slave.Open(Balanced: Boolean);
var
  Err: string;
  E: ShortString;
begin
  if Balanced then
  begin
    FM := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=OFF DIR=1 NOD=2 DNO=1 LEN=0 NAM=LOOP PAIR=ISL END=1', Err);
    AssertTrue(Err, FM <> nil);
    FS := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=OFF DIR=0 NOD=1 DNO=2 LEN=0 NAM=LOOP PAIR=ISL END=2', Err);
    AssertTrue(Err, FS <> nil);
    AssertEquals(res_Ok, FT12BalancedInit(Peer, FM));
    Peer.OnUserData := @PeerUser;
    Peer.Data := Self;
    Peer.TimeoutMs := 200;
  end
  else
  begin
    FM := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=MASTER NOD=0 DNO=1 LEN=0 NAM=LOOP PAIR=ISL END=1', Err);
    AssertTrue(Err, FM <> nil);
    FS := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=LOOP PAIR=ISL END=2', Err);
    AssertTrue(Err, FS <> nil);
    FT12LinkInit(FLink, 1);
  end;
  AssertEquals(res_Ok, IecSlaveInit(S, FS, IecDefaultParams, 1, E));
  AssertEquals('', E);
  S.OnCommand := @OnCmd;
  S.OnClock := @OnClock;
  S.OnBad := @OnBad;
  S.Data := Self;
end;

procedure TTestChnIec101Slave.Add(Ti: Byte; Ioa: LongWord; Int: LongInt; Group: Byte);
var
  O: tIecObject;
  E: ShortString;
begin
  O := IecObject(Ioa);
  O.Int := Int;
  AssertEquals(E, res_Ok, IecSlaveAddPoint(S, Ti, O, Group, E));
end;

{ The points of lib60870's cs101_slave example, and its command point. }
procedure TTestChnIec101Slave.AddStd;
begin
  Add(M_ME_NB_1, 100, -1);
  Add(M_ME_NB_1, 101, 23);
  Add(M_ME_NB_1, 102, 2300);
  Add(M_SP_NA_1, 104, 1);
  Add(M_SP_NA_1, 105, 0);
  Add(C_SC_NA_1, 5000, 0);
end;

{ A spontaneous update of point Ioa to V (the integer of a scaled value). }
procedure TTestChnIec101Slave.UpdateInt(Ioa: LongWord; V: LongInt; Quality: Byte);
var
  O: tIecObject;
  E: ShortString;
begin
  O := IecObject(0);
  O.Int := V;
  O.Quality := Quality;
  AssertEquals(E, res_Ok, IecSlaveUpdate(S, Ioa, O, True, E));
end;

{ Req (hex) sent, its confirmation polled: the same with COT 7. }
procedure TTestChnIec101Slave.Confirmed(const Req: string);
begin
  Send(Req);
  AssertEquals(Req, Copy(Req, 1, 6) + '07' + Copy(Req, 9, MaxInt), Poll(1));
end;

procedure TTestChnIec101Slave.Send(const Hex: string);
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  B: TBytes;
  I: Integer;
begin
  B := HexToBytes(Hex);
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpLongM;
  Req.FC := FCM_UserDataReply;
  for I := 0 to High(B) do
    Req.Data[I + 1] := B[I];
  AssertEquals('user data ' + Hex, res_Ok, FT12Transact(FM, FLink, Req, cSizeHeadSndMsg + Length(B),
    Rep, RepLen, 200, 1, @StepSlave, Self));
  AssertTrue('ACK for ' + Hex, (Rep.MessType = tpSACK) or (Rep.FC = FCS_Ack));
  FAcd := FLink.Acd;
end;

function TTestChnIec101Slave.Poll(ClassNo: Byte): string;
var
  Rep: tRecRecord;
  RepLen: Word;
begin
  AssertEquals('class ' + IntToStr(ClassNo), res_Ok,
    FT12RequestClass(FM, FLink, ClassNo, Rep, RepLen, 200, 1, @StepSlave, Self));
  FAcd := FLink.Acd;
  if (Rep.MessType = tpLongM) and (Rep.FC = FCS_UserData) then
    Result := BytesToHex(Rep.Data[1], RepLen - cSizeHeadRecMsg)
  else
    Result := '-';
end;

procedure TTestChnIec101Slave.TestInitRefusesOtherChannels;
var
  Err: string;
  E: ShortString;
  P: tIecParams;
begin
  FM := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NAM=LOOP PAIR=ISX END=1', Err);
  AssertEquals(res_BadMessage, IecSlaveInit(S, FM, IecDefaultParams, 1, E));
  AssertTrue(E, Pos('MAS=SLAVE', E) > 0);
  FS := OpenStack(ChnLoop.cName, 'PAIR=ISX END=2', Err);
  AssertEquals(res_WrongLayer, IecSlaveInit(S, FS, IecDefaultParams, 1, E));
  Dispose(FM, Done);
  FM := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NAM=LOOP PAIR=ISY END=1', Err);
  P := IecDefaultParams;
  P.IoaSize := 4;
  AssertEquals(res_AsduParam, IecSlaveInit(S, FM, P, 1, E));
  AssertTrue(E, Pos('IOA size 4', E) > 0);
  P.IoaSize := 3;
  P.CaSize := 1;
  AssertEquals(res_BadParam, IecSlaveInit(S, FM, P, 256, E));
  AssertTrue(E, Pos('common address 256', E) > 0);
  AssertEquals(res_Ok, IecSlaveInit(S, FM, P, 255, E));
end;

procedure TTestChnIec101Slave.TestAddPointRefusals;
var
  O: tIecObject;
  E: ShortString;
  P: tIecParams;
begin
  FS := nil;
  Open;
  O := IecObject(10);
  AssertEquals(res_AsduType, IecSlaveAddPoint(S, M_EI_NA_1, O, 0, E));
  AssertTrue(E, Pos('point 10: type 70', E) = 1);
  AssertEquals(res_AsduType, IecSlaveAddPoint(S, C_IC_NA_1, O, 0, E));
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  AssertEquals(res_BadParam, IecSlaveAddPoint(S, M_DP_NA_1, O, 0, E));
  AssertEquals('point 10: IOA twice', E);
  O := IecObject($1000000);
  AssertEquals(res_AsduIoa, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  AssertTrue(E, Pos('IOA above 16777215', E) > 0);
  O := IecObject(11);
  O.Number := 1.5;                        { a normalized value is below 1 }
  AssertEquals(res_AsduValue, IecSlaveAddPoint(S, M_ME_NA_1, O, 0, E));
  AssertTrue(E, Pos('point 11: ', E) = 1);
  O := IecObject(12);
  O.Int := 2;                             { a single point is 0 or 1 }
  AssertEquals(res_AsduValue, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  AssertEquals(res_BadParam, IecSlaveAddPoint(S, M_IT_NA_1, IecObject(13), 5, E));
  AssertEquals(res_BadParam, IecSlaveAddPoint(S, M_SP_NA_1, IecObject(13), 17, E));
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, IecObject(13), 16, E));
  AssertEquals(res_AsduIoa, IecSlaveUpdate(S, 99, IecObject(0), True, E));
  AssertEquals('no point with IOA 99', E);
  AssertEquals(2, S.PointCount);
  P := IecDefaultParams;
  AssertEquals(3, P.IoaSize);
end;

{ The point table grows as points come (it is no fixed table any more):
  every point of a full table keeps its value, one more is refused, and
  a station set up again starts empty (heaptrc: the old table freed). }
procedure TTestChnIec101Slave.TestTableGrowsToItsMaximum;
var
  O: tIecObject;
  E: ShortString;
  I: LongInt;
begin
  Open;
  IecSlaveReservePoints(S, 10);
  AssertEquals('reserved', 10, Length(S.Points));
  for I := 0 to IecSlaveMaxPoints - 1 do
  begin
    O := IecObject(100 + I);
    O.Int := I mod 30000;
    AssertEquals('point ' + IntToStr(I), res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, O, 0, E));
  end;
  AssertEquals(IecSlaveMaxPoints, S.PointCount);
  for I := 0 to IecSlaveMaxPoints - 1 do
  begin
    AssertEquals('IOA kept', 100 + I, S.Points[I].Obj.Ioa);
    AssertEquals('value kept', I mod 30000, S.Points[I].Obj.Int);
  end;
  AssertEquals(res_Busy, IecSlaveAddPoint(S, M_ME_NB_1, IecObject(5000), 0, E));
  AssertEquals('point 5000: table full (1024 points)', E);
  IecSlaveReservePoints(S, 5000);
  AssertEquals('never beyond the maximum', IecSlaveMaxPoints, Length(S.Points));
  AssertEquals(res_Ok, IecSlaveInit(S, FS, IecDefaultParams, 1, E));
  AssertEquals('set up again: empty', 0, S.PointCount);
  AssertEquals('its table freed', 0, Length(S.Points));
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, IecObject(7), 0, E));
end;

procedure TTestChnIec101Slave.TestStationInterrogation;
begin
  Open;
  AddStd;
  Send('64 01 06 00 01 00 00 00 00 14');
  AssertTrue('ACD after the activation', FAcd);
  AssertEquals('ACT_CON in class 1', '64 01 07 00 01 00 00 00 00 14', Poll(1));
  AssertFalse(FAcd);
  { IOA 100..102 (64 00 00 ..) scaled -1, 23, 2300 (FF FF, 17 00, FC 08), QDS 0 }
  AssertEquals('0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00', Poll(2));
  AssertEquals('01 02 14 00 01 00 68 00 00 01 69 00 00 00', Poll(2));
  AssertEquals('no more class 2', '-', Poll(2));
  AssertTrue('ACT_TERM waits in class 1', FAcd);
  AssertEquals('64 01 0A 00 01 00 00 00 00 14', Poll(1));
  AssertFalse(FAcd);
  AssertEquals('-', Poll(2));
  AssertEquals(1, S.Interrogations);
  AssertEquals(0, S.BadAsdus);
  AssertEquals('commands are not interrogated', 0, Cmds.Count);
end;

procedure TTestChnIec101Slave.TestGroupInterrogation;
begin
  Open;
  Add(M_SP_NA_1, 1, 1, 2);
  Add(M_SP_NA_1, 2, 0);
  Add(M_SP_NA_1, 3, 1, 2);
  Add(M_DP_NA_1, 4, 2, 3);
  { QOI 22 = group 2: COT 22 }
  Send('64 01 06 00 01 00 00 00 00 16');
  AssertEquals('64 01 07 00 01 00 00 00 00 16', Poll(1));
  AssertEquals('01 02 16 00 01 00 01 00 00 01 03 00 00 01', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('64 01 0A 00 01 00 00 00 00 16', Poll(1));
  { QOI 23: the double point, COT 23 }
  Send('64 01 06 00 01 00 00 00 00 17');
  AssertEquals('64 01 07 00 01 00 00 00 00 17', Poll(1));
  AssertEquals('03 01 17 00 01 00 04 00 00 02', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('64 01 0A 00 01 00 00 00 00 17', Poll(1));
  { QOI 19 is no interrogation: negative ACT_CON (7 + $40) }
  Send('64 01 06 00 01 00 00 00 00 13');
  AssertEquals('64 01 47 00 01 00 00 00 00 13', Poll(1));
end;

procedure TTestChnIec101Slave.TestSpontaneousEventsInClass1WithAcd;
var
  O: tIecObject;
  E: ShortString;
  B: TBytes;
  H: tIecAsdu;
  Objs: array[0..0] of tIecObject;
  DT: TDateTime;
begin
  Open;
  AddStd;
  Add(M_ME_TE_1, 200, 7);
  AssertEquals('-', Poll(2));
  AssertFalse(FAcd);
  O := IecObject(0);
  O.Int := 5;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 100, O, True, E));
  AssertEquals('-', Poll(2));
  AssertTrue('ACD for the event', FAcd);
  AssertEquals('0B 01 03 00 01 00 64 00 00 05 00 00', Poll(1));
  AssertFalse(FAcd);
  { without Spontaneous only the table changes }
  O.Int := 6;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 101, O, False, E));
  AssertEquals('-', Poll(2));
  AssertFalse(FAcd);
  { a time-tagged type takes the time of the change }
  O.Int := -3;
  O.Quality := Q_Invalid;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 200, O, True, E));
  B := HexToBytes(Poll(1));
  AssertEquals(res_Ok, IecDecodeAsdu(IecDefaultParams, B, Length(B), H, Objs, E));
  AssertEquals(M_ME_TE_1, H.Ti);
  AssertEquals(Cot_Spontaneous, H.Cot);
  AssertEquals(-3, Objs[0].Int);
  AssertEquals(Q_Invalid, Objs[0].Quality);
  AssertTrue(IecTimeToDateTime(Objs[0].Time, DT));
  AssertTrue('time of the change', Abs(MilliSecondsBetween(DT, Now)) < 2000);
  AssertEquals(2, S.Events);
end;

procedure TTestChnIec101Slave.TestCounterInterrogationFreezeReset;
var
  O: tIecObject;
  E: ShortString;
begin
  Open;
  AddStd;
  Add(M_IT_NA_1, 600, 1000, 1);
  { read, general (QCC 5): COT 37; IOA 600 = 58 02 00, 1000 = E8 03 00 00, seq 0 }
  Send('65 01 06 00 01 00 00 00 00 05');
  AssertEquals('65 01 07 00 01 00 00 00 00 05', Poll(1));
  AssertEquals('0F 01 25 00 01 00 58 02 00 E8 03 00 00 00', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('65 01 0A 00 01 00 00 00 00 05', Poll(1));
  { a station interrogation leaves counters out }
  Send('64 01 06 00 01 00 00 00 00 14');
  AssertEquals('64 01 07 00 01 00 00 00 00 14', Poll(1));
  AssertEquals('0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00', Poll(2));
  AssertEquals('01 02 14 00 01 00 68 00 00 01 69 00 00 00', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('64 01 0A 00 01 00 00 00 00 14', Poll(1));
  { freeze (FRZ 1, QCC $45): confirmed and terminated, no values }
  Send('65 01 06 00 01 00 00 00 00 45');
  AssertEquals('65 01 07 00 01 00 00 00 00 45', Poll(1));
  AssertEquals('65 01 0A 00 01 00 00 00 00 45', Poll(1));
  AssertEquals('-', Poll(2));
  O := IecObject(0);
  O.Int := 2000;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 600, O, False, E));
  { group 1 read (QCC 1, COT 38): the frozen 1000, sequence number 1 }
  Send('65 01 06 00 01 00 00 00 00 01');
  AssertEquals('65 01 07 00 01 00 00 00 00 01', Poll(1));
  AssertEquals('0F 01 26 00 01 00 58 02 00 E8 03 00 00 01', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('65 01 0A 00 01 00 00 00 00 01', Poll(1));
  { freeze with reset (FRZ 2): 2000 frozen, counter 0; group 2 has nothing }
  Send('65 01 06 00 01 00 00 00 00 85');
  AssertEquals('65 01 07 00 01 00 00 00 00 85', Poll(1));
  AssertEquals('65 01 0A 00 01 00 00 00 00 85', Poll(1));
  Send('65 01 06 00 01 00 00 00 00 05');
  AssertEquals('65 01 07 00 01 00 00 00 00 05', Poll(1));
  { 2000 = D0 07, sequence number 2 }
  AssertEquals('0F 01 25 00 01 00 58 02 00 D0 07 00 00 02', Poll(2));
  AssertEquals('-', Poll(2));
  AssertEquals('65 01 0A 00 01 00 00 00 00 05', Poll(1));
  AssertEquals(0, S.Points[IecSlaveFind(S, 600)].Obj.Int);
  AssertEquals(2, S.Points[IecSlaveFind(S, 600)].Obj.Seq);
  { QCC 0 (no group): negative }
  Send('65 01 06 00 01 00 00 00 00 00');
  AssertEquals('65 01 47 00 01 00 00 00 00 00', Poll(1));
end;

procedure TTestChnIec101Slave.TestCommandsDirectAndRefused;
begin
  Open;
  AddStd;
  { C_SC_NA_1 IOA 5000 (88 13 00), SCO 1 = on, execute }
  Send('2D 01 06 00 01 00 88 13 00 01');
  AssertEquals('2D 01 07 00 01 00 88 13 00 01', Poll(1));
  AssertEquals('C_SC_NA_1 5000 1 select=False', Cmds[0]);
  AssertEquals(1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  Accept := False;
  Send('2D 01 06 00 01 00 88 13 00 00');
  AssertEquals('refused: P/N set', '2D 01 47 00 01 00 88 13 00 00', Poll(1));
  AssertEquals(2, Cmds.Count);
  AssertEquals(1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  AssertEquals(1, S.Refused);
  { another IOA, and a double command to the single command point: 47 }
  Send('2D 01 06 00 01 00 89 13 00 01');
  AssertEquals('2D 01 6F 00 01 00 89 13 00 01', Poll(1));
  Send('2E 01 06 00 01 00 88 13 00 01');
  AssertEquals('2E 01 6F 00 01 00 88 13 00 01', Poll(1));
  AssertEquals('the callback saw neither', 2, Cmds.Count);
end;

procedure TTestChnIec101Slave.TestSelectBeforeOperateTimeout;
var
  T0: QWord;
begin
  Open;
  AddStd;
  S.SelectMs := 100;
  { select (S/E bit 7: 81), then execute in time }
  Send('2D 01 06 00 01 00 88 13 00 81');
  AssertEquals('2D 01 07 00 01 00 88 13 00 81', Poll(1));
  AssertTrue(S.SelActive);
  AssertEquals(0, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  Send('2D 01 06 00 01 00 88 13 00 01');
  AssertEquals('2D 01 07 00 01 00 88 13 00 01', Poll(1));
  AssertFalse(S.SelActive);
  AssertEquals('C_SC_NA_1 5000 1 select=True', Cmds[0]);
  AssertEquals('C_SC_NA_1 5000 1 select=False', Cmds[1]);
  { select, wait past the timeout: the execute is refused, not passed on }
  Send('2D 01 06 00 01 00 88 13 00 80');
  AssertEquals('2D 01 07 00 01 00 88 13 00 80', Poll(1));
  T0 := ChMsTick;
  while ChMsTick - T0 < 150 do
    Sleep(10);
  Send('2D 01 06 00 01 00 88 13 00 00');
  AssertEquals('2D 01 47 00 01 00 88 13 00 00', Poll(1));
  AssertEquals(3, Cmds.Count);
  AssertEquals(1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  { select, then deactivation (COT 8): DEACT_CON (9) }
  Send('2D 01 06 00 01 00 88 13 00 81');
  AssertEquals('2D 01 07 00 01 00 88 13 00 81', Poll(1));
  Send('2D 01 08 00 01 00 88 13 00 81');
  AssertEquals('2D 01 09 00 01 00 88 13 00 81', Poll(1));
  AssertFalse(S.SelActive);
end;

procedure TTestChnIec101Slave.TestClockSyncAppliedAsOffset;
var
  T: tIecTime;
  O: tIecObject;
  B: array[0..63] of Byte;
  Len: Word;
  E: ShortString;
  Off: Int64;
begin
  Open;
  AddStd;
  O := IecObject(0);
  O.Time := IecTimeFromDateTime(IncHour(Now, 1));
  AssertEquals(res_Ok, IecEncodeOne(IecDefaultParams, C_CS_NA_1, Cot_Activation, 1, O, B, Len, E));
  Send(BytesToHex(B, Len));
  AssertEquals(1, Clocks.Count);
  Off := StrToInt64(Clocks[0]);
  AssertTrue('offset ' + Clocks[0], Abs(Off - 3600000) < 2000);
  AssertEquals(Off, S.ClockOffsetMs);
  AssertTrue(Abs(MilliSecondsBetween(IecSlaveNow(S), IncHour(Now, 1))) < 2000);
  IecSetCot(B, Len, Cot_ActCon, False);
  AssertEquals('ACT_CON with the time', BytesToHex(B, Len), Poll(1));
  { the events carry the station clock }
  Add(M_SP_TB_1, 700, 0);
  O := IecObject(0);
  O.Int := 1;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 700, O, True, E));
  T := S.Points[IecSlaveFind(S, 700)].Obj.Time;
  AssertEquals('hour of the station clock', HourOf(IncHour(Now, 1)), T.Hour);
  { IOA 700 = BC 02 00, SIQ 1, then the CP56 of the change }
  AssertEquals('1E 01 03 00 01 00 BC 02 00 01', Copy(Poll(1), 1, 29));
  { a time that is no date (month 13): refused }
  O := IecObject(0);
  O.Time := IecTimeFromDateTime(Now);
  IecEncodeOne(IecDefaultParams, C_CS_NA_1, Cot_Activation, 1, O, B, Len, E);
  B[Len - 2] := 13;
  Send(BytesToHex(B, Len));
  IecSetCot(B, Len, Cot_ActCon, True);
  AssertEquals(BytesToHex(B, Len), Poll(1));
  AssertEquals(1, S.ClockSyncs);
end;

procedure TTestChnIec101Slave.TestReadOneIoa;
begin
  Open;
  AddStd;
  { C_RD_NA_1 IOA 104, COT 5: the point with COT 5 }
  Send('66 01 05 00 01 00 68 00 00');
  AssertEquals('01 01 05 00 01 00 68 00 00 01', Poll(1));
  Send('66 01 05 00 01 00 65 00 00');
  AssertEquals('0B 01 05 00 01 00 65 00 00 17 00 00', Poll(1));
  { IOA 999 (E7 03 00): unknown IOA }
  Send('66 01 05 00 01 00 E7 03 00');
  AssertEquals('66 01 6F 00 01 00 E7 03 00', Poll(1));
  { a command point is no monitoring point }
  Send('66 01 05 00 01 00 88 13 00');
  AssertEquals('66 01 6F 00 01 00 88 13 00', Poll(1));
  AssertEquals(2, S.Reads);
end;

procedure TTestChnIec101Slave.TestNegativeCauses44To47;
begin
  Open;
  AddStd;
  { type 200 does not exist: 44 ($6C with P/N) }
  Send('C8 01 06 00 01 00 00 00 00 00');
  AssertEquals('C8 01 6C 00 01 00 00 00 00 00', Poll(1));
  { a monitoring type in control direction: 44 }
  Send('01 01 06 00 01 00 68 00 00 01');
  AssertEquals('01 01 6C 00 01 00 68 00 00 01', Poll(1));
  { an interrogation with COT 3: 45 ($6D) }
  Send('64 01 03 00 01 00 00 00 00 14');
  AssertEquals('64 01 6D 00 01 00 00 00 00 14', Poll(1));
  { common address 2: 46 ($6E), the OA kept }
  Send('64 01 06 07 02 00 00 00 00 14');
  AssertEquals('64 01 6E 07 02 00 00 00 00 14', Poll(1));
  { a command to an IOA the table does not have: 47 ($6F) }
  Send('31 01 06 00 01 00 10 27 00 10 00 00');
  AssertEquals('31 01 6F 00 01 00 10 27 00 10 00 00', Poll(1));
  { the broadcast common address is taken }
  Send('68 01 06 00 FF FF 00 00 00 AA 55');
  AssertEquals('68 01 07 00 FF FF 00 00 00 AA 55', Poll(1));
  { but not for a command or a read }
  Send('2D 01 06 00 FF FF 88 13 00 01');
  AssertEquals('2D 01 6E 00 FF FF 88 13 00 01', Poll(1));
  Send('66 01 05 00 FF FF 68 00 00');
  AssertEquals('66 01 6E 00 FF FF 68 00 00', Poll(1));
  AssertEquals(0, Cmds.Count);
  AssertEquals(7, S.Negatives);
  AssertEquals(0, S.BadAsdus);
end;

procedure TTestChnIec101Slave.TestMalformedCountedNeverStops;
begin
  Open;
  AddStd;
  Send('64 01 06');                                 { shorter than the identifier }
  Send('64 01 06 00 01 00 00 00 00 14 00');         { one octet too many for C_IC_NA_1 }
  Send('2D 00 06 00 01 00 88 13 00');               { no object }
  AssertEquals(3, S.BadAsdus);
  AssertEquals(3, Bads.Count);
  AssertTrue(S.LastBad, S.LastBad <> '');
  AssertEquals('nothing answered', '-', Poll(1));
  AssertFalse(FAcd);
  { and the slave goes on }
  Send('64 01 06 00 01 00 00 00 00 14');
  AssertEquals('64 01 07 00 01 00 00 00 00 14', Poll(1));
  AssertEquals(4, S.Asdus);
end;

procedure TTestChnIec101Slave.TestBalancedInterrogationInOrder;
var
  B: TBytes;
  T0: QWord;
  I: Integer;
  O: tIecObject;
  E: ShortString;
begin
  Open(True);
  AddStd;
  for I := 1 to 20 do
    Add(M_SP_NA_1, 1000 + I, I and 1);
  B := HexToBytes('64 01 06 00 01 00 00 00 00 14');
  T0 := ChMsTick;
  repeat
    FT12BalancedStep(Peer);
    IecSlaveStep(S);
    if (Peer.State = bsAvailable) and (Length(B) > 0) then
    begin
      AssertEquals(res_Ok, FT12BalancedSend(Peer, @B[0], Length(B), True));
      B := nil;
    end;
    if not IecSlaveStep(S) then
      Sleep(1);
  until (PeerGot.Count >= 5) or (ChMsTick - T0 > 5000);
  AssertEquals('ACT_CON, 3 ASDUs, ACT_TERM: ' + PeerGot.Text, 5, PeerGot.Count);
  AssertEquals('64 01 07 00 01 00 00 00 00 14', PeerGot[0]);
  AssertEquals('0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00', PeerGot[1]);
  AssertEquals('01 02 14 00 01 00 68 00 00 01 69 00 00 00', PeerGot[2]);
  { 20 single points in one ASDU: 1001 = E9 03 00 on, 1002 = EA 03 00 off ... }
  AssertEquals('01 14 14 00 01 00 E9 03 00 01 EA 03 00 00 EB 03 00 01',
    Copy(PeerGot[3], 1, Length('01 14 14 00 01 00 E9 03 00 01 EA 03 00 00 EB 03 00 01')));
  AssertEquals((6 + 20 * 4) * 3, Length(PeerGot[3]) + 1);
  AssertEquals('64 01 0A 00 01 00 00 00 00 14', PeerGot[4]);
  { a spontaneous change goes out as user data at once }
  O := IecObject(0);
  O.Int := 7;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 101, O, True, E));
  T0 := ChMsTick;
  repeat
    FT12BalancedStep(Peer);
    if not IecSlaveStep(S) then
      Sleep(1);
  until (PeerGot.Count >= 6) or (ChMsTick - T0 > 3000);
  AssertEquals('0B 01 03 00 01 00 65 00 00 07 00 00', PeerGot[5]);
  AssertEquals(0, S.BadAsdus);
  AssertEquals(S.Link.Bal.State = bsAvailable, True);
end;

{ 400 random ASDUs (a known type or not, any length): each is counted as
  malformed or answered, nothing is raised, and the slave then answers an
  interrogation as before. }
procedure TTestChnIec101Slave.TestRandomAsdusNeverStopIt;
const
  Types: array[0..9] of Byte = (45, 46, 48, 50, 58, 100, 101, 102, 103, 200);
var
  I, J, N: Integer;
  Hex: string;
  Answers: Integer;
begin
  Open;
  AddStd;
  RandSeed := 20261201;
  Answers := 0;
  for I := 1 to 400 do
  begin
    N := 1 + Random(24);
    Hex := IntToHex(Types[Random(Length(Types))], 2);
    for J := 2 to N do
      if (J = 5) and (Random(2) = 0) then
        Hex := Hex + ' 01'                      { often our common address }
      else
        Hex := Hex + ' ' + IntToHex(Random(256), 2);
    Send(Hex);
    while Poll(1) <> '-' do
      Inc(Answers);
    AssertFalse('nothing left for class 1', FAcd);
  end;
  AssertEquals('every ASDU counted', 400, S.Asdus);
  AssertTrue('some malformed', S.BadAsdus > 0);
  AssertTrue('some answered', Answers > 0);
  { the interrogations the random ASDUs started are finished by now (class 2) }
  while Poll(2) <> '-' do ;
  while Poll(1) <> '-' do ;
  Send('64 01 06 00 01 00 00 00 00 14');
  AssertEquals('64 01 07 00 01 00 00 00 00 14', Poll(1));
  AssertEquals('0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00', Poll(2));
end;

{ QRP 2 is the reset of pending information with time tag (IEC
  60870-5-101 7.2.6.27): the time-tagged events waiting go; the
  confirmation of a command executed before it stays (its loss would leave
  the master without ACT_CON for a command the station executed), and so
  do untagged events. }
procedure OnResetProc(Data: Pointer; Qrp: Byte);
begin
  TTestChnIec101Slave(Data).Cmds.Add('reset ' + IntToStr(Qrp));
end;

{ M_EI_NA_1 (70 = $46), VSQ 1, COT 4 (2 octets), CA 1, IOA 0, COI:
  0 local power on, 1 local manual reset (+$80 after a local parameter
  change), 2 remote reset - after C_RP_NA_1 (105 = $69) QRP 1, whose
  ACT_CON comes first and which drops what was waiting. }
procedure TTestChnIec101Slave.TestEndOfInitOctets;
var
  O: tIecObject;
  E: ShortString;
begin
  Open;
  AddStd;
  S.OnReset := @OnResetProc;
  AssertEquals('nothing before the program says so', '-', Poll(1));
  IecSlaveEndOfInit(S, Coi_PowerOn);
  AssertEquals('after a start', '46 01 04 00 01 00 00 00 00 00', Poll(1));
  AssertFalse(FAcd);
  IecSlaveEndOfInit(S, Coi_ManualReset or Coi_LocalChange);
  AssertEquals('manual reset, local change', '46 01 04 00 01 00 00 00 00 81', Poll(1));
  O := IecObject(0);
  O.Int := 0;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 104, O, True, E));   { an event waits }
  Send('69 01 06 00 01 00 00 00 00 01');
  AssertEquals('the reset''s ACT_CON', '69 01 07 00 01 00 00 00 00 01', Poll(1));
  AssertTrue('more to come', FAcd);
  AssertEquals('remote reset', '46 01 04 00 01 00 00 00 00 02', Poll(1));
  AssertFalse('the event went with the reset', FAcd);
  AssertEquals('-', Poll(1));
  AssertEquals('reset 1', Cmds[0]);
  AssertEquals(3, S.EndOfInits);
end;

{ P_ME_NB_1 (111 = $6F) SVA QPM, P_ME_NA_1 (110 = $6E) NVA QPM, P_ME_NC_1
  (112 = $70) R32 QPM, P_AC_NA_1 (113 = $71) QPA; COT 6 / 8, mirrored with
  7 / 9; P/N is bit 6 of the COT octet (7 + $40 = $47, 47 + $40 = $6F).
  IOA 101 = 65 00 00 (scaled), 200 = C8 00 00 (float). }
procedure TTestChnIec101Slave.TestParameterLoadingOctets;
var
  O: tIecObject;
  E: ShortString;
begin
  Open;
  AddStd;
  O := IecObject(200);
  O.Number := 1.5;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NC_1, O, 0, E));
  { threshold 10 (0A 00, KPA 1) for the scaled value 101 }
  Send('6F 01 06 00 01 00 65 00 00 0A 00 01');
  AssertEquals('ACT_CON', '6F 01 07 00 01 00 65 00 00 0A 00 01', Poll(1));
  { a normalized parameter for a scaled value: no such object (COT 47) }
  Send('6E 01 06 00 01 00 65 00 00 00 10 01');
  AssertEquals('COT 47', '6E 01 6F 00 01 00 65 00 00 00 10 01', Poll(1));
  { KPA 5 is reserved: negative ACT_CON }
  Send('6F 01 06 00 01 00 65 00 00 0A 00 05');
  AssertEquals('KPA 5', '6F 01 47 00 01 00 65 00 00 0A 00 05', Poll(1));
  { float 0.5 (3F000000) as the threshold of 200, loaded not in operation (POP, $81) }
  Send('70 01 06 00 01 00 C8 00 00 00 00 00 3F 81');
  AssertEquals('float ACT_CON', '70 01 07 00 01 00 C8 00 00 00 00 00 3F 81', Poll(1));
  { activation of the object's parameters (QPA 2), then deactivation }
  Send('71 01 06 00 01 00 C8 00 00 02');
  AssertEquals('P_AC ACT_CON', '71 01 07 00 01 00 C8 00 00 02', Poll(1));
  Send('71 01 08 00 01 00 65 00 00 02');
  AssertEquals('P_AC DEACT_CON', '71 01 09 00 01 00 65 00 00 02', Poll(1));
  { cyclic transmission (QPA 3) is not offered }
  Send('71 01 06 00 01 00 65 00 00 03');
  AssertEquals('QPA 3', '71 01 47 00 01 00 65 00 00 03', Poll(1));
  { a P_ME_NB_1 with COT 3 is no activation: COT 45 ($2D + $40 = $6D) }
  Send('6F 01 03 00 01 00 65 00 00 0A 00 01');
  AssertEquals('COT 45', '6F 01 6D 00 01 00 65 00 00 0A 00 01', Poll(1));
  AssertEquals(4, S.Parameters);
  { a station interrogation reports them after the points, COT 20 ($14),
    POP set for 101 (deactivated) and not for 200 (activated) }
  Send('64 01 06 00 01 00 00 00 00 14');
  AssertEquals('64 01 07 00 01 00 00 00 00 14', Poll(1));
  AssertEquals('0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00', Poll(2));
  AssertEquals('01 02 14 00 01 00 68 00 00 01 69 00 00 00', Poll(2));
  AssertEquals('0D 01 14 00 01 00 C8 00 00 00 00 C0 3F 00', Poll(2));
  AssertEquals('101: threshold, not in operation', '6F 01 14 00 01 00 65 00 00 0A 00 81', Poll(2));
  AssertEquals('200: threshold in operation', '70 01 14 00 01 00 C8 00 00 00 00 00 3F 01', Poll(2));
  AssertEquals('none left', '-', Poll(2));
  AssertTrue('ACT_TERM waits', FAcd);
  AssertEquals('ACT_TERM', '64 01 0A 00 01 00 00 00 00 14', Poll(1));
end;

{ A threshold in operation is a deadband around the value reported last:
  M_ME_NB_1 (11 = $0B) SVA QDS. }
procedure TTestChnIec101Slave.TestThresholdIsADeadband;

  procedure Update(V: LongInt; Quality: Byte = 0);
  begin
    UpdateInt(101, V, Quality);
  end;

begin
  Open;
  AddStd;
  Send('6F 01 06 00 01 00 65 00 00 0A 00 01');
  AssertEquals('6F 01 07 00 01 00 65 00 00 0A 00 01', Poll(1));
  Update(30);
  AssertEquals('the first change', '0B 01 03 00 01 00 65 00 00 1E 00 00', Poll(1));
  Update(35);
  AssertEquals('5 from 30: within 10', '-', Poll(1));
  Update(39);
  AssertEquals('9 from 30: within', '-', Poll(1));
  Update(40);
  AssertEquals('10 from 30: reported', '0B 01 03 00 01 00 65 00 00 28 00 00', Poll(1));
  Update(41, Q_Invalid);
  AssertEquals('a quality change is always reported', '0B 01 03 00 01 00 65 00 00 29 00 80', Poll(1));
  AssertEquals(2, S.Suppressed);
  { deactivated (P_AC_NA_1 QPA 2, COT 8): every change again }
  Send('71 01 08 00 01 00 65 00 00 02');
  AssertEquals('71 01 09 00 01 00 65 00 00 02', Poll(1));
  Update(42, Q_Invalid);
  AssertEquals('0B 01 03 00 01 00 65 00 00 2A 00 80', Poll(1));
  { activated again for all loaded parameters (QPA 1, IOA 0) }
  Send('71 01 06 00 01 00 00 00 00 01');
  AssertEquals('71 01 07 00 01 00 00 00 00 01', Poll(1));
  Update(43, Q_Invalid);
  AssertEquals('-', Poll(1));
end;

{ P_ME_NB_1 (6F) to IOA 101 (65 00 00, scaled, 23): smoothing factor
  (KPA 2) 50 per cent = 32 00. Each spontaneous update moves the value
  half way: 23 -> 103 gives 63 (3F 00), 83 (53 00), 93 (5D 00); the table
  keeps it (a read answers 93). 0 % and 101 % (65 00) are refused
  (negative ACT_CON, 47); 100 % (64 00) is no smoothing. }
procedure TTestChnIec101Slave.TestSmoothingFactor;
var
  E: ShortString;
  O: tIecObject;

  procedure Update(V: LongInt);
  begin
    UpdateInt(101, V);
  end;

begin
  Open;
  AddStd;
  Confirmed('6F 01 06 00 01 00 65 00 00 32 00 02');
  Update(103);
  AssertEquals('half way from 23', '0B 01 03 00 01 00 65 00 00 3F 00 00', Poll(1));
  Update(103);
  AssertEquals('0B 01 03 00 01 00 65 00 00 53 00 00', Poll(1));
  Update(103);
  AssertEquals('0B 01 03 00 01 00 65 00 00 5D 00 00', Poll(1));
  { C_RD_NA_1 (66, COT 5) of IOA 101: the smoothed value }
  Send('66 01 05 00 01 00 65 00 00');
  AssertEquals('0B 01 05 00 01 00 65 00 00 5D 00 00', Poll(1));
  Send('6F 01 06 00 01 00 65 00 00 00 00 02');
  AssertEquals('0 %', '6F 01 47 00 01 00 65 00 00 00 00 02', Poll(1));
  Send('6F 01 06 00 01 00 65 00 00 65 00 02');
  AssertEquals('101 %', '6F 01 47 00 01 00 65 00 00 65 00 02', Poll(1));
  { not in operation (P_AC_NA_1 QPA 2, COT 8): the value as given }
  Send('71 01 08 00 01 00 65 00 00 02');
  AssertEquals('71 01 09 00 01 00 65 00 00 02', Poll(1));
  Update(-7);
  AssertEquals('0B 01 03 00 01 00 65 00 00 F9 FF 00', Poll(1));
  { 100 %, in operation: every value as it is }
  Confirmed('6F 01 06 00 01 00 65 00 00 64 00 02');
  Update(1000);
  AssertEquals('0B 01 03 00 01 00 65 00 00 E8 03 00', Poll(1));
  { a float (M_ME_NC_1, IOA 110 = 6E 00 00, 0): P_ME_NC_1 (70) takes k
    itself - 1.5 (00 00 C0 3F) refused, 0.25 (00 00 80 3E) taken; 8.0
    then gives 2.0 (00 00 00 40), 3.5 (00 00 60 40) }
  Add(M_ME_NC_1, 110, 0);
  Send('70 01 06 00 01 00 6E 00 00 00 00 C0 3F 02');
  AssertEquals('70 01 47 00 01 00 6E 00 00 00 00 C0 3F 02', Poll(1));
  Confirmed('70 01 06 00 01 00 6E 00 00 00 00 80 3E 02');
  O := IecObject(0);
  O.Number := 8.0;
  AssertEquals(E, res_Ok, IecSlaveUpdate(S, 110, O, True, E));
  AssertEquals('0D 01 03 00 01 00 6E 00 00 00 00 00 40 00', Poll(1));
  AssertEquals(E, res_Ok, IecSlaveUpdate(S, 110, O, True, E));
  AssertEquals('0D 01 03 00 01 00 6E 00 00 00 00 60 40 00', Poll(1));
end;

{ IOA 102 (66 00 00, scaled 2300): threshold 300 (2C 01, KPA 1), low
  limit 2300 (FC 08, KPA 3), high limit 2500 (C4 09, KPA 4). Within the
  threshold a change is reported only when the value goes into another
  zone (below 2300, 2300..2500, above 2500) than the one reported last. }
procedure TTestChnIec101Slave.TestLimitsReportAZoneChange;

  procedure Update(V: LongInt);
  begin
    UpdateInt(102, V);
  end;

begin
  Open;
  AddStd;
  Confirmed('6F 01 06 00 01 00 66 00 00 2C 01 01');
  Confirmed('6F 01 06 00 01 00 66 00 00 FC 08 03');
  Confirmed('6F 01 06 00 01 00 66 00 00 C4 09 04');
  Update(2400);
  AssertEquals('the first change: 2400 = 60 09', '0B 01 03 00 01 00 66 00 00 60 09 00', Poll(1));
  Update(2450);
  AssertEquals('within, between the limits', '-', Poll(1));
  Update(2550);
  AssertEquals('150 from 2400, above the high limit: F6 09', '0B 01 03 00 01 00 66 00 00 F6 09 00', Poll(1));
  Update(2600);
  AssertEquals('still above', '-', Poll(1));
  Update(2450);
  AssertEquals('back between: 92 09', '0B 01 03 00 01 00 66 00 00 92 09 00', Poll(1));
  Update(2290);
  AssertEquals('160 from 2450, below the low limit: F2 08', '0B 01 03 00 01 00 66 00 00 F2 08 00', Poll(1));
  Update(2300);
  AssertEquals('the limit itself is between: FC 08', '0B 01 03 00 01 00 66 00 00 FC 08 00', Poll(1));
  Update(2320);
  AssertEquals('-', Poll(1));
  AssertEquals(3, S.Suppressed);
  { out of operation: every change, limits or not }
  Send('71 01 08 00 01 00 66 00 00 02');
  AssertEquals('71 01 09 00 01 00 66 00 00 02', Poll(1));
  Update(2330);
  AssertEquals('0B 01 03 00 01 00 66 00 00 1A 09 00', Poll(1));
end;

{ The command types the other tests leave out, each to a point of its own
  type, confirmed by mirroring with COT 7. IOA 5002.. = 8A 13 00 ...;
  RCO 02 higher; NVA 0.5 = 00 40, QOS 0; SVA 100 = 64 00; R32 1.5 =
  00 00 C0 3F; BSI 12345678 low first; DCO 02 on; CP56 2026-01-02
  03:04:05.000 = 88 13 04 03 02 01 1A. }
procedure TTestChnIec101Slave.TestEveryCommandTypeConfirmed;

  procedure Check(const Req: string);
  begin
    Send(Req);
    AssertEquals(Req, Copy(Req, 1, 6) + '07' + Copy(Req, 9, MaxInt), Poll(1));
  end;

begin
  Open;
  Add(C_RC_NA_1, 5002, 0);
  Add(C_SE_NA_1, 5003, 0);
  Add(C_SE_NC_1, 5004, 0);
  Add(C_BO_NA_1, 5005, 0);
  Add(C_SE_NB_1, 5006, 0);
  Add(C_DC_NA_1, 5007, 0);
  Add(C_BO_TA_1, 5008, 0);
  Add(C_SE_TC_1, 5009, 0);
  Check('2F 01 06 00 01 00 8A 13 00 02');
  Check('30 01 06 00 01 00 8B 13 00 00 40 00');
  Check('32 01 06 00 01 00 8C 13 00 00 00 C0 3F 00');
  Check('33 01 06 00 01 00 8D 13 00 78 56 34 12');
  Check('31 01 06 00 01 00 8E 13 00 64 00 00');
  Check('2E 01 06 00 01 00 8F 13 00 02');
  Check('40 01 06 00 01 00 90 13 00 78 56 34 12 88 13 04 03 02 01 1A');
  Check('3F 01 06 00 01 00 91 13 00 00 00 C0 3F 00 88 13 04 03 02 01 1A');
  AssertEquals(8, Cmds.Count);
end;

procedure TTestChnIec101Slave.TestResetOfTaggedEventsKeepsConfirmations;
var
  O: tIecObject;
  E: ShortString;
begin
  Open;
  AddStd;
  Add(M_SP_TB_1, 300, 0);
  Add(C_SC_TA_1, 5001, 0);
  O := IecObject(0);
  O.Int := 1;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 300, O, True, E));   { tagged event }
  AssertEquals(res_Ok, IecSlaveUpdate(S, 105, O, True, E));   { untagged event }
  Send('2D 01 06 00 01 00 88 13 00 01');                      { C_SC on }
  { C_SC_TA_1 (58 = $3A) IOA 5001 on, CP56Time2a 2026-01-02 03:04:05.000:
    ms 5000 = 88 13, min 04, hour 03, day 02, month 01, year 1A }
  Send('3A 01 06 00 01 00 89 13 00 01 88 13 04 03 02 01 1A');
  { C_RP_NA_1 (105 = $69), QRP 2 }
  Send('69 01 06 00 01 00 00 00 00 02');
  AssertEquals('the untagged event (IOA 105 = 69 00 00, SIQ 1)', '01 01 03 00 01 00 69 00 00 01', Poll(1));
  AssertEquals('the command''s ACT_CON', '2D 01 07 00 01 00 88 13 00 01', Poll(1));
  AssertEquals('a time-tagged command''s ACT_CON', '3A 01 07 00 01 00 89 13 00 01 88 13 04 03 02 01 1A', Poll(1));
  AssertEquals('the reset''s ACT_CON', '69 01 07 00 01 00 00 00 00 02', Poll(1));
  AssertFalse(FAcd);
  AssertEquals('-', Poll(1));
  AssertEquals('C_SC_NA_1 5000 1 select=False', Cmds[0]);
end;

{ T = 1 (test, IEC 60870-5-101 7.2.3): not meant to change the process -
  refused, never handed to the program, the T bit mirrored. P/N = 1 in
  control direction: no cause carries it - COT 45, negative. }
procedure TTestChnIec101Slave.TestTestBitAndPnBitNeverExecuted;
begin
  Open;
  AddStd;
  { COT 6 + T ($80) = $86: negative ACT_CON $80 + $40 + 7 = $C7 }
  Send('2D 01 86 00 01 00 88 13 00 01');
  AssertEquals('2D 01 C7 00 01 00 88 13 00 01', Poll(1));
  { a select with T = 1, and a deactivation with T = 1 ($88 -> $C9) }
  Send('2D 01 86 00 01 00 88 13 00 81');
  AssertEquals('2D 01 C7 00 01 00 88 13 00 81', Poll(1));
  AssertFalse(S.SelActive);
  Send('2D 01 88 00 01 00 88 13 00 81');
  AssertEquals('2D 01 C9 00 01 00 88 13 00 81', Poll(1));
  { P/N set ($46): COT 45 with P/N = $6D }
  Send('2D 01 46 00 01 00 88 13 00 01');
  AssertEquals('2D 01 6D 00 01 00 88 13 00 01', Poll(1));
  Send('64 01 46 00 01 00 00 00 00 14');
  AssertEquals('64 01 6D 00 01 00 00 00 00 14', Poll(1));
  AssertEquals('the program saw none', 0, Cmds.Count);
  AssertEquals(0, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  AssertEquals(0, S.Interrogations);
  { the same command without them is executed }
  Send('2D 01 06 00 01 00 88 13 00 01');
  AssertEquals('2D 01 07 00 01 00 88 13 00 01', Poll(1));
  AssertEquals(1, Cmds.Count);
end;

{ Select and execute (IEC 60870-5-5 6.8): the execute must be the command
  selected - another value or qualifier is refused and ends the selection. }
procedure TTestChnIec101Slave.TestExecuteMustCarryTheSelection;
begin
  Open;
  AddStd;
  Send('2D 01 06 00 01 00 88 13 00 81');          { select on }
  AssertEquals('2D 01 07 00 01 00 88 13 00 81', Poll(1));
  Send('2D 01 06 00 01 00 88 13 00 00');          { execute off }
  AssertEquals('2D 01 47 00 01 00 88 13 00 00', Poll(1));
  AssertFalse(S.SelActive);
  Send('2D 01 06 00 01 00 88 13 00 81');          { select on, QU 0 }
  AssertEquals('2D 01 07 00 01 00 88 13 00 81', Poll(1));
  Send('2D 01 06 00 01 00 88 13 00 05');          { execute on, QU 1 (short pulse) }
  AssertEquals('2D 01 47 00 01 00 88 13 00 05', Poll(1));
  AssertEquals('only the selects reached the program', 2, Cmds.Count);
  AssertEquals(0, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  Send('2D 01 06 00 01 00 88 13 00 81');
  AssertEquals('2D 01 07 00 01 00 88 13 00 81', Poll(1));
  Send('2D 01 06 00 01 00 88 13 00 01');          { the one selected }
  AssertEquals('2D 01 07 00 01 00 88 13 00 01', Poll(1));
  AssertEquals('C_SC_NA_1 5000 1 select=False', Cmds[3]);
  AssertEquals(1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  AssertEquals(2, S.Refused);
end;

{ IEC 60870-5-101 7.2.6.22: QOI 20 station, 21..36 groups 1..16; 37 is
  not one (negative ACT_CON, $47). A command carries one object (7.3.2):
  two are refused as unknown type (44, $6C), nothing executed. A command
  comes with cause 6 or 8: COT 7 (ACT_CON, the slave's own) is an unknown
  cause (45, $6D). QOI 36 is taken (positive ACT_CON). }
procedure TTestChnIec101Slave.TestQoiCountAndCauseOfCommands;
begin
  Open;
  AddStd;
  Send('64 01 06 00 01 00 00 00 00 25');
  AssertEquals('QOI 37', '64 01 47 00 01 00 00 00 00 25', Poll(1));
  Send('2D 02 06 00 01 00 88 13 00 01 89 13 00 01');
  AssertEquals('two objects', '2D 02 6C 00 01 00 88 13 00 01 89 13 00 01', Poll(1));
  Send('2D 01 07 00 01 00 88 13 00 01');
  AssertEquals('COT 7', '2D 01 6D 00 01 00 88 13 00 01', Poll(1));
  AssertEquals('nothing executed', 0, Cmds.Count);
  AssertEquals(0, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  AssertEquals(0, S.Interrogations);
  Send('64 01 06 00 01 00 00 00 00 24');
  AssertEquals('QOI 36', '64 01 07 00 01 00 00 00 00 24', Poll(1));
end;

initialization
  RegisterTest(TTestChnIec101Slave);
end.
