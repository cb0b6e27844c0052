{ Station services between the library's slave and master: parameter
  loading and activation (P_ME_NA/NB/NC_1, P_AC_NA_1: the master's calls,
  blocking and stepped, the slave's deadband), and end of initialisation
  (M_EI_NA_1, COT 4), over FT 1.2 unbalanced and balanced (LOOP) and over IEC 104
  (loopback TCP): the slave sends it when the program says it has
  initialised (COI 0 after a start) and after a general reset of process
  (COI 2); the master reports it (OnEndOfInit) and, unless told not to,
  interrogates the slave (station interrogation, and counters when
  CiAfterInit is set); a program's own interrogation meanwhile takes the
  master's over. The octets of M_EI_NA_1 itself are checked by hand in
  TestChnIec101Slave.TestEndOfInitOctets. One thread: the master's Idle
  steps the slave. }
unit TestIecStation;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnLoop, ChnFT1_2,
  ChnIec104, ChnIec101Asdu, ChnIec101Master, ChnIec101Slave, ChnWait, TestSupport;

type
  tPairKind = (pkUnbalanced, pkBalanced, pk104);
  TTestIecStation = class;
  TFunc = function(T: TTestIecStation): Boolean;

  TTestIecStation = class(TTestCase)
  private
    SChn, MChn: pChnVirt;
    Kind: tPairKind;
    Addr: Word;          { the slave's link address as the master names it }
    procedure OpenPair(K: tPairKind);
    procedure StepSlave;
    procedure PollUntil(const What: string; Ms: LongInt; Cond: TFunc);
    procedure StartAndInterrogate(K: tPairKind);
    procedure RemoteResetInterrogatesAgain(K: tPairKind);
    procedure InterrogationFillsEachAsdu(K: tPairKind; const Want: array of string);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    M: tIecMaster;
    S: tIecSlaveStation;
    Objects, Inits, Answers: TStringList;
    Resets, Commands: Integer;
  published
    procedure TestUnbalancedStartThenInterrogation;
    procedure TestBalancedStartThenInterrogation;
    procedure Test104StartThenInterrogation;
    procedure TestUnbalancedRemoteReset;
    procedure Test104RemoteReset;
    procedure TestCounterInterrogationToo;
    procedure TestToldNotToInterrogate;
    procedure TestProgramInterrogationTakesItOver;
    procedure TestParametersUnbalanced;
    procedure TestParameters104Stepped;
    procedure TestParameterDeactivation;
    procedure TestEveryCommandType104;
    procedure TestInterrogationFillsEachFT12Frame;
    procedure TestInterrogationFillsEachBalancedFrame;
    procedure TestInterrogationFillsEach104Apdu;
  end;

implementation

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIecStation(Data).Objects.Add(IecTypeName(H.Ti) + ' COT ' + IntToStr(H.Cot) +
    ' IOA ' + IntToStr(O.Ioa));
end;

procedure OnInit(Data: Pointer; Addr, Ca: Word; Coi: Byte);
begin
  TTestIecStation(Data).Inits.Add(Format('slave %d CA %d COI %d', [Addr, Ca, Coi]));
end;

function AcceptAll(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
begin
  Inc(TTestIecStation(Data).Commands);
  Result := True;
end;

procedure OnReset(Data: Pointer; Qrp: Byte);
begin
  Inc(TTestIecStation(Data).Resets);
end;

{ the interrogation's answers (COT 20) the slave hands to its link:
  type, VSQ and length }
procedure OnSlaveAsdu(Data: Pointer; Sent: Boolean; Buf: PByte; Len: Word);
begin
  if Sent and (Len > 2) and (Buf[2] = Cot_Interrogated) then
    TTestIecStation(Data).Answers.Add(Format('%.2X %.2X: %d', [Buf[0], Buf[1], Len]));
end;

procedure IdleSlave(Data: Pointer);
begin
  TTestIecStation(Data).StepSlave;
end;

procedure TTestIecStation.StepSlave;
begin
  IecSlaveStep(S);
  ChnWaitAny(2);
end;

procedure TTestIecStation.SetUp;
begin
  Objects := TStringList.Create;
  Inits := TStringList.Create;
  Answers := TStringList.Create;
  SChn := nil;
  MChn := nil;
  Resets := 0;
end;

procedure TTestIecStation.TearDown;
begin
  if MChn <> nil then Dispose(MChn, Done);
  if SChn <> nil then Dispose(SChn, Done);
  Objects.Free;
  Inits.Free;
  Answers.Free;
end;

procedure TTestIecStation.OpenPair(K: tPairKind);
var
  Err: string;
  E: ShortString;
  O: tIecObject;
  Port: Word;
begin
  Kind := K;
  Addr := 1;
  if K = pk104 then
    Addr := 0;        { no link address: the connection's peer }
  case K of
    pkUnbalanced:
      begin
        SChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=LOOP PAIR=EOI END=2', Err);
        MChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=ON MAS=MASTER NOD=0 DNO=1 LEN=0 NAM=LOOP PAIR=EOI END=1', Err);
      end;
    pkBalanced:
      begin
        SChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=OFF DIR=0 NOD=1 DNO=2 LEN=0 NAM=LOOP PAIR=EOB END=2', Err);
        MChn := OpenStack(ChnFT1_2.cName, 'NAM=FT1_2 MS=OFF DIR=1 NOD=2 DNO=1 LEN=0 NAM=LOOP PAIR=EOB END=1', Err);
      end;
    pk104:
      begin
        SChn := OpenListening('IEC104', 'NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0', Port);
        MChn := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port) +
          ' RECON=200', Err);
      end;
  end;
  AssertNotNull(Err, SChn);
  AssertNotNull(Err, MChn);
  AssertEquals('slave', res_Ok, IecSlaveInit(S, SChn, IecDefaultParams, 1, E));
  S.OnReset := @OnReset;
  S.Data := Self;
  O := IecObject(100);
  O.Int := 1;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  O := IecObject(300);
  O.Int := 1234;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_IT_NA_1, O, 0, E));
  AssertEquals('master', res_Ok, IecMasterInit(M, MChn, IecDefaultParams));
  if K = pkUnbalanced then
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
  M.CommandMs := 3000;
  M.OnObject := @OnObj;
  M.OnEndOfInit := @OnInit;
  M.Data := Self;
  M.Idle := @IdleSlave;
  M.IdleData := Self;
