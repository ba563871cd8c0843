#!/usr/bin/env python3
"""Known-answer test of the study report's liquefaction-resistance curves (grainlab_plot.py liquefaction_fit,
cyclic_section) on synthetic cyclic tests:
- mu_r 0: four tests at CSR 0.1, 0.15, 0.2, 0.3 whose N at 5 % DA strain lie exactly on CSR = 0.3 N^-0.34 (N = (CSR /
  0.3)^(-1/0.34): 25.3 ... 1), and whose N at r_u = 0.95 lie on CSR = 0.25 N^-0.2 for the three that met it (the
  fourth stood: not met). The fit gives a and b to 1e-12 and CRR = a 15^-b (0.1195 and 0.1455): within the DA tests'
  N (1 to 25.3), beyond the r_u tests' (0.40 to 12.9: marked extrapolated); the report's table gives them to 4
  digits; the rms misfit of exact points is round-off.
- mu_r 0.3: one test met the criterion: not fitted, and the report says so.
- liquefaction_fit refuses points whose CSR rises with N (no resistance curve) and points at one N.
- a study over confining pressure (the jobs' p0 differ): a curve per mu_r and p'_0, the 100 kPa tests on CSR = 0.3
  N^-0.34, the 200 kPa ones on CSR = 0.2 N^-0.3, each fitted exactly (one curve through all seven was the report
  before: a = 0.275, b = 0.341, rms 0.16 in log CSR, of no sample), the table with a conditions column; a drained test beside undrained ones likewise
  is a group of its own (here one test: not fitted, named with its drainage). The overburden table: K_sigma = CRR(200
  kPa)/CRR(100 kPa) = 0.2 15^-0.3 / (0.3 15^-0.34) and C_sigma = (1 - K_sigma)/ln 2; overburden_factor on CRR 0.12,
  0.10, 0.08 at 100, 200, 400 kPa: K_sigma 1, 5/6, 2/3 and C_sigma = (5/6)/(5 ln 2) by least squares, to 1e-12.
  Referred to one atmosphere along that line (at_one_atmosphere): CRR(p_a) = CRR(100 kPa) (1 - C ln(1.01325)) and
  C' = C / (1 - C ln(1.01325)), so that CRR(p')/CRR(p_a) = 1 - C' ln(p'/p_a) at every tested p' (to 1e-12);
  tests from 200 kPa up give it extrapolated."""
import csv
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import grainlab_plot  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/liquefaction_fit_check"
shutil.rmtree(work, ignore_errors=True)
figs = os.path.join(work, "figs")
os.makedirs(figs)
fails = []


def da_law(csr):
    return (csr / 0.3) ** (-1 / 0.34)


def ru_law(csr):
    return (csr / 0.25) ** (-1 / 0.2)


def cyclic_run(name, csr, n_da, n_ru, mu_r, **job_keys):
    """A run dir with a consolidation and one undrained cyclic stage (series rows and summary.json as the run writes
    them, only what the section reads) and its job."""
    run = os.path.join(work, name)
    os.makedirs(run)
    n_end = max(x for x in (n_da, n_ru, 1.0) if x is not None)
    rows = [("consolidate", 0, 0, 100, 0), ("shake", 3, 0, 100, 0), ("shake", 3, n_end / 2, 80, 20),
            ("shake", 3, n_end, 60, 40)]
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage", "time", "step", "eps_a", "p", "q", "u", "e", "mu_r", "stage_type", "cycle"])
        for k, (st, ty, n, p, u) in enumerate(rows):
            w.writerow([st, k * 1e-3, k, 1e-4 * k if ty else 0, p * 1e3, 0, u * 1e3, 0.7, mu_r, ty, n])
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "consolidate", "type": "isotropic"},
                              {"name": "shake", "type": "cyclic", "drainage": "undrained", "cycles": 30,
                               "cycle": n_end, "liquefaction_ru": 0.95, "n_ru": n_ru, "liquefaction_da_strain": 0.05,
                               "n_da": n_da, "quarter_cycle_transits": 8.0}]}, f)
    job = dict({"name": name, "mu_r": mu_r, "csr": csr, "drainage": "undrained", "cycles": 30}, **job_keys)
    return job, run, grainlab_plot.load(run)


cyc = []
for csr in (0.1, 0.15, 0.2, 0.3):
    cyc.append(cyclic_run(f"t{csr:g}", csr, da_law(csr), ru_law(csr) if csr > 0.1 else None, 0.0))
cyc.append(cyclic_run("r0.2", 0.2, 3.0, None, 0.3))
cyc.append(cyclic_run("r0.3", 0.3, None, None, 0.3))

# the fit itself, exactly
f = grainlab_plot.liquefaction_fit([(da_law(c), c) for c in (0.1, 0.15, 0.2, 0.3)])
want = {"a": 0.3, "b": 0.34, "crr": 0.3 * 15 ** -0.34}
for k, v in want.items():
    if f is None or abs(f[k] - v) > 1e-12 * v:
        fails.append(f"DA fit {k} = {None if f is None else f[k]}, wanted {v}")
if f is not None and not (f["tests"] == 4 and f["rms"] < 1e-12 and abs(f["n_min"] - 1) < 1e-12):
    fails.append(f"DA fit {f}")
if grainlab_plot.liquefaction_fit([(1.0, 0.1), (10.0, 0.2)]) is not None:
    fails.append("a CSR rising with N was fitted")
