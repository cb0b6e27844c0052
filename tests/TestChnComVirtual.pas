{ Tests of the virtual line (ChnCom on a pty slave, a socat link to one,
  DRV=PTY) on the real port drivers (RTL, and SYNAPSE when built in): a
  virtual line takes every setting as given, and the pty itself is left
  raw, as the kernel's termios of the open descriptor shows. Unix only. }
unit TestChnComVirtual;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, BaseUnix, TermIO, Process,
  PtyPair, ChnTypes, ChnVirt, ChnCom, ChnPty, TestSupport, BinSupport, StackCase;

type
  { The virtual line: a pty slave, a socat link to one, DRV=PTY, on the
    real drivers (RTL, and SYNAPSE when built in). }
  TTestChnComVirtual = class(TStackCase)
  private
    FPty: TPtyPair;
    FBuf: array[0..1023] of Byte;
    function Open(const Params: string): pChnVirt;
    procedure Pass(A, B: pChnVirt; const What: string);
    procedure TakesAsGiven(const Drv: string);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestPtySlaveTakesSettingsAsGiven;
    procedure TestDrvPtyTakesSettingsAsGiven;
    procedure TestSocatLinkIsVirtual;
    procedure TestManualStringOnPty;
    procedure TestExamplesPrintTheToken;
  end;

implementation

uses
  ComPtySupport;

procedure TTestChnComVirtual.SetUp;
begin
  FPty := TPtyPair.Create;
end;

procedure TTestChnComVirtual.TearDown;
begin
  CloseStacks;
  FPty.Free;
  inherited TearDown;
end;

function TTestChnComVirtual.Open(const Params: string): pChnVirt;
begin
  Result := Stack('COM', Params);
  Result^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
end;

{ All 256 byte values (XON, XOFF, DLE among them) from A to B, unchanged. }
procedure TTestChnComVirtual.Pass(A, B: pChnVirt; const What: string);
var
  Msg: array[0..255] of Byte;
  Got, I: LongInt;
  Len: Word;
  Deadline: QWord;
begin
  for I := 0 to 255 do
    Msg[I] := I;
  AssertTrue(What + ': idle', WaitSent(A, 2000));
  A^.ChSend(@Msg, 256);
  AssertEquals(What + ': send', res_Ok, A^.ChSendResult);
  Got := 0;
  Deadline := GetTickCount64 + 3000;
  while (Got < 256) and (GetTickCount64 < Deadline) do
  begin
    A^.ChSendReady;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      B^.ChReceiveBuffer(@FBuf[Got], SizeOf(FBuf) - Got);
      B^.ChReceive(Len);
      Inc(Got, Len);
    end;
  end;
  AssertEquals(What + ': every byte arrives', 256, Got);
  for I := 0 to 255 do
    AssertEquals(What + ': byte ' + IntToStr(I), I, FBuf[I]);
end;

procedure TTestChnComVirtual.TakesAsGiven(const Drv: string);
const
  Cases: array[0..3] of string = (
    'BD=19200 BIT=7 STOP=2 PAR=E FLW=NONE',
    'BD=12345 BIT=5 STOP=1 PAR=M FLW=RTSCTS',
    'BD=4000000 BIT=6 STOP=2 PAR=S FLW=XONXOFF',
    'BD=50 BIT=8 STOP=1 PAR=O FLW=NONE');
var
  I: Integer;
  C: pChnVirt;
  T: Termios;
  Line: string;
begin
  for I := Low(Cases) to High(Cases) do
  begin
    C := Stack('COM', 'NAM=COM DRV=' + Drv + ' DEV=' + FPty.SlavePath + ' ' + Cases[I]);
    Line := C^.ChGetParam('BD') + ' ' + C^.ChGetParam('BIT') + ' ' +
      C^.ChGetParam('STOP') + ' ' + C^.ChGetParam('PAR') + ' ' + C^.ChGetParam('FLW');
    AssertEquals(Drv + ': reported as given', Cases[I], Line);
    AssertTrue(Drv + ': virtual', pChnCom(C)^.CH_Port.VirtualLine);
    { the pty itself is left raw, 8 bits, no parity, no flow control }
    AssertEquals('tcgetattr', 0, TCGetAttr(pChnCom(C)^.CH_Port.OsHandle, T));
    AssertEquals(Cases[I] + ': CS8, no PARENB/CSTOPB/CRTSCTS', KCS8,
      T.c_cflag and (KCSIZE or KPARENB or KCSTOPB or KCRTSCTS or KCMSPAR));
    AssertEquals(Cases[I] + ': no IXON/IXOFF', 0, T.c_iflag and (IXON or IXOFF));
    CloseStacks;
  end;
end;

procedure TTestChnComVirtual.TestPtySlaveTakesSettingsAsGiven;
begin
  TakesAsGiven('RTL');
  {$IFDEF CHN_SYNAPSE}
  TakesAsGiven('SYNAPSE');
  {$ENDIF}
end;

procedure TTestChnComVirtual.TestDrvPtyTakesSettingsAsGiven;
var
  Host, Client: pChnVirt;
begin
  Host := Open('NAM=COM DRV=PTY BD=9600 BIT=7 PAR=E STOP=2 FLW=XONXOFF');
  AssertEquals('as given', 'PAR=E', Host^.ChGetParam('PAR'));
  AssertEquals('FLW=XONXOFF', Host^.ChGetParam('FLW'));
  Client := Open('NAM=COM DEV=' + PtyLastSlave + ' BD=9600 BIT=7 PAR=E STOP=2 FLW=XONXOFF');
  Pass(Host, Client, 'host -> client');
  Pass(Client, Host, 'client -> host');
end;

{ socat's pty link= is a symlink to /dev/pts/N: a virtual line as well }
procedure TTestChnComVirtual.TestSocatLinkIsVirtual;
var
  P: TProcess;
  Dir, A, B: string;
  Deadline: QWord;
  CA, CB: pChnVirt;
begin
  if FileSearch('socat', GetEnvironmentVariable('PATH')) = '' then
    Ignore('socat is not installed (Debian package socat): the socat link is not checked');
  Dir := GetTempDir(False) + 'chn-socat-' + IntToStr(FpGetPid);
  CreateDir(Dir);
  A := Dir + '/ttyA';
  B := Dir + '/ttyB';
  P := TProcess.Create(nil);
  try
    P.Executable := FileSearch('socat', GetEnvironmentVariable('PATH'));
    P.Parameters.Add('pty,raw,echo=0,link=' + A);
    P.Parameters.Add('pty,raw,echo=0,link=' + B);
    P.Execute;
    Deadline := GetTickCount64 + 5000;
    while not (FileExists(A) and FileExists(B)) and (GetTickCount64 < Deadline) do
      Sleep(10);
    AssertTrue('socat made its links', FileExists(A) and FileExists(B));
    { the manuals' line settings on both ends }
    CA := Open('NAM=COM DEV=' + A + ' BD=9600 BIT=8 STOP=1 PAR=E IRQ=4 LRB=1000');
    CB := Open('NAM=COM DEV=' + B + ' BD=9600 BIT=8 STOP=1 PAR=E IRQ=4 LRB=1000');
    AssertEquals('PAR=E', CA^.ChGetParam('PAR'));
    Pass(CA, CB, 'A -> B');
    Pass(CB, CA, 'B -> A');
  finally
    P.Terminate(0);
    P.WaitOnExit;
    P.Free;
    DeleteFile(A);
    DeleteFile(B);
    RemoveDir(Dir);
  end;
end;

{ The manual's whole parameter string, pointed at a pty by DEV= }
procedure TTestChnComVirtual.TestManualStringOnPty;
var
  Host, Client: pChnVirt;
begin
  Host := Open('NAM=COM DRV=PTY');
  Client := Stack('DF1',
    'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON NAM=COM COM=1 IRQ=4 BD=9600 ' +
    'BIT=8 STOP=1 PAR=E LRB=1000 DEV=' + PtyLastSlave);
  AssertEquals('', Client^.ChParamError);
end;

{ What the example programs print when ChOpen refuses: the token, whichever
  way they open (plain ChOpen, DF1OpenStack). Expected texts by hand. }
procedure TTestChnComVirtual.TestExamplesPrintTheToken;
var
  Output: string;
begin
  AssertTrue(BinPath('comraw') + ' missing (make examples)', FileExists(BinPath('comraw')));
  AssertEquals('comraw exit code', 1, RunBin('comraw', ['DEV=/dev/null BD=9600'], 10000, Output));
  AssertTrue('comraw: ' + Output, Pos('comraw: device refuses the setting (DEV=/dev/null): ' +
    'Inappropriate ioctl for device', Output) > 0);
  { the OS's reason through DF1 on top, and a bad value with what it takes }
  RunBin('df1read', ['N7:0', '1', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/chn-no-such-tty'],
    10000, Output);
  AssertTrue('df1read: ' + Output, Pos('device cannot be opened (DEV=/dev/chn-no-such-tty): ' +
    'No such file or directory', Output) > 0);
  RunBin('df1read', ['N7:0', '1', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/tmp BD=abc'], 10000, Output);
  AssertTrue('df1read: ' + Output, Pos('df1read: bad parameter string: bad parameter (BD=abc): ' +
    'a number 50..4000000', Output) > 0);
  { a pty has no RS-485: refused, and named, through DF1 on top }
  RunBin('df1read', ['N7:0', '1', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + FPty.SlavePath +
    ' RS485=KERNEL'], 10000, Output);
  AssertTrue('df1read: ' + Output, Pos('device refuses the setting (RS485=KERNEL)', Output) > 0);
  RunBin('ft12master', ['NAM=FT1_2 MAS=MASTER NAM=COM DEV=/dev/null', '100'], 10000, Output);
  AssertTrue('ft12master: ' + Output, Pos('(DEV=/dev/null)', Output) > 0);
end;

initialization
  RegisterTest(TTestChnComVirtual);
end.
