#!/usr/bin/env bash
# tools/cross.sh - the library for ARM Linux (armhf, aarch64), built on an
# x86_64 Debian machine, and its suite run under qemu-user
# ("make cross ARCH=..." and "make crosstest ARCH=..."; docs/ARM.md).
#
#   tools/cross.sh toolchain ARCH   the FPC cross compiler and its units,
#                                   once, into $CROSS_CACHE/ARCH
#   tools/cross.sh build ARCH       toolchain, then library, examples and
#                                   tools with the project's flags (make all)
#   tools/cross.sh test ARCH        build, then the FPCUnit suite and the
#                                   legacy programs under qemu-user
#   tools/cross.sh fpc ARCH         print the path of the compiler wrapper
# ARCH: armhf (ARMv7, EABIHF, VFPv3: Debian armhf, Raspberry Pi 2 and
# later) or aarch64 (ARMv8 64 bit: Debian arm64, Raspberry Pi 3 and later).
#
# Why this way: Debian ships no FPC cross compiler, and fpc-source alone
# cannot build one (no top-level Makefile.fpc, no message files), but
# Debian's source package of fpc can: "apt-get source" of the version the
# host compiler is (so its units match), with Debian's patches applied
# (glibc2.34.patch makes the RTL's startup code link against glibc 2.34
# and later), Makefiles from fpcmake, then "make crossall". Nothing is
# downloaded from anywhere but the Debian archive. The deb-src entry is a
# private apt configuration inside the cache: the system's is not touched,
# so this works as any user (CI runs it as uid 65534 with HOME a temporary
# folder) and can be repeated.
#
# Environment: CROSS_CACHE (default $HOME/.cache/chn-cross), DEBIAN_MIRROR
# (default http://deb.debian.org/debian), NICE (default "nice -n 10": the
# toolchain build is CPU-heavy), JOBS (make -j, default 1), BUILD (the
# project's build folder, default build/ARCH), T (crosstest: only tests and
# legacy programs whose name contains it), ARM_OPT (armhf code generation,
# default "-CpARMV7A -CfVFPV3").
# Needs (Debian packages): dpkg-dev fp-utils fpc fpc-source make qemu-user
# binutils-aarch64-linux-gnu libc6-dev-arm64-cross libgcc-12-dev-arm64-cross
# binutils-arm-linux-gnueabihf libc6-dev-armhf-cross libgcc-12-dev-armhf-cross
set -u
CMD=${1:-}
ARCH=${2:-}
HOSTFPC=${HOSTFPC:-fpc}
CROSS_CACHE=${CROSS_CACHE:-${HOME:-/tmp}/.cache/chn-cross}
DEBIAN_MIRROR=${DEBIAN_MIRROR:-http://deb.debian.org/debian}
NICE=${NICE-nice -n 10}
JOBS=${JOBS:-1}
ARM_OPT=${ARM_OPT:--CpARMV7A -CfVFPV3}

die() { echo "cross.sh: $*" >&2; exit 1; }

case $ARCH in
  aarch64)
    CPU=aarch64; TRIPLE=aarch64-linux-gnu; PPC=ppcrossa64; QEMU=qemu-aarch64
    COMPOPT=; RTLOPT=; CROSSDEBS="binutils-aarch64-linux-gnu libc6-dev-arm64-cross libgcc-12-dev-arm64-cross" ;;
  armhf)
    # -dFPC_ARMHF: a compiler for the hard-float ABI (without it,
    # -CaEABIHF is an illegal parameter); the RTL and the programs for
    # ARMv7-A with VFPv3, the Debian armhf baseline
    CPU=arm; TRIPLE=arm-linux-gnueabihf; PPC=ppcrossarm; QEMU=qemu-arm
    COMPOPT=-dFPC_ARMHF; RTLOPT=$ARM_OPT
    CROSSDEBS="binutils-arm-linux-gnueabihf libc6-dev-armhf-cross libgcc-12-dev-armhf-cross" ;;
  *) die "ARCH=armhf or ARCH=aarch64 (got '${ARCH}')" ;;
esac

PREFIX=$CROSS_CACHE/$ARCH
WRAPPER=$PREFIX/bin/fpc-$ARCH
LOG=$CROSS_CACHE/$ARCH-build.log

