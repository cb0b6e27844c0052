{ ChnPortWin - TChnPort on the Windows API (CreateFile, SetCommState,
  SetCommTimeouts, ReadFile, WriteFile, ClearCommError). Registered as
  driver 'RTL' on Windows; compiled only there (tools/build-win64.sh
  cross-compiles it on Debian, make wintest runs it under Wine on COM
  ports linked to Linux ptys: docs/Windows.md).

  The handle is opened exclusively, for overlapped I/O, with no read
  timeouts. While the port is open one overlapped read of a single byte
  is always outstanding ("the waiting read"): it completes at the first
  byte that arrives and signals its event, which is what this port gives
  the program-wide wait (unit ChnWait, a wkHandle source) and what
  WaitInput waits on. Read never waits: it takes the byte of a completed
  waiting read, then exactly the cbInQue bytes ClearCommError reports (a
  read of bytes that are there completes at once), and starts the next
  waiting read. (WaitCommEvent(EV_RXCHAR) would be the textbook event, but
  Wine 8 ends it at once on a pty; a pending one-byte read works on both.)
  Writes never wait either: Write hands over only what fits in the
  driver's output queue (SetupComm size minus ClearCommError's cbOutQue),
  and a 1 ms write timeout bounds any driver that still blocks.

  Result mapping: ERROR_FILE_NOT_FOUND/PATH_NOT_FOUND, and ACCESS_DENIED or
  SHARING_VIOLATION at open (Windows' answer for a port in use by another
  program) -> res_CannotOpen; a handle that takes no DCB (not a serial
  device) or a DCB the driver rejects or changes -> res_BadSetting (FailKey
  names the setting: for a rejected DCB the settings are tried one at a
  time to find it); the
  errors a pulled USB adapter gives (ACCESS_DENIED, BAD_COMMAND,
  GEN_FAILURE, OPERATION_ABORTED, DEVICE_NOT_CONNECTED) and NOT_READY or
  BROKEN_PIPE (what Wine makes of EIO from a hung-up tty) -> res_DeviceLost.
  CE_OVERRUN / CE_RXOVER are counted for OsOverruns, one per event (Windows
  does not say how many bytes were lost). }
unit ChnPortWin;

{$I chn.inc}

interface

uses
  Windows, ChnTypes, ChnWait, ChnPort;

type
  TChnPortWin = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  private
    FH: THandle;
    FOutSize: DWORD;
    FToggle: Boolean;          {< RTS_CONTROL_TOGGLE requested }
    FFlow: tPortFlow;
    FOverruns: LongWord;
    FWaitOv: TOverlapped;      {< the waiting read; its hEvent is the wait source }
    FIoOv: TOverlapped;        {< reads and writes that complete at once }
    FWaitByte: Byte;
    FWaitPending: Boolean;     {< the waiting read is outstanding }
    FWaitHas: Boolean;         {< it completed with FWaitByte, not yet delivered }
    FWaitErr: DWORD;           {< it failed with this error (device lost ...) }
    function Fail(E: DWORD): tChResult;
    function EscapeLine(Code: DWORD): tChResult;
    procedure ArmWait;
    procedure CollectWait(Block: Boolean);
    function IoResult(Ok: BOOL; out N: DWORD): Boolean;
    function Status(out InQue, OutQue: DWORD): tChResult;
    function ApplyDcb(var D: TDCB): tChResult;
    function RejectedKey(const D: TDCB): ShortString;
    function Refuse(const Key: ShortString): tChResult;
  public
    constructor Create; override;
    function Open(const Path: tWordString): tChResult; override;
    function Configure(const S: tPortSettings): tChResult; override;
    function WaitInput(Ms: LongInt): Boolean; override;
    function WaitOutput(Ms: LongInt): Boolean; override;
    function OutQueue(out N: LongInt): tChResult; override;
    function Drain: tChResult; override;
    function Flush(Input, Output: Boolean): tChResult; override;
    function SetRts(On: Boolean): tChResult; override;
    function SetDtr(On: Boolean): tChResult; override;
    function GetLines(out Lines: tPortLines): tChResult; override;
    function SetKernelRs485(On: Boolean): tChResult; override;
    function OsOverruns(out N: LongWord): tChResult; override;
    function WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
      out Rearm: tChnWaitRearm; out Data: Pointer): Boolean; override;
    function OsHandle: PtrInt; override;
    procedure Close; override;
  end;

