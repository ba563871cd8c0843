#!/usr/bin/env python3
"""Known-answer test of the study report's oedometric (K0) section (grainlab_plot.py oedometric_section) and of
grainlab plot's figure of it, on synthetic K0 tests whose wall stresses lie on known lines.
- Seed 1, stage `load` (stage_type 5, eps_a 0 -> 2 %): sigma_v = 100 kPa + 20 MPa eps_a, sigma_h = 100 kPa + 0.45
  (sigma_v - 100 kPa) (sigma_x = sigma_h + 1 kPa, sigma_y = sigma_h - 1 kPa: their mean is sigma_h). Row: sigma_v
  100.0 -> 500.0, K0 at the end 280 / 500 = 0.560, tangent K0 0.450, M 20.0 MPa.
  Stage `unload` (eps_a 0 -> -0.5 %): sigma_v = 500 kPa + 40 MPa eps_a, sigma_h = 280 kPa + 0.2 (sigma_v - 500 kPa):
  unloading, 500.0 -> 300.0, K0 240 / 300 = 0.800, tangent 0.200, M 40.0 MPa. The void ratio lies on straight lines
  in e - log10 sigma_v through e = 0.665 at 500 kPa: Cc = 0.05 on loading (e 0.6650 at its end), Cs = 0.01 on
  unloading (e 0.6672 at its end).
- Seed 2, the same test with a loading slope of 0.55: K0 320 / 500 = 0.640 at the end of loading; unloading from
  320 kPa, K0 280 / 300 = 0.933. Both seeds together: each stage's K0, tangent and M as mean ± sd [95 %, t = 12.706],
  worked out here.
- A study of only these tests: no peak or critical-state tables (an oedometric test has neither), the K0 section, and
  figures/oedometric.png (its curves named by the job, not by the run directory "run"). The lines are exact, so the printed strings must match.
- Against Jaky (jaky_rows), a second study: the seed-1 K0 test beside a drained compression of its sample whose
  stress ratio peaks at M = 0.75 (10 %) and is steady at 0.60 from 30 % to 40 % (a critical state): phi'_max =
  asin(3 x 0.75 / 6.75) = 19.47°, 1 - sin = 0.667; phi'_cs = asin(1.8 / 6.6) = 15.83°, 1 - sin = 0.727; the tangent
  K0 0.450 needs phi' = asin(0.55) = 33.4° and mobilises asin(0.55 / 1.45) = 22.3°. A drained compression of another
  sample, a drained extension and an undrained compression of the same sample are left out of the comparison.
- What carries the stress ratio: each stage's last row's a_c, a_d, a_n, a_t (a_n rising over the loading, falling over
  the unloading: anisotropies()), its q/p' and the stress-force-fabric sum, per test and stage.
- Against Mayne & Kulhawy (unloading_rows): each unloading stage's OCR 500 / 300 = 1.67, K0,nc (the loading's end) and
  K0 at its end give alpha = ln(K0 / K0,nc) / ln OCR (0.70 and 0.74), with '-' for the angles in the first study and
  sin phi'_max = 0.333, sin phi'_cs = 0.273 of the same drained compression in the second."""
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
        "inertial_number", "a_c", "a_d", "a_n", "a_t", "sff"]
CC, CS, E_TOP = 0.05, 0.01, 0.665  # the e - log10 sigma_v lines: Cc on loading, Cs on unloading, e at 500 kPa


def anisotropies(stage, ea):
    """a_c, a_d, a_n, a_t of a row: a_n climbs 0 -> 0.8 over the loading (40 eps_a) and falls back to 0.3 over the
    unloading (0.8 + 100 eps_a); the others constant per stage."""
    return (0.2, 0.01, 40 * ea, 0.2) if stage == "load" else (0.1, 0.01, 0.8 + 100 * ea, 0.0)


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
            e = E_TOP + (CC if stage == "load" else CS) * math.log10(5e5 / sv)  # straight in e - log10 sigma_v
            a = anisotropies(stage, ea)
            w.writerow([stage, step, step, ea, p, q, q / p, e, 0, 5, sh + 1e3, sh - 1e3, sv, 1e-4, *a,
                        0.4 * (a[0] + a[1] + a[2] + 1.5 * a[3])])
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


