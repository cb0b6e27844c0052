{ Tests of ChnIecPointTable: our master on a pty, examples/iec101slave
  (as built) on its other side as the RTU. The values and qualities
  expected are those of the points file written here; the slave's return
  information (--return CMD=MON) brings a command's value back. A
  stopped slave (SIGSTOP) turns the table's health down, then demoted,
  its points bad; going on (SIGCONT) it is ok and interrogated again.
  Unix only (ptys, signals). }
unit TestChnIecPointTable;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnPty,
  ChnWait, ChnFT1_2, ChnIec101Asdu, ChnIec101Master, ChnIecPointTable, BinSupport, TestTempDir;

type
  TFunc = function: Boolean of object;

  TTestChnIecPointTable = class(TTestCase)
  private
    FDir, FPty, FSlaveOut: string;
    FChn: pChnVirt;
    FSlave: TProcess;
    M: tIecMaster;
    T: tIecPointTable;
    procedure StartSlave(const Extra: array of string);
    procedure StopSlave;
    procedure Open(TimeoutMs: LongInt);
    { step until Done or Ms ran out }
    function StepUntil(Ms: LongInt; Done: TFunc): Boolean;
    procedure StepFor(Ms: LongInt);
    function Point(Ioa: LongWord): LongInt;
    function Changed: string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestValuesQualityAndCommands;
    procedure TestDeadSlaveDownDemotedAndBack;
    procedure TestCommandTypesAndRefusals;
  end;

implementation

const
  Points =
    '100 M_ME_NB_1 -1'#10 +
    '101 M_ME_NC_1 1.5'#10 +
    '104 M_SP_NA_1 1 IV'#10 +
    '105 M_DP_NA_1 2'#10 +
    '300 M_SP_TB_1 0 NT+SB'#10 +
    '5000 C_SC_NA_1 0'#10 +
    '5101 C_SE_NC_1 0'#10;

procedure TTestChnIecPointTable.SetUp;
begin
  FDir := MakeTempDir('iectable');
  FChn := nil;
  FSlave := nil;
  FillChar(T, SizeOf(T), 0);
  with TStringList.Create do
  try
    Text := Points;
    SaveToFile(FDir + '/rtu.txt');
  finally
    Free;
  end;
end;

procedure TTestChnIecPointTable.TearDown;
begin
  StopSlave;
  IecTableDone(T);
  if FChn <> nil then
    Dispose(FChn, Done);
  RemoveTempDir(FDir);
end;

procedure TTestChnIecPointTable.Open(TimeoutMs: LongInt);
begin
  FChn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  FChn^.ChSetParam('NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DRV=PTY');
  FChn^.ChOpen;
  FChn^.ChConnect;
  AssertEquals(FChn^.ChResultStr(FChn^.ChResult), res_Ok, FChn^.ChResult);
  FPty := PtyLastSlave;
  AssertEquals(res_Ok, IecMasterInit(M, FChn, IecDefaultParams));
  AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
  M.CycleMs := 20;
  M.TimeoutMs := TimeoutMs;
  if TimeoutMs < 1000 then
    M.Retries := 0;      { a dead slave found at once }
  M.DeadMinMs := 2 * TimeoutMs;
  M.DeadMaxMs := 8 * TimeoutMs;
  M.CommandMs := 3000;
  IecTableInit(T, M, 1);
end;

procedure TTestChnIecPointTable.StartSlave(const Extra: array of string);
var
  S: string;
begin
  AssertTrue(BinPath('iec101slave') + ' missing (make examples)', FileExists(BinPath('iec101slave')));
  FSlave := TProcess.Create(nil);
  BinExecutable(FSlave, BinPath('iec101slave'));
  FSlave.Parameters.Add('--json');
  FSlave.Parameters.Add('--points=' + FDir + '/rtu.txt');
  FSlave.Parameters.Add('--seconds=60');
  for S in Extra do
    FSlave.Parameters.Add(S);
  FSlave.Parameters.Add('NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=' + FPty + ' BD=9600 PAR=E');
  FSlave.Options := [poUsePipes, poStderrToOutPut];
  FSlave.Execute;
end;

procedure TTestChnIecPointTable.StopSlave;
begin
  if FSlave = nil then
    Exit;
  if FSlave.Running then
  begin
    FpKill(FSlave.ProcessID, SIGKILL);
    FpKill(FSlave.ProcessID, SIGCONT);
    FSlave.WaitOnExit;
  end;
  FreeAndNil(FSlave);
end;

function TTestChnIecPointTable.StepUntil(Ms: LongInt; Done: TFunc): Boolean;
var
  Deadline: QWord;
  W: LongInt;
begin
  Deadline := ChMsTick + QWord(Ms);
  repeat
    if FSlave <> nil then
      Drain(FSlave, FSlaveOut);
    if Assigned(Done) and Done() then
      Exit(True);
    if not IecTableStep(T) then
    begin
      W := IecTableWaitMs(T);
      if W > 50 then
        W := 50;
      ChnWaitAny(W);
    end;
  until ChMsTick > Deadline;
  Result := Assigned(Done) and Done();
