{ ft12balanced - an IEC 60870-5-101 station in balanced transmission: one
  FT 1.2 channel with MS=OFF, primary and secondary at once, driven by the
  balanced link helper of ChnFT12Link (tFT12Balanced).

  * establishes the link (request status of link, reset of remote link)
    and answers the peer doing the same; test function for link when
    quiet (both ways);
  * prints every ASDU it receives; confirms every activation (COT 6) with
    its mirror as ACT_CON (COT 7); a general interrogation (C_IC_NA_1) is
    then answered with the measured value (COT 20) and terminated
    (ACT_TERM, COT 10);
  * as station A (DIR=1, the controlling side) it starts with a general
    interrogation of common address 1 when the link is first available;
  * sends a measured value, scaled (M_ME_NB_1, IOA 110, common address 1,
    spontaneous) as user data every PERIOD seconds while the link is
    available.

  Usage:  ft12balanced 'parameter string' SECONDS [PERIOD]   (PERIOD 1)
  e.g.    ft12balanced 'NAM=FT1_2 MS=OFF NOD=3 DNO=2 LEN=0 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E' 60
  Against a controlling station that sends DIR = 1 (lib60870's balanced
  master) this station is B: DIR=0 (the default); against a station B,
  give DIR=1. A string without GAP= gets the tools' default (ChnFT12Gap).
  The command line is unit ChnCli's; --help lists the exit codes
  (docs/TOOLS.md). }
program ft12balanced;

{$MODE OBJFPC}{$H-}

uses
  SysUtils, uString, ChnTypes, ChnVirt, ChnWait, ChnLayers, ChnFT1_2, ChnFT12Balanced,
  ChnIec101Asdu, ChnIec101Print, ChnFT12Gap, ChnCli;

var
  Chn: pChnVirt;
  L: tFT12Balanced;
  Value: SmallInt = 0;

procedure Fail(const What: string; R: tChResult);
begin
  if R = Chn^.ChResult then
    WriteLn(StdErr, 'ft12balanced: ', What, ': ', Chn^.ChErrorText)
  else
    WriteLn(StdErr, 'ft12balanced: ', What, ': ', Chn^.ChResultStr(R));
  Dispose(Chn, Done);
  Halt(1);
end;

function Stamp: string;
begin
  Result := FormatDateTime('hh:nn:ss.zzz', Now) + ' ';
end;