e_end = f"{E_TOP + CS * math.log10(5 / 3):.4f}"  # 0.6672
want = ["| shear_oedometric_s1_n300 | 0 | load | loading | 100.0 → 500.0 | 0.560 | 0.450 | 20.0 | 0.0500 | 0.6650 |",
        f"| shear_oedometric_s1_n300 | 0 | unload | unloading | 500.0 → 300.0 | 0.800 | 0.200 | 40.0 | 0.0100 | {e_end} |",
        "| shear_oedometric_s2_n300 | 0 | load | loading | 100.0 → 500.0 | 0.640 | 0.550 | 20.0 | 0.0500 | 0.6650 |",
        f"| shear_oedometric_s2_n300 | 0 | unload | unloading | 500.0 → 300.0 | 0.933 | 0.200 | 40.0 | 0.0100 | {e_end} |",
        f"| shear_oedometric_s*_n300 | load | 2 (1, 2) | {spread(0.56, 0.64, 3)} | {spread(0.45, 0.55, 3)} | "
        f"{spread(20, 20, 1)} | {spread(CC, CC, 4)} |",
        f"| shear_oedometric_s*_n300 | unload | 2 (1, 2) | {spread(0.8, 280 / 300, 3)} | {spread(0.2, 0.2, 3)} | "
        f"{spread(40, 40, 1)} | {spread(CS, CS, 4)} |"]
# Against Mayne & Kulhawy (unloading_rows): unloaded from sigma_v,max = 500 to 300 kPa, OCR 5/3, from K0,nc = 280 / 500
# (seed 1) and 320 / 500 (seed 2) to 240 / 300 and 280 / 300; no drained test in this study.
for seed, k_nc, k_end in ((1, 0.56, 0.8), (2, 0.64, 280 / 300)):
    want.append(f"| shear_oedometric_s{seed}_n300 | unload | 1.67 | {k_nc:.3f} | {k_end:.3f} | "
                f"{math.log(k_end / k_nc) / math.log(5 / 3):.2f} | - | - | - |")
rows = [line for line in sec.splitlines() if line.startswith("| shear_") and "| 0.200 | 0.010 |" not in line
        and "| 0.100 | 0.010 |" not in line]
