#!/usr/bin/env python3
"""Known-answer test of the report's flow section (scripts/grainlab_plot.py flow_section, scripts/dilatancy.py
deviatoric_flow; true triaxial).

1. normal_b against the b of a central-difference gradient of ln(I1 I2 / I3) (Matsuoka-Nakai) and ln(I1^3 / I3)
   (Lade-Duncan), worked out here from the invariants alone; 0 at b = 0, 1 at b = 1.
2. energy_ratio reduces to Rowe's relations: sigma_1 / sigma_3 = K (1 - d) in triaxial compression, K / (1 + d) in
   extension (dilatancy.principal_ratio's stresses), sigma_1 / sigma_3 = K (-d lambda_3 / d lambda_1) in plane strain.
3. A synthetic study of one sample sheared drained at b = 0 and b = 0.5 whose strain increments obey, at every instant,
   Rowe's energy ratio K = 3 (phi_f 30 deg; K_EARLY = 2 below 3 % strain, long before the largest contraction, where
   Rowe's fit does not look) and b_eps = BETA (0 and 0.3): sigma_3 = 100 kPa, sigma_1 / sigma_3 rising
   to a peak at 15 % natural axial strain and down to the constant-volume state of K and BETA by 30 %, steady to 40 %
   (a dense sample: contraction, dilation, critical state). Each axis's natural strain integrated here from the
   increments; the series holds their engineering strains. The section's cells against a plain re-working from the
   CSV (numpy.polyfit slopes over the same window, the largest obliquity's row, the critical-state window's means,
   the fit through the origin): and at critical state the known answers b 0.50, b_eps 0.30, K 3 to the window's
   transition. A third test (b = 0.25, BETA 0.3) stopped at 20 %, while it softens: no critical state, '-' in those
   four cells, the others as worked out. A fourth in plane strain (summary.json stress_path: plane_strain; eps_x 0,
   sigma_x at b = 0.3 of the others), on Rowe's K alone (d lambda_y = -sigma_z / (K sigma_y)): it joins the
   constant-sigma_3 series as '0.3 (plane strain)', its b_eps at critical state (d lambda_y = -1) 0.5.
   In the critical-state lines it is a direction of its own, "compression, plane strain", at 30.0 deg.
4. A plane-strain extension (direction extension; eps_x 0, the y walls held at 100 kPa, the axis unloaded: sigma_y the
   major stress, sigma_x at b = 0.4 between it and sigma_z) on Rowe's K alone (per unit -d lambda_z, d lambda_y =
   K sigma_z / sigma_y): it joins the series as '0.4 (plane strain extension)' at its measured b, not a triaxial
   extension's b = 1, its cells worked out from the CSV with the loading along -eps_a and the order y, x, z; its b_eps
   at critical state 0.5 (d lambda_y = 1), K 3; its own critical-state direction "extension, plane strain", 30.0 deg.
5. The b = 0 test with the two plane-strain tests alone (no b > 0 set): the section is written, titled plane strain.
"""
import csv
import json
import math
import os
import shutil
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(here, "..", "scripts"))
import dilatancy  # noqa: E402
from synthetic_study import SHEAR_COLUMNS, study_report  # noqa: E402

fails = []


def check(what, got, want, tol):
    if not abs(got - want) <= tol:
        fails.append(f"{what}: {got:.12g}, expected {want:.12g} (tolerance {tol:g})")


def b3(v):
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.float64(v[1] - v[2]) / np.float64(v[0] - v[2])


def cell(v):
    """v as the report's two-decimal cell; the oracle's -1e-10 (a central difference's noise about 0) as 0.00."""
    return f"{round(float(v), 2) + 0.0:.2f}"


def gradient_b(sig, f, h=1e-6):
    """b of the central-difference gradient of f at the stresses sig (1, 2, 3)."""
    g = []
    for i in range(3):
        up, dn = list(sig), list(sig)
        up[i] += h * sig[i]
        dn[i] -= h * sig[i]
        g.append((f(*up) - f(*dn)) / (2 * h * sig[i]))
    return b3(g)


def ln_mn(s1, s2, s3):
    return math.log((s1 + s2 + s3) * (s1 * s2 + s2 * s3 + s3 * s1) / (s1 * s2 * s3))


