{ Tests of NAM=TCP on the loopback interface: a server layer (LISTEN=) and
  a client layer in one process, raw bytes both ways, the fault table
  (name not resolved, refused, peer gone, send into a dead connection,
  reconnect by ChOpen and by RECON=), one client at a time. The RFC 2217
  side against a real server is in TestChnTcpSer2net. }
unit TestChnTcp;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, {$IFDEF LINUX}BaseUnix, Linux,{$ENDIF} ChnPort, ChnPortTcp, ChnTcp, ChnLoop, ChnSock, ChnWait, Sockets,
  Process, TestSupport, BinSupport, ChildLine;

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
    {$IFDEF LINUX}
    procedure TestConnectTimeout;
    {$ENDIF}
    procedure TestPeerGoneIsDeviceLostNextTick;
    procedure TestPeerResetIsDeviceLostNextTick;
    procedure TestReconnectsByItself;
    procedure TestSecondClientIsTurnedAway;
    procedure TestKickAndIdleParameters;
    procedure TestKickTakesTheLineFromASilentSquatter;
    procedure TestIdleClosesASilentSquatter;
    procedure TestIdleClosesATricklingSquatter;
    procedure TestRapidReconnectsAreNotDelayed;
    procedure TestDf1simListenOutlivesASquatter;
    procedure TestFullRingHoldsTheSenderBack;
    procedure TestRfc2217ServerChangesTheRate;
    procedure TestRfc2217ServerRefusesTheOption;
    procedure TestRfc2217ServerSilent;
    procedure TestRfc2217DataNotifyAndPurgeOnTheWire;
    procedure TestRfc2217FloodWhileNegotiatingIsCapped;
    procedure TestRfc2217UnclosedSubnegotiationIsNamed;
    procedure TestRfc2217DataKeptWhileNegotiatingEndsTheWait;
    procedure TestClientIsInTheSharedWait;
    procedure TestServerIsInTheSharedWait;   { epoll / one WSA event }
    {$IFDEF LINUX}
    procedure TestIdlePollingLoopCpu;
    procedure TestNoDelayAndKeepAlive;
    {$ENDIF}
  end;

  { Sends one byte through a channel after DelayMs, from its own thread. }
  TSendLater = class(TThread)
    Chn: pChnVirt;
    DelayMs: Integer;
    procedure Execute; override;
  end;

  { A scripted RFC 2217 server on a thread: the bytes it expects and sends
    are written here by hand from RFC 854 / RFC 2217, not produced by the
    codec under test. }
  { smFlood: 1 MiB of data before its DO COM-PORT-OPTION }
  TScriptMode = (smHonest, smChangeBaud, smRefuse, smSilent, smFlood);
  TScriptServer = class(TThread)
  private
    FListen, FConn: tSock;
    FMode: TScriptMode;
    FLock: TRTLCriticalSection;
    FSeen: AnsiString;              { every byte the client sent }
    FToSend: AnsiString;            { bytes the test wants sent now }
    procedure Put(const S: AnsiString);
  protected
    procedure Execute; override;
  public
    Port: Word;
    constructor Create(Mode: TScriptMode);
    destructor Destroy; override;
    function Seen: AnsiString;
    procedure Send(const S: AnsiString);
  end;

implementation

function RawConnect(Port: Word; Ms: Integer): tSock; forward;

type
  { after DelayMs: connect to Port and send Text (Sock is then that
    connection), or - with Sock set - send Text on it, or close it when
    Text is '' }
  TRawLater = class(TThread)
    Port: Word;
    Sock: tSock;
    Text: AnsiString;
    DelayMs: Integer;
    procedure Execute; override;
  end;

procedure TRawLater.Execute;
var
  Done: LongInt;
begin
  Sleep(DelayMs);
  if Sock = NoSock then
    Sock := RawConnect(Port, 2000);
  if Text = '' then
    SockClose(Sock)
  else if Sock <> NoSock then
    SockSend(Sock, Text[1], Length(Text), Done);
end;

{ A TRawLater, started. }
function RawLater(Port: Word; Sock: tSock; const Text: AnsiString): TRawLater;
begin
  Result := TRawLater.Create(True);
  Result.Port := Port;
  Result.Sock := Sock;
  Result.Text := Text;
  Result.DelayMs := 100;
  Result.Start;
end;

procedure TSendLater.Execute;
var
  B: Byte;
begin
  Sleep(DelayMs);
  B := $42;
  Chn^.ChSend(@B, 1);
end;

function Hex(const S: AnsiString): string;
var
  I: Integer;
begin
  Result := '';
  for I := 1 to Length(S) do
  begin
    if I > 1 then
      Result := Result + ' ';
    Result := Result + IntToHex(Ord(S[I]), 2);
  end;
end;

{ What the script server saw after Mark, once N bytes came (3 s at most). }
function SeenAfter(Srv: TScriptServer; Mark, N: Integer): AnsiString;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + 3000;
  repeat
    Result := Copy(Srv.Seen, Mark + 1, MaxInt);
    if Length(Result) >= N then
      Exit;
    Sleep(5);
  until GetTickCount64 > Deadline;
end;

function Bytes(const HexText: string): AnsiString;
var
  B: TBytes;
begin
  B := HexToBytes(HexText);
  SetLength(Result, Length(B));
  if Length(B) > 0 then
    Move(B[0], Result[1], Length(B));
end;

const
  FloodLen = 1 shl 20;

{ What smFlood pushes: no $FF, so it is data byte for byte. }
function FloodData: AnsiString;
var
  I: Integer;
