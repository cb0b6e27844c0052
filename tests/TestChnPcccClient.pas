{ Tests of unit ChnPcccClient: every address form read and written against
  the simulator's table (unit ChnSlc behind a ChnDF1Link station) over the
  in-memory null modem NAM=LOOP in full and half duplex, CRC and BCC; reads
  and writes longer than a frame; the stepped form; every failure (no ACK,
  NAK on every try, no reply, error reply, a reply of the wrong length, a
  bad address, count or value, a value of the wrong kind) with its result
  and text; and end to end against tools/df1sim on a Unix pty, full and half
  duplex. Expected values come from the table the test loads, not from the
  code under test. }
unit TestChnPcccClient;

{$MODE OBJFPC}{$H+}

interface

uses
  {$IFDEF UNIX}BaseUnix, PtyPair,{$ENDIF}
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop,
  ChnCom, ChnDF1Codec, ChnDF1, ChnDF1Link, ChnSlc, ChnPccc, ChnPcccClient,
  TestSupport, BinSupport, Df1Pair;

type
  TTestChnPcccClient = class(TDf1PairCase)
  private
    C: tPcccClient;
    { StartPair, and C a client on Master that steps the station }
    procedure StartClient(Full, Crc: Boolean; const Pair: string);
    procedure EveryAddressForm(const What: string);
  protected
    procedure SetUp; override;
  published
    procedure TestFullDuplexCrc;
    procedure TestFullDuplexBcc;
    procedure TestHalfDuplexCrc;
    procedure TestHalfDuplexBcc;
    procedure TestLongReadAndWriteSplit;
    procedure TestSmallFramesSplitMore;
    procedure TestSteppedRequestDoesNotBlock;
    procedure TestOneRequestAtATime;
    procedure TestCancel;
    procedure TestNoAck;
    procedure TestNakOnEveryTry;
    procedure TestNoReply;
    procedure TestErrorReply;
    procedure TestReplyOfWrongLength;
    procedure TestReplyToAnotherCommand;
    procedure TestRefusedBeforeSending;
    procedure TestNoDF1Channel;
    procedure TestExitCodesFollowTheToolsScheme;
    {$IFDEF UNIX}
    procedure TestAgainstDf1SimFullDuplex;
    procedure TestAgainstDf1SimHalfDuplex;
    procedure TestLineLost;
    {$ENDIF}
  end;

implementation

const
  Config =
    'S2 4'#10'S2:1 = $0102'#10 +
    'B3 4'#10'B3:0 = $8001 $0010'#10 +
    'T4 3'#10'T4:0 = $A000 100 42'#10'T4:1.PRE = 10'#10 +
    'C5 2'#10'C5:0 = $8000 10 3'#10 +
    'R6 2'#10'R6:0.LEN = 8'#10'R6:0.POS = 2'#10 +
    'N7 300'#10'N7:0 = 1 -2 3 32767 -32768'#10 +
    'F8 100'#10'F8:0 = 1.5 -2.25'#10 +
    'ST10 2'#10'ST10:0 = "hello"'#10 +
    'L11 2'#10'L11:0 = 100000 -2'#10;

procedure StepStation(Data: Pointer);
begin
  DF1StationStep(pDF1Station(Data)^);
end;

{ a station whose replies lose their last data byte }
function ShortHandler(Data: Pointer; constref Cmd: tRecRecord; CmdLen: Word;
  var Reply: tSendRecord; var ReplyLen: Word): Boolean;
begin
  Result := SlcHandle(pSlcTable(Data)^, Cmd, CmdLen, Reply, ReplyLen);
  if ReplyLen > cSizeHead then
    Dec(ReplyLen);
end;

{ a station that ACKs and never answers }
function MuteHandler(Data: Pointer; constref Cmd: tRecRecord; CmdLen: Word;
  var Reply: tSendRecord; var ReplyLen: Word): Boolean;
begin
  Result := False;
end;

{ a raw end that answers everything with DLE NAK }
procedure NakEverything(Data: Pointer);
var
  Chn: pChnVirt;
  Buf: array[0..511] of Byte;
  Len: Word;
  Nak: array[0..1] of Byte;
begin
  Chn := pChnVirt(Data);
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  if Chn^.ChReceiveReady = CHS_ReceiveReady then
  begin
    Len := 0;
    Chn^.ChReceive(Len);
    Nak[0] := $10;
    Nak[1] := $15;
    Chn^.ChSend(@Nak, 2);
  end;
end;

{ a slave answered by hand: ACK, then a reply with the next TNS }
procedure WrongTnsSlave(Data: Pointer);
var
  Chn: pChnVirt;
  Rec, Ans: tRecRecord;
  Len: Word;
