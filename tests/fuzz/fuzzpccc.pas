{ fuzzpccc - random-mutation fuzzer for the pure PCCC unit ChnPccc.

  Built with range, overflow and stack checks and heaptrc (make fuzz): it
  mutates good addresses into bad ones (bit flips, inserted, deleted and
  replaced characters, pieces of other addresses) and parses them; every
  address accepted must print as a text that parses to the same record.
  Accepted addresses are planned with random counts and request sizes,
  every request of the plan is built, and its reply data decoded from
  random bytes of random length into arrays of random length; random
  values are written. A range or overflow error ends the run with a
  run-time error; a result outside the documented set, a request longer
  than a frame or a value written past the caller's array is a failure.

    fuzzpccc [seconds [seed]]      (default 10 s, seed from the clock) }
program fuzzpccc;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Math, ChnTypes, ChnDF1Codec, ChnPccc, FuzzRun;

const
  Seeds: array[0..23] of string = (
    'N7:0', 'F8:2', 'B3:1/4', 'B3/20', 'T4:0.ACC', 'T4:1.PRE', 'T4:2.DN', 'C5:0.CU',
    'C5:3.OV', 'R6:0.LEN', 'R6:1.POS/3', 'R6:2.FD', 'ST9:0', 'L10:3', 'A11:0', 'S:1',
    'S2:3/7', 'O0:0', 'I1:2', 'N255:65535', 'N7:0/15', 'T4:0', 'C5:1.PRE', 'N10:300');
  Noise = 'NFBTCRSLAIO0123456789:./ STXZ$-';
  Guard = $5A5A5A5A;

var
  Parsed, Accepted, Requests, Decoded: Int64;

function Mutate(const S: string): string;
var
  K, P: Integer;
begin
  Result := S;
  for K := 1 to Random(4) do
  begin
    P := Random(Length(Result) + 1) + 1;
    case Random(6) of
      0: if P <= Length(Result) then
           Result[P] := Chr(Ord(Result[P]) xor (1 shl Random(8)));
      1: if P <= Length(Result) then
           Result[P] := Noise[Random(Length(Noise)) + 1];
      2: Delete(Result, P, 1);
      3: Insert(Noise[Random(Length(Noise)) + 1], Result, P);
      4: Result := Copy(Result, 1, P) + Copy(Seeds[Random(Length(Seeds))], Random(6) + 1, 5);
      5: Insert(IntToStr(Random(70000)), Result, P);
    end;
  end;
end;

function Known(R: tChResult): Boolean;
begin
  Result := R in [res_Ok, res_PcccAddress, res_PcccCount, res_PcccValue, res_PcccReply,
    res_PcccUsage];
end;

procedure FuzzPlan(const A: tPcccAddr);
var
  P: tPcccPlan;
  Err: ShortString;
  Count, MaxBytes, I, N, K, Room: LongInt;
  Write: Boolean;
  Req: tSendRecord;
  Len, Expect: Word;
  Data: array[0..299] of Byte;
  DataLen: Word;
  Ints: array of LongInt;
  Floats: array of Single;
  S: ShortString;
  R: tChResult;
