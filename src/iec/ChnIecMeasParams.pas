{ ChnIecMeasParams - what the parameters of a measured value do to a
  controlled station's reports of it. IEC 60870-5-101 (7.2.6.24, QPM)
  names four kinds - threshold value, smoothing factor (filter time
  constant), low and high limit for the transmission of measured values -
  loaded with P_ME_NA/NB/NC_1 and put in operation with P_AC_NA_1, and
  leaves what they do to the station. This library's choice:

  * threshold: a deadband - a spontaneous change closer than it to the
    value reported last is not reported;
  * smoothing factor: a first-order filter - each new value moves the
    station's value by the weight k of the difference, v := v + k (x - v);
    k is the parameter of a normalized or float value (0 < k <= 1), per
    cent for a scaled one (1..100); 1 (100 %) is no smoothing;
  * low and high limit: the value is in one of three zones, below the low
    limit, between (the limits included), above the high one; a change
    into another zone than that of the value reported last is reported
    whatever the threshold. A value is never held back by a limit.

  Pure functions on the values; ChnIec101Slave keeps the parameters per
  point and calls them. }
unit ChnIecMeasParams;

{$I chn.inc}

interface

uses
  ChnIec101Asdu;

{ Does the station take Value for kind Kpa (Scaled: of a scaled value)?
  A threshold >= 0, a smoothing factor as above; limits any value. }
function IecParValid(Kpa: Byte; Value: Double; Scaled: Boolean): Boolean;
{ The weight k of a smoothing factor as loaded. }
function IecParWeight(Value: Double; Scaled: Boolean): Double;
{ The filter's next value: V + K (X - V). }
function IecParSmooth(V, X, K: Double): Double;
{ The zone of V between the limits that are set (bit KPA of Set_, as a
  point's ParSet): -1 below Low, +1 above High, 0 else. The values come
  by value: a point's may lie unaligned in its packed record (ARM). }
function IecParZone(Set_: Byte; Low, High, V: Double): ShortInt;

implementation

function IecParWeight(Value: Double; Scaled: Boolean): Double;
begin
  if Scaled then
    Result := Value / 100
  else
    Result := Value;
end;

function IecParValid(Kpa: Byte; Value: Double; Scaled: Boolean): Boolean;
var
  K: Double;
begin
  case Kpa of
    Kpa_Threshold: Result := Value >= 0;
    Kpa_Smoothing:
      begin
        K := IecParWeight(Value, Scaled);
        Result := (K > 0) and (K <= 1);
      end;
    Kpa_Low, Kpa_High: Result := True;
  else
    Result := False;
  end;
end;

function IecParSmooth(V, X, K: Double): Double;
begin
  Result := V + K * (X - V);
end;

function IecParZone(Set_: Byte; Low, High, V: Double): ShortInt;
begin
  Result := 0;
  if (Set_ and (1 shl Kpa_Low) <> 0) and (V < Low) then
    Result := -1
  else if (Set_ and (1 shl Kpa_High) <> 0) and (V > High) then
    Result := 1;
end;

end.
