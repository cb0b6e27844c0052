{ Tests of ChnFT12Codec: frames worked out by hand from IEC 60870-5-1/-2/-101,
  every receive error path, address filter, line-idle gap and random round
  trips (fixed RandSeed). Expected bytes are literal hex from the standard's
  rules, never produced by the codec. }
unit TestChnFT12Codec;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnFT12Codec, TestSupport;

type
  TTestChnFT12Codec = class(TTestCase)
  private
    function Cfg(Primary: Boolean; AddrLen, FixedLen: Byte): tFT12Config;
    function Enc(const C: tFT12Config; const Rec: tFT12Record; Len, Addr: Word): string;
    { feed all bytes at time Now; the events, one letter each: F frame,
      E error, '.' nothing }
    function FeedAll(var S: tFT12Rx; const Hex: string; Now: QWord = 0): string;
  published
    procedure TestRecordLayout;
    procedure TestIec101RequestLinkStatus;
    procedure TestIec101ResetRemoteLink;
    procedure TestIec101StatusOfLinkReply;
    procedure TestIec101RequestClass2WithFcb;
    procedure TestIec101GeneralInterrogationVariableFrame;
    procedure TestTwoOctetAddressLittleEndian;
    procedure TestBalancedDirBit;
    procedure TestBalancedReceiveBothPrmAndDirCheck;
    procedure TestUnbalancedSendsResAsZero;
    procedure TestFixedFrameOfManualDefaultLen4;
    procedure TestSingleCharacters;
    procedure TestEveryFCAndControlBitRoundTrips;
    procedure TestEncodeErrors;
    procedure TestEncodeDoesNotWritePastDest;
    procedure TestDecodeHandWorkedFrames;
    procedure TestErrChecksum;
    procedure TestErrLenBytesDiffer;
    procedure TestErrLenTooSmall;
    procedure TestErrLenTooLarge;
    procedure TestErrFrameSecondStart;
    procedure TestErrFrameMissingEnd;
    procedure TestErrCodePrmRole;
    procedure TestResyncOnNextStartCharacter;
    procedure TestSlaveFilterOwnAndBroadcast;
    procedure TestSlaveIgnoresSingleCharacters;
    procedure TestGapDiscardsHalfFrame;
    procedure TestGetRecordBufferTooSmall;
    procedure TestFixedLenAboveMaxIsRefused;
    procedure TestSingleByteCorruptionNeverAccepted;
    procedure TestRandomRecordsRoundTrip;
    procedure TestRandomNoiseIsSafe;
  end;

implementation

function TTestChnFT12Codec.Cfg(Primary: Boolean; AddrLen, FixedLen: Byte): tFT12Config;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Primary := Primary;
  Result.AddrLen := AddrLen;
  Result.FixedLen := FixedLen;
  Result.CheckPrm := True;
end;

function TTestChnFT12Codec.Enc(const C: tFT12Config; const Rec: tFT12Record;
  Len, Addr: Word): string;
var
  Buf: array[0..cFT12MaxFrame - 1] of Byte;
  N: Word;
  R: tChResult;
begin
  N := 0;
  R := FT12Encode(C, Rec, Len, Addr, @Buf, SizeOf(Buf), N);
  AssertEquals('encode result', res_Ok, R);
  Result := BytesToHex(Buf, N);
end;

function TTestChnFT12Codec.FeedAll(var S: tFT12Rx; const Hex: string; Now: QWord): string;
var
  B: TBytes;
  I: Integer;
begin
  B := HexToBytes(Hex);
  Result := '';
  for I := 0 to High(B) do
    case FT12Feed(S, B[I], Now) of
      fe_None: Result := Result + '.';
      fe_Frame: Result := Result + 'F';
      fe_Error: Result := Result + 'E';
    end;
end;

function MakeRec(T: tMessType; FCB, FCV: Boolean; FC: Byte): tFT12Record;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.MessType := T;
  Result.FCB_ACD := FCB;
  Result.FCV_DFC := FCV;
  Result.FC := FC;
end;

function NewRx(const C: tFT12Config): tFT12Rx;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Cfg := C;
  FT12RxReset(Result);
end;

procedure TTestChnFT12Codec.TestRecordLayout;
var
  R: tFT12Record;
