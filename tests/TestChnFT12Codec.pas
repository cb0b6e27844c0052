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
    procedure TestEncodeTable;
    procedure TestBalancedReceiveBothPrmAndDirCheck;
    procedure TestSingleCharacters;
    procedure TestEveryFCAndControlBitRoundTrips;
    procedure TestEncodeErrors;
    procedure TestEncodeDoesNotWritePastDest;
    procedure TestDecodeHandWorkedFrames;
    procedure TestReceiveErrorTable;
    procedure TestResyncOnNextStartCharacter;
    procedure TestSingleCharacterAfterGarbageNeedsIdle;
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

type
  { one frame worked out by hand from IEC 60870-5-1/-2/-101 }
  TEncodeCase = record
    What    : string;
    Primary : Boolean;
    AddrLen : Byte;
    FixedLen: Byte;
    Balanced, Dir: Boolean;
    Kind    : tMessType;
    FCB, FCV: Boolean;
    FC      : Byte;
    Data    : string;    { hex, into Data[1..] }
    Len     : Word;
    Addr    : Word;
    Wire    : string;    { the expected bytes }
  end;

const
  EncodeCases: array[0..17] of TEncodeCase = (
    (What: 'IEC 101 request status of link (FC 9) to 1, FCV 0: CODE $40+9, CS $49+$01';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 9; Data: ''; Len: 4; Addr: 1; Wire: '10 49 01 4A 16'),
    (What: 'reset of remote link (FC 0) to 1: CODE $40, CS $41';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 4; Addr: 1; Wire: '10 40 01 41 16'),
    (What: 'secondary status of link (FC 11), ACD = DFC = 0: CODE $0B, CS $0C';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 11; Data: ''; Len: 4; Addr: 1; Wire: '10 0B 01 0C 16'),
    (What: 'secondary user data (FC 8) with ACD = 1: CODE $20+8, CS $29';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: True; FCV: False; FC: 8; Data: ''; Len: 4; Addr: 1; Wire: '10 28 01 29 16'),
    (What: 'request class 2 (FC 11), FCB = FCV = 1: CODE $40+$20+$10+$0B, CS $7C';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: True; FCV: True; FC: 11; Data: ''; Len: 4; Addr: 1; Wire: '10 7B 01 7C 16'),
    (What: 'user data (FC 3) with C_IC_NA_1 (type $64 VSQ 1 COT 6 CA 1 IOA 0 QOI 20): ' +
       'L = 12, CS $73+$01+$80';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpLongM;
     FCB: True; FCV: True; FC: 3; Data: '64 01 06 00 01 00 00 00 00 14'; Len: 14; Addr: 1;
     Wire: '68 0C 0C 68 73 01 64 01 06 00 01 00 00 00 00 14 F4 16'),
    (What: 'two address octets, low first: $0102, CS $49+$02+$01';
     Primary: True; AddrLen: 2; FixedLen: 0; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 9; Data: ''; Len: 4; Addr: 258; Wire: '10 49 02 01 4C 16'),
    (What: 'variable frame from $1234 (2 octets), data AA: L 4, CS $08+$34+$12+$AA';
     Primary: False; AddrLen: 2; FixedLen: 0; Balanced: False; Dir: False; Kind: tpLongM;
     FCB: False; FCV: False; FC: 8; Data: 'AA'; Len: 5; Addr: $1234; Wire: '68 04 04 68 08 34 12 AA F8 16'),
    (What: 'balanced, DIR = 1, reset of remote link: CODE $80+$40, CS $C1';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: True; Dir: True; Kind: tpShortM;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 4; Addr: 1; Wire: '10 C0 01 C1 16'),
    (What: 'balanced, DIR = 0, secondary ACK (FC 0): CODE $00, CS $01';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: True; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 4; Addr: 1; Wire: '10 00 01 01 16'),
    (What: 'unbalanced: DIR set, but bit 7 is RES and stays 0';
     Primary: True; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: True; Kind: tpShortM;
     FCB: False; FCV: False; FC: 9; Data: ''; Len: 4; Addr: 1; Wire: '10 49 01 4A 16'),
    (What: 'manual default LEN=4: user data (FC 3) to 5, 11 22 33 44: CS $F2';
     Primary: True; AddrLen: 1; FixedLen: 4; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 3; Data: '11 22 33 44'; Len: 8; Addr: 5;
     Wire: '10 43 05 11 22 33 44 F2 16'),
    (What: 'LEN=4 without address octets: CS $43+$11+$22+$33+$44';
     Primary: True; AddrLen: 0; FixedLen: 4; Balanced: False; Dir: False; Kind: tpShortM;
     FCB: False; FCV: False; FC: 3; Data: '11 22 33 44'; Len: 8; Addr: 5;
     Wire: '10 43 11 22 33 44 ED 16'),
    (What: 'SACK';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpSACK;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 1; Addr: 1; Wire: 'E5'),
    (What: 'SNAK';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpSNAK;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 1; Addr: 1; Wire: 'A2'),
    (What: 'SACK: Len is ignored (200)';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpSACK;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 200; Addr: 1; Wire: 'E5'),
    (What: 'SACK: Len 0 is fine (the manual: ignored)';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpSACK;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 0; Addr: 1; Wire: 'E5'),
    (What: 'SNAK: Len 0 is fine';
     Primary: False; AddrLen: 1; FixedLen: 0; Balanced: False; Dir: False; Kind: tpSNAK;
     FCB: False; FCV: False; FC: 0; Data: ''; Len: 0; Addr: 1; Wire: 'A2'));

