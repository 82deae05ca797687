#!/usr/bin/env bash
# Benchmark (not a test): slamboosterd's frame rate with no clients vs with 64 watching clients plus one
# client that never reads, and whether every reader gets every POSE in order. Runs A/B/A/B... interleaved
# (the machine may be shared) and prints the ratio per pair and overall.
#   scripts/bench_daemon.sh [BUILD_DIR] [FRAMES] [ROUNDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
frames=${2:-120}
rounds=${3:-3}
daemon="$build/daemon/slamboosterd"
clients="$build/tests/daemon/daemon_bench_clients"
tool="$build/tools/slambooster/slambooster"
for b in "$daemon" "$clients" "$tool"; do
  [ -x "$b" ] || { echo "bench_daemon: $b is missing; build the targets slamboosterd daemon_bench_clients slambooster" >&2; exit 1; }
done
work=$(mktemp -d /tmp/sb-bench-daemon-XXXXXX)
trap 'rm -rf "$work"' EXIT
"$tool" synth --out "$work/seq" --builtin-frames "$frames" --width 320 --height 240 --fx 240 --fy 240 >/dev/null
echo '{"volume_resolution": 128, "knobs": "csr=2,ir=1"}' > "$work/pipeline.json"

run() {  # $1 = label, $2 = readers, $3 = sleepers
  local out="$work/out-$1" sock="$work/$1.sock" result=""
  rm -rf "$out"
  local t0=$(date +%s.%N)
  "$daemon" --input "$work/seq" --out "$out" --socket "$sock" --pacing fast --at-end exit --controller fixed \
    --set slam.pipeline_config="$work/pipeline.json" --set log_level=warn &
  local pid=$!
  if [ "$2" -gt 0 ]; then result=$("$clients" "$sock" "$2" "$3"); fi
  wait "$pid"
  local t1=$(date +%s.%N)
  local n=$(grep -vc '^#' "$out/trajectory.tum")
  # summary.json's field through its type (report/run_summary.h, `slambooster summary`), not a grep of its text
  local comp=$("$tool" summary "$out" --get computation_ms_per_frame)
  awk -v l="$1" -v n="$n" -v a="$t0" -v b="$t1" -v c="$comp" -v r="$result" \
    'BEGIN { printf "%s frames %d wall %.3f s  %.2f frames/s  computation %.1f ms/frame %s\n", l, n, b-a, n/(b-a), c, r }'
}

for i in $(seq "$rounds"); do
  run "none-$i" 0 0
  run "clients-$i" 64 1
done | tee "$work/results.txt"
awk '
  /^none-/    { split($0, f, " "); none[++nn] = f[7] }
  /^clients-/ { split($0, f, " "); with[++nc] = f[7] }
  END {
    for (i = 1; i <= nn && i <= nc; ++i) { printf "round %d: with clients / without = %.3f\n", i, with[i] / none[i]; sa += none[i]; sb += with[i] }
    printf "mean frames/s without %.2f, with 64+1 clients %.2f: ratio %.3f\n", sa / nn, sb / nc, sb / sa
  }' "$work/results.txt"
