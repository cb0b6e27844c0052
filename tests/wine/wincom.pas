{ wincom - ChnCom on the Windows API backend (ChnPortWin), run under Wine
  by tools/wintest.sh against tests/wine/ptyecho on the Linux side.

    wincom <echo COM number> <COM number with no device> [driver]

  driver is DRV= of tChnCom: RTL (default, ChnPortWin) or SYNAPSE (a build
  with -dCHN_SYNAPSE).

  Wine's COM<n> is a symlink in $WINEPREFIX/dosdevices; the script points
  the first one at ptyecho's pty slave, so the bytes go
  tChnCom -> ChnPortWin -> CreateFile/WriteFile -> Wine -> /dev/pts/N ->
  ptyecho, and back. ptyecho also reports the termios Wine derived from our
  DCB, so the settings are checked outside the code under test.
  Prints "ok    ..." / "FAIL  ..." per check and "RESULT <passed> <failed>"
  last; exit code 1 on any failure. Windows only; not part of make test. }
program wincom;

{$MODE OBJFPC}{$H+}

uses
  Windows, Classes, SysUtils, ChnTypes, ChnVirt, ChnCom, ChnLoop, ChnWait;

const
  CmdTermios = #27'CHN!TERMIOS'#27;
  CmdHangup = #27'CHN!HANGUP'#27;
  CmdCount = #27'CHN!COUNT'#27;
  Big = 65536;

var
  Passed, Failed: Integer;
  EchoCom, MissingCom, Drv: string;
  RBuf: array[0..65534] of Byte;

{ What Wine does differently from Windows: reported, not counted. }
procedure Note(const What: string);
begin
  WriteLn('note  wincom ', Drv, ': ', What);
  Flush(Output);
end;

procedure Check(Ok: Boolean; const What: string);
begin
  if Ok then
  begin
    Inc(Passed);
    WriteLn('ok    wincom ', Drv, ': ', What);
  end
  else
  begin
    Inc(Failed);
    WriteLn('FAIL  wincom ', Drv, ': ', What);
  end;
  Flush(Output);
end;

function ResName(R: tChResult): string;
begin
  Result := IntToStr(R);
  case R of
    res_Ok: Result := 'res_Ok';
    res_CannotOpen: Result := 'res_CannotOpen';
    res_NoPermission: Result := 'res_NoPermission';
    res_BadSetting: Result := 'res_BadSetting';
    res_IOError: Result := 'res_IOError';
    res_DeviceLost: Result := 'res_DeviceLost';
    res_Overrun: Result := 'res_Overrun';
  end;
end;

function Pattern(I: LongInt): Byte; inline;
begin
  Result := Byte((I * 7) xor (I shr 8) xor (I shr 16));
end;

{ A COM channel with Params, opened and connected; nil (and R) on failure. }
function OpenCom(const Params: string; out R: tChResult): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(ChnCom.cName);
  Result^.ChSetParam('NAM=COM DRV=' + Drv + ' ' + Params);
  R := Result^.ChResult;
  if R = res_Ok then
  begin
    Result^.ChOpen;
    R := Result^.ChResult;
  end;
  if R = res_Ok then
  begin
    Result^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    Result^.ChConnect;
    R := Result^.ChResult;
  end;
  if R <> res_Ok then
  begin
    Dispose(Result, Done);
    Result := nil;
  end;
end;

{ Send S whole (through ChSendReady polls) and append what arrives to Got
  until it holds Want bytes or TimeoutMs pass. }
procedure Exchange(C: pChnVirt; const S: AnsiString; Want: LongInt;
  var Got: AnsiString; TimeoutMs: LongInt);
var
  Deadline: QWord;
  Sent, Chunk: LongInt;
  Len: Word;
  Start: LongInt;
begin
  Deadline := ChMsTick + QWord(TimeoutMs);
  Sent := 0;
  Start := Length(Got);
  while ((Sent < Length(S)) or (Length(Got) - Start < Want)) and (ChMsTick < Deadline) do
  begin
    if (Sent < Length(S)) and (C^.ChSendReady = CHS_SendReady) then
    begin
      Chunk := Length(S) - Sent;
      if Chunk > 4000 then
        Chunk := 4000;
      C^.ChSend(@S[Sent + 1], Chunk);
      if C^.ChSendResult <> res_Ok then
        Exit;
      Inc(Sent, Chunk);
    end;
    if C^.ChReceiveReady = CHS_ReceiveReady then
    begin
      C^.ChReceive(Len);
      if C^.ChReceiveResult <> res_Ok then
        Exit;
      SetLength(Got, Length(Got) + Len);
      Move(RBuf, Got[Length(Got) - Len + 1], Len);
    end
    else if C^.ChReceiveResult <> res_Ok then
      Exit;
  end;
