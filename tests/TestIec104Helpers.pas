{ The IEC 101 master and slave helpers over NAM=IEC104 (loopback TCP, one
  process, the slave stepped while the master waits): the same
  procedures as on FT 1.2, with 104's differences - no link polling,
  CP24 types served as their CP56 counterparts, C_TS_NA_1 refused with
  COT 44, events made while no connection is started sent after STARTDT;
  a command confirmed later (IecSlaveDefer / IecSlaveConfirm) and a
  command point sharing the IOA of the value it sets, whose events go
  with CP56 time tags (IecSlaveEventType). }
unit TestIec104Helpers;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnIec104,
  ChnIec101Asdu, ChnIec101Master, ChnIec101Slave, ChnWait, TestSupport, TestTempDir,
  BinSupport;

type
  TTestIec104Helpers = class(TTestCase)
  private
    SChn, MChn: pChnVirt;
    Objects: TStringList;
    Commands: Integer;
    Defer: Boolean;
    Ticket: LongWord;
    Last: tIecObject;
    procedure OpenPair(const Extra: string = ''; const Below: string = '');
    procedure StepSlave;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    M: tIecMaster;
    S: tIecSlaveStation;
  published
    procedure TestInterrogationServesCp56ForCp24;
    procedure TestCounterInterrogation;
    procedure TestCommandConfirmed;
    procedure TestClockSyncAndTest;
    procedure TestTestWithoutTimeTagRefusedWithCot44;
    procedure TestEventsQueuedUntilStartDt;
    procedure TestPcapIsATcpStreamTsharkDissects;
    procedure TestDeferredConfirmation;
    procedure TestSharedIoaAndCp56Events;
  end;

implementation

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIec104Helpers(Data).Objects.Add(IecTypeName(H.Ti) + ' COT ' + IntToStr(H.Cot) +
    ' IOA ' + IntToStr(O.Ioa));
  TTestIec104Helpers(Data).Last := O;
end;

function OnCmd(Data: Pointer; const H: tIecAsdu; const O: tIecObject): Boolean;
begin
  with TTestIec104Helpers(Data) do
  begin
    Inc(Commands);
    if Defer then
      Ticket := IecSlaveDefer(S);
  end;
  Result := True;
end;

procedure IdleSlave(Data: Pointer);
begin
  TTestIec104Helpers(Data).StepSlave;
end;

procedure TTestIec104Helpers.StepSlave;
begin
  IecSlaveStep(S);
  ChnWaitAny(2);
end;

procedure TTestIec104Helpers.SetUp;
begin
  Objects := TStringList.Create;
  SChn := nil;
  MChn := nil;
  Commands := 0;
  Defer := False;
  Ticket := 0;
end;

procedure TTestIec104Helpers.TearDown;
begin
  if MChn <> nil then Dispose(MChn, Done);
  if SChn <> nil then Dispose(SChn, Done);
  Objects.Free;
end;

procedure TTestIec104Helpers.OpenPair(const Extra: string; const Below: string = '');
var
  Err: string;
  E: ShortString;
  O: tIecObject;
  Port: Word;
begin
  SChn := OpenListening('IEC104', 'NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0', Port);
  AssertEquals('slave', res_Ok, IecSlaveInit(S, SChn, IecDefaultParams, 1, E));
  S.OnCommand := @OnCmd;
  S.Data := Self;
  O := IecObject(100);
  O.Bits := 1;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_NA_1, O, 0, E));
  O := IecObject(101);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_SP_TA_1, O, 0, E));     { CP24: served as 30 }
  O := IecObject(200);
  O.Number := 1.5;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_ME_NC_1, O, 0, E));
  O := IecObject(300);
  O.Int := 1234;
  AssertEquals(res_Ok, IecSlaveAddPoint(S, M_IT_NA_1, O, 0, E));
  O := IecObject(5000);
  AssertEquals(res_Ok, IecSlaveAddPoint(S, C_SC_NA_1, O, 0, E));
  MChn := OpenStack('IEC104', 'NAM=IEC104 ' + Extra + ' ' + Below + ' NAM=TCP HOST=127.0.0.1 PORT=' +
    IntToStr(Port) + ' RECON=200', Err);
  AssertNotNull(Err, MChn);
  AssertEquals('master', res_Ok, IecMasterInit(M, MChn, IecDefaultParams));
  M.CommandMs := 3000;
  M.OnObject := @OnObj;
  M.Data := Self;
  M.Idle := @IdleSlave;
  M.IdleData := Self;
end;

