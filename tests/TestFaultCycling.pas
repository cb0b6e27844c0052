{ Fault cycling: 10,000 ChOpen/ChClose cycles per physical layer - COM on a
  pty, COM creating a pty (DRV=PTY), LOOP, TCP - mixed with opens that fail
  and with the device lost in the middle of a frame, and afterwards the
  process has as many open descriptors and as much heap in use as before.
  A layer that leaks a descriptor or a buffer on any of these paths fails
  here long before a plant runs out of them. Unix (descriptors are counted
  in /proc/self/fd). }
unit TestFaultCycling;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp,
  ChnDF1, ChnPty, TestSupport, PtyPair;

type
  TTestFaultCycling = class(TTestCase)
  private
    FFds: LongInt;
    FHeap: PtrUInt;
    procedure Before;
    procedure After(const What: string);
  published
    procedure TestComOnPty;
    procedure TestPtyOwnPair;
    procedure TestLoop;
    procedure TestTcp;
  end;

implementation

const
  Cycles = 10000;
  { half a DF1 frame: DLE STX DST SRC CMD, the rest never comes }
  HalfFrame: array[0..4] of Byte = ($10, $02, $01, $00, $06);

function HeapInUse: PtrUInt;
begin
  Result := GetFPCHeapStatus.CurrHeapUsed;
end;

procedure TTestFaultCycling.Before;
begin
  FFds := OpenFdCount('self');
  FHeap := HeapInUse;
end;

procedure TTestFaultCycling.After(const What: string);
var
  Fds: LongInt;
  Heap: PtrUInt;
begin
  { taken before the messages below are built: they are on the heap too }
  Heap := HeapInUse;
  Fds := OpenFdCount('self');
  AssertEquals(What + ': open descriptors', FFds, Fds);
  AssertEquals(What + ': heap in use', Int64(FHeap), Int64(Heap));
end;

{ Open Params as a stack of layer Name; nil when the open failed (the
  stack is freed then): Res is the result. }
function TryOpen(const Name, Params: string; out Res: tChResult): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(Name);
  Result^.ChSetParam(Params);
  Res := Result^.ChResult;
  if Res = res_Ok then
  begin
    Result^.ChOpen;
    Res := Result^.ChResult;
  end;
  if Res = res_Ok then
  begin
    Result^.ChConnect;
    Res := Result^.ChResult;
  end;
  if Res <> res_Ok then
  begin
    Dispose(Result, Done);
    Result := nil;
  end;
end;

procedure Shut(var C: pChnVirt);
begin
  C^.ChClose;
  Dispose(C, Done);
  C := nil;
end;

{ Poll a DF1 stack until it has taken Want bytes of a frame (it is then
  inside the frame) or the lower layer failed; True when inside. }
function InsideFrame(C: pChnVirt; Ms: LongInt): Boolean;
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(Ms);
  repeat
    C^.ChReceiveReady;
    if C^.CH_RCtrl >= CHS_ProtoBase then
      Exit(True);
    Sleep(0);
  until ChMsTick > Deadline;
  Result := False;
end;

{ Poll until the stack reports the device lost; the result seen. }
function LostResult(C: pChnVirt; Ms: LongInt): tChResult;
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + QWord(Ms);
  repeat
    C^.ChReceiveReady;
    Result := C^.ChResult;
    if Result = res_Ok then
      Result := C^.ChReceiveResult;
    if Result <> res_Ok then
      Exit;
    Sleep(1);
  until ChMsTick > Deadline;
end;

{ COM on the slave side of a pty pair the test made: good cycles, failed
  opens (no such device, a directory), and every 100th cycle a DF1 stack
  that receives half a frame before the pty disappears. }
