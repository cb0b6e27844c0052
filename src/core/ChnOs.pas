{ ChnOs - the few services of the operating system the portable units
  ask for, each answered by the OS's part (unix/chnos.inc, win/chnos.inc):
  the words for an OS error code, the device of COM=N, the UTC clock of a
  capture record, and a log file several writers append to; and a whole
  file read or written at once (portable, here for every unit and tool). }
unit ChnOs;

{$I chn.inc}

interface

{ The system's words for error code Code ('No such file or directory'), no
  full stop at the end. }
function OsErrorText(Code: LongInt): ShortString;
{ The device of serial port N (1 = the first): /dev/ttyS<N-1>, \\.\COM<N>. }
function OsComDevicePath(N: LongInt): ShortString;
{ UTC seconds since 1970 and microseconds (a pcap record's time). }
procedure OsUtcNow(out Sec, USec: LongWord);
{ Open the file Name for appending, created if missing, shared: several
  writers (both ends of a test) and any reader may have it open at once.
  THandle(-1) when it cannot be opened; a FIFO nobody reads fails at once
  instead of blocking. }
function OsOpenAppend(const Name: AnsiString): THandle;
{ Before each write to a file of OsOpenAppend: where the OS does not
  append by itself (Windows), to its end. }
procedure OsBeforeAppend(H: THandle);
{ A whole file into Content / Content into a file (created or emptied):
  False with Err, the path and the OS's reason. }
function OsFileLoad(const Path: AnsiString; out Content: AnsiString; out Err: ShortString): Boolean;
function OsFileSave(const Path: AnsiString; const Content: AnsiString; out Err: ShortString): Boolean;

implementation

uses
  {$IFDEF UNIX}BaseUnix, Unix, ChnUnix,{$ENDIF} SysUtils, Classes, DateUtils, uString;

{$IFDEF UNIX}{$I unix/chnos.inc}{$ENDIF}
{$IFDEF WINDOWS}{$I win/chnos.inc}{$ENDIF}

function OsFileLoad(const Path: AnsiString; out Content: AnsiString; out Err: ShortString): Boolean;
var
  S: TFileStream;
begin
  Content := '';
  Err := '';
  try
    S := TFileStream.Create(Path, fmOpenRead or fmShareDenyNone);
    try
      SetLength(Content, S.Size);
      if S.Size > 0 then
        S.ReadBuffer(Content[1], S.Size);
    finally
      S.Free;
    end;
  except
    on X: Exception do
      Err := Path + ': ' + X.Message;
  end;
  Result := Err = '';
end;

function OsFileSave(const Path: AnsiString; const Content: AnsiString; out Err: ShortString): Boolean;
var
  S: TFileStream;
begin
  Err := '';
  try
    S := TFileStream.Create(Path, fmCreate);
    try
      if Content <> '' then
        S.WriteBuffer(Content[1], Length(Content));
    finally
      S.Free;
    end;
  except
    on X: Exception do
      Err := Path + ': ' + X.Message;
  end;
  Result := Err = '';
end;

end.
