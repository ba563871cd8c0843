#!/usr/bin/env python3
"""Known-answer test of grainlab plot's grading figure (grainlab_plot.py fig_grading, sieve_curve, grading_indices): a
run whose first snapshot holds 80 spheres of d = 1 mm and 20 of 2 mm (volumes 80 and 160 in units of the small one),
so by mass P = 33.33 % at 1 mm and 100 % at 2 mm. In ln d between the two: D50 = 2^((50 - 33.33)/66.67) = 2^0.25 mm,
D60 = 2^0.4 mm; D10 and D30 lie below the first point, so 1 mm: Cu = 2^0.4 = 1.3195, Cc = 2^-0.4 = 0.7579 (the
run's plan reads the same curve: packing.cpp grading_indices, test Packing.AGradingIsDrawnByMassAsItsCurve). Its
config.yaml asks 0 / 40 / 100 % at 1 / 1.5 / 2 mm: drawn 33.33 / 33.33 / 100, the largest miss +33.33 points at 1 mm.
A run from that run's saved sample (sample.file, as a study's shear job) is compared with the same asked curve. A run
without snapshots draws nothing."""
import contextlib
import io
import math
import os
import shutil
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import grainlab_plot  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/sieve_check"
shutil.rmtree(work, ignore_errors=True)
run = os.path.join(work, "two_sizes")
os.makedirs(os.path.join(run, "snapshots"))
r = np.array([0.5e-3] * 80 + [1.0e-3] * 20)
np.random.default_rng(3).shuffle(r)
with h5py.File(os.path.join(run, "snapshots", "snap_00000.h5"), "w") as f:
    f["particles/r"] = r
with open(os.path.join(run, "config.yaml"), "w") as f:
    f.write("sample:\n  count: 100\n  grading:\n    diameter: [0.001, 0.0015, 0.002]\n    passing: [0, 40, 100]\n"
            "  seed: 1\n")
reused = os.path.join(work, "reused")
os.makedirs(os.path.join(reused, "snapshots"))
shutil.copy(os.path.join(run, "snapshots", "snap_00000.h5"), os.path.join(reused, "snapshots"))
with open(os.path.join(reused, "config.yaml"), "w") as f:
    f.write(f"sample:\n  file: {os.path.join(run, 'sample_consolidate.h5')}\n")
bare = os.path.join(work, "no_snapshots")
os.makedirs(bare)
out = os.path.join(work, "figures")
os.makedirs(out)
fails = []
text = io.StringIO()
with contextlib.redirect_stdout(text):
    found = grainlab_plot.fig_grading([run, reused, bare], out)
printed = text.getvalue()
print(printed)
want = {"d10": 1e-3, "d30": 1e-3, "d50": 1e-3 * 2 ** 0.25, "d60": 1e-3 * 2 ** 0.4, "cu": 2 ** 0.4, "cc": 2 ** -0.4}
got = found.get(run, {})
for k, v in want.items():
    if not math.isclose(got.get(k, float("nan")), v, rel_tol=1e-12):
        fails.append(f"{k} = {got.get(k)}, want {v}")
if bare in found:
    fails.append("a run without snapshots has a grading")
line = ("grading: two_sizes: 100 spheres, D50 = 1.19 mm, Cu = 1.32, Cc = 0.758 (by mass); against sample.grading: "
        "+33.33 points at 1 mm (the largest miss)")
if line not in printed:
    fails.append(f"the printed line is not '{line}'")
if line.replace("two_sizes", "reused") not in printed:
    fails.append("the run from the saved sample is not compared with the curve its sample's run asked")
if not os.path.isfile(os.path.join(out, "grading.png")):
    fails.append("no figures/grading.png")
if fails:
    sys.exit("sieve_check: " + "; ".join(fails))
print("sieve_check: ok")
