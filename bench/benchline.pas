{ benchline - how much of a serial line each protocol's normal exchange
  keeps busy, on the in-memory line at a real speed (NAM=LOOP BD=, docs/
  ChnLoop.md): a master reads 50 words (N7:0..49) from SLC stations again
  and again for SECONDS (default 2) and the line's busy time (characters
  carried times the character time, both directions summed) is divided by
  the time it took. A protocol that waits for nothing it need not wait for
  comes close to 100 % (a full-duplex line can pass 100 %: both directions
  carry at once); the rest is what the master and the stations spend
  between frames. Rows: DF1 full duplex (DF1Transact's master), DF1 half
  duplex through the poll master (ChnDF1Poll) with one station and with
  four on one bus; FT 1.2 / IEC 60870-5-101 unbalanced (ChnIec101Master)
  interrogating 86 points of one slave (ChnIec101Slave) and of four on a
  bus (also with one point per answer ASDU), and balanced with one; ICSlink, a master reading 32 numbers of a
  station (RD, answered at once); 9600 and 19200 Bd, DF1 8N1, FT 1.2 and
  ICS 8E1.
  Run by "make bench". }
program benchline;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnWait, ChnLoop, ChnDF1, ChnDF1Link, ChnDF1Poll,
  ChnPcccClient, ChnSlc, ChnFT1_2, ChnIec101Asdu, ChnIec101Master, ChnIec101Slave,
  ChnICS, ChnICSCodec;

const
  MaxSt = 4;

var
  Table: tSlcTable;
  Stations: array[1..MaxSt] of tDF1Station;
  StChn: array[1..MaxSt] of pChnVirt;
  NSt: LongInt;
  Seconds: LongInt = 2;

procedure StepStations(Data: Pointer);
var
  I: LongInt;
  Busy: Boolean;
