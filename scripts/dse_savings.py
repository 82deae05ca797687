#!/usr/bin/env python3
"""How much computation dse's pruning saved: per results.csv of `slambooster dse`, the computation time its
runs spent against what running every setting to the end would have cost. A stopped run's ms/frame over its
first frames stands in for its whole run, so the 'to the end' figure is an estimate.

usage: scripts/dse_savings.py DSE_DIR/*/results.csv
"""
import csv
import sys


def savings(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    whole = [int(r["frames"]) for r in rows if not r["stopped_at_frame"]]
    if not whole:
        sys.exit(f"dse_savings: {path}: no run went to the end, so the sequence length is unknown")
    frames = max(whole)
    spent = sum(float(r["computation_ms_per_frame"]) * int(r["frames"]) for r in rows) / 1e3
    full = sum(float(r["computation_ms_per_frame"]) * frames for r in rows) / 1e3
    stopped = sum(1 for r in rows if r["stopped_at_frame"])
    return len(rows), stopped, spent, full


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__.strip())
    total_spent = total_full = 0.0
    for path in sys.argv[1:]:
        settings, stopped, spent, full = savings(path)
        total_spent += spent
        total_full += full
        print(f"{path}: {settings} settings, {stopped} stopped early, computation {spent:.0f} s "
              f"vs {full:.0f} s to the end ({full / spent:.1f}x)")
    if len(sys.argv) > 2:
        print(f"all: {total_spent:.0f} s vs {total_full:.0f} s ({total_full / total_spent:.1f}x)")


if __name__ == "__main__":
    main()
