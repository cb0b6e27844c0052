{ Tests of ChnTelnet, the Telnet / RFC 2217 codec: byte streams written out
  by hand from RFC 854 (IAC = $FF, SB $FA, SE $F0, WILL $FB, WONT $FC, DO
  $FD, DONT $FE) and RFC 2217 (COM-PORT-OPTION 44 = $2C, SET-BAUDRATE 1 with
  a 4-byte big-endian rate, server codes + 100). }
unit TestChnTelnet;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTelnet, TestSupport;

type
  TTestChnTelnet = class(TTestCase)
  private
    function Decode(const Hex: string; out Events: string): string;
  published
    procedure TestDataAndDoubledIac;
    procedure TestOptionRequests;
    procedure TestSubnegotiationWithDoubledIac;
    procedure TestOverlongSubnegotiationIsCut;
    procedure TestUnclosedSubnegotiationIsBroken;
    procedure TestEscapeStopsAtCapacity;
    procedure TestComPortCommands;
    procedure TestNegotiationPolicy;
    procedure TestNoReplyLoop;
  end;

implementation

{ Feed Hex; returns the data bytes as hex, Events lists 'O<cmd>/<opt>' and
  'S<opt>:<hex>' in order. }
function TTestChnTelnet.Decode(const Hex: string; out Events: string): string;
var
  D: tTelnetDecoder;
  B: TBytes;
  I: Integer;
  Data: TBytes;
begin
  TelnetInit(D);
  B := HexToBytes(Hex);
  Events := '';
  SetLength(Data, 0);
  for I := 0 to High(B) do
    case TelnetFeed(D, B[I]) of
      teData:
        begin
          SetLength(Data, Length(Data) + 1);
          Data[High(Data)] := B[I];
        end;
      teOption:
        Events := Events + Format('O%d/%d ', [D.Cmd, D.Opt]);
      teSub:
        Events := Events + Format('S%d:%s ', [D.Opt, BytesToHex(D.Sub, D.SubLen)]);
    end;
  Result := BytesToHex(Data, Length(Data));
end;

procedure TTestChnTelnet.TestDataAndDoubledIac;
var
  Ev: string;
begin
  AssertEquals('01 FF 02', Decode('01 FF FF 02', Ev));
  AssertEquals('', Ev);
  AssertEquals('FF FF', Decode('FF FF FF FF', Ev));
  { a lone command (NOP) is dropped, the data around it kept }
  AssertEquals('41 42', Decode('41 FF F1 42', Ev));
end;

procedure TTestChnTelnet.TestOptionRequests;
var
  Ev: string;
begin
  AssertEquals('10 20', Decode('10 FF FD 2C 20 FF FB 00', Ev));
  AssertEquals('O253/44 O251/0 ', Ev);
end;

procedure TTestChnTelnet.TestSubnegotiationWithDoubledIac;
var
  Ev: string;
begin
  { server's SET-BAUDRATE answer for 16777215 + 255: value 00 FF FF FF FF
    would not fit; use 0x00FFFF00 -> 00 FF FF FF FF 00 on the wire }
  AssertEquals('55 66', Decode('55 FF FA 2C 65 00 FF FF FF FF 00 FF F0 66', Ev));
  AssertEquals('S44:65 00 FF FF 00 ', Ev);
end;

procedure TTestChnTelnet.TestOverlongSubnegotiationIsCut;
var
  D: tTelnetDecoder;
  I: Integer;
  E: tTelnetEvent;
begin
  TelnetInit(D);
  TelnetFeed(D, $FF);
  TelnetFeed(D, $FA);
  TelnetFeed(D, 44);
  for I := 1 to TelnetSubLimit - 1 do
    AssertTrue('no event inside', TelnetFeed(D, $41) = teNone);
  TelnetFeed(D, $FF);
  E := TelnetFeed(D, $F0);
  AssertTrue('ends', E = teSub);
  AssertTrue('flagged as cut', D.SubCut);
  AssertEquals(TelnetMaxSub, D.SubLen);
  AssertTrue('data again', TelnetFeed(D, $42) = teData);
end;

{ A server that opens IAC SB and never sends IAC SE would swallow every
  data byte after it: after TelnetSubLimit bytes the decoder says so and
  the bytes after are data again. }
procedure TTestChnTelnet.TestUnclosedSubnegotiationIsBroken;
var
  D: tTelnetDecoder;
  I: Integer;
  E: tTelnetEvent;
begin
  TelnetInit(D);
  AssertTrue(TelnetFeed(D, $FF) = teNone);
  AssertTrue(TelnetFeed(D, $FA) = teNone);
  AssertTrue(TelnetFeed(D, 44) = teNone);
  AssertTrue(TelnetFeed(D, 107) = teNone);      { NOTIFY-MODEMSTATE ... }
  for I := 2 to TelnetSubLimit - 1 do
    AssertTrue('no event inside', TelnetFeed(D, $41) = teNone);
  E := TelnetFeed(D, $41);
  AssertTrue('the limit is named', E = teSubBroken);
  AssertTrue('data again', TelnetFeed(D, $42) = teData);
  { a doubled IAC counts as one byte of the value }
  TelnetInit(D);
  TelnetFeed(D, $FF);
  TelnetFeed(D, $FA);
  TelnetFeed(D, 44);
  for I := 1 to TelnetSubLimit - 1 do
  begin
    AssertTrue(TelnetFeed(D, $FF) = teNone);
    AssertTrue(TelnetFeed(D, $FF) = teNone);
  end;
  TelnetFeed(D, $FF);
  AssertTrue('doubled IACs too', TelnetFeed(D, $FF) = teSubBroken);
  { a subnegotiation closed just below the limit is one }
  TelnetInit(D);
  TelnetFeed(D, $FF);
  TelnetFeed(D, $FA);
  TelnetFeed(D, 44);
  for I := 1 to TelnetSubLimit - 1 do
    TelnetFeed(D, $41);
  TelnetFeed(D, $FF);
  AssertTrue(TelnetFeed(D, $F0) = teSub);
