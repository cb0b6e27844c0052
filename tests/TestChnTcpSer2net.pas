{ NAM=TCP against a real serial device server: Debian's ser2net on a pty
  pair the test creates (tests/support/Ser2netRun), raw and with RFC 2217.
  What reaches the far end is read from the pty master and its termios, not
  through the code under test. Every test is skipped (counted, with the
  reason) when ser2net is not installed. Unix only: ser2net and ptys. }
unit TestChnTcpSer2net;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, BaseUnix, TermIO,
  ChnTypes, ChnVirt, ChnTcp, PtyPair, Ser2netRun, BinSupport;

type
  TTestChnTcpSer2net = class(TTestCase)
  private
    FPty: TPtyPair;
    FSer: TSer2net;
    FCli: pChnVirt;
    FRBuf: array[0..65534] of Byte;
    procedure NeedSer2net;
    procedure StartOnPty(const Line: string);
    function OpenClient(const Params: string): tChResult;
    procedure CloseClient;
    procedure WaitDeviceReleased;
    function MasterGets(N: LongInt; TimeoutMs: LongInt): string;
    procedure ClientSends(const S: string);
    procedure OneMiBBothWays(const Params: string);
    procedure Df1Examples(const TcpParams: string);
  protected
    procedure TearDown; override;
  published
    procedure TestDf1EchoAndReadRaw;
    procedure TestDf1EchoAndReadRfc2217;
    procedure TestRfc2217BaudReachesThePty;
    procedure TestRfc2217OneMiBWithIacBothWays;
    procedure TestRawOneMiBBothWays;
    procedure TestRfc2217ModemLinesAndPurge;
    procedure TestKilledMidSessionThenReopened;
    procedure TestKilledMidSessionReconnectsByItself;
  end;

implementation

const
  CBaudMask = $100F;                { Linux CBAUD: the rate code in c_cflag }

procedure TTestChnTcpSer2net.NeedSer2net;
begin
  if TSer2net.Path = '' then
    Ignore('ser2net is not installed (Debian: apt-get install ser2net; .ci/run does)');
end;

procedure TTestChnTcpSer2net.StartOnPty(const Line: string);
begin
  NeedSer2net;
  FPty := TPtyPair.Create;
  FSer := TSer2net.Create(FPty.SlavePath, Line);
end;

procedure TTestChnTcpSer2net.TearDown;
begin
  CloseClient;
  FreeAndNil(FSer);                 { stops it by PID, removes its folder }
  FreeAndNil(FPty);
end;

{ Wait (at most 3 s) until no program holds the pty's slave side: the
  master then reports a hang-up. }
procedure TTestChnTcpSer2net.WaitDeviceReleased;
var
  P: TPollFd;
  Deadline: QWord;
begin
  if FPty = nil then
    Exit;
  Deadline := GetTickCount64 + 3000;
  repeat
    P.fd := FPty.Master;
    P.events := POLLIN;
    P.revents := 0;
    FpPoll(@P, 1, 0);
    if P.revents and POLLHUP <> 0 then
      Exit;
    Sleep(10);
  until GetTickCount64 > Deadline;
end;

{ ser2net frees the device of a session a moment after the client left; a
  connection before that is told "Port's device already in use" and closed
  (res_CannotOpen during an RFC 2217 open). Like a user, try again. }
function TTestChnTcpSer2net.OpenClient(const Params: string): tChResult;
var
  Deadline: QWord;
begin
  CloseClient;
  WaitDeviceReleased;
  FCli := ChnCollection^.ChNewInit('TCP');
  FCli^.ChSetParam(Params);
  AssertEquals('parameters ' + Params, res_Ok, FCli^.ChResult);
  Deadline := GetTickCount64 + 3000;
  repeat
    FCli^.ChOpen;
    Result := FCli^.ChResult;
    if (Result <> res_CannotOpen) or (GetTickCount64 > Deadline) then
      Break;
    Sleep(50);
  until False;
  if Result = res_Ok then
  begin
    FCli^.ChConnect;
    FCli^.ChReceiveBuffer(@FRBuf, SizeOf(FRBuf));
  end;
end;

