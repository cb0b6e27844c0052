{ ChnDF1Codec - the Allen-Bradley DF1 frame codec: record <-> wire bytes,
  DLE transparency, BCC/CRC-16, and an incremental receive automaton fed one
  byte at a time. No I/O, no objects: tChnDF1 (unit ChnDF1) glues it to a
  channel; tools, the fuzzer and the benchmark call it directly.

  Frame formats (SofCon manual ChnDF1 section 6, docs/PROTOCOLS.md section 4):
    full duplex, both directions  DLE STX DST SRC CMD STS TNSlo TNShi [FNC] DATA DLE ETX BCC|CRClo CRChi
                  link symbols    DLE ACK, DLE NAK, DLE ENQ
    half duplex, master           DLE SOH STN DLE STX DST SRC ... DLE ETX BCC|CRC
                  poll            DLE ENQ STN BCC          (always BCC)
    half duplex, slave            DLE STX DST SRC ... DLE ETX BCC|CRC,  DLE EOT, DLE ACK
  A data byte (STN included) equal to DLE is sent twice; checksum bytes are
  never stuffed. BCC = two's complement of the byte sum of DST..DATA (plus STN
  in a half-duplex master frame); CRC-16 ($A001 reflected, init 0) over the
  same bytes plus ETX, low byte first.

  Record mapping: CF = CMD shl 8 + FNC. A command (CMD and $40 = 0) whose
  command nibble (CMD and $0F) is $06, $07 or $0F carries FNC as the first
  byte after TNS; every other command and every reply carries none, and its
  CF low byte is neither sent nor received (0 after decoding).
  Len of a data message = 8 + count of Data bytes; tpAckNak is 2 bytes long,
  tpEnq/tpPoll/tpNoPollRep 1 byte.

  Receiving: bytes between frames other than DLE are line noise and ignored.
  A broken frame gives one dfError (res_ErrSum, res_ErrFrame, res_ErrLen);
  the rest of it is then skipped quietly up to its DLE ETX and checksum, and
  a DLE STX (DLE SOH) anywhere starts a new frame. A half-duplex slave
  ignores master frames and polls for other stations and frames of other
  slaves, without any event.

  Deliberate differences from the SofCon manual: NAK is $15 on the wire (the
  manual prints $0F); DLE $0F is accepted as NAK too, and the NAK byte sent is
  configurable (tDF1Config.NakByte). In full duplex a DLE ACK / DLE NAK
  embedded in an incoming frame is reported and the frame goes on (Rockwell
  allows embedded responses). }
