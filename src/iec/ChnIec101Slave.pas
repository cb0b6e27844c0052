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
    smoothing, limits kept per IOA; in operation, the threshold a deadband
    on the spontaneous reports, the smoothing factor a filter on the
    value, a change of zone between the limits reported (ChnIecMeasParams);
    reported after the points of a station interrogation) and their activation (P_AC_NA_1): ACT_CON / DEACT_CON;
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
  helpers send the answer at once) and returns.

  The slave's parts, a unit each: ChnIec101SlaveTypes (the record),
  ChnIec101SlaveQueue (the class 1 / class 2 queues and the answers put
  in them), ChnIec101SlavePoints (the point table, updates, events),
  ChnIec101SlaveGi (interrogations), ChnIec101SlaveCommands (commands,
  select before operate, deferred confirmation), ChnIec101SlaveParams
  (parameters of measured values). This unit is the program's interface:
  set-up, the ASDUs received handed to those parts (and clock
  synchronisation, read, test, reset of process, delay acquisition, end
  of initialisation), the link side (unbalanced station or balanced
  transport) and the file transfer hooks. }
unit ChnIec101Slave;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Station, ChnIec101Asdu, ChnIecTransport,
  ChnIecFile, ChnIecFileServer, ChnIec101SlaveTypes;

{ The slave's names, declared in ChnIec101SlaveTypes (why: see there),
  given again here for programs that use this unit. }
const
  IecSlaveMaxPoints   = ChnIec101SlaveTypes.IecSlaveMaxPoints;
  IecSlaveQueueLen    = ChnIec101SlaveTypes.IecSlaveQueueLen;
  IecSlaveSelectMs    = ChnIec101SlaveTypes.IecSlaveSelectMs;
  IecSlaveMaxDeferred = ChnIec101SlaveTypes.IecSlaveMaxDeferred;

type
  tIecPoint            = ChnIec101SlaveTypes.tIecPoint;
  pIecPoint            = ChnIec101SlaveTypes.pIecPoint;
  tIecQueued           = ChnIec101SlaveTypes.tIecQueued;
  tIecQueue            = ChnIec101SlaveTypes.tIecQueue;
  tIecDeferred         = ChnIec101SlaveTypes.tIecDeferred;
  tIecSlaveCommandFunc = ChnIec101SlaveTypes.tIecSlaveCommandFunc;
  tIecSlaveClockFunc   = ChnIec101SlaveTypes.tIecSlaveClockFunc;
  tIecSlaveAsduFunc    = ChnIec101SlaveTypes.tIecSlaveAsduFunc;
  tIecSlaveBadFunc     = ChnIec101SlaveTypes.tIecSlaveBadFunc;
  tIecSlaveResetFunc   = ChnIec101SlaveTypes.tIecSlaveResetFunc;
  tIecSlaveStation     = ChnIec101SlaveTypes.tIecSlaveStation;
  pIecSlaveStation     = ChnIec101SlaveTypes.pIecSlaveStation;


{ A slave on an open tChnFT1_2 stack (it stays the caller's) with the
  application parameters P and common address Ca. res_WrongLayer (no
  tChnFT1_2), res_AsduParam (Err), res_BadParam (Ca above the CA size),
  res_BadMessage (an unbalanced master channel). S must not move
  afterwards (the channel receives into it). Its point table is a dynamic
  array: S is a variable, a field or New's (memory Pascal initialised),
  and Dispose or the end of its scope frees the table. }
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
{ Room for N points in all (IecSlaveMaxPoints at most) at once: a program
  that knows its table's size saves the table's steps of
  IecSlavePointStep points (each moves the table). }
procedure IecSlaveReservePoints(var S: tIecSlaveStation; N: LongInt);
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
  SysUtils, DateUtils, ChnIec101SlaveQueue, ChnIec101SlavePoints, ChnIec101SlaveGi,
  ChnIec101SlaveCommands, ChnIec101SlaveParams;

{- ------------------------------------------- the parts' public calls }

function IecSlaveAddPoint(var S: tIecSlaveStation; Ti: Byte; const Obj: tIecObject; Group: Byte;
  out Err: ShortString): tChResult;
begin
  Result := ChnIec101SlavePoints.IecSlaveAddPoint(S, Ti, Obj, Group, Err);
end;

procedure IecSlaveReservePoints(var S: tIecSlaveStation; N: LongInt);
begin
  ChnIec101SlavePoints.IecSlaveReservePoints(S, N);
end;

function IecSlaveFind(const S: tIecSlaveStation; Ioa: LongWord): LongInt;
begin
  Result := ChnIec101SlavePoints.IecSlaveFind(S, Ioa);
end;

function IecSlaveEventType(var S: tIecSlaveStation; Ioa: LongWord; Ti: Byte;
  out Err: ShortString): tChResult;
begin
  Result := ChnIec101SlavePoints.IecSlaveEventType(S, Ioa, Ti, Err);
end;

function IecSlaveUpdate(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
begin
  Result := ChnIec101SlavePoints.IecSlaveUpdate(S, Ioa, Obj, Spontaneous, Err);
end;

function IecSlaveUpdateAt(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
begin
  Result := ChnIec101SlavePoints.IecSlaveUpdateAt(S, Ioa, Obj, Spontaneous, Err);
end;

function IecSlaveNow(const S: tIecSlaveStation): TDateTime;
begin
  Result := ChnIec101SlavePoints.IecSlaveNow(S);
end;

function IecSlaveDefer(var S: tIecSlaveStation): LongWord;
begin
  Result := ChnIec101SlaveCommands.IecSlaveDefer(S);
end;

function IecSlaveConfirm(var S: tIecSlaveStation; Ticket: LongWord; Ok: Boolean): tChResult;
begin
  Result := ChnIec101SlaveCommands.IecSlaveConfirm(S, Ticket, Ok);
end;

function IecSlaveDeferred(const S: tIecSlaveStation): LongInt;
begin
  Result := ChnIec101SlaveCommands.IecSlaveDeferred(S);
end;

{- ------------------------------------------------------------ file hooks }

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

{- ---------------------------------------------------------------- answers }

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
  S.Points := nil;              { a station set up again: its old table goes }
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
