#!/usr/bin/env bash
# Soak test of `slambooster run` (issue 34; docs/running-for-weeks.md): the same 32x24 synthetic room corner
# as the daemon's test-pattern source (scripts/soak_daemon.sh), written as a SLAMBench .raw file of N frames
# (1552 bytes a frame at 32x24, no RGB), replayed as fast as one thread goes, with the process's RSS sampled every
# INTERVAL seconds. One CSV line per sample:
#   t_s,frames,rss_kib
# and at the end it checks: RSS at the last sample in the frame loop (the frame count still moving) within
# RSS_SLACK_KIB of the RSS at the end of the warm-up, and `run` exiting 0 with every frame in summary.json.
# What `run` does after its last frame (model.png, the summary, report.html from the whole frames.jsonl of a
# replay) is reported apart: its peak RSS among the samples.
#
#   scripts/soak_run.sh [options]
#     --build DIR        build directory with tools/slambooster/slambooster (default: build in the checkout)
#     --frames N         frames in the .raw file (default 1000000)
#     --warmup S         seconds before the reference RSS (default 60)
#     --interval S       seconds between samples (default 5)
#     --rss-slack-kib K  allowed RSS growth after the warm-up (default 5120)
#     --size WxH         frame size (default 32x24; as scripts/soak_daemon.sh says, frames of that size are lost)
#     --pipeline JSON    the pipeline config (default {"volume_resolution": 32, "knobs": "csr=1,ir=30"})
#     --out DIR          keep the input, the outputs and the log there (default: a temporary directory, removed)
# Exits 1 when a check fails, 2 on bad use.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build" frames=1000000 warmup=60 interval=5 rss_slack_kib=5120 out="" size=32x24
pipeline='{"volume_resolution": 32, "knobs": "csr=1,ir=30"}'
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --warmup) warmup=$2; shift 2 ;;
    --interval) interval=$2; shift 2 ;;
    --rss-slack-kib) rss_slack_kib=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --pipeline) pipeline=$2; shift 2 ;;
    *) echo "soak_run: unknown option $1 (see the comment at the top of $0)" >&2; exit 2 ;;
  esac
done
tool="$build/tools/slambooster/slambooster"
[ -x "$tool" ] || { echo "soak_run: $tool is missing; build the target slambooster" >&2; exit 2; }

keep_out=1
if [ -z "$out" ]; then out=$(mktemp -d /tmp/sb-soak-run-XXXXXX); keep_out=0; fi
mkdir -p "$out"
cleanup() {
  [ -z "${pid:-}" ] || kill "$pid" 2>/dev/null || true
  [ "$keep_out" = 1 ] || rm -rf "$out"
}
trap cleanup EXIT

# The room of daemon/pattern_source.cpp: fx = fy = 0.8 x width, depth in millimetres, the same frame N times.
raw="$out/room.raw"
python3 - "$raw" "$frames" "${size%x*}" "${size#*x}" <<'PY'
import struct, sys
path, n = sys.argv[1], int(sys.argv[2])
w, h = int(sys.argv[3]), int(sys.argv[4])
f = 0.8 * w
cx, cy = 0.5 * (w - 1), 0.5 * (h - 1)
def depth(x, y):
    z = 3.0
    if x < 0: z = min(z, -1.5 / x)
    if x > 0: z = min(z, 1.8 / x)
    if y < 0: z = min(z, -1.3 / y)
    if y > 0: z = min(z, 1.0 / y)
    return z
px = [int(round(depth((u - cx) / f, (v - cy) / f) * 1000)) for v in range(h) for u in range(w)]
frame = struct.pack('<II', w, h) + struct.pack('<%dH' % len(px), *px) + struct.pack('<II', 0, 0)
chunk = frame * 4096
with open(path, 'wb') as out:
    for _ in range(n // 4096): out.write(chunk)
    out.write(frame * (n % 4096))
with open(path + '.json', 'w') as out:
    out.write('{"width": %d, "height": %d, "fx": %g, "fy": %g, "cx": %g, "cy": %g, "depth_scale": 1000}\n'
              % (w, h, f, f, cx, cy))
PY
echo "$pipeline" > "$out/pipeline.json"

log="$out/run.log"
"$tool" run "$raw" --out "$out/outputs" --config "$out/pipeline.json" --threads 1 --quiet >"$log" 2>&1 &
pid=$!
summary_frames() {
  # summary.json's "frames", read through its type (`slambooster summary`); none while it is rewritten
  "$tool" summary "$out/outputs" --get frames 2>/dev/null || true
}
echo "t_s,frames,rss_kib"
start=$(date +%s.%N)
rss_warm="" rss_last="" rss_after="" t=0 last_n=0
while kill -0 "$pid" 2>/dev/null; do
  sleep "$interval"
  t=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss" ] || break  # ended between the two looks
  n=$(summary_frames); n=${n:-0}
  echo "$t,$n,$rss"
  if [ "$n" -gt "$last_n" ] && [ "$n" -lt "$frames" ]; then  # in the frame loop
    if [ -z "$rss_warm" ] && awk -v t="$t" -v w="$warmup" 'BEGIN { exit !(t >= w) }'; then rss_warm=$rss; fi
    rss_last=$rss
  elif [ "$n" -ge "$frames" ] && { [ -z "$rss_after" ] || [ "$rss" -gt "$rss_after" ]; }; then
    rss_after=$rss  # after the last frame: the end-of-run outputs
  fi
  last_n=$n
done
rc=0
wait "$pid" || rc=$?
pid=""
n=$(summary_frames)
echo "soak_run: ${n:-0} of $frames frames in $t s; RSS after the warm-up (${warmup} s) ${rss_warm:-?} KiB," \
  "at the last sample in the frame loop ${rss_last:-?} KiB; after the last frame (end-of-run outputs) at most" \
  "${rss_after:-?} KiB"
failed=0
[ "$rc" = 0 ] || { echo "FAIL: slambooster run exited $rc (log: $log)"; tail -n 20 "$log"; failed=1; }
[ "${n:-0}" = "$frames" ] || { echo "FAIL: summary.json counts ${n:-0} frames, not $frames"; failed=1; }
if [ -z "$rss_warm" ]; then
  echo "FAIL: the run ended before the warm-up (${warmup} s): no reference RSS"; failed=1
elif [ $((rss_last - rss_warm)) -gt "$rss_slack_kib" ]; then
  echo "FAIL: RSS grew by $((rss_last - rss_warm)) KiB after the warm-up (allowed $rss_slack_kib)"; failed=1
fi
[ "$failed" = 0 ] || exit 1
echo "soak_run: passed"
