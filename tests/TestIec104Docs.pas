{ The complete program of docs/ChnIec104.md, as printed there: cut out of
  the document, built with fpc against the library's units (build/units)
  outside the tree, and run against a ChnIec101Slave over loopback 104 in
  the test. What it must print is written out from the document and the
  slave's table. Unix only (as the other doc programs). }
unit TestIec104Docs;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, ChnTypes, ChnVirt, ChnTcp, ChnIec104,
  ChnIec101Asdu, ChnIec101Slave, Iec101Points, ChnWait, BinSupport, TestTempDir, DocProgram;

type
  TTestIec104Docs = class(TTestCase)
  private
    FDir: string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  public
    S: tIecSlaveStation;
  published
    procedure TestClientProgram;
  end;

implementation

procedure TTestIec104Docs.SetUp;
begin
  FDir := MakeTempDir('iec104docs');
end;

procedure TTestIec104Docs.TearDown;
begin
  RemoveTempDir(FDir);
end;

procedure StepSlave(Data: Pointer);
begin
  if not IecSlaveStep(tIecSlaveStation(Data^)) then
    ChnWaitAny(5);
end;

procedure TTestIec104Docs.TestClientProgram;
var
  Exe, Out, Want, Err: string;
  Chn: pChnVirt;
  P: TProcess;
  E: AnsiString;
  Es: ShortString;
begin
  Exe := BuildDocProgram('docs/ChnIec104.md', 'iec104gi', FDir);
  Chn := ChnCollection^.ChNewInit(ChnIec104.cName);
  Chn^.ChSetParam('NAM=IEC104 NAM=TCP LISTEN=127.0.0.1:0');
  Chn^.ChOpen;
  Chn^.ChConnect;
  AssertEquals(res_Ok, Chn^.ChResult);
  P := TProcess.Create(nil);
  try
    AssertEquals(res_Ok, IecSlaveInit(S, Chn, IecDefaultParams, 1, Es));
    AssertTrue(E, IecLoadPoints(S, 'table', '100 M_ME_NB_1 -1'#10'101 M_ME_NB_1 23'#10 +
      '104 M_SP_NA_1 1'#10'500 M_BO_NA_1 0xAAAA'#10, E));
    BinExecutable(P, Exe);
    P.Parameters.Add('NAM=IEC104 NAM=TCP HOST=127.0.0.1 PORT=' +
      IntToStr(pChnTcp(Chn^.CH_Low)^.ChLocalPort));
    P.Options := [poUsePipes, poStderrToOutPut];
    P.Execute;
    Out := ServeUntilEnded(P, 15000, @StepSlave, @S);
    Want := 'C_IC_NA_1 ACTIVATION_CON IOA 0 = 20' + LineEnding +
      'M_ME_NB_1 INTERROGATED_BY_STATION IOA 100 = -1' + LineEnding +
      'M_ME_NB_1 INTERROGATED_BY_STATION IOA 101 = 23' + LineEnding +
      'M_SP_NA_1 INTERROGATED_BY_STATION IOA 104 = 1' + LineEnding +
      'M_BO_NA_1 INTERROGATED_BY_STATION IOA 500 = 0x0000AAAA' + LineEnding +
      'C_IC_NA_1 ACTIVATION_TERMINATION IOA 0 = 20' + LineEnding + 'Ok' + LineEnding;
    Err := Out;
    AssertEquals(Err, Want, Out);
    AssertEquals(0, P.ExitCode);
  finally
    StopProcess(P);
    Dispose(Chn, Done);
  end;
end;

initialization
  RegisterTest(TTestIec104Docs);
end.
