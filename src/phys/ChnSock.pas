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
    seWouldBlock,     {< nothing now (no data, no room, connect in progress) }
    seNoHost,         {< name not resolved }
    seRefused,        {< connection refused }
    seTimeout,        {< connect did not complete in time }
    seLost,           {< peer closed or reset the connection }
    seInUse,          {< address in use (listen) }
    seAccess,         {< not allowed (privileged port, firewall) }
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
{ A TCP port on 127.0.0.1 that nothing listens on right now (a test's or
  a benchmark's server); 0 when none can be bound. }
function  SockFreeLoopbackPort: Word;
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
{ What the program-wide wait watches for several sockets at once (a
  server's listening socket and the client it serves, whose descriptor
  changes with each client): on Linux an epoll descriptor, readable while
  one of its sockets is; on Windows an event that WSAEventSelect sets on a
  connection, input or a close of any of them (wait kind wkHandle; re-arm
  it with SockGroupRearm); NoSock on other systems. Remove a socket before
  closing it (a new socket may get its number). }
function  SockGroupCreate: tSock;
procedure SockGroupAdd(G, S: tSock);
procedure SockGroupRemove(G, S: tSock);
{ Windows: reset the group's event, and set it again at once when one of
  Socks is still readable (a connection waiting, input, a close: Winsock
  signals each only once until it is taken). Nothing elsewhere. }
procedure SockGroupRearm(G: tSock; const Socks: array of tSock);
procedure SockGroupFree(var G: tSock);
{ The OS error code of the last failing call, for messages. }
function  SockLastOsError: LongInt;

implementation

uses
  {$IFDEF WINDOWS}WinSock2,{$ELSE}BaseUnix, Unix, {$IFDEF LINUX}Linux, {$ENDIF}ChnUnix,{$ENDIF} Sockets, SysUtils, uString;

const
  AI_PASSIVE = 1;
  { connections the OS completes before the server takes them: a burst of
    reconnects must not find the queue full (a dropped SYN is retried only
    after a second); a server takes them all at its next poll }
  ListenBacklog = 128;

{ the OS part: struct addrinfo, error codes, non-blocking mode, waiting,
  event handles, keep-alive timing }
{$IFDEF UNIX}{$I unix/chnsock.inc}{$ENDIF}
{$IFDEF WINDOWS}{$I win/chnsock.inc}{$ENDIF}

function SockLastOsError: LongInt;
begin
  Result := LastOsError;
end;

procedure SockClose(var S: tSock);
begin
  if S <> NoSock then
    CloseSocket(S);
  S := NoSock;
end;

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
  if BadSocket(S) then
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
  fpSetSockOpt(S, SOL_SOCKET, ListenReuse, @One, SizeOf(One));
  if (fpBind(S, PSockAddr(@A.Data), A.Len) <> 0) or (fpListen(S, ListenBacklog) <> 0) then
  begin
    Result := MapError(SocketError);
    SockClose(S);
  end;
end;

function SockAccept(L: tSock; out S: tSock): tSockErr;
begin
  S := fpAccept(L, nil, nil);
  if BadSocket(S) then
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
var
  One: LongInt;
begin
  One := 1;
  fpSetSockOpt(S, IPPROTO_TCP, TCP_NODELAY, @One, SizeOf(One));
  fpSetSockOpt(S, SOL_SOCKET, SO_KEEPALIVE, @One, SizeOf(One));
  OsTune(S);
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
  N := fpSend(S, @Buf, Len, SendFlags);
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

function SockFreeLoopbackPort: Word;
var
  A: tSockAddrs;
  N: LongInt;
  S: tSock;
begin
  Result := 0;
  if (SockResolve('127.0.0.1', 0, True, A, N) = seOk) and (SockListen(A[0], S) = seOk) then
  begin
    Result := SockLocalPort(S);
    SockClose(S);
  end;
end;

end.
