{ Tests of ChnCom over real pseudo-terminal pairs (no hardware): the pty
  tests run once per port backend built in (TTestChnComRtl always,
  TTestChnComSynapse with make SYNAPSE_DIR=...). A pty is a virtual line,
  which takes every setting as given; to test the strict path a real UART
  takes (read-back, refusals naming the token), these tests open the pty
  through a test driver (RTLSTRICT, SYNSTRICT) that is the backend with the
  virtual-line detection switched off. Settings are checked by reading the
  kernel's termios of the open descriptor, not through the code under
  test. The virtual line itself is TestChnComVirtual's, the parameters and
  the RS-485/overrun logic on a scripted port TestChnComLogic's; on Windows
  this unit is empty (no ptys there; tools/wintest.sh runs ChnPortWin on a
  Wine COM port instead). }
unit TestChnCom;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry,
  {$IFDEF UNIX}BaseUnix, Unix, TermIO, Linux, Process, PtyPair, ChnPortUnix, ChnUnix, ChnPty, BinSupport,{$ENDIF}
  {$IFDEF CHN_SYNAPSE}ChnPortSynapse,{$ENDIF}
  {$IFDEF UNIX}ComPtySupport,{$ENDIF}
  ChnTypes, ChnVirt, ChnPort, ChnCom, ChnDF1, TestSupport;

{$IFDEF UNIX}
type
  TTestChnComPty = class(TTestCase)
  protected
    FPty: TPtyPair;
    FChn: pChnVirt;
    FRBuf: array[0..65534] of Byte;
    function Drv: string; virtual; abstract;
    procedure SetUp; override;
    procedure TearDown; override;
    { NAM=COM DRV=<Drv> DEV=<slave> + Extra, then ChOpen; ChConnect when the
      open worked. Returns ChResult of the open. }
    function OpenCom(const Extra: string): tChResult;
    function Com: pChnCom;
    { Receive exactly N bytes from the channel into Dst within TimeoutMs. }
    function ChnReceiveAll(Dst: PByte; N: LongInt; TimeoutMs: LongInt): LongInt;
    procedure CheckTermios(const What: string; CFlag: Cardinal; Speed: Cardinal);
    procedure ExchangeAllByteValues(const What: string);
  published
    procedure TestBytesBothWaysAtSeveralSettings;
    procedure TestSettingsThePtyRefuses;
    procedure TestXonXoffFlowControl;
    procedure TestNonStandardBaud;
    procedure TestOneMiBBothWaysNoLoss;
    procedure TestLargeWritesCompleteThroughSendReady;
    procedure TestMissingDevice;
    procedure TestNoPermission;
    procedure TestNotATerminalIsRefused;
    procedure TestDeviceInUse;
    procedure TestOtherUserCanOpenAfterClose;
    procedure TestDeviceLostThenReopen;
    procedure TestReconnectsAfterDeviceLoss;
    procedure TestReconnectStopsAtARefusedSetting;
    procedure TestLatencyRefusedWithoutTheTimer;
    procedure TestLatencyWrittenWhereTheDriverHasIt;
    procedure TestCloseRightAfterSendLosesNothing;
    procedure TestCloseWaitsUntilALongMessageLeft;
    procedure TestCloseIsBoundedWhenNobodyReads;
    procedure TestOverrunReportedWithoutFlowControl;
    procedure TestFlowControlPausesInsteadOfDropping;
    procedure TestRs485RefusedOnPty;
    procedure TestIdleWaitReturnsOnFirstByte;
    procedure TestLegacyPollingLoopCpu;
    procedure TestRefusalNamesTheToken;
    procedure TestOpenErrorsSayTheOsReason;
  end;

  TTestChnComRtl = class(TTestChnComPty)
  protected
    function Drv: string; override;
  end;

  {$IFDEF CHN_SYNAPSE}
  TTestChnComSynapse = class(TTestChnComPty)
  protected
    function Drv: string; override;
  end;
  {$ENDIF}

  {$ENDIF UNIX}

implementation

{$IFDEF UNIX}
function Pattern(I: LongInt): Byte; inline;
begin
  Result := Byte((I * 7) xor (I shr 8) xor (I shr 16));
end;

{ Whether termios on this system keeps the rate code Code: qemu-user 7.2
  translates only codes up to B460800 and drops the rest. Asked of the
  pty master, not through the code under test. }
