{ ChnIecTransport - the seam between the IEC 60870-5-101 application
  procedures (ChnIec101Master, ChnIec101Slave) and a transport that
  carries ASDUs both ways on its own: an FT 1.2 balanced link
  (ChnFT12Link's tFT12Balanced on a tChnFT1_2 with MS=OFF) or an IEC
  60870-5-104 connection (NAM=IEC104). One application layer, two
  transports: the helpers call these five routines and never ask which.

  Unbalanced FT 1.2 (link polling, classes) is not a transport of this
  kind and stays in the helpers. }
unit ChnIecTransport;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Balanced, ChnIec104, ChnIec104Codec;

type
  tIecTransportKind = (itFT12Balanced, itIec104);

  tIecTransport = record
    Kind      : tIecTransportKind;
    Chn       : pChnVirt;
    Bal       : tFT12Balanced;     {< itFT12Balanced }
    { itIec104: the ASDU received, kept while OnUserData has no room }
    RxBuf     : array[0..Apci104MaxAsdu - 1] of Byte;
    RxLen     : Word;
    RxHeld    : Boolean;
    OnUserData: tFT12UserDataFunc; {< each ASDU received; False: no room now }
    Data      : Pointer;
  end;

{ What Chn is to an IEC 101 helper (the master and the slave set up on
  it the same way): Over104 on a NAM=IEC104 stack; Balanced there and on
  a tChnFT1_2 with MS=OFF; Primary: the tChnFT1_2's MAS=MASTER (False on
  IEC 104). res_WrongLayer when Chn is neither. }
