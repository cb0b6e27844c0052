{ ChnLadder - a trace drawn as a sequence (ladder) diagram in SVG, for
  chndecode --svg: two lanes (the traced side on the left, the other end
  on the right), time downwards, one arrow per decoded frame (tx left to
  right, rx right to left) labelled with its decoded summary; a broken
  frame is red, a frame that reports a failure (NAK, an error reply) dark
  orange; a pause longer than GapMs between two frames is marked
  with its length. Each arrow carries the whole description as a <title>,
  which a browser shows on hover.

  Plain SVG 1.1 with no script and no external reference: readable in a
  browser, printable (white background, black lines), and rendered by
  rsvg-convert. Pure: returns the text. }
unit ChnLadder;

{$I chn.inc}

interface

uses
  ChnTrcFormat, ChnFrameDecode;

type
  tLadderOptions = record
    Title    : AnsiString;
    LeftName : AnsiString;   { the side that wrote the trace (tx) }
    RightName: AnsiString;   { the other end (rx) }
    GapMs    : LongInt;      { mark pauses longer than this; 0 = never }
  end;

procedure LadderDefaults(var Opt: tLadderOptions);
{ The summary on an arrow: the description without its data bytes, at
  most 108 characters. }
function LadderLabel(const E: tDecEvent): AnsiString;
function LadderSvg(const Events: tDecEvents; Count: LongInt;
  const Opt: tLadderOptions): AnsiString;

implementation

uses
  SysUtils;

const
  Width    = 1000;
  LeftX    = 170;
  RightX   = 960;
  TopY     = 90;
  RowH     = 34;
  GapH     = 30;
  MaxLabel = 108;

procedure LadderDefaults(var Opt: tLadderOptions);
begin
  Opt.Title := 'trace';
  Opt.LeftName := 'this side (tx)';
  Opt.RightName := 'other end (rx)';
  Opt.GapMs := 1000;
end;

function Esc(const S: AnsiString): AnsiString;
var
  I: Integer;
begin
  Result := '';
  for I := 1 to Length(S) do
    case S[I] of
      '&': Result := Result + '&amp;';
      '<': Result := Result + '&lt;';
      '>': Result := Result + '&gt;';
      '"': Result := Result + '&quot;';
      #0..#8, #11, #12, #14..#31, #127..#255: Result := Result + '?';   { not UTF-8 text }
    else
      Result := Result + S[I];
    end;
end;

function LadderLabel(const E: tDecEvent): AnsiString;
var
  P, Q: Integer;
begin
  Result := E.Text;
  { 'N data bytes: 41 68 6F 6A, CRC ...' -> 'N data bytes, CRC ...' }
  P := Pos(' data bytes: ', Result);
  if P = 0 then
    P := Pos(' numbers: ', Result);
  if P > 0 then
  begin
    P := Pos(':', Copy(Result, P, MaxInt)) + P - 1;
    Q := P + 1;
    while (Q <= Length(Result)) and (Result[Q] in ['0'..'9', 'A'..'F', ' ', '-']) do
      Inc(Q);
    Delete(Result, P, Q - P);
  end;
  Result := E.Proto + ' ' + Result;
  if Length(Result) > MaxLabel then
    Result := Copy(Result, 1, MaxLabel - 3) + '...';
end;

function Num(N: LongInt): AnsiString;
begin
  Result := IntToStr(N);
end;

function GapText(Ms: LongInt): AnsiString;
begin
  if Ms >= 1000 then
    Result := Format('%d.%.3d s', [Ms div 1000, Ms mod 1000])
  else
    Result := Format('%d ms', [Ms]);
end;

{ The dashed line across both ends for a pause longer than the option. }
function GapRow(Y, Delta, GapMs: LongInt): AnsiString;
begin
  Result := '<g class="gap">' +
    '<line x1="10" y1="' + Num(Y + 4) + '" x2="' + Num(Width - 10) + '" y2="' + Num(Y + 4) +
    '" stroke="#888" stroke-dasharray="6,4"/>' +
    '<text x="' + Num((LeftX + RightX) div 2) + '" y="' + Num(Y + 20) +
    '" text-anchor="middle" fill="#555" font-style="italic">' +
    Esc(GapText(Delta) + ' without a frame (more than ' + GapText(GapMs) + ')') +
    '</text></g>' + LineEnding;
end;

{ One frame's arrow, its time, the time since the one before (First: none)
  and its label; red for an error, orange for a refusal. }
function FrameRow(const E: tDecEvent; Y, Delta: LongInt; First: Boolean): AnsiString;
var
  X1, X2: LongInt;
  Colour, Marker, Cls: AnsiString;
