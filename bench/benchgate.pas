{ benchgate - tools/chngate under load (Linux; "make bench",
  docs/chngate.md): 8 tools/df1sim on ptys, 100 tags each (N7:0, N7:2 ..
  N7:198) and the clock S2:4, scan 500 ms, a mosquitto broker on a free
  loopback port, and this program as the MQTT subscriber of every clock.
  It prints the reads per scan (from chngate --check), the time from the
  read that saw a clock change (the payload's ts) to its arrival here
  (median and p99; the change itself happened up to one scan before that
  read), chngate's CPU in % of one core under that load and idle (scan
  60 s: nothing to do but wait), and its resident memory. Skipped with the
  reason when mosquitto or libmosquitto is missing.

    benchgate          10 s under load, 5 s idle
    benchgate quick    3 s and 2 s }
program benchgate;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  Classes, SysUtils, DateUtils, BaseUnix, Process, ChildLine, ProcStat, ChnWait, ChnMqtt, ChnSock;

const
  Lines = 8;
  TagsPerLine = 100;
  ScanMs = 500;

var
  Quick: Boolean;
  Dir: string;
  Sims: array of TProcess;
  Broker, Gate: TProcess;
  Port: Word;

function Bin(const Name: string): string;
begin
  Result := ExtractFilePath(ParamStr(0)) + Name;
end;

function FreePort: Word;
var
  A: tSockAddrs;
  N: LongInt;
  S: tSock;
begin
  Result := 0;
  if (SockResolve('127.0.0.1', 0, True, A, N) = seOk) and (SockListen(A[0], S) = seOk) then
  begin
    Result := SockLocalPort(S);
    SockClose(S);
  end;
end;

procedure Stop(var P: TProcess);
begin
  if P = nil then
    Exit;
  if P.Running then
  begin
    FpKill(P.ProcessID, SIGTERM);
    P.WaitOnExit;
  end;
  FreeAndNil(P);
end;

procedure Cleanup;
var
  I: LongInt;
begin
  Stop(Gate);
  for I := 0 to High(Sims) do
    Stop(Sims[I]);
  Stop(Broker);
  DeleteFile(Dir + '/sim.conf');
  DeleteFile(Dir + '/gate.conf');
  DeleteFile(Dir + '/m.conf');
  RemoveDir(Dir);
end;

procedure WriteText(const Name, Text: string);
var
  L: TStringList;
begin
  L := TStringList.Create;
  try
    L.Text := Text;
    L.SaveToFile(Name);
  finally
    L.Free;
  end;
end;

function GateConfig(Scan: LongInt): string;
var
  I, K: LongInt;
  Tags: string;
begin
  Tags := '';
  for K := 0 to TagsPerLine - 1 do
    Tags := Tags + ' N7:' + IntToStr(2 * K);
  Result := '[mqtt]'#10'port = ' + IntToStr(Port) + #10'prefix = bench'#10;
  for I := 0 to High(Sims) do
  begin
    Result := Result + #10'[device plc' + IntToStr(I + 1) + ']'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Sims[I].Parameters.Values['pty'] + #10 +
      'tags =' + Tags + ' clock=S2:4'#10'scan = ' + IntToStr(Scan) + #10;
  end;
end;

function StartGate: TProcess;
begin
  Result := TProcess.Create(nil);
  Result.Executable := Bin('chngate');
  Result.Parameters.Add(Dir + '/gate.conf');
  Result.Options := [poUsePipes, poStderrToOutPut];
  Result.Execute;
end;

{ 2026-12-04T10:00:00.123Z of a payload: UTC ms since 1970; -1 if none. }
function PayloadMs(const P: string): Int64;
var
  I: LongInt;
  S: string;
  T: TDateTime;
begin
  Result := -1;
  I := Pos('"ts":"', P);
  if I = 0 then
    Exit;
  S := Copy(P, I + 6, 23);
  try
    T := EncodeDateTime(StrToInt(Copy(S, 1, 4)), StrToInt(Copy(S, 6, 2)), StrToInt(Copy(S, 9, 2)),
      StrToInt(Copy(S, 12, 2)), StrToInt(Copy(S, 15, 2)), StrToInt(Copy(S, 18, 2)), StrToInt(Copy(S, 21, 3)));
    Result := Int64(DateTimeToUnix(T)) * 1000 + MilliSecondOf(T);
  except
    Result := -1;
  end;
end;

function NowUtcMs: Int64;
begin
  Result := Round((LocalTimeToUniversal(Now) - UnixDateDelta) * MSecsPerDay);
end;

var
  I, N, Reads: LongInt;
  Sub: tMqttClient;
  M: tMqttMessage;
  Lat: array of LongInt;
  Err, Pty, Check: string;
  Deadline, T0, T1: QWord;
  C0, C1, LoadCpu, IdleCpu: Double;
  Rss, Clocks, J, V: LongInt;
  LoadS: Double;

