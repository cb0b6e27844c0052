{ Tests of ChnProto, the protocol base, run over each of its layers (DF1,
  FT 1.2, ICS) from one table: the receive rule (ChReceive steps the
  receiver itself), a babbling line that cannot stall a poll, and the
  "holds input not yet taken" flag of the program-wide wait (counted while
  a frame waits or bytes wait undecoded, never leaked by close, disconnect
  or Dispose). }
unit TestChnProto;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnWait, ChnProto, ChnLoop,
  ChnDF1, ChnFT1_2, ChnICS, TestSupport;

type
  TTestChnProto = class(TTestCase)
  private
    Sender, Receiver: pChnVirt;
    RBuf: array[0..599] of Byte;
    { the case's two stacks over LOOP, the receiver's buffer RBuf }
    procedure OpenPair(Index: Integer);
    procedure SendMessage(Index, Nr: Integer);
    { SendMessage, then poll the receiver until the frame waits }
    procedure Arrive(Index, Nr: Integer);
    function CaseName(Index: Integer): string;
  protected
    procedure SetUp; override;
    procedure TearDown; override;
  published
    procedure TestEveryProtocolLayerIsAProto;
    procedure TestReceiveStepsTheReceiverItself;
    procedure TestBabblingLineDoesNotStallAPoll;
    procedure TestHeldWhileAFrameWaits;
    procedure TestHeldWhileBytesWaitUndecoded;
    procedure TestHeldClearedByCloseDisconnectFlushAndDispose;
    procedure TestResultTextsRegistered;
  end;

implementation

type
  TProtoCase = record
    Name    : string;
    Sender  : string;   { %s: the LOOP pair }
    Receiver: string;
    Babble  : string;   { the layer over a NOISE line babbling bytes that start no frame }
  end;

const
  Cases: array[0..2] of TProtoCase = (
    (Name: 'DF1';
     Sender: 'NAM=DF1 NOD=1 DNO=2 NAM=LOOP PAIR=%s END=1 IDL=0';
     Receiver: 'NAM=DF1 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=%s END=2 IDL=0';
     Babble: 'NAM=DF1 NAM=NOISE BYTE=0 CNT=1000000'),         { zeros, never a DLE }
    (Name: 'FT1_2';
     Sender: 'NAM=FT1_2 NOD=1 DNO=2 NAM=LOOP PAIR=%s END=1 IDL=0';
     Receiver: 'NAM=FT1_2 NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=%s END=2 IDL=0';
     Babble: 'NAM=FT1_2 NAM=NOISE BYTE=0 CNT=1000000'),       { never a start character }
    (Name: 'ICS';
     Sender: 'NAM=ICS NOD=1 DNO=2 NAM=LOOP PAIR=%s END=1 IDL=0';
     Receiver: 'NAM=ICS NOD=2 DNO=1 MAS=SLAVE NAM=LOOP PAIR=%s END=2 IDL=0';
     Babble: 'NAM=ICS NAM=NOISE BYTE=65 CNT=1000000'));       { letters, never an SOH }

procedure TTestChnProto.SetUp;
begin
  Sender := nil;
  Receiver := nil;
end;

procedure TTestChnProto.TearDown;
begin
  if Sender <> nil then
    Dispose(Sender, Done);
  if Receiver <> nil then
    Dispose(Receiver, Done);
  Sender := nil;
  Receiver := nil;
end;

function TTestChnProto.CaseName(Index: Integer): string;
begin
  Result := Cases[Index].Name;
end;

procedure TTestChnProto.OpenPair(Index: Integer);
var
  Err, Pair: string;
begin
  TearDown;
  Pair := 'PROTO' + Cases[Index].Name;
  Sender := OpenStack(Cases[Index].Name, Format(Cases[Index].Sender, [Pair]), Err);
  AssertTrue(Err, Sender <> nil);
  Receiver := OpenStack(Cases[Index].Name, Format(Cases[Index].Receiver, [Pair]), Err);
  AssertTrue(Err, Receiver <> nil);
  Receiver^.ChReceiveBuffer(@RBuf, SizeOf(RBuf));
end;

