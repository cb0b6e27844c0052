{ ChnPcccTags - a tag engine for one SLC 500 / MicroLogix (or df1sim) on
  one DF1 line: a list of tags in Kepware's notation ('N7:0[10]' an array
  of ten, 'F8:2', 'B3:0/5', 'T4:1.ACC', 'ST9:0', 'L10:0[4]'), each in a
  scan class (ms), polled with as few PCCC reads as possible, stepped from
  the program's ChnWaitAny (no thread, no sleep).

  Reads. The tags of one data file and one scan class that lie close
  together (gaps of at most MaxGap bytes) are read by one protected typed
  logical read (CMD 0F FNC A2) of whole elements, as long as it stays
  within MaxRead bytes (at most 244, what one DF1 frame carries; fewer
  make more reads with shorter replies: a change waits up to one scan for
  its read, then for that read's reply on the line); each tag is decoded
  from its block's bytes by unit ChnPccc. TagDeviceReads tells how many
  requests one scan of every tag takes: 100 tags scattered over N7:0..99
  are one read.

  State per tag: the value (Values, or Text for ST), its quality (good;
  bad: the device did not answer; refused: the PLC answered the read with
  an error status, e.g. the file does not exist; initial: not read yet)
  and the UTC time of the read that gave it. Changes only: a tag is
  queued for TagTakeChange when its quality changed or a value moved by
  more than Deadband (analog tags: integers and floats; bits and strings
  change on any difference) since it was last taken.

  Health. A device that failed DemoteAfter requests in a row (no ACK, no
  reply, NAK, line lost) is demoted: its tags go bad and only one read is
  tried every DemoteMs until one is answered, so a dead PLC on a shared
  line costs one timeout per DemoteMs instead of one per block and scan.
  After the first failure the device is down (tags bad) and keeps its
  rate. Counters: requests, errors, retries (link tries after the first,
  and the reads tried while demoted) and the last error's text.

  Writes. TagDeviceWrite queues a value for a tag marked writable (one
  integer, bit or float); it goes out before the next read, and its
  outcome comes back through TagTakeWrite with the caller's Id (for a
  command that must be confirmed only when the PLC confirmed); the tag's
  block is read again at once. }
unit ChnPcccTags;

{$I chn.inc}

interface

uses
  ChnTypes, ChnRing, ChnVirt, ChnDF1Codec, ChnDF1Link, ChnPccc, ChnPlc5, ChnPcccClient;

const
  TagMaxReadDefault     = MaxDataLen;   {< data bytes of one read: a whole DF1 frame }
  TagMaxGapDefault      = 32;      {< bytes read in vain rather than a request more }
  TagDemoteAfterDefault = 3;
  TagDemoteMsDefault    = 10000;
  TagScanMsDefault      = 1000;