if rows != want:
    fails.append("rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
# What carries the stress ratio, each stage's last row: load (eps_a 2 %) a_n 0.8, unload (-0.5 %) a_n 0.3; the
# walls' q/p' there (sigma_h 280 / 320 kPa at sigma_v 500, then 240 / 280 at 300)
want = []
for seed, sh_load, sh_unload in ((1, 2.8e5, 2.4e5), (2, 3.2e5, 2.8e5)):
    for stage, ea, sv, sh in (("load", 0.02, 5e5, sh_load), ("unload", -0.005, 3e5, sh_unload)):
        a = anisotropies(stage, ea)
        qp = (sv - sh) / ((sv + 2 * sh) / 3)
        want.append(f"| shear_oedometric_s{seed}_n300 | {stage} | " + " | ".join(
            f"{v:.3f}" for v in (*a, qp, 0.4 * (a[0] + a[1] + a[2] + 1.5 * a[3]))) + " |")
rows = [line for line in sec.splitlines() if line.startswith("| shear_") and ("| 0.200 | 0.010 |" in line
        or "| 0.100 | 0.010 |" in line)]
if rows != want:
    fails.append("fabric rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
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
# A study job's curves are named by the job (jobs/<job>/run), not by its run directory, which is "run" for all
if grainlab_plot.label(run, s) != "shear_oedometric_s1_n300 (mu_r=0)":
    fails.append(f"label of a study job's run: {grainlab_plot.label(run, s)!r}")
# The study figures' legend: base p'_0 and e_0 (0 in study.json) left out, a job's own shown, the seed on request;
# a compression test that ends unloading (this one) is no extension
for job, seed, want_label in ((job1, False, "mu_r=0 oedometric"), (job1, True, "mu_r=0 oedometric seed 1"),
                              (dict(job1, p0=2e5, e0=0.65), False, "mu_r=0 oedometric p0=200k e0=0.65"),
                              (dict(job1, direction="extension"), False, "mu_r=0 oedometric extension")):
    if grainlab_plot.job_label(job, s, seed) != want_label:
        fails.append(f"job_label: {grainlab_plot.job_label(job, s, seed)!r}, wanted {want_label!r}")
# The run's strain figures draw the two stages on one axis of axial strain from the loading's start: the unloading's
# eps_a (from its own start, its H0) composed with the loading's, 1 - (1 - 0.02)(1 + 0.005) = 1.51 % at the end; the
# loading's rows as they are (they drew the unloading back over them from 0, joined by a line back across)
ea, run_ea, st = s["eps_a"], s["eps_a_run"], s["stage"]
load_rows, unload_rows = st == "load", st == "unload"
if not (load_rows.any() and unload_rows.any()) or list(run_ea[load_rows]) != list(ea[load_rows]):
    fails.append(f"eps_a_run of the loading: {run_ea[load_rows]}")
elif abs(run_ea[unload_rows][-1] - (1 - 0.98 * 1.005)) > 1e-12 or abs(run_ea[unload_rows][0] - 0.02) > 1e-12:
    fails.append(f"eps_a_run of the unloading: {run_ea[unload_rows][0]} .. {run_ea[unload_rows][-1]}, wanted 0.02 .. "
                 f"{1 - 0.98 * 1.005}")
grainlab_plot.fig_oedometric([(run, s)], figs)
if not os.path.isfile(os.path.join(figs, "oedometric.png")):
    fails.append("fig_oedometric drew nothing")
s["oedometric"][:] = False
os.remove(os.path.join(figs, "oedometric.png"))
grainlab_plot.fig_oedometric([(run, s)], figs)
if os.path.isfile(os.path.join(figs, "oedometric.png")):
    fails.append("fig_oedometric drew a run without an oedometric stage")

# Against Jaky: the seed-1 K0 test beside drained and other shears (rate_check's columns, a synthetic path)
work = work + "_jaky"
shutil.rmtree(work, ignore_errors=True)
_, k0 = k0_test(1, 0.45)
shear_cols = ["time", "step", "eps_a", "p", "q", "q_p", "e", "mu_r", "stage_type", "a_c", "a_d", "a_n", "a_t",
              "sff_share_c", "sff_share_d", "sff_share_n", "sff_share_t", "sff", "inertial_number", "sigma_x", "sigma_y",
              "sigma_z"]


def shear(name, sample, drainage, sign):
    """A triaxial shear to 40 % (sign -1: extension): q/p' up to 0.75 at 10 %, down to a steady 0.60 from 30 %."""
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + shear_cols)
        for i in range(41):
            ea = 0.01 * i
            qp = 0.75 * ea / 0.1 if ea <= 0.1 else 0.75 - 0.15 * min(1.0, (ea - 0.1) / 0.2)
            p, q = 1e5, sign * qp * 1e5
            w.writerow(["shear", i, i, sign * ea, p, q, qp, 0.7, 0, 2 if drainage == "drained" else 1, 0.1, 0.05, 0.1,
                        0.02, 0.25, 0.25, 0.25, 0.25, qp, 1e-4, p - q / 3, p - q / 3, p + 2 * q / 3])
    return {"name": name, "dir": f"jobs/{name}/run", "sample": sample, "mu_r": 0, "e0": 0, "p0": 0,
            "drainage": drainage, "direction": "compression" if sign > 0 else "extension", "b": 0, "seed": 1,
            "count": 300, "csr": 0, "cycles": 0, "strain_amplitude": 0, "axial_strain_rate": 0, "rate_group": "",
            "max_axial_strain": 0.4}


jobs = [k0, shear("shear_drained_s1_n300_to0.4", "sample_s1_n300", "drained", 1),
        shear("shear_drained_s9_n300_to0.4", "sample_s9_n300", "drained", 1),
        shear("shear_drained_s1_n300_ext", "sample_s1_n300", "drained", -1),
        shear("shear_undrained_s1_n300", "sample_s1_n300", "undrained", 1)]
text = study_report(work, jobs)
sec = text.split("## Oedometric (K0) tests")[1].split("\n## ")[0] if "## Oedometric (K0) tests" in text else ""
phi_max, phi_cs = math.degrees(math.asin(2.25 / 6.75)), math.degrees(math.asin(1.8 / 6.6))
want = [f"| shear_oedometric_s1_n300 | load | shear_drained_s1_n300_to0.4 | 0.560 | 0.450 | {phi_max:.1f} | "
        f"{1 - math.sin(math.radians(phi_max)):.3f} | {phi_cs:.1f} | {1 - math.sin(math.radians(phi_cs)):.3f} | "
        f"{math.degrees(math.asin(0.55)):.1f} | {math.degrees(math.asin(0.55 / 1.45)):.1f} |"]
rows = [line for line in sec.splitlines() if line.startswith("| shear_oedometric") and "| load | shear_" in line]
if rows != want:
    fails.append("Jaky rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
if "phi' for the tangent K0" not in sec:
    fails.append("no Jaky table header")
# The unloading stage beside the same drained compression: sin phi'_max = 2.25 / 6.75, sin phi'_cs = 1.8 / 6.6.
want = [f"| shear_oedometric_s1_n300 | unload | 1.67 | 0.560 | 0.800 | {math.log(0.8 / 0.56) / math.log(5 / 3):.2f} | "
        f"shear_drained_s1_n300_to0.4 | {2.25 / 6.75:.3f} | {1.8 / 6.6:.3f} |"]
rows = [line for line in sec.splitlines() if line.startswith("| shear_oedometric") and "| unload | 1.67 |" in line]
if rows != want:
    fails.append("Mayne-Kulhawy rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
if fails:
    sys.exit("\n".join(fails))
print("oedometric ok")
