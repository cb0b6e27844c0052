#!/usr/bin/env bash
# tools/mklpk.sh - writes chn.lpk, the Lazarus runtime package, listing
# every unit of fpmake.pp, the one list (through tools/units.sh; run by
# make whenever fpmake.pp changes; tests/packaging.sh checks the committed
# file is current). OS-specific units and the optional Synapse backend stay out
# of the package's uses section: ChnCom pulls in the one its OS needs.
set -eu
cd "$(dirname "$0")/.."
files=$({ bash tools/units.sh all; bash tools/units.sh --optional; } | LC_ALL=C sort -f)
incs=$(ls src/*.inc src/*/*.inc src/*/*/*.inc 2>/dev/null | LC_ALL=C sort -f)
# the part folders (src/README.md), and the per-OS folder of src/phys
parts=$(ls -d src/*/ | sed 's|/$||' | LC_ALL=C sort | tr '\n' ';')
n=$(($(echo "$files" | wc -l) + $(echo "$incs" | wc -l)))
{
cat <<HEAD
<?xml version="1.0" encoding="UTF-8"?>
<!-- chn.lpk - the Chn library as a Lazarus runtime package (no LCL).
     Written by tools/mklpk.sh from the units fpmake.pp lists; do not
     edit.
     Add it to a project (Package > Open Package File > chn.lpk, compile,
     then Project Inspector > Add > New Requirement > chn) or from the
     command line: lazbuild -add-package-link chn.lpk; lazbuild your.lpi.
     OS-specific units (ChnPortUnix, ChnPty, ChnPortWin) and the optional
     ChnPortSynapse are not in the package's uses list: ChnCom pulls in
     the one its OS needs. -->
<CONFIG>
  <Package Version="5">
    <Name Value="chn"/>
    <Type Value="RunTimeOnly"/>
    <CompilerOptions>
      <Version Value="11"/>
      <SearchPaths>
        <IncludeFiles Value="src"/>
        <OtherUnitFiles Value="${parts}src/phys/\$(SrcOS)"/>
        <UnitOutputDirectory Value="lib/\$(TargetCPU)-\$(TargetOS)"/>
      </SearchPaths>
    </CompilerOptions>
    <Description Value="SofCon Chn serial-communication units (DF1, FT 1.2, ICSlink): layered channels driven by polling."/>
    <License Value="LGPL-2.1-or-later with the static linking exception (modified LGPL, as the FPC RTL): COPYING"/>
    <Version Major="1"/>
HEAD
echo "    <Files Count=\"$n\">"
i=0
for f in $files; do
  i=$((i + 1)); u=$(basename "$f" .pas)
  echo "      <Item$i>"
  echo "        <Filename Value=\"$f\"/>"
  echo "        <UnitName Value=\"$u\"/>"
  case $u in
    *Unix|*Win|ChnPty|*Synapse) echo '        <AddToUsesPkgSection Value="False"/>' ;;
  esac
  echo "      </Item$i>"
done
for f in $incs; do
  i=$((i + 1))
  echo "      <Item$i>"
  echo "        <Filename Value=\"$f\"/>"
  echo '        <Type Value="Include"/>'
  echo "      </Item$i>"
done
cat <<'TAIL'
    </Files>
    <RequiredPkgs Count="1">
      <Item1>
        <PackageName Value="FCL"/>
      </Item1>
    </RequiredPkgs>
    <UsageOptions>
      <UnitPath Value="$(PkgOutDir)"/>
    </UsageOptions>
    <PublishOptions>
      <Version Value="2"/>
    </PublishOptions>
  </Package>
</CONFIG>
TAIL
} > chn.lpk.tmp
# the same list: touched, so make takes it as current and does not run
# this script again at every make (it was 0.7 of a no-op make's 1.1 s)
if cmp -s chn.lpk.tmp chn.lpk 2>/dev/null; then rm -f chn.lpk.tmp; touch chn.lpk
else mv chn.lpk.tmp chn.lpk; fi