function SystemKeepsRate(Pty: TPtyPair; Code: Cardinal): Boolean;
var
  T, Old: Termios;
begin
  Result := False;
  if TCGetAttr(Pty.Master, Old) <> 0 then
    Exit;
  T := Old;
  CFSetOSpeed(T, Code);
  CFSetISpeed(T, Code);
  if TCSetAttr(Pty.Master, TCSANOW, T) <> 0 then
    Exit;
  Result := (TCGetAttr(Pty.Master, T) = 0) and (T.c_cflag and KCBAUD = Code);
  TCSetAttr(Pty.Master, TCSANOW, Old);
end;

{ ------------------------------------------------------------ pty tests }

procedure TTestChnComPty.SetUp;
begin
  FPty := TPtyPair.Create;
  FChn := nil;
end;

procedure TTestChnComPty.TearDown;
begin
  if FChn <> nil then
    Dispose(FChn, Done);
  FChn := nil;
  FPty.Free;
end;

function TTestChnComPty.Com: pChnCom;
begin
  Result := pChnCom(FChn);
end;

function TTestChnComPty.OpenCom(const Extra: string): tChResult;
begin
  if FChn <> nil then
    Dispose(FChn, Done);
  FChn := ChnCollection^.ChNewInit(ChnCom.cName);
  AssertTrue('COM registered', FChn <> nil);
  FChn^.ChSetParam('NAM=COM DRV=' + Drv + ' DEV=' + FPty.SlavePath + ' ' + Extra);
  AssertEquals('params ' + Extra + ' ' + FChn^.ChParamError, res_Ok, FChn^.ChResult);
  FChn^.ChOpen;
  Result := FChn^.ChResult;
  if Result = res_Ok then
  begin
    FChn^.ChReceiveBuffer(@FRBuf, SizeOf(FRBuf));
    FChn^.ChConnect;
    AssertEquals('connect', res_Ok, FChn^.ChResult);
  end;
end;

function TTestChnComPty.ChnReceiveAll(Dst: PByte; N: LongInt; TimeoutMs: LongInt): LongInt;
var
  Deadline: QWord;
  Len: Word;
  Take: LongInt;
begin
  Result := 0;
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  while (Result < N) and (GetTickCount64 <= Deadline) do
    if FChn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      FChn^.ChReceive(Len);
      AssertEquals('receive result', res_Ok, FChn^.ChReceiveResult);
      Take := Len;
      if Take > N - Result then
        Take := N - Result;   { more than asked for: the test reads too little }
      AssertEquals('no extra bytes', Take, Len);
      Move(FRBuf, Dst[Result], Take);
      Inc(Result, Take);
    end;
end;

procedure TTestChnComPty.CheckTermios(const What: string; CFlag: Cardinal; Speed: Cardinal);
var
  T: tTermios2;
  Classic: Termios;
  Mask: Cardinal;
begin
  FillChar(T, SizeOf(T), 0);
  if FpIOCtl(Com^.CH_Port.OsHandle, TCGETS2, @T) <> 0 then
  begin
    { the device refuses termios2 (qemu-user 7.2): classic termios holds
      the same flags, and a rate code for every rate the layer could set }
    AssertTrue(What + ': rate needs termios2', Speed <> KBOTHER);
    AssertEquals(What + ': tcgetattr', 0, TCGetAttr(Com^.CH_Port.OsHandle, Classic));
    T.c_cflag := Classic.c_cflag;
    T.c_lflag := Classic.c_lflag;
  end;
  Mask := KCSIZE or KCSTOPB or KPARENB or KPARODD or KCMSPAR or KCRTSCTS;
  AssertEquals(What + ': c_cflag bits', IntToHex(CFlag and Mask, 8),
    IntToHex(T.c_cflag and Mask, 8));
  if Speed = KBOTHER then
    AssertEquals(What + ': rate code', KBOTHER, T.c_cflag and KCBAUD)
  else
    AssertEquals(What + ': rate code', Speed, T.c_cflag and KCBAUD);
  AssertEquals(What + ': raw (no ICANON/ECHO)', 0, T.c_lflag and (ICANON or ECHO));
end;

