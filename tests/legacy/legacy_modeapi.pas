{ legacy_modeapi - every public routine of uString, ChnTypes and ChnVirt
  called with variables declared the plain legacy way ("Integer",
  "string"), whose sizes change with the compiler mode. tests/run.sh builds
  it in -Mtp -Mfpc -Mobjfpc -Mdelphi; in -Mfpc it also switches to long strings (H+), so
  the four runs cover every pairing a caller can have: SmallInt with
  ShortString (tp), SmallInt with AnsiString (fpc + H+), LongInt with
  ShortString (objfpc), LongInt with AnsiString (delphi). It must compile
  in each and exits 1 on any wrong value. }
program legacy_modeapi;

{$IF not (defined(FPC_TP) or defined(FPC_OBJFPC) or defined(FPC_DELPHI))}
{$H+}
{$IFEND}

uses
  uString,
  ChnTypes,
  ChnVirt,
  ChnLoop;

var
  S, T, K, V: string;
  I, J, N: Integer;
  L: LongInt;
  Q: QWord;
  W: Word;
  B: Byte;
  F: Boolean;
  Cmd: tCmd;
  Buf: array[0..7] of Byte;
  P: Pointer;
  Chn, Peer: pChnVirt;
  Mgr: pAddChnVirt;
  SNode, DNode: tNode;

{$I check.inc}