end;

procedure TTestIecStation.PollUntil(const What: string; Ms: LongInt; Cond: TFunc);
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(Ms);
  while not Cond(Self) and (ChMsTick < Deadline) do
    IecPollFor(M, 20);
  AssertTrue(What + ' within ' + IntToStr(Ms) + ' ms; objects: ' + Objects.CommaText +
    ' inits: ' + Inits.CommaText, Cond(Self));
end;

function Interrogated(T: TTestIecStation): Boolean;
begin
  Result := (T.Objects.IndexOf('C_IC_NA_1 COT 10 IOA 0') >= 0) and IecCommandDone(T.M);
end;

function TwoInterrogations(T: TTestIecStation): Boolean;
begin
  Result := (T.S.Interrogations = 2) and IecCommandDone(T.M) and
    (T.Objects.IndexOf('C_IC_NA_1 COT 10 IOA 0') <> T.Objects.Count - 1) and
    (T.Objects[T.Objects.Count - 1] = 'C_IC_NA_1 COT 10 IOA 0');
end;

function CountersRead(T: TTestIecStation): Boolean;
begin
  Result := (T.Objects.IndexOf('C_CI_NA_1 COT 10 IOA 0') >= 0) and IecCommandDone(T.M);
end;

function InitSeen(T: TTestIecStation): Boolean;
begin
  Result := T.Inits.Count > 0;
end;

