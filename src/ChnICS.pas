{ ChnICS - tChnICS, the DACS ICSlink protocol layer (NAM=ICS), and its
  manager tAddChnICS.

  Implements the SofCon manual ChnICS v1.20 and docs/PROTOCOLS.md
  section 8. The frame format lives in the I/O-free unit ChnICSCodec; this
  unit declares the manual's constants and types and glues the codec to
  ChnVirt (docs/LAYERS.md).

  Differences from the manual:
  * tData is SmallInt (Borland "integer"), so Len = 4 + 2 * count as in
    legacy code.
  * The manual's text also names OPM_ReadData/OPM_ReadParams/OPM_WriteData
    and MaxTBuff; they are aliases of OCM_* and MaxTBuf.
  * DNO is the destination (CH_DNode), SNO the sender (CH_Node); ChGetNode
    reports them for a received frame. Frames addressed to other stations
    are not filtered: the application checks ChGetNode.
  * MAS= is recorded in CH_Master; framing is the same for both roles.
  * LSB=0 (the default) means "allocate a send buffer for the longest
    frame on first use".
  * A received frame whose data or text does not fit the buffer given to
    ChReceiveBuffer gives res_ErrLen; nothing is written past the buffer.
  * ChSend of an invalid record gives res_ErrLen (Len, text length) or
    res_BadMessage (node, block, op code, text) and sends nothing. }
unit ChnICS;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnICSCodec;

