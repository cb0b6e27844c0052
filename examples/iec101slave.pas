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
  opened then). }
program iec101slave;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  Classes, SysUtils, CustApp, ChnTypes, ChnVirt, ChnWait, ChnCom, ChnLoop, ChnTrc, ChnTcp,
  ChnFT1_2, ChnIec101Asdu, ChnIec101Slave, Iec101Print, Iec101Points;

const
  Version = '1.0';
  DefaultPoints =
    '100 M_ME_NB_1 -1'#10'101 M_ME_NB_1 23'#10'102 M_ME_NB_1 2300'#10 +
    '104 M_SP_NA_1 1'#10'105 M_SP_NA_1 0'#10 +
    '300 M_SP_NA_1 1'#10'301 M_SP_NA_1 0'#10'302 M_SP_NA_1 1'#10'303 M_SP_NA_1 0'#10 +
    '304 M_SP_NA_1 1'#10'305 M_SP_NA_1 0'#10'306 M_SP_NA_1 1'#10'307 M_SP_NA_1 0'#10 +
    '500 M_BO_NA_1 0xAAAA'#10'5000 C_SC_NA_1 0'#10;

type
  TSlaveApp = class(TCustomApplication)
  private
    FJson, FRefuse: Boolean;
    FSeconds, FCa, FSelectMs: LongInt;
    FParams: tIecParams;
    FParamStr, FPointsFile: AnsiString;
    procedure Usage(ToErr: Boolean);
    procedure Die(const What: AnsiString; Code: Integer);
    procedure ParseArgs;
  protected
    procedure DoRun; override;
  end;

var
  App: TSlaveApp;
  Stop: Boolean = False;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  Stop := True;
end;
{$ENDIF}

procedure TSlaveApp.Usage(ToErr: Boolean);
var
  T: Text;
begin
  if ToErr then
    T := StdErr
  else
    T := Output;
  WriteLn(T, 'Usage: iec101slave [OPTION]... ''PARAMS'' [--points FILE] [--seconds N]');
  WriteLn(T, 'An IEC 60870-5-101 slave: answers interrogations, counter interrogations, reads,');
  WriteLn(T, 'clock synchronisation and commands from a point table, unbalanced (MS=ON MAS=SLAVE)');
  WriteLn(T, 'or balanced (MS=OFF) as the FT 1.2 parameter string says; prints every object');
  WriteLn(T, 'received or sent.');
  WriteLn(T);
  WriteLn(T, '  --points FILE    point table, one "IOA TYPE VALUE [QUALITY]" per line');
  WriteLn(T, '                   (default: the points of lib60870''s cs101_slave example and');
  WriteLn(T, '                   the single command point 5000)');
  WriteLn(T, '  --seconds N      stop after N seconds (default: at SIGINT or SIGTERM)');
  WriteLn(T, '  --ca N           own common address (default 1)');
  WriteLn(T, '  --cot-size N     octets of the cause of transmission, 1 or 2 (default 2)');
  WriteLn(T, '  --ca-size N      octets of the common address, 1 or 2 (default 2)');
  WriteLn(T, '  --ioa-size N     octets of the information object address, 1..3 (default 3)');
  WriteLn(T, '  --select-ms MS   select-before-operate timeout (default 10000)');
  WriteLn(T, '  --refuse         refuse every command (negative ACT_CON)');
  WriteLn(T, '  --json           one JSON object per line on stdout, nothing else');
  WriteLn(T, '  -h, --help       this text');
  WriteLn(T, '  --version        the version');
  WriteLn(T);
  WriteLn(T, 'Example: iec101slave ''NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E''');
  WriteLn(T, 'Exit status: 0 done, 1 the line cannot be opened or failed, 2 a usage, parameter');
  WriteLn(T, 'or points-file error.');
end;

procedure TSlaveApp.Die(const What: AnsiString; Code: Integer);
begin
  WriteLn(StdErr, 'iec101slave: ', What);
  Halt(Code);
end;

