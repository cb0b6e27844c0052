{ ChnTypes - types, states, result codes and checksums shared by every layer
  of the Chn library.

  The SofCon manual of this unit was lost; the interface is reconstructed
  from how the ChnDF1, ChnFT1_2 and ChnICS manuals use it (docs/PROTOCOLS.md section 2).
  Names are binding for legacy code, numeric values of general results and
  states are this port's choice except res_Ok = 0. Protocol units number
  their own result codes from res_Proto ($20) and register readable texts
  for them with ChRegisterResultText. }
unit ChnTypes;

{$I chn.inc}

interface

type
  tParamStr   = string[255];  {< a whole parameter string }
  tWordString = string[255];  {< one KEY=VALUE token (device paths can be long) }
  tCmd        = Word;         {< what ChSetOneParam is asked to do, see cmd_* }
  tNode       = Word;         {< station address (FT 1.2 allows 2 octets) }
  tChResult   = Word;         {< result code, see res_* }
  tChState    = Word;         {< state code, see CHS_* }

const
  { the library's version ('1.0.0'), written once in chnversion.inc }
  ChnVersion = {$I chnversion.inc};
  { tCmd: ChSetParam validates the whole string first (cmd_Check, no side
    effects), then applies it (cmd_Set); so a bad token changes nothing.
    Checks that depend on several keys of one string are the layer's
    whole-string check (tChnVirt.ChCheckParams). cmd_Peek was a pass
    before the checks; it is no longer sent and stays for sources that
    name it. }
  cmd_Set   = 0;
  cmd_Check = 1;
  cmd_Peek  = 2;

  { Life-cycle states returned by ChReady }
  CHS_Close        = 0;
  CHS_Open         = 1;
  CHS_Connect      = 2;
  CHS_DisConnect   = 3;
  {- Transmitter: ChSendReady }
  CHS_SendReady    = 4;    {< transmitter idle, ChSend may be called }
  CHS_Sending      = 5;    {< a message is still being transmitted }
  {- Receiver: ChReceiveReady / CH_RCtrl }
  CHS_ReceiveReady = 6;    {< a whole message is waiting for ChReceive }
  CHS_Receiving    = 7;    {< receiver active, no whole message yet }
  CHS_RecInactive  = 8;    {< receiver off (not connected) }
  CHS_Opening      = 9;    {< open in progress }
  { Protocol units may define private receiver states from here upward;
    ChReceiveReady maps them to CHS_Receiving for the caller. }
  CHS_ProtoBase    = $20;

  { General results }
  res_Ok           = 0;
  res_BadParam     = 1;    {< malformed token or value out of range }
  res_UnknownParam = 2;    {< key not known to this layer }
  res_DupParam     = 3;    {< the same key twice for one layer }
  res_UnknownLayer = 4;    {< NAM= names no registered layer }
  res_WrongState   = 5;    {< call not allowed in the current state }
  res_CannotOpen   = 6;    {< device cannot be opened (missing, in use) }
  res_NoPermission = 7;    {< device exists but access is denied }
  res_BadSetting   = 8;    {< the device refuses a setting (baud rate ...) }
  res_IOError      = 9;    {< read/write failed }
  res_DeviceLost   = 10;   {< the device went away (USB adapter pulled) }
  res_NoRecBuff    = 11;   {< no receive buffer given (ChReceiveBuffer) }
  res_SmallRecBuff = 12;   {< receive buffer too small for the message }
  res_Busy         = 13;   {< ChSend while the transmitter is busy }
  res_TooLong      = 14;   {< message longer than allowed }
  res_Overrun      = 15;   {< receive buffer overrun: bytes were lost }
  res_NoLowLayer   = 16;   {< a protocol layer has no layer below it }
  res_BadLen       = 17;   {< Len passed to ChSend is impossible }
  res_BadMessage   = 18;   {< record content cannot be sent }
  res_NoMessage    = 19;   {< ChReceive with no message waiting }
  res_Timeout      = 20;   {< no answer in time (helpers, tools) }
  res_WrongLayer   = 21;   {< a helper got a channel of another layer type }
  res_HostUnknown  = 22;   {< network: host name not resolved }
  res_Refused      = 23;   {< network: connection refused }
  res_Reconnecting = 24;   {< network: connection lost, reconnecting by itself }
  res_ParamTooLong = 25;   {< a parameter string longer than tParamStr: refused, not cut }
  res_BadStream    = 26;   {< network: the peer broke the Telnet protocol }
  res_LastGeneral  = res_BadStream;   {< the highest general code in use }
  res_Proto        = $20;  {< first code a protocol unit may use }

type
  tBcc8  = Byte;   {< DF1 block check: two's complement of the byte sum }
  tCrc16 = Word;   {< DF1 CRC-16: poly $A001 reflected, init 0 }
  tSum8  = Byte;   {< FT 1.2: arithmetic byte sum modulo 256 }
  tXor8  = Byte;   {< ICS: XOR of bytes }

{ Readable English text for a result code. Codes from res_Proto upward are
  per protocol and the same value means different things in different
  units (FT 1.2's $20 is res_ErrSum, DF1's res_ErrFrame): give the layer
  type (cName, e.g. 'DF1') to pick its text, or call the channel's
  ChResultStr. Without a layer a protocol code gets the text of whichever
  unit registered that value first. }
function ChResultText(R: tChResult; const Layer: ShortString): ShortString;
function ChResultText(R: tChResult): ShortString;
{ Protocol units call this from their initialization section; the same
  layer and code again replaces the text. A full table (MaxResultTexts) is
  a programming error and stops the program with RunError(217), as a full
  layer or port driver registry does. }
procedure ChRegisterResultText(const Layer: ShortString; R: tChResult; const Text: ShortString);

{ Checksums. The *Add functions fold one byte into a running value that
  starts at 0; the *Block functions do a whole buffer. }
function Bcc8Add(Sum: tBcc8; B: Byte): tBcc8; inline;
function Bcc8Final(Sum: tBcc8): tBcc8; inline;       {< value sent on the line }
function Bcc8Block(const Buf; Len: Word): tBcc8;      {< final value }
function Crc16Add(Crc: tCrc16; B: Byte): tCrc16; inline;
function Crc16Block(const Buf; Len: Word; Crc: tCrc16): tCrc16;
function Sum8Add(Sum: tSum8; B: Byte): tSum8; inline;
function Sum8Block(const Buf; Len: Word): tSum8;
function Xor8Add(X: tXor8; B: Byte): tXor8; inline;
function Xor8Block(const Buf; Len: Word): tXor8;

{ UTC milliseconds since 1970, now (the time stamps of values). }
function ChUtcMs: Int64;

implementation

uses SysUtils, DateUtils;

function ChUtcMs: Int64;
begin
  Result := Round((LocalTimeToUniversal(Now) - UnixDateDelta) * MSecsPerDay);
end;

const
  MaxResultTexts = 96;

type
  tResultText = record
    Layer: string[15];
    Code : tChResult;
    Text : string[80];
  end;

var
  ResultTexts: array[1..MaxResultTexts] of tResultText;
  ResultTextCount: Integer = 0;
  Crc16Table: array[Byte] of tCrc16;

function GeneralText(R: tChResult): ShortString;
begin
  case R of
    res_Ok:           Result := 'ok';
    res_BadParam:     Result := 'bad parameter';
    res_UnknownParam: Result := 'unknown parameter key';
    res_DupParam:     Result := 'parameter given twice';
    res_UnknownLayer: Result := 'unknown layer name';
    res_WrongState:   Result := 'call not allowed in this state';
    res_CannotOpen:   Result := 'device cannot be opened';
    res_NoPermission: Result := 'no permission to open the device';
    res_BadSetting:   Result := 'device refuses the setting';
    res_IOError:      Result := 'input/output error';
    res_DeviceLost:   Result := 'device lost';
    res_NoRecBuff:    Result := 'no receive buffer';
    res_SmallRecBuff: Result := 'receive buffer too small';
    res_Busy:         Result := 'transmitter busy';
    res_TooLong:      Result := 'message too long';
    res_Overrun:      Result := 'receive overrun, data lost';
    res_NoLowLayer:   Result := 'no lower layer';
    res_BadLen:       Result := 'bad message length';
    res_BadMessage:   Result := 'message cannot be sent';
    res_NoMessage:    Result := 'no message waiting';
    res_Timeout:      Result := 'timeout';
    res_WrongLayer:   Result := 'the channel is not of the layer type this helper needs';
    res_HostUnknown:  Result := 'host name not resolved';
    res_Refused:      Result := 'connection refused';
    res_Reconnecting: Result := 'connection lost, reconnecting';
    res_ParamTooLong: Result := 'parameter string too long';
    res_BadStream:    Result := 'the peer broke the Telnet protocol (subnegotiation never closed)';
  else
    Result := '';
  end;
end;

procedure ChRegisterResultText(const Layer: ShortString; R: tChResult; const Text: ShortString);
var
  I: Integer;
begin
  for I := 1 to ResultTextCount do
    if (ResultTexts[I].Code = R) and (ResultTexts[I].Layer = UpperCase(Layer)) then
    begin
      ResultTexts[I].Text := Text;
      Exit;
    end;
  if ResultTextCount >= MaxResultTexts then
    RunError(217);      { programming error: raise MaxResultTexts }
  Inc(ResultTextCount);
  ResultTexts[ResultTextCount].Layer := UpperCase(Layer);
  ResultTexts[ResultTextCount].Code := R;
  ResultTexts[ResultTextCount].Text := Text;
end;

function ChResultText(R: tChResult; const Layer: ShortString): ShortString;
var
  I: Integer;
begin
  Result := GeneralText(R);
  if Result <> '' then
    Exit;
  for I := 1 to ResultTextCount do
    if (ResultTexts[I].Code = R) and
       ((Layer = '') or (ResultTexts[I].Layer = UpperCase(Layer))) then
    begin
      Result := ResultTexts[I].Layer + ': ' + ResultTexts[I].Text;
      Exit;
    end;
  Result := 'unknown result code ' + IntToStr(R);
end;

function ChResultText(R: tChResult): ShortString;
begin
  Result := ChResultText(R, '');
end;

function Bcc8Add(Sum: tBcc8; B: Byte): tBcc8;
begin
  Result := Byte(Sum + B);
end;

function Bcc8Final(Sum: tBcc8): tBcc8;
begin
  Result := Byte(-Sum);
end;

function Bcc8Block(const Buf; Len: Word): tBcc8;
begin
  Result := Bcc8Final(Sum8Block(Buf, Len));
end;

function Crc16Add(Crc: tCrc16; B: Byte): tCrc16;
begin
  Result := (Crc shr 8) xor Crc16Table[Byte(Crc xor B)];
end;

function Crc16Block(const Buf; Len: Word; Crc: tCrc16): tCrc16;
var
  P: PByte;
  I: Integer;
begin
  P := @Buf;
  for I := 0 to Integer(Len) - 1 do
    Crc := Crc16Add(Crc, P[I]);
  Result := Crc;
end;

function Sum8Add(Sum: tSum8; B: Byte): tSum8;
begin
  Result := Byte(Sum + B);
end;

function Sum8Block(const Buf; Len: Word): tSum8;
var
  P: PByte;
  I: Integer;
begin
  P := @Buf;
  Result := 0;
  for I := 0 to Integer(Len) - 1 do
    Result := Sum8Add(Result, P[I]);
end;

function Xor8Add(X: tXor8; B: Byte): tXor8;
begin
  Result := X xor B;
end;

function Xor8Block(const Buf; Len: Word): tXor8;
var
  P: PByte;
  I: Integer;
begin
  P := @Buf;
  Result := 0;
  for I := 0 to Integer(Len) - 1 do
    Result := Result xor P[I];
end;

procedure MakeCrc16Table;
var
  I, J: Integer;
  C: tCrc16;
begin
  for I := 0 to 255 do
  begin
    C := I;
    for J := 1 to 8 do
      if Odd(C) then
        C := (C shr 1) xor $A001
      else
        C := C shr 1;
    Crc16Table[I] := C;
  end;
end;

initialization
  MakeCrc16Table;
end.
