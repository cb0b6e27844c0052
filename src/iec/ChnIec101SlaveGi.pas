{ ChnIec101SlaveGi - the IEC 60870-5-101 slave's interrogations: a
  station or group interrogation (C_IC_NA_1) and a counter interrogation
  (C_CI_NA_1) taken (ACT_CON, or refused), their answers built one ASDU
  at a time as the link asks for them (the points, then the parameters
  loaded), ACT_TERM after the last; a counter freeze or reset. }
unit ChnIec101SlaveGi;

{$I chn.inc}

interface

uses
  ChnIec101Asdu, ChnIec101SlaveTypes;

{ The next answer ASDU of the interrogation under way; False when none
  is left (then its ACT_TERM is in class 1). }
function GiNextAsdu(var S: tIecSlaveStation; var Out: tIecQueued): Boolean;
{ A C_IC_NA_1 or C_CI_NA_1 received (H, O decoded from Buf). }
procedure TakeInterrogation(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);

implementation

uses
  ChnTypes, ChnIec101SlaveQueue, ChnIec101SlavePoints;

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
    SetMeasuredValue(P^.Ti, O, P^.Par[Kpa]);
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
end.
