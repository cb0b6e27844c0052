#!/usr/bin/env bash
# tests/packaging.sh - the library as users get it (called by tests/run.sh):
#  0. no file points outside the repository;
#  1. fpmake.pp lists every unit of src/ with its OSes and dependencies
#     (tests/fpmakecheck.pl), chn.lpk lists every unit of src/ and its OS
#     folders;
#  2. every complete program in README.md ("program ...;" in a ```pascal
#     block), and docs/TOOLS.md's three, is built outside the tree the three ways the README gives -
#     -Fu to this checkout, "make install" (per user, found by plain fpc),
#     the Lazarus package (lazbuild) - and run against tools/df1sim on a
#     pty: each must print "Ok";
#  3. make install DESTDIR=... PREFIX=/usr puts the units where Debian's
#     fpc looks, a program builds against them, the tools go into usr/bin
#     with man pages and work there, make uninstall removes it all;
#  4. fpmake.pp builds and installs the package;
#  5. make doc: the pasdoc API reference, no warnings, every unit.
# Prints "ok|FAIL|skip  name" lines; tests/run.sh counts them.
set -u
BUILD=${BUILD:-build}
FPC=${FPC:-fpc}
REPO=$(pwd)
TMP=$(mktemp -d "${TMPDIR:-/tmp}/chn-pkg.XXXXXX")
SIMPID=
cleanup() {
  [ -n "$SIMPID" ] && { kill "$SIMPID" 2>/dev/null; wait "$SIMPID" 2>/dev/null; }
  rm -rf "$TMP"
}
trap cleanup EXIT
# pass, fail, skip (tests/run.sh counts the lines)
. tests/support/report.sh
# a failure, and the end of the log that says why
bad() { fail "$1"; [ -n "${2:-}" ] && [ -f "$2" ] && tail -n 15 "$2"; }

# 0. the repository stands alone: no file cites the project's outside
# inputs (the specification, the seed copies of the manuals) or a path
# beside the checkout; docs/PROTOCOLS.md and docs/REFERENCES.md say it
pat='SPEC\.md|SPEC section|seed [0-9]{3}|seeds/|\.\./shared'
hits=$(grep -rlE "$pat" --exclude-dir=.git --exclude-dir="$(basename "$BUILD")" \
       --exclude=packaging.sh . 2>/dev/null || true)
if [ -z "$hits" ]; then pass "package: no file points outside the repository"
else bad "package: files citing SPEC/seeds/../shared: $(echo $hits)"; fi

# 1. fpmake.pp is the one list of units (every unit of src/, its OSes, its
# real dependencies), and chn.lpk lists them
perl tests/fpmakecheck.pl

