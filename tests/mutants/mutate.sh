#!/usr/bin/env bash
# tests/mutants/mutate.sh - mutation testing: does the suite fail when the
# code is wrong? (docs/reliability.md, "Mutation testing")
#
#   bash tests/mutants/mutate.sh check [LIST]   every listed line found, once
#   bash tests/mutants/mutate.sh run [LIST]     the mutation run
#   make mutate-check / make mutate [ONLY=id] [MUTANTS=LIST]
#
# LIST (default tests/mutants/mutants.txt) holds one record per mutant:
#
#   [id]
#   file     = src/core/ChnWait.pas
#   after    = a line of the file before it, found exactly once (optional)
#   line     = the line as it is
#   mutant   = the line as mutated (empty: the line is removed)
#   tests    = T= filters of the tests that must catch it (blank-separated)
#   programs = yes: rebuild the programs too (tests that run build/bin/*)
#   equivalent = why it cannot be caught (optional: then it is not run)
#
# Lines are matched without leading and trailing blanks, by their text,
# never by number: code moves. Without "after" the line must occur exactly
# once in the file; with it, the anchor must occur once and the line is
# its first occurrence after it. A line that is no longer there is
# reported "not found": the list needs refreshing, it is no pass.
#
# run: copies the tree (without $BUILD and .git) to a scratch folder,
# builds it once, checks that every named test passes unmutated, then for
# each mutant applies it in the scratch copy (never in the working tree),
# rebuilds the test runner (and the programs with programs = yes; all of
# it when the unit has inline routines, which its callers copy), runs
# the named tests and restores the line. A mutant is killed when a named
# test fails, crashes or hangs (TIMEOUT s, default 600). Reports each one
# and the kill rate; exit 1 when any survived, was not found or does not
# build. ONLY=text runs the mutants whose id contains it; KEEP=1 keeps the
# scratch folder. Needs FPC and TESTFLAGS (the Makefile passes them).
set -u
mode=${1:-}
LIST=${2:-${MUTANTS:-tests/mutants/mutants.txt}}
ONLY=${ONLY:-}
TIMEOUT=${TIMEOUT:-600}
FPC=${FPC:-fpc}
BUILD=${BUILD:-build}
case $mode in check|run) ;; *) sed -n '2,12p' "$0"; exit 2 ;; esac
[ -f "$LIST" ] || { echo "mutate: no list $LIST"; exit 2; }

# ---- the list: parallel arrays, one entry per record
ids=(); files=(); afters=(); lines=(); mutants=(); testss=(); progs=(); equivs=()
n=-1
while IFS= read -r raw || [ -n "$raw" ]; do
  case $raw in
    '#'*|'') continue ;;
    '['*']')
      n=$((n + 1))
      ids[n]=${raw:1:${#raw}-2}; files[n]=''; afters[n]=''; lines[n]=''
      mutants[n]=''; testss[n]=''; progs[n]=''; equivs[n]=''
      continue ;;
  esac
  [ "$n" -ge 0 ] || { echo "mutate: $LIST: '$raw' before the first [id]"; exit 2; }
  key=${raw%%=*}; key=${key//[[:space:]]/}
  val=${raw#*=}; val=${val# }
  case $key in
    file) files[n]=$val ;; after) afters[n]=$val ;; line) lines[n]=$val ;;
    mutant) mutants[n]=$val ;; tests) testss[n]=$val ;; programs) progs[n]=$val ;;
    equivalent) equivs[n]=$val ;;
    *) echo "mutate: $LIST: unknown key '$key' in [${ids[n]}]"; exit 2 ;;
  esac
done <"$LIST"
count=$((n + 1))

# locate FILE LINE AFTER: "ok <number>", or why not
locate() {
  [ -f "$1" ] || { echo "no file $1"; return; }
  M_LINE=$2 M_AFTER=$3 awk '
    function trim(s) { gsub(/^[ \t]+|[ \t\r]+$/, "", s); return s }
    BEGIN { L = trim(ENVIRON["M_LINE"]); A = trim(ENVIRON["M_AFTER"]); na = 0; nl = 0; at = 0 }
    { t = trim($0) }
    A != "" && t == A { na++; if (na == 1) anchor = NR }
    t == L {
      if (A == "") { nl++; at = NR }
      else if (na >= 1 && at == 0 && NR > anchor) at = NR
    }
    END {
      if (A != "" && na != 1) print "anchor found " na " times";
      else if (A == "" && nl > 1) print "line found " nl " times (give an anchor: after =)";
      else if (at == 0) print "not found";
      else print "ok " at
    }' "$1"
}

# replace line NUMBER of FILE with TEXT, keeping its indentation
replace_line() {
  M_TEXT=$3 awk -v at="$2" '
    NR == at {
      if (ENVIRON["M_TEXT"] == "") { print ""; next }
      match($0, /^[ \t]*/); print substr($0, 1, RLENGTH) ENVIRON["M_TEXT"]; next
    }
    { print }' "$1" >"$1.mut" && mv "$1.mut" "$1"
}

bad=0
if [ "$mode" = check ]; then
  for ((i = 0; i < count; i++)); do
    r=$(locate "${files[i]}" "${lines[i]}" "${afters[i]}")
    if [[ $r == ok* ]]; then
      echo "ok        ${ids[i]}  ${files[i]}:${r#ok }"
    else
      echo "FAIL      ${ids[i]}  ${files[i]}: $r: ${lines[i]}"; bad=$((bad + 1))
    fi
    [ -n "${equivs[i]}" ] || [ -n "${testss[i]}" ] ||
      { echo "FAIL      ${ids[i]}: no tests ="; bad=$((bad + 1)); }
  done
  echo "mutate-check: $count mutants, $bad not usable"
  [ "$bad" = 0 ]; exit
