{ Df1Pair - the parameter strings of a DF1 master (NOD=0, END=1) and slave
  (NOD=1, END=2) on the in-memory null modem NAM=LOOP, for tests that run
  both ends in one process. }
unit Df1Pair;

{$MODE OBJFPC}{$H+}

interface

{ 'NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL CRC=ON NAM=LOOP PAIR=X END=1'
  and the slave's counterpart. }
function Df1PairParams(Master, Full, Crc: Boolean; const Pair: string): string;

implementation

uses
  SysUtils;

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

end.
