#!/usr/bin/env python3
"""Known-answer test of the study report's stiffness section (scripts/grainlab_plot.py stiffness_section).

Synthetic drained triaxial tests with an unload-reload loop, their stages as a run writes them (series.csv rows by
stage name, each stage's eps_a and eps_v from its own start; summary.json's stages with q_0, p_0, E_sec):
- first loading q = E50 eps_a (a line: its secant at q_peak/2 is E50 itself, whatever rows bracket it) to 0.6 q_peak,
  an unloading to q = 0 with E_ur and nu_ur exactly (eps_v of the stage from eps_r = -nu_ur eps_a through
  (1 - eps_v) = (1 - eps_a)(1 - eps_r)^2), a reloading on to the peak at 2 % and softening after it;
- at p'_0 = 50, 100, 200 kPa with E50 = 30 MPa (p'_0 / 100 kPa)^0.5 and E_ur = 90 MPa (p'_0 / 100 kPa)^0.6 for mu_r =
  0.3: the fits must give E_ref 30.00 ± 0.00 and 90.00 ± 0.00 MPa, m 0.500 ± 0.000 and 0.600 ± 0.000;
- mu_r = 0: two tests, one whose loading turned at 0.4 q_peak (E50 '-', below half the peak) and one whose q still
  rose at the end ('(rising)') with two loops (the first's E_ur, the second's, 2/3 of it, as a further loop), no fit
  (too few tests);
- the damping's drag (series q_drag) +2 % of the turn's q while loading, -1 % unloading: E_ur less drag = 0.97 E_ur;
- an undrained test and a drained extension test are not in the section; summary.json without E_sec (a build before
  it) gives E_ur from the stage's last row.
- A study over the contact stiffness (jobs with E, the E axis): the three mu_r = 0.3 tests at E = 1e8 and, ten times
  stiffer, at 1e9 Pa: a section per E, each with its own tests, fits (30 and 90 MPa; 300 and 900 MPa: not pooled) and
  figures/E_<E>/stiffness.png.
The values are printed to 2-3 decimals and exact here, so the strings must match.
"""
import csv
import json
import math
import os
import shutil
import sys

from synthetic_study import study_report

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/stiffness_check"
shutil.rmtree(work, ignore_errors=True)
cols = ["time", "step", "eps_a", "eps_v", "p", "q", "q_p", "e", "mu_r", "stage_type", "a_c", "a_d", "a_n", "a_t",
        "sff_share_c", "sff_share_d", "sff_share_n", "sff_share_t", "sff", "inertial_number", "sigma_x", "sigma_y",
        "sigma_z", "q_drag"]
jobs = []


def eps_v_of(ea, nu):
    """A stage's eps_v where eps_r = -nu eps_a (the run's radial strain relation, inverted)."""
    return 1 - (1 - ea) * (1 + nu * ea) ** 2


