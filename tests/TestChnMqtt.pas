{ TestChnMqtt - the MQTT client (libmosquitto loaded at run time) against
  Debian's mosquitto broker started on a free loopback port, with
  mosquitto_sub and mosquitto_pub as the other side: publish and
  subscribe through the program-wide wait, the online message on the
  will's topic, a broker killed and started again losing none of the
  messages queued meanwhile, nor those handed over and not acknowledged,
  and sending none twice; a full queue dropping (and counting) its
  oldest; user name and password (a wrong password refused with the
  broker and the reason named) and TLS against a broker with a
  certificate made for the test; an idle client waking only when its
  keep-alive ping is due, and that ping keeping it connected. Skipped, with the reason, where
  mosquitto (or openssl) is not installed. }
unit TestChnMqtt;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, {$IFDEF UNIX}MosquittoRun,{$ENDIF} ChnMqtt;

type
  { Each broker test's broker, subscriber, clients and folder, stopped,
    closed and removed after it whatever happened. }
  TTestChnMqtt = class(TTestCase)
  {$IFDEF UNIX}
  private
    Broker: TMosquitto;
    Sub: TMqttSub;
    C, Other: tMqttClient;
    Dir: string;
    { mosquitto started with Listener's settings; the test skipped,
      with the reason, where it is not installed }
    procedure StartBroker(const Listener: string = 'allow_anonymous true');
    { (again) mosquitto_sub on Topic, Extra its further arguments }
    procedure Subscribe(const Topic: string; const Extra: array of string);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  {$ENDIF}
  published
    procedure TestStateTextAndDefaults;
    procedure TestQueueKeepsOrderAsItGrows;
    {$IFDEF UNIX}
    procedure TestPublishAndSubscribe;
    procedure TestIdleWakesOnlyForThePing;
    procedure TestTrafficStampedWithTheRoundsClock;
    procedure TestBrokerRestartLosesNothingQueued;
    procedure TestFullQueueDropsTheOldest;
    procedure TestHandedOverSentOnceAfterLoss;
    procedure TestAcknowledgedNotSentAgain;
    procedure TestUserAndPassword;
    procedure TestTls;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, TestTempDir, TestSupport,{$ENDIF}
  ChnWait;

procedure TTestChnMqtt.TestStateTextAndDefaults;
var
  Q: tMqttClient;
begin
  MqttInit(Q);
  AssertEquals('closed', 'closed', MqttStateText(Q));
  AssertEquals('port', 1883, Q.Port);
  AssertEquals('QoS 1 by default', 1, Q.Qos);
  AssertEquals('queue', MqttQueueDefault, Q.QueueMax);
  { a queue without a broker: the oldest goes, counted }
  Q.QueueMax := 2;
  MqttPublish(Q, 'a', '1', False);
  MqttPublish(Q, 'a', '2', False);
  MqttPublish(Q, 'a', '3', False);
  AssertEquals('queued', 2, MqttQueued(Q));
  AssertEquals('dropped', 1, Q.Dropped);
  AssertEquals('oldest kept', '2', MqttQueuedMessage(Q, 0).Payload);
  MqttClose(Q);
end;

{ Without a broker the queue grows past its first room and wraps around
  as the oldest go: whatever its room, the newest QueueMax stay, in order. }
procedure TTestChnMqtt.TestQueueKeepsOrderAsItGrows;
var
  Q: tMqttClient;
  I: LongInt;
begin
  MqttInit(Q);
  Q.QueueMax := 40;
  for I := 1 to 25 do
    MqttPublish(Q, 't', IntToStr(I), False);
  AssertEquals('25 queued', 25, MqttQueued(Q));
  for I := 0 to 24 do
    AssertEquals('in order', IntToStr(I + 1), MqttQueuedMessage(Q, I).Payload);
  for I := 26 to 100 do
    MqttPublish(Q, 't', IntToStr(I), I mod 2 = 0);
  AssertEquals('full', 40, MqttQueued(Q));
  AssertEquals('dropped', 60, Q.Dropped);
  for I := 0 to 39 do
  begin
    AssertEquals('the newest, in order', IntToStr(61 + I), MqttQueuedMessage(Q, I).Payload);
    AssertEquals('retain kept', (61 + I) mod 2 = 0, MqttQueuedMessage(Q, I).Retain);
  end;
  MqttClose(Q);
  AssertEquals('closed: empty', 0, MqttQueued(Q));
  { grown while its oldest message is not at the ring's start: the part
    that wrapped round comes after the rest }
  MqttInit(Q);
  Q.QueueMax := 16;
  for I := 1 to 20 do
    MqttPublish(Q, 't', IntToStr(I), False);
  AssertEquals('4 dropped', 4, Q.Dropped);
  Q.QueueMax := 40;
  for I := 21 to 30 do
    MqttPublish(Q, 't', IntToStr(I), False);
  AssertEquals('26 queued', 26, MqttQueued(Q));
  for I := 0 to 25 do
    AssertEquals('in order after growing', IntToStr(5 + I), MqttQueuedMessage(Q, I).Payload);
  MqttClose(Q);
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

