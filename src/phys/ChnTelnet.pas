{ ChnTelnet - the Telnet byte stream and RFC 2217 (Telnet COM Port Control
  option) as a pure codec: no sockets, no objects, no I/O. ChnPortTcp glues
  it to a connection (docs/ChnTcp.md).

  Decoding: TelnetFeed takes the received bytes one by one and says what
  each completed: a data byte (IAC IAC gives one $FF), an option request
  (IAC WILL/WONT/DO/DONT opt), a subnegotiation (IAC SB opt ... IAC SE, with
  doubled IACs undone) or nothing yet. A subnegotiation longer than
  TelnetMaxSub is cut and flagged, never overruns; one still not closed
  after TelnetSubLimit bytes is teSubBroken (a peer that never sends IAC SE
  would otherwise swallow the whole data stream after it).

  Negotiation: TelnetAnswer decides the reply to an option request with the
  loop avoidance of RFC 1143 (answer only a request that changes the
  state): this client wants BINARY both ways (8-bit clean data), SGA both
  ways, and to use COM-PORT-OPTION (44) itself; everything else is refused.

  Encoding: TelnetEscape doubles $FF in data; TelnetCmd and ComPortCmd build
  option requests and COM-PORT-OPTION subnegotiations (client codes 0..12;
  the server answers with the code + 100). }
unit ChnTelnet;

{$I chn.inc}

interface

const
  TN_SE   = 240;
  TN_NOP  = 241;
  TN_SB   = 250;
  TN_WILL = 251;
  TN_WONT = 252;
  TN_DO   = 253;
  TN_DONT = 254;
  TN_IAC  = 255;

  TNO_BINARY  = 0;
  TNO_ECHO    = 1;
  TNO_SGA     = 3;
  TNO_COMPORT = 44;

  { COM-PORT-OPTION commands, client to server; server answers + 100 }
  CPO_SIGNATURE      = 0;
  CPO_SETBAUDRATE    = 1;
  CPO_SETDATASIZE    = 2;
  CPO_SETPARITY      = 3;
  CPO_SETSTOPSIZE    = 4;
  CPO_SETCONTROL     = 5;
  CPO_NOTIFYLINE     = 6;
  CPO_NOTIFYMODEM    = 7;
  CPO_FLOWSUSPEND    = 8;
  CPO_FLOWRESUME     = 9;
  CPO_SETLINEMASK    = 10;
  CPO_SETMODEMMASK   = 11;
  CPO_PURGEDATA      = 12;
  CPO_SERVER         = 100;

  { SET-PARITY values }
  CPP_NONE = 1; CPP_ODD = 2; CPP_EVEN = 3; CPP_MARK = 4; CPP_SPACE = 5;
  { SET-CONTROL values }
  CPC_FLOWNONE = 1; CPC_FLOWXON = 2; CPC_FLOWHW = 3;
  CPC_DTRON = 8; CPC_DTROFF = 9; CPC_RTSON = 11; CPC_RTSOFF = 12;
  { PURGE-DATA values: the access server's receive / transmit buffer / both }
  CPU_RX = 1; CPU_TX = 2; CPU_BOTH = 3;
  { NOTIFY-LINESTATE bits }
  CPL_OVERRUN = $02; CPL_PARITY = $04; CPL_FRAMING = $08; CPL_BREAK = $10;
  { NOTIFY-MODEMSTATE bits }
  CPM_CTS = $10; CPM_DSR = $20; CPM_RI = $40; CPM_CD = $80;

  TelnetMaxSub = 64;      {< longest subnegotiation kept (RFC 2217 needs 6) }
  TelnetSubLimit = 256;   {< bytes of one subnegotiation before it is broken }

type
  { teSubBroken: TelnetSubLimit bytes after IAC SB without IAC SE; the
    decoder is back in data mode, the bytes in between are not data }
  tTelnetEvent = (teNone, teData, teOption, teSub, teSubBroken);

  tTelnetDecoder = record
    St      : Byte;           {< automaton state, private }
    Cmd     : Byte;           {< teOption: TN_WILL/WONT/DO/DONT }
    Opt     : Byte;           {< teOption, teSub: the option }
    Sub     : array[0..TelnetMaxSub - 1] of Byte;  {< teSub: data after opt }
    SubLen  : Word;
    SubCut  : Boolean;        {< teSub: longer than TelnetMaxSub, cut }
    SubSeen : Word;           {< bytes since IAC SB opt, private }
  end;

  { What each side has agreed for one option (RFC 1143 "Q method" reduced
    to yes/no: this client never has two requests in flight). }
  tTelnetOptState = record
    Us  : Boolean;            {< we WILL (the peer said DO) }
    Him : Boolean;            {< the peer WILL (we said DO) }
    UsAsked, HimAsked: Boolean;  {< our WILL / DO is unanswered }
  end;
  tTelnetNeg = array[Byte] of tTelnetOptState;

procedure TelnetInit(out D: tTelnetDecoder);
{ Feed one received byte. teData: B is a data byte for the application. }
function  TelnetFeed(var D: tTelnetDecoder; B: Byte): tTelnetEvent;

procedure TelnetNegInit(out N: tTelnetNeg);
{ Note that we sent WILL (Cmd = TN_WILL) or DO (TN_DO) for Opt. }
procedure TelnetAsked(var N: tTelnetNeg; Cmd, Opt: Byte);
{ The reply to the peer's request Cmd for Opt, or 0 when none is due (the
  request confirms the current state or answers ours). }