type
  { bytes fed to a fresh receiver: the event of each byte (F frame, E error,
    '.' nothing) and the result of the error }
  TReceiveCase = record
    What    : string;
    Primary : Boolean;
    AddrLen : Byte;
    CheckPrm: Boolean;
    Wire    : string;
    Events  : string;
    Err     : tChResult;
  end;

const
  ReceiveCases: array[0..16] of TReceiveCase = (
    (What: 'fixed frame, checksum $4B for $4A'; Primary: False; AddrLen: 1; CheckPrm: True;
     Wire: '10 49 01 4B 16'; Events: '...E.'; Err: res_ErrSum),
    (What: 'variable frame, checksum $F9 for $F8 ($08+$34+$12+$AA)'; Primary: True; AddrLen: 2;
     CheckPrm: True; Wire: '68 04 04 68 08 34 12 AA F9 16'; Events: '........E.'; Err: res_ErrSum),
    (What: 'the two L bytes differ'; Primary: True; AddrLen: 1; CheckPrm: True;
     Wire: '68 03 04'; Events: '..E'; Err: res_ErrLen),
    (What: 'L below CODE + ADDR (1 octet)'; Primary: True; AddrLen: 1; CheckPrm: True;
     Wire: '68 01 01'; Events: '..E'; Err: res_ErrLen),
    (What: 'L below CODE + ADDR (2 octets)'; Primary: True; AddrLen: 2; CheckPrm: True;
     Wire: '68 02 02'; Events: '..E'; Err: res_ErrLen),
    (What: 'L = 0'; Primary: True; AddrLen: 0; CheckPrm: True;
     Wire: '68 00 00'; Events: '..E'; Err: res_ErrLen),
    (What: 'L = 1 is the smallest without address: CODE only, CS = CODE'; Primary: True;
     AddrLen: 0; CheckPrm: True; Wire: '68 01 01 68 0B 0B 16'; Events: '......F'; Err: res_Ok),
    (What: '1 octet: L = $FF (253 data octets, above the manual''s 247) is legal'; Primary: True;
     AddrLen: 1; CheckPrm: True; Wire: '68 FF FF'; Events: '...'; Err: res_Ok),
    (What: '1 octet: L = $F9 is allowed'; Primary: True; AddrLen: 1; CheckPrm: True;
     Wire: '68 F9 F9'; Events: '...'; Err: res_Ok),
    (What: '2 octets: L = $FA is allowed'; Primary: True; AddrLen: 2; CheckPrm: True;
     Wire: '68 FA FA'; Events: '...'; Err: res_Ok),
    (What: '2 octets: L = $FF is legal too'; Primary: True; AddrLen: 2; CheckPrm: True;
     Wire: '68 FF FF'; Events: '...'; Err: res_Ok),
    (What: 'second start character wrong'; Primary: True; AddrLen: 1; CheckPrm: True;
     Wire: '68 03 03 69'; Events: '...E'; Err: res_ErrFrame),
    (What: 'fixed frame without the end character'; Primary: False; AddrLen: 1; CheckPrm: True;
     Wire: '10 49 01 4A 17'; Events: '....E'; Err: res_ErrFrame),
    (What: 'variable frame without the end character'; Primary: True; AddrLen: 2; CheckPrm: True;
     Wire: '68 04 04 68 08 34 12 AA F8 00'; Events: '.........E'; Err: res_ErrFrame),
    (What: 'a master receives PRM = 1'; Primary: True; AddrLen: 1; CheckPrm: True;
     Wire: '10 49 01 4A 16'; Events: '....E'; Err: res_ErrCode),
    (What: 'a slave (no filter) receives PRM = 0'; Primary: False; AddrLen: 1; CheckPrm: True;
     Wire: '10 0B 01 0C 16'; Events: '....E'; Err: res_ErrCode),
    (What: 'CheckPrm off (a line monitor): PRM = 1 at a master passes'; Primary: True;
     AddrLen: 1; CheckPrm: False; Wire: '10 49 01 4A 16'; Events: '....F'; Err: res_Ok));

