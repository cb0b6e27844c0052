{ ChnFT1_2 - IEC 60870-5-2 frame format FT 1.2, balanced and unbalanced
  (SofCon manual ChnFT1_2; docs/PROTOCOLS.md section 5).

  tChnFT1_2 is a protocol layer: it encodes tSendRecord into FT 1.2 frames
  and decodes received frames into tRecRecord through ChnFT12Codec, and
  moves the bytes through the layer below (COM, LOOP, ...); the receive
  loop, ChReceive and the send buffer are tChnProto's (ChnProto).

    'NAM=FT1_2 MS=ON MAS=MASTER LSB=500 NOD=1 DNO=2 LEN=0 NAM=COM ...'

  Parameters of the manual: MS=ON|OFF, MAS=MASTER|SLAVE, PRI=ON|OFF, LSB=,
  NOD=, DNO=, LEN=. Added by the port (see docs/ChnFT1_2.md):
    ADR=0|1|2  link address octets (default 1 as in the manual; 2 octets are
               little-endian and NOD=/DNO= then range up to 65535)
    DIR=0|1    balanced: station A (1) or B (0); the DIR bit sent, and a
               received frame with it is res_ErrDir (own side); not
               given: 1 when PRI=ON or MAS=MASTER is (the controlling
               station), else 0
    GAP=n      line-idle gap in character times that discards a
               half-received frame (0 = off, default); the character time
               is 11 bits at the BD= of the layer below, 9600 Bd if none
  Balanced (MS=OFF): one channel takes requests and answers (CH_RPrm,
  CH_RDir tell which came) and sends either (ChSendAs); PRI= is only the
  default direction of ChSend.
  The link dialogue (FCB toggling, repetition, answering) is the
  application's job, as in the SofCon design, or ChnFT12Link's. }
unit ChnFT1_2;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnProto, ChnFT12Codec;

