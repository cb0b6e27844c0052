{ TestChnGateway - the gateway's pure parts: its configuration (every
  fault as FILE:LINE: [section] key: why, with nothing opened), the JSON
  it publishes (payloads written out by hand) and the commands it takes
  (ChnJson). The running gateway: TestChngateTool. }
unit TestChnGateway;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestChnGateway = class(TTestCase)
  published
    procedure TestJson;
    procedure TestGoodConfig;
    procedure TestConfigFaults;
    procedure TestTagPayloads;
    procedure TestIec104Config;
    procedure TestIec104Types;
    procedure TestBurstRule;
  end;

implementation

uses
  Math, ChnTypes, ChnLayers, ChnPcccTags, ChnJson, ChnGateway, ChnGate104, ChnIec101Asdu;

procedure TTestChnGateway.TestJson;
var
  V: Double;
  E: AnsiString;
begin
  AssertEquals('escapes', '"a\"b\\c\n\u0001"', JsonString('a"b\c'#10#1));
  AssertEquals('whole', '-12', JsonNumber(-12));
  AssertEquals('single', '3.14159', JsonNumber(Single(3.14159), 7));
  AssertEquals('1.5', '1.5', JsonNumber(1.5, 7));
  AssertEquals('NaN', 'null', JsonNumber(NaN));
  { 2026-12-04 10:00:00.123 UTC = 1796378400 s since 1970 }
  AssertEquals('time', '2026-12-04T10:00:00.123Z', JsonTime(Int64(1796378400) * 1000 + 123));
  AssertTrue('number', JsonParseValue(' 42 ', V, E));
  AssertEquals(42, V, 0);
  AssertTrue('float', JsonParseValue('-2.5e1', V, E));
  AssertEquals(-25, V, 0);
  AssertTrue('true', JsonParseValue('true', V, E));
  AssertEquals(1, V, 0);
  AssertTrue('false', JsonParseValue('false', V, E));
  AssertEquals(0, V, 0);
  AssertTrue('object', JsonParseValue('{"value": 7}', V, E));
  AssertEquals(7, V, 0);
  AssertFalse('text', JsonParseValue('"on"', V, E));
  AssertEquals('why', 'not a number, true or false: "on"', E);
  AssertFalse('empty', JsonParseValue('', V, E));
  AssertFalse('object without value', JsonParseValue('{"v":1}', V, E));
  AssertEquals('why', 'an object without "value": {"v":1}', E);
end;

const
  Good =
    '# a gateway'#10 +
    '[mqtt]'#10 +
    'host = 127.0.0.1'#10 +
    'port = 1883'#10 +
    'prefix = plant'#10 +
    'queue = 500'#10 +
    #10 +
    '[device plc1]'#10 +
    'line = NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200'#10 +
    'tags = N7:0[10] speed=F8:2 run=B3:0/5@250 T4:1.ACC'#10 +
    'scan = 500'#10 +
    'write = run speed'#10 +
    'deadband = 0.5'#10;

procedure TTestChnGateway.TestGoodConfig;
var
  Cfg: tGateConfig;
  E: AnsiString;
begin
  AssertTrue('good: ' + E, GateParseConfig('g.conf', Good, Cfg, E));
  AssertEquals('prefix', 'plant', Cfg.Prefix);
  AssertEquals('queue', 500, Cfg.Queue);
  AssertEquals('qos default', 1, Cfg.Qos);
  AssertEquals('devices', 1, Length(Cfg.Devices));
  AssertEquals('tags', 4, Length(Cfg.Devices[0].Tags));
  AssertEquals('N7:0[10]', 'N7:0[10]', Cfg.Devices[0].Tags[0].Name);
  AssertEquals('speed', 'speed', Cfg.Devices[0].Tags[1].Name);
  AssertEquals('run scan', 250, Cfg.Devices[0].Tags[2].ScanMs);
  AssertEquals('N7 scan', 500, Cfg.Devices[0].Tags[0].ScanMs);
  AssertTrue('run writable', Cfg.Devices[0].Tags[2].Writable);
  AssertFalse('N7 not', Cfg.Devices[0].Tags[0].Writable);
  { N7, F8, B3 (250 ms), T4 }
  AssertEquals('summary', '1 devices, 4 tags, 4 reads per scan', GateSummary(Cfg));
end;

procedure Fault(const Text, Expect: string);
var
  Cfg: tGateConfig;
  E: AnsiString;
begin
  TAssert.AssertFalse('accepted: ' + Text, GateParseConfig('g.conf', Text, Cfg, E));
  TAssert.AssertTrue('expected "' + Expect + '" in:'#10 + E, Pos(Expect, E) > 0);
end;

procedure TTestChnGateway.TestConfigFaults;
begin
  Fault(StringReplace(Good, 'port = 1883', 'port = 99999', []),
    'g.conf:4: [mqtt] port: "99999" is not a whole number 1..65535');
  Fault(StringReplace(Good, 'prefix = plant', 'prefix = plant/#', []),
    'g.conf:5: [mqtt] prefix: "plant/#": no wildcards (+ #) and no trailing /');
  Fault(StringReplace(Good, 'prefix = plant'#10, '', []), ': [mqtt] prefix: missing');
  Fault(StringReplace(Good, 'queue = 500', 'qeue = 500', []),
    'g.conf:6: [mqtt] qeue: unknown key (host port prefix qos user password tls ca queue client_id keepalive)');
  Fault(StringReplace(Good, 'N7:0[10]', 'Q7:0', []), 'g.conf:10: [device plc1] tags: "Q7:0": ');
  Fault(StringReplace(Good, 'N7:0[10]', 'N7:0[200]', []),
    'g.conf:10: [device plc1] tags: "N7:0[200]": 400 bytes, more than one read carries (244); split it');
  Fault(StringReplace(Good, 'write = run speed', 'write = run N7:0[10]', []),
    'g.conf:12: [device plc1] write: "N7:0[10]": only a tag of one integer, bit or float can be written');
  Fault(StringReplace(Good, 'write = run speed', 'write = stop', []),
    'g.conf:12: [device plc1] write: "stop" is none of the device''s tags');
  Fault(StringReplace(Good, 'BD=19200', 'BD=abc', []),
    'g.conf:9: [device plc1] line: bad parameter string: ');
  Fault(StringReplace(Good, 'BD=19200', 'BD=abc', []), 'BD=abc');
  Fault(StringReplace(Good, 'NAM=DF1 NOD=0', 'NAM=ICS NOD=0', []),
    'g.conf:9: [device plc1] line: "NAM=ICS": the line starts with NAM=DF1');
  Fault(StringReplace(Good, 'run=B3:0/5@250', 'run=B3:0/5@5', []),
    '"run=B3:0/5@5": the scan after @ is not a whole number 10..3600000 (ms)');
  Fault(StringReplace(Good, 'speed=F8:2', 'run=F8:2', []), 'g.conf:10: [device plc1] tags: "run" is there twice');
  Fault(Good + '[device plc1]'#10'line = NAM=DF1'#10, 'g.conf:14: [device plc1]: the section is there twice');
  Fault(Good + '[modbus]'#10, 'g.conf:14: [modbus]: unknown section (mqtt, iec104, device NAME)');
  Fault(Good + 'just words'#10, 'g.conf:14: "just words": not KEY = VALUE');
  Fault(StringReplace(Good, 'deadband = 0.5', 'deadband = -1', []),
    'g.conf:13: [device plc1] deadband: "-1" is not a number 0 or above');
  Fault('[mqtt]'#10'prefix = p'#10, 'g.conf:0: no [device NAME] section');
end;

procedure TTestChnGateway.TestTagPayloads;
var
  D: tPcccDevice;
  E: ShortString;
begin
  TagDeviceInit(D, 'plc1');
  try
    TagAdd(D, '', 'N7:0[3]', 500, 0, False, E);
    TagAdd(D, 'run', 'B3:0/5', 500, 0, False, E);
    TagAdd(D, '', 'F8:0', 500, 0, False, E);
    TagAdd(D, '', 'ST9:0', 500, 0, False, E);
    D.Tags[0].Quality := tqBad;
    AssertEquals('bad before any good read', '{"value":null,"quality":"bad","ts":"1970-01-01T00:00:00.000Z"}',
      GateTagPayload(D.Tags[0]));
    D.Tags[0].Quality := tqInitial;
    AssertEquals('not read yet', '{"value":null,"quality":"initial","ts":"1970-01-01T00:00:00.000Z"}',
      GateTagPayload(D.Tags[0]));
    D.Tags[0].Values[0] := 1; D.Tags[0].Values[1] := -2; D.Tags[0].Values[2] := 30000;
    D.Tags[0].Quality := tqGood;
    D.Tags[0].Known := True;
    D.Tags[0].TimeMs := Int64(1796378400) * 1000 + 123;
    AssertEquals('array', '{"value":[1,-2,30000],"quality":"good","ts":"2026-12-04T10:00:00.123Z"}',
      GateTagPayload(D.Tags[0]));
    D.Tags[1].Values[0] := 1;
    D.Tags[1].Quality := tqBad;
    D.Tags[1].Known := True;
    D.Tags[1].TimeMs := Int64(1796378400) * 1000;
    AssertEquals('bit', '{"value":true,"quality":"bad","ts":"2026-12-04T10:00:00.000Z"}',
      GateTagPayload(D.Tags[1]));
    D.Tags[2].Values[0] := Single(-2.25);
    D.Tags[2].Quality := tqGood;
    D.Tags[2].Known := True;
    AssertEquals('float', '{"value":-2.25,"quality":"good","ts":"1970-01-01T00:00:00.000Z"}',
      GateTagPayload(D.Tags[2]));
    D.Tags[3].Text := 'say "hi"';
    D.Tags[3].Quality := tqRefused;
    D.Tags[3].Known := True;
    AssertEquals('string', '{"value":"say \"hi\"","quality":"refused","ts":"1970-01-01T00:00:00.000Z"}',
      GateTagPayload(D.Tags[3]));
    D.Requests := 12;
    D.Errors := 1;
    D.LastError := 'N7:0: no reply';
    D.State := tdDown;
    AssertEquals('health', '{"state":"down","requests":12,"errors":1,"retries":0,"reads_per_scan":0,' +
      '"last_error":"N7:0: no reply"}', GateHealthPayload(D));
  finally
    TagDeviceDone(D);
  end;
end;

const
  With104 = '[iec104]'#10'listen = 127.0.0.1:2404'#10'ca = 5'#10'k = 20'#10'w = 10'#10't1 = 20'#10;

  Rtus = '[device rtu1]'#10'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB2'#10 +
    'points = a=3 b=100'#10'write = b>97'#10'ioa = 10'#10 +
    '[device rtu2]'#10'line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB3'#10 +
    'points = c=10'#10'write = c>7'#10'ioa = 100'#10;

procedure TTestChnGateway.TestIec104Config;
var
  Cfg: tGateConfig;
  E: AnsiString;
  Many: string;
  I: LongInt;
begin
  AssertTrue('good: ' + E, GateParseConfig('g.conf', Good + With104, Cfg, E));
  AssertTrue('present', Cfg.Iec104.Present);
  AssertEquals('ca', 5, Cfg.Iec104.Ca);
  AssertEquals('command timeout default', 10000, Cfg.Iec104.CommandMs);
  AssertEquals('the server''s line', 'NAM=IEC104 K=20 W=10 T1=20 NAM=TCP LISTEN=127.0.0.1:2404',
    Gate104Line(Cfg.Iec104));
  { N7:0[10] 10, speed 1, run 1, T4:1.ACC 1; run and speed writable: 2 command points each }
  AssertEquals('IOAs', 13, Cfg.Devices[0].Points);
  AssertEquals('table', 17, Cfg.Devices[0].TablePoints);
  AssertEquals('summary', '1 devices, 4 tags, 4 reads per scan, 13 IEC 104 points', GateSummary(Cfg));
  { IEC 104 alone: no [mqtt] needed }
  AssertTrue('without mqtt: ' + E, GateParseConfig('g.conf', Copy(Good, Pos('[device', Good), MaxInt) + With104, Cfg, E));
  Fault(Copy(Good, Pos('[device', Good), MaxInt), 'g.conf:0: no [mqtt] or [iec104] section: nowhere to publish');
  Fault(Good + '[iec104]'#10'ca = 1'#10, 'g.conf:14: [iec104] listen: missing or not HOST:PORT (0.0.0.0:2404)');
  Fault(Good + StringReplace(With104, 'ca = 5', 'ca = 0', []), 'g.conf:16: [iec104] ca: "0" is not a whole number 1..65534');
  Fault(Good + StringReplace(With104, 'k = 20', 'k = 5', []), 'g.conf:14: [iec104]: bad parameter string: ');
  Fault(Good + StringReplace(With104, 'k = 20', 'k = 5', []), 'W=10');
  Fault(Good + With104 + 'x = 1'#10, 'g.conf:20: [iec104] x: unknown key (listen ca con k w t0 t1 t2 t3 command_timeout)');
  { IOAs: plc2 from 5 overlaps plc1's 1..13 }
  Fault(Good + With104 + '[device plc2]'#10'line = NAM=DF1 NAM=COM DEV=/dev/ttyUSB1'#10'tags = N7:0'#10'ioa = 5'#10,
    'g.conf:23: [device plc2] ioa: IOAs 5..5 overlap those of device plc1 (1..13)');
  AssertTrue('after them: ' + E, GateParseConfig('g.conf', Good + With104 +
    '[device plc2]'#10'line = NAM=DF1 NAM=COM DEV=/dev/ttyUSB1'#10'tags = N7:0'#10'ioa = 14'#10, Cfg, E));
  { an RTU's configured points at ioa= + IOA: not on a DF1 device's IOAs
    (plc1 1..13), nor on another RTU's point or command IOA }
  Fault(Good + With104 + Rtus, 'g.conf:22: [device rtu1] points: device rtu1''s point a (10 + 3): ' +
    'IEC 104 IOA 13 falls in device plc1''s IOAs 1..13');
  Fault(Good + With104 + Rtus, 'g.conf:27: [device rtu2] points: device rtu2''s point c (100 + 10): ' +
    'IEC 104 IOA 110 is device rtu1''s point b (10 + 100) already');
  Fault(Good + With104 + Rtus, 'g.conf:28: [device rtu2] write: device rtu2''s command IOA of c (100 + 7): ' +
    'IEC 104 IOA 107 is device rtu1''s command IOA of b (10 + 97) already');
  AssertTrue('apart: ' + E, GateParseConfig('g.conf', Good + With104 + StringReplace(StringReplace(Rtus,
    'a=3', 'a=4', []), 'ioa = 100', 'ioa = 1000', []), Cfg, E));
  { more points than the server's table holds }
  Many := '';
  for I := 0 to 10 do
    Many := Many + ' N7:' + IntToStr(I * 100) + '[100]';
  Fault('[device big]'#10'line = NAM=DF1 NAM=COM DEV=/dev/ttyUSB1'#10'tags =' + Many + #10 + With104,
    'g.conf:4: [iec104]: 1100 points (a writable tag''s commands count 2), more than 1024');
end;

{ The types of docs/chngate.md's IEC 104 table. }
procedure TTestChnGateway.TestIec104Types;
const
  Tags: array[0..10] of string = ('N7:0', 'F8:0', 'B3:0/5', 'L11:0', 'S2:4', 'B3:1', 'T4:0.ACC', 'T4:0.DN',
    'ST10:0', 'T4:1', 'N7:10[4]');
  Types: array[0..10] of Byte = (M_ME_NB_1, M_ME_NC_1, M_SP_NA_1, M_BO_NA_1, M_BO_NA_1, M_BO_NA_1, M_ME_NB_1,
    M_SP_NA_1, 0, M_ME_NB_1, M_ME_NB_1);
  Commands: array[0..10] of Byte = (C_SE_NB_1, C_SE_NC_1, C_SC_NA_1, C_BO_NA_1, C_BO_NA_1, C_BO_NA_1, C_SE_NB_1,
    C_SC_NA_1, 0, 0, 0);
var
  D: tPcccDevice;
  E: ShortString;
  I: LongInt;
begin
  TagDeviceInit(D, 'plc1');
  try
    for I := 0 to High(Tags) do
    begin
      AssertEquals(Tags[I] + ': ' + E, res_Ok, TagAdd(D, '', Tags[I], 500, 0, I < 8, E));
      AssertEquals(Tags[I], Types[I], Gate104TagType(D.Tags[I]));
      AssertEquals(Tags[I] + ' command', Commands[I], Gate104CommandType(D.Tags[I]));
    end;
    { one each, the string none, the whole timer 3, the array 4 }
    AssertEquals('IOAs', 8 + 3 + 4, Gate104DevicePoints(D));
    AssertEquals('table', 8 + 3 + 4 + 8 * 2, Gate104TablePoints(D));
  finally
    TagDeviceDone(D);
  end;
end;

{ A burst is over when the north queues fell to GateBurstLow after
  holding GateBurst or more at once; small ups and downs are none. }
procedure TTestChnGateway.TestBurstRule;
var
  High: LongInt;
begin
  High := 0;
  AssertFalse('nothing queued', GateBurstOver(High, 0));
  AssertFalse('a few', GateBurstOver(High, 5));
  AssertFalse('emptied after a few', GateBurstOver(High, 0));
  AssertFalse('rising', GateBurstOver(High, GateBurst - 1));
  AssertFalse('falling, not empty', GateBurstOver(High, 3));
  AssertFalse('empty below a burst', GateBurstOver(High, 0));
  AssertFalse('a burst', GateBurstOver(High, GateBurst));
  AssertEquals('kept', GateBurst, High);
  AssertFalse('draining', GateBurstOver(High, GateBurstLow + 1));
  AssertTrue('over', GateBurstOver(High, GateBurstLow));
  AssertFalse('once', GateBurstOver(High, 0));
  AssertEquals('counting anew from there', GateBurstLow, High);
end;

initialization
  RegisterTest(TTestChnGateway);
end.
