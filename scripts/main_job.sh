#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build, and run the main job on the default input.
#
# The main job is the daemon: slamboosterd replays the default input through KinectFusion under the adaptive
# controller (its default), publishing pose and knobs on its Unix socket while slamboosterctl shows progress,
# and exits when the sequence ends. Then DEFAULT (SLAMBench's fixed knobs) runs on the same input, and one
# line says how the two compare: frames, % tracked, ATE, ms/frame. The default input is ../shared/data/7scenes-redkitchen-a (600 real Kinect frames) when that
# directory is present beside the checkout; otherwise a synthetic living-room sequence that the project
# renders itself along its built-in handheld trajectory. Outputs go to out/ (or the directory given as $1):
# out/run-NAME/{trajectory.tum, frames.jsonl, summary.json, model.png, mesh.ply, report.html}, slamboosterd.log,
# and DEFAULT's run in out/default-NAME/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/out"}
"$root/scripts/install_deps.sh"
# Only the three programs the job runs (tests and their TSan builds come with scripts/test.sh).
"$root/scripts/build.sh" "$root/build" slambooster slamboosterd slamboosterctl
tool="$root/build/tools/slambooster/slambooster"
daemon="$root/build/daemon/slamboosterd"
ctl="$root/build/tools/slamboosterctl/slamboosterctl"
mkdir -p "$out"
out=$(cd "$out" && pwd)

shared="$root/../shared/data/7scenes-redkitchen-a"
if [ -d "$shared" ]; then
  seq="$shared"
  name=7scenes-redkitchen-a
  echo "main_job: input: real 7-Scenes sequence $seq"
else
  seq="$out/synthetic-livingroom"
  name=synthetic-livingroom
  if [ ! -f "$seq/calibration.json" ]; then
    echo "main_job: ../shared/data not found; rendering a synthetic sequence into $seq"
    "$tool" synth --out "$seq" --scene livingroom --builtin-frames 300 --overwrite
  fi
  echo "main_job: input: synthetic sequence $seq"
fi

# The socket lives in a private /tmp directory: Unix socket paths are limited to 107 bytes.
rundir=$(mktemp -d /tmp/slambooster-main-job-XXXXXX)
socket="$rundir/slamboosterd.sock"
pid=""
cleanup() {
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then kill -TERM "$pid"; wait "$pid" || true; fi
  rm -rf "$rundir"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

run="$out/run-$name"
rm -rf "$run"
echo "main_job: starting slamboosterd (socket $socket, log $out/slamboosterd.log)"
"$daemon" --input "$seq" --out "$run" --socket "$socket" --pacing fast --at-end exit --controller adaptive \
  --set output.mesh=true --set output.model_png=true 2> "$out/slamboosterd.log" &
pid=$!
for _ in $(seq 200); do [ -S "$socket" ] || ! kill -0 "$pid" 2>/dev/null && break; sleep 0.05; done
# Progress from the socket, as any client would see it, until the daemon finishes the sequence.
while kill -0 "$pid" 2>/dev/null; do
  # slamboosterctl's own status line (no JSON picking in shell): "N processed, T tracked, F fps, M ms/frame".
  line=$("$ctl" --socket "$socket" --timeout 2 status 2>/dev/null | sed -n 's/^  frames *//p' || true)
  [ -n "$line" ] && echo "main_job: slamboosterd: $line"
  sleep 5
done
status=0
wait "$pid" || status=$?
pid=""
if [ "$status" -ne 0 ]; then
  echo "main_job: slamboosterd failed (exit $status); its log:" >&2
  tail -20 "$out/slamboosterd.log" >&2
  exit "$status"
fi
tail -3 "$out/slamboosterd.log"
echo "main_job: outputs in $run (trajectory.tum, frames.jsonl, summary.json, model.png, mesh.ply, report.html)"
baseline="$out/default-$name"
echo "main_job: DEFAULT (fixed knobs, SLAMBench's settings) on the same input, for comparison: $baseline"
rm -rf "$baseline"
"$tool" run "$seq" --out "$baseline" --controller default --quiet > "$out/default.log"
echo "main_job: $("$tool" compare "$run" --against "$baseline")"
