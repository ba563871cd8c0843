#!/usr/bin/env python3
"""Known-answer test of the study report's rate-dependence section (scripts/grainlab_plot.py rate_section).

A synthetic study of drained compressions whose stress ratio and void ratio lie exactly on lines in the inertial
number I (the low-I form of the mu(I) rheology): at its peak (10 % strain) q/p' = 0.75 + 50 I, at critical state
(steady from 30 %) q/p' = 0.60 + 25 I and e = 0.70 + 10 I, with I = 4e-4 x the axial strain rate.
- Series A, rates 0.5, 1, 2 /s: the report must give q/p' 0.750 and 0.600 and e_c 0.7000 at I -> 0, each ± 0.000 (an
  exact line, three tests), the Mohr-Coulomb angles of those (asin(3M / (6 + M)), worked out here), and the slowest
  test's excess over the limits: 50 x 2e-4 = +0.010 at the peak and 25 x 2e-4 = +0.005 at critical state.
- Series B, rates 1 and 3 /s on the same lines, its 3 /s test still compacting (e drifting), joined by the test named
  as the series at the base's rate (2 /s in its summary.json, no rate group: an extra job's rate beside the grid's):
  three peaks on the line (± 0.000), two critical states, which the line meets exactly (no ±).
- Undrained series E at 0.5, 1, 2 /s (q_0 = 30 kPa) on s_u / sigma'_v0 = 0.30 + 40 I at the q peak: each test's
  I and s_u / sigma'_v0, and 0.300 ± 0.000 at I -> 0 with the slowest's excess +0.008; drained studies have no such table.
  Series F, the same after a K0 loading at 0.5 /s to a larger q: each test's own rate and its shear stage's s_u, and
  the peak table's q_peak and max q/p' of the shear, not of the loading (its oedometric rows are the consolidation).
- The limit's form (three rates or more): each limit by a line in I and in sqrt(I) with its lack-of-fit p; series E
  (one test per rate) no p, an undrained series by its s_u alone, series D (two rates) no row; series G, two seeds at
  three rates on 0.30 + 40 I +- 0.01: p 1.000 for the line in I, the sqrt(I) line's limit and p worked out here.
- A test without a rate (rate_group ""): not in the section. Without any rate group there is no section.
- Series D at 10 and 30 /s reaches I = 1.2e-2, past the line's low-I range (1e-2): a note names it, and only it.
- The peak table gives each test's q_peak, and the walls' q less the damping's drag (2 % of q, NaN in the first two
  rows) at its peak, and its I at its largest stress ratio (I starts at twice its steady value and falls to it
  by the peak, so a wrong row shows) and counts the peaks above the quasi-static I = 1e-3.
- The critical-state lines are fitted per rate (summary.json's axial_strain_rate), named where there are several:
  the three critical states at 1 /s share one p'_c, so no line (a fit through them was singular and stopped the
  report).
Tolerances: the values are printed to 3-4 decimals and the lines are exact, so the strings must match.
"""
import csv
import json
import math
import os
import shutil
import sys

import numpy as np
import scipy.stats

from synthetic_study import study_report
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/rate_check"
shutil.rmtree(work, ignore_errors=True)
cols = ["time", "step", "eps_a", "p", "q", "q_p", "e", "mu_r", "stage_type", "a_c", "a_d", "a_n", "a_t", "sff_share_c",
        "sff_share_d", "sff_share_n", "sff_share_t", "sff", "inertial_number", "sigma_x", "sigma_y", "sigma_z", "p_drag",
        "q_drag"]
jobs = []


