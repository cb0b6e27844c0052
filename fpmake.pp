{ fpmake.pp - the Chn library as a Free Pascal package (FPC's own package
  build):

    fpc fpmake.pp && ./fpmake build            # units into units/<cpu>-<os>
    ./fpmake install                           # where fpc finds them
    ./fpmake install --prefix=$HOME/.fppkg     # per user (Debian searches it)

  Every unit in src/ belongs to the package; per-OS units and include
  files are in src/unix (Unix-likes) and src/win (Windows).
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

procedure AddDir(P: TPackage; const Dir: string; OSes: TOSes);
var
  T: TTarget;
  F: TSearchRec;
begin
  if FindFirst(Dir + PathDelim + '*.pas', faAnyFile, F) = 0 then
  try
    repeat
      if Pos('Synapse', F.Name) > 0 then
        Continue;                      { optional third-party backend }
      T := P.Targets.AddUnit(F.Name, OSes);
      T.Dependencies.AddInclude('chn.inc');
    until FindNext(F) <> 0;
  finally
    FindClose(F);
  end;
end;

var
  P: TPackage;
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
    P.SourcePath.Add('src/unix', AllUnixOSes);
    P.SourcePath.Add('src/win', [win32, win64]);
    P.IncludePath.Add('src');
    AddDir(P, 'src', AllOSes);
    AddDir(P, 'src/unix', AllUnixOSes);
    AddDir(P, 'src/win', [win32, win64]);
    Run;
  end;
end.
