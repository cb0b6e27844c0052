{ Tests of ChnDF1Poll, the DF1 half-duplex master for a multidrop line:
  the poll and the master message octet by octet against a raw LOOP end
  (worked out by hand below), the poll cycle of priority and normal
  stations, message-based polling, commands through the poller to
  ChnSlc stations, a slave's own message to the master and to another
  slave (routed), a dead station demoted. The line is NAM=LOOP with
  several ends (a bus); one test runs it at 19200 Bd. }
unit TestChnDF1Poll;

{$MODE OBJFPC}{$H+}

interface

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnDF1,
  ChnDF1Link, ChnDF1Poll, ChnPcccClient, ChnWait, ChnSlc, TestSupport, BinSupport,
  ChildLine, StackCase;

type
  TFunc = function: Boolean;

  TTestChnDF1Poll = class(TStackCase)
  private
    Master: pChnVirt;
    P: tDF1Poller;
    Table: tSlcTable;
    St: array[1..4] of tDF1Station;
    Ch: array[1..4] of pChnVirt;
    NSt: Integer;
    procedure OpenMaster(const Pair, Line: string);
    procedure AddStation(Node: Integer; const Pair, Line: string);
    { step the poller and the stations until Done or MaxMs }
    procedure Run(MaxMs: Integer; Done: TFunc = nil);
    function RawFrames(Raw: pChnVirt; WaitMs: Integer): string;
  published
    procedure TestPollAndEotOctets;
    procedure TestMasterMessageOctets;
    procedure TestPriorityAndNormalCycle;
    procedure TestCommandThroughThePoller;
    procedure TestMessageBasedPollsOnlyForReplies;
    procedure TestSlaveMessageToTheMaster;
    procedure TestSlaveToSlaveIsRouted;
    procedure TestDeadStationDemoted;
    procedure TestRefusesAFullDuplexStack;
    procedure TestPcccClientThroughThePoller;
    {$IFDEF UNIX}
    procedure TestTwoDf1simOnAPtyBus;
    {$ENDIF}
  end;

implementation

var
  Cur: TTestChnDF1Poll;

procedure TTestChnDF1Poll.OpenMaster(const Pair, Line: string);
begin
  Master := Stack('DF1', 'NOD=0 MAS=MASTER FHD=HALF CRC=OFF NAM=LOOP PAIR=' + Pair +
    ' END=1 ' + Line);
  AssertEquals(res_Ok, DF1PollInit(P, Master));
  P.PollMs := 200;
  P.AckMs := 200;
  P.ReplyMs := 2000;
end;

procedure TTestChnDF1Poll.AddStation(Node: Integer; const Pair, Line: string);
begin
  Inc(NSt);
  Ch[NSt] := Stack('DF1', Format('NOD=%d DNO=0 MAS=SLAVE FHD=HALF CRC=OFF NAM=LOOP PAIR=%s END=%d %s',
    [Node, Pair, Node + 1, Line]));
  if NSt = 1 then
    SlcLoadDefault(Table);
  AssertEquals(res_Ok, SlcStationInit(St[NSt], Ch[NSt], @Table));
end;

procedure TTestChnDF1Poll.Run(MaxMs: Integer; Done: TFunc);
var
  Deadline: QWord;
  I: Integer;
  Busy: Boolean;
begin
  Deadline := ChMsTick + QWord(MaxMs);
  while ChMsTick < Deadline do
  begin
    if Assigned(Done) and Done() then
      Exit;
    Busy := DF1PollStep(P);
    for I := 1 to NSt do
      if DF1StationStep(St[I]) then
        Busy := True;
    if not Busy then
      ChnWaitAny(5);
  end;
end;

