{ Tests of ChnDF1Codec: record layout, encoding against frames worked out
  by hand (BCC) or by an independent reference (CRC: the RACOM captures of
  the RACOM note and values from a separate bit-by-bit implementation), decoding of
  the real line captures, every error path of the receive automaton, and a
  property test encode -> decode = identity over thousands of random
  records. }
unit TestChnDF1Codec;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnDF1Codec, TestSupport;

type
  TTestChnDF1Codec = class(TTestCase)
  private
    function Cfg(FullDup, Master, Crc: Boolean; Node, DNode: Byte): tDF1Config;
    function Enc(const C: tDF1Config; const R: tSendRecord; Len: Word): string;
    { feed hex; return the events as text, e.g. 'M8 E21 M2' }
    function Feed(var D: tDF1Decoder; const Hex: string): string;
    procedure DataRec(var R: tSendRecord; CF: Word; Tns: Word; const Data: string);
  published
    procedure TestRecordLayout;
    procedure TestFncRule;
    procedure TestEncodeEchoFullDuplexBcc;
    procedure TestEncodeEchoFullDuplexCrc;
    procedure TestEncodeReplyCarriesNoFnc;
    procedure TestEncodeHalfDuplexMasterFrame;
    procedure TestEncodeDleEverywhere;
    procedure TestEncodeShortMessages;
    procedure TestEncodeRefusals;
    procedure TestDecodeRacomCaptures;
    procedure TestRacomBccFrameNakEnq;
    procedure TestRoundTripEveryTypeModeChecksum;
    procedure TestRoundTripRandomRecords;
    procedure TestErrBadCrcAndBcc;
    procedure TestErrDleUnexpectedByte;
    procedure TestErrEtxWithoutStx;
    procedure TestErrTooManyDataBytes;
    procedure TestErrMissingFncAndShortFrame;
    procedure TestNewStxInsideFrameStartsNewFrame;
    procedure TestNoiseBetweenFramesIgnored;
    procedure TestNakVariantsAccepted;
    procedure TestEmbeddedAckInFullDuplex;
    procedure TestModeSymbolErrors;
    procedure TestHalfDuplexSlaveFiltersStation;
    procedure TestPollErrors;
    procedure TestRandomBytesNeverBreakDecoder;
  end;

implementation

const
  { read off the RACOM frames (TestSupport) by hand: DST SRC CMD STS TNS and the data
    between TNS and DLE ETX with DLE DLE written once }
  RacomDst: array[1..6] of Byte = ($03, $00, $03, $00, $03, $00);
  RacomSrc: array[1..6] of Byte = ($00, $03, $00, $03, $00, $03);
  RacomCmd: array[1..6] of Byte = ($0B, $4B, $0A, $4A, $0B, $4B);
  RacomTns: array[1..6] of Word = ($007E, $007E, $007F, $007F, $008F, $008F);
  RacomData: array[1..6] of string = (
    '0000 5402 2006 2401 07E9 0000 0380 827F 0080 E943 0100 8D91 1300 0000 0000 E070 7200 F643 E070 7200 F643 A302 2002 2401',
    '0000 D400 0000 3D7F 0080 827F 0080 E943 0100 8D91 1300 E070 7200 E070 7200 0000',
    '0000 3D7F 7F00 4C08 910B 546F 5472 616E 7370 6F72 7400 2800 10 00',
    '0000 827F 7F00 CC00 0000 C300 0A1A 0200 0300 0400 0500 0600 0700 0800 0000 0000 0000 0000 0000 0000 0000 0000',
    '0000 4E02 2006 2401 07E9 E943 0100 8D91 1300 0200 2002 2401 10 00',
    '0000 CE00 0000 E943 0100 8D91 1300 0000');

  { Echo 'Ahoj', TNS 10, station 1 -> 2. BCC worked out by hand:
    02+01+06+00+0A+00+00+41+68+6F+6A = $195, -$95 = $6B. CRC values from an
    independent bit-by-bit CRC-16 ($A001) over DST..DATA,ETX. }
  EchoBcc = '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 6B';
  EchoCrc = '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E3 88';
  { reply 2 -> 1: CMD $46, no FNC; BCC: 01+02+46+0A+41+68+6F+6A = $1D5 -> $2B }
  ReplyBcc = '10 02 01 02 46 00 0A 00 41 68 6F 6A 10 03 2B';
  ReplyCrc = '10 02 01 02 46 00 0A 00 41 68 6F 6A 10 03 6B 86';
  { half-duplex master, STN 2 (in the BCC: $6B - 2 = $69) }
  EchoHdBcc = '10 01 02 10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 69';
  EchoHdCrc = '10 01 02 10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E4 CA';
  { DST $10 SRC $10 CMD $0F STS $10 TNS $1010 FNC $10 data 10 10: every
    $10 doubled, the checksum not }
  DleCrc = '10 02 10 10 10 10 0F 10 10 10 10 10 10 10 10 10 10 10 10 10 03 16 43';
  DleBcc = '10 02 10 10 10 10 0F 10 10 10 10 10 10 10 10 10 10 10 10 10 03 71';
  DleHdCrc = '10 01 10 10 10 02 10 10 10 10 0F 10 10 10 10 10 10 10 10 10 10 10 10 10 03 42 83';
  { Protected Typed Logical Read, 3 address fields (manual 6.3.5), TNS 14 }
  TypedReadBcc = '10 02 02 01 0F 00 0E 00 A2 05 07 89 00 00 10 03 A9';

