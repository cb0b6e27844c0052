program readn7;  { N7:0 of an SLC 500 / MicroLogix: readn7 /dev/ttyUSB0 }
{ The README's program with the tools' command line (unit ChnCli,
  docs/TOOLS.md): "readn7 --help" prints the usage, no argument or an
  option it does not know is a usage error (exit 2), and nothing is opened
  before that - the README's version would open DEV=--help. }
{$MODE OBJFPC}{$H+}
uses ChnLayers, ChnDF1, ChnPcccClient, ChnCli;
var
  Cli: tCli;
  C: tPcccClient;
  V: array[0..0] of LongInt;
  R: LongInt;
begin
  CliInit(Cli, 'readn7', 'DEVICE', 'Read N7:0 of an SLC 500 / MicroLogix (DF1 full ' +
    'duplex, CRC, station 1, 19200 baud) on the serial DEVICE and print it.');
  CliEpilog(Cli, 'Example:' + LineEnding + '  readn7 /dev/ttyUSB0' + LineEnding);
  CliExit(Cli, 0, 'N7:0 was read and printed');
  CliExit(Cli, 1, 'the device could not be opened, or was lost');
  CliExit(Cli, 3, 'an error reply or a reply that does not fit');
  CliExit(Cli, 4, 'no answer in time');
  CliParse(Cli);
  if CliArgCount(Cli) <> 1 then
    CliUsageError(Cli, 'one DEVICE wanted', CliRest(Cli, 0));
  CliCheckParams(Cli, 'NAM=DF1 NOD=0 DNO=1 NAM=COM BD=19200 DEV=' + Cli.Args[0], 'DF1');
  if PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 NAM=COM BD=19200 DEV=' + Cli.Args[0]) <> 0 then
  begin
    WriteLn(StdErr, 'readn7: ', C.Err);
    ExitCode := 1;
  end
  else
  begin
    R := PcccReadInts(C, 'N7:0', 1, V);
    if R = 0 then
      WriteLn('N7:0 = ', V[0])
    else
    begin
      WriteLn(StdErr, 'readn7: ', C.Err);
      ExitCode := CliExitOf(R);
    end;
  end;
  PcccClose(C);
end.