type
  tTagQuality = (tqInitial, tqGood, tqBad, tqRefused);
  tTagDeviceState = (tdOk, tdDown, tdDemoted);

  tPcccTag = record
    {- AnsiStrings, not ShortStrings: four of 256 bytes were most of a
      gateway's memory (800 tags: 0.8 MB) }
    Name    : AnsiString;    {< the name it is published under (default: Address) }
    Address : AnsiString;    {< as parsed, canonical: 'N7:0[10]', 'T4:1.ACC' }
    Addr    : tPcccAddr;
    Count   : LongInt;       {< items: 1, or the [n] of an array }
    Plan    : tPcccPlan;     {< a read of the tag alone: how its bytes decode }
    Kind    : tPcccValueKind;
    ScanMs  : LongInt;
    Deadband: Double;
    Writable: Boolean;
    Block   : LongInt;       {< the block that reads it }
    First   : LongInt;       {< its first element in the data file }
    Values  : array of Double;   {< PcccPlanValues of Plan (ints and floats) }
    Text    : AnsiString;        {< an ST tag's value }
    Quality : tTagQuality;
    Known   : Boolean;       {< Values hold what a good read gave (else nothing yet) }
    TimeMs  : Int64;         {< UTC ms since 1970 of the read that gave them }
    Sent    : array of Double;   {< the values last taken by TagTakeChange }
    SentText: AnsiString;
    SentQuality: tTagQuality;
    Queued  : Boolean;       {< in the change queue }
  end;

  tPcccBlock = record
    FileType: Byte;
    FileNo  : Word;
    First   : LongInt;       {< first element read }
    Elems   : LongInt;
    ScanMs  : LongInt;
    Due     : QWord;         {< ChMsTick when its next read is due }
  end;

  tTagWrite = record
    Tag  : LongInt;
    Value: Double;
    Id   : LongInt;
    Res  : tChResult;
    Err  : ShortString;
  end;

  tTagBusy = (tbIdle, tbRead, tbWrite);

  pPcccDevice = ^tPcccDevice;
  tPcccDevice = record
    Name       : ShortString;
    Client     : tPcccClient;
    Plc5       : Boolean;    {< a PLC-5 (TagDevicePlc5) }
    Tags       : array of tPcccTag;
    Blocks     : array of tPcccBlock;
    MaxGap     : LongInt;
    MaxRead    : LongInt;    {< data bytes one read merges tags into, 2..TagMaxReadDefault }
    DemoteAfter: LongInt;
    DemoteMs   : LongInt;
    State      : tTagDeviceState;
    StateChanged: Boolean;   {< health to report (TagTakeHealth) }
    Fails      : LongInt;    {< failed requests in a row }
    RetryAt    : QWord;      {< demoted: when the next read is tried }
    Requests   : LongInt;
    Errors     : LongInt;
    Retries    : LongInt;
    LastError  : ShortString;
    { the request under way }
    Busy       : tTagBusy;
    Cur        : LongInt;    {< block read, or write (index in Writes) }
    Expect     : Word;
    Master     : tDF1Master;
    WriteReq   : tPcccRequest;
    Writes     : array of tTagWrite;   {< waiting, Writes[0] under way }
    Done       : array of tTagWrite;   {< finished, for TagTakeWrite }
    Changes    : tIndexQueue;          {< tags queued, oldest first }
  end;

const
  TagQualityNames: array[tTagQuality] of string[7] = ('initial', 'good', 'bad', 'refused');
  TagStateNames: array[tTagDeviceState] of string[7] = ('ok', 'down', 'demoted');

{ Parse a tag in Kepware's notation: a data table address (unit ChnPccc)
  and optionally [n], an array of n items (1..PcccMaxItems). res_Ok, or
  res_PcccAddress / res_PcccCount with Err naming what is wrong. }
function TagParse(const S: ShortString; out Addr: tPcccAddr; out Count: LongInt;
  out Err: ShortString): tChResult;

{ An empty device (no line yet). }
procedure TagDeviceInit(var D: tPcccDevice; const Name: ShortString);
{ The device is a PLC-5: its tags take PLC-5 addresses (unit ChnPlc5:
  'I:012/05', 'D10:0' read as 0..9999), blocks are read by word range
  (0F 01), writes go as the client's PLC-5 commands. Call after the line
  is opened (PcccOpen sets the client up anew) and before TagAdd. }
procedure TagDevicePlc5(var D: tPcccDevice);
{ Add a tag; res_Ok, or the parse result with Err. A tag whose bytes do
  not fit in one request (more than 244), or an array of strings, is
  refused (res_PcccCount). Call before TagDeviceStart. }
function TagAdd(var D: tPcccDevice; const Name, Address: ShortString; ScanMs: LongInt;
  Deadband: Double; Writable: Boolean; out Err: ShortString): tChResult;
{ Index of the tag named Name (or addressed so); -1 when none. }
function TagFind(const D: tPcccDevice; const Name: ShortString): LongInt;
{ Merge the tags into blocks; the first reads are due at once. The line:
  an open DF1 stack (D.Client by PcccClientInit) or one opened by
  PcccOpen into D.Client; TagDeviceStart only plans. }
procedure TagDeviceStart(var D: tPcccDevice);
{ Requests one scan of every tag takes (the number of blocks). }
function TagDeviceReads(const D: tPcccDevice): LongInt;
{ Disconnect (when D.Client owns its line) and free everything. }
procedure TagDeviceDone(var D: tPcccDevice);

{ Take what the line has for the request under way and start the next
  one that is due; never waits. True when something happened that the
  caller may want to take (a change, health, a finished write). }
function TagDeviceStep(var D: tPcccDevice): Boolean;
{ The same with the ChMsTick the caller read (one clock read for many
  devices stepped in a row). }
function TagDeviceStepAt(var D: tPcccDevice; Now_: QWord): Boolean;
{ Milliseconds until the device needs TagDeviceStep again with no input
  (a reply timer, the next read due); the program's ChnWaitAny waits at
  most the smallest of these. }
function TagDeviceWaitMs(const D: tPcccDevice): LongInt;
{ The same as the ChMsTick at which it is due (0: now; High(QWord):
  never): a program stepping many devices takes the earliest and reads
  the clock once. }
function TagDeviceDueAt(const D: tPcccDevice): QWord;

{ The next changed tag (its index); False when none. The tag's Sent
  values become its current ones. }
function TagTakeChange(var D: tPcccDevice; out Tag: LongInt): Boolean;
{ True once after the device's state changed. }
function TagTakeHealth(var D: tPcccDevice): Boolean;

{ Queue a write of Value to tag Tag; False (Err says why: not writable,
  an array, not a whole number for an integer tag, not 0/1 for a bit)
  when it is refused at once. Id comes back with the outcome. }
function TagDeviceWrite(var D: tPcccDevice; Tag: LongInt; Value: Double; Id: LongInt;
  out Err: ShortString): Boolean;
{ A finished write: its Id, res_Ok when the PLC confirmed it, else the
  failure and its text. False when none finished. }
function TagTakeWrite(var D: tPcccDevice; out W: tTagWrite): Boolean;

{ True for tags whose values are analog (the deadband applies): integer
  and float words that are not bits. }
function TagIsAnalog(const T: tPcccTag): Boolean;
{ True for a tag of bits (0/1 values). }
function TagIsBit(const T: tPcccTag): Boolean;
{ UTC milliseconds since 1970, now. }
function TagUtcMs: Int64;

implementation

uses
  SysUtils, ChnWait;

function TagUtcMs: Int64;
begin
  Result := ChUtcMs;
end;

function TagParseAs(Dialect: tPcccDialect; const S: ShortString; out Addr: tPcccAddr;
  out Count: LongInt; out Err: ShortString): tChResult; forward;

function TagParse(const S: ShortString; out Addr: tPcccAddr; out Count: LongInt;
  out Err: ShortString): tChResult;
begin
  Result := TagParseAs(pdSlc, S, Addr, Count, Err);
end;

function TagParseAs(Dialect: tPcccDialect; const S: ShortString; out Addr: tPcccAddr;
  out Count: LongInt; out Err: ShortString): tChResult;
var
  Base, N: ShortString;
  Open, Code: LongInt;
begin
  Count := 1;
  Err := '';
  Base := Trim(S);
  Open := Pos('[', Base);
  if Open > 0 then
  begin
    if Base[Length(Base)] <> ']' then
    begin
      Err := '"' + S + '": an array is ADDRESS[n]';
      FillChar(Addr, SizeOf(Addr), 0);
      Exit(res_PcccAddress);
    end;
    N := Copy(Base, Open + 1, Length(Base) - Open - 1);
    Val(N, Count, Code);
    if (Code <> 0) or (Count < 1) or (Count > PcccMaxItems) then
    begin
      Err := '"' + S + '": the array size "' + N + '" is not 1..' + IntToStr(PcccMaxItems);
      FillChar(Addr, SizeOf(Addr), 0);
      Exit(res_PcccCount);
    end;
    Base := Copy(Base, 1, Open - 1);
  end;
  Result := PcccParseAddressAs(Dialect, Base, Addr, Err);
  if Result <> res_Ok then
    Err := '"' + S + '": ' + Err;
end;

procedure TagDeviceInit(var D: tPcccDevice; const Name: ShortString);
begin
  Finalize(D);
  FillChar(D, SizeOf(D), 0);
  D.Name := Name;
  PcccClientInit(D.Client, nil);
  D.MaxGap := TagMaxGapDefault;
  D.MaxRead := TagMaxReadDefault;
  D.DemoteAfter := TagDemoteAfterDefault;
  D.DemoteMs := TagDemoteMsDefault;
  D.Cur := -1;
end;

procedure TagDevicePlc5(var D: tPcccDevice);
begin
  D.Plc5 := True;
  PcccClientPlc5(D.Client, p5WordRange);
end;

function Dialect(const D: tPcccDevice): tPcccDialect;
begin
  if D.Plc5 then
    Result := pdPlc5
  else
    Result := pdSlc;
end;

function TagIsBit(const T: tPcccTag): Boolean;
begin
  Result := T.Addr.Bit >= 0;
end;

function TagIsAnalog(const T: tPcccTag): Boolean;
begin
  Result := (T.Kind <> pvString) and not TagIsBit(T);
end;

{ Last element of the data file a tag covers. }
function TagLast(const T: tPcccTag): LongInt;
begin
  if T.Plan.Mode = pmBits then
    Result := T.Addr.Elem + T.Plan.Units - 1
  else
    Result := T.Addr.Elem + T.Count - 1;
end;

function TagAdd(var D: tPcccDevice; const Name, Address: ShortString; ScanMs: LongInt;
  Deadband: Double; Writable: Boolean; out Err: ShortString): tChResult;
var
  T: tPcccTag;
  N, Bytes: LongInt;
begin
  Result := TagParseAs(Dialect(D), Address, T.Addr, T.Count, Err);
  if Result <> res_Ok then
    Exit;
  Result := PcccPlan(T.Addr, T.Count, False, MaxDataLen, T.Plan, Err);
  if Result <> res_Ok then
  begin
    Err := '"' + Address + '": ' + Err;
    Exit;
  end;
  T.Kind := PcccValueKind(T.Addr);
  T.First := T.Addr.Elem;
  Bytes := (TagLast(T) - T.First + 1) * PcccElemSize(T.Addr.FileType);
  if (T.Kind = pvString) and (T.Count <> 1) then
  begin
    Err := '"' + Address + '": strings are tags of one element';
    Exit(res_PcccCount);
  end;
  if Bytes > MaxDataLen then
  begin
    Err := Format('"%s": %d bytes, more than one read carries (%d); split it',
      [Address, Bytes, MaxDataLen]);
    Exit(res_PcccCount);
  end;
  if Writable and ((T.Kind = pvString) or (PcccPlanValues(T.Plan) <> 1)) then
  begin
    Err := '"' + Address + '": only a tag of one integer, bit or float can be written';
    Exit(res_PcccUsage);
  end;
  T.Address := PcccAddressTextAs(Dialect(D), T.Addr);
  if T.Count > 1 then
    T.Address := T.Address + '[' + IntToStr(T.Count) + ']';
  if Name = '' then
    T.Name := T.Address
  else
    T.Name := Name;
  if ScanMs <= 0 then
    ScanMs := TagScanMsDefault;
  T.ScanMs := ScanMs;
  T.Deadband := Deadband;
  T.Writable := Writable;
  T.Block := -1;
  N := PcccPlanValues(T.Plan);
  T.Values := nil;
  T.Sent := nil;
  SetLength(T.Values, N);
  SetLength(T.Sent, N);
  T.Text := '';
  T.SentText := '';
  T.Quality := tqInitial;
  T.Known := False;
  T.SentQuality := tqInitial;
  T.TimeMs := 0;
  T.Queued := False;
  SetLength(D.Tags, Length(D.Tags) + 1);
  D.Tags[High(D.Tags)] := T;
  Result := res_Ok;
end;

function TagFind(const D: tPcccDevice; const Name: ShortString): LongInt;
begin
  for Result := 0 to High(D.Tags) do
    if (D.Tags[Result].Name = Name) or SameText(D.Tags[Result].Address, Name) then
      Exit;
  Result := -1;
end;

{- ------------------------------------------------------------ merging }

{ Tag A before B: by file, scan class, first element. }
function Before(const A, B: tPcccTag): Boolean;
begin
  if A.Addr.FileType <> B.Addr.FileType then
    Exit(A.Addr.FileType < B.Addr.FileType);
  if A.Addr.FileNo <> B.Addr.FileNo then
    Exit(A.Addr.FileNo < B.Addr.FileNo);
  if A.ScanMs <> B.ScanMs then
    Exit(A.ScanMs < B.ScanMs);
  Result := A.First < B.First;
end;

procedure TagDeviceStart(var D: tPcccDevice);
var
  Order: array of LongInt;
  I, J, K, Size, Last: LongInt;
  Now_: QWord;
  B: ^tPcccBlock;
  T: ^tPcccTag;
begin
  { the tags in file/scan/element order (insertion sort: a device has
    hundreds of tags at most, and they come mostly in order) }
  SetLength(Order, Length(D.Tags));
  for I := 0 to High(Order) do
  begin
    J := I;
    while (J > 0) and Before(D.Tags[I], D.Tags[Order[J - 1]]) do
    begin
      Order[J] := Order[J - 1];
      Dec(J);
    end;
    Order[J] := I;
  end;
  D.Blocks := nil;
  Now_ := ChMsTick;
  B := nil;
  for K := 0 to High(Order) do
  begin
    T := @D.Tags[Order[K]];
    Size := PcccElemSize(T^.Addr.FileType);
    Last := TagLast(T^);
    if (B <> nil) and (B^.FileType = T^.Addr.FileType) and (B^.FileNo = T^.Addr.FileNo) and
       (B^.ScanMs = T^.ScanMs) and
       ((T^.First - (B^.First + B^.Elems)) * Size <= D.MaxGap) and
       ((Last - B^.First + 1) * Size <= D.MaxRead) then
    begin
      if Last - B^.First + 1 > B^.Elems then
        B^.Elems := Last - B^.First + 1;
    end
    else
    begin
      SetLength(D.Blocks, Length(D.Blocks) + 1);
      B := @D.Blocks[High(D.Blocks)];
      B^.FileType := T^.Addr.FileType;
      B^.FileNo := T^.Addr.FileNo;
      B^.First := T^.First;
      B^.Elems := Last - T^.First + 1;
      B^.ScanMs := T^.ScanMs;
      B^.Due := Now_;
    end;
    T^.Block := High(D.Blocks);
  end;
end;

function TagDeviceReads(const D: tPcccDevice): LongInt;
begin
  Result := Length(D.Blocks);
end;

procedure TagDeviceDone(var D: tPcccDevice);
begin
  if D.Busy = tbRead then
    DF1MasterCancel(D.Master)
  else if D.Busy = tbWrite then
    PcccCancel(D.WriteReq);
  D.Busy := tbIdle;
  PcccClose(D.Client);
  D.Tags := nil;
  D.Blocks := nil;
  D.Writes := nil;
  D.Done := nil;
  IndexQueueClear(D.Changes);
  D.WriteReq.Ints := nil;
  D.WriteReq.Floats := nil;
end;

{- ------------------------------------------------------------ values }

procedure QueueChange(var D: tPcccDevice; Tag: LongInt);
begin
  if D.Tags[Tag].Queued then
    Exit;
  D.Tags[Tag].Queued := True;
  IndexQueuePut(D.Changes, Tag);
end;

{ Tag I has new values or quality: queue it when that is a change. }
procedure Noticed(var D: tPcccDevice; I: LongInt);
var
  T: ^tPcccTag;
  K: LongInt;
  Moved: Boolean;
begin
  T := @D.Tags[I];
  Moved := T^.Quality <> T^.SentQuality;
  if not Moved and (T^.Quality = tqGood) then
    if T^.Kind = pvString then
      Moved := T^.Text <> T^.SentText
    else
      for K := 0 to High(T^.Values) do
        if (TagIsAnalog(T^) and (Abs(T^.Values[K] - T^.Sent[K]) > T^.Deadband)) or
           (not TagIsAnalog(T^) and (T^.Values[K] <> T^.Sent[K])) then
        begin
          Moved := True;
          Break;
        end;
  if Moved then
    QueueChange(D, I);
end;

{ Decode tag T from the data of its block (Data[0] is element B.First). }
function Decode(var T: tPcccTag; const B: tPcccBlock; const Data: array of Byte): tChResult;
var
  S: ShortString;
  Ints: array of LongInt;
  Floats: array of Single;
  Off, Len, J, Size: LongInt;
begin
  Size := PcccElemSize(T.Addr.FileType);
  Off := (T.First - B.First) * Size;
  if T.Kind = pvString then
  begin
    Result := PcccDecodeString(Data, Off, S);
    T.Text := S;
    Exit;
  end;
  Ints := nil;
  Floats := nil;
  Result := res_Ok;
  if T.Kind = pvFloat then
  begin
    SetLength(Floats, Length(T.Values));
    Len := T.Plan.Units * T.Plan.UnitBytes;
    Result := PcccDecodePlanFloats(T.Plan, 0, Data[Off..Off + Len - 1], Len, Floats);
    for J := 0 to High(Floats) do
      T.Values[J] := Floats[J];
    Exit;
  end;
  SetLength(Ints, Length(T.Values));
  if T.Plan.Mode = pmSubs then
    { one word (or bit) of each element: request J of the tag's own plan }
    for J := 0 to T.Count - 1 do
    begin
      Len := Off + J * Size + T.Addr.Sub * 2;
      Result := PcccDecodePlanInts(T.Plan, J, Data[Len..Len + 1], 2, Ints);
      if Result <> res_Ok then
        Break;
    end
  else
  begin
    Len := T.Plan.Units * T.Plan.UnitBytes;
    { PLC-5 D words are BCD: Plc5DecodePlanInts gives 0..9999 }
    Result := Plc5DecodePlanInts(T.Plan, 0, Data[Off..Off + Len - 1], Len, Ints);
  end;
  for J := 0 to High(Ints) do
    T.Values[J] := Ints[J];
end;

{ Every tag of block Blk (-1: all) gets quality Q at time Ms. }
procedure Mark(var D: tPcccDevice; Blk: LongInt; Q: tTagQuality; Ms: Int64);
var
  I: LongInt;
begin
  for I := 0 to High(D.Tags) do
    if (Blk < 0) or (D.Tags[I].Block = Blk) then
    begin
      D.Tags[I].Quality := Q;
      D.Tags[I].TimeMs := Ms;
      Noticed(D, I);
    end;
end;

procedure SetState(var D: tPcccDevice; S: tTagDeviceState);
begin
  if D.State <> S then
  begin
    D.State := S;
    D.StateChanged := True;
  end;
end;

{- ------------------------------------------------------------ stepping }

{ The device answered. }
procedure Answered(var D: tPcccDevice);
begin
  D.Fails := 0;
  SetState(D, tdOk);
end;

{ A request was not answered (Why): down, demoted after DemoteAfter in a row. }
procedure Failed(var D: tPcccDevice; const Why: ShortString);
begin
  Inc(D.Errors);
  D.LastError := Why;
  Inc(D.Fails);
  if D.Fails >= D.DemoteAfter then
  begin
    SetState(D, tdDemoted);
    D.RetryAt := ChMsTick + QWord(D.DemoteMs);
  end
  else
    SetState(D, tdDown);
  Mark(D, -1, tqBad, TagUtcMs);
end;

procedure ReadDone(var D: tPcccDevice);
var
  B: ^tPcccBlock;
  Res: tChResult;
  E: ShortString;
  I: LongInt;
  Ms: Int64;
begin
  B := @D.Blocks[D.Cur];
  D.Busy := tbIdle;
  Inc(D.Requests);
  if D.Master.Tries > 1 then
    Inc(D.Retries, D.Master.Tries - 1);
  B^.Due := B^.Due + QWord(B^.ScanMs);
  if B^.Due < ChMsTick then
    B^.Due := ChMsTick;
  E := '';
  if D.Master.Result <> res_Ok then
  begin
    Failed(D, PcccFileLetter(B^.FileType) + IntToStr(B^.FileNo) + ':' + IntToStr(B^.First) +
      ': ' + PcccMasterFailure(D.Master, D.Client.Chn));
    Exit;
  end;
  Answered(D);
  Ms := TagUtcMs;
  Res := PcccCheckReply(D.Master.Rep, D.Master.RepLen, D.Expect, E);
  if Res <> res_Ok then
  begin
    { the PLC answered: the device is fine, these addresses are not }
    Inc(D.Errors);
    D.LastError := Format('%s%d:%d[%d]: %s', [PcccFileLetter(B^.FileType), B^.FileNo, B^.First,
      B^.Elems, E]);
    Mark(D, D.Cur, tqRefused, Ms);
    Exit;
  end;
  for I := 0 to High(D.Tags) do
    if D.Tags[I].Block = D.Cur then
    begin
      if Decode(D.Tags[I], B^, D.Master.Rep.Data) = res_Ok then
      begin
        D.Tags[I].Quality := tqGood;
        D.Tags[I].Known := True;
      end
      else
        D.Tags[I].Quality := tqRefused;
      D.Tags[I].TimeMs := Ms;
      Noticed(D, I);
    end;
end;

procedure WriteDone(var D: tPcccDevice);
var
  W: tTagWrite;
  I: LongInt;
begin
  D.Busy := tbIdle;
  Inc(D.Requests);
  W := D.Writes[0];
  for I := 1 to High(D.Writes) do
    D.Writes[I - 1] := D.Writes[I];
  SetLength(D.Writes, Length(D.Writes) - 1);
  W.Res := D.WriteReq.Result;
  W.Err := D.WriteReq.Err;
  if W.Res = res_Ok then
    Answered(D)
  else if W.Res in [res_PcccStatus, res_PcccReply, res_PcccValue] then
  begin
    Inc(D.Errors);
    D.LastError := W.Err;
  end
  else
    Failed(D, W.Err);
  { its new value comes back with the next step }
  D.Blocks[D.Tags[W.Tag].Block].Due := ChMsTick;
  SetLength(D.Done, Length(D.Done) + 1);
  D.Done[High(D.Done)] := W;
end;

function StartWrite(var D: tPcccDevice): Boolean;
var
  T: ^tPcccTag;
  Ok: Boolean;
begin
  T := @D.Tags[D.Writes[0].Tag];
  if T^.Kind = pvFloat then
    Ok := PcccStartWriteFloats(D.WriteReq, D.Client, PcccAddressTextAs(Dialect(D), T^.Addr), [D.Writes[0].Value])
  else
    Ok := PcccStartWriteInts(D.WriteReq, D.Client, PcccAddressTextAs(Dialect(D), T^.Addr),
      [Round(D.Writes[0].Value)]);
  D.Busy := tbWrite;
  if not Ok then
    WriteDone(D);
  Result := True;
end;

{ The block to read now: the most overdue one due; -1 when none is due. }
function NextBlock(const D: tPcccDevice; Now_: QWord): LongInt;
var
  I: LongInt;
begin
  Result := -1;
  for I := 0 to High(D.Blocks) do
    if (D.Blocks[I].Due <= Now_) and ((Result < 0) or (D.Blocks[I].Due < D.Blocks[Result].Due)) then
      Result := I;
end;

procedure StartRead(var D: tPcccDevice; Blk: LongInt);
var
  A: tPcccAddr;
  Req: tSendRecord;
  Len: Word;
  B: ^tPcccBlock;
begin
  B := @D.Blocks[Blk];
  FillChar(A, SizeOf(A), 0);
  A.FileType := B^.FileType;
  A.FileNo := B^.FileNo;
  A.Elem := Word(B^.First);
  A.Bit := -1;
  D.Expect := B^.Elems * PcccElemSize(B^.FileType);
  if D.Plc5 then
    Plc5BuildWordRead(A, D.Expect, D.Client.Tns, Req, Len)
  else
    PcccBuildRead(A, D.Expect, D.Client.Tns, Req, Len);
  D.Client.Tns := Word(D.Client.Tns + 1);
  D.Cur := Blk;
  D.Busy := tbRead;
  if not DF1MasterStart(D.Master, D.Client.Chn, Req, Len, D.Client.TimeoutMs) then
    ReadDone(D);
end;

function TagDeviceStep(var D: tPcccDevice): Boolean;
begin
  Result := TagDeviceStepAt(D, ChMsTick);
end;

function TagDeviceStepAt(var D: tPcccDevice; Now_: QWord): Boolean;
var
  Blk: LongInt;
begin
  if D.Client.Chn = nil then
    Exit(False);
  case D.Busy of
    tbRead:
      if DF1MasterStep(D.Master) then
        ReadDone(D);
    tbWrite:
      if PcccStep(D.WriteReq) then
        WriteDone(D);
  end;
  if D.Busy = tbIdle then
  begin
    if Length(D.Writes) > 0 then
      StartWrite(D)
    else if D.State = tdDemoted then
    begin
      if Now_ >= D.RetryAt then
      begin
        D.RetryAt := Now_ + QWord(D.DemoteMs);
        Inc(D.Retries);
        Blk := NextBlock(D, High(QWord));
        if Blk >= 0 then
          StartRead(D, Blk);
      end;
    end
    else
    begin
      Blk := NextBlock(D, Now_);
      if Blk >= 0 then
        StartRead(D, Blk);
    end;
  end;
  Result := (IndexQueueCount(D.Changes) > 0) or D.StateChanged or (Length(D.Done) > 0);
end;

function TagDeviceDueAt(const D: tPcccDevice): QWord;
var
  I: LongInt;
begin
  if D.Client.Chn = nil then
    Exit(High(QWord));
  case D.Busy of
    tbRead: Exit(DF1MasterWaitEnd(D.Master));
    tbWrite: Exit(DF1MasterWaitEnd(D.WriteReq.Master));
  end;
  if Length(D.Writes) > 0 then
    Exit(0);
  if D.State = tdDemoted then
    Exit(D.RetryAt);
  Result := High(QWord);
  for I := 0 to High(D.Blocks) do
    if D.Blocks[I].Due < Result then
      Result := D.Blocks[I].Due;
end;

function TagDeviceWaitMs(const D: tPcccDevice): LongInt;
begin
  Result := ChnWaitLeft(TagDeviceDueAt(D));
end;

function TagTakeChange(var D: tPcccDevice; out Tag: LongInt): Boolean;
var
  T: ^tPcccTag;
begin
  Result := IndexQueueTake(D.Changes, Tag);
  if not Result then
    Exit;
  T := @D.Tags[Tag];
  T^.Queued := False;
  T^.SentQuality := T^.Quality;
  if T^.Quality = tqGood then
  begin
    T^.Sent := Copy(T^.Values);
    T^.SentText := T^.Text;
  end;
end;

function TagTakeHealth(var D: tPcccDevice): Boolean;
begin
  Result := D.StateChanged;
  D.StateChanged := False;
end;

function TagDeviceWrite(var D: tPcccDevice; Tag: LongInt; Value: Double; Id: LongInt;
  out Err: ShortString): Boolean;
var
  T: ^tPcccTag;
begin
  Err := '';
  if (Tag < 0) or (Tag > High(D.Tags)) then
    Err := 'no such tag'
  else
  begin
    T := @D.Tags[Tag];
    if not T^.Writable then
      Err := T^.Name + ' is not writable'
    else if TagIsBit(T^) and (Value <> 0) and (Value <> 1) then
      Err := T^.Name + ' is a bit: 0, 1, false or true, not ' + FloatToStr(Value)
    else if (T^.Kind = pvInt) and (Frac(Value) <> 0) then
      Err := T^.Name + ' holds integers, not ' + FloatToStr(Value)
    else if D.State = tdDemoted then
      Err := D.Name + ' is demoted (not answering): ' + D.LastError
    else if D.Client.Chn = nil then
      Err := D.Name + ' has no line';
  end;
  Result := Err = '';
  if not Result then
    Exit;
  SetLength(D.Writes, Length(D.Writes) + 1);
  D.Writes[High(D.Writes)].Tag := Tag;
  D.Writes[High(D.Writes)].Value := Value;
  D.Writes[High(D.Writes)].Id := Id;
  D.Writes[High(D.Writes)].Res := res_Ok;
  D.Writes[High(D.Writes)].Err := '';
end;

function TagTakeWrite(var D: tPcccDevice; out W: tTagWrite): Boolean;
var
  I: LongInt;
begin
  Result := Length(D.Done) > 0;
  if not Result then
  begin
    FillChar(W, SizeOf(W), 0);
    Exit;
  end;
  W := D.Done[0];
  for I := 1 to High(D.Done) do
    D.Done[I - 1] := D.Done[I];
  SetLength(D.Done, Length(D.Done) - 1);
end;

end.
