{ TestChngate104 - tools/chngate's IEC 104 north as it runs: df1sim on a
  pty as the PLC, two ptys nobody answers as a dead PLC (down) and a
  demoted one, the library's IEC 101 master helper over NAM=IEC104 as the
  control centre (and, when Debian's mosquitto is there, a broker with
  mosquitto_sub as a second north fed by the same changes).

  Worked out by hand from the configuration and df1sim's data table
  (tools/df1sim.conf): plc1's IOAs from 100 in tag order - N7:0[3] 100..102
  (0 10 20, scaled), run=B3:0/5 103 (B3:0 = 0001h: 0, single point), F8:0
  104 (1.5, float), L11:0 105 (100000, bitstring), sp=N7:5 106 (50), fl=F8:1
  107 (-2.25), T4:0 108..110 (control word 2000h = 8192, PRE 100, ACC 100),
  clock=S2:4 111 (bitstring), ST10:0 none, bad=N20:0 112 (no such file in
  df1sim: refused, IV); plc2 (down) 200 IV; plc3 (demoted) 300 IV + NT.
  A change (the free-running clock) comes as M_BO_TB_1 with a CP56 time
  of now; a set point reaches the PLC (its new value comes back from it)
  and its ACT_CON comes only after the PLC answered the write: with
  df1sim stopped (SIGSTOP) none comes until it runs again (SIGCONT), or a
  negative one when command_timeout passed; a PLC that refuses the write,
  a dead one and a demoted one give a negative ACT_CON; a tag that is not
  writable, an unknown IOA and a type the point does not take: COT 47.
  IEC 101 pass-through: examples/iec101slave on a pty it makes as the
  RTU (its clock 5000 s behind), its points at the device's offset (ioa =
  1000) with their own types (CP24 M_ME_TB_1 served as M_ME_TE_1), its
  quality (IV) kept, its time tags kept (CP56 as sent; CP24: the RTU's
  minute and ms, the hour nearest to now); its IOA 100 lands on a DF1
  device's 1100 and is refused (log, $gateway/error), the DF1 point stays;
  a command to offset + the RTU's command IOA goes to the RTU and its
  ACT_CON comes only after the RTU's (none while the RTU is stopped); a
  select goes as a select, the qualifier as sent; the RTU stopped long
  enough is dead: its points IV (event and interrogation), good again
  when it runs. }
unit TestChngate104;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestChngate104 = class(TTestCase)
  published
    {$IFDEF UNIX}
    procedure TestIec104North;
    procedure TestIec101PassThrough;
    {$ENDIF}
  end;

implementation

{$IFDEF UNIX}
uses
  BaseUnix, Process, DateUtils, PtyPair, ChildLine, MosquittoRun, Ser2netRun, BinSupport, TestTempDir, TestSupport,
  ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnIec101Asdu, ChnIec101Master;

type
  TCentre = class
    Objects: TStringList;
    Last: array of tIecObject;     { by IOA - 100, the last event }
    constructor Create;
    destructor Destroy; override;
  end;

constructor TCentre.Create;
begin
  Objects := TStringList.Create;
  SetLength(Last, 1200);
end;

destructor TCentre.Destroy;
begin
  Objects.Free;
  inherited Destroy;
end;

{ 'TYPE COT n IOA n = value Q hh' }
function Show(const H: tIecAsdu; const O: tIecObject): string;
var
  V: string;
begin
  case IecTypeKind(H.Ti) of
    ikFloat: V := FloatToStr(O.Number);
    ikBits: V := IntToStr(O.Bits);
  else
    V := IntToStr(O.Int);
  end;
  Result := Format('%s COT %d IOA %d = %s Q %.2x', [IecTypeName(H.Ti), H.Cot, O.Ioa, V, O.Quality]);
end;

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TCentre(Data).Objects.Add(Show(H, O));
  if (O.Ioa >= 100) and (O.Ioa < 1300) and (H.Cot = Cot_Spontaneous) then
    TCentre(Data).Last[O.Ioa - 100] := O;
end;

