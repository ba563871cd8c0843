#!/usr/bin/env python3
"""Known-answer test of the study report's state-parameter section (grainlab_plot.py state_parameter_section).

Nine synthetic drained compressions (mu_r 0.1) at p'_0 = 50, 100 and 200 kPa, three states each, built so that:
- every one ends at critical state (q/p' = 0.75 steady from 20 % to 40 %, p' = 3 p'_0 / (3 - q/p'), e steady) on the
  line e_c = 0.80 - 5e-4 p' [kPa], so the report's critical-state line is that line exactly;
- its state parameter psi_0 = e_0 - e_c(p'_0) is the chosen one (-0.06 ... +0.01);
- its peak friction angle is phi'_cs + 0.5 - 40 psi_0 degrees (q/p' peaks at 10 %) and its largest dilatancy
  (-d)_max = 0.03 - 2 psi_0 (eps_v piecewise linear: contraction to 5 %, dilation at that rate to 20 %, then none).
The section must give its line (e_c = 0.8000 - 5.000e-04 p' through the nine critical states at 67-267 kPa), each
test's e_c(p'_0), psi_0 and psi_end (0 on the line), phi'_cs = asin(2.25 / 6.75), the
difference, (-d)_max and psi at the row of (-d)_max (e less the line's at that row's p', the row found here by
scripts/dilatancy.py); mark the 50 kPa tests' e_c as extrapolated (their p'_0 below the line's lowest p'_c, 66.7 kPa);
and fit both measures in psi_0: 0.50 and -40.00 (0.030 and -2.000) with zero residual, where the line in e_0 alone
leaves a residual (the pressures differ), and (-d)_max on psi at it by least squares worked out here. A mu_r 0.3 test
(one critical state: no line) and an undrained test are not in the section; without any line, there is no section.
The same nine over a stage axis: pooled on one line in the table across the values over a preparation stage's key
(consolidate.mu) or the shear's end (shear.max_axial_strain), a line per value over a key of the shear (shear.mu).
Nine drained extensions beside them (eps_a < 0, q < 0, p' = 3 p'_0 / (3 + q/p') falling at constant sigma_3), built the
same way (but dilating to 30 %) on a line of their own, e_c = 0.78 - 4e-4 p', at q/p' = 0.6 (phi'_cs = asin(3 M / (6 -
M)) = asin(1/3)), their peaks phi'_cs + 0.5 - 40 psi_0 by Mohr-Coulomb in extension, their dilatancy along -eps_a: the
extension section gives each on the extensions' line (the compressions' would put psi_0 off by 0.02 - 1e-4 p'_0), its
200 kPa tests' e_c extrapolated (above the line's highest p'_c, 166.7 kPa), the fits 0.50 and -40.00, 0.030 and -2.000
as in compression; the compression section keeps its nine alone; across a preparation stage's values the extensions get
a heading of their own.
"""
import math
import os
import shutil
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import dilatancy as D  # noqa: E402
from synthetic_study import SHEAR_COLUMNS, shear_row, study_report, write_compression  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/state_parameter_check"
shutil.rmtree(work, ignore_errors=True)
cols = SHEAR_COLUMNS
jobs = []
A_LINE, B_LINE = 0.80, -5e-4  # e_c = A_LINE + B_LINE p' [kPa]
M_CS = 0.75
PHI_CS = math.degrees(math.asin(3 * M_CS / (6 + M_CS)))
A_EXT, B_EXT, M_EXT = 0.78, -4e-4, 0.6  # the extensions' line and stress ratio at critical state
PHI_EXT = math.degrees(math.asin(3 * M_EXT / (6 - M_EXT)))
eps = np.round(np.arange(0, 0.4001, 0.0025), 10)  # rows every 0.25 %: the dilatancy windows (2 %) lie in a segment


def e_line(p_kpa, ext=False):
    return (A_EXT + B_EXT * p_kpa) if ext else (A_LINE + B_LINE * p_kpa)


