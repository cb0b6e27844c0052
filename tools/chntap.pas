{ chntap - a software Y-cable between two serial devices: every byte that
  arrives on one side is passed on to the other as it arrives, each frame
  is printed decoded, live, with its time and direction, and the traffic
  can be written as a pcap file and/or a text trace.

    chntap [protocol] [--pcap=FILE] [--trace=FILE] [--quiet] 'A' 'B'
      A, B      parameter strings of the two sides, e.g.
                'NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E'
      protocol  --df1 [--crc|--bcc] [--half [--master=A|B]]  (default; without
                --crc or --bcc the check is found from the first frames,
                and the choice printed)
                --ft12 [--adr=0..2] [--len=N] [--cot-size=1|2] [--ca-size=1|2] [--ioa-size=1..3]
                --ics
                --raw     decode nothing, only forward (and trace)
      --pcap=FILE   pcap of link type 250 (NAM=TRC MOD=PCAP)
      --trace=FILE  the trace layer's text log
      --quiet       no line per frame, only the summary at the end
    "--pcap FILE" and "--trace FILE" work too.

  Directions: tx is A to B, rx is B to A, in the printout ("A>B", "B>A"),
  the pcap and the trace alike, as if the trace was written by a program
  at A. The pcap and the trace are trace layers (NAM=TRC) on B's stack, so
  they record what is handed to B and what B sends.

  Either side going away (a USB adapter pulled, the program on a pty
  gone) is reported; that side is closed and opened again every second
  until it is back, with the same parameters, while the other side stays
  open with its settings; bytes that arrive meanwhile for the missing side
  are counted as dropped. SIGINT or SIGTERM ends the tap: both sides are
  closed, the files completed, the summary printed; exit code 0. Exit code
  1: a side that cannot be opened at the start; 2: a command-line error
  (unit ChnCli, docs/TOOLS.md; both strings are checked before either side
  is opened).

  The loop polls A then B; on a COM layer a poll that finds nothing waits
  up to IDL= ms (default 1), and that wait (unit ChnWait) ends at input on
  either device, so a byte is taken in the next pass: docs/chntap.md has
  the measured latency (make bench, benchtap). }
program chntap;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, uString, ChnTypes, ChnVirt, ChnLayers, ChnCom, ChnTrc,
  ChnTrcFormat, ChnFrameDecode, ChnCli;

const
  BufSize   = 65535;
  TapLrb    = ' LRB=1048576';  { see LastLayerIsCom }
  MaxQueue  = 4 * 1024 * 1024;   { bytes waiting for a slow side, at most }
  RetryMs   = 1000;
  SideName: array[0..1] of string = ('A', 'B');
  DirName: array[0..1] of string = ('A>B', 'B>A');

type
  tSide = record
    Params : ShortString;
    Chn    : pChnVirt;
    Open   : Boolean;
    RetryAt: QWord;
    Buf    : array[0..BufSize - 1] of Byte;
    Queue  : AnsiString;        { bytes from the other side not yet sent here }
    RxBytes: Int64;             { bytes that came from this side }
    Dropped: Int64;             { bytes for this side lost while it was away }
    Frames, Errors: Int64;      { decoded frames that came from this side }
  end;

var
  Cli: tCli;
  Sides: array[0..1] of tSide;
  Stop: Boolean = False;
  Quiet: Boolean = False;
  Raw: Boolean = False;
  Dec: tDecoder;
  { DF1 without --crc/--bcc: a BCC decoder beside Dec (CRC) until the
    first frame tells them apart }
  Guessing: Boolean = False;
  DecBcc: tDecoder;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  Stop := True;
end;
{$ENDIF}

procedure Usage(const Why: string);
begin
  CliUsageError(Cli, Why, '');
end;

procedure Say(const S: string);
begin
  WriteLn(TrcTimeText(TrcMsOfDay), ' ', S);
  Flush(Output);
end;

{ The first NAM= of a parameter string: the top layer to create. }
function TopLayer(const P: ShortString): ShortString;
var
  Pos: LongInt;
  Tok, Key, Value: ShortString;
begin
  Result := '';
  Pos := 1;
  Tok := '';
  Key := '';
  Value := '';
  if NextToken(P, Pos, Tok) and SplitKeyValue(Tok, Key, Value) and (UpStr(Key) = 'NAM') then
    Result := Value;
end;

{ A tap must not lose bytes while it forwards the other way: a COM side
  whose string sets no LRB= gets a 1 MiB receive ring (default 4096) -
  appended to the string, so when COM is its last layer. }
function WithTapLrb(const P: ShortString): ShortString;
var
  Pos: LongInt;
  Tok, Key, Value, Last: ShortString;
  HasLrb: Boolean;
