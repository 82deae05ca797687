#!/usr/bin/env bash
# Benchmark of the compute backends: runs `slambooster run` on a sequence (default: the 7-Scenes redkitchen
# sequence of the shared data) for each backend x controller and prints ms/frame (host wall clock of the
# computation stages, as in the paper), the frame rate that gives, the summed OpenCL kernel times per frame
# (profiling events), and the ATE.
#
# usage: scripts/bench_backends.sh [SEQUENCE] [BUILD_DIR] [FRAMES] [BACKENDS] [CONTROLLERS]
#   SEQUENCE     sequence directory (default ../shared/data/7scenes-redkitchen-a, relative to the repo root)
#   BUILD_DIR    build directory holding tools/slambooster/slambooster (default build/)
#   FRAMES       frames per run (default 0 = all)
#   BACKENDS     comma-separated, from: cpu, opencl, opencl-half (half storage of the preprocessed and raycast
#                maps) (default "cpu,opencl,opencl-half")
#   CONTROLLERS  comma-separated `run --controller` names (default "default,slambooster" where the build has
#                the slambooster controller, else "default")
# Environment: OPENCL_PLATFORM / OPENCL_DEVICE select the OpenCL device (index or name substring; default:
# the backend's automatic choice). Run on an otherwise idle machine for numbers worth comparing.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sequence=${1:-"$root/../shared/data/7scenes-redkitchen-a"}
build=${2:-"$root/build"}
frames=${3:-0}
backends=${4:-cpu,opencl,opencl-half}
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_backends: $bin not found (build first: scripts/build.sh $build)" >&2; exit 1; }
[ -d "$sequence" ] || { echo "bench_backends: sequence '$sequence' not found" >&2; exit 1; }
command -v jq >/dev/null || { echo "bench_backends: jq is needed to read the outputs (apt-get install jq)" >&2; exit 1; }
if [ -n "${5:-}" ]; then
  controllers=$5
elif "$bin" run --help 2>/dev/null | grep -q "slambooster:"; then
  controllers=default,slambooster
else
  controllers=default
fi
out=$(mktemp -d /tmp/bench_backends.XXXXXX)
echo "sequence $sequence, frames ${frames/#0/all}, $(nproc) cores, outputs in $out"

# One config file per backend (the run command takes the backend from its --config file).
config() {
  local backend=opencl half=false
  case "$1" in
    cpu) backend=cpu ;;
    opencl) ;;
    opencl-half) half=true ;;
    *) echo "bench_backends: unknown backend '$1' (cpu, opencl, opencl-half)" >&2; exit 1 ;;
  esac
  jq -n --arg b "$backend" --argjson h "$half" --arg p "${OPENCL_PLATFORM:-}" --arg d "${OPENCL_DEVICE:-}" \
    'if $b == "cpu" then {backend: $b} else {backend: $b, opencl_half_storage: $h, opencl_platform: $p, opencl_device: $d} end'
}

printf '%-12s %-12s %8s %10s %8s %12s %9s %s\n' backend controller frames "ms/frame" fps "device ms" "ATE cm" tracked
for backend in ${backends//,/ }; do
  config "$backend" > "$out/$backend.json"
  for controller in ${controllers//,/ }; do
    dir="$out/$backend-$controller"
    if ! "$bin" run "$sequence" --out "$dir" --config "$out/$backend.json" --controller "$controller" \
        --frames "$frames" --quiet > "$dir.log" 2>&1; then
      echo "bench_backends: $backend / $controller failed:" >&2
      tail -5 "$dir.log" >&2
      continue
    fi
    device=$(grep -o "compute backend: .*" "$dir.log" | head -1 || true)
    [ -n "$device" ] && echo "  ($backend: $device)" >&2
    ms=$("$bin" summary "$dir" --get computation_ms_per_frame)
    device_ms=$(jq -s 'map((.device_ms // {}) | to_entries | map(select(.key != "render") | .value) | add // 0)
                       | add / length' "$dir/frames.jsonl")
    # summary.json through its type (`slambooster summary`; "-": no ground truth)
    "$bin" summary "$dir" --missing - --get frames --get ate.rmse_m --get tracked --get tracking_attempted |
      awk -F'\t' -v b="$backend" -v c="$controller" -v d="$device_ms" -v ms="$ms" '{
        dev = d > 0 ? sprintf("%.2f", d) : "-"; ate = $2 == "-" ? "-" : sprintf("%.2f", $2 * 100)
        printf "%-12s %-12s %8s %10.2f %8.1f %12s %9s %s/%s\n", b, c, $1, ms, 1000 / ms, dev, ate, $3, $4 }'
  done
done
