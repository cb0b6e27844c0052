{ ChnIecFileClient - file transfer of an IEC 60870-5-101/104 controlling
  station (IEC 60870-5-101 clause 7.4.11): the directory of a slave, a
  file fetched from it, a file sent to it; over any ChnIec101Master
  (unbalanced or balanced FT 1.2, IEC 104). It sends through the master
  (IecStartAsdu, one ASDU at a time) and takes the master's file ASDUs
  (OnFileAsdu): one transfer at a time, stepped from the program's poll
  loop like the master's commands, with blocking forms.

  Fetching (IecFileStartGet):
    -> F_SC_NA_1 SCQ 1 select     <- F_FR_NA_1 file ready (LOF)
    -> F_SC_NA_1 SCQ 2 call file  <- F_SR_NA_1 section ready
    -> F_SC_NA_1 SCQ 6 call section  <- F_SG_NA_1 ... F_LS_NA_1 LSQ 3 CHS
    -> F_AF_NA_1 AFQ 3 (CHS = the sum of the section's octets modulo 256),
       or AFQ 4 + cause 2: the slave sends the section again (once;
       SectionRetries), then the next section ready ...
                                  <- F_LS_NA_1 LSQ 1 CHS of the file
    -> F_AF_NA_1 AFQ 1 (file checksum and LOF right) or AFQ 2 + cause.
  Sending (IecFileStartPut): F_FR_NA_1 offered, the slave calls the file
  and each section (F_SC_NA_1 SCQ 2, 6), segments and F_LS_NA_1 LSQ 3
  go, F_AF_NA_1 AFQ 3 / 4 (4: the section again), F_LS_NA_1 LSQ 1, AFQ 1.
  Directory (IecFileStartDir): F_SC_NA_1 with COT 5, F_DR_TA_1 entries
  until the one with SOF bit LFD; a negative answer is an empty one.
  Query log (IecFileStartQueryLog): F_SC_NB_1 with COT 5 (NOF, range
  start, range stop), answered as the directory: the files created then.
  One section (IecFileStartGetSection): select, call file; the first
  section ready answered by F_SC_NA_1 SCQ 5 select section (unless it is
  the one), call section, the segments, F_AF_NA_1 AFQ 3; what the slave
  offers next is answered by F_SC_NA_1 SCQ 3, deactivate file.
  Deleting (IecFileStartDelete): -> F_SC_NA_1 SCQ 1 select <- F_FR_NA_1,
  -> F_SC_NA_1 SCQ 4 delete file <- F_AF_NA_1 AFQ 1 (deleted) or AFQ 2 +
  the cause (refused).
  Giving up (no answer in time, a checksum still wrong, an answer out of
  sequence, IecFileAbort) the client tells the slave, so that it is free
  for the next transfer at once: fetching, F_SC_NA_1 SCQ 3 deactivate file
  (a bad checksum: F_AF_NA_1 AFQ 2 + cause 2); sending, F_LS_NA_1 LSQ 2
  (file transfer with deactivation).

  Results: res_Ok; res_IecFileRefused (the slave has no such file, refuses
  the one offered, or answers negatively / with COT 44..47);
  res_IecFileChecksum (a checksum still wrong after the repeat, or the
  file's); res_IecFileAborted (the slave ended the transfer: LSQ 2/4,
  AFQ 2); res_IecFileSequence (an answer that does not fit the step);
  res_Timeout (interrupted: no answer in TimeoutMs, or the link failed);
  res_IecFileAborted also when the program aborted (IecFileAbort);
  res_IecBusy (a transfer under way). Err names the file, the step and,
  for an interruption, how far it got. }
unit ChnIecFileClient;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIec101Asdu, ChnIec101Master, ChnIecFile;

const
  res_IecFileRefused  = res_Proto + 20;   {< no such file, or refused by the slave }
  res_IecFileChecksum = res_Proto + 21;   {< checksum of a section or the file wrong }
  res_IecFileAborted  = res_Proto + 22;   {< the slave ended the transfer }
  res_IecFileSequence = res_Proto + 23;   {< an answer out of sequence }

  IecFileMaxDir = 256;

type
  tIecFileDirEntry = record
    Ioa : LongWord;
    Nof : Word;
    Lof : LongWord;
    Sof : Byte;
    Time: tIecTime;
  end;

  tIecFileJob = (fjNone, fjDir, fjGet, fjPut, fjDelete);
  tIecFileWait = (fwNone,
    fwFileReady,       {< get: select sent }
    fwSectionReady,    {< get: call file or section ack sent }
    fwSegments,        {< get: call section sent }
    fwCallFile,        {< put: file ready sent }
    fwCallSection,     {< put: section ready sent }
    fwSending,         {< put: segments and the last segment going out }
    fwSectionAck,      {< put: last segment sent }
    fwFileAck,         {< put: last section sent }
    fwDirectory,       {< directory called (or query log sent) }
    fwDeleted,         {< delete: delete file sent }
    fwDone);

  tIecFileClient = record
    M        : pIecMaster;
    Addr, Ca : Word;
    MaxAsdu  : Word;        {< ASDUs at most this long (249 on IEC 104, 247 on FT 1.2) }
    SectionSize: LongInt;   {< put: octets per section (1024) }
    TimeoutMs: LongInt;     {< each answer within (10000) }
    SectionRetries: LongInt;   {< a section with a bad checksum asked again this often (1) }
    Job      : tIecFileJob;
    Wait     : tIecFileWait;
    Ioa      : LongWord;
    Nof      : Word;
    X        : tIecFileXfer;   {< get: what arrived; put: what goes }
    Lof      : LongWord;
    Repeats  : LongInt;     {< of the section under way }
    OnlyNos  : Byte;        {< get: this section alone (0: the file) }
    Selected : Boolean;     {< get: the select section went }
    Dir      : array[0..IecFileMaxDir - 1] of tIecFileDirEntry;
    DirCount : LongInt;
    { the ASDU waiting for the master's command slot, and one under way }
    Pend     : array[0..IecMaxAsdu - 1] of Byte;
    PendLen  : Word;
    Sending  : Boolean;
    Deadline : QWord;
    Result   : tChResult;
    Err      : ShortString;
    BadChecksums: LongInt;  {< sections or files whose checksum was wrong }
  end;
  pIecFileClient = ^tIecFileClient;

{ A client on master M (it takes M's OnFileAsdu); C must not move. }
procedure IecFileClientInit(var C: tIecFileClient; var M: tIecMaster);
{ Stepped: False when refused (C.Result, C.Err). }
function IecFileStartDir(var C: tIecFileClient; Addr, Ca: Word): Boolean;
function IecFileStartGet(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): Boolean;
function IecFileStartPut(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const Content: AnsiString): Boolean;
{ Query log: the files of kind Nof (0: any) created from RangeStart to
  RangeStop (both included), in C.Dir as for the directory; Ioa goes in
  the query. }
function IecFileStartQueryLog(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const RangeStart, RangeStop: tIecTime): Boolean;
function IecFileStartDelete(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): Boolean;
{ Section Nos (1..255) of the file alone, into C.X.Content. }
function IecFileStartGetSection(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  Nos: Byte): Boolean;
{ The program gives up the transfer under way: res_IecFileAborted, and the
  slave is told (deactivate file / last section with deactivation). }
procedure IecFileAbort(var C: tIecFileClient);
{ One step of the master and the transfer; True when something was done. }
function IecFileStep(var C: tIecFileClient): Boolean;
function IecFileDone(const C: tIecFileClient): Boolean;
{ Step to the end (the master's Idle or ChnWaitAny between steps). }
function IecFileFinish(var C: tIecFileClient): tChResult;
{ Blocking forms. }
function IecFileDir(var C: tIecFileClient; Addr, Ca: Word): tChResult;
function IecFileGet(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  out Content: AnsiString): tChResult;
function IecFilePut(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const Content: AnsiString): tChResult;
function IecFileQueryLog(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const RangeStart, RangeStop: tIecTime): tChResult;
function IecFileDelete(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): tChResult;
function IecFileGetSection(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  Nos: Byte; out Content: AnsiString): tChResult;

implementation

uses
  SysUtils, ChnVirt, ChnFT12Codec;

procedure OnAsdu(Data: Pointer; Addr: Word; const Buf: array of Byte; Len: Word); forward;

procedure IecFileClientInit(var C: tIecFileClient; var M: tIecMaster);
begin
  Finalize(C);
  FillChar(C, SizeOf(C), 0);
  C.M := @M;
  { the longest ASDU of the transport: IEC 104's APDU, FT 1.2's record }
  if M.Over104 then
    C.MaxAsdu := 249
  else
    C.MaxAsdu := MaxDataLen;
  C.SectionSize := 1024;
  C.TimeoutMs := 10000;
  C.SectionRetries := 1;
  M.OnFileAsdu := @OnAsdu;
  M.FileData := @C;
end;

function IecFileDone(const C: tIecFileClient): Boolean;
begin
  { done once its last word (an acknowledgement) went too }
  Result := (C.Wait in [fwNone, fwDone]) and (C.PendLen = 0) and not C.Sending;
end;

function What(const C: tIecFileClient): ShortString;
begin
  case C.Job of
    fjDir: Result := 'directory of slave ' + IntToStr(C.Addr);
    fjGet: Result := 'file IOA ' + IntToStr(C.Ioa) + ' from slave ' + IntToStr(C.Addr);
    fjDelete: Result := 'delete of file IOA ' + IntToStr(C.Ioa) + ' on slave ' + IntToStr(C.Addr);
  else
    Result := 'file IOA ' + IntToStr(C.Ioa) + ' to slave ' + IntToStr(C.Addr);
  end;
end;

function WaitName(W: tIecFileWait): ShortString;
begin
  case W of
    fwFileReady: Result := 'file ready (F_FR_NA_1)';
    fwSectionReady: Result := 'section ready (F_SR_NA_1)';
    fwSegments: Result := 'segments (F_SG_NA_1)';
    fwCallFile: Result := 'call file (F_SC_NA_1)';
    fwCallSection: Result := 'call section (F_SC_NA_1)';
    fwSending: Result := 'the link';
    fwSectionAck, fwFileAck: Result := 'acknowledgement (F_AF_NA_1)';
    fwDirectory: Result := 'directory (F_DR_TA_1)';
    fwDeleted: Result := 'acknowledgement of the delete (F_AF_NA_1)';
  else
    Result := 'nothing';
  end;
end;

procedure Finish(var C: tIecFileClient; R: tChResult; const Text: ShortString);
begin
  C.Wait := fwDone;
  C.Result := R;
  if R = res_Ok then
    C.Err := ''
  else
    C.Err := What(C) + ': ' + Text;
end;

procedure Send(var C: tIecFileClient; Ti, Cot: Byte; const O: tIecFileObj); forward;
function Obj(const C: tIecFileClient; Nos, Q: Byte): tIecFileObj; forward;
function Progress(const C: tIecFileClient): ShortString; forward;

{ Given up (Finish with R): the slave told, so that it frees the transfer
  now rather than after its own timeout - a fetch deactivated (SCQ 3), a
  file being sent ended with deactivation (LSQ 2). }
procedure GiveUp(var C: tIecFileClient; R: tChResult; const Text: ShortString);
begin
  Finish(C, R, Text);
  case C.Job of
    fjGet: Send(C, F_SC_NA_1, Cot_File, Obj(C, 0, Scq_DeactFile));
    fjPut: Send(C, F_LS_NA_1, Cot_File, Obj(C, C.X.Nos, Lsq_FileDeact));
  end;
end;

procedure Expect(var C: tIecFileClient; W: tIecFileWait);
begin
  C.Wait := W;
  C.Deadline := ChMsTick + QWord(C.TimeoutMs);
end;

{ Queue one ASDU for the master. }
procedure Send(var C: tIecFileClient; Ti, Cot: Byte; const O: tIecFileObj);
var
  E: ShortString;
  R: tChResult;
begin
  R := IecFileEncode(C.M^.Params, Ti, Cot, False, C.Ca, [O], 1, C.Pend, C.PendLen, E);
  if R <> res_Ok then
    Finish(C, R, E);
end;

function Obj(const C: tIecFileClient; Nos, Q: Byte): tIecFileObj;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Ioa := C.Ioa;
  Result.Nof := C.Nof;
  Result.Nos := Nos;
  Result.Q := Q;
end;

function Start(var C: tIecFileClient; Job: tIecFileJob; Addr, Ca: Word; Ioa: LongWord; Nof: Word): Boolean;
begin
  Result := IecFileDone(C);
  if not Result then
  begin
    C.Err := 'a transfer is under way (' + What(C) + ')';
    Exit;
  end;
  C.Job := Job;
  C.Addr := Addr;
  C.Ca := Ca;
  C.Ioa := Ioa;
  C.Nof := Nof;
  C.X.Content := '';
  C.X.Nos := 0;
  C.X.SecStart := 0;
  C.X.SecLen := 0;
  C.X.SecDone := 0;
  C.DirCount := 0;
  C.Repeats := 0;
  C.OnlyNos := 0;
  C.Selected := False;
  C.Sending := False;
  C.Result := res_Ok;
  C.Err := '';
  if IecMasterSlave(C.M^, Addr) < 0 then
  begin
    Finish(C, res_IecNoSlave, 'no slave with link address ' + IntToStr(Addr));
    Exit(False);
  end;
end;

function IecFileStartDir(var C: tIecFileClient; Addr, Ca: Word): Boolean;
begin
  Result := Start(C, fjDir, Addr, Ca, 0, 0);
  if not Result then
    Exit;
  Send(C, F_SC_NA_1, Cot_Request, Obj(C, 0, Scq_Default));
  Expect(C, fwDirectory);
end;

{ A job that starts with the select of the file: get, delete. }
function StartSelect(var C: tIecFileClient; Job: tIecFileJob; Addr, Ca: Word; Ioa: LongWord;
  Nof: Word): Boolean;
begin
  Result := Start(C, Job, Addr, Ca, Ioa, Nof);
  if not Result then
    Exit;
  Send(C, F_SC_NA_1, Cot_File, Obj(C, 0, Scq_SelectFile));
  Expect(C, fwFileReady);
  Result := not IecFileDone(C);
end;

function IecFileStartGet(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): Boolean;
begin
  Result := StartSelect(C, fjGet, Addr, Ca, Ioa, Nof);
end;

function IecFileStartPut(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const Content: AnsiString): Boolean;
var
  O: tIecFileObj;
begin
  Result := Start(C, fjPut, Addr, Ca, Ioa, Nof);
  if not Result then
    Exit;
  if (Length(Content) > $FFFFFF) or (C.SectionSize < 1) or
     (Length(Content) > 255 * C.SectionSize) then
  begin
    Finish(C, res_BadParam, IntToStr(Length(Content)) + ' octets do not fit 255 sections of '
      + IntToStr(C.SectionSize) + ' octets');
    Exit(False);
  end;
  C.X.Content := Content;
  C.Lof := Length(Content);
  O := Obj(C, 0, 0);
  O.Lof := C.Lof;
  Send(C, F_FR_NA_1, Cot_File, O);
  Expect(C, fwCallFile);
  Result := not IecFileDone(C);
end;

function IecFileStartQueryLog(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const RangeStart, RangeStop: tIecTime): Boolean;
var
  O: tIecFileObj;
begin
  Result := Start(C, fjDir, Addr, Ca, Ioa, Nof);
  if not Result then
    Exit;
  O := Obj(C, 0, 0);
  O.Time := RangeStart;
  O.Stop := RangeStop;
  Send(C, F_SC_NB_1, Cot_Request, O);
  Expect(C, fwDirectory);
  Result := not IecFileDone(C);
end;

function IecFileStartGetSection(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  Nos: Byte): Boolean;
begin
  if Nos = 0 then
  begin
    C.Result := res_BadParam;
    C.Err := 'file IOA ' + IntToStr(Ioa) + ': no section 0 (sections are 1..255)';
    Exit(False);
  end;
  Result := IecFileStartGet(C, Addr, Ca, Ioa, Nof);
  C.OnlyNos := Nos;
end;

function IecFileStartDelete(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): Boolean;
begin
  Result := StartSelect(C, fjDelete, Addr, Ca, Ioa, Nof);
end;

procedure IecFileAbort(var C: tIecFileClient);
begin
  if not (C.Wait in [fwNone, fwDone]) then
    GiveUp(C, res_IecFileAborted, 'aborted by the program' + Progress(C));
end;

{- ------------------------------------------------------------ put }

{ Offer section Nos of the file (F_SR_NA_1), or after the last the last
  section (F_LS_NA_1 LSQ 1, the file's checksum). }
procedure PutSection(var C: tIecFileClient; Nos: Byte);
var
  O: tIecFileObj;
begin
  if not IecXferSection(C.X, Nos, C.SectionSize) then
  begin
    O := Obj(C, Nos - 1, Lsq_File);
    O.Chs := IecFileSum(C.X.Content);
    Send(C, F_LS_NA_1, Cot_File, O);
    Expect(C, fwFileAck);
  end
  else
  begin
    O := Obj(C, Nos, 0);
    O.Lof := C.X.SecLen;
    Send(C, F_SR_NA_1, Cot_File, O);
    Expect(C, fwCallSection);
  end;
end;

{ The next segment of the section, or its last segment. }
procedure PutNext(var C: tIecFileClient);
var
  O: tIecFileObj;
begin
  O := Obj(C, C.X.Nos, 0);
  if IecXferSegment(C.X, IecFileMaxSegment(C.M^.Params, C.MaxAsdu), O) then
  begin
    Send(C, F_SG_NA_1, Cot_File, O);
    Expect(C, fwSending);
  end
  else
  begin
    O.Q := Lsq_Section;                  { O.Chs: the section's }
    Send(C, F_LS_NA_1, Cot_File, O);
    Expect(C, fwSectionAck);
  end;
end;

{- ------------------------------------------------------------ answers }

procedure Unexpected(var C: tIecFileClient; const H: tIecAsdu; const O: tIecFileObj);
begin
  GiveUp(C, res_IecFileSequence, IecFileTypeName(H.Ti) + ' (qualifier ' + IntToStr(O.Q)
    + ') while waiting for ' + WaitName(C.Wait));
end;

{ A segment or the last segment/section while fetching. }
procedure GetSegments(var C: tIecFileClient; const H: tIecAsdu; const O: tIecFileObj);
var
  Sum: Byte;
begin
  if (H.Ti = F_SG_NA_1) and (C.Wait = fwSegments) and (O.Nos = C.X.Nos) then
  begin
    if IecXferTake(C.X, O) then
      Expect(C, fwSegments)
    else
      GiveUp(C, res_IecFileSequence, 'section ' + IntToStr(C.X.Nos) + ' longer than its '
        + IntToStr(C.X.SecLen) + ' octets');
    Exit;
  end;
  if (H.Ti <> F_LS_NA_1) then
  begin
    Unexpected(C, H, O);
    Exit;
  end;
  case O.Q of
    Lsq_Section:
      if C.Wait <> fwSegments then
        Unexpected(C, H, O)
      else
      begin
        Sum := IecXferSectionSum(C.X);
        if (Sum = O.Chs) and IecXferSectionWhole(C.X) then
        begin
          Send(C, F_AF_NA_1, Cot_File, Obj(C, C.X.Nos, Afq_SectionOk));
          Expect(C, fwSectionReady);
          C.Repeats := 0;
        end
        else
        begin
          Inc(C.BadChecksums);
          IecXferDrop(C.X);
          if C.Repeats < C.SectionRetries then
          begin
            Inc(C.Repeats);
            Send(C, F_AF_NA_1, Cot_File, Obj(C, C.X.Nos, Afq_SectionBad or (Fe_Checksum shl 4)));
            Expect(C, fwSectionReady);
          end
          else
          begin
            Finish(C, res_IecFileChecksum, 'section ' + IntToStr(C.X.Nos) + ': checksum '
              + IntToStr(O.Chs) + ' received, ' + IntToStr(Sum) + ' computed over '
              + IntToStr(C.X.SecDone) + ' of ' + IntToStr(C.X.SecLen) + ' octets (asked '
              + IntToStr(C.Repeats + 1) + ' times)');
            Send(C, F_AF_NA_1, Cot_File, Obj(C, C.X.Nos, Afq_FileBad or (Fe_Checksum shl 4)));
          end;
        end;
      end;
    Lsq_File:
      if C.Wait <> fwSectionReady then
        Unexpected(C, H, O)
      else
      begin
        Sum := IecFileSum(C.X.Content);
        if (Sum = O.Chs) and (LongWord(Length(C.X.Content)) = C.Lof) then
        begin
          Send(C, F_AF_NA_1, Cot_File, Obj(C, O.Nos, Afq_FileOk));
          Finish(C, res_Ok, '');
        end
        else
        begin
          Inc(C.BadChecksums);
          Finish(C, res_IecFileChecksum, 'file checksum ' + IntToStr(O.Chs) + ' received, '
            + IntToStr(Sum) + ' computed; ' + IntToStr(Length(C.X.Content)) + ' octets of '
            + IntToStr(C.Lof) + ' announced');
          Send(C, F_AF_NA_1, Cot_File, Obj(C, O.Nos, Afq_FileBad or (Fe_Checksum shl 4)));
        end;
      end;
    Lsq_FileDeact, Lsq_SectionDeact:
      Finish(C, res_IecFileAborted, 'the slave ended the transfer (F_LS_NA_1 LSQ ' + IntToStr(O.Q)
        + ') after ' + IntToStr(Length(C.X.Content)) + ' of ' + IntToStr(C.Lof) + ' octets');
  else
    Unexpected(C, H, O);
  end;
end;

procedure TakeGet(var C: tIecFileClient; const H: tIecAsdu; const O: tIecFileObj);
begin
  case C.Wait of
    fwFileReady:
      if H.Ti <> F_FR_NA_1 then
        Unexpected(C, H, O)
      else if O.Q and Frq_Negative <> 0 then
        Finish(C, res_IecFileRefused, 'the slave has no such file (F_FR_NA_1 negative)')
      else
      begin
        C.Lof := O.Lof;
        Send(C, F_SC_NA_1, Cot_File, Obj(C, 0, Scq_CallFile));
        Expect(C, fwSectionReady);
      end;
    fwSectionReady:
      if (C.OnlyNos <> 0) and (C.X.Nos = C.OnlyNos) and IecXferSectionWhole(C.X) then
      begin
        { the section came: whatever the slave offers next is not wanted }
        Finish(C, res_Ok, '');
        Send(C, F_SC_NA_1, Cot_File, Obj(C, 0, Scq_DeactFile));
      end
      else if H.Ti = F_SR_NA_1 then
      begin
        if O.Q and Srq_NotReady <> 0 then
        begin
          GiveUp(C, res_IecFileRefused, 'section ' + IntToStr(O.Nos) + ' not ready');
          Exit;
        end;
        if (C.OnlyNos <> 0) and (O.Nos <> C.OnlyNos) then
        begin
          if C.Selected then
            Unexpected(C, H, O)
          else
          begin
            C.Selected := True;
            Send(C, F_SC_NA_1, Cot_File, Obj(C, C.OnlyNos, Scq_SelectSection));
            Expect(C, fwSectionReady);
          end;
          Exit;
        end;
        IecXferExpect(C.X, O.Nos, O.Lof);
        Send(C, F_SC_NA_1, Cot_File, Obj(C, O.Nos, Scq_CallSection));
        Expect(C, fwSegments);
      end
      else
        GetSegments(C, H, O);
    fwSegments: GetSegments(C, H, O);
  else
    Unexpected(C, H, O);
  end;
end;

procedure TakePut(var C: tIecFileClient; const H: tIecAsdu; const O: tIecFileObj);
begin
  case C.Wait of
    fwCallFile:
      if (H.Ti = F_SC_NA_1) and (O.Q and $0F = Scq_CallFile) then
        PutSection(C, 1)
      else if (H.Ti = F_FR_NA_1) and (O.Q and Frq_Negative <> 0) then
        Finish(C, res_IecFileRefused, 'the slave refuses the file (F_FR_NA_1 negative)')
      else
        Unexpected(C, H, O);
    fwCallSection:
      if (H.Ti = F_SC_NA_1) and (O.Q and $0F = Scq_CallSection) and (O.Nos = C.X.Nos) then
        PutNext(C)
      else
        Unexpected(C, H, O);
    fwSectionAck, fwFileAck:
      if H.Ti <> F_AF_NA_1 then
        Unexpected(C, H, O)
      else
        case O.Q and $0F of
          Afq_SectionOk:
            if C.Wait = fwSectionAck then
            begin
              C.Repeats := 0;
              PutSection(C, C.X.Nos + 1);
            end
            else
              Unexpected(C, H, O);
          Afq_SectionBad:
            if (C.Wait = fwSectionAck) and (C.Repeats < C.SectionRetries) then
            begin
              Inc(C.Repeats);
              Inc(C.BadChecksums);
              PutSection(C, C.X.Nos);
            end
            else
              GiveUp(C, res_IecFileChecksum, 'section ' + IntToStr(C.X.Nos) + ' refused by the slave ('
                + IecFileErrorName(O.Q shr 4) + ')');
          Afq_FileOk:
            if C.Wait = fwFileAck then
              Finish(C, res_Ok, '')
            else
              Unexpected(C, H, O);
          Afq_FileBad:
            if O.Q shr 4 = Fe_Checksum then
              Finish(C, res_IecFileChecksum, 'the slave refused the file: ' + IecFileErrorName(O.Q shr 4))
            else
              Finish(C, res_IecFileAborted, 'the slave refused the file: ' + IecFileErrorName(O.Q shr 4));
        else
          Unexpected(C, H, O);
        end;
  else
    Unexpected(C, H, O);
  end;
end;

procedure TakeDelete(var C: tIecFileClient; const H: tIecAsdu; const O: tIecFileObj);
begin
  if (C.Wait = fwFileReady) and (H.Ti = F_FR_NA_1) then
  begin
    if O.Q and Frq_Negative <> 0 then
      Finish(C, res_IecFileRefused, 'the slave has no such file (F_FR_NA_1 negative)')
    else
    begin
      Send(C, F_SC_NA_1, Cot_File, Obj(C, 0, Scq_DeleteFile));
      Expect(C, fwDeleted);
    end;
  end
  else if (C.Wait = fwDeleted) and (H.Ti = F_AF_NA_1) and (O.Q and $0F = Afq_FileOk) then
    Finish(C, res_Ok, '')
  else if (C.Wait = fwDeleted) and (H.Ti = F_AF_NA_1) and (O.Q and $0F = Afq_FileBad) then
    Finish(C, res_IecFileRefused, 'the slave did not delete it (F_AF_NA_1 negative: '
      + IecFileErrorName(O.Q shr 4) + ')')
  else
    Unexpected(C, H, O);
end;

procedure TakeDir(var C: tIecFileClient; const Buf: array of Byte; Len: Word; const H: tIecAsdu;
  const First: tIecFileObj);
var
  I: LongInt;
  O: tIecFileObj;
  H2: tIecAsdu;
  E: ShortString;
  Last: Boolean;
begin
  if H.Ti <> F_DR_TA_1 then
  begin
    Unexpected(C, H, First);
    Exit;
  end;
  Last := False;
  for I := 0 to H.Count - 1 do
    if (IecFileDecode(C.M^.Params, Buf, Len, I, H2, O, E) = res_Ok) and (C.DirCount < IecFileMaxDir) then
    begin
      C.Dir[C.DirCount].Ioa := O.Ioa;
      C.Dir[C.DirCount].Nof := O.Nof;
      C.Dir[C.DirCount].Lof := O.Lof;
      C.Dir[C.DirCount].Sof := O.Q;
      C.Dir[C.DirCount].Time := O.Time;
      Inc(C.DirCount);
      Last := O.Q and Sof_LastFile <> 0;
    end;
  if Last then
    Finish(C, res_Ok, '')
  else
    Expect(C, fwDirectory);
end;

{ A file ASDU the master received from slave Addr. }
procedure OnAsdu(Data: Pointer; Addr: Word; const Buf: array of Byte; Len: Word);
var
  C: pIecFileClient;
  H: tIecAsdu;
  O: tIecFileObj;
  E: ShortString;
begin
  C := pIecFileClient(Data);
  if (C^.Wait in [fwNone, fwDone]) or (Addr <> C^.Addr) then
    Exit;                                { no transfer with this slave }
  if IecFileDecode(C^.M^.Params, Buf, Len, 0, H, O, E) <> res_Ok then
  begin
    GiveUp(C^, res_IecFileSequence, 'malformed answer: ' + E);
    Exit;
  end;
  if (H.Ca <> C^.Ca) or ((C^.Job <> fjDir) and (O.Ioa <> C^.Ioa)) then
    Exit;                                { another transfer's }
  if (C^.Job = fjDir) and (H.Ti in [F_SC_NA_1, F_SC_NB_1]) and H.Negative and (H.Cot = Cot_Request) then
    Finish(C^, res_Ok, '')               { no file there (in the range) }
  else if H.Negative or (H.Cot >= Cot_UnknownType) then
    Finish(C^, res_IecFileRefused, 'the slave answered ' + IecFileTypeName(H.Ti) + ' with COT '
      + IntToStr(H.Cot) + ' ' + IecCotName(H.Cot) + BoolToStr(H.Negative, ', negative', ''))
  else
    case C^.Job of
      fjDir: TakeDir(C^, Buf, Len, H, O);
      fjGet: TakeGet(C^, H, O);
      fjPut: TakePut(C^, H, O);
      fjDelete: TakeDelete(C^, H, O);
    end;
end;

function Progress(const C: tIecFileClient): ShortString;
begin
  case C.Job of
    fjGet: Result := ' (' + IntToStr(Length(C.X.Content)) + ' of ' + IntToStr(C.Lof) + ' octets received)';
    fjPut: Result := ' (' + IntToStr(C.X.SecStart + C.X.SecDone) + ' of ' + IntToStr(C.Lof) + ' octets sent)';
  else
    Result := ' (' + IntToStr(C.DirCount) + ' entries received)';
  end;
end;

function IecFileStep(var C: tIecFileClient): Boolean;
var
  M: pIecMaster;
begin
  M := C.M;
  Result := IecMasterStep(M^);
  if C.Sending and IecCommandDone(M^) then
  begin
    { the ASDU under way went, or the link gave up }
    C.Sending := False;
    Result := True;
    if M^.Cmd.Result <> res_Ok then
    begin
      C.PendLen := 0;
      if not (C.Wait in [fwNone, fwDone]) then
        Finish(C, res_Timeout, 'interrupted: ' + M^.Cmd.Err + Progress(C));
    end
    else if C.Wait = fwSending then
      PutNext(C)                         { the next segment once this one went }
    else
      C.Deadline := ChMsTick + QWord(C.TimeoutMs);   { the answer's time runs from here }
  end;
  if (C.PendLen > 0) and not C.Sending and IecCommandDone(M^) then
  begin
    if IecStartAsdu(M^, C.Addr, C.Pend, C.PendLen) then
      C.Sending := True
    else if not (C.Wait in [fwNone, fwDone]) then
      Finish(C, M^.Cmd.Result, M^.Cmd.Err);
    C.PendLen := 0;
    Result := True;
  end;
  if not (C.Wait in [fwNone, fwDone, fwSending]) and not C.Sending and (ChMsTick > C.Deadline) then
  begin
    GiveUp(C, res_Timeout, 'interrupted: no ' + WaitName(C.Wait) + ' in ' + IntToStr(C.TimeoutMs)
      + ' ms' + Progress(C) + IecLineShowed(M^, IecMasterSlave(M^, C.Addr)));
    Result := True;
  end;
end;

function IecFileFinish(var C: tIecFileClient): tChResult;
begin
  while not IecFileDone(C) do
    if not IecFileStep(C) then
      IecMasterWait(C.M^, C.Deadline + 1);
  Result := C.Result;
end;

{ The blocking forms: the transfer stepped to its end once it started. }
function Ended(var C: tIecFileClient; Started: Boolean): tChResult;
begin
  if Started then
    Result := IecFileFinish(C)
  else
    Result := C.Result;
end;

{ What a fetch got: the file (the section), '' unless it succeeded. }
function Fetched(const C: tIecFileClient; R: tChResult; out Content: AnsiString): tChResult;
begin
  if R = res_Ok then
    Content := C.X.Content
  else
    Content := '';
  Result := R;
end;

function IecFileDir(var C: tIecFileClient; Addr, Ca: Word): tChResult;
begin
  Result := Ended(C, IecFileStartDir(C, Addr, Ca));
end;

function IecFileQueryLog(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const RangeStart, RangeStop: tIecTime): tChResult;
begin
  Result := Ended(C, IecFileStartQueryLog(C, Addr, Ca, Ioa, Nof, RangeStart, RangeStop));
end;

function IecFileDelete(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word): tChResult;
begin
  Result := Ended(C, IecFileStartDelete(C, Addr, Ca, Ioa, Nof));
end;

function IecFileGetSection(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  Nos: Byte; out Content: AnsiString): tChResult;
begin
  Result := Fetched(C, Ended(C, IecFileStartGetSection(C, Addr, Ca, Ioa, Nof, Nos)), Content);
end;

function IecFileGet(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  out Content: AnsiString): tChResult;
begin
  Result := Fetched(C, Ended(C, IecFileStartGet(C, Addr, Ca, Ioa, Nof)), Content);
end;

function IecFilePut(var C: tIecFileClient; Addr, Ca: Word; Ioa: LongWord; Nof: Word;
  const Content: AnsiString): tChResult;
begin
  Result := Ended(C, IecFileStartPut(C, Addr, Ca, Ioa, Nof, Content));
end;

initialization
  ChRegisterResultText(Iec101Layer, res_IecFileRefused, 'file refused or unknown');
  ChRegisterResultText(Iec101Layer, res_IecFileChecksum, 'file checksum failed');
  ChRegisterResultText(Iec101Layer, res_IecFileAborted, 'file transfer aborted by the peer');
  ChRegisterResultText(Iec101Layer, res_IecFileSequence, 'file transfer out of sequence');
end.