begin
  Chn := pChnVirt(Data);
  Chn^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  if Chn^.ChReceiveReady <> CHS_ReceiveReady then
    Exit;
  Len := 0;
  Chn^.ChReceive(Len);
  if (Chn^.ChReceiveResult <> res_Ok) or (Rec.MessType <> tpDataMess) then
    Exit;
  FillChar(Ans, SizeOf(Ans), 0);
  Ans.MessType := tpAckNak;
  Ans.FlAck := True;
  ChSendWhenFree(Chn, @Ans, 2, 100);
  Ans.MessType := tpDataMess;
  Ans.CF := $4F00;
  Ans.Tns := Word(Rec.Tns + 1);
  ChSendWhenFree(Chn, @Ans, cSizeHead + 2, 100);
end;

{$IFDEF UNIX}
{ the USB adapter is pulled as the first frame arrives }
procedure PullOnFirstFrame(Data: Pointer);
var
  P: TPtyPair;
  B: array[0..63] of Byte;
begin
  P := TPtyPair(Data);
  if (P.Master >= 0) and (P.MasterRead(B, SizeOf(B)) > 0) then
    P.CloseMaster;
end;
{$ENDIF}

procedure TTestChnPcccClient.SetUp;
begin
  inherited SetUp;
  PcccClientInit(C, nil);
  LoadTable(Config);
end;

procedure TTestChnPcccClient.StartClient(Full, Crc: Boolean; const Pair: string);
begin
  StartPair(Full, Crc, Pair);
  PcccClientInit(C, Master);
  C.Idle := @StepStation;
  C.IdleData := @Station;
  C.TimeoutMs := 500;
end;

{ Every address form, read and written, the table checked after writes. }
procedure TTestChnPcccClient.EveryAddressForm(const What: string);
var
  V: array[0..9] of LongInt;
  F: array[0..2] of Single;
  S: ShortString;

  procedure Ok(R: tChResult; const Op: string);
  begin
    AssertEquals(What + ' ' + Op + ': ' + C.Err, res_Ok, R);
  end;

