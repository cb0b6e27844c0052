{ legacy_ics - the ChnICS manual's example (section 7), corrected, run
  against a slave on an in-memory loop. tests/run.sh compiles it in -Mtp,
  -Mfpc, -Mobjfpc and -Mdelphi; it checks the record layout and the
  manual's constants itself and exits 1 on any mismatch. }
program legacy_ics;

uses
  ChnLoop,    { the in-memory line this test runs on, then ... }
  uString,    { ... the manual's uses clause, unchanged }
  ChnVirt,
  ChnCom,
  ChnICS;

const
  ParamStr : tParamStr =
             'NAM=ICS LSB=500 NOD=1 DNO=2 ' +
             'NAM=LOOP PAIR=LEGICS END=1';
  SlaveStr : tParamStr =
             'NAM=ICS MAS=SLAVE NOD=2 DNO=1 ' +
             'NAM=LOOP PAIR=LEGICS END=2';

var
  Chn, Sl: pChnVirt;
  SMess : pSendRecord;
  RMess : pRecRecord;
  SlMess: pRecRecord;
  LSMess: word;
  LRMess: word;
  SNode, DNode: tNode;
  Tries : LongInt;
  R     : tSendRecord;

{$I check.inc}

procedure CheckOffset(Field, Rec: Pointer; Expected: LongInt; const What: string);
begin
  Check(LongInt(PtrUInt(Field) - PtrUInt(Rec)) = Expected, What);
end;

begin
  { record layout of the Borland original }
  Check(SizeOf(tData) = 2, 'SizeOf(tData)');
  Check(SizeOf(tSendRecord) = 269, 'SizeOf(tSendRecord)');
  Check(SizeOf(tRecRecord) = 269, 'SizeOf(tRecRecord)');
  CheckOffset(@R.OpCode, @R, 0, 'offset OpCode');
  CheckOffset(@R.BlockNum, @R, 3, 'offset BlockNum');
  CheckOffset(@R.Data, @R, 4, 'offset Data');
  CheckOffset(@R.Text, @R, 68, 'offset Text');
  { constants of manual section 4 }
  Check((MaxDataLen = 32) and (MaxTextLen = 200) and (MaxTBuf = 65500), 'sizes');
  Check((SOH = 1) and (STX = 2) and (ETX = 3) and (EOT = 4), 'control characters');
  Check((res_ErrFrame = $20) and (res_ErrSum = $21) and (res_ErrLen = $22) and
        (res_ErrVal = $23) and (res_ErrETX = $24) and (res_ErrEOT = $25), 'result codes');
  Check((OPM_ReadData = OCM_ReadData) and (OCS_WriteData = 'OK'), 'op codes');
  Check(cName = 'ICS', 'cName');
  { the object's fields keep their size in every mode (a Borland integer) }
  Check(SizeOf(tChnICS(nil^).CH_DataI) = 2, 'SizeOf(CH_DataI)');

  New(SMess);
  New(RMess);
  New(SlMess);

  { the slave, so that the master gets an answer }
  Sl := ChnCollection^.ChNewInit(ChnICS.cName);
  Check(Sl <> nil, 'ChNewInit slave');
  with Sl^ do
  begin
    ChSetParam(SlaveStr);
    Check(ChResult = res_Ok, 'slave ChSetParam');
    ChOpen;
    ChReceiveBuffer(SlMess, SizeOf(SlMess^));
    ChConnect;
    Check(ChReady = CHS_Connect, 'slave connected');
  end;

  { the manual's example from here on }
  Chn := ChnCollection^.ChNewInit(ChnICS.cName);
  with Chn^ do
  begin
    ChSetParam(ParamStr);
    Check(ChResult = res_Ok, 'ChSetParam');
    ChOpen;
    Tries := 0;
    repeat
      Check(ChResult = res_Ok, 'ChOpen');
      Inc(Tries);
      Check(Tries < 100000, 'open never finished');
    until ChReady = CHS_Open;
    ChReceiveBuffer(RMess, SizeOf(RMess^));
    Check(ChReceiveResult = res_Ok, 'ChReceiveBuffer');
    ChConnect;
    Tries := 0;
    repeat
      Check(ChResult = res_Ok, 'ChConnect');
      Inc(Tries);
      Check(Tries < 100000, 'connect never finished');
    until ChReady = CHS_Connect;

    with SMess^ do
    begin
      OpCode  := OCM_ReadData;
      BlockNum:= 0;
      { the manual prints typographic quotes, which are not one identical
        byte on both ends; a plain '"' is }
      Text    := '"Pozadavek na cteni dat"';
      Data[0] := 0;
      Data[1] := 10;
      Data[2] := 15;
      LSMess  := 4+3*SizeOf(tData);
    end;
    if ChSendReady = CHS_SendReady then
    begin
      ChSend(SMess, LSMess);
      Tries := 0;
      repeat
        Check(ChSendResult = res_Ok, 'ChSend');
        Inc(Tries);
        Check(Tries < 100000, 'send never finished');
      until ChSendReady = CHS_SendReady;
    end;
  end;

  { the slave answers ReadData with DB and three numbers }
  Tries := 0;
  while not (Sl^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(Tries);
    Check(Tries < 100000, 'slave received nothing');
  end;
  Sl^.ChReceive(LRMess);
  Check(Sl^.ChReceiveResult = res_Ok, 'slave ChReceive');
  Check((SlMess^.OpCode = OCM_ReadData) and (LRMess = 4+3*SizeOf(tData)), 'request');
  Check(SlMess^.Text = '"Pozadavek na cteni dat"', 'request text');
  Sl^.ChGetNode(SNode, DNode);
  Check((SNode = 1) and (DNode = 2), 'request addresses');
  with SMess^ do
  begin
    OpCode  := OCS_ReadData;
    BlockNum:= SlMess^.BlockNum;
    Text    := '';
    Data[0] := -32768;
    Data[1] := 12345;
    Data[2] := 32767;
  end;
  Sl^.ChSend(SMess, 4+3*SizeOf(tData));
  Check(Sl^.ChSendResult = res_Ok, 'slave ChSend');

  with Chn^ do
  begin
    Tries := 0;
    while not (ChReceiveReady = CHS_ReceiveReady) do
    begin
      Check(ChReceiveResult = res_Ok, 'ChReceiveResult while waiting');
      Inc(Tries);
      Check(Tries < 100000, 'no answer');
    end;
    ChReceive(LRMess);
    Check(ChReceiveResult = res_Ok, 'ChReceive');
    with RMess^ do
      Check((OpCode = OCS_ReadData) and (LRMess = 4+3*SizeOf(tData)) and
            (Data[0] = -32768) and (Data[1] = 12345) and (Data[2] = 32767) and
            (Text = ''), 'answer');
    Check(ChResultStr(res_ErrSum) = 'ICS: checksum error', 'ChResultStr');

    ChDisConnect;
    Check(ChReady = CHS_DisConnect, 'ChDisConnect');
    ChClose;
    Check(ChReady = CHS_Close, 'ChClose');
  end;
  Dispose(Chn, Done);
  Dispose(Sl, Done);
  Dispose(SMess);
  Dispose(RMess);
  Dispose(SlMess);
  WriteLn('legacy_ics ok');
end.
