{ benchtcp - NAM=TCP on the loopback interface against the in-memory null
  modem NAM=LOOP as the baseline of the same run, the Telnet codec, and the
  CPU an idle polling loop on a TCP client costs. Run with "make bench";
  figures are for comparison on one machine, not assertions. }
program benchtcp;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads, BaseUnix, Linux,{$ENDIF}
  SysUtils, ChnTypes, ChnVirt, ChnLoop, ChnTcp, ChnTelnet;

const
  Total = 16 shl 20;
  Chunk = 60000;

var
  Block: array[0..Chunk - 1] of Byte;
  RBuf: array[0..65534] of Byte;

function Open(const Name, Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(Name);
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult <> res_Ok then
  begin
    WriteLn(Name, ' ', Params, ': ', Result^.ChResultStr(Result^.ChResult));
    Halt(1);
  end;
  Result^.ChConnect;
  Result^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
end;

{ Bytes from A to B, both polled from this thread; MB/s. }
function Pump(A, B: pChnVirt; Total: Int64): Double;
var
  Sent, Got: Int64;
  Len: Word;
  T: QWord;
begin
  Sent := 0;
  Got := 0;
  T := GetTickCount64;
  while Got < Total do
  begin
    if (Sent < Total) and (A^.ChSendReady = CHS_SendReady) then
    begin
      A^.ChSend(@Block, Chunk);
      Inc(Sent, Chunk);
    end;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      Inc(Got, Len);
    end;
  end;
  T := GetTickCount64 - T;
  if T = 0 then
    T := 1;
  Result := Got / 1e6 / (T / 1000);
end;

function CpuMs: Double;
{$IFDEF UNIX}
var
  Ts: TTimeSpec;
begin
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, @Ts);
  Result := Ts.tv_sec * 1000.0 + Ts.tv_nsec / 1e6;
end;
{$ELSE}
begin
  Result := 0;
end;
{$ENDIF}

var
  L1, L2, Srv, Cli: pChnVirt;
  Loop, Tcp: Double;
  I, Used, N: LongInt;
  Enc: array of Byte;
  D: tTelnetDecoder;
  T: QWord;
  C0: Double;
  Polls: LongInt;
begin
  for I := 0 to Chunk - 1 do
    Block[I] := I * 7 mod 251;
  L1 := Open('LOOP', 'PAIR=benchtcp END=1 IDL=0');
  L2 := Open('LOOP', 'PAIR=benchtcp END=2 IDL=0');
  Loop := Pump(L1, L2, 16 * Int64(Total));
  Dispose(L1, Done);
  Dispose(L2, Done);
  Srv := Open('TCP', 'LISTEN=0 IDL=0 LRB=65536');
  Cli := Open('TCP', Format('HOST=127.0.0.1 PORT=%d IDL=0 LRB=65536',
    [pChnTcp(Srv)^.ChLocalPort]));
  Srv^.ChReceiveReady;               { takes its client }
  Tcp := Pump(Cli, Srv, Total);
  WriteLn(Format('%-40s %8.1f MB/s', ['LOOP (baseline), 256 MiB', Loop]));
  WriteLn(Format('%-40s %8.1f MB/s  (%.2f of LOOP)', ['TCP loopback raw, 16 MiB', Tcp,
    Tcp / Loop]));

  { the codec: escape and decode 16 MiB, a quarter of it $FF }
  SetLength(Enc, 2 * Chunk);
  for I := 0 to Chunk - 1 do
    if I mod 4 = 0 then
      Block[I] := $FF;
  T := GetTickCount64;
  TelnetInit(D);
  for I := 1 to Total div Chunk do
  begin
    N := TelnetEscape(Block, Chunk, Enc[0], Length(Enc), Used);
    while N > 0 do
    begin
      Dec(N);
      TelnetFeed(D, Enc[N]);
    end;
  end;
  T := GetTickCount64 - T;
  if T = 0 then
    T := 1;
  WriteLn(Format('%-40s %8.1f MB/s', ['Telnet escape + decode, 16 MiB', Total / 1e6 / (T / 1000)]));

  { an idle legacy polling loop on the TCP client, IDL=1 }
  Dispose(Cli, Done);
  Cli := Open('TCP', Format('HOST=127.0.0.1 PORT=%d', [pChnTcp(Srv)^.ChLocalPort]));
  Srv^.ChReceiveReady;
  C0 := CpuMs;
  T := GetTickCount64;
  Polls := 0;
  while GetTickCount64 - T < 2000 do
  begin
    Cli^.ChReceiveReady;
    Inc(Polls);
  end;
  WriteLn(Format('%-40s %8.1f ms CPU in 2000 ms, %d polls', ['idle TCP client poll loop, IDL=1',
    CpuMs - C0, Polls]));
  Dispose(Cli, Done);
  Dispose(Srv, Done);
end.
