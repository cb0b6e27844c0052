{ iec101slave - an IEC 60870-5-101 controlled station (slave) on a serial
  line, a pty or a TCP port: ChnIec101Slave over the FT 1.2 layer,
  unbalanced (MS=ON MAS=SLAVE) or balanced (MS=OFF) as the parameter
  string says. It answers interrogations, counter interrogations, reads,
  clock synchronisation and commands from its point table, and prints
  every ASDU it receives or sends, object by object: one readable line
  each, or with --json one JSON object per line on stdout and nothing
  else (docs/ChnIec101.md). Counters and problems go to stderr.

  Usage: iec101slave [OPTION]... 'PARAMS' [--points FILE] [--seconds N]
  e.g.   iec101slave 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E' --points rtu.txt

  Without --points the table is that of lib60870's cs101_slave example
  (scaled 100..102 = -1, 23, 2300; single points 104, 105, 300..307;
  bitstring 500 = 0xAAAA) plus the single command point 5000. Exit codes:
  0 done (N seconds, or SIGINT/SIGTERM), 1 the line cannot be opened or
  failed, 2 a command-line, parameter or points-file error (nothing is
  opened then). The command line is unit ChnCli's (docs/TOOLS.md); the
  slave is set up on its channel before the channel is opened, so a
  parameter string that does not make a slave opens nothing either. }
program iec101slave;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix, ChnPty,{$ENDIF}
  Classes, SysUtils, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnFT1_2, ChnIec101Asdu,
  ChnIec101Slave, ChnIec101Print, Iec101Points, ChnCli, ChnIecFileServer;

const
  DefaultPoints =
    '100 M_ME_NB_1 -1'#10'101 M_ME_NB_1 23'#10'102 M_ME_NB_1 2300'#10 +
    '104 M_SP_NA_1 1'#10'105 M_SP_NA_1 0'#10 +
    '300 M_SP_NA_1 1'#10'301 M_SP_NA_1 0'#10'302 M_SP_NA_1 1'#10'303 M_SP_NA_1 0'#10 +
    '304 M_SP_NA_1 1'#10'305 M_SP_NA_1 0'#10'306 M_SP_NA_1 1'#10'307 M_SP_NA_1 0'#10 +
    '500 M_BO_NA_1 0xAAAA'#10'5000 C_SC_NA_1 0'#10;