def test(name, group, rate, drifting=False, root=work, listed=jobs, drainage="drained", q0=0.0, peak=None, k0=False,
         seed=1):
    """peak: q/p' at the peak as a function of I (0.75 + 50 I by default); q0: the shear's start deviator (summary);
    k0: a K0 loading at 0.5 /s before the shear (stage "load", oedometric rows to q = 300 kPa), as a SHANSEP test's."""
    I = 4e-4 * rate
    run = os.path.join(root, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(root, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": ([{"name": "load", "type": "triaxial", "b": 0, "axial_strain_rate": 0.5,
                                "drainage": "oedometric", "p_0": 5e4, "q_0": 0}] if k0 else []) +
                              [{"name": "shear", "type": "triaxial", "b": 0, "axial_strain_rate": rate, "drainage": drainage,
                                "p_0": 1e5, "q_0": q0}]}, f)
    m_pk, m_cs, e_cs = (peak or (lambda i: 0.75 + 50 * i))(I), 0.60 + 25 * I, 0.70 + 10 * I
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i in range(5 if k0 else 0):  # the K0 loading: q up to 300 kPa at p' 200 kPa, I = 2e-4
            w.writerow(["load", i, i, 0.01 * i, 2e5, 7.5e4 * i, 0.375 * i, 0.7, 0.3, 5, 0.1, 0.05, 0.1, 0.02, 0.25, 0.25, 0.25,
                        0.25, 0.375 * i, 2e-4, 1e5, 1e5, 1e5 + 7.5e4 * i, 0.0, 0.0])
        for i in range(41):  # to 40 %: up to the peak at 10 %, down to the critical state at 30 %, steady after
            ea = 0.01 * i
            qp = m_pk * ea / 0.1 if ea <= 0.1 else m_pk + (m_cs - m_pk) * min(1.0, (ea - 0.1) / 0.2)
            e = e_cs - (0.2 * (ea - 0.3) if drifting and ea > 0.3 else 0.0)
            p = 1e5
            I_row = I * (2 - ea / 0.1) if ea < 0.1 else I  # a start-up transient: twice the steady I, gone by the peak
            # the damping's drag: 2 % of q, none on p; NaN in the first two rows (restored from a checkpoint of a build
            # before the columns)
            drag = ["nan", "nan"] if i < 2 else [0.0, 0.02 * qp * p]
            w.writerow(["shear", i, i, ea, p, qp * p, qp, e, 0.3, 2, 0.1, 0.05, 0.1, 0.02, 0.25, 0.25, 0.25, 0.25, qp, I_row,
                        p - qp * p / 3, p - qp * p / 3, p + 2 * qp * p / 3] + drag)
    listed.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_x", "mu_r": 0.3, "e0": 0, "p0": 0,
                 "drainage": drainage, "direction": "compression", "b": 0, "seed": seed, "count": 300, "csr": 0,
                 "cycles": 0, "strain_amplitude": 0, "axial_strain_rate": rate if group else 0, "rate_group": group})


for r in (2, 0.5, 1):  # out of order: the section sorts by rate
    test(f"shear_a_rate{r:g}", "shear_a", r)
test("shear_b_rate1", "shear_b", 1)
test("shear_b_rate3", "shear_b", 3, drifting=True)
test("shear_b", "", 2)
test("shear_c", "", 1)
test("shear_d_rate10", "shear_d", 10)  # I = 4e-3 and 1.2e-2: past the line's range, which the section names
test("shear_d_rate30", "shear_d", 30)


def phi(M):
    return math.degrees(math.asin(3 * M / (6 + M)))


fails = []
text = study_report(work, jobs)
if "## Rate dependence" not in text:
    sys.exit("no rate-dependence section in report.md")
sec = text.split("## Rate dependence")[1]
want = {
    "| shear_a | 3 |": f"| shear_a | 3 | 0.750 ± 0.000 ({phi(0.75):.1f}°) | +0.010 (I = 2.0e-04) | 0.600 ± 0.000 "
                      f"({phi(0.6):.1f}°) | 0.7000 ± 0.0000 | +0.005 (I = 2.0e-04) |",
    "| shear_b | 3 |": f"| shear_b | 3 | 0.750 ± 0.000 ({phi(0.75):.1f}°) | +0.020 (I = 4.0e-04) | 0.600 "
                      f"({phi(0.6):.1f}°) | 0.7000 | +0.010 (I = 4.0e-04) |",
}
for start, line in want.items():
    got = next((l for l in sec.splitlines() if l.startswith(start)), "")
    if got != line:
        fails.append(f"expected\n  {line}\ngot\n  {got}")
# the per-test rows, slowest first: I at the peak and at critical state, M and e of each
rows = [l for l in sec.splitlines() if l.startswith("| shear_a_rate")]
if [l.split(" | ")[0] for l in rows] != ["| shear_a_rate0.5", "| shear_a_rate1", "| shear_a_rate2"]:
    fails.append(f"series A's rows not sorted by rate: {rows}")
if rows and rows[0] != (f"| shear_a_rate0.5 | 0.5 | 2.0e-04 | 0.760 ({phi(0.76):.1f}°) | 2.0e-04 | 0.605 "
                        f"({phi(0.605):.1f}°) | 0.7020 |"):
    fails.append(f"series A's slowest row: {rows[0] if rows else None}")