def ln_ld(s1, s2, s3):
    return math.log((s1 + s2 + s3) ** 3 / (s1 * s2 * s3))


# 1. Tolerance: the central difference's error is O(h^2) relative, 1e-12, and its round-off ~1e-16 / h = 1e-10 of the
# gradient's components, whose differences (b's numerator and denominator) are O(0.1) of them: 1e-8 on b.
for s in [(3.0, 1.0, 1.0), (3.0, 3.0, 1.0), (3.0, 2.0, 1.0), (5.2, 1.7, 1.0), (2.0, 1.9, 1.1), (4.0, 1.2, 1.0)]:
    sig = np.array(s, dtype=float).reshape(3, 1)
    check(f"MN normal b at {s}", float(dilatancy.normal_b(sig, "MN")[0]), gradient_b(s, ln_mn), 1e-8)
    check(f"LD normal b at {s}", float(dilatancy.normal_b(sig, "LD")[0]), gradient_b(s, ln_ld), 1e-8)
for crit in ("MN", "LD"):
    check(f"{crit} normal at b = 0", float(dilatancy.normal_b(np.array([[3.0], [1.0], [1.0]]), crit)[0]), 0.0, 1e-15)
    check(f"{crit} normal at b = 1", float(dilatancy.normal_b(np.array([[3.0], [3.0], [1.0]]), crit)[0]), 1.0, 1e-15)

# 2. Rowe's relations (to round-off: 1e-12 relative)
for d in (0.3, 0.0, -0.4):
    for eta in (0.6, 1.2):
        R = dilatancy.principal_ratio(eta)  # compression: d lambda = (1, -(1 - d)/2, -(1 - d)/2)
        w_in, w_out = dilatancy.energy_ratio(np.array([[R], [1.0], [1.0]]),
                                             np.array([[1.0], [-(1 - d) / 2], [-(1 - d) / 2]]))
        check(f"compression E at d {d}, eta {eta}", float(w_in[0] / w_out[0]), R / (1 - d), 1e-12 * R)
        R = dilatancy.principal_ratio(eta, True)  # extension: the lateral pair shortens, d lambda_3 = -1
        w_in, w_out = dilatancy.energy_ratio(np.array([[R], [R], [1.0]]),
                                             np.array([[(1 + d) / 2], [(1 + d) / 2], [-1.0]]))
        check(f"extension E at d {d}, eta {eta}", float(w_in[0] / w_out[0]), R * (1 + d), 1e-12 * R)
w_in, w_out = dilatancy.energy_ratio(np.array([[4.0], [2.0], [1.0]]), np.array([[1.0], [0.0], [-1.3]]))
check("plane strain E", float(w_in[0] / w_out[0]), 4.0 / 1.3, 1e-12)
if not np.isnan(dilatancy.energy_ratio(np.array([[4.0], [2.0], [1.0]]), np.array([[1.0], [np.nan], [-1.3]]))[0][0]):
    fails.append("energy_ratio: an increment not measured must give NaN, not a zero term")

# 3. The synthetic study.
K, S3, E0 = 3.0, 1e5, 0.7
N_ROWS, DT, SUB = 81, 0.005, 200  # rows every 0.5 % of natural axial strain to 40 %; SUB integration steps a row
T_PEAK, T_CS, OVERSHOOT = 0.15, 0.30, 1.25
K_EARLY, T_EARLY = 2.0, 0.03  # the fit from the first row instead of the turn holds these rows: K 2.980 at b = 0


def increments(s1, s2, s3, beta, k=K):
    """(d lambda_x, d lambda_y) per unit d lambda_z with b_eps = beta and W_in / W_out = k at stresses sigma_z = s1,
    sigma_x = s2, sigma_y = s3: d lambda_x = d lambda_y + beta (1 - d lambda_y) (b_eps's definition), and d lambda_y
    by bisection (E falls from infinity to 0 as d lambda_y goes from 0 to -infinity)."""
    def ratio(ay):
        ax = ay + beta * (1 - ay)
        inc, sig = (1.0, ax, ay), (s1, s2, s3)
        w_in = sum(s * a for s, a in zip(sig, inc) if a > 0)
        w_out = -sum(s * a for s, a in zip(sig, inc) if a < 0)
        return w_in / w_out
    lo, hi = -100.0, -1e-12
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) < k else (lo, mid)
    ay = 0.5 * (lo + hi)
    return ay + beta * (1 - ay), ay


