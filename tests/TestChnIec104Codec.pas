{ Tests of ChnIec104Codec: APDUs worked out by hand from IEC 60870-5-104
  clause 5 (start 68h, length, four control octets; N(S) and N(R) are the
  15-bit numbers shifted left by one over octets 1..2 and 3..4), every
  refusal, and a random round trip. }
unit TestChnIec104Codec;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnIec104Codec, TestSupport;

type
  TTestChnIec104Codec = class(TTestCase)
  published
    procedure TestUFramesByHand;
    procedure TestSFrameByHand;
    procedure TestIFrameInterrogationByHand;
    procedure TestIFrameHighestNumbers;
    procedure TestDecodeIFrame;
    procedure TestFeedCollectsOneApdu;
    procedure TestFeedRefusesStartAndLength;
    procedure TestDecodeRefusals;
    procedure TestEncodeRefusals;
    procedure TestSeqDiffWraps;
    procedure TestConOfEveryAct;
    procedure TestRandomRoundTrip;
  end;

implementation

function Enc(Kind: Char; A, B: Word; const Asdu: string = ''): string;
var
  Out: array[0..Apci104MaxApdu - 1] of Byte;
  N: Word;
  D: TBytes;
begin
  case Kind of
    'U': Apci104EncodeU(A, Out, N);
    'S': Apci104EncodeS(A, Out, N);
  else
    begin
      D := HexToBytes(Asdu);
      if Apci104EncodeI(A, B, D, Length(D), Out, N) <> res_Ok then
        Exit('refused');
    end;
  end;
  Result := BytesToHex(Out, N);
end;

procedure TTestChnIec104Codec.TestUFramesByHand;
begin
  { octet 1 = 03h + the function bit: STARTDT act 04, con 08, STOPDT act
    10, con 20, TESTFR act 40, con 80 }
  AssertEquals('STARTDT act', '68 04 07 00 00 00', Enc('U', U104StartDtAct, 0));
  AssertEquals('STARTDT con', '68 04 0B 00 00 00', Enc('U', U104StartDtCon, 0));
  AssertEquals('STOPDT act', '68 04 13 00 00 00', Enc('U', U104StopDtAct, 0));
  AssertEquals('STOPDT con', '68 04 23 00 00 00', Enc('U', U104StopDtCon, 0));
  AssertEquals('TESTFR act', '68 04 43 00 00 00', Enc('U', U104TestFrAct, 0));
  AssertEquals('TESTFR con', '68 04 83 00 00 00', Enc('U', U104TestFrCon, 0));
end;

procedure TTestChnIec104Codec.TestSFrameByHand;
begin
  { N(R) = 5: 5 shl 1 = 0Ah in octet 3 }
  AssertEquals('N(R)=5', '68 04 01 00 0A 00', Enc('S', 5, 0));
  { N(R) = 300: 600 = 258h: octet 3 = 58h, octet 4 = 300 shr 7 = 2 }
  AssertEquals('N(R)=300', '68 04 01 00 58 02', Enc('S', 300, 0));
end;

procedure TTestChnIec104Codec.TestIFrameInterrogationByHand;
begin
  { C_IC_NA_1 (100), one object, COT 6, OA 0, CA 1, IOA 0, QOI 20: ten
    octets of ASDU, length 14 = 0Eh; N(S) = 0, N(R) = 0 }
  AssertEquals('first', '68 0E 00 00 00 00 64 01 06 00 01 00 00 00 00 14',
    Enc('I', 0, 0, '64 01 06 00 01 00 00 00 00 14'));
  { N(S) = 3 (06 00), N(R) = 129 (258 = 0102h: 02 01) }
  AssertEquals('N(S)=3 N(R)=129', '68 0E 06 00 02 01 64 01 06 00 01 00 00 00 00 14',
    Enc('I', 3, 129, '64 01 06 00 01 00 00 00 00 14'));
end;