rows_b = [l.split(" | ")[0] for l in sec.split("| rate series |")[0].splitlines() if l.startswith("| shear_b")]
if rows_b != ["| shear_b_rate1", "| shear_b", "| shear_b_rate3"]:
    fails.append(f"series B's rows (the base-rate test at 2 /s between 1 and 3): {rows_b}")
if "Past I = 0.01 the stress ratio bends below the line" not in sec or "shear_d (I up to 1.2e-02)" not in sec \
        or "shear_a (" in sec or "shear_b (" in sec:
    fails.append("the note on series past I = 0.01 must name shear_d, and only it")
b3 = next((l for l in sec.splitlines() if l.startswith("| shear_b_rate3 |")), "")
if "| not at critical state | - |" not in b3:
    fails.append(f"the drifting test must be named as not at critical state: {b3}")
if "shear_c" in sec.split("## ")[0]:
    fails.append("a test without a rate is in the rate section")
csl_rows = [l for l in text.split("## Critical-state lines")[1].split("## ")[0].splitlines() if l.startswith("| 0.3 |")]
if csl_rows != ["| 0.3 | compression, 0.5/s | 1 | fewer than 3 critical states 10 % apart in p'_c: no fit | | | | | "
                f"0.605 ({phi(0.605):.1f}°) | 2.0e-04 | 0.605, 0.593, - |",
                "| 0.3 | compression, 1/s | 3 | fewer than 3 critical states 10 % apart in p'_c: no fit | | | | | "
                f"0.610 ± 0.000 ({phi(0.61):.1f}°) | 4.0e-04 | 0.610, 0.598, - |",
                "| 0.3 | compression, 2/s | 2 | fewer than 3 critical states 10 % apart in p'_c: no fit | | | | | "
                f"0.620 ± 0.000 ({phi(0.62):.1f}°) | 8.0e-04 | 0.620, 0.608, - |",
                "| 0.3 | compression, 10/s | 1 | fewer than 3 critical states 10 % apart in p'_c: no fit | | | | | "
                f"0.700 ({phi(0.7):.1f}°) | 4.0e-03 | 0.700, 0.686, - |",
                "| 0.3 | compression, 30/s | 1 | fewer than 3 critical states 10 % apart in p'_c: no fit | | | | | "
                f"0.900 ({phi(0.9):.1f}°) | 1.2e-02 | 0.900, 0.882, - |"]:
    fails.append("critical-state lines not one per rate: " + "\n".join(csl_rows))
# The peak table gives the I at each test's largest stress ratio (the steady I, not the start-up's twice that), and a
# note counts those above the quasi-static 1e-3: shear_b_rate3 (1.2e-3), shear_d_rate10 and _rate30, of 9.
pk_sec = text.split("## Peak states")[1].split("## ")[0]
for name, rate in (("shear_a_rate0.5", 0.5), ("shear_b", 2), ("shear_c", 1), ("shear_d_rate30", 30)):
    row = next((l for l in pk_sec.splitlines() if l.startswith(f"| {name} |")), "")
    m = 0.75 + 50 * 4e-4 * rate
    if not row.endswith(f"| {m:.3f} ({phi(m):.1f}°) | {4e-4 * rate:.1e} | {phi(m):.1f}° at 10.0 % |"):
        fails.append(f"peak table, {name}: expected max q/p' {m:.3f} at I {4e-4 * rate:.1e}, got '{row}'")
    # q_peak and q_peak less drag (the walls' q less 2 % of it, past two NaN rows): at 10 %, p' = 100 kPa
    if f" | {100 * m:.1f} | {98 * m:.1f} | 10.00 | " not in row:
        fails.append(f"peak table, {name}: expected q_peak {100 * m:.1f} and less drag {98 * m:.1f} kPa, got '{row}'")
if "3 of 9 largest stress ratios were reached at an inertial number above the quasi-static limit I < 0.001 " \
        "(up to 1.2e-02)" not in pk_sec:
    fails.append(f"the peak table's note must count 3 of 9 peaks above I = 1e-3: {pk_sec}")
if not os.path.isfile(os.path.join(work, "figures", "rate.png")):
    fails.append("figures/rate.png missing")
if "Undrained strength" in sec:
    fails.append("an undrained-strength table in a study of drained tests")
