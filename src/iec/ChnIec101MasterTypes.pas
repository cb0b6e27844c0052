{ ChnIec101MasterTypes - the IEC 60870-5-101 master's record (tIecMaster:
  its slaves, its command, the link service under way) and the few
  questions every part of the master asks of it.
  Why a unit of its own: the master's parts (ChnIec101MasterCmd,
  ChnIec101MasterInbound, ChnIec101MasterPoll) take the record in their
  interfaces, and ChnIec101Master uses them; with the record here the
  units form no cycle (fpmake builds them in order). ChnIec101Master
  gives programs the same names again: a program names only it. }
unit ChnIec101MasterTypes;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT12Codec, ChnFT12Link, ChnFT12Primary, ChnIec101Asdu, ChnIecTransport;

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

{ Index of a slave, -1 when not added. }
function IecMasterSlave(const M: tIecMaster; Addr: Word): LongInt;
{ No command under way (none yet, or the last one ended). }
function IecCommandDone(const M: tIecMaster): Boolean;
{ The state's name, and what the line showed of slave index S besides
  its answers, for an error text (ChnIec101Master says more). }
function IecSlaveStateName(S: tIecSlaveState): ShortString;
function IecLineShowed(const M: tIecMaster; S: LongInt): ShortString;

implementation

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

function IecMasterSlave(const M: tIecMaster; Addr: Word): LongInt;
var
  I: Integer;
begin
  for I := 0 to M.SlaveCount - 1 do
    if M.Slaves[I].Addr = Addr then
      Exit(I);
  Result := -1;
end;

function IecCommandDone(const M: tIecMaster): Boolean;
begin
  Result := M.Cmd.Phase in [cpNone, cpDone];
end;

end.
