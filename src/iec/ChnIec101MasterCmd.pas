{ ChnIec101MasterCmd - the IEC 60870-5-101 master's command under way:
  its stages (select, execute; delay acquisition, the delay, the time),
  each encoded once as it begins (BeginStage) and sent as it is; its
  start, refused before anything is sent when it cannot be encoded; the
  answers that end a stage (ACT_CON, ACT_TERM, DEACT_CON, the negative
  causes 44..47) matched against what was sent; its end and its text. }
unit ChnIec101MasterCmd;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIec101MasterTypes;

{ The command's name and slave, for its error text. }
function CmdName(const M: tIecMaster): ShortString;
{ The command ends with R; Text says why (R <> res_Ok). }
procedure Finish(var M: tIecMaster; R: tChResult; const Text: ShortString);
{ Stage St begins: its ASDU encoded into M.CmdAsdu. }
function BeginStage(var M: tIecMaster; St: tIecCmdStage; out Err: ShortString): tChResult;
{ Start command Ti with object Obj to slave Addr: False when refused
  (M.Cmd.Result, M.Cmd.Err; nothing sent). }
function Start(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo, WaitTerm, Delay: Boolean): Boolean;
{ Start a command whose element is one number (a qualifier, the test pattern). }
function StartWith(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Value: LongInt;
  WaitTerm: Boolean): Boolean;
{ The program asks for the master's own interrogation under way: True,
  and it is the program's now. }
function JoinAuto(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Q: Byte): Boolean;
{ The stage answered positively (or needs no answer): on to the next, or done. }
procedure StageConfirmed(var M: tIecMaster);
{ An object received from slave index S: does it answer the command? }
procedure MatchCommand(var M: tIecMaster; S: LongInt; const H: tIecAsdu; const O: tIecObject);
{ The current stage went out to slave index S: tell OnSent. }
procedure StageSent(var M: tIecMaster; S: LongInt);

implementation

uses
  SysUtils, ChnVirt;

function CmdName(const M: tIecMaster): ShortString;
begin
  Result := IecTypeName(M.Cmd.Ti);
  if Result = '' then
    Result := 'ASDU type ' + IntToStr(M.Cmd.Ti);
  if IecTypeKind(M.Cmd.Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled,
    ikSetFloat, ikBitsCmd, ikRead] then
    Result := Result + ' IOA ' + IntToStr(M.Cmd.Obj.Ioa);
  if M.Cmd.Slave >= 0 then
    Result := Result + ' to slave ' + IntToStr(M.Slaves[M.Cmd.Slave].Addr);
end;

procedure Finish(var M: tIecMaster; R: tChResult; const Text: ShortString);
begin
  M.Cmd.Phase := cpDone;
  M.Cmd.Result := R;
  if R = res_Ok then
    M.Cmd.Err := ''
  else
    M.Cmd.Err := CmdName(M) + ': ' + Text;
end;

{ Stage St of the command begins: its ASDU is encoded, once, into
  M.CmdAsdu (res_AsduParam ... with Err: it cannot be sent). The delay
  acquisition carries the time it began (SDT), the delay sent the one
  measured; a clock synchronisation after them the time it begins at
  (the slave adds the delay). }
function BeginStage(var M: tIecMaster; St: tIecCmdStage; out Err: ShortString): tChResult;
var
  O: tIecObject;
begin
  M.Cmd.Stage := St;
  M.Cmd.Phase := cpSend;
  O := M.Cmd.Obj;
  M.StageTi := M.Cmd.Ti;
  M.StageCot := Cot_Activation;
  case St of
    stDelayAct:
      begin
        M.StageTi := C_CD_NA_1;
        O := IecObject(0);
        O.Elapsed := ChMsTick mod 60000;
      end;
    stDelaySend:
      begin
        M.StageTi := C_CD_NA_1;
        M.StageCot := Cot_Spontaneous;
        O := IecObject(0);
        O.Elapsed := M.Cmd.DelayMs;
      end;
    stSelect: O.Select := True;
    stMain:
      begin
        { the execute after a select; alone, what the caller gave (a
          gateway passes a control centre's select on as a select) }
        O.Select := O.Select and not M.Cmd.Sbo;
        if M.Cmd.Ti = C_RD_NA_1 then
          M.StageCot := Cot_Request
        else if M.Cmd.Deact then
          M.StageCot := Cot_Deactivation
        else if (M.Cmd.Ti = C_CS_NA_1) and M.Cmd.Delay then
        begin
          O.Time := IecTimeFromDateTime(Now);
          M.Cmd.Obj.Time := O.Time;
        end;
      end;
  end;
  M.StageObj := O;
  Result := IecEncodeOne(M.Params, M.StageTi, M.StageCot, M.Cmd.Ca, O, M.CmdAsdu, M.CmdLen, Err);
end;

function Start(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; const Obj: tIecObject;
  Sbo, WaitTerm, Delay: Boolean): Boolean;
var
  E: ShortString;
  R: tChResult;
begin
  if not IecCommandDone(M) then
  begin
    { keep the command under way; say why this one was refused }
    M.Cmd.Err := IecTypeName(Ti) + ': a command is under way (' + CmdName(M) + ')';
    Exit(False);
  end;
  FillChar(M.Cmd, SizeOf(M.Cmd), 0);
  M.Cmd.Ti := Ti;
  M.Cmd.Ca := Ca;
  M.Cmd.Obj := Obj;
  M.Cmd.Sbo := Sbo;
  M.Cmd.WaitTerm := WaitTerm;
  M.Cmd.Delay := Delay;
  M.Cmd.Slave := IecMasterSlave(M, Addr);
  if M.Cmd.Slave < 0 then
  begin
    Finish(M, res_IecNoSlave, 'no slave with link address ' + IntToStr(Addr));
    Exit(False);
  end;
  { a command that does not encode is refused now. The first stage is
    checked: the stages after it (the execute after its select, the delay
    and the time after a delay acquisition) have the same common address
    and object, their own values taken as they come }
  if Sbo then
    R := BeginStage(M, stSelect, E)
  else if Delay then
    R := BeginStage(M, stDelayAct, E)
  else
    R := BeginStage(M, stMain, E);
  if R <> res_Ok then
  begin
    Finish(M, R, E);
    Exit(False);
  end;
  M.Cmd.Result := res_Ok;
  M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
  Result := True;
end;

{ A command whose element is one number (a qualifier, the test pattern). }
function StartWith(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Value: LongInt;
  WaitTerm: Boolean): Boolean;
var
  O: tIecObject;
begin
  O := IecObject(0);
  O.Int := Value;
  Result := Start(M, Addr, Ca, Ti, O, False, WaitTerm, False);
end;

{ The master's own interrogation after an end of initialisation is the
  one the program asks for: it takes it over. }
function JoinAuto(var M: tIecMaster; Addr, Ca: Word; Ti: Byte; Q: Byte): Boolean;
begin
  Result := M.Cmd.Auto and not IecCommandDone(M) and (M.Cmd.Ti = Ti) and
    (M.Cmd.Obj.Int = Q) and (M.Cmd.Ca = Ca) and (M.Slaves[M.Cmd.Slave].Addr = Addr);
  if Result then
    M.Cmd.Auto := False;
end;

{ The stage answered positively: on to the next, or done. }
procedure StageConfirmed(var M: tIecMaster);
var
  R: tChResult;
  E: ShortString;
begin
  R := res_Ok;
  case M.Cmd.Stage of
    stDelayAct:
      begin
        M.Cmd.DelayMs := (ChMsTick - M.Cmd.SentAt) div 2;
        R := BeginStage(M, stDelaySend, E);
      end;
    stDelaySend, stSelect:
      R := BeginStage(M, stMain, E);
  else
    if M.Cmd.WaitTerm then
      M.Cmd.Phase := cpTerm
    else
      Finish(M, res_Ok, '');
  end;
  if R <> res_Ok then
    Finish(M, R, E);                    { cannot happen: the first stage encoded }
end;

{ Does a command of type Ti carry the S/E bit? }
function HasSelectBit(Ti: Byte): Boolean;
begin
  Result := IecTypeKind(Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat];
end;

{ An ASDU from slave index S: does it answer the command? }
procedure MatchCommand(var M: tIecMaster; S: LongInt; const H: tIecAsdu; const O: tIecObject);
var
  Ti: Byte;
  Want: tIecObject;
  What: ShortString;
begin
  if (M.Cmd.Slave <> S) or not (M.Cmd.Phase in [cpConfirm, cpTerm]) then
    Exit;
  Ti := M.StageTi;
  Want := M.StageObj;
  if H.Ca <> M.Cmd.Ca then
    Exit;
  if (M.Cmd.Ti = C_RD_NA_1) and (M.Cmd.Stage = stMain) and (H.Cot = Cot_Request)
    and (O.Ioa = Want.Ioa) and (H.Ti <> C_RD_NA_1) then
  begin
    Finish(M, res_Ok, '');
    Exit;
  end;
  if (H.Ti <> Ti) or (O.Ioa <> Want.Ioa) then
    Exit;
  { a confirmation mirrors the command: the S/E bit of this stage (an
    execute's ACT_CON confirms no select), and T = 0 (this master sends no
    test-mode commands) }
  if H.Test or (HasSelectBit(Ti) and (O.Select <> Want.Select)) then
    Exit;
  What := 'COT ' + IntToStr(H.Cot) + ' ' + IecCotName(H.Cot);
  case H.Cot of
    Cot_ActCon, Cot_DeactCon:
      if (H.Cot = Cot_DeactCon) <> M.Cmd.Deact then
        Exit                             { the confirmation of the other cause }
      else if H.Negative then
        Finish(M, res_IecNegative, BoolToStr(M.Cmd.Deact, 'negative DEACT_CON', 'negative ACT_CON'))
      else if M.Cmd.Phase = cpConfirm then
        StageConfirmed(M);
    Cot_ActTerm:
      { before this command's ACT_CON a termination is the last one's (it
        follows its confirmation in the slave's queue): not an answer }
      if M.Cmd.Phase <> cpTerm then
        Exit
      else if H.Negative then
        Finish(M, res_IecNegative, 'negative ACT_TERM')
      else
        Finish(M, res_Ok, '');
    Cot_UnknownType: Finish(M, res_IecUnknownType, 'the slave does not know the type (' + What + ')');
    Cot_UnknownCause: Finish(M, res_IecUnknownCot, 'the slave does not know the cause (' + What + ')');
    Cot_UnknownCa: Finish(M, res_IecUnknownCa, 'the slave does not know common address '
      + IntToStr(H.Ca) + ' (' + What + ')');
    Cot_UnknownIoa: Finish(M, res_IecUnknownIoa, 'the slave does not know IOA '
      + IntToStr(O.Ioa) + ' (' + What + ')');
  end;
end;

{ The current stage went out to slave index S: tell OnSent. }
procedure StageSent(var M: tIecMaster; S: LongInt);
var
  H: tIecAsdu;
begin
  if not Assigned(M.OnSent) or M.Cmd.Raw then
    Exit;
  FillChar(H, SizeOf(H), 0);
  H.Ti := M.StageTi;
  H.Count := 1;
  H.Cot := M.StageCot;
  H.Ca := M.Cmd.Ca;
  M.OnSent(M.Data, M.Slaves[S].Addr, H, M.StageObj);
end;

end.
