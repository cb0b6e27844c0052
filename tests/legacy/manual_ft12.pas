{ manual_ft12 - the example program of the SofCon manual "ChnFT1_2"
  v1.10, chapter 7 ("Příklad"): a master sends a variable-length frame to
  a slave and decodes the answer, over ChnCom, typed in as printed.
  tests/run.sh builds it in -Mtp -Mfpc -Mobjfpc -Mdelphi and runs it
  against examples/ft12slave on a socat null-modem (manual_ft12.peer),
  which answers the test function of link with a single character ACK;
  the manual's output for that, "Přijat SACK", is the last line.

  Changed from the printed text, and nothing else:
  - the program line; the parameter string is the manual's, pointed at the
    pty by DEV= (the first argument), in place of the first "...";
  - the other "..." (elided code) are left out;
  - MASTER=ON is MAS=MASTER (no key MASTER exists);
  - the two Writeln(...) before "for" get their semicolons.
  Comments are the manual's, in Czech. }
program manual_ft12;

uses
  uString,
  ChnVirt,
  ChnCom,
  ChnFT1_2;

const
  ParamStr : tParamStr =
             'NAM=FT1_2 MS=ON MAS=MASTER LSB=500 NOD=1 DNO=2 ' +
             'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 ' +
             'PAR=E LRB=1000';

var
  Chn   : pChnVirt;
  SMess : pSendRecord;
  RMess : pRecRecord;
  LSMess: word;
  LRMess: word;
  I     : byte;

begin
  ParamStr := ParamStr + ' DEV=' + System.ParamStr(1);
  New(SMess);
  New(RMess);
  { vytvoření instance Chn }
  Chn:=ChnCollection^.ChNewInit(ChnFT1_2.cName);
  with Chn^ do
  begin
    { nastavení parametrů komunikace }
    ChSetParam(ParamStr);
    if ChResult<>res_Ok then WriteLn('Chyba');
    ChOpen;
    repeat
      if ChResult<>res_Ok then WriteLn('Chyba');
    until ChReady=CHS_Open;
    if ChResult<>res_Ok then WriteLn('Chyba');
    { definování místa, kam se má přijatá zpráva uložit }
    ChReceiveBuffer(RMess,SizeOf(RMess^));
    if ChReceiveResult<>res_Ok then WriteLn('Chyba');
    ChConnect;
    repeat
      if ChResult<>res_Ok then WriteLn('Chyba');
    until ChReady=CHS_Connect;
    if ChResult<>res_Ok then WriteLn('Chyba');
    { příklad naplnění zprávy daty }
    with SMess^ do
    begin
      MessType := tpLongM;
      FCB_ACD  := False;
      FCV_DFC  := False;
      FC       := FCM_CheckLink;
      Data[1]  := $10;
      Data[2]  := $20;
      Data[3]  := $30;
      Data[4]  := $40;
      Data[5]  := $50;
      LSMess := cSizeHeadSndMsg + 5 {5 je délka pole data};
    end;
    { vyslání zprávy }
    if ChSendReady=CHS_SendReady then
    begin
      ChSend(SMess, LSMess);
      { čekání na odvysílání zprávy }
      repeat
        if ChSendResult<>res_Ok then WriteLn('Chyba');
      until ChSendReady=CHS_SendReady;
      if ChSendResult<>res_Ok then WriteLn('Chyba');
    end;
    { čekání na příjem zprávy }
    while ChReceiveReady<>CHS_ReceiveReady do
    begin
      if ChReceiveResult<>res_Ok then WriteLn('Chyba');
    end;
    { příjem zprávy }
    ChReceive(LRMess);
    if ChReceiveResult<>res_Ok then WriteLn('Chyba')
    else
      { dekódování odpovědi }
      with RMess^ do
      case MessType of
        tpSACK:
          Writeln('Přijat SACK');
        tpSNAK:
          writeln('Přijat SNAK');
        tpShortM:
          begin
            Writeln('Přijata datová zpráva pevné délky');
            for I:=1 to LRMess-cSizeHeadRecMsg do
              Write(Data[I], ' ');
          end;
        tpLongM:
          begin
            Writeln('Přijata datová zpráva proměnné délky');
            for I:=1 to LRMess-cSizeHeadRecMsg do
              Write(Data[I], ' ');
          end;
        else
          Writeln('Chyba');
      end;
    { ukončení }
    ChDisConnect;
    repeat
      if ChResult<>res_Ok then WriteLn('Chyba');
    until ChReady=CHS_DisConnect;
    if ChResult<>res_Ok then WriteLn('Chyba');
    ChClose;
    repeat
      if ChResult<>res_Ok then WriteLn('Chyba');
    until ChReady=CHS_Close;
    if ChResult<>res_Ok then WriteLn('Chyba');
  end;
  { zrušení instance Chn }
  Dispose(Chn,Done);
end.