const
  cVerNo = $0100;                 {< BCD }
  cVer   = '01.00,21.11.2026';
  cName  = 'FT1_2';
  MaxTBuf = 65500;                {< largest send buffer (LSB=) }
  MaxDataLen = ChnFT12Codec.MaxDataLen;
  FT12MaxUserData = ChnFT12Codec.FT12MaxUserData;   {< L = 255: 254 - ADR octets }

  { control characters (manual 4.1) }
  SD1  = ChnFT12Codec.SD1;
  SD2  = ChnFT12Codec.SD2;
  ED   = ChnFT12Codec.ED;
  SACK = ChnFT12Codec.SACK;
  SNAK = ChnFT12Codec.SNAK;

  {- function codes from a master/primary station (manual 4.2);
    V = balanced, N = unbalanced }
  FCM_1stSetTransmit =  0;  {< V N  reset of remote link, FCV = False }
  FCM_1stSetUserFun  =  1;  {< V N  reset of user process, FCV = False }
  FCM_CheckLink      =  2;  {< V    test function for link, FCV = True }
  FCM_UserDataReply  =  3;  {< V N  user data, confirm expected, FCV = True }
  FCM_UserDataNoRep  =  4;  {< V N  user data, no reply, FCV = False }
  FCM_ReqReplyAcces  =  8;  {<   N  request for access demand, FCV = False }
  FCM_ReqLinkState   =  9;  {< V N  request status of link, FCV = False }
  FCM_ReqUserData1   = 10;  {<   N  request user data class 1, FCV = True }
  FCM_ReqUserData2   = 11;  {<   N  request user data class 2, FCV = True }

  {- function codes from a slave/secondary station }
  FCS_Ack            =  0;  {< V N  ACK }
  FCS_NackBusy       =  1;  {< V N  NACK: message not accepted, link busy }
  FCS_UserData       =  8;  {<   N  user data }
  FCS_DataNotAcces   =  9;  {<   N  NACK: requested data not available }
  FCS_LinkSAccesReq  = 11;  {< V N  status of link or access demand }

  {- receive results (manual 4.3) }
  res_ErrSum   = ChnFT12Codec.res_ErrSum;     {< $20 }
  res_ErrLen   = ChnFT12Codec.res_ErrLen;     {< $21 }
  res_ErrCode  = ChnFT12Codec.res_ErrCode;    {< $22 }
  res_ErrFrame = ChnFT12Codec.res_ErrFrame;   {< $23 }
  res_ErrDir   = ChnFT12Codec.res_ErrDir;     {< $24 port: balanced, DIR of the own side }

  { message types (manual 4) }
  tpSACK   = ChnFT12Codec.tpSACK;
  tpSNAK   = ChnFT12Codec.tpSNAK;
  tpShortM = ChnFT12Codec.tpShortM;
  tpLongM  = ChnFT12Codec.tpLongM;

  { header sizes (manual 4.5) and the names the manual's text uses }
  cSizeHeadSndMsg   = ChnFT12Codec.cSizeHeadSndMsg;
  cSizeHeadRecMsg   = ChnFT12Codec.cSizeHeadRecMsg;
  cSizeHeadMaSndMsg = cSizeHeadSndMsg;
  cSizeHeadSlSndMsg = cSizeHeadSndMsg;
  cSizeHeadMaRecMsg = cSizeHeadRecMsg;
  cSizeHeadSlRecMsg = cSizeHeadRecMsg;

type
  { receiver control type of the manual; the port keeps the automaton
    state in the codec and CH_RCtrl, the type is kept for old sources }
  tRec = (Znk, NoZnk, Err);
  tMessType = ChnFT12Codec.tMessType;
  tData = ChnFT12Codec.tData;
  tFT12MaxRecord = ChnFT12Codec.tFT12MaxRecord;   {< a tRecRecord for any L }

  pSendRecord = ^tSendRecord;
  tSendRecord = ChnFT12Codec.tFT12Record;
  pRecRecord  = ^tRecRecord;
  tRecRecord  = tSendRecord;

  { names the manual's method descriptions use }
  pMaSendRecord = pSendRecord;  tMaSendRecord = tSendRecord;
  pSlSendRecord = pSendRecord;  tSlSendRecord = tSendRecord;
  pMaRecRecord  = pRecRecord;   tMaRecRecord  = tRecRecord;
  pSlRecRecord  = pRecRecord;   tSlRecRecord  = tRecRecord;

  pChnFT1_2 = ^tChnFT1_2;
  tChnFT1_2 = object(tChnProto)
    CH_RSum     : tSum8;     {< receiver checksum }
    CH_SSum     : tSum8;     {< checksum of the last frame sent }
    CH_MaSl     : Boolean;   {< True: unbalanced (MS=ON) }
    CH_Master   : Boolean;   {< master (unbalanced) or primary (balanced) }
    CH_LenShortM: Byte;      {< LEN=: data octets of a fixed frame }
    {- --- additions of the port --- }
    CH_MasParam : Boolean;   {< MAS=MASTER; CH_Master follows it when MS=ON }
    CH_PriParam : Boolean;   {< PRI=ON; CH_Master follows it when MS=OFF }
    CH_AdrLen   : Byte;      {< ADR= }
    CH_Dir      : Boolean;   {< DIR= }
    CH_Gap      : Word;      {< GAP= in character times }
    CH_Rx       : tFT12Rx;   {< receive automaton }
    { direction of the frame the last ChReceive gave (False after a broken
      frame): PRM (True = a request from the peer's primary; single
      characters count as secondary) and the DIR bit it carried }
    CH_RPrm     : Boolean;
    CH_RDir     : Boolean;
    { BD= of the stack below for GAP= (9600 if none), taken when the stack
      is built (ChSetParam) and at ChConnect, not on every send }
    CH_LowBaud  : LongInt;
    CH_SPrimary : Boolean;   {< direction of the frame ChSend is encoding }
    CH_RNow     : QWord;     {< time stamp of the bytes of this receive tick }
    { which of MAS=, PRI=, DIR= the strings gave: a balanced station whose
      role is given (PRI=ON or MAS=MASTER: the controlling station) and
      no DIR= is station A, DIR=1, as lib60870's balanced master }
    CH_MasGiven, CH_PriGiven, CH_DirGiven: Boolean;

    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    procedure ChSetParam(const S: tParamStr); virtual; overload;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChMaxNode: tNode; virtual;
    { NOD=/DNO= against the ADR= in force after the string, in any order }
    function  ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult; virtual;
    procedure ChConnect; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    { ChSend with the PRM bit chosen per frame: Primary = True sends a
      request (address DNO), False an answer (address NOD). Balanced mode
      only; unbalanced, a direction other than the role is res_BadMessage.
      ChSend = ChSendAs(CH_Master, ...). }
    procedure ChSendAs(Primary: Boolean; Buff: Pointer; Len: Word);
    { the codec (tChnProto) }
    procedure ChRxReset; virtual;
    procedure ChRxBegin; virtual;
    function  ChRxByte(B: Byte; var Err: tChResult): Boolean; virtual;
    procedure ChRxEnd; virtual;
    function  ChRxDeliver(var Len: Word): tChResult; virtual;
    procedure ChRxTaken; virtual;
    function  ChSendNeedsLen(Buff: Pointer): Boolean; virtual;
    function  ChSendCheck(Buff: Pointer; Len: Word): tChResult; virtual;
    function  ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult; virtual;
    { The settings now in force, as the codec takes them (Primary = the
      role, CH_Master; Balanced = MS=OFF; AddrLen = ADR=; FixedLen = LEN=;
      Dir = DIR=): what a helper above the layer asks, instead of reading
      its fields. }
    function  ChFT12Config: tFT12Config;
    { The PRM bit of the frame the last ChReceive gave: True for a request
      of the peer's primary (CH_RPrm). }
    function  ChReceivedPrm: Boolean;
    { Frames the receiver dropped because they were for another link
      address (other stations' traffic on a bus), since ChOpen; LastAddr
      the address the last of them carried. }
    function  ChForeignFrames(out LastAddr: Word): LongWord;
    { ChSendAs once the transmitter is free, waiting for it at most
      TimeoutMs as ChSendWhenFree does (res_Timeout; a channel fault at
      once); the result of the send. }
    function  ChSendAsWhenFree(Primary: Boolean; Buff: Pointer; Len: Word;
      TimeoutMs: LongInt): tChResult;
    { GAP= in milliseconds (0 = off) }
    function  ChGapMs: LongWord;
    { CH_LowBaud := the BD= of the stack below, 9600 if none }
    procedure ChTakeLowBaud;
    procedure ChAskLineIdle;
  end;

  pAddChnFT1_2 = ^tAddChnFT1_2;
  tAddChnFT1_2 = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

uses
  uString;

const
  cBitsPerChar = 11;     { FT 1.2 character: start, 8 data, even parity, stop }
  cDefaultBaud = 9600;   { for GAP= when no layer below has BD= }
  cMinIdleBits = 33;     { IEC 60870-5-1: idle line between frames, bit times }

constructor tChnFT1_2.Init;
begin
  inherited Init;
  ChProtoSetup(cName, 1, MaxTBuf, cFT12MaxFrame);   { no LSB=: room for any frame }
  CH_RSum := 0;
  CH_SSum := 0;
  CH_MaSl := True;
  CH_Master := True;
  CH_LenShortM := 4;
  IData := 0;
  CH_MasParam := True;
  CH_PriParam := True;
  CH_AdrLen := 1;
  CH_Dir := False;
  CH_Gap := 0;
  CH_RPrm := False;
  CH_RDir := False;
  CH_LowBaud := cDefaultBaud;
  CH_SPrimary := True;
  CH_RNow := 0;
  CH_MasGiven := False;
  CH_PriGiven := False;
  CH_DirGiven := False;
  FillChar(CH_Rx, SizeOf(CH_Rx), 0);
  CH_Rx.Cfg := ChFT12Config;
  FT12RxReset(CH_Rx);
end;

constructor tChnFT1_2.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

procedure tChnFT1_2.ChTakeLowBaud;
var
  Tok: string;
  P: Integer;
begin
  CH_LowBaud := cDefaultBaud;
  if CH_Low <> nil then
  begin
    P := 1;
    if NextToken(CH_Low^.ChGetParam('BD'), P, Tok) then
      StrToNum(ParamValue(Tok), 1, 10000000, CH_LowBaud);
  end;
end;

{ IEC 60870-5-1 wants at least 33 bit times of idle line between frames.
  A line below with a speed (BD= reported: COM, LOOP BD=) and less IFG=
  is given IFG=33 through its parameters, as a user would write it; a
  larger IFG= stays, a layer without BD= (TCP) is left alone. }
procedure tChnFT1_2.ChAskLineIdle;
var
  Tok: string;
  P: Integer;
  Ifg: LongInt;
begin
  if (CH_Low = nil) or (CH_Low^.ChGetParam('BD') = '') then
    Exit;
  Ifg := 0;
  P := 1;
  if NextToken(CH_Low^.ChGetParam('IFG'), P, Tok) then
    StrToNum(ParamValue(Tok), 0, 10000, Ifg);
  if Ifg < cMinIdleBits then
    CH_Low^.ChSetParam('IFG=33');     { cMinIdleBits }
end;

function tChnFT1_2.ChGapMs: LongWord;
begin
  if CH_Gap = 0 then
    Exit(0);
  { round up: a gap shorter than one tick cannot be measured }
  Result := (QWord(CH_Gap) * cBitsPerChar * 1000 + LongWord(CH_LowBaud) - 1) div
    LongWord(CH_LowBaud);
  if Result = 0 then
    Result := 1;
end;

function tChnFT1_2.ChFT12Config: tFT12Config;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.AddrLen := CH_AdrLen;
  Result.FixedLen := CH_LenShortM;
  Result.Balanced := not CH_MaSl;
  Result.Dir := CH_Dir;
  Result.Primary := CH_Master;
  { balanced: primary and secondary at once, frames of both PRM values come
    in; a DIR of the own side is reported. Unbalanced: the role is fixed }
  Result.CheckPrm := CH_MaSl;
  Result.CheckDir := not CH_MaSl;
  { a slave/secondary takes only its own and broadcast frames; balanced,
    requests (PRM = 1) only }
  Result.Filter := (CH_AdrLen > 0) and (not CH_Master or not CH_MaSl);
  Result.OwnAddr := CH_Node;
  Result.GapMs := ChGapMs;
end;

procedure tChnFT1_2.ChSetParam(const S: tParamStr);
begin
  inherited ChSetParam(S);
  ChTakeLowBaud;                  { the stack below may be new }
  ChAskLineIdle;
  { new settings: a half-received frame starts afresh with them; a whole
    frame waiting for ChReceive is kept }
  CH_Rx.Cfg := ChFT12Config;
  if CH_RCtrl <> CHS_ReceiveReady then
    FT12RxReset(CH_Rx);
end;

function tChnFT1_2.ChMaxNode: tNode;
begin
  { the widest a token may give; ChCheckParams narrows it by ADR= }
  Result := FT12MaxAddr(2);
end;

function tChnFT1_2.ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult;
var
  Adr: LongInt;

  { a NOD=/DNO= of the string must fit the ADR= in force after it; a kept
    one that no longer fits is the ADR= token's fault }
  function Fits(const Key: ShortString; Kept: LongInt): Boolean;
  var
    I, V: LongInt;
  begin
    I := ParamFind(L, Key);
    V := Kept;
    if I >= 0 then
      ParamNum(L.Items[I].Text, 0, High(LongInt), V)
    else
      I := ParamFind(L, 'ADR');
    Result := V <= FT12MaxAddr(Adr);
    if not Result and (I >= 0) then   { (fields written directly: no token) }
      Culprit := L.Items[I].Text;
  end;

begin
  Result := res_Ok;
  Adr := CH_AdrLen;
  if ParamFind(L, 'ADR') >= 0 then
    ParamNum(L.Items[ParamFind(L, 'ADR')].Text, 0, 2, Adr);
  { the first of NOD=/DNO= in the string is named first, as a token check would }
  if ParamFind(L, 'DNO') < ParamFind(L, 'NOD') then
  begin
    if not Fits('DNO', CH_DNode) or not Fits('NOD', CH_Node) then
      Result := res_BadParam;
  end
  else if not Fits('NOD', CH_Node) or not Fits('DNO', CH_DNode) then
    Result := res_BadParam;
end;

function tChnFT1_2.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  N: LongInt;
begin
  Key := ParamKey(S);
  N := 0;
  if Key = 'MS' then
    Result := ParamFlag(S, OnOffChoice, CmdL, CH_MaSl)
  else if Key = 'MAS' then
    Result := ParamFlag(S, MasterChoice, CmdL, CH_MasParam)
  else if Key = 'PRI' then
    Result := ParamFlag(S, OnOffChoice, CmdL, CH_PriParam)
  else if Key = 'LEN' then
  begin
    Result := ParamNum(S, 0, MaxDataLen, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_LenShortM := N;
  end
  else if Key = 'ADR' then
  begin
    Result := ParamNum(S, 0, 2, N);   { with NOD=/DNO=: ChCheckParams }
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_AdrLen := N;
  end
  else if Key = 'DIR' then
  begin
    Result := ParamNum(S, 0, 1, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Dir := N = 1;
  end
  else if Key = 'GAP' then
  begin
    Result := ParamNum(S, 0, 10000, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Gap := N;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
  if (Result = res_Ok) and (CmdL = cmd_Set) then
  begin
    if Key = 'MAS' then
      CH_MasGiven := True
    else if Key = 'PRI' then
      CH_PriGiven := True
    else if Key = 'DIR' then
      CH_DirGiven := True;
    { the manual's one role field follows MAS= or PRI= by the mode }
    if CH_MaSl then
      CH_Master := CH_MasParam
    else
      CH_Master := CH_PriParam;
    { balanced, no DIR=: the role given says which station this is }
    if not CH_MaSl and not CH_DirGiven then
      if CH_PriGiven then
        CH_Dir := CH_PriParam
      else if CH_MasGiven then
        CH_Dir := CH_MasParam;
  end;
end;

function tChnFT1_2.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + FlagText('MS', OnOffChoice, CH_MaSl) +
    FlagText('MAS', MasterChoice, CH_MasParam) + FlagText('PRI', OnOffChoice, CH_PriParam) +
    ChLsbText + ParamText('LEN', CH_LenShortM) + ParamText('ADR', CH_AdrLen) +
    ParamText('DIR', Ord(CH_Dir)) + ParamText('GAP', CH_Gap);
end;

procedure tChnFT1_2.ChConnect;
begin
  if (CH_State = CHS_Open) or (CH_State = CHS_DisConnect) then
    ChTakeLowBaud;                { BD= may have changed below since }
  inherited ChConnect;            { resets the automaton with it }
end;

procedure tChnFT1_2.ChSend(Buff: Pointer; Len: Word);
begin
  ChSendAs(CH_Master, Buff, Len);
end;

procedure tChnFT1_2.ChSendAs(Primary: Boolean; Buff: Pointer; Len: Word);
begin
  CH_SPrimary := Primary;
  inherited ChSend(Buff, Len);
end;

function tChnFT1_2.ChSendAsWhenFree(Primary: Boolean; Buff: Pointer; Len: Word;
  TimeoutMs: LongInt): tChResult;
begin
  Result := ChWaitSendReady(@Self, TimeoutMs);
  if Result <> res_Ok then
    Exit;
  ChSendAs(Primary, Buff, Len);
  Result := ChSendResult;
end;

function tChnFT1_2.ChForeignFrames(out LastAddr: Word): LongWord;
begin
  LastAddr := CH_Rx.ForeignAddr;
  Result := CH_Rx.Foreign;
end;

function tChnFT1_2.ChReceivedPrm: Boolean;
begin
  Result := CH_RPrm;
end;

function tChnFT1_2.ChSendNeedsLen(Buff: Pointer): Boolean;
begin
  { Len is ignored for single characters (the manual), so 0 is fine there }
  Result := not (PByte(Buff)^ in [Ord(tpSACK), Ord(tpSNAK)]);
end;

function tChnFT1_2.ChSendCheck(Buff: Pointer; Len: Word): tChResult;
begin
  if CH_MaSl and (CH_SPrimary <> CH_Master) then
    Result := res_BadMessage      { unbalanced: the role is fixed }
  else
    Result := res_Ok;
end;

function tChnFT1_2.ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult;
var
  Addr: tNode;
  Cfg: tFT12Config;
begin
  { one address field: the destination from a master/primary, the own
    address (SNO) from a slave/secondary }
  if CH_SPrimary then
    Addr := CH_DNode
  else
    Addr := CH_Node;
  Cfg := ChFT12Config;
  Cfg.Primary := CH_SPrimary;
  Result := FT12Encode(Cfg, pSendRecord(Buff)^, Len, Addr, CH_SBuff, CH_MSBuff, N);
  if (Result = res_Ok) and (N > 1) then
    CH_SSum := PByte(CH_SBuff)[N - 2];
end;

procedure tChnFT1_2.ChRxReset;
begin
  CH_Rx.Cfg := ChFT12Config;
  FT12RxReset(CH_Rx);
end;

procedure tChnFT1_2.ChRxBegin;
begin
  CH_RNow := ChMsTick;     { one time stamp for the bytes pulled in this tick }
end;

function tChnFT1_2.ChRxByte(B: Byte; var Err: tChResult): Boolean;
begin
  case FT12Feed(CH_Rx, B, CH_RNow) of
    fe_Frame: Result := True;
    fe_Error:
      begin
        Err := CH_Rx.Err;
        Result := True;
      end;
  else
    Result := False;
  end;
end;

procedure tChnFT1_2.ChRxEnd;
begin
  CH_RSum := CH_Rx.Sum;
end;

function tChnFT1_2.ChRxDeliver(var Len: Word): tChResult;
var
  Addr: tNode;
begin
  Result := FT12GetRecord(CH_Rx, CH_RBuff, CH_RSize, Len);
  if Result <> res_Ok then
    Exit;
  CH_RPrm := FT12FramePrm(CH_Rx);
  CH_RDir := (CH_Rx.Kind in [tpShortM, tpLongM]) and (CH_Rx.Code and cBitDirRes <> 0);
  { one address on the line: report it on the side it belongs to; with no
    address field (ADR=0, single characters) the configured peer }
  if CH_RPrm then
  begin
    if CH_AdrLen > 0 then
      Addr := CH_Rx.Addr
    else
      Addr := CH_Node;
    CH_RDNode := Addr;
    CH_RSNode := CH_DNode;
  end
  else
  begin
    if (CH_AdrLen > 0) and (CH_Rx.Kind in [tpShortM, tpLongM]) then
      Addr := CH_Rx.Addr
    else
      Addr := CH_DNode;
    CH_RSNode := Addr;
    CH_RDNode := CH_Node;
  end;
end;

procedure tChnFT1_2.ChRxTaken;
begin
  if CH_RResult <> res_Ok then
  begin
    CH_RPrm := False;              { a broken frame has no direction }
    CH_RDir := False;
  end;
end;

const
  FT12Texts: array[0..4] of tProtoText = (
    (Code: res_ErrSum;   Text: 'checksum error'),
    (Code: res_ErrLen;   Text: 'bad frame length'),
    (Code: res_ErrCode;  Text: 'PRM bit does not fit this station''s role'),
    (Code: res_ErrFrame; Text: 'frame error (start or end character)'),
    (Code: res_ErrDir;   Text: 'DIR bit says the frame came from this station''s own side'));

function tAddChnFT1_2.ChInit: pChnVirt;
begin
  Result := New(pChnFT1_2, Init);
end;

initialization
  ProtoRegister(New(pAddChnFT1_2, Init(cName)), FT12Texts);
end.
