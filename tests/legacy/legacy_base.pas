{ legacy_base - a SofCon-style program on the foundation units, compiled
  by tests/run.sh in -Mtp, -Mfpc, -Mobjfpc and -Mdelphi. It must compile
  unchanged in every mode and exits 1 on any unexpected result. }
program legacy_base;

uses
  uString,
  ChnTypes,
  ChnVirt,
  ChnLoop;

const
  ParamA: tParamStr = 'NAM=LOOP PAIR=LEG END=1';
  ParamB: tParamStr = 'NAM=LOOP PAIR=LEG END=2';

var
  ChA, ChB: pChnVirt;
  SBuf, RBuf: array[0..15] of Byte;
  LRMess: Word;
  SNode, DNode: tNode;
  I: Integer;
  Tries: LongInt;

{$I check.inc}

begin
  Check(SizeOf(tNode) = 2, 'SizeOf(tNode)');
  Check(SizeOf(tParamStr) = 256, 'SizeOf(tParamStr)');
  Check(ChnCollection^.ChNewInit('NOSUCH') = nil, 'unknown name gives nil');
  ChA := ChnCollection^.ChNewInit(ChnLoop.cName);
  ChB := ChnCollection^.ChNewInit(ChnLoop.cName);
  with ChA^ do
  begin
    ChSetParam(ParamA);
    Check(ChResult = res_Ok, 'ChSetParam A');
    ChOpen;
    repeat
      Check(ChResult = res_Ok, 'ChOpen A');
    until ChReady = CHS_Open;
    ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    ChConnect;
    Check(ChReady = CHS_Connect, 'ChConnect A');
  end;
  with ChB^ do
  begin
    ChSetParam(ParamB);
    ChOpen;
    ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    ChConnect;
    Check(ChResult = res_Ok, 'B connected');
  end;
  for I := 0 to 15 do
    SBuf[I] := I * 3;
  if ChA^.ChSendReady = CHS_SendReady then
    ChA^.ChSend(@SBuf, 16);
  Check(ChA^.ChSendResult = res_Ok, 'send');
  Tries := 0;
  while not (ChB^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(Tries);
    Check(Tries < 100000, 'nothing received');
  end;
  ChB^.ChReceive(LRMess);
  Check((ChB^.ChReceiveResult = res_Ok) and (LRMess = 16), 'receive 16 bytes');
  for I := 0 to 15 do
    Check(RBuf[I] = I * 3, 'byte content');
  ChB^.ChGetNode(SNode, DNode);
  Check(ChResultText(res_Ok) = 'ok', 'result text');
  ChA^.ChDisConnect;
  Check(ChA^.ChReady = CHS_DisConnect, 'disconnect');
  ChA^.ChClose;
  Check(ChA^.ChReady = CHS_Close, 'close');
  ChA^.ChClose;
  Check(ChA^.ChResult = res_WrongState, 'close twice gives res_WrongState');
  Dispose(ChA, Done);
  Dispose(ChB, Done);
  WriteLn('legacy_base ok');
end.
