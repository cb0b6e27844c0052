{ DocProgram - a complete program a document of docs/ prints, cut out of
  it and built as a reader would build it: fpc against the library's units
  (build/units), outside the tree; then run while the test serves its
  other end. }
unit DocProgram;

{$MODE OBJFPC}{$H+}

interface

uses
  Process;

{ Cut program Name out of document Doc (the ```pascal block whose first
  line is "program Name;"), build it in Dir; the executable. Fails the
  test when the document lacks the program or it does not build. }
function BuildDocProgram(const Doc, Name, Dir: string): string;

type
  { one step of the test's own end while the program runs (it waits a
    little itself when it had nothing to do) }
  TServeStep = procedure(Data: Pointer);

{ Call Serve(Data) while P, started with its standard error in its
  output, runs, for Ms at the most; what P printed. Fails the test when
  P has not ended by then. }
function ServeUntilEnded(P: TProcess; Ms: LongInt; Serve: TServeStep; Data: Pointer): string;

implementation

uses
  SysUtils, Classes, fpcunit, ChnVirt, BinSupport;

function BuildDocProgram(const Doc, Name, Dir: string): string;
var
  Text, Prog: TStringList;
  I: Integer;
  Inside: Boolean;
  Output, Fpc: string;
begin
  Text := TStringList.Create;
  Prog := TStringList.Create;
  try
    Text.LoadFromFile(Doc);
    Inside := False;
    for I := 0 to Text.Count - 1 do
      if Inside then
      begin
        if Text[I] = '```' then
          Break;
        Prog.Add(Text[I]);
      end
      else if (Text[I] = '```pascal') and (I < Text.Count - 1) and
        (Pos('program ' + Name + ';', Text[I + 1]) = 1) then
        Inside := True;
    TAssert.AssertTrue('program ' + Name + ' in ' + Doc, Prog.Count > 10);
    Prog.SaveToFile(Dir + '/' + Name + '.pas');
  finally
    Text.Free;
    Prog.Free;
  end;
  Fpc := ExeSearch('fpc', GetEnvironmentVariable('PATH'));
  TAssert.AssertTrue('fpc', Fpc <> '');
  TAssert.AssertEquals(Name + ' builds: ', 0, RunExe(Fpc, ['-v0', '-Fubuild/units', '-Fisrc',
    '-FU' + Dir, '-FE' + Dir, Dir + '/' + Name + '.pas'], 120000, Output));
  Result := Dir + '/' + Name;
  TAssert.AssertTrue(Output, FileExists(Result));
end;

function ServeUntilEnded(P: TProcess; Ms: LongInt; Serve: TServeStep; Data: Pointer): string;
var
  Deadline: QWord;
begin
  Result := '';
  Deadline := ChMsTick + QWord(Ms);
  while P.Running and (ChMsTick < Deadline) do
  begin
    Serve(Data);
    Result := Result + PipeText(P.Output);
  end;
  Result := Result + PipeText(P.Output);
  TAssert.AssertFalse('ended', P.Running);
end;

end.
