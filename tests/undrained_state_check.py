#!/usr/bin/env python3
"""Known-answer test of the study report's undrained state-parameter section (grainlab_plot.py
undrained_state_section, undrained_response).

Nine synthetic drained compressions (mu_r 0.1) at p'_0 = 50, 100 and 200 kPa end at critical state (q/p' = 0.75) on
the line e_c = 0.80 - 5e-4 p' [kPa], which the report's critical-state line is then exactly. Eight undrained
compressions (constant e = e_0) of the same mu_r, with piecewise-linear paths of known shape:
- liquefies: e_0 = 0.81 at 100 kPa (psi_0 +0.06, e_0 above the line's intercept: the line says it liquefies), q
  rises to 30 kPa at 1 % and falls with p' to 0.375 and 0.5 kPa at 5 % and on to 0.06 and 0.08 kPa at 30 %: I_B =
  0.998, r_u,max = 0.9994 (liquefied); p' then fluctuates (0.3 kPa at 35 %, 0.12 at 40 %: more than half its least
  but not a tenth of p'_0, no phase transformation), not critical and not on the line (as a liquefied sample's p'
  near 0, which fluctuates by as much as itself);
- liquefies and re-jams: e_0 = 0.805 at 200 kPa (psi_0 +0.105): q peaks at 40 kPa at 0.5 % (p' 180: q/p' 0.222
  there), p' falls to 5 kPa at 3 % (2.5 % of p'_0: I_B 0.906, r_u,max 0.981) and from 10 % rises to 30 kPa at 40 %: a
  rise past both thresholds from a liquefied least, '- (regains)', no transformation (a sixth of the end's p', so
  the least is liquefied against p'_0, not against where the test ends);
- limited liquefaction at 100 kPa (psi_0 -0.02) and at 50 kPa (-0.04, its p'_0 below the line's pressures: *): q
  peaks at 0.4 p'_0 at 1 %, falls to 0.1 p'_0 at 5 % with p' to 0.2 p'_0 (I_B 0.75, phase transformation at q/p'
  0.5), then p' rises to the line's p'_c at e_0 (140 and 130 kPa) by 20 % with q = 0.75 p' and stays: on the line;
- dilative at 100 kPa (psi_0 -0.1): p' dips to 95 kPa at 1 % and rises toward p'_c = 300 kPa (above the line's
  pressures: *), which it reaches at the end, still rising (not critical), q rising all along: I_B 0 ('-' peak and
  trough), phase transformation at 1 %;
- a late collapse at 50 kPa (psi_0 0): limited liquefaction (I_B 0.75, p' 10 kPa at 5 %), a phase transformation
  (p' up to 40 kPa at 15 %), then p' falls back to 12 kPa by the end (not critical): the transformation is the rise
  after the least, not where the test ends;
- steady at 200 kPa (psi_0 +0.02, the line's p'_c 160 kPa): q peaks at 140 kPa at 2 % and falls to 118 at 10 %
  (I_B 22 / 140) with p' to 158, which then fluctuates up to 185 kPa at 20 % (a tenth of p'_0 but not half its least:
  no phase transformation) and is 160 kPa from 30 %;
- dilative from the start at 200 kPa (psi_0 -0.06, p'_c 320 kPa, *): p' rises 200 -> 400 kPa from the first row to
  the end (not critical): no phase transformation, p'_min / p'_0 1.000 at 0, r_u,max 0 (at the start); q falls by a
  fifth at 31 % and is back by 33 %: a dilating sample's
  fluctuation about its critical state, past the least p', which I_B leaves out (0).
The section must list the eight (not the drained tests nor a test of another mu_r), each measure as built, the line's
p'_c at e_0 with '0 (liquefies)' for the first, the residual of each critical end against it, and I_B and p'_min /
p'_0 on lines in psi_0 by least squares worked out here, beside the rms about a line in e_0. Over a preparation stage
axis the table across the values pools them; without a line, there is no section.
Triaxial extensions beside them (eps_a < 0, q < 0; u = p'_0 + q/3 - p' as in compression, the lateral stress held):
nine drained ones at critical state (q/p' = 0.6, p' = 3 p'_0 / (3 + q/p')) on a line of their own, e_c = 0.78 - 4e-4
p' (p'_c 41.7-166.7 kPa), and three undrained ones: limited liquefaction at 100 kPa (psi_0 -0.02: |q| peaks at 0.4
p'_0 at eps_a -1 %, falls to 0.1 p'_0 at -5 % with p' to 0.2 p'_0, I_B 0.75, a phase transformation at q/p' 0.5, then
on to the extension line's p'_c at e_0, 150 kPa, at q/p' = 0.6), liquefaction (e_0 0.79, above the extensions'
intercept: '0 (liquefies)'; p' as the compression's LIQ_P, q = -0.6 p' from -5 %) and a dilative one (psi_0 -0.08,
p'_c 300 kPa *). Their section, "State parameter (undrained extension)", must give each measure as built, q's peak
and trough < 0 at eps_a < 0, the p'_c of the extensions' line (the compressions' would give 260 kPa for the first),
and the fits in psi_0 worked out here; the compression section keeps its eight.
"""
import os
import shutil
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from synthetic_study import SHEAR_COLUMNS, shear_row, study_report, write_compression  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/undrained_state_check"
shutil.rmtree(work, ignore_errors=True)
cols = SHEAR_COLUMNS + ["u"]
jobs = []
A_LINE, B_LINE = 0.80, -5e-4  # e_c = A_LINE + B_LINE p' [kPa]
M_CS = 0.75
eps = np.round(np.arange(0, 0.4001, 0.0025), 10)


