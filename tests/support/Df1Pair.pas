{ Df1Pair - the fixture of the tests that run a DF1 master and a slave
  station (answering from a ChnSlc table) in one process over the
  in-memory null modem NAM=LOOP, or a master against tools/df1sim: the
  channels and the simulator process are closed after every test. }
unit Df1Pair;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, Process, fpcunit, ChnVirt, ChnSlc, ChnDF1Link;

type
  TDf1PairCase = class(TTestCase)
  protected
    Table: tSlcTable;
    Station: tDF1Station;
    Master, Slave, Raw: pChnVirt;   { disposed of after the test }
    Proc: TProcess;                 { ended and freed after the test }
    procedure SetUp; override;
    procedure TearDown; override;
    { Load a table (SlcLoadConfig); a bad one fails the test. }
    procedure LoadTable(const Config: string);
    { A DF1 stack from Params, opened and connected, or the test fails. }
    function Open(const Params: string): pChnVirt;
    { Master (NOD=0, END=1) and Slave (NOD=1, END=2) on NAM=LOOP PAIR=Pair,
      Station answering from Table on Slave. }
    procedure StartPair(Full, Crc: Boolean; const Pair: string);
  end;

{ 'NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=ON NAM=LOOP PAIR=X END=1'
  and the slave's counterpart. }
function Df1PairParams(Master, Full, Crc: Boolean; const Pair: string): string;

implementation

uses
  SysUtils, TestSupport;

function Df1PairParams(Master, Full, Crc: Boolean; const Pair: string): string;
const
  FHD: array[Boolean] of string = ('HALF', 'FULL');
  CRCS: array[Boolean] of string = ('OFF', 'ON');
begin
  if Master then
    Result := Format('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=%s CRC=%s NAM=LOOP PAIR=%s END=1',
      [FHD[Full], CRCS[Crc], Pair])
  else
    Result := Format('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=%s CRC=%s NAM=LOOP PAIR=%s END=2',
      [FHD[Full], CRCS[Crc], Pair]);
end;

procedure TDf1PairCase.SetUp;
begin
  Master := nil;
  Slave := nil;
  Raw := nil;
  Proc := nil;
end;

procedure TDf1PairCase.TearDown;
begin
  if Master <> nil then Dispose(Master, Done);
  if Slave <> nil then Dispose(Slave, Done);
  if Raw <> nil then Dispose(Raw, Done);
  if Proc <> nil then
  begin
    if Proc.Running then
      Proc.Terminate(1);
    Proc.Free;
  end;
end;

procedure TDf1PairCase.LoadTable(const Config: string);
var
  Line: LongInt;
  Err: AnsiString;
begin
  Line := 0;
  Err := '';
  if not SlcLoadConfig(Table, Config, Line, Err) then
    Fail('table line ' + IntToStr(Line) + ': ' + Err);
end;

function TDf1PairCase.Open(const Params: string): pChnVirt;
var
  Err: string;
begin
  Result := OpenStack('DF1', Params, Err);
  AssertTrue('open ' + Err, Result <> nil);
end;

procedure TDf1PairCase.StartPair(Full, Crc: Boolean; const Pair: string);
begin
  Slave := Open(Df1PairParams(False, Full, Crc, Pair));
  Master := Open(Df1PairParams(True, Full, Crc, Pair));
  SlcStationInit(Station, Slave, @Table);
end;

end.