procedure TTestChnMqtt.SetUp;
begin
  Broker := nil;
  Sub := nil;
  MqttInit(C);
  MqttInit(Other);
  Dir := '';
end;

procedure TTestChnMqtt.TearDown;
begin
  MqttClose(Other);
  MqttClose(C);
  FreeAndNil(Sub);
  FreeAndNil(Broker);
  if Dir <> '' then
    RemoveTempDir(Dir);
end;

procedure TTestChnMqtt.StartBroker(const Listener: string);
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Broker := TMosquitto.Create(Listener);
end;

procedure TTestChnMqtt.Subscribe(const Topic: string; const Extra: array of string);
begin
  FreeAndNil(Sub);
  Sub := TMqttSub.Create(Broker.Port, Topic, Extra);
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
  M: tMqttMessage;
begin
  StartBroker;
  Subscribe('chn/#', []);
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
end;

{ Idle, the client wakes only for its keep-alive PINGREQ (KeepAlive s
  after the last traffic, and a second for the library's clock of whole
  seconds), not on a tick: with KeepAlive 5 it sleeps about 6 s, where a
  look every quarter of it woke 4 times. The ping keeps it connected past
  the 7.5 s (1.5 KeepAlive) after which the broker drops a silent
  client. }
procedure TTestChnMqtt.TestIdleWakesOnlyForThePing;
var
  Deadline: QWord;
  W, Wakes: LongInt;
  Calls: LongWord;
  Err: AnsiString;
