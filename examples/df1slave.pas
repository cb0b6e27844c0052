{ df1slave - a small DF1 slave: answers Echo, Diagnostic Status, Read and
  Reset Diagnostic Counters and the protected typed logical read/write with
  three address fields (manual section 6.3) from a 256-byte integer file;
  other commands get STS $10. Full duplex: ACK good frames, NAK broken
  ones, repeat the last ACK/NAK on ENQ. Half duplex: ACK, hold the reply
  for the master's poll, EOT when there is nothing to send.

    df1slave [-t seconds] [parameter string]
    df1slave -t 30 NAM=DF1 NOD=2 DNO=1 MAS=SLAVE CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  -t ends the program after that many seconds without a message (default:
  run until interrupted). Exit code 0, or 1 on a setup error, printed as
  text. }
program df1slave;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnDF1;

{$I df1common.inc}

const
  DefaultParams = 'NAM=DF1 LSB=500 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON ' +
                  'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Chn: pChnVirt;
  Slave: tResponder;
  Params: string;
  I: Integer;
  IdleSec: LongInt;
  LastMsg: QWord;

procedure Fail(const What: string; R: tChResult);
begin
  if R = res_Ok then
    R := res_Timeout;          { the state never came }
  Write('df1slave: ', What, ': ', Chn^.ChResultStr(R));
  if Chn^.ChParamError <> '' then
    Write(' (', Chn^.ChParamError, ')');
  WriteLn;
  Dispose(Chn, Done);
  Halt(1);
end;

begin
  Params := '';
  IdleSec := 0;
  I := 1;
  while I <= ParamCount do
  begin
    if ParamStr(I) = '-t' then
    begin
      Inc(I);
      if not StrToNum(ParamStr(I), 1, 86400, IdleSec) then
      begin
        WriteLn('df1slave: -t wants seconds (1..86400)');
        Halt(1);
      end;
    end
    else
      Params := Trim(Params + ' ' + ParamStr(I));
    Inc(I);
  end;
  if Params = '' then
    Params := DefaultParams;
  Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  Chn^.ChSetParam(Params);
  if Chn^.ChResult <> res_Ok then
    Fail('parameters "' + Params + '"', Chn^.ChResult);
  if pChnDF1(Chn)^.CH_Master then
    WriteLn('df1slave: note: MAS=MASTER given; answering anyway');
  Chn^.ChOpen;
  if not WaitState(Chn, CHS_Open) then
    Fail('open', Chn^.ChResult);
  Chn^.ChConnect;
  if not WaitState(Chn, CHS_Connect) then
    Fail('connect', Chn^.ChResult);
  WriteLn('df1slave: ', Chn^.ChGetParam(''));
  ResponderInit(Slave, Chn, 'slave');
  LastMsg := ChMsTick;
  repeat
    if ResponderStep(Slave) then
      LastMsg := ChMsTick
    else if Chn^.ChResult <> res_Ok then
    begin
      WriteLn('df1slave: line lost: ', Chn^.ChResultStr(Chn^.ChResult));
      Break;
    end
    else
      Sleep(1);            { nothing waiting: do not burn the CPU }
  until (IdleSec > 0) and (ChMsTick - LastMsg > QWord(IdleSec) * 1000);
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
