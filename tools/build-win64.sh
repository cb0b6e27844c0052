#!/usr/bin/env bash
# tools/build-win64.sh - cross-compile the serial layer for win64 on Debian.
#
# Not part of "make test". Builds a win64 RTL and the FCL units the test
# runner needs (fpcunit, process) from Debian's fpc-source (the RTL copied
# to a writable folder outside the repository), then compiles every unit
# fpmake.pp lists for Windows (tools/units.sh win) and any program given
# against it.
# tools/wintest.sh ("make wintest") runs the results under Wine.
#   tools/build-win64.sh                  units only
#   tools/build-win64.sh prog.pas ...     also these programs (.exe in $OUT/bin)
# Environment: FPCSRC (default /usr/share/fpcsrc/3.2.2), WORK (default
# /tmp/win64rtl), OUT (default build/win64), SYNAPSE_DIR (also build the
# Synapse backend for Windows).
# Needs: apt-get install fpc-source (and wine to run the result).
set -eu
FPCSRC=${FPCSRC:-/usr/share/fpcsrc/3.2.2}
WORK=${WORK:-/tmp/win64rtl}
OUT=${OUT:-build/win64}
PPC=${PPC:-ppcx64}
RTLU="$WORK/units"
if [ ! -f "$RTLU/system.ppu" ] || [ ! -f "$RTLU/windows.ppu" ]; then
  [ -d "$FPCSRC/rtl/win64" ] || { echo "no $FPCSRC/rtl/win64: apt-get install fpc-source"; exit 1; }
  mkdir -p "$WORK" "$RTLU"
  [ -d "$WORK/rtl" ] || cp -r "$FPCSRC/rtl" "$WORK/rtl"
  R="$WORK/rtl"
  INC="-Fi$R/inc -Fi$R/x86_64 -Fi$R/win -Fi$R/win/wininc -Fi$R/win64 -Fi$R/objpas -Fi$R/objpas/sysutils -Fi$R/objpas/classes"
  UNI="-Fu$R/inc -Fu$R/win -Fu$R/win64 -Fu$R/objpas -Fu$R/x86_64"
  COMMONF="-Twin64 -Px86_64 -n -v0 -FU$RTLU -FE$RTLU $INC $UNI"
  LOG="$WORK/rtl-build.log"
  (cd "$R/win64" && $PPC $COMMONF -Us -Sg system.pp && $PPC $COMMONF -Fu"$RTLU" buildrtl.pp) \
    >"$LOG" 2>&1 || { tail -n 20 "$LOG"; echo "win64 RTL build failed, see $LOG"; exit 1; }
fi
# FCL units the FPCUnit runner needs (fpcunit, testregistry, process with
# pipes) and lnfodwrf for -gl, from the same sources into the same folder
if [ ! -f "$RTLU/fpcunit.ppu" ] || [ ! -f "$RTLU/process.ppu" ] || [ ! -f "$RTLU/lnfodwrf.ppu" ]; then
  P="$FPCSRC/packages"
  R="$WORK/rtl"
  FCLF="-Twin64 -Px86_64 -n -v0 -Fu$RTLU -FU$RTLU"
  LOG="$WORK/fcl-build.log"
  { $PPC $FCLF -Fi"$R/inc" -Fi"$R/win" -Fi"$R/x86_64" "$R/inc/lnfodwrf.pp" &&
    $PPC $FCLF -Fu"$P/fcl-fpcunit/src" "$P/fcl-fpcunit/src/fpcunit.pp" &&
    $PPC $FCLF -Fu"$P/fcl-fpcunit/src" "$P/fcl-fpcunit/src/testregistry.pp" &&
    $PPC $FCLF -Fu"$P/fcl-fpcunit/src" "$P/fcl-fpcunit/src/testutils.pp" &&
    $PPC $FCLF -Fu"$P/fcl-process/src" -Fi"$P/fcl-process/src" -Fi"$P/fcl-process/src/win" \
      "$P/fcl-process/src/process.pp"; } >"$LOG" 2>&1 \
    || { tail -n 20 "$LOG"; echo "win64 FCL build failed, see $LOG"; exit 1; }
