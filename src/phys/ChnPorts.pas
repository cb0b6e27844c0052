{ ChnPorts - links the serial port drivers of this build, so that DRV=
  finds them: each registers itself in its initialization (unit ChnPort),
  and tChnCom uses this unit in its implementation only. Nothing else uses
  a backend to get it registered, and no backend uses another.

    Unix      'RTL' (unix/ChnPortUnix, termios), 'PTY' (unix/ChnPty)
    Windows   'RTL' (win/ChnPortWin, Windows API)
    -dCHN_SYNAPSE  'SYNAPSE' (ChnPortSynapse, Synapse's synaser)

  NAM=TCP and NAM=LOOP bring their own drivers with their layers. }
unit ChnPorts;

{$I chn.inc}

interface

implementation

uses
  {$IFDEF UNIX}ChnPortUnix, ChnPty{$ENDIF}
  {$IFDEF WINDOWS}ChnPortWin{$ENDIF}
  {$IFDEF CHN_SYNAPSE}, ChnPortSynapse{$ENDIF};

end.
