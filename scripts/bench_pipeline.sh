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
command -v jq >/dev/null || { echo "bench_pipeline: jq is needed to read summary.json (apt-get install jq)" >&2; exit 1; }
out=$(mktemp -d /tmp/bench_pipeline.XXXXXX)
echo "sequence $sequence, $(nproc) cores, threads $threads, outputs in $out"
for preset in ${presets//,/ }; do
  dir="$out/$preset"
  /usr/bin/time -v -o "$out/$preset.time" "$bin" run "$sequence" --out "$dir" --preset "$preset" \
    --threads "$threads" --quiet > "$out/$preset.log"
  rss_kb=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$out/$preset.time")
  echo "== preset $preset"
  jq -r '"frames \(.frames), tracked \(.tracked)/\(.tracking_attempted) (\(.tracked_percent | . * 100 | round / 100)%)",
         "computation \(.computation_ms_per_frame | . * 100 | round / 100) ms/frame (wall), process CPU \(.cpu_ms_per_frame | . * 100 | round / 100) ms/frame",
         (.stage_ms_per_frame | to_entries | map("  \(.key) \(.value | . * 100 | round / 100) ms") | .[]),
         (if .ate then "ATE rmse \(.ate.rmse_m * 1000 | round / 10) cm, mean \(.ate.mean_m * 1000 | round / 10) cm, max \(.ate.max_m * 1000 | round / 10) cm, unaligned mean \(.ate.unaligned_mean_m * 1000 | round / 10) cm"
          else "ATE: no ground truth" end)' "$dir/summary.json"
  echo "peak RSS $((rss_kb / 1024)) MiB"
done
