{ fuzzparams - every key of every layer with numbers built to break a
  parser: overflow (2e308, 1E400, 300 digits, 2^32, 2^63), NaN and Inf,
  lone signs and exponents, hex beyond 32 bits, and random strings of
  digits, signs, points and exponents. Built with range, overflow and
  stack checks and heaptrc (make fuzz).

  For each layer the keys are what its ChGetParam reports on a fresh
  instance (the contract: every parameter in force), plus the keys every
  layer's string may carry (NOD=, DNO=, LSB=, PORT=, LISTEN= ...) - each
  tried on every layer. A token must give res_Ok or a refusal with ChParamError naming
  it; an exception, a run-time error or a refusal that names nothing
  fails the run. An accepted token must come back through ChGetParam and
  rebuild the same configuration.

    fuzzparams [seconds [seed]]      (default 10 s, seed from the clock) }
program fuzzparams;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnCom, ChnLoop, ChnDF1, ChnFT1_2, ChnICS,
  ChnNoise, ChnTrc, ChnTcp, {$IFDEF UNIX}ChnPty,{$ENDIF} FuzzRun;

const
  Hostile: array[0..33] of string = (
    '2e308', '1E400', '-1E400', '1e-400', '2E+308', '1.7976931348623159e308',
    'NaN', 'nan', 'Inf', '-Inf', 'INF', 'Infinity',
    '4294967296', '4294967295', '-2147483649', '2147483648', '9223372036854775808',
    '18446744073709551616', '-9223372036854775809', '99999999999999999999999',
    '$FFFFFFFFF', '$FFFFFFFFFFFFFFFFFFFF', '-$80000001', '0x10', '1e', '1e+',
    '+', '-', '.', '-.', '.e1', '1..2', '--1', '1e1e1');
  { keys a fresh instance does not report (another form of the same
    setting, DOS-only, or a client's/server's alternative), from the
    layers' ChSetOneParam }
  ExtraKeys: array[0..12] of string = ('NOD', 'DNO', 'LSB', 'IDL', 'LRB', 'BD', 'COM', 'IRQ',
    'BASE', 'DEV', 'HOST', 'PORT', 'LISTEN');
  Chars = '0123456789+-.eE$';

var
  Keys: array of string;
  Tried, Accepted, Refused: Int64;

procedure AddKey(const K: string);
var
  I: Integer;
begin
  if K = 'NAM' then
    Exit;
  for I := 0 to High(Keys) do
    if Keys[I] = K then
      Exit;
  SetLength(Keys, Length(Keys) + 1);
  Keys[High(Keys)] := K;
end;

{ every key every registered layer reports on a fresh instance }
procedure CollectKeys;
var
  I, P: Integer;
  C: pChnVirt;
  All, Tok: ShortString;
begin
  for I := 0 to High(ExtraKeys) do
    AddKey(ExtraKeys[I]);
  for I := 1 to ChnCollection^.Count do
  begin
    C := ChnCollection^.Items[I]^.ChInit;
    All := C^.ChGetParam('');
    P := 1;
    while NextToken(All, P, Tok) do
      AddKey(ParamKey(Tok));
    Dispose(C, Done);
  end;
end;

function RandomNumberText: string;
var
  I, N: Integer;
begin
  case Random(4) of
    0: begin                                    { very long digit strings }
         Result := '';
         if Random(2) = 0 then
           Result := '-';
         for I := 1 to 1 + Random(240) do
           Result := Result + Chr(Ord('0') + Random(10));
         if Random(3) = 0 then
           Result := Result + 'e' + IntToStr(Random(1000) - 500);
       end;
    1: Result := Hostile[Random(Length(Hostile))];
    2: Result := IntToStr(Int64(Random($7FFFFFFF)) * (Random(5) + 1) - $7FFFFFFF);
  else
    begin
      Result := '';
      N := 1 + Random(20);
      for I := 1 to N do
        Result := Result + Chars[1 + Random(Length(Chars))];
    end;
  end;
end;

{ one token on a fresh instance of layer Index }
procedure TryToken(Index: Integer; const Key, Value: string);
var
  C, D: pChnVirt;
  Tok: string;
  R: tChResult;
  Back: ShortString;
begin
  Tok := Key + '=' + Value;
  if Length(Tok) > High(tWordString) then
    Exit;
  C := ChnCollection^.Items[Index]^.ChInit;
  try
    try
      Inc(Tried);
      C^.ChSetParam(Tok);
      R := C^.ChResult;
      if R = res_Ok then
      begin
        Inc(Accepted);
        { what was accepted comes back and rebuilds the same configuration }
        Back := C^.ChGetParam('');
        if Length(Back) >= High(tParamStr) - Length(Tok) then
          Exit;               { the getter's text is cut at 255 (documented) }
        D := ChnCollection^.Items[Index]^.ChInit;
        try
          D^.ChSetParam(Back);
          if D^.ChResult <> res_Ok then
            Fail(C^.CH_Type + ' ' + Tok + ': ChGetParam "' + Back + '" does not set back: ' +
              D^.ChResultStr(D^.ChResult) + ' (' + D^.ChParamError + ')')
          else if D^.ChGetParam('') <> Back then
            Fail(C^.CH_Type + ' ' + Tok + ': round trip changed "' + Back + '"');
        finally
          Dispose(D, Done);
        end;
      end
      else
      begin
        Inc(Refused);
        if C^.ChParamError <> Tok then
          Fail(C^.CH_Type + ' ' + Tok + ': refused (' + C^.ChResultStr(R) +
            ') naming "' + C^.ChParamError + '"');
      end;
    except
      on E: Exception do
        Fail(C^.CH_Type + ' ' + Tok + ': ' + E.ClassName + ': ' + E.Message);
    end;
  finally
    Dispose(C, Done);
  end;
end;

var
  Deadline: QWord;
  I, K, J: Integer;
begin
  Deadline := FuzzDeadline('fuzzparams');
  CollectKeys;
  Write(ChnCollection^.Count, ' layers, ', Length(Keys), ' keys:');
  for K := 0 to High(Keys) do
    Write(' ', Keys[K]);
  WriteLn;
  { every key, every layer, every fixed hostile value once }
  for I := 1 to ChnCollection^.Count do
    for K := 0 to High(Keys) do
      for J := 0 to High(Hostile) do
        TryToken(I, Keys[K], Hostile[J]);
  { then random ones until the time is up }
  while GetTickCount64 < Deadline do
    for I := 1 to ChnCollection^.Count do
      TryToken(I, Keys[Random(Length(Keys))], RandomNumberText);
  WriteLn('tokens ', Tried, ', accepted ', Accepted, ', refused ', Refused,
    ', failures ', Failures);
  if Failures > 0 then
    ExitCode := 1;      { not Halt: the main block's strings are freed first }
end.
