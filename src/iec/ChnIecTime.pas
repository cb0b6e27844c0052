{ ChnIecTime - the time tags of IEC 60870-5-101/104, without I/O:
  CP24Time2a (ms, minute) and CP56Time2a (ms, minute, hour, day of month
  and of week, month, year) with IV and SU, their octets, the checks of
  their fields and the conversions to and from a TDateTime.

  Octets (IEC 60870-5-101 clause 7.2.6.18; 7.2.6.19 the CP24Time2a):
    ms low, ms high, IV RES1 minute(6), SU RES2 hour(5),
    day of week(3) day of month(5), RES3 month(4), RES4 year(7)
  the first three alone are a CP24Time2a. Reserved bits are dropped when
  read and sent as 0.

  ChnIec101Asdu puts these tags into the information objects and gives
  the same names to programs that use it alone. }
unit ChnIecTime;

{$I chn.inc}

interface

type
  { A CP56Time2a, or the ms and minute (and IV) of a CP24Time2a. Fields
    hold what the wire bits hold; the encoder refuses what does not fit
    them; IecTimeValid tells a real date. Reserved bits are dropped. }
  tIecTime = packed record
    Msec     : Word;      {< milliseconds of the minute, 0..59999 }
    Minute   : Byte;      {< 0..59 }
    Hour     : Byte;      {< 0..23 }
    Day      : Byte;      {< day of the month 1..31 }
    DayOfWeek: Byte;      {< 1 Monday .. 7 Sunday, 0 not used }
    Month    : Byte;      {< 1..12 }
    Year     : Byte;      {< 0..99, years of the century }
    Invalid  : Boolean;   {< IV }
    Summer   : Boolean;   {< SU }
  end;

  tIecTimeKind = (tkNone, tkCP24, tkCP56);

{ The fields of a time from a TDateTime (DayOfWeek filled, IV and SU
  clear) and back; IecTimeToDateTime is False for a time that is no date
  (month 13, minute 60 ...), DT then 0. A CP24Time2a gives only minutes
  and ms: use IecTimeValid with Short. }
function IecTimeFromDateTime(DT: TDateTime): tIecTime;
function IecTimeToDateTime(const T: tIecTime; out DT: TDateTime): Boolean;
{ True for a real time (Short: only Msec and Minute), else False with Err
  naming the field and its range. }
function IecTimeValid(const T: tIecTime; Short: Boolean; out Err: ShortString): Boolean;
{ True when the fields fit the bits of a tag of kind K (a minute up to
  63, a month up to 15 ...: what the wire can carry, real or not), else
  False with Err naming the field. }
function IecTimeFits(const T: tIecTime; K: tIecTimeKind; out Err: ShortString): Boolean;
{ Octets of a tag of kind K: 3, 7, or 0 for tkNone. }
function IecTimeLen(K: tIecTimeKind): LongInt;
{ A CP24Time2a or CP56Time2a at B[At]; the caller checks that B is long
  enough (IecTimeLen) and, before IecPutTime, that T fits (IecTimeFits). }
procedure IecPutTime(const T: tIecTime; K: tIecTimeKind; var B: array of Byte; At: LongInt);
procedure IecGetTime(const B: array of Byte; At: LongInt; K: tIecTimeKind; out T: tIecTime);

implementation

uses
  SysUtils, DateUtils;

function IecTimeFromDateTime(DT: TDateTime): tIecTime;
var
  Y, Mo, D, H, Mi, S, Ms: Word;
begin
  DecodeDateTime(DT, Y, Mo, D, H, Mi, S, Ms);
  FillChar(Result, SizeOf(Result), 0);
  Result.Msec := S * 1000 + Ms;
  Result.Minute := Mi;
  Result.Hour := H;
  Result.Day := D;
  Result.DayOfWeek := DayOfTheWeek(DT);   { ISO: 1 Monday .. 7 Sunday }
  Result.Month := Mo;
  Result.Year := Y mod 100;
