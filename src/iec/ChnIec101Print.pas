{ ChnIec101Print - the one way the IEC 101 tools (iec101master, iec101slave,
  chndecode --ft12, the FT 1.2 examples) show an information object: a JSON
  object on one line, or one readable line; and an ASDU as one line.

  JSON keys (docs/ChnIec101.md): type (standard name), ti, cot, negative,
  test, oa, ca, ioa, value, quality (the quality bits as a number, 0 where
  the type has none), time (only for time-tagged types: YYYY-MM-DDThh:mm:ss.mmm
  from a CP56Time2a, mm:ss.mmm from a CP24Time2a, no time zone). value:
  true/false for single points and single commands; the state 0..3 for
  double points, double and regulating step commands; the position for step
  positions plus "transient"; the unsigned 32-bit number for bitstrings,
  packed points and protection start/output events; the fraction for
  normalized values; the integer for scaled values; the number for short
  floats (null when NaN or infinite); the counter plus "seq" for integrated
  totals; the qualifier octet for interrogation, counter interrogation,
  reset process, parameter activation and end of initialisation (COI); the
  pattern or counter of test commands; the ms of a delay acquisition; null
  for read and clock synchronisation. Commands add "select", protection
  events "elapsed" (ms), parameters "qpm". A program of its own prints
  what it receives the same way with these routines. }
unit ChnIec101Print;

{$I chn.inc}

interface

uses
  ChnIec101Asdu;

{ The time tag as the JSON "time" shows it; '' for tkNone. }
function IecTimeText(const T: tIecTime; K: tIecTimeKind): AnsiString;
{ The JSON value of the object (after "value":), with its extra keys. }
function IecValueJson(Ti: Byte; const O: tIecObject): AnsiString;
{ The value in words: 'on', 'ON (2)', '-2', '0.5', '12 seq 3' ... }
function IecValueText(Ti: Byte; const O: tIecObject): AnsiString;
{ Quality bits in words: 'IV NT', '' when none. }
function IecQualityText(Ti: Byte; Quality: Byte): AnsiString;
{ One JSON object (no newline). }
function IecObjectJson(const H: tIecAsdu; const O: tIecObject): AnsiString;
{ 'M_ME_NB_1 SPONTANEOUS CA 1 IOA 110 = -2' (+ ' negative', ' test',
  ' OA n', quality words, time). }
function IecObjectText(const H: tIecAsdu; const O: tIecObject): AnsiString;
{ A whole ASDU on one line: the identifier, then 'IOA n = value' for each
  object; a malformed one gives 'bad ASDU: <what is wrong>: <octets in hex>'. }
function IecAsduText(const P: tIecParams; const Buf: array of Byte; Len: Word): AnsiString;

implementation

uses
  SysUtils, Math;

var
  Fmt: TFormatSettings;

{ A number for JSON: Digits significant digits (7 for a short float,
  the digits a Single has; 15 for a normalized fraction); null when NaN or
  infinite. }
function Num(X: Double; Digits: Integer = 15): AnsiString;
begin
  if IsNan(X) or IsInfinite(X) then
    Result := 'null'
  else
    Result := FloatToStrF(X, ffGeneral, Digits, 0, Fmt);
end;

function Bool(B: Boolean): AnsiString;
begin
  if B then
    Result := 'true'
  else
    Result := 'false';
end;

function IecTimeText(const T: tIecTime; K: tIecTimeKind): AnsiString;
begin
  case K of
    tkCP24: Result := Format('%.2d:%.2d.%.3d', [T.Minute, T.Msec div 1000, T.Msec mod 1000]);
    tkCP56: Result := Format('%.4d-%.2d-%.2dT%.2d:%.2d:%.2d.%.3d', [2000 + T.Year, T.Month, T.Day,
      T.Hour, T.Minute, T.Msec div 1000, T.Msec mod 1000]);
  else
    Result := '';
  end;
end;

function IecValueJson(Ti: Byte; const O: tIecObject): AnsiString;
var
  K: tIecKind;