procedure TTestChnIec104Codec.TestIFrameHighestNumbers;
begin
  { N(S) = 32767: 65534 = FFFEh -> FE FF; N(R) = 16384: 32768 = 8000h ->
    00 80 }
  AssertEquals('32767/16384', '68 05 FE FF 00 80 AA', Enc('I', 32767, 16384, 'AA'));
  { numbers count modulo 32768: 32768 is 0 }
  AssertEquals('wraps', '68 05 00 00 02 00 AA', Enc('I', 32768, 1, 'AA'));
end;

procedure TTestChnIec104Codec.TestDecodeIFrame;
var
  B: TBytes;
  A: tApci104;
  E: ShortString;
begin
  B := HexToBytes('68 0E 06 00 02 01 64 01 06 00 01 00 00 00 00 14');
  AssertEquals(res_Ok, Apci104Decode(B, Length(B), A, E));
  AssertTrue('I', A.Format = af104I);
  AssertEquals('N(S)', 3, A.Ns);
  AssertEquals('N(R)', 129, A.Nr);
  AssertEquals('text', 'I N(S)=3 N(R)=129', Apci104Text(A));
  B := HexToBytes('68 04 01 00 58 02');
  AssertEquals(res_Ok, Apci104Decode(B, Length(B), A, E));
  AssertTrue('S', A.Format = af104S);
  AssertEquals('S N(R)', 300, A.Nr);
  B := HexToBytes('68 04 83 00 00 00');
  AssertEquals(res_Ok, Apci104Decode(B, Length(B), A, E));
  AssertEquals('U text', 'U TESTFR con', Apci104Text(A));
end;

procedure TTestChnIec104Codec.TestFeedCollectsOneApdu;
var
  F: tApci104Feed;
  B: TBytes;
  I: Integer;
  Ev: tApci104FeedEvent;
begin
  B := HexToBytes('68 05 00 00 00 00 AA 68 04 07 00 00 00');
  Apci104FeedReset(F);
  for I := 0 to 5 do
    AssertTrue('not yet ' + IntToStr(I), Apci104Feed(F, B[I]) = fe104None);
  AssertTrue('whole I frame', Apci104Feed(F, B[6]) = fe104Apdu);
  AssertEquals('its length', 7, F.Pos);
  Apci104FeedReset(F);
  Ev := fe104None;
  for I := 7 to 12 do
    Ev := Apci104Feed(F, B[I]);
  AssertTrue('whole U frame', Ev = fe104Apdu);
  AssertEquals('STARTDT act', U104StartDtAct, F.Buf[2]);
end;

procedure TTestChnIec104Codec.TestFeedRefusesStartAndLength;
var
  F: tApci104Feed;
begin
  Apci104FeedReset(F);
  AssertTrue('67h', Apci104Feed(F, $67) = fe104Error);
  AssertEquals('start', res_ApciStart, F.Error);
  AssertEquals('the octet', $67, F.Bad);
  Apci104FeedReset(F);
  Apci104Feed(F, $68);
  AssertTrue('length 3', Apci104Feed(F, 3) = fe104Error);
  AssertEquals(res_ApciLength, F.Error);
  Apci104FeedReset(F);
  Apci104Feed(F, $68);
  AssertTrue('length 254', Apci104Feed(F, 254) = fe104Error);
  AssertEquals(res_ApciLength, F.Error);
  Apci104FeedReset(F);
  Apci104Feed(F, $68);
  AssertTrue('length 253 is good', Apci104Feed(F, 253) = fe104None);
end;

procedure TTestChnIec104Codec.TestDecodeRefusals;

  procedure Bad(const HexText: string; R: tChResult; const Part: string);
  var
    B: TBytes;
    A: tApci104;
    E: ShortString;
  begin
    B := HexToBytes(HexText);
    AssertEquals(HexText, R, Apci104Decode(B, Length(B), A, E));
    AssertTrue(HexText + ': ' + E, Pos(Part, E) > 0);
  end;

