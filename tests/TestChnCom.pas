{ Tests of ChnCom's line over real pseudo-terminal pairs (no hardware):
  the settings the kernel took, all byte values at several settings, flow
  control, large transfers both ways, a close that loses nothing and is
  bounded, overrun and flow-control reporting, the idle wait and the CPU
  of a legacy polling loop. Once per port backend built in
  (TTestChnComRtl always, TTestChnComSynapse with make SYNAPSE_DIR=...),
  on the fixture of ComPtyCase (the strict drivers RTLSTRICT, SYNSTRICT).
  Opening, refusals and the loss of the device are TestChnComOpen's, the
  virtual line itself TestChnComVirtual's, the parameters and the
  RS-485/overrun logic on a scripted port TestChnComLogic's; on Windows
  this unit is empty (no ptys there; tools/wintest.sh runs ChnPortWin on
  a Wine COM port instead). }
unit TestChnCom;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry,
  {$IFDEF UNIX}BaseUnix, Unix, TermIO, Linux, Process, PtyPair, ChnPortUnix, ChnUnix, ChnPty, BinSupport,
  ComPtySupport, ComPtyCase,{$ENDIF}
  ChnTypes, ChnVirt, ChnPort, ChnCom, ChnDF1, TestSupport;

{$IFDEF UNIX}
type
  TTestChnComPty = class(TComPtyCase)
  published
    procedure TestBytesBothWaysAtSeveralSettings;
    procedure TestSettingsThePtyRefuses;
    procedure TestXonXoffFlowControl;
    procedure TestNonStandardBaud;
    procedure TestOneMiBBothWaysNoLoss;
    procedure TestLargeWritesCompleteThroughSendReady;
    procedure TestCloseRightAfterSendLosesNothing;
    procedure TestCloseWaitsUntilALongMessageLeft;
    procedure TestCloseIsBoundedWhenNobodyReads;
    procedure TestOverrunReportedWithoutFlowControl;
    procedure TestFlowControlPausesInsteadOfDropping;
    procedure TestIdleWaitReturnsOnFirstByte;
    procedure TestLegacyPollingLoopCpu;
  end;

  TTestChnComRtl = class(TTestChnComPty)
  protected
    function Drv: string; override;
  end;

  {$IFDEF CHN_SYNAPSE}
  TTestChnComSynapse = class(TTestChnComPty)
  protected
    function Drv: string; override;
  end;
  {$ENDIF}

{$ENDIF UNIX}

implementation

{$IFDEF UNIX}
procedure TTestChnComPty.TestBytesBothWaysAtSeveralSettings;
type
  tCase = record
    P: string;
    CFlag, Speed: Cardinal;
  end;
const
  { a Linux pty keeps rate, stop bits and RTS/CTS, but always has 8 data
    bits and no parity (see TestSettingsThePtyRefuses) }
  Cases: array[0..3] of tCase = (
    (P: 'BD=9600 BIT=8 STOP=1 PAR=N'; CFlag: KCS8; Speed: KB9600),
    (P: 'BD=115200 STOP=2'; CFlag: KCS8 or KCSTOPB; Speed: KB115200),
    (P: 'BD=4000000 FLW=RTSCTS'; CFlag: KCS8 or KCRTSCTS; Speed: KB4000000),
    (P: 'BD=50 STOP=2'; CFlag: KCS8 or KCSTOPB; Speed: KB50));
var
  I: Integer;
begin
  for I := Low(Cases) to High(Cases) do
  begin
    if not SystemKeepsRate(FPty, Cases[I].Speed) then
    begin
      { only where this system's termios cannot hold the rate (qemu-user
        7.2 above 460800): refused, the token named }
      AssertEquals(Cases[I].P + ' refused here', res_BadSetting, OpenCom(Cases[I].P));
      AssertEquals(Cases[I].P + ' the token', Copy(Cases[I].P, 1, Pos(' ', Cases[I].P) - 1),
        FChn^.ChParamError);
      Continue;
    end;
    AssertEquals(Cases[I].P + ' open', res_Ok, OpenCom(Cases[I].P));
    CheckTermios(Cases[I].P, Cases[I].CFlag, Cases[I].Speed);
    ExchangeAllByteValues(Cases[I].P);
    FChn^.ChClose;
    AssertEquals(Cases[I].P + ' close', res_Ok, FChn^.ChResult);
  end;