begin
  K := IecTypeKind(Ti);
  case K of
    ikSingle, ikSingleCmd: Result := Bool(O.Int <> 0);
    ikDouble, ikDoubleCmd, ikStepCmd, ikScaled, ikSetScaled, ikParScaled, ikEndInit,
    ikQualifier, ikTest, ikTestTime, ikProtection:
      Result := IntToStr(O.Int);
    ikStep: Result := IntToStr(O.Int) + ',"transient":' + Bool(O.Transient);
    ikBits, ikBitsCmd, ikPacked, ikStartEvents, ikOutputCircuit: Result := IntToStr(O.Bits);
    ikNormal, ikSetNormal, ikParNormal: Result := Num(O.Number);
    ikFloat, ikSetFloat, ikParFloat: Result := Num(O.Number, 7);
    ikCounter: Result := IntToStr(O.Int) + ',"seq":' + IntToStr(O.Seq);
    ikDelay: Result := IntToStr(O.Elapsed);
  else
    Result := 'null';
  end;
  if K in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat] then
    Result := Result + ',"select":' + Bool(O.Select);
  if (K in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat]) and (O.Qu <> 0) then
    Result := Result + ',"qu":' + IntToStr(O.Qu);
  if K in [ikProtection, ikStartEvents, ikOutputCircuit] then
    Result := Result + ',"elapsed":' + IntToStr(O.Elapsed);
  if K in [ikParNormal, ikParScaled, ikParFloat] then
    Result := Result + ',"qpm":' + IntToStr(O.Qu);
end;

const
  DoubleNames: array[0..3] of string[13] = ('INTERMEDIATE', 'OFF', 'ON', 'INDETERMINATE');
  StepNames: array[0..3] of string[11] = ('NOT_ALLOWED', 'LOWER', 'HIGHER', 'NOT_ALLOWED');

function IecValueText(Ti: Byte; const O: tIecObject): AnsiString;
var
  K: tIecKind;
begin
  K := IecTypeKind(Ti);
  case K of
    ikSingle, ikSingleCmd:
      if O.Int <> 0 then Result := 'on' else Result := 'off';
    ikDouble, ikDoubleCmd: Result := DoubleNames[O.Int and 3] + ' (' + IntToStr(O.Int) + ')';
    ikStepCmd: Result := StepNames[O.Int and 3] + ' (' + IntToStr(O.Int) + ')';
    ikStep:
      begin
        Result := IntToStr(O.Int);
        if O.Transient then
          Result := Result + ' transient';
      end;
    ikBits, ikBitsCmd, ikPacked, ikStartEvents, ikOutputCircuit:
      Result := '0x' + IntToHex(O.Bits, 8);
    ikNormal, ikSetNormal, ikParNormal: Result := Num(O.Number);
    ikFloat, ikSetFloat, ikParFloat: Result := Num(O.Number, 7);
    ikCounter: Result := IntToStr(O.Int) + ' seq ' + IntToStr(O.Seq);
    ikProtection: Result := DoubleNames[O.Int and 3] + ' (' + IntToStr(O.Int) + ')';
    ikDelay: Result := IntToStr(O.Elapsed) + ' ms';
    ikTest, ikTestTime: Result := '0x' + IntToHex(O.Int, 4);
    ikScaled, ikSetScaled, ikParScaled, ikEndInit, ikQualifier: Result := IntToStr(O.Int);
  else
    Result := '';
  end;
  if K in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat] then
    if O.Select then Result := Result + ' select' else Result := Result + ' execute';
  { the qualifier (QU of a command, QL of a set point) when not 0 }
  if (K in [ikSingleCmd, ikDoubleCmd, ikStepCmd]) and (O.Qu <> 0) then
    Result := Result + ' QU ' + IntToStr(O.Qu)
  else if (K in [ikSetNormal, ikSetScaled, ikSetFloat]) and (O.Qu <> 0) then
    Result := Result + ' QL ' + IntToStr(O.Qu);
  if K in [ikProtection, ikStartEvents, ikOutputCircuit] then
    Result := Result + ' elapsed ' + IntToStr(O.Elapsed) + ' ms';
  if K in [ikParNormal, ikParScaled, ikParFloat] then
    Result := Result + ' QPM ' + IntToStr(O.Qu);