implementation

const
  ERROR_DEVICE_NOT_CONNECTED_ = 1167;
  STATUS_PENDING_ = $103;
  DefaultOutQueue = 4096;
  { DCB.flags bits (winbase.h) }
  fBinary          = $0001;
  fParity          = $0002;
  fOutxCtsFlow     = $0004;
  fOutxDsrFlow     = $0008;
  fDtrControlMask  = $0030;
  fDtrControlEnable = $0010;
  fDsrSensitivity  = $0040;
  fTXContinueOnXoff = $0080;
  fOutX            = $0100;
  fInX             = $0200;
  fErrorChar       = $0400;
  fNull            = $0800;
  fRtsControlMask  = $3000;
  fRtsControlEnable = $1000;
  fRtsControlHandshake = $2000;
  fRtsControlToggle = $3000;
  fAbortOnError    = $4000;

constructor TChnPortWin.Create;
begin
  inherited Create;
  FH := INVALID_HANDLE_VALUE;
  FOutSize := DefaultOutQueue;
  FToggle := False;
  FFlow := flowNone;
  FOverruns := 0;
  FillChar(FWaitOv, SizeOf(FWaitOv), 0);
  FillChar(FIoOv, SizeOf(FIoOv), 0);
end;

{ An overlapped call that may have gone pending: wait for it (it moves
  bytes that are there, or is bounded by the 1 ms write timeout). }
function TChnPortWin.IoResult(Ok: BOOL; out N: DWORD): Boolean;
begin
  if Ok then
    Exit(GetOverlappedResult(FH, FIoOv, N, False));
  N := 0;
  Result := (GetLastError = ERROR_IO_PENDING) and GetOverlappedResult(FH, FIoOv, N, True);
end;

{ Start the waiting read unless it is outstanding or its byte waits. }
procedure TChnPortWin.ArmWait;
var
  N: DWORD;
begin
  if not FOpen or FWaitPending or FWaitHas or (FWaitErr <> 0) then
  begin
    if FWaitHas or (FWaitErr <> 0) then
      SetEvent(FWaitOv.hEvent);     { still to be taken: keep waking }
    Exit;
  end;
  ResetEvent(FWaitOv.hEvent);
  N := 0;
  if ReadFile(FH, FWaitByte, 1, N, @FWaitOv) then
    FWaitHas := N = 1               { a byte was there already }
  else if GetLastError = ERROR_IO_PENDING then
    FWaitPending := True
  else
    FWaitErr := GetLastError;
  if FWaitHas or (FWaitErr <> 0) then
    SetEvent(FWaitOv.hEvent);
end;

