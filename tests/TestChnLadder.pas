{ Tests of ChnLadder (chndecode --svg): the arrow labels, the structure of
  the SVG (one arrow per frame in the right direction, errors red, pauses
  marked, text escaped), and that a diagram of a real DF1 trace is
  well-formed XML (xmllint) and renders (rsvg-convert to PNG); those two
  checks are skipped, with the reason, when the programs are missing. }
unit TestChnLadder;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, fpcunit, testregistry, ChnTrcFormat, ChnFrameDecode,
  ChnLadder, TestTempDir;

type
  TTestChnLadder = class(TTestCase)
  private
    Dir: string;
    function DemoSvg: AnsiString;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestLabel;
    procedure TestStructure;
    procedure TestPauseAcrossMidnight;
    procedure TestWellFormed;
    procedure TestRendersToPng;
    procedure TestChndecodeWritesSvg;
  end;

implementation

uses
  BinSupport, TestSupport;

const
  Df1Trace =
    '23:53:29.438 tx   17 | TRC'#10 +
    '1002 0100 0600 0000 0041 686F 6A10 0363 0F'#10 +
    '23:53:29.439 rx   18 | TRC'#10 +
    '1006 1002 0001 4600 0000 4168 6F6A 1003 3575'#10 +
    '23:53:29.439 tx   2 | TRC'#10 +
    '1006'#10 +
    '23:53:31.442 tx   18 | TRC'#10 +
    '1002 0100 0F00 0100 A214 0789 0000 1003 6047'#10 +
    '23:53:31.462 rx   2 | TRC'#10 +
    '1015'#10;

function Ev(Ms: LongInt; Dir: tTrcDir; const Text: AnsiString; Err: Boolean): tDecEvent;
begin
  Result.TimeMs := Ms;
  Result.Dir := Dir;
  Result.Line := 0;
  Result.Proto := 'DF1';
  Result.Text := Text;
  Result.IsError := Err;
  Result.Refused := False;
end;

procedure TTestChnLadder.SetUp;
begin
  Dir := MakeTempDir('chnladder');
end;

procedure TTestChnLadder.TearDown;
begin
  RemoveTempDir(Dir);
end;

{ The diagram of Df1Trace through the decoder, as chndecode draws it. }
function TTestChnLadder.DemoSvg: AnsiString;
var
  F: tTrcFrames;
  N, I: LongInt;
  D: tDecoder;
  Opt: tDecOptions;
  St: tDecStats;
  L: tLadderOptions;
begin
  N := TrcReadText(Df1Trace, F);
  AssertEquals(5, N);
  DecodeDefaults(Opt);
  DecodeBegin(D, Opt, nil);
  D.KeepEvents := True;
  for I := 0 to N - 1 do
    DecodeChunk(D, F[I]);
  DecodeEnd(D, St);
  AssertEquals('ACK, reply, ACK, bad frame, NAK, and the command', 6, D.EventCount);
  AssertEquals(1, St.Errors);
  LadderDefaults(L);
  L.Title := 'DF1 <demo> & test';
  Result := LadderSvg(D.Events, D.EventCount, L);
end;

procedure TTestChnLadder.TestLabel;
begin
  AssertEquals('DF1 DST=1 SRC=0 CMD=$06 FNC=$00 STS=$00 TNS=$0000 (Echo), 4 data bytes, CRC $0F63 ok',
    LadderLabel(Ev(0, trcTx, 'DST=1 SRC=0 CMD=$06 FNC=$00 STS=$00 TNS=$0000 (Echo), ' +
    '4 data bytes: 41 68 6F 6A, CRC $0F63 ok', False)));
  AssertEquals('DF1 ACK (DLE ACK)', LadderLabel(Ev(0, trcTx, 'ACK (DLE ACK)', False)));
  { a long description is cut to 108 characters }
  AssertEquals(108, Length(LadderLabel(Ev(0, trcTx, StringOfChar('x', 300), False))));
  AssertEquals('...', Copy(LadderLabel(Ev(0, trcTx, StringOfChar('x', 300), False)), 106, 3));
end;

procedure TTestChnLadder.TestStructure;
var
  E: tDecEvents;
  L: tLadderOptions;
  S: AnsiString;