begin
  Write := Random(2) = 0;
  case Random(4) of
    0: Count := Random(5) - 1;
    1: Count := Random(300);
    2: Count := PcccMaxItems - Random(3) + 1;
  else
    Count := Random(20) + 1;
  end;
  MaxBytes := MaxDataLen;
  if Random(3) = 0 then
    MaxBytes := Random(250);
  R := PcccPlan(A, Count, Write, MaxBytes, P, Err);
  if not Known(R) then
    Fail('PcccPlan gave ' + IntToStr(R));
  if R <> res_Ok then
    Exit;
  N := PcccPlanRequests(P);
  if N < 1 then
    Fail(PcccAddressText(A) + ': a plan without requests');
  { arrays of about the right length, sometimes too short }
  Room := PcccPlanValues(P) - Random(3) + 1;
  if Room < 1 then
    Room := 1;
  SetLength(Ints, Room + 1);
  SetLength(Floats, Room + 1);
  Ints[Room] := Guard;
  Floats[Room] := 12345;
  for I := 0 to Room - 1 do
  begin
    if Random(8) = 0 then
      Ints[I] := Random(200000) - 100000
    else
      Ints[I] := Random(2);
    Floats[I] := Random * 1000;
  end;
  for I := 0 to N - 1 do
  begin
    if I > 3 then
      Break;                                  { a few per plan do }
    Len := 0;
    if Write then
    begin
      R := PcccBuildPlanWriteInts(P, I, Ints[0..Room - 1], 1, Req, Len, Err);
      if not Known(R) then
        Fail('PcccBuildPlanWriteInts gave ' + IntToStr(R));
      if (R = res_Ok) and ((Len < cSizeHead + 5) or (Len > cSizeHead + MaxDataLen)) then
        Fail('write request of Len ' + IntToStr(Len));
      R := PcccBuildPlanWriteFloats(P, I, Floats[0..Room - 1], 1, Req, Len, Err);
      if not Known(R) then
        Fail('PcccBuildPlanWriteFloats gave ' + IntToStr(R));
      if (R = res_Ok) and (Len > cSizeHead + MaxDataLen) then
        Fail('float write request of Len ' + IntToStr(Len));
      Inc(Requests);
    end
    else
    begin
      R := PcccBuildPlanRead(P, I, 1, Req, Len, Expect);
      if R <> res_Ok then
        Fail('read request ' + IntToStr(I) + ' of ' + IntToStr(N) + ' gave ' + IntToStr(R));
      if (Expect < 1) or (Expect > MaxBytes) then
        Fail('read request expects ' + IntToStr(Expect) + ' bytes');
      Inc(Requests);
      for K := 0 to High(Data) do
        Data[K] := Random(256);
      DataLen := Expect;
      if Random(3) = 0 then
        DataLen := Random(Length(Data));
      R := PcccDecodePlanInts(P, I, Data[0..Max(DataLen, 1) - 1], DataLen, Ints[0..Room - 1]);
      if not Known(R) then
        Fail('PcccDecodePlanInts gave ' + IntToStr(R));
      R := PcccDecodePlanFloats(P, I, Data[0..Max(DataLen, 1) - 1], DataLen, Floats[0..Room - 1]);
      if not Known(R) then
        Fail('PcccDecodePlanFloats gave ' + IntToStr(R));
      R := PcccDecodeString(Data[0..Max(DataLen, 1) - 1], Random(5) - 1, S);
      if not Known(R) or (Length(S) > PcccStringChars) then
        Fail('PcccDecodeString');
      Inc(Decoded);
    end;
    if (Ints[Room] <> Guard) or (Floats[Room] <> 12345) then
      Fail(PcccAddressText(A) + ': written past the values given');
  end;
end;

procedure FuzzOne;
var
  S, T: string;
  A, B: tPcccAddr;
  Err: ShortString;
  R: tChResult;
begin
  S := Mutate(Seeds[Random(Length(Seeds))]);
  if Random(4) = 0 then
    S := LowerCase(S);
  Inc(Parsed);
  R := PcccParseAddress(S, A, Err);
  if R = res_PcccAddress then
  begin
    if Err = '' then
      Fail('"' + S + '" refused without a text');
    Exit;
  end;
  if R <> res_Ok then
  begin
    Fail('"' + S + '" gave ' + IntToStr(R));
    Exit;
  end;
  Inc(Accepted);
  T := PcccAddressText(A);
  if (PcccParseAddress(T, B, Err) <> res_Ok) or not CompareMem(@A, @B, SizeOf(A)) then
    Fail('"' + S + '" prints as "' + T + '", which parses differently');
  FuzzPlan(A);
end;

var
  Deadline: QWord;
begin
  Deadline := FuzzDeadline('fuzzpccc');
  repeat
    FuzzOne;
  until GetTickCount64 >= Deadline;
  WriteLn(Format('%d addresses parsed, %d accepted, %d requests built, %d replies decoded, %d failures',
    [Parsed, Accepted, Requests, Decoded, Failures]));
  if (Accepted = 0) or (Requests = 0) or (Decoded = 0) then
  begin
    WriteLn('FAIL nothing was accepted, built or decoded: the run checked nothing');
    Inc(Failures);
  end;
  if Failures > 0 then
    Halt(1);
end.
