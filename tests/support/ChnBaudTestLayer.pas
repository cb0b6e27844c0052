{ ChnBaudTestLayer - a pass-through test layer (NAM=BDT) that only adds a
  BD= parameter, so tests can check how an upper layer reads the baud rate
  of the stack below (e.g. GAP= of ChnFT1_2) without a serial port. }
unit ChnBaudTestLayer;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnTestLayer;

const
  cName = 'BDT';

type
  pChnBaudTestLayer = ^tChnBaudTestLayer;
  tChnBaudTestLayer = object(tChnTestLayer)
    CH_Baud: LongInt;
    constructor Init;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
  end;

  pAddChnBaudTestLayer = ^tAddChnBaudTestLayer;
  tAddChnBaudTestLayer = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

implementation

constructor tChnBaudTestLayer.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Baud := 9600;
end;

function tChnBaudTestLayer.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  N: LongInt;
begin
  N := 0;
  if ParamKey(S) = 'BD' then
  begin
    Result := ParamNum(S, 50, 4000000, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Baud := N;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnBaudTestLayer.ChOwnParams: tParamStr;
begin
  Result := inherited ChOwnParams + ParamText('BD', CH_Baud);
end;

function tAddChnBaudTestLayer.ChInit: pChnVirt;
begin
  Result := New(pChnBaudTestLayer, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnBaudTestLayer, Init(cName)));
end.
