{ ChnNoiseLayer - a test physical layer (NAM=NOISE) for a babbling line:
  it always has bytes waiting, CNT= of them in all, every one equal to
  BYTE=, as fast as they are taken. CH_Given counts what was taken, so a
  test can see how much one poll of the layer above pulled. }
unit ChnNoiseLayer;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, uString;

const
  NoiseName = 'NOISE';

type
  pChnNoise = ^tChnNoise;
  tChnNoise = object(tChnVirt)
    CH_Byte : Byte;       { BYTE= }
    CH_Count: LongInt;    { CNT= }
    CH_Given: LongInt;    { bytes taken so far }
    constructor Init;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChHasLow: Boolean; virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
  end;

  pAddChnNoise = ^tAddChnNoise;
  tAddChnNoise = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ Build Params ('NAM=ICS ... NAM=NOISE ...'), open, connect, give a receive
  buffer and poll ChReceiveReady once: how many bytes that one poll took
  from the NOISE layer at the bottom (-1 if the stack did not open), and
  the state it answered. }
function NoiseOnePoll(const Params: tParamStr; var State: tChState): LongInt;

implementation

constructor tChnNoise.Init;
begin
  inherited Init;
  CH_Type := NoiseName;
  CH_Name := CH_Type;
  CH_NumName := ChNumName(CH_Type);
  CH_Byte := $41;
  CH_Count := 1000000;
  CH_Given := 0;
end;

function tChnNoise.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  N: LongInt;
begin
  N := 0;
  if ParamKey(S) = 'BYTE' then
  begin
    Result := ParamNum(S, 0, 255, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Byte := N;
  end
  else if ParamKey(S) = 'CNT' then
  begin
    Result := ParamNum(S, 0, 100000000, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Count := N;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnNoise.ChHasLow: Boolean;
begin
  Result := False;
end;

function tChnNoise.ChReceiveReady: tChState;
begin
  if CH_State <> CHS_Connect then
    Exit(CHS_RecInactive);
  if CH_Given < CH_Count then
    CH_RCtrl := CHS_ReceiveReady
  else
    CH_RCtrl := CHS_Receiving;
  Result := CH_RCtrl;
end;

procedure tChnNoise.ChReceive(var Len: Word);
var
  N: LongInt;
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  N := CH_Count - CH_Given;
  if N > CH_RSize then
    N := CH_RSize;
  FillChar(CH_RBuff^, N, CH_Byte);
  Inc(CH_Given, N);
  Len := N;
  if N = 0 then
    CH_RResult := res_NoMessage
  else
    CH_RResult := res_Ok;
end;

function NoiseOnePoll(const Params: tParamStr; var State: tChState): LongInt;
var
  C, L: pChnVirt;
  Buf: array[0..511] of Byte;
  Tok: string;
  P, Start: Integer;
begin
  Result := -1;
  State := CHS_Close;
  P := 1;
  Start := 1;
  if not NextTokenAt(Params, P, Tok, Start) then
    Exit;
  C := ChnCollection^.ChNewInit(ParamValue(Tok));
  if C = nil then
    Exit;
  C^.ChSetParam(Params);
  if C^.ChResult = res_Ok then
  begin
    C^.ChOpen;
    C^.ChConnect;
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    if C^.ChResult = res_Ok then
    begin
      State := C^.ChReceiveReady;
      L := C;
      while L^.CH_Low <> nil do
        L := L^.CH_Low;
      if L^.CH_Type = NoiseName then
        Result := pChnNoise(L)^.CH_Given;
    end;
  end;
  Dispose(C, Done);
end;

function tAddChnNoise.ChInit: pChnVirt;
begin
  Result := New(pChnNoise, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnNoise, Init(NoiseName)));
end.