def test(name, p0, psi0, mu_r=0.1, drainage="drained", keys=None, E=None, ext=False):
    """A drained compression (ext: extension) from p'_0 [kPa] at state psi0, as the docstring builds it; returns its
    measures. keys: its stage-axis values (study.json's stage_keys, 'stage.key' -> value)."""
    e0 = e_line(p0, ext) + psi0
    phi_max = (PHI_EXT if ext else PHI_CS) + 0.5 - 40 * psi0
    s = math.sin(math.radians(phi_max))
    M_pk = 6 * s / (3 + s) if ext else 6 * s / (3 - s)
    M_end = M_EXT if ext else M_CS
    dil = 0.03 - 2 * psi0  # (-d)_max, > 0 for every psi0 here
    p_c = 3 * p0 / (3 + M_end) if ext else 3 * p0 / (3 - M_CS)
    # eps_v at the end takes e from e_0 to the line's e_c(p'_c): e = e_0 - (1 + e_0) eps_v; contraction at rate c to
    # 5 %, dilation at rate dil to 20 % (30 % in extension, where p' falls and the dense end state lies further
    # from e_0: a dilation to 20 % would need the contraction to dilate faster than it)
    dil_end, dil_span = (0.30, 0.25) if ext else (0.20, 0.15)
    ev_end = (e0 - e_line(p_c, ext)) / (1 + e0)
    c = (ev_end + dil_span * dil) / 0.05
    assert c > -dil, "the contraction must not dilate faster than the dilation segment"
    ev = np.where(eps <= 0.05, c * eps, np.where(eps <= dil_end, 0.05 * c - dil * (eps - 0.05), ev_end))
    eta = np.where(eps <= 0.10, M_pk * eps / 0.10, np.where(eps <= 0.20, M_pk + (M_end - M_pk) * (eps - 0.10) / 0.10,
                                                            M_end))
    if drainage == "undrained":
        eta = 0.5 + 3 * eps  # still rising at its end (q/p' by 0.15 over the window): no critical state
    sign = -1 if ext else 1
    p = 3 * p0 * 1e3 / (3 - sign * eta)  # constant sigma_3 = p'_0 (the lateral stress in extension)
    e = e0 - (1 + e0) * ev
    series = [shear_row(i, *r, mu_r, drainage) for i, r in enumerate(zip(sign * eps, ev, p, sign * eta * p, e))]
    jobs.append(write_compression(work, name, p0, drainage, series, cols, mu_r, keys, E,
                                  "extension" if ext else "compression"))
    rows = list(zip(p, e))
    # psi where the test dilates fastest: the row the dilatancy's windows find (the segment's rate is one, so which
    # of its rows depends on round-off), its e less the line's at its p'
    k_d = int(np.nanargmin(D.analyse(sign * eps, ev, eta, extension=ext)["d"]))
    psi_d = rows[k_d][1] - e_line(rows[k_d][0] / 1e3, ext)
    return dict(name=name, p0=p0, e0=e0, psi0=psi0, phi=phi_max, dil=dil, psi_d=psi_d)


fails = []
want = [test(f"cd_p{p0}_{k}", p0, psi) for p0, psis in ((50, (-0.05, -0.02, 0.01)), (100, (-0.06, -0.03, 0.0)),
                                                        (200, (-0.04, -0.01, 0.005))) for k, psi in enumerate(psis)]
test("other_mu_r", 100, -0.02, mu_r=0.3)
test("undrained", 100, 0.0, drainage="undrained")
want_ext = [test(f"te_p{p0}_{k}", p0, psi, ext=True) for p0, psis in ((50, (-0.05, -0.02, 0.01)),
                                                                     (100, (-0.06, -0.03, 0.0)),
                                                                     (200, (-0.04, -0.01, 0.005)))
            for k, psi in enumerate(psis)]
text = study_report(work, jobs)
head = "## State parameter (drained compression)"


