{ The complete programs of docs/ChnIec101.md, as printed there: each is
  cut out of the document, built with fpc against the library's units
  (build/units) outside the tree, and run on a pty against the other
  helper in the test - the master program against a ChnIec101Slave with
  lib60870's example points, the slave program against a ChnIec101Master.
  What they must print is written out from the document. Unix only. }
unit TestIec101Docs;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnCom, ChnPty,
  ChnFT1_2, ChnIec101Asdu, ChnIec101Slave, ChnIec101Master, Iec101Points, BinSupport,
  TestTempDir, DocProgram;

type
  TTestIec101Docs = class(TTestCase)
  private
    FDir: string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    Objects: TStringList;
    S: tIecSlaveStation;
  published
    procedure TestMasterProgram;
    procedure TestSlaveProgram;
  end;

implementation

procedure TTestIec101Docs.SetUp;
begin
  FDir := MakeTempDir('iec101docs');
  Objects := TStringList.Create;
end;

procedure TTestIec101Docs.TearDown;
begin
  Objects.Free;
  RemoveTempDir(FDir);
end;

procedure StepSlave(Data: Pointer);
begin
  if not IecSlaveStep(tIecSlaveStation(Data^)) then
    Sleep(1);
end;

procedure StepMaster(Data: Pointer);
begin
  IecMasterStep(tIecMaster(Data^));
  Sleep(5);
end;

procedure TTestIec101Docs.TestMasterProgram;
var
  Exe, Out, Err: string;
  Chn: pChnVirt;
  P: TProcess;
  E: AnsiString;
  Es: ShortString;
begin
  Exe := BuildDocProgram('docs/ChnIec101.md', 'iecgi', FDir);
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam('NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DRV=PTY');
  Chn^.ChOpen;
  Chn^.ChConnect;
  AssertEquals(res_Ok, Chn^.ChResult);
  P := TProcess.Create(nil);
  try
    AssertEquals(res_Ok, IecSlaveInit(S, Chn, IecDefaultParams, 1, Es));
    AssertTrue(E, IecLoadPoints(S, 'table', '100 M_ME_NB_1 -1'#10'101 M_ME_NB_1 23'#10 +
      '102 M_ME_NB_1 2300'#10'104 M_SP_NA_1 1'#10'500 M_BO_NA_1 0xAAAA'#10, E));
    P.Executable := Exe;
    P.Parameters.Add('NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=' + PtyLastSlave +
      ' BD=9600 PAR=E');
    P.Options := [poUsePipes, poStderrToOutPut];
    P.Execute;
    Out := ServeUntilEnded(P, 15000, @StepSlave, @S);
    Err := 'C_IC_NA_1 ACTIVATION_CON IOA 0 = 20' + LineEnding +
      'M_ME_NB_1 INTERROGATED_BY_STATION IOA 100 = -1' + LineEnding +
      'M_ME_NB_1 INTERROGATED_BY_STATION IOA 101 = 23' + LineEnding +
      'M_ME_NB_1 INTERROGATED_BY_STATION IOA 102 = 2300' + LineEnding +
      'M_SP_NA_1 INTERROGATED_BY_STATION IOA 104 = 1' + LineEnding +
      'M_BO_NA_1 INTERROGATED_BY_STATION IOA 500 = 0x0000AAAA' + LineEnding +
      'C_IC_NA_1 ACTIVATION_TERMINATION IOA 0 = 20' + LineEnding + 'Ok' + LineEnding;
    AssertEquals(Err, Out);
    AssertEquals(0, P.ExitCode);
  finally
    StopProcess(P);
    Dispose(Chn, Done);
  end;
end;

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  TTestIec101Docs(Data).Objects.Add(Format('%s %d %d = %d', [IecTypeName(H.Ti), H.Cot, O.Ioa, O.Int]));
end;

procedure TTestIec101Docs.TestSlaveProgram;
var
  Exe, Out: string;
  Chn: pChnVirt;
  P: TProcess;
  M: tIecMaster;
  O: tIecObject;
  Gi: TStringList;
  Line: string;
begin
  Exe := BuildDocProgram('docs/ChnIec101.md', 'iecrtu', FDir);
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam('NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DRV=PTY');
  Chn^.ChOpen;
  Chn^.ChConnect;
  AssertEquals(res_Ok, Chn^.ChResult);
  P := TProcess.Create(nil);
  try
    P.Executable := Exe;
    P.Parameters.Add('NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DEV=' + PtyLastSlave +
      ' BD=9600 PAR=E');
    P.Parameters.Add('4');
    P.Options := [poUsePipes, poStderrToOutPut];
    P.Execute;
    AssertEquals(res_Ok, IecMasterInit(M, Chn, IecDefaultParams));
    AssertEquals(res_Ok, IecMasterAddSlave(M, 1));
    M.OnObject := @OnObj;
    M.Data := Self;
    M.CycleMs := 20;
    AssertEquals(M.Cmd.Err, res_Ok, IecInterrogation(M, 1, 1, Qoi_Station));
    { a change the program made before the interrogation came (every
      second, from its start) is a class 1 event and may come first: the
      interrogation's own sequence, without spontaneous objects (COT 3) }
    Gi := TStringList.Create;
    try
      for Line in Objects do
        if Pos(' 3 ', Line) = 0 then
          Gi.Add(Line);
      AssertTrue(Objects.Text, Gi.Count >= 4);
      AssertEquals(Objects.Text, 'C_IC_NA_1 7 0 = 20', Gi[0]);
      AssertTrue(Objects.Text, Pos('M_ME_NB_1 20 100 = ', Gi[1]) = 1);
      AssertEquals(Objects.Text, 'M_SP_NA_1 20 104 = 1', Gi[2]);
      AssertEquals(Objects.Text, 'C_IC_NA_1 10 0 = 20', Gi[3]);
    finally
      Gi.Free;
    end;
    O := IecObject(5000);
    O.Int := 1;
    AssertEquals(M.Cmd.Err, res_Ok, IecCommand(M, 1, 1, C_SC_NA_1, O, True));
    IecPollFor(M, 2200);
    { the changes every second, as events }
    AssertTrue(Objects.Text, Pos('M_ME_NB_1 3 100 = ', Objects.Text) > 0);
    Out := ServeUntilEnded(P, 10000, @StepMaster, @M);
    AssertEquals('C_SC_NA_1 IOA 5000 = 1 select TRUE' + LineEnding +
      'C_SC_NA_1 IOA 5000 = 1 select FALSE' + LineEnding + 'Ok' + LineEnding, Out);
  finally
    StopProcess(P);
    Dispose(Chn, Done);
  end;
end;

initialization
  RegisterTest(TTestIec101Docs);
end.
