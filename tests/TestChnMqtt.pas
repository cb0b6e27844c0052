{ TestChnMqtt - the MQTT client (libmosquitto loaded at run time) against
  Debian's mosquitto broker started on a free loopback port, with
  mosquitto_sub and mosquitto_pub as the other side: publish and
  subscribe through the program-wide wait, the online message on the
  will's topic, a broker killed and started again losing none of the
  messages queued meanwhile, a full queue dropping (and counting) its
  oldest. Skipped, with the reason, where mosquitto is not installed. }
unit TestChnMqtt;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry;

type
  TTestChnMqtt = class(TTestCase)
  published
    procedure TestStateTextAndDefaults;
    {$IFDEF UNIX}
    procedure TestPublishAndSubscribe;
    procedure TestBrokerRestartLosesNothingQueued;
    procedure TestFullQueueDropsTheOldest;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, MosquittoRun,{$ENDIF}
  ChnWait, ChnMqtt;

procedure TTestChnMqtt.TestStateTextAndDefaults;
var
  C: tMqttClient;
begin
  MqttInit(C);
  AssertEquals('closed', 'closed', MqttStateText(C));
  AssertEquals('port', 1883, C.Port);
  AssertEquals('QoS 1 by default', 1, C.Qos);
  AssertEquals('queue', MqttQueueDefault, C.QueueMax);
  { a queue without a broker: the oldest goes, counted }
  C.QueueMax := 2;
  MqttPublish(C, 'a', '1', False);
  MqttPublish(C, 'a', '2', False);
  MqttPublish(C, 'a', '3', False);
  AssertEquals('queued', 2, MqttQueued(C));
  AssertEquals('dropped', 1, C.Dropped);
  AssertEquals('oldest kept', '2', C.Queue[0].Payload);
  MqttClose(C);
end;

{$IFDEF UNIX}

{ Step C from the wait until Done or Ms pass. }
type
  tDoneFn = function(var C: tMqttClient): Boolean;

function Connected(var C: tMqttClient): Boolean;
begin
  Result := C.State = msConnected;
end;

function Emptied(var C: tMqttClient): Boolean;
begin
  Result := (C.State = msConnected) and (MqttQueued(C) = 0);
end;

function Waiting(var C: tMqttClient): Boolean;
begin
  Result := C.State = msWaiting;
end;

function HasMessage(var C: tMqttClient): Boolean;
begin
  Result := C.InboxHead < Length(C.Inbox);
end;

function StepUntil(var C: tMqttClient; Done: tDoneFn; Ms: LongInt): Boolean;
var
  Deadline: QWord;
  W: LongInt;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    MqttStep(C);
    if Done(C) then
      Exit(True);
    W := MqttWaitMs(C);
    if W > ChnWaitLeft(Deadline) then
      W := ChnWaitLeft(Deadline);
    ChnWaitAny(W);
  until GetTickCount64 >= Deadline;
  Result := Done(C);
end;

procedure Client(var C: tMqttClient; Port: Word);
var
  Err: AnsiString;
begin
  MqttInit(C);
  C.Port := Port;
  C.WillTopic := 'chn/$gateway/status';
  C.WillPayload := 'offline';
  C.OnlinePayload := 'online';
  if not MqttOpen(C, Err) then
    raise Exception.Create(Err);
end;

procedure TTestChnMqtt.TestPublishAndSubscribe;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  C: tMqttClient;
  M: tMqttMessage;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Broker := TMosquitto.Create;
  Sub := nil;
  try
    Sub := TMqttSub.Create(Broker.Port, 'chn/#', []);
    Client(C, Broker.Port);
    MqttSubscribe(C, 'chn/set/#');
    AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
    MqttPublish(C, 'chn/plc1/N7:0', '{"value":12}', True);
    AssertTrue('emptied', StepUntil(C, @Emptied, 5000));
    AssertTrue('the subscriber got it: ' + Sub.Text, Sub.WaitFor('chn/plc1/N7:0 {"value":12}', 5000));
    AssertTrue('online on the will''s topic: ' + Sub.Text, Sub.WaitFor('chn/$gateway/status online', 5000));
    AssertEquals('delivered', 1, C.Delivered);
    { the other way: mosquitto_pub to a topic the client subscribed to }
    AssertEquals('mosquitto_pub', 0, MqttPub(Broker.Port, 'chn/set/x', '42'));
    AssertTrue('received', StepUntil(C, @HasMessage, 5000));
    AssertTrue('taken', MqttTakeMessage(C, M));
    AssertEquals('topic', 'chn/set/x', M.Topic);
    AssertEquals('payload', '42', M.Payload);
    AssertFalse('one only', MqttTakeMessage(C, M));
  finally
    MqttClose(C);
    Sub.Free;
    Broker.Free;
  end;
end;

procedure TTestChnMqtt.TestBrokerRestartLosesNothingQueued;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  C: tMqttClient;
  I: LongInt;
  Missing: string;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Broker := TMosquitto.Create;
  Sub := nil;
  try
    Client(C, Broker.Port);
    AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
    Broker.Stop(SIGKILL);
    AssertTrue('the client saw the broker go', StepUntil(C, @Waiting, 10000));
    for I := 1 to 30 do
      MqttPublish(C, 'q/' + IntToStr(I), IntToStr(I), False);
    AssertEquals('queued', 30, MqttQueued(C));
    Broker.Start;
    Sub := TMqttSub.Create(Broker.Port, 'q/#', []);
    Sleep(300);     { mosquitto_sub subscribed before the client comes back (1 s back-off at least) }
    AssertTrue('all sent after the restart: ' + C.LastError, StepUntil(C, @Emptied, 40000));
    Missing := '';
    for I := 1 to 30 do
      if not Sub.WaitFor('q/' + IntToStr(I) + ' ' + IntToStr(I) + #10, 3000) then
        Missing := Missing + ' ' + IntToStr(I);
    AssertEquals('missing after the restart: ' + Sub.Text, '', Missing);
    AssertEquals('nothing dropped', 0, C.Dropped);
    AssertTrue('connected twice', C.Connects >= 2);
  finally
    MqttClose(C);
    Sub.Free;
    Broker.Free;
  end;
end;

procedure TTestChnMqtt.TestFullQueueDropsTheOldest;
var
  Broker: TMosquitto;
  Sub: TMqttSub;
  C: tMqttClient;
  I: LongInt;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Broker := TMosquitto.Create;
  Sub := nil;
  try
    Broker.Stop;
    Client(C, Broker.Port);          { nobody there yet }
    C.QueueMax := 10;
    for I := 1 to 15 do
      MqttPublish(C, 'd/' + IntToStr(I), IntToStr(I), False);
    AssertEquals('dropped', 5, C.Dropped);
    AssertEquals('queued', 10, MqttQueued(C));
    AssertTrue('waiting to reconnect: ' + MqttStateText(C), StepUntil(C, @Waiting, 3000));
    Broker.Start;
    Sub := TMqttSub.Create(Broker.Port, 'd/#', []);
    Sleep(300);
    AssertTrue('sent: ' + C.LastError, StepUntil(C, @Emptied, 40000));
    AssertTrue('the newest: ' + Sub.Text, Sub.WaitFor('d/15 15'#10, 3000));
    AssertTrue('the oldest kept: ' + Sub.Text, Sub.WaitFor('d/6 6'#10, 3000));
    AssertEquals('the dropped ones never came: ' + Sub.Text, 0, Pos('d/5 5'#10, Sub.Text));
  finally
    MqttClose(C);
    Sub.Free;
    Broker.Free;
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnMqtt);
end.
