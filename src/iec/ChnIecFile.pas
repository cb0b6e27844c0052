{ ChnIecFile - the ASDUs of file transfer, IEC 60870-5-101 types 120..127
  (clause 7.3.6; IEC 60870-5-104 keeps them), without I/O: encode and
  decode, and the checksum. The procedures on top of them are
  ChnIecFileServer (controlled station) and ChnIecFileClient (controlling
  station).

  Elements after the IOA (every multi-octet field little-endian):
    F_FR_NA_1 120 file ready        NOF(2) LOF(3) FRQ
    F_SR_NA_1 121 section ready     NOF(2) NOS LOF(3) SRQ
    F_SC_NA_1 122 call, select      NOF(2) NOS SCQ
    F_LS_NA_1 123 last section/seg. NOF(2) NOS LSQ CHS
    F_AF_NA_1 124 ack file/section  NOF(2) NOS AFQ
    F_SG_NA_1 125 segment           NOF(2) NOS LOS segment(LOS octets)
    F_DR_TA_1 126 directory entry   NOF(2) LOF(3) SOF CP56Time2a
    F_SC_NB_1 127 query log         NOF(2) CP56Time2a(start) CP56Time2a(stop)
  NOF names the kind of file (1 transparent file, 2 disturbance data ...),
  the IOA the file itself; NOS the section (1..255); LOF the length of a
  file or section; CHS the arithmetic sum modulo 256 of the octets of the
  section (F_LS_NA_1 with LSQ 3/4) or of the whole file (LSQ 1/2).
  Every type carries one object, except the directory (several entries:
  each with its IOA, SQ = 0, or consecutive IOAs, SQ = 1, as decoded).

  Every refusal is a result code of ChnIec101Asdu (res_Asdu*) and a text
  naming the field; nothing reads or writes past the arrays given. }
unit ChnIecFile;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu;

const
  F_FR_NA_1 = 120; F_SR_NA_1 = 121; F_SC_NA_1 = 122; F_LS_NA_1 = 123;
  F_AF_NA_1 = 124; F_SG_NA_1 = 125; F_DR_TA_1 = 126; F_SC_NB_1 = 127;

  {- SCQ, low nibble (F_SC_NA_1) }
  Scq_Default       = 0;   {< with COT 5: call the directory }
  Scq_SelectFile    = 1;
  Scq_CallFile      = 2;
  Scq_DeactFile     = 3;
  Scq_DeleteFile    = 4;
  Scq_SelectSection = 5;
  Scq_CallSection   = 6;
  Scq_DeactSection  = 7;
  {- LSQ (F_LS_NA_1) }
  Lsq_File          = 1;   {< file transfer without deactivation }
  Lsq_FileDeact     = 2;   {< file transfer with deactivation (aborted) }
  Lsq_Section       = 3;   {< section transfer without deactivation }
  Lsq_SectionDeact  = 4;   {< section transfer with deactivation (aborted) }
  {- AFQ, low nibble (F_AF_NA_1) }
  Afq_FileOk        = 1;
  Afq_FileBad       = 2;
  Afq_SectionOk     = 3;
  Afq_SectionBad    = 4;
  {- the cause in the high nibble of SCQ and AFQ }
  Fe_None           = 0;
  Fe_NoMemory       = 1;   {< requested memory space not available }
  Fe_Checksum       = 2;   {< checksum failed }
  Fe_Unexpected     = 3;   {< unexpected communication service }
  Fe_UnknownFile    = 4;   {< unexpected name of file }
  Fe_UnknownSection = 5;   {< unexpected name of section }
  {- FRQ, SRQ bit 7 }
  Frq_Negative      = $80; {< file not ready (negative confirmation of a select ...) }
  Srq_NotReady      = $80; {< section not ready }
  {- SOF of a directory entry: STATUS bits 0-4 }
  Sof_LastFile      = $20; {< LFD: last file of the directory }
  Sof_Directory     = $40; {< FOR: the name is a subdirectory }
  Sof_Active        = $80; {< FA: file transfer active }
  {- NOF }
  Nof_Transparent   = 1;
  Nof_Disturbance   = 2;

  IecFileSegHead    = 4;   {< octets of an F_SG_NA_1 element before its data: NOF NOS LOS }

