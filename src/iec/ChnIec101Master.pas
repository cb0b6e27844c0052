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
  slave died), res_IecNoSlave; Cmd.Err names the command and the slave.
  The blocking forms (IecInterrogation ...) start and step to the end.

  Link dependency: the one place that drives an FT 1.2 primary service is
  LinkStart/LinkStep below, on ChnFT12Link's stepped primary: a step never
  waits, so the master serves its line from the program's poll loop (Idle,
  when set, runs between steps of the blocking forms instead of the wait). }
unit ChnIec101Master;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnIec101Asdu, ChnIecTransport;

const
  res_IecNegative    = res_Proto + 8;    {< negative confirmation (P/N = 1) }
  res_IecUnknownType = res_Proto + 9;    {< COT 44 }
  res_IecUnknownCot  = res_Proto + 10;   {< COT 45 }
  res_IecUnknownCa   = res_Proto + 11;   {< COT 46 }
  res_IecUnknownIoa  = res_Proto + 12;   {< COT 47 }
  res_IecNoSlave     = res_Proto + 13;   {< no such slave on this master }
  res_IecBusy        = res_Proto + 14;   {< a command is under way }

  IecMaxSlaves = 32;

type
  tIecSlaveState = (isOffline, isLinkStatus, isOnline, isDead);

  { What the master keeps per slave (link address). }
  tIecSlave = record
    Addr     : Word;
    Link     : tFT12Link;
    State    : tIecSlaveState;
    NextPoll : QWord;      {< no class 2 poll before (ChMsTick) }
    RetryAt  : QWord;      {< dead: next attempt }
    BackoffMs: LongInt;    {< dead: the wait after the next failure }
    {- counters }
    Class1, Class2: LongInt;   {< polls answered }
    Commands : LongInt;    {< user data (commands) confirmed by the link }
    Asdus    : LongInt;    {< ASDUs received }
    Objects  : LongInt;    {< information objects passed to OnObject }
    BadAsdus : LongInt;    {< malformed ASDUs }
    Failures : LongInt;    {< services without an answer }
    Deaths   : LongInt;    {< times marked dead }
    Resets   : LongInt;    {< link resets acknowledged }
    Probation: Boolean;    {< died, and no class poll or command answered since }
    PolledAt : QWord;      {< the last class poll left (ChMsTick) }
    EndOfInits: LongInt;   {< end of initialisation ASDUs (M_EI_NA_1, COT 4) }
    LastCoi  : Byte;       {< the COI of the last one }
    InitGi, InitCi: Boolean;   {< interrogations due after one }
    InitCa   : Word;
  end;

  tIecObjectFunc = procedure(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
  tIecBadFunc = procedure(Data: Pointer; Addr: Word; const Err: ShortString);
  { A slave's end of initialisation: its common address and COI. }
  tIecInitFunc = procedure(Data: Pointer; Addr, Ca: Word; Coi: Byte);
  { An ASDU of file transfer (types 120..127) from slave Addr, undecoded. }
  tIecFileAsduFunc = procedure(Data: Pointer; Addr: Word; const Buf: array of Byte; Len: Word);

  tIecCmdPhase = (cpNone, cpSend, cpConfirm, cpTerm, cpDone);
  { what the link service under way is for }
  tIecLinkJob = (ljNone, ljStatus, ljReset, ljCommand, ljClass1, ljClass2);
  tIecCmdStage = (stDelayAct, stDelaySend, stSelect, stMain);

  { The command under way. }
  tIecCommand = record
    Phase   : tIecCmdPhase;
    Stage   : tIecCmdStage;
    Slave   : LongInt;     {< index in Slaves }
    Ti      : Byte;        {< type of the main command }
    Ca      : Word;
    Obj     : tIecObject;  {< its object (IOA, value, qualifier) }
    Sbo     : Boolean;     {< select before operate }
    WaitTerm: Boolean;     {< ends on ACT_TERM (interrogations) }
    Delay   : Boolean;     {< clock sync: delay acquisition first }
    SentAt  : QWord;       {< the current stage left }
    Deadline: QWord;
    DelayMs : LongInt;     {< the delay measured (clock sync with delay) }
    Result  : tChResult;
    Err     : ShortString;
    Auto    : Boolean;     {< the master's own, after an end of initialisation }
    Raw     : Boolean;     {< an ASDU of another procedure (IecStartAsdu): done once sent }
    Deact   : Boolean;     {< a deactivation (COT 8): ends on its DEACT_CON }
  end;

  tIecMaster = record
    Chn      : pChnVirt;
    Params   : tIecParams;
    Balanced : Boolean;
    Slaves   : array[0..IecMaxSlaves - 1] of tIecSlave;
    SlaveCount: LongInt;
    Turn     : LongInt;    {< the slave whose turn it is }
    Over104  : Boolean;    {< on an IEC104 channel (Balanced too: no link polling) }
    TestCount: LongInt;    {< 104: TSC of the last C_TS_TA_1 }
    Link     : tIecTransport;   {< balanced FT 1.2 link or IEC 104 }
    {- settings }
    TimeoutMs: LongInt;    {< link answer (FT12LinkTimeoutMs) }
    Retries  : LongInt;    {< link repetitions (FT12LinkRetries) }
    CycleMs  : LongInt;    {< class 2 polls of a slave that had no data at most this often (100) }
    PollBurst: LongInt;    {< services in a row for a slave with data before the turn passes (3) }
    DeadMinMs, DeadMaxMs: LongInt;   {< back-off of a dead slave (1000, 30000) }
    CommandMs: LongInt;    {< confirmation of a command (10000) }
    OnObject : tIecObjectFunc;
    OnSent   : tIecObjectFunc;   {< each command object as it goes out (nil: none) }
    OnBad    : tIecBadFunc;
    OnEndOfInit: tIecInitFunc;   {< a slave's end of initialisation (nil: none) }
    NoGiAfterInit: Boolean;      {< do not interrogate a slave after its end of initialisation }
    CiAfterInit: Byte;     {< QCC of a counter interrogation after it too (0: none) }
    { file transfer (ChnIecFileClient): its ASDUs go here, not to OnObject
      (nil: counted as ASDUs of an unknown type, BadAsdus) }
    OnFileAsdu: tIecFileAsduFunc;
    FileData : Pointer;
    Data     : Pointer;
    Idle     : tFT12Idle;  {< blocking forms: called instead of waiting (tests: the slave) }
    IdleData : Pointer;
    Cmd      : tIecCommand;
    { counters and the last trouble }
    Asdus, Objects, BadAsdus, EndOfInits: LongInt;
    LastBad  : ShortString;
    LineResult: tChResult; {< the channel failed (res_DeviceLost ...), else res_Ok }
    { the link service under way (unbalanced) }
    Job      : tIecLinkJob;
    JobSlave : LongInt;
    LinkResult: tChResult;
    Prim     : tFT12Primary;
    Rep      : tFT12MaxRecord;
    RepLen   : Word;
    Run      : LongInt;    {< services in a row of the slave whose turn it is }
    { the ASDU of the command's stage under way, encoded once as the stage
      begins (BeginStage) and sent as it is (again after a busy NACK); its
      type, cause and object for OnSent and for matching the answers }
    CmdAsdu  : array[0..IecMaxAsdu - 1] of Byte;
    CmdLen   : Word;
    StageTi, StageCot: Byte;
    StageObj : tIecObject;
  end;
  pIecMaster = ^tIecMaster;

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
  SysUtils, ChnWait, ChnFT12Codec;

function IecSlaveStateName(S: tIecSlaveState): ShortString;
begin
  case S of
    isOffline: Result := 'OFFLINE';
    isLinkStatus: Result := 'LINK_STATUS';
    isOnline: Result := 'ONLINE';
  else
    Result := 'DEAD';
  end;
end;

function IecLineShowed(const M: tIecMaster; S: LongInt): ShortString;
begin
  if M.Over104 then
    Result := ''                         { TCP: no link addresses, no DIR }
  else if M.Balanced then
    Result := FT12IgnoredText(M.Link.Bal.OtherAddr, M.Link.Bal.OtherLast, M.Link.Bal.BadDir)
  else if (S >= 0) and (S < M.SlaveCount) then
    Result := FT12IgnoredText(M.Slaves[S].Link.OtherAddr, M.Slaves[S].Link.OtherLast, 0)
  else
    Result := '';
end;

procedure SlaveInit(var S: tIecSlave; Addr: Word; BackoffMs: LongInt);
begin
  FillChar(S, SizeOf(S), 0);
  S.Addr := Addr;
  FT12LinkInit(S.Link, Addr);
  S.BackoffMs := BackoffMs;
end;

function OnBalancedData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean; forward;

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

function IecMasterSlave(const M: tIecMaster; Addr: Word): LongInt;
var
  I: Integer;
begin
  for I := 0 to M.SlaveCount - 1 do
    if M.Slaves[I].Addr = Addr then
      Exit(I);
  Result := -1;
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

function CmdName(const M: tIecMaster): ShortString;
begin
  Result := IecTypeName(M.Cmd.Ti);
  if Result = '' then
    Result := 'ASDU type ' + IntToStr(M.Cmd.Ti);
  if IecTypeKind(M.Cmd.Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled,
    ikSetFloat, ikBitsCmd, ikRead] then
    Result := Result + ' IOA ' + IntToStr(M.Cmd.Obj.Ioa);
  if M.Cmd.Slave >= 0 then
    Result := Result + ' to slave ' + IntToStr(M.Slaves[M.Cmd.Slave].Addr);
end;

procedure Finish(var M: tIecMaster; R: tChResult; const Text: ShortString);
begin
  M.Cmd.Phase := cpDone;
  M.Cmd.Result := R;
  if R = res_Ok then
    M.Cmd.Err := ''
  else
    M.Cmd.Err := CmdName(M) + ': ' + Text;
end;

{ Stage St of the command begins: its ASDU is encoded, once, into
  M.CmdAsdu (res_AsduParam ... with Err: it cannot be sent). The delay
  acquisition carries the time it began (SDT), the delay sent the one
  measured; a clock synchronisation after them the time it begins at
  (the slave adds the delay). }
function BeginStage(var M: tIecMaster; St: tIecCmdStage; out Err: ShortString): tChResult;
var
  O: tIecObject;
begin
  M.Cmd.Stage := St;
  M.Cmd.Phase := cpSend;
  O := M.Cmd.Obj;
  M.StageTi := M.Cmd.Ti;
  M.StageCot := Cot_Activation;
  case St of
    stDelayAct:
      begin
        M.StageTi := C_CD_NA_1;
        O := IecObject(0);
        O.Elapsed := ChMsTick mod 60000;
      end;
    stDelaySend:
      begin
        M.StageTi := C_CD_NA_1;
        M.StageCot := Cot_Spontaneous;
        O := IecObject(0);
        O.Elapsed := M.Cmd.DelayMs;
      end;
    stSelect: O.Select := True;
    stMain:
      begin
        { the execute after a select; alone, what the caller gave (a
          gateway passes a control centre's select on as a select) }
        O.Select := O.Select and not M.Cmd.Sbo;
        if M.Cmd.Ti = C_RD_NA_1 then
          M.StageCot := Cot_Request
        else if M.Cmd.Deact then
          M.StageCot := Cot_Deactivation
        else if (M.Cmd.Ti = C_CS_NA_1) and M.Cmd.Delay then
        begin
          O.Time := IecTimeFromDateTime(Now);
          M.Cmd.Obj.Time := O.Time;
        end;
      end;
  end;
  M.StageObj := O;
  Result := IecEncodeOne(M.Params, M.StageTi, M.StageCot, M.Cmd.Ca, O, M.CmdAsdu, M.CmdLen, Err);
end;

function Start(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo, WaitTerm, Delay: Boolean): Boolean;
var
  E: ShortString;
  R: tChResult;
begin
  if not IecCommandDone(M) then
  begin
    { keep the command under way; say why this one was refused }
    M.Cmd.Err := IecTypeName(Ti) + ': a command is under way (' + CmdName(M) + ')';
    Exit(False);
  end;
  FillChar(M.Cmd, SizeOf(M.Cmd), 0);
  M.Cmd.Ti := Ti;
  M.Cmd.Ca := Ca;
  M.Cmd.Obj := Obj;
  M.Cmd.Sbo := Sbo;
  M.Cmd.WaitTerm := WaitTerm;
  M.Cmd.Delay := Delay;
  M.Cmd.Slave := IecMasterSlave(M, Addr);
  if M.Cmd.Slave < 0 then
  begin
    Finish(M, res_IecNoSlave, 'no slave with link address ' + IntToStr(Addr));
    Exit(False);
  end;
  { a command that does not encode is refused now. The first stage is
    checked: the stages after it (the execute after its select, the delay
    and the time after a delay acquisition) have the same common address
    and object, their own values taken as they come }
  if Sbo then
    R := BeginStage(M, stSelect, E)
  else if Delay then
    R := BeginStage(M, stDelayAct, E)
  else
    R := BeginStage(M, stMain, E);
  if R <> res_Ok then
  begin
    Finish(M, R, E);
    Exit(False);
  end;
  M.Cmd.Result := res_Ok;
  M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
  Result := True;
end;

{ A command whose element is one number (a qualifier, the test pattern). }
function StartWith(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Value: LongInt;
  WaitTerm: Boolean): Boolean;
var
  O: tIecObject;
begin
  O := IecObject(0);
  O.Int := Value;
  Result := Start(M, Addr, Ca, Ti, O, False, WaitTerm, False);
end;

{ The master's own interrogation after an end of initialisation is the
  one the program asks for: it takes it over. }
function JoinAuto(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Q: Byte): Boolean;
begin
  Result := M.Cmd.Auto and not IecCommandDone(M) and (M.Cmd.Ti = Ti) and
    (M.Cmd.Obj.Int = Q) and (M.Cmd.Ca = Ca) and (M.Slaves[M.Cmd.Slave].Addr = Addr);
  if Result then
    M.Cmd.Auto := False;
end;

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

function IecCommandDone(const M: tIecMaster): Boolean;
begin
  Result := M.Cmd.Phase in [cpNone, cpDone];
end;

{ The stage answered positively: on to the next, or done. }
procedure StageConfirmed(var M: tIecMaster);
var
  R: tChResult;
  E: ShortString;
begin
  R := res_Ok;
  case M.Cmd.Stage of
    stDelayAct:
      begin
        M.Cmd.DelayMs := (ChMsTick - M.Cmd.SentAt) div 2;
        R := BeginStage(M, stDelaySend, E);
      end;
    stDelaySend, stSelect:
      R := BeginStage(M, stMain, E);
  else
    if M.Cmd.WaitTerm then
      M.Cmd.Phase := cpTerm
    else
      Finish(M, res_Ok, '');
  end;
  if R <> res_Ok then
    Finish(M, R, E);                    { cannot happen: the first stage encoded }
end;

{ Does a command of type Ti carry the S/E bit? }
function HasSelectBit(Ti: Byte): Boolean;
begin
  Result := IecTypeKind(Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat];
end;

{ An ASDU from slave index S: does it answer the command? }
procedure MatchCommand(var M: tIecMaster; S: Integer; const H: tIecAsdu; const O: tIecObject);
var
  Ti: Byte;
  Want: tIecObject;
  What: ShortString;
begin
  if (M.Cmd.Slave <> S) or not (M.Cmd.Phase in [cpConfirm, cpTerm]) then
    Exit;
  Ti := M.StageTi;
  Want := M.StageObj;
  if H.Ca <> M.Cmd.Ca then
    Exit;
  if (M.Cmd.Ti = C_RD_NA_1) and (M.Cmd.Stage = stMain) and (H.Cot = Cot_Request)
    and (O.Ioa = Want.Ioa) and (H.Ti <> C_RD_NA_1) then
  begin
    Finish(M, res_Ok, '');
    Exit;
  end;
  if (H.Ti <> Ti) or (O.Ioa <> Want.Ioa) then
    Exit;
  { a confirmation mirrors the command: the S/E bit of this stage (an
    execute's ACT_CON confirms no select), and T = 0 (this master sends no
    test-mode commands) }
  if H.Test or (HasSelectBit(Ti) and (O.Select <> Want.Select)) then
    Exit;
  What := 'COT ' + IntToStr(H.Cot) + ' ' + IecCotName(H.Cot);
  case H.Cot of
    Cot_ActCon, Cot_DeactCon:
      if (H.Cot = Cot_DeactCon) <> M.Cmd.Deact then
        Exit                             { the confirmation of the other cause }
      else if H.Negative then
        Finish(M, res_IecNegative, BoolToStr(M.Cmd.Deact, 'negative DEACT_CON', 'negative ACT_CON'))
      else if M.Cmd.Phase = cpConfirm then
        StageConfirmed(M);
    Cot_ActTerm:
      { before this command's ACT_CON a termination is the last one's (it
        follows its confirmation in the slave's queue): not an answer }
      if M.Cmd.Phase <> cpTerm then
        Exit
      else if H.Negative then
        Finish(M, res_IecNegative, 'negative ACT_TERM')
      else
        Finish(M, res_Ok, '');
    Cot_UnknownType: Finish(M, res_IecUnknownType, 'the slave does not know the type (' + What + ')');
    Cot_UnknownCause: Finish(M, res_IecUnknownCot, 'the slave does not know the cause (' + What + ')');
    Cot_UnknownCa: Finish(M, res_IecUnknownCa, 'the slave does not know common address '
      + IntToStr(H.Ca) + ' (' + What + ')');
    Cot_UnknownIoa: Finish(M, res_IecUnknownIoa, 'the slave does not know IOA '
      + IntToStr(O.Ioa) + ' (' + What + ')');
  end;
end;

{ Slave index S has initialised (M_EI_NA_1, COT 4): tell the program;
  its data may all have changed - interrogate it (and its counters) when
  no command is under way, unless told not to. }
procedure EndOfInit(var M: tIecMaster; S: Integer; Ca: Word; Coi: Byte);
begin
  Inc(M.EndOfInits);
  with M.Slaves[S] do
  begin
    Inc(EndOfInits);
    LastCoi := Coi;
    InitCa := Ca;
    InitGi := not M.NoGiAfterInit;
    InitCi := not M.NoGiAfterInit and (M.CiAfterInit <> 0);
    { an interrogation of this slave not yet confirmed is answered after
      the initialisation: it is the one that follows it }
    if (M.Cmd.Slave = S) and (M.Cmd.Phase in [cpSend, cpConfirm]) then
      if M.Cmd.Ti = C_IC_NA_1 then
        InitGi := False
      else if M.Cmd.Ti = C_CI_NA_1 then
        InitCi := False;
  end;
  if Assigned(M.OnEndOfInit) then
    M.OnEndOfInit(M.Data, M.Slaves[S].Addr, Ca, Coi);
end;

{ The interrogations due after an end of initialisation, one at a time,
  when the program has no command under way. }
procedure StartAfterInit(var M: tIecMaster);
var
  I: Integer;
begin
  if not IecCommandDone(M) then
    Exit;
  for I := 0 to M.SlaveCount - 1 do
    with M.Slaves[I] do
      if InitGi or InitCi then
      begin
        if InitGi then
        begin
          InitGi := False;
          if StartWith(M, Addr, InitCa, C_IC_NA_1, Qoi_Station, True) then
            M.Cmd.Auto := True;
        end
        else
        begin
          InitCi := False;
          if StartWith(M, Addr, InitCa, C_CI_NA_1, M.CiAfterInit, True) then
            M.Cmd.Auto := True;
        end;
        Exit;
      end;
end;

{ An ASDU received from slave index S. }
procedure TakeAsdu(var M: tIecMaster; S: Integer; const Buf: array of Byte; Len: Word);
var
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
  I: Integer;
begin
  Inc(M.Asdus);
  Inc(M.Slaves[S].Asdus);
  if (Len > 0) and (Buf[0] >= 120) and (Buf[0] <= 127) and Assigned(M.OnFileAsdu) then
  begin
    M.OnFileAsdu(M.FileData, M.Slaves[S].Addr, Buf, Len);   { file transfer }
    Exit;
  end;
  if IecDecodeHeader(M.Params, Buf, Len, H, E) <> res_Ok then
  begin
    Inc(M.BadAsdus);
    Inc(M.Slaves[S].BadAsdus);
    M.LastBad := 'slave ' + IntToStr(M.Slaves[S].Addr) + ': ' + E;
    if Assigned(M.OnBad) then
      M.OnBad(M.Data, M.Slaves[S].Addr, M.LastBad);
    Exit;
  end;
  for I := 0 to H.Count - 1 do
  begin
    IecDecodeObject(M.Params, H, Buf, I, O);
    Inc(M.Objects);
    Inc(M.Slaves[S].Objects);
    if Assigned(M.OnObject) then
      M.OnObject(M.Data, M.Slaves[S].Addr, H, O);
    if I = 0 then
      MatchCommand(M, S, H, O);
    if (H.Ti = M_EI_NA_1) and (H.Cot = Cot_Initialized) then
      EndOfInit(M, S, H.Ca, O.Int);
  end;
end;

{ The current stage went out to slave index S: tell OnSent. }
procedure StageSent(var M: tIecMaster; S: Integer);
var
  H: tIecAsdu;
begin
  if not Assigned(M.OnSent) or M.Cmd.Raw then
    Exit;
  FillChar(H, SizeOf(H), 0);
  H.Ti := M.StageTi;
  H.Count := 1;
  H.Cot := M.StageCot;
  H.Ca := M.Cmd.Ca;
  M.OnSent(M.Data, M.Slaves[S].Addr, H, M.StageObj);
end;

{- ------------------------------------------------------------ unbalanced }

{ The one place that drives an FT 1.2 primary service. LinkStart starts
  FC with Len octets of user data (an ASDU) to slave S for Job; LinkStep
  takes what has arrived, without waiting, and is True once the service is
  over (M.LinkResult, the reply in M.Rep/M.RepLen): ChnFT12Link's stepped
  primary (FT12PrimaryStart/Step). }
procedure LinkStart(var M: tIecMaster; S: LongInt; Job: tIecLinkJob; FC: Byte;
  const Asdu: array of Byte; Len: Word; Retries: LongInt);
var
  Req: tSendRecord;
begin
  FillChar(Req, SizeOf(Req), 0);
  if Len > 0 then
  begin
    Req.MessType := tpLongM;
    Move(Asdu[0], Req.Data[1], Len);
  end
  else
  begin
    Req.MessType := tpShortM;
    Len := pChnFT1_2(M.Chn)^.ChFT12Config.FixedLen;   { a fixed frame: LEN= zero octets }
  end;
  Req.FC := FC;
  M.Job := Job;
  M.JobSlave := S;
  { False: nothing sent, the service is over at once (Prim.Result says why) }
  FT12PrimaryStart(M.Prim, M.Chn, M.Slaves[S].Link, Req, cSizeHeadSndMsg + Len, M.TimeoutMs, Retries);
end;

function LinkStep(var M: tIecMaster): Boolean;
begin
  Result := (M.Job <> ljNone) and FT12PrimaryStep(M.Prim);
  if Result then
  begin
    M.LinkResult := M.Prim.Result;
    M.RepLen := M.Prim.RepLen;
    if M.RepLen > 0 then
      M.Rep := M.Prim.Rep;
  end;
end;

procedure SlaveFailed(var M: tIecMaster; S: Integer; R: tChResult);
var
  Sl: ^tIecSlave;
  E: ShortString;
begin
  Sl := @M.Slaves[S];
  Inc(Sl^.Failures);
  if (R <> res_Timeout) and (R <> res_BadMessage) then
    M.LineResult := R;                   { the channel itself failed }
  if R = res_BadMessage then
  begin
    Sl^.State := isOffline;              { an answer that does not fit: set the link up again }
    Exit;
  end;
  { a slave that failed again before it answered a poll (dead, or set up
    again after it) waits twice as long; a healthy one just died }
  if not Sl^.Probation then
    Inc(Sl^.Deaths)
  else if Sl^.BackoffMs < M.DeadMaxMs then
    Sl^.BackoffMs := Sl^.BackoffMs * 2;
  Sl^.Probation := True;
  if Sl^.BackoffMs > M.DeadMaxMs then
    Sl^.BackoffMs := M.DeadMaxMs;
  Sl^.State := isDead;
  Sl^.RetryAt := ChMsTick + QWord(Sl^.BackoffMs);
  if (M.Cmd.Slave = S) and not IecCommandDone(M) then
  begin
    E := IecLineShowed(M, S);
    if E <> '' then
      E := ': no answer from link address ' + IntToStr(Sl^.Addr) + E;
    Finish(M, res_Timeout, 'slave does not answer (' + ChResultText(R) + ')' + E);
  end;
end;

{ A class poll or a command was answered: the slave serves again. (A
  status or reset answer alone does not count: a slave may answer those
  and never a poll.) }
procedure SlaveServes(var M: tIecMaster; S: Integer);
begin
  M.Slaves[S].Probation := False;
  M.Slaves[S].BackoffMs := M.DeadMinMs;
end;

{ Is slave S due for a service now? }
function Due(const M: tIecMaster; S: Integer; Now_: QWord): Boolean;
begin
  with M.Slaves[S] do
    case State of
      isDead: Result := Now_ >= RetryAt;
      isOnline: Result := (Now_ >= NextPoll) or ((M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend));
    else
      Result := True;
    end;
end;

{ Start the service slave S is due for. }
procedure Serve(var M: tIecMaster; S: LongInt);
var
  Buf: array[0..0] of Byte;
  Sl: ^tIecSlave;
  Retries: LongInt;
begin
  Sl := @M.Slaves[S];
  Buf[0] := 0;                          { fixed frames carry none of it }
  Retries := M.Retries;
  if Sl^.Probation then
    Retries := 0;                       { one try: the others wait one timeout only }
  case Sl^.State of
    isOffline, isDead: LinkStart(M, S, ljStatus, FCM_ReqLinkState, Buf, 0, Retries);
    isLinkStatus: LinkStart(M, S, ljReset, FCM_1stSetTransmit, Buf, 0, Retries);
  else
    if (M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend) then
    begin
      M.Cmd.SentAt := ChMsTick;
      LinkStart(M, S, ljCommand, FCM_UserDataReply, M.CmdAsdu, M.CmdLen, Retries);
    end
    else
    begin
      Sl^.PolledAt := ChMsTick;
      if Sl^.Link.Acd then
        LinkStart(M, S, ljClass1, FCM_ReqUserData1, Buf, 0, Retries)
      else
        LinkStart(M, S, ljClass2, FCM_ReqUserData2, Buf, 0, Retries);
    end;
  end;
end;

{ The turn goes to the slave after S. }
procedure PassTurn(var M: tIecMaster; S: LongInt);
begin
  M.Turn := (S + 1) mod M.SlaveCount;
  M.Run := 0;
end;

{ The service under way is over: act on its answer. }
procedure Complete(var M: tIecMaster);
var
  S: LongInt;
  Sl: ^tIecSlave;
  Job: tIecLinkJob;
  Data: Boolean;
begin
  S := M.JobSlave;
  Sl := @M.Slaves[S];
  Job := M.Job;
  M.Job := ljNone;
  if M.LinkResult <> res_Ok then
  begin
    SlaveFailed(M, S, M.LinkResult);
    if Job <> ljCommand then
      PassTurn(M, S);
    Exit;
  end;
  Data := False;
  case Job of
    ljStatus:
      Sl^.State := isLinkStatus;        { dead or not: set its link up (again) }
    ljReset:
      begin
        Inc(Sl^.Resets);
        Sl^.State := isOnline;
        Sl^.NextPoll := 0;
      end;
    ljCommand:
      if (M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend)
        and ((M.Rep.MessType = tpSACK) or (M.Rep.FC = FCS_Ack)) then
      begin
        SlaveServes(M, S);
        Inc(Sl^.Commands);
        StageSent(M, S);
        if (M.Cmd.Stage = stDelaySend) or M.Cmd.Raw then
          StageConfirmed(M)             { the delay is no activation: nothing confirms it }
        else
        begin
          M.Cmd.Phase := cpConfirm;
          M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
        end;
      end;
      { a NACK (busy): sent again at the next turn }
    ljClass1, ljClass2:
      begin
        SlaveServes(M, S);
        if Job = ljClass1 then
          Inc(Sl^.Class1)
        else
          Inc(Sl^.Class2);
        Data := (M.Rep.MessType = tpLongM) and (M.Rep.FC = FCS_UserData) and (M.RepLen > cSizeHeadRecMsg);
        if Data then
          TakeAsdu(M, S, M.Rep.Data, M.RepLen - cSizeHeadRecMsg);
        { more data (ACD, or class 2 had some): polled again at once;
          none: not before CycleMs after this poll }
        Data := Data or Sl^.Link.Acd;
        if Data then
          Sl^.NextPoll := 0
        else
          Sl^.NextPoll := Sl^.PolledAt + QWord(M.CycleMs);
      end;
  end;
  if Sl^.Link.Acd then
    Sl^.NextPoll := 0;                  { class 1 waits (a command's ACT_CON ...) }
  { a command jumps the queue: the turn stays where it was }
  if Job = ljCommand then
    Exit;
  { a slave with data keeps the turn for PollBurst services at most; the
    link set up (status, reset) takes a turn each }
  if S <> M.Turn then
  begin
    M.Turn := S;                        { the ones before it had nothing due }
    M.Run := 0;
  end;
  Inc(M.Run);
  if not Data or (M.Run >= M.PollBurst) then
    PassTurn(M, S);
end;

function StepUnbalanced(var M: tIecMaster): Boolean;
var
  I, S: LongInt;
  T: QWord;
begin
  Result := False;
  if M.Job <> ljNone then
  begin
    { a service under way: done yet? }
    if LinkStep(M) then
    begin
      Complete(M);
      Result := True;
    end;
    Exit;
  end;
  if M.SlaveCount = 0 then
    Exit;
  T := ChMsTick;
  { the command's slave first while it has something to send }
  S := -1;
  if (M.Cmd.Phase = cpSend) and (M.Cmd.Slave >= 0) and Due(M, M.Cmd.Slave, T) then
    S := M.Cmd.Slave
  else
    for I := 0 to M.SlaveCount - 1 do
      if Due(M, (M.Turn + I) mod M.SlaveCount, T) then
      begin
        S := (M.Turn + I) mod M.SlaveCount;
        Break;
      end;
  if S < 0 then
    Exit;
  Serve(M, S);
  if (M.Job <> ljNone) and LinkStep(M) then
    Complete(M);
  Result := True;
end;

{- ------------------------------------------------------------ balanced }

function OnBalancedData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  M: pIecMaster;
begin
  M := pIecMaster(Data);
  if Len > 0 then
    TakeAsdu(M^, 0, PByteArray(Buf)^[0..Len - 1], Len)
  else
    TakeAsdu(M^, 0, M^.Rep.Data, 0);
  Result := True;
end;

function StepBalanced(var M: tIecMaster): Boolean;
var
  R: tChResult;
begin
  Result := IecTransportStep(M.Link);
  if M.Chn^.ChResult <> res_Ok then
    M.LineResult := M.Chn^.ChResult;
  if IecTransportUp(M.Link) then
    M.Slaves[0].State := isOnline
  else
    M.Slaves[0].State := isOffline;
  if (M.Cmd.Phase = cpSend) and IecTransportUp(M.Link) and IecTransportRoom(M.Link) then
  begin
    R := IecTransportSend(M.Link, @M.CmdAsdu, M.CmdLen);
    if R = res_Ok then
    begin
      Inc(M.Slaves[0].Commands);
      StageSent(M, 0);
      M.Cmd.SentAt := ChMsTick;
      if (M.Cmd.Stage = stDelaySend) or M.Cmd.Raw then
        StageConfirmed(M)
      else
      begin
        M.Cmd.Phase := cpConfirm;
        M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
      end;
    end
    else
      Finish(M, R, 'the link refused the ASDU of ' + IntToStr(M.CmdLen) + ' octets ('
        + ChResultText(R) + ')');
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
  if not M.Balanced then
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
