{ ChnPort - the small serial-port interface under the physical layers (tChnPhys) (docs/PROTOCOLS.md section 3).

  One abstract class, TChnPort, in the spirit of Synapse's TBlockSerial: open
  a device, configure it, move bytes without blocking, wait for input for a
  bounded time, control the modem lines, close. Every operation answers with
  a tChResult of ChnTypes, never with an exception, so the channel layer can
  pass it on unchanged. OS code lives only in the backends:

    unix/ChnPortUnix  termios (Free Pascal RTL), driver name 'RTL' on Unix
    unix/ChnPty       a new pseudo-terminal pair,  driver name 'PTY'
    win/ChnPortWin    Windows API,                 driver name 'RTL' on Windows
    ChnPortSynapse    Synapse's synaser,           driver name 'SYNAPSE'
                      (built only with -dCHN_SYNAPSE, see docs/ChnCom.md)
    ChnPortTcp        a TCP connection (NAM=TCP), ChnLoop the in-memory
                      null modem (NAM=LOOP): chosen by their layers

  Backends register a class under a driver name in their initialization;
  unit ChnPorts links those of the build, so tChnCom picks one with its
  DRV= parameter. Tests register their own fake backends the same way.

  Result codes used by every backend:
    res_CannotOpen    device missing, in use, or not a device at all
    res_NoPermission  the OS denied access
    res_BadSetting    the device refuses a setting (rate, parity, RS-485 ...);
                      FailKey then names the parameter key at fault
    res_DeviceLost    the device went away (USB adapter pulled, pty closed)
    res_IOError       any other failure of a read, write or control call
    res_WrongState    call on a port that is not open }
unit ChnPort;

{$I chn.inc}

interface

uses
  ChnTypes, ChnWait;

