{ legacy_tcp - a SofCon-style program whose line moved to the network: the
  same polling code as on NAM=COM, only the parameter string (and the unit
  ChnTcp in the uses clause) differ. A server layer (LISTEN=) and a client
  layer in one program on the loopback interface; compiled by tests/run.sh
  in -Mtp, -Mfpc, -Mobjfpc and -Mdelphi. Exits 1 on any unexpected result. }
program legacy_tcp;

uses
  ChnTypes,
  ChnVirt,
  ChnTcp;

var
  Srv, Cli: pChnVirt;
  RBuf, CBuf: array[0..63] of Byte;
  SBuf: array[0..2] of Byte;
  LRMess: Word;
  Tries: LongInt;
  PortNum: string[7];

{$I check.inc}

begin
  Srv := ChnCollection^.ChNewInit(ChnTcp.cName);
  Check(Srv <> nil, 'TCP registered');
  with Srv^ do
  begin
    ChSetParam('LISTEN=0 LRB=1000');
    Check(ChResult = res_Ok, 'server parameter line');
    ChOpen;
    Check(ChResult = res_Ok, 'listen on a free loopback port');
    ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    ChConnect;
  end;
  Str(pChnTcp(Srv)^.ChLocalPort, PortNum);
  Cli := ChnCollection^.ChNewInit(ChnTcp.cName);
  with Cli^ do
  begin
    ChSetParam('HOST=127.0.0.1 PORT=' + PortNum + ' BD=19200 PAR=E');
    Check(ChResult = res_Ok, 'client parameter line');
    Check(ChGetParam('PORT') = 'PORT=' + PortNum, 'PORT reported');
    ChOpen;
    repeat
      Check(ChResult = res_Ok, 'ChOpen');
    until ChReady = CHS_Open;
    ChReceiveBuffer(@CBuf, SizeOf(CBuf));
    ChConnect;
    Check(ChReady = CHS_Connect, 'ChConnect');
    SBuf[0] := $10; SBuf[1] := $FF; SBuf[2] := $03;
    if ChSendReady = CHS_SendReady then
      ChSend(@SBuf, 3);
    Check(ChSendResult = res_Ok, 'send');
  end;
  Tries := 0;
  while Srv^.ChReceiveReady <> CHS_ReceiveReady do
  begin
    Inc(Tries);
    Check(Tries < 3000, 'server received nothing');
    Cli^.ChSendReady;
  end;
  Srv^.ChReceive(LRMess);
  Check((Srv^.ChReceiveResult = res_Ok) and (LRMess = 3), 'receive 3 bytes');
  Check((RBuf[0] = $10) and (RBuf[1] = $FF) and (RBuf[2] = $03), 'content');
  { the server goes away: the client's next poll says so }
  Srv^.ChClose;
  Tries := 0;
  while Cli^.ChResult = res_Ok do
  begin
    Inc(Tries);
    Check(Tries < 3000, 'lost connection not noticed');
    Cli^.ChReceiveReady;
  end;
  Check(Cli^.ChResult = res_DeviceLost, 'res_DeviceLost');
  Cli^.ChClose;
  Cli^.ChOpen;
  Check(Cli^.ChResult = res_Refused, 'nobody listens: res_Refused');
  Check(Cli^.ChResultStr(Cli^.ChResult) = 'connection refused', 'its text');
  Check(Cli^.ChReady = CHS_Close, 'refused stays closed');
  Dispose(Cli, Done);
  Dispose(Srv, Done);
  WriteLn('legacy_tcp ok');
end.
