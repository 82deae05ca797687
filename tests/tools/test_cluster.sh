#!/usr/bin/env bash
# The experiment matrix past one machine, run for real (architecture.md D5b): a small bench matrix (2 synthetic
# sequences x DEFAULT, SLAMBooster, ACCURATE; 20 frames each) run
#   reference  in one process (`slambooster bench`), the result every other case must equal;
#   parallel   as a plan run by GNU parallel with two workers (scripts/parallel_matrix.sh);
#   slurm      as a plan submitted to a single-node Slurm cluster started here from Debian's packages, one
#              array task per run, the report as a dependent job (scripts/slurm_matrix.sh);
#   kill       with GNU parallel, one worker killed with SIGKILL mid-run, the report before the rerun (the
#              killed run listed missing, not counted), then a rerun that completes the matrix.
# Equal means: the same runs, the same trajectories byte for byte, the same frames, % tracked and ATE in
# results.csv. Wall times go to WORK/wall_times.txt (the README quotes them).
#
#   test_cluster.sh CASE SLAMBOOSTER SCRIPTS_DIR WORK_DIR
#
# Without Slurm (or not as root) the slurm case says why and skips (exit 77), except under CI (CI set),
# where it fails: CI installs Slurm (scripts/install_deps.sh) and runs as root.
set -uo pipefail
case_name=$1 tool=$2 scripts=$3 work=$4
here=$(cd "$(dirname "$0")" && pwd)
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

