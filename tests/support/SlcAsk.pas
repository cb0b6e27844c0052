{ SlcAsk - one request to the simulator's table (tools/lib/ChnSlc) as
  the DF1 link would hand it over, and the reply as text. }
unit SlcAsk;

{$MODE OBJFPC}{$H+}

interface

uses
  ChnSlc;

{ Hand T a data message with command CF, transaction Tns and the data
  DataHex; checks the reply's head (a data message, CF with $40 and no
  FNC, the same TNS) and gives its STS and data as 'STS=00 01 02'. }
function SlcAskText(var T: tSlcTable; CF: Word; const DataHex: string; Tns: Word): string;

implementation

uses
  SysUtils, fpcunit, ChnDF1Codec, TestSupport;

function SlcAskText(var T: tSlcTable; CF: Word; const DataHex: string; Tns: Word): string;
var
  Req: tRecRecord;
  Rep: tSendRecord;
  D: TBytes;
  RepLen: Word;
begin
  FillChar(Req, SizeOf(Req), 0);
  FillChar(Rep, SizeOf(Rep), $EE);
  Req.MessType := tpDataMess;
  Req.CF := CF;
  Req.Tns := Tns;
  D := HexToBytes(DataHex);
  if Length(D) > 0 then
    Move(D[0], Req.Data[0], Length(D));
  RepLen := 0;
  TAssert.AssertTrue('handled', SlcHandle(T, Req, 8 + Length(D), Rep, RepLen));
  TAssert.AssertEquals('reply MessType', Ord(tpDataMess), Ord(Rep.MessType));
  TAssert.AssertEquals('reply CF: CMD + $40, no FNC', (CF and $FF00) or $4000, Rep.CF);
  TAssert.AssertEquals('reply TNS', Tns, Rep.Tns);
  Result := Format('STS=%.2x', [Rep.Sts]);
  if RepLen > 8 then
    Result := Result + ' ' + BytesToHex(Rep.Data, RepLen - 8);
end;

end.
