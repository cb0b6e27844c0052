{ ChnPortSynapse - TChnPort on Synapse's TBlockSerial (unit synaser).
  Registered as driver 'SYNAPSE'. Built only when the build is given a
  Synapse source folder: make SYNAPSE_DIR=/path/to/synapse (the Makefile
  then passes -dCHN_SYNAPSE). Synapse is not part of this repository; get
  it from https://github.com/geby/synapse (or the Ararat Synapse release,
  http://synapse.ararat.cz), see docs/ChnCom.md.

  How TBlockSerial is used, and what this unit adds around it:
  * RaiseExcept stays False: every call is followed by a look at LastError,
    mapped to a tChResult (Connect's errno, Windows' GetLastError).
  * LinuxLock is switched off: Synapse's /var/lock/LCK..<name> files cannot
    name /dev/pts/N or /dev/serial/by-id paths. Like the RTL backend this
    unit takes an flock on the descriptor instead.
  * On Unix Synapse opens the device blocking; this unit sets O_NONBLOCK on
    TBlockSerial.Handle so SendBuffer/RecvBuffer never stall the caller
    (a partial write is fine, the layer retries from ChSendReady). On
    Windows, where Synapse uses overlapped I/O and waits for completion,
    writes are cut to what the driver's output queue has room for, and
    WaitInput polls the input queue (synaser's WaitCommEvent wait ends at
    once under Wine).
  * After Config the settings are read back (GetCommState): what the driver
    changed is res_BadSetting, FailKey naming the setting.
  * A pty (Unix, as in ChnPortUnix) is a virtual line: Config is given 8N1
    without flow control and every setting is taken as asked.
  * Config takes only the rates of Synapse's own table (50..4000000 on
    Linux, up to 256000 on Windows) and cannot do mark/space parity on Unix:
    anything else is res_BadSetting here rather than Synapse's silent B0
    (which would hang the line up).
  * RS-485: Synapse has no kernel RS-485 call, so KERNEL is refused (AUTO
    then falls back to RTS toggling by tChnCom).
  * The program-wide wait (unit ChnWait): on Unix the port joins it with
    synaser's descriptor. On Windows it does not: synaser reads through
    its own overlapped calls on the handle, and an outstanding read of our
    own (what ChnPortWin waits on) would take bytes from under them, while
    WaitCommEvent ends at once under Wine, so it could not be checked
    either. There a poll waits on this port alone (WaitInput in
    win/chnportsynapse.inc), as before: a program with many Synapse lines
    on Windows should use the RTL backend for the shared wait. }
unit ChnPortSynapse;

{$I chn.inc}

interface

uses
  SysUtils, synaser, ChnTypes, ChnWait, ChnPort;

type
  { synaser's Connect and CloseSocket purge both directions (TCIOFLUSH,
    PurgeComm with TXABORT): output not yet on the line - and on a pty
    whatever the other side has not read yet, such as the last frame of
    the session before - was lost. tChnCom drains (bounded) before it
    closes; synaser's own purges here discard input only, and
    TChnPortSynapse.Flush purges the directions it is asked for. }
  TChnBlockSerial = class(TBlockSerial)
  public
    procedure Purge; override;
  end;

  TChnPortSynapse = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FSer: TChnBlockSerial;
    function Check: tChResult;
    function MapError(E: LongInt): tChResult;
    function Refuse(const Key: ShortString): tChResult;
    { what differs per OS (unix/ or win/chnportsynapse.inc) }
    procedure BeforeConnect;
    function AfterConnect(const Path: tWordString): tChResult;
    function BeforeConfig(const S: tPortSettings): tChResult;
    { the settings the driver took against those Config asked for }
    function ReadBack: tChResult;
    { nothing queued, yet a read would tell something (a hang-up) }
    function ReadableAnyway: Boolean;
    function WouldBlock: Boolean;
    { RecvBuffer gave N: True when that settles the read (R) }
    function ReadEnded(N: LongInt; out R: tChResult): Boolean;
    { how much of Len a write may hand the driver now }
    function WriteRoom(Len: LongInt): LongInt;
  public
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
    function OsOverruns(out N: LongWord): tChResult; override;
    function SetLatency(Ms: LongInt): tChResult; override;
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    function OsHandle: PtrInt; override;
    { synaser's words for its own codes (9991 'Port owned by other
      process'), the OS's for the others }
    function OSErrorText: ShortString; override;
    procedure Close; override;
    property Serial: TChnBlockSerial read FSer;
  end;

implementation

{ the uses clause, SynapseMaxBaud and what differs per OS }
{$IFDEF UNIX}{$I unix/chnportsynapse.inc}{$ENDIF}
{$IFDEF WINDOWS}{$I win/chnportsynapse.inc}{$ENDIF}

const
  SynapseBauds: array[0..29] of LongInt = (
    50, 75, 110, 134, 150, 200, 300, 600, 1200, 1800, 2400, 4800, 9600,
    19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600,
    1000000, 1152000, 1500000, 2000000, 2500000, 3000000, 3500000, 4000000);



function TChnPortSynapse.OSErrorText: ShortString;
begin
  if (FOSError >= ErrAccessDenied) and (FOSError <= ErrTxFull) then
    Result := TBlockSerial.GetErrorDesc(FOSError)
  else
    Result := inherited OSErrorText;
end;

function TChnPortSynapse.Refuse(const Key: ShortString): tChResult;
begin
  FailKey := Key;
  Result := res_BadSetting;
end;

