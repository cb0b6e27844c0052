{ FakePort - the port drivers the channel tests register instead of a
  device, on TChnPort's defaults (a driver overrides only what it does):

    TFakePort    DRV=FAKE: scripted. Records every call in Log, reads
                 RxData, takes at most 100 bytes a Write, answers OutQueue
                 with Queue (then 100 less), GetLines with LineState; can
                 refuse Configure (RefuseConfig, FailKey PAR), kernel RS-485
                 (KernelOk False) and fail reads (ReadFault).
    TEndlessPort DRV=ENDLESS: input that never pauses - every Read fills
                 the buffer (at most MaxRead bytes, 4 KiB as a tty; 0: all
                 it is given, as a socket with a full buffer or a pty whose
                 writer keeps feeding it from the other CPU) with the next
                 bytes of EndlessPattern; writes vanish.

  Test units register the one they use (RegisterPortDriver). }
unit FakePort;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, ChnTypes, ChnPort;

type
  TFakePort = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  public
    class var Log: string;
    class var KernelOk: Boolean;
    class var RefuseConfig: Boolean;
    class var Queue: LongInt;        { OutQueue answers this, then -100 }
    class var RxData: string;
    class var OsLost: LongWord;
    class var LineState: tPortLines; { GetLines answers these }
    class var ReadFault: tChResult;  { Read answers this when not res_Ok }
    { every class var back to its start value }
    class procedure Reset;
    function Open(const Path: tWordString): tChResult; override;
    function Configure(const S: tPortSettings): tChResult; override;
    function WaitInput(Ms: LongInt): Boolean; override;
    function OutQueue(out N: LongInt): tChResult; override;
    function Drain: tChResult; override;
    function SetRts(On: Boolean): tChResult; override;
    function SetDtr(On: Boolean): tChResult; override;
    function GetLines(out Lines: tPortLines): tChResult; override;
    function SetKernelRs485(On: Boolean): tChResult; override;
    function OsOverruns(out N: LongWord): tChResult; override;
    procedure Close; override;
  end;

  TEndlessPort = class(TChnPort)
  protected
    function DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult; override;
    function DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult; override;
  public
    class var Produced: Int64;       { bytes handed out since Open }
    class var MaxRead: LongInt;      { bytes a Read gives at most, 0: no bound }
    function Open(const Path: tWordString): tChResult; override;
    function WaitInput(Ms: LongInt): Boolean; override;
  end;

{ Byte I of TEndlessPort's stream. }
function EndlessPattern(I: Int64): Byte;

implementation

class procedure TFakePort.Reset;
begin
  Log := '';
  KernelOk := False;
  RefuseConfig := False;
  Queue := 0;
  RxData := '';
  OsLost := 0;
  LineState := [];
  ReadFault := res_Ok;
end;

function TFakePort.Open(const Path: tWordString): tChResult;
begin
  FDevice := Path;
  FOpen := True;
  Log := Log + 'open ' + Path + ';';
  Result := res_Ok;
end;

function TFakePort.Configure(const S: tPortSettings): tChResult;
begin
  if RefuseConfig then
  begin
    FailKey := 'PAR';
    Exit(res_BadSetting);
  end;
  Log := Log + Format('cfg %d %d%s%d;', [S.Baud, S.DataBits, 'NEOMS'[Ord(S.Parity) + 1], S.StopBits]);
  Result := res_Ok;
end;

function TFakePort.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
begin
  if ReadFault <> res_Ok then
  begin
    Got := 0;
    Exit(ReadFault);
  end;
  Got := Length(RxData);
  if Got > Size then
    Got := Size;
  if Got > 0 then
    Move(RxData[1], Buf, Got);
  Delete(RxData, 1, Got);
  Result := res_Ok;
end;

function TFakePort.WaitInput(Ms: LongInt): Boolean;
begin
  Result := RxData <> '';
end;

function TFakePort.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
begin
  Done := Len;
  if Done > 100 then
    Done := 100;
  Inc(Queue, Done);
  Log := Log + 'w' + IntToStr(Done) + ';';
  Result := res_Ok;
end;

function TFakePort.OutQueue(out N: LongInt): tChResult;
begin
  N := Queue;
  Log := Log + 'q' + IntToStr(N) + ';';
  Dec(Queue, 100);
  if Queue < 0 then
    Queue := 0;
  Result := res_Ok;
end;

function TFakePort.Drain: tChResult;
begin
  Log := Log + 'drain;';
  Result := res_Ok;
end;

function TFakePort.SetRts(On: Boolean): tChResult;
begin
  Log := Log + 'rts' + IntToStr(Ord(On)) + ';';
  Result := res_Ok;
end;

function TFakePort.SetDtr(On: Boolean): tChResult;
begin
  Log := Log + 'dtr' + IntToStr(Ord(On)) + ';';
  Result := res_Ok;
end;

function TFakePort.GetLines(out Lines: tPortLines): tChResult;
begin
  Lines := LineState;
  Log := Log + 'lines;';
  Result := res_Ok;
end;

function TFakePort.SetKernelRs485(On: Boolean): tChResult;
begin
  if not KernelOk then
    Exit(res_BadSetting);
  Log := Log + 'k' + IntToStr(Ord(On)) + ';';
  Result := res_Ok;
end;

function TFakePort.OsOverruns(out N: LongWord): tChResult;
begin
  N := OsLost;
  Result := res_Ok;
end;

procedure TFakePort.Close;
begin
  if FOpen then
    Log := Log + 'close;';
  FOpen := False;
end;

function EndlessPattern(I: Int64): Byte;
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

function TEndlessPort.DoRead(var Buf; Size: LongInt; out Got: LongInt): tChResult;
var
  I: LongInt;
  P: PByte;
begin
  { there is always more; a tty hands out 4 KiB a read (MaxRead) }
  Got := Size;
  if (MaxRead > 0) and (Got > MaxRead) then
    Got := MaxRead;
  P := @Buf;
  for I := 0 to Got - 1 do
    P[I] := EndlessPattern(Produced + I);
  Inc(Produced, Got);
  Result := res_Ok;
end;

function TEndlessPort.WaitInput(Ms: LongInt): Boolean;
begin
  Result := True;
end;

function TEndlessPort.DoWrite(const Buf; Len: LongInt; out Done: LongInt): tChResult;
begin
  Done := Len;
  Result := res_Ok;
end;

end.