{ The frames a raw end received within WaitMs (polling the master), as hex. }
function TTestChnDF1Poll.RawFrames(Raw: pChnVirt; WaitMs: Integer): string;
var
  Buf: array[0..255] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  Result := '';
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Deadline := ChMsTick + QWord(WaitMs);
  while ChMsTick < Deadline do
  begin
    DF1PollStep(P);
    if Raw^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Raw^.ChReceive(Len);
      if Result <> '' then
        Result := Result + ' ';
      Result := Result + BytesToHex(Buf, Len);
    end
    else
      ChnWaitAny(5);
  end;
end;

{ Poll of station 3: DLE ENQ 03, BCC = -03 = FD. Of station 16 ($10):
  its DLE doubled, BCC = -$10 = F0. A slave with nothing: DLE EOT. }
procedure TTestChnDF1Poll.TestPollAndEotOctets;
var
  Raw: pChnVirt;
  Eot: array[0..1] of Byte = ($10, $04);
begin
  OpenMaster('PEO', '');
  Raw := Stack('LOOP', 'PAIR=PEO END=2');
  AssertEquals(res_Ok, DF1PollAdd(P, 3, False));
  AssertEquals('poll of 3', '10 05 03 FD', RawFrames(Raw, 50));
  Raw^.ChSend(@Eot, 2);
  RawFrames(Raw, 20);
  AssertEquals('EOT counted', 1, DF1PollStationOf(P, 3)^.Eots);
  AssertEquals('alive', False, DF1PollStationOf(P, 3)^.Dead);
  CloseStacks;
  OpenMaster('PEO16', '');
  Raw := Stack('LOOP', 'PAIR=PEO16 END=2');
  AssertEquals(res_Ok, DF1PollAdd(P, 16, False));
  AssertEquals('poll of 16', '10 05 10 10 F0', RawFrames(Raw, 50));
end;

{ Echo ($06 FNC $00, TNS $0102, data $41) to station 2 from the master
  (NOD=0): DLE SOH 02 DLE STX DST=02 SRC=00 CMD=06 STS=00 TNS=02 01 FNC=00
  41 DLE ETX BCC; BCC = -(02 + 02+00+06+00+02+01+00+41) = -$4E = B2. The
  slave's ACK ends the message; its reply comes at the next poll, which
  follows at once: DLE ENQ 02 FE. }
procedure TTestChnDF1Poll.TestMasterMessageOctets;
var
  Raw: pChnVirt;
  Req: tSendRecord;
  Job: LongInt;
  Ack: array[0..1] of Byte = ($10, $06);
  Reply: array[0..12] of Byte = ($10, $02, $00, $02, $46, $00, $02, $01, $41, $10, $03, 0, 0);
  Rep: tRecRecord;
  RepLen: Word;
  R: tChResult;
begin
  OpenMaster('MMO', '');
  P.Mode := dpMessage;              { no polls of its own: only the message }
  Raw := Stack('LOOP', 'PAIR=MMO END=2');
  AssertEquals(res_Ok, DF1PollAdd(P, 2, False));
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_Echo;
  Req.Tns := $0102;
  Req.Data[0] := $41;
  AssertEquals(res_Ok, DF1PollSend(P, 2, Req, 9, Job));
  AssertEquals('master message', '10 01 02 10 02 02 00 06 00 02 01 00 41 10 03 B2',
    RawFrames(Raw, 50));
  Raw^.ChSend(@Ack, 2);
  AssertEquals('the poll for the reply', '10 05 02 FE', RawFrames(Raw, 50));
  { reply: DST=00 SRC=02 CMD=46 STS=00 TNS=02 01 41; BCC = -(00+02+46+00+02+01+41) = -$8C = 74 }
  Reply[11] := $74;
  Raw^.ChSend(@Reply, 12);
  AssertEquals('the master ACKs it', '10 06', RawFrames(Raw, 50));
  AssertTrue('done', DF1PollResult(P, Job, Rep, RepLen, R));
  AssertEquals(res_Ok, R);
  AssertEquals('reply CF, FNC given back', $4600, Rep.CF);
  AssertEquals(9, RepLen);
  AssertEquals($41, Rep.Data[0]);
  AssertEquals(1, DF1PollStationOf(P, 2)^.MsgsOut);
  AssertEquals(1, DF1PollStationOf(P, 2)^.MsgsIn);
