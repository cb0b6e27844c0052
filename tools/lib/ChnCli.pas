{ ChnCli - the command line of every example and tool: one option parser
  (the RTL's getopts, GetLongOpts), one usage text, one error format.

  A program describes itself and its options, then calls CliParse once,
  before it opens anything:

    CliInit(Cli, 'df1read', '[OPTION]... [ADDRESS [COUNT]] PARAMETER-STRING...',
      'Read SLC 500 / MicroLogix data by address ...');
    CliOption(Cli, 'timeout', #0, 'MS', 'wait at most MS ms for an answer');
    CliExit(Cli, 0, 'the values were read');
    CliParse(Cli);                      // --help, --version, errors: exits
    T := CliNum(Cli, 'timeout', 1, 600000, 2000);
    Params := CliRest(Cli, 0);          // the positional arguments joined
    CliCheckParams(Cli, Params, 'DF1'); // a bad parameter string: exit 2

  The conventions (docs/TOOLS.md):
  * -h/--help prints the usage on standard output, exit 0; -V/--version
    prints "PROG (Chn) VERSION", exit 0 (help2man makes the man pages from
    both);
  * no arguments at all prints the usage on standard error, exit 2 -
    unless the program runs without arguments (CliNoArgsOk), which its
    usage then says;
  * every value option takes "--opt VALUE" and "--opt=VALUE"; a flag
    refuses a value; a long option must be spelt out (getopts alone would
    take any part of a name);
  * an argument that starts with "-" and a digit is a number, not an
    option (df1write N7:0 -5 ...), and an empty argument is an argument;
  * every command-line error is one line "PROG: what is wrong (TOKEN)" on
    standard error, exit 2 (CliExitUsage), before anything was opened;
  * the other exit codes are the program's, listed with CliExit, and
    follow one scheme where they can: 1 setup or line fault (cannot
    open, device lost), 3 a wrong or error answer, 4 no answer in time.

  FCL's CustApp would do the same for a TCustomApplication, but its
  CheckOptions (FPC 3.2.2) takes long option values only as --opt=VALUE;
  getopts takes both. Positional arguments (parameter strings, files,
  addresses) are kept in order; "--" ends the options. }
unit ChnCli;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnLayers;

const
  CliExitUsage = 2;      { every command-line error }

type
  tCliOption = record
    Name : AnsiString;   { long name without "--" }
    Short: Char;         { #0: none }
    Arg  : AnsiString;   { '' for a flag, else the value's name (MS, FILE) }
    Help : AnsiString;
    Given: Boolean;
    Value: AnsiString;   { the last one given }
    Token: AnsiString;   { as written, for error texts }
  end;

  tCli = record
    Prog, Synopsis, Description, Epilog: AnsiString;
    NoArgsOk: Boolean;   { runs without arguments (df1demo) }
    Options : array of tCliOption;
    ExitCodes: array of LongInt;
    ExitTexts: array of AnsiString;
    Args    : array of AnsiString;   { positional arguments, in order }
  end;

{ Program name, synopsis (after "Usage: PROG "), one paragraph that says
  what the program does. -h/--help and -V/--version are added. }
procedure CliInit(out Cli: tCli; const Prog, Synopsis, Description: AnsiString);
{ An option: Arg '' = a flag; Short #0 = none. }
procedure CliOption(var Cli: tCli; const Name: AnsiString; Short: Char;
  const Arg, Help: AnsiString);
{ An exit code and its meaning, listed under "Exit status:". }
procedure CliExit(var Cli: tCli; Code: LongInt; const Meaning: AnsiString);
{ Text after the options (examples, notes), printed as given. }
procedure CliEpilog(var Cli: tCli; const Text: AnsiString);
{ The program runs without arguments: no usage error for none. }
procedure CliNoArgsOk(var Cli: tCli);

{ Parses ParamStr(1..ParamCount). Ends the program for --help, --version,
  no arguments (unless CliNoArgsOk) and every malformed option. }
procedure CliParse(var Cli: tCli);

function CliHas(const Cli: tCli; const Name: AnsiString): Boolean;
function CliValue(const Cli: tCli; const Name, Default: AnsiString): AnsiString;
{ The option's value as a whole number Min..Max, Default when not given;
  anything else ends the program with a usage error naming the token. }
function CliNum(const Cli: tCli; const Name: AnsiString; Min, Max, Default: LongInt): LongInt;
{ The index (0-based) of the option's value in Choices ('OFF|ON'),
  Default when not given; case-insensitive. }
function CliChoice(const Cli: tCli; const Name, Choices: AnsiString; Default: LongInt): LongInt;
function CliArgCount(const Cli: tCli): LongInt;
{ The positional arguments from First (0-based) on, joined with blanks:
  a parameter string given as one argument or as several. }
function CliRest(const Cli: tCli; First: LongInt): AnsiString;

{ "PROG: What (Token)" on standard error, exit Code (without a Halt here:
  what the routines under way hold is freed on the way out). Token '' = none. }
procedure CliFail(const Cli: tCli; const What, Token: AnsiString; Code: LongInt);
{ End the program with Code the way CliFail does (what the routines under
  way hold freed, the program's finally parts run), without a message:
  for a program that said what happened itself. }
procedure CliEnd(Code: LongInt);
{ A usage error: CliFail with CliExitUsage. }
procedure CliUsageError(const Cli: tCli; const What, Token: AnsiString);
{ The whole usage text. }
function CliUsageText(const Cli: tCli): AnsiString;

{ A parameter string checked the way ChSetParam checks it, with nothing
  opened: a layer of type TopLayer (or, when Params starts with NAM=, the
  one it names) is created, given the string and freed. A refusal is a
  usage error: "PROG: bad parameter string: <result text> (TOKEN): <what
  the key allows>" (ChErrorText). }
procedure CliCheckParams(const Cli: tCli; const Params, TopLayer: AnsiString);
{ The same, but the channel (not opened) is the caller's. }
function CliChannel(const Cli: tCli; const Params, TopLayer: AnsiString): pChnVirt;
{ The channel of Params (not opened), or nil with Why: what is wrong and
  the token ('bad parameter string: ... (BD=abc)'). For a program that
  must not exit on a bad string (a gateway reading its configuration). }
function CliNewChannel(const Params, TopLayer: AnsiString; out Why: AnsiString): pChnVirt;
{ The check of CliCheckParams for a program that reports on its own (a
  configuration file): '' when Params is good, else 'bad parameter
  string: ...' with the token and what the key allows. }
function CliParamsProblem(const Params, TopLayer: AnsiString): AnsiString;

{ The exit code for a result of the scheme above: res_Ok 0, res_Timeout 4,
  an answer that is wrong or an error reply (res_BadMessage, protocol
  codes) 3, everything else (parameters, open, I/O, device lost) 1. }
function CliExitOf(R: tChResult): LongInt;

implementation

uses
  SysUtils, getopts, uString;

procedure AddOption(var Cli: tCli; const Name: AnsiString; Short: Char;
  const Arg, Help: AnsiString);
var
  N: LongInt;
begin
  N := Length(Cli.Options);
  SetLength(Cli.Options, N + 1);
  Cli.Options[N].Name := Name;
  Cli.Options[N].Short := Short;
  Cli.Options[N].Arg := Arg;
  Cli.Options[N].Help := Help;
  Cli.Options[N].Given := False;
  Cli.Options[N].Value := '';
  Cli.Options[N].Token := '';
end;

procedure CliInit(out Cli: tCli; const Prog, Synopsis, Description: AnsiString);
begin
  Cli.Prog := Prog;
  Cli.Synopsis := Synopsis;
  Cli.Description := Description;
  Cli.Epilog := '';
  Cli.NoArgsOk := False;
  SetLength(Cli.ExitCodes, 0);
  SetLength(Cli.ExitTexts, 0);
  SetLength(Cli.Options, 0);
  SetLength(Cli.Args, 0);
  AddOption(Cli, 'help', 'h', '', 'print this help on standard output and exit');
  AddOption(Cli, 'version', 'V', '', 'print the version and exit');
end;

procedure CliOption(var Cli: tCli; const Name: AnsiString; Short: Char;
  const Arg, Help: AnsiString);
begin
  AddOption(Cli, Name, Short, Arg, Help);
end;

procedure CliExit(var Cli: tCli; Code: LongInt; const Meaning: AnsiString);
var
  N: LongInt;
begin
  N := Length(Cli.ExitCodes);
  SetLength(Cli.ExitCodes, N + 1);
  SetLength(Cli.ExitTexts, N + 1);
  Cli.ExitCodes[N] := Code;
  Cli.ExitTexts[N] := Meaning;
end;

procedure CliEpilog(var Cli: tCli; const Text: AnsiString);
begin
  Cli.Epilog := Cli.Epilog + Text;
end;

procedure CliNoArgsOk(var Cli: tCli);
begin
  Cli.NoArgsOk := True;
end;

{ Text wrapped to Width columns, each line after the first indented by
  Indent blanks. }
function Wrap(const Text: AnsiString; Indent, Width: LongInt): AnsiString;
var
  Line, W: AnsiString;
  P, Q: LongInt;
begin
  Result := '';
  Line := '';
  P := 1;
  while P <= Length(Text) do
  begin
    while (P <= Length(Text)) and (Text[P] = ' ') do
      Inc(P);
    Q := P;
    while (Q <= Length(Text)) and (Text[Q] <> ' ') do
      Inc(Q);
    W := Copy(Text, P, Q - P);
    P := Q;
    if W = '' then
      Continue;
    if (Line <> '') and (Length(Line) + 1 + Length(W) > Width - Indent) then
    begin
      Result := Result + Line + LineEnding + StringOfChar(' ', Indent);
      Line := '';
    end;
    if Line <> '' then
      Line := Line + ' ';
    Line := Line + W;
  end;
  Result := Result + Line;
end;

function CliUsageText(const Cli: tCli): AnsiString;
var
  I, Code: LongInt;
  Left: AnsiString;
begin
  Result := 'Usage: ' + Cli.Prog + ' ' + Cli.Synopsis + LineEnding +
    Wrap(Cli.Description, 0, 78) + LineEnding;
  if Cli.NoArgsOk then
    Result := Result + 'Without arguments it runs as described (it needs none).' + LineEnding;
  Result := Result + LineEnding + 'Options:' + LineEnding;
  for I := 0 to High(Cli.Options) do
    with Cli.Options[I] do
    begin
      if Short <> #0 then
        Left := '  -' + Short + ', --' + Name
      else
        Left := '      --' + Name;
      if Arg <> '' then
        Left := Left + '=' + Arg;
      if Length(Left) > 26 then
        Result := Result + Left + LineEnding + StringOfChar(' ', 28)
      else
        Result := Result + Left + StringOfChar(' ', 28 - Length(Left));
      Result := Result + Wrap(Help, 28, 79) + LineEnding;
    end;
  Result := Result + '  Every option that takes a value takes it as --opt VALUE or --opt=VALUE;'
    + LineEnding + '  "--" ends the options.' + LineEnding;
  if Cli.Epilog <> '' then
    Result := Result + LineEnding + Cli.Epilog;
  { the program's codes and the usage error, in order }
  Result := Result + LineEnding + 'Exit status:' + LineEnding;
  for Code := 0 to 255 do
  begin
    if Code = CliExitUsage then
      Result := Result + Format('  %-3d %s', [Code, Wrap('a command-line error ' +
        '(an option, an argument, the parameter string): nothing was opened', 6, 79)]) + LineEnding;
    for I := 0 to High(Cli.ExitCodes) do
      if Cli.ExitCodes[I] = Code then
        Result := Result + Format('  %-3d %s', [Code, Wrap(Cli.ExitTexts[I], 6, 79)]) + LineEnding;
  end;
end;

{ Ending the program from deep inside it: a Halt there would leave every
  string and dynamic array of the routines under way (and of the main
  program's block) unfreed, and skip their finally parts. CliFail raises
  a TCliExit instead: on its way out every routine frees its own, and
  the program's try/finally parts run; no handler takes it (it is no
  Exception), so the run-time library hands it to CliExceptProc, which
  drops it and ends the program with its code. }
type
  TCliExit = class
    Code: LongInt;
  end;

var
  OtherExceptProc: TExceptProc;

{ the run-time library's own: takes the exception off its stack (and
  frees the stack entry), returns the object }
function PopExceptObject: TObject; external name 'FPC_POPOBJECTSTACK';

procedure CliExceptProc(Obj: TObject; Addr: CodePointer; FrameCount: LongInt; Frame: PCodePointer);
var
  Code: LongInt;
begin
  if not (Obj is TCliExit) then
  begin
    if Assigned(OtherExceptProc) then
      OtherExceptProc(Obj, Addr, FrameCount, Frame);
    Exit;
  end;
  Code := TCliExit(Obj).Code;
  PopExceptObject.Free;
  Halt(Code);
end;

procedure CliEnd(Code: LongInt);
var
  E: TCliExit;
begin
  E := TCliExit.Create;
  E.Code := Code;
  raise E;
end;

procedure CliFail(const Cli: tCli; const What, Token: AnsiString; Code: LongInt);
begin
  if Token <> '' then
    WriteLn(StdErr, Cli.Prog, ': ', What, ' (', Token, ')')
  else
    WriteLn(StdErr, Cli.Prog, ': ', What);
  CliEnd(Code);
end;

procedure CliUsageError(const Cli: tCli; const What, Token: AnsiString);
begin
  CliFail(Cli, What, Token, CliExitUsage);
end;

function FindOption(const Cli: tCli; const Name: AnsiString): LongInt;
begin
  for Result := 0 to High(Cli.Options) do
    if Cli.Options[Result].Name = Name then
      Exit;
  Result := -1;
end;

const
  StandIn: PChar = #1;

{ argv as it was (ParamStr reads it), before the program goes on or ends }
procedure RestoreArgv(const Orig: array of AnsiString);
var
  I: LongInt;
begin
  for I := 1 to High(Orig) do
    if argv[I] = StandIn then
      argv[I] := PChar(Orig[I]);
end;

var
  { the arguments as given; argv points into them again after CliParse,
    so they live as long as the program }
  Orig: array of AnsiString;

{ The usage on F, its text freed when this returns (a Halt right after
  would leave a temporary of the caller unfreed). }
procedure WriteUsage(var F: Text; const Cli: tCli);
begin
  Write(F, CliUsageText(Cli));
end;

{ End the program at once (--help, --version, no arguments): Halt frees
  neither a caller's strings nor the main program's variables, so the
  description is emptied first and heaptrc finds nothing left. }
procedure EndNow(var Cli: tCli; Code: LongInt);
begin
  Finalize(Cli);
  Halt(Code);
end;

type
  tLongOptions = array of TOption;

{ getopts' tables: long options (value = #128 + index), short letters;
  '-' first: arguments come back in order, as option #0. }
procedure GetoptTables(const Cli: tCli; out Long: tLongOptions; out Shorts: AnsiString);
var
  I: LongInt;
begin
  SetLength(Long, Length(Cli.Options) + 1);
  Shorts := '-';
  for I := 0 to High(Cli.Options) do
    with Cli.Options[I] do
    begin
      Long[I].Name := Name;
      Long[I].Has_arg := Ord(Arg <> '');
      Long[I].Flag := nil;
      Long[I].Value := Chr(128 + I);
      if Short <> #0 then
        if Arg <> '' then
          Shorts := Shorts + Short + ':'
        else
          Shorts := Shorts + Short;
    end;
  Long[High(Long)].Name := '';
end;

{ getopts fails on an empty argument and takes "-5" for options: it sees a
  one-character stand-in (a non-option) for those; Orig keeps every
  argument as given. }
procedure StandIns;
var
  I: LongInt;
begin
  SetLength(Orig, ParamCount + 1);
  for I := 1 to ParamCount do
  begin
    Orig[I] := ParamStr(I);
    if (Orig[I] = '') or ((Length(Orig[I]) >= 2) and (Orig[I][1] = '-') and
       (Orig[I][2] in ['0'..'9', '.'])) then
      argv[I] := StandIn;
  end;
end;

{ '--name=value' -> 'name' }
function LongName(const Tok: AnsiString): AnsiString;
begin
  Result := Copy(Tok, 3, MaxInt);
  if Pos('=', Result) > 0 then
    Result := Copy(Result, 1, Pos('=', Result) - 1);
end;

{ What getopts refused ('?' or ':'), said as the user wrote it. }
procedure RefuseOption(var Cli: tCli; const Tok: AnsiString);
var
  Name: AnsiString;
  K: LongInt;
begin
  if Copy(Tok, 1, 2) = '--' then
  begin
    Name := LongName(Tok);
    K := FindOption(Cli, Name);
    if (K >= 0) and (Cli.Options[K].Arg = '') then
      CliUsageError(Cli, '--' + Name + ' takes no value', Tok)
    else if K >= 0 then
      CliUsageError(Cli, '--' + Name + ' wants a value, ' + Cli.Options[K].Arg, Tok)
    else
      CliUsageError(Cli, 'unknown option', Tok);
  end
  else if OptOpt <> '?' then
    CliUsageError(Cli, 'unknown option -' + OptOpt + ' or it wants a value', Tok)
  else
    CliUsageError(Cli, 'unknown option', Tok);
end;

{ An option getopts returned as C (from the word Tok): marked given with its
  value. True for --help and --version, their text written. }
function TakeOption(var Cli: tCli; C: Char; const Tok: AnsiString): Boolean;
var
  I, K: LongInt;
begin
  Result := False;
  K := -1;
  if Ord(C) >= 128 then
    K := Ord(C) - 128
  else
    for I := 0 to High(Cli.Options) do
      if Cli.Options[I].Short = C then
        K := I;
  if K < 0 then
    CliUsageError(Cli, 'unknown option', Tok);
  { getopts takes any part of a long name: only the whole one here }
  if (Copy(Tok, 1, 2) = '--') and (LongName(Tok) <> Cli.Options[K].Name) then
    CliUsageError(Cli, 'unknown option', Tok);
  Cli.Options[K].Given := True;
  Cli.Options[K].Value := OptArg;
  if (Cli.Options[K].Arg <> '') and (Pos(OptArg, Tok) = 0) then
    Cli.Options[K].Token := Tok + ' ' + OptArg
  else
    Cli.Options[K].Token := Tok;
  if Cli.Options[K].Name = 'help' then
    WriteUsage(Output, Cli)
  else if Cli.Options[K].Name = 'version' then
    WriteLn(Cli.Prog, ' (Chn) ', ChnVersion)
  else
    Exit;
  Result := True;
end;

procedure AddArg(var Cli: tCli; const A: AnsiString);
begin
  SetLength(Cli.Args, Length(Cli.Args) + 1);
  Cli.Args[High(Cli.Args)] := A;
end;

{ CliParse up to --help or --version (then 0, the text written: the caller
  ends the program once this function's strings are freed), else -1. }
function ParseArgs(var Cli: tCli): LongInt;
var
  Long: tLongOptions;
  Shorts, Tok: AnsiString;
  I, Before, LongIndex: LongInt;
  C: Char;
begin
  if (ParamCount = 0) and not Cli.NoArgsOk then
  begin
    WriteUsage(StdErr, Cli);
    EndNow(Cli, CliExitUsage);
  end;
  GetoptTables(Cli, Long, Shorts);
  OptErr := False;               { our own messages, on standard error }
  StandIns;
  repeat
    Before := OptInd;
    if Before < 1 then
      Before := 1;
    LongIndex := 0;
    C := GetLongOpts(Shorts, @Long[0], LongIndex);
    Tok := '';
    if Before <= ParamCount then
      Tok := Orig[Before];
    if (OptArg = StandIn) and (OptInd >= 1) and (OptInd - 1 <= ParamCount) then
      OptArg := Orig[OptInd - 1];
    case C of
      EndOfOptions:
        Break;
      #0:
        AddArg(Cli, OptArg);
      '?', ':':
        RefuseOption(Cli, Tok);
    else
      if TakeOption(Cli, C, Tok) then
        Exit(0);
    end;
  until False;
  { after "--": the rest as it is }
  for I := OptInd to ParamCount do
    AddArg(Cli, Orig[I]);
  RestoreArgv(Orig);
  Result := -1;
end;

procedure CliParse(var Cli: tCli);
var
  Code: LongInt;
begin
  Code := ParseArgs(Cli);
  if Code >= 0 then
    EndNow(Cli, Code);
end;

function CliHas(const Cli: tCli; const Name: AnsiString): Boolean;
var
  K: LongInt;
begin
  K := FindOption(Cli, Name);
  Result := (K >= 0) and Cli.Options[K].Given;
end;

function CliValue(const Cli: tCli; const Name, Default: AnsiString): AnsiString;
var
  K: LongInt;
begin
  K := FindOption(Cli, Name);
  if (K >= 0) and Cli.Options[K].Given then
    Result := Cli.Options[K].Value
  else
    Result := Default;
end;

function CliNum(const Cli: tCli; const Name: AnsiString; Min, Max, Default: LongInt): LongInt;
var
  K: LongInt;
begin
  Result := Default;
  K := FindOption(Cli, Name);
  if (K < 0) or not Cli.Options[K].Given then
    Exit;
  if not StrToNum(Cli.Options[K].Value, Min, Max, Result) then
    CliUsageError(Cli, Format('--%s wants a whole number %d..%d', [Name, Min, Max]),
      Cli.Options[K].Token);
end;

function CliChoice(const Cli: tCli; const Name, Choices: AnsiString; Default: LongInt): LongInt;
var
  K: LongInt;
begin
  Result := Default;
  K := FindOption(Cli, Name);
  if (K < 0) or not Cli.Options[K].Given then
    Exit;
  Result := ChoiceIndex(Cli.Options[K].Value, Choices);
  if Result < 0 then
    CliUsageError(Cli, Format('--%s wants one of %s', [Name,
      StringReplace(LowerCase(Choices), '|', ', ', [rfReplaceAll])]), Cli.Options[K].Token);
end;

function CliArgCount(const Cli: tCli): LongInt;
begin
  Result := Length(Cli.Args);
end;

function CliRest(const Cli: tCli; First: LongInt): AnsiString;
var
  I: LongInt;
begin
  Result := '';
  for I := First to High(Cli.Args) do
    Result := Trim(Result + ' ' + Cli.Args[I]);
end;

{ A channel of the top layer Params names (TopLayer when it names none),
  given Params and not opened; nil with Why (and the token in Token). }
function NewChannel(const Params, TopLayer: AnsiString; out Why, Token: AnsiString): pChnVirt;
var
  Layer, Rest: AnsiString;
  P: LongInt;
begin
  Why := '';
  Token := '';
  if Length(Params) > High(tParamStr) then
  begin
    Why := Format('parameter string longer than %d characters', [High(tParamStr)]);
    Token := '...' + Copy(Params, High(tParamStr) - 19, 20) + '...';
    Exit(nil);
  end;
  Layer := TopLayer;
  Rest := Trim(Params);
  if UpStr(Copy(Rest, 1, 4)) = 'NAM=' then
  begin
    P := Pos(' ', Rest + ' ');
    Layer := Copy(Rest, 5, P - 5);
    Rest := Trim(Copy(Rest, P, MaxInt));
  end;
  Result := ChnCollection^.ChNewInit(Layer);
  if Result = nil then
  begin
    Why := 'bad parameter string: ' + ChResultText(res_UnknownLayer);
    Token := ChUnknownLayerText(Layer);
    Exit;
  end;
  Result^.ChSetParam(Rest);
  if Result^.ChResult <> res_Ok then
  begin
    Why := 'bad parameter string: ' + Result^.ChErrorText;     { the token and what it allows }
    Dispose(Result, Done);
    Result := nil;
  end;
end;

function CliChannel(const Cli: tCli; const Params, TopLayer: AnsiString): pChnVirt;
var
  Why, Token: AnsiString;
begin
  Result := NewChannel(Params, TopLayer, Why, Token);
  if Result = nil then
    CliUsageError(Cli, Why, Token);
end;

function CliNewChannel(const Params, TopLayer: AnsiString; out Why: AnsiString): pChnVirt;
var
  Token: AnsiString;
begin
  Result := NewChannel(Params, TopLayer, Why, Token);
  if (Result = nil) and (Token <> '') then
    Why := Why + ' (' + Token + ')';
end;

function CliParamsProblem(const Params, TopLayer: AnsiString): AnsiString;
var
  Chn: pChnVirt;
begin
  Chn := CliNewChannel(Params, TopLayer, Result);
  if Chn <> nil then
    Dispose(Chn, Done);
end;

procedure CliCheckParams(const Cli: tCli; const Params, TopLayer: AnsiString);
var
  Chn: pChnVirt;
begin
  Chn := CliChannel(Cli, Params, TopLayer);
  Dispose(Chn, Done);
end;

function CliExitOf(R: tChResult): LongInt;
begin
  if R = res_Ok then
    Result := 0
  else if R = res_Timeout then
    Result := 4
  else if (R = res_BadMessage) or (R >= res_Proto) then
    Result := 3
  else
    Result := 1;
end;

initialization
  OtherExceptProc := ExceptProc;
  ExceptProc := @CliExceptProc;
end.
