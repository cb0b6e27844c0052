{ No silent truncation: every entry point that takes a
  parameter string takes a long one (AnsiString) and refuses more than the
  legacy 255 characters with res_ParamTooLong and a text naming the
  length and the limit, instead of cutting it to another string - a
  device path cut at character 255 names another device, a 100-layer
  string cut to 24 layers still opens. }
unit TestParamLength;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnDF1, ChnDF1Link,
  ChnPcccClient, ChnTestLayer;

type
  TTestParamLength = class(TTestCase)
  published
    procedure TestSetParamRefusesALongString;
    procedure TestHundredLayersAreNotCutToTwentyFour;
    procedure TestLongestLegacyStringStillWorks;
    procedure TestDF1OpenStackRefusesALongString;
    procedure TestPcccOpenRefusesALongString;
  end;

implementation

{ 'NAM=DF1 ... DEV=/tmp/x...x/AB' where the B is character Len }
function LongDevString(Len: Integer): AnsiString;
begin
  Result := 'NAM=DF1 NOD=1 DNO=2 NAM=COM DEV=/tmp/';
  while Length(Result) < Len - 3 do
    Result := Result + 'x';
  Result := Result + '/AB';
end;

procedure TTestParamLength.TestSetParamRefusesALongString;
var
  C: pChnVirt;
  S: AnsiString;
begin
  S := LongDevString(300);
  AssertEquals(300, Length(S));
  C := ChnCollection^.ChNewInit('DF1');
  try
    C^.ChSetParam('NOD=5');
    AssertEquals(res_Ok, C^.ChResult);
    C^.ChSetParam(S);
    AssertEquals('refused, not cut', res_ParamTooLong, C^.ChResult);
    AssertEquals('300 characters, the limit is 255', C^.ChParamError);
    AssertEquals('parameter string too long', C^.ChResultStr(res_ParamTooLong));
    AssertEquals('nothing applied', 'NOD=5', C^.ChGetParam('NOD'));
    AssertTrue('no layer below built', C^.CH_Low = nil);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestParamLength.TestHundredLayersAreNotCutToTwentyFour;
var
  C, L: pChnVirt;
  S: AnsiString;
  I, Depth: Integer;
begin
  S := '';
  for I := 1 to 100 do
    S := S + 'NAM=TSTP ';
  S := S + 'NAM=LOOP PAIR=PLEN END=1';
  C := ChnCollection^.ChNewInit('TSTP');
  try
    C^.ChSetParam(S);
    AssertEquals('a 100-layer string is refused', res_ParamTooLong, C^.ChResult);
    Depth := 0;
    L := C^.CH_Low;
    while L <> nil do
    begin
      Inc(Depth);
      L := L^.CH_Low;
    end;
    AssertEquals('no stack of 24 layers opened in its place', 0, Depth);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestParamLength.TestLongestLegacyStringStillWorks;
var
  C: pChnVirt;
  S: AnsiString;
begin
  S := LongDevString(255);
  C := ChnCollection^.ChNewInit('DF1');
  try
    C^.ChSetParam(S);
    AssertEquals('255 characters are within the legacy limit', res_Ok, C^.ChResult);
    AssertEquals('the whole device path', Copy(S, Pos('DEV=', S), 255),
      C^.CH_Low^.ChGetParam('DEV'));
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestParamLength.TestDF1OpenStackRefusesALongString;
var
  C: pChnVirt;
  Err: AnsiString;
begin
  Err := '';
  C := DF1OpenStack(LongDevString(256), 100, Err);
  AssertTrue('nothing opened', C = nil);
  AssertEquals('parameter string too long: 256 characters, the limit is 255', Err);
end;

procedure TTestParamLength.TestPcccOpenRefusesALongString;
var
  C: tPcccClient;
begin
  AssertEquals(res_ParamTooLong, PcccOpen(C, LongDevString(256)));
  AssertTrue('nothing opened', C.Chn = nil);
  AssertEquals('parameter string too long: 256 characters, the limit is 255', C.Err);
  PcccClose(C);
end;

initialization
  RegisterTest(TTestParamLength);
end.
