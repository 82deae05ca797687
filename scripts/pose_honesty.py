#!/usr/bin/env python3
"""How honest a run's tracking state is about its pose (issue 52's measure).

    scripts/pose_honesty.py RUN_DIR GROUNDTRUTH [--off-m 0.5] [--after FRAME] [--per-frame CSV]

Reads RUN_DIR/frames.jsonl (each frame's pose and state) and a TUM groundtruth.txt. The estimate and the truth
are anchored at the first frame (as a robot's map frame is: no alignment fitted), and each frame's position
error is the distance between them. Prints one JSON object: the frames, the posed share (every state but
lost), the ATE rmse over the posed frames (anchored, metres), the worst error, and the count of `good` frames
more than --off-m from the truth (the lie the issue counts). --after: the ATE over the posed frames from that
frame on as well (after a relocalisation). --per-frame: each frame's `frame,state,error_m` into that file."""
import argparse
import json
import math
import sys


def quat_to_rot(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def apply(R, t, p):
    return [sum(R[i][j] * p[j] for j in range(3)) + t[i] for i in range(3)]


def transpose(R):
    return [[R[j][i] for j in range(3)] for i in range(3)]


def read_truth(path):
    truth = []
    with open(path) as f:
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            truth.append((v[0], v[1:4], v[4:8]))
    return truth


def nearest(truth, stamp):
    lo, hi = 0, len(truth) - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if truth[mid][0] < stamp:
            lo = mid + 1
        else:
            hi = mid
    best = min((i for i in (lo - 1, lo) if 0 <= i < len(truth)), key=lambda i: abs(truth[i][0] - stamp))
    return truth[best] if abs(truth[best][0] - stamp) < 0.02 else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('run')
    ap.add_argument('groundtruth')
    ap.add_argument('--off-m', type=float, default=0.5)
    ap.add_argument('--after', type=int, default=None)
    ap.add_argument('--per-frame', default=None)
    a = ap.parse_args()
    truth = read_truth(a.groundtruth)
    frames = []
    with open(a.run + '/frames.jsonl') as f:
        for line in f:
            if line.strip():
                frames.append(json.loads(line))
    if not frames or not truth:
        sys.exit('pose_honesty: no frames or no truth')
    anchor = None
    errors = []  # (frame, state, error m)
    for fr in frames:
        g = nearest(truth, fr['timestamp'])
        if g is None:
            continue
        if anchor is None:
            # truth_from_estimate = G0 * E0^-1
            Rg, tg = quat_to_rot(g[2]), g[1]
            Re, te = quat_to_rot(fr['quaternion']), fr['position']
            R = [[sum(Rg[i][k] * transpose(Re)[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
            t = [tg[i] - sum(R[i][j] * te[j] for j in range(3)) for i in range(3)]
            anchor = (R, t)
        p = apply(anchor[0], anchor[1], fr['position'])
        errors.append((fr['frame'], fr['state'], math.dist(p, g[1])))
    if a.per_frame:
        with open(a.per_frame, 'w') as f:
            f.write('frame,state,error_m\n')
            f.writelines('%d,%s,%.4f\n' % e for e in errors)
    posed = [e for e in errors if e[1] != 'lost']
    after = [e for e in posed if a.after is not None and e[0] >= a.after]
    rmse = lambda es: math.sqrt(sum(e[2] ** 2 for e in es) / len(es)) if es else None
    lies = [e for e in errors if e[1] == 'good' and e[2] > a.off_m]
    out = {
        'frames': len(errors),
        'posed_share': len(posed) / len(errors),
        'ate_posed_m': rmse(posed),
        'worst_m': max((e[2] for e in errors), default=None),
        'good_off': len(lies),
        'first_good_off': lies[0][0] if lies else None,
        'states': {s: sum(1 for e in errors if e[1] == s) for s in sorted({e[1] for e in errors})},
    }
    if a.after is not None:
        out['ate_after_m'] = rmse(after)
    print(json.dumps(out))


if __name__ == '__main__':
    main()
