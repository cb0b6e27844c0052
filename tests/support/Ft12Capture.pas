{ Ft12Capture - FT 1.2 line captures (text traces of NAM=TRC or chntap
  --trace, tests/data/*.trc) as a list of frames in time order, for the
  replay tests of lib60870 exchanges. Each direction is split into frames
  by the library's own receive automaton set up as a line monitor (both
  PRM values, any DIR, 1-octet addresses, LEN=0); a broken frame raises. }
unit Ft12Capture;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Codec, ChnTrcFormat, TestSupport;

type
  TCapFrame = record
    Tx    : Boolean;       { tx in the trace }
    TimeMs: LongInt;
    Prm   : Boolean;
    Kind  : tMessType;
    FC    : Byte;
    Acd   : Boolean;       { FCB/ACD bit of the control field }
    Data  : TBytes;        { user data octets }
    Hex   : string;        { the frame as on the line }
  end;
  TCapFrames = array of TCapFrame;

{ Split one direction's bytes into frames; Times[i] is the time of byte i
  (may be empty). }
procedure CapSplit(const B: TBytes; Tx: Boolean; const Times: array of LongInt;
  var F: TCapFrames);
{ Both directions of a trace file, merged in time order. }
function CapLoad(const FileName: string): TCapFrames;
{ The hex octets as bytes ('68 0C ...'). }
function CapBytes(const Hex: string): TBytes;

implementation

uses
  TestTempDir;

function CapBytes(const Hex: string): TBytes;
begin
  Result := HexToBytes(Hex);
end;

procedure CapSplit(const B: TBytes; Tx: Boolean; const Times: array of LongInt;
  var F: TCapFrames);
var
  S: tFT12Rx;
  I, N, Len: Integer;
begin
  FillChar(S, SizeOf(S), 0);
  S.Cfg.AddrLen := 1;
  S.Cfg.FixedLen := 0;
  S.Cfg.Balanced := True;
  FT12RxReset(S);
  for I := 0 to High(B) do
    case FT12Feed(S, B[I], 0) of
      fe_Frame:
        begin
          N := Length(F);
          SetLength(F, N + 1);
          F[N].Tx := Tx;
          if Length(Times) > I then
            F[N].TimeMs := Times[I]
          else
            F[N].TimeMs := 0;
          F[N].Prm := FT12FramePrm(S);
          F[N].Kind := S.Kind;
          F[N].FC := S.Code and cMaskFC;
          F[N].Acd := S.Code and $20 <> 0;
          SetLength(F[N].Data, S.DataLen);
          if S.DataLen > 0 then
            Move(S.Data[0], F[N].Data[0], S.DataLen);
          case S.Kind of
            tpSACK, tpSNAK: Len := 1;
            tpShortM: Len := 5;
          else
            Len := S.L + 6;
          end;
          F[N].Hex := BytesToHex(B[I - Len + 1], Len);
        end;
      fe_Error:
        raise Exception.CreateFmt('broken frame in the capture at byte %d', [I]);
    end;
end;

function CapLoad(const FileName: string): TCapFrames;
var
  T: tTrcFrames;
  Tx, Rx: TBytes;
  TxT, RxT: array of LongInt;
  I, J, N: Integer;
  A, B: TCapFrames;
begin
  T := nil;
  if not FileExists(FileName) then
    raise Exception.Create(FileName + ' missing');
  if TrcReadText(ReadFileText(FileName), T) < 1 then
    raise Exception.Create(FileName + ': no chunks');
  Tx := nil; Rx := nil; TxT := nil; RxT := nil;
  for I := 0 to High(T) do
  begin
    if T[I].Status <> res_Ok then
      raise Exception.CreateFmt('%s line %d: chunk not whole', [FileName, T[I].Line]);
    for J := 0 to High(T[I].Data) do
      if T[I].Dir = trcTx then
      begin
        N := Length(Tx);
        SetLength(Tx, N + 1);
        SetLength(TxT, N + 1);
        Tx[N] := T[I].Data[J];
        TxT[N] := T[I].TimeMs;
      end
      else
      begin
        N := Length(Rx);
        SetLength(Rx, N + 1);
        SetLength(RxT, N + 1);
        Rx[N] := T[I].Data[J];
        RxT[N] := T[I].TimeMs;
      end;
  end;
  A := nil;
  B := nil;
  CapSplit(Tx, True, TxT, A);
  CapSplit(Rx, False, RxT, B);
  { one list in time order (ours first at equal times) }
  Result := nil;
  I := 0;
  J := 0;
  while (I < Length(A)) or (J < Length(B)) do
  begin
    N := Length(Result);
    SetLength(Result, N + 1);
    if (J >= Length(B)) or ((I < Length(A)) and (A[I].TimeMs <= B[J].TimeMs)) then
    begin
      Result[N] := A[I];
      Inc(I);
    end
    else
    begin
      Result[N] := B[J];
      Inc(J);
    end;
  end;
end;

end.