function TTestChnDF1Codec.Cfg(FullDup, Master, Crc: Boolean; Node, DNode: Byte): tDF1Config;
begin
  Result.FullDup := FullDup;
  Result.Master := Master;
  Result.Crc := Crc;
  Result.Node := Node;
  Result.DNode := DNode;
  Result.NakByte := NAK;
end;

function TTestChnDF1Codec.Enc(const C: tDF1Config; const R: tSendRecord; Len: Word): string;
var
  Buf: array[0..DF1MaxWire - 1] of Byte;
  N: Word;
  Res: tChResult;
begin
  N := 0;
  Res := DF1Encode(C, R, Len, Buf, SizeOf(Buf), N);
  if Res <> res_Ok then
    Exit('result ' + IntToStr(Res));
  Result := BytesToHex(Buf, N);
end;

function TTestChnDF1Codec.Feed(var D: tDF1Decoder; const Hex: string): string;
var
  B: TBytes;
  I: Integer;
  E: tDF1Event;
begin
  B := HexToBytes(Hex);
  Result := '';
  for I := 0 to High(B) do
  begin
    E := DF1Feed(D, B[I]);
    if E = dfMessage then
      Result := Result + ' M' + IntToStr(D.MsgLen)
    else if E = dfError then
      Result := Result + ' E' + IntToHex(D.Err, 2);
  end;
  Result := Trim(Result);
end;

procedure TTestChnDF1Codec.DataRec(var R: tSendRecord; CF: Word; Tns: Word; const Data: string);
begin
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpDataMess;
  R.CF := CF;
  R.Sts := 0;
  R.Tns := Tns;
  if Data <> '' then
    Move(Data[1], R.Data[0], Length(Data));
end;

procedure TTestChnDF1Codec.TestRecordLayout;
var
  R: tSendRecord;
  Base: PtrUInt;
begin
  Base := PtrUInt(@R);
  AssertEquals('SizeOf(tSendRecord)', 252, SizeOf(tSendRecord));
  AssertEquals('SizeOf(tRecRecord)', 252, SizeOf(tRecRecord));
  AssertEquals('SizeOf(tMessType)', 1, SizeOf(tMessType));
  AssertEquals('MessType', 0, PtrUInt(@R.MessType) - Base);
  AssertEquals('FlAck', 1, PtrUInt(@R.FlAck) - Base);
  AssertEquals('Dummy1_1', 1, PtrUInt(@R.Dummy1_1) - Base);
  AssertEquals('CF', 2, PtrUInt(@R.CF) - Base);
  AssertEquals('Sts', 4, PtrUInt(@R.Sts) - Base);
  AssertEquals('Dummy1_2', 5, PtrUInt(@R.Dummy1_2) - Base);
  AssertEquals('Tns', 6, PtrUInt(@R.Tns) - Base);
  AssertEquals('Data', 8, PtrUInt(@R.Data) - Base);
  AssertEquals('MaxDataLen', 244, MaxDataLen);
  AssertEquals('NAK on the wire', $15, NAK);
  AssertEquals(6 + 1 + 244, DF1MaxBody);
  AssertEquals('worst case: every body byte and STN stuffed, CRC', 512, DF1MaxWire);
end;

