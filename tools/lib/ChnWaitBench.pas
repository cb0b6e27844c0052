{ ChnWaitBench - the many-lines scenario of bench/benchwait ("make bench")
  and of its short check in the suite (TestChnWait), Linux only.

  A legacy round-robin program - N DF1 full-duplex slaves on N pseudo
  terminals this unit creates, polled with
    for I := 1 to N do if Chn[I]^.ChReceiveReady = CHS_ReceiveReady then ...
  and default parameters (IDL=1) - answers Echo commands. A peer thread
  sends each Echo as raw bytes to a random line's pty master and times the
  reply (DLE ACK + reply frame) with poll(2) on that master, then ACKs it;
  the peer never touches the library, so it does not join the wait it
  measures. IdleCpu measures the same program with nobody sending. }
unit ChnWaitBench;

{$I chn.inc}

interface

type
  tLatency = record
    Count : LongInt;        { replies timed }
    Median, P90, P99, Max: Double;   { ms }
  end;

  tIdleCost = record
    CpuPct   : Double;      { CPU of the polling program, % of one core }
    WakePerS : Double;      { voluntary context switches (sleeps) a second }
    PollPerS : Double;      { rounds over all lines a second }
  end;

{ Count Echoes to random lines of N, a pause of 0..PauseMs ms before each
  (so the program is found both polling and asleep). False and Err when
  something failed (a pty, a wrong or missing reply within 2 s). }
function RoundRobinEchoes(N, Count, PauseMs: LongInt; var L: tLatency;
  var Err: ShortString): Boolean;
{ The program polling N idle lines for Ms ms. }
function IdleCost(N, Ms: LongInt; var C: tIdleCost; var Err: ShortString): Boolean;
{ Seconds of a monotonic clock, microsecond resolution. }
function NowSec: Double;
{ CPU seconds this process has used (all threads). }
function CpuSec: Double;
{ Sort A[0..N-1] ascending and give the value at fraction Q (0..1). }
function Quantile(var A: array of Double; N: LongInt; Q: Double): Double;

implementation

uses
  Classes, SysUtils, BaseUnix, Unix, Linux, Syscall, ChnTypes, ChnVirt,
  ChnCom, ChnDF1, ChnDF1Codec, ChnPty;

const
  MaxLines = 256;
  EchoData: array[0..3] of Byte = ($41, $68, $6F, $6A);
  SlaveParams = 'NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=COM BD=19200 DEV=';

type
  tLines = record
    N     : LongInt;
    Master: array[0..MaxLines - 1] of cint;
    Slave : array[0..MaxLines - 1] of ShortString;
    Chn   : array[0..MaxLines - 1] of pChnVirt;
  end;

  { struct rusage of getrusage(2), which the RTL does not wrap }
  tRUsage = record
    UTime, STime: TTimeVal;
    MaxRss, IxRss, IdRss, IsRss, MinFlt, MajFlt, NSwap, InBlock, OuBlock,
    MsgSnd, MsgRcv, NSignals, NvCsw, NivCsw: PtrInt;
  end;

  TPeer = class(TThread)
  public
    Lines  : ^tLines;
    Count, PauseMs: LongInt;
    Times  : array of Double;
    Done   : Boolean;
    Err    : ShortString;
    procedure Execute; override;
  end;

function NowSec: Double;
var
  T: TTimeSpec;
begin
  clock_gettime(CLOCK_MONOTONIC, @T);
  Result := T.tv_nsec;
  Result := T.tv_sec + Result / 1e9;    { a Double: 1e9 alone is a Single }
end;

function CpuSec: Double;
var
  T: TTimeSpec;
begin
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, @T);
  Result := T.tv_nsec;
  Result := T.tv_sec + Result / 1e9;
end;

function Quantile(var A: array of Double; N: LongInt; Q: Double): Double;
var
  I, J: LongInt;
  X: Double;
begin
  { insertion sort: a few thousand values }
  for I := 1 to N - 1 do
  begin
    X := A[I];
    J := I - 1;
    while (J >= 0) and (A[J] > X) do
    begin
      A[J + 1] := A[J];
      Dec(J);
    end;
    A[J + 1] := X;
  end;
  if N = 0 then
    Exit(0);
  I := Trunc(Q * (N - 1) + 0.5);
  Result := A[I];
