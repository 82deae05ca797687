#!/usr/bin/env bash
# One map from two runs (issue 55): run 1 drives the first part of a corridor drive with a new map store, run 2
# is the robot restarted at a place of run 1's drive and driving on to the end (the rest of the drive and back
# over run 1's part), given run 1's store. Run 2's map.pgm covers everything the store holds, in run 1's frame;
# it is scored against the corridor's true occupancy (`slambooster eval-map --frame-of`: aligned by run 1's frame,
# no refit on run 2), next to run 1's own grid and run 2's poses in run 1's frame.
#
# usage: scripts/map_store_grid.sh OUT [CONTROLLER] [CASE...]
#   CASE: NAME:SEED:LENGTH_M:RUN1_TO:RUN2_FROM (default: the three below). Images 160x120 to keep the runs short;
#   SCALE=2 in the environment for 320x240 (the focal lengths scaled with them).
# Prints one line per case; every run's outputs stay under OUT.
set -euo pipefail
out=${1:?usage: scripts/map_store_grid.sh OUT [CONTROLLER] [CASE...]}
controller=${2:-default}
shift $(($# < 2 ? $# : 2))
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(b0-12m:0:12:330:200 b3-12m:3:12:330:200 b0-16m:0:16:430:290)
tool=${SLAMBOOSTER:-build/tools/slambooster/slambooster}
scale=${SCALE:-1}
mkdir -p "$out"

score() {  # eval-map's output -> "precision P recall R"
  awk '/^precision/ {p = $2} /^recall/ {r = $2} END {printf "precision %s recall %s", p, r}'
}

printf 'case controller | run 1 alone | run 2 localised at, in run 1 frame | both runs (run 2 map.pgm)\n'
for c in "${cases[@]}"; do
  IFS=: read -r name seed length to from <<<"$c"
  d=$out/$name-$controller-x$scale
  rm -rf "$d" && mkdir -p "$d"
  synth="$tool synth --scene corridor --corridor-length $length --stress drive --seed $seed --threads 2"
  synth+=" --width $((160 * scale)) --height $((120 * scale)) --fx $(echo "120.3 * $scale" | bc) --fy $((120 * scale))"
  $synth --frames-to "$to" --out "$d/run1" >"$d/synth1.log" 2>&1
  $synth --frames-from "$from" --out "$d/run2" >"$d/synth2.log" 2>&1
  run="$tool run --controller $controller --volume-size 5 --threads 2 --quiet"
  $run "$d/run1" --map-store "$d/store" --out "$d/out1" >"$d/run1.log" 2>&1
  $run "$d/run2" --map-store "$d/store" --out "$d/out2" >"$d/run2.log" 2>&1
  grid="$tool eval-map --seed $seed --corridor-length $length"
  one=$($grid "$d/out1" "$d/run1" | score)
  at=$(jq -r '.map_store.localised_frame' "$d/out2/summary.json")
  if [ "$at" = null ]; then
    printf '%s %s | %s | never localised | -\n' "$name-x$scale" "$controller" "$one"
    continue
  fi
  ate=$($tool eval "$d/out2/trajectory.tum" "$d/run2/groundtruth.txt" --json \
          --frame-of "$d/out1/trajectory.tum" "$d/run1/groundtruth.txt" \
          --from-s "$(jq .map_store.localised_s "$d/out2/summary.json")" |
        jq -r '"rmse \(.ate.rmse_m * 100 | . * 10 | round / 10) cm, max \(.ate.max_m * 100 | . * 10 | round / 10) cm"')
  both=$($grid "$d/out2" "$d/run2" --frame-of "$d/out1/trajectory.tum" "$d/run1/groundtruth.txt" \
           --picture "$d/both.pgm" | score)
  printf '%s %s | %s | frame %s, %s | %s (%s cells)\n' "$name-x$scale" "$controller" "$one" "$at" "$ate" "$both" \
    "$(jq -r '"\(.occupied_cells) occupied, \(.free_cells) free"' "$d/out2/map_frame.json")"
done
