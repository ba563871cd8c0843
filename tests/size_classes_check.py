#!/usr/bin/env python3
"""Known answers of scripts/size_classes.py (the load by size class), and its stress against the run's own.
- Four spheres: s0 (r 1, at the origin), s1 (r 0.5, at x 1.4), s2 (r 1, at x 2.8), s3 (r 1, at y 1.9), each contact's
  overlap 0.1, forces f_n 2 (s0-s1), 3 (s1-s2), 1 (s0-s3). Each sphere's moment trace is (r - delta/2) f_n per contact:
  s1 (the fine class of a gap grading 0.8-1.2 / 1.6-2.4 mm, scaled) gets 0.45 x 2 + 0.45 x 3 = 2.25 of the
  contacts' sum |d| f_n = 2.8 + 4.2 + 1.9 = 8.9, so p_share = 2.25/8.9; its volume share 0.125/3.125 = 0.04, alpha =
  p_share / 0.04; Z 2 (fine) and 4/3 (coarse), rattlers 0 and 2/3. Four equal-mass classes of equal spheres: one.
- The smoke run's snapshots (argument 1, the run; 2, a scratch directory): the classes' p shares add to 1, and the
  contacts' sum over 3 V, V = V_s (1 + e) of the series row at the snapshot's step, is the series' p_contacts (the
  device's Christoffersen stress) to 1e-6 (e is written to 12 digits)."""
import csv
import glob
import math
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import size_classes as S  # noqa: E402

fails = []
x = np.array([[0, 0, 0], [1.4, 0, 0], [2.8, 0, 0], [0, 1.9, 0]], float)
r = np.array([1.0, 0.5, 1.0, 1.0])
i, j, fn = np.array([0, 1, 0]), np.array([1, 2, 3]), np.array([2.0, 3.0, 1.0])
classes = [(0.8, 1.2), (1.6, 2.4)]
rows = S.load_share(x, r, i, j, fn, classes)
fine, coarse = rows
want = [(fine["p_share"], 2.25 / 8.9), (coarse["p_share"], 6.65 / 8.9), (fine["volume_share"], 0.04),
        (fine["alpha"], 2.25 / 8.9 / 0.04), (fine["z"], 2), (coarse["z"], 4 / 3), (fine["rattler_share"], 0),
        (coarse["rattler_share"], 2 / 3), (fine["spheres"], 1), (coarse["spheres"], 3)]
for k, (got, w) in enumerate(want):
    if not math.isclose(got, w, rel_tol=1e-12):
        fails.append(f"four spheres: value {k} is {got}, want {w}")
if len(S.quartile_classes(np.full(10, 0.3))) != 1:
    fails.append("equal spheres make more than one class")

run, work = sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "/tmp/size_classes_check"
with open(os.path.join(run, "series.csv")) as f:
    series = {int(float(row["step"])): row for row in csv.DictReader(f)}
checked = 0
for p in sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5"))):
    with h5py.File(p, "r") as f:
        step = int(f.attrs["step"])
        xs, rs = f["particles/x"][:], f["particles/r"][:]
        i, j, fn = f["contacts/i"][:], f["contacts/j"][:], f["contacts/f_n"][:]
    if len(fn) == 0 or step not in series:
        continue
    got = S.load_share(xs, rs, i, j, fn, S.quartile_classes(rs))
    if abs(sum(g["p_share"] for g in got) - 1) > 1e-12:
        fails.append(f"{p}: the classes' p shares add to {sum(g['p_share'] for g in got)}")
    total = float(np.sum(np.linalg.norm(xs[j] - xs[i], axis=1) * fn))
    V = float(np.sum(4 / 3 * math.pi * rs ** 3)) * (1 + float(series[step]["e"]))
    pc = float(series[step]["p_contacts"])
    if not math.isclose(total / (3 * V), pc, rel_tol=1e-6):
        fails.append(f"{p}: the spheres' moments give p' {total / (3 * V)}, the series p_contacts {pc}")
    checked += 1
if checked == 0:
    fails.append(f"no snapshot of {run} at a series row")
os.makedirs(work, exist_ok=True)
last = S.write_csv(run, work)
if not os.path.isfile(os.path.join(work, "size_classes.csv")) or len(last) != 4:
    fails.append("no size_classes.csv of four classes")
if fails:
    sys.exit("size_classes_check: " + "; ".join(fails))
print(f"size_classes_check: ok ({checked} snapshots against the series)")
