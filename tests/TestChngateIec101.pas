{ TestChngateIec101 - IEC 101 devices in tools/chngate: their
  configuration keys (every fault as FILE:LINE: [section] key: why) and,
  on Unix, the gateway as it runs: examples/iec101slave on a pty it makes
  as the RTU (with return information for its command points), a pty
  nobody answers as a dead RTU, df1sim as a DF1 PLC on the same gateway,
  Debian's mosquitto on a free loopback port, mosquitto_sub and
  mosquitto_pub as the IT side. The values and qualities expected are
  those of the points file written here. Skipped, with the reason,
  without mosquitto. }
unit TestChngateIec101;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestChngateIec101 = class(TTestCase)
  published
    procedure TestConfig;
    procedure TestConfigFaults;
    {$IFDEF UNIX}
    procedure TestIec101DeviceEndToEnd;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, PtyPair, MosquittoRun,{$ENDIF}
  Process, BinSupport, TestTempDir, ChnGateway, ChildLine;

const
  Good =
    '[mqtt]'#10 +                                                          { 1 }
    'prefix = plant'#10 +                                                  { 2 }
    #10 +                                                                  { 3 }
    '[device rtu1]'#10 +                                                   { 4 }
    'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E'#10 +
    'slaves = 1 2'#10 +                                                    { 6 }
    'ca = 7'#10 +                                                          { 7 }
    'ioa = 1000'#10 +                                                      { 8 }
    'points = pump=104 level=2:101'#10 +                                   { 9 }
    'write = pump>5000 level>5101 2:300'#10 +                              { 10 }
    'deadband = 0.5'#10 +                                                  { 11 }
    'gi = 60000'#10;                                                       { 12 }

procedure TTestChngateIec101.TestConfig;
var
  Cfg: tGateConfig;
  E: AnsiString;
