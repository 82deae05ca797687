#!/usr/bin/env bash
# The paper's experiments (issue 5) as one command: renders the synthetic sequences, runs the offline
# design-space exploration per sequence, profiles the tc controller's table on two profiling sets, then
# `slambooster bench` over
# the whole set with every controller, and prints where report.md is.
#
# usage: scripts/bench_paper.sh [--frames N] [--jobs N] [--quick] [--plan] [OUT] [BUILD]
#   OUT        output directory (default out/bench-paper); everything generated lands here:
#                OUT/sequences/  the rendered synthetic sequences (TUM layout, with ground truth)
#                OUT/dse/NAME/   `slambooster dse` per sequence (best.json = the offline column's setting)
#                OUT/profile-real/, OUT/profile-synth/  `slambooster profile` per profiling set (tc_table.json)
#                OUT/bench/      `slambooster bench`: report.md, report.html, results.csv, *.svg, runs/
#   BUILD      build directory holding tools/slambooster/slambooster (default build/)
#   --frames N process (and render) at most N frames per sequence: a quick check of the whole chain
#   --jobs N   runs in parallel (default 2), each with one worker thread
#   --quick    2-setting dse and profile grids instead of the full ones (with --frames: a smoke test)
#   --plan     print the sequences and how many runs remain, then stop
#   --emit-plan FILE  for a cluster (README "Using the tool", docs/experiments.md): render the sequences here, then write the
#              runs of the next stage as one plan, one self-contained command per line, for Slurm
#              (scripts/slurm_run.sbatch) or GNU parallel, and stop. Stage 1 is every dse and profile run
#              (about 1,200 of the ~1,350); once they are all complete, the next call writes their
#              results (best.json, tc_table.json) and stage 2, the bench runs. After stage 2 ran, the call
#              without --emit-plan runs nothing more and writes the report.
#
# Resumable: rendered sequences are kept (each is rendered into NAME.partial and renamed when complete),
# and dse, profile and bench skip the runs whose summary.json says complete; re-running the same command
# continues where it stopped. OUT remembers its --frames / --quick setting and refuses another one (runs of a
# different length must not mix).
#
# The sequence set (11 sequences, about 11,200 frames):
#   7scenes-redkitchen-a   ../shared/data/7scenes-redkitchen-a (real, 600 frames), when present
#   synth-SCENE-trajT      scenes livingroom and office along the ICL-NUIM living-room trajectories
#                          ../shared/data/icl-nuim-trajectories/livingroomT.tum, T = 0..3 (1508, 965, 880 and
#                          1240 frames), seed 0
#   stress-bursts          `slambooster synth --stress bursts`, livingroom, seed 0 (468 frames: four 0.5 s
#                          bursts that move and turn at once, 0.5-1.15 m/s and 30-55 deg/s, between calm
#                          stretches; one passes the pose corrector's 0.035 m/frame)
#   stress-blank-wall      `slambooster synth --stress blank-wall`, office, seed 0 (538 frames: 6 s panning in
#                          front of a blank stretch at a room corner; the smooth-surface detector fires on
#                          every frame, the side wall and floor at the image border keep ICP constrained)
# Both stress sequences are tracked by DEFAULT (full precision): ATE well under 1 cm, 100% tracked.
# Every sequence has ground truth (the synthetic ones: their trajectory), so ATE is against ground truth.
#
# The tc controller gets two tables, as the paper's TC table has two profiling sets: "real", profiled on
# the real 7scenes-redkitchen-a (without the real data, synth-livingroom-traj2 stands in), and "synth",
# profiled on synth-office-traj2 (the shortest ICL-NUIM trajectory, in the other scene). Each runs at the 3
# reference velocities (columns tc-real@V, tc-synth@V). The profiled sequences stay in the bench set (as in
# the paper, tc is profiled on sequences it is also run on), so tc is if anything favoured there.
#
# Runs: dse 96 settings x 11 sequences, profile 72 settings x 1 sequence x 2 sets, bench 14 columns x 11
# sequences (default, accurate, pid, pid+surface, pid+surface+correction, slambooster, step, tc of each set at
# 3 reference velocities, offline).
# Time estimate for the full set, CPU backend, --jobs 2 --threads 1 on an idle 2-core machine: ~32 hours.
# From process CPU ms/frame measured at b35e4d0 on this machine class (single runs of 60-511 frames): DEFAULT
# 340-370, csr=2 175-185, csr=4 118-128 (ir=1), csr=8 15 where it loses tracking (nothing is integrated)
# and ~110 where it tracks, slambooster ~120 on stress-blank-wall (README: 0.24 x DEFAULT on 7-Scenes);
# rendering 66 ms/frame. Hence dse ~27 h (96 settings x ~10,800 frames x ~190 ms mean / 2 cores), profile
# ~2.5 h (72 x 1,480 frames x ~170 ms / 2), bench ~3 h (per frame of the set: DEFAULT 350 + ACCURATE 420 +
# 9 approximate columns x ~120 ms, / 2; the second tc set adds ~0.5 h), rendering ~10 min. (The CPU
# backend got ~1.5-2x faster since, at the same results: these are upper bounds.) On a shared, loaded machine wall time was 3-4x
# the CPU time. `--frames 20 --quick` took 20 minutes there (3 minutes on the idle machine at 15feaed). The dse figure is for running every setting to the
# end: dse now stops a run once it is slower than the fastest setting within the bound so far, which took
# 3.0x less computation time (2.3-4.4x per sequence) on 8 synthetic sequences with a 36-setting grid
# (f638528, 2026-11-24; scripts/dse_savings.py).
# Expect more with the 96-setting grid, half of whose settings are at csr 1 and 2.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

