{ ProcStat - what Linux's /proc says about a running process, for the
  benchmarks: its CPU time and its resident memory. }
unit ProcStat;

{$I chn.inc}

interface

uses
  BaseUnix;

{ utime + stime of a running process, in seconds (/proc/PID/stat). }
function ProcCpu(Pid: TPid): Double;
{ Its resident set (VmRSS of /proc/PID/status), in KiB; -1 when unknown. }
function ProcRssKb(Pid: TPid): LongInt;

implementation

uses
  Classes, SysUtils;

function sysconf(Name: cint): clong; cdecl; external 'c';

const
  _SC_CLK_TCK = 2;

function ProcCpu(Pid: TPid): Double;
var
  F: TStringList;
  S: AnsiString;
  Fields: TStringArray;
begin
  Result := 0;
  F := TStringList.Create;
  try
    F.LoadFromFile('/proc/' + IntToStr(Pid) + '/stat');
    S := F.Text;
    S := Copy(S, Pos(')', S) + 2, Length(S));   { after "pid (comm) " }
    Fields := S.Split([' ']);
    { fields 14 and 15 of stat(5), 12 and 13 here (state is the first) }
    Result := (StrToInt64(Fields[11]) + StrToInt64(Fields[12])) / sysconf(_SC_CLK_TCK);
  finally
    F.Free;
  end;
end;

function ProcRssKb(Pid: TPid): LongInt;
var
  F: TStringList;
  I: LongInt;
  S: AnsiString;
begin
  Result := -1;
  F := TStringList.Create;
  try
    F.LoadFromFile('/proc/' + IntToStr(Pid) + '/status');
    for I := 0 to F.Count - 1 do
      if Copy(F[I], 1, 6) = 'VmRSS:' then
      begin
        S := Trim(Copy(F[I], 7, MaxInt));
        S := Copy(S, 1, Pos(' ', S + ' ') - 1);
        Result := StrToIntDef(S, -1);
      end;
  finally
    F.Free;
  end;
end;

end.
