{ ChnIec101SlaveCommands - the IEC 60870-5-101 slave's commands (types
  45..51, 58..64) to its command points: select before operate (the
  selection, its timeout, an execute that must carry what was selected,
  deactivation), the test bit, the program's OnCommand, and the deferred
  confirmation (IecSlaveDefer, IecSlaveConfirm) for a program whose
  device must confirm first. }
unit ChnIec101SlaveCommands;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIec101SlaveTypes;

{ A command received (H, O decoded from Buf), COT 6 or 8. }
procedure TakeCommand(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);
{ The public calls of ChnIec101Slave, which documents them. }
function IecSlaveDefer(var S: tIecSlaveStation): LongWord;
function IecSlaveConfirm(var S: tIecSlaveStation; Ticket: LongWord; Ok: Boolean): tChResult;
function IecSlaveDeferred(const S: tIecSlaveStation): LongInt;

implementation

uses
  ChnVirt, ChnIec101SlaveQueue, ChnIec101SlavePoints;

{ Does an execute carry what was selected (value, qualifier)? }
function SameCommand(const Sel, O: tIecObject): Boolean;
begin
  Result := (Sel.Int = O.Int) and (Sel.Bits = O.Bits) and (Sel.Number = O.Number) and (Sel.Qu = O.Qu);
end;

{ The end of an accepted (Ok) or refused command to point I: the
  selection, the command point's value, the ACT_CON. }
procedure EndCommand(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  I: LongInt; const O: tIecObject; Select, Ok: Boolean);
var
  Ti: Byte;
begin
  Ti := S.Points[I].Ti;
  if Ok then
  begin
    Inc(S.Commands);
    if Select then
    begin
      S.SelActive := True;
      S.SelTi := Ti;
      S.SelIoa := O.Ioa;
      S.SelUntil := ChMsTick + QWord(S.SelectMs);
      S.SelObj := O;
    end
    else
    begin
      if S.SelActive and (S.SelTi = Ti) and (S.SelIoa = O.Ioa) then
        S.SelActive := False;
      { the command point keeps the last value executed }
      S.Points[I].Obj.Int := O.Int;
      S.Points[I].Obj.Bits := O.Bits;
      S.Points[I].Obj.Number := O.Number;
      S.Points[I].Obj.Qu := O.Qu;
    end;
  end
  else
    Inc(S.Refused);
  Answer(S, Buf, Len, Cot_ActCon, not Ok);
end;

procedure TakeCommand(var S: tIecSlaveStation; const Buf: array of Byte; Len: Word;
  const H: tIecAsdu; const O: tIecObject);
var
  I: Integer;
  Ok, Select: Boolean;
  D: ^tIecDeferred;
begin
  I := FindCommand(S, O.Ioa, H.Ti);
  if I < 0 then
  begin
    Answer(S, Buf, Len, Cot_UnknownIoa, True);
    Exit;
  end;
  Select := O.Select and (IecTypeKind(H.Ti) <> ikBitsCmd);
  if H.Test then
  begin
    { T = 1: generated under test conditions, not meant to change the
      process - never executed, refused (negative, T kept) }
    Inc(S.Refused);
    Answer(S, Buf, Len, ActOrDeact(H.Cot), True);
    Exit;
  end;
  if H.Cot = Cot_Deactivation then
  begin
    { ends a selection of this object }
    Ok := S.SelActive and (S.SelTi = H.Ti) and (S.SelIoa = O.Ioa);
    if Ok then
      S.SelActive := False;
    Answer(S, Buf, Len, Cot_DeactCon, not Ok);
    Exit;
  end;
  if not Select and S.SelActive and (S.SelTi = H.Ti) and (S.SelIoa = O.Ioa) and
     ((ChMsTick > S.SelUntil) or not SameCommand(S.SelObj, O)) then
  begin
    { the execute of a selection whose time is up, or with another value
      or qualifier than the one selected }
    S.SelActive := False;
    Inc(S.Refused);
    Answer(S, Buf, Len, Cot_ActCon, True);
    Exit;
  end;
  S.DeferSlot := -1;
  S.InCommand := True;
  Ok := not Assigned(S.OnCommand) or S.OnCommand(S.Data, H, O);
  S.InCommand := False;
  if S.DeferSlot >= 0 then
  begin
    D := @S.Deferred[S.DeferSlot];
    if Ok then
    begin
      { the confirmation waits for IecSlaveConfirm }
      D^.Point := I;
      D^.Obj := O;
      D^.Select := Select;
      D^.Asdu.Len := Len;
      Move(Buf[0], D^.Asdu.Data[0], Len);
      Exit;
    end;
    D^.Ticket := 0;                  { refused all the same: at once }
  end;
  EndCommand(S, Buf, Len, I, O, Select, Ok);
end;

function IecSlaveDefer(var S: tIecSlaveStation): LongWord;
var
  I: LongInt;
begin
  Result := 0;
  if not S.InCommand or (S.DeferSlot >= 0) then
    Exit;
  for I := 0 to IecSlaveMaxDeferred - 1 do
    if S.Deferred[I].Ticket = 0 then
    begin
      Inc(S.NextTicket);
      if S.NextTicket = 0 then
        S.NextTicket := 1;
      S.Deferred[I].Ticket := S.NextTicket;
      S.DeferSlot := I;
      Exit(S.NextTicket);
    end;
end;

function IecSlaveConfirm(var S: tIecSlaveStation; Ticket: LongWord; Ok: Boolean): tChResult;
var
  I: LongInt;
begin
  if Ticket <> 0 then
    for I := 0 to IecSlaveMaxDeferred - 1 do
      if S.Deferred[I].Ticket = Ticket then
      begin
        S.Deferred[I].Ticket := 0;
        EndCommand(S, S.Deferred[I].Asdu.Data, S.Deferred[I].Asdu.Len, S.Deferred[I].Point,
          S.Deferred[I].Obj, S.Deferred[I].Select, Ok);
        Exit(res_Ok);
      end;
  Result := res_BadParam;
end;

function IecSlaveDeferred(const S: tIecSlaveStation): LongInt;
var
  I: LongInt;
begin
  Result := 0;
  for I := 0 to IecSlaveMaxDeferred - 1 do
    if S.Deferred[I].Ticket <> 0 then
      Inc(Result);
end;
end.
