{ The command line of every shipped program (examples/*.pas, tools/*.pas,
  as built in build/bin), against the conventions of docs/TOOLS.md:
  --help and -h print the usage on standard output and exit 0; --version
  prints "PROG (Chn) VERSION"; no arguments print the usage on standard
  error and exit 2 (df1demo, which needs none, runs); an unknown option is
  "PROG: unknown option (TOKEN)" with exit 2; nothing is opened before the
  whole command line has been checked - the device is a FIFO, and Linux
  reports POLLHUP on its reading end once a writer has opened and closed
  it, so an open is noticed (TestOpenIsNoticed shows the detector sees
  one); "--opt VALUE" equals "--opt=VALUE"; no Czech left in messages.
  The program list is read from the source folders, so a new program is
  held to the same rules. }
unit TestToolCli;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, Classes, Process, Pipes, fpcunit, testregistry, BinSupport;

type
  TTestToolCli = class(TTestCase)
  private
    FOut, FErr: string;
    function RunProg(const Prog: string; const Args: array of string; const Exe: string = '';
      const HeapLog: string = ''): Integer;
    function Programs: TStringList;
  published
    procedure TestHelpOnStdoutExit0;
    procedure TestVersion;
    procedure TestNoArgumentsIsUsageOnStderrExit2;
    procedure TestUnknownOptionNamesItsToken;
    procedure TestValueOptionBothForms;
    procedure TestNoCzechInMessages;
    procedure TestUnknownLayerNamesItsUnit;
    procedure TestErrorExitsFreeEverything;
    {$IFDEF LINUX}
    procedure TestOpenIsNoticed;
    procedure TestNothingOpenedOnABadCommandLine;
    {$ENDIF}
  end;

implementation

uses
  {$IFDEF UNIX}BaseUnix,{$ENDIF} ChnTypes, ChnVirt, ChnLayers, ChnCom, ChnTcp, ChnLoop,
  ChnTrc, ChnNoise, ChnDF1, ChnFT1_2, ChnICS, TestTempDir;

{ Prog with Args, standard output and standard error apart; exit code,
  -1 if it still ran after 10 s. Exe: another build of it than
  build/bin's; HeapLog: heaptrc's report into this file. }
function TTestToolCli.RunProg(const Prog: string; const Args: array of string; const Exe: string;
  const HeapLog: string): Integer;
var
  P: TProcess;
  A: string;
begin
  P := TProcess.Create(nil);
  try
    if Exe <> '' then
      BinExecutable(P, Exe)
    else
      BinExecutable(P, BinPath(Prog));
    if HeapLog <> '' then
      HeapLogTo(P, HeapLog);
    for A in Args do
      P.Parameters.Add(A);
    Result := RunProcess(P, 10000, FOut, FErr);
  finally
    P.Free;
  end;
end;

function TTestToolCli.Programs: TStringList;
var
  F: TSearchRec;
  Dir: string;
begin
  Result := TStringList.Create;
  Result.Sorted := True;
  for Dir in ['examples', 'tools'] do
    if FindFirst(Dir + '/*.pas', faAnyFile, F) = 0 then
    try
      repeat
        Result.Add(ChangeFileExt(F.Name, ''));
      until FindNext(F) <> 0;
    finally
      FindClose(F);
    end;
  AssertTrue('programs found', Result.Count >= 16);
end;

procedure TTestToolCli.TestHelpOnStdoutExit0;
var
  L: TStringList;
  P, Opt: string;
begin
  L := Programs;
  try
    for P in L do
      for Opt in ['--help', '-h'] do
      begin
        AssertTrue(BinPath(P) + ' missing (make)', FileExists(BinPath(P)));
        AssertEquals(P + ' ' + Opt + ': exit code'#10 + FErr, 0, RunProg(P, [Opt]));
        AssertEquals(P + ' ' + Opt + ': usage on stdout'#10 + FOut, 1,
          Pos('Usage: ' + P + ' ', FOut));
        AssertTrue(P + ' ' + Opt + ': exit codes listed', Pos('Exit status:', FOut) > 0);
        AssertEquals(P + ' ' + Opt + ': nothing on stderr', '', FErr);
      end;
  finally
    L.Free;
  end;
end;

procedure TTestToolCli.TestVersion;
var
  L: TStringList;
  P: string;
begin
  L := Programs;
  try
    for P in L do
    begin
      AssertEquals(P + ' --version', 0, RunProg(P, ['--version']));
      AssertEquals(P + ' --version'#10 + FOut, 1, Pos(P + ' (Chn) ', FOut));
    end;
  finally
    L.Free;
  end;
end;

procedure TTestToolCli.TestNoArgumentsIsUsageOnStderrExit2;
var
  L: TStringList;
  P: string;
begin
  L := Programs;
  try
    for P in L do
      if P = 'df1demo' then
      begin
        { it needs no arguments, and its usage says so }
        AssertEquals('df1demo runs without arguments', 0, RunProg(P, []));
        RunProg(P, ['--help']);
        AssertTrue('df1demo --help says it takes none', Pos('takes no arguments', FOut) > 0);
      end
      else
      begin
        AssertEquals(P + ' without arguments: exit code'#10 + FOut + FErr, 2, RunProg(P, []));
        AssertEquals(P + ' without arguments: usage on stderr'#10 + FErr, 1,
          Pos('Usage: ' + P + ' ', FErr));
        AssertEquals(P + ' without arguments: nothing on stdout', '', FOut);
      end;
  finally
    L.Free;
  end;
end;

procedure TTestToolCli.TestUnknownOptionNamesItsToken;
var
  L: TStringList;
  P: string;
begin
  L := Programs;
  try
    for P in L do
    begin
      AssertEquals(P + ' --no-such-option', 2, RunProg(P, ['--no-such-option', 'NAM=DF1']));
      AssertEquals(P + ': one error line naming the token'#10 + FErr,
        P + ': unknown option (--no-such-option)' + LineEnding, FErr);
      { a part of a long name is not the option (getopts alone takes it) }
      AssertEquals(P + ' --hel', 2, RunProg(P, ['--hel']));
      AssertTrue(P + ' --hel'#10 + FErr, Pos('(--hel)', FErr) > 0);
    end;
    { a value that is wrong names the option as written }
    AssertEquals(2, RunProg('df1slave', ['-t', 'x', 'NAM=DF1']));
    AssertEquals('df1slave: --timeout wants a whole number 1..86400 (-t x)' + LineEnding, FErr);
    AssertEquals(2, RunProg('icsread', ['--timeout', '0', 'NAM=ICS']));
    AssertEquals('icsread: --timeout wants a whole number 1..600000 (--timeout 0)' + LineEnding, FErr);
    AssertEquals(2, RunProg('chndecode', ['--lines=x', 'file']));
    AssertEquals('chndecode: --lines wants A-B or A- (line numbers) (x)' + LineEnding, FErr);
    AssertEquals(2, RunProg('df1sim', ['--pty', '--dup', 'maybe']));
    AssertEquals('df1sim: --dup wants one of off, on (--dup maybe)' + LineEnding, FErr);
    { a flag takes no value }
    AssertEquals(2, RunProg('df1sim', ['--pty=yes']));
    AssertTrue(FErr, Pos('--pty takes no value (--pty=yes)', FErr) > 0);
    { a bad parameter string is a command-line error that names the token }
    AssertEquals(2, RunProg('df1read', ['N7:0', 'NAM=DF1', 'XYZ=1', 'NAM=LOOP']));
    AssertTrue(FErr, Pos('bad parameter string: ', FErr) > 0);
    AssertTrue(FErr, Pos('(XYZ=1)', FErr) > 0);
  finally
    L.Free;
  end;
end;

procedure TTestToolCli.TestValueOptionBothForms;
var
  Name, Sep, Joined: string;
  T: TStringList;
begin
  Name := GetTempFileName('', 'chncli') + '.log';
  T := TStringList.Create;
  try
    T.Add('10:00:00.000 tx   2 | TRC');
    T.Add('1006');
    T.Add('10:00:01.000 rx   2 | TRC');
    T.Add('1015');
    T.Add('10:00:02.000 tx   2 | TRC');
    T.Add('1005');
    T.SaveToFile(Name);
  finally
    T.Free;
  end;
  try
    AssertEquals(0, RunProg('chndecode', ['--df1', '--crc', '--lines=1-3', Name]));
    Joined := FOut;
    AssertTrue(Joined, Pos('NAK', Joined) > 0);
    AssertEquals('not past line 3', 0, Pos('ENQ', Joined));
    AssertEquals(0, RunProg('chndecode', ['--df1', '--crc', '--lines', '1-3', Name]));
    AssertEquals('--lines 1-3 = --lines=1-3', Joined, FOut);
    { options after the file and "--" before a name that looks like one }
    AssertEquals(0, RunProg('chndecode', [Name, '--lines', '1-3', '--crc']));
    AssertEquals(Joined, FOut);
    Sep := '--';
    AssertEquals(2, RunProg('chndecode', ['--crc', Sep, '--lines']));
    AssertTrue('after -- a file name:'#10 + FErr, Pos('--lines', FErr) > 0);
  finally
    DeleteFile(Name);
  end;
end;

{ The string literals of Pascal source Text (comments skipped), lower case. }
function Literals(const Text: string): string;
var
  I: Integer;
  InStr: Boolean;
begin
  Result := '';
  InStr := False;
  I := 1;
  while I <= Length(Text) do
  begin
    if InStr then
    begin
      if Text[I] = '''' then
      begin
        InStr := False;
        Result := Result + ' ';
      end
      else
        Result := Result + LowerCase(Text[I]);
    end
    else if Text[I] = '''' then
      InStr := True
    else if Text[I] = '{' then
    begin
      while (I <= Length(Text)) and (Text[I] <> '}') do
        Inc(I);
    end
    else if Copy(Text, I, 2) = '//' then
    begin
      while (I <= Length(Text)) and (Text[I] <> #10) do
        Inc(I);
    end;
    Inc(I);
  end;
end;

procedure TTestToolCli.TestNoCzechInMessages;
var
  L: TStringList;
  P, Dir, Text: string;
  S: TStringList;
  W: string;
begin
  L := Programs;
  S := TStringList.Create;
  try
    for P in L do
    begin
      Dir := 'examples/';
      if not FileExists(Dir + P + '.pas') then
        Dir := 'tools/';
      S.LoadFromFile(Dir + P + '.pas');
      Text := Literals(S.Text);
      for W in ['chyba', 'nelze', 'spojeni', 'neni', 'chybny'] do
        AssertEquals(P + ': a Czech word "' + W + '"', 0, Pos(W, Text));
    end;
  finally
    S.Free;
    L.Free;
  end;
end;

{ ChnVirt's table of layer names and units is complete: every layer the
  runner links (it links them all, as ChnLayers does) has its unit there,
  and an unknown NAM= of the library says which unit to add. }
procedure TTestToolCli.TestUnknownLayerNamesItsUnit;
const
  LibraryLayers: array[0..7] of string = ('COM', 'TCP', 'LOOP', 'TRC', 'NOISE', 'DF1', 'FT1_2', 'ICS');
var
  Chn: pChnVirt;
  Name: string;
begin
  { every layer of the library (the test suite's own layers aside) }
  AssertEquals('ChnCom', ChLayerUnit(ChnCom.cName));
  AssertEquals('ChnTcp', ChLayerUnit(ChnTcp.cName));
  AssertEquals('ChnLoop', ChLayerUnit(ChnLoop.cName));
  AssertEquals('ChnTrc', ChLayerUnit(ChnTrc.cName));
  AssertEquals('ChnNoise', ChLayerUnit(ChnNoise.cName));
  AssertEquals('ChnDF1', ChLayerUnit(ChnDF1.cName));
  AssertEquals('ChnFT1_2', ChLayerUnit(ChnFT1_2.cName));
  AssertEquals('ChnICS', ChLayerUnit(ChnICS.cName));
  { and each of them is linked by ChnLayers }
  for Name in LibraryLayers do
    AssertTrue(Name + ' registered', ChnCollection^.Search(Name) <> nil);
  AssertEquals('NAM=trc: add ChnTrc to the uses clause', ChUnknownLayerText('trc'));
  AssertEquals('ChnNoise', ChLayerUnit('NOISE'));
  AssertEquals('not the library''s', 'NAM=NOSUCH', ChUnknownLayerText('NOSUCH'));
  { through ChSetParam: the token names the name as given }
  Chn := ChnCollection^.ChNewInit('DF1');
  try
    Chn^.ChSetParam('NOD=1 NAM=NOSUCH');
    AssertEquals(res_UnknownLayer, Chn^.ChResult);
    AssertEquals('NAM=NOSUCH', Chn^.ChParamError);
  finally
    Dispose(Chn, Done);
  end;
end;

{$IFDEF LINUX}
type
  tFifo = record
    Path: string;
    Fd: cint;
  end;

procedure FifoOpen(out F: tFifo);
begin
  F.Path := GetTempFileName('', 'chnfifo');
  DeleteFile(F.Path);
  if FpMkfifo(F.Path, &600) <> 0 then
    raise Exception.Create('mkfifo ' + F.Path);
  F.Fd := FpOpen(F.Path, O_RDONLY or O_NONBLOCK);
  if F.Fd < 0 then
    raise Exception.Create('open ' + F.Path);
end;

{ True once a writer has opened the FIFO (and closed it: the program ended) }
function FifoWasOpened(const F: tFifo): Boolean;
var
  P: pollfd;
begin
  P.fd := F.Fd;
  P.events := POLLIN;
  P.revents := 0;
  Result := (FpPoll(@P, 1, 0) > 0) and (P.revents and POLLHUP <> 0);
end;

procedure FifoClose(var F: tFifo);
begin
  FpClose(F.Fd);
  DeleteFile(F.Path);
end;

procedure TTestToolCli.TestOpenIsNoticed;
var
  F: tFifo;
begin
  FifoOpen(F);
  try
    AssertFalse('a fresh FIFO', FifoWasOpened(F));
    { a good command line: comraw opens the "device" (and is refused its
      settings: a FIFO is no terminal) }
    AssertEquals('comraw opens it:'#10 + FErr, 1, RunProg('comraw', ['--seconds', '0', 'DEV=' + F.Path]));
    AssertTrue('the open was noticed', FifoWasOpened(F));
  finally
    FifoClose(F);
  end;
end;

procedure TTestToolCli.TestNothingOpenedOnABadCommandLine;

  procedure Check(const Prog: string; const Args: array of string);
  var
    F: tFifo;
    A: array of string;
    I: Integer;
  begin
    FifoOpen(F);
    try
      SetLength(A, Length(Args));
      for I := 0 to High(Args) do
        A[I] := StringReplace(Args[I], '@DEV', F.Path, [rfReplaceAll]);
      AssertEquals(Prog + ': a command-line error'#10 + FErr, 2, RunProg(Prog, A));
      AssertFalse(Prog + ': the device was not opened'#10 + FErr, FifoWasOpened(F));
    finally
      FifoClose(F);
    end;
  end;

begin
  { the bad part comes last, after a parameter string naming the device }
  Check('df1read', ['N7:0', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=@DEV', '--bogus']);
  Check('df1read', ['N7:0', '0', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=@DEV']);
  Check('df1write', ['N7:0', '40000', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=@DEV']);
  Check('df1echo', ['NAM=DF1 NAM=COM DEV=@DEV', 'NAM=NOSUCH']);
  Check('df1slave', ['NAM=DF1 MAS=SLAVE NAM=COM DEV=@DEV', '-t', '0']);
  Check('readn7', ['@DEV', '--bogus']);
  Check('ft12master', ['NAM=FT1_2 MAS=MASTER NAM=COM DEV=@DEV', '0']);
  Check('ft12slave', ['NAM=FT1_2 MAS=SLAVE NAM=COM DEV=@DEV', 'x']);
  Check('ft12balanced', ['NAM=FT1_2 MS=OFF NAM=COM DEV=@DEV', '0']);
  Check('icsread', ['NAM=ICS NAM=COM DEV=@DEV BD=7x']);
  Check('icsslave', ['-n', '0', 'NAM=ICS MAS=SLAVE NAM=COM DEV=@DEV']);
  Check('comraw', ['DEV=@DEV', '0G']);
  Check('waitany', ['1', 'DEV=@DEV', 'DEV=/dev/null PAR=Q']);
  Check('chntap', ['NAM=COM DEV=@DEV', 'NAM=COM DEV=/dev/null XYZ=1']);
  Check('df1sim', ['--dev=@DEV', '--node=999']);
  Check('df1sim', ['NAM=DF1 MAS=SLAVE NAM=COM DEV=@DEV', '--bd=9600']);
  Check('plcconc', ['NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=@DEV', 'NAM=DF1 NAM=NOSUCH']);
  Check('plcconc', ['--addr=Q7:0', 'NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=@DEV']);
  { a parameter string the master or slave refuses, and --slaves for a
    balanced line: found on the channel before it is opened }
  Check('iec101master', ['NAM=FT1_2 MS=ON MAS=SLAVE NAM=COM DEV=@DEV', 'gi']);
  Check('iec101master', ['--slaves=5,7', 'NAM=FT1_2 MS=OFF PRI=ON NAM=COM DEV=@DEV', 'gi']);
  Check('iec101master', ['NAM=FT1_2 MS=ON MAS=MASTER NAM=COM DEV=@DEV', 'gi', 'sc', '5000=2']);
  Check('iec101slave', ['NAM=FT1_2 MS=ON MAS=MASTER NAM=COM DEV=@DEV']);
  Check('iec101slave', ['--ca-size=1', '--ca=300', 'NAM=FT1_2 MS=ON MAS=SLAVE NAM=COM DEV=@DEV']);
end;
{$ENDIF}

{ A command-line error found deep inside a program (getopts' table under
  way, a parameter string being checked, inside an exception handler,
  after a file was read), a line that cannot be opened, a file that
  cannot be read, or a check that is done (chngate --check) ends it with
  its code, and everything it allocated is freed on the way (heaptrc: 0
  unfreed blocks). The programs' test builds (build/test-bin, with
  heaptrc) are run; they ended with Halt before, leaving the strings of
  every routine under way. }
procedure TTestToolCli.TestErrorExitsFreeEverything;
var
  Dir, HeapLog, Report: string;

  procedure Check(const Prog: string; const Args: array of string; Want: Integer; const Says: string);
  var
    Code: Integer;
  begin
    DeleteFile(HeapLog);
    Code := RunProg(Prog, Args, TestBinDir + Prog {$IFDEF WINDOWS} + '.exe'{$ENDIF}, HeapLog);
    AssertEquals(Prog + ' ' + Args[0] + ': exit code; ' + FErr, Want, Code);
    AssertTrue(Prog + ': ' + FOut + FErr, Pos(Says, FOut + FErr) > 0);
    AssertTrue(Prog + ' ' + Args[0] + ': no heaptrc report in ' + HeapLog, FileExists(HeapLog));
    Report := ReadFileText(HeapLog);
    AssertTrue(Prog + ' ' + Args[0] + ': ' + Report,
      Pos(LineEnding + '0 unfreed memory blocks : 0' + LineEnding, LineEnding + Report) > 0);
  end;

begin
  if not FileExists(TestBinDir + 'df1write' {$IFDEF WINDOWS} + '.exe'{$ENDIF}) then
    Ignore('the heap-checked programs are not built (make test builds them; make mutate does not)');
  Dir := MakeTempDir('clileak');
  try
    HeapLog := Dir + '/heap.log';
    Check('df1write', ['N7:0', '--bogus'], 2, 'df1write: unknown option (--bogus)');
    Check('df1write', ['N7:0', '5', 'NAM=XYZ'], 2, 'unknown layer name (NAM=XYZ)');
    Check('chntap', ['--frames=xyz'], 2, 'chntap: unknown option (--frames=xyz)');
    Check('df1sim', ['--msg-to=3'], 2, '--msg-to needs --half');
    Check('df1sim', ['--pty', '--config=' + Dir + '/none.conf'], 2, 'cannot read the data table');
    WriteFileText(Dir + '/bad.points', 'M_XX_NA_1 1 0' + LineEnding);
    Check('iec101slave', ['--points=' + Dir + '/bad.points', 'NAM=FT1_2 NAM=COM DEV=' + Dir + '/none'], 2,
      'bad.points');
    Check('iec101slave', ['NAM=FT1_2 MS=ON MAS=SLAVE NAM=COM DEV=' + Dir + '/none'], 1, 'iec101slave: ');
    { ended from the main program's block (CliEnd): its variables too }
    Check('chndecode', [Dir + '/none.trc'], 2, 'none.trc');
    Check('chngate', [Dir + '/none.conf'], 2, 'none.conf: cannot be read');
    Check('chngate', ['--check', 'tools/chngate.conf'], 0, 'tools/chngate.conf: good: ');
  finally
    RemoveTempDir(Dir);
  end;
end;

initialization
  RegisterTest(TTestToolCli);
end.
