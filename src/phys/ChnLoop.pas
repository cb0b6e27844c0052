{ ChnLoop - in-memory null modem (NAM=LOOP), a physical layer.

  Two channel stacks in one process talk to each other with no OS device:
    'NAM=DF1 NOD=1 NAM=LOOP PAIR=A END=1'   and   '... NAM=LOOP PAIR=A END=2'
  Each end is a tChnLoop: a tChnCom whose port is TChnPortLoop, so the
  receive ring, LRB=, IDL=, the transmit buffer and the program-wide wait
  are COM's. The ends of one PAIR share two byte rings in the drivers, one
  per direction, each of the receiving end's LRB bytes. A message larger
  than the free space stays pending at the sender (COM's transmit buffer)
  and moves on as the receiver reads, so the transfer is flow-controlled
  and never loses bytes (ChSendReady reports CHS_Sending meanwhile). Bytes
  sent while the other end is closed are lost, as on a cable with nobody
  listening.

  Parameters: PAIR=name (default A), END=1|2 (default 1; PAIR= and END=
  cannot change while the end is open: res_WrongState), LRB=receive ring
  size (default 4096, taken at the next ChOpen), IDL=ms to wait in
  ChReceiveReady when nothing is waiting (default 0: the peer usually runs
  in the same thread, where waiting only adds latency; give IDL when the
  peer runs in another thread). COM's device and line keys mean nothing
  here. Each open end is a wkSignal source of the program-wide wait (unit
  ChnWait): bytes put into its ring, or room made for its pending send,
  wake the waits of the process. Safe for two threads when the program
  uses cthreads. }
unit ChnLoop;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnRing, ChnWait, ChnPort, ChnCom;

const
  cName = 'LOOP';
  LoopDefaultLRB = 4096;

type
  pLoopPair = ^tLoopPair;

  pChnLoop = ^tChnLoop;
  tChnLoop = object(tChnCom)
    CH_Pair   : string[31];   { PAIR= }
    CH_End    : Byte;         { END=, 1 or 2 }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    { CHS_Sending also while the port still holds part of the message. }
    function  ChSendReady: tChState; virtual;
    { While COM's ring is empty, input is taken straight from the pair's
      ring (one copy instead of two); otherwise as COM. }
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
  protected
    function  ComOpenPort(out Port: TChnPort): tChResult; virtual;
    function  ComDropsWhenFull: Boolean; virtual;
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

  { One end of a pair as a port: Write puts bytes into the other end's
    ring (as many as fit), Read takes them from this end's. }
  TChnPortLoop = class(TChnPort)
  private
    FPair: pLoopPair;
    FEnd: Byte;
    FPendBuf: PByte;            { the rest of the last message, see Write }
    FPendCap: LongInt;
  public
    PairName: ShortString;      { set before Open }
    EndNo: Byte;
    RingSize: LongInt;
    { Path is ignored: the pair is PairName, the end EndNo. res_CannotOpen
      when that end is open in another stack. }
    function Open(const Path: tWordString): tChResult; override;
    function Read(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    { Takes a whole message or nothing: what does not fit into the other
      end's ring stays here (OutQueue) and moves on as that end reads, also
      when this end is not polled; 0 while the last one is still here. }
    function Write(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
    { Bytes of the last message not yet in the other end's ring. }
    function OutQueue(out N: LongInt): tChResult; override;
    { Whether bytes wait; never sleeps (the shared wait does that). }
    function WaitInput(Ms: LongInt): Boolean; override;
    { Whether the other end's ring has room now. }
    function WaitOutput(Ms: LongInt): Boolean; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    procedure WaitJoined(Src: pChnWaitSource); override;
    procedure Close; override;
    destructor Destroy; override;
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
  Lock: TRTLCriticalSection;    { guards Pairs, every ring and Wait[] }

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

{ ---------------------------------------------------------------- port }

function TChnPortLoop.Open(const Path: tWordString): tChResult;
var
  P: pLoopPair;
begin
  if FOpen then
    Exit(res_WrongState);
  FDevice := PairName;
  FVirtual := True;
  EnterCriticalSection(Lock);
  try
    P := Pairs;
    while (P <> nil) and (P^.Name <> PairName) do
      P := P^.Next;
    if P = nil then
    begin
      New(P);
      FillChar(P^, SizeOf(P^), 0);
      P^.Name := PairName;
      P^.Next := Pairs;
      Pairs := P;
    end;
    if P^.Open[EndNo] then
      Exit(res_CannotOpen);         { this end is in use by another stack }
    P^.Open[EndNo] := True;
    RingAlloc(P^.Dir[EndNo].Ring, RingSize, True);   { input held here ends ChnWaitAny }
    FPair := P;
    FEnd := EndNo;
    FOpen := True;
  finally
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

procedure TChnPortLoop.Close;
var
  Link: ^pLoopPair;
begin
  if FPair <> nil then
  begin
    EnterCriticalSection(Lock);
    try
      FPair^.Open[FEnd] := False;
      FPair^.Wait[FEnd] := nil;
      RingFree(FPair^.Dir[FEnd].Ring);
      with FPair^.Dir[OtherEnd(FEnd)] do
      begin
        Pend := nil;                { our buffer may go away now }
        PendLen := 0;
        PendPos := 0;
      end;
      if not FPair^.Open[OtherEnd(FEnd)] then
      begin
        Link := @Pairs;
        while Link^ <> FPair do
          Link := @Link^^.Next;
        Link^ := FPair^.Next;
        Dispose(FPair);
      end;
      FPair := nil;
    finally
      LeaveCriticalSection(Lock);
    end;
  end;
  inherited Close;
end;

destructor TChnPortLoop.Destroy;
begin
  inherited Destroy;            { closes: nothing points into FPendBuf }
  if FPendBuf <> nil then
    FreeMem(FPendBuf);
end;

function TChnPortLoop.Read(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  Before: LongInt;
begin
  EnterCriticalSection(Lock);
  try
    with FPair^.Dir[FEnd] do
    begin
      Pump(FPair^.Dir[FEnd]);
      Got := RingGet(Ring, @Buf, Size);
      Before := PendPos;
      Pump(FPair^.Dir[FEnd]);       { room again for the sender }
      if PendPos > Before then
        ChnWaitSignal(FPair^.Wait[OtherEnd(FEnd)]);   { its send went on }
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

function TChnPortLoop.Write(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  Put: LongInt;
begin
  Done := 0;
  EnterCriticalSection(Lock);
  try
    with FPair^.Dir[OtherEnd(FEnd)] do
    begin
      Pump(FPair^.Dir[OtherEnd(FEnd)]);
      if PendPos < PendLen then
        Exit(res_Ok);               { the last message is still on its way }
      if Ring.Buf = nil then
        Put := Len                  { nobody listening: the bytes are gone }
      else
        Put := RingPut(Ring, @Buf, Len);
      if Put < Len then
      begin
        if Len - Put > FPendCap then
        begin
          ReAllocMem(FPendBuf, Len - Put);
          FPendCap := Len - Put;
        end;
        Move(PByte(@Buf)[Put], FPendBuf^, Len - Put);
        Pend := FPendBuf;
        PendLen := Len - Put;
        PendPos := 0;
      end;
      Done := Len;
      if Put > 0 then
        ChnWaitSignal(FPair^.Wait[OtherEnd(FEnd)]);
    end;
  finally
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

function TChnPortLoop.OutQueue(out N: LongInt): tChResult;
begin
  N := 0;
  Result := res_Ok;
  { no lock for nothing pending: only this end's Write makes a rest }
  with FPair^.Dir[OtherEnd(FEnd)] do
    if PendPos >= PendLen then
      Exit;
  EnterCriticalSection(Lock);
  with FPair^.Dir[OtherEnd(FEnd)] do
  begin
    Pump(FPair^.Dir[OtherEnd(FEnd)]);
    N := PendLen - PendPos;
  end;
  LeaveCriticalSection(Lock);
  Result := res_Ok;
end;

{ No lock: only this end takes bytes out of its ring, so a count above 0
  read at any moment is true (one read a moment too early only says 0). }
function TChnPortLoop.WaitInput(Ms: LongInt): Boolean;
begin
  Result := FPair^.Dir[FEnd].Ring.Count > 0;
end;

function TChnPortLoop.WaitOutput(Ms: LongInt): Boolean;
begin
  EnterCriticalSection(Lock);
  with FPair^.Dir[OtherEnd(FEnd)] do
    Result := (Ring.Buf = nil) or (PendPos >= PendLen);
  LeaveCriticalSection(Lock);
end;

function TChnPortLoop.Flush(Input, Output: Boolean): tChResult;
begin
  if Input then
  begin
    EnterCriticalSection(Lock);
    RingClear(FPair^.Dir[FEnd].Ring);
    LeaveCriticalSection(Lock);
  end;
  Result := res_Ok;
end;

{ wkSignal (TChnPort's answer, but True): the ends signal each other. }
function TChnPortLoop.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  inherited WaitSource(Kind, Os, Rearm, Data);
  Result := True;
end;

procedure TChnPortLoop.WaitJoined(Src: pChnWaitSource);
begin
  EnterCriticalSection(Lock);
  FPair^.Wait[FEnd] := Src;
  LeaveCriticalSection(Lock);
end;

{ --------------------------------------------------------------- layer }

constructor tChnLoop.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Pair := 'A';
  CH_End := 1;
  CH_LRB := LoopDefaultLRB;
  CH_Idle := 0;
end;

constructor tChnLoop.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
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
  else if Key = 'LRB' then         { COM's ranges, without its key chain }
    Result := ParamSetNum(S, 1, 1 shl 24, CmdL, CH_LRB)
  else if Key = 'IDL' then
    Result := ParamSetNum(S, 0, 1000, CmdL, CH_Idle)
  else
    { COM's device and line keys mean nothing on an in-memory line }
    Result := tChnVirt.ChSetOneParam(S, CmdL);
end;

function tChnLoop.ChOwnParams: tParamStr;
begin
  Result := tChnVirt.ChOwnParams + ' PAIR=' + CH_Pair + ParamText('END', CH_End) +
    ParamText('LRB', CH_LRB) + ParamText('IDL', CH_Idle);
end;

function tChnLoop.ComOpenPort(out Port: TChnPort): tChResult;
var
  P: TChnPortLoop;
begin
  P := TChnPortLoop.Create;
  P.PairName := CH_Pair;
  P.EndNo := CH_End;
  P.RingSize := CH_LRB;
  Result := P.Open('');
  if Result <> res_Ok then
  begin
    CH_ParamErr := ChGetParam('END');
    FreeAndNil(P);
  end;
  Port := P;
end;

procedure tChnLoop.ChSend(Buff: Pointer; Len: Word);
begin
  if ChSendReady <> CHS_SendReady then
    CH_SResult := res_Busy
  else
    inherited ChSend(Buff, Len);
end;

function tChnLoop.ChSendReady: tChState;
var
  N: LongInt;
begin
  Result := inherited ChSendReady;
  if (Result = CHS_SendReady) and (CH_Port <> nil) and (ComPortUsable = res_Ok) and
    (CH_Port.OutQueue(N) = res_Ok) and (N > 0) then
    Result := CHS_Sending;
end;

function tChnLoop.ChReceiveReady: tChState;
begin
  if (CH_State = CHS_Connect) and (CH_RCtrl <> CHS_ReceiveReady) and
    (CH_Ring.Count = 0) and (CH_Port <> nil) and CH_Port.WaitInput(0) then
  begin
    ComPumpTx;                    { a long message keeps moving meanwhile }
    CH_RCtrl := CHS_ReceiveReady;
    Exit(CH_RCtrl);
  end;
  Result := inherited ChReceiveReady;
end;

procedure tChnLoop.ChReceive(var Len: Word);
var
  Got: LongInt;
begin
  if (CH_Ring.Count > 0) or (CH_Port = nil) then
  begin
    inherited ChReceive(Len);
    Exit;
  end;
  if not ChReceiveAllowed(Len) then
    Exit;
  CH_Port.Read(PByte(CH_RBuff)^, CH_RSize, Got);
  ChnWaitServed(CH_Wait, True);   { looked: the next input wakes the waits }
  Len := Got;
  if Len = 0 then
    CH_RResult := res_NoMessage
  else
    CH_RResult := res_Ok;
  CH_RCtrl := CHS_Receiving;     { the next ChReceiveReady looks again }
end;

{ The sender waits for room: nothing is ever lost on a loop. }
function tChnLoop.ComDropsWhenFull: Boolean;
begin
  Result := False;
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
