#!/usr/bin/env bash
# Command (2) of the README: install what is missing, build, and run every test; then the armhf checks
# (scripts/test_armhf.sh: cross build for the board, the armhf unit-test subset under qemu-arm, the .deb).
#
#   scripts/test.sh                 # native suite, then the armhf checks (what CI runs)
#   scripts/test.sh --native-only   # the native suite alone
#
# Exits non-zero on any failure. Tests that read ../shared/data fail (not skip) when CI is set and the data
# is missing. The armhf part needs root or sudo once, to add the armhf packages (cross-toolchain/prepare_host.sh),
# and takes about 20 minutes on 2 cores from scratch.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
armhf=1
case "${1:-}" in
  "") ;;
  --native-only) armhf=0 ;;
  *) echo "usage: scripts/test.sh [--native-only]" >&2; exit 2 ;;
esac
"$root/scripts/install_deps.sh"
# Everything, warnings as errors: CI's build stays warning-free.
"$root/scripts/build.sh" --werror "$root/build"
# Every test has its own TIMEOUT and a label (tests/CMakeLists.txt): `ctest -L unit` is the quick loop.
(cd "$root/build" && ctest --output-on-failure -j "$(nproc)")
if [ "$armhf" = 1 ]; then
  "$root/scripts/test_armhf.sh" "$root/build-armhf"
fi
