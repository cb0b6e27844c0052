{ df1slave - a small DF1 slave: a tDF1Station (unit ChnDF1Link) that
  answers from the default SLC data table of unit ChnSlc (docs/df1sim.md:
  N7:0..9 = 0, 10 .. 90, F8, B3, S2, N9) the commands of manual section
  6.3 - Echo, Diagnostic Status, Read and Reset Diagnostic Counters, the
  protected typed logical read/write with three address fields and the
  unprotected read/write; other commands get STS $10. Full duplex: ACK good
  frames, NAK broken ones, repeat the last ACK/NAK on ENQ. Half duplex:
  ACK, hold the reply for the master's poll, EOT when there is nothing to
  send. tools/df1sim is the same station with options, a configurable
  table and a pty of its own.

    df1slave [-t seconds] [parameter string]
    df1slave -t 30 NAM=DF1 NOD=2 DNO=1 MAS=SLAVE CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  -t ends the program after that many seconds without a message (default:
  run until interrupted). Exit code 0, or 1 on a setup error, printed as
  text. }
program df1slave;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp, ChnTrc, ChnDF1,
  ChnSlc, ChnDF1Link;

const
  DefaultParams = 'NAM=DF1 LSB=500 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON ' +
                  'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Chn: pChnVirt;
  Table: tSlcTable;
  Slave: tDF1Station;
  Params, Err: string;
  I: Integer;
  IdleSec: LongInt;
  LastMsg: QWord;

procedure SlaveLog(const Line: string);
begin
  WriteLn('slave ', Line);
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
  Chn := DF1OpenStack(Params, 3000, Err);
  if Chn = nil then
  begin
    WriteLn('df1slave: ', Err);
    Halt(1);
  end;
  if pChnDF1(Chn)^.CH_Master then
    WriteLn('df1slave: note: MAS=MASTER given; answering anyway');
  WriteLn('df1slave: ', Chn^.ChGetParam(''));
  SlcLoadDefault(Table);
  SlcStationInit(Slave, Chn, @Table);
  Slave.Log := @SlaveLog;
  Slave.LogWire := True;
  LastMsg := ChMsTick;
  repeat
    if DF1StationStep(Slave) then
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
