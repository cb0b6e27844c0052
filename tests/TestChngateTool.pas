{ TestChngateTool - tools/chngate as it runs: df1sim on a pty as a live
  PLC, a pty nobody answers as a dead one, Debian's mosquitto on a free
  loopback port, mosquitto_sub and mosquitto_pub as the IT side. Values
  arrive with their value and quality, a set reaches the PLC and its new
  value comes back, a command to a read-only tag is refused on the error
  topic, the dead device turns down, bad and demoted while the live one
  keeps its rate, SIGKILL leaves the broker's last will (offline); and
  --check. Skipped, with the reason, without mosquitto. }
unit TestChngateTool;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestChngateTool = class(TTestCase)
  published
    procedure TestCheck;
    {$IFDEF UNIX}
    procedure TestGatewayEndToEnd;
    procedure TestPlc5Device;
    procedure TestMissingLibrary;
    procedure TestWrongPasswordLogged;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, PtyPair, MosquittoRun, TestSupport,{$ENDIF}
  Process, BinSupport, TestTempDir;

procedure TTestChngateTool.TestCheck;
var
  Dir, Output: string;
  Code: LongInt;
begin
  AssertTrue(BinPath('chngate') + ' missing (make tools)', FileExists(BinPath('chngate')));
  Dir := MakeTempDir('chn-gate');
  try
    WriteFileText(Dir + '/g.conf', '[mqtt]'#10'prefix = plant'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'tags = N7:0[10] N7:20 F8:0'#10);
    Code := RunBin('chngate', ['--check', Dir + '/g.conf'], 5000, Output);
    AssertEquals('good: exit 0'#10 + Output, 0, Code);
    AssertEquals(Dir + '/g.conf: good: 1 devices, 3 tags, 2 reads per scan' + LineEnding, Output);
    { maxread: reads of at most 20 bytes: N7:0[10] fills one, N7:20 (merged
      with it up to 244 bytes) takes a read of its own }
    WriteFileText(Dir + '/m.conf', '[mqtt]'#10'prefix = plant'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'tags = N7:0[10] N7:20 F8:0'#10'maxread = 20'#10);
    Code := RunBin('chngate', ['--check', Dir + '/m.conf'], 5000, Output);
    AssertEquals(Dir + '/m.conf: good: 1 devices, 3 tags, 3 reads per scan' + LineEnding, Output);
    WriteFileText(Dir + '/m.conf', '[mqtt]'#10'prefix = plant'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'tags = N7:0'#10'maxread = 245'#10);
    Code := RunBin('chngate', ['--check', Dir + '/m.conf'], 5000, Output);
    AssertEquals('maxread 245: exit 2'#10 + Output, 2, Code);
    AssertTrue('the maxread'#10 + Output, Pos(Dir + '/m.conf:7: [device plc1] maxread: "245" is not a whole number 2..244', Output) > 0);
    WriteFileText(Dir + '/b.conf', '[mqtt]'#10'prefix = plant'#10'port = x'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'tags = N7:0[10] X9:1'#10);
    Code := RunBin('chngate', ['--check', Dir + '/b.conf'], 5000, Output);
    AssertEquals('bad: exit 2'#10 + Output, 2, Code);
    AssertTrue('the port'#10 + Output, Pos(Dir + '/b.conf:3: [mqtt] port: "x" is not a whole number 1..65535', Output) > 0);
    AssertTrue('the tag'#10 + Output, Pos(Dir + '/b.conf:7: [device plc1] tags: "X9:1": ', Output) > 0);
    { a bad configuration opens nothing, also without --check }
    Code := RunBin('chngate', [Dir + '/b.conf'], 5000, Output);
    AssertEquals('bad, run: exit 2'#10 + Output, 2, Code);
    { the example the repository ships (and make install installs) }
    Code := RunBin('chngate', ['--check', 'tools/chngate.conf'], 5000, Output);
    AssertEquals('tools/chngate.conf: exit 0'#10 + Output, 0, Code);
    AssertEquals('tools/chngate.conf: good: 1 devices, 5 tags, 5 reads per scan, 14 IEC 104 points' + LineEnding, Output);
    { family = plc5: PLC-5 addresses; an SLC device refuses them }
    WriteFileText(Dir + '/p.conf', '[mqtt]'#10'prefix = plant'#10#10'[device p5]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'family = plc5'#10'tags = I:012/05 D10:0[2]'#10);
    Code := RunBin('chngate', ['--check', Dir + '/p.conf'], 5000, Output);
    AssertEquals('plc5: exit 0'#10 + Output, 0, Code);
    AssertEquals(Dir + '/p.conf: good: 1 devices, 2 tags, 2 reads per scan' + LineEnding, Output);
    WriteFileText(Dir + '/p.conf', '[mqtt]'#10'prefix = plant'#10#10'[device p5]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'family = plc6'#10'tags = D10:0 L11:0'#10);
    Code := RunBin('chngate', ['--check', Dir + '/p.conf'], 5000, Output);
    AssertEquals('plc6: exit 2'#10 + Output, 2, Code);
    AssertTrue('the family'#10 + Output, Pos(Dir + '/p.conf:6: [device p5] family: "plc6" is neither slc', Output) > 0);
    AssertTrue('D10:0 is no SLC address'#10 + Output, Pos(Dir + '/p.conf:7: [device p5] tags: "D10:0": ', Output) > 0);
    WriteFileText(Dir + '/p.conf', '[mqtt]'#10'prefix = plant'#10#10'[device p5]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0'#10'family = plc5'#10'tags = L11:0'#10);
    Code := RunBin('chngate', ['--check', Dir + '/p.conf'], 5000, Output);
    AssertTrue('L11:0 is no PLC-5 address'#10 + Output, Pos(Dir + '/p.conf:7: [device p5] tags: "L11:0": ', Output) > 0);
    Code := RunBin('chngate', [Dir + '/none.conf'], 5000, Output);
    AssertEquals('missing file: exit 2'#10 + Output, 2, Code);
    AssertTrue('says so'#10 + Output, Pos('none.conf: cannot be read', Output) > 0);
  finally
    RemoveTempDir(Dir);
  end;
end;

{$IFDEF UNIX}

{ chngate CONF, its output in a pipe }
function StartGate(const Conf: string): TProcess;
begin
  Result := TProcess.Create(nil);
  BinExecutable(Result, BinPath('chngate'));
  Result.Parameters.Add(Conf);
  Result.Options := [poUsePipes, poStderrToOutPut];
  Result.Execute;
end;

procedure TTestChngateTool.TestGatewayEndToEnd;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  Sim, Gate: TProcess;
  Dead: TPtyPair;
  Dir, Pty, Before: string;
  Clocks: LongInt;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Dir := MakeTempDir('chn-gate');
  Broker := TMosquitto.Create;
  Sub := nil;
  Gate := nil;
  Dead := TPtyPair.Create;
  Sim := StartSimPty(['--quiet', '--timeout=60'], Pty);
  try
    AssertTrue('df1sim pty', Pty <> '');
    WriteFileText(Dir + '/g.conf',
      '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10#10 +
      '[device plc1]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty + #10 +
      'tags = N7:0[3] clock=S2:4@200 run=B3:0/5 F8:0'#10'scan = 300'#10'write = run'#10#10 +
      '[device plc2]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Dead.SlavePath + #10 +
      'tags = N7:0'#10'scan = 200'#10'timeout = 100'#10'fails = 2'#10'demote = 500'#10);
    Sub := TMqttSub.Create(Broker.Port, 'plant/#', []);
    Sleep(200);
    Gate := StartGate(Dir + '/g.conf');
    { values, with their quality }
    AssertTrue('N7:0[3]: ' + Sub.Text,
      Sub.WaitFor('plant/plc1/N7:0[3] {"value":[0,10,20],"quality":"good","ts":"', 10000));
    AssertTrue('F8:0: ' + Sub.Text, Sub.WaitFor('plant/plc1/F8:0 {"value":1.5,"quality":"good"', 5000));
    AssertTrue('run: ' + Sub.Text, Sub.WaitFor('plant/plc1/run {"value":false,"quality":"good"', 5000));
    AssertTrue('online: ' + Sub.Text, Sub.WaitFor('plant/$gateway/status online', 5000));
    { the dead one: down and bad, then demoted }
    AssertTrue('plc2 bad: ' + Sub.Text, Sub.WaitFor('plant/plc2/N7:0 {"value":null,"quality":"bad"', 10000));
    AssertTrue('plc2 down: ' + Sub.Text, Sub.WaitFor('plant/plc2/$health {"state":"down"', 5000));
    AssertTrue('plc2 demoted: ' + Sub.Text, Sub.WaitFor('plant/plc2/$health {"state":"demoted"', 5000));
    { meanwhile the live one keeps its 200 ms clock: about 10 changes in 2 s }
    Before := Sub.Text;
    Sleep(2000);
    Clocks := CountOf('plant/plc1/clock {', Sub.Text) - CountOf('plant/plc1/clock {', Before);
    AssertTrue(Format('plc1 clock changes in 2 s while plc2 is demoted: %d', [Clocks]), Clocks >= 7);
    { a set reaches the PLC; its new value comes back from it }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/plc1/run/set', 'true'));
    AssertTrue('run back: ' + Sub.Text, Sub.WaitFor('plant/plc1/run {"value":true,"quality":"good"', 5000));
    { a read-only tag: refused, with the reason }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/plc1/F8:0/set', '2'));
    AssertTrue('refused: ' + Sub.Text, Sub.WaitFor(
      'plant/$gateway/error {"topic":"plant/plc1/F8:0/set","error":"F8:0 is not writable"}', 5000));
    { SIGHUP: the configuration read again, a tag more; the MQTT
      connection stays (online is not published a second time) }
    WriteFileText(Dir + '/g.conf', StringReplace(ReadFileText(Dir + '/g.conf'),
      'tags = N7:0[3] ', 'tags = N7:0[3] N7:5 ', []));
    FpKill(Gate.ProcessID, SIGHUP);
    AssertTrue('N7:5 after SIGHUP: ' + Sub.Text, Sub.WaitFor('plant/plc1/N7:5 {"value":50,"quality":"good"', 10000));
    AssertEquals('one connection: ' + Sub.Text, 1, CountOf('plant/$gateway/status online', Sub.Text));
    { the gateway vanishes: the broker publishes its will }
    FpKill(Gate.ProcessID, SIGKILL);
    Gate.WaitOnExit;
    AssertTrue('the will: ' + Sub.Text, Sub.WaitFor('plant/$gateway/status offline', 5000));
  finally
    Ended(Gate, SIGKILL);
    Sub.Free;
    Ended(Sim, SIGTERM);
    Dead.Free;
    Broker.Free;
    RemoveTempDir(Dir);
  end;
end;

{ family = plc5 against df1sim --plc5: PLC-5 addresses read by word
  range (an octal I/O bit, BCD D words), a set written with the PLC-5's
  command and read back. }
procedure TTestChngateTool.TestPlc5Device;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  Sim, Gate: TProcess;
  Dir, Pty: string;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Dir := MakeTempDir('chn-gate');
  Broker := TMosquitto.Create;
  Sub := nil;
  Gate := nil;
  Sim := StartSimPty(['--plc5', '--quiet', '--timeout=60'], Pty);
  try
    AssertTrue('df1sim pty', Pty <> '');
    WriteFileText(Dir + '/g.conf',
      '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10#10 +
      '[device p5]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty + #10 +
      'family = plc5'#10'tags = in=I:012/05 D10:0[2] N7:0[3] bcd=D10:3'#10'scan = 200'#10'write = bcd'#10);
    Sub := TMqttSub.Create(Broker.Port, 'plant/#', []);
    Sleep(200);
    Gate := StartGate(Dir + '/g.conf');
    AssertTrue('I:012/05: ' + Sub.Text, Sub.WaitFor('plant/p5/in {"value":true,"quality":"good"', 10000));
    AssertTrue('D10:0[2] from BCD $1234 $9999: ' + Sub.Text,
      Sub.WaitFor('plant/p5/D10:0[2] {"value":[1234,9999],"quality":"good"', 5000));
    AssertTrue('N7:0[3]: ' + Sub.Text, Sub.WaitFor('plant/p5/N7:0[3] {"value":[0,10,20],"quality":"good"', 5000));
    AssertTrue('health: ' + Sub.Text, Sub.WaitFor('plant/p5/$health {"state":"ok"', 5000));
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/p5/bcd/set', '4321'));
    AssertTrue('bcd back: ' + Sub.Text, Sub.WaitFor('plant/p5/bcd {"value":4321,"quality":"good"', 5000));
  finally
    Ended(Gate, SIGTERM);
    Sub.Free;
    Ended(Sim, SIGTERM);
    Broker.Free;
    RemoveTempDir(Dir);
  end;
end;

{ Without libmosquitto chngate says which file it did not find and how to
  install it, exits 1 and opens nothing (CHN_LIBMOSQUITTO makes the
  loader look for a file that is not there; a library that is not
  libmosquitto is named too). }
procedure TTestChngateTool.TestMissingLibrary;
const
  WithLib = 'CHN_LIBMOSQUITTO="$1" exec %s "$0"';
var
  Dir, Output: string;
  Code: LongInt;
begin
  Dir := MakeTempDir('chn-gate');
  try
    WriteFileText(Dir + 'g.conf', '[mqtt]'#10'prefix = plant'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + Dir + 'nodevice'#10'tags = N7:0'#10);
    Code := RunExe('/bin/sh', ['-c', Format(WithLib, [BinShellWord('chngate')]), Dir + 'g.conf',
      Dir + 'libmosquitto.so.1'], 10000, Output);
    AssertEquals('exit 1'#10 + Output, 1, Code);
    AssertEquals('chngate: ' + Dir + 'libmosquitto.so.1 not found (apt-get install libmosquitto1)' +
      LineEnding, Output);
    Code := RunExe('/bin/sh', ['-c', Format(WithLib, [BinShellWord('chngate')]), Dir + 'g.conf', 'libc.so.6'],
      10000, Output);
    AssertEquals('exit 1'#10 + Output, 1, Code);
    AssertEquals('chngate: libc.so.6 has no mosquitto_lib_init (libmosquitto 1.6 or later is needed)' +
      LineEnding, Output);
  finally
    RemoveTempDir(Dir);
  end;
end;

{ A broker that refuses the gateway's password: the log names the broker,
  the reason and when it tries again. }
procedure TTestChngateTool.TestWrongPasswordLogged;
var
  Broker: TMosquitto;
  Gate: TProcess;
  Dir, Why, Output: string;
  Deadline: QWord;
  Expect: string;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Dir := MakeTempDir('chn-gate');
  Broker := nil;
  Gate := nil;
  try
    Why := MakePasswordFile(Dir, 'gate', 's3cret');
    if Why <> '' then
      Ignore(Why);
    Broker := TMosquitto.Create('allow_anonymous false' + LineEnding + 'password_file ' + Dir + 'passwd');
    WriteFileText(Dir + 'g.conf', '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10 +
      'user = gate'#10'password = wrong'#10#10'[device plc1]'#10 +
      'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + Dir + 'nodevice'#10'tags = N7:0'#10'demote = 60000'#10);
    Gate := StartGate(Dir + 'g.conf');
    Expect := Format('chngate: MQTT: the broker 127.0.0.1:%d refused the connection: ' +
      'Connection Refused: not authorised. (again in ', [Broker.Port]);
    Output := '';
    Deadline := GetTickCount64 + 10000;
    while (Pos(Expect, Output) = 0) and (GetTickCount64 < Deadline) do
    begin
      Drain(Gate, Output);
      Sleep(20);
    end;
    AssertTrue('logged'#10 + Output, Pos(Expect, Output) > 0);
  finally
    Ended(Gate, SIGTERM);
    Broker.Free;
    RemoveTempDir(Dir);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChngateTool);
end.
