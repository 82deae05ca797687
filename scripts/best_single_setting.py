#!/usr/bin/env python3
"""The best single fixed setting for a whole sequence set: the one a user would pick without knowing the
trajectory. Reads `slambooster dse` results.csv of every sequence (one grid, every setting run to the end:
--no-prune) and picks, among the settings within the bound (ATE and % tracked as dse judged them) on the most
sequences, the one with the lowest mean ms/frame over the set. Prints the choice and, per sequence, whether it
is within the bound there.

    scripts/best_single_setting.py DSE_DIR/*/results.csv      # last line: the knobs, for bench --fixed
"""
import csv
import os
import sys


def main(paths):
    if not paths:
        sys.exit(__doc__)
    table = {}  # knobs -> sequence -> (within, ms)
    sequences = []
    for path in paths:
        name = os.path.basename(os.path.dirname(os.path.abspath(path)))
        sequences.append(name)
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                if row["stopped_at_frame"] not in ("", "0"):
                    sys.exit(f"{path}: {row['knobs']} was stopped early: run dse with --no-prune")
                within = row["within_bound"].strip().lower() in ("1", "true", "yes")
                table.setdefault(row["knobs"], {})[name] = (within, float(row["computation_ms_per_frame"]))
    complete = {k: v for k, v in table.items() if len(v) == len(sequences)}
    if not complete:
        sys.exit("no setting was run on every sequence: use one grid for all")

    def key(item):
        knobs, per = item
        safe = sum(w for w, _ in per.values())
        mean = sum(ms for _, ms in per.values()) / len(per)
        return (-safe, mean)

    knobs, per = min(complete.items(), key=key)
    safe = [s for s in sequences if per[s][0]]
    print(f"best single setting over {len(sequences)} sequences: {knobs}")
    print(f"  within the bound on {len(safe)} of {len(sequences)}; mean {sum(ms for _, ms in per.values()) / len(per):.1f} ms/frame")
    for s in sequences:
        print(f"  {s}: {'within' if per[s][0] else 'OUT of'} the bound, {per[s][1]:.1f} ms/frame")
    print(knobs)


if __name__ == "__main__":
    main(sys.argv[1:])
