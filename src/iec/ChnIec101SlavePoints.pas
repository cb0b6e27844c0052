{ ChnIec101SlavePoints - the IEC 60870-5-101 slave's point table: points
  added and checked (type, IOA, group, a value the type carries), found
  by IOA, given a time-tagged type for their events, updated by the
  program (a spontaneous change queued as a class 1 event, unless within
  the deadband of its threshold parameter); the station clock. }
unit ChnIec101SlavePoints;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIec101SlaveTypes;

{ Is Ti an integrated total (counter)? }
function IsCounter(Ti: Byte): Boolean;
{ Is Ti a command type (45..51, 58..64)? }
function IsCommand(Ti: Byte): Boolean;
{ The station clock (PC clock + ClockOffsetMs). }
function IecSlaveNow(const S: tIecSlaveStation): TDateTime;
{ The command point of type Ti at Ioa; -1 when none. }
function FindCommand(const S: tIecSlaveStation; Ioa: LongWord; Ti: Byte): LongInt;
{ The point at Ioa (its monitoring point when a command point shares it); -1 when none. }
function IecSlaveFind(const S: tIecSlaveStation; Ioa: LongWord): LongInt;
{ The public calls of ChnIec101Slave, which documents them. }
procedure IecSlaveReservePoints(var S: tIecSlaveStation; N: LongInt);
function IecSlaveAddPoint(var S: tIecSlaveStation; Ti: Byte; const Obj: tIecObject; Group: Byte;
  out Err: ShortString): tChResult;
function IecSlaveEventType(var S: tIecSlaveStation; Ioa: LongWord; Ti: Byte;
  out Err: ShortString): tChResult;
function IecSlaveUpdate(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
function IecSlaveUpdateAt(var S: tIecSlaveStation; Ioa: LongWord; const Obj: tIecObject;
  Spontaneous: Boolean; out Err: ShortString): tChResult;
{ The value of a measured value as its parameters count it. }
function MeasuredValue(Ti: Byte; const O: tIecObject): Double;
procedure SetMeasuredValue(Ti: Byte; var O: tIecObject; V: Double);
{ The parameter type (P_ME_NA/NB/NC_1) of a measured value type; 0 when none. }
function ParamType(Ti: Byte): Byte;

implementation

uses
  SysUtils, DateUtils, ChnIec101SlaveQueue, ChnIecMeasParams;

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

procedure IecSlaveReservePoints(var S: tIecSlaveStation; N: LongInt);
begin
  if N > IecSlaveMaxPoints then
    N := IecSlaveMaxPoints;
  if N > Length(S.Points) then
    SetLength(S.Points, N);
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
  if S.PointCount >= Length(S.Points) then
    IecSlaveReservePoints(S, Length(S.Points) + IecSlavePointStep);
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

{ The value of a measured value as its parameters count it: the fraction
  of a normalized value, the integer of a scaled one, the float. }
function MeasuredValue(Ti: Byte; const O: tIecObject): Double;
begin
  if IecTypeKind(Ti) = ikScaled then
    Result := O.Int
  else
    Result := O.Number;
end;

procedure SetMeasuredValue(Ti: Byte; var O: tIecObject; V: Double);
begin
  if IecTypeKind(Ti) = ikScaled then
    O.Int := Round(V)
  else
    O.Number := V;
end;

{ The new value O of point P through its smoothing filter, when a
  smoothing factor is in operation. }
procedure Smooth(var P: tIecPoint; var O: tIecObject);
begin
  if not P.ParOn or (P.ParSet and (1 shl Kpa_Smoothing) = 0) then
    Exit;
  if not P.HasFiltered then
    P.Filtered := MeasuredValue(P.Ti, P.Obj);
  P.HasFiltered := True;
  P.Filtered := IecParSmooth(P.Filtered, MeasuredValue(P.Ti, O),
    IecParWeight(P.Par[Kpa_Smoothing], IecTypeKind(P.Ti) = ikScaled));
  SetMeasuredValue(P.Ti, O, P.Filtered);
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
  operation, with the same quality and in the zone of the limits of the
  value reported last, is not reported (a deadband around that value). }
function InDeadband(const P: tIecPoint; const O: tIecObject; OldQuality: Byte): Boolean;
var
  V: Double;
begin
  V := MeasuredValue(P.Ti, O);
  Result := P.ParOn and (P.ParSet and (1 shl Kpa_Threshold) <> 0) and P.HasReported and
    (O.Quality = OldQuality) and (Abs(V - P.Reported) < P.Par[Kpa_Threshold]) and
    (IecParZone(P.ParSet, P.Par[Kpa_Low], P.Par[Kpa_High], V) =
     IecParZone(P.ParSet, P.Par[Kpa_Low], P.Par[Kpa_High], P.Reported));
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
  if ParamType(S.Points[I].Ti) <> 0 then
    Smooth(S.Points[I], O);
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

end.
