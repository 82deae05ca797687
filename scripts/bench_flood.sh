#!/usr/bin/env bash
# Benchmark (not a test): the POSE stream a watcher sees while other connections flood the daemon with
# pipelined requests (reading every reply). One daemon per case, the cases one after the other in one run of
# the script (so they share the machine's load). The flooders connect as an unprivileged uid (65534) when run
# as root, else as the caller. Prints one line per case: p50, p99 and max latency in ms (the delay of each
# POSE beyond the fastest one of its run: the daemon replays at the recorded pace, so each frame's release
# time is known), max_gap_ms (the largest gap between two POSEs: the frame rate's worst moment), and the
# replies the flooders got (error_replies: those that were ERROR, e.g. a rate limit's answer).
#   scripts/bench_flood.sh [BUILD_DIR] [SECONDS] [DAEMON] [SPEED] [REQUEST] [FLOODERS...]
# REQUEST: `?STATUS;` (default), `?MAP;`, `?CLOUD;`, `?POLL;` ...; with `?MAP;` or `?CLOUD;` the daemon makes
# its navigation grid (output.navmap, renewed every 0.5 s) and the flood starts after a 3 s warm-up (the
# first grid; the same warm-up for every case). FLOODERS: the cases (default 0 1 8 32). With `?MAP;` and two
# or more cases the last line compares the largest POSE gap of each case with the first one's (issue 53:
# at most 2x with 16 flooders):
#   scripts/bench_flood.sh build 10 "" 1 '?MAP;' 0 16
# SPEED (default 1: 30 fps) slows the replay where SLAM cannot keep up (then the backlog, not the socket,
# would be measured: the 0-flooder line shows it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
seconds=${2:-10}
daemon=${3:-}
[ -n "$daemon" ] || daemon="$build/daemon/slamboosterd"
speed=${4:-1}
request=${5:-'?STATUS;'}
shift $(( $# < 5 ? $# : 5 ))
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(0 1 8 32)
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
extra=()
warmup=0
case "$request" in
  '?MAP;' | '?CLOUD;')
    # The grid's frame from a mount 1 m above the floor (the synthetic room's camera), its cloud at 0.1 m.
    echo '{"up": "mount", "mount_height_m": 1.0, "octomap_resolution_m": 0.1}' > "$work/navmap.json"
    extra=(--set output.navmap="$work/navmap.json" --set output.navmap_period_s=0.5)
    warmup=3
    ;;
esac
uid=(-)
[ "$(id -u)" = 0 ] && uid=(65534)
echo "bench_flood: $(nproc) CPUs, load $(cut -d' ' -f1 /proc/loadavg), ${seconds} s per case, speed $speed," \
  "request $request, warm-up ${warmup} s, daemon $daemon"
gaps=()
for n in "${cases[@]}"; do
  sock="$work/$n.sock"
  "$daemon" --input "$work/seq" --out "$work/out-$n" --socket "$sock" --pacing recorded --at-end loop \
    --controller fixed --set slam.pipeline_config="$work/pipeline.json" --set log_level=warn \
    --set socket.mode=0666 --set socket.max_clients=64 --set source.speed="$speed" "${extra[@]}" \
    >"$work/daemon-$n.log" 2>&1 &
  pid=$!
  result=$("$flood" "$sock" "$n" "$seconds" "$speed" "${uid[@]}" "$request" "$warmup" || true)
  kill -TERM "$pid"; wait "$pid" || true
  echo "flooders $n: $result"
  grep -E '\[(error|critical)\]' "$work/daemon-$n.log" || true  # the daemon's own complaints, if any
  gaps+=("$(sed -n 's/.*"max_gap_ms":\([-0-9.e+]*\).*/\1/p' <<<"$result")")
done
if [ "$request" = '?MAP;' ] && [ ${#cases[@]} -ge 2 ]; then
  for i in $(seq 1 $(( ${#cases[@]} - 1 ))); do
    awk -v a="${gaps[0]}" -v b="${gaps[$i]}" -v n0="${cases[0]}" -v n="${cases[$i]}" 'BEGIN {
      if (a <= 0 || b <= 0) { print "largest POSE gap: not measured (no POSE in a case)"; exit }
      printf "largest POSE gap: %.0f ms with %s flooders, %.0f ms with %s: %.2fx (issue 53 asks at most 2x)\n",
             a, n0, b, n, b / a }'
  done
fi
