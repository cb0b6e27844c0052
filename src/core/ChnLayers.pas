{ ChnLayers - every layer of the library in one uses clause.

  A layer is known to ChnCollection (and so to NAM= in a parameter string)
  only when its unit is linked into the program. A tool that takes its
  parameter string from the user cannot know which layers the user will
  name, so it uses this unit: NAM=COM (with DRV=PTY on Unix), TCP, LOOP,
  TRC, NOISE, DF1, FT1_2, ICS and IEC104 then work in every program. A program that
  links fewer units gets, for a layer it lacks, "unknown layer name
  (NAM=TRC: add ChnTrc to the uses clause)" (ChnVirt.ChUnknownLayerText).

  DRV=PTY (Unix) comes with NAM=COM: ChnCom links the port drivers of the
  OS (ChnPorts). The unit has nothing of its own. }
unit ChnLayers;

{$I chn.inc}

interface

uses
  ChnCom, ChnTcp, ChnLoop, ChnTrc, ChnNoise, ChnDF1, ChnFT1_2, ChnICS, ChnIec104;

implementation

end.