def test(name, mu_r, p0, E50, E_ur, nu, turn=0.6, rising=False, loops=1, with_esec=True, drainage="drained",
         direction="compression", E=None, into=None):
    """Stages load (to turn q_peak), then `loops` x (unload to 0, reload: to turn q_peak again, the last to 8 %).
    into: (study directory, jobs list) to add it to (work's and jobs by default); E: the job's contact stiffness."""
    study_dir, job_list = into or (work, jobs)
    q_peak = 1.5 * p0
    run = os.path.join(study_dir, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(study_dir, "jobs", name, "done"), "w").close()
    rows, stages = [], []
    step = [0]

    def row(stage, st_type, ea, ev, q):
        p = p0 + q / 3
        # the damping's drag: +2 % of the turn's q while the walls load, -1 % while they unload (E_ur less drag 0.97 E_ur)
        drag = (-0.01 if stage.startswith("unload") else 0.02) * turn * q_peak
        rows.append([stage, step[0], step[0], ea, ev, p, q, q / p, 0.6, mu_r, st_type, 0.1, 0.05, 0.1, 0.02, 0.25, 0.25,
                     0.25, 0.25, q / p, 5e-4, p0, p0, p0 + q, drag])
        step[0] += 1

    st_type = 2 if drainage == "drained" else 1
    sign = -1 if direction == "extension" else 1
    # the first loading: q = E50 eps_a in rows of 0.05 %
    q_turn = turn * q_peak
    n = int(math.ceil(q_turn / E50 / 5e-4))
    for i in range(n + 1):
        ea = min(i * 5e-4, q_turn / E50)
        row("load", st_type, sign * ea, 0.0, sign * E50 * ea)
    stages.append({"name": "load", "type": "triaxial", "drainage": drainage, "direction": direction, "b": 0,
                   "p_0": p0, "q_0": 0, "q": sign * q_turn, "E_sec": E50})
    for k in range(loops):
        E_k = E_ur * (1 - k / 3)  # a second loop softer: 2/3 of the first's
        ea_end = -q_turn / E_k
        for i in range(11):
            ea = ea_end * i / 10
            row(f"unload{k}", 2, ea, eps_v_of(ea, nu), q_turn + E_k * ea)
        st = {"name": f"unload{k}", "type": "triaxial", "drainage": "drained", "direction": "extension", "b": 0,
              "p_0": p0 + q_turn / 3, "q_0": q_turn, "q": q_turn + E_k * ea_end}
        if with_esec:
            st["E_sec"] = (st["q"] - q_turn) / ea_end
        stages.append(st)
        last = k == loops - 1
        # the reloading: stiff back to the turn, then on to q_peak at 2 %, softening to 0.8 q_peak at 8 % (or still
        # rising to q_peak at 8 %)
        for i in range(161):
            ea = i * 5e-4
            if not last:
                q = min(q_turn, E_ur * ea)
            elif rising:
                q = min(E_ur * ea, q_turn + (q_peak - q_turn) * ea / 0.08)
            else:
                q = min(E_ur * ea, q_turn + (q_peak - q_turn) * ea / 0.02) if ea <= 0.02 else \
                    q_peak * (1 - 0.2 * (ea - 0.02) / 0.06)
            row(f"reload{k}", 2, ea, 0.0, q)
            if not last and q >= q_turn:
                break
        stages.append({"name": f"reload{k}", "type": "triaxial", "drainage": "drained", "direction": "compression",
                       "b": 0, "p_0": p0, "q_0": st["q"], "q": rows[-1][6]})
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "consolidate", "type": "isotropic"}] + stages}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        w.writerows(rows)
    job_list.append({"name": name, "dir": f"jobs/{name}/run", "sample": "sample_x", "mu_r": mu_r, "e0": 0, "p0": p0,
                     "drainage": drainage, "direction": direction, "b": 0, "seed": 1, "count": 300, "csr": 0,
                     "cycles": 0, "strain_amplitude": 0, "axial_strain_rate": 0, "rate_group": "",
                     **({"E": E} if E else {})})


def law(E_ref, m, p0):
    return E_ref * (p0 / 1e5) ** m


for p0 in (50e3, 100e3, 200e3):
    test(f"ur_p{p0 / 1e3:g}", 0.3, p0, law(30e6, 0.5, p0), law(90e6, 0.6, p0), 0.2, with_esec=p0 != 100e3)
test("ur_low", 0.0, 100e3, 30e6, 90e6, 0.25, turn=0.4)
test("ur_rising", 0.0, 100e3, 30e6, 90e6, 0.25, rising=True, loops=2)
test("undrained", 0.3, 100e3, 30e6, 90e6, 0.2, drainage="undrained")
test("extension", 0.3, 100e3, 30e6, 90e6, 0.2, direction="extension")

fails = []
text = study_report(work, jobs)
if "## Stiffness (drained triaxial)" not in text:
    sys.exit("no stiffness section in report.md")
