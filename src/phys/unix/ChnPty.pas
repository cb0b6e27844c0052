{ ChnPty - pseudo-terminal pairs (Unix only): a serial line on one machine
  with no hardware and no root.

  PtyCreate opens /dev/ptmx, unlocks the slave side and returns its path
  (/dev/pts/N): a program opens that path with NAM=COM DEV=/dev/pts/N as if
  it were a serial port, while the creator talks through the master side.

  The port driver 'PTY' (NAM=COM DRV=PTY) makes tChnCom itself the master
  side of a new pair: DEV= and COM= are ignored, the pair is created on
  ChOpen and gone on ChClose (closing the master hangs the slave up). The
  slave path is TChnPortPty(CH_Port).SlavePath, also kept in PtyLastSlave.
  Line settings on a pty master are accepted and mean nothing, as on any
  pty. While no program has the slave open (before the first one, between
  two), the master reads nothing and a write the kernel refuses counts as
  sent, as on a line with nothing attached: a simulator outlives its
  clients. (Bytes the kernel accepts meanwhile wait for the next client.) tools/df1sim --pty and tests/support/PtyPair use this unit. }
unit ChnPty;

{$I chn.inc}

interface

uses
  BaseUnix, ChnTypes, ChnPort, ChnPortUnix, ChnUnix;

const
  PtyDriver = 'PTY';

type
  TChnPortPty = class(TChnPortUnix)
  protected
    { no client on the slave side (EIO) is no fault: nothing came, and
      what was sent is gone as on a line with nobody listening }
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FSlavePath: AnsiString;
    FNoClient: Boolean;
  public
    { Creates a new pair; Path is ignored. }
    function Open(const Path: tWordString): tChResult; override;
    { No program on the slave side (never opened, or closed again) is an
      idle line here, not a lost device: a simulator outlives its clients. }
    { Without a client poll(2) answers POLLHUP at once, every time; that
      is no input, so wait the Ms as on an idle line (no busy loop). }
    function WaitInput(Ms: LongInt): Boolean; override;
    { False while no program has the slave open (the last read saw the
      hang-up): the shared wait would wake at once for nothing. }
    function WaitUseful: Boolean; override;
    property SlavePath: AnsiString read FSlavePath;
  end;

{ Make the master side Fd (already open on /dev/ptmx) usable: unlock the
  slave and return its path. 0 or the errno of the failing call. }
function PtyUnlock(Fd: cint; out SlavePath: AnsiString): cint;

{ A new pair: master opened read/write, non-blocking, raw; 0 or an errno
  (then Fd = -1). }
function PtyCreate(out Fd: cint; out SlavePath: AnsiString): cint;

var
  PtyLastSlave: AnsiString = '';   {< slave path of the last TChnPortPty opened }

implementation

uses
  SysUtils, TermIO;

const
  TIOCSPTLCK = $40045431;   { _IOW('T', 0x31, int) }
  TIOCGPTN   = $80045430;   { _IOR('T', 0x30, unsigned int) }

function PtyUnlock(Fd: cint; out SlavePath: AnsiString): cint;
var
  Unlock: cint;
  N: cuint;
begin
  SlavePath := '';
  Unlock := 0;
  N := 0;
  if (FpIOCtl(Fd, TIOCSPTLCK, @Unlock) <> 0) or
     (FpIOCtl(Fd, TIOCGPTN, @N) <> 0) then
    Exit(FpGetErrno);
  SlavePath := '/dev/pts/' + IntToStr(N);
  Result := 0;
end;

function PtyCreate(out Fd: cint; out SlavePath: AnsiString): cint;
var
  T: Termios;
begin
  SlavePath := '';
  Fd := FpOpen('/dev/ptmx', O_RDWR or O_NOCTTY or O_NONBLOCK or OpenCloseOnExec);
  if Fd < 0 then
    Exit(FpGetErrno);
  Result := PtyUnlock(Fd, SlavePath);
  if Result <> 0 then
  begin
    FpClose(Fd);
    Fd := -1;
    Exit;
  end;
  if TCGetAttr(Fd, T) = 0 then
  begin
    CFMakeRaw(T);
    TCSetAttr(Fd, TCSANOW, T);
  end;
end;

function TChnPortPty.Open(const Path: tWordString): tChResult;
var
  Err: cint;
begin
  FSlavePath := '';
  { the termios backend opens and makes the master raw; no flock: it would
    lock the one /dev/ptmx inode and refuse every other pair on the system }
  FNoLock := True;
  Result := inherited Open('/dev/ptmx');
  if Result <> res_Ok then
    Exit;
  Err := PtyUnlock(OsHandle, FSlavePath);
  if Err <> 0 then
  begin
    FOSError := Err;
    Close;
    Exit(res_CannotOpen);
  end;
  PtyLastSlave := FSlavePath;
end;

function TChnPortPty.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  Result := inherited DoRead(Buf, Size, Got);
  FNoClient := (Result = res_DeviceLost) and (FOSError = ESysEIO);
  if FNoClient then
  begin
    FOSError := 0;
    Got := 0;
    Result := res_Ok;
  end;
end;

function TChnPortPty.WaitUseful: Boolean;
begin
  Result := not FNoClient;
end;

function TChnPortPty.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
begin
  Result := inherited DoWrite(Buf, Len, Done);
  if (Result = res_DeviceLost) and (FOSError = ESysEIO) then
  begin
    FOSError := 0;
    Done := Len;             { nobody listens: the bytes are gone }
    Result := res_Ok;
  end;
end;

function TChnPortPty.WaitInput(Ms: LongInt): Boolean;
var
  P: TPollFd;
begin
  if not IsOpen then
    Exit(False);
  P.fd := OsHandle;
  P.events := POLLIN;
  P.revents := 0;
  Result := (FpPoll(@P, 1, Ms) > 0) and (P.revents and (POLLIN or POLLERR) <> 0);
  if not Result and (P.revents and POLLHUP <> 0) and (Ms > 0) then
    Sleep(Ms);                 { hung up, nothing waiting: an idle line }
end;

initialization
  RegisterPortDriver(PtyDriver, TChnPortPty);
end.