procedure TTestChnTcpSer2net.CloseClient;
begin
  if FCli <> nil then
    Dispose(FCli, Done);
  FCli := nil;
end;

function TTestChnTcpSer2net.MasterGets(N: LongInt; TimeoutMs: LongInt): string;
var
  Deadline: QWord;
  B: array[0..4095] of Byte;
  Got: LongInt;
begin
  Result := '';
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  while (Length(Result) < N) and (GetTickCount64 < Deadline) do
  begin
    FCli^.ChSendReady;
    Got := FPty.MasterRead(B, SizeOf(B));
    if Got > 0 then
    begin
      SetLength(Result, Length(Result) + Got);
      Move(B, Result[Length(Result) - Got + 1], Got);
    end
    else
      Sleep(1);
  end;
end;

procedure TTestChnTcpSer2net.ClientSends(const S: string);
begin
  FCli^.ChSend(@S[1], Length(S));
  AssertEquals('send result', res_Ok, FCli^.ChSendResult);
end;

{ 1 MiB each way, a quarter of the bytes $FF (Telnet's IAC), the rest
  random; sent in chunks while the other end reads, compared whole. }
procedure TTestChnTcpSer2net.OneMiBBothWays(const Params: string);
const
  Total = 1 shl 20;
var
  Data, Got: array of Byte;
  I, Sent, Recv, N, Chunk: LongInt;
  Len: Word;
  Deadline: QWord;
begin
  SetLength(Data, Total);
  SetLength(Got, Total);
  RandSeed := 2217;
  for I := 0 to Total - 1 do
    if Random(4) = 0 then
      Data[I] := $FF
    else
      Data[I] := Random(256);
  AssertEquals('step 1 '+ FSer.LogText, res_Ok, OpenClient(Params));
  { client -> ser2net -> pty }
  Sent := 0;
  Recv := 0;
  Deadline := GetTickCount64 + 60000;
  while (Recv < Total) and (GetTickCount64 < Deadline) do
  begin
    if (Sent < Total) and (FCli^.ChSendReady = CHS_SendReady) then
    begin
      Chunk := Total - Sent;
      if Chunk > 32768 then
        Chunk := 32768;
      FCli^.ChSend(@Data[Sent], Chunk);
      AssertEquals('send', res_Ok, FCli^.ChSendResult);
      Inc(Sent, Chunk);
    end;
    N := FPty.MasterRead(Got[Recv], Total - Recv);
    if N > 0 then
      Inc(Recv, N)
    else
      FCli^.ChReceiveReady;         { waits IDL ms at most }
  end;
  AssertEquals('bytes at the pty', Total, Recv);
  AssertTrue('unchanged to the pty', CompareByte(Data[0], Got[0], Total) = 0);
  { pty -> ser2net -> client }
  FillChar(Got[0], Total, 0);
  Sent := 0;
  Recv := 0;
  Deadline := GetTickCount64 + 60000;
  while (Recv < Total) and (GetTickCount64 < Deadline) do
  begin
    if Sent < Total then
    begin
      N := FPty.MasterWrite(Data[Sent], Total - Sent);
      if N > 0 then
        Inc(Sent, N);
    end;
    if FCli^.ChReceiveReady = CHS_ReceiveReady then
    begin
      FCli^.ChReceive(Len);
      AssertEquals('receive', res_Ok, FCli^.ChReceiveResult);
      AssertTrue('not more than sent', Recv + Len <= Total);
      Move(FRBuf, Got[Recv], Len);
      Inc(Recv, Len);
    end;
  end;
  AssertEquals('bytes at the client', Total, Recv);
  AssertTrue('unchanged to the client', CompareByte(Data[0], Got[0], Total) = 0);
end;

{ An example program through ser2net; run again when ser2net had not yet
  freed the device of the previous one (see OpenClient). }
function RunExample(const Name: string; const Args: array of string; out Output: string): Integer;
var
  I: Integer;
begin
  for I := 1 to 5 do
  begin
    Result := RunBin(Name, Args, 20000, Output);
    if (Result = 0) or ((Pos('cannot be opened', Output) = 0) and
      (Pos('device lost', Output) = 0)) then
      Exit;
    Sleep(200);
  end;
end;

procedure TTestChnTcpSer2net.Df1Examples(const TcpParams: string);
var
  Sim: TProcess;
  Pty, Output: string;
  Code: Integer;
  Str: TStringList;
begin
  NeedSer2net;
  Sim := StartSimPty(['--timeout=20', '--quiet'], Pty);
  try
    AssertTrue('df1sim printed its pty', Pty <> '');
    FSer := TSer2net.Create(Pty, '19200n81');
    Str := TStringList.Create;
    try
      Str.Delimiter := ' ';
      Str.StrictDelimiter := True;
      Str.DelimitedText := 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=TCP HOST=127.0.0.1 ' +
        StringReplace(StringReplace(TcpParams, '<raw>', IntToStr(FSer.RawPort), []),
          '<rfc>', IntToStr(FSer.RfcPort), []);
      Code := RunExample('df1echo', Str.ToStringArray, Output);
      AssertEquals('df1echo exit code:'#10 + Output + FSer.LogText, 0, Code);
      AssertTrue('Ok:'#10 + Output, Pos(#10'Ok'#10, Output) > 0);
      AssertTrue('the echo came back', Pos(
        'master <- reply CMD=$46 STS=$00 TNS=0 data: 41 68 6F 6A', Output) > 0);
      Str.Insert(0, '10');
      Str.Insert(0, 'N7:0');
      Code := RunExample('df1read', Str.ToStringArray, Output);
      AssertEquals('df1read exit code:'#10 + Output, 0, Code);
      AssertTrue('N7:9 read:'#10 + Output, Pos('N7:9 = 90', Output) > 0);
      AssertTrue('N7:0 read', Pos('N7:0 = 0', Output) > 0);
    finally
      Str.Free;
    end;
  finally
    StopProcess(Sim);
  end;
end;

procedure TTestChnTcpSer2net.TestDf1EchoAndReadRaw;
begin
  Df1Examples('PORT=<raw>');
end;

procedure TTestChnTcpSer2net.TestDf1EchoAndReadRfc2217;
begin
  Df1Examples('PORT=<rfc> RFC2217=ON BD=19200');
end;

procedure TTestChnTcpSer2net.TestRfc2217BaudReachesThePty;
var
  Tio: Termios;
begin
  StartOnPty('9600n81');
  AssertEquals('step 2 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON BD=19200',
    [FSer.RfcPort])));
  { the far end's speed, from the kernel: tcgetattr on the master reads
    the slave's termios, which ser2net set }
  AssertEquals(0, TCGetAttr(FPty.Master, Tio));
  AssertEquals('B19200 at the pty', B19200, (Tio.c_cflag and CBaudMask));
  ClientSends('x');
  AssertEquals('x', MasterGets(1, 3000));
  AssertEquals('step 3 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON BD=38400 STOP=2',
    [FSer.RfcPort])));
  AssertEquals(0, TCGetAttr(FPty.Master, Tio));
  AssertEquals('B38400 at the pty', B38400, (Tio.c_cflag and CBaudMask));
  AssertTrue('two stop bits at the pty', Tio.c_cflag and CSTOPB <> 0);
  { raw: the server's own 9600 stays, BD= is only reported }
  AssertEquals('step 4 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d BD=19200',
    [FSer.RawPort])));
  ClientSends('y');
  AssertEquals('y', MasterGets(1, 3000));
  AssertEquals(0, TCGetAttr(FPty.Master, Tio));
  AssertEquals('raw leaves B9600', B9600, (Tio.c_cflag and CBaudMask));
end;

procedure TTestChnTcpSer2net.TestRfc2217OneMiBWithIacBothWays;
begin
  StartOnPty('115200n81');
  OneMiBBothWays(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON BD=115200 LRB=65536',
    [FSer.RfcPort]));
