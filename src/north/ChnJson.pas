{ ChnJson - the little JSON a gateway writes and reads, without a JSON
  library: strings escaped as RFC 8259 says, numbers in the shortest form
  that keeps a single's precision (with a '.' whatever the locale), UTC
  time stamps in ISO 8601 with milliseconds, and the value of a command
  (a JSON number, true or false, alone or as the member "value" of an
  object). }
unit ChnJson;

{$I chn.inc}

interface

{ S as a JSON string, quotes included. }
function JsonString(const S: AnsiString): AnsiString;
{ V as a JSON number: a whole number without a fraction; else at most
  Digits significant digits (7 for a single, 15 for a double); null for
  NaN and infinities (JSON has no such numbers). }
function JsonNumber(V: Double; Digits: LongInt = 15): AnsiString;
{ '2026-12-04T10:00:00.123Z' for Ms, UTC milliseconds since 1970. }
function JsonTime(Ms: Int64): AnsiString;
{ The value of a command payload: a JSON number, true, false, or an
  object whose "value" is one of them. False with Err (what was found)
  for anything else. }
function JsonParseValue(const Payload: AnsiString; out V: Double; out Err: AnsiString): Boolean;

implementation

uses
  SysUtils, Math, DateUtils;

function JsonString(const S: AnsiString): AnsiString;
var
  I: LongInt;
  C: Char;
begin
  Result := '"';
  for I := 1 to Length(S) do
  begin
    C := S[I];
    case C of
      '"': Result := Result + '\"';
      '\': Result := Result + '\\';
      #8: Result := Result + '\b';
      #9: Result := Result + '\t';
      #10: Result := Result + '\n';
      #12: Result := Result + '\f';
      #13: Result := Result + '\r';
      #0..#7, #11, #14..#31: Result := Result + '\u' + IntToHex(Ord(C), 4);
    else
      Result := Result + C;
    end;
  end;
  Result := Result + '"';
end;

function JsonNumber(V: Double; Digits: LongInt): AnsiString;
var
  F: TFormatSettings;
begin
  if IsNan(V) or IsInfinite(V) then
    Exit('null');
  if (Frac(V) = 0) and (Abs(V) < 1e15) then
    Exit(IntToStr(Trunc(V)));
  F := DefaultFormatSettings;
  F.DecimalSeparator := '.';
  Result := FloatToStrF(V, ffGeneral, Digits, 0, F);
end;

function JsonTime(Ms: Int64): AnsiString;
var
  T: TDateTime;
begin
  T := UnixToDateTime(Ms div 1000) + (Ms mod 1000) / MSecsPerDay;
  Result := FormatDateTime('yyyy"-"mm"-"dd"T"hh":"nn":"ss"."zzz"Z"', T);
end;

function JsonParseValue(const Payload: AnsiString; out V: Double; out Err: AnsiString): Boolean;
var
  S: AnsiString;
  P, Code: LongInt;
begin
  V := 0;
  Err := '';
  S := Trim(Payload);
  if (S <> '') and (S[1] = '{') then
  begin
    { an object: its member "value" }
    P := Pos('"value"', S);
    if (P = 0) or (S[Length(S)] <> '}') then
    begin
      Err := 'an object without "value": ' + Payload;
      Exit(False);
    end;
    S := Copy(S, P + 7, MaxInt);
    S := Trim(Copy(S, 1, Length(S) - 1));
    if (S = '') or (S[1] <> ':') then
    begin
      Err := 'no ":" after "value": ' + Payload;
      Exit(False);
    end;
    S := Trim(Copy(S, 2, MaxInt));
  end;
  if S = 'true' then
    V := 1
  else if S = 'false' then
    V := 0
  else
  begin
    Val(S, V, Code);
    if (S = '') or (Code <> 0) or not (S[1] in ['-', '0'..'9']) or IsNan(V) or IsInfinite(V) then
    begin
      Err := 'not a number, true or false: ' + Payload;
      Exit(False);
    end;
  end;
  Result := True;
end;

end.
