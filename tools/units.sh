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
    # each is in one of the part folders
    for f in $(sed -n "s/^ *Optional = '\(.*\)';.*/\1/p" fpmake.pp); do ls src/*/"$f"; done
    exit ;;
  unix|win|all) want=${1:-all} ;;
  *) echo "usage: tools/units.sh unix|win|all|--optional" >&2; exit 2 ;;
esac
# "Part(P, 'core');" names the folder src/core of the units after it;
# "AddUnit(P, 'Name.pas', OSES, [...])": AllOSes -> src/<part>/,
# AllUnixOSes -> src/<part>/unix/, AllWindowsOSes -> src/<part>/win/
sed -n -e "s/^ *Part(P, '\([a-z0-9]*\)');.*/part \1/p" \
       -e "s/.*AddUnit(P, '\([A-Za-z0-9_]*\.pas\)', \([A-Za-z]*\),.*/\2 \1/p" fpmake.pp |
while read -r oses file; do
  case $oses in
    part) part=src/$file; continue ;;
    AllOSes) dir=$part; fam="unix win" ;;
    AllUnixOSes) dir=$part/unix; fam=unix ;;
    AllWindowsOSes) dir=$part/win; fam=win ;;
    *) echo "tools/units.sh: unknown OS set $oses for $file in fpmake.pp" >&2; exit 1 ;;
  esac
  if [ "$want" = all ] || [[ " $fam " == *" $want "* ]]; then echo "$dir/$file"; fi
done
