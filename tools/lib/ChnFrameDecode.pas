{ ChnFrameDecode - decoding captured traffic frame by frame: the logic of
  tools/chndecode, as a unit so that tests call it directly.

  Input is a list of chunks (tTrcFrame of unit ChnTrcFormat): read from a
  capture in the RACOM text format that the trace layer NAM=TRC writes
  (TrcReadText), or made from raw hex text or a binary file as one
  received chunk. Each direction (tx, rx) has its own receive automaton of
  the protocol's codec (DF1Feed, FT12Feed, ICSFeed), fed with the chunks of
  that direction in order, so a frame may span chunks: its description is
  printed under the chunk in which it ends. A DF1 reply is named after the
  command with the same TNS seen before (replies carry no FNC).

  Per frame: the fields, the checksum verdict (a good frame passed the
  codec's BCC/CRC/sum check; a bad one says what was received and what was
  computed) and, for a broken frame, the codec's result code and text.
  Half-duplex DF1: the master's direction is decoded as a slave would (but
  for every station address), the other one as the master would.

  Nothing here does I/O: lines are appended to a TStrings. }
unit ChnFrameDecode;

{$I chn.inc}

interface

uses
  Classes, ChnTypes, ChnTrcFormat, ChnDF1Codec, ChnFT12Codec, ChnICSCodec, ChnIec101Asdu,
  ChnIec104Codec;