begin
  Bad('68 04 47 00 00 00', res_ApciControl, 'exactly one function');   { STARTDT + TESTFR act }
  Bad('68 04 03 00 00 00', res_ApciControl, 'exactly one function');   { none }
  Bad('68 04 07 00 01 00', res_ApciControl, '07 00 01 00');
  Bad('68 04 01 01 00 00', res_ApciControl, 'S format');
  Bad('68 04 01 00 01 00', res_ApciControl, 'S format');
  Bad('68 05 01 00 00 00 AA', res_ApciLength, 'S format with 1');
  Bad('68 05 07 00 00 00 AA', res_ApciLength, 'U format with 1');
  Bad('68 04 00 00 00 00', res_ApciLength, 'without an ASDU');
  Bad('68 05 00 00 01 00 AA', res_ApciControl, 'bit 0');
  Bad('68 05 00 00 00 00', res_ApciLength, '6 octets');                 { length says 7 }
end;

procedure TTestChnIec104Codec.TestEncodeRefusals;
var
  Big: array[0..300] of Byte;
  Out: array[0..Apci104MaxApdu - 1] of Byte;
  Small: array[0..9] of Byte;
  N: Word;
begin
  FillChar(Big, SizeOf(Big), 1);
  AssertEquals('249 fits', res_Ok, Apci104EncodeI(0, 0, Big, 249, Out, N));
  AssertEquals('253 on the wire', 253, Out[1]);
  AssertEquals('255 octets', 255, N);
  AssertEquals('250 does not', res_BadLen, Apci104EncodeI(0, 0, Big, 250, Out, N));
  AssertEquals('empty', res_BadLen, Apci104EncodeI(0, 0, Big, 0, Out, N));
  AssertEquals('no room', res_TooLong, Apci104EncodeI(0, 0, Big, 5, Small, N));
  AssertEquals('nothing', 0, N);
end;

procedure TTestChnIec104Codec.TestSeqDiffWraps;
begin
  AssertEquals(0, Seq104Diff(5, 5));
  AssertEquals(3, Seq104Diff(8, 5));
  AssertEquals('across the wrap', 2, Seq104Diff(1, 32767));
  AssertEquals('behind', 32767, Seq104Diff(4, 5));
end;

procedure TTestChnIec104Codec.TestConOfEveryAct;
begin
  AssertEquals(U104StartDtCon, Apci104ConOf(U104StartDtAct));
  AssertEquals(U104StopDtCon, Apci104ConOf(U104StopDtAct));
  AssertEquals(U104TestFrCon, Apci104ConOf(U104TestFrAct));
end;

procedure TTestChnIec104Codec.TestRandomRoundTrip;
var
  I, J, L: Integer;
  Asdu: array[0..Apci104MaxAsdu - 1] of Byte;
  Out: array[0..Apci104MaxApdu - 1] of Byte;
  N: Word;
  Ns, Nr: Word;
  F: tApci104Feed;
  A: tApci104;
  E: ShortString;
  Ev: tApci104FeedEvent;
begin
  RandSeed := 104;
  for I := 1 to 2000 do
  begin
    L := 1 + Random(Apci104MaxAsdu);
    for J := 0 to L - 1 do
      Asdu[J] := Random(256);
    Ns := Random(32768);
    Nr := Random(32768);
    AssertEquals(res_Ok, Apci104EncodeI(Ns, Nr, Asdu, L, Out, N));
    Apci104FeedReset(F);
    Ev := fe104None;
    for J := 0 to N - 1 do
    begin
      AssertTrue('no early end', Ev = fe104None);
      Ev := Apci104Feed(F, Out[J]);
    end;
    AssertTrue('whole', Ev = fe104Apdu);
    AssertEquals(res_Ok, Apci104Decode(F.Buf, F.Pos, A, E));
    AssertEquals('N(S)', Ns, A.Ns);
    AssertEquals('N(R)', Nr, A.Nr);
    AssertTrue('ASDU', CompareByte(F.Buf[6], Asdu[0], L) = 0);
  end;
end;

initialization
  RegisterTest(TTestChnIec104Codec);
end.