end;

{ Priority station 1, normal 2, 3, 4, one normal per cycle: the polls go
  1 2 1 3 1 4 1 2 (a raw end answers EOT to each for all of them). }
procedure TTestChnDF1Poll.TestPriorityAndNormalCycle;
var
  Raw: pChnVirt;
  Buf: array[0..63] of Byte;
  Len: Word;
  Order: string;
  Eot: array[0..1] of Byte = ($10, $04);
  Deadline: QWord;
begin
  OpenMaster('CYC', '');
  Raw := Stack('LOOP', 'PAIR=CYC END=9');
  DF1PollAdd(P, 2, False);
  DF1PollAdd(P, 1, True);
  DF1PollAdd(P, 3, False);
  DF1PollAdd(P, 4, False);
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Order := '';
  Deadline := ChMsTick + 3000;
  while (Length(Order) < 8) and (ChMsTick < Deadline) do
  begin
    DF1PollStep(P);
    if Raw^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Raw^.ChReceive(Len);
      if (Len = 4) and (Buf[1] = $05) then
      begin
        Order := Order + IntToStr(Buf[2]);
        Raw^.ChSend(@Eot, 2);
      end;
    end
    else
      ChnWaitAny(5);
  end;
  AssertEquals('poll order', '12131412', Order);
  AssertEquals('cycles', 4, P.Cycles);
end;

function ReplyIn: Boolean;
begin
  Result := Cur.P.Jobs[0].State = pjDone;
end;

{ Three SLC stations on a bus at 19200 Bd: an echo to station 2 through
  the poller, while 1 and 3 are polled too. }
procedure TTestChnDF1Poll.TestCommandThroughThePoller;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Job, I: LongInt;
  R: tChResult;
  Coll, Garb: LongWord;
begin
  OpenMaster('CMD', 'BD=19200');
  for I := 1 to 3 do
  begin
    AddStation(I, 'CMD', 'BD=19200');
    DF1PollAdd(P, I, False);
  end;
  P.NormalGroup := 3;
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_Echo;
  Req.Tns := 77;
  Req.Data[0] := $55;
  AssertEquals(res_Ok, DF1PollSend(P, 2, Req, 9, Job));
  Cur := Self;
  Run(3000, @ReplyIn);
  AssertTrue('done', DF1PollResult(P, Job, Rep, RepLen, R));
  AssertEquals('reply', res_Ok, R);
  AssertEquals($55, Rep.Data[0]);
  AssertEquals(77, Rep.Tns);
  Run(300);
  AssertTrue('1 polled', DF1PollStationOf(P, 1)^.Polls > 0);
  AssertTrue('3 polled', DF1PollStationOf(P, 3)^.Polls > 0);
  AssertTrue(LoopLineStats('CMD', Coll, Garb));
  AssertEquals('one speaker at a time: no collision', 0, Coll);
end;

{ Message-based: nothing on the line while no reply is due. }
procedure TTestChnDF1Poll.TestMessageBasedPollsOnlyForReplies;
var
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  Job: LongInt;
  R: tChResult;
begin
  OpenMaster('MSGB', '');
  AddStation(1, 'MSGB', '');
  AddStation(2, 'MSGB', '');
  DF1PollAdd(P, 1, True);
  DF1PollAdd(P, 2, False);
  P.Mode := dpMessage;
  Run(200);
  AssertEquals('no polls while idle', 0, DF1PollStationOf(P, 1)^.Polls + DF1PollStationOf(P, 2)^.Polls);
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_Echo;
  Req.Tns := 5;
  AssertEquals(res_Ok, DF1PollSend(P, 2, Req, 8, Job));
  Cur := Self;
  Run(2000, @ReplyIn);
  AssertTrue('done', DF1PollResult(P, Job, Rep, RepLen, R));
  AssertEquals('reply', res_Ok, R);
  AssertEquals('station 1 never polled', 0, DF1PollStationOf(P, 1)^.Polls);
  AssertTrue('station 2 polled for it', DF1PollStationOf(P, 2)^.Polls > 0);