begin
  if E.IsError then
  begin
    Colour := '#c00000';
    Marker := 'url(#headerr)';
    Cls := 'frame error';
  end
  else if E.Refused then
  begin
    Colour := '#b05000';
    Marker := 'url(#headref)';
    Cls := 'frame refused';
  end
  else
  begin
    Colour := '#000000';
    Marker := 'url(#head)';
    Cls := 'frame';
  end;
  X1 := RightX;
  X2 := LeftX;
  if E.Dir = trcTx then
  begin
    X1 := LeftX;
    X2 := RightX;
  end;
  Result := '<g class="' + Cls + '"><title>' +
    Esc(TrcTimeText(E.TimeMs) + ' ' + E.Proto + ' ' + E.Text) + '</title>' +
    '<text x="10" y="' + Num(Y + 24) + '" font-size="11" fill="#333">' +
    TrcTimeText(E.TimeMs) + '</text>';
  if not First then
    Result := Result + '<text x="10" y="' + Num(Y + 12) + '" font-size="9" fill="#777">+' +
      Esc(GapText(Delta)) + '</text>';
  Result := Result +
    '<text x="' + Num((LeftX + RightX) div 2) + '" y="' + Num(Y + 14) +
    '" text-anchor="middle" fill="' + Colour + '">' + Esc(LadderLabel(E)) + '</text>' +
    '<line x1="' + Num(X1) + '" y1="' + Num(Y + 20) + '" x2="' + Num(X2) + '" y2="' +
    Num(Y + 24) + '" stroke="' + Colour + '" stroke-width="1.5" marker-end="' + Marker + '"/>' +
    '</g>' + LineEnding;
end;

{ The picture around the rows: the title, the arrow heads, both ends. }
function Frame(const Opt: tLadderOptions; Height, Count, Gaps: LongInt;
  const Body: AnsiString): AnsiString;
begin
  Result :=
    '<?xml version="1.0" encoding="UTF-8"?>' + LineEnding +
    '<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="' + Num(Width) +
    '" height="' + Num(Height) + '" viewBox="0 0 ' + Num(Width) + ' ' + Num(Height) +
    '" font-family="DejaVu Sans Mono, monospace" font-size="12">' + LineEnding +
    '<title>' + Esc(Opt.Title) + '</title>' + LineEnding +
    '<defs>' +
    '<marker id="head" markerWidth="10" markerHeight="8" refX="9" refY="4" orient="auto">' +
    '<path d="M0,0 L10,4 L0,8 z" fill="#000000"/></marker>' +
    '<marker id="headerr" markerWidth="10" markerHeight="8" refX="9" refY="4" orient="auto">' +
    '<path d="M0,0 L10,4 L0,8 z" fill="#c00000"/></marker>' +
    '<marker id="headref" markerWidth="10" markerHeight="8" refX="9" refY="4" orient="auto">' +
    '<path d="M0,0 L10,4 L0,8 z" fill="#b05000"/></marker>' +
    '</defs>' + LineEnding +
    '<rect x="0" y="0" width="' + Num(Width) + '" height="' + Num(Height) + '" fill="#ffffff"/>' +
    LineEnding +
    '<text x="10" y="22" font-size="14" font-weight="bold">' + Esc(Opt.Title) + '</text>' +
    '<text x="' + Num(Width - 10) + '" y="22" text-anchor="end" fill="#555">' +
    Num(Count) + ' frames, ' + Num(Gaps) + ' pauses marked</text>' + LineEnding +
    '<text x="' + Num(LeftX) + '" y="' + Num(TopY - 16) + '" text-anchor="middle" font-weight="bold">' +
    Esc(Opt.LeftName) + '</text>' +
    '<text x="' + Num(RightX) + '" y="' + Num(TopY - 16) + '" text-anchor="end" font-weight="bold">' +
    Esc(Opt.RightName) + '</text>' + LineEnding +
    '<line x1="' + Num(LeftX) + '" y1="' + Num(TopY - 8) + '" x2="' + Num(LeftX) + '" y2="' +
    Num(Height - 20) + '" stroke="#444" stroke-width="2"/>' +
    '<line x1="' + Num(RightX) + '" y1="' + Num(TopY - 8) + '" x2="' + Num(RightX) + '" y2="' +
    Num(Height - 20) + '" stroke="#444" stroke-width="2"/>' + LineEnding +
    Body +
    '</svg>' + LineEnding;
end;

function LadderSvg(const Events: tDecEvents; Count: LongInt;
  const Opt: tLadderOptions): AnsiString;
var
  Body: AnsiString;
  I, Y, Delta, Prev, Gaps: LongInt;
begin
  Body := '';
  Y := TopY;
  Prev := 0;
  Gaps := 0;
  for I := 0 to Count - 1 do
  begin
    Delta := 0;
    if I > 0 then
    begin
      Delta := Events[I].TimeMs - Prev;
      if Delta < 0 then
        Inc(Delta, TrcMsPerDay);             { past midnight }
    end;
    if (I > 0) and (Opt.GapMs > 0) and (Delta > Opt.GapMs) then
    begin
      Inc(Gaps);
      Body := Body + GapRow(Y, Delta, Opt.GapMs);
      Inc(Y, GapH);
    end;
    Prev := Events[I].TimeMs;
    Body := Body + FrameRow(Events[I], Y, Delta, I = 0);
    Inc(Y, RowH);
  end;
  Result := Frame(Opt, Y + 30, Count, Gaps, Body);
end;

end.