unit ChnDF1Codec;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  { control characters (manual 4.1; NAK per SPEC 6) }
  SOH    = $01;
  STX    = $02;
  ETX    = $03;
  EOT    = $04;
  ENQ    = $05;
  ACK    = $06;
  NAK    = $15;
  NAKAlt = $0F;   {< the manual's value; accepted on receive, sent with NAK=0F }
  DLE    = $10;

  MaxDataLen = 244;   {< Data bytes of one message }
  cSizeHead  = 8;     {< MessType..Tns: Len = cSizeHead + data bytes }

  {- protocol results (manual section 4) }
  res_ErrFrame = $20;   {< malformed frame }
  res_ErrSum   = $21;   {< BCC/CRC mismatch }
  res_ErrLen   = $22;   {< too many data bytes, or larger than the receive buffer }

  { unstuffed frame body DST SRC CMD STS TNS TNS [FNC] DATA }
  DF1MaxBody = 6 + 1 + MaxDataLen;
  { longest frame on the wire: a half-duplex master frame, every body byte
    and STN stuffed, CRC: DLE SOH STN STN DLE STX body*2 DLE ETX CRC CRC }
  DF1MaxWire = 2 + 2 + 2 + 2 * DF1MaxBody + 2 + 2;

type
  tMessType = (tpAckNak, tpEnq, tpPoll, tpNoPollRep, tpDataMess);

  { manual 4.3, byte-exact (chn.inc packs records): MessType@0,
    FlAck/Dummy1_1@1, CF@2, Sts@4, Dummy1_2@5, Tns@6, Data@8 }
  pSendRecord = ^tSendRecord;
  tSendRecord = record
    case MessType: tMessType of
      tpAckNak:
        (FlAck: Boolean);
      tpEnq, tpPoll, tpNoPollRep:
        ();
      tpDataMess:
        (Dummy1_1: Byte;
         case CF: Word of   {< command and function; the variant is the manual's
                              (CF_WriteBytesPhysical = $0F18) }
           $0F18:
             (Sts     : Byte;
              Dummy1_2: Byte;
              Tns     : Word;
              Data    : array[0..MaxDataLen - 1] of Byte));
  end;
  tRecRecord = tSendRecord;
  pRecRecord = ^tRecRecord;

  { What the codec needs to know about the station. }
  tDF1Config = record
    FullDup: Boolean;   {< False: half duplex }
    Master : Boolean;   {< half duplex: master sends SOH frames and polls }
    Crc    : Boolean;   {< CRC-16, else BCC }
    Node   : Byte;      {< own address: SRC of sent frames; a half-duplex
                          slave accepts only frames and polls with STN = Node }
    DNode  : Byte;      {< DST of sent frames; STN of master frames and polls }
    NakByte: Byte;      {< NAK or NAKAlt }
  end;

  tDF1Event = (
    dfNone,      {< byte consumed, nothing complete yet }
    dfMessage,   {< Msg/MsgLen hold a whole message }
    dfError);    {< a frame was broken: Err says why; ready for the next }

  { Receive automaton. Init with DF1DecoderInit; feed with DF1Feed. After
    dfMessage, Msg/MsgLen/Src/Dst are valid until the next DF1Feed. }
  tDF1Decoder = record
    Cfg     : tDF1Config;
    State   : Byte;       {< ds* below; dsIdle = between frames }
    Skip    : Boolean;    {< after an error: eat the rest of the broken frame quietly }
    Ignore  : Boolean;    {< frame or poll for another station: no event }
    HdMaster: Boolean;    {< current frame began with DLE SOH STN }
    Stn     : Byte;
    SumLeft : Byte;       {< checksum bytes still to read }
    RxSum   : Word;       {< checksum as received }
    Bcc     : tBcc8;      {< running byte sum }
    Crc     : tCrc16;     {< running CRC }
    BodyLen : Word;
    Body    : array[0..DF1MaxBody - 1] of Byte;
    Msg     : tRecRecord; {< the decoded message }
    MsgLen  : Word;       {< its Len (8 + data, or 1/2 for short messages) }
    Src, Dst: Byte;       {< SRC/DST of a data frame; Dst = STN of a poll }
    Err     : tChResult;  {< after dfError }
  end;

const
  {- decoder states (tDF1Decoder.State) }
  dsIdle       = 0;    {< between frames, hunting for DLE }
  dsIdleDle    = 1;    {< DLE seen between frames }
  dsStn        = 2;    {< after DLE SOH: station byte }
  dsStnDle     = 3;    {< STN was DLE: its second DLE }
  dsSohDle     = 4;    {< after STN: DLE of DLE STX }
  dsSohStx     = 5;    {< after STN DLE: STX }
  dsBody       = 6;    {< inside DST..DATA }
  dsBodyDle    = 7;    {< DLE inside the body }
  dsSum        = 8;    {< checksum bytes after DLE ETX }
  dsPollStn    = 9;    {< after DLE ENQ in a half-duplex slave: STN }
  dsPollStnDle = 10;
  dsPollBcc    = 11;

{ True when a command byte carries FNC after TNS (see the header). }
function DF1HasFnc(Cmd: Byte): Boolean;

{ Encode one record as wire bytes into Out (OutSize bytes available).
  Len counts as described above and matters only for tpDataMess.
  Results: res_Ok; res_BadLen (data Len outside 8..8+MaxDataLen);
  res_BadMessage (MessType unknown, or not sendable in this mode: tpEnq only
  in full duplex, tpPoll only by a half-duplex master, tpNoPollRep only by a
  half-duplex slave, NAK not by a half-duplex slave); res_TooLong (OutSize
  too small). On error OutLen = 0 and Out is untouched. Only the record
  bytes the message needs are read. }
function DF1Encode(const Cfg: tDF1Config; constref Rec: tSendRecord; Len: Word;
  var Out; OutSize: Word; var OutLen: Word): tChResult;

procedure DF1DecoderInit(var D: tDF1Decoder; const Cfg: tDF1Config);
{ Forget any partial frame; keep the configuration. }
procedure DF1DecoderReset(var D: tDF1Decoder);
{ Feed one received byte. }
function DF1Feed(var D: tDF1Decoder; B: Byte): tDF1Event;
{ Feed bytes from Buf until an event or the end; Used = bytes consumed. }
function DF1FeedBlock(var D: tDF1Decoder; const Buf; Len: Word; var Used: Word): tDF1Event;

{ Reply CF. A reply carries no FNC on the wire, but the manuals' programs
  test a reply as CF_xxx or MskCF_Reply. So a station remembers the last
  commands it sent, and a reply that matches one (same TNS, reply command
  byte = the sent command byte or $40) is reported with that command's CF
  or $4000, FNC included. A log of DF1SentMemory entries lets a master keep
  that many commands outstanding; the oldest entry is dropped first. }
const
  DF1SentMemory = 16;

type
  tDF1Sent = record
    Dst: Byte;    {< DST the command went to }
    CF : Word;    {< CF as the application gave it }
    Tns: Word;
  end;
  tDF1SentLog = record
    Count: Byte;                                     {< entries in use }
    Next : Byte;                                     {< slot of the next note }
    Items: array[0..DF1SentMemory - 1] of tDF1Sent;
  end;

procedure DF1SentInit(var L: tDF1SentLog);
{ Note a message just sent to Dst; only commands (tpDataMess, reply bit
  clear) are noted. }
procedure DF1SentNote(var L: tDF1SentLog; Dst: Byte; constref Rec: tSendRecord);
{ The CF to report for a message received from Src: for a reply matching a
  noted command that command's CF or $4000 (the newest match, one sent to
  Src preferred), else Rec.CF unchanged. }
