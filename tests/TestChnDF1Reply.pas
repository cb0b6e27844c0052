{ Tests of the DF1 reply CF (unit ChnDF1, the sent-command log of
  ChnDF1Codec): a reply carries no FNC on the wire, and the layer that sent
  the command gives it back, so the manuals' test
  "RMess^.CF = CF_DiagnosticSts or MskCF_Reply" holds. Two DF1 stations
  over the in-memory null modem (LOOP) and over a real pty pair
  (NAM=COM DRV=PTY and a second channel on its slave), commands in both
  directions, several outstanding, answered out of order. }
unit TestChnDF1Reply;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnCom,
  {$IFDEF UNIX}ChnPty,{$ENDIF} ChnDF1, TestSupport, StackCase;

type
  TTestChnDF1Reply = class(TStackCase)
  private
    function Open(const Params: string): pChnVirt;
    procedure Send(Chn: pChnVirt; CF, Tns: Word; const Data: array of Byte);
    function Recv(Chn, Other: pChnVirt; var Rec: tRecRecord): Word;
    procedure OutOfOrder(A, B: pChnVirt; const Tag: string);
  published
    procedure TestLogMatchesTnsAndCommand;
    procedure TestLogKeepsSixteenNewestFirst;
    procedure TestReplyOnTheWireHasNoFnc;
    procedure TestOutOfOrderBothDirectionsLoop;
    procedure TestUnmatchedReplyKeepsLowByteZero;
    procedure TestSixteenOutstanding;
    {$IFDEF UNIX}
    procedure TestOutOfOrderBothDirectionsPty;
    {$ENDIF}
  end;

implementation

uses
  ChnDF1Codec;

const
  TimeoutMs = 3000;

function Cmd(CF, Tns: Word): tSendRecord;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.MessType := tpDataMess;
  Result.CF := CF;
  Result.Tns := Tns;
end;

function TTestChnDF1Reply.Open(const Params: string): pChnVirt;
begin
  Result := Stack('DF1', Params);
end;

procedure TTestChnDF1Reply.Send(Chn: pChnVirt; CF, Tns: Word; const Data: array of Byte);
var
  R: tSendRecord;
  I: Integer;
begin
  R := Cmd(CF, Tns);
  for I := 0 to High(Data) do
    R.Data[I] := Data[I];
  AssertTrue('transmitter idle', WaitSent(Chn, TimeoutMs));
  Chn^.ChSend(@R, 8 + Length(Data));
  AssertEquals('send: ' + Chn^.ChResultStr(Chn^.ChSendResult), res_Ok, Chn^.ChSendResult);
end;

