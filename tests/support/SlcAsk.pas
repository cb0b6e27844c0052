{ SlcAsk - one request to the simulator's table (tools/lib/ChnSlc) as
  the DF1 link would hand it over, and the reply as text; the request's
  data and the reply's text for a DF1 transaction too. }
unit SlcAsk;

{$MODE OBJFPC}{$H+}

interface

uses
  ChnSlc;

{ Hand T a data message with command CF, transaction Tns and the data
  DataHex; checks the reply's head (a data message, CF with $40 and no
  FNC, the same TNS) and gives its STS and data as 'STS=00 01 02'. }
function SlcAskText(var T: tSlcTable; CF: Word; const DataHex: string; Tns: Word): string;
{ The octets of DataHex ('0A 07') at the start of Data; how many. }
function PutHex(const DataHex: string; var Data: array of Byte): Integer;
{ A reply as text: 'STS=00', then its first DataLen data octets, if any. }
function ReplyText(Sts: Byte; const Data: array of Byte; DataLen: Integer): string;

implementation

uses
  SysUtils, fpcunit, ChnDF1Codec, TestSupport;

function SlcAskText(var T: tSlcTable; CF: Word; const DataHex: string; Tns: Word): string;
var
  Req: tRecRecord;
  Rep: tSendRecord;
  N: Integer;
  RepLen: Word;
begin
  FillChar(Req, SizeOf(Req), 0);
  FillChar(Rep, SizeOf(Rep), $EE);
  Req.MessType := tpDataMess;
  Req.CF := CF;
  Req.Tns := Tns;
  N := PutHex(DataHex, Req.Data);
  RepLen := 0;
  TAssert.AssertTrue('handled', SlcHandle(T, Req, 8 + N, Rep, RepLen));
  TAssert.AssertEquals('reply MessType', Ord(tpDataMess), Ord(Rep.MessType));
  TAssert.AssertEquals('reply CF: CMD + $40, no FNC', (CF and $FF00) or $4000, Rep.CF);
  TAssert.AssertEquals('reply TNS', Tns, Rep.Tns);
  Result := ReplyText(Rep.Sts, Rep.Data, RepLen - 8);
end;

function PutHex(const DataHex: string; var Data: array of Byte): Integer;
var
  D: TBytes;
begin
  D := HexToBytes(DataHex);
  Result := Length(D);
  if Result > 0 then
    Move(D[0], Data[0], Result);
end;

function ReplyText(Sts: Byte; const Data: array of Byte; DataLen: Integer): string;
begin
  Result := Format('STS=%.2x', [Sts]);
  if DataLen > 0 then
    Result := Result + ' ' + BytesToHex(Data, DataLen);
end;

end.