begin
  AssertTrue('good: ' + E, GateParseConfig('g.conf', Good, Cfg, E));
  AssertEquals('devices', 1, Length(Cfg.Devices));
  AssertTrue('an IEC 101 device', Cfg.Devices[0].Iec);
  with Cfg.Devices[0].Iec101 do
  begin
    AssertEquals('slaves', 2, Length(Slaves));
    AssertEquals(1, Slaves[0]);
    AssertEquals(2, Slaves[1]);
    AssertEquals('ca', 7, Ca);
    AssertEquals('ioa offset', 1000, IoaOffset);
    AssertEquals('deadband', 0.5, Deadband, 0);
    AssertEquals('gi', 60000, GiMs);
    AssertEquals('sizes (defaults)', 2, Params.CotSize);
    AssertEquals(2, Params.CaSize);
    AssertEquals(3, Params.IoaSize);
    AssertEquals('points', 3, Length(Points));
    AssertEquals('pump', Points[0].Name);
    AssertEquals(1, Points[0].Addr);
    AssertEquals(104, Points[0].Ioa);
    AssertTrue(Points[0].Writable);
    AssertEquals(5000, Points[0].CmdIoa);
    AssertEquals('level', Points[1].Name);
    AssertEquals(2, Points[1].Addr);
    AssertEquals(101, Points[1].Ioa);
    AssertEquals(5101, Points[1].CmdIoa);
    AssertEquals('unnamed', '', Points[2].Name);
    AssertEquals(2, Points[2].Addr);
    AssertEquals(300, Points[2].Ioa);
    AssertEquals('commands to its own IOA', 300, Points[2].CmdIoa);
  end;
  AssertEquals('summary', '1 devices, 0 tags, 0 reads per scan, 2 IEC 101 slaves', GateSummary(Cfg));
  { without slaves=: the line's DNO= }
  AssertTrue(E, GateParseConfig('g.conf', StringReplace(StringReplace(StringReplace(Good, 'slaves = 1 2'#10, '', []),
    'level=2:101', 'level=101', []), ' 2:300', '', []), Cfg, E));
  AssertEquals('DNO=', 1, Length(Cfg.Devices[0].Iec101.Slaves));
  AssertEquals('DNO=', 1, Cfg.Devices[0].Iec101.Slaves[0]);
end;

procedure Fault(const Text, Expect: string);
var
  Cfg: tGateConfig;
  E: AnsiString;
begin
  TAssert.AssertFalse('accepted: ' + Text, GateParseConfig('g.conf', Text, Cfg, E));
  TAssert.AssertTrue('expected "' + Expect + '" in:'#10 + E, Pos(Expect, E) > 0);
end;

function Change(const Old, New: string): string;
begin
  TAssert.AssertTrue(Old, Pos(Old, Good) > 0);
  Result := StringReplace(Good, Old, New, []);
end;

procedure TTestChngateIec101.TestConfigFaults;
const
  Df1 = #10'[device plc1]'#10'line = NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB1'#10'tags = N7:0'#10;
begin
  Fault(Change('slaves = 1 2', 'slaves = 1 x'), 'g.conf:6: [device rtu1] slaves: "x" is not a link address 0..65535');
  Fault(Change('slaves = 1 2', 'slaves = 1 1'),
    'g.conf:6: [device rtu1] slaves: slave 1: twice, too large for ADR=, or the broadcast address');
  Fault(Change('slaves = 1 2', 'slaves = 1 255'),
    'g.conf:6: [device rtu1] slaves: slave 255: twice, too large for ADR=, or the broadcast address');
  Fault(Change('ca = 7', 'ca = 300'#10'ca_size = 1'), 'g.conf:7: [device rtu1] ca: ca 300 is above 255 (ca_size 1)');
  Fault(Change('ca = 7', 'cot_size = 3'), 'g.conf:7: [device rtu1] cot_size: "3" is not a whole number 1..2');
  Fault(Change('ioa = 1000', 'ioa = -1'), 'g.conf:8: [device rtu1] ioa: "-1" is not a whole number 0..16777215');
  Fault(Change('pump=104 ', 'pump=104 pump=105 '), 'g.conf:9: [device rtu1] points: "pump" is there twice');
  Fault(Change('pump=104 ', '104 '),
    'g.conf:9: [device rtu1] points: "104": NAME=IOA or NAME=ADDR:IOA, the name one topic level (no / + #)');
  Fault(Change('level=2:101', 'level=3:101'), 'g.conf:9: [device rtu1] points: "level=3:101": 3 is none of the slaves');
  Fault(Change('level=2:101', 'level=2:x'), 'g.conf:9: [device rtu1] points: "level=2:x": the IOA is a whole number');
  Fault(Change('write = pump>5000', 'write = stop>5000'),
    'g.conf:10: [device rtu1] write: "stop>5000": neither a name of points= nor an IOA');
  Fault(Change('write = pump>5000', 'write = pump>x'),
    'g.conf:10: [device rtu1] write: "pump>x": the command IOA after > is a whole number 0..16777215');
  Fault(Change('gi = 60000', 'gi = 60000'#10'tags = N7:0'),
    'g.conf:13: [device rtu1] tags: not for an IEC 101 device');
  Fault(Change('MAS=MASTER', 'MAS=SLAVE'), 'g.conf:5: [device rtu1] line: a slave''s parameter string: ' +
    'an IEC 101 device is polled by a master (MS=ON MAS=MASTER, or MS=OFF balanced)');
  Fault(Change('BD=9600', 'BD=abc'), 'g.conf:5: [device rtu1] line: bad parameter string: ');
  Fault(Change('slaves = 1 2'#10, '') + Df1 + 'slaves = 1'#10,
    'g.conf:16: [device plc1] slaves: only for an IEC 101 device (line = NAM=FT1_2 ...)');
  Fault(Change('NAM=FT1_2', 'NAM=ICS'), 'g.conf:5: [device rtu1] line: "NAM=ICS": the line starts with NAM=DF1 or NAM=FT1_2');
end;

{$IFDEF UNIX}

procedure TTestChngateIec101.TestIec101DeviceEndToEnd;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  Sim, Rtu, Gate: TProcess;
  Dead: TPtyPair;
  Dir, Pty, RtuPty, Before: string;
  Clocks: LongInt;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  AssertTrue(BinPath('iec101slave') + ' missing (make examples)', FileExists(BinPath('iec101slave')));
  Dir := MakeTempDir('chn-gate101');
  Broker := TMosquitto.Create;
  Sub := nil;
  Gate := nil;
  Rtu := nil;
  Dead := TPtyPair.Create;
  Sim := StartSimPty(['--quiet', '--timeout=60'], Pty);
  try
    AssertTrue('df1sim pty', Pty <> '');
    { the RTU: a scaled value, a float set point with its return, a single
      point (invalid) switched by command point 5000, a double point }
    WriteFileText(Dir + '/rtu.txt', '100 M_ME_NB_1 -1'#10'101 M_ME_NC_1 1.5'#10'104 M_SP_NA_1 1 IV'#10 +
      '105 M_DP_NA_1 2'#10'5000 C_SC_NA_1 0'#10'5101 C_SE_NC_1 0'#10);
    Rtu := TProcess.Create(nil);
    BinExecutable(Rtu, BinPath('iec101slave'));
    Rtu.Parameters.Add('--points=' + Dir + '/rtu.txt');
    Rtu.Parameters.Add('--return=5000=104,5101=101');
    Rtu.Parameters.Add('--seconds=60');
    Rtu.Parameters.Add('NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DRV=PTY');
    Rtu.Options := [poUsePipes, poStderrToOutPut];
    Rtu.Execute;
    RtuPty := ReadFirstLine(Rtu, 5000);
    AssertEquals('iec101slave: PTY /dev/', Copy(RtuPty, 1, 22));
    RtuPty := Copy(RtuPty, 18, MaxInt);
    WriteFileText(Dir + '/g.conf',
      '[mqtt]'#10'port = ' + IntToStr(Broker.Port) + #10'prefix = plant'#10#10 +
      '[device plc1]'#10'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=' + Pty + #10 +
      'tags = clock=S2:4@200'#10#10 +
      '[device rtu1]'#10'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=' + RtuPty + #10 +
      'points = pump=104 level=101'#10'write = pump>5000 level>5101'#10'deadband = 0.1'#10 +
      'demote = 1000'#10#10 +
      '[device rtu2]'#10'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=' + Dead.SlavePath + #10 +
      'points = x=1'#10'timeout = 100'#10'demote = 500'#10);
    Sub := TMqttSub.Create(Broker.Port, 'plant/#', []);
    Sleep(200);
    Gate := TProcess.Create(nil);
    BinExecutable(Gate, BinPath('chngate'));
    Gate.Parameters.Add(Dir + '/g.conf');
    Gate.Options := [poUsePipes, poStderrToOutPut];
    Gate.Execute;
    { the RTU's values with their quality, by IOA or by name }
    AssertTrue('100: ' + Sub.Text, Sub.WaitFor('plant/rtu1/100 {"value":-1,"quality":"good","ts":"', 10000));
    AssertTrue('level: ' + Sub.Text, Sub.WaitFor('plant/rtu1/level {"value":1.5,"quality":"good"', 5000));
    AssertTrue('pump: ' + Sub.Text, Sub.WaitFor('plant/rtu1/pump {"value":true,"quality":"IV"', 5000));
    AssertTrue('105: ' + Sub.Text, Sub.WaitFor('plant/rtu1/105 {"value":2,"quality":"good"', 5000));
    AssertTrue('health: ' + Sub.Text, Sub.WaitFor('plant/rtu1/$health {"state":"ok"', 5000));
    { the dead RTU: its point bad, down, then demoted }
    AssertTrue('rtu2 bad: ' + Sub.Text, Sub.WaitFor('plant/rtu2/x {"value":null,"quality":"bad"', 10000));
    AssertTrue('rtu2 down: ' + Sub.Text, Sub.WaitFor('plant/rtu2/$health {"state":"down"', 5000));
    AssertTrue('rtu2 demoted: ' + Sub.Text, Sub.WaitFor('plant/rtu2/$health {"state":"demoted"', 5000));
    AssertTrue('says why: ' + Sub.Text, Sub.WaitFor('"last_error":"no answer from link address 1', 5000));
    { meanwhile the DF1 PLC keeps its 200 ms clock: about 10 changes in 2 s }
    Before := Sub.Text;
    Sleep(2000);
    Clocks := Occurs('plant/plc1/clock {', Sub.Text) - Occurs('plant/plc1/clock {', Before);
    AssertTrue(Format('plc1 clock changes in 2 s while rtu2 is demoted: %d', [Clocks]), Clocks >= 7);
    { a single command reaches the RTU (C_SC_NA_1 to 5000); its return
      information brings the new value, quality good }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/rtu1/pump/set', 'false'));
    AssertTrue('pump back: ' + Sub.Text, Sub.WaitFor('plant/rtu1/pump {"value":false,"quality":"good"', 5000));
    { a float set point (C_SE_NC_1 to 5101) }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/rtu1/level/set', '{"value":3.25}'));
    AssertTrue('level back: ' + Sub.Text, Sub.WaitFor('plant/rtu1/level {"value":3.25,"quality":"good"', 5000));
    { not writable, not a point, a value the type cannot take: refused with the reason }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/rtu1/100/set', '3'));
    AssertTrue('refused: ' + Sub.Text, Sub.WaitFor(
      'plant/$gateway/error {"topic":"plant/rtu1/100/set","error":"IOA 100 is not writable"}', 5000));
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/rtu1/999/set', '3'));
    AssertTrue('no point: ' + Sub.Text, Sub.WaitFor(
      'plant/$gateway/error {"topic":"plant/rtu1/999/set","error":"no point \"999\" on rtu1"}', 5000));
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'plant/rtu1/pump/set', '2'));
    AssertTrue('range: ' + Sub.Text, Sub.WaitFor(
      'plant/$gateway/error {"topic":"plant/rtu1/pump/set","error":"IOA 104: a single command is 0 or 1', 5000));
    { the RTU's line goes (the pty it made vanishes with it): down, bad }
    Ended(Rtu, SIGKILL);
    AssertTrue('pump bad: ' + Sub.Text, Sub.WaitFor('plant/rtu1/pump {"value":false,"quality":"bad"', 5000));
    AssertTrue('rtu1 down: ' + Sub.Text, Sub.WaitFor('plant/rtu1/$health {"state":"down"', 5000));
    AssertTrue('line lost: ' + Sub.Text, Sub.WaitFor('"last_error":"line failed: ', 5000));
  finally
    Ended(Gate, SIGKILL);
    Ended(Rtu, SIGKILL);
    Sub.Free;
    Ended(Sim, SIGTERM);
    Dead.Free;
    Broker.Free;
    RemoveTempDir(Dir);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChngateIec101);
end.
