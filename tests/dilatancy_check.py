#!/usr/bin/env python3
"""Known-answer test of scripts/dilatancy.py and the study report's stress-dilatancy section.

1. The rate on eps_v = a cubic in eps_a, rows evenly spaced: a line through a symmetric window has the slope
   f' + f'''/6 sum(t^4)/sum(t^2) (checked to 1e-12); the series' ends, where a window is not whole, have none;
   sparse rows widen the window.
2. sin psi = -d / (2 - d): 0 at constant volume, asin(0.2) at d = -0.5.
3. A synthetic drained compression that obeys Rowe exactly, sigma_1/sigma_3 = K (1 - d) with K = 2 (phi_f =
   asin(1/3) = 19.47 deg), on a dilatancy d(eps) = 0.3 exp(-eps/0.1) - 0.6 (eps/0.1)^3 exp(3 (1 - eps/0.1))
   (contracting to 3.75 %, dilating most near 10 %, at critical state by 35-40 %), its stress ratio 0.7 of Rowe's
   until its largest contraction (the fit starts there):
   - (-d)_max within 1 % and its strain within a row spacing and a half (the window's cubic term: 0.4 %);
   - K within 0.25 % (from the start it would be 0.5 % low), phi_f within 0.1 deg;
   - in the report: its row, the critical state's phi'_cs = asin(1/3) (q/p' = 0.75: Rowe at d = 0), Bolton's ratio
     (phi'_max - phi'_cs) / (-d)_max as computed from the row's own numbers; the note's range of phi_f - phi'_cs as
     the rows give it;
   - zig-zag noise on eps_v larger than the dilation: psi_max '-' (not significant).
   An undrained and an extension test are not in the section; without eps_v (an older series) a test is left out.
4. Triaxial extension (eps_a falls, q < 0; the two lateral strain increments the major ones): sin psi = -d / (2 + d)
   (asin(1/3) at d = -0.5); sigma_1/sigma_3 = (3 + eta) / (3 - 2 eta) at eta = |q|/p' (the stresses' own ratio);
   a synthetic drained extension that obeys Rowe's extension law exactly, sigma_1/sigma_3 = K / (1 + d) (Rowe, Barden
   & Lee 1964) with K = 2, on the same d along -eps_a: (-d)_max, its axial strain (< 0), K and phi_f as in 3, while
   read as a compression (d along eps_a, Rowe's compression law) its K is off by more than 10 %; in the report the
   section "Stress and dilatancy (drained extension)" holds it alone, with phi'_cs = asin(1/3) (Mohr-Coulomb in
   extension at q/p' = 0.6: Rowe at d = 0) and phi'_max by 3 M / (6 - M).
"""
import csv
import json
import math
import os
import shutil
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import dilatancy as D  # noqa: E402
from synthetic_study import SHEAR_COLUMNS, study_report  # noqa: E402

fails = []


def check(what, got, want, tol):
    if not abs(got - want) <= tol:
        fails.append(f"{what}: {got!r}, expected {want!r} within {tol}")


# 1. the rate of a cubic
x = np.arange(0, 0.2001, 0.003)  # no row on a window's edge (h = 0.01), where round-off would pick a side
y = 0.3 * x - 2 * x ** 2 + 5 * x ** 3
d, se = D.rate(x, y)
h = D.WINDOW / 2
inner = (x - h >= x[0] - 1e-12) & (x + h <= x[-1] + 1e-12)
# a least-squares line through points symmetric about x0: the slope is f'(x0) + f'''/6 * sum(t^4)/sum(t^2)
t = x[(np.abs(x - x[20]) <= h + 1e-12)] - x[20]
want = 0.3 - 4 * x + 15 * x ** 2 + 30 / 6 * float((t ** 4).sum() / (t ** 2).sum())
ok = np.isfinite(d)
if not np.array_equal(ok, inner) or np.abs(d[ok] - want[ok]).max() > 1e-12:
    fails.append(f"rate of a cubic: {np.abs(d[ok] - want[ok]).max() if ok.any() else 'none'} off, rows {ok.sum()}")
# sparse rows (0.01 apart): the window widens to MIN_ROWS spacings, so a rate is found
xs = np.arange(0, 0.2001, 0.01)
if not np.isfinite(D.rate(xs, 0.1 * xs)[0]).any():
    fails.append("rows sparser than the window: no rate")

# 2. the dilation angle
check("psi at d = 0", float(D.dilation_angle(np.array(0.0))), 0.0, 1e-12)
check("psi at d = -0.5", float(D.dilation_angle(np.array(-0.5))), math.degrees(math.asin(0.2)), 1e-12)

# 3. a synthetic test on Rowe's line
K = 2.0


def dilatancy_of(e):
    return 0.3 * np.exp(-e / 0.1) - 0.6 * (e / 0.1) ** 3 * np.exp(3 * (1 - e / 0.1))


