#!/usr/bin/env bash
# tests/hostile/attack.sh - attacks on a TCP line and on the decoders, as
# an adversary would run them; prints one line of figures per attack
# (docs/reliability.md, "Attacks"). Not part of make test: it takes a few
# minutes and measures rather than asserts.
#
#   bash tests/hostile/attack.sh [BIN]      BIN: the programs (build/bin)
#   SECS=30 ITER=2000 ONLY=name bash tests/hostile/attack.sh
#
# Attacks (ONLY= selects those whose name contains it):
#   squat-silent   a client connects to df1sim --listen and sends nothing;
#                  legitimate df1read calls every SECS/7 s for SECS s
#   squat-trickle  the same with a byte every 5 s
#   squat-recon    a squatter that reconnects at once whenever it is closed
#   burst          50 connects in a row (each closed at once): the slowest
#   burst-busy     the same while df1sim is stopped (SIGSTOP), as a busy server
#   rfc-flood      an RFC 2217 "server" pushes 29 MiB before its DO
#                  COM-PORT-OPTION: the client's peak RSS (comraw)
#   rfc-unclosed   the server answers with IAC SB and never IAC SE: what
#                  the client reports
#   params         20000 hostile parameter strings through every layer
#                  (tests/hostile/paramattack.pas, built with range and
#                  overflow checks; needs fpc)
#   decode         ITER mutated pcap and trace files through chndecode:
#                  exit codes, crashes, run-time errors, hangs (a build
#                  with range/overflow checks when CHECKED=1 and fpc is here)
# Needs socat and GNU time (/usr/bin/time); nothing leaves the loopback.
set -u
BIN=${1:-build/bin}
SECS=${SECS:-30}
ITER=${ITER:-2000}
ONLY=${ONLY:-}
tmp=$(mktemp -d)
pids=()
groups=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${groups[@]}"; do kill -- -"$p" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT

want() { [ -z "$ONLY" ] || [[ $1 == *"$ONLY"* ]]; }
now_ms() { echo $(( $(date +%s%N) / 1000000 )); }

# df1sim --listen=0 in the background; sets $port
start_sim() {
  "$BIN/df1sim" --listen=0 --quiet --timeout=600 >"$tmp/sim.out" 2>&1 &
  sim=$!
  pids+=("$sim")
  port=
  for _ in $(seq 100); do
    port=$(sed -n 's/^LISTEN //p' "$tmp/sim.out" | head -n 1)
    [ -n "$port" ] && return 0
    sleep 0.05
  done
  echo "df1sim gave no port"; cat "$tmp/sim.out"; exit 1
}
stop_sim() { kill "$sim" 2>/dev/null; wait "$sim" 2>/dev/null; }

# N legitimate reads, one every $2 s; prints "ok of N"
legit_reads() {
  local n=$1 every=$2 ok=0 i
  for i in $(seq "$n"); do
    sleep "$every"
    timeout 10 "$BIN/df1read" N7:0 3 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=TCP \
      HOST=127.0.0.1 PORT="$port" >"$tmp/read.out" 2>&1 && ok=$((ok + 1))
  done
  echo "$ok of $n"
}

squat() {   # name, squatter command (runs with $port set)
  local name=$1 cmd=$2 sq r
  want "$name" || return 0
  start_sim
  # its own process group (setsid), so the squatter and its children end
  # together by the group's id
  port=$port setsid bash -c "$cmd" >/dev/null 2>&1 &
  sq=$!
  groups+=("$sq")
  sleep 0.5
  r=$(legit_reads 7 "$(awk "BEGIN{print $SECS/7}")")
  kill -- -"$sq" 2>/dev/null; wait "$sq" 2>/dev/null
  stop_sim
  echo "attack $name: legitimate df1read calls over ${SECS} s: $r succeeded"
}

squat squat-silent 'exec socat EXEC:"sleep 600" TCP:127.0.0.1:$port' 
printf 'while :; do printf x; sleep 5; done\n' >"$tmp/trickle.sh"
squat squat-trickle 'exec socat EXEC:"bash '"$tmp"'/trickle.sh" TCP:127.0.0.1:$port'
squat squat-recon 'while :; do socat EXEC:"sleep 600" TCP:127.0.0.1:$port; sleep 0.01; done'