type
  tPortParity = (ppNone, ppEven, ppOdd, ppMark, ppSpace);
  tPortFlow = (flowNone, flowRtsCts, flowXonXoff);

  tPortSettings = record
    Baud    : LongInt;      {< bits per second }
    DataBits: Byte;         {< 5..8 }
    StopBits: Byte;         {< 1 or 2 }
    Parity  : tPortParity;
    Flow    : tPortFlow;
    InQueue : LongInt;      {< receive buffer size the OS should use, a hint }
  end;

  { Modem lines, for GetLines }
  tPortLine = (plCts, plDsr, plRing, plCarrier);
  tPortLines = set of tPortLine;

  TChnPortClass = class of TChnPort;

  { The serial-port interface. A driver implements Open, DoRead, DoWrite,
    WaitInput and Close (calling inherited Close); Read and Write are not
    virtual: their checks hold for every driver. Every other method has
    a default for a device without that capability (below), so a driver
    overrides only what its device does. All return at once unless the
    text says otherwise. }
  TChnPort = class
  protected
    FDevice: ShortString;
    FOpen: Boolean;
    FOSError: LongInt;   {< OS error code of the last failure, 0 if none }
    FVirtual: Boolean;   {< no physical line behind the device (a pty) }
    { Read and Write of the driver, called by Read and Write once the
      port is open and there is something to move (Size, Len > 0). }
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; virtual; abstract;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; virtual; abstract;
  public
    { After a failed Open or Configure: the parameter key at fault ('BD',
      'BIT', 'STOP', 'PAR', 'FLW', 'RS485', or '' for the device itself),
      so the layer can name the token in ChParamError. }
    FailKey: ShortString;
    { Delays SetKernelRs485(True) gives the driver (Linux serial_rs485
      delay_rts_before_send / delay_rts_after_send, ms); set them first.
      Windows' RTS_CONTROL_TOGGLE has none. }
    Rs485BeforeMs, Rs485AfterMs: LongInt;
    constructor Create; virtual;
    destructor Destroy; override;
    { Open Path ('/dev/ttyUSB0', '\\.\COM3') for exclusive use, raw and
      non-blocking. Rate and framing stay as the OS had them: call
      Configure next. }
    function Open(const Path: tWordString): tChResult; virtual; abstract;
    { Apply every setting; a value the device cannot take exactly (a baud
      rate the OS or the chip lacks, mark parity without support) gives
      res_BadSetting and no silent fallback. Default: res_Ok (a device
      with no line settings: only bytes cross it). }
    function Configure(const S: tPortSettings): tChResult; virtual;
    { Copy up to Size waiting bytes into Buf, never wait. Got = 0 with
      res_Ok means nothing is waiting; res_WrongState while not open. The
      checks are here, the reading is the driver's DoRead. }
    function Read(var Buf; Size: LongInt; out Got: LongInt): tChResult; inline;
    { Wait at most Ms milliseconds for input; True as soon as a byte (or a
      fault, which the next Read reports) is waiting. Ms = 0 only looks. }
    function WaitInput(Ms: LongInt): Boolean; virtual; abstract;
    { Wait at most Ms milliseconds until Write could accept bytes. Default:
      True at once (no buffer the OS could fill). }
    function WaitOutput(Ms: LongInt): Boolean; virtual;
    { Hand up to Len bytes to the OS, never wait: Done tells how many were
      taken (possibly 0 when the OS buffer is full); res_WrongState while
      not open. The checks are here, the writing is the driver's DoWrite. }
    function Write(const Buf; Len: LongInt; out Done: LongInt): tChResult; inline;
    { Bytes handed to the OS but not yet on the line; 0 where unknown (the
      default). }
    function OutQueue(out N: LongInt): tChResult; virtual;
    { Wait until the last bit has left the transmitter (tcdrain). Blocks for
      as long as the OS still holds bytes: call it when OutQueue is 0.
      Default: res_Ok at once (nothing is held). }
    function Drain: tChResult; virtual;
    { Discard received and/or not yet sent bytes held by the OS. Default:
      res_Ok (the OS holds none). }
    function Flush(Input, Output: Boolean): tChResult; virtual;
    { Modem lines. Default: res_BadSetting, a line without them (raw TCP,
      an in-memory line); GetLines then answers []. }
    function SetRts(On: Boolean): tChResult; virtual;
    function SetDtr(On: Boolean): tChResult; virtual;
    function GetLines(out Lines: tPortLines): tChResult; virtual;
    { Let the driver switch RTS around each transmission (Linux TIOCSRS485,
      Windows RTS_CONTROL_TOGGLE). res_BadSetting where not supported (the
      default). }
    function SetKernelRs485(On: Boolean): tChResult; virtual;
    { The receive latency timer of a USB serial adapter, 1..255 ms (Linux:
      the driver's latency_timer in sysfs, FTDI's default is 16 ms).
      res_BadSetting where the driver has none (the default), with OSError
      saying why; res_NoPermission where it may not be written. }
    function SetLatency(Ms: LongInt): tChResult; virtual;
    { Receive overruns the OS counted since Open (UART or driver buffer);
      0 where the OS does not count them (the default). }
    function OsOverruns(out N: LongWord): tChResult; virtual;
    { What the program-wide wait (unit ChnWait) can wait on for input of
      this port: a descriptor or an event handle, and for a handle the
      procedure that arms it again after it fired; or wkSignal for a
      device that signals its input itself (WaitJoined). False: nothing;
      tChnPhys then waits with WaitInput on this port alone. The default
      is False. }
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; virtual;
    { The source tChnPhys made of WaitSource in the program-wide wait, or
      nil before it leaves it: a wkSignal port calls ChnWaitSignal on it
      when input arrives. Default: ignored. }
    procedure WaitJoined(Src: pChnWaitSource); virtual;
    { False while waiting on WaitSource's object would only wake at once
      for nothing (a pty master with no program on the slave side answers
      poll with a hang-up every time); default True. }
    function WaitUseful: Boolean; virtual;
    { True when a Read that returns less than asked took everything the
      OS held at that moment (a tty's line buffer, a plain socket), so a
      caller the shared wait watches need not read again to find EAGAIN.
      False (the default) for a port that buffers or decodes internally. }
    function ShortReadDrains: Boolean; virtual;
    { Duties on a timer that must not wait for input (a server closing a
      client silent for too long): called at every receive poll, which the
      program-wide wait does not turn into a Read while nothing arrives.
      Default: nothing. }
    procedure PollTimers; virtual;
    { True while the driver keeps input aside that its next Read returns
      but the OS no longer shows (so the wait would not end for it):
      tChnPhys then reads without waiting. The driver reports such input to
      the program-wide wait itself (ChnWaitHeld), so ChnWaitAny ends at
      once. Default False. }
    function HoldsInput: Boolean; virtual;
    { The OS handle (file descriptor, HANDLE), for tests and special calls;
      -1 when closed or when there is none (the default). }
    function OsHandle: PtrInt; virtual;
    { Close; safe to call when not open. A driver releases its device and
      calls inherited (which marks the port closed). }
    procedure Close; virtual;

    property Device: ShortString read FDevice;
    property IsOpen: Boolean read FOpen;
    property OSError: LongInt read FOSError;
    { The OS's own words for OSError ('No such file or directory', 'Is a
      directory', 'Inappropriate ioctl for device'; Windows' text for its
      code), '' when OSError is 0. A backend with codes of its own
      (Synapse) translates those. }
    function OSErrorText: ShortString; virtual;
    { A virtual line (a Linux pty slave or master, a socat link to one)
      carries bytes only: Configure takes BD BIT STOP PAR FLW as given and
      changes nothing on it. Known after Open; always False on Windows,
      where a virtual port's driver answers for itself. }
    property VirtualLine: Boolean read FVirtual;
  end;

const
  { Defaults of a new port and of tChnPhys: 9600 8N1, no flow control }
  DefaultPortSettings: tPortSettings = (
    Baud: 9600; DataBits: 8; StopBits: 1; Parity: ppNone; Flow: flowNone;
    InQueue: 4096);

{ Device of COM=n: /dev/ttyS<n-1> on Unix, \\.\COMn on Windows. }
function ComDevicePath(N: LongInt): ShortString;

{ Backend registry. Names are upper case ('RTL', 'SYNAPSE'); registering a
  name again replaces the class; a full table (MaxDrivers) stops the
  program with RunError(217), as the other registries do (docs/LAYERS.md). }
procedure RegisterPortDriver(const Name: ShortString; Cls: TChnPortClass);
function FindPortDriver(const Name: ShortString): TChnPortClass;
{ 'RTL|SYNAPSE|...' in registration order, for ParamChoice and messages. }
function PortDriverNames: ShortString;
{ The driver tChnCom uses without DRV=: 'SYNAPSE' when built with
  -dCHN_SYNAPSE, otherwise 'RTL'. }
function DefaultPortDriver: ShortString;

implementation

uses
  ChnOs, SysUtils, uString;

const
  MaxDrivers = 8;

var
  DriverNames: array[1..MaxDrivers] of string[15];
  DriverClasses: array[1..MaxDrivers] of TChnPortClass;
  DriverCount: Integer = 0;

constructor TChnPort.Create;
begin
  inherited Create;
  FDevice := '';
  FOpen := False;
  FOSError := 0;
  FVirtual := False;
  FailKey := '';
end;

destructor TChnPort.Destroy;
begin
  if FOpen then
    Close;
  inherited Destroy;
end;

function TChnPort.Configure(const S: tPortSettings): tChResult;
begin
  Result := res_Ok;
end;

function TChnPort.Read(var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  Got := 0;
  if not FOpen then
    Exit(res_WrongState);
  if Size <= 0 then
    Exit(res_Ok);
  Result := DoRead(Buf, Size, Got);
end;

function TChnPort.Write(const Buf; Len: LongInt; out Done: LongInt): tChResult;
begin
  Done := 0;
  if not FOpen then
    Exit(res_WrongState);
  if Len <= 0 then
    Exit(res_Ok);
  Result := DoWrite(Buf, Len, Done);
end;

function TChnPort.WaitOutput(Ms: LongInt): Boolean;
begin
  Result := True;
end;

function TChnPort.OutQueue(out N: LongInt): tChResult;
begin
  N := 0;
  Result := res_Ok;
end;

function TChnPort.Drain: tChResult;
begin
  Result := res_Ok;
end;

function TChnPort.Flush(Input, Output: Boolean): tChResult;
begin
  Result := res_Ok;
end;

function TChnPort.SetRts(On: Boolean): tChResult;
begin
  Result := res_BadSetting;
end;

function TChnPort.SetDtr(On: Boolean): tChResult;
begin
  Result := res_BadSetting;
end;

function TChnPort.GetLines(out Lines: tPortLines): tChResult;
begin
  Lines := [];
  Result := res_BadSetting;
end;

function TChnPort.SetKernelRs485(On: Boolean): tChResult;
begin
  Result := res_BadSetting;
end;

function TChnPort.SetLatency(Ms: LongInt): tChResult;
begin
  Result := res_BadSetting;
end;

function TChnPort.OsOverruns(out N: LongWord): tChResult;
begin
  N := 0;
  Result := res_Ok;
end;

function TChnPort.OsHandle: PtrInt;
begin
  Result := -1;
end;

function TChnPort.OSErrorText: ShortString;
begin
  if FOSError = 0 then
    Exit('');
  Result := ChnOs.OsErrorText(FOSError);
end;

procedure TChnPort.Close;
begin
  FOpen := False;
end;

procedure TChnPort.WaitJoined(Src: pChnWaitSource);
begin
end;

function TChnPort.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  Kind := wkSignal;
  Os := -1;
  Rearm := nil;
  Data := nil;
  Result := False;
end;

function TChnPort.WaitUseful: Boolean;
begin
  Result := True;
end;

function TChnPort.ShortReadDrains: Boolean;
begin
  Result := False;
end;

procedure TChnPort.PollTimers;
begin
end;

function TChnPort.HoldsInput: Boolean;
begin
  Result := False;
end;

procedure RegisterPortDriver(const Name: ShortString; Cls: TChnPortClass);
var
  I: Integer;
  U: string;
begin
  U := UpStr(Name);
  for I := 1 to DriverCount do
    if DriverNames[I] = U then
    begin
      DriverClasses[I] := Cls;
      Exit;
    end;
  if DriverCount >= MaxDrivers then
    RunError(217);      { programming error: raise MaxDrivers }
  Inc(DriverCount);
  DriverNames[DriverCount] := U;
  DriverClasses[DriverCount] := Cls;
end;

function FindPortDriver(const Name: ShortString): TChnPortClass;
var
  I: Integer;
  U: string;
begin
  U := UpStr(Name);
  for I := 1 to DriverCount do
    if DriverNames[I] = U then
      Exit(DriverClasses[I]);
  Result := nil;
end;

function PortDriverNames: ShortString;
var
  I: Integer;
begin
  Result := '';
  for I := 1 to DriverCount do
  begin
    if I > 1 then
      Result := Result + '|';
    Result := Result + DriverNames[I];
  end;
end;

function ComDevicePath(N: LongInt): ShortString;
begin
  Result := OsComDevicePath(N);
end;

function DefaultPortDriver: ShortString;
begin
  {$IFDEF CHN_SYNAPSE}
  Result := 'SYNAPSE';
  {$ELSE}
  Result := 'RTL';
  {$ENDIF}
end;

end.
