#!/usr/bin/env python3
"""Known-answer test of a probe study's report (scripts/grainlab_plot.py probe_report: the response envelopes).

Synthetic probes of two states, their runs as grainlab writes them (series.csv rows of the probe stage, its eps_a and
eps_v from its own start; summary.json's last stage a linear path with p_0, q_0, stress_direction, lateral_slope):
- state A (stages.load.stress_ratio = 0.3): isotropic linear elasticity, K = 40 MPa, G = 30 MPa: deps_v = dp'/K,
  deps_q = dq/(3G) (eps_q = 2/3 (eps_a - eps_r)); each probe reaches its direction with a 2 % lag of the lateral
  increment, as the servo's;
- state B (stages.load.stress_ratio = 0.6): the same elasticity plus a plastic strain h <n . dsigma> m in the Rendulic
  plane, loading direction n at 100 deg, flow direction m at 160 deg (non-associated, dilatant), h = 4e-7 / Pa: the
  probes that load it are softer and some have d2W <= 0 (computed here), which the report must list, and no other.
- The incremental law fitted to each state's probes: A's linear fit exact (K 40.0, G 30.0 MPa: incrementally
  linear), B's with one plastic mechanism exact (K, G, n at 100.0 deg, m at 160.0 deg, H = 1/h = 2.50 MPa).
Each row's reached direction, increments, strain response, its direction, |dsigma|/|deps| and d2W, and the drag's
share (p_drag, q_drag change by 1 % and 2 % of dp' and dq) are checked against the values computed here from the
stresses and strains the series holds, to the printed digits (within half a unit of the last); so are the stiffest /
softest lines and the unstable directions.
"""
import json
import math
import os
import shutil
import sys

import numpy as np

from synthetic_study import study_report

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/probe_check"
shutil.rmtree(work, ignore_errors=True)
K, G, H = 40e6, 30e6, 4e-7
P0, Q0 = {0.3: (110e3, 33e3), 0.6: (125e3, 75e3)}, None
DS = 5e3
THETAS = [20, 35.26, 60, 90, 125.26, 150, 200, 215.26, 240, 270, 305.26, 330]
cols = ["time", "step", "eps_a", "eps_v", "e", "p", "q", "sigma_x", "sigma_y", "sigma_z", "stage_type", "p_drag", "q_drag"]
jobs, expect = [], {}


def unit(deg):
    return np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])


def response(dsa, dsr, plastic):
    """(deps_a, deps_r) of a stress increment: the elastic part, plus the plastic one in state B."""
    dp, dq = (dsa + 2 * dsr) / 3, dsa - dsr
    dev, deq = dp / K, dq / (3 * G)
    dea, der = dev / 3 + deq, dev / 3 - deq / 2
    if plastic:
        ds = np.array([math.sqrt(2) * dsr, dsa])
        load = float(unit(100) @ ds)
        if load > 0:
            de = H * load * unit(160)
            dea, der = dea + de[1], der + de[0] / math.sqrt(2)
    return dea, der


for eta in (0.3, 0.6):
    p0, q0 = P0[eta]
    for th in THETAS:
        name = f"shear_drained_mur0_ebase_pbase_s5_n2000_load-stress_ratio{eta:g}_probe-stress_direction{th:g}"
        run = os.path.join(work, "jobs", name, "run")
        os.makedirs(run)
        open(os.path.join(work, "jobs", name, "done"), "w").close()
        slope = 0.0 if th in (90, 270) else math.cos(math.radians(th)) / (math.sqrt(2) * math.sin(math.radians(th)))
        u = unit(th)
        dsa, dsr = DS * u[1], 0.98 * DS * u[0] / math.sqrt(2)  # the lateral increment 2 % short: the servo's lag
        dea, der = response(dsa, dsr, eta == 0.6)
        sa0, sr0 = p0 + 2 * q0 / 3, p0 - q0 / 3
        rows = []
        for i, f in enumerate(np.linspace(0, 1, 11)):
            ea, er = f * dea, f * der
            ev = 1 - (1 - ea) * (1 - er) ** 2
            sa, sr = sa0 + f * dsa, sr0 + f * dsr
            p, q = (sa + 2 * sr) / 3, sa - sr
            rows.append([i, i, ea, ev, 0.7, p, q, sr, sr, sa, 2, 0.01 * (p - p0), 0.02 * (q - q0)])
        with open(os.path.join(run, "series.csv"), "w") as fh:
            fh.write("stage," + ",".join(cols) + "\n")
            fh.write("load,0,0,0.01,0.002,0.7,%r,%r,%r,%r,%r,2,0,0\n" % (p0, q0, sr0, sr0, sa0))
            for r in rows:
                fh.write("probe," + ",".join(repr(float(v)) for v in r) + "\n")
        # the increments as the run writes them (Laboratory::probe_increments, its arithmetic tested against the series
        # in Lab.LinearStressPathHoldsItsSlope): the last row's, in the Rendulic plane, eps_r from H and V
        x = np.array([math.sqrt(2) * dsr, dsa])
        er_exact = 1 - math.sqrt((1 - rows[-1][3]) / (1 - dea))
        y = np.array([math.sqrt(2) * er_exact, dea])
        with open(os.path.join(run, "summary.json"), "w") as fh:
            json.dump({"stages": [{"name": "load", "type": "triaxial", "stress_path": "constant_sigma3"},
                                  {"name": "probe", "type": "triaxial", "drainage": "drained", "stress_path": "linear",
                                   "lateral_slope": slope, "stress_direction": th, "p_0": p0, "q_0": q0, "steps": 10,
                                   "dsigma_rendulic": list(x), "deps_rendulic": list(y)}]}, fh)
        jobs.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_mur0", "mu_r": 0, "e0": 0, "p0": 0,
                     "drainage": "drained", "direction": "compression", "b": 0, "stress_path": "constant_sigma3",
                     "seed": 5, "count": 2000, "stage_keys": {"load.stress_ratio": eta, "probe.stress_direction": th},
                     "grading": "", "cu": 0, "E": 0})
        # what the report must give, from what the series holds
        dp, dq = rows[-1][11], rows[-1][12]
        drag = math.hypot(math.sqrt(2) * (dp - dq / 3), dp + 2 * dq / 3) / np.linalg.norm(x)
        expect[name] = [th, slope, math.degrees(math.atan2(x[1], x[0])) % 360, dsa / 1e3, x[0] / 1e3, 1e4 * y[1],
                        1e4 * y[0], math.degrees(math.atan2(y[1], y[0])) % 360,
                        np.linalg.norm(x) / np.linalg.norm(y) / 1e6, float(x @ y) / (np.linalg.norm(x) * np.linalg.norm(y)),
                        100 * drag]

