{ ChnPcap - serial traffic as a pcap file of link type 250 (RTAC serial),
  the binary trace format of NAM=TRC MOD=PCAP, which Wireshark and tshark
  open directly. Pure: builds and parses bytes, no I/O, no clock.

  File (classic libpcap, written little-endian, version 2.4):
    file header   24 bytes  tPcapFileHeader, link type 250
    per chunk     16 bytes  tPcapRecHeader (seconds, microseconds, lengths)
                  12 bytes  tRtacHeader, big-endian (Wireshark's rtacser
                            dissector):
                              0  seconds since 1970 (UTC)
                              4  microseconds
                              8  event type: 3 DATA_TX_END, 4 DATA_RX_END
                                 (1 TX_START / 2 RX_START are read too)
                              9  control lines: CTS 1, DCD 2, DSR 4, RTS 8,
                                 DTR 16, RING 32, MBOK 64 (written 0:
                                 the layer does not know them)
                             10  footer, 2 bytes (written 0)
                  the bytes of the chunk as they passed the line
  A chunk is one record: the unit of ChSend / ChReceive, as in the text log.

  The reader takes files of either byte order and the nanosecond variant
  (magic A1B23C4D), as other RTAC-serial captures come; records of other
  event types (status change, errors, capture lost) are counted in Skipped.
  Times: the pcap holds UTC seconds; the text log local time of day. The
  caller passes the offset (PcapReadBytes) or the epoch of the local
  midnight a time of day belongs to (PcapFromTrc), so this unit needs no
  clock or time zone. }
unit ChnPcap;

{$I chn.inc}

interface

uses
  ChnTypes, ChnTrcFormat;