{ Options take "--opt VALUE" and "--opt=VALUE"; the one positional
  argument is the parameter string. (CustApp's CheckOptions takes long
  values only as --opt=VALUE.) }
procedure TSlaveApp.ParseArgs;
var
  I, Eq: Integer;
  A, Opt, Value: AnsiString;
  HasValue: Boolean;

  function Num(Min, Max: LongInt): LongInt;
  begin
    if not TryStrToInt(Value, Result) or (Result < Min) or (Result > Max) then
      Die(Format('--%s takes a number %d..%d (%s)', [Opt, Min, Max, Value]), 2);
  end;

begin
  FSeconds := 0;
  FCa := 1;
  FSelectMs := IecSlaveSelectMs;
  FParams := IecDefaultParams;
  if ParamCount = 0 then
  begin
    Usage(True);
    Halt(2);
  end;
  I := 1;
  while I <= ParamCount do
  begin
    A := Params[I];
    Inc(I);
    if (A = '-h') or (A = '--help') then
    begin
      Usage(False);
      Halt(0);
    end;
    if A = '--version' then
    begin
      WriteLn('iec101slave (Chn) ', Version);
      Halt(0);
    end;
    if Copy(A, 1, 2) <> '--' then
    begin
      if (A <> '') and (A[1] = '-') then
        Die('unknown option (' + A + ')', 2);
      if FParamStr <> '' then
        Die('one parameter string only (' + A + ')', 2);
      FParamStr := A;
      Continue;
    end;
    Opt := Copy(A, 3, MaxInt);
    Eq := Pos('=', Opt);
    HasValue := Eq > 0;
    Value := '';
    if HasValue then
    begin
      Value := Copy(Opt, Eq + 1, MaxInt);
      SetLength(Opt, Eq - 1);
    end;
    if (Opt = 'json') or (Opt = 'refuse') then
    begin
      if HasValue then
        Die('--' + Opt + ' takes no value (' + A + ')', 2);
      if Opt = 'json' then FJson := True else FRefuse := True;
      Continue;
    end;
    if (Opt <> 'points') and (Opt <> 'seconds') and (Opt <> 'ca') and (Opt <> 'cot-size') and
       (Opt <> 'ca-size') and (Opt <> 'ioa-size') and (Opt <> 'select-ms') then
      Die('unknown option (' + A + ')', 2);
    if not HasValue then
    begin
      if I > ParamCount then
        Die('--' + Opt + ' needs a value (' + A + ')', 2);
      Value := Params[I];
      Inc(I);
    end;
    if Opt = 'points' then FPointsFile := Value
    else if Opt = 'seconds' then FSeconds := Num(1, 1000000)
    else if Opt = 'ca' then FCa := Num(0, 65535)
    else if Opt = 'cot-size' then FParams.CotSize := Num(1, 2)
    else if Opt = 'ca-size' then FParams.CaSize := Num(1, 2)
    else if Opt = 'ioa-size' then FParams.IoaSize := Num(1, 3)
    else FSelectMs := Num(1, 3600000);
  end;
  if FParamStr = '' then
    Die('no parameter string (''NAM=FT1_2 ... NAM=COM DEV=...'')', 2);
  if FCa > IecMaxCa(FParams) then
    Die(Format('--ca above %d for a %d-octet common address (%d)', [IecMaxCa(FParams),
      FParams.CaSize, FCa]), 2);
end;

var
  Slave, Table: tIecSlaveStation;

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
    { not decodable (an unknown type): said on stderr, JSON stays clean }
    WriteLn(StdErr, FormatDateTime('hh:nn:ss.zzz ', Now), Arrow, IecAsduText(Slave.Params, A, Len));
    Exit;
  end;
  for I := 0 to H.Count - 1 do
    if IecDecodeObject(Slave.Params, H, A, I, O) = res_Ok then
      if App.FJson then
        WriteLn(IecObjectJson(H, O))
      else
        WriteLn(FormatDateTime('hh:nn:ss.zzz ', Now), Arrow, IecObjectText(H, O));
  Flush(Output);
end;

