{ ChnParam - the parameter-string parser every layer's ChSetOneParam and
  ChOwnParams use: a string split into KEY=VALUE tokens once (ParamSplit),
  numbers, choices and flags checked and set in one place (ParamNum,
  ParamChoice, ParamFlag, ParamSetNum), and the tokens ChGetParam reports
  (ParamText, FlagText). A failing check records what the key allows
  ('a number 50..4000000', 'one of N|E|O|M|S') for ChErrorText
  (ParamAllowed). Pure: no layer, no I/O.

  ChnVirt offers every name here too (chnvirtnames.inc), so a layer or a
  program that uses only ChnVirt keeps compiling. }
unit ChnParam;

{$I chn.inc}

interface

uses
  ChnTypes;

type
  { One token of a parameter string, split once by ParamSplit. }
  tParamToken = record
    Text : tWordString;   {< KEY=VALUE as given }
    Key  : string[31];    {< upper-cased KEY ('' when there is no '=') }
    Ok   : Boolean;       {< of the form KEY=VALUE, VALUE not empty, one '=' }
    Start: LongInt;       {< where it begins in the string }
  end;
  { A parameter string as tokens; while ChSetParam checks a layer's tokens,
    Items[OwnFirst .. OwnEnd - 1] are that layer's own (OwnEnd: the NAM=
    of the layer below, or Count). }
  tParamList = record
    Count   : LongInt;
    Items   : array of tParamToken;
    OwnFirst: LongInt;
    OwnEnd  : LongInt;
  end;

{ Split a parameter string into tokens, once (ChSetParam). }
procedure ParamSplit(const S: ShortString; var L: tParamList);
{ Index of the first of a layer's own tokens with Key (upper case) while
  ChCheckParams runs, -1 when the string does not give it. }
