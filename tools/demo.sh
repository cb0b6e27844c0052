#!/usr/bin/env bash
# tools/demo.sh - "make demo": a DF1 conversation on this machine, no
# hardware, no root. tools/df1sim plays an SLC 5/0x on a pseudo terminal it
# creates; examples/df1echo (the manual's section 7 echo test, corrected)
# and examples/df1read (typed read of N7:0..9) talk to it through the
# trace layer (NAM=TRC) and the serial layer (NAM=COM DEV=<pty>); then
# tools/chndecode decodes the trace. Everything it starts or writes is
# removed on exit (trap), also on Ctrl-C or an error.
set -eu
BUILD=${1:-build}
BIN=$BUILD/bin
TMP=$(mktemp -d "${TMPDIR:-/tmp}/chn-demo.XXXXXX")
SIMPID=

cleanup() {
  if [ -n "$SIMPID" ]; then
    kill "$SIMPID" 2>/dev/null || true
    wait "$SIMPID" 2>/dev/null || true
  fi
  rm -rf "$TMP"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# --timeout: should this script die without its trap, df1sim ends by itself
"$BIN/df1sim" --pty --timeout=10 --config=tools/df1sim.conf >"$TMP/sim.log" 2>&1 &
SIMPID=$!
for _ in $(seq 50); do
  [ -s "$TMP/sim.log" ] && break
  sleep 0.1
done
read -r tag PTY <"$TMP/sim.log" || true
if [ "${tag:-}" != PTY ]; then
  echo "demo: df1sim did not start:"; cat "$TMP/sim.log"; exit 1
fi
COMMON="NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=TRC FILE=$TMP/trace.log NAM=COM DEV=$PTY BD=19200"

echo "== df1sim (tools/df1sim --pty) plays an SLC 5/0x, station 1, on $PTY"
echo
echo "== examples/df1echo $COMMON"
"$BIN/df1echo" $COMMON
echo
echo "== examples/df1read N7:0 10 $COMMON"
"$BIN/df1read" N7:0 10 $COMMON
echo
echo "== the trace the NAM=TRC layer wrote"
cat "$TMP/trace.log"
echo
echo "== tools/chndecode --df1 --crc <trace>"
"$BIN/chndecode" --df1 --crc "$TMP/trace.log"
echo
echo "== what df1sim saw"
tail -n +2 "$TMP/sim.log"