# Undrained series E at 0.5, 1, 2 /s, consolidated anisotropically (q_0 = 30 kPa: sigma'_v0 = 100 + 2/3 30 = 120 kPa),
# its q peak (at 10 %, where I has settled to its steady value) on s_u / sigma'_v0 = 0.30 + 40 I exactly: the table
# gives each test's I at q_peak and s_u / sigma'_v0, the series 0.300 ± 0.000 at I -> 0 and the slowest test's excess
# 40 x 2e-4 = +0.008 at I = 2e-4. (A sigma'_v0 without the 2 q_0 / 3, or p'_0 alone, gives other values.)
undrained = []
shutil.rmtree(work + "_undrained", ignore_errors=True)
for r in (1, 0.5, 2):
    test(f"shear_e_rate{r:g}", "shear_e", r, root=work + "_undrained", listed=undrained, drainage="undrained", q0=3e4,
         peak=lambda i: 2 * 1.2 * (0.30 + 40 * i))  # above the critical state's q/p' 0.6
usec = study_report(work + "_undrained", undrained).split("## Rate dependence")[-1]
got = [l for l in usec.split("Undrained strength")[-1].split("The limit's form")[0].split("\n## ")[0].splitlines()
       if l.startswith("| shear_e")]
want_u = [f"| shear_e_rate{r:g} | {r:g} | {4e-4 * r:.1e} | {0.30 + 40 * 4e-4 * r:.3f} |" for r in (0.5, 1, 2)] + \
    ["| shear_e | 3 | 0.300 ± 0.000 | +0.008 (I = 2.0e-04) |"]
if "Undrained strength" not in usec or got != want_u:
    fails.append("the undrained strength against I:\n" + "\n".join(got) + "\nwanted:\n" + "\n".join(want_u))
# Series F: the same shears at 0.125, 0.25, 0.5 /s after a K0 loading at 0.5 /s whose q (300 kPa) exceeds their peaks:
# the rate is the shear's (not the loading's 0.5 for all), s_u the shear stage's (not the loading's q), and 0.300 at
# I -> 0 with the slowest's excess 40 x 5e-5 = +0.002.
k0_tests = []
shutil.rmtree(work + "_k0", ignore_errors=True)
for r in (0.5, 0.125, 0.25):
    test(f"shear_f_rate{r:g}", "shear_f", r, root=work + "_k0", listed=k0_tests, drainage="undrained", q0=3e4,
         peak=lambda i: 2 * 1.2 * (0.30 + 40 * i), k0=True)
ksec = study_report(work + "_k0", k0_tests).split("## Rate dependence")[-1]
got = [l for l in ksec.split("Undrained strength")[-1].split("The limit's form")[0].split("\n## ")[0].splitlines()
       if l.startswith("| shear_f")]
want_k = [f"| shear_f_rate{r:g} | {r:g} | {4e-4 * r:.1e} | {0.30 + 40 * 4e-4 * r:.3f} |" for r in (0.125, 0.25, 0.5)] + \
    ["| shear_f | 3 | 0.300 ± 0.000 | +0.002 (I = 5.0e-05) |"]
if got != want_k:
    fails.append("after a K0 loading, the undrained strength against I:\n" + "\n".join(got) + "\nwanted:\n" +
                 "\n".join(want_k))
# ... and the peak table's q_peak and max q/p' are the shear's, not the K0 loading's (q 300 kPa, q/p' 1.5)
kpk = study_report(work + "_k0", k0_tests).split("## Peak states")[1].split("\n## ")[0]
for r in (0.125, 0.25, 0.5):
    m = 2.4 * (0.30 + 40 * 4e-4 * r)
    row = next((l for l in kpk.splitlines() if l.startswith(f"| shear_f_rate{r:g} |")), "")
    if not row.startswith(f"| shear_f_rate{r:g} | 0.3 | undrained | compression | {100 * m:.1f} |") or \
            f"| {m:.3f} ({phi(m):.1f}°) |" not in row:
        fails.append(f"peak table after a K0 loading, shear_f_rate{r:g}: expected q_peak {100 * m:.1f} kPa and max q/p' "
                     f"{m:.3f}, got '{row}'")
