{ Tests of ChnPty: PtyCreate gives a usable pair, and the port driver
  NAM=COM DRV=PTY creates its own pair whose slave path a second channel
  opens; bytes go both ways; a client that closes and a new one that
  opens do not end the PTY side (it is not a lost device). }
unit TestChnPty;

{$MODE OBJFPC}{$H+}

interface

uses
  BaseUnix, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnPty,
  TestSupport;

type
  TTestChnPty = class(TTestCase)
  private
    Host, Client: pChnVirt;
    function Pass(From, To_: pChnVirt; const Hex: string): string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestPtyCreate;
    procedure TestDriverPairBothWays;
    procedure TestOutlivesItsClients;
    procedure TestNoBusyLoopWithoutClient;
    procedure TestTwoPairsAtOnce;
  end;

implementation

procedure TTestChnPty.SetUp;
begin
  Host := nil;
  Client := nil;
end;

procedure TTestChnPty.TearDown;
begin
  if Client <> nil then Dispose(Client, Done);
  if Host <> nil then Dispose(Host, Done);
end;

function TTestChnPty.Pass(From, To_: pChnVirt; const Hex: string): string;
var
  D: TBytes;
  Buf: array[0..255] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  D := HexToBytes(Hex);
  From^.ChSend(@D[0], Length(D));
  AssertEquals('send', res_Ok, From^.ChSendResult);
  To_^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Result := '';
  Deadline := ChMsTick + 1000;
  while (Length(Result) < Length(Hex)) and (ChMsTick < Deadline) do
    if To_^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      To_^.ChReceive(Len);
      if Result <> '' then
        Result := Result + ' ';
      Result := Result + BytesToHex(Buf, Len);
    end;
end;

procedure TTestChnPty.TestPtyCreate;
var
  Fd, S: cint;
  Path: string;
  B: Byte;
begin
  AssertEquals('created', 0, PtyCreate(Fd, Path));
  try
    AssertEquals('/dev/pts/', Copy(Path, 1, 9));
    S := FpOpen(Path, O_RDWR or O_NOCTTY);
    AssertTrue('slave opens', S >= 0);
    B := $5A;
    AssertEquals(1, FpWrite(Fd, B, 1));
    B := 0;
    AssertEquals(1, FpRead(S, B, 1));
    AssertEquals('raw, one byte through', $5A, B);
    FpClose(S);
  finally
    FpClose(Fd);
  end;
end;

procedure TTestChnPty.TestDriverPairBothWays;
var
  Err: string;
begin
  PtyLastSlave := '';
  Host := OpenStack('COM', 'NAM=COM DRV=PTY', Err);
  AssertTrue(Err, Host <> nil);
  AssertEquals('/dev/pts/', Copy(PtyLastSlave, 1, 9));
  AssertEquals('the port knows it', PtyLastSlave,
    TChnPortPty(pChnCom(Host)^.CH_Port).SlavePath);
  Client := OpenStack('COM', 'NAM=COM DEV=' + PtyLastSlave + ' BD=19200', Err);
  AssertTrue(Err, Client <> nil);
  AssertEquals('host -> client', '10 02 10 03', Pass(Host, Client, '10 02 10 03'));
  AssertEquals('client -> host', '10 06', Pass(Client, Host, '10 06'));
end;

procedure TTestChnPty.TestOutlivesItsClients;
var
  Err, Path: string;
  D: Byte;
  I: Integer;
begin
  Host := OpenStack('COM', 'NAM=COM DRV=PTY', Err);
  AssertTrue(Err, Host <> nil);
  Path := PtyLastSlave;
  { nobody on the slave side yet: polling is no error }
  Host^.ChReceiveBuffer(@D, 1);
  Host^.ChReceiveReady;
  AssertEquals('no client yet', res_Ok, Host^.ChResult);
  Client := OpenStack('COM', 'NAM=COM DEV=' + Path, Err);
  AssertTrue(Err, Client <> nil);
  AssertEquals('first client', '01', Pass(Client, Host, '01'));
  Dispose(Client, Done);
  Client := nil;
  { the hang-up is no device loss on the pty side }
  Host^.ChReceiveBuffer(@D, 1);
  for I := 1 to 20 do
  begin
    Host^.ChReceiveReady;
    Sleep(1);
  end;
  AssertEquals('host still fine', res_Ok, Host^.ChResult);
  Client := OpenStack('COM', 'NAM=COM DEV=' + Path, Err);
  AssertTrue('second client: ' + Err, Client <> nil);
  AssertEquals('second client', '02', Pass(Client, Host, '02'));
  AssertEquals('and back', '03', Pass(Host, Client, '03'));
end;

{ After a client hung up, poll(2) on the master reports POLLHUP at once,
  every time: ChReceiveReady must still wait its IDL= instead of spinning. }
procedure TTestChnPty.TestNoBusyLoopWithoutClient;
var
  Err: string;
  D: Byte;
  S: cint;
  N: Integer;
  T0: QWord;
begin
  Host := OpenStack('COM', 'NAM=COM DRV=PTY IDL=5', Err);
  AssertTrue(Err, Host <> nil);
  S := FpOpen(PtyLastSlave, O_RDWR or O_NOCTTY);
  AssertTrue('slave opens', S >= 0);
  FpClose(S);
  Host^.ChReceiveBuffer(@D, 1);
  N := 0;
  T0 := ChMsTick;
  while ChMsTick - T0 < 100 do
  begin
    Host^.ChReceiveReady;
    Inc(N);
  end;
  AssertEquals('still no error', res_Ok, Host^.ChResult);
  { 100 ms at IDL=5 is about 20 polls; a busy loop makes 100000s }
  AssertTrue('polls in 100 ms: ' + IntToStr(N), N <= 40);
end;

{ Every open of /dev/ptmx is a new pair: a lock on the /dev/ptmx inode
  must not keep a second DRV=PTY channel (here, or in any other process:
  a second df1sim --pty, a test run beside this one) from opening. }
procedure TTestChnPty.TestTwoPairsAtOnce;
var
  Err, First: string;
begin
  Host := OpenStack('COM', 'NAM=COM DRV=PTY', Err);
  AssertTrue(Err, Host <> nil);
  First := PtyLastSlave;
  Client := OpenStack('COM', 'NAM=COM DRV=PTY', Err);
  AssertTrue('second pair: ' + Err, Client <> nil);
  AssertTrue('another slave', PtyLastSlave <> First);
end;

initialization
  RegisterTest(TTestChnPty);
end.
