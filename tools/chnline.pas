{ chnline - a serial line at a real speed between programs on this
  machine: N pseudo terminals joined as a null modem (two) or an RS-485
  bus (more, or --bus), carrying each character when a line at --bd with
  the character format --bit/--par/--stop would have.

    chnline [--ends=N] [--bus] [--bd=N] [--bit=N] [--par=L] [--stop=N]
            [--link=PREFIX] [--quiet]

  The first line on standard output is "PTY <path 1> ... <path N>": each
  program opens one of them as its serial port (a simulator, a master, a
  concentrator under test). With --link=PREFIX the paths are also linked
  as PREFIX1 ... PREFIXN (removed at the end).

  The line is unit ChnLoop's (NAM=LOOP PAIR= END= BD=): what one pty's
  program writes is delivered to every other pty, character by character
  at the line's speed; a program that writes while another one's message
  is on a bus collides with it, and both arrive garbled (docs/ChnLoop.md).
  SIGINT or SIGTERM ends it: each end's bytes, the collisions and the
  garbled characters are printed; exit 0. Exit 1: a pty could not be
  made; 2: a command-line error. docs/chnline.md. }
program chnline;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix, ChnPty,{$ENDIF}
  SysUtils, ChnTypes, ChnVirt, ChnLayers, ChnWait, ChnLoop, ChnCli;

const
  BufSize = 4096;
  MaxQueue = 1024 * 1024;   { bytes waiting for a pty whose program does not read }
  IdleWaitMs = 20;          { a pty without a client is not in the wait: look again then }

