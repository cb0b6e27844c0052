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

    df1slave [-t SECONDS] PARAMETER-STRING...
    df1slave -t 30 NAM=DF1 NOD=2 DNO=1 MAS=SLAVE CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  -t (--timeout) ends the program after that many seconds without a
  message (default: run until interrupted). Without arguments it prints
  its usage and opens nothing. The command line is unit ChnCli's; --help
  lists the exit codes (docs/TOOLS.md). }
program df1slave;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnDF1, ChnSlc, ChnDF1Link, ChnCli;

const
  DefaultParams = 'NAM=DF1 LSB=500 NOD=2 DNO=1 MAS=SLAVE FHD=FULL CRC=ON ' +
                  'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Cli: tCli;
  Chn: pChnVirt;
  Table: tSlcTable;
  Slave: tDF1Station;
  Params, Err: string;
  IdleSec: LongInt;
  LastMsg: QWord;

procedure SlaveLog(const Line: string);
begin
  WriteLn('slave ', Line);
end;

begin
  CliInit(Cli, 'df1slave', '[-t SECONDS] PARAMETER-STRING...',
    'A small DF1 slave (a tDF1Station of ChnDF1Link) answering from the default ' +
    'SLC data table of ChnSlc: Echo, Diagnostic Status, the diagnostic counters, ' +
    'the protected typed logical read/write and the unprotected read/write. ' +
    'All arguments after the options form the parameter string.');
  CliOption(Cli, 'timeout', 't', 'SECONDS', 'end after SECONDS without a message ' +
    '(default: run until interrupted)');
  CliEpilog(Cli, 'Example (the manual''s string):' + LineEnding + '  df1slave -t 30 ' +
    DefaultParams + LineEnding);
  CliExit(Cli, 0, 'ended by --timeout');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliParse(Cli);
  IdleSec := CliNum(Cli, 'timeout', 1, 86400, 0);
  Params := CliRest(Cli, 0);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string', '');
  CliCheckParams(Cli, Params, ChnDF1.cName);
  Chn := DF1OpenStack(Params, 3000, Err);
  if Chn = nil then
  begin
    WriteLn(StdErr, 'df1slave: ', Err);
    Halt(1);
  end;
  if pChnDF1(Chn)^.ChDF1Config.Master then
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
      WriteLn(StdErr, 'df1slave: line lost: ', Chn^.ChResultStr(Chn^.ChResult));
      Dispose(Chn, Done);
      Halt(1);
    end
    else
      ChnWaitAny(20);      { nothing waiting: until the line has something }
  until (IdleSec > 0) and (ChMsTick - LastMsg > QWord(IdleSec) * 1000);
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