end;

procedure TTestChnTcpSer2net.TestRawOneMiBBothWays;
begin
  StartOnPty('115200n81');
  OneMiBBothWays(Format('HOST=127.0.0.1 PORT=%d LRB=65536', [FSer.RawPort]));
end;

procedure TTestChnTcpSer2net.TestRfc2217ModemLinesAndPurge;
var
  Len: Word;
  S: string;
  Deadline: QWord;
begin
  StartOnPty('9600n81');
  AssertEquals('step 5 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON',
    [FSer.RfcPort])));
  AssertEquals('DTR by RFC 2217', res_Ok, pChnTcp(FCli)^.ChSetDtr(True));
  AssertEquals('RTS by RFC 2217', res_Ok, pChnTcp(FCli)^.ChSetRts(False));
  { bytes from the pty, flushed: what arrives afterwards is only the new }
  AssertTrue(FPty.MasterWriteAll(PChar('old')^, 3, 1000));
  Sleep(200);
  FCli^.ChReceiveFlush;
  { the purge reaches ser2net while we go on polling: nothing comes }
  Deadline := GetTickCount64 + 300;
  while GetTickCount64 < Deadline do
    AssertTrue('nothing after the flush', FCli^.ChReceiveReady <> CHS_ReceiveReady);
  AssertTrue(FPty.MasterWriteAll(PChar('new')^, 3, 1000));
  S := '';
  Deadline := GetTickCount64 + 3000;
  while (Length(S) < 3) and (GetTickCount64 < Deadline) do
    if FCli^.ChReceiveReady = CHS_ReceiveReady then
    begin
      FCli^.ChReceive(Len);
      SetLength(S, Length(S) + Len);
      Move(FRBuf, S[Length(S) - Len + 1], Len);
    end;
  AssertEquals('the flushed bytes are gone', 'new', S);
  AssertEquals(res_Ok, FCli^.ChResult);
  { raw TCP carries no modem lines: said so }
  AssertEquals('step 6 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d', [FSer.RawPort])));
  AssertEquals(res_BadSetting, pChnTcp(FCli)^.ChSetRts(True));
