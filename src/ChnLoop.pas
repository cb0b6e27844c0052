{ ChnLoop - in-memory null modem (NAM=LOOP), a physical layer.

  Two channel stacks in one process talk to each other with no OS device:
    'NAM=DF1 NOD=1 NAM=LOOP PAIR=A END=1'   and   '... NAM=LOOP PAIR=A END=2'
  Each end is a tChnLoop; the ends of one PAIR share two byte rings, one per
  direction. A ring holds LRB bytes; a message larger than the free space
  stays pending at the sender and moves on as the receiver reads, so the
  transfer is flow-controlled and never loses bytes (ChSendReady reports
  CHS_Sending meanwhile). Bytes sent while the other end is closed are lost,
  as on a cable with nobody listening.

  Parameters: PAIR=name (default A), END=1|2 (default 1; PAIR= and END=
  cannot change while the end is open: res_WrongState), LRB=receive ring
  size (default 4096, taken at the next ChOpen), IDL=ms to sleep in
  ChReceiveReady when nothing is waiting (default 0: the peer usually runs
  in the same thread, where waiting only adds latency; give IDL when the
  peer runs in another thread). Each open end is a wkSignal source of the
  program-wide wait (unit ChnWait): bytes put into its ring, or room made
  for its pending send, wake the waits of the process.
  Safe for two threads when the program uses cthreads. }
unit ChnLoop;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnRing, ChnWait;

const
  cName = 'LOOP';
  LoopDefaultLRB = 4096;