# the Debian packages the toolchain needs: named with the command that
# installs them (a build never runs apt-get itself; .ci/run installs them)
need_debs() {
  local p missing=""
  for p in "$@"; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
  [ -z "$missing" ] && return 0
  echo "cross.sh: missing Debian packages:$missing (install: sudo apt-get install -y$missing)" >&2
  return 1
}

# apt-get with a private configuration in the cache: a deb-src entry for
# the host's Debian release, its own package lists, no lock on the system's
apt_private() {
  local a=$CROSS_CACHE/apt suite
  suite=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
  [ -n "$suite" ] || { echo "cross.sh: no VERSION_CODENAME in /etc/os-release" >&2; return 1; }
  mkdir -p "$a/lists/partial" "$a/cache/archives/partial"
  echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $DEBIAN_MIRROR $suite main" >"$a/sources.list"
  apt-get -q -o Dir::Etc::SourceList="$a/sources.list" -o Dir::Etc::SourceParts=/nonexistent \
    -o Dir::State::Lists="$a/lists" -o Dir::Cache="$a/cache" -o Debug::NoLocking=1 \
    -o APT::Sandbox::User="$(id -un)" "$@"
}

# The source of the host's fpc, unpacked with Debian's patches applied,
# into $1 (a fresh folder).
fetch_source() {
  local dest=$1 ver dl=$CROSS_CACHE/dl dsc
  ver=$(dpkg-query -W -f='${source:Version}' fp-compiler 2>/dev/null)
  [ -n "$ver" ] || { echo "cross.sh: fp-compiler is not installed" >&2; return 1; }
  mkdir -p "$dl"
  dsc=$(ls "$dl"/fpc_*.dsc 2>/dev/null | head -n 1)
  if [ -z "$dsc" ]; then
    echo "== apt-get source fpc=$ver (deb-src in $CROSS_CACHE/apt)"
    apt_private update >"$CROSS_CACHE/apt.log" 2>&1 || { cat "$CROSS_CACHE/apt.log" >&2; return 1; }
    (cd "$dl" && apt_private source --download-only "fpc=$ver") >>"$CROSS_CACHE/apt.log" 2>&1 ||
      { tail -n 20 "$CROSS_CACHE/apt.log" >&2; return 1; }
    dsc=$(ls "$dl"/fpc_*.dsc 2>/dev/null | head -n 1)
    [ -n "$dsc" ] || { echo "cross.sh: apt-get source fetched no .dsc" >&2; return 1; }
  fi
  rm -rf "$dest"
  # dpkg-source applies debian/patches (a "3.0 (quilt)" package)
  dpkg-source --no-check --no-copy -x "$dsc" "$dest" >/dev/null || return 1
  grep -qx 'glibc2.34.patch' "$dest/debian/patches/series" ||
    { echo "cross.sh: the source has no glibc2.34.patch: this recipe is for fpc 3.2.2 of Debian 12" >&2; return 1; }
}

