{ Tests of tChnCom's own logic on a scripted port (DRV=FAKE, TFakePort of
  tests/support/FakePort): its parameters and their report, the DOS keys,
  COM= numbers, the RS-485 RTS timing, overruns, send errors, modem lines
  and the port driver names. No line needed: built on every OS. }
unit TestChnComLogic;

{$MODE OBJFPC}{$H+}

interface

uses
  SysUtils, fpcunit, testregistry, ChnTypes, ChnVirt, ChnPort, ChnCom, TestSupport, FakePort;

type
  TTestChnComLogic = class(TTestCase)
  protected
    procedure SetUp; override;
  published
    procedure TestDefaultParams;
    procedure TestGetParamRoundTrip;
    procedure TestBadParamsChangeNothing;
    procedure TestDosKeysAcceptedAndIgnored;
    procedure TestComNumberNamesTtyS;
    procedure TestRs485RtsRaisedUntilLastBitLeft;
    procedure TestRs485AutoPrefersKernel;
    procedure TestRs485AutoFallsBackToRts;
    procedure TestOsOverrunReported;
    procedure TestSendErrors;
    procedure TestSettingRefusedLeavesClosed;
    procedure TestModemLinesReachThePort;
    procedure TestPortDriverNames;
    {$IFDEF WINDOWS}
    procedure TestMissingPortSaysTheOsReason;
    {$ENDIF}
  end;

implementation

{ the scripted port (DRV=FAKE) is TFakePort of tests/support/FakePort }

procedure TTestChnComLogic.SetUp;
begin
  RegisterPortDriver('FAKE', TFakePort);
  TFakePort.Reset;
end;

procedure TTestChnComLogic.TestDefaultParams;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    AssertEquals('defaults of the manual (COM=1 9600 8N1) and the port',
      'NAM=COM DRV=' + DefaultPortDriver + ' COM=1 BD=9600 BIT=8 STOP=1 PAR=N ' +
      'FLW=NONE RS485=OFF LRB=4096 LSB=65535 IDL=1', C^.ChGetParam(''));
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestGetParamRoundTrip;
const
  P = 'NAM=COM DRV=FAKE DEV=/dev/serial/by-id/usb-FTDI_FT232R_USB_UART_A50285BI-if00-port0 ' +
      'BD=19200 BIT=7 STOP=2 PAR=E FLW=RTSCTS RS485=AUTO LRB=1000 LSB=500 IDL=5 IRQ=4 ADR=$3F8';
var
  A, B: pChnVirt;
begin
  A := ChnCollection^.ChNewInit('COM');
  B := ChnCollection^.ChNewInit('COM');
  try
    A^.ChSetParam(P);
    AssertEquals('set ' + A^.ChParamError, res_Ok, A^.ChResult);
    AssertEquals('reported as given', P, A^.ChGetParam(''));
    B^.ChSetParam(A^.ChGetParam(''));
    AssertEquals('rebuilt', A^.ChGetParam(''), B^.ChGetParam(''));
    AssertEquals('one key', 'BD=19200', A^.ChGetParam('BD'));
  finally
    Dispose(A, Done);
    Dispose(B, Done);
  end;
end;

procedure TTestChnComLogic.TestBadParamsChangeNothing;
const
  Bad: array[0..14] of string = ('BD=49', 'BD=4000001', 'BD=96OO', 'BIT=4', 'BIT=9',
    'STOP=0', 'STOP=3', 'PAR=X', 'FLW=CTS', 'RS485=YES', 'LRB=0', 'LSB=65536',
    'IDL=1001', 'COM=0', 'DRV=NOPE');
  Allowed: array[0..14] of string = ('a number 50..4000000', 'a number 50..4000000',
    'a number 50..4000000', 'a number 5..8', 'a number 5..8', 'a number 1..2',
    'a number 1..2', 'one of N|E|O|M|S', 'one of NONE|RTSCTS|XONXOFF',
    'one of OFF|RTS|KERNEL|AUTO', 'a number 1..16777216', 'a number 1..65535',
    'a number 0..1000', 'a number 1..256', 'one of @DRIVERS');
