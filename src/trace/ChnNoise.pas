{ ChnNoise - a noise layer (NAM=NOISE): a bad line for testing, put between
  a protocol and its physical layer like NAM=TRC.

    'NAM=DF1 ... NAM=NOISE BER=1E-5 DRP=0.01 SEED=42 NAM=COM DEV=/dev/ttyUSB0'

  Not in the SofCon manuals; an addition of the port. Every byte that
  passes (received and sent, or one direction with DIR=) may have bits
  flipped, be dropped, or have a garbage byte inserted before it:
    BER=p    probability of each bit being inverted (0..1, e.g. 1E-5)
    DRP=p    probability of a byte being dropped (0.01 = 1 %)
    INS=p    probability of a garbage byte before a byte
    BYTE=n|RND  the garbage byte: always n (0..255), or random (default)
    CNT=n    at most n garbage bytes in all (0 = no limit, the default)
    DIR=BOTH|RX|TX  which direction is disturbed (default BOTH)
    SEED=n   1..2147483647; 0 (the default) takes a new seed at each ChOpen
             from the clock. ChGetParam reports the seed in use, so the
             parameters of a failing run replay it.
  Rates are plain or exponent numbers ('0.001', '1E-3'); 0 disables.
  Faults of whole chunks (a chunk sent is one ChSend of the layer above,
  i.e. one frame), for link procedures:
    LOS=p    probability of a sent chunk being lost whole
    STL=p    probability of the line stalling before a sent chunk: for
             STM= ms nothing passes in either direction; then what was
             held goes on, in order (a relay or a radio that stops)
    STM=ms   length of a stall, 1..600000 (default 1500)
    ROR=p    probability of a sent chunk being held back and going after
             the next one (at the latest STM ms later): reordering
  A stall or a held chunk ends at the first call into the layer after its
  time (the layer has no clock of its own to wake a wait); input held
  after a stall counts as held for ChnWaitAny.

  Replay: what happens to a byte depends only on the seed, the direction
  and the byte's position in that direction's stream since ChConnect (a
  counter-based generator, not a sequence drawn per call). The same seed
  and the same bytes give the same damage whatever the chunk sizes of the
  line, so a soak failure replays from its seed.

  Without a layer below, the layer is a line on which nothing but garbage
  arrives: it always has bytes waiting (BYTE= or random, CNT= in all) and
  swallows what is sent. Tests use it as a babbling line.

  Counters for the curious: CH_Flipped (bits), CH_Dropped, CH_Inserted,
  CH_Passed (bytes that went through, per direction). }
unit ChnNoise;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt;

const
  cName = 'NOISE';
  NoiseRandomByte = -1;   {< BYTE=RND }

