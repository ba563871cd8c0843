#!/usr/bin/env python3
"""Known-answer test of the study report's failure-criteria section (scripts/grainlab_plot.py, true triaxial).

1. failure_criteria(phi_tc, b): at b = 0 both criteria give phi_tc back; the angle each returns at b reproduces its
   invariant ratio (Matsuoka-Nakai I1 I2 / I3, Lade-Duncan I1^3 / I3) of the b = 0 state; Matsuoka-Nakai is phi_tc
   again at b = 1 (its ratio is symmetric in the principal stresses) and above it in between; Lade-Duncan lies above
   Matsuoka-Nakai for 0 < b <= 1.
2. A synthetic study of three drained compression tests of one sample, b = 0, 0.5, 1, whose final wall stresses lie
   exactly on Matsuoka-Nakai's surface through the b = 0 state (sigma_3 = 100 kPa, phi_tc = 30 deg; the b = 0.5 state
   solved as a polynomial's root by numpy, not by the bisection under test): the report must give Matsuoka-Nakai a
   misfit of 0.00 deg at the peak and at the critical state, Mohr-Coulomb and Lade-Duncan the misfits worked out here
   from those roots, the servo error of summary.json (or '-' without it), and the figure.
3. How the peaks are taken (study.json peak block): a dynamic row (kinetic / elastic energy 0.1) whose angle
   overshoots every other is the peak of single rows (no block: an older build's study.json; or the block at its
   defaults); peak.max_ke_ratio leaves it out and the last column names it; peak.window averages each row's angle
   over its neighbours within the window first (checked against a plain loop).
4. A drained triaxial extension of the same sample (eps_a < 0, the lateral walls at sigma_3 = 100 kPa the major pair,
   the axis unloaded to sigma_1 / sigma_3 = 2.8 of them: 27.8 deg) joins the series as the Lode angle of b = 1: its row
   '1 (extension)', measured b 1.00, Mohr-Coulomb and Matsuoka-Nakai 30.0, Lade-Duncan its b = 1 root; the misfits
   count it (five tests) and the heading says "true triaxial and extension". Its critical state is the window along
   -eps_a (along eps_a the window would hold the whole shear: 16.1 deg at b 0.98).
5. A plane-strain test of the same sample (summary.json stress_path: plane_strain; its stage's b 0) whose x walls'
   stress develops b = 0.3 on Matsuoka-Nakai's surface joins the constant-sigma_3 series (not a path of its own, which
   would have no b = 0 test): its row '0.3 (plane strain)', measured b 0.30, MN exact, the misfits over six tests, the
   heading "true triaxial, plane strain and extension", the peak table's direction "compression, plane strain (b 0.3)".
6. A plane-strain extension of the same sample (stress_path: plane_strain, eps_a < 0: the y walls at 100 kPa become
   sigma_1 as the axis unloads, sigma_x develops b = 0.6 on Matsuoka-Nakai's surface) joins the series at its measured
   b, not as a triaxial extension's b = 1: its row '0.6 (plane strain extension)', measured b 0.60, MN exact, Lade-
   Duncan its b = 0.6 root, the misfits over seven tests, the peak table's direction "extension, plane strain (b 0.6)".
"""
import csv
import json
import math
import os
import shutil
import sys

import numpy as np
from numpy.polynomial import Polynomial as P

here = os.path.dirname(os.path.abspath(__file__))
script = os.path.join(here, "..", "scripts", "grainlab_plot.py")
sys.path.insert(0, os.path.dirname(script))
from grainlab_plot import failure_criteria  # noqa: E402
from synthetic_study import study_report  # noqa: E402

fails = []


def check(what, got, want, tol):
    if not abs(got - want) <= tol:
        fails.append(f"{what}: {got:.12g}, expected {want:.12g} (tolerance {tol:g})")


def ratios(s1, s2, s3):
    i1, i2, i3 = s1 + s2 + s3, s1 * s2 + s2 * s3 + s3 * s1, s1 * s2 * s3
    return i1 * i2 / i3, i1 ** 3 / i3