procedure TTestIecStation.StartAndInterrogate(K: tPairKind);
begin
  OpenPair(K);
  IecSlaveEndOfInit(S, Coi_PowerOn);
  PollUntil('interrogation after the end of initialisation', 5000, @Interrogated);
  AssertEquals('reported', Format('slave %d CA 1 COI 0', [Addr]), Inits[0]);
  AssertEquals('the ASDU first', 'M_EI_NA_1 COT 4 IOA 0', Objects[0]);
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 COT 20 IOA 100') > 0);
  AssertEquals('one interrogation', 1, S.Interrogations);
  AssertEquals('no counter interrogation unless asked', 0, S.CounterInterrogations);
  AssertEquals('master counted it', 1, M.EndOfInits);
  AssertEquals(res_Ok, M.Cmd.Result);
  { the program's commands go on as before }
  AssertEquals(M.Cmd.Err, res_Ok, IecCounterInterrogation(M, Addr, 1, Qcc_General));
  AssertTrue(Objects.Text, Objects.IndexOf('M_IT_NA_1 COT 37 IOA 300') > 0);
end;

procedure TTestIecStation.TestUnbalancedStartThenInterrogation;
begin
  StartAndInterrogate(pkUnbalanced);
end;

procedure TTestIecStation.TestBalancedStartThenInterrogation;
begin
  StartAndInterrogate(pkBalanced);
end;

procedure TTestIecStation.Test104StartThenInterrogation;
begin
  StartAndInterrogate(pk104);
end;

{ A station interrogation packs consecutive points of one type into as
  few ASDUs as the link carries (the slave sends SQ = 0: each object with
  its IOA), and no more. IecDefaultParams: TI, VSQ, COT (2), CA (2) = 6
  octets of head; M_SP_NA_1 is IOA (3) + SIQ = 4 octets an object,
  M_ME_NB_1 IOA (3) + value (2) + QDS = 6.
  FT 1.2, ADR=1 (unbalanced and balanced alike): L = 255 counts the
  control and address octets, so an ASDU has up to 253 octets: singles
  (253 - 6) div 4 = 61 (250 octets; 62 would be 254), scaled
  (253 - 6) div 6 = 41 (252; 42 would be 258). The manual's 247-octet
  record gave 60 and 40.
  IEC 104: the APDU length is at most 253, the control field takes 4:
  ASDUs up to 249 octets, singles 243 div 4 = 60 (246; 61 would be 250),
  scaled 243 div 6 = 40 (246; 41 would be 252).
  The table: single point IOA 100 (the pair's own), a counter (not in a
  station interrogation; it ends the run of singles), 70 singles IOA
  1001..1070, 45 scaled values IOA 2001..2045. Every one reaches the
  master. }
procedure TTestIecStation.InterrogationFillsEachAsdu(K: tPairKind; const Want: array of string);
var
  I: Integer;
  O: tIecObject;
  E: ShortString;
begin
  OpenPair(K);
  for I := 1 to 70 do
  begin
    O := IecObject(1000 + I);
    O.Int := I and 1;
    AssertEquals(E, res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  end;
  for I := 1 to 45 do
  begin
    O := IecObject(2000 + I);
    O.Int := I;
    AssertEquals(E, res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, O, 0, E));
  end;
  S.OnAsdu := @OnSlaveAsdu;
  AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, Addr, 1, Qoi_Station));
  AssertEquals(Answers.Text, Length(Want), Answers.Count);
  for I := 0 to High(Want) do
    AssertEquals('answer ' + IntToStr(I + 1), Want[I], Answers[I]);
  { on the line and taken: 1 + 70 singles, 45 scaled values }
  AssertEquals('M_SP_NA_1 COT 20 IOA 1061', Objects[Objects.IndexOf('M_SP_NA_1 COT 20 IOA 1001') + 60]);
  AssertTrue(Objects.IndexOf('M_SP_NA_1 COT 20 IOA 1070') > 0);
  AssertEquals('M_ME_NB_1 COT 20 IOA 2045', Objects[Objects.IndexOf('M_ME_NB_1 COT 20 IOA 2001') + 44]);
  AssertEquals(0, M.BadAsdus);
end;

procedure TTestIecStation.TestInterrogationFillsEachFT12Frame;
begin
  { VSQ 3D = 61, 09 = 9, 29 = 41, 04 = 4 }
  InterrogationFillsEachAsdu(pkUnbalanced, ['01 01: 10', '01 3D: 250', '01 09: 42', '0B 29: 252', '0B 04: 30']);
end;

procedure TTestIecStation.TestInterrogationFillsEachBalancedFrame;
begin
  InterrogationFillsEachAsdu(pkBalanced, ['01 01: 10', '01 3D: 250', '01 09: 42', '0B 29: 252', '0B 04: 30']);
end;

procedure TTestIecStation.TestInterrogationFillsEach104Apdu;
begin
  { VSQ 3C = 60, 0A = 10, 28 = 40, 05 = 5 }
  InterrogationFillsEachAsdu(pk104, ['01 01: 10', '01 3C: 246', '01 0A: 46', '0B 28: 246', '0B 05: 36']);
end;

procedure TTestIecStation.RemoteResetInterrogatesAgain(K: tPairKind);
begin
  OpenPair(K);
  IecSlaveEndOfInit(S, Coi_PowerOn);
  PollUntil('first interrogation', 5000, @Interrogated);
  AssertEquals(M.Cmd.Err, res_Ok, IecResetProcess(M, Addr, 1, Qrp_General));
  AssertEquals('the slave was told', 1, Resets);
  PollUntil('interrogation after the remote reset', 5000, @TwoInterrogations);
  AssertEquals('COI 2: remote reset', Format('slave %d CA 1 COI 2', [Addr]), Inits[1]);