fi

# ---- run
: "${TESTFLAGS:?TESTFLAGS not set: run it as make mutate}"
src=$(pwd)
scratch=$(mktemp -d "${TMPDIR:-/tmp}/chn-mutate.XXXXXX")
cleanup() { [ "${KEEP:-0}" = 1 ] && echo "scratch kept: $scratch" || rm -rf "$scratch"; }
trap cleanup EXIT
tar --exclude="./$BUILD" --exclude=./.git -cf - . | tar -xf - -C "$scratch"
cd "$scratch" || exit 2
log=$scratch/mutate.log
echo "mutate: scratch copy $scratch"
# FPC compares a source's time with the one its unit was built from, in
# one-second steps: each change gets a time of its own, ahead of the last
stamp=0
future() {
  local now=$(( $(date +%s) + 2 ))
  [ "$now" -gt "$stamp" ] && stamp=$now || stamp=$((stamp + 2))
  touch -d "@$stamp" "$1"
}
# a unit with inline routines is compiled into the units that call them:
# a change to it rebuilds everything (-B), and so does its restoring
build_runner() { $FPC $TESTFLAGS ${1:+-B} tests/runtests.pas >>"$log" 2>&1; }
build_programs() { make -s BUILD="$BUILD" all >>"$log" 2>&1; }
if ! make -s BUILD="$BUILD" all "$BUILD/testunits.inc" "$BUILD/fpcunit/stamp" >>"$log" 2>&1 ||
   ! { mkdir -p "$BUILD/test-units" "$BUILD/test-bin"; build_runner; }; then
  echo "mutate: the unmutated tree does not build"; tail -n 20 "$log"; exit 2
fi
# run_tests FILTERS: "pass", or "fail: ..." naming the first failing filter
run_tests() {
  local f out rc res
  for f in $1; do
    out=$(BUILD=$BUILD timeout "$TIMEOUT" "$BUILD/test-bin/runtests" "$f" 2>&1)
    rc=$?
    res=$(grep '^RESULT ' <<<"$out" | tail -n 1)
    if [ "$rc" = 124 ]; then echo "fail: $f hung (${TIMEOUT} s)"; return; fi
    if [ -z "$res" ]; then echo "fail: $f crashed (exit $rc)"; return; fi
    read -r _ p fl _ <<<"$res"
    if [ "$fl" -gt 0 ] || [ "$rc" != 0 ]; then
      echo "fail: $f ($fl failed: $(grep -m1 '^FAIL' <<<"$out" | cut -c7-90))"; return
    fi
    [ "$p" -gt 0 ] || { echo "fail: $f selects no test"; return; }
  done
  echo pass
}
selected() { [ -z "$ONLY" ] || [[ ${ids[$1]} == *"$ONLY"* ]]; }
# every named test must pass unmutated first (before any mutant was built)
declare -A baseline=()
for ((i = 0; i < count; i++)); do
  selected "$i" && [ -z "${equivs[i]}" ] || continue
  [ -n "${baseline[${testss[i]}]:-}" ] || baseline[${testss[i]}]=$(run_tests "${testss[i]}")
done
killed=0; survived=0; notfound=0; invalid=0; equiv=0
for ((i = 0; i < count; i++)); do
  id=${ids[i]}
  selected "$i" || continue
  if [ -n "${equivs[i]}" ]; then
    echo "equivalent ${id}: ${equivs[i]}"; equiv=$((equiv + 1)); continue
  fi
  f=${files[i]}
  r=$(locate "$f" "${lines[i]}" "${afters[i]}")
  if [[ $r != ok* ]]; then
    echo "not found  ${id}  $f: $r: ${lines[i]}"; notfound=$((notfound + 1)); continue
  fi
  at=${r#ok }
  if [ "${baseline[${testss[i]}]}" != pass ]; then
    echo "invalid    ${id}: its tests fail unmutated: ${baseline[${testss[i]}]#fail: }"
    invalid=$((invalid + 1)); continue
  fi
  cp "$f" "$f.orig"
  replace_line "$f" "$at" "${mutants[i]}"
  future "$f"
  t0=$(date +%s)
  full=
  grep -qi 'inline;' "$f" && full=1
  if { [ "${progs[i]}" = yes ] && ! build_programs; } || ! build_runner "$full"; then
    echo "invalid    ${id}  $f:$at: the mutant does not build (see $log with KEEP=1)"
    invalid=$((invalid + 1))
  else
    v=$(run_tests "${testss[i]}")
    if [ "$v" = pass ]; then
      echo "SURVIVED   ${id}  $f:$at  (${testss[i]}): ${mutants[i]}"; survived=$((survived + 1))
    else
      echo "killed     ${id}  $f:$at  $(( $(date +%s) - t0 )) s, ${v#fail: }"; killed=$((killed + 1))
    fi
  fi
  mv "$f.orig" "$f"
  future "$f"
  [ "${progs[i]}" = yes ] && build_programs
  [ -n "$full" ] && build_runner "$full"
done
total=$((killed + survived))
rate=$(awk -v k="$killed" -v t="$total" 'BEGIN { if (t) printf "%.1f", 100 * k / t; else print "-" }')
echo "mutate: $((killed + survived + notfound + invalid + equiv)) mutants: $killed killed, $survived survived," \
  "$notfound not found, $invalid invalid, $equiv equivalent (not run); kill rate $rate % ($killed of $total)"
[ "$survived" = 0 ] && [ "$notfound" = 0 ] && [ "$invalid" = 0 ]
