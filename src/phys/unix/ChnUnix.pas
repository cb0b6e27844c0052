{ ChnUnix - what the Unix parts of the library share: close-on-exec for
  every descriptor it opens, and the termios questions both serial
  backends ask (ChnPortUnix on the RTL, ChnPortSynapse on synaser), so no
  backend borrows from another. }
unit ChnUnix;

{$I chn.inc}

interface

uses
  BaseUnix, TermIO, ChnTypes;

const
  { open(2) flag O_CLOEXEC, which the RTL does not name: descriptors of
    the library stay out of programs this one starts (a pty a child kept
    open would never hang up for the other side) }
  OpenCloseOnExec = {$IFDEF LINUX}$80000{$ELSE}0{$ENDIF};
  { fcntl(F_SETFD) flag of the same meaning, for descriptors made by
    calls without an O_CLOEXEC (pipe, socket, epoll_create) }
  FD_CLOEXEC = 1;

{$IFDEF LINUX}
type
  { struct termios2 of <asm-generic/termbits.h>: any rate, in
    c_ispeed/c_ospeed with BOTHER (ChnPortUnix sets it, tests read it) }
  tTermios2 = record
    c_iflag, c_oflag, c_cflag, c_lflag: LongWord;
    c_line: Byte;
    c_cc: array[0..18] of Byte;
    c_ispeed, c_ospeed: LongWord;
  end;

const
  TCGETS2 = $802C542A;        {< _IOR('T', 0x2A, struct termios2) }
  TCSETS2 = $402C542B;        {< _IOW('T', 0x2B, struct termios2) }
  BOTHER = $1000;             {< c_cflag speed code: rate in c_ispeed/c_ospeed }
{$ENDIF}

{ Mark Fd close-on-exec. }
procedure CloseOnExec(Fd: cint);

{ The C library's words for errno E ('Inappropriate ioctl for device'),
  as the system's own tools print them (the RTL's table has older ones:
  'Not a typewriter'). }
function OsErrorText(E: cint): ShortString;

{ True when Fd (opened on Path) is a pseudo terminal, slave or master: a
  virtual line. }
function PortIsPty(Fd: cint; const Path: tWordString): Boolean;

{ The parameter key ('BIT', 'STOP', 'PAR', 'FLW', else 'BD') behind the
  c_cflag bits (within Mask) a driver changed from Want to Got. }
function PortCFlagKey(Got, Want, Mask: LongWord): ShortString;

{ Linux: set the latency timer of the USB serial adapter behind Path (a
  device or a symlink to one, /dev/serial/by-id/...) to Ms and read it
  back: /sys/class/tty/<name>/device/latency_timer, as ftdi_sio and a few
  other usb-serial drivers offer it. res_BadSetting (Err = ENOENT) when the
  driver has no such timer (a pty, a UART, CDC-ACM), res_NoPermission when
  it may not be written (root, or a udev rule, may), res_BadSetting when
  the value read back differs. Elsewhere res_BadSetting. }
function PortSetLatency(const Path: tWordString; Ms: LongInt; out Err: cint): tChResult;

var
  { the sysfs class folder of ttys (a test points it at a folder of its own) }
  PortSysfsTty: ShortString = '/sys/class/tty/';

implementation

uses
  SysUtils;

function strerror(E: cint): PChar; cdecl; external 'c' name 'strerror';

function OsErrorText(E: cint): ShortString;
var
  P: PChar;
begin
  P := strerror(E);
  if P = nil then
    Result := 'error ' + IntToStr(E)
  else
    Result := StrPas(P);
end;

function PortSetLatency(const Path: tWordString; Ms: LongInt; out Err: cint): tChResult;
{$IFDEF LINUX}
var
  Dev, Name, F, Back: string;
  H: THandle;
  Buf: array[0..15] of Char;
  N: LongInt;
begin
  Err := 0;
  { the tty's own name: /dev/ttyUSB0 behind any symlink }
  Dev := ExpandFileName(Path);
  N := 0;
  while (N < 16) and (FpReadLink(Dev) <> '') do
  begin
    F := FpReadLink(Dev);
    if (F <> '') and (F[1] <> '/') then
      F := ExtractFilePath(Dev) + F;
    Dev := ExpandFileName(F);
    Inc(N);
  end;
  Name := ExtractFileName(Dev);
  F := PortSysfsTty + Name + '/device/latency_timer';
  H := FileOpen(F, fmOpenReadWrite);
  if H = THandle(-1) then
  begin
    Err := FpGetErrno;
    if (Err = ESysEACCES) or (Err = ESysEPERM) then
      Exit(res_NoPermission);
    Exit(res_BadSetting);
  end;
  Back := IntToStr(Ms) + #10;
  N := FileWrite(H, Back[1], Length(Back));
  if N <> Length(Back) then
  begin
    Err := FpGetErrno;
    FileClose(H);
    Exit(res_BadSetting);
  end;
  FileSeek(H, 0, fsFromBeginning);
  N := FileRead(H, Buf, SizeOf(Buf));
  FileClose(H);
  if N <= 0 then
    Exit(res_BadSetting);
  SetString(Back, PChar(@Buf[0]), N);
  if StrToIntDef(Trim(Back), -1) <> Ms then
    Exit(res_BadSetting);
  Result := res_Ok;
end;
{$ELSE}
begin
  Err := ESysENOENT;
  Result := res_BadSetting;
end;
{$ENDIF}

procedure CloseOnExec(Fd: cint);
begin
  FpFcntl(Fd, F_SETFD, FpFcntl(Fd, F_GETFD) or FD_CLOEXEC);
end;

function PortCFlagKey(Got, Want, Mask: LongWord): ShortString;
var
  Diff: LongWord;
begin
  Diff := (Got xor Want) and Mask;
  if Diff and CSIZE <> 0 then
    Result := 'BIT'
  else if Diff and CSTOPB <> 0 then
    Result := 'STOP'
  else if Diff and (PARENB or PARODD {$IFDEF LINUX}or CMSPAR{$ENDIF}) <> 0 then
    Result := 'PAR'
  else if Diff and CRTSCTS <> 0 then
    Result := 'FLW'
  else
    Result := 'BD';
end;

{ A pseudo terminal, slave or master, by device number on Linux (Unix98
  slaves: majors 136..143, /dev/ptmx: 5,2; BSD-style ptys: 2 and 3), by
  path elsewhere. A symlink (socat link=) was resolved by open. }
function PortIsPty(Fd: cint; const Path: tWordString): Boolean;
{$IFDEF LINUX}
var
  St: Stat;
  Major, Minor: QWord;
begin
  Result := False;
  if FpFStat(Fd, St) <> 0 then
    Exit;
  if not FpS_ISCHR(St.st_mode) then
    Exit;
  Major := ((St.st_rdev shr 8) and $FFF) or ((St.st_rdev shr 32) and not QWord($FFF));
  Minor := (St.st_rdev and $FF) or ((St.st_rdev shr 12) and not QWord($FF));
  Result := ((Major >= 136) and (Major <= 143)) or ((Major = 5) and (Minor = 2)) or
    (Major = 2) or (Major = 3);
end;
{$ELSE}
begin
  Result := (Copy(Path, 1, 9) = '/dev/pts/') or (Path = '/dev/ptmx') or
    (Copy(Path, 1, 8) = '/dev/pty') or (Copy(Path, 1, 8) = '/dev/tty') and
    (Length(Path) = 10) and (Path[9] in ['p'..'z']);
end;
{$ENDIF}

end.