begin
  Ok(PcccReadInts(C, 'N7:0', 5, V), 'read N7:0');
  AssertEquals(1, V[0]); AssertEquals(-2, V[1]); AssertEquals(32767, V[3]); AssertEquals(-32768, V[4]);
  Ok(PcccWriteInts(C, 'N7:10', [-5, 6]), 'write N7:10');
  AssertEquals('N7:10 in the table', $FFFB, SlcGetWord(Table, 7, 10));
  AssertEquals('N7:11 in the table', 6, SlcGetWord(Table, 7, 11));
  Ok(PcccReadInts(C, 'B3:0', 2, V), 'read B3:0');
  AssertEquals($8001, V[0]); AssertEquals($0010, V[1]);
  Ok(PcccReadInts(C, 'B3:0/15', 3, V), 'read B3:0/15');
  AssertEquals(1, V[0]); AssertEquals('B3:1/0', 0, V[1]); AssertEquals('B3:1/1', 0, V[2]);
  Ok(PcccReadInts(C, 'B3/20', 1, V), 'read B3/20');
  AssertEquals('B3/20 = B3:1/4', 1, V[0]);
  Ok(PcccWriteInts(C, 'B3:1/2', [1]), 'set B3:1/2');
  AssertEquals('B3:1 with bit 2', $0014, SlcGetWord(Table, 3, 1));
  Ok(PcccWriteInts(C, 'B3:0/0', [0]), 'clear B3:0/0');
  AssertEquals('B3:0 without bit 0', $8000, SlcGetWord(Table, 3, 0));
  Ok(PcccReadFloats(C, 'F8:0', 2, F), 'read F8:0');
  AssertEquals(1.5, F[0], 0); AssertEquals(-2.25, F[1], 0);
  Ok(PcccWriteFloats(C, 'F8:5', [3.25]), 'write F8:5');
  AssertEquals(3.25, SlcGetFloat(Table, 8, 5), 0);
  Ok(PcccReadInts(C, 'L11:0', 2, V), 'read L11:0');
  AssertEquals(100000, V[0]); AssertEquals(-2, V[1]);
  Ok(PcccWriteInts(C, 'L11:1', [-123456]), 'write L11:1');
  Ok(PcccReadInts(C, 'L11:1', 1, V), 'read L11:1');
  AssertEquals(-123456, V[0]);
  Ok(PcccReadString(C, 'ST10:0', S), 'read ST10:0');
  AssertEquals('hello', S);
  Ok(PcccWriteString(C, 'ST10:1', 'Odd length'), 'write ST10:1');
  Ok(PcccReadString(C, 'ST10:1', S), 'read ST10:1');
  AssertEquals('Odd length', S);
  Ok(PcccReadInts(C, 'T4:0', 2, V), 'read T4:0 whole');
  AssertEquals(SmallInt($A000), V[0]); AssertEquals(100, V[1]); AssertEquals(42, V[2]);
  AssertEquals('T4:1.PRE', 10, V[4]);
  Ok(PcccReadInts(C, 'T4:0.ACC', 1, V), 'read T4:0.ACC');
  AssertEquals(42, V[0]);
  Ok(PcccReadInts(C, 'T4:0.PRE', 2, V), 'read T4:0.PRE');
  AssertEquals(100, V[0]); AssertEquals(10, V[1]);
  Ok(PcccReadInts(C, 'T4:0.DN', 1, V), 'read T4:0.DN');
  AssertEquals(1, V[0]);
  Ok(PcccReadInts(C, 'T4:0.EN', 2, V), 'read T4:0.EN');
  AssertEquals(1, V[0]); AssertEquals(0, V[1]);
  Ok(PcccWriteInts(C, 'T4:2.PRE', [500]), 'write T4:2.PRE');
  AssertEquals(500, SlcGetWord(Table, 4, 2, 1));
  Ok(PcccWriteInts(C, 'T4:2.DN', [1]), 'set T4:2.DN');
  AssertEquals($2000, SlcGetWord(Table, 4, 2, 0));
  Ok(PcccReadInts(C, 'C5:0.ACC', 1, V), 'read C5:0.ACC');
  AssertEquals(3, V[0]);
  Ok(PcccReadInts(C, 'C5:0.CU', 1, V), 'read C5:0.CU');
  AssertEquals(1, V[0]);
  Ok(PcccWriteInts(C, 'C5:1.PRE', [-7]), 'write C5:1.PRE');
  AssertEquals($FFF9, SlcGetWord(Table, 5, 1, 1));
  Ok(PcccWriteInts(C, 'C5:1.OV', [1]), 'set C5:1.OV');
  AssertEquals($1000, SlcGetWord(Table, 5, 1, 0));
  Ok(PcccReadInts(C, 'R6:0.LEN', 1, V), 'read R6:0.LEN');
  AssertEquals(8, V[0]);
  Ok(PcccReadInts(C, 'R6:0.POS', 1, V), 'read R6:0.POS');
  AssertEquals(2, V[0]);
  Ok(PcccWriteInts(C, 'R6:1', [$2000, 16, 4]), 'write R6:1 whole');
  AssertEquals(16, SlcGetWord(Table, 6, 1, 1));
  AssertEquals(4, SlcGetWord(Table, 6, 1, 2));
  Ok(PcccReadInts(C, 'R6:1.DN', 1, V), 'read R6:1.DN');
  AssertEquals(1, V[0]);
  Ok(PcccReadInts(C, 'S:1', 1, V), 'read S:1');
  AssertEquals($0102, V[0]);
end;

procedure TTestChnPcccClient.TestFullDuplexCrc;
begin
  StartClient(True, True, 'PCFC');
  EveryAddressForm('full CRC');
end;

procedure TTestChnPcccClient.TestFullDuplexBcc;
begin
  StartClient(True, False, 'PCFB');
  EveryAddressForm('full BCC');
end;

procedure TTestChnPcccClient.TestHalfDuplexCrc;
begin
  StartClient(False, True, 'PCHC');
  EveryAddressForm('half CRC');
end;

procedure TTestChnPcccClient.TestHalfDuplexBcc;
begin
  StartClient(False, False, 'PCHB');
  EveryAddressForm('half BCC');
end;

procedure TTestChnPcccClient.TestLongReadAndWriteSplit;
var
  W, V: array[0..299] of LongInt;
  F: array[0..99] of Single;
  I, N: LongInt;
begin
  StartClient(True, True, 'PCLONG');
  for I := 0 to 299 do
    W[I] := I * 100 - 15000;
  N := C.Requests;
  AssertEquals('write 300 words: ' + C.Err, res_Ok, PcccWriteInts(C, 'N7:0', W));
  AssertEquals('117 words per write request', 3, C.Requests - N);
  for I := 0 to 299 do
    AssertEquals('N7:' + IntToStr(I) + ' in the table', Word(W[I]), SlcGetWord(Table, 7, I));
  N := C.Requests;
  FillChar(V, SizeOf(V), 0);
  AssertEquals('read 300 words: ' + C.Err, res_Ok, PcccReadInts(C, 'N7:0', 300, V));
  AssertEquals('122 words per read request', 3, C.Requests - N);
  for I := 0 to 299 do
    AssertEquals('N7:' + IntToStr(I), W[I], V[I]);
  for I := 0 to 99 do
    F[I] := I / 4;
  AssertEquals('write 100 floats', res_Ok, PcccWriteFloats(C, 'F8:0', F));
  FillChar(F, SizeOf(F), 0);
  AssertEquals('read 100 floats', res_Ok, PcccReadFloats(C, 'F8:0', 100, F));
  for I := 0 to 99 do
    AssertEquals('F8:' + IntToStr(I), I / 4, F[I], 0);
