{ chndecode - print each frame of a capture decoded: DF1, FT1.2 or ICS.

    chndecode [input] [protocol] [options] [output] FILE
      input     --capture  RACOM text capture / NAM=TRC log, or a pcap
                           file (link type 250, RTAC serial) (default)
                --pcap     a pcap file (link type 250) only
                --hex      hex text ('10 02 03 00 ...'), one received stream
                --bin      a binary file, one received stream
      protocol  --df1 [--crc|--bcc] [--half [--master=tx|rx]]   (default --df1;
                without --crc or --bcc the check is found from the frames
                and named on standard error)
                --ft12 [--adr=0..2] [--len=N] [--cot-size=1|2] [--ca-size=1|2] [--ioa-size=1..3]
                --ics
                --iec104 [--cot-size=1|2] [--ca-size=1|2] [--ioa-size=1..3]
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
  (docs/chndecode.md); the command line is unit ChnCli's (docs/TOOLS.md):
  every value option takes --opt VALUE and --opt=VALUE. Exit code: 0 all
  frames good, 1 broken or incomplete frames found, 2 usage error, or an
  input that is unreadable or damaged (a pcap cut off or with an
  impossible record, a chunk shorter than its header says): what could
  be read is still decoded and printed. }
program chndecode;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, Classes, DateUtils, uString, ChnTypes, ChnOs, ChnTrcFormat, ChnPcap,
  ChnFrameDecode, ChnLadder, ChnCli;

var
  Cli: tCli;

procedure Usage(const Why: string);
begin
  CliUsageError(Cli, Why, '');
end;

function ReadAll(const Name: string; out Text: AnsiString): Boolean;
var
  M: TMemoryStream;
  Inp: THandleStream;
  Err: ShortString;
begin
  Text := '';
  if Name <> '-' then
  begin
    Result := OsFileLoad(Name, Text, Err);
    if not Result then
      WriteLn(StdErr, 'chndecode: ', Err);
    Exit;
  end;
  Result := False;
  try
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
  Err: ShortString;
begin
  Result := OsFileSave(Name, Data, Err);
  if not Result then
    WriteLn(StdErr, 'chndecode: ', Err);
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
  FileName, Err, Value, Why: string;
  Text: AnsiString;
  I, Count, Dash: Integer;
  N, N2: LongInt;
  Damaged: Boolean;
