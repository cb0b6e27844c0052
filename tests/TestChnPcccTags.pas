{ TestChnPcccTags - the PCCC tag engine: Kepware's tag notation, the
  merging of tags into few reads (the request count worked out by hand
  from the element sizes and the 244-byte limit), and the engine stepped
  from ChnWaitAny against tools/df1sim on a pty: the values of its
  built-in table (docs/df1sim.md), changes only (the free-running clock
  S2:4 moves, N7 does not; a deadband holds S2:4 back), a write that comes
  back as a change, a refused read, and a dead device that goes down, is
  demoted and retried every DEMOTE ms while a live one keeps its rate;
  reads of at most MaxRead bytes; and two blocks on a busy 19200 Bd line
  (an SLC station of tools/lib on an in-memory line) each read every scan. }
unit TestChnPcccTags;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, fpcunit, testregistry, ChnTypes, ChnPccc, ChnPcccClient, ChnPcccTags;

type
  TTestChnPcccTags = class(TTestCase)
  published
    procedure TestParseKepwareNotation;
    procedure TestMergeScatteredTags;
    procedure TestMergeKeepsFilesAndScanClassesApart;
    procedure TestRefusals;
    {$IFDEF UNIX}
    procedure TestValuesFromDf1sim;
    procedure TestChangesOnlyAndDeadband;
    procedure TestWriteComesBack;
    procedure TestRefusedRead;
    procedure TestDeadDeviceDemotedOtherKeepsItsRate;
    procedure TestPlc5Device;
    procedure TestBlocksKeepTheirScanOnABusyLine;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix, Process, BinSupport, PtyPair, ChnLayers, ChnDF1Link, ChnSlc,{$ENDIF}
  ChnWait, ChnVirt;

procedure TTestChnPcccTags.TestParseKepwareNotation;
var
  A: tPcccAddr;
  N: LongInt;
  E: ShortString;
begin
  AssertEquals('N7:0[10]', res_Ok, TagParse('N7:0[10]', A, N, E));
  AssertEquals('count', 10, N);
  AssertEquals('file', 7, A.FileNo);
  AssertEquals('type', pft_Integer, A.FileType);
  AssertEquals('F8:2', res_Ok, TagParse(' F8:2 ', A, N, E));
  AssertEquals('count 1', 1, N);
  AssertEquals('elem', 2, A.Elem);
  AssertEquals('B3:0/5', res_Ok, TagParse('B3:0/5', A, N, E));
  AssertEquals('bit', 5, A.Bit);
  AssertEquals('T4:1.ACC', res_Ok, TagParse('T4:1.ACC', A, N, E));
  AssertEquals('sub ACC', 2, A.Sub);
  AssertEquals('ST9:0', res_Ok, TagParse('ST9:0', A, N, E));
  AssertEquals('L10:0[4]', res_Ok, TagParse('L10:0[4]', A, N, E));
  AssertEquals('L count', 4, N);
  AssertEquals('[0]', res_PcccCount, TagParse('N7:0[0]', A, N, E));
  AssertEquals('[0] text', '"N7:0[0]": the array size "0" is not 1..4096', E);
  AssertEquals('[x]', res_PcccCount, TagParse('N7:0[x]', A, N, E));
  AssertEquals('unclosed', res_PcccAddress, TagParse('N7:0[4', A, N, E));
  AssertEquals('unclosed text', '"N7:0[4": an array is ADDRESS[n]', E);
  AssertEquals('bad file', res_PcccAddress, TagParse('Q7:0', A, N, E));
  AssertTrue('names it: ' + E, Pos('"Q7:0": ', E) = 1);
end;

function Added(var D: tPcccDevice; const Addr: string; Scan: LongInt = 500): LongInt;
var
  E: ShortString;
begin
  if TagAdd(D, '', Addr, Scan, 0, False, E) <> res_Ok then
    raise Exception.Create(E);
  Result := High(D.Tags);
end;

{ 100 tags N7:0, N7:2 .. N7:198 (one word in two): elements 0..198, 398
  bytes; one read carries 244 bytes = 122 elements, so N7:0..N7:120 (61
  tags, 121 elements) and N7:122..N7:198 (39 tags, 77 elements): 2 reads }
procedure TTestChnPcccTags.TestMergeScatteredTags;
var
  D: tPcccDevice;
  I: LongInt;
