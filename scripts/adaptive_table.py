#!/usr/bin/env python3
"""Issue 21's table from a `slambooster bench` results.csv: DEFAULT, slambooster, adaptive, offline and the best
single fixed setting side by side (ms/frame / ATE cm, % tracked where below 100), then the bars of the issue:
safe (adaptive under 5 cm and >= 99% tracked wherever ACCURATE is under 5 cm; nowhere failing where pid
passes), fast (mean cut against DEFAULT; mean time against offline's; beating the best single setting
wherever that setting is safe) and the controller's own cost.

    scripts/adaptive_table.py BENCH_DIR/results.csv [--single LABEL[,LABEL...]] [--grid LABEL[,LABEL...]]

LABELs are bench --fixed columns (default best-single); with several, the best single setting is the one within
the bound on the most sequences, then the fastest on average: what a user would pick for the whole set.
--grid: the offline column is the fastest setting within the bound per sequence among these columns and
DEFAULT (the search `slambooster dse` makes with the whole trajectory known, run side by side with the other
columns; where no setting is within the bound, the most accurate one); --single defaults to the grid.
"""
import csv
import sys

BOUND_M = 0.05
MIN_TRACKED = 99.0


def load(path):
    runs = {}
    order = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            seq = row["sequence"]
            if seq not in order:
                order.append(seq)
            ate = row["ate_rmse_m"]
            runs[(seq, row["controller"])] = {
                "ms": float(row["computation_ms_per_frame"]),
                "ate": float(ate) if ate not in ("", "nan") else float("nan"),
                "tracked": float(row["tracked_percent"]),
                "frames": int(float(row["frames"])),
                "controller_ms": float(row["controller_ms_per_frame"] or 0),
            }
    return runs, order


def safe(r):
    return r is not None and r["ate"] == r["ate"] and r["ate"] < BOUND_M and r["tracked"] >= MIN_TRACKED


def cell(r):
    if r is None:
        return "-"
    ate = "-" if r["ate"] != r["ate"] else f"{r['ate'] * 100:.2f}"
    if not safe(r) and ate != "-":
        ate = f"**{ate}**"
    text = f"{r['ms']:.1f} / {ate}"
    return text + (f" ({r['tracked']:.1f}%)" if r["tracked"] < 100 else "")


def main(argv):
    if not argv:
        sys.exit(__doc__)
    candidates = ["best-single"]
    if "--single" in argv:
        candidates = argv[argv.index("--single") + 1].split(",")
    runs, order = load(argv[0])
    if "--grid" in argv:
        grid = argv[argv.index("--grid") + 1].split(",")
        if "--single" not in argv:
            candidates = grid
        for seq in order:
            rs = [(label, runs[(seq, label)]) for label in grid + ["default"] if (seq, label) in runs]
            within = [x for x in rs if safe(x[1])]
            label, best = (min(within, key=lambda x: x[1]["ms"]) if within
                           else min(rs, key=lambda x: x[1]["ate"] if x[1]["ate"] == x[1]["ate"] else 1e9))
            runs[(seq, "offline")] = dict(best, label=label)
            print(f"offline setting of {seq}: {label}")
        print()

    def rank(label):
        rs = [runs.get((seq, label)) for seq in order]
        rs = [r for r in rs if r is not None]
        return (-sum(safe(r) for r in rs), sum(r["ms"] for r in rs) / max(1, len(rs)))

    single = min(candidates, key=rank)
    if len(candidates) > 1:
        for label in candidates:
            n, mean = rank(label)
            print(f"candidate {label}: within the bound on {-n} of {len(order)} sequences, mean {mean:.2f} ms/frame")
        print(f"best single setting: {single}\n")
    cols = [("DEFAULT", "default"), ("slambooster", "slambooster"), ("adaptive", "adaptive"),
            ("offline", "offline"), ("best single", single)]
    print("| sequence | frames | " + " | ".join(c for c, _ in cols) + " | ACCURATE ATE cm | adaptive cut |")
    print("|---" * (len(cols) + 4) + "|")
    cuts, ad_ms, off_ms, notes = [], [], [], []
    for seq in order:
        get = lambda name: runs.get((seq, name))
        d, a, acc, pid, off, one = get("default"), get("adaptive"), get("accurate"), get("pid"), get("offline"), get(single)
        cut = 100 * (1 - a["ms"] / d["ms"]) if a and d else float("nan")
        cuts.append(cut)
        frames = (d or a)["frames"]
        acc_ate = "-" if not acc or acc["ate"] != acc["ate"] else f"{acc['ate'] * 100:.2f}"
        print(f"| {seq} | {frames} | " + " | ".join(cell(get(n)) for _, n in cols) + f" | {acc_ate} | {cut:.1f}% |")
        if safe(acc) and not safe(a):
            notes.append(f"UNSAFE: {seq}: ACCURATE is under 5 cm, adaptive is not ({cell(a)})")
        if safe(pid) and not safe(a):
            notes.append(f"UNSAFE: {seq}: pid passes, adaptive does not")
        if off is not None and a is not None and safe(off):
            ad_ms.append(a["ms"])
            off_ms.append(off["ms"])
            if a["ms"] >= off["ms"]:
                notes.append(f"{seq}: offline ({off.get('label', 'offline')}) is faster than adaptive "
                             f"({off['ms']:.1f} vs {a['ms']:.1f} ms/frame)")
        if one is not None and a is not None and safe(one):
            verdict = "beats" if a["ms"] < one["ms"] else "does NOT beat"
            notes.append(f"{seq}: adaptive {verdict} the best single setting ({a['ms']:.1f} vs {one['ms']:.1f} ms/frame)")
    print()
    valid = [c for c in cuts if c == c]
    print(f"adaptive's mean cut against DEFAULT: {sum(valid) / len(valid):.1f}% over {len(valid)} sequences "
          f"({min(valid):.1f}-{max(valid):.1f}%)")
    if ad_ms:
        print(f"mean ms/frame over the {len(ad_ms)} sequences where an offline setting is within the bound: adaptive "
              f"{sum(ad_ms) / len(ad_ms):.2f}, offline {sum(off_ms) / len(off_ms):.2f}")
    shares = [r["controller_ms"] / r["ms"] * 100 for (s, c), r in runs.items() if c == "adaptive" and r["ms"] > 0]
    if shares:
        print(f"adaptive's own cost: at most {max(shares):.2f}% of the frame's computation time")
    for n in notes:
        print(n)


if __name__ == "__main__":
    main(sys.argv[1:])
