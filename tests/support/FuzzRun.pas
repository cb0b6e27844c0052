{ FuzzRun - the command line of the fuzzers: "NAME [seconds [seed]]"
  (default 10 s, seed from the clock); seeds Random and prints the seed so
  a failing run can be repeated; counts and prints the checks that failed. }
unit FuzzRun;

{$MODE OBJFPC}{$H+}

interface

{ Parse the arguments, seed Random, print "NAME: S s, seed N"; the
  GetTickCount64 value at which the run ends. }
function FuzzDeadline(const Name: string): QWord;

var
  Failures: Int64 = 0;   {< checks that failed }

{ A check failed: counted, and the first 20 printed ('FAIL What'). }
procedure Fail(const What: string);

implementation

uses
  SysUtils;

function FuzzDeadline(const Name: string): QWord;
var
  Seconds: Integer;
  Seed: LongInt;
begin
  Seconds := 10;
  if ParamCount >= 1 then
    Seconds := StrToIntDef(ParamStr(1), 10);
  Seed := LongInt(GetTickCount64 and $7FFFFFFF);
  if ParamCount >= 2 then
    Seed := StrToIntDef(ParamStr(2), Seed);
  RandSeed := Seed;
  WriteLn(Name, ': ', Seconds, ' s, seed ', Seed);
  Result := GetTickCount64 + QWord(Seconds) * 1000;
end;

procedure Fail(const What: string);
begin
  Inc(Failures);
  if Failures <= 20 then
    WriteLn('FAIL ', What);
end;

end.
