{ ComPtyCase - the fixture of the serial layer's tests on pseudo-terminal
  pairs (Unix only; TestChnCom, TestChnComOpen): a pty pair per test, a
  NAM=COM channel on its slave through the driver the subclass names
  (Drv), the kernel's termios of the open descriptor read directly (not
  through the code under test). A pty is a virtual line, which takes
  every setting as given; to test the strict path a real UART takes
  (read-back, refusals naming the token) the channel opens the pty
  through a test driver registered here (RTLSTRICT, SYNSTRICT with
  CHN_SYNAPSE) that is the backend with the virtual-line detection
  switched off. }
unit ComPtyCase;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, BaseUnix, TermIO, PtyPair, ChnUnix, ChnPortUnix,
  {$IFDEF CHN_SYNAPSE}ChnPortSynapse,{$ENDIF}
  ComPtySupport, ChnTypes, ChnVirt, ChnPort, ChnCom, TestSupport;

type
  TComPtyCase = class(TTestCase)
  protected
    FPty: TPtyPair;
    FChn: pChnVirt;
    FRBuf: array[0..65534] of Byte;
    { the port driver: RTLSTRICT, SYNSTRICT }
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
  end;

{ Byte I of the tests' data pattern. }
function Pattern(I: LongInt): Byte; inline;
{ Whether termios on this system keeps the rate code Code: qemu-user 7.2
  translates only codes up to B460800 and drops the rest. Asked of the
  pty master, not through the code under test. }
function SystemKeepsRate(Pty: TPtyPair; Code: Cardinal): Boolean;

implementation

function Pattern(I: LongInt): Byte; inline;
begin
  Result := Byte((I * 7) xor (I shr 8) xor (I shr 16));
end;

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


procedure TComPtyCase.SetUp;
begin
  FPty := TPtyPair.Create;
  FChn := nil;
end;

procedure TComPtyCase.TearDown;
begin
  if FChn <> nil then
    Dispose(FChn, Done);
  FChn := nil;
  FPty.Free;
end;

function TComPtyCase.Com: pChnCom;
begin
  Result := pChnCom(FChn);
end;

function TComPtyCase.OpenCom(const Extra: string): tChResult;
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

function TComPtyCase.ChnReceiveAll(Dst: PByte; N: LongInt; TimeoutMs: LongInt): LongInt;
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

procedure TComPtyCase.CheckTermios(const What: string; CFlag: Cardinal; Speed: Cardinal);
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
procedure TComPtyCase.ExchangeAllByteValues(const What: string);
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

initialization
  RegisterPortDriver('RTLSTRICT', TStrictRtlPort);
  {$IFDEF CHN_SYNAPSE}
  RegisterPortDriver('SYNSTRICT', TStrictSynapsePort);
  {$ENDIF}
end.