def state(phi, b):
    """sigma_1, sigma_2, sigma_3 of a Mohr-Coulomb angle phi [deg] at b, sigma_3 = 1."""
    N = (1 + math.sin(math.radians(phi))) / (1 - math.sin(math.radians(phi)))
    return N, 1 + b * (N - 1), 1.0


# 1. The criteria. Tolerances: the bisection stops at double precision on ln N (1e-15 relative); through asin the
# angle is good to ~1e-12 deg, and the invariant ratios of the returned state to ~1e-12 relative.
for phi_tc in (15.0, 30.0, 45.0):
    mn0, ld0 = failure_criteria(phi_tc, 0.0)
    check(f"MN({phi_tc}, b=0)", mn0, phi_tc, 1e-9)
    check(f"LD({phi_tc}, b=0)", ld0, phi_tc, 1e-9)
    check(f"MN({phi_tc}, b=1)", failure_criteria(phi_tc, 1.0)[0], phi_tc, 1e-9)
    ref = ratios(*state(phi_tc, 0.0))
    for b in (0.1, 0.3, 0.5, 0.8, 1.0):
        mn, ld = failure_criteria(phi_tc, b)
        check(f"MN ratio at b={b}, phi_tc={phi_tc}", ratios(*state(mn, b))[0] / ref[0], 1.0, 1e-10)
        check(f"LD ratio at b={b}, phi_tc={phi_tc}", ratios(*state(ld, b))[1] / ref[1], 1.0, 1e-10)
        if b < 1 and not mn > phi_tc + 0.1:
            fails.append(f"MN({phi_tc}, b={b}) = {mn:.3f} must exceed phi_tc (the criterion's known rise)")
        if not ld > mn:
            fails.append(f"LD({phi_tc}, b={b}) = {ld:.3f} must exceed MN = {mn:.3f}")

# 2. The report. The b = 0.5 and b = 1 states on each criterion's surface through (3, 1, 1), the b = 0 state of
# phi = 30 deg: roots of I1 I2 - k I3 (resp. I1^3 - k I3) in N = sigma_1 / sigma_3, sigma_2 = 1 + b (N - 1).


def root(b, which, N0=3.0):
    N = P([0, 1])
    s2 = 1 + b * (N - 1)
    i1, i2, i3 = N + s2 + 1, N * s2 + s2 + N, N * s2
    k = ratios(N0, 1.0, 1.0)[which]
    poly = i1 * i2 - k * i3 if which == 0 else i1 ** 3 - k * i3
    r = [x.real for x in poly.roots() if abs(x.imag) < 1e-9 and x.real > 1 + 1e-9]
    assert len(r) == 1, (b, which, poly.roots())
    return r[0]


def angle(N):
    return math.degrees(math.asin((N - 1) / (N + 1)))


N_mn = {b: (3.0 if b == 0 else root(b, 0)) for b in (0.0, 0.5, 1.0)}
phi = {b: angle(N) for b, N in N_mn.items()}
phi_ld = {b: angle(root(b, 1)) for b in (0.5, 1.0, 0.3, 0.6)}
B_PS, B_PSE = 0.3, 0.6
phi_ps, phi_pse = angle(root(B_PS, 0)), angle(root(B_PSE, 0))
check("MN at b = 1 (by roots)", phi[1.0], 30.0, 1e-9)
# A second series of the same sample on the constant-p' path (summary.json stress_path: constant_p), on MN's surface
# through sigma_1 / sigma_3 = 3.5 at b = 0 (33.7 deg): calibrated on its own b = 0 test, MN fits it exactly too; a
# report that pooled the two paths would calibrate both on one b = 0 test and give MN a misfit.
N_cp = {b: (3.5 if b == 0 else root(b, 0, 3.5)) for b in (0.0, 0.5, 1.0)}
phi_cp = {b: angle(N) for b, N in N_cp.items()}
phi_ld_cp = {b: angle(root(b, 1, 3.5)) for b in (0.5, 1.0)}

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/failure_criteria_check"
shutil.rmtree(work, ignore_errors=True)
cols = ["time", "step", "eps_a", "p", "q", "q_p", "e", "mu_r", "stage_type", "sigma_x", "sigma_y", "sigma_z", "a_c",
        "a_d", "a_n", "a_t", "sff_share_c", "sff_share_d", "sff_share_n", "sff_share_t", "sff", "ke_ratio",
        "ke_fluct_ratio"]
