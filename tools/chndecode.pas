{ chndecode - print each frame of a capture decoded: DF1, FT1.2 or ICS.

    chndecode [input] [protocol] [options] [output] FILE
      input     --capture  RACOM text capture / NAM=TRC log, or a pcap
                           file (link type 250, RTAC serial) (default)
                --pcap     a pcap file (link type 250) only
                --hex      hex text ('10 02 03 00 ...'), one received stream
                --bin      a binary file, one received stream
      protocol  --df1 [--crc|--bcc] [--half [--master=tx|rx]]   (default --df1 --crc)
                --ft12 [--adr=0..2] [--len=N] [--cot-size=1|2] [--ca-size=1|2] [--ioa-size=1..3]
                --ics
      options   --lines=A-B   only chunks whose header is on lines A..B
                              (pcap: records A..B)
      output    --to-pcap=OUT [--date=YYYY-MM-DD]  the chunks as a pcap file
                              (time of day as local time on that date,
                              default today); nothing is decoded
                --to-text     the chunks in the trace layer's text format
                --svg=OUT [--gap=MS] [--title=T]  also a ladder diagram;
                              pauses longer than MS (default 1000) marked
    FILE '-' reads standard input.

  The work is done by units ChnFrameDecode, ChnPcap and ChnLadder
  (docs/chndecode.md). Exit code: 0 all
  frames good, 1 broken or incomplete frames found, 2 usage error or
  unreadable input. }
program chndecode;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, DateUtils, uString, ChnTypes, ChnTrcFormat, ChnPcap,
  ChnFrameDecode, ChnLadder;

procedure Usage(const Why: string);
begin
  WriteLn(StdErr, 'chndecode: ', Why);
  WriteLn(StdErr, 'usage: chndecode [--capture|--pcap|--hex|--bin] [--df1 [--crc|--bcc] [--half [--master=tx|rx]] | --ft12 [--adr=N] [--len=N] [--cot-size=N] [--ca-size=N] [--ioa-size=N] | --ics] [--lines=A-B]');
  WriteLn(StdErr, '                 [--to-pcap=OUT [--date=YYYY-MM-DD] | --to-text | --svg=OUT [--gap=MS] [--title=T]] FILE');
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

{ Seconds to add to UTC for local time, now. }
function UtcOffsetSec: LongInt;
begin
  Result := Round((Now - LocalTimeToUniversal(Now)) * 86400);
end;

function WriteAll(const Name: string; const Data: AnsiString): Boolean;
var
  S: TFileStream;
begin
  Result := False;
  try
    S := TFileStream.Create(Name, fmCreate);
    try
      if Data <> '' then
        S.WriteBuffer(Data[1], Length(Data));
    finally
      S.Free;
    end;
    Result := True;
  except
    on E: Exception do
      WriteLn(StdErr, 'chndecode: ', Name, ': ', E.Message);
  end;
end;

function IsPcap(const Text: AnsiString): Boolean;
var
  Magic: LongWord;
begin
  Result := False;
  if Length(Text) < 4 then
    Exit;
  Move(Text[1], Magic, 4);
  Magic := LEtoN(Magic);
  Result := (Magic = PcapMagic) or (Magic = PcapMagicNano) or
    (SwapEndian(Magic) = PcapMagic) or (SwapEndian(Magic) = PcapMagicNano);
end;