{ Step the master for Ms, or until a line starting with Prefix arrived. }
function Await(var M: tIecMaster; C: TCentre; const Prefix: string; Ms: LongInt): Boolean;
var
  Deadline: QWord;
  I, From: LongInt;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  From := 0;
  repeat
    for I := From to C.Objects.Count - 1 do
      if (Prefix <> '') and (Pos(Prefix, C.Objects[I]) = 1) then
        Exit(True);
    From := C.Objects.Count;
    IecMasterStep(M);
    ChnWaitAny(10);
  until GetTickCount64 > Deadline;
  Result := False;
end;

{ The answers to a station interrogation, one line each. }
function Interrogated(var M: tIecMaster; C: TCentre; Ca: Word): string;
var
  K: LongInt;
begin
  C.Objects.Clear;
  TAssert.AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 0, Ca, Qoi_Station));
  Result := '';
  for K := 0 to C.Objects.Count - 1 do
    if Pos(' COT 20 ', C.Objects[K]) > 0 then
      Result := Result + C.Objects[K] + LineEnding;
end;

{ chngate on Conf, listening on Port, and the control centre connected to
  it (the master helper over NAM=IEC104, objects into C). }
function StartGateway(const Conf: string; Port: Word; var M: tIecMaster; C: TCentre;
  out Chn: pChnVirt): TProcess;
var
  Deadline: QWord;
  Err: string;
begin
  Chn := nil;
  Result := TProcess.Create(nil);
  BinExecutable(Result, BinPath('chngate'));
  Result.Parameters.Add(Conf);
  Result.Options := [poUsePipes, poStderrToOutPut];
  Result.Execute;
  Deadline := GetTickCount64 + 5000;
  while not PortTaken(Port) and (GetTickCount64 < Deadline) do
    Sleep(20);
  TAssert.AssertTrue('the gateway listens on ' + IntToStr(Port), PortTaken(Port));
  Chn := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port) + ' RECON=200', Err);
  TAssert.AssertNotNull(Err, Chn);
  TAssert.AssertEquals('master', res_Ok, IecMasterInit(M, Chn, IecDefaultParams));
  M.CommandMs := 8000;
  M.OnObject := @OnObj;
  M.Data := C;
end;

{ Command Ti with O while the device below (process Pid) is stopped: no
  ACT_CON in 1 s; then it runs again and the ACT_CON (positive) follows.
  The ms from SIGCONT to it. }
function ConfirmedAfterResume(var M: tIecMaster; Pid: LongInt; Ca: Word; Ti: Byte; const O: tIecObject): QWord;
var
  Stopped, Resumed: QWord;
  R: tChResult;
begin
  FpKill(Pid, SIGSTOP);
  Stopped := GetTickCount64;
  TAssert.AssertTrue(M.Cmd.Err, IecStartCommand(M, 0, Ca, Ti, O, False));
  while GetTickCount64 < Stopped + 1000 do
  begin
    IecMasterStep(M);
    ChnWaitAny(10);
  end;
  TAssert.AssertFalse('no ACT_CON while the device below is stopped', IecCommandDone(M));
  FpKill(Pid, SIGCONT);
  Resumed := GetTickCount64;
  R := IecFinish(M);
  Result := GetTickCount64 - Resumed;
  TAssert.AssertEquals(IecTypeName(Ti) + ' after SIGCONT ' + M.Cmd.Err, res_Ok, R);
end;

{ Stop P (SIGCONT first: it may be stopped) and free it. }
procedure Ended(var P: TProcess);
begin
  if (P <> nil) and P.Running then
  begin
    FpKill(P.ProcessID, SIGCONT);
    FpKill(P.ProcessID, SIGTERM);
    P.WaitOnExit;
  end;
  FreeAndNil(P);
end;