# 50 connects in a row, each closed at once; "busy": the server stopped
# (SIGSTOP) meanwhile, as one busy with a long exchange
burst() {
  local name=$1 busy=$2 worst=0 slow=0 t0 t i ok
  want "$name" || return 0
  start_sim
  [ "$busy" = 1 ] && kill -STOP "$sim"
  for i in $(seq 50); do
    t0=$(now_ms)
    socat -u /dev/null TCP:127.0.0.1:"$port",connect-timeout=10 2>/dev/null
    t=$(( $(now_ms) - t0 ))
    [ "$t" -gt "$worst" ] && worst=$t
    [ "$t" -ge 500 ] && slow=$((slow + 1))
  done
  [ "$busy" = 1 ] && kill -CONT "$sim"
  ok=$(legit_reads 1 0)
  stop_sim
  echo "attack $name: 50 connects in a row: slowest ${worst} ms, ${slow} took 500 ms or more; a df1read after: $ok"
}
burst burst 0
burst burst-busy 1

# an RFC 2217 "server": the bytes of $1 (a script printing them) to the
# first client; sets $rport
start_server() {
  printf '%s\n' "$1" >"$tmp/server.sh"
  rport=$(( 20000 + RANDOM % 20000 ))
  socat TCP-LISTEN:"$rport",bind=127.0.0.1,reuseaddr EXEC:"bash $tmp/server.sh" 2>/dev/null &
  srv=$!
  pids+=("$srv")
  for _ in $(seq 100); do
    ss -Hltn "sport = :$rport" 2>/dev/null | grep -q . && return 0
    sleep 0.05
  done
}

if want rfc-flood; then
  start_server 'head -c 30408704 /dev/zero | tr "\000" "A"; printf "\377\375\054"; sleep 5'
  /usr/bin/time -f '%M' -o "$tmp/rss" timeout 30 "$BIN/comraw" \
    "NAM=TCP HOST=127.0.0.1 PORT=$rport RFC2217=ON CTO=3000" '' 1 >"$tmp/flood.out" 2>&1
  kill "$srv" 2>/dev/null; wait "$srv" 2>/dev/null
  echo "attack rfc-flood: 29 MiB pushed while negotiating: client peak RSS $(tail -n 1 "$tmp/rss") KiB;" \
    "it said: $(grep -v '^Command' "$tmp/flood.out" | head -n 1)"
fi

if want rfc-unclosed; then
  start_server 'printf "\377\375\054\377\373\000\377\375\000"; sleep 0.3; printf "\377\372\054\153"; head -c 1000 /dev/zero | tr "\000" "B"; sleep 5'
  t0=$(now_ms)
  timeout 30 "$BIN/comraw" "NAM=TCP HOST=127.0.0.1 PORT=$rport RFC2217=ON CTO=3000" '' 1 >"$tmp/sb.out" 2>&1
  rc=$?
  kill "$srv" 2>/dev/null; wait "$srv" 2>/dev/null
  echo "attack rfc-unclosed: IAC SB never closed, 1000 data bytes after it: exit $rc after $(( $(now_ms) - t0 )) ms;" \
    "it said: $(head -n 1 "$tmp/sb.out")"
fi

if want params && command -v fpc >/dev/null; then
  mkdir -p "$tmp/pu"
  if fpc -v0 -Fisrc -Fu'src/*' -Cr -Co -Ct -gl -FU"$tmp/pu" -FE"$tmp" tests/hostile/paramattack.pas >"$tmp/pa.log" 2>&1; then
    (cd "$tmp" && ./paramattack 20000 1) >"$tmp/pa.out" 2>&1
    echo "attack params: $(tail -n 1 "$tmp/pa.out")"
    grep -m3 '^exception\|^refused naming nothing' "$tmp/pa.out" | sed 's/^/  /'
  else
    echo "attack params: paramattack did not build"; cat "$tmp/pa.log"
  fi
fi

