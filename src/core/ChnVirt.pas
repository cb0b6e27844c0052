{ ChnVirt - tChnVirt, the ancestor of every layer, and the layer registry.
  The parameter-string parser the layers use is unit ChnParam.

  Reconstructed from the ChnDF1, ChnFT1_2 and ChnICS manuals (docs/PROTOCOLS.md
  section 4); identifiers legacy code uses are binding.

  A channel is a stack of layers built from one parameter string:
    'NAM=DF1 NOD=1 DNO=2 NAM=COM DEV=/dev/ttyUSB0 BD=19200'
  Every layer speaks the same Ch* methods. A physical layer's "message" is a
  chunk of raw bytes; a protocol layer sends through CH_Low^.ChSend and pulls
  bytes through CH_Low^.ChReceiveReady / ChReceive (see ChLowGetByte), never
  around it.

  Parameter strings are validated whole: ChSetParam first asks every layer
  to check its tokens (ChSetOneParam with cmd_Check, no side effects) and
  only then applies them (cmd_Set). On a bad token ChResult tells why,
  ChParamError names the token, and the previous configuration stays. }
unit ChnVirt;

{$I chn.inc}

interface

uses
  ChnTypes, uString, ChnParam;

{$I chnvirtnames.inc}   {- ChnTypes' and ChnParam's names, for "uses ChnVirt" alone }

const
  MaxLowChunk = 256;   {< bytes a protocol layer pulls from below at once }
  { bytes one ChReceiveTick of a protocol layer may feed its automaton, so
    a line babbling bytes that never make a frame cannot stall a poll }
  MaxBytesPerTick = 4096;
  MaxChnManagers = 32;

