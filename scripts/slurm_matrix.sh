#!/usr/bin/env bash
# Runs a slambooster matrix (bench, dse or profile) on a Slurm cluster: writes the plan (OUT/plan.txt, one
# run per line), submits it as one array job (one task per run, at most K at once), and the report step
# (the same command with --report-only) as a job that starts after the array ended, whatever became of its
# tasks; the report lists the runs that are missing. OUT must be on a file system every node shares, and
# the slambooster binary and the sequences at the same paths on every node.
#
#   scripts/slurm_matrix.sh [--at-once K] [--sbatch "OPTIONS"] [--wait] slambooster bench SEQ... --out OUT ...
#
#   --at-once K     at most K array tasks at once (default 8): --array=0-N%K
#   --sbatch OPTS   more sbatch options for every job, e.g. "--partition=boards --cpus-per-task=4"
#   --wait          wait for the report job and exit with its status (default: print the job ids and return)
#
# Logs: OUT/slurm/run-<array>_<task>.out per run, OUT/slurm/report.out; the runs' own logs are OUT/runs/.../run.log.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
at_once=8
sbatch_options=""
wait_for_report=0
while [ $# -gt 0 ]; do
  case "$1" in
    --at-once) at_once=$2; shift 2 ;;
    --sbatch) sbatch_options=$2; shift 2 ;;
    --wait) wait_for_report=1; shift ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { sed -n '2,14p' "$0" >&2; exit 2; }
# shellcheck source=scripts/matrix_out.sh
. "$here/matrix_out.sh"
out=$(matrix_out_dir "$@")
[ -n "$out" ] || { echo "slurm_matrix: the command needs --out DIR (a directory every node shares)" >&2; exit 2; }
mkdir -p "$out/slurm"
out=$(cd "$out" && pwd)
plan="$out/plan.txt"
"$@" --plan "$plan"
runs=$(wc -l < "$plan")
[ "$runs" -gt 0 ] || { echo "slurm_matrix: the plan $plan is empty" >&2; exit 1; }
read -r -a extra <<< "$sbatch_options"
array=$(sbatch --parsable "${extra[@]}" --array="0-$((runs - 1))%$at_once" \
  --output="$out/slurm/run-%A_%a.out" "$here/slurm_run.sbatch" "$plan")
array=${array%%;*}
report_command="cd $(printf %q "$PWD") && $(printf '%q ' "$@") --report-only; echo \$? > $(printf %q "$out/slurm/report.status")"
rm -f "$out/slurm/report.status"
report=$(sbatch --parsable "${extra[@]}" --job-name=slambooster-report --dependency="afterany:$array" \
  --output="$out/slurm/report.out" --wrap "$report_command")
report=${report%%;*}
echo "slurm_matrix: $runs runs as array job $array (at most $at_once at once), report job $report"
echo "slurm_matrix: runs' output in $out/slurm, report in $out/slurm/report.out"
[ "$wait_for_report" = 1 ] || exit 0
while squeue -h -j "$array,$report" 2>/dev/null | grep -q .; do sleep 1; done
cat "$out/slurm/report.out" 2>/dev/null || true
if [ ! -f "$out/slurm/report.status" ]; then
  echo "slurm_matrix: the report job $report ended without running the report (see $out/slurm/report.out)" >&2
  exit 1
fi
exit "$(cat "$out/slurm/report.status")"