begin
  AssertEquals('SizeOf(tMessType)', 1, SizeOf(tMessType));
  AssertEquals('SizeOf(tFT12Record)', 4 + 247, SizeOf(tFT12Record));
  AssertEquals('MessType@0', 0, PtrUInt(@R.MessType) - PtrUInt(@R));
  AssertEquals('FCB_ACD@1', 1, PtrUInt(@R.FCB_ACD) - PtrUInt(@R));
  AssertEquals('FCV_DFC@2', 2, PtrUInt(@R.FCV_DFC) - PtrUInt(@R));
  AssertEquals('FC@3', 3, PtrUInt(@R.FC) - PtrUInt(@R));
  AssertEquals('Data[1]@4', 4, PtrUInt(@R.Data[1]) - PtrUInt(@R));
  AssertEquals('cSizeHeadSndMsg', 4, cSizeHeadSndMsg);
  AssertEquals('tpLongM = 3', 3, Ord(tpLongM));
end;

procedure TTestChnFT12Codec.TestIec101RequestLinkStatus;
begin
  { IEC 101 request status of link (FC 9) to address 1, FCV = 0:
    CODE = PRM $40 + FC 9 = $49; CS = $49 + $01 = $4A }
  AssertEquals('10 49 01 4A 16',
    Enc(Cfg(True, 1, 0), MakeRec(tpShortM, False, False, 9), 4, 1));
end;

procedure TTestChnFT12Codec.TestIec101ResetRemoteLink;
begin
  { reset of remote link (FC 0) to address 1: CODE = $40; CS = $40 + $01 }
  AssertEquals('10 40 01 41 16',
    Enc(Cfg(True, 1, 0), MakeRec(tpShortM, False, False, 0), 4, 1));
end;

procedure TTestChnFT12Codec.TestIec101StatusOfLinkReply;
begin
  { secondary answers status of link (FC 11), ACD = DFC = 0, address 1:
    CODE = $0B; CS = $0B + $01 = $0C }
  AssertEquals('10 0B 01 0C 16',
    Enc(Cfg(False, 1, 0), MakeRec(tpShortM, False, False, 11), 4, 1));
  { with ACD = 1 (class 1 data waiting): CODE = $20 + $08 = $28 for user
    data; CS = $28 + $01 = $29 }
  AssertEquals('10 28 01 29 16',
    Enc(Cfg(False, 1, 0), MakeRec(tpShortM, True, False, 8), 4, 1));
end;

procedure TTestChnFT12Codec.TestIec101RequestClass2WithFcb;
begin
  { request class 2 data (FC 11), FCB = 1, FCV = 1, address 1:
    CODE = $40 + $20 + $10 + $0B = $7B; CS = $7B + $01 = $7C }
  AssertEquals('10 7B 01 7C 16',
    Enc(Cfg(True, 1, 0), MakeRec(tpShortM, True, True, 11), 4, 1));
end;

procedure TTestChnFT12Codec.TestIec101GeneralInterrogationVariableFrame;
var
  R: tFT12Record;
  D: TBytes;
begin
  { user data with confirm (FC 3), FCB = 1, FCV = 1, address 1, carrying a
    general interrogation ASDU C_IC_NA_1: type $64, VSQ $01, COT 6 (2
    octets: 06 00), common address 1 (01 00), IOA 0 (00 00 00), QOI 20 ($14).
    CODE = $40 + $20 + $10 + 3 = $73. L = CODE + ADDR + 10 data = 12 = $0C.
    CS = $73 + $01 + ($64 + $01 + $06 + $01 + $14 = $80) = $F4 }
  R := MakeRec(tpLongM, True, True, 3);
  D := HexToBytes('64 01 06 00 01 00 00 00 00 14');
  Move(D[0], R.Data[1], 10);
  AssertEquals('68 0C 0C 68 73 01 64 01 06 00 01 00 00 00 00 14 F4 16',
    Enc(Cfg(True, 1, 0), R, 4 + 10, 1));
end;

procedure TTestChnFT12Codec.TestTwoOctetAddressLittleEndian;
var
  R: tFT12Record;
begin
  { request status of link to address $0102 = 258 with 2 address octets,
    low octet first: CS = $49 + $02 + $01 = $4C }
  AssertEquals('10 49 02 01 4C 16',
    Enc(Cfg(True, 2, 0), MakeRec(tpShortM, False, False, 9), 4, 258));
  { variable frame, 2 octets, secondary user data (FC 8) from $1234 with
    data AA: L = 1 + 2 + 1 = 4; CS = $08 + $34 + $12 + $AA = $F8 }
  R := MakeRec(tpLongM, False, False, 8);
  R.Data[1] := $AA;
  AssertEquals('68 04 04 68 08 34 12 AA F8 16',
    Enc(Cfg(False, 2, 0), R, 5, $1234));
