{ ChnPcccClient - read and write SLC 500 / MicroLogix (and, with
  PcccClientPlc5, PLC-5: unit ChnPlc5) data by address
  ('N7:0', 'F8:2', 'B3:1/4', 'T4:0.ACC', 'ST9:0', 'L10:0') over any DF1
  stack (full or half duplex, BCC or CRC), as a master.

  The requests come from unit ChnPccc (0F A2 read, 0F AA write, 0F AB
  masked write for bits); a read or write longer than one frame becomes
  several requests whose results are joined. The link dialogue (ACK, NAK,
  ENQ, three tries, polling in half duplex) is ChnDF1Link's master.

  Two forms:
  * blocking: PcccReadInts, PcccReadFloats, PcccReadString, PcccWrite*
    return when done; Client.Err says what went wrong;
  * stepped: PcccStartRead / PcccStartWrite* send the first request and
    PcccStep, called from the program's poll loop, advances the exchange
    without waiting, so the program keeps serving its other lines.
  Every failure is a result code and a text naming the address: timeout
  (no ACK after the tries, or no reply), res_PcccNak (every try NAKed),
  res_PcccStatus (error reply, with STS and EXT STS), res_PcccReply (a
  reply whose length does not match), res_PcccAddress, res_PcccCount,
  res_PcccValue, res_PcccUsage, or the channel's result when the line
  fails. Nothing is written past the caller's arrays. }
unit ChnPcccClient;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnDF1Codec, ChnDF1Link, ChnDF1Poll, ChnPccc, ChnPlc5;

type
  tPcccClient = record
    Chn      : pChnVirt;     {< a tChnDF1 stack, master }
    OwnsChn  : Boolean;      {< PcccClose disposes of Chn }
    TimeoutMs: LongInt;      {< link timeout, default DF1LinkTimeoutMs }
    MaxBytes : Word;         {< data bytes per request, 2..244 (default 244) }
    Tns      : Word;         {< TNS of the next request }
    Idle     : tDF1Idle;     {< blocking calls: called while waiting (nil: the program-wide wait) }
    IdleData : Pointer;
    Log      : tDF1LogProc;  {< nil: quiet }
    LogWire  : Boolean;
    Requests : LongInt;      {< exchanges made }
    InUse    : Boolean;      {< a request is under way: one at a time }
    Err      : ShortString;  {< the text of the last failure }
    Plc5     : Boolean;      {< PLC-5 addresses and commands (PcccClientPlc5) }
    Plc5Cmd  : tPlc5Command; {< typed read/write or word range }
    Poller   : pDF1Poller;   {< nil: the client's own master (DF1MasterStart) }
    PollDst  : Byte;         {< the station the poller sends to }
  end;
  pPcccClient = ^tPcccClient;

  tPcccOp = (poRead, poWrite);

  { One read or write in progress. The values of a read are in Ints,
    Floats or Str (by Kind) once it is done with res_Ok. }
  tPcccRequest = record
    Client : pPcccClient;
    Op     : tPcccOp;
    Kind   : tPcccValueKind;
    Plan   : tPcccPlan;
    Index  : LongInt;        {< request of the plan under way }
    Expect : Word;           {< data bytes its reply must carry }
    Busy   : Boolean;
    Result : tChResult;
    Err    : ShortString;
    Ints   : array of LongInt;
    Floats : array of Single;
    Str    : ShortString;
    Master : tDF1Master;
    PollJob: LongInt;        {< the poller's job (PcccClientPoller) }
  end;

{ A client on an open DF1 stack (it stays the caller's). }
procedure PcccClientInit(var C: tPcccClient; Chn: pChnVirt);
{ A client on a new DF1 stack built from Params (DF1OpenStack); res_Ok, or
  res_CannotOpen with C.Err saying why; a string longer than the legacy
  255 characters is res_ParamTooLong (C.Err: its length and the limit),
  never cut to another device name. }
function PcccOpen(var C: tPcccClient; const Params: AnsiString): tChResult;
{ Requests of C go through the half-duplex poll master P (unit
  ChnDF1Poll) to station Dst, between its polls of the other stations;
  C.Chn becomes P's channel. Blocking calls and PcccFinish step P (and
  only P: stations in this process need stepping by the caller's Idle). }
procedure PcccClientPoller(var C: tPcccClient; var P: tDF1Poller; Dst: Byte);
{ Disconnect and dispose of a stack PcccOpen built. }
procedure PcccClose(var C: tPcccClient);
{ Talk to a PLC-5: its addresses ('I:012/05', 'D10:0', unit ChnPlc5) and
  commands - typed read/write (0F 68/67, Cmd p5Typed) or word range read/
  write (0F 01/00, p5WordRange); bits by read-modify-write (0F 26). }
procedure PcccClientPlc5(var C: tPcccClient; Cmd: tPlc5Command);

{ Blocking. Count items from Addr (see ChnPccc.PcccPlan: ints are 16-bit
  words, 32-bit for L, 0/1 for bits, three per whole T/C/R element). }
function PcccReadInts(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  var Values: array of LongInt): tChResult;
function PcccReadFloats(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  var Values: array of Single): tChResult;
function PcccReadString(var C: tPcccClient; const Addr: ShortString; out S: ShortString): tChResult;
function PcccWriteInts(var C: tPcccClient; const Addr: ShortString;
  const Values: array of LongInt): tChResult;
function PcccWriteFloats(var C: tPcccClient; const Addr: ShortString;
  const Values: array of Single): tChResult;
function PcccWriteString(var C: tPcccClient; const Addr: ShortString; const S: ShortString): tChResult;

{ Stepped. Start: False when nothing could be sent (R.Result, R.Err say
  why; R is then done). R must stay where it is until PcccStep returns
  True; then R.Result and R.Err hold the outcome. }
function PcccStartRead(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  Count: LongInt): Boolean;
{ Whether a read of Count items at Addr can be made on C (address,
  count, kind, in C's PLC family), with no channel needed and nothing
  sent: res_Ok, or the result and the text PcccStartRead would give (a
  tool checks its arguments with it before it opens the line). }
function PcccCheckRead(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  out Err: ShortString): tChResult;
function PcccStartWriteInts(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of LongInt): Boolean;
function PcccStartWriteFloats(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of Single): Boolean;
function PcccStartWriteString(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const S: ShortString): Boolean;
{ Values given as text, one per item, parsed for the address's kind
  ('12', '$FF', '-1.5e3', a whole string for ST). }
function PcccStartWriteText(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of ShortString): Boolean;
{ Take everything the line has received for R, without waiting; True
  when the request is done. A program with many requests in flight waits
  in ChnWaitAny and steps each of them after every wait. }
function PcccStep(var R: tPcccRequest): Boolean;
{ Abandon a request under way (R.Result res_Timeout, 'cancelled'); the
  client takes a new one at once. A client runs one request at a time: a
  start while one is under way is refused with res_WrongState. }
procedure PcccCancel(var R: tPcccRequest);
{ Drive a started request to its end: a step, then C.Idle when the client
  has one, otherwise the program-wide wait up to the request's next timer
  (ChnWaitUntil: it ends at the first input or at the timer) - no sleep,
  no busy loop. }
function PcccFinish(var R: tPcccRequest): tChResult;
{ Why the link exchange M on Chn failed, in words ('no ACK after 3 tries',
  'NAK on each of 3 tries', 'no reply', ...); M.Result <> res_Ok. }
function PcccMasterFailure(const M: tDF1Master; Chn: pChnVirt): ShortString;
{ A program's exit code for a request's result, in the tools' one scheme
  (docs/TOOLS.md): 0 res_Ok; 1 the line failed (cannot be opened, lost, any
  other error); 2 the request cannot be made (address, count, value, kind,
  no DF1 channel: what the command line asked is wrong); 3 the PLC's
  answer is an error reply, does not fit, or a NAK on every try; 4 no
  answer in time. }
function PcccExitCode(Res: tChResult): LongInt;
{ 'N7:3 = -1', 'F8:0 = 1.5', 'B3:1/4 = 1', 'T4:0 = $A000 100 42' for item
  Item of a finished read. }
function PcccItemText(const R: tPcccRequest; Item: LongInt): ShortString;

implementation

uses
  SysUtils, Math, uString, ChnWait;

procedure PcccClientInit(var C: tPcccClient; Chn: pChnVirt);
begin
  FillChar(C, SizeOf(C), 0);
  C.Chn := Chn;
  C.TimeoutMs := DF1LinkTimeoutMs;
  C.MaxBytes := MaxDataLen;
  { a PLC that detects duplicates drops a command with the TNS of the last
    one: a program started again must not begin where it began before (the
    clock, and the process id for two programs started in one millisecond) }
  C.Tns := Word(ChMsTick xor (QWord(GetProcessID) * 40503));
end;

function PcccOpen(var C: tPcccClient; const Params: AnsiString): tChResult;
var
  Chn: pChnVirt;
  E: AnsiString;
  Why: ShortString;
begin
  Why := '';
  Result := ParamLengthCheck(Length(Params), Why);
  if Result <> res_Ok then
  begin
    PcccClientInit(C, nil);
    C.Err := 'parameter string too long: ' + Why;
    Exit;
  end;
  Chn := DF1OpenStack(Params, 3000, E);
  PcccClientInit(C, Chn);
  if Chn = nil then
  begin
    C.Err := E;
    Exit(res_CannotOpen);
  end;
  C.OwnsChn := True;
  Result := res_Ok;
end;

procedure PcccClientPlc5(var C: tPcccClient; Cmd: tPlc5Command);
begin
  C.Plc5 := True;
  C.Plc5Cmd := Cmd;
end;

{ The address rules of the client's PLC family. }
function ParseFor(const C: tPcccClient; const Addr: ShortString; out A: tPcccAddr;
  out E: ShortString): tChResult;
begin
  if C.Plc5 then
    Result := Plc5ParseAddress(Addr, A, E)
  else
    Result := PcccParseAddress(Addr, A, E);
end;

function TextFor(C: pPcccClient; const A: tPcccAddr): ShortString;
begin
  if (C <> nil) and C^.Plc5 then
    Result := Plc5AddressText(A)
  else
    Result := PcccAddressText(A);
end;

procedure PcccClose(var C: tPcccClient);
begin
  if C.OwnsChn and (C.Chn <> nil) then
  begin
    C.Chn^.ChDisConnect;
    C.Chn^.ChClose;
    Dispose(C.Chn, Done);
  end;
  C.Chn := nil;
  C.OwnsChn := False;
end;

{- ------------------------------------------------------------- stepping }

{ R is over: the client is free for the next one. }
procedure Release(var R: tPcccRequest);
begin
  if R.Busy then
  begin
    R.Busy := False;
    R.Client^.InUse := False;
  end;
end;

function Fail(var R: tPcccRequest; Res: tChResult; const Why: ShortString): Boolean;
begin
  Release(R);
  R.Result := Res;
  R.Err := TextFor(R.Client, R.Plan.Addr) + ': ' + Why;
  if R.Client <> nil then
    R.Client^.Err := R.Err;
  Result := False;
end;

{ Prepare R for an operation at Addr; False (R failed) on a bad address
  or count. The client's channel is not looked at (Prepare does). }
function PrepareRequest(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  Count: LongInt; Op: tPcccOp): Boolean;
var
  A: tPcccAddr;
  E: ShortString;
  Res: tChResult;
begin
  if C.InUse then
  begin
    { R itself may be the one under way: leave it running }
    R.Result := res_WrongState;
    R.Err := Addr + ': another request is under way on this client';
    C.Err := R.Err;
    Exit(False);
  end;
  FillChar(R.Plan, SizeOf(R.Plan), 0);
  R.Client := @C;
  R.Op := Op;
  R.Index := 0;
  R.Busy := False;
  R.Result := res_Ok;
  R.Err := '';
  R.Str := '';
  SetLength(R.Ints, 0);
  SetLength(R.Floats, 0);
  C.Err := '';
  Res := ParseFor(C, Addr, A, E);
  if Res <> res_Ok then
  begin
    R.Result := Res;
    R.Err := E;
    C.Err := E;
    Exit(False);
  end;
  R.Plan.Addr := A;
  R.Kind := PcccValueKind(A);
  if C.Plc5 then
    Res := Plc5Plan(A, Count, Op = poWrite, C.MaxBytes, R.Plan, E)
  else
    Res := PcccPlan(A, Count, Op = poWrite, C.MaxBytes, R.Plan, E);
  if Res <> res_Ok then
    Exit(Fail(R, Res, E));
  if (R.Kind = pvString) and (Count <> 1) then
    Exit(Fail(R, res_PcccCount, 'strings are read and written one at a time'));
  Result := True;
end;

{ PrepareRequest, on a client with a DF1 channel. }
function Prepare(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  Count: LongInt; Op: tPcccOp): Boolean;
begin
  Result := PrepareRequest(R, C, Addr, Count, Op);
  if Result and not IsDF1Channel(C.Chn) then
    Result := Fail(R, res_WrongLayer, 'the client has no DF1 channel');
end;

function PcccCheckRead(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  out Err: ShortString): tChResult;
var
  R: tPcccRequest;
begin
  if PrepareRequest(R, C, Addr, Count, poRead) then
  begin
    Err := '';
    Result := res_Ok;
  end
  else
  begin
    Err := R.Err;
    Result := R.Result;
  end;
end;

{ Request R.Index to a PLC-5. }
function BuildPlc5(var R: tPcccRequest; var Req: tSendRecord; out Len: Word; out E: ShortString): tChResult;
var
  C: pPcccClient;
begin
  C := R.Client;
  E := '';
  if R.Op = poRead then
    Result := Plc5BuildPlanRead(R.Plan, R.Index, C^.Plc5Cmd, C^.Tns, Req, Len, R.Expect)
  else
    case R.Kind of
      pvFloat: Result := Plc5BuildPlanWriteFloats(R.Plan, R.Index, R.Floats, C^.Plc5Cmd, C^.Tns, Req, Len, E);
      pvString: Result := Plc5BuildWriteString(R.Plan.Addr, R.Str, C^.Tns, Req, Len, E);
    else
      Result := Plc5BuildPlanWriteInts(R.Plan, R.Index, R.Ints, C^.Plc5Cmd, C^.Tns, Req, Len, E);
    end;
end;

{ Build request R.Index and send it. }
function SendCurrent(var R: tPcccRequest): Boolean;
var
  Req: tSendRecord;
  Len: Word;
  Res: tChResult;
  E: ShortString;
  Buf: array[0..2 + PcccStringChars - 1] of Byte;
  C: pPcccClient;
begin
  C := R.Client;
  E := '';
  R.Expect := 0;
  if C^.Plc5 then
    Res := BuildPlc5(R, Req, Len, E)
  else if R.Op = poRead then
    Res := PcccBuildPlanRead(R.Plan, R.Index, C^.Tns, Req, Len, R.Expect)
  else
    case R.Kind of
      pvFloat: Res := PcccBuildPlanWriteFloats(R.Plan, R.Index, R.Floats, C^.Tns, Req, Len, E);
      pvString:
        begin
          Res := PcccEncodeString(R.Str, Buf, E);
          if Res = res_Ok then
            Res := PcccBuildWrite(R.Plan.Addr, Buf, SizeOf(Buf), C^.Tns, Req, Len);
        end;
    else
      Res := PcccBuildPlanWriteInts(R.Plan, R.Index, R.Ints, C^.Tns, Req, Len, E);
    end;
  if Res <> res_Ok then
  begin
    if E = '' then
      E := ChResultText(Res, PcccLayer);
    Exit(Fail(R, Res, E));
  end;
  C^.Tns := Word(C^.Tns + 1);
  R.Busy := True;
  C^.InUse := True;
  if C^.Poller <> nil then
  begin
    { the poller sends it between polls; R.Master only carries the outcome }
    FillChar(R.Master, SizeOf(R.Master), 0);
    R.Master.Chn := C^.Chn;
    R.Master.State := dmWaitAck;
    R.Master.Tries := 1;
    Res := DF1PollSend(C^.Poller^, C^.PollDst, Req, Len, R.PollJob);
    if Res <> res_Ok then
      Exit(Fail(R, Res, 'cannot queue: ' + ChResultText(Res, PcccLayer)));
  end
  else if not DF1MasterStart(R.Master, C^.Chn, Req, Len, C^.TimeoutMs, C^.Log, C^.LogWire) then
    Exit(Fail(R, R.Master.Result, 'cannot send: ' + C^.Chn^.ChResultStr(R.Master.Result)));
  Result := True;
end;

procedure PcccClientPoller(var C: tPcccClient; var P: tDF1Poller; Dst: Byte);
begin
  C.Poller := @P;
  C.PollDst := Dst;
  C.Chn := P.Chn;
end;

{ The poller's step for R: True when R's job is over (R.Master then says
  how, as DF1MasterStep leaves it). }
function PollStep(var R: tPcccRequest): Boolean;
var
  Res: tChResult;
begin
  DF1PollStep(R.Client^.Poller^);
  Result := DF1PollResult(R.Client^.Poller^, R.PollJob, R.Master.Rep, R.Master.RepLen, Res);
  if Result then
  begin
    R.Master.Result := Res;
    R.Master.Acked := Res = res_Ok;
    R.Master.State := dmDone;
  end;
end;

function Start(var R: tPcccRequest): Boolean;
begin
  Result := SendCurrent(R);
end;

const
  KindNames: array[tPcccValueKind] of string[8] = ('integers', 'floats', 'a string');

function WrongKind(var R: tPcccRequest; const Given: ShortString): Boolean;
begin
  Result := Fail(R, res_PcccUsage, 'holds ' + KindNames[R.Kind] + ', not ' + Given);
end;

{ Start a read; with Check, only of kind Want and only when Room values
  (-1: any) hold its result. }
function StartReadAs(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  Count: LongInt; Check: Boolean; Want: tPcccValueKind; Room: LongInt): Boolean;
var
  N: LongInt;
begin
  Result := Prepare(R, C, Addr, Count, poRead);
  if not Result then
    Exit;
  if Check and (R.Kind <> Want) then
    Exit(WrongKind(R, KindNames[Want]));
  N := PcccPlanValues(R.Plan);
  if (Room >= 0) and (Room < N) then
    Exit(Fail(R, res_PcccCount, Format('%d values to read, room for %d', [N, Room])));
  case R.Kind of
    pvInt: SetLength(R.Ints, N);
    pvFloat: SetLength(R.Floats, N);
  end;
  Result := Start(R);
end;

function PcccStartRead(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  Count: LongInt): Boolean;
begin
  Result := StartReadAs(R, C, Addr, Count, False, pvInt, -1);
end;

function PcccStartWriteInts(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of LongInt): Boolean;
var
  I, PerItem: LongInt;
  A: tPcccAddr;
  E: ShortString;
begin
  { a whole T/C/R element takes three values: the plan counts elements }
  PerItem := 1;
  if (ParseFor(C, Addr, A, E) = res_Ok) and
     (A.FileType in [pft_Timer, pft_Counter, pft_Control]) and not A.HasSub and (A.Bit < 0) then
    PerItem := 3;
  Result := Prepare(R, C, Addr, Max(Length(Values) div PerItem, 1), poWrite);
  if not Result then
    Exit;
  if R.Kind <> pvInt then
    Exit(WrongKind(R, 'integers'));
  if Length(Values) = 0 then
    Exit(Fail(R, res_PcccCount, 'no values given'));
  if Length(Values) mod PerItem <> 0 then
    Exit(Fail(R, res_PcccCount, Format('%d values given for whole elements of %d',
      [Length(Values), PerItem])));
  SetLength(R.Ints, Length(Values));
  for I := 0 to High(Values) do
    R.Ints[I] := Values[I];
  Result := Start(R);
end;

function PcccStartWriteFloats(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of Single): Boolean;
var
  I: LongInt;
begin
  Result := Prepare(R, C, Addr, Length(Values), poWrite);
  if not Result then
    Exit;
  if R.Kind <> pvFloat then
    Exit(WrongKind(R, 'floats'));
  SetLength(R.Floats, Length(Values));
  for I := 0 to High(Values) do
    R.Floats[I] := Values[I];
  Result := Start(R);
end;

function PcccStartWriteString(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const S: ShortString): Boolean;
begin
  Result := Prepare(R, C, Addr, 1, poWrite);
  if not Result then
    Exit;
  if R.Kind <> pvString then
    Exit(WrongKind(R, 'a string'));
  R.Str := S;
  Result := Start(R);
end;

function PcccStartWriteText(var R: tPcccRequest; var C: tPcccClient; const Addr: ShortString;
  const Values: array of ShortString): Boolean;
var
  A: tPcccAddr;
  E: ShortString;
  Ints: array of LongInt;
  Floats: array of Single;
  I: LongInt;
  D: Double;
  Res: tChResult;
begin
  Res := ParseFor(C, Addr, A, E);
  if Res <> res_Ok then
  begin
    Prepare(R, C, Addr, 1, poWrite);      { fails the same way, fills R }
    Exit(False);
  end;
  case PcccValueKind(A) of
    pvString:
      begin
        if Length(Values) <> 1 then
        begin
          Prepare(R, C, Addr, Length(Values), poWrite);
          Exit(Fail(R, res_PcccCount, 'one string at a time'));
        end;
        Result := PcccStartWriteString(R, C, Addr, Values[0]);
      end;
    pvFloat:
      begin
        SetLength(Floats, Length(Values));
        for I := 0 to High(Values) do
        begin
          { the shared parser: 2e308 is refused, never EOverflow }
          if not StrToReal(Values[I], -3.4e38, 3.4e38, D) then
          begin
            Prepare(R, C, Addr, Length(Values), poWrite);
            Exit(Fail(R, res_PcccValue, '"' + Values[I] + '" is no float'));
          end;
          Floats[I] := D;
        end;
        Result := PcccStartWriteFloats(R, C, Addr, Floats);
      end;
  else
    SetLength(Ints, Length(Values));
    for I := 0 to High(Values) do
    begin
      Ints[I] := 0;
      if not StrToNum(Values[I], Low(LongInt), High(LongInt), Ints[I]) then
      begin
        Prepare(R, C, Addr, Length(Values), poWrite);
        Exit(Fail(R, res_PcccValue, '"' + Values[I] + '" is no integer'));
      end;
    end;
    Result := PcccStartWriteInts(R, C, Addr, Ints);
  end;
end;

{ The exchange of request R.Index is over: check, decode, go on. }
function PcccMasterFailure(const M: tDF1Master; Chn: pChnVirt): ShortString;
begin
  if (M.Result = res_Timeout) and not M.Acked and (M.Naks >= M.Tries) then
    Result := Format('NAK on each of %d tries', [M.Tries])
  else if (M.Result = res_Timeout) and not M.Acked then
    Result := Format('no ACK after %d tries', [M.Tries])
  else if M.Result = res_Timeout then
    Result := 'no reply'
  else if M.Result = res_BadMessage then
    Result := 'the reply is not the one to this command'
  else
    Result := Chn^.ChResultStr(M.Result);
end;

procedure Exchanged(var R: tPcccRequest);
var
  E: ShortString;
  First: Word;
  Res: tChResult;
  M: ^tDF1Master;
begin
  M := @R.Master;
  Inc(R.Client^.Requests);
  if M^.Result <> res_Ok then
  begin
    if (M^.Result = res_Timeout) and not M^.Acked and (M^.Naks >= M^.Tries) then
      Fail(R, res_PcccNak, PcccMasterFailure(M^, R.Client^.Chn))
    else
      Fail(R, M^.Result, PcccMasterFailure(M^, R.Client^.Chn));
    Exit;
  end;
  First := 0;
  if R.Client^.Plc5 and (R.Op = poRead) then
    Res := Plc5CheckReadReply(R.Plan, R.Client^.Plc5Cmd, M^.Rep, M^.RepLen, R.Expect, First, E)
  else
    Res := PcccCheckReply(M^.Rep, M^.RepLen, R.Expect, E);
  if Res = res_PcccStatus then
  begin
    Fail(R, Res, 'error reply ' + E);
    Exit;
  end;
  if Res <> res_Ok then
  begin
    Fail(R, Res, E);
    Exit;
  end;
  if R.Op = poRead then
  begin
    if First > 0 then
      Move(M^.Rep.Data[First], M^.Rep.Data[0], R.Expect);   { past the type parameter }
    case R.Kind of
      pvInt:
        if R.Client^.Plc5 then
          Res := Plc5DecodePlanInts(R.Plan, R.Index, M^.Rep.Data, R.Expect, R.Ints)
        else
          Res := PcccDecodePlanInts(R.Plan, R.Index, M^.Rep.Data, R.Expect, R.Ints);
      pvFloat: Res := PcccDecodePlanFloats(R.Plan, R.Index, M^.Rep.Data, R.Expect, R.Floats);
      pvString: Res := PcccDecodeString(M^.Rep.Data, 0, R.Str);
    end;
    if Res <> res_Ok then
    begin
      Fail(R, Res, 'reply data cannot be decoded: ' + ChResultText(Res, PcccLayer));
      Exit;
    end;
  end;
  Inc(R.Index);
  if R.Index < PcccPlanRequests(R.Plan) then
    SendCurrent(R)
  else
  begin
    Release(R);
    R.Result := res_Ok;
  end;
end;

procedure PcccCancel(var R: tPcccRequest);
begin
  if R.Busy then
  begin
    if R.Client^.Poller <> nil then
      DF1PollCancel(R.Client^.Poller^, R.PollJob)
    else
      DF1MasterCancel(R.Master);
    Fail(R, res_Timeout, 'cancelled');
  end;
end;

function PcccStep(var R: tPcccRequest): Boolean;
begin
  if R.Busy and (R.Client^.Poller <> nil) then
  begin
    if PollStep(R) then
      Exchanged(R);
  end
  else if R.Busy and DF1MasterStep(R.Master) then
    Exchanged(R);
  Result := not R.Busy;
end;

function PcccFinish(var R: tPcccRequest): tChResult;
begin
  while not PcccStep(R) do
    if Assigned(R.Client^.Idle) then
      R.Client^.Idle(R.Client^.IdleData)
    else if R.Client^.Poller <> nil then
      ChnWaitUntil(DF1PollWaitEnd(R.Client^.Poller^))
    else
      ChnWaitUntil(DF1MasterWaitEnd(R.Master));   { the program-wide wait }
  Result := R.Result;
end;

function PcccExitCode(Res: tChResult): LongInt;
begin
  case Res of
    res_Ok: Result := 0;
    res_PcccAddress, res_PcccCount, res_PcccValue, res_PcccUsage, res_WrongLayer: Result := 2;
    res_PcccStatus, res_PcccReply, res_BadMessage, res_PcccNak: Result := 3;
    res_Timeout: Result := 4;
  else
    Result := 1;
  end;
end;

function PcccItemText(const R: tPcccRequest; Item: LongInt): ShortString;
var
  A: tPcccAddr;
  K: LongInt;
begin
  A := PcccItemAddress(R.Plan, Item);
  Result := TextFor(R.Client, A) + ' = ';
  case R.Kind of
    pvFloat: Result := Result + FloatToStr(R.Floats[Item]);
    pvString: Result := Result + '"' + R.Str + '"';
  else
    if R.Plan.PerItem = 3 then
    begin
      Result := Result + '$' + IntToHex(Word(R.Ints[Item * 3]), 4);
      for K := 1 to 2 do
        Result := Result + ' ' + IntToStr(R.Ints[Item * 3 + K]);
    end
    else if (A.Bit < 0) and not A.HasSub and
            (A.FileType in [pft_Bit, pft_Status, pft_Output, pft_Input, pft_Ascii]) then
      Result := Result + '$' + IntToHex(R.Ints[Item], 4)
    else
      Result := Result + IntToStr(R.Ints[Item]);
  end;
end;

{- ------------------------------------------------------------- blocking }

function Copied(var C: tPcccClient; var R: tPcccRequest): tChResult;
begin
  Result := R.Result;
  C.Err := R.Err;
end;

function PcccReadInts(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  var Values: array of LongInt): tChResult;
var
  R: tPcccRequest;
  I: LongInt;
begin
  if StartReadAs(R, C, Addr, Count, True, pvInt, Length(Values)) and (PcccFinish(R) = res_Ok) then
    for I := 0 to High(R.Ints) do
      Values[I] := R.Ints[I];
  Result := Copied(C, R);
end;

function PcccReadFloats(var C: tPcccClient; const Addr: ShortString; Count: LongInt;
  var Values: array of Single): tChResult;
var
  R: tPcccRequest;
  I: LongInt;
begin
  if StartReadAs(R, C, Addr, Count, True, pvFloat, Length(Values)) and (PcccFinish(R) = res_Ok) then
    for I := 0 to High(R.Floats) do
      Values[I] := R.Floats[I];
  Result := Copied(C, R);
end;

function PcccReadString(var C: tPcccClient; const Addr: ShortString; out S: ShortString): tChResult;
var
  R: tPcccRequest;
begin
  S := '';
  if StartReadAs(R, C, Addr, 1, True, pvString, -1) and (PcccFinish(R) = res_Ok) then
    S := R.Str;
  Result := Copied(C, R);
end;

function PcccWriteInts(var C: tPcccClient; const Addr: ShortString;
  const Values: array of LongInt): tChResult;
var
  R: tPcccRequest;
begin
  if PcccStartWriteInts(R, C, Addr, Values) then
    PcccFinish(R);
  Result := Copied(C, R);
end;

function PcccWriteFloats(var C: tPcccClient; const Addr: ShortString;
  const Values: array of Single): tChResult;
var
  R: tPcccRequest;
begin
  if PcccStartWriteFloats(R, C, Addr, Values) then
    PcccFinish(R);
  Result := Copied(C, R);
end;

function PcccWriteString(var C: tPcccClient; const Addr: ShortString; const S: ShortString): tChResult;
var
  R: tPcccRequest;
begin
  if PcccStartWriteString(R, C, Addr, S) then
    PcccFinish(R);
  Result := Copied(C, R);
end;

end.
