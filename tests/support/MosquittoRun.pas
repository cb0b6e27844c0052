{ MosquittoRun - Debian's mosquitto broker for the tests, and its
  mosquitto_sub / mosquitto_pub clients as the IT side.

  TMosquitto writes a configuration into a new temporary folder (one
  listener on a free loopback port, anonymous clients or the listener
  settings given - a password file, TLS certificates -, no persistence),
  starts "mosquitto -c" and waits until the port is taken; Stop ends it by
  its PID (SIGTERM, or SIGKILL: a crash), Start brings it back on the same
  port. MakePasswordFile and MakeTlsFiles make what such settings name
  (with Debian's mosquitto_passwd and openssl). TMqttSub runs mosquitto_sub -v on a topic and collects what it
  printed ("topic payload" lines). A test that needs them calls
  MosquittoMissing first and skips with the reason when it says one. }
unit MosquittoRun;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix, DaemonRun;

type
  TMosquitto = class(TDaemon)
  private
    FDir: string;
    FPort: Word;
  public
    { Listener: the lines after "listener PORT 127.0.0.1" (default:
      anonymous clients) }
    constructor Create(const Listener: string = 'allow_anonymous true');
    destructor Destroy; override;
    procedure Start;
    property Port: Word read FPort;
  end;

  TMqttSub = class
  private
    FProc: TProcess;
    FOut: string;
  public
    { mosquitto_sub -v -t Topic on the broker at Port (-q 1) }
    constructor Create(Port: Word; const Topic: string; const Extra: array of string);
    destructor Destroy; override;
    { what arrived so far ("topic payload" lines) }
    function Text: string;
    { wait up to Ms until Text contains S }
    function WaitFor(const S: string; Ms: LongInt): Boolean;
  end;

{ '' when mosquitto, mosquitto_sub and mosquitto_pub and libmosquitto are
  there; else why not, with the install command. }
function MosquittoMissing: string;
{ mosquitto_pub -t Topic -m Payload on the broker at Port; its exit code. }
function MqttPub(Port: Word; const Topic, Payload: string): LongInt;
{ How often Needle occurs in S (messages a subscriber saw). }
function Occurs(const Needle, S: string): LongInt;
{ Stop P (with Sig) if it still runs, and free it: the gateway tests'
  programs. }
procedure Ended(var P: TProcess; Sig: cint);
{ Dir/passwd with User and Password (mosquitto_passwd -b); '' or why not. }
function MakePasswordFile(const Dir, User, Password: string): string;
{ A CA (Dir/ca.crt) and a server certificate it signed for 127.0.0.1
  (Dir/server.crt, Dir/server.key), made by openssl; '' or why not. The
  key is readable by all: mosquitto started as root reads it after
  dropping to its own user. }
function MakeTlsFiles(const Dir: string): string;

implementation

uses
  Ser2netRun, TestTempDir, BinSupport, ChnMqtt;

function Occurs(const Needle, S: string): LongInt;
var
  P: LongInt;
begin
  Result := 0;
  P := Pos(Needle, S);
  while P > 0 do
  begin
    Inc(Result);
    P := Pos(Needle, S, P + 1);
  end;
end;

procedure Ended(var P: TProcess; Sig: cint);
begin
  StopProcessWith(P, Sig);
end;

function Tool(const Name: string): string;
begin
  Result := ExeSearch(Name, GetEnvironmentVariable('PATH') + ':/usr/sbin:/sbin');
end;

function MosquittoMissing: string;
var
  Err: AnsiString;
begin
  Result := '';
  if (Tool('mosquitto') = '') or (Tool('mosquitto_sub') = '') or (Tool('mosquitto_pub') = '') then
    Result := 'mosquitto or its clients are not installed'
  else if not MqttLoad(Err) then
    Result := Err;
  if Result <> '' then
    Result := Result + ' (Debian: apt-get install mosquitto mosquitto-clients libmosquitto1; .ci/run does)';
end;

constructor TMosquitto.Create(const Listener: string);
begin
  inherited Create;
  FDir := MakeTempDir('chn-mosquitto');
  FLog := FDir + '/mosquitto.log';
  FPort := FreeLoopbackPort;
  WriteFileText(FDir + '/mosquitto.conf',
    'listener ' + IntToStr(FPort) + ' 127.0.0.1' + LineEnding +
    Listener + LineEnding +
    'persistence false' + LineEnding +
    'log_dest stderr' + LineEnding);
  Start;
end;

destructor TMosquitto.Destroy;
begin
  Stop(SIGTERM);
  RemoveTempDir(FDir);
  inherited Destroy;
end;

procedure TMosquitto.Start;
var
  Deadline: QWord;
begin
  if Running then
    Exit;
  Launch('exec "$0" -c "$1" >>"$2" 2>&1', [Tool('mosquitto'), FDir + '/mosquitto.conf', FLog]);
  Deadline := GetTickCount64 + 15000;   { generous: a loaded machine starts it slowly }
  repeat
    if PortTaken(FPort) then
      Exit;
    Sleep(10);
  until (GetTickCount64 > Deadline) or not FProc.Running;
  raise Exception.Create('mosquitto did not come up: ' + LogText);
end;

constructor TMqttSub.Create(Port: Word; const Topic: string; const Extra: array of string);
var
  A: string;
begin
  inherited Create;
  FProc := TProcess.Create(nil);
  FProc.Executable := Tool('mosquitto_sub');
  FProc.Parameters.Add('-h');
  FProc.Parameters.Add('127.0.0.1');
  FProc.Parameters.Add('-p');
  FProc.Parameters.Add(IntToStr(Port));
  FProc.Parameters.Add('-q');
  FProc.Parameters.Add('1');
  FProc.Parameters.Add('-v');
  FProc.Parameters.Add('-t');
  FProc.Parameters.Add(Topic);
  for A in Extra do
    FProc.Parameters.Add(A);
  FProc.Options := [poUsePipes, poStderrToOutPut];
  FProc.Execute;
end;

destructor TMqttSub.Destroy;
begin
  StopProcessWith(FProc, SIGTERM);
  inherited Destroy;
end;

function TMqttSub.Text: string;
begin
  Drain(FProc, FOut);
  Result := FOut;
end;

function TMqttSub.WaitFor(const S: string; Ms: LongInt): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    if Pos(S, Text) > 0 then
      Exit(True);
    Sleep(10);
  until GetTickCount64 > Deadline;
  Result := Pos(S, Text) > 0;
end;

function MqttPub(Port: Word; const Topic, Payload: string): LongInt;
var
  Output: string;
begin
  Result := RunExe(Tool('mosquitto_pub'), ['-h', '127.0.0.1', '-p', IntToStr(Port), '-q', '1',
    '-t', Topic, '-m', Payload], 5000, Output);
end;

{ Run a shell script; '' or its output when it failed. }
function Shell(const Script: string; const Args: array of string): string;
var
  A: array of string;
  I: LongInt;
  Output: string;
begin
  SetLength(A, Length(Args) + 2);
  A[0] := '-c';
  A[1] := Script;
  for I := 0 to High(Args) do
    A[I + 2] := Args[I];
  if RunExe('/bin/sh', A, 30000, Output) = 0 then
    Result := ''
  else
    Result := Script + ': ' + Output;
end;

function MakePasswordFile(const Dir, User, Password: string): string;
begin
  if Tool('mosquitto_passwd') = '' then
    Exit('mosquitto_passwd is not installed (Debian: apt-get install mosquitto)');
  Result := Shell('"$0" -c -b "$1/passwd" "$2" "$3" && chmod 644 "$1/passwd"',
    [Tool('mosquitto_passwd'), Dir, User, Password]);
end;

function MakeTlsFiles(const Dir: string): string;
begin
  if Tool('openssl') = '' then
    Exit('openssl is not installed (Debian: apt-get install openssl)');
  Result := Shell('cd "$0" && ' +
    'openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2 -subj /CN=chn-test-ca && ' +
    'openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr -subj /CN=127.0.0.1 && ' +
    'printf "subjectAltName=IP:127.0.0.1,DNS:localhost\n" > san.cnf && ' +
    'openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial -out server.crt ' +
    '-days 2 -extfile san.cnf && chmod 644 server.key', [Dir]);
end;

end.
