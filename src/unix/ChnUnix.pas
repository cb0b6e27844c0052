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

{ Mark Fd close-on-exec. }
procedure CloseOnExec(Fd: cint);

{ True when Fd (opened on Path) is a pseudo terminal, slave or master: a
  virtual line. }
function PortIsPty(Fd: cint; const Path: tWordString): Boolean;

{ The parameter key ('BIT', 'STOP', 'PAR', 'FLW', else 'BD') behind the
  c_cflag bits (within Mask) a driver changed from Want to Got. }
function PortCFlagKey(Got, Want, Mask: LongWord): ShortString;

implementation

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
