{ ChnPhys - the physical base every physical layer stands on (NAM=COM,
  NAM=TCP, NAM=LOOP), docs/PROTOCOLS.md section 3.

  tChnPhys is the bottom of a channel stack: its "message" is a chunk of
  raw bytes, moved by a TChnPort (unit ChnPort) the descendant opens
  (ComOpenPort). What every physical layer shares lives here:

    the receive ring   every poll moves what the port holds into a ring of
                       LRB= bytes (at most MaxPullPerPoll a poll, in reads
                       of at most that, so a sender that never pauses cannot
                       fill the ring in one poll). When it is full and the
                       line cannot hold the sender back (ComDropsWhenFull:
                       FLW=NONE on a serial line) further bytes are lost as
                       on the original interrupt-driven UART, counted, and
                       the next ChReceive answers res_Overrun (the kept
                       bytes are delivered); else reading pauses and nothing
                       is lost. Bytes the OS itself lost are counted too.
    the transmit pump  what the port does not take at once is kept and moved
                       on by the polls; LSB= bounds a message (res_TooLong);
                       a direction line raised for the message (RS-485 by
                       RTS, CH_RtsToggle) drops once the last bit has left.
    the drain          ChClose (and Done) first let what was sent leave the
                       driver, bounded by the line time of the pending bytes
                       (ComDrainTx).
    the reconnect      RECON=ms: a port lost while open is reopened by the
                       polls (ComReopen); results say res_Reconnecting
                       meanwhile. A descendant supplies only how a new port
                       is started and completed (ComReopenBegins,
                       ComReopenStart, ComReopenPoll).
    the wait           the open port joins the program-wide wait (ChnWait);
                       IDL=ms bounds how long a poll that finds nothing
                       waits for input (0 never waits).

  Parameters of the base: LRB= LSB= IDL= RECON= (a descendant names those
  it offers with PhysKeys); the line settings BD= BIT= STOP= PAR= FLW=
  (CH_Set) are parsed by PhysLineParam for the kinds that have a line.

  Faults: a port that cannot be opened leaves the layer in CHS_Close with
  the reason in ChResult and the token named by ChParamError; a port lost
  while open makes ChResult, ChReceiveResult and ChSendResult answer
  res_DeviceLost (or res_IOError) from the next poll on, bytes already
  received can still be taken, and ChClose + ChOpen starts again - or
  RECON= reopens it. docs/ChnCom.md tells the whole story. }
unit ChnPhys;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnRing, ChnWait, ChnPort;

const
  PhysDefaultLRB = 4096;
  PhysDefaultLSB = 65535;
  PhysDefaultIdle = 1;

