{ Tests of examples/iec101master as built (build/bin), run through
  TProcess against a slave in the test (tests/support/Iec101Sim: a
  tFT12Station on NAM=COM DRV=PTY, the program opens the pty's other
  side). The JSON lines expected are written out from the format of
  docs/ChnIec101.md for the octets the slave sends. Unix only
  (ptys). }
unit TestIec101Examples;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnPty,
  ChnFT1_2, ChnWait, BinSupport, Iec101Sim, TestTempDir;

type
  TTestIec101Examples = class(TTestCase)
  private
    FSim: TSim;
    FOut, FErr: string;
    FExe, FHeapLog: string;   { the program run; heaptrc's report there when set }
    function Run(const Args: array of string; Serve: Boolean = True): Integer;
    function MasterParams: string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestUsageAndBadArguments;
    procedure TestInterrogationAndCommandAsJson;
    procedure TestGroupInterrogations;
    procedure TestReadableLinesAndSelect;
    procedure TestNegativeAndUnknownAnswers;
    procedure TestSlaveThatDoesNotAnswer;
    procedure TestBalancedLine;
    procedure TestSeveralSlavesOneDead;
    procedure TestBalancedWrongAddressNamed;
    procedure TestNothingLeftAtExit;
  end;

implementation

procedure TTestIec101Examples.SetUp;
begin
  FSim := TSim.Create('NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=5 NAM=COM DRV=PTY', False);
  FOut := '';
  FErr := '';
  FExe := BinPath('iec101master');
  FHeapLog := '';
end;

procedure TTestIec101Examples.TearDown;
begin
  FreeAndNil(FSim);
end;

function TTestIec101Examples.MasterParams: string;
begin
  Result := 'NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=5 NAM=COM DEV=' + PtyLastSlave + ' BD=9600 PAR=E';
end;

{ Run the program to its end (10 s at most), the slave served meanwhile
  (Serve) with the program-wide wait between steps. }
function TTestIec101Examples.Run(const Args: array of string; Serve: Boolean): Integer;
var
  P: TProcess;
  I: Integer;
  Deadline: QWord;

  procedure Take;
  begin
    FOut := FOut + PipeText(P.Output);
    FErr := FErr + PipeText(P.Stderr);
  end;

begin
  AssertTrue(FExe + ' missing (make examples)', FileExists(FExe));
  P := TProcess.Create(nil);
  try
    BinExecutable(P, FExe);
    if FHeapLog <> '' then
    begin
      HeapLogTo(P, FHeapLog);
      DeleteFile(FHeapLog);
    end;
    for I := 0 to High(Args) do
      P.Parameters.Add(Args[I]);
    P.Options := [poUsePipes];
    P.Execute;
    Deadline := ChMsTick + 10000;
    repeat
      if Serve then
      begin
        if not FSim.Step then
          ChnWaitAny(5);
      end
      else
        ChnWaitAny(5);
      Take;
    until not P.Running or (ChMsTick > Deadline);
    if P.Running then
    begin
      P.Terminate(255);
      Fail('did not end in 10 s: ' + FOut + FErr);
    end;
    Take;
    Result := P.ExitCode;
  finally
    P.Free;
  end;
end;

procedure TTestIec101Examples.TestUsageAndBadArguments;
begin
  AssertEquals('no arguments', 2, Run([], False));
  AssertEquals('nothing on stdout', '', FOut);
  AssertTrue(FErr, Pos('Usage: iec101master', FErr) = 1);
  FErr := '';
  AssertEquals(0, Run(['--help'], False));
  AssertTrue(FOut, Pos('setpoint-float IOA=X', FOut) > 0);
  FOut := '';
  AssertEquals(0, Run(['--version'], False));
  AssertEquals('iec101master (Chn) 1.0.0' + LineEnding, FOut);
  FOut := '';
  AssertEquals(2, Run(['--ioa-size', '2', MasterParams, 'sc', '70000=1'], False));
  AssertEquals('iec101master: IOA 70000 too large for 2 octet(s) (70000=1)' + LineEnding, FErr);
  FErr := '';
  AssertEquals(2, Run([MasterParams, 'dc', '5000=3'], False));
  AssertEquals('iec101master: dc wants IOA=1|2 (1 off, 2 on) (dc 5000=3)' + LineEnding, FErr);
  FErr := '';
  AssertEquals(2, Run([MasterParams, 'gi', 'gi-group', '17'], False));
  AssertEquals('iec101master: gi-group wants a group 1..16 (17)' + LineEnding, FErr);
  FErr := '';
  AssertEquals(2, Run([MasterParams, 'ci-group', '5'], False));
  AssertEquals('iec101master: ci-group wants a counter group 1..4 (5)' + LineEnding, FErr);
  FErr := '';
  AssertEquals(2, Run([MasterParams, 'gi-group'], False));
  AssertTrue(FErr, Pos('gi-group wants a group', FErr) > 0);
  FErr := '';
  AssertEquals(2, Run(['--cot-size=3', MasterParams, 'gi'], False));
  AssertTrue(FErr, Pos('iec101master: --cot-size wants a whole number 1..2 (--cot-size=3)', FErr) > 0);
  FErr := '';
  AssertEquals(2, Run(['--jsn', MasterParams, 'gi'], False));
  AssertTrue(FErr, Pos('unknown option (--jsn)', FErr) > 0);
  FErr := '';
  AssertEquals(2, Run([MasterParams + ' XYZ=1', 'gi'], False));
  AssertTrue(FErr, Pos('bad parameter string', FErr) > 0);
  AssertTrue(FErr, Pos('(XYZ=1)', FErr) > 0);
  AssertEquals('the slave heard nothing', 0, FSim.Got.Count);
end;

procedure TTestIec101Examples.TestInterrogationAndCommandAsJson;
const
  Head = '{"type":"%s","ti":%d,"cot":%d,"negative":false,"test":false,"oa":0,"ca":1,"ioa":%d,"value":%s,"quality":%d%s}';
var
  L: TStringList;
begin
  AssertEquals(FErr, 0, Run(['--json', '--timeout=200', MasterParams, 'gi', 'sc', '5000=1', 'poll', '1']));
  L := TStringList.Create;
  try
    L.Text := FOut;
    AssertEquals(FOut, 12, L.Count);
    AssertEquals(Format(Head, ['C_IC_NA_1', 100, 6, 0, '20', 0, '']), L[0]);
    AssertEquals(Format(Head, ['C_IC_NA_1', 100, 7, 0, '20', 0, '']), L[1]);
    AssertEquals(Format(Head, ['M_ME_NB_1', 11, 20, 100, '-1', 0, '']), L[2]);
    AssertEquals(Format(Head, ['M_ME_NB_1', 11, 20, 101, '23', 0, '']), L[3]);
    AssertEquals(Format(Head, ['M_ME_NB_1', 11, 20, 102, '2300', 0, '']), L[4]);
    AssertEquals(Format(Head, ['M_SP_NA_1', 1, 20, 104, 'true', 0, '']), L[5]);
    AssertEquals(Format(Head, ['M_SP_NA_1', 1, 20, 105, 'false', 0, '']), L[6]);
    AssertEquals(Format(Head, ['M_SP_TB_1', 30, 20, 300, 'true', 0, ',"time":"2026-12-01T22:15:30.250"']), L[7]);
    AssertEquals(Format(Head, ['C_IC_NA_1', 100, 10, 0, '20', 0, '']), L[8]);
    AssertEquals(Format(Head, ['C_SC_NA_1', 45, 6, 5000, 'true,"select":false', 0, '']), L[9]);
    AssertEquals(Format(Head, ['C_SC_NA_1', 45, 7, 5000, 'true,"select":false', 0, '']), L[10]);
    AssertEquals(Format(Head, ['C_SC_NA_1', 45, 10, 5000, 'true,"select":false', 0, '']), L[11]);
  finally
    L.Free;
  end;
  AssertEquals('nothing on stderr with --json', '', FErr);
  AssertEquals('64 01 06 00 01 00 00 00 00 14', FSim.Got[0]);
  AssertEquals('2D 01 06 00 01 00 88 13 00 01', FSim.Got[1]);
end;

{ gi-group N sends QOI 20+N, ci-group N the QCC with RQT N (freeze 0). }
procedure TTestIec101Examples.TestGroupInterrogations;
begin
  AssertEquals(FErr, 0, Run(['--timeout=200', MasterParams, 'gi-group', '2', 'ci-group', '3', 'gi']));
  AssertEquals(3, FSim.Got.Count);
  AssertEquals('QOI 22', '64 01 06 00 01 00 00 00 00 16', FSim.Got[0]);
  AssertEquals('RQT 3', '65 01 06 00 01 00 00 00 00 03', FSim.Got[1]);
  AssertEquals('QOI 20', '64 01 06 00 01 00 00 00 00 14', FSim.Got[2]);
end;

procedure TTestIec101Examples.TestReadableLinesAndSelect;
begin
  AssertEquals(FErr, 0, Run(['--select', '--timeout', '200', MasterParams, 'sc', '5000=0', 'read', '100',
    'setpoint-scaled', '5000=-7', 'clock', 'test', 'ci']));
  AssertTrue(FOut, Pos('-> C_SC_NA_1 ACTIVATION CA 1 IOA 5000 = off select' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('<- C_SC_NA_1 ACTIVATION_CON CA 1 IOA 5000 = off select' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('-> C_SC_NA_1 ACTIVATION CA 1 IOA 5000 = off execute' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('<- M_ME_NB_1 REQUEST CA 1 IOA 100 = -1' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('-> C_SE_NB_1 ACTIVATION CA 1 IOA 5000 = -7 select', FOut) > 0);
  AssertTrue(FOut, Pos('<- C_CS_NA_1 ACTIVATION_CON CA 1 IOA 0 ', FOut) > 0);
  AssertTrue(FOut, Pos('<- C_TS_NA_1 ACTIVATION_CON CA 1 IOA 0 = 0x55AA', FOut) > 0);
  AssertTrue(FOut, Pos('<- M_IT_NA_1 REQUESTED_BY_GENERAL_COUNTER CA 1 IOA 500 = 1000 seq 2', FOut) > 0);
  AssertTrue(FErr, Pos('iec101master: slave 5 ONLINE:', FErr) = 1);
  AssertEquals('select + execute twice, read, clock, test, ci', 8, FSim.Got.Count);
  AssertEquals('31 01 06 00 01 00 88 13 00 F9 FF 80', FSim.Got[3]);
end;

procedure TTestIec101Examples.TestNegativeAndUnknownAnswers;
begin
  AssertEquals(3, Run(['--timeout=200', MasterParams, 'setpoint-float', '5000=1.5', 'gi']));
  AssertTrue(FErr, Pos('iec101master: C_SE_NC_1 IOA 5000 to slave 5: negative ACT_CON (setpoint-float 5000=1.5)',
    FErr) > 0);
  AssertTrue('the interrogation ran all the same', Pos('<- C_IC_NA_1 ACTIVATION_TERMINATION', FOut) > 0);
  FOut := '';
  FErr := '';
  AssertEquals(3, Run(['--json', '--timeout=200', MasterParams, 'sc', '77=1']));
  AssertTrue(FOut, Pos('{"type":"C_SC_NA_1","ti":45,"cot":47,"negative":true,', FOut) > 0);
  AssertTrue(FErr, Pos('the slave does not know IOA 77', FErr) > 0);
  FOut := '';
  FErr := '';
  AssertEquals(3, Run(['--ca', '9', '--timeout=200', MasterParams, 'gi']));
  AssertTrue(FErr, Pos('does not know common address 9', FErr) > 0);
end;

procedure TTestIec101Examples.TestSlaveThatDoesNotAnswer;
begin
  AssertEquals(4, Run(['--timeout=50', '--retries=0', '--wait=2000', MasterParams, 'gi'], False));
  AssertTrue(FErr, Pos('C_IC_NA_1 to slave 5: slave does not answer', FErr) > 0);
  AssertTrue(FErr, Pos('slave 5 DEAD', FErr) > 0);
end;

procedure TTestIec101Examples.TestBalancedLine;
begin
  FreeAndNil(FSim);
  FSim := TSim.Create('NAM=FT1_2 MS=OFF PRI=OFF DIR=0 LEN=0 NOD=5 DNO=1 NAM=COM DRV=PTY', True, 200);
  AssertEquals(FErr, 0, Run(['--timeout=200', 'NAM=FT1_2 MS=OFF PRI=ON DIR=1 LEN=0 NOD=1 DNO=5 NAM=COM DEV='
    + PtyLastSlave, 'gi', 'sc', '5000=1']));
  AssertTrue(FOut, Pos('<- M_ME_NB_1 INTERROGATED_BY_STATION CA 1 IOA 102 = 2300' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('<- C_IC_NA_1 ACTIVATION_TERMINATION CA 1 IOA 0 = 20' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('<- C_SC_NA_1 ACTIVATION_CON CA 1 IOA 5000 = on execute' + LineEnding, FOut) > 0);
  AssertEquals('64 01 06 00 01 00 00 00 00 14', FSim.Got[0]);
  AssertTrue(FErr, Pos('slave 5 ONLINE', FErr) > 0);
end;

{ --slaves 5,7 on a line where only 5 answers: 5's interrogation is
  complete, 7's fails (exit 4), 5 is polled meanwhile and after. }
procedure TTestIec101Examples.TestSeveralSlavesOneDead;
begin
  AssertEquals(FErr, 4, Run(['--slaves', '5,7', '--timeout=50', '--wait=1000', MasterParams, 'gi', 'poll', '1']));
  AssertTrue(FOut, Pos('slave 5 <- C_IC_NA_1 ACTIVATION_TERMINATION CA 1 IOA 0 = 20' + LineEnding, FOut) > 0);
  AssertTrue(FOut, Pos('slave 5 <- M_ME_NB_1 INTERROGATED_BY_STATION CA 1 IOA 100 = -1' + LineEnding, FOut) > 0);
  { 7 died during 5's interrogation: its command fails at its next try
  (does not answer) or, when that try is due after --wait, unsent }
  AssertTrue(FErr, (Pos('C_IC_NA_1 to slave 7: slave does not answer', FErr) > 0) or
    (Pos('C_IC_NA_1 to slave 7: not sent in 1000 ms (slave DEAD)', FErr) > 0));
  AssertTrue(FErr, Pos('slave 5 ONLINE', FErr) > 0);
  AssertTrue(FErr, Pos('slave 7 DEAD', FErr) > 0);
  AssertEquals('only the interrogation reached slave 5', 1, FSim.Got.Count);
end;

{ The peer sends to link address 2, this station is 1 (a wrong DNO= on
  the other side): the error names what the line showed. }
procedure TTestIec101Examples.TestBalancedWrongAddressNamed;
begin
  FreeAndNil(FSim);
  FSim := TSim.Create('NAM=FT1_2 MS=OFF PRI=OFF LEN=0 NOD=5 DNO=2 NAM=COM DRV=PTY', True, 200);
  AssertEquals(FErr, 4, Run(['--timeout=200', '--wait=1500', 'NAM=FT1_2 MS=OFF PRI=ON LEN=0 NOD=1 DNO=5 NAM=COM DEV='
    + PtyLastSlave, 'gi']));
  AssertTrue(FErr, Pos('C_IC_NA_1 to slave 5: ', FErr) > 0);
  AssertTrue(FErr, Pos(' — ', FErr) > 0);
  AssertTrue(FErr, Pos(' frames from link address 2 ignored', FErr) > 0);
end;

{ The program as make test builds it with heaptrc (build/test-bin): the
  usage, --help and --version (which end inside the option parser), an
  interrogation answered and one not answered free all they took.
  heaptrc's report must be there (the build is heaptrc's) and say 0
  unfreed blocks. (A command-line error ends the program where it is
  found, a caller's strings not freed: not checked.) }
procedure TTestIec101Examples.TestNothingLeftAtExit;
var
  Dir, Build: string;

  procedure Check(const What: string; Want, Got: Integer);
  var
    Report: AnsiString;
  begin
    AssertEquals(What + ': exit code; ' + FErr, Want, Got);
    AssertTrue(What + ': no heaptrc report in ' + FHeapLog, FileExists(FHeapLog));
    Report := ReadFileText(FHeapLog);
    AssertTrue(What + ': ' + Report, Pos(LineEnding + '0 unfreed memory blocks : 0' + LineEnding,
      LineEnding + Report) > 0);
    FOut := '';
    FErr := '';
  end;

begin
  Build := GetEnvironmentVariable('BUILD');
  if Build = '' then
    Build := 'build';
  FExe := Build + '/test-bin/iec101master' {$IFDEF WINDOWS} + '.exe'{$ENDIF};
  if not FileExists(FExe) then
    Ignore(FExe + ' is not built (make test builds it with heaptrc; make mutate does not)');
  Dir := MakeTempDir('iec101leak');
  try
    FHeapLog := Dir + '/heap.log';
    Check('no arguments', 2, Run([], False));
    Check('--help', 0, Run(['--help'], False));
    Check('--version', 0, Run(['--version'], False));
    Check('gi answered', 0, Run(['--timeout=200', MasterParams, 'gi']));
    Check('gi not answered', 4, Run(['--timeout=50', '--retries=0', '--wait=2000', MasterParams, 'gi'], False));
  finally
    RemoveTempDir(Dir);
  end;
end;

initialization
  RegisterTest(TTestIec101Examples);
end.