end;

procedure TTestChnPcccClient.TestSmallFramesSplitMore;
var
  V: array[0..9] of LongInt;
  N: LongInt;
begin
  StartClient(False, True, 'PCSMALL');
  C.MaxBytes := 4;                     { two words a request }
  N := C.Requests;
  AssertEquals(res_Ok, PcccReadInts(C, 'N7:0', 5, V));
  AssertEquals('three requests', 3, C.Requests - N);
  AssertEquals(1, V[0]); AssertEquals(-32768, V[4]);
end;

procedure TTestChnPcccClient.TestSteppedRequestDoesNotBlock;
var
  R1, R2: tPcccRequest;
  Steps, I: LongInt;
  T0, Longest: QWord;
  Done1, Done2: Boolean;
begin
  StartClient(False, False, 'PCSTEP');
  AssertTrue('start read', PcccStartRead(R1, C, 'N7:0', 200));
  Steps := 0;
  Longest := 0;
  Done1 := False;
  while not Done1 do
  begin
    T0 := ChMsTick;
    Done1 := PcccStep(R1);
    if ChMsTick - T0 > Longest then
      Longest := ChMsTick - T0;
    Inc(Steps);
    DF1StationStep(Station);        { "the other lines" of the program }
    AssertTrue('done within 20000 steps', Steps < 20000);
  end;
  AssertEquals('read: ' + R1.Err, res_Ok, R1.Result);
  AssertTrue('it took several steps', Steps > 3);
  AssertTrue('no step waited (' + IntToStr(Longest) + ' ms)', Longest < 400);
  AssertEquals(200, Length(R1.Ints));
  AssertEquals(-2, R1.Ints[1]);
  AssertEquals('N7:0 = 1', PcccItemText(R1, 0));
  { a write, then a read of what it wrote, one after the other }
  AssertTrue(PcccStartWriteText(R2, C, 'F8:3', ['2.5', '-1e3']));
  Done2 := False;
  for I := 1 to 20000 do
  begin
    Done2 := PcccStep(R2);
    if Done2 then
      Break;
    DF1StationStep(Station);
  end;
  AssertTrue('write done', Done2);
  AssertEquals('write: ' + R2.Err, res_Ok, R2.Result);
  AssertEquals(-1000, SlcGetFloat(Table, 8, 4), 0);
  AssertTrue(PcccStartRead(R2, C, 'F8:3', 2));
  while not PcccStep(R2) do
    DF1StationStep(Station);
  AssertEquals('F8:4 = -1000', PcccItemText(R2, 1));
  { text values refused before anything is sent }
  AssertFalse(PcccStartWriteText(R2, C, 'N7:0', ['12x']));
  AssertEquals(res_PcccValue, R2.Result);
  AssertTrue(R2.Err, Pos('"12x"', R2.Err) > 0);
  AssertFalse(PcccStartWriteText(R2, C, 'ST10:0', ['a', 'b']));
  AssertEquals(res_PcccCount, R2.Result);
  { a float beyond Double is refused, not EOverflow inside Val }
  AssertFalse(PcccStartWriteText(R2, C, 'F8:0', ['2e308']));
  AssertEquals(res_PcccValue, R2.Result);
  AssertTrue(R2.Err, Pos('"2e308"', R2.Err) > 0);
end;

procedure TTestChnPcccClient.TestOneRequestAtATime;
var
  R1, R2: tPcccRequest;
  V: array[0..0] of LongInt;
  I: LongInt;
begin
  StartClient(True, True, 'PCONE');
  AssertTrue('first', PcccStartRead(R1, C, 'N7:1', 1));
  AssertFalse('second while the first runs', PcccStartRead(R2, C, 'N7:2', 1));
  AssertEquals(res_WrongState, R2.Result);
  AssertEquals('N7:2: another request is under way on this client', R2.Err);
  AssertEquals('blocking call too', res_WrongState, PcccReadInts(C, 'N7:0', 1, V));
  for I := 1 to 20000 do
  begin
    if PcccStep(R1) then
      Break;
    DF1StationStep(Station);
  end;
  AssertEquals('the first is unharmed: ' + R1.Err, res_Ok, R1.Result);
  AssertEquals(-2, R1.Ints[0]);
  AssertTrue('the client is free again', PcccStartRead(R2, C, 'N7:2', 1));
  AssertEquals(res_Ok, PcccFinish(R2));
  AssertEquals(3, R2.Ints[0]);
  { a refused request (bad address) does not hold the client }
  AssertFalse(PcccStartRead(R1, C, 'N7:x', 1));
  AssertEquals(res_Ok, PcccReadInts(C, 'N7:0', 1, V));