end;

{ Linux's pty driver forces CS8 and clears PARENB in every tcsetattr: the
  kernel's answer differs from the request, and the layer must refuse
  rather than run the line with settings nobody asked for. }
procedure TTestChnComPty.TestSettingsThePtyRefuses;
const
  Refused: array[0..4] of string = ('BIT=7 PAR=E', 'BIT=5', 'PAR=O', 'PAR=M', 'BIT=6 PAR=S STOP=2');
var
  I: Integer;
begin
  for I := Low(Refused) to High(Refused) do
  begin
    AssertEquals(Refused[I], res_BadSetting, OpenCom(Refused[I]));
    AssertEquals(Refused[I] + ' stays closed', CHS_Close, FChn^.ChReady);
  end;
  AssertEquals('and 8N1 opens', res_Ok, OpenCom('BIT=8 PAR=N'));
end;

procedure TTestChnComPty.TestXonXoffFlowControl;
var
  B: Byte;
  Msg: array[0..2] of Byte;
  Back: array[0..2] of Byte;
  Got, N: LongInt;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('FLW=XONXOFF IDL=0'));
  CheckTermios('XONXOFF', KCS8, KB9600);
  B := $13;                                 { XOFF from the peer }
  AssertTrue('xoff', FPty.MasterWriteAll(B, 1, 1000));
  Sleep(50);
  Msg[0] := Ord('a'); Msg[1] := Ord('b'); Msg[2] := Ord('c');
  FChn^.ChSend(@Msg, 3);
  AssertEquals('send accepted', res_Ok, FChn^.ChSendResult);
  Sleep(100);
  FChn^.ChSendReady;
  AssertEquals('held back by XOFF', 0, FPty.MasterRead(Back, 3));
  AssertEquals('XOFF is not data', CHS_Receiving, FChn^.ChReceiveReady);
  B := $11;                                 { XON }
  AssertTrue('xon', FPty.MasterWriteAll(B, 1, 1000));
  Got := 0;
  Deadline := GetTickCount64 + 2000;
  while (Got < 3) and (GetTickCount64 < Deadline) do
  begin
    FChn^.ChSendReady;
    N := FPty.MasterRead(Back[Got], 3 - Got);
    AssertTrue('master read', N >= 0);
    Inc(Got, N);
  end;
  AssertEquals('released by XON', 3, Got);
  AssertEquals('a', Ord('a'), Back[0]);
  AssertEquals('c', Ord('c'), Back[2]);
  AssertEquals('idle', CHS_SendReady, FChn^.ChSendReady);
end;

procedure TTestChnComPty.TestNonStandardBaud;
var
  T: tTermios2;
  E: cint;
begin
  if Drv = 'SYNSTRICT' then
  begin
    AssertEquals('12345 Bd is not in synaser''s table', res_BadSetting, OpenCom('BD=12345'));
    AssertEquals('closed', CHS_Close, FChn^.ChReady);
    Exit;
  end;
  FillChar(T, SizeOf(T), 0);
  if FpIOCtl(FPty.Master, TCGETS2, @T) <> 0 then
  begin
    E := FpGetErrno;
    { only where the device refuses termios2 (qemu-user 7.2 does not
      emulate TCGETS2): a rate outside the table cannot be set - refused,
      the token named - while the standard rates work (the other tests) }
    AssertEquals('12345 Bd without termios2', res_BadSetting, OpenCom('BD=12345'));
    AssertEquals('the token', 'BD=12345', FChn^.ChParamError);
    AssertEquals('closed', CHS_Close, FChn^.ChReady);
    AssertEquals('460800 Bd is a standard rate', res_Ok, OpenCom('BD=460800'));
    CheckTermios('460800', KCS8, $1004);
    Ignore('this system refuses termios2 (TCGETS2: errno ' + IntToStr(E) +
      '), so a rate outside the table cannot be set: refused with BD= named, checked');
  end;
  AssertEquals('12345 Bd through termios2', res_Ok, OpenCom('BD=12345'));
  FillChar(T, SizeOf(T), 0);
  AssertEquals('TCGETS2', 0, FpIOCtl(Com^.CH_Port.OsHandle, TCGETS2, @T));
  AssertEquals('BOTHER', KBOTHER, T.c_cflag and KCBAUD);
  AssertEquals('output rate', 12345, T.c_ospeed);
  AssertEquals('input rate', 12345, T.c_ispeed);
  ExchangeAllByteValues('12345 Bd');
