{ legacy_pccc - the PCCC client from a program written the old way: plain
  "string" and "Integer" variables (their sizes change with the compiler
  mode), a DF1 slave answered by hand with ChReceive/ChSend in the same
  poll loop that steps a client request (the stepped form, for programs
  that keep polling their other lines). tests/run.sh builds it in -Mtp
  -Mfpc (there with long strings) -Mobjfpc -Mdelphi; it exits 1 on any
  wrong value. }
program legacy_pccc;

{$IF not (defined(FPC_TP) or defined(FPC_OBJFPC) or defined(FPC_DELPHI))}
{$H+}
{$IFEND}

uses
  ChnTypes, ChnVirt, ChnLoop, ChnDF1, ChnPccc, ChnPcccClient;

var
  Master, Slave: pChnVirt;
  C: tPcccClient;
  R: tPcccRequest;
  Rec, Ans: tRecRecord;
  Addr, Err: string;
  Len: Word;
  I, Loops: Integer;
  V: array[0..1] of LongInt;
  A: tPcccAddr;
  E: ShortString;

{$I check.inc}

procedure SendNow(Chn: pChnVirt; var M: tSendRecord; L: Word);
var
  K: Integer;
begin
  K := 0;
  while (Chn^.ChSendReady <> CHS_SendReady) and (K < 10000) do
    Inc(K);
  Chn^.ChSend(@M, L);
end;

function Open(const P: string): pChnVirt;
var
  Chn: pChnVirt;
begin
  Chn := ChnCollection^.ChNewInit('DF1');
  Chn^.ChSetParam(P);
  Chn^.ChOpen;
  Chn^.ChConnect;
  Open := Chn;
end;

begin
  Addr := 'n7:0';
  Check(PcccParseAddress(Addr, A, E) = res_Ok, 'parse ' + Addr);
  Check(PcccAddressText(A) = 'N7:0', 'address text');
  Addr := 'N7:0.ACC';
  Check(PcccParseAddress(Addr, A, E) = res_PcccAddress, 'N7:0.ACC refused');
  Slave := Open('NAM=DF1 NOD=1 DNO=0 MAS=SLAVE FHD=FULL NAM=LOOP PAIR=LEGPCCC END=2');
  Master := Open('NAM=DF1 NOD=0 DNO=1 MAS=MASTER FHD=FULL NAM=LOOP PAIR=LEGPCCC END=1');
  Slave^.ChReceiveBuffer(@Rec, SizeOf(Rec));
  PcccClientInit(C, Master);
  Addr := 'N7:0';
  Check(PcccStartRead(R, C, Addr, 2), 'start: ' + R.Err);
  Loops := 0;
  while not PcccStep(R) and (Loops < 30000) do
  begin
    Inc(Loops);
    if Slave^.ChReceiveReady = CHS_ReceiveReady then
    begin
      Len := 0;
      Slave^.ChReceive(Len);
      if (Slave^.ChReceiveResult = res_Ok) and (Rec.MessType = tpDataMess) then
      begin
        FillChar(Ans, SizeOf(Ans), 0);
        Ans.MessType := tpAckNak;
        Ans.FlAck := True;
        SendNow(Slave, Ans, 2);
        { the reply: CMD + $40, the TNS, N7:0 = 300, N7:1 = -2 }
        FillChar(Ans, SizeOf(Ans), 0);
        Ans.MessType := tpDataMess;
        Ans.CF := $4F00;
        Ans.Tns := Rec.Tns;
        Ans.Data[0] := $2C; Ans.Data[1] := $01;
        Ans.Data[2] := $FE; Ans.Data[3] := $FF;
        SendNow(Slave, Ans, 12);
      end;
    end;
  end;
  Check(R.Result = res_Ok, 'read: ' + R.Err);
  Check((R.Ints[0] = 300) and (R.Ints[1] = -2), 'values');
  Err := PcccItemText(R, 1);
  Check(Err = 'N7:1 = -2', 'item text ' + Err);
  { refused before sending: a value out of range, a count past the array }
  Check(PcccWriteInts(C, 'N7:0', [70000]) = res_PcccValue, 'value refused');
  Err := C.Err;
  Check(Pos('70000', Err) > 0, 'text names the value: ' + Err);
  Check(PcccReadInts(C, Addr, 3, V) = res_PcccCount, 'count past the array');
  Dispose(Master, Done);
  Dispose(Slave, Done);
  I := SizeOf(Integer);
  WriteLn('legacy_pccc ok (Integer ', I, ' bytes, string ', SizeOf(string), ' bytes)');
end.
