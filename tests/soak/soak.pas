{ soak - the whole stack on a noisy line, for a long time (make soak).

  Each scenario runs over a real pty pair between two processes: this
  program is the master, with NAM=NOISE between its protocol layer and
  NAM=COM; the peer is tools/df1sim (DF1 full duplex) or this program
  started again with --serve=... (DF1 half duplex with three stations on one
  line, FT 1.2 secondary, FT 1.2 balanced station B, ICS slave, two IEC
  101 slaves on one line), which creates the pty itself. The FT 1.2 link procedures (unbalanced and
  balanced) also run over faults of whole frames (FrameFaults: a stall
  longer than the timeout, drops with stalls, reordering; NAM=NOISE LOS=
  STL= STM= ROR=); the balanced scenario sends numbered user data both
  ways and fails when a message was confirmed to its sender but not
  delivered, or delivered twice beyond what link resets explain.
  The IEC 101 scenarios poll two slaves on one line with ChnIec101Master;
  half way one of them turns hostile (answers status and reset but no
  poll, keeps ACD set, or streams events) and the other must keep at
  least half the class 2 polls it got before.

    soak [--seconds=N | --count=N] [--seed=N] [--only=TEXT] [--df1sim=PATH]

  --seconds  per scenario (default 10); --count  messages per scenario
  instead; --seed  the first NOISE seed (scenario k uses seed + k; default
  from the clock); --only  runs the scenarios whose name contains TEXT.

  Every scenario prints one line, 'ok    soak NAME: ...' or 'FAIL  soak
  NAME: ... (why)', with: messages (application messages completed),
  retries (link repetitions and application re-sends), timeouts, losses,
  duplicates, bad (a reply with wrong data or status accepted, or - DF1 -
  a command the peer refused as malformed: a checksum that let damage
  through), RSS and open descriptors of both processes at
  start (after a warm-up) and end, and the seed. A scenario fails on a
  loss, a duplicate (on FT 1.2: beyond one per message sent again after
  its transaction failed and the link was reset), bad data on a CRC line,
  RSS growth above 1 MiB, a descriptor count that changed, or no progress
  (fewer than 3 messages; --seconds is a minimum, a scenario goes on
  until 3 messages went through, for at most 60 s). Exit code 0 when
  every scenario passed. See docs/reliability.md. }
program soak;

{$MODE OBJFPC}{$H+}

uses
  BaseUnix, SysUtils, Classes, Process,
  ChnTypes, ChnVirt, ChnCom, ChnLoop, ChnNoise, ChnPty, uString,
  ChnDF1, ChnDF1Link, ChnPccc, ChnSlc, ChnFT1_2, ChnFT12Link, ChnFT12Primary, ChnFT12Station, ChnFT12Balanced, ChnICS, ChnWait, Math,
  ChnIec101Asdu, ChnIec101Master, TestSupport, LoopHub, Iec101Sim;

