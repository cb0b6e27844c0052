{ ChnProto - tChnProto, the base of the protocol layers (DF1, FT 1.2, ICS):
  everything a protocol layer must do the same way, done once.

  It owns
  * the receive loop: ChReceiveTick pulls chunks from the layer below
    (tChnVirt's byte feed, CH_LowBuf) and hands the bytes one by one to
    the layer's codec (ChRxByte), at most MaxBytesPerTick per tick so a
    babbling line cannot stall a poll, and stops at the first whole or
    broken frame: the bytes after it stay in CH_LowBuf for the next one;
  * ChReceive: the checks (connected, a buffer), the rule below, broken
    frames (Len = 0, ChReceiveResult = the codec's code), the copy-out
    through the layer's ChRxDeliver and CH_LRMess;
  * the send path: the checks, the LSB= send buffer (CH_SBuff, CH_MSBuff,
    each layer with its own range and default), encoding through the
    layer's ChEncode into that buffer, and handing it down;
  * "this channel holds input the program has not taken" for the
    program-wide wait (ChnWaitHeld): a decoded frame waiting for
    ChReceive, or bytes pulled from below and not yet decoded. The flag
    is cleared on disconnect, close and Done, so the process-wide count
    never leaks;
  * the registration of the layer's manager and result texts
    (ProtoRegister).

  One rule for every protocol layer: ChReceive runs a receive step itself
  when no frame is waiting yet, so "ChReceive takes a message if a whole
  one has arrived" holds whether or not the program polled
  ChReceiveReady first (DF1 always did this; FT 1.2 and ICS answered
  res_NoMessage until the next ChReceiveReady).

  A layer descends from tChnProto and supplies its codec: ChRxByte (feed
  one byte), ChRxDeliver (copy the decoded frame out), ChEncode (record to
  wire bytes), ChRxReset (start hunting afresh) and, where it needs them,
  the optional hooks (docs/LAYERS.md). }
unit ChnProto;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnWait;

type
  { one readable text of a layer's result code, for ProtoRegister }
  tProtoText = record
    Code: tChResult;
    Text: string[80];
  end;

  pChnProto = ^tChnProto;
  tChnProto = object(tChnVirt)
    CH_RTick  : Boolean;     {< inside ChReceiveTick (debugging aid) }
    CH_SBuff  : Pointer;     {< send buffer: wire bytes of the last ChSend }
    CH_MSBuff : Word;        {< its size (LSB=) }
    CH_SLen   : Word;        {< wire bytes of the last frame sent }
    CH_LRMess : Word;        {< Len of the last received message (0: broken) }
    CH_RErr   : tChResult;   {< the frame waiting for ChReceive: res_Ok when
                               good, else why it is broken }
    CH_Held   : Boolean;     {< counted in ChnWaitHeld now }
    CH_LsbMin, CH_LsbMax: LongInt;   {< LSB= range of this layer }
    CH_LsbDefault: Word;     {< send buffer allocated when LSB= gave none }

    constructor Init;
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    procedure ChConnect; virtual;
    procedure ChDisConnect; virtual;
    procedure ChClose; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    procedure ChReceive(var Len: Word); virtual;
    procedure ChReceiveFlush; virtual;
    procedure ChReceiveTick; virtual;

    { For a descendant's Init: the layer type, the LSB= range and the send
      buffer allocated on the first ChSend when LSB= gave none (LsbMin = 0:
      LSB=0 means that). }
    procedure ChProtoSetup(const AType: ShortString; LsbMin, LsbMax: LongInt;
      SBuffDefault: Word);
    { ' LSB=n' for ChOwnParams: always when LSB=0 is a setting of its own
      (LsbMin = 0), else only once a buffer is there }
    function  ChLsbText: ShortString;

    {- --- the codec: every protocol layer overrides these --- }
    { Start hunting for a frame afresh (connect, flush, disconnect, close). }
    procedure ChRxReset; virtual;
    { Feed one received byte. True when a frame is complete: a good one
      (Err left res_Ok) or a broken one (Err = its result code). }
    function  ChRxByte(B: Byte; var Err: tChResult): Boolean; virtual;
    { Copy the good frame just completed into CH_RBuff (never more than
      CH_RSize bytes), Len as the manual says, CH_RSNode/CH_RDNode for
      ChGetNode. Another result (res_ErrLen: it does not fit) leaves the
      buffer untouched. }
    function  ChRxDeliver(var Len: Word): tChResult; virtual;
    { Encode the record Buff^ (Len) into CH_SBuff (CH_MSBuff bytes); N the
      wire bytes. Any other result sends nothing. }
    function  ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult; virtual;

    {- --- optional hooks (the base does nothing) --- }
    { before the bytes of one receive tick }
    procedure ChRxBegin; virtual;
    { after them; CH_RCtrl is CHS_ReceiveReady or CHS_Receiving (a layer
      may refine the latter to a private state from CHS_ProtoBase) }
    procedure ChRxEnd; virtual;
    { after ChReceive took a frame, good or broken (CH_RResult says) }
    procedure ChRxTaken; virtual;
    { ChSend: does a record at Buff need Len > 0 (default False: the
      codec checks Len) }
    function  ChSendNeedsLen(Buff: Pointer): Boolean; virtual;
    { ChSend: a check of the record before the send buffer is allocated;
      another result than res_Ok sends nothing }
    function  ChSendCheck(Buff: Pointer; Len: Word): tChResult; virtual;
    { ChSend: the frame was handed to the layer below (CH_SResult = res_Ok) }
    procedure ChSent(Buff: Pointer); virtual;

    { ChnWaitHeld := connected and (a frame waits or bytes wait in
      CH_LowBuf); called by the base after every change of either. }
    procedure ChHeldUpdate;
    { The wire bytes of the last frame sent (CH_SBuff, Len of them), for
      a helper that shows them; nil and 0 before the first. }
    function  ChSentFrame(out Len: Word): PByte;
  end;

{ Register a protocol layer: its manager in ChnCollection and a readable
  text for each of its result codes (ChRegisterResultText). For the
  unit's initialization section. }
procedure ProtoRegister(Manager: pAddChnVirt; const Texts: array of tProtoText);

implementation

procedure ProtoRegister(Manager: pAddChnVirt; const Texts: array of tProtoText);
var
  I: LongInt;
  Name: ShortString;
begin
  Name := Manager^.Name;
  ChnCollection^.Insert(Manager);
  for I := Low(Texts) to High(Texts) do
    ChRegisterResultText(Name, Texts[I].Code, Texts[I].Text);
end;

constructor tChnProto.Init;
begin
  inherited Init;
  CH_RTick := False;
  CH_SBuff := nil;
  CH_MSBuff := 0;
  CH_SLen := 0;
  CH_LRMess := 0;
  CH_RErr := res_Ok;
  CH_Held := False;
  CH_LsbMin := 1;
  CH_LsbMax := 65500;
  CH_LsbDefault := 512;
end;

destructor tChnProto.Done;
begin
  inherited Done;                  { closes (clears the flag), disposes below }
  ChFreeSendBuffer(CH_SBuff, CH_MSBuff);
  ChnWaitHeld(CH_Held, False);     { never leak the process-wide count }
end;

procedure tChnProto.ChProtoSetup(const AType: ShortString; LsbMin, LsbMax: LongInt;
  SBuffDefault: Word);
begin
  ChSetType(AType);
  CH_LsbMin := LsbMin;
  CH_LsbMax := LsbMax;
  CH_LsbDefault := SBuffDefault;
end;

function tChnProto.ChLsbText: ShortString;
begin
  if (CH_MSBuff > 0) or (CH_LsbMin = 0) then
    Result := ParamText('LSB', CH_MSBuff)
  else
    Result := '';
end;

function tChnProto.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
begin
  if ParamKey(S) = 'LSB' then
    Result := ChParamSendBuffer(S, CH_LsbMin, CH_LsbMax, CmdL, CH_SBuff, CH_MSBuff)
  else
    Result := inherited ChSetOneParam(S, CmdL);   { NOD=, DNO= }
end;

procedure tChnProto.ChHeldUpdate;
begin
  ChnWaitHeld(CH_Held, (CH_State = CHS_Connect) and
    ((CH_RCtrl = CHS_ReceiveReady) or (CH_LowPos < CH_LowLen)));
end;

procedure tChnProto.ChConnect;
begin
  inherited ChConnect;
  if CH_Result = res_Ok then
  begin
    ChRxReset;
    CH_RErr := res_Ok;
  end;
  ChHeldUpdate;
end;

procedure tChnProto.ChDisConnect;
begin
  inherited ChDisConnect;
  if CH_Result = res_Ok then
  begin
    ChRxReset;                     { a frame not taken is gone }
    CH_RErr := res_Ok;
  end;
  ChHeldUpdate;
end;

procedure tChnProto.ChClose;
begin
  inherited ChClose;
  ChRxReset;
  CH_RErr := res_Ok;
  ChLowDiscard;
  ChHeldUpdate;
end;

{- ----------------------------------------------------------------- sending }

procedure tChnProto.ChSend(Buff: Pointer; Len: Word);
var
  N: Word;
  R: tChResult;
begin
  if not ChSendAllowed(Buff, Len, (Buff <> nil) and ChSendNeedsLen(Buff)) then
    Exit;
  R := ChSendCheck(Buff, Len);
  if R <> res_Ok then
  begin
    CH_SResult := R;
    Exit;
  end;
  ChSendBuffer(CH_SBuff, CH_MSBuff, CH_LsbDefault);
  N := 0;
  R := ChEncode(Buff, Len, N);
  if R <> res_Ok then
  begin
    CH_SResult := R;               { nothing is sent }
    Exit;
  end;
  CH_SLen := N;
  ChLowSend(CH_SBuff, N);
  if CH_SResult = res_Ok then
    ChSent(Buff);
end;

{- --------------------------------------------------------------- receiving }

procedure tChnProto.ChReceiveTick;
var
  Budget: LongInt;
  Err: tChResult;
  Complete: Boolean;
begin
  if (CH_State <> CHS_Connect) or (CH_RCtrl = CHS_ReceiveReady) then
    Exit;
  CH_RTick := True;
  ChRxBegin;
  Budget := MaxBytesPerTick;
  Err := res_Ok;
  Complete := False;
  { CH_LowBuf is read directly: one call per byte less than ChLowGetByte }
  while not Complete and (Budget > 0) and ChLowFill do
    repeat
      Dec(Budget);
      Inc(CH_LowPos);
      Complete := ChRxByte(CH_LowBuf[CH_LowPos - 1], Err);
    until Complete or (Budget = 0) or (CH_LowPos >= CH_LowLen);
  if Complete then
  begin
    CH_RErr := Err;
    CH_RCtrl := CHS_ReceiveReady;  { the rest stays below for the next frame }
  end
  else
    CH_RCtrl := CHS_Receiving;
  ChRxEnd;
  CH_RTick := False;
  ChHeldUpdate;
end;

procedure tChnProto.ChReceive(var Len: Word);
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  if CH_RCtrl <> CHS_ReceiveReady then
    ChReceiveTick;                 { the one rule: see the unit header }
  if CH_RCtrl <> CHS_ReceiveReady then
  begin
    CH_RResult := res_NoMessage;
    Exit;
  end;
  if CH_RErr <> res_Ok then
    CH_RResult := CH_RErr          { broken frame: the application answers }
  else
  begin
    CH_RResult := ChRxDeliver(Len);
    if CH_RResult <> res_Ok then
      Len := 0;
  end;
  CH_LRMess := Len;
  CH_RErr := res_Ok;
  CH_RCtrl := CHS_Receiving;
  ChRxTaken;
  ChHeldUpdate;
end;

procedure tChnProto.ChReceiveFlush;
begin
  ChRxReset;
  CH_RErr := res_Ok;
  inherited ChReceiveFlush;
  ChHeldUpdate;
end;

{- ------------------------------------------------ codec and hook defaults }

procedure tChnProto.ChRxReset;
begin
end;

function tChnProto.ChRxByte(B: Byte; var Err: tChResult): Boolean;
begin
  Result := False;                 { no codec: bytes are dropped }
end;

function tChnProto.ChRxDeliver(var Len: Word): tChResult;
begin
  Len := 0;
  Result := res_NoMessage;
end;

function tChnProto.ChEncode(Buff: Pointer; Len: Word; var N: Word): tChResult;
begin
  N := 0;
  Result := res_BadMessage;
end;

procedure tChnProto.ChRxBegin;
begin
end;

procedure tChnProto.ChRxEnd;
begin
end;

procedure tChnProto.ChRxTaken;
begin
end;

function tChnProto.ChSendNeedsLen(Buff: Pointer): Boolean;
begin
  Result := False;
end;

function tChnProto.ChSendCheck(Buff: Pointer; Len: Word): tChResult;
begin
  Result := res_Ok;
end;

function tChnProto.ChSentFrame(out Len: Word): PByte;
begin
  Len := CH_SLen;
  Result := CH_SBuff;
end;

procedure tChnProto.ChSent(Buff: Pointer);
begin
end;

end.