var
  Cli: tCli;
  Json, Refuse: Boolean;
  Seconds, Ca, SelectMs, ClockOffset: LongInt;
  Params: tIecParams;
  LineParams, PointsFile, FilesDir: AnsiString;
  Stop: Boolean = False;
  { --return: a command point's monitoring point (return information) }
  Returns: array of record Cmd, Mon: LongWord; end;
  { executed commands whose return information is still to be sent }
  Pending: array of tIecObject;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  Stop := True;
end;
{$ENDIF}

{ --return CMD=MON,...: pairs of IOAs. }
procedure ParseReturns;
var
  L: TStringList;
  I, Eq, C, M, Code1, Code2: LongInt;
begin
  L := TStringList.Create;
  try
    L.CommaText := CliValue(Cli, 'return', '');
    SetLength(Returns, L.Count);
    for I := 0 to L.Count - 1 do
    begin
      Eq := Pos('=', L[I]);
      Val(Copy(L[I], 1, Eq - 1), C, Code1);
      Val(Copy(L[I], Eq + 1, MaxInt), M, Code2);
      if (Eq = 0) or (Code1 <> 0) or (Code2 <> 0) or (C < 0) or (M < 0) or (C > $FFFFFF) or (M > $FFFFFF) then
        CliUsageError(Cli, '--return wants CMD=MON pairs of IOAs', L[I]);
      Returns[I].Cmd := C;
      Returns[I].Mon := M;
    end;
  finally
    L.Free;
  end;
end;

procedure ParseArgs;
begin
  CliInit(Cli, 'iec101slave', '[OPTION]... ''PARAMS'' [--points FILE] [--seconds N]',
    'An IEC 60870-5-101 slave: answers interrogations, counter interrogations, ' +
    'reads, clock synchronisation and commands from a point table, unbalanced ' +
    '(MS=ON MAS=SLAVE) or balanced (MS=OFF) as the FT 1.2 parameter string says; ' +
    'prints every object received or sent, and its counters on standard error at the end.');
  CliOption(Cli, 'points', #0, 'FILE', 'point table, one "IOA TYPE VALUE [QUALITY] [GROUP=N]" per line ' +
    '(default: the points of lib60870''s cs101_slave example and the single command point 5000)');
  CliOption(Cli, 'seconds', #0, 'N', 'stop after N seconds (default: at SIGINT or SIGTERM)');
  CliOption(Cli, 'ca', #0, 'N', 'own common address (default 1)');
  CliOption(Cli, 'cot-size', #0, 'N', 'octets of the cause of transmission, 1 or 2 (default 2)');
  CliOption(Cli, 'ca-size', #0, 'N', 'octets of the common address, 1 or 2 (default 2)');
  CliOption(Cli, 'ioa-size', #0, 'N', 'octets of the information object address, 1..3 (default 3)');
  CliOption(Cli, 'select-ms', #0, 'MS', 'select-before-operate timeout (default ' +
    IntToStr(IecSlaveSelectMs) + ')');
  CliOption(Cli, 'clock-offset', #0, 'MS', 'the station clock runs MS ms after (negative: before) ' +
    'the PC clock, as after a clock synchronisation (default 0)');
  CliOption(Cli, 'refuse', #0, '', 'refuse every command (negative ACT_CON)');
  CliOption(Cli, 'return', #0, 'CMD=MON,...', 'return information: an executed command to ' +
    'command point CMD sets monitoring point MON to its value, sent as a spontaneous event ' +
    'after the ACT_CON (5000=104,5101=101)');
  CliOption(Cli, 'json', #0, '', 'one JSON object per line on stdout, nothing else');
  CliOption(Cli, 'files', #0, 'DIR', 'file transfer: serve the files of DIR named by their IOA ' +
    '(30000, 30000.dat ...), keep the files received there as DIR/IOA and delete them when the ' +
    'master asks');
  CliOption(Cli, 'no-init', #0, '', 'send no end of initialisation (M_EI_NA_1, COT 4, COI 0) ' +
    'after the start');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  iec101slave ''NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E''' +
    LineEnding);
  CliExit(Cli, 0, 'done: N seconds, or SIGINT/SIGTERM');
  CliExit(Cli, 1, 'the line cannot be opened, or failed');
  CliExit(Cli, 2, 'or a points file that cannot be read or has a bad line: nothing was opened');
  CliParse(Cli);
  Json := CliHas(Cli, 'json');
  Refuse := CliHas(Cli, 'refuse');
  PointsFile := CliValue(Cli, 'points', '');
  FilesDir := CliValue(Cli, 'files', '');
  if (FilesDir <> '') and not DirectoryExists(FilesDir) then
    CliUsageError(Cli, 'no such directory', FilesDir);
  Seconds := CliNum(Cli, 'seconds', 1, 1000000, 0);
  Ca := CliNum(Cli, 'ca', 0, 65535, 1);
  Params := IecDefaultParams;
  Params.CotSize := CliNum(Cli, 'cot-size', 1, 2, Params.CotSize);
  Params.CaSize := CliNum(Cli, 'ca-size', 1, 2, Params.CaSize);
  Params.IoaSize := CliNum(Cli, 'ioa-size', 1, 3, Params.IoaSize);
  SelectMs := CliNum(Cli, 'select-ms', 1, 3600000, IecSlaveSelectMs);
  ClockOffset := CliNum(Cli, 'clock-offset', -864000000, 864000000, 0);
  ParseReturns;
  if CliArgCount(Cli) = 0 then
    CliUsageError(Cli, 'no parameter string (''NAM=FT1_2 ... NAM=COM DEV=...'')', '');
  if CliArgCount(Cli) > 1 then
    CliUsageError(Cli, 'one parameter string only', Cli.Args[1]);
  LineParams := Cli.Args[0];
  if Ca > IecMaxCa(Params) then
    CliUsageError(Cli, Format('--ca above %d for a %d-octet common address', [IecMaxCa(Params),
      Params.CaSize]), IntToStr(Ca));
end;

var
  Slave, Table: tIecSlaveStation;
  Files: tIecFileServer;

procedure Show(Data: Pointer; Sent: Boolean; Buf: PByte; Len: Word);
var
  A: array[0..MaxDataLen - 1] of Byte;
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
  I: Integer;
  Arrow: string;
begin
  if Sent then Arrow := '-> ' else Arrow := '<- ';
  if Len > SizeOf(A) then
    Len := SizeOf(A);
  Move(Buf^, A[0], Len);
  if IecDecodeHeader(Slave.Params, A, Len, H, E) <> res_Ok then
  begin
    { not decodable here (file transfer, an unknown type): said on
      stderr, JSON stays clean }
    WriteLn(StdErr, FormatDateTime('hh:nn:ss.zzz ', Now), Arrow, IecAsduText(Slave.Params, A, Len));
    Exit;
  end;
  for I := 0 to H.Count - 1 do
    if IecDecodeObject(Slave.Params, H, A, I, O) = res_Ok then
      if Json then
        WriteLn(IecObjectJson(H, O))
      else
        WriteLn(FormatDateTime('hh:nn:ss.zzz ', Now), Arrow, IecObjectText(H, O));
  Flush(Output);
end;

function OnCommand(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
var
  I: Integer;
begin
  Result := not Refuse;
  if Result and not O.Select then
    for I := 0 to High(Returns) do
      if Returns[I].Cmd = O.Ioa then
      begin
        { sent after the ACT_CON the slave is about to queue }
        SetLength(Pending, Length(Pending) + 1);
        Pending[High(Pending)] := O;
        Pending[High(Pending)].Ioa := Returns[I].Mon;
      end;
end;

{ The return information of the commands just executed. }
procedure SendReturns;
var
  I: Integer;
  E: ShortString;
begin
  for I := 0 to High(Pending) do
    if IecSlaveUpdate(Slave, Pending[I].Ioa, Pending[I], True, E) <> res_Ok then
      WriteLn(StdErr, FormatDateTime('hh:nn:ss.zzz ', Now), 'return information to IOA ',
        Pending[I].Ioa, ': ', E);
  Pending := nil;
end;

procedure OnClock(Data: Pointer; const T: tIecTime; OffsetMs: Int64);
begin
  if not Json then
    WriteLn(FormatDateTime('hh:nn:ss.zzz ', Now), 'clock synchronised: station clock ',
      FormatDateTime('yyyy-mm-dd hh:nn:ss.zzz', IecSlaveNow(Slave)), ' (offset ', OffsetMs, ' ms)');
end;

procedure OnBad(Data: Pointer; const Err: ShortString);
begin
  WriteLn(StdErr, FormatDateTime('hh:nn:ss.zzz ', Now), 'malformed ASDU: ', Err);
end;

var
  Chn: pChnVirt;
  E: ShortString;
  Err, Text, TableName: AnsiString;
  L: TStringList;
  I: Integer;
  Deadline: QWord;
  R: tChResult;
begin
  ParseArgs;
  { the table first, in a record of its own: a bad file opens nothing }
  FillChar(Table, SizeOf(Table), 0);
  Table.Params := Params;
  Table.Ca := Ca;
  if PointsFile = '' then
  begin
    Text := DefaultPoints;
    TableName := 'built-in table';
  end
  else
  begin
    if not FileExists(PointsFile) then
      CliUsageError(Cli, 'cannot read the points file', PointsFile);
    L := TStringList.Create;
    try
      L.LoadFromFile(PointsFile);
      Text := L.Text;
    finally
      L.Free;
    end;
    TableName := PointsFile;
  end;
  if not IecLoadPoints(Table, TableName, Text, Err) then
    CliUsageError(Cli, Err, '');
  for I := 0 to High(Returns) do
    if (IecSlaveFind(Table, Returns[I].Cmd) < 0) or (IecSlaveFind(Table, Returns[I].Mon) < 0) then
      CliUsageError(Cli, '--return: IOA ' + IntToStr(Returns[I].Cmd) + ' or ' + IntToStr(Returns[I].Mon) +
        ' is not in the ' + TableName, IntToStr(Returns[I].Cmd) + '=' + IntToStr(Returns[I].Mon));
  { the slave on its channel, not yet opened }
  Chn := CliChannel(Cli, LineParams, ChnFT1_2.cName);
  if IecSlaveInit(Slave, Chn, Params, Ca, E) <> res_Ok then
  begin
    Dispose(Chn, Done);
    CliUsageError(Cli, E, LineParams);
  end;
  for I := 0 to Table.PointCount - 1 do
    IecSlaveAddPoint(Slave, Table.Points[I].Ti, Table.Points[I].Obj, Table.Points[I].Group, E);
  Slave.SelectMs := SelectMs;
  Slave.ClockOffsetMs := ClockOffset;
  Slave.OnAsdu := @Show;
  Slave.OnCommand := @OnCommand;
  Slave.OnClock := @OnClock;
  Slave.OnBad := @OnBad;
  if FilesDir <> '' then
  begin
    IecFileServerInit(Files, Params, Ca);
    Files.Dir := FilesDir;
    IecSlaveServeFiles(Slave, @Files);
  end;
  { the station has initialised: the master learns it (and interrogates) }
  if not CliHas(Cli, 'no-init') then
    IecSlaveEndOfInit(Slave, Coi_PowerOn);
  Chn^.ChOpen;
  if Chn^.ChResult = res_Ok then
    Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then
  begin
    Err := Chn^.ChErrorText;
    Dispose(Chn, Done);
    CliFail(Cli, Err, LineParams, 1);
  end;
  {$IFDEF UNIX}
  { a pty it made (NAM=COM DRV=PTY): the device the master opens }
  if Pos('DRV=PTY', UpperCase(LineParams)) > 0 then
    WriteLn(StdErr, 'iec101slave: PTY ', PtyLastSlave);
  {$ENDIF}
  WriteLn(StdErr, 'iec101slave: ', Chn^.ChGetParam(''), ', ', Slave.PointCount, ' points, CA ', Ca);
  Flush(StdErr);
  {$IFDEF UNIX}
  FpSignal(SIGINT, @OnSignal);
  FpSignal(SIGTERM, @OnSignal);
  {$ENDIF}
  Deadline := ChMsTick + QWord(Seconds) * 1000;
  R := res_Ok;
  while not Stop and ((Seconds = 0) or (ChMsTick < Deadline)) do
  begin
    if Chn^.ChResult <> res_Ok then
    begin
      R := Chn^.ChResult;
      Break;
    end;
    if IecSlaveStep(Slave) then
      SendReturns
    else
      ChnWaitAny(IecSlaveWaitMs(Slave));
  end;
  with Slave do
    WriteLn(StdErr, Format('iec101slave: %d ASDUs received, %d malformed, %d interrogations, '
      + '%d counter interrogations, %d reads, %d commands (%d refused), %d clock syncs, '
      + '%d events, %d negative answers, %d lost', [Asdus, BadAsdus, Interrogations,
      CounterInterrogations, Reads, Commands, Refused, ClockSyncs, Events, Negatives, Overflows]));
  if FilesDir <> '' then
    with Files do
      WriteLn(StdErr, Format('iec101slave: files: %d sent, %d received, %d failed, %d aborted, '
        + '%d bad checksums, %d refused, %d deleted%s', [Sent, Received, Failed, Aborted, BadChecksums, Refused, Deleted,
        BoolToStr(LastError <> '', ' (last: ' + LastError + ')', '')]));
  if R <> res_Ok then
  begin
    Err := Chn^.ChResultStr(R);
    Dispose(Chn, Done);
    CliFail(Cli, 'line failed: ' + Err, '', 1);
  end;
  Dispose(Chn, Done);
end.
