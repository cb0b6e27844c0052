{ Tests of ChnTrc, the trace layer (NAM=TRC): it is transparent (the same
  exchange with and without it gives identical received data, chunk by
  chunk), loses no byte in a 64 KiB burst, never writes past the caller's
  buffer, and its log reads back (ChnTrcFormat) to exactly the bytes that
  passed. Files go to a private temp dir that TearDown removes. }
unit TestChnTrc;

{$MODE OBJFPC}{$H+}

interface

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF}
  SysUtils, Classes, fpcunit, testregistry, ChnTypes, ChnVirt, ChnLoop, ChnTestLayer,
  ChnDF1, ChnTrc, ChnTrcFormat, TestSupport, TestTempDir;

type
  TTestChnTrc = class(TTestCase)
  private
    Dir: string;
    A, B: pChnVirt;
    RBuf: array of Byte;
    function Stack(const Name, Params: string): pChnVirt;
    procedure DisposeAll;
    function Transfer(W, R: pChnVirt; const Msg: array of Byte; RSize: Word;
      var Seen: AnsiString): Boolean;
    function Exchange(const ParamsA, ParamsB: string; RSize: Word): AnsiString;
    function LogFrames(const Name: string; var F: tTrcFrames): LongInt;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestDefaultParams;
    procedure TestParamRoundTripInStack;
    procedure TestBadParams;
    procedure TestLogFileCannotBeOpened;
    {$IFDEF UNIX}
    procedure TestFifoWithoutReaderIsRefused;
    {$ENDIF}
    procedure TestFileCannotChangeWhileOpen;
    procedure TestTransparentUnderProtocolLayer;
    procedure TestTransparentAsTopLayer;
    procedure TestBurst64KiB;
    procedure TestSmallBufferNeverWrittenPast;
    procedure TestReceiveBufferBeforeAndAfterConnect;
    procedure TestWrongStateAndNoBuffer;
    procedure TestRefusedSendIsNotLogged;
    procedure TestLogLinesHexAndDec;
    procedure TestAppendsToExistingFile;
    {$IFDEF UNIX}
    { both need Unix: dup2 of descriptor 2, and /dev/full }
    procedure TestDefaultIsStandardError;
    {$ENDIF}
    procedure TestFlushPassesDown;
    procedure TestNodesPassThrough;
    procedure TestLengthBeyondBufferIsCut;
    {$IFDEF UNIX}
    procedure TestFailedLogWriteKeepsData;
    {$ENDIF}
    procedure TestResultTextOfTheLayerBelow;
  end;

implementation

type
  { ChOpen of a channel on its own thread, so a test sees an open that
    blocks instead of hanging with it. }
  TOpenThread = class(TThread)
    Chn: pChnVirt;
    procedure Execute; override;
  end;

procedure TOpenThread.Execute;
begin
  Chn^.ChOpen;
end;

type
  { A broken physical layer (NAM=TLIE, tests only): always has data, fills
    the buffer it was given but claims 5 bytes more than its size. }
  pChnLiar = ^tChnLiar;
  tChnLiar = object(tChnVirt)
    constructor Init;
    function  ChHasLow: Boolean; virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
  end;

  pAddChnLiar = ^tAddChnLiar;
  tAddChnLiar = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

constructor tChnLiar.Init;
begin
  inherited Init;
  ChSetType('TLIE');
end;

function tChnLiar.ChHasLow: Boolean;
begin
  Result := False;
end;

function tChnLiar.ChReceiveReady: tChState;
begin
  Result := CHS_ReceiveReady;
end;

procedure tChnLiar.ChReceive(var Len: Word);
begin
  FillChar(CH_RBuff^, CH_RSize, $11);
  Len := CH_RSize + 5;
  CH_RResult := res_Ok;
end;

function tAddChnLiar.ChInit: pChnVirt;
begin
  Result := New(pChnLiar, Init);
end;

const
  Sizes: array[0..9] of Integer = (1, 2, 3, 255, 256, 257, 1000, 4095, 4096, 5000);

function Pattern(Seed, I: Integer): Byte;
begin
  Result := (I * 7 + I shr 8 + Seed * 13) and $FF;
end;

function MsNow: LongInt;
var
  H, M, S, Ms: Word;
begin
  DecodeTime(Now, H, M, S, Ms);
  Result := ((LongInt(H) * 60 + M) * 60 + S) * 1000 + Ms;
end;

procedure TTestChnTrc.SetUp;
begin
  Dir := MakeTempDir('chntrc');
  A := nil;
  B := nil;
  SetLength(RBuf, 65536);
end;

procedure TTestChnTrc.DisposeAll;
begin
  if A <> nil then
    Dispose(A, Done);
  if B <> nil then
    Dispose(B, Done);
  A := nil;
  B := nil;
end;

procedure TTestChnTrc.TearDown;
begin
  DisposeAll;
  RemoveTempDir(Dir);
  AssertFalse('temp dir removed', DirectoryExists(Dir));
end;

function TTestChnTrc.Stack(const Name, Params: string): pChnVirt;
var
  Err: string;
begin
  Result := OpenStack(Name, StringReplace(Params, '%D', Dir, [rfReplaceAll]), Err);
  AssertNotNull(Err, Result);
