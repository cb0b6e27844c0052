{ NAM=COM under a sender that never pauses (found by tools/chntap's 1 MiB
  test on a loaded machine: with LRB=1048576 exactly 1048576 bytes passed
  and the rest of the stream was lost). One poll read "until the driver is
  empty"; when input keeps coming it never is, so a single ChReceiveReady
  read until the LRB ring was full and then dropped what followed, before
  the caller could take anything. A poll now pulls at most
  MaxPullPerPoll bytes (64 KiB) and returns; the rest waits in the driver
  for the next poll.

  A port driver of this test (DRV=ENDLESS) always has more input: every
  Read fills the whole buffer it is given with the next bytes of a
  pattern. A caller that takes what arrives after each poll must get every
  byte, in order, without an overrun. }
unit TestChnComBurst;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnPort, ChnVirt, ChnCom;

type
  TTestChnComBurst = class(TTestCase)
  published
    procedure TestEndlessInputLosesNothing;
  end;

implementation

type
  TEndlessPort = class(TChnPort)
  public
    class var Produced: Int64;
    function Open(const Path: tWordString): tChResult; override;
    function Configure(const S: tPortSettings): tChResult; override;
    function Read(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function WaitInput(Ms: LongInt): Boolean; override;
    function WaitOutput(Ms: LongInt): Boolean; override;
    function Write(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
    function OutQueue(out N: LongInt): tChResult; override;
    function Drain: tChResult; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    function SetRts(On: Boolean): tChResult; override;
    function SetDtr(On: Boolean): tChResult; override;
    function GetLines(out Lines: tPortLines): tChResult; override;
    function SetKernelRs485(On: Boolean): tChResult; override;
    function OsOverruns(out N: LongWord): tChResult; override;
    function OsHandle: PtrInt; override;
    procedure Close; override;
  end;

function Pattern(I: Int64): Byte; inline;
begin
  Result := (I * 31 + I shr 11) and $FF;
end;

function TEndlessPort.Open(const Path: tWordString): tChResult;
begin
  FDevice := Path;
  FOpen := True;
  Produced := 0;
  Result := res_Ok;
end;

function TEndlessPort.Configure(const S: tPortSettings): tChResult;
begin
  Result := res_Ok;
end;

function TEndlessPort.Read(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  I: LongInt;
  P: PByte;
begin
  { a tty hands out at most 4 KiB per read; there is always more }
  Got := Size;
  if Got > 4096 then
    Got := 4096;
  P := @Buf;
  for I := 0 to Got - 1 do
    P[I] := Pattern(Produced + I);
  Inc(Produced, Got);
  Result := res_Ok;
end;

function TEndlessPort.WaitInput(Ms: LongInt): Boolean;
begin
  Result := True;
end;

function TEndlessPort.WaitOutput(Ms: LongInt): Boolean;
begin
  Result := True;
end;

function TEndlessPort.Write(const Buf; Len: LongInt; out Done: LongInt): tChResult;
begin
  Done := Len;
  Result := res_Ok;
end;

function TEndlessPort.OutQueue(out N: LongInt): tChResult;
begin
  N := 0;
  Result := res_Ok;
end;

function TEndlessPort.Drain: tChResult;
begin
  Result := res_Ok;
end;

function TEndlessPort.Flush(Input, Output: Boolean): tChResult;
begin
  Result := res_Ok;
end;

function TEndlessPort.SetRts(On: Boolean): tChResult;
begin
  Result := res_Ok;
end;

function TEndlessPort.SetDtr(On: Boolean): tChResult;
begin
  Result := res_Ok;
end;

function TEndlessPort.GetLines(out Lines: tPortLines): tChResult;
begin
  Lines := [];
  Result := res_Ok;
end;

function TEndlessPort.SetKernelRs485(On: Boolean): tChResult;
begin
  Result := res_BadSetting;
end;

function TEndlessPort.OsOverruns(out N: LongWord): tChResult;
begin
  N := 0;
  Result := res_Ok;
end;

function TEndlessPort.OsHandle: PtrInt;
begin
  Result := -1;
end;

procedure TEndlessPort.Close;
begin
  FOpen := False;
end;

procedure TTestChnComBurst.TestEndlessInputLosesNothing;
var
  C: pChnVirt;
  Buf: array[0..65534] of Byte;
  Len: Word;
  Got: Int64;
  I, Polls, Bad: LongInt;
begin
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
        if (Bad < 0) and (Buf[I] <> Pattern(Got + I)) then
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

initialization
  RegisterPortDriver('ENDLESS', TEndlessPort);
  RegisterTest(TTestChnComBurst);
end.