function DF1ReplyCF(const L: tDF1SentLog; Src: Byte; constref Rec: tRecRecord): Word;
{ True when one of the noted commands went to Dst. }
function DF1SentTo(const L: tDF1SentLog; Dst: Byte): Boolean;

implementation

function DF1HasFnc(Cmd: Byte): Boolean;
begin
  Result := (Cmd and $40 = 0) and ((Cmd and $0F) in [$06, $07, $0F]);
end;

{- ------------------------------------------------------------------ encode }

type
  tWire = record
    Buf: array[0..DF1MaxWire - 1] of Byte;
    N  : Word;
    Bcc: tBcc8;
    Crc: tCrc16;
  end;

procedure PutRaw(var W: tWire; B: Byte); inline;
begin
  W.Buf[W.N] := B;
  Inc(W.N);
end;

{ a body byte: stuffed and folded into both checksums }
procedure PutData(var W: tWire; B: Byte); inline;
begin
  if B = DLE then
    PutRaw(W, DLE);
  PutRaw(W, B);
  W.Bcc := Bcc8Add(W.Bcc, B);
  W.Crc := Crc16Add(W.Crc, B);
end;

function DF1Encode(const Cfg: tDF1Config; constref Rec: tSendRecord; Len: Word;
  var Out; OutSize: Word; var OutLen: Word): tChResult;
var
  W: tWire;
  Cmd: Byte;
  I: Integer;
  HdMaster, HdSlave: Boolean;