end;

function IecTimeValid(const T: tIecTime; Short: Boolean; out Err: ShortString): Boolean;
begin
  Err := '';
  if T.Msec > 59999 then
    Err := 'milliseconds ' + IntToStr(T.Msec) + ' (0..59999)'
  else if T.Minute > 59 then
    Err := 'minute ' + IntToStr(T.Minute) + ' (0..59)'
  else if not Short then
    if T.Hour > 23 then
      Err := 'hour ' + IntToStr(T.Hour) + ' (0..23)'
    else if (T.Month < 1) or (T.Month > 12) then
      Err := 'month ' + IntToStr(T.Month) + ' (1..12)'
    else if (T.Day < 1) or (T.Day > DaysInAMonth(2000 + T.Year, T.Month)) then
      Err := 'day ' + IntToStr(T.Day) + ' (1..' + IntToStr(DaysInAMonth(2000 + T.Year, T.Month)) + ')'
    else if T.DayOfWeek > 7 then
      Err := 'day of week ' + IntToStr(T.DayOfWeek) + ' (0..7)'
    else if T.Year > 99 then
      Err := 'year ' + IntToStr(T.Year) + ' (0..99)';
  Result := Err = '';
end;

function IecTimeToDateTime(const T: tIecTime; out DT: TDateTime): Boolean;
var
  E: ShortString;
begin
  DT := 0;
  Result := IecTimeValid(T, False, E);
  if Result then
    DT := EncodeDateTime(2000 + T.Year, T.Month, T.Day, T.Hour, T.Minute,
      T.Msec div 1000, T.Msec mod 1000);
end;

function IecTimeFits(const T: tIecTime; K: tIecTimeKind; out Err: ShortString): Boolean;
begin
  Err := '';
  if T.Minute > 63 then
    Err := 'minute ' + IntToStr(T.Minute)
  else if K = tkCP56 then
    if T.Hour > 31 then
      Err := 'hour ' + IntToStr(T.Hour)
    else if T.Day > 31 then
      Err := 'day ' + IntToStr(T.Day)
    else if T.DayOfWeek > 7 then
      Err := 'day of week ' + IntToStr(T.DayOfWeek)
    else if T.Month > 15 then
      Err := 'month ' + IntToStr(T.Month)
    else if T.Year > 127 then
      Err := 'year ' + IntToStr(T.Year);
  Result := Err = '';
end;

function IecTimeLen(K: tIecTimeKind): LongInt;
begin
  case K of
    tkCP24: Result := 3;
    tkCP56: Result := 7;
  else
    Result := 0;
  end;
end;

procedure IecPutTime(const T: tIecTime; K: tIecTimeKind; var B: array of Byte; At: LongInt);
begin
  B[At] := Lo(T.Msec);
  B[At + 1] := Hi(T.Msec);
  B[At + 2] := T.Minute or (Ord(T.Invalid) shl 7);
  if K = tkCP56 then
  begin
    B[At + 3] := T.Hour or (Ord(T.Summer) shl 7);
    B[At + 4] := T.Day or (T.DayOfWeek shl 5);
    B[At + 5] := T.Month;
    B[At + 6] := T.Year;
  end;
end;

procedure IecGetTime(const B: array of Byte; At: LongInt; K: tIecTimeKind; out T: tIecTime);
begin
  FillChar(T, SizeOf(T), 0);
  T.Msec := B[At] or (Word(B[At + 1]) shl 8);
  T.Minute := B[At + 2] and $3F;
  T.Invalid := B[At + 2] and $80 <> 0;
  if K = tkCP56 then
  begin
    T.Hour := B[At + 3] and $1F;
    T.Summer := B[At + 3] and $80 <> 0;
    T.Day := B[At + 4] and $1F;
    T.DayOfWeek := B[At + 4] shr 5;
    T.Month := B[At + 5] and $0F;
    T.Year := B[At + 6] and $7F;
  end;
end;

end.
