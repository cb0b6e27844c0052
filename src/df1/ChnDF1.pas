{ ChnDF1 - Allen-Bradley DF1 protocol layer (NAM=DF1), full and half duplex,
  master and slave, BCC or CRC-16.

  Implements the SofCon manual "ChnDF1" v1.20 with the decisions of
  docs/PROTOCOLS.md section 4. The frame work is done by the I/O-free codec
  ChnDF1Codec; the receive loop, ChReceive, the send buffer and the
  rest of the channel are tChnProto's (ChnProto); tChnDF1 supplies the
  codec's feed, delivery and encoding.

  Parameters: MAS=MASTER|SLAVE, FHD=FULL|HALF, CRC=ON|OFF, LSB=size,
  NOD=n, DNO=n (0..255) and, added by the port, NAK=15|0F (the byte sent as
  NAK; both are accepted on receive) and DUP=ON|OFF (duplicate detection,
  default OFF).

  DUP=ON is the "duplicate packet detect" of a PLC channel: a command with
  the same SRC, CMD, FNC and TNS as the last command from that SRC is a
  repetition by a master that missed our ACK. The layer ACKs it itself and
  does not deliver it again; CH_DupCount/CH_DupSrc/CH_DupTns tell a link
  helper (ChnDF1Link's station) so it can send its cached reply again.

  Full duplex, a reply (reply bit set) addressed to another station - DST
  other than NOD, or SRC neither DNO nor a station one of the last
  commands went to - is not ours: it is counted (CH_ForeignCount, the
  last one's CH_ForeignSrc/CH_ForeignDst) and dropped, not delivered.
  Commands are taken from any SRC, as a slave must (SPEC 6).

  As in the SofCon design the link dialogue (ACK after a good frame,
  NAK/ENQ/retries, polling) is the application's: it sends tpAckNak, tpEnq,
  tpPoll, tpNoPollRep records with ChSend like any other message.

  Differences from the manual, all deliberate (see docs/ChnDF1.md):
  NAK = $15 (the manual prints $0F); replies never carry FNC on the wire, so
  a received reply gets its FNC back from the command this layer sent
  (same TNS and command; the last DF1SentMemory commands are remembered),
  and a reply matching none has CF low byte 0; a broken frame is reported by ChReceiveReady =
  CHS_ReceiveReady and ChReceive giving Len = 0 with ChReceiveResult =
  res_ErrSum / res_ErrFrame / res_ErrLen. }
unit ChnDF1;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnProto, ChnDF1Codec;

const
  cVerNo = $0100;                 {< BCD: version 1.00 of the port }
  cVer   = '01.00,21.11.2026';
  cName  = 'DF1';

  MaxDataLen = ChnDF1Codec.MaxDataLen;
  MaxTBuff   = 65500;             {< largest send buffer LSB= may ask for }

  res_ErrFrame    = ChnDF1Codec.res_ErrFrame;
  res_ErrSum      = ChnDF1Codec.res_ErrSum;
  res_ErrLen      = ChnDF1Codec.res_ErrLen;
  res_ErrMessFrame = res_ErrFrame;   {< name used by manual v1.10 }

  { control characters, manual 4.1 (NAK: SPEC 6) }
  SOH    = ChnDF1Codec.SOH;
  STX    = ChnDF1Codec.STX;
  ETX    = ChnDF1Codec.ETX;
  EOT    = ChnDF1Codec.EOT;
  ENQ    = ChnDF1Codec.ENQ;
  ACK    = ChnDF1Codec.ACK;
  NAK    = ChnDF1Codec.NAK;
  NAKAlt = ChnDF1Codec.NAKAlt;
  DLE    = ChnDF1Codec.DLE;

  { tMessType values, so that "uses ChnDF1" is enough }
  tpAckNak    = ChnDF1Codec.tpAckNak;
  tpEnq       = ChnDF1Codec.tpEnq;
  tpPoll      = ChnDF1Codec.tpPoll;
  tpNoPollRep = ChnDF1Codec.tpNoPollRep;
  tpDataMess  = ChnDF1Codec.tpDataMess;

  { header of a data message: Len = cSizeHead... + data bytes }
  cSizeHeadSndMsg   = ChnDF1Codec.cSizeHead;
  cSizeHeadRecMsg   = ChnDF1Codec.cSizeHead;
  cSizeHeadMaSndMsg = ChnDF1Codec.cSizeHead;
  cSizeHeadSlSndMsg = ChnDF1Codec.cSizeHead;

  { CF = Command (high byte) and Function (low byte), manual 4.2 }
  MskCF_Reply      = $4000;
  MskCF_HiPriority = $2000;
  MaskCmd          = $0F00;

  CF_Echo              = $0600;
  CF_ReadDiagnCounts   = $0601;
  CF_SetVariables      = $0602;
  CF_DiagnosticSts     = $0603;
  CF_SetTimeOut        = $0604;
  CF_SetNAKs           = $0605;
  CF_SetENQs           = $0606;
  CF_ResetDiagnCounts  = $0607;
  CF_SetDataTableSize  = $0608;
  CF_ReadLinkParams    = $0609;
  CF_SetLinkParams     = $060A;
  CF_DisableOutputs    = $0700;
  CF_EnableOutputs     = $0701;
  CF_EnablePLCScaning  = $0703;
  CF_EnterDnLoadMode   = $0704;
  CF_ExitDnUpLoadMode  = $0705;
  CF_EnterUpLoadMode   = $0706;
  CF_ShutDown          = $0F07;
  CF_SetCPUMode        = $0F3A;
  CF_ChangeMode1       = $0F3A;
  CF_ChangeMode2       = $0F80;
  CF_OpenFile          = $0F81;
  CF_CloseFile         = $0F82;
  CF_WordRangeWrite    = $0F00;
  CF_WordRangeRead     = $0F01;
  CF_WriteFile         = $0F03;
  CF_ReadFile          = $0F04;
  CF_WriteBytesPhysical= $0F18;
  CF_ApplyPortConfg    = $0F8F;
  CF_DisableForces     = $0F41;
  CF_TypedRead         = $0F68;
  CF_TypedWrite        = $0F67;
  CF_DnLoadRequest     = $0F05;
  CF_UpLoad            = $0F06;
  CF_DnLoadAllRequest  = $0F50;
  CF_DnLoadCompleted   = $0F52;
  CF_UpLoadAllRequest  = $0F53;
  CF_UpLoadCompleted   = $0F55;
  CF_GetEditSource     = $0F11;
  CF_InitMemory        = $0F57;
  CF_ModifyPLC2File    = $0F5E;
  CF_ProtectWrite      = $0000;
  CF_UnProtectRead     = $0100;
  CF_UnProtectWrite    = $0800;
  CF_WriteBit          = $0F02;
  CF_ProtectWriteBit   = $0200;
  CF_UnProtectWriteBit = $0500;
  CF_PhysicalWrite     = $0F08;
  CF_PhysicalRead2     = $0F09;
  CF_PhysicalRead1     = $0400;
  CF_ProtectReadTFile  = $0FA7;
  CF_ProtectWriteTFile = $0FAF;
  CF_ProtectRead3Addr  = $0FA2;
  CF_ProtectWrite3Addr = $0FAA;
  CF_ReadBytesPhysical = $0F17;
  CF_ReadModifyWrite   = $0F26;
  CF_ReadModifyWriteN  = $0F79;
  CF_ReadSectionSize   = $0F29;
  CF_RestartRequest    = $0F0A;
  CF_ReturnEditSource  = $0F12;

  DF1DefaultSBuff = DF1MaxWire;   {< send buffer when LSB= is not given }

type
  { the last command seen from one source station (DUP=ON) }
  tDF1LastCmd = record
    Cf   : Word;
    Tns  : Word;
    Valid: Boolean;
  end;
  pDF1LastCmds = ^tDF1LastCmds;
  tDF1LastCmds = array[0..255] of tDF1LastCmd;

  tMessType   = ChnDF1Codec.tMessType;
  tSendRecord = ChnDF1Codec.tSendRecord;
  pSendRecord = ChnDF1Codec.pSendRecord;
  tRecRecord  = ChnDF1Codec.tRecRecord;
  pRecRecord  = ChnDF1Codec.pRecRecord;
  { names used by legacy SofCon programs (SPEC 2) }
  tMaSendRecord = tSendRecord;   pMaSendRecord = pSendRecord;
  tSlSendRecord = tSendRecord;   pSlSendRecord = pSendRecord;
  tMaRecRecord  = tRecRecord;    pMaRecRecord  = pRecRecord;
  tSlRecRecord  = tRecRecord;    pSlRecRecord  = pRecRecord;

  pChnDF1 = ^tChnDF1;
  tChnDF1 = object(tChnProto)
    CH_FlCrc   : Boolean;     {< CRC-16, else BCC }
    CH_RSumBcc : tBcc8;       {< receiver's running BCC sum }
    CH_SSumBcc : tBcc8;       {< BCC of the last frame sent }
    CH_RSumCrc : tCrc16;      {< receiver's running CRC }
    CH_SSumCrc : tCrc16;      {< CRC of the last frame sent }
    CH_Master  : Boolean;
    CH_FullDup : Boolean;
    CH_DLE     : Boolean;     {< receiver has just seen a DLE }
    CH_NakByte : Byte;        {< NAK= : byte sent as NAK ($15 or $0F) }
    CH_Dec     : tDF1Decoder; {< receive automaton }
    CH_Event   : tDF1Event;   {< what is waiting while CH_RCtrl = CHS_ReceiveReady }
    CH_DupDetect: Boolean;    {< DUP=ON }
    CH_LastCmds: pDF1LastCmds; {< per SRC, while DUP=ON (allocated on demand) }
    CH_DupCount: LongInt;     {< repeated commands ACKed and not delivered }
    CH_DupSrc  : Byte;        {< SRC and TNS of the last of them }
    CH_DupTns  : Word;
    CH_DupAck  : Boolean;     {< its ACK still waits for the layer below }
    CH_Sent    : tDF1SentLog; {< last commands sent, to restore a reply's CF }
    { full duplex: replies addressed to another station (DST <> NOD, or
      from a station this layer sent no command to), dropped }
    CH_ForeignCount: LongInt;
    CH_ForeignSrc, CH_ForeignDst: Byte;   {< SRC and DST of the last of them }

    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChMaxNode: tNode; virtual;
    procedure ChConnect; virtual;
    { the codec (tChnProto) }
    procedure ChRxReset; virtual;
    procedure ChRxBegin; virtual;
    function  ChRxByte(B: Byte; var Err: tChResult): Boolean; virtual;
    procedure ChRxEnd; virtual;
    function  ChRxDeliver(var Len: Word): tChResult; virtual;
    procedure ChRxTaken; virtual;
    function  ChSendCheck(Buff: Pointer; Len: Word): tChResult; virtual;
    function  ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult; virtual;
    procedure ChSent(Buff: Pointer); virtual;
    { the codec's view of the current settings }
    function  ChDF1Config: tDF1Config;
    { DUP=ON: True (and the ACK sent) when the message just decoded repeats
      the last command from its source }
    function  ChDuplicate: Boolean;
    { Repeated commands ACKed and not delivered since Init (CH_DupCount). }
    function  ChDupCount: LongInt;
    { full duplex: True (and counted) when the reply just decoded is not
      addressed to this station: DST <> NOD, or SRC is neither DNO nor a
      station one of the last commands went to. Commands are never
      foreign: a slave takes them from any SRC (SPEC 6). }
    function  ChForeignReply: Boolean;
    procedure ChSendDupAck;
  end;

  pAddChnDF1 = ^tAddChnDF1;
  tAddChnDF1 = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

const
  DuplexChoice = 'HALF|FULL';   { FHD=, False first as ParamFlag wants }

constructor tChnDF1.Init;
begin
  inherited Init;
  ChProtoSetup(cName, 16, MaxTBuff, DF1DefaultSBuff);
  CH_Master  := True;
  CH_FullDup := True;
  CH_FlCrc   := True;
  CH_DLE     := False;
  IData      := 0;
  CH_NakByte := NAK;
  CH_RSumBcc := 0;
  CH_SSumBcc := 0;
  CH_RSumCrc := 0;
  CH_SSumCrc := 0;
  CH_Event   := dfNone;
  CH_DupDetect := False;
  CH_LastCmds := nil;
  CH_DupCount := 0;
  CH_DupSrc := 0;
  CH_DupTns := 0;
  CH_DupAck := False;
  CH_ForeignCount := 0;
  CH_ForeignSrc := 0;
  CH_ForeignDst := 0;
  DF1SentInit(CH_Sent);
  DF1DecoderInit(CH_Dec, ChDF1Config);
end;

constructor tChnDF1.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnDF1.Done;
begin
  inherited Done;
  if CH_LastCmds <> nil then
    Dispose(CH_LastCmds);
  CH_LastCmds := nil;
end;

function tChnDF1.ChMaxNode: tNode;
begin
  Result := 255;
end;

function tChnDF1.ChDF1Config: tDF1Config;
begin
  Result.FullDup := CH_FullDup;
  Result.Master := CH_Master;
  Result.Crc := CH_FlCrc;
  Result.Node := Byte(CH_Node);
  Result.DNode := Byte(CH_DNode);
  Result.NakByte := CH_NakByte;
end;

function tChnDF1.ChDupCount: LongInt;
begin
  Result := CH_DupCount;
end;

function tChnDF1.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  I: Integer;
begin
  Key := ParamKey(S);
  I := 0;
  if Key = 'MAS' then
    Result := ParamFlag(S, MasterChoice, CmdL, CH_Master)
  else if Key = 'FHD' then
    Result := ParamFlag(S, DuplexChoice, CmdL, CH_FullDup)
  else if Key = 'CRC' then
    Result := ParamFlag(S, OnOffChoice, CmdL, CH_FlCrc)
  else if Key = 'DUP' then
    Result := ParamFlag(S, OnOffChoice, CmdL, CH_DupDetect)
  else if Key = 'NAK' then
  begin
    Result := ParamChoice(S, '15|0F', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      if I = 0 then
        CH_NakByte := NAK
      else
        CH_NakByte := NAKAlt;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnDF1.ChOwnParams: tParamStr;
var
  NakText: string[2];
begin
  if CH_NakByte = NAKAlt then
    NakText := '0F'
  else
    NakText := '15';
  Result := inherited ChOwnParams + FlagText('MAS', MasterChoice, CH_Master) +
    FlagText('FHD', DuplexChoice, CH_FullDup) + FlagText('CRC', OnOffChoice, CH_FlCrc) +
    ' NAK=' + NakText + FlagText('DUP', OnOffChoice, CH_DupDetect) + ChLsbText;
end;

procedure tChnDF1.ChConnect;
begin
  inherited ChConnect;
  if CH_Result = res_Ok then
  begin
    { a new session: no command seen yet from anybody }
    if CH_LastCmds <> nil then
      FillChar(CH_LastCmds^, SizeOf(CH_LastCmds^), 0);
    CH_DupAck := False;
  end;
end;

function tChnDF1.ChSendCheck(Buff: Pointer; Len: Word): tChResult;
begin
  { DST/STN are one byte: ChDestNode(256) must not go to station 0 }
  if (CH_DNode > 255) and
     (Byte(pSendRecord(Buff)^.MessType) in [Ord(tpDataMess), Ord(tpPoll)]) then
    Result := res_BadMessage
  else
    Result := res_Ok;
end;

function tChnDF1.ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult;
var
  P: PByte;
begin
  { Len only counts for data messages: the codec checks it }
  Result := DF1Encode(ChDF1Config, pSendRecord(Buff)^, Len, CH_SBuff^, CH_MSBuff, N);
  if Result <> res_Ok then
    Exit;
  { keep the checksum of a data frame for inspection, as the manual's fields }
  P := CH_SBuff;
  if pSendRecord(Buff)^.MessType = tpDataMess then
    if CH_FlCrc then
      CH_SSumCrc := P[N - 2] or (P[N - 1] shl 8)
    else
      CH_SSumBcc := P[N - 1];
end;

procedure tChnDF1.ChSent(Buff: Pointer);
begin
  DF1SentNote(CH_Sent, Byte(CH_DNode), pSendRecord(Buff)^);
end;

const
  DupAckBytes: array[0..1] of Byte = (DLE, ACK);

procedure tChnDF1.ChSendDupAck;
begin
  { never into CH_SBuff: the layer below may still be sending from it }
  CH_DupAck := True;
  if (CH_Low <> nil) and (CH_Low^.ChSendReady = CHS_SendReady) then
  begin
    CH_Low^.ChSend(@DupAckBytes, SizeOf(DupAckBytes));
    CH_DupAck := CH_Low^.ChSendResult = res_Busy;
  end;
end;

function tChnDF1.ChDuplicate: Boolean;
var
  L: ^tDF1LastCmd;
begin
  Result := False;
  if not CH_DupDetect or (CH_Dec.Msg.MessType <> tpDataMess) or
     (CH_Dec.Msg.CF and MskCF_Reply <> 0) then
    Exit;
  if CH_LastCmds = nil then
  begin
    New(CH_LastCmds);
    FillChar(CH_LastCmds^, SizeOf(CH_LastCmds^), 0);
  end;
  L := @CH_LastCmds^[CH_Dec.Src];
  Result := L^.Valid and (L^.Cf = CH_Dec.Msg.CF) and (L^.Tns = CH_Dec.Msg.Tns);
  if Result then
  begin
    Inc(CH_DupCount);
    CH_DupSrc := CH_Dec.Src;
    CH_DupTns := CH_Dec.Msg.Tns;
    ChSendDupAck;
  end
  else
  begin
    L^.Valid := True;
    L^.Cf := CH_Dec.Msg.CF;
    L^.Tns := CH_Dec.Msg.Tns;
  end;
end;

function tChnDF1.ChForeignReply: Boolean;
begin
  Result := CH_FullDup and (CH_Dec.Msg.MessType = tpDataMess) and
    (CH_Dec.Msg.CF and MskCF_Reply <> 0) and
    ((CH_Dec.Dst <> Byte(CH_Node)) or
     ((CH_Dec.Src <> Byte(CH_DNode)) and not DF1SentTo(CH_Sent, CH_Dec.Src)));
  if Result then
  begin
    Inc(CH_ForeignCount);
    CH_ForeignSrc := CH_Dec.Src;
    CH_ForeignDst := CH_Dec.Dst;
  end;
end;

procedure tChnDF1.ChRxReset;
begin
  DF1DecoderInit(CH_Dec, ChDF1Config);
  CH_Event := dfNone;
  CH_DLE := False;
end;

procedure tChnDF1.ChRxBegin;
begin
  if CH_DupAck then
    ChSendDupAck;              { the layer below was busy last time }
  { settings may have changed (ChSetParam, or fields set directly) }
  CH_Dec.Cfg := ChDF1Config;
end;

function tChnDF1.ChRxByte(B: Byte; var Err: tChResult): Boolean;
begin
  CH_Event := DF1Feed(CH_Dec, B);
  if (CH_Event = dfMessage) and (ChDuplicate or ChForeignReply) then
    CH_Event := dfNone;        { ACKed and not delivered again, or not ours }
  if CH_Event = dfError then
    Err := CH_Dec.Err;
  Result := CH_Event <> dfNone;
end;

procedure tChnDF1.ChRxEnd;
begin
  CH_RSumBcc := Bcc8Final(CH_Dec.Bcc);
  CH_RSumCrc := CH_Dec.Crc;
  CH_DLE := CH_Dec.State in [dsIdleDle, dsStnDle, dsSohStx, dsBodyDle, dsPollStnDle];
  if (CH_RCtrl = CHS_Receiving) and (CH_Dec.State <> dsIdle) then
    CH_RCtrl := CHS_ProtoBase + CH_Dec.State;   { inside a frame }
end;

function tChnDF1.ChRxDeliver(var Len: Word): tChResult;
begin
  if CH_Dec.MsgLen > CH_RSize then
    Exit(res_ErrLen);                 { does not fit: nothing is written }
  Move(CH_Dec.Msg, CH_RBuff^, CH_Dec.MsgLen);
  Len := CH_Dec.MsgLen;
  if CH_Dec.Msg.MessType in [tpDataMess, tpPoll] then
  begin
    CH_RSNode := CH_Dec.Src;
    CH_RDNode := CH_Dec.Dst;
  end;
  if CH_Dec.Msg.MessType = tpDataMess then   { a reply gets its FNC back }
    pRecRecord(CH_RBuff)^.CF := DF1ReplyCF(CH_Sent, CH_Dec.Src, CH_Dec.Msg);
  Result := res_Ok;
end;

procedure tChnDF1.ChRxTaken;
begin
  CH_Event := dfNone;
end;

function tAddChnDF1.ChInit: pChnVirt;
begin
  Result := New(pChnDF1, Init);
end;

const
  DF1Texts: array[0..2] of tProtoText = (
    (Code: res_ErrFrame; Text: 'malformed frame'),
    (Code: res_ErrSum;   Text: 'checksum (BCC/CRC) error'),
    (Code: res_ErrLen;   Text: 'message too long (data or receive buffer)'));

initialization
  ProtoRegister(New(pAddChnDF1, Init(cName)), DF1Texts);
end.