begin
  Result := P;
  Pos := 1;
  Tok := '';
  Key := '';
  Value := '';
  Last := '';
  HasLrb := False;
  while NextToken(P, Pos, Tok) do
    if SplitKeyValue(Tok, Key, Value) then
    begin
      if UpStr(Key) = 'NAM' then
        Last := UpStr(Value)
      else if UpStr(Key) = 'LRB' then
        HasLrb := True;
    end;
  if (Last = ChnCom.cName) and not HasLrb and (Length(P) + Length(TapLrb) <= 255) then
    Result := P + TapLrb;
end;

function OpenSide(var S: tSide; Quietly: Boolean): Boolean;
var
  R: tChResult;
begin
  Result := False;
  if S.Chn = nil then
  begin
    S.Chn := ChnCollection^.ChNewInit(TopLayer(S.Params));
    if S.Chn = nil then
    begin
      WriteLn(StdErr, 'chntap: ', S.Params, ': no layer NAM=', TopLayer(S.Params));
      Exit;
    end;
    S.Chn^.ChSetParam(S.Params);
    if S.Chn^.ChResult <> res_Ok then
    begin
      WriteLn(StdErr, 'chntap: ', S.Params, ': ', S.Chn^.ChErrorText);
      Exit;
    end;
  end;
  S.Chn^.ChOpen;
  R := S.Chn^.ChResult;
  if R = res_Ok then
  begin
    S.Chn^.ChReceiveBuffer(@S.Buf, BufSize);
    S.Chn^.ChConnect;
    R := S.Chn^.ChResult;
  end;
  if R <> res_Ok then
  begin
    if not Quietly then
      WriteLn(StdErr, 'chntap: ', S.Params, ': ', S.Chn^.ChResultStr(R));
    S.Chn^.ChClose;
    Exit;
  end;
  S.Open := True;
  Result := True;
end;

procedure LoseSide(I: Integer; R: tChResult);
begin
  Say(Format('%s: %s (%s); closed, opened again every %d ms; %s keeps its settings',
    [SideName[I], Sides[I].Chn^.ChResultStr(R), Sides[I].Params, RetryMs, SideName[1 - I]]));
  Sides[I].Chn^.ChClose;
  Sides[I].Open := False;
  Sides[I].Queue := '';
  Sides[I].RetryAt := GetTickCount64 + RetryMs;
end;

{ Decode a chunk that came from side I and print its frames. }
procedure Decode(I: Integer; Len: Word);
var
  F: tTrcFrame;
  K: LongInt;
  E: ^tDecEvent;
begin
  if Raw then
    Exit;
  FillChar(F, SizeOf(F) - SizeOf(F.Data), 0);
  F.Line := 0;
  F.TimeMs := TrcMsOfDay;
  if I = 0 then
    F.Dir := trcTx
  else
    F.Dir := trcRx;
  F.DirText := DirName[I];
  F.Len := Len;
  F.Status := res_Ok;
  SetLength(F.Data, Len);
  Move(Sides[I].Buf, F.Data[0], Len);
  DecodeChunk(Dec, F);
  if Guessing then
  begin
    DecodeChunk(DecBcc, F);
    if (Dec.Stats.Errors <> DecBcc.Stats.Errors) or (Dec.Stats.Frames <> DecBcc.Stats.Frames) then
    begin
      Guessing := False;
      if not DecodeBetterCheck(Dec.Stats, DecBcc.Stats) then
      begin
        Dec := DecBcc;                 { its events of this chunk are printed below }
        Say('DF1 check: BCC, found from the first frames (--crc or --bcc sets it)');
      end
      else
        Say('DF1 check: CRC, found from the first frames (--crc or --bcc sets it)');
    end
    else
      DecBcc.EventCount := 0;
  end;
  for K := 0 to Dec.EventCount - 1 do
  begin
    E := @Dec.Events[K];
    if E^.IsError then
      Inc(Sides[I].Errors)
    else
      Inc(Sides[I].Frames);
    if not Quiet then
      WriteLn(TrcTimeText(E^.TimeMs), ' ', DirName[I], ' ', E^.Proto, ' ', E^.Text);
  end;
  if (Dec.EventCount > 0) and not Quiet then
    Flush(Output);
  Dec.EventCount := 0;
end;

{ Hand what waits for side I down, as much as it takes now. }
procedure SendQueued(I: Integer);
var
  N: LongInt;
begin
  with Sides[I] do
  begin
    if (not Open) or (Queue = '') then
      Exit;
    if Chn^.ChSendReady <> CHS_SendReady then
      Exit;
    N := Length(Queue);
    if N > 65535 then
      N := 65535;
    Chn^.ChSend(@Queue[1], N);
    case Chn^.ChSendResult of
      res_Ok: Delete(Queue, 1, N);
      res_Busy: ;
    else
      LoseSide(I, Chn^.ChSendResult);
    end;
  end;