procedure TTestChnFT12Codec.TestEncodeTable;
var
  I: Integer;
  C: tFT12Config;
  R: tFT12Record;
  D: TBytes;
begin
  for I := Low(EncodeCases) to High(EncodeCases) do
    with EncodeCases[I] do
    begin
      C := Cfg(Primary, AddrLen, FixedLen);
      C.Balanced := Balanced;
      C.Dir := Dir;
      R := MakeRec(Kind, FCB, FCV, FC);
      D := HexToBytes(Data);
      if Length(D) > 0 then
        Move(D[0], R.Data[1], Length(D));
      AssertEquals(What, Wire, Enc(C, R, Len, Addr));
    end;
end;

procedure TTestChnFT12Codec.TestReceiveErrorTable;
var
  I: Integer;
  S: tFT12Rx;
begin
  for I := Low(ReceiveCases) to High(ReceiveCases) do
    with ReceiveCases[I] do
    begin
      S := NewRx(Cfg(Primary, AddrLen, 0));
      S.Cfg.CheckPrm := CheckPrm;
      AssertEquals(What, Events, FeedAll(S, Wire));
      if Pos('E', Events) > 0 then
        AssertEquals(What + ': result', Err, S.Err);
    end;
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

procedure TTestChnFT12Codec.TestSingleCharacters;
var
  R: tFT12Record;
  B: array[0..3] of Byte;
  N: Word;
begin
  { the bytes and Len: TestEncodeTable; a master/primary never sends them }
  R := MakeRec(tpSACK, False, False, 0);
  N := 99;
  AssertEquals(res_BadMessage, FT12Encode(Cfg(True, 1, 0), R, 1, 1, @B, 4, N));
  AssertEquals(0, N);
  { no room for the one byte is res_TooLong }
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
  Big: tFT12MaxRecord;
  PR: ^tFT12Record;
  B: array[0..cFT12MaxFrame - 1] of Byte;
  N: Word;