function ParamFind(const L: tParamList; const Key: ShortString): LongInt;
{ res_Ok when a parameter string of Len characters fits the legacy
  tParamStr, else res_ParamTooLong and Why = 'N characters, the limit is
  255' - for every entry point that takes a long string. }
function ParamLengthCheck(Len: LongInt; var Why: ShortString): tChResult; overload;
function ParamLengthCheck(Len: LongInt; var Why: AnsiString): tChResult; overload;

{ Helpers for ChSetOneParam/ChOwnParams of every layer, so that number
  parsing, range checks and ON/OFF live in one place. }
{ A routine that returns a number by reference comes for LongInt and SmallInt
  (a caller's plain "Integer" in any compiler mode). }
function ParamKey(const S: tWordString): ShortString;
function ParamValue(const S: tWordString): ShortString;
function ParamNum(const S: tWordString; Min, Max: LongInt; var N: LongInt): tChResult; overload;
function ParamNum(const S: tWordString; Min, Max: LongInt; var N: SmallInt): tChResult; overload;
function ParamChoice(const S: tWordString; const Choices: ShortString; var Index: LongInt): tChResult; overload;
function ParamChoice(const S: tWordString; const Choices: ShortString; var Index: SmallInt): tChResult; overload;
function ParamText(const Key: ShortString; N: LongInt): ShortString;
{ res_BadParam for a value a layer checks itself, with what the key
  allows ('one of RTL|PTY'), for ChErrorText; ParamNum and ParamChoice
  say it by themselves. }
function ParamBad(const Allowed: ShortString): tChResult;
{ A two-way choice kept in a Boolean. Choices lists the False word first
  ('OFF|ON', 'SLAVE|MASTER'); Flag is set only when CmdL = cmd_Set. }
function ParamFlag(const S: tWordString; const Choices: ShortString; CmdL: tCmd;
  var Flag: Boolean): tChResult;
{ A number kept in a LongInt field: checked as ParamNum, Field set only
  when CmdL = cmd_Set. }
function ParamSetNum(const S: tWordString; Min, Max: LongInt; CmdL: tCmd;
  var Field: LongInt): tChResult; overload;
function ParamSetNum(const S: tWordString; Min, Max: LongInt; CmdL: tCmd;
  var Field: SmallInt): tChResult; overload;
{ ' KEY=WORD' for a Boolean kept as in ParamFlag. }
function FlagText(const Key, Choices: ShortString; Flag: Boolean): ShortString;

const
  OnOffChoice  = 'OFF|ON';
  MasterChoice = 'SLAVE|MASTER';

{ ' KEY1 KEY2 ...': the keys of ' KEY1=VALUE KEY2=VALUE ...' (a layer's
  ChOwnParams), for the text of an unknown key. }
function ParamKeyList(const Tokens: AnsiString): ShortString;
{ Is Key one of the blank-separated words of List ('LRB IDL')? (No
  string is built: a layer asks it for every token it is given.) }
function ParamKeyIn(const Key, List: ShortString): Boolean;
{ What the key of the last failing ParamNum, ParamChoice or ParamBad
  allows ('' after ParamAllowedClear); ChSetParam reads it right after the
  check (one thread sets parameters). }
function ParamAllowed: ShortString;
procedure ParamAllowedClear;

implementation

uses
  SysUtils, uString;

var
  ParamAllowedText: ShortString = '';

function ParamAllowed: ShortString;
begin
  Result := ParamAllowedText;
end;

procedure ParamAllowedClear;
begin
  ParamAllowedText := '';
end;

{ The position of the one '=' of KEY=VALUE, 0 when there is none, a
  second one or no key (SplitKeyValue's rule). ParamKey and ParamValue
  are written out on it: each layer's ChSetOneParam calls them for every
  token, twice a ChSetParam, and SplitKeyValue builds both halves. }
function OnlyEqualAt(const S: ShortString): LongInt;
var
  I: LongInt;
begin
  Result := 0;
  for I := 1 to Length(S) do
    if S[I] = '=' then
      if Result = 0 then
        Result := I
      else
        Exit(0);
  if Result = 1 then
    Result := 0;
end;

procedure ParamSplit(const S: ShortString; var L: tParamList);
var
  P, Start, E: LongInt;
  Tok: ShortString;
begin
  L.Count := 0;
  L.OwnFirst := 0;
  L.OwnEnd := 0;
  P := 1;
  Start := 1;
  while NextTokenAt(S, P, Tok, Start) do
  begin
    if L.Count >= Length(L.Items) then
      SetLength(L.Items, 8 + 2 * L.Count);
    with L.Items[L.Count] do
    begin
      Text := Tok;
      { the key up to the first '=' even when a second one makes the
        token bad (the duplicate check compares keys) }
      E := Pos('=', Tok);
      if E > 1 then
        Key := UpStr(Copy(Tok, 1, E - 1))
      else
        Key := '';
      Ok := (E > 1) and (E < Length(Tok)) and (OnlyEqualAt(Tok) = E);
    end;
    L.Items[L.Count].Start := Start;
    Inc(L.Count);
  end;
end;

function ParamFind(const L: tParamList; const Key: ShortString): LongInt;
var
  I: LongInt;
begin
  for I := L.OwnFirst to L.OwnEnd - 1 do
    if L.Items[I].Key = Key then
      Exit(I);
  Result := -1;
end;

function ParamLengthCheck(Len: LongInt; var Why: AnsiString): tChResult;
var
  W: ShortString;
begin
  W := '';
  Result := ParamLengthCheck(Len, W);
  if Result <> res_Ok then
    Why := W;
end;

function ParamLengthCheck(Len: LongInt; var Why: ShortString): tChResult;
begin
  if Len <= High(tParamStr) then
    Exit(res_Ok);
  Why := NumStr(Len) + ' characters, the limit is ' + NumStr(High(tParamStr));
  Result := res_ParamTooLong;
end;

function ParamKey(const S: tWordString): ShortString;
var
  P: LongInt;
begin
  P := OnlyEqualAt(S);
  if P = 0 then
    Exit('');
  Result := UpStr(Copy(S, 1, P - 1));
end;

function ParamValue(const S: tWordString): ShortString;
var
  P: LongInt;
begin
  P := OnlyEqualAt(S);
  if P = 0 then
    Exit('');
  Result := Copy(S, P + 1, Length(S) - P);
end;

function ParamKeyIn(const Key, List: ShortString): Boolean;
var
  P, E: Integer;
begin
  Result := False;
  if Key = '' then
    Exit;
  P := Pos(Key, List);
  while P > 0 do
  begin
    E := P + Length(Key);
    if ((P = 1) or (List[P - 1] = ' ')) and ((E > Length(List)) or (List[E] = ' ')) then
      Exit(True);
    P := Pos(Key, List, P + 1);
  end;
end;

function ParamKeyList(const Tokens: AnsiString): ShortString;
var
  I: LongInt;
  InKey: Boolean;
begin
  Result := '';
  InKey := False;
  for I := 1 to Length(Tokens) do
    if Tokens[I] = ' ' then
    begin
      InKey := True;
      if (Result <> '') and (Result[Length(Result)] <> ' ') then
        Result := Result + ' ';
    end
    else if Tokens[I] = '=' then
      InKey := False
    else if InKey and (Length(Result) < 250) then
    begin
      if Result = '' then
        Result := ' ';
      Result := Result + Tokens[I];
    end;
  Result := TrimRight(Result);
end;

function ParamBad(const Allowed: ShortString): tChResult;
begin
  ParamAllowedText := Allowed;
  Result := res_BadParam;
end;

function NumAllowed(Min, Max: LongInt): ShortString;
begin
  Result := 'a number ' + NumStr(Min) + '..' + NumStr(Max);
end;

function ParamNum(const S: tWordString; Min, Max: LongInt; var N: LongInt): tChResult;
begin
  if StrToNum(ParamValue(S), Min, Max, N) then
    Result := res_Ok
  else
    Result := ParamBad(NumAllowed(Min, Max));
end;

function ParamNum(const S: tWordString; Min, Max: LongInt; var N: SmallInt): tChResult;
begin
  if StrToNum(ParamValue(S), Min, Max, N) then
    Result := res_Ok
  else
    Result := ParamBad(NumAllowed(Min, Max));
end;

function ParamChoice(const S: tWordString; const Choices: ShortString; var Index: LongInt): tChResult;
var
  I: LongInt;
begin
  I := ChoiceIndex(ParamValue(S), Choices);
  if I < 0 then
  begin
    ParamAllowedText := 'one of ' + Choices;
    Exit(res_BadParam);
  end;
  Index := I;
  Result := res_Ok;
end;

function ParamChoice(const S: tWordString; const Choices: ShortString; var Index: SmallInt): tChResult;
var
  I: LongInt;
begin
  I := 0;
  Result := ParamChoice(S, Choices, I);
  if Result = res_Ok then
    Index := I;
end;

function ParamText(const Key: ShortString; N: LongInt): ShortString;
begin
  Result := ' ' + Key + '=' + NumStr(N);
end;

function ParamFlag(const S: tWordString; const Choices: ShortString; CmdL: tCmd;
  var Flag: Boolean): tChResult;
var
  I: LongInt;
begin
  I := 0;
  Result := ParamChoice(S, Choices, I);
  if (Result = res_Ok) and (CmdL = cmd_Set) then
    Flag := I = 1;
end;

function ParamSetNum(const S: tWordString; Min, Max: LongInt; CmdL: tCmd;
  var Field: LongInt): tChResult;
var
  N: LongInt;
begin
  N := 0;
  Result := ParamNum(S, Min, Max, N);
  if (Result = res_Ok) and (CmdL = cmd_Set) then
    Field := N;
end;

function ParamSetNum(const S: tWordString; Min, Max: LongInt; CmdL: tCmd;
  var Field: SmallInt): tChResult;
var
  N: SmallInt;
begin
  N := 0;
  Result := ParamNum(S, Min, Max, N);
  if (Result = res_Ok) and (CmdL = cmd_Set) then
    Field := N;
end;

function FlagText(const Key, Choices: ShortString; Flag: Boolean): ShortString;
begin
  Result := ' ' + Key + '=' + ChoiceWord(Choices, Ord(Flag));
end;

end.
