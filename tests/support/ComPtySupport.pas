{ ComPtySupport - what the serial-layer tests on ptys share (Unix only):
  the Linux c_cflag bits they check the kernel's termios against (read
  from <asm/termbits.h>, not from the code under test), and an open as
  another user: root may open everything, so a refusal for lack of
  permission, or a device another user must still be able to open, is
  tried in a forked child that dropped to nobody first. }
unit ComPtySupport;

{$MODE OBJFPC}{$H+}

interface

const
  { tTermios2 and TCGETS2 are ChnUnix's }
  KBOTHER = $1000;
  KCBAUD = $100F;
  { the c_cflag bits the layer is responsible for (Linux <asm/termbits.h>) }
  KCSIZE = $30; KCS5 = $00; KCS6 = $10; KCS7 = $20; KCS8 = $30;
  KCSTOPB = $40; KPARENB = $100; KPARODD = $200;
  KCMSPAR = $40000000; KCRTSCTS = $80000000;
  KB50 = $1; KB1200 = $9; KB9600 = $D; KB115200 = $1002; KB4000000 = $100F;

  { OpenComAsNobody's codes above any ChResult: the child could not drop
    root, or was still root after dropping it }
  NobodyNotDropped = 90;
  NobodyStillRoot = 91;

{ ChOpen of a new NAM=COM channel set up with Params, in a forked child
  that runs as nobody (65534) when the suite runs as root. The child's
  exit code: ChResult, plus 50 when CheckClosed and the channel is not
  closed after the open, or NobodyNotDropped / NobodyStillRoot; -1 when
  the fork or the wait failed, -2 when the child did not exit. No FPCUnit
  in the child: it ends by FpExit with the code. }
function OpenComAsNobody(const Params: string; CheckClosed: Boolean): LongInt;

implementation

uses
  BaseUnix, ChnTypes, ChnVirt, ChnCom;

function OpenComAsNobody(const Params: string; CheckClosed: Boolean): LongInt;
var
  Pid: TPid;
  Status: cint;
  C: pChnVirt;
  Code: LongInt;
begin
  Pid := FpFork;
  if Pid < 0 then
    Exit(-1);
  if Pid = 0 then
  begin
    if FpGetuid = 0 then
      if (FpSetgid(65534) <> 0) or (FpSetuid(65534) <> 0) then
        FpExit(NobodyNotDropped);
    if FpGetuid = 0 then
      FpExit(NobodyStillRoot);
    C := ChnCollection^.ChNewInit(ChnCom.cName);
    C^.ChSetParam(Params);
    C^.ChOpen;
    Code := C^.ChResult;
    if CheckClosed and (C^.ChReady <> CHS_Close) then
      Code := Code + 50;
    FpExit(Code);
  end;
  Status := 0;
  if FpWaitPid(Pid, @Status, 0) <> Pid then
    Exit(-1);
  if not WIFEXITED(Status) then
    Exit(-2);
  Result := WEXITSTATUS(Status);
end;

end.
