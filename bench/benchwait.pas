{ benchwait - many lines in one program: reply time against the number of
  channels, idle CPU, the single-line DF1 echo against a plain read/write
  ping-pong, and the system calls of one DF1 exchange (Linux; "make bench",
  docs/ChnCom.md "Performance"). One table per run:

  1. round robin: a legacy program polls N = 1, 8, 32, 128 DF1 full-duplex
     slaves on ptys (default parameters, IDL=1); a peer thread sends Echo
     to a random line, 0..2 ms apart, and times each reply (unit
     ChnWaitBench): median, p90, p99, max;
  2. idle: the same program with nobody sending, 10 s each for N = 1 and
     128: CPU in % of one core and sleeps a second, next to the floor of
     any loop that sleeps 1 ms at a time (poll(2) with no descriptor);
  3. echo: one DF1 Echo round trip between two library processes (master
     here on DRV=PTY, the legacy slave program in a child) against a plain
     Pascal ping-pong of the same chunks (17 bytes; 2 + 16; 2) over the
     same kind of pty pair, in the same run: medians and their ratio;
  4. system calls per exchange of (3), both processes, counted with strace
     (when installed) as the difference of two runs of different length.

    benchwait            the full run (about a minute)
    benchwait quick      shorter (fewer echoes, 2 s idle)
  Internal roles: --df1slave PATH CPU, --plainslave PATH CPU (the
  children), --libecho N, --plainecho N (what strace counts). The echo's
  two ends run pinned to CPUs (sched_setaffinity), once on two CPUs and
  once on one, since where the scheduler puts them changes a pty round
  trip more than anything measured here. }
program benchwait;

{$MODE OBJFPC}{$H+}

uses
  cthreads, Classes, SysUtils, BaseUnix, Unix, Linux, Syscall, TermIO, Process, ChnTypes, ChnVirt,
  ChnCom, ChnDF1, ChnPty, ChnWaitBench;

const
  MasterParams = 'NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=ON NAM=COM DRV=PTY';
  SlaveParams  = 'NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=COM BD=19200 DEV=';
  CmdLen = 17;          { the Echo command with 4 data bytes, CRC }
  AckLen = 2;           { DLE ACK }
  ReplyLen = 16;        { the Echo reply }

var
  Quick: Boolean = False;

function Fmt(X: Double): string;
begin
  Result := Format('%7.3f', [X]);
end;

{ ------------------------------------------------------------ children }

{ Run this process on CPU N only (of two or more): the echo's two ends
  are pinned to different CPUs for both kinds of pair, so the scheduler's
  choice of placing them does not decide the comparison. }
procedure PinTo(N: LongInt);
var
  Mask: QWord;
begin
  if N < 0 then
    Mask := not QWord(0)          { every CPU again }
  else
    Mask := QWord(1) shl N;
  do_syscall(syscall_nr_sched_setaffinity, 0, SizeOf(Mask), TSysParam(@Mask));
end;


{ The legacy slave on one line, until the line hangs up. }
procedure Df1Slave(const Path: string; Cpu: LongInt);
var
  Chn: pChnVirt;
  R, S: tSendRecord;
  Len: Word;
begin
  PinTo(Cpu);
  Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  Chn^.ChSetParam(SlaveParams + Path);
  if Chn^.ChResult = res_Ok then
    Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then
  begin
    WriteLn('benchwait --df1slave: ', Chn^.ChResultStr(Chn^.ChResult));
    Halt(1);
  end;
  Chn^.ChReceiveBuffer(@R, SizeOf(R));
  Chn^.ChConnect;
  repeat
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Chn^.ChReceive(Len);
      if (Chn^.ChReceiveResult = res_Ok) and (R.MessType = tpDataMess) then
      begin
        S.MessType := tpAckNak;
        S.FlAck := True;
        Chn^.ChSend(@S, 2);
        S := R;
        S.CF := R.CF or MskCF_Reply;
        Chn^.ChSend(@S, Len);
      end;
    end;
  until Chn^.ChResult <> res_Ok;      { the master closed: line lost }
  Dispose(Chn, Done);
end;

function ReadAll(Fd: cint; var Buf; Len: LongInt): Boolean;
var
  Got, N: LongInt;
begin
  Got := 0;
  while Got < Len do
  begin
    N := FpRead(Fd, PByte(@Buf)[Got], Len - Got);
    if N <= 0 then
      Exit(False);
    Inc(Got, N);
  end;
  Result := True;
end;

