#!/usr/bin/env bash
# tests/run.sh - the whole regression suite, called by "make test".
#  1. the FPCUnit suite (runtests, built with -Cr -Co -Ct and heaptrc);
#  2. a heap check: heaptrc must report 0 unfreed blocks;
#  3. the type rule of docs/LAYERS.md over the library's interfaces
#     (tests/apicheck.pl; selected by T=api too), and their comments in
#     the form the API reference needs (tests/doccheck.pl);
#  4. legacy programs in tests/legacy compiled in -Mtp -Mfpc -Mobjfpc
#     -Mdelphi and run (each asserts record sizes and offsets itself); a
#     program with a NAME.peer file runs against that peer on a socat
#     null-modem (see run_with_peer) and must end with the peer file's
#     expected line;
#  5. the soak (tests/soak/soak.pas), every scenario for 2 s over ptys
#     between two processes (selected by T=soak too);
#  6. tests/packaging.sh: make install, fpmake, chn.lpk and the README's
#     programs built outside the tree.
# Ends with "N passed, N failed" alone on the last line; exit 1 on failure.
# CHN_EXEC=qemu-aarch64 (make crosstest, tools/cross.sh): the suite and the
# legacy programs are target programs, run through that emulator; the soak
# and the packaging checks (host installs) are left out then.
set -u
BUILD=${BUILD:-build}
export CHN_EXEC=${CHN_EXEC:-}
FPC=${FPC:-fpc}
FILTER=${T:-}
# pass, fail, skip, report_lines, report_end
. tests/support/report.sh

# run_with_peer PROGRAM PEERFILE: a socat null-modem of two ptys; the peer
# the .peer file defines (function "peer DEVICE", variable "expect") on one
# end, PROGRAM with the other end as its argument. Output (at most 100 kB:
# a legacy loop printing 'Chyba' must not fill the disk) goes to stdout,
# then the peer's log after a line "--- peer:".
run_with_peer() {
  local prog=$1 peerfile=$2 tmp sp pp i dev
  tmp=$(mktemp -d)
  socat pty,raw,echo=0,link="$tmp/a" pty,raw,echo=0,link="$tmp/b" 2>"$tmp/socat.log" &
  sp=$!
  for i in $(seq 100); do [ -e "$tmp/a" ] && [ -e "$tmp/b" ] && break; sleep 0.05; done
  BIN="$BUILD/bin"
  # shellcheck disable=SC1090
  . "$peerfile"
  peer "$tmp/b" >"$tmp/peer.log" 2>&1 &
  pp=$!
  # the program starts once the peer holds its end open, and a little
  # later: the peer's ChConnect, right after its open, flushes the input
  # (a frame sent in between would be lost, and the manuals' programs
  # never repeat one)
  dev=$(readlink -f "$tmp/b")
  for i in $(seq 200); do
    ls -l /proc/$pp/fd 2>/dev/null | grep -q " $dev\$" && break
    sleep 0.05
  done
  sleep 0.5
  timeout 60 $CHN_EXEC "$prog" "$tmp/a" 2>&1 | head -c 100000
  kill $pp $sp 2>/dev/null; wait $pp $sp 2>/dev/null
  echo "--- peer:"; cat "$tmp/peer.log"
  rm -rf "$tmp"
  return 0
}

heaplog="$BUILD/heaptrc.log"
rm -f "$heaplog"
out="$BUILD/runtests.out"
# a hung test must not hang CI: 30 minutes is far beyond the ~10 s it takes
# XML=file.xml (make test XML=...) also writes JUnit XML for CI systems
HEAPTRC="log=$heaplog" timeout 1800 $CHN_EXEC "$BUILD/test-bin/runtests" "$FILTER" ${XML:+--xml="$XML"} 2>&1 | tee "$out" | grep -v '^RESULT '
rc=${PIPESTATUS[0]}
res=$(grep '^RESULT ' "$out" | tail -n 1)
if [ -z "$res" ]; then
  fail "runtests crashed (exit $rc) before it finished"
else
  read -r _ p f s <<<"$res"
  passed=$((passed + p)); failed=$((failed + f)); skipped=$((skipped + ${s:-0}))
  [ "$rc" = 0 ] || [ "$f" -gt 0 ] || fail "runtests exit code $rc"
fi

if [ -f "$heaplog" ] && grep -q '^0 unfreed memory blocks' "$heaplog"; then
  pass "heap: no leaks (heaptrc)"
else
  fail "heap: leaks or no heaptrc report, see $heaplog"
  [ -f "$heaplog" ] && sed -n 1,40p "$heaplog"
fi

if [ -z "$FILTER" ] || [[ "api" == *"${FILTER,,}"* ]]; then
  if command -v perl >/dev/null; then
    if perl tests/apicheck.pl src/*/*.pas src/*/*/*.pas $(ls tools/lib/*.pas 2>/dev/null); then
      pass "api: no Integer, Cardinal, plain string or {\$H+} in library interfaces"
    else
      fail "api: mode-dependent types in library interfaces (docs/LAYERS.md)"
    fi
  else
    fail "api: perl is missing (it is part of every Debian system)"
  fi
  # the API reference (make doc, pasdoc) gives every description to the
  # declaration it was written for: a comment after a declaration is a
  # back comment {< ... } (tests/doccheck.pl)
  if perl tests/doccheck.pl src/*/*.pas src/*/*/*.pas; then
    pass "api: every comment after a declaration is a pasdoc back comment ({< ...})"
  else
    fail "api: comments the API reference would give to the next declaration (above)"
  fi
fi