begin
  R := MakeRec(tpLongM, False, False, 3);
  N := 1;
  AssertEquals('Len 0', res_BadLen, FT12Encode(Cfg(True, 1, 0), R, 0, 1, @B, SizeOf(B), N));
  AssertEquals('Len below header', res_BadLen, FT12Encode(Cfg(True, 1, 0), R, 3, 1, @B, SizeOf(B), N));
  { L = 255 at most: 253 data octets with one address octet, 252 with two;
    a record longer than tFT12Record (Len says) }
  FillChar(Big, SizeOf(Big), $11);
  Big.MessType := tpLongM;
  Big.FC := 3;
  PR := @Big;
  AssertEquals('L = 256 with ADR=1', res_TooLong,
    FT12Encode(Cfg(True, 1, 0), PR^, 4 + 253 + 1, 1, @B, SizeOf(B), N));
  AssertEquals('L = 255 with ADR=1', res_Ok,
    FT12Encode(Cfg(True, 1, 0), PR^, 4 + 253, 1, @B, SizeOf(B), N));
  AssertEquals('longest frame with ADR=1', cFT12MaxFrame, N);
  AssertEquals('L', $FF, B[1]);
  AssertEquals('last data octet', $11, B[cFT12MaxFrame - 3]);
  AssertEquals('L = 256 with ADR=2', res_TooLong,
    FT12Encode(Cfg(True, 2, 0), PR^, 4 + 252 + 1, 1, @B, SizeOf(B), N));
  AssertEquals('L = 255 with ADR=2', res_Ok,
    FT12Encode(Cfg(True, 2, 0), PR^, 4 + 252, 1, @B, SizeOf(B), N));
  AssertEquals('longest frame with ADR=2', cFT12MaxFrame, N);
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

{ A single character has no check: met right after a broken frame or a
  skipped byte it may be a byte of that frame, and is dropped until the
  line was idle FT12SuspectIdleMs (or GapMs, when longer) or a whole frame
  came. A master's view (secondary answers). }
procedure TTestChnFT12Codec.TestSingleCharacterAfterGarbageNeedsIdle;
var
  S: tFT12Rx;
begin
  S := NewRx(Cfg(True, 1, 0));
  AssertEquals('at first', 'F', FeedAll(S, 'E5', 1000));
  { L1 <> L2: the E5 after it is a byte of the broken frame }
  AssertEquals('..E.', FeedAll(S, '68 07 08 E5', 2000));
  AssertEquals(1, S.Suspects);
  AssertEquals('49 ms later still', '.', FeedAll(S, 'E5', 2049));
  AssertEquals('idle 50 ms', 'F', FeedAll(S, 'E5', 2099));
  AssertTrue(S.Kind = tpSACK);
  { a skipped byte, then A2 and E5 in the same instant }
  AssertEquals('...', FeedAll(S, '33 A2 E5', 3000));
  AssertEquals('two so far and these two', 4, S.Suspects);
  { a whole frame puts the line in step: an E5 right after it counts }
  AssertEquals('....F' + 'F', FeedAll(S, '10 0B 01 0C 16' + ' E5', 3000));
  { a checksum error, the E5 in the same chunk }
  AssertEquals('...E.' + '.', FeedAll(S, '10 0B 01 0D 16' + ' E5', 4000));
  { GapMs longer than 50 ms is the idle needed }
  S.Cfg.GapMs := 200;
  AssertEquals('..E', FeedAll(S, '68 07 08', 5000));
  AssertEquals('.', FeedAll(S, 'E5', 5100));
  AssertEquals('F', FeedAll(S, 'E5', 5300));
  AssertEquals(6, S.Suspects);
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
    { the peer has the opposite role; noise before the frame, then the
      line idle (without it a single character would be suspect) }
    C.Primary := not C.Primary;
    S := NewRx(C);
    FT12Feed(S, $00, 0);
    FT12Feed(S, $16, 0);
    Frames := 0;
    for I := 0 to BLen - 1 do
      if FT12Feed(S, Buf[I], 1000) = fe_Frame then
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
