{ Tests of NAM=TCP on the loopback interface: a server layer (LISTEN=) and
  a client layer in one process, raw bytes both ways, the fault table
  (name not resolved, refused, peer gone, send into a dead connection,
  reconnect by ChOpen and by RECON=), one client at a time. The RFC 2217
  side against a real server is in TestChnTcpSer2net. }
unit TestChnTcp;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnSock, Sockets,
  TestSupport;

type
  TTestChnTcp = class(TTestCase)
  private
    Srv, Cli, Cli2: pChnVirt;
    RBuf: array[0..65534] of Byte;
    function OpenServer(const Listen: string): Word;
    function OpenClient(const Extra: string): tChResult;
    function Receive(C, Other: pChnVirt; N, TimeoutMs: Integer): string;
    procedure SendText(C: pChnVirt; const S: string);
  protected
    procedure TearDown; override;
  published
    procedure TestParameters;
    procedure TestBytesBothWays;
    procedure TestListenIsLoopbackByDefault;
    procedure TestHostNotResolved;
    procedure TestConnectionRefused;
    procedure TestPeerGoneIsDeviceLostNextTick;
    procedure TestReconnectsByItself;
    procedure TestSecondClientIsTurnedAway;
  end;

implementation

procedure TTestChnTcp.TearDown;
begin
  if Cli <> nil then Dispose(Cli, Done);
  if Cli2 <> nil then Dispose(Cli2, Done);
  if Srv <> nil then Dispose(Srv, Done);
  Cli := nil;
  Cli2 := nil;
  Srv := nil;
end;

function TTestChnTcp.OpenServer(const Listen: string): Word;
var
  Err: string;
begin
  Srv := OpenStack('TCP', 'LISTEN=' + Listen, Err);
  AssertNotNull(Err, Srv);
  Result := pChnTcp(Srv)^.ChLocalPort;
  AssertTrue('the OS gave a port', Result > 0);
  Srv^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
end;

function TTestChnTcp.OpenClient(const Extra: string): tChResult;
begin
  Cli := ChnCollection^.ChNewInit('TCP');
  Cli^.ChSetParam(Extra);
  AssertEquals('params ' + Extra, res_Ok, Cli^.ChResult);
  Cli^.ChOpen;
  Result := Cli^.ChResult;
  if Result = res_Ok then
  begin
    Cli^.ChConnect;
    Cli^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  end;
end;

function TTestChnTcp.Receive(C, Other: pChnVirt; N, TimeoutMs: Integer): string;
var
  Deadline: QWord;
  Len: Word;
begin
  Result := '';
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  while (Length(Result) < N) and (GetTickCount64 < Deadline) do
  begin
    if Other <> nil then
      Other^.ChReceiveReady;          { a server takes its client on a poll }
    if C^.ChReceiveReady = CHS_ReceiveReady then
    begin
      C^.ChReceive(Len);
      SetLength(Result, Length(Result) + Len);
      Move(RBuf, Result[Length(Result) - Len + 1], Len);
    end;
  end;
end;

procedure TTestChnTcp.SendText(C: pChnVirt; const S: string);
begin
  C^.ChSend(@S[1], Length(S));
  AssertEquals('send', res_Ok, C^.ChSendResult);
  AssertTrue('sent', WaitSent(C, 2000));
end;

procedure TTestChnTcp.TestParameters;
var
  C: pChnVirt;
  Want: string;

  procedure Bad(const S: string; R: tChResult);
  begin
    C^.ChSetParam(S);
    AssertEquals(S, R, C^.ChResult);
    AssertEquals(S + ' names the token', S, C^.ChParamError);
  end;

