{ ChnMqtt - an MQTT client on Eclipse Mosquitto's client library
  (libmosquitto, Debian package libmosquitto1), loaded when the first
  client opens: a program that never opens one runs without it, and one
  that does on a system without it gets
  'libmosquitto.so.1 not found (apt-get install libmosquitto1)'. The
  environment variable CHN_LIBMOSQUITTO names another file to load instead
  (a libmosquitto built elsewhere: a path, or a name the loader searches);
  the messages then name that file.

  One thread: the broker's socket joins the program-wide wait (ChnWait),
  so ChnWaitAny ends when the broker sent something or, while the client
  has bytes to send (mosquitto_want_write), when the socket can take them.
  MqttStep, called after every wait, does the library's work without
  blocking (mosquitto_loop_read, loop_write, loop_misc for the keep-alive)
  and MqttWaitMs says how long the program may wait at most (the next
  keep-alive or reconnect). No thread of libmosquitto's own is started.
  An idle client costs little: the socket is read only when the wait saw
  it readable, and the program wakes for the keep-alive only when a
  PINGREQ is due (KeepAlive s after the last traffic either way, plus the
  second the library rounds its clock to), not on a fixed tick.

  Delivery. Every message goes through the client's own queue, bounded
  by QueueMax messages: while the broker is away (not yet connected, lost,
  restarting) messages wait there and the oldest is dropped and counted
  (Dropped) when it is full. Once connected they are handed to the
  library in order; a QoS 1 message stays in the queue until the broker
  acknowledged it (PUBACK). One handed over when the connection was lost
  is sent again after the reconnect by the library itself (same message
  id, DUP set), one not yet handed over then goes out in its turn - so a
  broker restart loses nothing that fit in the queue and sends nothing
  twice that the broker had acknowledged (at least once: a message the
  broker passed on just before it died may still arrive twice). QoS 0
  messages leave the queue when handed over.

  Connection: host and port, user name and password, TLS with a CA file
  (or directory) as libmosquitto offers them, a last will (published by
  the broker when the client vanishes) and an online message published
  retained after each connect; a lost or refused connection is tried again
  after 1 s, doubling up to 30 s. Subscriptions are made again after each
  connect; received messages wait in Inbox for MqttTakeMessage. }
unit ChnMqtt;

{$I chn.inc}

interface

uses
  ChnWait;