begin
  SetLength(Result, FloodLen);
  for I := 1 to FloodLen do
    Result[I] := Chr(1 + I mod 200);
end;

constructor TScriptServer.Create(Mode: TScriptMode);
var
  A: tSockAddrs;
  N: LongInt;
begin
  FMode := Mode;
  InitCriticalSection(FLock);
  SockResolve('127.0.0.1', 0, True, A, N);
  if SockListen(A[0], FListen) <> seOk then
    raise Exception.Create('script server: cannot listen');
  Port := SockLocalPort(FListen);
  FConn := NoSock;
  inherited Create(False);
end;

destructor TScriptServer.Destroy;
begin
  Terminate;
  WaitFor;
  SockClose(FConn);
  SockClose(FListen);
  DoneCriticalSection(FLock);
  inherited Destroy;
end;

function TScriptServer.Seen: AnsiString;
begin
  EnterCriticalSection(FLock);
  Result := FSeen;
  LeaveCriticalSection(FLock);
end;

procedure TScriptServer.Send(const S: AnsiString);
begin
  EnterCriticalSection(FLock);
  FToSend := FToSend + S;
  LeaveCriticalSection(FLock);
end;

procedure TScriptServer.Put(const S: AnsiString);
var
  Done, P: LongInt;
begin
  P := 1;
  while (P <= Length(S)) and not Terminated do
  begin
    if SockSend(FConn, S[P], Length(S) - P + 1, Done) <> seOk then
      Exit;
    Inc(P, Done);
    if Done = 0 then
      SockWait([FConn], True, 10);
  end;
end;

procedure TScriptServer.Execute;
var
  Buf: array[0..4095] of Byte;
  Got: LongInt;
  Pending, Out, Ans: AnsiString;
  P, E: Integer;
  Agreed: Boolean;
