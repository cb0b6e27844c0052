{ manual_df1 - the example program of the SofCon manual "ChnDF1" v1.20,
  section 7 ("Příklad"): an Echo to an Allen-Bradley SLC over ChnCom,
  typed in as printed. tests/run.sh builds it in -Mtp -Mfpc -Mobjfpc
  -Mdelphi and runs it against tools/df1sim on a socat null-modem
  (manual_df1.peer); the manual's success output is the last line, "Ok".

  Changed from the printed text, and nothing else:
  - the program line; the parameter string is the manual's, pointed at the
    pty by DEV= (the first argument), in place of the first "...";
  - the other "..." (elided code) are left out;
  - 'CRC=ON' + 'NAM=COM' gets its separating space;
  - Data[0] assigned four times becomes Data[0..3];
  - typographic quotes are ';
  - "while not ChReceiveReady=CHS_ReceiveReady" (compiles, never waits)
    is "while ChReceiveReady<>CHS_ReceiveReady";
  - LRMess = 8+5 is 8+4: a reply carries no FNC, so the echo of 4 bytes
    is 8+4 long (docs/ChnDF1.md).
  Comments are the manual's, in Czech. }
program manual_df1;

uses
  uString,
  ChnVirt,
  ChnCom,
  ChnDF1;

const
  ParamStr : tParamStr =
             'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON ' +
             'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 ' +
             'PAR=E LRB=1000';
var
  Chn   : pChnVirt;
  SMess : pMaSendRecord;
  RMess : pMaRecRecord;
  LSMess: word;
  LRMess: word;

begin
  ParamStr := ParamStr + ' DEV=' + System.ParamStr(1);
  New(SMess);
  New(RMess);
  { vytvoření instance Chn }
  Chn:=ChnCollection^.ChNewInit(ChnDF1.cName);
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
    { naplnění zprávy daty (např. zpráva Connect)}
    with SMess^ do
    begin
      MessType:=tpDataMess;
      CF      :=CF_Echo;
      Sts     :=0;
      Tns     :=0;
      Data[0] :=Ord('A');
      Data[1] :=Ord('h');
      Data[2] :=Ord('o');
      Data[3] :=Ord('j');
      LSMess:=8+4;
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
      { dekódování odpovědi ACK }
      with RMess^ do
      begin
        if (MessType = tpAckNak) and
           (FlAck    = true    ) then
        begin
          { čekání na příjem zprávy }
          while ChReceiveReady<>CHS_ReceiveReady do
          begin
            if ChReceiveResult<>res_Ok then WriteLn('Chyba');
          end;
          { příjem zprávy }
          ChReceive(LRMess);
          if ChReceiveResult<>res_Ok then WriteLn('Chyba')
          else
            { dekódování datové odpovědi na zprávu Echo }
            if (MessType = tpDataMess) and
               (CF = CF_Echo or MskCF_Reply) and
               (Tns = 0) and
               (Sts = 0) and
               (LRMess = 8+4) then
              writeln('Ok')
            else
              writeln('Chyba');
        end
        else
          writeln('Chyba');
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
