{ uString - the string helpers the Chn library needs.

  The SofCon examples put "uString" in every uses clause; this unit keeps
  that name. It holds only what the library itself uses: splitting a
  parameter string into tokens, upper-casing and strict number parsing.
  All strings are ShortStrings so callers in any compiler mode can use it. }
unit uString;

{$I chn.inc}

interface

{ Upper-case ASCII letters only (parameter keys and values are ASCII). }
function UpStr(const S: ShortString): ShortString;

{ Next whitespace-separated token of S starting at Pos (1-based). Skips
  spaces, tabs and line breaks; returns False at the end. Pos is advanced
  past the token; TokStart receives where the token began.
  Pos and Tok are var parameters, so each routine taking a number or a text
  by reference comes in the sizes a caller's plain "Integer" and "string"
  have in any compiler mode (SmallInt or LongInt, ShortString or
  AnsiString); see docs/LAYERS.md, "Types in public signatures". }
function NextToken(const S: ShortString; var Pos: LongInt; var Tok: ShortString): Boolean; overload;
function NextToken(const S: ShortString; var Pos: SmallInt; var Tok: ShortString): Boolean; overload;
function NextToken(const S: ShortString; var Pos: LongInt; var Tok: AnsiString): Boolean; overload;
function NextToken(const S: ShortString; var Pos: SmallInt; var Tok: AnsiString): Boolean; overload;
function NextTokenAt(const S: ShortString; var Pos: LongInt; var Tok: ShortString;
  var TokStart: LongInt): Boolean; overload;
function NextTokenAt(const S: ShortString; var Pos: SmallInt; var Tok: ShortString;
  var TokStart: SmallInt): Boolean; overload;
function NextTokenAt(const S: ShortString; var Pos: LongInt; var Tok: AnsiString;
  var TokStart: LongInt): Boolean; overload;
function NextTokenAt(const S: ShortString; var Pos: SmallInt; var Tok: AnsiString;
  var TokStart: SmallInt): Boolean; overload;

{ Split 'KEY=VALUE'. Fails when there is no '=', the key is empty, or the
  value holds another '=' (a fused token such as 'CRC=ONNAM=COM'). Key is
  returned upper-cased, Value as written. }
function SplitKeyValue(const Tok: ShortString; var Key, Value: ShortString): Boolean; overload;
function SplitKeyValue(const Tok: ShortString; var Key, Value: AnsiString): Boolean; overload;

{ Strict integer parsing: optional sign, decimal digits, or '$' followed by
  hex digits; nothing else, no blanks. False on any other text or when the
  number lies outside Min..Max (or outside the range of N's type; then N is
  left unchanged). }
function StrToNum(const S: ShortString; Min, Max: LongInt; var N: LongInt): Boolean; overload;
function StrToNum(const S: ShortString; Min, Max: LongInt; var N: SmallInt): Boolean; overload;

{ Strict decimal real ('0.01', '1E-5', no blanks), Min..Max; False
  (D unchanged) for anything else. }
function StrToReal(const S: ShortString; Min, Max: Double; var D: Double): Boolean;

{ Position (0-based) of upper-cased S in a '|' separated list of choices
  such as 'FULL|HALF'; -1 when not found. }
function ChoiceIndex(const S, Choices: ShortString): LongInt;

{ The word at Index (0-based) of a '|' separated list; '' if none. }
function ChoiceWord(const Choices: ShortString; Index: LongInt): ShortString;

{ Value of a hexadecimal digit, -1 for any other character. }
function HexDigit(C: Char): SmallInt;

