#!/usr/bin/env bash
# The odometry issue's table (docs/odometry.md): corridor drives of docs/test-sequences.md at 320x240 (a wheeled
# robot's camera driving 2 x 17 m with an in-place U-turn, `slambooster synth --scene corridor --stress drive`),
# each with the odometry.txt synth writes (a cheap base: 3% scale, 2% yaw scale, 0.3 deg/s yaw bias, noise),
# run by DEFAULT and adaptive in the moving 5 m volume (--volume-size 5: the drive's hint is a cube that holds the
# whole path, 20.5 m, which `run` would otherwise take as one fixed volume), four ways:
#   none    without odometry (--no-odometry): depth alone
#   odo     with the drive's odometry
#   slip    the same odometry with a wheel slip (0.4 m forward in one 20 ms step at 20 s)
#   cover   the lens covered for 2 s mid-drive (frames 300-359 blank), with odometry
# and prints the share of frames with a pose (every state but lost), the states, the ATE over the posed frames
# and ms/frame. Runs one after another (compare side by side on one machine).
#
# usage: scripts/bench_odometry.sh [BUILD_DIR] [OUT] [SEED...]     (default seeds: 0 1)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build"}
out=${2:-/tmp/bench_odometry}
shift $(( $# > 2 ? 2 : $# ))
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(0 1)
bin="$build/tools/slambooster/slambooster"
[ -x "$bin" ] || { echo "bench_odometry: $bin not found (build first)" >&2; exit 1; }
mkdir -p "$out"
small=(--width 320 --height 240 --fx 240.6 --fy 240)

# A copy of SEQ whose frames FIRST..FIRST+N-1 are blank (a covered lens): 16-bit PNGs of zeros, the rest linked.
cover() {
  python3 - "$1" "$2" "$3" "$4" <<'PY'
import os, shutil, struct, sys, zlib
src, dst, first, n = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
os.makedirs(dst + "/depth", exist_ok=True)
for f in os.listdir(src):
    if f != "depth": shutil.copy(os.path.join(src, f), os.path.join(dst, f))
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
w, h = 320, 240
blank = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)) +
         chunk(b"IDAT", zlib.compress(b"".join(b"\x00" * (1 + 2 * w) for _ in range(h)))) + chunk(b"IEND", b""))
rows = [l.split() for l in open(src + "/depth.txt") if l.strip() and not l.startswith("#")]
for i, (_, rel) in enumerate(rows):
    target = os.path.join(dst, rel)
    if os.path.lexists(target): os.remove(target)
    if first <= i < first + n: open(target, "wb").write(blank)
    else: os.symlink(os.path.abspath(os.path.join(src, rel)), target)
PY
}

printf '%-6s %-5s %-9s %7s %6s %6s %6s %6s %6s %8s %9s\n' case seed controller posed% good weak odom reloc lost ATE_cm ms/frame
for seed in "${seeds[@]}"; do
  s="$out/drive$seed"
  [ -f "$s/odometry.txt" ] || "$bin" synth --scene corridor --stress drive --seed "$seed" "${small[@]}" --out "$s" > "$out/synth$seed.log"
  [ -f "$s-slip/odometry.txt" ] ||
    "$bin" synth --scene corridor --stress drive --seed "$seed" "${small[@]}" --odom-slip-at 20 --out "$s-slip" > "$out/synth$seed-slip.log"
  [ -f "$s-cover/odometry.txt" ] || cover "$s" "$s-cover" 300 60
  for variant in none odo slip cover; do
    seq=$s; args=()
    case $variant in
      none) args=(--no-odometry) ;;
      slip) seq=$s-slip ;;
      cover) seq=$s-cover ;;
    esac
    for c in default adaptive; do
      run="$out/$variant-$seed-$c"
      "$bin" run "$seq" --out "$run" --controller "$c" --threads 1 --volume-size 5 "${args[@]}" > "$run.log" 2>&1
      read -r frames good weak odom reloc lost ate ms < <("$bin" summary "$run" --get frames \
        --get tracking_state.frames.good --get tracking_state.frames.weak --get tracking_state.frames.odometry \
        --get tracking_state.frames.relocalised --get tracking_state.frames.lost --get ate.rmse_m \
        --get computation_ms_per_frame --missing nan | tr '\t' ' ')
      python3 -c "import sys; f,l,a,m=map(float,sys.argv[1:5]); print('%-6s %-5s %-9s %7.1f %6s %6s %6s %6s %6s %8.2f %9.1f' % (sys.argv[5], sys.argv[6], sys.argv[7], 100*(f-l)/f, *sys.argv[8:13], 100*a, m))" \
        "$frames" "$lost" "$ate" "$ms" "$variant" "$seed" "$c" "$good" "$weak" "$odom" "$reloc" "$lost"
    done
  done
done