def final_ratio(b, beta):
    """sigma_1 / sigma_3 at which the flow of K and beta keeps the volume: 1 + d lambda_x + d lambda_y = 0."""
    lo, hi = 1.0 + 1e-9, 20.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        ax, ay = increments(mid, 1 + b * (mid - 1), 1.0, beta)
        lo, hi = (mid, hi) if 1 + ax + ay > 0 else (lo, mid)  # contracting: the stress ratio is below it
    return 0.5 * (lo + hi)


def stresses(t, b, r_cs):
    """sigma_z, sigma_x, sigma_y [Pa] at natural axial strain t: up to OVERSHOOT r_cs at T_PEAK, down to r_cs at
    T_CS."""
    r_pk = OVERSHOOT * r_cs
    r = 1 + (r_pk - 1) * t / T_PEAK if t <= T_PEAK else (r_pk + (r_cs - r_pk) * (t - T_PEAK) / (T_CS - T_PEAK)
                                                         if t <= T_CS else r_cs)
    return S3 * r, S3 * (1 + b * (r - 1)), S3


work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/deviatoric_flow_check"
shutil.rmtree(work, ignore_errors=True)
cols = SHEAR_COLUMNS + ["eps_x", "eps_y"]
jobs, tests = [], {}
PS = 0.3  # the plane-strain test's b, keyed by it below


def increments_ps(s1, s3, k):
    """Plane strain's (d lambda_x, d lambda_y): x held, Rowe's W_in / W_out = sigma_1 / (-sigma_3 d lambda_y) = k."""
    return 0.0, -s1 / (k * s3)


PSE = 0.4  # the plane-strain extension's b


def write_pse():
    """Section 4's test: sigma_y = S3 held, sigma_z = S3 / r unloaded along r's path to K (stresses()), sigma_x at
    PSE of the two; natural strains per unit -d lambda_z: (0, K_ sigma_z / sigma_y, -1), integrated as above."""
    lam = np.zeros((3, N_ROWS))
    for i in range(1, N_ROWS):
        lam[:, i] = lam[:, i - 1]
        for k in range(SUB):
            t = DT * (i - 1 + (k + 0.5) / SUB)
            r = stresses(t, 0.0, K)[0] / S3
            lam[:, i] += DT / SUB * np.array([0.0, (K_EARLY if t < T_EARLY else K) / r, -1.0])
    eng, ev = -np.expm1(-lam), -np.expm1(-lam.sum(axis=0))
    name = "shear_drained_mur0.3_ebase_pbase_s1_n300_ext_ps"
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0, "drainage": "drained",
                               "direction": "extension", "stress_path": "plane_strain"}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i in range(N_ROWS):
            sy = S3
            sz = S3 * S3 / stresses(DT * i, 0.0, K)[0]
            sx = sz + PSE * (sy - sz)
            p, q = (sx + sy + sz) / 3, sz - (sx + sy) / 2
            row = dict(time=i, step=i, eps_a=eng[2, i], eps_v=ev[i], p=p, q=q, q_p=abs(q) / p,
                       e=(1 + E0) * (1 - ev[i]) - 1, mu=0.5, mu_r=0.3, stage_type=2, a_c=0.1, a_d=0.05, a_n=0.1,
                       a_t=0.02, sff_share_c=0.25, sff_share_d=0.25, sff_share_n=0.25, sff_share_t=0.25, sff=abs(q) / p,
                       inertial_number=5e-4, sigma_x=sx, sigma_y=sy, sigma_z=sz, eps_x=eng[0, i], eps_y=eng[1, i])
            w.writerow(["shear"] + [repr(float(row[k])) for k in cols])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_mur0.3_ebase_pbase_s1_n300", "mu_r": 0.3,
                 "e0": 0, "p0": S3, "drainage": "drained", "direction": "extension", "b": 0, "seed": 1, "count": 300,
                 "csr": 0, "cycles": 0, "strain_amplitude": 0})
    tests[PSE] = (name, run, K, True, None, True)