end;

procedure TTestChnComPty.TestOneMiBBothWaysNoLoss;
const
  Total = 1024 * 1024;
var
  Sent, ToMaster, MasterSent, FromMaster, N, I, Chunk: LongInt;
  SBuf: array[0..65534] of Byte;
  MBuf: array[0..8191] of Byte;
  Len: Word;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=115200 LRB=8192'));
  Sent := 0; ToMaster := 0; MasterSent := 0; FromMaster := 0;
  Chunk := 1;
  Deadline := GetTickCount64 + 60000;
  while ((ToMaster < Total) or (FromMaster < Total)) and (GetTickCount64 < Deadline) do
  begin
    { channel -> master, messages of changing size up to 65535 }
    if (Sent < Total) and (FChn^.ChSendReady = CHS_SendReady) then
    begin
      Chunk := (Chunk * 37 + 1001) mod 65535 + 1;
      N := Chunk;
      if N > Total - Sent then
        N := Total - Sent;
      for I := 0 to N - 1 do
        SBuf[I] := Pattern(Sent + I);
      FChn^.ChSend(@SBuf, N);
      AssertEquals('send result', res_Ok, FChn^.ChSendResult);
      Inc(Sent, N);
    end;
    N := FPty.MasterRead(MBuf, SizeOf(MBuf));
    AssertTrue('master read', N >= 0);
    for I := 0 to N - 1 do
      if MBuf[I] <> Pattern(ToMaster + I) then
        Fail(Format('to master: byte %d is %d, expected %d',
          [ToMaster + I, MBuf[I], Pattern(ToMaster + I)]));
    Inc(ToMaster, N);
    { master -> channel }
    if MasterSent < Total then
    begin
      N := 4096;
      if N > Total - MasterSent then
        N := Total - MasterSent;
      for I := 0 to N - 1 do
        MBuf[I] := Pattern(MasterSent + I) xor $5A;
      N := FPty.MasterWrite(MBuf, N);
      AssertTrue('master write', N >= 0);
      Inc(MasterSent, N);
    end;
    if FChn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      FChn^.ChReceive(Len);
      AssertEquals('receive result', res_Ok, FChn^.ChReceiveResult);
      for I := 0 to Len - 1 do
        if FRBuf[I] <> Pattern(FromMaster + I) xor $5A then
          Fail(Format('from master: byte %d wrong', [FromMaster + I]));
      Inc(FromMaster, Len);
    end;
  end;
  AssertEquals('1 MiB reached the master', Total, ToMaster);
  AssertEquals('1 MiB reached the channel', Total, FromMaster);
  AssertEquals('nothing lost', 0, Com^.ChLostBytes);
  AssertEquals('nothing left over', 0, FPty.MasterRead(MBuf, SizeOf(MBuf)));
end;

procedure TTestChnComPty.TestLargeWritesCompleteThroughSendReady;
const
  Msg = 65535;
