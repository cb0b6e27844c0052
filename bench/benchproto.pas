{ benchproto - the protocol layers as channels: messages per second through
  a whole DF1, FT 1.2 and ICS stack over the in-memory null modem (encode,
  send, the byte feed, the receive loop, ChReceive's copy-out), and the
  parameter parser on a protocol stack's string. Run with "make bench";
  figures are for comparison between builds on one machine. }
program benchproto;

{$MODE OBJFPC}{$H+}

uses
  SysUtils, ChnTypes, ChnVirt, ChnLoop, ChnDF1, ChnFT1_2, ChnICS;

procedure ReportRate(const What: string; Count: LongInt; Ms: QWord);
begin
  if Ms = 0 then
    Ms := 1;
  WriteLn(Format('%-44s %10.0f /s', [What, Count / (Ms / 1000)]));
end;

{ Count messages of Len bytes from Msg, A to B, one at a time: each is
  taken at B before the next is sent. }
procedure PingOneWay(const What, ParamsA, ParamsB: string; const Msg; Len: Word;
  Count: LongInt);
var
  A, B: pChnVirt;
  Rec: array[0..1023] of Byte;
  I: LongInt;
  L: Word;
  T: QWord;
  P: LongInt;
begin
  P := Pos(' ', ParamsA);
  A := ChnCollection^.ChNewInit(Copy(ParamsA, 5, P - 5));
  B := ChnCollection^.ChNewInit(Copy(ParamsA, 5, P - 5));
  A^.ChSetParam(ParamsA);
  B^.ChSetParam(ParamsB);
  A^.ChOpen; A^.ChConnect;
  B^.ChOpen; B^.ChConnect;
  B^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  if (A^.ChResult <> res_Ok) or (B^.ChResult <> res_Ok) then
  begin
    WriteLn(What, ': the stacks did not open');
    Halt(1);
  end;
  T := GetTickCount64;
  for I := 1 to Count do
  begin
    A^.ChSend(@Msg, Len);
    if A^.ChSendResult <> res_Ok then
    begin
      WriteLn(What, ': send failed ', A^.ChSendResult);
      Halt(1);
    end;
    while B^.ChReceiveReady <> CHS_ReceiveReady do
      ;
    B^.ChReceive(L);
    if (B^.ChReceiveResult <> res_Ok) or (L = 0) then
    begin
      WriteLn(What, ': receive failed ', B^.ChReceiveResult);
      Halt(1);
    end;
  end;
  ReportRate(What, Count, GetTickCount64 - T);
  Dispose(A, Done);
  Dispose(B, Done);
end;

procedure BenchDF1;
var
  M: ChnDF1.tSendRecord;
  I: Integer;
begin
  FillChar(M, SizeOf(M), 0);
  M.MessType := ChnDF1.tpDataMess;
  M.CF := ChnDF1.CF_Echo;
  M.Tns := 1;
  for I := 0 to 99 do
    M.Data[I] := I;
  PingOneWay('DF1 channel, 100 data, CRC, messages',
    'NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=BPD END=1 IDL=0',
    'NAM=DF1 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=BPD END=2 IDL=0',
    M, ChnDF1.cSizeHeadSndMsg + 100, 100000);
end;

procedure BenchFT12;
var
  M: ChnFT1_2.tSendRecord;
  I: Integer;
begin
  FillChar(M, SizeOf(M), 0);
  M.MessType := ChnFT1_2.tpLongM;
  M.FC := ChnFT1_2.FCM_UserDataReply;
  M.FCV_DFC := True;
  for I := 1 to 100 do
    M.Data[I] := I;
  PingOneWay('FT1_2 channel, 100 data, messages',
    'NAM=FT1_2 NOD=1 DNO=2 NAM=LOOP PAIR=BPF END=1 IDL=0',
    'NAM=FT1_2 NOD=2 DNO=2 MAS=SLAVE NAM=LOOP PAIR=BPF END=2 IDL=0',
    M, ChnFT1_2.cSizeHeadSndMsg + 100, 100000);
end;

procedure BenchICS;
var
  M: ChnICS.tSendRecord;
  I: Integer;
begin
  FillChar(M, SizeOf(M), 0);
  M.OpCode := ChnICS.OCS_ReadData;
  M.BlockNum := 1;
  for I := 0 to 9 do
    M.Data[I] := I * 1000 - 3000;
  M.Text := '"hello"';
  PingOneWay('ICS channel, 10 numbers + text, messages',
    'NAM=ICS NOD=1 DNO=2 NAM=LOOP PAIR=BPI END=1 IDL=0',
    'NAM=ICS NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=BPI END=2 IDL=0',
    M, 4 + 10 * SizeOf(ChnICS.tData), 100000);
end;

procedure BenchStackParams;
const
  Rounds = 20000;
  S = 'NAM=DF1 NOD=1 DNO=2 MAS=MASTER FHD=FULL CRC=ON LSB=600 DUP=OFF ' +
      'NAM=LOOP PAIR=BPP END=1 LRB=4096 IDL=0';
var
  P: pChnVirt;
  I: Integer;
  T: QWord;
begin
  P := ChnCollection^.ChNewInit('DF1');
  T := GetTickCount64;
  for I := 1 to Rounds do
    P^.ChSetParam(S);
  if P^.ChResult <> res_Ok then
  begin
    WriteLn('ChSetParam failed: ', P^.ChResult, ' ', P^.ChParamError);
    Halt(1);
  end;
  ReportRate('ChSetParam DF1+LOOP (12 tokens, 2 layers)', Rounds, GetTickCount64 - T);
  Dispose(P, Done);
end;

begin
  BenchDF1;
  BenchFT12;
  BenchICS;
  BenchStackParams;
end.
