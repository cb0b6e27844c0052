{ manual_ics - the example program of the SofCon manual "ChnICS" v1.20,
  section 7 ("Příklad"): a request with data and text to a PLC over
  ChnCom, typed in as printed. tests/run.sh builds it in -Mtp -Mfpc
  -Mobjfpc -Mdelphi and runs it against examples/icsslave on a socat
  null-modem (manual_ics.peer); the manual's success output, "Ok data
  přijata v poli Data", is the last line.

  Changed from the printed text, and nothing else:
  - the program line; the parameter string is the manual's, pointed at the
    pty by DEV= (the first argument), in place of the first "...";
  - the other "..." (elided code) are left out;
  - typographic quotes are ': the text ’“Požadavek na čtení dat“’ is
    '''Požadavek na čtení dat''', the text with ' as its delimiters (an
    ICS delimiter is one byte; “ is three in this UTF-8 file, see
    docs/MIGRATING.md on code pages);
  - "while not ChReceiveReady=CHS_ReceiveReady" (compiles, never waits)
    is "while ChReceiveReady<>CHS_ReceiveReady".
  Comments are the manual's, in Czech. }
program manual_ics;

uses
  uString,
  ChnVirt,
  ChnCom,
  ChnICS;

const
  ParamStr : tParamStr =
             'NAM=ICS LSB=500 NOD=1 DNO=2 ' +
             'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 ' +
             'PAR=E LRB=1000';

var
  Chn   : pChnVirt;
  SMess : pSendRecord;
  RMess : pRecRecord;
  LSMess: word;
  LRMess: word;

begin
  ParamStr := ParamStr + ' DEV=' + System.ParamStr(1);
  New(SMess);
  New(RMess);
  { vytvoření instance Chn }
  Chn:=ChnCollection^.ChNewInit(ChnICS.cName);
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
      OpCode  :=OCM_ReadData;
      BlockNum:=0;
      Text    :='''Požadavek na čtení dat''';
      Data[0] :=0;
      Data[1] :=10;
      Data[2] :=15;
      LSMess  :=4+3*SizeOf(tData);
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
      { dekódování správné odpovědi (např. odpověď na ReadData)}
      with RMess^ do
      begin
        if (OpCode = OCS_ReadData) and
           (LRMess = 4+3*SizeOf(tData)) then
          writeln('Ok data přijata v poli Data')
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
