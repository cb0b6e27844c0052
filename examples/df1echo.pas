{ df1echo - the echo test of the SofCon ChnDF1 manual, section 7, corrected
  (docs/PROTOCOLS.md section 7): sends CF_Echo with 'Ahoj' to a DF1 slave and checks
  the reply.

    df1echo [parameter string]
    df1echo NAM=DF1 NOD=1 DNO=2 FHD=FULL CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  All arguments together form the parameter string; without any, the
  manual's string is used. Corrections to the manual's program: a space
  between 'CRC=ON' and 'NAM=COM'; Data[0..3] := 'Ahoj' (the manual assigns
  Data[0] four times); the reply is 8+4 bytes long (replies carry no FNC
  byte; the manual checks 8+5); the waits for CHS_Open and CHS_Connect end
  on an error or after 3 s; the send and the two "while not
  (ChReceiveReady = ...)" loops are DF1Transact of unit ChnDF1Link, which
  adds the link dialogue the manual leaves out (NAK, ENQ, retries, ACK of
  the reply, polling in half duplex) and bounds every wait.

  Exit code: 0 echo ok, 1 setup error (parameters, open, connect),
  2 no answer, 3 wrong answer. Every error is printed as text. }
program df1echo;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnTcp, ChnTrc, ChnDF1,
  ChnDF1Link;
  { units register their layer names when they are linked in: LOOP, COM,
    TRC and DF1 can be named in the parameter string }

const
  DefaultParams = 'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON ' +
                  'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';
  Text = 'Ahoj';

var
  Chn: pChnVirt;
  SMess: tSendRecord;
  RMess: tRecRecord;
  LSMess, LRMess: Word;
  Params: string;
  I, Code: Integer;
  R: tChResult;

procedure Fail(const What: string; R: tChResult);
begin
  if R = res_Ok then
    R := res_Timeout;          { the state never came }
  Write('df1echo: ', What, ': ', Chn^.ChResultStr(R));
  if Chn^.ChParamError <> '' then
    Write(' (', Chn^.ChParamError, ')');
  WriteLn;
  Dispose(Chn, Done);
  Halt(1);
end;

{ the manual's "repeat until ChReady = ...", bounded }
function WaitFor(State: tChState): Boolean;
var
  Deadline: QWord;
begin
  Deadline := ChMsTick + 3000;
  while (Chn^.ChReady <> State) and (Chn^.ChResult = res_Ok) and (ChMsTick < Deadline) do
    Sleep(1);
  Result := Chn^.ChReady = State;
end;

procedure ShowLine(const Line: string);
begin
  WriteLn('master ', Line);
end;

begin
  Params := '';
  for I := 1 to ParamCount do
    Params := Trim(Params + ' ' + ParamStr(I));
  if Params = '' then
    Params := DefaultParams;
  if Length(Params) > High(tParamStr) then
  begin
    WriteLn('df1echo: parameter string longer than ', High(tParamStr), ' characters');
    Halt(1);
  end;
  Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  with Chn^ do
  begin
    ChSetParam(Params);
    if ChResult <> res_Ok then
      Fail('parameters "' + Params + '"', ChResult);
    ChOpen;
    if not WaitFor(CHS_Open) then
      Fail('open', ChResult);
    ChConnect;
    if not WaitFor(CHS_Connect) then
      Fail('connect', ChResult);
    WriteLn('df1echo: ', ChGetParam(''));
    FillChar(SMess, SizeOf(SMess), 0);
    with SMess do
    begin
      MessType := tpDataMess;
      CF := CF_Echo;
      Sts := 0;
      Tns := 0;
      Move(Text[1], Data[0], Length(Text));    { Data[0..3] := 'Ahoj' }
      LSMess := 8 + Length(Text);
    end;
    LRMess := 0;
    R := DF1Transact(Chn, SMess, LSMess, RMess, LRMess, nil, nil, DF1LinkTimeoutMs,
      @ShowLine, True);
    if R <> res_Ok then
    begin
      WriteLn('Chyba (error): ', ChResultStr(R));
      Code := 2;
    end
    else
      with RMess do
        if (MessType = tpDataMess) and (CF = CF_Echo or MskCF_Reply) and
           (Tns = 0) and (Sts = 0) and (LRMess = 8 + Length(Text)) and
           (CompareByte(Data, SMess.Data, Length(Text)) = 0) then
        begin
          WriteLn('Ok');
          Code := 0;
        end
        else
        begin
          WriteLn('Chyba (error): the reply is not the echo');
          Code := 3;
        end;
    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Halt(Code);
end.