end;

{ The wire bytes of the Echo command and of what the slave answers. }
procedure EchoFrames(var Cmd: array of Byte; var CmdLen: Word;
  var Reply: array of Byte; var ReplyLen: Word);
var
  Cfg: tDF1Config;
  R: tSendRecord;
  N: Word;
begin
  FillChar(Cfg, SizeOf(Cfg), 0);
  Cfg.FullDup := True;
  Cfg.Crc := True;
  Cfg.Node := 0;
  Cfg.DNode := 1;
  Cfg.NakByte := NAK;
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF_Echo;
  R.Tns := 7;
  Move(EchoData, R.Data, SizeOf(EchoData));
  DF1Encode(Cfg, R, 8 + SizeOf(EchoData), Cmd, High(Cmd) + 1, CmdLen);
  Cfg.Node := 1;
  Cfg.DNode := 0;
  Reply[0] := DLE;
  Reply[1] := ACK;
  R.CF := CF_Echo or MskCF_Reply;
  N := 0;
  DF1Encode(Cfg, R, 8 + SizeOf(EchoData), Reply[2], High(Reply) - 1, N);
  ReplyLen := N + 2;
end;

procedure TPeer.Execute;
var
  Cmd, Want, Got: array[0..63] of Byte;
  CmdLen, WantLen: Word;
  I, K, Have, R: LongInt;
  P: TPollFd;
  T0: Double;
  AckBytes: array[0..1] of Byte;
begin
  Err := '';
  EchoFrames(Cmd, CmdLen, Want, WantLen);
  AckBytes[0] := DLE;
  AckBytes[1] := ACK;
  SetLength(Times, Count);
  RandSeed := 11;
  for I := 0 to Count - 1 do
  begin
    if PauseMs > 0 then
      Sleep(Random(PauseMs + 1));
    K := Random(Lines^.N);
    T0 := NowSec;
    if FpWrite(Lines^.Master[K], Cmd, CmdLen) <> CmdLen then
    begin
      Err := 'write to line ' + IntToStr(K) + ' failed';
      Break;
    end;
    Have := 0;
    while Have < WantLen do
    begin
      P.fd := Lines^.Master[K];
      P.events := POLLIN;
      P.revents := 0;
      if FpPoll(@P, 1, 2000) <= 0 then
        Break;
      R := FpRead(Lines^.Master[K], Got[Have], SizeOf(Got) - Have);
      if R <= 0 then
        Break;
      Inc(Have, R);
    end;
    Times[I] := (NowSec - T0) * 1000;
    if (Have <> WantLen) or (CompareByte(Got, Want, WantLen) <> 0) then
    begin
      Err := Format('line %d: reply %d of %d bytes or wrong', [K, Have, WantLen]);
      Break;
    end;
    FpWrite(Lines^.Master[K], AckBytes, 2);
  end;
  Done := True;
end;

procedure CloseLines(var L: tLines);
var
  I: LongInt;
begin
  for I := 0 to L.N - 1 do
  begin
    if L.Chn[I] <> nil then
      Dispose(L.Chn[I], Done);
    L.Chn[I] := nil;
    if L.Master[I] >= 0 then
      FpClose(L.Master[I]);
    L.Master[I] := -1;
  end;
  L.N := 0;
end;

{ N pty pairs and a DF1 slave on each slave side, as a legacy program
  opens them. }
function OpenLines(var L: tLines; N: LongInt; var Err: ShortString): Boolean;
var
  I: LongInt;
  Path: AnsiString;
begin
  Result := False;
  L.N := 0;
  if N > MaxLines then
    N := MaxLines;
  for I := 0 to N - 1 do
  begin
    L.Chn[I] := nil;
    if PtyCreate(L.Master[I], Path) <> 0 then
    begin
      Err := 'no pty';
      CloseLines(L);
      Exit;
    end;
    L.Slave[I] := Path;
    L.N := I + 1;
    L.Chn[I] := ChnCollection^.ChNewInit(ChnDF1.cName);
    L.Chn[I]^.ChSetParam(SlaveParams + Path);
    if L.Chn[I]^.ChResult = res_Ok then
      L.Chn[I]^.ChOpen;
    if L.Chn[I]^.ChResult = res_Ok then
      L.Chn[I]^.ChConnect;
    if L.Chn[I]^.ChResult <> res_Ok then
    begin
      Err := 'line ' + IntToStr(I) + ': ' + L.Chn[I]^.ChResultStr(L.Chn[I]^.ChResult);
      CloseLines(L);
      Exit;
    end;
  end;
  Result := True;
