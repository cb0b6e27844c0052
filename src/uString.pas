{ uString - the string helpers the Chn library needs.

  The SofCon examples put "uString" in every uses clause; this unit keeps
  that name. It holds only what the library itself uses: splitting a
  parameter string into tokens, upper-casing and strict number parsing.
  All strings are ShortStrings so callers in any compiler mode can use it. }
unit uString;

{$I chn.inc}

interface

{ Upper-case ASCII letters only (parameter keys and values are ASCII). }
function UpStr(const S: string): string;

{ Next whitespace-separated token of S starting at Pos (1-based). Skips
  spaces, tabs and line breaks; returns False at the end. Pos is advanced
  past the token; TokStart receives where the token began. }
function NextToken(const S: string; var Pos: Integer; var Tok: string): Boolean;
function NextTokenAt(const S: string; var Pos: Integer; var Tok: string;
  var TokStart: Integer): Boolean;

{ Split 'KEY=VALUE'. Fails when there is no '=', the key is empty, or the
  value holds another '=' (a fused token such as 'CRC=ONNAM=COM'). Key is
  returned upper-cased, Value as written. }
function SplitKeyValue(const Tok: string; var Key, Value: string): Boolean;

{ Strict integer parsing: optional sign, decimal digits, or '$' followed by
  hex digits; nothing else, no blanks. False on any other text or when the
  number lies outside Min..Max (then N is left unchanged). }
function StrToNum(const S: string; Min, Max: LongInt; var N: LongInt): Boolean;

{ Position (0-based) of upper-cased S in a '|' separated list of choices
  such as 'FULL|HALF'; -1 when not found. }
{ Strict decimal real ('0.01', '1E-5', no blanks), Min..Max; False
  (D unchanged) for anything else. }
function StrToReal(const S: string; Min, Max: Double; var D: Double): Boolean;
function ChoiceIndex(const S, Choices: string): Integer;

{ The word at Index (0-based) of a '|' separated list; '' if none. }
function ChoiceWord(const Choices: string; Index: Integer): string;

{ Value of a hexadecimal digit, -1 for any other character. }
function HexDigit(C: Char): Integer;

{ 'XX XX ...': Len bytes at P in hex, blank-separated. An AnsiString:
  a frame's bytes pass 255 characters. }
function HexBytes(P: PByte; Len: Integer): AnsiString;

{ Decimal text of N. }
function NumStr(N: LongInt): string;

implementation

function UpStr(const S: string): string;
var
  I: Integer;
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

function NextTokenAt(const S: string; var Pos: Integer; var Tok: string;
  var TokStart: Integer): Boolean;
var
  L: Integer;
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

function NextToken(const S: string; var Pos: Integer; var Tok: string): Boolean;
var
  Start: Integer;
begin
  Result := NextTokenAt(S, Pos, Tok, Start);
end;

function SplitKeyValue(const Tok: string; var Key, Value: string): Boolean;
var
  P: Integer;
begin
  P := Pos('=', Tok);
  Result := False;
  if P <= 1 then
    Exit;
  Key := UpStr(Copy(Tok, 1, P - 1));
  Value := Copy(Tok, P + 1, Length(Tok) - P);
  Result := Pos('=', Value) = 0;
end;

function StrToNum(const S: string; Min, Max: LongInt; var N: LongInt): Boolean;
var
  I, D: Integer;
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

function StrToReal(const S: string; Min, Max: Double; var D: Double): Boolean;
var
  V: Double;
  Code, I: Integer;
begin
  Result := False;
  if S = '' then
    Exit;
  for I := 1 to Length(S) do
    if not (S[I] in ['0'..'9', '.', 'e', 'E', '+', '-']) then
      Exit;                     { Val would take blanks, '$' and 'Inf' }
  V := 0;
  Code := 0;
  Val(S, V, Code);
  if (Code <> 0) or not (V >= Min) or not (V <= Max) then
    Exit;
  D := V;
  Result := True;
end;

function ChoiceIndex(const S, Choices: string): Integer;
var
  U, Item: string;
  I, Start, Index: Integer;
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

function ChoiceWord(const Choices: string; Index: Integer): string;
var
  I, Start: Integer;
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

function HexDigit(C: Char): Integer;
begin
  case C of
    '0'..'9': Result := Ord(C) - Ord('0');
    'A'..'F': Result := Ord(C) - Ord('A') + 10;
    'a'..'f': Result := Ord(C) - Ord('a') + 10;
  else
    Result := -1;
  end;
end;

function HexBytes(P: PByte; Len: Integer): AnsiString;
const
  Digits: array[0..15] of Char = '0123456789ABCDEF';
var
  I: Integer;
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

function NumStr(N: LongInt): string;
begin
  Str(N, Result);
end;

end.