{ all 256 byte values from the channel to the master and back }
procedure TTestChnComPty.ExchangeAllByteValues(const What: string);
var
  Out, Back: array[0..255] of Byte;
  I: Integer;
begin
  for I := 0 to 255 do
    Out[I] := I;
  AssertEquals(What + ': send ready', CHS_SendReady, FChn^.ChSendReady);
  FChn^.ChSend(@Out, 256);
  AssertEquals(What + ': send result', res_Ok, FChn^.ChSendResult);
  AssertTrue(What + ': sent', WaitSent(FChn, 2000));
  FillChar(Back, SizeOf(Back), 0);
  AssertEquals(What + ': master got all', 256, FPty.MasterReadAll(Back, 256, 2000));
  for I := 0 to 255 do
    AssertEquals(What + ': byte to master ' + IntToStr(I), I, Back[I]);
  for I := 0 to 255 do
    Out[I] := 255 - I;
  AssertTrue(What + ': master write', FPty.MasterWriteAll(Out, 256, 2000));
  FillChar(Back, SizeOf(Back), 0);
  AssertEquals(What + ': channel got all', 256, ChnReceiveAll(@Back, 256, 2000));
  for I := 0 to 255 do
    AssertEquals(What + ': byte from master ' + IntToStr(I), 255 - I, Back[I]);
end;

procedure TTestChnComPty.TestBytesBothWaysAtSeveralSettings;
type
  tCase = record
    P: string;
    CFlag, Speed: Cardinal;
  end;
const
  { a Linux pty keeps rate, stop bits and RTS/CTS, but always has 8 data
    bits and no parity (see TestSettingsThePtyRefuses) }
  Cases: array[0..3] of tCase = (
    (P: 'BD=9600 BIT=8 STOP=1 PAR=N'; CFlag: KCS8; Speed: KB9600),
    (P: 'BD=115200 STOP=2'; CFlag: KCS8 or KCSTOPB; Speed: KB115200),
    (P: 'BD=4000000 FLW=RTSCTS'; CFlag: KCS8 or KCRTSCTS; Speed: KB4000000),
    (P: 'BD=50 STOP=2'; CFlag: KCS8 or KCSTOPB; Speed: KB50));
var
  I: Integer;
begin
  for I := Low(Cases) to High(Cases) do
  begin
    if not SystemKeepsRate(FPty, Cases[I].Speed) then
    begin
      { only where this system's termios cannot hold the rate (qemu-user
        7.2 above 460800): refused, the token named }
      AssertEquals(Cases[I].P + ' refused here', res_BadSetting, OpenCom(Cases[I].P));
      AssertEquals(Cases[I].P + ' the token', Copy(Cases[I].P, 1, Pos(' ', Cases[I].P) - 1),
        FChn^.ChParamError);
      Continue;
    end;
    AssertEquals(Cases[I].P + ' open', res_Ok, OpenCom(Cases[I].P));
    CheckTermios(Cases[I].P, Cases[I].CFlag, Cases[I].Speed);
    ExchangeAllByteValues(Cases[I].P);
    FChn^.ChClose;
    AssertEquals(Cases[I].P + ' close', res_Ok, FChn^.ChResult);
  end;
end;

{ Linux's pty driver forces CS8 and clears PARENB in every tcsetattr: the
  kernel's answer differs from the request, and the layer must refuse
  rather than run the line with settings nobody asked for. }
procedure TTestChnComPty.TestSettingsThePtyRefuses;
const
  Refused: array[0..4] of string = ('BIT=7 PAR=E', 'BIT=5', 'PAR=O', 'PAR=M', 'BIT=6 PAR=S STOP=2');
var
  I: Integer;
begin
  for I := Low(Refused) to High(Refused) do
  begin
    AssertEquals(Refused[I], res_BadSetting, OpenCom(Refused[I]));
    AssertEquals(Refused[I] + ' stays closed', CHS_Close, FChn^.ChReady);
  end;
  AssertEquals('and 8N1 opens', res_Ok, OpenCom('BIT=8 PAR=N'));
end;

