{ runtests - console runner of the FPCUnit suite.

    runtests [FILTER] [--list] [--xml=FILE]

  Runs every registered test (or those whose path contains FILTER), prints
  one line per test - a failure with the file, line and source text of the
  failing assert (see Where), so even an assert without a message says
  what it checked - and, last,
  a line "RESULT <passed> <failed> <skipped>" that tests/run.sh folds into
  the suite's final "N passed, N failed" line. A test that cannot run here
  (a Debian package missing ...) calls Ignore('why'): it is printed as
  "skip  Suite.Test: why" and counted as skipped, neither passed nor
  failed. --list prints the selected tests'
  names and runs nothing; --xml=FILE also writes the results as JUnit XML
  (testsuite/testcase/failure), which CI systems read. Exit code 1 on any
  failure or error. A test that calls no Assert counts as failed. }
program runtests;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  {$I testunits.inc}
  Classes, SysUtils, DateUtils, fpcunit, testregistry;

type
  TLineListener = class(TInterfacedObject, ITestListener)
    Passed, Failed, Skipped: Integer;
    CurrentFailed, CurrentSkipped: Boolean;
    Started: TDateTime;
    Xml: TStringList;        { <testcase> elements; nil: no XML wanted }
    Failure: string;         { the current test's <failure>, if any }
    procedure AddFailure(ATest: TTest; AFailure: TTestFailure);
    procedure AddError(ATest: TTest; AError: TTestFailure);
    procedure StartTest(ATest: TTest);
    procedure EndTest(ATest: TTest);
    procedure StartTestSuite(ATestSuite: TTestSuite);
    procedure EndTestSuite(ATestSuite: TTestSuite);
  end;

function XmlText(const S: string): string;
begin
  Result := StringReplace(S, '&', '&amp;', [rfReplaceAll]);
  Result := StringReplace(Result, '<', '&lt;', [rfReplaceAll]);
  Result := StringReplace(Result, '>', '&gt;', [rfReplaceAll]);
  Result := StringReplace(Result, '"', '&quot;', [rfReplaceAll]);
end;

{ 'tests/TestChnCom.pas:123: AssertEquals(...)': where a failure was
  raised (FPCUnit's LocationInfo, from the suite's line info: -gl -Xs-),
  with the source line itself, so every assert reads as its own message.
  The location is exact when the Makefile could build FPCUnit from
  Debian's fpc-source without optimisation; Debian's prebuilt fpcunit
  loses the caller's frame and the location is then only an address. }
function Where(const Loc: string): string;
const
  Dirs: array[0..2] of string = ('', 'tests/', 'tests/support/');
var
  P, Q, LineNo, I: Integer;
  FileName: string;
  Src: TStringList;
begin
  Result := Trim(Loc);
  P := Pos(' line ', Loc);
  Q := Pos(' of ', Loc);
  if (P = 0) or (Q <= P) or not TryStrToInt(Copy(Loc, P + 6, Q - P - 6), LineNo) then
    Exit;
  FileName := Trim(Copy(Loc, Q + 4, MaxInt));
  Result := FileName + ':' + IntToStr(LineNo);
  for I := Low(Dirs) to High(Dirs) do
    if FileExists(Dirs[I] + FileName) then
    begin
      Src := TStringList.Create;
      try
        Src.LoadFromFile(Dirs[I] + FileName);
        if (LineNo >= 1) and (LineNo <= Src.Count) then
          Result := Result + ': ' + Trim(Src[LineNo - 1]);
      finally
        Src.Free;
      end;
      Exit;
    end;
end;

procedure TLineListener.AddFailure(ATest: TTest; AFailure: TTestFailure);
begin
  if AFailure.IsIgnoredTest then
  begin
    CurrentSkipped := True;
    WriteLn('skip  ', ATest.TestSuiteName, '.', ATest.TestName, ': ',
      AFailure.ExceptionMessage);
    Failure := Format('<skipped message="%s"/>', [XmlText(AFailure.ExceptionMessage)]);
    Exit;
  end;
  CurrentFailed := True;
  WriteLn('FAIL  ', ATest.TestSuiteName, '.', ATest.TestName, ': ',
    AFailure.ExceptionMessage, ' at ', Where(AFailure.LocationInfo));
  Failure := Format('<failure message="%s">at %s</failure>',
    [XmlText(AFailure.ExceptionMessage), XmlText(Where(AFailure.LocationInfo))]);
end;

procedure TLineListener.AddError(ATest: TTest; AError: TTestFailure);
begin
  CurrentFailed := True;
  WriteLn('ERROR ', ATest.TestSuiteName, '.', ATest.TestName, ': ',
    AError.ExceptionClassName, ': ', AError.ExceptionMessage,
    ' at ', Where(AError.LocationInfo));
  Failure := Format('<error type="%s" message="%s">at %s</error>',
    [XmlText(AError.ExceptionClassName), XmlText(AError.ExceptionMessage),
     XmlText(Where(AError.LocationInfo))]);
end;

procedure TLineListener.StartTest(ATest: TTest);
begin
  CurrentFailed := False;
  CurrentSkipped := False;
  Failure := '';
  Started := Now;
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
  if Xml <> nil then
    Xml.Add(Format('  <testcase classname="%s" name="%s" time="%.3f">%s</testcase>',
      [XmlText(ATest.TestSuiteName), XmlText(ATest.TestName),
       MilliSecondsBetween(Now, Started) / 1000, Failure]));
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

procedure WriteXml(const FileName: string; L: TLineListener);
begin
  L.Xml.Insert(0, '<?xml version="1.0" encoding="UTF-8"?>');
  L.Xml.Insert(1, Format('<testsuite name="chn" tests="%d" failures="%d" skipped="%d">',
    [L.Passed + L.Failed + L.Skipped, L.Failed, L.Skipped]));
  L.Xml.Add('</testsuite>');
  L.Xml.SaveToFile(FileName);
end;

var
  Listener: TLineListener;
  Keep: ITestListener;
  Res: TTestResult;
  List: TFPList;
  I: Integer;
  Filter, XmlFile, Arg: string;
  ListOnly: Boolean;
begin
  { a test that asserts nothing fails: it could not have failed otherwise }
  TTestCase.CheckAssertCalled := True;
  Filter := '';
  XmlFile := '';
  ListOnly := False;
  for I := 1 to ParamCount do
  begin
    Arg := ParamStr(I);
    if Arg = '--list' then
      ListOnly := True
    else if Copy(Arg, 1, 6) = '--xml=' then
      XmlFile := Copy(Arg, 7, MaxInt)
    else if Copy(Arg, 1, 2) = '--' then
    begin
      WriteLn(StdErr, 'runtests: unknown option ', Arg,
        ' (usage: runtests [FILTER] [--list] [--xml=FILE])');
      Halt(2);
    end
    else
      Filter := Arg;
  end;
  Listener := TLineListener.Create;
  Keep := Listener;
  if XmlFile <> '' then
    Listener.Xml := TStringList.Create;
  Res := TTestResult.Create;
  List := TFPList.Create;
  try
    CollectTests(GetTestRegistry, Filter, List);
    if ListOnly then
    begin
      for I := 0 to List.Count - 1 do
        WriteLn(TTest(List[I]).TestSuiteName, '.', TTest(List[I]).TestName);
      Exit;
    end;
    Res.AddListener(Listener);
    for I := 0 to List.Count - 1 do
      TTest(List[I]).Run(Res);
    WriteLn('RESULT ', Listener.Passed, ' ', Listener.Failed, ' ', Listener.Skipped);
    if XmlFile <> '' then
      WriteXml(XmlFile, Listener);
    if Listener.Failed > 0 then
      ExitCode := 1;
  finally
    Listener.Xml.Free;
    List.Free;
    Res.Free;
  end;
end.
