#!/usr/bin/env bash
# tools/fpcsearches.sh FPC DIR - exit 0 when FPC, as its configuration
# (/etc/fpc.cfg, ~/.fpc.cfg) sets it up, searches DIR for units, 1 when
# not. Asked of fpc itself: it compiles an empty program with -vt and
# prints every unit path it uses, with the cfg's wildcards and macros
# expanded (only folders that exist: run it after DIR is made).
fpc=$1; dir=${2%/}
t=$(mktemp -d) || exit 2
trap 'rm -rf "$t"' EXIT
echo 'program p; begin end.' > "$t/p.pas"
"$fpc" -vt -FU"$t" -FE"$t" "$t/p.pas" 2>/dev/null | grep -qxF "Using unit path: $dir/"
