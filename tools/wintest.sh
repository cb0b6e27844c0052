#!/usr/bin/env bash
# tools/wintest.sh - the suite as Windows programs, run under Wine
# ("make wintest"; not part of "make test": CI has no Wine).
#
#  1. tools/build-win64.sh: win64 RTL and FCL units (outside the repository),
#     the library, examples, tools and tests/wine/wincom.pas as .exe;
#  2. every tests/legacy program cross-compiled in -Mtp -Mfpc -Mobjfpc
#     -Mdelphi and run under Wine;
#  3. the FPCUnit suite (tests/runtests.pas, -Cr -Co -Ct -gh -gl) for win64
#     under Wine, and heaptrc's verdict; test units that need Unix are in
#     {$IFDEF UNIX} in the uses list make generates (UNIX_TESTS in the
#     Makefile), single Unix-only tests in their unit;
#  4. the Windows serial backend (ChnPortWin) on a real Wine COM port: Wine
#     maps COMn to a symlink in $WINEPREFIX/dosdevices, which this script
#     points at a Linux pty: tests/wine/wincom.exe against the Linux helper
#     tests/wine/ptyecho, and examples/df1echo.exe and df1read.exe against
#     the Linux tools/df1sim --pty;
#  5. NAM=TCP on Winsock: df1echo.exe and df1read.exe against the Linux
#     tools/df1sim --listen on loopback, and df1echo.exe with RFC 2217
#     through Linux ser2net (when installed) to df1sim --pty.
# Ends with "N passed, N failed" on the last line; exit 1 on any failure.
#
#   tools/wintest.sh [BUILD]        BUILD defaults to build (needs make all
#                                   and $BUILD/testunits.inc: make wintest)
# Environment: WINE (default /usr/lib/wine/wine64, else wine64/wine on the
# PATH), WINEPREFIX (default /tmp/chn-wine, created on first use, never
# ~/.wine), T=xyz (only tests and legacy programs whose name contains xyz),
# FPC (native compiler, default fpc), SYNAPSE_DIR (also run the serial
# checks on the Synapse backend, built in $BUILD/win64-synapse), and those
# of tools/build-win64.sh.
# Needs: apt-get install wine64 fpc-source.
set -u
BUILD=${1:-${BUILD:-build}}
OUT=$BUILD/win64
FPC=${FPC:-fpc}
PPC=${PPC:-ppcx64}
RTLU=${WORK:-/tmp/win64rtl}/units
FILTER=${T:-}
export WINEPREFIX=${WINEPREFIX:-/tmp/chn-wine}
export WINEDEBUG=${WINEDEBUG:--all}
if [ -z "${WINE:-}" ]; then
  for w in /usr/lib/wine/wine64 "$(command -v wine64)" "$(command -v wine)"; do
    [ -n "$w" ] && [ -x "$w" ] && { WINE=$w; break; }
  done
fi
[ -n "${WINE:-}" ] || { echo "wine not found: apt-get install wine64"; echo "0 passed, 1 failed"; exit 1; }
WINESERVER=${WINESERVER:-$(dirname "$WINE")/wineserver}
[ -x "$WINESERVER" ] || WINESERVER=$(command -v wineserver || echo wineserver)

# pass, fail, skip, report_end (the protocol of tests/run.sh)
. tests/support/report.sh
finish() {
  # tests that skip (an optional program missing) print "skip  X: why"
  report_end "each says why in its skip line"
  exit
}
# "ok    X" -> "ok    win64 X" (also FAIL, ERROR, note)
win64_lines() { sed -E 's/^(ok|FAIL|ERROR|note|skip)( +)/\1\2win64 /'; }
# run a Windows program with a deadline
wrun() { timeout "${WTIMEOUT:-120}" "$WINE" "$@"; }

mkdir -p "$OUT/test-units" "$OUT/test-bin" "$OUT/legacy" "$OUT/wine"
LOG=$OUT/wine

