{ TestSupport - helpers shared by the test units: hex text <-> bytes and
  polling a channel with a deadline so a broken test fails instead of
  hanging. }
unit TestSupport;

{$MODE OBJFPC}{$H+}

interface

uses
  ChnTypes, ChnVirt;

type
  TBytes = array of Byte;

const
  { the six full-duplex frames of the RACOM capture (RACOM note), all CRC: the
    DF1 tests' reference octets }
  RacomFrames: array[1..6] of string = (
    '1002 0300 0B00 7E00 0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100 8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401 1003 15C6',
    '1002 0003 4B00 7E00 0000 D400 0000 3D7F 0080 827F 0080 E943 0100 8D91 1300 E070 7200 E070 7200 0000 1003 0FC9',
    '1002 0300 0A00 7F00 0000 3D7F 7F00 4C08 910B 546F 5472 616E 7370 6F72 7400 2800 1010 0010 03B6 99',
    '1002 0003 4A00 7F00 0000 827F 7F00 CC00 0000 C300 0A1A 0200 0300 0400 0500 0600 0700 0800 0000 0000 0000 0000 0000 0000 0000 0000 1003 854D',
    '1002 0300 0B00 8F00 0000 4E02 2006 2401 07E9 E943 0100 8D91 1300 0200 2002 2401 1010 0010 03A3 C4',
    '1002 0003 4B00 8F00 0000 CE00 0000 E943 0100 8D91 1300 0000 1003 B56A');

{ '10 02 0A' or '10020A' (blanks ignored) -> bytes; any other character
  or an odd number of digits raises, so a typo fails the test }
function HexToBytes(const S: string): TBytes;
function BytesToHex(const B: array of Byte; Len: Integer): string;
{ How often Sub stands in S (not overlapping). }
function CountOf(const Sub, S: AnsiString): Integer;
{ Poll Chn^.ChReceiveReady (and, if given, Other^.ChReceiveReady /
  ChSendReady to keep a peer moving) until a message waits or TimeoutMs. }
function WaitReceive(Chn: pChnVirt; TimeoutMs: Integer; Other: pChnVirt = nil): Boolean;
function WaitSent(Chn: pChnVirt; TimeoutMs: Integer; Other: pChnVirt = nil): Boolean;
{ Build a stack with ChNewInit + ChSetParam, open and connect it; nil and
  Err set when any step fails. }
function OpenStack(const Name, Params: string; var Err: string): pChnVirt;
{ OpenStack for a stack on a TCP server whose port the OS chooses
  (Params end with NAM=TCP LISTEN=127.0.0.1:0, or are LISTEN=... for a
  bare TCP layer); fails the test when it does not open. Port: the port
  the server took. }
function OpenListening(const Name, Params: string; out Port: Word): pChnVirt;
{ Append to Got all Chn has received by now; Buf is the receive buffer
  the caller gave it (ChReceiveBuffer). }
procedure ReceiveAllInto(Chn: pChnVirt; Buf: PByte; var Got: TBytes);
{ How many descriptors process Proc ('self' or a pid) holds open now: the
  entries of /proc/Proc/fd (0 where there is no /proc). }
function OpenFdCount(const Proc: string): LongInt;
{ Build Params ('NAM=ICS ... NAM=NOISE ...', a NOISE layer at the bottom:
  a babbling line), open, connect, give a receive buffer and poll
  ChReceiveReady once: how many bytes that one poll took from the line
  (-1 if the stack did not open), and the state it answered. }
function NoiseOnePoll(const Params: tParamStr; var State: tChState): LongInt;
{ The most CPU an idle polling loop may take in a test (ms, or % of a
  core): Native on the machine itself, three times that under qemu-user
  (make crosstest, CHN_EXEC), where every system call costs tens of
  microseconds of emulation (1000 idle polls: 23-25 ms natively, 35-65 ms
  under qemu-arm); a spinning loop takes ten times more still. }
function IdleCpuBound(Native: Double): Double;
{$IFDEF LINUX}
{ CPU time this process used so far, ms (CLOCK_PROCESS_CPUTIME_ID): what
  a wait costs, whatever else the machine runs. }
function CpuMs: Double;
{$ENDIF}

implementation

uses
  {$IFDEF LINUX}Linux, UnixType,{$ENDIF} SysUtils, fpcunit, uString, ChnNoise, ChnTcp;

{$IFDEF LINUX}
function CpuMs: Double;
var
  Ts: TTimeSpec;
begin
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, @Ts);
  Result := Ts.tv_sec * 1000.0 + Ts.tv_nsec / 1e6;
end;
{$ENDIF}

function IdleCpuBound(Native: Double): Double;
begin
  Result := Native;
  if GetEnvironmentVariable('CHN_EXEC') <> '' then
    Result := 3 * Native;
