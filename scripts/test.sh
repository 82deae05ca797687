#!/usr/bin/env bash
# Command (2) of the README: install what is missing, build, and run every test.
# Exits non-zero on any failure. Tests that read ../shared/data fail (not skip) when CI is set and the data
# is missing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build"
cd "$root/build"
ctest --output-on-failure -j "$(nproc)" --timeout 1500