def e_line(p_kpa):
    return A_LINE + B_LINE * p_kpa


def write(name, p, q, e, p0, mu_r=0.1, drainage="drained", keys=None, ext=False):
    """A compression (ext: extension, eps_a = -eps) test's run (p, q [kPa] and e per row of eps) and its job in
    study.json."""
    # SPEC §6: u = p'_0 + q/3 - p' (0 in a drained test)
    rows = [shear_row(i, -ea if ext else ea, (e[0] - ek) / (1 + e[0]), pk * 1e3, qk * 1e3, ek, mu_r, drainage,
                      u=(p0 + qk / 3 - pk) * 1e3 if drainage == "undrained" else 0.0)
            for i, (ea, pk, qk, ek) in enumerate(zip(eps, p, q, e))]
    jobs.append(write_compression(work, name, p0, drainage, rows, cols, mu_r, keys, None,
                                  "extension" if ext else "compression"))


def drained(name, p0, psi0, mu_r=0.1, keys=None):
    """At constant sigma_3 = p'_0, q/p' up to M_CS by 10 %, e from e_0 to the line's at p'_c by 20 %: critical."""
    eta = np.minimum(M_CS * eps / 0.10, M_CS)
    p = 3 * p0 / (3 - eta)
    e0 = e_line(p0) + psi0
    e = e0 + (e_line(3 * p0 / (3 - M_CS)) - e0) * np.minimum(eps / 0.20, 1)
    write(name, p, eta * p, e, p0, mu_r, keys=keys)


A_EXT, B_EXT, M_EXT = 0.78, -4e-4, 0.6  # the extensions' line and critical stress ratio


def e_line_ext(p_kpa):
    return A_EXT + B_EXT * p_kpa


def drained_ext(name, p0, psi0):
    """An extension at constant sigma_3 = p'_0 (the lateral stress), q/p' up to M_EXT by 10 %: critical on the
    extensions' line by 20 %."""
    eta = np.minimum(M_EXT * eps / 0.10, M_EXT)
    p = 3 * p0 / (3 + eta)
    e0 = e_line_ext(p0) + psi0
    e = e0 + (e_line_ext(3 * p0 / (3 + M_EXT)) - e0) * np.minimum(eps / 0.20, 1)
    write(name, p, -eta * p, e, p0, ext=True)


def lin(points):
    """The piecewise-linear function through (eps, value) points, constant past the last, at every row."""
    x, y = zip(*points)
    return np.interp(eps, x, y)


E0 = {}  # each undrained test's e_0


def undrained(name, p0, e0, p_pts, q_pts, mu_r=0.1, keys=None, ext=False):
    E0[name] = e0
    write(name, lin(p_pts), lin(q_pts), np.full(len(eps), e0), p0, mu_r, "undrained", keys, ext)


def p_line(e0):
    """The line's p' at void ratio e0 [kPa]."""
    return (e0 - A_LINE) / B_LINE


