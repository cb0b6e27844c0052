{ ChnCom - the serial physical layer (NAM=COM), docs/ChnCom.md,
  docs/PROTOCOLS.md sections 2 and 3.

  tChnCom is the serial line on the physical base tChnPhys (unit ChnPhys:
  the receive ring, the transmit pump, the drain at a close, RECON=, the
  program-wide wait, LRB= LSB= IDL=). It opens a TChnPort (unit ChnPort)
  chosen by DRV=, so no OS code lives here. Its own parameters (ChGetParam
  reports them all):

    COM=n     port number: /dev/ttyS<n-1> on Unix, \\.\COMn on Windows
    DEV=path  any device (/dev/ttyUSB0, /dev/pts/3, \\.\COM12); overrides COM
    BD=       rate 50..4000000; one the OS or chip cannot set is an error
    BIT=5..8  STOP=1|2  PAR=N|E|O|M|S
    FLW=NONE|RTSCTS|XONXOFF                   flow control
    RS485=OFF|RTS|KERNEL|AUTO                 RS-485 direction control:
              OFF: none by this layer; RTS: this layer raises RTS before a
              message and drops it once the last bit has left; KERNEL: the
              driver does it, refused if it cannot; AUTO: KERNEL where
              supported, else RTS
    LAT=ms    1..255: the latency timer of a USB adapter; 0 (default)
              leaves it as it is
    RTSB=ms   0..1000: RS485=RTS waits this long after raising RTS before
              the first bit (a transceiver or radio that keys up slowly);
              RS485=KERNEL gives it to the driver (delay_rts_before_send)
    RTSA=ms   0..1000: RTS stays up this long after the last bit
              (delay_rts_after_send with KERNEL)
    TURN=ms   0..10000: a send starts at least this long after the last
              byte received (a slave's turnaround delay, for masters that
              need time to switch their line around)
    IFG=bits  0..10000: a send starts only after the line was idle this
              many bit times (sent or received; FT 1.2 needs 33, i.e.
              three characters of 11 bits, between frames)
              All four without sleeping: the message is held in the
              transmit buffer (ChSendReady says CHS_Sending) and goes out
              from a later poll (ChnPhys), the program-wide wait woken then
    DRV=RTL|SYNAPSE|PTY                       port backend; PTY (unit
              ChnPty, Unix) makes a new pseudo-terminal pair and serves its
              master side
    IRQ=, ADR=, BASE=, PORT=                  DOS hardware keys: accepted,
              reported back, ignored
    LRB= LSB= IDL= RECON=                     the base's (unit ChnPhys)

  With FLW=NONE a full receive ring loses further bytes (counted, then
  res_Overrun); with flow control reading pauses instead. A device that
  cannot be opened, is not accessible or refuses a setting leaves the layer
  closed with res_CannotOpen, res_NoPermission or res_BadSetting and the
  token named; a device lost while open answers res_DeviceLost until
  ChClose + ChOpen, or RECON= reopens it.

  Differences from the SofCon original: DEV=, FLW=, RS485=, IDL=, DRV=,
  RECON=, LAT= are additions of the port; IRQ and port addresses mean nothing here. }
unit ChnCom;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnPort, ChnPhys;

const
  cName = 'COM';
  ComDefaultLRB = PhysDefaultLRB;
  ComDefaultLSB = PhysDefaultLSB;
  ComDefaultIdle = PhysDefaultIdle;

  rs485Off = 0;
  rs485Rts = 1;
  rs485Kernel = 2;
  rs485Auto = 3;

