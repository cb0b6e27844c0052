{ fuzzcodecs - random-mutation fuzzer for the three pure codecs.

  Built with range, overflow and stack checks and heaptrc (make fuzz), it
  encodes random records, mutates the wire bytes (bit flips, byte
  changes, insertions, deletions, splices with other frames, noise) and
  feeds them to the receive automaton byte by byte. A range or overflow
  error ends the run with a run-time error; every frame the decoder
  accepts must re-encode and decode to the same message (idempotence).

    fuzzcodecs [seconds [seed]]      (default 10 s, seed from the clock) }
program fuzzcodecs;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnDF1Codec, ChnFT12Codec, ChnICSCodec, FuzzRun;

type
  TWire = array of Byte;

var
  Frames, Accepted, Errors: Int64;
  Checked: array[1..3] of Int64;   { round trips checked: DF1, FT 1.2, ICS }
  Failures: Integer = 0;

procedure Fail(const What: string);
begin
  Inc(Failures);
  if Failures <= 20 then
    WriteLn('FAIL ', What, ' (RandSeed chain broken here, rerun with the same seed)');
end;

{ Append N bytes of Src to W. }
procedure Add(var W: TWire; const Src: array of Byte; N: Integer);
var
  L: Integer;
begin
  L := Length(W);
  SetLength(W, L + N);
  if N > 0 then
    Move(Src[0], W[L], N);
end;

procedure Mutate(var W: TWire);
var
  K, I, P: Integer;
begin
  for K := 1 to Random(4) do
  begin
    if Length(W) = 0 then
      Exit;
    P := Random(Length(W));
    case Random(6) of
      0: W[P] := W[P] xor (1 shl Random(8));
      1: W[P] := Random(256);
      2: begin                                  { delete one byte }
           for I := P to High(W) - 1 do
             W[I] := W[I + 1];
           SetLength(W, Length(W) - 1);
         end;
      3: begin                                  { insert one byte }
           SetLength(W, Length(W) + 1);
           for I := High(W) downto P + 1 do
             W[I] := W[I - 1];
           W[P] := Random(256);
         end;
      4: SetLength(W, P);                       { truncate }
      5: ;                                      { leave it whole }
    end;
  end;
end;

{ ---------------------------------------------------------------- DF1 }

procedure RandomDF1Config(var C: tDF1Config);
begin
  C.FullDup := Random(2) = 0;
  C.Master := Random(2) = 0;
  C.Crc := Random(2) = 0;
  C.Node := Random(4) * $10 + Random(2);    { include the stuffed $10 }
  C.DNode := Random(4) * $10 + Random(2);
  if Random(2) = 0 then C.NakByte := NAK else C.NakByte := NAKAlt;
end;

procedure FuzzDF1;
var
  Tx, Rx, Tx2: tDF1Config;
  Rec: tSendRecord;
  D, D2: tDF1Decoder;
  Buf: array[0..1023] of Byte;
  W: TWire;
  N, N2, Len: Word;
  I: Integer;
  J: Integer;
  Ev: tDF1Event;
