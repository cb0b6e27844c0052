{ chngate - a gateway: DF1 PLCs (SLC 500, MicroLogix, df1sim) and IEC
  60870-5-101 RTUs (iec101slave) south, an MQTT broker and an IEC 104
  server north, from one configuration file (docs/chngate.md).

    chngate CONFIG            run until SIGINT or SIGTERM; SIGHUP reads
                              CONFIG again (the north connections stay)
    chngate --check CONFIG    check CONFIG and exit

  Every tag is polled by the tag engine (ChnPcccTags: few merged reads,
  scan classes, changes only, demotion of a dead PLC) and published on
  PREFIX/DEVICE/TAG as a JSON object (value, quality, ts),
  retained; PREFIX/DEVICE/$health holds the device's state and counters;
  PREFIX/DEVICE/TAG/set writes a writable tag; PREFIX/$gateway/status is
  online, or offline (the broker's last will when the gateway vanished).
  With [iec104], every tag is a point of an IEC 60870-5-104 server
  (interrogation, spontaneous events with CP56 time, commands confirmed
  when the PLC confirmed the write). One thread: every line, the
  broker's socket and the IEC 104 connections in one ChnWaitAny. }
program chngate;

{$MODE OBJFPC}{$H+}

uses
  { cmem: the C library's allocator, which libmosquitto uses already. It
    reuses freed memory better than Free Pascal's own heap, and the gateway
    runs for months: its heap is about a quarter smaller (docs/chngate.md,
    "Speed and size"). Test builds (CHN_HEAPTRC) keep Free Pascal's heap,
    which heaptrc watches for leaks. }
  {$IFDEF UNIX}{$IFNDEF CHN_HEAPTRC}cmem,{$ENDIF} cthreads, BaseUnix,{$ENDIF}
  SysUtils, ChnWait, ChnLayers, ChnGateway, ChnCli;

var
  Stop: Boolean = False;
  Reload: Boolean = False;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  if Sig = SIGHUP then
    Reload := True
  else
    Stop := True;
end;

procedure CatchSignals;
var
  Act: SigActionRec;
begin
  FillChar(Act, SizeOf(Act), 0);
  Act.sa_handler := SigActionHandler(@OnSignal);
  FpSigAction(SIGINT, @Act, nil);
  FpSigAction(SIGTERM, @Act, nil);
  FpSigAction(SIGHUP, @Act, nil);
end;
{$ENDIF}

procedure LogLine(const Line: AnsiString);
begin
  WriteLn(StdErr, 'chngate: ', Line);
  Flush(StdErr);
end;

var
  Cli: tCli;
  Cfg, NewCfg: tGateConfig;
  G: tGate;
  Errors, Err, Name: AnsiString;

begin
  CliInit(Cli, 'chngate', '[--check] CONFIG',
    'A gateway: reads the tags of DF1 PLCs (SLC 500, MicroLogix, PLC-5, df1sim) with few merged ' +
    'requests and the points of IEC 60870-5-101 RTUs (line = NAM=FT1_2 ..., polled by an IEC 101 ' +
    'master) and publishes their changes to an MQTT broker and serves them to IEC 104 control ' +
    'centres, from one INI configuration ' +
    'file (docs/chngate.md); runs until SIGINT or SIGTERM, SIGHUP reads the configuration again.');
  CliOption(Cli, 'check', #0, '', 'check the configuration, print a summary and exit');
  CliEpilog(Cli, 'Topics:' + LineEnding +
    '  PREFIX/DEVICE/TAG         {"value":...,"quality":"good","ts":"2026-12-04T10:00:00.123Z"} (retained)' + LineEnding +
    '  PREFIX/DEVICE/$health     {"state":"ok","requests":...} (retained)' + LineEnding +
    '  PREFIX/DEVICE/TAG/set     a number, true or false: written to a writable tag' + LineEnding +
    '  PREFIX/$gateway/status    online, or offline (the last will)' + LineEnding +
    '  PREFIX/$gateway/error     a refused command and why' + LineEnding + LineEnding +
    'IEC 104 ([iec104] listen = HOST:PORT): one point per tag item from the device''s ioa =; ' +
    'bits M_SP_NA_1, words M_ME_NB_1, floats M_ME_NC_1, L and bit words M_BO_NA_1 (events with ' +
    'CP56 time); a set point to a writable tag is confirmed when the PLC confirmed the write. ' +
    'An RTU''s points at its ioa = + their IOA, with the RTU''s types, quality (IV while the RTU is ' +
    'dead) and time tags (a CP24 one completed to the hour nearest its arrival); a command, a select ' +
    'and its qualifier go to the RTU as sent, confirmed when the RTU confirmed. --check refuses an ' +
    'RTU''s configured point on another device''s IOA; a point learned at run time on a taken IOA ' +
    'is refused then (log and PREFIX/$gateway/error).' +
    LineEnding + LineEnding +
    'Example:' + LineEnding + '  chngate --check /etc/chngate.conf' + LineEnding);
  CliExit(Cli, 0, 'ended by SIGINT or SIGTERM, or --check found the configuration good');
  CliExit(Cli, 1, 'libmosquitto is missing, or the IEC 104 port cannot be taken');
  CliExit(Cli, 2, 'a command-line error, or the configuration is bad (FILE:LINE: [section] key: why); ' +
    'nothing was opened');
  CliParse(Cli);
  if CliArgCount(Cli) <> 1 then
    CliUsageError(Cli, 'one configuration file', CliRest(Cli, 0));
  Name := Cli.Args[0];
  if not GateLoadConfig(Name, Cfg, Errors) then
  begin
    Write(StdErr, Errors);
    CliEnd(CliExitUsage);
  end;
  if CliHas(Cli, 'check') then
  begin
    WriteLn(Name, ': good: ', GateSummary(Cfg));
    CliEnd(0);
  end;
  {$IFDEF UNIX}
  CatchSignals;
  {$ENDIF}
  G.Log := @LogLine;
  if not GateStart(G, Cfg, Err) then
  begin
    LogLine(Err);
    CliEnd(1);
  end;
  if Cfg.Mqtt then
    LogLine(Format('%s: %s; MQTT %s:%d, prefix %s', [Name, GateSummary(Cfg), Cfg.Host, Cfg.Port, Cfg.Prefix]))
  else
    LogLine(Format('%s: %s', [Name, GateSummary(Cfg)]));
  if Cfg.Iec104.Present then
    LogLine(Format('IEC 104 server on %s, CA %d', [Cfg.Iec104.Listen, Cfg.Iec104.Ca]));
  while not Stop do
  begin
    ChnWaitAny(GateStep(G));
    if Reload then
    begin
      Reload := False;
      if GateLoadConfig(Name, NewCfg, Errors) then
      begin
        GateReload(G, NewCfg);
        LogLine('SIGHUP: ' + Name + ' read again: ' + GateSummary(NewCfg));
      end
      else
        LogLine('SIGHUP: ' + Name + ' is bad, the running configuration stays:' + LineEnding + Errors);
    end;
  end;
  LogLine('signal: stopping');
  GateStop(G, 2000);
end.
