{ paramattack - hostile parameter strings against every layer, in one
  process (tests/hostile/attack.sh, attack "params"; docs/reliability.md).

    paramattack [count [seed]]      (default 20000 strings, seed 1)

  Each string is built from layer names, their real keys and hostile
  values (numbers that overflow, NaN, 300 digits, fused tokens, keys
  without '=', 100-layer chains, strings beyond 255 characters). It goes
  through ChSetParam; a string that is taken and ends in a LOOP or a TCP
  client to 127.0.0.1 is also opened and closed (nothing else is opened:
  no device, no file, no name lookup). Counted: taken, refused naming a
  token, refused naming nothing, taken although longer than 255
  characters (cut without a word), exceptions (by class and message).
  Built with range and overflow checks by attack.sh; exit 1 when any
  exception was raised or a refusal named nothing. }
program paramattack;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp, ChnDF1,
  ChnFT1_2, ChnICS, ChnTrc, ChnNoise;

const
  Layers: array[0..7] of string = ('DF1', 'FT1_2', 'ICS', 'TRC', 'NOISE', 'LOOP', 'TCP', 'COM');
  Keys: array[0..7] of string = (
    'NOD DNO MAS FHD CRC NAK DUP LSB',
    'NOD DNO MS MAS PRI LSB LEN ADR DIR GAP',
    'NOD DNO MAS LSB',
    'MOD',
    'BER DRP SEED BYTE CNT DIR',
    'PAIR END IDL LRB',
    'PORT CTO RECON RFC2217 KICK IDLE BD BIT STOP PAR FLW LRB LSB IDL',
    'COM BD BIT STOP PAR FLW LRB LSB IDL RS485 IRQ ADR');
  Values: array[0..27] of string = (
    '0', '1', '-1', '255', '65535', '65536', '2147483647', '2147483648',
    '-2147483649', '1E400', '2e308', '-1E400', 'NaN', 'Inf', '0x10', '$FF',
    '1.5', '', '=', 'ON', 'OFF', 'MAYBE', 'MASTER', 'HALF', '1E-3',
    '99999999999999999999', #1#2, 'A B');

var
  Taken, Named, Unnamed, LongTaken, Opened, Exceptions: LongInt;
  ExcKinds: TStringList;

function Pick(const A: array of string): string;
begin
  Result := A[Random(Length(A))];
end;

function Word_(const List: string; N: Integer): string;
var
  L: TStringList;
begin
  L := TStringList.Create;
  try
    L.Delimiter := ' ';
    L.DelimitedText := List;
    Result := L[N mod L.Count];
  finally
    L.Free;
  end;
end;

function HostileValue: string;
begin
  case Random(6) of
    0: Result := StringOfChar('9', 300);
    1: Result := StringOfChar('A', 200 + Random(200));
    2: Result := '1' + StringOfChar('0', 40) + 'E' + IntToStr(Random(1000));
  else
    Result := Pick(Values);
  end;
end;

{ One layer's part: NAM=X and some of its keys (or someone else's). }
function LayerPart(L: Integer): string;
var
  K: Integer;
begin
  Result := 'NAM=' + Layers[L];
  for K := 1 to Random(5) do
  begin
    case Random(10) of
      0: Result := Result + ' ' + Word_(Keys[Random(8)], Random(20)) + '=' + HostileValue;
      1: Result := Result + ' ' + Word_(Keys[L], Random(20));          { no '=' }
      2: Result := Result + ' ' + Word_(Keys[L], Random(20)) + '=ONNAM=' + Layers[Random(8)];
      3: Result := Result + ' NAM=';
    else
      Result := Result + ' ' + Word_(Keys[L], Random(20)) + '=' + HostileValue;
    end;
  end;
  if Layers[L] = 'LOOP' then
    Result := Result + ' PAIR=PA' + IntToStr(Random(4));
  if Layers[L] = 'TCP' then
    Result := Result + ' HOST=127.0.0.1 PORT=1';     { refused at once }
  if Layers[L] = 'COM' then
    Result := Result + ' DEV=/nonexistent/tty';
  if Layers[L] = 'TRC' then
    Result := Result + ' FILE=/dev/null';
end;

function HostileString: string;
var
  I, Depth: Integer;
begin
  if Random(20) = 0 then
  begin
    Result := '';                       { a 100-layer chain }
    for I := 1 to 100 do
      Result := Result + 'NAM=TRC FILE=/dev/null ';
    Exit(Result + 'NAM=LOOP PAIR=DEEP');
  end;
  if Random(20) = 0 then
    { a token that ends at character 256 (the attack: a cut
      string names another device) }
    Exit('NAM=DF1 NAM=COM DEV=/nonexistent/' + StringOfChar('a', 256 - 32 - 1) + 'B');
  Result := '';
  Depth := 1 + Random(4);
  for I := 1 to Depth do
  begin
    if Result <> '' then
      Result := Result + ' ';
    Result := Result + LayerPart(Random(8));
  end;
  if Random(3) = 0 then
    Result := Result + ' NAM=LOOP PAIR=PB END=1';
end;

{ Would opening it touch anything beyond the loopback and memory? }
function SafeToOpen(const S: string): Boolean;
begin
  Result := (Pos('NAM=COM', S) = 0) and (Pos('LISTEN', S) = 0) and
    ((Pos('NAM=LOOP', S) > 0) or (Pos('HOST=127.0.0.1 PORT=1', S) > 0));
end;

procedure Attack(const S: string);
var
  C: pChnVirt;
  First: string;
  P: Integer;
begin
  First := Copy(S, 5, MaxInt);
  P := Pos(' ', First);
  if P > 0 then
    First := Copy(First, 1, P - 1);
  C := ChnCollection^.ChNewInit(First);
  if C = nil then
    Exit;
  try
    try
      C^.ChSetParam(S);
      if C^.ChResult = res_Ok then
      begin
        Inc(Taken);
        if Length(S) > 255 then
          Inc(LongTaken);
        if SafeToOpen(S) then
        begin
          C^.ChOpen;
          if C^.ChResult = res_Ok then
            Inc(Opened);
          C^.ChClose;
        end;
      end
      else if C^.ChParamError <> '' then
        Inc(Named)
      else
      begin
        Inc(Unnamed);
        if Unnamed <= 5 then
          WriteLn('refused naming nothing (', C^.ChResultStr(C^.ChResult), '): ', Copy(S, 1, 200));
      end;
    except
      on E: Exception do
      begin
        Inc(Exceptions);
        if ExcKinds.IndexOf(E.ClassName + ': ' + E.Message) < 0 then
        begin
          ExcKinds.Add(E.ClassName + ': ' + E.Message);
          WriteLn('exception ', E.ClassName, ': ', E.Message, ' on: ', Copy(S, 1, 200));
        end;
      end;
    end;
  finally
    Dispose(C, Done);
  end;
end;

var
  Count, I: LongInt;
begin
  Count := StrToIntDef(ParamStr(1), 20000);
  RandSeed := StrToIntDef(ParamStr(2), 1);
  ExcKinds := TStringList.Create;
  for I := 1 to Count do
    Attack(HostileString);
  WriteLn(Format('paramattack: %d strings: %d taken (%d opened), %d refused naming the token, ' +
    '%d refused naming nothing, %d taken although longer than 255 characters, %d exceptions (%d kinds)',
    [Count, Taken, Opened, Named, Unnamed, LongTaken, Exceptions, ExcKinds.Count]));
  ExcKinds.Free;
  if (Exceptions > 0) or (Unnamed > 0) then
    ExitCode := 1;
end.
