{ ChnIecFileServer - file transfer of an IEC 60870-5-101/104 controlled
  station (IEC 60870-5-101 clause 7.4.11, 5.6 of IEC 60870-5-5): the
  directory, files sent to the controlling station and files received
  from it. No I/O of its own: ChnIec101Slave hands it the file ASDUs it
  receives (IecFileServerTake) and sends what it has to send
  (IecFileServerNext) whenever its queue has room, so a long file never
  fills the slave's queues and the slave stays one thread without sleeps.

  Files: those the program adds (IecFileServerAdd: a disturbance record
  kept in memory ...) and, with Dir set, the files of a directory named by
  their IOA: '30000' or '30000.anything' is the file of IOA 30000 (NOF
  Nof_Transparent); other names are not served. A file received goes to
  OnReceived and, with Dir set, to Dir/<IOA>.

  Sending a file (the controlling station's select, call, acks):
    <- F_SC_NA_1 SCQ 1 select file    -> F_FR_NA_1 file ready (LOF; FRQ bit 7: unknown file)
    <- F_SC_NA_1 SCQ 2 call file      -> F_SR_NA_1 section 1 ready (its length)
    <- F_SC_NA_1 SCQ 6 call section   -> F_SG_NA_1 segments ..., F_LS_NA_1 LSQ 3 with the
                                         section's checksum
    <- F_AF_NA_1 AFQ 3 section ok     -> the next F_SR_NA_1, or after the last section
                                         F_LS_NA_1 LSQ 1 with the file's checksum
       F_AF_NA_1 AFQ 4 section bad    -> the same section again (F_SR_NA_1)
    <- F_AF_NA_1 AFQ 1 file ok        -> done (Sent); AFQ 2: failed (Failed, LastError)
    <- F_SC_NA_1 SCQ 5 select section -> F_SR_NA_1 of that section (SRQ bit 7: there is
                                         none); the transfer goes on from there
    <- F_SC_NA_1 SCQ 7 deactivate section -> the section stops; the file stays called (a
                                         call file or a select section goes on)
    <- F_SC_NA_1 SCQ 3 deactivate file -> aborted (Aborted): ready for the next at once
  Deleting a file (with or without a select before):
    <- F_SC_NA_1 SCQ 4 delete file    -> F_AF_NA_1 AFQ 1 (deleted, Deleted counts), or AFQ 2
                                         + cause 4 (no such file) or 3 (OnDelete refused,
                                         the OS could not, NoDelete; LastError says why)
  Receiving a file:
    <- F_FR_NA_1 file ready (LOF)     -> F_SC_NA_1 SCQ 2 call file (F_FR_NA_1 with FRQ bit 7:
                                         refused - no Dir, no OnReceived, too long)
    <- F_SR_NA_1 section ready        -> F_SC_NA_1 SCQ 6 call section
    <- F_SG_NA_1 segments, F_LS_NA_1 LSQ 3 -> F_AF_NA_1 AFQ 3, or AFQ 4 + cause 2 when
                                         the checksum is not the sum of the segments
                                         (the section is dropped: the peer sends it again)
    <- F_LS_NA_1 LSQ 1                -> F_AF_NA_1 AFQ 1, the file kept; AFQ 2 + cause 2
                                         (checksum) or 3 (length not LOF): dropped
    <- F_LS_NA_1 LSQ 2                -> aborted by the peer: ready for the next at once
    <- F_LS_NA_1 LSQ 4                -> the section dropped: the peer offers it again
  Directory: F_SC_NA_1 with COT 5 -> F_DR_TA_1 entries with COT 5 (as many
  per ASDU as fit; the last entry has SOF bit LFD); no file: the call
  mirrored with P/N = 1.
  Query log: F_SC_NB_1 with COT 5 (NOF, range start and stop, CP56Time2a)
  -> F_DR_TA_1 with COT 5 of the files of that NOF (NOF 0: any) created
  in the range, both ends included; none (or a range that is no date):
  the query mirrored with P/N = 1.
  A transfer the peer leaves for TimeoutMs ends (Aborted, LastError); a
  select or file ready starts a new one whatever runs. Every ASDU of the
  wrong common address is mirrored with COT 46 and P/N = 1. }
unit ChnIecFileServer;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIecFile;

const
  IecFileMaxFiles = 64;           {< program's files }
  IecFileMaxLen   = 16777215;     {< LOF: three octets }

type
  { A file from the program: Content as octets (an AnsiString). }
  tIecFileEntry = record
    Ioa    : LongWord;
    Nof    : Word;
    Time   : tIecTime;   {< time of creation, in the directory }
    Content: AnsiString;
  end;

  { A file received completely, checksums right. }
  tIecFileReceivedFunc = procedure(Data: Pointer; Ioa: LongWord; Nof: Word; const Content: AnsiString);
  { The master asks to delete file Ioa: True lets the server delete it,
    False refuses (Why: the reason, kept in LastError). }
  tIecFileDeleteFunc = function(Data: Pointer; Ioa: LongWord; Nof: Word; out Why: ShortString): Boolean;

  tIecFileServerState = (fsIdle,
    fsSelected,        {< F_FR_NA_1 sent: waiting for the call file }
    fsSectionReady,    {< F_SR_NA_1 sent: waiting for the call section }
    fsSending,         {< segments going out }
    fsSectionAck,      {< F_LS_NA_1 LSQ 3 sent }
    fsFileCalled,      {< a section deactivated: waiting for a select section or call file }
    fsFileAck,         {< F_LS_NA_1 LSQ 1 sent }
    fsReceiveReady,    {< call file sent: waiting for a section ready or the last section }
    fsReceiving);      {< call section sent: segments coming }

  tIecFileServer = record
    Params   : tIecParams;
    Ca       : Word;
    MaxAsdu  : Word;        {< ASDUs at most this long (249: IEC 104's; IecSlaveServeFiles: at most what its link takes) }
    SectionSize: LongInt;   {< octets per section sent (1024) }
    TimeoutMs: LongInt;     {< a transfer the peer leaves this long ends (30000) }
    MaxReceive: LongInt;    {< longest file taken (1 MiB) }
    Dir      : AnsiString;  {< directory served ('' none) }
    Files    : array[0..IecFileMaxFiles - 1] of tIecFileEntry;
    FileCount: LongInt;
    OnReceived: tIecFileReceivedFunc;
    OnDelete : tIecFileDeleteFunc;   {< asked before a file is deleted (nil: it is) }
    NoDelete : Boolean;     {< refuse every delete }
    Data     : Pointer;
    { the transfer under way }
    State    : tIecFileServerState;
    Ioa      : LongWord;
    Nof      : Word;
    Oa       : Byte;
    X        : tIecFileXfer;   {< the file sent, or what was received so far }
    Lof      : LongWord;    {< receiving: the length announced }
    Until_   : QWord;       {< the peer's next message before this }
    { what is to go out before anything else }
    Out      : array[0..IecMaxAsdu - 1] of Byte;
    OutLen   : Word;
    DirAt    : LongInt;     {< directory entries left to send from (-1: none) }
    DirCot   : Byte;
    DirLog   : Boolean;     {< the directory answers a query log: only these files }
    LogNof   : Word;
    LogFrom, LogTo: TDateTime;
    LogQuery : tIecFileObj; {< mirrored when no file is in the range }
    { counters and the last trouble }
    Sent, Received, Failed, Aborted, BadChecksums, Refused, Deleted: LongInt;
    LastError: ShortString;
  end;
  pIecFileServer = ^tIecFileServer;

{ A server for common address Ca under P, no files. }
procedure IecFileServerInit(var F: tIecFileServer; const P: tIecParams; Ca: Word);
{ Add (or replace) the program's file of IOA Ioa: res_BadParam (IOA too
  large, file too long), res_Busy (IecFileMaxFiles files). }
function IecFileServerAdd(var F: tIecFileServer; Ioa: LongWord; Nof: Word;
  const Content: AnsiString; const Time: tIecTime): tChResult;
{ A file ASDU from the controlling station (OA taken over in answers). }
procedure IecFileServerTake(var F: tIecFileServer; const Buf: array of Byte; Len: Word);
{ Something to send now (a transfer the peer left TimeoutMs ends here). }
function IecFileServerReady(var F: tIecFileServer): Boolean;
{ Something to send, without looking at the time. }
function IecFileServerBusy(const F: tIecFileServer): Boolean;
{ The next ASDU to send (False: none now). }
function IecFileServerNext(var F: tIecFileServer; var Buf: array of Byte; out Len: Word): Boolean;
function IecFileServerStateName(S: tIecFileServerState): ShortString;
{ A whole file into Content / Content into a file: False with Err
  (the path and the OS's reason). }
function IecFileLoad(const Path: AnsiString; out Content: AnsiString; out Err: ShortString): Boolean;
function IecFileSave(const Path: AnsiString; const Content: AnsiString; out Err: ShortString): Boolean;

implementation

uses
  SysUtils, Classes, ChnVirt, ChnOs;

function IecFileServerStateName(S: tIecFileServerState): ShortString;
begin
  WriteStr(Result, S);
  Delete(Result, 1, 2);
end;

procedure IecFileServerInit(var F: tIecFileServer; const P: tIecParams; Ca: Word);
begin
  Finalize(F);
  FillChar(F, SizeOf(F), 0);
  F.Params := P;
  F.Ca := Ca;
  F.MaxAsdu := 249;
  F.SectionSize := 1024;
  F.TimeoutMs := 30000;
  F.MaxReceive := 1024 * 1024;
  F.DirAt := -1;
end;

function IecFileServerAdd(var F: tIecFileServer; Ioa: LongWord; Nof: Word;
  const Content: AnsiString; const Time: tIecTime): tChResult;
var
  I: LongInt;
begin
  if (Ioa > IecMaxIoa(F.Params)) or (Length(Content) > IecFileMaxLen) then
    Exit(res_BadParam);
  I := 0;
  while (I < F.FileCount) and (F.Files[I].Ioa <> Ioa) do
    Inc(I);
  if I = IecFileMaxFiles then
    Exit(res_Busy);
  if I = F.FileCount then
    Inc(F.FileCount);
  F.Files[I].Ioa := Ioa;
  F.Files[I].Nof := Nof;
  F.Files[I].Time := Time;
  F.Files[I].Content := Content;
  Result := res_Ok;
end;

{- ------------------------------------------------------------ the files }

{ The IOA a directory entry's name gives ('30000', '30000.dat'); -1 else. }
function NameIoa(const Name: AnsiString): LongInt;
var
  P: LongInt;
  Digits: AnsiString;
begin
  P := Pos('.', Name);
  if P > 0 then
    Digits := Copy(Name, 1, P - 1)
  else
    Digits := Name;
  if (Digits = '') or (Length(Digits) > 8) then
    Exit(-1);
  for P := 1 to Length(Digits) do
    if not (Digits[P] in ['0'..'9']) then
      Exit(-1);
  Result := StrToInt(Digits);
end;

function IecFileLoad(const Path: AnsiString; out Content: AnsiString; out Err: ShortString): Boolean;
begin
  Result := OsFileLoad(Path, Content, Err);
end;

function IecFileSave(const Path: AnsiString; const Content: AnsiString; out Err: ShortString): Boolean;
begin
  Result := OsFileSave(Path, Content, Err);
end;

{ Every file there is: the program's, then the directory's (sorted by
  name) - through Visit, which stops the walk by returning True. }
type
  tVisit = function(var F: tIecFileServer; const E: tIecFileEntry; const Path: AnsiString;
    Size: Int64): Boolean;

function WalkFiles(var F: tIecFileServer; Visit: tVisit): Boolean;
var
  I, Ioa: LongInt;
  SR: TSearchRec;
  E: tIecFileEntry;
  Names: TStringList;
begin
  Result := False;
  for I := 0 to F.FileCount - 1 do
    if Visit(F, F.Files[I], '', Length(F.Files[I].Content)) then
      Exit(True);
  if F.Dir = '' then
    Exit;
  Names := TStringList.Create;
  try
    if FindFirst(IncludeTrailingPathDelimiter(F.Dir) + '*', faAnyFile, SR) = 0 then
    begin
      repeat
        if SR.Attr and faDirectory = 0 then
          Names.AddObject(SR.Name, TObject(PtrInt(SR.Size)));
      until FindNext(SR) <> 0;
      FindClose(SR);
    end;
    Names.Sort;
    for I := 0 to Names.Count - 1 do
    begin
      Ioa := NameIoa(Names[I]);
      if (Ioa < 0) or (LongWord(Ioa) > IecMaxIoa(F.Params)) then
        Continue;
      E.Ioa := Ioa;
      E.Nof := Nof_Transparent;
      E.Content := '';
      E.Time := IecTimeFromDateTime(FileDateToDateTime(FileAge(IncludeTrailingPathDelimiter(F.Dir) + Names[I])));
      if Visit(F, E, IncludeTrailingPathDelimiter(F.Dir) + Names[I], PtrInt(Names.Objects[I])) then
        Exit(True);
    end;
  finally
    Names.Free;
  end;
end;

var
  { the walk's argument and result (one thread serves every station) }
  Want: LongWord;
  Found: AnsiString;
  FoundNof: Word;

function VisitFind(var F: tIecFileServer; const E: tIecFileEntry; const Path: AnsiString;
  Size: Int64): Boolean;
var
  Err: ShortString;
begin
  Result := E.Ioa = Want;
  if not Result then
    Exit;
  FoundNof := E.Nof;
  if Path = '' then
    Found := E.Content
  else if not IecFileLoad(Path, Found, Err) then
  begin
    F.LastError := 'file: ' + Err;
    Result := False;
  end;
end;

function VisitLocate(var F: tIecFileServer; const E: tIecFileEntry; const Path: AnsiString;
  Size: Int64): Boolean;
begin
  Result := E.Ioa = Want;
  if Result then
    Found := Path;
end;

{ The content of the file of IOA Ioa. }
function FindFile(var F: tIecFileServer; Ioa: LongWord; out Content: AnsiString; out Nof: Word): Boolean;
begin
  Want := Ioa;
  Found := '';
  FoundNof := 0;
  Result := WalkFiles(F, @VisitFind);
  Content := Found;
  Nof := FoundNof;
  Found := '';
end;

{- ------------------------------------------------------------ answers }

function Obj(Ioa: LongWord; Nof: Word; Nos: Byte; Q: Byte): tIecFileObj;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Ioa := Ioa;
  Result.Nof := Nof;
  Result.Nos := Nos;
  Result.Q := Q;
end;

{ Queue one ASDU for Next (what was there is replaced: the peer talks in
  turns, one answer per message). }
procedure Answer(var F: tIecFileServer; Ti, Cot: Byte; Negative: Boolean; const O: tIecFileObj);
var
  A: array[0..0] of tIecFileObj;
  E: ShortString;
begin
  A[0] := O;
  if IecFileEncode(F.Params, Ti, Cot, Negative, F.Ca, A, 1, F.Out, F.OutLen, E) <> res_Ok then
  begin
    F.OutLen := 0;
    F.LastError := E;
  end
  else if F.Params.CotSize = 2 then
    F.Out[3] := F.Oa;
end;

{ The ASDU received, mirrored with P/N = 1 and Cot. }
procedure Mirror(var F: tIecFileServer; const Buf: array of Byte; Len: Word; Cot: Byte);
begin
  if (Len = 0) or (Len > SizeOf(F.Out)) then
    Exit;
  Move(Buf[0], F.Out[0], Len);
  F.OutLen := Len;
  IecSetCot(F.Out, Len, Cot, True);
  Inc(F.Refused);
end;

procedure Touch(var F: tIecFileServer);
begin
  F.Until_ := ChMsTick + QWord(F.TimeoutMs);
end;

procedure Stop(var F: tIecFileServer; const Why: ShortString);
begin
  F.State := fsIdle;
  F.X.Content := '';
  if Why <> '' then
    F.LastError := Why;
end;

function What(const F: tIecFileServer): ShortString;
begin
  Result := 'file IOA ' + IntToStr(F.Ioa);
end;

{ Section Nos of the file being sent ready: F_SR_NA_1; past the last
  one, the last section (F_LS_NA_1 LSQ 1, the file's checksum). }
procedure SectionReady(var F: tIecFileServer; Nos: Byte);
var
  O: tIecFileObj;
begin
  if not IecXferSection(F.X, Nos, F.SectionSize) then
  begin
    O := Obj(F.Ioa, F.Nof, Nos - 1, Lsq_File);
    O.Chs := IecFileSum(F.X.Content);
    Answer(F, F_LS_NA_1, Cot_File, False, O);
    F.State := fsFileAck;
  end
  else
  begin
    O := Obj(F.Ioa, F.Nof, Nos, 0);
    O.Lof := F.X.SecLen;
    Answer(F, F_SR_NA_1, Cot_File, False, O);
    F.State := fsSectionReady;
  end;
end;

procedure Select(var F: tIecFileServer; const O: tIecFileObj);
var
  R: tIecFileObj;
  C: AnsiString;
  Nof: Word;
begin
  if F.State <> fsIdle then
  begin
    Inc(F.Aborted);
    F.LastError := What(F) + ': left for a new select';
  end;
  Stop(F, '');
  F.Ioa := O.Ioa;
  F.Nof := O.Nof;
  R := Obj(O.Ioa, O.Nof, 0, 0);
  if not FindFile(F, O.Ioa, C, Nof) or (Length(C) > IecFileMaxLen) then
  begin
    R.Q := Frq_Negative;               { file not ready: there is none }
    Inc(F.Refused);
    F.LastError := 'select of file IOA ' + IntToStr(O.Ioa) + ': no such file';
    Answer(F, F_FR_NA_1, Cot_File, False, R);
    Exit;
  end;
  F.X.Content := C;
  if Nof <> 0 then
    F.Nof := Nof;
  R.Nof := F.Nof;
  R.Lof := Length(C);
  Answer(F, F_FR_NA_1, Cot_File, False, R);
  F.State := fsSelected;
  Touch(F);
end;

procedure Deliver(var F: tIecFileServer);
var
  E: ShortString;
begin
  Inc(F.Received);
  if Assigned(F.OnReceived) then
    F.OnReceived(F.Data, F.Ioa, F.Nof, F.X.Content);
  if (F.Dir <> '') and not IecFileSave(IncludeTrailingPathDelimiter(F.Dir) + IntToStr(F.Ioa), F.X.Content, E) then
    F.LastError := 'file IOA ' + IntToStr(F.Ioa) + ' received, not written: ' + E;
end;

{ The peer's file ready: take it (call file) or refuse it. }
procedure Offered(var F: tIecFileServer; const O: tIecFileObj);
var
  R: tIecFileObj;
begin
  if F.State <> fsIdle then
    Inc(F.Aborted);
  Stop(F, '');
  F.Ioa := O.Ioa;
  F.Nof := O.Nof;
  if ((F.Dir = '') and not Assigned(F.OnReceived)) or (O.Lof > LongWord(F.MaxReceive)) then
  begin
    R := Obj(O.Ioa, O.Nof, 0, Frq_Negative);
    R.Lof := O.Lof;
    Inc(F.Refused);
    F.LastError := What(F) + ' of ' + IntToStr(O.Lof) + ' octets offered: refused';
    Answer(F, F_FR_NA_1, Cot_File, False, R);
    Exit;
  end;
  F.Lof := O.Lof;
  Answer(F, F_SC_NA_1, Cot_File, False, Obj(F.Ioa, F.Nof, 0, Scq_CallFile));
  F.State := fsReceiveReady;
  Touch(F);
end;

{ A last section or segment from the peer while receiving. }
procedure LastReceived(var F: tIecFileServer; const O: tIecFileObj);
var
  Sum: Byte;
  Cause: Byte;
begin
  case O.Q of
    Lsq_Section:
      if F.State = fsReceiving then
      begin
        Sum := IecXferSectionSum(F.X);
        if Sum = O.Chs then
        begin
          Answer(F, F_AF_NA_1, Cot_File, False, Obj(F.Ioa, F.Nof, O.Nos, Afq_SectionOk));
        end
        else
        begin
          { the section goes: the peer sends it again }
          Inc(F.BadChecksums);
          F.LastError := What(F) + ' section ' + IntToStr(O.Nos) + ': checksum '
            + IntToStr(O.Chs) + ' received, ' + IntToStr(Sum) + ' computed';
          IecXferDrop(F.X);
          Answer(F, F_AF_NA_1, Cot_File, False,
            Obj(F.Ioa, F.Nof, O.Nos, Afq_SectionBad or (Fe_Checksum shl 4)));
        end;
        F.State := fsReceiveReady;
        Touch(F);
      end;
    Lsq_File:
      if F.State = fsReceiveReady then
      begin
        Cause := Fe_None;
        Sum := IecFileSum(F.X.Content);
        if O.Chs <> Sum then
        begin
          Cause := Fe_Checksum;
          Inc(F.BadChecksums);
          F.LastError := What(F) + ': file checksum ' + IntToStr(O.Chs) + ' received, '
            + IntToStr(Sum) + ' computed';
        end
        else if LongWord(Length(F.X.Content)) <> F.Lof then
        begin
          Cause := Fe_Unexpected;
          F.LastError := What(F) + ': ' + IntToStr(Length(F.X.Content)) + ' octets received, '
            + IntToStr(F.Lof) + ' announced';
        end;
        if Cause = Fe_None then
        begin
          Answer(F, F_AF_NA_1, Cot_File, False, Obj(F.Ioa, F.Nof, O.Nos, Afq_FileOk));
          Deliver(F);
        end
        else
        begin
          Inc(F.Failed);
          Answer(F, F_AF_NA_1, Cot_File, False, Obj(F.Ioa, F.Nof, O.Nos, Afq_FileBad or (Cause shl 4)));
        end;
        Stop(F, '');
      end;
    Lsq_FileDeact:
      begin
        Inc(F.Aborted);
        Stop(F, What(F) + ': transfer aborted by the peer');
      end;
    Lsq_SectionDeact:
      if F.State = fsReceiving then
      begin
        { the section goes; the peer offers it (or another) again }
        IecXferDrop(F.X);
        F.State := fsReceiveReady;
        Touch(F);
      end;
  end;
end;

procedure Acked(var F: tIecFileServer; const O: tIecFileObj);
begin
  case O.Q and $0F of
    Afq_SectionOk:
      if F.State = fsSectionAck then
      begin
          SectionReady(F, F.X.Nos + 1);
        Touch(F);
      end;
    Afq_SectionBad:
      if F.State = fsSectionAck then
      begin
        SectionReady(F, F.X.Nos);        { once more }
        Touch(F);
      end;
    Afq_FileOk:
      if F.State = fsFileAck then
      begin
        Inc(F.Sent);
        Stop(F, '');
      end;
    Afq_FileBad:
      if F.State <> fsIdle then
      begin
        Inc(F.Failed);
        Stop(F, What(F) + ': negative acknowledgement from the peer (' + IecFileErrorName(O.Q shr 4) + ')');
      end;
  end;
end;

{ Select section Nos of the file called: its section ready, or one with
  SRQ bit 7 when the file has no such section. }
procedure SelectSection(var F: tIecFileServer; Nos: Byte);
var
  O: tIecFileObj;
begin
  O := Obj(F.Ioa, F.Nof, Nos, 0);
  if (Nos >= 1) and IecXferSection(F.X, Nos, F.SectionSize) then
  begin
    O.Lof := F.X.SecLen;
    F.State := fsSectionReady;
  end
  else
  begin
    O.Q := Srq_NotReady;
    F.State := fsFileCalled;
    F.LastError := What(F) + ': no section ' + IntToStr(Nos);
  end;
  Answer(F, F_SR_NA_1, Cot_File, False, O);
  Touch(F);
end;

{ The index of the program's file of IOA Ioa in F.Files, -1: none. }
function ProgramFile(const F: tIecFileServer; Ioa: LongWord): LongInt;
begin
  Result := F.FileCount - 1;
  while (Result >= 0) and (F.Files[Result].Ioa <> Ioa) do
    Dec(Result);
end;

{ Delete file: the program's or the directory's, unless NoDelete or
  OnDelete says no; F_AF_NA_1 positive, or negative with the cause. }
procedure DeleteAsked(var F: tIecFileServer; const O: tIecFileObj);
var
  I: LongInt;
  Path: AnsiString;
  Why: ShortString;
  Cause: Byte;
begin
  Cause := Fe_Unexpected;
  Why := '';
  Path := '';
  I := ProgramFile(F, O.Ioa);
  if I < 0 then
  begin
    Want := O.Ioa;
    Found := '';
    if WalkFiles(F, @VisitLocate) then
      Path := Found;
    Found := '';
  end;
  if (I < 0) and (Path = '') then
  begin
    Cause := Fe_UnknownFile;
    Why := 'no such file';
  end
  else if F.NoDelete then
    Why := 'this station deletes no file'
  else if Assigned(F.OnDelete) and not F.OnDelete(F.Data, O.Ioa, O.Nof, Why) then
  begin
    if Why = '' then
      Why := 'refused by the program';
  end
  else if I >= 0 then
  begin
    F.Files[I] := F.Files[F.FileCount - 1];
    Finalize(F.Files[F.FileCount - 1]);
    Dec(F.FileCount);
    Cause := Fe_None;
  end
  else if not SysUtils.DeleteFile(Path) then
    Why := Path + ': ' + SysErrorMessage(GetLastOSError)
  else
    Cause := Fe_None;
  if (F.State in [fsSelected, fsSectionReady, fsSending, fsSectionAck, fsFileAck, fsFileCalled]) and
     (F.Ioa = O.Ioa) then
    Stop(F, '');                         { the file selected: its transfer is over }
  if Cause = Fe_None then
  begin
    Inc(F.Deleted);
    Answer(F, F_AF_NA_1, Cot_File, False, Obj(O.Ioa, O.Nof, 0, Afq_FileOk));
  end
  else
  begin
    Inc(F.Refused);
    F.LastError := 'delete of file IOA ' + IntToStr(O.Ioa) + ': ' + Why;
    Answer(F, F_AF_NA_1, Cot_File, False, Obj(O.Ioa, O.Nof, 0, Afq_FileBad or (Cause shl 4)));
  end;
end;

{ Query log: the directory of the files of NOF (0: any) created in the
  range, from DirNext. }
procedure QueryLog(var F: tIecFileServer; const O: tIecFileObj);
var
  RangeFrom, RangeTo: TDateTime;         { locals: F's may lie unaligned (packed, ARM) }
begin
  F.DirLog := True;
  F.LogNof := O.Nof;
  F.LogQuery := O;
  if not IecTimeToDateTime(O.Time, RangeFrom) or not IecTimeToDateTime(O.Stop, RangeTo) then
  begin
    F.LastError := 'query log: the range is no date';
    RangeFrom := 1;                      { an empty range }
    RangeTo := 0;
  end;
  F.LogFrom := RangeFrom;
  F.LogTo := RangeTo;
  F.DirAt := 0;
  F.DirCot := Cot_Request;
  F.OutLen := 0;
end;

procedure Called(var F: tIecFileServer; const Buf: array of Byte; Len: Word; const O: tIecFileObj);
begin
  case O.Q and $0F of
    Scq_SelectFile: Select(F, O);
    Scq_DeleteFile: DeleteAsked(F, O);
    Scq_SelectSection:
      if (F.State in [fsSectionReady, fsSending, fsSectionAck, fsFileCalled]) and (O.Ioa = F.Ioa) then
        SelectSection(F, O.Nos)
      else
        Mirror(F, Buf, Len, Cot_File);
    Scq_DeactSection:
      if (F.State in [fsSectionReady, fsSending, fsSectionAck]) and (O.Ioa = F.Ioa) then
      begin
        F.State := fsFileCalled;         { the section stops, the file stays called }
        Touch(F);
      end;
    Scq_CallFile:
      if (F.State in [fsSelected, fsFileCalled]) and (O.Ioa = F.Ioa) then
      begin
        SectionReady(F, 1);
        Touch(F);
      end
      else
        Mirror(F, Buf, Len, Cot_File);
    Scq_CallSection:
      if (F.State = fsSectionReady) and (O.Ioa = F.Ioa) and (O.Nos = F.X.Nos) then
      begin
        F.State := fsSending;
        Touch(F);
      end
      else
        Mirror(F, Buf, Len, Cot_File);
    Scq_DeactFile:
      if F.State <> fsIdle then
      begin
        Inc(F.Aborted);
        Stop(F, What(F) + ': transfer deactivated by the peer');
      end;
  else
    Mirror(F, Buf, Len, Cot_File);      { SCQ 0, 8..15 with COT 13 }
  end;
end;

procedure Segment(var F: tIecFileServer; const O: tIecFileObj);
begin
  if (F.State <> fsReceiving) or (O.Ioa <> F.Ioa) or (O.Nos <> F.X.Nos) then
    Exit;
  if IecXferTake(F.X, O) then
    Touch(F)
  else                                   { dropped: the checksum will fail }
    F.LastError := What(F) + ' section ' + IntToStr(O.Nos) + ': longer than announced';
end;

procedure IecFileServerTake(var F: tIecFileServer; const Buf: array of Byte; Len: Word);
var
  H: tIecAsdu;
  O: tIecFileObj;
  E: ShortString;
begin
  if IecFileDecode(F.Params, Buf, Len, 0, H, O, E) <> res_Ok then
  begin
    F.LastError := E;
    if (Len >= 3) and IecIsFileType(Buf[0]) then
      Mirror(F, Buf, Len, Cot_UnknownType);
    Exit;
  end;
  F.Oa := H.Oa;
  if H.Ca <> F.Ca then
  begin
    Mirror(F, Buf, Len, Cot_UnknownCa);
    Exit;
  end;
  if (H.Ti = F_SC_NA_1) and (H.Cot = Cot_Request) then
  begin
    F.DirAt := 0;                        { the directory }
    F.DirCot := Cot_Request;
    F.DirLog := False;
    F.OutLen := 0;
    Exit;
  end;
  if H.Ti = F_SC_NB_1 then
  begin
    if H.Cot = Cot_Request then
      QueryLog(F, O)
    else
      Mirror(F, Buf, Len, Cot_UnknownCause);
    Exit;
  end;
  if H.Cot <> Cot_File then
  begin
    Mirror(F, Buf, Len, Cot_UnknownCause);
    Exit;
  end;
  case H.Ti of
    F_SC_NA_1: Called(F, Buf, Len, O);
    F_AF_NA_1: if O.Ioa = F.Ioa then Acked(F, O);
    F_FR_NA_1: Offered(F, O);
    F_SR_NA_1:
      if (F.State = fsReceiveReady) and (O.Ioa = F.Ioa) then
      begin
        IecXferExpect(F.X, O.Nos, O.Lof);
        Answer(F, F_SC_NA_1, Cot_File, False, Obj(F.Ioa, F.Nof, O.Nos, Scq_CallSection));
        F.State := fsReceiving;
        Touch(F);
      end;
    F_SG_NA_1: Segment(F, O);
    F_LS_NA_1: if O.Ioa = F.Ioa then LastReceived(F, O);
  else
    Mirror(F, Buf, Len, Cot_UnknownType);   { F_DR_TA_1: not in this direction }
  end;
end;

{- ------------------------------------------------------------ sending }

var
  DirSkip: LongInt;                      { walk: entries to pass over }
  DirObjs: array[0..IecMaxObjects - 1] of tIecFileObj;
  DirCount, DirRoom: LongInt;

{ A query log's: of its NOF, created in its range. }
function InLog(const F: tIecFileServer; const E: tIecFileEntry): Boolean;
var
  T: TDateTime;
begin
  Result := ((F.LogNof = 0) or (E.Nof = F.LogNof)) and IecTimeToDateTime(E.Time, T) and
    (T >= F.LogFrom) and (T <= F.LogTo);
end;

function VisitDir(var F: tIecFileServer; const E: tIecFileEntry; const Path: AnsiString;
  Size: Int64): Boolean;
begin
  if F.DirLog and not InLog(F, E) then
    Exit(False);
  if DirSkip > 0 then
  begin
    Dec(DirSkip);
    Exit(False);
  end;
  if DirCount = DirRoom then
    Exit(True);                          { this one goes in the next ASDU }
  FillChar(DirObjs[DirCount], SizeOf(DirObjs[DirCount]), 0);
  DirObjs[DirCount].Ioa := E.Ioa;
  DirObjs[DirCount].Nof := E.Nof;
  if (Size < 0) or (Size > IecFileMaxLen) then
    Size := IecFileMaxLen;
  DirObjs[DirCount].Lof := Size;
  DirObjs[DirCount].Time := E.Time;
  Inc(DirCount);
  Result := False;
end;

{ The next ASDU of the directory, from entry F.DirAt. }
function DirNext(var F: tIecFileServer; var Buf: array of Byte; out Len: Word): Boolean;
var
  More: Boolean;
  E: ShortString;
  O: tIecFileObj;
begin
  DirSkip := F.DirAt;
  DirCount := 0;
  DirRoom := (F.MaxAsdu - IecHeadLen(F.Params)) div (F.Params.IoaSize + IecFileElemLen(F_DR_TA_1));
  More := WalkFiles(F, @VisitDir);
  Result := True;
  if DirCount = 0 then
  begin
    { no file: the call (the query) mirrored, negative }
    F.DirAt := -1;
    if F.DirLog then
      Result := IecFileEncode(F.Params, F_SC_NB_1, F.DirCot, True, F.Ca, [F.LogQuery], 1, Buf, Len, E) = res_Ok
    else
    begin
      O := Obj(0, 0, 0, Scq_Default);
      Result := IecFileEncode(F.Params, F_SC_NA_1, F.DirCot, True, F.Ca, [O], 1, Buf, Len, E) = res_Ok;
    end;
    Exit;
  end;
  if More then
    Inc(F.DirAt, DirCount)
  else
  begin
    DirObjs[DirCount - 1].Q := DirObjs[DirCount - 1].Q or Sof_LastFile;
    F.DirAt := -1;
  end;
  Result := IecFileEncode(F.Params, F_DR_TA_1, F.DirCot, False, F.Ca, DirObjs, DirCount, Buf, Len, E) = res_Ok;
  if not Result then
    F.LastError := 'directory: ' + E;
end;

procedure CheckTimeout(var F: tIecFileServer);
begin
  if (F.State <> fsIdle) and (ChMsTick > F.Until_) then
  begin
    Inc(F.Aborted);
    Stop(F, What(F) + ': abandoned, no message from the peer in ' + IntToStr(F.TimeoutMs) + ' ms ('
      + IecFileServerStateName(F.State) + ')');
  end;
end;

function IecFileServerBusy(const F: tIecFileServer): Boolean;
begin
  Result := (F.OutLen > 0) or (F.DirAt >= 0) or (F.State = fsSending);
end;

function IecFileServerReady(var F: tIecFileServer): Boolean;
begin
  CheckTimeout(F);
  Result := IecFileServerBusy(F);
end;

function IecFileServerNext(var F: tIecFileServer; var Buf: array of Byte; out Len: Word): Boolean;
var
  O: tIecFileObj;
  E: ShortString;
begin
  Len := 0;
  Result := IecFileServerReady(F);
  if not Result then
    Exit;
  if F.OutLen > 0 then
  begin
    Len := F.OutLen;
    Move(F.Out[0], Buf[0], Len);
    F.OutLen := 0;
    Exit;
  end;
  if F.DirAt >= 0 then
    Exit(DirNext(F, Buf, Len));
  { fsSending: the next segment, or the section's last }
  O := Obj(F.Ioa, F.Nof, F.X.Nos, 0);
  if IecXferSegment(F.X, IecFileMaxSegment(F.Params, F.MaxAsdu), O) then
    Result := IecFileEncode(F.Params, F_SG_NA_1, Cot_File, False, F.Ca, [O], 1, Buf, Len, E) = res_Ok
  else
  begin
    O.Q := Lsq_Section;                  { O.Chs: the section's }
    Result := IecFileEncode(F.Params, F_LS_NA_1, Cot_File, False, F.Ca, [O], 1, Buf, Len, E) = res_Ok;
    F.State := fsSectionAck;
  end;
  if not Result then
    Stop(F, What(F) + ': ' + E)
  else if F.Params.CotSize = 2 then
    Buf[3] := F.Oa;
  Touch(F);
end;

end.