type
  pChnPhys = ^tChnPhys;
  tChnPhys = object(tChnVirt)
    CH_Set     : tPortSettings;    {< BD BIT STOP PAR FLW, where the kind has a line }
    CH_LRB     : LongInt;          {< LRB= }
    CH_LSB     : LongInt;          {< LSB= }
    CH_Idle    : LongInt;          {< IDL= }
    CH_Port    : TChnPort;         {< the open port, nil when closed }
    CH_RtsToggle: Boolean;         {< this layer switches RTS (COM's RS485=RTS/AUTO) }
    CH_RtsUp   : Boolean;          {< RTS raised for the message being sent }
    CH_Fault   : tChResult;        {< device lost / I/O error while open }
    CH_Ring    : tByteRing;        {< receive ring of CH_LRB bytes }
    CH_Lost    : LongWord;         {< bytes lost since open (ring or OS) }
    CH_LostShown: LongWord;        {< part of CH_Lost already reported }
    CH_OsLost  : LongWord;         {< OS overrun count last seen }
    CH_TxBuf   : PByte;            {< copy of the message being sent }
    CH_TxCap, CH_TxLen, CH_TxPos: LongInt;
    CH_Wait    : pChnWaitSource;   {< this port in the program-wide wait; nil: none }
    CH_Reopen  : LongInt;          {< RECON= ms between reopen attempts, 0 = off }
    CH_ReopenAt: QWord;            {< next reopen attempt (GetTickCount64) }
    CH_ReopenPort: TChnPort;       {< a reopen in progress (ComReopenStart said res_Busy) }
    {- line timing (COM's RTSB= RTSA= TURN= IFG=; 0 elsewhere) }
    CH_RtsBefore: LongInt;         {< RTSB= ms from raising RTS to the first bit }
    CH_RtsAfter: LongInt;          {< RTSA= ms from the last bit to dropping RTS }
    CH_Turn    : LongInt;          {< TURN= ms at least from the last byte received to a send }
    CH_Ifg     : LongInt;          {< IFG= bit times at least of idle line before a send }
    CH_TxAt    : QWord;            {< ChnClockUs before which the held message must not start; 0: now }
    CH_RtsDropAt: QWord;           {< ChnClockUs at which RTS drops (RTSA=); 0: none due }
    CH_LastRxUs: QWord;            {< ChnClockUs of the last byte received }
    CH_LastTxEndUs: QWord;         {< ChnClockUs when the last message sent ends on the line }
    constructor Init;
    destructor  Done; virtual;
    { LRB= LSB= IDL= RECON=, those of PhysKeys }
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChHasLow: Boolean; virtual;
    procedure ChOpen; virtual;
    procedure ChClose; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    function  ChSendReady: tChState; virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
    procedure ChReceiveFlush; virtual;
    { --- additions of the port --- }
    { Bytes lost on receive since ChOpen (ring full or OS overrun). }
    function  ChLostBytes: LongWord;
    { Modem lines, for applications that drive them by hand (where the
      port has them: a serial port, RFC 2217). }
    function  ChSetRts(On: Boolean): tChResult;
    function  ChSetDtr(On: Boolean): tChResult;
    function  ChModemLines(var Lines: tPortLines): tChResult;
  protected
    { The keys of the base this kind takes, separated by spaces (default
      'LRB LSB IDL RECON'); the others are unknown to it. }
    function  PhysKeys: ShortString; virtual;
    { BD= BIT= STOP= PAR= FLW= into CH_Set; res_UnknownParam for any other
      key. For the kinds that have a serial line (COM, TCP with RFC 2217). }
    function  PhysLineParam(const S: tWordString; var CmdL: tCmd): tChResult;
    { Create, open and configure the port this layer drives. On failure
      Port is nil and CH_ParamErr names the token. The base has none. }
    function  ComOpenPort(out Port: TChnPort): tChResult; virtual;
    { The device failed while open: latch R (once: a later fault does not
      replace the first), drop the message being sent, stop waiting on it. }
    procedure ComFault(R: tChResult);
    { Put R into CH_Fault and the three results the application polls
      (ChResult, ChReceiveResult, ChSendResult): the one place a fault, a
      reconnect in progress (res_Reconnecting) or its end (res_Ok) is
      reported; CH_Fault itself belongs to this layer. }
    procedure ComLatch(R: tChResult);
    { Open again: Port (open, configured) replaces the one in use - the
      wait follows it, a pending send is dropped, faults are cleared. }
    procedure ComReplacePort(Port: TChnPort);
    { res_Ok when the port can be used now: res_WrongState while closed,
      the fault once the device failed }
    function  ComPortUsable: tChResult;
    procedure ComJoinWait;
    procedure ComLeaveWait;
    { A full ring drops further input (FLW=NONE on a serial line); False
      where the line itself holds the sender back (flow control, TCP). }
    function  ComDropsWhenFull: Boolean; virtual;
    procedure ComPull;
    { up to IDL= ms for input: True when this port's came }
    function  ComIdleWait: Boolean;
    { RECON=: after a device loss, reopen the device in the polls }
    procedure ComReopen;
    { RECON=: CH_Fault (a fault, or res_Reconnecting) becomes res_Reconnecting
      where this port kind mends it; True while reconnecting }
    function  ComReconnecting: Boolean;
    { RECON=, the parts a port kind supplies. ComReopenBegins: CH_Fault has
      just been latched; True when a reconnect mends it - then let go of the
      lost port as this kind must and set CH_ReopenAt to the first attempt
      (the base: device lost or I/O error; the device is closed at once, so
      the kernel can give its name again, first attempt after RECON ms). }
    function  ComReopenBegins: Boolean; virtual;
    { Start a new port: res_Ok (Port open and configured), res_Busy (Port
      on its way, ComReopenPoll completes it), else failed (Port nil, the
      token named; res_BadSetting ends the retries). The base: ComOpenPort. }
    function  ComReopenStart(out Port: TChnPort): tChResult; virtual;
    { A port ComReopenStart left res_Busy: res_Busy still, res_Ok ready,
      else failed (the caller frees it). The base never gets here. }
    function  ComReopenPoll(Port: TChnPort): tChResult; virtual;
    procedure ComPumpTx;
    { Before a close: what ChSend was given leaves the driver, bounded }
    procedure ComDrainTx;
    { Milliseconds N bytes take on the line at the BD BIT PAR STOP in force }
    function  ComLineMs(N: LongInt): LongInt;
    { Microseconds N bytes take on the line (0 without BD). }
    function  ComLineUs(N: LongInt): LongInt;
    { The earliest a message handed over at Now may start, ChnClockUs. }
    function  ComTxStart(Now: QWord): QWord;
    procedure ComFreeBuffers;
    { ' LRB=.. LSB=.. IDL=..' for ChOwnParams }
    function  ComBufferText: ShortString;
  end;

{ ' BD=.. BIT=.. STOP=.. PAR=.. FLW=..' as ChGetParam reports them. }
function ComLineText(const S: tPortSettings): ShortString;
{ ' BIT=.. STOP=.. PAR=..', the character alone. }
function ComCharText(const S: tPortSettings): ShortString;

{ The time N characters take on a line of settings S (start, data, parity
  and stop bits at S.Baud), in units of 1/PerSecond s, rounded up; 0 when
  no speed is set. }
function LineTime(const S: tPortSettings; N, PerSecond: LongInt): LongInt;

implementation

uses
  SysUtils, uString, ChnParam;

const
  ParityLetters: array[tPortParity] of Char = ('N', 'E', 'O', 'M', 'S');
  FlowNames: array[tPortFlow] of string[7] = ('NONE', 'RTSCTS', 'XONXOFF');
  MaxDrainPerPoll = 65536;   { bytes discarded per poll when the ring is full }
  MaxPullPerPoll  = 65536;   { bytes one poll moves into the ring, see ComPull }
  SmallChunk = 1024;         { a message rather than bulk input, see ComPull }

constructor tChnPhys.Init;
begin
  inherited Init;
  CH_Set := DefaultPortSettings;
  CH_LRB := PhysDefaultLRB;
  CH_LSB := PhysDefaultLSB;
  CH_Idle := PhysDefaultIdle;
  CH_Port := nil;
  CH_RtsToggle := False;
  CH_RtsUp := False;
  CH_Fault := res_Ok;
  FillChar(CH_Ring, SizeOf(CH_Ring), 0);
  CH_Lost := 0;
  CH_LostShown := 0;
  CH_OsLost := 0;
  CH_TxBuf := nil;
  CH_TxCap := 0;
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_Wait := nil;
  CH_Reopen := 0;
  CH_ReopenAt := 0;
  CH_ReopenPort := nil;
  CH_RtsBefore := 0;
  CH_RtsAfter := 0;
  CH_Turn := 0;
  CH_Ifg := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
  CH_LastRxUs := 0;
  CH_LastTxEndUs := 0;
end;

destructor tChnPhys.Done;
begin
  inherited Done;               { closes the port }
  ComFreeBuffers;
end;

function tChnPhys.ChHasLow: Boolean;
begin
  Result := False;
end;

procedure tChnPhys.ComFreeBuffers;
begin
  RingFree(CH_Ring);
  if CH_TxBuf <> nil then
    FreeMem(CH_TxBuf);
  CH_TxBuf := nil;
  CH_TxCap := 0;
end;

function tChnPhys.PhysKeys: ShortString;
begin
  Result := 'LRB LSB IDL RECON';
end;

function tChnPhys.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
begin
  Key := ParamKey(S);
  if not ParamKeyIn(Key, PhysKeys) then
    Result := inherited ChSetOneParam(S, CmdL)
  else if Key = 'LRB' then
    Result := ParamSetNum(S, 1, 1 shl 24, CmdL, CH_LRB)
  else if Key = 'LSB' then
    Result := ParamSetNum(S, 1, 65535, CmdL, CH_LSB)
  else if Key = 'IDL' then
    Result := ParamSetNum(S, 0, 1000, CmdL, CH_Idle)
  else if Key = 'RECON' then
    Result := ParamSetNum(S, 0, 3600000, CmdL, CH_Reopen)
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnPhys.PhysLineParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  N := 0;
  I := 0;
  if Key = 'BD' then
    Result := ParamSetNum(S, 50, 4000000, CmdL, CH_Set.Baud)
  else if Key = 'IFG' then
    Result := ParamSetNum(S, 0, 10000, CmdL, CH_Ifg)
  else if Key = 'BIT' then
  begin
    Result := ParamNum(S, 5, 8, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Set.DataBits := N;
  end
  else if Key = 'STOP' then
  begin
    Result := ParamNum(S, 1, 2, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Set.StopBits := N;
  end
  else if Key = 'PAR' then
  begin
    Result := ParamChoice(S, 'N|E|O|M|S', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Set.Parity := tPortParity(I);
  end
  else if Key = 'FLW' then
  begin
    Result := ParamChoice(S, 'NONE|RTSCTS|XONXOFF', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Set.Flow := tPortFlow(I);
  end
  else
    Result := res_UnknownParam;
end;

function ComLineText(const S: tPortSettings): ShortString;
begin
  Result := ParamText('BD', S.Baud) + ComCharText(S) + ' FLW=' + FlowNames[S.Flow];
end;

function ComCharText(const S: tPortSettings): ShortString;
begin
  Result := ParamText('BIT', S.DataBits) + ParamText('STOP', S.StopBits) +
    ' PAR=' + ParityLetters[S.Parity];
end;

function tChnPhys.ComBufferText: ShortString;
begin
  Result := ParamText('LRB', CH_LRB) + ParamText('LSB', CH_LSB) + ParamText('IDL', CH_Idle);
end;

function tChnPhys.ComOpenPort(out Port: TChnPort): tChResult;
begin
  Port := nil;                      { a descendant opens its kind of port }
  Result := res_CannotOpen;
end;

function tChnPhys.ComDropsWhenFull: Boolean;
begin
  Result := CH_Set.Flow = flowNone;
end;

{ Put CH_Port into the program-wide wait, where the port offers a source. }
procedure tChnPhys.ComJoinWait;
var
  WaitKind: tChnWaitKind;
  WaitOs: PtrInt;
  WaitRearm: tChnWaitRearm;
  WaitData: Pointer;
begin
  CH_Wait := nil;
  if ChnWaitShared and CH_Port.WaitSource(WaitKind, WaitOs, WaitRearm, WaitData) then
  begin
    CH_Wait := ChnWaitJoin(WaitKind, WaitOs, WaitRearm, WaitData);
    CH_Port.WaitJoined(CH_Wait);
  end;
end;

{ Out of the program-wide wait, before the port's descriptor goes. }
procedure tChnPhys.ComLeaveWait;
begin
  if (CH_Wait <> nil) and (CH_Port <> nil) then
    CH_Port.WaitJoined(nil);
  ChnWaitLeave(CH_Wait);
end;

procedure tChnPhys.ComReplacePort(Port: TChnPort);
begin
  ComLeaveWait;
  CH_Port.Free;
  CH_Port := Port;
  ComJoinWait;
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
  CH_RtsUp := False;
  ComLatch(res_Ok);
end;

procedure tChnPhys.ChOpen;
var
  Port: TChnPort;
  R: tChResult;
begin
  if not ChOpenAllowed then
    Exit;
  CH_Set.InQueue := CH_LRB;
  CH_RtsToggle := False;
  CH_ParamErr := '';
  CH_ErrWhy := '';
  R := ComOpenPort(Port);
  if R <> res_Ok then
  begin
    CH_Result := R;
    Exit;
  end;
  CH_Port := Port;
  ComJoinWait;
  RingAlloc(CH_Ring, CH_LRB, True);   { input held here ends ChnWaitAny at once }
  CH_Lost := 0;
  CH_LostShown := 0;
  CH_OsLost := 0;
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
  CH_RtsUp := False;
  CH_Fault := res_Ok;
  ChOpened;
end;

procedure tChnPhys.ChClose;
begin
  if CH_State = CHS_Close then
  begin
    CH_Result := res_WrongState;
    Exit;
  end;
  ComLeaveWait;
  if CH_Port <> nil then
  begin
    if CH_Fault = res_Ok then
    begin
      ComDrainTx;                   { nothing sent is lost at a close }
      if CH_RtsUp and (CH_Fault = res_Ok) then
        CH_Port.SetRts(False);
    end;
    CH_Port.Free;
    CH_Port := nil;
  end;
  FreeAndNil(CH_ReopenPort);
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
  CH_RtsUp := False;
  RingClear(CH_Ring);
  CH_Fault := res_Ok;
  CH_State := CHS_Close;
  CH_RCtrl := CHS_RecInactive;
  CH_Result := res_Ok;
end;

{ The device failed: remember why, report it everywhere, stop using it. }
procedure tChnPhys.ComFault(R: tChResult);
begin
  if CH_Fault <> res_Ok then
    Exit;
  ComLatch(R);
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
  CH_RtsUp := False;
  ChnWaitServed(CH_Wait, False);  { nothing more to wait for on it }
  ComReconnecting;                { RECON=: res_Reconnecting from this poll on }
end;

procedure tChnPhys.ComLatch(R: tChResult);
begin
  CH_Fault := R;
  CH_Result := R;
  CH_RResult := R;
  CH_SResult := R;
end;

{ Move what the OS holds into the ring; see the unit header for a full ring. }
procedure tChnPhys.ComPull;
var
  ShortDrains: Boolean;
  Room, Got, Dropped, Pulled: LongInt;
  Tail: PByte;
  Scratch: array[0..1023] of Byte;
  R: tChResult;
  Os: LongWord;
begin
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Exit;
  Got := 0;
  ShortDrains := CH_Port.ShortReadDrains and ChnWaitArmed(CH_Wait);
  Pulled := 0;
  { until the driver is empty, but at most MaxPullPerPoll bytes: input that
    never pauses (a fast sender, a tap forwarding a stream) would keep one
    poll reading until the ring is full and the next bytes were lost before
    the caller could take any; the rest waits in the driver for the next
    poll }
  while (RingRoom(CH_Ring) > 0) and (Pulled < MaxPullPerPoll) do
  begin
    Room := RingTailSpan(CH_Ring, Tail);
    { the bound holds for one read too: a socket with megabytes queued, or
      a pty fed from the other CPU, fills all the room a read is given }
    if Room > MaxPullPerPoll - Pulled then
      Room := MaxPullPerPoll - Pulled;
    R := CH_Port.Read(Tail^, Room, Got);
    if R <> res_Ok then
    begin
      ComFault(R);
      Exit;
    end;
    if Got = 0 then
      Break;
    RingCommit(CH_Ring, Got);
    if (CH_Turn > 0) or (CH_Ifg > 0) then
      CH_LastRxUs := ChnClockUs;      { TURN=, IFG= count from here }
    Inc(Pulled, Got);
    { Read again until the driver says empty - except after a small chunk
      (a request, a reply) from a port whose short read proves it empty,
      while the shared wait watches it: anything that came meanwhile ends
      the next wait at once, so the read that would find nothing (one per
      message) is saved. Bulk input keeps being read at once: left behind,
      it would pile up in the OS and, without flow control, overrun the
      ring under a burst. }
    if (Got < Room) and (Got < SmallChunk) and ShortDrains then
      Break;
  end;
  if (RingRoom(CH_Ring) = 0) and ComDropsWhenFull then
  begin
    { no flow control can stop the sender: bytes beyond LRB are lost, and
      said so, as with the interrupt-driven ring of the original }
    Dropped := 0;
    repeat
      R := CH_Port.Read(Scratch, SizeOf(Scratch), Got);
      if R <> res_Ok then
      begin
        ComFault(R);
        Exit;
      end;
      Inc(Dropped, Got);
    until (Got = 0) or (Dropped >= MaxDrainPerPoll);
    Inc(CH_Lost, Dropped);
  end;
  if CH_Port.OsOverruns(Os) = res_Ok then
    if Os > CH_OsLost then
    begin
      Inc(CH_Lost, Os - CH_OsLost);
      CH_OsLost := Os;
    end;
  { looked at the device: wake the program's waits for its next input,
    unless the ring cannot take any (flow control holds the sender) }
  ChnWaitServed(CH_Wait, ((RingRoom(CH_Ring) > 0) or ComDropsWhenFull) and
    CH_Port.WaitUseful);
end;

{ RECON=: a lost device (USB adapter pulled) is closed at once - so the
  kernel can give the adapter its name again when it comes back - and
  reopened every RECON ms from the polls with every setting (ComOpenPort,
  as ChOpen); results say res_Reconnecting until that works. An open of a
  tty does not block (O_NONBLOCK), so a poll never hangs on it, and one
  attempt per RECON ms never spins. A device that comes back but refuses
  a setting ends it: res_BadSetting, the token named. Bytes received
  before the loss can still be taken. A descendant changes only what
  ComReopenBegins, ComReopenStart and ComReopenPoll do (NAM=TCP: a
  non-blocking connect bounded by CTO=, at once after the loss). }
procedure tChnPhys.ComReopen;
var
  R: tChResult;
  Now: QWord;
begin
  if not ComReconnecting then
    Exit;
  Now := GetTickCount64;
  R := res_Busy;                    { not due yet, or on its way }
  if (CH_ReopenPort = nil) and (Now >= CH_ReopenAt) then
    R := ComReopenStart(CH_ReopenPort);
  if (R = res_Busy) and (CH_ReopenPort <> nil) then
    R := ComReopenPoll(CH_ReopenPort);
  if R = res_Busy then
    Exit;
  if R = res_Ok then
  begin
    ComReplacePort(CH_ReopenPort);  { the shared wait follows the new port }
    CH_ReopenPort := nil;
    CH_OsLost := 0;                 { the new port counts from 0 }
    CH_ParamErr := '';
    Exit;
  end;
  FreeAndNil(CH_ReopenPort);
  if R = res_BadSetting then
    ComLatch(R)                     { back, but not as configured: no retry }
  else
    CH_ReopenAt := Now + QWord(CH_Reopen);
end;

function tChnPhys.ComReconnecting: Boolean;
begin
  if (CH_Reopen <> 0) and (CH_Port <> nil) and (CH_Fault <> res_Ok) and
    (CH_Fault <> res_Reconnecting) and ComReopenBegins then
    ComLatch(res_Reconnecting);
  Result := CH_Fault = res_Reconnecting;
end;

function tChnPhys.ComReopenBegins: Boolean;
begin
  Result := (CH_Fault = res_DeviceLost) or (CH_Fault = res_IOError);
  if not Result then
    Exit;
  ComLeaveWait;
  CH_Port.Close;                    { the object stays until a new port works }
  CH_ReopenAt := GetTickCount64 + QWord(CH_Reopen);
end;

function tChnPhys.ComReopenStart(out Port: TChnPort): tChResult;
begin
  CH_RtsToggle := False;
  Result := ComOpenPort(Port);      { names the token when it fails }
end;

function tChnPhys.ComReopenPoll(Port: TChnPort): tChResult;
begin
  Result := res_Ok;                 { ComReopenStart never leaves one on its way }
end;

{ Hand as much of the pending message to the OS as it takes now; drop RTS
  once an RS-485 transmission has completely left the line. }
procedure tChnPhys.ComPumpTx;
var
  Written, Queued: LongInt;
  R: tChResult;
begin
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Exit;
  if CH_TxAt <> 0 then
  begin
    if ChnClockUs < CH_TxAt then
    begin
      ChnWaitDue(CH_Wait, CH_TxAt);  { RTSB=, TURN=, IFG=: not yet }
      Exit;
    end;
    CH_TxAt := 0;
    CH_LastTxEndUs := ChnClockUs + QWord(ComLineUs(CH_TxLen - CH_TxPos));
  end;
  while CH_TxPos < CH_TxLen do
  begin
    R := CH_Port.Write(CH_TxBuf[CH_TxPos], CH_TxLen - CH_TxPos, Written);
    if R <> res_Ok then
    begin
      ComFault(R);
      Exit;
    end;
    if Written = 0 then
    begin
      ChnWaitOutput(CH_Wait, True);  { ChnWaitAny wakes when it can go on }
      Exit;
    end;
    Inc(CH_TxPos, Written);
  end;
  ChnWaitOutput(CH_Wait, False);
  if CH_RtsUp then
  begin
    R := CH_Port.OutQueue(Queued);
    if R <> res_Ok then
    begin
      ComFault(R);
      Exit;
    end;
    if Queued > 0 then
      Exit;
    { only the UART FIFO and shift register are left: a short wait }
    if CH_RtsDropAt = 0 then
    begin
      R := CH_Port.Drain;
      if R <> res_Ok then
      begin
        ComFault(R);
        Exit;
      end;
      CH_RtsDropAt := ChnClockUs + QWord(CH_RtsAfter) * 1000;
    end;
    if ChnClockUs < CH_RtsDropAt then
    begin
      ChnWaitDue(CH_Wait, CH_RtsDropAt);   { RTSA=: RTS stays up a while }
      Exit;
    end;
    CH_RtsDropAt := 0;
    R := CH_Port.SetRts(False);
    if R <> res_Ok then
    begin
      ComFault(R);
      Exit;
    end;
    CH_RtsUp := False;
  end;
end;

function LineTime(const S: tPortSettings; N, PerSecond: LongInt): LongInt;
var
  Bits: LongInt;
begin
  if S.Baud <= 0 then
    Exit(0);
  Bits := 1 + S.DataBits + S.StopBits;    { start, data, stop }
  if S.Parity <> ppNone then
    Inc(Bits);
  Result := (Int64(N) * Bits * PerSecond + S.Baud - 1) div S.Baud;
end;

function tChnPhys.ComLineUs(N: LongInt): LongInt;
begin
  Result := LineTime(CH_Set, N, 1000000);
end;

{ The earliest a message handed over now may start (ChnClockUs): RTSB=
  after RTS is raised, TURN= after the last byte received, IFG= bit
  times of idle line after whatever was on it last. }
function tChnPhys.ComTxStart(Now: QWord): QWord;
var
  T: QWord;
begin
  Result := Now;
  if CH_RtsToggle and (CH_RtsBefore > 0) then
    Result := Now + QWord(CH_RtsBefore) * 1000;
  if (CH_Turn > 0) and (CH_LastRxUs > 0) then
  begin
    T := CH_LastRxUs + QWord(CH_Turn) * 1000;
    if T > Result then
      Result := T;
  end;
  if (CH_Ifg > 0) and (CH_Set.Baud > 0) then
  begin
    T := CH_LastRxUs;
    if CH_LastTxEndUs > T then
      T := CH_LastTxEndUs;
    if T > 0 then
    begin
      T := T + (QWord(CH_Ifg) * 1000000 + QWord(CH_Set.Baud) - 1) div QWord(CH_Set.Baud);
      if T > Result then
        Result := T;
    end;
  end;
end;

function tChnPhys.ComLineMs(N: LongInt): LongInt;
begin
  Result := LineTime(CH_Set, N, 1000);
end;

{ A message handed to ChSend just before ChClose (an answer, then exit)
  must reach the line: the rest of it goes to the OS, the OS queue empties,
  then Drain waits for the last bit (tcdrain, FlushFileBuffers, synaser's
  Flush). All of it within 1.5 times the time the pending bytes take at
  BD, plus 250 ms: a line held by flow control, or a pty nobody reads,
  cannot keep ChClose for ever; what is left then is discarded, as
  before. No purge happens before this (a purge is what lost the tail). }
procedure tChnPhys.ComDrainTx;
var
  Queued, Left: LongInt;
  Deadline, Now: QWord;
begin
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Exit;
  Queued := 0;
  if CH_Port.OutQueue(Queued) <> res_Ok then
    Queued := 0;
  Deadline := GetTickCount64 + QWord(ComLineMs(CH_TxLen - CH_TxPos + Queued)) * 3 div 2 + 250;
  repeat
    ComPumpTx;
    if CH_Fault <> res_Ok then
      Exit;
    Now := GetTickCount64;
    if Now >= Deadline then
      Break;
    Left := Deadline - Now;
    if CH_TxPos < CH_TxLen then
      CH_Port.WaitOutput(Left)      { returns when the OS takes more }
    else
    begin
      if CH_Port.OutQueue(Queued) <> res_Ok then
        Queued := 0;
      if Queued = 0 then
        Break;
      { the OS is sending: wait as long as that takes, then look again }
      if ComLineMs(Queued) + 1 < Left then
        Left := ComLineMs(Queued) + 1;
      Sleep(Left);
    end;
  until False;
  if (CH_TxPos >= CH_TxLen) and (CH_Port.OutQueue(Queued) <> res_Ok) then
    Queued := 0;
  if (CH_TxPos >= CH_TxLen) and (Queued = 0) then
    CH_Port.Drain                   { only the UART FIFO is left: short }
  else
    CH_Port.Flush(False, True);     { the bound is over: abandon the rest }
  CH_TxLen := 0;
  CH_TxPos := 0;
  CH_TxAt := 0;
  CH_RtsDropAt := 0;
end;

procedure tChnPhys.ChSend(Buff: Pointer; Len: Word);
var
  R: tChResult;
  Written, Rest: LongInt;
  Now, Start: QWord;
begin
  if not ChSendAllowed(Buff, Len, True) then
    Exit;
  ComReopen;
  if CH_Fault <> res_Ok then
  begin
    CH_SResult := CH_Fault;
    Exit;
  end;
  if Len > CH_LSB then
  begin
    CH_SResult := res_TooLong;
    Exit;
  end;
  ComPumpTx;
  if (CH_TxPos < CH_TxLen) or CH_RtsUp then
  begin
    CH_SResult := res_Busy;
    Exit;
  end;
  if CH_Fault <> res_Ok then
  begin
    CH_SResult := CH_Fault;
    Exit;
  end;
  if CH_RtsToggle then
  begin
    R := CH_Port.SetRts(True);
    if R <> res_Ok then
    begin
      ComFault(R);
      Exit;
    end;
    CH_RtsUp := True;
  end;
  { the clock (a system call) and the start time only when RTSB=, TURN=
    or IFG= need them }
  if (CH_RtsToggle and (CH_RtsBefore > 0)) or (CH_Turn > 0) or (CH_Ifg > 0) then
  begin
    Now := ChnClockUs;
    Start := ComTxStart(Now);
    if Start > Now then
    begin
      { all of it waits here for its time (ComPumpTx) }
      if Len > CH_TxCap then
      begin
        ReAllocMem(CH_TxBuf, Len);
        CH_TxCap := Len;
      end;
      Move(Buff^, CH_TxBuf^, Len);
      CH_TxLen := Len;
      CH_TxPos := 0;
      CH_TxAt := Start;
      CH_SResult := res_Ok;
      ChnWaitDue(CH_Wait, Start);
      Exit;
    end;
    if Now > 0 then
      CH_LastTxEndUs := Now + QWord(ComLineUs(Len));
  end;
  { what the port takes now goes straight from the caller's buffer; only
    the rest is copied, to move on from later polls }
  R := CH_Port.Write(Buff^, Len, Written);
  if R <> res_Ok then
  begin
    ComFault(R);
    Exit;
  end;
  Rest := Len - Written;
  if Rest > CH_TxCap then
  begin
    ReAllocMem(CH_TxBuf, Rest);
    CH_TxCap := Rest;
  end;
  if Rest > 0 then
    Move(PByte(Buff)[Written], CH_TxBuf^, Rest);
  CH_TxLen := Rest;
  CH_TxPos := 0;
  CH_SResult := res_Ok;
  { all of it taken and no RTS to drop: ComPumpTx above has done the rest }
  if (Rest = 0) and not CH_RtsUp then
    Exit;
  ComPumpTx;
  if CH_Fault <> res_Ok then
    CH_SResult := CH_Fault;
end;

function tChnPhys.ChSendReady: tChState;
begin
  ComReopen;
  Result := CHS_SendReady;
  if (CH_Port = nil) or (CH_Fault <> res_Ok) then
    Exit;
  ComPumpTx;
  if (CH_TxPos < CH_TxLen) and (CH_Fault = res_Ok) then
  begin
    { OS buffer full: wait for room, bounded like the receive side }
    if CH_Idle > 0 then
    begin
      CH_Port.WaitOutput(CH_Idle);
      ComPumpTx;
    end;
  end
  else if CH_RtsUp and (CH_Fault = res_Ok) and (CH_Idle > 0) and (CH_RtsDropAt = 0) then
  begin
    Sleep(1);                     { the last bytes are on the line }
    ComPumpTx;
  end;
  if (CH_Fault = res_Ok) and ((CH_TxPos < CH_TxLen) or CH_RtsUp) then
    Result := CHS_Sending;
end;

{ Up to IDL= ms for input: True when this port's came. The program-wide
  wait (ChnWaitUse) ends at the first input on any channel; without one
  the port's own wait; a port that failed has nothing to wait on and
  sleeps (still no busy loop). }
function tChnPhys.ComIdleWait: Boolean;
begin
  if CH_Wait <> nil then
    Result := ChnWaitIdle(CH_Wait, CH_Idle)
  else if CH_Fault <> res_Ok then
  begin
    Sleep(CH_Idle);
    Result := False;
  end
  else
    Result := CH_Port.WaitInput(CH_Idle);
end;

function tChnPhys.ChReceiveReady: tChState;
var
  Watched: Boolean;
begin
  if CH_State <> CHS_Connect then
    Exit(CHS_RecInactive);
  ComReopen;
  if (CH_Port <> nil) and (CH_Fault = res_Ok) then
    CH_Port.PollTimers;
  if CH_RCtrl <> CHS_ReceiveReady then
  begin
    ComPumpTx;                    { a long message keeps moving meanwhile }
    { one path: read what has come; nothing: wait up to IDL= ms and read
      if it came. When the shared wait watches this port (and the port
      holds nothing read already) the read before the wait is left out:
      input that came ends the wait at once, so an idle poll makes no read
      that finds nothing }
    Watched := (CH_Idle > 0) and (CH_Ring.Count = 0) and ChnWaitWatching(CH_Wait) and
      not CH_Port.HoldsInput;
    if not Watched then
      ComPull;
    if (CH_Ring.Count = 0) and (CH_Idle > 0) and ComIdleWait then
    begin
      { the wait may have ended for a held send's own time (TURN=, IFG=,
        RTSB=: its due time fired and is spent): it goes now, or its time
        is set again - else nothing would wake the program for it }
      if CH_TxAt <> 0 then
        ComPumpTx;
      ComPull;
    end;
    if CH_Ring.Count > 0 then
      CH_RCtrl := CHS_ReceiveReady
    else
      CH_RCtrl := CHS_Receiving;
  end;
  Result := CH_RCtrl;
end;

procedure tChnPhys.ChReceive(var Len: Word);
begin
  ComReopen;
  if not ChReceiveAllowed(Len) then
    Exit;
  if CH_RCtrl <> CHS_ReceiveReady then
    ComPull;
  Len := RingGet(CH_Ring, CH_RBuff, CH_RSize);
  if CH_Lost > CH_LostShown then
  begin
    CH_LostShown := CH_Lost;     { reported once, with the bytes kept }
    CH_RResult := res_Overrun;
  end
  else if CH_Fault <> res_Ok then
    CH_RResult := CH_Fault
  else if Len = 0 then
    CH_RResult := res_NoMessage
  else
    CH_RResult := res_Ok;
  if CH_Ring.Count > 0 then
    CH_RCtrl := CHS_ReceiveReady
  else
    CH_RCtrl := CHS_Receiving;
end;

procedure tChnPhys.ChReceiveFlush;
begin
  if (CH_Port <> nil) and (CH_Fault = res_Ok) then
    CH_Port.Flush(True, False);
  RingClear(CH_Ring);
  CH_LostShown := CH_Lost;
  inherited ChReceiveFlush;
  if CH_Fault <> res_Ok then
    CH_RResult := CH_Fault;
end;

function tChnPhys.ComPortUsable: tChResult;
begin
  if CH_Port = nil then
    Result := res_WrongState
  else
    Result := CH_Fault;
end;

function tChnPhys.ChSetRts(On: Boolean): tChResult;
begin
  Result := ComPortUsable;
  if Result = res_Ok then
    Result := CH_Port.SetRts(On);
end;

function tChnPhys.ChSetDtr(On: Boolean): tChResult;
begin
  Result := ComPortUsable;
  if Result = res_Ok then
    Result := CH_Port.SetDtr(On);
end;

function tChnPhys.ChModemLines(var Lines: tPortLines): tChResult;
begin
  Lines := [];
  Result := ComPortUsable;
  if Result = res_Ok then
    Result := CH_Port.GetLines(Lines);
end;

function tChnPhys.ChLostBytes: LongWord;
begin
  Result := CH_Lost;
end;

end.
