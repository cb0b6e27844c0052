#!/usr/bin/env bash
# tools/demo.sh - "make demo": a DF1 echo exchange on this machine with no
# hardware. For now both stations run in one process over the in-memory
# null modem (NAM=LOOP), see examples/df1demo.pas; a simulator on a pty
# pair can replace this once the COM layer exists.
set -eu
BUILD=${1:-build}
exec "$BUILD/bin/df1demo"