end;

procedure TTestChnTelnet.TestEscapeStopsAtCapacity;
var
  Src: array[0..3] of Byte = ($01, $FF, $02, $FF);
  Dst: array[0..7] of Byte;
  Used, N: LongInt;
begin
  N := TelnetEscape(Src, 4, Dst, 8, Used);
  AssertEquals(6, N);
  AssertEquals(4, Used);
  AssertEquals('01 FF FF 02 FF FF', BytesToHex(Dst, N));
  { an $FF never split from its double }
  N := TelnetEscape(Src, 4, Dst, 2, Used);
  AssertEquals(1, N);
  AssertEquals(1, Used);
  N := TelnetEscape(Src, 4, Dst, 5, Used);
  AssertEquals(4, N);
  AssertEquals(3, Used);
end;

procedure TTestChnTelnet.TestComPortCommands;
var
  Out: array[0..31] of Byte;
  V: array[0..3] of Byte;
  N: LongInt;
begin
  BaudToBytes(19200, V);
  N := ComPortCmd(Out, CPO_SETBAUDRATE, V, 4);
  AssertEquals('FF FA 2C 01 00 00 4B 00 FF F0', BytesToHex(Out, N));
  AssertEquals(19200, BytesToBaud(V, 0));
  { a rate with an $FF byte: 65535 = 00 00 FF FF, doubled }
  BaudToBytes(65535, V);
  N := ComPortCmd(Out, CPO_SETBAUDRATE, V, 4);
  AssertEquals('FF FA 2C 01 00 00 FF FF FF FF FF F0', BytesToHex(Out, N));
  V[0] := CPU_RX;
  N := ComPortCmd(Out, CPO_PURGEDATA, V, 1);
  AssertEquals('FF FA 2C 0C 01 FF F0', BytesToHex(Out, N));
  N := TelnetCmd(Out, TN_WILL, TNO_COMPORT);
  AssertEquals('FF FB 2C', BytesToHex(Out, N));
end;

procedure TTestChnTelnet.TestNegotiationPolicy;
var
  N: tTelnetNeg;
begin
  TelnetNegInit(N);
  { ser2net's opening: WILL SGA, DO SGA, WILL ECHO, DO BINARY, WILL BINARY }
  AssertEquals('DO SGA', TN_DO, TelnetAnswer(N, TN_WILL, TNO_SGA));
  AssertEquals('WILL SGA', TN_WILL, TelnetAnswer(N, TN_DO, TNO_SGA));
  AssertEquals('no echo from the server', TN_DONT, TelnetAnswer(N, TN_WILL, TNO_ECHO));
  AssertEquals('WILL BINARY', TN_WILL, TelnetAnswer(N, TN_DO, TNO_BINARY));
  AssertEquals('DO BINARY', TN_DO, TelnetAnswer(N, TN_WILL, TNO_BINARY));
  AssertEquals('unknown option refused', TN_WONT, TelnetAnswer(N, TN_DO, 24));
  AssertEquals('the peer doing COM-PORT is not for us', TN_DONT,
    TelnetAnswer(N, TN_WILL, TNO_COMPORT));
  { asked ourselves: the DO is the answer, no reply }
  TelnetAsked(N, TN_WILL, TNO_COMPORT);
  AssertEquals('answer to our WILL', 0, TelnetAnswer(N, TN_DO, TNO_COMPORT));
  AssertTrue('COM-PORT on', N[TNO_COMPORT].Us);
  AssertEquals('turned off', TN_WONT, TelnetAnswer(N, TN_DONT, TNO_COMPORT));
  AssertFalse(N[TNO_COMPORT].Us);
end;

procedure TTestChnTelnet.TestNoReplyLoop;
var
  N: tTelnetNeg;
begin
  TelnetNegInit(N);
  AssertEquals(TN_WILL, TelnetAnswer(N, TN_DO, TNO_BINARY));
  { the same request again confirms the state: no reply (RFC 1143) }
  AssertEquals(0, TelnetAnswer(N, TN_DO, TNO_BINARY));
  AssertEquals(0, TelnetAnswer(N, TN_WONT, TNO_ECHO));
  AssertEquals(0, TelnetAnswer(N, TN_DONT, TNO_ECHO));
  { our refused WILL: no reply to the DONT }
  TelnetAsked(N, TN_WILL, TNO_COMPORT);
  AssertEquals(0, TelnetAnswer(N, TN_DONT, TNO_COMPORT));
  AssertFalse(N[TNO_COMPORT].UsAsked);
end;

initialization
  RegisterTest(TTestChnTelnet);
end.