end;

procedure TTestChnIecPointTable.StepFor(Ms: LongInt);
begin
  StepUntil(Ms, nil);
end;

function TTestChnIecPointTable.Point(Ioa: LongWord): LongInt;
begin
  Result := IecTableFind(T, 1, 1, Ioa);
end;

{ The changes taken: 'IOA=VALUE QUALITY' each, blank-separated. }
function TTestChnIecPointTable.Changed: string;
var
  P: LongInt;
  V: Double;
begin
  Result := '';
  while IecTableTakeChange(T, P) do
  begin
    { a copy: Format takes the address of a Double, and the table's packed
      record may hold it at an address ARM's VFP cannot load from }
    V := T.Points[P].Value;
    Result := Result + Format('%d=%g %s ', [T.Points[P].Ioa, V,
      IecPointQualityText(T.Points[P])]);
  end;
  Result := Trim(Result);
end;

type
  TCond = class
    Tc: TTestChnIecPointTable;
    Want: LongInt;
    function AllKnown: Boolean;
    function WriteDone: Boolean;
    function HealthIs: Boolean;
  end;

var
  W: tIecTableWrite;
  Got: Boolean;

function TCond.AllKnown: Boolean;
var
  I: LongInt;
begin
  Result := (Length(Tc.T.Points) >= 5) and not Tc.T.Running and (Tc.T.Slaves[0].Health = ihOk);
  for I := 0 to High(Tc.T.Points) do
    Result := Result and Tc.T.Points[I].Known;
end;

function TCond.WriteDone: Boolean;
begin
  if not Got then
    Got := IecTableTakeWrite(Tc.T, W);
  Result := Got;
end;

function TCond.HealthIs: Boolean;
begin
  Result := Ord(Tc.T.Slaves[0].Health) = Want;
end;

procedure TTestChnIecPointTable.TestValuesQualityAndCommands;
var
  C: TCond;
  E: ShortString;
  P: LongInt;
  S: string;
  HS, Errs: LongInt;
begin
  Open(1000);
  C := TCond.Create;
  try
    C.Tc := Self;
    { named and writable before the first value }
    P := IecTableAdd(T, 1, 1, 104, 'pump');
    IecTableSetWritable(T, P, 5000, 0);
    P := IecTableAdd(T, 1, 1, 101, '');
    IecTableSetWritable(T, P, 5101, 0);
    T.Points[P].Deadband := 0.5;
    StartSlave(['--return=5000=104,5101=101']);
    AssertTrue('interrogated', StepUntil(8000, @C.AllKnown));
    AssertTrue('health reported', IecTableTakeHealth(T, HS));
    AssertEquals(0, HS);
    AssertEquals('ok', IecHealthNames[T.Slaves[0].Health]);
    { the first state of every point, in the order the slave sends them }
    S := Changed;
    AssertTrue(S, Pos('100=-1 good', S) > 0);
    AssertTrue(S, Pos('101=1.5 good', S) > 0);
    AssertTrue(S, Pos('104=1 IV', S) > 0);
    AssertTrue(S, Pos('105=2 good', S) > 0);
    AssertTrue(S, Pos('300=0 NT+SB', S) > 0);
    AssertEquals('pump', T.Points[Point(104)].Name);
    AssertEquals(M_SP_NA_1, T.Points[Point(104)].Ti);
    AssertEquals(M_ME_NB_1, T.Points[Point(100)].Ti);
    AssertTrue('polls counted', T.Slaves[0].Polls > 0);
    { (the slave may have missed the first status request while it started) }
    Errs := T.Slaves[0].Errors;
    { a CP56 time tag: the slave's clock, close to ours }
    AssertTrue('time tag', Abs(T.Points[Point(300)].TimeMs - ChUtcMs) < 60000);
    { a single command to 104's command point: ACT_CON, then its return
      information: value 0, quality good }
    AssertTrue(E, IecTableWrite(T, Point(104), 0, 7, E));
    Got := False;
    AssertTrue('confirmed', StepUntil(5000, @C.WriteDone));
    AssertEquals(W.Err, res_Ok, W.Res);
    AssertEquals(7, W.Id);
    StepFor(300);
    AssertEquals('104=0 good', Changed);
    { a float set point within the deadband comes back but is no change }
    AssertTrue(E, IecTableWrite(T, Point(101), 1.75, 8, E));
    Got := False;
    AssertTrue('confirmed', StepUntil(5000, @C.WriteDone));
    AssertEquals(W.Err, res_Ok, W.Res);
    StepFor(300);
    AssertEquals(1.75, T.Points[Point(101)].Value, 1e-6);
    AssertEquals('within the deadband', '', Changed);
    AssertTrue(E, IecTableWrite(T, Point(101), 2.25, 9, E));
    Got := False;
    AssertTrue('confirmed', StepUntil(5000, @C.WriteDone));
    AssertEquals(W.Err, res_Ok, W.Res);
    StepFor(300);
    AssertEquals(FSlaveOut, '101=2.25 good', Changed);
    { refused at once: not writable, a value the type cannot take }
    AssertFalse(IecTableWrite(T, Point(100), 5, 10, E));
    AssertEquals('IOA 100 is not writable', E);
    AssertFalse(IecTableWrite(T, Point(104), 2, 11, E));
    AssertEquals('IOA 104: a single command is 0 or 1 (false or true)', E);
    { a command point the slave does not have: its negative answer }
    P := IecTableAdd(T, 1, 1, 105, '');
    IecTableSetWritable(T, P, 5999, 0);
    AssertTrue(E, IecTableWrite(T, P, 2, 12, E));
    Got := False;
    AssertTrue('answered', StepUntil(5000, @C.WriteDone));
    AssertEquals(W.Err, res_IecUnknownIoa, W.Res);
    AssertEquals(W.Err, 'C_DC_NA_1 IOA 5999 to slave 1: the slave does not know IOA 5999 (COT 47 UNKNOWN_INFORMATION_OBJECT_ADDRESS)', W.Err);
    AssertEquals('counted', Errs + 1, T.Slaves[0].Errors);
    AssertEquals(W.Err, T.Slaves[0].LastError);
  finally
    C.Free;
  end;
end;

procedure TTestChnIecPointTable.TestDeadSlaveDownDemotedAndBack;
var
  C: TCond;
  S: string;
  HS: LongInt;
  E: ShortString;
begin
  Open(300);
  C := TCond.Create;
  try
    C.Tc := Self;
    StartSlave([]);
    AssertTrue('interrogated', StepUntil(8000, @C.AllKnown));
    Changed;
    while IecTableTakeHealth(T, HS) do;
    { the RTU stops (SIGSTOP: the line stays, nobody answers) }
    FpKill(FSlave.ProcessID, SIGSTOP);
    C.Want := Ord(ihDown);
    AssertTrue('down', StepUntil(5000, @C.HealthIs));
    AssertTrue('health reported', IecTableTakeHealth(T, HS));
    S := Changed;
    AssertEquals('every point bad', '100=-1 bad 101=1.5 bad 104=1 bad 105=2 bad 300=0 bad', S);
    AssertTrue(T.Slaves[0].LastError, Pos('no answer from link address 1', T.Slaves[0].LastError) = 1);
    AssertTrue('errors counted', T.Slaves[0].Errors >= 1);
    { a command to a slave that is not ok is refused at once }
    IecTableSetWritable(T, Point(104), 5000, 0);
    AssertFalse(IecTableWrite(T, Point(104), 1, 1, E));
    AssertEquals('IOA 104: slave 1 is not ok (down)', E);
    C.Want := Ord(ihDemoted);
    AssertTrue('demoted after its retry failed', StepUntil(5000, @C.HealthIs));
    AssertEquals('still bad: no change', '', Changed);
    { the RTU goes on (what reached it meanwhile is stale): ok,
      interrogated, good again }
    FpKill(FSlave.ProcessID, SIGCONT);
    C.Want := Ord(ihOk);
    AssertTrue('ok again', StepUntil(8000, @C.HealthIs));
    AssertTrue('known', StepUntil(5000, @C.AllKnown));
    StepFor(300);
    S := Changed;
    AssertTrue(S, Pos('100=-1 good', S) > 0);
    AssertTrue(S, Pos('104=1 IV', S) > 0);
  finally
    C.Free;
  end;
end;

procedure TTestChnIecPointTable.TestCommandTypesAndRefusals;
var
  P: tIecTablePoint;
begin
  AssertEquals(C_SC_NA_1, IecCommandType(M_SP_NA_1));
  AssertEquals(C_SC_NA_1, IecCommandType(M_SP_TB_1));
  AssertEquals(C_DC_NA_1, IecCommandType(M_DP_TB_1));
  AssertEquals(C_SE_NA_1, IecCommandType(M_ME_NA_1));
  AssertEquals(C_SE_NB_1, IecCommandType(M_ME_TE_1));
  AssertEquals(C_SE_NC_1, IecCommandType(M_ME_NC_1));
  AssertEquals(C_BO_NA_1, IecCommandType(M_BO_NA_1));
  AssertEquals('counters take no command', 0, IecCommandType(M_IT_NA_1));
  FillChar(P, SizeOf(P), 0);
  AssertEquals('initial', IecPointQualityText(P));
  P.Known := True;
  P.Ti := M_IT_NA_1;
  P.Quality := Q_Substituted or Q_NotTopical;   { CY, CA of a counter: no quality }
  AssertEquals('good', IecPointQualityText(P));
  P.Quality := P.Quality or Q_Invalid;
  AssertEquals('IV', IecPointQualityText(P));
  P.Ti := M_ME_NB_1;
  P.Quality := Q_Overflow or Q_Blocked;
  AssertEquals('BL+OV', IecPointQualityText(P));
  P.Bad := True;
  AssertEquals('bad', IecPointQualityText(P));
end;

initialization
  RegisterTest(TTestChnIecPointTable);
end.