procedure TTestChnComPty.TestXonXoffFlowControl;
var
  B: Byte;
  Msg: array[0..2] of Byte;
  Back: array[0..2] of Byte;
  Got, N: LongInt;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('FLW=XONXOFF IDL=0'));
  CheckTermios('XONXOFF', KCS8, KB9600);
  B := $13;                                 { XOFF from the peer }
  AssertTrue('xoff', FPty.MasterWriteAll(B, 1, 1000));
  Sleep(50);
  Msg[0] := Ord('a'); Msg[1] := Ord('b'); Msg[2] := Ord('c');
  FChn^.ChSend(@Msg, 3);
  AssertEquals('send accepted', res_Ok, FChn^.ChSendResult);
  Sleep(100);
  FChn^.ChSendReady;
  AssertEquals('held back by XOFF', 0, FPty.MasterRead(Back, 3));
  AssertEquals('XOFF is not data', CHS_Receiving, FChn^.ChReceiveReady);
  B := $11;                                 { XON }
  AssertTrue('xon', FPty.MasterWriteAll(B, 1, 1000));
  Got := 0;
  Deadline := GetTickCount64 + 2000;
  while (Got < 3) and (GetTickCount64 < Deadline) do
  begin
    FChn^.ChSendReady;
    N := FPty.MasterRead(Back[Got], 3 - Got);
    AssertTrue('master read', N >= 0);
    Inc(Got, N);
  end;
  AssertEquals('released by XON', 3, Got);
  AssertEquals('a', Ord('a'), Back[0]);
  AssertEquals('c', Ord('c'), Back[2]);
  AssertEquals('idle', CHS_SendReady, FChn^.ChSendReady);
end;

procedure TTestChnComPty.TestNonStandardBaud;
var
  T: tTermios2;
  E: cint;
begin
  if Drv = 'SYNSTRICT' then
  begin
    AssertEquals('12345 Bd is not in synaser''s table', res_BadSetting, OpenCom('BD=12345'));
    AssertEquals('closed', CHS_Close, FChn^.ChReady);
    Exit;
  end;
  FillChar(T, SizeOf(T), 0);
  if FpIOCtl(FPty.Master, TCGETS2, @T) <> 0 then
  begin
    E := FpGetErrno;
    { only where the device refuses termios2 (qemu-user 7.2 does not
      emulate TCGETS2): a rate outside the table cannot be set - refused,
      the token named - while the standard rates work (the other tests) }
    AssertEquals('12345 Bd without termios2', res_BadSetting, OpenCom('BD=12345'));
    AssertEquals('the token', 'BD=12345', FChn^.ChParamError);
    AssertEquals('closed', CHS_Close, FChn^.ChReady);
    AssertEquals('460800 Bd is a standard rate', res_Ok, OpenCom('BD=460800'));
    CheckTermios('460800', KCS8, $1004);
    Ignore('this system refuses termios2 (TCGETS2: errno ' + IntToStr(E) +
      '), so a rate outside the table cannot be set: refused with BD= named, checked');
  end;
  AssertEquals('12345 Bd through termios2', res_Ok, OpenCom('BD=12345'));
  FillChar(T, SizeOf(T), 0);
  AssertEquals('TCGETS2', 0, FpIOCtl(Com^.CH_Port.OsHandle, TCGETS2, @T));
  AssertEquals('BOTHER', KBOTHER, T.c_cflag and KCBAUD);
  AssertEquals('output rate', 12345, T.c_ospeed);
  AssertEquals('input rate', 12345, T.c_ispeed);
  ExchangeAllByteValues('12345 Bd');
end;

procedure TTestChnComPty.TestOneMiBBothWaysNoLoss;
const
  Total = 1024 * 1024;