# the liquefied test's p' [kPa] (eps, p'); its q is 0.75 p' from 5 % on
LIQ_P = [(0, 100), (0.01, 80), (0.05, 0.5), (0.3, 0.08), (0.35, 0.3), (0.4, 0.12)]


# a late collapse at 50 kPa (psi_0 0): limited liquefaction to p' 10 kPa at 5 %, a rise to 40 kPa at 15 % (a phase
# transformation) and a fall to 16 and 12 kPa at 30 and 40 %, q = 0.75 p' from 15 % on
# liquefies at 200 kPa (e_0 0.805, above the line's intercept) by 3 % and re-jams from 10 %: p' 5 -> 30 kPa by 40 %
REG_P = [(0, 200), (0.005, 180), (0.03, 5), (0.1, 5), (0.4, 30)]
DIL2_P = [(0, 200), (0.4, 400)]  # the dilative test at 200 kPa: p' rising from the first row to the end
LATE_P = [(0, 50), (0.01, 42), (0.05, 10), (0.15, 40), (0.25, 16), (0.3, 16), (0.4, 12)]
LATE_Q = [(0, 0), (0.01, 20), (0.05, 5), (0.15, 30), (0.25, 12), (0.3, 12), (0.4, 9)]


EXT_PC = (e_line_ext(100) - 0.02 - A_EXT) / B_EXT  # 150 kPa: the limited extension's end on its line
DILE_P = [(0, 100), (0.01, 95), (0.4, 300)]


def build(keys=None, ext=False):
    """The tests above (keys: over a preparation stage's values); ext: the extensions too."""
    if ext:
        for p0, psis in ((50, (-0.05, 0.01)), (100, (-0.06, 0.0)), (200, (-0.04, 0.005))):
            for n, psi in enumerate(psis):
                drained_ext(f"te_p{p0}_{n}", p0, psi)
        undrained("ce_limited", 100, e_line_ext(100) - 0.02, [(0, 100), (0.01, 84), (0.05, 20), (0.2, EXT_PC)],
                  [(0, 0), (0.01, -40), (0.05, -10), (0.2, -M_EXT * EXT_PC)], ext=True)
        undrained("ce_liquefies", 100, 0.79, LIQ_P, [(0, 0), (0.01, -30)] + [(x, -0.6 * y) for x, y in LIQ_P[2:]],
                  ext=True)
        undrained("ce_dilative", 100, e_line_ext(100) - 0.08, DILE_P, [(0, 0), (0.4, -180)], ext=True)
    k = 0
    for p0, psis in ((50, (-0.05, -0.02, 0.01)), (100, (-0.06, -0.03, 0.0)), (200, (-0.04, -0.01, 0.005))):
        for psi in psis:
            drained(f"cd_p{p0}_{k}", p0, psi, keys=keys and {"consolidate.mu": (0.1, 0.3, 0.5)[k % 3]})
            k += 1
    kk = keys and {"consolidate.mu": 0.5}
    undrained("cu_liquefies", 100, 0.81, LIQ_P, [(0, 0), (0.01, 30)] + [(x, 0.75 * y) for x, y in LIQ_P[2:]],
              keys=kk)
    for p0, psi in ((100, -0.02), (50, -0.04)):
        e0 = e_line(p0) + psi
        pc = p_line(e0)
        undrained(f"cu_limited_p{p0}", p0, e0, [(0, p0), (0.01, 0.84 * p0), (0.05, 0.2 * p0), (0.2, pc)],
                  [(0, 0), (0.01, 0.4 * p0), (0.05, 0.1 * p0), (0.2, M_CS * pc)], keys=kk)
    undrained("cu_dilative", 100, e_line(100) - 0.1, [(0, 100), (0.01, 95), (0.4, 300)], [(0, 0), (0.4, 225)],
              keys=kk)
    undrained("cu_dilative_p200", 200, e_line(200) - 0.06, DIL2_P, [(0, 0), (0.2, 240), (0.3, 240), (0.31, 192),
                                                                   (0.33, 240), (0.4, 300)], keys=kk)
    undrained("cu_late", 50, e_line(50), LATE_P, LATE_Q, keys=kk)
    undrained("cu_regains", 200, 0.805, REG_P, [(0, 0), (0.005, 40)] + [(x, 0.75 * y) for x, y in REG_P[2:]], keys=kk)
    undrained("cu_steady", 200, e_line(200) + 0.02, [(0, 200), (0.1, 158), (0.2, 185), (0.3, 160)],
              [(0, 0), (0.02, 140), (0.1, 118), (0.2, 138.75), (0.3, 120)], keys=kk)
    undrained("cu_other_mu_r", 100, 0.73, [(0, 100), (0.2, 140)], [(0, 0), (0.2, 105)], mu_r=0.3, keys=kk)


