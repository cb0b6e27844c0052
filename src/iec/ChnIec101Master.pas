{ ChnIec101Master - an IEC 60870-5-101 controlling station (master) on a
  tChnFT1_2 channel, unbalanced (MS=ON, several slaves on one line) or
  balanced (MS=OFF, one peer).

  Unbalanced: the slaves get their turns round-robin, and the line is
  never idle while a slave has data. A slave whose link is not up gets
  request status of link (FC 9) and reset of remote link (FC 0); an
  online slave is polled for class 1 data (FC 10) whenever the last reply
  had ACD set, else for class 2 data (FC 11). After an answer with data
  (ACD set, or class 2 user data) the slave is polled again at once; one
  that had nothing waits CycleMs. A slave keeps the turn for at most
  PollBurst services in a row while it has data, then the next slave
  that is due gets it: one that always has data (ACD stuck, a stream of
  events) cannot starve the others. A slave that stops answering is
  marked dead and tried again after DeadMinMs, doubling up to DeadMaxMs,
  with a single transmission; its back-off is reset only by an answered
  class poll or command, not by a status or reset answer alone, so a
  slave that answers FC 9 and FC 0 but never a poll costs the others one
  timeout per back-off too. Commands go as SEND/CONFIRM
  user data (FC 3) when their slave is online. The link procedures (FCB,
  repetitions, the reset in front of FCV = 1 services) are ChnFT12Link's.
  Balanced: ChnFT12Link's tFT12Balanced runs the link; commands are
  queued as user data; the peer's user data are taken as they come.

  Every ASDU received reaches OnObject object by object, typed
  (ChnIec101Asdu), whatever type and cause (lib60870's slaves answer an
  interrogation with time-tagged types: they are passed on as they are).
  A malformed ASDU is counted (BadAsdus, per slave too), its text kept in
  LastBad and given to OnBad; it never stops the master.

  One command at a time: IecStart* checks it, refuses what cannot be sent
  (a value out of range, an IOA too large for the IOA size: the encoder's
  result, nothing sent) and starts it; IecMasterStep, called from the
  program's poll loop (with ChnWaitAny between steps), runs the line and
  ends the command on its confirmation: res_Ok (positive ACT_CON; also
  ACT_TERM after it for interrogations - one before it is the last
  command's; the answer with COT 5 for a read),
  res_IecNegative (negative ACT_CON), res_IecUnknownType, ..Cot, ..Ca,
  ..Ioa (COT 44..47), res_Timeout (no confirmation in CommandMs, or the
  Link dependency: the one place that drives an FT 1.2 primary service is
  LinkStart/LinkStep in ChnIec101MasterPoll, on ChnFT12Link's stepped
  primary: a step never waits, so the master serves its line from the
  program's poll loop (Idle, when set, runs between steps of the blocking
  forms instead of the wait).

  The master's parts, a unit each: ChnIec101MasterTypes (the record),
  ChnIec101MasterCmd (the command's stages and the answers that end
  them), ChnIec101MasterInbound (the ASDUs received, ends of
  initialisation), ChnIec101MasterPoll (the line: polling scheduler and
  link services, or the balanced transport). This unit is the program's
  interface: set-up, the stepped and blocking commands, the step and the
  waits. }
unit ChnIec101Master;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnIec101Asdu, ChnIecTransport,
  ChnIec101MasterTypes;

{ The master's names, declared in ChnIec101MasterTypes (why: see there),
  given again here for programs that use this unit. }
const
  res_IecNegative    = ChnIec101MasterTypes.res_IecNegative;
  res_IecUnknownType = ChnIec101MasterTypes.res_IecUnknownType;
  res_IecUnknownCot  = ChnIec101MasterTypes.res_IecUnknownCot;
  res_IecUnknownCa   = ChnIec101MasterTypes.res_IecUnknownCa;
  res_IecUnknownIoa  = ChnIec101MasterTypes.res_IecUnknownIoa;
  res_IecNoSlave     = ChnIec101MasterTypes.res_IecNoSlave;
  res_IecBusy        = ChnIec101MasterTypes.res_IecBusy;
  IecMaxSlaves       = ChnIec101MasterTypes.IecMaxSlaves;

  isOffline = ChnIec101MasterTypes.isOffline;
  isLinkStatus = ChnIec101MasterTypes.isLinkStatus;
  isOnline = ChnIec101MasterTypes.isOnline;
  isDead = ChnIec101MasterTypes.isDead;
  cpNone = ChnIec101MasterTypes.cpNone;
  cpSend = ChnIec101MasterTypes.cpSend;
  cpConfirm = ChnIec101MasterTypes.cpConfirm;
  cpTerm = ChnIec101MasterTypes.cpTerm;
  cpDone = ChnIec101MasterTypes.cpDone;
  ljNone = ChnIec101MasterTypes.ljNone;
  ljStatus = ChnIec101MasterTypes.ljStatus;
  ljReset = ChnIec101MasterTypes.ljReset;
  ljCommand = ChnIec101MasterTypes.ljCommand;
  ljClass1 = ChnIec101MasterTypes.ljClass1;
  ljClass2 = ChnIec101MasterTypes.ljClass2;
  stDelayAct = ChnIec101MasterTypes.stDelayAct;
  stDelaySend = ChnIec101MasterTypes.stDelaySend;
  stSelect = ChnIec101MasterTypes.stSelect;
  stMain = ChnIec101MasterTypes.stMain;

type
  tIecSlaveState   = ChnIec101MasterTypes.tIecSlaveState;
  tIecSlave        = ChnIec101MasterTypes.tIecSlave;
  tIecObjectFunc   = ChnIec101MasterTypes.tIecObjectFunc;
  tIecBadFunc      = ChnIec101MasterTypes.tIecBadFunc;
  tIecInitFunc     = ChnIec101MasterTypes.tIecInitFunc;
  tIecFileAsduFunc = ChnIec101MasterTypes.tIecFileAsduFunc;
  tIecCmdPhase     = ChnIec101MasterTypes.tIecCmdPhase;
  tIecLinkJob      = ChnIec101MasterTypes.tIecLinkJob;
  tIecCmdStage     = ChnIec101MasterTypes.tIecCmdStage;
  tIecCommand      = ChnIec101MasterTypes.tIecCommand;
  tIecMaster       = ChnIec101MasterTypes.tIecMaster;
  pIecMaster       = ChnIec101MasterTypes.pIecMaster;

{ A master on an open tChnFT1_2 stack (it stays the caller's), with the
  application parameters P; unbalanced or balanced as the channel is.
  res_WrongLayer (no tChnFT1_2), res_AsduParam, res_BadMessage (a slave
  or secondary channel). M must not move afterwards (the channel
  receives into it). Balanced: the peer is slave DNO of the channel. }
function IecMasterInit(var M: tIecMaster; Chn: pChnVirt; const P: tIecParams): tChResult;
{ Add a slave link address (unbalanced); res_Busy when IecMaxSlaves are
  there, res_BadParam for an address twice, above 255 (ADR=1) or the
  broadcast address (255, ADR=2: 65535), which no station answers. }
function IecMasterAddSlave(var M: tIecMaster; Addr: Word): tChResult;
{ Index of a slave, -1 when not added. }
function IecMasterSlave(const M: tIecMaster; Addr: Word): LongInt;
{ One step: at most one link service (unbalanced) or one frame
  (balanced), the command's timer. True when something was done; False:
  nothing is due before IecMasterWaitEnd (wait with ChnWaitAny). }
function IecMasterStep(var M: tIecMaster): Boolean;
function IecMasterWaitEnd(const M: tIecMaster): QWord;
function IecSlaveStateName(S: tIecSlaveState): ShortString;
{ What the line showed of slave index S besides its answers, for an
  error: ' — 12 frames from link address 1 ignored' (a wrong NOD=/DNO=),
  balanced also ' — N frames with this station's own DIR bit ignored'
  (both stations DIR= alike); '' when nothing was ignored. }
function IecLineShowed(const M: tIecMaster; S: LongInt): ShortString;

{ Stepped commands to slave Addr, common address Ca: False when refused
  (M.Cmd.Result, M.Cmd.Err say why; nothing sent). Then step until
  IecCommandDone. }
function IecStartInterrogation(var M: tIecMaster; Addr, Ca: Word; Qoi: Byte): Boolean;
function IecStartCounterInterrogation(var M: tIecMaster; Addr, Ca: Word; Qcc: Byte): Boolean;
function IecStartRead(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord): Boolean;
{ T: the time to set (IecTimeFromDateTime(Now)); Delay: acquire the
  transmission delay first (C_CD_NA_1) and send it to the slave. }
function IecStartClockSync(var M: tIecMaster; Addr, Ca: Word; const T: tIecTime; Delay: Boolean): Boolean;
function IecStartTest(var M: tIecMaster; Addr, Ca: Word): Boolean;
function IecStartResetProcess(var M: tIecMaster; Addr, Ca: Word; Qrp: Byte): Boolean;
{ A command of types 45..51 or 58..64 with its object; Sbo: select,
  then execute after the positive ACT_CON. Without Sbo, Obj.Select
  sends the select alone (it ends on its ACT_CON), else the execute. }
function IecStartCommand(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo: Boolean): Boolean;
{ Parameter loading: one per parameter type - the parameter of kind Qpm
  (Kpa_Threshold, Kpa_Smoothing, Kpa_Low, Kpa_High; + Qpm_NotInOperation
  to load it without putting it in operation) of the measured value Ioa:
  a normalized (P_ME_NA_1, -1 <= Value < 1), scaled (P_ME_NB_1) or float
  (P_ME_NC_1) one; ends on its ACT_CON. Activation (P_AC_NA_1, COT 6)
  with Qpa (Qpa_Loaded with Ioa 0: every parameter loaded; Qpa_Object:
  those of Ioa). }
function IecStartParamNormal(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): Boolean;
function IecStartParamScaled(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: LongInt; Qpm: Byte): Boolean;
function IecStartParamFloat(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): Boolean;
function IecStartParamActivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): Boolean;
{ The same with COT 8: the parameters out of operation; ends on the
  DEACT_CON (COT 9). }
function IecStartParamDeactivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): Boolean;
{ One ASDU built by another procedure (file transfer, ChnIecFileClient)
  to slave Addr: ends res_Ok once the link took it (unbalanced: its
  SEND/CONFIRM confirmed; balanced, IEC 104: handed to the transport);
  the answers come to OnFileAsdu. False when refused as the others. }