var
  Sent, ToMaster, MasterSent, FromMaster, N, I, Chunk: LongInt;
  SBuf: array[0..65534] of Byte;
  MBuf: array[0..8191] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=115200 LRB=8192'));
  Sent := 0; ToMaster := 0; MasterSent := 0; FromMaster := 0;
  Chunk := 1;
  Deadline := GetTickCount64 + 60000;
  while ((ToMaster < Total) or (FromMaster < Total)) and (GetTickCount64 < Deadline) do
  begin
    { channel -> master, messages of changing size up to 65535 }
    if (Sent < Total) and (FChn^.ChSendReady = CHS_SendReady) then
    begin
      Chunk := (Chunk * 37 + 1001) mod 65535 + 1;
      N := Chunk;
      if N > Total - Sent then
        N := Total - Sent;
      for I := 0 to N - 1 do
        SBuf[I] := Pattern(Sent + I);
      FChn^.ChSend(@SBuf, N);
      AssertEquals('send result', res_Ok, FChn^.ChSendResult);
      Inc(Sent, N);
    end;
    N := FPty.MasterRead(MBuf, SizeOf(MBuf));
    AssertTrue('master read', N >= 0);
    for I := 0 to N - 1 do
      if MBuf[I] <> Pattern(ToMaster + I) then
        Fail(Format('to master: byte %d is %d, expected %d',
          [ToMaster + I, MBuf[I], Pattern(ToMaster + I)]));
    Inc(ToMaster, N);
    { master -> channel }
    if MasterSent < Total then
    begin
      N := 4096;
      if N > Total - MasterSent then
        N := Total - MasterSent;
      for I := 0 to N - 1 do
        MBuf[I] := Pattern(MasterSent + I) xor $5A;
      N := FPty.MasterWrite(MBuf, N);
      AssertTrue('master write', N >= 0);
      Inc(MasterSent, N);
    end;
    if FChn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      FChn^.ChReceive(Len);
      AssertEquals('receive result', res_Ok, FChn^.ChReceiveResult);
      for I := 0 to Len - 1 do
        if FRBuf[I] <> Pattern(FromMaster + I) xor $5A then
          Fail(Format('from master: byte %d wrong', [FromMaster + I]));
      Inc(FromMaster, Len);
    end;
  end;
  AssertEquals('1 MiB reached the master', Total, ToMaster);
  AssertEquals('1 MiB reached the channel', Total, FromMaster);
  AssertEquals('nothing lost', 0, Com^.ChLostBytes);
  AssertEquals('nothing left over', 0, FPty.MasterRead(MBuf, SizeOf(MBuf)));
end;

procedure TTestChnComPty.TestLargeWritesCompleteThroughSendReady;
const
  Msg = 65535;
var
  SBuf: array[0..Msg - 1] of Byte;
  MBuf: array[0..8191] of Byte;
  I, Messages, Got, N: LongInt;
  T0, Slowest: QWord;
  Busy: Boolean;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=9600 IDL=0'));
  for I := 0 to Msg - 1 do
    SBuf[I] := Pattern(I);
  { nobody reads the master: the pty (about 64 KiB) fills up; each ChSend
    must still return at once and ChSendReady report the rest pending }
  Messages := 0;
  Slowest := 0;
  Busy := False;
  while (Messages < 4) and not Busy do
  begin
    T0 := GetTickCount64;
    FChn^.ChSend(@SBuf, Msg);
    if GetTickCount64 - T0 > Slowest then
      Slowest := GetTickCount64 - T0;
    AssertEquals('send result', res_Ok, FChn^.ChSendResult);
    Inc(Messages);
    Busy := FChn^.ChSendReady = CHS_Sending;
  end;
  AssertTrue('a message larger than the OS buffer is pending', Busy);
  { a blocking write would wait for a reader that never comes }
  AssertTrue('ChSend did not block (' + IntToStr(Slowest) + ' ms)', Slowest < 1000);
  FChn^.ChSend(@SBuf, 10);
  AssertEquals('busy while sending', res_Busy, FChn^.ChSendResult);
  { now the master reads; ChSendReady polling completes the message }
  Got := 0;
  Deadline := GetTickCount64 + 10000;
  while (Got < Messages * Msg) and (GetTickCount64 < Deadline) do
  begin
    FChn^.ChSendReady;
    N := FPty.MasterRead(MBuf, SizeOf(MBuf));
    AssertTrue('master read', N >= 0);
    for I := 0 to N - 1 do
      if MBuf[I] <> Pattern((Got + I) mod Msg) then
        Fail(Format('byte %d wrong', [Got + I]));
    Inc(Got, N);
  end;
  AssertEquals('every byte arrived', Messages * Msg, Got);
  AssertEquals('transmitter idle', CHS_SendReady, FChn^.ChSendReady);
end;

procedure TTestChnComPty.TestMissingDevice;
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
procedure TTestChnComPty.TestNoPermission;
var
  Code: LongInt;