# the liquefied test's end window (the rows within 5 % of strain of the last, as critical_state takes it): the mean
# of its p' rows (LIQ_P)
P_END_LIQ = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], *zip(*LIQ_P))))
P_END_DIL2 = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], *zip(*DIL2_P))))
P_END_REG = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], *zip(*REG_P))))
P_END_LATE = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], *zip(*LATE_P))))
# the dilative test's: p' rising from 95 kPa at 1 % to 300 at 40 %; and its q (0 -> 225 kPa over 40 %)
P_END_DIL = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], [0.01, 0.4], [95, 300])))


def q_dil(x):
    return 225 * x / 0.4


# name -> psi_0, the line's p'_c, p'_end, psi_end, q_pk / p'_0 (eps %), q/p' at q_pk, q_min / p'_0 (eps %), I_B,
#         p'_min / p'_0 (eps %), q/p' at PT, r_u,max; built above
WANT = {
    "cu_liquefies": (+0.06, "0 (liquefies)", f"{P_END_LIQ:.1f} (not critical)", e_line(100) + 0.06 - e_line(P_END_LIQ),
                     "0.300 (1.0)", f"{30 / 80:.3f}", "0.001 (30.0)", (30 - 0.06) / 30, "0.001 (30.0)", "-",
                     f"{1 + 0.02 / 100 - 0.0008:.3f} (liquefied)"),
    "cu_limited_p100": (-0.02, "140 ± 0", "140.0", 0.0, "0.400 (1.0)", f"{40 / 84:.3f}", "0.100 (5.0)", 0.75,
                        "0.200 (5.0)", "0.500", f"{(100 + 10 / 3 - 20) / 100:.3f}"),
    "cu_limited_p50": (-0.04, "130 ± 0", "130.0", 0.0, "0.400 (1.0)", f"{20 / 42:.3f}", "0.100 (5.0)", 0.75,
                       "0.200 (5.0)", "0.500", f"{(50 + 5 / 3 - 10) / 50:.3f}"),
    "cu_dilative": (-0.1, "300 ± 0 *", f"{P_END_DIL:.1f} (not critical)", e_line(100) - 0.1 - e_line(P_END_DIL),
                    "-", "-", "-", 0.0, "0.950 (1.0)", f"{q_dil(0.01) / 95:.3f}",
                    f"{(100 + q_dil(0.01) / 3 - 95) / 100:.3f}"),
    "cu_dilative_p200": (-0.06, "320 ± 0 *", f"{P_END_DIL2:.1f} (not critical)", -B_LINE * (P_END_DIL2 - 320), "-",
                         "-", "-", 0.0, "1.000 (0.0)", "-", "0.000"),
    "cu_late": (0.0, "50 ± 0 *", f"{P_END_LATE:.1f} (not critical)", -B_LINE * (P_END_LATE - 50), "0.400 (1.0)",
                f"{20 / 42:.3f}", "0.100 (5.0)", 0.75, "0.200 (5.0)", "0.500",
                f"{max(50 + q / 3 - p for (_, p), (_, q) in zip(LATE_P, LATE_Q)) / 50:.3f}"),
    "cu_steady": (+0.02, "160 ± 0", "160.0", 0.0, "0.700 (2.0)", f"{140 / 191.6:.3f}", "0.590 (10.0)", 22 / 140,
                  "0.790 (10.0)", "-", f"{(200 + 118 / 3 - 158) / 200:.3f}"),
    "cu_regains": (0.805 - e_line(200), "0 (liquefies)", f"{P_END_REG:.1f} (not critical)",
                   0.805 - e_line(P_END_REG), "0.200 (0.5)", f"{40 / 180:.3f}", "0.019 (3.0)", (40 - 3.75) / 40,
                   "0.025 (3.0)", "- (regains)", f"{(200 + 1.25 - 5) / 200:.3f} (liquefied)"),
}
build(ext=True)
text = study_report(work, jobs)
head = "## State parameter (undrained compression)"
fails = []
# the extensions' section: name -> the row from psi_0 on, as built (module docstring)
P_END_DILE = float(np.mean(np.interp(eps[eps >= eps[-1] - 0.05], *zip(*DILE_P))))
WANT_EXT = {
    "ce_limited": ["-0.0200", "150 ± 0", "150.0", "+0.0000", "-0.400 (-1.0)", f"{40 / 84:.3f}", "-0.100 (-5.0)",
                   "0.750", "0.200 (-5.0)", "0.500", f"{(100 - 10 / 3 - 20) / 100:.3f}"],
    "ce_liquefies": [f"{0.79 - e_line_ext(100):+.4f}", "0 (liquefies)", f"{P_END_LIQ:.1f} (not critical)",
                     f"{0.79 - e_line_ext(P_END_LIQ):+.4f}", "-0.300 (-1.0)", f"{30 / 80:.3f}",
                     f"{-0.6 * 0.08 / 100:.3f} (-30.0)", f"{(30 - 0.048) / 30:.3f}", "0.001 (-30.0)", "-",
                     f"{(100 - 0.048 / 3 - 0.08) / 100:.3f} (liquefied)"],
    "ce_dilative": ["-0.0800", "300 ± 0 *", f"{P_END_DILE:.1f} (not critical)",
                    f"{e_line_ext(100) - 0.08 - e_line_ext(P_END_DILE):+.4f}", "-", "-", "-", "0.000",
                    "0.950 (-1.0)", f"{180 * 0.01 / 0.4 / 95:.3f}", f"{(100 - 180 * 0.01 / 0.4 / 3 - 95) / 100:.3f}"],
}
head_e = "## State parameter (undrained extension)"
sec_e = text.split(head_e)[1].split("\n## ")[0] if head_e in text else ""
rows_e = {r.split(" | ")[0][2:]: [x.strip() for x in r.strip("| ").split(" | ")] for r in sec_e.splitlines()
          if r.startswith("| c") or r.startswith("| te_")}