end;

procedure TTestChnPcccClient.TestCancel;
var
  R: tPcccRequest;
  Buf: array[0..15] of Byte;
  Err: string;
begin
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=PCCANCEL END=2', Err);
  AssertTrue(Err, Raw <> nil);
  Master := Open(Df1PairParams(True, True, True, 'PCCANCEL'));
  PcccClientInit(C, Master);
  Master^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  AssertTrue(PcccStartRead(R, C, 'N7:0', 1));
  AssertTrue('the request receives into itself', Master^.CH_RBuff <> @Buf);
  AssertFalse('nobody answers', PcccStep(R));
  PcccCancel(R);
  AssertTrue(PcccStep(R));
  AssertEquals(res_Timeout, R.Result);
  AssertEquals('N7:0: cancelled', R.Err);
  AssertTrue('the program''s receive buffer is back', Master^.CH_RBuff = @Buf);
  AssertTrue('the client takes the next one', PcccStartRead(R, C, 'N7:1', 1));
  PcccCancel(R);
  PcccCancel(R);                          { twice: nothing more happens }
  AssertEquals('N7:1: cancelled', R.Err);
end;

procedure TTestChnPcccClient.TestNoAck;
var
  V: array[0..0] of LongInt;
  T0: QWord;
  C0: Double;
begin
  StartClient(True, True, 'PCNOACK');
  C.Idle := nil;                      { the station is never stepped }
  C.TimeoutMs := 50;
  V[0] := 12345;
  T0 := ChMsTick;
  AssertEquals(res_Timeout, PcccReadInts(C, 'N7:0', 1, V));
  AssertEquals('N7:0: no ACK after 3 tries', C.Err);
  AssertTrue('bounded: three tries and ENQs of 50 ms', ChMsTick - T0 < 3000);
  {$IFDEF LINUX}
  { without Idle PcccFinish waits in the program-wide wait: the 300 ms
    and more of timers cost next to no CPU (a polling loop takes them
    all) }
  C0 := CpuMs;
  T0 := ChMsTick;
  AssertEquals(res_Timeout, PcccReadInts(C, 'N7:0', 1, V));
  AssertTrue(Format('waited, not polled: %.1f ms CPU in %d ms', [CpuMs - C0, ChMsTick - T0]),
    CpuMs - C0 < 0.3 * (ChMsTick - T0));
  {$ENDIF}
  AssertEquals('the caller''s value untouched', 12345, V[0]);
end;

{ PcccExitCode in the tools' one scheme (docs/TOOLS.md): 0 done, 1 the
  line failed, 2 a command-line error, 3 an error or unfitting answer, 4
  no answer in time. }
procedure TTestChnPcccClient.TestExitCodesFollowTheToolsScheme;
const
  Codes: array[0..13] of tChResult = (res_Ok, res_CannotOpen, res_DeviceLost, res_IOError,
    res_WrongState, res_PcccAddress, res_PcccCount, res_PcccValue, res_PcccUsage,
    res_WrongLayer, res_PcccStatus, res_PcccReply, res_PcccNak, res_Timeout);
  Want: array[0..13] of LongInt = (0, 1, 1, 1, 1, 2, 2, 2, 2, 2, 3, 3, 3, 4);
var
  I: Integer;
begin
  for I := Low(Codes) to High(Codes) do
    AssertEquals(ChResultText(Codes[I], PcccLayer), Want[I], PcccExitCode(Codes[I]));
  AssertEquals('a reply to another command', 3, PcccExitCode(res_BadMessage));
end;

procedure TTestChnPcccClient.TestNakOnEveryTry;
var
  V: array[0..0] of LongInt;
  Err: string;
begin
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=PCNAK END=2', Err);
  AssertTrue(Err, Raw <> nil);
  Master := Open(Df1PairParams(True, True, True, 'PCNAK'));
  PcccClientInit(C, Master);
  C.Idle := @NakEverything;
  C.IdleData := Raw;
  C.TimeoutMs := 200;
  AssertEquals(res_PcccNak, PcccReadInts(C, 'N7:0', 1, V));
  AssertEquals('N7:0: NAK on each of 3 tries', C.Err);
  AssertEquals(res_PcccNak, PcccWriteInts(C, 'B3:0/1', [1]));
