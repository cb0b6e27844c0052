{ ptyecho - the Linux end of the Wine serial test (tools/wintest.sh).

  Creates a pseudo-terminal pair (unit ChnPty), prints "PTY /dev/pts/N" on
  its first line and echoes every byte that arrives on the master side.
  tools/wintest.sh links a Wine COM port to the slave, so a Windows program
  (tests/wine/wincom.exe) reaches this echo through ChnPortWin.

  Two commands in the byte stream, echoed like all other bytes:
    ESC 'CHN!TERMIOS' ESC  then the line settings Wine gave the slave are
                           appended: 'speed=19200 bits=8 parity=N stop=1
                           rtscts=0 ixon=0' and LF (read with tcgetattr, and
                           TCGETS2 for a non-standard rate, on a descriptor
                           of our own on the slave)
    ESC 'CHN!COUNT' ESC    then 'count=N' and LF: the bytes that arrived
                           on the master since the start, this command
                           included (a close must not lose what was sent)
    ESC 'CHN!HANGUP' ESC   close the master (the COM port's device is gone
                           for the Windows side) and exit 0
  Exits 2 after --timeout=N seconds (default 60) without a hang-up.

  Linux only; not part of "make test". }
program ptyecho;

{$MODE OBJFPC}{$H+}

uses
  BaseUnix, TermIO, SysUtils, ChnPty;

const
  CmdTermios = #27'CHN!TERMIOS'#27;
  CmdHangup = #27'CHN!HANGUP'#27;
  CmdCount = #27'CHN!COUNT'#27;

var
  Received: Int64;            { bytes that arrived on the master }
  Master: cint;
  Slave: string;
  Tail: string;               { the last bytes seen, to find the commands }
  Pending: string;            { bytes still to be written back }
  TimeoutS: LongInt;

type
  { struct termios2 of <asm/termbits.h>: the rate itself for BOTHER }
  tTermios2 = record
    c_iflag, c_oflag, c_cflag, c_lflag: Cardinal;
    c_line: Byte;
    c_cc: array[0..18] of Byte;
    c_ispeed, c_ospeed: Cardinal;
  end;

const
  TCGETS2 = $802C542A;
  KBOTHER = $1000;

function SpeedOf(Fd: cint; T: Termios): LongInt;
const
  Codes: array[0..11] of LongInt = (B1200, B2400, B4800, B9600, B19200,
    B38400, B57600, B115200, B230400, B460800, B500000, B921600);
  Rates: array[0..11] of LongInt = (1200, 2400, 4800, 9600, 19200,
    38400, 57600, 115200, 230400, 460800, 500000, 921600);
var
  I: Integer;
  S: LongInt;
  T2: tTermios2;
begin
  S := T.c_cflag and CBAUD;
  if S = KBOTHER then
  begin
    FillChar(T2, SizeOf(T2), 0);
    if FpIOCtl(Fd, TCGETS2, @T2) = 0 then
      Exit(T2.c_ospeed);
  end;
  for I := 0 to High(Codes) do
    if Codes[I] = S then
      Exit(Rates[I]);
  Result := -S;               { a code this table lacks, as -code }
end;

{ The settings of the slave as Wine left them. }
function TermiosLine: string;
var
  Fd: cint;
  T: Termios;
  Bits: Integer;
  Par: Char;
  Speed: LongInt;
begin
  Fd := FpOpen(Slave, O_RDWR or O_NOCTTY or O_NONBLOCK);
  if Fd < 0 then
    Exit('error=' + IntToStr(FpGetErrno) + #10);
  FillChar(T, SizeOf(T), 0);
  if TCGetAttr(Fd, T) <> 0 then
  begin
    FpClose(Fd);
    Exit('error=tcgetattr' + #10);
  end;
  Speed := SpeedOf(Fd, T);
  FpClose(Fd);
  case T.c_cflag and CSIZE of
    CS5: Bits := 5;
    CS6: Bits := 6;
    CS7: Bits := 7;
  else
    Bits := 8;
  end;
  if T.c_cflag and PARENB = 0 then
    Par := 'N'
  else if T.c_cflag and PARODD <> 0 then
    Par := 'O'
  else
    Par := 'E';
  Result := Format('speed=%d bits=%d parity=%s stop=%d rtscts=%d ixon=%d'#10,
    [Speed, Bits, Par, 1 + Ord(T.c_cflag and CSTOPB <> 0),
     Ord(T.c_cflag and CRTSCTS <> 0), Ord(T.c_iflag and IXON <> 0)]);
end;

procedure Flush;
var
  N: TSsize;
begin
  while Pending <> '' do
  begin
    N := FpWrite(Master, Pending[1], Length(Pending));
    if N <= 0 then
      Exit;                   { full (EAGAIN) or nobody on the slave: later }
    Delete(Pending, 1, N);
  end;
end;

var
  Buf: array[0..4095] of Char;
  N: TSsize;
  I: Integer;
  P: TPollFd;
  Deadline: QWord;
  Err: cint;
begin
  TimeoutS := 60;
  for I := 1 to ParamCount do
    if Copy(ParamStr(I), 1, 10) = '--timeout=' then
      TimeoutS := StrToIntDef(Copy(ParamStr(I), 11, 9), 60);
  Err := PtyCreate(Master, Slave);
  if Err <> 0 then
  begin
    WriteLn('ptyecho: no pty (errno ', Err, ')');
    Halt(1);
  end;
  WriteLn('PTY ', Slave);
  System.Flush(Output);
  Tail := '';
  Pending := '';
  Received := 0;
  Deadline := GetTickCount64 + QWord(TimeoutS) * 1000;
  while GetTickCount64 < Deadline do
  begin
    P.fd := Master;
    P.events := POLLIN;
    if Pending <> '' then
      P.events := P.events or POLLOUT;
    P.revents := 0;
    FpPoll(@P, 1, 20);
    N := FpRead(Master, Buf, SizeOf(Buf));
    if N <= 0 then
    begin
      { EAGAIN: nothing; EIO: no program has the slave open (yet, again) }
      if (N < 0) and (FpGetErrno = ESysEIO) then
        Sleep(5);
      Flush;
      Continue;
    end;
    for I := 0 to N - 1 do
    begin
      Pending := Pending + Buf[I];
      Inc(Received);
      Tail := Copy(Tail + Buf[I], Length(Tail) + 2 - 16, 16);
      if Copy(Tail, Length(Tail) - Length(CmdTermios) + 1, 255) = CmdTermios then
        Pending := Pending + TermiosLine
      else if Copy(Tail, Length(Tail) - Length(CmdCount) + 1, 255) = CmdCount then
        Pending := Pending + 'count=' + IntToStr(Received) + #10
      else if Copy(Tail, Length(Tail) - Length(CmdHangup) + 1, 255) = CmdHangup then
      begin
        Flush;
        FpClose(Master);
        WriteLn('ptyecho: hung up');
        Halt(0);
      end;
    end;
    Flush;
  end;
  WriteLn('ptyecho: timeout');
  Halt(2);
end.