end;

function TTestChnTrc.LogFrames(const Name: string; var F: tTrcFrames): LongInt;
var
  Skipped: LongInt;
begin
  Skipped := -1;
  Result := TrcReadText(ReadFileText(Dir + Name), F, Skipped);
  AssertEquals(Name + ': every line is a frame line', 0, Skipped);
end;

{ Send Msg from W, read it on R in a buffer of RSize bytes; Seen gets the
  length and bytes of every chunk R's application received. }
function TTestChnTrc.Transfer(W, R: pChnVirt; const Msg: array of Byte; RSize: Word;
  var Seen: AnsiString): Boolean;
var
  Got: array of Byte;
  Total: Integer;
  Len: Word;
  Deadline: QWord;
begin
  Result := False;
  AssertTrue('sender idle', WaitSent(W, 2000, R));
  W^.ChSend(@Msg[0], Length(Msg));
  AssertEquals('send result', res_Ok, W^.ChSendResult);
  SetLength(Got, Length(Msg));
  R^.ChReceiveBuffer(@RBuf[0], RSize);
  Total := 0;
  Len := 0;
  Deadline := GetTickCount64 + 5000;
  while (Total < Length(Msg)) and (GetTickCount64 < Deadline) do
  begin
    W^.ChSendReady;
    if R^.ChReceiveReady = CHS_ReceiveReady then
    begin
      R^.ChReceive(Len);
      AssertTrue('no more than the buffer', Len <= RSize);
      AssertTrue('no more than was sent', Total + Len <= Length(Msg));
      Move(RBuf[0], Got[Total], Len);
      Inc(Total, Len);
      Seen := Seen + IntToStr(Len) + ':' + BytesToHex(RBuf, Len) + ';';
    end;
  end;
  AssertEquals('all bytes arrived', Length(Msg), Total);
  AssertTrue('same bytes', CompareByte(Msg[0], Got[0], Total) = 0);
  Seen := Seen + '|';
  Result := True;
end;

{ The same dialogue on any pair of stacks: every size in Sizes from A to B
  and back. Returns what both applications saw, chunk by chunk. }
function TTestChnTrc.Exchange(const ParamsA, ParamsB: string; RSize: Word): AnsiString;
var
  I, J: Integer;
  Msg: array of Byte;
begin
  Result := '';
  A := Stack('TSTP', ParamsA);
  B := Stack('TSTP', ParamsB);
  for I := 0 to High(Sizes) do
  begin
    SetLength(Msg, Sizes[I]);
    for J := 0 to High(Msg) do
      Msg[J] := Pattern(I, J);
    Transfer(A, B, Msg, RSize, Result);
    for J := 0 to High(Msg) do
      Msg[J] := Pattern(I + 50, J);
    Transfer(B, A, Msg, RSize, Result);
  end;
  DisposeAll;
end;

procedure TTestChnTrc.TestDefaultParams;
var
  T: pChnVirt;
begin
  T := ChnCollection^.ChNewInit('trc');
  try
    AssertNotNull(T);
    AssertEquals('NAM=TRC FILE=STDERR MOD=HEX', T^.ChGetParam(''));
    T^.ChSetParam('FILE=stdout MOD=dec');
    AssertEquals(res_Ok, T^.ChResult);
    AssertEquals('NAM=TRC FILE=STDOUT MOD=DEC', T^.ChGetParam(''));
    AssertEquals('FILE=STDOUT', T^.ChGetParam('FILE'));
    T^.ChSetParam('NAM=TRC FILE=Stderr');
    AssertEquals('NAM=TRC FILE=STDERR MOD=DEC', T^.ChGetParam(''));
    T^.ChSetParam('FILE=' + Dir + 'a.log');
    AssertEquals('a path is kept as written', 'FILE=' + Dir + 'a.log', T^.ChGetParam('FILE'));
    AssertFalse('nothing opened by ChSetParam', FileExists(Dir + 'a.log'));
    T^.ChOpen;
    AssertEquals('no layer below', res_NoLowLayer, T^.ChResult);
    AssertEquals(CHS_Close, T^.ChReady);
  finally
    Dispose(T, Done);
  end;
end;

procedure TTestChnTrc.TestParamRoundTripInStack;
var
  T, U: pChnVirt;
  P: string;
begin
  T := ChnCollection^.ChNewInit('TSTP');
  U := ChnCollection^.ChNewInit('TSTP');
  try
    { both layers have a MOD= key: each takes its own }
    T^.ChSetParam('NAM=TSTP MOD=B NAM=TRC FILE=' + Dir + 'rt.log MOD=DEC NAM=LOOP PAIR=RT END=2');
    AssertEquals(T^.ChParamError, res_Ok, T^.ChResult);
    P := T^.ChGetParam('');
    AssertEquals('NAM=TSTP NOD=0 DNO=0 MOD=B CNT=0 FLG=OFF NAM=TRC FILE=' + Dir +
      'rt.log MOD=DEC NAM=LOOP PAIR=RT END=2 LRB=4096 IDL=0', P);
    AssertTrue(pChnTrc(T^.CH_Low)^.CH_Mode = trcDec);
    U^.ChSetParam(P);
    AssertEquals(res_Ok, U^.ChResult);
    AssertEquals('ChSetParam(ChGetParam) rebuilds the stack', P, U^.ChGetParam(''));
  finally
    Dispose(T, Done);
    Dispose(U, Done);
  end;
end;

procedure TTestChnTrc.TestBadParams;
var
  T: pChnVirt;

  procedure Expect(const S: string; R: tChResult; const Tok: string);
  begin
    T^.ChSetParam(S);
    AssertEquals(S, R, T^.ChResult);
    AssertEquals(S + ' token', Tok, T^.ChParamError);
    AssertEquals(S + ' changes nothing', 'NAM=TRC FILE=STDERR MOD=DEC', T^.ChGetParam(''));
  end;

begin
  T := ChnCollection^.ChNewInit('TRC');
  try
    T^.ChSetParam('MOD=DEC');
    Expect('MOD=OCT', res_BadParam, 'MOD=OCT');
    Expect('MOD=HEX FILE=', res_BadParam, 'FILE=');
    Expect('MOD=HEX NOD=1', res_UnknownParam, 'NOD=1');
    Expect('MOD=HEX MOD=HEX', res_DupParam, 'MOD=HEX');
    Expect('FILE=x.log MOD=HEXNAM=LOOP', res_BadParam, 'MOD=HEXNAM=LOOP');
    Expect('MOD=HEX NAM=LOOP PAIR=?', res_BadParam, 'PAIR=?');
  finally
    Dispose(T, Done);
  end;
end;

procedure TTestChnTrc.TestLogFileCannotBeOpened;
var
  T: pChnVirt;
  Other: pChnVirt;
  Bad: array[0..1] of string;
  I: Integer;
begin
  Bad[0] := Dir + 'nodir' + PathDelim + 'x.log';   { missing directory }
  Bad[1] := Dir;                                  { a directory }
  for I := 0 to 1 do
  begin
    T := ChnCollection^.ChNewInit('TRC');
    try
      T^.ChSetParam('FILE=' + Bad[I] + ' NAM=LOOP PAIR=CO END=1');
      AssertEquals(res_Ok, T^.ChResult);
      T^.ChOpen;
      AssertEquals(Bad[I], res_CannotOpen, T^.ChResult);
      AssertEquals('stays closed', CHS_Close, T^.ChReady);
      AssertEquals('the layer below was not opened', CHS_Close, T^.CH_Low^.ChReady);
      { so its loop end is free for another stack }
      Other := Stack('LOOP', 'PAIR=CO END=1');
      Dispose(Other, Done);
      T^.ChConnect;
      AssertEquals(res_WrongState, T^.ChResult);
      { a good file makes the same stack usable }
      T^.ChSetParam('FILE=' + Dir + 'ok.log');
      T^.ChOpen;
      AssertEquals(res_Ok, T^.ChResult);
      AssertEquals(CHS_Open, T^.CH_Low^.ChReady);
    finally
      Dispose(T, Done);
    end;
  end;
  AssertFalse(DirectoryExists(Dir + 'nodir'));
end;

{$IFDEF UNIX}
{ open(2) of a FIFO for writing waits for a reader: FILE= a FIFO nobody
  reads blocked ChOpen for ever. It is refused at once; with a reader it
  is a log like a pipe. }
procedure TTestChnTrc.TestFifoWithoutReaderIsRefused;
var
  Fifo: string;
  Th: TOpenThread;
  Deadline: QWord;
  Rd: cint;
  Buf: array[0..4095] of Char;
  N: TSsize;
  Seen: AnsiString;
begin
  Fifo := Dir + 'trace.fifo';
  AssertEquals('mkfifo', 0, FpMkfifo(Fifo, &600));
  A := ChnCollection^.ChNewInit('TRC');
  A^.ChSetParam('FILE=' + Fifo + ' NAM=LOOP PAIR=FIFO END=1');
  AssertEquals(res_Ok, A^.ChResult);
  Rd := -1;
  Th := TOpenThread.Create(True);
  try
    Th.Chn := A;
    Th.Start;
    Deadline := GetTickCount64 + 2000;
    while not Th.Finished and (GetTickCount64 < Deadline) do
      Sleep(10);
    if not Th.Finished then
      Rd := FpOpen(Fifo, O_RDONLY or O_NONBLOCK);   { releases the blocked open }
    Th.WaitFor;
    AssertTrue('ChOpen returned at once', Rd < 0);
  finally
    Th.Free;
    if Rd >= 0 then
      FpClose(Rd);
  end;
  AssertEquals('refused', res_CannotOpen, A^.ChResult);
  AssertEquals('names the token', 'FILE=' + Fifo, A^.ChParamError);
  AssertEquals('the layer below was not opened', CHS_Close, A^.CH_Low^.ChReady);
  { with a reader it opens, and the log goes there }
  Rd := FpOpen(Fifo, O_RDONLY or O_NONBLOCK);
  AssertTrue('reader', Rd >= 0);
  try
    A^.ChOpen;
    AssertEquals(res_Ok, A^.ChResult);
    A^.ChConnect;
    B := Stack('LOOP', 'PAIR=FIFO END=2');
    Seen := '';
    AssertTrue(Transfer(A, B, [$10, $02], 100, Seen));
    Deadline := GetTickCount64 + 2000;
    repeat
      N := FpRead(Rd, Buf, SizeOf(Buf));
      if N <= 0 then
        Sleep(5);
    until (N > 0) or (GetTickCount64 > Deadline);
    AssertTrue('the log came through the FIFO', N > 0);
    AssertTrue(Copy(Buf, 0, N), Pos('tx   2 | TRC', Copy(Buf, 0, N)) > 0);
  finally
    FpClose(Rd);
  end;
end;
{$ENDIF}

procedure TTestChnTrc.TestFileCannotChangeWhileOpen;
var
  X: array[0..2] of Byte;
  F: tTrcFrames;
begin
  A := Stack('TRC', 'NAM=TRC FILE=%Da.log NAM=LOOP PAIR=FC END=1');
  B := Stack('LOOP', 'PAIR=FC END=2');
  A^.ChSetParam('FILE=' + Dir + 'b.log');
  AssertEquals(res_WrongState, A^.ChResult);
  AssertEquals('FILE=' + Dir + 'b.log', A^.ChParamError);
  AssertEquals('FILE=' + Dir + 'a.log', A^.ChGetParam('FILE'));
  { the same file and another MOD are fine, MOD at once }
  A^.ChSetParam('FILE=' + Dir + 'a.log MOD=DEC');
  AssertEquals(res_Ok, A^.ChResult);
  A^.ChOpen;
  AssertEquals('ChOpen while open', res_WrongState, A^.ChResult);
  X[0] := 16; X[1] := 2; X[2] := 255;
  A^.ChSend(@X, 3);
  AssertEquals(res_Ok, A^.ChSendResult);
  F := nil;
  AssertEquals(1, LogFrames('a.log', F));
  AssertEquals(3, Length(F[0].Data));
  AssertTrue(Pos(LineEnding + '016 002 255' + LineEnding, ReadFileText(Dir + 'a.log')) > 0);
  A^.ChClose;
  A^.ChSetParam('FILE=' + Dir + 'b.log');
  AssertEquals('closed: allowed', res_Ok, A^.ChResult);
  AssertFalse(FileExists(Dir + 'b.log'));
end;

procedure TTestChnTrc.TestTransparentUnderProtocolLayer;
var
  Plain, Traced: AnsiString;
  F: tTrcFrames;
  N, I, J, K, Pos0: LongInt;
  T0, T1: LongInt;
begin
  Plain := Exchange('NAM=TSTP NAM=LOOP PAIR=P1 END=1', 'NAM=TSTP NAM=LOOP PAIR=P1 END=2', 300);
  T0 := MsNow;
  Traced := Exchange('NAM=TSTP NAM=TRC FILE=%Da.log NAM=LOOP PAIR=P2 END=1',
    'NAM=TSTP NAM=TRC FILE=%Db.log MOD=DEC NAM=LOOP PAIR=P2 END=2', 300);
  T1 := MsNow;
  AssertEquals('same chunks, same bytes with and without TRC', Plain, Traced);
  { a.log: A's sends one frame each, B's replies in chunks of at most
    256 bytes (TSTP pulls through CH_LowBuf) }
  F := nil;
  N := LogFrames('a.log', F);
  K := 0;
  for I := 0 to High(Sizes) do
  begin
    AssertTrue('tx frame', (K < N) and (F[K].Dir = trcTx));
    AssertEquals('tx length', Sizes[I], Length(F[K].Data));
    for J := 0 to Sizes[I] - 1 do
      if F[K].Data[J] <> Pattern(I, J) then
        Fail('tx byte ' + IntToStr(J) + ' of message ' + IntToStr(I));
    AssertEquals(res_Ok, F[K].Status);
    AssertEquals('TRC', F[K].Tag);
    if T1 >= T0 then
      AssertTrue('time of day', (F[K].TimeMs >= T0) and (F[K].TimeMs <= T1));
    Inc(K);
    Pos0 := 0;
    while (K < N) and (F[K].Dir = trcRx) do
    begin
      AssertTrue('rx chunk size', (Length(F[K].Data) > 0) and (Length(F[K].Data) <= MaxLowChunk));
      for J := 0 to High(F[K].Data) do
        if F[K].Data[J] <> Pattern(I + 50, Pos0 + J) then
          Fail('rx byte ' + IntToStr(Pos0 + J) + ' of reply ' + IntToStr(I));
      Inc(Pos0, Length(F[K].Data));
      Inc(K);
    end;
    AssertEquals('reply complete in the log', Sizes[I], Pos0);
  end;
  AssertEquals('nothing else logged', N, K);
  { b.log (MOD=DEC) reads back to the same amount the other way }
  N := LogFrames('b.log', F);
  Pos0 := 0;
  for I := 0 to N - 1 do
    if F[I].Dir = trcRx then
      Inc(Pos0, Length(F[I].Data));
  K := 0;
  for I := 0 to High(Sizes) do
    Inc(K, Sizes[I]);
  AssertEquals('bytes B received', K, Pos0);
end;

procedure TTestChnTrc.TestTransparentAsTopLayer;
var
  Plain, Traced: AnsiString;
  F: tTrcFrames;
  N, I, J, K, Pos0, Dir0: LongInt;
begin
  Plain := Exchange('NAM=LOOP PAIR=T1 END=1', 'NAM=LOOP PAIR=T1 END=2', 1000);
  { both ends trace into one file: appends must not overwrite each other }
  Traced := Exchange('NAM=TRC FILE=%Dab.log NAM=LOOP PAIR=T2 END=1',
    'NAM=TRC FILE=%Dab.log NAM=LOOP PAIR=T2 END=2', 1000);
  AssertEquals('same chunks, same bytes with and without TRC', Plain, Traced);
  F := nil;
  N := LogFrames('ab.log', F);
  K := 0;
  for I := 0 to 2 * Length(Sizes) - 1 do
  begin
    Dir0 := (I mod 2) * 50 + I div 2;    { pattern seed of this message }
    AssertTrue('tx frame', (K < N) and (F[K].Dir = trcTx));
    AssertEquals(Sizes[I div 2], Length(F[K].Data));
    for J := 0 to High(F[K].Data) do
      if F[K].Data[J] <> Pattern(Dir0, J) then
        Fail('tx byte ' + IntToStr(J));
    Inc(K);
    Pos0 := 0;
    while (K < N) and (F[K].Dir = trcRx) do
    begin
      AssertTrue('rx chunk fits the caller''s buffer', Length(F[K].Data) <= 1000);
      for J := 0 to High(F[K].Data) do
        if F[K].Data[J] <> Pattern(Dir0, Pos0 + J) then
          Fail('rx byte ' + IntToStr(Pos0 + J));
      Inc(Pos0, Length(F[K].Data));
      Inc(K);
    end;
    AssertEquals(Sizes[I div 2], Pos0);
  end;
  AssertEquals(N, K);
end;

procedure TTestChnTrc.TestBurst64KiB;
const
  Total = 65536;
var
  Msg, Got: array of Byte;
  Sent, Recv, I: LongInt;
  Len: Word;
  Deadline: QWord;
  F: tTrcFrames;
  TxBytes, RxBytes: array of Byte;
  NTx, NRx: LongInt;
begin
  SetLength(Msg, Total);
  SetLength(Got, Total);
  for I := 0 to Total - 1 do
    Msg[I] := Pattern(3, I);
  { sender: TRC on top; receiver: a protocol layer over TRC }
  A := Stack('TRC', 'NAM=TRC FILE=%Dburst.log NAM=LOOP PAIR=BU END=1');
  B := Stack('TSTP', 'NAM=TSTP NAM=TRC FILE=%Dburst.log NAM=LOOP PAIR=BU END=2');
  B^.ChReceiveBuffer(@RBuf[0], 1000);
  A^.ChSend(@Msg[0], 65535);                 { the largest Len there is }
  AssertEquals(res_Ok, A^.ChSendResult);
  Sent := 65535;
  Recv := 0;
  Len := 0;
  Deadline := GetTickCount64 + 10000;
  while (Recv < Total) and (GetTickCount64 < Deadline) do
  begin
    if (Sent < Total) and (A^.ChSendReady = CHS_SendReady) then
    begin
      A^.ChSend(@Msg[Sent], Total - Sent);
      AssertEquals(res_Ok, A^.ChSendResult);
      Sent := Total;
    end;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      AssertTrue(Recv + Len <= Total);
      Move(RBuf[0], Got[Recv], Len);
      Inc(Recv, Len);
    end;
  end;
  AssertEquals('every byte arrived', Total, Recv);
  AssertTrue('in order', CompareByte(Msg[0], Got[0], Total) = 0);
  DisposeAll;
  { the log holds all 64 KiB both ways }
  F := nil;
  SetLength(TxBytes, Total);
  SetLength(RxBytes, Total);
  NTx := 0;
  NRx := 0;
  for I := 0 to LogFrames('burst.log', F) - 1 do
  begin
    AssertEquals(res_Ok, F[I].Status);
    if F[I].Dir = trcTx then
    begin
      AssertTrue(NTx + Length(F[I].Data) <= Total);
      Move(F[I].Data[0], TxBytes[NTx], Length(F[I].Data));
      Inc(NTx, Length(F[I].Data));
    end
    else
    begin
      AssertTrue(NRx + Length(F[I].Data) <= Total);
      Move(F[I].Data[0], RxBytes[NRx], Length(F[I].Data));
      Inc(NRx, Length(F[I].Data));
    end;
  end;
  AssertEquals(Total, NTx);
  AssertEquals(Total, NRx);
  AssertTrue('tx log', CompareByte(Msg[0], TxBytes[0], Total) = 0);
  AssertTrue('rx log', CompareByte(Msg[0], RxBytes[0], Total) = 0);
end;

procedure TTestChnTrc.TestSmallBufferNeverWrittenPast;
var
  Guard: array[0..63] of Byte;
  Msg, Got: array[0..99] of Byte;
  I, Recv: Integer;
  Len: Word;
  Deadline: QWord;
  F: tTrcFrames;
begin
  for I := 0 to 99 do
    Msg[I] := Pattern(9, I);
  A := Stack('LOOP', 'PAIR=SB END=1');
  B := Stack('TRC', 'NAM=TRC FILE=%Dsb.log NAM=LOOP PAIR=SB END=2');
  FillChar(Guard, SizeOf(Guard), $AA);
  B^.ChReceiveBuffer(@Guard[8], 7);
  A^.ChSend(@Msg, 100);
  Recv := 0;
  Len := 0;
  Deadline := GetTickCount64 + 5000;
  while (Recv < 100) and (GetTickCount64 < Deadline) do
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      AssertTrue('at most the buffer size', (Len > 0) and (Len <= 7));
      for I := 0 to 7 do
        AssertEquals('guard before', $AA, Guard[I]);
      for I := 15 to 63 do
        AssertEquals('guard after', $AA, Guard[I]);
      Move(Guard[8], Got[Recv], Len);
      Inc(Recv, Len);
    end;
  AssertEquals(100, Recv);
  AssertTrue(CompareByte(Msg, Got, 100) = 0);
  F := nil;
  AssertEquals('100 bytes in chunks of 7', 15, LogFrames('sb.log', F));
  AssertEquals(2, Length(F[14].Data));
end;

procedure TTestChnTrc.TestReceiveBufferBeforeAndAfterConnect;
var
  Buf1, Buf2: array[0..15] of Byte;
  Msg: array[0..4] of Byte;
  Len: Word;
  I: Integer;
begin
  for I := 0 to 4 do
    Msg[I] := I + 1;
  A := Stack('LOOP', 'PAIR=RB END=1');
  B := ChnCollection^.ChNewInit('TRC');
  FillChar(Buf1, SizeOf(Buf1), 0);
  FillChar(Buf2, SizeOf(Buf2), 0);
  { the manuals' order: buffer first, then open and connect }
  B^.ChReceiveBuffer(@Buf1, SizeOf(Buf1));
  B^.ChSetParam('FILE=' + Dir + 'rb.log NAM=LOOP PAIR=RB END=2');
  B^.ChOpen;
  B^.ChConnect;
  AssertEquals(res_Ok, B^.ChResult);
  A^.ChSend(@Msg, 5);
  AssertTrue(WaitReceive(B, 2000));
  B^.ChReceive(Len);
  AssertEquals(5, Len);
  AssertEquals(res_Ok, B^.ChReceiveResult);
  AssertEquals('01 02 03 04 05 00', BytesToHex(Buf1, 6));
  { a new buffer while connected }
  B^.ChReceiveBuffer(@Buf2, 3);
  Msg[0] := $77;
  A^.ChSend(@Msg, 5);
  AssertTrue(WaitReceive(B, 2000));
  B^.ChReceive(Len);
  AssertEquals(3, Len);
  AssertEquals('77 02 03 00', BytesToHex(Buf2, 4));
  AssertEquals('old buffer untouched', '01 02 03 04 05 00', BytesToHex(Buf1, 6));
  AssertTrue(WaitReceive(B, 2000));
  B^.ChReceive(Len);
  AssertEquals('the rest', 2, Len);
  AssertEquals('04 05 03 00', BytesToHex(Buf2, 4));
end;

procedure TTestChnTrc.TestWrongStateAndNoBuffer;
var
  X: array[0..3] of Byte;
  Len: Word;
begin
  FillChar(X, SizeOf(X), 1);
  A := ChnCollection^.ChNewInit('TRC');
  A^.ChSetParam('FILE=' + Dir + 'ws.log NAM=LOOP PAIR=WS END=1');
  A^.ChSend(@X, 4);
  AssertEquals('closed', res_WrongState, A^.ChSendResult);
  Len := 99;
  A^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals(res_WrongState, A^.ChReceiveResult);
  AssertEquals(CHS_RecInactive, A^.ChReceiveReady);
  AssertFalse('log opened only by ChOpen', FileExists(Dir + 'ws.log'));
  A^.ChOpen;
  A^.ChConnect;
  AssertEquals(res_Ok, A^.ChResult);
  A^.ChReceive(Len);
  AssertEquals(res_NoRecBuff, A^.ChReceiveResult);
  AssertEquals(0, Len);
  A^.ChSend(nil, 4);
  AssertEquals(res_BadLen, A^.ChSendResult);
  A^.ChSend(@X, 0);
  AssertEquals(res_BadLen, A^.ChSendResult);
  A^.ChReceiveBuffer(@X, SizeOf(X));
  AssertEquals(CHS_Receiving, A^.ChReceiveReady);
  Len := 99;
  A^.ChReceive(Len);
  AssertEquals(0, Len);
  AssertEquals('the lower layer''s result', res_NoMessage, A^.ChReceiveResult);
  A^.ChDisConnect;
  AssertEquals(CHS_RecInactive, A^.ChReceiveReady);
  A^.ChReceive(Len);
  AssertEquals(res_WrongState, A^.ChReceiveResult);
  AssertEquals('nothing logged', '', ReadFileText(Dir + 'ws.log'));
end;

procedure TTestChnTrc.TestRefusedSendIsNotLogged;
var
  Msg: array[0..99] of Byte;
  F: tTrcFrames;
  Seen: AnsiString;
  Got: Integer;
  Len: Word;
  Deadline: QWord;
begin
  FillChar(Msg, SizeOf(Msg), $5A);
  A := Stack('TRC', 'NAM=TRC FILE=%Dbusy.log NAM=LOOP PAIR=BZ END=1');
  B := Stack('LOOP', 'PAIR=BZ END=2 LRB=16');
  A^.ChSend(@Msg, 100);
  AssertEquals(res_Ok, A^.ChSendResult);
  AssertEquals('held back by flow control', CHS_Sending, A^.ChSendReady);
  A^.ChSend(@Msg, 5);
  AssertEquals(res_Busy, A^.ChSendResult);
  F := nil;
  AssertEquals('only the send that went down', 1, LogFrames('busy.log', F));
  AssertEquals(100, Length(F[0].Data));
  { B gets exactly those 100 bytes, then the next message }
  B^.ChReceiveBuffer(@RBuf[0], 1000);
  Got := 0;
  Len := 0;
  Deadline := GetTickCount64 + 5000;
  while (Got < 100) and (GetTickCount64 < Deadline) do
  begin
    A^.ChSendReady;
    if B^.ChReceiveReady = CHS_ReceiveReady then
    begin
      B^.ChReceive(Len);
      Inc(Got, Len);
    end;
  end;
  AssertEquals(100, Got);
  Seen := '';
  Transfer(A, B, [1, 2, 3], 1000, Seen);
  AssertEquals('3:01 02 03;|', Seen);
  AssertEquals(2, LogFrames('busy.log', F));
end;

procedure TTestChnTrc.TestLogLinesHexAndDec;
var
  X: array[0..2] of Byte;
  Text: AnsiString;
  Lines: array of string;
  I, P: Integer;
begin
  X[0] := $10; X[1] := $06; X[2] := $FF;
  A := Stack('TRC', 'NAM=TRC FILE=%Dhex.log NAM=LOOP PAIR=HX END=1');
  B := Stack('TRC', 'NAM=TRC FILE=%Ddec.log MOD=DEC NAM=LOOP PAIR=HX END=2');
  A^.ChSend(@X, 2);
  B^.ChSend(@X, 3);
  Text := ReadFileText(Dir + 'hex.log');
  SetLength(Lines, 0);
  P := 1;
  for I := 1 to Length(Text) do
    if Text[I] = #10 then
    begin
      SetLength(Lines, Length(Lines) + 1);
      Lines[High(Lines)] := Copy(Text, P, I - P);
      if Copy(LineEnding, 1, 1) = #13 then        { CR LF on Windows }
        SetLength(Lines[High(Lines)], Length(Lines[High(Lines)]) - 1);
      P := I + 1;
    end;
  AssertEquals(2, Length(Lines));
  { 'HH:MM:SS.mmm tx   2 | TRC' }
  AssertEquals(25, Length(Lines[0]));
  for I in [1, 2, 4, 5, 7, 8, 10, 11, 12] do
    AssertTrue('digit at ' + IntToStr(I), Lines[0][I] in ['0'..'9']);
  AssertEquals('::.', Lines[0][3] + Lines[0][6] + Lines[0][9]);
  AssertEquals(' tx   2 | TRC', Copy(Lines[0], 13, 13));
  AssertEquals('1006', Lines[1]);
  Text := ReadFileText(Dir + 'dec.log');
  AssertEquals(' tx   3 | TRC' + LineEnding + '016 006 255' + LineEnding, Copy(Text, 13, 100));
end;

procedure TTestChnTrc.TestAppendsToExistingFile;
var
  X: array[0..1] of Byte;
  F: tTrcFrames;
  Skipped: LongInt;
begin
  WriteFileText(Dir + 'old.log', 'an earlier run' + LineEnding);
  X[0] := $10; X[1] := $05;
  A := Stack('TRC', 'NAM=TRC FILE=%Dold.log NAM=LOOP PAIR=AP END=1');
  A^.ChSend(@X, 2);
  A^.ChClose;
  A^.ChOpen;                       { a second open appends too }
  A^.ChConnect;
  A^.ChSend(@X, 2);
  AssertEquals('an earlier run' + LineEnding,
    Copy(ReadFileText(Dir + 'old.log'), 1, Length('an earlier run' + LineEnding)));
  F := nil;
  Skipped := 0;
  AssertEquals(2, TrcReadText(ReadFileText(Dir + 'old.log'), F, Skipped));
  AssertEquals(1, Skipped);
end;

{$IFDEF UNIX}
procedure TTestChnTrc.TestDefaultIsStandardError;
var
  X: array[0..1] of Byte;
  F: tTrcFrames;
  Fd, Save, Std: cint;
  Name: string;
begin
  X[0] := $10; X[1] := $06;
  for Std := 1 to 2 do
  begin
    if Std = 2 then
      Name := ''                       { the default }
    else
      Name := 'FILE=stdout';
    Save := FpDup(Std);
    Fd := FpOpen(Dir + 'std.txt', O_WRONLY or O_CREAT or O_TRUNC, &600);
    AssertTrue(Fd >= 0);
    FpDup2(Fd, Std);
    FpClose(Fd);
    try
      A := Stack('TRC', 'NAM=TRC ' + Name + ' NAM=LOOP PAIR=SE END=1');
      A^.ChSend(@X, 2);
      DisposeAll;
    finally
      FpDup2(Save, Std);
      FpClose(Save);
    end;
    F := nil;
    AssertEquals('descriptor ' + IntToStr(Std), 1, LogFrames('std.txt', F));
    AssertEquals('10 06', BytesToHex(F[0].Data, Length(F[0].Data)));
  end;
end;
{$ENDIF}

procedure TTestChnTrc.TestFlushPassesDown;
var
  X: array[0..9] of Byte;
  Len: Word;
  F: tTrcFrames;
begin
  FillChar(X, SizeOf(X), 7);
  A := Stack('LOOP', 'PAIR=FL END=1');
  B := Stack('TRC', 'NAM=TRC FILE=%Dfl.log NAM=LOOP PAIR=FL END=2');
  B^.ChReceiveBuffer(@RBuf[0], 100);
  A^.ChSend(@X, 10);
  AssertTrue(WaitReceive(B, 2000));
  B^.ChReceiveFlush;
  AssertEquals(CHS_Receiving, B^.ChReceiveReady);
  B^.ChReceive(Len);
  AssertEquals(0, Len);
  F := nil;
  AssertEquals('discarded bytes were never received', 0, LogFrames('fl.log', F));
end;

procedure TTestChnTrc.TestNodesPassThrough;
var
  S, D: tNode;
begin
  A := ChnCollection^.ChNewInit('TRC');
  A^.ChSetParam('NAM=TRC NAM=TSTP NOD=3 NAM=LOOP PAIR=ND END=1');
  AssertEquals(res_Ok, A^.ChResult);
  A^.ChDestNode(5);
  AssertEquals('destination reaches the layer below', 5, A^.CH_Low^.CH_DNode);
  A^.CH_Low^.CH_RSNode := 7;
  A^.CH_Low^.CH_RDNode := 3;
  S := 0;
  D := 0;
  A^.ChGetNode(S, D);
  AssertEquals(7, S);
  AssertEquals(3, D);
end;

procedure TTestChnTrc.TestLengthBeyondBufferIsCut;
var
  Guard: array[0..63] of Byte;
  Len: Word;
  F: tTrcFrames;
begin
  FillChar(Guard, SizeOf(Guard), $AA);
  A := Stack('TRC', 'NAM=TRC FILE=%Dlie.log NAM=TLIE');
  A^.ChReceiveBuffer(@Guard[8], 7);
  AssertEquals(CHS_ReceiveReady, A^.ChReceiveReady);
  A^.ChReceive(Len);
  AssertEquals('never more than the caller''s buffer', 7, Len);
  F := nil;
  AssertEquals(1, LogFrames('lie.log', F));
  AssertEquals('11 11 11 11 11 11 11', BytesToHex(F[0].Data, Length(F[0].Data)));
end;

{$IFDEF UNIX}
procedure TTestChnTrc.TestFailedLogWriteKeepsData;
var
  Seen: AnsiString;
begin
  if not FileExists('/dev/full') then
    Exit;          { Linux only; the runner counts Ignore() as a failure }
  { every write to /dev/full fails (ENOSPC) }
  A := Stack('TRC', 'NAM=TRC FILE=/dev/full NAM=LOOP PAIR=DF END=1');
  B := Stack('LOOP', 'PAIR=DF END=2');
  Seen := '';
  Transfer(A, B, [1, 2, 3], 100, Seen);
  Transfer(B, A, [4, 5], 100, Seen);
  AssertEquals('3:01 02 03;|2:04 05;|', Seen);
  AssertEquals('both writes failed, counted', 2, pChnTrc(A)^.CH_LogErrors);
  AssertEquals(res_Ok, A^.ChResult);
end;
{$ENDIF}

{ On top of a protocol layer TRC passes its codes ($20 up) through: their
  text is the protocol's, not TRC's own reader codes ($20 res_TrcShort,
  $21 res_TrcLong) that share the numbers. }
procedure TTestChnTrc.TestResultTextOfTheLayerBelow;
begin
  A := ChnCollection^.ChNewInit('TRC');
  A^.ChSetParam('NAM=TRC NAM=DF1 NAM=LOOP PAIR=RTX END=1');
  AssertEquals(res_Ok, A^.ChResult);
  AssertEquals('DF1 checksum', ChResultText(ChnDF1.res_ErrSum, 'DF1'),
    A^.ChResultStr(ChnDF1.res_ErrSum));
  AssertEquals('DF1 frame', ChResultText(ChnDF1.res_ErrFrame, 'DF1'),
    A^.ChResultStr(ChnDF1.res_ErrFrame));
  AssertEquals('general', 'transmitter busy', A^.ChResultStr(res_Busy));
end;

initialization
  ChnCollection^.Insert(New(pAddChnLiar, Init('TLIE')));
  RegisterTest(TTestChnTrc);
end.
