{ ChnFT12Link - the IEC 60870-5-2 unbalanced link procedures that SofCon's
  ChnFT1_2 leaves to the application (manual 4.4: "evaluating FCB and
  repeating a message with unchanged FCB is the job of the application";
  docs/PROTOCOLS.md section 5: "or the optional helpers"), for both ends, on top of a
  tChnFT1_2 channel with MS=ON:

  * FT12Transact, the primary (master): one SEND/CONFIRM, REQUEST/RESPOND
    or SEND/NO REPLY service to one secondary, with the frame count bit
    kept per secondary in a tFT12Link record:
      - FCV = 1 for FC 2, 3, 10, 11, else 0 (IEC 60870-5-2 function table;
        the manual's FCM_* comments say the same);
      - every new FCV = 1 transmission to a secondary carries the opposite
        FCB of the previous one; a repetition after a missing or garbled
        reply carries the same FCB;
      - reset of remote link (FC 0) is sent with FCB = 0, FCV = 0; after
        its ACK the next FCV = 1 frame carries FCB = 1;
      - an FCV = 1 service to a link not reset (new record, or after a
        service failed) is preceded by a reset of remote link;
      - SEND/NO REPLY (FC 4) and the broadcast address expect no reply.
    FT12PrimaryStart / FT12PrimaryStep are the same service stepped by the
    program's own loop (many lines, one ChnWaitAny); FT12Transact is them
    with the program-wide wait (or the caller's Idle) between the steps.
  * tFT12Station / FT12StationStep, the secondary (slave): answers the
    unbalanced functions, and when an FCV = 1 frame carries the same FCB
    as the last one it accepted it sends the last reply again without
    executing the frame a second time (a repetition by the primary).

  Both poll the channel; nothing blocks for longer than the timeouts given.
  A caller that runs both ends in one thread passes an Idle procedure that
  steps the other end while the primary waits (as ChnDF1Link does).

  * tFT12Balanced / FT12BalancedStep, a station of a balanced link (MS=OFF):
    primary and secondary at once on one channel - link set-up (FC 9,
    FC 0), user data from a queue (FC 3/4), test function for link (FC 2)
    when quiet, repetitions with the same FCB; answers to the peer's
    requests at once, also while a request of its own is out, with the
    cached answer for a repeated FCB. On a lost frame station B (DIR=0)
    repeats half a timeout later than station A, so the two do not meet
    again (docs/ChnFT1_2.md, balanced mode).

  Late answers (both primaries). An answer carries nothing that says which
  transmission it answers, so after a repetition the answer to the first
  transmission, held up on the line longer than the timeout, and the
  answer to the repetition may both arrive - the second while the next
  request is out, where it would confirm a frame the secondary never got. The primary therefore keeps count: after a request that was
  sent more than once (or not answered at all) answers to it may still
  come (Suspect), and before its next request it sends a fence, request
  status of link (FC 9). Its answer, status of link (FC 11), fits no other
  request, and on a line that keeps order it arrives after every answer
  the secondary sent before; every other answer meanwhile is late and
  ignored (Stale). Status answers owed by earlier FC 9 transmissions are
  counted too (OwedStatus; forgotten after 4 timeouts without one) and
  skipped by the next FC 9. A fresh answer to any other request proves
  that nothing older is still on the way.

  Not covered: DFC flow control beyond holding back after DFC = 1, the
  "link service not functioning" (FC 14) state.

  This unit holds what the three share: the primary's record per
  secondary (tFT12Link), the secondary's callbacks, the function table
  (FT12FcvOf, FT12ReplyFits) and the fixed-frame helpers. The procedures
  are units of their own: ChnFT12Primary (FT12Transact, FT12PrimaryStart
  and FT12PrimaryStep), ChnFT12Station (tFT12Station, FT12StationStep),
  ChnFT12Balanced (tFT12Balanced, FT12BalancedStep). }
unit ChnFT12Link;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2;

const
  FT12LinkTimeoutMs = 1000;
  FT12LinkRetries   = 3;
  { frames one step takes at most: all that was received, but a peer that
    never stops sending cannot keep a step from running the timers }
  FT12MaxFramesPerStep = 64;

  {- secondary function codes of IEC 60870-5-2 that the manual does not name }
  FCS_NotFunctioning  = 14;  {< link service not functioning }
  FCS_NotImplemented  = 15;  {< link service not implemented }

type
  tFT12Idle = procedure(Data: Pointer);

  { What the primary keeps per secondary. }
  tFT12Link = record
    Addr    : Word;      {< link address of the secondary (DNO) }
    Fcb     : Boolean;   {< FCB for the next new FCV = 1 transmission }
    Reset   : Boolean;   {< reset of remote link acknowledged, no failure since }
    Acd     : Boolean;   {< ACD of the last reply: class 1 data waiting }
    Dfc     : Boolean;   {< DFC of the last reply: secondary cannot take more }
    Repeats : LongInt;   {< repetitions sent after a missing reply }
    Ignored : LongInt;   {< frames ignored while waiting (other address, broken) }
    {- late answers (unit header): }
    Suspect   : Boolean; {< answers to earlier transmissions may still come: fence first }
    OwedStatus: LongInt; {< status of link answers (FC 11) that may still come }
    StatusAt  : QWord;   {< when a status request last went out }
    Fences    : LongInt; {< fences (FC 9) sent before a service }
    Stale     : LongInt; {< late answers recognised and ignored }
    OtherAddr : LongInt; {< of Ignored: answers from another link address }
    OtherLast : Word;    {< the address the last of them carried }
  end;

  { Secondary callbacks; Data is tFT12Station.Data.
    UserData: user data of FC 3 (Confirm = True) or FC 4 / broadcast
      (Confirm = False); Len data octets in Buf^. True accepts it (ACK),
      False refuses it (NACK, FC 1); the result of FC 4 is not sent.
    ClassData: data of class 1 or 2 for the reply; put up to MaxDataLen
      octets in Rep.Data and their count in Len; False: none (FC 9).
    LongClassData: the same into a record with room for the longest
      frame: up to FT12MaxUserData minus the link address octets.
    Class1Waiting: ACD of every reply; nil = never. }
  tFT12UserDataFunc = function(Data: Pointer; Buf: PByte; Len: Word;
    Confirm: Boolean): Boolean;
  tFT12ClassDataFunc = function(Data: Pointer; ClassNo: Byte;
    var Rep: tSendRecord; var Len: Word): Boolean;
  tFT12LongClassDataFunc = function(Data: Pointer; ClassNo: Byte;
    var Rep: tFT12MaxRecord; var Len: Word): Boolean;
  tFT12Class1Func = function(Data: Pointer): Boolean;

procedure FT12LinkInit(var Link: tFT12Link; Addr: Word);

{ True when Chn is the top of a tChnFT1_2 stack (by the registry's number
  of the layer type). }
function IsFT12Channel(Chn: pChnVirt): Boolean;
{ FCV the standard gives a primary function code. }
function FT12FcvOf(FC: Byte): Boolean;

{ Octets of a fixed frame on this channel (LEN=), as a record length. }
function FT12FixedLen(Chn: pChnVirt): Word;
{ What the line showed besides the answers awaited, for an error text:
  ' — 12 frames from link address 1 ignored', ' — 3 frames with this
  station's own DIR bit ignored' (both when both), '' when none. }
function FT12IgnoredText(OtherAddr: LongInt; OtherLast: Word; OwnDir: LongInt): ShortString;
{ Frames the channel dropped for another link address since the last
  look (Seen): added to Count, Last the address of the last of them. }
procedure FT12NoteForeign(Chn: pChnVirt; var Seen: LongWord; var Count: LongInt; var Last: Word);
{ Send once the transmitter is free (bounded wait). }
function FT12SendNow(Chn: pChnVirt; constref R: tSendRecord; Len: Word): tChResult;
function FT12SendNow(Chn: pChnVirt; constref R: tFT12MaxRecord; Len: Word): tChResult;
{ User data octets the longest frame (L = 255) carries on this channel:
  FT12MaxUserData minus its link address octets (ADR=). }
function FT12MaxData(Chn: pChnVirt): Word;
{ Does a secondary's reply of type T and function FC answer primary
  function Req? (IEC 60870-5-2 table of services) }
function FT12ReplyFits(Req: Byte; T: tMessType; FC: Byte): Boolean;
{ The answer to SEND/CONFIRM user data (FC 3) of Len record octets: ACK
  when the application takes it, NACK when it refuses or has no callback. }
function FT12UserDataAnswer(F: tFT12UserDataFunc; Data: Pointer;
  constref R: tFT12MaxRecord; Len: Word): Byte;

implementation

uses
  SysUtils, ChnFT12Codec;

var
  FT12NumName: Word;   { ChNumName(ChnFT1_2.cName) }

function IsFT12Channel(Chn: pChnVirt): Boolean;
begin
  Result := (Chn <> nil) and (Chn^.CH_NumName = FT12NumName);
end;

function FT12FcvOf(FC: Byte): Boolean;
begin
  Result := FC in [FCM_CheckLink, FCM_UserDataReply, FCM_ReqUserData1,
    FCM_ReqUserData2];
end;

function FT12IgnoredText(OtherAddr: LongInt; OtherLast: Word; OwnDir: LongInt): ShortString;
begin
  Result := '';
  if OtherAddr > 0 then
    Result := ' — ' + IntToStr(OtherAddr) + ' frames from link address ' + IntToStr(OtherLast) + ' ignored';
  if OwnDir > 0 then
    Result := Result + ' — ' + IntToStr(OwnDir) + ' frames with this station''s own DIR bit ignored';
end;

procedure FT12NoteForeign(Chn: pChnVirt; var Seen: LongWord; var Count: LongInt; var Last: Word);
var
  N: LongWord;
  A: Word;
begin
  N := pChnFT1_2(Chn)^.ChForeignFrames(A);
  if N <> Seen then
  begin
    Inc(Count, LongInt(N - Seen));
    Seen := N;
    Last := A;
  end;
end;

procedure FT12LinkInit(var Link: tFT12Link; Addr: Word);
begin
  FillChar(Link, SizeOf(Link), 0);
  Link.Addr := Addr;
end;

{ Octets of a fixed frame on this channel (LEN=), as a record length. }
function FT12FixedLen(Chn: pChnVirt): Word;
begin
  Result := cSizeHeadSndMsg + pChnFT1_2(Chn)^.ChFT12Config.FixedLen;
end;

{ Send once the transmitter is free (bounded wait). }
function FT12SendNow(Chn: pChnVirt; constref R: tSendRecord; Len: Word): tChResult;
begin
  Result := ChSendWhenFree(Chn, @R, Len, FT12LinkTimeoutMs);
end;

function FT12SendNow(Chn: pChnVirt; constref R: tFT12MaxRecord; Len: Word): tChResult;
begin
  Result := ChSendWhenFree(Chn, @R, Len, FT12LinkTimeoutMs);
end;

function FT12MaxData(Chn: pChnVirt): Word;
begin
  Result := FT12MaxUserData - pChnFT1_2(Chn)^.ChFT12Config.AddrLen;
end;

{ Does a secondary's reply of type T and function FC answer primary
  function Req? (IEC 60870-5-2 table of services) }
function FT12ReplyFits(Req: Byte; T: tMessType; FC: Byte): Boolean;
begin
  if T = tpSNAK then
    Exit(False);                           { not an IEC 60870-5-2 reply }
  case Req of
    FCM_1stSetTransmit, FCM_1stSetUserFun, FCM_UserDataReply, FCM_CheckLink:
      Result := (T = tpSACK) or (FC in [FCS_Ack, FCS_NackBusy]);
    FCM_ReqReplyAcces, FCM_ReqLinkState:
      Result := (T <> tpSACK) and (FC = FCS_LinkSAccesReq);
    FCM_ReqUserData1, FCM_ReqUserData2:
      Result := (T = tpSACK) or (FC in [FCS_UserData, FCS_DataNotAcces]);
  else
    Result := T <> tpSACK;                { not a standard function: any frame }
  end;
  { "not functioning" / "not implemented" answer anything }
  if (T in [tpShortM, tpLongM]) and (FC in [FCS_NotFunctioning, FCS_NotImplemented]) then
    Result := True;
end;

{ The answer to SEND/CONFIRM user data (FC 3) of Len record octets: ACK
  when the application takes it, NACK when it refuses or has no callback. }
function FT12UserDataAnswer(F: tFT12UserDataFunc; Data: Pointer;
  constref R: tFT12MaxRecord; Len: Word): Byte;
begin
  if Assigned(F) and F(Data, @R.Data[1], Len - cSizeHeadRecMsg, True) then
    Result := FCS_Ack
  else
    Result := FCS_NackBusy;
end;

initialization
  FT12NumName := ChNumName(ChnFT1_2.cName);
end.