# A dynamic event in the constant-sigma_3 b = 0.5 test: at 28 % strain one row whose deviator overshoots 1.5 times the
# final one (b unchanged) with kinetic / elastic energy about the affine motion (ke_fluct_ratio) 0.1, every other row
# 0.005; the whole kinetic / elastic energy (ke_ratio, the walls' deformation in it) 0.5 on every row, so a filter on
# it would leave no peak. Single rows and every row (the
# study.json of an older build, without a peak block): the spike is the peak. With peak.max_ke_ratio 0.02 the peak
# leaves it out, and the last column names it. With peak.window 0.05 the angles are averaged over the rows within
# 2.5 % of strain (5 rows at this 1 % spacing, no row on the window's edge) before the largest is taken: worked out
# here by a plain loop over the rows, not by the cumulative sums under test.
KE_MAX, SPIKE_ROW, SPIKE_KE, SPIKE, WINDOW = 0.02, 28, 0.1, 1.5, 0.05
s1_sp, s3_sp = 1 + SPIKE * (N_mn[0.5] - 1), 1.0
phi_spike = math.degrees(math.asin((s1_sp - s3_sp) / (s1_sp + s3_sp)))
b05_angles = []  # the b = 0.5 (constant sigma_3) test's angle of every row, for the window's oracle
jobs = []
for path, b, N in [("", b, N) for b, N in N_mn.items()] + [("constant_p", b, N) for b, N in N_cp.items()]:
    name = "shear_drained_mur0.3_ebase_pbase_s1_n300" + (f"_b{b:g}" if b > 0 else "") + ("_cp" if path else "")
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        shear = {"name": "shear", "type": "triaxial", "b": b}
        if path:
            shear["stress_path"] = path  # the constant-sigma_3 series has none (an older build's summary)
        if b == 0.5 and not path:
            shear["servo_error"] = 0.034  # the table's last column, in %; a summary without it (older build): "-"
        json.dump({"stages": [{"name": "c", "type": "isotropic"}, shear]}, f)
    s1, s2 = 1e5 * N, 1e5 * (1 + b * (N - 1))
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i in range(41):  # to 40 % axial strain, steady from 30 %: the peak obliquity and the critical state agree
            ea = 0.01 * i
            ramp = min(1.0, ea / 0.3)
            sx, sy, sz = 1e5 + ramp * (s2 - 1e5), 1e5, 1e5 + ramp * (s1 - 1e5)
            ke = 0.005
            if b == 0.5 and not path and i == SPIKE_ROW:
                sx, sz, ke = 1e5 + SPIKE * (s2 - 1e5), 1e5 + SPIKE * (s1 - 1e5), SPIKE_KE
            p, q = (sx + sy + sz) / 3, sz - (sx + sy) / 2
            if b == 0.5 and not path:
                b05_angles.append(math.degrees(math.asin((sz - sy) / (sz + sy))))
            w.writerow(["shear", i, i, ea, p, q, q / p, 0.7, 0.3, 2, sx, sy, sz, 0.1, 0.05, 0.1, 0.02, 0.25, 0.25, 0.25,
                        0.25, q / p, 0.5, ke])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_mur0.3_ebase_pbase_s1_n300", "mu_r": 0.3,
                 "e0": 0, "p0": 0, "drainage": "drained", "direction": "compression", "b": b, "seed": 1, "count": 300,
                 "csr": 0, "cycles": 0, "strain_amplitude": 0})


