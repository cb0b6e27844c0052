{ DocProgram - a complete program a document of docs/ prints, cut out of
  it and built as a reader would build it: fpc against the library's units
  (build/units), outside the tree. }
unit DocProgram;

{$MODE OBJFPC}{$H+}

interface

{ Cut program Name out of document Doc (the ```pascal block whose first
  line is "program Name;"), build it in Dir; the executable. Fails the
  test when the document lacks the program or it does not build. }
function BuildDocProgram(const Doc, Name, Dir: string): string;

implementation

uses
  SysUtils, Classes, fpcunit, BinSupport;

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

end.