if sorted(rows_e) != sorted(WANT_EXT):
    fails.append(f"the extension section's tests: {sorted(rows_e)}, expected {sorted(WANT_EXT)}")
for name, w in WANT_EXT.items():
    got = [x.replace("-0.0000", "+0.0000") for x in rows_e.get(name, [])[4:15]]
    if got != w:
        fails.append(f"{name}: {got}, expected {w}")
names_e = sorted(WANT_EXT)
psi_e = np.array([float(WANT_EXT[n][0]) for n in names_e])
e0_e = np.array([E0[n] for n in names_e])
# (dilative, limited, liquefies: their I_B and p'_min / p'_0 unrounded)
for col, y in (("I_B on psi_0", np.array([0.0, 0.75, (30 - 0.048) / 30])),
               ("p'_min / p'_0 on psi_0", np.array([0.95, 0.2, 0.0008]))):
    k, c = np.polyfit(psi_e, y, 1)
    rms = float(np.sqrt(np.mean((y - c - k * psi_e) ** 2)))
    ke, ce = np.polyfit(e0_e, y, 1)
    rms_e = float(np.sqrt(np.mean((y - ce - ke * e0_e) ** 2)))
    row = next((x for x in sec_e.splitlines() if x.startswith(f"| 0.1 | 3 | {col} |")), "")
    if not row.startswith(f"| 0.1 | 3 | {col} | {c:.3f} ± ") or f"| {k:.3f} ± " not in row or \
            not row.endswith(f"| {rms:.3f} | {rms_e:.3f} |"):
        fails.append(f"the extensions' fit {col}: {row!r}, expected {c:.3f} + {k:.3f} psi_0, rms {rms:.3f}, on e_0 "
                     f"{rms_e:.3f}")
if "The line: mu_r 0.1: e_c = 0.7800 ± 0.0000 + (-4.000e-04 ± " not in sec_e:
    fails.append(f"the extensions' line: {sec_e.split('The line')[-1][:120]!r}")
if head not in text:
    sys.exit(f"undrained_state_check: no '{head}' in report.md")
