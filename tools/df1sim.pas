{ df1sim - a DF1 slave that behaves like an Allen-Bradley SLC 5/0x, on a
  serial port or on a pseudo terminal it creates itself. Built on the
  library: tChnDF1 (NAM=DF1) over tChnCom (NAM=COM), the link dialogue of
  unit ChnDF1Link and the data table / command handler of unit ChnSlc.
  See docs/df1sim.md.

    df1sim [options] [parameter string]
      --pty             create a pty pair; the first line on standard output
                        is "PTY /dev/pts/N", the device to connect to
      --dev=PATH        serial device (NAM=COM DEV=PATH), default /dev/ttyS0
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
      --count=N         exit after answering N commands
      --timeout=S       exit after S seconds without a message
      --quiet           no per-message log
    A parameter string given instead of the options ('NAM=DF1 MAS=SLAVE
    ... NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E') is used as it is.

  SIGINT and SIGTERM end it cleanly: the port is closed (a pty it created
  disappears), nothing else is touched. Exit code 0, 1 on a setup error. }
program df1sim;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix, ChnPty,{$ENDIF}
  SysUtils, Classes, uString, ChnTypes, ChnVirt, ChnCom, ChnTcp, ChnTrc, ChnDF1,
  ChnSlc, ChnDF1Link;

const
  LingerMs = 1000;   { after the last counted command: time for the master's ACK }

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

procedure Die(const Why: string);
begin
  WriteLn(StdErr, 'df1sim: ', Why);
  Halt(1);
end;

function NumArg(const Name, Value: string; Min, Max: LongInt): LongInt;
begin
  Result := 0;
  if not StrToNum(Value, Min, Max, Result) then
    Die(Format('%s wants a number %d..%d', [Name, Min, Max]));
end;

function LoadFile(const Name: string): AnsiString;
var
  S: TFileStream;
begin
  Result := '';
  try
    S := TFileStream.Create(Name, fmOpenRead or fmShareDenyNone);
    try
      SetLength(Result, S.Size);
      if S.Size > 0 then
        S.ReadBuffer(Result[1], S.Size);
    finally
      S.Free;
    end;
  except
    on E: Exception do
      Die(Name + ': ' + E.Message);
  end;
end;

var
  Table: tSlcTable;
  Station: tDF1Station;
  Chn: pChnVirt;
  Params, Arg, Key, Value, Dev, Par, ConfigName, Err, Listen: string;
  UsePty, Half, Crc, Dup, LineGiven: Boolean;
  Node, DNo, Bd, Count, TimeoutS, I, ErrLine: LongInt;
  LastMsg, CountReached: QWord;

begin
  Params := '';
  Dev := '/dev/ttyS0';
  Par := 'N';
  ConfigName := '';
  Listen := '';
  UsePty := False;
  LineGiven := False;
  Half := False;
  Crc := True;
  Dup := True;
  Node := 1;
  DNo := 0;
  Bd := 19200;
  Count := 0;
  TimeoutS := 0;
  I := 1;
  while I <= ParamCount do
  begin
    Arg := ParamStr(I);
    Inc(I);
    if Copy(Arg, 1, 2) <> '--' then
    begin
      Params := Trim(Params + ' ' + Arg);
      Continue;
    end;
    Key := Arg;
    Value := '';
    if Pos('=', Arg) > 0 then
    begin
      Key := Copy(Arg, 1, Pos('=', Arg) - 1);
      Value := Copy(Arg, Pos('=', Arg) + 1, MaxInt);
    end
    else if ((Key = '--count') or (Key = '--timeout') or (Key = '--config') or
             (Key = '--dev') or (Key = '--node') or (Key = '--dno') or
             (Key = '--bd') or (Key = '--par') or (Key = '--dup') or
             (Key = '--listen')) and (I <= ParamCount) then
    begin
      Value := ParamStr(I);         { "--count 3" as well as "--count=3" }
      Inc(I);
    end;
    if Key = '--pty' then UsePty := True
    else if Key = '--half' then Half := True
    else if Key = '--full' then Half := False
    else if Key = '--bcc' then Crc := False
    else if Key = '--crc' then Crc := True
    else if Key = '--quiet' then Quiet := True
    else if Key = '--dup' then
      case ChoiceIndex(Value, 'OFF|ON') of
        0: Dup := False;
        1: Dup := True;
      else
        Die('--dup wants on or off');
      end
    else if Key = '--dev' then Dev := Value
    else if Key = '--listen' then Listen := Value
    else if Key = '--par' then begin Par := Value; LineGiven := True; end
    else if Key = '--bd' then begin Bd := NumArg(Key, Value, 50, 4000000); LineGiven := True; end
    else if Key = '--node' then Node := NumArg(Key, Value, 0, 254)
    else if Key = '--dno' then DNo := NumArg(Key, Value, 0, 254)
    else if Key = '--count' then Count := NumArg(Key, Value, 1, MaxLongInt)
    else if Key = '--timeout' then TimeoutS := NumArg(Key, Value, 1, 86400)
    else if Key = '--config' then ConfigName := Value
    else
      Die('unknown option ' + Arg + ' (see docs/df1sim.md)');
  end;

  if ConfigName = '' then
    SlcLoadDefault(Table)
  else if not SlcLoadConfig(Table, LoadFile(ConfigName), ErrLine, Err) then
    Die(Format('%s line %d: %s', [ConfigName, ErrLine, Err]));

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
    if UsePty and (Listen <> '') then
      Die('--pty or --listen, not both')
    { a pty takes BD=/PAR= as given and reports them (a virtual line) }
    else if UsePty then
      Params := Params + Format(' NAM=COM DRV=PTY BD=%d PAR=%s', [Bd, Par])
    else if Listen <> '' then
      Params := Params + ' NAM=TCP KICK=ON LISTEN=' + Listen
    else
      Params := Params + Format(' NAM=COM DEV=%s BD=%d PAR=%s', [Dev, Bd, Par]);
  end
  else if UsePty and (Pos('DRV=PTY', UpperCase(Params)) = 0) then
    Die('--pty with a parameter string: put NAM=COM DRV=PTY in it')
  else if LineGiven then
    Die('--bd/--par with a parameter string: put BD=/PAR= in its NAM=COM part');

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
  LastMsg := ChMsTick;
  CountReached := 0;
  while not Stop do
  begin
    if DF1StationStep(Station) then
      LastMsg := ChMsTick
    else if Chn^.ChResult <> res_Ok then
    begin
      LogLine('df1sim: line lost: ' + Chn^.ChResultStr(Chn^.ChResult));
      Break;
    end
    else
      Sleep(1);
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
