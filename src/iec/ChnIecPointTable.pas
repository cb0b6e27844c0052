{ ChnIecPointTable - the points an IEC 60870-5-101 master (ChnIec101Master,
  also over IEC 104) receives, kept as a gateway needs them: per (slave
  link address, common address, IOA) the value, the quality, the type and
  the UTC time; per slave its health and counters; commands to writable
  points queued and their outcome kept - the model of the PCCC tag engine
  (ChnPcccTags) for IEC points.

  Values. The table takes every monitoring object (types 1..21, 30..40)
  through the master's OnObject, whatever its cause (interrogated,
  spontaneous, requested, periodic). A point is created when its first
  object arrives, or before by IecTableAdd (to name it or mark it
  writable). Its value is a number: 0/1 single point, 0..3 double point
  (DPI), the step position, the scaled value, the normalized fraction, the
  float, the counter, the event state, or the bits of a bitstring. Its
  quality: the quality bits the object carried (IV NT SB BL OV, EI; for
  integrated totals IV only), and Bad while its slave is not ok. Its time:
  the object's CP56 time tag (taken as UTC); a CP24 tag (minute and ms
  only) completed with the hour and date that put it nearest to the UTC
  time it arrived (within half an hour: an event of 10:59:58 arriving at
  11:00:01 is of 10:59, not 11:59); without a tag, the time it arrived.
  Tagged and Tag keep the tag itself (a CP24 one completed) for a
  gateway that passes it on. Changes only: a point is queued for IecTableTakeChange when
  its quality, bad flag or type changed, or its value moved by more than
  its Deadband (analog kinds: normalized, scaled, float, counters; other
  kinds change on any difference).

  Health, from what the master itself knows (IecMasterSlaveInfo): ok
  while the slave is online and answers polls; down after it failed a
  service (dead) or while its link is being set up again; demoted when it
  failed again after its back-off (the master then tries it only every
  BackoffMs, doubling up to DeadMaxMs, so a dead slave does not slow the
  others). Its points go Bad while it is not ok. When a slave becomes ok
  the table interrogates it (station interrogation), so values are known
  again; with GiMs set, also every GiMs. Counters: polls (class polls
  answered), errors (services unanswered, malformed ASDUs, commands that
  failed), retries (link repetitions) and the last error's text.

  Commands. IecTableWrite queues a value for a writable point; it goes to
  the slave as the command of the point's type (single point C_SC_NA_1,
  double point C_DC_NA_1, normalized C_SE_NA_1, scaled C_SE_NB_1, float
  C_SE_NC_1, bitstring C_BO_NA_1) to its command IOA, one at a time, and
  its outcome (positive ACT_CON: res_Ok; negative: res_IecNegative; no
  confirmation: res_Timeout ...) comes back through IecTableTakeWrite with
  the caller's Id. The slave's new value comes back as its own object.

  The table steps the master (IecTableStep instead of IecMasterStep); it
  sets the master's OnObject, OnBad and Data. Nothing here waits. }
unit ChnIecPointTable;

{$I chn.inc}

interface

uses
  ChnTypes, ChnRing, ChnIec101Asdu, ChnIec101Master;

