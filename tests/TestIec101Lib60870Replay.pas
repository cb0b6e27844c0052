{ Replays of IEC 60870-5-101 exchanges with lib60870-C 2.4.1
  (tests/data/iec101-lib60870-*.trc, made with tools/chntap between two pty
  pairs; how: tests/data/README, docs/ChnIec101.md). CI has no lib60870:
  the captures stand in for it.

  * lib60870's master against examples/iec101slave: the requests lib60870
    sent are fed, in order, to a ChnIec101Slave loaded with the same point
    table (tests/data/iec101-alltypes.points, every monitoring type); what
    it answers is decoded and must be what lib60870's master printed then,
    value and quality of every object (the expected lines below are
    lib60870's output, copied; not produced by this code). The ASDUs
    iec101slave sent in the capture decode to the same.
  * examples/iec101master against lib60870's cs101_slave: a ChnIec101Master
    talks to a replaying peer that answers each request with the answer
    lib60870 gave to a request of that kind in the capture, in order; the
    objects the master delivers must be that example's points, as
    lib60870's own master printed them, and the command and the clock
    synchronisation confirmed.
  * the pcap of the first exchange (NAM=TRC MOD=PCAP under chntap) is
    dissected by tshark with no malformed frame (skipped when tshark is
    not installed). }
unit TestIec101Lib60870Replay;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnFT1_2,
  ChnFT12Link, ChnIec101Asdu, ChnIec101Slave, ChnIec101Master, Iec101Points,
  Ft12Capture, TestSupport, TestTempDir, BinSupport;

type
  TTestIec101Lib60870Replay = class(TTestCase)
  private
    FUs, FRaw: pChnVirt;
    procedure OpenPair(const Params: string);
    function RawFrames: TCapFrames;
    procedure RawSend(const Hex: string);
    procedure CheckSlaveReplay(const Name, Params: string; Balanced: Boolean);
    procedure CheckMasterReplay(const Name, Params: string; Balanced: Boolean);
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    S: tIecSlaveStation;
    M: tIecMaster;
    Objects: TStringList;
    { the replaying peer of the master test }
    Answers: array[0..15] of TStringList;   { recorded answers per request FC }
    PeerAck, PeerStatus: string;
    procedure PeerPump;
  published
    procedure TestIec101SlaveToLib60870MasterUnbalanced;
    procedure TestIec101SlaveToLib60870MasterBalanced;
    procedure TestIec101MasterToLib60870SlaveUnbalanced;
    procedure TestIec101MasterToLib60870SlaveBalanced;
    procedure TestPcapDissectedByTshark;
  end;

implementation

const
  DataDir = 'tests/data/';

  { What lib60870's CS101_Master printed for every element our slave sent
    (GI, counter interrogation, read of IOA 104, clock sync, C_SC_NA_1 5000),
    one line per element: the ASDU's cot and P/N, then the element as
    lib60870's accessors gave it (times left out: they were the run's). }
  Lib60870Printed: array[0..38] of string = (
    'cot=7 neg=0 ti=100 ioa=0 qoi=20',
    'cot=20 neg=0 ti=1 ioa=1 value=1 quality=0',
    'cot=20 neg=0 ti=2 ioa=2 value=0 quality=128',
    'cot=20 neg=0 ti=3 ioa=3 value=2 quality=0',
    'cot=20 neg=0 ti=4 ioa=4 value=1 quality=64',
    'cot=20 neg=0 ti=5 ioa=5 value=-5 transient=0 quality=0',
    'cot=20 neg=0 ti=6 ioa=6 value=17 transient=1 quality=32',
    'cot=20 neg=0 ti=7 ioa=7 value=43690 quality=0',
    'cot=20 neg=0 ti=8 ioa=8 value=305419896 quality=16',
    'cot=20 neg=0 ti=9 ioa=9 value=0.500000 quality=0',
    'cot=20 neg=0 ti=10 ioa=10 value=-0.250000 quality=1',
    'cot=20 neg=0 ti=11 ioa=11 value=-1 quality=0',
    'cot=20 neg=0 ti=12 ioa=12 value=12345 quality=192',
    'cot=20 neg=0 ti=13 ioa=13 value=12.5 quality=0',
    'cot=20 neg=0 ti=14 ioa=14 value=-3.75 quality=32',
    'cot=20 neg=0 ti=17 ioa=17 state=2 qdp=8 elapsed=0',
    'cot=20 neg=0 ti=18 ioa=18 event=33 qdp=16 elapsed=0',
    'cot=20 neg=0 ti=19 ioa=19 oci=15 qdp=128 optime=0',
    'cot=20 neg=0 ti=20 ioa=20 st=15 cd=240 quality=64',
    'cot=20 neg=0 ti=21 ioa=21 value=-0.500000 quality=0',
    'cot=20 neg=0 ti=30 ioa=30 value=1 quality=32',
    'cot=20 neg=0 ti=31 ioa=31 value=3 quality=128',
    'cot=20 neg=0 ti=32 ioa=32 value=63 transient=0 quality=16',
    'cot=20 neg=0 ti=33 ioa=33 value=4294967295 quality=64',
    'cot=20 neg=0 ti=34 ioa=34 value=0.750000 quality=128',
    'cot=20 neg=0 ti=35 ioa=35 value=-32768 quality=32',
    'cot=20 neg=0 ti=36 ioa=36 value=12.5 quality=0',
    'cot=20 neg=0 ti=38 ioa=38 state=1 qdp=128 elapsed=0',
    'cot=20 neg=0 ti=39 ioa=39 event=63 qdp=32 elapsed=0',
    'cot=20 neg=0 ti=40 ioa=40 oci=14 qdp=64 optime=0',
    'cot=10 neg=0 ti=100 ioa=0 qoi=20',
    'cot=7 neg=0 ti=101 ioa=0 qcc=5',
    'cot=37 neg=0 ti=15 ioa=15 value=100000 seq=0 cy=0 ca=0 iv=0',
    'cot=37 neg=0 ti=16 ioa=16 value=-7 seq=0 cy=1 ca=0 iv=0',
    'cot=37 neg=0 ti=37 ioa=37 value=2147483647 seq=0 cy=0 ca=1 iv=0',
    'cot=10 neg=0 ti=101 ioa=0 qcc=5',
    'cot=47 neg=1 ti=102 ioa=104',
    'cot=7 neg=0 ti=103 ioa=0',
    'cot=7 neg=0 ti=45 ioa=5000 state=1 select=0 qu=0');

  { What lib60870's own master printed for the interrogation answer of its
    cs101_slave example (the periodic IOA 110 left out), and the
    confirmations of the single command to IOA 5000 and of the clock
    synchronisation. }
  Lib60870SlavePoints: array[0..17] of string = (
    'cot=7 neg=0 ti=100 ioa=0 qoi=20',
    'cot=20 neg=0 ti=11 ioa=100 value=-1 quality=0',
    'cot=20 neg=0 ti=11 ioa=101 value=23 quality=0',
    'cot=20 neg=0 ti=11 ioa=102 value=2300 quality=0',
    'cot=20 neg=0 ti=1 ioa=104 value=1 quality=0',
    'cot=20 neg=0 ti=1 ioa=105 value=0 quality=0',
    'cot=20 neg=0 ti=1 ioa=300 value=1 quality=0',
    'cot=20 neg=0 ti=1 ioa=301 value=0 quality=0',
    'cot=20 neg=0 ti=1 ioa=302 value=1 quality=0',
    'cot=20 neg=0 ti=1 ioa=303 value=0 quality=0',
    'cot=20 neg=0 ti=1 ioa=304 value=1 quality=0',
    'cot=20 neg=0 ti=1 ioa=305 value=0 quality=0',
    'cot=20 neg=0 ti=1 ioa=306 value=1 quality=0',
    'cot=20 neg=0 ti=1 ioa=307 value=0 quality=0',
    'cot=20 neg=0 ti=7 ioa=500 value=43690 quality=0',
    'cot=10 neg=0 ti=100 ioa=0 qoi=20',
    'cot=7 neg=0 ti=45 ioa=5000 state=1 select=0 qu=0',
    'cot=7 neg=0 ti=103 ioa=0');