procedure TTestChnDF1Codec.TestFncRule;
begin
  AssertTrue('$06 command', DF1HasFnc($06));
  AssertTrue('$07 command', DF1HasFnc($07));
  AssertTrue('$0F command', DF1HasFnc($0F));
  AssertTrue('$0F with priority bit', DF1HasFnc($2F));
  AssertFalse('$46 reply', DF1HasFnc($46));
  AssertFalse('$4F reply', DF1HasFnc($4F));
  AssertFalse('$0A', DF1HasFnc($0A));
  AssertFalse('$0B', DF1HasFnc($0B));
  AssertFalse('$00 protected write', DF1HasFnc($00));
  AssertFalse('$08', DF1HasFnc($08));
end;

procedure TTestChnDF1Codec.TestEncodeEchoFullDuplexBcc;
var
  R: tSendRecord;
begin
  DataRec(R, $0600, 10, 'Ahoj');
  AssertEquals(EchoBcc, Enc(Cfg(True, True, False, 1, 2), R, 12));
  { full duplex: a slave's data frame looks the same }
  AssertEquals(EchoBcc, Enc(Cfg(True, False, False, 1, 2), R, 12));
end;

procedure TTestChnDF1Codec.TestEncodeEchoFullDuplexCrc;
var
  R: tSendRecord;
begin
  DataRec(R, $0600, 10, 'Ahoj');
  AssertEquals(EchoCrc, Enc(Cfg(True, True, True, 1, 2), R, 12));
  DataRec(R, $0FA2, 14, #5#7#$89#0#0);
  AssertEquals(TypedReadBcc, Enc(Cfg(True, True, False, 1, 2), R, 13));
end;

procedure TTestChnDF1Codec.TestEncodeReplyCarriesNoFnc;
var
  R: tSendRecord;
begin
  { the application may leave the FNC in CF (CF_Echo or MskCF_Reply with
    FNC 1): a reply never sends it }
  DataRec(R, $4601, 10, 'Ahoj');
  AssertEquals(ReplyBcc, Enc(Cfg(True, False, False, 2, 1), R, 12));
  AssertEquals(ReplyCrc, Enc(Cfg(True, False, True, 2, 1), R, 12));
  { half-duplex slave replies are plain STX frames }
  AssertEquals(ReplyCrc, Enc(Cfg(False, False, True, 2, 1), R, 12));
end;

procedure TTestChnDF1Codec.TestEncodeHalfDuplexMasterFrame;
var
  R: tSendRecord;
begin
  DataRec(R, $0600, 10, 'Ahoj');
  AssertEquals(EchoHdBcc, Enc(Cfg(False, True, False, 1, 2), R, 12));
  AssertEquals(EchoHdCrc, Enc(Cfg(False, True, True, 1, 2), R, 12));
end;

procedure TTestChnDF1Codec.TestEncodeDleEverywhere;
var
  R: tSendRecord;
begin
  DataRec(R, $0F10, $1010, #$10#$10);
  R.Sts := $10;
  AssertEquals(DleCrc, Enc(Cfg(True, True, True, $10, $10), R, 10));
  AssertEquals(DleBcc, Enc(Cfg(True, True, False, $10, $10), R, 10));
  { half-duplex master: STN $10 is stuffed too }
  AssertEquals(DleHdCrc, Enc(Cfg(False, True, True, $10, $10), R, 10));
end;

procedure TTestChnDF1Codec.TestEncodeShortMessages;
var
  R: tSendRecord;
  C: tDF1Config;
begin
  FillChar(R, SizeOf(R), 0);
  R.MessType := tpAckNak;
  R.FlAck := True;
  AssertEquals('ACK', '10 06', Enc(Cfg(True, True, True, 1, 2), R, 0));
  AssertEquals('ACK, half-duplex slave', '10 06', Enc(Cfg(False, False, True, 1, 2), R, 0));
  R.FlAck := False;
  AssertEquals('NAK is $15', '10 15', Enc(Cfg(True, True, True, 1, 2), R, 0));
  AssertEquals('NAK, half-duplex master (link reset)', '10 15', Enc(Cfg(False, True, False, 1, 2), R, 0));
  C := Cfg(True, False, True, 1, 2);
  C.NakByte := NAKAlt;
  AssertEquals('NAK=0F', '10 0F', Enc(C, R, 0));
  R.MessType := tpEnq;
  AssertEquals('ENQ', '10 05', Enc(Cfg(True, False, False, 1, 2), R, 99));
  R.MessType := tpPoll;
  { BCC of a poll: -2 = $FE; always BCC even with CRC=ON }
  AssertEquals('poll 2', '10 05 02 FE', Enc(Cfg(False, True, True, 1, 2), R, 0));
  AssertEquals('poll 16: STN stuffed, BCC -$10 = $F0', '10 05 10 10 F0',
    Enc(Cfg(False, True, False, 1, 16), R, 0));
  R.MessType := tpNoPollRep;
  AssertEquals('EOT', '10 04', Enc(Cfg(False, False, True, 2, 1), R, 0));
end;

procedure TTestChnDF1Codec.TestEncodeRefusals;
var
  R: tSendRecord;
  Buf: array[0..DF1MaxWire - 1] of Byte;
  N: Word;
  C: tDF1Config;
begin
  C := Cfg(True, True, True, 1, 2);
  DataRec(R, $0600, 1, 'x');
  FillChar(Buf, SizeOf(Buf), $AA);
  N := 99;
  AssertEquals('Len 7', res_BadLen, DF1Encode(C, R, 7, Buf, SizeOf(Buf), N));
  AssertEquals('OutLen 0 on error', 0, N);
  AssertEquals('Len 8+245', res_BadLen, DF1Encode(C, R, 8 + 245, Buf, SizeOf(Buf), N));
  AssertEquals('Len 0', res_BadLen, DF1Encode(C, R, 0, Buf, SizeOf(Buf), N));
  AssertEquals('Len 8+244 is fine', res_Ok, DF1Encode(C, R, 8 + 244, Buf, SizeOf(Buf), N));
  FillChar(Buf, SizeOf(Buf), $AA);
  AssertEquals('too small output', res_TooLong, DF1Encode(C, R, 9, Buf, 13, N));
  AssertEquals(0, N);
  AssertEquals('output untouched', $AA, Buf[0]);
  AssertEquals('exactly fits: 2+7+1+2+2', res_Ok, DF1Encode(C, R, 9, Buf, 14, N));
  PByte(@R.MessType)^ := 5;
  AssertEquals('unknown MessType', res_BadMessage, DF1Encode(C, R, 9, Buf, SizeOf(Buf), N));
  PByte(@R.MessType)^ := 200;
  AssertEquals('unknown MessType 200', res_BadMessage, DF1Encode(C, R, 9, Buf, SizeOf(Buf), N));
  R.MessType := tpPoll;
  AssertEquals('poll in full duplex', res_BadMessage, DF1Encode(C, R, 0, Buf, SizeOf(Buf), N));
  AssertEquals('poll by a half-duplex slave', res_BadMessage,
    DF1Encode(Cfg(False, False, True, 1, 2), R, 0, Buf, SizeOf(Buf), N));
  R.MessType := tpNoPollRep;
  AssertEquals('EOT in full duplex', res_BadMessage, DF1Encode(C, R, 0, Buf, SizeOf(Buf), N));
  AssertEquals('EOT by a half-duplex master', res_BadMessage,
    DF1Encode(Cfg(False, True, True, 1, 2), R, 0, Buf, SizeOf(Buf), N));
  R.MessType := tpEnq;
  AssertEquals('ENQ in half duplex', res_BadMessage,
    DF1Encode(Cfg(False, True, True, 1, 2), R, 0, Buf, SizeOf(Buf), N));
  R.MessType := tpAckNak;
  R.FlAck := False;
  AssertEquals('NAK by a half-duplex slave', res_BadMessage,
    DF1Encode(Cfg(False, False, True, 1, 2), R, 0, Buf, SizeOf(Buf), N));
end;

procedure TTestChnDF1Codec.TestDecodeRacomCaptures;
var
  I, J: Integer;
  D: tDF1Decoder;
  F, Want: TBytes;
  Used: Word;
  C: tDF1Config;
begin
  for I := 1 to 6 do
  begin
    F := HexToBytes(RacomFrames[I]);
    Want := HexToBytes(RacomData[I]);
    DF1DecoderInit(D, Cfg(True, True, True, 0, 0));
    AssertTrue('frame ' + IntToStr(I) + ' decodes',
      DF1FeedBlock(D, F[0], Length(F), Used) = dfMessage);
    AssertEquals('whole frame used', Length(F), Used);
    AssertEquals('DST', RacomDst[I], D.Dst);
    AssertEquals('SRC', RacomSrc[I], D.Src);
    AssertTrue(D.Msg.MessType = tpDataMess);
    AssertEquals('CMD', RacomCmd[I], Hi(D.Msg.CF));
    AssertEquals('no FNC: CF low byte 0', 0, Lo(D.Msg.CF));
    AssertEquals('STS', 0, D.Msg.Sts);
    AssertEquals('TNS', RacomTns[I], D.Msg.Tns);
    AssertEquals('Len', 8 + Length(Want), D.MsgLen);
    for J := 0 to High(Want) do
      AssertEquals('frame ' + IntToStr(I) + ' data ' + IntToStr(J), Want[J], D.Msg.Data[J]);
    { re-encode from the decoded record: the same bytes }
    C := Cfg(True, True, True, D.Src, D.Dst);
    AssertEquals('frame ' + IntToStr(I) + ' re-encoded',
      BytesToHex(F, Length(F)), Enc(C, D.Msg, D.MsgLen));
  end;
end;

procedure TTestChnDF1Codec.TestRacomBccFrameNakEnq;
var
  D: tDF1Decoder;
begin
  { RACOM note, failed exchange: the radio modem sent 10 02 0E 0D AA AA 10 03 91
    (the PLC payload replaced by AA AA), the PLC answered 10 15 (NAK); later
    10 05 (ENQ). The BCC is right, so the automaton gets past the checksum:
    the frame is too short to hold TNS, hence res_ErrFrame (the PLC NAKed). }
  DF1DecoderInit(D, Cfg(True, True, False, 0, 0));
  AssertEquals('E20 M2 M1', Feed(D, '10 02 0E 0D AA AA 10 03 91  10 15  10 05'));
  AssertFalse('NAK', D.Msg.FlAck);
  AssertTrue('ENQ', D.Msg.MessType = tpEnq);
  { the same frame with a wrong BCC fails the checksum first }
  AssertEquals('E21 M2', Feed(D, '10 02 0E 0D AA AA 10 03 92  10 15'));
  AssertTrue(D.Msg.MessType = tpAckNak);
end;

procedure TTestChnDF1Codec.TestRoundTripEveryTypeModeChecksum;
var
  Mode, Crc: Integer;
  T: tMessType;
  S, RCfg: tDF1Config;
  R: tSendRecord;
  D: tDF1Decoder;
  Buf: array[0..DF1MaxWire - 1] of Byte;
  N, Used: Word;
  Res: tChResult;
  Sendable, Sent: Integer;
  What: string;
begin
  Sent := 0;
  { modes: 0 full duplex master, 1 full duplex slave, 2 half-duplex
    master -> slave, 3 half-duplex slave -> master }
  for Mode := 0 to 3 do
    for Crc := 0 to 1 do
      for T := Low(tMessType) to High(tMessType) do
      begin
        S := Cfg(Mode < 2, Mode in [0, 2], Crc = 1, 7, 9);
        RCfg := Cfg(Mode < 2, not S.Master, Crc = 1, 9, 7);
        What := Format('mode %d crc %d type %d', [Mode, Crc, Ord(T)]);
        FillChar(R, SizeOf(R), 0);
        R.MessType := T;
        R.FlAck := True;
        if T = tpDataMess then
        begin
          DataRec(R, $0F68, $1234, #1#2#$10#3);
          R.Sts := $10;
        end;
        Res := DF1Encode(S, R, 12, Buf, SizeOf(Buf), N);
        case T of
          tpEnq: Sendable := Ord(Mode < 2);
          tpPoll: Sendable := Ord(Mode = 2);
          tpNoPollRep: Sendable := Ord(Mode = 3);
        else
          Sendable := 1;
        end;
        if Sendable = 0 then
        begin
          AssertEquals(What + ' refused', res_BadMessage, Res);
          Continue;
        end;
        AssertEquals(What + ' encodes', res_Ok, Res);
        DF1DecoderInit(D, RCfg);
        AssertTrue(What + ' decodes', DF1FeedBlock(D, Buf, N, Used) = dfMessage);
        AssertEquals(What + ' at the last byte', N, Used);
        AssertTrue(What + ' type', D.Msg.MessType = T);
        case T of
          tpAckNak:
            begin
              AssertEquals(2, D.MsgLen);
              AssertTrue(D.Msg.FlAck);
            end;
          tpDataMess:
            begin
              AssertEquals(12, D.MsgLen);
              AssertTrue(What + ' record', CompareByte(R, D.Msg, 12) = 0);
              AssertEquals('DST', 9, D.Dst);
              AssertEquals('SRC', 7, D.Src);
            end;
          tpPoll:
            AssertEquals('polled station', 9, D.Dst);
        else
          AssertEquals(1, D.MsgLen);
        end;
        Inc(Sent);
      end;
  { 4 modes x 2 checksums x (ACK + data) + 2x2 ENQ + 2 polls + 2 EOT }
  AssertEquals('messages round-tripped', 8 * 2 + 4 + 2 + 2, Sent);
end;

procedure TTestChnDF1Codec.TestRoundTripRandomRecords;
var
  I, J, N, Mode: Integer;
  R: tSendRecord;
  S, RCfg: tDF1Config;
  D: tDF1Decoder;
  Buf: array[0..DF1MaxWire - 1] of Byte;
  W, Used: Word;
  Cmd: Byte;
  FullOfDle: Integer;
begin
  RandSeed := 20260401;   { fixed: a failure reproduces }
  FullOfDle := 0;
  for I := 1 to 5000 do
  begin
    Mode := Random(4);
    S := Cfg(Mode < 2, Mode in [0, 2], Random(2) = 1, Random(256), Random(256));
    if I mod 5 = 0 then
    begin
      S.Node := DLE;
      S.DNode := DLE;
    end;
    RCfg := Cfg(S.FullDup, not S.Master, S.Crc, S.DNode, S.Node);
    FillChar(R, SizeOf(R), 0);
    R.MessType := tpDataMess;
    Cmd := Random(256);
    if I mod 7 = 0 then
      Cmd := $0F;
    if DF1HasFnc(Cmd) then
      R.CF := Cmd shl 8 or Random(256)
    else
      R.CF := Cmd shl 8;      { no FNC on the wire: low byte is 0 after decoding }
    R.Sts := Random(256);
    R.Tns := Random(65536);
    N := Random(MaxDataLen + 1);
    if I mod 10 = 0 then
      N := MaxDataLen;
    if I mod 4 = 0 then
    begin
      FillChar(R.Data, N, DLE);
      R.Sts := DLE;
      R.Tns := $1010;
      Inc(FullOfDle);
    end
    else
      for J := 0 to N - 1 do
        R.Data[J] := Random(256);
    AssertEquals('encode ' + IntToStr(I), res_Ok, DF1Encode(S, R, 8 + N, Buf, SizeOf(Buf), W));
    DF1DecoderInit(D, RCfg);
    if DF1FeedBlock(D, Buf, W, Used) <> dfMessage then
      Fail(Format('record %d (mode %d) did not decode: %s', [I, Mode, BytesToHex(Buf, W)]));
    AssertEquals('whole frame used', W, Used);
    AssertEquals('Len ' + IntToStr(I), 8 + N, D.MsgLen);
    if CompareByte(R, D.Msg, 8 + N) <> 0 then
      Fail(Format('record %d differs after the round trip', [I]));
    AssertEquals('DST', S.DNode, D.Dst);
    AssertEquals('SRC', S.Node, D.Src);
  end;
  AssertEquals(1250, FullOfDle);
end;

procedure TTestChnDF1Codec.TestErrBadCrcAndBcc;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  AssertEquals('CRC low byte wrong', 'E21', Feed(D, '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E2 88'));
  AssertEquals('CRC high byte wrong', 'E21', Feed(D, '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E3 89'));
  AssertEquals('a data byte changed', 'E21', Feed(D, '10 02 02 01 06 00 0A 00 00 41 68 6F 6B 10 03 E3 88'));
  AssertEquals('ready for the next frame', 'M12', Feed(D, EchoCrc));
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  AssertEquals('BCC wrong', 'E21', Feed(D, '10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 6C'));
  AssertEquals('CRC frame read with BCC', 'E21', Feed(D, EchoCrc));
  AssertEquals('M12', Feed(D, EchoBcc));
end;

procedure TTestChnDF1Codec.TestErrDleUnexpectedByte;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  { DLE $07 inside a frame; the rest of the broken frame (up to its DLE ETX
    and checksum) is skipped without a second error }
  AssertEquals('E20', Feed(D, '10 02 02 01 06 00 0A 00 00 41 10 07 6F 6A 10 03 E3 88'));
  AssertEquals('M12', Feed(D, EchoCrc));
  { DLE at the end of the body followed by a checksum-like byte }
  AssertEquals('E20', Feed(D, '10 02 02 01 06 00 0A 00 10 88'));
  AssertEquals('M12', Feed(D, EchoCrc));
  { after DLE SOH STN a half-duplex slave wants DLE STX }
  DF1DecoderInit(D, Cfg(False, False, False, 2, 1));
  AssertEquals('E20', Feed(D, '10 01 02 41 10 02'));
  AssertEquals('E20', Feed(D, '10 01 02 10 41'));
  AssertEquals('E20 M12', Feed(D, '10 01 02 10 03 ' + EchoHdBcc));
end;

procedure TTestChnDF1Codec.TestErrEtxWithoutStx;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  AssertEquals('E20', Feed(D, '10 03'));
  AssertEquals('M12', Feed(D, EchoBcc));
  AssertEquals('DLE DLE outside a frame', 'E20', Feed(D, '41 10 10'));
  { the broken-frame tail after an error is quiet, then frames decode }
  AssertEquals('M12', Feed(D, '42 43 10 03 11 ' + EchoBcc));
  AssertEquals('E20 M12', Feed(D, '10 03 ' + EchoBcc));
end;

procedure TTestChnDF1Codec.TestErrTooManyDataBytes;
var
  D: tDF1Decoder;
  S: string;
  I: Integer;
  Sum: Byte;
begin
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  { CMD $0A (no FNC) with 245 data bytes of 1: checksum right, too long }
  S := '10 02 02 01 0A 00 00 00';
  Sum := 2 + 1 + $0A;
  for I := 1 to 245 do
  begin
    S := S + ' 01';
    Sum := Byte(Sum + 1);
  end;
  S := S + ' 10 03 ' + IntToHex(Byte(-Sum), 2);
  AssertEquals('245 data bytes', 'E22', Feed(D, S));
  AssertEquals('M12', Feed(D, EchoBcc));
  { 600 body bytes: stops at the buffer, one error, the tail is skipped }
  S := '10 02';
  for I := 1 to 600 do
    S := S + ' 01';
  AssertEquals('600 bytes', 'E22', Feed(D, S + ' 10 03 00'));
  AssertEquals('M12', Feed(D, EchoBcc));
  { exactly 244 data bytes is fine }
  S := '10 02 02 01 0A 00 00 00';
  Sum := 2 + 1 + $0A;
  for I := 1 to 244 do
  begin
    S := S + ' 01';
    Sum := Byte(Sum + 1);
  end;
  AssertEquals('M252', Feed(D, S + ' 10 03 ' + IntToHex(Byte(-Sum), 2)));
end;

procedure TTestChnDF1Codec.TestErrMissingFncAndShortFrame;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  { CMD 06 needs FNC: DST SRC CMD STS TNS only; BCC -(2+1+6+$0A) = $ED }
  AssertEquals('E20', Feed(D, '10 02 02 01 06 00 0A 00 10 03 ED'));
  { the same with CMD $46 (a reply) is a good empty reply: -(2+1+$46+$0A) = $AD }
  AssertEquals('M8', Feed(D, '10 02 02 01 46 00 0A 00 10 03 AD'));
  AssertEquals('empty frame', 'E20', Feed(D, '10 02 10 03 00'));
  AssertEquals('M12', Feed(D, EchoBcc));
end;

procedure TTestChnDF1Codec.TestNewStxInsideFrameStartsNewFrame;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  AssertEquals('E20 M12', Feed(D, '10 02 02 01 06 00 ' + EchoCrc));
  { also while skipping the tail of a broken frame }
  AssertEquals('E20 M12', Feed(D, '10 02 02 10 09 33 ' + EchoCrc));
  { and right after DLE SOH STN in a half-duplex slave }
  DF1DecoderInit(D, Cfg(False, False, True, 2, 1));
  AssertEquals('E20 M12', Feed(D, '10 01 02 10 01 ' + Copy(EchoHdCrc, 7, 200)));
end;

procedure TTestChnDF1Codec.TestNoiseBetweenFramesIgnored;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  AssertEquals('M12 M2', Feed(D, '00 FF 41 ' + EchoBcc + ' 03 02 10 06'));
end;

procedure TTestChnDF1Codec.TestNakVariantsAccepted;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, False, 1, 2));
  AssertEquals('M2', Feed(D, '10 15'));
  AssertTrue(D.Msg.MessType = tpAckNak);
  AssertFalse(D.Msg.FlAck);
  AssertEquals('M2', Feed(D, '10 0F'));
  AssertFalse(D.Msg.FlAck);
  AssertEquals('M2', Feed(D, '10 06'));
  AssertTrue(D.Msg.FlAck);
end;

procedure TTestChnDF1Codec.TestEmbeddedAckInFullDuplex;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  AssertEquals('M2 M12', Feed(D, '10 02 02 01 06 00 0A 00 00 41 10 06 68 6F 6A 10 03 E3 88'));
  AssertEquals(12, D.MsgLen);
  AssertEquals(Ord('h'), D.Msg.Data[1]);
  { not in half duplex }
  DF1DecoderInit(D, Cfg(False, True, True, 1, 2));
  AssertEquals('E20', Feed(D, '10 02 01 02 46 00 0A 00 41 10 06 68 6F 6A 10 03 6B 86'));
end;

procedure TTestChnDF1Codec.TestModeSymbolErrors;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  AssertEquals('EOT in full duplex', 'E20', Feed(D, '10 04'));
  AssertEquals('SOH in full duplex', 'E20', Feed(D, '10 01'));
  AssertEquals('M1', Feed(D, '10 05'));
  AssertTrue(D.Msg.MessType = tpEnq);
  DF1DecoderInit(D, Cfg(False, True, True, 1, 2));
  AssertEquals('a master is never polled', 'E20', Feed(D, '10 05'));
  AssertEquals('EOT to the master', 'M1', Feed(D, '10 04'));
  AssertTrue(D.Msg.MessType = tpNoPollRep);
  AssertEquals('slave data to the master', 'M12', Feed(D, ReplyCrc));
end;

procedure TTestChnDF1Codec.TestHalfDuplexSlaveFiltersStation;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(False, False, False, 3, 1));
  { EchoHdBcc is for station 2: nothing, not even for a bad checksum }
  AssertEquals('', Feed(D, EchoHdBcc));
  AssertEquals('', Feed(D, Copy(EchoHdBcc, 1, Length(EchoHdBcc) - 2) + '00'));
  AssertEquals('poll for 2', '', Feed(D, '10 05 02 FE'));
  AssertEquals('another slave''s reply and EOT', '', Feed(D, ReplyBcc + ' 10 04'));
  AssertEquals('poll for 3', 'M1', Feed(D, '10 05 03 FD'));
  AssertTrue(D.Msg.MessType = tpPoll);
  DF1DecoderInit(D, Cfg(False, False, False, 2, 1));
  AssertEquals('M12', Feed(D, EchoHdBcc));
  AssertEquals('DST', 2, D.Dst);
  AssertEquals('SRC', 1, D.Src);
  { station 16: STN stuffed }
  DF1DecoderInit(D, Cfg(False, False, True, $10, $10));
  AssertEquals('M10', Feed(D, DleHdCrc));
  AssertEquals('M1', Feed(D, '10 05 10 10 F0'));
end;

procedure TTestChnDF1Codec.TestPollErrors;
var
  D: tDF1Decoder;
begin
  DF1DecoderInit(D, Cfg(False, False, True, 2, 1));
  AssertEquals('poll BCC wrong', 'E21', Feed(D, '10 05 02 FF'));
  AssertEquals('poll STN DLE not doubled', 'E20', Feed(D, '10 05 10 41'));
  AssertEquals('M1', Feed(D, '10 05 02 FE'));
end;

procedure TTestChnDF1Codec.TestRandomBytesNeverBreakDecoder;
var
  D: tDF1Decoder;
  I, Mode, Msgs, Errs: Integer;
  B: Byte;
  E: tDF1Event;
begin
  { random and DLE-heavy garbage: every event is well formed, the
    automaton never leaves its states, and it still decodes afterwards }
  RandSeed := 77;
  Msgs := 0;
  Errs := 0;
  for Mode := 0 to 3 do
  begin
    DF1DecoderInit(D, Cfg(Mode < 2, Mode in [0, 2], Odd(Mode), 2, 1));
    for I := 1 to 200000 do
    begin
      case Random(4) of
        0: B := DLE;
        1: B := Random(7);
      else
        B := Random(256);
      end;
      E := DF1Feed(D, B);
      AssertTrue(D.State <= dsPollBcc);
      AssertTrue(D.BodyLen <= DF1MaxBody);
      if E = dfMessage then
      begin
        Inc(Msgs);
        AssertTrue(D.MsgLen <= SizeOf(tRecRecord));
        AssertTrue(Ord(D.Msg.MessType) <= Ord(High(tMessType)));
      end
      else if E = dfError then
      begin
        Inc(Errs);
        AssertTrue((D.Err = res_ErrFrame) or (D.Err = res_ErrSum) or (D.Err = res_ErrLen));
      end;
    end;
  end;
  AssertTrue('some messages', Msgs > 0);
  AssertTrue('some errors', Errs > 0);
  DF1DecoderInit(D, Cfg(True, True, True, 1, 2));
  Feed(D, '10 02 41 42');
  AssertEquals('E20 M12', Feed(D, '10 07 ' + EchoCrc));
end;

initialization
  RegisterTest(TTestChnDF1Codec);
end.