procedure TTestChnProto.Arrive(Index, Nr: Integer);
begin
  SendMessage(Index, Nr);
  AssertTrue(CaseName(Index) + ': arrived', WaitReceive(Receiver, 2000));
end;

{ One data message of the case's protocol, numbered Nr. }
procedure TTestChnProto.SendMessage(Index, Nr: Integer);
var
  D: ChnDF1.tSendRecord;
  F: ChnFT1_2.tSendRecord;
  I: ChnICS.tSendRecord;
begin
  case Index of
    0: begin
         FillChar(D, SizeOf(D), 0);
         D.MessType := ChnDF1.tpDataMess;
         D.CF := ChnDF1.CF_Echo;
         D.Tns := Nr;
         D.Data[0] := Nr;
         Sender^.ChSend(@D, ChnDF1.cSizeHeadSndMsg + 1);
       end;
    1: begin
         FillChar(F, SizeOf(F), 0);
         F.MessType := ChnFT1_2.tpLongM;
         F.FC := ChnFT1_2.FCM_UserDataNoRep;
         F.Data[1] := Nr;
         Sender^.ChSend(@F, ChnFT1_2.cSizeHeadSndMsg + 1);
       end;
    2: begin
         FillChar(I, SizeOf(I), 0);
         I.OpCode := ChnICS.OCM_WriteData;
         I.BlockNum := 1;
         I.Data[0] := Nr;
         Sender^.ChSend(@I, 4 + SizeOf(ChnICS.tData));
       end;
  end;
  AssertEquals(CaseName(Index) + ' send', res_Ok, Sender^.ChSendResult);
end;

procedure TTestChnProto.TestEveryProtocolLayerIsAProto;
var
  I: Integer;
  C: pChnVirt;
begin
  { the base's LSB= is each layer's; ChGetParam keeps each layer's form }
  for I := Low(Cases) to High(Cases) do
  begin
    C := ChnCollection^.ChNewInit(Cases[I].Name);
    try
      C^.ChSetParam('LSB=300');
      AssertEquals(CaseName(I) + ' LSB=300', res_Ok, C^.ChResult);
      AssertEquals(CaseName(I), 300, pChnProto(C)^.CH_MSBuff);
      AssertTrue(CaseName(I) + ' reports LSB', Pos(' LSB=300', C^.ChGetParam('')) > 0);
      C^.ChSetParam('LSB=70000');
      AssertEquals(CaseName(I) + ' LSB=70000', res_BadParam, C^.ChResult);
    finally
      Dispose(C, Done);
    end;
  end;
end;

{ The one rule of the base: ChReceive takes a message that has arrived
  whether or not ChReceiveReady was polled since (FT 1.2 and ICS answered
  res_NoMessage here before the base). }
procedure TTestChnProto.TestReceiveStepsTheReceiverItself;
var
  I: Integer;
  Len: Word;
begin
  for I := Low(Cases) to High(Cases) do
  begin
    OpenPair(I);
    Len := 0;
    Receiver^.ChReceive(Len);
    AssertEquals(CaseName(I) + ': nothing sent yet', res_NoMessage, Receiver^.ChReceiveResult);
    SendMessage(I, 7);
    Receiver^.ChReceive(Len);
    AssertEquals(CaseName(I) + ': ChReceive without ChReceiveReady', res_Ok,
      Receiver^.ChReceiveResult);
    AssertTrue(CaseName(I) + ': Len', Len > 0);
    AssertEquals(CaseName(I) + ': CH_LRMess', Len, pChnProto(Receiver)^.CH_LRMess);
  end;
end;

{ A line that never stops sending bytes that start no frame: one
  ChReceiveReady returns after a bounded number of bytes, not after the
  babble ends. }
procedure TTestChnProto.TestBabblingLineDoesNotStallAPoll;
var
  I: Integer;
  State: tChState;
  N: LongInt;
begin
  for I := Low(Cases) to High(Cases) do
  begin
    State := CHS_Close;
    N := NoiseOnePoll(Cases[I].Babble, State);
    AssertTrue(CaseName(I) + ': stack opened', N >= 0);
    AssertEquals(CaseName(I) + ': no message', CHS_Receiving, State);
    AssertTrue(CaseName(I) + ': one poll took ' + IntToStr(N) + ' bytes', N <= 65536);
  end;
end;

procedure TTestChnProto.TestHeldWhileAFrameWaits;
var
  I: Integer;
  Len: Word;
  Base: LongInt;
  T: QWord;
begin
  Base := ChnWaitHeldCount;
  for I := Low(Cases) to High(Cases) do
  begin
    OpenPair(I);
    AssertEquals(CaseName(I) + ': nothing held', Base, ChnWaitHeldCount);
    Arrive(I, 1);
    AssertEquals(CaseName(I) + ': a frame waits', Base + 1, ChnWaitHeldCount);
    T := GetTickCount64;
    AssertTrue(CaseName(I) + ': ChnWaitAny sees it', ChnWaitAny(1000));
    AssertTrue(CaseName(I) + ': at once', GetTickCount64 - T < 200);
    Receiver^.ChReceive(Len);
    AssertEquals(CaseName(I), res_Ok, Receiver^.ChReceiveResult);
    AssertEquals(CaseName(I) + ': taken', Base, ChnWaitHeldCount);
  end;
end;

{ Two frames in one chunk: the first is decoded, the second's bytes stay
  in the layer, so it still holds input after the first is taken. }
procedure TTestChnProto.TestHeldWhileBytesWaitUndecoded;
var
  I: Integer;
  Len: Word;
  Base: LongInt;
begin
  Base := ChnWaitHeldCount;
  for I := Low(Cases) to High(Cases) do
  begin
    OpenPair(I);
    SendMessage(I, 1);
    AssertTrue(CaseName(I) + ': LOOP takes the second at once', WaitSent(Sender, 2000));
    Arrive(I, 2);
    Receiver^.ChReceive(Len);
    AssertEquals(CaseName(I) + ' first', res_Ok, Receiver^.ChReceiveResult);
    AssertTrue(CaseName(I) + ': the second frame''s bytes wait in the layer',
      pChnProto(Receiver)^.CH_LowPos < pChnProto(Receiver)^.CH_LowLen);
    AssertEquals(CaseName(I) + ': still held', Base + 1, ChnWaitHeldCount);
    AssertTrue(CaseName(I) + ': ChnWaitAny returns at once', ChnWaitAny(0));
    Receiver^.ChReceive(Len);
    AssertEquals(CaseName(I) + ' second', res_Ok, Receiver^.ChReceiveResult);
    AssertEquals(CaseName(I) + ': all taken', Base, ChnWaitHeldCount);
  end;
end;

procedure TTestChnProto.TestHeldClearedByCloseDisconnectFlushAndDispose;
var
  I, Way: Integer;
  Base: LongInt;
begin
  Base := ChnWaitHeldCount;
  for I := Low(Cases) to High(Cases) do
    for Way := 0 to 3 do
    begin
      OpenPair(I);
      Arrive(I, 1);
      AssertEquals(CaseName(I) + ': held', Base + 1, ChnWaitHeldCount);
      case Way of
        0: Receiver^.ChClose;
        1: Receiver^.ChDisConnect;
        2: Receiver^.ChReceiveFlush;
        3: begin
             Dispose(Receiver, Done);    { open, holding: Done closes it }
             Receiver := nil;
           end;
      end;
      AssertEquals(CaseName(I) + ' way ' + IntToStr(Way) + ': count back', Base,
        ChnWaitHeldCount);
    end;
end;

procedure TTestChnProto.TestResultTextsRegistered;
begin
  AssertEquals('DF1: checksum (BCC/CRC) error', ChResultText(ChnDF1.res_ErrSum, ChnDF1.cName));
  AssertEquals('FT1_2: DIR bit says the frame came from this station''s own side',
    ChResultText(ChnFT1_2.res_ErrDir, ChnFT1_2.cName));
  AssertEquals('ICS: EOT missing after the checksum', ChResultText(ChnICS.res_ErrEOT, ChnICS.cName));
  AssertTrue('layers registered', (ChnCollection^.Search('DF1') <> nil) and
    (ChnCollection^.Search('FT1_2') <> nil) and (ChnCollection^.Search('ICS') <> nil));
end;

initialization
  RegisterTest(TTestChnProto);
end.
