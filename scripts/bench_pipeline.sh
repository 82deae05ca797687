#!/usr/bin/env bash
# Benchmark of the KinectFusion pipeline: runs `slambooster run` on a sequence (default: the 7-Scenes
# redkitchen sequence of the shared data) for each knob preset and prints computation ms/frame, per-stage ms,
# ATE, % tracked and peak RSS.
#
# usage: scripts/bench_pipeline.sh [SEQUENCE] [PRESETS] [BUILD_DIR] [THREADS]
#   SEQUENCE   sequence directory (default ../shared/data/7scenes-redkitchen-a, relative to the repo root)
#   PRESETS    comma-separated knob presets (default "default,accurate")
#   BUILD_DIR  build directory holding tools/slambooster/slambooster (default build/)
#   THREADS    worker threads (default 0 = all cores)
# Timings are wall-clock per stage: run on an otherwise idle machine for numbers worth comparing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sequence=${1:-"$root/../shared/data/7scenes-redkitchen-a"}
presets=${2:-default,accurate}
build=${3:-"$root/build"}
threads=${4:-0}
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_pipeline: $bin not found (build first: scripts/build.sh $build)" >&2; exit 1; }
[ -d "$sequence" ] || { echo "bench_pipeline: sequence '$sequence' not found" >&2; exit 1; }
command -v jq >/dev/null || { echo "bench_pipeline: jq is needed to list the stage times (apt-get install jq)" >&2; exit 1; }
out=$(mktemp -d /tmp/bench_pipeline.XXXXXX)
echo "sequence $sequence, $(nproc) cores, threads $threads, outputs in $out"
for preset in ${presets//,/ }; do
  dir="$out/$preset"
  /usr/bin/time -v -o "$out/$preset.time" "$bin" run "$sequence" --out "$dir" --preset "$preset" \
    --threads "$threads" --quiet > "$out/$preset.log"
  rss_kb=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/$preset.time")
  echo "== preset $preset"
  # summary.json through its type (`slambooster summary`; "-": a field this run did not write)
  IFS=$'\t' read -r frames tracked attempted pct comp cpu rmse mean max unaligned < <("$bin" summary "$dir" \
    --missing - --get frames --get tracked --get tracking_attempted --get tracked_percent \
    --get computation_ms_per_frame --get cpu_ms_per_frame --get ate.rmse_m --get ate.mean_m --get ate.max_m \
    --get ate.unaligned_mean_m)
  printf "frames %s, tracked %s/%s (%.2f%%)\n" "$frames" "$tracked" "$attempted" "$pct"
  printf "computation %.2f ms/frame (wall), process CPU %.2f ms/frame\n" "$comp" "$cpu"
  "$bin" summary "$dir" --get stage_ms_per_frame | jq -r 'to_entries[] | "  \(.key) \(.value * 100 | round / 100) ms"'
  if [ "$rmse" = - ]; then
    echo "ATE: no ground truth"
  else
    awk -v r="$rmse" -v m="$mean" -v x="$max" -v u="$unaligned" 'BEGIN {
      printf "ATE rmse %.1f cm, mean %.1f cm, max %.1f cm, unaligned mean %.1f cm\n", r * 100, m * 100, x * 100, u * 100 }'
  fi
  echo "peak RSS $((rss_kb / 1024)) MiB"
done