begin
  CliInit(Cli, 'chndecode', '[OPTION]... FILE',
    'Print each frame of a capture decoded: DF1, FT 1.2, ICS or IEC 104. FILE is a RACOM ' +
    'text capture or NAM=TRC log (--capture, the default), a pcap file of link type ' +
    '250 (RTAC serial), hex text or a binary stream; - reads standard input. DF1 ' +
    'without --crc or --bcc: the check is found from the frames and named on ' +
    'standard error.');
  CliOption(Cli, 'capture', #0, '', 'a RACOM text capture / NAM=TRC log, or a pcap (default)');
  CliOption(Cli, 'pcap', #0, '', 'a pcap file (link type 250) only');
  CliOption(Cli, 'hex', #0, '', 'hex text (''10 02 03 00 ...''), one received stream');
  CliOption(Cli, 'bin', #0, '', 'a binary file, one received stream');
  CliOption(Cli, 'df1', #0, '', 'DF1 (default)');
  CliOption(Cli, 'crc', #0, '', 'DF1 with CRC-16');
  CliOption(Cli, 'bcc', #0, '', 'DF1 with BCC');
  CliOption(Cli, 'half', #0, '', 'DF1 half duplex');
  CliOption(Cli, 'master', #0, 'tx|rx', 'DF1 half duplex: the direction of the master''s bytes');
  CliOption(Cli, 'ft12', #0, '', 'FT 1.2 (IEC 60870-5-2)');
  CliOption(Cli, 'adr', #0, '0..2', 'FT 1.2 link address octets (default 1)');
  CliOption(Cli, 'len', #0, 'N', 'FT 1.2 data octets of a fixed frame (default 0)');
  CliOption(Cli, 'cot-size', #0, '1|2', 'FT 1.2 ASDU: cause of transmission octets (default 2)');
  CliOption(Cli, 'ca-size', #0, '1|2', 'FT 1.2 ASDU: common address octets (default 2)');
  CliOption(Cli, 'ioa-size', #0, '1..3', 'FT 1.2 ASDU: information object address octets (default 3)');
  CliOption(Cli, 'ics', #0, '', 'DACS ICSlink');
  CliOption(Cli, 'iec104', #0, '', 'IEC 60870-5-104 (APCI; the ASDU of each I frame with the sizes above)');
  CliOption(Cli, 'lines', #0, 'A-B', 'only chunks whose header is on lines A..B (pcap: records); ' +
    'A- for all from A');
  CliOption(Cli, 'to-pcap', #0, 'OUT', 'write the chunks as a pcap file; nothing is decoded');
  CliOption(Cli, 'date', #0, 'YYYY-MM-DD', 'with --to-pcap: the date of the times (default today)');
  CliOption(Cli, 'to-text', #0, '', 'print the chunks in the trace layer''s text format');
  CliOption(Cli, 'svg', #0, 'OUT', 'also draw a ladder diagram into OUT');
  CliOption(Cli, 'gap', #0, 'MS', 'with --svg: mark pauses longer than MS (default 1000, 0 none)');
  CliOption(Cli, 'title', #0, 'T', 'with --svg: the title (default the file name)');
  CliEpilog(Cli, 'Examples:' + LineEnding +
    '  chndecode --df1 plc.log' + LineEnding +
    '  chndecode --df1 --svg=plc.svg plc.pcap' + LineEnding +
    '  chndecode --ft12 --adr=1 --lines 1-20 line.log' + LineEnding);
  CliExit(Cli, 0, 'every frame good');
  CliExit(Cli, 1, 'broken or incomplete frames found');
  CliExit(Cli, 2, 'also: the input cannot be read or is damaged (a pcap cut off or with an ' +
    'impossible record, a chunk shorter than announced); what could be read is decoded');
  CliParse(Cli);
  DecodeDefaults(Opt);
  LadderDefaults(Ladder);
  Input := 'c';
  ToPcap := '';
  ToText := '';
  SvgOut := '';
  Midnight := Date;
  if CliArgCount(Cli) = 0 then
    Usage('no input file');
  if CliArgCount(Cli) > 1 then
    CliUsageError(Cli, 'more than one input file', Cli.Args[1]);
  FileName := Cli.Args[0];
  for I := 0 to High(DecodeOptionNames) do
    if CliHas(Cli, DecodeOptionNames[I]) then
      if DecodeOption('--' + DecodeOptionNames[I], CliValue(Cli, DecodeOptionNames[I], ''), Opt, Err) and
         (Err <> '') then
        CliUsageError(Cli, Err, CliValue(Cli, DecodeOptionNames[I], ''));
  if CliHas(Cli, 'pcap') then Input := 'p';
  if CliHas(Cli, 'hex') then Input := 'h';
  if CliHas(Cli, 'bin') then Input := 'b';
  case CliChoice(Cli, 'master', 'TX|RX', 0) of
    0: Opt.MasterDir := trcTx;
    1: Opt.MasterDir := trcRx;
  end;
  ToPcap := CliValue(Cli, 'to-pcap', '');
  if CliHas(Cli, 'to-pcap') and (ToPcap = '') then
    Usage('--to-pcap wants a file name');
  if CliHas(Cli, 'to-text') then
    ToText := 'y';
  SvgOut := CliValue(Cli, 'svg', '');
  if CliHas(Cli, 'svg') and (SvgOut = '') then
    Usage('--svg wants a file name');
  Ladder.GapMs := CliNum(Cli, 'gap', 0, 86400000, Ladder.GapMs);
  Ladder.Title := CliValue(Cli, 'title', Ladder.Title);
  if CliHas(Cli, 'date') then
  begin
    Value := CliValue(Cli, 'date', '');
    Y := 0;
    Mo := 0;
    Dy := 0;
    if (Length(Value) <> 10) or (Value[5] <> '-') or (Value[8] <> '-') or
       not StrToNum(Copy(Value, 1, 4), 1970, 2105, Y) or
       not StrToNum(Copy(Value, 6, 2), 1, 12, Mo) or
       not StrToNum(Copy(Value, 9, 2), 1, 31, Dy) or
       not TryEncodeDate(Y, Mo, Dy, Midnight) then
      CliUsageError(Cli, '--date wants YYYY-MM-DD, e.g. 2026-12-01', Value);
  end;
  if CliHas(Cli, 'lines') then
  begin
    Value := CliValue(Cli, 'lines', '');
    Dash := Pos('-', Value);
    N := 0;
    N2 := 0;
    if (Dash = 0) or not StrToNum(Copy(Value, 1, Dash - 1), 1, MaxLongInt, N) or
       ((Dash < Length(Value)) and not StrToNum(Copy(Value, Dash + 1, MaxInt), N, MaxLongInt, N2)) then
      CliUsageError(Cli, '--lines wants A-B or A- (line numbers)', Value);
    Opt.FirstLine := N;
    Opt.LastLine := N2;
  end;
  Damaged := False;
  if not ReadAll(FileName, Text) then
    CliEnd(2);
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
            CliEnd(2);
          Damaged := True;
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
          CliEnd(2);
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
      CliEnd(2);
    end;
    if not WriteAll(ToPcap, PcapFromTrc(Frames, Count,
      DateTimeToUnix(LocalTimeToUniversal(Midnight)))) then
      CliEnd(2);
    WriteLn(Count, ' chunks written to ', ToPcap);
    CliEnd(0);
  end;
  if ToText <> '' then
  begin
    if Count = 0 then
    begin
      WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
      CliEnd(2);
    end;
    { the tag the trace layer writes, so a NAM=TRC log comes back as it was }
    for I := 0 to Count - 1 do
      if Length(Frames[I].Data) > 0 then
        Write(TrcFormat(Frames[I].TimeMs, Frames[I].Dir, Frames[I].Data[0],
          Length(Frames[I].Data), trcHex, 'TRC'))
      else
        Write(TrcFormat(Frames[I].TimeMs, Frames[I].Dir, I, 0, trcHex, 'TRC'));
    CliEnd(0);
  end;
  if (Opt.Proto = dpDF1) and not CliHas(Cli, 'crc') and not CliHas(Cli, 'bcc') then
  begin
    Opt.Crc := DecodeGuessDF1Check(Opt, Frames, Count, Why);
    if Opt.Crc then
      WriteLn(StdErr, 'chndecode: DF1 check: CRC, found from the frames (', Why, ')')
    else
      WriteLn(StdErr, 'chndecode: DF1 check: BCC, found from the frames (', Why, ')');
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
      CliEnd(2);
  end;
  if Stats.Chunks = 0 then
  begin
    WriteLn(StdErr, 'chndecode: ', FileName, ': no chunks found');
    CliEnd(2);
  end;
  if Damaged or (Stats.BadChunks > 0) then
  begin
    WriteLn(StdErr, 'chndecode: ', FileName, ': the input is damaged (',
      Stats.BadChunks, ' chunks shorter than announced); what could be read is above');
    CliEnd(2);
  end;
  if (Stats.Errors > 0) or (Stats.Incomplete > 0) then
    CliEnd(1);
end.
