{ bench104 - IEC 104 over loopback: the time of a general interrogation of
  1000 scaled values and spontaneous events per second, our master and
  slave (ChnIec101Master / ChnIec101Slave over NAM=IEC104, both stepped
  from this one thread without waiting: IDL=0), against the same exchange between two programs
  on lib60870-C when LIB60870_BENCH names a directory holding them (srv
  PORT N E and cli PORT R E, printing "gi_ms=X events_per_s=Y"; they are
  built by hand outside this repository, see docs/ChnIec104.md). Run
  with "make bench"; figures compare on one machine, not assertions. }
program bench104;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, Classes, Process, ChnTypes, ChnVirt, ChnTcp, ChnIec104, ChnWait, ChnIec101Asdu,
  ChnIec101Master, ChnIec101Slave;

const
  Points = 1000;
  Rounds = 20;
  Events = 20000;

var
  M: tIecMaster;
  S: tIecSlaveStation;
  GotEvents, GotObjects: LongInt;

procedure OnObj(Data: Pointer; Addr: Word; const H: tIecAsdu; const O: tIecObject);
begin
  if H.Cot = Cot_Spontaneous then
    Inc(GotEvents)
  else if H.Cot = Cot_Interrogated then
    Inc(GotObjects);
end;

procedure StepSlave(Data: Pointer);
begin
  if not IecSlaveStep(S) then
    ChnWaitAny(0);
end;

function Open(const Params: string): pChnVirt;
begin
  Result := ChnCollection^.ChNewInit('IEC104');
  Result^.ChSetParam(Params);
  if Result^.ChResult = res_Ok then
    Result^.ChOpen;
  if Result^.ChResult = res_Ok then
    Result^.ChConnect;
  if Result^.ChResult <> res_Ok then
  begin
    WriteLn(Params, ': ', Result^.ChResultStr(Result^.ChResult));
    Halt(1);
  end;
end;

procedure Ours(out GiMs, PerSec: Double);
var
  SChn, MChn: pChnVirt;
  E: ShortString;
  O: tIecObject;
  I, Sent: LongInt;
  T0: QWord;
begin
  SChn := Open('NAM=IEC104 QUE=65535 NAM=TCP LISTEN=127.0.0.1:0 IDL=0');
  IecSlaveInit(S, SChn, IecDefaultParams, 1, E);
  for I := 0 to Points - 1 do
  begin
    O := IecObject(100 + I);
    O.Int := I mod 1000;
    IecSlaveAddPoint(S, M_ME_NB_1, O, 0, E);
  end;
  MChn := Open('NAM=IEC104 NAM=TCP IDL=0 HOST=127.0.0.1 PORT=' +
    IntToStr(pChnTcp(SChn^.CH_Low)^.ChLocalPort));
  IecMasterInit(M, MChn, IecDefaultParams);
  M.OnObject := @OnObj;
  M.Idle := @StepSlave;
  IecInterrogation(M, 0, 1, Qoi_Station);         { connection up, warm }
  GotObjects := 0;
  T0 := ChUsTick;
  for I := 1 to Rounds do
    if IecInterrogation(M, 0, 1, Qoi_Station) <> res_Ok then
      WriteLn('GI: ', M.Cmd.Err);
  GiMs := (ChUsTick - T0) / 1000 / Rounds;
  if GotObjects <> Rounds * Points then
    WriteLn('GI: ', GotObjects, ' objects of ', Rounds * Points);
  GotEvents := 0;
  Sent := 0;
  T0 := ChUsTick;
  while (GotEvents < Events) and (ChUsTick - T0 < 60000000) do
  begin
    while (Sent < Events) and (S.Class1.Count < IecSlaveQueueLen) do
    begin
      O := IecObject(100 + Sent mod Points);
      O.Int := Sent mod 1000;
      if IecSlaveUpdate(S, O.Ioa, O, True, E) <> res_Ok then
        Break;
      Inc(Sent);
    end;
    IecSlaveStep(S);
    IecMasterStep(M);
  end;
  PerSec := Events / ((ChUsTick - T0) / 1e6);
  Dispose(MChn, Done);
  Dispose(SChn, Done);
end;

{ the lib60870 pair, when there: its line "gi_ms=X events_per_s=Y" }
function Theirs(const Dir: string; out GiMs, PerSec: Double): Boolean;
var
  Srv: TProcess;
  Line: string;
  P: Integer;
  Fs: TFormatSettings;
begin
  Result := False;
  Srv := TProcess.Create(nil);
  try
    Srv.Executable := Dir + '/srv';
    Srv.Parameters.Add('24104');
    Srv.Parameters.Add(IntToStr(Points));
    Srv.Parameters.Add(IntToStr(Events));
    Srv.Options := [poUsePipes];
    Srv.Execute;
    Sleep(300);
    if not RunCommand(Dir + '/cli', ['24104', IntToStr(Rounds), IntToStr(Events)], Line) then
      Exit;
    Fs := DefaultFormatSettings;
    Fs.DecimalSeparator := '.';
    P := Pos('gi_ms=', Line);
    if P = 0 then
      Exit;
    Line := Copy(Line, P + 6, MaxInt);
    GiMs := StrToFloat(Copy(Line, 1, Pos(' ', Line) - 1), Fs);
    P := Pos('events_per_s=', Line);
    Line := Copy(Line, P + 13, MaxInt);
    PerSec := StrToFloat(Trim(Copy(Line, 1, Pos(' ', Line + ' ') - 1)), Fs);
    Result := True;
  finally
    Srv.Terminate(0);
    Srv.Free;
  end;
end;

var
  Gi, Ev, LGi, LEv: Double;
  Dir: string;
begin
  Ours(Gi, Ev);
  WriteLn(Format('iec104: GI of %d points %.2f ms, %.0f events/s (our master and slave, one thread)',
    [Points, Gi, Ev]));
  Dir := GetEnvironmentVariable('LIB60870_BENCH');
  if Dir = '' then
    WriteLn('iec104: lib60870 pair not run (LIB60870_BENCH=dir with its srv and cli)')
  else if Theirs(Dir, LGi, LEv) then
    WriteLn(Format('iec104: lib60870 pair GI %.2f ms, %.0f events/s; ours/lib60870: GI time %.0f %%, events/s %.0f %%',
      [LGi, LEv, 100 * Gi / LGi, 100 * Ev / LEv]))
  else
    WriteLn('iec104: the lib60870 pair in ', Dir, ' did not run');
end.
