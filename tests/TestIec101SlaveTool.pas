{ Tests of examples/iec101slave as built (build/bin) and of its points
  file reader (tools/lib/Iec101Points): the command-line conventions, the
  refusal of a bad points line naming the line and the token, and a run
  on a pty against a ChnIec101Master in the test (interrogation, command,
  clock sync, unknown IOA), its JSON lines checked against the format of
  docs/ChnIec101.md written out by hand. Unix only (ptys, SIGINT). }
unit TestIec101SlaveTool;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, BaseUnix, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnPty,
  ChnFT1_2, ChnIec101Asdu, ChnIec101Slave, ChnIec101Master, Iec101Points, BinSupport,
  TestTempDir;

type
  TTestIec101SlaveTool = class(TTestCase)
  private
    FDir: string;
    procedure InOrder(const Lines: array of string);
    function Run(const Args: array of string; out Output: string): Integer;
    function Line(const Text: string; out Err: AnsiString): Boolean;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    Objects: TStringList;
    S: tIecSlaveStation;
  published
    procedure TestPointLines;
    procedure TestPointLineRefusals;
    procedure TestUsageVersionAndErrors;
    procedure TestBadPointsFileOpensNothing;
    procedure TestAnswersOurMasterOnAPty;
    procedure TestPcapOfEveryTypeDissectedByTshark;
  end;

implementation

procedure TTestIec101SlaveTool.SetUp;
begin
  FDir := MakeTempDir('iec101slave');
  Objects := TStringList.Create;
  FillChar(S, SizeOf(S), 0);
  S.Params := IecDefaultParams;
  S.Ca := 1;
end;

procedure TTestIec101SlaveTool.TearDown;
begin
  Objects.Free;
  RemoveTempDir(FDir);
end;

function TTestIec101SlaveTool.Run(const Args: array of string; out Output: string): Integer;
begin
  AssertTrue(BinPath('iec101slave') + ' missing (make examples)', FileExists(BinPath('iec101slave')));
  Result := RunBin('iec101slave', Args, 10000, Output);
end;

function TTestIec101SlaveTool.Line(const Text: string; out Err: AnsiString): Boolean;
begin
  Result := IecPointLine(S, Text, Err);
end;

procedure TTestIec101SlaveTool.TestPointLines;
var
  E: AnsiString;
  P: pIecPoint;
