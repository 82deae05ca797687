#!/usr/bin/env bash
# Soak test and benchmark of a long live session (README "Running for weeks"): slamboosterd on the endless
# test-pattern source (tiny synthetic frames, as fast as the SLAM thread takes them) with its outputs rotated,
# for a number of frames or seconds, whichever comes first. Every INTERVAL seconds it prints one CSV line:
#   t_s,frames,rss_kib,segment_bytes,dir_bytes,free_bytes,segments,removed_segments
# and at the end checks: RSS at the end within RSS_SLACK_KIB of the RSS at the end of the warm-up, the rotated
# outputs within the retention limit at every sample, the daemon alive until it was stopped and exiting 0,
# and no error in its log.
#
#   scripts/soak_daemon.sh [options]
#     --build DIR        build directory with daemon/slamboosterd (default: build in the checkout)
#     --frames N         stop after N frames (default 1000000)
#     --seconds S        ... or after S seconds (default 1800)
#     --warmup S         seconds before the reference RSS (default 60; shorter runs: a fifth of --seconds)
#     --interval S       seconds between samples (default 5)
#     --segment-mib M    output.rotation.segment_mib (default 1)
#     --keep-mib M       output.rotation.keep_mib (default 16)
#     --min-free-mib M   output.rotation.min_free_mib (default 1)
#     --tmpfs-mib M      write the outputs to a tmpfs of M MiB of its own (a private mount namespace through
#                        `unshare -rm`), smaller than --keep-mib: the disk fills and the oldest segments must go
#     --fill-after S     with --tmpfs-mib: after S seconds another file takes all the free space left (the disk
#                        fills from elsewhere): writes fail with ENOSPC, and the oldest segments must go
#     --rss-slack-kib K  allowed RSS growth after the warm-up (default 5120)
#     --size WxH         the test pattern's frame size (default 32x24: every frame after the first four is lost,
#                        the tracker cannot hold a 32^3 volume at that size; 64x48 with --pipeline below tracks)
#     --pipeline JSON    the pipeline config (default {"volume_resolution": 32, "knobs": "csr=1,ir=30"}; one
#                        that tracks at 64x48, for the first 16,370 frames (then the pose of the weak view
#                        has slid too far): {"volume_resolution": 64, "mu_m": 0.3, "knobs": "csr=1,ir=4"})
#     --out DIR          keep the outputs and the log there (default: a temporary directory, removed)
# Exits 1 when a check fails, 2 on bad use, 77 (a skip for ctest) when --tmpfs-mib cannot mount a tmpfs here.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build" frames=1000000 seconds=1800 warmup="" interval=5 segment_mib=1 keep_mib=16 min_free_mib=1
tmpfs_mib="" fill_after="" rss_slack_kib=5120 out="" in_ns=0 size=32x24
pipeline='{"volume_resolution": 32, "knobs": "csr=1,ir=30"}'
args=("$@")
while [ $# -gt 0 ]; do
  case $1 in
    --build) build=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --warmup) warmup=$2; shift 2 ;;
    --interval) interval=$2; shift 2 ;;
    --segment-mib) segment_mib=$2; shift 2 ;;
    --keep-mib) keep_mib=$2; shift 2 ;;
    --min-free-mib) min_free_mib=$2; shift 2 ;;
    --tmpfs-mib) tmpfs_mib=$2; shift 2 ;;
    --rss-slack-kib) rss_slack_kib=$2; shift 2 ;;
    --fill-after) fill_after=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --pipeline) pipeline=$2; shift 2 ;;
    --in-namespace) in_ns=1; shift ;;
    *) echo "soak_daemon: unknown option $1 (see the comment at the top of $0)" >&2; exit 2 ;;
  esac
done
[ -n "$warmup" ] || warmup=$(awk -v s="$seconds" 'BEGIN { w = s / 5; print (w < 60 ? w : 60) }')
daemon="$build/daemon/slamboosterd"
tool="$build/tools/slambooster/slambooster"  # reads summary.json (`slambooster summary`)
for b in "$daemon" "$tool"; do
  [ -x "$b" ] || { echo "soak_daemon: $b is missing; build the targets slamboosterd slambooster" >&2; exit 2; }
done

# A tmpfs of its own: the whole script runs again inside a private mount namespace (as root, or as an
# unprivileged user mapped to root in a user namespace).
if [ -n "$tmpfs_mib" ] && [ "$in_ns" = 0 ]; then
  if ! unshare -rm sh -c "mount -t tmpfs -o size=1m sb-soak-probe /tmp 2>/dev/null" 2>/dev/null; then
    echo "soak_daemon: cannot mount a tmpfs in a private mount namespace here (unshare -rm: no user or mount" \
      "namespaces?): the disk-full soak is skipped" >&2
    exit 77
  fi
  exec unshare -rm "$0" "${args[@]}" --in-namespace
fi

keep_out=1
if [ -z "$out" ]; then out=$(mktemp -d /tmp/sb-soak-XXXXXX); keep_out=0; fi
mkdir -p "$out"
outputs="$out/outputs"
mkdir -p "$outputs"
if [ -n "$tmpfs_mib" ]; then
  mount -t tmpfs -o "size=${tmpfs_mib}m" sb-soak "$outputs" ||
    { echo "soak_daemon: cannot mount a tmpfs of $tmpfs_mib MiB on $outputs" >&2; exit 2; }
fi
log="$out/daemon.log"
cleanup() {
  [ -z "${pid:-}" ] || kill "$pid" 2>/dev/null || true
  [ -z "$tmpfs_mib" ] || umount "$outputs" 2>/dev/null || true
  [ "$keep_out" = 1 ] || rm -rf "$out"
}
trap cleanup EXIT