procedure TTestIec104Helpers.TestInterrogationServesCp56ForCp24;
begin
  OpenPair;
  AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 0, 1, Qoi_Station));
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 COT 20 IOA 100') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_TB_1 COT 20 IOA 101') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NC_1 COT 20 IOA 200') >= 0);
  AssertEquals('no counter, no command point', -1, Objects.IndexOf('M_IT_NA_1 COT 20 IOA 300'));
  AssertEquals('slave saw one', 1, S.Interrogations);
end;

procedure TTestIec104Helpers.TestCounterInterrogation;
begin
  OpenPair;
  AssertEquals(M.Cmd.Err, res_Ok, IecCounterInterrogation(M, 0, 1, Qcc_General));
  AssertTrue(Objects.Text, Objects.IndexOf('M_IT_NA_1 COT 37 IOA 300') >= 0);
end;

procedure TTestIec104Helpers.TestCommandConfirmed;
var
  O: tIecObject;
begin
  OpenPair;
  O := IecObject(5000);
  O.Bits := 1;
  AssertEquals(M.Cmd.Err, res_Ok, IecCommand(M, 0, 1, C_SC_NA_1, O, False));
  AssertEquals('the program saw it', 1, Commands);
  O := IecObject(5001);
  AssertEquals('no such point: COT 47', res_IecUnknownIoa, IecCommand(M, 0, 1, C_SC_NA_1, O, False));
end;

procedure TTestIec104Helpers.TestClockSyncAndTest;
begin
  OpenPair;
  AssertEquals(M.Cmd.Err, res_Ok, IecClockSync(M, 0, 1, IecTimeFromDateTime(Now), True));
  AssertEquals('synchronised', 1, S.ClockSyncs);
  AssertEquals(M.Cmd.Err, res_Ok, IecTestCommand(M, 0, 1));
  AssertEquals('C_TS_TA_1 went out', C_TS_TA_1, M.Cmd.Ti);
end;

procedure TTestIec104Helpers.TestTestWithoutTimeTagRefusedWithCot44;
var
  Err: string;
  C: pChnVirt;
  A: TBytes;
  Buf: array[0..255] of Byte;
  Len: Word;
  Deadline: QWord;
  Got: string;
begin
  OpenPair;
  Dispose(MChn, Done);              { a raw 104 client in place of the master }
  MChn := nil;
  C := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' +
    IntToStr(pChnTcp(SChn^.CH_Low)^.ChLocalPort), Err);
  AssertNotNull(Err, C);
  try
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    { C_TS_NA_1, COT 6, CA 1, IOA 0, FBP AA55 }
    A := HexToBytes('68 01 06 00 01 00 00 00 00 55 AA');
    C^.ChSend(@A[0], Length(A));
    Got := '';
    Deadline := GetTickCount64 + 3000;
    repeat
      IecSlaveStep(S);
      Len := 0;
      C^.ChReceive(Len);
      if (C^.ChReceiveResult = res_Ok) and (Len > 0) then
        Got := BytesToHex(Buf, Len);
      ChnWaitAny(2);
    until (Got <> '') or (GetTickCount64 > Deadline);
    { mirrored, P/N = 1, COT 44: 40h + 2Ch = 6Ch }
    AssertEquals('68 01 6C 00 01 00 00 00 00 55 AA', Got);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestIec104Helpers.TestEventsQueuedUntilStartDt;
var
  O: tIecObject;
  Err: ShortString;
  I: Integer;
begin
  OpenPair;
  { no connection started yet: the events wait in the layer }
  O := IecObject(100);
  O.Bits := 0;
  AssertEquals(Err, res_Ok, IecSlaveUpdate(S, 100, O, True, Err));
  O.Bits := 1;
  AssertEquals(Err, res_Ok, IecSlaveUpdate(S, 100, O, True, Err));
  IecSlaveStep(S);
  AssertFalse('not started', pChnIec104(SChn)^.ChDataStarted);
  for I := 1 to 200 do
  begin
    IecMasterStep(M);
    StepSlave;
  end;
  AssertEquals(Objects.Text, 2, Objects.Count);
  AssertEquals('M_SP_NA_1 COT 3 IOA 100', Objects[0]);
  AssertEquals('M_SP_NA_1 COT 3 IOA 100', Objects[1]);
  for I := 1 to 50 do
  begin
    IecMasterStep(M);
    StepSlave;
  end;
  AssertEquals('none twice', 2, Objects.Count);
end;

{ The master's channel with NAM=TRC MOD=PCAP between IEC104 and TCP: an
  IPv4 + TCP stream, the server on port 2404. The first record worked out
  by hand: IPv4 45 00, total 46 = 002Eh, DF, TTL 64, TCP, checksum of
  4500 002E 0000 4000 4006 0A00 0001 0A00 0002 = D937h: 26C8h; TCP ports
  50000 = C350h, 2404 = 0964h, sequence 1, acknowledgement 1, 20 octets,
  PSH ACK, window FFFFh; then STARTDT act. tshark (when installed) checks
  both checksums and dissects it as IEC 104 with nothing malformed. }
