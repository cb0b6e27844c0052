{ iec101master - an IEC 60870-5-101 master (controlling station) on the
  command line: sets up the link of every slave, runs the commands given,
  in order, for every slave, and prints every information object sent and
  received (the confirmations too), one line each: readable, or with
  --json one JSON object per line (tools/lib/Iec101Print, docs/ChnIec101.md).
  Unbalanced or balanced as the parameter string says (MS=ON / MS=OFF).

  Usage:  iec101master [OPTION]... 'PARAMS' COMMAND...
  e.g.    iec101master --json 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E' gi sc 5000=1 poll 10

  Built on ChnIec101Master (library) and TCustomApplication (FCL CustApp;
  long options take "--opt VALUE" as well as "--opt=VALUE", which FPC
  3.2's CheckOptions does not, so the arguments are walked here). }
program iec101master;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, CustApp, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp,
  ChnFT1_2, ChnFT12Link, ChnIec101Asdu, ChnIec101Master, Iec101Print;

const
  Prog = 'iec101master';
  Version = '1.0.0';
  ValueOptions: array[0..7] of string = ('ca', 'cot-size', 'ca-size', 'ioa-size', 'slaves',
    'timeout', 'wait', 'retries');
  FlagOptions: array[0..4] of string = ('json', 'select', 'delay', 'help', 'version');

  ExitOk = 0; ExitLine = 1; ExitUsage = 2; ExitAnswer = 3; ExitNoAnswer = 4;

type
  tCmdKind = (ckGi, ckCi, ckRead, ckClock, ckTest, ckSc, ckDc, ckScaled, ckFloat, ckPoll);
  tCmd = record
    Kind : tCmdKind;
    Ioa  : LongWord;
    Int  : LongInt;
    Num  : Double;
    Token: string;
  end;

  TMasterApp = class(TCustomApplication)
  private
    FValues: TStringList;        { name=value of the value options given }
    FFlags : TStringList;
    FArgs  : TStringList;        { PARAMS and the commands, in order }
    FCmds  : array of tCmd;
    FParams: tIecParams;
    FCa    : LongInt;
    FSlaves: array of Word;
    FJson  : Boolean;
    M      : tIecMaster;
    procedure Usage(ToErr: Boolean);
    procedure Die(const What, Token: string);
    procedure WalkArguments;
    function Num(const Opt: string; Lo, Hi, Default: LongInt): LongInt;
    procedure ParseCommands;
    function RunCommand(const C: tCmd; Addr: Word): Integer;
  protected
    procedure DoRun; override;
  public
    constructor Create(AOwner: TComponent); override;
    destructor Destroy; override;
  end;

var
  App: TMasterApp;

procedure Show(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject; const Dir: string);
var
  A: TMasterApp;
begin
  A := TMasterApp(Data);
  if A.FJson then
    WriteLn(IecObjectJson(H, O))
  else if Length(A.FSlaves) > 1 then
    WriteLn('slave ', Addr, ' ', Dir, ' ', IecObjectText(H, O))
  else
    WriteLn(Dir, ' ', IecObjectText(H, O));
  Flush(Output);
end;

procedure OnReceived(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  Show(Data, Addr, H, O, '<-');
end;

procedure OnSent(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  Show(Data, Addr, H, O, '->');
end;

procedure OnBad(Data: Pointer; Addr: Word; const Err: ShortString);
begin
  WriteLn(StdErr, Prog, ': bad ASDU from ', Err);
end;

constructor TMasterApp.Create(AOwner: TComponent);
begin
  inherited Create(AOwner);
  FValues := TStringList.Create;
  FFlags := TStringList.Create;
  FArgs := TStringList.Create;
  StopOnException := True;
end;

destructor TMasterApp.Destroy;
begin
  FValues.Free;
  FFlags.Free;
  FArgs.Free;
  inherited Destroy;
end;

procedure TMasterApp.Usage(ToErr: Boolean);
var
  F: ^Text;
begin
  if ToErr then F := @StdErr else F := @Output;
  WriteLn(F^, 'Usage: ', Prog, ' [OPTION]... ''PARAMS'' COMMAND...');
  WriteLn(F^, 'An IEC 60870-5-101 master: runs the commands in order for every slave and prints');
  WriteLn(F^, 'every information object sent and received, one per line.');
  WriteLn(F^);
  WriteLn(F^, 'Commands:');
  WriteLn(F^, '  gi                      station interrogation');
  WriteLn(F^, '  ci                      counter interrogation (general, read)');
  WriteLn(F^, '  read IOA                read one information object');
  WriteLn(F^, '  clock                   clock synchronisation with the PC clock');
  WriteLn(F^, '  test                    test command');
  WriteLn(F^, '  sc IOA=0|1              single command');
  WriteLn(F^, '  dc IOA=1|2              double command (1 off, 2 on)');
  WriteLn(F^, '  setpoint-scaled IOA=N   set point, scaled value (-32768..32767)');
  WriteLn(F^, '  setpoint-float IOA=X    set point, short float');
  WriteLn(F^, '  poll SECONDS            keep polling and print what arrives');
  WriteLn(F^);
  WriteLn(F^, 'Options:');
  WriteLn(F^, '  --ca N             common address of ASDU (default 1)');
  WriteLn(F^, '  --cot-size N       octets of the cause of transmission, 1 or 2 (default 2)');
  WriteLn(F^, '  --ca-size N        octets of the common address, 1 or 2 (default 2)');
  WriteLn(F^, '  --ioa-size N       octets of the information object address, 1..3 (default 3)');
  WriteLn(F^, '  --slaves A,B,...   link addresses to poll (default DNO= of PARAMS)');
  WriteLn(F^, '  --select           commands as select-before-operate');
  WriteLn(F^, '  --delay            clock: acquire the transmission delay first');
  WriteLn(F^, '  --timeout MS       link answer timeout (default 1000)');
  WriteLn(F^, '  --retries N        link repetitions (default 3)');
  WriteLn(F^, '  --wait MS          wait for a confirmation at most MS (default 10000)');
  WriteLn(F^, '  --json             one JSON object per line on standard output, nothing else');
  WriteLn(F^, '  -h, --help         this text');
  WriteLn(F^, '  --version          the version');
  WriteLn(F^);
  WriteLn(F^, 'Exit status: 0 every command confirmed, 1 the line failed, 2 bad command line,');
  WriteLn(F^, '3 a negative or unknown-object answer, 4 no answer in time.');
end;

procedure TMasterApp.Die(const What, Token: string);
begin
  WriteLn(StdErr, Prog, ': ', What, ' (', Token, ')');
  Halt(ExitUsage);
end;

function IsIn(const S: string; const List: array of string): Boolean;
var
  I: Integer;
begin
  for I := 0 to High(List) do
    if List[I] = S then
      Exit(True);
  Result := False;
end;

procedure TMasterApp.WalkArguments;
var
  I, P: Integer;
  A, OptName, Value: string;
  Ended: Boolean;
begin
  I := 1;
  Ended := False;
  while I <= ParamCount do
  begin
    A := Params[I];
    Inc(I);
    if Ended or (A = '') or (A[1] <> '-') or ((Length(A) > 1) and (A[2] in ['0'..'9'])) then
    begin
      FArgs.Add(A);
      Continue;
    end;
    if A = '--' then
    begin
      Ended := True;
      Continue;
    end;
    if A = '-h' then
      A := '--help';
    if Copy(A, 1, 2) <> '--' then
      Die('unknown option', A);
    OptName := Copy(A, 3, MaxInt);
    Value := '';
    P := Pos('=', OptName);
    if P > 0 then
    begin
      Value := Copy(OptName, P + 1, MaxInt);
      OptName := Copy(OptName, 1, P - 1);
    end;
    if IsIn(OptName, FlagOptions) then
    begin
      if P > 0 then
        Die('--' + OptName + ' takes no value', A);
      FFlags.Add(OptName);
    end
    else if IsIn(OptName, ValueOptions) then
    begin
      if P = 0 then
      begin
        if I > ParamCount then
          Die('--' + OptName + ' wants a value', A);
        Value := Params[I];
        Inc(I);
      end;
      FValues.Values[OptName] := Value;
    end
    else
      Die('unknown option', A);
  end;
end;

function TMasterApp.Num(const Opt: string; Lo, Hi, Default: LongInt): LongInt;
var
  V: LongInt;
begin
  Result := Default;
  if FValues.IndexOfName(Opt) < 0 then
    Exit;
  V := 0;
  if not StrToNum(FValues.Values[Opt], Lo, Hi, V) then
    Die('--' + Opt + ' wants a number ' + IntToStr(Lo) + '..' + IntToStr(Hi),
      '--' + Opt + '=' + FValues.Values[Opt]);
  Result := V;
end;

{ 'IOA=VALUE' of command Name: the IOA checked against --ioa-size. }
procedure SplitAssign(A: TMasterApp; const Name, Tok: string; out Ioa: LongWord; out Value: string);
var
  P: Integer;
  N: LongInt;
begin
  P := Pos('=', Tok);
  N := 0;
  if (P < 2) or not StrToNum(Copy(Tok, 1, P - 1), 0, MaxLongInt, N) then
    A.Die(Name + ' wants IOA=VALUE', Tok);
  if LongWord(N) > IecMaxIoa(A.FParams) then
    A.Die('IOA ' + IntToStr(N) + ' too large for ' + IntToStr(A.FParams.IoaSize) + ' octet(s)', Tok);
  Ioa := N;
  Value := Copy(Tok, P + 1, MaxInt);
end;

procedure TMasterApp.ParseCommands;
var
  I: Integer;
  C: tCmd;
  W, V, Tok: string;
  N: LongInt;

  function Next(const What: string): string;
  begin
    if I + 1 >= FArgs.Count then
      Die(W + ' wants ' + What, W);
    Inc(I);
    Result := FArgs[I];
  end;

begin
  SetLength(FCmds, 0);
  I := 1;
  while I < FArgs.Count do
  begin
    FillChar(C, SizeOf(C), 0);
    W := FArgs[I];
    C.Token := W;
    if W = 'gi' then C.Kind := ckGi
    else if W = 'ci' then C.Kind := ckCi
    else if W = 'clock' then C.Kind := ckClock
    else if W = 'test' then C.Kind := ckTest
    else if W = 'read' then
    begin
      C.Kind := ckRead;
      V := Next('an IOA');
      N := 0;
      if not StrToNum(V, 0, MaxLongInt, N) or (LongWord(N) > IecMaxIoa(FParams)) then
        Die('read wants an IOA 0..' + IntToStr(IecMaxIoa(FParams)), V);
      C.Ioa := N;
      C.Token := W + ' ' + V;
    end
    else if (W = 'sc') or (W = 'dc') or (W = 'setpoint-scaled') then
    begin
      Tok := Next('IOA=VALUE');
      C.Token := W + ' ' + Tok;
      SplitAssign(Self, W, Tok, C.Ioa, V);
      N := 0;
      if W = 'sc' then
      begin
        C.Kind := ckSc;
        if not StrToNum(V, 0, 1, N) then
          Die('sc wants IOA=0|1', C.Token);
      end
      else if W = 'dc' then
      begin
        C.Kind := ckDc;
        if not StrToNum(V, 1, 2, N) then
          Die('dc wants IOA=1|2 (1 off, 2 on)', C.Token);
      end
      else
      begin
        C.Kind := ckScaled;
        if not StrToNum(V, -32768, 32767, N) then
          Die('setpoint-scaled wants IOA=N, N -32768..32767', C.Token);
      end;
      C.Int := N;
    end
    else if W = 'setpoint-float' then
    begin
      C.Kind := ckFloat;
      Tok := Next('IOA=X');
      C.Token := W + ' ' + Tok;
      SplitAssign(Self, W, Tok, C.Ioa, V);
      if not StrToReal(V, -3.4e38, 3.4e38, C.Num) then
        Die('setpoint-float wants IOA=X, a short float', C.Token);
    end
    else if W = 'poll' then
    begin
      C.Kind := ckPoll;
      V := Next('SECONDS');
      N := 0;
      if not StrToNum(V, 0, 86400, N) then
        Die('poll wants SECONDS 0..86400', V);
      C.Int := N;
      C.Token := W + ' ' + V;
    end
    else
      Die('unknown command', W);
    SetLength(FCmds, Length(FCmds) + 1);
    FCmds[High(FCmds)] := C;
    Inc(I);
  end;
end;

{ One command to one slave; the exit code it earns. }
function TMasterApp.RunCommand(const C: tCmd; Addr: Word): Integer;
var
  R: tChResult;
  O: tIecObject;
  Sbo: Boolean;
begin
  Sbo := FFlags.IndexOf('select') >= 0;
  O := IecObject(C.Ioa);
  O.Int := C.Int;
  O.Number := C.Num;
  case C.Kind of
    ckGi: R := IecInterrogation(M, Addr, FCa, Qoi_Station);
    ckCi: R := IecCounterInterrogation(M, Addr, FCa, Qcc_General);
    ckRead: R := IecRead(M, Addr, FCa, C.Ioa);
    ckClock: R := IecClockSync(M, Addr, FCa, IecTimeFromDateTime(Now), FFlags.IndexOf('delay') >= 0);
    ckTest: R := IecTestCommand(M, Addr, FCa);
    ckSc: R := IecCommand(M, Addr, FCa, C_SC_NA_1, O, Sbo);
    ckDc: R := IecCommand(M, Addr, FCa, C_DC_NA_1, O, Sbo);
    ckScaled: R := IecCommand(M, Addr, FCa, C_SE_NB_1, O, Sbo);
    ckFloat: R := IecCommand(M, Addr, FCa, C_SE_NC_1, O, Sbo);
  else
    begin
      IecPollFor(M, C.Int * 1000);
      R := M.LineResult;
    end;
  end;
  if M.LineResult <> res_Ok then
  begin
    WriteLn(StdErr, Prog, ': line: ', ChResultText(M.LineResult), ' (', C.Token, ')');
    Exit(ExitLine);
  end;
  if R = res_Ok then
    Exit(ExitOk);
  WriteLn(StdErr, Prog, ': ', M.Cmd.Err, ' (', C.Token, ')');
  case R of
    res_Timeout: Result := ExitNoAnswer;
    res_IecNegative, res_IecUnknownType, res_IecUnknownCot, res_IecUnknownCa, res_IecUnknownIoa:
      Result := ExitAnswer;
  else
    Result := ExitLine;
  end;
end;

procedure TMasterApp.DoRun;
var
  Chn: pChnVirt;
  S: string;
  I, J, Code, Worst: Integer;
  N: LongInt;
  R: tChResult;
  List: TStringList;
begin
  Terminate;
  if ParamCount = 0 then
  begin
    Usage(True);
    Halt(ExitUsage);
  end;
  WalkArguments;
  if HasOption('h', 'help') or (FFlags.IndexOf('help') >= 0) then
  begin
    Usage(False);
    Halt(ExitOk);
  end;
  if FFlags.IndexOf('version') >= 0 then
  begin
    WriteLn(Prog, ' (Chn) ', Version);
    Halt(ExitOk);
  end;
  FJson := FFlags.IndexOf('json') >= 0;
  FParams := IecDefaultParams;
  FParams.CotSize := Num('cot-size', 1, 2, 2);
  FParams.CaSize := Num('ca-size', 1, 2, 2);
  FParams.IoaSize := Num('ioa-size', 1, 3, 3);
  FCa := Num('ca', 0, IecMaxCa(FParams), 1);
  if FArgs.Count = 0 then
    Die('no parameter string', 'PARAMS');
  if FArgs.Count = 1 then
    Die('no command', FArgs[0]);
  if Length(FArgs[0]) > 255 then
    Die('parameter string longer than 255 characters', Copy(FArgs[0], 1, 40) + '...');
  ParseCommands;
  { the parameter string, checked before anything opens }
  if Pos('NAM=FT1_2', UpperCase(TrimLeft(FArgs[0]))) <> 1 then
    Die('the parameter string must start with NAM=FT1_2', Copy(FArgs[0], 1, 20));
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam(FArgs[0]);
  R := Chn^.ChResult;
  if R <> res_Ok then
  begin
    S := Chn^.ChParamError;
    Dispose(Chn, Done);
    Die('bad parameter string: ' + ChResultText(R), S);
  end;
  if FValues.IndexOfName('slaves') >= 0 then
  begin
    List := TStringList.Create;
    List.StrictDelimiter := True;
    List.CommaText := FValues.Values['slaves'];
    for I := 0 to List.Count - 1 do
    begin
      N := 0;
      if not StrToNum(Trim(List[I]), 0, 65535, N) then
      begin
        List.Free;
        Dispose(Chn, Done);
        Die('--slaves wants link addresses A,B,...', FValues.Values['slaves']);
      end;
      SetLength(FSlaves, Length(FSlaves) + 1);
      FSlaves[High(FSlaves)] := N;
    end;
    List.Free;
  end
  else
  begin
    SetLength(FSlaves, 1);
    FSlaves[0] := Chn^.CH_DNode;
  end;
  Chn^.ChOpen;
  if Chn^.ChResult = res_Ok then
    Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then
  begin
    WriteLn(StdErr, Prog, ': cannot open the line: ', Chn^.ChResultStr(Chn^.ChResult), ' (',
      Chn^.ChParamError, ')');
    Dispose(Chn, Done);
    Halt(ExitLine);
  end;
  R := IecMasterInit(M, Chn, FParams);
  if R <> res_Ok then
  begin
    WriteLn(StdErr, Prog, ': ', ChResultText(R, Iec101Layer), ': PARAMS must be MAS=MASTER (MS=ON) or PRI=ON (MS=OFF)',
      ' (', FArgs[0], ')');
    Dispose(Chn, Done);
    Halt(ExitUsage);
  end;
  M.TimeoutMs := Num('timeout', 1, 60000, FT12LinkTimeoutMs);
  M.Bal.TimeoutMs := M.TimeoutMs;
  M.Retries := Num('retries', 0, 100, FT12LinkRetries);
  M.CommandMs := Num('wait', 1, 3600000, 10000);
  M.OnObject := @OnReceived;
  M.OnSent := @OnSent;
  M.OnBad := @OnBad;
  M.Data := Self;
  if M.Balanced then
  begin
    if Length(FSlaves) > 1 then
    begin
      Dispose(Chn, Done);
      Die('a balanced line has one peer: DNO=', FValues.Values['slaves']);
    end;
    M.Slaves[0].Addr := FSlaves[0];
  end
  else
    for I := 0 to High(FSlaves) do
      if IecMasterAddSlave(M, FSlaves[I]) <> res_Ok then
      begin
        Dispose(Chn, Done);
        Die('slave address twice or too large for ADR=', IntToStr(FSlaves[I]));
      end;
  Worst := ExitOk;
  for I := 0 to High(FCmds) do
  begin
    if FCmds[I].Kind = ckPoll then
      Code := RunCommand(FCmds[I], FSlaves[0])
    else
      for J := 0 to High(FSlaves) do
      begin
        Code := RunCommand(FCmds[I], FSlaves[J]);
        if Code > Worst then
          Worst := Code;
        if Code = ExitLine then
          Break;
      end;
    if Code > Worst then
      Worst := Code;
    if Code = ExitLine then
      Break;
  end;
  if not FJson then
    for I := 0 to M.SlaveCount - 1 do
      with M.Slaves[I] do
        WriteLn(StdErr, Format('%s: slave %d %s: %d class 1, %d class 2 polls, %d ASDUs, '
          + '%d objects, %d bad ASDUs, %d failures, %d link resets',
          [Prog, Addr, IecSlaveStateName(State), Class1, Class2, Asdus, Objects, BadAsdus,
           Failures, Resets]));
  Dispose(Chn, Done);
  Halt(Worst);
end;

begin
  App := TMasterApp.Create(nil);
  App.Title := Prog;
  App.Initialize;
  App.Run;
  App.Free;
end.
