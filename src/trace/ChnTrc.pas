{ ChnTrc - trace layer (NAM=TRC): a transparent layer that can sit between
  any two layers and logs every chunk passing through it.

    'NAM=DF1 NOD=1 DNO=2 NAM=TRC FILE=trace.log NAM=COM DEV=/dev/ttyUSB0'

  Not in the SofCon manuals; an addition of the port. Each chunk
  handed down by ChSend is logged as 'tx', each chunk taken up by ChReceive
  as 'rx', in the RACOM capture format of the RACOM note (see ChnTrcFormat, which
  also reads the log back):

    13:33:33.065 tx   2 | TRC
    1006

  The layer changes nothing: ChSend passes the caller's buffer down
  unchanged and logs it after the layer below took it (a refused send, e.g.
  res_Busy, is not logged); ChReceiveBuffer hands the caller's own buffer
  and size down, so the layer below writes straight into it, never more
  than Size bytes, and ChReceive logs what arrived. States and results are
  those of the layer below. The only cost is formatting and one write per
  chunk.

  Parameters:
    FILE=path|STDERR|STDOUT  where the log goes (default STDERR). A file is
             opened in append mode (created if missing) by ChOpen and
             closed by ChClose; if it cannot be opened, ChOpen gives
             res_CannotOpen and the stack stays closed. FILE= cannot name
             another file while the layer is open (res_WrongState).
    MOD=HEX|DEC|PCAP  bytes in hex groups as in the capture (default), as
             3-digit decimal numbers, or a binary pcap file of link type
             250 (RTAC serial, unit ChnPcap) that Wireshark opens: one
             record per chunk with its time (UTC, microseconds) and
             direction. Switching between PCAP and a text mode is refused
             while open (res_WrongState): the file would mix both. A pcap
             FILE= that is not empty must be a pcap this layer appends to
             (little-endian, link type 250), else ChOpen gives
             res_CannotOpen.
  A failed write to the log is counted in CH_LogErrors and never affects
  the data passing through. }
unit ChnTrc;

{$I chn.inc}

interface

uses
  ChnTypes, ChnVirt, ChnTrcFormat, ChnPcap;

const
  cName = TrcLayer;
  TrcStdErr = 'STDERR';
  TrcStdOut = 'STDOUT';