report = study_report(work, jobs)
fail = []
decimals = [1, 3, 1, 2, 2, 3, 3, 1, 1, 3, 1]
seen = 0
for line in report.splitlines():
    if not line.startswith("| shear_"):
        continue
    cells = [c.strip() for c in line.strip("|").split("|")]
    want = expect.get(cells[0])
    if want is None:
        fail.append(f"unknown row {cells[0]}")
        continue
    seen += 1
    for got, w, d in zip(cells[1:], want, decimals):
        if abs(float(got) - w) > 0.5 * 10 ** -d + 1e-9:
            fail.append(f"{cells[0]}: {got} against {w:.{d + 2}f}")
if seen != 2 * len(THETAS):
    fail.append(f"{seen} probe rows, not {2 * len(THETAS)}")
for eta in (0.3, 0.6):
    names = [n for n in expect if f"ratio{eta:g}_" in n]
    mods = [(expect[n][8], expect[n][2], n) for n in names]
    hi, lo = max(mods), min(mods)

    def softest(n):
        """the softest probe's strain direction and dilatancy deps_v / deps_q, from its eps_a and exact eps_r"""
        dea, der = expect[n][5] / 1e4, expect[n][6] / 1e4 / math.sqrt(2)
        return f"theta_eps = {expect[n][7]:.1f}° (deps_v/deps_q = {(dea + 2 * der) / (2 / 3 * (dea - der)):+.3f})"
    # an elastic envelope is symmetric: theta and theta + 180 tie, and the last bit picks one; either is right
    lines = {f"Stiffest along theta_sigma = {a:.1f}° ({hi[0]:.1f} MPa), softest along {b:.1f}° ({lo[0]:.1f} MPa): "
             f"{hi[0] / lo[0]:.1f}x; the softest strains along {softest(n)}."
             for a in [t for m, t, _ in mods if abs(m - hi[0]) <= 1e-9 * hi[0]]
             for b, n in [(t, n) for m, t, n in mods if abs(m - lo[0]) <= 1e-9 * lo[0]]}
    if not any(x in report for x in lines):
        fail.append(f"state {eta}: none of the lines {sorted(lines)}")
    bad = [f"{expect[n][2]:.1f}" for n in sorted(names, key=lambda n: expect[n][0]) if not expect[n][9] > 0]
    if eta == 0.3 and bad:
        fail.append(f"the elastic state has d2W <= 0 along {bad}: the synthetic state is wrong")
    if eta == 0.6 and not bad:
        fail.append("the plastic state has no direction with d2W <= 0: the synthetic state tests nothing")
    want = (f"d2W <= 0 along {', '.join(bad)}°" if bad else "d2W > 0 in every direction probed")
    section = report.split(f"stages.load.stress_ratio = {eta:g}, mu_r = 0")[1].split("###")[0]
    if want not in section:
        fail.append(f"state {eta}: no '{want}' in its section")
    if f"The probes start at p'_0 = {P0[eta][0] / 1e3:.2f} kPa, q_0 = {P0[eta][1] / 1e3:.2f} kPa" not in section:
        fail.append(f"state {eta}: its start is not named")
    # the incremental law: A linear (K, G back), B one plastic mechanism (K, G, n, m, H back)
    want = ("misses by 0.0 % of the mean |deps| (K = 40.0 MPa, G = 30.0 MPa" if eta == 0.3 else
            "it fits to 0.0 %: K = 40.0 MPa, G = 30.0 MPa")
    if want not in section:
        fail.append(f"state {eta}: no '{want}' in its incremental law")
    want = ("incrementally linear (elastic)" if eta == 0.3 else
            "loading direction n at 100.0°, flow direction m at 160.0° (non-associated by +60.0°), plastic modulus "
            "H = 2.50 MPa")
    if want not in section:
        fail.append(f"state {eta}: no '{want}' in its incremental law")
    # the loading sector: none for the elastic state; B's probes softer than the geometric mean, 20 to 150 deg
    want = None if eta == 0.3 else "Soft sector(s), |dsigma|/|deps| below the geometric mean of the stiffest and the " \
        "softest: theta_sigma 20.4° to 149.5° (middle 84.9°)."
    if (want is None and "Soft sector" in section) or (want is not None and want not in section):
        fail.append(f"state {eta}: its soft sector is not {want}")
if not os.path.isfile(os.path.join(work, "figures", "response_envelopes.png")):
    fail.append("no figures/response_envelopes.png")
if fail:
    print("\n".join(fail))
    sys.exit(1)
print("probe report ok")
