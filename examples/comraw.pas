{ comraw - raw use of a physical layer, no protocol: send some bytes, then
  show what arrives, in hex, for a few seconds.

    comraw 'DEV=/dev/ttyUSB0 BD=9600' ['01 02 FF'] [seconds]
    comraw 'NAM=TCP HOST=nport1 PORT=4001' ['01 02 FF'] [seconds]

  The first argument is the COM layer's parameter string (docs/ChnCom.md),
  or another physical layer's after its NAM= (docs/ChnTcp.md); the channel
  is opened exactly as a legacy program would open it. }
program comraw;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnCom, ChnTcp;

var
  Chn: pChnVirt;
  Buf: array[0..255] of Byte;
  Out: array[0..255] of Byte;
  OutLen, I: Integer;
  Len: Word;
  Hex: string;
  Deadline: QWord;
  Seconds: LongInt;
  Layer, Params: string;
begin
  if ParamCount < 1 then
  begin
    WriteLn('usage: comraw ''DEV=/dev/ttyUSB0 BD=9600'' [''01 02 FF''] [seconds]');
    Halt(2);
  end;
  Layer := ChnCom.cName;
  Params := Trim(ParamStr(1));
  if UpStr(Copy(Params, 1, 4)) = 'NAM=' then
  begin
    { 'NAM=TCP HOST=...': the first token names the layer }
    Layer := Copy(Params, 5, Pos(' ', Params + ' ') - 5);
    Params := Trim(Copy(Params, Length(Layer) + 5, MaxInt));
  end;
  Chn := ChnCollection^.ChNewInit(Layer);
  if Chn = nil then
  begin
    WriteLn('comraw: unknown layer NAM=', Layer);
    Halt(1);
  end;
  Chn^.ChSetParam(Params);
  if Chn^.ChResult = res_Ok then
    Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then
  begin
    WriteLn('comraw: ', Chn^.ChResultStr(Chn^.ChResult), ' ', Chn^.ChParamError);
    Dispose(Chn, Done);
    Halt(1);
  end;
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Chn^.ChConnect;
  WriteLn(Chn^.ChGetParam(''));
  OutLen := 0;
  if ParamCount >= 2 then
  begin
    Hex := StringReplace(ParamStr(2), ' ', '', [rfReplaceAll]);
    while (Length(Hex) >= 2) and (OutLen < SizeOf(Out)) do
    begin
      Out[OutLen] := StrToIntDef('$' + Copy(Hex, 1, 2), 0);
      Inc(OutLen);
      Delete(Hex, 1, 2);
    end;
    Chn^.ChSend(@Out, OutLen);
    while Chn^.ChSendReady <> CHS_SendReady do ;   { IDL keeps this cheap }
    WriteLn('sent ', OutLen, ' bytes: ', Chn^.ChResultStr(Chn^.ChSendResult));
  end;
  Seconds := StrToIntDef(ParamStr(3), 2);
  Deadline := GetTickCount64 + QWord(Seconds) * 1000;
  while (GetTickCount64 < Deadline) and (Chn^.ChResult = res_Ok) do
    if Chn^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Chn^.ChReceive(Len);
      Write(FormatDateTime('hh:nn:ss.zzz', Now), ' ', Len:3, ':');
      for I := 0 to Len - 1 do
        Write(' ', IntToHex(Buf[I], 2));
      if Chn^.ChReceiveResult <> res_Ok then
        Write('  (', Chn^.ChResultStr(Chn^.ChReceiveResult), ')');
      WriteLn;
    end;
  if Chn^.ChResult <> res_Ok then
    WriteLn('comraw: ', Chn^.ChResultStr(Chn^.ChResult));
  Dispose(Chn, Done);
end.
