#!/usr/bin/env python3
"""Checks every relocalisation of a run against the ground truth (issue 29's "no false relocalisation").

  scripts/relocalisation_check.py RUN_DIR GROUNDTRUTH.txt [--max-cm 5] [--max-deg 3]

For each frame whose state is "relocalised" (frames.jsonl), the relocalised pose is compared with the truth in
the map's own frame: relative to the earlier tracked frame whose true pose is nearest (the place seen before,
which built the part of the map it relocalised against), the estimated motion (trajectory.tum) against the true
one (ground truth at the same timestamps). This leaves out the drift of the map itself, which relocalisation
cannot undo and the ATE already measures. A relocalisation more than --max-cm or --max-deg off is false. Prints one line per relocalisation and exits 1 when
any is false, 0 otherwise (also when there are none). Standard library only.
"""
import argparse
import json
import math
import sys


def read_tum(path):
    poses = []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p or p[0].startswith("#") or len(p) < 8:
                continue
            poses.append((float(p[0]), [float(v) for v in p[1:8]]))
    return poses


def nearest(poses, t, tolerance=0.02):
    best = min(poses, key=lambda p: abs(p[0] - t)) if poses else None
    return best[1] if best and abs(best[0] - t) <= tolerance else None


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def quat_conj(q):
    return [-q[0], -q[1], -q[2], q[3]]


def rotate(q, v):
    r = quat_mul(quat_mul(q, v + [0.0]), quat_conj(q))
    return r[:3]


def relative(a, b):
    """Pose b in the frame of pose a (tx ty tz qx qy qz qw)."""
    qa_inv = quat_conj(a[3:])
    d = [b[i] - a[i] for i in range(3)]
    return rotate(qa_inv, d), quat_mul(qa_inv, b[3:])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("groundtruth")
    ap.add_argument("--max-cm", type=float, default=5.0)
    ap.add_argument("--max-deg", type=float, default=3.0)
    a = ap.parse_args()
    est = read_tum(a.run + "/trajectory.tum")
    gt = read_tum(a.groundtruth)
    frames = [json.loads(line) for line in open(a.run + "/frames.jsonl") if line.strip()]
    last_good = None
    good = []  # (frame record, true pose) of tracked frames so far
    false_count = checked = 0
    for f in frames:
        state = f.get("state")
        if state == "relocalised" and last_good is not None:
            g_here = nearest(gt, f["timestamp"])
            ref = last_good
            if g_here is not None and good:
                def distance(item):
                    rel = relative(item[1], g_here)
                    angle = math.degrees(2.0 * math.acos(min(1.0, abs(rel[1][3]))))
                    return math.sqrt(sum(v * v for v in rel[0])) + 0.01 * angle
                # The map's first view of the place (least drift): the earliest tracked frame within 5 cm and
                # 3 degrees (truth) of the relocalised frame, else the nearest.
                close = [item for item in good if distance(item) <= 0.05 + 0.01 * 3.0]
                ref = close[0][0] if close else min(good, key=distance)[0]
            t0, t1 = ref["timestamp"], f["timestamp"]
            e0, e1, g0, g1 = nearest(est, t0), nearest(est, t1), nearest(gt, t0), nearest(gt, t1)
            if None in (e0, e1, g0, g1):
                print(f"frame {f['frame']}: relocalised, no ground truth near t={t1:.3f} or t={t0:.3f}: not checked")
                continue
            (de, qe), (dg, qg) = relative(e0, e1), relative(g0, g1)
            err_cm = 100.0 * math.dist(de, dg)
            dq = quat_mul(quat_conj(qg), qe)
            err_deg = math.degrees(2.0 * math.acos(min(1.0, abs(dq[3]))))
            bad = err_cm > a.max_cm or err_deg > a.max_deg
            false_count += bad
            checked += 1
            print(f"frame {f['frame']}: relocalised {f['frame'] - last_good['frame']} frames after the last good "
                  f"frame {last_good['frame']}; against frame {ref['frame']} (nearest place seen before): "
                  f"{err_cm:.2f} cm, {err_deg:.2f} deg from the truth"
                  f"{'  FALSE' if bad else ''}")
        if state in ("good", "weak", "relocalised"):
            last_good = f
            g = nearest(gt, f["timestamp"])
            if g is not None and state != "relocalised":
                good.append((f, g))
    print(f"{checked} relocalisations checked, {false_count} false (> {a.max_cm} cm or > {a.max_deg} deg)")
    return 1 if false_count else 0


if __name__ == "__main__":
    sys.exit(main())