begin
  OutLen := 0;
  W.N := 0;
  W.Bcc := 0;
  W.Crc := 0;
  HdMaster := not Cfg.FullDup and Cfg.Master;
  HdSlave := not Cfg.FullDup and not Cfg.Master;
  { MessType may hold any byte when the record comes from an application }
  case Byte(Rec.MessType) of
    Ord(tpAckNak):
      begin
        PutRaw(W, DLE);
        if Byte(Rec.FlAck) <> 0 then
          PutRaw(W, ACK)
        else if HdSlave then
          Exit(res_BadMessage)      { a half-duplex slave never NAKs }
        else
          PutRaw(W, Cfg.NakByte);
      end;
    Ord(tpEnq):
      begin
        if not Cfg.FullDup then
          Exit(res_BadMessage);     { half duplex: ENQ is the master's poll }
        PutRaw(W, DLE);
        PutRaw(W, ENQ);
      end;
    Ord(tpPoll):
      begin
        if not HdMaster then
          Exit(res_BadMessage);
        PutRaw(W, DLE);
        PutRaw(W, ENQ);
        PutData(W, Cfg.DNode);
        PutRaw(W, Bcc8Final(W.Bcc));  { the poll is always BCC }
      end;
    Ord(tpNoPollRep):
      begin
        if not HdSlave then
          Exit(res_BadMessage);
        PutRaw(W, DLE);
        PutRaw(W, EOT);
      end;
    Ord(tpDataMess):
      begin
        if (Len < cSizeHead) or (Len > cSizeHead + MaxDataLen) then
          Exit(res_BadLen);
        PutRaw(W, DLE);
        if HdMaster then
        begin
          PutRaw(W, SOH);
          PutData(W, Cfg.DNode);      { STN }
          PutRaw(W, DLE);
        end;
        PutRaw(W, STX);
        Cmd := Hi(Rec.CF);
        PutData(W, Cfg.DNode);
        PutData(W, Cfg.Node);
        PutData(W, Cmd);
        PutData(W, Rec.Sts);
        PutData(W, Lo(Rec.Tns));
        PutData(W, Hi(Rec.Tns));
        if DF1HasFnc(Cmd) then
          PutData(W, Lo(Rec.CF));
        for I := 0 to Integer(Len) - cSizeHead - 1 do
          PutData(W, Rec.Data[I]);
        PutRaw(W, DLE);
        PutRaw(W, ETX);
        if Cfg.Crc then
        begin
          W.Crc := Crc16Add(W.Crc, ETX);
          PutRaw(W, Lo(W.Crc));
          PutRaw(W, Hi(W.Crc));
        end
        else
          PutRaw(W, Bcc8Final(W.Bcc));
      end;
  else
    Exit(res_BadMessage);
  end;
  if W.N > OutSize then
    Exit(res_TooLong);
  Move(W.Buf, Out, W.N);
  OutLen := W.N;
  Result := res_Ok;
end;

{- ------------------------------------------------------------------ decode }

procedure DF1DecoderReset(var D: tDF1Decoder);
begin
  D.State := dsIdle;
  D.Skip := False;
  D.Ignore := False;
  D.HdMaster := False;
  D.BodyLen := 0;
  D.SumLeft := 0;
  D.Err := res_Ok;
end;

procedure DF1DecoderInit(var D: tDF1Decoder; const Cfg: tDF1Config);
begin
  FillChar(D, SizeOf(D), 0);
  D.Cfg := Cfg;
  DF1DecoderReset(D);
end;

{ A short message: MessType (and FlAck) only. }
function ShortMsg(var D: tDF1Decoder; T: tMessType; Ack: Boolean): tDF1Event;
begin
  D.Msg.MessType := T;
  D.Msg.FlAck := Ack;
  if T = tpAckNak then
    D.MsgLen := 2
  else
    D.MsgLen := 1;
  Result := dfMessage;
end;

{ The current frame is broken. Report it (unless it was for another
  station) and eat the rest of it quietly. }
function Fail(var D: tDF1Decoder; Code: tChResult): tDF1Event;
begin
  if D.Ignore then
    Result := dfNone
  else
  begin
    D.Err := Code;
    Result := dfError;
  end;
  D.State := dsIdle;
  D.Skip := True;
  D.Ignore := False;
end;

{ A whole frame was read but is bad: report it; nothing is left to skip. }
function FailWhole(var D: tDF1Decoder; Code: tChResult): tDF1Event;
begin
  Result := Fail(D, Code);
  D.Skip := False;
end;

procedure SumLength(var D: tDF1Decoder);
begin
  if D.Cfg.Crc then
    D.SumLeft := 2
  else
    D.SumLeft := 1;
  D.RxSum := 0;
  D.State := dsSum;
end;

{ DLE STX or DLE SOH: a new frame begins (also in the middle of another). }
procedure StartFrame(var D: tDF1Decoder; C: Byte);
begin
  D.Skip := False;
  D.Ignore := False;
  D.Bcc := 0;
  D.Crc := 0;
  D.BodyLen := 0;
  D.HdMaster := C = SOH;
  if D.HdMaster then
    D.State := dsStn
  else
  begin
    D.State := dsBody;
    { a half-duplex slave also hears other slaves' frames on a two-wire
      line: they are not for it }
    D.Ignore := not D.Cfg.FullDup and not D.Cfg.Master;
  end;
end;

{ Can C (after DLE) start a frame in this mode? }
function IsFrameStart(const D: tDF1Decoder; C: Byte): Boolean;
begin
  if C = STX then
    Result := True
  else if C = SOH then
    Result := not D.Cfg.FullDup and not D.Cfg.Master
  else
    Result := False;
end;

{ A DLE between frames was followed by C. }
function LinkSymbol(var D: tDF1Decoder; C: Byte): tDF1Event;
var
  WasSkip: Boolean;
begin
  Result := dfNone;
  WasSkip := D.Skip;
  D.State := dsIdle;
  if IsFrameStart(D, C) then
  begin
    StartFrame(D, C);
    Exit;
  end;
  case C of
    ACK:
      begin
        D.Skip := False;
        Result := ShortMsg(D, tpAckNak, True);
      end;
    NAK, NAKAlt:
      begin
        D.Skip := False;
        Result := ShortMsg(D, tpAckNak, False);
      end;
    ENQ:
      begin
        D.Skip := False;
        if D.Cfg.FullDup then
          Result := ShortMsg(D, tpEnq, False)
        else if not D.Cfg.Master then
          D.State := dsPollStn
        else
          Result := FailWhole(D, res_ErrFrame);   { a master is never polled }
      end;
    EOT:
      begin
        D.Skip := False;
        if D.Cfg.FullDup then
          Result := FailWhole(D, res_ErrFrame)
        else if D.Cfg.Master then
          Result := ShortMsg(D, tpNoPollRep, False);
        { a half-duplex slave ignores another slave's EOT }
      end;
    ETX:
      if WasSkip then
      begin
        { end of the frame being skipped: eat its checksum quietly }
        D.Ignore := True;
        SumLength(D);
      end
      else
        Result := FailWhole(D, res_ErrFrame);     { ETX without STX }
  else
    { DLE DLE or DLE + anything else outside a frame: we are probably in
      a frame whose start was lost; skip its tail quietly }
    if not WasSkip then
      Result := Fail(D, res_ErrFrame);
  end;
end;

{ The body and checksum are complete: check and decode. }
function Finish(var D: tDF1Decoder): tDF1Event;
var
  Ok: Boolean;
  Cmd: Byte;
  Start, N: Integer;
begin
  D.State := dsIdle;
  if D.Ignore then
  begin
    D.Ignore := False;
    D.Skip := False;
    Exit(dfNone);
  end;
  if D.Cfg.Crc then
    Ok := D.RxSum = D.Crc
  else
    Ok := D.RxSum = Bcc8Final(D.Bcc);
  if not Ok then
    Exit(FailWhole(D, res_ErrSum));
  if D.BodyLen < 6 then
    Exit(FailWhole(D, res_ErrFrame));      { no room for DST SRC CMD STS TNS }
  Cmd := D.Body[2];
  Start := 6;
  if DF1HasFnc(Cmd) then
    Start := 7;
  N := D.BodyLen - Start;
  if N < 0 then
    Exit(FailWhole(D, res_ErrFrame));      { FNC missing }
  if N > MaxDataLen then
    Exit(FailWhole(D, res_ErrLen));
  D.Skip := False;
  D.Dst := D.Body[0];
  D.Src := D.Body[1];
  FillChar(D.Msg, cSizeHead, 0);
  D.Msg.MessType := tpDataMess;
  if Start = 7 then
    D.Msg.CF := Cmd shl 8 or D.Body[6]
  else
    D.Msg.CF := Cmd shl 8;
  D.Msg.Sts := D.Body[3];
  D.Msg.Tns := D.Body[4] or (D.Body[5] shl 8);
  if N > 0 then
    Move(D.Body[Start], D.Msg.Data[0], N);
  D.MsgLen := cSizeHead + N;
  Result := dfMessage;
end;

procedure AddSum(var D: tDF1Decoder; B: Byte); inline;
begin
  D.Bcc := Bcc8Add(D.Bcc, B);
  D.Crc := Crc16Add(D.Crc, B);
end;

function AddBody(var D: tDF1Decoder; B: Byte): tDF1Event; inline;
begin
  if D.BodyLen >= DF1MaxBody then
    Exit(Fail(D, res_ErrLen));
  D.Body[D.BodyLen] := B;
  Inc(D.BodyLen);
  AddSum(D, B);
  D.State := dsBody;
  Result := dfNone;
end;

{ DLE + C where the frame cannot go on: a new frame interrupts it (report
  the broken one and start the new one), anything else breaks it. }
function Interrupt(var D: tDF1Decoder; C: Byte): tDF1Event;
var
  WasIgnored: Boolean;
begin
  if IsFrameStart(D, C) then
  begin
    WasIgnored := D.Ignore;
    StartFrame(D, C);
    if WasIgnored then
      Result := dfNone
    else
    begin
      D.Err := res_ErrFrame;
      Result := dfError;
    end;
  end
  else
    Result := Fail(D, res_ErrFrame);
end;

{ DLE + C inside the body, C <> DLE. }
function BodyControl(var D: tDF1Decoder; C: Byte): tDF1Event;
begin
  if C = ETX then
  begin
    D.Crc := Crc16Add(D.Crc, ETX);
    SumLength(D);
    Result := dfNone;
  end
  else if D.Cfg.FullDup and (C in [ACK, NAK, NAKAlt]) then
  begin
    { full duplex: a response to our own message embedded in this one }
    D.State := dsBody;
    Result := ShortMsg(D, tpAckNak, C = ACK);
  end
  else
    Result := Interrupt(D, C);
end;

procedure TakeStn(var D: tDF1Decoder; B: Byte);
begin
  D.Stn := B;
  AddSum(D, B);
  D.Ignore := B <> D.Cfg.Node;
  D.State := dsSohDle;
end;

function DF1Feed(var D: tDF1Decoder; B: Byte): tDF1Event;
begin
  Result := dfNone;
  case D.State of
    dsIdle:
      if B = DLE then
        D.State := dsIdleDle;
      { any other byte between frames is line noise: ignored }
    dsIdleDle:
      Result := LinkSymbol(D, B);
    dsStn:
      if B = DLE then
        D.State := dsStnDle
      else
        TakeStn(D, B);
    dsStnDle:
      if B = DLE then
        TakeStn(D, DLE)
      else
        Result := Interrupt(D, B);
    dsSohDle:
      if B = DLE then
        D.State := dsSohStx
      else
        Result := Fail(D, res_ErrFrame);
    dsSohStx:
      if B = STX then
        D.State := dsBody          { STN is already in both sums }
      else
        Result := Interrupt(D, B);
    dsBody:
      if B = DLE then
        D.State := dsBodyDle
      else
        Result := AddBody(D, B);
    dsBodyDle:
      if B = DLE then
        Result := AddBody(D, DLE)
      else
        Result := BodyControl(D, B);
    dsSum:
      begin
        { CRC low byte first; BCC is a single byte }
        if D.Cfg.Crc and (D.SumLeft = 1) then
          D.RxSum := D.RxSum or (B shl 8)
        else
          D.RxSum := B;
        Dec(D.SumLeft);
        if D.SumLeft = 0 then
          Result := Finish(D);
      end;
    dsPollStn:
      if B = DLE then
        D.State := dsPollStnDle
      else
      begin
        D.Stn := B;
        D.State := dsPollBcc;
      end;
    dsPollStnDle:
      if B = DLE then
      begin
        D.Stn := DLE;
        D.State := dsPollBcc;
      end
      else
        Result := Interrupt(D, B);
    dsPollBcc:
      begin
        D.State := dsIdle;
        if D.Stn <> D.Cfg.Node then
          { a poll for another station: not ours }
        else if B <> Bcc8Final(D.Stn) then
          Result := FailWhole(D, res_ErrSum)
        else
        begin
          D.Dst := D.Stn;
          D.Src := 0;
          Result := ShortMsg(D, tpPoll, False);
        end;
      end;
  else
    DF1DecoderReset(D);
  end;
end;

function DF1FeedBlock(var D: tDF1Decoder; const Buf; Len: Word; var Used: Word): tDF1Event;
var
  P: PByte;
begin
  P := @Buf;
  Used := 0;
  Result := dfNone;
  while (Result = dfNone) and (Used < Len) do
  begin
    Result := DF1Feed(D, P[Used]);
    Inc(Used);
  end;
end;

{- --------------------------------------------------------------- reply CF }

procedure DF1SentInit(var L: tDF1SentLog);
begin
  FillChar(L, SizeOf(L), 0);
end;

procedure DF1SentNote(var L: tDF1SentLog; Dst: Byte; constref Rec: tSendRecord);
begin
  if (Rec.MessType <> tpDataMess) or (Hi(Rec.CF) and $40 <> 0) then
    Exit;
  L.Items[L.Next].Dst := Dst;
  L.Items[L.Next].CF := Rec.CF;
  L.Items[L.Next].Tns := Rec.Tns;
  L.Next := (L.Next + 1) mod DF1SentMemory;
  if L.Count < DF1SentMemory then
    Inc(L.Count);
end;

function DF1ReplyCF(const L: tDF1SentLog; Src: Byte; constref Rec: tRecRecord): Word;
var
  I, Slot, Found: LongInt;
  Cmd: Byte;
begin
  Result := Rec.CF;
  Cmd := Hi(Rec.CF);
  if (Rec.MessType <> tpDataMess) or (Cmd and $40 = 0) then
    Exit;
  Found := -1;
  for I := 1 to L.Count do   { newest first }
  begin
    Slot := (L.Next + DF1SentMemory - I) mod DF1SentMemory;
    if (L.Items[Slot].Tns = Rec.Tns) and (Hi(L.Items[Slot].CF) or $40 = Cmd) then
    begin
      if L.Items[Slot].Dst = Src then
      begin
        Found := Slot;
        Break;
      end;
      if Found < 0 then
        Found := Slot;
    end;
  end;
  if Found >= 0 then
    Result := L.Items[Found].CF or $4000;
end;

function DF1SentTo(const L: tDF1SentLog; Dst: Byte): Boolean;
var
  I: LongInt;
begin
  for I := 0 to L.Count - 1 do
    if L.Items[I].Dst = Dst then
      Exit(True);
  Result := False;
end;

end.