begin
  Quick := ParamStr(1) = 'quick';
  if not MqttLoad(Err) then
  begin
    WriteLn('benchgate: skipped: ', Err);
    Halt(0);
  end;
  if (ExeSearch('mosquitto', '/usr/sbin:/usr/bin:' + GetEnvironmentVariable('PATH')) = '') then
  begin
    WriteLn('benchgate: skipped: no mosquitto broker (apt-get install mosquitto)');
    Halt(0);
  end;
  Dir := GetTempDir + 'chn-benchgate-' + IntToStr(GetProcessID);
  ForceDirectories(Dir);
  Port := FreePort;
  WriteText(Dir + '/sim.conf', 'S2 32'#10'N7 200'#10);
  WriteText(Dir + '/m.conf', 'listener ' + IntToStr(Port) + ' 127.0.0.1'#10'allow_anonymous true'#10 +
    'persistence false'#10);
  try
    Broker := TProcess.Create(nil);
    Broker.Executable := ExeSearch('mosquitto', '/usr/sbin:/usr/bin:' + GetEnvironmentVariable('PATH'));
    Broker.Parameters.Add('-c');
    Broker.Parameters.Add(Dir + '/m.conf');
    Broker.Options := [poUsePipes, poStderrToOutPut];    { a few lines: the pipe never fills }
    Broker.Execute;
    SetLength(Sims, Lines);
    for I := 0 to Lines - 1 do
    begin
      Sims[I] := TProcess.Create(nil);
      Sims[I].Executable := Bin('df1sim');
      Sims[I].Parameters.Add('--pty');
      Sims[I].Parameters.Add('--quiet');
      Sims[I].Parameters.Add('--config=' + Dir + '/sim.conf');
      Sims[I].Options := [poUsePipes];
      Sims[I].Execute;
      Pty := ReadFirstLine(Sims[I], 3000);
      Sims[I].Parameters.Add('pty=' + Copy(Pty, 5, 255));
    end;
    WriteText(Dir + '/gate.conf', GateConfig(ScanMs));
    { the reads per scan, as chngate --check counts them }
    RunCommand(Bin('chngate'), ['--check', Dir + '/gate.conf'], Check, [], swoNone);
    Reads := StrToIntDef(Trim(Copy(Check, Pos('tags, ', Check) + 6, Pos(' reads', Check) - Pos('tags, ', Check) - 6)), -1);
    MqttInit(Sub);
    Sub.Port := Port;
    MqttSubscribe(Sub, 'bench/+/clock');
    if not MqttOpen(Sub, Err) then
      raise Exception.Create(Err);
    Gate := StartGate;
    { settle: every line read once }
    Deadline := GetTickCount64 + 2000;
    while GetTickCount64 < Deadline do
    begin
      MqttStep(Sub);
      while MqttTakeMessage(Sub, M) do ;
      ChnWaitAny(ChnWaitLeft(Deadline));
    end;
    Lat := nil;
    C0 := ProcCpu(Gate.ProcessID);
    T0 := GetTickCount64;
    if Quick then
      Deadline := T0 + 3000
    else
      Deadline := T0 + 10000;
    while GetTickCount64 < Deadline do
    begin
      MqttStep(Sub);
      while MqttTakeMessage(Sub, M) do
        if PayloadMs(M.Payload) > 0 then
        begin
          SetLength(Lat, Length(Lat) + 1);
          Lat[High(Lat)] := NowUtcMs - PayloadMs(M.Payload);
        end;
      ChnWaitAny(ChnWaitLeft(Deadline));
    end;
    C1 := ProcCpu(Gate.ProcessID);
    T1 := GetTickCount64;
    LoadS := (T1 - T0) / 1000;
    LoadCpu := (C1 - C0) / LoadS * 100;
    Rss := ProcRssKb(Gate.ProcessID);
    Clocks := Length(Lat);
    Stop(Gate);
    { idle: one read of everything, then nothing for 60 s }
    WriteText(Dir + '/gate.conf', GateConfig(60000));
    Gate := StartGate;
    Sleep(2000);
    C0 := ProcCpu(Gate.ProcessID);
    T0 := GetTickCount64;
    if Quick then Sleep(2000) else Sleep(5000);
    C1 := ProcCpu(Gate.ProcessID);
    T1 := GetTickCount64;
    IdleCpu := (C1 - C0) / ((T1 - T0) / 1000) * 100;
    Stop(Gate);
    MqttClose(Sub);
    { median and p99 }
    N := Length(Lat);
    for I := 1 to N - 1 do     { insertion sort: a few hundred values }
    begin
      V := Lat[I];
      J := I;
      while (J > 0) and (Lat[J - 1] > V) do
      begin
        Lat[J] := Lat[J - 1];
        Dec(J);
      end;
      Lat[J] := V;
    end;
    WriteLn(Format('benchgate: %d lines x %d tags + clock, scan %d ms: %d reads per scan (%d per line)',
      [Lines, TagsPerLine, ScanMs, Reads, Reads div Lines]));
    if N > 0 then
      WriteLn(Format('benchgate: read -> MQTT subscriber: median %d ms, p99 %d ms, max %d ms (%d clock changes ' +
        'in %.1f s; a change is read up to one scan after it happened)',
        [Lat[N div 2], Lat[(N * 99) div 100], Lat[N - 1], Clocks, LoadS]))
    else
      WriteLn('benchgate: no clock change arrived');
    WriteLn(Format('benchgate: chngate CPU %.2f %% of a core under load, %.2f %% idle; RSS %d KiB',
      [LoadCpu, IdleCpu, Rss]));
  finally
    Cleanup;
  end;
end.