type
  pLoopPair = ^tLoopPair;

  pChnLoop = ^tChnLoop;
  tChnLoop = object(tChnVirt)
    CH_Pair   : string[31];   { PAIR= }
    CH_End    : Byte;         { END=, 1 or 2 }
    CH_LRB    : LongInt;      { LRB= }
    CH_Idle   : LongInt;      { IDL= in ms }
    CH_PairRef: pLoopPair;    { shared state while open }
    CH_TxBuf  : PByte;        { copy of the message being sent }
    CH_TxCap  : LongInt;
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChHasLow: Boolean; virtual;
    procedure ChOpen; virtual;
    procedure ChClose; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    function  ChSendReady: tChState; virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
    procedure ChReceiveFlush; virtual;
  private
    function LoopAvail: LongInt;
  end;

  tLoopDir = record             { bytes flowing towards one end }
    Ring: tByteRing;            { Buf is nil while that end is closed }
    Pend: PByte;                { sender's message not yet in the ring }
    PendLen, PendPos: LongInt;
  end;

  tLoopPair = record
    Name: string[31];
    Dir : array[1..2] of tLoopDir;   { Dir[E]: data received by end E }
    Open: array[1..2] of Boolean;
    Wait: array[1..2] of pChnWaitSource;   { each open end in the shared wait }
    Next: pLoopPair;
  end;

  pAddChnLoop = ^tAddChnLoop;
  tAddChnLoop = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

uses
  SysUtils, uString;

var
  Pairs: pLoopPair = nil;
  Lock: TRTLCriticalSection;    { guards Pairs and every ring }

function OtherEnd(E: Byte): Byte; inline;
begin
  Result := 3 - E;
end;

{ Move what fits of the pending message into the ring. Caller holds Lock. }
procedure Pump(var D: tLoopDir);
begin
  if D.Ring.Buf = nil then
    D.PendPos := D.PendLen      { nobody listening: the bytes are gone }
  else if D.PendPos < D.PendLen then
    Inc(D.PendPos, RingPut(D.Ring, @D.Pend[D.PendPos], D.PendLen - D.PendPos));
end;

constructor tChnLoop.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Pair := 'A';
  CH_End := 1;
  CH_LRB := LoopDefaultLRB;
  CH_Idle := 0;
  CH_PairRef := nil;
  CH_TxBuf := nil;
  CH_TxCap := 0;
end;

constructor tChnLoop.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnLoop.Done;
begin
  inherited Done;               { closes the end }
  if CH_TxBuf <> nil then
    FreeMem(CH_TxBuf);
  CH_TxBuf := nil;
end;

function tChnLoop.ChHasLow: Boolean;
begin
  Result := False;
end;

function tChnLoop.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key, Value: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  Value := ParamValue(S);
  N := 0;
  if Key = 'PAIR' then
  begin
    Result := res_Ok;
    if Length(Value) > 31 then
      Result := res_BadParam;
    for I := 1 to Length(Value) do
      if not (Value[I] in ['A'..'Z', 'a'..'z', '0'..'9', '_', '-', '.']) then
        Result := res_BadParam;
    { an open end holds the rings of its pair: they cannot change under it }
    if (Result = res_Ok) and (CH_State <> CHS_Close) and (UpStr(Value) <> CH_Pair) then
      Result := res_WrongState;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Pair := UpStr(Value);
  end
  else if Key = 'END' then
  begin
    Result := ParamNum(S, 1, 2, N);
    if (Result = res_Ok) and (CH_State <> CHS_Close) and (N <> CH_End) then
      Result := res_WrongState;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_End := N;
  end
  else if Key = 'LRB' then
    Result := ParamSetNum(S, 1, 1 shl 24, CmdL, CH_LRB)
  else if Key = 'IDL' then
    Result := ParamSetNum(S, 0, 1000, CmdL, CH_Idle)
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnLoop.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + ' PAIR=' + CH_Pair + ParamText('END', CH_End) +
    ParamText('LRB', CH_LRB) + ParamText('IDL', CH_Idle);
end;

procedure tChnLoop.ChOpen;
var
  P: pLoopPair;
begin
  if CH_State <> CHS_Close then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  EnterCriticalSection(Lock);
  try
    P := Pairs;
    while (P <> nil) and (P^.Name <> CH_Pair) do
      P := P^.Next;
    if P = nil then
    begin
      New(P);
      FillChar(P^, SizeOf(P^), 0);
      P^.Name := CH_Pair;
      P^.Next := Pairs;
      Pairs := P;
    end;
    if P^.Open[CH_End] then
    begin
      CH_Result := res_CannotOpen;   { this end is in use by another stack }
      Exit;
    end;
    P^.Open[CH_End] := True;
    RingAlloc(P^.Dir[CH_End].Ring, CH_LRB, True);   { held input ends ChnWaitAny }
    P^.Wait[CH_End] := ChnWaitJoin(wkSignal, -1, nil, nil);
    CH_PairRef := P;
  finally
    LeaveCriticalSection(Lock);
  end;
  ChOpened;
end;

procedure tChnLoop.ChClose;
var
  P: pLoopPair;
  Link: ^pLoopPair;
begin
  if CH_State = CHS_Close then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  EnterCriticalSection(Lock);
  try
    P := CH_PairRef;
    P^.Open[CH_End] := False;
    ChnWaitLeave(P^.Wait[CH_End]);
    RingFree(P^.Dir[CH_End].Ring);
    with P^.Dir[OtherEnd(CH_End)] do
    begin
      Pend := nil;                  { our transmit buffer may go away now }
      PendLen := 0;
      PendPos := 0;
    end;
    if not P^.Open[OtherEnd(CH_End)] then
    begin
      Link := @Pairs;
      while Link^ <> P do
        Link := @Link^^.Next;
      Link^ := P^.Next;
      Dispose(P);
    end;
    CH_PairRef := nil;
  finally
    LeaveCriticalSection(Lock);
  end;
  CH_State := CHS_Close;
  CH_RCtrl := CHS_RecInactive;
  CH_Result := res_Ok;
end;

procedure tChnLoop.ChSend(Buff: Pointer; Len: Word);
begin
  if not ChSendAllowed(Buff, Len, True) then
    Exit;
  if ChSendReady <> CHS_SendReady then
  begin
    CH_SResult := res_Busy;
    Exit;
  end;
  if Len > CH_TxCap then
  begin
    ReAllocMem(CH_TxBuf, Len);
    CH_TxCap := Len;
  end;
  Move(Buff^, CH_TxBuf^, Len);
  EnterCriticalSection(Lock);
  try
    with CH_PairRef^.Dir[OtherEnd(CH_End)] do
    begin
      Pend := CH_TxBuf;
      PendLen := Len;
      PendPos := 0;
    end;
    Pump(CH_PairRef^.Dir[OtherEnd(CH_End)]);
    ChnWaitSignal(CH_PairRef^.Wait[OtherEnd(CH_End)]);
  finally
    LeaveCriticalSection(Lock);
  end;
  CH_SResult := res_Ok;
end;

function tChnLoop.ChSendReady: tChState;
begin
  Result := CHS_SendReady;
  if CH_PairRef = nil then
    Exit;
  EnterCriticalSection(Lock);
  try
    with CH_PairRef^.Dir[OtherEnd(CH_End)] do
    begin
      Pump(CH_PairRef^.Dir[OtherEnd(CH_End)]);
      if PendPos < PendLen then
        Result := CHS_Sending;
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

function tChnLoop.LoopAvail: LongInt;
begin
  EnterCriticalSection(Lock);
  try
    { looking now: the next bytes for this end wake the program's waits }
    ChnWaitServed(CH_PairRef^.Wait[CH_End], True);
    Pump(CH_PairRef^.Dir[CH_End]);
    Result := CH_PairRef^.Dir[CH_End].Ring.Count;
  finally
    LeaveCriticalSection(Lock);
  end;
end;

function tChnLoop.ChReceiveReady: tChState;
var
  Avail: LongInt;
  Deadline, Now: QWord;
begin
  if (CH_State <> CHS_Connect) or (CH_PairRef = nil) then
    Exit(CHS_RecInactive);
  Avail := LoopAvail;
  if (Avail = 0) and (CH_Idle > 0) then
  begin
    { nothing yet: wait up to IDL ms on the program-wide wait, which the
      peer's ChSend ends at once (from any thread) }
    Deadline := ChMsTick + QWord(CH_Idle);
    repeat
      Now := ChMsTick;
      if Now >= Deadline then
        Break;
      if not ChnWaitIdle(CH_PairRef^.Wait[CH_End], Deadline - Now) then
        Break;                    { timed out, or woke for another channel }
      Avail := LoopAvail;
    until Avail > 0;
  end;
  if Avail > 0 then
    CH_RCtrl := CHS_ReceiveReady
  else
    CH_RCtrl := CHS_Receiving;
  Result := CH_RCtrl;
end;

procedure tChnLoop.ChReceive(var Len: Word);
var
  Before: LongInt;
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  EnterCriticalSection(Lock);
  try
    with CH_PairRef^.Dir[CH_End] do
    begin
      Pump(CH_PairRef^.Dir[CH_End]);
      Len := RingGet(Ring, CH_RBuff, CH_RSize);
      Before := PendPos;
      Pump(CH_PairRef^.Dir[CH_End]);   { room again for the sender }
      if PendPos > Before then
        ChnWaitSignal(CH_PairRef^.Wait[OtherEnd(CH_End)]);   { its send went on }
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
  if Len = 0 then
    CH_RResult := res_NoMessage
  else
    CH_RResult := res_Ok;
  CH_RCtrl := CHS_Receiving;
end;

procedure tChnLoop.ChReceiveFlush;
begin
  if CH_PairRef <> nil then
  begin
    EnterCriticalSection(Lock);
    try
      RingClear(CH_PairRef^.Dir[CH_End].Ring);
    finally
      LeaveCriticalSection(Lock);
    end;
  end;
  inherited ChReceiveFlush;
end;

function tAddChnLoop.ChInit: pChnVirt;
begin
  Result := New(pChnLoop, Init);
end;

initialization
  InitCriticalSection(Lock);
  ChnCollection^.Insert(New(pAddChnLoop, Init(cName)));
finalization
  DoneCriticalSection(Lock);
end.
