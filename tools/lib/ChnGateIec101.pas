{ ChnGateIec101 - the IEC 60870-5-101 devices of tools/chngate: a
  [device NAME] whose line is NAM=FT1_2 ... (any physical layer) is an
  IEC 101 master (ChnIec101Master) polling its slaves, its points kept by
  ChnIecPointTable. This unit reads the device's own keys (their text
  checked here, the file and line said by ChnGateway), opens and steps the
  device, names its points and writes their payloads, and queues the
  commands a client (MQTT, or the IEC 104 north) sends to writable points.

  For the north side, a point of a device is T.Points[P] of its table
  (ChnIecPointTable.tIecTablePoint: IOA, type, value, quality, time);
  GateIecNorthIoa gives the IOA it has in a gateway-wide table (the
  device's ioa= offset + its IOA), GateIecFindNorth the way back, and
  GateIecWrite sends a value to it as the command of its type. }
unit ChnGateIec101;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnIec101Asdu, ChnIec101Master, ChnIecPointTable;

type
  { A point the configuration names or makes writable. }
  tGateIecPointCfg = record
    Name    : AnsiString;    {< '' : published under its IOA }
    Addr    : Word;          {< slave link address }
    Ioa     : LongWord;
    Writable: Boolean;
    CmdIoa  : LongWord;      {< where its commands go }
  end;

  tGateIecCfg = record
    Params  : tIecParams;    {< cot_size, ca_size, ioa_size }
    Ca      : Word;
    Slaves  : array of Word; {< link addresses (balanced: the peer, DNO=) }
    IoaOffset: LongWord;     {< ioa= : the north IOA of IOA n is IoaOffset + n }
    Points  : array of tGateIecPointCfg;
    Deadband: Double;
    TimeoutMs: LongInt;      {< link answer }
    DemoteMs: LongInt;       {< most ms between the tries of a dead slave }
    CycleMs : LongInt;       {< class 2 polls of a slave with nothing to say }
    GiMs    : LongInt;       {< periodic interrogation, 0: none }
  end;

  pGateIecDevice = ^tGateIecDevice;
  tGateIecDevice = record
    Name    : AnsiString;
    Line    : AnsiString;
    Cfg     : tGateIecCfg;
    Chn     : pChnVirt;      {< nil while the line is not open }
    M       : tIecMaster;
    T       : tIecPointTable;
    OpenAt  : QWord;         {< when a line that failed is opened again (0: open) }
    LineError: AnsiString;
    Shown   : AnsiString;    {< the states and line error last reported }
  end;

{ Point entries 'NAME=IOA' or 'NAME=ADDR:IOA' (the slave's link address,
  needed with several slaves) into C.Points. False with Err naming the
  entry and what is wrong. }