{ 'XX XX ...': Len bytes at P in hex, blank-separated. An AnsiString:
  a frame's bytes pass 255 characters. }
function HexBytes(P: PByte; Len: LongInt): AnsiString;

{ Decimal text of N. }
function NumStr(N: LongInt): ShortString;

implementation

uses
  Math;

function UpStr(const S: ShortString): ShortString;
var
  I: LongInt;
begin
  Result := S;
  for I := 1 to Length(Result) do
    if Result[I] in ['a'..'z'] then
      Result[I] := Chr(Ord(Result[I]) - 32);
end;

function IsBlank(C: Char): Boolean; inline;
begin
  Result := C in [#9, #10, #13, ' '];
end;

function NextTokenAt(const S: ShortString; var Pos: LongInt; var Tok: ShortString;
  var TokStart: LongInt): Boolean;
var
  L: LongInt;
begin
  L := Length(S);
  while (Pos <= L) and IsBlank(S[Pos]) do
    Inc(Pos);
  TokStart := Pos;
  while (Pos <= L) and not IsBlank(S[Pos]) do
    Inc(Pos);
  Tok := Copy(S, TokStart, Pos - TokStart);
  Result := Tok <> '';
end;

{ The other sizes go through the LongInt/ShortString version. }
function NextTokenAt(const S: ShortString; var Pos: SmallInt; var Tok: ShortString;
  var TokStart: SmallInt): Boolean;
var
  P, T: LongInt;
begin
  P := Pos;
  Result := NextTokenAt(S, P, Tok, T);
  Pos := P;
  TokStart := T;
end;

function NextTokenAt(const S: ShortString; var Pos: LongInt; var Tok: AnsiString;
  var TokStart: LongInt): Boolean;
var
  T: ShortString;
begin
  Result := NextTokenAt(S, Pos, T, TokStart);
  Tok := T;
end;

function NextTokenAt(const S: ShortString; var Pos: SmallInt; var Tok: AnsiString;
  var TokStart: SmallInt): Boolean;
var
  P, Start: LongInt;
  T: ShortString;
begin
  P := Pos;
  Result := NextTokenAt(S, P, T, Start);
  Pos := P;
  TokStart := Start;
  Tok := T;
end;

function NextToken(const S: ShortString; var Pos: LongInt; var Tok: ShortString): Boolean;
var
  Start: LongInt;
begin
  Result := NextTokenAt(S, Pos, Tok, Start);
end;

function NextToken(const S: ShortString; var Pos: SmallInt; var Tok: ShortString): Boolean;
var
  Start: SmallInt;
begin
  Result := NextTokenAt(S, Pos, Tok, Start);
end;

function NextToken(const S: ShortString; var Pos: LongInt; var Tok: AnsiString): Boolean;
var
  Start: LongInt;
begin
  Result := NextTokenAt(S, Pos, Tok, Start);
end;

function NextToken(const S: ShortString; var Pos: SmallInt; var Tok: AnsiString): Boolean;
var
  Start: SmallInt;
begin
  Result := NextTokenAt(S, Pos, Tok, Start);
end;

function SplitKeyValue(const Tok: ShortString; var Key, Value: ShortString): Boolean;
var
  P: LongInt;
begin
  P := Pos('=', Tok);
  Result := False;
  if P <= 1 then
    Exit;
  Key := UpStr(Copy(Tok, 1, P - 1));
  Value := Copy(Tok, P + 1, Length(Tok) - P);
  Result := Pos('=', Value) = 0;
end;

function SplitKeyValue(const Tok: ShortString; var Key, Value: AnsiString): Boolean;
var
  K, V: ShortString;
begin
  Result := SplitKeyValue(Tok, K, V);
  if Pos('=', Tok) > 1 then   { as the ShortString version: set once '=' is found }
  begin
    Key := K;
    Value := V;
  end;
end;

function StrToNum(const S: ShortString; Min, Max: LongInt; var N: LongInt): Boolean;
var
  I, D: LongInt;
  Neg, Hex: Boolean;
  V: Int64;
begin
  Result := False;
  I := 1;
  Neg := False;
  Hex := False;
  if (I <= Length(S)) and (S[I] in ['+', '-']) then
  begin
    Neg := S[I] = '-';
    Inc(I);
  end;
  if (I <= Length(S)) and (S[I] = '$') then
  begin
    Hex := True;
    Inc(I);
  end;
  if I > Length(S) then
    Exit;
  V := 0;
  while I <= Length(S) do
  begin
    D := HexDigit(S[I]);
    if (D < 0) or ((D > 9) and not Hex) then
      Exit;
    if Hex then
      V := V * 16 + D
    else
      V := V * 10 + D;
    if V > High(LongWord) then   { stop before Int64 could overflow }
      Exit;
    Inc(I);
  end;
  if Neg then
    V := -V;
  if (V < Min) or (V > Max) then
    Exit;
  N := V;
  Result := True;
end;

function StrToNum(const S: ShortString; Min, Max: LongInt; var N: SmallInt): Boolean;
var
  V: LongInt;
begin
  if Min < Low(SmallInt) then
    Min := Low(SmallInt);
  if Max > High(SmallInt) then
    Max := High(SmallInt);
  V := 0;
  Result := StrToNum(S, Min, Max, V);
  if Result then
    N := V;
end;

function StrToReal(const S: ShortString; Min, Max: Double; var D: Double): Boolean;
var
  V: Double;
  Code, I, Digits: LongInt;
  Masked: TFPUExceptionMask;

  { skip an optional sign (Signed) and the digits at I; how many digits }
  function Skip(Signed: Boolean): LongInt;
  begin
    if Signed and (I <= Length(S)) and (S[I] in ['+', '-']) then
      Inc(I);
    Result := 0;
    while (I <= Length(S)) and (S[I] in ['0'..'9']) do
    begin
      Inc(I);
      Inc(Result);
    end;
  end;

begin
  Result := False;
  { strict form: [+-] digits [. digits] [e|E [+-] digits], at least one
    digit before the exponent; Val would take blanks, '$', 'Inf', 'NaN' }
  I := 1;
  Digits := Skip(True);
  if (I <= Length(S)) and (S[I] = '.') then
  begin
    Inc(I);
    Inc(Digits, Skip(False));
  end;
  if Digits = 0 then
    Exit;
  if (I <= Length(S)) and (S[I] in ['e', 'E']) then
  begin
    Inc(I);
    if Skip(True) = 0 then
      Exit;
  end;
  if I <= Length(S) then
    Exit;
  { 2e308, 1E400, 300 digits: with the FPU's overflow exception unmasked
    Val raises EOverflow (run-time error 217 in a program without
    SysUtils' handler); masked, it gives Inf or 0, which the range check
    below refuses or takes }
  Masked := GetExceptionMask;
  SetExceptionMask(Masked + [exInvalidOp, exDenormalized, exZeroDivide,
    exOverflow, exUnderflow, exPrecision]);
  try
    V := 0;
    Code := 0;
    Val(S, V, Code);
  finally
    SetExceptionMask(Masked);
  end;
  if (Code <> 0) or not (V >= Min) or not (V <= Max) then
    Exit;
  D := V;
  Result := True;
end;

function ChoiceIndex(const S, Choices: ShortString): LongInt;
var
  U, Item: ShortString;
  I, Start, Index: LongInt;
begin
  U := UpStr(S);
  Index := 0;
  Start := 1;
  for I := 1 to Length(Choices) + 1 do
    if (I > Length(Choices)) or (Choices[I] = '|') then
    begin
      Item := Copy(Choices, Start, I - Start);
      if (Item <> '') and (Item = U) then
        Exit(Index);
      Inc(Index);
      Start := I + 1;
    end;
  Result := -1;
end;

function ChoiceWord(const Choices: ShortString; Index: LongInt): ShortString;
var
  I, Start: LongInt;
begin
  Start := 1;
  for I := 1 to Length(Choices) + 1 do
    if (I > Length(Choices)) or (Choices[I] = '|') then
    begin
      if Index = 0 then
        Exit(Copy(Choices, Start, I - Start));
      Dec(Index);
      Start := I + 1;
    end;
  Result := '';
end;

function HexDigit(C: Char): SmallInt;
begin
  case C of
    '0'..'9': Result := Ord(C) - Ord('0');
    'A'..'F': Result := Ord(C) - Ord('A') + 10;
    'a'..'f': Result := Ord(C) - Ord('a') + 10;
  else
    Result := -1;
  end;
end;

function HexBytes(P: PByte; Len: LongInt): AnsiString;
const
  Digits: array[0..15] of Char = '0123456789ABCDEF';
var
  I: LongInt;
begin
  if Len <= 0 then
    Exit('');
  SetLength(Result, Len * 3 - 1);
  for I := 0 to Len - 1 do
  begin
    Result[I * 3 + 1] := Digits[P[I] shr 4];
    Result[I * 3 + 2] := Digits[P[I] and $F];
    if I < Len - 1 then
      Result[I * 3 + 3] := ' ';
  end;
end;

function NumStr(N: LongInt): ShortString;
begin
  Str(N, Result);
end;

end.
