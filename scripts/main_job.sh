#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build, and run the main job on the default input.
#
# The default input is ../shared/data/7scenes-redkitchen-a (600 real Kinect frames) when that directory is
# present beside the checkout; otherwise a synthetic living-room sequence that the project renders itself
# along its built-in handheld trajectory. Outputs go to out/ (or the directory given as $1).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/out"}
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" "$root/build"
tool="$root/build/tools/slambooster/slambooster"
mkdir -p "$out"

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

"$tool" run "$seq" --out "$out/run-$name" --preset default --mesh
echo "main_job: outputs in $out/run-$name (trajectory.tum, frames.jsonl, summary.json, model.png, mesh.ply)"