end;

{ Station 3 sends a message of its own (an SLC MSG) to the master: it
  comes out of DF1PollReceive with SRC 3. }
procedure TTestChnDF1Poll.TestSlaveMessageToTheMaster;
var
  Msg: tSendRecord;
  M: tDF1PollMsg;
  Deadline: QWord;
  Got: Boolean;
begin
  OpenMaster('OWN', '');
  AddStation(3, 'OWN', '');
  DF1PollAdd(P, 3, False);
  FillChar(Msg, SizeOf(Msg), 0);
  Msg.MessType := tpDataMess;
  Msg.CF := CF_Echo;
  Msg.Tns := 900;
  Msg.Data[0] := $33;
  AssertEquals(res_Ok, DF1StationQueue(St[1], 0, Msg, 9));
  Got := False;
  Deadline := ChMsTick + 2000;
  while not Got and (ChMsTick < Deadline) do
  begin
    Run(20);
    Got := DF1PollReceive(P, M);
  end;
  AssertTrue('the message reached the program', Got);
  AssertEquals('its source', 3, M.Src);
  AssertEquals('to the master', 0, M.Dst);
  AssertEquals(900, M.Msg.Tns);
  AssertEquals($33, M.Msg.Data[0]);
  AssertEquals('ACKed: the station knows', 1, St[1].OwnSent);
  AssertEquals(1, DF1PollStationOf(P, 3)^.MsgsIn);
end;

function OwnReplied: Boolean;
begin
  Result := Cur.St[1].OwnReplies > 0;
end;

{ Station 1 sends an echo to station 2: the master routes it (SRC 1
  kept), station 2 answers to 1, the master routes the answer back. }
procedure TTestChnDF1Poll.TestSlaveToSlaveIsRouted;
var
  Msg: tSendRecord;
  M: tDF1PollMsg;
begin
  OpenMaster('RT', 'BD=19200');
  AddStation(1, 'RT', 'BD=19200');
  AddStation(2, 'RT', 'BD=19200');
  DF1PollAdd(P, 1, False);
  DF1PollAdd(P, 2, False);
  FillChar(Msg, SizeOf(Msg), 0);
  Msg.MessType := tpDataMess;
  Msg.CF := CF_Echo;
  Msg.Tns := 4242;
  Msg.Data[0] := $12;
  AssertEquals(res_Ok, DF1StationQueue(St[1], 2, Msg, 9));
  Cur := Self;
  Run(3000, @OwnReplied);
  AssertEquals('station 1 got the answer', 1, St[1].OwnReplies);
  AssertEquals('from station 2', 2, St[1].LastReplySrc);
  AssertEquals(4242, St[1].LastReply.Tns);
  AssertEquals($12, St[1].LastReply.Data[0]);
  AssertEquals('station 2 answered one command', 1, St[2].Requests);
  AssertEquals('routed from 1', 1, DF1PollStationOf(P, 1)^.Routed);
  AssertEquals('routed from 2', 1, DF1PollStationOf(P, 2)^.Routed);
  AssertFalse('nothing for the program', DF1PollReceive(P, M));
end;

{ Station 5 is on the list but not on the line: after DeadAfter misses it
  is polled only every DeadEvery cycles; 1 and 2 go on at full pace. }
procedure TTestChnDF1Poll.TestDeadStationDemoted;
var
  Polls5, Cycles: LongWord;
