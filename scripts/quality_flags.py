#!/usr/bin/env python3
"""Issue 21's tracking-quality goal from a bench directory: the share of a corridor sequence's wall-only
frames flagged unconstrained, and of every other sequence's frames, per controller (frames with an ICP result;
"constrained" as each run's frames.jsonl recorded it).

    scripts/quality_flags.py BENCH_DIR [CORRIDOR_NAME] [--threshold T] [--tool SLAMBOOSTER]
        CORRIDOR_NAME: default stress-corridor; its segments.csv is read from the sequence directory its summary
        names. --threshold: flag frames whose recorded conditioning is below T instead of reading each run's
        recorded "constrained" (runs made under another constrained_min_conditioning, compared alike).
        --tool: the slambooster that reads summary.json (`slambooster summary`; default build/ of the checkout).
"""
import csv
import json
import os
import subprocess
import sys


def frames(path):
    with open(path) as f:
        for line in f:
            if line.strip():
                yield json.loads(line)


def main(argv):
    if not argv:
        sys.exit(__doc__)
    threshold = None
    if "--threshold" in argv:
        i = argv.index("--threshold")
        threshold = float(argv[i + 1])
        argv = argv[:i] + argv[i + 2:]
    tool = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build", "tools", "slambooster", "slambooster")
    if "--tool" in argv:
        i = argv.index("--tool")
        tool = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    runs = os.path.join(argv[0], "runs")
    corridor = argv[1] if len(argv) > 1 else "stress-corridor"
    wall = set()
    run = os.path.join(runs, corridor, "default")
    if os.path.exists(os.path.join(run, "summary.json")):
        seq = subprocess.run([tool, "summary", run, "--get", "sequence"], check=True, capture_output=True,
                             text=True).stdout.rstrip("\n")
        for row in csv.DictReader(open(os.path.join(seq, "segments.csv"))):
            if row["label"] == "wall-only":
                wall.update(range(int(row["begin_frame"]), int(row["end_frame"])))
    per = {}  # controller -> [wall flagged, wall frames, other flagged, other frames]
    for name in sorted(os.listdir(runs)):
        for controller in sorted(os.listdir(os.path.join(runs, name))):
            log = os.path.join(runs, name, controller, "frames.jsonl")
            if not os.path.exists(log):
                continue
            c = per.setdefault(controller, [0, 0, 0, 0])
            for f in frames(log):
                if "constrained" not in f:
                    continue
                flagged = not f["constrained"]
                if threshold is not None and "conditioning" in f:
                    flagged = f["conditioning"] < threshold
                if name == corridor:
                    if f["frame"] in wall:
                        c[0] += flagged
                        c[1] += 1
                else:
                    c[2] += flagged
                    c[3] += 1
    print("| controller | wall-only frames flagged | frames of the other sequences flagged |")
    print("|---|---|---|")
    for controller, (wf, wn, of, on) in per.items():
        w = f"{wf}/{wn} ({100 * wf / wn:.1f}%)" if wn else "-"
        o = f"{of}/{on} ({100 * of / on:.2f}%)" if on else "-"
        print(f"| {controller} | {w} | {o} |")


if __name__ == "__main__":
    main(sys.argv[1:])
