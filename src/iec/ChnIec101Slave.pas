{ ChnIec101Slave - an IEC 60870-5-101 controlled station (slave) on a
  tChnFT1_2 channel: unbalanced (MS=ON, MAS=SLAVE; ChnFT12Link's
  tFT12Station answers the link functions) or balanced (MS=OFF;
  ChnFT12Link's tFT12Balanced runs both link procedures).

  The program fills a point table (IOA, type, value, quality, time; a
  group 1..16 for group interrogations, 1..4 for counters) and steps the
  slave from its poll loop (IecSlaveStep, ChnWaitAny between steps). The
  slave then answers, on its own:
  * station and group interrogation (C_IC_NA_1): ACT_CON in class 1, the
    points of the table (every monitoring type but integrated totals, each
    with its own type, as lib60870's slaves do) in class 2 with COT 20 (+
    group), ACT_TERM in class 1 once the last of them has been taken;
  * counter interrogation (C_CI_NA_1): FRZ 0 reads the counters (the
    frozen values once frozen), COT 37 (+ group); FRZ 1 freezes, 2
    freezes and resets, 3 resets; ACT_CON and ACT_TERM in class 1;
  * spontaneous changes (IecSlaveUpdate): class 1 events with COT 3, ACD
    set in every reply while one waits; a time-tagged type takes the time
    of the change (the station clock: PC clock + the offset of the last
    clock synchronisation); a point may send its events as the
    time-tagged type of its information (IecSlaveEventType: M_ME_TE_1
    events of an M_ME_NB_1 point) while interrogations and reads keep its
    own type;
  * commands (types 45..51, 58..64) to command points of the table (a
    command point may share its IOA with the monitoring point it acts on):
    handed to OnCommand (True accepts: positive ACT_CON, False: negative;
    a program whose device below must confirm first calls IecSlaveDefer
    in OnCommand and gives the outcome later with IecSlaveConfirm: the
    ACT_CON, positive or negative, waits until then);
    a select (S/E = 1) is remembered for SelectMs, the execute that
    follows it in time is passed on, one after the timeout is refused
    (negative ACT_CON, OnCommand not called), and so is an execute with
    another value or qualifier than the one selected; deactivation (COT 8)
    ends a selection (DEACT_CON); a command with T = 1 (test) is never
    executed: negative confirmation, T kept;
  * clock synchronisation (C_CS_NA_1): the difference to the PC clock is
    kept as the station clock's offset, OnClock told, ACT_CON with the
    time received;
  * read (C_RD_NA_1): the point in class 1 with COT 5;
  * end of initialisation (M_EI_NA_1, COT 4) in class 1 when the program
    says the station has initialised (IecSlaveEndOfInit, COI 0 after a
    start), and after a general reset of process;
  * test (C_TS_NA_1, C_TS_TA_1), reset process (C_RP_NA_1: QRP 1 starts
    the station again - queues dropped, OnReset told - and queues an end
    of initialisation with COI 2 after the ACT_CON; QRP 2 drops
    the queued time-tagged events, never a confirmation), delay acquisition (C_CD_NA_1: COT 6 confirmed,
    COT 3 kept as the delay): ACT_CON;
  * parameters of measured values (P_ME_NA_1..P_ME_NC_1: threshold,
    smoothing, limits kept per IOA, a threshold in operation a deadband on
    the spontaneous reports, reported after the points of a station
    interrogation) and their activation (P_AC_NA_1): ACT_CON / DEACT_CON;
  * file transfer (types 120..127) when the program gave a file server
    (IecSlaveServeFiles, ChnIecFileServer): its answers and segments go
    in class 1, one segment whenever class 1 is empty, so a long file
    never fills the queue; without one they are of an unknown type;
  * anything else is mirrored as a negative answer with COT 44 (unknown
    type), 45 (a cause the type does not take, or P/N = 1), 46 (another common
    address, or the broadcast address with a read or a command) or 47 (an
    IOA the table does not have for that type).
  A malformed ASDU (too short, wrong length for its type and count) is
  counted in BadAsdus, described in LastBad and given to OnBad; it is not
  answered and never stops the slave.

  Balanced mode has no classes: class 1 goes first, then class 2, each
  ASDU as SEND/CONFIRM user data as soon as the link queue has room.

  Nothing here waits: IecSlaveStep takes at most one frame (the link
  helpers send the answer at once) and returns. }
unit ChnIec101Slave;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Station, ChnIec101Asdu, ChnIecTransport,
  ChnIecFile, ChnIecFileServer;

const
  IecSlaveMaxPoints = 1024;
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
    Points   : array[0..IecSlaveMaxPoints - 1] of tIecPoint;
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

{ A slave on an open tChnFT1_2 stack (it stays the caller's) with the
  application parameters P and common address Ca. res_WrongLayer (no
  tChnFT1_2), res_AsduParam (Err), res_BadParam (Ca above the CA size),
  res_BadMessage (an unbalanced master channel). S must not move
  afterwards (the channel receives into it). }
function IecSlaveInit(var S: tIecSlaveStation; Chn: pChnVirt; const P: tIecParams; Ca: Word;
  out Err: ShortString): tChResult;
{ Add a point; Obj.Ioa is its address. One monitoring point per IOA; a
  command point may share its IOA with a monitoring point (the value it
  sets), one command point per IOA and type. res_AsduType (not a
  monitoring or command type, or end of initialisation), res_AsduIoa
  (above the IOA size), res_BadParam (IOA twice, group above 16 / 4 for
  counters),
  res_Busy (table full), res_AsduValue (a value its type cannot carry);
  Err names the point and what is wrong. }
function IecSlaveAddPoint(var S: tIecSlaveStation; Ti: Byte; const Obj: tIecObject; Group: Byte;
  out Err: ShortString): tChResult;
{ Index of the point with this IOA (its monitoring point when a command
  point shares the IOA), -1 when there is none. }
function IecSlaveFind(const S: tIecSlaveStation; Ioa: LongWord): LongInt;
{ The spontaneous events of monitoring point Ioa go as type Ti, the
  same information with a time tag (M_SP_TB_1 for M_SP_NA_1, M_ME_TE_1
  for M_ME_NB_1, M_ME_TF_1 for M_ME_NC_1, M_BO_TB_1 for M_BO_NA_1 ...; a
  CP24 type is taken as its CP56 counterpart over IEC 104), stamped with
  the station clock; interrogations and reads keep the point's own type.
  res_AsduIoa (no monitoring point Ioa), res_AsduType (Ti is not the
  point's information with a time tag; Err says why). }
function IecSlaveEventType(var S: tIecSlaveStation; Ioa: LongWord; Ti: Byte;
  out Err: ShortString): tChResult;
{ New value and quality of point Ioa (the value fields of Obj; its IOA,
  and a counter's sequence number, are the table's); a time-tagged type
  takes the station clock's time. With
  Spontaneous the change goes out as a class 1 event (COT 3).
  res_AsduIoa (no such point), res_AsduValue (Err), res_Busy (event
  queue full: the table has the new value, the event is lost). }
function IecSlaveUpdate(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
{ The same with the time tag Obj.Time instead of the station clock's (a
  gateway passing on the time its source stamped the change with). }
function IecSlaveUpdateAt(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
{ The station clock (PC clock + ClockOffsetMs). }
function IecSlaveNow(const S: tIecSlaveStation): TDateTime;
{ Take at most one frame and act on it; move waiting ASDUs to a balanced
  link. True when a frame was taken. (A selection whose time is up stays
  until its execute, which is refused, or the next select.) }
function IecSlaveStep(var S: tIecSlaveStation): Boolean;
{ ms the caller may wait (ChnWaitAny) before the next step when
  IecSlaveStep returned False: short while a balanced link has work. }
function IecSlaveWaitMs(const S: tIecSlaveStation): LongInt;
{ ASDUs waiting in class 1 and class 2 (and an interrogation's rest). }
function IecSlavePending(const S: tIecSlaveStation): Boolean;
{ The station has initialised: queue its end of initialisation (M_EI_NA_1,
  COT 4, IOA 0, the COI: Coi_PowerOn after a start, Coi_ManualReset,
  + Coi_LocalChange when local parameters changed) in class 1. A program
  calls it once its point table is filled; it goes out when the master
  has reset the link and polls class 1 (unbalanced), or as soon as the
  link is up (balanced FT 1.2, IEC 104). A general reset of process
  (C_RP_NA_1, QRP 1) sends one with Coi_RemoteReset by itself. }
procedure IecSlaveEndOfInit(var S: tIecSlaveStation; Coi: Byte);
{ Serve file transfer with F (ChnIecFileServer; its application parameters
  and common address become the slave's); nil: no file transfer. F must
  not move while the slave runs. }
procedure IecSlaveServeFiles(var S: tIecSlaveStation; F: pIecFileServer);

{ Deferred confirmation of a command. Called from OnCommand (which then
  returns True): the command's ACT_CON waits for IecSlaveConfirm with the
  ticket returned (above 0) - for a program that passes the command to a
  device and may confirm it only when the device did. 0 when no command
  is being handed to OnCommand or IecSlaveMaxDeferred commands wait
  already: then OnCommand's result confirms it at once, as without. A
  general reset of process (C_RP_NA_1, QRP 1) drops the waiting ones. }
function IecSlaveDefer(var S: tIecSlaveStation): LongWord;
{ The outcome of deferred command Ticket: a positive (Ok) or negative
  ACT_CON, in class 1; accepted, an execute sets its command point's
  value and a select starts the selection (SelectMs from now).
  res_BadParam when no command waits with this ticket (confirmed
  already, or dropped by a general reset). }
function IecSlaveConfirm(var S: tIecSlaveStation; Ticket: LongWord; Ok: Boolean): tChResult;
{ Commands waiting for IecSlaveConfirm. }
function IecSlaveDeferred(const S: tIecSlaveStation): LongInt;

implementation

uses
  SysUtils, DateUtils, Math, ChnIec104Codec;

{- ---------------------------------------------------------------- queues }

function QueuePut(var Q: tIecQueue; const Buf: array of Byte; Len: Word): Boolean;
var
  Slot: Integer;
begin
  Result := (Q.Count < IecSlaveQueueLen) and (Len <= IecMaxAsdu);
  if not Result then
    Exit;
  Slot := (Q.Head + Q.Count) mod IecSlaveQueueLen;
  Q.Items[Slot].Len := Len;
  Move(Buf[0], Q.Items[Slot].Data[0], Len);
  Inc(Q.Count);
end;

procedure QueueDrop(var Q: tIecQueue);
begin
  Q.Head := (Q.Head + 1) mod IecSlaveQueueLen;
  Dec(Q.Count);
end;

{ Reset of pending information with time tag (QRP 2): the queued
  spontaneous ASDUs of time-tagged types go; confirmations, terminations,
  answers to reads and untagged events stay, in their order. }
procedure QueueDropTaggedEvents(var Q: tIecQueue);
var
  Old: tIecQueue;
  I: Integer;
begin
  Old := Q;
  Q.Head := 0;
  Q.Count := 0;
  for I := 0 to Old.Count - 1 do
    with Old.Items[(Old.Head + I) mod IecSlaveQueueLen] do
      if (Len < 3) or (Data[2] and $3F <> Cot_Spontaneous) or (IecTypeTime(Data[0]) = tkNone) then
        QueuePut(Q, Data, Len);
end;

procedure Queue1(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word);
begin
  if not QueuePut(S.Class1, Buf, Len) then
    Inc(S.Overflows);
end;

{ The longest ASDU the link takes: IEC 104's APDU of 253 octets less
  its control field (249); FT 1.2's frame of L = 255 less the control
  octet and the link address (253 with ADR=1; no ASDU exceeds IecMaxAsdu). }
function MaxAsdu(const S: tIecSlaveStation): Word;
begin
  if S.Over104 then
    Result := Apci104MaxAsdu
  else
    Result := Min(IecMaxAsdu, FT12MaxData(S.Chn));
end;

procedure IecSlaveServeFiles(var S: tIecSlaveStation; F: pIecFileServer);
begin
  S.Files := F;
  if F <> nil then
  begin
    F^.Params := S.Params;
    F^.Ca := S.Ca;
    { no longer than the link takes }
    if F^.MaxAsdu > MaxAsdu(S) then
      F^.MaxAsdu := MaxAsdu(S);
  end;
end;

{ Class 1 is empty: the file server's next ASDU into it. }
procedure FeedFiles(var S: tIecSlaveStation);
var
  Buf: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
begin
  if (S.Files <> nil) and (S.Class1.Count = 0) and IecFileServerNext(S.Files^, Buf, Len) then
    Queue1(S, Buf, Len);
end;

function FilesReady(var S: tIecSlaveStation): Boolean;
begin
  Result := (S.Files <> nil) and IecFileServerReady(S.Files^);
end;

{- ---------------------------------------------------------------- points }

function IsCounter(Ti: Byte): Boolean;
begin
  Result := IecTypeKind(Ti) = ikCounter;
end;

function IsCommand(Ti: Byte): Boolean;
begin
  Result := Ti in [C_SC_NA_1..C_BO_NA_1, C_SC_TA_1..C_BO_TA_1];
end;

function IecSlaveNow(const S: tIecSlaveStation): TDateTime;
begin
  Result := IncMilliSecond(Now, S.ClockOffsetMs);
end;

{ The monitoring point at Ioa; -1 when none. }
function FindMonitor(const S: tIecSlaveStation; Ioa: LongWord): LongInt;
var
  I: Integer;
begin
  for I := 0 to S.PointCount - 1 do
    if (S.Points[I].Obj.Ioa = Ioa) and not IsCommand(S.Points[I].Ti) then
      Exit(I);
  Result := -1;
end;

{ The command point of type Ti at Ioa; -1 when none. }
function FindCommand(const S: tIecSlaveStation; Ioa: LongWord; Ti: Byte): LongInt;
var
  I: Integer;
begin
  for I := 0 to S.PointCount - 1 do
    if (S.Points[I].Obj.Ioa = Ioa) and (S.Points[I].Ti = Ti) then
      Exit(I);
  Result := -1;
end;

function IecSlaveFind(const S: tIecSlaveStation; Ioa: LongWord): LongInt;
var
  I: Integer;
begin
  Result := FindMonitor(S, Ioa);
  if Result >= 0 then
    Exit;
  for I := 0 to S.PointCount - 1 do
    if S.Points[I].Obj.Ioa = Ioa then
      Exit(I);
end;

{ Can Obj be sent as type Ti? (the encoder's own checks) }
function CheckObject(const S: tIecSlaveStation; Ti: Byte; const Obj: tIecObject; out Err: ShortString): tChResult;
var
  Buf: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
begin
  Result := IecEncodeOne(S.Params, Ti, Cot_Spontaneous, S.Ca, Obj, Buf, Len, Err);
end;

{ IEC 104 has no CP24 types (IEC 60870-5-104 clause 8): the CP56 type
  of the same information. }
function Cp56Counterpart(Ti: Byte): Byte;
begin
  case Ti of
    M_SP_TA_1: Result := M_SP_TB_1;
    M_DP_TA_1: Result := M_DP_TB_1;
    M_ST_TA_1: Result := M_ST_TB_1;
    M_BO_TA_1: Result := M_BO_TB_1;
    M_ME_TA_1: Result := M_ME_TD_1;
    M_ME_TB_1: Result := M_ME_TE_1;
    M_ME_TC_1: Result := M_ME_TF_1;
    M_IT_TA_1: Result := M_IT_TB_1;
    M_EP_TA_1: Result := M_EP_TD_1;
    M_EP_TB_1: Result := M_EP_TE_1;
    M_EP_TC_1: Result := M_EP_TF_1;
  else
    Result := Ti;
  end;
end;

function IecSlaveAddPoint(var S: tIecSlaveStation; Ti: Byte; const Obj: tIecObject; Group: Byte;
  out Err: ShortString): tChResult;
var
  P: pIecPoint;
  O: tIecObject;
begin
  Err := '';
  if S.Over104 then
    Ti := Cp56Counterpart(Ti);
  if not ((IecIsMonitor(Ti) and (Ti <> M_EI_NA_1)) or IsCommand(Ti)) then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': type ' + IntToStr(Ti) +
      ' is no monitoring (1..21, 30..40) or command type (45..51, 58..64)';
    Exit(res_AsduType);
  end;
  if Obj.Ioa > IecMaxIoa(S.Params) then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': IOA above ' + IntToStr(IecMaxIoa(S.Params)) +
      ' (IOA size ' + IntToStr(S.Params.IoaSize) + ')';
    Exit(res_AsduIoa);
  end;
  if (IsCommand(Ti) and (FindCommand(S, Obj.Ioa, Ti) >= 0)) or
     (not IsCommand(Ti) and (FindMonitor(S, Obj.Ioa) >= 0)) then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': IOA twice';
    Exit(res_BadParam);
  end;
  if (Group > 16) or (IsCounter(Ti) and (Group > 4)) then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': group ' + IntToStr(Group);
    Exit(res_BadParam);
  end;
  if S.PointCount >= IecSlaveMaxPoints then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': table full (' + IntToStr(IecSlaveMaxPoints) + ' points)';
    Exit(res_Busy);
  end;
  O := Obj;
  if IecTypeTime(Ti) <> tkNone then
    O.Time := IecTimeFromDateTime(IecSlaveNow(S));
  Result := CheckObject(S, Ti, O, Err);
  if Result <> res_Ok then
  begin
    Err := 'point ' + IntToStr(Obj.Ioa) + ': ' + Err;
    Exit;
  end;
  P := @S.Points[S.PointCount];
  FillChar(P^, SizeOf(P^), 0);
  P^.Ti := Ti;
  P^.Group := Group;
  P^.Obj := O;
  Inc(S.PointCount);
end;

function IecSlaveEventType(var S: tIecSlaveStation; Ioa: LongWord; Ti: Byte;
  out Err: ShortString): tChResult;
var
  I: LongInt;
begin
  Err := '';
  I := FindMonitor(S, Ioa);
  if I < 0 then
  begin
    Err := 'no monitoring point with IOA ' + IntToStr(Ioa);
    Exit(res_AsduIoa);
  end;
  if S.Over104 then
    Ti := Cp56Counterpart(Ti);          { no CP24 over IEC 104 }
  if (IecTypeTime(S.Points[I].Ti) <> tkNone) or (IecTypeTime(Ti) = tkNone) or not IecIsMonitor(Ti) or
     (IecTypeKind(Ti) <> IecTypeKind(S.Points[I].Ti)) then
  begin
    Err := 'point ' + IntToStr(Ioa) + ': ' + IecTypeName(Ti) + ' is not ' +
      IecTypeName(S.Points[I].Ti) + ' with a time tag';
    Exit(res_AsduType);
  end;
  S.Points[I].EventTi := Ti;
  Result := res_Ok;
end;

{ Encode one object of type Ti with cause Cot into the class 1 queue. }
function QueueObject(var S: tIecSlaveStation; Ti, Cot: Byte; const O: tIecObject): tChResult;
var
  Buf: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  Err: ShortString;
begin
  Result := IecEncodeOne(S.Params, Ti, Cot, S.Ca, O, Buf, Len, Err);
  if Result <> res_Ok then
    Exit;
  if not QueuePut(S.Class1, Buf, Len) then
  begin
    Inc(S.Overflows);
    Result := res_Busy;
  end;
end;

{ The value of a measured value as its parameters count it: the fraction
  of a normalized value, the integer of a scaled one, the float. }
function MeasuredValue(Ti: Byte; const O: tIecObject): Double;
begin
  if IecTypeKind(Ti) = ikScaled then
    Result := O.Int
  else
    Result := O.Number;
end;

{ The parameter type (P_ME_NA/NB/NC_1) of a measured value type; 0 when
  it has none. }
function ParamType(Ti: Byte): Byte;
begin
  case IecTypeKind(Ti) of
    ikNormal: Result := P_ME_NA_1;
    ikScaled: Result := P_ME_NB_1;
    ikFloat: Result := P_ME_NC_1;
  else
    Result := 0;
  end;
end;

{ A change within the threshold of a point whose parameters are in
  operation, and with the same quality, is not reported (a deadband around
  the value reported last). }
function InDeadband(const P: tIecPoint; const O: tIecObject; OldQuality: Byte): Boolean;
begin
  Result := P.ParOn and (P.ParSet and (1 shl Kpa_Threshold) <> 0) and P.HasReported and
    (O.Quality = OldQuality) and (Abs(MeasuredValue(P.Ti, O) - P.Reported) < P.Par[Kpa_Threshold]);
end;

{ IecSlaveUpdate, and IecSlaveUpdateAt with Obj.Time kept (KeepTime). }
function UpdatePoint(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous, KeepTime: Boolean; out Err: ShortString): tChResult;
var
  I: Integer;
  O: tIecObject;
  Quality, EvTi: Byte;
begin
  Err := '';
  I := IecSlaveFind(S, Ioa);
  if I < 0 then
  begin
    Err := 'no point with IOA ' + IntToStr(Ioa);
    Exit(res_AsduIoa);
  end;
  O := Obj;
  O.Ioa := Ioa;
  if IsCounter(S.Points[I].Ti) then
    O.Seq := S.Points[I].Obj.Seq;           { the freezes count it, not the program }
  if (IecTypeTime(S.Points[I].Ti) <> tkNone) and not KeepTime then
    O.Time := IecTimeFromDateTime(IecSlaveNow(S));
  Result := CheckObject(S, S.Points[I].Ti, O, Err);
  if Result <> res_Ok then
  begin
    Err := 'point ' + IntToStr(Ioa) + ': ' + Err;
    Exit;
  end;
  Quality := S.Points[I].Obj.Quality;
  S.Points[I].Obj := O;
  if Spontaneous and InDeadband(S.Points[I], O, Quality) then
  begin
    Inc(S.Suppressed);
    Exit(res_Ok);
  end;
  if Spontaneous then
  begin
    S.Points[I].Reported := MeasuredValue(S.Points[I].Ti, O);
    S.Points[I].HasReported := True;
    EvTi := S.Points[I].EventTi;
    if EvTi = 0 then
      EvTi := S.Points[I].Ti
    else if not KeepTime then
      O.Time := IecTimeFromDateTime(IecSlaveNow(S));
    Result := QueueObject(S, EvTi, Cot_Spontaneous, O);
    if Result = res_Ok then
      Inc(S.Events);
    if Result = res_Busy then
      Err := 'point ' + IntToStr(Ioa) + ': class 1 queue full, event lost';
  end;
end;

function IecSlaveUpdate(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
begin
  Result := UpdatePoint(S, Ioa, Obj, Spontaneous, False, Err);
end;

function IecSlaveUpdateAt(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
begin
  Result := UpdatePoint(S, Ioa, Obj, Spontaneous, True, Err);
end;

{- ---------------------------------------------------------- interrogation }

{ Does point P answer the interrogation under way? }
function GiWants(const S: tIecSlaveStation; const P: tIecPoint): Boolean;
var
  Grp: Byte;
begin
  if IsCommand(P.Ti) then
    Exit(False);
  if S.GiAsdu.Data[0] = C_CI_NA_1 then
  begin
    Grp := S.GiQoi and $3F;           { RQT: 1..4 a group, 5 all }
    Result := IsCounter(P.Ti) and ((Grp = Qcc_General) or (P.Group = Grp));
  end
  else
    Result := not IsCounter(P.Ti) and ((S.GiQoi = Qoi_Station) or (P.Group = S.GiQoi - Qoi_Station));
end;

{ After the points, the parameters loaded for the points the interrogation
  covers, one ASDU each (P_ME_NA/NB/NC_1, COT 20 + group; QPM the KPA, POP
  set while they are not in operation); False when none is left. }
function GiParamAsdu(var S: tIecSlaveStation; var Out: tIecQueued): Boolean;
var
  P: pIecPoint;
  Kpa: Integer;
  O: tIecObject;
  Err: ShortString;
begin
  Result := False;
  while not Result and (S.GiPar < S.PointCount * 4) do
  begin
    P := @S.Points[S.GiPar div 4];
    Kpa := S.GiPar mod 4 + 1;
    Inc(S.GiPar);
    if (P^.ParSet and (1 shl Kpa) = 0) or not GiWants(S, P^) then
      Continue;
    O := IecObject(P^.Obj.Ioa);
    if ParamType(P^.Ti) = P_ME_NB_1 then
      O.Int := Round(P^.Par[Kpa])
    else
      O.Number := P^.Par[Kpa];
    O.Qu := Kpa;
    if not P^.ParOn then
      O.Qu := O.Qu or Qpm_NotInOperation;
    Result := IecEncodeOne(S.Params, ParamType(P^.Ti), Cot_Interrogated + (S.GiQoi - Qoi_Station),
      S.Ca, O, Out.Data, Out.Len, Err) = res_Ok;
  end;
end;

{ The next answer ASDU of the interrogation: consecutive points of one
  type, as many as fit; False when none is left (then ACT_TERM is queued). }
function GiNextAsdu(var S: tIecSlaveStation; var Out: tIecQueued): Boolean;
var
  Objs: array[0..IecMaxObjects - 1] of tIecObject;
  H: tIecAsdu;
  N, Room, Size: Integer;
  Ti, Cot: Byte;
  Err: ShortString;
  Counter: Boolean;
begin
  Result := False;
  if not S.GiActive then
    Exit;
  Counter := S.GiAsdu.Data[0] = C_CI_NA_1;
  while (S.GiNext < S.PointCount) and not GiWants(S, S.Points[S.GiNext]) do
    Inc(S.GiNext);
  if (S.GiNext >= S.PointCount) and not Counter and GiParamAsdu(S, Out) then
    Exit(True);
  if S.GiNext >= S.PointCount then
  begin
    { all sent: ACT_TERM, in class 1 }
    S.GiActive := False;
    IecSetCot(S.GiAsdu.Data, S.GiAsdu.Len, Cot_ActTerm, False);
    Queue1(S, S.GiAsdu.Data, S.GiAsdu.Len);
    Exit;
  end;
  Ti := S.Points[S.GiNext].Ti;
  Size := S.Params.IoaSize + IecElementSize(Ti);
  Room := (MaxAsdu(S) - IecHeadLen(S.Params)) div Size;
  if Room > IecMaxObjects then
    Room := IecMaxObjects;
  N := 0;
  while (S.GiNext < S.PointCount) and (N < Room) and (S.Points[S.GiNext].Ti = Ti) do
  begin
    if GiWants(S, S.Points[S.GiNext]) then
    begin
      if Counter and S.Points[S.GiNext].HasFrozen then
        Objs[N] := S.Points[S.GiNext].Frozen
      else
        Objs[N] := S.Points[S.GiNext].Obj;
      Inc(N);
    end;
    Inc(S.GiNext);
  end;
  if Counter then
    Cot := Cot_CounterReq + (S.GiQoi and $3F) mod Qcc_General
  else
    Cot := Cot_Interrogated + (S.GiQoi - Qoi_Station);
  FillChar(H, SizeOf(H), 0);
  H.Ti := Ti;
  H.Count := N;
  H.Cot := Cot;
  H.Oa := S.GiAsdu.Data[3] * Ord(S.Params.CotSize = 2);
  H.Ca := S.Ca;
  Result := IecEncodeAsdu(S.Params, H, Objs[0..N - 1], Out.Data, Out.Len, Err) = res_Ok;
end;

{ Freeze / reset the counters of the group of a C_CI_NA_1. }
procedure CounterAction(var S: tIecSlaveStation; Qcc: Byte);
var
  I: Integer;
  Grp: Byte;
  P: pIecPoint;
begin
  Grp := Qcc and $3F;
  for I := 0 to S.PointCount - 1 do
  begin
    P := @S.Points[I];
    if not IsCounter(P^.Ti) or not ((Grp = Qcc_General) or (P^.Group = Grp)) then
      Continue;
    if Qcc and $C0 in [Qcc_Freeze, Qcc_FreezeReset] then
    begin
      { each freeze is a new reading: the next sequence number }
      P^.Obj.Seq := (P^.Obj.Seq + 1) and 31;
      P^.Frozen := P^.Obj;
      P^.HasFrozen := True;
    end;
    if Qcc and $C0 in [Qcc_FreezeReset, Qcc_Reset] then
      P^.Obj.Int := 0;
  end;
end;

{- ---------------------------------------------------------------- answers }

procedure Bad(var S: tIecSlaveStation; const Err: ShortString);
begin
  Inc(S.BadAsdus);
  S.LastBad := Err;
  if Assigned(S.OnBad) then
    S.OnBad(S.Data, Err);
end;

{ The received ASDU mirrored with Cot (negative or not) into class 1. }
procedure Answer(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word; Cot: Byte; Negative: Boolean);
var
  Out: array[0..IecMaxAsdu - 1] of Byte;
begin
  if (Len = 0) or (Len > IecMaxAsdu) then
    Exit;
  Move(Buf[0], Out[0], Len);
  IecSetCot(Out, Len, Cot, Negative);
  if Negative then
    Inc(S.Negatives);
  Queue1(S, Out, Len);
end;

{ Does an execute carry what was selected (value, qualifier)? }
function SameCommand(const Sel, O: tIecObject): Boolean;
begin
  Result := (Sel.Int = O.Int) and (Sel.Bits = O.Bits) and (Sel.Number = O.Number) and (Sel.Qu = O.Qu);
end;

{ The confirmation cause of an activation (7) or deactivation (9). }
function ActOrDeact(Cot: Byte): Byte;
begin
  if Cot = Cot_Deactivation then
    Result := Cot_DeactCon
  else
    Result := Cot_ActCon;
end;

{ A command of types 45..51 / 58..64 with cause 6 or 8. }
{ The end of an accepted (Ok) or refused command to point I: the
  selection, the command point's value, the ACT_CON. }
procedure EndCommand(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  I: LongInt; const O: tIecObject; Select, Ok: Boolean);
var
  Ti: Byte;
begin
  Ti := S.Points[I].Ti;
  if Ok then
  begin
    Inc(S.Commands);
    if Select then
    begin
      S.SelActive := True;
      S.SelTi := Ti;
      S.SelIoa := O.Ioa;
      S.SelUntil := ChMsTick + QWord(S.SelectMs);
      S.SelObj := O;
    end
    else
    begin
      if S.SelActive and (S.SelTi = Ti) and (S.SelIoa = O.Ioa) then
        S.SelActive := False;
      { the command point keeps the last value executed }
      S.Points[I].Obj.Int := O.Int;
      S.Points[I].Obj.Bits := O.Bits;
      S.Points[I].Obj.Number := O.Number;
      S.Points[I].Obj.Qu := O.Qu;
    end;
  end
  else
    Inc(S.Refused);
  Answer(S, Buf, Len, Cot_ActCon, not Ok);
end;

procedure TakeCommand(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);
var
  I: Integer;
  Ok, Select: Boolean;
  D: ^tIecDeferred;
begin
  I := FindCommand(S, O.Ioa, H.Ti);
  if I < 0 then
  begin
    Answer(S, Buf, Len, Cot_UnknownIoa, True);
    Exit;
  end;
  Select := O.Select and (IecTypeKind(H.Ti) <> ikBitsCmd);
  if H.Test then
  begin
    { T = 1: generated under test conditions, not meant to change the
      process - never executed, refused (negative, T kept) }
    Inc(S.Refused);
    Answer(S, Buf, Len, ActOrDeact(H.Cot), True);
    Exit;
  end;
  if H.Cot = Cot_Deactivation then
  begin
    { ends a selection of this object }
    Ok := S.SelActive and (S.SelTi = H.Ti) and (S.SelIoa = O.Ioa);
    if Ok then
      S.SelActive := False;
    Answer(S, Buf, Len, Cot_DeactCon, not Ok);
    Exit;
  end;
  if not Select and S.SelActive and (S.SelTi = H.Ti) and (S.SelIoa = O.Ioa) and
     ((ChMsTick > S.SelUntil) or not SameCommand(S.SelObj, O)) then
  begin
    { the execute of a selection whose time is up, or with another value
      or qualifier than the one selected }
    S.SelActive := False;
    Inc(S.Refused);
    Answer(S, Buf, Len, Cot_ActCon, True);
    Exit;
  end;
  S.DeferSlot := -1;
  S.InCommand := True;
  Ok := not Assigned(S.OnCommand) or S.OnCommand(S.Data, H, O);
  S.InCommand := False;
  if S.DeferSlot >= 0 then
  begin
    D := @S.Deferred[S.DeferSlot];
    if Ok then
    begin
      { the confirmation waits for IecSlaveConfirm }
      D^.Point := I;
      D^.Obj := O;
      D^.Select := Select;
      D^.Asdu.Len := Len;
      Move(Buf[0], D^.Asdu.Data[0], Len);
      Exit;
    end;
    D^.Ticket := 0;                  { refused all the same: at once }
  end;
  EndCommand(S, Buf, Len, I, O, Select, Ok);
end;

function IecSlaveDefer(var S: tIecSlaveStation): LongWord;
var
  I: LongInt;
begin
  Result := 0;
  if not S.InCommand or (S.DeferSlot >= 0) then
    Exit;
  for I := 0 to IecSlaveMaxDeferred - 1 do
    if S.Deferred[I].Ticket = 0 then
    begin
      Inc(S.NextTicket);
      if S.NextTicket = 0 then
        S.NextTicket := 1;
      S.Deferred[I].Ticket := S.NextTicket;
      S.DeferSlot := I;
      Exit(S.NextTicket);
    end;
end;

function IecSlaveConfirm(var S: tIecSlaveStation; Ticket: LongWord; Ok: Boolean): tChResult;
var
  I: LongInt;
begin
  if Ticket <> 0 then
    for I := 0 to IecSlaveMaxDeferred - 1 do
      if S.Deferred[I].Ticket = Ticket then
      begin
        S.Deferred[I].Ticket := 0;
        EndCommand(S, S.Deferred[I].Asdu.Data, S.Deferred[I].Asdu.Len, S.Deferred[I].Point,
          S.Deferred[I].Obj, S.Deferred[I].Select, Ok);
        Exit(res_Ok);
      end;
  Result := res_BadParam;
end;

function IecSlaveDeferred(const S: tIecSlaveStation): LongInt;
var
  I: LongInt;
begin
  Result := 0;
  for I := 0 to IecSlaveMaxDeferred - 1 do
    if S.Deferred[I].Ticket <> 0 then
      Inc(Result);
end;

procedure TakeClock(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word; const O: tIecObject);
var
  DT: TDateTime;
begin
  if not IecTimeToDateTime(O.Time, DT) then
  begin
    Answer(S, Buf, Len, Cot_ActCon, True);     { no date: refused }
    Exit;
  end;
  { the time the master sent plus the transmission delay it measured }
  S.ClockOffsetMs := Round((IncMilliSecond(DT, S.DelayMs) - Now) * MSecsPerDay);
  Inc(S.ClockSyncs);
  if Assigned(S.OnClock) then
    S.OnClock(S.Data, O.Time, S.ClockOffsetMs);
  Answer(S, Buf, Len, Cot_ActCon, False);      { ACT_CON with the time received }
end;

procedure TakeRead(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word; const O: tIecObject);
var
  I: Integer;
begin
  I := IecSlaveFind(S, O.Ioa);
  if (I < 0) or IsCommand(S.Points[I].Ti) then
  begin
    Answer(S, Buf, Len, Cot_UnknownIoa, True);
    Exit;
  end;
  Inc(S.Reads);
  QueueObject(S, S.Points[I].Ti, Cot_Request, S.Points[I].Obj);
end;

procedure TakeInterrogation(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);
var
  Q: Byte;
begin
  Q := O.Int;
  if (H.Ti = C_IC_NA_1) and not (Q in [Qoi_Station..Qoi_Station + 16]) then
  begin
    Answer(S, Buf, Len, Cot_ActCon, True);     { a QOI we do not know }
    Exit;
  end;
  if (H.Ti = C_CI_NA_1) and not ((Q and $3F) in [1..Qcc_General]) then
  begin
    Answer(S, Buf, Len, Cot_ActCon, True);
    Exit;
  end;
  if S.GiActive then
  begin
    Answer(S, Buf, Len, Cot_ActCon, True);     { one at a time }
    Exit;
  end;
  Answer(S, Buf, Len, Cot_ActCon, False);
  S.GiAsdu.Len := Len;
  Move(Buf[0], S.GiAsdu.Data[0], Len);
  S.GiQoi := Q;
  S.GiNext := 0;
  S.GiPar := 0;
  if H.Ti = C_CI_NA_1 then
  begin
    Inc(S.CounterInterrogations);
    if Q and $C0 <> Qcc_Read then
    begin
      { freeze / reset: confirmed and terminated, no values }
      CounterAction(S, Q);
      IecSetCot(S.GiAsdu.Data, Len, Cot_ActTerm, False);
      Queue1(S, S.GiAsdu.Data, Len);
      Exit;
    end;
  end
  else
    Inc(S.Interrogations);
  S.GiActive := True;
end;

procedure IecSlaveEndOfInit(var S: tIecSlaveStation; Coi: Byte);
var
  Buf: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  O: tIecObject;
  Err: ShortString;
begin
  O := IecObject(0);
  O.Int := Coi;
  if IecEncodeOne(S.Params, M_EI_NA_1, Cot_Initialized, S.Ca, O, Buf, Len, Err) = res_Ok then
  begin
    Queue1(S, Buf, Len);
    Inc(S.EndOfInits);
  end;
end;

{ A general reset of process: the station starts again - what waited is
  dropped, an interrogation or selection under way ends - and says so
  with an end of initialisation after the confirmation. }
procedure GeneralReset(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word);
begin
  S.Class1.Count := 0;
  S.Class2.Count := 0;
  S.GiActive := False;
  S.SelActive := False;
  FillChar(S.Deferred, SizeOf(S.Deferred), 0);
  Answer(S, Buf, Len, Cot_ActCon, False);
  if Assigned(S.OnReset) then
    S.OnReset(S.Data, Qrp_General);
  IecSlaveEndOfInit(S, Coi_RemoteReset);
end;

{ Parameter loading (P_ME_NA/NB/NC_1, for a measured value of the same
  kind: normalized, scaled, float) and activation (P_AC_NA_1). }
procedure TakeParameter(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);
var
  I, Kpa: Integer;
  Ok: Boolean;
begin
  I := IecSlaveFind(S, O.Ioa);
  if (H.Ti = P_AC_NA_1) and (O.Int = Qpa_Loaded) and (O.Ioa = 0) then
  begin
    { every point's loaded parameters }
    for I := 0 to S.PointCount - 1 do
      S.Points[I].ParOn := H.Cot = Cot_Activation;
    Inc(S.Parameters);
    Answer(S, Buf, Len, ActOrDeact(H.Cot), False);
    Exit;
  end;
  if (I < 0) or (ParamType(S.Points[I].Ti) = 0) or
     (H.Ti <> P_AC_NA_1) and (ParamType(S.Points[I].Ti) <> H.Ti) then
  begin
    Answer(S, Buf, Len, Cot_UnknownIoa, True);
    Exit;
  end;
  if H.Ti = P_AC_NA_1 then
  begin
    { this object's parameters; cyclic transmission is not offered }
    Ok := O.Int in [Qpa_Loaded, Qpa_Object];
    if Ok then
      S.Points[I].ParOn := H.Cot = Cot_Activation;
  end
  else
  begin
    Kpa := O.Qu and $3F;
    Ok := (Kpa >= Kpa_Threshold) and (Kpa <= Kpa_High) and
      ((Kpa <> Kpa_Threshold) or (MeasuredValue(S.Points[I].Ti, O) >= 0));
    if Ok then
    begin
      S.Points[I].Par[Kpa] := MeasuredValue(S.Points[I].Ti, O);
      S.Points[I].ParSet := S.Points[I].ParSet or (1 shl Kpa);
      S.Points[I].ParOn := O.Qu and Qpm_NotInOperation = 0;
    end;
  end;
  if Ok then
    Inc(S.Parameters);
  Answer(S, Buf, Len, ActOrDeact(H.Cot), not Ok);
end;

{ Does type Ti take cause Cot in control direction? }
function CotFits(Ti, Cot: Byte): Boolean;
begin
  case Ti of
    C_RD_NA_1: Result := Cot = Cot_Request;
    C_CS_NA_1, C_TS_NA_1, C_RP_NA_1, C_TS_TA_1: Result := Cot = Cot_Activation;
    C_IC_NA_1, C_CI_NA_1: Result := Cot in [Cot_Activation];
    P_ME_NA_1, P_ME_NB_1, P_ME_NC_1: Result := Cot = Cot_Activation;
    P_AC_NA_1: Result := Cot in [Cot_Activation, Cot_Deactivation];
    C_CD_NA_1: Result := Cot in [Cot_Activation, Cot_Spontaneous];
  else
    Result := Cot in [Cot_Activation, Cot_Deactivation];   { commands }
  end;
end;

{ One ASDU from the master. }
procedure TakeAsdu(var S: tIecSlaveStation; Buf: PByte; Len: Word);
var
  A: array[0..IecMaxAsdu - 1] of Byte;
  H: tIecAsdu;
  O: tIecObject;
  R: tChResult;
  Err: ShortString;
  Ca: Word;
  HeadLen: Word;
begin
  if Len > IecMaxAsdu then
    Len := IecMaxAsdu;                   { L = 255 with ADR=0: no ASDU is that long }
  Move(Buf^, A[0], Len);
  Inc(S.Asdus);
  if Assigned(S.OnAsdu) then
    S.OnAsdu(S.Data, False, @A[0], Len);
  if (Len > 0) and IecIsFileType(A[0]) and (S.Files <> nil) then
  begin
    IecFileServerTake(S.Files^, A, Len);
    Exit;
  end;
  R := IecDecodeHeader(S.Params, A, Len, H, Err);
  HeadLen := IecHeadLen(S.Params);
  if R = res_AsduType then
  begin
    { a type we do not know: its identifier is there, answer COT 44 }
    Answer(S, A, Len, Cot_UnknownType, True);
    Exit;
  end;
  if R <> res_Ok then
  begin
    Bad(S, Err);
    Exit;
  end;
  Ca := A[HeadLen - S.Params.CaSize];
  if S.Params.CaSize = 2 then
    Ca := Ca or (A[HeadLen - 1] shl 8);
  { the broadcast address is for the station-wide requests only (a read
    or a command to every station at once is refused, as lib60870 does) }
  if ((Ca <> S.Ca) and (Ca <> IecMaxCa(S.Params))) or
     ((Ca = IecMaxCa(S.Params)) and (Ca <> S.Ca) and
      not (H.Ti in [C_IC_NA_1, C_CI_NA_1, C_CS_NA_1, C_TS_NA_1, C_RP_NA_1, C_CD_NA_1, C_TS_TA_1])) then
  begin
    Answer(S, A, Len, Cot_UnknownCa, True);
    Exit;
  end;
  if IecIsMonitor(H.Ti) or (H.Ti > P_AC_NA_1) or (H.Count <> 1) or
     (S.Over104 and (H.Ti in [C_TS_NA_1, C_CD_NA_1])) then
  begin
    { monitoring types, file transfer, several objects: not taken here; 104
      does not use test without time tag and delay acquisition }
    Answer(S, A, Len, Cot_UnknownType, True);
    Exit;
  end;
  { P/N is the confirmation's: in control direction no cause carries it }
  if not CotFits(H.Ti, H.Cot) or H.Negative then
  begin
    Answer(S, A, Len, Cot_UnknownCause, True);
    Exit;
  end;
  R := IecDecodeObject(S.Params, H, A, 0, O);
  if R <> res_Ok then
  begin
    Bad(S, 'object of ' + IecTypeName(H.Ti) + ': ' + ChResultText(R, Iec101Layer));
    Exit;
  end;
  case H.Ti of
    C_IC_NA_1, C_CI_NA_1: TakeInterrogation(S, A, Len, H, O);
    C_RD_NA_1: TakeRead(S, A, Len, O);
    P_ME_NA_1, P_ME_NB_1, P_ME_NC_1, P_AC_NA_1: TakeParameter(S, A, Len, H, O);
    C_CS_NA_1: TakeClock(S, A, Len, O);
    C_TS_NA_1, C_TS_TA_1, C_RP_NA_1:
      if (H.Ti = C_RP_NA_1) and (O.Int = Qrp_General) then
        GeneralReset(S, A, Len)
      else
      begin
        if (H.Ti = C_RP_NA_1) and (O.Int = Qrp_Events) then
          QueueDropTaggedEvents(S.Class1);
        Answer(S, A, Len, Cot_ActCon, False);
        if (H.Ti = C_RP_NA_1) and Assigned(S.OnReset) then
          S.OnReset(S.Data, O.Int);
      end;
    C_CD_NA_1:
      if H.Cot = Cot_Spontaneous then
        S.DelayMs := O.Elapsed                  { the delay: no answer }
      else
        Answer(S, A, Len, Cot_ActCon, False);
  else
    TakeCommand(S, A, Len, H, O);
  end;
end;

{- ------------------------------------------------------------- link glue }

function OnUserData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  S: pIecSlaveStation;
begin
  S := pIecSlaveStation(Data);
  { no room for the answers: NACK, the master sends it again }
  Result := S^.Class1.Count + 3 <= IecSlaveQueueLen;
  if Result then
    TakeAsdu(S^, Buf, Len);
end;

procedure Sent(var S: tIecSlaveStation; const Q: tIecQueued);
begin
  if Assigned(S.OnAsdu) then
    S.OnAsdu(S.Data, True, @Q.Data[0], Q.Len);
end;

function OnClassData(Data: Pointer; ClassNo: Byte; var Rep: tFT12MaxRecord; var Len: Word): Boolean;
var
  S: pIecSlaveStation;
  Q: ^tIecQueue;
  G: tIecQueued;
begin
  S := pIecSlaveStation(Data);
  if ClassNo = 1 then
    Q := @S^.Class1
  else
    Q := @S^.Class2;
  if ClassNo = 1 then
    FeedFiles(S^);
  if (ClassNo = 2) and (Q^.Count = 0) and S^.GiActive then
    if GiNextAsdu(S^, G) then
      QueuePut(Q^, G.Data, G.Len);
  Result := Q^.Count > 0;
  if not Result then
    Exit;
  Len := Q^.Items[Q^.Head].Len;
  Move(Q^.Items[Q^.Head].Data[0], Rep.Data[1], Len);
  Sent(S^, Q^.Items[Q^.Head]);
  QueueDrop(Q^);
end;

function OnClass1(Data: Pointer): Boolean;
begin
  Result := (pIecSlaveStation(Data)^.Class1.Count > 0) or FilesReady(pIecSlaveStation(Data)^);
end;

function IecSlaveInit(var S: tIecSlaveStation; Chn: pChnVirt; const P: tIecParams; Ca: Word;
  out Err: ShortString): tChResult;
var
  Balanced, Primary: Boolean;
begin
  FillChar(S, SizeOf(S), 0);
  S.Params := P;
  S.Ca := Ca;
  S.SelectMs := IecSlaveSelectMs;
  S.DeferSlot := -1;
  Result := IecCheckParams(P, Err);
  if Result <> res_Ok then
    Exit;
  Result := IecLinkKind(Chn, S.Over104, Balanced, Primary);
  if Result <> res_Ok then
  begin
    Err := 'the channel is no FT 1.2 or IEC 104 stack';
    Exit;
  end;
  if Ca > IecMaxCa(P) then
  begin
    Err := 'common address ' + IntToStr(Ca) + ' above ' + IntToStr(IecMaxCa(P));
    Exit(res_BadParam);
  end;
  S.Chn := Chn;
  S.Balanced := Balanced;
  if S.Balanced then
    Result := IecTransportStart(S.Link, Chn, @OnUserData, @S)
  else
  begin
    if Primary then
    begin
      Err := 'an unbalanced slave needs MAS=SLAVE';
      Exit(res_BadMessage);
    end;
    FT12StationInit(S.Station, Chn);
    S.Station.OnUserData := @OnUserData;
    S.Station.OnLongClassData := @OnClassData;
    S.Station.OnClass1 := @OnClass1;
    S.Station.Data := @S;
  end;
end;

{ Balanced and IEC 104: hand waiting ASDUs to the transport while it has
  room, class 1 first. }
procedure FeedBalanced(var S: tIecSlaveStation);
var
  G: tIecQueued;
  Q: ^tIecQueue;
begin
  while IecTransportRoom(S.Link) do
  begin
    FeedFiles(S);
    if S.Class1.Count > 0 then
      Q := @S.Class1
    else
    begin
      if (S.Class2.Count = 0) and S.GiActive and GiNextAsdu(S, G) then
        QueuePut(S.Class2, G.Data, G.Len);
      if S.Class1.Count > 0 then
        Continue;                                { ACT_TERM came first }
      if S.Class2.Count = 0 then
        Exit;
      Q := @S.Class2;
    end;
    if IecTransportSend(S.Link, @Q^.Items[Q^.Head].Data[0], Q^.Items[Q^.Head].Len) <> res_Ok then
      Exit;
    Sent(S, Q^.Items[Q^.Head]);
    QueueDrop(Q^);
  end;
end;

function IecSlaveStep(var S: tIecSlaveStation): Boolean;
begin
  Result := False;
  if S.Chn = nil then
    Exit;
  if S.Files <> nil then
    IecFileServerReady(S.Files^);        { its timer: a transfer left ends }
  if S.Balanced then
  begin
    Result := IecTransportStep(S.Link);
    FeedBalanced(S);
  end
  else
    Result := FT12StationStep(S.Station);
end;

function IecSlavePending(const S: tIecSlaveStation): Boolean;
begin
  Result := (S.Class1.Count > 0) or (S.Class2.Count > 0) or S.GiActive or
    ((S.Files <> nil) and IecFileServerBusy(S.Files^));
end;

function IecSlaveWaitMs(const S: tIecSlaveStation): LongInt;
begin
  if S.Over104 then
    Result := IecTransportWaitMs(S.Link, 1000)   { the layer's timers }
  else if S.Balanced and (IecSlavePending(S) or not IecTransportQuiet(S.Link) or
     not IecTransportUp(S.Link)) then
    Result := 10           { the balanced link's timers }
  else if S.Balanced then
    Result := 100          { test function timer }
  else
    Result := 1000;        { unbalanced: only the master's frames wake us }
end;

end.