begin
  Busy := False;
  for I := 1 to NSt do
    if DF1StationStep(Stations[I]) then
      Busy := True;
  if not Busy then
    ChnWaitAny(5);                    { woken when the line's characters arrive }
end;

function Open(const Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit('DF1');
  Result^.ChSetParam(Params);
  Result^.ChOpen;
  Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    WriteLn('benchline: cannot open ', Params, ': ', Result^.ChErrorText);
    Halt(1);
  end;
end;

procedure AddStations(N: LongInt; const Pair, Line, Duplex, Crc: string);
var
  I: LongInt;
begin
  NSt := N;
  for I := 1 to N do
  begin
    StChn[I] := Open(Format('NOD=%d DNO=0 MAS=SLAVE FHD=%s CRC=%s NAM=LOOP PAIR=%s END=%d %s',
      [I, Duplex, Crc, Pair, I + 1, Line]));
    SlcStationInit(Stations[I], StChn[I], @Table);
  end;
end;

procedure CloseAll(Master: pChnVirt);
var
  I: LongInt;
begin
  for I := 1 to NSt do
    Dispose(StChn[I], Done);
  NSt := 0;
  Dispose(Master, Done);
end;

procedure Report(const What: string; Bd, Reads: LongInt; const Pair: string; T0: QWord);
var
  Chars, BusyUs, Took: QWord;
begin
  Took := ChnClockUs - T0;
  LoopLineLoad(Pair, Chars, BusyUs);
  WriteLn(Format('%-46s %6d %8.2f %8d %7.1f %%', [What, Bd, Reads / (Took / 1e6),
    Chars, 100.0 * BusyUs / Took]));
end;

procedure Run(const What: string; Bd, N: LongInt; Half: Boolean);
var
  Master: pChnVirt;
  P: tDF1Poller;
  C: tPcccClient;
  V: array[0..49] of LongInt;
  Pair, Line: string;
  Reads: LongInt;
  T0, Stop: QWord;
begin
  Pair := Format('BL%d%d%d', [Bd, N, Ord(Half)]);
  Line := Format('BD=%d', [Bd]);
  if Half then
  begin
    Master := Open(Format('NOD=0 MAS=MASTER FHD=HALF CRC=OFF NAM=LOOP PAIR=%s END=1 %s', [Pair, Line]));
    AddStations(N, Pair, Line, 'HALF', 'OFF');
    DF1PollInit(P, Master);
    for Reads := 1 to N do
      DF1PollAdd(P, Reads, False);
    P.NormalGroup := N;
    PcccClientInit(C, Master);
  end
  else
  begin
    Master := Open(Format('NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=ON NAM=LOOP PAIR=%s END=1 %s', [Pair, Line]));
    AddStations(1, Pair, Line, 'FULL', 'ON');
    PcccClientInit(C, Master);
  end;
  C.Idle := @StepStations;
  Reads := 0;
  T0 := ChnClockUs;
  Stop := ChMsTick + QWord(Seconds) * 1000;
  while ChMsTick < Stop do
  begin
    if Half then
      PcccClientPoller(C, P, 1 + Reads mod N);
    if PcccReadInts(C, 'N7:0', 50, V) <> res_Ok then
    begin
      WriteLn('benchline: ', What, ': ', C.Err);
      Break;
    end;
    Inc(Reads);
  end;
  Report(What, Bd, Reads, Pair, T0);
  CloseAll(Master);
end;

var
  Iec: array[1..MaxSt] of tIecSlaveStation;

procedure StepIecSlaves(Data: Pointer);
var
  I: LongInt;
  Busy: Boolean;
begin
  Busy := False;
  for I := 1 to NSt do
    if IecSlaveStep(Iec[I]) then
      Busy := True;
  if not Busy then
    ChnWaitAny(5);
end;

function OpenFt(const Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit('FT1_2');
  Result^.ChSetParam(Params);
  Result^.ChOpen;
  Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    WriteLn('benchline: cannot open ', Params, ': ', Result^.ChErrorText);
    Halt(1);
  end;
end;

{ FT 1.2: interrogations of 86 points (60 single points, 26 floats) of
  each of N slaves, in turn. Short: the types alternate, so the slave
  (which packs consecutive points of one type) answers with one point
  per ASDU - many short frames, as lib60870's slaves answer, where a
  master that waits between polls loses most. }
procedure RunIec(const What: string; Bd, N: LongInt; Balanced: Boolean; Short: Boolean = False);
var
  Master: pChnVirt;
  M: tIecMaster;
  Pair, Line, Ms, Err: string;
  E: ShortString;
  I, K, Gis: LongInt;
  O: tIecObject;
  T0, Stop: QWord;
begin
  Pair := Format('BLI%d%d%d%d', [Bd, N, Ord(Balanced), Ord(Short)]);
  Line := Format('NAM=LOOP PAIR=%s BD=%d PAR=E', [Pair, Bd]);
  Ms := 'MS=ON';
  if Balanced then
    Ms := 'MS=OFF';
  Master := OpenFt(Format('NAM=FT1_2 %s MAS=MASTER LEN=0 NOD=0 DNO=1 %s END=1', [Ms, Line]));
  NSt := N;
  for I := 1 to N do
  begin
    StChn[I] := OpenFt(Format('NAM=FT1_2 %s MAS=SLAVE LEN=0 NOD=%d DNO=0 %s END=%d', [Ms, I, Line, I + 1]));
    if IecSlaveInit(Iec[I], StChn[I], IecDefaultParams, 1, E) <> res_Ok then
    begin
      WriteLn('benchline: ', E);
      Halt(1);
    end;
    for K := 0 to 85 do
    begin
      FillChar(O, SizeOf(O), 0);
      O.Ioa := 100 + K;
      O.Int := K and 1;
      O.Number := K * 1.5;
      if (not Short and (K < 60)) or (Short and not Odd(K)) then
        IecSlaveAddPoint(Iec[I], M_SP_NA_1, O, 0, E)
      else
        IecSlaveAddPoint(Iec[I], M_ME_NC_1, O, 0, E);
    end;
  end;
  if IecMasterInit(M, Master, IecDefaultParams) <> res_Ok then
  begin
    WriteLn('benchline: ', What, ': the master does not start');
    Halt(1);
  end;
  for I := 1 to N do
    IecMasterAddSlave(M, I);
  M.Idle := @StepIecSlaves;
  Err := '';
  Gis := 0;
  T0 := ChnClockUs;
  Stop := ChMsTick + QWord(Seconds) * 1000;
  while ChMsTick < Stop do
  begin
    if IecInterrogation(M, 1 + Gis mod N, 1, 20) <> res_Ok then
    begin
      WriteLn('benchline: ', What, ': the interrogation failed');
      Break;
    end;
    Inc(Gis);
  end;
  Report(What, Bd, Gis, Pair, T0);
  for I := 1 to N do
    Dispose(StChn[I], Done);
  NSt := 0;
  Dispose(Master, Done);
end;

{ ICSlink: RD of block 0, 3 numbers asked, 32 answered, over and over. }
procedure RunIcs(const What: string; Bd: LongInt);
var
  A, B: pChnVirt;
  Req, Ans, RA, RB: tICSRecord;
  Pair, Line: string;
  Len: Word;
  I, Reads: LongInt;
  T0, Stop: QWord;

  function OpenIcs(const Params: string): pChnVirt;
  begin
    Result := ChnCollection^.ChNewInit('ICS');
    Result^.ChSetParam(Params);
    Result^.ChOpen;
    Result^.ChConnect;
    if Result^.ChResult <> res_Ok then
    begin
      WriteLn('benchline: cannot open ', Params, ': ', Result^.ChErrorText);
      Halt(1);
    end;
  end;

begin
  Pair := Format('BLS%d', [Bd]);
  Line := Format('NAM=LOOP PAIR=%s BD=%d PAR=E', [Pair, Bd]);
  A := OpenIcs(Format('NAM=ICS MAS=MASTER NOD=1 DNO=2 %s END=1', [Line]));
  B := OpenIcs(Format('NAM=ICS MAS=SLAVE NOD=2 DNO=1 %s END=2', [Line]));
  A^.ChReceiveBuffer(@RA, SizeOf(RA));
  B^.ChReceiveBuffer(@RB, SizeOf(RB));
  FillChar(Req, SizeOf(Req), 0);
  Req.OpCode := OCM_ReadData;
  Req.Data[0] := 0;
  Req.Data[1] := 10;
  Req.Data[2] := 15;
  Ans := Req;
  for I := 0 to ICSMaxDataLen - 1 do
    Ans.Data[I] := I * 100;
  Reads := 0;
  T0 := ChnClockUs;
  Stop := ChMsTick + QWord(Seconds) * 1000;
  while ChMsTick < Stop do
  begin
    A^.ChSend(@Req, 4 + 3 * SizeOf(tICSData));
    if A^.ChSendResult <> res_Ok then
      Break;
    repeat
      if B^.ChReceiveReady = CHS_ReceiveReady then
      begin
        B^.ChReceive(Len);
        while B^.ChSendReady <> CHS_SendReady do
          ChnWaitAny(5);
        B^.ChSend(@Ans, 4 + ICSMaxDataLen * SizeOf(tICSData));
      end
      else if A^.ChReceiveReady <> CHS_ReceiveReady then
        ChnWaitAny(5);
    until (A^.ChReceiveReady = CHS_ReceiveReady) or (ChMsTick > Stop + 2000);
    A^.ChReceive(Len);
    Inc(Reads);
    while A^.ChSendReady <> CHS_SendReady do
      ChnWaitAny(5);
  end;
  Report(What, Bd, Reads, Pair, T0);
  Dispose(A, Done);
  Dispose(B, Done);
end;

const
  Rates: array[0..1] of LongInt = (9600, 19200);
var
  Bd: LongInt;

begin
  if ParamCount >= 1 then
    Seconds := StrToIntDef(ParamStr(1), 2);
  SlcLoadDefault(Table);
  WriteLn('line share on NAM=LOOP at BD: DF1 reads N7:0..49 (8N1), FT 1.2 interrogations (8E1)');
  WriteLn(Format('%-46s %6s %8s %8s %9s', ['exchange', 'Bd', 'n/s', 'chars', 'line used']));
  for Bd in Rates do
  begin
    Run('DF1 full duplex, CRC', Bd, 1, False);
    Run('DF1 half duplex, 1 station', Bd, 1, True);
    Run('DF1 half duplex, 4 stations (bus)', Bd, 4, True);
    RunIec('FT 1.2 unbalanced, GI of 86, 1 slave', Bd, 1, False);
    RunIec('FT 1.2 unbalanced, GI of 86, 4 slaves', Bd, 4, False);
    RunIec('FT 1.2 unbalanced, GI, 1 point/ASDU, 1 slave', Bd, 1, False, True);
    RunIec('FT 1.2 unbalanced, GI, 1 point/ASDU, 4 slaves', Bd, 4, False, True);
    RunIec('FT 1.2 balanced, GI of 86', Bd, 1, True);
    RunIcs('ICSlink RD, 32 numbers', Bd);
  end;
end.
