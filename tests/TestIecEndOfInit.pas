{ End of initialisation (M_EI_NA_1, COT 4) between the library's slave and
  master, over FT 1.2 unbalanced and balanced (LOOP) and over IEC 104
  (loopback TCP): the slave sends it when the program says it has
  initialised (COI 0 after a start) and after a general reset of process
  (COI 2); the master reports it (OnEndOfInit) and, unless told not to,
  interrogates the slave (station interrogation, and counters when
  CiAfterInit is set); a program's own interrogation meanwhile takes the
  master's over. The octets of M_EI_NA_1 itself are checked by hand in
  TestChnIec101Slave.TestEndOfInitOctets. One thread: the master's Idle
  steps the slave. }
unit TestIecEndOfInit;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnLoop, ChnFT1_2,
  ChnIec104, ChnIec101Asdu, ChnIec101Master, ChnIec101Slave, ChnWait, TestSupport;

type
  tPairKind = (pkUnbalanced, pkBalanced, pk104);
  TTestIecEndOfInit = class;
  TFunc = function(T: TTestIecEndOfInit): Boolean;

  TTestIecEndOfInit = class(TTestCase)
  private
    SChn, MChn: pChnVirt;
    Kind: tPairKind;
    Addr: Word;          { the slave's link address as the master names it }
    procedure OpenPair(K: tPairKind);
    procedure StepSlave;
    procedure PollUntil(const What: string; Ms: LongInt; Cond: TFunc);
    procedure StartAndInterrogate(K: tPairKind);
    procedure RemoteResetInterrogatesAgain(K: tPairKind);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    M: tIecMaster;
    S: tIecSlaveStation;
    Objects, Inits: TStringList;
    Resets: Integer;
  published
    procedure TestUnbalancedStartThenInterrogation;
    procedure TestBalancedStartThenInterrogation;
    procedure Test104StartThenInterrogation;
    procedure TestUnbalancedRemoteReset;
    procedure Test104RemoteReset;
    procedure TestCounterInterrogationToo;
    procedure TestToldNotToInterrogate;
    procedure TestProgramInterrogationTakesItOver;
  end;

implementation

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIecEndOfInit(Data).Objects.Add(IecTypeName(H.Ti) + ' COT ' + IntToStr(H.Cot) +
    ' IOA ' + IntToStr(O.Ioa));
end;

procedure OnInit(Data: Pointer; Addr, Ca: Word; Coi: Byte);
begin
  TTestIecEndOfInit(Data).Inits.Add(Format('slave %d CA %d COI %d', [Addr, Ca, Coi]));
end;

procedure OnReset(Data: Pointer; Qrp: Byte);
begin
  Inc(TTestIecEndOfInit(Data).Resets);
end;

procedure IdleSlave(Data: Pointer);
begin
  TTestIecEndOfInit(Data).StepSlave;
end;

procedure TTestIecEndOfInit.StepSlave;
begin
  IecSlaveStep(S);
  ChnWaitAny(2);
end;

procedure TTestIecEndOfInit.SetUp;
begin
  Objects := TStringList.Create;
  Inits := TStringList.Create;
  SChn := nil;
  MChn := nil;
  Resets := 0;
end;

procedure TTestIecEndOfInit.TearDown;
begin
  if MChn <> nil then Dispose(MChn, Done);
  if SChn <> nil then Dispose(SChn, Done);
  Objects.Free;
  Inits.Free;
end;

procedure TTestIecEndOfInit.OpenPair(K: tPairKind);
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
        SChn := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0', Err);
        AssertNotNull(Err, SChn);
        Port := pChnTcp(SChn^.CH_Low)^.ChLocalPort;
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

procedure TTestIecEndOfInit.PollUntil(const What: string; Ms: LongInt; Cond: TFunc);
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(Ms);
  while not Cond(Self) and (ChMsTick < Deadline) do
    IecPollFor(M, 20);
  AssertTrue(What + ' within ' + IntToStr(Ms) + ' ms; objects: ' + Objects.CommaText +
    ' inits: ' + Inits.CommaText, Cond(Self));
end;

function Interrogated(T: TTestIecEndOfInit): Boolean;
begin
  Result := (T.Objects.IndexOf('C_IC_NA_1 COT 10 IOA 0') >= 0) and IecCommandDone(T.M);
end;

function TwoInterrogations(T: TTestIecEndOfInit): Boolean;
begin
  Result := (T.S.Interrogations = 2) and IecCommandDone(T.M) and
    (T.Objects.IndexOf('C_IC_NA_1 COT 10 IOA 0') <> T.Objects.Count - 1) and
    (T.Objects[T.Objects.Count - 1] = 'C_IC_NA_1 COT 10 IOA 0');
end;

function CountersRead(T: TTestIecEndOfInit): Boolean;
begin
  Result := (T.Objects.IndexOf('C_CI_NA_1 COT 10 IOA 0') >= 0) and IecCommandDone(T.M);
end;

function InitSeen(T: TTestIecEndOfInit): Boolean;
begin
  Result := T.Inits.Count > 0;
end;

procedure TTestIecEndOfInit.StartAndInterrogate(K: tPairKind);
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

procedure TTestIecEndOfInit.TestUnbalancedStartThenInterrogation;
begin
  StartAndInterrogate(pkUnbalanced);
end;

procedure TTestIecEndOfInit.TestBalancedStartThenInterrogation;
begin
  StartAndInterrogate(pkBalanced);
end;

procedure TTestIecEndOfInit.Test104StartThenInterrogation;
begin
  StartAndInterrogate(pk104);
end;

procedure TTestIecEndOfInit.RemoteResetInterrogatesAgain(K: tPairKind);
begin
  OpenPair(K);
  IecSlaveEndOfInit(S, Coi_PowerOn);
  PollUntil('first interrogation', 5000, @Interrogated);
  AssertEquals(M.Cmd.Err, res_Ok, IecResetProcess(M, Addr, 1, Qrp_General));
  AssertEquals('the slave was told', 1, Resets);
  PollUntil('interrogation after the remote reset', 5000, @TwoInterrogations);
  AssertEquals('COI 2: remote reset', Format('slave %d CA 1 COI 2', [Addr]), Inits[1]);
end;

procedure TTestIecEndOfInit.TestUnbalancedRemoteReset;
begin
  RemoteResetInterrogatesAgain(pkUnbalanced);
end;

procedure TTestIecEndOfInit.Test104RemoteReset;
begin
  RemoteResetInterrogatesAgain(pk104);
end;

procedure TTestIecEndOfInit.TestCounterInterrogationToo;
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

procedure TTestIecEndOfInit.TestToldNotToInterrogate;
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

procedure TTestIecEndOfInit.TestProgramInterrogationTakesItOver;
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

initialization
  RegisterTest(TTestIecEndOfInit);
end.
