{ asducodec - throughput of the IEC 101 ASDU codec (ChnIec101Asdu), no
  I/O: every type the codec knows, an ASDU of 8 objects each, encoded and
  decoded again. Prints ASDUs/s for each direction. }
program asducodec;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnIec101Asdu;

const
  PerAsdu = 8;
  Rounds = 4000;

type
  tAsduBytes = record
    Len: Word;
    B: array[0..IecMaxAsdu - 1] of Byte;
  end;

var
  Types: array of Byte;
  Objs: array of array[0..PerAsdu - 1] of tIecObject;
  Wire: array of tAsduBytes;

{ An object of type Ti with a value of its kind that every field can hold. }
function Sample(Ti: Byte; Ioa: LongWord): tIecObject;
begin
  Result := IecObject(Ioa);
  case IecTypeKind(Ti) of
    ikSingle, ikSingleCmd: Result.Int := 1;
    ikDouble, ikDoubleCmd, ikStepCmd, ikProtection: Result.Int := 2;
    ikStep: Result.Int := -5;
    ikScaled, ikSetScaled, ikParScaled: Result.Int := -1234;
    ikNormal, ikSetNormal, ikParNormal: Result.Number := -0.25;
    ikFloat, ikSetFloat, ikParFloat: Result.Number := 3.5;
    ikCounter: begin Result.Int := -100000; Result.Seq := 17; end;
    ikBits, ikBitsCmd, ikPacked: Result.Bits := $DEADBEEF;
    ikStartEvents, ikOutputCircuit: Result.Bits := 5;
    ikEndInit, ikQualifier: Result.Int := 21;
    ikTest, ikTestTime: Result.Int := $55AA;
    ikDelay: Result.Elapsed := 321;
  end;
  if IecTypeKind(Ti) in [ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled, ikSetFloat] then
  begin
    Result.Select := True;
    Result.Qu := 3;
  end;
  if IecTypeTime(Ti) <> tkNone then
  begin
    Result.Time.Msec := 59999;
    Result.Time.Minute := 59;
    Result.Time.Hour := 23;
    Result.Time.Day := 31;
    Result.Time.DayOfWeek := 7;
    Result.Time.Month := 12;
    Result.Time.Year := 99;
  end;
end;

procedure Prepare;
var
  Ti: Integer;
  N, J: Integer;
begin
  N := 0;
  for Ti := 1 to 255 do
    if IecTypeKind(Ti) <> ikNone then
    begin
      SetLength(Types, N + 1);
      SetLength(Objs, N + 1);
      Types[N] := Ti;
      for J := 0 to PerAsdu - 1 do
        Objs[N][J] := Sample(Ti, 1000 + J);
      Inc(N);
    end;
  SetLength(Wire, N);
end;

procedure Report(const What: string; Count: Int64; Ms: QWord);
begin
  if Ms = 0 then
    Ms := 1;
  WriteLn(Format('%-40s %10.0f ASDUs/s', [What, Count / (Ms / 1000)]));
end;

procedure EncodeEvery;
var
  P: tIecParams;
  H: tIecAsdu;
  R, I: LongInt;
  E: ShortString;
  T: QWord;
begin
  P := IecDefaultParams;
  FillChar(H, SizeOf(H), 0);
  H.Count := PerAsdu;
  H.Cot := Cot_Spontaneous;
  H.Ca := 1;
  T := GetTickCount64;
  for R := 1 to Rounds do
    for I := 0 to High(Types) do
    begin
      H.Ti := Types[I];
      if IecEncodeAsdu(P, H, Objs[I], Wire[I].B, Wire[I].Len, E) <> res_Ok then
      begin
        WriteLn(IecTypeName(Types[I]), ': ', E);
        Halt(1);
      end;
    end;
  Report(Format('encode, %d types x %d objects', [Length(Types), PerAsdu]),
    Int64(Rounds) * Length(Types), GetTickCount64 - T);
end;

procedure DecodeEvery;
var
  P: tIecParams;
  H: tIecAsdu;
  Back: array[0..PerAsdu - 1] of tIecObject;
  R, I: LongInt;
  E: ShortString;
  T: QWord;
begin
  P := IecDefaultParams;
  T := GetTickCount64;
  for R := 1 to Rounds do
    for I := 0 to High(Types) do
      if IecDecodeAsdu(P, Wire[I].B, Wire[I].Len, H, Back, E) <> res_Ok then
      begin
        WriteLn(IecTypeName(Types[I]), ': ', E);
        Halt(1);
      end;
  Report(Format('decode, %d types x %d objects', [Length(Types), PerAsdu]),
    Int64(Rounds) * Length(Types), GetTickCount64 - T);
end;

begin
  Prepare;
  EncodeEvery;
  DecodeEvery;
end.
