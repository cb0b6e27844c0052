{ LoopHub - a shared line (an RS-485 bus) made of LOOP pairs, for tests.

  A LOOP pair is point to point. To put several stations on one line, each
  station's stack ends in 'NAM=LOOP PAIR=<p> END=1' and the hub opens
  END=2 of every pair as a port. Pump copies every chunk a port receives
  to all other ports, as a bus does: every station hears every other
  station (not itself). Nothing is merged or reordered; stations talking at
  the same time would interleave, as they would garble a real bus.
  AddChannel puts an open channel of another kind on the bus too (the
  soak's pty to a master in another process). }
unit LoopHub;

{$MODE OBJFPC}{$H+}

interface

uses
  ChnTypes, ChnVirt, ChnLoop;

const
  MaxHubPorts = 8;

type
  TLoopHub = class
  private
    FPorts: array[1..MaxHubPorts] of pChnVirt;
    FCount: Integer;
    FBuf: array[0..4095] of Byte;
  public
    Copied: LongInt;   { bytes received from all ports }
    destructor Destroy; override;
    { open END=2 of PAIR=Pair; False if it cannot be opened }
    function AddPort(const Pair: string): Boolean;
    { put P (open, connected) on the bus; the hub disposes of it. False
      (and P left to the caller) when the hub is full }
    function AddChannel(P: pChnVirt): Boolean;
    { move everything waiting; True if any byte moved }
    function Pump: Boolean;
  end;

implementation

destructor TLoopHub.Destroy;
var
  I: Integer;
begin
  for I := 1 to FCount do
    Dispose(FPorts[I], Done);
  inherited Destroy;
end;

function TLoopHub.AddPort(const Pair: string): Boolean;
var
  P: pChnVirt;
begin
  Result := False;
  if FCount >= MaxHubPorts then
    Exit;
  P := ChnCollection^.ChNewInit(ChnLoop.cName);
  P^.ChSetParam('PAIR=' + Pair + ' END=2');
  if P^.ChResult = res_Ok then
    P^.ChOpen;
  if P^.ChResult = res_Ok then
    P^.ChConnect;
  if P^.ChResult <> res_Ok then
  begin
    Dispose(P, Done);
    Exit;
  end;
  Result := AddChannel(P);
end;

function TLoopHub.AddChannel(P: pChnVirt): Boolean;
begin
  Result := FCount < MaxHubPorts;
  if not Result then
    Exit;
  P^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
  Inc(FCount);
  FPorts[FCount] := P;
end;

function TLoopHub.Pump: Boolean;
var
  I, J: Integer;
  N: Word;
begin
  Result := False;
  for I := 1 to FCount do
    while FPorts[I]^.ChReceiveReady = CHS_ReceiveReady do
    begin
      N := 0;
      FPorts[I]^.ChReceive(N);
      if N = 0 then
        Break;
      Inc(Copied, N);
      Result := True;
      for J := 1 to FCount do
        if J <> I then
          ChSendWhenFree(FPorts[J], @FBuf, N, 1000);   { LOOP copies the bytes at once }
    end;
end;

end.