toolchain() {
  [ -x "$WRAPPER" ] && "$WRAPPER" -iV >/dev/null 2>&1 && return 0
  need_debs dpkg-dev fp-compiler fp-utils make $CROSSDEBS || return 1
  command -v "$TRIPLE-as" >/dev/null || { echo "cross.sh: $TRIPLE-as not found" >&2; return 1; }
  mkdir -p "$CROSS_CACHE"
  local src=$CROSS_CACHE/src-$ARCH t0 units pp ppc
  t0=$(date +%s)
  # one fetch at a time (make cross for both targets may run at once)
  exec 9>"$CROSS_CACHE/.lock"
  flock 9
  fetch_source "$src" || { flock -u 9; return 1; }
  flock -u 9
  echo "== fpc cross compiler for $ARCH ($CPU-linux), log in $LOG"
  pp=$("$HOSTFPC" -PB)
  # (Debian's build writes version.inc and generates the Makefiles too).
  # Run from make cross, the environment carries the project's make
  # variables (MAKEFLAGS has ARCH=...), which FPC's Makefiles would take
  # as their own: ARCH there is the host CPU of the compiler's first cycle.
  local clean="env -u MAKEFLAGS -u MAKELEVEL -u MFLAGS -u ARCH -u BUILD -u T"
  { cd "$src/fpcsrc" &&
    echo "'$(dpkg-query -W -f='${source:Version}' fp-compiler)'" >compiler/version.inc &&
    fpcmake -r -Tall -q Makefile.fpc &&
    $clean $NICE make -j"$JOBS" crossall CPU_TARGET=$CPU OS_TARGET=linux BINUTILSPREFIX=$TRIPLE- \
      PP="$pp" ${COMPOPT:+OPT="$COMPOPT"} ${RTLOPT:+CROSSOPT="$RTLOPT"} &&
    $clean $NICE make crossinstall CPU_TARGET=$CPU OS_TARGET=linux BINUTILSPREFIX=$TRIPLE- \
      PP="$pp" ${COMPOPT:+OPT="$COMPOPT"} ${RTLOPT:+CROSSOPT="$RTLOPT"} \
      INSTALL_PREFIX="$PREFIX" && cd - >/dev/null; } >"$LOG" 2>&1 || { tail -n 30 "$LOG" >&2; echo "cross.sh: the cross compiler did not build (log: $LOG)" >&2; return 1; }
  # (Debian's patches put it under lib/<multiarch>/fpc/<version>)
  ppc=$(find "$PREFIX/lib" -name "$PPC" -type f | head -n 1)
  [ -n "$ppc" ] || { echo "cross.sh: no $PPC after the install (log: $LOG)" >&2; return 1; }
  units=$(dirname "$ppc")/units/$CPU-linux
  [ -f "$units/rtl/system.ppu" ] || { echo "cross.sh: no RTL in $units" >&2; return 1; }
  # its own configuration: the host's fpc.cfg would add the host's units
  mkdir -p "$PREFIX/bin"
  {
    echo "# written by tools/cross.sh"
    echo "-XP$TRIPLE-"
    echo "-Fu$units/*"
    echo "-Fl/usr/$TRIPLE/lib"
    echo "-Fl$(dirname "$(ls /usr/lib/gcc-cross/$TRIPLE/*/crtbegin.o | tail -n 1)")"
    for o in $RTLOPT; do echo "$o"; done
  } >"$PREFIX/fpc.cfg"
  cat >"$WRAPPER" <<EOF
#!/bin/sh
# the $ARCH cross compiler with its own configuration (tools/cross.sh)
exec "$ppc" -n @"$PREFIX/fpc.cfg" "\$@"
EOF
  chmod +x "$WRAPPER"
  rm -rf "$src"
  echo "== $ARCH toolchain built in $(( $(date +%s) - t0 )) s: $WRAPPER"
}

# The project's own build with the cross compiler: the Makefile's flags
# (-Sew for the library, -O2 ...) into BUILD, default build/ARCH.
build() {
  toolchain || return 1
  env -u MAKEFLAGS -u MAKELEVEL ${NICE} make --no-print-directory BUILD="$BUILD" FPC="$WRAPPER" ${SYNAPSE_DIR:+SYNAPSE_DIR="$SYNAPSE_DIR"} all
}

# make test with the cross compiler; run.sh runs the suite and the legacy
# programs through qemu-user (CHN_EXEC), which takes the target's shared
# libraries (libc for threads) from the cross libc6 package
crosstest() {
  toolchain || return 1
  command -v "$QEMU" >/dev/null || { echo "cross.sh: $QEMU not found (apt-get install qemu-user)" >&2; return 1; }
  env -u MAKEFLAGS -u MAKELEVEL CHN_EXEC=$QEMU QEMU_LD_PREFIX=/usr/$TRIPLE ${NICE} make --no-print-directory \
    BUILD="$BUILD" FPC="$WRAPPER" ${SYNAPSE_DIR:+SYNAPSE_DIR="$SYNAPSE_DIR"} T="${T:-}" test
}

BUILD=${BUILD:-build/$ARCH}
case $CMD in
  toolchain) toolchain ;;
  build) build ;;
  test) crosstest ;;
  fpc) echo "$WRAPPER" ;;
  *) die "usage: tools/cross.sh toolchain|build|test|fpc armhf|aarch64" ;;
esac