procedure TTestIec104Helpers.TestPcapIsATcpStreamTsharkDissects;
var
  Dir, F, Tshark, Output: string;
  Cap: AnsiString;
  Code: Integer;
begin
  Dir := MakeTempDir('iec104pcap');
  try
    F := Dir + '/m.pcap';
    OpenPair('', 'NAM=TRC MOD=PCAP FILE=' + F);
    AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 0, 1, Qoi_Station));
    Dispose(MChn, Done);
    MChn := nil;
    Cap := ReadFileText(F);
    AssertEquals('link type 228', 'E4 00 00 00', BytesToHex(PByte(@Cap[21])^, 4));
    AssertEquals('record length', '2E 00 00 00 2E 00 00 00', BytesToHex(PByte(@Cap[33])^, 8));
    AssertEquals('IPv4', '45 00 00 2E 00 00 40 00 40 06 26 C8 0A 00 00 01 0A 00 00 02',
      BytesToHex(PByte(@Cap[41])^, 20));
    AssertEquals('TCP', 'C3 50 09 64 00 00 00 01 00 00 00 01 50 18 FF FF',
      BytesToHex(PByte(@Cap[61])^, 16));
    AssertEquals('STARTDT act', '68 04 07 00 00 00', BytesToHex(PByte(@Cap[81])^, 6));
    Tshark := ExeSearch('tshark', GetEnvironmentVariable('PATH'));
    if Tshark = '' then
      Ignore('tshark is not installed (Debian package tshark): the pcap is not checked by Wireshark');
    Code := RunExe(Tshark, ['-r', F, '-o', 'tcp.check_checksum:TRUE', '-o', 'ip.check_checksum:TRUE',
      '-Y', '_ws.malformed or _ws.expert.severity >= warning or tcp.checksum.status == 0 or ' +
      'ip.checksum.status == 0 or data'], 30000, Output);
    AssertEquals(Output, 0, Code);
    AssertEquals('nothing malformed, no bad checksum: ' + Output, 0, Pos('10.0.0', Output));
    Code := RunExe(Tshark, ['-r', F], 30000, Output);
    AssertEquals(Output, 0, Code);
    AssertTrue(Output, Pos('U (STARTDT act)', Output) > 0);
    AssertTrue(Output, Pos('U (STARTDT con)', Output) > 0);
    AssertTrue(Output, Pos('C_IC_NA_1 Act ', Output) > 0);
    AssertTrue(Output, Pos('M_SP_TB_1 Inrogen IOA=101', Output) > 0);
    AssertTrue(Output, Pos('C_IC_NA_1 ActTerm', Output) > 0);
  finally
    RemoveTempDir(Dir);
  end;
end;

{ Step master and slave for Ms or until the command ended. }
procedure StepBoth(T: TTestIec104Helpers; Ms: LongInt);
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    IecMasterStep(T.M);
    T.StepSlave;
  until IecCommandDone(T.M) or (GetTickCount64 > Deadline);
end;

procedure TTestIec104Helpers.TestDeferredConfirmation;
var
  O: tIecObject;
  First: LongWord;
