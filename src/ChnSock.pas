{ ChnSock - the OS side of NAM=TCP: a handful of non-blocking TCP socket
  calls over Free Pascal's "sockets" unit, Berkeley sockets on Unix and
  Winsock on Windows. Name resolution is the system's getaddrinfo (libc on
  Unix, ws2_32 on Windows), so /etc/hosts, DNS and IPv6 work as for any
  other program. Nothing here knows about channels or Telnet; every call
  answers a tSockErr and never raises or blocks longer than its Ms. }
unit ChnSock;

{$I chn.inc}
{$IFDEF UNIX}{$LINKLIB c}{$ENDIF}

interface

type
  tSock = PtrInt;

  tSockErr = (
    seOk,
    seWouldBlock,     { nothing now (no data, no room, connect in progress) }
    seNoHost,         { name not resolved }
    seRefused,        { connection refused }
    seTimeout,        { connect did not complete in time }
    seLost,           { peer closed or reset the connection }
    seInUse,          { address in use (listen) }
    seAccess,         { not allowed (privileged port, firewall) }
    seOther);

  { One resolved address, a struct sockaddr_storage in disguise. }
  tSockAddr = record
    Len : LongInt;
    Data: array[0..127] of Byte;
  end;

const
  NoSock = -1;
  MaxSockAddrs = 8;

type
  tSockAddrs = array[0..MaxSockAddrs - 1] of tSockAddr;

