#!/usr/bin/env bash
# Runs a slambooster matrix (bench, dse or profile) with GNU parallel, on this machine or, with
# --sshloginfile, on several (OUT, the slambooster binary and the sequences at the same paths on every one:
# a shared file system): writes the plan (OUT/plan.txt, one self-contained command per run), runs its lines
# K at a time, then the report (the same command with --report-only), which lists any run that is missing.
# Rerunning it after a worker was killed runs what is missing (claims of dead workers are taken over).
#
#   scripts/parallel_matrix.sh [-j K] [--sshloginfile FILE] slambooster bench SEQ... --out OUT ...
#
# By hand, the same three steps (--will-cite: parallel's citation notice would otherwise wait for input):
#   slambooster bench SEQ... --out OUT --plan OUT/plan.txt
#   parallel --will-cite -j 2 --sshloginfile nodes.txt --joblog OUT/parallel.log < OUT/plan.txt
#   slambooster bench SEQ... --out OUT --report-only
set -euo pipefail
jobs=2
ssh=()
while [ $# -gt 0 ]; do
  case "$1" in
    -j) jobs=$2; shift 2 ;;
    --sshloginfile) ssh=(--sshloginfile "$2"); shift 2 ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || { sed -n '2,14p' "$0" >&2; exit 2; }
# shellcheck source=scripts/matrix_out.sh
. "$(dirname "$0")/matrix_out.sh"
out=$(matrix_out_dir "$@")
[ -n "$out" ] || { echo "parallel_matrix: the command needs --out DIR" >&2; exit 2; }
mkdir -p "$out"
"$@" --plan "$out/plan.txt"
status=0
parallel --will-cite -j "$jobs" "${ssh[@]}" --joblog "$out/parallel.log" < "$out/plan.txt" || status=$?
[ "$status" = 0 ] || echo "parallel_matrix: $status runs failed (see $out/parallel.log); the report lists them" >&2
"$@" --report-only
exit "$status"