type
  pChnVirt = ^tChnVirt;
  tChnVirt = object
    CH_Type    : string[15];   {< layer type, the registry name ('DF1') }
    CH_Name    : string[15];   {< instance name, CH_Type unless changed }
    CH_NumName : Word;         {< ChNumName(CH_Type) }
    CH_Node    : tNode;        {< own station address }
    CH_DNode   : tNode;        {< destination station address }
    CH_RSNode  : tNode;        {< source address of the last received message }
    CH_RDNode  : tNode;        {< destination address of the last received message }
    CH_RCtrl   : tChState;     {< receiver automaton state }
    CH_State   : tChState;     {< life cycle: CHS_Close/Open/Connect/DisConnect }
    CH_Result  : tChResult;    {< result of the last life-cycle call }
    CH_SResult : tChResult;    {< result of the last send }
    CH_RResult : tChResult;    {< result of the last receive step }
    CH_Low     : pChnVirt;     {< the layer below; nil in a physical layer }
    CH_RBuff   : Pointer;      {< the application's receive buffer }
    CH_RSize   : Word;         {< and its size }
    CH_ParamErr: tWordString;  {< token that made the last ChSetParam fail }
    IData      : LongInt;      {< free for the application }
    { bytes pulled from the lower layer and not yet consumed }
    CH_LowBuf  : array[0..MaxLowChunk - 1] of Byte;
    CH_LowLen, CH_LowPos: Word;
    { what the code and the token of the last failed ChSetParam or ChOpen
      do not say: what the key allows, the OS's reason a device could not
      be opened; '' when nothing more is known (ChErrorText) }
    CH_ErrWhy  : tWordString;

    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;

    procedure ChSetParam(const S: tParamStr); virtual; overload;
    { The same for a long string (an AnsiString of new code): more than
      the legacy limit of 255 characters is refused with res_ParamTooLong
      (ChParamError says how long and the limit), never cut. }
    procedure ChSetParam(const S: AnsiString); overload;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    { '' : the whole configuration (cut after the last whole token that
      fits 255 characters); a key: only the tokens with that key }
    function  ChGetParam(const S: tParamStr): tParamStr; virtual;

    procedure ChOpen; virtual;
    procedure ChClose; virtual;
    procedure ChConnect; virtual;
    procedure ChDisConnect; virtual;
    function  ChReady: tChState; virtual;
    function  ChResult: tChResult; virtual;

    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    function  ChSendReady: tChState; virtual;
    function  ChSendResult: tChResult; virtual;

    procedure ChReceiveBuffer(Buff: Pointer; Size: Word); virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
    function  ChReceiveResult: tChResult; virtual;
    procedure ChReceiveFlush; virtual;
    procedure ChReceiveTick; virtual;

    procedure ChDestNode(DNode: tNode); virtual;
    procedure ChGetNode(var SNode, DNode: tNode); virtual;

    {- --- additions of the port (not in the SofCon manuals) --- }
    { The receive buffer ChReceiveBuffer gave last (nil, 0: none) and the
      destination ChDestNode set: what a helper that borrows the channel
      for an exchange gives back afterwards, through ChReceiveBuffer and
      ChDestNode. }
    procedure ChGetReceiveBuffer(var Buff: Pointer; var Size: Word);
    function  ChGetDestNode: tNode;
    { True while the layer holds input it has already pulled in: a
      message waiting for ChReceive, or bytes from below not yet fed to
      its automaton. A stepped client takes more messages in the same
      step only while this is True, so a step never waits for new input
      (a poll of a layer with IDL= may). }
    function  ChHoldsInput: Boolean; virtual;
    { The token that made the last ChSetParam fail ('' after success). }
    function  ChParamError: tWordString; virtual;
    { Readable text of a result code of this layer (protocol codes included). }
    function  ChResultStr(R: tChResult): ShortString; virtual;
    { ChResult as a sentence for a person: its text, the token at fault
      and why, when known - 'bad parameter (BD=abc): a number 50..4000000',
      'device cannot be opened (DEV=/dev/ttyUSB9): No such file or
      directory' (the OS's own words, on every OS and port backend). }
    function  ChErrorText: ShortString;
    { Own parameters as ' KEY=VALUE' tokens, for ChGetParam; descendants
      append theirs to inherited ChOwnParams. }
    function  ChOwnParams: tParamStr; virtual;
    { The whole-string check: called once every own token of the string
      passed its own check (ChSetOneParam with cmd_Check), before anything
      is applied, with the string's tokens (L.Items[L.OwnFirst ..
      L.OwnEnd - 1] this layer's). A layer whose keys depend on each other
      (FT 1.2: NOD=/DNO= on ADR=, in any order) checks them here; on an
      error it names the token at fault in Culprit. Default: res_Ok. }
    function  ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult; virtual;
    { ChSetParam's steps: check the own tokens; build the layer below }
    function  ChCheckOwn(const L: tParamList; var ErrTok: tWordString): tChResult;
    function  ChBuildLow(const S: tParamStr; const L: tParamList;
      var ErrTok: tWordString; var NewLow: pChnVirt): tChResult;
    { False for a physical layer, which cannot have a layer below. }
    function  ChHasLow: Boolean; virtual;
    { Highest station address NOD=/DNO= accept; 0: the layer has none. }
    function  ChMaxNode: tNode; virtual;
    { Next byte received by the lower layer, False if none is waiting now.
      Lower-layer errors are copied to CH_RResult. }
    function  ChLowGetByte(var B: Byte): Boolean;
    { True when bytes pulled from below wait in CH_LowBuf[CH_LowPos ..
      CH_LowLen - 1]; pulls the next chunk when none is left (errors as
      ChLowGetByte). For a loop that reads CH_LowBuf itself (tChnProto). }
    function  ChLowFill: Boolean;
    { Hand Len bytes to the lower layer's ChSend; result in CH_SResult. }
    procedure ChLowSend(Buff: Pointer; Len: Word);
    { Discard bytes pulled from the lower layer but not consumed yet. }
    procedure ChLowDiscard;
    { The check every ChOpen starts with: the channel closed. When not:
      CH_Result = res_WrongState, False. }
    function  ChOpenAllowed: Boolean;
    { The checks every ChReceive starts with: connected and a receive
      buffer given. When one fails: Len = 0, CH_RResult says why, False. }
    function  ChReceiveAllowed(var Len: Word): Boolean;
    { The checks every ChSend starts with: the channel open, a buffer given
      (and Len > 0 when NeedLen), the layer below present and idle - a
      protocol layer must not overwrite a send buffer the layer below may
      still be reading. When one fails: CH_SResult says why, False. }
    function  ChSendAllowed(Buff: Pointer; Len: Word; NeedLen: Boolean): Boolean;
    { The end of every successful ChOpen: state CHS_Open, receiver off until
      ChConnect, every result Ok, nothing pulled from below. }
    procedure ChOpened;
    { For a descendant's Init: CH_Type and CH_Name := AType, CH_NumName
      its ChNumName. }
    procedure ChSetType(const AType: ShortString);
    { LSB= of a protocol layer: the size of its send buffer Buf (Size
      bytes), Min..Max; with Min = 0, LSB=0 means none until the first
      send (ChSendBuffer). While the channel is open only the size in force
      is accepted (it changes nothing), another one is res_WrongState: the
      layer below may still be sending from the buffer. The same rule in
      every protocol layer. }
    function  ChParamSendBuffer(const S: tWordString; Min, Max: LongInt;
      CmdL: tCmd; var Buf: Pointer; var Size: Word): tChResult;
  end;

  pChnMiddle = ^tChnMiddle;
  { The ancestor of a middle layer that passes messages through (TRC,
    NOISE): station addresses, the receive automaton and protocol result
    codes belong to the layer below, so ChDestNode, ChGetNode,
    ChReceiveTick and ChResultStr (codes from res_Proto up) are handed to
    it. Without a layer below it behaves as tChnVirt. No fields of its own. }
  tChnMiddle = object(tChnVirt)
    procedure ChReceiveTick; virtual;
    procedure ChDestNode(DNode: tNode); virtual;
    procedure ChGetNode(var SNode, DNode: tNode); virtual;
    function  ChResultStr(R: tChResult): ShortString; virtual;
  end;

  pAddChnVirt = ^tAddChnVirt;
  { A manager knows how to create one layer type; one per layer unit,
    registered in ChnCollection from the unit's initialization. }
  tAddChnVirt = object
    Name: string[15];
    constructor Init(const AName: ShortString);
    destructor  Done; virtual;
    function    ChInit: pChnVirt; virtual;
  end;

  pChnCollection = ^tChnCollection;
  tChnCollection = object
    Count: SmallInt;
    Items: array[1..MaxChnManagers] of pAddChnVirt;
    constructor Init;
    destructor  Done; virtual;
    { Register a manager; a manager of the same name is replaced. A full
      table or a ChNumName clash stops the program with RunError(217), as
      the other registries do (docs/LAYERS.md). }
    procedure Insert(Item: pAddChnVirt);
    function  Search(const Name: ShortString): pAddChnVirt;
    { A new, initialised layer of that type, or nil for an unknown name. }
    function  ChNewInit(const Name: ShortString): pChnVirt;
  end;

{ Numeric identifier of a layer name: CRC-16 of the upper-cased name, the
  same in every program; registration refuses a clash. }
function ChNumName(const Name: ShortString): Word;

{ The library unit that registers layer Name ('TRC' -> 'ChnTrc'), '' for a
  name the library does not have: an unknown NAM= can say which unit is
  missing from the program's uses clause (unit ChnLayers links them all). }
function ChLayerUnit(const Name: ShortString): ShortString;
{ 'NAM=TRC: add ChnTrc to the uses clause' for a layer of the library
  that is not linked in, else 'NAM=NAME': the token an unknown layer
  error names. }
function ChUnknownLayerText(const Name: ShortString): ShortString;

{ Milliseconds from a monotonic clock, for timeouts and line-idle gaps. }
function ChMsTick: QWord;
{ Microseconds from a monotonic clock, for measuring what a millisecond
  cannot resolve (a byte's time at 115200 baud is 87 us): differences
  only, its zero is not ChMsTick's. Linux CLOCK_MONOTONIC, Windows
  QueryPerformanceCounter, other systems ChMsTick * 1000: ChnWait's
  ChnClockUs, the shared wait's time base, under the name beside
  ChMsTick. }
function ChUsTick: QWord;

{ ChSend once the transmitter is free, waiting for it at most TimeoutMs
  (res_Timeout); a channel fault while waiting is returned at once. For
  helpers above a channel (the DF1 and FT 1.2 link procedures). }
function ChSendWhenFree(Chn: pChnVirt; Buff: Pointer; Len: Word;
  TimeoutMs: LongInt): tChResult;
{ The wait of ChSendWhenFree alone: res_Ok once Chn^.ChSendReady says
  CHS_SendReady, res_Timeout after TimeoutMs, a channel fault at once. }
function ChWaitSendReady(Chn: pChnVirt; TimeoutMs: LongInt): tChResult;
{ A protocol layer's send buffer: allocated with Default bytes when none is
  there yet (no LSB=, or LSB=0), freed by Done. }
procedure ChSendBuffer(var Buf: Pointer; var Size: Word; Default: Word);
procedure ChFreeSendBuffer(var Buf: Pointer; var Size: Word);

var
  ChnCollection: pChnCollection;

implementation

uses
  SysUtils, ChnWait;

{$DEFINE CHNVIRT_BODIES}
{$I chnvirtnames.inc}

const
  { every layer name of the library and the unit that registers it }
  LayerUnits: array[0..8, 0..1] of string[9] = (
    ('COM', 'ChnCom'), ('TCP', 'ChnTcp'), ('LOOP', 'ChnLoop'),
    ('TRC', 'ChnTrc'), ('NOISE', 'ChnNoise'), ('DF1', 'ChnDF1'),
    ('FT1_2', 'ChnFT1_2'), ('ICS', 'ChnICS'), ('IEC104', 'ChnIec104'));

function ChLayerUnit(const Name: ShortString): ShortString;
var
  I: Integer;
begin
  Result := '';
  for I := Low(LayerUnits) to High(LayerUnits) do
    if LayerUnits[I, 0] = UpStr(Name) then
      Result := LayerUnits[I, 1];
end;

function ChUnknownLayerText(const Name: ShortString): ShortString;
begin
  Result := 'NAM=' + Name;
  if ChLayerUnit(Name) <> '' then
    Result := Result + ': add ' + ChLayerUnit(Name) + ' to the uses clause';
end;

function ChNumName(const Name: ShortString): Word;
var
  U: ShortString;
begin
  U := UpStr(Name);
  Result := Crc16Block(U[1], Length(U), $FFFF);
end;

function ChMsTick: QWord;
begin
  Result := GetTickCount64;
end;

function ChUsTick: QWord;
begin
  Result := ChnClockUs;             { the wait's clock: one per OS, in its OS part }
end;

function ChSendWhenFree(Chn: pChnVirt; Buff: Pointer; Len: Word;
  TimeoutMs: LongInt): tChResult;
begin
  Result := ChWaitSendReady(Chn, TimeoutMs);
  if Result <> res_Ok then
    Exit;
  Chn^.ChSend(Buff, Len);
  Result := Chn^.ChSendResult;
end;

function ChWaitSendReady(Chn: pChnVirt; TimeoutMs: LongInt): tChResult;
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(TimeoutMs);
  while Chn^.ChSendReady <> CHS_SendReady do
  begin
    if Chn^.ChResult <> res_Ok then
      Exit(Chn^.ChResult);
    if ChMsTick > Deadline then
      Exit(res_Timeout);
    { the program-wide wait ends when the transmitter can take more; at
      most 10 ms, for a transmitter that cannot end it (an RS-485 line
      draining with RTS raised) }
    ChnWaitUntil(Deadline + 1, 10);
  end;
  Result := res_Ok;
end;

procedure ChSendBuffer(var Buf: Pointer; var Size: Word; Default: Word);
begin
  if Buf = nil then
  begin
    GetMem(Buf, Default);
    Size := Default;
  end;
end;

procedure ChFreeSendBuffer(var Buf: Pointer; var Size: Word);
begin
  if Buf <> nil then
    FreeMem(Buf);
  Buf := nil;
  Size := 0;
end;

{ ---------------------------------------------------------------- tChnVirt }

constructor tChnVirt.Init;
begin
  CH_Type := '';
  CH_Name := '';
  CH_NumName := 0;
  CH_Node := 0;
  CH_DNode := 0;
  CH_RSNode := 0;
  CH_RDNode := 0;
  CH_RCtrl := CHS_RecInactive;
  CH_State := CHS_Close;
  CH_Result := res_Ok;
  CH_SResult := res_Ok;
  CH_RResult := res_Ok;
  CH_Low := nil;
  CH_RBuff := nil;
  CH_RSize := 0;
  CH_ParamErr := '';
  CH_ErrWhy := '';
  IData := 0;
  CH_LowLen := 0;
  CH_LowPos := 0;
end;

constructor tChnVirt.ChInitParam(const S: tParamStr);
begin
  { Constructors are not virtual: this calls tChnVirt.Init, so every
    descendant declares its own ChInitParam that calls its own Init. }
  Init;
  ChSetParam(S);
end;

destructor tChnVirt.Done;
begin
  if CH_State <> CHS_Close then
    ChClose;
  if CH_Low <> nil then
    Dispose(CH_Low, Done);
  CH_Low := nil;
end;

{ ChSetParam's check of this layer's own tokens (no side effects): the
  form, duplicates, then ChSetOneParam(cmd_Check) of each, then the
  whole-string check. ErrTok names the token at fault. }
function tChnVirt.ChCheckOwn(const L: tParamList; var ErrTok: tWordString): tChResult;
var
  I, J: LongInt;
  Cmd: tCmd;
begin
  Result := res_Ok;
  for I := L.OwnFirst to L.OwnEnd - 1 do
  begin
    ErrTok := L.Items[I].Text;
    if not L.Items[I].Ok then
      Exit(res_BadParam);
    for J := L.OwnFirst to I - 1 do
      if L.Items[J].Key = L.Items[I].Key then
        Exit(res_DupParam);
    Cmd := cmd_Check;
    ParamAllowedClear;
    Result := ChSetOneParam(L.Items[I].Text, Cmd);
    if Result = res_UnknownParam then
      CH_ErrWhy := CH_Type + ' takes' + ParamKeyList(ChOwnParams)
    else if Result <> res_Ok then
      CH_ErrWhy := ParamAllowed;
    if Result <> res_Ok then
      Exit;
  end;
  ErrTok := '';
  Result := ChCheckParams(L, ErrTok);
end;

{ ChSetParam's layer below, from the NAM= token Items[L.OwnEnd] on: built
  completely through its own (virtual) ChSetParam before anything changes
  here; NewLow nil when it fails (ErrTok: the token at fault). }
function tChnVirt.ChBuildLow(const S: tParamStr; const L: tParamList;
  var ErrTok: tWordString; var NewLow: pChnVirt): tChResult;
var
  Nam: tParamToken;
begin
  NewLow := nil;
  Nam := L.Items[L.OwnEnd];
  ErrTok := Nam.Text;
  if not Nam.Ok or not ChHasLow then
    Exit(res_BadParam);                 { a physical layer has nothing below }
  if CH_State <> CHS_Close then
    Exit(res_WrongState);               { cannot swap the stack while open }
  NewLow := ChnCollection^.ChNewInit(ParamValue(Nam.Text));
  if NewLow = nil then
  begin
    ErrTok := ChUnknownLayerText(ParamValue(Nam.Text));
    Exit(res_UnknownLayer);
  end;
  NewLow^.ChSetParam(Copy(S, Nam.Start, Length(S) - Nam.Start + 1));
  Result := NewLow^.ChResult;
  if Result <> res_Ok then
  begin
    ErrTok := NewLow^.ChParamError;
    CH_ErrWhy := NewLow^.CH_ErrWhy;
    Dispose(NewLow, Done);
    NewLow := nil;
  end;
end;

procedure tChnVirt.ChSetParam(const S: tParamStr);
var
  L: tParamList;
  I: LongInt;
  ErrTok: tWordString;
  Cmd: tCmd;
  R: tChResult;
  NewLow: pChnVirt;
begin
  CH_ParamErr := '';
  CH_ErrWhy := '';
  ParamSplit(S, L);
  { a leading NAM=<this layer's type> names this layer itself; any later
    NAM= starts the layer below (so 'NAM=TSTP NAM=TSTP' is two layers) }
  L.OwnFirst := 0;
  if (L.Count > 0) and (L.Items[0].Key = 'NAM') and
     (UpStr(ParamValue(L.Items[0].Text)) = UpStr(CH_Type)) then
    L.OwnFirst := 1;
  L.OwnEnd := L.OwnFirst;
  while (L.OwnEnd < L.Count) and (L.Items[L.OwnEnd].Key <> 'NAM') do
    Inc(L.OwnEnd);
  ErrTok := '';
  NewLow := nil;
  R := ChCheckOwn(L, ErrTok);
  if (R = res_Ok) and (L.OwnEnd < L.Count) then
    R := ChBuildLow(S, L, ErrTok, NewLow);
  if R <> res_Ok then
  begin
    CH_Result := R;
    CH_ParamErr := ErrTok;              { nothing is applied }
    Exit;
  end;
  for I := L.OwnFirst to L.OwnEnd - 1 do
  begin
    Cmd := cmd_Set;
    ChSetOneParam(L.Items[I].Text, Cmd);
  end;
  if NewLow <> nil then
  begin
    if CH_Low <> nil then
      Dispose(CH_Low, Done);
    CH_Low := NewLow;
  end;
  CH_Result := res_Ok;
end;

procedure tChnVirt.ChSetParam(const S: AnsiString);
var
  Why: ShortString;
begin
  Why := '';
  CH_Result := ParamLengthCheck(Length(S), Why);
  if CH_Result <> res_Ok then
    CH_ParamErr := Why                  { nothing is applied }
  else
    ChSetParam(tParamStr(S));         { the virtual one: a layer's override runs }
end;

function tChnVirt.ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult;
begin
  Result := res_Ok;
end;

function tChnVirt.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  N: LongInt;
begin
  Key := ParamKey(S);
  if ((Key = 'NOD') or (Key = 'DNO')) and (ChMaxNode > 0) then
  begin
    N := 0;
    Result := ParamNum(S, 0, ChMaxNode, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      if Key = 'NOD' then
        CH_Node := N
      else
        CH_DNode := N;
  end
  else
    Result := res_UnknownParam;
end;

function tChnVirt.ChOwnParams: tParamStr;
begin
  if ChMaxNode > 0 then
    Result := ParamText('NOD', CH_Node) + ParamText('DNO', CH_DNode)
  else
    Result := '';
end;

function tChnVirt.ChGetParam(const S: tParamStr): tParamStr;
var
  All: AnsiString;   { a deep stack may pass 255 characters }
  Own: tParamStr;
  Tok: string;
  P, Start: Integer;
  Want: string;
begin
  Own := ChOwnParams;
  { a full ShortString may have been cut inside its last token by the
    descendant's concatenation: keep whole tokens only, so it parses }
  if Length(Own) = High(tParamStr) then
    while (Length(Own) > 0) and (Own[Length(Own)] <> ' ') do
      SetLength(Own, Length(Own) - 1);
  All := 'NAM=' + CH_Type + Own;
  if CH_Low <> nil then
    All := All + ' ' + CH_Low^.ChGetParam('');
  Want := UpStr(S);
  if Want = '' then
  begin
    { too long for a tParamStr: cut at the last whole token, so the text
      still parses. A getter leaves CH_Result alone: polling loops read a
      result there as a fault of the line. }
    if Length(All) > High(tParamStr) then
    begin
      P := High(tParamStr) + 1;
      while (P > 1) and (All[P] <> ' ') do
        Dec(P);
      SetLength(All, P - 1);
    end;
    Exit(All);
  end;
  { S names a key: return only the tokens with that key, from the whole text }
  Result := '';
  P := 1;
  while P <= Length(All) do
  begin
    while (P <= Length(All)) and (All[P] = ' ') do
      Inc(P);
    Start := P;
    while (P <= Length(All)) and (All[P] <> ' ') do
      Inc(P);
    Tok := Copy(All, Start, P - Start);
    if (Tok <> '') and (ParamKey(Tok) = Want) then
    begin
      if Result <> '' then
        Result := Result + ' ';
      Result := Result + Tok;
    end;
  end;
end;

function tChnVirt.ChParamError: tWordString;
begin
  Result := CH_ParamErr;
end;

function tChnVirt.ChResultStr(R: tChResult): ShortString;
begin
  Result := ChResultText(R, CH_Type);
end;

function tChnVirt.ChErrorText: ShortString;
var
  R: tChResult;
begin
  R := ChResult;
  Result := ChResultStr(R);
  if R = res_Ok then
    Exit;
  if ChParamError <> '' then
    Result := Result + ' (' + ChParamError + ')';
  if CH_ErrWhy <> '' then
    Result := Result + ': ' + CH_ErrWhy;
end;

function tChnVirt.ChHasLow: Boolean;
begin
  Result := True;
end;

function tChnVirt.ChMaxNode: tNode;
begin
  Result := 0;
end;

{ Life cycle. A protocol layer opens, connects, disconnects and closes the
  whole stack below it; a physical layer overrides ChOpen/ChClose. }

procedure tChnVirt.ChOpen;
begin
  if not ChOpenAllowed then
    Exit;
  if ChHasLow then
  begin
    if CH_Low = nil then
    begin
      CH_Result := res_NoLowLayer;
      Exit;
    end;
    CH_Low^.ChOpen;
    CH_Result := CH_Low^.ChResult;
    if CH_Result <> res_Ok then
    begin
      CH_ParamErr := CH_Low^.ChParamError;  { the setting a device refused }
      CH_ErrWhy := CH_Low^.CH_ErrWhy;
      Exit;
    end;
  end;
  ChOpened;
end;

procedure tChnVirt.ChSetType(const AType: ShortString);
begin
  CH_Type := AType;
  CH_Name := CH_Type;
  CH_NumName := ChNumName(CH_Type);
end;

function tChnVirt.ChParamSendBuffer(const S: tWordString; Min, Max: LongInt;
  CmdL: tCmd; var Buf: Pointer; var Size: Word): tChResult;
var
  N: LongInt;
begin
  N := 0;
  Result := ParamNum(S, Min, Max, N);
  if (Result <> res_Ok) or (N = Size) then
    Exit;
  if CH_State <> CHS_Close then
    Result := res_WrongState
  else if CmdL = cmd_Set then
  begin
    ChFreeSendBuffer(Buf, Size);
    if N > 0 then
      GetMem(Buf, N);
    Size := N;
  end;
end;

procedure tChnVirt.ChOpened;
begin
  CH_LowLen := 0;
  CH_LowPos := 0;
  CH_State := CHS_Open;
  CH_RCtrl := CHS_RecInactive;
  CH_Result := res_Ok;
  CH_SResult := res_Ok;
  CH_RResult := res_Ok;
  CH_ErrWhy := '';              { nothing left of an earlier failure }
end;

procedure tChnVirt.ChClose;
begin
  if CH_State = CHS_Close then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  if (CH_Low <> nil) and (CH_Low^.ChReady <> CHS_Close) then
    CH_Low^.ChClose;
  CH_State := CHS_Close;
  CH_RCtrl := CHS_RecInactive;
  CH_Result := res_Ok;
end;

procedure tChnVirt.ChConnect;
begin
  if (CH_State <> CHS_Open) and (CH_State <> CHS_DisConnect) then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  if CH_Low <> nil then
  begin
    CH_Low^.ChConnect;
    CH_Result := CH_Low^.ChResult;
    if CH_Result <> res_Ok then
      Exit;
    CH_Low^.ChReceiveBuffer(@CH_LowBuf, SizeOf(CH_LowBuf));
  end;
  CH_LowLen := 0;
  CH_LowPos := 0;
  CH_State := CHS_Connect;
  CH_RCtrl := CHS_Receiving;
  CH_RResult := res_Ok;
  CH_Result := res_Ok;
end;

procedure tChnVirt.ChDisConnect;
begin
  if CH_State <> CHS_Connect then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  if CH_Low <> nil then
    CH_Low^.ChDisConnect;
  CH_State := CHS_DisConnect;
  CH_RCtrl := CHS_RecInactive;
  CH_Result := res_Ok;
end;

function tChnVirt.ChReady: tChState;
begin
  Result := CH_State;
end;

function tChnVirt.ChResult: tChResult;
begin
  Result := CH_Result;
  { a fault below (device lost ...) shows through every layer above }
  if (Result = res_Ok) and (CH_Low <> nil) and (CH_State <> CHS_Close) then
    Result := CH_Low^.ChResult;
end;

{ Sending. The base passes messages down unchanged (a transparent layer);
  protocol layers encode and then call ChLowSend. }

procedure tChnVirt.ChSend(Buff: Pointer; Len: Word);
begin
  if ChSendAllowed(Buff, Len, True) then
    ChLowSend(Buff, Len);
end;

function tChnVirt.ChSendAllowed(Buff: Pointer; Len: Word; NeedLen: Boolean): Boolean;
begin
  Result := False;
  if (CH_State = CHS_Close) or (CH_State = CHS_Opening) then
    CH_SResult := res_WrongState
  else if (Buff = nil) or (NeedLen and (Len = 0)) then
    CH_SResult := res_BadLen
  else if ChHasLow and (CH_Low = nil) then
    CH_SResult := res_NoLowLayer
  else if (CH_Low <> nil) and (CH_Low^.ChSendReady <> CHS_SendReady) then
    CH_SResult := res_Busy
  else
    Result := True;
end;

procedure tChnVirt.ChLowSend(Buff: Pointer; Len: Word);
begin
  if CH_Low = nil then
    CH_SResult := res_NoLowLayer
  else if CH_Low^.ChSendReady <> CHS_SendReady then
    CH_SResult := res_Busy
  else
  begin
    CH_Low^.ChSend(Buff, Len);
    CH_SResult := CH_Low^.ChSendResult;
  end;
end;

function tChnVirt.ChSendReady: tChState;
begin
  if CH_Low <> nil then
    Result := CH_Low^.ChSendReady
  else
    Result := CHS_SendReady;
end;

function tChnVirt.ChSendResult: tChResult;
begin
  Result := CH_SResult;
  if (Result = res_Ok) and (CH_Low <> nil) then
    Result := CH_Low^.ChSendResult;
end;

{ Receiving }

procedure tChnVirt.ChReceiveBuffer(Buff: Pointer; Size: Word);
begin
  if (Buff = nil) or (Size = 0) then
  begin
    CH_RBuff := nil;
    CH_RSize := 0;
    CH_RResult := res_NoRecBuff;
  end
  else
  begin
    CH_RBuff := Buff;
    CH_RSize := Size;
    CH_RResult := res_Ok;
  end;
end;

function tChnVirt.ChReceiveReady: tChState;
begin
  ChReceiveTick;
  Result := CH_RCtrl;
  if Result >= CHS_ProtoBase then
    Result := CHS_Receiving;     { private automaton states look alike outside }
end;

procedure tChnVirt.ChReceive(var Len: Word);
begin
  { the base has no receiver of its own; descendants implement it }
  if ChReceiveAllowed(Len) then
    CH_RResult := res_NoMessage;
end;

function tChnVirt.ChOpenAllowed: Boolean;
begin
  Result := CH_State = CHS_Close;
  if not Result then
    CH_Result := res_WrongState;
end;

function tChnVirt.ChReceiveAllowed(var Len: Word): Boolean;
begin
  Len := 0;
  Result := False;
  if CH_State <> CHS_Connect then
    CH_RResult := res_WrongState
  else if CH_RBuff = nil then
    CH_RResult := res_NoRecBuff
  else
    Result := True;
end;

function tChnVirt.ChReceiveResult: tChResult;
begin
  Result := CH_RResult;
end;

procedure tChnVirt.ChReceiveFlush;
begin
  ChLowDiscard;
  if CH_Low <> nil then
    CH_Low^.ChReceiveFlush;
  if CH_State = CHS_Connect then
    CH_RCtrl := CHS_Receiving;
  CH_RResult := res_Ok;
end;

procedure tChnVirt.ChReceiveTick;
begin
end;

procedure tChnVirt.ChGetReceiveBuffer(var Buff: Pointer; var Size: Word);
begin
  Buff := CH_RBuff;
  Size := CH_RSize;
end;

function tChnVirt.ChGetDestNode: tNode;
begin
  Result := CH_DNode;
end;

function tChnVirt.ChHoldsInput: Boolean;
begin
  Result := (CH_RCtrl = CHS_ReceiveReady) or (CH_LowPos < CH_LowLen);
end;

procedure tChnVirt.ChDestNode(DNode: tNode);
begin
  CH_DNode := DNode;
end;

procedure tChnVirt.ChGetNode(var SNode, DNode: tNode);
begin
  SNode := CH_RSNode;
  DNode := CH_RDNode;
end;

function tChnVirt.ChLowFill: Boolean;
var
  N: Word;
  R: tChResult;
begin
  if CH_LowPos < CH_LowLen then
    Exit(True);
  CH_LowPos := 0;
  CH_LowLen := 0;
  if CH_Low = nil then
    Exit(False);
  if CH_Low^.ChReceiveReady <> CHS_ReceiveReady then
  begin
    R := CH_Low^.ChReceiveResult;
    if R <> res_Ok then
      CH_RResult := R;
    Exit(False);
  end;
  N := 0;
  CH_Low^.ChReceive(N);
  R := CH_Low^.ChReceiveResult;
  if R <> res_Ok then
    CH_RResult := R;          { e.g. res_Overrun: report, keep the bytes }
  if N > SizeOf(CH_LowBuf) then
    N := SizeOf(CH_LowBuf);
  CH_LowLen := N;
  Result := N > 0;
end;

function tChnVirt.ChLowGetByte(var B: Byte): Boolean;
begin
  Result := ChLowFill;
  if Result then
  begin
    B := CH_LowBuf[CH_LowPos];
    Inc(CH_LowPos);
  end;
end;

procedure tChnVirt.ChLowDiscard;
begin
  CH_LowLen := 0;
  CH_LowPos := 0;
end;

{- -------------------------------------------------------------- tChnMiddle }

procedure tChnMiddle.ChReceiveTick;
begin
  if (CH_State = CHS_Connect) and (CH_Low <> nil) then
    CH_Low^.ChReceiveTick;
end;

procedure tChnMiddle.ChDestNode(DNode: tNode);
begin
  inherited ChDestNode(DNode);
  if CH_Low <> nil then
    CH_Low^.ChDestNode(DNode);
end;

procedure tChnMiddle.ChGetNode(var SNode, DNode: tNode);
begin
  if CH_Low <> nil then
    CH_Low^.ChGetNode(SNode, DNode)
  else
    inherited ChGetNode(SNode, DNode);
end;

function tChnMiddle.ChResultStr(R: tChResult): ShortString;
begin
  { a middle layer's own codes of that range, if any, are not results of
    the channel (TRC's belong to its log reader) }
  if (R >= res_Proto) and (CH_Low <> nil) then
    Result := CH_Low^.ChResultStr(R)
  else
    Result := inherited ChResultStr(R);
end;

{- ------------------------------------------------------------- tAddChnVirt }

constructor tAddChnVirt.Init(const AName: ShortString);
begin
  Name := UpStr(AName);
end;

destructor tAddChnVirt.Done;
begin
end;

function tAddChnVirt.ChInit: pChnVirt;
begin
  Result := nil;
end;

{- ---------------------------------------------------------- tChnCollection }

constructor tChnCollection.Init;
begin
  Count := 0;
end;

destructor tChnCollection.Done;
var
  I: Integer;
begin
  for I := 1 to Count do
    Dispose(Items[I], Done);
  Count := 0;
end;

procedure tChnCollection.Insert(Item: pAddChnVirt);
var
  I: Integer;
begin
  if Item = nil then
    Exit;
  for I := 1 to Count do
    if Items[I]^.Name = Item^.Name then
    begin
      Dispose(Items[I], Done);
      Items[I] := Item;
      Exit;
    end;
  for I := 1 to Count do
    if ChNumName(Items[I]^.Name) = ChNumName(Item^.Name) then
      RunError(217);   { programming error: two names share a ChNumName }
  if Count >= MaxChnManagers then
    RunError(217);     { programming error: raise MaxChnManagers }
  Inc(Count);
  Items[Count] := Item;
end;

function tChnCollection.Search(const Name: ShortString): pAddChnVirt;
var
  I: Integer;
  U: string;
begin
  U := UpStr(Name);
  for I := 1 to Count do
    if Items[I]^.Name = U then
      Exit(Items[I]);
  Result := nil;
end;

function tChnCollection.ChNewInit(const Name: ShortString): pChnVirt;
var
  M: pAddChnVirt;
begin
  M := Search(Name);
  if M = nil then
    Result := nil
  else
    Result := M^.ChInit;
end;

initialization
  New(ChnCollection, Init);
finalization
  Dispose(ChnCollection, Done);
  ChnCollection := nil;
end.
