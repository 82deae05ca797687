#!/usr/bin/env bash
# Benchmark of the moving volume (docs/moving-volume.md): the corridor drive of docs/test-sequences.md (a
# wheeled robot's camera driving 2 x 17 m, `slambooster synth --scene corridor --stress drive`, seed 0, 1,200
# frames) at 320x240, run with one controller four ways:
#   fixed5      the default 5 m volume at 256^3, fixed (--fixed-volume): the paper's setting
#   moving5     the same volume following the camera (the default of `run`), with the whole run's map (--mesh)
#   moving5cam  the same following the camera itself instead of the view centre (volume_view_distance_m 0)
#   fixedbig    one fixed volume holding the whole path (the sequence's hint cube) at 512^3
# and prints tracked %, ATE, ms/frame (computation stages), the shift's cost per frame (the backend's move and
# the slab meshing, summed over the run / frames) and the peak resident memory (/usr/bin/time -v). Runs one
# after another (compare side by side on the same machine).
#
# usage: scripts/bench_moving_volume.sh [BUILD_DIR] [OUT] [CONTROLLER] [THREADS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
out=${2:-/tmp/bench_moving_volume}
controller=${3:-default}
threads=${4:-2}
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_moving_volume: $bin not found (build first)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench_moving_volume: /usr/bin/time is needed (apt-get install time)" >&2; exit 1; }
mkdir -p "$out"
seq="$out/seq"
[ -f "$seq/groundtruth.txt" ] ||
  "$bin" synth --scene corridor --stress drive --width 320 --height 240 --fx 240.6 --fy 240 --out "$seq" > "$out/synth.log"
echo '{"volume_view_distance_m": 0.0}' > "$out/camera.json"
printf '%-11s %8s %8s %9s %9s %7s %9s\n' volume tracked% ATE_cm ms/frame shift_ms shifts peak_MiB
for v in fixed5 moving5 moving5cam fixedbig; do
  case $v in
    fixed5) args=(--volume-size 5 --fixed-volume) ;;
    moving5) args=(--volume-size 5 --mesh) ;;
    moving5cam) args=(--volume-size 5 --config "$out/camera.json") ;;
    fixedbig) args=(--fixed-volume --volume-resolution 512) ;;
  esac
  run="$out/runs/$controller-$v"
  rm -rf "$run"
  mkdir -p "$run"
  /usr/bin/time -v -o "$run/time.txt" "$bin" run "$seq" --controller "$controller" --threads "$threads" "${args[@]}" \
    --out "$run" --quiet > "$run/run.log" 2>&1
  peak=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$run/time.txt")
  # "-": a field this run did not write (no ground truth: ATE -1; a fixed volume: no moving_volume, 0)
  "$bin" summary "$run" --missing - --get tracked_percent --get ate.rmse_m --get computation_ms_per_frame \
    --get moving_volume.shift_ms --get moving_volume.slab_ms --get moving_volume.shifts --get frames |
    awk -F'\t' -v v="$v" -v p="$peak" 'function n(x) { return x == "-" ? 0 : x }
      { printf "%-11s %8.1f %8.2f %9.1f %9.2f %7d %9s\n", v, $1, ($2 == "-" ? -1 : $2 * 100), $3,
               (n($4) + n($5)) / $7, n($6), p }'
done
echo "outputs in $out/runs"