echo "$pipeline" > "$out/pipeline.json"
"$daemon" --out "$outputs" --socket "$out/soak.sock" --controller fixed --at-end stop \
  --set source.type=pattern --set source.pacing=fast --set source.max_frames="$frames" \
  --set source.camera.width="${size%x*}" --set source.camera.height="${size#*x}" \
  --set slam.pipeline_config="$out/pipeline.json" --set slam.cpus=all --set slam.threads=1 \
  --set output.report=false --set power.config= \
  --set output.rotation.mode=always --set output.rotation.segment_mib="$segment_mib" \
  --set output.rotation.keep_mib="$keep_mib" --set output.rotation.min_free_mib="$min_free_mib" \
  --set log_level=info >"$log" 2>&1 &
pid=$!

keep_bytes=$(awk -v m="$keep_mib" 'BEGIN { printf "%d", m * 1048576 }')
segment_list() {
  find "$outputs" -maxdepth 2 -type f -regex '.*-[0-9][0-9][0-9][0-9][0-9][0-9]+\.[a-z]+$' -printf "$1" 2>/dev/null || true
}
segment_bytes() {  # the rotated outputs on disk
  # Sizes, then the names again: a segment counted and removed before the listing ends would be counted with
  # the newer bytes written in its place, more than was ever on disk at once; only the ones still there count
  # (segments only grow while they are there, so this is never more than the disk held at the second listing).
  local sizes names
  sizes=$(segment_list '%p %s\n')
  names=$(segment_list '%p\n')
  awk 'NR == FNR { there[$0] = 1; next } ($1 in there) { s += $2 } END { printf "%d", s }' \
    <(printf '%s\n' "$names") <(printf '%s\n' "$sizes")
}
summary_frames() {
  # summary.json's "frames", read through its type (`slambooster summary`); none while it is rewritten
  "$tool" summary "$outputs" --get frames 2>/dev/null || true
}
echo "t_s,frames,rss_kib,segment_bytes,dir_bytes,free_bytes,segments,removed_segments"
start=$(date +%s.%N)
failed=0
rss_warm="" rss_last="" over=0 t=0 n=0
while kill -0 "$pid" 2>/dev/null; do
  sleep "$interval"
  kill -0 "$pid" 2>/dev/null || break
  t=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null || echo 0)
  seg=$(segment_bytes)
  # Files come and go while these look (the daemon rotates and removes segments): never fatal.
  dir=$(du -sb "$outputs" 2>/dev/null | cut -f1 || true)
  free=$(df -B1 --output=avail "$outputs" | tail -n1 | tr -d ' ')
  count=$(find "$outputs" -maxdepth 2 -type f -regex '.*-[0-9][0-9][0-9][0-9][0-9][0-9]+\.[a-z]+$' 2>/dev/null | wc -l || true)
  # Segments removed so far: the frame log's highest number less the ones still there.
  removed=$(find "$outputs" -maxdepth 1 -name 'frames-*.jsonl' -printf '%f\n' 2>/dev/null | sed 's/frames-0*\([0-9]*\)\.jsonl/\1/' |
    awk '{ if ($1 > m) m = $1; c++ } END { print m - c }' || true)
  n=$(summary_frames); n=${n:-0}
  echo "$t,$n,$rss,$seg,$dir,$free,$count,$removed"
  [ "$seg" -le "$keep_bytes" ] || { echo "soak_daemon: rotated outputs $seg bytes > keep $keep_bytes" >&2; over=1; }
  if [ -z "$rss_warm" ] && awk -v t="$t" -v w="$warmup" 'BEGIN { exit !(t >= w) }'; then rss_warm=$rss; fi
  rss_last=$rss
  if [ -n "$fill_after" ] && [ -n "$tmpfs_mib" ] && [ ! -e "$outputs/filler" ] &&
    awk -v t="$t" -v f="$fill_after" 'BEGIN { exit !(t >= f) }'; then
    dd if=/dev/zero of="$outputs/filler" bs=4k 2>/dev/null || true  # until the disk is full
    echo "soak_daemon: at $t s another file took the free space: $(du -b "$outputs/filler" | cut -f1) bytes" >&2
  fi
  if awk -v t="$t" -v s="$seconds" 'BEGIN { exit !(t >= s) }'; then kill -TERM "$pid"; fi
  # The source ended (max_frames): the daemon keeps serving; stop it.
  if grep -q 'input ended after' "$log"; then kill -TERM "$pid"; fi
done
rc=0
wait "$pid" || rc=$?
pid=""
n=$(summary_frames); n=${n:-0}
echo "soak_daemon: $n frames in $t s; RSS after the warm-up (${warmup} s) ${rss_warm:-?} KiB, at the end ${rss_last:-?} KiB;" \
  "keep $keep_bytes bytes${tmpfs_mib:+, tmpfs $tmpfs_mib MiB}"
[ "$rc" = 0 ] || { echo "FAIL: slamboosterd exited $rc (log: $log)"; failed=1; }
[ "$over" = 0 ] || { echo "FAIL: the rotated outputs passed the retention limit"; failed=1; }
if grep -E '\[(error|critical)\]' "$log"; then echo "FAIL: errors in the daemon's log"; failed=1; fi
if [ -z "$rss_warm" ]; then
  echo "FAIL: the run ended before the warm-up (${warmup} s): no reference RSS"; failed=1
elif [ $((rss_last - rss_warm)) -gt "$rss_slack_kib" ]; then
  echo "FAIL: RSS grew by $((rss_last - rss_warm)) KiB after the warm-up (allowed $rss_slack_kib)"; failed=1
fi
if [ "$failed" = 1 ]; then
  [ "$keep_out" = 1 ] || { echo "--- daemon log (last 30 lines)"; tail -n 30 "$log"; }
  exit 1
fi
echo "soak_daemon: passed"