{ The plain peer: blocking read of the command, the same two writes as the
  DF1 slave (ACK, reply), read of the ACK; until the line hangs up. }
procedure PlainSlave(const Path: string; Cpu: LongInt);
var
  Fd: cint;
  T: Termios;
  Buf: array[0..63] of Byte;
begin
  PinTo(Cpu);
  Fd := FpOpen(Path, O_RDWR or O_NOCTTY);
  if Fd < 0 then
    Halt(1);
  TCGetAttr(Fd, T);
  CFMakeRaw(T);
  TCSetAttr(Fd, TCSANOW, T);
  FillChar(Buf, SizeOf(Buf), $55);
  FpWrite(Fd, Buf, 1);               { ready }
  while ReadAll(Fd, Buf, CmdLen) do
  begin
    FpWrite(Fd, Buf, AckLen);
    FpWrite(Fd, Buf, ReplyLen);
    if not ReadAll(Fd, Buf, AckLen) then
      Break;
  end;
  FpClose(Fd);
end;

var
  ChildCpu: LongInt = 1;    { where StartChild's children run }

function StartChild(const Role, Path: string): TProcess;
begin
  Result := TProcess.Create(nil);
  Result.Executable := ParamStr(0);
  Result.Parameters.Add(Role);
  Result.Parameters.Add(Path);
  Result.Parameters.Add(IntToStr(ChildCpu));
  Result.Options := [];
  Result.Execute;
end;

{ ---------------------------------------------------------- echo timing }

{ Poll Chn until a message waits; False after about 2 s (2000 polls
  that each waited IDL=1 ms, or more that did not). Counting polls keeps
  clock calls - system calls here - out of what is measured. }
function WaitMsg(Chn: pChnVirt): Boolean;
var
  Polls: LongInt;
  T0: QWord;
begin
  Polls := 0;
  T0 := 0;
  repeat
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
      Exit(True);
    Inc(Polls);
    if Polls = 2000 then
      T0 := GetTickCount64
    else if (Polls > 2000) and (Polls mod 1000 = 0) and (GetTickCount64 - T0 > 2000) then
      Break;
  until False;
  Result := False;
end;

type
  { one end of each kind of pair, kept open across the interleaved blocks }
  tLibEnd = record
    Chn  : pChnVirt;
    Child: TProcess;
    S, R : tSendRecord;
  end;
  tPlainEnd = record
    Fd   : cint;
    Child: TProcess;
    Buf  : array[0..63] of Byte;
  end;

{ One library round trip: Echo out, ACK and reply in, ACK out. }
function LibRound(var L: tLibEnd; out Ms: Double): Boolean;
var
  Len: Word;
  T0: Double;
begin
  Inc(L.S.Tns);
  T0 := NowSec;
  L.Chn^.ChSend(@L.S, 12);
  Result := WaitMsg(L.Chn);              { ACK }
  if Result then
  begin
    L.Chn^.ChReceive(Len);
    Result := (L.R.MessType = tpAckNak) and WaitMsg(L.Chn);   { reply }
  end;
  if Result then
  begin
    L.Chn^.ChReceive(Len);
    Ms := (NowSec - T0) * 1000;
    Result := (L.R.MessType = tpDataMess) and (L.R.Tns = L.S.Tns);
    L.R.MessType := tpAckNak;
    L.R.FlAck := True;
    L.Chn^.ChSend(@L.R, 2);
  end;
end;

{ The library master here on DRV=PTY, the legacy slave in a child. }
function LibStart(var L: tLibEnd): Boolean;
var
  Tries: LongInt;
  Ms: Double;
begin
  Result := False;
  L.Child := nil;
  L.Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  L.Chn^.ChSetParam(MasterParams);
  L.Chn^.ChOpen;
  if L.Chn^.ChResult <> res_Ok then
  begin
    WriteLn('benchwait: master: ', L.Chn^.ChResultStr(L.Chn^.ChResult));
    Exit;
  end;
  L.Chn^.ChReceiveBuffer(@L.R, SizeOf(L.R));
  L.Chn^.ChConnect;
  L.Child := StartChild('--df1slave', PtyLastSlave);
  FillChar(L.S, SizeOf(L.S), 0);
  L.S.MessType := tpDataMess;
  L.S.CF := CF_Echo;
  Move(PChar('Ahoj')^, L.S.Data, 4);
  { until the child has the line open, sends go nowhere: repeat the first }
  Tries := 0;
  repeat
    Result := LibRound(L, Ms);
    Inc(Tries);
  until Result or (Tries > 5);
end;

procedure LibStop(var L: tLibEnd);
begin
  if L.Chn <> nil then
    Dispose(L.Chn, Done);                { hangs the child's line up }
  L.Chn := nil;
  if L.Child <> nil then
  begin
    L.Child.WaitOnExit;
    L.Child.Free;
  end;
  L.Child := nil;
end;

{ The same chunks with plain read/write on a pty pair. }
function PlainRound(var P: tPlainEnd; out Ms: Double): Boolean;
var
  T0: Double;
begin
  T0 := NowSec;
  FpWrite(P.Fd, P.Buf, CmdLen);
  Result := ReadAll(P.Fd, P.Buf, AckLen + ReplyLen);
  Ms := (NowSec - T0) * 1000;
  FpWrite(P.Fd, P.Buf, AckLen);
end;

function PlainStart(var P: tPlainEnd): Boolean;
var
  Path: AnsiString;
begin
  P.Child := nil;
  if PtyCreate(P.Fd, Path) <> 0 then
    Exit(False);
  FpFcntl(P.Fd, F_SETFL, FpFcntl(P.Fd, F_GETFL) and not O_NONBLOCK);   { blocking reads }
  P.Child := StartChild('--plainslave', Path);
  FillChar(P.Buf, SizeOf(P.Buf), $10);
  Result := ReadAll(P.Fd, P.Buf, 1);     { the child is ready }
end;

procedure PlainStop(var P: tPlainEnd);
begin
  if P.Fd >= 0 then
    FpClose(P.Fd);
  P.Fd := -1;
  if P.Child <> nil then
  begin
    P.Child.WaitOnExit;
    P.Child.Free;
  end;
  P.Child := nil;
end;

function LibEcho(Count: LongInt): Boolean;
var
  L: tLibEnd;
  I: LongInt;
  Ms: Double;
begin
  Result := LibStart(L);
  for I := 1 to Count do
    if Result then
      Result := LibRound(L, Ms);
  LibStop(L);
end;

function PlainEcho(Count: LongInt): Boolean;
var
  P: tPlainEnd;
  I: LongInt;
  Ms: Double;
begin
  Result := PlainStart(P);
  for I := 1 to Count do
    if Result then
      Result := PlainRound(P, Ms);
  PlainStop(P);
end;

{ ----------------------------------------------------------- the table }

procedure RoundRobin;
const
  Ns: array[0..3] of LongInt = (1, 8, 32, 128);
var
  I, Count: LongInt;
  L: tLatency;
  Err: ShortString;
  One: Double;
begin
  if Quick then
    Count := 300
  else
    Count := 2000;
  WriteLn;
  WriteLn(Format('round robin: Echo to a random line, %d replies each, ms', [Count]));
  WriteLn('| channels | median | p90 | p99 | max | median / 1-channel median |');
  WriteLn('|---|---|---|---|---|---|');
  One := 0;
  for I := 0 to High(Ns) do
    if RoundRobinEchoes(Ns[I], Count, 2, L, Err) then
    begin
      if I = 0 then
        One := L.Median;
      WriteLn(Format('| %d | %s | %s | %s | %s | %.2f |', [Ns[I], Fmt(L.Median),
        Fmt(L.P90), Fmt(L.P99), Fmt(L.Max), L.Median / One]));
    end
    else
      WriteLn(Format('| %d | failed: %s |', [Ns[I], Err]));
end;

procedure Idle;
const
  Ns: array[0..1] of LongInt = (1, 128);
var
  I, Ms, Sleeps: LongInt;
  C: tIdleCost;
  Err: ShortString;
  C0, T0, T1: Double;
begin
  if Quick then
    Ms := 2000
  else
    Ms := 10000;
  WriteLn;
  WriteLn(Format('idle: a legacy program polling N idle DF1 lines, default IDL=1, %d s', [Ms div 1000]));
  WriteLn('| channels | CPU, % of one core | sleeps a second | rounds over all lines a second |');
  WriteLn('|---|---|---|---|');
  for I := 0 to High(Ns) do
    if IdleCost(Ns[I], Ms, C, Err) then
      WriteLn(Format('| %d | %.2f | %.0f | %.0f |', [Ns[I], C.CpuPct, C.WakePerS, C.PollPerS]))
    else
      WriteLn(Format('| %d | failed: %s |', [Ns[I], Err]));
  { the floor: nothing but 1 ms sleeps, as any poll with IDL=1 must do }
  Sleeps := 0;
  C0 := CpuSec;
  T0 := NowSec;
  repeat
    FpPoll(nil, 0, 1);
    Inc(Sleeps);
    T1 := NowSec;
  until (T1 - T0) * 1000 >= Ms div 2;
  WriteLn(Format('| floor: poll(2) of nothing for 1 ms in a loop | %.2f | %.0f | |',
    [(CpuSec - C0) / (T1 - T0) * 100, Sleeps / (T1 - T0)]));
end;

{ Both pairs open at once, measured in alternating blocks, so a load that
  comes and goes on the machine falls on both alike. }
procedure EchoRatio;
const
  Block = 100;
  Placement: array[0..1] of string = ('the two ends on different CPUs',
    'both ends on one CPU');
var
  Count, B, I, Pl: LongInt;
  TL, TP: array of Double;
  ML, MP: Double;
  L: tLibEnd;
  P: tPlainEnd;
  Ok: Boolean;
begin
  if Quick then
    Count := 1000
  else
    Count := 5000;
  SetLength(TL, Count);
  SetLength(TP, Count);
  WriteLn;
  WriteLn(Format('echo: one line, two processes, %d round trips each in alternating blocks of %d, ms',
    [Count, Block]));
  WriteLn('| placement | round trip | median | p90 | p99 |');
  WriteLn('|---|---|---|---|---|');
  for Pl := 0 to 1 do
  begin
    PinTo(0);
    ChildCpu := 1 - Pl;
    Ok := PlainStart(P) and LibStart(L);
    B := 0;
    while Ok and (B < Count) do
    begin
      for I := B to B + Block - 1 do
        if Ok then
          Ok := PlainRound(P, TP[I]);
      for I := B to B + Block - 1 do
        if Ok then
          Ok := LibRound(L, TL[I]);
      Inc(B, Block);
    end;
    LibStop(L);
    PlainStop(P);
    if not Ok then
    begin
      WriteLn('| ', Placement[Pl], ' | failed: no answer from a child | | | |');
      Continue;
    end;
    MP := Quantile(TP, Count, 0.5);
    ML := Quantile(TL, Count, 0.5);
    WriteLn(Format('| %s | plain read/write, 17 -> 2 + 16 -> 2 bytes | %s | %s | %s |',
      [Placement[Pl], Fmt(MP), Fmt(Quantile(TP, Count, 0.9)), Fmt(Quantile(TP, Count, 0.99))]));
    WriteLn(Format('| %s | DF1 Echo through the library, both ends | %s | %s | %s |',
      [Placement[Pl], Fmt(ML), Fmt(Quantile(TL, Count, 0.9)), Fmt(Quantile(TL, Count, 0.99))]));
    WriteLn(Format('| %s | **ratio of the medians** | **%.2f** | | |', [Placement[Pl], ML / MP]));
  end;
  PinTo(-1);
end;

{ ------------------------------------------------------ syscall counting }

type
  tCounts = record
    Names: array of string;
    Counts: array of LongInt;
  end;

procedure AddCount(var C: tCounts; const Name: string; N: LongInt);
var
  I: LongInt;
begin
  for I := 0 to High(C.Names) do
    if C.Names[I] = Name then
    begin
      Inc(C.Counts[I], N);
      Exit;
    end;
  SetLength(C.Names, Length(C.Names) + 1);
  SetLength(C.Counts, Length(C.Counts) + 1);
  C.Names[High(C.Names)] := Name;
  C.Counts[High(C.Counts)] := N;
end;

function CountOf(const C: tCounts; const Name: string): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(C.Names) do
    if C.Names[I] = Name then
      Exit(C.Counts[I]);
  Result := 0;
end;

{ strace -ff one role run; Master/Slave: syscall counts of the two
  processes (the slave's file is the one that ran --df1slave/--plainslave). }
function Trace(const Role: string; N: LongInt; var Master, Slave: tCounts): Boolean;
var
  Dir, Line, Name, Out: string;
  SR: TSearchRec;
  Lines: TStringList;
  IsSlave: Boolean;
  I, P: LongInt;
begin
  Master.Names := nil; Master.Counts := nil;
  Slave.Names := nil; Slave.Counts := nil;
  Dir := GetTempDir(False) + 'benchwait-strace-' + IntToStr(FpGetPid);
  ForceDirectories(Dir);
  Result := RunCommand('strace', ['-ff', '-o', Dir + '/t', ParamStr(0), Role, IntToStr(N)], Out, [], swoNone);
  Lines := TStringList.Create;
  try
    if FindFirst(Dir + '/t.*', faAnyFile, SR) = 0 then
    repeat
      Lines.LoadFromFile(Dir + '/' + SR.Name);
      IsSlave := (Lines.Count > 0) and (Pos('slave', Lines[0]) > 0);
      for I := 0 to Lines.Count - 1 do
      begin
        Line := Lines[I];
        P := Pos('(', Line);
        if (P <= 1) or (Line[1] in ['<', '-', '+', ' ']) then
          Continue;                      { resumed calls, signals, exit }
        Name := Copy(Line, 1, P - 1);
        if IsSlave then
          AddCount(Slave, Name, 1)
        else
          AddCount(Master, Name, 1);
      end;
      DeleteFile(Dir + '/' + SR.Name);
    until FindNext(SR) <> 0;
    FindClose(SR);
  finally
    Lines.Free;
  end;
  RemoveDir(Dir);
end;

procedure Syscalls;
const
  N1 = 100;
  N2 = 600;
var
  A1, A2, B1, B2: array[0..1] of tCounts;
  Roles: array[0..1] of string = ('--plainecho', '--libecho');
  Titles: array[0..1] of string = ('plain read/write', 'library');
  R, I: LongInt;
  Names: TStringList;
  Row: string;
  D: Double;
  Out: string;
begin
  WriteLn;
  if not RunCommand('strace', ['-V'], Out, [], swoNone) then
  begin
    WriteLn('system calls: strace is not installed (apt-get install strace); not counted');
    Exit;
  end;
  for R := 0 to 1 do
  begin
    Trace(Roles[R], N1, A1[R], B1[R]);
    Trace(Roles[R], N2, A2[R], B2[R]);
  end;
  WriteLn(Format('system calls per Echo exchange (strace -ff, runs of %d and %d exchanges, difference / %d)',
    [N2, N1, N2 - N1]));
  WriteLn('| process | call | plain | library |');
  WriteLn('|---|---|---|---|');
  Names := TStringList.Create;
  try
    Names.Sorted := True;
    Names.Duplicates := dupIgnore;
    for R := 0 to 1 do
    begin
      for I := 0 to High(A2[R].Names) do
        Names.Add('master ' + A2[R].Names[I]);
      for I := 0 to High(B2[R].Names) do
        Names.Add('slave ' + B2[R].Names[I]);
    end;
    for I := 0 to Names.Count - 1 do
    begin
      Row := '';
      for R := 0 to 1 do
      begin
        if Copy(Names[I], 1, 7) = 'master ' then
          D := (CountOf(A2[R], Copy(Names[I], 8, 99)) - CountOf(A1[R], Copy(Names[I], 8, 99))) / (N2 - N1)
        else
          D := (CountOf(B2[R], Copy(Names[I], 7, 99)) - CountOf(B1[R], Copy(Names[I], 7, 99))) / (N2 - N1);
        Row := Row + Format(' %.2f |', [D]);
      end;
      if Pos(' 0.00 | 0.00 |', ' ' + Trim(Row) + ' ') <> 0 then
        Continue;                        { set-up only }
      if Pos('clock_gettime', Names[I]) > 0 then
        Continue;                        { the benchmark's own clock, see below }
      WriteLn('| ', StringReplace(Names[I], ' ', ' | ', []), ' |', Row);
    end;
  finally
    Names.Free;
  end;
  WriteLn('(not shown: clock_gettime, the benchmark''s own clock around each round trip, alike in both)');
end;

var
  N: LongInt;
begin
  if (ParamCount = 3) and (ParamStr(1) = '--df1slave') then
    Df1Slave(ParamStr(2), StrToIntDef(ParamStr(3), 1))
  else if (ParamCount = 3) and (ParamStr(1) = '--plainslave') then
    PlainSlave(ParamStr(2), StrToIntDef(ParamStr(3), 1))
  else if (ParamCount = 2) and (ParamStr(1) = '--libecho') then
  begin
    N := StrToIntDef(ParamStr(2), 100);
    if not LibEcho(N) then
      Halt(1);
  end
  else if (ParamCount = 2) and (ParamStr(1) = '--plainecho') then
  begin
    N := StrToIntDef(ParamStr(2), 100);
    if not PlainEcho(N) then
      Halt(1);
  end
  else
  begin
    Quick := (ParamCount >= 1) and (ParamStr(1) = 'quick');
    WriteLn('benchwait: many lines in one program (Linux ', ParamStr(0), ')');
    RoundRobin;
    Idle;
    EchoRatio;
    Syscalls;
  end;
end.
