{ NAM=COM under a sender that never pauses (found by tools/chntap's 1 MiB
  test on a loaded machine: with LRB=1048576 exactly 1048576 bytes passed
  and the rest of the stream was lost). One poll read "until the driver is
  empty"; when input keeps coming it never is, so a single ChReceiveReady
  read until the LRB ring was full and then dropped what followed, before
  the caller could take anything. A poll now pulls at most
  MaxPullPerPoll bytes (64 KiB) and returns; the rest waits in the driver
  for the next poll.

  That bound held for the reads of a tty, 4 KiB each, but not for one
  read: a pty whose writer keeps feeding it from the other CPU (seen once
  in CI, the same symptom again), or a socket with megabytes queued, hands
  a single read(2) all the room it is given - the whole empty ring - and
  the poll dropped what followed. Each read now asks for at most what is
  left of MaxPullPerPoll.

  A port driver (DRV=ENDLESS, tests/support/FakePort) always has more
  input: every Read fills the buffer it is given with the next bytes of a
  pattern, 4 KiB at most as a tty, or all of it. A caller that takes what
  arrives after each poll must get every byte, in order, without an
  overrun. }
unit TestChnComBurst;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnPort, ChnVirt, ChnCom, FakePort;

type
  TTestChnComBurst = class(TTestCase)
  private
    procedure CheckEndless(MaxRead: LongInt);
  published
    procedure TestEndlessInputLosesNothing;
    procedure TestOneHugeReadLosesNothing;
  end;

implementation

procedure TTestChnComBurst.CheckEndless(MaxRead: LongInt);
var
  C: pChnVirt;
  Buf: array[0..65534] of Byte;
  Len: Word;
  Got: Int64;
  I, Polls, Bad: LongInt;
begin
  TEndlessPort.MaxRead := MaxRead;
  C := ChnCollection^.ChNewInit(ChnCom.cName);
  try
    C^.ChSetParam('NAM=COM DRV=ENDLESS DEV=/endless LRB=1048576');
    AssertEquals(res_Ok, C^.ChResult);
    C^.ChOpen;
    AssertEquals(res_Ok, C^.ChResult);
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    C^.ChConnect;
    Got := 0;
    Bad := -1;
    { 4 MiB, four times the ring, taken up to 65535 bytes at a time }
    Polls := 0;
    while (Got < 4 * 1048576) and (Polls < 1000) do
    begin
      Inc(Polls);
      AssertEquals('poll ' + IntToStr(Polls), CHS_ReceiveReady, C^.ChReceiveReady);
      AssertTrue('one poll pulls a bounded amount, not the ring full: ' +
        IntToStr(TEndlessPort.Produced - Got), TEndlessPort.Produced - Got <= 2 * 65536);
      Len := 0;
      C^.ChReceive(Len);
      AssertEquals('no overrun at poll ' + IntToStr(Polls) + ', lost ' +
        IntToStr(pChnCom(C)^.ChLostBytes), res_Ok, C^.ChReceiveResult);
      for I := 0 to Len - 1 do
        if (Bad < 0) and (Buf[I] <> EndlessPattern(Got + I)) then
          Bad := Got + I;
      Inc(Got, Len);
    end;
    AssertTrue('4 MiB taken', Got >= 4 * 1048576);
    AssertEquals('in order, unchanged (first wrong byte)', -1, Bad);
    AssertEquals('nothing lost', 0, pChnCom(C)^.ChLostBytes);
  finally
    Dispose(C, Done);
  end;
end;

{ reads of a tty: 4 KiB each }
procedure TTestChnComBurst.TestEndlessInputLosesNothing;
begin
  CheckEndless(4096);
end;

{ one read takes all the room it is given (a socket, a fed pty) }
procedure TTestChnComBurst.TestOneHugeReadLosesNothing;
begin
  CheckEndless(0);
end;

initialization
  RegisterPortDriver('ENDLESS', TEndlessPort);
  RegisterTest(TTestChnComBurst);
end.