type
  { One file transfer object; the fields its type uses are filled, the
    others 0. Q is the type's qualifier: FRQ, SRQ, SCQ, LSQ, AFQ or SOF. }
  tIecFileObj = record
    Ioa   : LongWord;
    Nof   : Word;        {< name of file }
    Nos   : Byte;        {< name of section }
    Lof   : LongWord;    {< length of file (120, 126) or section (121), 0..16777215 }
    Q     : Byte;
    Chs   : Byte;        {< F_LS_NA_1 }
    SegLen: Byte;        {< F_SG_NA_1: LOS }
    Seg   : array[0..IecMaxAsdu - 1] of Byte;
    Time  : tIecTime;    {< F_DR_TA_1: time of creation; F_SC_NB_1: start }
    Stop  : tIecTime;    {< F_SC_NB_1: end of the range }
  end;

  { A file's octets in transit, section by section: what both roles
    keep, sending (ChnIecFileServer's files, ChnIecFileClient's put) or
    receiving. }
  tIecFileXfer = record
    Content: AnsiString;   {< the file, or what was received so far }
    Nos    : Byte;         {< the section under way }
    SecStart, SecLen, SecDone: LongInt;   {< the section in Content, octets sent/received }
    SecChs : Byte;         {< sending: the sum of the octets sent of the section }
  end;

{ 'F_SG_NA_1' for 120..127, '' otherwise. }
function IecFileTypeName(Ti: Byte): ShortString;
function IecIsFileType(Ti: Byte): Boolean;
{ Octets of one element after the IOA (F_SG_NA_1: without its data). }
function IecFileElemLen(Ti: Byte): LongInt;
{ The largest segment an ASDU of MaxAsdu octets carries under P. }
function IecFileMaxSegment(const P: tIecParams; MaxAsdu: Word): LongInt;
{ CHS: Start plus the Len octets of Buf, modulo 256. }
function IecFileChecksum(Start: Byte; const Buf: array of Byte; Len: LongInt): Byte;
{ 'checksum failed' ... for the cause nibble of SCQ/AFQ. }
function IecFileErrorName(Cause: Byte): ShortString;

{ Encode the object(s) of a file transfer ASDU: Ti, Cot (13 file
  transfer, 5 request, 3 spontaneous ...), P/N, Ca; Count objects of
  Objs (more than one only for F_DR_TA_1, SQ = 0). res_AsduType (not a
  file type), res_AsduCount, res_AsduValue / res_AsduIoa (a field out of
  range, Err names it), res_AsduLength (no room in Buf or above
  IecMaxAsdu). }
function IecFileEncode(const P: tIecParams; Ti, Cot: Byte; Negative: Boolean; Ca: Word;
  const Objs: array of tIecFileObj; Count: LongInt; var Buf: array of Byte; out Len: Word;
  out Err: ShortString): tChResult;
{ Decode the identifier of a file transfer ASDU (H) and its object Index
  (0..H.Count-1): res_AsduShort, res_AsduType (not 120..127), res_AsduCount
  (no object, more than one of a type that has one, Index outside),
  res_AsduLength (the length does not fit the type, count and LOS). }
function IecFileDecode(const P: tIecParams; const Buf: array of Byte; Len: Word;
  Index: LongInt; out H: tIecAsdu; out F: tIecFileObj; out Err: ShortString): tChResult;

{ Sending: section Nos (1..) of X.Content in sections of SectionSize;
  False past the last one. }
function IecXferSection(var X: tIecFileXfer; Nos: Byte; SectionSize: LongInt): Boolean;
{ Sending: the next segment of the section into O (SegLen, Seg; at most
  MaxSeg octets); False once the section is out (O.Chs: its checksum). }
function IecXferSegment(var X: tIecFileXfer; MaxSeg: LongInt; var O: tIecFileObj): Boolean;
{ Receiving: section Nos of Len octets comes next. }
procedure IecXferExpect(var X: tIecFileXfer; Nos: Byte; Len: LongInt);
{ Receiving: a segment's octets; False (nothing taken) when the section
  would be longer than announced. }
function IecXferTake(var X: tIecFileXfer; const O: tIecFileObj): Boolean;
{ Receiving: the checksum of the section received so far; whether all of
  it came. }
function IecXferSectionSum(const X: tIecFileXfer): Byte;
function IecXferSectionWhole(const X: tIecFileXfer): Boolean;
{ Receiving: forget the section (its checksum failed: it comes again). }
procedure IecXferDrop(var X: tIecFileXfer);
{ The checksum of a whole file. }
function IecFileSum(const Content: AnsiString): Byte;

implementation

uses
  SysUtils;

const
  Names: array[F_FR_NA_1..F_SC_NB_1] of string[9] = ('F_FR_NA_1', 'F_SR_NA_1', 'F_SC_NA_1',
    'F_LS_NA_1', 'F_AF_NA_1', 'F_SG_NA_1', 'F_DR_TA_1', 'F_SC_NB_1');
  ElemLens: array[F_FR_NA_1..F_SC_NB_1] of Byte = (6, 7, 4, 5, 4, IecFileSegHead, 13, 16);

function IecIsFileType(Ti: Byte): Boolean;
begin
  Result := (Ti >= F_FR_NA_1) and (Ti <= F_SC_NB_1);
end;

function IecFileTypeName(Ti: Byte): ShortString;
begin
  if IecIsFileType(Ti) then
    Result := Names[Ti]
  else
    Result := '';
end;

function IecFileElemLen(Ti: Byte): LongInt;
begin
  if IecIsFileType(Ti) then
    Result := ElemLens[Ti]
  else
    Result := -1;
end;

function IecFileMaxSegment(const P: tIecParams; MaxAsdu: Word): LongInt;
begin
  if MaxAsdu > IecMaxAsdu then
    MaxAsdu := IecMaxAsdu;
  Result := LongInt(MaxAsdu) - IecHeadLen(P) - P.IoaSize - IecFileSegHead;
  if Result > 255 then
    Result := 255;
end;

function IecFileChecksum(Start: Byte; const Buf: array of Byte; Len: LongInt): Byte;
var
  I: LongInt;
  Sum: LongWord;
begin
  Sum := Start;
  if Len > Length(Buf) then
    Len := Length(Buf);
  for I := 0 to Len - 1 do
    Sum := Sum + Buf[I];
  Result := Sum and $FF;
end;

function IecFileSum(const Content: AnsiString): Byte;
begin
  if Content = '' then
    Result := 0
  else
    Result := IecFileChecksum(0, PByteArray(@Content[1])^[0..Length(Content) - 1], Length(Content));
end;

function IecXferSection(var X: tIecFileXfer; Nos: Byte; SectionSize: LongInt): Boolean;
begin
  X.Nos := Nos;
  X.SecStart := (Nos - 1) * SectionSize;
  X.SecLen := Length(X.Content) - X.SecStart;
  if X.SecLen > SectionSize then
    X.SecLen := SectionSize;
  X.SecDone := 0;
  X.SecChs := 0;
  Result := X.SecLen > 0;
end;

function IecXferSegment(var X: tIecFileXfer; MaxSeg: LongInt; var O: tIecFileObj): Boolean;
var
  N: LongInt;
begin
  N := X.SecLen - X.SecDone;
  Result := N > 0;
  if not Result then
  begin
    O.Chs := X.SecChs;
    Exit;
  end;
  if N > MaxSeg then
    N := MaxSeg;
  O.SegLen := N;
  Move(X.Content[X.SecStart + X.SecDone + 1], O.Seg[0], N);
  X.SecChs := IecFileChecksum(X.SecChs, O.Seg, N);
  Inc(X.SecDone, N);
end;

procedure IecXferExpect(var X: tIecFileXfer; Nos: Byte; Len: LongInt);
begin
  X.Nos := Nos;
  X.SecStart := Length(X.Content);
  X.SecLen := Len;
  X.SecDone := 0;
end;

function IecXferTake(var X: tIecFileXfer; const O: tIecFileObj): Boolean;
begin
  Result := X.SecDone + O.SegLen <= X.SecLen;
  if not Result then
    Exit;
  SetLength(X.Content, X.SecStart + X.SecDone + O.SegLen);
  if O.SegLen > 0 then
    Move(O.Seg[0], X.Content[X.SecStart + X.SecDone + 1], O.SegLen);
  Inc(X.SecDone, O.SegLen);
end;

function IecXferSectionSum(const X: tIecFileXfer): Byte;
begin
  if X.SecDone = 0 then
    Result := 0
  else
    Result := IecFileChecksum(0, PByteArray(@X.Content[X.SecStart + 1])^[0..X.SecDone - 1], X.SecDone);
end;

function IecXferSectionWhole(const X: tIecFileXfer): Boolean;
begin
  Result := X.SecDone = X.SecLen;
end;

procedure IecXferDrop(var X: tIecFileXfer);
begin
  SetLength(X.Content, X.SecStart);
  X.SecDone := 0;
end;

function IecFileErrorName(Cause: Byte): ShortString;
begin
  case Cause of
    Fe_None: Result := 'no cause given';
    Fe_NoMemory: Result := 'requested memory space not available';
    Fe_Checksum: Result := 'checksum failed';
    Fe_Unexpected: Result := 'unexpected communication service';
    Fe_UnknownFile: Result := 'unexpected name of file';
    Fe_UnknownSection: Result := 'unexpected name of section';
  else
    Result := 'cause ' + IntToStr(Cause);
  end;
end;

function Refuse(R: tChResult; const Text: ShortString; out Err: ShortString): tChResult;
begin
  Err := Text;
  Result := R;
end;

procedure Put24(V: LongWord; var B: array of Byte; At: LongInt);
begin
  B[At] := V and $FF;
  B[At + 1] := (V shr 8) and $FF;
  B[At + 2] := (V shr 16) and $FF;
end;

function Get24(const B: array of Byte; At: LongInt): LongWord;
begin
  Result := B[At] or (LongWord(B[At + 1]) shl 8) or (LongWord(B[At + 2]) shl 16);
end;

{ The element of F after its IOA at B[At]. }
procedure PutElement(Ti: Byte; const F: tIecFileObj; var B: array of Byte; At: LongInt);
begin
  B[At] := Lo(F.Nof);
  B[At + 1] := Hi(F.Nof);
  Inc(At, 2);
  case Ti of
    F_FR_NA_1:
      begin
        Put24(F.Lof, B, At);
        B[At + 3] := F.Q;
      end;
    F_SR_NA_1:
      begin
        B[At] := F.Nos;
        Put24(F.Lof, B, At + 1);
        B[At + 4] := F.Q;
      end;
    F_SC_NA_1, F_AF_NA_1:
      begin
        B[At] := F.Nos;
        B[At + 1] := F.Q;
      end;
    F_LS_NA_1:
      begin
        B[At] := F.Nos;
        B[At + 1] := F.Q;
        B[At + 2] := F.Chs;
      end;
    F_SG_NA_1:
      begin
        B[At] := F.Nos;
        B[At + 1] := F.SegLen;
        if F.SegLen > 0 then
          Move(F.Seg[0], B[At + 2], F.SegLen);
      end;
    F_DR_TA_1:
      begin
        Put24(F.Lof, B, At);
        B[At + 3] := F.Q;
        IecPutTime(F.Time, tkCP56, B, At + 4);
      end;
    F_SC_NB_1:
      begin
        IecPutTime(F.Time, tkCP56, B, At);
        IecPutTime(F.Stop, tkCP56, B, At + 7);
      end;
  end;
end;

procedure GetElement(Ti: Byte; const B: array of Byte; At: LongInt; var F: tIecFileObj);
begin
  F.Nof := B[At] or (Word(B[At + 1]) shl 8);
  Inc(At, 2);
  case Ti of
    F_FR_NA_1:
      begin
        F.Lof := Get24(B, At);
        F.Q := B[At + 3];
      end;
    F_SR_NA_1:
      begin
        F.Nos := B[At];
        F.Lof := Get24(B, At + 1);
        F.Q := B[At + 4];
      end;
    F_SC_NA_1, F_AF_NA_1:
      begin
        F.Nos := B[At];
        F.Q := B[At + 1];
      end;
    F_LS_NA_1:
      begin
        F.Nos := B[At];
        F.Q := B[At + 1];
        F.Chs := B[At + 2];
      end;
    F_SG_NA_1:
      begin
        F.Nos := B[At];
        F.SegLen := B[At + 1];
        if F.SegLen > 0 then
          Move(B[At + 2], F.Seg[0], F.SegLen);
      end;
    F_DR_TA_1:
      begin
        F.Lof := Get24(B, At);
        F.Q := B[At + 3];
        IecGetTime(B, At + 4, tkCP56, F.Time);
      end;
    F_SC_NB_1:
      begin
        IecGetTime(B, At, tkCP56, F.Time);
        IecGetTime(B, At + 7, tkCP56, F.Stop);
      end;
  end;
end;

function IecFileEncode(const P: tIecParams; Ti, Cot: Byte; Negative: Boolean; Ca: Word;
  const Objs: array of tIecFileObj; Count: LongInt; var Buf: array of Byte; out Len: Word;
  out Err: ShortString): tChResult;
var
  H: tIecAsdu;
  At: Word;
  I, Need, Room: LongInt;
begin
  Len := 0;
  if not IecIsFileType(Ti) then
    Exit(Refuse(res_AsduType, 'type ' + IntToStr(Ti) + ' is no file transfer type (120..127)', Err));
  if (Count < 1) or (Count > Length(Objs)) or (Count > IecMaxObjects) or
     ((Count > 1) and (Ti <> F_DR_TA_1)) then
    Exit(Refuse(res_AsduCount, Names[Ti] + ' with ' + IntToStr(Count) + ' objects', Err));
  Need := IecHeadLen(P) + Count * (P.IoaSize + ElemLens[Ti]);
  if Ti = F_SG_NA_1 then
    Inc(Need, Objs[0].SegLen);
  Room := Length(Buf);
  if Room > IecMaxAsdu then
    Room := IecMaxAsdu;
  if Need > Room then
    Exit(Refuse(res_AsduLength, Names[Ti] + ' needs ' + IntToStr(Need) + ' octets, room for '
      + IntToStr(Room), Err));
  for I := 0 to Count - 1 do
    with Objs[I] do
      if Ioa > IecMaxIoa(P) then
        Exit(Refuse(res_AsduIoa, Names[Ti] + ': IOA ' + IntToStr(Ioa) + ' too large for '
          + IntToStr(P.IoaSize) + ' octet(s)', Err))
      else if Lof > $FFFFFF then
        Exit(Refuse(res_AsduValue, Names[Ti] + ': length ' + IntToStr(Lof) + ' above 16777215', Err));
  FillChar(H, SizeOf(H), 0);
  H.Ti := Ti;
  H.Count := Count;
  H.Cot := Cot;
  H.Negative := Negative;
  H.Ca := Ca;
  Result := IecPutIdent(P, H, Buf, At, Err);
  if Result <> res_Ok then
    Exit;
  for I := 0 to Count - 1 do
  begin
    IecPutIoa(P, Objs[I].Ioa, Buf, At);
    Inc(At, P.IoaSize);
    PutElement(Ti, Objs[I], Buf, At);
    Inc(At, ElemLens[Ti]);
  end;
  if Ti = F_SG_NA_1 then
    Inc(At, Objs[0].SegLen);
  Len := At;
  Err := '';
end;

function IecFileDecode(const P: tIecParams; const Buf: array of Byte; Len: Word;
  Index: LongInt; out H: tIecAsdu; out F: tIecFileObj; out Err: ShortString): tChResult;
var
  Need, At, Elem: LongInt;
begin
  FillChar(F, SizeOf(F), 0);
  Result := IecDecodeHeader(P, Buf, Len, H, Err);
  if Result = res_Ok then
    Exit(Refuse(res_AsduType, IecTypeName(H.Ti) + ' is no file transfer type', Err));
  if Result <> res_AsduType then
    Exit;
  if not IecIsFileType(H.Ti) then
    Exit;                                { the codec's own text: unknown type }
  Elem := ElemLens[H.Ti];
  if (H.Count = 0) or ((H.Count > 1) and (H.Ti <> F_DR_TA_1)) then
    Exit(Refuse(res_AsduCount, Names[H.Ti] + ' with ' + IntToStr(H.Count) + ' objects', Err));
  if (Index < 0) or (Index >= H.Count) then
    Exit(Refuse(res_AsduCount, Names[H.Ti] + ': no object ' + IntToStr(Index), Err));
  if H.Sq then
    Need := H.HeadLen + P.IoaSize + H.Count * Elem
  else
    Need := H.HeadLen + H.Count * (P.IoaSize + Elem);
  if (H.Ti = F_SG_NA_1) and (Len >= Need) then
    Inc(Need, Buf[Need - 1]);            { LOS, the last octet of the head }
  if Need <> Len then
    Exit(Refuse(res_AsduLength, Names[H.Ti] + ' with ' + IntToStr(H.Count) + ' object(s) needs '
      + IntToStr(Need) + ' octets, got ' + IntToStr(Len), Err));
  if H.Sq then
  begin
    F.Ioa := IecGetIoa(P, Buf, H.HeadLen) + LongWord(Index);
    At := H.HeadLen + P.IoaSize + Index * Elem;
  end
  else
  begin
    At := H.HeadLen + Index * (P.IoaSize + Elem);
    F.Ioa := IecGetIoa(P, Buf, At);
    Inc(At, P.IoaSize);
  end;
  GetElement(H.Ti, Buf, At, F);
  Err := '';
  Result := res_Ok;
end;

end.