frames=0 jobs=2 quick=0 plan=0 emit_plan=""
bench_args=()
positional=()
while [ $# -gt 0 ]; do
  case "$1" in
    --frames) frames=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --plan) plan=1; shift ;;
    --emit-plan) emit_plan=$(realpath -m "$2"); shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "bench_paper: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) positional+=("$1"); shift ;;
  esac
done
out=$(realpath -m "${positional[0]:-$root/out/bench-paper}")
build=$(realpath -m "${positional[1]:-$root/build}")
bin="$build/tools/slambooster/slambooster"
data=$(realpath -m "$root/../shared/data")
[ -x "$bin" ] || { echo "bench_paper: $bin not found (build first: scripts/build.sh $build)" >&2; exit 1; }
[[ "$frames" =~ ^[0-9]+$ && "$jobs" =~ ^[1-9][0-9]*$ ]] ||
  { echo "bench_paper: --frames needs a number >= 0 and --jobs one >= 1 (got '$frames', '$jobs')" >&2; exit 2; }
trajectories="$data/icl-nuim-trajectories"
[ -d "$trajectories" ] || { echo "bench_paper: $trajectories not found (the ICL-NUIM trajectories)" >&2; exit 1; }

# Knob grids: the tools' full defaults, or two settings each with --quick.
# shellcheck disable=SC2054  # the commas separate the values of one option
if [ "$quick" = 1 ]; then
  dse_grid=(--csr 2,8 --icp 1e-05 --pd0 4 --ir 1)
  profile_grid=(--csr 2,8 --icp 1e-4 --pd0 4 --ir 1)
  dse_settings=2 profile_settings=3  # + DEFAULT, which profile always runs
else
  dse_grid=(--csr 1,2,4,8 --icp 0,1e-6,1e-5,1e-4,1e-3,1 --pd0 10,8,6,4 --ir 1)
  profile_grid=(--csr 1,2,4,8 --icp 1e-5,1e-4,1e-3 --pd0 10,6,4 --ir 1,2)
  dse_settings=96 profile_settings=72  # DEFAULT is in this grid
fi
controllers=default,accurate,pid,pid+surface,pid+surface+correction,slambooster,step
tc_velocities=0.005,0.01,0.02
bench_columns=14  # 7 controllers + 2 sets x 3 tc + offline