{ An element the way the lib60870 program printed it (its format, so the
  lines above can be compared as they are). }
function Lib60870Line(const H: tIecAsdu; const O: tIecObject): string;
var
  Fmt: TFormatSettings;
begin
  Fmt := DefaultFormatSettings;
  Fmt.DecimalSeparator := '.';
  Result := Format('cot=%d neg=%d ti=%d ioa=%d', [H.Cot, Ord(H.Negative), H.Ti, O.Ioa]);
  case IecTypeKind(H.Ti) of
    ikSingle, ikDouble, ikScaled:
      Result := Result + Format(' value=%d quality=%d', [O.Int, O.Quality]);
    ikStep:
      Result := Result + Format(' value=%d transient=%d quality=%d', [O.Int, Ord(O.Transient), O.Quality]);
    ikBits:
      Result := Result + ' value=' + IntToStr(Int64(O.Bits)) + Format(' quality=%d', [O.Quality]);
    ikNormal:
      Result := Result + Format(' value=%.6f quality=%d', [O.Number, O.Quality], Fmt);
    ikFloat:
      Result := Result + ' value=' + FloatToStrF(O.Number, ffGeneral, 6, 0, Fmt) +
        Format(' quality=%d', [O.Quality]);
    ikCounter:
      Result := Result + Format(' value=%d seq=%d cy=%d ca=%d iv=%d', [O.Int, O.Seq,
        Ord(O.Quality and $20 <> 0), Ord(O.Quality and $40 <> 0), Ord(O.Quality and $80 <> 0)]);
    ikProtection:
      Result := Result + Format(' state=%d qdp=%d elapsed=%d', [O.Int, O.Quality, O.Elapsed]);
    ikStartEvents:
      Result := Result + Format(' event=%d qdp=%d elapsed=%d', [O.Bits, O.Quality, O.Elapsed]);
    ikOutputCircuit:
      Result := Result + Format(' oci=%d qdp=%d optime=%d', [O.Bits, O.Quality, O.Elapsed]);
    ikPacked:
      Result := Result + Format(' st=%d cd=%d quality=%d', [LongInt(O.Bits and $FFFF), LongInt(O.Bits shr 16), O.Quality]);
    ikSingleCmd:
      Result := Result + Format(' state=%d select=%d qu=%d', [O.Int, Ord(O.Select), O.Qu]);
    ikQualifier:
      if H.Ti = C_IC_NA_1 then
        Result := Result + Format(' qoi=%d', [O.Int])
      else
        Result := Result + Format(' qcc=%d', [O.Int]);
  end;