begin
  RandomDF1Config(Tx);
  Rx := Tx;
  Rx.Master := not Tx.Master;
  Rx.Node := Tx.DNode;
  Rx.DNode := Tx.Node;
  SetLength(W, 0);
  for J := 1 to 1 + Random(3) do
  begin
    FillChar(Rec, SizeOf(Rec), 0);
    Rec.MessType := ChnDF1Codec.tMessType(Random(5));
    Rec.FlAck := Random(2) = 0;
    Rec.CF := Random(65536);
    Rec.Sts := Random(256);
    Rec.Tns := Random(65536);
    Len := 8 + Random(ChnDF1Codec.MaxDataLen + 1);
    for I := 0 to Len - 9 do
      if Random(3) = 0 then Rec.Data[I] := $10 else Rec.Data[I] := Random(256);
    N := 0;
    if DF1Encode(Tx, Rec, Len, Buf, SizeOf(Buf), N) = res_Ok then
      Add(W, Buf, N);
    Inc(Frames);
  end;
  Mutate(W);
  DF1DecoderInit(D, Rx);
  for J := 0 to High(W) do
  begin
    Ev := DF1Feed(D, W[J]);
    if Ev = dfError then
      Inc(Errors)
    else if Ev = dfMessage then
    begin
      Inc(Accepted);
      if D.MsgLen > SizeOf(tRecRecord) then
        Fail('DF1 MsgLen beyond the record');
      { the sender of what was accepted, as seen by the receiver }
      Tx2 := Tx;
      if D.Msg.MessType = tpDataMess then
      begin
        Tx2.Node := D.Src;
        Tx2.DNode := D.Dst;
      end;
      { a half-duplex master sends STN = DST = its DNO: a frame whose DST
        was mutated away from the station byte has no record to match }
      if not Tx.FullDup and Tx.Master and (D.Msg.MessType = tpDataMess) and
         (D.Dst <> Rx.Node) then
        Continue;
      N2 := 0;
      if DF1Encode(Tx2, D.Msg, D.MsgLen, Buf, SizeOf(Buf), N2) <> res_Ok then
        Continue;           { e.g. a poll: only a master may send it }
      Inc(Checked[1]);
      DF1DecoderInit(D2, Rx);
      Ev := dfNone;
      for I := 0 to N2 - 1 do
        Ev := DF1Feed(D2, Buf[I]);
      if (Ev <> dfMessage) or (D2.MsgLen <> D.MsgLen) or
         not CompareMem(@D2.Msg, @D.Msg, D.MsgLen) then
        Fail(Format('DF1 re-encoded message differs: ev %d type %d len %d/%d cf %x/%x src %d dst %d full %s master %s',
          [Ord(Ev), Ord(D.Msg.MessType), D.MsgLen, D2.MsgLen, D.Msg.CF, D2.Msg.CF, D.Src, D.Dst,
           BoolToStr(Tx.FullDup, True), BoolToStr(Tx.Master, True)]));
    end;
  end;
end;

{ ---------------------------------------------------------------- FT 1.2 }

procedure FuzzFT12;
var
  Tx, Rx: tFT12Config;
  Rec: tFT12Record;
  S, S2: tFT12Rx;
  Buf: array[0..cFT12MaxFrame - 1] of Byte;
  Got: array[0..SizeOf(tFT12Record) - 1] of Byte;
  W: TWire;
  N, N2, Len, GotLen: Word;
  I: Integer;
  J: Integer;
  Ev: tFT12Event;
begin
  FillChar(Tx, SizeOf(Tx), 0);
  Tx.AddrLen := Random(3);
  Tx.FixedLen := Random(5);
  Tx.Balanced := Random(2) = 0;
  Tx.Dir := Random(2) = 0;
  Tx.Primary := Random(2) = 0;
  Rx := Tx;
  Rx.Primary := not Tx.Primary;
  Rx.CheckPrm := Random(4) > 0;
  SetLength(W, 0);
  for J := 1 to 1 + Random(3) do
  begin
    FillChar(Rec, SizeOf(Rec), 0);
    Rec.MessType := ChnFT12Codec.tMessType(Random(4));
    Rec.FCB_ACD := Random(2) = 0;
    Rec.FCV_DFC := Random(2) = 0;
    Rec.FC := Random(16);
    if Rec.MessType = tpShortM then
      Len := cSizeHeadSndMsg + Tx.FixedLen
    else
      Len := cSizeHeadSndMsg + Random(ChnFT12Codec.MaxDataLen + 1);
    for I := 1 to Len - cSizeHeadSndMsg do
      Rec.Data[I] := Random(256);
    N := 0;
    if FT12Encode(Tx, Rec, Len, Random(256), @Buf, SizeOf(Buf), N) = res_Ok then
      Add(W, Buf, N);
    Inc(Frames);
  end;
  Mutate(W);
  FillChar(S, SizeOf(S), 0);
  S.Cfg := Rx;
  FT12RxReset(S);
  for J := 0 to High(W) do
  begin
    Ev := FT12Feed(S, W[J], 0);
    if Ev = fe_Error then
      Inc(Errors)
    else if Ev = fe_Frame then
    begin
      Inc(Accepted);
      GotLen := 0;
      if FT12GetRecord(S, @Got, SizeOf(Got), GotLen) <> res_Ok then
      begin
        Fail('FT12 GetRecord refused a full-size buffer');
        Continue;
      end;
      N2 := 0;
      if FT12Encode(Tx, tFT12Record(Got), GotLen, S.Addr, @Buf, SizeOf(Buf), N2) <> res_Ok then
        Continue;           { e.g. a variable frame now as short as a fixed one }
      if S.Kind in [tpShortM, tpLongM] then
        Inc(Checked[2]);    { single characters alone would prove little }
      FillChar(S2, SizeOf(S2), 0);
      S2.Cfg := Rx;
      FT12RxReset(S2);
      Ev := fe_None;
      for I := 0 to N2 - 1 do
        Ev := FT12Feed(S2, Buf[I], 0);
      { DIR/RES and PRM come from the station's configuration, not from
        the record, so only FCB/ACD, FCV/DFC and FC must survive }
      if (Ev <> fe_Frame) or ((S2.Code xor S.Code) and $3F <> 0) or (S2.Addr <> S.Addr) or
         (S2.DataLen <> S.DataLen) or not CompareMem(@S2.Data, @S.Data, S.DataLen) then
        Fail(Format('FT12 re-encoded frame differs: ev %d code %x/%x addr %d/%d len %d/%d kind %d',
          [Ord(Ev), S.Code, S2.Code, S.Addr, S2.Addr, S.DataLen, S2.DataLen, Ord(S.Kind)]));
    end;
  end;
