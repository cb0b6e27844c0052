{ Iec104Capture - IEC 104 captures (text traces of NAM=TRC between
  NAM=IEC104 and NAM=TCP, tests/data/iec104-*.trc) as the APDUs of both
  directions in the order the trace has them, split by the library's APCI
  codec; a broken APDU raises. For the replay tests of lib60870 exchanges. }
unit Iec104Capture;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, ChnTypes, ChnIec104Codec, ChnTrcFormat, TestSupport;

type
  TApdu104 = record
    Tx   : Boolean;       { tx in the trace: the side that wrote it }
    Apci : tApci104;
    Bytes: TBytes;
  end;
  TApdus104 = array of TApdu104;

  { One direction of a live stream cut into APDUs as they come. }
  TApduSplitter = record
    Feed: tApci104Feed;
  end;

function Cap104Load(const FileName: string): TApdus104;
{ Feed Len octets of one direction; complete APDUs are appended to A. }
procedure Cap104Split(var S: TApduSplitter; const Buf: array of Byte; Len: Integer; Tx: Boolean;
  var A: TApdus104);
{ What a replay compares of an APDU: the format, a U frame's function, an
  I frame's ASDU identifier (type, VSQ, COT with P/N and test bits,
  originator, CA) and first IOA - not the sequence numbers (they follow
  the timing of acknowledgements) nor values that carry the clock. }
function Cap104Key(const A: TApdu104): string;

implementation

uses
  TestTempDir;

procedure Cap104Split(var S: TApduSplitter; const Buf: array of Byte; Len: Integer; Tx: Boolean;
  var A: TApdus104);
var
  I, N: Integer;
  E: ShortString;
begin
  for I := 0 to Len - 1 do
    case Apci104Feed(S.Feed, Buf[I]) of
      fe104Error:
        raise Exception.CreateFmt('broken APDU at octet %d (%s)', [I, IntToHex(Buf[I], 2)]);
      fe104Apdu:
        begin
          N := Length(A);
          SetLength(A, N + 1);
          A[N].Tx := Tx;
          if Apci104Decode(S.Feed.Buf, S.Feed.Pos, A[N].Apci, E) <> res_Ok then
            raise Exception.Create('APDU: ' + E);
          SetLength(A[N].Bytes, S.Feed.Pos);
          Move(S.Feed.Buf[0], A[N].Bytes[0], S.Feed.Pos);
          Apci104FeedReset(S.Feed);
        end;
    end;
end;

function Cap104Load(const FileName: string): TApdus104;
var
  T: tTrcFrames;
  SplitTx, SplitRx: TApduSplitter;
  I: Integer;
begin
  T := nil;
  Result := nil;
  if not FileExists(FileName) then
    raise Exception.Create(FileName + ' missing');
  if TrcReadText(ReadFileText(FileName), T) < 1 then
    raise Exception.Create(FileName + ': no chunks');
  Apci104FeedReset(SplitTx.Feed);
  Apci104FeedReset(SplitRx.Feed);
  for I := 0 to High(T) do
  begin
    if T[I].Status <> res_Ok then
      raise Exception.CreateFmt('%s line %d: chunk not whole', [FileName, T[I].Line]);
    if T[I].Dir = trcTx then
      Cap104Split(SplitTx, T[I].Data, Length(T[I].Data), True, Result)
    else
      Cap104Split(SplitRx, T[I].Data, Length(T[I].Data), False, Result);
  end;
end;

function Cap104Key(const A: TApdu104): string;
var
  N: Integer;
begin
  case A.Apci.Format of
    af104S: Result := 'S';
    af104U: Result := Apci104Text(A.Apci);
  else
    begin
      N := Length(A.Bytes) - 6;
      if N > 9 then
        N := 9;                      { TI VSQ COT(2) CA(2) IOA(3) }
      Result := 'I ' + BytesToHex(A.Bytes[6], N);
    end;
  end;
end;

end.