begin
  AssertTrue(E, Line('100 M_ME_NB_1 -1', E));
  AssertTrue(E, Line('104 M_SP_NA_1 1', E));
  AssertTrue(E, Line('500 M_BO_NA_1 0xAAAA', E));
  AssertTrue(E, Line('700 M_ME_TF_1 12.5', E));
  AssertTrue(E, Line('  # a comment', E));
  AssertTrue(E, Line('', E));
  AssertTrue(E, Line(#9'6'#9'M_ST_TA_1  17t  SB+BL  # transient, substituted, blocked', E));
  AssertTrue(E, Line('9 m_me_na_1 -0.5 $80', E));
  AssertTrue(E, Line('15 M_IT_NA_1 -2147483648 CY+CA+IV', E));
  AssertTrue(E, Line('33 M_BO_TB_1 4294967295', E));
  AssertTrue(E, Line('5000 C_SC_NA_1 off', E));
  AssertTrue(E, Line('41 M_SP_NA_1 1 group=2', E));
  AssertTrue(E, Line('42 M_IT_NA_1 7 GROUP=4 CY', E));
  AssertEquals(11, S.PointCount);
  AssertEquals('no group', 0, S.Points[0].Group);
  AssertEquals(2, S.Points[9].Group);
  AssertEquals(4, S.Points[10].Group);
  AssertEquals('CY', $20, S.Points[10].Obj.Quality);
  P := @S.Points[0];
  AssertEquals(M_ME_NB_1, P^.Ti);
  AssertEquals(100, P^.Obj.Ioa);
  AssertEquals(-1, P^.Obj.Int);
  AssertEquals(1, S.Points[1].Obj.Int);
  AssertEquals($AAAA, S.Points[2].Obj.Bits);
  AssertEquals(12.5, S.Points[3].Obj.Number, 0);
  AssertTrue('time of the change', S.Points[3].Obj.Time.Year > 0);
  AssertEquals(17, S.Points[4].Obj.Int);
  AssertTrue(S.Points[4].Obj.Transient);
  AssertEquals(Q_Substituted or Q_Blocked, S.Points[4].Obj.Quality);
  AssertEquals(-0.5, S.Points[5].Obj.Number, 0);
  AssertEquals(Q_Invalid, S.Points[5].Obj.Quality);
  AssertEquals(Low(LongInt), S.Points[6].Obj.Int);
  AssertEquals($E0, S.Points[6].Obj.Quality);
  AssertEquals(High(LongWord), S.Points[7].Obj.Bits);
  AssertEquals(C_SC_NA_1, S.Points[8].Ti);
end;

procedure TTestIec101SlaveTool.TestPointLineRefusals;
var
  E, Err: AnsiString;
begin
  AssertFalse(Line('100 M_XX_NA_1 1', E));
  AssertEquals('unknown type (M_XX_NA_1)', E);
  AssertFalse(Line('100 M_ME_NB_1 40000', E));
  AssertEquals('no value for M_ME_NB_1 (40000)', E);
  AssertFalse(Line('100 M_ME_NA_1 1.0', E));
  AssertEquals('no value for M_ME_NA_1 (1.0)', E);
  AssertFalse(Line('100 M_SP_NA_1 2', E));
  AssertFalse(Line('100 M_BO_NA_1 0x1FFFFFFFF', E));
  AssertFalse(Line('100 M_ST_NA_1 64', E));
  AssertFalse(Line('x100 M_SP_NA_1 1', E));
  AssertTrue(E, Pos('(x100)', E) > 0);
  AssertFalse(Line('100 M_SP_NA_1', E));
  AssertTrue(E, Pos('IOA TYPE VALUE [QUALITY] [GROUP=N] expected', E) = 1);
  AssertFalse(Line('100 M_SP_NA_1 1 IV extra', E));
  AssertEquals('too many fields (extra)', E);
  AssertFalse(Line('100 M_SP_NA_1 1 IV GROUP=1 extra', E));
  AssertEquals('too many fields (extra)', E);
  AssertFalse(Line('100 M_SP_NA_1 1 GROUP=17', E));
  AssertEquals('GROUP= takes an interrogation group 1..16 (GROUP=17)', E);
  AssertFalse(Line('100 M_SP_NA_1 1 GROUP=', E));
  AssertEquals('GROUP= takes an interrogation group 1..16 (GROUP=)', E);
  AssertFalse(Line('100 M_SP_NA_1 1 GROUP=1 GROUP=2', E));
  AssertEquals('GROUP= twice (GROUP=2)', E);
  AssertFalse(Line('100 M_IT_NA_1 1 GROUP=5', E));
  AssertTrue(E, Pos('point 100: group 5', E) = 1);
  AssertFalse(Line('100 M_SP_NA_1 1 XX', E));
  AssertTrue(E, Pos('(XX)', E) > 0);
  AssertFalse(Line('100 M_SP_NA_1 1 256', E));
  AssertFalse(Line('100 C_IC_NA_1 20', E));
  AssertTrue(E, Pos('unknown type', E) + Pos('no value', E) + Pos('type 100', E) > 0);
  AssertTrue(Line('100 M_SP_NA_1 1', E));
  AssertFalse(Line('100 M_DP_NA_1 1', E));
  AssertTrue(E, Pos('point 100: IOA twice', E) = 1);
  AssertFalse(IecLoadPoints(S, 'rtu.txt', '# table'#10'101 M_SP_NA_1 0'#10'102 M_SP_NA_1 on?'#10, Err));
  AssertEquals('rtu.txt line 3: no value for M_SP_NA_1 (on?)', Err);
end;

procedure TTestIec101SlaveTool.TestUsageVersionAndErrors;
var
  Output: string;
  Params: string;
begin
  Params := 'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=' + FDir + '/none';
  AssertEquals(0, Run(['--help'], Output));
  AssertTrue(Output, Pos('Usage: iec101slave', Output) = 1);
  AssertEquals(0, Run(['-h'], Output));
  AssertTrue(Output, Pos('--points FILE', Output) > 0);
  AssertEquals(0, Run(['--version'], Output));
  AssertEquals('iec101slave (Chn) 1.0.0' + LineEnding, Output);
  { no arguments: the usage on stderr only, exit 2 }
  AssertEquals(2, RunExe('/bin/sh', ['-c', BinShellWord('iec101slave') + ' 2>/dev/null'], 10000, Output));
  AssertEquals('nothing on stdout', '', Output);
  AssertEquals(2, RunExe('/bin/sh', ['-c', BinShellWord('iec101slave') + ' 2>&1 >/dev/null'], 10000, Output));
  AssertTrue(Output, Pos('Usage: iec101slave', Output) = 1);
  AssertEquals(2, Run(['--bogus', Params], Output));
  AssertEquals('iec101slave: unknown option (--bogus)' + LineEnding, Output);
  AssertEquals(2, Run(['--seconds', 'x', Params], Output));
  AssertEquals('iec101slave: --seconds wants a whole number 1..1000000 (--seconds x)' + LineEnding, Output);
  AssertEquals(2, Run(['--seconds=0', Params], Output));
  AssertTrue(Output, Pos('(--seconds=0)', Output) > 0);
  AssertEquals(2, Run([Params, '--ca'], Output));
  AssertEquals('iec101slave: --ca wants a value, N (--ca)' + LineEnding, Output);
  AssertEquals(2, Run(['--ca-size', '1', '--ca=256', Params], Output));
  AssertTrue(Output, Pos('(256)', Output) > 0);
  AssertEquals(2, Run(['--json=yes', Params], Output));
  AssertEquals('iec101slave: --json takes no value (--json=yes)' + LineEnding, Output);
  AssertEquals(2, Run(['--json'], Output));
  AssertTrue(Output, Pos('no parameter string', Output) > 0);
  AssertEquals(2, Run(['--points', FDir + '/missing.txt', Params], Output));
  AssertEquals('iec101slave: cannot read the points file (' + FDir + '/missing.txt)' + LineEnding, Output);
  { the parameter string: a bad token named, exit 2; a device that is not there, exit 1 }
  AssertEquals(2, Run(['NAM=FT1_2 MS=ON MAS=SLAVE BOGUS=1 NAM=COM DEV=/dev/null'], Output));
  AssertTrue(Output, Pos('(BOGUS=1)', Output) > 0);
  AssertEquals(1, Run(['--seconds', '1', Params], Output));
  AssertTrue(Output, Pos('iec101slave: device cannot be opened', Output) = 1);
end;

procedure TTestIec101SlaveTool.TestBadPointsFileOpensNothing;
var
  Output: string;
  Lst: TStringList;
begin
  Lst := TStringList.Create;
  try
    Lst.Add('# RTU 7');
    Lst.Add('100 M_ME_NB_1 -1');
    Lst.Add('101 M_ME_NX_1 5');
    Lst.SaveToFile(FDir + '/bad.txt');
  finally
    Lst.Free;
  end;
  { a device that would fail: the table is refused before it is tried }
  AssertEquals(2, Run(['--points', FDir + '/bad.txt',
    'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=' + FDir + '/none'], Output));
  AssertEquals('iec101slave: ' + FDir + '/bad.txt line 3: unknown type (M_ME_NX_1)' + LineEnding, Output);
end;

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIec101SlaveTool(Data).Objects.Add(Format('%s %d %d int=%d bits=%d q=%d',
    [IecTypeName(H.Ti), H.Cot, O.Ioa, O.Int, Int64(O.Bits), O.Quality]));
end;

{ Each line is among the objects, after the one before it. }
procedure TTestIec101SlaveTool.InOrder(const Lines: array of string);
var
  I, At, Prev: Integer;
begin
  Prev := -1;
  for I := 0 to High(Lines) do
  begin
    At := Prev + 1;
    while (At < Objects.Count) and (Objects[At] <> Lines[I]) do
      Inc(At);
    AssertTrue(Lines[I] + ' after the line before it in ' + Objects.CommaText, At < Objects.Count);
    Prev := At;
  end;
end;

procedure TTestIec101SlaveTool.TestAnswersOurMasterOnAPty;
var
  Chn: pChnVirt;
  Err, Out, Errs: string;
  M: tIecMaster;
  P: TProcess;
  Lst: TStringList;
  O: tIecObject;
  I: Integer;
  Deadline: QWord;
begin
  AssertTrue(FileExists(BinPath('iec101slave')));
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam('NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DRV=PTY');
  Chn^.ChOpen;
  Chn^.ChConnect;
  AssertEquals(Chn^.ChResultStr(Chn^.ChResult), res_Ok, Chn^.ChResult);
  P := TProcess.Create(nil);
  Lst := TStringList.Create;
  try
    Lst.Add('100 M_ME_NB_1 -1');
    Lst.Add('104 M_SP_NA_1 1 IV');
    Lst.Add('500 M_BO_NA_1 0xAAAA');
    Lst.Add('600 M_IT_NA_1 77');
    Lst.Add('5000 C_SC_NA_1 0');
    Lst.SaveToFile(FDir + '/rtu.txt');
    BinExecutable(P, BinPath('iec101slave'));
    P.Parameters.Add('--json');
    P.Parameters.Add('--points');
    P.Parameters.Add(FDir + '/rtu.txt');
    P.Parameters.Add('--seconds=20');
    P.Parameters.Add('NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DEV=' + PtyLastSlave + ' BD=9600 PAR=E');
    P.Options := [poUsePipes];
    P.Execute;
    AssertEquals(res_Ok, IecMasterInit(M, Chn, IecDefaultParams));
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
    M.OnObject := @OnObj;
    M.Data := Self;
    M.CycleMs := 20;
    AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 1, 1, Qoi_Station));
    AssertEquals(M.Cmd.Err, res_Ok, IecCounterInterrogation(M, 1, 1, Qcc_General));
    O := IecObject(5000);
    O.Int := 1;
    AssertEquals(M.Cmd.Err, res_Ok, IecCommand(M, 1, 1, C_SC_NA_1, O, False));
    O.Ioa := 5001;
    AssertEquals(M.Cmd.Err, res_IecUnknownIoa, IecCommand(M, 1, 1, C_SC_NA_1, O, False));
    AssertEquals(M.Cmd.Err, res_Ok, IecClockSync(M, 1, 1, IecTimeFromDateTime(Now), False));
    AssertEquals(M.Cmd.Err, res_Ok, IecRead(M, 1, 1, 500));
    { the objects our master got, as written out from the points file }
    { first its end of initialisation (COT 4, COI 0: started), after which
      the master interrogates it (its own interrogation, or the program's
      when that was under way: then one more follows) }
    AssertEquals('M_EI_NA_1 4 0 int=0 bits=0 q=0', Objects[0]);
    InOrder(['C_IC_NA_1 7 0 int=20 bits=0 q=0', 'M_ME_NB_1 20 100 int=-1 bits=0 q=0',
      'M_SP_NA_1 20 104 int=1 bits=0 q=128', 'M_BO_NA_1 20 500 int=0 bits=43690 q=0',
      'C_IC_NA_1 10 0 int=20 bits=0 q=0', 'C_CI_NA_1 7 0 int=5 bits=0 q=0',
      'M_IT_NA_1 37 600 int=77 bits=0 q=0', 'C_CI_NA_1 10 0 int=5 bits=0 q=0']);
    AssertEquals('M_BO_NA_1 5 500 int=0 bits=43690 q=0', Objects[Objects.Count - 1]);
    { SIGINT ends it cleanly }
    FpKill(P.ProcessID, SIGINT);
    Out := '';
    Errs := '';
    Deadline := ChMsTick + 5000;
    while (P.Running or (P.Output.NumBytesAvailable > 0)) and (ChMsTick < Deadline) do
    begin
      Out := Out + PipeText(P.Output);
      Errs := Errs + PipeText(P.Stderr);
      Sleep(10);
    end;
    Errs := Errs + PipeText(P.Stderr);
    AssertFalse('ended', P.Running);
    AssertEquals(Errs, 0, P.ExitCode);
    Lst.Text := Out;
    for I := 0 to Lst.Count - 1 do
      AssertTrue('only JSON on stdout: ' + Lst[I], (Copy(Lst[I], 1, 1) = '{') and
        (Copy(Lst[I], Length(Lst[I]), 1) = '}'));
    { the keys docs/ChnIec101.md gives, written out by hand }
    AssertTrue(Out, Lst.IndexOf('{"type":"C_SC_NA_1","ti":45,"cot":6,"negative":false,"test":false,'
      + '"oa":0,"ca":1,"ioa":5000,"value":true,"select":false,"quality":0}') >= 0);
    AssertTrue(Out, Lst.IndexOf('{"type":"C_SC_NA_1","ti":45,"cot":47,"negative":true,"test":false,'
      + '"oa":0,"ca":1,"ioa":5001,"value":true,"select":false,"quality":0}') >= 0);
    AssertTrue(Out, Lst.IndexOf('{"type":"M_SP_NA_1","ti":1,"cot":20,"negative":false,"test":false,'
      + '"oa":0,"ca":1,"ioa":104,"value":true,"quality":128}') >= 0);
    AssertTrue(Out, Lst.IndexOf('{"type":"M_IT_NA_1","ti":15,"cot":37,"negative":false,"test":false,'
      + '"oa":0,"ca":1,"ioa":600,"value":77,"seq":0,"quality":0}') >= 0);
    AssertTrue(Out, Pos('{"type":"C_CS_NA_1","ti":103,"cot":6,', Out) > 0);
    AssertTrue(Errs, Pos('1 commands (0 refused), 1 clock syncs', Errs) > 0);
    AssertTrue(Errs, Pos('0 malformed', Errs) > 0);
  finally
    StopProcess(P);
    Lst.Free;
    Dispose(Chn, Done);
  end;
end;

procedure StepSlave(Data: Pointer);
begin
  IecSlaveStep(TTestIec101SlaveTool(Data).S);
end;

{ Our master (with NAM=TRC MOD=PCAP under it) and our slave with every
  monitoring type (tests/data/iec101-alltypes.points) on a pty pair, in
  one thread; then tshark reads the pcap as IEC 60870-5-101 with the
  sizes COT 2, CA 2, IOA 3: no malformed frame, every ASDU there. }
procedure TTestIec101SlaveTool.TestPcapOfEveryTypeDissectedByTshark;
var
  MChn, SChn: pChnVirt;
  M: tIecMaster;
  E: AnsiString;
  Es: ShortString;
  Tshark, Output: string;
  Code: Integer;
begin
  Tshark := ExeSearch('tshark', GetEnvironmentVariable('PATH'));
  if Tshark = '' then
    Ignore('tshark is not installed (Debian package tshark): the pcap is not checked by Wireshark');
  MChn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  MChn^.ChSetParam('NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=TRC FILE=' + FDir +
    '/live.pcap MOD=PCAP NAM=COM DRV=PTY');
  MChn^.ChOpen;
  MChn^.ChConnect;
  AssertEquals(res_Ok, MChn^.ChResult);
  SChn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  try
    SChn^.ChSetParam('NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DEV=' + PtyLastSlave + ' PAR=E');
    SChn^.ChOpen;
    SChn^.ChConnect;
    AssertEquals(res_Ok, SChn^.ChResult);
    AssertEquals(res_Ok, IecSlaveInit(S, SChn, IecDefaultParams, 1, Es));
    AssertTrue(E, IecLoadPoints(S, 'alltypes', ReadFileText('tests/data/iec101-alltypes.points'), E));
    AssertEquals(res_Ok, IecMasterInit(M, MChn, IecDefaultParams));
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
    M.Idle := @StepSlave;
    M.IdleData := Self;
    M.OnObject := @OnObj;
    M.Data := Self;
    M.CycleMs := 1;
    AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 1, 1, Qoi_Station));
    AssertEquals(M.Cmd.Err, res_Ok, IecCounterInterrogation(M, 1, 1, Qcc_General));
    AssertEquals('29 points, 3 counters, 4 confirmations', 36, Objects.Count);
  finally
    Dispose(MChn, Done);
    Dispose(SChn, Done);
  end;
  Code := RunExe(Tshark, ['-r', FDir + '/live.pcap', '-d', 'rtacser.data,iec60870_101',
    '-o', 'iec60870_101.cot_len:2 octet', '-o', 'iec60870_101.asdu_addr_len:2 octet',
    '-o', 'iec60870_101.asdu_ioa_len:3 octet',
    '-Y', 'data or _ws.malformed or _ws.expert.severity >= warning'], 30000, Output);
  AssertEquals(Output, 0, Code);
  AssertEquals('no undissected or malformed frame: ' + Output, 0, Pos('IEC 60870', Output) + Pos('RTAC', Output));
  Code := RunExe(Tshark, ['-r', FDir + '/live.pcap', '-d', 'rtacser.data,iec60870_101',
    '-o', 'iec60870_101.cot_len:2 octet', '-o', 'iec60870_101.asdu_addr_len:2 octet',
    '-o', 'iec60870_101.asdu_ioa_len:3 octet', '-Y', 'iec60870_asdu'], 30000, Output);
  AssertEquals(Output, 0, Code);
  AssertTrue(Output, Pos('M_SP_NA_1 Inrogen IOA=1', Output) > 0);
  AssertTrue(Output, Pos('M_EP_TF_1 Inrogen IOA=40', Output) > 0);
  AssertTrue(Output, Pos('M_IT_TB_1 Reqcogen IOA=37', Output) > 0);
  AssertTrue(Output, Pos('C_CI_NA_1 ActTerm IOA=0', Output) > 0);
end;

initialization
  RegisterTest(TTestIec101SlaveTool);
end.
