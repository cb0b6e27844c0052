{ ChnFT12Gap - the default GAP= the FT 1.2 tools set (docs/ChnFT1_2.md,
  "GAP"): with GAP=0 one corrupted length byte makes a receiver wait for
  up to 255 bytes that never belong to one frame, and every request in
  them goes unanswered. IEC 60870-5-2 allows no idle time inside a frame,
  so a receiver may drop a half frame once the line has been quiet for
  longer than a USB adapter's burst (up to 16 ms) plus margin: 50 ms, in
  character times at the line's BD=. }
unit ChnFT12Gap;

{$I chn.inc}

interface

uses
  ChnVirt;

const
  FT12DefaultGapMs = 50;

{ GAP= in character times (11 bits) for FT12DefaultGapMs at Baud. }
function FT12GapChars(Baud: LongInt): LongInt;
{ Chn: an FT 1.2 channel built from Params, not yet open. When Params sets
  no GAP=, give it FT12GapChars of the BD= of the layers below (9600 when
  none has one, as the layer itself assumes). Returns the GAP= token set,
  or '' when Params had one. }
function FT12SetDefaultGap(Chn: pChnVirt; const Params: AnsiString): AnsiString;

implementation

uses
  SysUtils, uString;

function FT12GapChars(Baud: LongInt): LongInt;
begin
  if Baud <= 0 then
    Baud := 9600;
  Result := (Int64(FT12DefaultGapMs) * Baud + 10999) div 11000;
  if Result < 1 then
    Result := 1
  else if Result > 10000 then
    Result := 10000;
end;

function FT12SetDefaultGap(Chn: pChnVirt; const Params: AnsiString): AnsiString;
var
  Bd: AnsiString;
  Baud: LongInt;
begin
  Result := '';
  if Pos('GAP=', UpperCase(Params)) > 0 then
    Exit;
  Bd := Chn^.ChGetParam('BD');
  Baud := 9600;
  if Copy(Bd, 1, 3) = 'BD=' then
    if not StrToNum(Trim(Copy(Bd, 4, 20)), 1, MaxLongInt, Baud) then
      Baud := 9600;
  Result := 'GAP=' + IntToStr(FT12GapChars(Baud));
  Chn^.ChSetParam(Result);
end;

end.