type
  tDecProto = (dpDF1, dpFT12, dpICS, dpIec104);

  tDecOptions = record
    Proto    : tDecProto;
    Crc      : Boolean;   { DF1: CRC-16, else BCC }
    Half     : Boolean;   { DF1: half duplex }
    MasterDir: tTrcDir;   { DF1 half duplex: direction of the master's bytes }
    AddrLen  : Byte;      { FT1.2: link address octets 0..2 }
    FixedLen : Byte;      { FT1.2: data octets of a fixed frame }
    Asdu     : tIecParams; { FT1.2, IEC 104: the ASDU of a variable frame / I frame, decoded
                            (--cot-size --ca-size --ioa-size, default 2 2 3) }
    FirstLine: LongInt;   { only chunks whose header line lies in }
    LastLine : LongInt;   { FirstLine..LastLine; 0 = no limit }
  end;

  tDecStats = record
    Chunks    : LongInt;  { chunks decoded }
    Bytes     : LongInt;
    Frames    : LongInt;  { good frames and link symbols }
    Errors    : LongInt;  { broken frames }
    Incomplete: LongInt;  { directions that ended inside a frame }
    BadChunks : LongInt;  { chunks the reader found short or long }
  end;

  { commands seen, by TNS: names the replies (which carry no FNC) }
  tTnsTable = array[Byte] of record
    Used: Boolean;
    Tns : Word;
    Cmd, Fnc: Byte;
  end;

  tDirState = record
    Name : ShortString;
    DF1  : tDF1Decoder;
    FT   : tFT12Rx;
    ICS  : tICSState;
    A104 : tApci104Feed;
    Hunt104: Boolean;    { IEC 104: after a broken APDU, skip to the next 68h }
    Monitor: Boolean;    { DF1 half duplex: decode master frames for every station }
  end;

  { One decoded frame (or link symbol, or broken frame), for programs that
    draw or print frames their own way (chndecode --svg, chntap). }
  tDecEvent = record
    TimeMs : LongInt;     { of the chunk in which the frame ended }
    Dir    : tTrcDir;
    Line   : LongInt;     { the chunk's header line / pcap record }
    Proto  : string[7];   { DF1, FT1.2, ICS, IEC104 }
    Text   : AnsiString;  { the description chndecode prints after the protocol }
    IsError: Boolean;     { a broken frame }
    Refused: Boolean;     { a good frame that reports a failure: a DF1 reply
                            with STS <> 0, a DF1 NAK, an FT 1.2 NACK ($A2) }
  end;
  tDecEvents = array of tDecEvent;

  { The decoder for one run: DecodeBegin, DecodeChunk per chunk in order,
    DecodeEnd. Lines (may be nil) gets the printed lines; Events[0..
    EventCount-1] every frame when KeepEvents (a caller may take them and
    set EventCount := 0 between chunks). }
  tDecoder = record
    Opt       : tDecOptions;
    Dirs      : array[tTrcDir] of tDirState;
    Seen      : tTnsTable;
    Stats     : tDecStats;
    Lines     : TStrings;
    KeepEvents: Boolean;
    Events    : tDecEvents;
    EventCount: LongInt;
    CurTime   : LongInt;
    CurLine   : LongInt;
  end;

procedure DecodeDefaults(var Opt: tDecOptions);

{ '--key=value' -> '--key', 'value'; without '=' Value is ''. }
procedure DecodeSplitArg(const Arg: AnsiString; out Key, Value: AnsiString);
{ The protocol options the programs share: --df1 --crc --bcc --half --ft12
  --adr=0..2 --len=0..247 --cot-size=1|2 --ca-size=1|2 --ioa-size=1..3
  (the ASDU of FT 1.2 variable frames) --ics. True when Key is one of them; Err is ''
  or says what is wrong with Value. (--master differs per program.) }
const
  { the protocol options DecodeOption takes, without the leading '--':
    chndecode and chntap offer exactly these }
  DecodeOptionNames: array[0..11] of ShortString = ('df1', 'crc', 'bcc', 'half',
    'ft12', 'ics', 'iec104', 'adr', 'len', 'cot-size', 'ca-size', 'ioa-size');

function DecodeOption(const Key, Value: AnsiString; var Opt: tDecOptions;
  out Err: AnsiString): Boolean;

procedure DecodeBegin(var D: tDecoder; const Opt: tDecOptions; Lines: TStrings);
{ One chunk (a header line goes to Lines, then its frames); chunks outside
  Opt.FirstLine..LastLine are passed over. }
procedure DecodeChunk(var D: tDecoder; const F: tTrcFrame);
{ Directions that end inside a frame, and the summary line. }
procedure DecodeEnd(var D: tDecoder; out Stats: tDecStats);

{ Hex text ('10 02 0300', '1002,0E0D', '0x10 0x02'): pairs of hex digits,
  separated by anything that is not a hex digit; a '0x' prefix is skipped.
  False (with Err) for an odd run of digits. }
function DecodeHexText(const Text: AnsiString; var Data: tTrcBytes; out Err: AnsiString): Boolean;

{ Raw bytes as one received chunk (line 0). }
procedure DecodeBytesAsChunk(const Data: tTrcBytes; var Frames: tTrcFrames);

{ Decode Frames[0..Count-1]; lines go to Lines, counts to Stats. }
procedure DecodeRun(const Opt: tDecOptions; const Frames: tTrcFrames; Count: LongInt;
  Lines: TStrings; out Stats: tDecStats);
{ DF1 without --crc or --bcc: decodes the chunks both ways and returns
  True for CRC, False for BCC - the check with fewer broken frames (a BCC
  frame read as CRC takes one byte too many and fails, a CRC frame read as
  BCC fails its one-byte sum), on a tie the one with more good frames, on
  a tie CRC. Why gives the counts, for the line that says which was taken. }
function DecodeGuessDF1Check(const Opt: tDecOptions; const Frames: tTrcFrames;
  Count: LongInt; out Why: AnsiString): Boolean;
{ The rule above for two running totals (chntap decides live): True = CRC. }
function DecodeBetterCheck(const Crc, Bcc: tDecStats): Boolean;

implementation

uses
  SysUtils, uString, ChnDF1, ChnFT1_2, ChnICS, ChnPcccNames, ChnIec101Print;

procedure DecodeSplitArg(const Arg: AnsiString; out Key, Value: AnsiString);
begin
  Key := Arg;
  Value := '';
  if Pos('=', Arg) > 0 then
  begin
    Key := Copy(Arg, 1, Pos('=', Arg) - 1);
    Value := Copy(Arg, Pos('=', Arg) + 1, MaxInt);
  end;
end;

function DecodeOption(const Key, Value: AnsiString; var Opt: tDecOptions;
  out Err: AnsiString): Boolean;
var
  N: LongInt;
begin
  Err := '';
  N := 0;
  Result := True;
  if Key = '--df1' then Opt.Proto := dpDF1
  else if Key = '--crc' then Opt.Crc := True
  else if Key = '--bcc' then Opt.Crc := False
  else if Key = '--half' then Opt.Half := True
  else if Key = '--ft12' then Opt.Proto := dpFT12
  else if Key = '--ics' then Opt.Proto := dpICS
  else if Key = '--iec104' then Opt.Proto := dpIec104
  else if Key = '--adr' then
  begin
    if StrToNum(Value, 0, 2, N) then
      Opt.AddrLen := N
    else
      Err := '--adr wants 0, 1 or 2';
  end
  else if Key = '--len' then
  begin
    if StrToNum(Value, 0, 247, N) then
      Opt.FixedLen := N
    else
      Err := '--len wants 0..247';
  end
  else if Key = '--cot-size' then
  begin
    if StrToNum(Value, 1, 2, N) then
      Opt.Asdu.CotSize := N
    else
      Err := '--cot-size wants 1 or 2';
  end
  else if Key = '--ca-size' then
  begin
    if StrToNum(Value, 1, 2, N) then
      Opt.Asdu.CaSize := N
    else
      Err := '--ca-size wants 1 or 2';
  end
  else if Key = '--ioa-size' then
  begin
    if StrToNum(Value, 1, 3, N) then
      Opt.Asdu.IoaSize := N
    else
      Err := '--ioa-size wants 1, 2 or 3';
  end
  else
    Result := False;
end;

procedure DecodeDefaults(var Opt: tDecOptions);
begin
  FillChar(Opt, SizeOf(Opt), 0);
  Opt.Proto := dpDF1;
  Opt.Crc := True;
  Opt.MasterDir := trcTx;
  Opt.AddrLen := 1;
  Opt.Asdu := IecDefaultParams;
end;


function DecodeHexText(const Text: AnsiString; var Data: tTrcBytes; out Err: AnsiString): Boolean;
var
  I, J, N: Integer;
begin
  Err := '';
  N := 0;
  SetLength(Data, Length(Text) div 2 + 1);
  I := 1;
  while I <= Length(Text) do
  begin
    if (Text[I] = '0') and (I < Length(Text)) and (Text[I + 1] in ['x', 'X']) then
      Inc(I, 2);
    if (I > Length(Text)) or (HexDigit(Text[I]) < 0) then
    begin
      Inc(I);
      Continue;
    end;
    J := I;
    while (J <= Length(Text)) and (HexDigit(Text[J]) >= 0) do
      Inc(J);
    if Odd(J - I) then
    begin
      Err := Format('odd number of hex digits at character %d', [I]);
      SetLength(Data, 0);
      Exit(False);
    end;
    while I < J do
    begin
      Data[N] := HexDigit(Text[I]) * 16 + HexDigit(Text[I + 1]);
      Inc(N);
      Inc(I, 2);
    end;
  end;
  SetLength(Data, N);
  Result := True;
end;

procedure DecodeBytesAsChunk(const Data: tTrcBytes; var Frames: tTrcFrames);
begin
  SetLength(Frames, 1);
  FillChar(Frames[0], SizeOf(Frames[0]) - SizeOf(Frames[0].Data), 0);
  Frames[0].Line := 0;
  Frames[0].Dir := trcRx;
  Frames[0].DirText := 'rx';
  Frames[0].Tag := 'raw';
  Frames[0].Len := Length(Data);
  Frames[0].Data := Copy(Data, 0, Length(Data));
  Frames[0].Status := res_Ok;
end;


{ A frame was decoded: print it and keep it as an event. }
procedure Emit(var D: tDecoder; Dir: tTrcDir; const Proto, Text: AnsiString; IsError: Boolean);
begin
  if IsError then
    Inc(D.Stats.Errors)
  else
    Inc(D.Stats.Frames);
  if D.Lines <> nil then
    D.Lines.Add('  ' + D.Dirs[Dir].Name + ' ' + Proto + ' ' + Text);
  if not D.KeepEvents then
    Exit;
  if D.EventCount >= Length(D.Events) then
    SetLength(D.Events, 2 * D.EventCount + 16);
  D.Events[D.EventCount].TimeMs := D.CurTime;
  D.Events[D.EventCount].Dir := Dir;
  D.Events[D.EventCount].Line := D.CurLine;
  D.Events[D.EventCount].Proto := Proto;
  D.Events[D.EventCount].Text := Text;
  D.Events[D.EventCount].IsError := IsError;
  D.Events[D.EventCount].Refused := False;
  Inc(D.EventCount);
end;

{ ----------------------------------------------------------------- DF1 }

function DF1SumText(const D: tDF1Decoder): AnsiString;
begin
  if D.Cfg.Crc then
    Result := Format('CRC $%.4x', [D.RxSum])
  else
    Result := Format('BCC $%.2x', [D.RxSum]);
end;

function DF1Message(const D: tDF1Decoder; var Seen: tTnsTable): AnsiString;
var
  M: ChnDF1Codec.tRecRecord;
  Cmd, Fnc: Byte;
  Name: AnsiString;
  N: Integer;
begin
  M := D.Msg;
  case M.MessType of
    tpAckNak:
      if M.FlAck then
        Result := 'ACK (DLE ACK)'
      else
        Result := 'NAK (DLE NAK)';
    tpEnq: Result := 'ENQ (DLE ENQ)';
    tpPoll: Result := Format('poll STN=%d, BCC ok', [D.Dst]);
    tpNoPollRep: Result := 'EOT (DLE EOT, nothing to send)';
    tpDataMess:
      begin
        Cmd := Hi(M.CF);
        Fnc := Lo(M.CF);
        N := D.MsgLen - cSizeHead;
        Result := Format('DST=%d SRC=%d CMD=$%.2x', [D.Dst, D.Src, Cmd]);
        if DF1HasFnc(Cmd) then
          Result := Result + Format(' FNC=$%.2x', [Fnc]);
        Result := Result + Format(' STS=$%.2x TNS=$%.4x', [M.Sts, M.Tns]);
        if D.HdMaster then
          Result := Format('STN=%d ', [D.Stn]) + Result;
        Name := PcccCommandName(Cmd, Fnc);
        if Cmd and $40 = 0 then
        begin
          Seen[Lo(M.Tns)].Used := True;
          Seen[Lo(M.Tns)].Tns := M.Tns;
          Seen[Lo(M.Tns)].Cmd := Cmd;
          Seen[Lo(M.Tns)].Fnc := Fnc;
        end
        else if Seen[Lo(M.Tns)].Used and (Seen[Lo(M.Tns)].Tns = M.Tns) and
                (Seen[Lo(M.Tns)].Cmd or $40 = Cmd) then
          Name := PcccCommandName(Cmd, Seen[Lo(M.Tns)].Fnc);
        if Cmd and $40 <> 0 then
        begin
          if Name = '' then
            Name := 'reply'
          else
            Name := 'reply to ' + Name;
          if M.Sts <> 0 then
          begin
            Name := Name + ', STS: ' + PcccStsText(M.Sts);
            if (M.Sts = $F0) and (N > 0) then
              Name := Name + Format(', EXT STS $%.2x: %s', [M.Data[0], PcccExtStsText(M.Data[0])]);
          end;
        end
        else if Name = '' then
          Name := 'command';
        Result := Result + ' (' + Name + ')';
        Result := Result + Format(', %d data bytes', [N]);
        if N > 0 then
          Result := Result + ': ' + HexBytes(@M.Data[0], N);
        Result := Result + ', ' + DF1SumText(D) + ' ok';
      end;
  else
    Result := '?';
  end;
end;

function DF1Error(const D: tDF1Decoder; AfterSum: Boolean): AnsiString;
var
  Calc: Word;
begin
  Result := Format('ERROR $%.2x %s', [D.Err, ChResultText(D.Err, ChnDF1.cName)]);
  if not AfterSum then
    Exit;
  { a whole frame was read: say what was in it }
  if D.Cfg.Crc then
    Calc := D.Crc
  else
    Calc := Bcc8Final(D.Bcc);
  if D.Err = ChnDF1Codec.res_ErrSum then
  begin
    if D.Cfg.Crc then
      Result := Result + Format(': received CRC $%.4x, computed $%.4x', [D.RxSum, Calc])
    else
      Result := Result + Format(': received BCC $%.2x, computed $%.2x', [D.RxSum, Calc]);
  end
  else
  begin
    Result := Result + ': ' + DF1SumText(D) + ' ok';
    if (D.Err = ChnDF1Codec.res_ErrFrame) and (D.BodyLen < 6) then
      Result := Result + Format(', but only %d bytes between DLE STX and DLE ETX (%s);' +
        ' DST SRC CMD STS TNS need 6', [D.BodyLen, HexBytes(@D.Body[0], D.BodyLen)]);
  end;
end;

procedure DF1Init(var S: tDirState; const Opt: tDecOptions; Dir: tTrcDir);
var
  Cfg: tDF1Config;
begin
  FillChar(Cfg, SizeOf(Cfg), 0);
  Cfg.FullDup := not Opt.Half;
  Cfg.Crc := Opt.Crc;
  Cfg.NakByte := NAK;
  { half duplex: the master's bytes are read as a slave reads them }
  Cfg.Master := not (Opt.Half and (Dir = Opt.MasterDir));
  S.Monitor := Opt.Half and (Dir = Opt.MasterDir);
  DF1DecoderInit(S.DF1, Cfg);
end;

procedure DF1Byte(var Dec: tDecoder; Dir: tTrcDir; B: Byte);
var
  Before: Byte;
  Ev: tDF1Event;
begin
  Before := Dec.Dirs[Dir].DF1.State;
  { a monitor hears every station: take the poll's / frame's STN as ours }
  if Dec.Dirs[Dir].Monitor and (Before = dsPollBcc) then
    Dec.Dirs[Dir].DF1.Cfg.Node := Dec.Dirs[Dir].DF1.Stn;
  Ev := DF1Feed(Dec.Dirs[Dir].DF1, B);
  if Dec.Dirs[Dir].Monitor and (Before in [dsStn, dsStnDle]) and (Dec.Dirs[Dir].DF1.State = dsSohDle) then
    Dec.Dirs[Dir].DF1.Ignore := False;
  case Ev of
    dfMessage:
      begin
        Emit(Dec, Dir, 'DF1', DF1Message(Dec.Dirs[Dir].DF1, Dec.Seen), False);
        with Dec.Dirs[Dir].DF1.Msg do
          if Dec.KeepEvents and (((MessType = tpAckNak) and not FlAck) or
             ((MessType = tpDataMess) and (Hi(CF) and $40 <> 0) and (Sts <> 0))) then
            Dec.Events[Dec.EventCount - 1].Refused := True;
      end;
    dfError:
      begin
        Emit(Dec, Dir, 'DF1', DF1Error(Dec.Dirs[Dir].DF1, Before = dsSum), True);
      end;
  end;
end;

{ ----------------------------------------------------------------- FT1.2 }

procedure FTInit(var S: tDirState; const Opt: tDecOptions);
begin
  FillChar(S.FT, SizeOf(S.FT), 0);
  S.FT.Cfg.AddrLen := Opt.AddrLen;
  S.FT.Cfg.FixedLen := Opt.FixedLen;
  FT12RxReset(S.FT);
end;

procedure FTByte(var Dec: tDecoder; Dir: tTrcDir; B: Byte);
var
  T: AnsiString;
begin
  case FT12Feed(Dec.Dirs[Dir].FT, B, 0) of
    fe_Frame:
      begin
        case Dec.Dirs[Dir].FT.Kind of
          tpSACK: T := 'single character ACK ($E5)';
          tpSNAK: T := 'single character NAK ($A2)';
        else
          begin
            if Dec.Dirs[Dir].FT.Kind = tpShortM then
              T := 'fixed frame'
            else
              T := Format('variable frame L=%d', [Dec.Dirs[Dir].FT.L]);
            T := T + Format(' CODE=$%.2x (PRM=%d FCB/ACD=%d FCV/DFC=%d FC=%d)',
              [Dec.Dirs[Dir].FT.Code, Ord(Dec.Dirs[Dir].FT.Code and cBitPrm <> 0), Ord(Dec.Dirs[Dir].FT.Code and cBitFcbAcd <> 0),
               Ord(Dec.Dirs[Dir].FT.Code and cBitFcvDfc <> 0), Dec.Dirs[Dir].FT.Code and cMaskFC]);
            if Dec.Dirs[Dir].FT.Cfg.AddrLen > 0 then
              T := T + Format(' ADDR=%d', [Dec.Dirs[Dir].FT.Addr]);
            T := T + Format(', %d data bytes', [Dec.Dirs[Dir].FT.DataLen]);
            { the user data of a variable frame is an ASDU (IEC 60870-5-101) }
            if (Dec.Dirs[Dir].FT.Kind = tpLongM) and (Dec.Dirs[Dir].FT.DataLen > 0) then
              T := T + ': ' + IecAsduText(Dec.Opt.Asdu, Dec.Dirs[Dir].FT.Data,
                Dec.Dirs[Dir].FT.DataLen)
            else if Dec.Dirs[Dir].FT.DataLen > 0 then
              T := T + ': ' + HexBytes(@Dec.Dirs[Dir].FT.Data[0], Dec.Dirs[Dir].FT.DataLen);
            T := T + ', checksum ok';
          end;
        end;
        Emit(Dec, Dir, 'FT1.2', T, False);
        if Dec.KeepEvents and (Dec.Dirs[Dir].FT.Kind = tpSNAK) then
          Dec.Events[Dec.EventCount - 1].Refused := True;
      end;
    fe_Error:
      begin
        Emit(Dec, Dir, 'FT1.2', Format('ERROR $%.2x %s', [Dec.Dirs[Dir].FT.Err,
          ChResultText(Dec.Dirs[Dir].FT.Err, ChnFT1_2.cName)]), True);
      end;
  end;
end;

{ ------------------------------------------------------------------- ICS }

procedure ICSByte(var Dec: tDecoder; Dir: tTrcDir; B: Byte);
var
  T: AnsiString;
  I: Integer;
begin
  case ICSFeed(Dec.Dirs[Dir].ICS, B) of
    icsFrame:
      begin
        T := Format('DNO=%d SNO=%d OP=%s BLOCK=%d, %d numbers', [Dec.Dirs[Dir].ICS.DNode,
          Dec.Dirs[Dir].ICS.SNode, Dec.Dirs[Dir].ICS.Rec.OpCode, Dec.Dirs[Dir].ICS.Rec.BlockNum, Dec.Dirs[Dir].ICS.Count]);
        if Dec.Dirs[Dir].ICS.Count > 0 then
        begin
          T := T + ':';
          for I := 0 to Dec.Dirs[Dir].ICS.Count - 1 do
            T := T + ' ' + IntToStr(Dec.Dirs[Dir].ICS.Rec.Data[I]);
        end;
        if Dec.Dirs[Dir].ICS.Rec.Text <> '' then
          T := T + ', text ' + Dec.Dirs[Dir].ICS.Rec.Text;
        T := T + Format(', SUM $%.2x ok', [Dec.Dirs[Dir].ICS.RecvSum]);
        Emit(Dec, Dir, 'ICS', T, False);
      end;
    icsError:
      begin
        Emit(Dec, Dir, 'ICS', Format('ERROR $%.2x %s', [Dec.Dirs[Dir].ICS.Error,
          ChResultText(Dec.Dirs[Dir].ICS.Error, ChnICS.cName)]), True);
      end;
  end;
end;

{ ---------------------------------------------------------------- IEC 104 }

procedure Iec104Byte(var Dec: tDecoder; Dir: tTrcDir; B: Byte);
var
  S: ^tDirState;
  T: AnsiString;
  A: tApci104;
  E: ShortString;
begin
  S := @Dec.Dirs[Dir];
  if S^.Hunt104 then
  begin
    if B <> Apci104Start then
      Exit;
    S^.Hunt104 := False;
  end;
  case Apci104Feed(S^.A104, B) of
    fe104Apdu:
      begin
        if Apci104Decode(S^.A104.Buf, S^.A104.Pos, A, E) <> res_Ok then
          Emit(Dec, Dir, 'IEC104', 'ERROR ' + E, True)
        else
        begin
          T := Apci104Text(A);
          if A.Format = af104I then
            T := T + ': ' + IecAsduText(Dec.Opt.Asdu, S^.A104.Buf[6..S^.A104.Pos - 1], S^.A104.Pos - 6);
          Emit(Dec, Dir, 'IEC104', T, False);
        end;
        Apci104FeedReset(S^.A104);
      end;
    fe104Error:
      begin
        if S^.A104.Error = res_ApciStart then
          E := Format('octet $%.2x where an APDU starts', [B])
        else
          E := Format('length octet %d (4..253)', [B]);
        Emit(Dec, Dir, 'IEC104', 'ERROR ' + E, True);
        Apci104FeedReset(S^.A104);
        S^.Hunt104 := True;
      end;
  end;
end;

{ ----------------------------------------------------------------- run }

function InFrame(const Opt: tDecOptions; const S: tDirState): Boolean;
begin
  case Opt.Proto of
    dpDF1: Result := (S.DF1.State <> dsIdle) and not S.DF1.Ignore;
    dpFT12: Result := S.FT.Phase <> 0;        { 0 = hunting for a start }
    dpICS: Result := S.ICS.Phase <> ipHunt;
    dpIec104: Result := S.A104.Pos <> 0;
  else
    Result := False;
  end;
end;

procedure DecodeBegin(var D: tDecoder; const Opt: tDecOptions; Lines: TStrings);
var
  Dir: tTrcDir;
begin
  FillChar(D.Stats, SizeOf(D.Stats), 0);
  FillChar(D.Seen, SizeOf(D.Seen), 0);
  D.Opt := Opt;
  D.Lines := Lines;
  D.KeepEvents := False;
  SetLength(D.Events, 0);
  D.EventCount := 0;
  D.CurTime := 0;
  D.CurLine := 0;
  for Dir := Low(Dir) to High(Dir) do
  begin
    if Dir = trcTx then
      D.Dirs[Dir].Name := 'tx'
    else
      D.Dirs[Dir].Name := 'rx';
    D.Dirs[Dir].Monitor := False;
    case Opt.Proto of
      dpDF1: DF1Init(D.Dirs[Dir], Opt, Dir);
      dpFT12: FTInit(D.Dirs[Dir], Opt);
      dpICS: ICSReset(D.Dirs[Dir].ICS);
      dpIec104:
        begin
          Apci104FeedReset(D.Dirs[Dir].A104);
          D.Dirs[Dir].Hunt104 := False;
        end;
    end;
  end;
end;

procedure DecodeChunk(var D: tDecoder; const F: tTrcFrame);
var
  K: LongInt;
  Head: AnsiString;
begin
  if (D.Opt.FirstLine > 0) and (F.Line < D.Opt.FirstLine) then
    Exit;
  if (D.Opt.LastLine > 0) and (F.Line > D.Opt.LastLine) then
    Exit;
  Inc(D.Stats.Chunks);
  Inc(D.Stats.Bytes, Length(F.Data));
  D.CurTime := F.TimeMs;
  D.CurLine := F.Line;
  if F.Line > 0 then
  begin
    { a pcap's chunks are records, a text capture's are header lines }
    if F.Tag = 'pcap' then
      Head := Format('%s %s %d bytes (record %d)', [TrcTimeText(F.TimeMs), F.DirText, F.Len, F.Line])
    else
      Head := Format('%s %s %d bytes (line %d)', [TrcTimeText(F.TimeMs), F.DirText, F.Len, F.Line]);
  end
  else
    Head := Format('%s %d bytes', [F.DirText, Length(F.Data)]);
  if F.Status <> res_Ok then
  begin
    Inc(D.Stats.BadChunks);
    Head := Head + Format(' - the capture holds %d bytes: %s', [Length(F.Data),
      ChResultText(F.Status, TrcLayer)]);
  end;
  if D.Lines <> nil then
    D.Lines.Add(Head);
  for K := 0 to High(F.Data) do
    case D.Opt.Proto of
      dpDF1: DF1Byte(D, F.Dir, F.Data[K]);
      dpFT12: FTByte(D, F.Dir, F.Data[K]);
      dpICS: ICSByte(D, F.Dir, F.Data[K]);
      dpIec104: Iec104Byte(D, F.Dir, F.Data[K]);
    end;
end;

procedure DecodeEnd(var D: tDecoder; out Stats: tDecStats);
var
  Dir: tTrcDir;
begin
  for Dir := Low(Dir) to High(Dir) do
    if InFrame(D.Opt, D.Dirs[Dir]) then
    begin
      Inc(D.Stats.Incomplete);
      if D.Lines <> nil then
        D.Lines.Add(Format('%s: input ends inside a frame', [D.Dirs[Dir].Name]));
    end;
  if D.Lines <> nil then
    D.Lines.Add(Format('%d chunks, %d bytes: %d frames, %d errors, %d incomplete',
      [D.Stats.Chunks, D.Stats.Bytes, D.Stats.Frames, D.Stats.Errors, D.Stats.Incomplete]));
  SetLength(D.Events, D.EventCount);
  Stats := D.Stats;
end;

function DecodeGuessDF1Check(const Opt: tDecOptions; const Frames: tTrcFrames;
  Count: LongInt; out Why: AnsiString): Boolean;
var
  O: tDecOptions;
  Crc, Bcc: tDecStats;
begin
  O := Opt;
  O.Crc := True;
  DecodeRun(O, Frames, Count, nil, Crc);
  O.Crc := False;
  DecodeRun(O, Frames, Count, nil, Bcc);
  Result := DecodeBetterCheck(Crc, Bcc);
  Why := Format('CRC: %d frames good, %d broken; BCC: %d good, %d broken',
    [Crc.Frames, Crc.Errors, Bcc.Frames, Bcc.Errors]);
end;

function DecodeBetterCheck(const Crc, Bcc: tDecStats): Boolean;
begin
  if Crc.Errors <> Bcc.Errors then
    Result := Crc.Errors < Bcc.Errors
  else
    Result := Crc.Frames >= Bcc.Frames;
end;

procedure DecodeRun(const Opt: tDecOptions; const Frames: tTrcFrames; Count: LongInt;
  Lines: TStrings; out Stats: tDecStats);
var
  D: tDecoder;
  I: LongInt;
begin
  DecodeBegin(D, Opt, Lines);
  for I := 0 to Count - 1 do
    DecodeChunk(D, Frames[I]);
  DecodeEnd(D, Stats);
end;

end.
