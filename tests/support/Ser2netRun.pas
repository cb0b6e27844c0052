{ Ser2netRun - Debian's ser2net as a serial device server for the tests.

  Writes a YAML configuration into a new temporary folder with two ports
  on the loopback interface for one serial device: a raw TCP port and a
  Telnet port with RFC 2217; starts "ser2net -n -u" (in the foreground, no
  UUCP lock files) and waits until it accepts connections; stops it by its
  PID (SIGTERM, or SIGKILL for a crash) and waits for it. The ports are
  free ones the OS handed out just before. }
unit Ser2netRun;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix, DaemonRun;

type
  TSer2net = class(TDaemon)
  private
    FDir, FDevice: string;
    FRawPort, FRfcPort: Word;
  public
    { The program on PATH, '' when not installed. }
    class function Path: string;
    { Configure for Device (a pty slave) at Line (e.g. '9600n81') and start. }
    constructor Create(const Device, Line: string);
    destructor Destroy; override;
    procedure Start;
    property RawPort: Word read FRawPort;
    property RfcPort: Word read FRfcPort;
  end;

{ A TCP port on 127.0.0.1 that nothing listens on right now. }
function FreeLoopbackPort: Word;
{ True when something listens on 127.0.0.1:Port (probed by binding it). }
function PortTaken(Port: Word): Boolean;

implementation

uses
  ChnSock, TestTempDir;

function FreeLoopbackPort: Word;
begin
  Result := SockFreeLoopbackPort;
  if Result = 0 then
    raise Exception.Create('cannot bind a loopback port');
end;

class function TSer2net.Path: string;
begin
  Result := ExeSearch('ser2net', GetEnvironmentVariable('PATH') + ':/usr/sbin:/sbin');
end;

constructor TSer2net.Create(const Device, Line: string);
var
  Cfg: string;
begin
  inherited Create;
  FDevice := Device;
  FDir := MakeTempDir('chn-ser2net');
  FLog := FDir + '/ser2net.log';
  FRawPort := FreeLoopbackPort;
  repeat
    FRfcPort := FreeLoopbackPort;
  until FRfcPort <> FRawPort;
  Cfg :=
    'connection: &raw' + LineEnding +
    '  accepter: tcp,127.0.0.1,' + IntToStr(FRawPort) + LineEnding +
    '  connector: serialdev,' + Device + ',' + Line + ',local' + LineEnding +
    'connection: &rfc2217' + LineEnding +
    '  accepter: telnet(rfc2217),tcp,127.0.0.1,' + IntToStr(FRfcPort) + LineEnding +
    '  connector: serialdev,' + Device + ',' + Line + ',local' + LineEnding;
  WriteFileText(FDir + '/ser2net.yaml', Cfg);
  Start;
end;

destructor TSer2net.Destroy;
begin
  Stop(SIGTERM);
  RemoveTempDir(FDir);
  inherited Destroy;
end;

function PortTaken(Port: Word): Boolean;
var
  A: tSockAddrs;
  N: LongInt;
  S: tSock;
begin
  SockResolve('127.0.0.1', Port, True, A, N);
  Result := SockListen(A[0], S) = seInUse;
  SockClose(S);
end;

procedure TSer2net.Start;
var
  Deadline: QWord;
begin
  if Running then
    Exit;
  Launch('exec "$0" -n -u -c "$1" -P "$2" >>"$3" 2>&1',
    [Path, FDir + '/ser2net.yaml', FDir + '/ser2net.pid', FLog]);
  { ready when both ports are taken: probed by binding them ourselves, as
    a probe connection would open the device and hold it for a moment }
  Deadline := GetTickCount64 + 5000;
  repeat
    if PortTaken(FRawPort) and PortTaken(FRfcPort) then
      Exit;
    Sleep(20);
  until (GetTickCount64 > Deadline) or not FProc.Running;
  raise Exception.Create('ser2net did not come up: ' + LogText);
end;

end.