var
  C: pChnVirt;
  Before: string;
  I: Integer;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    Before := C^.ChGetParam('');
    for I := Low(Bad) to High(Bad) do
    begin
      C^.ChSetParam('IRQ=4 ' + Bad[I]);
      AssertEquals(Bad[I], res_BadParam, C^.ChResult);
      AssertEquals(Bad[I] + ' named', Bad[I], C^.ChParamError);
      AssertEquals(Bad[I] + ' changed nothing', Before, C^.ChGetParam(''));
      AssertEquals(Bad[I] + ': what it allows', 'bad parameter (' + Bad[I] + '): ' +
        StringReplace(Allowed[I], '@DRIVERS', PortDriverNames, []), C^.ChErrorText);
    end;
    C^.ChSetParam('XYZ=1');
    AssertEquals('unknown key', res_UnknownParam, C^.ChResult);
    AssertEquals('unknown parameter key (XYZ=1): COM takes DRV COM BD BIT STOP PAR FLW RS485 LRB LSB IDL',
      C^.ChErrorText);
    C^.ChSetParam('NAM=DF1');
    AssertEquals('nothing below a physical layer', res_BadParam, C^.ChResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestDosKeysAcceptedAndIgnored;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    { the manuals' example line, with the port's DEV= added }
    C^.ChSetParam('NAM=COM COM=1 IRQ=4 BD=9600 BIT=8 STOP=1 PAR=E LRB=1000 DRV=FAKE DEV=/x');
    AssertEquals('manual example', res_Ok, C^.ChResult);
    C^.ChOpen;
    AssertEquals('open', res_Ok, C^.ChResult);
    AssertEquals('IRQ does not reach the port', 'open /x;cfg 9600 8E1;', TFakePort.Log);
    AssertEquals('IRQ reported back', 'IRQ=4', C^.ChGetParam('IRQ'));
    C^.ChClose;
    C^.ChSetParam('PORT=$2F8');
    AssertEquals('port address', res_Ok, C^.ChResult);
    C^.ChSetParam('BASE=3F8h');
    AssertEquals('base address in any notation', res_Ok, C^.ChResult);
    { kept as text for ChGetParam, so their length is bounded: IRQ= value
      up to 15 characters, an ADR=/BASE=/PORT= token up to 31 }
    C^.ChSetParam('IRQ=' + StringOfChar('1', 15));
    AssertEquals('IRQ, 15 characters', res_Ok, C^.ChResult);
    C^.ChSetParam('IRQ=' + StringOfChar('1', 16));
    AssertEquals('IRQ, 16 characters', res_BadParam, C^.ChResult);
    AssertEquals('IRQ kept', 'IRQ=' + StringOfChar('1', 15), C^.ChGetParam('IRQ'));
    C^.ChSetParam('ADR=' + StringOfChar('3', 27));
    AssertEquals('ADR token, 31 characters', res_Ok, C^.ChResult);
    C^.ChSetParam('ADR=' + StringOfChar('3', 28));
    AssertEquals('ADR token, 32 characters', res_BadParam, C^.ChResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestComNumberNamesTtyS;
var
  C: pChnVirt;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE COM=3');
    C^.ChOpen;
    {$IFDEF WINDOWS}
    AssertEquals('COM3', 'open \\.\COM3;cfg 9600 8N1;', TFakePort.Log);
    {$ELSE}
    AssertEquals('COM=3 is the third UART', 'open /dev/ttyS2;cfg 9600 8N1;', TFakePort.Log);
    {$ENDIF}
    C^.ChClose;
    TFakePort.Log := '';
    C^.ChSetParam('DEV=/dev/ttyUSB0');
    C^.ChOpen;
    AssertEquals('DEV overrides COM', 'open /dev/ttyUSB0;cfg 9600 8N1;', TFakePort.Log);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestRs485RtsRaisedUntilLastBitLeft;
var
  C: pChnVirt;
  Msg: array[0..249] of Byte;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x RS485=RTS IDL=0');
    C^.ChOpen;
    AssertEquals('open', res_Ok, C^.ChResult);
    AssertEquals('receive direction after open', 'open /x;cfg 9600 8N1;rts0;', TFakePort.Log);
    TFakePort.Log := '';
    FillChar(Msg, SizeOf(Msg), $55);
    C^.ChSend(@Msg, SizeOf(Msg));
    AssertEquals('send', res_Ok, C^.ChSendResult);
    AssertEquals('RTS before the first byte', 'rts1;w100;w100;w50;q250;', TFakePort.Log);
    AssertEquals('150 bytes still queued', CHS_Sending, C^.ChSendReady);
    C^.ChSend(@Msg, 1);               { looks at the queue once more: 50 left }
    AssertEquals('no new message while RTS is up', res_Busy, C^.ChSendResult);
    AssertEquals('queue empty, drained, RTS down', CHS_SendReady, C^.ChSendReady);
    AssertEquals('sequence', 'rts1;w100;w100;w50;q250;q150;q50;q0;drain;rts0;', TFakePort.Log);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestRs485AutoPrefersKernel;
var
  C: pChnVirt;
  Msg: array[0..9] of Byte;
begin
  TFakePort.KernelOk := True;
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x RS485=AUTO');
    C^.ChOpen;
    FillChar(Msg, SizeOf(Msg), 0);
    C^.ChSend(@Msg, 10);
    AssertEquals('sent', CHS_SendReady, C^.ChSendReady);
    AssertEquals('the driver switches, not the layer', 'open /x;cfg 9600 8N1;k1;w10;', TFakePort.Log);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestRs485AutoFallsBackToRts;
var
  C: pChnVirt;
  Msg: array[0..9] of Byte;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x RS485=AUTO IDL=0');
    C^.ChOpen;
    AssertEquals('open', res_Ok, C^.ChResult);
    FillChar(Msg, SizeOf(Msg), 0);
    C^.ChSend(@Msg, 10);
    C^.ChSendReady;
    AssertEquals('layer toggles RTS', 'open /x;cfg 9600 8N1;rts0;rts1;w10;q10;q0;drain;rts0;',
      TFakePort.Log);
    C^.ChSetParam('RS485=KERNEL');
    C^.ChClose;
    C^.ChOpen;
    AssertEquals('KERNEL alone is refused', res_BadSetting, C^.ChResult);
    AssertEquals('closed', CHS_Close, C^.ChReady);
    TFakePort.KernelOk := True;
    C^.ChSetParam('RS485=AUTO FLW=RTSCTS');
    C^.ChOpen;
    AssertEquals('RTS is either handshake or direction', res_BadSetting, C^.ChResult);
    AssertEquals('closed too', CHS_Close, C^.ChReady);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestOsOverrunReported;
var
  C: pChnVirt;
  Buf: array[0..15] of Byte;
  Len: Word;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x');
    C^.ChOpen;
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    C^.ChConnect;
    TFakePort.OsLost := 5;          { the UART lost 5 bytes }
    TFakePort.RxData := 'abc';
    AssertEquals('ready', CHS_ReceiveReady, C^.ChReceiveReady);
    C^.ChReceive(Len);
    AssertEquals('3 bytes', 3, Len);
    AssertEquals('overrun', res_Overrun, C^.ChReceiveResult);
    AssertEquals('counted', 5, pChnCom(C)^.ChLostBytes);
    TFakePort.RxData := 'd';
    AssertEquals('ready again', CHS_ReceiveReady, C^.ChReceiveReady);
    C^.ChReceive(Len);
    AssertEquals('reported once', res_Ok, C^.ChReceiveResult);
    AssertEquals('byte', Ord('d'), Buf[0]);
    { a small application buffer takes the rest on the next call }
    TFakePort.RxData := StringOfChar('x', 20);
    C^.ChReceiveReady;
    C^.ChReceive(Len);
    AssertEquals('buffer size', 16, Len);
    AssertEquals('rest waits', CHS_ReceiveReady, C^.ChReceiveReady);
    C^.ChReceive(Len);
    AssertEquals('rest', 4, Len);
    C^.ChReceive(Len);
    AssertEquals('nothing', 0, Len);
    AssertEquals('no message', res_NoMessage, C^.ChReceiveResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestSendErrors;
var
  C: pChnVirt;
  Msg: array[0..99] of Byte;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x LSB=50');
    FillChar(Msg, SizeOf(Msg), 0);
    C^.ChSend(@Msg, 10);
    AssertEquals('closed', res_WrongState, C^.ChSendResult);
    C^.ChOpen;
    TFakePort.Log := '';
    C^.ChOpen;
    AssertEquals('open twice', res_WrongState, C^.ChResult);
    AssertEquals('no second port opened', '', TFakePort.Log);
    AssertEquals('still open', CHS_Open, C^.ChReady);
    C^.ChSend(@Msg, 0);
    AssertEquals('empty', res_BadLen, C^.ChSendResult);
    C^.ChSend(nil, 5);
    AssertEquals('nil', res_BadLen, C^.ChSendResult);
    TFakePort.Log := '';
    C^.ChSend(@Msg, 51);
    AssertEquals('above LSB', res_TooLong, C^.ChSendResult);
    AssertEquals('nothing written', '', TFakePort.Log);
    C^.ChSend(@Msg, 50);
    AssertEquals('LSB itself', res_Ok, C^.ChSendResult);
    C^.ChClose;
    C^.ChClose;
    AssertEquals('close twice', res_WrongState, C^.ChResult);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestSettingRefusedLeavesClosed;
var
  C: pChnVirt;
begin
  TFakePort.RefuseConfig := True;
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DRV=FAKE DEV=/x PAR=M');
    C^.ChOpen;
    AssertEquals('refused', res_BadSetting, C^.ChResult);
    AssertEquals('the port''s key, as a token', 'PAR=M', C^.ChParamError);
    AssertEquals('closed', CHS_Close, C^.ChReady);
    AssertEquals('port closed again', 'open /x;close;', TFakePort.Log);
    TFakePort.RefuseConfig := False;
    TFakePort.Log := '';
    C^.ChOpen;
    AssertEquals('opens', res_Ok, C^.ChResult);
    AssertEquals('no token after success', '', C^.ChParamError);
  finally
    Dispose(C, Done);
  end;
end;

procedure TTestChnComLogic.TestModemLinesReachThePort;
var
  C: pChnCom;
  Lines: tPortLines;
  Buf: array[0..15] of Byte;
begin
  New(C, Init);
  try
    C^.ChSetParam('DRV=FAKE DEV=/x');
    Lines := [plRing];
    AssertEquals('RTS while closed', res_WrongState, C^.ChSetRts(True));
    AssertEquals('DTR while closed', res_WrongState, C^.ChSetDtr(True));
    AssertEquals('lines while closed', res_WrongState, C^.ChModemLines(Lines));
    AssertTrue('no lines while closed', Lines = []);
    C^.ChOpen;
    AssertEquals(res_Ok, C^.ChResult);
    TFakePort.Log := '';
    AssertEquals(res_Ok, C^.ChSetRts(True));
    AssertEquals(res_Ok, C^.ChSetDtr(False));
    AssertEquals(res_Ok, C^.ChSetRts(False));
    AssertEquals(res_Ok, C^.ChSetDtr(True));
    TFakePort.LineState := [plCts, plCarrier];
    AssertEquals(res_Ok, C^.ChModemLines(Lines));
    AssertTrue('CTS and CD as the port reports them', Lines = [plCts, plCarrier]);
    AssertEquals('each call reaches the port, in order',
      'rts1;dtr0;rts0;dtr1;lines;', TFakePort.Log);
    { once the device failed, the calls say so and leave the port alone }
    TFakePort.ReadFault := res_DeviceLost;
    C^.ChReceiveBuffer(@Buf, SizeOf(Buf));
    C^.ChConnect;
    C^.ChReceiveReady;
    AssertEquals('the fault', res_DeviceLost, C^.ChResult);
    TFakePort.Log := '';
    Lines := [plDsr];
    AssertEquals(res_DeviceLost, C^.ChSetRts(True));
    AssertEquals(res_DeviceLost, C^.ChSetDtr(True));
    AssertEquals(res_DeviceLost, C^.ChModemLines(Lines));
    AssertTrue('no lines from a lost device', Lines = []);
    AssertEquals('nothing reached the port', '', TFakePort.Log);
    C^.ChClose;
    AssertEquals('closed again', res_WrongState, C^.ChSetDtr(False));
  finally
    Dispose(C, Done);
  end;
end;

{$IFDEF WINDOWS}
{ A COM port that is not there: ChErrorText ends with Windows' own text
  for ERROR_FILE_NOT_FOUND (FormatMessage; its words differ between
  Windows and Wine, so only its presence is checked). }
procedure TTestChnComLogic.TestMissingPortSaysTheOsReason;
var
  C: pChnVirt;
  T, Head: string;
begin
  C := ChnCollection^.ChNewInit('COM');
  try
    C^.ChSetParam('DEV=\\.\COM199');
    C^.ChOpen;
    AssertEquals(res_CannotOpen, C^.ChResult);
    T := C^.ChErrorText;
    Head := 'device cannot be opened (DEV=\\.\COM199): ';
    AssertTrue(T, (Pos(Head, T) = 1) and (Length(T) > Length(Head) + 3));
    AssertTrue('no full stop or line break at the end: ' + T, not (T[Length(T)] in ['.', #10, #13]));
  finally
    Dispose(C, Done);
  end;
end;
{$ENDIF}

procedure TTestChnComLogic.TestPortDriverNames;
var
  Names, Seen, Name: string;
  P: Integer;
begin
  RegisterPortDriver('fake', TFakePort);   { again, in lower case: replaces }
  Names := PortDriverNames;
  AssertTrue(Names, (Names <> '') and (Names[1] <> '|') and (Names[Length(Names)] <> '|'));
  Seen := '|';
  P := 1;
  while P <= Length(Names) do
  begin
    Name := '';
    while (P <= Length(Names)) and (Names[P] <> '|') do
    begin
      Name := Name + Names[P];
      Inc(P);
    end;
    Inc(P);
    AssertEquals('upper case', UpperCase(Name), Name);
    AssertTrue(Name + ' is found', FindPortDriver(Name) <> nil);
    AssertEquals(Name + ' once', 0, Pos('|' + Name + '|', Seen));
    Seen := Seen + Name + '|';
  end;
  AssertTrue('the default backend', Pos('|' + DefaultPortDriver + '|', Seen) > 0);
  AssertTrue('the test''s own', Pos('|FAKE|', Seen) > 0);
  {$IFDEF UNIX}
  AssertTrue('pty pairs', Pos('|PTY|', Seen) > 0);
  {$ENDIF}
end;

initialization
  RegisterTest(TTestChnComLogic);
end.