# The limit's form. Series E (three rates, one test each) exactly on a line in I: that line's limit with no standard
# error, the line in sqrt(I) with the one its residuals give, no lack-of-fit p (no replicates), and no stress-ratio rows
# (an undrained test's are taken where it has collapsed); series A likewise for
# the drained measures; series D (two rates) no row. Series G: undrained at 0.5, 1, 2 /s over two seeds, s_u / sigma'_v0
# = 0.30 + 40 I + 0.01 (seed 1) or - 0.01 (seed 2): the rates' means on the line in I (lack-of-fit p 1.000), its limit
# 0.300 with the standard error of the seeds' scatter; the line in sqrt(I) misses the means, its limit and p worked out
# here from the lack-of-fit F test's definition (Draper & Smith 1998, sec. 2.1).
def line_limit(x, y):
    """Intercept and its standard error of the least-squares line (worked out from the normal equations)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n, sx, sxx = len(x), x.sum(), (x * x).sum()
    b = (n * (x * y).sum() - sx * y.sum()) / (n * sxx - sx * sx)
    a = (y.sum() - b * sx) / n
    s2 = ((y - a - b * x) ** 2).sum() / (n - 2)
    return a, math.sqrt(s2 * sxx / (n * sxx - sx * sx)), b


def lof_p(x, y, g):
    a, _, b = line_limit(x, y)
    keys = sorted(set(g))
    y, g = np.asarray(y), np.asarray(g)
    pe = sum(((y[g == k] - y[g == k].mean()) ** 2).sum() for k in keys)
    lof = sum((g == k).sum() * (y[g == k].mean() - (a + b * np.asarray(x)[g == k]).mean()) ** 2 for k in keys)
    return scipy.stats.f.sf((lof / (len(keys) - 2)) / (pe / (len(y) - len(keys))), len(keys) - 2, len(y) - len(keys))


form_sec = sec.split("The limit's form")[-1].split("\n## ")[0] if "The limit's form" in sec else ""
I_e = [4e-4 * r for r in (0.5, 1, 2)]
a_s, se_s, _ = line_limit(np.sqrt(I_e), [0.30 + 40 * i for i in I_e])
if "| shear_a | max q/p' | 3 (3) | 0.750 ± 0.000 | - |" not in form_sec or "| shear_d |" in form_sec:
    fails.append("the limit's form, drained: series A's exact line and no row of series D (two rates):\n" + form_sec)
form_u = usec.split("The limit's form")[-1].split("\n## ")[0] if "The limit's form" in usec else ""
want_e = f"| shear_e | s_u / sigma'_v0 | 3 (3) | 0.300 ± 0.000 | - | {a_s:.3f} ± {se_s:.3f} | - |"
if want_e not in form_u.splitlines() or "| shear_e | max q/p' |" in form_u:
    fails.append(f"the limit's form of series E: expected\n  {want_e}\ngot\n{form_u}")
shutil.rmtree(work + "_seeds", ignore_errors=True)
seeded = []
for s, d in ((1, 0.01), (2, -0.01)):
    for r in (0.5, 1, 2):
        test(f"shear_g_s{s}_n300_rate{r:g}", f"shear_g_s{s}_n300", r, root=work + "_seeds", listed=seeded,
             drainage="undrained", q0=3e4, peak=lambda i, d=d: 2.4 * (0.30 + 40 * i + d), seed=s)
gsec = study_report(work + "_seeds", seeded).split("## Rate dependence")[-1]
form_g = gsec.split("The limit's form")[-1].split("\n## ")[0] if "The limit's form" in gsec else ""
I_g = [4e-4 * r for _ in (1, 2) for r in (0.5, 1, 2)]
y_g = [0.30 + 40 * i + d for d in (0.01, -0.01) for i in I_g[:3]]
rates_g = [r for _ in (1, 2) for r in (0.5, 1, 2)]
a_i, se_i, _ = line_limit(I_g, y_g)
a_q, se_q, _ = line_limit(np.sqrt(I_g), y_g)
want_g = (f"| shear_g_s*_n300 | s_u / sigma'_v0 | 3 (6) | {a_i:.3f} ± {se_i:.3f} | 1.000 | {a_q:.3f} ± {se_q:.3f} | "
          f"{lof_p(np.sqrt(I_g), y_g, rates_g):.3f} |")
if abs(a_i - 0.30) > 1e-9 or want_g not in form_g.splitlines():
    fails.append(f"the limit's form over two seeds: expected\n  {want_g}\ngot\n{form_g}")
for j in jobs:
    j["rate_group"] = ""
if "## Rate dependence" in study_report(work, jobs):
    fails.append("a study without a rate axis has a rate-dependence section")
if fails:
    sys.exit("\n".join(fails))
print("rate_check ok")