end;

procedure TTestChnFT12Codec.TestBalancedDirBit;
var
  C: tFT12Config;
begin
  { balanced, controlling station (DIR = 1), reset of remote link to
    address 1: CODE = $80 + $40 + 0 = $C0; CS = $C0 + $01 = $C1 }
  C := Cfg(True, 1, 0);
  C.Balanced := True;
  C.Dir := True;
  AssertEquals('10 C0 01 C1 16', Enc(C, MakeRec(tpShortM, False, False, 0), 4, 1));
  { the secondary of the other station (DIR = 0) answers ACK (FC 0),
    address 1: CODE = $00, CS = $01 }
  C := Cfg(False, 1, 0);
  C.Balanced := True;
  AssertEquals('10 00 01 01 16', Enc(C, MakeRec(tpShortM, False, False, 0), 4, 1));
end;

procedure TTestChnFT12Codec.TestBalancedReceiveBothPrmAndDirCheck;
var
  S: tFT12Rx;
  C: tFT12Config;
begin
  { station B (DIR = 0), own address 2, as the channel sets it up }
  C := Cfg(False, 1, 0);
  C.Balanced := True;
  C.CheckPrm := False;
  C.CheckDir := True;
  C.Filter := True;
  C.OwnAddr := 2;
  S := NewRx(C);
  { A's request to 2 (C9 + 02 = CB) and A's ACK from 1 (80 + 01 = 81) }
  AssertEquals('....F', FeedAll(S, '10 C9 02 CB 16'));
  AssertEquals('....F', FeedAll(S, '10 80 01 81 16'));
  AssertEquals('F', FeedAll(S, 'E5'));
  { a request for 3 is ignored; an answer from 3 is not (the peer's) }
  AssertEquals('.....', FeedAll(S, '10 C9 03 CC 16'));
  AssertEquals(1, S.Ignored);
  AssertEquals('....F', FeedAll(S, '10 80 03 83 16'));
  { DIR = 0 is B's own side, in either direction }
  AssertEquals('....E', FeedAll(S, '10 49 02 4B 16'));
  AssertEquals(res_ErrDir, S.Err);
  AssertEquals('....E', FeedAll(S, '10 00 01 01 16'));
  AssertEquals(res_ErrDir, S.Err);
  { without CheckDir (a line monitor) both pass }
  S.Cfg.CheckDir := False;
  AssertEquals('....F', FeedAll(S, '10 49 02 4B 16'));
end;

procedure TTestChnFT12Codec.TestUnbalancedSendsResAsZero;
var
  C: tFT12Config;
begin
  { DIR set but unbalanced: bit 7 is RES and stays 0 }
  C := Cfg(True, 1, 0);
  C.Dir := True;
  AssertEquals('10 49 01 4A 16', Enc(C, MakeRec(tpShortM, False, False, 9), 4, 1));
end;

procedure TTestChnFT12Codec.TestFixedFrameOfManualDefaultLen4;
var
  R: tFT12Record;
begin
  { manual default LEN=4: master user data (FC 3) to address 5, data
    11 22 33 44: CODE $43, CS = $43+$05+$11+$22+$33+$44 = $F2 }
  R := MakeRec(tpShortM, False, False, 3);
  R.Data[1] := $11; R.Data[2] := $22; R.Data[3] := $33; R.Data[4] := $44;
  AssertEquals('10 43 05 11 22 33 44 F2 16', Enc(Cfg(True, 1, 4), R, 8, 5));
  { no address octets: CS = $43+$11+$22+$33+$44 = $ED }
  AssertEquals('10 43 11 22 33 44 ED 16', Enc(Cfg(True, 0, 4), R, 8, 5));
end;

procedure TTestChnFT12Codec.TestSingleCharacters;
var
  R: tFT12Record;
  B: array[0..3] of Byte;
  N: Word;
begin
  AssertEquals('E5', Enc(Cfg(False, 1, 0), MakeRec(tpSACK, False, False, 0), 1, 1));
  AssertEquals('A2', Enc(Cfg(False, 1, 0), MakeRec(tpSNAK, False, False, 0), 1, 1));
  { Len is ignored for single characters }
  AssertEquals('E5', Enc(Cfg(False, 1, 0), MakeRec(tpSACK, False, False, 0), 200, 1));
  { a master/primary never sends them }
  R := MakeRec(tpSACK, False, False, 0);
  N := 99;
  AssertEquals(res_BadMessage, FT12Encode(Cfg(True, 1, 0), R, 1, 1, @B, 4, N));
  AssertEquals(0, N);
  { Len 0 is fine for them too (the manual: Len is ignored); no room for
    the one byte is res_TooLong }
  AssertEquals('E5', Enc(Cfg(False, 1, 0), MakeRec(tpSACK, False, False, 0), 0, 1));
  AssertEquals('A2', Enc(Cfg(False, 1, 0), MakeRec(tpSNAK, False, False, 0), 0, 1));
  B[0] := $CC;
  N := 99;
  AssertEquals('DestSize 0', res_TooLong, FT12Encode(Cfg(False, 1, 0), R, 1, 1, @B, 0, N));
  AssertEquals(0, N);
  AssertEquals('nothing written', $CC, B[0]);
end;

procedure TTestChnFT12Codec.TestEveryFCAndControlBitRoundTrips;
var
  FC, Bits: Integer;
  Prim: Boolean;
  C: tFT12Config;
  R, Got: tFT12Record;
  Buf: array[0..31] of Byte;
  N, Len: Word;
  S: tFT12Rx;
  I: Integer;
  Ev: tFT12Event;
  Expect: Byte;
begin
  for Prim := False to True do
    for FC := 0 to 15 do
      for Bits := 0 to 3 do
      begin
        C := Cfg(Prim, 1, 0);
        R := MakeRec(tpShortM, Bits and 1 <> 0, Bits and 2 <> 0, FC);
        AssertEquals(res_Ok, FT12Encode(C, R, 4, 7, @Buf, SizeOf(Buf), N));
        AssertEquals('length', 5, N);
        { CODE by the table of manual 6.1.1 }
        Expect := FC or (Bits and 1) * $20 or (Bits and 2) * $08 or Ord(Prim) * $40;
        AssertEquals('CODE', Expect, Buf[1]);
        C.Primary := not Prim;
        S := NewRx(C);
        Ev := fe_None;
        for I := 0 to N - 1 do
          Ev := FT12Feed(S, Buf[I], 0);
        AssertTrue('frame', Ev = fe_Frame);
        AssertEquals(res_Ok, FT12GetRecord(S, @Got, SizeOf(Got), Len));
        AssertEquals('Len', 4, Len);
        AssertEquals('FC', FC, Got.FC);
        AssertEquals('FCB_ACD', R.FCB_ACD, Got.FCB_ACD);
        AssertEquals('FCV_DFC', R.FCV_DFC, Got.FCV_DFC);
        AssertEquals('PRM', Prim, FT12FramePrm(S));
        AssertEquals('address', 7, S.Addr);
      end;
end;

procedure TTestChnFT12Codec.TestEncodeErrors;
var
  R: tFT12Record;
  B: array[0..cFT12MaxFrame - 1] of Byte;
  N: Word;
begin
  R := MakeRec(tpLongM, False, False, 3);
  N := 1;
  AssertEquals('Len 0', res_BadLen, FT12Encode(Cfg(True, 1, 0), R, 0, 1, @B, SizeOf(B), N));
  AssertEquals('Len below header', res_BadLen, FT12Encode(Cfg(True, 1, 0), R, 3, 1, @B, SizeOf(B), N));
  AssertEquals('too much data', res_TooLong,
    FT12Encode(Cfg(True, 1, 0), R, 4 + MaxDataLen + 1, 1, @B, SizeOf(B), N));
  AssertEquals('MaxDataLen fits', res_Ok,
    FT12Encode(Cfg(True, 2, 0), R, 4 + MaxDataLen, 1, @B, SizeOf(B), N));
  AssertEquals('longest frame', cFT12MaxFrame, N);
  R.MessType := tpShortM;
  AssertEquals('fixed frame with other than LEN data', res_BadLen,
    FT12Encode(Cfg(True, 1, 0), R, 5, 1, @B, SizeOf(B), N));
  R.FC := 16;
  AssertEquals('FC 16', res_BadMessage, FT12Encode(Cfg(True, 1, 0), R, 4, 1, @B, SizeOf(B), N));
  R.FC := 0;
  PByte(@R.MessType)^ := 4;
  AssertEquals('MessType 4', res_BadMessage, FT12Encode(Cfg(True, 1, 0), R, 4, 1, @B, SizeOf(B), N));
  R.MessType := tpShortM;
  AssertEquals('address 256, 1 octet', res_BadMessage,
    FT12Encode(Cfg(True, 1, 0), R, 4, 256, @B, SizeOf(B), N));
  AssertEquals('address 256, 2 octets', res_Ok,
    FT12Encode(Cfg(True, 2, 0), R, 4, 256, @B, SizeOf(B), N));
  AssertEquals('no address: any value', res_Ok,
    FT12Encode(Cfg(True, 0, 0), R, 4, 999, @B, SizeOf(B), N));
  FT12Encode(Cfg(True, 1, 0), R, 0, 1, @B, SizeOf(B), N);
  AssertEquals('DestLen 0 after an error', 0, N);
end;

procedure TTestChnFT12Codec.TestEncodeDoesNotWritePastDest;
var
  R: tFT12Record;
  B: array[0..7] of Byte;
  N: Word;
  I: Integer;
begin
  FillChar(B, SizeOf(B), $CC);
  R := MakeRec(tpShortM, False, False, 9);
  { 10 49 01 4A 16 needs 5 bytes; give 4 }
  AssertEquals(res_TooLong, FT12Encode(Cfg(True, 1, 0), R, 4, 1, @B, 4, N));
  AssertEquals(0, N);
  for I := 0 to 7 do
    AssertEquals('untouched', $CC, B[I]);
end;

procedure TTestChnFT12Codec.TestDecodeHandWorkedFrames;
var
  S: tFT12Rx;
  R: tFT12Record;
  Len: Word;
begin
  S := NewRx(Cfg(False, 1, 0));
  AssertEquals('....F', FeedAll(S, '10 49 01 4A 16'));
  AssertEquals(res_Ok, FT12GetRecord(S, @R, SizeOf(R), Len));
  AssertTrue(R.MessType = tpShortM);
  AssertEquals(9, R.FC);
  AssertEquals(False, R.FCB_ACD);
  AssertEquals(4, Len);
  S := NewRx(Cfg(True, 1, 0));
  { user data from secondary 1: CODE $08, ASDU 64 01 07 00 01 00 00 00 00 14
    (activation confirmation): CS = $08 + $01 + $64 + $01 + $07 + $01 + $14 = $8A }
  AssertEquals('.................F',
    FeedAll(S, '68 0C 0C 68 08 01 64 01 07 00 01 00 00 00 00 14 8A 16'));
  AssertEquals(res_Ok, FT12GetRecord(S, @R, SizeOf(R), Len));
  AssertTrue(R.MessType = tpLongM);
  AssertEquals(8, R.FC);
  AssertEquals(14, Len);
  AssertEquals($64, R.Data[1]);
  AssertEquals($14, R.Data[10]);
  AssertEquals(1, S.Addr);
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('.........F', FeedAll(S, '68 04 04 68 08 34 12 AA F8 16'));
  AssertEquals($1234, S.Addr);
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('F', FeedAll(S, 'E5'));
  AssertTrue(S.Kind = tpSACK);
  AssertEquals(res_Ok, FT12GetRecord(S, @R, 1, Len));
  AssertEquals('single character Len', 1, Len);
  AssertEquals('F', FeedAll(S, 'A2'));
  AssertTrue(S.Kind = tpSNAK);
end;

procedure TTestChnFT12Codec.TestErrChecksum;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(False, 1, 0));
  AssertEquals('...E.', FeedAll(S, '10 49 01 4B 16'));
  AssertEquals(res_ErrSum, S.Err);
  { right sum is $F8 ($08 + $34 + $12 + $AA) }
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('........E.', FeedAll(S, '68 04 04 68 08 34 12 AA F9 16'));
  AssertEquals(res_ErrSum, S.Err);
end;

procedure TTestChnFT12Codec.TestErrLenBytesDiffer;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('..E', FeedAll(S, '68 03 04'));
  AssertEquals(res_ErrLen, S.Err);
end;

procedure TTestChnFT12Codec.TestErrLenTooSmall;
var
  S: tFT12Rx;
begin
  { L must hold at least CODE + ADDR: 2 with one address octet }
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('..E', FeedAll(S, '68 01 01'));
  AssertEquals(res_ErrLen, S.Err);
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('..E', FeedAll(S, '68 02 02'));
  AssertEquals(res_ErrLen, S.Err);
  { L = 0 }
  S := NewRx(Cfg(True, 0, 0));
  AssertEquals('..E', FeedAll(S, '68 00 00'));
  { L = 1 is the smallest with no address: CODE only, CS = CODE }
  S := NewRx(Cfg(True, 0, 0));
  AssertEquals('......F', FeedAll(S, '68 01 01 68 0B 0B 16'));
end;

procedure TTestChnFT12Codec.TestErrLenTooLarge;
var
  S: tFT12Rx;
begin
  { 1 address octet: L <= 1 + 1 + 247 = 249 = $F9 }
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('..E', FeedAll(S, '68 FA FA'));
  AssertEquals(res_ErrLen, S.Err);
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('...', FeedAll(S, '68 F9 F9'));
  { 2 octets: 250 is allowed, 251 not }
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('...', FeedAll(S, '68 FA FA'));
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('..E', FeedAll(S, '68 FB FB'));
end;

procedure TTestChnFT12Codec.TestErrFrameSecondStart;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('...E', FeedAll(S, '68 03 03 69'));
  AssertEquals(res_ErrFrame, S.Err);
end;

procedure TTestChnFT12Codec.TestErrFrameMissingEnd;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(False, 1, 0));
  AssertEquals('....E', FeedAll(S, '10 49 01 4A 17'));
  AssertEquals(res_ErrFrame, S.Err);
  S := NewRx(Cfg(True, 2, 0));
  AssertEquals('.........E', FeedAll(S, '68 04 04 68 08 34 12 AA F8 00'));
  AssertEquals(res_ErrFrame, S.Err);
end;

procedure TTestChnFT12Codec.TestErrCodePrmRole;
var
  S: tFT12Rx;
begin
  { a master receives a frame with PRM = 1 }
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('....E', FeedAll(S, '10 49 01 4A 16'));
  AssertEquals(res_ErrCode, S.Err);
  { a slave (no filter here) receives PRM = 0 }
  S := NewRx(Cfg(False, 1, 0));
  AssertEquals('....E', FeedAll(S, '10 0B 01 0C 16'));
  AssertEquals(res_ErrCode, S.Err);
  { with CheckPrm off (a line monitor) both pass }
  S := NewRx(Cfg(True, 1, 0));
  S.Cfg.CheckPrm := False;
  AssertEquals('....F', FeedAll(S, '10 49 01 4A 16'));
end;

procedure TTestChnFT12Codec.TestResyncOnNextStartCharacter;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(False, 1, 0));
  { junk, a frame with a wrong checksum, more junk, then a good frame }
  AssertEquals('.....' + '...E.' + '..' + '....F',
    FeedAll(S, '00 FF 16 4A 01' + ' 10 49 01 4B 16' + ' 33 44' + ' 10 7B 01 7C 16'));
  AssertEquals($7B, S.Code);
  { bad L, then a good frame at once }
  AssertEquals('..E' + '....F', FeedAll(S, '68 05 06' + ' 10 49 01 4A 16'));
  AssertEquals(2, S.Errors);
  AssertEquals(2, S.Frames);