begin
  TagDeviceInit(D, 'plc');
  for I := 0 to 99 do
    Added(D, 'N7:' + IntToStr(2 * I));
  TagDeviceStart(D);
  AssertEquals('reads per scan', 2, TagDeviceReads(D));
  AssertEquals('block 0 first', 0, D.Blocks[0].First);
  AssertEquals('block 0 elements', 121, D.Blocks[0].Elems);
  AssertEquals('block 1 first', 122, D.Blocks[1].First);
  AssertEquals('block 1 elements', 77, D.Blocks[1].Elems);
  AssertEquals('N7:120 in block 0', 0, D.Tags[60].Block);
  AssertEquals('N7:122 in block 1', 1, D.Tags[61].Block);
  TagDeviceDone(D);
  { reads of at most 100 bytes (50 words): N7:0..48 (25 tags, 49
    elements, 98 bytes; N7:50 would make 102), N7:50..98, N7:100..148,
    N7:150..198 }
  TagDeviceInit(D, 'plc');
  D.MaxRead := 100;
  for I := 0 to 99 do
    Added(D, 'N7:' + IntToStr(2 * I));
  TagDeviceStart(D);
  AssertEquals('100 bytes: reads per scan', 4, TagDeviceReads(D));
  for I := 0 to 3 do
  begin
    AssertEquals('100 bytes: block first', 50 * I, D.Blocks[I].First);
    AssertEquals('100 bytes: block elements', 49, D.Blocks[I].Elems);
  end;
  TagDeviceDone(D);
  { a gap wider than MaxGap (32 bytes = 16 words) is a read of its own:
    N7:0 and N7:17 (gap 16 words: 32 bytes, merged), N7:35 (gap 17: apart) }
  TagDeviceInit(D, 'plc');
  Added(D, 'N7:35');
  Added(D, 'N7:17');
  Added(D, 'N7:0');
  TagDeviceStart(D);
  AssertEquals('gaps: reads', 2, TagDeviceReads(D));
  AssertEquals('N7:0..17', 18, D.Blocks[0].Elems);
  AssertEquals('N7:35 alone', 35, D.Blocks[1].First);
  TagDeviceDone(D);
end;

procedure TTestChnPcccTags.TestMergeKeepsFilesAndScanClassesApart;
var
  D: tPcccDevice;
begin
  TagDeviceInit(D, 'plc');
  Added(D, 'N7:0[10]');
  Added(D, 'N7:5', 1000);        { another scan class: a read of its own }
  Added(D, 'N9:0');              { another file }
  Added(D, 'F8:0[2]');
  Added(D, 'F8:3');              { F8:0..3: 16 bytes, one read }
  Added(D, 'B3:0/5');
  Added(D, 'B3:1/15');           { B3:0..1 }
  Added(D, 'T4:0.ACC');
  Added(D, 'T4:1');              { T4:0..1, 12 bytes }
  Added(D, 'ST10:0');
  Added(D, 'ST10:1');            { 2 x 84 bytes = 168: one read }
  Added(D, 'ST10:2');            { 252 bytes: a second read }
  TagDeviceStart(D);
  { N7 500, N7 1000, N9, F8, B3, T4, ST10 x2 }
  AssertEquals('reads', 8, TagDeviceReads(D));
  AssertEquals('F8 block elements', 4, D.Blocks[D.Tags[3].Block].Elems);
  AssertTrue('F8:0[2] and F8:3 together', D.Tags[3].Block = D.Tags[4].Block);
  AssertTrue('B3 together', D.Tags[5].Block = D.Tags[6].Block);
  AssertTrue('T4 together', D.Tags[7].Block = D.Tags[8].Block);
  AssertTrue('ST10:0,1 together', D.Tags[9].Block = D.Tags[10].Block);
  AssertTrue('ST10:2 apart', D.Tags[10].Block <> D.Tags[11].Block);
  AssertTrue('scan classes apart', D.Tags[0].Block <> D.Tags[1].Block);
  TagDeviceDone(D);
end;

procedure TTestChnPcccTags.TestRefusals;
var
  D: tPcccDevice;
  E: ShortString;
