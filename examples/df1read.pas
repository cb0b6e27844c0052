{ df1read - read data table elements of an SLC 5/0x (or tools/df1sim) with
  the Protected Typed Logical Read with three address fields (CMD $0F,
  FNC $A2; manual section 6.3.5) and print them.

    df1read [ADDRESS [COUNT]] parameter string
    df1read N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200

  ADDRESS is N, B, S (16-bit words) or F (floats) with file and element
  number, default N7:0; COUNT elements, default 10. The link dialogue
  (ACK, NAK, ENQ, retries, polling in half duplex) is ChnDF1Link's.
  Exit code: 0 ok, 1 setup error, 2 no answer, 3 error reply (STS <> 0). }
program df1read;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp, ChnTrc, ChnDF1,
  ChnSlc, ChnDF1Link, ChnPcccNames;

var
  Chn: pChnVirt;
  Params, Addr, Arg: string;
  Kind: Char;
  FileNo, Elem, Count, ES, I, Colon: LongInt;
  Req: tSendRecord;
  Rep: tRecRecord;
  RepLen: Word;
  R: tChResult;
  W: Word;
  L: LongWord;
  F: Single;

procedure Fail(const What: string; Code: Integer);
begin
  WriteLn('df1read: ', What);
  if Chn <> nil then
    Dispose(Chn, Done);
  Halt(Code);
end;

begin
  Chn := nil;
  Addr := 'N7:0';
  Count := 10;
  Params := '';
  I := 1;
  while I <= ParamCount do
  begin
    Arg := ParamStr(I);
    if (Params = '') and (Pos('=', Arg) = 0) and (I = 1) then
      Addr := UpperCase(Arg)
    else if (Params = '') and (Pos('=', Arg) = 0) and (I = 2) then
    begin
      if not StrToNum(Arg, 1, 244, Count) then
        Fail('COUNT wants 1..244', 1);
    end
    else
      Params := Trim(Params + ' ' + Arg);
    Inc(I);
  end;
  if Params = '' then
    Fail('no parameter string (e.g. NAM=DF1 NOD=0 DNO=1 NAM=COM DEV=/dev/ttyUSB0)', 1);
  Colon := Pos(':', Addr);
  Kind := #0;
  if Addr <> '' then
    Kind := Addr[1];
  ES := SlcElemSize(Kind);
  FileNo := 0;
  Elem := 0;
  if (Colon < 3) or (ES = 0) or not StrToNum(Copy(Addr, 2, Colon - 2), 0, 255, FileNo) or
     not StrToNum(Copy(Addr, Colon + 1, 255), 0, 65535, Elem) then
    Fail('address "' + Addr + '": N7:0, B3:0, S2:0 or F8:0 expected', 1);
  if Count * ES > 244 then
    Fail('too many elements for one reply (244 bytes)', 1);

  Chn := DF1OpenStack(Params, 3000, Arg);
  if Chn = nil then
    Fail(Arg, 1);
  WriteLn('df1read: ', Chn^.ChGetParam(''));

  { SIZE, FILE, TYPE, ELEMENT, SUB-ELEMENT (one byte each, or $FF + word) }
  FillChar(Req, SizeOf(Req), 0);
  Req.MessType := tpDataMess;
  Req.CF := CF_ProtectRead3Addr;
  Req.Tns := 1;
  I := 0;
  Req.Data[I] := Count * ES; Inc(I);
  { a field of 255 or more is $FF and a word: a lone $FF is the escape }
  if FileNo < 255 then
  begin
    Req.Data[I] := FileNo; Inc(I);
  end
  else
  begin
    Req.Data[I] := $FF; Req.Data[I + 1] := Lo(FileNo); Req.Data[I + 2] := Hi(FileNo); Inc(I, 3);
  end;
  Req.Data[I] := SlcTypeCode(Kind); Inc(I);
  if Elem < 255 then
  begin
    Req.Data[I] := Elem; Inc(I);
  end
  else
  begin
    Req.Data[I] := $FF; Req.Data[I + 1] := Lo(Elem); Req.Data[I + 2] := Hi(Elem); Inc(I, 3);
  end;
  Req.Data[I] := 0; Inc(I);
  WriteLn('df1read: ', DF1Describe(Req, 8 + I));
  RepLen := 0;
  R := DF1Transact(Chn, Req, 8 + I, Rep, RepLen, nil, nil, DF1LinkTimeoutMs);
  if R <> res_Ok then
    Fail('no answer: ' + Chn^.ChResultStr(R), 2);
  WriteLn('df1read: ', DF1Describe(Rep, RepLen));
  if Rep.Sts <> 0 then
  begin
    Arg := PcccStsText(Rep.Sts);
    if (Rep.Sts = sts_ExtSts) and (RepLen > 8) then
      Arg := Arg + ': ' + PcccExtStsText(Rep.Data[0]);
    Fail(Format('error reply STS $%.2x (%s)', [Rep.Sts, Arg]), 3);
  end;
  if RepLen - 8 <> Count * ES then
    Fail(Format('reply has %d data bytes, %d expected', [RepLen - 8, Count * ES]), 3);
  for I := 0 to Count - 1 do
    if Kind = 'F' then
    begin
      L := LongWord(Rep.Data[I * 4]) or (LongWord(Rep.Data[I * 4 + 1]) shl 8) or
           (LongWord(Rep.Data[I * 4 + 2]) shl 16) or (LongWord(Rep.Data[I * 4 + 3]) shl 24);
      Move(L, F, 4);
      WriteLn(Format('%s%d:%d = %g', [Kind, FileNo, Elem + I, F]));
    end
    else
    begin
      W := Rep.Data[I * 2] or (Rep.Data[I * 2 + 1] shl 8);
      if Kind = 'N' then
        WriteLn(Format('%s%d:%d = %d', [Kind, FileNo, Elem + I, SmallInt(W)]))
      else
        WriteLn(Format('%s%d:%d = $%.4x', [Kind, FileNo, Elem + I, W]));
    end;
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