function IecStartAsdu(var M: tIecMaster; Addr: Word; const Asdu: array of Byte; Len: Word): Boolean;
function IecCommandDone(const M: tIecMaster): Boolean;
{ Step a started command to its end (Idle, or ChnWaitAny); its result. }
function IecFinish(var M: tIecMaster): tChResult;

{ Blocking forms: start and finish. }
function IecInterrogation(var M: tIecMaster; Addr, Ca: Word; Qoi: Byte): tChResult;
function IecCounterInterrogation(var M: tIecMaster; Addr, Ca: Word; Qcc: Byte): tChResult;
function IecRead(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord): tChResult;
function IecClockSync(var M: tIecMaster; Addr, Ca: Word; const T: tIecTime; Delay: Boolean): tChResult;
function IecTestCommand(var M: tIecMaster; Addr, Ca: Word): tChResult;
function IecResetProcess(var M: tIecMaster; Addr, Ca: Word; Qrp: Byte): tChResult;
function IecCommand(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo: Boolean): tChResult;
function IecParamNormal(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): tChResult;
function IecParamScaled(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: LongInt; Qpm: Byte): tChResult;
function IecParamFloat(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): tChResult;
function IecParamActivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): tChResult;
function IecParamDeactivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): tChResult;
{ Step for Ms milliseconds (polling, objects to OnObject). }
procedure IecPollFor(var M: tIecMaster; Ms: LongInt);
{ The pause of a loop whose step did nothing: Idle when set, else
  ChnWaitAny until the line has something or the master's next service
  is due (Limit at the latest; at most one second). }
