{ ChnPortTcp - a TChnPort on a TCP connection, the port under NAM=TCP
  (docs/ChnTcp.md). The socket calls are in ChnSock, the Telnet and RFC 2217
  codec in ChnTelnet; this unit glues them to the port interface tChnCom
  drives, so ring, send pump, overrun and idle wait are COM's own.

  Client: Connect (bounded by a timeout) or StartConnect + ConnectPoll (for
  reconnecting without blocking a poll). Server: Listen; one client at a
  time - a further connection is accepted and closed at once, or with Kick
  takes the line from the one served (ser2net's kickolduser); with IdleMs a
  client that sends nothing for that long is closed, so no squatter holds
  the line for ever; a client that leaves is an idle line, not a fault, and
  the next one is taken.

  With Rfc2217 the stream is Telnet: BINARY both ways, COM-PORT-OPTION
  used by us. Configure sends the line settings and waits for the server's
  answers; an answer that differs from the request (or none in time) is
  res_BadSetting with FailKey naming the setting ('BD', 'BIT', 'PAR',
  'STOP', 'FLW', or 'RFC2217' when the server does not do the option).
  Answers arriving later (after a reconnect) are checked the same way and
  turn the next Read into res_BadSetting. NOTIFY-MODEMSTATE gives GetLines,
  NOTIFY-LINESTATE overrun bits count in OsOverruns; data bytes are never
  disturbed by either. Data that arrives before the negotiation is done is
  kept up to EarlyCap bytes; more is dropped and counted in OsOverruns (a
  server pushing megabytes must not grow the process without bound). A
  subnegotiation never closed (ChnTelnet's teSubBroken) ends the stream:
  the data before it is delivered, then every Read answers res_BadStream
  with FailKey 'RFC2217'. }
unit ChnPortTcp;

{$I chn.inc}

interface

uses
  ChnTypes, ChnPort, ChnWait, ChnSock, ChnTelnet;

type
  TChnPortTcp = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FSock, FListen: tSock;
    FAddrs: tSockAddrs;
    FAddrCount, FAddrNext: LongInt;
    FDec: tTelnetDecoder;
    FNeg: tTelnetNeg;
    FOut: array of Byte;            {< Telnet: encoded bytes not yet sent }
    FOutLen: LongInt;
    FEarly: array of Byte;          {< data that arrived while negotiating }
    FEarlyLen, FEarlyPos: LongInt;
    FWant: tPortSettings;           {< what Configure asked for }
    FAsked: array[CPO_SETBAUDRATE..CPO_SETCONTROL] of Boolean;  {< answer due }
    FBad: ShortString;                  {< a setting the server answered otherwise }
    FModem: Byte;                   {< last NOTIFY-MODEMSTATE }
    FLineOverruns: LongWord;
    FConnecting: Boolean;
    FSettingsDue: Boolean;          {< SendSettings before the server's DO }
    FEvent: PtrInt;                 {< Windows: the client socket's wait event }
    FDueUntil: QWord;               {< ... which must come by then }
    FLastInput: QWord;              {< server: when the client last sent a byte }
    FEarlyLost: LongWord;           {< data beyond EarlyCap, dropped }
    FBroken: Boolean;               {< the peer broke the Telnet stream }
    FKicked, FIdleDropped: LongWord;
    FSession: LongWord;             {< this connection's number (NewSession) }
    FStandby: array of tSock;       {< server: connections kept besides the one served }
    FStandbySession: array of LongWord;  {< their numbers }
    { server on Linux: the program-wide wait watches the listening socket
      and the client served through this one descriptor (SockGroupCreate) }
    FGroup: tSock;
    FGroupSock: tSock;              {< the client socket in FGroup }
    FHeld: Boolean;                 {< FEarly counted in ChnWaitHeld }
    procedure NoteEarly;
    procedure NewSession;
    procedure GroupTakeClient;
    procedure GroupLoseClient;
    function SockResult(E: tSockErr): tChResult;
    function TryNextAddr: tSockErr;
    function Resolve(Passive: Boolean): tSockErr;
    procedure Started;
    procedure Queue(const Buf; Len: LongInt);
    function FlushOut: tChResult;
    procedure SendSetting(Code: Byte; const Value; Len: LongInt);
    function Take(var Buf; Size: LongInt; out Got: LongInt; Keep: Boolean): tChResult;
    procedure OnSub;
    function Answered: Boolean;
    function NegotiateStep: tChResult;
    function SetControl(V: Byte): tChResult;
    function SettingsOverdue: tChResult;
    function AcceptOne: Boolean;
    procedure TurnAway;
    procedure DropClient;
    procedure DropIdleClient;
    function ServeRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
  public
    { set before Open/Connect/Listen }
    Host       : ShortString;
    Port       : Word;
    ConnectMs  : LongInt;
    Rfc2217    : Boolean;
    { FailKey (TChnPort) after a failure: 'HOST', 'BD', ... }
    { Open ignores Path: Connect, or Listen when IsServer }
    IsServer   : Boolean;
    { server only: a new connection takes the line from the old one }
    Kick       : Boolean;
    { server only: close a client that sent nothing for IdleMs (0 = never) }
    IdleMs     : LongInt;
    MaxStandby : LongInt;           {< server only: further connections kept besides
                                         the one served (IEC 104 redundancy); 0: turned away }
    constructor Create; override;
    function Open(const Path: tWordString): tChResult; override;
    function Connect: tChResult;
    function Listen: tChResult;
    { Non-blocking connect for reconnecting: StartConnect, then ConnectPoll
      answers res_Busy while in progress, res_Ok when up. }
    function StartConnect: tChResult;
    function ConnectPoll: tChResult;
    function Configure(const S: tPortSettings): tChResult; override;
    { Configure without waiting for the answers (after a reconnect) }
    procedure SendSettings(const S: tPortSettings);
    function WaitInput(Ms: LongInt): Boolean; override;
    function WaitOutput(Ms: LongInt): Boolean; override;
    function OutQueue(out N: LongInt): tChResult; override;
    function Drain: tChResult; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    function SetRts(On: Boolean): tChResult; override;
    function SetDtr(On: Boolean): tChResult; override;
    function GetLines(out Lines: tPortLines): tChResult; override;
    function OsOverruns(out N: LongWord): tChResult; override;
    function OsHandle: PtrInt; override;
    { server: IdleMs is checked at every poll, input or not }
    procedure PollTimers; override;
    { data kept while negotiating, which the socket no longer shows }
    function HoldsInput: Boolean; override;
    { the program-wide wait (ChnWait): a client's socket on Unix; a
      server's listening and client socket together on Linux (one epoll
      descriptor), so a connection ends the wait too; Windows: a client's
      socket event, a server not at all (it waits on its own sockets) }
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    { the local port (a server on port 0 gets a free one) }
    function LocalPort: Word;
    function HasClient: Boolean;
    function ListenHandle: tSock;
    { server: clients closed by Kick, and for IdleMs without input }
    property Kicked: LongWord read FKicked;
    property IdleDropped: LongWord read FIdleDropped;
    { The connection served now, a number no other connection of this
      process had; 0 while there is none. A protocol above that keeps
      state per connection (IEC 104's sequence numbers) sees a new one. }
    function Session: LongWord;
    function StandbyCount: LongInt;
    function StandbySession(I: LongInt): LongWord;
    { non-blocking read / write on standby connection I; res_DeviceLost
      when it is gone (StandbyHangUp it then) }
    function StandbyRead(I: LongInt; var Buf; Size: LongInt; out Got: LongInt): tChResult;
    function StandbyWrite(I: LongInt; const Buf; Len: LongInt): tChResult;
    procedure StandbyHangUp(I: LongInt);
    { standby connection I becomes the one served; the one served so far
      takes its place among the standby ones }
    procedure Promote(I: LongInt);
    { Close the connection served now (a protocol above found the peer
      broke it): a server waits for the next client, a client's next read
      finds no connection. }
    procedure HangUp;
    procedure Close; override;
  end;

implementation

uses
  SysUtils;

const
  OutCap = 8192;           { encoded bytes held before Write says "full" }
  MaxLeftPerRead = 64;     { closed connections one server read works through }
  EarlyCap = 65536;        { data kept while RFC 2217 is negotiated }
  CtlReserve = 256;        { room kept for control commands }

constructor TChnPortTcp.Create;
begin
  inherited Create;
  FSock := NoSock;
  FListen := NoSock;
  FGroup := NoSock;
  FGroupSock := NoSock;
  ConnectMs := 3000;
  SetLength(FOut, OutCap + CtlReserve);
end;

function TChnPortTcp.SockResult(E: tSockErr): tChResult;
begin
  FOSError := SockLastOsError;
  case E of
    seOk: Result := res_Ok;
    seNoHost: begin Result := res_HostUnknown; FailKey := 'HOST'; end;
    seRefused: Result := res_Refused;
    seTimeout: Result := res_Timeout;
    seLost: Result := res_DeviceLost;
    seInUse: Result := res_CannotOpen;
    seAccess: Result := res_NoPermission;
  else
    Result := res_IOError;
  end;
end;

function TChnPortTcp.Open(const Path: tWordString): tChResult;
begin
  if IsServer then
    Result := Listen
  else
    Result := Connect;
end;

procedure TChnPortTcp.Started;
begin
  FOpen := True;
  FOutLen := 0;
  FEarlyLen := 0;
  FEarlyPos := 0;
  NoteEarly;
  FBad := '';
  FModem := 0;
  FLineOverruns := 0;
  FEarlyLost := 0;
  FBroken := False;
  FillChar(FAsked, SizeOf(FAsked), 0);
  FSettingsDue := False;
  TelnetInit(FDec);
  TelnetNegInit(FNeg);
end;

function TChnPortTcp.TryNextAddr: tSockErr;
begin
  Result := seNoHost;
  while FAddrNext < FAddrCount do
  begin
    Result := SockConnectStart(FAddrs[FAddrNext], FSock);
    Inc(FAddrNext);
    if Result in [seOk, seWouldBlock] then
      Exit;
  end;
end;

{ A fresh start: closed, no fault named, Host:Port resolved. }
function TChnPortTcp.Resolve(Passive: Boolean): tSockErr;
begin
  Close;
  FailKey := '';
  FDevice := Host + ':' + IntToStr(Port);
  Result := SockResolve(Host, Port, Passive, FAddrs, FAddrCount);
end;

function TChnPortTcp.StartConnect: tChResult;
var
  E: tSockErr;
begin
  E := Resolve(False);
  if E <> seOk then
    Exit(SockResult(E));
  FAddrNext := 0;
  E := TryNextAddr;
  if not (E in [seOk, seWouldBlock]) then
    Exit(SockResult(E));
  FConnecting := True;
  Result := res_Busy;
end;

{ A connected client in Telnet mode asks for what it wants at once. }
function TChnPortTcp.ConnectPoll: tChResult;
var
  E: tSockErr;
  B: array[0..8] of Byte;
begin
  if not FConnecting then
    Exit(res_WrongState);
  E := SockConnectDone(FSock, 0);
  while not (E in [seOk, seWouldBlock]) do
  begin
    { this address failed: the next one (IPv6 and IPv4 of one name) }
    SockClose(FSock);
    if FAddrNext >= FAddrCount then
    begin
      FConnecting := False;
      Exit(SockResult(E));          { the last address's reason }
    end;
    E := TryNextAddr;
    if E = seOk then
      E := SockConnectDone(FSock, 0)
    else if E = seWouldBlock then
      E := SockConnectDone(FSock, 0);
  end;
  if E = seWouldBlock then
    Exit(res_Busy);
  FConnecting := False;
  Started;
  NewSession;
  FEvent := SockEventCreate(FSock);
  if Rfc2217 then
  begin
    TelnetCmd(B[0], TN_WILL, TNO_COMPORT);
    TelnetCmd(B[3], TN_WILL, TNO_BINARY);
    TelnetCmd(B[6], TN_DO, TNO_BINARY);
    TelnetAsked(FNeg, TN_WILL, TNO_COMPORT);
    TelnetAsked(FNeg, TN_WILL, TNO_BINARY);
    TelnetAsked(FNeg, TN_DO, TNO_BINARY);
    Queue(B, 9);
    FlushOut;
  end;
  Result := res_Ok;
end;

function TChnPortTcp.Connect: tChResult;
var
  Deadline: QWord;
begin
  Result := StartConnect;
  Deadline := GetTickCount64 + QWord(ConnectMs);
  while Result = res_Busy do
  begin
    if GetTickCount64 >= Deadline then
    begin
      Close;
      Exit(res_Timeout);
    end;
    SockWait([FSock], True, 10);
    Result := ConnectPoll;
  end;
  if Result <> res_Ok then
    Close;
end;

function TChnPortTcp.Listen: tChResult;
var
  E: tSockErr;
begin
  E := Resolve(True);
  if E = seOk then
    E := SockListen(FAddrs[0], FListen);
  if E <> seOk then
  begin
    Result := SockResult(E);
    if E = seNoHost then
      FailKey := 'LISTEN';
    Exit;
  end;
  Started;
  FGroup := SockGroupCreate;        { NoSock where there is none: see WaitSource }
  SockGroupAdd(FGroup, FListen);
  Result := res_Ok;
end;

{ Server, line free: take the oldest waiting connection; False if none. }
function TChnPortTcp.AcceptOne: Boolean;
var
  S: tSock;
begin
  Result := (FListen <> NoSock) and (FSock = NoSock) and (SockAccept(FListen, S) = seOk);
  if not Result then
    Exit;
  FSock := S;
  FOutLen := 0;
  FLastInput := GetTickCount64;
  TelnetInit(FDec);
  GroupTakeClient;
  NewSession;
end;

{ Server, line held by a client just read from (so one that left is
  already gone): one client at a time, a further connection is closed at
  once - or, with Kick, takes the line from the one served. }
procedure TChnPortTcp.TurnAway;
var
  S: tSock;
  Kept: LongWord;
begin
  while (FSock <> NoSock) and (SockAccept(FListen, S) = seOk) do
    if Length(FStandby) < MaxStandby then
    begin
      SetLength(FStandby, Length(FStandby) + 1);
      SetLength(FStandbySession, Length(FStandby));
      FStandby[High(FStandby)] := S;
      if FGroup <> NoSock then
        SockGroupAdd(FGroup, S);
      Kept := FSession;              { the served one keeps its number }
      NewSession;
      FStandbySession[High(FStandby)] := FSession;
      FSession := Kept;
    end
    else if Kick then
    begin
      DropClient;
      Inc(FKicked);
      FSock := S;
      FLastInput := GetTickCount64;
      TelnetInit(FDec);
      GroupTakeClient;
      NewSession;
    end
    else
      SockClose(S);
end;

{ Data kept aside (while RFC 2217 is negotiated, by Configure or Write)
  is input the socket no longer shows: held, so ChnWaitAny ends at once
  and tChnCom reads it without waiting. }
procedure TChnPortTcp.NoteEarly;
begin
  ChnWaitHeld(FHeld, FEarlyPos < FEarlyLen);
end;

function TChnPortTcp.HoldsInput: Boolean;
begin
  Result := FEarlyPos < FEarlyLen;
end;

procedure TChnPortTcp.PollTimers;
begin
  if FOpen and (FListen <> NoSock) then
    DropIdleClient;
end;

{ With IdleMs, a client that sent nothing for that long is closed. }
procedure TChnPortTcp.DropIdleClient;
begin
  if (FSock <> NoSock) and (IdleMs > 0) and
    (GetTickCount64 - FLastInput >= QWord(IdleMs)) then
  begin
    DropClient;
    Inc(FIdleDropped);
  end;
end;

var
  LastSession: LongWord = 0;       { the last connection number given }

procedure TChnPortTcp.NewSession;
begin
  Inc(LastSession);
  if LastSession = 0 then
    LastSession := 1;
  FSession := LastSession;
end;

function TChnPortTcp.Session: LongWord;
begin
  if FOpen and not FConnecting and (FSock <> NoSock) then
    Result := FSession
  else
    Result := 0;
end;

procedure TChnPortTcp.HangUp;
begin
  if FSock = NoSock then
    Exit;
  if FListen <> NoSock then
    DropClient
  else
    SockClose(FSock);
end;

function TChnPortTcp.StandbyCount: LongInt;
begin
  Result := Length(FStandby);
end;

function TChnPortTcp.StandbySession(I: LongInt): LongWord;
begin
  Result := FStandbySession[I];
end;

function TChnPortTcp.StandbyRead(I: LongInt; var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  Result := SockResult(SockRecv(FStandby[I], Buf, Size, Got));
end;

function TChnPortTcp.StandbyWrite(I: LongInt; const Buf; Len: LongInt): tChResult;
var
  Done: LongInt;
begin
  Result := SockResult(SockSend(FStandby[I], Buf, Len, Done));
  if (Result = res_Ok) and (Done < Len) then
    Result := res_Busy;             { a few bytes of U frames: the OS takes them }
end;

procedure TChnPortTcp.StandbyHangUp(I: LongInt);
var
  J: LongInt;
begin
  if FGroup <> NoSock then
    SockGroupRemove(FGroup, FStandby[I]);
  SockClose(FStandby[I]);
  for J := I to High(FStandby) - 1 do
  begin
    FStandby[J] := FStandby[J + 1];
    FStandbySession[J] := FStandbySession[J + 1];
  end;
  SetLength(FStandby, Length(FStandby) - 1);
  SetLength(FStandbySession, Length(FStandby));
end;

procedure TChnPortTcp.Promote(I: LongInt);
var
  S: tSock;
  N: LongWord;
begin
  S := FStandby[I];
  N := FStandbySession[I];
  if FSock <> NoSock then
  begin
    GroupLoseClient;
    FStandby[I] := FSock;
    FStandbySession[I] := FSession;
    if FGroup <> NoSock then
      SockGroupAdd(FGroup, FSock);
  end
  else
    StandbyHangUp(I);               { nothing served: it only leaves the list }
  if FGroup <> NoSock then
    SockGroupRemove(FGroup, S);
  FSock := S;
  FSession := N;
  FOutLen := 0;
  FLastInput := GetTickCount64;
  TelnetInit(FDec);
  GroupTakeClient;
end;

procedure TChnPortTcp.DropClient;
begin
  GroupLoseClient;                  { out of the group before its number is free }
  SockClose(FSock);
  FOutLen := 0;
end;

{ FGroup holds FListen and the client served now: GroupTakeClient when a
  client is taken, GroupLoseClient before one is closed. }
procedure TChnPortTcp.GroupTakeClient;
begin
  GroupLoseClient;
  if (FGroup <> NoSock) and (FSock <> NoSock) then
  begin
    SockGroupAdd(FGroup, FSock);
    FGroupSock := FSock;
  end;
end;

procedure TChnPortTcp.GroupLoseClient;
begin
  if FGroupSock <> NoSock then
    SockGroupRemove(FGroup, FGroupSock);
  FGroupSock := NoSock;
end;

{ Server: read from the client served. One that left is closed and the
  next waiting connection taken at once (a burst of short connections is
  worked through in one poll, so a client behind them is not turned away
  by a dead one holding the line); then the idle and one-client rules. }
function TChnPortTcp.ServeRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  Left: LongInt;
begin
  Got := 0;
  Result := res_Ok;
  Left := 0;
  repeat
    if (FSock = NoSock) and not AcceptOne then
      Break;
    Result := Take(Buf, Size, Got, False);
    if Result <> res_DeviceLost then
      Break;
    DropClient;                     { the client left: wait for the next }
    Result := res_Ok;
    Inc(Left);
  until Left >= MaxLeftPerRead;
  if Result = res_Ok then
  begin
    DropIdleClient;
    TurnAway;
  end;
end;

function TChnPortTcp.ListenHandle: tSock;
begin
  Result := FListen;
end;

function TChnPortTcp.HasClient: Boolean;
begin
  Result := FSock <> NoSock;
end;

procedure TChnPortTcp.Queue(const Buf; Len: LongInt);
begin
  if FOutLen + Len > Length(FOut) then
    Exit;                           { a peer that reads nothing: dropped }
  Move(Buf, FOut[FOutLen], Len);
  Inc(FOutLen, Len);
end;

function TChnPortTcp.FlushOut: tChResult;
var
  Done: LongInt;
  E: tSockErr;
begin
  Result := res_Ok;
  if (FOutLen = 0) or (FSock = NoSock) then
    Exit;
  E := SockSend(FSock, FOut[0], FOutLen, Done);
  if E <> seOk then
    Exit(SockResult(E));
  if Done > 0 then
  begin
    Move(FOut[Done], FOut[0], FOutLen - Done);
    Dec(FOutLen, Done);
  end;
end;

procedure TChnPortTcp.SendSetting(Code: Byte; const Value; Len: LongInt);
var
  B: array[0..15] of Byte;
begin
  Queue(B, ComPortCmd(B, Code, Value, Len));
  if Code in [CPO_SETBAUDRATE..CPO_SETCONTROL] then
    FAsked[Code] := True;
end;

procedure TChnPortTcp.SendSettings(const S: tPortSettings);
const
  ParCodes: array[tPortParity] of Byte = (CPP_NONE, CPP_EVEN, CPP_ODD, CPP_MARK, CPP_SPACE);
  FlowCodes: array[tPortFlow] of Byte = (CPC_FLOWNONE, CPC_FLOWHW, CPC_FLOWXON);
var
  V: array[0..3] of Byte;
begin
  FWant := S;
  FBad := '';
  if not Rfc2217 then
    Exit;
  FSettingsDue := not FNeg[TNO_COMPORT].Us;
  if FSettingsDue then
  begin
    { no subnegotiation before the option is on; data waits for it too,
      so nothing leaves at the server's old settings }
    FDueUntil := GetTickCount64 + QWord(ConnectMs);
    Exit;
  end;
  BaudToBytes(S.Baud, V);
  SendSetting(CPO_SETBAUDRATE, V, 4);
  V[0] := S.DataBits;
  SendSetting(CPO_SETDATASIZE, V, 1);
  V[0] := ParCodes[S.Parity];
  SendSetting(CPO_SETPARITY, V, 1);
  V[0] := S.StopBits;
  SendSetting(CPO_SETSTOPSIZE, V, 1);
  V[0] := FlowCodes[S.Flow];
  SendSetting(CPO_SETCONTROL, V, 1);
  { the line-state mask is 0 by default: ask for overrun reports }
  V[0] := CPL_OVERRUN;
  SendSetting(CPO_SETLINEMASK, V, 1);
  FlushOut;
end;

{ A COM-PORT-OPTION message from the server. }
procedure TChnPortTcp.OnSub;
const
  ParCodes: array[tPortParity] of Byte = (CPP_NONE, CPP_EVEN, CPP_ODD, CPP_MARK, CPP_SPACE);
  FlowCodes: array[tPortFlow] of Byte = (CPC_FLOWNONE, CPC_FLOWHW, CPC_FLOWXON);

  procedure Check(Code: Byte; Ok: Boolean; const Key: string);
  begin
    if not FAsked[Code] then
      Exit;                         { not ours to check (an unsolicited report) }
    FAsked[Code] := False;
    if (not Ok) and (FBad = '') then
      FBad := Key;
  end;

var
  Code: Byte;
begin
  if (FDec.Opt <> TNO_COMPORT) or (FDec.SubLen < 1) or (FDec.Sub[0] < CPO_SERVER) then
    Exit;
  Code := FDec.Sub[0] - CPO_SERVER;
  with FDec do
    case Code of
      CPO_SETBAUDRATE:
        if SubLen >= 5 then
          Check(Code, BytesToBaud(Sub, 1) = LongWord(FWant.Baud), 'BD');
      CPO_SETDATASIZE:
        if SubLen >= 2 then
          Check(Code, Sub[1] = FWant.DataBits, 'BIT');
      CPO_SETPARITY:
        if SubLen >= 2 then
          Check(Code, Sub[1] = ParCodes[FWant.Parity], 'PAR');
      CPO_SETSTOPSIZE:
        if SubLen >= 2 then
          Check(Code, Sub[1] = FWant.StopBits, 'STOP');
      CPO_SETCONTROL:
        { the flow answer; DTR/RTS answers come unasked and pass }
        if (SubLen >= 2) and (Sub[1] <= CPC_FLOWHW) then
          Check(Code, Sub[1] = FlowCodes[FWant.Flow], 'FLW');
      CPO_NOTIFYLINE:
        if (SubLen >= 2) and (Sub[1] and CPL_OVERRUN <> 0) then
          Inc(FLineOverruns);
      CPO_NOTIFYMODEM:
        if SubLen >= 2 then
          FModem := Sub[1];
    end;
end;

function TChnPortTcp.Answered: Boolean;
var
  C: Byte;
begin
  Result := True;
  for C := Low(FAsked) to High(FAsked) do
    if FAsked[C] then
      Exit(False);
end;

{ Receive and decode: data into Buf (or, with Keep, into FEarly), Telnet
  commands handled on the way. }
function TChnPortTcp.Take(var Buf; Size: LongInt; out Got: LongInt; Keep: Boolean): tChResult;
var
  Raw: array[0..4095] of Byte;
  N, I: LongInt;
  E: tSockErr;
  Ans: Byte;
  R: array[0..2] of Byte;
  D: PByte;
begin
  Got := 0;
  D := @Buf;
  if Keep or (Size > SizeOf(Raw)) then
    Size := SizeOf(Raw);            { decoded data is never longer than raw }
  E := SockRecv(FSock, Raw, Size, N);
  if E <> seOk then
    Exit(SockResult(E));
  if N > 0 then
    FLastInput := GetTickCount64;
  if not Rfc2217 then
  begin
    Move(Raw, Buf, N);
    Got := N;
    Exit(res_Ok);
  end;
  for I := 0 to N - 1 do
    case TelnetFeed(FDec, Raw[I]) of
      teData:
        if Keep then
        begin
          if FEarlyLen >= EarlyCap then
            Inc(FEarlyLost)
          else
          begin
            if FEarlyLen >= Length(FEarly) then
              SetLength(FEarly, FEarlyLen + 4096);
            FEarly[FEarlyLen] := Raw[I];
            Inc(FEarlyLen);
          end;
        end
        else
        begin
          D[Got] := Raw[I];
          Inc(Got);
        end;
      teOption:
        begin
          Ans := TelnetAnswer(FNeg, FDec.Cmd, FDec.Opt);
          if Ans <> 0 then
            Queue(R, TelnetCmd(R, Ans, FDec.Opt));
          if FSettingsDue and FNeg[TNO_COMPORT].Us then
            SendSettings(FWant);
        end;
      teSub:
        OnSub;
      teSubBroken:
        begin
          FBroken := True;          { what follows is not to be trusted }
          FailKey := 'RFC2217';
          Break;
        end;
    end;
  if Keep then
    NoteEarly;
  Result := FlushOut;
end;

{ One look at the server while Configure waits for its answers: what it
  says is taken, data that comes with it is kept for DoRead. }
function TChnPortTcp.NegotiateStep: tChResult;
var
  Got: LongInt;
  Dummy: Byte;
begin
  SockWait([FSock], False, 10);
  Result := Take(Dummy, 1, Got, True);
  if (Result = res_Ok) and FBroken then
    Result := res_BadStream;
end;

function TChnPortTcp.Configure(const S: tPortSettings): tChResult;
var
  Deadline: QWord;
begin
  FWant := S;
  if not Rfc2217 then
    Exit(res_Ok);                   { the server's own settings apply }
  Deadline := GetTickCount64 + QWord(ConnectMs);
  { first the server's consent to COM-PORT-OPTION }
  while not FNeg[TNO_COMPORT].Us do
  begin
    if (GetTickCount64 >= Deadline) or not FNeg[TNO_COMPORT].UsAsked then
    begin
      FailKey := 'RFC2217';
      Exit(res_BadSetting);
    end;
    Result := NegotiateStep;
    if Result <> res_Ok then
      Exit;
  end;
  SendSettings(S);
  while not Answered do
  begin
    if GetTickCount64 >= Deadline then
      Break;
    Result := NegotiateStep;
    if Result <> res_Ok then
      Exit;
  end;
  if FBad = '' then
    if FAsked[CPO_SETBAUDRATE] then FBad := 'BD'
    else if FAsked[CPO_SETDATASIZE] then FBad := 'BIT'
    else if FAsked[CPO_SETPARITY] then FBad := 'PAR'
    else if FAsked[CPO_SETSTOPSIZE] then FBad := 'STOP'
    else if FAsked[CPO_SETCONTROL] then FBad := 'FLW';
  if FBad <> '' then
  begin
    FailKey := FBad;
    Exit(res_BadSetting);
  end;
  Result := res_Ok;
end;

function TChnPortTcp.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  N: LongInt;
begin
  if FEarlyPos < FEarlyLen then
  begin
    N := FEarlyLen - FEarlyPos;
    if N > Size then
      N := Size;
    Move(FEarly[FEarlyPos], Buf, N);
    Inc(FEarlyPos, N);
    Got := N;
    if FEarlyPos = FEarlyLen then
    begin
      FEarlyPos := 0;               { taken: the room is free again }
      FEarlyLen := 0;
      SetLength(FEarly, 0);
    end;
    NoteEarly;
    Exit(res_Ok);
  end;
  if FBroken then
    Exit(res_BadStream);
  if FListen <> NoSock then
    Result := ServeRead(Buf, Size, Got)
  else if FSock = NoSock then
    Exit(res_Ok)
  else
    Result := Take(Buf, Size, Got, False);
  if (Result = res_Ok) and FSettingsDue then
    Result := SettingsOverdue;
  if (Result = res_Ok) and (FBad <> '') then
  begin
    FailKey := FBad;
    Result := res_BadSetting;
  end;
end;

function TChnPortTcp.SettingsOverdue: tChResult;
begin
  Result := res_Ok;
  if FSettingsDue and (GetTickCount64 > FDueUntil) then
  begin
    FailKey := 'RFC2217';           { the server never agreed to the option }
    Result := res_BadSetting;
  end;
end;

function TChnPortTcp.WaitInput(Ms: LongInt): Boolean;
begin
  if FEarlyPos < FEarlyLen then
    Exit(True);
  Result := SockWait([FSock, FListen], False, Ms);
end;

function TChnPortTcp.WaitOutput(Ms: LongInt): Boolean;
begin
  if FSettingsDue then
    Result := SockWait([FSock], False, Ms)   { data waits for the server's DO }
  else
    Result := SockWait([FSock], True, Ms);
end;

function TChnPortTcp.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  E: tSockErr;
  Dummy: Byte;
  Got: LongInt;
begin
  if FSock = NoSock then
    AcceptOne;
  if FSock = NoSock then
  begin
    Done := Len;                    { no client: as a line with no cable }
    Exit(res_Ok);
  end;
  Result := FlushOut;
  if (Result = res_Ok) and FSettingsDue then
    Result := Take(Dummy, 1, Got, True);   { the server's DO may be waiting }
  if (Result = res_Ok) and FSettingsDue then
    Result := SettingsOverdue
  else if Result = res_Ok then
    if not Rfc2217 then
    begin
      if FOutLen = 0 then
      begin
        E := SockSend(FSock, Buf, Len, Done);
        Result := SockResult(E);
      end;
    end
    else if FOutLen < OutCap then
    begin
      Inc(FOutLen, TelnetEscape(Buf, Len, FOut[FOutLen], OutCap - FOutLen, Done));
      Result := FlushOut;
    end;
  if (Result = res_DeviceLost) and (FListen <> NoSock) then
  begin
    DropClient;
    Done := Len;
    Result := res_Ok;
  end;
end;

function TChnPortTcp.OutQueue(out N: LongInt): tChResult;
begin
  N := FOutLen + SockOutQueue(FSock);
  Result := res_Ok;
end;

function TChnPortTcp.Drain: tChResult;
begin
  Result := FlushOut;
end;

function TChnPortTcp.Flush(Input, Output: Boolean): tChResult;
var
  Scratch: array[0..4095] of Byte;
  Got, Rounds: LongInt;
  V: Byte;
begin
  Result := res_Ok;
  if FSock = NoSock then
    Exit;
  if Output then
    FOutLen := 0;                   { may cut a command; only on close }
  if Input then
  begin
    FEarlyLen := 0;
    FEarlyPos := 0;
    NoteEarly;
    Rounds := 0;
    repeat
      Result := Take(Scratch, SizeOf(Scratch), Got, False);
      Inc(Rounds);
    until (Result <> res_Ok) or (Got = 0) or (Rounds >= 64);
  end;
  if Rfc2217 and (Result = res_Ok) and (Input or Output) then
  begin
    if Input and Output then V := CPU_BOTH
    else if Input then V := CPU_RX
    else V := CPU_TX;
    SendSetting(CPO_PURGEDATA, V, 1);
    Result := FlushOut;
  end;
end;

{ SET-CONTROL value V (an RTS or DTR state): sent, no answer awaited }
function TChnPortTcp.SetControl(V: Byte): tChResult;
begin
  if not Rfc2217 then
    Exit(res_BadSetting);           { raw TCP carries no modem lines }
  SendSetting(CPO_SETCONTROL, V, 1);
  FAsked[CPO_SETCONTROL] := False;
  Result := FlushOut;
end;

function TChnPortTcp.SetRts(On: Boolean): tChResult;
const
  Code: array[Boolean] of Byte = (CPC_RTSOFF, CPC_RTSON);
begin
  Result := SetControl(Code[On]);
end;

function TChnPortTcp.SetDtr(On: Boolean): tChResult;
const
  Code: array[Boolean] of Byte = (CPC_DTROFF, CPC_DTRON);
begin
  Result := SetControl(Code[On]);
end;

function TChnPortTcp.GetLines(out Lines: tPortLines): tChResult;
begin
  Lines := [];
  if not Rfc2217 then
    Exit(res_BadSetting);
  if FModem and CPM_CTS <> 0 then Include(Lines, plCts);
  if FModem and CPM_DSR <> 0 then Include(Lines, plDsr);
  if FModem and CPM_RI <> 0 then Include(Lines, plRing);
  if FModem and CPM_CD <> 0 then Include(Lines, plCarrier);
  Result := res_Ok;
end;


function TChnPortTcp.OsOverruns(out N: LongWord): tChResult;
begin
  N := FLineOverruns + FEarlyLost;
  Result := res_Ok;
end;

{ A client's socket is fixed for the port's life (a reconnect makes a new
  port), so it joins the shared wait: its descriptor on Unix, an event of
  WSAEventSelect on Windows (re-armed after each read, set again while
  input waits). A server's sockets change with each client: it waits on
  them itself (WaitInput), bounded by IDL like any layer. }
procedure TcpRearm(Data: Pointer);
begin
  with TChnPortTcp(Data) do
    SockEventRearm(FSock, FEvent);
end;

procedure TcpGroupRearm(Data: Pointer);
begin
  with TChnPortTcp(Data) do
    SockGroupRearm(FGroup, [FListen, FSock]);
end;

function TChnPortTcp.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  {$IFDEF WINDOWS}
  Kind := wkHandle;
  Data := Self;
  if FListen <> NoSock then
  begin
    { a server: one event for its listening socket and its client }
    Os := FGroup;
    Rearm := @TcpGroupRearm;
    Result := FOpen and (FGroup <> NoSock);
  end
  else
  begin
    Os := FEvent;
    Rearm := @TcpRearm;
    Result := FOpen and (FSock <> NoSock) and (FEvent <> 0);
  end;
  {$ELSE}
  Kind := wkDescriptor;
  Rearm := nil;
  Data := nil;
  if FListen <> NoSock then
  begin
    { a server: the group of its listening socket and its client, so a
      connection, a client's input and its leaving all end the wait }
    Os := FGroup;
    Result := FOpen and (FGroup <> NoSock);
  end
  else
  begin
    Os := FSock;
    Result := FOpen and (FSock <> NoSock);
  end;
  {$ENDIF}
end;

function TChnPortTcp.OsHandle: PtrInt;
begin
  Result := FSock;
end;

function TChnPortTcp.LocalPort: Word;
begin
  if FListen <> NoSock then
    Result := SockLocalPort(FListen)
  else if FSock <> NoSock then
    Result := SockLocalPort(FSock)
  else
    Result := 0;
end;

procedure TChnPortTcp.Close;
begin
  if FOutLen > 0 then
    FlushOut;                       { a last command (purge ...) still leaves }
  GroupLoseClient;
  SockClose(FSock);
  while Length(FStandby) > 0 do
    StandbyHangUp(0);
  SockClose(FListen);
  SockGroupFree(FGroup);
  SockEventFree(FEvent);
  FEarlyLen := 0;
  FEarlyPos := 0;
  NoteEarly;
  FConnecting := False;
  FOpen := False;
end;

end.