sec = text.split(head)[1].split("\n## ")[0]
rows = {r.split(" | ")[0][2:]: [x.strip() for x in r.strip("| ").split(" | ")] for r in sec.splitlines()
        if r.startswith("| c")}
if sorted(rows) != sorted(WANT):
    fails.append(f"the section's tests: {sorted(rows)}, expected {sorted(WANT)}")
for name, w in WANT.items():
    r = rows.get(name)
    if r is None or len(r) != 15:
        fails.append(f"{name}: row {r}")
        continue
    psi0 = f"{w[0]:+.4f}" + (" *" if name in ("cu_limited_p50", "cu_late") else "")
    expect = [psi0, w[1], w[2], f"{w[3]:+.4f}", w[4], w[5], w[6], f"{w[7]:.3f}", w[8], w[9], w[10]]
    got = [r[4].replace("-0.0000", "+0.0000"), r[5], r[6], r[7].replace("-0.0000", "+0.0000"), *r[8:15]]
    if got != expect:
        fails.append(f"{name}: {got}, expected {expect}")
if "Of the 3 tests at critical state, the measured p'_end less the line's p'_c: +0, +0, +0 kPa." not in sec:
    fails.append(f"the residuals against the line: {sec[:0] + sec.split('Of the')[-1][:160]!r}")
# the fits: least squares worked out here, in psi_0 and in e_0
names = sorted(WANT)
psi = np.array([WANT[n][0] for n in names])
e0 = np.array([E0[n] for n in names])
pmin = {"cu_liquefies": 0.0008, "cu_limited_p100": 0.2, "cu_limited_p50": 0.2, "cu_dilative": 0.95,
        "cu_dilative_p200": 1.0, "cu_steady": 0.79, "cu_late": 0.2, "cu_regains": 0.025}
for col, y in (("I_B on psi_0", np.array([WANT[n][7] for n in names])),
               ("p'_min / p'_0 on psi_0", np.array([pmin[n] for n in names]))):
    k, c = np.polyfit(psi, y, 1)
    rms = float(np.sqrt(np.mean((y - c - k * psi) ** 2)))
    ke, ce = np.polyfit(e0, y, 1)
    rms_e = float(np.sqrt(np.mean((y - ce - ke * e0) ** 2)))
    want = f"| 0.1 | 8 | {col} | {c:.3f} ± "
    row = next((x for x in sec.splitlines() if x.startswith(f"| 0.1 | 8 | {col} |")), "")
    if not row.startswith(want) or f"| {k:.3f} ± " not in row or not row.endswith(f"| {rms:.3f} | {rms_e:.3f} |"):
        fails.append(f"the fit {col}: {row!r}, expected {c:.3f} + {k:.3f} psi_0, rms {rms:.3f}, on e_0 {rms_e:.3f}")
if "The line: mu_r 0.1: e_c = 0.8000 ± 0.0000 + (-5.000e-04 ± " not in sec:
    fails.append(f"the line's text: {sec.split('The line')[-1][:120]!r}")
# pooled across a preparation stage axis's values
shutil.rmtree(work)
jobs.clear()
build(keys=True)
text = study_report(work, jobs)
across = text.split("## Across the values")[1].split("\n## ")[0] if "## Across the values" in text else ""
sp = across.split("### Undrained state parameter across the values")
if len(sp) != 2 or not any(x.startswith("| consolidate.mu = 0.5 | cu_limited_p100 |") and "| 140 ± 0 |" in x
                           for x in sp[1].splitlines()):
    fails.append(f"pooled over consolidate.mu: {sp[-1][:300]!r}")
# without a line (one drained test): no section
shutil.rmtree(work)
jobs.clear()
drained("lonely", 100, -0.02)
undrained("cu_alone", 100, 0.73, [(0, 100), (0.2, 140)], [(0, 0), (0.2, 105)])
if head in study_report(work, jobs):
    fails.append("a section without a critical-state line")
if fails:
    sys.exit("undrained_state_check: " + "\n".join(fails))
print("undrained_state_check: ok (8 undrained tests against the line: liquefaction with and without re-jamming, "
      "limited liquefaction at two pressures, a steady state, a late collapse, dilation with and without a phase "
      "transformation; I_B, p'_min, "
      "r_u,max and the fits as built)")