var
  SBuf: array[0..Msg - 1] of Byte;
  MBuf: array[0..8191] of Byte;
  I, Messages, Got, N: LongInt;
  T0, Slowest: QWord;
  Busy: Boolean;
  Deadline: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=9600 IDL=0'));
  for I := 0 to Msg - 1 do
    SBuf[I] := Pattern(I);
  { nobody reads the master: the pty (about 64 KiB) fills up; each ChSend
    must still return at once and ChSendReady report the rest pending }
  Messages := 0;
  Slowest := 0;
  Busy := False;
  while (Messages < 4) and not Busy do
  begin
    T0 := GetTickCount64;
    FChn^.ChSend(@SBuf, Msg);
    if GetTickCount64 - T0 > Slowest then
      Slowest := GetTickCount64 - T0;
    AssertEquals('send result', res_Ok, FChn^.ChSendResult);
    Inc(Messages);
    Busy := FChn^.ChSendReady = CHS_Sending;
  end;
  AssertTrue('a message larger than the OS buffer is pending', Busy);
  { a blocking write would wait for a reader that never comes }
  AssertTrue('ChSend did not block (' + IntToStr(Slowest) + ' ms)', Slowest < 1000);
  FChn^.ChSend(@SBuf, 10);
  AssertEquals('busy while sending', res_Busy, FChn^.ChSendResult);
  { now the master reads; ChSendReady polling completes the message }
  Got := 0;
  Deadline := GetTickCount64 + 10000;
  while (Got < Messages * Msg) and (GetTickCount64 < Deadline) do
  begin
    FChn^.ChSendReady;
    N := FPty.MasterRead(MBuf, SizeOf(MBuf));
    AssertTrue('master read', N >= 0);
    for I := 0 to N - 1 do
      if MBuf[I] <> Pattern((Got + I) mod Msg) then
        Fail(Format('byte %d wrong', [Got + I]));
    Inc(Got, N);
  end;
  AssertEquals('every byte arrived', Messages * Msg, Got);
  AssertEquals('transmitter idle', CHS_SendReady, FChn^.ChSendReady);
end;

{ An answer sent just before the program closes the line (icsslave: answer,
  exit) must reach the peer: 50 times open, send a frame, close at once;
  the peer reads only afterwards and finds all 50 in order. (synaser's
  close purged both directions, which on a pty drops what the master
  side has not read yet.) }
procedure TTestChnComPty.TestCloseRightAfterSendLosesNothing;
const
  Frames = 50;
  FrameLen = 64;
var
  Frame: array[0..FrameLen - 1] of Byte;
  Back: array[0..Frames * FrameLen - 1] of Byte;
  I, J, Got: Integer;
begin
  for I := 0 to Frames - 1 do
  begin
    AssertEquals('open ' + IntToStr(I), res_Ok, OpenCom(''));
    for J := 0 to FrameLen - 1 do
      Frame[J] := Pattern(I * FrameLen + J);
    FChn^.ChSend(@Frame, FrameLen);
    AssertEquals('send ' + IntToStr(I), res_Ok, FChn^.ChSendResult);
    FChn^.ChClose;
    AssertEquals('close ' + IntToStr(I), res_Ok, FChn^.ChResult);
  end;
  FillChar(Back, SizeOf(Back), 0);
  Got := FPty.MasterReadAll(Back, SizeOf(Back), 3000);
  AssertEquals('the peer got every frame (bytes)', SizeOf(Back), Got);
  for I := 0 to High(Back) do
    AssertEquals('byte ' + IntToStr(I), Pattern(I), Back[I]);
end;

type
  { the peer: reads the master side until it has Want bytes or 10 s passed }
  TMasterReader = class(TThread)
    Pty: TPtyPair;
    Want, Got: LongInt;
    Buf: array of Byte;
    procedure Execute; override;
  end;

procedure TMasterReader.Execute;
begin
  SetLength(Buf, Want);
  Got := Pty.MasterReadAll(Buf[0], Want, 10000);
end;

{ A message larger than the pty takes at once (about 22 kB on Linux):
  without the drain, ChClose discarded the part not yet handed over. }
procedure TTestChnComPty.TestCloseWaitsUntilALongMessageLeft;
const
  Len = 60000;
