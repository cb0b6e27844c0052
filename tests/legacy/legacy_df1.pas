{ legacy_df1 - the example of the SofCon ChnDF1 manual, section 7, as a
  legacy program: compiled by tests/run.sh in -Mtp, -Mfpc, -Mobjfpc and
  -Mdelphi. Corrected per docs/PROTOCOLS.md section 7 (space before NAM=, Data[0..3],
  "not (...)", reply length 8+4 since replies carry no FNC). NAM=LOOP
  replaces NAM=COM and a second DF1 stack in this program plays the SLC.
  Also checks the record layout and the constants legacy code uses.
  Exits 1 on any mismatch. }
program legacy_df1;

uses
  ChnLoop,    { the in-memory line this test runs on, then ... }
  uString,    { ... the manual's uses clause, unchanged }
  ChnVirt,
  ChnCom,
  ChnDF1;

const
  ParamStr : tParamStr =
             'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON ' +
             'NAM=LOOP PAIR=LEGDF1 END=1';
  SlaveStr : tParamStr =
             'NAM=DF1 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON ' +
             'NAM=LOOP PAIR=LEGDF1 END=2';

var
  Chn   : pChnVirt;
  Sl    : pChnVirt;
  SMess : pMaSendRecord;
  RMess : pMaRecRecord;
  SlRec : tSlRecRecord;
  SlSnd : tSlSendRecord;
  Rec   : tSendRecord;
  LSMess: word;
  LRMess: word;
  SlLen : word;
  SNode, DNode: tNode;
  Tries : LongInt;

{$I check.inc}

function Offset(P: Pointer): LongInt;
begin
  Offset := PtrUInt(P) - PtrUInt(@Rec);
end;

{ the SLC: ACK a command and send the echo reply }
procedure SlaveTick;
begin
  if Sl^.ChReceiveReady = CHS_ReceiveReady then
  begin
    Sl^.ChReceive(SlLen);
    Check(Sl^.ChReceiveResult = res_Ok, 'slave receive');
    if SlRec.MessType = tpDataMess then
    begin
      SlSnd.MessType := tpAckNak;
      SlSnd.FlAck := true;
      Sl^.ChSend(@SlSnd, 2);
      Check(Sl^.ChSendResult = res_Ok, 'slave ACK');
      SlSnd := SlRec;
      SlSnd.CF := SlRec.CF or MskCF_Reply;
      Sl^.ChSend(@SlSnd, SlLen);
      Check(Sl^.ChSendResult = res_Ok, 'slave reply');
    end;
  end;
end;

procedure WaitMess;
begin
  Tries := 0;
  while not (Chn^.ChReceiveReady = CHS_ReceiveReady) do
  begin
    SlaveTick;
    if Chn^.ChReceiveResult <> res_Ok then WriteLn('Chyba');
    Inc(Tries);
    Check(Tries < 100000, 'no answer');
  end;
end;

begin
  { layout of manual 4.3 }
  Check(SizeOf(tSendRecord) = 252, 'SizeOf(tSendRecord)');
  Check(SizeOf(tRecRecord) = 252, 'SizeOf(tRecRecord)');
  Check(SizeOf(tMessType) = 1, 'SizeOf(tMessType)');
  Check(Offset(@Rec.MessType) = 0, 'MessType@0');
  Check(Offset(@Rec.FlAck) = 1, 'FlAck@1');
  Check(Offset(@Rec.Dummy1_1) = 1, 'Dummy1_1@1');
  Check(Offset(@Rec.CF) = 2, 'CF@2');
  Check(Offset(@Rec.Sts) = 4, 'Sts@4');
  Check(Offset(@Rec.Dummy1_2) = 5, 'Dummy1_2@5');
  Check(Offset(@Rec.Tns) = 6, 'Tns@6');
  Check(Offset(@Rec.Data) = 8, 'Data@8');
  Check(Offset(@Rec.Data[MaxDataLen - 1]) = 251, 'Data[243]@251');
  { constants }
  Check(MaxDataLen = 244, 'MaxDataLen');
  Check(MaxTBuff = 65500, 'MaxTBuff');
  Check((res_ErrFrame = $20) and (res_ErrSum = $21) and (res_ErrLen = $22), 'res_Err*');
  Check((SOH = 1) and (STX = 2) and (ETX = 3) and (EOT = 4) and (ENQ = 5) and
        (ACK = 6) and (DLE = $10), 'control characters');
  Check(NAK = $15, 'NAK is $15 on the wire');
  Check((cSizeHeadMaSndMsg = 8) and (cSizeHeadSlSndMsg = 8), 'header sizes');
  Check(CF_ProtectRead3Addr = $0FA2, 'CF_ProtectRead3Addr');
  Check(CF_ProtectWrite3Addr = $0FAA, 'CF_ProtectWrite3Addr');
  Check(MaskCmd = $0F00, 'MaskCmd');
  Check(Ord(tpDataMess) = 4, 'tpDataMess');
  Check(cName = 'DF1', 'cName');

  New(SMess);
  New(RMess);
  { the SLC }
  Sl := ChnCollection^.ChNewInit(ChnDF1.cName);
  Sl^.ChSetParam(SlaveStr);
  Check(Sl^.ChResult = res_Ok, 'slave ChSetParam');
  Sl^.ChOpen;
  Sl^.ChReceiveBuffer(@SlRec, SizeOf(SlRec));
  Sl^.ChConnect;
  Check(Sl^.ChReady = CHS_Connect, 'slave connect');

  { vytvoreni instance Chn }
  Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  with Chn^ do
  begin
    { nastaveni parametru komunikace }
    ChSetParam(ParamStr);
    if ChResult <> res_Ok then WriteLn('Chyba');
    Check(ChResult = res_Ok, 'ChSetParam');
    ChOpen;
    repeat
      if ChResult <> res_Ok then WriteLn('Chyba');
      Check(ChResult = res_Ok, 'ChOpen');
    until ChReady = CHS_Open;
    { definovani mista, kam se ma prijata zprava ulozit }
    ChReceiveBuffer(RMess, SizeOf(RMess^));
    if ChReceiveResult <> res_Ok then WriteLn('Chyba');
    ChConnect;
    repeat
      if ChResult <> res_Ok then WriteLn('Chyba');
      Check(ChResult = res_Ok, 'ChConnect');
    until ChReady = CHS_Connect;
    { naplneni zpravy daty }
    with SMess^ do
    begin
      MessType := tpDataMess;
      CF       := CF_Echo;
      Sts      := 0;
      Tns      := 0;
      Data[0]  := Ord('A');
      Data[1]  := Ord('h');
      Data[2]  := Ord('o');
      Data[3]  := Ord('j');
      LSMess   := 8 + 4;
    end;
    { vyslani zpravy }
    Check(ChSendReady = CHS_SendReady, 'ChSendReady');
    if ChSendReady = CHS_SendReady then
    begin
      ChSend(SMess, LSMess);
      { cekani na odvysilani zpravy }
      repeat
        if ChSendResult <> res_Ok then WriteLn('Chyba');
        Check(ChSendResult = res_Ok, 'ChSend');
      until ChSendReady = CHS_SendReady;
    end;
    { cekani na prijem zpravy }
    WaitMess;
    { prijem zpravy }
    ChReceive(LRMess);
    Check(ChReceiveResult = res_Ok, 'receive ACK');
    { dekodovani odpovedi ACK }
    with RMess^ do
    begin
      Check((MessType = tpAckNak) and (FlAck = true), 'ACK');
      WaitMess;
      ChReceive(LRMess);
      Check(ChReceiveResult = res_Ok, 'receive reply');
      { dekodovani datove odpovedi na zpravu Echo }
      if (MessType = tpDataMess) and
         (CF = CF_Echo or MskCF_Reply) and
         (Tns = 0) and
         (Sts = 0) and
         (LRMess = 8 + 4) then
        WriteLn('Ok')
      else
        Check(false, 'echo reply');
      Check(Data[3] = Ord('j'), 'reply data');
    end;
    ChGetNode(SNode, DNode);
    Check((SNode = 2) and (DNode = 1), 'ChGetNode');
    { ukonceni }
    ChDisConnect;
    repeat
      if ChResult <> res_Ok then WriteLn('Chyba');
    until ChReady = CHS_DisConnect;
    ChClose;
    repeat
      if ChResult <> res_Ok then WriteLn('Chyba');
    until ChReady = CHS_Close;
  end;
  { zruseni instance Chn }
  Dispose(Chn, Done);
  Dispose(Sl, Done);
  Dispose(SMess);
  Dispose(RMess);
  WriteLn('legacy_df1 ok');
end.