begin
  SetLength(E, 4);
  E[0] := Ev(1000, trcTx, 'first <one>', False);
  E[1] := Ev(1002, trcRx, 'answer & more', False);
  E[2] := Ev(5002, trcTx, 'broken', True);      { 4 s later }
  E[3] := Ev(5003, trcRx, 'NAK', False);
  LadderDefaults(L);
  L.GapMs := 1000;
  S := LadderSvg(E, 4, L);
  AssertEquals('good frames', 3, CountOf('<g class="frame">', S));
  AssertEquals('broken frames', 1, CountOf('<g class="frame error">', S));
  AssertEquals('pauses', 1, CountOf('<g class="gap">', S));
  AssertTrue(Pos('4.000 s without a frame', S) > 0);
  AssertTrue('escaped', Pos('DF1 first &lt;one&gt;', S) > 0);
  AssertTrue('escaped', Pos('answer &amp; more', S) > 0);
  AssertEquals('no raw markup from the text', 0, Pos('<one>', S));
  { tx from the left lane (x 170) to the right (x 960), rx back }
  AssertEquals(2, CountOf('<line x1="170" y1=', S) - 1 { the left lane itself });
  AssertEquals(2, CountOf('<line x1="960" y1=', S) - 1);
  AssertEquals('red arrow', 1, CountOf('stroke="#c00000"', S));
  AssertTrue(Pos('</svg>', S) > 0);
  { with GapMs = 0 no pause is marked }
  L.GapMs := 0;
  AssertEquals(0, CountOf('<g class="gap">', LadderSvg(E, 4, L)));
  { no frames: still a diagram }
  AssertTrue(Pos('0 frames', LadderSvg(E, 0, L)) > 0);
end;

procedure TTestChnLadder.TestPauseAcrossMidnight;
var
  E: tDecEvents;
  L: tLadderOptions;
  S: AnsiString;
begin
  SetLength(E, 2);
  E[0] := Ev(TrcMsPerDay - 500, trcTx, 'a', False);
  E[1] := Ev(1000, trcRx, 'b', False);
  LadderDefaults(L);
  S := LadderSvg(E, 2, L);
  AssertTrue(S, Pos('1.500 s without a frame', S) > 0);
end;

procedure TTestChnLadder.TestWellFormed;
var
  Xmllint, Output: string;
begin
  Xmllint := ExeSearch('xmllint', GetEnvironmentVariable('PATH'));
  if Xmllint = '' then
    Ignore('xmllint is not installed (Debian package libxml2-utils): the SVG is not checked');
  WriteFileText(Dir + 'demo.svg', DemoSvg);
  AssertEquals(Output, 0, RunExe(Xmllint, ['--noout', Dir + 'demo.svg'], 30000, Output));
  { and xmllint does fail on a broken one }
  WriteFileText(Dir + 'bad.svg', StringReplace(DemoSvg, '</svg>', '', []));
  AssertTrue(RunExe(Xmllint, ['--noout', Dir + 'bad.svg'], 30000, Output) <> 0);
end;

procedure TTestChnLadder.TestRendersToPng;
var
  Rsvg, Output, Png: string;
  W: LongWord;
begin
  Rsvg := ExeSearch('rsvg-convert', GetEnvironmentVariable('PATH'));
  if Rsvg = '' then
    Ignore('rsvg-convert is not installed (Debian package librsvg2-bin): the SVG is not rendered');
  WriteFileText(Dir + 'demo.svg', DemoSvg);
  AssertEquals(Output, 0, RunExe(Rsvg, ['-o', Dir + 'demo.png', Dir + 'demo.svg'], 60000, Output));
  Png := ReadFileText(Dir + 'demo.png');
  AssertTrue('a PNG of some size', Length(Png) > 5000);
  AssertEquals(#$89'PNG'#13#10#$1A#10, Copy(Png, 1, 8));
  { IHDR: width, big-endian, at byte 16 }
  W := BEtoN(PLongWord(@Png[17])^);
  AssertEquals(1000, W);
end;

procedure TTestChnLadder.TestChndecodeWritesSvg;
var
  Output, S: string;
begin
  WriteFileText(Dir + 'df1.log', Df1Trace);
  { exit code 1: the trace holds a broken frame }
  AssertEquals(Output, 1, RunBin('chndecode', ['--df1', '--svg=' + Dir + 'df1.svg',
    '--gap=500', '--title=demo', Dir + 'df1.log'], 30000, Output));
  AssertTrue(Output, Pos('5 chunks, 57 bytes: 5 frames, 1 errors', Output) > 0);
  S := ReadFileText(Dir + 'df1.svg');
  AssertEquals(4, CountOf('<g class="frame">', S));
  AssertEquals(1, CountOf('<g class="frame error">', S));
  AssertEquals('the 2 s pause', 1, CountOf('<g class="gap">', S));
  AssertTrue(Pos('<title>demo</title>', S) > 0);
  AssertEquals('the NAK', 1, CountOf('<g class="frame refused">', S));
  AssertEquals(2, RunBin('chndecode', ['--svg=', Dir + 'df1.log'], 30000, Output));
  AssertEquals(2, RunBin('chndecode', ['--gap=x', Dir + 'df1.log'], 30000, Output));
  AssertTrue(Output, Pos('--gap wants a whole number 0..86400000 (--gap=x)', Output) > 0);
end;

initialization
  RegisterTest(TTestChnLadder);
end.
