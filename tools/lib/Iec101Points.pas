{ Iec101Points - the point table of examples/iec101slave as a text file,
  one point per line:

    IOA TYPE VALUE [QUALITY] [GROUP=N]
                                  e.g.  100 M_ME_NB_1 -1
                                        104 M_SP_NA_1 1 GROUP=2
                                        500 M_BO_NA_1 0xAAAA
                                        700 M_ME_TF_1 12.5 IV+NT

  TYPE is the standard name of a monitoring type (1..21, 30..40) or of a
  command type (45..51, 58..64: a point the master may command). VALUE as
  the type's kind takes it (ChnIec101Asdu.tIecKind): 0/1 (also on/off,
  true/false) for single points and single commands, 0..3 for double
  points and double or step commands, -64..63 for a step position (a
  trailing "t" marks it transient: 5t), an unsigned 32-bit number
  (decimal, 0x or $ hex) for bitstrings, packed points and protection
  start and output events, the fraction -1 <= x < 1 for normalized values,
  -32768..32767 for scaled values, a number for short floats, a 32-bit
  signed counter for integrated totals, the event state 0..3 for protection
  events. QUALITY is the quality octet as a number, or names joined by "+"
  (IV NT SB BL OV EI; CY CA for counters). GROUP=N puts the point into
  interrogation group N, 1..16 (integrated totals: counter group 1..4):
  a group interrogation (QOI 20+N, QCC RQT N) answers with the points of
  its group; every point answers the station interrogation (without
  GROUP=, only that). A time-tagged type takes the
  time the point is loaded (the time of the change). "#" starts a comment;
  blank lines are skipped. A tool unit, not part of the library. }
unit Iec101Points;

{$MODE OBJFPC}{$H-}

interface

uses
  ChnIec101Asdu, ChnIec101Slave;

