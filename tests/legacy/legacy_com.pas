{ legacy_com - a SofCon-style program on ChnCom, compiled by tests/run.sh in
  -Mtp, -Mfpc, -Mobjfpc and -Mdelphi. It uses the manuals' parameter line,
  checks the missing-device result, and on Unix runs a polling exchange over
  a pseudo terminal it opens itself. Exits 1 on any unexpected result. }
program legacy_com;

uses
  {$IFDEF UNIX} BaseUnix, {$ENDIF}
  uString,
  ChnTypes,
  ChnVirt,
  ChnCom;

const
  ParamStr1: tParamStr = 'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 ' +
                         'PAR=E LRB=1000';

var
  Chn: pChnVirt;
  RBuf: array[0..63] of Byte;
  SBuf: array[0..2] of Byte;
  LRMess: Word;
  Tries: LongInt;
  {$IFDEF UNIX}
  Master, Unlock, PtyNum, N, R: LongInt;
  Num: string[15];
  PtyPath: string[40];
  Hello: array[0..4] of Char;
  Back: array[0..2] of Byte;
  {$ENDIF}

{$I check.inc}

begin
  Chn := ChnCollection^.ChNewInit(ChnCom.cName);
  Check(Chn <> nil, 'COM registered');
  with Chn^ do
  begin
    ChSetParam(ParamStr1);
    Check(ChResult = res_Ok, 'manual parameter line');
    Check(ChGetParam('BD') = 'BD=9600', 'BD reported');
    Check(ChGetParam('IRQ') = 'IRQ=4', 'IRQ reported');
    ChSetParam('BD=12 ');
    Check(ChResult = res_BadParam, 'BD=12 refused');
    Check(ChGetParam('BD') = 'BD=9600', 'bad BD changed nothing');
    ChSetParam('DEV=/dev/chn-legacy-missing');
    ChOpen;
    Check(ChResult = res_CannotOpen, 'missing device');
    Check(ChReady = CHS_Close, 'missing device stays closed');
  end;
  {$IFDEF UNIX}
  Master := FpOpen('/dev/ptmx', O_RDWR or O_NOCTTY or O_NONBLOCK);
  Check(Master >= 0, 'open /dev/ptmx');
  Unlock := 0;
  PtyNum := 0;
  Check(FpIOCtl(Master, $40045431, @Unlock) = 0, 'unlock pty');
  Check(FpIOCtl(Master, $80045430, @PtyNum) = 0, 'pty number');
  Str(PtyNum, Num);
  PtyPath := '/dev/pts/' + Num;
  with Chn^ do
  begin
    { a pty has 8 data bits and no parity }
    ChSetParam('DEV=' + PtyPath + ' PAR=N');
    Check(ChResult = res_Ok, 'DEV=' + PtyPath);
    ChOpen;
    repeat
      Check(ChResult = res_Ok, 'ChOpen');
    until ChReady = CHS_Open;
    ChReceiveBuffer(@RBuf, SizeOf(RBuf));
    ChConnect;
    Check(ChReady = CHS_Connect, 'ChConnect');
    Hello[0] := 'H'; Hello[1] := 'E'; Hello[2] := 'L'; Hello[3] := 'L'; Hello[4] := 'O';
    Check(FpWrite(Master, Hello, 5) = 5, 'master write');
    Tries := 0;
    while not (ChReceiveReady = CHS_ReceiveReady) do
    begin
      Inc(Tries);
      Check(Tries < 3000, 'nothing received');
    end;
    ChReceive(LRMess);
    Check((ChReceiveResult = res_Ok) and (LRMess = 5), 'receive 5 bytes');
    Check((RBuf[0] = Ord('H')) and (RBuf[4] = Ord('O')), 'content');
    SBuf[0] := 1; SBuf[1] := 2; SBuf[2] := 3;
    if ChSendReady = CHS_SendReady then
      ChSend(@SBuf, 3);
    Check(ChSendResult = res_Ok, 'send');
    Tries := 0;
    N := 0;
    while N < 3 do
    begin
      R := FpRead(Master, Back[N], 3 - N);
      if R > 0 then
        N := N + R;
      Inc(Tries);
      Check(Tries < 3000, 'master got nothing');
      ChSendReady;
      ChReceiveReady;          { waits up to IDL ms: no busy loop }
    end;
    Check((Back[0] = 1) and (Back[2] = 3), 'master content');
    ChDisConnect;
    ChClose;
    Check(ChReady = CHS_Close, 'close');
  end;
  FpClose(Master);
  {$ENDIF}
  Dispose(Chn, Done);
  WriteLn('legacy_com ok');
end.
