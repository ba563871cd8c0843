#!/usr/bin/env python3
"""Known-answer test of the study report's sample-scatter section (scripts/grainlab_plot.py seed_section).

A synthetic study of drained compressions at p' = 100 kPa: q/p' rises to its peak M at 10 % strain and falls to the
critical M_cs at 30 %, steady after; e falls from e_0 to e_c by 30 %, the interior's e_inner 0.05 below it; a_c =
0.1 + 0.01 x seed.
- Group A (seeds 1-4): M = 0.70, 0.72, 0.74, 0.76; M_cs = 0.60, 0.61, 0.62; e_0 = 0.75 + 0.01 x seed; e_c = 0.70 +
  0.001 x seed; seed 4 still compacting (e drifting), so 3 of 4 critical states. The cells are worked out here from
  the tabulated Student t (3.182 at 3 degrees of freedom, 4.303 at 2): e.g. max q/p' 0.730 ± 0.026 [0.041].
- Group B (p'_0 200 kPa in study.json, seeds 7-9): M = 0.60, 0.70, 0.80, so its peak angle scatters by ~2.6 deg and
  needs over 30 seeds for +-0.5 deg: the t quantile beyond the table (Cornish-Fisher), checked against tabulated
  values at 40, 60 and 120 degrees of freedom (2.021, 2.000, 1.980).
- Group C (p'_0 400 kPa, seeds 21 and 22, each at 1 and 2 /s, rate groups): a seed row per rate, and one rate series
  through all four tests named with s*, its limit's ± from the seeds' scatter about the line (0.750 ± 0.022).
- A test with one seed has no row; a study without two seeds of one test has no section.
- The figure's mean curve and band (ensemble) on two shears of known lines: mean 3 eps, sd sqrt(2) eps, on the grid
  from each shear's start to the shorter one's end.
- Each seed's p'_c is 0.2 % below the last: nine critical states at 1 /s, all at distinct p'_c but at one pressure
  level, get no critical-state line.
Tolerances: the cells are printed to 1-4 decimals from exact inputs, so the strings must match; the t quantiles to
the table's 3 decimals.
"""
import csv
import importlib.util
import json
import math
import os
import shutil
import sys

import numpy as np

from synthetic_study import study_report, SCRIPT
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/seed_check"
shutil.rmtree(work, ignore_errors=True)
cols = ["time", "step", "eps_a", "p", "q", "q_p", "e", "mu_r", "stage_type", "a_c", "a_d", "a_n", "a_t", "sff_share_c",
        "sff_share_d", "sff_share_n", "sff_share_t", "sff", "inertial_number", "sigma_x", "sigma_y", "sigma_z",
        "e_inner"]
jobs = []


def test(seed, p0, M, M_cs, e0, e_c, drifting=False, rate=0, I=1e-3):
    group = f"shear_drained_mur0.3_ebase_p{p0 / 1e3:g}k_s{seed}_n300" if rate else ""
    name = f"shear_drained_mur0.3_ebase_p{p0 / 1e3:g}k_s{seed}_n300" + (f"_rate{rate:g}" if rate else "")
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0, "axial_strain_rate": rate or 1}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i in range(41):
            ea = 0.01 * i
            qp = M * ea / 0.1 if ea <= 0.1 else M + (M_cs - M) * min(1.0, (ea - 0.1) / 0.2)
            e = e0 + (e_c - e0) * min(1.0, ea / 0.3) - (0.2 * (ea - 0.3) if drifting and ea > 0.3 else 0.0)
            p = 1e5 * (1 - 0.002 * seed if ea >= 0.3 else 1)  # p'_c 0.2 % apart per seed: one pressure level
            w.writerow(["shear", i, i, ea, p, qp * p, qp, e, 0.3, 2, 0.1 + 0.01 * seed, 0.05, 0.1, 0.02, 0.25, 0.25,
                        0.25, 0.25, qp, I, p - qp * p / 3, p - qp * p / 3, p + 2 * qp * p / 3, e - 0.05])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": group.replace("shear_drained", "sample"),
                 "mu_r": 0.3, "e0": 0, "p0": p0, "drainage": "drained", "direction": "compression", "b": 0,
                 "stress_path": "constant_sigma3", "seed": seed, "count": 300, "csr": 0, "cycles": 0,
                 "strain_amplitude": 0, "axial_strain_rate": rate, "rate_group": group})