fine = np.linspace(0, 0.4, 400001)  # eps_v by the trapezoid rule on a grid 1e-6 apart: exact to ~1e-9
ev_fine = np.concatenate([[0], np.cumsum(0.5 * (dilatancy_of(fine[1:]) + dilatancy_of(fine[:-1])) * np.diff(fine))])
eps = np.round(np.arange(0, 0.4001, 0.0025), 10)
ev = ev_fine[np.round(eps / 1e-6).astype(int)]
dil = dilatancy_of(eps)
R = K * (1 - dil)
eta = 3 * (R - 1) / (R + 2)
eta[:int(np.argmax(ev))] *= 0.7  # off Rowe's line while it contracts (an elastic start is): the fit starts after
res = D.analyse(eps, ev, eta)
true_max, true_at = float(-dilatancy_of(fine).min()), float(fine[np.argmin(dilatancy_of(fine))])
# the window's cubic term on this curve: 0.4 % of (-d)_max; its strain within a row and a half
check("(-d)_max", res["neg_d_max"], true_max, 0.01 * true_max)
check("its strain", res["eps_max"], true_at, 1.5 * 0.0025)
# K through 1 - d (the fitted d is within 0.1 % of 1 - d here): 0.25 %; fitted from the start (the contracting rows
# off the line) it would be 0.5 % low
check("K", res["K"], K, 0.0025 * K)
phi_f = math.degrees(math.asin(1 / 3))
check("phi_f", res["phi_f"], phi_f, 0.1)
if not res["psi_max"] == res["psi_max"]:
    fails.append("a clear dilation not significant")
noisy = D.analyse(eps, -0.001 * eps + 0.002 * (-1) ** np.arange(len(eps)), eta)
if noisy["psi_max"] == noisy["psi_max"]:
    fails.append(f"zig-zag noise above the dilation read as significant: {noisy}")

# 4. extension: the dilation angle and principal stress ratio from the strain and stress components themselves
# d = -0.5 along -eps_a: d eps_3 = d eps_a = -1, d eps_v = -0.5, so d eps_1 = d eps_2 = (d eps_v - d eps_3) / 2 = 0.25
de1, de3 = 0.25, -1.0
check("extension psi at d = -0.5", float(D.dilation_angle(np.array(-0.5), extension=True)),
      math.degrees(math.asin(-(2 * de1 + de3) / (2 * de1 - de3))), 1e-12)
p_, q_ = 1e5, -0.75e5  # sigma_a = p + 2q/3 (minor), sigma_r = p - q/3 (major)
check("extension sigma_1/sigma_3", float(D.principal_ratio(np.array(abs(q_) / p_), extension=True)),
      (p_ - q_ / 3) / (p_ + 2 * q_ / 3), 1e-12)
R_e = K / (1 + dil)  # Rowe in extension on the same d along the loading
eta_e = 3 * (R_e - 1) / (1 + 2 * R_e)
eta_e[:int(np.argmax(ev))] *= 0.7
res_e = D.analyse(-eps, ev, eta_e, extension=True)
check("extension (-d)_max", res_e["neg_d_max"], true_max, 0.01 * true_max)
check("extension: its axial strain", res_e["eps_max"], -true_at, 1.5 * 0.0025)
check("extension K", res_e["K"], K, 0.0025 * K)
check("extension phi_f", res_e["phi_f"], phi_f, 0.1)
as_comp = D.analyse(eps, ev, eta_e)  # the compression law on the extension's series: it must not fit
if abs(as_comp["K"] - K) < 0.1 * K:
    fails.append(f"the extension read with the compression law still gives K {as_comp['K']:.4f}: the test cannot "
                 "tell them apart")

# the report's section
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/dilatancy_check"
shutil.rmtree(work, ignore_errors=True)
cols = SHEAR_COLUMNS
jobs = []


def test(name, drainage="drained", sign=1, with_ev=True, ev_rows=ev, eta_rows=eta):
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0, "axial_strain_rate": 1}]}, f)
    use = [c for c in cols if with_ev or c != "eps_v"]
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + use)
        for i, (ea, v, qp) in enumerate(zip(eps, ev_rows, eta_rows)):
            p = 1e5
            e = 0.65 - 1.65 * v  # e follows the volume: steady once it is
            row = dict(time=i, step=i, eps_a=sign * ea, eps_v=v, p=p, q=sign * qp * p, q_p=qp, e=e, mu=0.5, mu_r=0.1,
                       stage_type=2 if drainage == "drained" else 1, a_c=0.1, a_d=0.05, a_n=0.1, a_t=0.02,
                       sff_share_c=0.25, sff_share_d=0.25, sff_share_n=0.25, sff_share_t=0.25, sff=qp,
                       inertial_number=1e-4, sigma_x=p - qp * p / 3, sigma_y=p - qp * p / 3, sigma_z=p + 2 * qp * p / 3)
            w.writerow(["shear"] + [row[c] for c in use])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_x", "mu_r": 0.1, "e0": 0, "p0": 0,
                 "drainage": drainage, "direction": "compression" if sign > 0 else "extension", "b": 0, "seed": 1,
                 "count": 300, "csr": 0, "cycles": 0, "strain_amplitude": 0, "axial_strain_rate": 0, "rate_group": ""})


