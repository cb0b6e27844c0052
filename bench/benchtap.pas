{ benchtap - the latency tools/chntap adds, and its throughput. Run with
  "make bench" (Unix only).

  Four pty pairs. chntap sits between the slaves of pairs 1 and 2; device
  A is played on master 1, device B on master 2: one byte goes master 1 ->
  chntap -> master 2, and back the other way. Baseline, in the same round
  so that both see the same load: this process itself forwards one byte
  from the slave of pair 3 to the slave of pair 4 at once (write master 3,
  poll slave 3, read, write slave 4, poll master 4), the two pty hops
  without a tap. The difference of the medians is what the tap adds. The
  rounds are spaced irregularly so the byte does not always arrive at the
  same point of the tap's poll loop. Last, 1 MiB each way at once with
  DF1 decoding. Figures compare runs on one machine; nothing is asserted. }
program benchtap;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix, Unix, Process, ChnPty,{$ENDIF}
  SysUtils, Classes;

{$IFDEF UNIX}
const
  Rounds = 300;

type
  tTimes = array of Double;

function NowUs: Double;
var
  T: TTimeVal;
begin
  fpgettimeofday(@T, nil);
  Result := Int64(T.tv_sec) * 1000000 + T.tv_usec;   { integer: a Single constant would round }
end;

{ Wait up to 1 s for Fd to be readable and read one byte. }
function ReadOne(Fd: cint): Boolean;
var
  P: array[0..0] of TPollFd;
  B: Byte;
begin
  P[0].fd := Fd;
  P[0].events := POLLIN;
  P[0].revents := 0;
  Result := (FpPoll(@P[0], 1, 1000) = 1) and (FpRead(Fd, B, 1) = 1);
end;

procedure Sort(var T: tTimes);
var
  I, J: Integer;
  X: Double;
begin
  for I := 1 to High(T) do
  begin
    X := T[I];
    J := I - 1;
    while (J >= 0) and (T[J] > X) do
    begin
      T[J + 1] := T[J];
      Dec(J);
    end;
    T[J + 1] := X;
  end;
end;

function Median(T: tTimes): Double;
begin
  Sort(T);
  Result := T[Length(T) div 2];
end;

procedure Report(const What: string; T: tTimes);
begin
  Sort(T);
  WriteLn(Format('  %-34s median %7.1f us   90%% %7.1f us   max %8.1f us',
    [What, T[Length(T) div 2], T[Length(T) * 9 div 10], T[High(T)]]));
end;

procedure Spacing(I: Integer);
begin
  { 0..3 ms, irregular }
  Sleep((I * 7) mod 4);
end;

var
  M1, M2, M3, M4, S3, S4: cint;
  Path1, Path2, Path3, Path4: AnsiString;
  Base, AB, BA: tTimes;
  I: Integer;
  T0: Double;
  B: Byte;
  Tap: TProcess;
  Sent1, Sent2, Got1, Got2, N: LongInt;
  Buf: array[0..65535] of Byte;
  Data: array of Byte;
  Deadline: QWord;
  Ok: Boolean;

function StartTap(const Extra: array of string): TProcess;
var
  A: string;
begin
  Result := TProcess.Create(nil);
  Result.Executable := ExtractFilePath(ParamStr(0)) + 'chntap';
  for A in Extra do
    Result.Parameters.Add(A);
  Result.Parameters.Add('NAM=COM DEV=' + Path1);
  Result.Parameters.Add('NAM=COM DEV=' + Path2);
  Result.Options := [poUsePipes, poStderrToOutPut];
  Result.Execute;
  Sleep(500);                          { both sides open }
end;

procedure StopTap(var P: TProcess);
var
  S: TStringList;
begin
  FpKill(P.ProcessID, SIGINT);
  P.WaitOnExit;
  if P.ExitCode <> 0 then
  begin
    S := TStringList.Create;
    S.LoadFromStream(P.Output);
    WriteLn('  chntap exit code ', P.ExitCode, ': ', S.Text);
    S.Free;
  end;
  FreeAndNil(P);
end;

