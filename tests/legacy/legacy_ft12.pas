{ legacy_ft12 - the ChnFT1_2 manual's example (chapter 7), corrected per
  docs/PROTOCOLS.md section 7 and run over an in-memory LOOP pair with a slave that
  answers SACK. tests/run.sh compiles it in -Mtp, -Mfpc, -Mobjfpc and
  -Mdelphi; it checks record sizes and offsets itself and exits 1 on any
  mismatch or unexpected result. }
program legacy_ft12;

uses
  ChnLoop,    { the in-memory line this test runs on, then ... }
  uString,    { ... the manual's uses clause, unchanged }
  ChnVirt,
  ChnCom,
  ChnFT1_2;

const
  ParamStr : tParamStr =
             'NAM=FT1_2 MS=ON MAS=MASTER LSB=500 NOD=1 DNO=2 ' +
             'NAM=LOOP PAIR=LEGFT END=1';
  SlaveStr : tParamStr =
             'NAM=FT1_2 MS=ON MAS=SLAVE NOD=2 DNO=1 ' +
             'NAM=LOOP PAIR=LEGFT END=2';

var
  Chn, Sl : pChnVirt;
  SMess : pSendRecord;
  RMess : pRecRecord;
  SlRec : tSlRecRecord;
  SlAns : tSlSendRecord;
  LSMess: word;
  LRMess: word;
  I     : byte;
  SNode, DNode: tNode;
  Tries : LongInt;
  Base  : PtrUInt;

{$I check.inc}

procedure Connect(C: pChnVirt; const P: tParamStr; Buf: Pointer; Size: Word);
begin
  with C^ do
  begin
    ChSetParam(P);
    Check(ChResult = res_Ok, 'ChSetParam');
    ChOpen;
    repeat
      Check(ChResult = res_Ok, 'ChOpen');
    until ChReady = CHS_Open;
    ChReceiveBuffer(Buf, Size);
    Check(ChReceiveResult = res_Ok, 'ChReceiveBuffer');
    ChConnect;
    repeat
      Check(ChResult = res_Ok, 'ChConnect');
    until ChReady = CHS_Connect;
  end;
end;

begin
  { layout of the manual (4.4), packed as in Borland Pascal }
  Check(SizeOf(tSendRecord) = 251, 'SizeOf(tSendRecord)');
  Check(SizeOf(tMaSendRecord) = 251, 'SizeOf(tMaSendRecord)');
  Check(SizeOf(tMaRecRecord) = 251, 'SizeOf(tMaRecRecord)');
  Check(SizeOf(tMessType) = 1, 'SizeOf(tMessType)');
  New(SMess);
  New(RMess);
  Base := PtrUInt(SMess);
  Check(PtrUInt(@SMess^.MessType) - Base = 0, 'MessType@0');
  Check(PtrUInt(@SMess^.FCB_ACD) - Base = 1, 'FCB_ACD@1');
  Check(PtrUInt(@SMess^.FCV_DFC) - Base = 2, 'FCV_DFC@2');
  Check(PtrUInt(@SMess^.FC) - Base = 3, 'FC@3');
  Check(PtrUInt(@SMess^.Data[1]) - Base = 4, 'Data[1]@4');
  Check(cSizeHeadSndMsg = 4, 'cSizeHeadSndMsg');
  Check(cSizeHeadMaSndMsg = cSizeHeadSlSndMsg, 'cSizeHeadMaSndMsg');
  Check((res_ErrSum = $20) and (res_ErrFrame = $23), 'result codes');

  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Sl := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Check((Chn <> nil) and (Sl <> nil), 'ChNewInit');
  Connect(Sl, SlaveStr, @SlRec, SizeOf(SlRec));
  Connect(Chn, ParamStr, RMess, SizeOf(RMess^));
  with Chn^ do
  begin
    { example of filling a message with data }
    with SMess^ do
    begin
      MessType := tpLongM;
      FCB_ACD  := False;
      FCV_DFC  := True;
      FC       := FCM_UserDataReply;
      Data[1]  := $10;
      Data[2]  := $20;
      Data[3]  := $30;
      Data[4]  := $40;
      Data[5]  := $50;
      LSMess := cSizeHeadSndMsg + 5; { 5 is the length of Data }
    end;
    { send the message }
    if ChSendReady = CHS_SendReady then
    begin
      ChSend(SMess, LSMess);
      repeat
        Check(ChSendResult = res_Ok, 'ChSend');
      until ChSendReady = CHS_SendReady;
    end;
  end;

  { the slave takes it and answers SACK }
  Tries := 0;
  while not (Sl^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    Inc(Tries);
    Check(Tries < 100000, 'slave received nothing');
  end;
  Sl^.ChReceive(LRMess);
  Check(Sl^.ChReceiveResult = res_Ok, 'slave ChReceive');
  Check(LRMess = cSizeHeadRecMsg + 5, 'slave LRMess');
  Check((SlRec.MessType = tpLongM) and (SlRec.FC = FCM_UserDataReply), 'slave record');
  Check(SlRec.FCV_DFC and not SlRec.FCB_ACD, 'slave FCB/FCV');
  Check(SlRec.Data[5] = $50, 'slave data');
  Sl^.ChGetNode(SNode, DNode);
  Check((DNode = 2) and (SNode = 1), 'slave ChGetNode');
  SlAns.MessType := tpSACK;
  Sl^.ChSend(@SlAns, 1);
  Check(Sl^.ChSendResult = res_Ok, 'slave ChSend');

  with Chn^ do
  begin
    { wait for the answer (the seed wrote "while not ChReceiveReady = ...") }
    Tries := 0;
    while not (ChReceiveReady = CHS_ReceiveReady) do
    begin
      Check(ChReceiveResult = res_Ok, 'ChReceiveResult while waiting');
      Inc(Tries);
      Check(Tries < 100000, 'master received nothing');
    end;
    ChReceive(LRMess);
    Check(ChReceiveResult = res_Ok, 'master ChReceive');
    Check(LRMess = 1, 'SACK length');
    with RMess^ do
      case MessType of
        tpSACK:
          WriteLn('SACK received');
        tpSNAK:
          Check(False, 'SNAK received');
        tpShortM, tpLongM:
          begin
            for I := 1 to LRMess - cSizeHeadRecMsg do
              Write(Data[I], ' ');
            Check(False, 'data message instead of SACK');
          end;
      else
        Check(False, 'bad MessType');
      end;
    ChDisConnect;
    repeat
      Check(ChResult = res_Ok, 'ChDisConnect');
    until ChReady = CHS_DisConnect;
    ChClose;
    repeat
      Check(ChResult = res_Ok, 'ChClose');
    until ChReady = CHS_Close;
  end;
  Dispose(Chn, Done);
  Dispose(Sl, Done);
  Dispose(SMess);
  Dispose(RMess);
  WriteLn('legacy_ft12 ok');
end.
