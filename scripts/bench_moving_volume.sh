#!/usr/bin/env bash
# Benchmark of the moving volume (README, The moving volume): a robot-like drive several volumes long, rendered
# with `slambooster synth` in the procedural living room (6.8 m long): along the room's long axis (z from -3.0
# to 2.6 m and back, 2.5 cm per frame, weaving +-10 cm across it so that the ground truth spans a plane), the
# camera 1.25 m above the floor looking sideways at the furnished wall 1.5 m away (ahead, the Kinect range
# would see mostly the far wall beyond 4 m in this room). Each controller runs it three ways with the same
# voxel size (1.56 cm):
#   fixed-small  a 2 m volume at 128^3 (the camera leaves it after about a metre)
#   fixed-big    one 8 m volume at 512^3 that holds the whole room
#   moving       the 2 m volume at 128^3 following the camera (slabs meshed into map_slabs/ as they leave)
# and prints tracked %, ATE, ms/frame (computation stages), the shift's ms per frame (moving the voxels and
# the skipping grid; copying out and meshing the slabs separately), and the peak resident memory
# (/usr/bin/time -v).
#
# usage: scripts/bench_moving_volume.sh [BUILD_DIR] [OUT] [CONTROLLERS] [SIZE]
#   BUILD_DIR    build directory holding tools/slambooster/slambooster (default build/)
#   OUT          output directory (default /tmp/bench_moving_volume)
#   CONTROLLERS  comma-separated `run --controller` names (default "default,adaptive")
#   SIZE         WIDTHxHEIGHT of the rendered frames (default 320x240)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
out=${2:-/tmp/bench_moving_volume}
controllers=${3:-default,adaptive}
size=${4:-320x240}
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_moving_volume: $bin not found (build first: scripts/build.sh $build)" >&2; exit 1; }
command -v jq >/dev/null || { echo "bench_moving_volume: jq is needed (apt-get install jq)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "bench_moving_volume: /usr/bin/time is needed (apt-get install time)" >&2; exit 1; }
mkdir -p "$out"

# The drive: there and back, looking along -x. TUM: t x y z qx qy qz qw.
seq_dir="$out/drive"
if [ ! -f "$seq_dir/groundtruth.txt" ]; then
  awk 'BEGIN {
    fps = 30; step = 0.025; z0 = -3.0; z1 = 2.6; s = sin(-3.14159265358979 / 4); c = cos(-3.14159265358979 / 4)
    n = int((z1 - z0) / step + 0.5); i = 0
    for (k = 0; k <= n; ++k) { printf "%.6f %.6f 0 %.6f 0 %.9f 0 %.9f\n", i / fps, -1.0 + 0.1 * sin(i * 0.05), z0 + k * step, s, c; ++i }
    for (k = 1; k <= n; ++k) { printf "%.6f %.6f 0 %.6f 0 %.9f 0 %.9f\n", i / fps, -1.0 + 0.1 * sin(i * 0.05), z1 - k * step, s, c; ++i }
  }' > "$out/drive_trajectory.txt"
  width=${size%x*} height=${size#*x}
  "$bin" synth --scene livingroom --trajectory "$out/drive_trajectory.txt" --width "$width" --height "$height" \
    --fx "$(awk -v w="$width" 'BEGIN { print 481.2 * w / 640 }')" \
    --fy "$(awk -v h="$height" 'BEGIN { print 480 * h / 480 }')" --out "$seq_dir" --overwrite > "$out/synth.log"
fi
frames=$(wc -l < "$out/drive_trajectory.txt")

printf '%-10s %-12s %8s %9s %9s %9s %7s %10s %10s\n' controller volume tracked% ATE_cm ms/frame shift_ms slabs slab_ms peak_MiB
IFS=, read -ra names <<< "$controllers"
for controller in "${names[@]}"; do
  for variant in fixed-small fixed-big moving; do
    case $variant in
      fixed-small) args=(--volume-size 2 --volume-resolution 128 --initial-position 0.2,0.5,0.2 --fixed-volume) ;;
      fixed-big) args=(--volume-size 8 --volume-resolution 512 --initial-position 0.1,0.5,0.5 --fixed-volume) ;;
      moving) args=(--volume-size 2 --volume-resolution 128 --initial-position 0.2,0.5,0.2 --mesh) ;;
    esac
    run="$out/runs/$controller-$variant"
    rm -rf "$run"
    mkdir -p "$run"
    /usr/bin/time -v -o "$run/time.txt" "$bin" run "$seq_dir" --controller "$controller" "${args[@]}" \
      --out "$run" --quiet > "$run/run.log" 2>&1
    peak=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$run/time.txt")
    jq -r --arg c "$controller" --arg v "$variant" --arg p "$peak" --argjson n "$frames" '
      [$c, $v, .tracked_percent, ((.ate.rmse_m // -0.01) * 100), .computation_ms_per_frame,
       ((.moving_volume.shift_ms // 0) / $n), (.mesh_slabs // 0), ((.moving_volume.slab_ms // 0) / $n), $p]
      | "\(.[0]) \(.[1]) \(.[2]) \(.[3]) \(.[4]) \(.[5]) \(.[6]) \(.[7]) \(.[8])"' "$run/summary.json" |
      awk '{printf "%-10s %-12s %8.1f %9.2f %9.1f %9.3f %7d %10.2f %10s\n", $1, $2, $3, $4, $5, $6, $7, $8, $9}'
  done
done
echo "outputs in $out/runs"
