{ ChnICS - tChnICS, the DACS ICSlink protocol layer (NAM=ICS), and its
  manager tAddChnICS.

  Implements the SofCon manual ChnICS v1.20 and docs/PROTOCOLS.md
  section 8. The frame format lives in the I/O-free unit ChnICSCodec; this
  unit declares the manual's constants and types and supplies the codec's
  feed, delivery and encoding to the protocol base tChnProto
  (docs/LAYERS.md).

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
  ChnTypes, ChnVirt, ChnProto, ChnICSCodec;

const
  cVerNo = $0120;                 {< BCD, port of manual v1.20 }
  cVer   = '01.20,21.11.2026';
  cName  = 'ICS';

  MaxDataLen = ICSMaxDataLen;     {< 32 numbers }
  MaxTextLen = ICSMaxTextLen;     {< 200 characters with both delimiters }
  MaxTBuf    = 65500;             {< largest send buffer (LSB=) }
  MaxTBuff   = MaxTBuf;           {< spelling used in the manual's text }

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
  OPM_ReadData   = OCM_ReadData;    {< names used in the manual's text }
  OPM_ReadParams = OCM_ReadParams;
  OPM_WriteData  = OCM_WriteData;

  {- receive results (manual 4.3) }
  res_ErrFrame = ICS_ErrFrame;    {< $20 }
  res_ErrSum   = ICS_ErrSum;      {< $21 }
  res_ErrLen   = ICS_ErrLen;      {< $22 }
  res_ErrVal   = ICS_ErrVal;      {< $23 }
  res_ErrETX   = ICS_ErrETX;      {< $24 }
  res_ErrEOT   = ICS_ErrEOT;      {< $25 }

type
  tData       = tICSData;
  pSendRecord = pICSRecord;
  tSendRecord = tICSRecord;
  pRecRecord  = pICSRecord;
  tRecRecord  = tICSRecord;

  pChnICS = ^tChnICS;
  tChnICS = object(tChnProto)
    CH_RSum   : tXor8;       {< receiver's running checksum }
    CH_SSum   : tXor8;       {< checksum of the last frame sent }
    CH_Master : Boolean;     {< MAS=MASTER }
    CH_DataI  : SmallInt;    {< numbers received so far in the current frame }
    CH_PomS   : ShortString;      {< the number being received (text) }
    CH_Codec  : tICSState;   {< the receive automaton }
    CH_Event  : tICSEvent;   {< what the automaton last reported }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChMaxNode: tNode; virtual;
    { the codec (tChnProto) }
    procedure ChRxReset; virtual;
    function  ChRxByte(B: Byte; var Err: tChResult): Boolean; virtual;
    procedure ChRxEnd; virtual;
    function  ChRxDeliver(var Len: Word): tChResult; virtual;
    procedure ChRxTaken; virtual;
    function  ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult; virtual;
  end;

  pAddChnICS = ^tAddChnICS;
  tAddChnICS = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

constructor tChnICS.Init;
begin
  inherited Init;
  ChProtoSetup(cName, 0, MaxTBuf, ICSMaxFrame);   { LSB=0: the longest frame }
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
  else
    Result := inherited ChSetOneParam(S, CmdL);   { LSB=, NOD=, DNO= 0..207 }
end;

function tChnICS.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + FlagText('MAS', MasterChoice, CH_Master) +
    ChLsbText;
end;

procedure tChnICS.ChRxReset;
begin
  ICSReset(CH_Codec);
  CH_Event := icsNone;
end;

function tChnICS.ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult;
begin
  { Len = 4 (no numbers) is valid: the codec checks it }
  Result := ICSEncode(pICSRecord(Buff)^, Len, CH_DNode, CH_Node, CH_SBuff^,
    CH_MSBuff, N);
  if Result = res_Ok then
    CH_SSum := PByte(CH_SBuff)[N - 2];
end;

function tChnICS.ChRxByte(B: Byte; var Err: tChResult): Boolean;
begin
  CH_Event := ICSFeed(CH_Codec, B);
  if CH_Event = icsError then
    Err := CH_Codec.Error;
  Result := CH_Event <> icsNone;
end;

procedure tChnICS.ChRxEnd;
begin
  CH_RSum := CH_Codec.Sum;
  CH_DataI := CH_Codec.Count;
  CH_PomS := CH_Codec.NumText;
end;

function tChnICS.ChRxDeliver(var Len: Word): tChResult;
var
  Need: LongInt;
  Rec: pICSRecord;
begin
  Rec := @CH_Codec.Rec;
  { the application's buffer must hold the header, the numbers and, when
    a text came, the Text field up to its last character }
  Need := ICSRecLen(CH_Codec);
  if Rec^.Text <> '' then
    Need := PtrUInt(@Rec^.Text) - PtrUInt(Rec) + 1 + Length(Rec^.Text);
  if Need > CH_RSize then
    Exit(res_ErrLen);
  if CH_RSize < SizeOf(tICSRecord) then
    Move(Rec^, CH_RBuff^, CH_RSize)
  else
    Move(Rec^, CH_RBuff^, SizeOf(tICSRecord));
  Len := ICSRecLen(CH_Codec);
  CH_RSNode := CH_Codec.SNode;
  CH_RDNode := CH_Codec.DNode;
  Result := res_Ok;
end;

procedure tChnICS.ChRxTaken;
begin
  CH_Event := icsNone;
end;

const
  ICSTexts: array[0..5] of tProtoText = (
    (Code: res_ErrFrame; Text: 'frame format error'),
    (Code: res_ErrSum;   Text: 'checksum error'),
    (Code: res_ErrLen;   Text: 'too many numbers or text too long'),
    (Code: res_ErrVal;   Text: 'bad number (malformed or outside 16 bits)'),
    (Code: res_ErrETX;   Text: 'ETX missing'),
    (Code: res_ErrEOT;   Text: 'EOT missing after the checksum'));

function tAddChnICS.ChInit: pChnVirt;
begin
  Result := New(pChnICS, Init);
end;

initialization
  ProtoRegister(New(pAddChnICS, Init(cName)), ICSTexts);
end.
