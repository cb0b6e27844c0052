{ df1write - write SLC 500 / MicroLogix data (or tools/df1sim's) by address.

    df1write ADDRESS VALUE... parameter string
    df1write N7:0 1 2 3 NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0 BD=19200
    df1write B3:1/4 1 ...        a bit: 0 or 1 (a masked write, the other
                                 bits of the word stay)
    df1write F8:0 1.5 -2.25 ...  floats;  T4:0.PRE 100 ...  timer preset
    df1write ST9:0 'some text' ...

  One value per item from ADDRESS on (three for a whole T, C or R element:
  control word, PRE or LEN, ACC or POS); the parameter string starts at the
  first argument with '='. Exit code as df1read's: 0 ok, 1 setup error or a
  bad address, count or value, 2 no answer, 3 error reply. }
program df1write;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, ChnTypes, ChnLoop, ChnCom, ChnTcp, ChnTrc, ChnDF1, ChnPccc, ChnPcccClient;

var
  C: tPcccClient;
  R: tPcccRequest;
  Params, Addr, Arg: string;
  Values: array of ShortString;
  I: LongInt;

procedure Log(const Line: AnsiString);
begin
  WriteLn('df1write: ', Line);
end;

procedure Fail(const What: string; Code: Integer);
begin
  WriteLn('df1write: ', What);
  PcccClose(C);
  Halt(Code);
end;

begin
  PcccClientInit(C, nil);
  Params := '';
  Addr := ParamStr(1);
  SetLength(Values, 0);
  for I := 2 to ParamCount do
  begin
    Arg := ParamStr(I);
    if (Params = '') and (Pos('=', Arg) = 0) then
    begin
      SetLength(Values, Length(Values) + 1);
      Values[High(Values)] := Arg;
    end
    else
      Params := Trim(Params + ' ' + Arg);
  end;
  if (ParamCount < 2) or (Length(Values) = 0) or (Params = '') then
    Fail('usage: df1write ADDRESS VALUE... NAM=DF1 ... NAM=COM DEV=...', 1);
  if PcccOpen(C, Params) <> res_Ok then
    Fail(C.Err, 1);
  C.Log := @Log;
  if PcccStartWriteText(R, C, Addr, Values) then
    PcccFinish(R);
  if R.Result <> res_Ok then
    Fail(R.Err + ' (' + ChResultText(R.Result, PcccLayer) + ')', PcccExitCode(R.Result));
  WriteLn('df1write: ', Length(Values), ' value(s) written from ', Addr);
  PcccClose(C);
end.