type
  tNoiseDir = (ndRx, ndTx);

  pChnNoise = ^tChnNoise;
  tChnNoise = object(tChnMiddle)
    CH_Ber, CH_Drop, CH_Ins: Double;     {< BER= DRP= INS= }
    CH_BerT, CH_DropT, CH_InsT: LongWord; {< the same as thresholds of 2^32 }
    CH_Garbage : LongInt;     {< BYTE=: 0..255 or NoiseRandomByte }
    CH_Limit   : LongInt;     {< CNT=: garbage bytes in all, 0 = no limit }
    CH_DirRx, CH_DirTx: Boolean;  {< DIR= }
    CH_SeedSet : LongInt;     {< SEED= as given (0: new at each ChOpen) }
    CH_Seed    : LongInt;     {< the seed in use }
    CH_Pos     : array[tNoiseDir] of QWord;   {< stream positions }
    CH_Passed  : array[tNoiseDir] of QWord;
    CH_Flipped, CH_Dropped, CH_Inserted: QWord;
    CH_Pend    : array[0..1] of Byte;   {< received bytes not yet handed up }
    CH_PendLen, CH_PendPos: Byte;
    CH_TxBuf   : PByte;       {< sent bytes after the damage }
    CH_TxSize  : LongInt;
    { chunk faults: LOS= STL= STM= ROR= }
    CH_Los, CH_Stl, CH_Ror: Double;
    CH_LosT, CH_StlT, CH_RorT: LongWord;
    CH_StallMs : LongInt;
    CH_Chunk   : QWord;       {< chunks sent since ChConnect }
    CH_StallEnd: QWord;       {< 0: no stall now }
    CH_OutQ    : PByte;       {< bytes for the layer below, in order }
    CH_OutLen, CH_OutCap: LongInt;
    CH_RorBuf  : PByte;       {< a chunk held back to go after the next }
    CH_RorLen, CH_RorCap: LongInt;
    CH_RorEnd  : QWord;
    CH_RxQ     : PByte;       {< input held by a stall, then handed up first }
    CH_RxLen, CH_RxPos, CH_RxCap: LongInt;
    CH_RxHeld  : Boolean;     {< ChnWaitHeld's flag }
    CH_ChunksLost, CH_Stalls, CH_Reordered: QWord;
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    procedure ChOpen; virtual;
    procedure ChConnect; virtual;
    procedure ChClose; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
    procedure ChReceiveFlush; virtual;
    { What the line makes of byte B at the next position of direction Dir:
      0, 1 or 2 bytes in Out (garbage first). }
    function  ChDamage(Dir: tNoiseDir; B: Byte; var Out: array of Byte): LongInt;
    function  ChSendReady: tChState; virtual;
  private
    function  ChunkFaults: Boolean;
    procedure ChunkPump;
    procedure ChunkSend(P: PByte; N: LongInt);
    function  NextRaw(var B: Byte): Boolean;
    procedure ChunkReset;
  end;

  pAddChnNoise = ^tAddChnNoise;
  tAddChnNoise = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ 64 random bits for (Seed, Dir, Pos, K): splitmix64 of the four. }
function NoiseHash(Seed: LongInt; Dir: tNoiseDir; Pos: QWord; K: Byte): QWord;

implementation

uses
  SysUtils, uString, ChnWait;

const
  MaxStallHold = 65536;     { input kept during a stall; more is lost }
  StallChoice = 1500;       { STM= default }

{ Append N bytes at Src to the buffer Buf (Len used, Cap allocated). }
procedure Append(var Buf: PByte; var Len, Cap: LongInt; Src: PByte; N: LongInt);
begin
  if N <= 0 then
    Exit;
  if Len + N > Cap then
  begin
    Cap := 2 * (Len + N);
    ReAllocMem(Buf, Cap);
  end;
  Move(Src^, Buf[Len], N);
  Inc(Len, N);
end;

procedure FreeBuf(var Buf: PByte; var Len, Cap: LongInt);
begin
  if Buf <> nil then
    FreeMem(Buf);
  Buf := nil;
  Len := 0;
  Cap := 0;
end;

const
  DirChoice = 'BOTH|RX|TX';
  MaxRate = 1.0;

{$PUSH}{$Q-}{$R-}   { the generator wraps on purpose }
function NoiseHash(Seed: LongInt; Dir: tNoiseDir; Pos: QWord; K: Byte): QWord;
var
  Z: QWord;
begin
  Z := (QWord(LongWord(Seed)) shl 32) xor (QWord(Ord(Dir)) shl 63) xor
       (Pos * 16 + K);
  Z := Z + QWord($9E3779B97F4A7C15);
  Z := (Z xor (Z shr 30)) * QWord($BF58476D1CE4E5B9);
  Z := (Z xor (Z shr 27)) * QWord($94D049BB133111EB);
  Result := Z xor (Z shr 31);
end;

function Threshold(P: Double): LongWord;
begin
  if P >= 1 then
    Result := High(LongWord)
  else
    Result := LongWord(Trunc(P * 4294967296.0));
end;
{$POP}

function RateText(const Key: string; P: Double): string;
var
  FS: TFormatSettings;
begin
  FS := DefaultFormatSettings;
  FS.DecimalSeparator := '.';
  Result := ' ' + Key + '=' + FloatToStrF(P, ffGeneral, 9, 0, FS);
end;

