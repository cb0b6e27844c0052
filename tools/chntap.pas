{ chntap - a software Y-cable between two serial devices: every byte that
  arrives on one side is passed on to the other as it arrives, each frame
  is printed decoded, live, with its time and direction, and the traffic
  can be written as a pcap file and/or a text trace.

    chntap [protocol] [--pcap=FILE] [--trace=FILE] [--quiet] 'A' 'B'
      A, B      parameter strings of the two sides, e.g.
                'NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E'
      protocol  --df1 [--crc|--bcc] [--half [--master=A|B]]  (default)
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
  2: a usage error or a side that cannot be opened at the start.

  The loop polls A then B; on a COM layer a poll that finds nothing waits
  up to IDL= ms (default 1), and that wait (unit ChnWait) ends at input on
  either device, so a byte is taken in the next pass: docs/chntap.md has
  the measured latency (make bench, benchtap). }
program chntap;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, uString, ChnTypes, ChnVirt, ChnCom, ChnLoop, ChnTrc,
  ChnTrcFormat, ChnFrameDecode;

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
  Sides: array[0..1] of tSide;
  Stop: Boolean = False;
  Quiet: Boolean = False;
  Raw: Boolean = False;
  Dec: tDecoder;

{$IFDEF UNIX}
procedure OnSignal(Sig: cint); cdecl;
begin
  Stop := True;
end;
{$ENDIF}

procedure Usage(const Why: string);
begin
  WriteLn(StdErr, 'chntap: ', Why);
  WriteLn(StdErr, 'usage: chntap [--df1 [--crc|--bcc] [--half [--master=A|B]] | --ft12 [--adr=N] [--len=N] [--cot-size=N] [--ca-size=N] [--ioa-size=N] | --ics | --raw]');
  WriteLn(StdErr, '              [--pcap=FILE] [--trace=FILE] [--quiet] ''NAM=COM DEV=... (side A)'' ''NAM=COM DEV=... (side B)''');
  Halt(2);
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
      WriteLn(StdErr, 'chntap: ', S.Params, ': ', S.Chn^.ChResultStr(S.Chn^.ChResult),
        ' ', S.Chn^.ChParamError);
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
  Arg, Key, Value, Err: AnsiString;
  NSides, I: Integer;
  Full: AnsiString;
begin
  DecodeDefaults(Opt);
  PcapFile := '';
  TraceFile := '';
  NSides := 0;
  I := 1;
  while I <= ParamCount do
  begin
    Arg := ParamStr(I);
    Inc(I);
    if Copy(Arg, 1, 2) <> '--' then
    begin
      if NSides = 2 then
        Usage('more than two sides: ' + Arg);
      if Length(Arg) > 255 then
        Usage('parameter string longer than 255 characters: ' + Arg);
      Sides[NSides].Params := Arg;
      Inc(NSides);
      Continue;
    end;
    DecodeSplitArg(Arg, Key, Value);
    if (Value = '') and (Pos('=', Arg) = 0) and
       ((Key = '--pcap') or (Key = '--trace')) and (I <= ParamCount) then
    begin
      Value := ParamStr(I);
      Inc(I);
    end;
    if DecodeOption(Key, Value, Opt, Err) then
    begin
      if Err <> '' then
        Usage(Err);
    end
    else if Key = '--master' then
    begin
      if UpperCase(Value) = 'A' then Opt.MasterDir := trcTx
      else if UpperCase(Value) = 'B' then Opt.MasterDir := trcRx
      else Usage('--master wants A or B');
    end
    else if Key = '--raw' then Raw := True
    else if Key = '--quiet' then Quiet := True
    else if Key = '--pcap' then
    begin
      if (Value = '') or (Pos(' ', Value) > 0) then
        Usage('--pcap wants a file name without blanks');
      PcapFile := Value;
    end
    else if Key = '--trace' then
    begin
      if (Value = '') or (Pos(' ', Value) > 0) then
        Usage('--trace wants a file name without blanks');
      TraceFile := Value;
    end
    else
      Usage('unknown option ' + Arg);
  end;
  if NSides < 2 then
    Usage('two parameter strings needed, side A and side B');
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
  if not OpenSide(Sides[0], False) or not OpenSide(Sides[1], False) then
  begin
    for I := 0 to 1 do
      if Sides[I].Chn <> nil then
        Dispose(Sides[I].Chn, Done);
    Halt(2);
  end;
  {$IFDEF UNIX}
  FpSignal(SIGINT, @OnSignal);
  FpSignal(SIGTERM, @OnSignal);
  {$ENDIF}
  DecodeBegin(Dec, Opt, nil);
  Dec.KeepEvents := True;
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
