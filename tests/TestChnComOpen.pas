{ Tests of ChnCom's open over real pseudo-terminal pairs (no hardware):
  a missing device, no permission, not a terminal, a device in use (also
  for another user), the refusals naming the token and the OS's reason,
  RS-485 and the latency timer where the driver lacks them, a device lost
  while open and reopened, reconnecting by itself (RECON=) and stopping at
  a setting refused. Once per port backend built in (TTestChnComOpenRtl,
  TTestChnComOpenSynapse), on the fixture of ComPtyCase; the line itself
  is TestChnCom's. }
unit TestChnComOpen;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry,
  {$IFDEF UNIX}BaseUnix, Unix, TermIO, Linux, Process, PtyPair, ChnPortUnix, ChnUnix, ChnPty, BinSupport,
  ComPtySupport, ComPtyCase,{$ENDIF}
  ChnTypes, ChnVirt, ChnPort, ChnCom, ChnDF1, TestSupport;

{$IFDEF UNIX}
type
  TTestChnComOpen = class(TComPtyCase)
  published
    procedure TestMissingDevice;
    procedure TestNoPermission;
    procedure TestNotATerminalIsRefused;
    procedure TestOtherUserCanOpenAfterClose;
    procedure TestDeviceInUse;
    procedure TestDeviceLostThenReopen;
    procedure TestReconnectsAfterDeviceLoss;
    procedure TestReconnectStopsAtARefusedSetting;
    procedure TestLatencyRefusedWithoutTheTimer;
    procedure TestLatencyWrittenWhereTheDriverHasIt;
    procedure TestRs485RefusedOnPty;
    procedure TestRefusalNamesTheToken;
    procedure TestOpenErrorsSayTheOsReason;
  end;

  TTestChnComOpenRtl = class(TTestChnComOpen)
  protected
    function Drv: string; override;
  end;

  {$IFDEF CHN_SYNAPSE}
  TTestChnComOpenSynapse = class(TTestChnComOpen)
  protected
    function Drv: string; override;
  end;
  {$ENDIF}

{$ENDIF UNIX}

implementation

{$IFDEF UNIX}
procedure TTestChnComOpen.TestMissingDevice;
begin
  FChn := ChnCollection^.ChNewInit(ChnCom.cName);
  FChn^.ChSetParam('DRV=' + Drv + ' DEV=/dev/chn-no-such-tty');
  AssertEquals('params', res_Ok, FChn^.ChResult);
  FChn^.ChOpen;
  AssertEquals('missing device', res_CannotOpen, FChn^.ChResult);
  AssertEquals('state', CHS_Close, FChn^.ChReady);
  FChn^.ChSend(@FRBuf, 1);
  AssertEquals('send on closed', res_WrongState, FChn^.ChSendResult);
  { the path is the device: a typo in COM's directory is just as missing }
  FChn^.ChSetParam('DEV=/nonexistent-dir/ttyUSB0');
  FChn^.ChOpen;
  AssertEquals('missing directory', res_CannotOpen, FChn^.ChResult);
  { a directory is no device either }
  FChn^.ChSetParam('DEV=/tmp');
  FChn^.ChOpen;
  AssertEquals('a directory', res_CannotOpen, FChn^.ChResult);
  AssertEquals('state after all', CHS_Close, FChn^.ChReady);
end;

{ Opening a device the user may not access. Root may access everything, so
  when the suite runs as root the open is tried in a forked child that has
  dropped to nobody (65534) first; the child's exit code carries ChResult. }
procedure TTestChnComOpen.TestNoPermission;
var
  Code: LongInt;
begin
  AssertEquals('chmod 000', 0, FpChmod(PChar(FPty.SlavePath), 0));
  Code := OpenComAsNobody('DRV=' + Drv + ' DEV=' + FPty.SlavePath, True);
  AssertTrue('child forked and exited (code ' + IntToStr(Code) + ')', Code >= 0);
  AssertTrue('child could drop root (code ' + IntToStr(Code) + ')', Code < NobodyNotDropped);
  AssertEquals('no permission, state closed', res_NoPermission, Code);
end;

procedure TTestChnComOpen.TestNotATerminalIsRefused;
var
  Path: string;
  F: THandle;
begin
  Path := GetTempDir + 'chn-com-not-a-tty-' + IntToStr(FpGetPid);
  F := FileCreate(Path);
  AssertTrue('temp file', F <> THandle(-1));
  FileClose(F);
  try
    FChn := ChnCollection^.ChNewInit(ChnCom.cName);
    FChn^.ChSetParam('DRV=' + Drv + ' DEV=' + Path);
    FChn^.ChOpen;
    AssertEquals('regular file refuses serial settings', res_BadSetting, FChn^.ChResult);
    AssertEquals('state', CHS_Close, FChn^.ChReady);
    FChn^.ChSetParam('DEV=/dev/null');
    FChn^.ChOpen;
    AssertEquals('/dev/null refuses serial settings', res_BadSetting, FChn^.ChResult);
    AssertEquals('state', CHS_Close, FChn^.ChReady);
  finally
    DeleteFile(Path);
  end;
end;

{ Exclusive use ends with ChClose: TIOCEXCL would outlive the descriptor
  on a pty slave (its master stays open) and lock out every other non-root
  user. The second open runs in a child as nobody, as in TestNoPermission. }
procedure TTestChnComOpen.TestOtherUserCanOpenAfterClose;
var
  Code: LongInt;
begin
  AssertEquals('first open', res_Ok, OpenCom(''));
  FChn^.ChClose;
  if FpGetuid = 0 then
    AssertEquals('chown to nobody', 0, FpChown(PChar(FPty.SlavePath), 65534, 65534));
  Code := OpenComAsNobody('DRV=' + Drv + ' DEV=' + FPty.SlavePath, False);
  AssertTrue('child forked and exited (code ' + IntToStr(Code) + ')', Code >= 0);
  AssertTrue('child could drop root (code ' + IntToStr(Code) + ')', Code < NobodyNotDropped);
  AssertEquals('another user opens the closed device', res_Ok, Code);
end;

procedure TTestChnComOpen.TestDeviceInUse;
var
  Second: pChnVirt;
begin
  AssertEquals('first open', res_Ok, OpenCom(''));
  Second := ChnCollection^.ChNewInit(ChnCom.cName);
  try
    Second^.ChSetParam('DRV=' + Drv + ' DEV=' + FPty.SlavePath);
    Second^.ChOpen;
    AssertEquals('second open of the same device', res_CannotOpen, Second^.ChResult);
    AssertEquals('second stays closed', CHS_Close, Second^.ChReady);
    FChn^.ChClose;
    Second^.ChOpen;
    AssertEquals('free again after close', res_Ok, Second^.ChResult);
  finally
    Dispose(Second, Done);
  end;
end;

procedure TTestChnComOpen.TestDeviceLostThenReopen;
var
  B: array[0..2] of Byte;
  T0: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom(''));
  B[0] := 1; B[1] := 2; B[2] := 3;
  AssertTrue('master write', FPty.MasterWriteAll(B, 3, 1000));
  AssertEquals('3 bytes before the loss', 3, ChnReceiveAll(@B, 3, 2000));
  FPty.CloseMaster;                 { the USB adapter is pulled }
  FChn^.ChReceiveReady;             { the next tick notices }
  AssertEquals('ChResult', res_DeviceLost, FChn^.ChResult);
  AssertEquals('ChReceiveResult', res_DeviceLost, FChn^.ChReceiveResult);
  FChn^.ChSend(@B, 3);
  AssertEquals('ChSendResult', res_DeviceLost, FChn^.ChSendResult);
  AssertEquals('still open until the application closes', CHS_Connect, FChn^.ChReady);
  { a lost device must not turn a polling loop into a busy loop or a hang }
  T0 := GetTickCount64;
  AssertEquals('nothing to receive', CHS_Receiving, FChn^.ChReceiveReady);
  { IDL=1: a poll takes about 1 ms; a hang never returns. 500 ms leaves
    room for a loaded CI machine }
  AssertTrue('poll returns', GetTickCount64 - T0 < 500);
  FChn^.ChClose;
  AssertEquals('close', res_Ok, FChn^.ChResult);
  AssertEquals('closed', CHS_Close, FChn^.ChReady);
  { the adapter comes back (here: a new pty) }
  FPty.Free;
  FPty := TPtyPair.Create;
  FChn^.ChSetParam('DEV=' + FPty.SlavePath);
  FChn^.ChOpen;
  AssertEquals('reopen', res_Ok, FChn^.ChResult);
  FChn^.ChReceiveBuffer(@FRBuf, SizeOf(FRBuf));
  FChn^.ChConnect;
  ExchangeAllByteValues('after reopen');
end;

{ RECON=: the device is a symlink, as /dev/serial/by-id/... is; it goes
  away with the adapter and comes back pointing at another tty. The layer
  reports res_Reconnecting with the device named, polls keep waiting IDL
  (no busy loop), and once the device is back the layer has reopened it
  by itself with every setting (read from the kernel) and bytes flow. }
procedure TTestChnComOpen.TestReconnectsAfterDeviceLoss;
var
  Link: string;
  T0: QWord;
  C0, Used: Double;
  Polls: LongInt;
begin
  Link := GetTempDir(False) + 'chn-recon-' + IntToStr(FpGetPid) + '-' + Drv;
  DeleteFile(Link);
  AssertEquals('symlink', 0, FpSymlink(PChar(FPty.SlavePath), PChar(Link)));
  try
    FChn := ChnCollection^.ChNewInit(ChnCom.cName);
    FChn^.ChSetParam('NAM=COM DRV=' + Drv + ' DEV=' + Link + ' BD=19200 STOP=2 RECON=50 IDL=5');
    AssertEquals('params ' + FChn^.ChParamError, res_Ok, FChn^.ChResult);
    AssertTrue('reported back', Pos('RECON=50', FChn^.ChGetParam('')) > 0);
    FChn^.ChOpen;
    AssertEquals('open', res_Ok, FChn^.ChResult);
    FChn^.ChReceiveBuffer(@FRBuf, SizeOf(FRBuf));
    FChn^.ChConnect;
    ExchangeAllByteValues('before the loss');
    { the adapter is pulled: its tty hangs up, its by-id link goes }
    FPty.CloseMaster;
    DeleteFile(Link);
    T0 := GetTickCount64;
    C0 := CpuMs;
    Polls := 0;
    while GetTickCount64 - T0 < 600 do
    begin
      AssertEquals('receiving', CHS_Receiving, FChn^.ChReceiveReady);
      Inc(Polls);
    end;
    Used := CpuMs - C0;
    AssertEquals('ChResult while away', res_Reconnecting, FChn^.ChResult);
    AssertEquals('ChReceiveResult', res_Reconnecting, FChn^.ChReceiveResult);
    AssertEquals('the device named', 'DEV=' + Link, FChn^.ChParamError);
    FChn^.ChSend(@FRBuf, 1);
    AssertEquals('ChSendResult', res_Reconnecting, FChn^.ChSendResult);
    AssertEquals('still connected for the program', CHS_Connect, FChn^.ChReady);
    { IDL=5: about 120 polls in 600 ms, each waiting; a spinning loop
      makes thousands and burns the CPU }
    AssertTrue('polls waited (' + IntToStr(Polls) + ' polls)', Polls < 1000);
    AssertTrue('no busy loop (' + FloatToStrF(Used, ffFixed, 8, 1) + ' ms CPU in 600 ms)',
      Used < IdleCpuBound(200));
    { the adapter comes back: another tty behind the same name }
    FPty.Free;
    FPty := TPtyPair.Create;
    AssertEquals('symlink again', 0, FpSymlink(PChar(FPty.SlavePath), PChar(Link)));
    T0 := GetTickCount64;
    while (FChn^.ChResult <> res_Ok) and (GetTickCount64 - T0 < 3000) do
      FChn^.ChReceiveReady;
    AssertEquals('reconnected by itself', res_Ok, FChn^.ChResult);
    AssertEquals('receive result', res_Ok, FChn^.ChReceiveResult);
    AssertEquals('no token named', '', FChn^.ChParamError);
    CheckTermios('settings re-applied', KCS8 or KCSTOPB, $E { B19200 });
    ExchangeAllByteValues('after the reconnect');
  finally
    DeleteFile(Link);
  end;
end;

{ A device that comes back but is not what was configured (here: not a
  terminal at all) ends the reconnect with the refusal named; a device
  that never comes back stays res_Reconnecting until ChClose. }
procedure TTestChnComOpen.TestReconnectStopsAtARefusedSetting;
var
  Link: string;
  T0: QWord;
begin
  Link := GetTempDir(False) + 'chn-recon2-' + IntToStr(FpGetPid) + '-' + Drv;
  DeleteFile(Link);
  AssertEquals('symlink', 0, FpSymlink(PChar(FPty.SlavePath), PChar(Link)));
  try
    FChn := ChnCollection^.ChNewInit(ChnCom.cName);
    FChn^.ChSetParam('NAM=COM DRV=' + Drv + ' DEV=' + Link + ' RECON=20 IDL=5');
    FChn^.ChOpen;
    AssertEquals('open', res_Ok, FChn^.ChResult);
    FChn^.ChReceiveBuffer(@FRBuf, SizeOf(FRBuf));
    FChn^.ChConnect;
    FPty.CloseMaster;
    DeleteFile(Link);
    T0 := GetTickCount64;
    while GetTickCount64 - T0 < 300 do
      FChn^.ChReceiveReady;
    AssertEquals('never back (yet)', res_Reconnecting, FChn^.ChResult);
    AssertEquals('the device named', 'DEV=' + Link, FChn^.ChParamError);
    AssertEquals('back as something else', 0, FpSymlink(PChar('/dev/null'), PChar(Link)));
    T0 := GetTickCount64;
    while (FChn^.ChResult = res_Reconnecting) and (GetTickCount64 - T0 < 3000) do
      FChn^.ChReceiveReady;
    AssertEquals('refused', res_BadSetting, FChn^.ChResult);
    AssertEquals('the token', 'DEV=' + Link, FChn^.ChParamError);
    { no further attempts: a good device now changes nothing }
    DeleteFile(Link);
    FPty.Free;
    FPty := TPtyPair.Create;
    AssertEquals('symlink again', 0, FpSymlink(PChar(FPty.SlavePath), PChar(Link)));
    T0 := GetTickCount64;
    while GetTickCount64 - T0 < 200 do
      FChn^.ChReceiveReady;
    AssertEquals('stays refused', res_BadSetting, FChn^.ChResult);
    FChn^.ChClose;
    AssertEquals('close', res_Ok, FChn^.ChResult);
    FChn^.ChOpen;
    AssertEquals('ChClose + ChOpen starts again', res_Ok, FChn^.ChResult);
  finally
    DeleteFile(Link);
  end;
end;

{ LAT=: a pty (like a UART or a CDC-ACM modem) has no latency timer: the
  open is refused with the token named; LAT=0 leaves it alone. }
procedure TTestChnComOpen.TestLatencyRefusedWithoutTheTimer;
begin
  AssertEquals('LAT=1 on a pty', res_BadSetting, OpenCom('LAT=1'));
  AssertEquals('the token', 'LAT=1', FChn^.ChParamError);
  AssertEquals('closed', CHS_Close, FChn^.ChReady);
  AssertTrue('reported back', Pos(' LAT=1', FChn^.ChGetParam('')) > 0);
  AssertEquals('LAT=0 opens', res_Ok, OpenCom('LAT=0'));
  FChn^.ChSetParam('LAT=256');
  AssertEquals('LAT=256 is no value', res_BadParam, FChn^.ChResult);
  AssertEquals('LAT=256 named', 'LAT=256', FChn^.ChParamError);
end;

{ Where the driver has the timer (ftdi_sio: <sysfs tty>/ttyUSB0/device/
  latency_timer), LAT= writes it and reads it back. A folder of the test
  stands in for /sys/class/tty, named after this pty (/dev/pts/N: N). }
procedure TTestChnComOpen.TestLatencyWrittenWhereTheDriverHasIt;
var
  Root, F: string;
  T: Text;
  Line: string;
  Saved: ShortString;
begin
  Root := GetTempDir(False) + 'chn-sysfs-' + IntToStr(FpGetPid) + '-' + Drv + '/';
  F := Root + ExtractFileName(FPty.SlavePath) + '/device/latency_timer';
  ForceDirectories(ExtractFilePath(F));
  AssignFile(T, F);
  Rewrite(T);
  WriteLn(T, '16');                 { ftdi_sio's default }
  CloseFile(T);
  Saved := PortSysfsTty;
  PortSysfsTty := Root;
  try
    AssertEquals('LAT=2 open', res_Ok, OpenCom('LAT=2'));
    AssertEquals('no token', '', FChn^.ChParamError);
    AssignFile(T, F);
    Reset(T);
    ReadLn(T, Line);
    CloseFile(T);
    AssertEquals('written', '2', Trim(Line));
    if FpGetUid <> 0 then
    begin
      FpChmod(F, &444);
      AssertEquals('read-only timer', res_NoPermission, OpenCom('LAT=1'));
      AssertEquals('the token', 'LAT=1', FChn^.ChParamError);
    end;
  finally
    PortSysfsTty := Saved;
    DeleteFile(F);
    RemoveDir(ExtractFilePath(F));
    RemoveDir(Root + ExtractFileName(FPty.SlavePath));
    RemoveDir(Root);
  end;
end;

procedure TTestChnComOpen.TestRs485RefusedOnPty;
begin
  { a pty has neither RS-485 support nor an RTS line: every mode that needs
    one is refused instead of silently sending without direction control }
  AssertEquals('KERNEL', res_BadSetting, OpenCom('RS485=KERNEL'));
  AssertEquals('KERNEL closed', CHS_Close, FChn^.ChReady);
  AssertEquals('RTS', res_BadSetting, OpenCom('RS485=RTS'));
  AssertEquals('RTS closed', CHS_Close, FChn^.ChReady);
  AssertEquals('AUTO', res_BadSetting, OpenCom('RS485=AUTO'));
  AssertEquals('OFF opens', res_Ok, OpenCom('RS485=OFF'));
end;

{ Every refusal of ChOpen names its token in ChParamError, also through a
  protocol layer above, and a later good open clears it. }
procedure TTestChnComOpen.TestRefusalNamesTheToken;
var
  D: pChnVirt;
begin
  AssertEquals('BIT=7 PAR=E', res_BadSetting, OpenCom('BIT=7 PAR=E'));
  AssertEquals('the data bits go first', 'BIT=7', FChn^.ChParamError);
  AssertEquals(res_BadSetting, OpenCom('PAR=O'));
  AssertEquals('PAR=O', FChn^.ChParamError);
  AssertEquals(res_BadSetting, OpenCom('PAR=M'));
  AssertEquals('PAR=M', FChn^.ChParamError);
  AssertEquals(res_BadSetting, OpenCom('RS485=KERNEL'));
  AssertEquals('RS485=KERNEL', FChn^.ChParamError);
  AssertEquals(res_Ok, OpenCom('PAR=N'));
  AssertEquals('cleared by a good open', '', FChn^.ChParamError);
  FChn^.ChClose;
  FChn^.ChSetParam('DEV=/dev/null');
  FChn^.ChOpen;
  AssertEquals(res_BadSetting, FChn^.ChResult);
  AssertEquals('not a terminal: the device', 'DEV=/dev/null', FChn^.ChParamError);
  FChn^.ChSetParam('DEV=/dev/chn-no-such-tty');
  FChn^.ChOpen;
  AssertEquals(res_CannotOpen, FChn^.ChResult);
  AssertEquals('DEV=/dev/chn-no-such-tty', FChn^.ChParamError);
  { through a protocol layer: the top layer names it too }
  D := ChnCollection^.ChNewInit('DF1');
  AssertTrue('DF1 is linked in (TestChnDF1)', D <> nil);
  try
    D^.ChSetParam('NAM=DF1 NAM=COM DRV=' + Drv + ' DEV=' + FPty.SlavePath + ' PAR=O');
    AssertEquals(res_Ok, D^.ChResult);
    D^.ChOpen;
    AssertEquals(res_BadSetting, D^.ChResult);
    AssertEquals('the top layer', 'PAR=O', D^.ChParamError);
  finally
    Dispose(D, Done);
  end;
end;

{ ChErrorText after a refused open: the result, the token and the OS's
  own words for why (the C library's texts, as ls or cat print them),
  through a protocol layer above as well. }
procedure TTestChnComOpen.TestOpenErrorsSayTheOsReason;
var
  Second, D: pChnVirt;
  InUse: string;   { root: flock says EAGAIN; others: TIOCEXCL refuses the open, EBUSY }

  procedure OpenAs(const Dev: string);
  begin
    FChn^.ChSetParam('DRV=' + Drv + ' DEV=' + Dev);
    AssertEquals(Dev + ' params', res_Ok, FChn^.ChResult);
    FChn^.ChOpen;
  end;

begin
  FChn := ChnCollection^.ChNewInit(ChnCom.cName);
  OpenAs('/dev/chn-no-such-tty');
  AssertEquals('device cannot be opened (DEV=/dev/chn-no-such-tty): No such file or directory',
    FChn^.ChErrorText);
  OpenAs('/nonexistent-dir/ttyUSB0');
  AssertEquals('device cannot be opened (DEV=/nonexistent-dir/ttyUSB0): No such file or directory',
    FChn^.ChErrorText);
  OpenAs('/tmp');
  AssertEquals('device cannot be opened (DEV=/tmp): Is a directory', FChn^.ChErrorText);
  OpenAs('/dev/null');
  AssertEquals('device refuses the setting (DEV=/dev/null): Inappropriate ioctl for device',
    FChn^.ChErrorText);
  { a good open says nothing more }
  OpenAs(FPty.SlavePath);
  AssertEquals('ok', res_Ok, FChn^.ChResult);
  AssertEquals('ok', FChn^.ChErrorText);
  { the pty in use: for root flock says it would have to wait; for other
    users the kernel already refuses the open because of TIOCEXCL }
  Second := ChnCollection^.ChNewInit(ChnCom.cName);
  try
    Second^.ChSetParam('DRV=' + Drv + ' DEV=' + FPty.SlavePath);
    Second^.ChOpen;
    InUse := 'device cannot be opened (DEV=' + FPty.SlavePath + '): Resource temporarily unavailable';
    if Second^.ChErrorText <> InUse then
      InUse := 'device cannot be opened (DEV=' + FPty.SlavePath + '): Device or resource busy';
    AssertEquals(InUse, Second^.ChErrorText);
  finally
    Dispose(Second, Done);
  end;
  { through a protocol layer: the top layer's text is the same }
  D := ChnCollection^.ChNewInit('DF1');
  try
    D^.ChSetParam('NAM=DF1 NAM=COM DRV=' + Drv + ' DEV=/tmp');
    AssertEquals(res_Ok, D^.ChResult);
    D^.ChOpen;
    AssertEquals('device cannot be opened (DEV=/tmp): Is a directory', D^.ChErrorText);
    { and a bad value below says what the key takes }
    D^.ChSetParam('NAM=DF1 NAM=COM DRV=' + Drv + ' DEV=/tmp BD=abc');
    AssertEquals('bad parameter (BD=abc): a number 50..4000000', D^.ChErrorText);
    { the pty in use, then free: the reason does not outlive the failure }
    FChn^.ChClose;
    FChn^.ChOpen;
    D^.ChSetParam('NAM=DF1 NAM=COM DRV=' + Drv + ' DEV=' + FPty.SlavePath);
    D^.ChOpen;
    AssertEquals(InUse, D^.ChErrorText);
    FChn^.ChClose;
    D^.ChOpen;
    AssertEquals('opened', res_Ok, D^.ChResult);
    AssertEquals('no reason left', '', D^.CH_ErrWhy);
  finally
    Dispose(D, Done);
  end;
end;

function TTestChnComOpenRtl.Drv: string;
begin
  Result := 'RTLSTRICT';
end;

{$IFDEF CHN_SYNAPSE}
function TTestChnComOpenSynapse.Drv: string;
begin
  Result := 'SYNSTRICT';
end;
{$ENDIF}
{$ENDIF UNIX}

initialization
  {$IFDEF UNIX}
  RegisterTest(TTestChnComOpenRtl);
  {$IFDEF CHN_SYNAPSE}
  RegisterTest(TTestChnComOpenSynapse);
  {$ENDIF}
  {$ENDIF}
end.