begin
  OpenMaster('DEAD', '');
  AddStation(1, 'DEAD', '');
  AddStation(2, 'DEAD', '');
  DF1PollAdd(P, 1, True);
  DF1PollAdd(P, 2, True);
  DF1PollAdd(P, 5, True);
  P.PollMs := 30;
  P.DeadAfter := 2;
  P.DeadEvery := 20;
  Run(1500);
  with DF1PollStationOf(P, 5)^ do
  begin
    AssertTrue('dead', Dead);
    AssertEquals('one death', 1, Deaths);
    Polls5 := Polls;
  end;
  Cycles := P.Cycles;
  AssertTrue('many cycles: ' + IntToStr(Cycles), Cycles > 60);
  AssertTrue(Format('5 polled %d times in %d cycles', [Polls5, Cycles]),
    Polls5 <= 2 + Cycles div 20 + 1);
  AssertTrue('1 polled every cycle', DF1PollStationOf(P, 1)^.Polls >= Cycles - 1);
  AssertEquals('1 never missed', 0, DF1PollStationOf(P, 1)^.Timeouts);
end;

procedure TTestChnDF1Poll.TestRefusesAFullDuplexStack;
var
  C: pChnVirt;
  Q: tDF1Poller;
begin
  C := Stack('DF1', 'FHD=FULL NAM=LOOP PAIR=FDX END=1');
  AssertEquals(res_WrongLayer, DF1PollInit(Q, C));
  C := Stack('DF1', 'FHD=HALF MAS=SLAVE NAM=LOOP PAIR=FDX END=2');
  AssertEquals(res_WrongLayer, DF1PollInit(Q, C));
  C := Stack('LOOP', 'PAIR=FDX END=3');
  AssertEquals(res_WrongLayer, DF1PollInit(Q, C));
  OpenMaster('ADD', '');
  AssertEquals(res_Ok, DF1PollAdd(P, 7, False));
  AssertEquals('twice', res_BadParam, DF1PollAdd(P, 7, True));
  AssertEquals('own address', res_BadParam, DF1PollAdd(P, 0, True));
  AssertEquals('broadcast', res_BadParam, DF1PollAdd(P, 255, True));
end;

procedure StepStations(Data: Pointer);
var
  I: Integer;
  T: TTestChnDF1Poll;
begin
  T := TTestChnDF1Poll(Data);
  for I := 1 to T.NSt do
    DF1StationStep(T.St[I]);
  ChnWaitAny(2);
end;

{ The blocking PCCC calls through the poller: N7:0..2 of the default
  table (0 10 20) from station 2, while station 1 is polled too; a write
  to station 1 read back. }
procedure TTestChnDF1Poll.TestPcccClientThroughThePoller;
var
  C: tPcccClient;
  V: array[0..2] of LongInt;
  W: array[0..0] of LongInt;
begin
  OpenMaster('PCCC', 'BD=19200');
  AddStation(1, 'PCCC', 'BD=19200');
  AddStation(2, 'PCCC', 'BD=19200');
  DF1PollAdd(P, 1, False);
  DF1PollAdd(P, 2, False);
  PcccClientInit(C, Master);
  PcccClientPoller(C, P, 2);
  C.Idle := @StepStations;
  C.IdleData := Self;
  AssertEquals('read: ' + C.Err, res_Ok, PcccReadInts(C, 'N7:0', 3, V));
  AssertEquals(0, V[0]);
  AssertEquals(10, V[1]);
  AssertEquals(20, V[2]);
  PcccClientPoller(C, P, 1);
  W[0] := 4321;
  AssertEquals('write: ' + C.Err, res_Ok, PcccWriteInts(C, 'N7:5', W));
  AssertEquals('read back: ' + C.Err, res_Ok, PcccReadInts(C, 'N7:5', 1, V));
  AssertEquals(4321, V[0]);
  AssertTrue('station 2 polled', DF1PollStationOf(P, 2)^.Polls > 0);
  AssertEquals('two messages to 1', 2, DF1PollStationOf(P, 1)^.MsgsOut);
end;