if grainlab_plot.liquefaction_fit([(2.0, 0.1), (2.0, 0.2)]) is not None:
    fails.append("points at one N were fitted")

lines = grainlab_plot.cyclic_section(cyc, figs, {0.0: "C0", 0.3: "C1"})
text = "\n".join(lines)
crr_da, crr_ru = 0.3 * 15 ** -0.34, 0.25 * 15 ** -0.2
want_rows = [f"| 0 | 5 % DA strain | 4 | 0.3 | 0.34 | {crr_da:.4g} | 1–{da_law(0.1):.3g} | ",
             f"| 0 | r_u = 0.95 | 3 | 0.25 | 0.2 | {crr_ru:.4g} (extrapolated) | {ru_law(0.3):.3g}–{ru_law(0.15):.3g} | "]
for w in want_rows:
    if not any(x.startswith(w) for x in lines):
        fails.append(f"no report row starting {w!r}")
if "mu_r 0.3, 5 % DA strain (1 test)" not in text:
    fails.append("the report does not say mu_r 0.3's one test is not fitted")
if text.count("(extrapolated)") != 1:
    fails.append("not the r_u curve's CRR alone marked extrapolated")
if not os.path.isfile(os.path.join(figs, "liquefaction.png")):
    fails.append("no liquefaction.png")

# A confining-pressure study: a curve per p'_0
cyc2 = [cyclic_run(f"p1_{c:g}", c, da_law(c), None, 0.0, p0=1e5) for c in (0.1, 0.15, 0.2, 0.3)]
cyc2 += [cyclic_run(f"p2_{c:g}", c, (c / 0.2) ** (-1 / 0.3), None, 0.0, p0=2e5) for c in (0.1, 0.15)]
cyc2.append(cyclic_run("d0.2", 0.2, 4.0, None, 0.0, p0=1e5, drainage="drained"))
lines2 = grainlab_plot.cyclic_section(cyc2, figs, {0.0: "C0"})
text2 = "\n".join(lines2)
for w in (f"| 0 | p'_0 100 kPa, undrained | 5 % DA strain | 4 | 0.3 | 0.34 | {crr_da:.4g} | ",
          f"| 0 | p'_0 200 kPa, undrained | 5 % DA strain | 2 | 0.2 | 0.3 | {0.2 * 15 ** -0.3:.4g} (extrapolated) | "):
    if not any(x.startswith(w) for x in lines2):
        fails.append(f"no report row starting {w!r} in\n{text2}")
if "| mu_r | conditions | criterion |" not in text2 or "per mu_r, p0, drainage and criterion" not in text2:
    fails.append("the fit table names no conditions")
if "mu_r 0, p'_0 100 kPa, drained, 5 % DA strain (1 test)" not in text2:
    fails.append("the drained test is not a group of its own")
crr2 = 0.2 * 15 ** -0.3
k_sigma = crr2 / crr_da
c2 = (1 - k_sigma) / math.log(2)
f2 = 1 - c2 * math.log(1.01325)
w = (f"| 0 | undrained | 5 % DA strain | 100, 200 | {crr_da:.4g}, {crr2:.4g} | 1.000, {k_sigma:.3f} | "
     f"{c2:.3f} | {crr_da * f2:.4g} | {c2 / f2:.3f} |")
if w not in lines2:
    fails.append(f"no overburden row {w!r} in\n{text2}")
if "Overburden" in text:
    fails.append("an overburden table for tests at one pressure")
rows, c_sigma = grainlab_plot.overburden_factor([(2e5, 0.10), (1e5, 0.12), (4e5, 0.08)])
if [p for p, _, _ in rows] != [1e5, 2e5, 4e5] or \
        any(abs(k - v) > 1e-12 for (_, _, k), v in zip(rows, (1, 5 / 6, 2 / 3))) or \
        abs(c_sigma - (5 / 6) / (5 * math.log(2))) > 1e-12:
    fails.append(f"overburden_factor {rows} C_sigma {c_sigma}, wanted K 1, 5/6, 2/3 and {(5 / 6) / (5 * math.log(2))}")
crr_atm, c_atm, extrapolated = grainlab_plot.at_one_atmosphere(rows, c_sigma)
if abs(crr_atm - 0.12 * (1 - c_sigma * math.log(1.01325))) > 1e-12 or extrapolated:
    fails.append(f"at_one_atmosphere: CRR {crr_atm} (extrapolated {extrapolated})")
for p, _, _ in rows:  # the same line, referred to p_a
    line_ref = 1 - c_sigma * math.log(p / 1e5)
    if abs(line_ref * 0.12 / crr_atm - (1 - c_atm * math.log(p / 101.325e3))) > 1e-12:
        fails.append(f"at_one_atmosphere: C' {c_atm} does not give the line at {p}")
if not grainlab_plot.at_one_atmosphere([(2e5, 0.1, 1.0), (4e5, 0.08, 0.8)], 0.3)[2]:
    fails.append("at_one_atmosphere: p_a below the tests is not extrapolated")
print(text)
print(f"CRR at 15 cycles: DA {crr_da:.4f}, r_u {crr_ru:.4f}; N at DA {[round(da_law(c), 3) for c in (0.1, 0.15, 0.2, 0.3)]}")
if fails:
    sys.exit("liquefaction_fit_check: " + "; ".join(fails))
print("liquefaction_fit_check: ok")