const
  PcapMagic      = $A1B2C3D4;   {< microsecond timestamps }
  PcapMagicNano  = $A1B23C4D;   {< nanosecond timestamps }
  PcapLinkRtac   = 250;         {< LINKTYPE_RTAC_SERIAL }
  PcapLinkIPv4   = 228;         {< LINKTYPE_IPV4: raw IPv4 packets (a TCP stream) }
  PcapIec104Port = 2404;        {< the server side's port in a TCP stream (IEC 104's) }
  PcapSnapLen    = 65547;       {< longest record: 12 + 65535 chunk bytes }
  RtacHeaderLen  = 12;

  { RTAC serial event types }
  RtacStatusChange = 0;
  RtacTxStart      = 1;
  RtacRxStart      = 2;
  RtacTxEnd        = 3;
  RtacRxEnd        = 4;

  {- results of the reader (texts registered for TrcLayer, after the
    text reader's res_TrcShort / res_TrcLong) }
  res_PcapNotPcap  = res_Proto + 2;   {< no pcap magic, or a file header cut short }
  res_PcapLinkType = res_Proto + 3;   {< a pcap of another link type }
  res_PcapCut      = res_Proto + 4;   {< ends inside a record header, or a bad length }

type
  tPcapFileHeader = packed record
    Magic   : LongWord;
    VerMajor: Word;                {< 2 }
    VerMinor: Word;                {< 4 }
    ThisZone: LongInt;             {< 0: times are UTC }
    SigFigs : LongWord;
    SnapLen : LongWord;
    LinkType: LongWord;
  end;

  tPcapRecHeader = packed record
    TsSec  : LongWord;
    TsFrac : LongWord;             {< microseconds (nanoseconds: PcapMagicNano) }
    InclLen: LongWord;             {< bytes in the file }
    OrigLen: LongWord;             {< bytes on the wire }
  end;

  { The RTAC serial header before each record's bytes, big-endian on the
    wire. }
  tRtacHeader = packed record
    TsSec : LongWord;
    TsUSec: LongWord;
    Event : Byte;
    Lines : Byte;
    Footer: Word;
  end;

  tPcapInfo = record
    Records : LongInt;             {< records read }
    Skipped : LongInt;             {< records of other event types or < 12 bytes }
    Swapped : Boolean;             {< the file is big-endian }
    LinkType: LongWord;
    ErrPos  : LongInt;             {< byte offset of the culprit (result <> res_Ok) }
    ErrText : ShortString;         {< what is wrong there }
  end;

  { A TCP stream written as IPv4 packets: the next sequence number of each
    side, so Wireshark reassembles the stream. }
  tPcapTcpFlow = record
    SeqClient, SeqServer: LongWord;
  end;

{ The 24-byte file header (little-endian, link type 250). }
function PcapFileHeaderBytes: AnsiString;
{ The same of another link type (PcapLinkIPv4). }
function PcapFileHeaderOf(LinkType: LongWord): AnsiString;
{ One record of link type 228: an IPv4 + TCP header (client 10.0.0.1, port
  50000; server 10.0.0.2, port ServerPort; PSH ACK, both checksums) and
  Len bytes of Buf as its payload, sent by the server when FromServer. }
function PcapTcpRecordBytes(Sec, USec: LongWord; FromServer: Boolean; ServerPort: Word;
  var Flow: tPcapTcpFlow; const Buf; Len: LongInt): AnsiString;
{ Head is a header of ours of that link type (appended to). }
function PcapIsOwnHeaderOf(const Head: AnsiString; LinkType: LongWord): Boolean;
{ One record: pcap record header, RTAC header and Len bytes of Buf. }
function PcapRecordBytes(Sec, USec: LongWord; Dir: tTrcDir; const Buf;
  Len: LongInt): AnsiString;
{ True when Head (at least 24 bytes) is a header this unit appends to:
  little-endian microsecond pcap of link type 250. }
function PcapIsOwnHeader(const Head: AnsiString): Boolean;

{ Read a whole pcap file. Frames get one entry per TX/RX record: Line =
  record number (1-based), TimeMs = local time of day (UTC + UtcOffsetSec),
  Dir, DirText 'tx'/'rx', Tag 'pcap', the bytes; Status res_TrcShort when
  the record holds fewer bytes than were on the line. Returns res_Ok or a
  res_Pcap* code (Info.ErrPos/ErrText say where and why); the frames read
  before the fault are kept. }
function PcapReadBytes(const Data: AnsiString; UtcOffsetSec: LongInt;
  var Frames: tTrcFrames; var Info: tPcapInfo): tChResult;

{ A text trace as pcap: each frame's time of day (local) is placed on the
  day whose local midnight is MidnightUtc (seconds since 1970); a time
  earlier than the one before is taken as the next day. }
function PcapFromTrc(const Frames: tTrcFrames; Count: LongInt;
  MidnightUtc: Int64): AnsiString;

implementation

uses
  uString;

{ An unsigned 32-bit field as text (NumStr is for LongInt). }
function UNumStr(V: LongWord): ShortString;
begin
  Str(V, Result);
end;

function Swap32(V: LongWord): LongWord; inline;
begin
  Result := (V shr 24) or ((V shr 8) and $FF00) or ((V shl 8) and $FF0000) or (V shl 24);
end;

function PcapFileHeaderBytes: AnsiString;
begin
  Result := PcapFileHeaderOf(PcapLinkRtac);
end;

function PcapFileHeaderOf(LinkType: LongWord): AnsiString;
var
  H: tPcapFileHeader;
begin
  H.Magic := NtoLE(LongWord(PcapMagic));
  H.VerMajor := NtoLE(Word(2));
  H.VerMinor := NtoLE(Word(4));
  H.ThisZone := 0;
  H.SigFigs := 0;
  H.SnapLen := NtoLE(LongWord(PcapSnapLen));
  H.LinkType := NtoLE(LinkType);
  SetLength(Result, SizeOf(H));
  Move(H, Result[1], SizeOf(H));
end;

function PcapRecordBytes(Sec, USec: LongWord; Dir: tTrcDir; const Buf;
  Len: LongInt): AnsiString;
var
  R: tPcapRecHeader;
  T: tRtacHeader;
begin
  if Len < 0 then
    Len := 0;
  R.TsSec := NtoLE(Sec);
  R.TsFrac := NtoLE(USec);
  R.InclLen := NtoLE(LongWord(Len + RtacHeaderLen));
  R.OrigLen := R.InclLen;
  T.TsSec := NtoBE(Sec);
  T.TsUSec := NtoBE(USec);
  if Dir = trcTx then
    T.Event := RtacTxEnd
  else
    T.Event := RtacRxEnd;
  T.Lines := 0;
  T.Footer := 0;
  SetLength(Result, SizeOf(R) + SizeOf(T) + Len);
  Move(R, Result[1], SizeOf(R));
  Move(T, Result[1 + SizeOf(R)], SizeOf(T));
  if Len > 0 then
    Move(Buf, Result[1 + SizeOf(R) + SizeOf(T)], Len);
end;

function PcapIsOwnHeader(const Head: AnsiString): Boolean;
begin
  Result := PcapIsOwnHeaderOf(Head, PcapLinkRtac);
end;

function PcapIsOwnHeaderOf(const Head: AnsiString; LinkType: LongWord): Boolean;
var
  H: tPcapFileHeader;
begin
  Result := False;
  if Length(Head) < SizeOf(H) then
    Exit;
  Move(Head[1], H, SizeOf(H));
  Result := (LEtoN(H.Magic) = PcapMagic) and (LEtoN(H.LinkType) = LinkType);
end;

{ The Internet checksum (RFC 1071) of P[0 .. Len - 1], Sum carried in. }
function InetSum(const P: array of Byte; Len: LongInt; Sum: LongWord): LongWord;
var
  I: LongInt;
begin
  I := 0;
  while I + 1 < Len do
  begin
    Inc(Sum, (LongWord(P[I]) shl 8) or P[I + 1]);
    Inc(I, 2);
  end;
  if I < Len then
    Inc(Sum, LongWord(P[I]) shl 8);
  Result := Sum;
end;

function InetFold(Sum: LongWord): Word;
begin
  while Sum shr 16 <> 0 do
    Sum := (Sum and $FFFF) + (Sum shr 16);
  Result := not Word(Sum);
end;

procedure Put16(var P: array of Byte; At: LongInt; V: Word);
begin
  P[At] := V shr 8;
  P[At + 1] := V and $FF;
end;

procedure Put32(var P: array of Byte; At: LongInt; V: LongWord);
begin
  Put16(P, At, V shr 16);
  Put16(P, At + 2, V and $FFFF);
end;

function PcapTcpRecordBytes(Sec, USec: LongWord; FromServer: Boolean; ServerPort: Word;
  var Flow: tPcapTcpFlow; const Buf; Len: LongInt): AnsiString;
const
  ClientIp = $0A000001;
  ServerIp = $0A000002;
  ClientPort = 50000;
var
  P: array of Byte;
  R: tPcapRecHeader;
  Src, Dst: LongWord;
  Sum: LongWord;
begin
  if Len < 0 then
    Len := 0;
  SetLength(P, 40 + Len);
  FillChar(P[0], 40, 0);
  if FromServer then
  begin
    Src := ServerIp;
    Dst := ClientIp;
  end
  else
  begin
    Src := ClientIp;
    Dst := ServerIp;
  end;
  { IPv4: version 4, 20 octets, total length, DF, TTL 64, TCP }
  P[0] := $45;
  Put16(P, 2, 40 + Len);
  P[6] := $40;
  P[8] := 64;
  P[9] := 6;
  Put32(P, 12, Src);
  Put32(P, 16, Dst);
  Put16(P, 10, InetFold(InetSum(P, 20, 0)));
  { TCP: ports, sequence and acknowledgement numbers, 20 octets, PSH ACK }
  if FromServer then
  begin
    Put16(P, 20, ServerPort);
    Put16(P, 22, ClientPort);
    Put32(P, 24, Flow.SeqServer);
    Put32(P, 28, Flow.SeqClient);
    Inc(Flow.SeqServer, Len);
  end
  else
  begin
    Put16(P, 20, ClientPort);
    Put16(P, 22, ServerPort);
    Put32(P, 24, Flow.SeqClient);
    Put32(P, 28, Flow.SeqServer);
    Inc(Flow.SeqClient, Len);
  end;
  P[32] := $50;
  P[33] := $18;
  Put16(P, 34, $FFFF);
  if Len > 0 then
    Move(Buf, P[40], Len);
  { pseudo header: addresses, protocol, TCP length }
  Sum := (Src shr 16) + (Src and $FFFF) + (Dst shr 16) + (Dst and $FFFF) + 6 + LongWord(20 + Len);
  Put16(P, 36, InetFold(InetSum(P[20..High(P)], 20 + Len, Sum)));
  R.TsSec := NtoLE(Sec);
  R.TsFrac := NtoLE(USec);
  R.InclLen := NtoLE(LongWord(Length(P)));
  R.OrigLen := R.InclLen;
  SetLength(Result, SizeOf(R) + Length(P));
  Move(R, Result[1], SizeOf(R));
  Move(P[0], Result[1 + SizeOf(R)], Length(P));
end;

{ A value of the file in its own byte order, whatever the machine's. }
function FileOrder(const Info: tPcapInfo; V: LongWord): LongWord;
begin
  if Info.Swapped then
    Result := Swap32(LEtoN(V))
  else
    Result := LEtoN(V);
end;

{ The file is refused or cut at byte At: Info says where and why. }
function ReadFail(var Info: tPcapInfo; Code: tChResult; At: LongInt; const Why: string): tChResult;
begin
  Info.ErrPos := At;
  Info.ErrText := Why;
  Result := Code;
end;

{ The file header: the byte order and time resolution its magic says,
  its link type (RTAC serial only). }
function ReadFileHeader(const Data: AnsiString; var Info: tPcapInfo; out Nano: Boolean): tChResult;
var
  H: tPcapFileHeader;
begin
  Nano := False;
  if Length(Data) < SizeOf(H) then
    Exit(ReadFail(Info, res_PcapNotPcap, 0, NumStr(Length(Data)) +
      ' bytes, a pcap file header has 24'));
  Move(Data[1], H, SizeOf(H));
  case LEtoN(H.Magic) of
    PcapMagic: ;
    PcapMagicNano: Nano := True;
  else
    if Swap32(LEtoN(H.Magic)) = PcapMagic then
      Info.Swapped := True
    else if Swap32(LEtoN(H.Magic)) = PcapMagicNano then
    begin
      Info.Swapped := True;
      Nano := True;
    end
    else if LEtoN(H.Magic) = $0A0D0D0A then
      Exit(ReadFail(Info, res_PcapNotPcap, 0, 'a pcapng file: save it as "Wireshark/tcpdump - pcap"'))
    else
      Exit(ReadFail(Info, res_PcapNotPcap, 0, 'magic $' + HexBytes(@Data[1], 4) +
        ' is no pcap magic'));
  end;
  Info.LinkType := FileOrder(Info, H.LinkType);
  if Info.LinkType <> PcapLinkRtac then
    Exit(ReadFail(Info, res_PcapLinkType, 20, 'link type ' + UNumStr(Info.LinkType) +
      ', RTAC serial is 250'));
  Result := res_Ok;
end;

{ The header of the record at byte Pos, in the machine's byte order;
  res_PcapCut when the file ends inside it or its length is impossible. }
function ReadRecordHeader(const Data: AnsiString; Pos: LongInt; var Info: tPcapInfo;
  out R: tPcapRecHeader): tChResult;
begin
  FillChar(R, SizeOf(R), 0);
  if Pos + SizeOf(R) > Length(Data) then
    Exit(ReadFail(Info, res_PcapCut, Pos, 'record ' + NumStr(Info.Records + 1) +
      ': the file ends inside its header'));
  Move(Data[Pos + 1], R, SizeOf(R));
  R.TsSec := FileOrder(Info, R.TsSec);
  R.TsFrac := FileOrder(Info, R.TsFrac);
  R.InclLen := FileOrder(Info, R.InclLen);
  R.OrigLen := FileOrder(Info, R.OrigLen);
  if (R.InclLen > PcapSnapLen) or (R.InclLen > R.OrigLen) then
    Exit(ReadFail(Info, res_PcapCut, Pos, 'record ' + NumStr(Info.Records + 1) +
      ': impossible length ' + UNumStr(R.InclLen)));
  Result := res_Ok;
end;

{ The frame of an RTAC record (event T, N bytes at Pos with its RTAC
  header, record header R) into F: the time of the record header (the
  one tshark shows), the direction, the length announced, the bytes. }
procedure TakeRecord(const Data: AnsiString; Pos, N: LongInt; const R: tPcapRecHeader;
  const T: tRtacHeader; Nano: Boolean; UtcOffsetSec, Line: LongInt; var F: tTrcFrame);
var
  Payload: LongInt;
  Local: Int64;
begin
  Payload := N - RtacHeaderLen;
  FillChar(F, SizeOf(F) - SizeOf(F.Data), 0);
  Local := Int64(R.TsSec) + UtcOffsetSec;
  Local := Local mod 86400;
  if Local < 0 then
    Inc(Local, 86400);
  if Nano then
    F.TimeMs := Local * 1000 + R.TsFrac div 1000000
  else
    F.TimeMs := Local * 1000 + R.TsFrac div 1000;
  F.Line := Line;
  if T.Event in [RtacTxStart, RtacTxEnd] then
    F.Dir := trcTx
  else
    F.Dir := trcRx;
  if F.Dir = trcTx then
    F.DirText := 'tx'
  else
    F.DirText := 'rx';
  F.Tag := 'pcap';
  { the announced length, unsigned on the wire: one past what a chunk
    can hold stands for "more", and the record is flagged short below }
  if R.OrigLen - RtacHeaderLen > LongWord(High(LongInt)) then
    F.Len := High(LongInt)
  else
    F.Len := LongInt(R.OrigLen - RtacHeaderLen);
  SetLength(F.Data, Payload);
  if Payload > 0 then
    Move(Data[Pos + 1 + RtacHeaderLen], F.Data[0], Payload);
  if Payload < F.Len then
    F.Status := res_TrcShort
  else
    F.Status := res_Ok;
end;

function PcapReadBytes(const Data: AnsiString; UtcOffsetSec: LongInt;
  var Frames: tTrcFrames; var Info: tPcapInfo): tChResult;
var
  R: tPcapRecHeader;
  T: tRtacHeader;
  Pos, Count, N: LongInt;
  Nano: Boolean;
begin
  FillChar(Info, SizeOf(Info), 0);
  Info.ErrText := '';
  Count := 0;
  SetLength(Frames, 0);
  Result := ReadFileHeader(Data, Info, Nano);
  if Result <> res_Ok then
    Exit;
  Pos := SizeOf(tPcapFileHeader);            { 0-based offset of the next record }
  while Pos < Length(Data) do
  begin
    Result := ReadRecordHeader(Data, Pos, Info, R);
    if Result <> res_Ok then
      Break;
    Inc(Info.Records);
    Inc(Pos, SizeOf(R));
    N := R.InclLen;
    if Pos + N > Length(Data) then
      N := Length(Data) - Pos;              { the last record, cut off }
    { an RTAC record of a start or end of transmission is a frame; any
      other is skipped }
    if N >= RtacHeaderLen then
      Move(Data[Pos + 1], T, SizeOf(T));
    if (N < RtacHeaderLen) or not (T.Event in [RtacTxStart, RtacRxStart, RtacTxEnd, RtacRxEnd]) then
      Inc(Info.Skipped)
    else
    begin
      if Count >= Length(Frames) then
        SetLength(Frames, 2 * Count + 16);
      TakeRecord(Data, Pos, N, R, T, Nano, UtcOffsetSec, Info.Records, Frames[Count]);
      Inc(Count);
    end;
    Inc(Pos, N);
  end;
  SetLength(Frames, Count);
end;

function PcapFromTrc(const Frames: tTrcFrames; Count: LongInt;
  MidnightUtc: Int64): AnsiString;
var
  I, Size, Pos: LongInt;
  Day: Int64;
  Last: LongInt;
  Sec: Int64;
  Rec: AnsiString;
begin
  Size := 24;
  for I := 0 to Count - 1 do
    Inc(Size, 28 + Length(Frames[I].Data));
  SetLength(Result, Size);
  Rec := PcapFileHeaderBytes;
  Move(Rec[1], Result[1], Length(Rec));
  Pos := 1 + Length(Rec);
  Day := 0;
  Last := 0;
  for I := 0 to Count - 1 do
  begin
    if Frames[I].TimeMs < Last then
      Inc(Day);                             { past midnight }
    Last := Frames[I].TimeMs;
    Sec := MidnightUtc + Day * 86400 + Frames[I].TimeMs div 1000;
    if Length(Frames[I].Data) > 0 then
      Rec := PcapRecordBytes(LongWord(Sec), (Frames[I].TimeMs mod 1000) * 1000,
        Frames[I].Dir, Frames[I].Data[0], Length(Frames[I].Data))
    else
      Rec := PcapRecordBytes(LongWord(Sec), (Frames[I].TimeMs mod 1000) * 1000,
        Frames[I].Dir, Pos, 0);
    Move(Rec[1], Result[Pos], Length(Rec));
    Inc(Pos, Length(Rec));
  end;
end;

initialization
  ChRegisterResultText(TrcLayer, res_PcapNotPcap, 'not a pcap file');
  ChRegisterResultText(TrcLayer, res_PcapLinkType, 'pcap file of another link type than RTAC serial (250)');
  ChRegisterResultText(TrcLayer, res_PcapCut, 'pcap file cut off or damaged inside a record');
end.