function  TelnetAnswer(var N: tTelnetNeg; Cmd, Opt: Byte): Byte;

{ Copy Src to Dst doubling every $FF. Stops when the next byte does not fit
  in DstCap; Used = source bytes taken, result = bytes written. }
function  TelnetEscape(const Src; SrcLen: LongInt; var Dst; DstCap: LongInt;
  out Used: LongInt): LongInt;
{ IAC Cmd Opt into Dst (3 bytes); returns 3. }
function  TelnetCmd(var Dst; Cmd, Opt: Byte): LongInt;
{ IAC SB 44 Code Value... IAC SE into Dst (at most 6 + 2 * ValLen bytes),
  IACs in the value doubled; returns the length. }
function  ComPortCmd(var Dst; Code: Byte; const Value; ValLen: LongInt): LongInt;
{ The 4-byte big-endian value of SET-BAUDRATE and back. }
procedure BaudToBytes(Baud: LongWord; var B: array of Byte);
function  BytesToBaud(const B: array of Byte; Ofs: LongInt): LongWord;

implementation

const
  stData = 0; stIac = 1; stOpt = 2; stSub = 3; stSubIac = 4; stSubOpt = 5;

procedure TelnetInit(out D: tTelnetDecoder);
begin
  FillChar(D, SizeOf(D), 0);
end;

