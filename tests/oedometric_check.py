#!/usr/bin/env python3
"""Known-answer test of the study report's oedometric (K0) section (grainlab_plot.py oedometric_section) and of
grainlab plot's figure of it, on synthetic K0 tests whose wall stresses lie on known lines.
- Seed 1, stage `load` (stage_type 5, eps_a 0 -> 2 %): sigma_v = 100 kPa + 20 MPa eps_a, sigma_h = 100 kPa + 0.45
  (sigma_v - 100 kPa) (sigma_x = sigma_h + 1 kPa, sigma_y = sigma_h - 1 kPa: their mean is sigma_h). Row: sigma_v
  100.0 -> 500.0, K0 at the end 280 / 500 = 0.560, tangent K0 0.450, M 20.0 MPa.
  Stage `unload` (eps_a 0 -> -0.5 %): sigma_v = 500 kPa + 40 MPa eps_a, sigma_h = 280 kPa + 0.2 (sigma_v - 500 kPa):
  unloading, 500.0 -> 300.0, K0 240 / 300 = 0.800, tangent 0.200, M 40.0 MPa.
- Seed 2, the same test with a loading slope of 0.55: K0 320 / 500 = 0.640 at the end of loading; unloading from
  320 kPa, K0 280 / 300 = 0.933. Both seeds together: each stage's K0, tangent and M as mean ± sd [95 %, t = 12.706],
  worked out here.
- A study of only these tests: no peak or critical-state tables (an oedometric test has neither), the K0 section, and
  figures/oedometric.png. The lines are exact, so the printed strings must match."""
import csv
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from synthetic_study import SCRIPT, study_report  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/oedometric_check"
shutil.rmtree(work, ignore_errors=True)
cols = ["time", "step", "eps_a", "p", "q", "q_p", "e", "mu_r", "stage_type", "sigma_x", "sigma_y", "sigma_z",
        "inertial_number"]


def k0_test(seed, k_load):
    """A K0 test's job directory (series on the lines above, loading slope k_load) and its study.json entry."""
    name = f"shear_oedometric_s{seed}_n300"
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "load", "type": "triaxial", "drainage": "oedometric", "b": 0},
                              {"name": "unload", "type": "triaxial", "drainage": "oedometric", "b": 0}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        rows = [("load", 0.001 * i, 1e5 + 2e7 * 0.001 * i) for i in range(21)]
        rows += [("unload", -0.0005 * i, 5e5 - 4e7 * 0.0005 * i) for i in range(11)]
        sh_top = 1e5 + k_load * 4e5
        for step, (stage, ea, sv) in enumerate(rows):
            sh = 1e5 + k_load * (sv - 1e5) if stage == "load" else sh_top + 0.2 * (sv - 5e5)
            p, q = (sv + 2 * sh) / 3, sv - sh
            w.writerow([stage, step, step, ea, p, q, q / p, 0.7 - ea, 0, 5, sh + 1e3, sh - 1e3, sv, 1e-4])
    return run, {"name": name, "dir": f"jobs/{name}/run", "sample": f"sample_s{seed}_n300", "mu_r": 0, "e0": 0,
                 "p0": 0, "drainage": "oedometric", "direction": "compression", "b": 0, "seed": seed, "count": 300,
                 "csr": 0, "cycles": 0, "strain_amplitude": 0, "axial_strain_rate": 0, "rate_group": ""}


run, job1 = k0_test(1, 0.45)
_, job2 = k0_test(2, 0.55)
text = study_report(work, [job1, job2])
fails = []
sec = text.split("## Oedometric (K0) tests")[1].split("\n## ")[0] if "## Oedometric (K0) tests" in text else ""


def spread(a, b, digits):
    m, sd = (a + b) / 2, abs(a - b) / math.sqrt(2)
    return f"{m:.{digits}f} ± {sd:.{digits}f} [{12.706 * sd / math.sqrt(2):.{digits}f}]"


want = ["| shear_oedometric_s1_n300 | 0 | load | loading | 100.0 → 500.0 | 0.560 | 0.450 | 20.0 | 0.6800 |",
        "| shear_oedometric_s1_n300 | 0 | unload | unloading | 500.0 → 300.0 | 0.800 | 0.200 | 40.0 | 0.7050 |",
        "| shear_oedometric_s2_n300 | 0 | load | loading | 100.0 → 500.0 | 0.640 | 0.550 | 20.0 | 0.6800 |",
        "| shear_oedometric_s2_n300 | 0 | unload | unloading | 500.0 → 300.0 | 0.933 | 0.200 | 40.0 | 0.7050 |",
        f"| shear_oedometric_s*_n300 | load | 2 (1, 2) | {spread(0.56, 0.64, 3)} | {spread(0.45, 0.55, 3)} | "
        f"{spread(20, 20, 1)} |",
        f"| shear_oedometric_s*_n300 | unload | 2 (1, 2) | {spread(0.8, 280 / 300, 3)} | {spread(0.2, 0.2, 3)} | "
        f"{spread(40, 40, 1)} |"]
rows = [line for line in sec.splitlines() if line.startswith("| shear_")]
if rows != want:
    fails.append("rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
if "## Peak states" in text or "## Critical states" in text:
    fails.append("an oedometric-only study has peak or critical-state tables")
if not os.path.isfile(os.path.join(work, "figures", "oedometric.png")):
    fails.append("no figures/oedometric.png")
# grainlab plot's figure of it (fig_oedometric, which `plot` calls with its other figures, whose columns this series
# lacks), and none for a run without an oedometric stage
sys.path.insert(0, os.path.dirname(SCRIPT))
import grainlab_plot  # noqa: E402
figs = os.path.join(work, "plot")
os.makedirs(figs)
s = grainlab_plot.load(run)
grainlab_plot.fig_oedometric([(run, s)], figs)
if not os.path.isfile(os.path.join(figs, "oedometric.png")):
    fails.append("fig_oedometric drew nothing")
s["oedometric"][:] = False
os.remove(os.path.join(figs, "oedometric.png"))
grainlab_plot.fig_oedometric([(run, s)], figs)
if os.path.isfile(os.path.join(figs, "oedometric.png")):
    fails.append("fig_oedometric drew a run without an oedometric stage")
if fails:
    sys.exit("\n".join(fails))
print("oedometric ok")
