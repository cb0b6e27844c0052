{ iec101master - an IEC 60870-5-101 master (controlling station) on the
  command line: sets up the link of every slave, runs the commands given,
  in order, for every slave, and prints every information object sent and
  received (the confirmations too), one line each: readable, or with
  --json one JSON object per line (tools/lib/ChnIec101Print, docs/ChnIec101.md).
  Unbalanced or balanced as the parameter string says (MS=ON / MS=OFF).

  Usage:  iec101master [OPTION]... 'PARAMS' COMMAND...
  e.g.    iec101master --json 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E' gi sc 5000=1 poll 10

  Built on ChnIec101Master (library); the command line is unit ChnCli's
  (docs/TOOLS.md): the options, the commands, the parameter string and
  the master's set-up are all checked before the line is opened. }
program iec101master;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, uString, ChnTypes, ChnVirt, ChnLayers, ChnFT1_2, ChnFT12Link,
  ChnIec101Asdu, ChnIec101Master, ChnIec101Print, ChnCli, ChnIecFile, ChnIecFileClient, ChnIecFileServer;

const
  Prog = 'iec101master';
  ExitOk = 0; ExitLine = 1; ExitAnswer = 3; ExitNoAnswer = 4;

type
  tCmdKind = (ckGi, ckCi, ckRead, ckClock, ckTest, ckSc, ckDc, ckScaled, ckFloat, ckPoll,
    ckDir, ckGet, ckPut, ckLog, ckDelete);
  tCmd = record
    Kind : tCmdKind;
    Ioa  : LongWord;
    Int  : LongInt;
    Num  : Double;
    Token: string;
    Path : string;    {< get, put: the local file }
    From, Till: TDateTime;   {< log: the range }
  end;

var
  Cli    : tCli;
  Cmds   : array of tCmd;
  Params : tIecParams;
  Ca     : LongInt;
  Slaves : array of Word;
  Json, Sbo, Delay: Boolean;
  M      : tIecMaster;
  Files  : tIecFileClient;

procedure Show(Addr: Word; const H: tIecAsdu; const O: tIecObject; const Dir: string);
begin
  if Json then
    WriteLn(IecObjectJson(H, O))
  else if Length(Slaves) > 1 then
    WriteLn('slave ', Addr, ' ', Dir, ' ', IecObjectText(H, O))
  else
    WriteLn(Dir, ' ', IecObjectText(H, O));
  Flush(Output);
end;

procedure OnReceived(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  Show(Addr, H, O, '<-');
end;

procedure OnSent(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  Show(Addr, H, O, '->');
end;

procedure OnBad(Data: Pointer; Addr: Word; const Err: ShortString);
begin
  WriteLn(StdErr, Prog, ': bad ASDU from ', Err);
end;

procedure Describe;
begin
  CliInit(Cli, Prog, '[OPTION]... ''PARAMS'' COMMAND...',
    'An IEC 60870-5-101 master: runs the commands in order for every slave and ' +
    'prints every information object sent and received, one per line. PARAMS is ' +
    'an FT 1.2 stack (NAM=FT1_2 ...), unbalanced (MS=ON MAS=MASTER) or balanced ' +
    '(MS=OFF PRI=ON: the controlling station, DIR=1 unless DIR= says otherwise).');
  CliOption(Cli, 'ca', #0, 'N', 'common address of ASDU (default 1)');
  CliOption(Cli, 'cot-size', #0, 'N', 'octets of the cause of transmission, 1 or 2 (default 2)');
  CliOption(Cli, 'ca-size', #0, 'N', 'octets of the common address, 1 or 2 (default 2)');
  CliOption(Cli, 'ioa-size', #0, 'N', 'octets of the information object address, 1..3 (default 3)');
  CliOption(Cli, 'slaves', #0, 'A,B,...', 'link addresses to poll (default DNO= of PARAMS)');
  CliOption(Cli, 'select', #0, '', 'commands as select-before-operate');
  CliOption(Cli, 'delay', #0, '', 'clock: acquire the transmission delay first');
  CliOption(Cli, 'timeout', #0, 'MS', 'link answer timeout (default ' + IntToStr(FT12LinkTimeoutMs) + ')');
  CliOption(Cli, 'retries', #0, 'N', 'link repetitions (default ' + IntToStr(FT12LinkRetries) + ')');
  CliOption(Cli, 'wait', #0, 'MS', 'wait for a confirmation at most MS (default 10000)');
  CliOption(Cli, 'json', #0, '', 'one JSON object per line on standard output, nothing else');
  CliOption(Cli, 'no-gi-after-init', #0, '', 'do not interrogate a slave after its end of ' +
    'initialisation (M_EI_NA_1)');
  CliEpilog(Cli, 'Commands:' + LineEnding +
    '  gi                      station interrogation' + LineEnding +
    '  gi-group N              interrogation of group N (1..16)' + LineEnding +
    '  ci                      counter interrogation (general, read)' + LineEnding +
    '  ci-group N              counter interrogation of group N (1..4)' + LineEnding +
    '  read IOA                read one information object' + LineEnding +
    '  clock                   clock synchronisation with the PC clock' + LineEnding +
    '  test                    test command' + LineEnding +
    '  sc IOA=0|1              single command' + LineEnding +
    '  dc IOA=1|2              double command (1 off, 2 on)' + LineEnding +
    '  setpoint-scaled IOA=N   set point, scaled value (-32768..32767)' + LineEnding +
    '  setpoint-float IOA=X    set point, short float' + LineEnding +
    '  poll SECONDS            keep polling and print what arrives' + LineEnding +
    '  dir                     the slave''s directory of files (F_DR_TA_1)' + LineEnding +
    '  get IOA=PATH            fetch the file of IOA into PATH (file transfer)' + LineEnding +
    '  put IOA=PATH            send the file PATH as the file of IOA' + LineEnding +
    '  log FROM TO             the files created from FROM to TO (query log, F_SC_NB_1);' + LineEnding +
    '                          times as 2026-12-04T09:30:00 (seconds, .mmm optional)' + LineEnding +
    '  delete IOA              delete the slave''s file of IOA' + LineEnding +
    LineEnding + 'Example:' + LineEnding +
    '  iec101master --json ''NAM=FT1_2 MS=ON MAS=MASTER LEN=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 ' +
    'BD=9600 PAR=E'' gi sc 5000=1 poll 10' + LineEnding);
  CliExit(Cli, ExitOk, 'every command was confirmed');
  CliExit(Cli, ExitLine, 'the line could not be opened, or failed');
  CliExit(Cli, ExitAnswer, 'a negative or unknown-object answer');
  CliExit(Cli, ExitNoAnswer, 'no answer in time');
end;

{ 'IOA=VALUE' of command Name: the IOA checked against --ioa-size. }
procedure SplitAssign(const Name, Tok: string; out Ioa: LongWord; out Value: string);
var
  P: Integer;
  N: LongInt;
begin
  P := Pos('=', Tok);
  N := 0;
  if (P < 2) or not StrToNum(Copy(Tok, 1, P - 1), 0, MaxLongInt, N) then
    CliUsageError(Cli, Name + ' wants IOA=VALUE', Tok);
  if LongWord(N) > IecMaxIoa(Params) then
    CliUsageError(Cli, 'IOA ' + IntToStr(N) + ' too large for ' + IntToStr(Params.IoaSize) +
      ' octet(s)', Tok);
  Ioa := N;
  Value := Copy(Tok, P + 1, MaxInt);
end;

{ 'YYYY-MM-DD', 'YYYY-MM-DDTHH:MM', ':SS', '.mmm' (local time as the
  slave keeps it); False when it is none. }
function ParseStamp(const S: string; out DT: TDateTime): Boolean;
var
  Y, Mo, D, H, Mi, Sec, Ms: LongInt;
  T: TDateTime;
  Rest: string;
begin
  DT := 0;
  H := 0; Mi := 0; Sec := 0; Ms := 0;
  Result := (Length(S) >= 10) and (S[5] = '-') and (S[8] = '-') and
    StrToNum(Copy(S, 1, 4), 2000, 2099, Y) and StrToNum(Copy(S, 6, 2), 1, 12, Mo) and
    StrToNum(Copy(S, 9, 2), 1, 31, D);
  Rest := Copy(S, 11, MaxInt);
  if Result and (Rest <> '') then
    Result := (Length(Rest) >= 6) and (Rest[1] = 'T') and (Rest[4] = ':') and
      StrToNum(Copy(Rest, 2, 2), 0, 23, H) and StrToNum(Copy(Rest, 5, 2), 0, 59, Mi) and
      ((Length(Rest) = 6) or ((Rest[7] = ':') and StrToNum(Copy(Rest, 8, 2), 0, 59, Sec) and
      ((Length(Rest) = 9) or ((Rest[10] = '.') and (Length(Rest) = 13) and
      StrToNum(Copy(Rest, 11, 3), 0, 999, Ms)))));
  Result := Result and TryEncodeDate(Y, Mo, D, DT) and TryEncodeTime(H, Mi, Sec, Ms, T);
  if Result then
    DT := DT + T;
end;

{ The commands: the positional arguments after PARAMS. }
procedure ParseCommands;
var
  I: Integer;
  C: tCmd;
  W, V, Tok: string;
  N: LongInt;

  function Next(const What: string): string;
  begin
    if I + 1 >= CliArgCount(Cli) then
      CliUsageError(Cli, W + ' wants ' + What, W);
    Inc(I);
    Result := Cli.Args[I];
  end;

  { The number after W (What names it when it is missing), Min..Max, else
    the usage error Msg; the command's token becomes "W NUMBER". }
  function NumberArg(const What: string; Min, Max: LongInt; const Msg: string): LongInt;
  begin
    V := Next(What);
    Result := 0;
    if not StrToNum(V, Min, Max, Result) then
      CliUsageError(Cli, Msg, V);
    C.Token := W + ' ' + V;
  end;

begin
  SetLength(Cmds, 0);
  I := 1;
  while I < CliArgCount(Cli) do
  begin
    FillChar(C, SizeOf(C), 0);
    W := Cli.Args[I];
    C.Token := W;
    if W = 'gi' then C.Kind := ckGi
    else if W = 'ci' then C.Kind := ckCi
    else if W = 'gi-group' then
    begin
      C.Kind := ckGi;
      C.Int := NumberArg('a group', 1, 16, 'gi-group wants a group 1..16');
    end
    else if W = 'ci-group' then
    begin
      C.Kind := ckCi;
      C.Int := NumberArg('a group', 1, 4, 'ci-group wants a counter group 1..4');
    end
    else if W = 'clock' then C.Kind := ckClock
    else if W = 'test' then C.Kind := ckTest
    else if W = 'read' then
    begin
      C.Kind := ckRead;
      C.Ioa := NumberArg('an IOA', 0, LongInt(IecMaxIoa(Params)), 'read wants an IOA 0..' + IntToStr(IecMaxIoa(Params)));
    end
    else if (W = 'sc') or (W = 'dc') or (W = 'setpoint-scaled') then
    begin
      Tok := Next('IOA=VALUE');
      C.Token := W + ' ' + Tok;
      SplitAssign(W, Tok, C.Ioa, V);
      N := 0;
      if W = 'sc' then
      begin
        C.Kind := ckSc;
        if not StrToNum(V, 0, 1, N) then
          CliUsageError(Cli, 'sc wants IOA=0|1', C.Token);
      end
      else if W = 'dc' then
      begin
        C.Kind := ckDc;
        if not StrToNum(V, 1, 2, N) then
          CliUsageError(Cli, 'dc wants IOA=1|2 (1 off, 2 on)', C.Token);
      end
      else
      begin
        C.Kind := ckScaled;
        if not StrToNum(V, -32768, 32767, N) then
          CliUsageError(Cli, 'setpoint-scaled wants IOA=N, N -32768..32767', C.Token);
      end;
      C.Int := N;
    end
    else if W = 'setpoint-float' then
    begin
      C.Kind := ckFloat;
      Tok := Next('IOA=X');
      C.Token := W + ' ' + Tok;
      SplitAssign(W, Tok, C.Ioa, V);
      if not StrToReal(V, -3.4e38, 3.4e38, C.Num) then
        CliUsageError(Cli, 'setpoint-float wants IOA=X, a short float', C.Token);
    end
    else if W = 'dir' then C.Kind := ckDir
    else if W = 'delete' then
    begin
      C.Kind := ckDelete;
      C.Ioa := NumberArg('an IOA', 0, LongInt(IecMaxIoa(Params)), 'delete wants an IOA 0..' + IntToStr(IecMaxIoa(Params)));
    end
    else if W = 'log' then
    begin
      C.Kind := ckLog;
      V := Next('FROM TO');
      Tok := Next('FROM TO');
      C.Token := W + ' ' + V + ' ' + Tok;
      if not ParseStamp(V, C.From) then
        CliUsageError(Cli, 'log wants FROM as 2026-12-04T09:30:00', V);
      if not ParseStamp(Tok, C.Till) then
        CliUsageError(Cli, 'log wants TO as 2026-12-04T09:30:00', Tok);
      if C.Till < C.From then
        CliUsageError(Cli, 'log wants FROM before TO', C.Token);
    end
    else if (W = 'get') or (W = 'put') then
    begin
      Tok := Next('IOA=PATH');
      C.Token := W + ' ' + Tok;
      SplitAssign(W, Tok, C.Ioa, C.Path);
      if C.Path = '' then
        CliUsageError(Cli, W + ' wants IOA=PATH', C.Token);
      if W = 'get' then
        C.Kind := ckGet
      else
      begin
        C.Kind := ckPut;
        if not FileExists(C.Path) then
          CliUsageError(Cli, 'no such file', C.Path);
      end;
    end
    else if W = 'poll' then
    begin
      C.Kind := ckPoll;
      C.Int := NumberArg('SECONDS', 0, 86400, 'poll wants SECONDS 0..86400');
    end
    else
      CliUsageError(Cli, 'unknown command', W);
    SetLength(Cmds, Length(Cmds) + 1);
    Cmds[High(Cmds)] := C;
    Inc(I);
  end;
end;

{ --slaves A,B,...; none given: DNO= of the parameter string. }
procedure ParseSlaves(Chn: pChnVirt);
var
  List: TStringList;
  I: Integer;
  N: LongInt;
begin
  if not CliHas(Cli, 'slaves') then
  begin
    SetLength(Slaves, 1);
    Slaves[0] := Chn^.CH_DNode;
    Exit;
  end;
  List := TStringList.Create;
  try
    List.StrictDelimiter := True;
    List.CommaText := CliValue(Cli, 'slaves', '');
    for I := 0 to List.Count - 1 do
    begin
      N := 0;
      if not StrToNum(Trim(List[I]), 0, 65535, N) then
      begin
        Dispose(Chn, Done);
        CliUsageError(Cli, '--slaves wants link addresses A,B,...', CliValue(Cli, 'slaves', ''));
      end;
      SetLength(Slaves, Length(Slaves) + 1);
      Slaves[High(Slaves)] := N;
    end;
  finally
    List.Free;
  end;
end;

{ The master on the channel, not yet opened: a parameter string or a
  --slaves the master refuses is a command-line error. }
procedure SetUpMaster(Chn: pChnVirt);
var
  R: tChResult;
  I: Integer;
begin
  R := IecMasterInit(M, Chn, Params);
  if R <> res_Ok then
  begin
    Dispose(Chn, Done);
    if R = res_BadMessage then      { a slave's string }
      CliUsageError(Cli, 'PARAMS must be MAS=MASTER (MS=ON) or PRI=ON (MS=OFF)', Cli.Args[0]);
    CliUsageError(Cli, ChResultText(R, Iec101Layer), Cli.Args[0]);
  end;
  M.TimeoutMs := CliNum(Cli, 'timeout', 1, 60000, FT12LinkTimeoutMs);
  M.Link.Bal.TimeoutMs := M.TimeoutMs;
  M.Retries := CliNum(Cli, 'retries', 0, 100, FT12LinkRetries);
  M.CommandMs := CliNum(Cli, 'wait', 1, 3600000, 10000);
  M.OnObject := @OnReceived;
  M.OnSent := @OnSent;
  M.OnBad := @OnBad;
  M.NoGiAfterInit := CliHas(Cli, 'no-gi-after-init');
  M.Data := nil;
  IecFileClientInit(Files, M);
  Files.TimeoutMs := M.CommandMs;
  if M.Balanced then
  begin
    if Length(Slaves) > 1 then
    begin
      Dispose(Chn, Done);
      CliUsageError(Cli, 'a balanced line has one peer: DNO=', CliValue(Cli, 'slaves', ''));
    end;
    M.Slaves[0].Addr := Slaves[0];
  end
  else
    for I := 0 to High(Slaves) do
      if IecMasterAddSlave(M, Slaves[I]) <> res_Ok then
      begin
        Dispose(Chn, Done);
        CliUsageError(Cli, 'slave address twice, too large for ADR= or the broadcast address', IntToStr(Slaves[I]));
      end;
end;

{ A file command (dir, get, put) to one slave: ChnIecFileClient. }
function RunFile(const C: tCmd; Addr: Word): tChResult;
var
  Content: AnsiString;
  I: Integer;
  E: ShortString;
begin
  Content := '';
  case C.Kind of
    ckDir, ckLog:
      begin
        if C.Kind = ckDir then
          Result := IecFileDir(Files, Addr, Ca)
        else
          Result := IecFileQueryLog(Files, Addr, Ca, 0, 0, IecTimeFromDateTime(C.From),
            IecTimeFromDateTime(C.Till));
        for I := 0 to Files.DirCount - 1 do
          with Files.Dir[I] do
            if Json then
              WriteLn(Format('{"slave":%d,"file":%d,"nof":%d,"length":%d,"sof":%d,"time":"%s"}',
                [Addr, Ioa, Nof, Lof, Sof, IecTimeText(Time, tkCP56)]))
            else
              WriteLn(Format('file IOA %d NOF %d %d octets SOF 0x%.2x %s',
                [Ioa, Nof, Lof, Sof, IecTimeText(Time, tkCP56)]));
      end;
    ckGet:
      begin
        Result := IecFileGet(Files, Addr, Ca, C.Ioa, Nof_Transparent, Content);
        if (Result = res_Ok) and not IecFileSave(C.Path, Content, E) then
        begin
          Files.Err := E;
          Result := res_BadParam;
        end;
      end;
    ckDelete: Result := IecFileDelete(Files, Addr, Ca, C.Ioa, Nof_Transparent);
  else
    if IecFileLoad(C.Path, Content, E) then
      Result := IecFilePut(Files, Addr, Ca, C.Ioa, Nof_Transparent, Content)
    else
    begin
      Files.Err := E;
      Result := res_BadParam;
    end;
  end;
  { what get, put and delete did (dir and log printed their entries) }
  if (Result <> res_Ok) or (C.Kind in [ckDir, ckLog]) then
  else if (C.Kind = ckDelete) and Json then
    WriteLn(Format('{"slave":%d,"deleted":%d}', [Addr, C.Ioa]))
  else if C.Kind = ckDelete then
    WriteLn(Format('file IOA %d deleted', [C.Ioa]))
  else if not Json then
    WriteLn(Format('%s file IOA %d: %d octets', [C.Token, C.Ioa, Length(Content)]))
  else
    WriteLn(Format('{"slave":%d,"%s":%d,"length":%d}', [Addr, Copy(C.Token, 1, 3), C.Ioa, Length(Content)]));
  Flush(Output);
end;

{ One command to one slave; the exit code it earns. }
function RunCommand(const C: tCmd; Addr: Word): Integer;
var
  R: tChResult;
  O: tIecObject;
begin
  O := IecObject(C.Ioa);
  O.Int := C.Int;
  O.Number := C.Num;
  case C.Kind of
    ckGi: R := IecInterrogation(M, Addr, Ca, Qoi_Station + C.Int);      { C.Int: the group, 0 = station }
    ckCi:
      if C.Int = 0 then
        R := IecCounterInterrogation(M, Addr, Ca, Qcc_General)
      else
        R := IecCounterInterrogation(M, Addr, Ca, C.Int);
    ckRead: R := IecRead(M, Addr, Ca, C.Ioa);
    ckClock: R := IecClockSync(M, Addr, Ca, IecTimeFromDateTime(Now), Delay);
    ckTest: R := IecTestCommand(M, Addr, Ca);
    ckSc: R := IecCommand(M, Addr, Ca, C_SC_NA_1, O, Sbo);
    ckDc: R := IecCommand(M, Addr, Ca, C_DC_NA_1, O, Sbo);
    ckScaled: R := IecCommand(M, Addr, Ca, C_SE_NB_1, O, Sbo);
    ckFloat: R := IecCommand(M, Addr, Ca, C_SE_NC_1, O, Sbo);
    ckDir, ckGet, ckPut, ckLog, ckDelete: R := RunFile(C, Addr);
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
  if C.Kind in [ckDir, ckGet, ckPut, ckLog, ckDelete] then
    WriteLn(StdErr, Prog, ': ', Files.Err, ' (', C.Token, ')')
  else
    WriteLn(StdErr, Prog, ': ', M.Cmd.Err, ' (', C.Token, ')');
  case R of
    res_Timeout: Result := ExitNoAnswer;
    res_IecNegative, res_IecUnknownType, res_IecUnknownCot, res_IecUnknownCa, res_IecUnknownIoa,
    res_IecFileRefused, res_IecFileChecksum, res_IecFileAborted, res_IecFileSequence:
      Result := ExitAnswer;
  else
    Result := ExitLine;
  end;
end;

var
  Chn: pChnVirt;
  I, J, Code, Worst: Integer;
begin
  Describe;
  CliParse(Cli);
  Json := CliHas(Cli, 'json');
  Sbo := CliHas(Cli, 'select');
  Delay := CliHas(Cli, 'delay');
  Params := IecDefaultParams;
  Params.CotSize := CliNum(Cli, 'cot-size', 1, 2, 2);
  Params.CaSize := CliNum(Cli, 'ca-size', 1, 2, 2);
  Params.IoaSize := CliNum(Cli, 'ioa-size', 1, 3, 3);
  Ca := CliNum(Cli, 'ca', 0, IecMaxCa(Params), 1);
  if CliArgCount(Cli) = 0 then
    CliUsageError(Cli, 'no parameter string', 'PARAMS');
  if CliArgCount(Cli) = 1 then
    CliUsageError(Cli, 'no command', Cli.Args[0]);
  ParseCommands;
  { the parameter string and the master, checked before anything opens }
  if (Pos('NAM=FT1_2', UpperCase(TrimLeft(Cli.Args[0]))) <> 1) and
     (Pos('NAM=IEC104', UpperCase(TrimLeft(Cli.Args[0]))) <> 1) then
    CliUsageError(Cli, 'the parameter string must start with NAM=FT1_2 or NAM=IEC104',
      Copy(Cli.Args[0], 1, 20));
  Chn := CliChannel(Cli, Cli.Args[0], ChnFT1_2.cName);
  ParseSlaves(Chn);
  SetUpMaster(Chn);
  Chn^.ChOpen;
  if Chn^.ChResult = res_Ok then
    Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then
  begin
    WriteLn(StdErr, Prog, ': cannot open the line: ', Chn^.ChErrorText);
    Dispose(Chn, Done);
    ExitCode := ExitLine;
    Exit;
  end;
  Worst := ExitOk;
  for I := 0 to High(Cmds) do
  begin
    if Cmds[I].Kind = ckPoll then
      Code := RunCommand(Cmds[I], Slaves[0])
    else
      for J := 0 to High(Slaves) do
      begin
        Code := RunCommand(Cmds[I], Slaves[J]);
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
  if not Json then
    for I := 0 to M.SlaveCount - 1 do
      with M.Slaves[I] do
        WriteLn(StdErr, Format('%s: slave %d %s: %d class 1, %d class 2 polls, %d ASDUs, '
          + '%d objects, %d bad ASDUs, %d failures, %d link resets%s',
          [Prog, Addr, IecSlaveStateName(State), Class1, Class2, Asdus, Objects, BadAsdus,
           Failures, Resets, IecLineShowed(M, I)]));
  Dispose(Chn, Done);
  { not Halt: the end of the program frees its strings and variables, which
    Halt leaves (heaptrc would count them) }
  ExitCode := Worst;
end.
