{ Iec101Sim - an IEC 60870-5-101 slave application for tests: a
  tFT12Station (unbalanced) or tFT12Balanced (balanced) on any channel,
  answering the master's ASDUs with octets written out by hand (COT 2,
  CA 2, IOA 3): the interrogation answer of lib60870's cs101_slave example
  (scaled IOA 100..102 = -1, 23, 2300, single points 104, 105 and a
  CP56-tagged single point 300), commands to IOA 5000 confirmed (and
  terminated on execute), C_SE_NC_1 refused, a read of IOA 100, every
  other IOA, CA or type answered with COT 47, 46 or 44. Step drives it. }
unit Iec101Sim;

{$MODE OBJFPC}{$H+}

interface

uses
  Classes, SysUtils, ChnTypes, ChnVirt, ChnFT1_2, ChnFT12Station, ChnFT12Balanced, ChnIec101Asdu, TestSupport;

const
  GiAnswer: array[0..2] of string = (
    '0B 03 14 00 01 00 64 00 00 FF FF 00 65 00 00 17 00 00 66 00 00 FC 08 00',
    '01 02 14 00 01 00 68 00 00 01 69 00 00 00',
    '1E 01 14 00 01 00 2C 01 00 01 2A 76 0F 16 41 0C 1A');

type
  { One slave's application. }
  TSim = class
    Chn: pChnVirt;
    St: tFT12Station;
    Bal: tFT12Balanced;
    Balanced: Boolean;
    Alive: Boolean;
    Ca: Word;
    Class1, Class2: TStringList;   { hex ASDUs to send }
    Got: TStringList;              { hex ASDUs received }
    RefuseNext: Boolean;           { the next command gets a negative ACT_CON }
    { hostile: a select's ACT_CON with S/E = 0; every ACT_CON with T = 1 }
    SelectConfirmedAsExecute, ConfirmInTest: Boolean;
    { hostile: the answer of phase MisPhase (1 a select's ACT_CON, 2 any
      other ACT_CON, 3 an ACT_TERM) for another object - MisWhat 'ioa':
      the IOA's low octet with bit 0 flipped, 'ca': the CA's }
    MisWhat: string;
    MisPhase: LongInt;
    ReadOtherIoa: Boolean;         { hostile: a read of IOA 100 answered with IOA 101 }
    { hostile links: ACD in every answer, none of it class 1 data
      (AcdStuck); this ASDU in every class 1 answer (Stream); status and
      reset answered, class polls never (HalfDead) }
    AcdStuck, HalfDead: Boolean;
    { the link by hand, as HalfDead, but class 2 polls answered from
      Class2 with frames of any length (L up to 255, longer than a
      tFT12Station's reply record holds), class 1 with "no data" }
    Manual: Boolean;
    Stream: string;
    HalfDeadPolls: LongInt;        { class polls a HalfDead slave left unanswered }
    constructor Create(const Params: string; IsBalanced: Boolean; LinkMs: LongInt = 40);
    destructor Destroy; override;
    procedure Take(const Hex: string);
    procedure Send(const Hex: string; ToClass1: Boolean);
    { one step of the link when Alive; True when a frame was taken }
    function Step: Boolean;
  end;


implementation

{ ------------------------------------------------------------ the slaves }

function SimUser(Data: Pointer; Buf: PByte; Len: Word; Confirm: Boolean): Boolean;
begin
  TSim(Data).Take(BytesToHex(Buf[0], Len));
  Result := True;
end;

function SimClass(Data: Pointer; ClassNo: Byte; var Rep: tSendRecord; var Len: Word): Boolean;
var
  S: TSim;
  L: TStringList;
  B: TBytes;
  I: Integer;
begin
  S := TSim(Data);
  if ClassNo = 1 then L := S.Class1 else L := S.Class2;
  if (ClassNo = 1) and (L.Count = 0) and (S.Stream <> '') then
    L.Add(S.Stream);
  Result := L.Count > 0;
  if not Result then
    Exit;
  B := HexToBytes(L[0]);
  L.Delete(0);
  for I := 0 to High(B) do
    Rep.Data[I + 1] := B[I];
  Len := Length(B);
end;

function SimAcd(Data: Pointer): Boolean;
begin
  with TSim(Data) do
    Result := (Class1.Count > 0) or AcdStuck or (Stream <> '');
end;

constructor TSim.Create(const Params: string; IsBalanced: Boolean; LinkMs: LongInt);
var
  Err: string;
begin
  Class1 := TStringList.Create;
  Class2 := TStringList.Create;
  Got := TStringList.Create;
  Alive := True;
  Ca := 1;
  Balanced := IsBalanced;
  Chn := OpenStack(ChnFT1_2.cName, Params, Err);
  if Chn = nil then
    raise Exception.Create(Err);
  if Balanced then
  begin
    FT12BalancedInit(Bal, Chn);
    Bal.TimeoutMs := LinkMs;
    Bal.OnUserData := @SimUser;
    Bal.Data := Self;
  end
  else
  begin
    FT12StationInit(St, Chn);
    St.OnUserData := @SimUser;
    St.OnClassData := @SimClass;
    St.OnClass1 := @SimAcd;
    St.Data := Self;
  end;
end;

destructor TSim.Destroy;
begin
  if Chn <> nil then
    Dispose(Chn, Done);
  Class1.Free;
  Class2.Free;
  Got.Free;
  inherited Destroy;
end;

procedure TSim.Send(const Hex: string; ToClass1: Boolean);
var
  B: TBytes;
begin
  if Balanced then
  begin
    B := HexToBytes(Hex);
    FT12BalancedSend(Bal, @B[0], Length(B), True);
  end
  else if ToClass1 then
    Class1.Add(Hex)
  else
    Class2.Add(Hex);
end;

{ The slave's application: answer the master's ASDU (octets in hex). }
procedure TSim.Take(const Hex: string);
var
  B: TBytes;
  Ti, Cot: Byte;
  Ioa: LongInt;

  function Mirror(NewCot: Byte; Negative: Boolean): string;
  var
    C: TBytes;
  begin
    C := Copy(B);
    C[2] := NewCot or (Ord(Negative) shl 6);
    if (NewCot = Cot_ActCon) and ConfirmInTest then
      C[2] := C[2] or $80;
    if (NewCot = Cot_ActCon) and SelectConfirmedAsExecute and (Ti in [C_SC_NA_1, C_DC_NA_1, C_SE_NB_1]) then
      C[Length(C) - 1] := C[Length(C) - 1] and $7F;
    if (MisWhat <> '') and (MisPhase = Ord(NewCot = Cot_ActTerm) * 3 + Ord(NewCot = Cot_ActCon)
      * (2 - Ord((Ti in [C_SC_NA_1, C_DC_NA_1, C_SE_NB_1]) and (B[Length(B) - 1] and $80 <> 0)))) then
      if MisWhat = 'ioa' then
        C[6] := C[6] xor 1
      else
        C[4] := C[4] xor 1;
    Result := BytesToHex(C, Length(C));
  end;

begin
  Got.Add(Hex);
  B := HexToBytes(Hex);
  Ti := B[0];
  Cot := B[2] and $3F;
  Ioa := B[6] or (B[7] shl 8) or (B[8] shl 16);
  if (B[4] or (B[5] shl 8)) <> Ca then
  begin
    Send(Mirror(Cot_UnknownCa, True), True);
    Exit;
  end;
  if RefuseNext and (Ti in [C_SC_NA_1..C_BO_NA_1, C_SC_TA_1..C_BO_TA_1]) then
  begin
    RefuseNext := False;
    Send(Mirror(Cot_ActCon, True), True);
    Exit;
  end;
  case Ti of
    C_IC_NA_1:
      begin
        Send(Mirror(Cot_ActCon, False), True);
        Send(GiAnswer[0], False);
        Send(GiAnswer[1], False);
        Send(GiAnswer[2], False);
        Send(Mirror(Cot_ActTerm, False), False);
      end;
    C_CI_NA_1:
      begin
        Send(Mirror(Cot_ActCon, False), True);
        Send('0F 01 25 00 01 00 F4 01 00 E8 03 00 00 02', False);
        Send(Mirror(Cot_ActTerm, False), False);
      end;
    C_SC_NA_1, C_DC_NA_1, C_SE_NB_1:
      if Ioa <> 5000 then
        Send(Mirror(Cot_UnknownIoa, True), True)
      else
      begin
        Send(Mirror(Cot_ActCon, False), True);
        if B[Length(B) - 1] and $80 = 0 then      { execute: terminated too }
          Send(Mirror(Cot_ActTerm, False), True);
      end;
    C_SE_NC_1: Send(Mirror(Cot_ActCon, True), True);      { refused }
    C_RD_NA_1:
      if (Ioa = 100) and ReadOtherIoa then
        Send('0B 01 05 00 01 00 65 00 00 FF FF 00', True)
      else if Ioa = 100 then
        Send('0B 01 05 00 01 00 64 00 00 FF FF 00', True)
      else
        Send(Mirror(Cot_UnknownIoa, True), True);
    C_CS_NA_1, C_TS_NA_1, C_RP_NA_1:
      Send(Mirror(Cot_ActCon, False), True);
    C_CD_NA_1:
      if Cot = Cot_Activation then
        Send(Mirror(Cot_ActCon, False), True);   { spontaneous: the delay, no answer }
  else
    Send(Mirror(Cot_UnknownType, True), True);
  end;
end;

{ HalfDead: the frame taken by hand; FC 9 gets the status of link (FC 11),
  FC 0 an ACK, anything else nothing. }
function HalfDeadStep(S: TSim): Boolean;
var
  Len: Word;
  Rep: tFT12MaxRecord;
  B: TBytes;
  I: Integer;
begin
  Result := S.Chn^.ChReceiveReady = CHS_ReceiveReady;
  if not Result then
    Exit;
  Len := 0;
  S.Chn^.ChReceive(Len);
  if (S.Chn^.ChReceiveResult <> res_Ok) or (S.St.RMess.MessType <> tpShortM) then
    Exit;
  if S.HalfDead and (S.St.RMess.FC in [FCM_ReqUserData1, FCM_ReqUserData2]) then
    Inc(S.HalfDeadPolls);
  FillChar(Rep, SizeOf(Rep), 0);
  Rep.MessType := tpShortM;
  Len := cSizeHeadSndMsg + pChnFT1_2(S.Chn)^.CH_LenShortM;
  case S.St.RMess.FC of
    FCM_ReqLinkState: Rep.FC := FCS_LinkSAccesReq;
    FCM_1stSetTransmit: Rep.FC := FCS_Ack;
    FCM_ReqUserData1, FCM_ReqUserData2:
      if S.HalfDead then
        Exit
      else if (S.St.RMess.FC = FCM_ReqUserData2) and (S.Class2.Count > 0) then
      begin
        B := HexToBytes(S.Class2[0]);
        S.Class2.Delete(0);
        Rep.MessType := tpLongM;
        Rep.FC := FCS_UserData;
        for I := 0 to High(B) do
          Rep.Data[I + 1] := B[I];
        Len := cSizeHeadSndMsg + Length(B);
      end
      else
        Rep.FC := FCS_DataNotAcces;
  else
    Exit;
  end;
  ChSendWhenFree(S.Chn, @Rep, Len, 100);
end;

function TSim.Step: Boolean;
begin
  Result := False;
  if Alive and (HalfDead or Manual) and not Balanced then
    Result := HalfDeadStep(Self)
  else if Alive then
    if Balanced then
      Result := FT12BalancedStep(Bal)
    else
      Result := FT12StationStep(St);
end;

end.