end;

{ Every element of the ASDU in lib60870's format into L. }
procedure AddAsdu(L: TStringList; const B: TBytes);
var
  H: tIecAsdu;
  Objs: array[0..IecMaxObjects - 1] of tIecObject;
  E: ShortString;
  I: Integer;
begin
  if IecDecodeAsdu(IecDefaultParams, B, Length(B), H, Objs, E) <> res_Ok then
  begin
    L.Add('bad ASDU: ' + E);
    Exit;
  end;
  for I := 0 to H.Count - 1 do
    L.Add(Lib60870Line(H, Objs[I]));
end;

procedure OnMasterObject(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIec101Lib60870Replay(Data).Objects.Add(Lib60870Line(H, O));
end;

procedure MasterIdle(Data: Pointer);
begin
  TTestIec101Lib60870Replay(Data).PeerPump;
end;

procedure TTestIec101Lib60870Replay.SetUp;
var
  I: Integer;
begin
  FUs := nil;
  FRaw := nil;
  Objects := TStringList.Create;
  for I := 0 to High(Answers) do
    Answers[I] := TStringList.Create;
end;

procedure TTestIec101Lib60870Replay.TearDown;
var
  I: Integer;
begin
  if FUs <> nil then
    Dispose(FUs, Done);
  if FRaw <> nil then
    Dispose(FRaw, Done);
  FUs := nil;
  FRaw := nil;
  Objects.Free;
  for I := 0 to High(Answers) do
    Answers[I].Free;
end;

procedure TTestIec101Lib60870Replay.OpenPair(const Params: string);
var
  Err: string;
begin
  FUs := OpenStack(ChnFT1_2.cName, Params + ' NAM=LOOP PAIR=IRP END=1', Err);
  AssertTrue(Err, FUs <> nil);
  FRaw := OpenStack(ChnLoop.cName, 'PAIR=IRP END=2', Err);
  AssertTrue(Err, FRaw <> nil);
end;

{ Whatever our station sent since the last call, as frames. }
function TTestIec101Lib60870Replay.RawFrames: TCapFrames;
var
  Buf: array[0..1023] of Byte;
  Got: TBytes;
begin
  Got := nil;
  FRaw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  ReceiveAllInto(FRaw, @Buf, Got);
  Result := nil;
  CapSplit(Got, True, [], Result);
end;

procedure TTestIec101Lib60870Replay.RawSend(const Hex: string);
var
  B: TBytes;
begin
  B := CapBytes(Hex);
  FRaw^.ChSend(@B[0], Length(B));
end;

{ lib60870's requests (tx, PRM = 1) to our slave, one by one; in balanced
  mode our slave's own requests get the answers lib60870 gave. }
procedure TTestIec101Lib60870Replay.CheckSlaveReplay(const Name, Params: string; Balanced: Boolean);
var
  F, Ours: TCapFrames;
  Ack, Status, Err: string;
  E: ShortString;
  Got, Recorded: TStringList;
  I, J, K: Integer;
  T0, Quiet: QWord;
begin
  F := CapLoad(DataDir + Name);
  AssertTrue('frames', Length(F) > 50);
  OpenPair(Params);
  AssertEquals(res_Ok, IecSlaveInit(S, FUs, IecDefaultParams, 1, E));
  AssertTrue(Err, IecLoadPoints(S, 'iec101-alltypes.points',
    ReadFileText(DataDir + 'iec101-alltypes.points'), Err));
  AssertEquals(33, S.PointCount);
  if Balanced then
  begin
    S.Link.Bal.TestMs := 0;
    S.Link.Bal.TimeoutMs := 60000;         { no repetitions while the replay waits }
  end;
  { lib60870's answers to requests of our station (balanced) }
  Ack := '';
  Status := '';
  for I := 0 to High(F) do
    if F[I].Tx and not F[I].Prm then
      if (F[I].Kind = tpShortM) and (F[I].FC = FCS_LinkSAccesReq) then
        Status := F[I].Hex
      else if (F[I].Kind = tpSACK) or ((F[I].Kind = tpShortM) and (F[I].FC = FCS_Ack)) then
        Ack := F[I].Hex;
  Got := TStringList.Create;
  Recorded := TStringList.Create;
  try
    for I := 0 to High(F) do
    begin
      { what iec101slave sent then, decoded }
      if not F[I].Tx and (F[I].Kind = tpLongM) then
        AddAsdu(Recorded, F[I].Data);
      if not (F[I].Tx and F[I].Prm) then
        Continue;
      RawSend(F[I].Hex);
      T0 := ChMsTick;
      K := Got.Count;
      repeat
        IecSlaveStep(S);
        Ours := RawFrames;
        for J := 0 to High(Ours) do
        begin
          if Ours[J].Kind = tpLongM then
            AddAsdu(Got, Ours[J].Data);
          if Balanced and Ours[J].Prm then
            if Ours[J].FC = FCM_ReqLinkState then
              RawSend(Status)
            else if Ours[J].FC <> FCM_UserDataNoRep then
              RawSend(Ack);
        end;
        if Length(Ours) = 0 then
          Sleep(1);
      until (ChMsTick - T0 > 60) or (not Balanced and (Got.Count > K) and (ChMsTick - T0 > 5));
    end;
    { the rest of what our slave had queued: until it is quiet for 300 ms
      (10 s at most; a loaded machine may be slow, never the order) }
    T0 := ChMsTick;
    Quiet := ChMsTick;
    while (ChMsTick - Quiet < 300) and (ChMsTick - T0 < 10000) do
    begin
      IecSlaveStep(S);
      Ours := RawFrames;
      for J := 0 to High(Ours) do
      begin
        Quiet := ChMsTick;
        if Ours[J].Kind = tpLongM then
          AddAsdu(Got, Ours[J].Data);
        if Balanced and Ours[J].Prm and (Ours[J].FC <> FCM_UserDataNoRep) then
          RawSend(Ack);
      end;
      if Length(Ours) = 0 then
        Sleep(1);
    end;
    AssertEquals('malformed', 0, S.BadAsdus);
    if Balanced then
      AssertEquals('broken frames', 0, S.Link.Bal.Broken);
    for I := 0 to High(Lib60870Printed) do
    begin
      AssertTrue('our answer ' + IntToStr(I) + ' missing', I < Got.Count);
      AssertEquals('as lib60870 printed it, element ' + IntToStr(I), Lib60870Printed[I], Got[I]);
      AssertEquals('the capture, element ' + IntToStr(I), Lib60870Printed[I], Recorded[I]);
    end;
    AssertEquals('nothing more: ' + Got.Text, Length(Lib60870Printed), Got.Count);
    AssertEquals(Length(Lib60870Printed), Recorded.Count);
  finally
    Got.Free;
    Recorded.Free;
  end;
end;

procedure TTestIec101Lib60870Replay.TestIec101SlaveToLib60870MasterUnbalanced;
begin
  CheckSlaveReplay('iec101-lib60870-master-unbal.trc', 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0', False);
end;

procedure TTestIec101Lib60870Replay.TestIec101SlaveToLib60870MasterBalanced;
begin
  CheckSlaveReplay('iec101-lib60870-master-bal.trc', 'NAM=FT1_2 MS=OFF NOD=1 DNO=2 DIR=0 LEN=0', True);
end;

{ The replaying lib60870 slave: each request of our master gets the next
  answer lib60870 gave to a request with that function (unbalanced), or
  the recorded status of link / ACK (balanced). }
procedure TTestIec101Lib60870Replay.PeerPump;
var
  Ours: TCapFrames;
  J: Integer;
  L: TStringList;
begin
  Ours := RawFrames;
  for J := 0 to High(Ours) do
  begin
    if not Ours[J].Prm then
      Continue;                       { our answers to the peer's requests }
    L := Answers[Ours[J].FC and 15];
    if M.Balanced then
    begin
      if Ours[J].FC = FCM_ReqLinkState then
        RawSend(PeerStatus)
      else if Ours[J].FC <> FCM_UserDataNoRep then
        RawSend(PeerAck);
    end
    else if L.Count > 0 then
    begin
      RawSend(L[0]);
      if L.Count > 1 then
        L.Delete(0);                  { the last one stays for more requests }
    end;
  end;
end;

procedure TTestIec101Lib60870Replay.CheckMasterReplay(const Name, Params: string; Balanced: Boolean);
var
  F: TCapFrames;
  I, N, Next: Integer;
  T0: QWord;
  Filtered: TStringList;
  Obj: tIecObject;
begin
  F := CapLoad(DataDir + Name);
  AssertTrue('frames', Length(F) > 20);
  OpenPair(Params);
  AssertEquals(res_Ok, IecMasterInit(M, FUs, IecDefaultParams));
  M.OnObject := @OnMasterObject;
  M.Data := Self;
  M.Idle := @MasterIdle;
  M.IdleData := Self;
  M.TimeoutMs := 100;
  M.CycleMs := 5;
  M.CommandMs := 3000;
  { the peer's answers, per function of the request they answered }
  PeerAck := '';
  PeerStatus := '';
  for I := 0 to High(F) - 1 do
    if F[I].Tx and F[I].Prm and not F[I + 1].Tx and not F[I + 1].Prm then
      Answers[F[I].FC and 15].Add(F[I + 1].Hex);
  for I := 0 to High(F) do
    if not F[I].Tx and not F[I].Prm then
      if (F[I].Kind = tpShortM) and (F[I].FC = FCS_LinkSAccesReq) then
        PeerStatus := F[I].Hex
      else if (F[I].Kind = tpSACK) or ((F[I].Kind = tpShortM) and (F[I].FC = FCS_Ack)) then
        PeerAck := F[I].Hex;
  if Balanced then
  begin
    M.Link.Bal.TestMs := 0;
    M.Link.Bal.TimeoutMs := 200;
    { the peer's own requests (rx, PRM = 1), in order, each once our
      station has answered the one before }
    Next := 0;
    T0 := ChMsTick;
    while ChMsTick - T0 < 5000 do
    begin
      while (Next <= High(F)) and (F[Next].Tx or not F[Next].Prm) do
        Inc(Next);
      if Next > High(F) then
        Break;
      RawSend(F[Next].Hex);
      Inc(Next);
      N := M.Link.Bal.Frames;
      repeat
        IecMasterStep(M);
        PeerPump;
        if M.Link.Bal.Frames = N then
          Sleep(1);
      until (M.Link.Bal.Frames > N) or (ChMsTick - T0 > 5000);
      { our answer goes out in the same step }
      IecMasterStep(M);
      PeerPump;
    end;
    AssertEquals('broken frames', 0, M.Link.Bal.Broken);
  end
  else
  begin
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
    AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 1, 1, Qoi_Station));
    Obj := IecObject(5000);
    Obj.Int := 1;
    AssertEquals(M.Cmd.Err, res_Ok, IecCommand(M, 1, 1, C_SC_NA_1, Obj, False));
    AssertEquals(M.Cmd.Err, res_Ok, IecClockSync(M, 1, 1, IecTimeFromDateTime(Now), False));
    IecPollFor(M, 300);
  end;
  AssertEquals('malformed', 0, M.BadAsdus);
  Filtered := TStringList.Create;
  try
    for I := 0 to Objects.Count - 1 do
      if Pos('ioa=110 ', Objects[I]) = 0 then    { the example's periodic value }
        Filtered.Add(Objects[I]);
    for I := 0 to High(Lib60870SlavePoints) do
    begin
      AssertTrue('object ' + IntToStr(I) + ' missing: ' + Filtered.Text, I < Filtered.Count);
      AssertEquals('as lib60870 printed it, object ' + IntToStr(I), Lib60870SlavePoints[I], Filtered[I]);
    end;
    AssertEquals(Filtered.Text, Length(Lib60870SlavePoints), Filtered.Count);
  finally
    Filtered.Free;
  end;
end;

procedure TTestIec101Lib60870Replay.TestIec101MasterToLib60870SlaveUnbalanced;
begin
  CheckMasterReplay('iec101-lib60870-slave-unbal.trc', 'NAM=FT1_2 MS=ON MAS=MASTER NOD=0 DNO=1 LEN=0', False);
end;

procedure TTestIec101Lib60870Replay.TestIec101MasterToLib60870SlaveBalanced;
begin
  CheckMasterReplay('iec101-lib60870-slave-bal.trc', 'NAM=FT1_2 MS=OFF NOD=3 DNO=1 DIR=1 LEN=0', True);
end;

procedure TTestIec101Lib60870Replay.TestPcapDissectedByTshark;
var
  Tshark, Output: string;
  Code, Asdus: Integer;
  L: TStringList;
  I: Integer;
const
  Prefs: array[0..5] of string = ('-o', 'iec60870_101.cot_len:2 octet',
    '-o', 'iec60870_101.asdu_addr_len:2 octet', '-o', 'iec60870_101.asdu_ioa_len:3 octet');
begin
  Tshark := ExeSearch('tshark', GetEnvironmentVariable('PATH'));
  if Tshark = '' then
    Ignore('tshark is not installed (Debian package tshark): the pcap is not checked by Wireshark');
  Code := RunExe(Tshark, ['-r', DataDir + 'iec101-lib60870-master-unbal.pcap', '-d',
    'rtacser.data,iec60870_101', Prefs[0], Prefs[1], Prefs[2], Prefs[3], Prefs[4], Prefs[5],
    '-Y', 'data or _ws.malformed or _ws.expert.severity >= warning'], 30000, Output);
  AssertEquals(Output, 0, Code);
  AssertEquals('no undissected or malformed frame: ' + Output, 0, Pos('IEC 60870', Output) + Pos('RTAC', Output));
  { and the ASDUs are there: every type our slave sent, with the right IOA }
  Code := RunExe(Tshark, ['-r', DataDir + 'iec101-lib60870-master-unbal.pcap', '-d',
    'rtacser.data,iec60870_101', Prefs[0], Prefs[1], Prefs[2], Prefs[3], Prefs[4], Prefs[5],
    '-Y', 'iec60870_asdu'], 30000, Output);
  AssertEquals(Output, 0, Code);
  L := TStringList.Create;
  try
    L.Text := Output;
    Asdus := 0;
    for I := 0 to L.Count - 1 do
      if Pos('ASDU=1 ', L[I]) > 0 then
        Inc(Asdus);
    { 5 requests, their 5 answers, 2 terminations, 29 points and 3 counters }
    AssertEquals(Output, 44, Asdus);
    AssertTrue(Output, Pos('M_ME_TF_1 Inrogen IOA=36', Output) > 0);
    AssertTrue(Output, Pos('M_IT_TB_1 Reqcogen IOA=37', Output) > 0);
    AssertTrue(Output, Pos('C_SC_NA_1 ActCon  IOA=5000', Output) > 0);
  finally
    L.Free;
  end;
end;

initialization
  RegisterTest(TTestIec101Lib60870Replay);
end.
