{ fpmake.pp - the Chn library as a Free Pascal package, and the one list
  of its units: every unit with the OSes it builds on and the units of
  this package it uses. The Makefile, chn.lpk (tools/mklpk.sh) and make
  install take the list from here (tools/units.sh); tests/packaging.sh
  fails when a unit of src/ is missing here or its dependencies here are
  not those of its uses clauses.

    fpc fpmake.pp && ./fpmake build            # units into units/<cpu>-<os>
    ./fpmake install                           # where fpc finds them
    ./fpmake install --prefix=$HOME/.fppkg     # per user (Debian searches it)

  The units are a folder per part under src/ (src/README.md); each Part
  call below names the folder of the units after it. Per-OS units and
  include files are in a part's unix/ (Unix-likes) and win/ (Windows)
  folders, as in Free Pascal's own packages. ChnPortSynapse needs
  Synapse, which is not part of this package: it is listed as
  "Optional" below and built by "make SYNAPSE_DIR=..." instead. Tools,
  examples and tests are built by the Makefile. }
{$mode objfpc}{$H+}
program fpmake;

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, fpmkunit;

const
  Version = {$I src/core/chnversion.inc};   { the library's version, written once }
  { units of src/ this package does not build (tools/units.sh reads it) }
  Optional = 'ChnPortSynapse.pas';

{ A part of the library: its folder src/<Name> and the per-OS folders in
  it are searched for the units (and include files) listed after it. }
procedure Part(P: TPackage; const Name: string);
begin
  P.SourcePath.Add('src/' + Name);
  P.SourcePath.Add('src/' + Name + '/unix', AllUnixOSes);
  P.SourcePath.Add('src/' + Name + '/win', AllWindowsOSes);
  P.IncludePath.Add('src/' + Name);
  P.IncludePath.Add('src/' + Name + '/unix', AllUnixOSes);
  P.IncludePath.Add('src/' + Name + '/win', AllWindowsOSes);
end;

{ One unit: its file (found in the folder of the current part or its
  folder for this OS), the OSes it builds on, the units of this package it
  uses on every OS. }
function AddUnit(P: TPackage; const FileName: string; OSes: TOSes;
  const Deps: array of string): TTarget;
var
  D: string;
begin
  Result := P.Targets.AddUnit(FileName, OSes);
  Result.Dependencies.AddInclude('chn.inc');
  for D in Deps do
    Result.Dependencies.AddUnit(D);
end;

var
  P: TPackage;
  T: TTarget;
begin
  with Installer do
  begin
    P := AddPackage('chn');
    P.Version := Version;
    P.Description := 'SofCon Chn serial-communication units (DF1, FT 1.2, ICSlink) ' +
      'for Free Pascal: layered channels driven by polling.';
    { as the FPC RTL and packages: COPYING, COPYING.LGPL }
    P.License := 'LGPL-2.1-or-later with the static linking exception (modified LGPL, as the FPC RTL)';
    P.OSes := AllUnixOSes + AllWindowsOSes;
    P.Dependencies.Add('rtl-extra');   { Sockets, WinSock2 (ChnSock) }
    P.Dependencies.Add('rtl-objpas');  { DateUtils (ChnTrc, ChnIecTime) }
    P.IncludePath.Add('src');          { chn.inc }

    { ---- src/core: types, tokens, the layer contract, the wait }
    Part(P, 'core');
    T := AddUnit(P, 'ChnTypes.pas', AllOSes, []);
      T.Dependencies.AddInclude('chnversion.inc');
    AddUnit(P, 'uString.pas', AllOSes, []);
    { the OS's services the portable units ask for (an error code's words,
      COM=N's device, the UTC clock, a log file shared by its writers);
      its OS parts are include files, as ChnWait's }
    T := AddUnit(P, 'ChnOs.pas', AllOSes, ['uString']);
      T.Dependencies.AddUnit('ChnUnix', AllUnixOSes);
      T.Dependencies.AddInclude('chnos.inc', AllUnixOSes);
      T.Dependencies.AddInclude('chnos.inc', AllWindowsOSes);
    AddUnit(P, 'ChnRing.pas', AllOSes, ['ChnWait']);
    { the parameter-string parser }
    AddUnit(P, 'ChnParam.pas', AllOSes, ['ChnTypes', 'uString']);
    { the layer contract and registry; the names legacy programs find in
      it are an include file }
    T := AddUnit(P, 'ChnVirt.pas', AllOSes, ['ChnTypes', 'uString', 'ChnParam', 'ChnWait']);
      T.Dependencies.AddInclude('chnvirtnames.inc');
    { the program-wide wait; its OS parts are include files (in the
      source as unix/chnwait.inc, found here through the OS's include path) }
    T := AddUnit(P, 'ChnWait.pas', AllOSes, []);
      T.Dependencies.AddUnit('ChnUnix', [linux]);
      T.Dependencies.AddInclude('chnwait.inc', AllUnixOSes);
      T.Dependencies.AddInclude('chnwait.inc', AllWindowsOSes);
    { the protocol base }
    AddUnit(P, 'ChnProto.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnWait']);
    { every layer at once, for programs that take any parameter string }
    AddUnit(P, 'ChnLayers.pas', AllOSes, ['ChnCom', 'ChnTcp', 'ChnLoop', 'ChnTrc', 'ChnNoise',
      'ChnDF1', 'ChnFT1_2', 'ChnICS', 'ChnIec104']);

    { ---- src/phys: the physical layers, their port drivers, sockets }
    Part(P, 'phys');
    { what the Unix parts share }
    AddUnit(P, 'ChnUnix.pas', AllUnixOSes, ['ChnTypes']);
    AddUnit(P, 'ChnPort.pas', AllOSes, ['ChnTypes', 'ChnWait', 'ChnOs', 'uString']);
    AddUnit(P, 'ChnPortUnix.pas', AllUnixOSes, ['ChnTypes', 'ChnWait', 'ChnPort', 'ChnUnix']);
    AddUnit(P, 'ChnPty.pas', AllUnixOSes, ['ChnTypes', 'ChnPort', 'ChnPortUnix', 'ChnUnix']);
    AddUnit(P, 'ChnPortWin.pas', AllWindowsOSes, ['ChnTypes', 'ChnWait', 'ChnPort']);
    T := AddUnit(P, 'ChnPorts.pas', AllOSes, []);
      T.Dependencies.AddUnit('ChnPortUnix', AllUnixOSes);
      T.Dependencies.AddUnit('ChnPty', AllUnixOSes);
      T.Dependencies.AddUnit('ChnPortWin', AllWindowsOSes);
    { the physical base: ring, transmit pump, drain, reconnect, wait }
    AddUnit(P, 'ChnPhys.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnRing', 'ChnWait', 'ChnPort',
      'ChnParam', 'uString']);
    AddUnit(P, 'ChnCom.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnPort', 'ChnPhys', 'uString',
      'ChnPorts']);
    AddUnit(P, 'ChnLoop.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnRing', 'ChnWait', 'ChnPort',
      'ChnPhys', 'uString']);
    T := AddUnit(P, 'ChnSock.pas', AllOSes, ['uString']);
      T.Dependencies.AddUnit('ChnUnix', AllUnixOSes);
      T.Dependencies.AddInclude('chnsock.inc', AllUnixOSes);
      T.Dependencies.AddInclude('chnsock.inc', AllWindowsOSes);
    AddUnit(P, 'ChnTelnet.pas', AllOSes, []);
    AddUnit(P, 'ChnPortTcp.pas', AllOSes, ['ChnTypes', 'ChnPort', 'ChnWait', 'ChnSock', 'ChnTelnet']);
    AddUnit(P, 'ChnTcp.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnPort', 'ChnPhys', 'ChnPortTcp',
      'uString', 'ChnRing']);

    { ---- src/trace: middle layers (fault injection, trace, capture files) }
    Part(P, 'trace');
    AddUnit(P, 'ChnNoise.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'uString', 'ChnWait']);
    AddUnit(P, 'ChnTrcFormat.pas', AllOSes, ['ChnTypes', 'uString']);
    AddUnit(P, 'ChnPcap.pas', AllOSes, ['ChnTypes', 'ChnTrcFormat', 'uString']);
    AddUnit(P, 'ChnTrc.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnTrcFormat', 'ChnPcap', 'ChnOs', 'uString']);

    { ---- protocols: per protocol codec, layer, link helpers }
    { src/df1: DF1 and PCCC }
    Part(P, 'df1');
    AddUnit(P, 'ChnDF1Codec.pas', AllOSes, ['ChnTypes']);
    AddUnit(P, 'ChnDF1.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnProto', 'ChnDF1Codec']);
    AddUnit(P, 'ChnPcccNames.pas', AllOSes, []);
    AddUnit(P, 'ChnDF1Link.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnDF1', 'ChnPcccNames', 'uString',
      'ChnWait']);
    AddUnit(P, 'ChnDF1Poll.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnDF1', 'ChnDF1Link', 'ChnWait', 'uString']);
    AddUnit(P, 'ChnPcccAddr.pas', AllOSes, ['ChnTypes', 'uString']);
    AddUnit(P, 'ChnPccc.pas', AllOSes, ['ChnTypes', 'ChnDF1Codec', 'ChnPcccAddr', 'ChnPcccNames']);
    AddUnit(P, 'ChnPlc5.pas', AllOSes, ['ChnTypes', 'ChnDF1Codec', 'ChnPccc']);
    AddUnit(P, 'ChnPcccClient.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnDF1Codec', 'ChnDF1Link', 'ChnDF1Poll',
      'ChnPccc', 'ChnPlc5', 'uString', 'ChnWait']);
    AddUnit(P, 'ChnPcccTags.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnDF1Codec', 'ChnDF1Link',
      'ChnPccc', 'ChnPlc5', 'ChnPcccClient', 'ChnWait', 'ChnRing']);
    { src/iec: FT 1.2 and IEC 60870-5-101 }
    Part(P, 'iec');
    AddUnit(P, 'ChnFT12Codec.pas', AllOSes, ['ChnTypes']);
    AddUnit(P, 'ChnFT1_2.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnProto', 'ChnFT12Codec', 'uString']);
    { the link procedures: what they share, then the primary, the
      secondary and the balanced station }
    AddUnit(P, 'ChnFT12Link.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Codec']);
    AddUnit(P, 'ChnFT12Primary.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Codec', 'ChnWait']);
    AddUnit(P, 'ChnFT12Station.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Codec']);
    AddUnit(P, 'ChnFT12Balanced.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Codec', 'ChnWait']);
    { IEC 60870-5-104: the APCI codec and the layer over NAM=TCP }
    AddUnit(P, 'ChnIec104Codec.pas', AllOSes, ['ChnTypes']);
    AddUnit(P, 'ChnIec104.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnProto', 'ChnIec104Codec',
      'uString', 'ChnTcp', 'ChnTrc']);
    { IEC 60870-5-101 application layer on the FT 1.2 link helpers or IEC 104 }
    { the time tags CP24Time2a/CP56Time2a, then the ASDU codec }
    AddUnit(P, 'ChnIecTime.pas', AllOSes, []);
    AddUnit(P, 'ChnIec101Asdu.pas', AllOSes, ['ChnTypes', 'ChnIecTime']);
    { the IEC 101 information objects as JSON or a readable line, for tools }
    AddUnit(P, 'ChnIec101Print.pas', AllOSes, ['ChnIec101Asdu']);
    AddUnit(P, 'ChnIecTransport.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link', 'ChnFT12Balanced',
      'ChnIec104', 'ChnIec104Codec']);
    { the master: its record, its command, what it receives, its line;
      ChnIec101Master is the program's interface to them }
    AddUnit(P, 'ChnIec101MasterTypes.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT12Codec', 'ChnFT12Link',
      'ChnFT12Primary', 'ChnIec101Asdu', 'ChnIecTransport']);
    AddUnit(P, 'ChnIec101MasterCmd.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnIec101Asdu',
      'ChnIec101MasterTypes']);
    AddUnit(P, 'ChnIec101MasterInbound.pas', AllOSes, ['ChnTypes', 'ChnIec101Asdu',
      'ChnIec101MasterTypes', 'ChnIec101MasterCmd']);
    AddUnit(P, 'ChnIec101MasterPoll.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Primary', 'ChnIecTransport', 'ChnIec101MasterTypes', 'ChnIec101MasterCmd',
      'ChnIec101MasterInbound']);
    AddUnit(P, 'ChnIec101Master.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Primary', 'ChnFT12Codec', 'ChnIec101Asdu', 'ChnWait', 'ChnIecTransport',
      'ChnIec101MasterTypes', 'ChnIec101MasterCmd', 'ChnIec101MasterInbound', 'ChnIec101MasterPoll']);
    { file transfer (types 120..127): codec, controlled and controlling station }
    AddUnit(P, 'ChnIecFile.pas', AllOSes, ['ChnTypes', 'ChnIec101Asdu']);
    AddUnit(P, 'ChnIecFileServer.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnIec101Asdu', 'ChnIecFile', 'ChnOs']);
    AddUnit(P, 'ChnIecFileClient.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT12Codec', 'ChnIec101Asdu', 'ChnIec101Master', 'ChnIecFile']);
    { the slave: its record, its queues, points, interrogations, commands
      and parameters; ChnIec101Slave is the program's interface to them }
    AddUnit(P, 'ChnIec101SlaveTypes.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT12Station',
      'ChnIec101Asdu', 'ChnIecTransport', 'ChnIecFileServer']);
    AddUnit(P, 'ChnIec101SlaveQueue.pas', AllOSes, ['ChnTypes', 'ChnIec101Asdu', 'ChnIec101SlaveTypes',
      'ChnFT12Link', 'ChnIec104Codec']);
    AddUnit(P, 'ChnIecMeasParams.pas', AllOSes, ['ChnIec101Asdu']);
    AddUnit(P, 'ChnIec101SlavePoints.pas', AllOSes, ['ChnTypes', 'ChnIec101Asdu', 'ChnIec101SlaveTypes',
      'ChnIec101SlaveQueue', 'ChnIecMeasParams']);
    AddUnit(P, 'ChnIec101SlaveGi.pas', AllOSes, ['ChnTypes', 'ChnIec101Asdu', 'ChnIec101SlaveTypes',
      'ChnIec101SlaveQueue', 'ChnIec101SlavePoints']);
    AddUnit(P, 'ChnIec101SlaveCommands.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnIec101Asdu',
      'ChnIec101SlaveTypes', 'ChnIec101SlaveQueue', 'ChnIec101SlavePoints']);
    AddUnit(P, 'ChnIec101SlaveParams.pas', AllOSes, ['ChnIec101Asdu', 'ChnIec101SlaveTypes',
      'ChnIec101SlaveQueue', 'ChnIec101SlavePoints', 'ChnIecMeasParams']);
    AddUnit(P, 'ChnIec101Slave.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnFT1_2', 'ChnFT12Link',
      'ChnFT12Station', 'ChnIec101Asdu', 'ChnIecTransport', 'ChnIecFile', 'ChnIecFileServer',
      'ChnIec101SlaveTypes', 'ChnIec101SlaveQueue', 'ChnIec101SlavePoints', 'ChnIec101SlaveGi',
      'ChnIec101SlaveCommands', 'ChnIec101SlaveParams']);
    { the points a master receives: value, quality, time; slave health; commands }
    AddUnit(P, 'ChnIecPointTable.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnWait', 'ChnIec101Asdu',
      'ChnIec101Master', 'ChnRing']);
    { src/ics: ICSlink }
    Part(P, 'ics');
    AddUnit(P, 'ChnICSCodec.pas', AllOSes, ['ChnTypes', 'uString']);
    AddUnit(P, 'ChnICS.pas', AllOSes, ['ChnTypes', 'ChnVirt', 'ChnProto', 'ChnICSCodec']);
    { src/north: what a gateway offers upwards; MQTT loads libmosquitto
      at run time, nothing is linked }
    Part(P, 'north');
    AddUnit(P, 'ChnMqtt.pas', AllOSes, ['ChnWait']);
    AddUnit(P, 'ChnJson.pas', AllOSes, []);
    Run;
  end;
end.