end;

procedure TTestIecStation.TestUnbalancedRemoteReset;
begin
  RemoteResetInterrogatesAgain(pkUnbalanced);
end;

procedure TTestIecStation.Test104RemoteReset;
begin
  RemoteResetInterrogatesAgain(pk104);
end;

procedure TTestIecStation.TestCounterInterrogationToo;
begin
  OpenPair(pkUnbalanced);
  M.CiAfterInit := Qcc_General;
  IecSlaveEndOfInit(S, Coi_ManualReset);
  PollUntil('counter interrogation after the end of initialisation', 5000, @CountersRead);
  AssertEquals('slave 1 CA 1 COI 1', Inits[0]);
  AssertEquals(1, S.Interrogations);
  AssertEquals(1, S.CounterInterrogations);
  AssertTrue('interrogation first', Objects.IndexOf('C_IC_NA_1 COT 10 IOA 0') <
    Objects.IndexOf('C_CI_NA_1 COT 7 IOA 0'));
end;

procedure TTestIecStation.TestToldNotToInterrogate;
begin
  OpenPair(pkUnbalanced);
  M.NoGiAfterInit := True;
  IecSlaveEndOfInit(S, Coi_PowerOn or Coi_LocalChange);
  PollUntil('end of initialisation', 5000, @InitSeen);
  IecPollFor(M, 300);
  AssertEquals('slave 1 CA 1 COI 128', Inits[0]);
  AssertEquals('no interrogation', 0, S.Interrogations);
  AssertTrue(IecCommandDone(M));
end;

procedure TTestIecStation.TestProgramInterrogationTakesItOver;
var
  Deadline: QWord;
begin
  OpenPair(pkUnbalanced);
  IecSlaveEndOfInit(S, Coi_PowerOn);
  Deadline := ChMsTick + 5000;
  while (Inits.Count = 0) and (ChMsTick < Deadline) do
    if not IecMasterStep(M) then
      StepSlave;
  AssertEquals('end of initialisation', 1, Inits.Count);
  { the step that took it started the master's own interrogation: the
    program's is that one }
  AssertTrue('under way', M.Cmd.Auto and not IecCommandDone(M));
  AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 1, 1, Qoi_Station));
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 COT 20 IOA 100') > 0);
  AssertEquals('one interrogation in all', 1, S.Interrogations);
  IecPollFor(M, 200);
  AssertEquals('still one', 1, S.Interrogations);
end;

{ One call per parameter type; the slave's table has them afterwards and
  its threshold holds back small changes. }
procedure TTestIecStation.TestParametersUnbalanced;
var
  O: tIecObject;
  E: ShortString;
begin
  OpenPair(pkUnbalanced);
  O := IecObject(110);
  O.Int := 100;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, O, 0, E));
  O := IecObject(111);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NA_1, O, 0, E));
  O := IecObject(112);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NC_1, O, 0, E));
  AssertEquals(M.Cmd.Err, res_Ok, IecParamScaled(M, 1, 1, 110, 50, Kpa_Threshold));
  AssertEquals(50, S.Points[IecSlaveFind(S, 110)].Par[Kpa_Threshold], 0);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamNormal(M, 1, 1, 111, 0.25, Kpa_Smoothing));
  AssertEquals(0.25, S.Points[IecSlaveFind(S, 111)].Par[Kpa_Smoothing], 1e-4);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamFloat(M, 1, 1, 112, 1.5, Kpa_High or Qpm_NotInOperation));
  AssertEquals(1.5, S.Points[IecSlaveFind(S, 112)].Par[Kpa_High], 0);
  AssertFalse('POP: not in operation', S.Points[IecSlaveFind(S, 112)].ParOn);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamActivation(M, 1, 1, 112, Qpa_Object));
  AssertTrue('activated', S.Points[IecSlaveFind(S, 112)].ParOn);
  { refusals come back as results }
  AssertEquals('a float parameter for a scaled value', res_IecUnknownIoa,
    IecParamFloat(M, 1, 1, 110, 1.0, Kpa_Threshold));
  AssertEquals('KPA 5', res_IecNegative, IecParamScaled(M, 1, 1, 110, 1, 5));
  AssertEquals('cyclic transmission', res_IecNegative, IecParamActivation(M, 1, 1, 110, Qpa_Cyclic));
  AssertFalse('a normalized value of 1 cannot be sent', IecStartParamNormal(M, 1, 1, 111, 1.0, Kpa_Threshold));
  { the threshold at work: 100 -> 120 held back, 100 -> 160 reported }
  O := IecObject(0);
  O.Int := 100;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 110, O, True, E));
  O.Int := 120;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 110, O, True, E));
  O.Int := 160;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 110, O, True, E));
  IecPollFor(M, 300);
  AssertEquals('one held back', 1, S.Suppressed);
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 COT 3 IOA 110') >= 0);
  AssertEquals('two reports', 2, Objects.Count - Objects.IndexOf('M_ME_NB_1 COT 3 IOA 110'));