end;

function NoiseOnePoll(const Params: tParamStr; var State: tChState): LongInt;
var
  C, L: pChnVirt;
  Buf: array[0..511] of Byte;
  Tok: ShortString;
  P, Start: Integer;
begin
  Result := -1;
  State := CHS_Close;
  P := 1;
  Start := 1;
  if not NextTokenAt(Params, P, Tok, Start) then
    Exit;
  C := ChnCollection^.ChNewInit(ParamValue(Tok));
  if C = nil then
    Exit;
  C^.ChSetParam(Params);
  if C^.ChResult = res_Ok then
  begin
    C^.ChOpen;
    C^.ChConnect;
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    if C^.ChResult = res_Ok then
    begin
      State := C^.ChReceiveReady;
      L := C;
      while L^.CH_Low <> nil do
        L := L^.CH_Low;
      if L^.CH_Type = ChnNoise.cName then
        Result := pChnNoise(L)^.CH_Inserted;
    end;
  end;
  Dispose(C, Done);
end;

function HexToBytes(const S: string): TBytes;
var
  Clean: string;
  I: Integer;
begin
  Clean := '';
  for I := 1 to Length(S) do
    if S[I] in ['0'..'9', 'A'..'F', 'a'..'f'] then
      Clean := Clean + S[I]
    else if S[I] <> ' ' then
      { a typo in an expected frame must fail the test, not shorten it }
      raise Exception.CreateFmt('HexToBytes: "%s" at %d in ''%s''', [S[I], I, S]);
  if Odd(Length(Clean)) then
    raise Exception.CreateFmt('HexToBytes: odd number of hex digits in ''%s''', [S]);
  SetLength(Result, Length(Clean) div 2);
  for I := 0 to High(Result) do
    Result[I] := StrToInt('$' + Copy(Clean, I * 2 + 1, 2));
end;

function BytesToHex(const B: array of Byte; Len: Integer): string;
begin
  if Len <= 0 then
    Exit('');
  Result := HexBytes(@B[0], Len);
end;

function CountOf(const Sub, S: AnsiString): Integer;
var
  P: Integer;
begin
  Result := 0;
  P := Pos(Sub, S);
  while P > 0 do
  begin
    Inc(Result);
    P := Pos(Sub, S, P + Length(Sub));
  end;
end;

function WaitReceive(Chn: pChnVirt; TimeoutMs: Integer; Other: pChnVirt): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  repeat
    if Other <> nil then
    begin
      Other^.ChSendReady;
      Other^.ChReceiveReady;
    end;
    Chn^.ChSendReady;
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
      Exit(True);
  until GetTickCount64 > Deadline;
  Result := False;
end;

function WaitSent(Chn: pChnVirt; TimeoutMs: Integer; Other: pChnVirt): Boolean;
var
  Deadline: QWord;
begin
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  repeat
    if Other <> nil then
      Other^.ChReceiveReady;
    if Chn^.ChSendReady = CHS_SendReady then
      Exit(True);
  until GetTickCount64 > Deadline;
  Result := False;
end;

function OpenStack(const Name, Params: string; var Err: string): pChnVirt;
begin
  Err := '';
  Result := ChnCollection^.ChNewInit(Name);
  if Result = nil then
  begin
    Err := 'unknown layer ' + Name;
    Exit;
  end;
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    Err := Params + ': ' + Result^.ChResultStr(Result^.ChResult) + ' ' +
      Result^.ChParamError;
    Dispose(Result, Done);
    Result := nil;
  end;
end;

function OpenListening(const Name, Params: string; out Port: Word): pChnVirt;
var
  Err: string;
  Low: pChnVirt;
begin
  Result := OpenStack(Name, Params, Err);
  TAssert.AssertNotNull(Err, Result);
  Low := Result;
  while Low^.CH_Low <> nil do
    Low := Low^.CH_Low;
  Port := pChnTcp(Low)^.ChLocalPort;
end;

procedure ReceiveAllInto(Chn: pChnVirt; Buf: PByte; var Got: TBytes);
var
  Len: Word;
  K: Integer;
begin
  while Chn^.ChReceiveReady = CHS_ReceiveReady do
  begin
    Len := 0;
    Chn^.ChReceive(Len);
    K := Length(Got);
    SetLength(Got, K + Len);
    Move(Buf^, Got[K], Len);
  end;
end;

function OpenFdCount(const Proc: string): LongInt;
var
  SR: TSearchRec;
begin
  Result := 0;
  if FindFirst('/proc/' + Proc + '/fd/*', faAnyFile, SR) = 0 then
  begin
    repeat
      Inc(Result);
    until FindNext(SR) <> 0;
    FindClose(SR);
  end;
end;

end.