const
  cVerNo = $0120;                 { BCD, port of manual v1.20 }
  cVer   = '01.20,21.11.2026';
  cName  = 'ICS';

  MaxDataLen = ICSMaxDataLen;     { 32 numbers }
  MaxTextLen = ICSMaxTextLen;     { 200 characters with both delimiters }
  MaxTBuf    = 65500;             { largest send buffer (LSB=) }
  MaxTBuff   = MaxTBuf;           { spelling used in the manual's text }

  { control characters (manual 4.1) }
  SOH = ICS_SOH;
  STX = ICS_STX;
  ETX = ICS_ETX;
  EOT = ICS_EOT;

  { op codes (manual 4.2) }
  OCM_ReadData   = 'RD';
  OCM_ReadParams = 'RL';
  OCM_WriteData  = 'WD';
  OCS_ReadData   = 'DB';
  OCS_ReadParams = 'LB';
  OCS_WriteData  = 'OK';
  OPM_ReadData   = OCM_ReadData;    { names used in the manual's text }
  OPM_ReadParams = OCM_ReadParams;
  OPM_WriteData  = OCM_WriteData;

  { receive results (manual 4.3) }
  res_ErrFrame = ICS_ErrFrame;    { $20 }
  res_ErrSum   = ICS_ErrSum;      { $21 }
  res_ErrLen   = ICS_ErrLen;      { $22 }
  res_ErrVal   = ICS_ErrVal;      { $23 }
  res_ErrETX   = ICS_ErrETX;      { $24 }
  res_ErrEOT   = ICS_ErrEOT;      { $25 }

type
  tData       = tICSData;
  pSendRecord = pICSRecord;
  tSendRecord = tICSRecord;
  pRecRecord  = pICSRecord;
  tRecRecord  = tICSRecord;

  pChnICS = ^tChnICS;
  tChnICS = object(tChnVirt)
    CH_RTick  : Boolean;     { the receive automaton is running (debugging) }
    CH_SBuff  : Pointer;     { send buffer }
    CH_MSBuff : Word;        { its size }
    CH_LRMess : Word;        { Len of the last received message }
    CH_RSum   : tXor8;       { receiver's running checksum }
    CH_SSum   : tXor8;       { checksum of the last frame sent }
    CH_Master : Boolean;     { MAS=MASTER }
    CH_DataI  : SmallInt;    { numbers received so far in the current frame }
    CH_PomS   : ShortString;      { the number being received (text) }
    CH_Codec  : tICSState;   { the receive automaton }
    CH_Event  : tICSEvent;   { what the automaton last reported }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChMaxNode: tNode; virtual;
    procedure ChConnect; virtual;
    procedure ChDisConnect; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    procedure ChReceive(var Len: Word); virtual;
    procedure ChReceiveFlush; virtual;
    procedure ChReceiveTick; virtual;
  end;

  pAddChnICS = ^tAddChnICS;
  tAddChnICS = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

constructor tChnICS.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_RTick := False;
  CH_SBuff := nil;
  CH_MSBuff := 0;
  CH_LRMess := 0;
  CH_RSum := 0;
  CH_SSum := 0;
  CH_Master := True;
  CH_DataI := 0;
  CH_PomS := '';
  ICSReset(CH_Codec);
  CH_Event := icsNone;
end;

constructor tChnICS.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnICS.Done;
begin
  inherited Done;                { closes the layers below first }
  ChFreeSendBuffer(CH_SBuff, CH_MSBuff);
end;

function tChnICS.ChMaxNode: tNode;
begin
  Result := ICSMaxNode;
end;

function tChnICS.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
begin
  Key := ParamKey(S);
  if Key = 'MAS' then
    Result := ParamFlag(S, MasterChoice, CmdL, CH_Master)
  else if Key = 'LSB' then
    Result := ChParamSendBuffer(S, 0, MaxTBuf, CmdL, CH_SBuff, CH_MSBuff)
  else
    Result := inherited ChSetOneParam(S, CmdL);   { NOD=, DNO= 0..207 }
end;

function tChnICS.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + FlagText('MAS', MasterChoice, CH_Master) +
    ParamText('LSB', CH_MSBuff);
end;

procedure tChnICS.ChConnect;
begin
  inherited ChConnect;
  if CH_Result = res_Ok then
  begin
    ICSReset(CH_Codec);
    CH_Event := icsNone;
  end;
end;

procedure tChnICS.ChDisConnect;
begin
  inherited ChDisConnect;
  if CH_Result = res_Ok then
  begin
    ICSReset(CH_Codec);
    CH_Event := icsNone;
  end;
end;

procedure tChnICS.ChSend(Buff: Pointer; Len: Word);
var
  N: Word;
  R: tChResult;
begin
  { Len = 4 (no numbers) is valid: the codec checks it }
  if not ChSendAllowed(Buff, Len, False) then
    Exit;
  ChSendBuffer(CH_SBuff, CH_MSBuff, ICSMaxFrame);
  N := 0;
  R := ICSEncode(pICSRecord(Buff)^, Len, CH_DNode, CH_Node, CH_SBuff^,
    CH_MSBuff, N);
  if R <> res_Ok then
  begin
    CH_SResult := R;
    Exit;
  end;
  CH_SSum := PByte(CH_SBuff)[N - 2];
  ChLowSend(CH_SBuff, N);
end;

procedure tChnICS.ChReceiveTick;
var
  B: Byte;
  Count: Integer;
begin
  if (CH_State <> CHS_Connect) or (CH_RCtrl <> CHS_Receiving) then
    Exit;
  CH_RTick := True;
  Count := 0;
  while (Count < MaxBytesPerTick) and ChLowGetByte(B) do
  begin
    Inc(Count);
    CH_Event := ICSFeed(CH_Codec, B);
    if CH_Event <> icsNone then
    begin
      { stop here: the bytes after the frame stay for the next one }
      CH_RCtrl := CHS_ReceiveReady;
      Break;
    end;
  end;
  CH_RSum := CH_Codec.Sum;
  CH_DataI := CH_Codec.Count;
  CH_PomS := CH_Codec.NumText;
  CH_RTick := False;
end;

procedure tChnICS.ChReceive(var Len: Word);
var
  Need: LongInt;
  Rec: pICSRecord;
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  if CH_RCtrl <> CHS_ReceiveReady then
  begin
    CH_RResult := res_NoMessage;
    Exit;
  end;
  if CH_Event = icsError then
    CH_RResult := CH_Codec.Error
  else
  begin
    Rec := @CH_Codec.Rec;
    { the application's buffer must hold the header, the numbers and, when
      a text came, the Text field up to its last character }
    Need := ICSRecLen(CH_Codec);
    if Rec^.Text <> '' then
      Need := PtrUInt(@Rec^.Text) - PtrUInt(Rec) + 1 + Length(Rec^.Text);
    if Need > CH_RSize then
      CH_RResult := res_ErrLen
    else
    begin
      if CH_RSize < SizeOf(tICSRecord) then
        Move(Rec^, CH_RBuff^, CH_RSize)
      else
        Move(Rec^, CH_RBuff^, SizeOf(tICSRecord));
      Len := ICSRecLen(CH_Codec);
      CH_LRMess := Len;
      CH_RSNode := CH_Codec.SNode;
      CH_RDNode := CH_Codec.DNode;
      CH_RResult := res_Ok;
    end;
  end;
  CH_Event := icsNone;
  CH_RCtrl := CHS_Receiving;
end;

procedure tChnICS.ChReceiveFlush;
begin
  ICSReset(CH_Codec);
  CH_Event := icsNone;
  inherited ChReceiveFlush;
end;

function tAddChnICS.ChInit: pChnVirt;
begin
  Result := New(pChnICS, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnICS, Init(cName)));
  ChRegisterResultText(cName, res_ErrFrame, 'frame format error');
  ChRegisterResultText(cName, res_ErrSum, 'checksum error');
  ChRegisterResultText(cName, res_ErrLen, 'too many numbers or text too long');
  ChRegisterResultText(cName, res_ErrVal, 'bad number (malformed or outside 16 bits)');
  ChRegisterResultText(cName, res_ErrETX, 'ETX missing');
  ChRegisterResultText(cName, res_ErrEOT, 'EOT missing after the checksum');
end.