fi
# Winsock and the sockets unit for NAM=TCP (ChnSock), from rtl-extra;
# DateUtils (ChnTrc) and StrUtils (tests) from rtl-objpas
if [ ! -f "$RTLU/sockets.ppu" ] || [ ! -f "$RTLU/winsock2.ppu" ] || [ ! -f "$RTLU/dateutils.ppu" ] ||
   [ ! -f "$RTLU/strutils.ppu" ]; then
  X="$FPCSRC/packages/rtl-extra/src"
  O="$FPCSRC/packages/rtl-objpas/src/inc"
  LOG="$WORK/sockets-build.log"
  { $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" -Fi"$O" "$O/dateutils.pp" &&
    $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" -Fi"$O" "$O/strutils.pp" &&
    $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" "$X/win/winsock2.pp" &&
    $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" -Fi"$X/inc" -Fi"$X/win" \
      "$X/win/sockets.pp"; } >"$LOG" 2>&1 \
    || { tail -n 20 "$LOG"; echo "win64 sockets build failed, see $LOG"; exit 1; }
fi
# StrUtils (rtl-objpas), which tests use; built on its own so an existing
# folder from before gets it too
if [ ! -f "$RTLU/strutils.ppu" ]; then
  P="$FPCSRC/packages/rtl-objpas/src/inc"
  $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" -Fi"$P" "$P/strutils.pp" \
    >"$WORK/strutils-build.log" 2>&1 \
    || { tail -n 20 "$WORK/strutils-build.log"; echo "win64 StrUtils build failed"; exit 1; }
fi
# IniFiles (fcl-base), which the gateway's configuration reader uses
if [ ! -f "$RTLU/inifiles.ppu" ]; then
  P="$FPCSRC/packages/fcl-base/src"
  $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$RTLU" -Fu"$P" -Fi"$P" "$P/inifiles.pp" \
    >"$WORK/inifiles-build.log" 2>&1 \
    || { tail -n 20 "$WORK/inifiles-build.log"; echo "win64 IniFiles build failed"; exit 1; }
fi
mkdir -p "$OUT/units" "$OUT/bin"
# the part folders of src/ (src/README.md) and the Windows folder of src/phys
PARTS=$(for d in src/*/; do printf -- '-Fu%s ' "${d%/}"; done)
FLAGS="-Twin64 -Px86_64 -n -v0ew -Sew -O2 -Fu$RTLU $PARTS-Fusrc/phys/win -Futools/lib -Fisrc -FU$OUT/units -FE$OUT/bin"
if [ -n "${SYNAPSE_DIR:-}" ]; then
  # synaser needs registry and winver from the FPC packages; its own
  # warnings are not ours, so no -Sew for it
  P="$FPCSRC/packages"
  $PPC -Twin64 -Px86_64 -n -v0 -Fu"$RTLU" -FU"$OUT/units" \
    -Fu"$P/winunits-base/src" -Fu"$P/fcl-registry/src" -Fi"$P/fcl-registry/src" \
    -Fu"$P/fcl-base/src" -Fi"$P/fcl-base/src" -Fu"$P/fcl-xml/src" -Fi"$P/fcl-xml/src" \
    -Fu"$SYNAPSE_DIR" -Fi"$SYNAPSE_DIR" "$SYNAPSE_DIR/synaser.pas" >/dev/null
  FLAGS="$FLAGS -Fu$SYNAPSE_DIR -Fi$SYNAPSE_DIR -dCHN_SYNAPSE"
  $PPC $FLAGS src/phys/ChnPortSynapse.pas
fi
# every unit fpmake.pp lists for Windows (tools/units.sh)
for u in $(bash tools/units.sh win); do $PPC $FLAGS "$u"; done
for p in "$@"; do $PPC $FLAGS "$p"; done
echo "win64 build ok: $OUT"