procedure TTestChngate104.TestIec104North;
const
  Ca = 7;
  Expected: array[0..14] of string = ('M_ME_NB_1 COT 20 IOA 100 = 0 Q 00', 'M_ME_NB_1 COT 20 IOA 101 = 10 Q 00',
    'M_ME_NB_1 COT 20 IOA 102 = 20 Q 00', 'M_SP_NA_1 COT 20 IOA 103 = 0 Q 00',
    'M_ME_NC_1 COT 20 IOA 104 = 1.5 Q 00', 'M_BO_NA_1 COT 20 IOA 105 = 100000 Q 00',
    'M_ME_NB_1 COT 20 IOA 106 = 50 Q 00', 'M_ME_NC_1 COT 20 IOA 107 = -2.25 Q 00',
    'M_ME_NB_1 COT 20 IOA 108 = 8192 Q 00', 'M_ME_NB_1 COT 20 IOA 109 = 100 Q 00',
    'M_ME_NB_1 COT 20 IOA 110 = 100 Q 00', 'M_BO_NA_1 COT 20 IOA 111 = ',
    'M_ME_NB_1 COT 20 IOA 112 = 0 Q 80', 'M_ME_NB_1 COT 20 IOA 200 = 0 Q 80',
    'M_ME_NB_1 COT 20 IOA 300 = 0 Q C0');
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  Sim, Gate: TProcess;
  Dead, Demoted: TPtyPair;
  Dir, Pty, Conf, Gi, Err, Mqtt, Log: string;
  Port: Word;
  Chn: pChnVirt;
  M: tIecMaster;
  C: TCentre;
  O: tIecObject;
  T: TDateTime;
  Stopped, Resumed, Done_, Deadline, AfterCont, TimedOut: QWord;
  R: tChResult;

  { what the gateway logged so far }
  function Logged: string;
  var
    N: LongInt;
    Buf: string;
  begin
    while (Gate <> nil) and (Gate.Output.NumBytesAvailable > 0) do
    begin
      SetLength(Buf, Gate.Output.NumBytesAvailable);
      N := Gate.Output.Read(Buf[1], Length(Buf));
      Log := Log + Copy(Buf, 1, N);
    end;
    Result := Log;
  end;