seqs=("$work/office" "$work/room")
matrix() {  # the bench command of the matrix, into $1
  echo "$tool" bench "${seqs[@]}" --out "$1" --config "$work/small.json" --controllers default,slambooster \
    --frames 20 --threads 1
}
now() { date +%s.%N; }
# Whether the run in directory $1 says "complete": true, read through summary.json's type (`slambooster summary`,
# which fails on a key the schema lacks); no file yet, a run going on or a torn file: not complete.
complete() { [ "$("$tool" summary "$1" --get complete --missing false 2>/dev/null)" = true ]; }
record_time() { echo "$1 $(awk "BEGIN { printf \"%.1f\", $3 - $2 }") s" | tee -a "$work/wall_times.txt"; }

# Same runs, same trajectories byte for byte, same frames / % tracked / ATE as the reference.
same_as_reference() {
  local dir=$1 ref=$work/reference
  local want got
  want=$(cd "$ref/runs" && find . -name summary.json | sort)
  got=$(cd "$dir/runs" && find . -name summary.json | sort)
  [ "$want" = "$got" ] || fail "$dir: runs differ from the reference: [$got] vs [$want]"
  [ "$(echo "$want" | wc -l)" = 6 ] || fail "reference has $(echo "$want" | wc -l) runs, not 6"
  local run
  for run in $want; do
    run=$(dirname "$run")
    cmp -s "$ref/runs/$run/trajectory.tum" "$dir/runs/$run/trajectory.tum" ||
      fail "$dir/runs/$run/trajectory.tum differs from the one-process run's"
    complete "$dir/runs/$run" || fail "$dir/runs/$run is not complete"
    [ ! -e "$dir/runs/$run/.claim" ] || fail "$dir/runs/$run/.claim left behind"
  done
  # results.csv: sequence, controller, frames, tracked_percent, ate_rmse_m (the times differ by nature).
  want=$(cut -d, -f1-4,6 "$ref/results.csv" | sort)
  got=$(cut -d, -f1-4,6 "$dir/results.csv" | sort)
  [ "$want" = "$got" ] || fail "$dir/results.csv differs from the reference:"$'\n'"$got"$'\n'"vs"$'\n'"$want"
  [ "$(tail -n +2 "$dir/results.csv" | wc -l)" = 6 ] || fail "$dir/results.csv has not exactly 6 runs"
  grep -q "^> Machine: " "$dir/report.md" || fail "$dir/report.md does not say where the runs ran"
  ! grep -q "Incomplete" "$dir/report.md" || fail "$dir/report.md says runs are missing"
}

case "$case_name" in
  reference)
    rm -rf "$work" && mkdir -p "$work"
    "$tool" synth --out "$work/office" --scene office --builtin-frames 20 --no-noise --width 160 --height 120 \
      --fx 131 --fy 131 >/dev/null || fail "synth office"
    "$tool" synth --out "$work/room" --builtin-frames 20 --no-noise --width 160 --height 120 --fx 131 --fy 131 \
      >/dev/null || fail "synth room"
    echo '{"volume_resolution": 64}' >"$work/small.json"
    start=$(now)
    $(matrix "$work/reference") --quiet >"$work/reference.log" 2>&1 || { cat "$work/reference.log"; fail "bench"; }
    record_time "one_process" "$start" "$(now)"
    [ "$(tail -n +2 "$work/reference/results.csv" | wc -l)" = 6 ] || fail "reference: not 6 runs"
    ;;
  parallel)
    command -v parallel >/dev/null || { echo "FAIL: GNU parallel is not installed (scripts/install_deps.sh)"; exit 1; }
    rm -rf "$work/parallel"
    start=$(now)
    "$scripts/parallel_matrix.sh" -j 2 $(matrix "$work/parallel") >"$work/parallel.log" 2>&1 ||
      { cat "$work/parallel.log"; fail "parallel_matrix.sh"; }
    record_time "gnu_parallel_2_workers" "$start" "$(now)"
    [ "$(wc -l <"$work/parallel/plan.txt")" = 6 ] || fail "the plan has not 6 lines"
    same_as_reference "$work/parallel"
    ;;
  slurm)
    source "$here/slurm_cluster.sh"
    if ! slurm_start "$work/slurm-cluster"; then
      if [ -n "${CI:-}" ]; then echo "FAIL (CI): $slurm_why"; exit 1; fi
      echo "SKIP: $slurm_why"
      exit 77
    fi
    trap slurm_stop EXIT
    rm -rf "$work/slurm"
    start=$(now)
    "$scripts/slurm_matrix.sh" --at-once 2 --wait $(matrix "$work/slurm") >"$work/slurm.log" 2>&1 ||
      { cat "$work/slurm.log"; fail "slurm_matrix.sh"; }
    record_time "slurm_array_2_at_once" "$start" "$(now)"
    ls "$work/slurm/slurm/"run-*.out >/dev/null 2>&1 || fail "no array task output in $work/slurm/slurm"
    [ "$(ls "$work/slurm/slurm/"run-*.out | wc -l)" = 6 ] || fail "not 6 array tasks: $(ls "$work/slurm/slurm")"
    same_as_reference "$work/slurm"
    ;;
  kill)
    command -v parallel >/dev/null || { echo "FAIL: GNU parallel is not installed (scripts/install_deps.sh)"; exit 1; }
    dir=$work/killed
    rm -rf "$dir" && mkdir -p "$dir"
    $(matrix "$dir") --plan "$dir/plan.txt" >/dev/null || fail "--plan"
    parallel --will-cite -j 2 <"$dir/plan.txt" >"$work/kill-parallel.log" 2>&1 &
    parallel_pid=$!
    # Catch a run mid-run: frames logged, summary not complete; kill its worker (the claim's holder).
    victim=""
    for _ in $(seq 3000); do
      for claim in "$dir"/runs/*/*/.claim; do
        [ -e "$claim" ] || continue
        run=$(dirname "$claim")
        [ -s "$run/frames.jsonl" ] || continue
        complete "$run" && continue
        read -r host pid <"$claim" || continue
        if kill -9 "$pid" 2>/dev/null; then
          victim=$run
          break 2
        fi
      done
      sleep 0.01
    done
    wait "$parallel_pid"
    [ -n "$victim" ] || fail "no run was caught mid-run to kill"
    if [ -n "$victim" ]; then
      echo "killed the worker of $victim ($(grep -c . "$victim/frames.jsonl") frames logged)"
      ! complete "$victim" || fail "$victim completed after its worker was killed"
      # The report before the rerun: the killed run is missing, not counted.
      $(matrix "$dir") --report-only >"$work/kill-report.log" 2>&1 || fail "--report-only after the kill"
      grep -q "1 of 6 runs missing" "$work/kill-report.log" || fail "--report-only did not list the killed run"
      [ "$(tail -n +2 "$dir/results.csv" | wc -l)" = 5 ] || fail "results.csv counts the killed run"
      grep -q "Incomplete: 1 of 6" "$dir/report.md" || fail "report.md does not say a run is missing"
    fi
    "$scripts/parallel_matrix.sh" -j 2 $(matrix "$dir") >"$work/kill-rerun.log" 2>&1 ||
      { cat "$work/kill-rerun.log"; fail "the rerun"; }
    same_as_reference "$dir"
    ;;
  *) echo "unknown case '$case_name'"; exit 2 ;;
esac
[ "$failures" = 0 ] && echo "PASS: $case_name" || { echo "$failures failures in $case_name"; exit 1; }