def write_test(name, shear, rows, direction="compression"):
    """Writes jobs/<name> of the sample (done; summary.json: an isotropic stage, then a triaxial one with the keys
    `shear`; series.csv: per row (eps_a, sigma_x, sigma_y, sigma_z), q/p' = |q|/p') and appends its job."""
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "c", "type": "isotropic"}, {"name": "shear", "type": "triaxial", "b": 0,
                                                                   **shear}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i, (ea, sx, sy, sz) in enumerate(rows):
            p, q = (sx + sy + sz) / 3, sz - (sx + sy) / 2
            w.writerow(["shear", i, i, ea, p, q, abs(q) / p, 0.7, 0.3, 2, sx, sy, sz, 0.1, 0.05, 0.1, 0.02, 0.25, 0.25,
                        0.25, 0.25, abs(q) / p, 0.5, 0.005])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_mur0.3_ebase_pbase_s1_n300",
                 "mu_r": 0.3, "e0": 0, "p0": 0, "drainage": "drained", "direction": direction, "b": 0, "seed": 1,
                 "count": 300, "csr": 0, "cycles": 0, "strain_amplitude": 0,
                 **({"stress_path": shear["stress_path"]} if "stress_path" in shear else {})})


def ramp(i):
    return min(1.0, 0.01 * i / 0.3)


# 4. the extension: lateral walls held at 1e5 (the major pair), the axis unloaded to 1e5 / N_EXT
N_EXT = 2.8
phi_ext = angle(N_EXT)
EXT_NAME = "shear_drained_mur0.3_ebase_pbase_s1_n300_ext"
write_test(EXT_NAME, {"direction": "extension"},
           [(-0.01 * i, 1e5, 1e5, 1e5 - ramp(i) * (1e5 - 1e5 / N_EXT)) for i in range(41)], "extension")
# 5. the plane-strain test: sigma_3 = 1e5 on the y walls, sigma_x as b = 0.3 on MN's surface puts it
PS_NAME = "shear_drained_mur0.3_ebase_pbase_s1_n300_ps"
N_ps = root(B_PS, 0)
write_test(PS_NAME, {"stress_path": "plane_strain"},
           [(0.01 * i, 1e5 + B_PS * ramp(i) * (1e5 * N_ps - 1e5), 1e5, 1e5 + ramp(i) * (1e5 * N_ps - 1e5))
            for i in range(41)])
# 6. the plane-strain extension: sigma_1 = 1e5 on the y walls, the axis unloaded to sigma_3 = 1e5 / N on MN's surface
# at b = 0.6, sigma_x at that b between them on every row
PSE_NAME = "shear_drained_mur0.3_ebase_pbase_s1_n300_ps_ext"
N_pse = root(B_PSE, 0)
write_test(PSE_NAME, {"stress_path": "plane_strain", "direction": "extension"},
           [(-0.01 * i, sz + B_PSE * (1e5 - sz), 1e5, sz)
            for i, sz in ((i, 1e5 - ramp(i) * (1e5 - 1e5 / N_pse)) for i in range(41))], "extension")
HEAD = "## Failure criteria (true triaxial, plane strain and extension)"


def report_of(peak):
    """The report of the synthetic study with this peak block in its study.json (None: without the block)."""
    return study_report(work, jobs, **({"peak": peak} if peak is not None else {}))


def b05_rows(report):
    """The b = 0.5 (constant sigma_3) test's rows of the failure-criteria section and of the peak table."""
    name = "| shear_drained_mur0.3_ebase_pbase_s1_n300_b0.5 |"
    return (next((l for l in report.split(HEAD)[1].splitlines() if l.startswith(name)), ""),
            next((l for l in report.split("## Peak states")[1].splitlines() if l.startswith(name)), ""))