def check_section(head, want, ext):
    """The rows, the line's text and the fits of the section under head against the tests want of a direction;
    returns the rms about lines in e_0 alone, the psi_0 and psi at (-d)_max, and that fit."""
    if head not in text:
        sys.exit(f"state_parameter_check: no '{head}' in report.md")
    sec = text.split(head)[1].split("\n## ")[0]
    rows = {r.split(" | ")[0][2:]: r.split(" | ") for r in sec.splitlines() if r.startswith("| cd_") or
            r.startswith("| te_") or r.startswith("| other") or r.startswith("| undrained")}
    if sorted(rows) != sorted(t["name"] for t in want):
        fails.append(f"{head}: the section's tests: {sorted(rows)}, expected the nine mu_r 0.1 drained ones")
    a, b, phi_cs = (A_EXT, B_EXT, PHI_EXT) if ext else (A_LINE, B_LINE, PHI_CS)
    # p'_0 beyond the line's critical states' p'_c (3 p'_0 / (3 + M) from 50 to 200 kPa in extension, 3 p'_0 /
    # (3 - M) in compression): extrapolated, marked *
    lo, hi = (50 * 3 / (3 + M_EXT), 200 * 3 / (3 + M_EXT)) if ext else (50 * 3 / (3 - M_CS), 200 * 3 / (3 - M_CS))
    for t in want:
        r = rows.get(t["name"])
        if r is None or len(r) != 12:
            fails.append(f"{t['name']}: row {r}")
            continue
        outside = not lo <= t["p0"] <= hi
        got_ec = f"{e_line(t['p0'], ext):.4f} ± 0.0000" + (" *" if outside else "")
        expect = [f"{t['p0']:.1f}", f"{t['e0']:.4f}", got_ec, f"{t['psi0']:+.4f}", "+0.0000", f"{t['phi']:.1f}",
                  f"{phi_cs:.1f}", f"{t['phi'] - phi_cs:+.1f}"]
        got = [r[2], r[3], r[4], r[5].replace("-0.0000", "+0.0000"), r[6].replace("-0.0000", "+0.0000"), r[7], r[8],
               r[9]]
        if got != expect:
            fails.append(f"{t['name']}: {got}, expected {expect}")
        if abs(float(r[10].split(" ± ")[0]) - t["dil"]) > 5e-4:
            fails.append(f"{t['name']}: (-d)_max {r[10]}, expected {t['dil']:.3f}")
        if r[11].rstrip(" |") != f"{t['psi_d']:+.4f}":
            fails.append(f"{t['name']}: psi at (-d)_max {r[11]}, expected {t['psi_d']:+.4f}")
    line_txt = f"{a:.4f} ± 0.0000 + ({b:.3e} ± "
    if f"The line: mu_r 0.1: e_c = {line_txt}" not in sec or "through 9 critical states at p'_c " \
            f"{lo:.0f}–{hi:.0f} kPa, phi'_cs {phi_cs:.1f}°." not in sec:
        fails.append(f"{head}: the line's text (e_c = {line_txt}...): {sec.split('The line')[-1][:200]!r}")
    if "*: p'_0 outside the pressures" not in sec:
        fails.append(f"{head}: no note on the extrapolated e_c (*)")
    fit_rows = [r for r in sec.splitlines() if r.startswith("| 0.1 | 9 |")]
    # the line in e_0 alone misses: its residual, worked out here
    psi = np.array([t["psi0"] for t in want])
    e0 = np.array([t["e0"] for t in want])
    rms_e = []
    for y in (np.array([t["phi"] - phi_cs for t in want]), np.array([t["dil"] for t in want])):
        k, c = np.polyfit(e0, y, 1)
        rms_e.append(float(np.sqrt(np.mean((y - c - k * e0) ** 2))))
    # (-d)_max on psi at it: least squares worked out here (the rows' psi are not on one line with (-d)_max)
    psi_d = np.array([t["psi_d"] for t in want])
    dil = np.array([t["dil"] for t in want])
    k_dd, c_dd = np.polyfit(psi_d, dil, 1)
    rms_dd = float(np.sqrt(np.mean((dil - c_dd - k_dd * psi_d) ** 2)))
    expect_fits = [f"| 0.1 | 9 | phi'_max - phi'_cs [°] on psi_0 | 0.50 ± 0.00 | -40.00 ± 0.00 | 0.00 | "
                   f"{rms_e[0]:.2f} |",
                   f"| 0.1 | 9 | (-d)_max on psi_0 | 0.030 ± 0.000 | -2.000 ± 0.000 | 0.000 | {rms_e[1]:.3f} |",
                   f"| 0.1 | 9 | (-d)_max on psi at it | {c_dd:.3f} ± "]
    # (the peak's row is the table's phi'_max; the fit takes the unrounded one: exact)
    got_fits = [r.replace("-0.00 |", "0.00 |").replace("-0.000 |", "0.000 |") for r in fit_rows]
    if got_fits[:2] != expect_fits[:2] or len(got_fits) != 3 or not got_fits[2].startswith(expect_fits[2]) or \
            f"| {k_dd:.3f} ± " not in got_fits[2] or not got_fits[2].endswith(f"| {rms_dd:.3f} | {rms_e[1]:.3f} |"):
        fails.append(f"{head}: the fits: {fit_rows}, expected {expect_fits} (the third: slope {k_dd:.3f}, "
                     f"rms {rms_dd:.3f})")
    if min(rms_e) < 0.01 * np.ptp(psi):
        fails.append(f"the line in e_0 fits as well as psi_0 ({rms_e}): the test cannot tell them apart")
    return rms_e, psi_d, c_dd, k_dd


