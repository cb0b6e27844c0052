{ fuzzasdu - random-mutation fuzzer for the pure ASDU unit ChnIec101Asdu.

  Built with range, overflow and stack checks and heaptrc (make fuzz): it
  encodes ASDUs of random types, counts, SQ and application parameters with
  random values (some out of range: the encoder must refuse them with a
  text), mutates the octets (bit flips, changed, inserted and deleted
  octets, truncation, pieces of other ASDUs) and decodes them with a
  random Len (sometimes beyond the array) into arrays of random length
  with a guard behind. A range or overflow error ends the run with a
  run-time error; a result outside the documented set, a refusal without
  text, a write past the caller's array, or an accepted ASDU that does not
  encode back to what decodes to the same objects is a failure.

    fuzzasdu [seconds [seed]]      (default 10 s, seed from the clock) }
program fuzzasdu;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Math, ChnTypes, ChnIec101Asdu, FuzzRun;

const
  Guard = $5A;

var
  Types: array of Byte = nil;
  Encoded, Refused, Decoded, Accepted, Checked: Int64;

function Known(R: tChResult): Boolean;
begin
  Result := (R = res_Ok) or ((R >= res_AsduParam) and (R <= res_AsduValue));
end;

function RandomParams: tIecParams;
begin
  Result.CotSize := 1 + Random(2);
  Result.CaSize := 1 + Random(2);
  Result.IoaSize := 1 + Random(3);
  if Random(50) = 0 then
    Result.IoaSize := Random(6);       { impossible now and then }
end;

{ 0..N-1, now and then up to N+Extra-1: mostly in range, sometimes not. }
function Wild(N, Extra: LongInt): LongInt;
begin
  if Random(16) = 0 then
    Result := N + Random(Extra)
  else
    Result := Random(N);
end;

function RandomObject(Ioa: LongWord): tIecObject;
begin
  Result := IecObject(Ioa);
  case Random(16) of
    0..9: Result.Int := Wild(2, 3);
    10..14: Result.Int := Random(65536) - 32768;
  else
    Result.Int := LongInt(Random($7FFFFFFF)) - Random($7FFFFFFF);
  end;
  Result.Bits := LongWord(Random($7FFFFFFF)) * 2 + LongWord(Random(2));
  if Random(4) <> 0 then
    Result.Bits := Wild(64, 200);
  case Random(16) of
    0..11: Result.Number := Random * 2 - 1;
    12, 13: Result.Number := (Random - 0.5) * 1e6;
    14: Result.Number := Random(3) - 1;
  else
    Result.Number := (Random - 0.5) * 1e40;
  end;
  Result.Quality := Random(256);
  Result.Transient := Random(2) = 0;
  Result.Seq := Wild(32, 8);
  Result.Select := Random(2) = 0;
  Result.Qu := Wild(32, 120);
  Result.Elapsed := Random(65536);
  Result.Time.Msec := Random(65536);
  Result.Time.Minute := Wild(64, 6);
  Result.Time.Hour := Wild(32, 3);
  Result.Time.Day := Wild(32, 3);
  Result.Time.DayOfWeek := Wild(8, 2);
  Result.Time.Month := Wild(16, 2);
  Result.Time.Year := Wild(128, 3);
  Result.Time.Invalid := Random(2) = 0;
  Result.Time.Summer := Random(2) = 0;
end;

{ Decode Buf[0..Len-1] under P into arrays of random room; check the
  guard and, for an accepted ASDU, the round trip. }
procedure DecodeAndCheck(const P: tIecParams; const Buf: array of Byte; Len: Word);
var
  H, H2: tIecAsdu;
  Objs, Objs2: array of tIecObject;
  Room, I: Integer;
  E: ShortString;
  R: tChResult;
  Out1, Out2: array[0..299] of Byte;
  L1, L2: Word;
  G: PByte;