sec = text.split("## Stiffness (drained triaxial)")[1].split("\n## ")[0]
want = []
for p0 in (50e3, 100e3, 200e3):
    E50, Eur = law(30e6, 0.5, p0), law(90e6, 0.6, p0)
    want.append(f"| ur_p{p0 / 1e3:g} | 0.3 | {p0 / 1e3:.1f} | {1.5 * p0 / 1e3:.1f} | {E50 / 1e6:.2f} | {Eur / 1e6:.2f} "
                f"({0.9 * p0 / 1e3:.0f} → 0) | {0.97 * Eur / 1e6:.2f} | 0.200 | {Eur / E50:.2f} | - |")
want.append("| ur_low | 0 | 100.0 | 150.0 | - | 90.00 (60 → 0) | 87.30 | 0.250 | - | - |")
want.append("| ur_rising | 0 | 100.0 | 150.0 (rising) | 30.00 | 90.00 (90 → 0) | 87.30 | 0.250 | 3.00 | 60.00 (90 → 0) |")
for line in want:
    if line not in sec.splitlines():
        got = next((x for x in sec.splitlines() if x.startswith(line.split(" | ")[0] + " |")), None)
        fails.append(f"expected\n  {line}\ngot\n  {got}")
for name in ("undrained", "extension"):
    if f"| {name} |" in sec:
        fails.append(f"{name} is in the stiffness section")
for line in ("| 0.3 | E50 | 3 | 30.00 ± 0.00 | 0.500 ± 0.000 | 50–200 |",
             "| 0.3 | E_ur | 3 | 90.00 ± 0.00 | 0.600 ± 0.000 | 50–200 |",
             "| 0 | E50 | 1 | not fitted: needs 3 tests at 2 pressures or more | | |",
             "| 0 | E_ur | 2 | not fitted: needs 3 tests at 2 pressures or more | | |"):
    if line not in sec.splitlines():
        fails.append(f"fit row missing: {line}\n{sec}")
if not os.path.isfile(os.path.join(work, "figures", "stiffness.png")):
    fails.append("figures/stiffness.png missing")

# The E axis: a section per contact stiffness, its fits its own
work_e, jobs_e = work + "_E", []
shutil.rmtree(work_e, ignore_errors=True)
for E, f in ((1e8, 1), (1e9, 10)):
    for p0 in (50e3, 100e3, 200e3):
        test(f"ur_p{p0 / 1e3:g}_E{E:g}".replace("e+0", "e"), 0.3, p0, f * law(30e6, 0.5, p0), f * law(90e6, 0.6, p0),
             0.2, E=E, into=(work_e, jobs_e))
text_e = study_report(work_e, jobs_e)
for E, name, f in ((1e8, "1e8", 1), (1e9, "1e9", 10)):
    head = f"## Contact stiffness E = {E:g} Pa"
    if head not in text_e:
        fails.append(f"no section '{head}'")
        continue
    part = text_e.split(head)[1].split("\n## Contact stiffness")[0]
    st = part.split("### Stiffness (drained triaxial)")[1].split("\n### ")[0] if "### Stiffness" in part else ""
    tests = [x.split(" | ")[0][2:] for x in st.splitlines() if x.startswith("| ur_")]
    if tests != [f"ur_p{p:g}_E{name}" for p in (50, 100, 200)]:
        fails.append(f"E = {E:g}: the stiffness rows are {tests}")
    for line in (f"| 0.3 | E50 | 3 | {30 * f:.2f} ± 0.00 | 0.500 ± 0.000 | 50–200 |",
                 f"| 0.3 | E_ur | 3 | {90 * f:.2f} ± 0.00 | 0.600 ± 0.000 | 50–200 |"):
        if line not in st.splitlines():
            fails.append(f"E = {E:g}: fit row missing: {line}")
    if not os.path.isfile(os.path.join(work_e, "figures", f"E_{name}", "stiffness.png")):
        fails.append(f"figures/E_{name}/stiffness.png missing")
    if f"`figures/E_{name}/stiffness.png`" not in st:
        fails.append(f"E = {E:g}: the section does not name figures/E_{name}/stiffness.png")
if fails:
    sys.exit("\n".join(fails))
print("stiffness section: E50, E_ur, nu_ur and the power laws as built")