end;

procedure TTestChnFT12Codec.TestSlaveFilterOwnAndBroadcast;
var
  S: tFT12Rx;
  C: tFT12Config;
begin
  C := Cfg(False, 1, 0);
  C.Filter := True;
  C.OwnAddr := 1;
  S := NewRx(C);
  { to address 2: CS = $49 + $02 = $4B -> ignored }
  AssertEquals('.....', FeedAll(S, '10 49 02 4B 16'));
  AssertEquals(1, S.Ignored);
  AssertEquals('....F', FeedAll(S, '10 49 01 4A 16'));
  { broadcast 255, user data no reply (FC 4): CS = $44 + $FF = $43 }
  AssertEquals('....F', FeedAll(S, '10 44 FF 43 16'));
  AssertEquals($FF, S.Addr);
  { an other secondary's answer from address 2 is ignored, not an error }
  AssertEquals('.....', FeedAll(S, '10 0B 02 0D 16'));
  AssertEquals(0, S.Errors);
  { 2 octets: broadcast is $FFFF; $00FF is a normal address }
  C.AddrLen := 2;
  C.OwnAddr := 300;
  S := NewRx(C);
  AssertEquals('......', FeedAll(S, '10 44 FF 00 43 16'));
  AssertEquals('.....F', FeedAll(S, '10 44 FF FF 42 16'));
  { 300 = $012C: CS = $49 + $2C + $01 = $76 }
  AssertEquals('.....F', FeedAll(S, '10 49 2C 01 76 16'));
end;

procedure TTestChnFT12Codec.TestSlaveIgnoresSingleCharacters;
var
  S: tFT12Rx;
  C: tFT12Config;
begin
  C := Cfg(False, 1, 0);
  C.Filter := True;
  C.OwnAddr := 1;
  S := NewRx(C);
  AssertEquals('..', FeedAll(S, 'E5 A2'));
  AssertEquals(2, S.Ignored);
  { ignored for what they are, not for their address (they carry none):
    a secondary with link address 0 ignores them as well }
  C.OwnAddr := 0;
  S := NewRx(C);
  AssertEquals('..', FeedAll(S, 'E5 A2'));
  AssertEquals(2, S.Ignored);
  { without a filter (no address field) they do not fit a secondary }
  C.Filter := False;
  S := NewRx(C);
  AssertEquals('E', FeedAll(S, 'E5'));
  AssertEquals(res_ErrCode, S.Err);
end;

procedure TTestChnFT12Codec.TestGapDiscardsHalfFrame;
var
  S: tFT12Rx;
  C: tFT12Config;
begin
  C := Cfg(False, 1, 0);
  C.GapMs := 5;
  S := NewRx(C);
  { 10 49 at t = 100, the rest 10 ms later: the half frame is gone, the
    rest is junk to the hunting receiver }
  AssertEquals('..', FeedAll(S, '10 49', 100));
  AssertEquals('...', FeedAll(S, '01 4A 16', 110));
  AssertEquals(1, S.GapDrops);
  { gaps of exactly GapMs are allowed }
  AssertEquals('..', FeedAll(S, '10 49', 200));
  AssertEquals('.', FeedAll(S, '01', 205));
  AssertEquals('.F', FeedAll(S, '4A 16', 210));
  { a gap between frames does not matter }
  AssertEquals('....F', FeedAll(S, '10 49 01 4A 16', 5000));
  { the same split with the gap off makes one frame }
  C.GapMs := 0;
  S := NewRx(C);
  AssertEquals('..', FeedAll(S, '10 49', 100));
  AssertEquals('..F', FeedAll(S, '01 4A 16', 110));
end;

procedure TTestChnFT12Codec.TestGetRecordBufferTooSmall;
var
  S: tFT12Rx;
  Buf: array[0..31] of Byte;
  Len: Word;
  I: Integer;
begin
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('.................F',
    FeedAll(S, '68 0C 0C 68 08 01 64 01 07 00 01 00 00 00 00 14 8A 16'));
  FillChar(Buf, SizeOf(Buf), $CC);
  Len := 77;
  { 4 + 10 bytes needed, 13 given }
  AssertEquals(res_ErrLen, FT12GetRecord(S, @Buf, 13, Len));
  AssertEquals(0, Len);
  for I := 0 to High(Buf) do
    AssertEquals('nothing written', $CC, Buf[I]);
  AssertEquals(res_Ok, FT12GetRecord(S, @Buf, 14, Len));
  AssertEquals(14, Len);
  AssertEquals('byte after the record untouched', $CC, Buf[14]);
  AssertEquals(res_NoRecBuff, FT12GetRecord(S, nil, 14, Len));
end;

procedure TTestChnFT12Codec.TestFixedLenAboveMaxIsRefused;
var
  S: tFT12Rx;
begin
  { LEN= stops at 247, but the codec API takes any byte: a fixed frame can
    then never fit the automaton's Data, so it is refused at its start }
  S := NewRx(Cfg(False, 1, 250));
  AssertEquals('E....', FeedAll(S, '10 49 01 4A 16'));
  AssertEquals(res_ErrLen, S.Err);
end;

procedure TTestChnFT12Codec.TestSingleByteCorruptionNeverAccepted;
const
  Frames: array[1..3] of string = (
    '10 49 01 4A 16',
    '10 43 05 11 22 33 44 F2 16',
    '68 0C 0C 68 73 01 64 01 06 00 01 00 00 00 00 14 F4 16');
  Lens: array[1..3] of Byte = (0, 4, 0);
var
  F: TBytes;
  K, Pos, Mask, I: Integer;
  S: tFT12Rx;
  C: tFT12Config;
  Ev: tFT12Event;
begin
  Ev := fe_None;
  for K := 1 to 3 do
  begin
    F := HexToBytes(Frames[K]);
    { the frame itself is accepted, else the loop below proves nothing }
    S := NewRx(Cfg(False, 1, Lens[K]));
    for I := 0 to High(F) do
      Ev := FT12Feed(S, F[I], 0);
    AssertTrue(Format('frame %d accepted uncorrupted', [K]),
      (Ev = fe_Frame) and (S.Kind in [tpShortM, tpLongM]));
    for Pos := 0 to High(F) do
      for Mask := 1 to 255 do
      begin
        C := Cfg(False, 1, Lens[K]);
        S := NewRx(C);
        for I := 0 to High(F) do
          if (FT12Feed(S, F[I] xor Ord(I = Pos) * Mask, 0) = fe_Frame) and
             (S.Kind in [tpShortM, tpLongM]) then
            Fail(Format('frame %d byte %d xor %x accepted', [K, Pos, Mask]));
      end;
  end;
end;

procedure TTestChnFT12Codec.TestRandomRecordsRoundTrip;
var
  Iter, I, N: Integer;
  C: tFT12Config;
  R, Got: tFT12Record;
  Buf: array[0..cFT12MaxFrame - 1] of Byte;
  BLen, Len: Word;
  Addr: Word;
  S: tFT12Rx;
  Frames: Integer;
begin
  RandSeed := 20260521;
  for Iter := 1 to 3000 do
  begin
    C := Cfg(Random(2) = 0, Random(3), Random(20));
    C.Balanced := Random(2) = 0;
    C.Dir := Random(2) = 0;
    FillChar(R, SizeOf(R), 0);
    case Random(4) of
      0: if C.Primary then R.MessType := tpLongM else R.MessType := tpSACK;
      1: if C.Primary then R.MessType := tpShortM else R.MessType := tpSNAK;
      2: R.MessType := tpShortM;
      3: R.MessType := tpLongM;
    end;
    R.FCB_ACD := Random(2) = 0;
    R.FCV_DFC := Random(2) = 0;
    R.FC := Random(16);
    if R.MessType = tpShortM then
      N := C.FixedLen
    else
      N := Random(MaxDataLen + 1);
    for I := 1 to N do
      R.Data[I] := Random(256);
    Addr := Random(FT12MaxAddr(C.AddrLen) + 1);
    AssertEquals('encode', res_Ok, FT12Encode(C, R, 4 + N, Addr, @Buf, SizeOf(Buf), BLen));
    { the peer has the opposite role; noise before the frame }
    C.Primary := not C.Primary;
    S := NewRx(C);
    FT12Feed(S, $00, 0);
    FT12Feed(S, $16, 0);
    Frames := 0;
    for I := 0 to BLen - 1 do
      if FT12Feed(S, Buf[I], 0) = fe_Frame then
      begin
        Inc(Frames);
        AssertEquals('frame ends at the last byte', BLen - 1, I);
      end;
    AssertEquals('one frame', 1, Frames);
    AssertEquals(res_OK, FT12GetRecord(S, @Got, SizeOf(Got), Len));
    AssertTrue('MessType', Got.MessType = R.MessType);
    if R.MessType in [tpSACK, tpSNAK] then
      AssertEquals(1, Len)
    else
    begin
      AssertEquals('Len', 4 + N, Len);
      AssertEquals('FCB_ACD', R.FCB_ACD, Got.FCB_ACD);
      AssertEquals('FCV_DFC', R.FCV_DFC, Got.FCV_DFC);
      AssertEquals('FC', R.FC, Got.FC);
      if C.AddrLen > 0 then
        AssertEquals('address', Addr, S.Addr);
      AssertTrue('data', CompareByte(R.Data, Got.Data, N) = 0);
      AssertEquals('DIR on the line', C.Balanced and C.Dir, S.Code and $80 <> 0);
    end;
  end;
end;

procedure TTestChnFT12Codec.TestRandomNoiseIsSafe;
var
  S: tFT12Rx;
  C: tFT12Config;
  I: Integer;
  R: tFT12Record;
  Len: Word;
  Ev: tFT12Event;
begin
  RandSeed := 4242;
  C := Cfg(True, 1, 4);
  C.CheckPrm := False;
  S := NewRx(C);
  for I := 1 to 200000 do
  begin
    { biased towards start characters so frames start often }
    case Random(8) of
      0: Ev := FT12Feed(S, SD2, I);
      1: Ev := FT12Feed(S, SD1, I);
    else
      Ev := FT12Feed(S, Random(256), I);
    end;
    if Ev = fe_Frame then
    begin
      AssertTrue(S.DataLen <= MaxDataLen);
      AssertEquals(res_Ok, FT12GetRecord(S, @R, SizeOf(R), Len));
    end
    else if Ev = fe_Error then
      AssertTrue((S.Err >= res_ErrSum) and (S.Err <= res_ErrFrame));
  end;
  AssertTrue('some errors seen', S.Errors > 0);
end;

initialization
  RegisterTest(TTestChnFT12Codec);
end.
