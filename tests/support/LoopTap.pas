{ LoopTap - a relay between two LOOP pairs that logs and can lose what
  passes, for link-procedure tests.

  Station A's stack ends in 'NAM=LOOP PAIR=<a> END=1', station B's in
  'NAM=LOOP PAIR=<b> END=1'; the tap opens END=2 of both and Pump copies
  every chunk from one to the other. Each chunk is logged as one line
  ('A> 10 40 05 45 16', 'B> E5'); a station sends a frame with one
  ChSend, so a chunk is a frame as long as Pump runs between two sends.
  DropA/DropB lose the next chunks from that side (logged with 'lost'),
  as a noisy line loses a frame. Inject puts bytes on the line towards a
  side, as a third station would. HoldA/HoldB keep the chunks from that
  side back (a stalled line; logged with 'held'); Release sends what was
  held on, in order (logged with 'released'). }
unit LoopTap;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, ChnTypes, ChnVirt, ChnLoop, uString;

type
  TBytesArray = array of TBytes;

  TLoopTap = class
  private
    FA, FB: pChnVirt;
    FBuf: array[0..4095] of Byte;
    FHeldA, FHeldB: TBytesArray;
    function MoveFrom(Src, Dst: pChnVirt; const Tag: string; var Drop: Integer;
      Hold: Boolean; var Held: TBytesArray): Boolean;
    procedure SendHeld(Dst: pChnVirt; const Tag: string; var Held: TBytesArray);
  public
    Log: TStringList;
    DropA, DropB: Integer;   { chunks still to lose from A resp. B }
    HoldA, HoldB: Boolean;   { keep the chunks from A resp. B back }
    { send the held chunks on (both sides), in order }
    procedure Release;
    constructor Create(const PairA, PairB: string);
    destructor Destroy; override;
    function Ok: Boolean;
    { move everything waiting both ways; True if any byte moved }
    function Pump: Boolean;
    { send Hex ('10 00 06 06 16') towards station A resp. B }
    procedure InjectToA(const Hex: string);
    procedure InjectToB(const Hex: string);
    { the logged lines from side Tag ('A' or 'B'), each without the tag }
    function Lines(const Tag: string): string;
  end;

implementation

uses
  TestSupport;

function OpenEnd(const Pair: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit(ChnLoop.cName);
  Result^.ChSetParam('PAIR=' + Pair + ' END=2');
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    Dispose(Result, Done);
    Result := nil;
  end;
end;

constructor TLoopTap.Create(const PairA, PairB: string);
begin
  inherited Create;
  Log := TStringList.Create;
  FA := OpenEnd(PairA);
  FB := OpenEnd(PairB);
  if FA <> nil then
    FA^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
  if FB <> nil then
    FB^.ChReceiveBuffer(@FBuf, SizeOf(FBuf));
end;

destructor TLoopTap.Destroy;
begin
  if FA <> nil then
    Dispose(FA, Done);
  if FB <> nil then
    Dispose(FB, Done);
  Log.Free;
  inherited Destroy;
end;

function TLoopTap.Ok: Boolean;
begin
  Result := (FA <> nil) and (FB <> nil);
end;

function TLoopTap.MoveFrom(Src, Dst: pChnVirt; const Tag: string; var Drop: Integer;
  Hold: Boolean; var Held: TBytesArray): Boolean;
var
  N: Word;
begin
  Result := False;
  while Src^.ChReceiveReady = CHS_ReceiveReady do
  begin
    N := 0;
    Src^.ChReceive(N);
    if N = 0 then
      Break;
    Result := True;
    if Drop > 0 then
    begin
      Dec(Drop);
      Log.Add(Tag + '> ' + HexBytes(@FBuf[0], N) + ' lost');
    end
    else if Hold then
    begin
      Log.Add(Tag + '> ' + HexBytes(@FBuf[0], N) + ' held');
      SetLength(Held, Length(Held) + 1);
      SetLength(Held[High(Held)], N);
      Move(FBuf[0], Held[High(Held)][0], N);
    end
    else
    begin
      Log.Add(Tag + '> ' + HexBytes(@FBuf[0], N));
      Dst^.ChSend(@FBuf, N);     { LOOP copies the bytes at once }
    end;
  end;
end;

function TLoopTap.Pump: Boolean;
begin
  Result := MoveFrom(FA, FB, 'A', DropA, HoldA, FHeldA);
  if MoveFrom(FB, FA, 'B', DropB, HoldB, FHeldB) then
    Result := True;
end;

procedure TLoopTap.SendHeld(Dst: pChnVirt; const Tag: string; var Held: TBytesArray);
var
  I: Integer;
begin
  for I := 0 to High(Held) do
  begin
    Log.Add(Tag + '> ' + HexBytes(@Held[I][0], Length(Held[I])) + ' released');
    Dst^.ChSend(@Held[I][0], Length(Held[I]));
  end;
  Held := nil;
end;

procedure TLoopTap.Release;
begin
  SendHeld(FB, 'A', FHeldA);
  SendHeld(FA, 'B', FHeldB);
end;

procedure TLoopTap.InjectToA(const Hex: string);
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  Log.Add('*> ' + Hex);
  FA^.ChSend(@B[0], Length(B));
end;

procedure TLoopTap.InjectToB(const Hex: string);
var
  B: TBytes;
begin
  B := HexToBytes(Hex);
  Log.Add('*> ' + Hex);
  FB^.ChSend(@B[0], Length(B));
end;

function TLoopTap.Lines(const Tag: string): string;
var
  I: Integer;
begin
  Result := '';
  for I := 0 to Log.Count - 1 do
    if Copy(Log[I], 1, Length(Tag) + 2) = Tag + '> ' then
    begin
      if Result <> '' then
        Result := Result + ' | ';
      Result := Result + Copy(Log[I], Length(Tag) + 3, MaxInt);
    end;
end;

end.
