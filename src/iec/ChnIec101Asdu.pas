{ ChnIec101Asdu - the application service data units (ASDUs) of
  IEC 60870-5-101, without I/O: encode and decode the data unit identifier
  and the information objects of every type the library knows, with the
  application parameters every IEC 101 station has.

  Layout (IEC 60870-5-101 clause 7.1, IEC 60870-5-104 clause 7.2 keeps it):
    TI  VSQ  COT [OA]  CA [CA]  object...
    object = IOA (1..3 octets) element [time tag]     VSQ bit 7 (SQ) = 0
    IOA element element ...                           SQ = 1: IOA of the first,
                                                      the others follow it
  Every multi-octet field travels little-endian. COT octet 1: cause 0..63,
  bit 6 P/N (negative), bit 7 T (test); octet 2 (when COT is two octets) the
  originator address. Type identifications (clause 7.2.1.1): monitoring
  1..21 and 30..40, end of initialisation 70, commands 45..51 and 58..64,
  system 100..107, parameters 110..113; the element layouts are those of
  clause 7.3. Time tags: CP24Time2a (ms, minute), CP56Time2a (ms, minute,
  hour, day of month and of week, month, year) with IV and SU (their
  octets and checks are ChnIecTime's, their names here too), CP16Time2a
  (ms) for elapsed, duration and delay times.

  One information object of any type is one tIecObject: the fields the
  type's kind uses (IecTypeKind, listed at tIecKind) are filled, the others
  are 0. Decoding is permissive where the standard leaves room (any cause,
  any qualifier, reserved bits dropped); encoding refuses what cannot be
  sent (a value outside its type's range, an IOA too large for its size).

  Every refusal is a result code (res_Asdu*, texts registered for the
  layer name Iec101Layer) and a text that names the part that is wrong.
  Nothing here reads or writes past the arrays it is given.
  File transfer (120..127) has its own codec, ChnIecFile, on the
  identifier, IOA and time helpers below. Not covered: the types of IEC 60870-5-104
  alone (the commands with CP56Time2a, 58..64, and C_TS_TA_1, 107, are
  here: IEC 101 stations and lib60870 use them too). }
unit ChnIec101Asdu;

{$I chn.inc}

interface

uses
  ChnTypes, ChnIecTime;

const
  Iec101Layer = 'IEC101';   {< ChResultText(R, Iec101Layer) }

  res_AsduParam  = res_Proto;       {< application parameters impossible }
  res_AsduShort  = res_Proto + 1;   {< shorter than the data unit identifier }
  res_AsduType   = res_Proto + 2;   {< unknown type identification }
  res_AsduLength = res_Proto + 3;   {< length does not fit type and count, or the buffer }
  res_AsduCount  = res_Proto + 4;   {< number of objects 0, above 127 or above the array }
  res_AsduIoa    = res_Proto + 5;   {< IOA out of range for its size or the sequence }
  res_AsduValue  = res_Proto + 6;   {< a value, cause or address out of range (encode) }

  IecMaxObjects = 127;               {< VSQ number field }
  IecMaxAsdu    = 253;               {< an ASDU never exceeds this (FT 1.2 L = 255, minus C and A) }

  { Type identifications (IEC 60870-5-101 table 8 ...) }
  M_SP_NA_1 = 1;   M_SP_TA_1 = 2;   M_DP_NA_1 = 3;   M_DP_TA_1 = 4;
  M_ST_NA_1 = 5;   M_ST_TA_1 = 6;   M_BO_NA_1 = 7;   M_BO_TA_1 = 8;
  M_ME_NA_1 = 9;   M_ME_TA_1 = 10;  M_ME_NB_1 = 11;  M_ME_TB_1 = 12;
  M_ME_NC_1 = 13;  M_ME_TC_1 = 14;  M_IT_NA_1 = 15;  M_IT_TA_1 = 16;
  M_EP_TA_1 = 17;  M_EP_TB_1 = 18;  M_EP_TC_1 = 19;  M_PS_NA_1 = 20;
  M_ME_ND_1 = 21;
  M_SP_TB_1 = 30;  M_DP_TB_1 = 31;  M_ST_TB_1 = 32;  M_BO_TB_1 = 33;
  M_ME_TD_1 = 34;  M_ME_TE_1 = 35;  M_ME_TF_1 = 36;  M_IT_TB_1 = 37;
  M_EP_TD_1 = 38;  M_EP_TE_1 = 39;  M_EP_TF_1 = 40;
  C_SC_NA_1 = 45;  C_DC_NA_1 = 46;  C_RC_NA_1 = 47;  C_SE_NA_1 = 48;
  C_SE_NB_1 = 49;  C_SE_NC_1 = 50;  C_BO_NA_1 = 51;
  C_SC_TA_1 = 58;  C_DC_TA_1 = 59;  C_RC_TA_1 = 60;  C_SE_TA_1 = 61;
  C_SE_TB_1 = 62;  C_SE_TC_1 = 63;  C_BO_TA_1 = 64;
  M_EI_NA_1 = 70;
  C_IC_NA_1 = 100; C_CI_NA_1 = 101; C_RD_NA_1 = 102; C_CS_NA_1 = 103;
  C_TS_NA_1 = 104; C_RP_NA_1 = 105; C_CD_NA_1 = 106; C_TS_TA_1 = 107;
  P_ME_NA_1 = 110; P_ME_NB_1 = 111; P_ME_NC_1 = 112; P_AC_NA_1 = 113;

  { Causes of transmission (clause 7.2.3) }
  Cot_Periodic     = 1;    Cot_Background   = 2;   Cot_Spontaneous = 3;
  Cot_Initialized  = 4;    Cot_Request      = 5;   Cot_Activation  = 6;
  Cot_ActCon       = 7;    Cot_Deactivation = 8;   Cot_DeactCon    = 9;
  Cot_ActTerm      = 10;   Cot_ReturnRemote = 11;  Cot_ReturnLocal = 12;
  Cot_File         = 13;
  Cot_Interrogated = 20;   {< station interrogation; group g is 20 + g (1..16) }
  Cot_CounterReq   = 37;   {< general counter request; group g is 37 + g (1..4) }
  Cot_UnknownType  = 44;   Cot_UnknownCause = 45;
  Cot_UnknownCa    = 46;   Cot_UnknownIoa   = 47;

  {- Qualifier of interrogation (QOI) and of counter interrogation (QCC) }
  Qoi_Station = 20;        {< group g (1..16) is 20 + g }
  Qcc_General = 5;         {< RQT: groups 1..4, 5 = general }
  Qcc_Read    = $00;       {< FRZ (bits 6-7): read without freeze or reset }
  Qcc_Freeze  = $40;       {< freeze without reset }
  Qcc_FreezeReset = $80;   {< freeze with reset }
  Qcc_Reset   = $C0;       {< counter reset }
  Qrp_General = 1;         {< QRP: general reset of process }
  Qrp_Events  = 2;         {< reset of pending time-tagged events }
  {- COI, the cause of an end of initialisation (M_EI_NA_1, COT 4) }
  Coi_PowerOn     = 0;     {< local power switch on }
  Coi_ManualReset = 1;     {< local manual reset }
  Coi_RemoteReset = 2;     {< remote reset (C_RP_NA_1) }
  Coi_LocalChange = $80;   {< BS1: initialisation after a change of local parameters }
  Fbp_Test    = $55AA;     {< fixed test bit pattern of C_TS_NA_1 }
  {- QPM of parameters of measured values (P_ME_NA_1..P_ME_NC_1): KPA in
    bits 0-5, LPC bit 6, POP bit 7 }
  Kpa_Threshold = 1;       {< threshold value (a deadband on spontaneous reports) }
  Kpa_Smoothing = 2;       {< smoothing factor (filter time constant) }
  Kpa_Low       = 3;       {< low limit for transmission of measured values }
  Kpa_High      = 4;       {< high limit for transmission of measured values }
  Qpm_LocalChange = $40;   {< LPC: local parameter change }
  Qpm_NotInOperation = $80; {< POP: parameter not in operation }
  {- QPA of parameter activation (P_AC_NA_1): COT 6 activates, 8 deactivates }
  Qpa_Loaded    = 1;       {< the parameters loaded before (IOA 0: all) }
  Qpa_Object    = 2;       {< the parameters of the addressed object }
  Qpa_Cyclic    = 3;       {< persistent cyclic or periodic transmission of the object }

  {- Quality bits (SIQ, DIQ, QDS, SEP, QDP, BCR): the Quality field keeps
    them in their places on the wire }
  Q_Overflow    = $01;     {< OV (QDS) }
  Q_ElapsedInv  = $08;     {< EI (SEP, QDP) }
  Q_Blocked     = $10;     {< BL }
  Q_Substituted = $20;     {< SB; in a BCR: CY, carry }
  Q_NotTopical  = $40;     {< NT; in a BCR: CA, adjusted }
  Q_Invalid     = $80;     {< IV }

type
  { The application parameters: octets of the cause of transmission (1, or
    2 with the originator address), of the common address (1 or 2) and of
    the information object address (1, 2 or 3). }
  tIecParams = packed record
    CotSize: Byte;
    CaSize : Byte;
    IoaSize: Byte;
  end;

  { A CP56Time2a, or the ms and minute (and IV) of a CP24Time2a
    (ChnIecTime); IecTimeCheck tells a real date. }
  tIecTime = ChnIecTime.tIecTime;
  tIecTimeKind = ChnIecTime.tIecTimeKind;

const
  tkNone = ChnIecTime.tkNone;
  tkCP24 = ChnIecTime.tkCP24;
  tkCP56 = ChnIecTime.tkCP56;

type

  { What the element of a type holds, and which fields of tIecObject it
    fills (Quality always: the quality bits of the element, 0 if none):
      ikSingle        Int 0/1                          (SIQ)
      ikDouble        Int state 0..3                   (DIQ)
      ikStep          Int -64..63, Transient           (VTI QDS)
      ikBits          Bits                             (BSI QDS)
      ikNormal        Number -1 <= x < 1, Int raw      (NVA [QDS])
      ikScaled        Int -32768..32767                (SVA QDS)
      ikFloat         Number                           (R32 QDS)
      ikCounter       Int (32-bit signed), Seq 0..31   (BCR; Quality CY CA IV)
      ikProtection    Int event state 0..3, Elapsed    (SEP CP16)
      ikStartEvents   Bits (GS SL1 SL2 SL3 SIE SRD), Elapsed   (SPE QDP CP16)
      ikOutputCircuit Bits (GC CL1 CL2 CL3), Elapsed   (OCI QDP CP16)
      ikPacked        Bits: status low word, change detection high word (SCD QDS)
      ikEndInit       Int: the COI octet (cause 0..127, +128 after a local change)
      ikSingleCmd     Int 0/1, Qu 0..31, Select        (SCO)
      ikDoubleCmd     Int state 0..3, Qu, Select       (DCO)
      ikStepCmd       Int 0..3 (1 lower, 2 higher), Qu, Select   (RCO)
      ikSetNormal     Number, Int raw, Qu = QL 0..127, Select   (NVA QOS)
      ikSetScaled     Int, Qu = QL, Select             (SVA QOS)
      ikSetFloat      Number, Qu = QL, Select          (R32 QOS)
      ikBitsCmd       Bits                             (BSI)
      ikQualifier     Int: QOI, QCC, QRP or QPA octet
      ikRead          nothing (the IOA is the request)
      ikClock         Time only                        (CP56)
      ikTest          Int: the FBP word ($55AA)
      ikDelay         Elapsed: the delay in ms         (CP16)
      ikTestTime      Int: the TSC counter, Time       (TSC CP56)
      ikParNormal     Number, Int raw, Qu = QPM octet  (NVA QPM)
      ikParScaled     Int, Qu = QPM                    (SVA QPM)
      ikParFloat      Number, Qu = QPM                 (R32 QPM)
    Time-tagged types (IecTypeTime <> tkNone) fill Time as well. }
  tIecKind = (ikNone, ikSingle, ikDouble, ikStep, ikBits, ikNormal, ikScaled,
    ikFloat, ikCounter, ikProtection, ikStartEvents, ikOutputCircuit, ikPacked,
    ikEndInit, ikSingleCmd, ikDoubleCmd, ikStepCmd, ikSetNormal, ikSetScaled,
    ikSetFloat, ikBitsCmd, ikQualifier, ikRead, ikClock, ikTest, ikDelay,
    ikTestTime, ikParNormal, ikParScaled, ikParFloat);

  { One information object (37 octets, offsets tested). }
  tIecObject = packed record
    Ioa      : LongWord;  {< information object address }
    Int      : LongInt;   {< the integer value (see tIecKind) }
    Bits     : LongWord;  {< bitstrings, packed points, event bits }
    Number   : Double;    {< normalized fraction, short float }
    Quality  : Byte;      {< quality bits as on the wire, 0 if the type has none }
    Transient: Boolean;   {< step position in transient state (VTI bit 7) }
    Seq      : Byte;      {< integrated totals: sequence number 0..31 }
    Select   : Boolean;   {< command: select (True) or execute (False) }
    Qu       : Byte;      {< command qualifier QU/QL, parameter QPM }
    Elapsed  : Word;      {< CP16Time2a: elapsed, duration or delay time, ms }
    Time     : tIecTime;  {< time tag of time-tagged types }
  end;
  pIecObject = ^tIecObject;

  { The data unit identifier of an ASDU (13 octets, offsets tested). }
  tIecAsdu = packed record
    Ti      : Byte;       {< type identification }
    Sq      : Boolean;    {< VSQ bit 7: objects in a sequence, one IOA }
    Count   : Byte;       {< number of information objects 1..127 }
    Cot     : Byte;       {< cause of transmission 0..63 }
    Negative: Boolean;    {< P/N bit: negative confirmation }
    Test    : Boolean;    {< T bit }
    Oa      : Byte;       {< originator address (0 when COT is one octet) }
    Ca      : Word;       {< common address of ASDU }
    HeadLen : Byte;       {< decode: octets of the identifier (TI..CA) }
    ElemLen : Byte;       {< decode: octets of one element (after the IOA) }
    Len     : Word;       {< decode: octets of the whole ASDU }
  end;

{ The parameters of lib60870 and most stations: COT 2, CA 2, IOA 3. }
function IecDefaultParams: tIecParams;
{ res_Ok, or res_AsduParam with Err naming the size that is wrong. }
function IecCheckParams(const P: tIecParams; out Err: ShortString): tChResult;
{ Octets of TI VSQ COT CA under P. }
function IecHeadLen(const P: tIecParams): Word;
{ The largest IOA (255, 65535, 16777215) and common address (255, 65535). }
function IecMaxIoa(const P: tIecParams): LongWord;
function IecMaxCa(const P: tIecParams): Word;

{ The standard name ('M_SP_NA_1'); '' for an unknown type. }
function IecTypeName(Ti: Byte): ShortString;
{ The type of a name (case ignored); 0 when unknown. }
function IecTypeByName(const Name: ShortString): Byte;
{ ikNone for an unknown type. }
function IecTypeKind(Ti: Byte): tIecKind;
function IecTypeTime(Ti: Byte): tIecTimeKind;
{ Octets of one element of the type after its IOA, time tag included;
  -1 for an unknown type. }
function IecElementSize(Ti: Byte): LongInt;
{ Monitoring direction (1..40, 70): sent by the controlled station. }
function IecIsMonitor(Ti: Byte): Boolean;
{ 'ACT_CON', 'INTERROGATED_BY_GROUP_3', 'UNKNOWN_IOA' ...; 'COT_n' otherwise. }
function IecCotName(Cot: Byte): ShortString;

{ Encode an ASDU: the identifier H (Ti, Sq, Count, Cot, Negative, Test, Oa,
  Ca; HeadLen, ElemLen, Len ignored) and H.Count objects of Objs into Buf.
  With Sq the objects' IOAs must follow each other (Objs[0].Ioa + i).
  res_AsduValue / res_AsduIoa / res_AsduCount / res_AsduType /
  res_AsduParam with Err naming the object and field; res_AsduLength when
  the ASDU does not fit in Buf or is longer than IecMaxAsdu. }
function IecEncodeAsdu(const P: tIecParams; const H: tIecAsdu; const Objs: array of tIecObject;
  var Buf: array of Byte; out Len: Word; out Err: ShortString): tChResult;
{ One object, not a sequence: the form of every command and confirmation. }
function IecEncodeOne(const P: tIecParams; Ti, Cot: Byte; Ca: Word; const Obj: tIecObject;
  var Buf: array of Byte; out Len: Word; out Err: ShortString): tChResult;

{ Decode the identifier of the ASDU in Buf[0..Len-1] and check that its
  length is exactly what its type and count need: res_AsduShort,
  res_AsduType, res_AsduCount (number 0), res_AsduLength (Err: the octets
  needed and got), res_AsduIoa (a sequence running past the largest IOA),
  res_AsduParam. Len above Length(Buf) is res_AsduLength. With
  res_AsduType H holds the identifier all the same (Ti ... Ca, HeadLen,
  Len): the codec of another family of types (ChnIecFile) takes it on. }
function IecDecodeHeader(const P: tIecParams; const Buf: array of Byte; Len: Word;
  out H: tIecAsdu; out Err: ShortString): tChResult;
{ Object Index (0..H.Count-1) of an ASDU whose header IecDecodeHeader
  accepted (res_AsduCount for an index outside). }
function IecDecodeObject(const P: tIecParams; const H: tIecAsdu; const Buf: array of Byte;
  Index: LongInt; out Obj: tIecObject): tChResult;
{ Header and every object into Objs; res_AsduCount when Objs is shorter
  than the count. }
function IecDecodeAsdu(const P: tIecParams; const Buf: array of Byte; Len: Word;
  out H: tIecAsdu; var Objs: array of tIecObject; out Err: ShortString): tChResult;

{ ChnIecTime's, for programs that use this unit alone: the fields of a
  time from a TDateTime (DayOfWeek filled, IV and SU clear) and back;
  IecTimeToDateTime is False for a time that is no date (month 13, minute
  60 ...), DT then 0. A CP24Time2a gives only minutes and ms: use
  IecTimeCheck with Short. }
function IecTimeFromDateTime(DT: TDateTime): tIecTime;
function IecTimeToDateTime(const T: tIecTime; out DT: TDateTime): Boolean;
{ res_Ok for a real time (Short: only Msec and Minute), else res_AsduValue
  with Err naming the field (IecTimeValid as a result code). }
function IecTimeCheck(const T: tIecTime; Short: Boolean; out Err: ShortString): tChResult;

{ A zero object (Quality 0, Time 0) with the IOA given. }
function IecObject(Ioa: LongWord): tIecObject;

{ The pieces other codecs of this family (file transfer) build on:
  IecPutIdent writes TI VSQ COT [OA] CA of H into Buf (At: the octets
  written) after checking cause, originator and common address (Err names
  the field); IecPutIoa / IecGetIoa one IOA of P.IoaSize octets at At;
  IecPutTime / IecGetTime a CP24Time2a or CP56Time2a at At (ChnIecTime's).
  The callers check that Buf is long enough. }
function IecPutIdent(const P: tIecParams; const H: tIecAsdu; var Buf: array of Byte;
  out At: Word; out Err: ShortString): tChResult;
procedure IecPutIoa(const P: tIecParams; Ioa: LongWord; var Buf: array of Byte; At: LongInt);
function IecGetIoa(const P: tIecParams; const Buf: array of Byte; At: LongInt): LongWord;
procedure IecPutTime(const T: tIecTime; K: tIecTimeKind; var B: array of Byte; At: LongInt);
procedure IecGetTime(const B: array of Byte; At: LongInt; K: tIecTimeKind; out T: tIecTime);
{ Set the cause and P/N bit of the ASDU in Buf (the test bit, the OA and
  the rest stay): an activation answered as its confirmation or
  termination in place. False (nothing changed) when Len < 3 or Cot > 63. }
function IecSetCot(var Buf: array of Byte; Len: Word; Cot: Byte; Negative: Boolean): Boolean;

implementation

uses
  SysUtils, Math;

type
  tTypeInfo = record
    Ti  : Byte;
    Name: string[9];
    Kind: tIecKind;
    Time: tIecTimeKind;
    Size: Byte;       { element octets after the IOA, time tag included }
  end;

const
  Types: array[0..58] of tTypeInfo = (
    (Ti: 1;   Name: 'M_SP_NA_1'; Kind: ikSingle;        Time: tkNone; Size: 1),
    (Ti: 2;   Name: 'M_SP_TA_1'; Kind: ikSingle;        Time: tkCP24; Size: 4),
    (Ti: 3;   Name: 'M_DP_NA_1'; Kind: ikDouble;        Time: tkNone; Size: 1),
    (Ti: 4;   Name: 'M_DP_TA_1'; Kind: ikDouble;        Time: tkCP24; Size: 4),
    (Ti: 5;   Name: 'M_ST_NA_1'; Kind: ikStep;          Time: tkNone; Size: 2),
    (Ti: 6;   Name: 'M_ST_TA_1'; Kind: ikStep;          Time: tkCP24; Size: 5),
    (Ti: 7;   Name: 'M_BO_NA_1'; Kind: ikBits;          Time: tkNone; Size: 5),
    (Ti: 8;   Name: 'M_BO_TA_1'; Kind: ikBits;          Time: tkCP24; Size: 8),
    (Ti: 9;   Name: 'M_ME_NA_1'; Kind: ikNormal;        Time: tkNone; Size: 3),
    (Ti: 10;  Name: 'M_ME_TA_1'; Kind: ikNormal;        Time: tkCP24; Size: 6),
    (Ti: 11;  Name: 'M_ME_NB_1'; Kind: ikScaled;        Time: tkNone; Size: 3),
    (Ti: 12;  Name: 'M_ME_TB_1'; Kind: ikScaled;        Time: tkCP24; Size: 6),
    (Ti: 13;  Name: 'M_ME_NC_1'; Kind: ikFloat;         Time: tkNone; Size: 5),
    (Ti: 14;  Name: 'M_ME_TC_1'; Kind: ikFloat;         Time: tkCP24; Size: 8),
    (Ti: 15;  Name: 'M_IT_NA_1'; Kind: ikCounter;       Time: tkNone; Size: 5),
    (Ti: 16;  Name: 'M_IT_TA_1'; Kind: ikCounter;       Time: tkCP24; Size: 8),
    (Ti: 17;  Name: 'M_EP_TA_1'; Kind: ikProtection;    Time: tkCP24; Size: 6),
    (Ti: 18;  Name: 'M_EP_TB_1'; Kind: ikStartEvents;   Time: tkCP24; Size: 7),
    (Ti: 19;  Name: 'M_EP_TC_1'; Kind: ikOutputCircuit; Time: tkCP24; Size: 7),
    (Ti: 20;  Name: 'M_PS_NA_1'; Kind: ikPacked;        Time: tkNone; Size: 5),
    (Ti: 21;  Name: 'M_ME_ND_1'; Kind: ikNormal;        Time: tkNone; Size: 2),
    (Ti: 30;  Name: 'M_SP_TB_1'; Kind: ikSingle;        Time: tkCP56; Size: 8),
    (Ti: 31;  Name: 'M_DP_TB_1'; Kind: ikDouble;        Time: tkCP56; Size: 8),
    (Ti: 32;  Name: 'M_ST_TB_1'; Kind: ikStep;          Time: tkCP56; Size: 9),
    (Ti: 33;  Name: 'M_BO_TB_1'; Kind: ikBits;          Time: tkCP56; Size: 12),
    (Ti: 34;  Name: 'M_ME_TD_1'; Kind: ikNormal;        Time: tkCP56; Size: 10),
    (Ti: 35;  Name: 'M_ME_TE_1'; Kind: ikScaled;        Time: tkCP56; Size: 10),
    (Ti: 36;  Name: 'M_ME_TF_1'; Kind: ikFloat;         Time: tkCP56; Size: 12),
    (Ti: 37;  Name: 'M_IT_TB_1'; Kind: ikCounter;       Time: tkCP56; Size: 12),
    (Ti: 38;  Name: 'M_EP_TD_1'; Kind: ikProtection;    Time: tkCP56; Size: 10),
    (Ti: 39;  Name: 'M_EP_TE_1'; Kind: ikStartEvents;   Time: tkCP56; Size: 11),
    (Ti: 40;  Name: 'M_EP_TF_1'; Kind: ikOutputCircuit; Time: tkCP56; Size: 11),
    (Ti: 45;  Name: 'C_SC_NA_1'; Kind: ikSingleCmd;     Time: tkNone; Size: 1),
    (Ti: 46;  Name: 'C_DC_NA_1'; Kind: ikDoubleCmd;     Time: tkNone; Size: 1),
    (Ti: 47;  Name: 'C_RC_NA_1'; Kind: ikStepCmd;       Time: tkNone; Size: 1),
    (Ti: 48;  Name: 'C_SE_NA_1'; Kind: ikSetNormal;     Time: tkNone; Size: 3),
    (Ti: 49;  Name: 'C_SE_NB_1'; Kind: ikSetScaled;     Time: tkNone; Size: 3),
    (Ti: 50;  Name: 'C_SE_NC_1'; Kind: ikSetFloat;      Time: tkNone; Size: 5),
    (Ti: 51;  Name: 'C_BO_NA_1'; Kind: ikBitsCmd;       Time: tkNone; Size: 4),
    (Ti: 58;  Name: 'C_SC_TA_1'; Kind: ikSingleCmd;     Time: tkCP56; Size: 8),
    (Ti: 59;  Name: 'C_DC_TA_1'; Kind: ikDoubleCmd;     Time: tkCP56; Size: 8),
    (Ti: 60;  Name: 'C_RC_TA_1'; Kind: ikStepCmd;       Time: tkCP56; Size: 8),
    (Ti: 61;  Name: 'C_SE_TA_1'; Kind: ikSetNormal;     Time: tkCP56; Size: 10),
    (Ti: 62;  Name: 'C_SE_TB_1'; Kind: ikSetScaled;     Time: tkCP56; Size: 10),
    (Ti: 63;  Name: 'C_SE_TC_1'; Kind: ikSetFloat;      Time: tkCP56; Size: 12),
    (Ti: 64;  Name: 'C_BO_TA_1'; Kind: ikBitsCmd;       Time: tkCP56; Size: 11),
    (Ti: 70;  Name: 'M_EI_NA_1'; Kind: ikEndInit;       Time: tkNone; Size: 1),
    (Ti: 100; Name: 'C_IC_NA_1'; Kind: ikQualifier;     Time: tkNone; Size: 1),
    (Ti: 101; Name: 'C_CI_NA_1'; Kind: ikQualifier;     Time: tkNone; Size: 1),
    (Ti: 102; Name: 'C_RD_NA_1'; Kind: ikRead;          Time: tkNone; Size: 0),
    (Ti: 103; Name: 'C_CS_NA_1'; Kind: ikClock;         Time: tkCP56; Size: 7),
    (Ti: 104; Name: 'C_TS_NA_1'; Kind: ikTest;          Time: tkNone; Size: 2),
    (Ti: 105; Name: 'C_RP_NA_1'; Kind: ikQualifier;     Time: tkNone; Size: 1),
    (Ti: 106; Name: 'C_CD_NA_1'; Kind: ikDelay;         Time: tkNone; Size: 2),
    (Ti: 107; Name: 'C_TS_TA_1'; Kind: ikTestTime;      Time: tkCP56; Size: 9),
    (Ti: 110; Name: 'P_ME_NA_1'; Kind: ikParNormal;     Time: tkNone; Size: 3),
    (Ti: 111; Name: 'P_ME_NB_1'; Kind: ikParScaled;     Time: tkNone; Size: 3),
    (Ti: 112; Name: 'P_ME_NC_1'; Kind: ikParFloat;      Time: tkNone; Size: 5),
    (Ti: 113; Name: 'P_AC_NA_1'; Kind: ikQualifier;     Time: tkNone; Size: 1));

var
  TypeIndex: array[Byte] of ShortInt;   { Types[] index of a TI, -1 unknown }

function Info(Ti: Byte; out I: Integer): Boolean;
begin
  I := TypeIndex[Ti];
  Result := I >= 0;
end;

function IecDefaultParams: tIecParams;
begin
  Result.CotSize := 2;
  Result.CaSize := 2;
  Result.IoaSize := 3;
end;

function IecCheckParams(const P: tIecParams; out Err: ShortString): tChResult;
begin
  Err := '';
  if not (P.CotSize in [1, 2]) then
    Err := 'COT size ' + IntToStr(P.CotSize) + ' (1 or 2 octets)'
  else if not (P.CaSize in [1, 2]) then
    Err := 'common address size ' + IntToStr(P.CaSize) + ' (1 or 2 octets)'
  else if not (P.IoaSize in [1..3]) then
    Err := 'IOA size ' + IntToStr(P.IoaSize) + ' (1, 2 or 3 octets)';
  if Err = '' then
    Result := res_Ok
  else
    Result := res_AsduParam;
end;

function IecHeadLen(const P: tIecParams): Word;
begin
  Result := 2 + P.CotSize + P.CaSize;
end;

function IecMaxIoa(const P: tIecParams): LongWord;
begin
  case P.IoaSize of
    1: Result := $FF;
    2: Result := $FFFF;
  else
    Result := $FFFFFF;
  end;
end;

function IecMaxCa(const P: tIecParams): Word;
begin
  if P.CaSize = 1 then
    Result := $FF
  else
    Result := $FFFF;
end;

const
  NoType: tTypeInfo = (Ti: 0; Name: ''; Kind: ikNone; Time: tkNone; Size: 0);

{ The table entry of a type; NoType when unknown. }
function TypeEntry(Ti: Byte): tTypeInfo;
var
  I: Integer;
begin
  if Info(Ti, I) then
    Result := Types[I]
  else
    Result := NoType;
end;

function IecTypeName(Ti: Byte): ShortString;
begin
  Result := TypeEntry(Ti).Name;
end;

function IecTypeByName(const Name: ShortString): Byte;
var
  I: Integer;
  U: ShortString;
begin
  U := UpperCase(Trim(Name));
  for I := Low(Types) to High(Types) do
    if Types[I].Name = U then
      Exit(Types[I].Ti);
  Result := 0;
end;

function IecTypeKind(Ti: Byte): tIecKind;
begin
  Result := TypeEntry(Ti).Kind;
end;

function IecTypeTime(Ti: Byte): tIecTimeKind;
begin
  Result := TypeEntry(Ti).Time;
end;

function IecElementSize(Ti: Byte): LongInt;
begin
  if TypeIndex[Ti] >= 0 then
    Result := TypeEntry(Ti).Size
  else
    Result := -1;
end;

function IecIsMonitor(Ti: Byte): Boolean;
begin
  Result := (TypeIndex[Ti] >= 0) and ((Ti <= 40) or (Ti = M_EI_NA_1));
end;

function IecCotName(Cot: Byte): ShortString;
begin
  case Cot of
    1: Result := 'PERIODIC';
    2: Result := 'BACKGROUND_SCAN';
    3: Result := 'SPONTANEOUS';
    4: Result := 'INITIALIZED';
    5: Result := 'REQUEST';
    6: Result := 'ACTIVATION';
    7: Result := 'ACTIVATION_CON';
    8: Result := 'DEACTIVATION';
    9: Result := 'DEACTIVATION_CON';
    10: Result := 'ACTIVATION_TERMINATION';
    11: Result := 'RETURN_INFO_REMOTE';
    12: Result := 'RETURN_INFO_LOCAL';
    13: Result := 'FILE_TRANSFER';
    20: Result := 'INTERROGATED_BY_STATION';
    21..36: Result := 'INTERROGATED_BY_GROUP_' + IntToStr(Cot - 20);
    37: Result := 'REQUESTED_BY_GENERAL_COUNTER';
    38..41: Result := 'REQUESTED_BY_GROUP_' + IntToStr(Cot - 37) + '_COUNTER';
    44: Result := 'UNKNOWN_TYPE_ID';
    45: Result := 'UNKNOWN_CAUSE_OF_TRANSMISSION';
    46: Result := 'UNKNOWN_COMMON_ADDRESS';
    47: Result := 'UNKNOWN_INFORMATION_OBJECT_ADDRESS';
  else
    Result := 'COT_' + IntToStr(Cot);
  end;
end;

function IecObject(Ioa: LongWord): tIecObject;
begin
  FillChar(Result, SizeOf(Result), 0);
  Result.Ioa := Ioa;
end;

function IecSetCot(var Buf: array of Byte; Len: Word; Cot: Byte; Negative: Boolean): Boolean;
begin
  Result := (Len >= 3) and (Length(Buf) >= 3) and (Cot <= 63);
  if Result then
    Buf[2] := (Buf[2] and $80) or Cot or (Ord(Negative) shl 6);
end;

{- ------------------------------------------------------------ time }

function IecTimeFromDateTime(DT: TDateTime): tIecTime;
begin
  Result := ChnIecTime.IecTimeFromDateTime(DT);
end;

function IecTimeCheck(const T: tIecTime; Short: Boolean; out Err: ShortString): tChResult;
begin
  if IecTimeValid(T, Short, Err) then
    Result := res_Ok
  else
    Result := res_AsduValue;
end;

function IecTimeToDateTime(const T: tIecTime; out DT: TDateTime): Boolean;
begin
  Result := ChnIecTime.IecTimeToDateTime(T, DT);
end;

{- ------------------------------------------------------------ elements }

procedure PutWord(W: Word; var B: array of Byte; At: Integer);
begin
  B[At] := Lo(W);
  B[At + 1] := Hi(W);
end;

procedure PutLong(L: LongWord; var B: array of Byte; At: Integer);
begin
  B[At] := L and $FF;
  B[At + 1] := (L shr 8) and $FF;
  B[At + 2] := (L shr 16) and $FF;
  B[At + 3] := L shr 24;
end;

function GetWord(const B: array of Byte; At: Integer): Word;
begin
  Result := B[At] or (Word(B[At + 1]) shl 8);
end;

function GetLong(const B: array of Byte; At: Integer): LongWord;
begin
  Result := B[At] or (LongWord(B[At + 1]) shl 8) or (LongWord(B[At + 2]) shl 16)
    or (LongWord(B[At + 3]) shl 24);
end;

{ One IOA of Size octets at D. A pointer, not an open array: FPC inlines
  no routine with an open array, and the codec's loops write and read one
  for every object (the callers have checked the room). }
procedure PutIoaAt(Size: Byte; Ioa: LongWord; D: PByte); inline;
begin
  D[0] := Ioa and $FF;
  if Size > 1 then
    D[1] := (Ioa shr 8) and $FF;
  if Size > 2 then
    D[2] := (Ioa shr 16) and $FF;
end;

function GetIoaAt(Size: Byte; S: PByte): LongWord; inline;
begin
  Result := S[0];
  if Size > 1 then
    Result := Result or (LongWord(S[1]) shl 8);
  if Size > 2 then
    Result := Result or (LongWord(S[2]) shl 16);
end;

function PutSingle(X: Double; var B: array of Byte; At: Integer): Boolean;
var
  S: Single;
begin
  Result := IsNan(X) or IsInfinite(X) or (Abs(X) <= MaxSingle);
  if IsNan(X) then
    PutLong($7FC00000, B, At)            { one quiet NaN, whatever the payload }
  else if Result then
  begin
    S := X;
    PutLong(PLongWord(@S)^, B, At);
  end;
end;

function GetSingle(const B: array of Byte; At: Integer): Double;
var
  L: LongWord;
begin
  L := GetLong(B, At);
  { a NaN from the line (signalling ones too) must not trap the FPU }
  if (L and $7F800000 = $7F800000) and (L and $007FFFFF <> 0) then
    Result := NaN
  else
    Result := PSingle(@L)^;
end;

{ -1 <= X < 1 as a 16-bit fraction; False when out of range. }
function NormalRaw(X: Double; out Raw: SmallInt): Boolean;
var
  R: Int64;
begin
  Result := not IsNan(X) and (X >= -1) and (X < 1);
  Raw := 0;
  if Result then
  begin
    R := Round(X * 32768);
    if R > 32767 then
      R := 32767;
    Raw := R;
  end;
end;

function Range(const What: ShortString; V, Lo, Hi: Int64; var Err: ShortString): Boolean;
begin
  Result := (V >= Lo) and (V <= Hi);
  if not Result then
    Err := What + ' ' + IntToStr(V) + ' out of range (' + IntToStr(Lo) + '..' + IntToStr(Hi) + ')';
end;

{ The octet after a measured value (at D): its quality in a report (K =
  Mon), QL and S/E in a set-point command (K = SetPt), else the QPM of a
  parameter. Inline: PutElement runs for every object. }
procedure PutValueTail(K, Mon, SetPt: tIecKind; const O: tIecObject; D: PByte;
  var Err: ShortString); inline;
begin
  if K = Mon then
    D^ := O.Quality and $F1
  else if K <> SetPt then
    D^ := O.Qu
  else if Range('QL', O.Qu, 0, 127, Err) then
    D^ := O.Qu or (Ord(O.Select) shl 7);
end;

{ PutValueTail's reverse, from the octet Q. }
procedure GetValueTail(K, Mon, SetPt: tIecKind; Q: Byte; var O: tIecObject); inline;
begin
  if K = Mon then
    O.Quality := Q and $F1
  else if K <> SetPt then
    O.Qu := Q
  else
  begin
    O.Qu := Q and $7F;
    O.Select := Q and $80 <> 0;
  end;
end;

{ The element of O (type Ti) into B[At..]; False with Err (the field) when
  a value does not fit. One case for every kind: a station's reports and
  a master's commands are the hot paths. }
function PutElement(Ti: Byte; const O: tIecObject; var B: array of Byte; At: Integer;
  out Err: ShortString): Boolean;
var
  I: Integer;
  K: tIecKind;
  Raw: SmallInt;
  V: Integer;   { octets of the value part }
begin
  Err := '';
  Info(Ti, I);
  K := Types[I].Kind;
  V := Types[I].Size - IecTimeLen(Types[I].Time);
  Result := False;
  case K of
    ikSingle:
      if Range('value', O.Int, 0, 1, Err) then
        B[At] := O.Int or (O.Quality and $F0);
    ikDouble:
      if Range('state', O.Int, 0, 3, Err) then
        B[At] := O.Int or (O.Quality and $F0);
    ikStep:
      if Range('step position', O.Int, -64, 63, Err) then
      begin
        B[At] := (O.Int and $7F) or (Ord(O.Transient) shl 7);
        B[At + 1] := O.Quality and $F1;
      end;
    ikBits, ikPacked:
      begin
        PutLong(O.Bits, B, At);
        B[At + 4] := O.Quality and $F1;
      end;
    ikNormal, ikSetNormal, ikParNormal:
      if not NormalRaw(O.Number, Raw) then
        Err := 'normalized value ' + FloatToStr(O.Number) + ' out of range (-1 <= x < 1)'
      else
      begin
        PutWord(Word(Raw), B, At);
        if V = 3 then    { M_ME_ND_1: no quality octet }
          PutValueTail(K, ikNormal, ikSetNormal, O, @B[At + 2], Err);
      end;
    ikScaled, ikSetScaled, ikParScaled:
      if Range('scaled value', O.Int, -32768, 32767, Err) then
      begin
        PutWord(Word(SmallInt(O.Int)), B, At);
        PutValueTail(K, ikScaled, ikSetScaled, O, @B[At + 2], Err);
      end;
    ikFloat, ikSetFloat, ikParFloat:
      if not PutSingle(O.Number, B, At) then
        Err := 'float value ' + FloatToStr(O.Number) + ' out of range of a short float'
      else
        PutValueTail(K, ikFloat, ikSetFloat, O, @B[At + 4], Err);
    ikCounter:
      if Range('sequence number', O.Seq, 0, 31, Err) then
      begin
        PutLong(LongWord(O.Int), B, At);
        B[At + 4] := O.Seq or (O.Quality and $E0);
      end;
    ikProtection:
      if Range('event state', O.Int, 0, 3, Err) then
      begin
        B[At] := O.Int or (O.Quality and $F8);
        PutWord(O.Elapsed, B, At + 1);
      end;
    ikStartEvents, ikOutputCircuit:
      if Range('event bits', O.Bits, 0, $3F, Err) then
      begin
        B[At] := O.Bits;
        B[At + 1] := O.Quality and $F8;
        PutWord(O.Elapsed, B, At + 2);
      end;
    { control direction and system information }
    ikEndInit, ikQualifier:
      if Range('qualifier', O.Int, 0, 255, Err) then
        B[At] := O.Int;
    ikSingleCmd, ikDoubleCmd, ikStepCmd:
      if ((K = ikSingleCmd) and Range('value', O.Int, 0, 1, Err))
        or ((K <> ikSingleCmd) and Range('state', O.Int, 0, 3, Err)) then
        if Range('QU', O.Qu, 0, 31, Err) then
          B[At] := O.Int or (O.Qu shl 2) or (Ord(O.Select) shl 7);
    ikBitsCmd:
      PutLong(O.Bits, B, At);
    ikTest, ikTestTime:
      if Range('test word', O.Int, 0, $FFFF, Err) then
        PutWord(O.Int, B, At);
    ikDelay:
      PutWord(O.Elapsed, B, At);
  end;
  if (Err = '') and (Types[I].Time <> tkNone) then
    if IecTimeFits(O.Time, Types[I].Time, Err) then
      ChnIecTime.IecPutTime(O.Time, Types[I].Time, B, At + V)
    else
      Err := 'time tag ' + Err + ' does not fit its bits';
  Result := Err = '';
end;

{ PutElement's reverse: the element of type Ti from B[At..] into O. }
procedure GetElement(Ti: Byte; const B: array of Byte; At: Integer; var O: tIecObject);
var
  I, V: Integer;
  K: tIecKind;
begin
  Info(Ti, I);
  K := Types[I].Kind;
  V := Types[I].Size - IecTimeLen(Types[I].Time);
  case K of
    ikSingle:
      begin
        O.Int := B[At] and 1;
        O.Quality := B[At] and $F0;
      end;
    ikDouble:
      begin
        O.Int := B[At] and 3;
        O.Quality := B[At] and $F0;
      end;
    ikStep:
      begin
        O.Int := ShortInt(B[At] shl 1) div 2;    { 7-bit two's complement }
        O.Transient := B[At] and $80 <> 0;
        O.Quality := B[At + 1] and $F1;
      end;
    ikBits, ikPacked:
      begin
        O.Bits := GetLong(B, At);
        O.Quality := B[At + 4] and $F1;
      end;
    ikNormal, ikSetNormal, ikParNormal:
      begin
        O.Int := SmallInt(GetWord(B, At));
        O.Number := O.Int / 32768;
        if V = 3 then    { M_ME_ND_1: no quality octet }
          GetValueTail(K, ikNormal, ikSetNormal, B[At + 2], O);
      end;
    ikScaled, ikSetScaled, ikParScaled:
      begin
        O.Int := SmallInt(GetWord(B, At));
        GetValueTail(K, ikScaled, ikSetScaled, B[At + 2], O);
      end;
    ikFloat, ikSetFloat, ikParFloat:
      begin
        O.Number := GetSingle(B, At);
        GetValueTail(K, ikFloat, ikSetFloat, B[At + 4], O);
      end;
    ikCounter:
      begin
        O.Int := LongInt(GetLong(B, At));
        O.Seq := B[At + 4] and $1F;
        O.Quality := B[At + 4] and $E0;
      end;
    ikProtection:
      begin
        O.Int := B[At] and 3;
        O.Quality := B[At] and $F8;
        O.Elapsed := GetWord(B, At + 1);
      end;
    ikStartEvents, ikOutputCircuit:
      begin
        O.Bits := B[At] and $3F;
        O.Quality := B[At + 1] and $F8;
        O.Elapsed := GetWord(B, At + 2);
      end;
    { control direction and system information }
    ikEndInit, ikQualifier:
      O.Int := B[At];
    ikSingleCmd, ikDoubleCmd, ikStepCmd:
      begin
        if K = ikSingleCmd then
          O.Int := B[At] and 1
        else
          O.Int := B[At] and 3;
        O.Qu := (B[At] shr 2) and $1F;
        O.Select := B[At] and $80 <> 0;
      end;
    ikBitsCmd:
      O.Bits := GetLong(B, At);
    ikTest, ikTestTime:
      O.Int := GetWord(B, At);
    ikDelay:
      O.Elapsed := GetWord(B, At);
  end;
  if Types[I].Time <> tkNone then
    ChnIecTime.IecGetTime(B, At + V, Types[I].Time, O.Time);
end;

{- ------------------------------------------------------------ ASDU }

function Refuse(R: tChResult; const Text: ShortString; out Err: ShortString): tChResult;
begin
  Err := Text;
  Result := R;
end;

function ObjectName(Index: Integer): ShortString;
begin
  Result := 'object ' + IntToStr(Index + 1);
end;

function IdentFits(const P: tIecParams; const H: tIecAsdu; out Err: ShortString): tChResult; inline;
begin
  Result := res_Ok;
  Err := '';
  if H.Cot > 63 then
    Exit(Refuse(res_AsduValue, 'cause of transmission ' + IntToStr(H.Cot) + ' (0..63)', Err));
  if (P.CotSize = 1) and (H.Oa <> 0) then
    Exit(Refuse(res_AsduValue, 'originator address ' + IntToStr(H.Oa)
      + ' with a one-octet cause of transmission', Err));
  if H.Ca > IecMaxCa(P) then
    Exit(Refuse(res_AsduValue, 'common address ' + IntToStr(H.Ca) + ' too large for '
      + IntToStr(P.CaSize) + ' octet(s)', Err));
end;

{ TI VSQ COT [OA] CA of H at Buf (room checked by the callers; a pointer
  to be inlined, as PutIoaAt); At: the octets written. }
procedure PutIdent(const P: tIecParams; const H: tIecAsdu; Buf: PByte; out At: Integer); inline;
begin
  Buf[0] := H.Ti;
  Buf[1] := H.Count or (Ord(H.Sq) shl 7);
  Buf[2] := H.Cot or (Ord(H.Negative) shl 6) or (Ord(H.Test) shl 7);
  At := 3;
  if P.CotSize = 2 then
  begin
    Buf[At] := H.Oa;
    Inc(At);
  end;
  Buf[At] := Lo(H.Ca);
  if P.CaSize = 2 then
    Buf[At + 1] := Hi(H.Ca);
  Inc(At, P.CaSize);
end;

function IecPutIdent(const P: tIecParams; const H: tIecAsdu; var Buf: array of Byte;
  out At: Word; out Err: ShortString): tChResult;
var
  A: Integer;
begin
  At := 0;
  Result := IecCheckParams(P, Err);
  if Result = res_Ok then
    Result := IdentFits(P, H, Err);
  if Result <> res_Ok then
    Exit;
  if Length(Buf) < IecHeadLen(P) then
    Exit(Refuse(res_AsduLength, 'no room for the data unit identifier', Err));
  PutIdent(P, H, @Buf[0], A);
  At := A;
end;

procedure IecPutIoa(const P: tIecParams; Ioa: LongWord; var Buf: array of Byte; At: LongInt);
begin
  PutIoaAt(P.IoaSize, Ioa, @Buf[At]);
end;

function IecGetIoa(const P: tIecParams; const Buf: array of Byte; At: LongInt): LongWord;
begin
  Result := GetIoaAt(P.IoaSize, @Buf[At]);
end;

procedure IecPutTime(const T: tIecTime; K: tIecTimeKind; var B: array of Byte; At: LongInt);
begin
  ChnIecTime.IecPutTime(T, K, B, At);
end;

procedure IecGetTime(const B: array of Byte; At: LongInt; K: tIecTimeKind; out T: tIecTime);
begin
  ChnIecTime.IecGetTime(B, At, K, T);
end;

function IecEncodeAsdu(const P: tIecParams; const H: tIecAsdu; const Objs: array of tIecObject;
  var Buf: array of Byte; out Len: Word; out Err: ShortString): tChResult;
var
  I, TI, At, Need, ElemLen: Integer;
  Ioa: LongWord;
  E: ShortString;
begin
  Len := 0;
  Result := IecCheckParams(P, Err);
  if Result <> res_Ok then
    Exit;
  if not Info(H.Ti, TI) then
    Exit(Refuse(res_AsduType, 'unknown type identification ' + IntToStr(H.Ti), Err));
  if (H.Count < 1) or (H.Count > IecMaxObjects) then
    Exit(Refuse(res_AsduCount, 'number of objects ' + IntToStr(H.Count) + ' (1..127)', Err));
  if H.Count > Length(Objs) then
    Exit(Refuse(res_AsduCount, 'number of objects ' + IntToStr(H.Count) + ' but '
      + IntToStr(Length(Objs)) + ' given', Err));
  Result := IdentFits(P, H, Err);
  if Result <> res_Ok then
    Exit;
  ElemLen := Types[TI].Size;
  if H.Sq then
    Need := IecHeadLen(P) + P.IoaSize + H.Count * ElemLen
  else
    Need := IecHeadLen(P) + H.Count * (P.IoaSize + ElemLen);
  if (Need > Length(Buf)) or (Need > IecMaxAsdu) then
    Exit(Refuse(res_AsduLength, Types[TI].Name + ' with ' + IntToStr(H.Count) + ' objects needs '
      + IntToStr(Need) + ' octets, room for ' + IntToStr(Min(Length(Buf), IecMaxAsdu)), Err));
  PutIdent(P, H, @Buf[0], At);
  for I := 0 to H.Count - 1 do
  begin
    Ioa := Objs[I].Ioa;
    if Ioa > IecMaxIoa(P) then
      Exit(Refuse(res_AsduIoa, ObjectName(I) + ': IOA ' + IntToStr(Ioa) + ' too large for '
        + IntToStr(P.IoaSize) + ' octet(s) (0..' + IntToStr(IecMaxIoa(P)) + ')', Err));
    if H.Sq and (I > 0) and (Ioa <> Objs[0].Ioa + LongWord(I)) then
      Exit(Refuse(res_AsduIoa, ObjectName(I) + ': IOA ' + IntToStr(Ioa) + ' does not follow IOA '
        + IntToStr(Objs[0].Ioa) + ' in a sequence', Err));
    if (I = 0) or not H.Sq then
    begin
      PutIoaAt(P.IoaSize, Ioa, @Buf[At]);
      Inc(At, P.IoaSize);
    end;
    if not PutElement(H.Ti, Objs[I], Buf, At, E) then
      Exit(Refuse(res_AsduValue, Types[TI].Name + ' ' + ObjectName(I) + ' (IOA ' + IntToStr(Ioa)
        + '): ' + E, Err));
    Inc(At, ElemLen);
  end;
  Len := At;
  Err := '';
  Result := res_Ok;
end;

function IecEncodeOne(const P: tIecParams; Ti, Cot: Byte; Ca: Word; const Obj: tIecObject;
  var Buf: array of Byte; out Len: Word; out Err: ShortString): tChResult;
var
  H: tIecAsdu;
  O: array[0..0] of tIecObject;
begin
  FillChar(H, SizeOf(H), 0);
  H.Ti := Ti;
  H.Count := 1;
  H.Cot := Cot;
  H.Ca := Ca;
  O[0] := Obj;
  Result := IecEncodeAsdu(P, H, O, Buf, Len, Err);
end;

function IecDecodeHeader(const P: tIecParams; const Buf: array of Byte; Len: Word;
  out H: tIecAsdu; out Err: ShortString): tChResult;
var
  TI, Need, At: Integer;
  Ioa: LongWord;
begin
  FillChar(H, SizeOf(H), 0);
  Result := IecCheckParams(P, Err);
  if Result <> res_Ok then
    Exit;
  if Len > Length(Buf) then
    Exit(Refuse(res_AsduLength, 'length ' + IntToStr(Len) + ' beyond the buffer of '
      + IntToStr(Length(Buf)) + ' octets', Err));
  if Len < IecHeadLen(P) then
    Exit(Refuse(res_AsduShort, 'ASDU of ' + IntToStr(Len) + ' octets is shorter than its identifier ('
      + IntToStr(IecHeadLen(P)) + ' octets: TI VSQ COT(' + IntToStr(P.CotSize) + ') CA('
      + IntToStr(P.CaSize) + '))', Err));
  H.Ti := Buf[0];
  H.Sq := Buf[1] and $80 <> 0;
  H.Count := Buf[1] and $7F;
  H.Cot := Buf[2] and $3F;
  H.Negative := Buf[2] and $40 <> 0;
  H.Test := Buf[2] and $80 <> 0;
  At := 3;
  if P.CotSize = 2 then
  begin
    H.Oa := Buf[3];
    Inc(At);
  end;
  H.Ca := Buf[At];
  if P.CaSize = 2 then
    H.Ca := H.Ca or (Word(Buf[At + 1]) shl 8);
  H.HeadLen := IecHeadLen(P);
  H.Len := Len;
  if not Info(H.Ti, TI) then
    Exit(Refuse(res_AsduType, 'unknown type identification ' + IntToStr(H.Ti), Err));
  H.ElemLen := Types[TI].Size;
  if H.Count = 0 then
    Exit(Refuse(res_AsduCount, Types[TI].Name + ': no information object (VSQ number 0)', Err));
  if H.Sq then
    Need := H.HeadLen + P.IoaSize + H.Count * H.ElemLen
  else
    Need := H.HeadLen + H.Count * (P.IoaSize + H.ElemLen);
  if Need <> Len then
    Exit(Refuse(res_AsduLength, Types[TI].Name + ' with ' + IntToStr(H.Count) + ' object(s)'
      + BoolToStr(H.Sq, ' in a sequence', '') + ' needs ' + IntToStr(Need) + ' octets, got '
      + IntToStr(Len), Err));
  if H.Sq then
  begin
    Ioa := IecGetIoa(P, Buf, H.HeadLen);
    if Ioa + H.Count - 1 > IecMaxIoa(P) then
      Exit(Refuse(res_AsduIoa, Types[TI].Name + ': sequence of ' + IntToStr(H.Count)
        + ' objects from IOA ' + IntToStr(Ioa) + ' runs past IOA ' + IntToStr(IecMaxIoa(P)), Err));
  end;
  Err := '';
  Result := res_Ok;
end;

function IecDecodeObject(const P: tIecParams; const H: tIecAsdu; const Buf: array of Byte;
  Index: LongInt; out Obj: tIecObject): tChResult;
var
  At: Integer;
  Ioa: LongWord;
begin
  FillChar(Obj, SizeOf(Obj), 0);
  if (Index < 0) or (Index >= H.Count) or (H.Len > Length(Buf)) or (TypeIndex[H.Ti] < 0)
    or (H.ElemLen <> Types[TypeIndex[H.Ti]].Size) then
    Exit(res_AsduCount);
  if H.Sq then
    At := H.HeadLen
  else
    At := H.HeadLen + Index * (P.IoaSize + H.ElemLen);
  if At + P.IoaSize + (Index * Ord(H.Sq) + 1) * H.ElemLen > H.Len then
    Exit(res_AsduCount);
  Ioa := GetIoaAt(P.IoaSize, @Buf[At]);
  Inc(At, P.IoaSize);
  if H.Sq then
  begin
    Inc(Ioa, Index);
    Inc(At, Index * H.ElemLen);
  end;
  Obj.Ioa := Ioa;
  GetElement(H.Ti, Buf, At, Obj);
  Result := res_Ok;
end;

function IecDecodeAsdu(const P: tIecParams; const Buf: array of Byte; Len: Word;
  out H: tIecAsdu; var Objs: array of tIecObject; out Err: ShortString): tChResult;
var
  I: Integer;
begin
  Result := IecDecodeHeader(P, Buf, Len, H, Err);
  if Result <> res_Ok then
    Exit;
  if H.Count > Length(Objs) then
    Exit(Refuse(res_AsduCount, IntToStr(H.Count) + ' objects, room for ' + IntToStr(Length(Objs)), Err));
  for I := 0 to H.Count - 1 do
    IecDecodeObject(P, H, Buf, I, Objs[I]);
end;

procedure BuildIndex;
var
  I: Integer;
begin
  FillChar(TypeIndex, SizeOf(TypeIndex), $FF);
  for I := Low(Types) to High(Types) do
    TypeIndex[Types[I].Ti] := I;
end;

initialization
  BuildIndex;
  ChRegisterResultText(Iec101Layer, res_AsduParam, 'impossible application parameters');
  ChRegisterResultText(Iec101Layer, res_AsduShort, 'ASDU shorter than its identifier');
  ChRegisterResultText(Iec101Layer, res_AsduType, 'unknown type identification');
  ChRegisterResultText(Iec101Layer, res_AsduLength, 'ASDU length does not fit its type and count');
  ChRegisterResultText(Iec101Layer, res_AsduCount, 'wrong number of information objects');
  ChRegisterResultText(Iec101Layer, res_AsduIoa, 'information object address out of range');
  ChRegisterResultText(Iec101Layer, res_AsduValue, 'value out of range for its type');
end.
