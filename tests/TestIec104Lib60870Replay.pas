{ Replays of IEC 60870-5-104 exchanges with lib60870-C 2.4.1
  (tests/data/iec104-lib60870-*.trc, NAM=TRC between NAM=IEC104 and
  NAM=TCP on our side; how they were made: tests/data/README). CI has no
  lib60870: the captures stand in for it. A raw NAM=TCP peer plays
  lib60870's side APDU by APDU, each once our side has sent what came
  before it in the capture, and checks every APDU of ours against the
  capture (format, U function, ASDU identifier and first IOA; sequence
  numbers follow the timing of acknowledgements and are the layer's own
  tests' business).

  * our master against lib60870's cs104_server example: interrogation
    (the example's points, their values from its source), counter
    interrogation (the example answers COT 44), a command and the clock
    synchronisation confirmed, the example's periodic measurement;
  * our slave (tests/data/iec101-alltypes.points, every monitoring type)
    against a client on lib60870's CS104_Connection: interrogation (the
    CP24 types served as CP56), counter interrogation, read, command,
    clock synchronisation and test with time tag confirmed, C_TS_NA_1
    refused with COT 44, STOPDT at the end. }
unit TestIec104Lib60870Replay;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnIec104,
  ChnIec104Codec, ChnIec101Asdu, ChnIec101Master, ChnIec101Slave, ChnWait, Iec101Points,
  Iec104Capture, TestSupport, TestTempDir;

type
  TTestIec104Lib60870Replay = class(TTestCase)
  private
    FPeer, FUs: pChnVirt;
    FCap: TApdus104;
    FNext: Integer;               { next capture APDU to play or match }
    FOurs: TApdus104;             { what our side sent, as the peer got it }
    FMatched: Integer;            { of FOurs, the non-S ones matched }
    FSplit: TApduSplitter;
    FBuf: array[0..4095] of Byte;
    FMismatch: string;
    FStepSlave: Boolean;
    procedure Load(const Name: string);
    function Done_: Boolean;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    M: tIecMaster;
    S: tIecSlaveStation;
    Objects: TStringList;
    procedure Pump;
  published
    procedure TestMasterAgainstLib60870Server;
    procedure TestSlaveAgainstLib60870Client;
  end;

implementation

const
  DataDir = 'tests/data/';

procedure TTestIec104Lib60870Replay.SetUp;
begin
  FPeer := nil;
  FUs := nil;
  Objects := TStringList.Create;
  FMismatch := '';
  FStepSlave := False;
end;

procedure TTestIec104Lib60870Replay.TearDown;
begin
  if FUs <> nil then Dispose(FUs, Done);
  if FPeer <> nil then Dispose(FPeer, Done);
  Objects.Free;
end;

procedure TTestIec104Lib60870Replay.Load(const Name: string);
begin
  FCap := Cap104Load(DataDir + Name);
  FNext := 0;
  FOurs := nil;
  FMatched := 0;
  Apci104FeedReset(FSplit.Feed);
end;

function TTestIec104Lib60870Replay.Done_: Boolean;
begin
  Result := (FNext >= Length(FCap)) or (FMismatch <> '');
end;

{ One round of the peer: take what our side sent, match it, play
  lib60870's next APDUs whose turn it is. }
procedure TTestIec104Lib60870Replay.Pump;
var
  Len: Word;
  Want: string;
begin
  if FStepSlave then
    IecSlaveStep(S);
  Len := 0;
  FPeer^.ChReceive(Len);
  if (FPeer^.ChReceiveResult = res_Ok) and (Len > 0) then
    Cap104Split(FSplit, FBuf, Len, True, FOurs);
  while not Done_ do
  begin
    if FCap[FNext].Tx then
    begin
      if FCap[FNext].Apci.Format = af104S then
      begin
        Inc(FNext);                 { acknowledgements follow the timing }
        Continue;
      end;
      while (FMatched < Length(FOurs)) and (FOurs[FMatched].Apci.Format = af104S) do
        Inc(FMatched);
      if FMatched >= Length(FOurs) then
        Break;                      { not sent yet }
      Want := Cap104Key(FCap[FNext]);
      if Cap104Key(FOurs[FMatched]) <> Want then
        FMismatch := Format('APDU %d of the capture: expected %s, sent %s',
          [FNext, Want, Cap104Key(FOurs[FMatched])]);
      Inc(FMatched);
      Inc(FNext);
    end
    else
    begin
      FPeer^.ChSend(@FCap[FNext].Bytes[0], Length(FCap[FNext].Bytes));
      if FPeer^.ChSendResult <> res_Ok then
        Break;                      { the layer below is busy: next round }
      Inc(FNext);
    end;
  end;
  ChnWaitAny(2);
end;

procedure PumpIdle(Data: Pointer);
begin
  TTestIec104Lib60870Replay(Data).Pump;
end;

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIec104Lib60870Replay(Data).Objects.Add(Format('%s %d %d int=%d bits=%d',
    [IecTypeName(H.Ti), H.Cot, O.Ioa, O.Int, O.Bits]));
end;

procedure TTestIec104Lib60870Replay.TestMasterAgainstLib60870Server;
var
  Err: string;
  Port: Word;
  O: tIecObject;
  Deadline: QWord;
begin
  Load('iec104-lib60870-server.trc');
  FPeer := OpenListening('TCP', 'LISTEN=127.0.0.1:0', Port);
  FPeer^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
  FUs := OpenStack('IEC104', 'NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  AssertNotNull(Err, FUs);
  AssertEquals(res_Ok, IecMasterInit(M, FUs, IecDefaultParams));
  M.CommandMs := 3000;
  M.OnObject := @OnObj;
  M.Data := Self;
  M.Idle := @PumpIdle;
  M.IdleData := Self;
  AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 0, 1, Qoi_Station));
  AssertEquals('the example does not do counters', res_IecUnknownType,
    IecCounterInterrogation(M, 0, 1, Qcc_General));
  O := IecObject(5000);
  O.Bits := 1;
  AssertEquals(M.Cmd.Err, res_Ok, IecCommand(M, 0, 1, C_SC_NA_1, O, False));
  AssertEquals(M.Cmd.Err, res_Ok, IecClockSync(M, 0, 1, IecTimeFromDateTime(Now), False));
  Deadline := GetTickCount64 + 3000;
  while not Done_ and (GetTickCount64 < Deadline) do
  begin
    IecMasterStep(M);
    Pump;
  end;
  AssertEquals('', FMismatch);
  AssertEquals('the whole capture played', Length(FCap), FNext);
  { cs104_server's interrogation answer, from its source: scaled 100 -1,
    101 23, 102 2300; single 104 on, 105 off, 300..307 on/off in turn;
    bitstring 500 AAAAh }
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 20 100 int=-1 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 20 101 int=23 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_ME_NB_1 20 102 int=2300 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 20 104 int=1 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 20 105 int=0 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_SP_NA_1 20 307 int=0 bits=0') >= 0);
  AssertTrue(Objects.Text, Objects.IndexOf('M_BO_NA_1 20 500 int=0 bits=43690') >= 0);
  AssertTrue('the periodic measurement (COT 1)', Objects.IndexOf('M_ME_NB_1 1 110 int=0 bits=0') >= 0);
  AssertEquals('no connection closed', 0, pChnIec104(FUs)^.ChClosings);
end;

procedure TTestIec104Lib60870Replay.TestSlaveAgainstLib60870Client;
var
  Err: string;
  E: ShortString;
  AE: AnsiString;
  Port: Word;
  Deadline: QWord;
begin
  Load('iec104-lib60870-client.trc');
  FUs := OpenListening('IEC104', 'NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0', Port);
  AssertEquals(res_Ok, IecSlaveInit(S, FUs, IecDefaultParams, 1, E));
  AssertTrue(AE, IecLoadPoints(S, 'iec101-alltypes.points',
    ReadFileText(DataDir + 'iec101-alltypes.points'), AE));
  FPeer := OpenStack('TCP', 'HOST=127.0.0.1 PORT=' + IntToStr(Port), Err);
  AssertNotNull(Err, FPeer);
  FPeer^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
  FStepSlave := True;
  Deadline := GetTickCount64 + 5000;
  while not Done_ and (GetTickCount64 < Deadline) do
    Pump;
  AssertEquals('', FMismatch);
  AssertEquals('the whole capture played', Length(FCap), FNext);
  AssertEquals('interrogations', 1, S.Interrogations);
  AssertEquals('counter interrogations', 1, S.CounterInterrogations);
  AssertEquals('commands', 1, S.Commands);
  AssertEquals('clock', 1, S.ClockSyncs);
  AssertFalse('stopped at the end', pChnIec104(FUs)^.ChDataStarted);
  AssertEquals('no connection closed', 0, pChnIec104(FUs)^.ChClosings);
end;

initialization
  RegisterTest(TTestIec104Lib60870Replay);
end.
