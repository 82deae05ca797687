#!/usr/bin/env bash
# Benchmark (not a test): the POSE latency a watcher sees while other connections flood the daemon with
# pipelined `?STATUS;` requests (reading every reply), for 0, 1, 8 and 32 flooders. The flooders connect as
# an unprivileged uid (65534) when run as root, else as the caller. Prints one line per case: p50, p99 and max
# latency in ms (the delay of each POSE beyond the fastest one of its run: the daemon replays at the recorded
# pace, so each frame's release time is known) and the STATUS replies the flooders got.
# SPEED (default 1: 30 fps) slows the replay where SLAM cannot keep up (then the backlog, not the socket,
# would be measured: the 0-flooder line shows it).
#   scripts/bench_flood.sh [BUILD_DIR] [SECONDS] [DAEMON] [SPEED]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
seconds=${2:-10}
daemon=${3:-"$build/daemon/slamboosterd"}
speed=${4:-1}
flood="$build/tests/daemon/daemon_bench_flood"
tool="$build/tools/slambooster/slambooster"
for b in "$daemon" "$flood" "$tool"; do
  [ -x "$b" ] || { echo "bench_flood: $b is missing; build the targets slamboosterd daemon_bench_flood slambooster" >&2; exit 1; }
done
work=$(mktemp -d /tmp/sb-bench-flood-XXXXXX)
chmod 755 "$work"
trap 'rm -rf "$work"' EXIT
# 160x120 at 30 fps and a 64^3 volume: SLAM keeps up with the recorded pace, so any delay is the socket's.
"$tool" synth --out "$work/seq" --builtin-frames 90 --width 160 --height 120 --fx 120 --fy 120 >/dev/null
echo '{"volume_resolution": 64, "knobs": "csr=1,ir=1"}' > "$work/pipeline.json"
uid=()
[ "$(id -u)" = 0 ] && uid=(65534)
echo "bench_flood: $(nproc) CPUs, load $(cut -d' ' -f1 /proc/loadavg), ${seconds} s per case, speed $speed, daemon $daemon"
for n in 0 1 8 32; do
  sock="$work/$n.sock"
  "$daemon" --input "$work/seq" --out "$work/out-$n" --socket "$sock" --pacing recorded --at-end loop \
    --controller fixed --set slam.pipeline_config="$work/pipeline.json" --set log_level=warn \
    --set socket.mode=0666 --set socket.max_clients=64 --set source.speed="$speed" &
  pid=$!
  result=$("$flood" "$sock" "$n" "$seconds" "$speed" "${uid[@]}" || true)
  kill -TERM "$pid"; wait "$pid" || true
  echo "flooders $n: $result"
done