begin
  Inc(Decoded);
  Room := Random(130);
  SetLength(Objs, Room + 1);
  FillChar(Objs[Room], SizeOf(tIecObject), Guard);
  if Room = 0 then
    R := IecDecodeHeader(P, Buf, Len, H, E)
  else
    R := IecDecodeAsdu(P, Buf, Len, H, Objs[0..Room - 1], E);
  if not Known(R) then
    Fail('decode gave ' + IntToStr(R));
  if (R <> res_Ok) and (E = '') then
    Fail('decode refused (' + IntToStr(R) + ') without a text');
  G := @Objs[Room];
  for I := 0 to SizeOf(tIecObject) - 1 do
    if G[I] <> Guard then
    begin
      Fail('decode wrote past the objects array');
      Break;
    end;
  if (R <> res_Ok) or (Room = 0) then
    Exit;
  Inc(Accepted);
  { every object index in range decodes, one outside does not }
  if IecDecodeObject(P, H, Buf, H.Count, Objs[0]) <> res_AsduCount then
    Fail('object index past the count decoded');
  for I := 0 to H.Count - 1 do
    IecDecodeObject(P, H, Buf, I, Objs[I]);
  { what was accepted encodes; that decodes to the same, and encodes the same again }
  R := IecEncodeAsdu(P, H, Objs[0..H.Count - 1], Out1, L1, E);
  if R <> res_Ok then
  begin
    Fail(IecTypeName(H.Ti) + ': accepted but does not encode back: ' + E);
    Exit;
  end;
  SetLength(Objs2, H.Count);
  R := IecDecodeAsdu(P, Out1, L1, H2, Objs2, E);
  if R <> res_Ok then
  begin
    Fail(IecTypeName(H.Ti) + ': its encoding does not decode: ' + E);
    Exit;
  end;
  if (H2.Ti <> H.Ti) or (H2.Count <> H.Count) or (H2.Sq <> H.Sq) or (H2.Cot <> H.Cot)
    or (H2.Negative <> H.Negative) or (H2.Test <> H.Test) or (H2.Oa <> H.Oa) or (H2.Ca <> H.Ca)
    or (L1 <> Len) then
    Fail(IecTypeName(H.Ti) + ': identifier changed in the round trip');
  R := IecEncodeAsdu(P, H2, Objs2, Out2, L2, E);
  if (R <> res_Ok) or (L2 <> L1) or not CompareMem(@Out1, @Out2, L1) then
    Fail(IecTypeName(H.Ti) + ': encoding is not stable');
  for I := 0 to H.Count - 1 do
    if (Objs2[I].Ioa <> Objs[I].Ioa) or (Objs2[I].Int <> Objs[I].Int) or (Objs2[I].Bits <> Objs[I].Bits)
      or (Objs2[I].Quality <> Objs[I].Quality) then
    begin
      Fail(IecTypeName(H.Ti) + ': object ' + IntToStr(I + 1) + ' changed in the round trip');
      Break;
    end;
  Inc(Checked);
end;

procedure Mutate(var W: array of Byte; var Len: Integer; const Other: array of Byte; OtherLen: Integer);
var
  K, I, P, N: Integer;
begin
  for K := 1 to Random(4) do
  begin
    if Len = 0 then
      Exit;
    P := Random(Len);
    case Random(7) of
      0: W[P] := W[P] xor (1 shl Random(8));
      1: W[P] := Random(256);
      2: begin
           for I := P to Len - 2 do
             W[I] := W[I + 1];
           Dec(Len);
         end;
      3: if Len < High(W) then
         begin
           for I := Len downto P + 1 do
             W[I] := W[I - 1];
           W[P] := Random(256);
           Inc(Len);
         end;
      4: Len := P;
      5: begin                                   { a piece of another ASDU }
           N := Min(Random(8) + 1, Min(OtherLen, High(W) + 1 - P));
           for I := 0 to N - 1 do
             W[P + I] := Other[I];
           Len := Max(Len, P + N);
         end;
      6: ;
    end;
  end;
end;

var
  Last: array[0..299] of Byte;
  LastLen: Integer = 0;

