{ df1sim - a DF1 slave that behaves like an Allen-Bradley SLC 5/0x, on a
  serial port or on a pseudo terminal it creates itself. Built on the
  library: tChnDF1 (NAM=DF1) over tChnCom (NAM=COM), the link dialogue of
  unit ChnDF1Link and the data table / command handler of unit ChnSlc.
  See docs/df1sim.md.

    df1sim [options] [parameter string]
      --pty             create a pty pair; the first line on standard output
                        is "PTY /dev/pts/N", the device to connect to
      --dev=PATH        serial device (NAM=COM DEV=PATH); one of --pty,
                        --dev, --listen or a parameter string is needed:
                        df1sim never opens a device nobody named
      --listen=[ADDR:]PORT  serve over TCP instead (NAM=TCP LISTEN=..., raw),
                        one client at a time (a new one takes the line:
                        KICK=ON), on the loopback interface
                        unless ADDR is given; the first line on standard
                        output is "LISTEN <port>" (PORT 0: a free one)
      --bd=N            baud rate (default 19200), --par=N|E|O (default N);
                        with --pty the pty takes them as given
      --half            half duplex (default full duplex)
      --bcc | --crc     checksum (default CRC)
      --dup=on|off      duplicate packet detect (DUP= of NAM=DF1; default on,
                        as a PLC channel: a repeated command is ACKed and
                        answered with the cached reply, not executed again)
      --node=N          station address (default 1); --dno=N peer (default 0)
      --config=FILE     data table (tools/df1sim.conf); default: built in
      --plc5            play a PLC-5: PLC-5 addresses in the data table (octal
                        I/O, D files in BCD) and its commands too (typed
                        read/write 0F 68/67, word range 0F 01/00,
                        read-modify-write 0F 26; unit ChnPlc5Sim)
      --msg-to=N        half duplex: send a message of its own to station N
                        every --msg-every=S seconds (default 5), as an SLC's
                        MSG instruction: a read of --msg-read=ADDR (default
                        N7:0, one element) that goes out at the next poll;
                        the master takes it (N = its address) or routes it
                        to station N, whose answer is logged
      --count=N         exit after answering N commands
      --timeout=S       exit after S seconds without a message
      --quiet           no per-message log
    A parameter string given instead of the options ('NAM=DF1 MAS=SLAVE
    ... NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E') is used as it is.

  SIGINT and SIGTERM end it cleanly: the port is closed (a pty it created
  disappears), nothing else is touched. Every value option takes
  "--opt VALUE" and "--opt=VALUE" (unit ChnCli, docs/TOOLS.md). Exit code
  0 (ended by a signal, --count or --timeout), 1 the port could not be
  opened or was lost, 2 a command-line error (nothing was opened). }
program df1sim;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix, ChnPty,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnOs, ChnVirt, ChnWait, ChnLayers, ChnTcp, ChnDF1,
  ChnSlc, ChnDF1Link, ChnPccc, ChnCli;

const
  LingerMs = 1000;   { after the last counted command: time for the master's ACK }
  { Nothing to answer: wait for the line (ChnWaitAny ends at its first
    byte) at most this long, for this loop's own timers and for a pty
    without a client, which is not in the wait. }
  WaitMs = 10;

var
  Stop: Boolean = False;
  Quiet: Boolean = False;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
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
end;
{$ENDIF}

procedure LogLine(const Line: string);
begin
  if Quiet then
    Exit;
  WriteLn(FormatDateTime('hh:nn:ss.zzz', Now), ' ', Line);
  Flush(Output);
end;

var
  Cli: tCli;

procedure Die(const Why: string);
begin
  WriteLn(StdErr, 'df1sim: ', Why);
  Halt(1);
end;

function LoadFile(const Name: string): AnsiString;
var
  Err: ShortString;
begin
  if not OsFileLoad(Name, Result, Err) then
    CliUsageError(Cli, 'cannot read the data table: ' + Err, '--config ' + Name);
end;

var
  Table: tSlcTable;
  Station: tDF1Station;
  Chn: pChnVirt;
  Params, Dev, Par, ConfigName, Err, Listen: string;
  UsePty, Half, Crc, Dup, LineGiven: Boolean;
  MsgTo, MsgEvery, MsgReplies: LongInt;
  MsgAddr: tPcccAddr;
  MsgReq: tSendRecord;
  MsgLen: Word;
  MsgTns: Word;
  MsgErr: ShortString;
  NextMsg: QWord;
  Node, DNo, Bd, Count, TimeoutS, ErrLine: LongInt;
  LastMsg, CountReached, Started: QWord;

begin
  CliInit(Cli, 'df1sim', '[OPTION]... [PARAMETER-STRING...]',
    'A DF1 slave that behaves like an Allen-Bradley SLC 5/0x, on a serial port ' +
    '(--dev), a pseudo terminal it creates (--pty) or a TCP port (--listen); or on ' +
    'the stack a parameter string gives (NAM=DF1 MAS=SLAVE ... NAM=COM ...), used ' +
    'as it is. One of them is needed: df1sim never opens a device nobody named.');
  CliOption(Cli, 'pty', #0, '', 'create a pty pair; the first line on standard output is ' +
    '"PTY /dev/pts/N", the device to connect to');
  CliOption(Cli, 'dev', #0, 'PATH', 'serial device (NAM=COM DEV=PATH)');
  CliOption(Cli, 'listen', #0, '[ADDR:]PORT', 'serve over TCP (NAM=TCP LISTEN=..., raw), one ' +
    'client at a time, loopback unless ADDR is given; the first line on standard output is ' +
    '"LISTEN <port>" (PORT 0: a free one)');
  CliOption(Cli, 'bd', #0, 'N', 'baud rate (default 19200); a pty takes it as given');
  CliOption(Cli, 'par', #0, 'N|E|O', 'parity (default N)');
  CliOption(Cli, 'half', #0, '', 'half duplex (default full duplex)');
  CliOption(Cli, 'full', #0, '', 'full duplex');
  CliOption(Cli, 'bcc', #0, '', 'BCC checksum (default CRC)');
  CliOption(Cli, 'crc', #0, '', 'CRC-16 checksum');
  CliOption(Cli, 'dup', #0, 'on|off', 'duplicate packet detect (DUP= of NAM=DF1; default on, ' +
    'as a PLC channel)');
  CliOption(Cli, 'node', #0, 'N', 'station address (default 1)');
  CliOption(Cli, 'dno', #0, 'N', 'peer address (default 0)');
  CliOption(Cli, 'config', #0, 'FILE', 'data table (tools/df1sim.conf); default: built in');
  CliOption(Cli, 'plc5', #0, '', 'play a PLC-5: PLC-5 addresses in the data table and its ' +
    'commands (typed read/write, word range read/write, read-modify-write)');
  CliOption(Cli, 'count', #0, 'N', 'exit after answering N commands');
  CliOption(Cli, 'timeout', #0, 'S', 'exit after S seconds without a message');
  CliOption(Cli, 'msg-to', #0, 'N', 'half duplex: send a message of its own (a read, as an ' +
    'SLC MSG instruction) to station N every --msg-every seconds, at the next poll');
  CliOption(Cli, 'msg-every', #0, 'S', 'seconds between two messages of its own (default 5)');
  CliOption(Cli, 'msg-read', #0, 'ADDR', 'what the message reads (default N7:0, one element)');
  CliOption(Cli, 'quiet', 'q', '', 'no per-message log');
  CliEpilog(Cli, 'Examples:' + LineEnding +
    '  df1sim --pty --half --bcc' + LineEnding +
    '  df1sim --dev=/dev/ttyUSB1 --bd=19200' + LineEnding +
    '  df1sim --pty --plc5' + LineEnding +
    '  df1sim NAM=DF1 MAS=SLAVE NOD=1 NAM=TRC FILE=sim.log NAM=COM DRV=PTY' + LineEnding);
  CliExit(Cli, 0, 'ended by a signal, --count or --timeout');
  CliExit(Cli, 1, 'the port could not be opened, or was lost');
  CliParse(Cli);
  UsePty := CliHas(Cli, 'pty');
  Half := CliHas(Cli, 'half') and not CliHas(Cli, 'full');
  Crc := not CliHas(Cli, 'bcc') or CliHas(Cli, 'crc');
  Quiet := CliHas(Cli, 'quiet');
  MsgTo := CliNum(Cli, 'msg-to', 0, 254, -1);
  MsgEvery := CliNum(Cli, 'msg-every', 1, 86400, 5);
  if (MsgTo >= 0) and not CliHas(Cli, 'half') then
    CliUsageError(Cli, '--msg-to needs --half (a full-duplex slave never sends on its own)', '--msg-to');
  MsgErr := '';
  FillChar(MsgAddr, SizeOf(MsgAddr), 0);
  MsgLen := 0;
  if PcccParseAddress(CliValue(Cli, 'msg-read', 'N7:0'), MsgAddr, MsgErr) <> res_Ok then
    CliUsageError(Cli, MsgErr, '--msg-read ' + CliValue(Cli, 'msg-read', 'N7:0'));
  Dup := CliChoice(Cli, 'dup', 'OFF|ON', 1) = 1;
  Dev := CliValue(Cli, 'dev', '');
  Listen := CliValue(Cli, 'listen', '');
  Par := CliValue(Cli, 'par', 'N');
  LineGiven := CliHas(Cli, 'bd') or CliHas(Cli, 'par');
  Bd := CliNum(Cli, 'bd', 50, 4000000, 19200);
  Node := CliNum(Cli, 'node', 0, 254, 1);
  DNo := CliNum(Cli, 'dno', 0, 254, 0);
  Count := CliNum(Cli, 'count', 1, MaxLongInt, 0);
  TimeoutS := CliNum(Cli, 'timeout', 1, 86400, 0);
  ConfigName := CliValue(Cli, 'config', '');
  Params := CliRest(Cli, 0);
  if Ord(UsePty) + Ord(Dev <> '') + Ord(Listen <> '') > 1 then
    CliUsageError(Cli, 'one of --pty, --dev, --listen', CliRest(Cli, 0));
  if (Params = '') and not UsePty and (Dev = '') and (Listen = '') then
    CliUsageError(Cli, 'no line: give --pty, --dev=PATH, --listen=PORT or a parameter string', '');

  if (ConfigName = '') and CliHas(Cli, 'plc5') then
    Plc5LoadDefault(Table)
  else if ConfigName = '' then
    SlcLoadDefault(Table)
  else if CliHas(Cli, 'plc5') and not Plc5LoadConfig(Table, LoadFile(ConfigName), ErrLine, Err) or
    not CliHas(Cli, 'plc5') and not SlcLoadConfig(Table, LoadFile(ConfigName), ErrLine, Err) then
    CliUsageError(Cli, Format('%s line %d: %s', [ConfigName, ErrLine, Err]), '--config ' + ConfigName);

  if Params = '' then
  begin
    Params := Format('NAM=DF1 MAS=SLAVE NOD=%d DNO=%d', [Node, DNo]);
    if Half then
      Params := Params + ' FHD=HALF'
    else
      Params := Params + ' FHD=FULL';
    if Crc then
      Params := Params + ' CRC=ON'
    else
      Params := Params + ' CRC=OFF';
    if Dup then
      Params := Params + ' DUP=ON'
    else
      Params := Params + ' DUP=OFF';
    { a pty takes BD=/PAR= as given and reports them (a virtual line) }
    if UsePty then
      Params := Params + Format(' NAM=COM DRV=PTY BD=%d PAR=%s', [Bd, Par])
    else if Listen <> '' then
      Params := Params + ' NAM=TCP KICK=ON LISTEN=' + Listen
    else
      Params := Params + Format(' NAM=COM DEV=%s BD=%d PAR=%s', [Dev, Bd, Par]);
  end
  else if UsePty and (Pos('DRV=PTY', UpperCase(Params)) = 0) then
    CliUsageError(Cli, '--pty with a parameter string: put NAM=COM DRV=PTY in it', '--pty')
  else if LineGiven then
    CliUsageError(Cli, '--bd/--par with a parameter string: put BD=/PAR= in its NAM=COM part',
      CliValue(Cli, 'bd', CliValue(Cli, 'par', '')))
  else if (Dev <> '') or (Listen <> '') then
    CliUsageError(Cli, '--dev/--listen with a parameter string: put the line in the string',
      CliRest(Cli, 0));
  CliCheckParams(Cli, Params, ChnDF1.cName);

  Chn := DF1OpenStack(Params, 3000, Err);
  if Chn = nil then
    Die(Err);
  {$IFDEF UNIX}
  if UsePty then
    WriteLn('PTY ', PtyLastSlave);
  {$ENDIF}
  if Listen <> '' then
    WriteLn('LISTEN ', pChnTcp(Chn^.CH_Low)^.ChLocalPort);
  Flush(Output);
  {$IFDEF UNIX}
  CatchSignals;
  {$ENDIF}
  LogLine('df1sim: ' + Chn^.ChGetParam(''));

  SlcStationInit(Station, Chn, @Table);
  Station.Log := @LogLine;
  MsgTns := Random(65536);
  MsgReplies := 0;
  NextMsg := ChMsTick + QWord(MsgEvery) * 1000;
  LastMsg := ChMsTick;
  Started := LastMsg;
  CountReached := 0;
  while not Stop do
  begin
    { S:4, the free-running clock, as of now for the command about to be answered }
    SlcClock(Table, ChMsTick - Started);
    if (MsgTo >= 0) and (ChMsTick >= NextMsg) then
    begin
      NextMsg := ChMsTick + QWord(MsgEvery) * 1000;
      Inc(MsgTns);
      if (PcccBuildRead(MsgAddr, PcccElemSize(MsgAddr.FileType), MsgTns, MsgReq, MsgLen) = res_Ok) and
        (DF1StationQueue(Station, MsgTo, MsgReq, MsgLen) = res_Ok) then
        LogLine(Format('df1sim: MSG to %d: read %s, TNS=%d (at the next poll)',
          [MsgTo, PcccAddressText(MsgAddr), MsgTns]));
    end;
    if Station.OwnReplies > MsgReplies then
    begin
      MsgReplies := Station.OwnReplies;
      LogLine(Format('df1sim: MSG reply from %d: %s', [Station.LastReplySrc,
        DF1Describe(Station.LastReply, Station.LastReplyLen)]));
    end;
    if DF1StationStep(Station) then
      LastMsg := ChMsTick
    else if Chn^.ChResult <> res_Ok then
    begin
      WriteLn(StdErr, 'df1sim: line lost: ', Chn^.ChResultStr(Chn^.ChResult));
      Dispose(Chn, Done);
      Halt(1);
    end
    else
      ChnWaitAny(WaitMs);
    if (TimeoutS > 0) and (ChMsTick - LastMsg > QWord(TimeoutS) * 1000) then
    begin
      LogLine(Format('df1sim: %d s without a message, done', [TimeoutS]));
      Break;
    end;
    if (Count > 0) and (Station.Requests >= Count) then
    begin
      { wait for the ACK of the last reply, at most LingerMs }
      if CountReached = 0 then
        CountReached := ChMsTick;
      if not Station.HasReply or (ChMsTick - CountReached > LingerMs) then
      begin
        LogLine(Format('df1sim: %d commands answered, done', [Station.Requests]));
        Break;
      end;
    end;
  end;
  if Stop then
    LogLine('df1sim: signal, closing');
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