end;

procedure TTestIecStation.TestParameters104Stepped;
var
  E: ShortString;
begin
  OpenPair(pk104);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, IecObject(120), 0, E));
  AssertTrue(M.Cmd.Err, IecStartParamScaled(M, 0, 1, 120, -3, Kpa_Low));
  AssertFalse('one at a time', IecStartParamActivation(M, 0, 1, 120, Qpa_Object));
  AssertEquals(M.Cmd.Err, res_Ok, IecFinish(M));
  AssertTrue(Objects.Text, Objects.IndexOf('P_ME_NB_1 COT 7 IOA 120') >= 0);
  AssertEquals(-3, S.Points[IecSlaveFind(S, 120)].Par[Kpa_Low], 0);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamActivation(M, 0, 1, 0, Qpa_Loaded));
end;

{ Deactivation of parameters (P_AC_NA_1, COT 8): the master's call ends
  on the DEACT_CON (COT 9, an ACT_CON would not do), the slave takes the
  threshold out of operation - a change inside it is reported again. }
procedure TTestIecStation.TestParameterDeactivation;
var
  E: ShortString;
  O: tIecObject;
  I: Integer;
begin
  OpenPair(pk104);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, IecObject(120), 0, E));
  I := IecSlaveFind(S, 120);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamScaled(M, 0, 1, 120, 10, Kpa_Threshold));
  AssertTrue('in operation', S.Points[I].ParOn);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamDeactivation(M, 0, 1, 120, Qpa_Object));
  AssertTrue(Objects.Text, Objects.IndexOf('P_AC_NA_1 COT 9 IOA 120') >= 0);
  AssertEquals('no ACT_CON', -1, Objects.IndexOf('P_AC_NA_1 COT 7 IOA 120'));
  AssertFalse('out of operation', S.Points[I].ParOn);
  { the deadband no longer holds back a change of 1 }
  O := IecObject(120);
  O.Int := 1;
  AssertEquals(res_Ok, IecSlaveUpdate(S, 120, O, True, E));
  AssertEquals(0, S.Suppressed);
  AssertEquals(M.Cmd.Err, res_Ok, IecParamActivation(M, 0, 1, 120, Qpa_Object));
  AssertTrue(S.Points[I].ParOn);
end;

{ Every command type, with and without time tag, from our master to our
  slave: each ends on its positive ACT_CON and reaches OnCommand. }
procedure TTestIecStation.TestEveryCommandType104;
const
  Types: array[0..13] of Byte = (C_SC_NA_1, C_DC_NA_1, C_RC_NA_1, C_SE_NA_1, C_SE_NB_1,
    C_SE_NC_1, C_BO_NA_1, C_SC_TA_1, C_DC_TA_1, C_RC_TA_1, C_SE_TA_1, C_SE_TB_1, C_SE_TC_1, C_BO_TA_1);
var
  I: Integer;
  O: tIecObject;
  E: ShortString;
begin
  OpenPair(pk104);
  S.OnCommand := @AcceptAll;
  for I := 0 to High(Types) do
    AssertEquals(res_Ok, IecSlaveAddPoint(S, Types[I], IecObject(6000 + I), 0, E));
  for I := 0 to High(Types) do
  begin
    O := IecObject(6000 + I);
    O.Int := 1;
    O.Number := 0.5;
    O.Bits := $12345678;
    O.Time := IecTimeFromDateTime(Now);
    AssertEquals(IecTypeName(Types[I]) + ': ' + M.Cmd.Err, res_Ok,
      IecCommand(M, 0, 1, Types[I], O, False));
  end;
  AssertEquals('all executed', Length(Types), Commands);
end;

initialization
  RegisterTest(TTestIecStation);
end.