const
  MqttLibName = {$IFDEF WINDOWS}'mosquitto.dll'{$ELSE}'libmosquitto.so.1'{$ENDIF};
  MqttQueueDefault = 10000;
  MqttQueueFirst = 16;       {< the queue's room at first (it doubles up to QueueMax) }
  MqttKeepAliveDefault = 30;
  MqttBackoffMinMs = 1000;
  MqttBackoffMaxMs = 30000;

type
  tMqttMessage = record
    Topic  : AnsiString;
    Payload: AnsiString;
    Qos    : LongInt;
    Retain : Boolean;
    Mid    : LongInt;     {< the library's message id while handed over }
    Sent   : Boolean;     {< handed to the library, no PUBACK yet }
  end;

  tMqttState = (msClosed, msConnecting, msConnected, msWaiting);

  pMqttClient = ^tMqttClient;
  tMqttClient = record
    { settings: fill before MqttOpen }
    Host       : AnsiString;
    Port       : LongInt;       {< default 1883 (8883 with TLS) }
    ClientId   : AnsiString;    {< '' : the library makes one }
    User       : AnsiString;
    Password   : AnsiString;
    Tls        : Boolean;
    CaFile     : AnsiString;    {< a CA file; a directory is taken as CA path }
    Insecure   : Boolean;       {< TLS without checking the server's name }
    KeepAlive  : LongInt;       {< seconds }
    Qos        : LongInt;       {< 0 or 1, default 1 }
    QueueMax   : LongInt;
    WillTopic  : AnsiString;    {< '' : no will }
    WillPayload: AnsiString;
    OnlinePayload: AnsiString;  {< published retained to WillTopic on connect }
    { state }
    State      : tMqttState;
    Mosq       : Pointer;
    Src        : pChnWaitSource;
    Sock       : LongInt;
    RetryAt    : QWord;
    BackoffMs  : LongInt;
    { the queue, a ring: QueueCount messages from QueueHead on (oldest
      first; those handed to the library and not acknowledged come first);
      its room doubles as it fills, up to QueueMax }
    Queue      : array of tMqttMessage;
    QueueHead  : LongInt;
    QueueCount : LongInt;
    Subs       : array of AnsiString;
    Inbox      : array of tMqttMessage;
    InboxHead  : LongInt;
    {- counters }
    Delivered  : LongInt;       {< acknowledged (QoS 1) or handed over (QoS 0) }
    Dropped    : LongInt;       {< dropped from a full queue }
    Connects   : LongInt;
    LastError  : AnsiString;
    Changed    : Boolean;       {< the connection state changed (MqttStep's result) }
    InAt, OutAt: QWord;         {< GetTickCount64 of the round that saw the last traffic in, out }
  end;

{ Load libmosquitto (MqttLibName, or the file CHN_LIBMOSQUITTO names);
  True when it is there (loaded once per process). Err:
  'libmosquitto.so.1 not found (apt-get install libmosquitto1)', or
  'FILE has no mosquitto_... (libmosquitto 1.6 or later is needed)'. }
function MqttLoad(out Err: AnsiString): Boolean;
{ Settings to their defaults (Host 127.0.0.1, Port 1883, QoS 1 ...). }
procedure MqttInit(var C: tMqttClient);
{ Create the client and start connecting (without waiting). False with
  Err when the library is missing or refuses a setting (the CA file ...). }
function MqttOpen(var C: tMqttClient; out Err: AnsiString): Boolean;
{ Disconnect cleanly (what is queued and not sent is lost), free it all. }
procedure MqttClose(var C: tMqttClient);
{ Queue a message (QoS of C.Qos). Never blocks; a full queue drops its
  oldest message (counted in Dropped). }
procedure MqttPublish(var C: tMqttClient; const Topic, Payload: AnsiString; Retain: Boolean);
{ Subscribe to Topic (wildcards allowed), now and after every reconnect. }
procedure MqttSubscribe(var C: tMqttClient; const Topic: AnsiString);
{ Do the client's work without blocking; True when a message arrived or
  the connection changed. Call after every ChnWaitAny. }
function MqttStep(var C: tMqttClient): Boolean;
{ The same, NowMs (GetTickCount64) read by the caller for its whole round
  (a program that reads the clock once per wake-up; the round, from NowMs
  to its MqttStepAt, shorter than a second). }
function MqttStepAt(var C: tMqttClient; NowMs: QWord): Boolean;
{ Milliseconds the program may wait before the next MqttStep at most. }
function MqttWaitMs(const C: tMqttClient): LongInt;
{ The same as a GetTickCount64 time; High(QWord) when nothing is due. }
function MqttDueAt(const C: tMqttClient): QWord;
{ The next received message; False when none. }
function MqttTakeMessage(var C: tMqttClient; out M: tMqttMessage): Boolean;
{ Messages waiting in the queue (not yet acknowledged). }
function MqttQueued(const C: tMqttClient): LongInt;
{ The I-th of them, oldest first (0 .. MqttQueued - 1). }
function MqttQueuedMessage(const C: tMqttClient; I: LongInt): tMqttMessage;
{ 'connected', 'connecting', 'waiting' (to reconnect), 'closed'. }
function MqttStateText(const C: tMqttClient): AnsiString;

implementation

uses
  SysUtils, DynLibs, ctypes;

const
  MOSQ_ERR_SUCCESS = 0;
  MOSQ_ERR_NO_CONN = 4;
  MOSQ_ERR_CONN_LOST = 7;

type
  PMosqMessage = ^TMosqMessage;
  {$PUSH}{$PACKRECORDS C}   { struct mosquitto_message, C layout (chn.inc packs records) }
  TMosqMessage = record
    Mid       : cint;
    Topic     : PChar;
    Payload   : Pointer;
    PayloadLen: cint;
    Qos       : cint;
    Retain    : Boolean;
  end;
  {$POP}
  TConnectCb = procedure(Mosq, Obj: Pointer; Rc: cint); cdecl;
  TPublishCb = procedure(Mosq, Obj: Pointer; Mid: cint); cdecl;
  TMessageCb = procedure(Mosq, Obj: Pointer; Msg: PMosqMessage); cdecl;

var
  Lib: TLibHandle = NilHandle;
  LibInited: Boolean = False;
  mosquitto_lib_init: function: cint; cdecl;
  mosquitto_lib_cleanup: function: cint; cdecl;
  mosquitto_new: function(Id: PChar; Clean: Boolean; Obj: Pointer): Pointer; cdecl;
  mosquitto_destroy: procedure(Mosq: Pointer); cdecl;
  mosquitto_username_pw_set: function(Mosq: Pointer; User, Pw: PChar): cint; cdecl;
  mosquitto_will_set: function(Mosq: Pointer; Topic: PChar; Len: cint; Payload: Pointer;
    Qos: cint; Retain: Boolean): cint; cdecl;
  mosquitto_tls_set: function(Mosq: Pointer; CaFile, CaPath, CertFile, KeyFile: PChar;
    PwCb: Pointer): cint; cdecl;
  mosquitto_tls_insecure_set: function(Mosq: Pointer; Value: Boolean): cint; cdecl;
  mosquitto_connect_async: function(Mosq: Pointer; Host: PChar; Port, KeepAlive: cint): cint; cdecl;
  mosquitto_reconnect_async: function(Mosq: Pointer): cint; cdecl;
  mosquitto_disconnect: function(Mosq: Pointer): cint; cdecl;
  mosquitto_socket: function(Mosq: Pointer): cint; cdecl;
  mosquitto_loop_read: function(Mosq: Pointer; MaxPackets: cint): cint; cdecl;
  mosquitto_loop_write: function(Mosq: Pointer; MaxPackets: cint): cint; cdecl;
  mosquitto_loop_misc: function(Mosq: Pointer): cint; cdecl;
  mosquitto_want_write: function(Mosq: Pointer): Boolean; cdecl;
  mosquitto_publish: function(Mosq: Pointer; Mid: pcint; Topic: PChar; Len: cint; Payload: Pointer;
    Qos: cint; Retain: Boolean): cint; cdecl;
  mosquitto_subscribe: function(Mosq: Pointer; Mid: pcint; Sub: PChar; Qos: cint): cint; cdecl;
  mosquitto_connect_callback_set: procedure(Mosq: Pointer; Cb: TConnectCb); cdecl;
  mosquitto_disconnect_callback_set: procedure(Mosq: Pointer; Cb: TConnectCb); cdecl;
  mosquitto_publish_callback_set: procedure(Mosq: Pointer; Cb: TPublishCb); cdecl;
  mosquitto_message_callback_set: procedure(Mosq: Pointer; Cb: TMessageCb); cdecl;
  mosquitto_strerror: function(Rc: cint): PChar; cdecl;
  mosquitto_connack_string: function(Rc: cint): PChar; cdecl;

function MqttLoad(out Err: AnsiString): Boolean;
var
  FileName: AnsiString;

  function Get(const Name: AnsiString; var P): Boolean;
  begin
    Pointer(P) := GetProcedureAddress(Lib, Name);
    Result := Pointer(P) <> nil;
    if not Result then
      Err := FileName + ' has no ' + Name + ' (libmosquitto 1.6 or later is needed)';
  end;

begin
  Err := '';
  if LibInited then
    Exit(True);
  FileName := GetEnvironmentVariable('CHN_LIBMOSQUITTO');
  if FileName = '' then
    FileName := MqttLibName;
  if Lib = NilHandle then
    Lib := LoadLibrary(FileName);
  if Lib = NilHandle then
  begin
    Err := FileName + ' not found (apt-get install libmosquitto1)';
    Exit(False);
  end;
  Result := Get('mosquitto_lib_init', mosquitto_lib_init) and
    Get('mosquitto_lib_cleanup', mosquitto_lib_cleanup) and
    Get('mosquitto_new', mosquitto_new) and Get('mosquitto_destroy', mosquitto_destroy) and
    Get('mosquitto_username_pw_set', mosquitto_username_pw_set) and
    Get('mosquitto_will_set', mosquitto_will_set) and Get('mosquitto_tls_set', mosquitto_tls_set) and
    Get('mosquitto_tls_insecure_set', mosquitto_tls_insecure_set) and
    Get('mosquitto_connect_async', mosquitto_connect_async) and
    Get('mosquitto_reconnect_async', mosquitto_reconnect_async) and
    Get('mosquitto_disconnect', mosquitto_disconnect) and Get('mosquitto_socket', mosquitto_socket) and
    Get('mosquitto_loop_read', mosquitto_loop_read) and
    Get('mosquitto_loop_write', mosquitto_loop_write) and
    Get('mosquitto_loop_misc', mosquitto_loop_misc) and
    Get('mosquitto_want_write', mosquitto_want_write) and
    Get('mosquitto_publish', mosquitto_publish) and Get('mosquitto_subscribe', mosquitto_subscribe) and
    Get('mosquitto_connect_callback_set', mosquitto_connect_callback_set) and
    Get('mosquitto_disconnect_callback_set', mosquitto_disconnect_callback_set) and
    Get('mosquitto_publish_callback_set', mosquitto_publish_callback_set) and
    Get('mosquitto_message_callback_set', mosquitto_message_callback_set) and
    Get('mosquitto_strerror', mosquitto_strerror) and
    Get('mosquitto_connack_string', mosquitto_connack_string);
  if not Result then
    Exit;
  mosquitto_lib_init();
  LibInited := True;
end;

procedure MqttInit(var C: tMqttClient);
begin
  Finalize(C);
  FillChar(C, SizeOf(C), 0);
  C.Host := '127.0.0.1';
  C.Port := 1883;
  C.KeepAlive := MqttKeepAliveDefault;
  C.Qos := 1;
  C.QueueMax := MqttQueueDefault;
  C.Sock := -1;
  C.BackoffMs := MqttBackoffMinMs;
end;

function MqttStateText(const C: tMqttClient): AnsiString;
const
  Names: array[tMqttState] of string[10] = ('closed', 'connecting', 'connected', 'waiting');
begin
  Result := Names[C.State];
end;

function MqttQueued(const C: tMqttClient): LongInt;
begin
  Result := C.QueueCount;
end;

{- ------------------------------------------------------------ the queue }

{ The slot of the I-th message, oldest first. }
function QueueSlot(const C: tMqttClient; I: LongInt): LongInt; inline;
begin
  Result := (C.QueueHead + I) mod Length(C.Queue);
end;

function MqttQueuedMessage(const C: tMqttClient; I: LongInt): tMqttMessage;
begin
  Result := C.Queue[QueueSlot(C, I)];
end;

{ Room for one more: the ring doubles (MqttQueueFirst at first, QueueMax
  at most), its messages moved to the front in order. Growing one slot at
  a time moved the whole queue on every message and left the heap full of
  holes. }
procedure QueueGrow(var C: tMqttClient);
var
  Old: array of tMqttMessage;
  Room, I: LongInt;
begin
  if C.QueueCount < Length(C.Queue) then
    Exit;
  Room := 2 * Length(C.Queue);
  if Room < MqttQueueFirst then
    Room := MqttQueueFirst;
  if (C.QueueMax > 0) and (Room > C.QueueMax) then
    Room := C.QueueMax;
  if Room <= C.QueueCount then
    Room := C.QueueCount + 1;
  Old := C.Queue;
  C.Queue := nil;
  SetLength(C.Queue, Room);
  for I := 0 to C.QueueCount - 1 do
    C.Queue[I] := Old[(C.QueueHead + I) mod Length(Old)];
  C.QueueHead := 0;
end;

{ Take the I-th message out, the ones after it closing up. }
procedure QueueRemove(var C: tMqttClient; I: LongInt);
var
  J: LongInt;
begin
  if I = 0 then
  begin
    Finalize(C.Queue[C.QueueHead]);
    C.QueueHead := (C.QueueHead + 1) mod Length(C.Queue);
  end
  else
  begin
    for J := I + 1 to C.QueueCount - 1 do
      C.Queue[QueueSlot(C, J - 1)] := C.Queue[QueueSlot(C, J)];
    Finalize(C.Queue[QueueSlot(C, C.QueueCount - 1)]);
  end;
  Dec(C.QueueCount);
  if C.QueueCount = 0 then
  begin
    C.QueueHead := 0;
    { a burst went out (a start's first values, the queue of a broker
      outage): the ring goes back to its first size, the memory to the
      program }
    if Length(C.Queue) > MqttQueueFirst then
      SetLength(C.Queue, MqttQueueFirst);
  end;
end;

function ErrText(Rc: cint): AnsiString;
begin
  Result := StrPas(mosquitto_strerror(Rc));
end;

{- ------------------------------------------------------------ the socket }

{ The socket the library uses now joins the wait (it changes on reconnect). }
procedure FollowSocket(var C: tMqttClient);
var
  S: LongInt;
begin
  if C.Mosq = nil then
    S := -1
  else
    S := mosquitto_socket(C.Mosq);
  if S = C.Sock then
    Exit;
  ChnWaitLeave(C.Src);
  C.Sock := S;
  if S >= 0 then
    C.Src := ChnWaitJoin(wkDescriptor, S, nil, nil);
end;

{ The connection is gone (Why): try again after the back-off. }
procedure Lost(var C: tMqttClient; const Why: AnsiString);
begin
  if C.State = msWaiting then
    Exit;
  C.LastError := Why;
  C.State := msWaiting;
  C.Changed := True;
  C.RetryAt := GetTickCount64 + QWord(C.BackoffMs);
  C.BackoffMs := C.BackoffMs * 2;
  if C.BackoffMs > MqttBackoffMaxMs then
    C.BackoffMs := MqttBackoffMaxMs;
  { what was handed over and not acknowledged stays Sent: the library
  keeps it and sends it again itself after the reconnect, under the same
  message id (with DUP) - publishing it again here sent it twice }
  { the library closed (or will close) the socket: out of the wait now,
    before its number can be another channel's }
  ChnWaitLeave(C.Src);
  C.Sock := -1;
end;

{- ------------------------------------------------------------ callbacks }

procedure OnConnect(Mosq, Obj: Pointer; Rc: cint); cdecl;
var
  C: pMqttClient;
  I: LongInt;
begin
  C := pMqttClient(Obj);
  if Rc <> 0 then
  begin
    Lost(C^, Format('the broker %s:%d refused the connection: %s',
      [C^.Host, C^.Port, StrPas(mosquitto_connack_string(Rc))]));
    Exit;
  end;
  C^.State := msConnected;
  C^.Changed := True;
  C^.BackoffMs := MqttBackoffMinMs;
  Inc(C^.Connects);
  if (C^.WillTopic <> '') and (C^.OnlinePayload <> '') then
    mosquitto_publish(Mosq, nil, PChar(C^.WillTopic), Length(C^.OnlinePayload),
      PChar(C^.OnlinePayload), 1, True);
  for I := 0 to High(C^.Subs) do
    mosquitto_subscribe(Mosq, nil, PChar(C^.Subs[I]), 1);
end;

procedure OnDisconnect(Mosq, Obj: Pointer; Rc: cint); cdecl;
begin
  if pMqttClient(Obj)^.State <> msClosed then
    Lost(pMqttClient(Obj)^, Format('disconnected from %s:%d: %s',
      [pMqttClient(Obj)^.Host, pMqttClient(Obj)^.Port, ErrText(Rc)]));
end;

procedure OnPublish(Mosq, Obj: Pointer; Mid_: cint); cdecl;
var
  C: pMqttClient;
  I: LongInt;
begin
  C := pMqttClient(Obj);
  for I := 0 to C^.QueueCount - 1 do
    with C^.Queue[QueueSlot(C^, I)] do
      if Sent and (Mid = cint(Mid_)) then
      begin
        QueueRemove(C^, I);
        Inc(C^.Delivered);
        Exit;
      end;
end;

procedure OnMessage(Mosq, Obj: Pointer; Msg: PMosqMessage); cdecl;
var
  C: pMqttClient;
  M: tMqttMessage;
begin
  C := pMqttClient(Obj);
  M.Topic := StrPas(Msg^.Topic);
  SetLength(M.Payload, Msg^.PayloadLen);
  if Msg^.PayloadLen > 0 then
    Move(Msg^.Payload^, M.Payload[1], Msg^.PayloadLen);
  M.Qos := Msg^.Qos;
  M.Retain := Msg^.Retain;
  M.Mid := Msg^.Mid;
  M.Sent := False;
  SetLength(C^.Inbox, Length(C^.Inbox) + 1);
  C^.Inbox[High(C^.Inbox)] := M;
end;

{- ------------------------------------------------------------ client }

function MqttOpen(var C: tMqttClient; out Err: AnsiString): Boolean;
var
  Rc: cint;
  Id: PChar;
begin
  Result := MqttLoad(Err);
  if not Result then
    Exit;
  Id := nil;
  if C.ClientId <> '' then
    Id := PChar(C.ClientId);
  C.Mosq := mosquitto_new(Id, True, @C);
  if C.Mosq = nil then
  begin
    Err := 'mosquitto_new failed (out of memory, or a bad client id "' + C.ClientId + '")';
    Exit(False);
  end;
  Rc := MOSQ_ERR_SUCCESS;
  if C.User <> '' then
    Rc := mosquitto_username_pw_set(C.Mosq, PChar(C.User), PChar(C.Password));
  if (Rc = MOSQ_ERR_SUCCESS) and (C.WillTopic <> '') then
    Rc := mosquitto_will_set(C.Mosq, PChar(C.WillTopic), Length(C.WillPayload),
      PChar(C.WillPayload), 1, True);
  if (Rc = MOSQ_ERR_SUCCESS) and C.Tls then
  begin
    if DirectoryExists(C.CaFile) then
      Rc := mosquitto_tls_set(C.Mosq, nil, PChar(C.CaFile), nil, nil, nil)
    else
      Rc := mosquitto_tls_set(C.Mosq, PChar(C.CaFile), nil, nil, nil, nil);
    if (Rc = MOSQ_ERR_SUCCESS) and C.Insecure then
      Rc := mosquitto_tls_insecure_set(C.Mosq, True);
  end;
  if Rc <> MOSQ_ERR_SUCCESS then
  begin
    Err := 'MQTT: ' + ErrText(Rc);
    mosquitto_destroy(C.Mosq);
    C.Mosq := nil;
    Exit(False);
  end;
  mosquitto_connect_callback_set(C.Mosq, @OnConnect);
  mosquitto_disconnect_callback_set(C.Mosq, @OnDisconnect);
  mosquitto_publish_callback_set(C.Mosq, @OnPublish);
  mosquitto_message_callback_set(C.Mosq, @OnMessage);
  C.State := msConnecting;
  Rc := mosquitto_connect_async(C.Mosq, PChar(C.Host), C.Port, C.KeepAlive);
  if Rc <> MOSQ_ERR_SUCCESS then
    Lost(C, Format('cannot connect to %s:%d: %s', [C.Host, C.Port, ErrText(Rc)]))
  else
    FollowSocket(C);
  Result := True;
end;

procedure MqttClose(var C: tMqttClient);
begin
  if C.Mosq <> nil then
  begin
    if C.State = msConnected then
    begin
      C.State := msClosed;
      { the library writes DISCONNECT at once (no thread of its own) }
      mosquitto_disconnect(C.Mosq);
    end;
    C.State := msClosed;
    mosquitto_destroy(C.Mosq);
    C.Mosq := nil;
  end;
  C.State := msClosed;
  ChnWaitLeave(C.Src);
  C.Sock := -1;
  C.Queue := nil;
  C.QueueHead := 0;
  C.QueueCount := 0;
  C.Inbox := nil;
  C.Subs := nil;
end;

procedure MqttPublish(var C: tMqttClient; const Topic, Payload: AnsiString; Retain: Boolean);
var
  M: ^tMqttMessage;
begin
  if (C.QueueMax > 0) and (C.QueueCount >= C.QueueMax) then
  begin
    QueueRemove(C, 0);
    Inc(C.Dropped);
  end;
  QueueGrow(C);
  Inc(C.QueueCount);
  M := @C.Queue[QueueSlot(C, C.QueueCount - 1)];
  M^.Topic := Topic;
  M^.Payload := Payload;
  M^.Qos := C.Qos;
  M^.Retain := Retain;
  M^.Mid := 0;
  M^.Sent := False;
end;

procedure MqttSubscribe(var C: tMqttClient; const Topic: AnsiString);
begin
  SetLength(C.Subs, Length(C.Subs) + 1);
  C.Subs[High(C.Subs)] := Topic;
  if (C.Mosq <> nil) and (C.State = msConnected) then
    mosquitto_subscribe(C.Mosq, nil, PChar(Topic), 1);
end;

{ Hand what waits in the queue to the library, in order; True when it
  handed any (the library wrote it). }
function Flush(var C: tMqttClient): Boolean;
var
  I: LongInt;
  M: ^tMqttMessage;
  Mid: cint;
  Rc: cint;
begin
  Result := False;
  I := 0;
  while (I < C.QueueCount) and (C.State = msConnected) do
  begin
    M := @C.Queue[QueueSlot(C, I)];
    if not M^.Sent then
    begin
      Mid := 0;
      Rc := mosquitto_publish(C.Mosq, @Mid, PChar(M^.Topic), Length(M^.Payload), PChar(M^.Payload), M^.Qos,
        M^.Retain);
      Result := True;
      if Rc <> MOSQ_ERR_SUCCESS then
      begin
        if (Rc = MOSQ_ERR_NO_CONN) or (Rc = MOSQ_ERR_CONN_LOST) then
          Lost(C, 'publish: ' + ErrText(Rc))
        else
          C.LastError := 'publish ' + M^.Topic + ': ' + ErrText(Rc);
        Exit;
      end;
      if M^.Qos = 0 then
      begin
        QueueRemove(C, I);
        Inc(C.Delivered);
        Continue;
      end;
      M^.Mid := Mid;
      M^.Sent := True;
    end;
    Inc(I);
  end;
end;

function MqttStep(var C: tMqttClient): Boolean;
begin
  Result := MqttStepAt(C, GetTickCount64);
end;

{ When loop_misc sends the PINGREQ: KeepAlive s after the last traffic in
  or out, by the library's clock of whole seconds - at the latest
  KeepAlive s after the traffic itself. InAt and OutAt are the time of
  the round that saw the traffic, less than a second before the library's
  own marks (the second more), so the ping is due by then. }
function PingAt(const C: tMqttClient): QWord;
begin
  Result := C.InAt;
  if C.OutAt < Result then
    Result := C.OutAt;
  Result := Result + QWord(C.KeepAlive) * 1000 + 1000;
end;

function MqttStepAt(var C: tMqttClient; NowMs: QWord): Boolean;
var
  Rc: cint;
  Read, Wrote: Boolean;
begin
  C.Changed := False;
  if C.Mosq = nil then
    Exit(False);
  if C.State = msWaiting then
  begin
    if NowMs >= C.RetryAt then
    begin
      C.State := msConnecting;
      Rc := mosquitto_reconnect_async(C.Mosq);
      if Rc <> MOSQ_ERR_SUCCESS then
        Lost(C, Format('cannot connect to %s:%d: %s', [C.Host, C.Port, ErrText(Rc)]));
      FollowSocket(C);
    end;
  end;
  if C.State in [msConnecting, msConnected] then
  begin
    { connected, its socket watched by the wait and not seen readable:
      nothing came, no read (TLS may hold decrypted bytes the socket does
      not show: always read; Windows' wait watches no socket) }
    {$IFDEF WINDOWS}
    Read := True;
    {$ELSE}
    Read := (C.State <> msConnected) or C.Tls or not ChnWaitWatching(C.Src);
    {$ENDIF}
    Wrote := False;
    Rc := MOSQ_ERR_SUCCESS;
    if Read then
      Rc := mosquitto_loop_read(C.Mosq, 100);
    if (Rc = MOSQ_ERR_SUCCESS) and (C.State in [msConnecting, msConnected]) then
    begin
      Wrote := Flush(C);
      if mosquitto_want_write(C.Mosq) then
      begin
        Wrote := True;
        Rc := mosquitto_loop_write(C.Mosq, 100);
      end;
    end;
    if (Rc = MOSQ_ERR_SUCCESS) and (C.State in [msConnecting, msConnected]) then
    begin
      if (C.State = msConnected) and (NowMs >= PingAt(C)) then
        Wrote := True;                 { loop_misc sends the PINGREQ now }
      Rc := mosquitto_loop_misc(C.Mosq);
    end;
    if (Rc <> MOSQ_ERR_SUCCESS) and (C.State in [msConnecting, msConnected]) then
      Lost(C, 'connection to ' + C.Host + ':' + IntToStr(C.Port) + ': ' + ErrText(Rc));
    if Read or Wrote or C.Changed then
    begin
      { the round's time, not the clock read again (a system call): it
        is before the library's own marks by the round's few us, well
        within the second PingAt adds (a ping resets both: it waits
        KeepAlive for the answer) }
      if Read or C.Changed or (NowMs >= PingAt(C)) then
        C.InAt := NowMs;
      if Wrote or C.Changed then
        C.OutAt := NowMs;
    end;
    if C.Src <> nil then
    begin
      ChnWaitServed(C.Src, True);
      ChnWaitOutput(C.Src, (C.State in [msConnecting, msConnected]) and mosquitto_want_write(C.Mosq));
    end;
  end;
  Result := C.Changed or (C.InboxHead < Length(C.Inbox));
end;

function MqttDueAt(const C: tMqttClient): QWord;
begin
  case C.State of
    msWaiting: Result := C.RetryAt;
    msConnecting:
      Result := GetTickCount64 + 1000;
    msConnected:
      begin
        Result := PingAt(C);
        {$IFDEF WINDOWS}
        { the wait watches no socket there: look every quarter of it }
        if Result > GetTickCount64 + QWord(C.KeepAlive) * 250 then
          Result := GetTickCount64 + QWord(C.KeepAlive) * 250;
        {$ENDIF}
      end;
  else
    Result := High(QWord);
  end;
end;

function MqttWaitMs(const C: tMqttClient): LongInt;
begin
  if C.State = msClosed then
    Result := High(LongInt)
  else
    Result := ChnWaitLeft(MqttDueAt(C));
end;

function MqttTakeMessage(var C: tMqttClient; out M: tMqttMessage): Boolean;
begin
  Result := C.InboxHead < Length(C.Inbox);
  if not Result then
  begin
    C.Inbox := nil;
    C.InboxHead := 0;
    M.Topic := '';
    M.Payload := '';
    Exit;
  end;
  M := C.Inbox[C.InboxHead];
  Inc(C.InboxHead);
end;

finalization
  if LibInited then
    mosquitto_lib_cleanup();
  if Lib <> NilHandle then
    UnloadLibrary(Lib);
end.
