{ Tests of the line timing keys of NAM=COM on a real pty: TURN= (a
  slave's turnaround: no answer before that long after the last byte
  received) and IFG= (idle line before a send, in bit times), both held
  without sleeping - the message waits in the transmit buffer and the
  program-wide wait wakes when it may go; RTSB=/RTSA= as parameters. }
unit TestChnComTiming;

{$MODE OBJFPC}{$H+}

interface

{$IFDEF UNIX}
uses
  BaseUnix, SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnWait,
  TestSupport, PtyPair, StackCase;

type
  TTestChnComTiming = class(TStackCase)
  private
    Pty: TPtyPair;
    Buf: array[0..15] of Byte;      {< the device's receive buffer }
    { a COM device on a new pty with Params, after the question $41 came
      to it from the master side }
    function Asked(const Params: string): pChnVirt;
    { the device answers one byte at once when one came; ms until the
      answer is at the master side }
    function AnswerTakes(const Params: string): QWord;
  protected
    procedure TearDown; override;
  published
    procedure TestNoDelayAnswersAtOnce;
    procedure TestTurnaroundHoldsTheAnswer;
    procedure TestIdleGapInBitTimes;
    procedure TestHeldAnswerGoesAfterAnIdlePoll;
    procedure TestParameters;
  end;
{$ENDIF}

implementation

{$IFDEF UNIX}
procedure TTestChnComTiming.TearDown;
begin
  inherited TearDown;
  FreeAndNil(Pty);
end;

function TTestChnComTiming.Asked(const Params: string): pChnVirt;
var
  B: Byte;
  Len: Word;
  Deadline: QWord;
begin
  Pty := TPtyPair.Create;
  Result := Stack('COM', 'DEV=' + Pty.SlavePath + ' ' + Params);
  Result^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  B := $41;
  AssertEquals(1, Pty.MasterWrite(B, 1));
  Deadline := ChMsTick + 3000;
  while (Result^.ChReceiveReady <> CHS_ReceiveReady) and (ChMsTick < Deadline) do
    ChnWaitAny(50);
  Result^.ChReceive(Len);
  AssertEquals('the question came', 1, Len);
end;

function TTestChnComTiming.AnswerTakes(const Params: string): QWord;
var
  Dev: pChnVirt;
  B: Byte;
  T0, Deadline: QWord;
  Waits: Integer;
  Sent: Boolean;
begin
  Dev := Asked('IDL=0 ' + Params);
  T0 := ChMsTick;
  B := $42;
  Dev^.ChSend(@B, 1);
  AssertEquals(res_Ok, Dev^.ChSendResult);
  Sent := False;
  Waits := 0;
  Deadline := ChMsTick + 3000;
  while ChMsTick < Deadline do
  begin
    if not Sent and (Dev^.ChSendReady = CHS_SendReady) then
      Sent := True;
    if Pty.MasterRead(B, 1) = 1 then
      Break;
    ChnWaitAny(1000);               { woken when the held answer may go }
    Inc(Waits);
  end;
  Result := ChMsTick - T0;
  AssertEquals('the answer', $42, B);
  AssertTrue('no busy loop: ' + IntToStr(Waits) + ' waits', Waits < 50);
end;

procedure TTestChnComTiming.TestNoDelayAnswersAtOnce;
var
  Took: QWord;
begin
  Took := AnswerTakes('');
  AssertTrue('took ' + IntToStr(Took) + ' ms', Took < 500);
end;

{ TURN=150: the answer leaves 150 ms after the question's last byte. }
procedure TTestChnComTiming.TestTurnaroundHoldsTheAnswer;
var
  Took: QWord;
begin
  Took := AnswerTakes('TURN=150');
  AssertTrue('took ' + IntToStr(Took) + ' ms, at least 150 less the reading',
    Took >= 140);
  AssertTrue('took ' + IntToStr(Took) + ' ms', Took < 1500);
end;

{ IFG=330 at 1200 Bd: 330 bit times = 275 ms of idle line after the
  question before the answer starts. }
procedure TTestChnComTiming.TestIdleGapInBitTimes;
var
  Took: QWord;
begin
  Took := AnswerTakes('BD=1200 IFG=330');
  AssertTrue('took ' + IntToStr(Took) + ' ms of 275', Took >= 265);
  AssertTrue('took ' + IntToStr(Took) + ' ms', Took < 2000);
end;

{ A poll that finds no input waits up to IDL= ms for it; when the time
  of a held answer (TURN=) comes within that wait, the wait ends for it
  and the answer goes then, by that poll - nothing else would wake the
  program for it (the due time is spent: before, it went only at the
  program's next look at the line, a whole wait later: an IEC 101 slave
  answered a poll one link timeout late on a loaded machine). }
procedure TTestChnComTiming.TestHeldAnswerGoesAfterAnIdlePoll;
var
  Dev: pChnVirt;
  B: Byte;
  Deadline: QWord;
  Got: LongInt;
begin
  Dev := Asked('IDL=400 TURN=100');
  B := $42;
  Dev^.ChSend(@B, 1);                { held for TURN= 100 ms }
  { one poll: nothing comes, its IDL= wait (400 ms) ends at the answer's time }
  AssertEquals('no input', Ord(CHS_Receiving), Ord(Dev^.ChReceiveReady));
  { the answer is on the line without another call into the channel }
  Got := 0;
  Deadline := ChMsTick + 300;
  while (Got <> 1) and (ChMsTick < Deadline) do
  begin
    Got := Pty.MasterRead(B, 1);
    if Got <> 1 then
      Sleep(5);
  end;
  AssertEquals('the answer went with the poll whose wait its time ended', 1, Got);
  AssertEquals('the answer', $42, B);
end;

procedure TTestChnComTiming.TestParameters;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('COM');
  Keep(C);
  C^.ChSetParam('RTSB=5 RTSA=2 TURN=20 IFG=33');
  AssertEquals(res_Ok, C^.ChResult);
  AssertEquals('RTSB=5', C^.ChGetParam('RTSB'));
  AssertEquals('RTSA=2', C^.ChGetParam('RTSA'));
  AssertEquals('TURN=20', C^.ChGetParam('TURN'));
  AssertEquals('IFG=33', C^.ChGetParam('IFG'));
  C^.ChSetParam('RTSB=1001');
  AssertEquals(res_BadParam, C^.ChResult);
  C^.ChSetParam('TURN=-1');
  AssertEquals(res_BadParam, C^.ChResult);
end;

initialization
  RegisterTest(TTestChnComTiming);
{$ENDIF}
end.