begin
  StartBroker;
  MqttInit(C);
  C.Port := Broker.Port;
  C.KeepAlive := 5;
  AssertTrue(Err, MqttOpen(C, Err));
  AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  MqttStep(C);
  W := MqttWaitMs(C);
  AssertTrue(Format('idle after the connect: a wait of %d ms', [W]), (W >= 5000) and (W <= 6100));
  Wakes := 0;
  Calls := ChnWaitOsChanges;
  Deadline := GetTickCount64 + 8500;
  while GetTickCount64 < Deadline do
  begin
    W := MqttWaitMs(C);
    if W > ChnWaitLeft(Deadline) then
      W := ChnWaitLeft(Deadline);
    ChnWaitAny(W);
    MqttStep(C);
    Inc(Wakes);
  end;
  AssertEquals('still connected (the ping went out): ' + C.LastError, 'connected', MqttStateText(C));
  AssertEquals('one connection', 1, C.Connects);
  { the ping's wait, its answer, the deadline; a quarter tick made 7 }
  AssertTrue(Format('%d wakes in 8.5 s', [Wakes]), Wakes <= 4);
  { the socket left the wait when the PINGRESP came and went back in when
    it was read: one call (one-shot, re-armed); out and in made two }
  Calls := ChnWaitOsChanges - Calls;
  {$IFDEF LINUX}
  AssertTrue(Format('%d calls changing the OS wait for one ping', [Calls]), Calls <= 1);
  {$ENDIF}
end;

{ MqttStepAt stamps the traffic of its round with the round's clock
  (NowMs), not with the clock read again - one system call less in each
  round that sent or received: a round that began 400 ms ago (well within
  the second PingAt allows for) sends a message; the stamp is that round's
  time. }
procedure TTestChnMqtt.TestTrafficStampedWithTheRoundsClock;
var
  Err: AnsiString;
  T: QWord;
begin
  StartBroker;
  MqttInit(C);
  C.Port := Broker.Port;
  C.Qos := 0;
  AssertTrue(Err, MqttOpen(C, Err));
  AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  MqttPublish(C, 'chn/stamp', 'x', False);
  T := GetTickCount64 - 400;
  MqttStepAt(C, T);
  AssertEquals('handed over and written', 0, MqttQueued(C));
  AssertEquals('the write stamped with the round''s clock', T, C.OutAt);
end;

procedure TTestChnMqtt.TestBrokerRestartLosesNothingQueued;
var
  I: LongInt;
  Missing: string;
begin
  StartBroker;
  Client(C, Broker.Port);
  AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  Broker.Stop(SIGKILL);
  AssertTrue('the client saw the broker go', StepUntil(C, @Waiting, 10000));
  for I := 1 to 30 do
    MqttPublish(C, 'q/' + IntToStr(I), IntToStr(I), False);
  AssertEquals('queued', 30, MqttQueued(C));
  Broker.Start;
  Subscribe('q/#', []);
  Sleep(300);     { mosquitto_sub subscribed before the client comes back (1 s back-off at least) }
  AssertTrue('all sent after the restart: ' + C.LastError, StepUntil(C, @Emptied, 40000));
  Missing := '';
  for I := 1 to 30 do
    if not Sub.WaitFor('q/' + IntToStr(I) + ' ' + IntToStr(I) + #10, 3000) then
      Missing := Missing + ' ' + IntToStr(I);
  AssertEquals('missing after the restart: ' + Sub.Text, '', Missing);
  AssertEquals('nothing dropped', 0, C.Dropped);
  AssertTrue('connected twice', C.Connects >= 2);
end;

procedure TTestChnMqtt.TestFullQueueDropsTheOldest;
var
  I: LongInt;
begin
  StartBroker;
  Broker.Stop;
  Client(C, Broker.Port);          { nobody there yet }
  C.QueueMax := 10;
  for I := 1 to 15 do
    MqttPublish(C, 'd/' + IntToStr(I), IntToStr(I), False);
  AssertEquals('dropped', 5, C.Dropped);
  AssertEquals('queued', 10, MqttQueued(C));
  AssertTrue('waiting to reconnect: ' + MqttStateText(C), StepUntil(C, @Waiting, 3000));
  Broker.Start;
  Subscribe('d/#', []);
  Sleep(300);
  AssertTrue('sent: ' + C.LastError, StepUntil(C, @Emptied, 40000));
  AssertTrue('the newest: ' + Sub.Text, Sub.WaitFor('d/15 15'#10, 3000));
  AssertTrue('the oldest kept: ' + Sub.Text, Sub.WaitFor('d/6 6'#10, 3000));
  AssertEquals('the dropped ones never came: ' + Sub.Text, 0, Pos('d/5 5'#10, Sub.Text));
end;

{ Open C, publish Payload on Topic: the broker acknowledges it and the
  subscriber Sub gets it. }
procedure AssertPublished(var C: tMqttClient; Sub: TMqttSub; const Topic, Payload: string);
var
  Err: AnsiString;
begin
  TAssert.AssertTrue(Err, MqttOpen(C, Err));
  TAssert.AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  MqttPublish(C, Topic, Payload, False);
  TAssert.AssertTrue('acknowledged', StepUntil(C, @Emptied, 5000));
  TAssert.AssertTrue('the subscriber got it: ' + Sub.Text, Sub.WaitFor(Topic + ' ' + Payload + #10, 5000));
end;

{ Messages Topic/1 .. Topic/N each exactly once in Text: '' or which not. }
function EachOnce(const Text, Topic: string; N: LongInt): string;
var
  I, K: LongInt;
begin
  Result := '';
  for I := 1 to N do
  begin
    K := CountOf(Topic + '/' + IntToStr(I) + ' ' + IntToStr(I) + #10, Text);
    if K <> 1 then
      Result := Result + Format(' %s/%d %d times', [Topic, I, K]);
  end;
end;

{ Messages handed to the library, the broker stopped before it could
  acknowledge them, then killed: after the restart each arrives, and
  once (the library sends them again itself, under their message ids). }
procedure TTestChnMqtt.TestHandedOverSentOnceAfterLoss;
var
  I: LongInt;
begin
  StartBroker;
  Client(C, Broker.Port);
  AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  FpKill(Broker.Pid, SIGSTOP);
  for I := 1 to 5 do
    MqttPublish(C, 'h/' + IntToStr(I), IntToStr(I), False);
  StepUntil(C, @Waiting, 500);          { handed over; no PUBACK can come }
  AssertEquals('still queued', 5, MqttQueued(C));
  for I := 0 to 4 do
    AssertTrue('handed over', MqttQueuedMessage(C, I).Sent);
  Broker.Stop(SIGKILL);
  AssertTrue('the client saw the broker go', StepUntil(C, @Waiting, 10000));
  Broker.Start;
  Subscribe('h/#', []);
  Sleep(300);
  AssertTrue('all acknowledged after the restart: ' + C.LastError, StepUntil(C, @Emptied, 40000));
  Sub.WaitFor('h/5 5'#10, 3000);
  Sleep(300);                           { a second copy would come now }
  AssertEquals('each once: ' + Sub.Text, '', EachOnce(Sub.Text, 'h', 5));
end;

{ Messages the broker acknowledged are not sent again after a reconnect. }
procedure TTestChnMqtt.TestAcknowledgedNotSentAgain;
var
  I: LongInt;
begin
  StartBroker;
  Subscribe('a/#', []);
  Sleep(300);
  Client(C, Broker.Port);
  AssertTrue('connected: ' + C.LastError, StepUntil(C, @Connected, 5000));
  for I := 1 to 5 do
    MqttPublish(C, 'a/' + IntToStr(I), IntToStr(I), False);
  AssertTrue('acknowledged', StepUntil(C, @Emptied, 5000));
  AssertTrue('arrived: ' + Sub.Text, Sub.WaitFor('a/5 5'#10, 3000));
  Broker.Stop(SIGKILL);
  AssertTrue('the client saw the broker go', StepUntil(C, @Waiting, 10000));
  FreeAndNil(Sub);
  Broker.Start;
  Subscribe('a/#', []);
  Sleep(300);
  for I := 6 to 8 do
    MqttPublish(C, 'a/' + IntToStr(I), IntToStr(I), False);
  AssertTrue('sent after the restart: ' + C.LastError, StepUntil(C, @Emptied, 40000));
  AssertTrue('the new ones: ' + Sub.Text, Sub.WaitFor('a/8 8'#10, 3000));
  Sleep(300);
  AssertEquals('none of the acknowledged ones again: ' + Sub.Text, 0, Pos('a/1 1'#10, Sub.Text));
  AssertEquals('each new one once: ' + Sub.Text, 1, CountOf('a/6 6'#10, Sub.Text));
end;

procedure TTestChnMqtt.TestUserAndPassword;
var
  Err, Why: string;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Dir := MakeTempDir('chn-mqtt');
  Why := MakePasswordFile(Dir, 'gate', 's3cret');
  if Why <> '' then
    Ignore(Why);
  StartBroker('allow_anonymous false' + LineEnding + 'password_file ' + Dir + 'passwd');
  Subscribe('pw/#', ['-u', 'gate', '-P', 's3cret']);
  Sleep(300);
  C.Port := Broker.Port;
  C.User := 'gate';
  C.Password := 's3cret';
  AssertPublished(C, Sub, 'pw/x', '1');
  { a wrong password: refused, the broker and the reason named }
  Other.Port := Broker.Port;
  Other.User := 'gate';
  Other.Password := 'wrong';
  AssertTrue(Err, MqttOpen(Other, Err));
  AssertTrue('refused: ' + MqttStateText(Other), StepUntil(Other, @Waiting, 5000));
  AssertEquals('never connected', 0, Other.Connects);
  AssertEquals(Format('the broker 127.0.0.1:%d refused the connection: Connection Refused: not authorised.',
    [Broker.Port]), Other.LastError);
end;

procedure TTestChnMqtt.TestTls;
var
  Err, Why: string;
begin
  if MosquittoMissing <> '' then
    Ignore(MosquittoMissing);
  Dir := MakeTempDir('chn-mqtt');
  Why := MakeTlsFiles(Dir);
  if Why <> '' then
    Ignore(Why);
  StartBroker('allow_anonymous true' + LineEnding + 'cafile ' + Dir + 'ca.crt' + LineEnding +
    'certfile ' + Dir + 'server.crt' + LineEnding + 'keyfile ' + Dir + 'server.key');
  Subscribe('tls/#', ['--cafile', Dir + 'ca.crt']);
  Sleep(300);
  C.Port := Broker.Port;
  C.Tls := True;
  C.CaFile := Dir + 'ca.crt';
  AssertPublished(C, Sub, 'tls/x', 'secret');
  { without TLS the broker's TLS listener never lets a client in }
  Other.Port := Broker.Port;
  AssertTrue(Err, MqttOpen(Other, Err));
  AssertFalse('plain client connected to a TLS listener', StepUntil(Other, @Connected, 1500));
  { a CA file that is not there: refused at open, named }
  MqttClose(C);
  MqttInit(C);
  C.Tls := True;
  C.CaFile := Dir + 'none.crt';
  AssertFalse('opened with no CA file', MqttOpen(C, Err));
  AssertTrue(Err, Pos('MQTT: ', Err) = 1);
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnMqtt);
end.
