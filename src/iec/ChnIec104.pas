{ ChnIec104 - NAM=IEC104, the transport of IEC 60870-5-104 over NAM=TCP
  (docs/ChnIec104.md): a message is one ASDU; the layer frames it as I
  APDUs (ChnIec104Codec), keeps the send and receive sequence numbers and
  the k / w windows, acknowledges with S frames, and answers and sends the
  U frames (STARTDT, STOPDT, TESTFR) itself, so the program sees ASDUs
  only.

    'NAM=IEC104 NAM=TCP HOST=10.0.0.5 PORT=2404 RECON=1000'   client
    'NAM=IEC104 NAM=TCP LISTEN=0.0.0.0:2404'                  server

  A client (the controlling station as a rule) sends STARTDT act on each
  new connection; a server starts data transfer on the peer's STARTDT act.
  ASDUs given to ChSend are queued (QUE=, the oldest dropped and counted
  when full) and leave as I frames while data transfer is started and
  fewer than K are unacknowledged; a connection lost drops the ones sent
  and not acknowledged (counted: none is sent twice), the ones not sent
  wait for the next STARTDT.

  The checks of IEC 60870-5-104 close the connection (NAM=TCP's ChHangUp;
  a client reconnects by RECON=): a wrong start or length octet, a control
  field of no format, N(S) other than expected, N(R) acknowledging what
  was never sent, an I frame while data transfer is stopped, t1 run out
  for an I frame or a U act. Each closing is counted with its reason
  (ChClosings, ChCloseReason).

  Timers (seconds, as the standard gives them): T0 the connect (NAM=TCP's
  CTO=), T1 the acknowledgement of a frame sent, T2 the latest S frame
  after an I frame received, T3 TESTFR act after that long without a
  frame. They run in the receive polls: nothing here waits or sleeps. }
unit ChnIec104;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnProto, ChnIec104Codec;