end;

var
  RecBuf: array[0..MaxLines - 1] of tRecRecord;

{ One round over the lines, as the legacy program does it: answer an Echo
  with ACK and the reply. }
procedure ServeRound(var L: tLines);
var
  I: LongInt;
  Len: Word;
  S: tSendRecord;
begin
  for I := 0 to L.N - 1 do
    if L.Chn[I]^.ChReceiveReady = CHS_ReceiveReady then
    begin
      L.Chn[I]^.ChReceive(Len);
      if (L.Chn[I]^.ChReceiveResult = res_Ok) and (RecBuf[I].MessType = tpDataMess) then
      begin
        S.MessType := tpAckNak;
        S.FlAck := True;
        L.Chn[I]^.ChSend(@S, 2);
        S := RecBuf[I];
        S.CF := RecBuf[I].CF or MskCF_Reply;
        L.Chn[I]^.ChSend(@S, Len);
      end;
    end;
end;

function RoundRobinEchoes(N, Count, PauseMs: LongInt; var L: tLatency;
  var Err: ShortString): Boolean;
var
  Lines: tLines;
  Peer: TPeer;
  I: LongInt;
begin
  FillChar(L, SizeOf(L), 0);
  Err := '';
  if not OpenLines(Lines, N, Err) then
    Exit(False);
  for I := 0 to Lines.N - 1 do
    Lines.Chn[I]^.ChReceiveBuffer(@RecBuf[I], SizeOf(RecBuf[I]));
  Peer := TPeer.Create(True);
  try
    Peer.Lines := @Lines;
    Peer.Count := Count;
    Peer.PauseMs := PauseMs;
    Peer.Start;
    repeat
      ServeRound(Lines);
    until Peer.Done;
    Peer.WaitFor;
    Err := Peer.Err;
    if Err = '' then
    begin
      L.Count := Count;
      L.Max := Quantile(Peer.Times, Count, 1);
      L.Median := Quantile(Peer.Times, Count, 0.5);
      L.P90 := Quantile(Peer.Times, Count, 0.9);
      L.P99 := Quantile(Peer.Times, Count, 0.99);
    end;
  finally
    Peer.Free;
    CloseLines(Lines);
  end;
  Result := Err = '';
end;

function IdleCost(N, Ms: LongInt; var C: tIdleCost; var Err: ShortString): Boolean;
var
  Lines: tLines;
  I: LongInt;
  R0, R1: tRUsage;
  T0, T1: Double;
  Rounds: Int64;

  function CpuSec(const R: tRUsage): Double;
  begin
    Result := R.UTime.tv_sec + R.UTime.tv_usec / 1e6 +
      R.STime.tv_sec + R.STime.tv_usec / 1e6;
  end;

  procedure Usage(var R: tRUsage);
  begin
    FillChar(R, SizeOf(R), 0);
    do_syscall(syscall_nr_getrusage, 0 { RUSAGE_SELF }, TSysParam(@R));
  end;

begin
  FillChar(C, SizeOf(C), 0);
  Err := '';
  if not OpenLines(Lines, N, Err) then
    Exit(False);
  try
    for I := 0 to Lines.N - 1 do
      Lines.Chn[I]^.ChReceiveBuffer(@RecBuf[I], SizeOf(RecBuf[I]));
    ServeRound(Lines);
    Rounds := 0;
    Usage(R0);
    T0 := NowSec;
    repeat
      ServeRound(Lines);
      Inc(Rounds);
      T1 := NowSec;
    until (T1 - T0) * 1000 >= Ms;
    Usage(R1);
    C.CpuPct := (CpuSec(R1) - CpuSec(R0)) / (T1 - T0) * 100;
    C.WakePerS := (R1.NvCsw - R0.NvCsw) / (T1 - T0);
    C.PollPerS := Rounds / (T1 - T0);
  finally
    CloseLines(Lines);
  end;
  Result := True;
end;

end.