end;

{ ---------------------------------------------------------------- ICS }

procedure FuzzICS;
const
  Delims = '"''/|#';
var
  Rec: tICSRecord;
  St, St2: tICSState;
  Buf: array[0..1023] of Byte;
  W: TWire;
  N, N2: Word;
  I: Integer;
  J, Count: Integer;
  Ev: tICSEvent;
  D: Char;
begin
  SetLength(W, 0);
  for J := 1 to 1 + Random(3) do
  begin
    FillChar(Rec, SizeOf(Rec), 0);
    Rec.OpCode := Chr(65 + Random(26)) + Chr(65 + Random(26));
    Rec.BlockNum := Random(10);
    Count := Random(ICSMaxDataLen + 1);
    for I := 0 to Count - 1 do
      Rec.Data[I] := Random(65536) - 32768;
    if Random(2) = 0 then
    begin
      D := Delims[1 + Random(Length(Delims))];
      Rec.Text := D + StringOfChar('t', Random(40)) + D;
    end;
    N := 0;
    if ICSEncode(Rec, ICSLenOfCount(Count), Random(208), Random(208), Buf,
      SizeOf(Buf), N) = res_Ok then
      Add(W, Buf, N);
    Inc(Frames);
  end;
  Mutate(W);
  ICSReset(St);
  for J := 0 to High(W) do
  begin
    Ev := ICSFeed(St, W[J]);
    if Ev = icsError then
      Inc(Errors)
    else if Ev = icsFrame then
    begin
      Inc(Accepted);
      if (St.Count < 0) or (St.Count > ICSMaxDataLen) then
        Fail('ICS count out of range');
      N2 := 0;
      if ICSEncode(St.Rec, ICSRecLen(St), St.DNode, St.SNode, Buf, SizeOf(Buf),
        N2) <> res_Ok then
        Continue;           { e.g. a received op code the encoder refuses }
      Inc(Checked[3]);
      ICSReset(St2);
      Ev := icsNone;
      for I := 0 to N2 - 1 do
        Ev := ICSFeed(St2, Buf[I]);
      if (Ev <> icsFrame) or (St2.Count <> St.Count) or (St2.Rec.Text <> St.Rec.Text) or
         (St2.Rec.OpCode <> St.Rec.OpCode) or (St2.DNode <> St.DNode) or
         not CompareMem(@St2.Rec.Data, @St.Rec.Data, St.Count * SizeOf(tICSData)) then
        Fail('ICS re-encoded frame differs');
    end;
  end;
end;

var
  Deadline: QWord;
  Rounds: Int64;
begin
  Deadline := FuzzDeadline('fuzzcodecs');
  Rounds := 0;
  FillChar(Checked, SizeOf(Checked), 0);
  repeat
    FuzzDF1;
    FuzzFT12;
    FuzzICS;
    Inc(Rounds);
  until GetTickCount64 >= Deadline;
  WriteLn(Format('%d rounds, %d frames encoded, %d accepted after mutation, %d errors reported, %d failures',
    [Rounds, Frames, Accepted, Errors, Failures]));
  { a codec whose round trip never ran has been checked for nothing }
  if (Checked[1] = 0) or (Checked[2] = 0) or (Checked[3] = 0) then
  begin
    WriteLn(Format('FAIL a codec had no round trip checked (DF1 %d, FT 1.2 %d, ICS %d)',
      [Checked[1], Checked[2], Checked[3]]));
    Inc(Failures);
  end;
  if Failures > 0 then
    Halt(1);
end.
