{ legacy_names - the rest of the legacy contract: identifiers of the seed
  manuals and docs/PROTOCOLS.md section 1 that no other legacy program uses. A layer
  of its own written the SofCon way (object of tChnVirt, ChSetOneParam with
  tWordString/tCmd, a tAddChnVirt manager), the fields every manual's Init
  sets, the checksum types, version constants and the protocol fields of
  tChnDF1, tChnFT1_2 and tChnICS. Compiled by tests/run.sh in -Mtp, -Mfpc,
  -Mobjfpc and -Mdelphi; exits 1 on any unexpected result. }
program legacy_names;

uses
  uString, ChnTypes, ChnVirt, ChnLoop, ChnDF1, ChnFT1_2, ChnICS;

const
  cMyName = 'MYL';

type
  pChnMy = ^tChnMy;
  tChnMy = object(tChnVirt)
    CH_Speed: Word;
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
  end;

  pAddChnMy = ^tAddChnMy;
  tAddChnMy = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

var
  Ok: Boolean;

{$I check.inc}

constructor tChnMy.Init;
begin
  inherited Init;
  CH_Type    := cMyName;
  CH_Name    := CH_Type;
  CH_NumName := ChNumName(CH_Type);
  CH_Speed   := 1;
  IData      := 0;
end;

constructor tChnMy.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnMy.Done;
begin
  inherited Done;
end;

function tChnMy.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  N: LongInt;
  Res: tChResult;
begin
  if ParamKey(S) = 'SPD' then
  begin
    N := 0;
    Res := ParamNum(S, 1, 9, N);
    if (Res = res_Ok) and (CmdL = cmd_Set) then
      CH_Speed := N;
  end
  else
    Res := inherited ChSetOneParam(S, CmdL);
  ChSetOneParam := Res;
end;

function tAddChnMy.ChInit: pChnVirt;
begin
  ChInit := New(pChnMy, Init);
end;

var
  Chn: pChnVirt;
  My: pChnMy;
  DF1: pChnDF1;
  FT: pChnFT1_2;
  ICS: pChnICS;
  B: tBcc8;
  C: tCrc16;
  S8: tSum8;
  X: tXor8;
  R: tRec;
  Cmd: tCmd;
  W: tWordString;
  SNode, DNode: tNode;

begin
  ChnCollection^.Insert(New(pAddChnMy, Init(cMyName)));
  Chn := ChnCollection^.ChNewInit(cMyName);
  Check(Chn <> nil, 'own layer registered');
  with Chn^ do
  begin
    Check(CH_Type = cMyName, 'CH_Type');
    Check(CH_Name = cMyName, 'CH_Name');
    Check(CH_NumName = ChNumName('myl'), 'CH_NumName, case-blind');
    Check(CH_NumName <> ChNumName(ChnLoop.cName), 'distinct per name');
    Check(CH_Low = nil, 'CH_Low');
    Check(CH_RCtrl = CHS_RecInactive, 'CH_RCtrl');
    IData := -5;
    Check(IData = -5, 'IData');
    ChSetParam('SPD=7 NAM=LOOP PAIR=LNAMES END=1');
    Check(ChResult = res_Ok, 'own key and a lower layer');
    Check(pChnMy(Chn)^.CH_Speed = 7, 'own key applied');
    Check(CH_Low <> nil, 'lower layer made');
    W := 'SPD=10';
    Cmd := cmd_Check;
    Check(ChSetOneParam(W, Cmd) = res_BadParam, 'ChSetOneParam range');
    Cmd := cmd_Set;
    W := 'XYZ=1';
    Check(ChSetOneParam(W, Cmd) = res_UnknownParam, 'unknown key');
    ChDestNode(3);
    Check(CH_DNode = 3, 'ChDestNode');
    Check(CH_Node = 0, 'CH_Node');
    ChOpen;
    ChConnect;
    Check(ChReady = CHS_Connect, 'connected');
    ChReceiveTick;
    ChReceiveFlush;
    Check(ChReceiveResult = res_Ok, 'flush');
    ChGetNode(SNode, DNode);
  end;
  Dispose(Chn, Done);
  My := New(pChnMy, ChInitParam('SPD=3'));
  Check(My^.CH_Speed = 3, 'ChInitParam of a descendant');
  Dispose(My, Done);

  { checksum types of ChnTypes }
  B := Bcc8Block(W[1], 0);
  C := Crc16Block(W[1], 0, 0);
  S8 := Sum8Block(W[1], 0);
  X := Xor8Block(W[1], 0);
  Check((B = 0) and (C = 0) and (S8 = 0) and (X = 0), 'checksums of nothing');
  Check((SizeOf(tBcc8) = 1) and (SizeOf(tCrc16) = 2) and (SizeOf(tSum8) = 1) and
        (SizeOf(tXor8) = 1), 'checksum type sizes');

  { DF1 (manual ChnDF1): fields of the manual's Init, version, v1.10 name }
  DF1 := New(pChnDF1, Init);
  with DF1^ do
  begin
    Check(not CH_DLE and CH_FlCrc and CH_Master and CH_FullDup, 'DF1 Init');
    Check((CH_RSumBcc = 0) and (CH_SSumCrc = 0), 'DF1 sums');
    Check((CH_SBuff = nil) and (CH_MSBuff = 0) and (CH_LRMess = 0), 'DF1 buffers');
  end;
  Dispose(DF1, Done);
  Check(ChnDF1.res_ErrMessFrame = ChnDF1.res_ErrFrame, 'res_ErrMessFrame');
  Check((ChnDF1.cVerNo > 0) and (ChnDF1.cVer <> ''), 'DF1 version');

  { FT 1.2 (manual ChnFT1_2) }
  FT := New(pChnFT1_2, Init);
  with FT^ do
    Check(CH_MaSl and CH_Master and (CH_LenShortM = 4), 'FT1_2 Init');
  Dispose(FT, Done);
  R := Znk;
  Ok := (R = Znk) and (Ord(NoZnk) = 1) and (Ord(Err) = 2);
  Check(Ok, 'tRec');
  Check((ChnFT1_2.cVerNo > 0) and (ChnFT1_2.cVer <> ''), 'FT1_2 version');

  { ICS (manual ChnICS) }
  ICS := New(pChnICS, Init);
  with ICS^ do
    Check((CH_DataI = 0) and (CH_PomS = '') and CH_Master, 'ICS Init');
  Dispose(ICS, Done);
  Check((ChnICS.cVerNo > 0) and (ChnICS.cVer <> ''), 'ICS version');
  Check((ChnICS.MaxTBuff = 65500) and (ChnICS.OPM_ReadData = 'RD'), 'ICS aliases');

  WriteLn('legacy_names ok');
end.