constructor tChnNoise.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Ber := 0;  CH_Drop := 0;  CH_Ins := 0;
  CH_BerT := 0; CH_DropT := 0; CH_InsT := 0;
  CH_Garbage := NoiseRandomByte;
  CH_Limit := 0;
  CH_DirRx := True;
  CH_DirTx := True;
  CH_SeedSet := 0;
  CH_Seed := 1;
  CH_TxBuf := nil;
  CH_TxSize := 0;
  CH_PendLen := 0;
  CH_PendPos := 0;
  CH_Pos[ndRx] := 0; CH_Pos[ndTx] := 0;
  CH_Passed[ndRx] := 0; CH_Passed[ndTx] := 0;
  CH_Flipped := 0; CH_Dropped := 0; CH_Inserted := 0;
  CH_Los := 0; CH_Stl := 0; CH_Ror := 0;
  CH_LosT := 0; CH_StlT := 0; CH_RorT := 0;
  CH_StallMs := StallChoice;
  CH_OutQ := nil; CH_OutLen := 0; CH_OutCap := 0;
  CH_RorBuf := nil; CH_RorLen := 0; CH_RorCap := 0;
  CH_RxQ := nil; CH_RxLen := 0; CH_RxCap := 0; CH_RxPos := 0;
  CH_RxHeld := False;
  CH_ChunksLost := 0; CH_Stalls := 0; CH_Reordered := 0;
  ChunkReset;
end;

constructor tChnNoise.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnNoise.Done;
begin
  inherited Done;
  if CH_TxBuf <> nil then
    FreeMem(CH_TxBuf, CH_TxSize);
  CH_TxBuf := nil;
  ChunkReset;
  FreeBuf(CH_OutQ, CH_OutLen, CH_OutCap);
  FreeBuf(CH_RorBuf, CH_RorLen, CH_RorCap);
  FreeBuf(CH_RxQ, CH_RxLen, CH_RxCap);
end;

{ A probability 0..1 (BER= DRP= INS= LOS= STL= ROR=) and its threshold of
  2^32, set only when CmdL = cmd_Set. }
function RateParam(const S: tWordString; CmdL: tCmd; var Rate: Double;
  var T: LongWord): tChResult;
var
  P: Double;
begin
  P := 0;
  if not StrToReal(ParamValue(S), 0, MaxRate, P) then
    Exit(ParamBad('a probability 0..1 (0.01, 1E-5)'));
  if CmdL = cmd_Set then
  begin
    Rate := P;
    T := Threshold(P);
  end;
  Result := res_Ok;
end;