end;

procedure Poll(I: Integer);
var
  Len: Word;
  St: tChState;
  R: tChResult;
  O: Integer;
begin
  O := 1 - I;
  with Sides[I] do
  begin
    if not Open then
    begin
      if GetTickCount64 >= RetryAt then
      begin
        if OpenSide(Sides[I], True) then
          Say(Format('%s: open again (%s)', [SideName[I], Params]))
        else
          RetryAt := GetTickCount64 + RetryMs;
      end;
      Exit;
    end;
    St := Chn^.ChReceiveReady;
    R := Chn^.ChResult;
    if (R = res_DeviceLost) or (R = res_IOError) then
    begin
      LoseSide(I, R);
      Exit;
    end;
    if St <> CHS_ReceiveReady then
      Exit;
    Len := 0;
    Chn^.ChReceive(Len);
    R := Chn^.ChReceiveResult;
    if Len > 0 then
    begin
      Inc(RxBytes, Len);
      if not Sides[O].Open then
        Inc(Sides[O].Dropped, Len)
      else if Length(Sides[O].Queue) + Len > MaxQueue then
      begin
        Inc(Sides[O].Dropped, Len);
        Say(Format('%s: %d bytes waiting, %d more dropped', [SideName[O],
          Length(Sides[O].Queue), Len]));
      end
      else
      begin
        SetLength(Sides[O].Queue, Length(Sides[O].Queue) + Len);
        Move(Buf, Sides[O].Queue[Length(Sides[O].Queue) - Len + 1], Len);
        SendQueued(O);          { at once: the point of a tap is no delay }
      end;
      Decode(I, Len);
    end;
    if R = res_Overrun then
      Say(Format('%s: receive overrun, bytes were lost (%s)', [SideName[I],
        Chn^.ChResultStr(R)]))
    else if (R = res_DeviceLost) or (R = res_IOError) then
      LoseSide(I, R);
  end;
end;

var
  Opt: tDecOptions;
  Stats: tDecStats;
  PcapFile, TraceFile, Prefix: string;
  Err: AnsiString;
  I: Integer;
  Full: AnsiString;
