{ df1echo - the echo test of the SofCon ChnDF1 manual, section 7, corrected
  (docs/PROTOCOLS.md section 7): sends CF_Echo with 'Ahoj' to a DF1 slave and checks
  the reply.

    df1echo [OPTION]... PARAMETER-STRING...
    df1echo NAM=DF1 NOD=1 DNO=2 FHD=FULL CRC=ON NAM=COM DEV=/dev/ttyUSB0 BD=19200 PAR=E

  All arguments together form the parameter string (the manual's string
  is the example of the usage; without arguments the program prints its
  usage and opens nothing, so it never transmits on a COM1 nobody named).
  The command line is unit ChnCli's (docs/TOOLS.md). Corrections to the manual's program: a space
  between 'CRC=ON' and 'NAM=COM'; Data[0..3] := 'Ahoj' (the manual assigns
  Data[0] four times); the reply is 8+4 bytes long (replies carry no FNC
  byte; the manual checks 8+5); the waits for CHS_Open and CHS_Connect end
  on an error or after 3 s; the send and the two "while not
  (ChReceiveReady = ...)" loops are DF1Transact of unit ChnDF1Link, which
  adds the link dialogue the manual leaves out (NAK, ENQ, retries, ACK of
  the reply, polling in half duplex) and bounds every wait.

  Exit code: 0 echo ok, 1 open or connect failed or the line was lost,
  2 command-line error, 3 wrong answer, 4 no answer. Every error is
  printed as text. }
program df1echo;

{$MODE OBJFPC}{$H+}

uses
  {$IFDEF UNIX}cthreads,{$ENDIF}
  SysUtils, uString, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnDF1, ChnDF1Link, ChnCli;
  { units register their layer names when they are linked in: ChnLayers
    links every layer, so any of them can be named in the parameter string }

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
  Code: Integer;
  R: tChResult;

var
  Cli: tCli;

procedure Fail(const What: string; R: tChResult);
begin
  if R = res_Ok then
    R := res_Timeout;          { the state never came }
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'df1echo: ', What, ': ', Chn^.ChErrorText)  { token, OS reason }
  else
    WriteLn(StdErr, 'df1echo: ', What, ': ', Chn^.ChResultStr(R));
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
    ChnWaitAny(10);            { the line, at most 10 ms }
  Result := Chn^.ChReady = State;
end;

procedure ShowLine(const Line: string);
begin
  WriteLn('master ', Line);
end;

begin
  CliInit(Cli, 'df1echo', '[OPTION]... PARAMETER-STRING...',
    'The echo test of the SofCon ChnDF1 manual (section 7), corrected: send ' +
    'CF_Echo with ''Ahoj'' to a DF1 station and check the reply, with the link ' +
    'dialogue of ChnDF1Link. All arguments together form the parameter string.');
  CliEpilog(Cli, 'Example (the manual''s string):' + LineEnding + '  df1echo ' +
    DefaultParams + LineEnding);
  CliExit(Cli, 0, 'the echo came back');
  CliExit(Cli, 1, 'the line could not be opened or connected, or was lost');
  CliExit(Cli, 3, 'an answer that is not the echo');
  CliExit(Cli, 4, 'no answer');
  CliParse(Cli);
  Params := CliRest(Cli, 0);
  if Params = '' then
    CliUsageError(Cli, 'no parameter string', '');
  CliCheckParams(Cli, Params, ChnDF1.cName);
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
      WriteLn(StdErr, 'df1echo: no echo: ', ChResultStr(R));
      Code := CliExitOf(R);
      if Code = 3 then
        Code := 1;               { a link fault, not an answer }
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
          WriteLn(StdErr, 'df1echo: the reply is not the echo');
          Code := 3;
        end;
    ChDisConnect;
    ChClose;
  end;
  Dispose(Chn, Done);
  Halt(Code);
end.