{ The waiting read's outcome, if it has one (Block: wait for it). }
procedure TChnPortWin.CollectWait(Block: Boolean);
var
  N: DWORD;
begin
  if not FWaitPending then
    Exit;
  if not Block and (FWaitOv.Internal = STATUS_PENDING_) then   { HasOverlappedIoCompleted }
    Exit;
  N := 0;
  if GetOverlappedResult(FH, FWaitOv, N, True) then
    FWaitHas := N = 1
  else if GetLastError <> ERROR_OPERATION_ABORTED then
    FWaitErr := GetLastError;       { aborted: by our own Flush or Close }
  FWaitPending := False;
end;

procedure WinRearm(Data: Pointer);
begin
  TChnPortWin(Data).ArmWait;
end;

function TChnPortWin.WaitSource(out Kind: tChnWaitKind; out Os: PtrInt;
  out Rearm: tChnWaitRearm; out Data: Pointer): Boolean;
begin
  Kind := wkHandle;
  Os := PtrInt(FWaitOv.hEvent);
  Rearm := @WinRearm;
  Data := Self;
  Result := FOpen;
end;

function TChnPortWin.Fail(E: DWORD): tChResult;
begin
  FOSError := LongInt(E);
  case E of
    ERROR_FILE_NOT_FOUND, ERROR_PATH_NOT_FOUND, ERROR_SHARING_VIOLATION:
      if FOpen then
        Result := res_DeviceLost
      else
        Result := res_CannotOpen;
    ERROR_ACCESS_DENIED:
      if FOpen then
        Result := res_DeviceLost
      else
        Result := res_CannotOpen;   { in use; Windows says the same for rights }
    ERROR_INVALID_FUNCTION, ERROR_INVALID_PARAMETER, ERROR_NOT_SUPPORTED:
      Result := res_BadSetting;
    ERROR_BAD_COMMAND, ERROR_GEN_FAILURE, ERROR_OPERATION_ABORTED,
    ERROR_INVALID_HANDLE, ERROR_DEVICE_NOT_CONNECTED_,
    ERROR_NOT_READY,                { Wine's word for EIO: a tty hung up }
    ERROR_BROKEN_PIPE:              { ... and for it in overlapped I/O }
      Result := res_DeviceLost;
  else
    Result := res_IOError;
  end;
end;

{ Queue sizes and line errors; overrun events are counted here. }
function TChnPortWin.Status(out InQue, OutQue: DWORD): tChResult;
var
  Errs: DWORD;
  St: TComStat;
begin
  InQue := 0;
  OutQue := 0;
  Errs := 0;
  FillChar(St, SizeOf(St), 0);
  if not ClearCommError(FH, Errs, @St) then
    Exit(Fail(GetLastError));
  if Errs and (CE_OVERRUN or CE_RXOVER) <> 0 then
    Inc(FOverruns);
  InQue := St.cbInQue;
  OutQue := St.cbOutQue;
  Result := res_Ok;
end;

function TChnPortWin.Open(const Path: tWordString): tChResult;
var
  Name: AnsiString;
  H: THandle;
  D: TDCB;
  T: TCommTimeouts;
begin
  if FOpen then
    Exit(res_WrongState);
  FDevice := Path;
  FOSError := 0;
  FailKey := '';
  Name := Path;
  H := CreateFileA(PAnsiChar(Name), GENERIC_READ or GENERIC_WRITE, 0, nil,
    OPEN_EXISTING, FILE_FLAG_OVERLAPPED, 0);
  if H = INVALID_HANDLE_VALUE then
    Exit(Fail(GetLastError));
  FillChar(D, SizeOf(D), 0);
  D.DCBlength := SizeOf(D);
  if not GetCommState(H, D) then
  begin
    CloseHandle(H);
    FOSError := LongInt(GetLastError);
    Exit(res_BadSetting);           { not a serial device }
  end;
  FillChar(T, SizeOf(T), 0);
  { no read timeouts: a read ends when its bytes came (Read asks only for
    bytes that are there; the waiting read for the next one) }
  T.WriteTotalTimeoutConstant := 1;   { a blocking driver stalls 1 ms at most }
  if not SetCommTimeouts(H, T) then
  begin
    Result := Fail(GetLastError);
    CloseHandle(H);
    Exit;
  end;
  FH := H;
  FOpen := True;
  FOverruns := 0;
  FillChar(FWaitOv, SizeOf(FWaitOv), 0);
  FillChar(FIoOv, SizeOf(FIoOv), 0);
  FWaitOv.hEvent := CreateEvent(nil, True, False, nil);
  FIoOv.hEvent := CreateEvent(nil, True, False, nil);
  FWaitPending := False;
  FWaitHas := False;
  FWaitErr := 0;
  ArmWait;
  Result := res_Ok;
end;

function TChnPortWin.Refuse(const Key: ShortString): tChResult;
begin
  FailKey := Key;
  Result := res_BadSetting;
end;

{ SetCommState refused D as a whole: change the port's DCB towards D one
  setting at a time; the first one refused is the one to name. }
function TChnPortWin.RejectedKey(const D: TDCB): ShortString;
var
  C: TDCB;
begin
  FillChar(C, SizeOf(C), 0);
  C.DCBlength := SizeOf(C);
  Result := 'BD';
  if not GetCommState(FH, C) then
    Exit;
  C.BaudRate := D.BaudRate;
  if not SetCommState(FH, C) then
    Exit('BD');
  C.ByteSize := D.ByteSize;
  if not SetCommState(FH, C) then
    Exit('BIT');
  C.StopBits := D.StopBits;
  if not SetCommState(FH, C) then
    Exit('STOP');
  C.Parity := D.Parity;
  C.flags := (C.flags and not fParity) or (D.flags and fParity);
  if not SetCommState(FH, C) then
    Exit('PAR');
  Result := 'FLW';                  { what is left: handshake and RTS }
end;

function TChnPortWin.ApplyDcb(var D: TDCB): tChResult;
var
  Back: TDCB;
  Rts, BackRts: DWORD;
begin
  if not SetCommState(FH, D) then
  begin
    Result := Fail(GetLastError);
    if Result = res_BadSetting then
      FailKey := RejectedKey(D);
    Exit;
  end;
  FillChar(Back, SizeOf(Back), 0);
  Back.DCBlength := SizeOf(Back);
  if not GetCommState(FH, Back) then
    Exit(Fail(GetLastError));
  Rts := D.flags and fRtsControlMask;
  BackRts := Back.flags and fRtsControlMask;
  { Wine reads RTS/CTS handshake back as RTS_CONTROL_ENABLE plus
    fOutxCtsFlow (its termios CRTSCTS covers both directions) }
  if (Rts = fRtsControlHandshake) and (BackRts = fRtsControlEnable) and
     (Back.flags and fOutxCtsFlow <> 0) then
    BackRts := fRtsControlHandshake;
  { the driver changed it: no fallback }
  if Back.BaudRate <> D.BaudRate then
    Exit(Refuse('BD'));
  if Back.ByteSize <> D.ByteSize then
    Exit(Refuse('BIT'));
  if Back.Parity <> D.Parity then
    Exit(Refuse('PAR'));
  if Back.StopBits <> D.StopBits then
    Exit(Refuse('STOP'));
  if (BackRts <> Rts) or ((Back.flags and fOutxCtsFlow) <> (D.flags and fOutxCtsFlow)) then
    Exit(Refuse('FLW'));
  Result := res_Ok;
end;

function TChnPortWin.Configure(const S: tPortSettings): tChResult;
var
  D: TDCB;
  InSize: DWORD;
begin
  if not FOpen then
    Exit(res_WrongState);
  FailKey := '';
  if not (S.DataBits in [5..8]) then
    Exit(Refuse('BIT'));
  if not (S.StopBits in [1, 2]) then
    Exit(Refuse('STOP'));
  InSize := S.InQueue;
  if InSize < 16 then
    InSize := 16;
  FOutSize := DefaultOutQueue;
  SetupComm(FH, InSize, FOutSize);  { a hint; drivers may keep their own }
  FillChar(D, SizeOf(D), 0);
  D.DCBlength := SizeOf(D);
  if not GetCommState(FH, D) then
    Exit(Fail(GetLastError));
  D.BaudRate := S.Baud;
  D.ByteSize := S.DataBits;
  case S.Parity of
    ppNone: D.Parity := NOPARITY;
    ppEven: D.Parity := EVENPARITY;
    ppOdd: D.Parity := ODDPARITY;
    ppMark: D.Parity := MARKPARITY;
    ppSpace: D.Parity := SPACEPARITY;
  end;
  if S.StopBits = 2 then
    D.StopBits := TWOSTOPBITS
  else
    D.StopBits := ONESTOPBIT;
  D.flags := fBinary or fDtrControlEnable or fTXContinueOnXoff;
  if S.Parity <> ppNone then
    D.flags := D.flags or fParity;
  case S.Flow of
    flowNone: D.flags := D.flags or fRtsControlEnable;
    flowRtsCts: D.flags := D.flags or fOutxCtsFlow or fRtsControlHandshake;
    flowXonXoff: D.flags := D.flags or fOutX or fInX or fRtsControlEnable;
  end;
  if FToggle and (S.Flow <> flowRtsCts) then
    D.flags := (D.flags and not fRtsControlMask) or fRtsControlToggle;
  D.XonChar := #17;
  D.XoffChar := #19;
  D.XonLim := InSize div 4;
  D.XoffLim := InSize div 4;
  FFlow := S.Flow;
  Result := ApplyDcb(D);
end;

function TChnPortWin.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  N, InQ, OutQ: DWORD;
  P: PByte;
begin
  P := @Buf;
  if FWaitPending then
  begin
    { bytes in the queue while the waiting read is still outstanding: it
      is about to complete with the first of them (Wine completes it a
      moment later) - wait for it, or the next bytes would come first }
    Result := Status(InQ, OutQ);
    if Result <> res_Ok then
      Exit;
    CollectWait(InQ > 0);
  end;
  if FWaitErr <> 0 then
    Exit(Fail(FWaitErr));
  if FWaitPending then
    Exit(res_Ok);                   { it would have the first byte: none came }
  if FWaitHas then
  begin
    P^ := FWaitByte;
    FWaitHas := False;
    Got := 1;
  end;
  Result := Status(InQ, OutQ);      { also picks up overrun flags }
  if (Result = res_Ok) and (InQ > 0) and (Got < Size) then
  begin
    if InQ > DWORD(Size - Got) then
      InQ := Size - Got;
    if not IoResult(ReadFile(FH, P[Got], InQ, N, @FIoOv), N) then
      Exit(Fail(GetLastError));
    Inc(Got, N);
  end;
  if Result = res_Ok then
    ArmWait;                        { the next byte signals again }
end;

function TChnPortWin.WaitInput(Ms: LongInt): Boolean;
begin
  Result := False;
  if not FOpen then
    Exit;
  ArmWait;
  Result := FWaitHas or (FWaitErr <> 0) or
    (WaitForSingleObject(FWaitOv.hEvent, DWORD(Ms)) = WAIT_OBJECT_0);
end;

function TChnPortWin.WaitOutput(Ms: LongInt): Boolean;
var
  Deadline: QWord;
  InQ, OutQ: DWORD;
begin
  Result := False;
  if not FOpen then
    Exit;
  Deadline := GetTickCount64 + QWord(Ms);
  repeat
    if (Status(InQ, OutQ) <> res_Ok) or (OutQ < FOutSize) then
      Exit(True);
    if GetTickCount64 >= Deadline then
      Exit;
    Sleep(1);
  until False;
end;

function TChnPortWin.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
var
  InQ, OutQ, N: DWORD;
  Room: LongInt;
begin
  Result := Status(InQ, OutQ);
  if Result <> res_Ok then
    Exit;
  Room := LongInt(FOutSize) - LongInt(OutQ);
  if Room <= 0 then
    Exit(res_Ok);
  if Len > Room then
    Len := Room;
  N := 0;
  if not IoResult(WriteFile(FH, Buf, DWORD(Len), N, @FIoOv), N) then
    Exit(Fail(GetLastError));
  Done := N;                        { a write timeout leaves N < Len }
  Result := res_Ok;
end;

function TChnPortWin.OutQueue(out N: LongInt): tChResult;
var
  InQ, OutQ: DWORD;
begin
  N := 0;
  if not FOpen then
    Exit(res_WrongState);
  Result := Status(InQ, OutQ);
  N := OutQ;
end;

function TChnPortWin.Drain: tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if not FlushFileBuffers(FH) then   { returns when the driver has sent all }
    Exit(Fail(GetLastError));
  Result := res_Ok;
end;

function TChnPortWin.Flush(Input, Output: Boolean): tChResult;
var
  F: DWORD;
begin
  if not FOpen then
    Exit(res_WrongState);
  F := 0;
  if Input then
    F := F or PURGE_RXCLEAR or PURGE_RXABORT;
  if Output then
    F := F or PURGE_TXCLEAR or PURGE_TXABORT;
  if (F <> 0) and not PurgeComm(FH, F) then
    Exit(Fail(GetLastError));
  if Input then
  begin
    CollectWait(True);              { PURGE_RXABORT ended the waiting read }
    FWaitHas := False;
    ArmWait;
  end;
  Result := res_Ok;
end;

{ One modem line by its EscapeCommFunction code. The codes are written
  Windows.SETRTS ...: inside the class, SETRTS names the method SetRts. }
function TChnPortWin.EscapeLine(Code: DWORD): tChResult;
begin
  if not FOpen then
    Exit(res_WrongState);
  if not EscapeCommFunction(FH, Code) then
    Exit(Fail(GetLastError));       { RTS under handshake: res_BadSetting }
  Result := res_Ok;
end;

function TChnPortWin.SetRts(On: Boolean): tChResult;
begin
  if On then
    Result := EscapeLine(Windows.SETRTS)
  else
    Result := EscapeLine(Windows.CLRRTS);
end;

function TChnPortWin.SetDtr(On: Boolean): tChResult;
begin
  if On then
    Result := EscapeLine(Windows.SETDTR)
  else
    Result := EscapeLine(Windows.CLRDTR);
end;

function TChnPortWin.GetLines(out Lines: tPortLines): tChResult;
var
  M: DWORD;
begin
  Lines := [];
  if not FOpen then
    Exit(res_WrongState);
  M := 0;
  if not GetCommModemStatus(FH, M) then
    Exit(Fail(GetLastError));
  if M and MS_CTS_ON <> 0 then
    Include(Lines, plCts);
  if M and MS_DSR_ON <> 0 then
    Include(Lines, plDsr);
  if M and MS_RING_ON <> 0 then
    Include(Lines, plRing);
  if M and MS_RLSD_ON <> 0 then
    Include(Lines, plCarrier);
  Result := res_Ok;
end;

function TChnPortWin.SetKernelRs485(On: Boolean): tChResult;
var
  D: TDCB;
begin
  if not FOpen then
    Exit(res_WrongState);
  if On = FToggle then
    Exit(res_Ok);
  if On and (FFlow = flowRtsCts) then
    Exit(res_BadSetting);           { RTS cannot be handshake and toggle }
  FillChar(D, SizeOf(D), 0);
  D.DCBlength := SizeOf(D);
  if not GetCommState(FH, D) then
    Exit(Fail(GetLastError));
  if On then
    D.flags := (D.flags and not fRtsControlMask) or fRtsControlToggle
  else
    D.flags := (D.flags and not fRtsControlMask) or fRtsControlEnable;
  Result := ApplyDcb(D);            { drivers without toggle refuse or change it }
  if Result = res_Ok then
    FToggle := On;
end;

function TChnPortWin.OsOverruns(out N: LongWord): tChResult;
begin
  N := FOverruns;
  if not FOpen then
    Exit(res_WrongState);
  Result := res_Ok;
end;

function TChnPortWin.OsHandle: PtrInt;
begin
  if FOpen then
    Result := PtrInt(FH)
  else
    Result := -1;
end;

procedure TChnPortWin.Close;
begin
  if FH <> INVALID_HANDLE_VALUE then
  begin
    if FWaitPending then
    begin
      CancelIo(FH);
      CollectWait(True);            { the OVERLAPPED must outlive the read }
    end;
    CloseHandle(FH);
  end;
  if FWaitOv.hEvent <> 0 then
    CloseHandle(FWaitOv.hEvent);
  if FIoOv.hEvent <> 0 then
    CloseHandle(FIoOv.hEvent);
  FillChar(FWaitOv, SizeOf(FWaitOv), 0);
  FillChar(FIoOv, SizeOf(FIoOv), 0);
  FWaitPending := False;
  FWaitHas := False;
  FWaitErr := 0;
  FH := INVALID_HANDLE_VALUE;
  FOpen := False;
  FToggle := False;
end;

initialization
  RegisterPortDriver('RTL', TChnPortWin);
end.