type
  pChnTrc = ^tChnTrc;
  tChnTrc = object(tChnMiddle)
    CH_File     : tWordString;  {< FILE=: a path, STDERR or STDOUT }
    CH_Mode     : tTrcMode;     {< MOD=HEX|DEC: the text format }
    CH_Pcap     : Boolean;      {< MOD=PCAP: binary pcap instead of text }
    CH_Handle   : THandle;      {< the log while open }
    CH_LogOpen  : Boolean;      {< CH_Handle is valid }
    CH_OwnHandle: Boolean;      {< CH_Handle is a file this layer opened }
    CH_LogErrors: LongInt;      {< log writes that failed }
    CH_PcapTcp  : Boolean;      {< MOD=PCAP as a TCP stream (ChPcapAsTcp) }
    CH_PcapServer: Boolean;     {< ... of which this side is the server }
    CH_Flow     : tPcapTcpFlow; {< its sequence numbers }
    constructor Init;
    constructor ChInitParam(const S: tParamStr);
    destructor  Done; virtual;
    function  ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult; virtual;
    function  ChOwnParams: tParamStr; virtual;
    procedure ChOpen; virtual;
    procedure ChClose; virtual;
    procedure ChConnect; virtual;
    procedure ChSend(Buff: Pointer; Len: Word); virtual;
    procedure ChReceiveBuffer(Buff: Pointer; Size: Word); virtual;
    function  ChReceiveReady: tChState; virtual;
    procedure ChReceive(var Len: Word); virtual;
    { Write one entry to the log (also usable by tools for their own notes). }
    procedure ChTrcLog(Dir: tTrcDir; Buff: Pointer; Len: Word);
    function  PcapStart: Boolean;
    { For the layer above, before ChOpen: MOD=PCAP writes what passes as
      the payload of a TCP stream (link type 228, IPv4 + TCP headers; the
      server side on port 2404, so Wireshark's IEC 104 dissector reads it),
      this side the server when Server. NAM=IEC104 asks for it. }
    procedure ChPcapAsTcp(Server: Boolean);
    function  LogWrite(const Text: AnsiString): Boolean;
  private
    procedure LogClose;
  end;

  pAddChnTrc = ^tAddChnTrc;
  tAddChnTrc = object(tAddChnVirt)
    function ChInit: pChnVirt; virtual;
  end;

{ Milliseconds since local midnight: the time the text log writes. }
function TrcMsOfDay: LongInt;

implementation

uses
  ChnOs, SysUtils, uString;

const
  ModeNames = 'HEX|DEC|PCAP';
  ModeText: array[tTrcMode] of string[3] = ('HEX', 'DEC');

function TrcMsOfDay: LongInt;
var
  H, M, S, Ms: Word;
begin
  DecodeTime(Now, H, M, S, Ms);
  Result := ((LongInt(H) * 60 + M) * 60 + S) * 1000 + Ms;
end;

constructor tChnTrc.Init;
begin
  inherited Init;
  ChSetType(cName);
  CH_File := TrcStdErr;
  CH_Mode := trcHex;
  CH_Pcap := False;
  CH_PcapTcp := False;
  CH_PcapServer := False;
  CH_Handle := 0;
  CH_LogOpen := False;
  CH_OwnHandle := False;
  CH_LogErrors := 0;
end;

constructor tChnTrc.ChInitParam(const S: tParamStr);
begin
  Init;
  ChSetParam(S);
end;

destructor tChnTrc.Done;
begin
  inherited Done;               { closes the stack, and with it the log }
end;

function tChnTrc.ChSetOneParam(const S: tWordString; var CmdL: tCmd): tChResult;
var
  Key, Value: string;
  I: Integer;
begin
  Key := ParamKey(S);
  Value := ParamValue(S);
  I := 0;
  if Key = 'FILE' then
  begin
    if (UpStr(Value) = TrcStdErr) or (UpStr(Value) = TrcStdOut) then
      Value := UpStr(Value);
    Result := res_Ok;
    if (CH_State <> CHS_Close) and (Value <> CH_File) then
      Result := res_WrongState;         { the open log stays what it is }
    if (Result = res_Ok) and (CmdL = cmd_Set) then
      CH_File := Value;
  end
  else if Key = 'MOD' then
  begin
    Result := ParamChoice(S, ModeNames, I);
    { an open file stays text or pcap: mixing both would spoil it }
    if (Result = res_Ok) and (CH_State <> CHS_Close) and ((I = 2) <> CH_Pcap) then
      Result := res_WrongState;
    if (Result = res_Ok) and (CmdL = cmd_Set) then
    begin
      CH_Pcap := I = 2;
      if not CH_Pcap then
        CH_Mode := tTrcMode(I);
    end;
  end
  else
    Result := inherited ChSetOneParam(S, CmdL);
end;

function tChnTrc.ChOwnParams: tParamStr;
begin
  if CH_Pcap then
    Result := inherited ChOwnParams + ' FILE=' + CH_File + ' MOD=PCAP'
  else
    Result := inherited ChOwnParams + ' FILE=' + CH_File + ' MOD=' + ModeText[CH_Mode];
end;

procedure tChnTrc.ChOpen;
begin
  if not ChOpenAllowed then
    Exit;
  { the log first: if it cannot be opened nothing below is opened either }
  CH_OwnHandle := False;
  if CH_File = TrcStdErr then
    CH_Handle := StdErrorHandle
  else if CH_File = TrcStdOut then
    CH_Handle := StdOutputHandle
  else
  begin
    { appended to: several layers (both ends of a test) may share one file }
    CH_Handle := OsOpenAppend(CH_File);
    if CH_Handle = THandle(-1) then
    begin
      CH_Result := res_CannotOpen;
      CH_ParamErr := 'FILE=' + CH_File;
      Exit;
    end;
    CH_OwnHandle := True;
  end;
  CH_LogOpen := True;
  if CH_Pcap and not PcapStart then
  begin
    LogClose;
    CH_Result := res_CannotOpen;
    Exit;
  end;
  inherited ChOpen;
  if CH_Result <> res_Ok then
    LogClose;
end;

{ The log given up: closed when this layer opened it (not STDERR/STDOUT). }
procedure tChnTrc.LogClose;
begin
  if CH_LogOpen and CH_OwnHandle then
    FileClose(CH_Handle);
  CH_LogOpen := False;
  CH_OwnHandle := False;
end;

{ MOD=PCAP at ChOpen: a new or empty file (or a pipe) gets the file header;
  a file with content must be a pcap of ours, which is appended to. }
function tChnTrc.PcapStart: Boolean;
var
  Size: Int64;
  Head: AnsiString;
  Fd: THandle;
begin
  Size := 0;
  if CH_OwnHandle then
    Size := FileSeek(CH_Handle, Int64(0), fsFromEnd);
  CH_Flow.SeqClient := 1;
  CH_Flow.SeqServer := 1;
  if Size <= 0 then
  begin
    if CH_PcapTcp then
      Head := PcapFileHeaderOf(PcapLinkIPv4)
    else
      Head := PcapFileHeaderBytes;
    Result := LogWrite(Head);
    Exit;
  end;
  { read the header through a second descriptor: ours is write-only }
  Result := False;
  Head := '';
  SetLength(Head, SizeOf(tPcapFileHeader));
  Fd := FileOpen(CH_File, fmOpenRead or fmShareDenyNone);
  if Fd = THandle(-1) then
    Exit;
  if FileRead(Fd, Head[1], Length(Head)) = Length(Head) then
    if CH_PcapTcp then
      Result := PcapIsOwnHeaderOf(Head, PcapLinkIPv4)
    else
      Result := PcapIsOwnHeader(Head);
  FileClose(Fd);
end;

procedure tChnTrc.ChPcapAsTcp(Server: Boolean);
begin
  CH_PcapTcp := True;
  CH_PcapServer := Server;
end;

function tChnTrc.LogWrite(const Text: AnsiString): Boolean;
var
  Written, N: LongInt;
begin
  if CH_OwnHandle then
    OsBeforeAppend(CH_Handle);
  Written := 0;
  while Written < Length(Text) do        { a pipe may take it in pieces }
  begin
    N := FileWrite(CH_Handle, Text[Written + 1], Length(Text) - Written);
    if N <= 0 then
      Exit(False);
    Inc(Written, N);
  end;
  Result := True;
end;

procedure tChnTrc.ChClose;
begin
  inherited ChClose;
  LogClose;
end;

procedure tChnTrc.ChConnect;
begin
  inherited ChConnect;
  { the base gave the layer below CH_LowBuf; it gets the caller's buffer }
  if (CH_Result = res_Ok) and (CH_Low <> nil) and (CH_RBuff <> nil) then
    CH_Low^.ChReceiveBuffer(CH_RBuff, CH_RSize);
end;

procedure tChnTrc.ChTrcLog(Dir: tTrcDir; Buff: Pointer; Len: Word);
var
  Text: AnsiString;
  Sec, USec: LongWord;
begin
  if not CH_LogOpen then
    Exit;
  if CH_Pcap then
  begin
    OsUtcNow(Sec, USec);
    if CH_PcapTcp then
      Text := PcapTcpRecordBytes(Sec, USec, (Dir = trcTx) = CH_PcapServer, PcapIec104Port,
        CH_Flow, Buff^, Len)
    else
      Text := PcapRecordBytes(Sec, USec, Dir, Buff^, Len);
  end
  else
    Text := TrcFormat(TrcMsOfDay, Dir, Buff^, Len, CH_Mode, CH_Name);
  { one write per entry: layers sharing a file (O_APPEND) do not interleave }
  if not LogWrite(Text) then
    Inc(CH_LogErrors);
end;

procedure tChnTrc.ChSend(Buff: Pointer; Len: Word);
begin
  inherited ChSend(Buff, Len);    { checks state and Len, then ChLowSend }
  if CH_SResult = res_Ok then
    ChTrcLog(trcTx, Buff, Len);
end;

procedure tChnTrc.ChReceiveBuffer(Buff: Pointer; Size: Word);
begin
  inherited ChReceiveBuffer(Buff, Size);
  { the layer below always holds exactly the caller's buffer, so no byte
    is copied and none can be written past it }
  if CH_Low <> nil then
    CH_Low^.ChReceiveBuffer(CH_RBuff, CH_RSize);
end;

function tChnTrc.ChReceiveReady: tChState;
begin
  if (CH_State <> CHS_Connect) or (CH_Low = nil) then
  begin
    CH_RCtrl := CHS_RecInactive;
    Exit(CHS_RecInactive);
  end;
  Result := CH_Low^.ChReceiveReady;
  CH_RResult := CH_Low^.ChReceiveResult;
  CH_RCtrl := Result;
end;

procedure tChnTrc.ChReceive(var Len: Word);
begin
  if not ChReceiveAllowed(Len) then
    Exit;
  CH_Low^.ChReceive(Len);
  CH_RResult := CH_Low^.ChReceiveResult;
  if Len > CH_RSize then
    Len := CH_RSize;             { never log (or report) past the buffer }
  if Len > 0 then
    ChTrcLog(trcRx, CH_RBuff, Len);
  CH_RCtrl := CHS_Receiving;
end;

function tAddChnTrc.ChInit: pChnVirt;
begin
  Result := New(pChnTrc, Init);
end;

initialization
  ChnCollection^.Insert(New(pAddChnTrc, Init(cName)));
end.