single = f"{phi_spike:.1f}° at {SPIKE_ROW:.1f} % (ke_fluct_ratio {SPIKE_KE:.3f})"  # the largest single row, named in every report
# Single rows, every row (an older build's study.json; the block at its defaults says the same): the spike is the peak.
for blk in (None, {"window": 0, "max_ke_ratio": 0}):
    old_report = report_of(blk)
    fc, pk = b05_rows(old_report)
    if not fc.startswith("| shear_drained_mur0.3_ebase_pbase_s1_n300_b0.5 | 0.3 | 0.5 | 0.50 | " + f"{phi_spike:.1f} |") \
            or not fc.endswith(f"| {single} |") or not pk.endswith(f"({phi_spike:.1f}°) | - | {single} |") \
            or "Peaks are the largest of single rows;" not in old_report:
        fails.append(f"peak block {blk}: the spike ({phi_spike:.1f} deg) must be the b = 0.5 peak, got '{fc}' and '{pk}'")
# The window: the largest 5-row mean of the angle, about the spike (above the steady 33.7 deg, below the spike's own).
e = [0.01 * i for i in range(41)]
means = [np.mean([a for a, ej in zip(b05_angles, e) if abs(ej - ei) < WINDOW / 2]) for ei in e]
phi_w = max(means)
win_report = report_of({"window": WINDOW, "max_ke_ratio": 0})
fc, pk = b05_rows(win_report)
if f"| 0.50 | {phi_w:.1f} | 30.0 |" not in fc or not pk.endswith(f"({phi_w:.1f}°) | - | {single} |") \
        or "averaged over 5 % of axial strain" not in win_report:
    fails.append(f"peak window {WINDOW}: expected phi'_max {phi_w:.3f} deg (the largest 5-row mean), got '{fc}' and '{pk}'")
print(f"b = 0.5 with the spike: single rows {phi_spike:.3f} deg, 5-row means {phi_w:.3f} deg, without it {phi[0.5]:.3f}")
report = report_of({"window": 0, "max_ke_ratio": KE_MAX})
if HEAD not in report:
    sys.exit(f"no '{HEAD}' in report.md")
if not os.path.isfile(os.path.join(work, "figures", "failure_criteria.png")):
    fails.append("figures/failure_criteria.png missing")
section = report.split(HEAD)[1]
line = next((l for l in section.splitlines() if l.startswith("| shear_drained_mur0.3_ebase_pbase_s1_n300_b0.5 |")), "")
# the row: measured b and angles, then the three predictions, at the peak and at the critical state
want = f"| 0.50 | {phi[0.5]:.1f} | 30.0 | {phi[0.5]:.1f} | {phi_ld[0.5]:.1f}"  # twice: the cells share a "|"
dyn = f"{single}; 1 row above ke_fluct_ratio {KE_MAX:g} left out"
if line.count(want) != 2 or not line.endswith(f"| 3.40 | {dyn} |"):
    fails.append(f"b = 0.5 row: expected twice '{want}', servo error 3.40 % and '{dyn}', got '{line}'")
peak = next((l for l in report.split("## Peak states")[1].splitlines()
             if l.startswith("| shear_drained_mur0.3_ebase_pbase_s1_n300_b0.5 |")), "")
if not peak.endswith(f"({phi[0.5]:.1f}°) | - | {dyn} |"):  # "-": these series have no inertial_number (older builds)
    fails.append(f"peak table, b = 0.5: expected phi'_max {phi[0.5]:.1f} deg and '{dyn}', got '{peak}'")
if "largest stress ratios were reached at an inertial number" in report:
    fails.append("a peak note on the inertial number where no series measured it")
if f"(ke_fluct_ratio; ke_ratio in runs of older builds) is at most {KE_MAX:g} (peak.max_ke_ratio)" not in report:
    fails.append("the report does not state the ke_fluct_ratio threshold")
cp = next((l for l in section.splitlines() if l.startswith("| shear_drained_mur0.3_ebase_pbase_s1_n300_b0.5_cp at constant p' |")), "")
want = f"| 0.50 | {phi_cp[0.5]:.1f} | {phi_cp[0.0]:.1f} | {phi_cp[0.5]:.1f} | {phi_ld_cp[0.5]:.1f}"
if cp.count(want) != 2:
    fails.append(f"constant-p' b = 0.5 row: expected twice '{want}' (its own b = 0 test's {phi_cp[0.0]:.1f} deg), got '{cp}'")
