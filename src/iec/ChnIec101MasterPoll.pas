{ ChnIec101MasterPoll - how the IEC 60870-5-101 master serves its line.
  Unbalanced: the polling scheduler (whose turn, what a slave is due for:
  link status, reset, a command, a class 1 or class 2 poll; a dead
  slave's back-off) and the link service under way, on ChnFT12Link's
  stepped primary. Balanced and IEC 104: the transport, the command's
  ASDU handed to it when it has room, the peer's ASDUs taken as they come. }
unit ChnIec101MasterPoll;

{$I chn.inc}

interface

uses
  ChnIec101MasterTypes;

{ One step of an unbalanced master: the service under way taken further,
  or the next one due started. True when something was done. }
function StepUnbalanced(var M: tIecMaster): Boolean;
{ One step of a balanced (or IEC 104) master. }
function StepBalanced(var M: tIecMaster): Boolean;
{ The transport's user data handler (Data: the master). }
function OnBalancedData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;

implementation

uses
  SysUtils, ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnIecTransport,
  ChnIec101MasterCmd, ChnIec101MasterInbound;

{ The one place that drives an FT 1.2 primary service. LinkStart starts
  FC with Len octets of user data (an ASDU) to slave S for Job; LinkStep
  takes what has arrived, without waiting, and is True once the service is
  over (M.LinkResult, the reply in M.Rep/M.RepLen): ChnFT12Link's stepped
  primary (FT12PrimaryStart/Step). }
procedure LinkStart(var M: tIecMaster; S: LongInt; Job: tIecLinkJob; FC: Byte;
  const Asdu: array of Byte; Len: Word; Retries: LongInt);
var
  Req: tSendRecord;
begin
  FillChar(Req, SizeOf(Req), 0);
  if Len > 0 then
  begin
    Req.MessType := tpLongM;
    Move(Asdu[0], Req.Data[1], Len);
  end
  else
  begin
    Req.MessType := tpShortM;
    Len := pChnFT1_2(M.Chn)^.ChFT12Config.FixedLen;   { a fixed frame: LEN= zero octets }
  end;
  Req.FC := FC;
  M.Job := Job;
  M.JobSlave := S;
  { False: nothing sent, the service is over at once (Prim.Result says why) }
  FT12PrimaryStart(M.Prim, M.Chn, M.Slaves[S].Link, Req, cSizeHeadSndMsg + Len, M.TimeoutMs, Retries);
end;

function LinkStep(var M: tIecMaster): Boolean;
begin
  Result := (M.Job <> ljNone) and FT12PrimaryStep(M.Prim);
  if Result then
  begin
    M.LinkResult := M.Prim.Result;
    M.RepLen := M.Prim.RepLen;
    if M.RepLen > 0 then
      M.Rep := M.Prim.Rep;
  end;
end;

procedure SlaveFailed(var M: tIecMaster; S: Integer; R: tChResult);
var
  Sl: ^tIecSlave;
  E: ShortString;
begin
  Sl := @M.Slaves[S];
  Inc(Sl^.Failures);
  if (R <> res_Timeout) and (R <> res_BadMessage) then
    M.LineResult := R;                   { the channel itself failed }
  if R = res_BadMessage then
  begin
    Sl^.State := isOffline;              { an answer that does not fit: set the link up again }
    Exit;
  end;
  { a slave that failed again before it answered a poll (dead, or set up
    again after it) waits twice as long; a healthy one just died }
  if not Sl^.Probation then
    Inc(Sl^.Deaths)
  else if Sl^.BackoffMs < M.DeadMaxMs then
    Sl^.BackoffMs := Sl^.BackoffMs * 2;
  Sl^.Probation := True;
  if Sl^.BackoffMs > M.DeadMaxMs then
    Sl^.BackoffMs := M.DeadMaxMs;
  Sl^.State := isDead;
  Sl^.RetryAt := ChMsTick + QWord(Sl^.BackoffMs);
  if (M.Cmd.Slave = S) and not IecCommandDone(M) then
  begin
    E := IecLineShowed(M, S);
    if E <> '' then
      E := ': no answer from link address ' + IntToStr(Sl^.Addr) + E;
    Finish(M, res_Timeout, 'slave does not answer (' + ChResultText(R) + ')' + E);
  end;
end;

{ A class poll or a command was answered: the slave serves again. (A
  status or reset answer alone does not count: a slave may answer those
  and never a poll.) }
procedure SlaveServes(var M: tIecMaster; S: Integer);
begin
  M.Slaves[S].Probation := False;
  M.Slaves[S].BackoffMs := M.DeadMinMs;
end;

{ Is slave S due for a service now? }
function Due(const M: tIecMaster; S: Integer; Now_: QWord): Boolean;
begin
  with M.Slaves[S] do
    case State of
      isDead: Result := Now_ >= RetryAt;
      isOnline: Result := (Now_ >= NextPoll) or ((M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend));
    else
      Result := True;
    end;
end;

{ Start the service slave S is due for. }
procedure Serve(var M: tIecMaster; S: LongInt);
var
  Buf: array[0..0] of Byte;
  Sl: ^tIecSlave;
  Retries: LongInt;
begin
  Sl := @M.Slaves[S];
  Buf[0] := 0;                          { fixed frames carry none of it }
  Retries := M.Retries;
  if Sl^.Probation then
    Retries := 0;                       { one try: the others wait one timeout only }
  case Sl^.State of
    isOffline, isDead: LinkStart(M, S, ljStatus, FCM_ReqLinkState, Buf, 0, Retries);
    isLinkStatus: LinkStart(M, S, ljReset, FCM_1stSetTransmit, Buf, 0, Retries);
  else
    if (M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend) then
    begin
      M.Cmd.SentAt := ChMsTick;
      LinkStart(M, S, ljCommand, FCM_UserDataReply, M.CmdAsdu, M.CmdLen, Retries);
    end
    else
    begin
      Sl^.PolledAt := ChMsTick;
      if Sl^.Link.Acd then
        LinkStart(M, S, ljClass1, FCM_ReqUserData1, Buf, 0, Retries)
      else
        LinkStart(M, S, ljClass2, FCM_ReqUserData2, Buf, 0, Retries);
    end;
  end;
end;

{ The turn goes to the slave after S. }
procedure PassTurn(var M: tIecMaster; S: LongInt);
begin
  M.Turn := (S + 1) mod M.SlaveCount;
  M.Run := 0;
end;

{ The service under way is over: act on its answer. }
procedure Complete(var M: tIecMaster);
var
  S: LongInt;
  Sl: ^tIecSlave;
  Job: tIecLinkJob;
  Data: Boolean;
begin
  S := M.JobSlave;
  Sl := @M.Slaves[S];
  Job := M.Job;
  M.Job := ljNone;
  if M.LinkResult <> res_Ok then
  begin
    SlaveFailed(M, S, M.LinkResult);
    if Job <> ljCommand then
      PassTurn(M, S);
    Exit;
  end;
  Data := False;
  case Job of
    ljStatus:
      Sl^.State := isLinkStatus;        { dead or not: set its link up (again) }
    ljReset:
      begin
        Inc(Sl^.Resets);
        Sl^.State := isOnline;
        Sl^.NextPoll := 0;
      end;
    ljCommand:
      if (M.Cmd.Slave = S) and (M.Cmd.Phase = cpSend)
        and ((M.Rep.MessType = tpSACK) or (M.Rep.FC = FCS_Ack)) then
      begin
        SlaveServes(M, S);
        Inc(Sl^.Commands);
        StageSent(M, S);
        if (M.Cmd.Stage = stDelaySend) or M.Cmd.Raw then
          StageConfirmed(M)             { the delay is no activation: nothing confirms it }
        else
        begin
          M.Cmd.Phase := cpConfirm;
          M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
        end;
      end;
      { a NACK (busy): sent again at the next turn }
    ljClass1, ljClass2:
      begin
        SlaveServes(M, S);
        if Job = ljClass1 then
          Inc(Sl^.Class1)
        else
          Inc(Sl^.Class2);
        Data := (M.Rep.MessType = tpLongM) and (M.Rep.FC = FCS_UserData) and (M.RepLen > cSizeHeadRecMsg);
        if Data then
          TakeAsdu(M, S, M.Rep.Data, M.RepLen - cSizeHeadRecMsg);
        { more data (ACD, or class 2 had some): polled again at once;
          none: not before CycleMs after this poll }
        Data := Data or Sl^.Link.Acd;
        if Data then
          Sl^.NextPoll := 0
        else
          Sl^.NextPoll := Sl^.PolledAt + QWord(M.CycleMs);
      end;
  end;
  if Sl^.Link.Acd then
    Sl^.NextPoll := 0;                  { class 1 waits (a command's ACT_CON ...) }
  { a command jumps the queue: the turn stays where it was }
  if Job = ljCommand then
    Exit;
  { a slave with data keeps the turn for PollBurst services at most; the
    link set up (status, reset) takes a turn each }
  if S <> M.Turn then
  begin
    M.Turn := S;                        { the ones before it had nothing due }
    M.Run := 0;
  end;
  Inc(M.Run);
  if not Data or (M.Run >= M.PollBurst) then
    PassTurn(M, S);
end;

function StepUnbalanced(var M: tIecMaster): Boolean;
var
  I, S: LongInt;
  T: QWord;
begin
  Result := False;
  if M.Job <> ljNone then
  begin
    { a service under way: done yet? }
    if LinkStep(M) then
    begin
      Complete(M);
      Result := True;
    end;
    Exit;
  end;
  if M.SlaveCount = 0 then
    Exit;
  T := ChMsTick;
  { the command's slave first while it has something to send }
  S := -1;
  if (M.Cmd.Phase = cpSend) and (M.Cmd.Slave >= 0) and Due(M, M.Cmd.Slave, T) then
    S := M.Cmd.Slave
  else
    for I := 0 to M.SlaveCount - 1 do
      if Due(M, (M.Turn + I) mod M.SlaveCount, T) then
      begin
        S := (M.Turn + I) mod M.SlaveCount;
        Break;
      end;
  if S < 0 then
    Exit;
  Serve(M, S);
  if (M.Job <> ljNone) and LinkStep(M) then
    Complete(M);
  Result := True;
end;

{- ------------------------------------------------------------ balanced }

function OnBalancedData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  M: pIecMaster;
begin
  M := pIecMaster(Data);
  if Len > 0 then
    TakeAsdu(M^, 0, PByteArray(Buf)^[0..Len - 1], Len)
  else
    TakeAsdu(M^, 0, M^.Rep.Data, 0);
  Result := True;
end;

function StepBalanced(var M: tIecMaster): Boolean;
var
  R: tChResult;
begin
  Result := IecTransportStep(M.Link);
  if M.Chn^.ChResult <> res_Ok then
    M.LineResult := M.Chn^.ChResult;
  if IecTransportUp(M.Link) then
    M.Slaves[0].State := isOnline
  else
    M.Slaves[0].State := isOffline;
  if (M.Cmd.Phase = cpSend) and IecTransportUp(M.Link) and IecTransportRoom(M.Link) then
  begin
    R := IecTransportSend(M.Link, @M.CmdAsdu, M.CmdLen);
    if R = res_Ok then
    begin
      Inc(M.Slaves[0].Commands);
      StageSent(M, 0);
      M.Cmd.SentAt := ChMsTick;
      if (M.Cmd.Stage = stDelaySend) or M.Cmd.Raw then
        StageConfirmed(M)
      else
      begin
        M.Cmd.Phase := cpConfirm;
        M.Cmd.Deadline := ChMsTick + QWord(M.CommandMs);
      end;
    end
    else
      Finish(M, R, 'the link refused the ASDU of ' + IntToStr(M.CmdLen) + ' octets ('
        + ChResultText(R) + ')');
    Result := True;
  end;
end;
end.
