{ benchgate - tools/chngate under load (Linux; "make bench",
  docs/chngate.md "Speed and size").

  Eight DF1 lines at 19200 Bd (or BD), 100 tags each (N7:0, N7:2 .. N7:198), scan
  500 ms, a mosquitto broker on a free loopback port. The lines are real
  in time: chngate opens a pty per line; this program passes its bytes to
  an SLC station (tools/lib ChnSlc, df1sim's table) over an in-memory
  line at 19200 8N1 (NAM=LOOP BD=, docs/ChnLoop.md), so every character
  takes the time it takes on the plant's cable, and the line's busy time
  is known. This program is also the subscriber, and it changes one tag
  of the stations every 25 ms (each line in turn, a new value each time).

  It prints:
  - the reads per scan chngate plans (chngate --check) and the requests
    that went over the lines, per scan;
  - the share of each line's time used (characters times the character
    time, both directions summed, over the time measured);
  - change -> MQTT: from the moment a value changed in a station to its
    message at the subscriber (median, p99, max; a change waits up to one
    scan for its read, and the read takes its time on the line);
    wire -> MQTT: from the end of the reply that carried the change (its
    last octet handed to chngate's pty; the reply is found by the value's
    octets in it) to the message - the gateway's own share; and
    read -> MQTT: from the read that saw it (the payload's ts) on;
  - the same for IEC 104: chngate also serves an IEC 104 server, this
    program is its control centre (the library's IEC 101 master over
    NAM=IEC104, a real TCP connection) and times each change's
    spontaneous M_ME_TE_1 (change -> IEC 104 and wire -> IEC 104);
  - chngate's CPU under load (% of one core), and idle (scan 60 s, nothing
    to read, MQTT keep-alive 5 s, after the first read's $health went
    out; measured over whole keep-alive cycles, from just after one)
    against two idle floors, each run as a child in the same run: the
    program-wide wait alone (ChnWaitAny over as many descriptors - 9
    serial lines on ptys for the gateway's 8 lines and its socket - woken
    as often as the gateway was), and that wait with the broker's socket
    in it and the same MQTT session kept alive by libmosquitto itself
    (loop_read, loop_misc, loop_write, the least a keep-alive costs):
    CPU per second and the ratios;
  - chngate's resident memory under load with the IEC 104 server and its
    centre, and idle with MQTT only, and by what is mapped (its own code,
    the anonymous memory of heap and stacks, each library).
  Skipped with the reason when mosquitto or libmosquitto is missing.

    benchgate [quick] [BD] [maxread=N]
                             10 s under load, 18 s idle (the gateway and
                             the floors each: 3 keep-alive cycles);
                             quick: 4 s and 6 s (one cycle); BD the
                             lines' rate (default 19200); maxread=N the
                             devices' maxread (default 244: 2 reads a line)
  Internal roles: --floor N MS (the idle floor: N pty lines, ChnWaitAny(MS)
  until killed); --floor-mqtt N PORT KEEPALIVE (the second floor: N pty
  lines and libmosquitto's session in the wait). }
program benchgate;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  Classes, SysUtils, DateUtils, BaseUnix, Process, DynLibs, ctypes, ChnTypes, ChnVirt, ChnWait, ChnLoop, ChnCom,
  ChnPty, ChnDF1, ChnDF1Link, ChnSlc, ChnMqtt, ChnGateway, ChnSock, ChnIec101Asdu, ChnIec101Master, ChnIec104, ProcStat;

const
  Lines = 8;
  TagsPerLine = 100;
  ScanMs = 500;
  ChangeEveryMs = 25;
  IdleKeepAlive = 5;        { s: the MQTT keep-alive of the idle run }
  FirstValue = 1000;        { change n writes FirstValue + n }
  MaxChanges = 30000;

type
  { A DF1 frame coming in (full duplex: DLE STX data DLE ETX CRC CRC):
    its data unstuffed, its octets on the wire counted. }
  tFrameIn = record
    Data  : AnsiString;
    Octets: LongInt;
    State : Byte;
  end;

  tLine = record
    Table  : tSlcTable;
    Station: tDF1Station;
    StChn  : pChnVirt;      { the station's DF1 stack, LOOP END=2 }
    Wire   : pChnVirt;      { LOOP END=1: the station's line, raw }
    Pty    : pChnVirt;      { the pty master; chngate opens its slave }
    Slave  : AnsiString;
    Pair   : string;
    Busy0  : QWord;         { the line's busy time (us) when measuring began }
    Requests: LongInt;      { frames from chngate longer than an ACK }
    Rx     : tFrameIn;      { the station's frames, to find the changes they carry }
    Tx     : tFrameIn;      { chngate's requests, to time each block's reads }
    ReqAt  : QWord;         { ChnClockUs: the last request handed to the line }
    ReqElem: LongInt;       { its first element (the block it reads) }
    ReqOctets: LongInt;     { its octets on the wire }
    LastAt : array[0..255] of QWord;   { ChnClockUs of the last read of the block at element K }
  end;

var
  Bd: LongInt = 19200;
  MaxRead: LongInt = 0;     { the devices' maxread, 0 the gateway's default }
  L: array[0..Lines - 1] of tLine;
  Buf: array[0..4095] of Byte;
  Quick: Boolean;
  Dir: string;
  Broker, Gate: TProcess;
  Port: Word;
  ChangeAt: array[0..MaxChanges - 1] of QWord;   { ChnClockUs of change n }
  Arrived, Arrived104: array[0..MaxChanges - 1] of Boolean;
  WireAt: array[0..MaxChanges - 1] of QWord;     { ChnClockUs: the end of the reply carrying it, 0 none yet }
  Changes: LongInt;
  { where a change's time goes: to the request of the read that sees it,
    that request to the end of its reply (and what of it is not wire
    time: the stations served late), one block's reads one to the next }
  ToReq, Late, ReadGap: array of Double;   { ms }
  ReqToEnd: array[Boolean] of array of Double;  { ms; [True]: the reads of the block at N7:0 }
  NToReq, NLate, NReadGap: LongInt;
  NReqToEnd: array[Boolean] of LongInt;
  Measuring: Boolean;       { under load: the reads and replies timed }
  ChangeLat, ReadLat, WireLat, Lat104, Wire104: array of Double;   { ms }
  Port104: Word;

function Bin(const Name: string): string;
begin
  Result := ExtractFilePath(ParamStr(0)) + Name;
end;

{ Raised, so that the finally below stops the broker and chngate. }
procedure Fail(const Why: string);
begin
  raise Exception.Create('benchgate: ' + Why);
end;

function OpenRaw(const Layer, Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(Layer);
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
    Fail(Layer + ' ' + Params + ': ' + Result^.ChErrorText);
  Result^.ChReceiveBuffer(@Buf, SizeOf(Buf));
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

procedure WriteText(const Name, Text: string);
var
  S: TStringList;
begin
  S := TStringList.Create;
  try
    S.Text := Text;
    S.SaveToFile(Name);
  finally
    S.Free;
  end;
end;

{ ------------------------------------------------------------ the lines }

procedure OpenLines;
var
  I: LongInt;
  ErrLine: LongInt;
  Err: AnsiString;
begin
  for I := 0 to Lines - 1 do
  begin
    L[I].Pair := 'GATE' + IntToStr(I);
    if not SlcLoadConfig(L[I].Table, 'N7 200', ErrLine, Err) then
      Fail('table: ' + Err);
    L[I].StChn := ChnCollection^.ChNewInit('DF1');
    L[I].StChn^.ChSetParam(Format('NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=%s END=2 BD=%d',
      [L[I].Pair, Bd]));
    L[I].StChn^.ChOpen;
    L[I].StChn^.ChConnect;
    if L[I].StChn^.ChResult <> res_Ok then
      Fail('station: ' + L[I].StChn^.ChErrorText);
    SlcStationInit(L[I].Station, L[I].StChn, @L[I].Table);
    L[I].Wire := OpenRaw(ChnLoop.cName, Format('PAIR=%s END=1 BD=%d', [L[I].Pair, Bd]));
    L[I].Pty := OpenRaw('COM', 'DRV=PTY IDL=0');
    L[I].Slave := PtyLastSlave;
  end;
end;

procedure CloseLines;
var
  I: LongInt;
begin
  for I := 0 to Lines - 1 do
  begin
    if L[I].Pty <> nil then
      Dispose(L[I].Pty, Done);
    if L[I].Wire <> nil then
      Dispose(L[I].Wire, Done);
    if L[I].StChn <> nil then
      Dispose(L[I].StChn, Done);
  end;
end;

{ Octet B of a frame coming in; True when it ended the frame (the CRC's
  second octet). }
function FrameOctet(var F: tFrameIn; B: Byte): Boolean;
const
  DLE = $10; STX = $02; ETX = $03;
begin
  Result := False;
  Inc(F.Octets);
  case F.State of
    0: if B = DLE then F.State := 1;
    1: if B = STX then begin F.Data := ''; F.Octets := 2; F.State := 2; end else F.State := 0;
    2: if B = DLE then F.State := 3 else F.Data := F.Data + Chr(B);
    3: if B = DLE then begin F.Data := F.Data + Chr(B); F.State := 2; end
       else if B = ETX then F.State := 4
       else F.State := 2;
    4: F.State := 5;                    { CRC, low }
    5: begin Result := True; F.State := 0; end;
  end;
end;

procedure Add(var A: array of Double; var N: LongInt; V: Double);
begin
  if N <= High(A) then
  begin
    A[N] := V;
    Inc(N);
  end;
end;

{ The octets on the wire take this long (8N1: 10 bits each), us. }
function WireUs(Octets: LongInt): Double;
begin
  Result := Octets * 10 * 1e6 / Bd;
end;

{ A request of line I ended at AtUs: a typed read (DST SRC CMD STS TNS
  TNS FNC size file type element) is timed against the last read of the
  same block. }
procedure RequestEnded(I: LongInt; AtUs: QWord);
var
  K: LongInt;
begin
  with L[I] do
  begin
    if Length(Tx.Data) < 11 then
      Exit;
    K := Ord(Tx.Data[11]);
    ReqAt := AtUs;
    ReqElem := K;
    ReqOctets := Tx.Octets;
    if Measuring and (LastAt[K] <> 0) then
      Add(ReadGap, NReadGap, (AtUs - LastAt[K]) / 1000);
    LastAt[K] := AtUs;
  end;
end;

{ Move chngate's octets of line I to the station's line; the number of
  chunks longer than 2 (the requests, not the ACKs). }
function Pass(I: LongInt): LongInt;
var
  N: Word;
  K: LongInt;
  AtUs: QWord;
begin
  Result := 0;
  while L[I].Pty^.ChReceiveReady = CHS_ReceiveReady do
  begin
    N := 0;
    L[I].Pty^.ChReceive(N);
    if N = 0 then
      Break;
    if N > 2 then
      Inc(Result);
    L[I].Wire^.ChSend(@Buf, N);
    AtUs := ChnClockUs;
    for K := 0 to N - 1 do
      if FrameOctet(L[I].Tx, Buf[K]) then
        RequestEnded(I, AtUs);
  end;
end;

{ A frame of line I ended at AtUs: the changes of that line whose value
  it carries (as a little-endian word) ended on the wire then; the time
  from its request on is the reply's wire time and the stations' lateness. }
procedure FrameEnded(I: LongInt; AtUs: QWord);
var
  N, V: LongInt;
  W: string[2];
  Us: Double;
begin
  if Measuring and (L[I].ReqAt <> 0) then
  begin
    Us := AtUs - L[I].ReqAt;
    Add(ReqToEnd[L[I].ReqElem = 0], NReqToEnd[L[I].ReqElem = 0], Us / 1000);
    { request, the station's DLE ACK, the reply }
    Add(Late, NLate, (Us - WireUs(L[I].ReqOctets + 2 + L[I].Rx.Octets)) / 1000);
  end;
  N := Changes - 1;
  while (N >= 0) and (N >= Changes - 2 * Lines * TagsPerLine) do
  begin
    if (N mod Lines = I) and (WireAt[N] = 0) then
    begin
      V := FirstValue + N;
      W := Chr(V and $FF) + Chr(V shr 8);
      if Pos(W, L[I].Rx.Data) > 0 then
      begin
        WireAt[N] := AtUs;
        if L[I].ReqAt <> 0 then
          Add(ToReq, NToReq, (Int64(L[I].ReqAt) - Int64(ChangeAt[N])) / 1000);
      end;
    end;
    Dec(N);
  end;
end;

{ The station's octets of line I, as they are handed to chngate. }
procedure Watch(I: LongInt; N: Word; AtUs: QWord);
var
  K: LongInt;
begin
  for K := 0 to N - 1 do
    if FrameOctet(L[I].Rx, Buf[K]) then
      FrameEnded(I, AtUs);
end;

procedure StepLines;
var
  I: LongInt;
  N: Word;
begin
  for I := 0 to Lines - 1 do
  begin
    Inc(L[I].Requests, Pass(I));
    DF1StationStep(L[I].Station);
    while L[I].Wire^.ChReceiveReady = CHS_ReceiveReady do
    begin
      N := 0;
      L[I].Wire^.ChReceive(N);
      if N = 0 then
        Break;
      L[I].Pty^.ChSend(@Buf, N);
      Watch(I, N, ChnClockUs);
    end;
  end;
end;

function LineBusyUs(I: LongInt): QWord;
var
  Chars: QWord;
begin
  LoopLineLoad(L[I].Pair, Chars, Result);
end;

{ ------------------------------------------------------------ measuring }

{ The IOA of line I's tag K on the IEC 104 server. }
function Ioa104(I, K: LongInt): LongInt;
begin
  Result := I * 1000 + 1 + K;
end;

{ The configuration; With104: an [iec104] server too, line I's tags from
  IOA Ioa104(I, 0); KeepAlive > 0: the MQTT keep-alive (s). }
function GateConfig(Scan: LongInt; With104: Boolean; KeepAlive: LongInt = 0): string;
var
  I, K: LongInt;
  Tags: string;
begin
  Tags := '';
  for K := 0 to TagsPerLine - 1 do
    Tags := Tags + ' N7:' + IntToStr(2 * K);
  Result := '[mqtt]'#10'port = ' + IntToStr(Port) + #10'prefix = bench'#10;
  if KeepAlive > 0 then
    Result := Result + 'keepalive = ' + IntToStr(KeepAlive) + #10;
  if With104 then
    Result := Result + #10'[iec104]'#10'listen = 127.0.0.1:' + IntToStr(Port104) + #10;
  for I := 0 to Lines - 1 do
  begin
    Result := Result + #10'[device plc' + IntToStr(I) + ']'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=' + L[I].Slave + #10 +
      'tags =' + Tags + #10'scan = ' + IntToStr(Scan) + #10'ioa = ' + IntToStr(Ioa104(I, 0)) + #10;
    if MaxRead > 0 then
      Result := Result + 'maxread = ' + IntToStr(MaxRead) + #10;
  end;
end;

function StartGate(Scan: LongInt; With104: Boolean; KeepAlive: LongInt = 0): TProcess;
begin
  WriteText(Dir + '/gate.conf', GateConfig(Scan, With104, KeepAlive));
  Result := TProcess.Create(nil);
  Result.Executable := Bin('chngate');
  Result.Parameters.Add(Dir + '/gate.conf');
  Result.Options := [poUsePipes, poStderrToOutPut];    { a few log lines: the pipe never fills }
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

{ Change n: line n mod Lines, tag n div Lines (each tag changes once in
  Lines * TagsPerLine changes: 20 s at 25 ms). }
procedure MakeChange;
var
  Line, Elem: LongInt;
begin
  if Changes >= MaxChanges then
    Exit;
  Line := Changes mod Lines;
  Elem := 2 * ((Changes div Lines) mod TagsPerLine);
  SlcSetWord(L[Line].Table, 7, Elem, FirstValue + Changes);
  ChangeAt[Changes] := ChnClockUs;
  Arrived[Changes] := False;
  Arrived104[Changes] := False;
  WireAt[Changes] := 0;
  Inc(Changes);
end;

var
  NChange, NRead, NWire, N104, NWire104: LongInt;

{ A message: a change's arrival when its value is one this program made. }
procedure Received(const M: tMqttMessage; AtUs: QWord);
var
  P, Q, Code, Id, Line, Elem: LongInt;
  V: LongInt;
  Ts: Int64;
begin
  P := Pos('"value":', M.Payload);
  if P = 0 then
    Exit;
  Q := P + 8;
  while (Q <= Length(M.Payload)) and (M.Payload[Q] in ['0'..'9', '-']) do
    Inc(Q);
  Val(Copy(M.Payload, P + 8, Q - P - 8), V, Code);
  Id := V - FirstValue;
  if (Code <> 0) or (Id < 0) or (Id >= Changes) or Arrived[Id] then
    Exit;
  Line := Id mod Lines;
  Elem := 2 * ((Id div Lines) mod TagsPerLine);
  if M.Topic <> Format('bench/plc%d/N7:%d', [Line, Elem]) then
    Exit;
  Arrived[Id] := True;
  Add(ChangeLat, NChange, (AtUs - ChangeAt[Id]) / 1000);
  if WireAt[Id] <> 0 then
    Add(WireLat, NWire, (AtUs - WireAt[Id]) / 1000);
  Ts := PayloadMs(M.Payload);
  if Ts > 0 then
    Add(ReadLat, NRead, NowUtcMs - Ts);
end;

var
  Centre: tIecMaster;
  CentreChn: pChnVirt;

{ An object at the control centre: a change's spontaneous event. }
procedure OnObject(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
var
  Id: LongInt;
  AtUs: QWord;
begin
  AtUs := ChnClockUs;
  if H.Cot <> Cot_Spontaneous then
    Exit;
  Id := O.Int - FirstValue;
  if (Id < 0) or (Id >= Changes) or Arrived104[Id] or
     (LongInt(O.Ioa) <> Ioa104(Id mod Lines, (Id div Lines) mod TagsPerLine)) then
    Exit;
  Arrived104[Id] := True;
  Add(Lat104, N104, (AtUs - ChangeAt[Id]) / 1000);
  if WireAt[Id] <> 0 then
    Add(Wire104, NWire104, (AtUs - WireAt[Id]) / 1000);
end;

{ Run the lines, the subscriber and the control centre (when connected)
  until Deadline; a change every ChangeEveryMs when Changing. }
procedure Serve(var Sub: tMqttClient; Deadline: QWord; Changing: Boolean);
var
  M: tMqttMessage;
  NextChange, AtUs: QWord;
  W: LongInt;
begin
  NextChange := GetTickCount64;
  while GetTickCount64 < Deadline do
  begin
    StepLines;
    MqttStep(Sub);
    AtUs := ChnClockUs;
    while MqttTakeMessage(Sub, M) do
      Received(M, AtUs);
    if CentreChn <> nil then
      while IecMasterStep(Centre) do;
    if Changing and (GetTickCount64 >= NextChange) then
    begin
      MakeChange;
      NextChange := NextChange + ChangeEveryMs;
    end;
    W := ChnWaitLeft(Deadline);
    if Changing and (ChnWaitLeft(NextChange) < W) then
      W := ChnWaitLeft(NextChange);
    if W > 20 then
      W := 20;             { the stations' own timers }
    ChnWaitAny(W);
  end;
end;

procedure Sort(var A: array of Double; N: LongInt);
var
  I, J: LongInt;
  V: Double;
begin
  for I := 1 to N - 1 do
  begin
    V := A[I];
    J := I;
    while (J > 0) and (A[J - 1] > V) do
    begin
      A[J] := A[J - 1];
      Dec(J);
    end;
    A[J] := V;
  end;
end;

function Quantiles(var A: array of Double; N: LongInt): string;
begin
  if N = 0 then
    Exit('none arrived');
  Sort(A, N);
  Result := Format('median %.1f ms, p99 %.1f ms, max %.1f ms (%d)', [A[N div 2], A[(N * 99) div 100], A[N - 1], N]);
end;

{ ------------------------------------------------------------ the floor }

{ --floor N MS: N lines (pty slaves, their masters held here) in the
  program-wide wait and nothing else, ChnWaitAny(MS) until killed. }
procedure OpenFloorLines(N: LongInt);
var
  I: LongInt;
  Fd: cint;
  Slave: AnsiString;
begin
  for I := 0 to N - 1 do
  begin
    if PtyCreate(Fd, Slave) <> 0 then
      Fail('floor: no pty');
    OpenRaw('COM', 'DEV=' + Slave + ' IDL=0');
  end;
end;

procedure Floor(N, Ms: LongInt);
begin
  OpenFloorLines(N);
  WriteLn('ready');
  Flush(Output);
  repeat
    ChnWaitAny(Ms);
  until False;
end;

{ --floor-mqtt N PORT KEEPALIVE: N lines and an MQTT session to the
  broker at PORT kept alive by libmosquitto itself, its socket in the
  same wait: the least a program serving lines and a broker does when
  idle. The calls as libmosquitto's documentation has them for an
  external loop, with no clock read of this program's own: wait until
  the broker sends (the PINGRESP) or KEEPALIVE + 1 s passed (the
  library's clock is whole seconds: its PINGREQ is due by then), read
  what came, loop_misc (sends the PINGREQ), write what waits, put the
  socket back into the wait. }
procedure FloorMqtt(N, Port, KeepAlive: LongInt);
var
  Lib: TLibHandle;
  lib_init: function: cint; cdecl;
  new_: function(Id: PChar; Clean: Boolean; Obj: Pointer): Pointer; cdecl;
  connect: function(Mosq: Pointer; Host: PChar; Port, KeepAlive: cint): cint; cdecl;
  socket_: function(Mosq: Pointer): cint; cdecl;
  loop_read, loop_write: function(Mosq: Pointer; MaxPackets: cint): cint; cdecl;
  loop_misc: function(Mosq: Pointer): cint; cdecl;
  want_write: function(Mosq: Pointer): Boolean; cdecl;
  Mosq: Pointer;
  Src: pChnWaitSource;

  procedure Get(var P; const Name: string);
  begin
    Pointer(P) := GetProcedureAddress(Lib, Name);
    if Pointer(P) = nil then
      Fail('floor: ' + Name + ' not in ' + MqttLibName);
  end;

begin
  Lib := LoadLibrary(MqttLibName);
  if Lib = NilHandle then
    Fail('floor: ' + MqttLibName + ' not found');
  Get(lib_init, 'mosquitto_lib_init');
  Get(new_, 'mosquitto_new');
  Get(connect, 'mosquitto_connect');
  Get(socket_, 'mosquitto_socket');
  Get(loop_read, 'mosquitto_loop_read');
  Get(loop_write, 'mosquitto_loop_write');
  Get(loop_misc, 'mosquitto_loop_misc');
  Get(want_write, 'mosquitto_want_write');
  lib_init();
  OpenFloorLines(N);
  Mosq := new_(nil, True, nil);
  if (Mosq = nil) or (connect(Mosq, '127.0.0.1', Port, KeepAlive) <> 0) then
    Fail('floor: no connection to the broker');
  Src := ChnWaitJoin(wkDescriptor, socket_(Mosq), nil, nil);
  { the CONNACK }
  ChnWaitAny(5000);
  loop_read(Mosq, 1);
  ChnWaitServed(Src, True);
  WriteLn('ready');
  Flush(Output);
  repeat
    if ChnWaitAny((KeepAlive + 1) * 1000) then
      loop_read(Mosq, 1);
    loop_misc(Mosq);
    if want_write(Mosq) then
      loop_write(Mosq, 1);
    ChnWaitServed(Src, True);
  until False;
end;

function StartFloor(const Args: array of string): TProcess;
var
  S: string;
  C: Char;
  I: LongInt;
begin
  Result := TProcess.Create(nil);
  Result.Executable := ParamStr(0);
  for I := 0 to High(Args) do
    Result.Parameters.Add(Args[I]);
  Result.Options := [poUsePipes];
  Result.Execute;
  S := '';
  while (Pos('ready', S) = 0) and Result.Running do
    if Result.Output.Read(C, 1) = 1 then
      S := S + C;
end;

{ Serve until Pid went to sleep again after a wake-up (its voluntary
  context switches moved), and 200 ms more for the wake-up that may
  follow (the PINGRESP after the PINGREQ): a window measured from here
  holds whole keep-alive cycles. At most MaxMs. }
procedure AfterWake(Pid: TPid; var Sub: tMqttClient; MaxMs: LongInt);
var
  S0: Int64;
  Deadline: QWord;
begin
  S0 := ProcSleeps(Pid);
  Deadline := GetTickCount64 + QWord(MaxMs);
  while (ProcSleeps(Pid) = S0) and (GetTickCount64 < Deadline) do
    Serve(Sub, GetTickCount64 + 20, False);
  Serve(Sub, GetTickCount64 + 200, False);
end;

{ CPU ns and sleeps a second of Pid over Ms, this program serving the
  lines meanwhile. }
procedure IdleCost(Pid: TPid; var Sub: tMqttClient; Ms: LongInt; out NsPerS, SleepsPerS: Double);
var
  C0, S0: Int64;
  T0: QWord;
begin
  C0 := ProcRunNs(Pid);
  S0 := ProcSleeps(Pid);
  T0 := ChnClockUs;
  Serve(Sub, GetTickCount64 + QWord(Ms), False);
  NsPerS := (ProcRunNs(Pid) - C0) / ((ChnClockUs - T0) / 1e6);
  SleepsPerS := (ProcSleeps(Pid) - S0) / ((ChnClockUs - T0) / 1e6);
end;

var
  I, Reads, LoadMs, IdleMs, Requests, Rss, RssIdle, FloorMs, Lost, Lost104: LongInt;
  Sub: tMqttClient;
  Err, Check, Shares, Map, MapIdle: AnsiString;
  T0, T1: QWord;
  C0, C1: Int64;
  LoadCpu, GateNs, GateSleeps, FloorNs, FloorSleeps, MosqNs, MosqSleeps: Double;
  FloorProc: TProcess;

begin
  if ParamStr(1) = '--floor' then
  begin
    Floor(StrToInt(ParamStr(2)), StrToInt(ParamStr(3)));
    Halt(0);
  end;
  if ParamStr(1) = '--floor-mqtt' then
  begin
    FloorMqtt(StrToInt(ParamStr(2)), StrToInt(ParamStr(3)), StrToInt(ParamStr(4)));
    Halt(0);
  end;
  Quick := False;
  for I := 1 to ParamCount do
    if ParamStr(I) = 'quick' then
      Quick := True
    else if Copy(ParamStr(I), 1, 8) = 'maxread=' then
      MaxRead := StrToInt(Copy(ParamStr(I), 9, 10))
    else
      Bd := StrToIntDef(ParamStr(I), Bd);
  if Quick then LoadMs := 4000 else LoadMs := 10000;
  { whole keep-alive cycles (a PINGREQ every keep-alive + 1 s) }
  if Quick then IdleMs := 1 else IdleMs := 3;
  IdleMs := IdleMs * (IdleKeepAlive + 1) * 1000;
  if not MqttLoad(Err) then
  begin
    WriteLn('benchgate: skipped: ', Err);
    Halt(0);
  end;
  if ExeSearch('mosquitto', '/usr/sbin:/usr/bin:' + GetEnvironmentVariable('PATH')) = '' then
  begin
    WriteLn('benchgate: skipped: no mosquitto broker (apt-get install mosquitto)');
    Halt(0);
  end;
  SetLength(ChangeLat, MaxChanges);
  SetLength(ReadLat, MaxChanges);
  SetLength(WireLat, MaxChanges);
  SetLength(Lat104, MaxChanges);
  SetLength(Wire104, MaxChanges);
  SetLength(ToReq, MaxChanges);
  SetLength(ReqToEnd[False], MaxChanges);
  SetLength(ReqToEnd[True], MaxChanges);
  SetLength(Late, MaxChanges);
  SetLength(ReadGap, MaxChanges);
  CentreChn := nil;
  Dir := GetTempDir + 'chn-benchgate-' + IntToStr(GetProcessID);
  ForceDirectories(Dir);
  Port := SockFreeLoopbackPort;
  Port104 := SockFreeLoopbackPort;
  WriteText(Dir + '/m.conf', 'listener ' + IntToStr(Port) + ' 127.0.0.1'#10'allow_anonymous true'#10 +
    'persistence false'#10);
  Broker := nil;
  Gate := nil;
  FloorProc := nil;
  MqttInit(Sub);
  try
    Broker := TProcess.Create(nil);
    Broker.Executable := ExeSearch('mosquitto', '/usr/sbin:/usr/bin:' + GetEnvironmentVariable('PATH'));
    Broker.Parameters.Add('-c');
    Broker.Parameters.Add(Dir + '/m.conf');
    Broker.Options := [poUsePipes, poStderrToOutPut];    { a few lines: the pipe never fills }
    Broker.Execute;
    OpenLines;
    { the reads per scan chngate plans }
    WriteText(Dir + '/gate.conf', GateConfig(ScanMs, True));
    RunCommand(Bin('chngate'), ['--check', Dir + '/gate.conf'], Check, [], swoNone);
    Reads := StrToIntDef(Trim(Copy(Check, Pos('tags, ', Check) + 6, Pos(' reads', Check) - Pos('tags, ', Check) - 6)), -1);
    Sub.Port := Port;
    MqttSubscribe(Sub, 'bench/+/+');
    if not MqttOpen(Sub, Err) then
      Fail(Err);
    Gate := StartGate(ScanMs, True);
    { the control centre, once the server listens }
    T0 := GetTickCount64 + 10000;
    repeat
      Serve(Sub, GetTickCount64 + 100, False);
      CentreChn := ChnCollection^.ChNewInit(ChnIec104.cName);
      CentreChn^.ChSetParam('NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port104) + ' RECON=200');
      if CentreChn^.ChResult = res_Ok then
        CentreChn^.ChOpen;
      if CentreChn^.ChResult = res_Ok then
        CentreChn^.ChConnect;
      if CentreChn^.ChResult = res_Ok then
        Break;
      Err := CentreChn^.ChErrorText;
      Dispose(CentreChn, Done);
      CentreChn := nil;
    until GetTickCount64 > T0;
    if (CentreChn = nil) or (IecMasterInit(Centre, CentreChn, IecDefaultParams) <> res_Ok) then
      Fail('IEC 104 control centre: ' + Err);
    Centre.OnObject := @OnObject;
    { settle: every tag read and published once }
    Serve(Sub, GetTickCount64 + 3000, False);
    { under load }
    for I := 0 to Lines - 1 do
    begin
      L[I].Busy0 := LineBusyUs(I);
      L[I].Requests := 0;
    end;
    C0 := ProcRunNs(Gate.ProcessID);
    T0 := ChnClockUs;
    Measuring := True;
    Serve(Sub, GetTickCount64 + QWord(LoadMs), True);
    T1 := ChnClockUs;
    C1 := ProcRunNs(Gate.ProcessID);
    LoadCpu := (C1 - C0) / ((T1 - T0) * 1000) * 100;
    Shares := '';
    Requests := 0;
    for I := 0 to Lines - 1 do
    begin
      Shares := Shares + Format(' %.0f', [100 * (LineBusyUs(I) - L[I].Busy0) / (T1 - T0)]);
      Inc(Requests, L[I].Requests);
    end;
    { the last changes' messages }
    Serve(Sub, GetTickCount64 + 2 * ScanMs + 500, False);
    Measuring := False;
    Lost := 0;
    for I := 0 to Changes - 1 do
      if not Arrived[I] then
        Inc(Lost);
    Lost104 := 0;
    for I := 0 to Changes - 1 do
      if not Arrived104[I] then
        Inc(Lost104);
    Rss := ProcRssKb(Gate.ProcessID);
    Map := ProcRssByMapping(Gate.ProcessID);
    Dispose(CentreChn, Done);
    CentreChn := nil;
    Stop(Gate);
    { idle: one read of everything, then nothing for 60 s (MQTT only, as
      the floor has one socket); measured once the $health of that first
      read went out (GateHealthMs after it), with the shortest MQTT
      keep-alive (5 s), so that the time measured holds several of the
      only wake-ups left: the keep-alive's ping and its answer }
    Gate := StartGate(60000, False, IdleKeepAlive);
    Serve(Sub, GetTickCount64 + GateHealthMs + 2000, False);
    AfterWake(Gate.ProcessID, Sub, (IdleKeepAlive + 2) * 1000);
    IdleCost(Gate.ProcessID, Sub, IdleMs, GateNs, GateSleeps);
    RssIdle := ProcRssKb(Gate.ProcessID);
    MapIdle := ProcRssByMapping(Gate.ProcessID);
    Stop(Gate);
    { the floor: the wait alone, woken as often as the gateway was }
    if GateSleeps > 0.01 then
      FloorMs := Round(1000 / GateSleeps)
    else
      FloorMs := 60000;
    FloorProc := StartFloor(['--floor', IntToStr(Lines + 1), IntToStr(FloorMs)]);
    Sleep(500);
    AfterWake(FloorProc.ProcessID, Sub, FloorMs + 1000);    { warm, as the gateway is }
    IdleCost(FloorProc.ProcessID, Sub, IdleMs, FloorNs, FloorSleeps);
    Stop(FloorProc);
    { the second floor: the same wait with the broker's socket one of its
      descriptors, the same session kept alive by libmosquitto itself }
    FloorProc := StartFloor(['--floor-mqtt', IntToStr(Lines), IntToStr(Port), IntToStr(IdleKeepAlive)]);
    Sleep(500);
    AfterWake(FloorProc.ProcessID, Sub, (IdleKeepAlive + 2) * 1000);
    IdleCost(FloorProc.ProcessID, Sub, IdleMs, MosqNs, MosqSleeps);
    Stop(FloorProc);

    WriteLn(Format('benchgate: %d DF1 lines at %d Bd x %d tags, scan %d ms: %d reads per scan planned ' +
      '(%d per line), %.1f requests per scan measured', [Lines, Bd, TagsPerLine, ScanMs, Reads,
      Reads div Lines, Requests / ((T1 - T0) / 1000 / ScanMs)]));
    WriteLn('benchgate: share of each line''s time used (%, both directions):' + Shares);
    WriteLn(Format('benchgate: change -> MQTT: %s; %d of %d changes not arrived',
      [Quantiles(ChangeLat, NChange), Lost, Changes]));
    WriteLn(Format('benchgate: wire -> MQTT:   %s', [Quantiles(WireLat, NWire)]));
    WriteLn(Format('benchgate: read -> MQTT:   %s', [Quantiles(ReadLat, NRead)]));
    WriteLn(Format('benchgate: change -> IEC 104: %s; %d of %d changes not arrived',
      [Quantiles(Lat104, N104), Lost104, Changes]));
    WriteLn(Format('benchgate: wire -> IEC 104:   %s', [Quantiles(Wire104, NWire104)]));
    WriteLn(Format('benchgate: change -> the request of the read that saw it: %s', [Quantiles(ToReq, NToReq)]));
    WriteLn(Format('benchgate: request -> its reply''s end: the block at N7:0 %s; the others %s',
      [Quantiles(ReqToEnd[True], NReqToEnd[True]), Quantiles(ReqToEnd[False], NReqToEnd[False])]));
    WriteLn(Format('benchgate: of it not wire time (the stations'' turnaround, this program served late): %s',
      [Quantiles(Late, NLate)]));
    WriteLn(Format('benchgate: a block''s reads, one to the next (scan %d ms): %s', [ScanMs, Quantiles(ReadGap, NReadGap)]));
    WriteLn(Format('benchgate: chngate CPU under load %.2f %% of a core', [LoadCpu]));
    if FloorNs > 0 then
      WriteLn(Format('benchgate: idle (keep-alive %d s): chngate %.1f us CPU/s, %.2f wake-ups/s; the wait alone (%d ' +
        'descriptors, ChnWaitAny(%d)) %.1f us/s, %.2f wake-ups/s; ratio %.2f',
        [IdleKeepAlive, GateNs / 1000, GateSleeps, Lines + 1, FloorMs, FloorNs / 1000, FloorSleeps, GateNs / FloorNs]))
    else
      WriteLn(Format('benchgate: idle: chngate %.1f us CPU/s, %.2f wake-ups/s; the wait alone %.1f us/s',
        [GateNs / 1000, GateSleeps, FloorNs / 1000]));
    if MosqNs > 0 then
      WriteLn(Format('benchgate: idle against the wait plus libmosquitto''s own keep-alive (%d descriptors, ' +
        'the broker''s socket one of them, ChnWaitAny(%d)): chngate %.1f us CPU/s, %.2f wake-ups/s; ' +
        'the floor %.1f us/s, %.2f wake-ups/s; ratio %.2f',
        [Lines + 1, (IdleKeepAlive + 1) * 1000, GateNs / 1000, GateSleeps, MosqNs / 1000, MosqSleeps, GateNs / MosqNs]));
    WriteLn(Format('benchgate: chngate RSS %d KiB with the IEC 104 server and a centre: %s', [Rss, Map]));
    WriteLn(Format('benchgate: chngate RSS %d KiB idle, MQTT only: %s', [RssIdle, MapIdle]));
  finally
    if CentreChn <> nil then
      Dispose(CentreChn, Done);
    Stop(FloorProc);
    Stop(Gate);
    MqttClose(Sub);
    CloseLines;
    Stop(Broker);
    DeleteFile(Dir + '/gate.conf');
    DeleteFile(Dir + '/m.conf');
    RemoveDir(Dir);
  end;
end.