end;

function AskTermios(C: pChnVirt): string;
var
  Got: AnsiString;
  P: Integer;
  Deadline: QWord;
begin
  Got := '';
  Exchange(C, CmdTermios, Length(CmdTermios) + 20, Got, 3000);
  { the rest of the line }
  Deadline := ChMsTick + 500;
  while (Pos(#10, Got) = 0) and (ChMsTick < Deadline) do
    Exchange(C, '', 1, Got, 50);
  Result := Copy(Got, Length(CmdTermios) + 1, MaxInt);
  P := Pos(#10, Result);
  if P > 0 then
    SetLength(Result, P - 1);
end;

{ The bytes ptyecho has received so far (-1 when no answer came). Echoes
  of earlier frames may come first: the last 'count=' line counts. }
function AskCount(C: pChnVirt): Int64;
var
  Got: AnsiString;
  P, Q: Integer;
  Deadline: QWord;
begin
  Got := '';
  Exchange(C, CmdCount, Length(CmdCount), Got, 3000);
  Deadline := ChMsTick + 3000;
  repeat
    P := Length(Got) - 6;
    while (P > 0) and (Copy(Got, P, 6) <> 'count=') do
      Dec(P);
    Q := P + 6;
    while (P > 0) and (Q <= Length(Got)) and (Got[Q] <> #10) do
      Inc(Q);
    if (P > 0) and (Q <= Length(Got)) then
      Exit(StrToInt64Def(Copy(Got, P + 6, Q - P - 6), -1));
    Exchange(C, '', 1, Got, 50);
  until ChMsTick >= Deadline;
  Result := -1;
end;

{ Nothing sent is lost at a close: 50 times open, send a frame, close at
  once (ChClose, or Dispose with Done every other time); ptyecho's count
  shows whether every byte left the driver. }
procedure TestCloseLosesNothing;
const
  Frames = 50;
  FrameLen = 64;
var
  C: pChnVirt;
  R: tChResult;
  Before, After: Int64;
  Frame: array[0..FrameLen - 1] of Byte;
  I, J, N: Integer;
  Junk: AnsiString;
begin
  C := OpenCom('COM=' + EchoCom, R);
  Check(C <> nil, 'open for the count: ' + ResName(R));
  if C = nil then
    Exit;
  Before := AskCount(C);
  Dispose(C, Done);
  for I := 1 to Frames do
  begin
    C := OpenCom('COM=' + EchoCom, R);
    if C = nil then
    begin
      Check(False, 'open ' + IntToStr(I) + ': ' + ResName(R));
      Exit;
    end;
    for J := 0 to FrameLen - 1 do
      Frame[J] := Pattern(I * FrameLen + J);
    C^.ChSend(@Frame, FrameLen);
    if Odd(I) then
      C^.ChClose;
    Dispose(C, Done);
  end;
  C := OpenCom('COM=' + EchoCom, R);
  Check(C <> nil, 'open after the frames: ' + ResName(R));
  if C = nil then
    Exit;
  After := AskCount(C);
  { echoes of the frames may still be on their way: take them here, so
    the next tests start on a quiet line }
  Junk := '';
  repeat
    N := Length(Junk);
    Exchange(C, '', MaxInt, Junk, 300);
  until Length(Junk) = N;
  Dispose(C, Done);
  Check((Before > 0) and (After - Before = Frames * FrameLen + Length(CmdCount)),
    Format('%d frames sent and closed at once: the peer got %d of %d bytes',
      [Frames, After - Before - Length(CmdCount), Frames * FrameLen]));
end;

type
  TLateLoop = class(TThread)
    Chn: pChnVirt;
    procedure Execute; override;
  end;

procedure TLateLoop.Execute;
var
  B: Byte;
begin
  Sleep(100);
  B := 1;
  Chn^.ChSend(@B, 1);
end;

{ A poll of C (IDL=1000, nothing coming) while another thread sends a
  byte through a LOOP pair after 100 ms: True when the poll returned well
  before its IDL. }
function SharedWaitWakes(C: pChnVirt): Boolean;
var
  A, B: pChnVirt;
  T: TLateLoop;
  T0, Took: QWord;
  LBuf: array[0..15] of Byte;
begin
  A := ChnCollection^.ChNewInit(ChnLoop.cName);
  A^.ChSetParam('PAIR=WINWAIT END=1');
  A^.ChOpen;
  A^.ChReceiveBuffer(@LBuf, SizeOf(LBuf));
  A^.ChConnect;
  B := ChnCollection^.ChNewInit(ChnLoop.cName);
  B^.ChSetParam('PAIR=WINWAIT END=2');
  B^.ChOpen;
  B^.ChConnect;
  T := TLateLoop.Create(True);
  T.Chn := B;
  T0 := ChMsTick;
  T.Start;
  C^.ChReceiveReady;
  Took := ChMsTick - T0;
  T.WaitFor;
  T.Free;
  Result := (Took < 700) and (A^.ChReceiveReady = CHS_ReceiveReady);
  WriteLn('info  wincom ', Drv, ': the COM poll returned after ', Took, ' ms');
  Dispose(A, Done);
  Dispose(B, Done);
end;

procedure TestMissingAndNotSerial;
var
  C: pChnVirt;
  R: tChResult;
  Tmp: string;
  F: THandle;
  X: Char;
begin
  C := OpenCom('COM=' + MissingCom, R);
  Check((C = nil) and (R = res_CannotOpen),
    'COM' + MissingCom + ' (no device): res_CannotOpen, got ' + ResName(R));
  C := ChnCollection^.ChNewInit(ChnCom.cName);
  C^.ChSetParam('NAM=COM DRV=' + Drv + ' COM=' + MissingCom);
  C^.ChOpen;
  Check(C^.ChReady = CHS_Close, 'missing port stays closed');
  Dispose(C, Done);
  { a plain file takes no DCB }
  Tmp := GetTempDir(False) + 'wincom-not-a-port.txt';
  F := FileCreate(Tmp);
  X := 'x';
  FileWrite(F, X, 1);
  FileClose(F);
  C := OpenCom('DEV=' + Tmp, R);
  Check((C = nil) and (R = res_BadSetting), 'a file: res_BadSetting, got ' + ResName(R));
  DeleteFile(Tmp);
end;

procedure TestEcho;
var
  C, C2: pChnVirt;
  R: tChResult;
  S, Got: AnsiString;
  I: LongInt;
  Same: Boolean;
  T0, Took: QWord;
  St: tChState;
  T: string;
  Len: Word;
  Woke: Boolean;
begin
  C := OpenCom('COM=' + EchoCom + ' BD=19200 LRB=65536', R);
  Check(C <> nil, 'COM' + EchoCom + ' BD=19200 opens: ' + ResName(R));
  if C = nil then
    Exit;
  T := AskTermios(C);
  Check(T = 'speed=19200 bits=8 parity=N stop=1 rtscts=0 ixon=0',
    'termios of the slave after BD=19200: ' + T);

  { every byte value, both ways }
  SetLength(S, 256);
  for I := 0 to 255 do
    S[I + 1] := Chr(I);
  Got := '';
  Exchange(C, S, 256, Got, 5000);
  Check(Got = S, 'all 256 byte values back (' + IntToStr(Length(Got)) + ' bytes)');

  { 64 KiB: Write hands over what fits, ChSendReady moves the rest }
  SetLength(S, Big);
  for I := 0 to Big - 1 do
    S[I + 1] := Chr(Pattern(I));
  Got := '';
  T0 := ChMsTick;
  Exchange(C, S, Big, Got, 20000);
  Took := ChMsTick - T0;
  Same := Got = S;
  Check(Same, Format('64 KiB back unchanged (%d bytes in %d ms)', [Length(Got), Took]));

  { IDL: an idle poll waits about IDL ms, no more }
  C^.ChSetParam('IDL=50');
  T0 := ChMsTick;
  St := C^.ChReceiveReady;
  Took := ChMsTick - T0;
  Check((St = CHS_Receiving) and (Took >= 30) and (Took < 500),
    Format('idle poll with IDL=50 waits %d ms', [Took]));

  { a second program on the same port: share mode 0 makes Windows refuse
    it; Wine does not apply share modes to devices, so only a note }
  C2 := OpenCom('COM=' + EchoCom, R);
  Note('second open of an open port: ' + ResName(R) +
    ' (Windows: res_CannotOpen; Wine ignores share mode 0 on devices)');
  if C2 <> nil then
    Dispose(C2, Done);

  { settings reach the device: close, set, open again }
  C^.ChClose;
  C^.ChSetParam('BD=9600 STOP=2 FLW=RTSCTS');
  C^.ChOpen;
  C^.ChConnect;
  Check(C^.ChResult = res_Ok, 'reopen with BD=9600 STOP=2 FLW=RTSCTS: ' + ResName(C^.ChResult));
  T := AskTermios(C);
  Check(T = 'speed=9600 bits=8 parity=N stop=2 rtscts=1 ixon=0',
    'termios after BD=9600 STOP=2 FLW=RTSCTS: ' + T);
  C^.ChClose;
  C^.ChSetParam('BD=115200 STOP=1 FLW=XONXOFF');
  C^.ChOpen;
  C^.ChConnect;
  Check(C^.ChResult = res_Ok, 'reopen with BD=115200 FLW=XONXOFF: ' + ResName(C^.ChResult));
  T := AskTermios(C);
  Check(T = 'speed=115200 bits=8 parity=N stop=1 rtscts=0 ixon=1',
    'termios after BD=115200 FLW=XONXOFF: ' + T);
  C^.ChClose;
  { a rate no Bxxx constant names (DMX): Wine 8 takes it, sets 38400 (its
    custom-divisor fallback, which a pty ignores) and reads 38400 back, so
    ApplyDcb must refuse it; a Wine with termios2 sets the rate itself.
    Never acceptable: open, but another rate on the line. }
  C^.ChSetParam('BD=250000 FLW=NONE');
  C^.ChOpen;
  R := C^.ChResult;
  if R = res_Ok then
  begin
    C^.ChConnect;
    T := AskTermios(C);
    Check(T = 'speed=250000 bits=8 parity=N stop=1 rtscts=0 ixon=0',
      'BD=250000 opened, and the line has it: ' + T);
  end
  else
    Check((R = res_BadSetting) and (C^.ChReady = CHS_Close),
      'BD=250000 the driver changed: res_BadSetting, got ' + ResName(R));
  C^.ChClose;

  { a pty keeps 8 data bits and no parity: the driver changes the setting
    and ApplyDcb must say so instead of falling back silently }
  C^.ChSetParam('BD=19200 FLW=NONE PAR=E');
  C^.ChOpen;
  Check((C^.ChResult = res_BadSetting) and (C^.ChReady = CHS_Close),
    'PAR=E on a pty: res_BadSetting, got ' + ResName(C^.ChResult));
  C^.ChSetParam('PAR=N BIT=7');
  C^.ChOpen;
  Check((C^.ChResult = res_BadSetting) and (C^.ChReady = CHS_Close),
    'BIT=7 on a pty: res_BadSetting, got ' + ResName(C^.ChResult));
  C^.ChClose;
  { RTS_CONTROL_TOGGLE: Wine (like many drivers) refuses it }
  C^.ChSetParam('BIT=8 RS485=KERNEL');
  C^.ChOpen;
  Check((C^.ChResult = res_BadSetting) and (C^.ChReady = CHS_Close),
    'RS485=KERNEL where the driver has no RTS toggle: res_BadSetting, got ' +
    ResName(C^.ChResult));
  C^.ChSetParam('RS485=OFF');
  C^.ChOpen;
  C^.ChConnect;
  Check(C^.ChResult = res_Ok, 'open again after refused settings: ' + ResName(C^.ChResult));

  { IDL: a poll waits for the first byte and returns with it }
  C^.ChSetParam('IDL=500');
  S := 'i';
  C^.ChSend(@S[1], 1);
  T0 := ChMsTick;
  St := C^.ChReceiveReady;
  Took := ChMsTick - T0;
  Check((St = CHS_ReceiveReady) and (Took < 250),
    Format('poll with IDL=500 returns with the echo after %d ms', [Took]));
  C^.ChReceive(Len);

  { the program-wide wait (ChnWait over WaitForMultipleObjects): a byte for
    another channel - a LOOP end written by another thread - ends this
    port's idle wait of IDL=1000 at once; and ChnWaitAny wakes on this
    port's echo }
  C^.ChSetParam('IDL=1000');
  if Drv = 'SYNAPSE' then
  begin
    { documented in ChnPortSynapse: on Windows it waits on its own }
    Note('the Synapse backend is not in the shared wait on Windows (see ChnPortSynapse)');
    C^.ChSetParam('IDL=500');
  end
  else
  begin
  Check(SharedWaitWakes(C), 'a LOOP byte from another thread ends the COM port''s IDL=1000 wait');
  S := 'w';
  C^.ChSend(@S[1], 1);
  T0 := ChMsTick;
  Woke := ChnWaitAny(1000);
  Took := ChMsTick - T0;
  Check(Woke and (Took < 700), Format('ChnWaitAny(1000) wakes on the echo after %d ms', [Took]));
  C^.ChSetParam('IDL=0');
  T0 := ChMsTick;
  while (C^.ChReceiveReady <> CHS_ReceiveReady) and (ChMsTick - T0 < 1000) do
    ;
  C^.ChReceive(Len);
  Check((Len = 1) and (RBuf[0] = Ord('w')), 'the echo is there for its channel');
  T0 := ChMsTick;
  Woke := ChnWaitAny(300);
  Took := ChMsTick - T0;
  Check(not Woke and (Took >= 250), Format('ChnWaitAny(300) with nothing new sleeps: %d ms', [Took]));
  C^.ChSetParam('IDL=500');
  end;

  { ring overrun with FLW=NONE: the first LRB bytes kept, the rest counted }
  C^.ChClose;
  C^.ChSetParam('LRB=64 IDL=0');
  C^.ChOpen;
  C^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  C^.ChConnect;
  SetLength(S, 1000);
  for I := 0 to 999 do
    S[I + 1] := Chr(Pattern(I));
  C^.ChSend(@S[1], 1000);
  T0 := ChMsTick;
  while (C^.ChSendReady <> CHS_SendReady) and (ChMsTick - T0 < 2000) do
    Sleep(1);
  Sleep(200);                      { the echo arrives in Wine's queue }
  St := C^.ChReceiveReady;
  Len := 0;
  C^.ChReceive(Len);
  R := C^.ChReceiveResult;
  Same := (Len = 64) and (CompareByte(RBuf, S[1], 64) = 0);
  Check((St = CHS_ReceiveReady) and (R = res_Overrun) and Same and
    (pChnCom(C)^.ChLostBytes = 936),
    Format('1000 bytes into LRB=64: %s, %d kept (first ones: %s), %d lost',
      [ResName(R), Len, BoolToStr(Same, True), pChnCom(C)^.ChLostBytes]));
  C^.ChClose;
  C^.ChSetParam('LRB=65536 IDL=1');
  C^.ChOpen;
  C^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
  C^.ChConnect;

  { the far end goes away: ptyecho closes the master on this command }
  Got := '';
  Exchange(C, CmdHangup, Length(CmdHangup), Got, 2000);
  T0 := ChMsTick;
  R := res_Ok;
  while (R = res_Ok) and (ChMsTick - T0 < 3000) do
  begin
    C^.ChReceiveReady;
    R := C^.ChReceiveResult;
    if R = res_Ok then
      R := C^.ChResult;
  end;
  { the outstanding overlapped read of the port fails when the tty hangs up }
  Check(R = res_DeviceLost, 'receiving on the hung-up pty: res_DeviceLost, got ' + ResName(R));
  { writing is where Wine sees it: write() gives EIO }
  S := 'x';
  T0 := ChMsTick;
  R := res_Ok;
  while (R = res_Ok) and (ChMsTick - T0 < 3000) do
  begin
    if C^.ChSendReady = CHS_SendReady then
      C^.ChSend(@S[1], 1);
    R := C^.ChSendResult;
  end;
  if pChnCom(C)^.CH_Port <> nil then
    Note('OS error of the failed write: ' + IntToStr(pChnCom(C)^.CH_Port.OSError));
  Check(R = res_DeviceLost, 'sending to the hung-up pty: res_DeviceLost, got ' + ResName(R));
  Check(C^.ChResult = res_DeviceLost, 'ChResult after the loss: ' + ResName(C^.ChResult));
  C^.ChClose;
  C^.ChOpen;
  Check(C^.ChResult = res_CannotOpen, 'reopen of the vanished pty: res_CannotOpen, got ' +
    ResName(C^.ChResult));
  Dispose(C, Done);
end;

begin
  if ParamCount < 2 then
  begin
    WriteLn('usage: wincom <echo COM number> <COM number with no device> [driver]');
    Halt(2);
  end;
  EchoCom := ParamStr(1);
  MissingCom := ParamStr(2);
  Drv := 'RTL';
  if ParamCount >= 3 then
    Drv := ParamStr(3);
  Passed := 0;
  Failed := 0;
  TestMissingAndNotSerial;
  TestCloseLosesNothing;
  TestEcho;
  WriteLn('RESULT ', Passed, ' ', Failed);
  if Failed > 0 then
    Halt(1);
end.