var
  Msg: array of Byte;
  R: TMasterReader;
  I: Integer;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=115200'));
  SetLength(Msg, Len);
  for I := 0 to Len - 1 do
    Msg[I] := Pattern(I);
  R := TMasterReader.Create(True);
  try
    R.Pty := FPty;
    R.Want := Len;
    FChn^.ChSend(@Msg[0], Len);
    AssertEquals('send', res_Ok, FChn^.ChSendResult);
    R.Start;                      { the peer starts reading now }
    FChn^.ChClose;
    AssertEquals('close', res_Ok, FChn^.ChResult);
    R.WaitFor;
    AssertEquals('every byte reached the peer', Len, R.Got);
    for I := 0 to Len - 1 do
      AssertEquals('byte ' + IntToStr(I), Msg[I], R.Buf[I]);
  finally
    R.Free;
  end;
end;

{ Nobody reads: ChClose gives up after 1.5 times the line time of what is
  pending at BD (here 460800 Bd: about 1.2 s for 38 kB left) + 250 ms. }
procedure TTestChnComPty.TestCloseIsBoundedWhenNobodyReads;
const
  Len = 60000;
var
  Msg: array of Byte;
  T0, Took: QWord;
begin
  AssertEquals('open', res_Ok, OpenCom('BD=460800'));
  SetLength(Msg, Len);
  FillChar(Msg[0], Len, $55);
  FChn^.ChSend(@Msg[0], Len);
  AssertEquals('send', res_Ok, FChn^.ChSendResult);
  T0 := GetTickCount64;
  FChn^.ChClose;
  Took := GetTickCount64 - T0;
  AssertEquals('close', res_Ok, FChn^.ChResult);
  AssertEquals('closed', CHS_Close, FChn^.ChReady);
  AssertTrue('waited, bounded (' + IntToStr(Took) + ' ms)', (Took >= 250) and (Took < 3000));
end;

procedure TTestChnComPty.TestOverrunReportedWithoutFlowControl;
var
  Flood: array[0..999] of Byte;
  I: Integer;
  Len: Word;
begin
  AssertEquals('open', res_Ok, OpenCom('LRB=64 FLW=NONE IDL=0'));
  for I := 0 to High(Flood) do
    Flood[I] := Pattern(I);
  AssertTrue('flood', FPty.MasterWriteAll(Flood, 1000, 1000));
  Sleep(100);                       { let the kernel deliver all of it }
  AssertEquals('ready', CHS_ReceiveReady, FChn^.ChReceiveReady);
  Len := 0;
  FChn^.ChReceive(Len);
  AssertEquals('overrun reported', res_Overrun, FChn^.ChReceiveResult);
  AssertEquals('the kept bytes: LRB of them', 64, Len);
  for I := 0 to 63 do
    AssertEquals('kept byte ' + IntToStr(I), Pattern(I), FRBuf[I]);
  AssertEquals('lost bytes counted', 936, Com^.ChLostBytes);
  { reported once; later data is fine }
  Flood[0] := $AA; Flood[1] := $55;
  AssertTrue('more', FPty.MasterWriteAll(Flood, 2, 1000));
  AssertEquals('2 new bytes', 2, ChnReceiveAll(@Flood[10], 2, 2000));
  AssertEquals('first new', $AA, Flood[10]);
  AssertEquals('second new', $55, Flood[11]);
end;

procedure TTestChnComPty.TestFlowControlPausesInsteadOfDropping;
var
  Flood, Back: array[0..9999] of Byte;
  I: Integer;
begin
  AssertEquals('open', res_Ok, OpenCom('LRB=64 FLW=RTSCTS IDL=0'));
  for I := 0 to High(Flood) do
    Flood[I] := Pattern(I);
  AssertTrue('flood', FPty.MasterWriteAll(Flood, SizeOf(Flood), 1000));
  Sleep(100);
  FillChar(Back, SizeOf(Back), 0);
  AssertEquals('everything arrives', SizeOf(Flood), ChnReceiveAll(@Back, SizeOf(Back), 5000));
  for I := 0 to High(Flood) do
    AssertEquals('byte ' + IntToStr(I), Flood[I], Back[I]);
  AssertEquals('nothing lost', 0, Com^.ChLostBytes);
end;

type
  TDelayedWriter = class(TThread)
    Pty: TPtyPair;
    DelayMs: Integer;
    WrittenAt: QWord;
    procedure Execute; override;
  end;

procedure TDelayedWriter.Execute;
var
  B: Byte;