begin
  while (FConn = NoSock) and not Terminated do
    if SockWait([FListen], False, 20) then
      SockAccept(FListen, FConn);
  Pending := '';
  Agreed := False;
  while not Terminated do
  begin
    SockWait([FConn], False, 10);
    if SockRecv(FConn, Buf, SizeOf(Buf), Got) <> seOk then
      Break;
    if Got > 0 then
    begin
      SetLength(Out, Got);
      Move(Buf, Out[1], Got);
      EnterCriticalSection(FLock);
      FSeen := FSeen + Out;
      LeaveCriticalSection(FLock);
      Pending := Pending + Out;
    end;
    if (FMode <> smSilent) and not Agreed and (Pos(#$FF#$FB#$2C, Pending) > 0) then
    begin
      Agreed := True;
      if FMode = smRefuse then
        Put(#$FF#$FE#$2C)                       { DONT COM-PORT-OPTION }
      else if FMode = smFlood then
        Put(FloodData + #$FF#$FD#$2C#$FF#$FB#$00#$FF#$FD#$00)
      else
        Put(#$FF#$FD#$2C#$FF#$FB#$00#$FF#$FD#$00);  { DO 44, WILL/DO BINARY }
    end;
    { answer each SET-xxx (codes 1..5) with code + 100 }
    repeat
      P := Pos(#$FF#$FA#$2C, Pending);
      if P = 0 then
        Break;
      E := Pos(#$FF#$F0, Copy(Pending, P, MaxInt));
      if E = 0 then
        Break;
      Ans := Copy(Pending, P + 3, E - 4);     { code and value }
      Delete(Pending, 1, P + E);
      if Agreed and (FMode <> smRefuse) and (Ans <> '') and (Ord(Ans[1]) in [1..5]) then
      begin
        if (FMode = smChangeBaud) and (Ans[1] = #1) then
          Ans := #1#$00#$00#$25#$80;          { 9600 instead }
        Ans[1] := Chr(Ord(Ans[1]) + 100);
        Put(#$FF#$FA#$2C + Ans + #$FF#$F0);
      end;
    until False;
    EnterCriticalSection(FLock);
    Out := FToSend;
    FToSend := '';
    LeaveCriticalSection(FLock);
    if Out <> '' then
      Put(Out);
  end;
end;

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
begin
  Srv := OpenListening('TCP', 'LISTEN=' + Listen, Result);
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
  { an IPv6 literal as HOST= }
  AssertEquals(res_Ok, OpenClient('HOST=::1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'v6');
  AssertEquals('v6', Receive(Srv, nil, 2, 3000));
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
  { the longest name a whole string holds (255 characters; a longer one is
    refused, not cut): no overrun, just not resolved }
  Dispose(Cli, Done);
  Cli := nil;
  AssertEquals(res_HostUnknown, OpenClient('PORT=4001 HOST=' + StringOfChar('a', 240)));
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
  { the OS's words too ({$IFDEF WINDOWS}Winsock's{$ELSE}the C library's{$ENDIF}) }
  {$IFDEF UNIX}
  AssertEquals('connection refused (PORT=' + IntToStr(Port) + '): Connection refused',
    Cli^.ChErrorText);
  {$ELSE}
  AssertTrue(Cli^.ChErrorText, Pos('connection refused (PORT=' + IntToStr(Port) + '): ',
    Cli^.ChErrorText) = 1);
  {$ENDIF}
end;

{$IFDEF LINUX}
{ A listener whose accept queue is full drops further SYNs (Linux): a
  connect to it neither succeeds nor is refused - as a host that is down. }
procedure TTestChnTcp.TestConnectTimeout;
var
  L: tSock;
  Fill: array[0..15] of tSock;
  A: tSockAddrs;
  N, I: LongInt;
  Port: Word;
  Full: Boolean;
  T0, Took: QWord;
begin
  for I := 0 to High(Fill) do
    Fill[I] := NoSock;
  L := fpSocket(AF_INET, SOCK_STREAM, 0);
  AssertTrue('socket', L >= 0);
  try
    AssertTrue(SockResolve('127.0.0.1', 0, True, A, N) = seOk);
    AssertEquals('bind', 0, fpBind(L, PSockAddr(@A[0].Data), A[0].Len));
    AssertEquals('listen, backlog 0', 0, fpListen(L, 0));
    Port := SockLocalPort(L);
    AssertTrue(SockResolve('127.0.0.1', Port, False, A, N) = seOk);
    Full := False;
    for I := 0 to High(Fill) do
    begin
      if SockConnectStart(A[0], Fill[I]) = seWouldBlock then
        if SockConnectDone(Fill[I], 300) = seWouldBlock then
        begin
          Full := True;             { this SYN was dropped: the queue is full }
          Break;
        end;
    end;
    AssertTrue('the accept queue filled up', Full);
    T0 := GetTickCount64;
    AssertEquals(res_Timeout, OpenClient('CTO=500 HOST=127.0.0.1 PORT=' + IntToStr(Port)));
    Took := GetTickCount64 - T0;
    AssertEquals('HOST=127.0.0.1', Cli^.ChParamError);
    AssertEquals(CHS_Close, Cli^.ChReady);
    AssertTrue(Format('after CTO=500 (%d ms)', [Took]), (Took >= 450) and (Took < 3000));
  finally
    for I := 0 to High(Fill) do
      SockClose(Fill[I]);
    CloseSocket(L);
  end;
end;
{$ENDIF}

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

{ A peer that aborts (SO_LINGER 0: RST instead of FIN) is lost the same way. }
procedure TTestChnTcp.TestPeerResetIsDeviceLostNextTick;
type
  TLinger = record
    OnOff, Secs: LongInt;
  end;
var
  L, S: tSock;
  A: tSockAddrs;
  N: LongInt;
  Lg: TLinger;
  Deadline: QWord;
begin
  AssertTrue(SockResolve('127.0.0.1', 0, True, A, N) = seOk);
  AssertTrue(SockListen(A[0], L) = seOk);
  S := NoSock;
  try
    AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(SockLocalPort(L))));
    Deadline := GetTickCount64 + 3000;
    while (SockAccept(L, S) <> seOk) and (GetTickCount64 < Deadline) do
      Sleep(5);
    AssertTrue('accepted', S <> NoSock);
    Lg.OnOff := 1;
    Lg.Secs := 0;
    AssertEquals(0, fpSetSockOpt(S, SOL_SOCKET, SO_LINGER, @Lg, SizeOf(Lg)));
    SockClose(S);                     { sends RST }
    Sleep(50);
    Cli^.ChReceiveReady;
    AssertEquals('one tick after the reset', res_DeviceLost, Cli^.ChResult);
    Cli^.ChSend(PChar('x'), 1);
    AssertEquals(res_DeviceLost, Cli^.ChSendResult);
  finally
    SockClose(S);
    SockClose(L);
  end;
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

{ Unlike a serial line without flow control, TCP never loses what a full
  ring cannot take: it stays in the socket and the sender is held back. }
procedure TTestChnTcp.TestFullRingHoldsTheSenderBack;
const
  Total = 60000;
var
  Port: Word;
  Data, Got: string;
  I: Integer;
  Len: Word;
  Deadline: QWord;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('LRB=16 HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'a');
  AssertEquals('a', Receive(Srv, nil, 1, 3000));
  SetLength(Data, Total);
  for I := 1 to Total do
    Data[I] := Chr(I * 7 mod 251);
  Srv^.ChSend(@Data[1], Total);
  AssertEquals(res_Ok, Srv^.ChSendResult);
  for I := 1 to 200 do             { polls that do not take the bytes }
  begin
    Srv^.ChSendReady;
    Cli^.ChReceiveReady;
  end;
  Got := '';
  Deadline := GetTickCount64 + 10000;
  while (Length(Got) < Total) and (GetTickCount64 < Deadline) do
  begin
    Srv^.ChSendReady;
    if Cli^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Cli^.ChReceive(Len);
      AssertEquals('no overrun', res_Ok, Cli^.ChReceiveResult);
      AssertTrue('never more than LRB at once', Len <= 16);
      SetLength(Got, Length(Got) + Len);
      Move(RBuf, Got[Length(Got) - Len + 1], Len);
    end;
  end;
  AssertEquals('all of it', Total, Length(Got));
  AssertTrue('unchanged', Got = Data);
  AssertEquals(0, pChnTcp(Cli)^.ChLostBytes);
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

{ A plain socket connected to Port (a squatter, or a client of a burst),
  NoSock when no connection came within Ms. }
function RawConnect(Port: Word; Ms: Integer): tSock;
var
  A: tSockAddrs;
  N: LongInt;
  E: tSockErr;
begin
  Result := NoSock;
  if SockResolve('127.0.0.1', Port, False, A, N) <> seOk then
    Exit;
  E := SockConnectStart(A[0], Result);
  if E = seWouldBlock then
    E := SockConnectDone(Result, Ms);
  if E <> seOk then
    SockClose(Result);
end;

{ True once the server closed S (end of stream), polling Srv meanwhile so
  it runs (and taking what it received); anything S receives is discarded. }
function ClosedByServer(S: tSock; Srv: pChnVirt; Ms: Integer): Boolean;
var
  Deadline: QWord;
  Buf: array[0..255] of Byte;
  Got: LongInt;
  Len: Word;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    if Srv^.ChReceiveReady = CHS_ReceiveReady then
      Srv^.ChReceive(Len);
    if SockWait([S], False, 5) and (SockRecv(S, Buf, SizeOf(Buf), Got) = seLost) then
      Exit(True);
  until GetTickCount64 > Deadline;
  Result := False;
end;

function ServerPort(Srv: pChnVirt): TChnPortTcp;
begin
  Result := TChnPortTcp(pChnTcp(Srv)^.CH_Port);
end;

{ Polls Srv until it has taken a client (2 s at most). }
procedure AwaitClient(Srv: pChnVirt);
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + 2000;
  while not pChnTcp(Srv)^.ChHasClient and (GetTickCount64 < Deadline) do
    Srv^.ChReceiveReady;
end;

procedure TTestChnTcp.TestKickAndIdleParameters;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('TCP');
  try
    C^.ChSetParam('LISTEN=0 KICK=ON IDLE=30000');
    AssertEquals(res_Ok, C^.ChResult);
    AssertEquals('NAM=TCP LISTEN=0 KICK=ON IDLE=30000 CTO=3000 RECON=0 RFC2217=OFF ' +
      'BD=9600 BIT=8 STOP=1 PAR=N FLW=NONE LRB=4096 LSB=65535 IDL=1', C^.ChGetParam(''));
    AssertEquals('KICK=ON', C^.ChGetParam('KICK'));
    AssertEquals('IDLE=30000', C^.ChGetParam('IDLE'));
    C^.ChSetParam(C^.ChGetParam(''));
    AssertEquals('taken back', res_Ok, C^.ChResult);
    C^.ChSetParam('KICK=MAYBE');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('KICK=MAYBE', C^.ChParamError);
    C^.ChSetParam('IDLE=-1');
    AssertEquals(res_BadParam, C^.ChResult);
    AssertEquals('IDLE=-1', C^.ChParamError);
    C^.ChSetParam('IDLE=3600001');
    AssertEquals(res_BadParam, C^.ChResult);
    Dispose(C, Done);
    C := ChnCollection^.ChNewInit('TCP');
    C^.ChSetParam('LISTEN=0');
    AssertEquals('the defaults', 'KICK=OFF IDLE=0', C^.ChGetParam('KICK') + ' ' + C^.ChGetParam('IDLE'));
  finally
    Dispose(C, Done);
  end;
  { a client has no line to give away: ChOpen names the token }
  AssertEquals(res_BadSetting, OpenClient('HOST=127.0.0.1 PORT=4001 KICK=ON'));
  AssertEquals('KICK=ON', Cli^.ChParamError);
  Dispose(Cli, Done);
  Cli := nil;
  AssertEquals(res_BadSetting, OpenClient('HOST=127.0.0.1 PORT=4001 IDLE=500'));
  AssertEquals('IDLE=500', Cli^.ChParamError);
end;

{ A client that connects and sends nothing holds a one-client line for
  ever; with KICK=ON the next connection takes the line from it. }
procedure TTestChnTcp.TestKickTakesTheLineFromASilentSquatter;
var
  Port: Word;
  Squat: tSock;
begin
  Port := OpenServer('0 KICK=ON');
  Squat := RawConnect(Port, 2000);
  try
    AssertTrue('the squatter is connected', Squat <> NoSock);
    AwaitClient(Srv);
    AssertTrue('the server took the squatter', pChnTcp(Srv)^.ChHasClient);
    AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
    SendText(Cli, 'read N7:0');
    AssertEquals('the new client has the line', 'read N7:0', Receive(Srv, nil, 9, 3000));
    SendText(Srv, 'reply');
    AssertEquals('and gets the answer', 'reply', Receive(Cli, nil, 5, 3000));
    AssertTrue('the squatter was closed', ClosedByServer(Squat, Srv, 2000));
    AssertEquals('counted', 1, ServerPort(Srv).Kicked);
    AssertEquals(res_Ok, Srv^.ChResult);
  finally
    SockClose(Squat);
  end;
end;

procedure TTestChnTcp.TestIdleClosesASilentSquatter;
var
  Port: Word;
  Squat: tSock;
  T0, Took: QWord;
begin
  Port := OpenServer('0 IDLE=300');
  Squat := RawConnect(Port, 2000);
  try
    AssertTrue(Squat <> NoSock);
    AwaitClient(Srv);
    T0 := GetTickCount64;
    AssertTrue('the silent client is closed', ClosedByServer(Squat, Srv, 3000));
    Took := GetTickCount64 - T0;
    AssertTrue(Format('after IDLE=300 (%d ms)', [Took]), (Took >= 250) and (Took < 1500));
    AssertEquals(1, ServerPort(Srv).IdleDropped);
    AssertFalse(pChnTcp(Srv)^.ChHasClient);
    AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
    SendText(Cli, 'legit');
    AssertEquals('the line is free again', 'legit', Receive(Srv, nil, 5, 3000));
  finally
    SockClose(Squat);
  end;
end;

{ A byte now and then (the attack sent one every 5 s) does not hold the
  line longer than IDLE between bytes; a client that talks keeps it. }
procedure TTestChnTcp.TestIdleClosesATricklingSquatter;
var
  Port: Word;
  Squat: tSock;
  B: Byte;
  Done: LongInt;
  Deadline: QWord;
  Closed: Boolean;
  Got: string;
  I: Integer;
begin
  Port := OpenServer('0 IDLE=400');
  Squat := RawConnect(Port, 2000);
  try
    AssertTrue(Squat <> NoSock);
    AwaitClient(Srv);
    B := 0;
    Closed := False;
    Deadline := GetTickCount64 + 3000;
    while not Closed and (GetTickCount64 < Deadline) do
    begin
      SockSend(Squat, B, 1, Done);
      Closed := ClosedByServer(Squat, Srv, 600);   { a byte every 600 ms }
    end;
    AssertTrue('the trickling client is closed', Closed);
    AssertEquals(1, ServerPort(Srv).IdleDropped);
    { a client sending every 100 ms for three IDLE periods keeps the line }
    AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
    Got := '';
    for I := 1 to 12 do
    begin
      SendText(Cli, 'x');
      Got := Got + Receive(Srv, nil, 1, 100);
      Deadline := GetTickCount64 + 100;
      while GetTickCount64 < Deadline do
        Srv^.ChReceiveReady;
      Got := Got + Receive(Srv, nil, 1, 0);
    end;
    Got := Got + Receive(Srv, nil, 12 - Length(Got), 1000);
    AssertEquals(StringOfChar('x', 12), Got);
    AssertTrue('still served', pChnTcp(Srv)^.ChHasClient);
    AssertEquals('not dropped', 1, ServerPort(Srv).IdleDropped);
  finally
    SockClose(Squat);
  end;
end;

{ A burst of connections while the server is busy (not polling) must not
  wait for the OS's SYN retry: the listen backlog holds them all. }
procedure TTestChnTcp.TestRapidReconnectsAreNotDelayed;
const
  Burst = 12;
var
  Port: Word;
  S: tSock;
  I: Integer;
  T0, Took, Worst: QWord;
begin
  Port := OpenServer('0');
  Worst := 0;
  for I := 1 to Burst do
  begin
    T0 := GetTickCount64;
    S := RawConnect(Port, 3000);
    Took := GetTickCount64 - T0;
    AssertTrue(Format('connect %d came through', [I]), S <> NoSock);
    SockClose(S);
    if Took > Worst then
      Worst := Took;
  end;
  AssertTrue(Format('the slowest of %d connects took %d ms', [Burst, Worst]), Worst < 300);
  { a client behind them: one poll of the server works through the closed
    ones and takes its bytes }
  AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'after');
  Sleep(100);
  AssertEquals('served at the first poll', CHS_ReceiveReady, Srv^.ChReceiveReady);
  AssertEquals('after', Receive(Srv, nil, 5, 3000));
end;

{ An attack: one client that connects and sends nothing held
  df1sim --listen's only line, and every legitimate read failed. df1sim
  serves with KICK=ON: each df1read takes the line. }
procedure TTestChnTcp.TestDf1simListenOutlivesASquatter;
var
  Sim: TProcess;
  Line, Output: string;
  Port, I, Code: Integer;
  Squat: tSock;
begin
  Squat := NoSock;
  Sim := TProcess.Create(nil);
  try
    BinExecutable(Sim, BinPath('df1sim'));
    Sim.Parameters.AddStrings(['--listen=0', '--quiet', '--timeout=20']);
    Sim.Options := [poUsePipes];
    Sim.Execute;
    Line := ReadFirstLine(Sim, 5000);
    AssertTrue('df1sim printed its port: ' + Line, (Copy(Line, 1, 7) = 'LISTEN ') and
      TryStrToInt(Copy(Line, 8, 10), Port));
    Squat := RawConnect(Port, 2000);
    AssertTrue('the squatter is connected', Squat <> NoSock);
    Sleep(200);                     { df1sim has taken it as its client }
    for I := 1 to 3 do
    begin
      Code := RunBin('df1read', ['N7:0', '3', 'NAM=DF1', 'NOD=0', 'DNO=1', 'CRC=ON',
        'NAM=TCP', 'HOST=127.0.0.1', 'PORT=' + IntToStr(Port)], 10000, Output);
      AssertEquals(Format('read %d past the squatter:'#10'%s', [I, Output]), 0, Code);
      AssertTrue(Output, Pos('N7:2 = 20', Output) > 0);
    end;
  finally
    SockClose(Squat);
    StopProcess(Sim);
  end;
end;

{ A server that pushes data while the options are negotiated: before the
  cap, 29 MiB pushed made 57 MB of resident memory. The first EarlyCap
  bytes are kept, the rest dropped and counted as lost. }
procedure TTestChnTcp.TestRfc2217FloodWhileNegotiatingIsCapped;
const
  Cap = 65536;
var
  Srv2: TScriptServer;
  Before, Grew: PtrUInt;
  Got: string;
  Mark: Integer;
begin
  Srv2 := TScriptServer.Create(smFlood);
  try
    Before := GetFPCHeapStatus.CurrHeapUsed;
    AssertEquals(res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON CTO=5000', [Srv2.Port])));
    Grew := GetFPCHeapStatus.CurrHeapUsed - Before;
    AssertTrue(Format('memory grew by %d bytes for %d pushed', [Grew, FloodLen]), Grew < 4 * Cap);
    { what was kept, then a byte sent after it }
    Srv2.Send('x');
    Got := Receive(Cli, nil, Cap + 1, 3000);
    AssertEquals('the first bytes are kept, then the new one', Cap + 1, Length(Got));
    AssertTrue('unchanged', Got = Copy(FloodData, 1, Cap) + 'x');
    AssertEquals('the rest is counted as lost', FloodLen - Cap, pChnTcp(Cli)^.ChLostBytes);
    Mark := Length(Srv2.Seen);
    SendText(Cli, 'after');
    AssertEquals('the line works', 'after', SeenAfter(Srv2, Mark, 5));
  finally
    Srv2.Free;
  end;
end;

{ Data the server sent before its DO COM-PORT-OPTION is kept by the port
  while it negotiates; the socket then shows nothing, so the wait used to
  sleep on it until the next byte came. Now it is held input: ChnWaitAny
  ends at once, a poll with IDL= takes it without waiting, and once taken
  the wait sleeps again. }
procedure TTestChnTcp.TestRfc2217DataKeptWhileNegotiatingEndsTheWait;
const
  Cap = 65536;
var
  Srv2: TScriptServer;
  Got: string;
  T0, Took: QWord;
  Woke: Boolean;
begin
  Srv2 := TScriptServer.Create(smFlood);
  try
    AssertEquals(res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON CTO=5000 IDL=50', [Srv2.Port])));
    T0 := GetTickCount64;
    Woke := ChnWaitAny(2000);
    Took := GetTickCount64 - T0;
    AssertTrue(Format('the kept data ends the wait at once (%d ms)', [Took]), Woke and (Took < 500));
    Got := Receive(Cli, nil, Cap, 3000);
    AssertEquals('all of it, no new byte needed', Cap, Length(Got));
    AssertTrue('unchanged', Got = Copy(FloodData, 1, Cap));
    T0 := GetTickCount64;
    Woke := ChnWaitAny(300);
    Took := GetTickCount64 - T0;
    AssertFalse('taken: nothing is held any more', Woke);
    AssertTrue(Format('the wait slept its 300 ms (%d ms)', [Took]), Took >= 250);
    AssertEquals('no byte held anywhere', 0, ChnWaitHeldCount);
  finally
    Srv2.Free;
  end;
end;

{ IAC SB never closed by IAC SE swallowed all data after it without a
  word; now the data before it arrives and the line says what happened. }
procedure TTestChnTcp.TestRfc2217UnclosedSubnegotiationIsNamed;
var
  Srv2: TScriptServer;
  Deadline: QWord;
begin
  Srv2 := TScriptServer.Create(smHonest);
  try
    AssertEquals(res_Ok, OpenClient(Format('HOST=127.0.0.1 PORT=%d RFC2217=ON CTO=2000', [Srv2.Port])));
    Srv2.Send('head' + #$FF#$FA#$2C#$6B + StringOfChar('A', 300) + 'tail');
    AssertEquals('the data before it', 'head', Receive(Cli, nil, 4, 3000));
    Deadline := GetTickCount64 + 3000;
    while (Cli^.ChResult = res_Ok) and (GetTickCount64 < Deadline) do
      Cli^.ChReceiveReady;
    AssertEquals('named', res_BadStream, Cli^.ChResult);
    AssertEquals(res_BadStream, Cli^.ChReceiveResult);
    AssertEquals('the peer broke the Telnet protocol (subnegotiation never closed)',
      Cli^.ChResultStr(Cli^.ChResult));
    AssertEquals('nothing after it is taken for data', '', Receive(Cli, nil, 1, 200));
  finally
    Srv2.Free;
  end;
end;

procedure TTestChnTcp.TestRfc2217ServerChangesTheRate;
var
  Srv2: TScriptServer;
begin
  Srv2 := TScriptServer.Create(smChangeBaud);
  try
    AssertEquals(res_BadSetting, OpenClient(Format(
      'HOST=127.0.0.1 PORT=%d RFC2217=ON BD=19200 CTO=2000', [Srv2.Port])));
    AssertEquals('names the token', 'BD=19200', Cli^.ChParamError);
    AssertEquals(CHS_Close, Cli^.ChReady);
    { what went out: WILL COM-PORT-OPTION, then SET-BAUDRATE 19200 }
    AssertTrue(Hex(Srv2.Seen), Pos(#$FF#$FB#$2C, Srv2.Seen) > 0);
    AssertTrue(Hex(Srv2.Seen), Pos(Bytes('FF FA 2C 01 00 00 4B 00 FF F0'), Srv2.Seen) > 0);
  finally
    Srv2.Free;
  end;
end;

procedure TTestChnTcp.TestRfc2217ServerRefusesTheOption;
var
  Srv2: TScriptServer;
begin
  Srv2 := TScriptServer.Create(smRefuse);
  try
    AssertEquals(res_BadSetting, OpenClient(Format(
      'HOST=127.0.0.1 PORT=%d RFC2217=ON CTO=2000', [Srv2.Port])));
    AssertEquals('RFC2217=ON', Cli^.ChParamError);
  finally
    Srv2.Free;
  end;
end;

procedure TTestChnTcp.TestRfc2217ServerSilent;
var
  Srv2: TScriptServer;
  T0: QWord;
begin
  Srv2 := TScriptServer.Create(smSilent);
  try
    T0 := GetTickCount64;
    AssertEquals(res_BadSetting, OpenClient(Format(
      'HOST=127.0.0.1 PORT=%d RFC2217=ON CTO=300', [Srv2.Port])));
    AssertEquals('RFC2217=ON', Cli^.ChParamError);
    AssertTrue('bounded by CTO', GetTickCount64 - T0 < 3000);
  finally
    Srv2.Free;
  end;
end;

procedure TTestChnTcp.TestRfc2217DataNotifyAndPurgeOnTheWire;
var
  Srv2: TScriptServer;
  Lines: tPortLines;
  Data: string;
  Mark: Integer;
begin
  Srv2 := TScriptServer.Create(smHonest);
  try
    AssertEquals(res_Ok, OpenClient(Format(
      'HOST=127.0.0.1 PORT=%d RFC2217=ON BD=57600 BIT=7 PAR=O STOP=2 FLW=RTSCTS', [Srv2.Port])));
    { the settings as RFC 2217 spells them }
    AssertTrue(Hex(Srv2.Seen), Pos(Bytes('FF FA 2C 01 00 00 E1 00 FF F0'), Srv2.Seen) > 0);
    AssertTrue('7 bits', Pos(Bytes('FF FA 2C 02 07 FF F0'), Srv2.Seen) > 0);
    AssertTrue('odd = 2', Pos(Bytes('FF FA 2C 03 02 FF F0'), Srv2.Seen) > 0);
    AssertTrue('2 stop', Pos(Bytes('FF FA 2C 04 02 FF F0'), Srv2.Seen) > 0);
    AssertTrue('hardware flow = 3', Pos(Bytes('FF FA 2C 05 03 FF F0'), Srv2.Seen) > 0);
    AssertTrue('overrun reports asked for', Pos(Bytes('FF FA 2C 0A 02 FF F0'), Srv2.Seen) > 0);
    { data with IAC doubled, a modem-state notification in the middle }
    Srv2.Send(Bytes('01 FF FF 02 FF FA 2C 6B 30 FF F0 03 FF FA 2C 6A 02 FF F0 04'));
    Data := Receive(Cli, nil, 5, 3000);
    AssertEquals('data undisturbed', '01 FF 02 03 04', Hex(Data));
    AssertEquals(res_Ok, pChnTcp(Cli)^.ChModemLines(Lines));
    AssertTrue('CTS and DSR from NOTIFY-MODEMSTATE', Lines = [plCts, plDsr]);
    AssertEquals('the line overrun counted', 1, pChnTcp(Cli)^.ChLostBytes);
    { our IAC doubled on the wire }
    Mark := Length(Srv2.Seen);
    SendText(Cli, #$FF#$00#$FF);
    AssertEquals('FF FF 00 FF FF', Hex(SeenAfter(Srv2, Mark, 5)));
    Mark := Length(Srv2.Seen);
    Cli^.ChReceiveFlush;
    AssertEquals('PURGE-DATA 1', 'FF FA 2C 0C 01 FF F0', Hex(SeenAfter(Srv2, Mark, 7)));
    Mark := Length(Srv2.Seen);
    AssertEquals(res_Ok, pChnTcp(Cli)^.ChSetDtr(False));
    AssertEquals(res_Ok, pChnTcp(Cli)^.ChSetRts(True));
    AssertEquals('DTR off = 9, RTS on = 11', 'FF FA 2C 05 09 FF F0 FF FA 2C 05 0B FF F0',
      Hex(SeenAfter(Srv2, Mark, 14)));
  finally
    Srv2.Free;
  end;
end;

{$IFDEF LINUX}
{ TCP_NODELAY and keep-alive with Linux timing, as the OS reports them for
  the client's socket and a server's accepted one. }
procedure TTestChnTcp.TestNoDelayAndKeepAlive;

  function Opt(S: PtrInt; Level, Name: LongInt): LongInt;
  var
    L: TSockLen;
  begin
    Result := -1;
    L := SizeOf(Result);
    AssertEquals('getsockopt', 0, fpGetSockOpt(S, Level, Name, @Result, @L));
  end;

  procedure Check(const Who: string; S: PtrInt);
  begin
    AssertTrue(Who + ' socket', S >= 0);
    AssertTrue(Who + ' TCP_NODELAY', Opt(S, IPPROTO_TCP, TCP_NODELAY) <> 0);
    AssertTrue(Who + ' SO_KEEPALIVE', Opt(S, SOL_SOCKET, SO_KEEPALIVE) <> 0);
    AssertEquals(Who + ' TCP_KEEPIDLE', 10, Opt(S, IPPROTO_TCP, TCP_KEEPIDLE));
    AssertEquals(Who + ' TCP_KEEPINTVL', 5, Opt(S, IPPROTO_TCP, TCP_KEEPINTVL));
    AssertEquals(Who + ' TCP_KEEPCNT', 3, Opt(S, IPPROTO_TCP, TCP_KEEPCNT));
  end;

var
  Port: Word;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'a');
  AssertEquals('a', Receive(Srv, nil, 1, 3000));
  Check('client', TChnPortTcp(pChnTcp(Cli)^.CH_Port).OsHandle);
  Check('server', TChnPortTcp(pChnTcp(Srv)^.CH_Port).OsHandle);
end;

{ A legacy "repeat until ChReceiveReady = CHS_ReceiveReady" on an idle TCP
  client costs little CPU with the default IDL=1 (the wait works), and
  spins with IDL=0 (so the measurement itself can see a busy loop). }
procedure TTestChnTcp.TestIdlePollingLoopCpu;
var
  Port: Word;

  function Spent(const Params: string): Double;
  var
    T: QWord;
    C0: Double;
  begin
    if Cli <> nil then
      Dispose(Cli, Done);
    Cli := nil;
    AssertEquals(res_Ok, OpenClient(Params + ' HOST=127.0.0.1 PORT=' + IntToStr(Port)));
    Srv^.ChReceiveReady;
    C0 := CpuMs;
    T := GetTickCount64;
    while GetTickCount64 - T < 1000 do
      AssertTrue('nothing comes', Cli^.ChReceiveReady <> CHS_ReceiveReady);
    Result := CpuMs - C0;
  end;

var
  Idle, Busy, Bound: Double;
begin
  Port := OpenServer('0');
  Idle := Spent('');
  Busy := Spent('IDL=0');
  Bound := IdleCpuBound(50);        { about 1000 idle polls }
  AssertTrue(Format('IDL=1: %.1f ms CPU in 1000 ms (bound %.0f)', [Idle, Bound]), Idle < Bound);
  AssertTrue(Format('IDL=0 spins: %.1f ms CPU in 1000 ms', [Busy]), Busy > 100);
end;
{$ENDIF}

{ An idle TCP client's poll ends at input on another line (a LOOP pair), and
  a LOOP line's poll ends at input on the TCP client: both are in the
  program-wide wait (ChnWait), not each on its own device for IDL ms. }
procedure TTestChnTcp.TestClientIsInTheSharedWait;
var
  Port: Word;
  L1, L2: pChnVirt;
  Err: string;
  S: TSendLater;
  T0, Took: QWord;
  St: tChState;
begin
  Port := OpenServer('0');
  AssertEquals(res_Ok, OpenClient('IDL=1000 HOST=127.0.0.1 PORT=' + IntToStr(Port)));
  SendText(Cli, 'a');
  AssertEquals('a', Receive(Srv, nil, 1, 3000));  { the server has its client }
  L1 := OpenStack('LOOP', 'PAIR=tcpwait END=1 IDL=1000', Err);
  AssertNotNull(Err, L1);
  L2 := OpenStack('LOOP', 'PAIR=tcpwait END=2', Err);
  AssertNotNull(Err, L2);
  S := TSendLater.Create(True);
  try
    S.Chn := L2;
    S.DelayMs := 100;
    T0 := GetTickCount64;
    S.Start;
    St := Cli^.ChReceiveReady;       { nothing for the TCP client }
    Took := GetTickCount64 - T0;
    S.WaitFor;
    AssertEquals('the client got nothing', CHS_Receiving, St);
    AssertTrue(Format('its wait ended at the LOOP byte, not after IDL=1000 (%d ms)',
      [Took]), Took < 700);
    AssertEquals(CHS_ReceiveReady, L1^.ChReceiveReady);
    L1^.ChReceiveFlush;
    S.Free;
    S := TSendLater.Create(True);
    S.Chn := Srv;
    S.DelayMs := 100;
    T0 := GetTickCount64;
    S.Start;
    St := L1^.ChReceiveReady;        { nothing for LOOP }
    Took := GetTickCount64 - T0;
    S.WaitFor;
    AssertEquals('LOOP got nothing', CHS_Receiving, St);
    AssertTrue(Format('its wait ended at the TCP byte (%d ms)', [Took]), Took < 700);
    AssertEquals(CHS_ReceiveReady, Cli^.ChReceiveReady);
  finally
    S.Free;
    Dispose(L1, Done);
    Dispose(L2, Done);
  end;
end;

{ A server's listening socket and its client are one source of the
  program-wide wait: ChnWaitAny ends at a connection, at the client's input
  and at its leaving, each while blocked - and sleeps its time when there is
  nothing, also after a second client was turned away and after the first
  one left (neither leaves a descriptor that wakes it for nothing). }
procedure TTestChnTcp.TestServerIsInTheSharedWait;

  { ChnWaitAny(Ms): whether it ended early, and how long it took }
  function WaitTook(Ms: Integer; out Took: QWord): Boolean;
  var
    T0: QWord;
  begin
    T0 := GetTickCount64;
    Result := ChnWaitAny(Ms);
    Took := GetTickCount64 - T0;
  end;

  procedure AssertSleeps(const What: string);
  var
    Took: QWord;
  begin
    AssertFalse(What + ': nothing ends the wait', WaitTook(300, Took));
    AssertTrue(Format('%s: the wait slept its 300 ms (%d ms)', [What, Took]), Took >= 250);
  end;

  procedure AssertWakes(const What: string; L: TRawLater);
  var
    Took: QWord;
    Woke: Boolean;
  begin
    Woke := WaitTook(3000, Took);
    L.WaitFor;
    AssertTrue(Format('%s ends the blocked wait (%d ms, not 3000)', [What, Took]),
      Woke and (Took < 1500));
  end;

var
  Port: Word;
  L: TRawLater;
  A, B: tSock;
  Deadline: QWord;
begin
  if not ChnWaitShared then
    Ignore('this OS has no kernel wait the channels share (ChnWaitShared False): ChnWaitAny polls');
  Port := OpenServer('0');
  A := NoSock;
  B := NoSock;
  L := nil;
  try
    AssertSleeps('no client');
    L := RawLater(Port, NoSock, 'x');
    AssertWakes('a connection with a byte', L);
    A := L.Sock;
    FreeAndNil(L);
    AssertTrue('connected', A <> NoSock);
    AssertEquals('x', Receive(Srv, nil, 1, 2000));
    AssertTrue('the server has its client', pChnTcp(Srv)^.ChHasClient);
    AssertSleeps('a silent client');
    L := RawLater(Port, NoSock, 'z');
    AssertWakes('a second connection', L);
    B := L.Sock;
    FreeAndNil(L);
    AssertTrue('turned away', ClosedByServer(B, Srv, 2000));
    AssertSleeps('after a client was turned away');
    L := RawLater(Port, A, 'y');
    AssertWakes('the client''s byte', L);
    FreeAndNil(L);
    AssertEquals('y', Receive(Srv, nil, 1, 2000));
    L := RawLater(Port, A, '');
    AssertWakes('the client leaving', L);
    A := NoSock;                     { closed by the thread }
    FreeAndNil(L);
    Deadline := GetTickCount64 + 2000;
    while pChnTcp(Srv)^.ChHasClient and (GetTickCount64 < Deadline) do
      Srv^.ChReceiveReady;
    AssertFalse('the server let the client go', pChnTcp(Srv)^.ChHasClient);
    AssertSleeps('after the client left');
  finally
    L.Free;
    SockClose(A);
    SockClose(B);
  end;
end;

initialization
  RegisterTest(TTestChnTcp);
end.
