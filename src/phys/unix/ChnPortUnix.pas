{ ChnPortUnix - TChnPort on termios, Free Pascal's own run-time library
  (units BaseUnix, Unix, TermIO). Registered as driver 'RTL' on Unix.

  The descriptor is opened O_NONBLOCK | O_NOCTTY and locked with flock, so
  a second user gets res_CannotOpen instead of a garbled line (TIOCEXCL is
  set as well; root ignores it, flock it does not). Raw mode with VMIN=1 and
  VTIME=0: then a non-blocking read answers EAGAIN when nothing waits, and 0
  only when the line is hung up (USB adapter pulled, pty master closed),
  which this unit reports as res_DeviceLost.

  Every setting is read back after tcsetattr: the kernel writes back what the
  driver really took (an 8250 falls back to 9600 for a rate it cannot make,
  a driver without CMSPAR clears it), and any difference is res_BadSetting
  with FailKey naming the setting. Rates outside the termios table use
  termios2/BOTHER on Linux; where the device refuses termios2 (TCGETS2
  fails, as under qemu-user 7.2) the standard rates still work through
  classic termios and any other is res_BadSetting with FailKey 'BD'. The
  table's codes above 230400 are this unit's own (the arm-linux RTL lacks
  them), for Linux's one termios ABI on x86, ARM, AArch64 and RISC-V.

  A pseudo terminal (slave /dev/pts/N, master /dev/ptmx, also reached
  through a symlink such as socat's link=) is a virtual line: it carries
  bytes only, and Linux keeps no rate, parity or framing there that could
  matter. Configure then takes every setting as given and leaves the pty
  raw, 8 bits, no flow control (XON/XOFF would eat bytes). Recognised by
  the device number, so a link to a pty is one too. }
unit ChnPortUnix;

{$I chn.inc}

interface

uses
  BaseUnix, Unix, TermIO, ChnTypes, ChnWait, ChnPort, ChnUnix;

type
  TChnPortUnix = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FFd: cint;
    FOverrunBase: LongWord;
    FNoCounters: Boolean;     {< the driver refused TIOCGICOUNT once: never ask again }
    function Fail(Err: cint): tChResult;
    function IoFailed(Err: cint): tChResult;
    function Counters(out N: LongWord): Boolean;
    function Refuse(const Key: ShortString): tChResult;
    function FailSet(Err: cint): tChResult;
    function SetStandardRate(var T: Termios; Code: LongWord): tChResult;
    function SetOtherRate(const T: Termios; Baud: LongInt): tChResult;
  protected
    { Open takes no flock: for /dev/ptmx (ChnPty), where every open is a
      new pair but a lock would hold the one inode for the whole system }
    FNoLock: Boolean;
  public
    constructor Create; override;
    function Open(const Path: tWordString): tChResult; override;
    function Configure(const S: tPortSettings): tChResult; override;
    function WaitInput(Ms: LongInt): Boolean; override;
    function WaitOutput(Ms: LongInt): Boolean; override;
    function OutQueue(out N: LongInt): tChResult; override;
    function Drain: tChResult; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    function SetRts(On: Boolean): tChResult; override;
    function SetDtr(On: Boolean): tChResult; override;
    function GetLines(out Lines: tPortLines): tChResult; override;
    function SetKernelRs485(On: Boolean): tChResult; override;
    function SetLatency(Ms: LongInt): tChResult; override;
    function OsOverruns(out N: LongWord): tChResult; override;
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    function ShortReadDrains: Boolean; override;
    function OsHandle: PtrInt; override;
    procedure Close; override;
  end;

implementation

{ Linux keeps one termios ABI (<asm-generic/termbits.h>) on x86, ARM,
  AArch64 and RISC-V: rate codes, termios2 and its ioctls below are
  written out for it, because the RTL of some targets lacks them (arm-linux
  stops at B460800). Other Linux CPUs (PowerPC, SPARC, MIPS, Alpha) have
  other values; there only the RTL's codes up to 230400 are used. }
{$IF DEFINED(LINUX) and (DEFINED(CPUX86_64) or DEFINED(CPUI386) or DEFINED(CPUARM) or
  DEFINED(CPUAARCH64) or DEFINED(CPURISCV64))}
  {$DEFINE CHN_TERMBITS}
{$ENDIF}

type
  tBaudCode = record
    Baud: LongInt;
    Code: Cardinal;
  end;

const
  BaudCodes: array[0..{$IFDEF CHN_TERMBITS}29{$ELSE}17{$ENDIF}] of tBaudCode = (
    (Baud: 50; Code: B50), (Baud: 75; Code: B75), (Baud: 110; Code: B110),
    (Baud: 134; Code: B134), (Baud: 150; Code: B150), (Baud: 200; Code: B200),
    (Baud: 300; Code: B300), (Baud: 600; Code: B600), (Baud: 1200; Code: B1200),
    (Baud: 1800; Code: B1800), (Baud: 2400; Code: B2400), (Baud: 4800; Code: B4800),
    (Baud: 9600; Code: B9600), (Baud: 19200; Code: B19200),
    (Baud: 38400; Code: B38400), (Baud: 57600; Code: B57600),
    (Baud: 115200; Code: B115200), (Baud: 230400; Code: B230400)
    {$IFDEF CHN_TERMBITS}
    { B460800 .. B4000000 of <asm-generic/termbits.h> }
    , (Baud: 460800; Code: $1004), (Baud: 500000; Code: $1005),
    (Baud: 576000; Code: $1006), (Baud: 921600; Code: $1007),
    (Baud: 1000000; Code: $1008), (Baud: 1152000; Code: $1009),
    (Baud: 1500000; Code: $100A), (Baud: 2000000; Code: $100B),
    (Baud: 2500000; Code: $100C), (Baud: 3000000; Code: $100D),
    (Baud: 3500000; Code: $100E), (Baud: 4000000; Code: $100F)
    {$ENDIF}
    );

{$IFDEF LINUX}
type
  { struct serial_rs485 of <linux/serial.h> }
  tSerialRs485 = record
    Flags, DelayRtsBeforeSend, DelayRtsAfterSend: Cardinal;
    Padding: array[0..4] of Cardinal;
  end;
  { struct serial_icounter_struct of <linux/serial.h> }
  tSerialICounter = record
    Cts, Dsr, Rng, Dcd, Rx, Tx, Frame, Overrun, Parity, Brk, BufOverrun: cint;
    Reserved: array[0..8] of cint;
  end;

const
  TIOCSRS485 = $542F;
  SER_RS485_ENABLED = 1;
  SER_RS485_RTS_ON_SEND = 2;  { RTS high while sending, low afterwards }
  { bits of c_cflag this unit sets and reads back, besides the rate }
  FramingCFlags = CSIZE or CSTOPB or PARENB or PARODD or CMSPAR or CRTSCTS;
{$ELSE}
const
  FramingCFlags = CSIZE or CSTOPB or PARENB or PARODD or CRTSCTS;
{$ENDIF}
  CheckedCFlags = CBAUD or FramingCFlags;
  { masks as "all bits but": xor keeps them within 32 bits, where "not"
    of an untyped constant is a 64-bit value (a range-check warning, fatal
    under -Sew, on targets whose tcflag_t constants are 32 bits) }
  AllCFlags = $FFFFFFFF;

constructor TChnPortUnix.Create;
begin
  inherited Create;
  FFd := -1;
  FOverrunBase := 0;
end;

{ Map errno to a result code, remember it, and say which. }
function TChnPortUnix.Fail(Err: cint): tChResult;
begin
  FOSError := Err;
  case Err of
    ESysEACCES, ESysEPERM:
      Result := res_NoPermission;
    ESysENOENT, ESysENODEV, ESysENXIO, ESysEBUSY, ESysEISDIR, ESysENOTDIR,
    ESysELOOP, ESysENAMETOOLONG, ESysEROFS:
      if FOpen then
        Result := res_DeviceLost
      else
        Result := res_CannotOpen;
    ESysEIO, ESysEBADF, ESysEPIPE:
      Result := res_DeviceLost;
    { ENOSYS: qemu-user's answer to an ioctl it does not emulate
      (TIOCSRS485, TCGETS2): as a driver's ENOTTY, a setting refused }
    ESysENOTTY, ESysEINVAL, ESysEOPNOTSUPP, ESysENOSYS:
      Result := res_BadSetting;
  else
    Result := res_IOError;
  end;
end;

function TChnPortUnix.Refuse(const Key: ShortString): tChResult;
begin
  FailKey := Key;
  Result := res_BadSetting;
end;

{ tcsetattr failed: EINVAL there is the rate (the tty layer takes every
  other flag and the driver adjusts it, which the read-back catches). }
function TChnPortUnix.FailSet(Err: cint): tChResult;
begin
  Result := Fail(Err);
  if Result = res_BadSetting then
    FailKey := 'BD';
end;

function TChnPortUnix.Open(const Path: tWordString): tChResult;
var
  NewFd: cint;
  T: Termios;
begin
  if FOpen then
    Exit(res_WrongState);
  FOSError := 0;
  FailKey := '';
  FVirtual := False;
  FDevice := Path;
  { close-on-exec: a program this one starts must not hold the line (a
    pty it kept open would never hang up for the other side) }
  NewFd := FpOpen(Path, O_RDWR or O_NOCTTY or O_NONBLOCK or OpenCloseOnExec);
  if NewFd < 0 then
    Exit(Fail(FpGetErrno));
  { flock: one user per device, honoured by root too }
  if not FNoLock and (FpFlock(NewFd, LOCK_EX or LOCK_NB) <> 0) then
  begin
    FOSError := FpGetErrno;
    FpClose(NewFd);
    Exit(res_CannotOpen);
  end;
  { not a terminal (a regular file, /dev/null ...): it takes no settings }
  if TCGetAttr(NewFd, T) <> 0 then
  begin
    Result := Fail(FpGetErrno);
    FpClose(NewFd);
    Exit;
  end;
  FpIOCtl(NewFd, TIOCEXCL, nil);   { best effort: keeps other non-root users out }
  FVirtual := PortIsPty(NewFd, Path);
  { raw at once, rate and framing as found; Configure sets them }
  CFMakeRaw(T);
  T.c_iflag := T.c_iflag and not (IXON or IXOFF or IXANY);
  T.c_cflag := T.c_cflag or CREAD or CLOCAL;
  T.c_cc[VMIN] := 1;           { with O_NONBLOCK: EAGAIN when empty, 0 = hangup }
  T.c_cc[VTIME] := 0;
  if TCSetAttr(NewFd, TCSANOW, T) <> 0 then
  begin
    Result := Fail(FpGetErrno);
    FpClose(NewFd);
    Exit;
  end;
  FFd := NewFd;
  FOpen := True;
  FNoCounters := False;
  { a pty or a USB adapter without counters refuses this: remembered, so
    polls do not repeat an ioctl that cannot succeed }
  FNoCounters := not Counters(FOverrunBase);
  Result := res_Ok;
end;

{ The c_cflag bits of S's character (data and stop bits) into Flags, and
  the ranges of the other settings; '' or the key of the one refused
  (BIT, STOP, BD, PAR, FLW). }
function CharFlags(const S: tPortSettings; out Flags: Cardinal): ShortString;
begin
  Result := '';
  Flags := CREAD or CLOCAL;
  case S.DataBits of
    5: Flags := Flags or CS5;
    6: Flags := Flags or CS6;
    7: Flags := Flags or CS7;
    8: Flags := Flags or CS8;
  else
    Exit('BIT');
  end;
  case S.StopBits of
    1: ;
    2: Flags := Flags or CSTOPB;
  else
    Exit('STOP');
  end;
  if S.Baud <= 0 then
    Exit('BD');
  if Ord(S.Parity) > Ord(High(tPortParity)) then
    Exit('PAR');
  if Ord(S.Flow) > Ord(High(tPortFlow)) then
    Exit('FLW');
end;

{ Parity into Flags, flow control into Flags or T's input flags; '' or
  PAR (mark and space parity: Linux only). }
function ParityFlowFlags(const S: tPortSettings; var Flags: Cardinal; var T: Termios): ShortString;
begin
  Result := '';
  case S.Parity of
    ppNone: ;
    ppEven: Flags := Flags or PARENB;
    ppOdd: Flags := Flags or PARENB or PARODD;
    {$IFDEF LINUX}
    ppMark: Flags := Flags or PARENB or PARODD or CMSPAR;
    ppSpace: Flags := Flags or PARENB or CMSPAR;
    {$ELSE}
    ppMark, ppSpace: Exit('PAR');
    {$ENDIF}
  end;
  case S.Flow of
    flowNone: ;
    flowRtsCts: Flags := Flags or CRTSCTS;
    flowXonXoff: T.c_iflag := T.c_iflag or IXON or IXOFF;
  end;
end;

{ T with a standard rate (its B constant Code), read back: a setting the
  device did not take is refused by its key, with no fallback. }
function TChnPortUnix.SetStandardRate(var T: Termios; Code: LongWord): tChResult;
var
  Back: Termios;
begin
  CFSetISpeed(T, Code);
  CFSetOSpeed(T, Code);
  if TCSetAttr(FFd, TCSANOW, T) <> 0 then
    Exit(FailSet(FpGetErrno));
  if TCGetAttr(FFd, Back) <> 0 then
    Exit(Fail(FpGetErrno));
  if (Back.c_cflag and CheckedCFlags) <> (T.c_cflag and CheckedCFlags) then
    Exit(Refuse(PortCFlagKey(Back.c_cflag, T.c_cflag, CheckedCFlags)));   { no fallback }
  Result := res_Ok;
end;

{ T with a rate without a B constant: termios2 with BOTHER. A device (or
  an emulator: qemu-user 7.2 does not know TCGETS2) that refuses termios2
  can only take the standard rates: this one is refused, BD= named. }
function TChnPortUnix.SetOtherRate(const T: Termios; Baud: LongInt): tChResult;
{$IFDEF CHN_TERMBITS}
var
  T2: tTermios2;
begin
  FillChar(T2, SizeOf(T2), 0);
  if FpIOCtl(FFd, TCGETS2, @T2) <> 0 then
  begin
    FOSError := FpGetErrno;
    Exit(Refuse('BD'));
  end;
  T2.c_iflag := T.c_iflag;
  T2.c_oflag := T.c_oflag;
  T2.c_lflag := T.c_lflag;
  T2.c_cflag := (T.c_cflag and (AllCFlags xor CBAUD)) or BOTHER;
  Move(T.c_cc, T2.c_cc, SizeOf(T2.c_cc));
  T2.c_ispeed := Baud;
  T2.c_ospeed := Baud;
  if FpIOCtl(FFd, TCSETS2, @T2) <> 0 then
    Exit(FailSet(FpGetErrno));
  FillChar(T2, SizeOf(T2), 0);
  if FpIOCtl(FFd, TCGETS2, @T2) <> 0 then
    Exit(Fail(FpGetErrno));
  { the kernel writes back the rate it set; allow 2 % as UARTs do }
  if Abs(Int64(T2.c_ospeed) - Baud) * 50 > Baud then
    Exit(Refuse('BD'));
  if (T2.c_cflag and FramingCFlags) <> (T.c_cflag and FramingCFlags) then
    Exit(Refuse(PortCFlagKey(T2.c_cflag, T.c_cflag, CheckedCFlags)));
  Result := res_Ok;
end;
{$ELSE}
begin
  Result := Refuse('BD');
end;
{$ENDIF}

function TChnPortUnix.Configure(const S: tPortSettings): tChResult;
var
  T: Termios;
  Flags, Code: Cardinal;
  Key: ShortString;
  I: Integer;
begin
  if not FOpen then
    Exit(res_WrongState);
  FailKey := '';
  if TCGetAttr(FFd, T) <> 0 then
    Exit(Fail(FpGetErrno));
  CFMakeRaw(T);
  T.c_iflag := T.c_iflag and not (IXON or IXOFF or IXANY or INPCK or IGNPAR);
  T.c_cc[VMIN] := 1;
  T.c_cc[VTIME] := 0;
  Key := CharFlags(S, Flags);
  if Key <> '' then
    Exit(Refuse(Key));
  if FVirtual then
  begin
    { bytes only: raw, 8 bits, no parity, no flow control; nothing to check }
    T.c_cflag := (T.c_cflag and (AllCFlags xor (FramingCFlags or HUPCL))) or
      CS8 or CREAD or CLOCAL;
    if TCSetAttr(FFd, TCSANOW, T) <> 0 then
      Exit(Fail(FpGetErrno));
    Exit(res_Ok);
  end;
  Key := ParityFlowFlags(S, Flags, T);
  if Key <> '' then
    Exit(Refuse(Key));
  Code := 0;
  for I := Low(BaudCodes) to High(BaudCodes) do
    if BaudCodes[I].Baud = S.Baud then
      Code := BaudCodes[I].Code;
  T.c_cflag := (T.c_cflag and (AllCFlags xor (CheckedCFlags or CREAD or CLOCAL or HUPCL))) or Flags;
  if Code <> 0 then
    Result := SetStandardRate(T, Code)
  else
    Result := SetOtherRate(T, S.Baud);
end;

{ A read or write of the non-blocking descriptor that failed with Err:
  EAGAIN only says nothing can move now. }
function TChnPortUnix.IoFailed(Err: cint): tChResult;
begin
  if (Err = ESysEAGAIN) or (Err = ESysEWOULDBLOCK) then
    Result := res_Ok
  else
    Result := Fail(Err);
end;

function TChnPortUnix.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  N: TSsize;
  E: cint;
begin
  repeat
    N := FpRead(FFd, Buf, Size);
    E := FpGetErrno;
  until (N >= 0) or (E <> ESysEINTR);
  if N > 0 then
  begin
    Got := N;
    Result := res_Ok;
  end
  else if N = 0 then
  begin
    FOSError := ESysEIO;      { end of file on a tty: the line was hung up }
    Result := res_DeviceLost;
  end
  else
    Result := IoFailed(E);
end;

function PollFd(Fd: cint; Events: cshort; Ms: LongInt): Boolean;
var
  P: TPollFd;
  R: cint;
begin
  P.fd := Fd;
  P.events := Events;
  P.revents := 0;
  R := FpPoll(@P, 1, Ms);
  Result := (R > 0) and (P.revents <> 0);
end;

function TChnPortUnix.WaitInput(Ms: LongInt): Boolean;
begin
  if not FOpen then
    Exit(False);
  Result := PollFd(FFd, POLLIN, Ms);
end;

function TChnPortUnix.WaitOutput(Ms: LongInt): Boolean;
begin
  if not FOpen then
    Exit(False);
  Result := PollFd(FFd, POLLOUT, Ms);
end;

function TChnPortUnix.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  N: TSsize;
  E: cint;
begin
  repeat
    N := FpWrite(FFd, Buf, Len);
    E := FpGetErrno;
  until (N >= 0) or (E <> ESysEINTR);
  if N >= 0 then
  begin
    Done := N;
    Result := res_Ok;
  end
  else
    Result := IoFailed(E);
end;

function TChnPortUnix.OutQueue(out N: LongInt): tChResult;
var
  Q: cint;
begin
  N := 0;
  if not FOpen then
    Exit(res_WrongState);
  Q := 0;
  if FpIOCtl(FFd, TIOCOUTQ, @Q) <> 0 then
    Exit(Fail(FpGetErrno));
  N := Q;
  Result := res_Ok;
end;

function TChnPortUnix.Drain: tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if TCDrain(FFd) <> 0 then
    Exit(Fail(FpGetErrno));
  Result := res_Ok;
end;

function TChnPortUnix.Flush(Input, Output: Boolean): tChResult;
var
  Q: cint;
begin
  if not FOpen then
    Exit(res_WrongState);
  if Input and Output then
    Q := TCIOFLUSH
  else if Input then
    Q := TCIFLUSH
  else if Output then
    Q := TCOFLUSH
  else
    Exit(res_Ok);
  if TCFlush(FFd, Q) <> 0 then
    Exit(Fail(FpGetErrno));
  Result := res_Ok;
end;

function ModemBit(Fd: cint; Bit: cint; On: Boolean): cint;
begin
  if On then
    Result := FpIOCtl(Fd, TIOCMBIS, @Bit)
  else
    Result := FpIOCtl(Fd, TIOCMBIC, @Bit);
end;

function TChnPortUnix.SetRts(On: Boolean): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if ModemBit(FFd, TIOCM_RTS, On) <> 0 then
    Exit(Fail(FpGetErrno));     { a pty has no modem lines: res_BadSetting }
  Result := res_Ok;
end;

function TChnPortUnix.SetDtr(On: Boolean): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if ModemBit(FFd, TIOCM_DTR, On) <> 0 then
    Exit(Fail(FpGetErrno));
  Result := res_Ok;
end;

function TChnPortUnix.GetLines(out Lines: tPortLines): tChResult;
var
  Bits: cint;
begin
  Lines := [];
  if not FOpen then
    Exit(res_WrongState);
  Bits := 0;
  if FpIOCtl(FFd, TIOCMGET, @Bits) <> 0 then
    Exit(Fail(FpGetErrno));
  if Bits and TIOCM_CTS <> 0 then
    Include(Lines, plCts);
  if Bits and TIOCM_DSR <> 0 then
    Include(Lines, plDsr);
  if Bits and TIOCM_RNG <> 0 then
    Include(Lines, plRing);
  if Bits and TIOCM_CAR <> 0 then
    Include(Lines, plCarrier);
  Result := res_Ok;
end;

function TChnPortUnix.SetKernelRs485(On: Boolean): tChResult;
{$IFDEF LINUX}
var
  R: tSerialRs485;
begin
  if not FOpen then
    Exit(res_WrongState);
  FillChar(R, SizeOf(R), 0);
  if On then
  begin
    R.Flags := SER_RS485_ENABLED or SER_RS485_RTS_ON_SEND;
    R.DelayRtsBeforeSend := Rs485BeforeMs;
    R.DelayRtsAfterSend := Rs485AfterMs;
  end;
  if FpIOCtl(FFd, TIOCSRS485, @R) <> 0 then
  begin
    Result := Fail(FpGetErrno);
    if Result = res_BadSetting then
      FOSError := ESysENOTTY;
    if not On and (Result = res_BadSetting) then
      Result := res_Ok;        { nothing to switch off }
    Exit;
  end;
  Result := res_Ok;
end;
{$ELSE}
begin
  if not FOpen then
    Exit(res_WrongState);
  if On then
    Result := res_BadSetting
  else
    Result := res_Ok;
end;
{$ENDIF}

function TChnPortUnix.SetLatency(Ms: LongInt): tChResult;
var
  E: cint;
begin
  if not FOpen then
    Exit(res_WrongState);
  Result := PortSetLatency(FDevice, Ms, E);
  if Result <> res_Ok then
    FOSError := E;
end;

{ OS count of lost received bytes (UART overrun + tty buffer overrun). }
function TChnPortUnix.Counters(out N: LongWord): Boolean;
{$IFDEF LINUX}
var
  C: tSerialICounter;
begin
  N := 0;
  FillChar(C, SizeOf(C), 0);
  Result := FpIOCtl(FFd, TIOCGICOUNT, @C) = 0;   { a pty does not count }
  if Result then
    N := LongWord(C.Overrun) + LongWord(C.BufOverrun);
end;
{$ELSE}
begin
  N := 0;
  Result := False;
end;
{$ENDIF}

function TChnPortUnix.OsOverruns(out N: LongWord): tChResult;
begin
  N := 0;
  if not FOpen then
    Exit(res_WrongState);
  if not FNoCounters then
    if Counters(N) then
      N := N - FOverrunBase
    else
      FNoCounters := True;
  Result := res_Ok;
end;

function TChnPortUnix.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  Kind := wkDescriptor;
  Os := FFd;
  Rearm := nil;
  Data := nil;
  Result := FOpen;
end;

{ read(2) on a tty copies all its line buffer holds, up to the size asked }
function TChnPortUnix.ShortReadDrains: Boolean;
begin
  Result := True;
end;

function TChnPortUnix.OsHandle: PtrInt;
begin
  Result := FFd;
end;

procedure TChnPortUnix.Close;
begin
  if FFd >= 0 then
  begin
    { a pty slave's tty outlives this descriptor while its master is open,
      and so would TIOCEXCL: every later open by a non-root user would get
      EBUSY. Clear it; closing the descriptor releases the flock. }
    FpIOCtl(FFd, TIOCNXCL, nil);
    FpClose(FFd);
  end;
  FFd := -1;
  FOpen := False;
end;

initialization
  RegisterPortDriver('RTL', TChnPortUnix);
end.