begin
  AssertEquals('chmod 000', 0, FpChmod(PChar(FPty.SlavePath), 0));
  Code := OpenComAsNobody('DRV=' + Drv + ' DEV=' + FPty.SlavePath, True);
  AssertTrue('child forked and exited (code ' + IntToStr(Code) + ')', Code >= 0);
  AssertTrue('child could drop root (code ' + IntToStr(Code) + ')', Code < NobodyNotDropped);
  AssertEquals('no permission, state closed', res_NoPermission, Code);
end;

procedure TTestChnComPty.TestNotATerminalIsRefused;
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
procedure TTestChnComPty.TestOtherUserCanOpenAfterClose;
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

procedure TTestChnComPty.TestDeviceInUse;
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

procedure TTestChnComPty.TestDeviceLostThenReopen;
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
procedure TTestChnComPty.TestReconnectsAfterDeviceLoss;
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
procedure TTestChnComPty.TestReconnectStopsAtARefusedSetting;
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
procedure TTestChnComPty.TestLatencyRefusedWithoutTheTimer;
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
procedure TTestChnComPty.TestLatencyWrittenWhereTheDriverHasIt;
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

{ An answer sent just before the program closes the line (icsslave: answer,
  exit) must reach the peer: 50 times open, send a frame, close at once;
  the peer reads only afterwards and finds all 50 in order. (synaser's
  close purged both directions, which on a pty drops what the master
  side has not read yet.) }
procedure TTestChnComPty.TestCloseRightAfterSendLosesNothing;
const
  Frames = 50;
  FrameLen = 64;
var
  Frame: array[0..FrameLen - 1] of Byte;
  Back: array[0..Frames * FrameLen - 1] of Byte;
  I, J, Got: Integer;
begin
  for I := 0 to Frames - 1 do
  begin
    AssertEquals('open ' + IntToStr(I), res_Ok, OpenCom(''));
    for J := 0 to FrameLen - 1 do
      Frame[J] := Pattern(I * FrameLen + J);
    FChn^.ChSend(@Frame, FrameLen);
    AssertEquals('send ' + IntToStr(I), res_Ok, FChn^.ChSendResult);
    FChn^.ChClose;
    AssertEquals('close ' + IntToStr(I), res_Ok, FChn^.ChResult);
  end;
  FillChar(Back, SizeOf(Back), 0);
  Got := FPty.MasterReadAll(Back, SizeOf(Back), 3000);
  AssertEquals('the peer got every frame (bytes)', SizeOf(Back), Got);
  for I := 0 to High(Back) do
    AssertEquals('byte ' + IntToStr(I), Pattern(I), Back[I]);
end;

type
  { the peer: reads the master side until it has Want bytes or 10 s passed }
  TMasterReader = class(TThread)
    Pty: TPtyPair;
    Want, Got: LongInt;
    Buf: array of Byte;
    procedure Execute; override;
  end;

procedure TMasterReader.Execute;
begin
  SetLength(Buf, Want);
  Got := Pty.MasterReadAll(Buf[0], Want, 10000);
end;

{ A message larger than the pty takes at once (about 22 kB on Linux):
  without the drain, ChClose discarded the part not yet handed over. }
procedure TTestChnComPty.TestCloseWaitsUntilALongMessageLeft;
const
  Len = 60000;
var
  Msg: array of Byte;
  R: TMasterReader;
  I: Integer;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=115200'));
  SetLength(Msg, Len);
  for I := 0 to Len - 1 do
    Msg[I] := Pattern(I);
  R := TMasterReader.Create(True);
  try
    R.Pty := FPty;
    R.Want := Len;
    FChn^.ChSend(@Msg[0], Len);
    AssertEquals('send', res_Ok, FChn^.ChSendResult);
    R.Start;                      { the peer starts reading now }
    FChn^.ChClose;
    AssertEquals('close', res_Ok, FChn^.ChResult);
    R.WaitFor;
    AssertEquals('every byte reached the peer', Len, R.Got);
    for I := 0 to Len - 1 do
      AssertEquals('byte ' + IntToStr(I), Msg[I], R.Buf[I]);
  finally
    R.Free;
  end;
end;

{ Nobody reads: ChClose gives up after 1.5 times the line time of what is
  pending at BD (here 460800 Bd: about 1.2 s for 38 kB left) + 250 ms. }
procedure TTestChnComPty.TestCloseIsBoundedWhenNobodyReads;
const
  Len = 60000;
