#!/usr/bin/env bash
# Issue 21's table in one resumable command: the product's controller (adaptive) against DEFAULT, the paper's
# slambooster, pid and candidate single fixed settings over the paper's 11 sequences plus the harder stress
# sequences (hard-bursts, robot, pan, corridor), then scripts/adaptive_table.py prints the table and the bars.
#
#   scripts/bench_adaptive.sh [OUT] [BUILD] [-- extra bench options, e.g. --dse-dir DSE for the offline column]
#
# OUT (default out/bench-adaptive) gets sequences/ (rendered once, seed 0) and bench/ (report.md, results.csv,
# report.html). Twelve fixed settings (--fixed columns, below) run beside the controllers: per sequence the
# fastest of them within the bound is the offline column, and over the whole set the best single setting (the
# one a user would pick without knowing the trajectory). Runs go two at a time, one thread each (--jobs 2
# --threads 1), so that every column is timed under the same conditions.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-"$root/out/bench-adaptive"}
build=${2:-"$root/build"}
shift $(( $# > 2 ? 2 : $# ))
[ "${1:-}" = "--" ] && shift
bin="$build/tools/slambooster/slambooster"
data="$root/../shared/data"
trajectories="$data/icl-nuim-trajectories"
[ -x "$bin" ] || { echo "bench_adaptive: $bin not found: build first (scripts/build.sh)" >&2; exit 1; }
mkdir -p "$out/sequences"

declare -A synth_args
names=()
for scene in livingroom office; do
  for t in 0 1 2 3; do
    synth_args[synth-$scene-traj$t]="--scene $scene --trajectory $trajectories/livingroom$t.tum"
    names+=("synth-$scene-traj$t")
  done
done
synth_args[stress-bursts]="--scene livingroom --stress bursts"
synth_args[stress-blank-wall]="--scene office --stress blank-wall"
for kind in hard-bursts robot pan corridor; do synth_args[stress-$kind]="--scene livingroom --stress $kind"; done
names+=(stress-bursts stress-blank-wall stress-hard-bursts stress-robot stress-pan stress-corridor)

paths=()
[ -d "$data/7scenes-redkitchen-a" ] && paths+=("$data/7scenes-redkitchen-a")
for name in "${names[@]}"; do
  seq="$out/sequences/$name"
  if [ ! -f "$seq/.rendered" ]; then
    echo "bench_adaptive: rendering $name"
    # shellcheck disable=SC2086  # the arguments are words
    "$bin" synth --out "$seq" ${synth_args[$name]} --seed 0 --overwrite > "$seq.log"
    touch "$seq/.rendered"
  fi
  paths+=("$seq")
done

# The grid of fixed settings: the ladder's coupled levels 2 and 3 (csr 4 and 8 with their icp and pd)
# integrating every 1st, 2nd, 4th and 8th frame, and level 1 (csr 2) every 4th and 8th (its denser rates are
# slower than every csr 4 setting). Per sequence its fastest setting within the bound is the offline column;
# over the whole set, the best single setting.
fixed=()
grid=()
declare -A level=([2]="icp=1e-5,pd=8:5:4" [4]="icp=1e-4,pd=6:5:4" [8]="icp=1e-4,pd=4:5:4")
declare -A rates=([2]="4 8" [4]="1 2 4 8" [8]="1 2 4 8")
for csr in 2 4 8; do
  for ir in ${rates[$csr]}; do
    fixed+=(--fixed "c${csr}i${ir}=csr=$csr,${level[$csr]},ir=$ir")
    grid+=("c${csr}i${ir}")
  done
done
"$bin" bench "${paths[@]}" --out "$out/bench" --controllers default,pid,slambooster,adaptive "${fixed[@]}" \
  --plot-sequence stress-hard-bursts --jobs 2 --threads 1 "$@"
python3 "$root/scripts/adaptive_table.py" "$out/bench/results.csv" --grid "$(IFS=,; echo "${grid[*]}")"