const
  DF1Timeout = 300;     { ms; the line is a pty, the machine is shared }
  FT12Timeout = 300;
  ICSTimeout = 300;
  AppTries = 100;       { re-sends of one message before it counts as lost }
  WarmUp = 50;          { messages before RSS/descriptors are taken }
  CheckEvery = 64;      { messages between checks of the peer's counters }
  HDStations = 3;
  MaxRssGrowthKb = 1024;
  { --seconds is a minimum: a scenario also goes on until MinMessages
    messages went through, which a loaded machine (make test runs five
    groups at once on two cores) can take longer for; "no progress" is
    fewer than that within ProgressCapMs }
  MinMessages = 3;
  ProgressCapMs = 60000;

type
  TNoise = record
    Name, Params: string;
  end;

  TStats = record
    Messages, Retries, Timeouts, Losses, Dups, Bad, Stale: Int64;
    DupsAfterReset: Int64;  { of Dups, those a link reset explains (FT 1.2) }
    RssStart, RssEnd, FdStart, FdEnd: LongInt;        { master }
    PRssStart, PRssEnd, PFdStart, PFdEnd: LongInt;    { peer }
    Note: string;
    Faults: string;         { what NAM=NOISE did to whole frames }
  end;

const
  Noises: array[0..3] of TNoise = (
    (Name: 'clean';    Params: 'BER=0'),
    (Name: 'ber1e-5';  Params: 'BER=1E-5'),
    (Name: 'ber1e-3';  Params: 'BER=1E-3'),
    (Name: 'drop1%';   Params: 'DRP=0.01'));
  { faults of whole frames for the FT 1.2 link procedures (late answers, docs/ChnFT1_2.md): a
    stall longer than the 300 ms timeout, drops with stalls, reordering }
  FrameFaults: array[0..2] of TNoise = (
    (Name: 'stall';     Params: 'STL=0.05 STM=450'),
    (Name: 'dropstall'; Params: 'LOS=0.06 STL=0.03 STM=450'),
    (Name: 'reorder';   Params: 'ROR=0.05 STM=450'));

var
  Parent: TPid;         { a peer ends when the master is gone }

function Orphaned: Boolean;
begin
  Result := FpGetPPid <> Parent;
end;

var
  Seconds, Count, Seed: LongInt;
  Only, Df1SimPath: string;
  Stop: Boolean = False;
  TurnHostile: Boolean = False;   { a peer's SIGUSR1 }

{ ------------------------------------------------------------ helpers }

procedure OnSignal(Sig: cint); cdecl;
begin
  if Sig = SIGUSR1 then
    TurnHostile := True
  else
    Stop := True;
end;

procedure CatchSignals;
var
  Act: SigActionRec;
begin
  FillChar(Act, SizeOf(Act), 0);
  Act.sa_handler := SigActionHandler(@OnSignal);
  FpSigAction(SIGINT, @Act, nil);
  FpSigAction(SIGTERM, @Act, nil);
  FpSigAction(SIGUSR1, @Act, nil);
end;

function RssKb(Pid: TPid): LongInt;
var
  F: TextFile;
  Line: string;
begin
  Result := -1;
  AssignFile(F, '/proc/' + IntToStr(Pid) + '/status');
  {$I-}Reset(F);{$I+}
  if IOResult <> 0 then
    Exit;
  while not Eof(F) do
  begin
    ReadLn(F, Line);
    if Copy(Line, 1, 6) = 'VmRSS:' then
      Result := StrToIntDef(Trim(StringReplace(Copy(Line, 7, 99), 'kB', '', [])), -1);
  end;
  CloseFile(F);
end;

{ the peer process and its standard output }
type
  TPeer = record
    Proc: TProcess;
    Out_: string;     { what it printed so far }
    Pty: string;
  end;

procedure PeerRead(var P: TPeer);
var
  Buf: array[0..1023] of Char;
  N: LongInt;
begin
  while P.Proc.Output.NumBytesAvailable > 0 do
  begin
    N := P.Proc.Output.Read(Buf, SizeOf(Buf));
    if N <= 0 then
      Break;
    P.Out_ := P.Out_ + Copy(Buf, 1, N);
  end;
end;

function PeerStart(var P: TPeer; const Exe: string; const Args: array of string;
  out Err: string): Boolean;
var
  I, At: LongInt;
  Deadline: QWord;
begin
  Err := '';
  P.Out_ := '';
  P.Pty := '';
  P.Proc := TProcess.Create(nil);
  P.Proc.Executable := Exe;
  for I := Low(Args) to High(Args) do
    P.Proc.Parameters.Add(Args[I]);
  P.Proc.Options := [poUsePipes, poStderrToOutPut];
  try
    P.Proc.Execute;
  except
    on E: Exception do
    begin
      Err := Exe + ': ' + E.Message;
      Exit(False);
    end;
  end;
  Deadline := ChMsTick + 5000;
  repeat
    PeerRead(P);
    At := Pos('PTY ', P.Out_);
    if (At > 0) and (Pos(#10, Copy(P.Out_, At, MaxInt)) > 0) then
    begin
      P.Pty := Trim(Copy(P.Out_, At + 4, Pos(#10, Copy(P.Out_, At, MaxInt)) - 5));
      Exit(True);
    end;
    Sleep(5);
  until (ChMsTick > Deadline) or not P.Proc.Running;
  Err := 'peer did not report its pty: ' + P.Out_;
  Result := False;
end;

{ SIGTERM, wait for the exit (and read what it printed last) }
procedure PeerStop(var P: TPeer);
var
  Deadline: QWord;
begin
  if P.Proc = nil then
    Exit;
  if P.Proc.Running then
    FpKill(P.Proc.ProcessID, SIGTERM);
  Deadline := ChMsTick + 5000;
  while P.Proc.Running and (ChMsTick < Deadline) do
  begin
    PeerRead(P);
    Sleep(5);
  end;
  if P.Proc.Running then
    P.Proc.Terminate(9);
  P.Proc.WaitOnExit;
  PeerRead(P);
  FreeAndNil(P.Proc);
end;

{ KEY=value from the peer's last STATS line; -1 if missing }
function PeerStat(const P: TPeer; const Key: string): Int64;
var
  At: LongInt;
  S: string;
begin
  Result := -1;
  At := Pos('STATS ', P.Out_);
  if At = 0 then
    Exit;
  S := Copy(P.Out_, At, MaxInt);
  At := Pos(' ' + Key + '=', S);
  if At = 0 then
    Exit;
  S := Copy(S, At + Length(Key) + 2, MaxInt);
  At := 1;
  while (At <= Length(S)) and (S[At] in ['0'..'9', '-']) do
    Inc(At);
  Result := StrToInt64Def(Copy(S, 1, At - 1), -1);
end;

function Done_(const St: TStats; Start: QWord): Boolean;
begin
  if Stop then
    Exit(True);
  if Count > 0 then
    Result := St.Messages >= Count
  else
    Result := (ChMsTick - Start >= QWord(Seconds) * 1000) and
      ((St.Messages >= MinMessages) or (ChMsTick - Start >= ProgressCapMs));
end;

procedure TakeStart(var St: TStats; Peer: TPid);
begin
  St.RssStart := RssKb(FpGetPid);
  St.FdStart := OpenFdCount(IntToStr(FpGetPid));
  St.PRssStart := RssKb(Peer);
  St.PFdStart := OpenFdCount(IntToStr(Peer));
end;

procedure TakeEnd(var St: TStats; Peer: TPid);
begin
  St.RssEnd := RssKb(FpGetPid);
  St.FdEnd := OpenFdCount(IntToStr(FpGetPid));
  St.PRssEnd := RssKb(Peer);
  St.PFdEnd := OpenFdCount(IntToStr(Peer));
end;

var
  Failed: LongInt = 0;
  Ran: LongInt = 0;

procedure Report(const Name: string; const St: TStats; ASeed: LongInt; Ms: QWord;
  BadAllowed: Boolean);
var
  Why, Line: string;
begin
  Why := St.Note;
  if St.Messages < MinMessages then
    Why := Why + ' no progress;';
  if St.Losses <> 0 then
    Why := Why + ' losses;';
  { a BCC line (an 8-bit sum) lets some damage through: a dropped $00 byte
    or two flips that cancel. A command damaged that way may run as
    another command (a second execution when the master repeats the real
    one) and a damaged reply may be taken. On such a line duplicates and
    bad data are reported, not failed, when the run shows that undetected
    damage happened (bad or stale replies); a CRC line fails on both. }
  if (St.Dups > St.DupsAfterReset) and not (BadAllowed and (St.Bad + St.Stale > 0)) then
    Why := Why + ' duplicates;';
  if (St.Bad <> 0) and not BadAllowed then
    Why := Why + ' bad data accepted;';
  if (St.RssEnd - St.RssStart > MaxRssGrowthKb) or (St.PRssEnd - St.PRssStart > MaxRssGrowthKb) then
    Why := Why + ' RSS grew;';
  if (St.FdEnd <> St.FdStart) or (St.PFdEnd <> St.PFdStart) then
    Why := Why + ' descriptors changed;';
  Line := Format('soak %s: %d messages, %d retries, %d timeouts, %d losses, %d duplicates, ' +
    '%d bad, %d stale; RSS %d->%d KiB, fds %d->%d; peer RSS %d->%d KiB, fds %d->%d; %.1f s, SEED=%d',
    [Name, St.Messages, St.Retries, St.Timeouts, St.Losses, St.Dups, St.Bad, St.Stale,
     St.RssStart, St.RssEnd, St.FdStart, St.FdEnd, St.PRssStart, St.PRssEnd,
     St.PFdStart, St.PFdEnd, Ms / 1000, ASeed]) + St.Faults;
  Inc(Ran);
  if BadAllowed and (St.Dups + St.Bad > 0) and (Why = '') then
    Line := Line + ' (BCC let damage through: reported, not failed)'
  else if (St.DupsAfterReset > 0) and (Why = '') then
    Line := Line + Format(' (%d after a link reset: reported, not failed)', [St.DupsAfterReset]);
  if Why = '' then
    WriteLn('ok    ', Line)
  else
  begin
    WriteLn('FAIL  ', Line, ' (', Trim(Why), ')');
    Inc(Failed);
  end;
  Flush(Output);
end;

{ The frame faults NAM=NOISE made on the line of Chn, for the report; a
  fault the scenario asks for that never happened although at least 10
  were due (chunks sent times its probability: by chance that is one run
  in 20,000) is a note - the scenario then proves nothing. A brief run
  (make test) may rightly see none. }
procedure NoteFrameFaults(var St: TStats; Chn: pChnVirt; const Noise: TNoise);

  function Missing(P: Double; Happened: QWord; Chunks: QWord): Boolean;
  begin
    Result := (P > 0) and (Happened = 0) and (Chunks * P >= 10);
  end;

var
  L: pChnVirt;
  N: pChnNoise;
begin
  L := Chn;
  while (L <> nil) and (L^.CH_NumName <> ChNumName(ChnNoise.cName)) do
    L := L^.CH_Low;
  if L = nil then
    Exit;
  N := pChnNoise(L);
  if (N^.CH_LosT = 0) and (N^.CH_StlT = 0) and (N^.CH_RorT = 0) then
    Exit;
  St.Faults := Format(' line: %d frames lost, %d stalls, %d reordered;',
    [N^.CH_ChunksLost, N^.CH_Stalls, N^.CH_Reordered]);
  if Missing(N^.CH_Los, N^.CH_ChunksLost, N^.CH_Chunk) or Missing(N^.CH_Stl, N^.CH_Stalls, N^.CH_Chunk) or
     Missing(N^.CH_Ror, N^.CH_Reordered, N^.CH_Chunk) then
    St.Note := St.Note + ' the line never made the fault asked for (' + Noise.Params + ');';
end;

{ ------------------------------------------------------------- DF1 master }

var
  LinkLines: LongInt;   { log lines of the current DF1Transact }
  LinkSends: LongInt;   { frames of the command sent (first + repeats) }
  LinkEnqs, LinkNoAck: LongInt;

var
  Verbose: Boolean = False;

procedure CountLink(const Line: AnsiString);
begin
  if Verbose then
    WriteLn(StdErr, FormatDateTime('nn:ss.zzz', Now), ' ', Line);
  Inc(LinkLines);
  if Copy(Line, 1, 3) = '-> ' then
  begin
    if Copy(Line, 4, 3) = 'ENQ' then
      Inc(LinkEnqs)
    else if (Copy(Line, 4, 3) <> 'ACK') and (Copy(Line, 4, 3) <> 'NAK') and
            (Copy(Line, 4, 4) <> 'poll') then
      Inc(LinkSends);
  end
  else if Copy(Line, 1, 5) = '-- no' then
    Inc(LinkNoAck);
end;

{ One command until it is answered: True and Rep/RepLen; False: lost. }
function DF1Do(Chn: pChnVirt; var Req: ChnDF1.tSendRecord; Len: Word;
  var Rep: ChnDF1.tRecRecord; var RepLen: Word; var St: TStats): Boolean;
var
  Tries: LongInt;
  R: tChResult;
begin
  for Tries := 1 to AppTries do
  begin
    LinkSends := 0;
    LinkEnqs := 0;
    LinkNoAck := 0;
    RepLen := 0;
    R := DF1Transact(Chn, Req, Len, Rep, RepLen, nil, nil, DF1Timeout, @CountLink);
    if LinkSends > 1 then
      Inc(St.Retries, LinkSends - 1);
    Inc(St.Timeouts, LinkNoAck);
    if R = res_Ok then
      Exit(True);
    if R = res_BadMessage then
      Inc(St.Stale)          { a reply to an earlier command: send again }
    else if R <> res_Timeout then
    begin
      St.Note := St.Note + ' ' + Chn^.ChResultStr(R) + ';';
      Exit(False);
    end;
    Inc(St.Retries);
    if Stop then
      Break;
  end;
  Result := False;
end;

procedure TypedReq(var Req: ChnDF1.tSendRecord; var Len: Word; Tns: Word; Elem: Byte;
  Write: Boolean; Value: Word);
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := ChnDF1.tpDataMess;
  Req.Tns := Tns;
  Req.Data[0] := 2;        { size: one word }
  Req.Data[1] := 7;        { N7 }
  Req.Data[2] := pft_Integer;
  Req.Data[3] := Elem;
  Req.Data[4] := 0;
  if Write then
  begin
    Req.CF := CF_ProtectWrite3Addr;
    Req.Data[5] := Lo(Value);
    Req.Data[6] := Hi(Value);
    Len := 8 + 7;
  end
  else
  begin
    Req.CF := CF_ProtectRead3Addr;
    Len := 8 + 5;
  end;
end;

{ Read diagnostic counters 5..7 (error replies, repeated commands,
  commands answered) of the station Chn talks to: N the commands it
  answered, Errs those it refused (an error status). Lost: the read got no
  answer. Bad: an answer with the wrong shape (damage the checksum let
  through), Refused: an answer with an error status; the read ran all the
  same. }
type
  TReadResult = (rrOk, rrLost, rrBad, rrRefused);

function ReadExecuted(Chn: pChnVirt; Tns: Word; var St: TStats; out N, Errs: Word): TReadResult;
var
  Req: ChnDF1.tSendRecord;
  Rep: ChnDF1.tRecRecord;
  RepLen: Word;
begin
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := ChnDF1.tpDataMess;
  Req.CF := CF_ReadDiagnCounts;
  Req.Tns := Tns;
  Req.Data[0] := 2 * dgErrReplies;
  Req.Data[1] := 0;
  Req.Data[2] := 2 * (dgCommands - dgErrReplies + 1);
  N := 0;
  Errs := 0;
  if not DF1Do(Chn, Req, 8 + 3, Rep, RepLen, St) then
    Exit(rrLost);
  Inc(St.Bad, Ord((RepLen <> 8 + Req.Data[2]) or (Rep.Sts <> 0)));
  if Rep.Sts <> 0 then
    Exit(rrRefused);
  if RepLen <> 8 + Req.Data[2] then
    Exit(rrBad);
  Errs := Rep.Data[0] or (Rep.Data[1] shl 8);
  N := Rep.Data[4] or (Rep.Data[5] shl 8);
  Result := rrOk;
end;

{ Writes of an increasing counter and reads back, to Stations stations
  (1..Stations) in turn; every CheckEvery messages each station's count of
  executed commands is compared with what was sent to it. }
procedure DF1Master(Chn: pChnVirt; Stations: LongInt; PeerPid: TPid; var St: TStats);
var
  Req: ChnDF1.tSendRecord;
  Rep: ChnDF1.tRecRecord;
  Len, RepLen, Tns, Got, Errs, Value: Word;
  Sent: array[1..HDStations] of Word;   { commands each station executed, mod 65536 }
  { error replies: each station's count at the last check, and those the
    master saw since (an answer with an error status) }
  Refused, SeenRefused: array[1..HDStations] of Word;
  Synced: array[1..HDStations] of Boolean;
  S: LongInt;
  Start: QWord;
  I: Int64;

  function Check(Stn: LongInt): Boolean;
  var
    T, Unseen: LongInt;
    R: TReadResult;
  begin
    Chn^.ChDestNode(Stn);
    for T := 1 to AppTries do
    begin
      Tns := Word(Tns + 1);      { wraps, as TNS does }
      R := ReadExecuted(Chn, Tns, St, Got, Errs);
      if R = rrLost then
        Exit(False);
      if R = rrOk then
        Break;
      if Synced[Stn] then
        Sent[Stn] := Word(Sent[Stn] + 1);   { it ran; its answer was damaged }
      if Synced[Stn] and (R = rrRefused) then
        SeenRefused[Stn] := Word(SeenRefused[Stn] + 1);
    end;
    if R <> rrOk then
      Exit(False);
    if not Synced[Stn] then
    begin
      Sent[Stn] := Got;             { what ran before this soak }
      Synced[Stn] := True;
    end
    else
    begin
      { The soak's commands are never refused: a refusal is a command
        damaged on the way in a way the checksum let through (on a BCC
        line a dropped $0F and a dropped byte further on can cancel). One
        the master never saw (its refusal was damaged or lost too) was
        answered all the same: it counts as sent, and as bad. An answer
        with an error status the master saw may also be a damaged answer
        to a command that ran: those are bad already. }
      Unseen := SmallInt(Word(Errs - Refused[Stn] - SeenRefused[Stn]));
      if Unseen > 0 then
      begin
        Sent[Stn] := Word(Sent[Stn] + Unseen);
        Inc(St.Bad, Unseen);
      end;
    end;
    if Got <> Sent[Stn] then
    begin
      Inc(St.Dups, SmallInt(Word(Got - Sent[Stn])));
      if SmallInt(Word(Got - Sent[Stn])) < 0 then
        Inc(St.Losses);
      Sent[Stn] := Got;
    end;
    Sent[Stn] := Word(Sent[Stn] + 1);   { the read itself }
    Refused[Stn] := Errs;
    SeenRefused[Stn] := 0;
    Result := True;
  end;

begin
  Tns := Word(Random(65536));
  for S := 1 to Stations do
  begin
    Synced[S] := False;
    Sent[S] := 0;
    Refused[S] := 0;
    SeenRefused[S] := 0;
  end;
  for S := 1 to Stations do
    if not Check(S) then
    begin
      Inc(St.Losses);
      Exit;
    end;
  Start := ChMsTick;
  I := 0;
  while not Done_(St, Start) do
  begin
    Inc(I);
    S := 1 + (I div 2) mod Stations;
    Chn^.ChDestNode(S);
    Value := Word(I div 2);
    Tns := Word(Tns + 1);      { wraps, as TNS does }
    TypedReq(Req, Len, Tns, (I div 2) mod 50, not Odd(I), Value);
    if not DF1Do(Chn, Req, Len, Rep, RepLen, St) then
    begin
      Inc(St.Losses);
      Break;
    end;
    Sent[S] := Word(Sent[S] + 1);
    Inc(St.Messages);
    if Rep.Sts <> 0 then
    begin
      Inc(St.Bad);
      SeenRefused[S] := Word(SeenRefused[S] + 1);
    end
    else if Odd(I) then
    begin
      if (RepLen <> 8 + 2) or (Rep.Data[0] or (Rep.Data[1] shl 8) <> Value) then
        Inc(St.Bad);
    end
    else if RepLen <> 8 then
      Inc(St.Bad);
    if (St.Messages = 1) or (St.Messages = WarmUp) then
      TakeStart(St, PeerPid);
    if I mod CheckEvery = 0 then
      for S := 1 to Stations do
        if not Check(S) then
        begin
          Inc(St.Losses);
          Exit;
        end;
  end;
  for S := 1 to Stations do
    if not Check(S) then
      Inc(St.Losses);
end;

{ A scenario's line below its protocol layer: the noise, then the pty to
  the peer. }
function NoisyLine(const Noise: TNoise; ASeed: LongInt; const Pty: string): string;
begin
  Result := Format('NAM=NOISE %s SEED=%d NAM=COM DEV=%s BD=38400', [Noise.Params, ASeed, Pty]);
end;

{ After PeerStart: False, with the scenario reported as failed for the
  reason, when the peer did not come up. }
function PeerUp(var Peer: TPeer; const Err, Name: string; var St: TStats; ASeed: LongInt): Boolean;
begin
  Result := Peer.Pty <> '';
  if not Result then
  begin
    St.Note := Err + ';';
    PeerStop(Peer);
    Report(Name, St, ASeed, 0, False);
  end;
end;

{ The start every scenario with a peer of this program shares: St
  cleared, the peer started with --serve=Serve, the master's stack
  (Layer, its Params, then the noisy line to the peer's pty) opened. False
  when the peer did not come up (the scenario is reported); Chn = nil with
  St.Note saying why when the stack did not open. }
function ScenarioStart(const Name, Serve, Layer, Params: string; const Noise: TNoise;
  ASeed: LongInt; var St: TStats; var Peer: TPeer; out Chn: pChnVirt; out T0: QWord): Boolean;
var
  Err: string;
begin
  FillChar(St, SizeOf(St), 0);
  St.Note := '';
  Chn := nil;
  T0 := ChMsTick;
  PeerStart(Peer, ParamStr(0), ['--serve=' + Serve], Err);
  if not PeerUp(Peer, Err, Name, St, ASeed) then
    Exit(False);
  T0 := ChMsTick;
  Chn := OpenStack(Layer, Params + ' ' + NoisyLine(Noise, ASeed, Peer.Pty), Err);
  if Chn = nil then
    St.Note := Err + ';';
  Result := True;
end;

procedure RunDF1(const Name: string; Half, Crc: Boolean; const Noise: TNoise; ASeed: LongInt);
var
  Peer: TPeer;
  Err, Params: string;
  Chn: pChnVirt;
  St: TStats;
  T0: QWord;
  CrcText: string;
begin
  FillChar(St, SizeOf(St), 0);
  St.Note := '';
  if Crc then CrcText := 'ON' else CrcText := 'OFF';
  if Half then
    PeerStart(Peer, ParamStr(0), ['--serve=df1hd', '--crc=' + CrcText], Err)
  else if Crc then
    PeerStart(Peer, Df1SimPath, ['--pty', '--quiet', '--crc', '--timeout=30'], Err)
  else
    PeerStart(Peer, Df1SimPath, ['--pty', '--quiet', '--bcc', '--timeout=30'], Err);
  if not PeerUp(Peer, Err, Name, St, ASeed) then
    Exit;
  Params := Format('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=%s CRC=%s ',
    [ChoiceWord('HALF|FULL', Ord(not Half)), CrcText]) + NoisyLine(Noise, ASeed, Peer.Pty);
  T0 := ChMsTick;
  Chn := DF1OpenStack(Params, 3000, Err);
  if Chn = nil then
    St.Note := Err + ';'
  else
  begin
    if Half then
      DF1Master(Chn, HDStations, Peer.Proc.ProcessID, St)
    else
      DF1Master(Chn, 1, Peer.Proc.ProcessID, St);
    TakeEnd(St, Peer.Proc.ProcessID);
    Chn^.ChDisConnect;
    Chn^.ChClose;
    Dispose(Chn, Done);
  end;
  PeerStop(Peer);
  Report(Name, St, ASeed, ChMsTick - T0, not Crc);
end;

{ A peer's stack; a peer that cannot open it says why and ends. }
function OpenOrHalt(const Layer, Params: string): pChnVirt;
var
  Err: string;
begin
  Result := OpenStack(Layer, Params, Err);
  if Result = nil then
  begin
    WriteLn('soak: ', Err);
    Halt(1);
  end;
end;

{ ------------------------------------------------------- DF1 HD stations }

{ The peer of the half-duplex scenario: HDStations DF1 slave stations on
  one line. The pty is the line; each station's stack ends in a LOOP pair
  whose other end this relay joins to the pty, as a multidrop bus does
  (every station hears the master, the master hears every station). }
procedure ServeDF1HD(const CrcText: string);
var
  Com: pChnVirt;
  Ends: array[1..HDStations] of pChnVirt;
  Stns: array[1..HDStations] of pChnVirt;
  Tables: array[1..HDStations] of tSlcTable;
  Stations: array[1..HDStations] of tDF1Station;
  Buf, Buf2: array[0..4095] of Byte;
  Len: Word;
  K: LongInt;
  Err: string;
  Busy: Boolean;
begin
  Com := OpenOrHalt('COM', 'NAM=COM DRV=PTY LRB=65000');
  for K := 1 to HDStations do
  begin
    Ends[K] := OpenStack('LOOP', Format('NAM=LOOP PAIR=hd%d END=2 IDL=0', [K]), Err);
    Stns[K] := DF1OpenStack(Format('NAM=DF1 MAS=SLAVE FHD=HALF NOD=%d DNO=0 CRC=%s DUP=ON ' +
      'NAM=LOOP PAIR=hd%d END=1 IDL=0', [K, CrcText, K]), 3000, Err);
    if (Ends[K] = nil) or (Stns[K] = nil) then
    begin
      WriteLn('soak: station ', K, ': ', Err);
      Halt(1);
    end;
    SlcLoadDefault(Tables[K]);
    SlcStationInit(Stations[K], Stns[K], @Tables[K]);
  end;
  WriteLn('PTY ', PtyLastSlave);
  Flush(Output);
  Com^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  while not Stop and not Orphaned and (Com^.ChResult = res_Ok) do
  begin
    Busy := False;
    if Com^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      Com^.ChReceive(Len);
      for K := 1 to HDStations do
        if Len > 0 then
          ChSendWhenFree(Ends[K], @Buf, Len, 1000);
      Busy := True;
    end;
    for K := 1 to HDStations do
    begin
      Ends[K]^.ChReceiveBuffer(@Buf2, SizeOf(Buf2));
      if Ends[K]^.ChReceiveReady = CHS_ReceiveReady then
      begin
        Len := 0;
        Ends[K]^.ChReceive(Len);
        if Len > 0 then
          ChSendWhenFree(Com, @Buf2, Len, 1000);
        Busy := True;
      end;
      if DF1StationStep(Stations[K]) then
        Busy := True;
    end;
    if not Busy then
      Sleep(1);
  end;
  Write('STATS');
  for K := 1 to HDStations do
    Write(Format(' executed%d=%d repeats%d=%d', [K, Stations[K].Requests, K, Stations[K].Repeats]));
  WriteLn;
  Flush(Output);
  for K := 1 to HDStations do
  begin
    Dispose(Stns[K], Done);
    Dispose(Ends[K], Done);
  end;
  Dispose(Com, Done);
end;

{ ------------------------------------------------------------- FT 1.2 }

type
  TFT12Peer = record
    Last, Delivered, Dups, Gaps: LongInt;
  end;

function FT12OnUserData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  P: ^TFT12Peer;
  Seq: LongInt;
begin
  P := Data;
  Result := True;
  if Len <> 4 then
    Exit;
  Seq := Buf[0] or (Buf[1] shl 8) or (Buf[2] shl 16) or (LongInt(Buf[3]) shl 24);
  if Seq <= P^.Last then
    Inc(P^.Dups)
  else
  begin
    Inc(P^.Gaps, Seq - P^.Last - 1);
    Inc(P^.Delivered);
    P^.Last := Seq;
  end;
end;

procedure PutLong(var D: array of Byte; At: LongInt; V: LongInt);
begin
  D[At] := Byte(V);
  D[At + 1] := Byte(V shr 8);
  D[At + 2] := Byte(V shr 16);
  D[At + 3] := Byte(V shr 24);
end;

function GetLong(const D: array of Byte; At: LongInt): LongInt;
begin
  Result := D[At] or (D[At + 1] shl 8) or (D[At + 2] shl 16) or (LongInt(D[At + 3]) shl 24);
end;

{ class 2 data: what arrived, for the master to check in band }
function FT12OnClassData(Data: Pointer; ClassNo: Byte; var Rep: ChnFT1_2.tSendRecord;
  var Len: Word): Boolean;
var
  P: ^TFT12Peer;
begin
  P := Data;
  PutLong(Rep.Data, 0, P^.Delivered);   { Data is 1-based: open array index 0 = Data[1] }
  PutLong(Rep.Data, 4, P^.Dups);
  PutLong(Rep.Data, 8, P^.Gaps);
  Len := 12;
  Result := True;
end;

const
  FT12SlaveParams = 'NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=2 DNO=1';
  FT12MasterParams = 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=1 DNO=2';
  FT12Retries = 10;

{ A peer's stack on a pty of its own (DRV=PTY); a peer that cannot open
  it says why and ends. }
function ServeOpen(const Layer, Params: string): pChnVirt;
begin
  Result := OpenOrHalt(Layer, Params + ' NAM=COM DRV=PTY');
end;

{ A balanced station of the soak: the soak's timeout and retries, no test
  function, user data counted in P. }
procedure BalInit(var B: tFT12Balanced; Chn: pChnVirt; var P: TFT12Peer);
begin
  FillChar(P, SizeOf(P), 0);
  FT12BalancedInit(B, Chn);
  B.TimeoutMs := FT12Timeout;
  B.Retries := FT12Retries;
  B.TestMs := 0;
  B.Data := @P;
  B.OnUserData := @FT12OnUserData;
end;

procedure ServeFT12;
var
  Chn: pChnVirt;
  S: tFT12Station;
  P: TFT12Peer;
  Err: string;
begin
  Chn := ServeOpen('FT1_2', FT12SlaveParams);
  FillChar(P, SizeOf(P), 0);
  FT12StationInit(S, Chn);
  S.Data := @P;
  S.OnUserData := @FT12OnUserData;
  S.OnClassData := @FT12OnClassData;
  WriteLn('PTY ', PtyLastSlave);
  Flush(Output);
  while not Stop and not Orphaned and (Chn^.ChResult = res_Ok) do
    if not FT12StationStep(S) then
      ChnWaitAny(20);
  WriteLn(Format('STATS delivered=%d dups=%d gaps=%d repeats=%d', [P.Delivered, P.Dups, P.Gaps, S.Repeats]));
  Flush(Output);
  Dispose(Chn, Done);
end;

procedure RunFT12(const Name: string; const Noise: TNoise; ASeed: LongInt);
var
  Peer: TPeer;
  Err: string;
  Chn: pChnVirt;
  St: TStats;
  T0, Start: QWord;
  Link: tFT12Link;
  Req: ChnFT1_2.tSendRecord;
  Rep: ChnFT1_2.tRecRecord;
  RepLen: Word;
  Seq, Tries, Delivered, Dups, Gaps: LongInt;
  R: tChResult;
  Ok: Boolean;

  function Check: Boolean;
  var
    T: LongInt;
  begin
    Result := False;
    for T := 1 to AppTries do
    begin
      RepLen := 0;
      R := FT12RequestClass(Chn, Link, 2, Rep, RepLen, FT12Timeout, FT12Retries);
      if (R = res_Ok) and (Rep.MessType = ChnFT1_2.tpLongM) and (RepLen = 4 + 12) then
      begin
        Delivered := GetLong(Rep.Data, 0);
        Dups := GetLong(Rep.Data, 4);
        Gaps := GetLong(Rep.Data, 8);
        Exit(True);
      end;
      Inc(St.Retries);
      if Stop then
        Exit;
    end;
  end;

begin
  if not ScenarioStart(Name, 'ft12', 'FT1_2', FT12MasterParams, Noise, ASeed, St, Peer, Chn, T0) then
    Exit;
  if Chn <> nil then
  begin
    FT12LinkInit(Link, 2);
    Seq := 0;
    Delivered := 0;
    Dups := 0;
    Gaps := 0;
    Start := ChMsTick;
    while not Done_(St, Start) do
    begin
      Inc(Seq);
      FillChar(Req, SizeOf(Req), 0);
      Req.MessType := ChnFT1_2.tpLongM;
      Req.FC := FCM_UserDataReply;
      PutLong(Req.Data, 0, Seq);
      Ok := False;
      for Tries := 1 to AppTries do
      begin
        RepLen := 0;
        R := FT12Transact(Chn, Link, Req, 4 + 4, Rep, RepLen, FT12Timeout, FT12Retries);
        if R = res_Ok then
        begin
          Ok := True;
          Break;
        end;
        if R <> res_Timeout then
        begin
          St.Note := St.Note + ' ' + Chn^.ChResultStr(R) + ';';
          Break;
        end;
        Inc(St.Retries);
        Inc(St.Timeouts);
        if Stop then
          Break;
      end;
      if not Ok then
      begin
        Inc(St.Losses);
        Break;
      end;
      Inc(St.Messages);
      if not (((Rep.MessType = ChnFT1_2.tpShortM) and (Rep.FC = FCS_Ack)) or
              (Rep.MessType = ChnFT1_2.tpSACK)) then
        Inc(St.Bad);
      if (St.Messages = 1) or (St.Messages = WarmUp) then
        TakeStart(St, Peer.Proc.ProcessID);
      if (Seq mod CheckEvery = 0) and not Check then
      begin
        Inc(St.Losses);
        Break;
      end;
    end;
    if Check then
    begin
      { delivered exactly once: every one arrived, none twice, none skipped }
      if Delivered <> Seq then
        St.Note := St.Note + Format(' secondary got %d of %d;', [Delivered, Seq]);
      Inc(St.Dups, Dups);
      { A transaction that fails after all its repetitions (a timeout: on
        a loaded machine the secondary's answer can be that late) leaves
        the link not reset; the next one resets it, and the secondary
        forgets its FCB, and sends the message again. If the first had
        arrived and only its answer was late or lost, the secondary takes
        it twice: IEC 60870-5-2 cannot tell after a reset. So each such
        re-send may explain one duplicate; more than that, or one without
        a failed transaction, fails (a secondary that ignores the FCB). }
      if Dups <= St.Timeouts then
        St.DupsAfterReset := Dups
      else
        St.DupsAfterReset := St.Timeouts;
      Inc(St.Losses, Gaps);
    end
    else
      Inc(St.Losses);
    Inc(St.Retries, Link.Repeats);
    TakeEnd(St, Peer.Proc.ProcessID);
    NoteFrameFaults(St, Chn, Noise);
    Dispose(Chn, Done);
  end;
  PeerStop(Peer);
  Report(Name, St, ASeed, ChMsTick - T0, False);
end;

{ ----------------------------------------------------- FT 1.2 balanced }

const
  FT12BalAParams = 'NAM=FT1_2 MS=OFF PRI=ON DIR=1 LEN=0 NOD=1 DNO=2';
  FT12BalBParams = 'NAM=FT1_2 MS=OFF PRI=OFF DIR=0 LEN=0 NOD=2 DNO=1';
  FT12BalQueued = 2;       { user data kept queued by each station }
  FT12BalDrainMs = 4000;   { at the end: until both are quiet, at most }

{ Queue user data with the next sequence number while the queue is short. }
procedure BalFeed(var B: tFT12Balanced; var Seq: LongInt);
var
  D: array[0..3] of Byte;
begin
  while B.QCount < FT12BalQueued do
  begin
    PutLong(D, 0, Seq + 1);
    if FT12BalancedSend(B, @D[0], 4, True) <> res_Ok then
      Exit;
    Inc(Seq);
  end;
end;

{ Step B once; wait on the program-wide wait when it took nothing. }
procedure BalStep(var B: tFT12Balanced);
begin
  if not FT12BalancedStep(B) then
    ChnWaitAny(20);
end;

{ The peer: station B, sending its own numbered user data to A and
  counting A's. On SIGTERM it stops queueing, runs until its queue is
  empty (or FT12BalDrainMs), and prints what it saw. }
procedure ServeFT12Bal;
var
  Chn: pChnVirt;
  B: tFT12Balanced;
  P: TFT12Peer;
  Err: string;
  Seq: LongInt;
  Until_: QWord;
begin
  Chn := ServeOpen('FT1_2', FT12BalBParams);
  BalInit(B, Chn, P);
  Seq := 0;
  WriteLn('PTY ', PtyLastSlave);
  Flush(Output);
  while not Stop and not Orphaned and (Chn^.ChResult = res_Ok) do
  begin
    BalFeed(B, Seq);
    BalStep(B);
  end;
  Until_ := ChMsTick + FT12BalDrainMs;
  while not FT12BalancedQuiet(B) and (ChMsTick < Until_) and not Orphaned and
        (Chn^.ChResult = res_Ok) do
    BalStep(B);
  WriteLn(Format('STATS delivered=%d dups=%d gaps=%d confirmed=%d sent=%d linklost=%d stale=%d',
    [P.Delivered, P.Dups, P.Gaps, B.Confirmed, Seq, B.LinkLost, B.Stale]));
  Flush(Output);
  Dispose(Chn, Done);
end;

procedure RunFT12Bal(const Name: string; const Noise: TNoise; ASeed: LongInt);
var
  Peer: TPeer;
  Err: string;
  Chn: pChnVirt;
  St: TStats;
  T0, Start, Until_: QWord;
  A: tFT12Balanced;
  P: TFT12Peer;
  Seq: LongInt;
  BDelivered, BDups, BGaps, BConfirmed, BLinkLost: Int64;
begin
  if not ScenarioStart(Name, 'ft12bal', 'FT1_2', FT12BalAParams, Noise, ASeed, St, Peer, Chn, T0) then
    Exit;
  if Chn <> nil then
  begin
    BalInit(A, Chn, P);
    Seq := 0;
    Start := ChMsTick;
    while not Done_(St, Start) do
    begin
      BalFeed(A, Seq);
      BalStep(A);
      St.Messages := A.Confirmed + P.Delivered;
      if (St.Messages >= WarmUp) and (St.RssStart = 0) then
        TakeStart(St, Peer.Proc.ProcessID);
      if Chn^.ChResult <> res_Ok then
      begin
        St.Note := St.Note + ' ' + Chn^.ChResultStr(Chn^.ChResult) + ';';
        Break;
      end;
    end;
    if St.RssStart = 0 then
      TakeStart(St, Peer.Proc.ProcessID);
    TakeEnd(St, Peer.Proc.ProcessID);
    { the end: both stop queueing and run until their queues are empty }
    FpKill(Peer.Proc.ProcessID, SIGTERM);
    Until_ := ChMsTick + FT12BalDrainMs + 2000;
    while Peer.Proc.Running and (ChMsTick < Until_) do
    begin
      BalStep(A);
      PeerRead(Peer);
    end;
    BDelivered := -1;
    PeerStop(Peer);
    BDelivered := PeerStat(Peer, 'delivered');
    BDups := PeerStat(Peer, 'dups');
    BGaps := PeerStat(Peer, 'gaps');
    BConfirmed := PeerStat(Peer, 'confirmed');
    BLinkLost := PeerStat(Peer, 'linklost');
    St.Messages := A.Confirmed + P.Delivered;
    St.Retries := A.Retransmits;
    St.Timeouts := A.LinkLost;
    St.Stale := A.Stale;
    if BDelivered < 0 then
    begin
      St.Note := St.Note + ' the peer reported nothing: ' + Peer.Out_ + ';';
      Inc(St.Losses);
    end
    else
    begin
      { confirmed to the sender only once the peer took it; never twice }
      if BDelivered < A.Confirmed then
      begin
        St.Note := St.Note + Format(' B got %d of %d confirmed;', [BDelivered, A.Confirmed]);
        Inc(St.Losses, A.Confirmed - BDelivered);
      end;
      if P.Delivered < BConfirmed then
      begin
        St.Note := St.Note + Format(' A got %d of %d confirmed;', [P.Delivered, BConfirmed]);
        Inc(St.Losses, BConfirmed - P.Delivered);
      end;
      Inc(St.Losses, BGaps + P.Gaps);
      St.Dups := BDups + P.Dups;
      { after a link reset the secondary forgets its FCB: a message whose
        ACK was lost is sent again and taken twice (IEC 60870-5-2 cannot
        tell); one per link loss of its sender is reported, not failed }
      St.DupsAfterReset := Min(BDups, A.LinkLost) + Min(P.Dups, BLinkLost);
    end;
    NoteFrameFaults(St, Chn, Noise);
    Dispose(Chn, Done);
  end;
  PeerStop(Peer);
  Report(Name, St, ASeed, ChMsTick - T0, False);
end;

{ ---------------------------------------------------------------- ICS }

const
  ICSSlaveParams = 'NAM=ICS MAS=SLAVE NOD=2 DNO=1';
  ICSMasterParams = 'NAM=ICS MAS=MASTER NOD=1 DNO=2';

function ICSValue(Seq: LongInt): SmallInt;
begin
  Result := SmallInt((Seq * 7) and $7FFF);
end;

procedure ServeICS;
var
  Chn: pChnVirt;
  Req, Ans: ChnICS.tRecRecord;
  Len: Word;
  Answered: LongInt;
  Err: string;
begin
  Chn := ServeOpen('ICS', ICSSlaveParams);
  Answered := 0;
  Chn^.ChReceiveBuffer(@Req, SizeOf(Req));
  WriteLn('PTY ', PtyLastSlave);
  Flush(Output);
  while not Stop and not Orphaned and (Chn^.ChResult = res_Ok) do
  begin
    if Chn^.ChReceiveReady <> CHS_ReceiveReady then
    begin
      Sleep(1);
      Continue;
    end;
    Len := 0;
    Chn^.ChReceive(Len);
    if (Chn^.ChReceiveResult <> res_Ok) or (Req.OpCode <> OCM_ReadData) or (Len <> 4 + 4) then
      Continue;                 { ICSlink has no NAK: the master asks again }
    FillChar(Ans, SizeOf(Ans), 0);
    Ans.OpCode := OCS_ReadData;
    Ans.BlockNum := Req.BlockNum;
    Ans.Data[0] := Req.Data[0];
    Ans.Data[1] := Req.Data[1];
    Ans.Data[2] := ICSValue(LongInt(Req.Data[0]) shl 15 + Req.Data[1]);
    Ans.Text := '';
    if ChSendWhenFree(Chn, @Ans, 4 + 6, 1000) = res_Ok then
      Inc(Answered);
  end;
  WriteLn(Format('STATS answered=%d', [Answered]));
  Flush(Output);
  Dispose(Chn, Done);
end;

procedure RunICS(const Name: string; const Noise: TNoise; ASeed: LongInt);
var
  Peer: TPeer;
  Err: string;
  Chn: pChnVirt;
  St: TStats;
  T0, Start, Until_: QWord;
  Req, Ans: ChnICS.tRecRecord;
  Len: Word;
  Seq, Tries: LongInt;
  Got: Boolean;
begin
  if not ScenarioStart(Name, 'ics', 'ICS', ICSMasterParams, Noise, ASeed, St, Peer, Chn, T0) then
    Exit;
  if Chn <> nil then
  begin
    Chn^.ChReceiveBuffer(@Ans, SizeOf(Ans));
    Seq := 0;
    Start := ChMsTick;
    while not Done_(St, Start) do
    begin
      Inc(Seq);
      FillChar(Req, SizeOf(Req), 0);
      Req.OpCode := OCM_ReadData;
      Req.BlockNum := Seq mod 10;
      Req.Data[0] := (Seq shr 15) and $7FFF;
      Req.Data[1] := Seq and $7FFF;
      Req.Text := '';
      Got := False;
      for Tries := 1 to AppTries do
      begin
        if Tries > 1 then
        begin
          Inc(St.Retries);
          Inc(St.Timeouts);
        end;
        if ChSendWhenFree(Chn, @Req, 4 + 4, 1000) <> res_Ok then
        begin
          St.Note := St.Note + ' send: ' + Chn^.ChResultStr(Chn^.ChSendResult) + ';';
          Break;
        end;
        Until_ := ChMsTick + ICSTimeout;
        repeat
          if Chn^.ChReceiveReady = CHS_ReceiveReady then
          begin
            Len := 0;
            Chn^.ChReceive(Len);
            if Chn^.ChReceiveResult <> res_Ok then
              Continue;         { broken: the answer is lost, ask again later }
            if (Ans.OpCode = OCS_ReadData) and (Len = 4 + 6) and (Ans.BlockNum = Req.BlockNum) and
               (Ans.Data[0] = Req.Data[0]) and (Ans.Data[1] = Req.Data[1]) then
            begin
              if Ans.Data[2] <> ICSValue(Seq) then
                Inc(St.Bad);
              Got := True;
            end
            else
              Inc(St.Stale);    { the answer to an earlier request, or damage }
          end
          else if Chn^.ChResult <> res_Ok then
            Break;
        until Got or (ChMsTick > Until_);
        if Got or (Chn^.ChResult <> res_Ok) or Stop then
          Break;
      end;
      if not Got then
      begin
        Inc(St.Losses);
        Break;
      end;
      Inc(St.Messages);
      if (St.Messages = 1) or (St.Messages = WarmUp) then
        TakeStart(St, Peer.Proc.ProcessID);
    end;
    TakeEnd(St, Peer.Proc.ProcessID);
    Dispose(Chn, Done);
  end;
  PeerStop(Peer);
  Report(Name, St, ASeed, ChMsTick - T0, False);
end;

{ ------------------------------------------------- IEC 101 hostile slaves }

const
  IecHealthy = 5;       { link addresses of the two slaves }
  IecHostile = 7;
  IecSettleMs = 2500;   { after 7 turns hostile: its first failures }
  { what slave 7 streams as class 1 data (M_SP_NA_1 IOA 104 on, COT 3) }
  IecStreamed = '01 01 03 00 01 00 68 00 00 01';
  IecKinds: array[0..2] of string = ('halfdead', 'acdstuck', 'stream');

{ The peer: slaves 5 and 7 (Iec101Sim, idle: "no data" to every class
  poll) on one line - each on a LOOP pair, the pairs and the pty joined
  by a LoopHub as a bus. On SIGUSR1 slave 7 turns hostile: Kind
  halfdead answers status and reset but no class poll, acdstuck sets ACD
  in every answer with no class 1 data behind it, stream has an event in
  class 1 for every poll. }
procedure ServeIec101(const Kind: string);
var
  Com: pChnVirt;
  Hub: TLoopHub;
  Sims: array[0..1] of TSim;
  K: Integer;
  Busy: Boolean;
begin
  Com := OpenOrHalt('COM', 'NAM=COM DRV=PTY LRB=65000');
  Hub := TLoopHub.Create;
  Hub.AddChannel(Com);
  for K := 0 to 1 do
  begin
    Sims[K] := TSim.Create(Format('NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=%d NAM=LOOP PAIR=iec%d END=1',
      [IecHealthy + 2 * K, K]), False);
    Hub.AddPort('iec' + IntToStr(K));
  end;
  WriteLn('PTY ', PtyLastSlave);
  Flush(Output);
  while not Stop and not Orphaned and (Com^.ChResult = res_Ok) do
  begin
    if TurnHostile then
    begin
      TurnHostile := False;
      Sims[1].HalfDead := Kind = 'halfdead';
      Sims[1].AcdStuck := Kind = 'acdstuck';
      if Kind = 'stream' then
        Sims[1].Stream := IecStreamed;
    end;
    Busy := Hub.Pump;
    for K := 0 to 1 do
      if Sims[K].Step then
        Busy := True;
    if not Busy then
      ChnWaitAny(5);
  end;
  WriteLn(Format('STATS unanswered=%d', [Sims[1].HalfDeadPolls]));
  Flush(Output);
  for K := 0 to 1 do
    Sims[K].Free;
  Hub.Free;                 { and Com with it }
end;

{ Class 2 polls slave 5 gets in Ms. A window in which slave 5 itself
  answered late (a link repetition to it: only a stalled machine delays a
  healthy peer on a pty) says nothing about the polling: it is measured
  again, up to 5 times; Late counts those. }
function PollsOfHealthy(var M: tIecMaster; Ms: LongInt; var Late: LongInt): LongInt;
var
  Try_, Repeats: LongInt;
begin
  for Try_ := 1 to 5 do
  begin
    Result := M.Slaves[0].Class2;
    Repeats := M.Slaves[0].Link.Repeats;
    IecPollFor(M, Ms);
    Result := M.Slaves[0].Class2 - Result;
    if M.Slaves[0].Link.Repeats = Repeats then
      Exit;
    Inc(Late);
  end;
end;

{ The master with its defaults (but the soak's link timeout) polls slaves
  5 and 7 half the time with both healthy, then the peer turns 7 hostile
  (SIGUSR1), and after IecSettleMs the other half: slave 5 must keep at
  least half its polls. The rates go into the report line. }
procedure RunIec101(const Name, Kind: string);
var
  Peer: TPeer;
  Chn: pChnVirt;
  St: TStats;
  T0, Until_: QWord;
  M: tIecMaster;
  PhaseMs, Normal, Hostile, Late: LongInt;
begin
  if not ScenarioStart(Name, 'iec101-' + Kind, 'FT1_2', 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=5',
    Noises[0], 0, St, Peer, Chn, T0) then
    Exit;
  if Chn <> nil then
  begin
    FillChar(M, SizeOf(M), 0);
    IecMasterInit(M, Chn, IecDefaultParams);
    M.TimeoutMs := FT12Timeout;
    IecMasterAddSlave(M, IecHealthy);
    IecMasterAddSlave(M, IecHostile);
    PhaseMs := Max(1000, Seconds * 500);
    Until_ := ChMsTick + 5000;
    repeat
      IecPollFor(M, 100);
    until ((M.Slaves[0].State = isOnline) and (M.Slaves[1].State = isOnline)) or (ChMsTick > Until_) or Stop;
    TakeStart(St, Peer.Proc.ProcessID);
    Late := 0;
    Normal := PollsOfHealthy(M, PhaseMs, Late);
    FpKill(Peer.Proc.ProcessID, SIGUSR1);
    IecPollFor(M, IecSettleMs);
    Hostile := PollsOfHealthy(M, PhaseMs, Late);
    St.Messages := M.Slaves[0].Class2;
    St.Retries := M.Retries;
    St.Timeouts := M.Slaves[1].Failures;
    St.Faults := Format(' slave 5: %.1f class 2 polls/s with slave 7 healthy, %.1f with it %s (%d %%);' +
      ' slave 7: %d class 1, %d class 2 polls, %d failures, back-off %d ms; %d windows measured again;',
      [Normal * 1000 / PhaseMs, Hostile * 1000 / PhaseMs, Kind, Hostile * 100 div Max(1, Normal),
       M.Slaves[1].Class1, M.Slaves[1].Class2, M.Slaves[1].Failures, M.Slaves[1].BackoffMs, Late]);
    if Normal < MinMessages then
      St.Note := St.Note + ' slave 5 hardly polled with both healthy;';
    if 2 * Hostile < Normal then
      St.Note := St.Note + ' slave 5 lost more than half its polls;';
    TakeEnd(St, Peer.Proc.ProcessID);
    Dispose(Chn, Done);
  end;
  PeerStop(Peer);
  Report(Name, St, 0, ChMsTick - T0, False);
end;

{ --------------------------------------------------------------- main }

function Selected(const Name: string): Boolean;
begin
  Result := (Only = '') or (Pos(LowerCase(Only), LowerCase(Name)) > 0);
end;

var
  I, K, N: LongInt;
  Arg, Key, Value, Serve, CrcArg: string;
begin
  Seconds := 10;
  Count := 0;
  Seed := 0;
  Only := '';
  Serve := '';
  CrcArg := 'ON';
  Df1SimPath := ExtractFilePath(ParamStr(0)) + '../bin/df1sim';
  for I := 1 to ParamCount do
  begin
    Arg := ParamStr(I);
    Key := Arg;
    Value := '';
    if Pos('=', Arg) > 0 then
    begin
      Key := Copy(Arg, 1, Pos('=', Arg) - 1);
      Value := Copy(Arg, Pos('=', Arg) + 1, MaxInt);
    end;
    N := 0;
    if (Key = '--seconds') and StrToNum(Value, 1, 1000000, N) then Seconds := N
    else if (Key = '--count') and StrToNum(Value, 0, MaxLongInt, N) then Count := N
    else if (Key = '--seed') and StrToNum(Value, 0, MaxLongInt - 100, N) then Seed := N
    else if Key = '--only' then Only := Value
    else if Key = '--df1sim' then Df1SimPath := Value
    else if Key = '--serve' then Serve := Value
    else if Key = '--crc' then CrcArg := Value
    else if Key = '--verbose' then Verbose := True
    else
    begin
      WriteLn('soak: bad argument ', Arg, ' (see tests/soak/soak.pas)');
      Halt(2);
    end;
  end;
  CatchSignals;
  Parent := FpGetPPid;
  if Serve = 'df1hd' then
    ServeDF1HD(CrcArg)
  else if Serve = 'ft12' then
    ServeFT12
  else if Serve = 'ft12bal' then
    ServeFT12Bal
  else if Serve = 'ics' then
    ServeICS
  else if Copy(Serve, 1, 7) = 'iec101-' then
    ServeIec101(Copy(Serve, 8, MaxInt))
  else if Serve <> '' then
  begin
    WriteLn('soak: unknown --serve=', Serve);
    Halt(2);
  end
  else
  begin
    Randomize;
    if Seed = 0 then
      Seed := 1 + Random(1000000);
    if Count > 0 then
      WriteLn(Format('soak: %d messages per scenario, seeds from %d', [Count, Seed]))
    else
      WriteLn(Format('soak: %d s per scenario, seeds from %d', [Seconds, Seed]));
    K := 0;
    for I := Low(Noises) to High(Noises) do
    begin
      if Selected('df1-full-crc-' + Noises[I].Name) then
        RunDF1('df1-full-crc-' + Noises[I].Name, False, True, Noises[I], Seed);
      Inc(K);
      if Selected('df1-full-bcc-' + Noises[I].Name) then
        RunDF1('df1-full-bcc-' + Noises[I].Name, False, False, Noises[I], Seed);
      Inc(K);
      if Selected('df1-half-crc-' + Noises[I].Name) then
        RunDF1('df1-half-crc-' + Noises[I].Name, True, True, Noises[I], Seed);
      Inc(K);
      if Selected('ft12-' + Noises[I].Name) then
        RunFT12('ft12-' + Noises[I].Name, Noises[I], Seed);
      Inc(K);
      if Selected('ics-' + Noises[I].Name) then
        RunICS('ics-' + Noises[I].Name, Noises[I], Seed);
      Inc(K);
      if Selected('ft12bal-' + Noises[I].Name) then
        RunFT12Bal('ft12bal-' + Noises[I].Name, Noises[I], Seed);
      Inc(K);
      if Stop then
        Break;
    end;
    for I := Low(FrameFaults) to High(FrameFaults) do
    begin
      if Stop then
        Break;
      if Selected('ft12-' + FrameFaults[I].Name) then
        RunFT12('ft12-' + FrameFaults[I].Name, FrameFaults[I], Seed);
      if Selected('ft12bal-' + FrameFaults[I].Name) then
        RunFT12Bal('ft12bal-' + FrameFaults[I].Name, FrameFaults[I], Seed);
    end;
    for I := Low(IecKinds) to High(IecKinds) do
      if not Stop and Selected('iec101-' + IecKinds[I]) then
        RunIec101('iec101-' + IecKinds[I], IecKinds[I]);
    WriteLn(Format('soak: %d failed, %d scenarios run', [Failed, Ran]));
    if Failed > 0 then
      ExitCode := 1;   { not Halt: the main program's strings are freed at its end }
  end;
end.