function tChnNoise.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  N := 0;
  I := 0;
  if Key = 'BER' then
    Result := RateParam(S, CmdL, CH_Ber, CH_BerT)
  else if Key = 'DRP' then
    Result := RateParam(S, CmdL, CH_Drop, CH_DropT)
  else if Key = 'INS' then
    Result := RateParam(S, CmdL, CH_Ins, CH_InsT)
  else if Key = 'LOS' then
    Result := RateParam(S, CmdL, CH_Los, CH_LosT)
  else if Key = 'STL' then
    Result := RateParam(S, CmdL, CH_Stl, CH_StlT)
  else if Key = 'ROR' then
    Result := RateParam(S, CmdL, CH_Ror, CH_RorT)
  else if Key = 'STM' then
    Result := ParamSetNum(S, 1, 600000, CmdL, CH_StallMs)
  else if Key = 'BYTE' then
  begin
    if UpStr(ParamValue(S)) = 'RND' then
    begin
      Result := res_Ok;
      N := NoiseRandomByte;
    end
    else
      Result := ParamNum(S, 0, 255, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Garbage := N;
  end
  else if Key = 'CNT' then
    Result := ParamSetNum(S, 0, MaxLongInt, CmdL, CH_Limit)
  else if Key = 'SEED' then
  begin
    Result := ParamNum(S, 0, MaxLongInt, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
    begin
      CH_SeedSet := N;
      if N <> 0 then
        CH_Seed := N;
    end;
  end
  else if Key = 'DIR' then
  begin
    Result := ParamChoice(S, DirChoice, I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
    begin
      CH_DirRx := I <> 2;
      CH_DirTx := I <> 1;
    end;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnNoise.ChOwnParams: tParamStr;
var
  G, Dir, ChunkText: string;
begin
  { the chunk faults only when used: the string stays short }
  ChunkText := '';
  if CH_Los > 0 then
    ChunkText := RateText('LOS', CH_Los);
  if CH_Stl > 0 then
    ChunkText := ChunkText + RateText('STL', CH_Stl);
  if CH_Ror > 0 then
    ChunkText := ChunkText + RateText('ROR', CH_Ror);
  if (CH_Stl > 0) or (CH_Ror > 0) or (CH_StallMs <> StallChoice) then
    ChunkText := ChunkText + ParamText('STM', CH_StallMs);
  if CH_DirRx and CH_DirTx then
    Dir := 'BOTH'
  else if CH_DirRx then
    Dir := 'RX'
  else
    Dir := 'TX';
  if CH_Garbage = NoiseRandomByte then
    G := 'RND'
  else
    G := NumStr(CH_Garbage);
  Result := inherited ChOwnParams + RateText('BER', CH_Ber) + RateText('DRP', CH_Drop) +
    RateText('INS', CH_Ins) + ChunkText +
    ' BYTE=' + G + ParamText('CNT', CH_Limit) +
    ' DIR=' + Dir + ParamText('SEED', CH_Seed);
end;

procedure tChnNoise.ChOpen;
begin
  if not ChOpenAllowed then
    Exit;
  if CH_SeedSet = 0 then
    CH_Seed := LongInt((GetTickCount64 * 2654435761 + QWord(GetProcessID)) mod MaxLongInt) + 1;
  if CH_Low = nil then
    ChOpened                     { a line of nothing but noise }
  else
    inherited ChOpen;
end;

procedure tChnNoise.ChConnect;
begin
  inherited ChConnect;
  if CH_Result = res_Ok then
  begin
    CH_Pos[ndRx] := 0;
    CH_Pos[ndTx] := 0;
    CH_PendLen := 0;
    CH_PendPos := 0;
    ChunkReset;
  end;
end;

procedure tChnNoise.ChClose;
begin
  inherited ChClose;
  ChunkReset;                    { what a stall held is gone with the line }
end;

{- ------------------------------------------------------- chunk faults }

function tChnNoise.ChunkFaults: Boolean;
begin
  Result := (CH_Low <> nil) and ((CH_LosT > 0) or (CH_StlT > 0) or (CH_RorT > 0) or
    (CH_OutLen > 0) or (CH_RorLen > 0) or (CH_RxPos < CH_RxLen) or (CH_StallEnd <> 0));
end;

procedure tChnNoise.ChunkReset;
begin
  CH_Chunk := 0;
  CH_StallEnd := 0;
  CH_OutLen := 0;
  CH_RorLen := 0;
  CH_RxLen := 0;
  CH_RxPos := 0;
  ChnWaitHeld(CH_RxHeld, False);
end;

{ Time up for a stall or a held chunk; hand what may go to the layer
  below; take input during a stall off the line (so no ring below holds
  it and keeps a program's wait awake). }
procedure tChnNoise.ChunkPump;
var
  Now: QWord;
  B: Byte;
begin
  Now := GetTickCount64;
  if (CH_StallEnd <> 0) and (Now >= CH_StallEnd) then
    CH_StallEnd := 0;
  if (CH_RorLen > 0) and (Now >= CH_RorEnd) then
  begin
    Append(CH_OutQ, CH_OutLen, CH_OutCap, CH_RorBuf, CH_RorLen);   { nothing came after it }
    CH_RorLen := 0;
  end;
  if CH_StallEnd <> 0 then
  begin
    while (CH_State = CHS_Connect) and (CH_Low^.ChReceiveReady = CHS_ReceiveReady) and
          ChLowGetByte(B) do
      if CH_RxLen < MaxStallHold then
        Append(CH_RxQ, CH_RxLen, CH_RxCap, @B, 1)
      else
        Inc(CH_Dropped);
  end
  else if (CH_OutLen > 0) and (CH_Low^.ChSendReady = CHS_SendReady) then
  begin
    ChLowSend(CH_OutQ, CH_OutLen);
    if CH_SResult = res_Ok then
      CH_OutLen := 0;
  end;
  if CH_RxPos >= CH_RxLen then
  begin
    CH_RxLen := 0;
    CH_RxPos := 0;
  end;
  ChnWaitHeld(CH_RxHeld, (CH_StallEnd = 0) and (CH_RxPos < CH_RxLen));
end;

{ A damaged chunk from the layer above: lost, held back, or queued. }
procedure tChnNoise.ChunkSend(P: PByte; N: LongInt);
var
  K: QWord;
begin
  K := CH_Chunk;
  Inc(CH_Chunk);
  CH_SResult := res_Ok;
  if LongWord(NoiseHash(CH_Seed, ndTx, K, 10)) < CH_LosT then
  begin
    Inc(CH_ChunksLost);
    ChunkPump;
    Exit;
  end;
  if (CH_StallEnd = 0) and (LongWord(NoiseHash(CH_Seed, ndTx, K, 11)) < CH_StlT) then
  begin
    Inc(CH_Stalls);
    CH_StallEnd := GetTickCount64 + QWord(CH_StallMs);
  end;
  if (CH_RorLen = 0) and (LongWord(NoiseHash(CH_Seed, ndTx, K, 12)) < CH_RorT) then
  begin
    Inc(CH_Reordered);
    Append(CH_RorBuf, CH_RorLen, CH_RorCap, P, N);
    CH_RorEnd := GetTickCount64 + QWord(CH_StallMs);
  end
  else
  begin
    Append(CH_OutQ, CH_OutLen, CH_OutCap, P, N);
    if CH_RorLen > 0 then
    begin
      Append(CH_OutQ, CH_OutLen, CH_OutCap, CH_RorBuf, CH_RorLen);   { after this one }
      CH_RorLen := 0;
    end;
  end;
  ChunkPump;
  CH_SResult := res_Ok;          { on the line, as far as the sender can tell }
end;

{ The next received byte before the damage: held by a stall first. }
function tChnNoise.NextRaw(var B: Byte): Boolean;
begin
  if CH_RxPos < CH_RxLen then
  begin
    B := CH_RxQ[CH_RxPos];
    Inc(CH_RxPos);
    Result := True;
  end
  else
    Result := ChLowGetByte(B);
end;

function tChnNoise.ChSendReady: tChState;
begin
  if ChunkFaults then
  begin
    ChunkPump;
    if (CH_OutLen > 0) and (CH_StallEnd = 0) then
      Exit(CHS_Sending);         { the layer below is still busy }
  end;
  Result := inherited ChSendReady;
end;

function tChnNoise.ChDamage(Dir: tNoiseDir; B: Byte; var Out: array of Byte): LongInt;
var
  H: QWord;
  K: Byte;
  Drop: Boolean;
begin
  H := NoiseHash(CH_Seed, Dir, CH_Pos[Dir], 0);
  Result := 0;
  if (LongWord(H shr 32) < CH_InsT) and
     ((CH_Limit = 0) or (CH_Inserted < QWord(CH_Limit))) then
  begin
    if CH_Garbage = NoiseRandomByte then
      Out[0] := Byte(NoiseHash(CH_Seed, Dir, CH_Pos[Dir], 9))
    else
      Out[0] := CH_Garbage;
    Inc(CH_Inserted);
    Result := 1;
  end;
  Drop := LongWord(H and $FFFFFFFF) < CH_DropT;
  if Drop then
    Inc(CH_Dropped)
  else
  begin
    if CH_BerT > 0 then
      for K := 0 to 7 do
        if LongWord(NoiseHash(CH_Seed, Dir, CH_Pos[Dir], 1 + K)) < CH_BerT then
        begin
          B := B xor (1 shl K);
          Inc(CH_Flipped);
        end;
    Out[Result] := B;
    Inc(Result);
    Inc(CH_Passed[Dir]);
  end;
  Inc(CH_Pos[Dir]);
end;

procedure tChnNoise.ChSend(Buff: Pointer; Len: Word);
var
  I, N, Need: LongInt;
  Two: array[0..1] of Byte;
  In_: PByte;
begin
  if (CH_Low = nil) and (CH_State <> CHS_Close) and (CH_State <> CHS_Opening) then
  begin
    CH_SResult := res_Ok;        { nothing on the line hears it }
    Exit;
  end;
  if not ChSendAllowed(Buff, Len, False) then
    Exit;
  if not CH_DirTx or (Len = 0) then
  begin
    if ChunkFaults and (Len > 0) then
      ChunkSend(Buff, Len)
    else
      ChLowSend(Buff, Len);
    Exit;
  end;
  Need := 2 * LongInt(Len);
  if Need > CH_TxSize then
  begin
    if CH_TxBuf <> nil then
      FreeMem(CH_TxBuf, CH_TxSize);
    CH_TxSize := Need;
    GetMem(CH_TxBuf, CH_TxSize);
  end;
  In_ := Buff;
  N := 0;
  for I := 0 to Len - 1 do
  begin
    Two[0] := 0;
    Two[1] := 0;
    case ChDamage(ndTx, In_[I], Two) of
      1: begin CH_TxBuf[N] := Two[0]; Inc(N); end;
      2: begin CH_TxBuf[N] := Two[0]; CH_TxBuf[N + 1] := Two[1]; Inc(N, 2); end;
    end;
  end;
  if N > High(Word) then
    N := High(Word);             { the chunk API carries at most 65535 bytes }
  if ChunkFaults then
    ChunkSend(CH_TxBuf, N)
  else if N = 0 then
    CH_SResult := res_Ok          { every byte lost on the way }
  else
    ChLowSend(CH_TxBuf, N);
end;

function tChnNoise.ChReceiveReady: tChState;
begin
  if ChunkFaults then
    ChunkPump;
  if CH_State <> CHS_Connect then
    CH_RCtrl := CHS_RecInactive
  else if CH_StallEnd <> 0 then
    CH_RCtrl := CHS_Receiving     { the line stalls: nothing arrives }
  else if (CH_PendPos < CH_PendLen) or (CH_LowPos < CH_LowLen) or (CH_RxPos < CH_RxLen) then
    CH_RCtrl := CHS_ReceiveReady
  else if CH_Low = nil then
  begin
    if (CH_Limit = 0) or (CH_Inserted < QWord(CH_Limit)) then
      CH_RCtrl := CHS_ReceiveReady
    else
      CH_RCtrl := CHS_Receiving;
  end
  else
  begin
    CH_RCtrl := CH_Low^.ChReceiveReady;
    CH_RResult := CH_Low^.ChReceiveResult;
  end;
  Result := CH_RCtrl;
end;

procedure tChnNoise.ChReceive(var Len: Word);
var
  Out_: PByte;
  B: Byte;
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  Out_ := CH_RBuff;
  Len := 0;
  CH_RResult := res_Ok;
  while Len < CH_RSize do
  begin
    if CH_PendPos < CH_PendLen then
    begin
      Out_[Len] := CH_Pend[CH_PendPos];
      Inc(CH_PendPos);
      Inc(Len);
      Continue;
    end;
    CH_PendPos := 0;
    CH_PendLen := 0;
    if CH_Low = nil then
    begin
      { the babbling line: garbage only }
      if (CH_Limit <> 0) and (CH_Inserted >= QWord(CH_Limit)) then
        Break;
      if CH_Garbage = NoiseRandomByte then
        Out_[Len] := Byte(NoiseHash(CH_Seed, ndRx, CH_Pos[ndRx], 9))
      else
        Out_[Len] := CH_Garbage;
      Inc(CH_Pos[ndRx]);
      Inc(CH_Inserted);
      Inc(Len);
      Continue;
    end;
    { only what the layer below already has: never wait for more }
    if (CH_LowPos >= CH_LowLen) and (CH_RxPos >= CH_RxLen) and (Len > 0) then
      Break;
    if CH_StallEnd <> 0 then
      Break;                     { a stall: nothing arrives }
    if not NextRaw(B) then
      Break;
    if CH_DirRx then
      CH_PendLen := ChDamage(ndRx, B, CH_Pend)
    else
    begin
      CH_Pend[0] := B;
      CH_PendLen := 1;
    end;
  end;
  if (Len = 0) and (CH_RResult = res_Ok) then
    CH_RResult := res_NoMessage;
  CH_RCtrl := CHS_Receiving;
  if ChunkFaults then
    ChunkPump;
end;

procedure tChnNoise.ChReceiveFlush;
begin
  CH_PendLen := 0;
  CH_PendPos := 0;
  CH_RxLen := 0;
  CH_RxPos := 0;
  ChnWaitHeld(CH_RxHeld, False);
  inherited ChReceiveFlush;
end;


function tAddChnNoise.ChInit: pChnVirt;
begin
  Result := New(pChnNoise, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnNoise, Init(cName)));
end.
