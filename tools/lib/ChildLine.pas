{ ChildLine - the first line a started program prints (df1sim's "PTY ..."
  or "LISTEN ..."), for the tests and benchmarks that start one. }
unit ChildLine;

{$MODE OBJFPC}{$H-}

interface

uses
  Process;

{ The first line of P's output (P started with poUsePipes), without its end
  (LF or CR LF); what came before the deadline when no line end came within
  TimeoutMs, '' when nothing did. Reads byte by byte, so nothing after the
  line is taken from the pipe. }
function ReadFirstLine(P: TProcess; TimeoutMs: LongInt): AnsiString;

implementation

uses
  SysUtils;

function ReadFirstLine(P: TProcess; TimeoutMs: LongInt): AnsiString;
var
  C: Char;
  Deadline: QWord;
begin
  Result := '';
  Deadline := GetTickCount64 + QWord(TimeoutMs);
  repeat
    if P.Output.NumBytesAvailable > 0 then
    begin
      P.Output.Read(C, 1);
      if C = #10 then
        Break;
      Result := Result + C;
    end
    else
      Sleep(2);               { a child's start-up, not a library wait }
  until GetTickCount64 > Deadline;
  if (Result <> '') and (Result[Length(Result)] = #13) then
    SetLength(Result, Length(Result) - 1);
end;

end.