function IecLinkKind(Chn: pChnVirt; out Over104, Balanced, Primary: Boolean): tChResult;
{ IecTransportInit, then (when it worked) IecTransportHandler: a balanced
  helper's set-up. }
function IecTransportStart(var T: tIecTransport; Chn: pChnVirt; F: tFT12UserDataFunc;
  Data: Pointer): tChResult;
{ The transport of Chn: a balanced tChnFT1_2 or a NAM=IEC104 stack.
  res_WrongLayer (neither), res_BadMessage (FT 1.2 with MS=ON). T must not
  move afterwards (the channel receives into it). }
function IecTransportInit(var T: tIecTransport; Chn: pChnVirt): tChResult;
{ The helper that takes the ASDUs received. }
procedure IecTransportHandler(var T: tIecTransport; F: tFT12UserDataFunc; Data: Pointer);
{ True when Chn is an IEC104 stack. }
function IecTransportIs104(Chn: pChnVirt): Boolean;
{ Take what was received (ASDUs to OnUserData) and run the timers; True
  when something was taken. }
function IecTransportStep(var T: tIecTransport): Boolean;
{ ASDUs can be exchanged now (link available / data transfer started). }
function IecTransportUp(const T: tIecTransport): Boolean;
{ IecTransportSend would take an ASDU now. IEC 104 takes them while data
  transfer is stopped too (queued for the next STARTDT). }
function IecTransportRoom(const T: tIecTransport): Boolean;
{ Queue one ASDU (FT 1.2: SEND/CONFIRM). }
function IecTransportSend(var T: tIecTransport; Buf: PByte; Len: Word): tChResult;
{ Nothing waiting to go out and nothing unacknowledged. }
function IecTransportQuiet(const T: tIecTransport): Boolean;
{ ms a caller may wait (ChnWaitAny) before the next step, at most Limit. }
function IecTransportWaitMs(const T: tIecTransport; Limit: LongInt): LongInt;

implementation

function IecTransportIs104(Chn: pChnVirt): Boolean;
begin
  Result := (Chn <> nil) and (Chn^.CH_Type = ChnIec104.cName);
end;

function IecLinkKind(Chn: pChnVirt; out Over104, Balanced, Primary: Boolean): tChResult;
begin
  Over104 := IecTransportIs104(Chn);
  Balanced := Over104;
  Primary := False;
  if Over104 then
    Exit(res_Ok);
  if (Chn = nil) or (Chn^.CH_Type <> ChnFT1_2.cName) then
    Exit(res_WrongLayer);
  Balanced := pChnFT1_2(Chn)^.ChFT12Config.Balanced;
  Primary := pChnFT1_2(Chn)^.ChFT12Config.Primary;
  Result := res_Ok;
end;

function IecTransportStart(var T: tIecTransport; Chn: pChnVirt; F: tFT12UserDataFunc;
  Data: Pointer): tChResult;
begin
  Result := IecTransportInit(T, Chn);
  if Result = res_Ok then
    IecTransportHandler(T, F, Data);
end;

function IecTransportInit(var T: tIecTransport; Chn: pChnVirt): tChResult;
begin
  T.Chn := Chn;
  T.RxLen := 0;
  T.RxHeld := False;
  if IecTransportIs104(Chn) then
  begin
    T.Kind := itIec104;
    Chn^.ChReceiveBuffer(@T.RxBuf, SizeOf(T.RxBuf));
    Result := res_Ok;
  end
  else
  begin
    T.Kind := itFT12Balanced;
    Result := FT12BalancedInit(T.Bal, Chn);
  end;
end;

procedure IecTransportHandler(var T: tIecTransport; F: tFT12UserDataFunc; Data: Pointer);
begin
  T.OnUserData := F;
  T.Data := Data;
  T.Bal.OnUserData := F;
  T.Bal.Data := Data;
end;

function Step104(var T: tIecTransport): Boolean;
var
  Len: Word;
begin
  Result := False;
  if not T.RxHeld then
  begin
    Len := 0;
    T.Chn^.ChReceive(Len);
    if (T.Chn^.ChReceiveResult <> res_Ok) or (Len = 0) then
      Exit;
    T.RxLen := Len;
    T.RxHeld := True;
  end;
  Result := True;
  if not Assigned(T.OnUserData) or T.OnUserData(T.Data, @T.RxBuf[0], T.RxLen, True) then
    T.RxHeld := False;
end;

function IecTransportStep(var T: tIecTransport): Boolean;
begin
  if T.Kind = itIec104 then
    Result := Step104(T)
  else
    Result := FT12BalancedStep(T.Bal);
end;

function IecTransportUp(const T: tIecTransport): Boolean;
begin
  if T.Kind = itIec104 then
    Result := pChnIec104(T.Chn)^.ChDataStarted
  else
    Result := T.Bal.State = bsAvailable;
end;

function IecTransportRoom(const T: tIecTransport): Boolean;
begin
  if T.Kind = itIec104 then
    Result := pChnIec104(T.Chn)^.ChQueueRoom > 0
  else
    Result := (T.Bal.State = bsAvailable) and (T.Bal.QCount < FT12BalQueueLen);
end;

function IecTransportSend(var T: tIecTransport; Buf: PByte; Len: Word): tChResult;
begin
  if T.Kind = itIec104 then
  begin
    T.Chn^.ChSend(Buf, Len);
    Result := T.Chn^.ChSendResult;
  end
  else
    Result := FT12BalancedSend(T.Bal, Buf, Len, True);
end;

function IecTransportQuiet(const T: tIecTransport): Boolean;
begin
  if T.Kind = itIec104 then
    Result := (pChnIec104(T.Chn)^.ChQueued = 0) and not T.RxHeld
  else
    Result := FT12BalancedQuiet(T.Bal);
end;

function IecTransportWaitMs(const T: tIecTransport; Limit: LongInt): LongInt;
var
  Due, Now_: QWord;
begin
  Result := Limit;
  if T.Kind <> itIec104 then
    Exit;
  if T.RxHeld then
    Exit(0);
  Now_ := ChMsTick;
  Due := pChnIec104(T.Chn)^.ChNextDue;
  if Due <= Now_ then
    Result := 0
  else if Due - Now_ < QWord(Limit) then
    Result := Due - Now_;
end;

end.
