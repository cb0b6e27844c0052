{ ChnFT12Codec - the IEC 60870-5-2 FT 1.2 frame codec, free of I/O.

  Implements the frame formats of the SofCon ChnFT1_2 manual (chapter 6)
  and docs/PROTOCOLS.md section 5:
    fixed length     SD1($10) CODE ADDR DATA[LEN] SUM ED($16)
    variable length  SD2($68) L L SD2 CODE ADDR DATA SUM ED
    single character SACK($E5), SNAK($A2)
  SUM is the byte sum of CODE, ADDR and DATA modulo 256; L counts CODE,
  ADDR and DATA. LEN = 0 gives the IEC 60870-5-101 fixed frame 10 C A CS 16.

  Beyond the manual (real IEC 101 links need it): the link address has
  0, 1 or 2 octets (2 octets: little-endian), and a line-idle gap inside a
  frame can discard the half-received frame (IEC 60870-5-1 FT 1.2 allows no
  gap between the characters of a frame).

  Two plain entry points, used by tChnFT1_2 and usable by tools and
  benchmarks as they are:
    FT12Encode  record -> frame bytes
    FT12Feed    one received byte -> receive automaton -> event
  The record type and the protocol constants live here; ChnFT1_2 exports
  them again under the manual's names. }
unit ChnFT12Codec;

{$I chn.inc}

interface

uses
  ChnTypes;

const
  MaxDataLen = 247;

  SD1  = $10;   {< start of a fixed-length frame }
  SD2  = $68;   {< start of a variable-length frame }
  ED   = $16;   {< end of a frame }
  SACK = $E5;   {< single character: positive acknowledgement }
  SNAK = $A2;   {< single character: negative acknowledgement }

  {- CODE bits }
  cBitDirRes = $80;   {< DIR in balanced mode, RES (0) in unbalanced mode }
  cBitPrm    = $40;   {< 1: frame from a master/primary station }
  cBitFcbAcd = $20;   {< FCB from a primary, ACD from a secondary }
  cBitFcvDfc = $10;   {< FCV from a primary, DFC from a secondary }
  cMaskFC    = $0F;

  {- Receive results (manual 4.3) }
  res_ErrSum   = res_Proto + 0;   {< $20 checksum error }
  res_ErrLen   = res_Proto + 1;   {< $21 bad length (L bytes, L range, buffer) }
  res_ErrCode  = res_Proto + 2;   {< $22 PRM bit does not fit this station }
  res_ErrFrame = res_Proto + 3;   {< $23 wrong second start byte, missing ED }
  res_ErrDir   = res_Proto + 4;   {< $24 balanced: DIR bit of this station's own side }

  cSizeHeadSndMsg = 1 + 1 + 1 + 1;   {< MessType, FCB_ACD, FCV_DFC, FC }
  cSizeHeadRecMsg = cSizeHeadSndMsg;

  { User data of the longest frame IEC 60870-5-1/-2 allow: L = 255 counts
    the control octet, the link address (0..2 octets) and the data, so up
    to 254 data octets (253 with ADR=1, lib60870's default ASDU of 249
    fits). The manual's records (tFT12Record) hold MaxDataLen = 247. }
  FT12MaxUserData = 255 - 1;

  { Longest frame: 68 L L 68, L = 255 octets (CODE ADDR DATA), SUM 16 }
  cFT12MaxFrame = 4 + 255 + 2;

type
  tMessType = (tpSACK, tpSNAK, tpShortM, tpLongM);
  tData = array[1..MaxDataLen] of Byte;

  { tSendRecord = tRecRecord of the manual (4.4); packed by chn.inc:
    MessType@0 FCB_ACD@1 FCV_DFC@2 FC@3 Data@4. }
  tFT12Record = record
    MessType: tMessType;
    FCB_ACD : Boolean;
    FCV_DFC : Boolean;
    FC      : Byte;
    Data    : tData;
  end;

  { The same with room for any frame (L up to 255): the link helpers
    receive into it. }
  tFT12MaxRecord = record
    MessType: tMessType;
    FCB_ACD : Boolean;
    FCV_DFC : Boolean;
    FC      : Byte;
    Data    : array[1..FT12MaxUserData] of Byte;
  end;

  { What the codec needs to know about this station and the link. }
  tFT12Config = record
    AddrLen  : Byte;     {< link address octets: 0, 1 or 2 }
    FixedLen : Byte;     {< data octets of a fixed frame (LEN=), 0..MaxDataLen;
                           above that every fixed frame is res_ErrLen }
    Balanced : Boolean;  {< balanced: bit 7 is DIR, else RES (sent as 0) }
    Dir      : Boolean;  {< DIR bit this station sends in balanced mode }
    Primary  : Boolean;  {< PRM bit this station sends }
    CheckPrm : Boolean;  {< receive: PRM must be the opposite of Primary }
    Filter   : Boolean;  {< receive: only frames for OwnAddr or broadcast;
                           balanced: only PRM = 1 frames are filtered }
    OwnAddr  : Word;
    GapMs    : LongWord; {< receive: idle gap that discards a frame, 0 = off }
    CheckDir : Boolean;  {< receive, balanced: a frame with DIR = Dir came from
                           this station's own side (an echo, or both stations
                           configured alike): res_ErrDir }
  end;

  tFT12Event = (fe_None,    {< byte consumed, nothing complete }
                fe_Frame,   {< a valid frame is in the state record }
                fe_Error);  {< a broken frame was dropped; see Err }

  { Receive automaton. After fe_Frame: Kind, Code, Addr, DataLen, Data
    describe the frame until the next FT12Feed. }
  tFT12Rx = record
    Cfg     : tFT12Config;
    Phase   : Byte;       {< rx* below }
    Kind    : tMessType;
    L       : Byte;       {< L of a variable frame }
    Code    : Byte;
    Addr    : Word;
    AddrPos : Byte;
    DataLen : Word;
    DataPos : Word;
    Sum     : tSum8;
    Err     : tChResult;  {< code of the last fe_Error }
    LastTime: QWord;      {< time of the previous byte, for the gap }
    Data    : array[0..FT12MaxUserData - 1] of Byte;
    { counters for diagnostics }
    Frames, Errors, Ignored, GapDrops: LongWord;
    { garbage or a broken frame since the last whole frame: a single
      character is taken only after FT12SuspectIdleMs of line idle }
    Suspect : Boolean;
    Suspects: LongWord;   {< single characters dropped so }
    { of Ignored: frames with another link address (not the broadcast),
      and the address the last of them carried }
    Foreign : LongWord;
    ForeignAddr: Word;
  end;

{ Broadcast address for the given address length (255 or 65535). }
function FT12Broadcast(AddrLen: Byte): Word;
{ Highest address for the given address length (255 or 65535). }
function FT12MaxAddr(AddrLen: Byte): Word;

{ CODE octet of a primary or secondary frame described by Rec. }
function FT12Code(const Cfg: tFT12Config; const Rec: tFT12Record): Byte;

{ Encode Rec (Len = cSizeHeadSndMsg + data octets; ignored for SACK and
  SNAK) with link address Addr into Dest[0..DestSize-1].
  Results: res_Ok; res_BadLen (Len 0 or below the header, a fixed frame
  whose data length is not Cfg.FixedLen); res_TooLong (L would
  exceed 255, or the frame does not fit DestSize);
  res_BadMessage (MessType out of range, FC > 15, SACK/SNAK from a primary,
  Addr too large for Cfg.AddrLen). On error DestLen = 0 and Dest is not
  touched. Only the first Len bytes of Rec are read. }
function FT12Encode(const Cfg: tFT12Config; constref Rec: tFT12Record;
  Len: Word; Addr: Word; Dest: PByte; DestSize: Word; var DestLen: Word): tChResult;

const
  { A single character (E5, A2) has no check of its own: met while hunting
    after a broken frame or a skipped byte, it may be a byte of the broken
    frame - an ACK nobody sent. It counts only once the line has been idle
    this long (or GapMs, when longer; USB adapters deliver in bursts up to
    about 16 ms apart) or a whole frame came in between. }
  FT12SuspectIdleMs = 50;

{ Start hunting for a frame; Cfg is kept, counters are cleared. }
procedure FT12RxReset(var S: tFT12Rx);

{ Feed one received byte. Now is a millisecond time stamp (ChMsTick in the
  channel, anything monotonic in tests); it is only used when
  S.Cfg.GapMs > 0: a frame whose previous byte came more than GapMs earlier
  is discarded silently and B starts the hunt anew.
  After an error the byte that showed it is dropped and the automaton hunts
  for the next start character; a single character met then is dropped
  (counted in Suspects) until the line was idle (FT12SuspectIdleMs).
  Frames that Cfg.Filter rejects are ignored (fe_None). }
function FT12Feed(var S: tFT12Rx; B: Byte; Now: QWord): tFT12Event;

{ Copy the frame of the last fe_Frame into a record buffer of Size bytes.
  Len = 1 for SACK/SNAK (only MessType is written), else
  cSizeHeadRecMsg + data octets. res_ErrLen with Len = 0 and nothing
  written when the buffer is too small. }
function FT12GetRecord(const S: tFT12Rx; Buf: Pointer; Size: Word;
  var Len: Word): tChResult;

{ PRM bit of the last frame (single characters count as secondary frames). }
function FT12FramePrm(const S: tFT12Rx): Boolean;

implementation

const
  rxHunt   = 0;
  rxL1     = 1;
  rxL2     = 2;
  rxStart2 = 3;
  rxCode   = 4;
  rxAddr   = 5;
  rxData   = 6;
  rxSum    = 7;
  rxEnd    = 8;

function FT12Broadcast(AddrLen: Byte): Word;
begin
  if AddrLen >= 2 then
    Result := $FFFF
  else
    Result := $FF;
end;

function FT12MaxAddr(AddrLen: Byte): Word;
begin
  Result := FT12Broadcast(AddrLen);
end;

function FT12Code(const Cfg: tFT12Config; const Rec: tFT12Record): Byte;
begin
  Result := Rec.FC and cMaskFC;
  if Cfg.Balanced and Cfg.Dir then
    Result := Result or cBitDirRes;
  if Cfg.Primary then
    Result := Result or cBitPrm;
  if Rec.FCB_ACD then
    Result := Result or cBitFcbAcd;
  if Rec.FCV_DFC then
    Result := Result or cBitFcvDfc;
end;

function FT12Encode(const Cfg: tFT12Config; constref Rec: tFT12Record;
  Len: Word; Addr: Word; Dest: PByte; DestSize: Word; var DestLen: Word): tChResult;
var
  N, Need, I, P: Integer;
  Code: Byte;
  Sum: tSum8;
  Frame: array[0..cFT12MaxFrame - 1] of Byte;
begin
  DestLen := 0;
  if PByte(@Rec)^ > Ord(High(tMessType)) then   { a byte from the caller }
    Exit(res_BadMessage);
  if Rec.MessType in [tpSACK, tpSNAK] then
  begin
    { the manual: Len is ignored for single characters (0 is fine).
      They answer a primary; a primary never sends them. }
    if Cfg.Primary then
      Exit(res_BadMessage);
    if DestSize < 1 then
      Exit(res_TooLong);
    if Rec.MessType = tpSACK then
      Dest[0] := SACK
    else
      Dest[0] := SNAK;
    DestLen := 1;
    Exit(res_Ok);
  end;
  if Len < cSizeHeadSndMsg then
    Exit(res_BadLen);
  N := Len - cSizeHeadSndMsg;
  if N > FT12MaxUserData - Cfg.AddrLen then
    Exit(res_TooLong);
  if (Rec.MessType = tpShortM) and (N <> Cfg.FixedLen) then
    Exit(res_BadLen);
  if Rec.FC > cMaskFC then
    Exit(res_BadMessage);
  if (Cfg.AddrLen > 0) and (Addr > FT12MaxAddr(Cfg.AddrLen)) then
    Exit(res_BadMessage);
  Code := FT12Code(Cfg, Rec);
  P := 0;
  if Rec.MessType = tpShortM then
  begin
    Frame[0] := SD1;
    P := 1;
  end
  else
  begin
    Frame[0] := SD2;
    Frame[1] := 1 + Cfg.AddrLen + N;   { L: CODE + ADDR + DATA }
    Frame[2] := Frame[1];
    Frame[3] := SD2;
    P := 4;
  end;
  Frame[P] := Code;
  Inc(P);
  if Cfg.AddrLen >= 1 then
  begin
    Frame[P] := Lo(Addr);
    Inc(P);
  end;
  if Cfg.AddrLen >= 2 then
  begin
    Frame[P] := Hi(Addr);
    Inc(P);
  end;
  { the caller's record may be longer than tFT12Record (Len says) }
  if N > 0 then
    Move(tFT12MaxRecord(Pointer(@Rec)^).Data[1], Frame[P], N);
  Inc(P, N);
  if Rec.MessType = tpShortM then
    Sum := Sum8Block(Frame[1], P - 1)
  else
    Sum := Sum8Block(Frame[4], P - 4);
  Frame[P] := Sum;
  Frame[P + 1] := ED;
  Need := P + 2;
  if Need > DestSize then
    Exit(res_TooLong);
  Move(Frame, Dest^, Need);
  DestLen := Need;
  Result := res_Ok;
end;

procedure FT12RxReset(var S: tFT12Rx);
var
  C: tFT12Config;
begin
  C := S.Cfg;
  FillChar(S, SizeOf(S), 0);
  S.Cfg := C;
  S.Phase := rxHunt;
end;

function FT12FramePrm(const S: tFT12Rx): Boolean;
begin
  Result := (S.Kind in [tpShortM, tpLongM]) and (S.Code and cBitPrm <> 0);
end;

{ A whole, well-formed frame: apply the station's address filter and role. }
function Complete(var S: tFT12Rx): tFT12Event;
var
  Prm, Single, Foreign: Boolean;
begin
  S.Phase := rxHunt;
  S.Suspect := False;           { a whole frame: the line is in step again }
  Prm := FT12FramePrm(S);
  Single := S.Kind in [tpSACK, tpSNAK];
  Foreign := (S.Addr <> S.Cfg.OwnAddr) and (S.Addr <> FT12Broadcast(S.Cfg.AddrLen));
  { unbalanced: single characters carry no address; on a shared line they
    are the answers of other secondaries, never meant for a secondary.
    Balanced: answers (PRM = 0, single characters) come from the one peer
    and carry its address; only requests are for this station or not }
  if S.Cfg.Filter and
     ((not S.Cfg.Balanced and (Single or Foreign)) or
      (S.Cfg.Balanced and Prm and Foreign)) then
  begin
    Inc(S.Ignored);
    if Foreign and not Single then
    begin
      Inc(S.Foreign);
      S.ForeignAddr := S.Addr;
    end;
    Exit(fe_None);
  end;
  if S.Cfg.Balanced and S.Cfg.CheckDir and not Single and
     ((S.Code and cBitDirRes <> 0) = S.Cfg.Dir) then
  begin
    S.Err := res_ErrDir;
    Inc(S.Errors);
    Exit(fe_Error);
  end;
  if S.Cfg.CheckPrm and (Prm = S.Cfg.Primary) then
  begin
    S.Err := res_ErrCode;
    Inc(S.Errors);
    Exit(fe_Error);
  end;
  Inc(S.Frames);
  Result := fe_Frame;
end;

function Fail(var S: tFT12Rx; R: tChResult): tFT12Event;
begin
  S.Phase := rxHunt;
  S.Suspect := True;
  S.Err := R;
  Inc(S.Errors);
  Result := fe_Error;
end;

{ After CODE (and ADDR): data, or the checksum if there is no data. }
procedure AfterHeader(var S: tFT12Rx);
begin
  if S.DataLen > 0 then
    S.Phase := rxData
  else
    S.Phase := rxSum;
end;

{ The time since the previous byte: a gap inside a frame drops it; a
  line idle long enough is in step again. }
procedure WatchIdle(var S: tFT12Rx; Now: QWord); inline;
var
  Idle: QWord;                  { ms since the previous byte }
begin
  Idle := 0;
  if Now > S.LastTime then
    Idle := Now - S.LastTime;
  if (S.Phase <> rxHunt) and (S.Cfg.GapMs > 0) and (Idle > S.Cfg.GapMs) then
  begin
    S.Phase := rxHunt;          { the line was idle inside a frame }
    S.Suspect := True;
    Inc(S.GapDrops);
  end;
  if S.Suspect and (Idle >= FT12SuspectIdleMs) and (Idle >= S.Cfg.GapMs) then
    S.Suspect := False;         { idle long enough: no broken frame goes on }
  S.LastTime := Now;
end;

{ Between frames: B starts a fixed or a variable frame, is a single
  character (a whole frame), or is garbage. }
function Hunt(var S: tFT12Rx; B: Byte): tFT12Event;
begin
  Result := fe_None;
  case B of
    SD1:
      if S.Cfg.FixedLen > MaxDataLen then
        Result := Fail(S, res_ErrLen)   { a configuration no frame fits }
      else
      begin
        S.Kind := tpShortM;
        S.DataLen := S.Cfg.FixedLen;
        S.Sum := 0;
        S.Phase := rxCode;
      end;
    SD2:
      S.Phase := rxL1;
    SACK, SNAK:
      if S.Suspect then
        Inc(S.Suspects)     { maybe a byte of the frame just broken }
      else
      begin
        if B = SACK then
          S.Kind := tpSACK
        else
          S.Kind := tpSNAK;
        S.Code := 0;
        S.Addr := 0;
        S.DataLen := 0;
        Result := Complete(S);
      end;
  else
    S.Suspect := True;      { not a start character: garbage, skipped }
  end;
end;

{ The head of a variable frame after its first start character: L, L
  again, the second start character. }
function LengthHead(var S: tFT12Rx; B: Byte): tFT12Event;
begin
  Result := fe_None;
  case S.Phase of
    rxL1:
      begin
        S.L := B;
        S.Phase := rxL2;
      end;
    rxL2:
      if B <> S.L then
        Result := Fail(S, res_ErrLen)
      else if S.L < 1 + S.Cfg.AddrLen then     { any L up to 255 is legal }
        Result := Fail(S, res_ErrLen)
      else
        S.Phase := rxStart2;
  else                                         { rxStart2 }
    if B <> SD2 then
      Result := Fail(S, res_ErrFrame)
    else
    begin
      S.Kind := tpLongM;
      S.DataLen := S.L - 1 - S.Cfg.AddrLen;
      S.Sum := 0;
      S.Phase := rxCode;
    end;
  end;
end;

function FT12Feed(var S: tFT12Rx; B: Byte; Now: QWord): tFT12Event;
begin
  Result := fe_None;
  WatchIdle(S, Now);
  case S.Phase of
    rxHunt:
      Result := Hunt(S, B);
    rxL1, rxL2, rxStart2:
      Result := LengthHead(S, B);
    rxCode:
      begin
        S.Code := B;
        S.Sum := Sum8Add(S.Sum, B);
        S.Addr := 0;
        S.AddrPos := 0;
        S.DataPos := 0;
        if S.Cfg.AddrLen > 0 then
          S.Phase := rxAddr
        else
          AfterHeader(S);
      end;
    rxAddr:
      begin
        S.Sum := Sum8Add(S.Sum, B);
        if S.AddrPos = 0 then
          S.Addr := B
        else
          S.Addr := S.Addr or (Word(B) shl 8);   { little-endian }
        Inc(S.AddrPos);
        if S.AddrPos >= S.Cfg.AddrLen then
          AfterHeader(S);
      end;
    rxData:
      begin
        S.Sum := Sum8Add(S.Sum, B);
        if S.DataPos < SizeOf(S.Data) then   { DataLen <= FT12MaxUserData always }
          S.Data[S.DataPos] := B;
        Inc(S.DataPos);
        if S.DataPos >= S.DataLen then
          S.Phase := rxSum;
      end;
    rxSum:
      if B <> S.Sum then
        Result := Fail(S, res_ErrSum)
      else
        S.Phase := rxEnd;
    rxEnd:
      if B <> ED then
        Result := Fail(S, res_ErrFrame)
      else
        Result := Complete(S);
  else
    S.Phase := rxHunt;
  end;
end;

function FT12GetRecord(const S: tFT12Rx; Buf: Pointer; Size: Word;
  var Len: Word): tChResult;
var
  Need: Word;
  R: ^tFT12Record;
begin
  Len := 0;
  if Buf = nil then
    Exit(res_NoRecBuff);
  R := Buf;
  if S.Kind in [tpSACK, tpSNAK] then
    Need := 1
  else
    Need := cSizeHeadRecMsg + S.DataLen;
  if Need > Size then
    Exit(res_ErrLen);
  R^.MessType := S.Kind;
  if Need > 1 then
  begin
    R^.FCB_ACD := S.Code and cBitFcbAcd <> 0;
    R^.FCV_DFC := S.Code and cBitFcvDfc <> 0;
    R^.FC := S.Code and cMaskFC;
    if S.DataLen > 0 then
      Move(S.Data[0], R^.Data[1], S.DataLen);
  end;
  Len := Need;
  Result := res_Ok;
end;

end.