const
  cName = 'IEC104';
  Iec104DefaultQueue = 256;
  Iec104QueueFirst = 8;      {< slots of the send queue's ring at first (it doubles up to QUE=) }

type
  tIec104Slot = record
    Len : Byte;
    Data: array[0..Apci104MaxAsdu - 1] of Byte;
  end;

  { A server's standby connection (CON=): tested with TESTFR, takes over
    with STARTDT act. }
  tIec104Standby = record
    Session : LongWord;
    Feed    : tApci104Feed;
    LastRxAt: QWord;
    TestAt  : QWord;              {< TESTFR act sent then, 0: none pending }
  end;

  pChnIec104 = ^tChnIec104;
  tChnIec104 = object(tChnProto)
    { parameters }
    CH_K, CH_W        : LongInt;
    CH_T0, CH_T1, CH_T2, CH_T3: LongInt;   {< seconds }
    CH_QueLen         : LongInt;
    CH_Con            : LongInt;     {< server: connections at once (CON=), one carries data }
    { the connection (NAM=TCP's session number, 0: none) }
    CH_Session        : LongWord;
    CH_Client         : Boolean;     {< the layer below connects out }
    CH_Started        : Boolean;     {< data transfer started }
    CH_Vs, CH_Vr, CH_Va, CH_AckVr: Word;
    CH_SentAt         : array of QWord;   {< send time of the unacknowledged I frames, K }
    CH_UAct           : Byte;        {< U act waiting for its con (0: none) }
    CH_UActAt         : QWord;
    CH_StopDue        : Boolean;     {< STOPDT con once all is acknowledged }
    CH_FirstRxAt      : QWord;       {< oldest I frame not acknowledged yet (t2) }
    CH_LastRxAt       : QWord;       {< last frame received (t3) }
    { ASDUs not sent yet }
    CH_Queue          : array of tIec104Slot;
    CH_QHead, CH_QCount: LongInt;
    { bytes on their way down (several APDUs per write) }
    CH_Out            : array[0..4095] of Byte;
    CH_OutLen         : Word;
    { the receive automaton and the ASDU of the last I frame }
    CH_Feed           : tApci104Feed;
    CH_RxAsdu         : array[0..Apci104MaxAsdu - 1] of Byte;
    CH_RxLen          : Word;
    { counters }
    CH_Connections, CH_Closings, CH_Dropped, CH_Unconfirmed,
      CH_IRx, CH_ITx, CH_STx, CH_TestFr: LongWord;
    CH_Reason         : ShortString;
    CH_Standby        : array of tIec104Standby;   {< server: the other connections' state }
    CH_TakeOvers      : LongWord;    {< standby connections that took over by STARTDT }

    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    procedure ChOpen; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    procedure ChReceiveTick; virtual;
    { the codec (tChnProto) }
    procedure ChRxReset; virtual;
    function  ChRxByte(B: Byte; var Err: tChResult): Boolean; virtual;
    function  ChRxDeliver(var Len: Word): tChResult; virtual;
    {- --- additions --- }
    { Data transfer is started on the connection in use. }
    function  ChDataStarted: Boolean;
    { ASDUs ChSend would queue now without dropping one. }
    function  ChQueueRoom: LongInt;
    { ASDUs queued and not sent yet. }
    function  ChQueued: LongInt;
    { The next moment a timer of this layer is due (ChMsTick); a wait
      should end then at the latest. }
    function  ChNextDue: QWord;
    { Client: STOPDT act, and STARTDT act again (a new connection sends
      STARTDT act by itself). }
    procedure ChStopDataTransfer;
    procedure ChStartDataTransfer;
    { Connections closed by this layer, and why the last one was. }
    function  ChClosings: LongWord;
    function  ChCloseReason: ShortString;
    { Server: standby connections taken over by STARTDT act. }
    function  ChTakeOvers: LongWord;
  private
    function  LowTcp: pChnVirt;
    procedure SyncSession;
    procedure Emit(const Buf: array of Byte; Len: Word);
    procedure Flush;
    procedure SendU(Func: Byte);
    procedure SendS;
    procedure Pump;
    procedure Timers;
    procedure Broken(R: tChResult; const Why: ShortString);
    function  TakeAck(Nr: Word): Boolean;
    function  TakeApdu: Boolean;
    procedure TakeU(Func: Byte);
    procedure ServeStandby;
    function  StandbyState(Session: LongWord): LongInt;
    procedure TakeOverStandby(I: LongInt);
    procedure ForgetStandby;
  end;

  pAddChnIec104 = ^tAddChnIec104;
  tAddChnIec104 = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

uses
  SysUtils, uString, ChnTcp, ChnTrc;

constructor tChnIec104.Init;
begin
  inherited Init;
  ChProtoSetup(cName, 1, 65500, 512);
  CH_K := 12;
  CH_W := 8;
  CH_T0 := 30;
  CH_T1 := 15;
  CH_T2 := 10;
  CH_T3 := 20;
  CH_QueLen := Iec104DefaultQueue;
  CH_Con := 4;
  CH_TakeOvers := 0;
  CH_Session := 0;
  CH_Started := False;
  CH_QHead := 0;
  CH_QCount := 0;
  CH_OutLen := 0;
  CH_Connections := 0;
  CH_Closings := 0;
  CH_Dropped := 0;
  CH_Unconfirmed := 0;
  CH_IRx := 0;
  CH_ITx := 0;
  CH_STx := 0;
  CH_TestFr := 0;
  CH_Reason := '';
  CH_UAct := 0;
  CH_StopDue := False;
  Apci104FeedReset(CH_Feed);
end;

constructor tChnIec104.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnIec104.Done;
begin
  inherited Done;
  SetLength(CH_Queue, 0);
  SetLength(CH_SentAt, 0);
  SetLength(CH_Standby, 0);
end;

function tChnIec104.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: ShortString;
begin
  Key := ParamKey(S);
  if (Key <> 'LSB') and (Key <> 'NOD') and (Key <> 'DNO') and (CmdL = cmd_Set) and
     (CH_State <> CHS_Close) then
    Exit(res_WrongState);           { windows and queue are sized at ChOpen }
  if Key = 'K' then
    Result := ParamSetNum(S, 1, 32767, CmdL, CH_K)
  else if Key = 'W' then
    Result := ParamSetNum(S, 1, 32767, CmdL, CH_W)
  else if Key = 'T0' then
    Result := ParamSetNum(S, 1, 255, CmdL, CH_T0)
  else if Key = 'T1' then
    Result := ParamSetNum(S, 1, 255, CmdL, CH_T1)
  else if Key = 'T2' then
    Result := ParamSetNum(S, 1, 255, CmdL, CH_T2)
  else if Key = 'T3' then
    Result := ParamSetNum(S, 1, 172800, CmdL, CH_T3)
  else if Key = 'QUE' then
    Result := ParamSetNum(S, 1, 65535, CmdL, CH_QueLen)
  else if Key = 'CON' then
    Result := ParamSetNum(S, 1, 16, CmdL, CH_Con)
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

{ W after K and T2 below T1, whatever their order in the string (clause
  5.5: the receiver acknowledges at the latest after w, and before the
  sender's t1 runs out). }
function tChnIec104.ChCheckParams(const L: tParamList; var Culprit: tWordString): tChResult;

  function Value(const Key: ShortString; Default: LongInt; out Tok: LongInt): LongInt;
  begin
    Tok := ParamFind(L, Key);
    if (Tok < 0) or not StrToNum(Copy(L.Items[Tok].Text, Length(Key) + 2, 255), 0, MaxLongInt, Result) then
      Result := Default;
  end;

var
  K, W, T1, T2, TokW, TokT2, Dummy: LongInt;
begin
  Result := inherited ChCheckParams(L, Culprit);
  if Result <> res_Ok then
    Exit;
  K := Value('K', CH_K, Dummy);
  W := Value('W', CH_W, TokW);
  T1 := Value('T1', CH_T1, Dummy);
  T2 := Value('T2', CH_T2, TokT2);
  if W > K then
  begin
    if TokW >= 0 then
      Culprit := L.Items[TokW].Text
    else
      Culprit := 'W=' + IntToStr(W);
    Exit(res_BadParam);
  end;
  if T2 >= T1 then
  begin
    if TokT2 >= 0 then
      Culprit := L.Items[TokT2].Text
    else
      Culprit := 'T2=' + IntToStr(T2);
    Exit(res_BadParam);
  end;
end;

function tChnIec104.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + ParamText('K', CH_K) + ParamText('W', CH_W) +
    ParamText('T0', CH_T0) + ParamText('T1', CH_T1) + ParamText('T2', CH_T2) +
    ParamText('T3', CH_T3) + ParamText('QUE', CH_QueLen) + ParamText('CON', CH_Con) + ChLsbText;
end;

function tChnIec104.LowTcp: pChnVirt;
begin
  Result := CH_Low;
  while (Result <> nil) and (Result^.CH_Type <> ChnTcp.cName) do
    Result := Result^.CH_Low;
end;

procedure tChnIec104.ChOpen;
var
  T: pChnVirt;
begin
  if CH_State = CHS_Close then
  begin
    T := LowTcp;
    if T = nil then
    begin
      CH_Result := res_WrongLayer;
      CH_ParamErr := 'NAM=IEC104 needs NAM=TCP below it';
      Exit;
    end;
    pChnTcp(T)^.ChSetConnectMs(CH_T0 * 1000);
    CH_Client := not pChnTcp(T)^.ChIsServer;
    if not CH_Client then
      pChnTcp(T)^.ChSetStandby(CH_Con - 1);
    SetLength(CH_Standby, 0);
    { a pcap trace between this layer and TCP is a TCP stream Wireshark
      dissects as IEC 104 }
    T := CH_Low;
    while (T <> nil) and (T^.CH_Type <> ChnTcp.cName) do
    begin
      if T^.CH_Type = ChnTrc.cName then
        pChnTrc(T)^.ChPcapAsTcp(not CH_Client);
      T := T^.CH_Low;
    end;
    SetLength(CH_Queue, 0);          { grows when ASDUs wait (ChSend) }
    SetLength(CH_SentAt, CH_K);
    CH_QHead := 0;
    CH_QCount := 0;
    CH_Session := 0;
    CH_Started := False;
    CH_OutLen := 0;
  end;
  inherited ChOpen;
end;

{- ---------------------------------------------------------------- sending }

procedure tChnIec104.Emit(const Buf: array of Byte; Len: Word);
begin
  if CH_OutLen + Len > SizeOf(CH_Out) then
    Flush;
  if CH_OutLen + Len > SizeOf(CH_Out) then
    Exit;                           { cannot happen: Pump leaves room }
  Move(Buf[0], CH_Out[CH_OutLen], Len);
  Inc(CH_OutLen, Len);
end;

{ Hand what was emitted to the layer below; kept while it is busy. }
procedure tChnIec104.Flush;
var
  R: tChResult;
begin
  if (CH_OutLen = 0) or (CH_Low = nil) then
    Exit;
  R := CH_SResult;
  ChLowSend(@CH_Out, CH_OutLen);
  if CH_SResult <> res_Busy then
    CH_OutLen := 0;                 { sent, or the connection is gone with it }
  CH_SResult := R;
end;

procedure tChnIec104.SendU(Func: Byte);
var
  B: array[0..5] of Byte;
  N: Word;
begin
  Apci104EncodeU(Func, B, N);
  Emit(B, N);
  if Func in [U104StartDtAct, U104StopDtAct, U104TestFrAct] then
  begin
    CH_UAct := Func;
    CH_UActAt := ChMsTick;
  end;
end;

procedure tChnIec104.SendS;
var
  B: array[0..5] of Byte;
  N: Word;
begin
  Apci104EncodeS(CH_Vr, B, N);
  Emit(B, N);
  CH_AckVr := CH_Vr;
  Inc(CH_STx);
end;

function InFlight(const C: tChnIec104): LongInt;
begin
  Result := Seq104Diff(C.CH_Vs, C.CH_Va);
end;

{ Queued ASDUs out as I frames while started and the k window has room. }
procedure tChnIec104.Pump;
var
  B: array[0..Apci104MaxApdu - 1] of Byte;
  N: Word;
begin
  if (CH_Session = 0) or not CH_Started or CH_StopDue then
    Exit;
  while (CH_QCount > 0) and (InFlight(Self) < CH_K) do
  begin
    if CH_OutLen + Apci104MaxApdu > SizeOf(CH_Out) then
    begin
      Flush;
      if CH_OutLen > 0 then
        Exit;                       { the layer below is busy: next poll }
    end;
    with CH_Queue[CH_QHead] do
      Apci104EncodeI(CH_Vs, CH_Vr, Data, Len, B, N);
    Emit(B, N);
    CH_SentAt[CH_Vs mod CH_K] := ChMsTick;
    CH_Vs := (CH_Vs + 1) mod Apci104SeqMod;
    CH_AckVr := CH_Vr;              { the I frame acknowledges too }
    Inc(CH_ITx);
    CH_QHead := (CH_QHead + 1) mod Length(CH_Queue);
    Dec(CH_QCount);
  end;
  if (CH_QCount = 0) and (Length(CH_Queue) > Iec104QueueFirst) then
  begin
    { a burst went out (a start's first values, a reconnect): the ring goes
      back to its first size, and the memory to the program }
    SetLength(CH_Queue, Iec104QueueFirst);
    CH_QHead := 0;
  end;
end;

procedure tChnIec104.ChSend(Buff: Pointer; Len: Word);
var
  Slot, Old, I: LongInt;
begin
  if (CH_State = CHS_Close) or (CH_State = CHS_Opening) then
  begin
    CH_SResult := res_WrongState;
    Exit;
  end;
  if (Buff = nil) or (Len = 0) then
  begin
    CH_SResult := res_BadLen;
    Exit;
  end;
  if Len > Apci104MaxAsdu then
  begin
    CH_SResult := res_TooLong;
    Exit;
  end;
  if CH_QCount = CH_QueLen then
  begin
    { full: the oldest waiting ASDU gives way }
    CH_QHead := (CH_QHead + 1) mod Length(CH_Queue);
    Dec(CH_QCount);
    Inc(CH_Dropped);
  end
  else if CH_QCount = Length(CH_Queue) then
  begin
    { the ring grows as ASDUs wait (doubling, up to QUE=) instead of
      holding QUE= slots of 250 octets from the start; the part that
      wrapped round goes after the rest }
    Old := Length(CH_Queue);
    I := 2 * Old;
    if I < Iec104QueueFirst then
      I := Iec104QueueFirst;
    if I > CH_QueLen then
      I := CH_QueLen;
    SetLength(CH_Queue, I);
    for I := 0 to CH_QHead - 1 do
      CH_Queue[(Old + I) mod Length(CH_Queue)] := CH_Queue[I];
  end;
  Slot := (CH_QHead + CH_QCount) mod Length(CH_Queue);
  CH_Queue[Slot].Len := Len;
  Move(Buff^, CH_Queue[Slot].Data[0], Len);
  Inc(CH_QCount);
  SyncSession;
  Pump;
  Flush;
  CH_SLen := Len;
  CH_SResult := res_Ok;
end;

{- -------------------------------------------------------------- receiving }

{ A new connection starts afresh; one gone stops data transfer. }
procedure tChnIec104.SyncSession;
var
  T: pChnVirt;
  Now_: LongWord;
begin
  T := LowTcp;
  if T = nil then
    Exit;
  Now_ := pChnTcp(T)^.ChSession;
  if Now_ = CH_Session then
    Exit;
  Inc(CH_Unconfirmed, InFlight(Self));   { sent, never acknowledged: not again }
  CH_Session := Now_;
  CH_Vs := 0;
  CH_Vr := 0;
  CH_Va := 0;
  CH_AckVr := 0;
  CH_Started := False;
  CH_StopDue := False;
  CH_UAct := 0;
  CH_OutLen := 0;
  CH_LastRxAt := ChMsTick;
  Apci104FeedReset(CH_Feed);
  if Now_ = 0 then
    Exit;
  Inc(CH_Connections);
  if CH_Client then
    SendU(U104StartDtAct);
end;

{ The peer broke the protocol or a timer ran out: close the connection. }
procedure tChnIec104.Broken(R: tChResult; const Why: ShortString);
var
  T: pChnVirt;
begin
  Inc(CH_Closings);
  CH_Reason := ChResultStr(R) + ': ' + Why;
  Apci104FeedReset(CH_Feed);
  CH_OutLen := 0;
  ChLowDiscard;
  T := LowTcp;
  if T <> nil then
    pChnTcp(T)^.ChHangUp;
  SyncSession;
end;

{ N(R) from the peer: False when it acknowledges what was never sent. }
function tChnIec104.TakeAck(Nr: Word): Boolean;
begin
  Result := Seq104Diff(Nr, CH_Va) <= InFlight(Self);
  if not Result then
  begin
    Broken(res_ApciSeq, 'N(R)=' + IntToStr(Nr) + ' outside ' + IntToStr(CH_Va) + '..' +
      IntToStr(CH_Vs));
    Exit;
  end;
  CH_Va := Nr;
end;

procedure tChnIec104.TakeU(Func: Byte);
begin
  case Func of
    U104StartDtAct:
      begin
        SendU(U104StartDtCon);
        CH_Started := True;
        CH_StopDue := False;
      end;
    U104StopDtAct:
      begin
        if Seq104Diff(CH_Vr, CH_AckVr) > 0 then
          SendS;
        CH_StopDue := True;         { STOPDT con once ours are acknowledged }
      end;
    U104TestFrAct:
      SendU(U104TestFrCon);
  else
    { a con: the act it answers is done }
    if (CH_UAct <> 0) and (Func = Apci104ConOf(CH_UAct)) then
    begin
      if Func = U104StartDtCon then
        CH_Started := True
      else if Func = U104StopDtCon then
        CH_Started := False
      else
        Inc(CH_TestFr);
      CH_UAct := 0;
    end;
  end;
end;

{ A whole APDU in CH_Feed: True for an I frame whose ASDU is to be
  delivered. }
function tChnIec104.TakeApdu: Boolean;
var
  A: tApci104;
  Err: ShortString;
  R: tChResult;
begin
  Result := False;
  R := Apci104Decode(CH_Feed.Buf, CH_Feed.Pos, A, Err);
  if R <> res_Ok then
  begin
    Broken(R, Err);
    Exit;
  end;
  CH_LastRxAt := ChMsTick;
  case A.Format of
    af104I:
      begin
        if not CH_Started then
        begin
          Broken(res_ApciNotStarted, 'I frame N(S)=' + IntToStr(A.Ns) + ' before STARTDT');
          Exit;
        end;
        if A.Ns <> CH_Vr then
        begin
          Broken(res_ApciSeq, 'N(S)=' + IntToStr(A.Ns) + ', expected ' + IntToStr(CH_Vr));
          Exit;
        end;
        if not TakeAck(A.Nr) then
          Exit;
        CH_RxLen := CH_Feed.Pos - 6;
        Move(CH_Feed.Buf[6], CH_RxAsdu[0], CH_RxLen);
        if CH_Vr = CH_AckVr then
          CH_FirstRxAt := ChMsTick;
        CH_Vr := (CH_Vr + 1) mod Apci104SeqMod;
        Inc(CH_IRx);
        if Seq104Diff(CH_Vr, CH_AckVr) >= CH_W then
          SendS;
        Result := True;
      end;
    af104S:
      TakeAck(A.Nr);
  else
    TakeU(A.UFunc);
  end;
end;

procedure tChnIec104.ChRxReset;
begin
  Apci104FeedReset(CH_Feed);
end;

function tChnIec104.ChRxByte(B: Byte; var Err: tChResult): Boolean;
begin
  Result := False;
  if CH_Feed.Pos = 0 then
    SyncSession;                    { the bytes are the connection's now in use }
  case Apci104Feed(CH_Feed, B) of
    fe104Error:
      if CH_Feed.Error = res_ApciStart then
        Broken(res_ApciStart, 'octet ' + IntToHex(B, 2) + ' where an APDU starts')
      else
        Broken(res_ApciLength, 'length octet ' + IntToStr(B) + ' (4..253)');
    fe104Apdu:
      begin
        Result := TakeApdu;
        Apci104FeedReset(CH_Feed);
      end;
  end;
end;

function tChnIec104.ChRxDeliver(var Len: Word): tChResult;
begin
  if CH_RxLen > CH_RSize then
    Exit(res_SmallRecBuff);
  Move(CH_RxAsdu[0], CH_RBuff^, CH_RxLen);
  Len := CH_RxLen;
  Result := res_Ok;
end;

{ t1, t2, t3 (see the unit header). }
procedure tChnIec104.Timers;
var
  Now_: QWord;
begin
  if CH_Session = 0 then
    Exit;
  Now_ := ChMsTick;
  if (CH_UAct <> 0) and (Now_ - CH_UActAt >= QWord(CH_T1) * 1000) then
  begin
    Broken(res_ApciTimeout, 'no ' + Apci104UName(Apci104ConOf(CH_UAct)) +
      ' within t1 (' + IntToStr(CH_T1) + ' s)');
    Exit;
  end;
  if (InFlight(Self) > 0) and (Now_ - CH_SentAt[CH_Va mod CH_K] >= QWord(CH_T1) * 1000) then
  begin
    Broken(res_ApciTimeout, 'I frame N(S)=' + IntToStr(CH_Va) + ' not acknowledged within t1 (' +
      IntToStr(CH_T1) + ' s)');
    Exit;
  end;
  if (CH_Vr <> CH_AckVr) and (Now_ - CH_FirstRxAt >= QWord(CH_T2) * 1000) then
    SendS;
  if (CH_UAct = 0) and (Now_ - CH_LastRxAt >= QWord(CH_T3) * 1000) then
    SendU(U104TestFrAct);
  if CH_StopDue and (InFlight(Self) = 0) then
  begin
    CH_StopDue := False;
    CH_Started := False;
    SendU(U104StopDtCon);
  end;
end;

procedure tChnIec104.ChReceiveTick;
begin
  if CH_State <> CHS_Connect then
    Exit;
  SyncSession;
  inherited ChReceiveTick;          { the bytes: ChRxByte }
  if not CH_Client then
    ServeStandby;
  Timers;
  Pump;
  Flush;
end;

{- ------------------------------------------------------------- additions }

function tChnIec104.ChDataStarted: Boolean;
begin
  Result := (CH_Session <> 0) and CH_Started;
end;

function tChnIec104.ChQueueRoom: LongInt;
begin
  Result := CH_QueLen - CH_QCount;
end;

function tChnIec104.ChQueued: LongInt;
begin
  Result := CH_QCount;
end;

function tChnIec104.ChNextDue: QWord;

  procedure Take(T: QWord);
  begin
    if T < Result then
      Result := T;
  end;

begin
  Result := ChMsTick + QWord(CH_T3) * 1000;
  if CH_Session = 0 then
    Exit(ChMsTick + 100);           { the connection: NAM=TCP's polls }
  if CH_UAct <> 0 then
    Take(CH_UActAt + QWord(CH_T1) * 1000);
  if InFlight(Self) > 0 then
    Take(CH_SentAt[CH_Va mod CH_K] + QWord(CH_T1) * 1000);
  if CH_Vr <> CH_AckVr then
    Take(CH_FirstRxAt + QWord(CH_T2) * 1000);
  Take(CH_LastRxAt + QWord(CH_T3) * 1000);
  if CH_OutLen > 0 then
    Take(ChMsTick + 1);
end;

procedure tChnIec104.ChStopDataTransfer;
begin
  if (CH_Session = 0) or (CH_UAct <> 0) then
    Exit;
  SendU(U104StopDtAct);
  Flush;
end;

procedure tChnIec104.ChStartDataTransfer;
begin
  if (CH_Session = 0) or (CH_UAct <> 0) then
    Exit;
  SendU(U104StartDtAct);
  Flush;
end;

{ ------------------------------------------------------------ redundancy }

function tChnIec104.StandbyState(Session: LongWord): LongInt;
begin
  for Result := 0 to High(CH_Standby) do
    if CH_Standby[Result].Session = Session then
      Exit;
  Result := Length(CH_Standby);
  SetLength(CH_Standby, Result + 1);
  CH_Standby[Result].Session := Session;
  Apci104FeedReset(CH_Standby[Result].Feed);
  CH_Standby[Result].LastRxAt := ChMsTick;
  CH_Standby[Result].TestAt := 0;
end;

{ What standby connection I (its state St) sent: TESTFR act and STOPDT
  act answered, TESTFR con noted, STARTDT act asked for (TakeOver). Got:
  the octets read, < 0 when the connection is gone. '' or why it is to be
  closed (a broken APDU, an I frame). }
function StandbyFrames(T: pChnTcp; I: LongInt; var St: tIec104Standby; out TakeOver: Boolean;
  out Got: LongInt): ShortString;
var
  J: LongInt;
  Buf: array[0..255] of Byte;
  U: array[0..5] of Byte;
  N: Word;
  A: tApci104;
  E: ShortString;
begin
  Result := '';
  TakeOver := False;
  if T^.ChStandbyRead(I, Buf, SizeOf(Buf), Got) <> res_Ok then
    Got := -1;
  for J := 0 to Got - 1 do
  begin
    case Apci104Feed(St.Feed, Buf[J]) of
      fe104Error: Result := 'standby connection: broken APDU';
      fe104Apdu:
        begin
          St.LastRxAt := ChMsTick;
          if Apci104Decode(St.Feed.Buf, St.Feed.Pos, A, E) <> res_Ok then
            Result := 'standby connection: ' + E
          else if A.Format = af104I then
            Result := 'standby connection: I frame before STARTDT'
          else if A.Format = af104U then
            case A.UFunc of
              U104TestFrAct, U104StopDtAct:
                begin
                  Apci104EncodeU(Apci104ConOf(A.UFunc), U, N);
                  T^.ChStandbySend(I, U, N);
                end;
              U104TestFrCon: St.TestAt := 0;
              U104StartDtAct: TakeOver := True;
            end;
          Apci104FeedReset(St.Feed);
        end;
    end;
    if (Result <> '') or TakeOver then
      Break;
  end;
end;

{ The test procedure of standby connection I: TESTFR act after T3 s of
  silence; '' or why it is to be closed (no TESTFR con within T1 s). }
function StandbyTest(T: pChnTcp; I: LongInt; var St: tIec104Standby; T1, T3: LongInt): ShortString;
var
  U: array[0..5] of Byte;
  N: Word;
  Now_: QWord;
begin
  Result := '';
  Now_ := ChMsTick;
  if St.TestAt = 0 then
  begin
    if Now_ - St.LastRxAt >= QWord(T3) * 1000 then
    begin
      Apci104EncodeU(U104TestFrAct, U, N);
      T^.ChStandbySend(I, U, N);
      St.TestAt := Now_;
    end;
  end
  else if Now_ - St.TestAt >= QWord(T1) * 1000 then
    Result := 'standby connection: no TESTFR con within t1';
end;

{ Standby connection I asked for STARTDT: it carries the data from now.
  The connection served so far is stopped (what it sent and was not read
  is dropped with it) and becomes a standby one. }
procedure tChnIec104.TakeOverStandby(I: LongInt);
begin
  ChLowDiscard;
  Apci104FeedReset(CH_Feed);
  pChnTcp(LowTcp)^.ChPromote(I);
  Inc(CH_TakeOvers);
  SyncSession;
  SendU(U104StartDtCon);
  CH_Started := True;
  Flush;
end;

{ Forget the state of standby connections that are gone. }
procedure tChnIec104.ForgetStandby;
var
  T: pChnTcp;
  I, J: LongInt;
  Live: Boolean;
begin
  T := pChnTcp(LowTcp);
  I := 0;
  while I < Length(CH_Standby) do
  begin
    Live := False;
    for J := 0 to T^.ChStandbyCount - 1 do
      if T^.ChStandbySession(J) = CH_Standby[I].Session then
        Live := True;
    if Live then
      Inc(I)
    else
    begin
      CH_Standby[I] := CH_Standby[High(CH_Standby)];
      SetLength(CH_Standby, Length(CH_Standby) - 1);
    end;
  end;
end;

{ The server's other connections: U frames only. TESTFR is answered and,
  after t3 of silence, sent (no con within t1: closed); STARTDT act makes
  the connection the one that carries data (the one before is stopped
  and becomes a standby connection); an I frame or a broken APDU closes
  it. }
procedure tChnIec104.ServeStandby;
var
  T: pChnTcp;
  I, K, Got: LongInt;
  Why: ShortString;
  TakeOver: Boolean;
begin
  T := pChnTcp(LowTcp);
  if T = nil then
    Exit;
  I := 0;
  while I < T^.ChStandbyCount do
  begin
    K := StandbyState(T^.ChStandbySession(I));
    Why := StandbyFrames(T, I, CH_Standby[K], TakeOver, Got);
    if (Why = '') and not TakeOver then
      Why := StandbyTest(T, I, CH_Standby[K], CH_T1, CH_T3);
    if Got < 0 then
      T^.ChStandbyHangUp(I)         { it left }
    else if Why <> '' then
    begin
      Inc(CH_Closings);
      CH_Reason := Why;
      T^.ChStandbyHangUp(I);
    end
    else
    begin
      if TakeOver then
        TakeOverStandby(I);
      Inc(I);
    end;
  end;
  ForgetStandby;
end;

function tChnIec104.ChTakeOvers: LongWord;
begin
  Result := CH_TakeOvers;
end;

function tChnIec104.ChClosings: LongWord;
begin
  Result := CH_Closings;
end;

function tChnIec104.ChCloseReason: ShortString;
begin
  Result := CH_Reason;
end;

const
  Iec104Texts: array[0..5] of tProtoText = (
    (Code: res_ApciStart;   Text: 'APDU without its start octet 68h'),
    (Code: res_ApciLength;  Text: 'APDU length outside 4..253 or wrong for its format'),
    (Code: res_ApciControl; Text: 'APDU control field of no format'),
    (Code: res_ApciSeq;     Text: 'sequence number out of order or window'),
    (Code: res_ApciNotStarted; Text: 'I frame while data transfer is stopped'),
    (Code: res_ApciTimeout; Text: 'no acknowledgement within t1'));

function tAddChnIec104.ChInit: pChnVirt;
begin
  Result := New(pChnIec104, Init);
end;

initialization
  ProtoRegister(New(pAddChnIec104, Init(cName)), Iec104Texts);
end.