procedure FuzzOne;
var
  P: tIecParams;
  H, H2: tIecAsdu;
  Objs: array[0..IecMaxObjects] of tIecObject;
  Buf: array[0..299] of Byte;
  Room, I, Len: Integer;
  L: Word;
  E: ShortString;
  R: tChResult;
  Ioa: LongWord;
begin
  P := RandomParams;
  FillChar(H, SizeOf(H), 0);
  H.Ti := Types[Random(Length(Types))];
  if Random(30) = 0 then
    H.Ti := Random(256);
  H.Sq := Random(3) = 0;
  H.Count := 1 + Random(4);
  if Random(10) = 0 then
    H.Count := Random(129);
  H.Cot := Random(64);
  if Random(40) = 0 then
    H.Cot := 64 + Random(10);
  H.Negative := Random(2) = 0;
  H.Test := Random(4) = 0;
  if P.CotSize = 2 then
    H.Oa := Random(256);
  H.Ca := Random(65536);
  if P.CaSize = 1 then
    H.Ca := H.Ca and $FF;
  Ioa := Random($1000000);
  if P.IoaSize = 1 then Ioa := Ioa and $FF
  else if P.IoaSize = 2 then Ioa := Ioa and $FFFF;
  for I := 0 to IecMaxObjects do
  begin
    if H.Sq then
      Objs[I] := RandomObject(Ioa + LongWord(I))
    else
      Objs[I] := RandomObject(Random($1000000) and IecMaxIoa(P));
  end;
  Room := 30 + Random(271);
  FillChar(Buf, SizeOf(Buf), Guard);
  R := IecEncodeAsdu(P, H, Objs[0..H.Count - 1], Buf[0..Room - 1], L, E);
  if not Known(R) then
    Fail('encode gave ' + IntToStr(R));
  for I := Room to High(Buf) do
    if Buf[I] <> Guard then
    begin
      Fail('encode wrote past the buffer');
      Break;
    end;
  if R <> res_Ok then
  begin
    Inc(Refused);
    if E = '' then
      Fail('encode refused (' + IntToStr(R) + ') without a text');
    if L <> 0 then
      Fail('refused encode with a length');
    { something to decode all the same: noise or the last ASDU }
    Len := Random(40);
    for I := 0 to Len - 1 do
      Buf[I] := Random(256);
    if Random(2) = 0 then
    begin
      Move(Last, Buf, LastLen);
      Len := LastLen;
    end;
  end
  else
  begin
    Inc(Encoded);
    if L > IecMaxAsdu then
      Fail('an ASDU of ' + IntToStr(L) + ' octets');
    Len := L;
    if IecDecodeHeader(P, Buf, L, H2, E) <> res_Ok then
      Fail(IecTypeName(H.Ti) + ': what was encoded does not decode: ' + E);
    DecodeAndCheck(P, Buf, L);
    Move(Buf, Last, L);
    LastLen := L;
  end;
  Mutate(Buf, Len, Last, LastLen);
  if Random(20) = 0 then
    DecodeAndCheck(P, Buf[0..Max(Len, 1) - 1], Len + Random(3))   { Len beyond the array }
  else
    DecodeAndCheck(P, Buf, Len);
end;

var
  Deadline: QWord;
  T: Integer;
begin
  for T := 0 to 255 do
    if IecTypeName(T) <> '' then
    begin
      SetLength(Types, Length(Types) + 1);
      Types[High(Types)] := T;
    end;
  Deadline := FuzzDeadline('fuzzasdu');
  repeat
    FuzzOne;
  until GetTickCount64 >= Deadline;
  WriteLn(Format('%d ASDUs encoded, %d refused, %d decoded, %d accepted, %d round trips checked, %d failures',
    [Encoded, Refused, Decoded, Accepted, Checked, Failures]));
  if (Encoded = 0) or (Refused = 0) or (Checked = 0) then
  begin
    WriteLn('FAIL nothing was encoded, refused or checked: the run checked nothing');
    Inc(Failures);
  end;
  if Failures > 0 then
    Halt(1);
end.
