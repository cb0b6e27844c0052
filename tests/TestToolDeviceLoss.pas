{ Every tool that holds a line ends at once, non-zero, when its device
  goes away, and says so: the device is a pty the test creates, and
  closing its master side hangs the program's side up, as a USB adapter
  that is pulled. ft12master used to wait out its timeout, comraw and
  df1sim --dev exited 0. (chntap is the exception by design: it reopens a
  lost side, tests/TestChnTap.) Unix only (ptys). }
unit TestToolDeviceLoss;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, fpcunit, testregistry, BinSupport
  {$IFDEF UNIX}, BaseUnix, PtyPair{$ENDIF};

type
  TTestToolDeviceLoss = class(TTestCase)
  {$IFDEF UNIX}
  private
    procedure LossEnds(const Prog: string; const Args: array of string;
      const Expect: string; StartMs: Integer = 500);
  published
    procedure TestComraw;
    procedure TestFT12Master;
    procedure TestDf1SimDev;
    procedure TestDf1Slave;
    procedure TestWaitany;
    procedure TestFT12Slave;
  {$ENDIF}
  end;

implementation

uses
  ChnVirt;

{$IFDEF UNIX}
{ Prog with Args (@DEV = the pty), running; after StartMs the device goes:
  the program must end within 3 s, exit code 1, naming the loss (Expect). }
procedure TTestToolDeviceLoss.LossEnds(const Prog: string; const Args: array of string;
  const Expect: string; StartMs: Integer);
var
  Pty: TPtyPair;
  P: TProcess;
  A, Output: string;
  Lost: QWord;
  Took: QWord;
begin
  Pty := TPtyPair.Create;
  P := TProcess.Create(nil);
  try
    FpFcntl(Pty.Master, F_SETFD, 1);   { FD_CLOEXEC: closing it here hangs up }
    BinExecutable(P, BinPath(Prog));
    for A in Args do
      P.Parameters.Add(StringReplace(A, '@DEV', Pty.SlavePath, [rfReplaceAll]));
    P.Options := [poUsePipes, poStderrToOutPut];
    P.Execute;
    Output := '';
    Lost := ChMsTick + QWord(StartMs);
    while P.Running and (ChMsTick < Lost) do
    begin
      Drain(P, Output);
      Sleep(10);
    end;
    AssertTrue(Prog + ' runs before the loss:'#10 + Output, P.Running);
    Pty.CloseMaster;
    Lost := ChMsTick;
    while P.Running and (ChMsTick < Lost + 3000) do
    begin
      Drain(P, Output);
      Sleep(5);
    end;
    Took := ChMsTick - Lost;
    if P.Running then
    begin
      P.Terminate(255);
      P.WaitOnExit;
      Fail(Prog + ': still running 3 s after the device went away:'#10 + Output);
    end;
    Drain(P, Output);
    AssertEquals(Prog + ' exit code after the loss:'#10 + Output, 1, P.ExitCode);
    AssertTrue(Prog + ' says so:'#10 + Output, Pos(Expect, Output) > 0);
    AssertTrue(Prog + ' at once (' + IntToStr(Took) + ' ms)', Took < 2000);
  finally
    P.Free;
    Pty.Free;
  end;
end;

procedure TTestToolDeviceLoss.TestComraw;
begin
  LossEnds('comraw', ['--seconds', '30', 'DEV=@DEV BD=9600'], 'comraw: line lost: device lost');
end;

procedure TTestToolDeviceLoss.TestFT12Master;
begin
  { waiting 20 s for an answer that cannot come any more }
  LossEnds('ft12master', ['NAM=FT1_2 MS=ON MAS=MASTER NOD=1 DNO=2 NAM=COM DEV=@DEV BD=9600',
    '20000'], 'ft12master: line lost: device lost');
end;

procedure TTestToolDeviceLoss.TestDf1SimDev;
begin
  LossEnds('df1sim', ['--dev=@DEV', '--bd=9600', '--quiet'], 'df1sim: line lost: device lost');
end;

procedure TTestToolDeviceLoss.TestDf1Slave;
begin
  LossEnds('df1slave', ['NAM=DF1 MAS=SLAVE NOD=1 DNO=0 NAM=COM DEV=@DEV BD=9600'],
    'df1slave: line lost: device lost');
end;

procedure TTestToolDeviceLoss.TestWaitany;
begin
  LossEnds('waitany', ['30', 'DEV=@DEV BD=9600'], 'waitany: line 1 lost: device lost');
end;

procedure TTestToolDeviceLoss.TestFT12Slave;
begin
  LossEnds('ft12slave', ['NAM=FT1_2 MS=ON MAS=SLAVE LEN=0 NOD=1 NAM=COM DEV=@DEV BD=9600', '30'],
    'ft12slave: line: device lost');
end;
{$ENDIF}

initialization
  {$IFDEF UNIX}RegisterTest(TTestToolDeviceLoss);{$ENDIF}   { ptys }
end.