type
  pChnCom = ^tChnCom;
  tChnCom = object(tChnPhys)
    CH_Com     : LongInt;          {< COM= }
    CH_Dev     : tWordString;      {< DEV=, '' = use COM }
    CH_Drv     : string[15];       {< DRV= }
    CH_Rs485   : Byte;             {< RS485=, rs485* }
    CH_Irq     : string[15];       {< IRQ= as given (ignored) }
    CH_DosKey  : string[31];       {< ADR=/BASE=/PORT= token as given (ignored) }
    CH_Lat     : LongInt;          {< LAT= USB adapter latency timer ms, 0 = as it is }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    { --- additions of the port --- }
    { The device path COM=/DEV= stand for now. }
    function  ChDevicePath: ShortString;
  protected
    { The DRV= backend on COM=/DEV=, configured (BD.. FLW, RS485=, LAT=). }
    function  ComOpenPort(out Port: TChnPort): tChResult; virtual;
    { The base's, and the device named when the reconnect begins. }
    function  ComReopenBegins: Boolean; virtual;
  end;

  pAddChnCom = ^tAddChnCom;
  tAddChnCom = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ ' BD=.. BIT=.. STOP=.. PAR=.. FLW=..' as ChGetParam reports them (the
  same as ChnPhys.ComLineText, kept here for programs that use ChnCom). }
function ComLineText(const S: tPortSettings): ShortString;

implementation

uses
  SysUtils, uString,
  ChnPorts;          { links the port drivers of this build (DRV=) }

const
  Rs485Names: array[0..3] of string[6] = ('OFF', 'RTS', 'KERNEL', 'AUTO');

constructor tChnCom.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_Com := 1;
  CH_Dev := '';
  CH_Drv := DefaultPortDriver;
  CH_Rs485 := rs485Off;
  CH_Irq := '';
  CH_DosKey := '';
  CH_Lat := 0;
end;

constructor tChnCom.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;


function tChnCom.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key, Value: string;
  N: LongInt;
  I: Integer;
begin
  Key := ParamKey(S);
  Value := ParamValue(S);
  N := 0;
  I := 0;
  if Key = 'COM' then
  begin
    Result := ParamNum(S, 1, 256, N);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Com := N;
  end
  else if Key = 'DEV' then
  begin
    Result := res_Ok;               { tWordString holds any token }
    if CmdL = cmd_Set then
      CH_Dev := Value;
  end
  else if Key = 'DRV' then
  begin
    if FindPortDriver(Value) = nil then
      Result := ParamBad('one of ' + PortDriverNames)  { not built in, see docs/ChnCom.md }
    else
      Result := res_Ok;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Drv := UpStr(Value);
  end
  else if Key = 'RS485' then
  begin
    Result := ParamChoice(S, 'OFF|RTS|KERNEL|AUTO', I);
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Rs485 := I;
  end
  else if Key = 'LAT' then
    Result := ParamSetNum(S, 0, 255, CmdL, CH_Lat)
  else if Key = 'RTSB' then
    Result := ParamSetNum(S, 0, 1000, CmdL, CH_RtsBefore)
  else if Key = 'RTSA' then
    Result := ParamSetNum(S, 0, 1000, CmdL, CH_RtsAfter)
  else if Key = 'TURN' then
    Result := ParamSetNum(S, 0, 10000, CmdL, CH_Turn)
  else if Key = 'IRQ' then
  begin
    Result := res_Ok;             { DOS only: accepted and ignored }
    if Length(Value) > High(CH_Irq) then
      Result := res_BadParam;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_Irq := Value;
  end
  else if (Key = 'ADR') or (Key = 'BASE') or (Key = 'PORT') then
  begin
    Result := res_Ok;             { DOS port address: accepted and ignored }
    if Length(S) > High(CH_DosKey) then
      Result := res_BadParam;     { the last one given is reported }
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_DosKey := Key + '=' + Value;
  end
  else
  begin
    Result := PhysLineParam(S, CmdL);    { BD BIT STOP PAR FLW }
    if Result = res_UnknownParam then
      Result := inherited ChSetOneParam(S, CmdL);
  end;
end;

function tChnCom.ChOwnParams: tParamStr;
var
  R: string;