test("rowe")
test("noisy", ev_rows=-0.001 * eps + 0.002 * (-1) ** np.arange(len(eps)))
test("undrained", drainage="undrained")
test("extension", sign=-1, eta_rows=eta_e)
test("old", with_ev=False)
text = study_report(work, jobs)
if "## Stress and dilatancy (drained compression)" not in text:
    sys.exit("dilatancy_check: no stress-dilatancy section in report.md")
sec = text.split("## Stress and dilatancy (drained compression)")[1].split("\n## ")[0]
names = [l.split(" | ")[0][2:] for l in sec.splitlines() if l.startswith("| ") and not l.startswith("| test")]
if names != ["rowe", "noisy"]:
    fails.append(f"the section's tests: {names}, expected rowe and noisy (drained compression with eps_v)")
row = next((l for l in sec.splitlines() if l.startswith("| rowe |")), "").split(" | ")
phi_cs = math.degrees(math.asin(3 * 0.75 / 6.75))
if len(row) == 10:
    phi_max, cs = float(row[2]), float(row[3])
    check("phi'_cs", cs, phi_cs, 0.05)
    check("phi'_max", phi_max, math.degrees(math.asin(3 * eta.max() / (6 + eta.max()))), 0.05)
    neg = float(row[4].split(" ± ")[0])
    check("report (-d)_max", neg, true_max, 0.01 * true_max)
    check("Bolton's ratio", float(row[6]), (phi_max - cs) / neg, 0.15)  # from the row's rounded numbers
    check("report K", float(row[7]), K, 0.0025 * K)
    check("report phi_f", float(row[8].split(" (")[0]), phi_f, 0.1)
    check("phi_mu", float(row[9].rstrip(" |")), math.degrees(math.atan(0.5)), 0.05)
else:
    fails.append(f"the rowe test's row: {row}")
noisy_row = next((l for l in sec.splitlines() if l.startswith("| noisy |")), "").split(" | ")
if len(noisy_row) < 6 or noisy_row[5] != "-":
    fails.append(f"the noisy test's psi_max must be '-': {noisy_row}")
# the note: the range of phi_f - phi'_cs over the tests at critical state, as the rows give them (0.1 deg rounding)
note = sec.split("phi_f - phi'_cs is ")[1].split("°")[0] if "phi_f - phi'_cs is " in sec else ""
lo, hi = (float(v) for v in note.split(" to ")) if " to " in note else (99, 99)
diffs = [float(r.split(" | ")[8].split(" (")[0]) - float(r.split(" | ")[3]) for r in sec.splitlines()
         if r.startswith("| rowe |") or r.startswith("| noisy |")]
if not diffs or abs(lo - min(diffs)) > 0.11 or abs(hi - max(diffs)) > 0.11:
    fails.append(f"phi_f - phi'_cs note: {note!r}, the rows give {diffs}")
# the extension's own section: the extension alone, its angles by Mohr-Coulomb in extension, Rowe's extension law
head_e = "## Stress and dilatancy (drained extension)"
sec_e = text.split(head_e)[1].split("\n## ")[0] if head_e in text else ""
names_e = [l.split(" | ")[0][2:] for l in sec_e.splitlines() if l.startswith("| ") and not l.startswith("| test")]
if names_e != ["extension"]:
    fails.append(f"the extension section's tests: {names_e}, expected the extension alone")
row = next((l for l in sec_e.splitlines() if l.startswith("| extension |")), "").split(" | ")
if len(row) == 10:
    check("extension phi'_cs", float(row[3]), math.degrees(math.asin(3 * 0.6 / 5.4)), 0.05)
    check("extension phi'_max", float(row[2]), math.degrees(math.asin(3 * eta_e.max() / (6 - eta_e.max()))), 0.05)
    neg, at = row[4].split(" ± ")[0], row[4].split("(")[1].rstrip(")")
    check("report extension (-d)_max", float(neg), true_max, 0.01 * true_max)
    check("report extension eps_a at it [%]", float(at), -100 * true_at, 100 * 1.5 * 0.0025)
    check("report extension psi_max", float(row[5]), float(D.dilation_angle(np.array(-true_max), True)), 0.3)
    check("report extension K", float(row[7]), K, 0.0025 * K)
    check("report extension phi_f", float(row[8].split(" (")[0]), phi_f, 0.1)
else:
    fails.append(f"the extension test's row: {row}")
if fails:
    sys.exit("dilatancy_check: " + "; ".join(fails))
print(f"dilatancy_check: ok ((-d)_max {res['neg_d_max']:.4f} of {true_max:.4f} at {res['eps_max']:.4f}, "
      f"K {res['K']:.4f}, phi_f {res['phi_f']:.2f} of {phi_f:.2f}; extension K {res_e['K']:.4f}, read as a compression "
      f"{as_comp['K']:.4f}; the report's two sections)")