for seed, M, M_cs in ((1, 0.70, 0.60), (2, 0.72, 0.61), (3, 0.74, 0.62), (4, 0.76, 0.63)):
    test(seed, 1e5, M, M_cs, 0.75 + 0.01 * seed, 0.70 + 0.001 * seed, drifting=seed == 4)
for seed, M in ((7, 0.60), (8, 0.70), (9, 0.80)):
    test(seed, 2e5, M, 0.6, 0.75, 0.70)
test(5, 3e5, 0.7, 0.6, 0.75, 0.70)  # one seed: no row
for seed, dm in ((21, 0.01), (22, -0.01)):  # a rate series on two seeds: M = 0.75 + 50 I +- 0.01
    for rate in (1, 2):
        test(seed, 4e5, 0.75 + 50 * 4e-4 * rate + dm, 0.6, 0.75, 0.70, rate=rate, I=4e-4 * rate)


def phi(m):
    return math.degrees(math.asin(3 * m / (6 + m)))


T = {2: 4.303, 3: 3.182}  # tabulated Student t, 0.975


def cell(v, digits):
    sd = float(np.std(v, ddof=1))
    return f"{np.mean(v):.{digits}f} ± {sd:.{digits}f} [{T[len(v) - 1] * sd / math.sqrt(len(v)):.{digits}f}]"


spec = importlib.util.spec_from_file_location("grainlab_plot", SCRIPT)
gp = importlib.util.module_from_spec(spec)
spec.loader.exec_module(gp)
fails = []
for dof, want in ((1, 12.706), (2, 4.303), (3, 3.182), (30, 2.042), (40, 2.021), (60, 2.000), (120, 1.980)):
    if abs(gp.t975(dof) - want) > 5e-4:
        fails.append(f"t975({dof}) = {gp.t975(dof):.4f}, tabulated {want}")


def needed(v):
    sd, n = float(np.std(v, ddof=1)), 2
    while gp.t975(n - 1) * sd / math.sqrt(n) > 0.5:
        n += 1
    return n


text = study_report(work, jobs)
if "## Sample-to-sample scatter (seed axis)" not in text:
    sys.exit("no sample-scatter section in report.md")
sec = text.split("## Sample-to-sample scatter (seed axis)")[1].split("\n## ")[0]
Ma, Mcs = [0.70, 0.72, 0.74, 0.76], [0.60, 0.61, 0.62]
pa = [phi(m) for m in Ma]
want_a = (f"| shear_drained_mur0.3_ebase_p100k_s*_n300 | 4 (1, 2, 3, 4) | {cell([0.76, 0.77, 0.78, 0.79], 4)} | "
          f"{cell([0.71, 0.72, 0.73, 0.74], 4)} | "
          f"{cell([100 * m for m in Ma], 1)} | {cell(Ma, 3)} | {cell(pa, 2)} | {needed(pa)} |")
want_a_cs = (f"| shear_drained_mur0.3_ebase_p100k_s*_n300 | 3 of 4 | 99.6 ± 0.2 [0.5] | {cell(Mcs, 3)} | "
             f"{cell([phi(m) for m in Mcs], 2)} | {cell([0.701, 0.702, 0.703], 4)} | {cell([0.651, 0.652, 0.653], 4)} | "
             f"{cell([0.11, 0.12, 0.13], 3)} | "
             f"{needed([phi(m) for m in Mcs])} |")
if "0.730 ± 0.026 [0.041]" not in want_a:  # the worked example of the docstring
    fails.append(f"the worked cell: {want_a}")
Mb = [0.60, 0.70, 0.80]
nb = needed([phi(m) for m in Mb])
want_b = (f"| shear_drained_mur0.3_ebase_p200k_s*_n300 | 3 (7, 8, 9) | 0.7500 ± 0.0000 [0.0000] | 0.7000 ± 0.0000 [0.0000] | "
          f"{cell([100 * m for m in Mb], 1)} | {cell(Mb, 3)} | {cell([phi(m) for m in Mb], 2)} | {nb} |")
for want in (want_a, want_a_cs, want_b):
    got = next((l for l in sec.splitlines() if l.startswith(want[:48]) and l.count("|") == want.count("|")
                and (" of " in l) == (" of " in want)), "")
    if got != want:
        fails.append(f"expected\n  {want}\ngot\n  {got}")
