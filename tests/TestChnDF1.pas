{ Tests of tChnDF1 (unit ChnDF1) over the in-memory null modem NAM=LOOP:
  parameters, the wire bytes ChSend hands down, receiving and every receive
  error, refused sends that send nothing, a master and a slave completing the
  exchanges of manual section 6.3, and a half-duplex poll / data / ACK / EOT
  session with two slaves on one line. }
unit TestChnDF1;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnDF1, ChnDF1Codec, TestSupport,
  StackCase;

type
  { the test's DF1 slave: answers commands like a small PLC }
  TSlaveSim = record
    Chn: pChnVirt;
    RMess: tRecRecord;
    Reply: tSendRecord;
    ReplyLen: Word;
    HasReply: Boolean;       { half duplex: reply waits for a poll }
    AwaitAck: Boolean;       { half duplex: reply just sent, an ACK is ours }
    LastCmd: tRecRecord;     { last command received, as received }
    LastCmdLen: Word;
    Commands, Polls, Acks: Integer;
    Counters: array[0..31] of Byte;
    IntFile: array[0..63] of Byte;   { "N7:" of the typed read/write }
  end;

  { the half-duplex line. Four-wire multidrop: the master's transmit line
    goes to every slave, the slaves' transmit lines are merged into the
    master's receive line, slaves do not hear each other. Two-wire
    (TwoWire): every station hears every other one. }
  TBus = record
    Master, SlaveA, SlaveB: pChnVirt;  { raw LOOP ends facing the stations }
    TwoWire: Boolean;
  end;

  TTestChnDF1 = class(TStackCase)
  private
    function Open(const Params: string): pChnVirt;
    function OpenRaw(const Pair: string): pChnVirt;
    function ReadRaw(Raw: pChnVirt): string;
    procedure SendRaw(Raw: pChnVirt; const Hex: string);
    procedure SendRec(Chn: pChnVirt; const R: tSendRecord; Len: Word);
    function WaitMsg(Chn: pChnVirt; Slave: Pointer; Bus: Pointer = nil): Boolean;
    procedure SlaveStep(var S: TSlaveSim);
    procedure PumpBus(var B: TBus);
    procedure HalfDuplexSession(TwoWire: Boolean; const Tag: string);
    function MasterExchange(M: pChnVirt; var S: TSlaveSim; CF, Tns: Word;
      const Data: array of Byte; var Rep: tRecRecord): Word;
  published
    procedure TestRegistryAndDefaults;
    procedure TestParameters;
    procedure TestParameterErrorsChangeNothing;
    procedure TestSendHandsWireBytesDown;
    procedure TestReceiveByteByByte;
    procedure TestDuplicateDetectionComparesCmdAndFnc;
    procedure TestReplyForAnotherStationIsDropped;
    procedure TestBrokenFramesThenRecovery;
    procedure TestReceiveBufferTooSmall;
    procedure TestRefusedSendsSendNothing;
    procedure TestFlushDropsPartialFrame;
    procedure TestSendWhileBusyKeepsFrame;
    procedure TestManualExchangesFullDuplex;
    procedure TestHalfDuplexTwoSlavesFourWire;
    procedure TestHalfDuplexTwoSlavesTwoWire;
  end;

implementation

const
  TimeoutMs = 2000;
  EchoBcc = '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 6B';   { see TestChnDF1Codec }
  EchoCrc = '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E3 88';

function TTestChnDF1.Open(const Params: string): pChnVirt;
begin
  Result := Stack('DF1', Params);
end;

function TTestChnDF1.OpenRaw(const Pair: string): pChnVirt;
begin
  Result := Stack('LOOP', 'NAM=LOOP PAIR=' + Pair + ' END=2');
end;

function TTestChnDF1.ReadRaw(Raw: pChnVirt): string;
var
  Buf: array[0..1023] of Byte;
  N: Word;
begin
  Result := '';
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  while Raw^.ChReceiveReady = CHS_ReceiveReady do
  begin
    N := 0;
    Raw^.ChReceive(N);
    if Result <> '' then
      Result := Result + ' ';
    Result := Result + BytesToHex(Buf, N);
  end;
end;

procedure TTestChnDF1.SendRaw(Raw: pChnVirt; const Hex: string);
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  AssertTrue(Raw^.ChSendReady = CHS_SendReady);
  Raw^.ChSend(@B[0], Length(B));
  AssertEquals('raw send', res_Ok, Raw^.ChSendResult);
end;

procedure TTestChnDF1.SendRec(Chn: pChnVirt; const R: tSendRecord; Len: Word);
begin
  AssertTrue('transmitter idle', WaitSent(Chn, TimeoutMs));
  Chn^.ChSend(@R, Len);
  AssertEquals('send: ' + Chn^.ChResultStr(Chn^.ChSendResult), res_Ok, Chn^.ChSendResult);
end;

{ Poll Chn until a message waits, running the slave simulator and the bus
  meanwhile; False after TimeoutMs. }
function TTestChnDF1.WaitMsg(Chn: pChnVirt; Slave: Pointer; Bus: Pointer): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + TimeoutMs;
  repeat
    if Bus <> nil then
      PumpBus(TBus(Bus^));
    if Slave <> nil then
      SlaveStep(TSlaveSim(Slave^));
    if Bus <> nil then
      PumpBus(TBus(Bus^));
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
      Exit(True);
  until GetTickCount64 > Deadline;
  Result := False;
end;

procedure TTestChnDF1.PumpBus(var B: TBus);
var
  Buf: array[0..1023] of Byte;
  N: Word;

  procedure Move1(From: pChnVirt; const Dest: array of pChnVirt);
  var
    I: Integer;
  begin
    From^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    while From^.ChReceiveReady = CHS_ReceiveReady do
    begin
      N := 0;
      From^.ChReceive(N);
      for I := 0 to High(Dest) do
      begin
        AssertTrue(Dest[I]^.ChSendReady = CHS_SendReady);
        Dest[I]^.ChSend(@Buf, N);
      end;
    end;
  end;

begin
  Move1(B.Master, [B.SlaveA, B.SlaveB]);
  if B.TwoWire then
  begin
    Move1(B.SlaveA, [B.Master, B.SlaveB]);
    Move1(B.SlaveB, [B.Master, B.SlaveA]);
  end
  else
  begin
    Move1(B.SlaveA, [B.Master]);
    Move1(B.SlaveB, [B.Master]);
  end;
end;

{ One step of the slave: take at most one message and answer it. Full
  duplex: ACK, then the reply at once. Half duplex: ACK, the reply waits
  for a poll; a poll with nothing waiting gets EOT; the master's ACK of the
  reply clears it. }
procedure TTestChnDF1.SlaveStep(var S: TSlaveSim);
var
  Len: Word;
  Ack: tSendRecord;
  Cmd: Word;
  I, N: Integer;
  FullDup: Boolean;
begin
  if S.Chn^.ChReceiveReady <> CHS_ReceiveReady then
    Exit;
  FullDup := pChnDF1(S.Chn)^.CH_FullDup;
  Len := 0;
  S.Chn^.ChReceiveBuffer(@S.RMess, SizeOf(S.RMess));
  S.Chn^.ChReceive(Len);
  AssertEquals('slave receive: ' + S.Chn^.ChResultStr(S.Chn^.ChReceiveResult),
    res_Ok, S.Chn^.ChReceiveResult);
  FillChar(Ack, SizeOf(Ack), 0);
  { half duplex: the master's ACK is not addressed; it is for us only
    right after we answered a poll with our reply }
  if (S.RMess.MessType = tpAckNak) and S.AwaitAck and S.RMess.FlAck then
    S.HasReply := False;             { the master has our reply }
  S.AwaitAck := False;
  case S.RMess.MessType of
    tpAckNak:
      Inc(S.Acks);
    tpPoll:
      begin
        Inc(S.Polls);
        if S.HasReply then
        begin
          SendRec(S.Chn, S.Reply, S.ReplyLen);
          S.AwaitAck := True;
        end
        else
        begin
          Ack.MessType := tpNoPollRep;
          SendRec(S.Chn, Ack, 1);
        end;
      end;
    tpDataMess:
      begin
        Inc(S.Commands);
        S.LastCmd := S.RMess;
        S.LastCmdLen := Len;
        Ack.MessType := tpAckNak;
        Ack.FlAck := True;
        SendRec(S.Chn, Ack, 2);
        { build the reply as manual 6.3 says: CF or MskCF_Reply }
        FillChar(S.Reply, SizeOf(S.Reply), 0);
        S.Reply.MessType := tpDataMess;
        S.Reply.CF := S.RMess.CF or MskCF_Reply;
        S.Reply.Sts := 0;
        S.Reply.Tns := S.RMess.Tns;
        N := 0;
        Cmd := S.RMess.CF;
        case Cmd of
          CF_Echo:
            begin
              N := Len - 8;
              Move(S.RMess.Data, S.Reply.Data, N);
            end;
          CF_DiagnosticSts:
            begin
              N := 4;
              S.Reply.Data[0] := $EE;  S.Reply.Data[1] := $5A;
              S.Reply.Data[2] := $10;  S.Reply.Data[3] := $01;
            end;
          CF_ReadDiagnCounts:
            begin
              N := S.RMess.Data[2];    { Data[0,1] = address, Data[2] = size }
              for I := 0 to N - 1 do
                S.Reply.Data[I] := S.Counters[(S.RMess.Data[0] + I) mod 32];
            end;
          CF_ResetDiagnCounts:
            FillChar(S.Counters, SizeOf(S.Counters), 0);
          CF_ProtectRead3Addr:
            begin
              { Size, File No., File Type, Element, Sub-element }
              N := S.RMess.Data[0];
              Move(S.IntFile[S.RMess.Data[3] * 2], S.Reply.Data, N);
            end;
          CF_ProtectWrite3Addr:
            Move(S.RMess.Data[5], S.IntFile[S.RMess.Data[3] * 2], S.RMess.Data[0]);
        else
          begin
            S.Reply.Sts := $10;        { illegal command }
          end;
        end;
        S.ReplyLen := 8 + N;
        S.HasReply := True;
        if FullDup then
          SendRec(S.Chn, S.Reply, S.ReplyLen);
      end;
  end;
end;

{ Full duplex master side of one exchange: command, wait for ACK, wait for
  the reply, ACK it. Returns the reply's Len. }
function TTestChnDF1.MasterExchange(M: pChnVirt; var S: TSlaveSim; CF, Tns: Word;
  const Data: array of Byte; var Rep: tRecRecord): Word;
var
  Cmd, Ack: tSendRecord;
  Len: Word;
  I: Integer;
begin
  FillChar(Cmd, SizeOf(Cmd), 0);
  Cmd.MessType := tpDataMess;
  Cmd.CF := CF;
  Cmd.Sts := 0;
  Cmd.Tns := Tns;
  for I := 0 to High(Data) do
    Cmd.Data[I] := Data[I];
  SendRec(M, Cmd, 8 + Length(Data));
  M^.ChReceiveBuffer(@Rep, SizeOf(Rep));
  AssertTrue('ACK arrives', WaitMsg(M, @S));
  Len := 0;
  M^.ChReceive(Len);
  AssertEquals(res_Ok, M^.ChReceiveResult);
  AssertTrue('ACK', (Rep.MessType = tpAckNak) and Rep.FlAck);
  AssertTrue('reply arrives', WaitMsg(M, @S));
  M^.ChReceive(Len);
  AssertEquals(res_Ok, M^.ChReceiveResult);
  AssertTrue('data reply', Rep.MessType = tpDataMess);
  FillChar(Ack, SizeOf(Ack), 0);
  Ack.MessType := tpAckNak;
  Ack.FlAck := True;
  SendRec(M, Ack, 2);
  { the slave takes the ACK }
  WaitMsg(S.Chn, nil);
  SlaveStep(S);
  { what the slave saw: the command as sent, FNC included in CF }
  AssertEquals('slave got CF', CF, S.LastCmd.CF);
  AssertEquals('slave got Len', 8 + Length(Data), S.LastCmdLen);
  AssertEquals('slave got TNS', Tns, S.LastCmd.Tns);
  for I := 0 to High(Data) do
    AssertEquals('slave got data', Data[I], S.LastCmd.Data[I]);
  Result := Len;
end;

procedure TTestChnDF1.TestRegistryAndDefaults;
var
  C: pChnVirt;
  D: pChnDF1;
begin
  C := ChnCollection^.ChNewInit(ChnDF1.cName);
  AssertTrue(C <> nil);
  Keep(C);
  D := pChnDF1(C);
  AssertEquals('DF1', C^.CH_Type);
  AssertEquals('DF1', C^.CH_Name);
  AssertEquals(ChNumName('DF1'), C^.CH_NumName);
  AssertTrue('master', D^.CH_Master);
  AssertTrue('full duplex', D^.CH_FullDup);
  AssertTrue('CRC', D^.CH_FlCrc);
  AssertFalse(D^.CH_DLE);
  AssertFalse(D^.CH_RTick);
  AssertTrue(D^.CH_SBuff = nil);
  AssertEquals(0, D^.CH_MSBuff);
  AssertEquals(0, D^.CH_LRMess);
  AssertEquals(0, C^.IData);
  AssertEquals('NAM=DF1 NOD=0 DNO=0 MAS=MASTER FHD=FULL CRC=ON NAK=15 DUP=OFF', C^.ChGetParam(''));
  AssertEquals('DF1: checksum (BCC/CRC) error', C^.ChResultStr(res_ErrSum));
  AssertEquals('DF1: malformed frame', C^.ChResultStr(res_ErrFrame));
  AssertTrue(Pos('too long', C^.ChResultStr(res_ErrLen)) > 0);
end;

procedure TTestChnDF1.TestParameters;
var
  C, C2: pChnVirt;
  D: pChnDF1;
  P: string;
begin
  C := Keep(ChnCollection^.ChNewInit('DF1'));
  C2 := Keep(ChnCollection^.ChNewInit('DF1'));
  D := pChnDF1(C);
  C^.ChSetParam('NAM=DF1 LSB=500 NOD=3 DNO=16 MAS=SLAVE FHD=HALF CRC=OFF NAK=0F NAM=LOOP PAIR=DF1P END=2');
  AssertEquals(C^.ChParamError, res_Ok, C^.ChResult);
  AssertFalse(D^.CH_Master);
  AssertFalse(D^.CH_FullDup);
  AssertFalse(D^.CH_FlCrc);
  AssertEquals(3, C^.CH_Node);
  AssertEquals(16, C^.CH_DNode);
  AssertEquals($0F, D^.CH_NakByte);
  AssertEquals(500, D^.CH_MSBuff);
  AssertTrue(D^.CH_SBuff <> nil);
  P := C^.ChGetParam('');
  AssertEquals('NAM=DF1 NOD=3 DNO=16 MAS=SLAVE FHD=HALF CRC=OFF NAK=0F DUP=OFF LSB=500 ' +
    'NAM=LOOP PAIR=DF1P END=2 LRB=4096 IDL=0', P);
  C2^.ChSetParam(P);
  AssertEquals(res_Ok, C2^.ChResult);
  AssertEquals('rebuilt from ChGetParam', P, C2^.ChGetParam(''));
  { lower case values, 255 is a valid node (broadcast) }
  C2^.ChSetParam('mas=master fhd=full crc=on nak=15 NOD=255');
  AssertEquals(res_Ok, C2^.ChResult);
  AssertTrue(pChnDF1(C2)^.CH_Master);
  AssertEquals(NAK, pChnDF1(C2)^.CH_NakByte);
  AssertEquals('CRC', 'CRC=ON', C2^.ChGetParam('crc'));
end;

procedure TTestChnDF1.TestParameterErrorsChangeNothing;
var
  C: pChnVirt;

  procedure Bad(const S: string; Code: tChResult);
  begin
    C^.ChSetParam(S);
    AssertEquals(S, Code, C^.ChResult);
    AssertTrue(S + ' names the token', C^.ChParamError <> '');
    AssertEquals(S + ' changed nothing',
      'NAM=DF1 NOD=1 DNO=2 MAS=MASTER FHD=FULL CRC=ON NAK=15 DUP=OFF', C^.ChGetParam(''));
  end;

begin
  C := Keep(ChnCollection^.ChNewInit('DF1'));
  C^.ChSetParam('NOD=1 DNO=2');
  AssertEquals(res_Ok, C^.ChResult);
  Bad('CRC=OFF MAS=BOSS', res_BadParam);
  Bad('FHD=QUARTER', res_BadParam);
  Bad('NOD=256', res_BadParam);
  Bad('DNO=-1', res_BadParam);
  Bad('LSB=15', res_BadParam);
  Bad('LSB=65501', res_BadParam);
  Bad('NAK=16', res_BadParam);
  Bad('CRC=ONNAM=COM', res_BadParam);
  Bad('CRC=OFF CRC=ON', res_DupParam);
  Bad('XYZ=1', res_UnknownParam);
  { LSB cannot change under an open channel }
  C^.ChSetParam('NAM=DF1 NAM=LOOP PAIR=DF1E');
  C^.ChOpen;
  AssertEquals(res_Ok, C^.ChResult);
  C^.ChSetParam('LSB=100');
  AssertEquals(res_WrongState, C^.ChResult);
  C^.ChSetParam('CRC=OFF');
  AssertEquals('other keys may change', res_Ok, C^.ChResult);
  C^.ChClose;
  C^.ChSetParam('LSB=100');
  AssertEquals('closed', res_Ok, C^.ChResult);
  C^.ChOpen;
  C^.ChSetParam('LSB=100');
  AssertEquals('the size in force, while open', res_Ok, C^.ChResult);
  C^.ChSetParam('LSB=101');
  AssertEquals('another size, while open', res_WrongState, C^.ChResult);
  AssertEquals(100, pChnDF1(C)^.CH_MSBuff);
end;

procedure TTestChnDF1.TestSendHandsWireBytesDown;
var
  M, Raw: pChnVirt;
  R: tSendRecord;
  D: pChnDF1;
begin
  M := Open('NAM=DF1 NOD=1 DNO=2 CRC=OFF NAM=LOOP PAIR=DF1S END=1');
  Raw := OpenRaw('DF1S');
  D := pChnDF1(M);
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  R.Tns := 10;
  R.Data[0] := Ord('A'); R.Data[1] := Ord('h'); R.Data[2] := Ord('o'); R.Data[3] := Ord('j');
  SendRec(M, R, 12);
  AssertEquals(EchoBcc, ReadRaw(Raw));
  AssertEquals('CH_SSumBcc', $6B, D^.CH_SSumBcc);
  AssertTrue('default send buffer holds the worst case', D^.CH_MSBuff >= 512);
  M^.ChSetParam('CRC=ON');
  SendRec(M, R, 12);
  AssertEquals(EchoCrc, ReadRaw(Raw));
  AssertEquals('CH_SSumCrc', $88E3, D^.CH_SSumCrc);
  R.MessType := tpAckNak;
  R.FlAck := True;
  SendRec(M, R, 0);
  AssertEquals('10 06', ReadRaw(Raw));
  R.FlAck := False;
  SendRec(M, R, 0);
  AssertEquals('10 15', ReadRaw(Raw));
  M^.ChSetParam('NAK=0F');
  SendRec(M, R, 0);
  AssertEquals('10 0F', ReadRaw(Raw));
  R.MessType := tpEnq;
  SendRec(M, R, 0);
  AssertEquals('10 05', ReadRaw(Raw));
end;

procedure TTestChnDF1.TestReceiveByteByByte;
var
  S, Raw: pChnVirt;
  B: TBytes;
  I: Integer;
  R: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;
begin
  S := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=DF1R END=1');
  Raw := OpenRaw('DF1R');
  S^.ChReceiveBuffer(@R, SizeOf(R));
  B := HexToBytes(EchoCrc);
  for I := 0 to High(B) do
  begin
    AssertTrue('nothing before the last byte', S^.ChReceiveReady <> CHS_ReceiveReady);
    Raw^.ChSend(@B[I], 1);
  end;
  AssertTrue(WaitReceive(S, TimeoutMs));
  Len := 0;
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals(12, Len);
  AssertEquals(12, pChnDF1(S)^.CH_LRMess);
  AssertTrue(R.MessType = tpDataMess);
  AssertEquals(CF_Echo, R.CF);
  AssertEquals(10, R.Tns);
  AssertEquals(Ord('j'), R.Data[3]);
  S^.ChGetNode(SNode, DNode);
  AssertEquals('SNode', 1, SNode);
  AssertEquals('DNode', 2, DNode);
  AssertEquals('CH_RSumCrc', $88E3, pChnDF1(S)^.CH_RSumCrc);
  AssertTrue('nothing more', S^.ChReceiveReady <> CHS_ReceiveReady);
  S^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals(res_NoMessage, S^.ChReceiveResult);
end;

{ DUP=ON: a command is a repetition only with the same SRC, CMD, FNC and
  TNS as the last one from that SRC. Same TNS from SRC 0, BCC frames by
  hand (BCC = two's complement of the sum DST..DATA): Echo 06/00 'A'
  (sum $4D, BCC $B3); 0F/00 'A' (another CMD only: sum $56, BCC $AA);
  0F/A2 02 07 89 00 00 (another FNC only: sum $149, BCC $B7); that again. }
procedure TTestChnDF1.TestDuplicateDetectionComparesCmdAndFnc;
var
  S, Raw: pChnVirt;
  R: tRecRecord;
  Len: Word;

  procedure Delivered(const Frame: string; CF: Word);
  begin
    SendRaw(Raw, Frame);
    AssertTrue(Format('CF $%.4x delivered', [CF]), WaitReceive(S, TimeoutMs));
    Len := 0;
    S^.ChReceive(Len);
    AssertEquals(res_Ok, S^.ChReceiveResult);
    AssertEquals(Format('CF $%.4x', [CF]), CF, R.CF);
    AssertEquals(5, R.Tns);
    AssertEquals(Format('after CF $%.4x: no repetition counted', [CF]), 0, pChnDF1(S)^.CH_DupCount);
  end;

begin
  S := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE CRC=OFF DUP=ON NAM=LOOP PAIR=DF1DUP END=1');
  Raw := OpenRaw('DF1DUP');
  S^.ChReceiveBuffer(@R, SizeOf(R));
  Delivered('10 02 01 00 06 00 05 00 00 41 10 03 B3', $0600);
  Delivered('10 02 01 00 0F 00 05 00 00 41 10 03 AA', $0F00);
  Delivered('10 02 01 00 0F 00 05 00 A2 02 07 89 00 00 10 03 B7', $0FA2);
  { the same command again: a repetition, ACKed by the layer, not delivered }
  SendRaw(Raw, '10 02 01 00 0F 00 05 00 A2 02 07 89 00 00 10 03 B7');
  AssertFalse('a repetition is not delivered', WaitReceive(S, 200));
  AssertEquals('counted', 1, pChnDF1(S)^.CH_DupCount);
  AssertEquals('and ACKed', '10 06', ReadRaw(Raw));
end;

procedure TTestChnDF1.TestBrokenFramesThenRecovery;
var
  S, Raw: pChnVirt;
  R: tRecRecord;
  Len: Word;
  Long: string;
  I: Integer;

  procedure Expect(Code: tChResult; WantLen: Word; const What: string);
  begin
    AssertTrue(What + ' arrives', WaitReceive(S, TimeoutMs));
    Len := 99;
    S^.ChReceive(Len);
    AssertEquals(What + ' result', Code, S^.ChReceiveResult);
    AssertEquals(What + ' Len', WantLen, Len);
  end;

begin
  S := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE CRC=ON NAM=LOOP PAIR=DF1B END=1');
  Raw := OpenRaw('DF1B');
  S^.ChReceiveBuffer(@R, SizeOf(R));
  SendRaw(Raw, '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E3 89 ' + EchoCrc);
  Expect(res_ErrSum, 0, 'bad CRC');
  Expect(res_Ok, 12, 'next frame');
  SendRaw(Raw, '10 02 02 01 06 00 0A 00 00 41 10 07 6F 6A 10 03 E3 88 ' + EchoCrc);
  Expect(res_ErrFrame, 0, 'DLE 07');
  Expect(res_Ok, 12, 'next frame');
  SendRaw(Raw, '10 03 10 06');
  Expect(res_ErrFrame, 0, 'ETX without STX');
  Expect(res_Ok, 2, 'ACK after it');
  Long := '10 02';
  for I := 1 to 300 do
    Long := Long + ' 01';
  SendRaw(Raw, Long + ' 10 03 00 00 ' + EchoCrc);
  Expect(res_ErrLen, 0, '300 bytes');
  Expect(res_Ok, 12, 'next frame');
  SendRaw(Raw, '10 02 02 01 06 ' + EchoCrc);
  Expect(res_ErrFrame, 0, 'interrupted by DLE STX');
  Expect(res_Ok, 12, 'the new frame');
  AssertEquals(Ord('A'), R.Data[0]);
end;

procedure TTestChnDF1.TestReceiveBufferTooSmall;
var
  S, Raw: pChnVirt;
  Buf: array[0..63] of Byte;
  Len: Word;
  I: Integer;
begin
  S := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=DF1T END=1');
  Raw := OpenRaw('DF1T');
  FillChar(Buf, SizeOf(Buf), $AA);
  S^.ChReceiveBuffer(@Buf, 11);
  SendRaw(Raw, EchoCrc + ' 10 06');
  AssertTrue(WaitReceive(S, TimeoutMs));
  Len := 99;
  S^.ChReceive(Len);
  AssertEquals('12 bytes into 11', res_ErrLen, S^.ChReceiveResult);
  AssertEquals(0, Len);
  for I := 0 to High(Buf) do
    AssertEquals('nothing written', $AA, Buf[I]);
  AssertTrue(WaitReceive(S, TimeoutMs));
  S^.ChReceive(Len);
  AssertEquals('ACK fits', res_Ok, S^.ChReceiveResult);
  AssertEquals(2, Len);
  AssertEquals(Ord(tpAckNak), Buf[0]);
  AssertEquals(1, Buf[1]);
  for I := 2 to High(Buf) do
    AssertEquals('only 2 bytes written', $AA, Buf[I]);
end;

procedure TTestChnDF1.TestRefusedSendsSendNothing;
var
  M, Raw, Closed: pChnVirt;
  R: tSendRecord;

  procedure Refused(Len: Word; Code: tChResult; const What: string);
  begin
    M^.ChSend(@R, Len);
    AssertEquals(What, Code, M^.ChSendResult);
  end;

begin
  M := Open('NAM=DF1 NOD=1 DNO=2 LSB=20 NAM=LOOP PAIR=DF1N END=1');
  Raw := OpenRaw('DF1N');
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  Refused(7, res_BadLen, 'Len 7');
  Refused(8 + 245, res_BadLen, 'Len 253');
  Refused(8 + 8, res_TooLong, '21 wire bytes, LSB=20');
  R.MessType := tpPoll;
  Refused(0, res_BadMessage, 'poll in full duplex');
  R.MessType := tpNoPollRep;
  Refused(0, res_BadMessage, 'EOT in full duplex');
  PByte(@R.MessType)^ := 9;
  Refused(12, res_BadMessage, 'MessType 9');
  M^.ChSend(nil, 12);
  AssertEquals('nil buffer', res_BadLen, M^.ChSendResult);
  { tNode is a Word; DF1 addresses are one byte: 256 is not station 0 }
  R.MessType := tpDataMess;
  M^.ChDestNode(256);
  Refused(8, res_BadMessage, 'ChDestNode(256)');
  M^.ChDestNode(2);
  AssertEquals('nothing on the line', '', ReadRaw(Raw));
  { the channel still works }
  R.MessType := tpDataMess;
  SendRec(M, R, 8 + 5);
  AssertTrue(ReadRaw(Raw) <> '');
  { half duplex: no ENQ from the master, no poll, EOT or NAK from a slave }
  M := Open('NAM=DF1 NOD=1 DNO=2 FHD=HALF NAM=LOOP PAIR=DF1H END=1');
  Raw := OpenRaw('DF1H');
  R.MessType := tpEnq;
  Refused(0, res_BadMessage, 'ENQ from a half-duplex master');
  R.MessType := tpNoPollRep;
  Refused(0, res_BadMessage, 'EOT from a half-duplex master');
  M^.ChSetParam('MAS=SLAVE');
  R.MessType := tpPoll;
  Refused(0, res_BadMessage, 'poll from a half-duplex slave');
  R.MessType := tpAckNak;
  R.FlAck := False;
  Refused(0, res_BadMessage, 'NAK from a half-duplex slave');
  M^.ChSetParam('MAS=MASTER');
  M^.ChDestNode(300);
  R.MessType := tpPoll;
  Refused(0, res_BadMessage, 'poll of station 300');
  M^.ChDestNode(2);
  M^.ChSetParam('MAS=SLAVE');
  AssertEquals('nothing on the half-duplex line', '', ReadRaw(Raw));
  R.MessType := tpNoPollRep;
  SendRec(M, R, 0);
  AssertEquals('10 04', ReadRaw(Raw));
  Closed := ChnCollection^.ChNewInit('DF1');
  try
    Closed^.ChSend(@R, 12);
    AssertEquals('closed', res_WrongState, Closed^.ChSendResult);
  finally
    Dispose(Closed, Done);
  end;
end;

procedure TTestChnDF1.TestFlushDropsPartialFrame;
var
  S, Raw: pChnVirt;
  R: tRecRecord;
  Len: Word;
begin
  S := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=DF1F END=1');
  Raw := OpenRaw('DF1F');
  S^.ChReceiveBuffer(@R, SizeOf(R));
  SendRaw(Raw, '10 02 02 01 06 00 0A');
  AssertFalse(WaitReceive(S, 20));
  AssertTrue('inside a frame', S^.ChReceiveReady = CHS_Receiving);
  AssertTrue('private state', S^.CH_RCtrl >= CHS_ProtoBase);
  S^.ChReceiveFlush;
  { the tail that would have completed the frame: alone it is an ETX
    without STX }
  SendRaw(Raw, Copy(EchoCrc, 22, 100));
  SendRaw(Raw, EchoCrc);
  AssertTrue(WaitReceive(S, TimeoutMs));
  Len := 0;
  S^.ChReceive(Len);
  AssertEquals('partial frame was dropped', res_ErrFrame, S^.ChReceiveResult);
  AssertTrue(WaitReceive(S, TimeoutMs));
  S^.ChReceive(Len);
  AssertEquals(res_Ok, S^.ChReceiveResult);
  AssertEquals(12, Len);
end;

procedure TTestChnDF1.TestSendWhileBusyKeepsFrame;
var
  M, Raw: pChnVirt;
  R: tSendRecord;
  Got: string;
  Deadline: QWord;
begin
  M := Open('NAM=DF1 NOD=1 DNO=2 CRC=OFF NAM=LOOP PAIR=DF1Y END=1');
  { a 4-byte receive ring at the far end: the frame stays pending. (LOOP
    copies what it is given, so this cannot show that CH_SBuff is left
    alone; it shows res_Busy and an intact first frame.) }
  Raw := Stack('LOOP', 'NAM=LOOP PAIR=DF1Y END=2 LRB=4');
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  R.Tns := 10;
  R.Data[0] := Ord('A'); R.Data[1] := Ord('h'); R.Data[2] := Ord('o'); R.Data[3] := Ord('j');
  M^.ChSend(@R, 12);
  AssertEquals(res_Ok, M^.ChSendResult);
  AssertTrue('still sending', M^.ChSendReady = CHS_Sending);
  R.Tns := 11;
  R.MessType := tpAckNak;
  M^.ChSend(@R, 2);
  AssertEquals('busy', res_Busy, M^.ChSendResult);
  { the first frame arrives intact }
  Got := '';
  Deadline := GetTickCount64 + TimeoutMs;
  while (Length(Got) < Length(EchoBcc)) and (GetTickCount64 < Deadline) do
  begin
    M^.ChSendReady;
    Got := Trim(Got + ' ' + ReadRaw(Raw));
  end;
  AssertEquals(EchoBcc, Got);
  AssertTrue(M^.ChSendReady = CHS_SendReady);
end;

procedure TTestChnDF1.TestManualExchangesFullDuplex;
var
  M: pChnVirt;
  S: TSlaveSim;
  Rep: tRecRecord;
  Len: Word;
  I: Integer;
begin
  FillChar(S, SizeOf(S), 0);
  M := Open('NAM=DF1 NOD=1 DNO=2 MAS=MASTER FHD=FULL CRC=ON NAM=LOOP PAIR=DF163 END=1');
  S.Chn := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=DF163 END=2');
  for I := 0 to 31 do
    S.Counters[I] := I + 1;
  for I := 0 to 63 do
    S.IntFile[I] := $C0 + I;

  { 6.3.1 Echo }
  Len := MasterExchange(M, S, CF_Echo, 10, [Ord('A'), Ord('h'), Ord('o'), Ord('j')], Rep);
  AssertEquals('echo reply Len 8+4', 12, Len);
  AssertEquals('reply CF: CMD $46, no FNC', CF_Echo or MskCF_Reply, Rep.CF);
  AssertEquals(10, Rep.Tns);
  AssertEquals(0, Rep.Sts);
  AssertEquals(Ord('j'), Rep.Data[3]);

  { 6.3.2 Diagnostic Status: 8 bytes out, 8 + data back }
  Len := MasterExchange(M, S, CF_DiagnosticSts, 11, [], Rep);
  AssertEquals(8 + 4, Len);
  AssertEquals('reply CF gets FNC 03 back from the command', CF_DiagnosticSts or MskCF_Reply, Rep.CF);
  AssertEquals(11, Rep.Tns);
  AssertEquals($10, Rep.Data[2]);

  { 6.3.3 Read Diagnostic Counters: address 0000h, size 10 }
  Len := MasterExchange(M, S, CF_ReadDiagnCounts, 12, [$00, $00, 10], Rep);
  AssertEquals(8 + 10, Len);
  AssertEquals(12, Rep.Tns);
  for I := 0 to 9 do
    AssertEquals('counter', I + 1, Rep.Data[I]);

  { 6.3.4 Reset Diagnostic Counters, then they read 0 }
  Len := MasterExchange(M, S, CF_ResetDiagnCounts, 13, [], Rep);
  AssertEquals(8, Len);
  AssertEquals(13, Rep.Tns);
  Len := MasterExchange(M, S, CF_ReadDiagnCounts, $1010, [$00, $00, 4], Rep);
  AssertEquals(8 + 4, Len);
  AssertEquals('TNS with DLE bytes', $1010, Rep.Tns);
  for I := 0 to 3 do
    AssertEquals('reset counter', 0, Rep.Data[I]);

  { 6.3.5 Protected Typed Logical Read, three address fields:
    size 5, file 7, type $89 (integer), element 0, sub-element 0 }
  Len := MasterExchange(M, S, CF_ProtectRead3Addr, 14, [5, $07, $89, 0, 0], Rep);
  AssertEquals(8 + 5, Len);
  AssertEquals('reply CF gets FNC $A2 back', CF_ProtectRead3Addr or MskCF_Reply, Rep.CF);
  AssertEquals(14, Rep.Tns);
  for I := 0 to 4 do
    AssertEquals('file data', $C0 + I, Rep.Data[I]);

  { 6.3.6 Protected Typed Logical Write, three address fields: 5 header
    bytes + 5 data bytes (the manual's "13" should read 8+5+5) }
  Len := MasterExchange(M, S, CF_ProtectWrite3Addr, 15,
    [5, $07, $89, 0, 0, $10, $10, $03, $02, $01], Rep);
  AssertEquals(8, Len);
  AssertEquals(15, Rep.Tns);
  AssertEquals(0, Rep.Sts);
  Len := MasterExchange(M, S, CF_ProtectRead3Addr, 16, [5, $07, $89, 0, 0], Rep);
  AssertEquals(8 + 5, Len);
  AssertEquals('written', $10, Rep.Data[0]);
  AssertEquals('written', $10, Rep.Data[1]);
  AssertEquals('written', $01, Rep.Data[4]);

  AssertEquals('commands seen by the slave', 8, S.Commands);
  AssertEquals('ACKs seen by the slave', 8, S.Acks);
end;

{ Poll / data / ACK / EOT with slaves 2 and 16 on one line. On a two-wire
  line each slave also hears the other's ACKs, replies and EOTs: replies
  and EOTs must not reach its application, ACKs do (they carry no
  address), and must not make it drop its own reply. }
procedure TTestChnDF1.HalfDuplexSession(TwoWire: Boolean; const Tag: string);
var
  M: pChnVirt;
  A, B: TSlaveSim;
  Bus: TBus;
  R: tSendRecord;
  Rep: tRecRecord;
  Len: Word;
  SNode, DNode: tNode;

  procedure Poll(Station: tNode);
  begin
    M^.ChDestNode(Station);
    FillChar(R, SizeOf(R), 0);
    R.MessType := tpPoll;
    SendRec(M, R, 0);
  end;

  procedure MasterGets(const What: string);
  begin
    AssertTrue(What + ' arrives', WaitMsg(M, nil, @Bus));
    Len := 0;
    M^.ChReceive(Len);
    AssertEquals(What + ': ' + M^.ChResultStr(M^.ChReceiveResult), res_Ok, M^.ChReceiveResult);
  end;

  procedure SlavesRun;
  var
    I: Integer;
  begin
    for I := 1 to 20 do
    begin
      PumpBus(Bus);
      SlaveStep(A);
      SlaveStep(B);
    end;
    PumpBus(Bus);
  end;

begin
  FillChar(A, SizeOf(A), 0);
  FillChar(B, SizeOf(B), 0);
  M := Open('NAM=DF1 NOD=1 DNO=2 MAS=MASTER FHD=HALF CRC=ON NAM=LOOP PAIR=' + Tag + 'M END=1');
  A.Chn := Open('NAM=DF1 NOD=2 DNO=1 MAS=SLAVE FHD=HALF CRC=ON NAM=LOOP PAIR=' + Tag + 'A END=1');
  { station 16 = $10: its STN is stuffed in every frame and poll }
  B.Chn := Open('NAM=DF1 NOD=16 DNO=1 MAS=SLAVE FHD=HALF CRC=ON NAM=LOOP PAIR=' + Tag + 'B END=1');
  Bus.Master := OpenRaw(Tag + 'M');
  Bus.SlaveA := OpenRaw(Tag + 'A');
  Bus.SlaveB := OpenRaw(Tag + 'B');
  Bus.TwoWire := TwoWire;
  M^.ChReceiveBuffer(@Rep, SizeOf(Rep));

  { 1. data frame to station 2: station 2 ACKs, station 16 ignores it }
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  R.Tns := 21;
  R.Data[0] := $10;
  R.Data[1] := $55;
  SendRec(M, R, 10);
  SlavesRun;
  MasterGets('ACK from 2');
  AssertTrue('ACK', (Rep.MessType = tpAckNak) and Rep.FlAck);
  AssertEquals(1, A.Commands);
  AssertEquals('16 got no command or poll', 0, B.Commands + B.Polls);
  AssertEquals('16 heard the ACK of 2 only on two wires', Ord(TwoWire), B.Acks);

  { 2. data frame to station 16 }
  M^.ChDestNode(16);
  R.Tns := 22;
  SendRec(M, R, 10);
  SlavesRun;
  MasterGets('ACK from 16');
  AssertTrue((Rep.MessType = tpAckNak) and Rep.FlAck);
  AssertEquals(1, B.Commands);
  AssertEquals(1, A.Commands);

  { 3. poll 16: its reply comes, the master ACKs it }
  Poll(16);
  SlavesRun;
  MasterGets('reply of 16');
  AssertTrue(Rep.MessType = tpDataMess);
  AssertEquals(8 + 2, Len);
  AssertEquals(CF_Echo or MskCF_Reply, Rep.CF);
  AssertEquals(22, Rep.Tns);
  AssertEquals($10, Rep.Data[0]);
  M^.ChGetNode(SNode, DNode);
  AssertEquals('from 16', 16, SNode);
  AssertEquals('to 1', 1, DNode);
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpAckNak;
  R.FlAck := True;
  SendRec(M, R, 2);
  SlavesRun;
  AssertFalse('16 dropped its reply', B.HasReply);
  AssertTrue('2 still holds its reply', A.HasReply);

  { 4. poll 16 again: nothing left, EOT }
  Poll(16);
  SlavesRun;
  MasterGets('EOT of 16');
  AssertTrue('EOT', Rep.MessType = tpNoPollRep);
  AssertEquals(1, Len);

  { 5. poll 2: its reply; without the master's ACK a second poll gets the
    same reply again (manual 6.1.1) }
  Poll(2);
  SlavesRun;
  MasterGets('reply of 2');
  AssertTrue(Rep.MessType = tpDataMess);
  AssertEquals(21, Rep.Tns);
  Poll(2);
  SlavesRun;
  MasterGets('reply of 2 again');
  AssertEquals(21, Rep.Tns);
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpAckNak;
  R.FlAck := True;
  SendRec(M, R, 2);
  SlavesRun;
  Poll(2);
  SlavesRun;
  MasterGets('EOT of 2');
  AssertTrue(Rep.MessType = tpNoPollRep);

  AssertEquals('polls seen by 2', 3, A.Polls);
  AssertEquals('polls seen by 16', 2, B.Polls);
  { both slaves hear every ACK of the master (one line to all slaves) and
    keep or drop their reply correctly: checked by the EOTs above }
  { two master ACKs each; on two wires also the other slave's data ACK }
  AssertEquals('ACKs heard by 2', 2 + Ord(TwoWire), A.Acks);
  AssertEquals('ACKs heard by 16', 2 + Ord(TwoWire), B.Acks);
  AssertEquals('commands of 2', 1, A.Commands);
  AssertEquals('commands of 16', 1, B.Commands);
end;

procedure TTestChnDF1.TestHalfDuplexTwoSlavesFourWire;
begin
  HalfDuplexSession(False, 'HD4');
end;

procedure TTestChnDF1.TestHalfDuplexTwoSlavesTwoWire;
begin
  HalfDuplexSession(True, 'HD2');
end;

{ Full duplex, a reply addressed to another station (DST <> NOD, or from
  a station we sent no command to) is counted and dropped; commands come
  from any SRC (a slave must take them, SPEC 6). }
procedure TTestChnDF1.TestReplyForAnotherStationIsDropped;
var
  M, Raw: pChnVirt;
  R: tRecRecord;
  Len: Word;

  { a frame with DST, SRC, CMD on the line from the raw end }
  procedure Arrive(Dst, Src: Byte; CF, Tns: Word);
  var
    Cfg: tDF1Config;
    Rec: tSendRecord;
    Wire: array[0..63] of Byte;
    N: Word;
  begin
    FillChar(Cfg, SizeOf(Cfg), 0);
    Cfg.FullDup := True;
    Cfg.Crc := True;
    Cfg.Node := Src;
    Cfg.DNode := Dst;
    Cfg.NakByte := NAK;
    FillChar(Rec, SizeOf(Rec), 0);
    Rec.MessType := tpDataMess;
    Rec.CF := CF;
    Rec.Tns := Tns;
    N := 0;
    AssertEquals('encode', res_Ok, DF1Encode(Cfg, Rec, cSizeHeadSndMsg, Wire, SizeOf(Wire), N));
    Raw^.ChSend(@Wire, N);
    AssertEquals('raw send', res_Ok, Raw^.ChSendResult);
  end;

  function Delivered: Boolean;
  begin
    Result := WaitReceive(M, 300);
    if Result then
    begin
      M^.ChReceive(Len);
      AssertEquals('taken', res_Ok, M^.ChReceiveResult);
    end;
  end;

begin
  M := Open('NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=DF1FOR END=1 IDL=0');
  Raw := OpenRaw('DF1FOR');
  M^.ChReceiveBuffer(@R, SizeOf(R));
  Arrive(1, 2, CF_Echo or MskCF_Reply, 1);
  AssertTrue('a reply from DNO to NOD is ours', Delivered);
  AssertEquals(0, pChnDF1(M)^.CH_ForeignCount);
  Arrive(3, 2, CF_Echo or MskCF_Reply, 2);
  AssertFalse('DST 3 is not NOD 1', Delivered);
  AssertEquals(1, pChnDF1(M)^.CH_ForeignCount);
  AssertEquals(3, pChnDF1(M)^.CH_ForeignDst);
  Arrive(1, 5, CF_Echo or MskCF_Reply, 3);
  AssertFalse('SRC 5: no command went there', Delivered);
  AssertEquals(2, pChnDF1(M)^.CH_ForeignCount);
  AssertEquals(5, pChnDF1(M)^.CH_ForeignSrc);
  { after a command to station 5, its reply is ours }
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  R.Tns := 4;
  M^.ChDestNode(5);
  SendRec(M, R, cSizeHeadSndMsg);
  M^.ChDestNode(2);
  Arrive(1, 5, CF_Echo or MskCF_Reply, 4);
  AssertTrue('a reply from a station we sent to', Delivered);
  { a command from any SRC: a slave must take it }
  Arrive(1, 9, CF_Echo, 5);
  AssertTrue('a command from SRC 9', Delivered);
  Arrive(1, 2, CF_Echo or MskCF_Reply, 6);
  AssertTrue('the line goes on', Delivered);
  AssertEquals(2, pChnDF1(M)^.CH_ForeignCount);
end;

initialization
  RegisterTest(TTestChnDF1);
end.
