{ TestTempDir - a private temporary directory per test, and whole-file
  read/write helpers, so tests that create files leave nothing behind. }
unit TestTempDir;

{$MODE OBJFPC}{$H+}

interface

{ A new empty directory under the system temp dir; ends with a separator. }
function MakeTempDir(const Prefix: string): string;
{ Delete Dir with every file and directory in it. }
procedure RemoveTempDir(const Dir: string);
function ReadFileText(const Path: string): AnsiString;
procedure WriteFileText(const Path: string; const Text: AnsiString);

implementation

uses
  SysUtils, ChnOs;

var
  Serial: Integer = 0;

function MakeTempDir(const Prefix: string): string;
begin
  repeat
    Inc(Serial);
    Result := IncludeTrailingPathDelimiter(GetTempDir(False)) + Prefix + '-' +
      IntToStr(GetProcessID) + '-' + IntToStr(Serial);
  until not DirectoryExists(Result);
  if not ForceDirectories(Result) then
    raise Exception.Create('cannot create ' + Result);
  Result := IncludeTrailingPathDelimiter(Result);
end;

procedure RemoveTempDir(const Dir: string);
var
  Info: TSearchRec;
  D: string;
begin
  if Dir = '' then
    Exit;
  D := IncludeTrailingPathDelimiter(Dir);
  if FindFirst(D + '*', faAnyFile, Info) = 0 then
  begin
    repeat
      if (Info.Name = '.') or (Info.Name = '..') then
        Continue;
      if (Info.Attr and faDirectory) <> 0 then
        RemoveTempDir(D + Info.Name)
      else
        DeleteFile(D + Info.Name);
    until FindNext(Info) <> 0;
    FindClose(Info);
  end;
  RemoveDir(ExcludeTrailingPathDelimiter(D));
end;

function ReadFileText(const Path: string): AnsiString;
var
  Err: ShortString;
begin
  if not OsFileLoad(Path, Result, Err) then
    raise EInOutError.Create(Err);
end;

procedure WriteFileText(const Path: string; const Text: AnsiString);
var
  Err: ShortString;
begin
  if not OsFileSave(Path, Text, Err) then
    raise EInOutError.Create(Err);
end;

end.
