{ ChnGate104 - the IEC 60870-5-104 north of tools/chngate: one point
  table for every south device, served by the library's IEC 101 slave
  (ChnIec101Slave) over NAM=IEC104 - one application layer, the same
  procedures as on a serial line (interrogation, read, clock
  synchronisation, commands with select and execute).

  Points (docs/chngate.md, "IEC 104"): each item of a DF1 tag is one
  point, IOAs consecutive from the device's ioa= in tag order (an array
  N7:0[10] takes ten, a whole timer three: control word, PRE, ACC; a
  string tag none):
    a bit (B3:0/5, T4:0.DN ...)          M_SP_NA_1, events M_SP_TB_1
    a signed word (N, T/C/R words)       M_ME_NB_1 scaled, events M_ME_TE_1
    a float (F)                          M_ME_NC_1, events M_ME_TF_1
    a 32-bit integer (L), a word of
    bits (B, S, I, O, A)                 M_BO_NA_1 bitstring, events M_BO_TB_1
  The quality comes from the tag and its device's health: good 0; the
  device did not answer (down) IV; demoted IV + NT (not tried at its
  rate); refused by the PLC IV; not read yet IV + NT.

  Commands: a writable tag has command points at its IOA (C_SC_NA_1 /
  C_SC_TA_1 for a bit, C_SE_NB_1 / C_SE_TB_1 for a word, C_SE_NC_1 /
  C_SE_TC_1 for a float, C_BO_NA_1 / C_BO_TA_1 for a bitstring); an
  execute becomes a PCCC write (ChnPcccTags) and its ACT_CON is deferred
  (IecSlaveDefer) until the PLC confirmed the write - negative when it
  refused, did not answer, or the command waited longer than
  CommandMs. A select is confirmed at once (nothing reaches the PLC). A
  command to any other IOA or of another type is refused by the slave
  with COT 47 (unknown IOA).

  IEC 101 devices (ChnGateIec101): their points are passed through, each
  as it is first reported, at the device's ioa= offset + its IOA, with
  its own type (a CP24 type served as its CP56 counterpart; when the RTU
  reports one point both with and without time tag, the interrogation
  keeps the first and the events take the other); the quality bits the
  RTU sent, IV added while the RTU is not ok. A writable point takes
  commands of its command type (and that type with CP56 time) at offset +
  its command IOA; they go to the RTU as that command with that value,
  and the ACT_CON waits for the RTU's. }
unit ChnGate104;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnPcccTags, ChnIec101Asdu, ChnIec101Slave, ChnIecPointTable, ChnGateIec101;

const
  Gate104CommandMsDefault = 10000;
  Gate104PortDefault      = 2404;