function OnCommand(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
begin
  Result := not App.FRefuse;
end;

procedure OnClock(Data: Pointer; const T: tIecTime; OffsetMs: Int64);
begin
  if not App.FJson then
    WriteLn(FormatDateTime('hh:nn:ss.zzz ', Now), 'clock synchronised: station clock ',
      FormatDateTime('yyyy-mm-dd hh:nn:ss.zzz', IecSlaveNow(Slave)), ' (offset ', OffsetMs, ' ms)');
end;

procedure OnBad(Data: Pointer; const Err: ShortString);
begin
  WriteLn(StdErr, FormatDateTime('hh:nn:ss.zzz ', Now), 'malformed ASDU: ', Err);
end;

procedure TSlaveApp.DoRun;
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
  Table.Params := FParams;
  Table.Ca := FCa;
  if FPointsFile = '' then
  begin
    Text := DefaultPoints;
    TableName := 'built-in table';
  end
  else
  begin
    if not FileExists(FPointsFile) then
      Die('cannot read the points file (' + FPointsFile + ')', 2);
    L := TStringList.Create;
    try
      L.LoadFromFile(FPointsFile);
      Text := L.Text;
    finally
      L.Free;
    end;
    TableName := FPointsFile;
  end;
  if not IecLoadPoints(Table, TableName, Text, Err) then
    Die(Err, 2);
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam(FParamStr);
  if Chn^.ChResult <> res_Ok then
  begin
    Err := Chn^.ChResultStr(Chn^.ChResult) + ' (' + Chn^.ChParamError + ')';
    Dispose(Chn, Done);
    Die(Err, 2);
  end;
  Chn^.ChOpen;
  if Chn^.ChResult = res_Ok then
    Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then
  begin
    Err := Chn^.ChResultStr(Chn^.ChResult);
    Dispose(Chn, Done);
    Die(Err + ' (' + FParamStr + ')', 1);
  end;
  if IecSlaveInit(Slave, Chn, FParams, FCa, E) <> res_Ok then
  begin
    Dispose(Chn, Done);
    Die(E + ' (' + FParamStr + ')', 2);
  end;
  for I := 0 to Table.PointCount - 1 do
    IecSlaveAddPoint(Slave, Table.Points[I].Ti, Table.Points[I].Obj, Table.Points[I].Group, E);
  Slave.SelectMs := FSelectMs;
  Slave.OnAsdu := @Show;
  Slave.OnCommand := @OnCommand;
  Slave.OnClock := @OnClock;
  Slave.OnBad := @OnBad;
  WriteLn(StdErr, 'iec101slave: ', Chn^.ChGetParam(''), ', ', Slave.PointCount, ' points, CA ', FCa);
  {$IFDEF UNIX}
  FpSignal(SIGINT, @OnSignal);
  FpSignal(SIGTERM, @OnSignal);
  {$ENDIF}
  Deadline := ChMsTick + QWord(FSeconds) * 1000;
  R := res_Ok;
  while not Stop and ((FSeconds = 0) or (ChMsTick < Deadline)) do
  begin
    if Chn^.ChResult <> res_Ok then
    begin
      R := Chn^.ChResult;
      Break;
    end;
    if not IecSlaveStep(Slave) then
      ChnWaitAny(IecSlaveWaitMs(Slave));
  end;
  with Slave do
    WriteLn(StdErr, Format('iec101slave: %d ASDUs received, %d malformed, %d interrogations, '
      + '%d counter interrogations, %d reads, %d commands (%d refused), %d clock syncs, '
      + '%d events, %d negative answers, %d lost', [Asdus, BadAsdus, Interrogations,
      CounterInterrogations, Reads, Commands, Refused, ClockSyncs, Events, Negatives, Overflows]));
  if R <> res_Ok then
  begin
    Err := Chn^.ChResultStr(R);
    Dispose(Chn, Done);
    Die('line failed: ' + Err, 1);
  end;
  Dispose(Chn, Done);
  Terminate;
end;

begin
  App := TSlaveApp.Create(nil);
  App.Run;
  App.Free;
end.