var
  Msg: array of Byte;
  T0, Took: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=460800'));
  SetLength(Msg, Len);
  FillChar(Msg[0], Len, $55);
  FChn^.ChSend(@Msg[0], Len);
  AssertEquals('send', res_Ok, FChn^.ChSendResult);
  T0 := GetTickCount64;
  FChn^.ChClose;
  Took := GetTickCount64 - T0;
  AssertEquals('close', res_Ok, FChn^.ChResult);
  AssertEquals('closed', CHS_Close, FChn^.ChReady);
  AssertTrue('waited, bounded (' + IntToStr(Took) + ' ms)', (Took >= 250) and (Took < 3000));
end;

procedure TTestChnComPty.TestOverrunReportedWithoutFlowControl;
var
  Flood: array[0..999] of Byte;
  I: Integer;
  Len: Word;
begin
  AssertEquals('open', res_Ok, OpenCom('LRB=64 FLW=NONE IDL=0'));
  for I := 0 to High(Flood) do
    Flood[I] := Pattern(I);
  AssertTrue('flood', FPty.MasterWriteAll(Flood, 1000, 1000));
  Sleep(100);                       { let the kernel deliver all of it }
  AssertEquals('ready', CHS_ReceiveReady, FChn^.ChReceiveReady);
  Len := 0;
  FChn^.ChReceive(Len);
  AssertEquals('overrun reported', res_Overrun, FChn^.ChReceiveResult);
  AssertEquals('the kept bytes: LRB of them', 64, Len);
  for I := 0 to 63 do
    AssertEquals('kept byte ' + IntToStr(I), Pattern(I), FRBuf[I]);
  AssertEquals('lost bytes counted', 936, Com^.ChLostBytes);
  { reported once; later data is fine }
  Flood[0] := $AA; Flood[1] := $55;
  AssertTrue('more', FPty.MasterWriteAll(Flood, 2, 1000));
  AssertEquals('2 new bytes', 2, ChnReceiveAll(@Flood[10], 2, 2000));
  AssertEquals('first new', $AA, Flood[10]);
  AssertEquals('second new', $55, Flood[11]);
end;

procedure TTestChnComPty.TestFlowControlPausesInsteadOfDropping;
var
  Flood, Back: array[0..9999] of Byte;
  I: Integer;
begin
  AssertEquals('open', res_Ok, OpenCom('LRB=64 FLW=RTSCTS IDL=0'));
  for I := 0 to High(Flood) do
    Flood[I] := Pattern(I);
  AssertTrue('flood', FPty.MasterWriteAll(Flood, SizeOf(Flood), 1000));
  Sleep(100);
  FillChar(Back, SizeOf(Back), 0);
  AssertEquals('everything arrives', SizeOf(Flood), ChnReceiveAll(@Back, SizeOf(Back), 5000));
  for I := 0 to High(Flood) do
    AssertEquals('byte ' + IntToStr(I), Flood[I], Back[I]);
  AssertEquals('nothing lost', 0, Com^.ChLostBytes);
end;

procedure TTestChnComPty.TestRs485RefusedOnPty;
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

type
  TDelayedWriter = class(TThread)
    Pty: TPtyPair;
    DelayMs: Integer;
    WrittenAt: QWord;
    procedure Execute; override;
  end;

procedure TDelayedWriter.Execute;
var
  B: Byte;
begin
  Sleep(DelayMs);
  B := $42;
  WrittenAt := GetTickCount64;
  Pty.MasterWrite(B, 1);
end;

procedure TTestChnComPty.TestIdleWaitReturnsOnFirstByte;
var
  T0, Took: QWord;
  W: TDelayedWriter;
  St: tChState;