{ The VALUE field for type Ti into O; False when it does not parse or is
  outside the type's range. }
function IecParseValue(Ti: Byte; const Tok: AnsiString; var O: tIecObject): Boolean;
{ The QUALITY field: a number 0..255 (decimal or hex) or names joined by "+". }
function IecParseQuality(const Tok: AnsiString; out Q: Byte): Boolean;
{ One line of the file into the table: True when it was a point, a blank
  line or a comment; False with Err 'what is wrong (TOKEN)'. }
function IecPointLine(var S: tIecSlaveStation; const Line: AnsiString; out Err: AnsiString): Boolean;
{ Every line of Text (a file's content) into the table; False with Err
  'NAME line N: what is wrong (TOKEN)' at the first bad line. }
function IecLoadPoints(var S: tIecSlaveStation; const Name, Text: AnsiString; out Err: AnsiString): Boolean;

implementation

uses
  SysUtils, Classes, uString;

function IecParseBits(const Tok: AnsiString; out V: LongWord): Boolean;
var
  T: AnsiString;
  I: Integer;
  Q: QWord;
  Hex: Boolean;
begin
  Result := False;
  T := Tok;
  Hex := False;
  if (Length(T) > 2) and (T[1] = '0') and (T[2] in ['x', 'X']) then
  begin
    Delete(T, 1, 2);
    Hex := True;
  end
  else if (Length(T) > 1) and (T[1] = '$') then
  begin
    Delete(T, 1, 1);
    Hex := True;
  end;
  if (T = '') or (Length(T) > 10) then
    Exit;
  for I := 1 to Length(T) do
    if (HexDigit(T[I]) < 0) or (not Hex and (HexDigit(T[I]) > 9)) then
      Exit;
  if Hex then
    T := '$' + T;
  if not TryStrToQWord(T, Q) or (Q > High(LongWord)) then
    Exit;
  V := Q;
  Result := True;
end;

function IntIn(const Tok: AnsiString; Min, Max: LongInt; out V: LongInt): Boolean;
begin
  V := 0;
  Result := (Length(Tok) < 250) and StrToNum(Tok, Min, Max, V);
end;

function IecParseValue(Ti: Byte; const Tok: AnsiString; var O: tIecObject): Boolean;
var
  U: AnsiString;
  V: LongInt;
  D: Double;
  B: LongWord;
begin
  U := UpperCase(Tok);
  D := 0;
  case IecTypeKind(Ti) of
    ikSingle, ikSingleCmd:
      begin
        Result := True;
        if (U = '1') or (U = 'ON') or (U = 'TRUE') then
          O.Int := 1
        else if (U = '0') or (U = 'OFF') or (U = 'FALSE') then
          O.Int := 0
        else
          Result := False;
      end;
    ikDouble, ikDoubleCmd, ikStepCmd, ikProtection:
      begin
        Result := IntIn(Tok, 0, 3, V);
        O.Int := V;
      end;
    ikStep:
      begin
        O.Transient := (U <> '') and (U[Length(U)] = 'T');
        if O.Transient then
          SetLength(U, Length(U) - 1);
        Result := IntIn(U, -64, 63, V);
        O.Int := V;
      end;
    ikBits, ikBitsCmd, ikPacked, ikStartEvents, ikOutputCircuit:
      begin
        Result := IecParseBits(Tok, B);
        O.Bits := B;
      end;
    ikScaled, ikSetScaled:
      begin
        Result := IntIn(Tok, -32768, 32767, V);
        O.Int := V;
      end;
    ikCounter:
      begin
        Result := IntIn(Tok, Low(LongInt), High(LongInt), V);
        O.Int := V;
      end;
    ikNormal, ikSetNormal:
      begin
        Result := (Length(Tok) < 250) and StrToReal(Tok, -1, 1, D) and (D < 1);
        O.Number := D;
      end;
    ikFloat, ikSetFloat:
      begin
        Result := (Length(Tok) < 250) and StrToReal(Tok, -3.4e38, 3.4e38, D);
        O.Number := D;
      end;
  else
    Result := False;
  end;
end;

function IecParseQuality(const Tok: AnsiString; out Q: Byte): Boolean;
const
  Names: array[0..7] of string[2] = ('IV', 'NT', 'SB', 'BL', 'OV', 'EI', 'CY', 'CA');
  Bits: array[0..7] of Byte = (Q_Invalid, Q_NotTopical, Q_Substituted, Q_Blocked,
    Q_Overflow, Q_ElapsedInv, Q_Substituted, Q_NotTopical);
var
  V: LongWord;
  L: TStringList;
  I, J: Integer;
  Found: Boolean;
begin
  Q := 0;
  if IecParseBits(Tok, V) then
  begin
    Result := V <= 255;
    if Result then
      Q := V;
    Exit;
  end;
  Result := False;
  L := TStringList.Create;
  try
    L.Delimiter := '+';
    L.StrictDelimiter := True;
    L.DelimitedText := UpperCase(Tok);
    for I := 0 to L.Count - 1 do
    begin
      Found := False;
      for J := 0 to High(Names) do
        if L[I] = Names[J] then
        begin
          Q := Q or Bits[J];
          Found := True;
        end;
      if not Found then
        Exit;
    end;
    Result := L.Count > 0;
  finally
    L.Free;
  end;
end;

function Fail(out Err: AnsiString; const Msg: AnsiString): Boolean;
begin
  Err := Msg;
  Result := False;
end;

{ The optional fields after VALUE: QUALITY and GROUP=N, in any order,
  each at most once. }
function OptionalFields(F: TStringList; var O: tIecObject; out Group: Byte;
  out Err: AnsiString): Boolean;
var
  I: Integer;
  V: LongInt;
  Q: Byte;
  HasQ, HasG: Boolean;
begin
  Result := False;
  Group := 0;
  HasQ := False;
  HasG := False;
  for I := 3 to F.Count - 1 do
    if UpperCase(Copy(F[I], 1, 6)) = 'GROUP=' then
    begin
      if HasG then
        Exit(Fail(Err, 'GROUP= twice (' + F[I] + ')'));
      if not IntIn(Copy(F[I], 7, MaxInt), 1, 16, V) then
        Exit(Fail(Err, 'GROUP= takes an interrogation group 1..16 (' + F[I] + ')'));
      Group := V;
      HasG := True;
    end
    else if HasQ then
      Exit(Fail(Err, 'too many fields (' + F[I] + ')'))
    else if not IecParseQuality(F[I], Q) then
      Exit(Fail(Err, 'quality: a number 0..255 or IV+NT+SB+BL+OV+EI (' + F[I] + ')'))
    else
    begin
      O.Quality := Q;
      HasQ := True;
    end;
  Result := True;
end;

function IecPointLine(var S: tIecSlaveStation; const Line: AnsiString; out Err: AnsiString): Boolean;
var
  F: TStringList;
  T: AnsiString;
  P: Integer;
  Ioa: LongInt;
  Ti, Group: Byte;
  O: tIecObject;
  E: ShortString;
begin
  Err := '';
  T := Line;
  P := Pos('#', T);
  if P > 0 then
    SetLength(T, P - 1);
  F := TStringList.Create;
  try
    F.Delimiter := ' ';
    F.StrictDelimiter := False;
    F.DelimitedText := StringReplace(Trim(T), #9, ' ', [rfReplaceAll]);
    if F.Count = 0 then
      Exit(True);
    Result := False;
    if not IntIn(F[0], 0, $FFFFFF, Ioa) then
      Err := 'IOA 0..' + IntToStr(IecMaxIoa(S.Params)) + ' expected (' + F[0] + ')'
    else if F.Count < 3 then
      Err := 'IOA TYPE VALUE [QUALITY] [GROUP=N] expected (' + Trim(T) + ')'
    else if F.Count > 5 then
      Err := 'too many fields (' + F[5] + ')'
    else
    begin
      Ti := IecTypeByName(F[1]);
      O := IecObject(Ioa);
      if Ti = 0 then
        Err := 'unknown type (' + F[1] + ')'
      else if not IecParseValue(Ti, F[2], O) then
        Err := 'no value for ' + IecTypeName(Ti) + ' (' + F[2] + ')'
      else if OptionalFields(F, O, Group, Err) then
        case IecSlaveAddPoint(S, Ti, O, Group, E) of
          0: Exit(True);
        else
          Err := E + ' (' + Trim(T) + ')';
        end;
    end;
  finally
    F.Free;
  end;
end;

function IecLoadPoints(var S: tIecSlaveStation; const Name, Text: AnsiString; out Err: AnsiString): Boolean;
var
  L: TStringList;
  I: Integer;
  E: AnsiString;
begin
  Err := '';
  L := TStringList.Create;
  try
    L.Text := Text;
    for I := 0 to L.Count - 1 do
      if not IecPointLine(S, L[I], E) then
      begin
        Err := Name + ' line ' + IntToStr(I + 1) + ': ' + E;
        Exit(False);
      end;
    Result := True;
  finally
    L.Free;
  end;
end;

end.