end;

procedure TTestChnTcpSer2net.TestKilledMidSessionThenReopened;
var
  T0: QWord;
begin
  StartOnPty('9600n81');
  AssertEquals('step 7 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d', [FSer.RawPort])));
  ClientSends('a');
  AssertEquals('a', MasterGets(1, 3000));
  FSer.Stop(SIGKILL);
  Sleep(100);                       { the kernel closes its sockets }
  T0 := GetTickCount64;
  FCli^.ChReceiveReady;
  AssertEquals('lost within one tick', res_DeviceLost, FCli^.ChResult);
  AssertTrue('no hang', GetTickCount64 - T0 < 500);
  FCli^.ChSend(PChar('z'), 1);
  AssertEquals('send into the dead connection', res_DeviceLost, FCli^.ChSendResult);
  FSer.Start;
  FCli^.ChClose;
  FCli^.ChOpen;
  AssertEquals('reopened: ' + FCli^.ChParamError, res_Ok, FCli^.ChResult);
  FCli^.ChConnect;
  ClientSends('b');
  AssertEquals('b', MasterGets(1, 3000));
end;

procedure TTestChnTcpSer2net.TestKilledMidSessionReconnectsByItself;
var
  Deadline: QWord;
  Tio: Termios;
begin
  StartOnPty('9600n81');
  AssertEquals('step 8 '+ FSer.LogText, res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON RECON=200 BD=19200',
    [FSer.RfcPort])));
  ClientSends('a');
  AssertEquals('a', MasterGets(1, 3000));
  FSer.Stop(SIGKILL);
  Sleep(100);
  FCli^.ChReceiveReady;
  AssertEquals(res_Reconnecting, FCli^.ChResult);
  FSer.Start;
  Deadline := GetTickCount64 + 10000;
  while (FCli^.ChResult <> res_Ok) and (GetTickCount64 < Deadline) do
    FCli^.ChReceiveReady;
  AssertEquals('reconnected by itself', res_Ok, FCli^.ChResult);
  ClientSends('c');
  AssertEquals('c', MasterGets(1, 3000));
  AssertEquals(0, TCGetAttr(FPty.Master, Tio));
  AssertEquals('BD=19200 set again on the new connection', B19200, (Tio.c_cflag and CBaudMask));
  FCli^.ChReceiveReady;
  AssertEquals('the settings went again and were accepted', res_Ok, FCli^.ChResult);
end;

initialization
  RegisterTest(TTestChnTcpSer2net);
end.