setting="frames=$frames quick=$quick"
if [ -f "$out/setting" ] && [ "$(cat "$out/setting")" != "$setting" ]; then
  echo "bench_paper: $out was started with '$(cat "$out/setting")', not '$setting': runs of another length" \
       "or grid must not mix; use another OUT or remove it" >&2
  exit 1
fi

# The sequence set: NAME -> how to make it (a path for existing data, or synth arguments).
names=() paths=() to_render=()
declare -A synth_args
if [ -d "$data/7scenes-redkitchen-a" ]; then
  names+=(7scenes-redkitchen-a) paths+=("$data/7scenes-redkitchen-a")
else
  echo "bench_paper: $data/7scenes-redkitchen-a not found: the real sequence is left out" >&2
fi
for scene in livingroom office; do
  for t in 0 1 2 3; do
    synth_args[synth-$scene-traj$t]="--scene $scene --trajectory $trajectories/livingroom$t.tum"
  done
done
synth_args[stress-bursts]="--scene livingroom --stress bursts"
synth_args[stress-blank-wall]="--scene office --stress blank-wall"
for scene in livingroom office; do
  for t in 0 1 2 3; do names+=("synth-$scene-traj$t"); done
done
names+=(stress-bursts stress-blank-wall)
rendered_ok() {  # a complete render of at least the frames we need
  local marker="$out/sequences/$1/.rendered"
  [ -f "$marker" ] || return 1
  local have; have=$(cat "$marker")
  [ "$have" = 0 ] || { [ "$frames" != 0 ] && [ "$have" -ge "$frames" ]; }
}
for name in "${names[@]}"; do
  [ -n "${synth_args[$name]:-}" ] || continue
  paths+=("$out/sequences/$name")
  rendered_ok "$name" || to_render+=("$name")
done
# The two profiling sets of the tc tables: NAME -> sequence.
if [ -d "$data/7scenes-redkitchen-a" ]; then
  profile_real="$data/7scenes-redkitchen-a"
else
  profile_real="$out/sequences/synth-livingroom-traj2"  # stand-in without the real data
fi
profile_synth="$out/sequences/synth-office-traj2"