begin
  Dir := MakeTempDir('chn-gate104');
  Log := '';
  Broker := nil;
  Sub := nil;
  Gate := nil;
  Chn := nil;
  C := TCentre.Create;
  Dead := TPtyPair.Create;
  Demoted := TPtyPair.Create;
  Sim := StartSimPty(['--quiet', '--timeout=60'], Pty);
  try
    AssertTrue('df1sim pty', Pty <> '');
    Mqtt := '';
    if MosquittoMissing = '' then
    begin
      Broker := TMosquitto.Create;
      Sub := TMqttSub.Create(Broker.Port, 'plant/plc1/sp', []);
      Mqtt := '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10#10;
    end;
    Port := FreeLoopbackPort;
    Conf := Dir + '/g.conf';
    WriteFileText(Conf, Mqtt +
      '[iec104]'#10'listen = 127.0.0.1:' + IntToStr(Port) + #10'ca = ' + IntToStr(Ca) + #10 +
      'command_timeout = 2500'#10#10 +
      '[device plc1]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty + #10 +
      'tags = N7:0[3] run=B3:0/5 F8:0 L11:0 sp=N7:5 fl=F8:1 T4:0 clock=S2:4@200 ST10:0 bad=N20:0'#10 +
      'scan = 300'#10'timeout = 3000'#10'write = run sp fl bad'#10'ioa = 100'#10#10 +
      '[device plc2]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Dead.SlavePath + #10 +
      'tags = N7:0'#10'write = N7:0'#10'scan = 200'#10'timeout = 100'#10'fails = 1000'#10'ioa = 200'#10#10 +
      '[device plc3]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Demoted.SlavePath + #10 +
      'tags = N7:0'#10'write = N7:0'#10'timeout = 100'#10'fails = 1'#10'demote = 60000'#10'ioa = 300'#10);
    AssertEquals('--check', 0, RunBin('chngate', ['--check', Conf], 5000, Err));
    AssertTrue(Err, Pos('3 devices, 12 tags, ', Err) > 0);
    AssertTrue(Err, Pos(', 15 IEC 104 points', Err) > 0);
    Gate := StartGateway(Conf, Port, M, C, Chn);
    AssertTrue('end of initialisation: ' + C.Objects.Text, Await(M, C, 'M_EI_NA_1 COT 4 IOA 0 = 0', 5000));
    { interrogation, until every device has its state (plc1 read, plc3 demoted) }
    Deadline := GetTickCount64 + 10000;
    repeat
      Gi := Interrogated(M, C, Ca);
    until ((Pos('IOA 100 = 0 Q 00', Gi) > 0) and (Pos('IOA 300 = 0 Q C0', Gi) > 0) and
      (Pos('IOA 200 = 0 Q 80', Gi) > 0)) or (GetTickCount64 > Deadline);
    for Err in Expected do
      AssertTrue('interrogation has "' + Err + '":'#10 + Gi, Pos(Err, Gi) > 0);
    AssertEquals('15 points, nothing else:'#10 + Gi, 15, Length(Gi.Split([LineEnding],
      TStringSplitOptions.ExcludeEmpty)));
    { the clock changes: spontaneous, bitstring with a CP56 time of now }
    C.Objects.Clear;
    AssertTrue('clock event: ' + C.Objects.Text, Await(M, C, 'M_BO_TB_1 COT 3 IOA 111 = ', 3000));
    AssertTrue('CP56 time', IecTimeToDateTime(C.Last[11].Time, T));
    AssertTrue('the time of the change: ' + DateTimeToStr(T) + ' now ' + DateTimeToStr(Now),
      Abs(MilliSecondsBetween(T, Now)) < 3000);
    { a set point to sp (N7:5): confirmed, and the PLC's new value follows }
    O := IecObject(106);
    O.Int := 1234;
    AssertEquals('C_SE_NB_1 ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    AssertTrue('sp from the PLC: ' + C.Objects.Text, Await(M, C, 'M_ME_TE_1 COT 3 IOA 106 = 1234 Q 00', 3000));
    if Sub <> nil then
      AssertTrue('and on MQTT: ' + Sub.Text, Sub.WaitFor('plant/plc1/sp {"value":1234,"quality":"good"', 5000));
    { a single command to the bit run (B3:0/5) }
    O := IecObject(103);
    O.Int := 1;
    AssertEquals('C_SC_NA_1 ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SC_NA_1, O, False));
    AssertTrue('run from the PLC: ' + C.Objects.Text, Await(M, C, 'M_SP_TB_1 COT 3 IOA 103 = 1 Q 00', 3000));
    { the PLC stopped: no ACT_CON until it runs again and answered }
    O := IecObject(107);
    O.Number := 2.5;
    AfterCont := ConfirmedAfterResume(M, Sim.ProcessID, Ca, C_SE_NC_1, O);
    AssertTrue('fl from the PLC: ' + C.Objects.Text, Await(M, C, 'M_ME_TF_1 COT 3 IOA 107 = 2.5 Q 00', 3000));
    { stopped longer than command_timeout (2.5 s): negative }
    FpKill(Sim.ProcessID, SIGSTOP);
    Stopped := GetTickCount64;
    O := IecObject(106);
    O.Int := 7;
    R := IecCommand(M, 0, Ca, C_SE_NB_1, O, False);
    Done_ := GetTickCount64;
    TimedOut := Done_ - Stopped;
    FpKill(Sim.ProcessID, SIGCONT);
    AssertEquals('no answer in time: negative ' + M.Cmd.Err, res_IecNegative, R);
    AssertTrue(Format('after command_timeout: %d ms', [Done_ - Stopped]), (Done_ - Stopped >= 2400) and
      (Done_ - Stopped < 7000));
    { the PLC refuses the write (no file N20): negative }
    O := IecObject(112);
    O.Int := 1;
    AssertEquals('refused by the PLC ' + M.Cmd.Err, res_IecNegative, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    { a dead PLC (down) and a demoted one: negative }
    O := IecObject(200);
    AssertEquals('dead PLC ' + M.Cmd.Err, res_IecNegative, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    O := IecObject(300);
    AssertEquals('demoted PLC ' + M.Cmd.Err, res_IecNegative, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    { not writable, unknown, another type: COT 47 }
    O := IecObject(100);
    AssertEquals('N7:0 is not writable', res_IecUnknownIoa, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    O := IecObject(999);
    AssertEquals('no IOA 999', res_IecUnknownIoa, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    O := IecObject(106);
    O.Number := 1;
    AssertEquals('a float to a word', res_IecUnknownIoa, IecCommand(M, 0, Ca, C_SE_NC_1, O, False));
    { the CP56 form of a set point is taken too }
    O.Int := 99;
    O.Time := IecTimeFromDateTime(Now);
    AssertEquals('C_SE_TB_1 ' + M.Cmd.Err + #10 + Logged, res_Ok, IecCommand(M, 0, Ca, C_SE_TB_1, O, False));
    AssertTrue('sp 99 from the PLC: ' + C.Objects.Text, Await(M, C, 'M_ME_TE_1 COT 3 IOA 106 = 99 Q 00', 3000));
    { SIGHUP: the table is built anew on the same connection; the centre is told }
    C.Objects.Clear;
    FpKill(Gate.ProcessID, SIGHUP);
    AssertTrue('end of initialisation, COI 1 + local change: ' + C.Objects.Text,
      Await(M, C, 'M_EI_NA_1 COT 4 IOA 0 = 129', 5000));
    Deadline := GetTickCount64 + 5000;
    repeat
      Gi := Interrogated(M, C, Ca);
    until (Pos('M_ME_NB_1 COT 20 IOA 106 = 99 Q 00', Gi) > 0) or (GetTickCount64 > Deadline);
    AssertTrue('after SIGHUP:'#10 + Gi, Pos('M_ME_NB_1 COT 20 IOA 106 = 99 Q 00', Gi) > 0);
    { the reasons, in the gateway's log }
    AssertTrue(Logged, Pos('IOA 106 (plc1 sp := 7): no confirmation from the PLC in 2500 ms', Logged) > 0);
    AssertTrue(Logged, Pos('IOA 112 (plc1 bad := 1): N20:0: error reply STS', Logged) > 0);
    AssertTrue(Logged, Pos('IOA 200 (plc2 N7:0 := 0): N7:0: no ACK', Logged) > 0);
    AssertTrue(Logged, Pos('IOA 300 (plc3 N7:0 := 0): refused, plc3 is demoted', Logged) > 0);
    if GetEnvironmentVariable('CHN_GATE104_LOG') <> '' then
      WriteLn(StdErr, Format('ACT_CON %d ms after SIGCONT, negative ACT_CON %d ms after the command',
        [AfterCont, TimedOut]), LineEnding, Logged);
  finally
    if Chn <> nil then
      Dispose(Chn, Done);
    Ended(Gate);
    Sub.Free;
    Ended(Sim);
    Dead.Free;
    Demoted.Free;
    Broker.Free;
    C.Free;
    RemoveTempDir(Dir);
  end;
end;

{ Read what P wrote so far onto Log. }
function Drained(P: TProcess; var Log: string): string;
var
  N: LongInt;
  Buf: string;
begin
  while (P <> nil) and (P.Output.NumBytesAvailable > 0) do
  begin
    SetLength(Buf, P.Output.NumBytesAvailable);
    N := P.Output.Read(Buf[1], Length(Buf));
    Log := Log + Copy(Buf, 1, N);
  end;
  Result := Log;
end;

{ ms of the hour of a time (minute, second, ms): a CP24 tag's part. }
function MsOfHour(T: TDateTime): LongInt;
begin
  Result := MinuteOf(T) * 60000 + SecondOf(T) * 1000 + MilliSecondOf(T);
end;

procedure TTestChngate104.TestIec101PassThrough;
const
  Ca = 7;
  { the RTU's clock runs 5000 s (1 h 23 min 20 s) behind }
  OffsetMs = -5000000;
  Expected: array[0..5] of string = ('M_ME_NC_1 COT 20 IOA 1101 = 1.5 Q 00',
    'M_ME_TE_1 COT 20 IOA 1102 = 7 Q 00', 'M_ME_TE_1 COT 20 IOA 1103 = 5 Q 00', 'M_SP_NA_1 COT 20 IOA 1104 = 1 Q 80',
    'M_DP_NA_1 COT 20 IOA 1105 = 2 Q 00', 'M_ME_NB_1 COT 20 IOA 1100 = 0 Q ');
var
  Rtu, Gate: TProcess;
  Broker: TMosquitto;
  Sub: TMqttSub;
  Dead: TPtyPair;
  Dir, RtuPty, Conf, Gi, Err, Mqtt, RtuLog, GateLog: string;
  Port: Word;
  Chn: pChnVirt;
  M: tIecMaster;
  C: TCentre;
  O: tIecObject;
  T, Rtc: TDateTime;
  Deadline, AfterCont, SelectCont: QWord;
  Off: LongInt;
begin
  AssertTrue(BinPath('iec101slave') + ' missing (make examples)', FileExists(BinPath('iec101slave')));
  Dir := MakeTempDir('chn-gate104r');
  Gate := nil;
  Chn := nil;
  Broker := nil;
  Sub := nil;
  RtuLog := '';
  GateLog := '';
  C := TCentre.Create;
  Dead := TPtyPair.Create;
  WriteFileText(Dir + '/rtu.txt', '100 M_ME_NB_1 -1'#10'101 M_ME_NC_1 1.5'#10'102 M_ME_TB_1 7'#10 +
    '103 M_ME_TE_1 5'#10'104 M_SP_NA_1 1 IV'#10'105 M_DP_NA_1 2'#10'5000 C_SC_NA_1 0'#10'5101 C_SE_NC_1 0'#10 +
    '5102 C_SE_NB_1 0'#10'5103 C_SE_NB_1 0'#10);
  Rtu := TProcess.Create(nil);
  BinExecutable(Rtu, BinPath('iec101slave'));
  Rtu.Parameters.Add('--points=' + Dir + '/rtu.txt');
  Rtu.Parameters.Add('--return=5000=104,5101=101,5102=102,5103=103');
  Rtu.Parameters.Add('--clock-offset=' + IntToStr(OffsetMs));
  Rtu.Parameters.Add('--seconds=90');
  Rtu.Parameters.Add('NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DRV=PTY');
  Rtu.Options := [poUsePipes, poStderrToOutPut];
  Rtu.Execute;
  try
    RtuPty := ReadFirstLine(Rtu, 5000);
    AssertEquals('iec101slave: PTY /dev/', Copy(RtuPty, 1, 22));
    RtuPty := Copy(RtuPty, 18, MaxInt);
    Mqtt := '';
    if MosquittoMissing = '' then
    begin
      Broker := TMosquitto.Create;
      Sub := TMqttSub.Create(Broker.Port, 'plant/$gateway/error', []);
      Mqtt := '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10#10;
    end;
    Port := FreeLoopbackPort;
    Conf := Dir + '/g.conf';
    { plc9 (a PLC nobody answers) takes IOA 1100: the RTU's point 100 lands
      there (1000 + 100) and is refused, plc9's point stays }
    WriteFileText(Conf, Mqtt + '[iec104]'#10'listen = 127.0.0.1:' + IntToStr(Port) + #10'ca = ' + IntToStr(Ca) + #10#10 +
      '[device plc9]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Dead.SlavePath + #10 +
      'tags = N7:0'#10'timeout = 100'#10'fails = 1000'#10'ioa = 1100'#10#10 +
      '[device rtu1]'#10'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=' + RtuPty + #10 +
      'points = pump=104 level=101'#10'write = pump>5000 level>5101 102>5102 103>5103'#10 +
      'timeout = 1500'#10'demote = 1000'#10'ioa = 1000'#10);
    AssertEquals('--check', 0, RunBin('chngate', ['--check', Conf], 5000, Err));
    Gate := StartGateway(Conf, Port, M, C, Chn);
    { the RTU's points, once the gateway's master has interrogated it }
    Deadline := GetTickCount64 + 10000;
    repeat
      Gi := Interrogated(M, C, Ca);
    until (Pos('IOA 1105 = 2', Gi) > 0) and (Pos('IOA 1103 = 5', Gi) > 0) or (GetTickCount64 > Deadline);
    for Err in Expected do
      AssertTrue('interrogation has "' + Err + '":'#10 + Gi, Pos(Err, Gi) > 0);
    { the RTU's IOA 100 on plc9's 1100: refused, said, never overwritten }
    AssertEquals('1100 stays plc9''s:'#10 + Gi, 0, Pos('IOA 1100 = -1', Gi));
    Err := 'rtu1 100: not served: IEC 104 IOA 1100 (ioa 1000 + 100) is plc9 N7:0''s';
    Deadline := GetTickCount64 + 3000;
    while (Pos(Err, Drained(Gate, GateLog)) = 0) and (GetTickCount64 < Deadline) do
      Sleep(20);
    AssertTrue('the refusal in the log: ' + GateLog, Pos(Err, GateLog) > 0);
    if Sub <> nil then
      AssertTrue('and on $gateway/error: ' + Sub.Text, Sub.WaitFor('{"topic":"plant/rtu1/100","error":"' +
        Err + '"}', 5000));
    { not writable: COT 47 }
    O := IecObject(1100);
    AssertEquals('1100 is not writable', res_IecUnknownIoa, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    { the RTU's time tags kept: a CP24 one (its minute and ms, the hour
      nearest to now) and a CP56 one as they are - not the gateway's clock }
    O := IecObject(6102);
    O.Int := 42;
    C.Objects.Clear;
    AssertEquals('C_SE_NB_1 ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    AssertTrue('102 from the RTU: ' + C.Objects.Text, Await(M, C, 'M_ME_TE_1 COT 3 IOA 1102 = 42 Q 00', 3000));
    Rtc := IncMilliSecond(Now, OffsetMs);
    AssertTrue('a CP56 time', IecTimeToDateTime(C.Last[1002].Time, T));
    Off := Abs(MsOfHour(T) - MsOfHour(Rtc));
    AssertTrue(Format('the RTU''s minute and ms: %s, the RTU''s clock %s', [FormatDateTime('hh:nn:ss.zzz', T),
      FormatDateTime('hh:nn:ss.zzz', Rtc)]), (Off < 5000) or (Off > 3600000 - 5000));
    AssertTrue('completed to the hour nearest to the arrival: ' + DateTimeToStr(T) + ' UTC now ' +
      DateTimeToStr(LocalTimeToUniversal(Now)), Abs(SecondsBetween(T, LocalTimeToUniversal(Now))) <= 1805);
    O := IecObject(6103);
    O.Int := 43;
    AssertEquals('C_SE_NB_1 ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SE_NB_1, O, False));
    AssertTrue('103 from the RTU: ' + C.Objects.Text, Await(M, C, 'M_ME_TE_1 COT 3 IOA 1103 = 43 Q 00', 3000));
    AssertTrue('a CP56 time', IecTimeToDateTime(C.Last[1003].Time, T));
    Rtc := IncMilliSecond(Now, OffsetMs);
    AssertTrue(Format('the RTU''s time %s, its clock %s', [DateTimeToStr(T), DateTimeToStr(Rtc)]),
      Abs(MilliSecondsBetween(T, Rtc)) < 5000);
    { select before operate, with a qualifier (QU 1, short pulse): the
      select reaches the RTU as a select, the execute as an execute, both
      with QU 1 }
    O := IecObject(6000);
    O.Int := 0;
    O.Qu := 1;
    C.Objects.Clear;
    AssertEquals('C_SC_NA_1 select + execute ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SC_NA_1, O, True));
    AssertTrue('pump from the RTU: ' + C.Objects.Text, Await(M, C, 'M_SP_NA_1 COT 3 IOA 1104 = 0 Q 00', 3000));
    Deadline := GetTickCount64 + 3000;
    while (Pos('<- C_SC_NA_1 ACTIVATION CA 1 IOA 5000 = off execute QU 1', Drained(Rtu, RtuLog)) = 0) and
      (GetTickCount64 < Deadline) do
      Sleep(20);
    AssertTrue('the RTU got the select: ' + RtuLog, Pos('<- C_SC_NA_1 ACTIVATION CA 1 IOA 5000 = off select QU 1',
      RtuLog) > 0);
    AssertTrue('and the execute: ' + RtuLog, Pos('<- C_SC_NA_1 ACTIVATION CA 1 IOA 5000 = off execute QU 1',
      RtuLog) > 0);
    { the RTU stopped: no ACT_CON for the select until it runs again and
      confirmed the select; then the execute }
    O := IecObject(6101);
    O.Number := 3.25;
    O.Select := True;
    O.Qu := 5;
    SelectCont := ConfirmedAfterResume(M, Rtu.ProcessID, Ca, C_SE_NC_1, O);
    O.Select := False;
    AssertEquals('execute ' + M.Cmd.Err, res_Ok, IecCommand(M, 0, Ca, C_SE_NC_1, O, False));
    AssertTrue('level from the RTU: ' + C.Objects.Text, Await(M, C, 'M_ME_NC_1 COT 3 IOA 1101 = 3.25 Q 00', 3000));
    Drained(Rtu, RtuLog);
    AssertTrue('QL 5 reached the RTU: ' + RtuLog, Pos('IOA 5101 = 3.25 select QL 5', RtuLog) > 0);
    { and an execute alone, while the RTU is stopped }
    O.Number := 4.5;
    O.Qu := 0;
    AfterCont := ConfirmedAfterResume(M, Rtu.ProcessID, Ca, C_SE_NC_1, O);
    AssertTrue('level from the RTU: ' + C.Objects.Text, Await(M, C, 'M_ME_NC_1 COT 3 IOA 1101 = 4.5 Q 00', 3000));
    { the RTU dead: its points go IV, spontaneously and in an interrogation;
      good again when it is back }
    C.Objects.Clear;
    FpKill(Rtu.ProcessID, SIGSTOP);
    AssertTrue('IV event: ' + C.Objects.Text, Await(M, C, 'M_ME_NC_1 COT 3 IOA 1101 = 4.5 Q 80', 15000));
    Gi := Interrogated(M, C, Ca);
    AssertTrue('IV in the interrogation:'#10 + Gi, (Pos('M_ME_NC_1 COT 20 IOA 1101 = 4.5 Q 80', Gi) > 0) and
      (Pos('M_DP_NA_1 COT 20 IOA 1105 = 2 Q 80', Gi) > 0) and (Pos('M_ME_TE_1 COT 20 IOA 1103 = 43 Q 80', Gi) > 0));
    C.Objects.Clear;
    FpKill(Rtu.ProcessID, SIGCONT);
    AssertTrue('good again: ' + C.Objects.Text, Await(M, C, 'M_ME_NC_1 COT 3 IOA 1101 = 4.5 Q 00', 15000));
    Deadline := GetTickCount64 + 10000;
    repeat
      Gi := Interrogated(M, C, Ca);
    until (Pos('IOA 1105 = 2 Q 00', Gi) > 0) or (GetTickCount64 > Deadline);
    AssertTrue('good in the interrogation:'#10 + Gi, (Pos('M_ME_NC_1 COT 20 IOA 1101 = 4.5 Q 00', Gi) > 0) and
      (Pos('M_DP_NA_1 COT 20 IOA 1105 = 2 Q 00', Gi) > 0));
    if GetEnvironmentVariable('CHN_GATE104_LOG') <> '' then
      WriteLn(StdErr, Format('RTU: select ACT_CON %d ms, execute ACT_CON %d ms after SIGCONT',
        [SelectCont, AfterCont]), LineEnding, Drained(Gate, GateLog));
  finally
    if Chn <> nil then
      Dispose(Chn, Done);
    Ended(Gate);
    Ended(Rtu);
    Sub.Free;
    Broker.Free;
    Dead.Free;
    C.Free;
    RemoveTempDir(Dir);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChngate104);
end.