for b, beta, n_rows in ((0.0, 0.0, N_ROWS), (0.5, 0.3, N_ROWS), (0.25, 0.3, 41), (PS, None, N_ROWS)):
    r_cs = K if beta is None else final_ratio(b, beta)  # plane strain keeps its volume at sigma_1 / sigma_3 = K
    lam = np.zeros((3, n_rows))  # x, y, z natural strains: the increments integrated by the midpoint rule
    for i in range(1, n_rows):
        lam[:, i] = lam[:, i - 1]
        for k in range(SUB):
            t = DT * (i - 1 + (k + 0.5) / SUB)
            sz_, sx_, sy_ = stresses(t, b, r_cs)
            k_ = K_EARLY if t < T_EARLY else K
            ax, ay = increments(sz_, sx_, sy_, beta, k_) if beta is not None else increments_ps(sz_, sy_, k_)
            lam[:, i] += DT / SUB * np.array([ax, ay, 1.0])
    eng = -np.expm1(-lam)  # engineering strains, compression positive
    ev = -np.expm1(-lam.sum(axis=0))
    name = "shear_drained_mur0.3_ebase_pbase_s1_n300" + ("_ps" if beta is None else f"_b{b:g}" if b > 0 else "")
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0 if beta is None else b,
                               "drainage": "drained", **({"stress_path": "plane_strain"} if beta is None else {})}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for i in range(n_rows):
            sz, sx, sy = stresses(DT * i, b, r_cs)
            p, q = (sx + sy + sz) / 3, sz - (sx + sy) / 2
            row = dict(time=i, step=i, eps_a=eng[2, i], eps_v=ev[i], p=p, q=q, q_p=q / p, e=(1 + E0) * (1 - ev[i]) - 1,
                       mu=0.5, mu_r=0.3, stage_type=2, a_c=0.1, a_d=0.05, a_n=0.1, a_t=0.02, sff_share_c=0.25,
                       sff_share_d=0.25, sff_share_n=0.25, sff_share_t=0.25, sff=q / p, inertial_number=5e-4,
                       sigma_x=sx, sigma_y=sy, sigma_z=sz, eps_x=eng[0, i], eps_y=eng[1, i])
            w.writerow(["shear"] + [repr(float(row[k])) for k in cols])
    jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_mur0.3_ebase_pbase_s1_n300", "mu_r": 0.3,
                 "e0": 0, "p0": S3, "drainage": "drained", "direction": "compression", "b": b, "seed": 1, "count": 300,
                 "csr": 0, "cycles": 0, "strain_amplitude": 0})
    tests[b] = (name, run, r_cs, n_rows == N_ROWS, beta, False)
write_pse()

report = study_report(work, jobs, peak={"window": 0, "max_ke_ratio": 0})
HEAD = "## Flow in the deviatoric plane (true triaxial and plane strain)"
if HEAD not in report:
    sys.exit(f"no '{HEAD}' in report.md")
if not os.path.isfile(os.path.join(work, "figures", "deviatoric_flow.png")):
    fails.append("figures/deviatoric_flow.png missing")
section = report.split(HEAD)[1].split("\n## ")[0]


def slope(x, y, k, window=dilatancy.WINDOW):
    """The least-squares slope of y on x over the rows within window / 2 of row k (NaN where the window is not whole
    or holds fewer than MIN_ROWS rows): numpy.polyfit, not dilatancy.rate."""
    window = max(window, dilatancy.MIN_ROWS * float(np.median(np.diff(x))))
    if x[k] - window / 2 < x[0] or x[k] + window / 2 > x[-1]:
        return float("nan")
    m = np.abs(x - x[k]) <= window / 2
    return float(np.polyfit(x[m], y[m], 1)[0]) if m.sum() >= dilatancy.MIN_ROWS else float("nan")


