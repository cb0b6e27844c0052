{ waitany - a new-style program that blocks instead of polling: it watches
  several lines at once and prints what arrives on each, in hex.

    waitany [seconds] 'DEV=/dev/ttyUSB0 BD=9600' 'DEV=/dev/ttyUSB1 BD=19200' ...

  Every argument after the first is the COM layer's parameter string of one
  line (docs/ChnCom.md). The channels are opened with IDL=0, so a poll never
  waits; the program waits once, in ChnWaitAny, for the first byte on any
  line (or one second), then polls every line once. Idle, it takes no CPU;
  a byte on any line wakes it at once (docs/LAYERS.md, "The shared wait"). }
program waitany;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnWait, ChnCom, uString;

const
  MaxLines = 32;

var
  Chn: array[1..MaxLines] of pChnVirt;
  Buf: array[0..255] of Byte;
  N, I: Integer;
  Len: Word;
  Seconds: LongInt;
  Deadline: QWord;
begin
  if (ParamCount < 2) or not StrToNum(ParamStr(1), 1, 86400, Seconds) then
  begin
    WriteLn('usage: waitany seconds ''DEV=/dev/ttyUSB0 BD=9600'' [''DEV=... '' ...]');
    Halt(2);
  end;
  N := 0;
  for I := 2 to ParamCount do
  begin
    if N = MaxLines then
      Break;
    Inc(N);
    Chn[N] := ChnCollection^.ChNewInit(ChnCom.cName);
    Chn[N]^.ChSetParam(ParamStr(I) + ' IDL=0');    { never wait in a poll }
    if Chn[N]^.ChResult = res_Ok then
      Chn[N]^.ChOpen;
    if Chn[N]^.ChResult <> res_Ok then
    begin
      WriteLn('waitany: line ', N, ': ', Chn[N]^.ChResultStr(Chn[N]^.ChResult),
        ' ', Chn[N]^.ChParamError);
      Dispose(Chn[N], Done);
      Dec(N);
      Continue;
    end;
    Chn[N]^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    Chn[N]^.ChConnect;
    WriteLn('line ', N, ': ', Chn[N]^.ChGetParam('DEV'));
  end;
  Deadline := GetTickCount64 + QWord(Seconds) * 1000;
  while (N > 0) and (GetTickCount64 < Deadline) do
  begin
    { sleep until a byte arrives on any line, at most a second }
    ChnWaitAny(1000);
    for I := 1 to N do
      while Chn[I]^.ChReceiveReady = CHS_ReceiveReady do
      begin
        Chn[I]^.ChReceive(Len);
        if Chn[I]^.ChReceiveResult = res_Overrun then
          WriteLn('line ', I, ': bytes were lost');
        WriteLn('line ', I, ': ', HexBytes(@Buf, Len));
      end;
  end;
  for I := 1 to N do
    Dispose(Chn[I], Done);
end.