# How many runs remain: expected runs minus those whose summary.json says complete.
complete_runs() {
  local n=0 f
  for f in "$@"; do grep -qs '"complete": *true' "$f" && n=$((n + 1)); done
  echo "$n"
}
# shellcheck disable=SC2086  # $1 is a glob
count() { shopt -s nullglob; complete_runs $1; shopt -u nullglob; }
nseq=${#names[@]}
dse_total=$((dse_settings * nseq)) profile_total=$((profile_settings * 2))
bench_total=$((bench_columns * nseq))
dse_done=$(count "$out/dse/*/runs/*/summary.json")
profile_done=$(count "$out/profile-*/runs/*/*/summary.json")
bench_done=$(count "$out/bench/runs/*/*/summary.json")
remaining=$((dse_total - dse_done + profile_total - profile_done + bench_total - bench_done))
echo "bench_paper: $nseq sequences (${#to_render[@]} to render) in $out; frames per run: ${frames/#0/all};" \
     "grids: $([ "$quick" = 1 ] && echo quick || echo full)"
echo "bench_paper: runs remaining: $remaining of $((dse_total + profile_total + bench_total))" \
     "(dse $((dse_total - dse_done))/$dse_total, profile $((profile_total - profile_done))/$profile_total," \
     "bench $((bench_total - bench_done))/$bench_total); $jobs at a time"
[ "$plan" = 1 ] && exit 0
mkdir -p "$out/sequences"
echo "$setting" > "$out/setting"

# 1. Render the synthetic sequences that are missing.
for name in "${to_render[@]}"; do
  dir="$out/sequences/$name"
  echo "bench_paper: rendering $name"
  rm -rf "$dir" "$dir.partial"
  # shellcheck disable=SC2086  # synth_args holds several arguments
  "$bin" synth --out "$dir.partial" --overwrite --seed 0 --frames "$frames" --threads "$jobs" ${synth_args[$name]}
  echo "$frames" > "$dir.partial/.rendered"
  mv "$dir.partial" "$dir"
done

# --emit-plan: the next stage's runs as one plan, instead of running them.
dse_command() { echo "$bin" dse "${paths[$1]}" --out "$out/dse/${names[$1]}" "${dse_grid[@]}" --frames "$frames" --threads 1; }
profile_command() {
  local sequence=$profile_real
  [ "$1" = synth ] && sequence=$profile_synth
  echo "$bin" profile "$sequence" --out "$out/profile-$1" "${profile_grid[@]}" --frames "$frames" --threads 1
}
if [ -n "$emit_plan" ]; then
  mkdir -p "$(dirname "$emit_plan")"
  : > "$emit_plan.partial"
  if [ "$dse_done" -lt "$dse_total" ] || [ "$profile_done" -lt "$profile_total" ]; then
    stage="1 (dse and profile)"
    for i in "${!names[@]}"; do
      $(dse_command "$i") --plan "$out/plans/dse-${names[$i]}.txt" > /dev/null
      cat "$out/plans/dse-${names[$i]}.txt" >> "$emit_plan.partial"
    done
    for set in real synth; do
      $(profile_command "$set") --plan "$out/plans/profile-$set.txt" > /dev/null
      cat "$out/plans/profile-$set.txt" >> "$emit_plan.partial"
    done
  else
    stage="2 (bench)"
    for i in "${!names[@]}"; do $(dse_command "$i") --report-only > /dev/null; done
    for set in real synth; do $(profile_command "$set") --report-only > /dev/null; done
    bench_args=(--plan "$out/plans/bench.txt")
  fi
fi

# 2. The offline column: the best fixed setting per sequence.
[ -n "$emit_plan" ] || for i in "${!names[@]}"; do
  echo "bench_paper: dse ${names[$i]}"
  "$bin" dse "${paths[$i]}" --out "$out/dse/${names[$i]}" "${dse_grid[@]}" --frames "$frames" --jobs "$jobs" \
    --threads 1
done

# 3. The tc controller's tables, one per profiling set.
[ -n "$emit_plan" ] || for set in real synth; do
  sequence=$profile_real
  [ "$set" = synth ] && sequence=$profile_synth
  echo "bench_paper: profile set $set on ${sequence##*/}"
  "$bin" profile "$sequence" --out "$out/profile-$set" "${profile_grid[@]}" --frames "$frames" --jobs "$jobs" \
    --threads 1
done

# 4. Every sequence under every controller, and the report.
if [ -n "$emit_plan" ] && [ "${bench_args[0]:-}" != --plan ]; then
  mv "$emit_plan.partial" "$emit_plan"
  echo "bench_paper: stage $stage: $(wc -l < "$emit_plan") runs in $emit_plan (Slurm: scripts/slurm_run.sbatch," \
       "GNU parallel: parallel --will-cite < $emit_plan); when they are done, run the same --emit-plan again"
  exit 0
fi
echo "bench_paper: bench"
"$bin" bench "${paths[@]}" --out "$out/bench" --controllers "$controllers" --dse-dir "$out/dse" \
  --tc-table real="$out/profile-real/tc_table.json" --tc-table synth="$out/profile-synth/tc_table.json" \
  --tc-velocities "$tc_velocities" --plot-sequence stress-bursts \
  --frames "$frames" --jobs "$jobs" --threads 1 "${bench_args[@]}" > "$out/bench.log"
if [ -n "$emit_plan" ]; then
  mv "$out/plans/bench.txt" "$emit_plan" && rm -f "$emit_plan.partial"
  echo "bench_paper: stage $stage: $(wc -l < "$emit_plan") runs in $emit_plan (Slurm: scripts/slurm_run.sbatch," \
       "GNU parallel: parallel --will-cite < $emit_plan); when they are done, scripts/bench_paper.sh without" \
       "--emit-plan writes the report"
  exit 0
fi
echo "bench_paper: done; report in $out/bench/report.md and $out/bench/report.html (bench output: $out/bench.log)"