begin
  C := ChnCollection^.ChNewInit('TCP');
  try
    Want := 'NAM=TCP HOST=plc7.example PORT=4001 CTO=500 RECON=2000 RFC2217=ON ' +
      'BD=19200 BIT=8 STOP=1 PAR=E FLW=NONE LRB=4096 LSB=65535 IDL=1';
    C^.ChSetParam('HOST=plc7.example PORT=4001 CTO=500 RECON=2000 RFC2217=ON BD=19200 PAR=E');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals(Want, C^.ChGetParam(''));
    C^.ChSetParam(C^.ChGetParam(''));
    AssertEquals('taken back', res_Ok, C^.ChResult);
    Bad('PORT=0', res_BadParam);
    Bad('PORT=65536', res_BadParam);
    Bad('HOST=', res_BadParam);
    Bad('LISTEN=::1:5000', res_BadParam);
    Bad('LISTEN=:5000', res_BadParam);
    Bad('LISTEN=host:x', res_BadParam);
    Bad('RFC2217=YES', res_BadParam);
    Bad('CTO=0', res_BadParam);
    Bad('COM=1', res_UnknownParam);
    Bad('DEV=/dev/ttyS0', res_UnknownParam);
    Bad('RS485=RTS', res_UnknownParam);
    C^.ChSetParam('LISTEN=[::1]:5000');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('LISTEN=[::1]:5000', C^.ChGetParam('LISTEN'));
    { a client without HOST= or PORT= names what is missing }
    Dispose(C, Done);
    C := ChnCollection^.ChNewInit('TCP');
    C^.ChSetParam('PORT=4001');
    C^.ChOpen;
    AssertEquals(res_BadSetting, C^.ChResult);
    AssertEquals('HOST=', C^.ChParamError);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnTcp.TestBytesBothWays;