begin
  TagDeviceInit(D, 'plc');
  AssertEquals('123 words', res_PcccCount, TagAdd(D, '', 'N7:0[123]', 500, 0, False, E));
  AssertEquals('text', '"N7:0[123]": 246 bytes, more than one read carries (244); split it', E);
  AssertEquals('122 words fit', res_Ok, TagAdd(D, '', 'N7:0[122]', 500, 0, False, E));
  AssertEquals('string array', res_PcccCount, TagAdd(D, '', 'ST9:0[2]', 500, 0, False, E));
  AssertEquals('writable array', res_PcccUsage, TagAdd(D, '', 'N7:0[2]', 500, 0, True, E));
  AssertEquals('writable string', res_PcccUsage, TagAdd(D, '', 'ST9:0', 500, 0, True, E));
  AssertEquals('writable bit', res_Ok, TagAdd(D, 'run', 'B3:0/5', 500, 0, True, E));
  AssertEquals('found by name', 1, TagFind(D, 'run'));
  AssertEquals('found by address', 0, TagFind(D, 'n7:0[122]'));
  AssertFalse('write to a read-only tag', TagDeviceWrite(D, 0, 1, 1, E));
  AssertEquals('why', 'N7:0[122] is not writable', E);
  AssertFalse('a bit takes 0/1', TagDeviceWrite(D, 1, 2, 1, E));
  AssertEquals('why', 'run is a bit: 0, 1, false or true, not 2', E);
  AssertFalse('no line', TagDeviceWrite(D, 1, 1, 1, E));
  AssertEquals('why', 'plc has no line', E);
  TagDeviceDone(D);
end;

{$IFDEF UNIX}

type
  { df1sim on a pty and a device on it }
  TSim = class
    Proc: TProcess;
    Pty: string;
    constructor Create(const Extra: array of string);
    destructor Destroy; override;
  end;

constructor TSim.Create(const Extra: array of string);
begin
  if not FileExists(BinPath('df1sim')) then
    raise Exception.Create(BinPath('df1sim') + ' missing (make tools)');
  Proc := StartSimPty(Extra, Pty);
  if Pty = '' then
    raise Exception.Create('df1sim gave no pty');
end;

destructor TSim.Destroy;
begin
  StopProcessWith(Proc, SIGTERM);
end;

