{ df1echo - the echo test of the SofCon ChnDF1 manual, section 7, corrected
  (SPEC.md section 9): sends CF_Echo with 'Ahoj' to a DF1 slave and checks
  the reply.

    df1echo [parameter string]
    df1echo NAM=DF1 NOD=1 DNO=2 FHD=FULL CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  All arguments together form the parameter string; without any, the
  manual's string is used. Corrections to the manual's program: a space
  between 'CRC=ON' and 'NAM=COM'; Data[0..3] := 'Ahoj' (the manual assigns
  Data[0] four times); the reply is 8+4 bytes long (replies carry no FNC
  byte; the manual checks 8+5); "while not (ChReceiveReady = ...)" with
  parentheses and with a timeout; the link dialogue (NAK, ENQ, retries,
  ACK of the reply, polling in half duplex) that the manual leaves out.

  Exit code: 0 echo ok, 1 setup error (parameters, open, connect),
  2 no answer, 3 wrong answer. Every error is printed as text. }
program df1echo;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnVirt, ChnLoop, ChnCom, ChnDF1;

{$I df1common.inc}

const
  DefaultParams = 'NAM=DF1 LSB=500 NOD=1 DNO=2 FHD=FULL CRC=ON ' +
                  'NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000';

var
  Chn: pChnVirt;
  Params: string;
  I, Code: Integer;

procedure Fail(const What: string; R: tChResult);
begin
  if R = res_Ok then
    R := res_Timeout;          { the state never came }
  Write('df1echo: ', What, ': ', Chn^.ChResultStr(R));
  if Chn^.ChParamError <> '' then
    Write(' (', Chn^.ChParamError, ')');
  WriteLn;
  Dispose(Chn, Done);
  Halt(ex_Setup);
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
    Halt(ex_Setup);
  end;
  Chn := ChnCollection^.ChNewInit(ChnDF1.cName);
  with Chn^ do
  begin
    ChSetParam(Params);
    if ChResult <> res_Ok then
      Fail('parameters "' + Params + '"', ChResult);
    ChOpen;
    if not WaitState(Chn, CHS_Open) then
      Fail('open', ChResult);
    ChConnect;
    if not WaitState(Chn, CHS_Connect) then
      Fail('connect', ChResult);
    WriteLn('df1echo: ', ChGetParam(''));
    Code := EchoExchange(Chn, 'Ahoj', 0, nil);
    if Code = ex_Ok then
      WriteLn('Ok')
    else
      WriteLn('Chyba (error) ', Code);
    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Halt(Code);
end.