# ---------------------------------------------------------------- build
if ! SYNAPSE_DIR= OUT=$OUT PPC=$PPC bash tools/build-win64.sh examples/*.pas tools/*.pas tests/wine/wincom.pas \
     >"$LOG/build.log" 2>&1; then
  cat "$LOG/build.log"; fail "win64 build (tools/build-win64.sh)"; finish
fi
# the Linux end of the serial tests
if ! "$FPC" -Fu"src/*" -Fusrc/phys/unix -Fisrc -v0ew -Sew -O2 -FU"$BUILD/units" -FE"$BUILD/bin" \
     tests/wine/ptyecho.pas >"$LOG/ptyecho-build.log" 2>&1; then
  cat "$LOG/ptyecho-build.log"; fail "tests/wine/ptyecho (native)"; finish
fi

# ---------------------------------------------------------------- wine
if [ ! -d "$WINEPREFIX/dosdevices" ]; then
  echo "creating Wine prefix $WINEPREFIX"
  "$WINE" wineboot -i >"$LOG/wineboot.log" 2>&1
fi
# Our own wineserver, its output in a log: when a pty it holds is hung up
# it gets SIGHUP and dumps its object table to standard error. One left
# from an earlier run (it lingers 5 s after its last client) ends first.
timeout 20 "$WINESERVER" -w >/dev/null 2>&1
"$WINESERVER" -p5 >"$LOG/wineserver.log" 2>&1

# ---------------------------------------------------------------- legacy
for prog in tests/legacy/*.pas; do
  name=$(basename "$prog" .pas)
  if [ -n "$FILTER" ] && [[ "${name,,}" != *"${FILTER,,}"* ]]; then continue; fi
  # the manuals' programs as printed need a peer on a null-modem
  # (tests/run.sh starts one over socat); here they are only compiled
  if [ -f "tests/legacy/$name.peer" ]; then
    for mode in tp fpc objfpc delphi; do
      dir="$OUT/legacy/$mode"; mkdir -p "$dir"
      if "$PPC" -Twin64 -Px86_64 -n -v0ew -M$mode -Fu"$RTLU" -Fu"src/*" -Fusrc/phys/win -Fisrc \
           -FU"$dir" -FE"$dir" -B -Cr -Co -Ct "$prog" >"$dir/$name.log" 2>&1; then
        skip "win64 legacy $name -M$mode: compiles; not run (needs its peer on a null-modem, run by make test on Linux)"
      else
        fail "win64 legacy $name -M$mode: does not compile"; tail -n 15 "$dir/$name.log"
      fi
    done
    continue
  fi
  for mode in tp fpc objfpc delphi; do
    dir="$OUT/legacy/$mode"
    mkdir -p "$dir"
    if ! "$PPC" -Twin64 -Px86_64 -n -v0ew -M$mode -Fu"$RTLU" -Fu"src/*" -Fusrc/phys/win -Fisrc \
         -FU"$dir" -FE"$dir" -B -Cr -Co -Ct "$prog" >"$dir/$name.log" 2>&1; then
      fail "win64 legacy $name -M$mode: does not compile"; tail -n 15 "$dir/$name.log"; continue
    fi
    if wrun "$dir/$name.exe" >"$dir/$name.run" 2>&1; then
      pass "win64 legacy $name -M$mode"
    else
      fail "win64 legacy $name -M$mode: run failed"; tail -n 15 "$dir/$name.run"
    fi
  done
done

# ---------------------------------------------------------------- FPCUnit
# the uses list make generates ($BUILD/testunits.inc): Unix-only units
# in it are in {$IFDEF UNIX}
if [ ! -f "$BUILD/testunits.inc" ]; then
  fail "no $BUILD/testunits.inc: run make wintest"
elif "$PPC" -Twin64 -Px86_64 -n -v0ew -Fu"$RTLU" -Fu"src/*" -Fusrc/phys/win -Fisrc -Futools/lib -Futests/support \
     -B -Cr -Co -Ct -gh -gl -FU"$OUT/test-units" -FE"$OUT/test-bin" -Fi"$BUILD" \
     tests/runtests.pas >"$LOG/runtests-build.log" 2>&1; then
  heaplog="$OUT/heaptrc.log"
  out="$OUT/runtests.out"
  rm -f "$heaplog"
  # BUILD: BinSupport finds df1demo.exe and df1echo.exe in $OUT/bin
  BUILD=$OUT HEAPTRC="log=$heaplog" wrun "$OUT/test-bin/runtests.exe" "$FILTER" \
    2>&1 | tr -d '\r' | tee "$out" | grep -v '^RESULT ' | win64_lines
  rc=${PIPESTATUS[0]}
  res=$(grep '^RESULT ' "$out" | tail -n 1)
  if [ -z "$res" ]; then
    fail "win64 runtests crashed (exit $rc) before it finished"
  else
    read -r _ p f s _ <<<"$res"
    passed=$((passed + p)); failed=$((failed + f)); skipped=$((skipped + ${s:-0}))
    [ "$rc" = 0 ] || [ "$f" -gt 0 ] || fail "win64 runtests exit code $rc"
  fi
  if [ -f "$heaplog" ] && tr -d '\r' <"$heaplog" | grep -q '^0 unfreed memory blocks'; then
    pass "win64 heap: no leaks (heaptrc)"
  else
    fail "win64 heap: leaks or no heaptrc report, see $heaplog"
    [ -f "$heaplog" ] && sed -n 1,40p "$heaplog"
  fi
else
  cat "$LOG/runtests-build.log"; fail "win64 runtests: does not compile"
fi

# ---------------------------------------------------------------- serial
# Start a Linux program whose first line is "TAG value"; sets PID and
# FIRST = value (empty when none came within 3 s).
start_first() {
  local tag=$1 out=$2; shift 2
  "$@" >"$out" 2>&1 &
  PID=$!
  FIRST=
  for _ in $(seq 60); do
    FIRST=$(head -n 1 "$out" 2>/dev/null | sed -n "s/^$tag //p")
    [ -n "$FIRST" ] && break
    sleep 0.05
  done
}
# "PTY /dev/pts/N" (df1sim --pty, ptyecho) -> PTY; "LISTEN port" -> PORT
start_pty() { start_first PTY "$@"; PTY=$FIRST; }
start_listen() { start_first LISTEN "$@"; PORT=$FIRST; }
stop() { kill "$1" 2>/dev/null; wait "$1" 2>/dev/null; }
# COMn of the Wine prefix -> a Linux device
link_com() { ln -sfn "$2" "$WINEPREFIX/dosdevices/com$1"; }

# The serial checks on the programs in $1 (a bin folder) with driver $2.
serial_tests() {
  local bin=$1 drv=$2 tag="win64 $2"
  # tChnCom on the echo; COM9 has no device
  rm -f "$WINEPREFIX/dosdevices/com9"
  start_pty "$LOG/ptyecho-$drv.out" "$BUILD/bin/ptyecho" --timeout=60
  if [ -z "$PTY" ]; then
    fail "ptyecho gave no pty"; cat "$LOG/ptyecho-$drv.out"
  else
    link_com 5 "$PTY"
    wrun "$bin/wincom.exe" 5 9 "$drv" 2>&1 | tr -d '\r' >"$LOG/wincom-$drv.out"
    rc=${PIPESTATUS[0]}
    grep -E '^(ok|FAIL|note) ' "$LOG/wincom-$drv.out" | win64_lines
    res=$(grep '^RESULT ' "$LOG/wincom-$drv.out" | tail -n 1)
    if [ -z "$res" ]; then
      fail "$tag wincom crashed (exit $rc)"
    else
      read -r _ p f _ <<<"$res"
      passed=$((passed + p)); failed=$((failed + f))
      [ "$rc" = 0 ] || [ "$f" -gt 0 ] || fail "$tag wincom exit code $rc"
    fi
  fi
  stop "$PID"

  # the DF1 example, full duplex CRC, against the Linux simulator
  start_pty "$LOG/df1sim-full-$drv.out" "$BUILD/bin/df1sim" --pty --timeout=20
  if [ -z "$PTY" ]; then
    fail "df1sim --pty gave no pty"; cat "$LOG/df1sim-full-$drv.out"
  else
    link_com 6 "$PTY"
    wrun "$bin/df1echo.exe" NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DRV="$drv" COM=6 \
      BD=19200 2>&1 | tr -d '\r' >"$LOG/df1echo-$drv.out"
    rc=${PIPESTATUS[0]}
    if [ "$rc" = 0 ] && grep -qx 'Ok' "$LOG/df1echo-$drv.out" &&
       grep -q 'master <- reply CMD=\$46 STS=\$00 TNS=0 data: 41 68 6F 6A' "$LOG/df1echo-$drv.out" &&
       grep -q -- '<- Echo STS=\$00 TNS=0 data: 41 68 6F 6A' "$LOG/df1sim-full-$drv.out"; then
      pass "$tag df1echo.exe COM6 (full duplex, CRC) against Linux df1sim --pty"
    else
      fail "$tag df1echo.exe COM6 against df1sim: exit $rc"
      cat "$LOG/df1echo-$drv.out" "$LOG/df1sim-full-$drv.out"
    fi
  fi
  stop "$PID"

  # the typed read, half duplex BCC (polls), against the simulator's table
  start_pty "$LOG/df1sim-half-$drv.out" "$BUILD/bin/df1sim" --pty --half --bcc --node=3 --timeout=20
  if [ -z "$PTY" ]; then
    fail "df1sim --pty --half gave no pty"; cat "$LOG/df1sim-half-$drv.out"
  else
    link_com 6 "$PTY"
    wrun "$bin/df1read.exe" N7:0 3 NAM=DF1 NOD=0 DNO=3 FHD=HALF CRC=OFF NAM=COM DRV="$drv" \
      COM=6 BD=19200 2>&1 | tr -d '\r' >"$LOG/df1read-$drv.out"
    rc=${PIPESTATUS[0]}
    if [ "$rc" = 0 ] && grep -qx 'N7:0 = 0' "$LOG/df1read-$drv.out" &&
       grep -qx 'N7:1 = 10' "$LOG/df1read-$drv.out" && grep -qx 'N7:2 = 20' "$LOG/df1read-$drv.out"; then
      pass "$tag df1read.exe COM6 (half duplex, BCC) against Linux df1sim --pty: N7:0..2 = 0 10 20"
    else
      fail "$tag df1read.exe COM6 against df1sim: exit $rc"
      cat "$LOG/df1read-$drv.out" "$LOG/df1sim-half-$drv.out"
    fi
  fi
  stop "$PID"
  rm -f "$WINEPREFIX/dosdevices/com5" "$WINEPREFIX/dosdevices/com6"
}

# ---------------------------------------------------------------- TCP
# NAM=TCP on Winsock: the Windows examples against Linux listeners on the
# loopback interface - tools/df1sim --listen (raw), and ser2net with RFC
# 2217 in front of df1sim --pty when ser2net is installed.
# a loopback port nothing listens on (bash's /dev/tcp connect fails)
free_port() {
  local p
  for _ in $(seq 50); do
    p=$((20000 + RANDOM % 20000))
    (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { echo "$p"; return; }
  done
}
tcp_tests() {
  local bin=$1 tag="win64 TCP"
  start_listen "$LOG/df1sim-tcp.out" "$BUILD/bin/df1sim" --listen=0 --timeout=20
  if [ -z "$PORT" ]; then
    fail "df1sim --listen=0 gave no port"; cat "$LOG/df1sim-tcp.out"
  else
    wrun "$bin/df1echo.exe" NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=TCP HOST=127.0.0.1 \
      PORT="$PORT" 2>&1 | tr -d '\r' >"$LOG/df1echo-tcp.out"
    rc=${PIPESTATUS[0]}
    if [ "$rc" = 0 ] && grep -qx 'Ok' "$LOG/df1echo-tcp.out" &&
       grep -q 'master <- reply CMD=\$46 STS=\$00 TNS=0 data: 41 68 6F 6A' "$LOG/df1echo-tcp.out" &&
       grep -q -- '<- Echo STS=\$00 TNS=0 data: 41 68 6F 6A' "$LOG/df1sim-tcp.out"; then
      pass "$tag df1echo.exe NAM=TCP against Linux df1sim --listen (127.0.0.1:$PORT)"
    else
      fail "$tag df1echo.exe against df1sim --listen: exit $rc"
      cat "$LOG/df1echo-tcp.out" "$LOG/df1sim-tcp.out"
    fi
    wrun "$bin/df1read.exe" N7:0 3 NAM=DF1 NOD=0 DNO=1 NAM=TCP HOST=localhost \
      PORT="$PORT" 2>&1 | tr -d '\r' >"$LOG/df1read-tcp.out"
    rc=${PIPESTATUS[0]}
    if [ "$rc" = 0 ] && grep -qx 'N7:0 = 0' "$LOG/df1read-tcp.out" &&
       grep -qx 'N7:1 = 10' "$LOG/df1read-tcp.out" && grep -qx 'N7:2 = 20' "$LOG/df1read-tcp.out"; then
      pass "$tag df1read.exe NAM=TCP HOST=localhost against df1sim --listen: N7:0..2 = 0 10 20"
    else
      fail "$tag df1read.exe against df1sim --listen: exit $rc"
      cat "$LOG/df1read-tcp.out" "$LOG/df1sim-tcp.out"
    fi
  fi
  stop "$PID"
  local s2n
  s2n=$(command -v ser2net || ls /usr/sbin/ser2net 2>/dev/null)
  if [ -z "$s2n" ]; then
    echo "note  $tag: ser2net not installed, RFC 2217 from Windows not run"
    return
  fi
  start_pty "$LOG/df1sim-s2n.out" "$BUILD/bin/df1sim" --pty --timeout=20
  local port cfg=$LOG/ser2net.yaml
  port=$(free_port)
  if [ -z "$PTY" ] || [ -z "$port" ]; then
    fail "df1sim --pty gave no pty (or no free port)"; stop "$PID"; return
  fi
  printf 'connection: &w\n  accepter: telnet(rfc2217),tcp,127.0.0.1,%s\n  connector: serialdev,%s,9600n81,local\n' \
    "$port" "$PTY" >"$cfg"
  "$s2n" -n -u -c "$cfg" -P "$LOG/ser2net.pid" >"$LOG/ser2net.out" 2>&1 &
  local s2pid=$!
  # listening? asked without connecting: a connection would make ser2net
  # open the device and hold it a moment after
  for _ in $(seq 100); do
    ss -Htln "sport = :$port" 2>/dev/null | grep -q . && break
    sleep 0.05
  done
  wrun "$bin/df1echo.exe" NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=TCP HOST=127.0.0.1 \
    PORT="$port" RFC2217=ON BD=19200 2>&1 | tr -d '\r' >"$LOG/df1echo-rfc.out"
  rc=${PIPESTATUS[0]}
  if [ "$rc" = 0 ] && grep -qx 'Ok' "$LOG/df1echo-rfc.out"; then
    pass "$tag df1echo.exe RFC2217=ON BD=19200 through Linux ser2net to df1sim --pty"
  else
    fail "$tag df1echo.exe through ser2net: exit $rc"
    cat "$LOG/df1echo-rfc.out" "$LOG/ser2net.out"
  fi
  stop "$s2pid"
  stop "$PID"
}

tcp=1
if [ -n "$FILTER" ] && [[ "tcp df1echo df1read" != *"${FILTER,,}"* ]]; then tcp=0; fi
[ "$tcp" = 1 ] && tcp_tests "$OUT/bin"

serial=1
if [ -n "$FILTER" ] && [[ "wincom df1echo df1read chncom synapse" != *"${FILTER,,}"* ]]; then serial=0; fi
if [ "$serial" = 1 ]; then
  serial_tests "$OUT/bin" RTL
  # with SYNAPSE_DIR the same on a second build whose tChnCom has synaser
  # (-dCHN_SYNAPSE), like make test SYNAPSE_DIR=... on Linux
  if [ -n "${SYNAPSE_DIR:-}" ]; then
    if OUT=$OUT-synapse PPC=$PPC bash tools/build-win64.sh examples/df1echo.pas \
         examples/df1read.pas tests/wine/wincom.pas >"$LOG/build-synapse.log" 2>&1; then
      serial_tests "$OUT-synapse/bin" SYNAPSE
    else
      cat "$LOG/build-synapse.log"; fail "win64 build with SYNAPSE_DIR=$SYNAPSE_DIR"
    fi
  fi
fi

finish