{ The ASDU at Buf as one line (ChnIec101Print, lib60870's sizes 2/2/3). }
function AsduText(Buf: PByte; Len: Word): string;
begin
  if Len = 0 then
    Result := 'empty ASDU'
  else
    Result := IecAsduText(IecDefaultParams, PByteArray(Buf)^[0..Len - 1], Len);
end;

procedure Queue(Buf: PByte; Len: Word);
begin
  if FT12BalancedSend(L, Buf, Len, True) <> res_Ok then
    WriteLn(Stamp, 'queue full: ', AsduText(Buf, Len), ' dropped')
  else
    WriteLn(Stamp, '-> ', AsduText(Buf, Len));
end;

{ A scaled measured value (IOA 110, CA 1) into Out; its length. }
function Measured(Cot: Byte; var Out: array of Byte): Word;
var
  O: tIecObject;
  E: ShortString;
begin
  O := IecObject(110);
  O.Int := Value;
  IecEncodeOne(IecDefaultParams, M_ME_NB_1, Cot, 1, O, Out, Result, E);
end;

{ The secondary's user data (FC 3 / FC 4): one ASDU. True = ACK. }
function OnUserData(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
var
  Out: array[0..MaxDataLen - 1] of Byte;
  N: Word;
  H: tIecAsdu;
  E: ShortString;
begin
  WriteLn(Stamp, '<- ', AsduText(Buf, Len));
  { room for the answers first, else NACK: the peer sends it again }
  Result := L.QCount + 3 <= FT12BalQueueLen;
  if not Result or (Len = 0) or (Len > SizeOf(Out))
    or (IecDecodeHeader(IecDefaultParams, PByteArray(Buf)^[0..Len - 1], Len, H, E) <> res_Ok)
    or (H.Cot <> Cot_Activation) then
    Exit;
  Move(Buf^, Out, Len);
  IecSetCot(Out, Len, Cot_ActCon, False);
  Queue(@Out, Len);
  if H.Ti = C_IC_NA_1 then
  begin
    N := Measured(Cot_Interrogated, Out);
    Queue(@Out, N);
    Move(Buf^, Out, Len);
    IecSetCot(Out, Len, Cot_ActTerm, False);
    Queue(@Out, Len);
  end;
end;

var
  Cli: tCli;
  Params: tParamStr;
  Seconds, Period: LongInt;
  EndTime, NextValue: QWord;
  Shown: tFT12BalState;
  Asked: Boolean = False;
  Out: array[0..15] of Byte;
  N: Word;
  Obj: tIecObject;
  Err: ShortString;
begin
  CliInit(Cli, 'ft12balanced', '[OPTION]... PARAMETER-STRING SECONDS [PERIOD]',
    'An IEC 60870-5-101 station in balanced transmission (MS=OFF) for SECONDS: ' +
    'establishes the link, answers interrogations and activations, and sends a ' +
    'measured value every PERIOD seconds (default 1). As station A (DIR=1) it ' +
    'starts with a general interrogation.');
  CliEpilog(Cli, 'Example:' + LineEnding +
    '  ft12balanced ''NAM=FT1_2 MS=OFF NOD=3 DNO=2 LEN=0 NAM=COM DEV=/dev/ttyUSB0 BD=9600 PAR=E'' 60' +
    LineEnding);
  CliExit(Cli, 0, 'the time is over');
  CliExit(Cli, 1, 'the line could not be opened, or was lost');
  CliParse(Cli);
  if (CliArgCount(Cli) < 2) or (CliArgCount(Cli) > 3) then
    CliUsageError(Cli, 'PARAMETER-STRING SECONDS [PERIOD] wanted', CliRest(Cli, 0));
  Params := Cli.Args[0];
  Seconds := 0;
  Period := 1;
  if not StrToNum(Cli.Args[1], 1, MaxLongInt, Seconds) then
    CliUsageError(Cli, 'SECONDS wants a positive number', Cli.Args[1]);
  if (CliArgCount(Cli) = 3) and not StrToNum(Cli.Args[2], 1, MaxLongInt, Period) then
    CliUsageError(Cli, 'PERIOD wants a positive number of seconds', Cli.Args[2]);
  CliCheckParams(Cli, Cli.Args[0], ChnFT1_2.cName);
  Chn := ChnCollection^.ChNewInit(ChnFT1_2.cName);
  Chn^.ChSetParam(Params);
  if Chn^.ChResult <> res_Ok then Fail('ChSetParam', Chn^.ChResult);
  FT12SetDefaultGap(Chn, Params);
  Chn^.ChOpen;
  if Chn^.ChResult <> res_Ok then Fail('ChOpen', Chn^.ChResult);
  Chn^.ChConnect;
  if Chn^.ChResult <> res_Ok then Fail('ChConnect', Chn^.ChResult);
  if FT12BalancedInit(L, Chn) <> res_Ok then
    Fail('not a balanced FT 1.2 channel (MS=OFF)', res_BadParam);
  L.OnUserData := @OnUserData;
  WriteLn('ft12balanced: ', Chn^.ChGetParam(''));
  Shown := L.State;
  WriteLn(Stamp, 'link ', FT12BalStateName(Shown));
  EndTime := ChMsTick + QWord(Seconds) * 1000;
  NextValue := ChMsTick + QWord(Period) * 1000;
  while ChMsTick < EndTime do
  begin
    if Chn^.ChResult <> res_Ok then Fail('line', Chn^.ChResult);
    if not FT12BalancedStep(L) then
      ChnWaitAny(20);   { the line or the link's timers, at most 20 ms }
    if L.State <> Shown then
    begin
      Shown := L.State;
      WriteLn(Stamp, 'link ', FT12BalStateName(Shown));
      if (Shown = bsAvailable) and pChnFT1_2(Chn)^.ChFT12Config.Dir and not Asked then
      begin
        Asked := True;
        Obj := IecObject(0);
        Obj.Int := Qoi_Station;
        IecEncodeOne(IecDefaultParams, C_IC_NA_1, Cot_Activation, 1, Obj, Out, N, Err);
        Queue(@Out, N);
      end;
    end;
    if ChMsTick >= NextValue then
    begin
      NextValue := NextValue + QWord(Period) * 1000;
      if L.State = bsAvailable then
      begin
        Inc(Value);
        N := Measured(Cot_Spontaneous, Out);
        Queue(@Out, N);
      end;
    end;
  end;
  WriteLn(Format('ft12balanced: %d frames, %d user data taken, %d confirmed, ' +
    '%d test functions, %d repetitions sent, %d answered from memory, ' +
    '%d link losses, %d broken, %d wrong DIR, %d unexpected answers',
    [L.Frames, L.Executed, L.Confirmed, L.Tests, L.Retransmits, L.Repeats,
     L.LinkLost, L.Broken, L.BadDir, L.Unexpected]));
  Chn^.ChDisConnect;
  Chn^.ChClose;
  Dispose(Chn, Done);
end.
