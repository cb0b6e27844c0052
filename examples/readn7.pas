program readn7;  { N7:0 of an SLC 500 / MicroLogix: readn7 /dev/ttyUSB0 }
uses ChnCom, ChnDF1, ChnPcccClient;
var
  C: tPcccClient;
  V: array[0..0] of LongInt;
begin
  if PcccOpen(C, 'NAM=DF1 NOD=0 DNO=1 NAM=COM BD=19200 DEV=' + ParamStr(1)) <> 0 then
    WriteLn(C.Err)
  else if PcccReadInts(C, 'N7:0', 1, V) = 0 then
    WriteLn('N7:0 = ', V[0])
  else
    WriteLn(C.Err);
  PcccClose(C);
end.
