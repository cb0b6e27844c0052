{ DaemonRun - a server program the tests start and stop (ser2net,
  mosquitto): run through "/bin/sh -c 'exec ...'" so that the PID is the
  server's own and its output goes to a log file, never to a pipe that
  could fill; stopped by its PID (SIGTERM, or SIGKILL for a crash) and
  waited for. }
unit DaemonRun;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix;

type
  TDaemon = class
  protected
    FProc: TProcess;
    FLog: string;
    { sh -c Script with Args as $0 $1 ...; Script must exec the server }
    procedure Launch(const Script: string; const Args: array of string);
  public
    destructor Destroy; override;
    { Stop by PID with Sig (SIGTERM, SIGKILL) and wait for the process. }
    procedure Stop(Sig: cint = SIGTERM);
    function Running: Boolean;
    function Pid: LongInt;
    { what the server printed, for failure messages }
    function LogText: string;
  end;

implementation

uses
  TestTempDir;

procedure TDaemon.Launch(const Script: string; const Args: array of string);
var
  A: string;
begin
  FreeAndNil(FProc);
  FProc := TProcess.Create(nil);
  FProc.Executable := '/bin/sh';
  FProc.Parameters.Add('-c');
  FProc.Parameters.Add(Script);
  for A in Args do
    FProc.Parameters.Add(A);
  FProc.Options := [];
  FProc.Execute;
end;

destructor TDaemon.Destroy;
begin
  Stop(SIGTERM);
  inherited Destroy;
end;

procedure TDaemon.Stop(Sig: cint);
var
  Deadline: QWord;
begin
  if (FProc = nil) or not FProc.Running then
    Exit;
  FpKill(FProc.ProcessID, Sig);
  Deadline := GetTickCount64 + 3000;
  while FProc.Running and (GetTickCount64 < Deadline) do
    Sleep(5);
  if FProc.Running then
    FpKill(FProc.ProcessID, SIGKILL);
  FProc.WaitOnExit;
  FreeAndNil(FProc);
end;

function TDaemon.Running: Boolean;
begin
  Result := (FProc <> nil) and FProc.Running;
end;

function TDaemon.Pid: LongInt;
begin
  if FProc = nil then
    Result := 0
  else
    Result := FProc.ProcessID;
end;

function TDaemon.LogText: string;
begin
  if FileExists(FLog) then
    Result := ReadFileText(FLog)
  else
    Result := '(no output)';
end;

end.