begin
  R := inherited ChOwnParams + ' DRV=' + CH_Drv;
  if CH_Dev <> '' then
    R := R + ' DEV=' + CH_Dev
  else
    R := R + ParamText('COM', CH_Com);
  R := R + ComLineText(CH_Set) + ' RS485=' + Rs485Names[CH_Rs485] +
    ComBufferText;
  if CH_Reopen <> 0 then
    R := R + ParamText('RECON', CH_Reopen);
  if CH_Lat <> 0 then
    R := R + ParamText('LAT', CH_Lat);
  if CH_RtsBefore <> 0 then
    R := R + ParamText('RTSB', CH_RtsBefore);
  if CH_RtsAfter <> 0 then
    R := R + ParamText('RTSA', CH_RtsAfter);
  if CH_Turn <> 0 then
    R := R + ParamText('TURN', CH_Turn);
  if CH_Ifg <> 0 then
    R := R + ParamText('IFG', CH_Ifg);
  if CH_Irq <> '' then
    R := R + ' IRQ=' + CH_Irq;
  if CH_DosKey <> '' then
    R := R + ' ' + CH_DosKey;
  Result := R;
end;

function ComLineText(const S: tPortSettings): ShortString;
begin
  Result := ChnPhys.ComLineText(S);
end;

function tChnCom.ChDevicePath: ShortString;
begin
  if CH_Dev <> '' then
    Result := CH_Dev
  else
    Result := ComDevicePath(CH_Com);
end;

function tChnCom.ComOpenPort(out Port: TChnPort): tChResult;
var
  Cls: TChnPortClass;
  R: tChResult;
  Key: ShortString;
begin
  Port := nil;
  Cls := FindPortDriver(CH_Drv);
  if Cls = nil then
  begin
    CH_ParamErr := ChGetParam('DRV');
    Exit(res_BadParam);
  end;
  Port := Cls.Create;
  { the token to name if this fails: the device, then the setting the port
    refused, then RS485= }
  if CH_Drv = 'PTY' then
    Key := 'DRV'
  else if CH_Dev <> '' then
    Key := 'DEV'
  else
    Key := 'COM';
  R := Port.Open(ChDevicePath);
  if R = res_Ok then
  begin
    R := Port.Configure(CH_Set);
    if Port.FailKey <> '' then
      Key := Port.FailKey;
  end;
  if R = res_Ok then
    Key := 'RS485';
  if (R = res_Ok) and (CH_Rs485 <> rs485Off) and (CH_Set.Flow = flowRtsCts) then
    R := res_BadSetting;            { RTS cannot be handshake and direction }
  Port.Rs485BeforeMs := CH_RtsBefore;   { the driver's delays (KERNEL) }
  Port.Rs485AfterMs := CH_RtsAfter;
  if R = res_Ok then
    case CH_Rs485 of
      rs485Off: ;                 { the driver's own setting stays }
      rs485Kernel:
        R := Port.SetKernelRs485(True);
      rs485Rts:
        begin
          CH_RtsToggle := True;
          R := Port.SetRts(False);    { receive direction until we send }
        end;
      rs485Auto:
        if Port.SetKernelRs485(True) <> res_Ok then
        begin
          CH_RtsToggle := True;
          R := Port.SetRts(False);
        end;
    end;
  if (R = res_Ok) and (CH_Lat <> 0) then
  begin
    Key := 'LAT';                   { a driver without the timer refuses it }
    R := Port.SetLatency(CH_Lat);
  end;
  if R <> res_Ok then
  begin
    CH_ParamErr := ChGetParam(Key);
    CH_ErrWhy := Port.OSErrorText;  { 'No such file or directory' }
    Port.Free;                      { closes it }
    Port := nil;
  end;
  Result := R;
end;

function tChnCom.ComReopenBegins: Boolean;
begin
  Result := inherited ComReopenBegins;
  if Result and (CH_ParamErr = '') then
    if CH_Dev <> '' then
      CH_ParamErr := ChGetParam('DEV')
    else
      CH_ParamErr := ChGetParam('COM');
end;

function tAddChnCom.ChInit: pChnVirt;
begin
  Result := New(pChnCom, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnCom, Init(cName)));
end.