function TTestChnDF1Reply.Recv(Chn, Other: pChnVirt; var Rec: tRecRecord): Word;
begin
  { a fresh buffer each time: nothing of the last message may be left }
  FillChar(Rec, SizeOf(Rec), $EE);
  Chn^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  AssertTrue('a message arrives', WaitReceive(Chn, TimeoutMs, Other));
  Result := 0;
  Chn^.ChReceive(Result);
  AssertEquals('receive result', res_Ok, Chn^.ChReceiveResult);
  { link ACKs are the application's; these stations send none }
  AssertTrue('a data message', Rec.MessType = tpDataMess);
end;

procedure TTestChnDF1Reply.TestLogMatchesTnsAndCommand;
var
  L: tDF1SentLog;
  R: tRecRecord;
begin
  DF1SentInit(L);
  DF1SentNote(L, 2, Cmd(CF_DiagnosticSts, 7));
  { the reply as decoded from the wire: CMD $46, low byte 0 }
  R := Cmd($4600, 7);
  AssertEquals('FNC restored', $4603, DF1ReplyCF(L, 2, R));
  AssertEquals('from another station: still the only match', $4603, DF1ReplyCF(L, 9, R));
  R.Tns := 8;
  AssertEquals('other TNS: low byte 0', $4600, DF1ReplyCF(L, 2, R));
  R := Cmd($4F00, 7);
  AssertEquals('other command: low byte 0', $4F00, DF1ReplyCF(L, 2, R));
  R := Cmd($0600, 7);
  AssertEquals('a command is no reply', $0600, DF1ReplyCF(L, 2, R));
  { replies sent are not noted: only what this station asked }
  DF1SentNote(L, 2, Cmd(CF_Echo or MskCF_Reply, 20));
  R := Cmd($4600, 20);
  AssertEquals('own reply not noted', $4600, DF1ReplyCF(L, 2, R));
  { the same TNS to two stations: the one the reply comes from wins }
  DF1SentNote(L, 3, Cmd(CF_ReadDiagnCounts, 30));
  DF1SentNote(L, 4, Cmd(CF_ResetDiagnCounts, 30));
  R := Cmd($4600, 30);
  AssertEquals('from 3', $4601, DF1ReplyCF(L, 3, R));
  AssertEquals('from 4', $4607, DF1ReplyCF(L, 4, R));
  AssertEquals('from 5: the newest', $4607, DF1ReplyCF(L, 5, R));
  { a command without FNC keeps what the application put in its CF }
  DF1SentNote(L, 2, Cmd(CF_UnProtectRead, 40));
  R := Cmd($4100, 40);
  AssertEquals($4100, DF1ReplyCF(L, 2, R));
  { high priority bit: the reply's CMD is the command's or $40 }
  DF1SentNote(L, 2, Cmd(CF_Echo or MskCF_HiPriority, 41));
  R := Cmd($6600, 41);
  AssertEquals($6600, DF1ReplyCF(L, 2, R));
end;

procedure TTestChnDF1Reply.TestLogKeepsSixteenNewestFirst;
var
  L: tDF1SentLog;
  R: tRecRecord;
  I: Integer;
begin
  DF1SentInit(L);
  AssertTrue('at least 16 remembered', DF1SentMemory >= 16);
  for I := 0 to DF1SentMemory - 1 do
    DF1SentNote(L, 2, Cmd($0F00 or I, 100 + I));
  for I := 0 to DF1SentMemory - 1 do
  begin
    R := Cmd($4F00, 100 + I);
    AssertEquals('entry ' + IntToStr(I), $4F00 or I, DF1ReplyCF(L, 2, R));
  end;
  { one more: the oldest is forgotten, the rest stay }
  DF1SentNote(L, 2, Cmd($0FEE, 500));
  R := Cmd($4F00, 100);
  AssertEquals('oldest dropped', $4F00, DF1ReplyCF(L, 2, R));
  R := Cmd($4F00, 101);
  AssertEquals('second oldest kept', $4F01, DF1ReplyCF(L, 2, R));
  R := Cmd($4F00, 500);
  AssertEquals('newest', $4FEE, DF1ReplyCF(L, 2, R));
  { a TNS used again: the newer command counts }
  DF1SentNote(L, 2, Cmd($0F55, 101));
  R := Cmd($4F00, 101);
  AssertEquals('TNS reused', $4F55, DF1ReplyCF(L, 2, R));
end;

procedure TTestChnDF1Reply.TestReplyOnTheWireHasNoFnc;
var
  A, Raw: pChnVirt;
  Buf: array[0..63] of Byte;
  N: Word;
begin
  A := Open('NAM=DF1 NOD=1 DNO=2 CRC=OFF NAM=LOOP PAIR=DRW END=1');
  Raw := Stack('LOOP', 'NAM=LOOP PAIR=DRW END=2');
  { a reply built as the manuals build it: CF_DiagnosticSts or MskCF_Reply,
    TNS 5, data $AA. Wire: DLE STX 02 01 46 00 05 00 AA DLE ETX BCC with
    BCC = -(2+1+$46+5+$AA) = -$F8 = $08; no FNC byte $03 anywhere }
  Send(A, CF_DiagnosticSts or MskCF_Reply, 5, [$AA]);
  Raw^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  AssertTrue(WaitReceive(Raw, TimeoutMs, A));
  N := 0;
  Raw^.ChReceive(N);
  AssertEquals('10 02 02 01 46 00 05 00 AA 10 03 08', BytesToHex(Buf, N));
end;

procedure TTestChnDF1Reply.OutOfOrder(A, B: pChnVirt; const Tag: string);
var
  R: tRecRecord;
  Len: Word;
begin
  { A asks three things; B answers the newest first, the oldest last }
  Send(A, CF_DiagnosticSts, 100, []);
  Send(A, CF_ReadDiagnCounts, 101, [0, 0, 4]);
  Send(A, CF_ProtectRead3Addr, 102, [2, 7, $89, 0, 0]);
  Len := Recv(B, A, R);
  AssertEquals(Tag + ': command CF', CF_DiagnosticSts, R.CF);
  Len := Recv(B, A, R);
  AssertEquals(Tag + ': command CF', CF_ReadDiagnCounts, R.CF);
  Len := Recv(B, A, R);
  AssertEquals(Tag + ': command CF', CF_ProtectRead3Addr, R.CF);
  AssertEquals(8 + 5, Len);
  { B replies the manual's way: the command's CF or MskCF_Reply }
  Send(B, CF_ProtectRead3Addr or MskCF_Reply, 102, [$34, $12, $78, $56]);
  Send(B, CF_ReadDiagnCounts or MskCF_Reply, 101, [1, 2, 3, 4]);
  Send(B, CF_DiagnosticSts or MskCF_Reply, 100, [9]);
  Len := Recv(A, B, R);
  AssertEquals(Tag + ': reply to the newest', CF_ProtectRead3Addr or MskCF_Reply, R.CF);
  AssertEquals(Tag + ': Len = 8 + data', 8 + 4, Len);
  AssertEquals(102, R.Tns);
  Len := Recv(A, B, R);
  AssertEquals(Tag + ': reply after a newer command', CF_ReadDiagnCounts or MskCF_Reply, R.CF);
  AssertEquals(8 + 4, Len);
  Len := Recv(A, B, R);
  AssertEquals(Tag + ': the oldest', CF_DiagnosticSts or MskCF_Reply, R.CF);
  AssertEquals(8 + 1, Len);
  AssertEquals(9, R.Data[0]);
  { and the other way: B asks, A answers }
  Send(B, CF_Echo, 7, [Ord('x')]);
  Len := Recv(A, B, R);
  AssertEquals(CF_Echo, R.CF);
  Send(A, CF_Echo or MskCF_Reply, 7, [Ord('x')]);
  Len := Recv(B, A, R);
  AssertEquals(Tag + ': B gets its reply', CF_Echo or MskCF_Reply, R.CF);
  Send(B, CF_TypedRead, 8, [0, 0, 7, 0, 1, 0]);
  Len := Recv(A, B, R);
  AssertEquals(CF_TypedRead, R.CF);
  { a reply built with CMD only (low byte 0) still gets the FNC back }
  Send(A, $4F00, 8, [1, 0]);
  Len := Recv(B, A, R);
  AssertEquals(Tag + ': B, FNC $68', CF_TypedRead or MskCF_Reply, R.CF);
end;

procedure TTestChnDF1Reply.TestOutOfOrderBothDirectionsLoop;
var
  A, B: pChnVirt;
begin
  A := Open('NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=DRL END=1');
  B := Open('NAM=DF1 NOD=2 DNO=1 NAM=LOOP PAIR=DRL END=2');
  OutOfOrder(A, B, 'LOOP');
end;

procedure TTestChnDF1Reply.TestUnmatchedReplyKeepsLowByteZero;
var
  A, B: pChnVirt;
  R: tRecRecord;
begin
  A := Open('NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=DRU END=1');
  B := Open('NAM=DF1 NOD=2 DNO=1 NAM=LOOP PAIR=DRU END=2');
  Send(A, CF_DiagnosticSts, 50, []);
  Recv(B, A, R);
  AssertEquals(CF_DiagnosticSts, R.CF);
  { no command with TNS 51 was sent, nor a $0F command with TNS 50 }
  Send(B, CF_DiagnosticSts or MskCF_Reply, 51, [1]);
  Recv(A, B, R);
  AssertEquals('TNS never sent', $4600, R.CF);
  Send(B, CF_ProtectRead3Addr or MskCF_Reply, 50, [1]);
  Recv(A, B, R);
  AssertEquals('other command', $4F00, R.CF);
end;

procedure TTestChnDF1Reply.TestSixteenOutstanding;
var
  A, B: pChnVirt;
  R: tRecRecord;
  I: Integer;
begin
  A := Open('NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=DR16 END=1');
  B := Open('NAM=DF1 NOD=2 DNO=1 NAM=LOOP PAIR=DR16 END=2');
  for I := 0 to 15 do
  begin
    Send(A, $0600 or (I mod 11), 1000 + I, []);
    Recv(B, A, R);
  end;
  for I := 15 downto 0 do
  begin
    Send(B, $4600, 1000 + I, [I]);
    Recv(A, B, R);
    AssertEquals('reply ' + IntToStr(I), $4600 or (I mod 11), R.CF);
  end;
end;

{$IFDEF UNIX}
procedure TTestChnDF1Reply.TestOutOfOrderBothDirectionsPty;
var
  A, B: pChnVirt;
begin
  { the manuals' line settings on a virtual line: PAR=E and all }
  PtyLastSlave := '';
  A := Open('NAM=DF1 NOD=1 DNO=2 NAM=COM DRV=PTY BD=19200 PAR=E');
  AssertEquals('/dev/pts/', Copy(PtyLastSlave, 1, 9));
  B := Open('NAM=DF1 NOD=2 DNO=1 NAM=COM DEV=' + PtyLastSlave + ' BD=19200 PAR=E IRQ=4');
  OutOfOrder(A, B, 'pty');
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnDF1Reply);
end.