function TChnPortSynapse.Check: tChResult;
begin
  Result := MapError(FSer.LastError);
end;

function TChnPortSynapse.Open(const Path: tWordString): tChResult;
begin
  if FOpen then
    Exit(res_WrongState);
  FDevice := Path;
  FOSError := 0;
  FailKey := '';
  FVirtual := False;
  FSer := TChnBlockSerial.Create;
  FSer.RaiseExcept := False;
  BeforeConnect;
  FSer.Connect(Path);
  Result := Check;
  if Result = res_Ok then
    Result := AfterConnect(Path);
  if Result <> res_Ok then
  begin
    FSer.Free;                    { closes the handle }
    FSer := nil;
    Exit;
  end;
  FOpen := True;
end;

function TChnPortSynapse.Configure(const S: tPortSettings): tChResult;
const
  Letters: array[tPortParity] of Char = ('N', 'E', 'O', 'M', 'S');
var
  I: Integer;
  Known: Boolean;
begin
  if not FOpen then
    Exit(res_WrongState);
  Known := False;
  for I := Low(SynapseBauds) to High(SynapseBauds) do
    if SynapseBauds[I] = S.Baud then
      Known := True;
  FailKey := '';
  if not (S.DataBits in [5..8]) then
    Exit(Refuse('BIT'));
  if not (S.StopBits in [1, 2]) then
    Exit(Refuse('STOP'));
  if FVirtual then
  begin
    { bytes only: 8N1, no flow control, whatever was asked }
    FSer.Config(9600, 8, 'N', SB1, False, False);
    Exit(Check);
  end;
  if not Known or (S.Baud > SynapseMaxBaud) then
    Exit(Refuse('BD'));
  Result := BeforeConfig(S);
  if Result <> res_Ok then
    Exit;
  if S.StopBits = 2 then
    I := SB2
  else
    I := SB1;
  FSer.Config(S.Baud, S.DataBits, Letters[S.Parity], I,
    S.Flow = flowXonXoff, S.Flow = flowRtsCts);
  Result := Check;
  if Result <> res_Ok then
  begin
    if Result = res_BadSetting then
      FailKey := 'BD';            { as in ChnPortUnix: EINVAL is the rate }
    Exit;
  end;
  { synaser does not look at what the driver really took: read it back }
  Result := ReadBack;
end;

function TChnPortSynapse.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  N: Integer;
begin
  N := FSer.WaitingData;
  Result := Check;
  if Result <> res_Ok then
    Exit;
  if N <= 0 then
  begin
    if not ReadableAnyway then
      Exit(res_Ok);
    N := 1;
  end;
  if N > Size then
    N := Size;
  N := FSer.RecvBuffer(@Buf, N);
  if ReadEnded(N, Result) then
    Exit;
  Result := Check;
  if (Result = res_Ok) or (Result = res_Overrun) then
    if N > 0 then
      Got := N;
  if Result = res_Overrun then
    Result := res_Ok;              { counted by OsOverruns on Windows }
end;


function TChnPortSynapse.WaitOutput(Ms: LongInt): Boolean;
begin
  Result := FOpen and FSer.CanWrite(Ms);
end;

function TChnPortSynapse.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  N: Integer;
begin
  Len := WriteRoom(Len);
  if Len <= 0 then
    Exit(res_Ok);
  N := FSer.SendBuffer(@Buf, Len);
  if (N < 0) and WouldBlock then
    Exit(res_Ok);
  Result := Check;
  if (Result = res_Ok) and (N > 0) then
    Done := N;
end;

function TChnPortSynapse.OutQueue(out N: LongInt): tChResult;
begin
  N := 0;
  if not FOpen then
    Exit(res_WrongState);
  N := FSer.SendingData;
  Result := Check;
end;

function TChnPortSynapse.Drain: tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  FSer.Flush;                       { tcdrain / FlushFileBuffers }
  Result := Check;
end;


function TChnPortSynapse.SetRts(On: Boolean): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  FSer.RTS := On;     { the setter reads the lines first: LastError tells }
  Result := Check;
end;

function TChnPortSynapse.SetDtr(On: Boolean): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  FSer.DTR := On;
  Result := Check;
end;

function TChnPortSynapse.GetLines(out Lines: tPortLines): tChResult;
begin
  Lines := [];
  if not FOpen then
    Exit(res_WrongState);
  FSer.ModemStatus;
  Result := Check;
  if Result <> res_Ok then
    Exit;
  if FSer.CTS then
    Include(Lines, plCts);
  if FSer.DSR then
    Include(Lines, plDsr);
  if FSer.Ring then
    Include(Lines, plRing);
  if FSer.Carrier then
    Include(Lines, plCarrier);
end;

function TChnPortSynapse.SetKernelRs485(On: Boolean): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if On then
    Result := res_BadSetting
  else
    Result := res_Ok;
end;

function TChnPortSynapse.OsOverruns(out N: LongWord): tChResult;
begin
  N := 0;                           { synaser does not count them }
  if not FOpen then
    Exit(res_WrongState);
  Result := res_Ok;
end;


function TChnPortSynapse.OsHandle: PtrInt;
begin
  if FSer = nil then
    Result := -1
  else
    Result := PtrInt(FSer.Handle);
end;

procedure TChnPortSynapse.Close;
begin
  if FSer <> nil then
  begin
    FSer.CloseSocket;
    FSer.Free;
  end;
  FSer := nil;
  FOpen := False;
end;

initialization
  RegisterPortDriver('SYNAPSE', TChnPortSynapse);
end.