type
  tGate104Log = procedure(const Line: AnsiString);

  { The [iec104] section. }
  tGate104Cfg = record
    Present  : Boolean;
    Listen   : AnsiString;   {< HOST:PORT }
    Ca       : LongInt;      {< common address of ASDU }
    Params   : AnsiString;   {< K= W= T0= .. CON= given, for NAM=IEC104 }
    CommandMs: LongInt;      {< longest wait for the device's confirmation }
  end;

  { One point and where its value comes from. }
  tGate104Point = record
    Ioa   : LongWord;
    Ti    : Byte;            {< monitoring type }
    Cmd   : Byte;            {< command type without time tag, 0: not writable }
    Dev, Tag, Item: LongInt; {< the device, its tag, the item of the tag }
    Iec   : pGateIecDevice;  {< or an IEC 101 device (nil: a DF1 tag) }
    IecPoint: LongInt;       {< its point (ChnIecPointTable) }
    CmdIoa: LongWord;        {< where its commands come (a DF1 tag: Ioa) }
    EvTi  : Byte;            {< an IEC 101 point: the type its events take (0: Ti) }
    Owner : AnsiString;      {< 'DEVICE TAG' or 'DEVICE POINT', for a clash's message }
    Sent  : Double;          {< value and quality the slave's table has }
    SentQ : Byte;
  end;

  { A command passed south, waiting for its device. }
  tGate104Pending = record
    Ticket : LongWord;       {< the slave's deferred confirmation }
    WriteId: LongInt;        {< the tag engine's write (negative: ours) }
    Until_ : QWord;          {< refused when the device has not answered by then }
    What   : AnsiString;
  end;

  tGate104 = record
    Cfg     : tGate104Cfg;
    Chn     : pChnVirt;
    S       : pIecSlaveStation;
    Points  : array of tGate104Point;
    Pending : array of tGate104Pending;
    NextId  : LongInt;
    Devs    : pPcccDevice;   {< the devices while Gate104Step runs the slave }
    DevCount: LongInt;
    Log     : tGate104Log;
    Commands, Confirmed, Refused, TimedOut: LongInt;
  end;

{ The monitoring type of a DF1 tag's items; 0: none (a string). }
function Gate104TagType(const T: tPcccTag): Byte;
{ The command type (without time tag) of a writable tag; 0 when it is not. }
function Gate104CommandType(const T: tPcccTag): Byte;
{ IOAs a device's tags take. }
function Gate104DevicePoints(const D: tPcccDevice): LongInt;
{ Points of the slave's table a device needs (monitoring and command). }
function Gate104TablePoints(const D: tPcccDevice): LongInt;
{ The parameter string of the server: 'NAM=IEC104 ... NAM=TCP LISTEN=...'. }
function Gate104Line(const Cfg: tGate104Cfg): AnsiString;

{ Open the server (listening; a control centre may connect from now on).
  False with Err when the port cannot be taken. }
function Gate104Open(var N: tGate104; const Cfg: tGate104Cfg; Log: tGate104Log; out Err: AnsiString): Boolean;
{ The point table of Devs, IOAs from Bases[i]; again after a reload: the
  commands waiting are refused, the slave starts anew on the same
  connection and says so (end of initialisation, COI 1 + local change). }
procedure Gate104Build(var N: tGate104; const Devs: array of tPcccDevice; const Bases: array of LongInt;
  Reload: Boolean);
{ Tag Tag of device Dev changed: its points get the new values and
  quality, as spontaneous events. }
procedure Gate104Change(var N: tGate104; const Devs: array of tPcccDevice; Dev, Tag: LongInt);
{ Device Dev's state changed: the quality of its points. }
procedure Gate104Health(var N: tGate104; const Devs: array of tPcccDevice; Dev: LongInt);
{ A write finished (ChnPcccTags.TagTakeWrite): True when it was one of
  the server's commands (its ACT_CON has been queued, or it had timed out). }
function Gate104WriteDone(var N: tGate104; const W: tTagWrite): Boolean;
{ The same for a command to an IEC 101 device (IecTableTakeWrite). }
function Gate104IecWriteDone(var N: tGate104; const W: tIecTableWrite): Boolean;
{ Point P of IEC 101 device D changed (IecTableTakeChange): its point in
  the table (added when it is new) gets value and quality, as an event.
  '', or the reason a new point is refused (its IOA is another device's
  point's, the table is full ...): said once, the point is not served. }
function Gate104IecChange(var N: tGate104; D: pGateIecDevice; P: LongInt): AnsiString;
{ ASDUs the server holds for its control centres (its class queues). }
function Gate104Queued(const N: tGate104): LongInt;
{ Serve the control centre: requests, commands to the devices, commands
  that waited too long. The ms the program may wait (ChnWaitAny). }
function Gate104Step(var N: tGate104; var Devs: array of tPcccDevice): LongInt;
{ Refuse what waits and close the server. }
procedure Gate104Close(var N: tGate104);

implementation

uses
  SysUtils, ChnPccc, ChnWait, ChnIec104;

function Gate104TagType(const T: tPcccTag): Byte;
begin
  if T.Kind = pvString then
    Result := 0
  else if TagIsBit(T) then
    Result := M_SP_NA_1
  else if T.Kind = pvFloat then
    Result := M_ME_NC_1
  else if (T.Addr.FileType = pft_Long) or
     (not T.Addr.HasSub and (T.Addr.FileType in [pft_Bit, pft_Status, pft_Input, pft_Output, pft_Ascii])) then
    Result := M_BO_NA_1
  else
    Result := M_ME_NB_1;
end;

function Gate104CommandType(const T: tPcccTag): Byte;
begin
  Result := 0;
  if not T.Writable then
    Exit;
  case Gate104TagType(T) of
    M_SP_NA_1: Result := C_SC_NA_1;
    M_ME_NB_1: Result := C_SE_NB_1;
    M_ME_NC_1: Result := C_SE_NC_1;
    M_BO_NA_1: Result := C_BO_NA_1;
  end;
end;

{ The time-tagged (CP56) form of a monitoring or command type. }
function TimeTagged(Ti: Byte): Byte;
begin
  case Ti of
    M_SP_NA_1: Result := M_SP_TB_1;
    M_ME_NB_1: Result := M_ME_TE_1;
    M_ME_NC_1: Result := M_ME_TF_1;
    M_BO_NA_1: Result := M_BO_TB_1;
    C_SC_NA_1: Result := C_SC_TA_1;
    C_SE_NB_1: Result := C_SE_TB_1;
    C_SE_NC_1: Result := C_SE_TC_1;
    C_BO_NA_1: Result := C_BO_TA_1;
  else
    Result := Ti;
  end;
end;

function Gate104DevicePoints(const D: tPcccDevice): LongInt;
var
  I: LongInt;
begin
  Result := 0;
  for I := 0 to High(D.Tags) do
    if Gate104TagType(D.Tags[I]) <> 0 then
      Inc(Result, Length(D.Tags[I].Values));
end;

function Gate104TablePoints(const D: tPcccDevice): LongInt;
var
  I: LongInt;
begin
  Result := Gate104DevicePoints(D);
  for I := 0 to High(D.Tags) do
    if Gate104CommandType(D.Tags[I]) <> 0 then
      Inc(Result, 2);
end;

function Gate104Line(const Cfg: tGate104Cfg): AnsiString;
begin
  Result := Trim('NAM=IEC104 ' + Cfg.Params) + ' NAM=TCP LISTEN=' + Cfg.Listen;
end;

procedure Say(const N: tGate104; const S: AnsiString);
begin
  if Assigned(N.Log) then
    N.Log('iec104: ' + S);
end;

{ The quality bits of a tag's points. }
function PointQuality(const D: tPcccDevice; const T: tPcccTag): Byte;
begin
  case T.Quality of
    tqGood: Result := 0;
    tqBad:
      if D.State = tdDemoted then
        Result := Q_Invalid or Q_NotTopical
      else
        Result := Q_Invalid;
    tqRefused: Result := Q_Invalid;
  else
    Result := Q_Invalid or Q_NotTopical;      { not read yet }
  end;
end;

{ Item K of T as an object of type Ti (the IOA is the caller's). }
function PointObject(Ti: Byte; const T: tPcccTag; K: LongInt; Quality: Byte): tIecObject;
var
  V: Double;
begin
  Result := IecObject(0);
  Result.Quality := Quality;
  V := 0;
  if K <= High(T.Values) then
    V := T.Values[K];
  case Ti of
    M_SP_NA_1: Result.Int := Ord(V <> 0);
    M_ME_NC_1: Result.Number := V;
    M_BO_NA_1: Result.Bits := LongWord(LongInt(Round(V)));
  else
    Result.Int := Round(V);
  end;
end;

function OnCommand(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean; forward;

{ The IEC104 stack of Line, opened and listening; nil with Err. }
function OpenServer(const Line: AnsiString; out Err: AnsiString): pChnVirt;
begin
  Err := '';
  Result := ChnCollection^.ChNewInit(ChnIec104.cName);
  Result^.ChSetParam(Line);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    Err := Line + ': ' + Result^.ChErrorText;
    Dispose(Result, Done);
    Result := nil;
  end;
end;

function Gate104Open(var N: tGate104; const Cfg: tGate104Cfg; Log: tGate104Log; out Err: AnsiString): Boolean;
var
  E: ShortString;
begin
  Finalize(N);
  FillChar(N, SizeOf(N), 0);
  N.Cfg := Cfg;
  N.Log := Log;
  N.Chn := OpenServer(Gate104Line(Cfg), Err);
  if N.Chn = nil then
    Exit(False);
  New(N.S);
  if IecSlaveInit(N.S^, N.Chn, IecDefaultParams, Cfg.Ca, E) <> res_Ok then
  begin
    Err := E;
    Gate104Close(N);
    Exit(False);
  end;
  Result := True;
end;

procedure Gate104Build(var N: tGate104; const Devs: array of tPcccDevice; const Bases: array of LongInt;
  Reload: Boolean);
var
  D, T, K, P, Used, Cmds: LongInt;
  Ti, Cmd: Byte;
  O: tIecObject;
  E: ShortString;
  Pt: ^tGate104Point;
begin
  if N.S = nil then
    Exit;
  for P := 0 to High(N.Pending) do
    IecSlaveConfirm(N.S^, N.Pending[P].Ticket, False);
  N.Pending := nil;
  N.Points := nil;
  if Reload then
    IecSlaveInit(N.S^, N.Chn, IecDefaultParams, N.Cfg.Ca, E);
  N.S^.OnCommand := @OnCommand;
  N.S^.Data := @N;
  { the table at its size at once: grown one point at a time, it moved on
    every point and left the heap full of holes }
  K := 0;
  Cmds := 0;
  for D := 0 to High(Devs) do
    for T := 0 to High(Devs[D].Tags) do
      if Gate104TagType(Devs[D].Tags[T]) <> 0 then
      begin
        Inc(K, Length(Devs[D].Tags[T].Values));
        if Gate104CommandType(Devs[D].Tags[T]) <> 0 then
          Inc(Cmds, 2 * Length(Devs[D].Tags[T].Values));
      end;
  SetLength(N.Points, K);
  IecSlaveReservePoints(N.S^, K + Cmds);
  Used := 0;
  for D := 0 to High(Devs) do
  begin
    P := Bases[D];
    for T := 0 to High(Devs[D].Tags) do
    begin
      Ti := Gate104TagType(Devs[D].Tags[T]);
      if Ti = 0 then
        Continue;
      Cmd := Gate104CommandType(Devs[D].Tags[T]);
      for K := 0 to High(Devs[D].Tags[T].Values) do
      begin
        Pt := @N.Points[Used];
        Inc(Used);
        with Pt^ do
        begin
          Ioa := P;
          Dev := D;
          Tag := T;
          Item := K;
          SentQ := PointQuality(Devs[D], Devs[D].Tags[T]);
          Sent := 0;
          if K <= High(Devs[D].Tags[T].Values) then
            Sent := Devs[D].Tags[T].Values[K];
        end;
        Pt^.Ti := Ti;
        Pt^.Cmd := Cmd;
        Pt^.CmdIoa := P;
        Pt^.Owner := Devs[D].Name + ' ' + Devs[D].Tags[T].Name;
        O := PointObject(Ti, Devs[D].Tags[T], K, Pt^.SentQ);
        O.Ioa := P;
        if (IecSlaveAddPoint(N.S^, Ti, O, 0, E) <> res_Ok) or
           (IecSlaveEventType(N.S^, P, TimeTagged(Ti), E) <> res_Ok) then
          Say(N, Devs[D].Name + ' ' + Devs[D].Tags[T].Name + ': ' + E);
        if Cmd <> 0 then
        begin
          IecSlaveAddPoint(N.S^, Cmd, IecObject(P), 0, E);
          IecSlaveAddPoint(N.S^, TimeTagged(Cmd), IecObject(P), 0, E);
        end;
        Inc(P);
      end;
    end;
  end;
  if Reload then
    IecSlaveEndOfInit(N.S^, Coi_ManualReset or Coi_LocalChange)
  else
    IecSlaveEndOfInit(N.S^, Coi_PowerOn);
end;

{ Bring point P up to date with its tag (a spontaneous event when its
  value or quality changed). }
procedure Refresh(var N: tGate104; const Devs: array of tPcccDevice; P: LongInt);
var
  Pt: ^tGate104Point;
  T: ^tPcccTag;
  Q: Byte;
  V: Double;
  O: tIecObject;
  E: ShortString;
begin
  Pt := @N.Points[P];
  T := @Devs[Pt^.Dev].Tags[Pt^.Tag];
  Q := PointQuality(Devs[Pt^.Dev], T^);
  V := 0;
  if Pt^.Item <= High(T^.Values) then
    V := T^.Values[Pt^.Item];
  if (V = Pt^.Sent) and (Q = Pt^.SentQ) then
    Exit;
  Pt^.Sent := V;
  Pt^.SentQ := Q;
  O := PointObject(Pt^.Ti, T^, Pt^.Item, Q);
  if IecSlaveUpdate(N.S^, Pt^.Ioa, O, True, E) <> res_Ok then
    Say(N, 'IOA ' + IntToStr(Pt^.Ioa) + ': ' + E);
end;

{ Refresh the points of device Dev's tag Tag (every tag: -1). }
procedure RefreshTags(var N: tGate104; const Devs: array of tPcccDevice; Dev, Tag: LongInt);
var
  P: LongInt;
begin
  if N.S = nil then
    Exit;
  for P := 0 to High(N.Points) do
    if (N.Points[P].Dev = Dev) and ((Tag < 0) or (N.Points[P].Tag = Tag)) then
      Refresh(N, Devs, P);
end;

procedure Gate104Change(var N: tGate104; const Devs: array of tPcccDevice; Dev, Tag: LongInt);
begin
  RefreshTags(N, Devs, Dev, Tag);
end;

procedure Gate104Health(var N: tGate104; const Devs: array of tPcccDevice; Dev: LongInt);
begin
  RefreshTags(N, Devs, Dev, -1);
end;

{ The value a command carries, as the tag engine writes it. }
function CommandValue(const H: tIecAsdu; const O: tIecObject): Double;
begin
  case IecTypeKind(H.Ti) of
    ikSetFloat, ikSetNormal: Result := O.Number;
    ikBitsCmd: Result := LongInt(O.Bits);
  else
    Result := O.Int;
  end;
end;

{ Remember a command passed south; its ACT_CON waits for the device. }
procedure AddPending(var N: tGate104; Ticket: LongWord; const What: AnsiString);
var
  K: LongInt;
begin
  K := Length(N.Pending);
  SetLength(N.Pending, K + 1);
  N.Pending[K].Ticket := Ticket;
  N.Pending[K].WriteId := N.NextId;
  N.Pending[K].Until_ := ChMsTick + QWord(N.Cfg.CommandMs);
  N.Pending[K].What := What;
end;

{ A command to IEC 101 point P: the same command to its RTU - a select
  as a select, the qualifier (QU, QL) as it came - its ACT_CON when the
  RTU's came. }
function PassCommand(var N: tGate104; P: LongInt; const H: tIecAsdu; const O: tIecObject): Boolean;
var
  Ticket: LongWord;
  What, Err: AnsiString;
  Select: Boolean;
begin
  Select := O.Select and (IecTypeKind(H.Ti) <> ikBitsCmd);
  What := IecTypeName(H.Ti) + ' IOA ' + IntToStr(O.Ioa) + ' (' + N.Points[P].Iec^.Name + ' ' +
    GateIecPointName(N.Points[P].Iec, N.Points[P].IecPoint) + ' := ' + FloatToStr(CommandValue(H, O));
  if Select then
    What := What + ' select';
  if O.Qu <> 0 then
    What := What + ' qualifier ' + IntToStr(O.Qu);
  What := What + ')';
  Inc(N.Commands);
  Result := False;
  Ticket := IecSlaveDefer(N.S^);
  if Ticket = 0 then
  begin
    Inc(N.Refused);
    Say(N, What + ': refused, ' + IntToStr(IecSlaveMaxDeferred) + ' commands wait already');
    Exit;
  end;
  Dec(N.NextId);
  if not GateIecCommand(N.Points[P].Iec, N.Points[P].IecPoint, CommandValue(H, O), Select, O.Qu, N.NextId,
    Err) then
  begin
    Inc(N.Refused);
    Say(N, What + ': refused, ' + Err);
    Exit;
  end;
  AddPending(N, Ticket, What);
  Result := True;
end;

{ The slave hands over a command to a command point (an IOA of a
  writable tag, of its type): a select is confirmed at once, an execute
  goes to the PLC and its ACT_CON waits for the PLC. }
function OnCommand(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
var
  N: ^tGate104;
  P, K: LongInt;
  Dev: pPcccDevice;
  Ticket: LongWord;
  E: ShortString;
  What: AnsiString;
begin
  N := Data;
  Result := False;
  P := -1;
  for K := 0 to High(N^.Points) do
    if (N^.Points[K].CmdIoa = O.Ioa) and (N^.Points[K].Cmd <> 0) then
      P := K;
  if (P >= 0) and (N^.Points[P].Iec <> nil) then
    Exit(PassCommand(N^, P, H, O));
  if (P < 0) or (N^.Points[P].Dev >= N^.DevCount) then
  begin
    Say(N^, IecTypeName(H.Ti) + ' IOA ' + IntToStr(O.Ioa) + ': refused, no device for it now');
    Exit;
  end;
  Dev := N^.Devs;
  Inc(Dev, N^.Points[P].Dev);
  What := IecTypeName(H.Ti) + ' IOA ' + IntToStr(O.Ioa) + ' (' + Dev^.Name + ' ' +
    Dev^.Tags[N^.Points[P].Tag].Name + ' := ' + FloatToStr(CommandValue(H, O)) + ')';
  Inc(N^.Commands);
  if O.Select then
  begin
    Say(N^, What + ': selected');
    Exit(True);
  end;
  Ticket := IecSlaveDefer(N^.S^);
  if Ticket = 0 then
  begin
    Inc(N^.Refused);
    Say(N^, What + ': refused, ' + IntToStr(IecSlaveMaxDeferred) + ' commands wait already');
    Exit;
  end;
  Dec(N^.NextId);
  if not TagDeviceWrite(Dev^, N^.Points[P].Tag, CommandValue(H, O), N^.NextId, E) then
  begin
    Inc(N^.Refused);
    Say(N^, What + ': refused, ' + E);
    Exit;                                     { negative ACT_CON at once }
  end;
  AddPending(N^, Ticket, What);
  Result := True;
end;

procedure DropPending(var N: tGate104; K: LongInt);
begin
  Delete(N.Pending, K, 1);
end;

{ The outcome of write Id from the device below: True when it was ours. }
function WriteDone(var N: tGate104; Id: LongInt; Res: tChResult; const Err, Who: AnsiString): Boolean;
var
  K: LongInt;
begin
  Result := Id < 0;
  if not Result or (N.S = nil) then
    Exit;
  for K := 0 to High(N.Pending) do
    if N.Pending[K].WriteId = Id then
    begin
      IecSlaveConfirm(N.S^, N.Pending[K].Ticket, Res = res_Ok);
      if Res = res_Ok then
      begin
        Inc(N.Confirmed);
        Say(N, N.Pending[K].What + ': confirmed by the ' + Who);
      end
      else
      begin
        Inc(N.Refused);
        Say(N, N.Pending[K].What + ': ' + Err);
      end;
      DropPending(N, K);
      Exit;
    end;
end;

function Gate104WriteDone(var N: tGate104; const W: tTagWrite): Boolean;
begin
  Result := WriteDone(N, W.Id, W.Res, W.Err, 'PLC');
end;

function Gate104IecWriteDone(var N: tGate104; const W: tIecTableWrite): Boolean;
begin
  Result := WriteDone(N, W.Id, W.Res, W.Err, 'RTU');
end;

{ The point served at IOA Ioa (a monitoring point), -1 when none. }
function ServedAt(const N: tGate104; Ioa: LongWord): LongInt;
begin
  for Result := 0 to High(N.Points) do
    if (N.Points[Result].Ioa = Ioa) and (N.Points[Result].Ti <> 0) then
      Exit;
  Result := -1;
end;

{ The table's point K of IEC 101 point P of D; added when new. Refused
  (Ti 0, not tried again) with Err when it cannot be: its IOA is another
  point's - never overwritten - or the table does not take it. }
function IecPointOf(var N: tGate104; D: pGateIecDevice; P: LongInt; out Err: AnsiString): LongInt;
var
  TP: ^tIecTablePoint;
  Ioa: LongWord;
  Cmd: Byte;
  E: ShortString;
  Other: LongInt;
begin
  Err := '';
  for Result := 0 to High(N.Points) do
    if (N.Points[Result].Iec = D) and (N.Points[Result].IecPoint = P) then
      Exit;
  TP := @D^.T.Points[P];
  Ioa := GateIecNorthIoa(D, P);
  Other := ServedAt(N, Ioa);
  Result := Length(N.Points);
  SetLength(N.Points, Result + 1);
  N.Points[Result].Iec := D;
  N.Points[Result].IecPoint := P;
  N.Points[Result].Ioa := Ioa;
  N.Points[Result].Owner := D^.Name + ' ' + GateIecPointName(D, P);
  if Other >= 0 then
    E := 'IEC 104 IOA ' + IntToStr(Ioa) + ' (ioa ' + IntToStr(D^.Cfg.IoaOffset) + ' + ' +
      IntToStr(TP^.Ioa) + ') is ' + N.Points[Other].Owner + '''s'
  else if IecSlaveAddPoint(N.S^, TP^.Ti, IecObject(Ioa), 0, E) = res_Ok then
    N.Points[Result].Ti := TP^.Ti;
  if N.Points[Result].Ti = 0 then          { not again }
  begin
    Err := N.Points[Result].Owner + ': not served: ' + E;
    Exit;
  end;
  if not TP^.Writable then
    Exit;
  Cmd := TP^.CmdTi;
  if Cmd = 0 then
    Cmd := IecCommandType(TP^.Ti);
  N.Points[Result].CmdIoa := D^.Cfg.IoaOffset + TP^.CmdIoa;
  if (Cmd = 0) or (IecSlaveAddPoint(N.S^, Cmd, IecObject(N.Points[Result].CmdIoa), 0, E) <> res_Ok) then
  begin
    Say(N, D^.Name + ' ' + GateIecPointName(D, P) + ': no commands: ' + E);
    Exit;
  end;
  N.Points[Result].Cmd := Cmd;
  if Cmd in [C_SC_NA_1..C_BO_NA_1] then
    IecSlaveAddPoint(N.S^, Cmd + (C_SC_TA_1 - C_SC_NA_1), IecObject(N.Points[Result].CmdIoa), 0, E);
end;

function Gate104IecChange(var N: tGate104; D: pGateIecDevice; P: LongInt): AnsiString;
var
  K: LongInt;
  TP: ^tIecTablePoint;
  O: tIecObject;
  E: ShortString;
begin
  Result := '';
  if (N.S = nil) or not IecIsMonitor(D^.T.Points[P].Ti) or (D^.T.Points[P].Ti = M_EI_NA_1) then
    Exit;
  K := IecPointOf(N, D, P, Result);
  if N.Points[K].Ti = 0 then
    Exit;
  TP := @D^.T.Points[P];
  if (TP^.Ti <> N.Points[K].Ti) and (TP^.Ti <> N.Points[K].EvTi) then
  begin
    { the same information with a time tag: the events take it }
    if IecSlaveEventType(N.S^, N.Points[K].Ioa, TP^.Ti, E) <> res_Ok then
    begin
      Say(N, D^.Name + ' ' + GateIecPointName(D, P) + ': ' + E);
      Exit;
    end;
    N.Points[K].EvTi := TP^.Ti;
  end;
  O := IecObject(N.Points[K].Ioa);
  case IecTypeKind(TP^.Ti) of
    ikNormal, ikFloat: O.Number := TP^.Value;
    ikBits, ikPacked, ikStartEvents, ikOutputCircuit: O.Bits := LongWord(Round(TP^.Value));
  else
    O.Int := Round(TP^.Value);
  end;
  O.Quality := TP^.Quality;
  if TP^.Bad or not TP^.Known then
    O.Quality := O.Quality or Q_Invalid;
  { the RTU's time tag as it came (a CP24 one completed with the hour and
    date, ChnIecPointTable); a change without one takes the gateway's clock }
  O.Time := TP^.Tag;
  if (TP^.Tagged and (IecSlaveUpdateAt(N.S^, N.Points[K].Ioa, O, True, E) <> res_Ok)) or
     (not TP^.Tagged and (IecSlaveUpdate(N.S^, N.Points[K].Ioa, O, True, E) <> res_Ok)) then
    Say(N, 'IOA ' + IntToStr(N.Points[K].Ioa) + ': ' + E);
end;

function Gate104Queued(const N: tGate104): LongInt;
begin
  Result := 0;
  if N.S <> nil then
    Result := N.S^.Class1.Count + N.S^.Class2.Count;
end;

function Gate104Step(var N: tGate104; var Devs: array of tPcccDevice): LongInt;
var
  K, Frames: LongInt;
  Now_: QWord;
begin
  Result := 1000;
  if N.S = nil then
    Exit;
  if Length(Devs) > 0 then
    N.Devs := @Devs[0]
  else
    N.Devs := nil;
  N.DevCount := Length(Devs);
  Frames := 0;
  while (Frames < 32) and IecSlaveStep(N.S^) do
    Inc(Frames);
  Now_ := ChMsTick;
  K := 0;
  while K <= High(N.Pending) do
    if Now_ >= N.Pending[K].Until_ then
    begin
      Inc(N.TimedOut);
      Say(N, N.Pending[K].What + ': no confirmation from the PLC in ' + IntToStr(N.Cfg.CommandMs) + ' ms');
      IecSlaveConfirm(N.S^, N.Pending[K].Ticket, False);
      DropPending(N, K);
    end
    else
      Inc(K);
  { what the requests and commands queued goes out now }
  if IecSlaveStep(N.S^) then
    Frames := 32;
  N.DevCount := 0;
  if Frames >= 32 then
    Result := 0
  else
    Result := IecSlaveWaitMs(N.S^);
  for K := 0 to High(N.Pending) do
    if ChnWaitLeft(N.Pending[K].Until_) < Result then
      Result := ChnWaitLeft(N.Pending[K].Until_);
end;

procedure Gate104Close(var N: tGate104);
var
  K: LongInt;
begin
  if N.S <> nil then
  begin
    for K := 0 to High(N.Pending) do
      IecSlaveConfirm(N.S^, N.Pending[K].Ticket, False);
    Dispose(N.S);
    N.S := nil;
  end;
  N.Pending := nil;
  N.Points := nil;
  if N.Chn <> nil then
    Dispose(N.Chn, Done);
  N.Chn := nil;
end;

end.