if "each path is calibrated on its own b = 0 test" not in section:
    fails.append("the section does not say that the constant-p' tests are calibrated apart")
line0 = next((l for l in section.splitlines() if l.startswith("| shear_drained_mur0.3_ebase_pbase_s1_n300 |")), "")
if "| - | " not in line0 or not line0.endswith("(ke_fluct_ratio 0.005) |"):
    fails.append(f"b = 0 row: a summary without servo_error must show '-', got '{line0}'")
ext = next((l for l in section.splitlines() if l.startswith(f"| {EXT_NAME} |")), "")
want = f"| 1.00 | {phi_ext:.1f} | 30.0 | 30.0 | {phi_ld[1.0]:.1f}"  # MN's b = 1 angle is phi_tc: 30 deg
if not ext.startswith(f"| {EXT_NAME} | 0.3 | 1 (extension) {want} {want} | - |"):
    fails.append(f"extension row: expected '1 (extension)' and twice '{want}', got '{ext}'")
# the plane-strain compression and extension: each at its measured b in the series, its direction in the peak table
for name, bv, phi_b, kind, how, direction in (
        (PS_NAME, B_PS, phi_ps, "plane strain", "A plane-strain test of the sample", "compression"),
        (PSE_NAME, B_PSE, phi_pse, "plane strain extension", "A plane-strain extension ('(plane strain extension)'",
         "extension")):
    row = next((l for l in section.splitlines() if l.startswith(f"| {name} |")), "")
    want = f"| {bv:.2f} | {phi_b:.1f} | 30.0 | {phi_b:.1f} | {phi_ld[bv]:.1f}"
    if not row.startswith(f"| {name} | 0.3 | {bv:g} ({kind}) {want} {want} |"):
        fails.append(f"{kind} row: expected '{bv:g} ({kind})' and twice '{want}', got '{row}'")
    if how not in section:
        fails.append(f"the section does not say how a {kind} test joins the series")
    pk = next((l for l in report.split("## Peak states")[1].splitlines() if l.startswith(f"| {name} |")), "")
    if f"| {direction}, plane strain (b {bv:g}) |" not in pk:
        fails.append(f"peak table: the {kind} test's direction, got '{pk}'")
# the misfits over the b > 0 tests: the two paths' b = 0.5 and b = 1, the extension (on the constant-sigma_3
# series: its b = 0 test's 30 deg), the plane-strain test and the plane-strain extension
mc = math.sqrt((sum((ph[b] - ph[0.0]) ** 2 for ph in (phi, phi_cp) for b in (0.5, 1.0)) + (phi_ext - 30) ** 2
                + (phi_ps - 30) ** 2 + (phi_pse - 30) ** 2) / 7)
mn = abs(phi_ext - 30) / math.sqrt(7)
ld = math.sqrt((sum((ph[b] - pl[b]) ** 2 for ph, pl in ((phi, phi_ld), (phi_cp, phi_ld_cp)) for b in (0.5, 1.0))
                + (phi_ext - phi_ld[1.0]) ** 2 + (phi_ps - phi_ld[B_PS]) ** 2 + (phi_pse - phi_ld[B_PSE]) ** 2) / 7)
for lab in ("largest obliquity", "critical state"):
    row = next((l for l in section.splitlines() if l.startswith(f"| {lab} |")), "")
    want = f"| {lab} | {mc:.2f}° (7) | {mn:.2f}° (7) | {ld:.2f}° (7) |"
    if row != want:
        fails.append(f"misfit row: expected '{want}', got '{row}'")
print(f"MN surface through phi_tc = 30 deg: phi(b=0.5) = {phi[0.5]:.3f}, LD there {phi_ld[0.5]:.3f}; "
      f"misfits MC {mc:.3f}, LD {ld:.3f} deg")
if fails:
    sys.exit("\n".join(fails))
print("failure criteria: ok")