end;

function IecQualityText(Ti: Byte; Quality: Byte): AnsiString;

  procedure Add(Bit: Byte; const Name: AnsiString);
  begin
    if Quality and Bit <> 0 then
    begin
      if Result <> '' then
        Result := Result + ' ';
      Result := Result + Name;
    end;
  end;

begin
  Result := '';
  Add(Q_Invalid, 'IV');
  if IecTypeKind(Ti) = ikCounter then
  begin
    Add(Q_NotTopical, 'CA');
    Add(Q_Substituted, 'CY');
  end
  else
  begin
    Add(Q_NotTopical, 'NT');
    Add(Q_Substituted, 'SB');
    Add(Q_Blocked, 'BL');
    Add(Q_ElapsedInv, 'EI');
    Add(Q_Overflow, 'OV');
  end;
end;

function IecObjectJson(const H: tIecAsdu; const O: tIecObject): AnsiString;
var
  K: tIecTimeKind;
begin
  Result := Format('{"type":"%s","ti":%d,"cot":%d,"negative":%s,"test":%s,"oa":%d,"ca":%d,'
    + '"ioa":%d,"value":%s,"quality":%d', [IecTypeName(H.Ti), H.Ti, H.Cot, Bool(H.Negative),
    Bool(H.Test), H.Oa, H.Ca, O.Ioa, IecValueJson(H.Ti, O), O.Quality]);
  K := IecTypeTime(H.Ti);
  if K <> tkNone then
    Result := Result + ',"time":"' + IecTimeText(O.Time, K) + '"';
  Result := Result + '}';
end;

function HeadText(const H: tIecAsdu): AnsiString;
begin
  Result := IecTypeName(H.Ti) + ' ' + IecCotName(H.Cot);
  if H.Negative then
    Result := Result + ' negative';
  if H.Test then
    Result := Result + ' test';
  if H.Oa <> 0 then
    Result := Result + ' OA ' + IntToStr(H.Oa);
  Result := Result + ' CA ' + IntToStr(H.Ca);
end;

function ObjText(Ti: Byte; const O: tIecObject): AnsiString;
var
  V, Q: AnsiString;
begin
  Result := 'IOA ' + IntToStr(O.Ioa);
  V := IecValueText(Ti, O);
  if V <> '' then
    Result := Result + ' = ' + V;
  Q := IecQualityText(Ti, O.Quality);
  if Q <> '' then
    Result := Result + ' [' + Q + ']';
  if IecTypeTime(Ti) <> tkNone then
  begin
    Result := Result + ' ' + IecTimeText(O.Time, IecTypeTime(Ti));
    if O.Time.Invalid then
      Result := Result + ' (time IV)';
    if O.Time.Summer then
      Result := Result + ' SU';
  end;
end;

function IecObjectText(const H: tIecAsdu; const O: tIecObject): AnsiString;
begin
  Result := HeadText(H) + ' ' + ObjText(H.Ti, O);
end;

function Hex(const Buf: array of Byte; Len: Integer): AnsiString;
var
  I: Integer;
begin
  Result := '';
  for I := 0 to Min(Len, Length(Buf)) - 1 do
  begin
    if I > 0 then
      Result := Result + ' ';
    Result := Result + IntToHex(Buf[I], 2);
  end;
end;

function IecAsduText(const P: tIecParams; const Buf: array of Byte; Len: Word): AnsiString;
var
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
  I: Integer;
begin
  if IecDecodeHeader(P, Buf, Len, H, E) <> 0 then
    Exit('bad ASDU: ' + E + ': ' + Hex(Buf, Len));
  Result := HeadText(H) + ':';
  for I := 0 to H.Count - 1 do
  begin
    IecDecodeObject(P, H, Buf, I, O);
    if I > 0 then
      Result := Result + ',';
    Result := Result + ' ' + ObjText(H.Ti, O);
  end;
end;

initialization
  Fmt := DefaultFormatSettings;
  Fmt.DecimalSeparator := '.';
end.
