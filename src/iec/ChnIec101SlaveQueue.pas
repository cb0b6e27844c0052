{ ChnIec101SlaveQueue - the IEC 60870-5-101 slave's class 1 and class 2
  queues of ASDUs waiting for the master, and what goes into them: an
  object encoded, a received ASDU mirrored as its answer (ACT_CON,
  DEACT_CON, the negative causes), a malformed one counted instead. }
unit ChnIec101SlaveQueue;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIec101SlaveTypes;

{ Len octets of Buf at the end of Q; False when Q is full. }
function QueuePut(var Q: tIecQueue; const Buf: array of Byte; Len: Word): Boolean;
{ The ASDU at the head of Q is gone. }
procedure QueueDrop(var Q: tIecQueue);
{ Reset of pending information with time tag (QRP 2): the queued
  spontaneous ASDUs of time-tagged types go; confirmations, terminations,
  answers to reads and untagged events stay, in their order. }
procedure QueueDropTaggedEvents(var Q: tIecQueue);
{ An ASDU into class 1 (Overflows counts one that did not fit). }
procedure Queue1(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word);
{ The longest ASDU the link takes. }
function MaxAsdu(const S: tIecSlaveStation): Word;
{ Encode one object of type Ti with cause Cot into the class 1 queue. }
function QueueObject(var S: tIecSlaveStation; Ti, Cot: Byte; const O: tIecObject): tChResult;
{ A malformed ASDU: counted, kept in LastBad, told to OnBad; no answer. }
procedure Bad(var S: tIecSlaveStation; const Err: ShortString);
{ The received ASDU mirrored with Cot (negative or not) into class 1. }
procedure Answer(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word; Cot: Byte; Negative: Boolean);
{ The confirmation cause of an activation (7) or deactivation (9). }
function ActOrDeact(Cot: Byte): Byte;

implementation

uses
  Math, ChnFT12Link, ChnIec104Codec;

function QueuePut(var Q: tIecQueue; const Buf: array of Byte; Len: Word): Boolean;
var
  Slot: Integer;
begin
  Result := (Q.Count < IecSlaveQueueLen) and (Len <= IecMaxAsdu);
  if not Result then
    Exit;
  Slot := (Q.Head + Q.Count) mod IecSlaveQueueLen;
  Q.Items[Slot].Len := Len;
  Move(Buf[0], Q.Items[Slot].Data[0], Len);
  Inc(Q.Count);
end;

procedure QueueDrop(var Q: tIecQueue);
begin
  Q.Head := (Q.Head + 1) mod IecSlaveQueueLen;
  Dec(Q.Count);
end;

{ Reset of pending information with time tag (QRP 2): the queued
  spontaneous ASDUs of time-tagged types go; confirmations, terminations,
  answers to reads and untagged events stay, in their order. }
procedure QueueDropTaggedEvents(var Q: tIecQueue);
var
  Old: tIecQueue;
  I: Integer;
begin
  Old := Q;
  Q.Head := 0;
  Q.Count := 0;
  for I := 0 to Old.Count - 1 do
    with Old.Items[(Old.Head + I) mod IecSlaveQueueLen] do
      if (Len < 3) or (Data[2] and $3F <> Cot_Spontaneous) or (IecTypeTime(Data[0]) = tkNone) then
        QueuePut(Q, Data, Len);
end;

procedure Queue1(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word);
begin
  if not QueuePut(S.Class1, Buf, Len) then
    Inc(S.Overflows);
end;

{ The longest ASDU the link takes: IEC 104's APDU of 253 octets less
  its control field (249); FT 1.2's frame of L = 255 less the control
  octet and the link address (253 with ADR=1; no ASDU exceeds IecMaxAsdu). }
function MaxAsdu(const S: tIecSlaveStation): Word;
begin
  if S.Over104 then
    Result := Apci104MaxAsdu
  else
    Result := Min(IecMaxAsdu, FT12MaxData(S.Chn));
end;

{ Encode one object of type Ti with cause Cot into the class 1 queue. }
function QueueObject(var S: tIecSlaveStation; Ti, Cot: Byte; const O: tIecObject): tChResult;
var
  Buf: array[0..IecMaxAsdu - 1] of Byte;
  Len: Word;
  Err: ShortString;
begin
  Result := IecEncodeOne(S.Params, Ti, Cot, S.Ca, O, Buf, Len, Err);
  if Result <> res_Ok then
    Exit;
  if not QueuePut(S.Class1, Buf, Len) then
  begin
    Inc(S.Overflows);
    Result := res_Busy;
  end;
end;

procedure Bad(var S: tIecSlaveStation; const Err: ShortString);
begin
  Inc(S.BadAsdus);
  S.LastBad := Err;
  if Assigned(S.OnBad) then
    S.OnBad(S.Data, Err);
end;

{ The received ASDU mirrored with Cot (negative or not) into class 1. }
procedure Answer(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word; Cot: Byte; Negative: Boolean);
var
  Out: array[0..IecMaxAsdu - 1] of Byte;
begin
  if (Len = 0) or (Len > IecMaxAsdu) then
    Exit;
  Move(Buf[0], Out[0], Len);
  IecSetCot(Out, Len, Cot, Negative);
  if Negative then
    Inc(S.Negatives);
  Queue1(S, Out, Len);
end;

{ The confirmation cause of an activation (7) or deactivation (9). }
function ActOrDeact(Cot: Byte): Byte;
begin
  if Cot = Cot_Deactivation then
    Result := Cot_DeactCon
  else
    Result := Cot_ActCon;
end;
end.