if want decode; then
  dec="$BIN/chndecode"
  if [ "${CHECKED:-0}" = 1 ] && command -v fpc >/dev/null; then
    mkdir -p "$tmp/u"
    fpc -v0 -Fisrc -Fu'src/*' -Futools/lib -Cr -Co -Ct -gl -FU"$tmp/u" -FE"$tmp" tools/chndecode.pas >/dev/null &&
      dec="$tmp/chndecode"
  fi
  # inputs: a pcap and a text log of a real exchange, and the repository's traces
  start_sim
  "$BIN/df1read" N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=TRC FILE="$tmp/in.pcap" MOD=PCAP \
    NAM=TCP HOST=127.0.0.1 PORT="$port" >/dev/null 2>&1
  "$BIN/df1read" N7:0 10 NAM=DF1 NOD=0 DNO=1 CRC=ON NAM=TRC FILE="$tmp/in.trc" \
    NAM=TCP HOST=127.0.0.1 PORT="$port" >/dev/null 2>&1
  stop_sim
  inputs=("$tmp/in.pcap:--df1" "$tmp/in.trc:--df1")
  for f in tests/data/*.trc; do inputs+=("$f:--ft12"); done
  declare -A codes=()
  crashes=0; rte=0; hangs=0
  for i in $(seq "$ITER"); do
    pick=${inputs[$((RANDOM % ${#inputs[@]}))]}
    src=${pick%%:*}; proto=${pick##*:}
    cp "$src" "$tmp/m"
    size=$(stat -c %s "$tmp/m")
    kind=$((RANDOM % 5))
    [ "$kind" = 4 ] && [[ $src != *.pcap ]] && kind=2
    case $kind in
      0) truncate -s $((RANDOM * 32768 % (size + 1) + RANDOM % (size + 1))) "$tmp/m" 2>/dev/null
         truncate -s $((RANDOM % (size + 1))) "$tmp/m" ;;
      1) for _ in 1 2 3; do
           printf "\\x$(printf %02x $((RANDOM % 256)))" |
             dd of="$tmp/m" bs=1 seek=$((RANDOM % size)) conv=notrunc 2>/dev/null
         done ;;
      2) printf '\xff\xff\xff\x7f' | dd of="$tmp/m" bs=1 seek=$((RANDOM % size)) conv=notrunc 2>/dev/null ;;
      3) head -c $((RANDOM % 64)) /dev/urandom |
           dd of="$tmp/m" bs=1 seek=$((RANDOM % size)) conv=notrunc 2>/dev/null ;;
      4) # a huge length in the first record's header (incl_len or orig_len)
         printf "\\x$(printf %02x $((RANDOM % 256)))\\xff\\xff\\x$(printf %02x $((128 + RANDOM % 128)))" |
           dd of="$tmp/m" bs=1 seek=$((32 + 4 * (RANDOM % 2))) conv=notrunc 2>/dev/null ;;
    esac
    timeout 10 "$dec" "$proto" "$tmp/m" >"$tmp/d.out" 2>&1
    rc=$?
    if [ "$rc" = 124 ]; then hangs=$((hangs + 1))
    elif grep -q 'Runtime error\|An unhandled exception' "$tmp/d.out"; then
      rte=$((rte + 1)); cp "$tmp/m" "$tmp/rte-$rte"
    elif [ "$rc" -ge 128 ]; then crashes=$((crashes + 1))
    fi
    codes[$rc]=$(( ${codes[$rc]:-0} + 1 ))
  done
  hist=
  for c in $(printf '%s\n' "${!codes[@]}" | sort -n); do hist="$hist exit $c: ${codes[$c]};"; done
  echo "attack decode: $ITER mutated inputs through $(basename "$dec")$([ "$dec" != "$BIN/chndecode" ] && echo ' (checked build)'):$hist" \
    "run-time errors $rte, crashes $crashes, hangs $hangs"
  if [ "$rte" -gt 0 ]; then
    echo "  first run-time error: $(timeout 10 "$dec" --df1 "$tmp/rte-1" 2>&1 | grep -m1 -A2 'Runtime error\|unhandled' | tr '\n' ' ')"
  fi
fi