type
  tEnd = record
    Pty, Line: pChnVirt;    { the pty's master side; this end of the line }
    Path, Link: AnsiString;
    PtyBuf, LineBuf: array[0..BufSize - 1] of Byte;
    Queue: AnsiString;      { from the line, not yet taken by the pty }
    Sent, Got, Dropped: Int64;
  end;

var
  Cli: tCli;
  Ends: array of tEnd;
  Stop: Boolean = False;
  Quiet: Boolean;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  Stop := True;
end;
{$ENDIF}

function OpenChannel(const Params: string): pChnVirt;
var
  Err: string;
begin
  Err := '';
  Result := ChnCollection^.ChNewInit(Copy(Params, 5, Pos(' ', Params) - 5));
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
  begin
    Result^.ChOpen;
    if Result^.ChResult = res_Ok then
      Result^.ChConnect;
  end;
  if Result^.ChResult <> res_Ok then
  begin
    Err := Result^.ChErrorText;
    Dispose(Result, Done);
    CliFail(Cli, 'cannot open ' + Params + ': ' + Err, '', 1);
  end;
end;

{ What waits for the pty of E, as much as it takes now. }
procedure ToPty(var E: tEnd);
begin
  if (E.Queue = '') or (E.Pty^.ChSendReady <> CHS_SendReady) then
    Exit;
  E.Pty^.ChSend(@E.Queue[1], Length(E.Queue));
  if E.Pty^.ChSendResult = res_Ok then
    E.Queue := '';
end;

{ One pass over every end; True when a byte moved. }
function Step: Boolean;
var
  I: LongInt;
  Len: Word;
  S: AnsiString;
begin
  Result := False;
  for I := 0 to High(Ends) do
    with Ends[I] do
    begin
      if Pty^.ChReceiveReady = CHS_ReceiveReady then
      begin
        Pty^.ChReceive(Len);
        if (Pty^.ChReceiveResult = res_Ok) and (Len > 0) then
        begin
          Line^.ChSend(@PtyBuf, Len);      { at a speed the line queues it }
          Inc(Sent, Len);
          Result := True;
        end;
      end;
      if Line^.ChReceiveReady = CHS_ReceiveReady then
      begin
        Line^.ChReceive(Len);
        if Len > 0 then
        begin
          Inc(Got, Len);
          if Length(Queue) + Len > MaxQueue then
            Inc(Dropped, Len)              { nobody reads this pty }
          else
          begin
            SetString(S, PChar(@LineBuf[0]), Len);
            Queue := Queue + S;
          end;
          Result := True;
        end;
      end;
      ToPty(Ends[I]);
    end;
end;

var
  N, I, Bd, Bits, StopBits: LongInt;
  Bus: Boolean;
  Par, LinkPrefix, PairName, LineParams, Paths: string;
  Coll, Garb: LongWord;

begin
  CliInit(Cli, 'chnline', '[OPTION]...',
    'A serial line at a real speed between programs on this machine: N pseudo ' +
    'terminals joined as a null modem (two) or an RS-485 bus (more, or --bus), ' +
    'each character delivered when a line at that speed and character format ' +
    'would have; on a bus two programs writing at once collide and both arrive ' +
    'garbled.');
  CliOption(Cli, 'ends', 'n', 'N', 'number of ptys, 2..32 (default 2)');
  CliOption(Cli, 'bus', #0, '', 'half duplex (RS-485) also with two ends: writes that overlap collide');
  CliOption(Cli, 'bd', #0, 'N', 'baud rate, 50..4000000 (default 9600); 0: no speed');
  CliOption(Cli, 'bit', #0, 'N', 'data bits, 5..8 (default 8)');
  CliOption(Cli, 'par', #0, 'N|E|O|M|S', 'parity (default N)');
  CliOption(Cli, 'stop', #0, '1|2', 'stop bits (default 1)');
  CliOption(Cli, 'link', #0, 'PREFIX', 'also link the ptys as PREFIX1 ... PREFIXN (removed at the end)');
  CliOption(Cli, 'quiet', 'q', '', 'no summary at the end');
  CliEpilog(Cli, 'The first line on standard output is "PTY <path 1> ... <path N>".' + LineEnding +
    'Examples:' + LineEnding +
    '  chnline --bd=9600 --par=E                 a null modem at 9600 8E1' + LineEnding +
    '  chnline --ends=5 --bd=19200 --link=/tmp/rs485-   a bus of five' + LineEnding);
  CliExit(Cli, 0, 'ended by a signal');
  CliExit(Cli, 1, 'a pty could not be made');
  CliParse(Cli);
  if CliArgCount(Cli) > 0 then
    CliUsageError(Cli, 'no arguments besides options', CliRest(Cli, 0));
  N := CliNum(Cli, 'ends', 2, LoopMaxEnds, 2);
  Bus := CliHas(Cli, 'bus');
  Bd := CliNum(Cli, 'bd', 0, 4000000, 9600);
  if (Bd > 0) and (Bd < 50) then
    CliUsageError(Cli, 'baud rate 0 or 50..4000000', '--bd ' + IntToStr(Bd));
  Bits := CliNum(Cli, 'bit', 5, 8, 8);
  Par := 'NEOMS'[CliChoice(Cli, 'par', 'N|E|O|M|S', 0) + 1];
  StopBits := CliNum(Cli, 'stop', 1, 2, 1);
  Quiet := CliHas(Cli, 'quiet');
  LinkPrefix := CliValue(Cli, 'link', '');

  PairName := 'CHNLINE' + IntToStr(GetProcessID);
  LineParams := Format(' BD=%d BIT=%d PAR=%s STOP=%d LRB=65536 IDL=0', [Bd, Bits, Par, StopBits]);
  if Bus then
    LineParams := LineParams + ' BUS=ON';
  SetLength(Ends, N);
  Paths := '';
  for I := 0 to N - 1 do
    with Ends[I] do
    begin
      Pty := OpenChannel('NAM=COM DRV=PTY IDL=0 LRB=65536');
      {$IFDEF UNIX}
      Path := PtyLastSlave;
      {$ENDIF}
      Pty^.ChReceiveBuffer(@PtyBuf, BufSize);
      Line := OpenChannel(Format('NAM=LOOP PAIR=%s END=%d', [PairName, I + 1]) + LineParams);
      Line^.ChReceiveBuffer(@LineBuf, BufSize);
      Paths := Paths + ' ' + Path;
      if LinkPrefix <> '' then
      begin
        Link := LinkPrefix + IntToStr(I + 1);
        {$IFDEF UNIX}
        FpUnlink(Link);
        if FpSymlink(PChar(Path), PChar(Link)) <> 0 then
          CliFail(Cli, 'cannot link ' + Link + ': ' + SysErrorMessage(fpgeterrno), '--link', 1);
        {$ENDIF}
      end;
    end;
  WriteLn('PTY', Paths);
  Flush(Output);
  {$IFDEF UNIX}
  FpSignal(SIGINT, @OnSignal);
  FpSignal(SIGTERM, @OnSignal);
  {$ENDIF}

  while not Stop do
    if not Step then
      ChnWaitAny(IdleWaitMs);

  if not Quiet then
  begin
    for I := 0 to N - 1 do
      with Ends[I] do
        WriteLn(Format('end %d %s: %d bytes sent, %d received, %d dropped (not read)',
          [I + 1, Path, Sent, Got, Dropped]));
    LoopLineStats(PairName, Coll, Garb);
    WriteLn(Format('line: %d collisions, %d characters garbled', [Coll, Garb]));
  end;
  for I := 0 to N - 1 do
    with Ends[I] do
    begin
      {$IFDEF UNIX}
      if Link <> '' then
        FpUnlink(Link);
      {$ENDIF}
      Dispose(Line, Done);
      Dispose(Pty, Done);
    end;
end.
