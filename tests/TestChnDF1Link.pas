{ TestChnDF1Link - the DF1 master's link dialogue (unit ChnDF1Link) against
  a slave driven by hand on NAM=LOOP, one step at a time: garbage and a
  peer's ENQs while the master waits for its ACK use up no try (50 ENQs
  used all 3 tries in 10 ms; one noise hit sent a write twice); a peer's
  ENQ gets the master's last ACK/NAK again; a retry only on NAK or
  timeout; the helpers give the caller's receive buffer and DNO back. }
unit TestChnDF1Link;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop,
  ChnDF1, ChnDF1Link;

type
  TTestChnDF1Link = class(TTestCase)
  private
    Master, Slave: pChnVirt;
    SRec: tRecRecord;
    M: tDF1Master;
    Req: tSendRecord;
    Commands, Acks, Naks: LongInt;   { what the slave received }
    procedure OpenPair(const Pair: string);
    { Take what the slave side received; count it. }
    procedure SlaveTake;
    procedure SlaveSend(T: tMessType; Ack: Boolean);
    procedure SlaveReply(Tns: Word);
    procedure SlaveGarbage;
  protected
    procedure TearDown; override;
  published
    procedure TestGarbageAndEnqsWhileWaitingForAckUseNoTry;
    procedure TestPeerEnqGetsTheLastAckOrNak;
    procedure TestNakAndTimeoutAreTries;
    procedure TestGivesBackReceiveBufferAndDestination;
  end;

implementation

uses
  TestSupport;

procedure TTestChnDF1Link.OpenPair(const Pair: string);
var
  Err: string;
begin
  Master := OpenStack('DF1', 'NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=ON NAM=LOOP PAIR=' +
    Pair + ' END=1', Err);
  AssertTrue(Err, Master <> nil);
  Slave := OpenStack('DF1', 'NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=' +
    Pair + ' END=2', Err);
  AssertTrue(Err, Slave <> nil);
  Slave^.ChReceiveBuffer(@SRec, SizeOf(SRec));
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := $0FA2;                 { protected typed logical read }
  Req.Tns := 77;
  Req.Data[0] := 2;
  Req.Data[1] := 7;
  Req.Data[2] := $89;
  Req.Data[3] := 0;
  Commands := 0;
  Acks := 0;
  Naks := 0;
end;

procedure TTestChnDF1Link.TearDown;
begin
  if M.State <> dmDone then
    DF1MasterCancel(M);
  if Master <> nil then
    Dispose(Master, Done);
  if Slave <> nil then
    Dispose(Slave, Done);
  Master := nil;
  Slave := nil;
end;

procedure TTestChnDF1Link.SlaveTake;
var
  Len: Word;
begin
  while Slave^.ChReceiveReady = CHS_ReceiveReady do
  begin
    Len := 0;
    Slave^.ChReceive(Len);
    if Slave^.ChReceiveResult <> res_Ok then
      Continue;
    case SRec.MessType of
      tpDataMess: Inc(Commands);
      tpAckNak:
        if SRec.FlAck then
          Inc(Acks)
        else
          Inc(Naks);
    end;
  end;
end;

procedure TTestChnDF1Link.SlaveSend(T: tMessType; Ack: Boolean);
var
  R: tSendRecord;
begin
  FillChar(R, SizeOf(R), 0);
  R.MessType := T;
  R.FlAck := Ack;
  if T = tpAckNak then
    AssertEquals(res_Ok, ChSendWhenFree(Slave, @R, 2, 1000))
  else
    AssertEquals(res_Ok, ChSendWhenFree(Slave, @R, 1, 1000));
end;

procedure TTestChnDF1Link.SlaveReply(Tns: Word);
var
  R: tSendRecord;
begin
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := $4F00;
  R.Tns := Tns;
  R.Data[0] := $34;
  R.Data[1] := $12;
  AssertEquals(res_Ok, ChSendWhenFree(Slave, @R, 8 + 2, 1000));
end;

{ A frame damaged on the line: start, some bytes, end, a wrong CRC. }
procedure TTestChnDF1Link.SlaveGarbage;
const
  G: array[0..13] of Byte = ($10, $02, $00, $01, $4F, $00, $4D, $00, $34, $12,
    $10, $03, $FF, $FF);
begin
  AssertEquals(res_Ok, ChSendWhenFree(Slave^.CH_Low, @G, SizeOf(G), 1000));
end;

procedure TTestChnDF1Link.TestGarbageAndEnqsWhileWaitingForAckUseNoTry;
var
  I: LongInt;
