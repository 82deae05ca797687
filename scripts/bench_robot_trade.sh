#!/usr/bin/env bash
# adaptive's trade on a robot (issue 41's last bar: at least 80% less time than DEFAULT with an ATE at most 1.25x
# DEFAULT's), measured over several drives rather than one: a centimetre-level ATE on one drive moves by a third with
# any small change (docs/odometry.md), so one drive decides nothing. Nine corridor drives of docs/test-sequences.md
# at 320x240 (2 x 17 m with an in-place U-turn), each with its own cheap base's odometry errors (scale, yaw scale,
# yaw bias in deg/s), run in the moving 5 m volume on one thread by DEFAULT, by adaptive and by adaptive with each
# CONFIG given (a JSON file of config keys, e.g. {"controller": {"adaptive": {"max_level_with_odometry": 0}}}).
# Prints per drive and run the ATE (cm) and the pipeline's computation ms/frame, then per run the mean ATE, the
# mean of its per-drive ATE ratios to DEFAULT and its total computation time over DEFAULT's. Runs one after
# another (compare ratios measured in one go, on one machine).
#
# usage: scripts/bench_robot_trade.sh [BUILD_DIR] [OUT] [CONFIG...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
out=${2:-/tmp/bench_robot_trade}
shift $(( $# > 2 ? 2 : $# ))
configs=("$@")
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_robot_trade: $bin not found (build first)" >&2; exit 1; }
for c in "${configs[@]}"; do [ -f "$c" ] || { echo "bench_robot_trade: config $c not found" >&2; exit 1; }; done
mkdir -p "$out"
# seed:scale:yaw_scale:yaw_bias_deg_per_s (seed 0 is synth's default base)
drives=(0:0.03:0.02:0.3 1:-0.03:-0.02:-0.3 2:-0.02:0.04:-0.2 3:0.02:0.03:0.5 4:0.04:-0.01:0.2 5:0.05:-0.03:0.6
        6:-0.04:0.01:-0.4 7:-0.01:-0.04:0.4 8:0.025:0.015:-0.5)
runs=(default adaptive)
for c in "${configs[@]}"; do runs+=("adaptive+$(basename "$c" .json)"); done

table="$out/table.tsv"
: > "$table"
printf '%-6s %-28s %8s %10s\n' drive run ATE_cm ms/frame
for spec in "${drives[@]}"; do
  IFS=: read -r seed scale yawscale yawbias <<< "$spec"
  seq="$out/drive$seed"
  [ -f "$seq/odometry.txt" ] ||
    "$bin" synth --scene corridor --stress drive --seed "$seed" --width 320 --height 240 --fx 240.6 --fy 240 \
      --odom-scale "$scale" --odom-yaw-scale "$yawscale" --odom-yaw-bias "$yawbias" --out "$seq" > "$seq.synth.log"
  for run in "${runs[@]}"; do
    controller=${run%%+*}
    args=()
    if [ "$run" != "$controller" ]; then
      for c in "${configs[@]}"; do [ "$(basename "$c" .json)" = "${run#*+}" ] && args=(--config "$c"); done
    fi
    dir="$out/$seed-$run"
    "$bin" run "$seq" --out "$dir" --controller "$controller" --threads 1 --volume-size 5 --quiet "${args[@]}" \
      > "$dir.log" 2>&1
    read -r ate ms < <("$bin" summary "$dir" --get ate.rmse_m --get computation_ms_per_frame | tr '\t' ' ')
    printf '%s\t%s\t%s\t%s\n' "$seed" "$run" "$ate" "$ms" >> "$table"
    python3 -c "import sys; print('%-6s %-28s %8.2f %10.2f' % (sys.argv[1], sys.argv[2], 100 * float(sys.argv[3]), float(sys.argv[4])))" \
      "$seed" "$run" "$ate" "$ms"
  done
done

python3 - "$table" <<'PY'
import collections, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
ate, ms, order = {}, collections.defaultdict(float), []
for seed, run, a, m in rows:
    ate[(seed, run)] = float(a)
    ms[run] += float(m)
    if run not in order: order.append(run)
seeds = sorted({s for s, _ in ate}, key=int)
print("\n%-28s %12s %22s %22s" % ("run", "mean ATE cm", "ATE / DEFAULT's (mean)", "time / DEFAULT's"))
for run in order:
    ratios = [ate[(s, run)] / ate[(s, "default")] for s in seeds]
    print("%-28s %12.2f %22.2f %22.3f" % (run, 100 * sum(ate[(s, run)] for s in seeds) / len(seeds),
                                           sum(ratios) / len(ratios), ms[run] / ms["default"]))
PY