begin
  AssertEquals('open', res_Ok, OpenCom('IDL=400'));
  { no input: one poll waits about IDL }
  T0 := GetTickCount64;
  AssertEquals('nothing', CHS_Receiving, FChn^.ChReceiveReady);
  Took := GetTickCount64 - T0;
  AssertTrue('waited IDL (' + IntToStr(Took) + ' ms)', (Took >= 350) and (Took < 2000));
  { a byte after 100 ms ends the wait at once: with IDL=1000 (the
    largest) anything well below 1 s shows it, even on a loaded machine }
  AssertEquals('open IDL=1000', res_Ok, OpenCom('IDL=1000'));
  W := TDelayedWriter.Create(True);
  try
    W.Pty := FPty;
    W.DelayMs := 100;
    T0 := GetTickCount64;
    W.Start;
    St := FChn^.ChReceiveReady;
    Took := GetTickCount64 - T0;
    W.WaitFor;
    AssertEquals('byte seen', CHS_ReceiveReady, St);
    AssertTrue('returned on the byte (' + IntToStr(Took) + ' ms)', Took < 700);
  finally
    W.Free;
  end;
  { IDL=0 never waits }
  AssertEquals('open IDL=0', res_Ok, OpenCom('IDL=0'));
  T0 := GetTickCount64;
  AssertEquals('nothing', CHS_Receiving, FChn^.ChReceiveReady);
  AssertTrue('no wait', GetTickCount64 - T0 < 200);
end;

procedure TTestChnComPty.TestLegacyPollingLoopCpu;
var
  C0, Used, Busy: Double;
  T0: QWord;
  St: tChState;
  Polls: LongInt;
begin
  { sanity of the measurement: IDL=0 spins and must show as busy }
  AssertEquals('open IDL=0', res_Ok, OpenCom('IDL=0'));
  C0 := CpuMs;
  T0 := GetTickCount64;
  repeat
    St := FChn^.ChReceiveReady;
  until (St = CHS_ReceiveReady) or (GetTickCount64 - T0 >= 300);
  Busy := (CpuMs - C0) / 300 * 100;
  AssertTrue(Format('IDL=0 spins (%.0f %% of a core)', [Busy]), Busy > 10);
  { the legacy loop: repeat until ChReceiveReady = CHS_ReceiveReady, 2 s,
    default IDL }
  AssertEquals('open default IDL', res_Ok, OpenCom(''));
  Polls := 0;
  C0 := CpuMs;
  T0 := GetTickCount64;
  repeat
    St := FChn^.ChReceiveReady;
    Inc(Polls);
  until (St = CHS_ReceiveReady) or (GetTickCount64 - T0 >= 2000);
  Used := CpuMs - C0;
  AssertEquals('no byte came', CHS_Receiving, St);
  WriteLn(Format('info  COM %s: idle legacy loop used %.1f ms CPU in 2 s (%.2f %% of a core, %d polls)',
    [Drv, Used, Used / 20, Polls]));
  AssertTrue(Format('under 5 %% of a core: %.1f ms in 2000 ms (bound %.0f)', [Used,
    IdleCpuBound(100)]), Used < IdleCpuBound(100));
end;

function TTestChnComRtl.Drv: string;
begin
  Result := 'RTLSTRICT';
end;

{ The pty as a stand-in for a real UART: the backend with the virtual-line
  detection off, so Configure checks what the kernel took. }
type
  TStrictRtlPort = class(TChnPortUnix)
  public
    function Open(const Path: tWordString): tChResult; override;
  end;

function TStrictRtlPort.Open(const Path: tWordString): tChResult;
begin
  Result := inherited Open(Path);
  FVirtual := False;
end;

{$IFDEF CHN_SYNAPSE}
type
  TStrictSynapsePort = class(TChnPortSynapse)
  public
    function Open(const Path: tWordString): tChResult; override;
  end;

function TStrictSynapsePort.Open(const Path: tWordString): tChResult;
begin
  Result := inherited Open(Path);
  FVirtual := False;
end;
{$ENDIF}

{ Every refusal of ChOpen names its token in ChParamError, also through a
  protocol layer above, and a later good open clears it. }
procedure TTestChnComPty.TestRefusalNamesTheToken;
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
procedure TTestChnComPty.TestOpenErrorsSayTheOsReason;
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

{$IFDEF CHN_SYNAPSE}
function TTestChnComSynapse.Drv: string;
begin
  Result := 'SYNSTRICT';
end;
{$ENDIF}
{$ENDIF UNIX}

initialization
  {$IFDEF UNIX}
  RegisterPortDriver('RTLSTRICT', TStrictRtlPort);
  RegisterTest(TTestChnComRtl);
  {$IFDEF CHN_SYNAPSE}
  RegisterPortDriver('SYNSTRICT', TStrictSynapsePort);
  RegisterTest(TTestChnComSynapse);
  {$ENDIF}
  {$ENDIF}
end.
