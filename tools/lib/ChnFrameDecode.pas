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
  Classes, ChnTypes, ChnTrcFormat, ChnDF1Codec, ChnFT12Codec, ChnICSCodec;

type
  tDecProto = (dpDF1, dpFT12, dpICS);

  tDecOptions = record
    Proto    : tDecProto;
    Crc      : Boolean;   { DF1: CRC-16, else BCC }
    Half     : Boolean;   { DF1: half duplex }
    MasterDir: tTrcDir;   { DF1 half duplex: direction of the master's bytes }
    AddrLen  : Byte;      { FT1.2: link address octets 0..2 }
    FixedLen : Byte;      { FT1.2: data octets of a fixed frame }
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

procedure DecodeDefaults(var Opt: tDecOptions);

{ Hex text ('10 02 0300', '1002,0E0D', '0x10 0x02'): pairs of hex digits,
  separated by anything that is not a hex digit; a '0x' prefix is skipped.
  False (with Err) for an odd run of digits. }
function DecodeHexText(const Text: AnsiString; var Data: tTrcBytes; out Err: AnsiString): Boolean;

{ Raw bytes as one received chunk (line 0). }
procedure DecodeBytesAsChunk(const Data: tTrcBytes; var Frames: tTrcFrames);

{ Decode Frames[0..Count-1]; lines go to Lines, counts to Stats. }
procedure DecodeRun(const Opt: tDecOptions; const Frames: tTrcFrames; Count: LongInt;
  Lines: TStrings; out Stats: tDecStats);

implementation

uses
  SysUtils, uString, ChnDF1, ChnFT1_2, ChnICS, ChnPcccNames;

type
  { commands seen, by TNS: names the replies (which carry no FNC) }
  tTnsTable = array[Byte] of record
    Used: Boolean;
    Tns : Word;
    Cmd, Fnc: Byte;
  end;

  tDirState = record
    Name : AnsiString;
    DF1  : tDF1Decoder;
    FT   : tFT12Rx;
    ICS  : tICSState;
    Monitor: Boolean;    { DF1 half duplex: decode master frames for every station }
  end;

procedure DecodeDefaults(var Opt: tDecOptions);
begin
  FillChar(Opt, SizeOf(Opt), 0);
  Opt.Proto := dpDF1;
  Opt.Crc := True;
  Opt.MasterDir := trcTx;
  Opt.AddrLen := 1;
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

procedure DF1Byte(var S: tDirState; B: Byte; Lines: TStrings; var Stats: tDecStats;
  var Seen: tTnsTable);
var
  Before: Byte;
  Ev: tDF1Event;
begin
  Before := S.DF1.State;
  { a monitor hears every station: take the poll's / frame's STN as ours }
  if S.Monitor and (Before = dsPollBcc) then
    S.DF1.Cfg.Node := S.DF1.Stn;
  Ev := DF1Feed(S.DF1, B);
  if S.Monitor and (Before in [dsStn, dsStnDle]) and (S.DF1.State = dsSohDle) then
    S.DF1.Ignore := False;
  case Ev of
    dfMessage:
      begin
        Inc(Stats.Frames);
        Lines.Add('  ' + S.Name + ' DF1 ' + DF1Message(S.DF1, Seen));
      end;
    dfError:
      begin
        Inc(Stats.Errors);
        Lines.Add('  ' + S.Name + ' DF1 ' + DF1Error(S.DF1, Before = dsSum));
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

procedure FTByte(var S: tDirState; B: Byte; Lines: TStrings; var Stats: tDecStats);
var
  T: AnsiString;
begin
  case FT12Feed(S.FT, B, 0) of
    fe_Frame:
      begin
        Inc(Stats.Frames);
        case S.FT.Kind of
          tpSACK: T := 'single character ACK ($E5)';
          tpSNAK: T := 'single character NAK ($A2)';
        else
          begin
            if S.FT.Kind = tpShortM then
              T := 'fixed frame'
            else
              T := Format('variable frame L=%d', [S.FT.L]);
            T := T + Format(' CODE=$%.2x (PRM=%d FCB/ACD=%d FCV/DFC=%d FC=%d)',
              [S.FT.Code, Ord(S.FT.Code and cBitPrm <> 0), Ord(S.FT.Code and cBitFcbAcd <> 0),
               Ord(S.FT.Code and cBitFcvDfc <> 0), S.FT.Code and cMaskFC]);
            if S.FT.Cfg.AddrLen > 0 then
              T := T + Format(' ADDR=%d', [S.FT.Addr]);
            T := T + Format(', %d data bytes', [S.FT.DataLen]);
            if S.FT.DataLen > 0 then
              T := T + ': ' + HexBytes(@S.FT.Data[0], S.FT.DataLen);
            T := T + ', checksum ok';
          end;
        end;
        Lines.Add('  ' + S.Name + ' FT1.2 ' + T);
      end;
    fe_Error:
      begin
        Inc(Stats.Errors);
        Lines.Add(Format('  %s FT1.2 ERROR $%.2x %s', [S.Name, S.FT.Err,
          ChResultText(S.FT.Err, ChnFT1_2.cName)]));
      end;
  end;
end;

{ ------------------------------------------------------------------- ICS }

procedure ICSByte(var S: tDirState; B: Byte; Lines: TStrings; var Stats: tDecStats);
var
  T: AnsiString;
  I: Integer;
begin
  case ICSFeed(S.ICS, B) of
    icsFrame:
      begin
        Inc(Stats.Frames);
        T := Format('DNO=%d SNO=%d OP=%s BLOCK=%d, %d numbers', [S.ICS.DNode,
          S.ICS.SNode, S.ICS.Rec.OpCode, S.ICS.Rec.BlockNum, S.ICS.Count]);
        if S.ICS.Count > 0 then
        begin
          T := T + ':';
          for I := 0 to S.ICS.Count - 1 do
            T := T + ' ' + IntToStr(S.ICS.Rec.Data[I]);
        end;
        if S.ICS.Rec.Text <> '' then
          T := T + ', text ' + S.ICS.Rec.Text;
        T := T + Format(', SUM $%.2x ok', [S.ICS.RecvSum]);
        Lines.Add('  ' + S.Name + ' ICS ' + T);
      end;
    icsError:
      begin
        Inc(Stats.Errors);
        Lines.Add(Format('  %s ICS ERROR $%.2x %s', [S.Name, S.ICS.Error,
          ChResultText(S.ICS.Error, ChnICS.cName)]));
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
  else
    Result := False;
  end;
end;

procedure DecodeRun(const Opt: tDecOptions; const Frames: tTrcFrames; Count: LongInt;
  Lines: TStrings; out Stats: tDecStats);
var
  Dirs: array[tTrcDir] of tDirState;
  Seen: tTnsTable;
  D: tTrcDir;
  I, K: LongInt;
  Head: AnsiString;
begin
  FillChar(Stats, SizeOf(Stats), 0);
  FillChar(Seen, SizeOf(Seen), 0);
  for D := Low(D) to High(D) do
  begin
    if D = trcTx then
      Dirs[D].Name := 'tx'
    else
      Dirs[D].Name := 'rx';
    Dirs[D].Monitor := False;
    case Opt.Proto of
      dpDF1: DF1Init(Dirs[D], Opt, D);
      dpFT12: FTInit(Dirs[D], Opt);
      dpICS: ICSReset(Dirs[D].ICS);
    end;
  end;
  for I := 0 to Count - 1 do
    with Frames[I] do
    begin
      if (Opt.FirstLine > 0) and (Line < Opt.FirstLine) then
        Continue;
      if (Opt.LastLine > 0) and (Line > Opt.LastLine) then
        Continue;
      Inc(Stats.Chunks);
      Inc(Stats.Bytes, Length(Data));
      if Line > 0 then
        Head := Format('%s %s %d bytes (line %d)', [TrcTimeText(TimeMs), DirText, Len, Line])
      else
        Head := Format('%s %d bytes', [DirText, Length(Data)]);
      if Status <> res_Ok then
      begin
        Inc(Stats.BadChunks);
        Head := Head + Format(' - the capture holds %d bytes: %s', [Length(Data),
          ChResultText(Status, 'TRC')]);
      end;
      Lines.Add(Head);
      for K := 0 to High(Data) do
        case Opt.Proto of
          dpDF1: DF1Byte(Dirs[Dir], Data[K], Lines, Stats, Seen);
          dpFT12: FTByte(Dirs[Dir], Data[K], Lines, Stats);
          dpICS: ICSByte(Dirs[Dir], Data[K], Lines, Stats);
        end;
    end;
  for D := Low(D) to High(D) do
    if InFrame(Opt, Dirs[D]) then
    begin
      Inc(Stats.Incomplete);
      Lines.Add(Format('%s: input ends inside a frame', [Dirs[D].Name]));
    end;
  Lines.Add(Format('%d chunks, %d bytes: %d frames, %d errors, %d incomplete',
    [Stats.Chunks, Stats.Bytes, Stats.Frames, Stats.Errors, Stats.Incomplete]));
end;

end.