{$IFDEF UNIX}
{ tools/chnline makes an RS-485 bus of three ptys at 19200 Bd; two
  df1sim --half on it send MSGs every second: station 1 to station 2
  (routed by the master, and station 2's answer routed back), station 2
  to the master. The master here reads from both with the PCCC client
  through the poller meanwhile. }
procedure TTestChnDF1Poll.TestTwoDf1simOnAPtyBus;
var
  Line, Sim1, Sim2: TProcess;
  Paths: TStringList;
  First: string;
  C: tPcccClient;
  V: array[0..1] of LongInt;
  M: tDF1PollMsg;
  FromTwo: Integer;
  Deadline: QWord;

  function Start(const Exe: string; const Args: array of string): TProcess;
  var
    A: string;
  begin
    Result := TProcess.Create(nil);
    BinExecutable(Result, BinPath(Exe));
    for A in Args do
      Result.Parameters.Add(A);
    Result.Options := [poUsePipes];
    Result.Execute;
  end;

  procedure Stop(var Pr: TProcess);
  begin
    StopProcessWith(Pr, SIGTERM);
  end;

begin
  Line := nil;
  Sim1 := nil;
  Sim2 := nil;
  Paths := TStringList.Create;
  try
    Line := Start('chnline', ['--ends=3', '--bd=19200', '--quiet']);
    First := ReadFirstLine(Line, 3000);
    AssertEquals('PTY ', Copy(First, 1, 4));
    Paths.Delimiter := ' ';
    Paths.DelimitedText := Copy(First, 5, MaxInt);
    AssertEquals(3, Paths.Count);
    Sim1 := Start('df1sim', ['--dev=' + Paths[1], '--half', '--bcc', '--node=1', '--quiet',
      '--msg-to=2', '--msg-every=1', '--timeout=20']);
    Sim2 := Start('df1sim', ['--dev=' + Paths[2], '--half', '--bcc', '--node=2', '--quiet',
      '--msg-to=0', '--msg-every=1', '--timeout=20']);
    Master := Stack('DF1', 'NOD=0 MAS=MASTER FHD=HALF CRC=OFF NAM=COM DEV=' + Paths[0] + ' IDL=0');
    AssertEquals(res_Ok, DF1PollInit(P, Master));
    P.PollMs := 300;
    DF1PollAdd(P, 1, False);
    DF1PollAdd(P, 2, False);
    P.NormalGroup := 2;
    PcccClientInit(C, Master);
    PcccClientPoller(C, P, 1);
    AssertEquals('read from 1: ' + C.Err, res_Ok, PcccReadInts(C, 'N7:1', 2, V));
    AssertEquals(10, V[0]);
    PcccClientPoller(C, P, 2);
    AssertEquals('read from 2: ' + C.Err, res_Ok, PcccReadInts(C, 'N7:2', 1, V));
    AssertEquals(20, V[0]);
    FromTwo := 0;
    Deadline := ChMsTick + 4000;
    while (ChMsTick < Deadline) and ((FromTwo < 2) or (DF1PollStationOf(P, 2)^.Routed < 2)) do
    begin
      if not DF1PollStep(P) then
        ChnWaitUntil(DF1PollWaitEnd(P), 20);
      while DF1PollReceive(P, M) do
        if (M.Src = 2) and (M.Msg.CF = $0FA2) then
          Inc(FromTwo);
    end;
    AssertTrue('MSGs of station 2 to the master: ' + IntToStr(FromTwo), FromTwo >= 2);
    AssertTrue('station 1''s MSGs routed to 2', DF1PollStationOf(P, 1)^.Routed >= 2);
    AssertTrue('station 2''s answers routed back to 1', DF1PollStationOf(P, 2)^.Routed >= 2);
    AssertEquals('nobody dead', 0, DF1PollStationOf(P, 1)^.Deaths + DF1PollStationOf(P, 2)^.Deaths);
  finally
    Stop(Sim1);
    Stop(Sim2);
    Stop(Line);
    Paths.Free;
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnDF1Poll);
end.
