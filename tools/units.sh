#!/usr/bin/env bash
# tools/units.sh - the library's units as fpmake.pp lists them, one source
# path a line (fpmake.pp is the one list; the Makefile, chn.lpk and make
# install read it through this script).
#   tools/units.sh unix|win     the units built on that OS family
#   tools/units.sh all          every unit fpmake.pp builds somewhere
#   tools/units.sh --optional   the units it leaves to the Makefile (Synapse)
set -eu
cd "$(dirname "$0")/.."
case ${1:-all} in
  --optional)
    sed -n "s/^ *Optional = '\(.*\)';.*/\1/p" fpmake.pp | tr ' ' '\n' | sed 's|^|src/|'
    exit ;;
  unix|win|all) want=${1:-all} ;;
  *) echo "usage: tools/units.sh unix|win|all|--optional" >&2; exit 2 ;;
esac
# "AddUnit(P, 'Name.pas', OSES, [...])": AllOSes -> src/, AllUnixOSes ->
# src/unix/, AllWindowsOSes -> src/win/
sed -n "s/.*AddUnit(P, '\([A-Za-z0-9_]*\.pas\)', \([A-Za-z]*\),.*/\2 \1/p" fpmake.pp |
while read -r oses file; do
  case $oses in
    AllOSes) dir=src; fam="unix win" ;;
    AllUnixOSes) dir=src/unix; fam=unix ;;
    AllWindowsOSes) dir=src/win; fam=win ;;
    *) echo "tools/units.sh: unknown OS set $oses for $file in fpmake.pp" >&2; exit 1 ;;
  esac
  if [ "$want" = all ] || [[ " $fam " == *" $want "* ]]; then echo "$dir/$file"; fi
done