# The critical-state table's e_c interior column: the interior's e over the window (0.701 - 0.05 for seed 1), "-" for a
# test whose series has no e_inner (an older build's) is left to failure_criteria_check's series, which lack it.
cs_lines = text.split("## Critical states")[1].splitlines()
cs1 = next((l for l in cs_lines if l.startswith("| shear_drained_mur0.3_ebase_p100k_s1_n300 |")), "")
col = next((l for l in cs_lines if l.startswith("| test |")), "").split("|").index(" e_c interior ")
if cs1.split("|")[col].strip() != "0.6510":
    fails.append(f"critical-state row of seed 1: e_c interior 0.6510 expected, got '{cs1}'")
if nb <= 30:
    fails.append(f"group B should need more than 30 seeds (the t beyond the table), needs {nb}")
# Crossed with a rate axis: a seed group per rate, and one rate series through both seeds, the line's ± from their
# scatter: residuals +-0.01 at I = 4e-4 and 8e-4 give the intercept's standard error sqrt(2e-4 (1/4 + 3.6e-7 / 1.6e-7))
# = 0.022, and the series is named with s*.
for rate in (1, 2):
    m = 0.75 + 50 * 4e-4 * rate
    want = (f"| shear_drained_mur0.3_ebase_p400k_s*_n300_rate{rate} | 2 (21, 22) | 0.7500 ± 0.0000 [0.0000] | "
            "0.7000 ± 0.0000 [0.0000] | "
            f"{100 * m:.1f} ± {100 * 0.01 * math.sqrt(2):.1f} [{12.706:.1f}] | {m:.3f} ± {0.01 * math.sqrt(2):.3f} [{12.706 * 0.01:.3f}] |")
    if not any(l.startswith(want) for l in sec.splitlines()):
        fails.append(f"expected a seed row starting\n  {want}\nin\n{sec}")
rate_sec = text.split("## Rate dependence")[1].split("\n## ")[0] if "## Rate dependence" in text else ""
series = next((l for l in rate_sec.splitlines() if l.startswith("| shear_drained_mur0.3_ebase_p400k_s*_n300 |")), "")
if not series.startswith(f"| shear_drained_mur0.3_ebase_p400k_s*_n300 | 4 | 0.750 ± 0.022 ({phi(0.75):.1f}°) | +0.020 "
                         "(I = 4.0e-04, mean of 2) |"):
    fails.append(f"the rate series through both seeds: '{series}'")
# Replicates are one pressure level: no critical-state line through the 9 critical states at 1 /s (p'_c 95.8 to
# 99.8 kPa, all distinct), whose slope would be their scatter.
csl_row = next((l for l in text.split("## Critical-state lines")[1].splitlines() if l.startswith("| 0.3 | compression, 1/s |")), "")
if not csl_row.startswith("| 0.3 | compression, 1/s | 9 | fewer than 3 critical states 10 % apart in p'_c: no fit |"):
    fails.append(f"a critical-state line through replicates at one pressure: '{csl_row}'")
if "p300k" in sec:
    fails.append("a test with one seed has a row")
for fig in ("seeds.png", "seeds_curves.png"):
    if not os.path.isfile(os.path.join(work, "figures", fig)):
        fails.append(f"figures/{fig} missing")
# The figure's mean curve and band: two shears of q/p' = 2 eps and 4 eps from eps_a = 0.01 (so the grid starts from
# each shear's start), to 10 % and 20 % (so it stops at the shorter), give mean 3 eps and sd sqrt(2) eps on 0..0.1.
two = []
for slope, end in ((2, 0.1), (4, 0.2)):
    ea = 0.01 + np.linspace(0, end, 11)
    two.append({"monotonic": np.ones(11, bool), "eps_a": ea, "q_p": slope * (ea - 0.01)})
x, mean, sd = gp.ensemble(two, "q_p", 51)
if not (np.isclose(x[-1], 0.1) and np.allclose(mean, 3 * x, atol=1e-12) and np.allclose(sd, math.sqrt(2) * x, atol=1e-12)):
    fails.append(f"ensemble: grid to {x[-1]}, mean {mean[-1]} (want 0.3), sd {sd[-1]} (want {0.1 * math.sqrt(2)})")
for j in jobs:
    j["p0"] = j["seed"]  # every test its own group
if "## Sample-to-sample scatter" in study_report(work, jobs):
    fails.append("a study without two seeds of one test has a sample-scatter section")
for j in jobs:
    j["p0"] = 1e5  # replicates again, but of a study.json that names no seeds (older builds): no section, no failure
    del j["seed"]
if "## Sample-to-sample scatter" in study_report(work, jobs):
    fails.append("a study.json without seeds has a sample-scatter section")
if fails:
    sys.exit("\n".join(fails))
print(f"seed_check ok (group B needs {nb} seeds)")