function TelnetFeed(var D: tTelnetDecoder; B: Byte): tTelnetEvent;

  { one byte of a subnegotiation's value: kept while there is room }
  procedure SubByte(V: Byte);
  begin
    if D.SubLen < TelnetMaxSub then
    begin
      D.Sub[D.SubLen] := V;
      Inc(D.SubLen);
    end
    else
      D.SubCut := True;
    Inc(D.SubSeen);
    if D.SubSeen >= TelnetSubLimit then
    begin
      D.St := stData;                    { never closed: give up, say so }
      Result := teSubBroken;
    end;
  end;

begin
  Result := teNone;
  case D.St of
    stData:
      if B = TN_IAC then
        D.St := stIac
      else
        Result := teData;
    stIac:
      case B of
        TN_IAC:
          begin
            D.St := stData;
            Result := teData;              { IAC IAC: one $FF }
          end;
        TN_WILL, TN_WONT, TN_DO, TN_DONT:
          begin
            D.Cmd := B;
            D.St := stOpt;
          end;
        TN_SB:
          D.St := stSubOpt;
      else
        D.St := stData;                  { NOP, GA, DM, a lone SE ...: ignored }
      end;
    stOpt:
      begin
        D.Opt := B;
        D.St := stData;
        Result := teOption;
      end;
    stSubOpt:
      begin
        D.Opt := B;
        D.SubLen := 0;
        D.SubCut := False;
        D.SubSeen := 0;
        D.St := stSub;
      end;
    stSub:
      if B = TN_IAC then
        D.St := stSubIac
      else
        SubByte(B);
    stSubIac:
      if B = TN_IAC then
      begin
        D.St := stSub;                   { a doubled $FF inside the value }
        SubByte(TN_IAC);
      end
      else
      begin
        { IAC SE ends it; any other command ends it too (RFC 854 says a
          subnegotiation is closed by IAC SE; a sender that forgot it must
          not swallow the data stream) }
        D.St := stData;
        Result := teSub;
      end;
  end;
end;

procedure TelnetNegInit(out N: tTelnetNeg);
begin
  FillChar(N, SizeOf(N), 0);
end;

procedure TelnetAsked(var N: tTelnetNeg; Cmd, Opt: Byte);
begin
  if Cmd = TN_WILL then
    N[Opt].UsAsked := True
  else if Cmd = TN_DO then
    N[Opt].HimAsked := True;
end;

{ Options we do ourselves when asked, and options we want the peer to do. }
function WeWill(Opt: Byte): Boolean;
begin
  Result := Opt in [TNO_BINARY, TNO_SGA, TNO_COMPORT];
end;

function WeWant(Opt: Byte): Boolean;
begin
  Result := Opt in [TNO_BINARY, TNO_SGA];
end;

function TelnetAnswer(var N: tTelnetNeg; Cmd, Opt: Byte): Byte;
var
  S: ^tTelnetOptState;
  Asked: Boolean;
begin
  Result := 0;
  S := @N[Opt];
  case Cmd of
    TN_DO:
      begin
        Asked := S^.UsAsked;
        S^.UsAsked := False;
        if S^.Us then
          Exit;                          { already on: no reply (RFC 1143) }
        if WeWill(Opt) then
        begin
          S^.Us := True;
          if not Asked then
            Result := TN_WILL;
        end
        else
          Result := TN_WONT;
      end;
    TN_DONT:
      begin
        S^.UsAsked := False;             { a refused WILL of ours needs no reply }
        if S^.Us then
        begin
          S^.Us := False;
          Result := TN_WONT;
        end;
      end;
    TN_WILL:
      begin
        Asked := S^.HimAsked;
        S^.HimAsked := False;
        if S^.Him then
          Exit;
        if WeWant(Opt) then
        begin
          S^.Him := True;
          if not Asked then
            Result := TN_DO;
        end
        else
          Result := TN_DONT;
      end;
    TN_WONT:
      begin
        S^.HimAsked := False;
        if S^.Him then
        begin
          S^.Him := False;
          Result := TN_DONT;
        end;
      end;
  end;
end;

function TelnetEscape(const Src; SrcLen: LongInt; var Dst; DstCap: LongInt;
  out Used: LongInt): LongInt;
var
  S, D: PByte;
  I, O: LongInt;
begin
  S := @Src;
  D := @Dst;
  I := 0;
  O := 0;
  while I < SrcLen do
  begin
    if S[I] = TN_IAC then
    begin
      if O + 2 > DstCap then
        Break;
      D[O] := TN_IAC;
      D[O + 1] := TN_IAC;
      Inc(O, 2);
    end
    else
    begin
      if O + 1 > DstCap then
        Break;
      D[O] := S[I];
      Inc(O);
    end;
    Inc(I);
  end;
  Used := I;
  Result := O;
end;

function TelnetCmd(var Dst; Cmd, Opt: Byte): LongInt;
var
  D: PByte;
begin
  D := @Dst;
  D[0] := TN_IAC;
  D[1] := Cmd;
  D[2] := Opt;
  Result := 3;
end;

function ComPortCmd(var Dst; Code: Byte; const Value; ValLen: LongInt): LongInt;
var
  D: PByte;
  Used: LongInt;
begin
  D := @Dst;
  D[0] := TN_IAC;
  D[1] := TN_SB;
  D[2] := TNO_COMPORT;
  D[3] := Code;
  Result := 4 + TelnetEscape(Value, ValLen, D[4], 2 * ValLen, Used);
  D[Result] := TN_IAC;
  D[Result + 1] := TN_SE;
  Inc(Result, 2);
end;

procedure BaudToBytes(Baud: LongWord; var B: array of Byte);
begin
  B[0] := Byte(Baud shr 24);
  B[1] := Byte(Baud shr 16);
  B[2] := Byte(Baud shr 8);
  B[3] := Byte(Baud);
end;

function BytesToBaud(const B: array of Byte; Ofs: LongInt): LongWord;
begin
  Result := (LongWord(B[Ofs]) shl 24) or (LongWord(B[Ofs + 1]) shl 16) or
    (LongWord(B[Ofs + 2]) shl 8) or LongWord(B[Ofs + 3]);
end;

end.