end;

procedure TTestChnPcccClient.TestNoReply;
var
  V: array[0..0] of LongInt;
begin
  StartClient(True, False, 'PCMUTE');
  Station.Handler := @MuteHandler;
  C.TimeoutMs := 50;
  AssertEquals(res_Timeout, PcccReadInts(C, 'N7:0', 1, V));
  AssertEquals('N7:0: no reply', C.Err);
end;

procedure TTestChnPcccClient.TestErrorReply;
var
  V: array[0..3] of LongInt;
  F: array[0..0] of Single;
begin
  StartClient(False, True, 'PCERR');
  AssertEquals(res_PcccStatus, PcccReadInts(C, 'N99:0', 1, V));
  AssertEquals('N99:0: error reply STS $F0, EXT STS $06: address doesn''t point to something usable', C.Err);
  AssertEquals(res_PcccStatus, PcccReadInts(C, 'N7:299', 2, V));
  AssertTrue(C.Err, Pos('EXT STS $07', C.Err) > 0);
  AssertEquals(res_PcccStatus, PcccWriteFloats(C, 'F8:100', [1]));
  AssertEquals('the link is fine afterwards', res_Ok, PcccReadFloats(C, 'F8:0', 1, F));
end;

procedure TTestChnPcccClient.TestReplyOfWrongLength;
var
  V: array[0..4] of LongInt;
  I: LongInt;
begin
  StartClient(True, True, 'PCSHORT');
  Station.Handler := @ShortHandler;
  for I := 0 to 4 do
    V[I] := 777;
  AssertEquals(res_PcccReply, PcccReadInts(C, 'N7:0', 4, V));
  AssertEquals('N7:0: reply has 7 data bytes, 8 expected', C.Err);
  for I := 0 to 4 do
    AssertEquals('V[' + IntToStr(I) + '] untouched', 777, V[I]);
end;

procedure TTestChnPcccClient.TestReplyToAnotherCommand;
var
  V: array[0..0] of LongInt;
begin
  Slave := Open(Df1PairParams(False, True, True, 'PCTNS'));
  Master := Open(Df1PairParams(True, True, True, 'PCTNS'));
  PcccClientInit(C, Master);
  C.Idle := @WrongTnsSlave;
  C.IdleData := Slave;
  V[0] := 5;
  AssertEquals(res_BadMessage, PcccReadInts(C, 'N7:0', 1, V));
  AssertEquals('N7:0: the reply is not the one to this command', C.Err);
  AssertEquals('untouched', 5, V[0]);
end;

procedure TTestChnPcccClient.TestRefusedBeforeSending;
var
  V: array[0..1] of LongInt;
  F: array[0..1] of Single;
  S: ShortString;
  N: LongInt;
begin
  StartClient(True, True, 'PCREF');
  N := C.Requests;
  AssertEquals(res_PcccAddress, PcccReadInts(C, 'X7:0', 1, V));
  AssertTrue(C.Err, Pos('"X7:0"', C.Err) > 0);
  AssertEquals(res_PcccCount, PcccReadInts(C, 'N7:0', 3, V));
  AssertEquals('N7:0: 3 values to read, room for 2', C.Err);
  AssertEquals('a whole timer is three values', res_PcccCount, PcccReadInts(C, 'T4:0', 1, V));
  AssertEquals(res_PcccCount, PcccReadInts(C, 'N7:0', 0, V));
  AssertEquals(res_PcccValue, PcccWriteInts(C, 'N7:0', [1, 70000]));
  AssertEquals('N7:0: value 70000 for N7:1 is not -32768..32767', C.Err);
  AssertEquals(res_PcccValue, PcccWriteInts(C, 'B3:0/3', [2]));
  AssertEquals(res_PcccUsage, PcccReadInts(C, 'F8:0', 1, V));
  AssertEquals('F8:0: holds floats, not integers', C.Err);
  AssertEquals(res_PcccUsage, PcccReadFloats(C, 'N7:0', 1, F));
  AssertEquals(res_PcccUsage, PcccReadString(C, 'N7:0', S));
  AssertEquals(res_PcccUsage, PcccWriteString(C, 'F8:0', 'x'));
  AssertEquals(res_PcccValue, PcccWriteString(C, 'ST10:0', StringOfChar('x', 83)));
  AssertEquals(res_PcccCount, PcccWriteInts(C, 'R6:0', [1, 2]));
  AssertEquals('R6:0: 2 values given for whole elements of 3', C.Err);
  AssertEquals(res_PcccCount, PcccWriteInts(C, 'N7:0', []));
  AssertEquals('N7:0: no values given', C.Err);
  AssertEquals(res_PcccCount, PcccWriteFloats(C, 'F8:0', []));
  AssertEquals(res_PcccCount, PcccWriteInts(C, 'N7:65535', [1, 2]));
  AssertEquals('nothing was sent', N, C.Requests);
  AssertEquals('nothing written', 1, SlcGetWord(Table, 7, 0));
