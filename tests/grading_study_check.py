#!/usr/bin/env python3
"""Oracle of a preparation study's grading axis (tests/study_grading.sh): each sample job drew from its own curve.
From the study config's curves, independently of src/packing.cpp: every sample named _g<its grading>, its job.yaml
giving that curve as sample.grading and none of the power law's keys, study.json's cu the curve's D60/D10 (the curve
linear in ln d between sieves, as ASTM D6913 reads a curve off semi-log paper), the drawn sample's D10 inside the
curve's sieve range and its Cu within DRAWN_CU of the curve's (300 spheres: 1.27-1.31 drawn for 1.32, 1.89-1.97
for 1.99 measured; mass of a few coarse spheres scatters), and the report's preparation rows one per grading."""
import json
import math
import os
import sys

import yaml

DRAWN_CU = 0.10  # relative: the few coarse spheres of 300 carry the top of a curve (the plan warns of 9 points)
study_file, out = sys.argv[1], sys.argv[2]
curves = yaml.safe_load(open(study_file))["axes"]["grading"]
idx = json.load(open(os.path.join(out, "study.json")))
report = open(os.path.join(out, "report.md")).read()
fails = []


def diameter_at(curve, percent):
    d, p = curve["diameter"], curve["passing"]
    for k in range(1, len(d)):
        if p[k] >= percent:
            return math.exp(math.log(d[k - 1]) + (percent - p[k - 1]) / (p[k] - p[k - 1]) * math.log(d[k] / d[k - 1]))
    raise ValueError(percent)


seen = set()
for j in idx["samples"]:
    g = j.get("grading")
    if g not in curves:
        fails.append(f"{j['name']}: grading {g!r} is not one of the study's {sorted(curves)}")
        continue
    seen.add(g)
    c = curves[g]
    if not j["name"].endswith("_g" + g):
        fails.append(f"{j['name']}: the name does not end with _g{g}")
    cfg = yaml.safe_load(open(os.path.join(out, "jobs", j["name"], "job.yaml")))["sample"]
    if [float(x) for x in cfg.get("grading", {}).get("diameter", [])] != [float(x) for x in c["diameter"]] or \
       [float(x) for x in cfg["grading"].get("passing", [])] != [float(x) for x in c["passing"]]:
        fails.append(f"{j['name']}: job.yaml's sample.grading {cfg.get('grading')} is not the study's {g} {c}")
    if {"D", "r_min", "r_max"} & set(cfg):
        fails.append(f"{j['name']}: job.yaml keeps the power law's {sorted({'D', 'r_min', 'r_max'} & set(cfg))}")
    cu = diameter_at(c, 60) / diameter_at(c, 10)
    if abs(j["cu"] - cu) > 1e-5 * cu:
        fails.append(f"{j['name']}: study.json cu {j['cu']} against the curve's {cu:.6g}")
    drawn = json.load(open(os.path.join(out, j["dir"], "summary.json")))["sample"]
    if not c["diameter"][0] <= drawn["d10"] <= c["diameter"][-1]:
        fails.append(f"{j['name']}: drawn D10 {drawn['d10']} outside the curve's sieves {c['diameter'][0]}-{c['diameter'][-1]}")
    if abs(drawn["cu"] - cu) > DRAWN_CU * cu:
        fails.append(f"{j['name']}: drawn Cu {drawn['cu']:.3f} more than {DRAWN_CU:.0%} from the curve's {cu:.3f}")
if seen != set(curves):
    fails.append(f"no sample of {sorted(set(curves) - seen)}")
prep = report.split("## Preparation")[1].split("\n## ")[0] if "## Preparation" in report else ""
for g in curves:
    rows = [line for line in prep.splitlines() if line.startswith("| sample_") and line.split(" | ")[0].endswith("_g" + g)]
    if len(rows) != 1:
        fails.append(f"the Preparation section has {len(rows)} rows of grading {g} (one, its seeds together)")
print("\n".join(fails) or f"grading study: {len(idx['samples'])} samples of {len(curves)} curves as asked")
sys.exit(1 if fails else 0)