var
  Opt: tDecOptions;
  Dec: tDecoder;
  Info: tPcapInfo;
  Ladder: tLadderOptions;
  ToPcap, ToText, SvgOut: string;
  Midnight: TDateTime;
  Y, Mo, Dy: LongInt;
  R: tChResult;
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
  LadderDefaults(Ladder);
  Input := 'c';
  FileName := '';
  ToPcap := '';
  ToText := '';
  SvgOut := '';
  Midnight := Date;
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
    DecodeSplitArg(Arg, Key, Value);
    N := 0;
    if DecodeOption(Key, Value, Opt, Err) then
    begin
      if Err <> '' then
        Usage(Err);
    end
    else if Key = '--capture' then Input := 'c'
    else if Key = '--pcap' then Input := 'p'
    else if Key = '--hex' then Input := 'h'
    else if Key = '--bin' then Input := 'b'
    else if Key = '--master' then
    begin
      if Value = 'tx' then Opt.MasterDir := trcTx
      else if Value = 'rx' then Opt.MasterDir := trcRx
      else Usage('--master wants tx or rx');
    end
    else if Key = '--to-pcap' then
    begin
      if Value = '' then
        Usage('--to-pcap wants a file name');
      ToPcap := Value;
    end
    else if Key = '--to-text' then ToText := 'y'
    else if Key = '--svg' then
    begin
      if Value = '' then
        Usage('--svg wants a file name');
      SvgOut := Value;
    end
    else if Key = '--gap' then
    begin
      if not StrToNum(Value, 0, 86400000, N) then
        Usage('--gap wants milliseconds, 0..86400000');
      Ladder.GapMs := N;
    end
    else if Key = '--title' then Ladder.Title := Value
    else if Key = '--date' then
    begin
      Y := 0;
      Mo := 0;
      Dy := 0;
      if (Length(Value) <> 10) or (Value[5] <> '-') or (Value[8] <> '-') or
         not StrToNum(Copy(Value, 1, 4), 1970, 2105, Y) or
         not StrToNum(Copy(Value, 6, 2), 1, 12, Mo) or
         not StrToNum(Copy(Value, 9, 2), 1, 31, Dy) or
         not TryEncodeDate(Y, Mo, Dy, Midnight) then
        Usage('--date wants YYYY-MM-DD, e.g. 2026-12-01');
    end
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
  if (Input = 'c') and IsPcap(Text) then
    Input := 'p';
  case Input of
    'c':
      Count := TrcReadText(Text, Frames);
    'p':
      begin
        R := PcapReadBytes(Text, UtcOffsetSec, Frames, Info);
        Count := Length(Frames);
        if R <> res_Ok then
        begin
          WriteLn(StdErr, 'chndecode: ', FileName, ': ', ChResultText(R, TrcLayer),
            ' at byte ', Info.ErrPos, ': ', Info.ErrText);
          if (R <> res_PcapCut) or (Count = 0) then
            Halt(2);
        end;
        if Info.Skipped > 0 then
          WriteLn(StdErr, 'chndecode: ', FileName, ': ', Info.Skipped,
            ' records without TX/RX data skipped');
      end;
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
  if ToPcap <> '' then
  begin
    if Count = 0 then
    begin
      WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
      Halt(2);
    end;
    if not WriteAll(ToPcap, PcapFromTrc(Frames, Count,
      DateTimeToUnix(LocalTimeToUniversal(Midnight)))) then
      Halt(2);
    WriteLn(Count, ' chunks written to ', ToPcap);
    Halt(0);
  end;
  if ToText <> '' then
  begin
    if Count = 0 then
    begin
      WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
      Halt(2);
    end;
    { the tag the trace layer writes, so a NAM=TRC log comes back as it was }
    for I := 0 to Count - 1 do
      if Length(Frames[I].Data) > 0 then
        Write(TrcFormat(Frames[I].TimeMs, Frames[I].Dir, Frames[I].Data[0],
          Length(Frames[I].Data), trcHex, 'TRC'))
      else
        Write(TrcFormat(Frames[I].TimeMs, Frames[I].Dir, I, 0, trcHex, 'TRC'));
    Halt(0);
  end;
  Lines := TStringList.Create;
  try
    DecodeBegin(Dec, Opt, Lines);
    Dec.KeepEvents := SvgOut <> '';
    for I := 0 to Count - 1 do
      DecodeChunk(Dec, Frames[I]);
    DecodeEnd(Dec, Stats);
    for I := 0 to Lines.Count - 1 do
      WriteLn(Lines[I]);
  finally
    Lines.Free;
  end;
  if SvgOut <> '' then
  begin
    if Ladder.Title = 'trace' then
      Ladder.Title := ExtractFileName(FileName);
    if not WriteAll(SvgOut, LadderSvg(Dec.Events, Dec.EventCount, Ladder)) then
      Halt(2);
  end;
  if Stats.Chunks = 0 then
  begin
    WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
    Halt(2);
  end;
  if (Stats.Errors > 0) or (Stats.Incomplete > 0) or (Stats.BadChunks > 0) then
    Halt(1);
end.
