"""Measures candidate ground rules on real files (docs/classification.md,
"Ground on terrain we did not train on"). Not a test: a measurement run by hand.

    python tests/python/ground_rules.py lone BIN REAL_DIR
    python tests/python/ground_rules.py lowveg FILE.las CLASSIFIED.las

lone: thins the training files (IGN Montpellier, IGN St Barth, BC forest) to
0.01 and 0.04 points per m² (random points, seeds 1-5), classifies each copy
with BIN and scores, ISPRS-style (bare 2 vs objects 4-6), the slope test for
lone points (no other point within 3 m) with the slopes and reaches given,
emulated on BIN's labels: how the slope and the reach were checked on files
the snippet is not.

lowveg: scores, on a producer-labelled FILE and BIN's output for it, the rule
"a point called ground more than T above the plane fitted to the ground
points of its 3 x 3 window of cells is low vegetation", for cells of 0.5 / 1
m and T 0.1-0.3 m: bare vs objects, and the total with class 3 as object.
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import laspy
import numpy as np

TRAINING = ["ign_montpellier_150x100m.laz", "ign_stbarth_100x100m.laz", "lasr_bcts_forest_1.laz"]


def thin(src, dst, per_m2, seed):
    f = laspy.read(src)
    area = (f.header.maxs[0] - f.header.mins[0]) * (f.header.maxs[1] - f.header.mins[1])
    c = np.asarray(f.classification)
    ok = np.flatnonzero((c != 7) & (c != 18))
    n = min(max(3, int(area * per_m2)), len(ok))
    keep = np.sort(np.random.default_rng(seed).choice(ok, size=n, replace=False))
    g = laspy.LasData(f.header)
    g.points = f.points[keep]
    g.write(dst)


def errors(c, lab):
    bare, obj = c == 2, (c >= 4) & (c <= 6)
    return np.array([bare.sum(), obj.sum(), (bare & (lab != 2)).sum(), (obj & (lab == 2)).sum()])


def lone_rules(orig, ours, slopes, reaches):
    c = np.asarray(orig.classification)
    lab = np.asarray(ours.classification)
    p = np.c_[orig.x, orig.y, orig.z]
    d3 = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(-1))
    np.fill_diagonal(d3, np.inf)
    d2 = np.sqrt(((p[:, None, :2] - p[None, :, :2]) ** 2).sum(-1))
    np.fill_diagonal(d2, np.inf)
    lone = d3.min(1) > 3.0
    g = lab == 2
    out = {"forest": errors(c, lab)}
    if not g.any():
        return out
    near = d2[:, g].min(1)
    for s in slopes:
        cone = (p[g, 2][None, :] + s * d2[:, g]).min(1)
        for reach in reaches:
            moved = lone & ~g & (p[:, 2] <= cone) & (near > reach)
            out[(s, reach)] = errors(c, np.where(moved, 2, lab))
    return out


def lone(binary, real):
    slopes, reaches = (0.1, 0.2, 0.22, 0.3, 0.5), (0, 8, 16, 24, 32)
    with tempfile.TemporaryDirectory() as work:
        for name in TRAINING:
            for per_m2 in (0.01, 0.04):
                total = {}
                for seed in range(1, 6):
                    copy, out = Path(work, "copy.las"), Path(work, "out.las")
                    thin(Path(real, name), copy, per_m2, seed)
                    subprocess.run([binary, "classify", "--in", copy, "--out", out],
                                   check=True, capture_output=True)
                    for k, v in lone_rules(laspy.read(copy), laspy.read(out), slopes, reaches).items():
                        total[k] = total.get(k, 0) + v
                for k, (nb, no, t1, t2) in total.items():
                    rule = "forest alone" if k == "forest" else f"slope {k[0]}, reach {k[1]} m"
                    print(f"{name} @ {per_m2}/m², {rule}: type I {t1}/{nb}, type II {t2}/{no}, "
                          f"total {100 * (t1 + t2) / max(nb + no, 1):.2f} %")


def plane_reference(x, y, z, g, cell):
    """Height at each point of the plane fitted to the ground points of its 3 x 3 cells."""
    x0, y0 = x.min(), y.min()
    i, j = ((x - x0) / cell).astype(int), ((y - y0) / cell).astype(int)
    cx, cy = (x - x0) - i * cell, (y - y0) - j * cell
    zm = z[g].mean()
    shape = (j.max() + 3, i.max() + 3)
    sums = {}
    for key, v in dict(n=np.ones_like(cx), x=cx, y=cy, z=z - zm, xx=cx * cx, xy=cx * cy,
                       yy=cy * cy, xz=cx * (z - zm), yz=cy * (z - zm)).items():
        s = np.zeros(shape)
        np.add.at(s, (j[g] + 1, i[g] + 1), v[g])
        sums[key] = s
    m = np.zeros((len(x), 3, 3))
    r = np.zeros((len(x), 3))
    for a in (-1, 0, 1):
        for b in (-1, 0, 1):
            at = (j + 1 + a, i + 1 + b)
            n, sx, sy, sz = (sums[k][at] for k in "nxyz")
            dx, dy = b * cell, a * cell
            sx2, sy2 = sx + dx * n, sy + dy * n
            sxx = sums["xx"][at] + 2 * dx * sx + dx * dx * n
            syy = sums["yy"][at] + 2 * dy * sy + dy * dy * n
            sxy = sums["xy"][at] + dy * sx + dx * sy + dx * dy * n
            m += np.stack([np.stack([n, sx2, sy2], -1), np.stack([sx2, sxx, sxy], -1),
                           np.stack([sy2, sxy, syy], -1)], -2)
            r += np.stack([sz, sums["xz"][at] + dx * sz, sums["yz"][at] + dy * sz], -1)
    ok = m[:, 0, 0] >= 6
    m[~ok] = np.eye(3)
    ok &= np.abs(np.linalg.det(m)) > 1e-6
    m[~ok] = np.eye(3)
    sol = np.linalg.solve(m, r[..., None])[..., 0]
    return np.where(ok, sol[:, 0] + sol[:, 1] * cx + sol[:, 2] * cy + zm, np.nan)


def lowveg(path, classified):
    o, u = laspy.read(path), laspy.read(classified)
    c, ours = np.asarray(o.classification), np.asarray(u.classification)
    x, y, z = np.asarray(o.x), np.asarray(o.y), np.asarray(o.z)
    g = ours == 2
    low = c == 3

    def line(lab, rule):
        nb, no, t1, t2 = errors(c, lab)
        t3 = (low & (lab == 2)).sum()
        print(f"{Path(path).name}, {rule}: type I {100 * t1 / max(nb, 1):.2f} %, type II "
              f"{100 * t2 / max(no, 1):.2f} %, total {100 * (t1 + t2) / max(nb + no, 1):.2f} %, "
              f"with class 3 {100 * (t1 + t2 + t3) / max(nb + no + low.sum(), 1):.2f} % "
              f"({t3} of {low.sum()} class 3 called ground)")

    line(ours, "as classified")
    for cell in (0.5, 1.0):
        ref = plane_reference(x, y, z, g, cell)
        for t in (0.1, 0.15, 0.2, 0.25, 0.3):
            line(np.where(g & (z - ref > t), 5, ours), f"cells {cell} m, {t} m over the plane")


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "lone":
        lone(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 4 and sys.argv[1] == "lowveg":
        lowveg(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
