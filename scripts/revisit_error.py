#!/usr/bin/env python3
"""The same place on two passes of one run (issue 55): how far apart a run puts two visits of one place.

For every frame of the first pass and the frame of the second pass nearest to it along the drive (ground truth
within --along-m of each other along the corridor, at least --apart-s apart in time), the error of the relative
pose between the two visits: |t(E_i^-1 E_j) - t(G_i^-1 G_j)|, E the run's poses, G the truth. Needs no alignment
(the relative pose is frame-free). The drive's way back runs beside the way there, so the visits are paired by
their place along the corridor (ground-truth z, the synthetic corridor's axis), not by distance.

usage: scripts/revisit_error.py EST.tum GT.txt [--along-m 0.05] [--apart-s 10]
Prints the median, the 90th percentile and the max over the pairs, in cm, and how many pairs.
"""
import argparse
import math
import statistics


def read_tum(path):
    poses = {}
    for line in open(path):
        f = line.split()
        if not f or f[0].startswith("#"):
            continue
        t, x, y, z, qx, qy, qz, qw = map(float, f[:8])
        n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
        qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
        r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
             [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
             [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
        poses[round(t, 4)] = (r, (x, y, z))  # T_camera_to_world: rotation rows, translation
    return poses


def relative(a, b):
    """The translation of a^-1 b: b's position in a's camera frame."""
    r, t = a
    d = [b[1][k] - t[k] for k in range(3)]
    return [sum(r[k][c] * d[k] for k in range(3)) for c in range(3)]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("estimate")
    p.add_argument("truth")
    p.add_argument("--along-m", type=float, default=0.05)
    p.add_argument("--apart-s", type=float, default=10.0)
    a = p.parse_args()
    est, gt = read_tum(a.estimate), read_tum(a.truth)
    times = sorted(t for t in est if t in gt)
    errors = []
    for i, ti in enumerate(times):
        zi = gt[ti][1][2]
        best = None
        for tj in times[i + 1:]:
            if tj - ti < a.apart_s:
                continue
            d = abs(gt[tj][1][2] - zi)
            if d <= a.along_m and (best is None or d < best[0]):
                best = (d, tj)
        if best is None:
            continue
        tj = best[1]
        e, g = relative(est[ti], est[tj]), relative(gt[ti], gt[tj])
        errors.append(math.dist(e, g))
    if not errors:
        raise SystemExit("no frame pairs: the run does not pass one place twice")
    errors.sort()
    cm = [100 * e for e in errors]
    print(f"revisit error over {len(cm)} pairs: median {statistics.median(cm):.2f} cm, "
          f"90th percentile {cm[int(0.9 * (len(cm) - 1))]:.2f} cm, max {cm[-1]:.2f} cm")


if __name__ == "__main__":
    main()