procedure IecMasterWait(var M: tIecMaster; Limit: QWord);

{ What the master knows of slave index S (0..SlaveCount - 1), for a
  program that shows its health: a copy of its record (State, BackoffMs,
  Probation, the counters; Link.Repeats the link's repetitions). False
  when there is no such slave. }
function IecMasterSlaveInfo(const M: tIecMaster; S: LongInt; out Info: tIecSlave): Boolean;
{ The outcome of the last command that ended (res_Ok also while none
  ended yet) and its text. }
function IecCommandResult(const M: tIecMaster; out Err: ShortString): tChResult;
{ res_Ok, or how the channel itself failed (res_DeviceLost ...). }
function IecMasterLineResult(const M: tIecMaster): tChResult;

implementation

uses
  SysUtils, ChnWait, ChnFT12Codec, ChnIec101MasterCmd, ChnIec101MasterInbound, ChnIec101MasterPoll;

{ the questions every part asks, answered in ChnIec101MasterTypes }
function IecSlaveStateName(S: tIecSlaveState): ShortString;
begin
  Result := ChnIec101MasterTypes.IecSlaveStateName(S);
end;

function IecLineShowed(const M: tIecMaster; S: LongInt): ShortString;
begin
  Result := ChnIec101MasterTypes.IecLineShowed(M, S);
end;

function IecMasterSlave(const M: tIecMaster; Addr: Word): LongInt;
begin
  Result := ChnIec101MasterTypes.IecMasterSlave(M, Addr);
end;

function IecCommandDone(const M: tIecMaster): Boolean;
begin
  Result := ChnIec101MasterTypes.IecCommandDone(M);
end;

procedure SlaveInit(var S: tIecSlave; Addr: Word; BackoffMs: LongInt);
begin
  FillChar(S, SizeOf(S), 0);
  S.Addr := Addr;
  FT12LinkInit(S.Link, Addr);
  S.BackoffMs := BackoffMs;
end;


function IecMasterInit(var M: tIecMaster; Chn: pChnVirt; const P: tIecParams): tChResult;
var
  E: ShortString;
  Primary: Boolean;
begin
  FillChar(M, SizeOf(M), 0);
  M.Chn := Chn;
  M.Params := P;
  M.TimeoutMs := FT12LinkTimeoutMs;
  M.Retries := FT12LinkRetries;
  M.CycleMs := 100;
  M.PollBurst := 3;
  M.DeadMinMs := 1000;
  M.DeadMaxMs := 30000;
  M.CommandMs := 10000;
  M.Cmd.Slave := -1;
  Result := IecCheckParams(P, E);
  if Result <> res_Ok then
    Exit;
  Result := IecLinkKind(Chn, M.Over104, M.Balanced, Primary);
  if Result <> res_Ok then
    Exit;
  if M.Balanced then
  begin
    Result := IecTransportStart(M.Link, Chn, @OnBalancedData, @M);
    if Result <> res_Ok then
      Exit;
    SlaveInit(M.Slaves[0], Chn^.CH_DNode, M.DeadMinMs);
    M.SlaveCount := 1;
  end
  else if not Primary then
    Result := res_BadMessage;
end;

function IecMasterAddSlave(var M: tIecMaster; Addr: Word): tChResult;
var
  AdrLen: Byte;
begin
  if M.Balanced then
    Exit(res_BadParam);
  { the broadcast address is no station: it never answers (SEND/NO REPLY only) }
  AdrLen := pChnFT1_2(M.Chn)^.ChFT12Config.AddrLen;
  if (IecMasterSlave(M, Addr) >= 0) or (Addr > $FFFF shr (8 * (2 - AdrLen))) or
     ((AdrLen > 0) and (Addr = FT12Broadcast(AdrLen))) then
    Exit(res_BadParam);
  if M.SlaveCount >= IecMaxSlaves then
    Exit(res_Busy);
  SlaveInit(M.Slaves[M.SlaveCount], Addr, M.DeadMinMs);
  Inc(M.SlaveCount);
  Result := res_Ok;
end;

{- ------------------------------------------------------------ commands }

function IecStartInterrogation(var M: tIecMaster; Addr, Ca: Word; Qoi: Byte): Boolean;
begin
  Result := JoinAuto(M, Addr, Ca, C_IC_NA_1, Qoi) or StartWith(M, Addr, Ca, C_IC_NA_1, Qoi, True);
end;

function IecStartCounterInterrogation(var M: tIecMaster; Addr, Ca: Word; Qcc: Byte): Boolean;
begin
  Result := JoinAuto(M, Addr, Ca, C_CI_NA_1, Qcc) or StartWith(M, Addr, Ca, C_CI_NA_1, Qcc, True);
end;

function IecStartRead(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord): Boolean;
begin
  Result := Start(M, Addr, Ca, C_RD_NA_1, IecObject(Ioa), False, False, False);
end;

function IecStartClockSync(var M: tIecMaster; Addr, Ca: Word; const T: tIecTime; Delay: Boolean): Boolean;
var
  O: tIecObject;
begin
  O := IecObject(0);
  O.Time := T;
  { 104 does not use delay acquisition (IEC 60870-5-104 clause 8) }
  Result := Start(M, Addr, Ca, C_CS_NA_1, O, False, False, Delay and not M.Over104);
end;

function IecStartTest(var M: tIecMaster; Addr, Ca: Word): Boolean;
var
  O: tIecObject;
begin
  if not M.Over104 then
    Exit(StartWith(M, Addr, Ca, C_TS_NA_1, Fbp_Test, False));
  { 104 tests with the time tag: C_TS_TA_1, TSC and CP56 }
  Inc(M.TestCount);
  O := IecObject(0);
  O.Int := M.TestCount and $FFFF;
  O.Time := IecTimeFromDateTime(Now);
  Result := Start(M, Addr, Ca, C_TS_TA_1, O, False, False, False);
end;

function IecStartResetProcess(var M: tIecMaster; Addr, Ca: Word; Qrp: Byte): Boolean;
begin
  Result := StartWith(M, Addr, Ca, C_RP_NA_1, Qrp, False);
end;

function IecStartCommand(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo: Boolean): Boolean;
begin
  if not (IecTypeKind(Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled,
    ikSetFloat, ikBitsCmd]) then
  begin
    if (M.Cmd.Phase = cpNone) or (M.Cmd.Phase = cpDone) then
    begin
      M.Cmd.Phase := cpDone;
      M.Cmd.Result := res_AsduType;
      M.Cmd.Err := 'type ' + IntToStr(Ti) + ' (' + IecTypeName(Ti) + ') is no command of 45..51, 58..64';
    end;
    Exit(False);
  end;
  { C_BO has no S/E bit: no select stage }
  Result := Start(M, Addr, Ca, Ti, Obj, Sbo and (IecTypeKind(Ti) <> ikBitsCmd), False, False);
end;

function StartParam(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Ioa: LongWord;
  Int: LongInt; Number: Double; Qu: Byte): Boolean;
var
  O: tIecObject;
begin
  O := IecObject(Ioa);
  O.Int := Int;
  O.Number := Number;
  O.Qu := Qu;
  Result := Start(M, Addr, Ca, Ti, O, False, False, False);
end;

function IecStartParamNormal(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): Boolean;
begin
  Result := StartParam(M, Addr, Ca, P_ME_NA_1, Ioa, 0, Value, Qpm);
end;

function IecStartParamScaled(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: LongInt; Qpm: Byte): Boolean;
begin
  Result := StartParam(M, Addr, Ca, P_ME_NB_1, Ioa, Value, 0, Qpm);
end;

function IecStartParamFloat(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): Boolean;
begin
  Result := StartParam(M, Addr, Ca, P_ME_NC_1, Ioa, 0, Value, Qpm);
end;

function IecStartParamActivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): Boolean;
begin
  Result := StartParam(M, Addr, Ca, P_AC_NA_1, Ioa, Qpa, 0, 0);