begin
  WriteLn('benchtap: latency tools/chntap adds between two ptys (', Rounds, ' one-byte rounds)');
  if (PtyCreate(M1, Path1) <> 0) or (PtyCreate(M2, Path2) <> 0) or
     (PtyCreate(M3, Path3) <> 0) or (PtyCreate(M4, Path4) <> 0) then
  begin
    WriteLn('  no pseudo terminals here: nothing measured');
    Halt(0);
  end;
  FpFcntl(M1, F_SETFD, 1);             { FD_CLOEXEC: chntap must not hold them }
  FpFcntl(M2, F_SETFD, 1);
  SetLength(Base, Rounds);
  SetLength(AB, Rounds);
  SetLength(BA, Rounds);
  S3 := FpOpen(Path3, O_RDWR or O_NOCTTY);
  S4 := FpOpen(Path4, O_RDWR or O_NOCTTY);
  B := $55;
  Tap := StartTap(['--raw', '--quiet']);
  for I := 0 to Rounds - 1 do
  begin
    { baseline: the two hops, forwarded by this process without delay }
    Spacing(I);
    T0 := NowUs;
    FpWrite(M3, B, 1);
    Ok := ReadOne(S3);
    FpWrite(S4, B, 1);
    Ok := Ok and ReadOne(M4);
    Base[I] := NowUs - T0;
    if not Ok then
      WriteLn('  baseline: a byte was lost');
    Spacing(I + 1);
    T0 := NowUs;
    FpWrite(M1, B, 1);
    if not ReadOne(M2) then
      WriteLn('  A>B: a byte did not arrive');
    AB[I] := NowUs - T0;
    Spacing(I + 2);
    T0 := NowUs;
    FpWrite(M2, B, 1);
    if not ReadOne(M1) then
      WriteLn('  B>A: a byte did not arrive');
    BA[I] := NowUs - T0;
  end;
  FpClose(S3);
  FpClose(S4);
  Report('two pty hops, no tap', Base);
  StopTap(Tap);
  Report('A>B through chntap (IDL=1)', AB);
  Report('B>A through chntap (IDL=1)', BA);
  WriteLn(Format('  added by chntap (median - baseline): A>B %.1f us, B>A %.1f us; ratio %.1fx',
    [Median(AB) - Median(Base), Median(BA) - Median(Base), Median(AB) / Median(Base)]));

  { throughput: 1 MiB each way at once, decoded as DF1 }
  SetLength(Data, 1024 * 1024);
  for I := 0 to High(Data) do
    Data[I] := (I * 7 + I shr 9) and $FF;
  Tap := StartTap(['--df1', '--quiet']);
  Sent1 := 0;
  Sent2 := 0;
  Got1 := 0;
  Got2 := 0;
  T0 := NowUs;
  Deadline := GetTickCount64 + 60000;
  while ((Got1 < Length(Data)) or (Got2 < Length(Data))) and (GetTickCount64 < Deadline) do
  begin
    if Sent1 < Length(Data) then
    begin
      N := FpWrite(M1, Data[Sent1], Length(Data) - Sent1);
      if N > 0 then
        Inc(Sent1, N);
    end;
    if Sent2 < Length(Data) then
    begin
      N := FpWrite(M2, Data[Sent2], Length(Data) - Sent2);
      if N > 0 then
        Inc(Sent2, N);
    end;
    N := FpRead(M2, Buf, SizeOf(Buf));
    if N > 0 then
      Inc(Got2, N);
    N := FpRead(M1, Buf, SizeOf(Buf));
    if N > 0 then
      Inc(Got1, N);
  end;
  T0 := NowUs - T0;
  StopTap(Tap);
  WriteLn(Format('  1 MiB each way at once, --df1 decoding: A>B %d bytes, B>A %d bytes in %.0f ms (%.1f MB/s each way)',
    [Got2, Got1, T0 / 1000, Length(Data) / T0]));
  FpClose(M1);
  FpClose(M2);
  FpClose(M3);
  FpClose(M4);
end.
{$ELSE}
begin
  WriteLn('benchtap: Unix only (pseudo terminals)');
end.
{$ENDIF}
