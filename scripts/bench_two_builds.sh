#!/usr/bin/env bash
# Two builds side by side (issue 43): `slambooster run` of each build in turn, pair after pair, on the same
# sequence and controller, and per pair the ratio NEW/OLD of computation ms/frame and of each stage's ms/frame
# (from summary.json), with both ATEs and tracked shares. The machine's drift cancels within a pair: quote the
# median ratio.
#
#   scripts/bench_two_builds.sh OLD_BUILD NEW_BUILD SEQUENCE CONTROLLER [PAIRS] [-- extra run options]
#
# e.g. scripts/bench_two_builds.sh ../base/build build ../shared/data/7scenes-redkitchen-a default 3 -- --frames 300
set -euo pipefail
old=$1 new=$2 sequence=$3 controller=$4 pairs=${5:-3}
shift $(( $# > 5 ? 5 : $# ))
[ "${1:-}" = "--" ] && shift
out=$(mktemp -d /tmp/bench_two_builds.XXXXXX)
for i in $(seq 1 "$pairs"); do
  "$old/tools/slambooster/slambooster" run "$sequence" --out "$out/old$i" --controller "$controller" --fixed-volume \
    --threads 2 --quiet "$@" > "$out/old$i.log" 2>&1
  "$new/tools/slambooster/slambooster" run "$sequence" --out "$out/new$i" --controller "$controller" --fixed-volume \
    --threads 2 --quiet "$@" > "$out/new$i.log" 2>&1
done
# summary.json through its type (`slambooster summary` of NEW, which reads OLD's files too; null: no ground truth)
python3 - "$out" "$pairs" "$new/tools/slambooster/slambooster" <<'PY'
import json, statistics, subprocess, sys
out, pairs, tool = sys.argv[1], int(sys.argv[2]), sys.argv[3]
keys = ["computation_ms_per_frame", "stage_ms_per_frame", "ate.rmse_m", "tracked_percent", "integrated", "work"]
def load(run):
    args = [tool, "summary", run, "--missing", "null"]
    for k in keys: args += ["--get", k]
    values = subprocess.run(args, check=True, capture_output=True, text=True).stdout.rstrip("\n").split("\t")
    return dict(zip(keys, map(json.loads, values)))
rows = []
for i in range(1, pairs + 1):
    o, n = load(f"{out}/old{i}"), load(f"{out}/new{i}")
    rows.append((o, n))
def med(f):
    return statistics.median(f(o, n) for o, n in rows)
o0, n0 = rows[0]
print(f"outputs in {out}; {pairs} pairs; medians")
print(f"computation ms/frame: old {med(lambda o, n: o['computation_ms_per_frame']):.2f}, "
      f"new {med(lambda o, n: n['computation_ms_per_frame']):.2f}, "
      f"new/old {med(lambda o, n: n['computation_ms_per_frame'] / o['computation_ms_per_frame']):.3f}")
for stage in o0["stage_ms_per_frame"]:
    if o0["stage_ms_per_frame"][stage] <= 0: continue
    print(f"  {stage:17s} old {med(lambda o, n: o['stage_ms_per_frame'][stage]):8.3f}  new "
          f"{med(lambda o, n: n['stage_ms_per_frame'][stage]):8.3f}  new/old "
          f"{med(lambda o, n: n['stage_ms_per_frame'][stage] / max(o['stage_ms_per_frame'][stage], 1e-9)):.3f}")
ate = lambda s: s["ate.rmse_m"] * 100 if s["ate.rmse_m"] is not None else float("nan")
print(f"ATE cm: old {ate(o0):.3f}, new {ate(n0):.3f}; tracked %: old {o0['tracked_percent']:.1f}, new {n0['tracked_percent']:.1f};"
      f" integrated: old {o0['integrated']}, new {n0['integrated']}")
if n0["work"]: print("new work:", json.dumps(n0["work"]))
PY