end;

function IecStartParamDeactivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): Boolean;
var
  E: ShortString;
begin
  Result := StartParam(M, Addr, Ca, P_AC_NA_1, Ioa, Qpa, 0, 0);
  if Result then
  begin
    { the same ASDU with COT 8 (it encoded with COT 6: it encodes) }
    M.Cmd.Deact := True;
    BeginStage(M, stMain, E);
  end;
end;

function IecStartAsdu(var M: tIecMaster; Addr: Word; const Asdu: array of Byte; Len: Word): Boolean;
begin
  Result := False;
  if not IecCommandDone(M) then
  begin
    M.Cmd.Err := 'ASDU: a command is under way (' + CmdName(M) + ')';
    Exit;
  end;
  FillChar(M.Cmd, SizeOf(M.Cmd), 0);
  M.Cmd.Raw := True;
  M.Cmd.Stage := stMain;
  M.Cmd.Slave := IecMasterSlave(M, Addr);
  if (Len >= 1) and (Len <= Length(Asdu)) then
    M.Cmd.Ti := Asdu[0];
  if M.Cmd.Slave < 0 then
    Finish(M, res_IecNoSlave, 'no slave with link address ' + IntToStr(Addr))
  else if (Len < 1) or (Len > Length(Asdu)) or (Len > IecMaxAsdu) then
    Finish(M, res_AsduLength, 'an ASDU of ' + IntToStr(Len) + ' octets')
  else
  begin
    Move(Asdu[0], M.CmdAsdu[0], Len);
    M.CmdLen := Len;
    M.StageTi := Asdu[0];
    M.Cmd.Result := res_Ok;
    M.Cmd.Phase := cpSend;
    M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
    Result := True;
  end;
