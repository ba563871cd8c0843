#!/usr/bin/env python3
"""Known-answer test of the study report's isotropic compression section (grainlab_plot.py compression_section), on
synthetic preparation studies whose samples' summary.json stages lie exactly on lines in ln p'.
- Seed 1: loading 50 -> 100 -> 200 -> 400 -> 800 kPa on e = 0.80 - 0.030 ln(p'/1 kPa), e_inner on 0.70 - 0.020 ln;
  unloading 800 -> 200 -> 50 on slopes 0.010 (e) and 0.008 (e_inner); then a reloading to 400 kPa, which is no part of
  either branch (fitted with it, kappa would not be exact). The row: lambda 0.0300 ± 0.0000, 0.0200 ± 0.0000, kappa
  0.0100 ± 0.0000, 0.0080 ± 0.0000 (exact lines through 5 and 3 stages).
- Seed 2: lambda 0.032 and 0.022, two unloading stages (800 -> 200) only: kappa from two points, no ±.
- The two seeds together: mean ± sd [95 % half-width, t = 12.706] worked out here.
- A sample of one isotropic stage has no row, nor one that prepares and then consolidates at one target pressure
  (190.0 and 190.4 kPa measured: not a path, PATH_GAP); a study without any multi-stage sample has no section.
Tolerances: the printed values are exact to their 4 decimals, so the strings must match."""
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from synthetic_study import study_report  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/compression_check"
fails = []


def stages(lam, lam_in, kap, kap_in, unload, reload=()):
    out = []
    for p in (50, 100, 200, 400, 800):
        out.append((p, 0.80 - lam * math.log(p), 0.70 - lam_in * math.log(p)))
    e8, i8 = out[-1][1], out[-1][2]
    for p in unload:
        out.append((p, e8 + kap * math.log(800 / p), i8 + kap_in * math.log(800 / p)))
    for p in reload:
        out.append((p, out[-1][1] - 0.001, out[-1][2] - 0.001))
    return [{"name": f"c{k}", "type": "isotropic", "done": True, "steps": 100, "mu": 0.5, "p": p * 1e3, "q": 0, "e": e,
             "e_inner": ei, "e_core": ei} for k, (p, e, ei) in enumerate(out)]


def make(root, samples):
    shutil.rmtree(root, ignore_errors=True)
    listed = []
    for name, seed, st in samples:
        d = os.path.join(root, "jobs", name, "run")
        os.makedirs(d)
        with open(os.path.join(d, "config.yaml"), "w") as f:
            f.write("sample:\n  count: 5000\n  seed: %d\n" % seed)
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump({"config": "x", "stages": st}, f)
        with open(os.path.join(root, "jobs", name, "done"), "w") as f:
            f.write("ok\n")
        listed.append({"name": name, "dir": f"jobs/{name}/run", "mu_r": 0, "e0": 0, "p0": 0, "seed": seed,
                       "count": 5000})
    return study_report(root, [], samples=listed)


one = stages(0.030, 0.020, 0.010, 0.008, (200, 50), reload=(400,))
two = stages(0.032, 0.022, 0.012, 0.009, (200,))
flat = stages(0.03, 0.02, 0.01, 0.008, ())[:1]
same = [dict(flat[0], p=190.0e3), dict(flat[0], name="c1", p=190.4e3, e=flat[0]["e"] - 0.002)]
text = make(os.path.join(work, "mixed"), [("sample_a_s1_n5000", 1, one), ("sample_a_s2_n5000", 2, two),
                                          ("sample_b_s1_n5000", 1, flat), ("sample_c_s1_n5000", 1, same)])
sec = text.split("## Isotropic compression")[1].split("\n## ")[0] if "## Isotropic compression" in text else ""
want = ["| sample_a_s1_n5000 | 50 → 100 → 200 → 400 → 800 → 200 → 50 | 0.0300 ± 0.0000 | 0.0200 ± 0.0000 | "
        "0.0100 ± 0.0000 | 0.0080 ± 0.0000 |",
        "| sample_a_s2_n5000 | 50 → 100 → 200 → 400 → 800 → 200 | 0.0320 ± 0.0000 | 0.0220 ± 0.0000 | 0.0120 | 0.0090 |"]


def spread(a, b):
    m, sd = (a + b) / 2, abs(a - b) / math.sqrt(2)
    return f"{m:.4f} ± {sd:.4f} [{12.706 * sd / math.sqrt(2):.4f}]"


want.append(f"| sample_a_s*_n5000 | 2 | {spread(0.030, 0.032)} | {spread(0.020, 0.022)} | {spread(0.010, 0.012)} | "
            f"{spread(0.008, 0.009)} |")
rows = [line for line in sec.splitlines() if line.startswith("| sample_")]
if rows != want:
    fails.append("rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
if "figures/compression.png" not in text or not os.path.isfile(os.path.join(work, "mixed", "figures", "compression.png")):
    fails.append("no figures/compression.png, or the report does not name it")
text = make(os.path.join(work, "single"), [("sample_b_s1_n5000", 1, flat), ("sample_c_s1_n5000", 1, same)])
if "## Isotropic compression" in text or "compression.png" in text:
    fails.append("a study of single-stage samples has a compression section: " + text)
if fails:
    sys.exit("\n".join(fails))
print("compression ok")