function GateIecParsePoints(const Text: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
{ Writable points: 'POINT' or 'POINT>CMDIOA', POINT a name of points=,
  an IOA or ADDR:IOA; commands go to CMDIOA (default the point's IOA). }
function GateIecParseWrite(const Text: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
{ The line's parameter string and the master's set-up (a master's string,
  the slaves' addresses, the sizes, the CA), as the device will open them;
  nothing is opened. C.Slaves empty: the line's DNO=. }
function GateIecCheckLine(const Line: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
{ 'N' points the configuration names. }
function GateIecSummary(const C: tGateIecCfg): AnsiString;

{ A device (its line opened now, or again every DemoteMs while it fails). }
function GateIecNew(const Name, Line: AnsiString; const C: tGateIecCfg): pGateIecDevice;
procedure GateIecFree(var D: pGateIecDevice);
{ Step the line and the table; True when something happened. }
function GateIecStep(D: pGateIecDevice): Boolean;
function GateIecWaitMs(D: pGateIecDevice): LongInt;
{ The device's state: the worst of its slaves', down while its line is not open. }
function GateIecState(D: pGateIecDevice): tIecHealth;
{ True once after the device's state or a slave's changed. }
function GateIecTakeHealth(D: pGateIecDevice): Boolean;

{ The topic level of point P: its name, else its IOA, with several
  slaves ADDR:IOA. }
function GateIecPointName(D: pGateIecDevice; P: LongInt): AnsiString;
{ The point of a topic level (a name, IOA or ADDR:IOA); -1 when none. }
function GateIecFind(D: pGateIecDevice; const Name: AnsiString): LongInt;
{ Its IOA in the gateway-wide table (the north): ioa= offset + IOA. }
function GateIecNorthIoa(D: pGateIecDevice; P: LongInt): LongWord;
{ The point whose north IOA is NorthIoa; -1 when none. }
function GateIecFindNorth(D: pGateIecDevice; NorthIoa: LongWord): LongInt;
{ Send Value to point P as the command of its type (ChnIecPointTable):
  False with Err when refused at once; else the outcome comes with Id
  from IecTableTakeWrite(D^.T, W). }
function GateIecWrite(D: pGateIecDevice; P: LongInt; Value: Double; Id: LongInt;
  out Err: AnsiString): Boolean;
{ The same with the S/E bit and the qualifier (QU / QL) the RTU gets
  (IecTableCommand): a control centre's command passed on as it came. }
function GateIecCommand(D: pGateIecDevice; P: LongInt; Value: Double; Select: Boolean; Qu: Byte;
  Id: LongInt; out Err: AnsiString): Boolean;

{ The payload of a point: value, quality and ts, as a DF1 tag's. }
function GateIecPointPayload(const P: tIecTablePoint): AnsiString;
{ The device's $health. }
function GateIecHealthPayload(D: pGateIecDevice): AnsiString;

implementation

uses
  SysUtils, StrUtils, ChnFT1_2, ChnWait, ChnJson, ChnCli;

{ ------------------------------------------------------------ configuration }

function WholeIn(const S: AnsiString; Min, Max: Int64; out V: LongWord): Boolean;
var
  X: Int64;
  Code: LongInt;
begin
  Val(S, X, Code);
  Result := (Code = 0) and (S <> '') and (X >= Min) and (X <= Max);
  if Result then
    V := X;
end;

{ 'IOA' or 'ADDR:IOA' into Addr (default: the first slave) and Ioa. }
function ParseRef(const S: AnsiString; const C: tGateIecCfg; out Addr: Word; out Ioa: LongWord): Boolean;
var
  P: LongInt;
  A: LongWord;
begin
  P := Pos(':', S);
  if Length(C.Slaves) > 0 then
    Addr := C.Slaves[0]
  else
    Addr := 0;
  if P > 0 then
  begin
    Result := WholeIn(Copy(S, 1, P - 1), 0, 65535, A) and WholeIn(Copy(S, P + 1, MaxInt), 0, $FFFFFF, Ioa);
    Addr := A;
  end
  else
    Result := WholeIn(S, 0, $FFFFFF, Ioa);
end;

function FindCfg(const C: tGateIecCfg; Addr: Word; Ioa: LongWord): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(C.Points) do
    if (C.Points[I].Addr = Addr) and (C.Points[I].Ioa = Ioa) then
      Exit(I);
  Result := -1;
end;

function AddCfg(var C: tGateIecCfg; Addr: Word; Ioa: LongWord): LongInt;
begin
  Result := FindCfg(C, Addr, Ioa);
  if Result >= 0 then
    Exit;
  Result := Length(C.Points);
  SetLength(C.Points, Result + 1);
  C.Points[Result].Name := '';
  C.Points[Result].Addr := Addr;
  C.Points[Result].Ioa := Ioa;
  C.Points[Result].Writable := False;
  C.Points[Result].CmdIoa := Ioa;
end;

function HasSlave(const C: tGateIecCfg; Addr: Word): Boolean;
var
  A: Word;
begin
  for A in C.Slaves do
    if A = Addr then
      Exit(True);
  Result := False;
end;

function GateIecParsePoints(const Text: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
var
  W, Name: AnsiString;
  Eq, K, I: LongInt;
  Addr: Word;
  Ioa: LongWord;
begin
  Err := '';
  for W in Trim(Text).Split([' ', #9], TStringSplitOptions.ExcludeEmpty) do
  begin
    Eq := Pos('=', W);
    Name := Copy(W, 1, Eq - 1);
    if (Eq <= 1) or (Pos('/', Name) > 0) or (Pos('+', Name) > 0) or (Pos('#', Name) > 0) then
      Err := Err + '; "' + W + '": NAME=IOA or NAME=ADDR:IOA, the name one topic level (no / + #)'
    else if not ParseRef(Copy(W, Eq + 1, MaxInt), C, Addr, Ioa) then
      Err := Err + '; "' + W + '": the IOA is a whole number 0..16777215 (ADDR:IOA: a link address 0..65535 first)'
    else if not HasSlave(C, Addr) then
      Err := Err + '; "' + W + '": ' + IntToStr(Addr) + ' is none of the slaves'
    else
    begin
      for I := 0 to High(C.Points) do
        if SameText(C.Points[I].Name, Name) then
          Err := Err + '; "' + Name + '" is there twice';
      K := AddCfg(C, Addr, Ioa);
      if C.Points[K].Name <> '' then
        Err := Err + '; "' + W + '": the point is named "' + C.Points[K].Name + '" already'
      else
        C.Points[K].Name := Name;
    end;
  end;
  Delete(Err, 1, 2);
  Result := Err = '';
end;

function GateIecParseWrite(const Text: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
var
  W, Ref: AnsiString;
  Gt, K, I: LongInt;
  Addr: Word;
  Ioa, Cmd: LongWord;
begin
  Err := '';
  for W in Trim(Text).Split([' ', #9], TStringSplitOptions.ExcludeEmpty) do
  begin
    Gt := Pos('>', W);
    if Gt > 0 then
      Ref := Copy(W, 1, Gt - 1)
    else
      Ref := W;
    K := -1;
    for I := 0 to High(C.Points) do
      if SameText(C.Points[I].Name, Ref) then
        K := I;
    if (K < 0) and ParseRef(Ref, C, Addr, Ioa) then
    begin
      if not HasSlave(C, Addr) then
      begin
        Err := Err + '; "' + W + '": ' + IntToStr(Addr) + ' is none of the slaves';
        Continue;
      end;
      K := AddCfg(C, Addr, Ioa);
    end;
    if K < 0 then
      Err := Err + '; "' + W + '": neither a name of points= nor an IOA'
    else if (Gt > 0) and not WholeIn(Copy(W, Gt + 1, MaxInt), 0, $FFFFFF, Cmd) then
      Err := Err + '; "' + W + '": the command IOA after > is a whole number 0..16777215'
    else if C.Points[K].Writable then
      Err := Err + '; "' + W + '": the point is there twice'
    else
    begin
      C.Points[K].Writable := True;
      if Gt > 0 then
        C.Points[K].CmdIoa := Cmd;
    end;
  end;
  Delete(Err, 1, 2);
  Result := Err = '';
end;

{ The master's channel of Line, not opened, with the master set up on it. }
function MasterOn(const Line: AnsiString; var C: tGateIecCfg; var M: tIecMaster; out Err: AnsiString): pChnVirt;
var
  R: tChResult;
  E: ShortString;
  A: Word;
begin
  Result := CliNewChannel(Line, ChnFT1_2.cName, Err);
  if Result = nil then
    Exit;
  R := IecMasterInit(M, Result, C.Params);
  if R = res_BadMessage then
    Err := 'a slave''s parameter string: an IEC 101 device is polled by a master (MS=ON MAS=MASTER, or MS=OFF balanced)'
  else if R = res_WrongLayer then
    Err := 'the line starts with NAM=FT1_2'
  else if R <> res_Ok then
  begin
    IecCheckParams(C.Params, E);
    Err := E;
  end
  else
  begin
    { before the slaves are added: they start their back-off with these }
    M.TimeoutMs := C.TimeoutMs;
    M.CycleMs := C.CycleMs;
    { a dead slave is tried again after DeadMinMs, doubling up to demote=
      (then it is demoted: ChnIecPointTable) }
    M.DeadMaxMs := C.DemoteMs;
    if M.DeadMinMs > C.DemoteMs div 2 then
      M.DeadMinMs := C.DemoteMs div 2;
    if Length(C.Slaves) = 0 then
    begin
      SetLength(C.Slaves, 1);
      C.Slaves[0] := Result^.CH_DNode;
    end;
    if not M.Balanced then
      for A in C.Slaves do
        if IecMasterAddSlave(M, A) <> res_Ok then
          Err := Err + '; slave ' + IntToStr(A) + ': twice, too large for ADR=, or the broadcast address';
    if M.Balanced and ((Length(C.Slaves) > 1) or (C.Slaves[0] <> Result^.CH_DNode)) then
      Err := 'a balanced line (MS=OFF) has one peer, the line''s DNO=' + IntToStr(Result^.CH_DNode);
    Delete(Err, 1, Ord(Copy(Err, 1, 2) = '; ') * 2);
  end;
  if Err <> '' then
  begin
    Dispose(Result, Done);
    Result := nil;
  end;
end;

function GateIecCheckLine(const Line: AnsiString; var C: tGateIecCfg; out Err: AnsiString): Boolean;
var
  Chn: pChnVirt;
  M: tIecMaster;
begin
  Chn := MasterOn(Line, C, M, Err);
  Result := Chn <> nil;
  if Result then
    Dispose(Chn, Done);
  if Result and (C.Ca > IecMaxCa(C.Params)) then
  begin
    Err := 'ca ' + IntToStr(C.Ca) + ' is above ' + IntToStr(IecMaxCa(C.Params)) + ' (ca_size ' +
      IntToStr(C.Params.CaSize) + ')';
    Result := False;
  end;
end;

function GateIecSummary(const C: tGateIecCfg): AnsiString;
begin
  Result := Format('%d slaves, %d points named or writable', [Length(C.Slaves), Length(C.Points)]);
end;

{ ------------------------------------------------------------ running }

procedure Declare(D: pGateIecDevice);
var
  P: tGateIecPointCfg;
  K: LongInt;
begin
  D^.T.Deadband := D^.Cfg.Deadband;
  D^.T.GiMs := D^.Cfg.GiMs;
  for P in D^.Cfg.Points do
  begin
    K := IecTableAdd(D^.T, P.Addr, D^.Cfg.Ca, P.Ioa, P.Name);
    if P.Writable then
      IecTableSetWritable(D^.T, K, P.CmdIoa, 0);
  end;
end;

procedure OpenLine(D: pGateIecDevice);
var
  Err: AnsiString;
begin
  D^.Chn := MasterOn(D^.Line + ' IDL=0', D^.Cfg, D^.M, Err);
  if D^.Chn <> nil then
  begin
    D^.Chn^.ChOpen;
    if D^.Chn^.ChResult = res_Ok then
      D^.Chn^.ChConnect;
    if D^.Chn^.ChResult <> res_Ok then
    begin
      Err := D^.Chn^.ChErrorText;
      Dispose(D^.Chn, Done);
      D^.Chn := nil;
    end;
  end;
  if D^.Chn = nil then
  begin
    D^.LineError := 'cannot open the line: ' + Err;
    D^.OpenAt := ChMsTick + QWord(D^.Cfg.DemoteMs);
    Exit;
  end;
  IecTableInit(D^.T, D^.M, D^.Cfg.Ca);
  Declare(D);
  D^.LineError := '';
  D^.OpenAt := 0;
end;

{ The line failed (a USB adapter unplugged, a device server gone): every
  point bad, the line opened again after DemoteMs. }
procedure LineLost(D: pGateIecDevice);
begin
  D^.LineError := 'line failed: ' + D^.Chn^.ChResultStr(IecMasterLineResult(D^.M));
  IecTableLineDown(D^.T);
  Dispose(D^.Chn, Done);
  D^.Chn := nil;
  D^.OpenAt := ChMsTick + QWord(D^.Cfg.DemoteMs);
end;

function GateIecNew(const Name, Line: AnsiString; const C: tGateIecCfg): pGateIecDevice;
begin
  New(Result);
  FillChar(Result^, SizeOf(Result^), 0);
  Result^.Name := Name;
  Result^.Line := Line;
  Result^.Cfg := C;
  Result^.Shown := '-';
  OpenLine(Result);
end;

procedure GateIecFree(var D: pGateIecDevice);
begin
  if D = nil then
    Exit;
  if D^.Chn <> nil then
    Dispose(D^.Chn, Done);
  IecTableDone(D^.T);
  Dispose(D);
  D := nil;
end;

function GateIecStep(D: pGateIecDevice): Boolean;
begin
  Result := False;
  if D^.Chn = nil then
  begin
    if ChMsTick >= D^.OpenAt then
    begin
      OpenLine(D);
      Result := True;
    end;
    Exit;
  end;
  Result := IecTableStep(D^.T);
  if IecMasterLineResult(D^.M) <> res_Ok then
  begin
    LineLost(D);
    Result := True;
  end;
end;

function GateIecWaitMs(D: pGateIecDevice): LongInt;
begin
  if D^.Chn = nil then
    Result := ChnWaitLeft(D^.OpenAt)
  else
    Result := IecTableWaitMs(D^.T);
end;

function GateIecState(D: pGateIecDevice): tIecHealth;
var
  S: tIecTableSlave;
begin
  if D^.Chn = nil then
    Exit(ihDown);
  Result := ihOk;
  for S in D^.T.Slaves do
    if S.Health > Result then
      Result := S.Health;
end;

function GateIecTakeHealth(D: pGateIecDevice): Boolean;
var
  S: LongInt;
  Now_: AnsiString;
begin
  while IecTableTakeHealth(D^.T, S) do;
  { reported when the device's, a slave's state or the line's trouble changed }
  Now_ := IecHealthNames[GateIecState(D)] + ' ' + D^.LineError;
  for S := 0 to High(D^.T.Slaves) do
    Now_ := Now_ + ' ' + IecHealthNames[D^.T.Slaves[S].Health];
  Result := Now_ <> D^.Shown;
  D^.Shown := Now_;
end;

function GateIecPointName(D: pGateIecDevice; P: LongInt): AnsiString;
begin
  with D^.T.Points[P] do
    if Name <> '' then
      Result := Name
    else if Length(D^.Cfg.Slaves) > 1 then
      Result := IntToStr(Addr) + ':' + IntToStr(Ioa)
    else
      Result := IntToStr(Ioa);
end;

function GateIecFind(D: pGateIecDevice; const Name: AnsiString): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(D^.T.Points) do
    if GateIecPointName(D, I) = Name then
      Exit(I);
  Result := -1;
end;

function GateIecNorthIoa(D: pGateIecDevice; P: LongInt): LongWord;
begin
  Result := D^.Cfg.IoaOffset + D^.T.Points[P].Ioa;
end;

function GateIecFindNorth(D: pGateIecDevice; NorthIoa: LongWord): LongInt;
var
  I: LongInt;
begin
  for I := 0 to High(D^.T.Points) do
    if GateIecNorthIoa(D, I) = NorthIoa then
      Exit(I);
  Result := -1;
end;

function GateIecWrite(D: pGateIecDevice; P: LongInt; Value: Double; Id: LongInt;
  out Err: AnsiString): Boolean;
begin
  Result := GateIecCommand(D, P, Value, False, 0, Id, Err);
end;

function GateIecCommand(D: pGateIecDevice; P: LongInt; Value: Double; Select: Boolean; Qu: Byte;
  Id: LongInt; out Err: AnsiString): Boolean;
var
  E: ShortString;
begin
  if D^.Chn = nil then
  begin
    Err := D^.Name + ': ' + D^.LineError;
    Exit(False);
  end;
  Result := IecTableCommand(D^.T, P, Value, Select, Qu, Id, E);
  Err := E;
end;

{ ------------------------------------------------------------ payloads }

function GateIecPointPayload(const P: tIecTablePoint): AnsiString;
var
  V: AnsiString;
begin
  if not P.Known then
    V := 'null'
  else if IecTypeKind(P.Ti) = ikSingle then
    V := IfThen(P.Value <> 0, 'true', 'false')
  else if IecTypeKind(P.Ti) = ikFloat then
    V := JsonNumber(P.Value, 7)
  else
    V := JsonNumber(P.Value);
  Result := '{"value":' + V + ',"quality":"' + IecPointQualityText(P) + '","ts":"' +
    JsonTime(P.TimeMs) + '"}';
end;

function SlaveJson(const S: tIecTableSlave): AnsiString;
begin
  Result := Format('"state":"%s","polls":%d,"errors":%d,"retries":%d,"last_error":%s',
    [IecHealthNames[S.Health], S.Polls, S.Errors, S.Retries, JsonString(S.LastError)]);
end;

function GateIecHealthPayload(D: pGateIecDevice): AnsiString;
var
  Sum, S: tIecTableSlave;
  Slaves: AnsiString;
begin
  FillChar(Sum, SizeOf(Sum), 0);
  Sum.Health := GateIecState(D);
  Sum.LastError := D^.LineError;      { the line's trouble first, else a slave's }
  Slaves := '';
  for S in D^.T.Slaves do
  begin
    Inc(Sum.Polls, S.Polls);
    Inc(Sum.Errors, S.Errors);
    Inc(Sum.Retries, S.Retries);
    if (D^.LineError = '') and (S.LastError <> '') and ((Sum.LastError = '') or (S.Health <> ihOk)) then
      Sum.LastError := S.LastError;
    Slaves := Slaves + ',{"addr":' + IntToStr(S.Addr) + ',' + SlaveJson(S) + '}';
  end;
  Result := '{' + SlaveJson(Sum);
  if Length(D^.Cfg.Slaves) > 1 then
    Result := Result + ',"slaves":[' + Copy(Slaves, 2, MaxInt) + ']';
  Result := Result + '}';
end;

end.
