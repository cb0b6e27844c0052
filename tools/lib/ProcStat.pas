{ ProcStat - what Linux's /proc says about a running process, for the
  benchmarks: its CPU time (in clock ticks, and in nanoseconds from the
  scheduler), how often it went to sleep, and its resident memory, whole
  and by what is mapped. }
unit ProcStat;

{$I chn.inc}

interface

uses
  BaseUnix;

{ utime + stime of a running process, in seconds (/proc/PID/stat). }
function ProcCpu(Pid: TPid): Double;
{ Its resident set (VmRSS of /proc/PID/status), in KiB; -1 when unknown. }
function ProcRssKb(Pid: TPid): LongInt;
{ Nanoseconds it ran on a CPU (/proc/PID/schedstat: the scheduler's own
  count, not rounded to clock ticks); -1 when unknown. }
function ProcRunNs(Pid: TPid): Int64;
{ Times it went to sleep by itself (voluntary_ctxt_switches): its
  wake-ups; -1 when unknown. }
function ProcSleeps(Pid: TPid): Int64;
{ Its resident set by what is mapped (/proc/PID/smaps): "NAME KiB" per
  file (the base name), "[heap] KiB" for the C library's malloc (brk),
  "[stack] KiB", and "anonymous KiB" for the other memory not backed by a
  file (a Free Pascal program's heap, the libraries' zeroed data), largest
  first, comma-separated. }
function ProcRssByMapping(Pid: TPid): AnsiString;

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

function ProcRunNs(Pid: TPid): Int64;
var
  F: TStringList;
begin
  F := TStringList.Create;
  try
    try
      F.LoadFromFile('/proc/' + IntToStr(Pid) + '/schedstat');
      Result := StrToInt64Def(Copy(F.Text, 1, Pos(' ', F.Text) - 1), -1);
    except
      Result := -1;
    end;
  finally
    F.Free;
  end;
end;

function ProcSleeps(Pid: TPid): Int64;
var
  F: TStringList;
  I: LongInt;
begin
  Result := -1;
  F := TStringList.Create;
  try
    try
      F.LoadFromFile('/proc/' + IntToStr(Pid) + '/status');
    except
      Exit;
    end;
    for I := 0 to F.Count - 1 do
      if Copy(F[I], 1, 24) = 'voluntary_ctxt_switches:' then
        Result := StrToInt64Def(Trim(Copy(F[I], 25, MaxInt)), -1);
  finally
    F.Free;
  end;
end;

{ A /proc file whole: they say size 0 and give a page per read, which
  TStringList.LoadFromFile takes for the end. }
function ReadProcFile(const Name: AnsiString): AnsiString;
var
  H, N: LongInt;
  Chunk: array[0..65535] of Char;
begin
  Result := '';
  H := FileOpen(Name, fmOpenRead);
  if H < 0 then
    Exit;
  repeat
    N := FileRead(H, Chunk, SizeOf(Chunk));
    if N > 0 then
      Result := Result + Copy(Chunk, 0, N);
  until N <= 0;
  FileClose(H);
end;

function ProcRssByMapping(Pid: TPid): AnsiString;
var
  F, Sum: TStringList;
  I, K, Best: LongInt;
  Line, Name, Field: AnsiString;
  Words: TStringArray;
begin
  Result := '';
  F := TStringList.Create;
  Sum := TStringList.Create;
  try
    F.Text := ReadProcFile('/proc/' + IntToStr(Pid) + '/smaps');
    Name := 'anonymous';
    for Line in F do
    begin
      Words := Line.Split([' '], TStringSplitOptions.ExcludeEmpty);
      if Length(Words) = 0 then
        Continue;
      Field := Words[0];
      if (Pos('-', Field) > 1) and (Field[Length(Field)] <> ':') then
      begin
        { a mapping's header: ADDR-ADDR PERMS OFFSET DEV INODE [PATH] }
        if (Length(Words) >= 6) and (Words[5][1] = '/') then
          Name := ExtractFileName(Words[5])
        else if Length(Words) >= 6 then
          Name := Words[5]           { [heap] (the C library's malloc), [stack] }
        else
          Name := 'anonymous';
      end
      else if (Field = 'Rss:') and (Length(Words) >= 2) then
      begin
        K := Sum.IndexOfName(Name);
        if K < 0 then
          Sum.Values[Name] := Words[1]
        else
          Sum.ValueFromIndex[K] := IntToStr(StrToInt(Sum.ValueFromIndex[K]) + StrToInt(Words[1]));
      end;
    end;
    { largest first }
    while Sum.Count > 0 do
    begin
      Best := 0;
      for I := 1 to Sum.Count - 1 do
        if StrToInt(Sum.ValueFromIndex[I]) > StrToInt(Sum.ValueFromIndex[Best]) then
          Best := I;
      if StrToInt(Sum.ValueFromIndex[Best]) > 0 then
      begin
        if Result <> '' then
          Result := Result + ', ';
        Result := Result + Sum.Names[Best] + ' ' + Sum.ValueFromIndex[Best];
      end;
      Sum.Delete(Best);
    end;
  finally
    Sum.Free;
    F.Free;
  end;
end;

end.
