{ ChnPcccNames - names of the PCCC commands carried by DF1 and the texts of
  their status bytes (STS, EXT STS), shared by the link helper (ChnDF1Link),
  the frame decoder of tools/chndecode and the simulator of tools/df1sim.

  Sources: Rockwell Automation publication 1770-6.5.16, "DF1 Protocol and
  Command Set Reference Manual" (October 1996), chapters 7 (commands) and 8
  (STS and EXT STS); see docs/PROTOCOLS.md. Pure: no I/O, no state. }
unit ChnPcccNames;

{$I chn.inc}

interface

const
  { STS: the high nibble is the remote node's verdict, the low nibble the
    local node's (the interface that could not deliver the command) }
  sts_Ok         = $00;
  sts_IllegalCmd = $10;   {< illegal command or format }
  sts_Address    = $50;   {< addressing problem or memory protect rungs }
  sts_ExtSts     = $F0;   {< the error code is in the EXT STS byte }
  {- EXT STS (the first data byte of a reply with STS $F0) }
  ext_IllegalVal = $01;   {< a field has an illegal value }
  ext_NotUsable  = $06;   {< address doesn't point to something usable }
  ext_WrongSize  = $07;   {< file is wrong size }

{ 'Echo', 'Protected Typed Logical Read (3 addr)' ...; '' when unknown.
  Cmd is the command byte (the reply bit $40 is ignored). }
function PcccCommandName(Cmd, Fnc: Byte): ShortString;
{ The meaning of an STS byte: its local nibble (1..8 in use, 9..F not),
  its remote nibble, or both as 'local: ...; remote: ...'. }
function PcccStsText(Sts: Byte): ShortString;
{ The meaning of an EXT STS byte; 'EXT STS $xx' when unknown. }
function PcccExtStsText(Ext: Byte): ShortString;
{ An error reply's status in one line: 'STS $10: illegal command or
  format', or with STS $F0 and HasExt 'STS $F0, EXT STS $06: address
  doesn't point to something usable'. }
function PcccStatusText(Sts, Ext: Byte; HasExt: Boolean): ShortString;

implementation

uses
  SysUtils;

function PcccCommandName(Cmd, Fnc: Byte): ShortString;
begin
  Result := '';
  case Cmd and not $40 of
    $01: Result := 'Unprotected Read';
    $08: Result := 'Unprotected Write';
    $06:
      case Fnc of
        $00: Result := 'Echo';
        $01: Result := 'Read Diagnostic Counters';
        $03: Result := 'Diagnostic Status';
        $07: Result := 'Reset Diagnostic Counters';
      end;
    $0F:
      case Fnc of
        $A2: Result := 'Protected Typed Logical Read (3 addr)';
        $AA: Result := 'Protected Typed Logical Write (3 addr)';
        $AB: Result := 'Protected Typed Logical Masked Write (3 addr)';
        $A1: Result := 'Protected Typed Logical Read (2 addr)';
        $A9: Result := 'Protected Typed Logical Write (2 addr)';
        $67: Result := 'Typed Write';
        $68: Result := 'Typed Read';
        $00: Result := 'Word Range Write';
        $01: Result := 'Word Range Read';
        $26: Result := 'Read-Modify-Write';
      end;
  end;
end;

{ 1770-6.5.16 chapter 8, "Local STS Error Codes": found by the local node
  (the interface that turned the command around). }
function LocalStsText(Code: Byte): ShortString;
begin
  case Code of
    $01: Result := 'DST node is out of buffer space';
    $02: Result := 'cannot guarantee delivery: the remote node does not ACK the command';
    $03: Result := 'duplicate token holder detected';
    $04: Result := 'local port is disconnected';
    $05: Result := 'application layer timed out waiting for a response';
    $06: Result := 'duplicate node detected';
    $07: Result := 'station is offline';
    $08: Result := 'hardware fault';
  else
    Result := 'unused local STS code';    { 09..0F are not used }
  end;
end;

{ "Remote STS Error Codes": found by the remote node. }
function RemoteStsText(Code: Byte): ShortString;
begin
  case Code of
    $00: Result := 'success';
    $10: Result := 'illegal command or format';
    $20: Result := 'host has a problem and will not communicate';
    $30: Result := 'remote node host is missing, disconnected or shut down';
    $40: Result := 'host could not complete function due to hardware fault';
    $50: Result := 'addressing problem or memory protect rungs';
    $60: Result := 'function not allowed due to command protection selection';
    $70: Result := 'processor is in Program mode';
    $80: Result := 'compatibility mode file missing or communication zone problem';
    $90: Result := 'remote node cannot buffer command';
    $B0: Result := 'remote node problem due to download';
    $F0: Result := 'error code in the EXT STS byte';
  else
    Result := 'unknown STS';
  end;
end;

function PcccStsText(Sts: Byte): ShortString;
begin
  if Sts and $0F = 0 then
    Result := RemoteStsText(Sts and $F0)
  else if Sts and $F0 = 0 then
    Result := LocalStsText(Sts and $0F)
  else
    Result := 'local: ' + LocalStsText(Sts and $0F) + '; remote: ' + RemoteStsText(Sts and $F0);
end;

function PcccExtStsText(Ext: Byte): ShortString;
begin
  case Ext of
    $01: Result := 'a field has an illegal value';
    $02: Result := 'fewer levels specified in address than minimum for any address';
    $03: Result := 'more levels specified in address than system supports';
    $04: Result := 'symbol not found';
    $05: Result := 'symbol is of improper format';
    $06: Result := 'address doesn''t point to something usable';
    $07: Result := 'file is wrong size';
    $08: Result := 'cannot complete request, situation has changed';
    $09: Result := 'data or file is too large';
    $0A: Result := 'transaction size plus word address is too large';
    $0B: Result := 'access denied, improper privilege';
    $10: Result := 'no access';
    $11: Result := 'illegal data type';
    $12: Result := 'invalid parameter or invalid data';
  else
    Result := 'EXT STS $' + IntToHex(Ext, 2);
  end;
end;

function PcccStatusText(Sts, Ext: Byte; HasExt: Boolean): ShortString;
begin
  if (Sts and $F0 = sts_ExtSts) and HasExt then
    Result := 'STS $' + IntToHex(Sts, 2) + ', EXT STS $' + IntToHex(Ext, 2) + ': ' +
      PcccExtStsText(Ext)
  else
    Result := 'STS $' + IntToHex(Sts, 2) + ': ' + PcccStsText(Sts);
end;

end.
