{ ChnIec101SlaveTypes - the IEC 60870-5-101 slave's record
  (tIecSlaveStation: its point table, its class 1 and class 2 queues, the
  interrogation, selection and deferred commands under way) and its
  callbacks.
  Why a unit of its own: the slave's parts (ChnIec101SlaveQueue,
  ChnIec101SlavePoints, ChnIec101SlaveGi, ChnIec101SlaveCommands,
  ChnIec101SlaveParams) take the record in their interfaces, and
  ChnIec101Slave uses them; with the record here the units form no cycle
  (fpmake builds them in order). ChnIec101Slave gives programs the same
  names again: a program names only it. }
unit ChnIec101SlaveTypes;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT12Station, ChnIec101Asdu, ChnIecTransport, ChnIecFileServer;

const
  IecSlaveMaxPoints = 1024;
  IecSlavePointStep = 64;        {< the point table grows by so many points }
  IecSlaveQueueLen  = 64;        {< ASDUs waiting per class }
  IecSlaveSelectMs  = 10000;     {< default select-before-operate timeout }
  IecSlaveMaxDeferred = 16;      {< commands waiting for IecSlaveConfirm at once }

type
  { One entry of the point table. }
  tIecPoint = record
    Ti    : Byte;         {< monitoring type (1..21, 30..40) or command type (45..51, 58..64) }
    Group : Byte;         {< interrogation group 1..16 (counters 1..4), 0 = station only }
    Obj   : tIecObject;   {< IOA, value, quality, time (see ChnIec101Asdu.tIecKind) }
    Frozen: tIecObject;   {< counters: the value of the last freeze }
    HasFrozen: Boolean;
    Par   : array[Kpa_Threshold..Kpa_High] of Double;   {< parameters loaded (P_ME_NA/NB/NC_1) }
    ParSet: Byte;         {< bit KPA set: Par[KPA] loaded }
    ParOn : Boolean;      {< the parameters are in operation (POP 0, or P_AC_NA_1) }
    Reported: Double;     {< the value of the last spontaneous report (the deadband's base) }
    HasReported: Boolean;
    Filtered: Double;     {< the smoothing filter's value (ChnIecMeasParams) }
    HasFiltered: Boolean; {< False: it starts from the table's value }
    EventTi: Byte;        {< type of its spontaneous events (IecSlaveEventType), 0: Ti }
  end;
  pIecPoint = ^tIecPoint;

  tIecQueued = record
    Len : Word;
    Data: array[0..IecMaxAsdu - 1] of Byte;
  end;

  tIecQueue = record
    Items: array[0..IecSlaveQueueLen - 1] of tIecQueued;
    Head, Count: LongInt;
  end;

  { A command whose confirmation waits for IecSlaveConfirm. }
  tIecDeferred = record
    Ticket: LongWord;     {< 0: the slot is free }
    Point : LongInt;      {< its command point }
    Obj   : tIecObject;
    Select: Boolean;
    Asdu  : tIecQueued;   {< the command, mirrored as its ACT_CON }
  end;

  { A command for the program: H the ASDU's identifier (Ti, Cot, Ca ...),
    O its object (O.Select for a select). True accepts it. }
  tIecSlaveCommandFunc = function(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
  { Clock synchronisation: T the time received, OffsetMs what the station
    clock now adds to the PC clock. }
  tIecSlaveClockFunc = procedure(Data: Pointer; const T: tIecTime; OffsetMs: Int64);
  { Every ASDU received (Sent = False, before it is answered) and every
    ASDU handed to the link (Sent = True). }
  tIecSlaveAsduFunc = procedure(Data: Pointer; Sent: Boolean; Buf: PByte; Len: Word);
  tIecSlaveBadFunc = procedure(Data: Pointer; const Err: ShortString);
  { A reset of process (C_RP_NA_1) with its QRP, after its ACT_CON. }
  tIecSlaveResetFunc = procedure(Data: Pointer; Qrp: Byte);

  tIecSlaveStation = record
    Chn      : pChnVirt;
    Params   : tIecParams;
    Ca       : Word;          {< own common address (IecSlaveInit: 1) }
    Balanced : Boolean;       {< no link polling: balanced FT 1.2 or IEC 104 }
    Over104  : Boolean;       {< on an IEC104 channel }
    Station  : tFT12Station;  {< unbalanced link }
    Link     : tIecTransport; {< balanced link or IEC 104 }
    { the point table: PointCount points; it grows IecSlavePointStep
      points at a time as points are added, up to IecSlaveMaxPoints (a
      fixed table of the maximum held 133 KB whatever a station served) }
    Points   : array of tIecPoint;
    PointCount: LongInt;
    Class1, Class2: tIecQueue;
    { interrogation under way (station/group or counters) }
    GiActive : Boolean;
    GiQoi    : Byte;
    GiNext   : LongInt;       {< next point index to look at }
    GiPar    : LongInt;       {< then the parameters: point * 4 + KPA - 1 }
    GiAsdu   : tIecQueued;    {< its ACT_CON, the mirror for ACT_TERM }
    { select before operate }
    SelActive: Boolean;
    SelTi    : Byte;
    SelIoa   : LongWord;
    SelUntil : QWord;
    SelectMs : LongInt;
    SelObj   : tIecObject;    {< the object selected: its execute must carry the same }
    { station clock: PC clock + ClockOffsetMs; delay from C_CD_NA_1 }
    ClockOffsetMs: Int64;
    DelayMs  : LongInt;
    OnCommand: tIecSlaveCommandFunc;
    OnClock  : tIecSlaveClockFunc;
    OnAsdu   : tIecSlaveAsduFunc;
    OnBad    : tIecSlaveBadFunc;
    OnReset  : tIecSlaveResetFunc;
    Files    : pIecFileServer;  {< file transfer (nil: none) }
    Data     : Pointer;
    { counters }
    Asdus, BadAsdus, Commands, Refused, ClockSyncs, Interrogations,
      CounterInterrogations, Reads, Events, Negatives, Overflows, EndOfInits,
      Parameters, Suppressed: LongInt;
    LastBad  : ShortString;
    { commands waiting for IecSlaveConfirm; DeferSlot: the one OnCommand
      deferred (-1: none), InCommand: OnCommand is running }
    Deferred : array[0..IecSlaveMaxDeferred - 1] of tIecDeferred;
    NextTicket: LongWord;
    DeferSlot: LongInt;
    InCommand: Boolean;
  end;
  pIecSlaveStation = ^tIecSlaveStation;

implementation

end.
