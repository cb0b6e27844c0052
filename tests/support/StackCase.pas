{ StackCase - the open-stack-and-tear-down fixture of the channel tests:
  a test case whose stacks, opened through Stack, are disposed after each
  test (in reverse order) whatever the test did, so a failing assert
  leaks nothing and no test unit writes its own TearDown for it. }
unit StackCase;

{$MODE OBJFPC}{$H+}

interface

uses
  fpcunit, ChnVirt;

type
  TStackCase = class(TTestCase)
  private
    FStacks: array of pChnVirt;
  protected
    { OpenStack (TestSupport): built, opened and connected, or the test
      fails with the reason; disposed by CloseStacks. }
    function Stack(const Name, Params: string): pChnVirt;
    { A stack the test built itself, disposed with the others. }
    function Keep(Chn: pChnVirt): pChnVirt;
    { Dispose every stack Stack opened (a test that starts over). }
    procedure CloseStacks;
    procedure TearDown; override;
  end;

implementation

uses
  TestSupport;

function TStackCase.Stack(const Name, Params: string): pChnVirt;
var
  Err: string;
begin
  Err := '';
  Result := OpenStack(Name, Params, Err);
  AssertTrue(Name + ' stack ' + Params + ': ' + Err, Result <> nil);
  Keep(Result);
end;

function TStackCase.Keep(Chn: pChnVirt): pChnVirt;
begin
  SetLength(FStacks, Length(FStacks) + 1);
  FStacks[High(FStacks)] := Chn;
  Result := Chn;
end;

procedure TStackCase.CloseStacks;
var
  I: Integer;
begin
  for I := High(FStacks) downto 0 do
    Dispose(FStacks[I], Done);
  FStacks := nil;
end;

procedure TStackCase.TearDown;
begin
  CloseStacks;
  inherited TearDown;
end;

end.