begin
  { uString }
  S := 'mixed Case 09';
  Check(UpStr(S) = 'MIXED CASE 09', 'UpStr');
  S := '  NAM=DF1'#9'CRC=ON  ';
  I := 1;
  Check(NextToken(S, I, T) and (T = 'NAM=DF1') and (I = 10), 'NextToken first');
  Check(NextTokenAt(S, I, T, J) and (T = 'CRC=ON') and (J = 11) and (I = 17),
    'NextTokenAt second');
  Check(not NextToken(S, I, T) and (T = ''), 'NextToken at the end');
  Check(SplitKeyValue('crc=On', K, V) and (K = 'CRC') and (V = 'On'), 'SplitKeyValue');
  Check(not SplitKeyValue('CRC=ONNAM=COM', K, V), 'SplitKeyValue fused');
  Check(not SplitKeyValue('=1', K, V), 'SplitKeyValue empty key');
  N := 7;
  Check(StrToNum('$7FFF', 0, 40000, N) and (N = 32767), 'StrToNum Integer');
  Check(not StrToNum('40000', 0, 40000, N) and (N = 32767) or
    (SizeOf(Integer) = 4) and (N = 40000), 'StrToNum beyond a 16-bit Integer');
  N := 5;
  Check(not StrToNum('1x', 0, 9, N) and (N = 5), 'StrToNum refuses 1x, N unchanged');
  L := 0;
  Check(StrToNum('-100000', -200000, 0, L) and (L = -100000), 'StrToNum LongInt');
  I := ChoiceIndex('half', 'FULL|HALF');
  Check(I = 1, 'ChoiceIndex');
  Check(ChoiceIndex('X', 'FULL|HALF') = -1, 'ChoiceIndex none');
  I := 2;
  T := ChoiceWord('N|E|O', I);
  Check(T = 'O', 'ChoiceWord');
  I := HexDigit('b');
  Check((I = 11) and (HexDigit('g') = -1), 'HexDigit');
  Buf[0] := $10; Buf[1] := $02; Buf[2] := $FF;
  I := 3;
  T := HexBytes(@Buf, I);
  Check(T = '10 02 FF', 'HexBytes');
  I := -12;
  T := NumStr(I);
  Check(T = '-12', 'NumStr');

  { ChnTypes }
  T := ChResultText(res_Ok);
  Check(T = 'ok', 'ChResultText');
  S := 'MODEAPI';
  T := 'mode test text';
  I := res_Proto + 9;
  ChRegisterResultText(S, I, T);
  V := ChResultText(I, S);
  Check(V = 'MODEAPI: mode test text', 'ChRegisterResultText/ChResultText(Layer)');
  Buf[0] := 1; Buf[1] := 2; Buf[2] := 3;
  I := 3;
  Check(Bcc8Block(Buf, I) = Bcc8Final(Bcc8Add(Bcc8Add(Bcc8Add(0, 1), 2), 3)), 'Bcc8');
  Check(Bcc8Block(Buf, I) = $FA, 'Bcc8 value');
  Check(Crc16Block(Buf, I, 0) = Crc16Add(Crc16Add(Crc16Add(0, 1), 2), 3), 'Crc16');
  Check(Sum8Block(Buf, I) = Sum8Add(Sum8Add(Sum8Add(0, 1), 2), 3), 'Sum8');
  Check(Sum8Block(Buf, I) = 6, 'Sum8 value');
  Check(Xor8Block(Buf, I) = Xor8Add(Xor8Add(Xor8Add(0, 1), 2), 3), 'Xor8');
  Check(Xor8Block(Buf, I) = 0, 'Xor8 value');

  { ChnVirt: unit-level helpers }
  S := 'loop';
  W := ChNumName(S);
  Check(W = ChNumName('LOOP'), 'ChNumName');
  Q := ChMsTick;
  Check(ChMsTick >= Q, 'ChMsTick');
  S := 'PAR=e';
  K := ParamKey(S);
  V := ParamValue(S);
  Check((K = 'PAR') and (V = 'e'), 'ParamKey/ParamValue');
  N := 0;
  Check((ParamNum('BD=9600', 50, 32767, N) = res_Ok) and (N = 9600), 'ParamNum Integer');
  Check(ParamNum('BD=x', 50, 32767, N) = res_BadParam, 'ParamNum bad');
  L := 0;
  Check((ParamNum('BD=115200', 50, 4000000, L) = res_Ok) and (L = 115200), 'ParamNum LongInt');
  I := -1;
  T := 'N|E|O|M|S';
  Check((ParamChoice(S, T, I) = res_Ok) and (I = 1), 'ParamChoice');
  Check(ParamChoice('PAR=Q', T, I) = res_BadParam, 'ParamChoice bad');
  T := 'LSB';
  I := 500;
  V := ParamText(T, I);
  Check(V = ' LSB=500', 'ParamText');
  F := False;
  Check((ParamFlag('CRC=ON', OnOffChoice, cmd_Check, F) = res_Ok) and not F, 'ParamFlag check');
  Check((ParamFlag('CRC=ON', OnOffChoice, cmd_Set, F) = res_Ok) and F, 'ParamFlag set');
  N := 1;
  Check((ParamSetNum('IDL=20', 0, 1000, cmd_Set, N) = res_Ok) and (N = 20), 'ParamSetNum Integer');
  L := 1;
  Check((ParamSetNum('IDL=20', 0, 1000, cmd_Check, L) = res_Ok) and (L = 1), 'ParamSetNum check');
  V := FlagText('CRC', OnOffChoice, True);
  Check(V = ' CRC=ON', 'FlagText');
  V := '';
  Check(ParamLengthCheck(255, V) = res_Ok, 'ParamLengthCheck 255');
  Check((ParamLengthCheck(300, V) = res_ParamTooLong) and
    (V = '300 characters, the limit is 255'), 'ParamLengthCheck 300');

  { ChnVirt: registry and the methods that take or return text and numbers }
  S := ChnLoop.cName;
  Mgr := ChnCollection^.Search(S);
  Check((Mgr <> nil) and (Mgr^.Name = 'LOOP'), 'Search');
  I := ChnCollection^.Count;
  Check(I > 0, 'Count');
  Chn := ChnCollection^.ChNewInit(S);
  Peer := Mgr^.ChInit;
  Check((Chn <> nil) and (Peer <> nil), 'ChNewInit/ChInit');
  S := 'NAM=LOOP PAIR=MODEAPI END=1 LRB=9600';
  Chn^.ChSetParam(S);
  Check(Chn^.ChResult = res_Ok, 'ChSetParam');
  Peer^.ChSetParam('NAM=LOOP PAIR=MODEAPI END=2');
  T := Chn^.ChGetParam('LRB');
  Check(T = 'LRB=9600', 'ChGetParam(LRB) gave ' + T);
  S := 'NAM=LOOP LRB=96OO';
  Chn^.ChSetParam(S);
  T := Chn^.ChParamError;
  Check((Chn^.ChResult = res_BadParam) and (T = 'LRB=96OO'), 'ChParamError');
  T := Chn^.ChResultStr(res_BadParam);
  Check(T = ChResultText(res_BadParam), 'ChResultStr');
  Cmd := cmd_Check;
  Check(Chn^.ChSetOneParam('LRB=19200', Cmd) = res_Ok, 'ChSetOneParam');
  T := Chn^.ChOwnParams;
  Check(Pos('LRB=9600', T) > 0, 'ChOwnParams');
  Chn^.ChOpen;
  Peer^.ChOpen;
  Chn^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Peer^.ChReceiveBuffer(@Buf, SizeOf(Buf));
  Chn^.ChConnect;
  Peer^.ChConnect;
  Check(Peer^.ChReady = CHS_Connect, 'connected');
  Buf[0] := $41;
  I := 1;
  Check(ChSendWhenFree(Chn, @Buf, I, 1000) = res_Ok, 'ChSendWhenFree');
  L := 0;
  while (Peer^.ChReceiveReady <> CHS_ReceiveReady) and (L < 1000000) do
    Inc(L);
  W := 0;
  Peer^.ChReceive(W);
  Check((W = 1) and (Buf[0] = $41), 'received');
  Peer^.ChGetNode(SNode, DNode);
  B := 0;
  Check(not Peer^.ChLowGetByte(B), 'ChLowGetByte on a physical layer');
  W := 0;
  Check(Peer^.ChReceiveAllowed(W), 'ChReceiveAllowed');
  Dispose(Chn, Done);
  Dispose(Peer, Done);
  New(Chn, Init);
  S := 'Mine';
  Chn^.ChSetType(S);
  Check((Chn^.CH_Type = 'Mine') and (Chn^.CH_Name = 'Mine') and
    (Chn^.CH_NumName = ChNumName('MINE')), 'ChSetType');
  P := nil;
  W := 0;
  S := 'LSB=40';
  Check((Chn^.ChParamSendBuffer(S, 0, 100, cmd_Set, P, W) = res_Ok) and
    (P <> nil) and (W = 40), 'ChParamSendBuffer');
  ChSendBuffer(P, W, 500);
  Check(W = 40, 'ChSendBuffer keeps a buffer given');
  ChFreeSendBuffer(P, W);
  Check((P = nil) and (W = 0), 'ChFreeSendBuffer');
  ChSendBuffer(P, W, 500);
  Check((P <> nil) and (W = 500), 'ChSendBuffer');
  ChFreeSendBuffer(P, W);
  Dispose(Chn, Done);
  WriteLn('legacy_modeapi ok (Integer ', SizeOf(Integer), ' bytes, string ',
    SizeOf(string), ' bytes)');
end.
