#!/usr/bin/env python3
"""Known-answer test of perf/speed_vs_error.py's bookkeeping (measure, write_report) on stubbed runs: the real runs
take an hour and a float build, so no test could run them, and a slip in the medians, the pairing of rates with
cases or the bitwise round check would otherwise go unseen until someone reads SPEED_VS_ERROR.md.

The stubs: every case's q lies above the reference by f * 1 kPa * eps / 5 %, so against p'_0 = 100 kPa its error is
f * 1e-2 over 5 % and f * 2e-3 over the first 1 %; its drift is f^2 * 1e-3. Round r of every case (r = 0, 1, 2)
times the shear at (3, 1, 1.5)[r] * 1e6 p-steps/s in (5, 9, 6)[r] s and step() at (4, 7, 5)[r] * 1e6 p-steps/s for
(1, 4, 2)[r] s per simulated ms: each median (1.5e6, 6, 5e6, 2) differs from the first round's, the last round's,
the mean, the smallest and the largest. The shear rates are further scaled by the case, (1 + f) x skin / 0.1 mm, halved
in float, so a rate reported against another case's row shows.
Then a round whose q differs by one ulp, or whose drift does, must stop the report (the errors are deterministic).
Values are compared exactly or to 1e-12 relative (float formatting of exact inputs)."""
import importlib.util
import os
import shutil
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
spec = importlib.util.spec_from_file_location("sve", os.path.join(ROOT, "perf", "speed_vs_error.py"))
sve = importlib.util.module_from_spec(spec)
spec.loader.exec_module(sve)

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/speed_vs_error_check"
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
sve.REPORT = work
P0 = 1e5
EPS = np.linspace(0, 0.05, 51)
REF = dict(eps=EPS, q=2e5 * EPS / 0.05, p=np.full_like(EPS, P0), steps=100000.0, inner_skin=0.5)
calls = {}
perturb = {"q": False, "drift": False}


def shear(sample, f, skin, n, prec="double"):
    r = calls.setdefault(("shear", f, skin, prec), 0)
    calls[("shear", f, skin, prec)] += 1
    q = REF["q"] + f * 1e3 * EPS / 0.05
    if r == 1 and perturb["q"]:
        q = q.copy()
        q[-1] = np.nextafter(q[-1], np.inf)
    scale = (1 + f) * skin / 1e-4 * (0.5 if prec == "float" else 1)
    return dict(eps=EPS, q=q, p=REF["p"], rate=(3e6, 1e6, 1.5e6)[r] * scale, wall=(5.0, 9.0, 6.0)[r], steps=1000.0 / f,
                inner_skin=0.5)


def drift(f, skin, prec="double"):
    r = calls.setdefault(("drift", f, skin, prec), 0)
    calls[("drift", f, skin, prec)] += 1
    d = f * f * 1e-3
    if r == 1 and perturb["drift"]:
        d = np.nextafter(d, np.inf)
    return d, 2 * d, (4e6, 7e6, 5e6)[r], (1.0, 4.0, 2.0)[r]


sve.shear, sve.drift = shear, drift
fails = []


def close(a, b):
    return abs(a - b) <= 1e-12 * max(abs(a), abs(b))


rows = sve.measure("sample.h5", 800, REF, 3)
if len(rows) != 20 or len({(r["f"], r["skin"], r["prec"]) for r in rows}) != 20:
    fails.append(f"expected 20 distinct cases (3 skins x 5 f double, 5 f float), got {len(rows)}")
for r in rows:
    f = r["f"]
    scale = (1 + f) * r["skin"] / 1e-4 * (0.5 if r["prec"] == "float" else 1)
    want = dict(q_err=f * 1e-2, q_err1=f * 2e-3, drift=f * f * 1e-3, band=2 * f * f * 1e-3, q_rate=1.5e6 * scale, q_wall=6.0,
                d_rate=5e6, d_cost=2.0, steps=1000.0 / f)
    bad = {k: (r[k], v) for k, v in want.items() if not close(r[k], v)}
    if bad or not (close(r["q_span"][0], 1e6 * scale) and close(r["q_span"][1], 3e6 * scale)) \
            or r["d_span"] != (4e6, 7e6):
        fails.append(f"case f={f} skin={r['skin']} {r['prec']}: (got, want) {bad}, spans {r['q_span']} {r['d_span']}")
if any(v != 3 for v in calls.values()):
    fails.append(f"every case must run once per round: {calls}")
sve.write_report(rows, REF, P0)
md = open(os.path.join(work, "SPEED_VS_ERROR.md")).read()
default = [l for l in md.splitlines() if "**(default)**" in l]
if default != ["| 0.2 **(default)** | 0.1 | double | 2.00e-03 | 4.00e-04 | 5000 | 6.0 | 1.8e+06, 1.2e+06-3.6e+06 | 4.00e-05 |"
               " 8.00e-05 | 2 | 5e+06, 4e+06-7e+06 |"]:
    fails.append(f"the default row: {default}")
if "f = 0.2 with a 0.1 mm skin: energy drift 4.0e-05 over 10^4 steps (6x below f = 0.5)" not in md:
    fails.append("the default's paragraph does not give its drift and the factor to f = 0.5 (2.5e-4 / 4e-5)")
if not os.path.isfile(os.path.join(work, "speed_vs_error.png")):
    fails.append("no speed_vs_error.png")
for key in ("q", "drift"):
    calls.clear()
    perturb.update(q=key == "q", drift=key == "drift")
    try:
        sve.measure("sample.h5", 800, REF, 2)
        fails.append(f"a round whose {key} differs by one ulp was accepted")
    except SystemExit as e:
        if "differs from round 1" not in str(e):
            fails.append(f"a round whose {key} differs stopped with '{e}'")
if fails:
    sys.exit("\n".join(fails))
print("speed_vs_error_check ok")
