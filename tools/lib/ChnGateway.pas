{ ChnGateway - the gateway of tools/chngate: its configuration (an INI file
  read with FCL's IniFiles, checked completely before anything is opened:
  every fault is "FILE:LINE: [section] key: what is wrong") and the loop
  that joins the south devices (DF1 PLCs through the tag engine,
  ChnPcccTags) to the north (MQTT through ChnMqtt, an IEC 104 server
  through ChnGate104), all in one ChnWaitAny. docs/chngate.md is the
  reference. }
unit ChnGateway;

{$I chn.inc}

interface

uses
  Classes, SysUtils, ChnTypes, ChnPccc, ChnPcccTags, ChnMqtt, ChnGate104, ChnGateIec101;

const
  GateHealthMs = 10000;     { $health: a new state at once, new counters at most this often }

type
  tGateTagCfg = record
    Name, Address: AnsiString;
    ScanMs: LongInt;
    Writable: Boolean;
  end;

  tGateDeviceCfg = record
    Name     : AnsiString;
    Line     : AnsiString;
    ScanMs   : LongInt;
    Deadband : Double;
    DemoteMs : LongInt;
    DemoteAfter: LongInt;
    TimeoutMs: LongInt;
    MaxRead  : LongInt;      { data bytes of one read (tags merged up to this) }
    Ioa      : LongInt;
    Plc5     : Boolean;      { family = plc5: PLC-5 addresses and commands }
    Points   : LongInt;      { IOAs its tags take on the IEC 104 server }
    TablePoints: LongInt;    { points of the server's table, commands included }
    Tags     : array of tGateTagCfg;
    Iec      : Boolean;      { NAM=FT1_2: an IEC 101 device (ChnGateIec101) }
    Iec101   : tGateIecCfg;
  end;

  tGateConfig = record
    FileName : AnsiString;
    Mqtt     : Boolean;      { an [mqtt] section is there }
    Host     : AnsiString;
    Port     : LongInt;
    Prefix   : AnsiString;
    Qos      : LongInt;
    User, Password: AnsiString;
    Tls      : Boolean;
    CaFile   : AnsiString;
    Queue    : LongInt;
    ClientId : AnsiString;
    KeepAlive: LongInt;
    Iec104   : tGate104Cfg;  { the [iec104] section }
    Devices  : array of tGateDeviceCfg;
  end;

  tGateLog = procedure(const Line: AnsiString);

  { What a device's $health shows, as last published: it is published
    again only when this changed (at most every GateHealthMs), so an idle
    gateway neither builds nor sends it, nor wakes for it. }
  tGateHealthMark = record
    State, Requests, Errors, Retries: LongInt;
  end;

  tGate = record
    Cfg    : tGateConfig;
    Devs   : array of tPcccDevice;
    Iecs   : array of pGateIecDevice;  { the IEC 101 devices (nil for a DF1 one) }
    OpenAt : array of QWord;      { when a device whose line failed is opened again }
    Mqtt   : tMqttClient;
    N104   : tGate104;
    HealthAt: QWord;              { when the changed $health go out; 0: none changed }
    Marks  : array of tGateHealthMark;
    Log    : tGateLog;
    WriteId: LongInt;
    QueuedHigh: LongInt;          { the most messages queued north since the last burst }
  end;

const
  { Messages queued north at once (MQTT and the IEC 104 server's queues)
    that make a burst: a start's first values, a broker's outage, a
    reload. }
  GateBurst = 128;
  { ... and the number it falls to that ends it (a gateway under load
    seldom has nothing queued at the end of a round: a change's message
    waits for its PUBACK) }
  GateBurstLow = 8;

{ Read and check FileName. False with Errors (one line per fault,
  "FILE:LINE: [section] key: what is wrong"); nothing is opened. }
function GateLoadConfig(const FileName: AnsiString; out Cfg: tGateConfig; out Errors: AnsiString): Boolean;
{ The same for a text (FileName only names it in the messages). }
function GateParseConfig(const FileName, Text: AnsiString; out Cfg: tGateConfig;
  out Errors: AnsiString): Boolean;
{ 'N devices, M tags, R reads per scan' of a checked configuration. }
function GateSummary(const Cfg: tGateConfig): AnsiString;

{ Open the north (MQTT, the IEC 104 server) and the devices of Cfg. False
  with Err when the MQTT library is missing or the IEC 104 port cannot be
  taken; a device whose line cannot be opened is down and opened again
  every DEMOTE ms. }
function GateStart(var G: tGate; const Cfg: tGateConfig; out Err: AnsiString): Boolean;
{ A new configuration (SIGHUP): the devices are closed and opened anew,
  the north connections stay (the IEC 104 point table is built anew). }
procedure GateReload(var G: tGate; const Cfg: tGateConfig);
{ One round: step everything, publish what changed, apply commands.
  Returns the ms the program may wait (ChnWaitAny) before the next. }
function GateStep(var G: tGate): LongInt;
{ Publish offline, give the queue up to Ms to go out, close everything. }
procedure GateStop(var G: tGate; Ms: LongInt);
{ The burst rule, Queued the messages queued north now: True once the
  queues fell to GateBurstLow after holding GateBurst or more at once;
  High keeps the most they held since (the last burst, or 0 at first). }
function GateBurstOver(var High: LongInt; Queued: LongInt): Boolean;

{ The payload of a tag: an object with value, quality and ts (docs/chngate.md). }
function GateTagPayload(const T: tPcccTag): AnsiString;
{ The payload of a device's health. }
function GateHealthPayload(const D: tPcccDevice): AnsiString;

implementation

uses
  IniFiles, StrUtils, Math, DynLibs, ChnWait, ChnPcccClient, ChnJson, ChnCli, ChnIec101Slave, ChnIecPointTable;

{ ------------------------------------------------------------ configuration }

type
  tChecker = record
    FileName: AnsiString;
    Lines   : TStringList;
    Errors  : AnsiString;
  end;

{ The line (1-based) of Key in Section, or of the section header when Key
  is ''; 0 when not found. }
function LineOf(const C: tChecker; const Section, Key: AnsiString): LongInt;
var
  I, Eq: LongInt;
  S, Cur: AnsiString;
begin
  Cur := '';
  for I := 0 to C.Lines.Count - 1 do
  begin
    S := Trim(C.Lines[I]);
    if (S <> '') and (S[1] = '[') then
    begin
      Cur := LowerCase(Trim(Copy(S, 2, Pos(']', S) - 2)));
      if (Key = '') and (Cur = LowerCase(Section)) then
        Exit(I + 1);
      Continue;
    end;
    Eq := Pos('=', S);
    if (Key <> '') and (Eq > 0) and (Cur = LowerCase(Section)) and
       (LowerCase(Trim(Copy(S, 1, Eq - 1))) = LowerCase(Key)) then
      Exit(I + 1);
  end;
  Result := 0;
end;

procedure Bad(var C: tChecker; const Section, Key, Why: AnsiString);
var
  Where: AnsiString;
  Line: LongInt;
begin
  Line := LineOf(C, Section, Key);
  if Line = 0 then
    Line := LineOf(C, Section, '');      { a key missing: its section }
  Where := C.FileName + ':' + IntToStr(Line) + ': [' + Section + ']';
  if Key <> '' then
    Where := Where + ' ' + Key;
  C.Errors := C.Errors + Where + ': ' + Why + LineEnding;
end;

{ The structure: sections known, keys known, no key or section twice,
  every line a section, a key = value, a comment or blank. }
procedure CheckLines(var C: tChecker);
const
  MqttKeys = ' host port prefix qos user password tls ca queue client_id keepalive ';
  DeviceKeys = ' line family tags scan write deadband demote fails timeout maxread ioa ' +
    'slaves ca cot_size ca_size ioa_size points gi cycle ';
  Iec104Keys = ' listen ca con k w t0 t1 t2 t3 command_timeout ';
var
  I, Eq: LongInt;
  S, Sec, Key, Keys: AnsiString;
  Seen: TStringList;
begin
  Seen := TStringList.Create;
  try
    Seen.Sorted := True;
    Seen.Duplicates := dupAccept;
    Sec := '';
    Keys := '';
    for I := 0 to C.Lines.Count - 1 do
    begin
      S := Trim(C.Lines[I]);
      if (S = '') or (S[1] in [';', '#']) then
        Continue;
      if S[1] = '[' then
      begin
        if S[Length(S)] <> ']' then
        begin
          C.Errors := C.Errors + Format('%s:%d: "%s": a section header is [NAME]', [C.FileName, I + 1, S]) + LineEnding;
          Continue;
        end;
        Sec := Trim(Copy(S, 2, Length(S) - 2));
        if Seen.IndexOf('[' + LowerCase(Sec)) >= 0 then
          C.Errors := C.Errors + Format('%s:%d: [%s]: the section is there twice', [C.FileName, I + 1, Sec]) + LineEnding;
        Seen.Add('[' + LowerCase(Sec));
        if LowerCase(Sec) = 'mqtt' then
          Keys := MqttKeys
        else if (LowerCase(Copy(Sec, 1, 7)) = 'device ') and (Trim(Copy(Sec, 8, MaxInt)) <> '') then
          Keys := DeviceKeys
        else if LowerCase(Sec) = 'iec104' then
          Keys := Iec104Keys
        else
        begin
          C.Errors := C.Errors + Format('%s:%d: [%s]: unknown section (mqtt, iec104, device NAME)',
            [C.FileName, I + 1, Sec]) + LineEnding;
          Keys := '*';
        end;
        Continue;
      end;
      Eq := Pos('=', S);
      if Eq = 0 then
      begin
        C.Errors := C.Errors + Format('%s:%d: "%s": not KEY = VALUE', [C.FileName, I + 1, S]) + LineEnding;
        Continue;
      end;
      Key := LowerCase(Trim(Copy(S, 1, Eq - 1)));
      if Sec = '' then
        C.Errors := C.Errors + Format('%s:%d: %s: a key before the first section', [C.FileName, I + 1, Key]) + LineEnding
      else if (Keys <> '*') and (Pos(' ' + Key + ' ', Keys) = 0) then
        C.Errors := C.Errors + Format('%s:%d: [%s] %s: unknown key (%s)', [C.FileName, I + 1, Sec, Key,
          Trim(Keys)]) + LineEnding
      else if Seen.IndexOf(LowerCase(Sec) + #0 + Key) >= 0 then
        C.Errors := C.Errors + Format('%s:%d: [%s] %s: given twice', [C.FileName, I + 1, Sec, Key]) + LineEnding;
      Seen.Add(LowerCase(Sec) + #0 + Key);
    end;
  finally
    Seen.Free;
  end;
end;

function Num(var C: tChecker; Ini: TMemIniFile; const Sec, Key: AnsiString; Min, Max, Default: LongInt): LongInt;
var
  S: AnsiString;
  Code: LongInt;
begin
  Result := Default;
  S := Trim(Ini.ReadString(Sec, Key, ''));
  if S = '' then
    Exit;
  Val(S, Result, Code);
  if (Code <> 0) or (Result < Min) or (Result > Max) then
  begin
    Bad(C, Sec, Key, Format('"%s" is not a whole number %d..%d', [S, Min, Max]));
    Result := Default;
  end;
end;

function Flag(var C: tChecker; Ini: TMemIniFile; const Sec, Key: AnsiString): Boolean;
var
  S: AnsiString;
begin
  S := LowerCase(Trim(Ini.ReadString(Sec, Key, '')));
  Result := (S = 'on') or (S = 'yes') or (S = 'true') or (S = '1');
  if not Result and (S <> '') and (S <> 'off') and (S <> 'no') and (S <> 'false') and (S <> '0') then
    Bad(C, Sec, Key, '"' + S + '" is not on or off');
end;

procedure ReadMqtt(var C: tChecker; Ini: TMemIniFile; var Cfg: tGateConfig);
const
  S = 'mqtt';
begin
  Cfg.Mqtt := Ini.SectionExists(S);
  Cfg.Host := Trim(Ini.ReadString(S, 'host', '127.0.0.1'));
  Cfg.Tls := Flag(C, Ini, S, 'tls');
  if Cfg.Tls then
    Cfg.Port := Num(C, Ini, S, 'port', 1, 65535, 8883)
  else
    Cfg.Port := Num(C, Ini, S, 'port', 1, 65535, 1883);
  Cfg.Prefix := Trim(Ini.ReadString(S, 'prefix', ''));
  Cfg.Qos := Num(C, Ini, S, 'qos', 0, 1, 1);
  Cfg.User := Ini.ReadString(S, 'user', '');
  Cfg.Password := Ini.ReadString(S, 'password', '');
  Cfg.CaFile := Trim(Ini.ReadString(S, 'ca', ''));
  Cfg.Queue := Num(C, Ini, S, 'queue', 1, 10000000, MqttQueueDefault);
  Cfg.ClientId := Trim(Ini.ReadString(S, 'client_id', ''));
  Cfg.KeepAlive := Num(C, Ini, S, 'keepalive', 5, 3600, MqttKeepAliveDefault);
  if not Cfg.Mqtt then
    Exit;
  if Cfg.Prefix = '' then
    Bad(C, S, 'prefix', 'missing: the first level of every topic (plant)')
  else if (Pos('+', Cfg.Prefix) > 0) or (Pos('#', Cfg.Prefix) > 0) or (Cfg.Prefix[Length(Cfg.Prefix)] = '/') then
    Bad(C, S, 'prefix', '"' + Cfg.Prefix + '": no wildcards (+ #) and no trailing /');
  if Cfg.Host = '' then
    Bad(C, S, 'host', 'empty');
  if Cfg.Tls and (Cfg.CaFile <> '') and not FileExists(Cfg.CaFile) and not DirectoryExists(Cfg.CaFile) then
    Bad(C, S, 'ca', '"' + Cfg.CaFile + '": no such file or directory');
  if (Cfg.Password <> '') and (Cfg.User = '') then
    Bad(C, S, 'password', 'given without user');
end;

procedure ReadIec104(var C: tChecker; Ini: TMemIniFile; var Cfg: tGateConfig);
const
  S = 'iec104';
  { the keys NAM=IEC104 takes as they are, and their largest values }
  Keys: array[0..6] of string[3] = ('con', 'k', 'w', 't0', 't1', 't2', 't3');
  Most: array[0..6] of LongInt = (16, 32767, 32767, 255, 255, 255, 172800);
var
  N: tGate104Cfg;
  Why: AnsiString;
  I, V: LongInt;
begin
  N.Present := Ini.SectionExists(S);
  N.Listen := Trim(Ini.ReadString(S, 'listen', ''));
  N.Ca := Num(C, Ini, S, 'ca', 1, 65534, 1);
  N.CommandMs := Num(C, Ini, S, 'command_timeout', 100, 600000, Gate104CommandMsDefault);
  N.Params := '';
  for I := 0 to High(Keys) do
  begin
    V := Num(C, Ini, S, Keys[I], 1, Most[I], 0);
    if V > 0 then
      N.Params := N.Params + UpperCase(Keys[I]) + '=' + IntToStr(V) + ' ';
  end;
  Cfg.Iec104 := N;
  if not N.Present then
    Exit;
  if Pos(':', N.Listen) = 0 then
    Bad(C, S, 'listen', 'missing or not HOST:PORT (0.0.0.0:2404)')
  else
  begin
    Why := CliParamsProblem(Gate104Line(N), 'IEC104');
    if Why <> '' then
      Bad(C, S, '', Why);
  end;
end;

{ The north IOAs an IEC 101 device's configuration gives (its points=
  and write= points at ioa= + IOA, commands at ioa= + CMDIOA) against the
  DF1 devices' ranges and the other RTUs' points: a clash is refused with
  the key that gave the point. (An RTU's other points are learned at run
  time: ChnGate104 refuses a clash then.) }
procedure CheckIecIoas(var C: tChecker; const Cfg: tGateConfig);
type
  tTaken = record
    Ioa: Int64;
    Cmd: Boolean;
    What: AnsiString;
  end;
var
  Taken: array of tTaken;
  I, J, K: LongInt;
  N: Int64;
  Cmd: Boolean;
  What: AnsiString;

  function Clash: AnsiString;
  var
    D: LongInt;
    T: tTaken;
  begin
    for D := 0 to High(Cfg.Devices) do
      with Cfg.Devices[D] do
        if not Iec and (Points > 0) and (N >= Ioa) and (N <= Ioa + Points - 1) then
          Exit(Format('falls in device %s''s IOAs %d..%d', [Name, Ioa, Ioa + Points - 1]));
    for T in Taken do
      if (T.Ioa = N) and (T.Cmd = Cmd) then
        Exit('is ' + T.What + ' already');
    Result := '';
  end;

begin
  Taken := nil;
  for I := 0 to High(Cfg.Devices) do
    if Cfg.Devices[I].Iec then
      with Cfg.Devices[I], Iec101 do
        for J := 0 to High(Points) do
          for Cmd in [False, True] do
          begin
            if Cmd and not Points[J].Writable then
              Continue;
            if Cmd then
              N := Int64(IoaOffset) + Points[J].CmdIoa
            else
              N := Int64(IoaOffset) + Points[J].Ioa;
            What := Points[J].Name;
            if What = '' then
              What := IntToStr(Points[J].Addr) + ':' + IntToStr(Points[J].Ioa);
            What := Format('device %s''s %s %s (%d + %d)', [Name, IfThen(Cmd, 'command IOA of', 'point'), What,
              IoaOffset, N - IoaOffset]);
            if N > 16777215 then
            begin
              Bad(C, 'device ' + Name, IfThen(Cmd or (Points[J].Name = ''), 'write', 'points'),
                Format('%s: IOA %d runs past 16777215', [What, N]));
              Continue;
            end;
            if Clash <> '' then
              Bad(C, 'device ' + Name, IfThen(Cmd or (Points[J].Name = ''), 'write', 'points'),
                Format('%s: IEC 104 IOA %d %s', [What, N, Clash]));
            K := Length(Taken);
            SetLength(Taken, K + 1);
            Taken[K].Ioa := N;
            Taken[K].Cmd := Cmd;
            Taken[K].What := What;
          end;
end;

{ The IEC 104 IOAs of the devices: within 1..16777215, none twice, the
  table within the slave's points. }
procedure CheckIoas(var C: tChecker; const Cfg: tGateConfig);
var
  I, J, Total: LongInt;
begin
  Total := 0;
  for I := 0 to High(Cfg.Devices) do
    with Cfg.Devices[I] do
    begin
      Inc(Total, TablePoints);
      if Ioa + Points - 1 > 16777215 then
        Bad(C, 'device ' + Name, 'ioa', Format('%d + %d points runs past IOA 16777215', [Ioa, Points]));
      for J := 0 to I - 1 do
        if (Points > 0) and (Cfg.Devices[J].Points > 0) and (Ioa <= Cfg.Devices[J].Ioa + Cfg.Devices[J].Points - 1) and
           (Cfg.Devices[J].Ioa <= Ioa + Points - 1) then
          Bad(C, 'device ' + Name, 'ioa', Format('IOAs %d..%d overlap those of device %s (%d..%d)',
            [Ioa, Ioa + Points - 1, Cfg.Devices[J].Name, Cfg.Devices[J].Ioa,
             Cfg.Devices[J].Ioa + Cfg.Devices[J].Points - 1]));
    end;
  CheckIecIoas(C, Cfg);
  if Total > IecSlaveMaxPoints then
    C.Errors := C.Errors + Format('%s:%d: [iec104]: %d points (a writable tag''s commands count 2), more than %d',
      [C.FileName, LineOf(C, 'iec104', ''), Total, IecSlaveMaxPoints]) + LineEnding;
end;

function Deadband(var C: tChecker; Ini: TMemIniFile; const Sec: AnsiString): Double;
var
  W: AnsiString;
  Code: LongInt;
begin
  Result := 0;
  W := Trim(Ini.ReadString(Sec, 'deadband', ''));
  if W = '' then
    Exit;
  Val(W, Result, Code);
  if (Code <> 0) or (Result < 0) then
  begin
    Bad(C, Sec, 'deadband', '"' + W + '" is not a number 0 or above');
    Result := 0;
  end;
end;

const
  IecOnlyKeys: array[0..7] of AnsiString = ('slaves', 'ca', 'cot_size', 'ca_size', 'ioa_size', 'points',
    'gi', 'cycle');

{ An IEC 101 device: the master's options; the point entries and the
  line are checked by ChnGateIec101. }
procedure ReadIecDevice(var C: tChecker; Ini: TMemIniFile; const Sec: AnsiString; var D: tGateDeviceCfg);
var
  K, W, Err: AnsiString;
  A: LongInt;
  LineOk: Boolean;
begin
  D.Iec := True;
  for K in ['tags', 'scan', 'fails', 'family', 'maxread'] do
    if Ini.ValueExists(Sec, K) then
      Bad(C, Sec, K, 'not for an IEC 101 device (the master demotes a slave by its own back-off)');
  with D.Iec101 do
  begin
    Params.CotSize := Num(C, Ini, Sec, 'cot_size', 1, 2, 2);
    Params.CaSize := Num(C, Ini, Sec, 'ca_size', 1, 2, 2);
    Params.IoaSize := Num(C, Ini, Sec, 'ioa_size', 1, 3, 3);
    Ca := Num(C, Ini, Sec, 'ca', 0, 65535, 1);
    IoaOffset := Num(C, Ini, Sec, 'ioa', 0, 16777215, 0);
    TimeoutMs := Num(C, Ini, Sec, 'timeout', 10, 60000, 1000);
    DemoteMs := Num(C, Ini, Sec, 'demote', 100, 3600000, TagDemoteMsDefault);
    CycleMs := Num(C, Ini, Sec, 'cycle', 10, 3600000, 100);
    GiMs := Num(C, Ini, Sec, 'gi', 0, 86400000, 0);
    Deadband := ChnGateway.Deadband(C, Ini, Sec);
    Slaves := nil;
    for W in Trim(Ini.ReadString(Sec, 'slaves', '')).Split([' ', #9, ','], TStringSplitOptions.ExcludeEmpty) do
    begin
      A := StrToIntDef(W, -1);
      if (A < 0) or (A > 65535) then
        Bad(C, Sec, 'slaves', '"' + W + '" is not a link address 0..65535')
      else
      begin
        SetLength(Slaves, Length(Slaves) + 1);
        Slaves[High(Slaves)] := A;
      end;
    end;
    Points := nil;
    LineOk := GateIecCheckLine(D.Line, D.Iec101, Err);
    if not LineOk then
    begin
      if Pos('slave ', Err) = 1 then
        Bad(C, Sec, 'slaves', Err)
      else if Pos('ca ', Err) = 1 then
        Bad(C, Sec, 'ca', Err)
      else
        Bad(C, Sec, 'line', Err);
      Exit;
    end;
    if not GateIecParsePoints(Ini.ReadString(Sec, 'points', ''), D.Iec101, Err) then
      Bad(C, Sec, 'points', Err);
    if not GateIecParseWrite(Ini.ReadString(Sec, 'write', ''), D.Iec101, Err) then
      Bad(C, Sec, 'write', Err);
  end;
end;

{ A DF1 device's numbers, PLC family, deadband and line. }
procedure ReadDf1Settings(var C: tChecker; Ini: TMemIniFile; const Sec: AnsiString;
  var D: tGateDeviceCfg);
var
  W, Why: AnsiString;
begin
  D.ScanMs := Num(C, Ini, Sec, 'scan', 10, 3600000, TagScanMsDefault);
  D.DemoteMs := Num(C, Ini, Sec, 'demote', 100, 3600000, TagDemoteMsDefault);
  D.DemoteAfter := Num(C, Ini, Sec, 'fails', 1, 1000, TagDemoteAfterDefault);
  D.TimeoutMs := Num(C, Ini, Sec, 'timeout', 10, 60000, 1000);
  D.MaxRead := Num(C, Ini, Sec, 'maxread', 2, TagMaxReadDefault, TagMaxReadDefault);
  D.Ioa := Num(C, Ini, Sec, 'ioa', 1, 16777215, 1);
  W := LowerCase(Trim(Ini.ReadString(Sec, 'family', 'slc')));
  D.Plc5 := W = 'plc5';
  if (W <> 'slc') and not D.Plc5 then
    Bad(C, Sec, 'family', '"' + W + '" is neither slc (SLC 500, MicroLogix) nor plc5');
  D.Deadband := Deadband(C, Ini, Sec);
  if D.Line = '' then
    Bad(C, Sec, 'line', 'missing: the parameter string of the device''s line (NAM=DF1 ... NAM=COM ...)')
  else if UpperCase(ExtractWord(1, D.Line, [' '])) <> 'NAM=DF1' then
    Bad(C, Sec, 'line', '"' + ExtractWord(1, D.Line, [' ']) + '": the line starts with NAM=DF1 or NAM=FT1_2')
  else
  begin
    Why := CliParamsProblem(D.Line, 'DF1');
    if Why <> '' then
      Bad(C, Sec, 'line', Why);
  end;
end;

{ One word of tags = : [NAME=]ADDRESS[@MS], added to Probe and as D.Tags[Count]
  (Count then counts it). }
procedure ReadDf1Tag(var C: tChecker; const Sec, W: AnsiString; var D: tGateDeviceCfg; var Count: LongInt;
  var Probe: tPcccDevice);
var
  Name, Addr: AnsiString;
  P, At, Code, I, K, Scan: LongInt;
  E: ShortString;
begin
  Name := '';
  Addr := W;
  P := Pos('=', Addr);
  if P > 0 then
  begin
    Name := Copy(Addr, 1, P - 1);
    Addr := Copy(Addr, P + 1, MaxInt);
    if (Name = '') or (Pos('/', Name) > 0) or (Pos('+', Name) > 0) or (Pos('#', Name) > 0) then
      Bad(C, Sec, 'tags', '"' + W + '": a tag name is one topic level (not empty, no / + #)');
  end;
  Scan := D.ScanMs;
  At := Pos('@', Addr);
  if At > 0 then
  begin
    Val(Copy(Addr, At + 1, MaxInt), Scan, Code);
    if (Code <> 0) or (Scan < 10) or (Scan > 3600000) then
    begin
      Bad(C, Sec, 'tags', '"' + W + '": the scan after @ is not a whole number 10..3600000 (ms)');
      Scan := D.ScanMs;
    end;
    Addr := Copy(Addr, 1, At - 1);
  end;
  if TagAdd(Probe, Name, Addr, Scan, D.Deadband, False, E) <> res_Ok then
  begin
    Bad(C, Sec, 'tags', E);
    Exit;
  end;
  Name := Probe.Tags[High(Probe.Tags)].Name;
  for I := 0 to Count - 1 do
    if D.Tags[I].Name = Name then
      Bad(C, Sec, 'tags', '"' + Name + '" is there twice');
  K := Count;
  Inc(Count);
  if SameText(Name, Addr) then
    Addr := Name;                   { one string for both (800 tags: 37 KB less) }
  D.Tags[K].Name := Name;
  D.Tags[K].Address := Addr;
  D.Tags[K].ScanMs := Scan;
  D.Tags[K].Writable := False;
end;

{ write = : the writable tags, by name or address. }
procedure ReadDf1Write(var C: tChecker; Ini: TMemIniFile; const Sec: AnsiString;
  var D: tGateDeviceCfg; var Probe: tPcccDevice);
var
  W: AnsiString;
  K: LongInt;
begin
  for W in Trim(Ini.ReadString(Sec, 'write', '')).Split([' ', #9], TStringSplitOptions.ExcludeEmpty) do
  begin
    K := TagFind(Probe, W);
    if K < 0 then
      Bad(C, Sec, 'write', '"' + W + '" is none of the device''s tags')
    else if (Probe.Tags[K].Kind = pvString) or (PcccPlanValues(Probe.Tags[K].Plan) <> 1) then
      Bad(C, Sec, 'write', '"' + W + '": only a tag of one integer, bit or float can be written')
    else
    begin
      D.Tags[K].Writable := True;
      Probe.Tags[K].Writable := True;
    end;
  end;
end;

procedure ReadDevice(var C: tChecker; Ini: TMemIniFile; const Sec: AnsiString; var D: tGateDeviceCfg;
  var Probe: tPcccDevice);
var
  Words: TStringArray;
  W: AnsiString;
  Count: LongInt;
begin
  D.Name := Trim(Copy(Sec, 8, MaxInt));
  if (Pos('/', D.Name) > 0) or (Pos('+', D.Name) > 0) or (Pos('#', D.Name) > 0) or (Pos(' ', D.Name) > 0) then
    Bad(C, Sec, '', '"' + D.Name + '": a device name is one topic level (no / + # or blanks)');
  D.Line := Trim(Ini.ReadString(Sec, 'line', ''));
  if UpperCase(ExtractWord(1, D.Line, [' '])) = 'NAM=FT1_2' then
  begin
    ReadIecDevice(C, Ini, Sec, D);
    Exit;
  end;
  for W in IecOnlyKeys do
    if Ini.ValueExists(Sec, W) then
      Bad(C, Sec, W, 'only for an IEC 101 device (line = NAM=FT1_2 ...)');
  ReadDf1Settings(C, Ini, Sec, D);
  { tags: [NAME=]ADDRESS[@MS] }
  D.Tags := nil;
  Words := Trim(Ini.ReadString(Sec, 'tags', '')).Split([' ', #9], TStringSplitOptions.ExcludeEmpty);
  if Length(Words) = 0 then
    Bad(C, Sec, 'tags', 'missing: the tags to read (N7:0[10] speed=F8:2 B3:0/5@500 ...)');
  TagDeviceInit(Probe, D.Name);
  if D.Plc5 then
    TagDevicePlc5(Probe);
  { room for every word at once (one at a time moved them on every tag) }
  SetLength(D.Tags, Length(Words));
  Count := 0;
  for W in Words do
    ReadDf1Tag(C, Sec, W, D, Count, Probe);
  SetLength(D.Tags, Count);
  ReadDf1Write(C, Ini, Sec, D, Probe);
  D.Points := Gate104DevicePoints(Probe);
  D.TablePoints := Gate104TablePoints(Probe);
end;

function GateParseConfig(const FileName, Text: AnsiString; out Cfg: tGateConfig;
  out Errors: AnsiString): Boolean;
var
  C: tChecker;
  Ini: TMemIniFile;
  Secs: TStringList;
  Sec: AnsiString;
  Probe: tPcccDevice;
  I: LongInt;
begin
  Finalize(Cfg);
  FillChar(Cfg, SizeOf(Cfg), 0);
  Cfg.FileName := FileName;
  C.FileName := FileName;
  C.Errors := '';
  C.Lines := TStringList.Create;
  Secs := TStringList.Create;
  Ini := nil;
  FillChar(Probe, SizeOf(Probe), 0);
  try
    C.Lines.Text := Text;
    CheckLines(C);
    Ini := TMemIniFile.Create('');
    Ini.SetStrings(C.Lines);
    ReadMqtt(C, Ini, Cfg);
    ReadIec104(C, Ini, Cfg);
    Ini.ReadSections(Secs);
    for Sec in Secs do
      if (LowerCase(Copy(Sec, 1, 7)) = 'device ') and (Trim(Copy(Sec, 8, MaxInt)) <> '') then
      begin
        SetLength(Cfg.Devices, Length(Cfg.Devices) + 1);
        ReadDevice(C, Ini, Sec, Cfg.Devices[High(Cfg.Devices)], Probe);
        for I := 0 to High(Cfg.Devices) - 1 do
          if SameText(Cfg.Devices[I].Name, Cfg.Devices[High(Cfg.Devices)].Name) then
            Bad(C, Sec, '', 'a device of this name is there twice');
        TagDeviceDone(Probe);
      end;
    if (C.Errors = '') and (Length(Cfg.Devices) = 0) then
      C.Errors := FileName + ':0: no [device NAME] section: nothing to read' + LineEnding;
    if Cfg.Iec104.Present then
      CheckIoas(C, Cfg);
    if (C.Errors = '') and not Cfg.Mqtt and not Cfg.Iec104.Present then
      C.Errors := FileName + ':0: no [mqtt] or [iec104] section: nowhere to publish' + LineEnding;
  finally
    Ini.Free;
    Secs.Free;
    C.Lines.Free;
  end;
  Errors := C.Errors;
  Result := Errors = '';
end;

function GateLoadConfig(const FileName: AnsiString; out Cfg: tGateConfig; out Errors: AnsiString): Boolean;
var
  L: TStringList;
begin
  L := TStringList.Create;
  try
    try
      L.LoadFromFile(FileName);
    except
      on E: Exception do
      begin
        Finalize(Cfg);
        FillChar(Cfg, SizeOf(Cfg), 0);
        Errors := FileName + ': cannot be read: ' + E.Message + LineEnding;
        Exit(False);
      end;
    end;
    Result := GateParseConfig(FileName, L.Text, Cfg, Errors);
  finally
    L.Free;
  end;
end;

{ The tag engine of configuration device D (not opened). }
procedure BuildDevice(var Dev: tPcccDevice; const D: tGateDeviceCfg);
var
  T: tGateTagCfg;
  E: ShortString;
  Name: AnsiString;
begin
  TagDeviceInit(Dev, D.Name);
  if D.Plc5 then
    TagDevicePlc5(Dev);
  Dev.DemoteMs := D.DemoteMs;
  Dev.DemoteAfter := D.DemoteAfter;
  Dev.MaxRead := D.MaxRead;
  for T in D.Tags do
  begin
    Name := T.Name;
    if SameText(Name, T.Address) then
      Name := '';
    TagAdd(Dev, Name, T.Address, T.ScanMs, D.Deadband, T.Writable, E);
  end;
  TagDeviceStart(Dev);
end;

function GateSummary(const Cfg: tGateConfig): AnsiString;
var
  D: tGateDeviceCfg;
  Dev: tPcccDevice;
  Tags, Reads, Slaves: LongInt;
begin
  Tags := 0;
  Reads := 0;
  Slaves := 0;
  FillChar(Dev, SizeOf(Dev), 0);
  for D in Cfg.Devices do
  begin
    BuildDevice(Dev, D);
    Inc(Tags, Length(Dev.Tags));
    Inc(Reads, TagDeviceReads(Dev));
    TagDeviceDone(Dev);
    if D.Iec then
      Inc(Slaves, Length(D.Iec101.Slaves));
  end;
  Result := Format('%d devices, %d tags, %d reads per scan', [Length(Cfg.Devices), Tags, Reads]);
  if Slaves > 0 then
    Result := Result + Format(', %d IEC 101 slaves', [Slaves]);
  if Cfg.Iec104.Present then
  begin
    Tags := 0;
    for D in Cfg.Devices do
      Inc(Tags, D.Points);
    Result := Result + Format(', %d IEC 104 points', [Tags]);
  end;
end;

{ ------------------------------------------------------------ payloads }

function ValueText(const T: tPcccTag; K: LongInt): AnsiString;
begin
  if TagIsBit(T) then
    Result := IfThen(T.Values[K] <> 0, 'true', 'false')
  else if T.Kind = pvFloat then
    Result := JsonNumber(T.Values[K], 7)
  else
    Result := JsonNumber(T.Values[K]);
end;

function GateTagPayload(const T: tPcccTag): AnsiString;
var
  V: AnsiString;
  K: LongInt;
begin
  if not T.Known then
    V := 'null'
  else if T.Kind = pvString then
    V := JsonString(T.Text)
  else if Length(T.Values) = 1 then
    V := ValueText(T, 0)
  else
  begin
    V := '[';
    for K := 0 to High(T.Values) do
    begin
      if K > 0 then
        V := V + ',';
      V := V + ValueText(T, K);
    end;
    V := V + ']';
  end;
  Result := '{"value":' + V + ',"quality":"' + TagQualityNames[T.Quality] + '","ts":"' +
    JsonTime(T.TimeMs) + '"}';
end;

function GateHealthPayload(const D: tPcccDevice): AnsiString;
begin
  Result := Format('{"state":"%s","requests":%d,"errors":%d,"retries":%d,"reads_per_scan":%d,' +
    '"last_error":%s}', [TagStateNames[D.State], D.Requests, D.Errors, D.Retries,
    TagDeviceReads(D), JsonString(D.LastError)]);
end;

{ ------------------------------------------------------------ running }

procedure Say(const G: tGate; const S: AnsiString);
begin
  if Assigned(G.Log) then
    G.Log(S);
end;

function Topic(const G: tGate; const Dev, Tag: AnsiString): AnsiString;
begin
  Result := G.Cfg.Prefix + '/' + Dev + '/' + Tag;
end;

procedure OpenDevice(var G: tGate; I: LongInt);
var
  R: tChResult;
begin
  R := PcccOpen(G.Devs[I].Client, G.Cfg.Devices[I].Line + ' IDL=0');
  if R <> res_Ok then
  begin
    G.Devs[I].LastError := 'cannot open the line: ' + G.Devs[I].Client.Err;
    if G.Devs[I].State <> tdDown then
    begin
      G.Devs[I].State := tdDown;
      G.Devs[I].StateChanged := True;
    end;
    G.OpenAt[I] := GetTickCount64 + QWord(G.Devs[I].DemoteMs);
    Say(G, G.Cfg.Devices[I].Name + ': ' + G.Devs[I].LastError);
  end
  else
  begin
    if G.Cfg.Devices[I].Plc5 then
      TagDevicePlc5(G.Devs[I]);     { PcccOpen set the client up anew }
    G.Devs[I].Client.TimeoutMs := G.Cfg.Devices[I].TimeoutMs;
    G.OpenAt[I] := 0;
  end;
end;

procedure OpenDevices(var G: tGate);
var
  I: LongInt;
begin
  SetLength(G.Devs, Length(G.Cfg.Devices));
  SetLength(G.OpenAt, Length(G.Cfg.Devices));
  SetLength(G.Iecs, Length(G.Cfg.Devices));
  G.Marks := nil;
  SetLength(G.Marks, Length(G.Cfg.Devices));
  G.HealthAt := 0;
  for I := 0 to High(G.Devs) do
  begin
    BuildDevice(G.Devs[I], G.Cfg.Devices[I]);
    G.Devs[I].StateChanged := True;      { a first $health }
    G.Iecs[I] := nil;
    if G.Cfg.Devices[I].Iec then
      G.Iecs[I] := GateIecNew(G.Cfg.Devices[I].Name, G.Cfg.Devices[I].Line, G.Cfg.Devices[I].Iec101)
    else
      OpenDevice(G, I);
  end;
end;

{ The IEC 104 point table of the devices (when the server runs). }
procedure Build104(var G: tGate; Reload: Boolean);
var
  Bases: array of LongInt;
  I: LongInt;
begin
  SetLength(Bases, Length(G.Devs));
  for I := 0 to High(Bases) do
    Bases[I] := G.Cfg.Devices[I].Ioa;
  Gate104Build(G.N104, G.Devs, Bases, Reload);
end;

{ Publish on MQTT, when the gateway has it. }
procedure Publish(var G: tGate; const Topic_, Payload: AnsiString; Retain: Boolean);
begin
  if G.Cfg.Mqtt then
    MqttPublish(G.Mqtt, Topic_, Payload, Retain);
end;

procedure CloseDevices(var G: tGate);
var
  I: LongInt;
begin
  for I := 0 to High(G.Devs) do
  begin
    TagDeviceDone(G.Devs[I]);
    GateIecFree(G.Iecs[I]);
  end;
  G.Devs := nil;
  G.OpenAt := nil;
  G.Iecs := nil;
end;

function GateStart(var G: tGate; const Cfg: tGateConfig; out Err: AnsiString): Boolean;
begin
  G.Cfg := Cfg;
  G.WriteId := 0;
  MqttInit(G.Mqtt);
  G.Mqtt.Host := Cfg.Host;
  G.Mqtt.Port := Cfg.Port;
  G.Mqtt.User := Cfg.User;
  G.Mqtt.Password := Cfg.Password;
  G.Mqtt.Tls := Cfg.Tls;
  G.Mqtt.CaFile := Cfg.CaFile;
  G.Mqtt.Qos := Cfg.Qos;
  G.Mqtt.QueueMax := Cfg.Queue;
  G.Mqtt.ClientId := Cfg.ClientId;
  G.Mqtt.KeepAlive := Cfg.KeepAlive;
  G.Mqtt.WillTopic := Cfg.Prefix + '/$gateway/status';
  G.Mqtt.WillPayload := 'offline';
  G.Mqtt.OnlinePayload := 'online';
  Result := not Cfg.Mqtt or MqttOpen(G.Mqtt, Err);
  if not Result then
    Exit;
  if Cfg.Mqtt then
  begin
    { PREFIX/DEVICE/TAG/set, also for tags with a '/' (B3:0/5) }
    MqttSubscribe(G.Mqtt, Cfg.Prefix + '/+/+/set');
    MqttSubscribe(G.Mqtt, Cfg.Prefix + '/+/+/+/set');
  end;
  if Cfg.Iec104.Present and not Gate104Open(G.N104, Cfg.Iec104, G.Log, Err) then
  begin
    MqttClose(G.Mqtt);
    Exit(False);
  end;
  OpenDevices(G);
  Build104(G, False);
end;

procedure GateReload(var G: tGate; const Cfg: tGateConfig);
begin
  CloseDevices(G);
  G.Cfg.Devices := Cfg.Devices;
  OpenDevices(G);
  Build104(G, True);
end;

procedure Refuse(var G: tGate; const Topic_, Why: AnsiString);
begin
  Say(G, 'refused ' + Topic_ + ': ' + Why);
  Publish(G, G.Cfg.Prefix + '/$gateway/error',
    '{"topic":' + JsonString(Topic_) + ',"error":' + JsonString(Why) + '}', False);
end;

procedure WriteTag(var G: tGate; const Topic_: AnsiString; Dev, Tag: LongInt; V: Double); forward;

{ A message on PREFIX/DEVICE/TAG/set. }
procedure Command(var G: tGate; const M: tMqttMessage);
var
  Rest, DevName, TagName, Err: AnsiString;
  I, Dev, Tag: LongInt;
  V: Double;
begin
  Rest := Copy(M.Topic, Length(G.Cfg.Prefix) + 2, MaxInt);
  Rest := Copy(Rest, 1, Length(Rest) - 4);       { without /set }
  I := Pos('/', Rest);
  DevName := Copy(Rest, 1, I - 1);
  TagName := Copy(Rest, I + 1, MaxInt);
  Dev := -1;
  for I := 0 to High(G.Devs) do
    if G.Cfg.Devices[I].Name = DevName then
      Dev := I;
  Tag := -1;
  if (Dev >= 0) and (G.Iecs[Dev] <> nil) then
    Tag := GateIecFind(G.Iecs[Dev], TagName)
  else if Dev >= 0 then
    Tag := TagFind(G.Devs[Dev], TagName);
  if Dev < 0 then
    Refuse(G, M.Topic, 'no device "' + DevName + '"')
  else if (Tag < 0) and (G.Iecs[Dev] <> nil) then
    Refuse(G, M.Topic, 'no point "' + TagName + '" on ' + DevName)
  else if Tag < 0 then
    Refuse(G, M.Topic, 'no tag "' + TagName + '" on ' + DevName)
  else if not JsonParseValue(M.Payload, V, Err) then
    Refuse(G, M.Topic, Err)
  else
    WriteTag(G, M.Topic, Dev, Tag, V);
end;

procedure WriteTag(var G: tGate; const Topic_: AnsiString; Dev, Tag: LongInt; V: Double);
var
  E: ShortString;
  Err: AnsiString;
begin
  Inc(G.WriteId);
  if G.Iecs[Dev] <> nil then
  begin
    if not GateIecWrite(G.Iecs[Dev], Tag, V, G.WriteId, Err) then
      Refuse(G, Topic_, Err);
  end
  else if not TagDeviceWrite(G.Devs[Dev], Tag, V, G.WriteId, E) then
    Refuse(G, Topic_, E);
end;

{ MqttStepAt, and a log line when the connection came or went (why, and
  when it is tried again). }
procedure StepMqtt(var G: tGate; Now_: QWord);
begin
  MqttStepAt(G.Mqtt, Now_);
  if not G.Mqtt.Changed then
    Exit;
  if G.Mqtt.State = msConnected then
    Say(G, Format('MQTT %s:%d: connected', [G.Mqtt.Host, G.Mqtt.Port]))
  else if G.Mqtt.State = msWaiting then
    Say(G, Format('MQTT: %s (again in %d ms)', [G.Mqtt.LastError, ChnWaitLeft(G.Mqtt.RetryAt)]));
end;

function HealthMark(const G: tGate; I: LongInt): tGateHealthMark;
var
  S: tIecTableSlave;
begin
  FillChar(Result, SizeOf(Result), 0);
  if G.Iecs[I] = nil then
  begin
    Result.State := Ord(G.Devs[I].State);
    Result.Requests := G.Devs[I].Requests;
    Result.Errors := G.Devs[I].Errors;
    Result.Retries := G.Devs[I].Retries;
    Exit;
  end;
  Result.State := Ord(GateIecState(G.Iecs[I]));
  for S in G.Iecs[I]^.T.Slaves do
  begin
    Inc(Result.Requests, S.Polls);
    Inc(Result.Errors, S.Errors);
    Inc(Result.Retries, S.Retries);
  end;
end;

{ Device I's $health: published now when its state changed (Changed), or
  at G.HealthAt (Due) when its counters did; else, when they changed, the
  time it goes out is set. }
procedure StepHealth(var G: tGate; I: LongInt; Changed, Due: Boolean; Now_: QWord);
var
  M: tGateHealthMark;
  Same: Boolean;
begin
  M := HealthMark(G, I);
  Same := CompareByte(M, G.Marks[I], SizeOf(M)) = 0;
  if Changed or (Due and not Same) then
  begin
    if G.Iecs[I] <> nil then
      Publish(G, Topic(G, G.Iecs[I]^.Name, '$health'), GateIecHealthPayload(G.Iecs[I]), True)
    else
      Publish(G, Topic(G, G.Devs[I].Name, '$health'), GateHealthPayload(G.Devs[I]), True);
    G.Marks[I] := M;
  end
  else if not Same and (G.HealthAt = 0) then
    G.HealthAt := Now_ + GateHealthMs;
end;

{ One round of IEC 101 device I; the ms it may wait. }
function StepIec(var G: tGate; I: LongInt; Health: Boolean; Now_: QWord): LongInt;
var
  D: pGateIecDevice;
  P: LongInt;
  Wr: tIecTableWrite;
  Name, Err: AnsiString;
  Changed: Boolean;
begin
  D := G.Iecs[I];
  if GateIecStep(D) then
    Result := 0
  else
    Result := GateIecWaitMs(D);
  while IecTableTakeChange(D^.T, P) do
  begin
    Publish(G, Topic(G, D^.Name, GateIecPointName(D, P)), GateIecPointPayload(D^.T.Points[P]), True);
    Err := Gate104IecChange(G.N104, D, P);
    if Err <> '' then
      Refuse(G, Topic(G, D^.Name, GateIecPointName(D, P)), Err);
  end;
  while IecTableTakeWrite(D^.T, Wr) do
  begin
    if Gate104IecWriteDone(G.N104, Wr) then
      Continue;                        { the IEC 104 north's command }
    Name := Topic(G, D^.Name, GateIecPointName(D, Wr.Point)) + '/set';
    if Wr.Res = res_Ok then
      Say(G, Name + ' ' + JsonNumber(Wr.Value) + ': positive ACT_CON')
    else
      Refuse(G, Name, Wr.Err);
  end;
  Changed := GateIecTakeHealth(D);
  if Changed then
    Say(G, D^.Name + ': ' + GateIecHealthPayload(D));
  StepHealth(G, I, Changed, Health, Now_);
end;

function GateBurstOver(var High: LongInt; Queued: LongInt): Boolean;
begin
  Result := (Queued <= GateBurstLow) and (High >= GateBurst);
  if Result or (Queued > High) then
    High := Queued;
end;

{$IFDEF LINUX}
var
  MallocTrim: function(Pad: PtrUInt): LongInt; cdecl = nil;
  MallocTrimLooked: Boolean = False;
{$ENDIF}

{ After a burst the C allocator (chngate's, cmem) keeps what it freed:
  glibc's malloc_trim gives it back to the system. Looked up at run time,
  so nothing happens where the C library has none (and off Linux). }
procedure GiveBackFreeMemory;
{$IFDEF LINUX}
var
  Lib: TLibHandle;
{$ENDIF}
begin
  {$IFDEF LINUX}
  if not MallocTrimLooked then
  begin
    MallocTrimLooked := True;
    Lib := LoadLibrary('libc.so.6');   { loaded already: never unloaded }
    if Lib <> NilHandle then
      Pointer(MallocTrim) := GetProcedureAddress(Lib, 'malloc_trim');
  end;
  if Assigned(MallocTrim) then
    MallocTrim(0);
  {$ENDIF}
end;

function GateStep(var G: tGate): LongInt;
var
  I, Tag, W: LongInt;
  M: tMqttMessage;
  Wr: tTagWrite;
  Changed: Boolean;
  Now_, Due: QWord;
  Health, Moved, Worked: Boolean;
begin
  { the clock is read once for an idle round (each read is a system call) }
  Now_ := GetTickCount64;
  Health := (G.HealthAt <> 0) and (Now_ >= G.HealthAt);
  if Health then
    G.HealthAt := 0;
  Moved := False;
  Worked := False;
  StepMqtt(G, Now_);
  while MqttTakeMessage(G.Mqtt, M) do
  begin
    Command(G, M);
    Worked := True;
  end;
  Result := High(LongInt);
  Due := MqttDueAt(G.Mqtt);
  { the control centre's requests and commands, before the devices' step }
  if G.Cfg.Iec104.Present then
    Result := Min(Result, Gate104Step(G.N104, G.Devs));
  for I := 0 to High(G.Devs) do
  begin
    if G.Iecs[I] <> nil then
    begin
      W := StepIec(G, I, Health, Now_);
      if W < Result then
        Result := W;
      Continue;
    end;
    if (G.OpenAt[I] <> 0) and (Now_ >= G.OpenAt[I]) then
      OpenDevice(G, I);
    if TagDeviceStepAt(G.Devs[I], Now_) then
      Moved := True;
    while TagTakeChange(G.Devs[I], Tag) do
    begin
      Worked := True;
      Publish(G, Topic(G, G.Devs[I].Name, G.Devs[I].Tags[Tag].Name), GateTagPayload(G.Devs[I].Tags[Tag]), True);
      Gate104Change(G.N104, G.Devs, I, Tag);
    end;
    while TagTakeWrite(G.Devs[I], Wr) do
      if not Gate104WriteDone(G.N104, Wr) and (Wr.Res <> res_Ok) then
        Refuse(G, Topic(G, G.Devs[I].Name, G.Devs[I].Tags[Wr.Tag].Name) + '/set', Wr.Err);
    Changed := TagTakeHealth(G.Devs[I]);
    if Changed then
    begin
      Say(G, G.Devs[I].Name + ': ' + TagStateNames[G.Devs[I].State] + ' ' + G.Devs[I].LastError);
      Gate104Health(G.N104, G.Devs, I);
    end;
    StepHealth(G, I, Changed, Health, Now_);
    { the clock is read once for all the devices }
    if G.OpenAt[I] <> 0 then
      Due := Min(Due, G.OpenAt[I])
    else
      Due := Min(Due, TagDeviceDueAt(G.Devs[I]));
  end;
  if G.HealthAt <> 0 then
    Due := Min(Due, G.HealthAt);
  Worked := Worked or Moved or (MqttQueued(G.Mqtt) > 0);
  if Worked then
    Now_ := GetTickCount64;            { the round took its time: the clock again }
  if Due <= Now_ then
    W := 0
  else
    W := LongInt(Min(Due - Now_, QWord(High(LongInt))));
  if W < Result then
    Result := W;
  { what was queued in this round goes out now (an idle round queued
    nothing: no second look) }
  if Worked or (Result = 0) then
  begin
    StepMqtt(G, Now_);
    if G.Cfg.Iec104.Present then
      Result := Min(Result, Gate104Step(G.N104, G.Devs));
    if GateBurstOver(G.QueuedHigh, MqttQueued(G.Mqtt) + Gate104Queued(G.N104)) then
      GiveBackFreeMemory;
  end;
end;

procedure GateStop(var G: tGate; Ms: LongInt);
var
  Deadline: QWord;
begin
  CloseDevices(G);
  if G.Mqtt.State = msConnected then
  begin
    MqttPublish(G.Mqtt, G.Cfg.Prefix + '/$gateway/status', 'offline', True);
    Deadline := GetTickCount64 + QWord(Ms);
    while (MqttQueued(G.Mqtt) > 0) and (G.Mqtt.State = msConnected) and (GetTickCount64 < Deadline) do
    begin
      MqttStep(G.Mqtt);
      ChnWaitAny(ChnWaitLeft(Deadline));
    end;
  end;
  MqttClose(G.Mqtt);
  Gate104Close(G.N104);
end;

end.