end;

procedure TTestChnPcccClient.TestNoDF1Channel;
var
  V: array[0..0] of LongInt;
  Err: string;
begin
  Raw := OpenStack('LOOP', 'NAM=LOOP PAIR=PCRAW END=1', Err);
  PcccClientInit(C, Raw);
  AssertEquals(res_WrongLayer, PcccReadInts(C, 'N7:0', 1, V));
  PcccClientInit(C, nil);
  AssertEquals(res_WrongLayer, PcccWriteInts(C, 'N7:0', [1]));
  AssertEquals(res_CannotOpen, PcccOpen(C, 'NAM=DF1 NAM=NOSUCH'));
  AssertTrue(C.Err, C.Err <> '');
  PcccClose(C);
end;

{$IFDEF UNIX}
{ df1sim's built-in table (docs/df1sim.md) over a pty, each address form }
procedure SimRoundTrip(T: TTestChnPcccClient; var C: tPcccClient; const What: string);
type
  tBitCase = record
    Addr: string[8];
    Want: LongInt;
  end;
const
  Bits: array[0..15] of tBitCase = (
    (Addr: 'T4:0.EN'; Want: 0), (Addr: 'T4:0.TT'; Want: 0), (Addr: 'T4:0.DN'; Want: 1),
    (Addr: 'C5:0.CU'; Want: 1), (Addr: 'C5:0.CD'; Want: 0), (Addr: 'C5:0.DN'; Want: 0),
    (Addr: 'C5:0.OV'; Want: 0), (Addr: 'C5:0.UN'; Want: 0), (Addr: 'R6:0.EN'; Want: 0),
    (Addr: 'R6:0.EU'; Want: 0), (Addr: 'R6:0.DN'; Want: 0), (Addr: 'R6:0.EM'; Want: 0),
    (Addr: 'R6:0.ER'; Want: 0), (Addr: 'R6:0.UL'; Want: 0), (Addr: 'R6:0.IN'; Want: 0),
    (Addr: 'R6:0.FD'; Want: 0));
var
  K: LongInt;
  V: array[0..5] of LongInt;
  F: array[0..1] of Single;
  S: ShortString;

  procedure Ok(R: tChResult; const Op: string);
  begin
    T.AssertEquals(What + ' ' + Op + ': ' + C.Err, res_Ok, R);
  end;

begin
  Ok(PcccReadInts(C, 'N7:0', 3, V), 'N7:0');
  T.AssertEquals(10, V[1]);
  Ok(PcccWriteInts(C, 'N7:20', [-3, 4]), 'write N7:20');
  Ok(PcccReadInts(C, 'N7:20', 2, V), 'N7:20');
  T.AssertEquals(-3, V[0]); T.AssertEquals(4, V[1]);
  Ok(PcccReadInts(C, 'B3:1/15', 1, V), 'B3:1/15');
  T.AssertEquals(1, V[0]);
  Ok(PcccWriteInts(C, 'B3:5/4', [1]), 'set B3:5/4');
  Ok(PcccReadInts(C, 'B3:5', 1, V), 'B3:5');
  T.AssertEquals($10, V[0]);
  Ok(PcccReadFloats(C, 'F8:0', 2, F), 'F8:0');
  T.AssertEquals(-2.25, F[1], 0);
  Ok(PcccWriteFloats(C, 'F8:9', [0.5]), 'write F8:9');
  Ok(PcccReadFloats(C, 'F8:9', 1, F), 'F8:9');
  T.AssertEquals(0.5, F[0], 0);
  Ok(PcccReadInts(C, 'T4:0.PRE', 1, V), 'T4:0.PRE');
  T.AssertEquals(100, V[0]);
  Ok(PcccWriteInts(C, 'T4:3.ACC', [9]), 'write T4:3.ACC');
  Ok(PcccReadInts(C, 'T4:3', 1, V), 'T4:3');
  T.AssertEquals(9, V[2]);
  Ok(PcccReadInts(C, 'T4:0.DN', 1, V), 'T4:0.DN');
  T.AssertEquals(1, V[0]);
  Ok(PcccReadInts(C, 'C5:0.CU', 1, V), 'C5:0.CU');
  T.AssertEquals(1, V[0]);
  Ok(PcccWriteInts(C, 'C5:2.PRE', [25]), 'write C5:2.PRE');
  Ok(PcccReadInts(C, 'C5:2.PRE', 1, V), 'C5:2.PRE');
  T.AssertEquals(25, V[0]);
  Ok(PcccReadInts(C, 'R6:0.LEN', 1, V), 'R6:0.LEN');
  T.AssertEquals(8, V[0]);
  Ok(PcccWriteInts(C, 'R6:1.POS', [3]), 'write R6:1.POS');
  Ok(PcccReadInts(C, 'R6:1.POS', 1, V), 'R6:1.POS');
  T.AssertEquals(3, V[0]);
  Ok(PcccReadString(C, 'ST10:0', S), 'ST10:0');
  T.AssertEquals('hello', S);
  Ok(PcccWriteString(C, 'ST10:1', 'over the pty'), 'write ST10:1');
  Ok(PcccReadString(C, 'ST10:1', S), 'ST10:1');
  T.AssertEquals('over the pty', S);
  Ok(PcccReadInts(C, 'L11:0', 2, V), 'L11:0');
  T.AssertEquals(100000, V[0]); T.AssertEquals(-2, V[1]);
  Ok(PcccWriteInts(C, 'L11:3', [-2000000000]), 'write L11:3');
  Ok(PcccReadInts(C, 'L11:3', 1, V), 'L11:3');
  T.AssertEquals(-2000000000, V[0]);
  { every bit sub-element: T4:0 control word $2000, C5:0 $8000, R6:0 0 }
  for K := 0 to High(Bits) do
  begin
    Ok(PcccReadInts(C, Bits[K].Addr, 1, V), Bits[K].Addr);
    T.AssertEquals(What + ' ' + Bits[K].Addr, Bits[K].Want, V[0]);
  end;
  Ok(PcccWriteInts(C, 'C5:3.UN', [1]), 'set C5:3.UN');
  Ok(PcccReadInts(C, 'C5:3', 1, V), 'C5:3');
  T.AssertEquals('C5:3 control word', $0800, V[0]);
  Ok(PcccReadInts(C, 'B3/16', 1, V), 'B3/16');
  T.AssertEquals('B3/16 = B3:1/0', 0, V[0]);
  Ok(PcccReadInts(C, 'S:0', 1, V), 'S:0');
  T.AssertEquals(res_PcccStatus, PcccReadInts(C, 'N7:50', 1, V));
end;

procedure TTestChnPcccClient.TestAgainstDf1SimFullDuplex;
var
  Pty: string;
begin
  AssertTrue(BinPath('df1sim') + ' missing (make tools)', FileExists(BinPath('df1sim')));
  Proc := StartSimPty(['--crc', '--timeout=20', '--quiet'], Pty);
  AssertTrue('df1sim printed its pty', Pty <> '');
  AssertEquals('open: ' + C.Err, res_Ok,
    PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM BD=19200 DEV=' + Pty));
  try
    SimRoundTrip(Self, C, 'df1sim full duplex');
  finally
    PcccClose(C);
  end;
end;

procedure TTestChnPcccClient.TestAgainstDf1SimHalfDuplex;
var
  Pty: string;
begin
  AssertTrue(BinPath('df1sim') + ' missing (make tools)', FileExists(BinPath('df1sim')));
  Proc := StartSimPty(['--half', '--bcc', '--node=5', '--timeout=20', '--quiet'], Pty);
  AssertTrue('df1sim printed its pty', Pty <> '');
  AssertEquals('open: ' + C.Err, res_Ok,
    PcccOpen(C, 'NAM=DF1 NOD=0 DNO=5 MAS=MASTER FHD=HALF CRC=OFF NAM=COM BD=19200 DEV=' + Pty));
  try
    SimRoundTrip(Self, C, 'df1sim half duplex');
  finally
    PcccClose(C);
  end;
end;

procedure TTestChnPcccClient.TestLineLost;
var
  P: TPtyPair;
  V: array[0..0] of LongInt;
  T0: QWord;
begin
  P := TPtyPair.Create;
  try
    Master := Open('NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + P.SlavePath);
    PcccClientInit(C, Master);
    C.Idle := @PullOnFirstFrame;
    C.IdleData := P;
    C.TimeoutMs := 300;
    T0 := ChMsTick;
    AssertEquals(res_DeviceLost, PcccReadInts(C, 'N7:0', 1, V));
    AssertEquals('N7:0: ' + Master^.ChResultStr(res_DeviceLost), C.Err);
    AssertTrue('at once, not after the tries: ' + IntToStr(ChMsTick - T0) + ' ms',
      ChMsTick - T0 < 800);
  finally
    P.Free;
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnPcccClient);
end.
