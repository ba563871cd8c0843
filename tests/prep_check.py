#!/usr/bin/env python3
"""Oracle of a preparation study's report (tests/study_prep.sh): every row of report.md's Preparation section and
every size-convergence line recomputed from the samples' own summary.json files (the last isotropic stage), grouped
by their name without the seed, independently of scripts/grainlab_plot.py: mean ± sd [t_0.975 sd / sqrt(n)] of e,
e_inner, e_core and e_core - e_inner over the seeds; the difference of the two largest sizes' interior means ± the
standard error of that difference. The Samples section has one row per sample."""
import json
import math
import os
import re
import sys

import numpy as np

T975 = {1: 12.706, 2: 4.303, 3: 3.182}  # Student's t, 0.975 quantile, to the 3 decimals of the printed tables (as the report)
out = sys.argv[1]
idx = json.load(open(os.path.join(out, "study.json")))
report = open(os.path.join(out, "report.md")).read()
fails = []
if idx["jobs"]:
    fails.append(f"a preparation study has shear jobs: {idx['jobs']}")
samples = idx["samples"]
stage = {}
for j in samples:
    st = json.load(open(os.path.join(out, j["dir"], "summary.json")))["stages"]
    stage[j["name"]] = [s for s in st if s["type"] == "isotropic"][-1]
sec = report.split("## Samples")[1].split("\n## ")[0] if "## Samples" in report else ""
rows = [line for line in sec.splitlines() if line.startswith("| sample_")]
if len(rows) != len(samples):
    fails.append(f"the Samples section has {len(rows)} rows for {len(samples)} samples")


def spread(v):
    m, sd = float(np.mean(v)), float(np.std(v, ddof=1))
    return f"{m:.4f} ± {sd:.4f} [{T975[len(v) - 1] * sd / math.sqrt(len(v)):.4f}]"


groups = {}
for j in samples:
    groups.setdefault(j["name"].replace(f"_s{j['seed']}_", "_s*_"), []).append(j)
prep = report.split("## Preparation")[1].split("\n## ")[0] if "## Preparation" in report else ""
for name, g in groups.items():
    s = [stage[j["name"]] for j in sorted(g, key=lambda j: j["seed"])]
    want = (f"| {name} | {g[0]['count']} | {len(g)} ({', '.join(str(j['seed']) for j in sorted(g, key=lambda j: j['seed']))})"
            f" | {spread([x['e'] for x in s])} | {spread([x['e_inner'] for x in s])} | {spread([x['e_core'] for x in s])}"
            f" | {spread([x['e_core'] - x['e_inner'] for x in s])} | ")
    # the gas's interior as placed: the first series row's e_inner
    gas = []
    for j in g:
        with open(os.path.join(out, j["dir"], "series.csv")) as f:
            head, first = f.readline().strip().split(","), f.readline().strip().split(",")
        gas.append(1 / (1 + float(first[head.index("e_inner")])))
    want_end = f" | {spread(gas)} |"
    got = [line for line in prep.splitlines() if line.startswith(f"| {name} |")]
    if len(got) != 1 or not got[0].startswith(want) or not got[0].endswith(want_end):
        fails.append(f"row of {name}:\n  got    {got}\n  wanted {want}...{want_end}")
# Size convergence: per series of sizes (the name without seed and count; a grading's _g<name>, an E's _E<E> and a
# preparation stage axis's _<stage>-<key><value> after the count),
# the two largest sizes' interior e_0; a series of one size has no line.
series = {}
for name, g in groups.items():
    series.setdefault(re.sub(r"_n\d+(?=$|_)", "", name), []).append(g)
for name, gs in series.items():
    gs = sorted(gs, key=lambda g: g[0]["count"])
    if len(gs) < 2:
        if any(line.startswith(f"- {name}: ") for line in prep.splitlines()):
            fails.append(f"a size line of {name}, which has one size")
        continue
    a, b = ([stage[j["name"]]["e_inner"] for j in g] for g in gs[-2:])
    d = np.mean(b) - np.mean(a)
    se = math.sqrt(np.var(a, ddof=1) / len(a) + np.var(b, ddof=1) / len(b))
    want = f"- {name}: interior e_0 at {', '.join(str(g[0]['count']) for g in gs)} spheres: "
    want2 = f"; from {gs[-2][0]['count']} to {gs[-1][0]['count']} {d:+.4f} ± {se:.4f}, " + (
        "within two standard errors" if abs(d) <= 2 * se else "more than two standard errors")
    got = [line for line in prep.splitlines() if line.startswith(want)]
    if len(got) != 1 or want2 not in got[0]:
        fails.append(f"size line of {name}: got {got}, wanted '{want}...{want2}'")
if fails:
    sys.exit("\n".join(fails))
print(f"prep ok: {len(groups)} groups of {len(samples)} samples, {len(series)} size series")