begin
  Sleep(DelayMs);
  B := $42;
  WrittenAt := GetTickCount64;
  Pty.MasterWrite(B, 1);
end;

procedure TTestChnComPty.TestIdleWaitReturnsOnFirstByte;
var
  T0, Took: QWord;
  W: TDelayedWriter;
  St: tChState;
begin
  AssertEquals('open', res_Ok, OpenCom('IDL=400'));
  { no input: one poll waits about IDL }
  T0 := GetTickCount64;
  AssertEquals('nothing', CHS_Receiving, FChn^.ChReceiveReady);
  Took := GetTickCount64 - T0;
  AssertTrue('waited IDL (' + IntToStr(Took) + ' ms)', (Took >= 350) and (Took < 2000));
  { a byte after 100 ms ends the wait at once: with IDL=1000 (the
    largest) anything well below 1 s shows it, even on a loaded machine }
  AssertEquals('open IDL=1000', res_Ok, OpenCom('IDL=1000'));
  W := TDelayedWriter.Create(True);
  try
    W.Pty := FPty;
    W.DelayMs := 100;
    T0 := GetTickCount64;
    W.Start;
    St := FChn^.ChReceiveReady;
    Took := GetTickCount64 - T0;
    W.WaitFor;
    AssertEquals('byte seen', CHS_ReceiveReady, St);
    AssertTrue('returned on the byte (' + IntToStr(Took) + ' ms)', Took < 700);
  finally
    W.Free;
  end;
  { IDL=0 never waits }
  AssertEquals('open IDL=0', res_Ok, OpenCom('IDL=0'));
  T0 := GetTickCount64;
  AssertEquals('nothing', CHS_Receiving, FChn^.ChReceiveReady);
  AssertTrue('no wait', GetTickCount64 - T0 < 200);
end;

procedure TTestChnComPty.TestLegacyPollingLoopCpu;
var
  C0, Used, Busy: Double;
  T0: QWord;
  St: tChState;
  Polls: LongInt;
begin
  { sanity of the measurement: IDL=0 spins and must show as busy }
  AssertEquals('open IDL=0', res_Ok, OpenCom('IDL=0'));
  C0 := CpuMs;
  T0 := GetTickCount64;
  repeat
    St := FChn^.ChReceiveReady;
  until (St = CHS_ReceiveReady) or (GetTickCount64 - T0 >= 300);
  Busy := (CpuMs - C0) / 300 * 100;
  AssertTrue(Format('IDL=0 spins (%.0f %% of a core)', [Busy]), Busy > 10);
  { the legacy loop: repeat until ChReceiveReady = CHS_ReceiveReady, 2 s,
    default IDL }
  AssertEquals('open default IDL', res_Ok, OpenCom(''));
  Polls := 0;
  C0 := CpuMs;
  T0 := GetTickCount64;
  repeat
    St := FChn^.ChReceiveReady;
    Inc(Polls);
  until (St = CHS_ReceiveReady) or (GetTickCount64 - T0 >= 2000);
  Used := CpuMs - C0;
  AssertEquals('no byte came', CHS_Receiving, St);
  WriteLn(Format('info  COM %s: idle legacy loop used %.1f ms CPU in 2 s (%.2f %% of a core, %d polls)',
    [Drv, Used, Used / 20, Polls]));
  AssertTrue(Format('under 5 %% of a core: %.1f ms in 2000 ms (bound %.0f)', [Used,
    IdleCpuBound(100)]), Used < IdleCpuBound(100));
end;

function TTestChnComRtl.Drv: string;
begin
  Result := 'RTLSTRICT';
end;

{$IFDEF CHN_SYNAPSE}
function TTestChnComSynapse.Drv: string;
begin
  Result := 'SYNSTRICT';
end;
{$ENDIF}
{$ENDIF UNIX}

initialization
  {$IFDEF UNIX}
  RegisterTest(TTestChnComRtl);
  {$IFDEF CHN_SYNAPSE}
  RegisterTest(TTestChnComSynapse);
  {$ENDIF}
  {$ENDIF}
end.