begin
  OpenPair('DF1LNK1');
  AssertTrue('sent', DF1MasterStart(M, Master, Req, 8 + 4, 500));
  SlaveTake;
  AssertEquals('the command arrived', 1, Commands);
  { the slave (or the line) babbles before the ACK comes }
  for I := 1 to 50 do
  begin
    SlaveSend(tpEnq, False);
    if I mod 10 = 0 then
      DF1MasterStep(M);
  end;
  SlaveGarbage;
  DF1MasterStep(M);
  AssertEquals('still waiting for the ACK', Ord(dmWaitAck), Ord(M.State));
  AssertEquals('no try used up by noise or ENQs', 1, M.Tries);
  AssertEquals('every ENQ seen', 50, M.EnqsIn);
  AssertTrue('the damaged frame ignored', M.Ignored >= 1);
  SlaveTake;
  AssertEquals('each ENQ answered with the last ACK/NAK (none yet: NAK)', 50, Naks);
  AssertEquals('the command was not sent again', 1, Commands);
  SlaveSend(tpAckNak, True);
  SlaveReply(77);
  AssertTrue('done', DF1MasterStep(M));
  AssertEquals(res_Ok, M.Result);
  SlaveTake;
  AssertEquals('the write went out once', 1, Commands);
  AssertEquals('the reply ACKed', 1, Acks);
end;

procedure TTestChnDF1Link.TestPeerEnqGetsTheLastAckOrNak;
begin
  OpenPair('DF1LNK2');
  AssertTrue(DF1MasterStart(M, Master, Req, 8 + 4, 500));
  SlaveTake;
  SlaveSend(tpAckNak, True);
  DF1MasterStep(M);
  AssertEquals(Ord(dmWaitReply), Ord(M.State));
  SlaveReply(76);                      { a late reply to an earlier command }
  DF1MasterStep(M);
  SlaveTake;
  AssertEquals('a stale reply is ACKed', 1, Acks);
  SlaveSend(tpEnq, False);
  DF1MasterStep(M);
  SlaveTake;
  AssertEquals('ENQ after an ACK: ACK again', 2, Acks);
  AssertEquals(0, Naks);
  SlaveGarbage;                        { a broken reply: NAK }
  DF1MasterStep(M);
  SlaveTake;
  AssertEquals('the broken reply NAKed', 1, Naks);
  SlaveSend(tpEnq, False);
  DF1MasterStep(M);
  SlaveTake;
  AssertEquals('ENQ after a NAK: NAK again', 2, Naks);
  AssertEquals(2, Acks);
  SlaveReply(77);
  AssertTrue(DF1MasterStep(M));
  AssertEquals(res_Ok, M.Result);
  AssertEquals(2, M.EnqsIn);
  AssertEquals(1, M.Stale);
end;

procedure TTestChnDF1Link.TestNakAndTimeoutAreTries;
var
  Deadline: QWord;
begin
  OpenPair('DF1LNK3');
  AssertTrue(DF1MasterStart(M, Master, Req, 8 + 4, 60));
  SlaveTake;
  SlaveSend(tpAckNak, False);
  DF1MasterStep(M);
  SlaveTake;
  AssertEquals('a NAK: the second try', 2, M.Tries);
  AssertEquals(2, Commands);
  { no answer: ENQ after the timeout, then the third try, then the end }
  Deadline := ChMsTick + 2000;
  while not DF1MasterStep(M) and (ChMsTick < Deadline) do
    Sleep(5);                          { the test's own clock, not a helper's }
  AssertEquals('timeout after the third try', res_Timeout, M.Result);
  SlaveTake;
  AssertEquals('three tries in all', 3, Commands);
  AssertEquals(3, M.Tries);
end;

procedure TTestChnDF1Link.TestGivesBackReceiveBufferAndDestination;
var
  Mine: array[0..9] of Byte;
  Buf: Pointer;
  Size: Word;
begin
  OpenPair('DF1LNK4');
  Master^.ChReceiveBuffer(@Mine, SizeOf(Mine));
  Master^.ChDestNode(1);
  AssertTrue(DF1MasterStart(M, Master, Req, 8 + 4, 500));
  Master^.ChGetReceiveBuffer(Buf, Size);
  AssertTrue('the exchange receives into its own record', Buf = @M.Rep);
  SlaveTake;
  SlaveSend(tpAckNak, True);
  SlaveReply(77);
  AssertTrue(DF1MasterStep(M));
  Master^.ChGetReceiveBuffer(Buf, Size);
  AssertTrue('the caller''s buffer again', Buf = @Mine);
  AssertEquals(SizeOf(Mine), Size);
  AssertEquals(1, Master^.ChGetDestNode);
end;

initialization
  RegisterTest(TTestChnDF1Link);
end.
