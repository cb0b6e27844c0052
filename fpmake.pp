{ fpmake.pp - the Chn library as a Free Pascal package (FPC's own package
  build):

    fpc fpmake.pp && ./fpmake build            # units into units/<cpu>-<os>
    ./fpmake install                           # where fpc finds them
    ./fpmake install --prefix=$HOME/.fppkg     # per user (Debian searches it)

  Every unit in src/ belongs to the package; the OS picks the serial
  backend: *Unix.pas and ChnPty for Unix-likes, *Win.pas for Windows.
  ChnPortSynapse needs Synapse, which is not part of this package (build
  it with "make SYNAPSE_DIR=..." instead). Tools, examples and tests are
  built by the Makefile. }
{$mode objfpc}{$H+}
program fpmake;

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, fpmkunit;

const
  Version = '1.0.0';

function OSesOf(const UnitName: string): TOSes;
begin
  if (Pos('Unix', UnitName) > 0) or (UnitName = 'ChnPty') then
    Result := AllUnixOSes
  else if Pos('Win', UnitName) > 0 then
    Result := [win32, win64]
  else
    Result := AllOSes;
end;

var
  P: TPackage;
  T: TTarget;
  F: TSearchRec;
  Name: string;
begin
  with Installer do
  begin
    P := AddPackage('chn');
    P.Version := Version;
    P.Description := 'SofCon Chn serial-communication units (DF1, FT 1.2, ICSlink) ' +
      'for Free Pascal: layered channels driven by polling.';
    P.License := 'see README.md';
    P.OSes := AllUnixOSes + [win32, win64];
    P.Dependencies.Add('rtl-extra');   { serial, termio }
    P.Dependencies.Add('fcl-base');
    P.SourcePath.Add('src');
    P.IncludePath.Add('src');
    if FindFirst('src' + PathDelim + '*.pas', faAnyFile, F) = 0 then
    try
      repeat
        Name := ChangeFileExt(F.Name, '');
        if Pos('Synapse', Name) > 0 then
          Continue;                      { optional third-party backend }
        T := P.Targets.AddUnit(F.Name, OSesOf(Name));
        T.Dependencies.AddInclude('chn.inc');
      until FindNext(F) <> 0;
    finally
      FindClose(F);
    end;
    Run;
  end;
end.