begin
  CliInit(Cli, 'chntap', '[OPTION]... SIDE-A SIDE-B',
    'A software Y-cable between two serial devices: every byte that arrives on one ' +
    'side is passed on to the other as it arrives, each frame is printed decoded ' +
    'with its time and direction (A>B, B>A), and the traffic can be written as a ' +
    'pcap file and/or a text trace. SIDE-A and SIDE-B are parameter strings ' +
    '(NAM=COM DEV=/dev/ttyUSB0 BD=19200 ...). A side that goes away is reported and ' +
    'opened again every second; SIGINT or SIGTERM ends the tap.');
  CliOption(Cli, 'df1', #0, '', 'DF1 (default)');
  CliOption(Cli, 'crc', #0, '', 'DF1 with CRC-16 (default: found from the first frames)');
  CliOption(Cli, 'bcc', #0, '', 'DF1 with BCC');
  CliOption(Cli, 'half', #0, '', 'DF1 half duplex');
  CliOption(Cli, 'master', #0, 'A|B', 'DF1 half duplex: the side of the master');
  CliOption(Cli, 'ft12', #0, '', 'FT 1.2 (IEC 60870-5-2)');
  CliOption(Cli, 'adr', #0, '0..2', 'FT 1.2 link address octets (default 1)');
  CliOption(Cli, 'len', #0, 'N', 'FT 1.2 data octets of a fixed frame');
  CliOption(Cli, 'cot-size', #0, '1|2', 'FT 1.2 ASDU: cause of transmission octets (default 2)');
  CliOption(Cli, 'ca-size', #0, '1|2', 'FT 1.2 ASDU: common address octets (default 2)');
  CliOption(Cli, 'ioa-size', #0, '1..3', 'FT 1.2 ASDU: information object address octets (default 3)');
  CliOption(Cli, 'ics', #0, '', 'DACS ICSlink');
  CliOption(Cli, 'raw', #0, '', 'decode nothing, only forward (and trace)');
  CliOption(Cli, 'pcap', #0, 'FILE', 'write a pcap of link type 250 (NAM=TRC MOD=PCAP)');
  CliOption(Cli, 'trace', #0, 'FILE', 'write the trace layer''s text log');
  CliOption(Cli, 'quiet', 'q', '', 'no line per frame, only the summary at the end');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  chntap --df1 --pcap=line.pcap ''NAM=COM DEV=/dev/ttyUSB0 BD=19200'' ''NAM=COM DEV=/dev/ttyUSB1 BD=19200''' +
    LineEnding);
  CliExit(Cli, 0, 'ended by SIGINT or SIGTERM');
  CliExit(Cli, 1, 'a side could not be opened at the start');
  CliParse(Cli);
  DecodeDefaults(Opt);
  for I := 0 to High(DecodeOptionNames) do
    if CliHas(Cli, DecodeOptionNames[I]) then
      if DecodeOption('--' + DecodeOptionNames[I], CliValue(Cli, DecodeOptionNames[I], ''), Opt, Err) and
         (Err <> '') then
        CliUsageError(Cli, Err, CliValue(Cli, DecodeOptionNames[I], ''));
  case CliChoice(Cli, 'master', 'A|B', 0) of
    0: Opt.MasterDir := trcTx;
    1: Opt.MasterDir := trcRx;
  end;
  Raw := CliHas(Cli, 'raw');
  Quiet := CliHas(Cli, 'quiet');
  PcapFile := CliValue(Cli, 'pcap', '');
  TraceFile := CliValue(Cli, 'trace', '');
  if CliHas(Cli, 'pcap') and ((PcapFile = '') or (Pos(' ', PcapFile) > 0)) then
    CliUsageError(Cli, '--pcap wants a file name without blanks', PcapFile);
  if CliHas(Cli, 'trace') and ((TraceFile = '') or (Pos(' ', TraceFile) > 0)) then
    CliUsageError(Cli, '--trace wants a file name without blanks', TraceFile);
  if CliArgCount(Cli) > 2 then
    CliUsageError(Cli, 'more than two sides', Cli.Args[2]);
  if CliArgCount(Cli) < 2 then
    Usage('two parameter strings needed, side A and side B');
  for I := 0 to 1 do
  begin
    if Length(Cli.Args[I]) > 255 then
      CliUsageError(Cli, 'parameter string longer than 255 characters', Copy(Cli.Args[I], 1, 40) + '...');
    Sides[I].Params := Cli.Args[I];
  end;
  { the files are trace layers on top of B's stack }
  Prefix := '';
  if PcapFile <> '' then
    Prefix := Prefix + 'NAM=TRC FILE=' + PcapFile + ' MOD=PCAP ';
  if TraceFile <> '' then
    Prefix := Prefix + 'NAM=TRC FILE=' + TraceFile + ' ';
  Full := Prefix + Sides[1].Params;
  if Length(Full) > 255 then
    Usage('side B with the trace layers is longer than 255 characters');
  Sides[1].Params := Full;
  for I := 0 to 1 do
  begin
    Sides[I].Params := WithTapLrb(Sides[I].Params);
    Sides[I].Chn := nil;
    Sides[I].Open := False;
    Sides[I].Queue := '';
    Sides[I].RxBytes := 0;
    Sides[I].Dropped := 0;
    Sides[I].Frames := 0;
    Sides[I].Errors := 0;
  end;
  { both strings whole before anything is opened }
  for I := 0 to 1 do
    Sides[I].Chn := CliChannel(Cli, Sides[I].Params, '');
  if not OpenSide(Sides[0], False) or not OpenSide(Sides[1], False) then
  begin
    for I := 0 to 1 do
      if Sides[I].Chn <> nil then
        Dispose(Sides[I].Chn, Done);
    Halt(1);
  end;
  {$IFDEF UNIX}
  FpSignal(SIGINT, @OnSignal);
  FpSignal(SIGTERM, @OnSignal);
  {$ENDIF}
  Guessing := (Opt.Proto = dpDF1) and not CliHas(Cli, 'crc') and not CliHas(Cli, 'bcc') and not Raw;
  Opt.Crc := Opt.Crc or Guessing;
  DecodeBegin(Dec, Opt, nil);
  Dec.KeepEvents := True;
  if Guessing then
  begin
    Opt.Crc := False;
    DecodeBegin(DecBcc, Opt, nil);
    DecBcc.KeepEvents := True;
  end;
  Say('A: ' + Sides[0].Chn^.ChGetParam(''));
  Say('B: ' + Sides[1].Chn^.ChGetParam(''));
  while not Stop do
  begin
    Poll(0);
    SendQueued(0);
    Poll(1);
    SendQueued(1);
    { a side that is not a polled device with IDL= would spin: rest a bit
      when both are closed }
    if not Sides[0].Open and not Sides[1].Open then
      Sleep(10);
  end;
  for I := 0 to 1 do
    Dispose(Sides[I].Chn, Done);
  DecodeEnd(Dec, Stats);
  for I := 0 to 1 do
    Say(Format('%s: %d bytes, %d frames, %d errors; %d bytes for %s dropped',
      [DirName[I], Sides[I].RxBytes, Sides[I].Frames, Sides[I].Errors,
       Sides[1 - I].Dropped, SideName[1 - I]]));
end.