def expected(run, b, ext=False):
    """The row's cells worked out from the CSV: (-d)_max and its strain, b, b_eps, MN, LD at the largest obliquity and
    over the critical-state window, and Rowe's K, phi_f and rms. ext: a plane-strain extension, loaded along -eps_a,
    its stresses in the order y, x, z."""
    with open(os.path.join(run, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    col = {k: np.array([float(r[k]) for r in rows]) for k in cols}
    lam = {a: -np.log(1 - col[c]) for a, c in (("x", "eps_x"), ("y", "eps_y"), ("z", "eps_a"), ("v", "eps_v"))}
    n = len(rows)
    load = -lam["z"] if ext else lam["z"]
    inc = {a: np.array([slope(load, lam[a], k) for k in range(n)]) for a in ("x", "y", "v")}
    # the order by the mean stresses: z, x, y (sigma_x >= sigma_y here, equal at b = 0: x first, as a stable sort);
    # in the plane-strain extension y, x, z
    s1, s2, s3 = col["sigma_z"], col["sigma_x"], col["sigma_y"]
    e1, e2, e3 = np.where(np.isfinite(inc["x"]), 1.0, np.nan), inc["x"], inc["y"]
    if ext:
        s1, s3 = s3, s1
        e1, e3 = inc["y"], np.where(np.isfinite(inc["x"]), -1.0, np.nan)
    b_eps = (e2 - e3) / (e1 - e3)
    bb = b3((s1, s2, s3))
    mn = [gradient_b((s1[k], s2[k], s3[k]), ln_mn) for k in range(n)]
    ld = [gradient_b((s1[k], s2[k], s3[k]), ln_ld) for k in range(n)]
    ang = np.degrees(np.arcsin((s1 - s3) / (s1 + s3)))
    kp = int(np.argmax(ang))
    along = -col["eps_a"] if ext else col["eps_a"]
    w = (along >= along[-1] - 0.05) & np.isfinite(b_eps)
    kd = int(np.nanargmin(inc["v"]))
    w_in, w_out = np.full(n, np.nan), np.full(n, np.nan)
    for k in range(n):
        if np.isfinite(e2[k]):
            work_ = [(s1[k], e1[k]), (s2[k], e2[k]), (s3[k], e3[k])]
            w_in[k] = sum(s * e for s, e in work_ if e > 0) / s3[k]
            w_out[k] = -sum(s * e for s, e in work_ if e < 0) / s3[k]
    k0 = int(np.argmax(col["eps_v"]))
    ok = np.isfinite(w_in) & (np.arange(n) >= k0)
    Kf = float(np.sum(w_in[ok] * w_out[ok]) / np.sum(w_out[ok] ** 2))
    rms = float(np.sqrt(np.mean(((w_in[ok] - Kf * w_out[ok]) / w_in[ok]) ** 2)))
    # plane strain's dilation angle at the largest dilation (d lambda_1 = 1, d lambda_3 = y's) and Bolton's ratio with
    # the angles of the peak row and of the critical-state window (wall stresses)
    psi = math.degrees(math.asin(-inc["v"][kd] / (e1[kd] - e3[kd])))
    bolton = (ang[kp] - np.mean(ang[w])) / psi
    return dict(d=(-inc["v"][kd], 100 * abs(col["eps_a"][kd])), peak=(bb[kp], b_eps[kp], mn[kp], ld[kp]), psi=psi,
                bolton=bolton,
                cs=(np.mean(bb[w]), np.mean(b_eps[w]), np.mean(np.array(mn)[w]), np.mean(np.array(ld)[w])),
                K=Kf, phi=math.degrees(math.asin((Kf - 1) / (Kf + 1))), rms=rms)


dev = {"peak": [], "cs": []}  # b_eps minus radial, MN and LD flow over the tests at 0 < b < 1
phis = []
for b, (name, run, r_cs, critical, beta, ext) in tests.items():
    x = expected(run, b, ext)
    if not critical:
        x["cs"] = None
    line = next((l for l in section.splitlines() if l.startswith(f"| {name} |")), "")
    cells = [c.strip() for c in line.strip("|").split("|")]
    if len(cells) != 14:
        fails.append(f"b = {b}: no row of 14 cells: '{line}'")
        continue
    kind = (" (plane strain extension)" if ext else " (plane strain)") if beta is None else ""
    want = [name, "0.3", f"{b:g}" + kind, None, *(cell(v) for v in x["peak"]),
            *((cell(v) for v in x["cs"]) if critical else ["-"] * 4), f"{x['K']:.3f}",
            f"{x['phi']:.1f} ({x['rms']:.3f})"]
    for i, (g, wv) in enumerate(zip(cells, want)):
        if wv is not None and g != wv:
            fails.append(f"b = {b}, column {i + 1}: '{g}', expected '{wv}'")
    if not cells[3].startswith(f"{x['d'][0]:.3f} ± ") or not cells[3].endswith(f"({x['d'][1]:.1f})"):
        fails.append(f"b = {b}: (-d)_max '{cells[3]}', expected {x['d'][0]:.3f} at {x['d'][1]:.1f} %")
    # the known answers: the flow's BETA everywhere past the window's reach of the early rows, K to the transition rows
    # the fit holds; at critical state the stresses' b too
    if beta is not None:
        check(f"b = {b}: b_eps at the peak", x["peak"][1], beta, 1e-9)
    check(f"b = {b}: Rowe K", x["K"], K, 0.05)
    if critical:
        check(f"b = {b}: b at c.s.", x["cs"][0], b, 1e-12)
        check(f"b = {b}: b_eps at c.s.", x["cs"][1], 0.5 if beta is None else beta, 1e-9)
    for st in ("peak", "cs"):
        if 0 < b < 1 and x[st] is not None:
            dev[st].append([x[st][1] - x[st][c] for c in (0, 2, 3)])
    phis.append(x["phi"])
    print(f"b = {b}: sigma_1/sigma_3 at c.s. {r_cs:.4f}; peak b_eps {x['peak'][1]:.4f}, MN {x['peak'][2]:.4f}, LD "
          f"{x['peak'][3]:.4f}; (-d)_max {x['d'][0]:.4f}; K {x['K']:.4f}, rms {x['rms']:.4f}")
for lab, st in (("largest obliquity", "peak"), ("critical state", "cs")):
    v = np.array(dev[st])
    want = f"| {lab} | " + " | ".join(f"{math.sqrt(np.mean(v[:, c] ** 2)):.3f} ({len(v)})" for c in range(3)) + " |"
    if want not in section:
        fails.append(f"misfit row: expected '{want}'")
# the critical-state lines: the plane-strain test a direction of its own (not a b of its own, nor a compression), its
# angle from the principal stresses (sigma_1 / sigma_3 = K = 3 at critical state: 30.0 deg)
for way in ("compression", "extension"):
    if f"| 0.3 | {way}, plane strain | 1 | fewer than 3 critical states" not in report or "(30.0°)" not in next(
            (l for l in report.splitlines() if l.startswith(f"| 0.3 | {way}, plane strain |")), ""):
        fails.append(f"the critical-state lines: no group '{way}, plane strain' at 30.0 deg")
for b in (PS, PSE):
    x = expected(tests[b][1], b, tests[b][5])
    want = f"{tests[b][0]}: psi_max {x['psi']:.1f}°, (phi'_max - phi'_cs) / psi_max {x['bolton']:.2f}"
    if want not in section:
        fails.append(f"expected the plane-strain line '{want}'")
    print(f"plane strain{' extension' if tests[b][5] else ''}: psi_max {x['psi']:.3f} deg, Bolton's ratio "
          f"{x['bolton']:.3f}")
want = (f"Rowe's phi_f across b: mu_r = 0.3 (sample_mur0.3_ebase_pbase_s1_n300): phi_f {min(phis):.1f} to "
        f"{max(phis):.1f}° over 5 tests.")
if want not in section:
    fails.append(f"expected the line '{want}'")

# 5. A series of a triaxial compression and plane-strain tests alone (no b set > 0): the plane-strain tests are its
# b > 0 members, in compression or extension, so the section is written, its rows as above.
report = study_report(work, [j for j in jobs if j["name"] in (tests[0.0][0], tests[PS][0], tests[PSE][0])],
                      peak={"window": 0, "max_ke_ratio": 0})
HEAD_PS = "## Flow in the deviatoric plane (plane strain)"
for b in (PS, PSE):
    row = next((l for l in report.split(HEAD_PS)[-1].splitlines() if l.startswith(f"| {tests[b][0]} |")), "")
    if HEAD_PS not in report or not row:
        fails.append(f"a series of plane-strain tests alone: no '{HEAD_PS}' section with the row of b = {b}")

if fails:
    sys.exit("deviatoric_flow_check:\n  " + "\n  ".join(fails))
print("deviatoric flow: ok")