# one clean unit folder per mode for this run: the first program builds
# the library units, the others reuse them (no -B for each of them)
for mode in tp fpc objfpc delphi; do rm -rf "$BUILD/legacy-$mode"; done
for prog in tests/legacy/*.pas; do
  [ -e "$prog" ] || continue
  name=$(basename "$prog" .pas)
  # with T=xyz only legacy programs whose name contains xyz
  if [ -n "$FILTER" ] && [[ "${name,,}" != *"${FILTER,,}"* ]]; then continue; fi
  for mode in tp fpc objfpc delphi; do
    dir="$BUILD/legacy-$mode"
    mkdir -p "$dir"
    if ! "$FPC" -M$mode -Fu'src/*' -Fisrc -FU"$dir" -FE"$dir" -Cr -Co -Ct "$prog" >"$dir/$name.log" 2>&1; then
      fail "legacy $name -M$mode: does not compile"; tail -n 15 "$dir/$name.log"; continue
    fi
    if [ -f "tests/legacy/$name.peer" ]; then
      if ! command -v socat >/dev/null; then
        skip "legacy $name -M$mode: socat is not installed (Debian package socat), no null-modem for its peer"
        continue
      fi
      expect=''
      run_with_peer "$dir/$name" "tests/legacy/$name.peer" >"$dir/$name.run"
      last=$(sed -n '/^--- peer:$/q;p' "$dir/$name.run" | tail -n 1)
      if [ -n "$expect" ] && [ "$last" = "$expect" ]; then
        pass "legacy $name -M$mode (against its peer: $expect)"
      else
        fail "legacy $name -M$mode: last line '$last', expected '$expect'"; tail -n 15 "$dir/$name.run"
      fi
    elif timeout 120 $CHN_EXEC "$dir/$name" >"$dir/$name.run" 2>&1; then
      pass "legacy $name -M$mode"
    else
      fail "legacy $name -M$mode: run failed"; tail -n 15 "$dir/$name.run"
    fi
  done
done

# the soak, short: every scenario a few seconds, the same assertions
if [ -z "$FILTER" ] || [[ "soak" == *"${FILTER,,}"* ]]; then
  if [ -n "$CHN_EXEC" ]; then
    echo "note: soak left out: a cross build under $CHN_EXEC (make crosstest)"
  elif [ ! -e /dev/ptmx ]; then
    skip "soak: no pseudo terminals (/dev/ptmx) on this machine"
  else
    # the groups at once: the scenarios mostly wait on timeouts. NAME@SEED
    # runs one scenario with a seed that once found a fault: on a BCC line
    # a command damaged undetected, refused by the peer, its refusal lost
    # too - counted as a duplicate before the peer's refusals were counted
    groups="df1-full-crc df1-full-bcc df1-half ft12- ft12bal ics iec101 df1-full-bcc-drop1%@132272"
    for g in $groups; do
      rm -f "$BUILD/soak-heap-$g.log"
      seed=; [[ $g == *@* ]] && seed=--seed=${g#*@}
      HEAPTRC="log=$BUILD/soak-heap-$g.log" timeout 600 "$BUILD/test-bin/soak" --seconds=2 \
        --only="${g%@*}" $seed --df1sim="$BUILD/bin/df1sim" >"$BUILD/soak-$g.out" 2>&1 &
    done
    wait
    for g in $groups; do
      finished=
      while IFS= read -r line; do
        case $line in
          "ok    "*) pass "${line#ok    }" ;;
          "FAIL  "*) fail "${line#FAIL  }" ;;
          "soak: "*" scenarios run") finished=1 ;;
          *) ;;
        esac
      done <"$BUILD/soak-$g.out"
      [ -n "$finished" ] || { fail "soak $g: did not finish (crashed or timed out)"; tail -n 15 "$BUILD/soak-$g.out"; }
      # the peers share the log; the master, ending last, writes it last
      if grep -q '^0 unfreed memory blocks' "$BUILD/soak-heap-$g.log" 2>/dev/null; then
        pass "soak $g: no leaks (heaptrc)"
      else
        fail "soak $g: leaks or no heaptrc report, see $BUILD/soak-heap-$g.log"
      fi
    done
  fi
fi

# the library as users get it: make install, fpmake, chn.lpk, README programs
if [ -n "$CHN_EXEC" ]; then
  echo "note: packaging checks left out: they install for the host (make crosstest)"
elif [ -z "$FILTER" ] || [[ "packaging" == *"${FILTER,,}"* ]]; then
  report_lines < <(BUILD=$BUILD FPC=$FPC bash tests/packaging.sh 2>&1)
fi

# the mutant list still fits the code: every record's line is found (a
# refactor that moves a line shows here, not only in the slow make mutate)
if [ -z "$FILTER" ] || [[ "mutants" == *"${FILTER,,}"* ]]; then
  if out=$(bash tests/mutants/mutate.sh check tests/mutants/mutants.txt 2>&1); then
    pass "mutants: every record of tests/mutants/mutants.txt finds its line (make mutate-check)"
  else
    fail "mutants: records that no longer find their line (make mutate-check):"
    echo "$out" | grep -v '^ok ' | tail -n 15 | sed 's/^/    /'
  fi
fi

# a T= filter that selects nothing is a mistake, not a pass (the heap
# check always runs, so it alone means nothing was selected)
if [ -n "$FILTER" ] && [ "$passed" -le 1 ] && [ "$failed" = 0 ] && [ "$skipped" = 0 ]; then
  fail "T=$FILTER selects no test"
fi

# skipped tests (an optional program missing) are listed with their reason
# by runtests ("skip  Test: why"); the count comes before the last line
report_end "an optional program is missing: see the skip lines"
