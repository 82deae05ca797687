#!/usr/bin/env bash
# Configures and builds SLAMBooster (Release) into build/ (or BUILD). Used by main_job.sh and test.sh.
#
#   scripts/build.sh [--werror] [BUILD [TARGET...]]
#
# TARGETs: only those and what they need (main_job.sh: the three programs it runs); none: everything, the
# test suite included (test.sh). --werror: warnings are errors (-DSB_WERROR=ON, what CI builds with).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
werror=()
if [ "${1:-}" = --werror ]; then werror=(-DSB_WERROR=ON); shift; fi
build=${1:-"$root/build"}
if [ $# -gt 0 ]; then shift; fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${werror[@]}"
elif [ ${#werror[@]} -gt 0 ]; then
  cmake -S "$root" -B "$build" "${werror[@]}" > /dev/null
fi
cmake --build "$build" -j "$(nproc)" "${targets[@]}"