begin
  OpenPair;
  AssertEquals('no command handed over: nothing to defer', 0, IecSlaveDefer(S));
  Defer := True;
  O := IecObject(5000);
  O.Int := 1;
  AssertTrue(M.Cmd.Err, IecStartCommand(M, 0, 1, C_SC_NA_1, O, False));
  StepBoth(Self, 500);
  AssertEquals('handed over', 1, Commands);
  AssertTrue('a ticket', Ticket > 0);
  AssertEquals('waiting', 1, IecSlaveDeferred(S));
  AssertFalse('no ACT_CON before the program confirmed', IecCommandDone(M));
  AssertEquals('not counted yet', 0, S.Commands);
  AssertEquals(res_Ok, IecSlaveConfirm(S, Ticket, True));
  StepBoth(Self, 3000);
  AssertTrue('ACT_CON after IecSlaveConfirm', IecCommandDone(M));
  AssertEquals(M.Cmd.Err, res_Ok, IecFinish(M));
  AssertEquals('counted', 1, S.Commands);
  AssertEquals('none waits', 0, IecSlaveDeferred(S));
  AssertEquals('the command point took the value', 1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  AssertEquals('a ticket once', res_BadParam, IecSlaveConfirm(S, Ticket, True));
  { refused later: negative ACT_CON }
  First := Ticket;
  O.Int := 0;
  AssertTrue(M.Cmd.Err, IecStartCommand(M, 0, 1, C_SC_NA_1, O, False));
  StepBoth(Self, 300);
  AssertFalse('waits', IecCommandDone(M));
  AssertTrue('a new ticket', (Ticket > 0) and (Ticket <> First));
  AssertEquals(res_Ok, IecSlaveConfirm(S, Ticket, False));
  StepBoth(Self, 3000);
  AssertEquals('negative ACT_CON', res_IecNegative, IecFinish(M));
  AssertEquals('refused', 1, S.Refused);
  AssertEquals('the value stays', 1, S.Points[IecSlaveFind(S, 5000)].Obj.Int);
  { a general reset drops a waiting command: its ticket is gone }
  M.CommandMs := 300;
  AssertEquals('the master gives up', res_Timeout, IecCommand(M, 0, 1, C_SC_NA_1, O, False));
  AssertEquals('still waiting', 1, IecSlaveDeferred(S));
  M.CommandMs := 3000;
  Defer := False;
  AssertEquals(M.Cmd.Err, res_Ok, IecResetProcess(M, 0, 1, Qrp_General));
  AssertEquals('dropped', 0, IecSlaveDeferred(S));
  AssertEquals('dropped', res_BadParam, IecSlaveConfirm(S, Ticket, True));
end;

procedure TTestIec104Helpers.TestSharedIoaAndCp56Events;
var
  O: tIecObject;
  E: ShortString;
  I: LongInt;
  Before, At: TDateTime;
begin
  OpenPair;
  { the measured value 400 and its set point at the same IOA }
  O := IecObject(400);
  O.Int := 7;
  AssertEquals(E, res_Ok, IecSlaveAddPoint(S, M_ME_NB_1, O, 0, E));
  AssertEquals(E, res_Ok, IecSlaveAddPoint(S, C_SE_NB_1, IecObject(400), 0, E));
  AssertEquals(E, res_Ok, IecSlaveAddPoint(S, C_SE_TB_1, IecObject(400), 0, E));
  AssertEquals('a second set point of one type', res_BadParam, IecSlaveAddPoint(S, C_SE_NB_1, IecObject(400), 0, E));
  AssertEquals('point 400: IOA twice', E);
  AssertEquals('a second value', res_BadParam, IecSlaveAddPoint(S, M_ME_NC_1, IecObject(400), 0, E));
  AssertEquals('the monitoring point', M_ME_NB_1, S.Points[IecSlaveFind(S, 400)].Ti);
  AssertEquals('not the same information', res_AsduType, IecSlaveEventType(S, 400, M_ME_TF_1, E));
  AssertEquals('point 400: M_ME_TF_1 is not M_ME_NB_1 with a time tag', E);
  AssertEquals('no time tag', res_AsduType, IecSlaveEventType(S, 400, M_ME_NB_1, E));
  AssertEquals('no such point', res_AsduIoa, IecSlaveEventType(S, 401, M_ME_TE_1, E));
  AssertEquals(E, res_Ok, IecSlaveEventType(S, 400, M_ME_TB_1, E));   { CP24: CP56 over 104 }
  AssertEquals('CP56', M_ME_TE_1, S.Points[IecSlaveFind(S, 400)].EventTi);
  { interrogated as itself, read as itself }
  AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 0, 1, Qoi_Station));
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 COT 20 IOA 400') >= 0);
  AssertEquals(M.Cmd.Err, res_Ok, IecRead(M, 0, 1, 400));
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 COT 5 IOA 400') >= 0);
  { a change: an event with a CP56 time tag of now }
  Objects.Clear;
  Before := Now;
  O.Int := -5;
  AssertEquals(E, res_Ok, IecSlaveUpdate(S, 400, O, True, E));
  for I := 1 to 100 do
  begin
    IecMasterStep(M);
    StepSlave;
  end;
  AssertEquals(Objects.Text, 'M_ME_TE_1 COT 3 IOA 400', Trim(Objects.Text));
  AssertEquals('the value', -5, Last.Int);
  AssertTrue('a CP56 time', IecTimeToDateTime(Last.Time, At));
  AssertTrue('of the change: ' + DateTimeToStr(At), (At >= Before - 1 / SecsPerDay) and (At <= Now + 1 / SecsPerDay));
  AssertEquals('the table keeps the type', M_ME_NB_1, S.Points[IecSlaveFind(S, 400)].Ti);
  AssertTrue('a set point to the shared IOA', IecCommand(M, 0, 1, C_SE_NB_1, O, False) = res_Ok);
  AssertTrue('and its CP56 form', IecCommand(M, 0, 1, C_SE_TB_1, O, False) = res_Ok);
  AssertEquals('another type: COT 47', res_IecUnknownIoa, IecCommand(M, 0, 1, C_SE_NC_1, O, False));
  AssertEquals(2, Commands);
end;

initialization
  RegisterTest(TTestIec104Helpers);
end.