missing=""
for f in src/*.inc src/*/*.pas src/*/*.inc src/*/*/*.pas src/*/*/*.inc; do
  grep -q "<Filename Value=\"$f\"/>" chn.lpk || missing="$missing $f"
done
if [ -z "$missing" ]; then pass "package: chn.lpk lists every unit of src/ (its part folders and their unix/, win/)"
else bad "package: chn.lpk misses$missing (make writes it: commit it)"; fi

# a make with nothing to do runs nothing (the README's 0.05 s): after one
# make, a second one remakes no file, only its phony goals
make -s BUILD="$BUILD" >/dev/null 2>&1
remade=$(make --debug=b BUILD="$BUILD" 2>/dev/null | sed -n "s/^ *Must remake target '\(.*\)'\.$/\1/p" |
         grep -vxE 'all|units|check-fpc' || true)
if [ -z "$remade" ]; then pass "package: a make with nothing to do remakes nothing"
else bad "package: a second make remakes: $(echo $remade)"; fi

# a changed library source or include file remakes the library, the
# programs that use it, and their tools/lib units afresh (make -n -W: what
# make would run were the file new; nothing is built)
would() { make -n -W "$1" BUILD="$BUILD" 2>/dev/null | sed -n 's/^fpc .* \([^ ]*\.pas\)$/\1/p; s/^rm -rf .*tool-units$/tool-units/p' | tr '\n' ' '; }
w1=$(would src/core/chnversion.inc); w2=$(would src/df1/ChnPccc.pas); w3=$(would tools/lib/ChnGateway.pas)
has() { case " $1 " in *" $2 "*) true;; *) false;; esac; }
if has "$w1" "$BUILD/chnall.pas" && has "$w1" tool-units && has "$w1" tools/chngate.pas &&
   has "$w2" tools/df1sim.pas && ! has "$w2" examples/icsread.pas && [ "$w3" = "tools/chngate.pas " ]; then
  pass "package: a changed unit or include file remakes the programs that use it (and their tools/lib units), no other"
else bad "package: make after a change would compile: chnversion.inc: $w1; ChnPccc.pas: $w2; ChnGateway.pas: $w3"; fi

# the license: stated once in COPYING, the same words in fpmake.pp and chn.lpk
lic=$(sed -n "s/^ *P\.License := '\(.*\)';/\1/p" fpmake.pp)
if [ -f COPYING ] && [ -f COPYING.LGPL ] && grep -q "Lesser General Public License" COPYING &&
   case "$lic" in LGPL-2.1-or-later*) true;; *) false;; esac &&
   grep -qF "<License Value=\"$lic: COPYING\"/>" chn.lpk; then
  pass "package: the license is stated (COPYING, COPYING.LGPL) and fpmake.pp and chn.lpk say the same"
else bad "package: license: COPYING/COPYING.LGPL missing or fpmake.pp ($lic) and chn.lpk differ"; fi

# 2. README programs, each in its own folder outside the tree
mkdir -p "$TMP/readme"
awk -v dir="$TMP/readme" '
  /^```pascal/ { inblk = 1; text = ""; name = ""; next }
  /^```/ && inblk { inblk = 0; if (name != "") { f = dir "/" name ".pas"; printf "%s", text > f; close(f) } next }
  inblk { text = text $0 "\n"; if (name == "" && match($0, /^program [A-Za-z0-9_]+;/)) { name = substr($0, 9, RLENGTH - 9) } }
' README.md
progs=$(cd "$TMP/readme" && ls *.pas 2>/dev/null | sed 's/\.pas$//')
if [ -z "$progs" ]; then bad "package: README.md has no complete program"; fi

# the simulator outlives every build below (an install on a loaded machine
# takes minutes; it is stopped at the end): 600 s without a message
"$BUILD/bin/df1sim" --pty --timeout=600 >"$TMP/sim.log" 2>&1 &
SIMPID=$!
for _ in $(seq 50); do [ -s "$TMP/sim.log" ] && break; sleep 0.1; done
read -r tag PTY <"$TMP/sim.log" || true
[ "${tag:-}" = PTY ] || { bad "package: df1sim did not start" "$TMP/sim.log"; PTY=/dev/null; }
PARAMS="NAM=DF1 NOD=0 DNO=1 FHD=FULL CRC=ON NAM=COM DEV=$PTY BD=9600"

# build_run WAY DIR PROG BUILD-COMMAND...: build in DIR, run against the
# simulator, expect what the program prints on success: readn7 takes the
# device and prints the simulator's N7:0 (0 in its default table), the
# others take a parameter string and print "Ok"
build_run() {
  local way=$1 dir=$2 p=$3 arg=$PARAMS want=${WANT:-'^Ok'}; shift 3
  if ! (cd "$dir" && "$@") >"$dir/$p.build" 2>&1; then
    bad "package: README program $p ($way) does not build" "$dir/$p.build"; return
  fi
  [ "$p" = readn7 ] && { arg=$PTY; want='^N7:0 = 0$'; }
  if timeout 20 "$dir/$p" "$arg" >"$dir/$p.run" 2>&1 && grep -q "$want" "$dir/$p.run"; then
    pass "package: README program $p built and run ($way)"
  else
    bad "package: README program $p ($way) did not print $want" "$dir/$p.run"
    # what the simulator saw, to tell a program's fault from the line's
    echo "simulator, last lines:"; tail -n 12 "$TMP/sim.log"
  fi
}

# way 1: -Fu to the checkout, the README's command as written (with this
# checkout for /path/to/chn and the program for plcecho.pas), in a fresh
# folder: the README's "mkdir -p lib" comes first
way1=$(awk '/^\*\*1\. Point fpc at a checkout/ { f = 1 } f && /^```sh/ { g = 1; next } g && /^```/ { exit } g { print }' README.md)
if ! echo "$way1" | grep -q -- '-FUlib'; then bad "package: README way 1 (-FUlib) not found"; fi
for p in $progs; do
  d="$TMP/checkout-$p"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/"
  cmd=$(echo "$way1" | sed "s|/path/to/chn|$REPO|g; s|plcecho\.pas|$p.pas|g; s|^fpc |$FPC -v0 |")
  build_run "-Fu to the checkout, README's commands" "$d" "$p" bash -c "$cmd"
done

# docs/TOOLS.md's programs (the three styles), the same way, each with
# the line it prints against the simulator's default table
mkdir -p "$TMP/tools-md"
awk -v dir="$TMP/tools-md" '
  /^```pascal/ { inblk = 1; text = ""; name = ""; next }
  /^```/ && inblk { inblk = 0; if (name != "") { f = dir "/" name ".pas"; printf "%s", text > f; close(f) } next }
  inblk { text = text $0 "\n"; if (name == "" && match($0, /^program [A-Za-z0-9_]+;/)) { name = substr($0, 9, RLENGTH - 9) } }
' docs/TOOLS.md
tprogs=$(cd "$TMP/tools-md" && ls *.pas 2>/dev/null | sed 's/\.pas$//')
[ "$(echo $tprogs)" = "blockread pollecho stepread" ] || bad "package: docs/TOOLS.md: the three programs, found: $(echo $tprogs)"
for p in $tprogs; do
  case $p in
    blockread) WANT='^N7:0 = 0, N7:1 = 10$' ;;
    stepread) WANT='^line 1: N7:0 = 0, N7:1 = 10$' ;;
    pollecho) WANT='^echo: Ok$' ;;
    *) WANT='^never$' ;;
  esac
  d="$TMP/toolsmd-$p"; mkdir -p "$d/lib"; cp "$TMP/tools-md/$p.pas" "$d/"
  build_run "docs/TOOLS.md, -Fu to the checkout" "$d" "$p" "$FPC" -v0 -Sew -Fu"$REPO/src/*" -Fi"$REPO/src" -FUlib "$p.pas"
done
WANT=

# the checkout stays clean: a build that follows the README leaves no
# compiled unit beside the library's sources
if [ -z "$(ls src/*.ppu src/*.o src/*/*.ppu src/*/*.o src/*/*/*.ppu src/*/*/*.o 2>/dev/null)" ]; then pass "package: building from the checkout writes nothing into src/"
else bad "package: compiled units were left in src/"; fi

# way 2: make install as a user (PREFIX=$HOME/.fppkg), then plain fpc
H="$TMP/home"; mkdir -p "$H"
if env HOME="$H" make -s install BUILD="$BUILD" PREFIX="$H/.fppkg" >"$TMP/install.log" 2>&1; then
  for p in $progs; do
    d="$TMP/installed-$p"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/"
    build_run "make install PREFIX=~/.fppkg, plain fpc" "$d" "$p" env HOME="$H" "$FPC" -v0 "$p.pas"
  done
  if grep -q -- '-Fu' "$TMP/install.log"; then bad "package: make install PREFIX=~/.fppkg asks for a -Fu fpc does not need" "$TMP/install.log"
  else pass "package: make install PREFIX=~/.fppkg prints no -Fu (fpc.cfg searches it)"; fi
else
  bad "package: make install PREFIX=\$HOME/.fppkg" "$TMP/install.log"
fi

# way 2b: another prefix - install prints the -Fu plain fpc needs, and a
# README program builds with exactly that
W="$TMP/some/where"
if env HOME="$H" make -s install BUILD="$BUILD" PREFIX="$W" >"$TMP/winstall.log" 2>&1; then
  fu=$(sed -n 's/^  fpc \(-Fu[^ ]*\) yourprogram\.pas$/\1/p' "$TMP/winstall.log")
  if [ "$fu" = "-Fu$W/lib/fpc/$("$FPC" -iV)/units/$("$FPC" -iTP)-$("$FPC" -iTO)/chn" ]; then
    pass "package: make install PREFIX=/some/where names the -Fu to add"
    p=$(echo $progs | cut -d' ' -f1)
    d="$TMP/where-$p"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/"
    build_run "make install PREFIX=/some/where, fpc $fu" "$d" "$p" env HOME="$H" "$FPC" -v0 "$fu" "$p.pas"
  else
    bad "package: make install PREFIX=/some/where does not say which -Fu to add (got '$fu')" "$TMP/winstall.log"
  fi
else
  bad "package: make install PREFIX=/some/where" "$TMP/winstall.log"
fi

# way 3: the Lazarus package
if ! command -v lazbuild >/dev/null 2>&1; then
  skip "package: README programs with the Lazarus package: lazbuild missing (apt-get install lcl-utils-2.2)"
else
  L="$TMP/laz"; mkdir -p "$L/pkg"; cp -r chn.lpk src "$L/pkg/"
  if lazbuild --pcp="$L/cfg" --add-package-link "$L/pkg/chn.lpk" >"$L/link.log" 2>&1 &&
     lazbuild --pcp="$L/cfg" "$L/pkg/chn.lpk" >"$L/pkg.log" 2>&1; then
    pass "package: lazbuild chn.lpk"
    for p in $progs; do
      d="$L/$p"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/$p.lpr"
      sed "s/@NAME@/$p/g" tests/data/project.lpi.in > "$d/$p.lpi"
      build_run "Lazarus project requiring chn.lpk" "$d" "$p" lazbuild --pcp="$L/cfg" "$p.lpi"
    done
  else
    bad "package: lazbuild chn.lpk" "$L/pkg.log"
  fi
fi

# 3. root layout under DESTDIR, and uninstall
D="$TMP/dest"
MA=$(gcc -print-multiarch 2>/dev/null || dpkg-architecture -qDEB_HOST_MULTIARCH)
U="$D/usr/lib/$MA/fpc/$($FPC -iV)/units/$($FPC -iTP)-$($FPC -iTO)/chn"
if make -s install BUILD="$BUILD" DESTDIR="$D" >"$TMP/dinstall.log" 2>&1 && [ -f "$U/chnvirt.ppu" ] &&
   [ -f "$D/usr/share/chn/src/core/ChnVirt.pas" ] && [ -f "$D/usr/share/chn/chn.lpk" ] &&
   [ -f "$D/usr/share/chn/COPYING" ] && [ -f "$D/usr/share/chn/COPYING.LGPL" ]; then
  p=$(echo $progs | cut -d' ' -f1)
  d="$TMP/destdir"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/"
  build_run "make install DESTDIR= PREFIX=/usr" "$d" "$p" "$FPC" -v0 -Fu"$U" "$p.pas"
  # the tools: in usr/bin, each answering --help, with a man page
  TOOLS_INSTALLED="df1sim chndecode chntap chnline df1read df1write df1echo comraw waitany"
  missing=""
  for t in $TOOLS_INSTALLED; do
    [ -x "$D/usr/bin/$t" ] && "$D/usr/bin/$t" --help 2>/dev/null | grep -q "^Usage: $t " || missing="$missing $t"
  done
  if [ -z "$missing" ]; then pass "package: make install puts the tools into \$PREFIX/bin, each answers --help"
  else bad "package: tools missing in $D/usr/bin or without --help:$missing"; fi
  if ! command -v help2man >/dev/null 2>&1; then
    skip "package: man pages of the tools: help2man missing (apt-get install help2man)"
  else
    missing=""
    for t in $TOOLS_INSTALLED; do
      grep -q "^\.TH $(echo $t | tr a-z A-Z) \"1\"" "$D/usr/share/man/man1/$t.1" 2>/dev/null || missing="$missing $t"
    done
    if [ -z "$missing" ]; then pass "package: a man page (help2man) for every installed tool in \$PREFIX/share/man/man1"
    else bad "package: man pages missing or not a man page:$missing"; fi
  fi
  # the installed tools at work, with nothing of the checkout: the
  # installed df1sim on its pty, the installed df1read and df1write against
  # it, the installed chndecode on the trace df1read wrote
  (
    cd "$TMP" || exit 1
    "$D/usr/bin/df1sim" --pty --timeout 20 --quiet >"$TMP/isim.log" 2>&1 &
    isim=$!
    for _ in $(seq 50); do [ -s "$TMP/isim.log" ] && break; sleep 0.1; done
    read -r _ IPTY <"$TMP/isim.log"
    P2="NAM=DF1 NOD=0 DNO=1 NAM=TRC FILE=$TMP/itrace.log NAM=COM DEV=$IPTY BD=19200"
    "$D/usr/bin/df1write" N7:3 33 $P2 >"$TMP/itools.log" 2>&1 &&
    "$D/usr/bin/df1read" N7:3 1 $P2 >>"$TMP/itools.log" 2>&1 &&
    "$D/usr/bin/chndecode" --df1 "$TMP/itrace.log" >>"$TMP/itools.log" 2>&1
    rc=$?
    kill $isim 2>/dev/null; wait $isim 2>/dev/null
    exit $rc
  )
  if [ $? = 0 ] && grep -q '^N7:3 = 33$' "$TMP/itools.log" && grep -q ' 0 errors, 0 incomplete$' "$TMP/itools.log"; then
    pass "package: the installed df1sim, df1write, df1read and chndecode work together"
  else
    bad "package: the installed tools against each other" "$TMP/itools.log"
  fi
  make -s uninstall BUILD="$BUILD" DESTDIR="$D" >/dev/null 2>&1
  left=$(cd "$D" 2>/dev/null && find . -type f | head -n 5)
  if [ -e "$U" ] || [ -e "$D/usr/share/chn" ] || [ -n "$left" ]; then bad "package: make uninstall left files: $left"
  else pass "package: make uninstall removes the units, sources, tools and man pages"; fi
else
  bad "package: make install DESTDIR=... PREFIX=/usr (units in $U)" "$TMP/dinstall.log"
fi

# 4. fpmake
F="$TMP/fpmake"; mkdir -p "$F"; cp -r fpmake.pp src "$F/"
# fpmake looks for the RTL's package files under its prefix unless told
# where the compiler's own units are: the folder above units/<target>/rtl
echo 'program probe; begin end.' >"$F/probe.pas"
G=$(cd "$F" && "$FPC" -va probe.pas 2>/dev/null | sed -n 's|.*PPU Loading \(.*\)/units/[^/]*/rtl/system.ppu|\1|p' | head -n 1)
if (cd "$F" && "$FPC" -v0 fpmake.pp && ./fpmake build && \
    ./fpmake install --prefix="$F/home/.fppkg" ${G:+--globalunitdir="$G"}) >"$F/log" 2>&1; then
  p=$(echo $progs | cut -d' ' -f1)
  d="$F/prog"; mkdir -p "$d"; cp "$TMP/readme/$p.pas" "$d/"
  build_run "fpmake install, plain fpc" "$d" "$p" env HOME="$F/home" "$FPC" -v0 "$p.pas"
else
  bad "package: fpc fpmake.pp && ./fpmake build && ./fpmake install" "$F/log"
fi

# 5. the API reference: make doc (pasdoc) builds without a warning and
# has a page for every library unit
if ! command -v pasdoc >/dev/null 2>&1; then
  skip "package: make doc: pasdoc missing (apt-get install pasdoc), the API reference is not checked"
elif make -s doc BUILD="$BUILD" >"$TMP/doc.log" 2>&1; then
  missing=""
  for f in $(ls src/*/*.pas src/*/*/*.pas 2>/dev/null); do
    u=$(basename "$f" .pas)
    [ -f "$BUILD/doc/$u.html" ] || missing="$missing $u"
  done
  if [ -z "$missing" ]; then pass "package: make doc: the API reference (pasdoc, no warnings) has every library unit"
  else bad "package: make doc: no page for$missing"; fi
else
  bad "package: make doc (pasdoc warnings or errors)" "$TMP/doc.log"
fi
