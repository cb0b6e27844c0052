{ Tests of the DF1 example programs as built (build/bin), run through
  TProcess with a deadline: df1demo (master and slave over NAM=LOOP, full
  and half duplex) and df1echo against tools/df1sim on a pty. The wire
  bytes expected in df1demo's output were worked out by hand from the CRC
  (CRC-16, poly $A001, over DST..data and ETX) and BCC (two's complement
  of the byte sum) definitions. }
unit TestDf1Examples;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, BinSupport, TestSupport;

type
  TTestDf1Examples = class(TTestCase)
  published
    procedure TestDf1DemoAllOk;
    procedure TestDf1EchoAgainstSim;
    {$IFDEF UNIX}
    { needs /bin/sh (an empty argument) and df1sim --pty }
    procedure TestDf1ReadAddresses;
    { df1write, df1read and readn7 against df1sim --pty }
    procedure TestDf1WriteThenRead;
    {$ENDIF}
  end;

implementation

procedure TTestDf1Examples.TestDf1DemoAllOk;
var
  Output: string;
begin
  AssertTrue(BinPath('df1demo') + ' missing (make examples)', FileExists(BinPath('df1demo')));
  AssertEquals('exit code (-1: still running after 10 s)', 0,
    RunBin('df1demo', [], 10000, Output));
  AssertTrue('all exchanges ok:'#10 + Output, Pos('df1demo: all exchanges ok', Output) > 0);
  AssertEquals('two echoes ok', 2, CountOf(#10'echo ok', Output));
  { full duplex, CRC: Echo 'Ahoj' TNS 10 from 1 to 2, and the slave's reply }
  AssertTrue('master frame', Pos('master -> Echo STS=$00 TNS=10 data: 41 68 6F 6A   ' +
    '[10 02 02 01 06 00 0A 00 00 41 68 6F 6A 10 03 E3 88]', Output) > 0);
  AssertTrue('slave reply frame', Pos('slave  -> reply CMD=$46 STS=$00 TNS=10 data: 41 68 6F 6A   ' +
    '[10 02 01 02 46 00 0A 00 41 68 6F 6A 10 03 6B 86]', Output) > 0);
  { half duplex, BCC, station 16: DLE bytes doubled, a poll, the reply }
  AssertTrue('half-duplex master frame', Pos('[10 01 10 10 10 02 10 10 01 06 00 0B 00 00 ' +
    '41 10 10 42 10 03 3B]', Output) > 0);
  AssertTrue('poll', Pos('master -> poll   [10 05 10 10 F0]', Output) > 0);
  AssertTrue('half-duplex reply', Pos('[10 02 01 10 10 46 00 0B 00 41 10 10 42 10 03 0B]',
    Output) > 0);
  AssertEquals('the slave took both final ACKs', 2, CountOf('slave  <- ACK', Output));
end;

procedure TTestDf1Examples.TestDf1EchoAgainstSim;
var
  {$IFDEF UNIX}
  Sim: TProcess;
  Pty: string;
  {$ENDIF}
  Output: string;
  Code: Integer;
begin
  AssertTrue(BinPath('df1echo') + ' missing (make examples)', FileExists(BinPath('df1echo')));
  {$IFDEF UNIX}
  { df1sim --pty needs a Unix pty; on Windows tools/wintest.sh runs
    df1echo.exe under Wine against the Linux df1sim instead }
  Sim := StartSimPty(['--timeout=10', '--quiet'], Pty);
  try
    AssertTrue('df1sim printed its pty', Pty <> '');
    Code := RunBin('df1echo', ['NAM=DF1', 'NOD=0', 'DNO=1', 'FHD=FULL', 'CRC=ON', 'NAM=COM',
      'DEV=' + Pty, 'BD=19200'], 10000, Output);
    AssertEquals('df1echo exit code:'#10 + Output, 0, Code);
    AssertTrue('Ok', Pos(#10'Ok'#10, Output) > 0);
    AssertTrue('the reply logged', Pos('master <- reply CMD=$46 STS=$00 TNS=0 data: 41 68 6F 6A',
      Output) > 0);
  finally
    StopProcess(Sim);
  end;
  {$ENDIF}
  Code := RunBin('df1echo', ['NAM=DF1', 'XYZ=1', 'NAM=LOOP'], 10000, Output);
  AssertEquals('bad parameter: a command-line error, exit 2', 2, Code);
  AssertTrue('says which:'#10 + Output, Pos('XYZ', Output) > 0);
end;

{ df1read's address argument: an empty one is a setup error (it crashed
  on Addr[1]); file 255 goes out as $FF $FF $00 (a lone $FF is the escape
  of the 3-address fields, 1770-6.5.16 p. 7-17), so the simulator finds no
  such file (EXT STS $06) instead of an illegal format. }
{$IFDEF UNIX}
procedure TTestDf1Examples.TestDf1ReadAddresses;
var
  Sim: TProcess;
  Pty, Output: string;
  Code: Integer;
begin
  AssertTrue(BinPath('df1read') + ' missing (make examples)', FileExists(BinPath('df1read')));
  Code := RunExe('/bin/sh', ['-c', BinShellWord('df1read') + ' "" NAM=DF1 NAM=LOOP'], 10000, Output);
  AssertEquals('empty address: a command-line error, exit 2'#10 + Output, 2, Code);
  AssertTrue('says why:'#10 + Output, Pos('address', Output) > 0);
  Sim := StartSimPty(['--timeout=10', '--quiet'], Pty);
  try
    AssertTrue('df1sim printed its pty', Pty <> '');
    Code := RunBin('df1read', ['N255:0', '1', 'NAM=DF1', 'NOD=0', 'DNO=1', 'NAM=COM',
      'DEV=' + Pty, 'BD=19200'], 10000, Output);
    AssertEquals('error reply: exit 3'#10 + Output, 3, Code);
    AssertTrue('file 255 encoded as $FF $FF $00:'#10 + Output,
      Pos('data: 02 FF FF 00 89 00 00', Output) > 0);
    AssertTrue('no such file:'#10 + Output, Pos('EXT STS', Output) + Pos('usable', Output) > 0);
  finally
    StopProcess(Sim);
  end;
end;

procedure TTestDf1Examples.TestDf1WriteThenRead;
var
  Sim: TProcess;
  Pty, Output: string;
  Code: Integer;

  function Params: string;
  begin
    Result := 'NAM=DF1 NOD=0 DNO=1 NAM=COM BD=19200 DEV=' + Pty;
  end;

  procedure Run(const Prog: string; const Args: array of string; Want: Integer);
  var
    All: array of string;
    I: Integer;
  begin
    SetLength(All, Length(Args) + 1);
    for I := 0 to High(Args) do
      All[I] := Args[I];
    All[High(All)] := Params;
    { the parameter string as one argument: the programs join them anyway }
    Code := RunExe(BinPath(Prog), All, 10000, Output);
    AssertEquals(Prog + ' ' + Args[0] + ': exit code'#10 + Output, Want, Code);
  end;

begin
  AssertTrue(BinPath('df1write') + ' missing (make examples)', FileExists(BinPath('df1write')));
  AssertTrue(BinPath('readn7') + ' missing (make examples)', FileExists(BinPath('readn7')));
  Sim := StartSimPty(['--timeout=20', '--quiet'], Pty);
  try
    AssertTrue('df1sim printed its pty', Pty <> '');
    { the README's program: N7:0 of the built-in table is 0 }
    AssertEquals('readn7', 0, RunBin('readn7', [Pty], 10000, Output));
    AssertEquals('readn7 output', 'N7:0 = 0', Trim(Output));
    Run('df1write', ['N7:0', '-7', '8'], 0);
    Run('df1read', ['N7:0', '2'], 0);
    AssertTrue(Output, Pos('N7:0 = -7'#10'N7:1 = 8', Output) > 0);
    AssertEquals('readn7 sees the write', 0, RunBin('readn7', [Pty], 10000, Output));
    AssertEquals('N7:0 = -7', Trim(Output));
    Run('df1write', ['B3:1/4', '1'], 0);
    AssertTrue('a masked write went out:'#10 + Output,
      Pos('Protected Typed Logical Masked Write (3 addr)', Output) > 0);
    Run('df1read', ['B3:1', '1'], 0);
    AssertTrue(Output, Pos('B3:1 = $8010', Output) > 0);
    Run('df1write', ['F8:2', '0.25'], 0);
    Run('df1read', ['F8:2', '1'], 0);
    AssertTrue(Output, Pos('F8:2 = 0.25', Output) > 0);
    Run('df1write', ['T4:2.PRE', '250'], 0);
    Run('df1read', ['T4:2.PRE', '1'], 0);
    AssertTrue(Output, Pos('T4:2.PRE = 250', Output) > 0);
    Run('df1write', ['C5:1.ACC', '6'], 0);
    Run('df1read', ['C5:1', '1'], 0);
    AssertTrue(Output, Pos('C5:1 = $0000 0 6', Output) > 0);
    Run('df1write', ['ST10:1', 'two words'], 0);
    Run('df1read', ['ST10:1'], 0);
    AssertTrue(Output, Pos('ST10:1 = "two words"', Output) > 0);
    Run('df1write', ['L11:2', '-99999'], 0);
    Run('df1read', ['L11:2', '1'], 0);
    AssertTrue(Output, Pos('L11:2 = -99999', Output) > 0);
    Run('df1read', ['R6:0.LEN', '1'], 0);
    AssertTrue(Output, Pos('R6:0.LEN = 8', Output) > 0);
    { refusals: a value out of range and a bad address before anything is
      opened (command-line errors, exit 2), an address the PLC does not
      have after }
    Run('df1write', ['N7:0', '40000'], 2);
    AssertTrue(Output, Pos('value 40000 for N7:0 is not -32768..32767', Output) > 0);
    Run('df1write', ['B3:1/4', '2'], 2);
    Run('df1read', ['N7:0.ACC', '1'], 2);
    AssertTrue(Output, Pos('".ACC"', Output) > 0);
    Run('df1write', ['N99:0', '1'], 3);
    AssertTrue(Output, Pos('EXT STS $06', Output) > 0);
  finally
    StopProcess(Sim);
  end;
end;
{$ENDIF}

initialization
  RegisterTest(TTestDf1Examples);
end.