end;

{- ------------------------------------------------------------ stepping }

function IecMasterStep(var M: tIecMaster): Boolean;
begin
  if M.Balanced then
    Result := StepBalanced(M)
  else
    Result := StepUnbalanced(M);
  if (M.Cmd.Phase in [cpSend, cpConfirm, cpTerm]) and (ChMsTick > M.Cmd.Deadline) then
    if M.Cmd.Phase = cpSend then
      Finish(M, res_Timeout, 'not sent in ' + IntToStr(M.CommandMs) + ' ms (slave '
        + IecSlaveStateName(M.Slaves[M.Cmd.Slave].State) + ')' + IecLineShowed(M, M.Cmd.Slave))
    else if M.Cmd.Phase = cpConfirm then
      Finish(M, res_Timeout, 'no ACT_CON in ' + IntToStr(M.CommandMs) + ' ms' + IecLineShowed(M, M.Cmd.Slave))
    else
      Finish(M, res_Timeout, 'no ACT_TERM in ' + IntToStr(M.CommandMs) + ' ms' + IecLineShowed(M, M.Cmd.Slave));
  StartAfterInit(M);
end;

function IecMasterWaitEnd(const M: tIecMaster): QWord;
var
  I: Integer;
  T: QWord;
begin
  Result := ChMsTick + QWord(IecTransportWaitMs(M.Link, 50));   { the link's timers }
  if not M.Balanced and (M.Job <> ljNone) then
    { a service under way: no poll starts before it ends, so its own
      deadline is the next (its answer ends the wait sooner) }
    Result := High(QWord)
  else if not M.Balanced then
  begin
    Result := ChMsTick + QWord(M.DeadMaxMs);
    for I := 0 to M.SlaveCount - 1 do
    begin
      with M.Slaves[I] do
        if State = isDead then
          T := RetryAt
        else if State = isOnline then
          T := NextPoll
        else
          T := 0;
      if T < Result then
        Result := T;
    end;
  end;
  if (M.Cmd.Phase in [cpSend, cpConfirm, cpTerm]) and (M.Cmd.Deadline + 1 < Result) then
    Result := M.Cmd.Deadline + 1;
  if (M.Job <> ljNone) and (FT12PrimaryWaitEnd(M.Prim) < Result) then
    Result := FT12PrimaryWaitEnd(M.Prim);
end;

{ Wait for the line or the next due service, or run Idle (one thread). }
procedure WaitABit(var M: tIecMaster; Limit: QWord);
var
  T, Until_: QWord;
begin
  if Assigned(M.Idle) then
  begin
    M.Idle(M.IdleData);
    Exit;
  end;
  T := ChMsTick;
  Until_ := IecMasterWaitEnd(M);
  if Limit < Until_ then
    Until_ := Limit;
  if Until_ > T + 1000 then
    Until_ := T + 1000;
  if Until_ > T then
    ChnWaitAny(Until_ - T);
end;

procedure IecMasterWait(var M: tIecMaster; Limit: QWord);
begin
  WaitABit(M, Limit);
end;

function IecFinish(var M: tIecMaster): tChResult;
begin
  while not IecCommandDone(M) do
    if not IecMasterStep(M) then
      WaitABit(M, M.Cmd.Deadline + 1);
  Result := M.Cmd.Result;
end;

procedure IecPollFor(var M: tIecMaster; Ms: LongInt);
var
  Until_: QWord;
begin
  Until_ := ChMsTick + QWord(Ms);
  while ChMsTick < Until_ do
    if not IecMasterStep(M) then
      WaitABit(M, Until_);
end;

{ A blocking call waits for the master's own interrogation after an end of
  initialisation to end first (a stepped start is refused meanwhile, as
  behind any command). }
procedure AwaitAuto(var M: tIecMaster);
begin
  while M.Cmd.Auto and not IecCommandDone(M) do
    if not IecMasterStep(M) then
      WaitABit(M, M.Cmd.Deadline + 1);
end;

function Blocking(var M: tIecMaster; Started: Boolean): tChResult;
begin
  if Started then
    Result := IecFinish(M)
  else if M.Cmd.Phase = cpDone then
    Result := M.Cmd.Result
  else
    Result := res_IecBusy;
end;

function IecInterrogation(var M: tIecMaster; Addr, Ca: Word; Qoi: Byte): tChResult;
begin
  if JoinAuto(M, Addr, Ca, C_IC_NA_1, Qoi) then
    Exit(Blocking(M, True));
  AwaitAuto(M);
  Result := Blocking(M, IecStartInterrogation(M, Addr, Ca, Qoi));
end;

function IecCounterInterrogation(var M: tIecMaster; Addr, Ca: Word; Qcc: Byte): tChResult;
begin
  if JoinAuto(M, Addr, Ca, C_CI_NA_1, Qcc) then
    Exit(Blocking(M, True));
  AwaitAuto(M);
  Result := Blocking(M, IecStartCounterInterrogation(M, Addr, Ca, Qcc));
end;

function IecRead(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartRead(M, Addr, Ca, Ioa));
end;

function IecClockSync(var M: tIecMaster; Addr, Ca: Word; const T: tIecTime; Delay: Boolean): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartClockSync(M, Addr, Ca, T, Delay));
end;