type
  tIecHealth = (ihOk, ihDown, ihDemoted);

  tIecTablePoint = record
    Name    : ShortString;   {< the name it is published under ('' : its IOA) }
    Addr    : Word;          {< slave link address }
    Ca      : Word;
    Ioa     : LongWord;
    Ti      : Byte;          {< type of the last object (0: none yet) }
    Value   : Double;
    Quality : Byte;          {< quality bits as on the wire (Q_Invalid ...) }
    Known   : Boolean;       {< a value arrived }
    Bad     : Boolean;       {< its slave is not ok }
    TimeMs  : Int64;         {< UTC ms since 1970 }
    Tagged  : Boolean;       {< the last object had a time tag: }
    Tag     : tIecTime;      {< it, as received (CP24: completed as CP56) }
    Cot     : Byte;          {< cause of the last object }
    Deadband: Double;
    Writable: Boolean;
    CmdIoa  : LongWord;      {< where its commands go (default: Ioa) }
    CmdTi   : Byte;          {< the command type (0: from Ti, IecCommandType) }
    SentValue: Double;       {< as last taken by IecTableTakeChange }
    SentQuality: Byte;
    SentBad, SentKnown: Boolean;
    SentTi  : Byte;
    Queued  : Boolean;
  end;

  tIecTableSlave = record
    Addr     : Word;
    Ca       : Word;         {< common address of its interrogations }
    Health   : tIecHealth;
    Changed  : Boolean;      {< health to report (IecTableTakeHealth) }
    Started  : Boolean;      {< health known once }
    GiDue    : Boolean;
    GiAt     : QWord;        {< next periodic interrogation (GiMs) }
    Polls, Errors, Retries: LongInt;
    LastError: ShortString;
    SeenFailures, SeenBad: LongInt;   {< the master's counters last looked at }
  end;

  tIecTableWrite = record
    Point: LongInt;
    Value: Double;
    Select: Boolean;         {< a select (S/E = 1) alone }
    Qu   : Byte;             {< the qualifier: QU of a command, QL of a set point }
    Id   : LongInt;
    Res  : tChResult;
    Err  : ShortString;
  end;

  tIecPointTable = record
    M       : pIecMaster;
    Points  : array of tIecTablePoint;
    Slaves  : array of tIecTableSlave;
    Deadband: Double;        {< of points the table creates }
    GiMs    : LongInt;       {< periodic station interrogation (0: only when a slave comes back) }
    Writes  : array of tIecTableWrite;   {< waiting, Writes[0] under way when Running }
    Done    : array of tIecTableWrite;   {< finished, for IecTableTakeWrite }
    Running : Boolean;       {< a command of the table is under way }
    RunGi   : LongInt;       {< the slave whose interrogation is under way, -1 none }
    Changes : tIndexQueue;   {< points queued, oldest first }
    Objects : LongInt;       {< monitoring objects taken }
  end;
  pIecPointTable = ^tIecPointTable;

const
  IecHealthNames: array[tIecHealth] of string[7] = ('ok', 'down', 'demoted');

{ A table for master M (initialised, its slaves added; it must not move
  afterwards, nor T), every slave interrogated at common address Ca when
  it comes up. Sets M's OnObject, OnBad and Data. }
procedure IecTableInit(var T: tIecPointTable; var M: tIecMaster; Ca: Word);
procedure IecTableDone(var T: tIecPointTable);
{ Declare a point before its first object (a name, writable); its index.
  A point already there is named (when Name <> '') and returned. }
function IecTableAdd(var T: tIecPointTable; Addr, Ca: Word; Ioa: LongWord;
  const Name: ShortString): LongInt;
{ Mark point P writable: commands go to CmdIoa as type CmdTi (0: the
  command of the point's type). }
procedure IecTableSetWritable(var T: tIecPointTable; P: LongInt; CmdIoa: LongWord; CmdTi: Byte);
{ Index of a point, -1 when none. }
function IecTableFind(const T: tIecPointTable; Addr, Ca: Word; Ioa: LongWord): LongInt;
{ Index of slave Addr in T.Slaves, -1 when none. }
function IecTableSlave(const T: tIecPointTable; Addr: Word): LongInt;

{ Step the master, start the next command or interrogation, follow the
  health. True when something happened. }
function IecTableStep(var T: tIecPointTable): Boolean;
{ The master's line itself failed (IecMasterLineResult): every slave is
  down, its points bad. (The program opens the line again, and starts
  the master and IecTableInit anew.) }
procedure IecTableLineDown(var T: tIecPointTable);
{ ms until the table needs a step with no input (ChnWaitAny). }
function IecTableWaitMs(const T: tIecPointTable): LongInt;

{ The next changed point; its Sent* become its current state. }
function IecTableTakeChange(var T: tIecPointTable; out P: LongInt): Boolean;
{ The next slave whose health changed (index in T.Slaves). }
function IecTableTakeHealth(var T: tIecPointTable; out S: LongInt): Boolean;

{ Queue a command of Value to point P; False with Err (not writable, no
  command for its type or the type not known yet, a value the type cannot
  take, its slave not ok) when refused at once. }
function IecTableWrite(var T: tIecPointTable; P: LongInt; Value: Double; Id: LongInt;
  out Err: ShortString): Boolean;
{ The same with the S/E bit and the qualifier (QU 0..31 of a single,
  double or step command, QL 0..127 of a set point) the RTU gets: a
  select goes alone, ending on the RTU's ACT_CON (a gateway passes a
  control centre's select-before-operate on, step by step). }
function IecTableCommand(var T: tIecPointTable; P: LongInt; Value: Double; Select: Boolean; Qu: Byte;
  Id: LongInt; out Err: ShortString): Boolean;
{ A finished command: res_Ok on a positive ACT_CON, else the failure and
  its text. False when none finished. }
function IecTableTakeWrite(var T: tIecPointTable; out W: tIecTableWrite): Boolean;

{ The command type for a monitoring type (C_SC_NA_1 for M_SP_*, ...); 0
  when it has none. }
function IecCommandType(MonTi: Byte): Byte;
{ 'good', 'bad' (slave not ok), 'initial' (no value yet), or the quality
  bits set, joined by '+' ('IV', 'NT+SB'). }
function IecPointQualityText(const P: tIecTablePoint): ShortString;
{ True for the kinds whose Deadband applies. }
function IecPointIsAnalog(const P: tIecTablePoint): Boolean;

implementation

uses
  SysUtils, ChnVirt, ChnWait;

const
  GiMsDefault = 0;

procedure Noticed(var T: tIecPointTable; P: LongInt);
var
  Pt: ^tIecTablePoint;
  Moved: Boolean;
begin
  Pt := @T.Points[P];
  if Pt^.Queued then
    Exit;
  if IecPointIsAnalog(Pt^) then
    Moved := Abs(Pt^.Value - Pt^.SentValue) > Pt^.Deadband
  else
    Moved := Pt^.Value <> Pt^.SentValue;
  { a point with no value that is not bad has nothing to say (yet) }
  if not Pt^.Known and not Pt^.Bad then
    Exit;
  if Moved or (Pt^.Quality <> Pt^.SentQuality) or (Pt^.Bad <> Pt^.SentBad) or
     (Pt^.Known <> Pt^.SentKnown) or (Pt^.Ti <> Pt^.SentTi) then
  begin
    Pt^.Queued := True;
    IndexQueuePut(T.Changes, P);
  end;
end;

function IecPointIsAnalog(const P: tIecTablePoint): Boolean;
begin
  Result := IecTypeKind(P.Ti) in [ikNormal, ikScaled, ikFloat, ikCounter];
end;

function IecCommandType(MonTi: Byte): Byte;
begin
  case IecTypeKind(MonTi) of
    ikSingle: Result := C_SC_NA_1;
    ikDouble: Result := C_DC_NA_1;
    ikNormal: Result := C_SE_NA_1;
    ikScaled: Result := C_SE_NB_1;
    ikFloat : Result := C_SE_NC_1;
    ikBits  : Result := C_BO_NA_1;
  else
    Result := 0;
  end;
end;

function IecPointQualityText(const P: tIecTablePoint): ShortString;
const
  Bits: array[0..5] of Byte = (Q_Invalid, Q_NotTopical, Q_Substituted, Q_Blocked, Q_Overflow, Q_ElapsedInv);
  Names: array[0..5] of string[2] = ('IV', 'NT', 'SB', 'BL', 'OV', 'EI');
var
  Q: Byte;
  I: LongInt;
begin
  if P.Bad then
    Exit('bad');
  if not P.Known then
    Exit('initial');
  Q := P.Quality;
  if IecTypeKind(P.Ti) = ikCounter then
    Q := Q and Q_Invalid;         { CY, CA: carry and adjusted, no quality }
  Result := '';
  for I := 0 to High(Bits) do
    if Q and Bits[I] <> 0 then
    begin
      if Result <> '' then
        Result := Result + '+';
      Result := Result + Names[I];
    end;
  if Result = '' then
    Result := 'good';
end;

function IecTableFind(const T: tIecPointTable; Addr, Ca: Word; Ioa: LongWord): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(T.Points) do
    if (T.Points[I].Ioa = Ioa) and (T.Points[I].Addr = Addr) and (T.Points[I].Ca = Ca) then
      Exit(I);
  Result := -1;
end;

function IecTableSlave(const T: tIecPointTable; Addr: Word): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(T.Slaves) do
    if T.Slaves[I].Addr = Addr then
      Exit(I);
  Result := -1;
end;

function IecTableAdd(var T: tIecPointTable; Addr, Ca: Word; Ioa: LongWord;
  const Name: ShortString): LongInt;
var
  S: LongInt;
begin
  Result := IecTableFind(T, Addr, Ca, Ioa);
  if Result < 0 then
  begin
    Result := Length(T.Points);
    SetLength(T.Points, Result + 1);
    FillChar(T.Points[Result], SizeOf(tIecTablePoint), 0);
    T.Points[Result].Addr := Addr;
    T.Points[Result].Ca := Ca;
    T.Points[Result].Ioa := Ioa;
    T.Points[Result].CmdIoa := Ioa;
    T.Points[Result].Deadband := T.Deadband;
    S := IecTableSlave(T, Addr);
    T.Points[Result].Bad := (S >= 0) and (T.Slaves[S].Health <> ihOk);
  end;
  if Name <> '' then
    T.Points[Result].Name := Name;
end;

procedure IecTableSetWritable(var T: tIecPointTable; P: LongInt; CmdIoa: LongWord; CmdTi: Byte);
begin
  T.Points[P].Writable := True;
  T.Points[P].CmdIoa := CmdIoa;
  T.Points[P].CmdTi := CmdTi;
end;

const
  HourMs = 3600000;

{ A CP24 time (minute, ms) completed to the UTC ms nearest to Arrived. }
function CompleteCp24(const Tm: tIecTime; Arrived: Int64): Int64;
begin
  Result := Arrived - Arrived mod HourMs + Int64(Tm.Minute) * 60000 + Tm.Msec;
  if Result - Arrived > HourMs div 2 then
    Dec(Result, HourMs)
  else if Arrived - Result > HourMs div 2 then
    Inc(Result, HourMs);
end;

{ The object's time: its CP56 tag (UTC), its CP24 tag completed, else
  now; Tagged and Tag when it had one. }
procedure TakeTime(var Pt: tIecTablePoint; Ti: Byte; const O: tIecObject);
var
  DT: TDateTime;
  Invalid: Boolean;
begin
  Pt.TimeMs := ChUtcMs;
  Pt.Tagged := False;
  case IecTypeTime(Ti) of
    tkCP56:
      if IecTimeToDateTime(O.Time, DT) then
      begin
        Pt.TimeMs := Round((DT - UnixDateDelta) * MSecsPerDay);
        Pt.Tagged := True;
        Pt.Tag := O.Time;
      end;
    tkCP24:
      if (O.Time.Minute < 60) and (O.Time.Msec < 60000) then
      begin
        Pt.TimeMs := CompleteCp24(O.Time, Pt.TimeMs);
        Invalid := O.Time.Invalid;
        Pt.Tag := IecTimeFromDateTime(UnixDateDelta + Pt.TimeMs / MSecsPerDay);
        { the RTU's own minute and ms, not a rounding of them }
        Pt.Tag.Minute := O.Time.Minute;
        Pt.Tag.Msec := O.Time.Msec;
        Pt.Tag.Invalid := Invalid;
        Pt.Tagged := True;
      end;
  end;
end;

function ObjectValue(Ti: Byte; const O: tIecObject): Double;
begin
  case IecTypeKind(Ti) of
    ikNormal, ikFloat: Result := O.Number;
    ikBits, ikPacked, ikStartEvents, ikOutputCircuit: Result := O.Bits;
  else
    Result := O.Int;
  end;
end;

procedure OnObject(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
var
  T: pIecPointTable;
  P: LongInt;
begin
  T := pIecPointTable(Data);
  if not IecIsMonitor(H.Ti) or (H.Ti = M_EI_NA_1) or H.Negative then
    Exit;
  Inc(T^.Objects);
  P := IecTableAdd(T^, Addr, H.Ca, O.Ioa, '');
  with T^.Points[P] do
  begin
    Ti := H.Ti;
    Cot := H.Cot;
    Value := ObjectValue(H.Ti, O);
    Quality := O.Quality;
    Known := True;
  end;
  TakeTime(T^.Points[P], H.Ti, O);
  Noticed(T^, P);
end;

procedure NoteError(var S: tIecTableSlave; const Err: ShortString);
begin
  Inc(S.Errors);
  S.LastError := Err;
end;

procedure OnBad(Data: Pointer; Addr: Word; const Err: ShortString);
var
  T: pIecPointTable;
  S: LongInt;
begin
  T := pIecPointTable(Data);
  S := IecTableSlave(T^, Addr);
  if S >= 0 then
    NoteError(T^.Slaves[S], 'malformed ASDU: ' + Err);
end;

procedure IecTableInit(var T: tIecPointTable; var M: tIecMaster; Ca: Word);
var
  Info: tIecSlave;
  I: LongInt;
begin
  IecTableDone(T);
  FillChar(T, SizeOf(T), 0);
  T.M := @M;
  T.GiMs := GiMsDefault;
  T.RunGi := -1;
  I := 0;
  while IecMasterSlaveInfo(M, I, Info) do
  begin
    SetLength(T.Slaves, I + 1);
    FillChar(T.Slaves[I], SizeOf(tIecTableSlave), 0);
    T.Slaves[I].Addr := Info.Addr;
    T.Slaves[I].Ca := Ca;
    T.Slaves[I].Health := ihOk;      { as a PLC of the tag engine: until it fails }
    Inc(I);
  end;
  M.OnObject := @OnObject;
  M.OnBad := @OnBad;
  M.Data := @T;
end;

procedure IecTableDone(var T: tIecPointTable);
begin
  T.Points := nil;
  T.Slaves := nil;
  T.Writes := nil;
  T.Done := nil;
  IndexQueueClear(T.Changes);
end;

{- ------------------------------------------------------------ health }

function HealthOf(const T: tIecPointTable; const Info: tIecSlave; Old: tIecHealth): tIecHealth;
begin
  case Info.State of
    isOnline:
      if Info.Probation then
        Result := Old                { set up again, no poll answered yet }
      else
        Result := ihOk;
    isDead:
      if Info.BackoffMs > T.M^.DeadMinMs then
        Result := ihDemoted          { failed again after its back-off }
      else
        Result := ihDown;
  else
    if (Old = ihDemoted) and Info.Probation then
      Result := ihDemoted
    else
      Result := ihDown;
  end;
end;

procedure MarkSlave(var T: tIecPointTable; S: LongInt);
var
  I: LongInt;
  B: Boolean;
begin
  B := T.Slaves[S].Health <> ihOk;
  for I := 0 to High(T.Points) do
    if (T.Points[I].Addr = T.Slaves[S].Addr) and (T.Points[I].Bad <> B) then
    begin
      T.Points[I].Bad := B;
      T.Points[I].TimeMs := ChUtcMs;
      T.Points[I].Tagged := False;     { the master's news, of now }
      Noticed(T, I);
    end;
end;

function FollowHealth(var T: tIecPointTable): Boolean;
var
  I: LongInt;
  Info: tIecSlave;
  H: tIecHealth;
begin
  Result := False;
  for I := 0 to High(T.Slaves) do
    with T.Slaves[I] do
    begin
      if not IecMasterSlaveInfo(T.M^, I, Info) then
        Continue;
      Polls := Info.Class1 + Info.Class2;
      Retries := Info.Link.Repeats;
      if Info.Failures > SeenFailures then
      begin
        Inc(Errors, Info.Failures - SeenFailures);
        SeenFailures := Info.Failures;
        LastError := 'no answer from link address ' + IntToStr(Addr) + IecLineShowed(T.M^, I);
      end;
      { nothing to say before its link is first up or a service failed }
      if not Started and (Info.State in [isOffline, isLinkStatus]) and (Info.Failures = 0) then
        Continue;
      H := HealthOf(T, Info, Health);
      if (H <> Health) or not Started then
      begin
        if (H = ihOk) and ((Health <> ihOk) or not Started) then
          GiDue := True;             { values known (again) }
        Health := H;
        Changed := True;
        Started := True;
        MarkSlave(T, I);
        Result := True;
      end;
      if (T.GiMs > 0) and (Health = ihOk) and (ChMsTick >= GiAt) then
      begin
        GiDue := True;
        GiAt := ChMsTick + QWord(T.GiMs);
      end;
    end;
end;

procedure IecTableLineDown(var T: tIecPointTable);
var
  I: LongInt;
begin
  for I := 0 to High(T.Slaves) do
    if T.Slaves[I].Health <> ihDown then
    begin
      T.Slaves[I].Health := ihDown;
      T.Slaves[I].Changed := True;
      MarkSlave(T, I);
    end;
end;

{- ------------------------------------------------------------ commands }

procedure Finished(var T: tIecPointTable; var W: tIecTableWrite);
begin
  SetLength(T.Done, Length(T.Done) + 1);
  T.Done[High(T.Done)] := W;
end;

procedure DropFirstWrite(var T: tIecPointTable);
begin
  if Length(T.Writes) > 1 then
    Move(T.Writes[1], T.Writes[0], (Length(T.Writes) - 1) * SizeOf(tIecTableWrite));
  { the moved records' strings are ShortStrings: a plain move is right }
  SetLength(T.Writes, Length(T.Writes) - 1);
end;

function CommandTi(const P: tIecTablePoint): Byte;
begin
  if P.CmdTi <> 0 then
    Result := P.CmdTi
  else
    Result := IecCommandType(P.Ti);
end;

{ The command object of Value for type Ti; False with Err when the type
  cannot take it. }
function CommandObject(Ti: Byte; Ioa: LongWord; Value: Double; out O: tIecObject;
  out Err: ShortString): Boolean;
begin
  O := IecObject(Ioa);
  Err := '';
  case IecTypeKind(Ti) of
    ikSingleCmd:
      if (Value = 0) or (Value = 1) then
        O.Int := Round(Value)
      else
        Err := 'a single command is 0 or 1 (false or true)';
    ikDoubleCmd:
      if (Value = 1) or (Value = 2) then
        O.Int := Round(Value)
      else
        Err := 'a double command is 1 (off) or 2 (on)';
    ikSetNormal:
      if (Value >= -1) and (Value < 1) then
        O.Number := Value
      else
        Err := 'a normalized set point is -1 <= x < 1';
    ikSetScaled:
      if (Frac(Value) = 0) and (Value >= -32768) and (Value <= 32767) then
        O.Int := Round(Value)
      else
        Err := 'a scaled set point is a whole number -32768..32767';
    ikSetFloat:
      if (Abs(Value) <= 3.4e38) then
        O.Number := Value
      else
        Err := 'a float set point is a number within a single''s range';
    ikBitsCmd:
      if (Frac(Value) = 0) and (Value >= 0) and (Value <= 4294967295.0) then
        O.Bits := LongWord(Round(Value))
      else
        Err := 'a bitstring is a whole number 0..4294967295';
  else
    Err := 'no command for type ' + IecTypeName(Ti);
  end;
  Result := Err = '';
end;

function IecTableWrite(var T: tIecPointTable; P: LongInt; Value: Double; Id: LongInt;
  out Err: ShortString): Boolean;
begin
  Result := IecTableCommand(T, P, Value, False, 0, Id, Err);
end;

function IecTableCommand(var T: tIecPointTable; P: LongInt; Value: Double; Select: Boolean; Qu: Byte;
  Id: LongInt; out Err: ShortString): Boolean;
var
  O: tIecObject;
  CmdType: Byte;
  S, K: LongInt;
  Pt: ^tIecTablePoint;
begin
  Result := False;
  if (P < 0) or (P > High(T.Points)) then
  begin
    Err := 'no such point';
    Exit;
  end;
  Pt := @T.Points[P];
  if not Pt^.Writable then
  begin
    Err := 'IOA ' + IntToStr(Pt^.Ioa) + ' is not writable';
    Exit;
  end;
  CmdType := CommandTi(Pt^);
  if CmdType = 0 then
  begin
    if Pt^.Known then
      Err := 'IOA ' + IntToStr(Pt^.Ioa) + ': no command for type ' + IecTypeName(Pt^.Ti)
    else
      Err := 'IOA ' + IntToStr(Pt^.Ioa) + ': its type is not known yet (no value received)';
    Exit;
  end;
  if not CommandObject(CmdType, Pt^.CmdIoa, Value, O, Err) then
  begin
    Err := 'IOA ' + IntToStr(Pt^.Ioa) + ': ' + Err;
    Exit;
  end;
  S := IecTableSlave(T, Pt^.Addr);
  if (S < 0) or (T.Slaves[S].Health <> ihOk) then
  begin
    Err := 'IOA ' + IntToStr(Pt^.Ioa) + ': slave ' + IntToStr(Pt^.Addr) + ' is not ok';
    if S >= 0 then
      Err := Err + ' (' + IecHealthNames[T.Slaves[S].Health] + ')';
    Exit;
  end;
  K := Length(T.Writes);
  SetLength(T.Writes, K + 1);
  T.Writes[K].Point := P;
  T.Writes[K].Value := Value;
  T.Writes[K].Select := Select;
  T.Writes[K].Qu := Qu;
  T.Writes[K].Id := Id;
  T.Writes[K].Res := res_Ok;
  T.Writes[K].Err := '';
  Result := True;
end;

function IecTableTakeWrite(var T: tIecPointTable; out W: tIecTableWrite): Boolean;
begin
  Result := Length(T.Done) > 0;
  if not Result then
    Exit;
  W := T.Done[0];
  if Length(T.Done) > 1 then
    Move(T.Done[1], T.Done[0], (Length(T.Done) - 1) * SizeOf(tIecTableWrite));
  SetLength(T.Done, Length(T.Done) - 1);
end;

{ The table's command under way ended. }
procedure CommandEnded(var T: tIecPointTable);
var
  R: tChResult;
  E: ShortString;
  S: LongInt;
begin
  R := IecCommandResult(T.M^, E);
  T.Running := False;
  if T.RunGi >= 0 then
  begin
    if R <> res_Ok then
      NoteError(T.Slaves[T.RunGi], E);
    T.RunGi := -1;
    Exit;
  end;
  T.Writes[0].Res := R;
  T.Writes[0].Err := E;
  if R <> res_Ok then
  begin
    S := IecTableSlave(T, T.Points[T.Writes[0].Point].Addr);
    if S >= 0 then
      NoteError(T.Slaves[S], E);
  end;
  Finished(T, T.Writes[0]);
  DropFirstWrite(T);
end;

{ Start the next write, else an interrogation that is due. }
procedure StartNext(var T: tIecPointTable);
var
  O: tIecObject;
  E: ShortString;
  I: LongInt;
  CmdType: Byte;
  Pt: ^tIecTablePoint;
begin
  if Length(T.Writes) > 0 then
  begin
    Pt := @T.Points[T.Writes[0].Point];
    CmdType := CommandTi(Pt^);
    CommandObject(CmdType, Pt^.CmdIoa, T.Writes[0].Value, O, E);
    O.Select := T.Writes[0].Select;
    O.Qu := T.Writes[0].Qu;
    if IecStartCommand(T.M^, Pt^.Addr, Pt^.Ca, CmdType, O, False) then
      T.Running := True
    else
    begin
      T.Writes[0].Res := IecCommandResult(T.M^, E);
      T.Writes[0].Err := E;
      Finished(T, T.Writes[0]);
      DropFirstWrite(T);
    end;
    Exit;
  end;
  for I := 0 to High(T.Slaves) do
    if T.Slaves[I].GiDue and (T.Slaves[I].Health = ihOk) then
    begin
      T.Slaves[I].GiDue := False;
      if IecStartInterrogation(T.M^, T.Slaves[I].Addr, T.Slaves[I].Ca, Qoi_Station) then
      begin
        T.Running := True;
        T.RunGi := I;
      end;
      Exit;
    end;
end;

{- ------------------------------------------------------------ stepping }

function IecTableStep(var T: tIecPointTable): Boolean;
begin
  Result := IecMasterStep(T.M^);
  if T.Running and IecCommandDone(T.M^) then
  begin
    CommandEnded(T);
    Result := True;
  end;
  if FollowHealth(T) then
    Result := True;
  if not T.Running and IecCommandDone(T.M^) then
  begin
    StartNext(T);
    if T.Running then
      Result := True;              { its first frame is due now: step again }
  end;
end;

function IecTableWaitMs(const T: tIecPointTable): LongInt;
begin
  if (Length(T.Writes) > 0) and not T.Running then
    Result := 0
  else
    Result := ChnWaitLeft(IecMasterWaitEnd(T.M^));
end;

function IecTableTakeChange(var T: tIecPointTable; out P: LongInt): Boolean;
begin
  Result := IndexQueueTake(T.Changes, P);
  if not Result then
    Exit;
  with T.Points[P] do
  begin
    Queued := False;
    SentValue := Value;
    SentQuality := Quality;
    SentBad := Bad;
    SentKnown := Known;
    SentTi := Ti;
  end;
end;

function IecTableTakeHealth(var T: tIecPointTable; out S: LongInt): Boolean;
var
  I: LongInt;
begin
  for I := 0 to High(T.Slaves) do
    if T.Slaves[I].Changed then
    begin
      T.Slaves[I].Changed := False;
      S := I;
      Exit(True);
    end;
  S := -1;
  Result := False;
end;

end.
