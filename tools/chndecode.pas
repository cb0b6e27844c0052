{ chndecode - print each frame of a capture decoded: DF1, FT1.2 or ICS.

    chndecode [input] [protocol] [options] FILE
      input     --capture  RACOM text capture / NAM=TRC log (default)
                --hex      hex text ('10 02 03 00 ...'), one received stream
                --bin      a binary file, one received stream
      protocol  --df1 [--crc|--bcc] [--half [--master=tx|rx]]   (default --df1 --crc)
                --ft12 [--adr=0..2] [--len=N]
                --ics
      options   --lines=A-B   only chunks whose header is on lines A..B
    FILE '-' reads standard input.

  The work is done by unit ChnFrameDecode (docs/chndecode.md). Exit code: 0 all
  frames good, 1 broken or incomplete frames found, 2 usage error or
  unreadable input. }
program chndecode;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, uString, ChnTypes, ChnTrcFormat, ChnFrameDecode;

procedure Usage(const Why: string);
begin
  WriteLn(StdErr, 'chndecode: ', Why);
  WriteLn(StdErr, 'usage: chndecode [--capture|--hex|--bin] [--df1 [--crc|--bcc] [--half [--master=tx|rx]] | --ft12 [--adr=N] [--len=N] | --ics] [--lines=A-B] FILE');
  Halt(2);
end;

function ReadAll(const Name: string; out Text: AnsiString): Boolean;
var
  S: TStream;
  M: TMemoryStream;
  Inp: THandleStream;
begin
  Result := False;
  Text := '';
  try
    if Name = '-' then
    begin
      M := TMemoryStream.Create;
      Inp := THandleStream.Create(StdInputHandle);
      try
        M.CopyFrom(Inp, 0);
        SetLength(Text, M.Size);
        if M.Size > 0 then
          Move(M.Memory^, Text[1], M.Size);
      finally
        Inp.Free;
        M.Free;
      end;
    end
    else
    begin
      S := TFileStream.Create(Name, fmOpenRead or fmShareDenyNone);
      try
        SetLength(Text, S.Size);
        if S.Size > 0 then
          S.ReadBuffer(Text[1], S.Size);
      finally
        S.Free;
      end;
    end;
    Result := True;
  except
    on E: Exception do
      WriteLn(StdErr, 'chndecode: ', Name, ': ', E.Message);
  end;
end;

var
  Opt: tDecOptions;
  Stats: tDecStats;
  Frames: tTrcFrames;
  Data: tTrcBytes;
  Lines: TStringList;
  Input: Char;       { c, h, b }
  Arg, Key, Value, FileName, Err: string;
  Text: AnsiString;
  I, Count, Dash: Integer;
  N, N2: LongInt;
begin
  DecodeDefaults(Opt);
  Input := 'c';
  FileName := '';
  for I := 1 to ParamCount do
  begin
    Arg := ParamStr(I);
    if (Arg = '-') or (Copy(Arg, 1, 2) <> '--') then
    begin
      if FileName <> '' then
        Usage('more than one input file');
      FileName := Arg;
      Continue;
    end;
    Key := Arg;
    Value := '';
    if Pos('=', Arg) > 0 then
    begin
      Key := Copy(Arg, 1, Pos('=', Arg) - 1);
      Value := Copy(Arg, Pos('=', Arg) + 1, MaxInt);
    end;
    N := 0;
    if Key = '--capture' then Input := 'c'
    else if Key = '--hex' then Input := 'h'
    else if Key = '--bin' then Input := 'b'
    else if Key = '--df1' then Opt.Proto := dpDF1
    else if Key = '--crc' then Opt.Crc := True
    else if Key = '--bcc' then Opt.Crc := False
    else if Key = '--half' then Opt.Half := True
    else if Key = '--master' then
    begin
      if Value = 'tx' then Opt.MasterDir := trcTx
      else if Value = 'rx' then Opt.MasterDir := trcRx
      else Usage('--master wants tx or rx');
    end
    else if Key = '--ft12' then Opt.Proto := dpFT12
    else if Key = '--adr' then
    begin
      if not StrToNum(Value, 0, 2, N) then
        Usage('--adr wants 0, 1 or 2');
      Opt.AddrLen := N;
    end
    else if Key = '--len' then
    begin
      if not StrToNum(Value, 0, 247, N) then
        Usage('--len wants 0..247');
      Opt.FixedLen := N;
    end
    else if Key = '--ics' then Opt.Proto := dpICS
    else if Key = '--lines' then
    begin
      Dash := Pos('-', Value);
      N2 := 0;
      if (Dash = 0) or not StrToNum(Copy(Value, 1, Dash - 1), 1, MaxLongInt, N) or
         ((Dash < Length(Value)) and not StrToNum(Copy(Value, Dash + 1, MaxInt), N, MaxLongInt, N2)) then
        Usage('--lines wants A-B or A- (line numbers)');
      Opt.FirstLine := N;
      Opt.LastLine := N2;
    end
    else
      Usage('unknown option ' + Arg);
  end;
  if FileName = '' then
    Usage('no input file');
  if not ReadAll(FileName, Text) then
    Halt(2);
  case Input of
    'c':
      Count := TrcReadText(Text, Frames);
    'h':
      begin
        if not DecodeHexText(Text, Data, Err) then
        begin
          WriteLn(StdErr, 'chndecode: ', FileName, ': ', Err);
          Halt(2);
        end;
        DecodeBytesAsChunk(Data, Frames);
        Count := 1;
      end;
  else
    begin
      SetLength(Data, Length(Text));
      if Text <> '' then
        Move(Text[1], Data[0], Length(Text));
      DecodeBytesAsChunk(Data, Frames);
      Count := 1;
    end;
  end;
  Lines := TStringList.Create;
  try
    DecodeRun(Opt, Frames, Count, Lines, Stats);
    for I := 0 to Lines.Count - 1 do
      WriteLn(Lines[I]);
  finally
    Lines.Free;
  end;
  if Stats.Chunks = 0 then
  begin
    WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
    Halt(2);
  end;
  if (Stats.Errors > 0) or (Stats.Incomplete > 0) or (Stats.BadChunks > 0) then
    Halt(1);
end.
