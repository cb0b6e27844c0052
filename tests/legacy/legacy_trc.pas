{ legacy_trc - a SofCon-style program with the trace layer (NAM=TRC)
  between the application and the line, compiled by tests/run.sh in -Mtp,
  -Mfpc, -Mobjfpc and -Mdelphi. The trace goes to standard error (the
  default), which run.sh keeps in the .run file beside the program.
  Exits 1 on any unexpected result. }
program legacy_trc;

uses
  uString,
  ChnTypes,
  ChnVirt,
  ChnLoop,
  ChnTrc;

const
  ParamA: tParamStr = 'NAM=TRC MOD=HEX NAM=LOOP PAIR=LTRC END=1';
  ParamB: tParamStr = 'NAM=LOOP PAIR=LTRC END=2';

var
  ChA, ChB: pChnVirt;
  SMess, RMessA, RMessB: array[0..15] of Byte;
  LRMess: Word;
  I: Integer;
  Tries: LongInt;

{$I check.inc}

begin
  ChA := ChnCollection^.ChNewInit(ChnTrc.cName);
  ChB := ChnCollection^.ChNewInit(ChnLoop.cName);
  Check(ChA <> nil, 'TRC is registered');
  with ChA^ do
  begin
    ChSetParam(ParamA);
    Check(ChResult = res_Ok, 'ChSetParam A');
    Check(ChGetParam('') = 'NAM=TRC FILE=STDERR MOD=HEX NAM=LOOP PAIR=LTRC END=1 LRB=4096 IDL=0',
      'ChGetParam A');
    ChReceiveBuffer(@RMessA, SizeOf(RMessA));
    ChOpen;
    repeat
      Check(ChResult = res_Ok, 'ChOpen A');
    until ChReady = CHS_Open;
    ChConnect;
    Check(ChReady = CHS_Connect, 'ChConnect A');
  end;
  with ChB^ do
  begin
    ChSetParam(ParamB);
    ChOpen;
    ChReceiveBuffer(@RMessB, SizeOf(RMessB));
    ChConnect;
    Check(ChResult = res_Ok, 'B connected');
  end;
  { A -> B through the trace layer }
  for I := 0 to 15 do
    SMess[I] := I * 3;
  if ChA^.ChSendReady = CHS_SendReady then
    ChA^.ChSend(@SMess, 16);
  Check(ChA^.ChSendResult = res_Ok, 'send A');
  Tries := 0;
  while not (ChB^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(Tries);
    Check(Tries < 100000, 'nothing received on B');
  end;
  ChB^.ChReceive(LRMess);
  Check((ChB^.ChReceiveResult = res_Ok) and (LRMess = 16), 'B receives 16 bytes');
  for I := 0 to 15 do
    Check(RMessB[I] = I * 3, 'bytes on B');
  { B -> A: the caller's buffer gets the bytes straight from below }
  SMess[0] := $10;
  SMess[1] := $06;
  ChB^.ChSend(@SMess, 2);
  Tries := 0;
  while not (ChA^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(Tries);
    Check(Tries < 100000, 'nothing received on A');
  end;
  ChA^.ChReceive(LRMess);
  Check((ChA^.ChReceiveResult = res_Ok) and (LRMess = 2), 'A receives 2 bytes');
  Check((RMessA[0] = $10) and (RMessA[1] = $06), 'bytes on A');
  ChA^.ChClose;
  Check(ChA^.ChReady = CHS_Close, 'close A');
  Dispose(ChA, Done);
  Dispose(ChB, Done);
  WriteLn('legacy_trc ok');
end.
