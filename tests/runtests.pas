{ runtests - console runner of the FPCUnit suite.

  Runs every registered test (or those whose path contains the first
  command-line argument), prints one line per test and, last, a line
  "RESULT <passed> <failed> <skipped>" that tests/run.sh folds into the
  suite's final "N passed, N failed" line. Exit code 1 on any failure or
  error. A test that calls no Assert counts as failed. A test that needs
  an optional program (tshark, xmllint ...) and finds it missing calls
  Ignore('why'): it is printed as "skip" with the reason and counted as
  skipped, neither passed nor failed. }
program runtests;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  {$I testunits.inc}
  Classes, SysUtils, fpcunit, testregistry;

type
  TLineListener = class(TInterfacedObject, ITestListener)
    Passed, Failed, Skipped: Integer;
    CurrentFailed, CurrentSkipped: Boolean;
    procedure AddFailure(ATest: TTest; AFailure: TTestFailure);
    procedure AddError(ATest: TTest; AError: TTestFailure);
    procedure StartTest(ATest: TTest);
    procedure EndTest(ATest: TTest);
    procedure StartTestSuite(ATestSuite: TTestSuite);
    procedure EndTestSuite(ATestSuite: TTestSuite);
  end;

procedure TLineListener.AddFailure(ATest: TTest; AFailure: TTestFailure);
begin
  if AFailure.IsIgnoredTest then
  begin
    CurrentSkipped := True;
    WriteLn('skip  ', ATest.TestSuiteName, '.', ATest.TestName, ': ', AFailure.ExceptionMessage);
    Exit;
  end;
  CurrentFailed := True;
  WriteLn('FAIL  ', ATest.TestSuiteName, '.', ATest.TestName, ': ', AFailure.ExceptionMessage);
end;

procedure TLineListener.AddError(ATest: TTest; AError: TTestFailure);
begin
  CurrentFailed := True;
  WriteLn('ERROR ', ATest.TestSuiteName, '.', ATest.TestName, ': ',
    AError.ExceptionClassName, ': ', AError.ExceptionMessage,
    ' at ', AError.SourceUnitName, ':', AError.LineNumber);
end;

procedure TLineListener.StartTest(ATest: TTest);
begin
  CurrentFailed := False;
  CurrentSkipped := False;
end;

procedure TLineListener.EndTest(ATest: TTest);
begin
  if CurrentFailed then
    Inc(Failed)
  else if CurrentSkipped then
    Inc(Skipped)
  else
  begin
    Inc(Passed);
    WriteLn('ok    ', ATest.TestSuiteName, '.', ATest.TestName);
  end;
  Flush(Output);
end;

procedure TLineListener.StartTestSuite(ATestSuite: TTestSuite);
begin
end;

procedure TLineListener.EndTestSuite(ATestSuite: TTestSuite);
begin
end;

procedure CollectTests(T: TTest; const Filter: string; List: TFPList);
var
  I: Integer;
  Path: string;
begin
  if T is TTestSuite then
    for I := 0 to TTestSuite(T).ChildTestCount - 1 do
      CollectTests(TTestSuite(T).Test[I], Filter, List)
  else
  begin
    Path := T.TestSuiteName + '.' + T.TestName;
    if (Filter = '') or (Pos(LowerCase(Filter), LowerCase(Path)) > 0) then
      List.Add(T);
  end;
end;

var
  Listener: TLineListener;
  Keep: ITestListener;
  Res: TTestResult;
  List: TFPList;
  I: Integer;
  Filter: string;
begin
  { a test that asserts nothing fails: it could not have failed otherwise }
  TTestCase.CheckAssertCalled := True;
  Filter := '';
  if ParamCount > 0 then
    Filter := ParamStr(1);
  Listener := TLineListener.Create;
  Keep := Listener;
  Res := TTestResult.Create;
  List := TFPList.Create;
  try
    Res.AddListener(Listener);
    CollectTests(GetTestRegistry, Filter, List);
    for I := 0 to List.Count - 1 do
      TTest(List[I]).Run(Res);
    WriteLn('RESULT ', Listener.Passed, ' ', Listener.Failed, ' ', Listener.Skipped);
    if Listener.Failed > 0 then
      ExitCode := 1;
  finally
    List.Free;
    Res.Free;
  end;
end.
