#!/usr/bin/env bash
# tools/mkdeps.sh - make rules for incremental builds (called by the Makefile).
#
#   tools/mkdeps.sh BINDIR SOURCE_DIRS... -- PROGRAMS...
#
# For every program it prints "BINDIR/name: program.pas unit.pas ...": the
# program's source and, transitively, every unit of SOURCE_DIRS it uses
# (uses clauses read from the sources; units not found there, such as the
# RTL's, are ignored; {$IFDEF}ed units count as used, which only costs a
# relink) and the files they include ({$I name}: chn.inc, a unit's per-OS
# unix/ and win/ include files, chnversion.inc...). A program is relinked
# only when one of those files changed.
set -eu
bindir=$1; shift
dirs=()
while [ "$1" != "--" ]; do dirs+=("$1"); shift; done
shift

# the unit names a source file uses, lower case, one per line
uses_of() {
  # drop comments but keep {$IFDEF..} text out of the way, then read every
  # "uses a, b, c;" clause (interface and implementation)
  sed -e 's/{[^}]*}//g' -e 's/(\*[^*]*\*)//g' -e 's://.*$::' "$1" | tr 'A-Z' 'a-z' |
    awk 'BEGIN { RS=";" } { gsub(/[ \t\r\n]+/, " ") }
         match($0, /(^| )uses /) { s = substr($0, RSTART + RLENGTH); n = split(s, a, ",");
           for (i = 1; i <= n; i++) { u = a[i]; sub(/ in .*$/, "", u); gsub(/ /, "", u); if (u != "") print u } }'
}

# the files a source includes ({$I name} or {$INCLUDE name}), as fpc finds
# them: beside the including file, else in src/ (-Fisrc); nested includes too
incs_of() {
  local f=$1 dir n p
  dir=$(dirname "$f")
  grep -oiE '\{\$(I|INCLUDE) +[^}]+\}' "$f" | sed -E 's/^\{\$[A-Za-z]+ +//; s/ *\}$//' |
    while read -r n; do
      for p in "$dir/$n" "src/$n"; do
        if [ -f "$p" ]; then echo "$p"; incs_of "$p"; break; fi
      done
    done
}

declare -A file_of deps_of incs
for d in "${dirs[@]}"; do
  for f in "$d"/*.pas; do
    [ -e "$f" ] || continue
    n=$(basename "$f" .pas); file_of[${n,,}]=$f
  done
done
for n in "${!file_of[@]}"; do
  incs[$n]=$(incs_of "${file_of[$n]}" | tr '\n' ' ')
  deps_of[$n]=$(uses_of "${file_of[$n]}" | while read -r u; do
    [ -n "${file_of[$u]:-}" ] && echo "$u"; done | tr '\n' ' ')
done

closure() {   # closure of unit names given on stdin
  declare -A seen=()
  local todo=($(cat)) u
  while [ ${#todo[@]} -gt 0 ]; do
    u=${todo[0]}; todo=("${todo[@]:1}")
    [ -n "${seen[$u]:-}" ] && continue
    seen[$u]=1
    todo+=(${deps_of[$u]:-})
  done
  for u in "${!seen[@]}"; do echo "${file_of[$u]}"; printf '%s\n' ${incs[$u]}; done | sort -u
}

for p in "$@"; do
  name=$(basename "$p" .pas)
  files=$({ uses_of "$p" | while read -r u; do [ -n "${file_of[$u]:-}" ] && echo "$u"; done | closure
           incs_of "$p"; } | sort -u | tr '\n' ' ')
  echo "$bindir/$name: $p $files"
done