procedure TTestFaultCycling.TestComOnPty;
var
  Pty: TPtyPair;
  Lost: LongInt;
  Buf: array[0..63] of Byte;

  procedure Cycle(I: LongInt);
  var
    C: pChnVirt;
    R: tChResult;
  begin
    case I mod 100 of
      0:
        begin
          { device lost mid-frame }
          C := TryOpen('DF1', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=' + Pty.SlavePath + ' IDL=0', R);
          AssertTrue('DF1 over COM opens: ' + IntToStr(R), C <> nil);
          C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
          AssertEquals('half a frame written', SizeOf(HalfFrame),
            Pty.MasterWrite(HalfFrame, SizeOf(HalfFrame)));
          AssertTrue('inside the frame', InsideFrame(C, 2000));
          Pty.CloseMaster;
          AssertEquals('device lost', res_DeviceLost, LostResult(C, 2000));
          Shut(C);
          Inc(Lost);
          Pty.Free;
          Pty := TPtyPair.Create;
        end;
      1, 51:
        begin
          C := TryOpen('COM', 'NAM=COM DEV=/dev/chn-no-such-device', R);
          AssertTrue('missing device refused', C = nil);
          AssertEquals('missing device', res_CannotOpen, R);
        end;
      2:
        begin
          C := TryOpen('COM', 'NAM=COM DEV=/tmp', R);
          AssertTrue('a directory refused', C = nil);
        end;
    else
      C := TryOpen('COM', 'NAM=COM DEV=' + Pty.SlavePath + ' BD=9600 IDL=0', R);
      AssertTrue('COM opens: ' + IntToStr(R), C <> nil);
      Shut(C);
    end;
  end;

var
  I: LongInt;
begin
  Lost := 0;
  Pty := TPtyPair.Create;
  try
    { one cycle of each kind first: what the first use allocates for good
      (the program-wide wait set) is not a leak }
    for I := 0 to 3 do
      Cycle(I);
    Pty.Free;
    Before;
    Pty := TPtyPair.Create;
    Lost := 0;
    for I := 1 to Cycles do
      Cycle(I);
  finally
    Pty.Free;
  end;
  AssertEquals('devices lost mid-frame', Cycles div 100, Lost);
  After('COM on a pty');
end;

{ COM creating its own pty (DRV=PTY): the pair comes and goes with the
  layer; a client that opens the slave, sends half a frame and hangs up
  every 100th cycle. }
procedure TTestFaultCycling.TestPtyOwnPair;
var
  Buf: array[0..63] of Byte;

  procedure Cycle(I: LongInt);
  var
    C, Cli: pChnVirt;
    R: tChResult;
  begin
    C := TryOpen('DF1', 'NAM=DF1 NOD=1 DNO=0 MAS=SLAVE NAM=COM DRV=PTY IDL=0', R);
    AssertTrue('DRV=PTY opens: ' + IntToStr(R), C <> nil);
    if I mod 100 = 0 then
    begin
      C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
      Cli := TryOpen('COM', 'NAM=COM DEV=' + PtyLastSlave + ' IDL=0', R);
      AssertTrue('client opens the slave: ' + IntToStr(R), Cli <> nil);
      Cli^.ChSend(@HalfFrame, SizeOf(HalfFrame));
      AssertTrue('inside the frame', InsideFrame(C, 2000));
      Shut(Cli);               { the client hangs up mid-frame }
      C^.ChReceiveReady;
    end;
    Shut(C);
  end;

var
  I: LongInt;
begin
  for I := 0 to 2 do
    Cycle(I);
  { PtyLastSlave keeps the last path on the heap, longer or shorter }
  PtyLastSlave := '';
  Before;
  for I := 1 to Cycles do
    Cycle(I);
  PtyLastSlave := '';
  After('DRV=PTY');
end;

{ LOOP pairs: good cycles, an end already in use (refused), and the peer
  closing in the middle of a frame. }
procedure TTestFaultCycling.TestLoop;
var
  Buf: array[0..63] of Byte;

  procedure Cycle(I: LongInt);
  var
    A, B, C: pChnVirt;
    R: tChResult;
  begin
    A := TryOpen('DF1', 'NAM=DF1 NAM=LOOP PAIR=FC END=1', R);
    AssertTrue('LOOP opens', A <> nil);
    if I mod 10 = 0 then
    begin
      C := TryOpen('LOOP', 'NAM=LOOP PAIR=FC END=1', R);
      AssertTrue('an end in use is refused', C = nil);
      AssertEquals('end in use', res_CannotOpen, R);
    end;
    if I mod 100 = 0 then
    begin
      B := TryOpen('LOOP', 'NAM=LOOP PAIR=FC END=2', R);
      AssertTrue('peer opens', B <> nil);
      A^.ChReceiveBuffer(@Buf, SizeOf(Buf));
      B^.ChSend(@HalfFrame, SizeOf(HalfFrame));
      AssertTrue('inside the frame', InsideFrame(A, 2000));
      Shut(B);                 { the peer goes away mid-frame }
      A^.ChReceiveReady;
    end;
    Shut(A);
  end;

var
  I: LongInt;
begin
  for I := 0 to 1 do
    Cycle(I);                  { the pair's registry entry stays }
  Before;
  for I := 1 to Cycles do
    Cycle(I);
  After('LOOP');
end;

{ TCP: a listener stays open; a client connects and closes, fails to
  connect to a port nobody listens on, and every 100th cycle a DF1 client
  receives half a frame before the server drops the connection. The whole
  round (listener included) runs once before the count, then for real. }
procedure TTestFaultCycling.TestTcp;
var
  Buf, SBuf: array[0..63] of Byte;

  procedure Round(Count: LongInt);
  var
    Srv, C: pChnVirt;
    R: tChResult;
    I, Port, Dead: LongInt;
    Deadline: QWord;
  begin
    Port := 20000 + Random(20000);
    Srv := nil;
    for I := 1 to 20 do
    begin
      Srv := TryOpen('TCP', 'NAM=TCP LISTEN=' + IntToStr(Port) + ' IDL=0', R);
      if Srv <> nil then
        Break;
      Port := 20000 + Random(20000);
    end;
    AssertTrue('listener', Srv <> nil);
    Dead := Port + 1;
    Srv^.ChReceiveBuffer(@SBuf, SizeOf(SBuf));
    for I := 1 to Count do
    begin
      if I mod 50 = 1 then
      begin
        C := TryOpen('TCP', Format('NAM=TCP HOST=127.0.0.1 PORT=%d IDL=0 CTO=2000', [Dead]), R);
        AssertTrue('nobody listens: refused', C = nil);
        Continue;
      end;
      if I mod 100 = 0 then
      begin
        C := TryOpen('DF1', Format('NAM=DF1 NAM=TCP HOST=127.0.0.1 PORT=%d IDL=0', [Port]), R);
        AssertTrue('DF1 over TCP opens: ' + IntToStr(R), C <> nil);
        C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
        { the server takes the connection, sends half a frame, drops it }
        Deadline := ChMsTick + 2000;
        repeat
          Srv^.ChReceiveReady;
          Srv^.ChSend(@HalfFrame, SizeOf(HalfFrame));
        until (Srv^.ChSendResult = res_Ok) or (ChMsTick > Deadline);
        AssertEquals('server sends', res_Ok, Srv^.ChSendResult);
        AssertTrue('inside the frame', InsideFrame(C, 2000));
        Srv^.ChClose;
        Srv^.ChOpen;
        AssertEquals('listener again', res_Ok, Srv^.ChResult);
        Srv^.ChConnect;
        AssertEquals('device lost', res_DeviceLost, LostResult(C, 2000));
        Shut(C);
        Continue;
      end;
      C := TryOpen('TCP', Format('NAM=TCP HOST=127.0.0.1 PORT=%d IDL=0', [Port]), R);
      AssertTrue('client opens: ' + IntToStr(R), C <> nil);
      Shut(C);
      Srv^.ChReceiveReady;     { the server sees the client come and go }
    end;
    Srv^.ChReceiveReady;
    Shut(Srv);
  end;

begin
  Round(100);
  Before;
  Round(Cycles);
  After('TCP');
end;

initialization
  RegisterTest(TTestFaultCycling);
end.
