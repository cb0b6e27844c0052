{ ChnIec101SlaveParams - the IEC 60870-5-101 slave's parameters of
  measured values: loading (P_ME_NA_1..P_ME_NC_1: threshold, smoothing,
  low and high limit, per IOA, in operation or not) and activation
  (P_AC_NA_1, COT 6 / 8: one object's or every loaded parameter). The
  parameters in operation act on the point's value and spontaneous
  reports (ChnIec101SlavePoints, ChnIecMeasParams); an interrogation reports the
  parameters loaded after the points (ChnIec101SlaveGi). }
unit ChnIec101SlaveParams;

{$I chn.inc}

interface

uses
  ChnIec101Asdu, ChnIec101SlaveTypes;

{ A P_ME_NA_1..P_ME_NC_1 or P_AC_NA_1 received (H, O decoded from Buf). }
procedure TakeParameter(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);

implementation

uses
  ChnIec101SlaveQueue, ChnIec101SlavePoints, ChnIecMeasParams;

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
    begin
      S.Points[I].ParOn := H.Cot = Cot_Activation;
      S.Points[I].HasFiltered := False;  { a smoothing filter starts again }
    end;
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
    Ok := IecParValid(Kpa, MeasuredValue(S.Points[I].Ti, O), IecTypeKind(S.Points[I].Ti) = ikScaled);
    if Ok then
    begin
      S.Points[I].Par[Kpa] := MeasuredValue(S.Points[I].Ti, O);
      S.Points[I].ParSet := S.Points[I].ParSet or (1 shl Kpa);
      S.Points[I].ParOn := O.Qu and Qpm_NotInOperation = 0;
    end;
  end;
  if Ok then
  begin
    Inc(S.Parameters);
    S.Points[I].HasFiltered := False;    { a smoothing filter starts again }
  end;
  Answer(S, Buf, Len, ActOrDeact(H.Cot), not Ok);
end;
end.