{ Addresses of Host (name, IPv4 or IPv6 literal; '' = loopback when not
  Passive, all interfaces when Passive) and Port, in the system's order. }
function  SockResolve(const Host: ShortString; Port: Word; Passive: Boolean;
  out Addrs: tSockAddrs; out Count: LongInt): tSockErr;
{ Start a non-blocking connect; seOk when already connected, seWouldBlock
  while in progress (finish with SockConnectDone). S is NoSock on failure. }
function  SockConnectStart(const A: tSockAddr; out S: tSock): tSockErr;
{ Wait at most Ms for a started connect: seOk, seWouldBlock (still going),
  or why it failed. }
function  SockConnectDone(S: tSock; Ms: LongInt): tSockErr;
{ A listening socket on A (SO_REUSEADDR, so a restarted server gets its
  port back at once). }
function  SockListen(const A: tSockAddr; out S: tSock): tSockErr;
{ Take one waiting connection, non-blocking; seWouldBlock when none. }
function  SockAccept(L: tSock; out S: tSock): tSockErr;
{ TCP_NODELAY and keep-alive (probe after 10 s idle, every 5 s, 3 tries
  where the OS lets us set it), so a dead peer is noticed. }
procedure SockTune(S: tSock);
{ Receive up to Size bytes, never wait: Got = 0 with seOk = nothing now;
  seLost when the peer closed (end of stream) or reset. }
function  SockRecv(S: tSock; var Buf; Size: LongInt; out Got: LongInt): tSockErr;
{ Send up to Len bytes, never wait: Done may be 0 when the buffer is full.
  seLost when the connection is dead (no SIGPIPE). }
function  SockSend(S: tSock; const Buf; Len: LongInt; out Done: LongInt): tSockErr;
{ Wait at most Ms until one of Socks is readable (ForWrite: writable);
  NoSock entries are skipped. }
function  SockWait(const Socks: array of tSock; ForWrite: Boolean; Ms: LongInt): Boolean;
{ Bytes sent but not yet acknowledged by the peer; 0 where unknown. }
function  SockOutQueue(S: tSock): LongInt;
{ The local port a socket is bound to (LISTEN=...:0 picks a free one). }
function  SockLocalPort(S: tSock): Word;
{ 'a.b.c.d:port' or '[v6]:port' of the local end, '' when unknown. }
function  SockLocalName(S: tSock): ShortString;
procedure SockClose(var S: tSock);
{ Windows: an event handle set on input or close (WSAEventSelect), for the
  program-wide wait; 0 on failure and on other systems. }
function  SockEventCreate(S: tSock): PtrInt;
{ Reset the event, and set it again when input is still waiting (called
  after the owner has read, so no signal is lost). }
procedure SockEventRearm(S: tSock; Ev: PtrInt);
procedure SockEventFree(var Ev: PtrInt);
{ The OS error code of the last failing call, for messages. }
function  SockLastOsError: LongInt;

implementation

uses
  {$IFDEF WINDOWS}WinSock2,{$ELSE}BaseUnix, Unix,{$ENDIF} Sockets, SysUtils, uString;

{$PACKRECORDS C}   { an OS structure: C alignment, not chn.inc's packing }
type
  { struct addrinfo: the field order differs between Linux and Windows }
  PAddrInfo = ^TAddrInfo;
  TAddrInfo = record
    ai_flags, ai_family, ai_socktype, ai_protocol: LongInt;
    {$IFDEF WINDOWS}
    ai_addrlen: PtrUInt;
    ai_canonname: PChar;
    ai_addr: PSockAddr;
    {$ELSE}
    ai_addrlen: LongWord;
    ai_addr: PSockAddr;
    ai_canonname: PChar;
    {$ENDIF}
    ai_next: PAddrInfo;
  end;
{$PACKRECORDS 1}

const
  AI_PASSIVE = 1;
  { connections the OS completes before the server takes them: a burst of
    reconnects must not find the queue full (a dropped SYN is retried only
    after a second); a server takes them all at its next poll }
  ListenBacklog = 128;
  {$IFDEF WINDOWS}
  GaiLib = 'ws2_32.dll';
  {$ENDIF}

{$IFDEF WINDOWS}
function getaddrinfo(Node, Service: PChar; Hints: PAddrInfo; var Res: PAddrInfo): LongInt;
  stdcall; external GaiLib name 'getaddrinfo';
procedure freeaddrinfo(Res: PAddrInfo); stdcall; external GaiLib name 'freeaddrinfo';
{$ELSE}
function getaddrinfo(Node, Service: PChar; Hints: PAddrInfo; var Res: PAddrInfo): LongInt;
  cdecl; external 'c' name 'getaddrinfo';
procedure freeaddrinfo(Res: PAddrInfo); cdecl; external 'c' name 'freeaddrinfo';
{$ENDIF}

var
  LastOsError: LongInt = 0;

function SockLastOsError: LongInt;
begin
  Result := LastOsError;
end;

{ ---- the OS-specific part: error codes, non-blocking mode, waiting ---- }

function MapError(E: LongInt): tSockErr;
begin
  LastOsError := E;
  {$IFDEF WINDOWS}
  case E of
    WSAEWOULDBLOCK, WSAEINPROGRESS, WSAEALREADY: Result := seWouldBlock;
    WSAECONNREFUSED: Result := seRefused;
    WSAETIMEDOUT: Result := seTimeout;
    WSAECONNRESET, WSAECONNABORTED, WSAENETRESET, WSAESHUTDOWN,
    WSAENOTCONN: Result := seLost;
    WSAEADDRINUSE: Result := seInUse;
    WSAEACCES: Result := seAccess;
  else
    Result := seOther;
  end;
  {$ELSE}
  case E of
    ESysEAGAIN, ESysEINPROGRESS, ESysEALREADY, ESysEINTR: Result := seWouldBlock;
    ESysECONNREFUSED: Result := seRefused;
    ESysETIMEDOUT, ESysEHOSTUNREACH, ESysENETUNREACH: Result := seTimeout;
    ESysECONNRESET, ESysECONNABORTED, ESysEPIPE, ESysENETRESET,
    ESysENOTCONN: Result := seLost;
    ESysEADDRINUSE: Result := seInUse;
    ESysEACCES, ESysEPERM: Result := seAccess;
  else
    Result := seOther;
  end;
  {$ENDIF}
end;

function SetNonBlocking(S: tSock): Boolean;
{$IFDEF WINDOWS}
var
  Arg: u_long;
begin
  Arg := 1;
  Result := ioctlsocket(TSocket(S), LongInt(FIONBIO), Arg) = 0;
end;
{$ELSE}
var
  Fl: LongInt;
begin
  Fl := FpFcntl(S, F_GETFL);
  Result := (Fl >= 0) and (FpFcntl(S, F_SETFL, Fl or O_NONBLOCK) = 0);
  FpFcntl(S, F_SETFD, 1);   { FD_CLOEXEC: a child we start must not keep it }
end;
{$ENDIF}

function SockWait(const Socks: array of tSock; ForWrite: Boolean; Ms: LongInt): Boolean;
{$IFDEF WINDOWS}
var
  Fs, Ex: TFDSet;
  Tv: TTimeVal;
  I: Integer;
begin
  FD_ZERO(Fs);
  for I := 0 to High(Socks) do
    if Socks[I] <> NoSock then
      FD_SET(TSocket(Socks[I]), Fs);
  Ex := Fs;
  if Fs.fd_count = 0 then
  begin
    if Ms > 0 then
      Sleep(Ms);
    Exit(False);
  end;
  Tv.tv_sec := Ms div 1000;
  Tv.tv_usec := (Ms mod 1000) * 1000;
  if ForWrite then
    { Winsock reports a failed connect in the except set, not as writable }
    Result := select(0, nil, @Fs, @Ex, @Tv) > 0
  else
    Result := select(0, @Fs, nil, nil, @Tv) > 0;
end;
{$ELSE}
var
  P: array[0..3] of TPollFd;
  I, N: Integer;
begin
  N := 0;
  for I := 0 to High(Socks) do
    if (Socks[I] <> NoSock) and (N <= High(P)) then
    begin
      P[N].fd := Socks[I];
      if ForWrite then
        P[N].events := POLLOUT
      else
        P[N].events := POLLIN;
      P[N].revents := 0;
      Inc(N);
    end;
  if N = 0 then
  begin
    if Ms > 0 then
      Sleep(Ms);
    Exit(False);
  end;
  Result := FpPoll(@P[0], N, Ms) > 0;
end;
{$ENDIF}

function SockOutQueue(S: tSock): LongInt;
{$IFDEF LINUX}
const
  SIOCOUTQ = $5411;               { = TIOCOUTQ }
var
  N: LongInt;
begin
  N := 0;
  if (S = NoSock) or (FpIoctl(S, SIOCOUTQ, @N) <> 0) then
    N := 0;
  Result := N;
end;
{$ELSE}
begin
  Result := 0;
end;
{$ENDIF}

function SockEventCreate(S: tSock): PtrInt;
{$IFDEF WINDOWS}
var
  Ev: WSAEVENT;
begin
  Result := 0;
  Ev := WSACreateEvent;
  if Ev = 0 then
    Exit;
  if WSAEventSelect(TSocket(S), Ev, FD_READ or FD_CLOSE) <> 0 then
  begin
    WSACloseEvent(Ev);
    Exit;
  end;
  Result := PtrInt(Ev);
end;
{$ELSE}
begin
  Result := 0;
end;
{$ENDIF}

procedure SockEventRearm(S: tSock; Ev: PtrInt);
{$IFDEF WINDOWS}
var
  N: u_long;
begin
  if Ev = 0 then
    Exit;
  WSAResetEvent(WSAEVENT(Ev));
  N := 0;
  if (ioctlsocket(TSocket(S), LongInt(FIONREAD), N) = 0) and (N > 0) then
    WSASetEvent(WSAEVENT(Ev));
end;
{$ELSE}
begin
end;
{$ENDIF}

procedure SockEventFree(var Ev: PtrInt);
begin
  {$IFDEF WINDOWS}
  if Ev <> 0 then
    WSACloseEvent(WSAEVENT(Ev));
  {$ENDIF}
  Ev := 0;
end;

procedure SockClose(var S: tSock);
begin
  if S <> NoSock then
    CloseSocket(S);
  S := NoSock;
end;

{ ---- portable over the sockets unit ---- }

function SockResolve(const Host: ShortString; Port: Word; Passive: Boolean;
  out Addrs: tSockAddrs; out Count: LongInt): tSockErr;
var
  Hints: TAddrInfo;
  Res, P: PAddrInfo;
  H, Svc: AnsiString;             { a 255-character name still gets its #0 }
  HP: PChar;
begin
  Count := 0;
  FillChar(Addrs, SizeOf(Addrs), 0);
  FillChar(Hints, SizeOf(Hints), 0);
  Hints.ai_family := AF_UNSPEC;
  Hints.ai_socktype := SOCK_STREAM;
  Hints.ai_protocol := IPPROTO_TCP;
  H := Host;
  Svc := NumStr(Port) + #0;
  HP := PChar(H);
  if Host = '' then
    HP := nil;                      { any interface if Passive, else loopback }
  if Passive then
    Hints.ai_flags := AI_PASSIVE;
  Res := nil;
  if getaddrinfo(HP, PChar(Svc), @Hints, Res) <> 0 then
  begin
    LastOsError := 0;
    Exit(seNoHost);
  end;
  P := Res;
  while (P <> nil) and (Count < MaxSockAddrs) do
  begin
    if (P^.ai_addr <> nil) and (P^.ai_addrlen <= SizeOf(Addrs[0].Data)) then
    begin
      Addrs[Count].Len := P^.ai_addrlen;
      Move(P^.ai_addr^, Addrs[Count].Data, P^.ai_addrlen);
      Inc(Count);
    end;
    P := P^.ai_next;
  end;
  freeaddrinfo(Res);
  if Count = 0 then
    Result := seNoHost
  else
    Result := seOk;
end;

{ S non-blocking, or closed and why not. }
function NonBlocking(var S: tSock): tSockErr;
begin
  if SetNonBlocking(S) then
    Exit(seOk);
  Result := MapError(SocketError);
  SockClose(S);
end;

function NewSocket(const A: tSockAddr; out S: tSock): tSockErr;
var
  Family: Word;
begin
  Family := PSockAddr(@A.Data)^.sa_family;
  S := fpSocket(Family, SOCK_STREAM, IPPROTO_TCP);
  if (S < 0) {$IFDEF WINDOWS}or (S = tSock(INVALID_SOCKET)){$ENDIF} then
  begin
    S := NoSock;
    Exit(MapError(SocketError));
  end;
  Result := NonBlocking(S);
end;

function SockConnectStart(const A: tSockAddr; out S: tSock): tSockErr;
begin
  Result := NewSocket(A, S);
  if Result <> seOk then
    Exit;
  SockTune(S);
  if fpConnect(S, PSockAddr(@A.Data), A.Len) = 0 then
    Exit(seOk);
  Result := MapError(SocketError);
  if Result <> seWouldBlock then
    SockClose(S);
end;

function SockConnectDone(S: tSock; Ms: LongInt): tSockErr;
var
  Err: LongInt;
  L: TSockLen;
begin
  if S = NoSock then
    Exit(seOther);
  if not SockWait([S], True, Ms) then
    Exit(seWouldBlock);
  Err := 0;
  L := SizeOf(Err);
  if fpGetSockOpt(S, SOL_SOCKET, SO_ERROR, @Err, @L) <> 0 then
    Exit(MapError(SocketError));
  if Err = 0 then
    Result := seOk
  else
  begin
    Result := MapError(Err);
    if Result = seWouldBlock then
      Result := seOther;
  end;
end;

function SockListen(const A: tSockAddr; out S: tSock): tSockErr;
var
  One: LongInt;
begin
  Result := NewSocket(A, S);
  if Result <> seOk then
    Exit;
  One := 1;
  {$IFDEF WINDOWS}
  { Windows' SO_REUSEADDR would let a second program steal the port }
  fpSetSockOpt(S, SOL_SOCKET, SO_EXCLUSIVEADDRUSE, @One, SizeOf(One));
  {$ELSE}
  fpSetSockOpt(S, SOL_SOCKET, SO_REUSEADDR, @One, SizeOf(One));
  {$ENDIF}
  if (fpBind(S, PSockAddr(@A.Data), A.Len) <> 0) or (fpListen(S, ListenBacklog) <> 0) then
  begin
    Result := MapError(SocketError);
    SockClose(S);
  end;
end;

function SockAccept(L: tSock; out S: tSock): tSockErr;
begin
  S := fpAccept(L, nil, nil);
  if (S < 0) {$IFDEF WINDOWS}or (S = tSock(INVALID_SOCKET)){$ENDIF} then
  begin
    S := NoSock;
    Result := MapError(SocketError);
    if Result = seLost then
      Result := seWouldBlock;     { the client gave up before we took it }
    Exit;
  end;
  Result := NonBlocking(S);
  if Result = seOk then
    SockTune(S);
end;

procedure SockTune(S: tSock);
{$IFDEF WINDOWS}
type
  TKeepAlive = record              { struct tcp_keepalive }
    OnOff, Time, Interval: LongWord;
  end;
const
  SIO_KEEPALIVE_VALS = $98000004;
var
  Ka: TKeepAlive;
  Ret: DWORD;
{$ENDIF}
var
  One: LongInt;
  {$IFDEF LINUX}
  V: LongInt;
  {$ENDIF}
begin
  One := 1;
  fpSetSockOpt(S, IPPROTO_TCP, TCP_NODELAY, @One, SizeOf(One));
  fpSetSockOpt(S, SOL_SOCKET, SO_KEEPALIVE, @One, SizeOf(One));
  {$IFDEF WINDOWS}
  Ka.OnOff := 1;                   { the same timing as on Linux; Windows }
  Ka.Time := 10000;                { sends 10 probes before giving up }
  Ka.Interval := 5000;
  Ret := 0;
  WSAIoctl(TSocket(S), SIO_KEEPALIVE_VALS, @Ka, SizeOf(Ka), nil, 0, @Ret, nil, nil);
  {$ENDIF}
  {$IFDEF LINUX}
  V := 10;
  fpSetSockOpt(S, IPPROTO_TCP, TCP_KEEPIDLE, @V, SizeOf(V));
  V := 5;
  fpSetSockOpt(S, IPPROTO_TCP, TCP_KEEPINTVL, @V, SizeOf(V));
  V := 3;
  fpSetSockOpt(S, IPPROTO_TCP, TCP_KEEPCNT, @V, SizeOf(V));
  {$ENDIF}
end;

function SockRecv(S: tSock; var Buf; Size: LongInt; out Got: LongInt): tSockErr;
var
  N: LongInt;
begin
  Got := 0;
  N := fpRecv(S, @Buf, Size, 0);
  if N > 0 then
  begin
    Got := N;
    Exit(seOk);
  end;
  if N = 0 then
    Exit(seLost);                   { orderly end of stream }
  Result := MapError(SocketError);
  if Result = seWouldBlock then
    Result := seOk
  else if Result in [seOther, seTimeout] then
    Result := seLost;               { keep-alive gave up, and the like }
end;

function SockSend(S: tSock; const Buf; Len: LongInt; out Done: LongInt): tSockErr;
var
  N: LongInt;
begin
  Done := 0;
  N := fpSend(S, @Buf, Len, {$IFDEF LINUX}MSG_NOSIGNAL{$ELSE}0{$ENDIF});
  if N >= 0 then
  begin
    Done := N;
    Exit(seOk);
  end;
  Result := MapError(SocketError);
  if Result = seWouldBlock then
    Result := seOk
  else if Result in [seOther, seTimeout] then
    Result := seLost;
end;

function SockLocalName(S: tSock): ShortString;
var
  A: tSockAddr;
  L: TSockLen;
begin
  Result := '';
  L := SizeOf(A.Data);
  if (S = NoSock) or (fpGetSockName(S, PSockAddr(@A.Data), @L) <> 0) then
    Exit;
  if PSockAddr(@A.Data)^.sa_family = AF_INET then
    Result := NetAddrToStr(PInetSockAddr(@A.Data)^.sin_addr)
  else if PSockAddr(@A.Data)^.sa_family = AF_INET6 then
    Result := '[' + NetAddrToStr6(PInetSockAddr6(@A.Data)^.sin6_addr) + ']'
  else
    Exit;
  Result := Result + ':' + NumStr(SockLocalPort(S));
end;

function SockLocalPort(S: tSock): Word;
var
  A: tSockAddr;
  L: TSockLen;
begin
  Result := 0;
  L := SizeOf(A.Data);
  if fpGetSockName(S, PSockAddr(@A.Data), @L) = 0 then
    { sin_port and sin6_port sit at the same offset, network order }
    Result := (Word(A.Data[2]) shl 8) or A.Data[3];
end;

end.
