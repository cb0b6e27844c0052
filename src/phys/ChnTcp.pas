{ ChnTcp - NAM=TCP, a serial line at a TCP port (docs/ChnTcp.md).

  The physical layer of a serial device server (Moxa NPort, Lantronix,
  Digi, ser2net): the same contract as NAM=COM - a message is a chunk of raw
  bytes, polled with ChReceiveReady/ChReceive/ChSend/ChSendReady, IDL=, LRB=,
  LSB= - because it is a tChnPhys (the physical base, unit ChnPhys) whose
  port is a TCP connection (ChnPortTcp). Parameters (ChGetParam reports them all):

    HOST=name   server name or IPv4/IPv6 address (client)
    PORT=n      its TCP port, 1..65535
    LISTEN=[addr:]port   serve instead: one client at a time; without addr
                the loopback interface only ([::1]:port for IPv6; 0.0.0.0
                or [::] for every interface must be written out)
    KICK=OFF|ON (server) ON: a new connection takes the line from the
                client served (ser2net's kickolduser); OFF: it is closed
    IDLE=ms     (server) close a client that sent nothing for ms, 0 = never
    CTO=ms      bound of a connect and of the RFC 2217 answers, default 3000
    RECON=ms    0 (default): a lost connection stays lost until ChClose +
                ChOpen; n: try again every n ms by itself, results say
                res_Reconnecting meanwhile (ignored with LISTEN=). The
                mechanism is tChnPhys's (ComReopen); this layer supplies the
                new connection: a non-blocking connect bounded by CTO, the
                first at once after the loss, then BD.. FLW sent again
    RFC2217=OFF|ON  Telnet COM Port Control: BD BIT PAR STOP FLW set the
                server's serial port, checked against its answers
    BD BIT STOP PAR FLW LRB LSB IDL   as NAM=COM (BD.. FLW only with RFC2217;
                raw, they are reported back and the server's own settings
                apply)

  Faults: name not resolved res_HostUnknown, connection refused
  res_Refused, no connection within CTO res_Timeout, address in use
  res_CannotOpen, a setting refused or changed by the server res_BadSetting
  - all leave the layer closed and ChParamError names the token at fault;
  peer closed or reset mid-session res_DeviceLost (or res_Reconnecting with
  RECON=) from the next poll on, as COM's lost device. }
unit ChnTcp;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnPort, ChnPhys, ChnPortTcp;

const
  cName = 'TCP';
  TcpDefaultCto = 3000;

type
  pChnTcp = ^tChnTcp;
  tChnTcp = object(tChnPhys)
    CH_Host    : tWordString;      {< HOST= }
    CH_TcpPort : LongInt;          {< PORT=, 0 = not given }
    CH_Listen  : tWordString;      {< LISTEN= as given, '' = client }
    CH_Cto     : LongInt;          {< CTO= }
    CH_Rfc     : Boolean;          {< RFC2217= }
    CH_Kick    : Boolean;          {< KICK= (server) }
    CH_IdleDrop: LongInt;          {< IDLE= ms (server), 0 = off }
    CH_RetryEnd: QWord;            {< the reconnect in progress gives up then (CTO=) }
    CH_Standby : LongInt;          {< standby connections a server keeps (ChSetStandby) }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    {- --- additions --- }
    { The local TCP port: with LISTEN=...:0 the one the OS picked. }
    function  ChLocalPort: Word;
    { A server (LISTEN=) has a client now. }
    function  ChHasClient: Boolean;
    { The listening socket (tests ask the OS what it is bound to). }
    function  ChListenHandle: PtrInt;
    { The connection in use: a number no other connection of the process
      had, 0 while there is none (a server without client, a client lost
      or reconnecting). }
    function  ChSession: LongWord;
    { LISTEN= was given: the layer serves instead of connecting. }
    function  ChIsServer: Boolean;
    { Close the connection in use because the protocol above found it
      broken: a server waits for its next client, a client is lost
      (res_DeviceLost; with RECON= it connects again). }
    procedure ChHangUp;
    { Server: keep up to N further connections besides the one served
      (before ChOpen; IEC 104 redundancy); 0 turns them away (default). }
    procedure ChSetStandby(N: LongInt);
    { The standby connections: how many, their numbers, non-blocking I/O
      (res_DeviceLost: gone, hang it up), closing one, and making one the
      connection served (the one served so far becomes a standby one; what
      it had sent and was not read is dropped). }
    function  ChStandbyCount: LongInt;
    function  ChStandbySession(I: LongInt): LongWord;
    function  ChStandbyRead(I: LongInt; var Buf; Size: LongInt; out Got: LongInt): tChResult;
    function  ChStandbySend(I: LongInt; const Buf; Len: LongInt): tChResult;
    procedure ChStandbyHangUp(I: LongInt);
    procedure ChPromote(I: LongInt);
    { CTO= from a layer above that has its own name for it (IEC 104's t0) }
    procedure ChSetConnectMs(Ms: LongInt);
  protected
    function  ComOpenPort(out Port: TChnPort): tChResult; virtual;
    function  ComDropsWhenFull: Boolean; virtual;
    function  ComReopenBegins: Boolean; virtual;
    function  ComReopenStart(out Port: TChnPort): tChResult; virtual;
    function  ComReopenPoll(Port: TChnPort): tChResult; virtual;
  private
    function  TcpNewPort: TChnPortTcp;
  end;

  pAddChnTcp = ^tAddChnTcp;
  tAddChnTcp = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ Split 'addr:port', 'port' or '[v6addr]:port'; False when malformed. }
function SplitHostPort(const S: ShortString; out Host: ShortString; out Port: LongInt): Boolean;

implementation

uses
  SysUtils, uString, ChnRing;

function SplitHostPort(const S: ShortString; out Host: ShortString; out Port: LongInt): Boolean;
var
  P: Integer;
  PortText: string;
begin
  Host := '';
  Port := 0;
  if (S <> '') and (S[1] = '[') then
  begin
    P := Pos(']:', S);
    if P < 3 then
      Exit(False);
    Host := Copy(S, 2, P - 2);
    PortText := Copy(S, P + 2, 255);
  end
  else
  begin
    P := Length(S);
    while (P > 0) and (S[P] <> ':') do
      Dec(P);
    Host := Copy(S, 1, P - 1);
    PortText := Copy(S, P + 1, 255);
    if (P > 0) and ((Host = '') or (Pos(':', Host) > 0)) then
      Exit(False);                  { ':5000', or IPv6 without brackets }
  end;
  Result := StrToNum(PortText, 0, 65535, Port);
end;

constructor tChnTcp.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Host := '';
  CH_TcpPort := 0;
  CH_Listen := '';
  CH_Cto := TcpDefaultCto;
  CH_Standby := 0;
  CH_Rfc := False;
  CH_Kick := False;
  CH_IdleDrop := 0;
  CH_RetryEnd := 0;
end;

constructor tChnTcp.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

function tChnTcp.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  H: ShortString;
  N: LongInt;
begin
  Key := ParamKey(S);
  if Key = 'HOST' then
  begin
    Result := res_Ok;
    if ParamValue(S) = '' then
      Result := res_BadParam;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Host := ParamValue(S);
  end
  else if Key = 'PORT' then
    Result := ParamSetNum(S, 1, 65535, CmdL, CH_TcpPort)
  else if Key = 'LISTEN' then
  begin
    if SplitHostPort(ParamValue(S), H, N) then
      Result := res_Ok
    else
      Result := res_BadParam;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Listen := ParamValue(S);
  end
  else if Key = 'CTO' then
    Result := ParamSetNum(S, 1, 600000, CmdL, CH_Cto)
  else if Key = 'RFC2217' then
    Result := ParamFlag(S, 'OFF|ON', CmdL, CH_Rfc)
  else if Key = 'KICK' then
    Result := ParamFlag(S, 'OFF|ON', CmdL, CH_Kick)
  else if Key = 'IDLE' then
    Result := ParamSetNum(S, 0, 3600000, CmdL, CH_IdleDrop)
  else
  begin
    Result := PhysLineParam(S, CmdL);    { BD BIT STOP PAR FLW }
    if Result = res_UnknownParam then
      Result := inherited ChSetOneParam(S, CmdL);   { LRB LSB IDL RECON }
  end;
end;

function tChnTcp.ChOwnParams: tParamStr;
var
  R: string;
begin
  R := inherited ChOwnParams;
  if CH_Listen <> '' then
    R := R + ' LISTEN=' + CH_Listen + FlagText('KICK', 'OFF|ON', CH_Kick) +
      ParamText('IDLE', CH_IdleDrop)
  else
  begin
    if CH_Host <> '' then
      R := R + ' HOST=' + CH_Host;
    if CH_TcpPort <> 0 then
      R := R + ParamText('PORT', CH_TcpPort);
  end;
  Result := R + ParamText('CTO', CH_Cto) + ParamText('RECON', CH_Reopen) +
    FlagText('RFC2217', 'OFF|ON', CH_Rfc) + ComLineText(CH_Set) + ComBufferText;
end;

function tChnTcp.TcpNewPort: TChnPortTcp;
var
  H: ShortString;
  N: LongInt;
begin
  Result := TChnPortTcp.Create;
  Result.ConnectMs := CH_Cto;
  Result.Rfc2217 := CH_Rfc;
  if CH_Listen <> '' then
  begin
    SplitHostPort(CH_Listen, H, N);
    if H = '' then
      H := '127.0.0.1';             { never every interface by default }
    Result.IsServer := True;
    Result.Kick := CH_Kick;
    Result.IdleMs := CH_IdleDrop;
    Result.MaxStandby := CH_Standby;
    Result.Host := H;
    Result.Port := N;
  end
  else
  begin
    Result.Host := CH_Host;
    Result.Port := CH_TcpPort;
  end;
end;

function tChnTcp.ComOpenPort(out Port: TChnPort): tChResult;
var
  P: TChnPortTcp;
  Key: string;
begin
  Port := nil;
  Key := '';
  if CH_Listen <> '' then
  begin
    if CH_Host <> '' then
      Key := 'HOST'                 { a server has no peer to name }
    else if CH_Rfc then
      Key := 'RFC2217';             { the server side of RFC 2217 is not ours }
  end
  else if CH_Host = '' then
    Key := 'HOST'
  else if CH_TcpPort = 0 then
    Key := 'PORT'
  else if CH_Kick then
    Key := 'KICK'                   { a client has no line to give away }
  else if CH_IdleDrop <> 0 then
    Key := 'IDLE';
  if Key <> '' then
  begin
    CH_ParamErr := Key + '=';
    if Key = 'HOST' then
      CH_ParamErr := ChGetParam(Key)
    else if Key = 'KICK' then
      CH_ParamErr := 'KICK=ON'      { reported for a server only }
    else if Key = 'IDLE' then
      CH_ParamErr := 'IDLE=' + IntToStr(CH_IdleDrop);
    if CH_ParamErr = '' then
      CH_ParamErr := Key + '=';
    Exit(res_BadSetting);
  end;
  P := TcpNewPort;
  Result := P.Open('');
  if Result = res_Ok then
    Result := P.Configure(CH_Set);
  if Result = res_DeviceLost then
    Result := res_CannotOpen;       { closed while opening: its port is busy }
  if Result <> res_Ok then
  begin
    Key := P.FailKey;
    if Key = '' then
      if CH_Listen <> '' then
        Key := 'LISTEN'
      else if Result = res_Refused then
        Key := 'PORT'
      else
        Key := 'HOST';
    CH_ParamErr := ChGetParam(Key);
    CH_ErrWhy := P.OSErrorText;     { 'Connection refused' }
    P.Free;
    Exit;
  end;
  Port := P;
end;

{ TCP holds the sender back itself: a full ring leaves the bytes in the
  socket, nothing is lost (the device server's own line may still overrun;
  it reports that by NOTIFY-LINESTATE). }
function tChnTcp.ComDropsWhenFull: Boolean;
begin
  Result := False;
end;

{ RECON=, the parts tChnPhys.ComReopen leaves to the port kind: a server
  waits for its next client by itself and a refused setting stays; else
  the first attempt is at once (a reset connection usually has its server
  still there), the lost socket stays until a new one replaces it. }
function tChnTcp.ComReopenBegins: Boolean;
begin
  Result := (CH_Listen = '') and (CH_Fault <> res_BadSetting);
  if Result then
    CH_ReopenAt := 0;
end;

{ A connect that does not block the poll; CTO= bounds it (ComReopenPoll). }
function tChnTcp.ComReopenStart(out Port: TChnPort): tChResult;
begin
  Port := TcpNewPort;
  CH_RetryEnd := GetTickCount64 + QWord(CH_Cto);
  Result := TChnPortTcp(Port).StartConnect;   { res_Busy or a failure }
  if Result <> res_Busy then
    FreeAndNil(Port);
end;

function tChnTcp.ComReopenPoll(Port: TChnPort): tChResult;
begin
  Result := TChnPortTcp(Port).ConnectPoll;
  if Result = res_Ok then
    TChnPortTcp(Port).SendSettings(CH_Set)   { answers are checked as they come }
  else if (Result = res_Busy) and (GetTickCount64 >= CH_RetryEnd) then
    Result := res_Timeout;
end;

function tChnTcp.ChLocalPort: Word;
begin
  if CH_Port = nil then
    Result := 0
  else
    Result := TChnPortTcp(CH_Port).LocalPort;
end;

function tChnTcp.ChHasClient: Boolean;
begin
  Result := (CH_Port <> nil) and TChnPortTcp(CH_Port).HasClient;
end;

function tChnTcp.ChListenHandle: PtrInt;
begin
  if CH_Port = nil then
    Result := -1
  else
    Result := TChnPortTcp(CH_Port).ListenHandle;
end;

function tChnTcp.ChSession: LongWord;
begin
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Result := 0
  else
    Result := TChnPortTcp(CH_Port).Session;
end;

function tChnTcp.ChIsServer: Boolean;
begin
  Result := CH_Listen <> '';
end;

procedure tChnTcp.ChHangUp;
begin
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Exit;
  TChnPortTcp(CH_Port).HangUp;
  if CH_Listen = '' then
    ComFault(res_DeviceLost);
end;

procedure tChnTcp.ChSetStandby(N: LongInt);
begin
  CH_Standby := N;
end;

function tChnTcp.ChStandbyCount: LongInt;
begin
  if CH_Port = nil then
    Result := 0
  else
    Result := TChnPortTcp(CH_Port).StandbyCount;
end;

function tChnTcp.ChStandbySession(I: LongInt): LongWord;
begin
  Result := TChnPortTcp(CH_Port).StandbySession(I);
end;

function tChnTcp.ChStandbyRead(I: LongInt; var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  Result := TChnPortTcp(CH_Port).StandbyRead(I, Buf, Size, Got);
end;

function tChnTcp.ChStandbySend(I: LongInt; const Buf; Len: LongInt): tChResult;
begin
  Result := TChnPortTcp(CH_Port).StandbyWrite(I, Buf, Len);
end;

procedure tChnTcp.ChStandbyHangUp(I: LongInt);
begin
  TChnPortTcp(CH_Port).StandbyHangUp(I);
end;

procedure tChnTcp.ChPromote(I: LongInt);
begin
  RingClear(CH_Ring);               { the bytes of the connection served so far }
  TChnPortTcp(CH_Port).Promote(I);
end;

procedure tChnTcp.ChSetConnectMs(Ms: LongInt);
begin
  CH_Cto := Ms;
end;

function tAddChnTcp.ChInit: pChnVirt;
begin
  Result := New(pChnTcp, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnTcp, Init(cName)));
end.
