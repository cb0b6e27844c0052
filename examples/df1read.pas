{ df1read - read SLC 500 / MicroLogix data (or tools/df1sim's) by address
  and print it, one line per item.

    df1read [ADDRESS [COUNT]] parameter string
    df1read N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200

  ADDRESS as unit ChnPccc reads it (N7:0, F8:2, B3:1/4, B3/20, T4:0.ACC,
  C5:0.DN, R6:0.POS, ST9:0, L10:0, S:1, O0:0, I1:0), default N7:0; COUNT
  items, default 10 (1 for a string). The requests and the link dialogue
  are unit ChnPcccClient's; each frame is shown as it goes.
  Exit code: 0 ok, 1 setup error or bad address/count, 2 no answer,
  3 error reply (STS <> 0) or a reply that does not fit. }
program df1read;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnLoop, ChnCom, ChnTcp, ChnTrc, ChnDF1, ChnPccc, ChnPcccClient;

var
  C: tPcccClient;
  R: tPcccRequest;
  Params, Addr, Arg: string;
  Count, I: LongInt;
  CountGiven: Boolean;

procedure Log(const Line: AnsiString);
begin
  WriteLn('df1read: ', Line);
end;

procedure Fail(const What: string; Code: Integer);
begin
  WriteLn('df1read: ', What);
  PcccClose(C);
  Halt(Code);
end;

begin
  PcccClientInit(C, nil);
  Addr := 'N7:0';
  Count := 10;
  CountGiven := False;
  Params := '';
  for I := 1 to ParamCount do
  begin
    Arg := ParamStr(I);
    if (Params = '') and (Pos('=', Arg) = 0) and (I = 1) then
      Addr := Arg
    else if (Params = '') and (Pos('=', Arg) = 0) and (I = 2) then
    begin
      if not StrToNum(Arg, 1, PcccMaxItems, Count) then
        Fail('COUNT wants 1..' + IntToStr(PcccMaxItems), 1);
      CountGiven := True;
    end
    else
      Params := Trim(Params + ' ' + Arg);
  end;
  if Params = '' then
    Fail('no parameter string (e.g. NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0)', 1);
  if Pos('ST', UpperCase(Trim(Addr))) = 1 then
    if not CountGiven then
      Count := 1;
  if PcccOpen(C, Params) <> res_Ok then
    Fail(C.Err, 1);
  WriteLn('df1read: ', C.Chn^.ChGetParam(''));
  C.Log := @Log;
  if PcccStartRead(R, C, Addr, Count) then
    PcccFinish(R);
  if R.Result <> res_Ok then
    Fail(R.Err + ' (' + ChResultText(R.Result, PcccLayer) + ')', PcccExitCode(R.Result));
  for I := 0 to Count - 1 do
    WriteLn(PcccItemText(R, I));
  PcccClose(C);
end.
