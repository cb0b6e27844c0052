{ ChnIec101MasterInbound - what the IEC 60870-5-101 master does with an
  ASDU from a slave: every object to OnObject (file transfer ASDUs to
  OnFileAsdu), a malformed one counted and described, the first object
  matched against the command under way; a slave's end of initialisation
  (M_EI_NA_1, COT 4) told to the program and followed by the
  interrogations it calls for, one at a time, when no command is under way. }
unit ChnIec101MasterInbound;

{$I chn.inc}

interface

uses
  ChnIec101MasterTypes;

{ An ASDU received from slave index S. }
procedure TakeAsdu(var M: tIecMaster; S: LongInt; const Buf: array of Byte; Len: Word);
{ The interrogations due after an end of initialisation: the next one,
  when the program has no command under way. }
procedure StartAfterInit(var M: tIecMaster);

implementation

uses
  SysUtils, ChnTypes, ChnIec101Asdu, ChnIec101MasterCmd;

{ Slave index S has initialised (M_EI_NA_1, COT 4): tell the program;
  its data may all have changed - interrogate it (and its counters) when
  no command is under way, unless told not to. }
procedure EndOfInit(var M: tIecMaster; S: LongInt; Ca: Word; Coi: Byte);
begin
  Inc(M.EndOfInits);
  with M.Slaves[S] do
  begin
    Inc(EndOfInits);
    LastCoi := Coi;
    InitCa := Ca;
    InitGi := not M.NoGiAfterInit;
    InitCi := not M.NoGiAfterInit and (M.CiAfterInit <> 0);
    { an interrogation of this slave not yet confirmed is answered after
      the initialisation: it is the one that follows it }
    if (M.Cmd.Slave = S) and (M.Cmd.Phase in [cpSend, cpConfirm]) then
      if M.Cmd.Ti = C_IC_NA_1 then
        InitGi := False
      else if M.Cmd.Ti = C_CI_NA_1 then
        InitCi := False;
  end;
  if Assigned(M.OnEndOfInit) then
    M.OnEndOfInit(M.Data, M.Slaves[S].Addr, Ca, Coi);
end;

{ The interrogations due after an end of initialisation, one at a time,
  when the program has no command under way. }
procedure StartAfterInit(var M: tIecMaster);
var
  I: Integer;
begin
  if not IecCommandDone(M) then
    Exit;
  for I := 0 to M.SlaveCount - 1 do
    with M.Slaves[I] do
      if InitGi or InitCi then
      begin
        if InitGi then
        begin
          InitGi := False;
          if StartWith(M, Addr, InitCa, C_IC_NA_1, Qoi_Station, True) then
            M.Cmd.Auto := True;
        end
        else
        begin
          InitCi := False;
          if StartWith(M, Addr, InitCa, C_CI_NA_1, M.CiAfterInit, True) then
            M.Cmd.Auto := True;
        end;
        Exit;
      end;
end;

{ An ASDU received from slave index S. }
procedure TakeAsdu(var M: tIecMaster; S: LongInt; const Buf: array of Byte; Len: Word);
var
  H: tIecAsdu;
  O: tIecObject;
  E: ShortString;
  I: Integer;
begin
  Inc(M.Asdus);
  Inc(M.Slaves[S].Asdus);
  if (Len > 0) and (Buf[0] >= 120) and (Buf[0] <= 127) and Assigned(M.OnFileAsdu) then
  begin
    M.OnFileAsdu(M.FileData, M.Slaves[S].Addr, Buf, Len);   { file transfer }
    Exit;
  end;
  if IecDecodeHeader(M.Params, Buf, Len, H, E) <> res_Ok then
  begin
    Inc(M.BadAsdus);
    Inc(M.Slaves[S].BadAsdus);
    M.LastBad := 'slave ' + IntToStr(M.Slaves[S].Addr) + ': ' + E;
    if Assigned(M.OnBad) then
      M.OnBad(M.Data, M.Slaves[S].Addr, M.LastBad);
    Exit;
  end;
  for I := 0 to H.Count - 1 do
  begin
    IecDecodeObject(M.Params, H, Buf, I, O);
    Inc(M.Objects);
    Inc(M.Slaves[S].Objects);
    if Assigned(M.OnObject) then
      M.OnObject(M.Data, M.Slaves[S].Addr, H, O);
    if I = 0 then
      MatchCommand(M, S, H, O);
    if (H.Ti = M_EI_NA_1) and (H.Cot = Cot_Initialized) then
      EndOfInit(M, S, H.Ca, O.Int);
  end;
end;
end.
