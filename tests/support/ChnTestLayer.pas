{ ChnTestLayer - a minimal protocol layer used only by the foundation tests
  (NAM=TSTP). It passes byte chunks through unchanged and has a few
  parameters of every kind, so stacking, parameter parsing and the life
  cycle of tChnVirt can be tested without any real protocol. }
unit ChnTestLayer;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, uString;

const
  cName = 'TSTP';

type
  pChnTestLayer = ^tChnTestLayer;
  tChnTestLayer = object(tChnVirt)
    CH_Mode : Integer;     { MOD=A|B|C }
    CH_Count: LongInt;     { CNT=0..1000 }
    CH_Flag : Boolean;     { FLG=ON|OFF }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    function  ChMaxNode: tNode; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    procedure ChReceiveTick; virtual;
    procedure ChReceive(var Len: Word); virtual;
  end;

  pAddChnTestLayer = ^tAddChnTestLayer;
  tAddChnTestLayer = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

constructor tChnTestLayer.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Mode := 0;
  CH_Count := 0;
  CH_Flag := False;
end;

constructor tChnTestLayer.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

function tChnTestLayer.ChMaxNode: tNode;
begin
  Result := 254;
end;

function tChnTestLayer.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  N := 0;
  I := 0;
  if Key = 'MOD' then
  begin
    Result := ParamChoice(S, 'A|B|C', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Mode := I;
  end
  else if Key = 'CNT' then
  begin
    Result := ParamNum(S, 0, 1000, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Count := N;
  end
  else if Key = 'FLG' then
    Result := ParamFlag(S, OnOffChoice, CmdL, CH_Flag)
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnTestLayer.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + ' MOD=' + ChoiceWord('A|B|C', CH_Mode) +
    ParamText('CNT', CH_Count) + FlagText('FLG', OnOffChoice, CH_Flag);
end;

procedure tChnTestLayer.ChSend(Buff: Pointer; Len: Word);
begin
  inherited ChSend(Buff, Len);   { transparent }
end;

procedure tChnTestLayer.ChReceiveTick;
begin
  if (CH_State = CHS_Connect) and (CH_RCtrl = CHS_Receiving) then
    if (CH_LowPos < CH_LowLen) or
       ((CH_Low <> nil) and (CH_Low^.ChReceiveReady = CHS_ReceiveReady)) then
      CH_RCtrl := CHS_ReceiveReady;
end;

procedure tChnTestLayer.ChReceive(var Len: Word);
var
  B: Byte;
  P: PByte;
begin
  if ChReceiveAllowed(Len) then
  begin
    CH_RResult := res_Ok;
    P := CH_RBuff;
    while (Len < CH_RSize) and ChLowGetByte(B) do
    begin
      P[Len] := B;
      Inc(Len);
    end;
    if (Len = 0) and (CH_RResult = res_Ok) then
      CH_RResult := res_NoMessage;
  end;
  if CH_State = CHS_Connect then
    CH_RCtrl := CHS_Receiving;
end;

function tAddChnTestLayer.ChInit: pChnVirt;
begin
  Result := New(pChnTestLayer, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnTestLayer, Init(cName)));
end.