var
  Port: Word;
  All, Got: string;
  I: Integer;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SetLength(All, 256);
  for I := 0 to 255 do
    All[I + 1] := Chr(I);
  SendText(Cli, All);
  Got := Receive(Srv, nil, 256, 3000);
  AssertEquals('client to server, every byte value', All, Got);
  AssertTrue('the server has its client', pChnTcp(Srv)^.ChHasClient);
  SendText(Srv, 'reply' + #$FF#0);
  AssertEquals('reply' + #$FF#0, Receive(Cli, nil, 7, 3000));
  { a name that resolves (to ::1 and/or 127.0.0.1): each address is tried }
  Dispose(Cli, Done);
  Cli := nil;
  Srv^.ChReceiveReady;
  AssertEquals(res_Ok, OpenClient('HOST=localhost PORT=' + IntToStr(Port)));
  SendText(Cli, 'x');
  AssertEquals('x', Receive(Srv, nil, 1, 3000));
end;

procedure TTestChnTcp.TestListenIsLoopbackByDefault;
var
  Port: Word;
begin
  Port := OpenServer('0');
  { what the socket is bound to, asked from the OS }
  AssertEquals('127.0.0.1:' + IntToStr(Port), SockLocalName(
    pChnTcp(Srv)^.ChListenHandle));
  Dispose(Srv, Done);
  Srv := nil;
  Port := OpenServer('[::1]:0');
  AssertEquals(Format('[%s]:%d', [NetAddrToStr6(StrToNetAddr6('::1')), Port]),
    SockLocalName(pChnTcp(Srv)^.ChListenHandle));
end;

procedure TTestChnTcp.TestHostNotResolved;
var
  T0: QWord;
begin
  T0 := GetTickCount64;
  AssertEquals(res_HostUnknown, OpenClient('HOST=no-such-host.invalid PORT=4001'));
  AssertEquals('HOST=no-such-host.invalid', Cli^.ChParamError);
  AssertEquals(CHS_Close, Cli^.ChReady);
  AssertTrue('bounded', GetTickCount64 - T0 < 20000);
end;

procedure TTestChnTcp.TestConnectionRefused;
var
  Port: Word;
begin
  Port := OpenServer('0');
  Srv^.ChClose;                     { now nothing listens there }
  AssertEquals(res_Refused, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  AssertEquals('PORT=' + IntToStr(Port), Cli^.ChParamError);
  AssertEquals(CHS_Close, Cli^.ChReady);
  AssertEquals('connection refused', Cli^.ChResultStr(Cli^.ChResult));
end;

procedure TTestChnTcp.TestPeerGoneIsDeviceLostNextTick;
var
  Port: Word;
  S: string;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'a');
  AssertEquals('a', Receive(Srv, nil, 1, 3000));
  Srv^.ChClose;
  Sleep(50);                        { the FIN crosses the loopback }
  Cli^.ChReceiveReady;
  AssertEquals('one tick after', res_DeviceLost, Cli^.ChResult);
  AssertEquals(res_DeviceLost, Cli^.ChReceiveResult);
  S := 'into the dead connection';
  Cli^.ChSend(@S[1], Length(S));
  AssertEquals(res_DeviceLost, Cli^.ChSendResult);
  AssertEquals('still open, as COM', CHS_Connect, Cli^.ChReady);
  { the server comes back: ChClose + ChOpen reconnects }
  Srv^.ChSetParam('LISTEN=127.0.0.1:' + IntToStr(Port));
  Srv^.ChOpen;
  AssertEquals(res_Ok, Srv^.ChResult);
  Srv^.ChConnect;
  Srv^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  Cli^.ChClose;
  Cli^.ChOpen;
  AssertEquals(res_Ok, Cli^.ChResult);
  Cli^.ChConnect;
  Cli^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  SendText(Cli, 'b');
  AssertEquals('b', Receive(Srv, nil, 1, 3000));
end;

procedure TTestChnTcp.TestReconnectsByItself;
var
  Port: Word;
  Deadline: QWord;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('RECON=100 HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'a');
  AssertEquals('a', Receive(Srv, nil, 1, 3000));
  Srv^.ChClose;
  Sleep(50);
  Cli^.ChReceiveReady;
  AssertEquals('says so', res_Reconnecting, Cli^.ChResult);
  AssertEquals('connection lost, reconnecting', Cli^.ChResultStr(Cli^.ChResult));
  { nobody listens: it keeps saying so, and a poll does not block }
  Deadline := GetTickCount64 + 300;
  while GetTickCount64 < Deadline do
    Cli^.ChReceiveReady;
  AssertEquals(res_Reconnecting, Cli^.ChResult);
  Srv^.ChSetParam('LISTEN=127.0.0.1:' + IntToStr(Port));
  Srv^.ChOpen;
  Srv^.ChConnect;
  Srv^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  Deadline := GetTickCount64 + 5000;
  while (Cli^.ChResult <> res_Ok) and (GetTickCount64 < Deadline) do
  begin
    Cli^.ChReceiveReady;
    Srv^.ChReceiveReady;
  end;
  AssertEquals('back by itself', res_Ok, Cli^.ChResult);
  SendText(Cli, 'b');
  AssertEquals('b', Receive(Srv, nil, 1, 3000));
end;

procedure TTestChnTcp.TestSecondClientIsTurnedAway;
var
  Port: Word;
  Deadline: QWord;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'one');
  AssertEquals('one', Receive(Srv, nil, 3, 3000));
  Cli2 := ChnCollection^.ChNewInit('TCP');
  Cli2^.ChSetParam('HOST=127.0.0.1 PORT=' + IntToStr(Port));
  Cli2^.ChOpen;
  AssertEquals('the OS completes the connect', res_Ok, Cli2^.ChResult);
  Cli2^.ChConnect;
  Cli2^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  Deadline := GetTickCount64 + 3000;
  while (Cli2^.ChResult = res_Ok) and (GetTickCount64 < Deadline) do
  begin
    Srv^.ChReceiveReady;
    Cli2^.ChReceiveReady;
  end;
  AssertEquals('the second is closed at once', res_DeviceLost, Cli2^.ChResult);
  SendText(Cli, 'two');
  AssertEquals('the first keeps its line', 'two', Receive(Srv, nil, 3, 3000));
end;

initialization
  RegisterTest(TTestChnTcp);
end.
