#!/usr/bin/env bash
# What keeping a map store costs a run, side by side (issue 55): the same drive run with and without a new store,
# alternated REPEATS times in one invocation so that both see the same machine (which of the two goes first
# alternates too). The drive is the 12 m corridor's whole drive (there and back: the way back brings the moving
# volume over places the store keeps, so slabs are written and swapped in within the run), 160x120 images to keep
# the runs short (SCALE=2 in the environment: 320x240, SCALE=4: 640x480, the focal lengths scaled with them).
#
# usage: scripts/map_store_cost.sh OUT [CONTROLLER] [REPEATS]
# Per run: summary.json's computation_ms_per_frame (the SLAM thread's stages), cpu_ms_per_frame (every thread of
# the process), the wall time per frame (frames.jsonl: first frame's start to last frame's end / frames), and with
# a store the worker's wall time, the SLAM thread's time in swap-in (map_store.load_ms), the swap-ins, the store's
# size per metre driven. Then the medians and their ratios (with / without).
set -euo pipefail
out=${1:?usage: scripts/map_store_cost.sh OUT [CONTROLLER] [REPEATS]}
controller=${2:-adaptive}
repeats=${3:-3}
tool=${SLAMBOOSTER:-build/tools/slambooster/slambooster}
scale=${SCALE:-1}
mkdir -p "$out"
seq=$out/drive-x$scale
[ -f "$seq/groundtruth.txt" ] ||
  $tool synth --scene corridor --corridor-length 12 --stress drive --width $((160 * scale)) --height $((120 * scale)) \
    --fx "$(echo "120.3 * $scale" | bc)" --fy $((120 * scale)) --threads 2 --out "$seq" >"$out/synth.log" 2>&1
run="$tool run $seq --controller $controller --volume-size 5 --threads 2 --quiet"
without() { $run --out "$out/without-$1" >"$out/without-$1.log" 2>&1; }
with() { $run --map-store "$out/store-$1" --out "$out/with-$1" >"$out/with-$1.log" 2>&1; }
for i in $(seq 1 "$repeats"); do  # the order alternates: a machine that speeds up or slows down favours neither
  rm -rf "$out/without-$i" "$out/with-$i" "$out/store-$i"
  if ((i % 2)); then without "$i" && with "$i"; else with "$i" && without "$i"; fi
done
python3 - "$out" "$repeats" <<'EOF'
import json, os, statistics, sys
out, repeats = sys.argv[1], int(sys.argv[2])

def measure(d):
    s = json.load(open(f"{d}/summary.json"))
    starts, ends = [], []
    for line in open(f"{d}/frames.jsonl"):
        f = json.loads(line)
        starts.append(f["t_start_mono_ns"]); ends.append(f["t_end_mono_ns"])
    m = {"comp": s["computation_ms_per_frame"], "cpu": s["cpu_ms_per_frame"],
         "wall": (max(ends) - min(starts)) / 1e6 / s["frames"], "frames": s["frames"],
         "path_m": s.get("odometry", {}).get("path_m")}
    if "map_store" in s:
        k = s["map_store"]
        m.update(worker=k["worker_ms"] / s["frames"], load=k["load_ms"] / s["frames"], swaps=k["swap_ins"],
                 slabs=k["slab_bytes"])
    return m

def size(d):
    return sum(os.path.getsize(os.path.join(r, f)) for r, _, fs in os.walk(d) for f in fs)

rows = []
for i in range(1, repeats + 1):
    a, b = measure(f"{out}/without-{i}"), measure(f"{out}/with-{i}")
    b["store"] = size(f"{out}/store-{i}")
    rows.append((a, b))
    print(f"pair {i}: without comp {a['comp']:.2f} cpu {a['cpu']:.2f} wall {a['wall']:.2f} ms/frame | with comp "
          f"{b['comp']:.2f} cpu {b['cpu']:.2f} wall {b['wall']:.2f} ms/frame, worker {b['worker']:.2f} ms/frame "
          f"(wall, own thread), swap-in {b['load']:.3f} ms/frame ({b['swaps']} swap-ins), store {b['store'] / 1e6:.1f} MB")
med = lambda key, side: statistics.median(r[side][key] for r in rows)
for key, what in (("comp", "computation"), ("cpu", "process CPU"), ("wall", "wall")):
    w, o = med(key, 1), med(key, 0)
    print(f"median {what}: {o:.2f} without, {w:.2f} with a store ms/frame: x{w / o:.3f} ({100 * (w / o - 1):+.1f}%)")
path = rows[0][1]["path_m"]
if path:
    st = statistics.median(r[1]["store"] for r in rows)
    print(f"store {st / 1e6:.1f} MB over {path:.2f} m driven: {st / 1e6 / path:.2f} MB per metre "
          f"(swap-in {med('load', 1):.3f} ms/frame, worker {med('worker', 1):.2f} ms/frame)")
EOF