function IecTestCommand(var M: tIecMaster; Addr, Ca: Word): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartTest(M, Addr, Ca));
end;

function IecResetProcess(var M: tIecMaster; Addr, Ca: Word; Qrp: Byte): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartResetProcess(M, Addr, Ca, Qrp));
end;

function IecCommand(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo: Boolean): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartCommand(M, Addr, Ca, Ti, Obj, Sbo));
end;

function IecParamNormal(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartParamNormal(M, Addr, Ca, Ioa, Value, Qpm));
end;

function IecParamScaled(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: LongInt; Qpm: Byte): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartParamScaled(M, Addr, Ca, Ioa, Value, Qpm));
end;

function IecParamFloat(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Value: Double; Qpm: Byte): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartParamFloat(M, Addr, Ca, Ioa, Value, Qpm));
end;

function IecParamActivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): tChResult;
begin
  AwaitAuto(M);
  Result := Blocking(M, IecStartParamActivation(M, Addr, Ca, Ioa, Qpa));
end;

function IecParamDeactivation(var M: tIecMaster; Addr, Ca: Word; Ioa: LongWord; Qpa: Byte): tChResult;
begin
  Result := Blocking(M, IecStartParamDeactivation(M, Addr, Ca, Ioa, Qpa));
end;

function IecMasterSlaveInfo(const M: tIecMaster; S: LongInt; out Info: tIecSlave): Boolean;
begin
  Result := (S >= 0) and (S < M.SlaveCount);
  if Result then
    Info := M.Slaves[S]
  else
    FillChar(Info, SizeOf(Info), 0);
end;

function IecCommandResult(const M: tIecMaster; out Err: ShortString): tChResult;
begin
  Result := M.Cmd.Result;
  Err := M.Cmd.Err;
end;

function IecMasterLineResult(const M: tIecMaster): tChResult;
begin
  Result := M.LineResult;
end;

initialization
  ChRegisterResultText(Iec101Layer, res_IecNegative, 'negative confirmation');
  ChRegisterResultText(Iec101Layer, res_IecUnknownType, 'unknown type identification (COT 44)');
  ChRegisterResultText(Iec101Layer, res_IecUnknownCot, 'unknown cause of transmission (COT 45)');
  ChRegisterResultText(Iec101Layer, res_IecUnknownCa, 'unknown common address (COT 46)');
  ChRegisterResultText(Iec101Layer, res_IecUnknownIoa, 'unknown information object address (COT 47)');
  ChRegisterResultText(Iec101Layer, res_IecNoSlave, 'no such slave');
  ChRegisterResultText(Iec101Layer, res_IecBusy, 'a command is under way');
end.