procedure OpenDevice(var D: tPcccDevice; const Dev: string);
begin
  if PcccOpen(D.Client, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=' + Dev + ' IDL=0') <> res_Ok then
    raise Exception.Create('open ' + Dev + ': ' + D.Client.Err);
end;

{ Step the devices from ChnWaitAny for Ms milliseconds (or until Stop). }
type
  tStopFn = function(Data: Pointer): Boolean;

procedure StepAll(const Devs: array of pPcccDevice; Ms: LongInt; Stop: tStopFn = nil; Data: Pointer = nil);
var
  Deadline: QWord;
  I, W, Wait: LongInt;
begin
  Deadline := ChMsTick + QWord(Ms);
  repeat
    for I := 0 to High(Devs) do
      TagDeviceStep(Devs[I]^);
    if Assigned(Stop) and Stop(Data) then
      Exit;
    Wait := ChnWaitLeft(Deadline);
    for I := 0 to High(Devs) do
    begin
      W := TagDeviceWaitMs(Devs[I]^);
      if W < Wait then
        Wait := W;
    end;
    ChnWaitAny(Wait);
  until ChMsTick >= Deadline;
end;

function AllRead(Data: Pointer): Boolean;
var
  I: LongInt;
begin
  with pPcccDevice(Data)^ do
    for I := 0 to High(Tags) do
      if Tags[I].Quality = tqInitial then
        Exit(False);
  Result := True;
end;

procedure TTestChnPcccTags.TestValuesFromDf1sim;
var
  Sim: TSim;
  D: tPcccDevice;
  Tag: LongInt;
  Seen: string;
begin
  Sim := TSim.Create(['--quiet', '--timeout=20']);
  TagDeviceInit(D, 'plc1');
  try
    OpenDevice(D, Sim.Pty);
    Added(D, 'N7:0[10]');
    Added(D, 'F8:0');
    Added(D, 'F8:1');
    Added(D, 'B3:0/0');
    Added(D, 'B3:1/15');
    Added(D, 'B3:2/8');
    Added(D, 'T4:0.ACC');
    Added(D, 'T4:0');
    Added(D, 'C5:0.PRE');
    Added(D, 'ST10:0');
    Added(D, 'L11:0[2]');
    Added(D, 'N7:11');
    TagDeviceStart(D);
    { N7 (0..11), F8, B3, T4, C5, ST10, L11 }
    AssertEquals('reads per scan', 7, TagDeviceReads(D));
    StepAll([@D], 5000, @AllRead, @D);
    AssertTrue('every tag read; last error: ' + D.LastError, AllRead(@D));
    AssertEquals('requests: one scan', 7, D.Requests);
    AssertEquals('state', 'ok', TagStateNames[D.State]);
    AssertEquals('N7:0 quality', 'good', TagQualityNames[D.Tags[0].Quality]);
    AssertEquals('N7:0[10]', 10, Length(D.Tags[0].Values));
    AssertEquals('N7:9', 90, D.Tags[0].Values[9]);
    AssertEquals('F8:0', 1.5, D.Tags[1].Values[0], 0);
    AssertEquals('F8:1', -2.25, D.Tags[2].Values[0], 0);
    AssertEquals('B3:0/0', 1, D.Tags[3].Values[0], 0);
    AssertEquals('B3:1/15', 1, D.Tags[4].Values[0], 0);
    AssertEquals('B3:2/8 ($00FF)', 0, D.Tags[5].Values[0], 0);
    AssertEquals('T4:0.ACC', 100, D.Tags[6].Values[0], 0);
    AssertEquals('T4:0 words', 3, Length(D.Tags[7].Values));
    AssertEquals('T4:0 control ($2000: DN)', $2000, D.Tags[7].Values[0], 0);
    AssertEquals('T4:0 PRE', 100, D.Tags[7].Values[1], 0);
    AssertEquals('C5:0.PRE', 10, D.Tags[8].Values[0], 0);
    AssertEquals('ST10:0', 'hello', D.Tags[9].Text);
    AssertEquals('L11:0', 100000, D.Tags[10].Values[0], 0);
    AssertEquals('L11:1', -2, D.Tags[10].Values[1], 0);
    AssertEquals('N7:11 (beyond the values given)', 0, D.Tags[11].Values[0], 0);
    AssertTrue('a UTC time stamp', Abs(D.Tags[0].TimeMs - TagUtcMs) < 10000);
    { every tag is a change once }
    Seen := '';
    while TagTakeChange(D, Tag) do
      Seen := Seen + D.Tags[Tag].Name + ' ';
    AssertEquals('changes', 12, Length(Seen) - Length(StringReplace(Seen, ' ', '', [rfReplaceAll])));
    AssertTrue('health reported', TagTakeHealth(D) = False);
  finally
    TagDeviceDone(D);
    Sim.Free;
  end;
end;

procedure TTestChnPcccTags.TestChangesOnlyAndDeadband;
var
  Sim: TSim;
  D: tPcccDevice;
  E: ShortString;
  Tag, Clock, Slow, Still: LongInt;
begin
  Sim := TSim.Create(['--quiet', '--timeout=20']);
  TagDeviceInit(D, 'plc1');
  try
    OpenDevice(D, Sim.Pty);
    AssertEquals(E, res_Ok, TagAdd(D, 'clock', 'S2:4', 100, 0, False, E));
    AssertEquals(E, res_Ok, TagAdd(D, 'slow', 'S2:4', 50, 100000, False, E));
    AssertEquals(E, res_Ok, TagAdd(D, 'still', 'N7:3', 100, 0, False, E));
    TagDeviceStart(D);
    Clock := 0;
    Slow := 0;
    Still := 0;
    StepAll([@D], 1000);
    while TagTakeChange(D, Tag) do
      case Tag of
        0: Inc(Clock);
        1: Inc(Slow);
        2: Inc(Still);
      end;
    StepAll([@D], 1000);
    while TagTakeChange(D, Tag) do
      case Tag of
        0: Inc(Clock);
        1: Inc(Slow);
        2: Inc(Still);
      end;
    { 2 s of a 100 ms scan: about 20 reads, each sees S2:4 moved by 10;
      taken twice, a change waiting is reported once per take }
    AssertTrue('S2:4 changes: ' + IntToStr(Clock), Clock >= 2);
    AssertEquals('S2:4 behind a deadband of 100000: only the first value', 1, Slow);
    AssertEquals('N7:3 does not change: once', 1, Still);
    { three reads: S2:4 at 100 and at 50 ms, N7:3 at 100 ms: 80 in 2 s }
    AssertEquals('reads per scan', 3, TagDeviceReads(D));
    AssertTrue('reads for 2 s: ' + IntToStr(D.Requests), (D.Requests >= 60) and (D.Requests <= 86));
    AssertEquals('no errors: ' + D.LastError, 0, D.Errors);
  finally
    TagDeviceDone(D);
    Sim.Free;
  end;
end;

function HasWrite(Data: Pointer): Boolean;
begin
  Result := Length(pPcccDevice(Data)^.Done) > 0;
end;

procedure TTestChnPcccTags.TestWriteComesBack;
var
  Sim: TSim;
  D: tPcccDevice;
  E: ShortString;
  Tag: LongInt;
  W: tTagWrite;
begin
  Sim := TSim.Create(['--quiet', '--timeout=20']);
  TagDeviceInit(D, 'plc1');
  try
    OpenDevice(D, Sim.Pty);
    AssertEquals(E, res_Ok, TagAdd(D, 'sp', 'N7:5', 60000, 0, True, E));
    AssertEquals(E, res_Ok, TagAdd(D, 'f', 'F8:9', 60000, 0, True, E));
    AssertEquals(E, res_Ok, TagAdd(D, 'b', 'B3:2/15', 60000, 0, True, E));
    TagDeviceStart(D);
    StepAll([@D], 5000, @AllRead, @D);
    while TagTakeChange(D, Tag) do ;
    AssertEquals('N7:5 before', 50, D.Tags[0].Values[0], 0);
    AssertFalse('2.5 to an integer', TagDeviceWrite(D, 0, 2.5, 7, E));
    AssertEquals('why', 'sp holds integers, not 2.5', E);
    AssertTrue(E, TagDeviceWrite(D, 0, 1234, 7, E));
    AssertTrue(E, TagDeviceWrite(D, 1, -0.5, 8, E));
    AssertTrue(E, TagDeviceWrite(D, 2, 1, 9, E));
    AssertTrue(E, TagDeviceWrite(D, 0, 99999, 10, E));   { the PLC's word cannot hold it }
    StepAll([@D], 5000, @HasWrite, @D);
    AssertTrue('first write done', TagTakeWrite(D, W));
    AssertEquals('its id', 7, W.Id);
    AssertEquals('confirmed: ' + W.Err, res_Ok, W.Res);
    StepAll([@D], 3000);
    AssertTrue('F8:9', TagTakeWrite(D, W));
    AssertEquals('F8:9 id', 8, W.Id);
    AssertEquals('F8:9 confirmed: ' + W.Err, res_Ok, W.Res);
    AssertTrue('B3:2/15', TagTakeWrite(D, W));
    AssertEquals('B3:2/15 confirmed: ' + W.Err, res_Ok, W.Res);
    AssertTrue('99999', TagTakeWrite(D, W));
    AssertEquals('99999 id', 10, W.Id);
    AssertEquals('99999 refused', res_PcccValue, W.Res);
    AssertTrue('says why: ' + W.Err, Pos('99999', W.Err) > 0);
    { the blocks were read again at once (the scan is 60 s): new values }
    AssertTrue('N7:5 changed', TagTakeChange(D, Tag));
    AssertEquals('N7:5 after', 1234, D.Tags[0].Values[0], 0);
    AssertEquals('F8:9 after', -0.5, D.Tags[1].Values[0], 0);
    AssertEquals('B3:2/15 after', 1, D.Tags[2].Values[0], 0);
  finally
    TagDeviceDone(D);
    Sim.Free;
  end;
end;

procedure TTestChnPcccTags.TestRefusedRead;
var
  Sim: TSim;
  D: tPcccDevice;
begin
  Sim := TSim.Create(['--quiet', '--timeout=20']);
  TagDeviceInit(D, 'plc1');
  try
    OpenDevice(D, Sim.Pty);
    Added(D, 'N7:0');
    Added(D, 'N40:0');    { no such file in df1sim's table }
    TagDeviceStart(D);
    StepAll([@D], 5000, @AllRead, @D);
    AssertEquals('N7:0', 'good', TagQualityNames[D.Tags[0].Quality]);
    AssertEquals('N40:0', 'refused', TagQualityNames[D.Tags[1].Quality]);
    AssertEquals('the device answered', 'ok', TagStateNames[D.State]);
    AssertEquals('an error counted', 1, D.Errors);
    AssertTrue('last error names the read: ' + D.LastError, Pos('N40:0[1]: ', D.LastError) = 1);
  finally
    TagDeviceDone(D);
    Sim.Free;
  end;
end;

{ A PLC-5 (df1sim --plc5): PLC-5 addresses, blocks read by word range,
  D words decoded from BCD, a write as the client's PLC-5 command. }
procedure TTestChnPcccTags.TestPlc5Device;
var
  Sim: TSim;
  D: tPcccDevice;
  E: ShortString;
  W: tTagWrite;
begin
  Sim := TSim.Create(['--plc5', '--quiet', '--timeout=20']);
  TagDeviceInit(D, 'plc5');
  try
    OpenDevice(D, Sim.Pty);
    TagDevicePlc5(D);
    Added(D, 'I:012/05');
    Added(D, 'D10:0[2]');
    Added(D, 'N7:0[3]');
    Added(D, 'T4:1.ACC');
    Added(D, 'F8:3');
    Added(D, 'ST9:0');
    AssertEquals(E, res_Ok, TagAdd(D, 'bcd', 'D10:3', 60000, 0, True, E));
    AssertEquals('an L file is no PLC-5 file', res_PcccAddress, TagAdd(D, '', 'L11:0', 500, 0, False, E));
    TagDeviceStart(D);
    StepAll([@D], 5000, @AllRead, @D);
    AssertTrue('every tag read; last error: ' + D.LastError, AllRead(@D));
    AssertEquals('I:012/05', D.Tags[0].Name);
    AssertEquals('I:012/05', 1, D.Tags[0].Values[0], 0);
    AssertEquals('D10:0 (BCD $1234)', 1234, D.Tags[1].Values[0], 0);
    AssertEquals('D10:1 (BCD $9999)', 9999, D.Tags[1].Values[1], 0);
    AssertEquals('N7:2', 20, D.Tags[2].Values[2], 0);
    AssertEquals('T4:1.ACC', 7, D.Tags[3].Values[0], 0);
    AssertEquals('F8:3', 1000000, D.Tags[4].Values[0], 0);
    AssertEquals('ST9:0', 'hello', D.Tags[5].Text);
    AssertTrue(E, TagDeviceWrite(D, 6, 4321, 1, E));
    StepAll([@D], 5000, @HasWrite, @D);
    AssertTrue('write done', TagTakeWrite(D, W));
    AssertEquals('confirmed: ' + W.Err, res_Ok, W.Res);
    StepAll([@D], 1000);
    AssertEquals('D10:3 read back', 4321, D.Tags[6].Values[0], 0);
  finally
    TagDeviceDone(D);
    Sim.Free;
  end;
end;

procedure TTestChnPcccTags.TestDeadDeviceDemotedOtherKeepsItsRate;
var
  Sim: TSim;
  Live, Dead: tPcccDevice;
  Pair: TPtyPair;
  Before, Reads, DeadReads: LongInt;
  T0: QWord;
  States: string;
begin
  Sim := TSim.Create(['--quiet', '--timeout=20']);
  Pair := TPtyPair.Create;      { nobody answers on its master side }
  TagDeviceInit(Live, 'live');
  TagDeviceInit(Dead, 'dead');
  try
    OpenDevice(Live, Sim.Pty);
    OpenDevice(Dead, Pair.SlavePath);
    Dead.Client.TimeoutMs := 100;
    Dead.DemoteAfter := 2;
    Dead.DemoteMs := 600;
    Added(Live, 'N7:0', 100);
    Added(Dead, 'N7:0', 100);
    Added(Dead, 'F8:0', 100);
    TagDeviceStart(Live);
    TagDeviceStart(Dead);
    { first failure: down, bad; the second: demoted }
    States := '';
    T0 := ChMsTick;
    while (Dead.State <> tdDemoted) and (ChMsTick - T0 < 10000) do
    begin
      StepAll([@Live, @Dead], 20);
      if TagTakeHealth(Dead) then
        States := States + TagStateNames[Dead.State] + ' ';
    end;
    AssertEquals('down, then demoted', 'down demoted ', States);
    AssertEquals('tags bad', 'bad', TagQualityNames[Dead.Tags[1].Quality]);
    AssertTrue('last error: ' + Dead.LastError, Pos('no ACK after', Dead.LastError) > 0);
    { 3 s: the live device keeps its 100 ms rate, the dead one is tried
      600 ms after its last try failed (each read: its tries of 100 ms) }
    Before := Live.Requests;
    DeadReads := Dead.Requests;
    T0 := ChMsTick;
    StepAll([@Live, @Dead], 3000);
    Reads := Live.Requests - Before;
    AssertTrue(Format('live: %d reads in %d ms at a 100 ms scan', [Reads, ChMsTick - T0]),
      (Reads >= 24) and (Reads <= 32));
    DeadReads := Dead.Requests - DeadReads;
    AssertTrue(Format('dead: %d reads in 3 s demoted', [DeadReads]), (DeadReads >= 2) and (DeadReads <= 5));
    AssertEquals('still demoted', 'demoted', TagStateNames[Dead.State]);
    AssertTrue('retries counted: ' + IntToStr(Dead.Retries), Dead.Retries >= DeadReads);
    AssertEquals('live errors', 0, Live.Errors);
  finally
    TagDeviceDone(Live);
    TagDeviceDone(Dead);
    Pair.Free;
    Sim.Free;
  end;
end;

{ Two blocks on one 19200 Bd line (an in-memory line that takes each
  character's time, an SLC station of tools/lib on its other end): the
  122-word read keeps the line about 145 ms, the 100-word one about
  120 ms, so at a 400 ms scan the line is busy two thirds of the time and
  the second block always waits behind the first. Each block is still
  read every 400 ms: its next read is due a scan after its last one was
  due, not after it ended (that would add the read's own time and the
  wait, 120..270 ms, to every cycle). }
type
  tBusyLine = record
    Dev: pPcccDevice;
    Station: tDF1Station;
    LastDue: array[0..1] of QWord;
    First, Last: array[0..1] of QWord;     { ChMsTick: first and last read seen done }
    Reads: array[0..1] of LongInt;
  end;
  pBusyLine = ^tBusyLine;

{ Serve the station; note each block's reads as they end (its Due moves on). }
function BusyStep(Data: Pointer): Boolean;
var
  K: LongInt;
begin
  with pBusyLine(Data)^ do
  begin
    DF1StationStep(Station);
    for K := 0 to 1 do
      if Dev^.Blocks[K].Due <> LastDue[K] then
      begin
        LastDue[K] := Dev^.Blocks[K].Due;
        if Reads[K] = 0 then
          First[K] := ChMsTick;
        Last[K] := ChMsTick;
        Inc(Reads[K]);
      end;
  end;
  Result := False;
end;

procedure TTestChnPcccTags.TestBlocksKeepTheirScanOnABusyLine;
const
  Scan = 400;
var
  D: tPcccDevice;
  B: tBusyLine;
  Table: tSlcTable;
  StChn: pChnVirt;
  ErrLine, K: LongInt;
  Err: AnsiString;
  Period: Double;
begin
  AssertTrue('table', SlcLoadConfig(Table, 'N7 256', ErrLine, Err));
  StChn := ChnCollection^.ChNewInit('DF1');
  TagDeviceInit(D, 'busy');
  try
    StChn^.ChSetParam('NOD=1 DNO=0 MAS=SLAVE FHD=FULL CRC=ON NAM=LOOP PAIR=TAGSBUSY END=2 BD=19200');
    StChn^.ChOpen;
    StChn^.ChConnect;
    AssertEquals('station: ' + StChn^.ChErrorText, res_Ok, StChn^.ChResult);
    FillChar(B, SizeOf(B), 0);
    B.Dev := @D;
    SlcStationInit(B.Station, StChn, @Table);
    if PcccOpen(D.Client, 'NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=LOOP PAIR=TAGSBUSY END=1 BD=19200') <> res_Ok then
      raise Exception.Create('open: ' + D.Client.Err);
    Added(D, 'N7:0[122]', Scan);
    Added(D, 'N7:122[100]', Scan);
    TagDeviceStart(D);
    AssertEquals('two reads', 2, TagDeviceReads(D));
    for K := 0 to 1 do
      B.LastDue[K] := D.Blocks[K].Due;
    StepAll([@D], 4500, @BusyStep, @B);
    AssertEquals('no read failed: ' + D.LastError, 0, D.Errors);
    for K := 0 to 1 do
    begin
      AssertTrue(Format('block %d: %d reads', [K, B.Reads[K]]), B.Reads[K] >= 6);
      Period := (B.Last[K] - B.First[K]) / (B.Reads[K] - 1);
      { generous for a loaded machine: a late round is caught up with, it
        does not move the schedule }
      AssertTrue(Format('block %d read every %.0f ms at a %d ms scan', [K, Period, Scan]),
        (Period > Scan - 30) and (Period < Scan + 50));
    end;
  finally
    TagDeviceDone(D);
    Dispose(StChn, Done);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestChnPcccTags);
end.