rms_e, psi_d, c_dd, k_dd = check_section(head, want, False)
check_section("## State parameter (drained extension)", want_ext, True)
# The same nine as a study over a preparation stage's axis (consolidate.mu, a value per state): the table across the
# values pools them on one line (a section column, the same psi_0 as above); over an axis of the shear stage itself
# (shear.mu: another material at each value) each value's three get a line of their own, but over its end
# (shear.max_axial_strain) they are pooled; at two contact stiffnesses (E: 1e8, 1e9) a line per E
STATES = ((50, (-0.05, -0.02, 0.01)), (100, (-0.06, -0.03, 0.0)), (200, (-0.04, -0.01, 0.005)))
for axis in ("consolidate.mu", "shear.mu", "shear.max_axial_strain", "E"):
    shutil.rmtree(work)
    jobs.clear()
    for E in ((1e8, 1e9) if axis == "E" else (None,)):  # the E axis: the nine at two stiffnesses, pooled apart
        for p0, psis in STATES:
            for k, psi in enumerate(psis):
                test(f"cd_p{p0}_{k}" + (f"_E{E:g}" if E else ""), p0, psi, E=E,
                     keys={"consolidate.mu" if axis == "E" else axis: (0.1, 0.3, 0.5)[k]})
                if axis == "consolidate.mu":  # and the extensions, pooled on their own line under their own heading
                    test(f"te_p{p0}_{k}", p0, psi, keys={axis: (0.1, 0.3, 0.5)[k]}, ext=True)
    text = study_report(work, jobs)
    across = text.split("## Across the values")[1].split("\n## ")[0] if "## Across the values" in text else ""
    heads = [x for x in across.splitlines() if x.startswith("### State parameter across the values")]
    if axis == "consolidate.mu":
        want_heads = ["### State parameter across the values", "### State parameter across the values (extension)"]
        # one line through both directions' critical states of every value, each direction's offset from it against
        # the scatter once each direction's mean offset is out (9 - 2 - 1 + 9 degrees of freedom), worked out here
        p0s = [p0 for p0, _ in STATES for _ in range(3)]
        st = [("compression", pc, e_line(pc)) for pc in (3 * p0 / (3 - M_CS) for p0 in p0s)] + \
             [("extension", pc, e_line(pc, True)) for pc in (3 * p0 / (3 + M_EXT) for p0 in p0s)]
        x, y = np.array([v[1] for v in st]), np.array([v[2] for v in st])
        k_j, c_j = np.polyfit(x, y, 1)
        res = y - c_j - k_j * x
        mine = {m: res[[v[0] == m for v in st]] for m in ("compression", "extension")}
        within = float(np.sqrt(sum(np.sum((r - r.mean()) ** 2) for r in mine.values()) / (len(st) - 3)))
        table = across.split("### One critical-state line across the values and directions")[-1].split("\n### ")[0]
        for m, r in mine.items():
            off, se = float(r.mean()), within / 3
            row = next((ln for ln in table.splitlines() if f"| {m} | 9 |" in ln), "")
            verdict = "off the line" if abs(off) > 2 * se else "on it"
            want_row = f"| {m} | 9 | {round(off, 4) + 0.0:+.4f} | {se:.4f} | {verdict} |"
            if not row.startswith(f"| mu_r 0.1 | e_c = {c_j:.4f} ± ") or not row.endswith(want_row) or \
                    "(18 states, rms " not in row:
                fails.append(f"the line across the values and directions, {m}: {row!r}, expected e_c = {c_j:.4f} "
                             f"... {want_row}")
        for t in want + want_ext:
            k = int(t["name"][-1])
            sp = across.split("### State parameter across the values" + (" (extension)" if t in want_ext else "") +
                              "\n")[-1].split("\n### ")[0]
            start = f"| {axis} = {(0.1, 0.3, 0.5)[k]:g} | {t['name']} |"
            row = next((x for x in sp.splitlines() if x.startswith(start)), "")
            if f"| {t['psi0']:+.4f} |".replace("-0.0000", "+0.0000") not in row.replace("-0.0000", "+0.0000"):
                fails.append(f"pooled over {axis}: {t['name']}'s row {row!r}, psi_0 {t['psi0']:+.4f} wanted")
    elif axis == "shear.mu":
        want_heads = [f"### State parameter across the values: {axis} = {v:g}" for v in (0.1, 0.3, 0.5)]
    elif axis == "E":
        want_heads = [f"### State parameter across the values: E = {E:g} Pa" for E in (1e8, 1e9)]
    else:  # the shear's own end: where it stops, not what it is: pooled
        want_heads = ["### State parameter across the values"]
    if heads != want_heads:
        fails.append(f"over {axis}: the state-parameter headings across the values {heads}, expected {want_heads}")
# without a line (the mu_r 0.3 test alone): no section
shutil.rmtree(work)
jobs.clear()
test("lonely", 100, -0.02)
if head in study_report(work, jobs):
    fails.append("a section without a critical-state line")
if fails:
    sys.exit("state_parameter_check: " + "\n".join(fails))
print(f"state_parameter_check: ok (9 tests on the line, psi_0 -0.06 to +0.01; rms about a line in e_0 {rms_e[0]:.2f}° "
      f"and {rms_e[1]:.3f}; psi at (-d)_max {psi_d.min():+.4f} to {psi_d.max():+.4f}, on it (-d)_max {c_dd:.3f} "
      f"{k_dd:+.3f} psi)")
