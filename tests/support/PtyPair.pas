{ PtyPair - a pseudo-terminal pair for the serial tests, no hardware needed.

  The slave (/dev/pts/N) is what tChnCom opens with DEV=; the test talks to
  it through the master side: raw, non-blocking. Closing the master hangs
  the slave up, which is what a pulled USB adapter looks like to a program. }
unit PtyPair;

{$MODE OBJFPC}{$H+}

interface

uses
  BaseUnix;

type
  TPtyPair = class
  private
    FMaster: cint;
    FSlavePath: string;
  public
    { Opens /dev/ptmx, unlocks the slave and puts both sides in raw mode.
      Raises an exception when the system has no pseudo terminals. }
    constructor Create;
    destructor Destroy; override;
    { Write to / read from the master side without blocking; -1 on error }
    function MasterWrite(const Buf; Len: LongInt): LongInt;
    function MasterRead(var Buf; Size: LongInt): LongInt;
    { Write all of Buf, waiting up to TimeoutMs; False on timeout. }
    function MasterWriteAll(const Buf; Len: LongInt; TimeoutMs: LongInt): Boolean;
    { Read Len bytes within TimeoutMs; returns how many arrived. }
    function MasterReadAll(var Buf; Len: LongInt; TimeoutMs: LongInt): LongInt;
    { Close the master now: the slave is hung up. }
    procedure CloseMaster;
    property Master: cint read FMaster;
    property SlavePath: string read FSlavePath;
  end;

implementation

uses
  SysUtils, ChnPty;

constructor TPtyPair.Create;
var
  Err: cint;
begin
  inherited Create;
  { the pair itself comes from src/phys/unix/ChnPty, shared with tools/df1sim --pty }
  Err := PtyCreate(FMaster, FSlavePath);
  if Err <> 0 then
    raise Exception.CreateFmt('cannot create a pty pair (errno %d)', [Err]);
end;

destructor TPtyPair.Destroy;
begin
  CloseMaster;
  inherited Destroy;
end;

procedure TPtyPair.CloseMaster;
begin
  if FMaster >= 0 then
    FpClose(FMaster);
  FMaster := -1;
end;

function TPtyPair.MasterWrite(const Buf; Len: LongInt): LongInt;
begin
  Result := FpWrite(FMaster, Buf, Len);
  if (Result < 0) and (FpGetErrno = ESysEAGAIN) then
    Result := 0;
end;

function TPtyPair.MasterRead(var Buf; Size: LongInt): LongInt;
begin
  Result := FpRead(FMaster, Buf, Size);
  if (Result < 0) and (FpGetErrno = ESysEAGAIN) then
    Result := 0;
end;

function TPtyPair.MasterWriteAll(const Buf; Len: LongInt; TimeoutMs: LongInt): Boolean;
var
  P: PByte;
  Done, N: LongInt;
  Deadline: QWord;
begin
  P := @Buf;
  Done := 0;
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  while Done < Len do
  begin
    N := MasterWrite(P[Done], Len - Done);
    if N < 0 then
      Exit(False);
    Inc(Done, N);
    if (N = 0) and (GetTickCount64 > Deadline) then
      Exit(False);
    if N = 0 then
      Sleep(1);
  end;
  Result := True;
end;

function TPtyPair.MasterReadAll(var Buf; Len: LongInt; TimeoutMs: LongInt): LongInt;
var
  P: PByte;
  N: LongInt;
  Deadline: QWord;
begin
  P := @Buf;
  Result := 0;
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  while Result < Len do
  begin
    N := MasterRead(P[Result], Len - Result);
    if N < 0 then
      Exit;
    Inc(Result, N);
    if N = 0 then
    begin
      if GetTickCount64 > Deadline then
        Exit;
      Sleep(1);
    end;
  end;
end;

end.
