#!/usr/bin/env bash
# tools/demo.sh - "make demo": a DF1 conversation on this machine, no
# hardware, no root. tools/df1sim plays an SLC 5/0x on a pseudo terminal it
# creates; examples/df1echo (the manual's section 7 echo test, corrected)
# and examples/df1read (typed read of N7:0..9) talk to it through the
# trace layer (NAM=TRC) and the serial layer (NAM=COM DEV=<pty>); then
# tools/chndecode decodes the trace. Then the gateway: tools/chngate reads
# a second df1sim and an IEC 101 RTU (examples/iec101slave on a pty it
# makes) and publishes to a local mosquitto (installed first when
# run as root, else the part is skipped with the install command); what a
# subscriber sees is printed. Everything it starts or writes is
# removed on exit (trap), also on Ctrl-C or an error.
set -eu
BUILD=${1:-build}
BIN=$BUILD/bin
TMP=$(mktemp -d "${TMPDIR:-/tmp}/chn-demo.XXXXXX")
SIMPID=
EXTRA=          # the gateway part's processes

cleanup() {
  for p in $EXTRA; do kill "$p" 2>/dev/null || true; done
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

# ---- the gateway: df1sim south, a local mosquitto north (docs/chngate.md)
echo
if ! command -v mosquitto >/dev/null 2>&1 && [ -x /usr/sbin/mosquitto ]; then PATH="$PATH:/usr/sbin"; fi
if ! command -v mosquitto >/dev/null 2>&1 || ! command -v mosquitto_sub >/dev/null 2>&1 ||
   ! ldconfig -p 2>/dev/null | grep -q libmosquitto.so.1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "== installing mosquitto mosquitto-clients libmosquitto1 for the gateway part"
    apt-get install -y mosquitto mosquitto-clients libmosquitto1 >/dev/null 2>&1 || true
    PATH="$PATH:/usr/sbin"
  fi
fi
if ! command -v mosquitto >/dev/null 2>&1 || ! command -v mosquitto_sub >/dev/null 2>&1; then
  echo "== the gateway (tools/chngate) needs an MQTT broker: skipped. Install it with"
  echo "  sudo apt-get install -y mosquitto mosquitto-clients libmosquitto1"
  exit 0
fi
"$BIN/df1sim" --pty --timeout=20 --quiet >"$TMP/sim2.log" 2>&1 &
SIM2=$!
EXTRA="$SIM2"
for _ in $(seq 50); do [ -s "$TMP/sim2.log" ] && break; sleep 0.1; done
read -r _ PTY2 <"$TMP/sim2.log" || true
# an IEC 101 RTU: a measured value, a breaker (single point 104) that its
# command point 5000 switches (return information), a double point
printf '100 M_ME_NB_1 2300\n104 M_SP_NA_1 1\n105 M_DP_NA_1 2\n5000 C_SC_NA_1 0\n' >"$TMP/rtu.txt"
"$BIN/iec101slave" --seconds=20 --points "$TMP/rtu.txt" --return 5000=104 \
  'NAM=FT1_2 MS=ON MAS=SLAVE NOD=1 LEN=0 NAM=COM DRV=PTY' >/dev/null 2>"$TMP/rtu.log" &
EXTRA="$EXTRA $!"
for _ in $(seq 50); do [ -s "$TMP/rtu.log" ] && break; sleep 0.1; done
read -r _ _ PTY3 <"$TMP/rtu.log" || true
# a free loopback port for the broker: the first that mosquitto keeps
for _ in $(seq 20); do
  PORT=$((20000 + RANDOM % 40000))
  printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\n' "$PORT" >"$TMP/mosquitto.conf"
  mosquitto -c "$TMP/mosquitto.conf" >"$TMP/mosquitto.log" 2>&1 &
  BROKER=$!
  EXTRA="$EXTRA $BROKER"
  sleep 0.3
  kill -0 "$BROKER" 2>/dev/null && break
done
cat >"$TMP/gate.conf" <<CONF
[mqtt]
port = $PORT
prefix = demo

[device plc1]
line = NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=$PTY2
tags = N7:0[10] speed=F8:0 run=B3:0/5 clock=S2:4@500
scan = 1000
write = run

[device rtu1]
line = NAM=FT1_2 MS=ON MAS=MASTER LEN=0 NOD=0 DNO=1 NAM=COM DEV=$PTY3
points = breaker=104
write = breaker>5000
CONF
echo "== tools/chngate $TMP/gate.conf: df1sim on $PTY2 and iec101slave on $PTY3 south, mosquitto on 127.0.0.1:$PORT north"
cat "$TMP/gate.conf"
mosquitto_sub -p "$PORT" -v -t 'demo/#' -W 5 >"$TMP/sub.log" 2>&1 &
SUB=$!
EXTRA="$EXTRA $SUB"
sleep 0.3
"$BIN/chngate" "$TMP/gate.conf" 2>"$TMP/gate.log" &
GATE=$!
EXTRA="$EXTRA $GATE"
sleep 1.5
echo "== mosquitto_pub -t demo/plc1/run/set -m true; mosquitto_pub -t demo/plc1/N7:0[10]/set -m 1"
echo "== mosquitto_pub -t demo/rtu1/breaker/set -m false"
mosquitto_pub -p "$PORT" -t demo/plc1/run/set -m true
mosquitto_pub -p "$PORT" -t 'demo/plc1/N7:0[10]/set' -m 1
mosquitto_pub -p "$PORT" -t demo/rtu1/breaker/set -m false
sleep 1.5
kill "$GATE"; wait "$GATE" 2>/dev/null || true
sleep 0.3
kill "$SUB" 2>/dev/null || true; wait "$SUB" 2>/dev/null || true
echo
echo "== what mosquitto_sub -v -t 'demo/#' saw"
grep -v '^Timed out' "$TMP/sub.log" || true
echo
echo "== what chngate logged"
cat "$TMP/gate.log"
kill "$BROKER" "$SIM2" 2>/dev/null || true
wait "$BROKER" "$SIM2" 2>/dev/null || true
