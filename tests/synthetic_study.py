"""The study report of a synthetic study: shared by the report's known-answer tests (failure_criteria_check.py,
rate_check.py), which write their jobs' series by hand."""
import csv
import json
import os
import subprocess
import sys

# The series columns of a synthetic drained or undrained shear with its volume (eps_v) and grain friction (mu): what
# the report's peak, critical-state, dilatancy and state-parameter sections read (dilatancy_check.py,
# state_parameter_check.py)
SHEAR_COLUMNS = ["time", "step", "eps_a", "eps_v", "p", "q", "q_p", "e", "mu", "mu_r", "stage_type", "a_c", "a_d", "a_n",
                 "a_t", "sff_share_c", "sff_share_d", "sff_share_n", "sff_share_t", "sff", "inertial_number", "sigma_x",
                 "sigma_y", "sigma_z"]



def shear_row(i, ea, ev, p, q, e, mu_r, drainage, **extra):
    """Row i of a synthetic axisymmetric compression's (or extension's: ea, q < 0) series (SHEAR_COLUMNS, and any
    extra columns given): strains, the walls' p' and q [Pa] (sigma_x = sigma_y = p - q/3, sigma_z = p + 2q/3), e, the
    contacts' q/p' = |q|/p' (SPEC §7's sqrt(3/2 s:s) / p', >= 0), fixed fabric and shares, a quasi-static inertial
    number."""
    return dict(time=i, step=i, eps_a=ea, eps_v=ev, p=p, q=q, q_p=abs(q) / p, e=e, mu=0.5, mu_r=mu_r,
                stage_type=2 if drainage == "drained" else 1, a_c=0.1, a_d=0.05, a_n=0.1, a_t=0.02, sff_share_c=0.25,
                sff_share_d=0.25, sff_share_n=0.25, sff_share_t=0.25, sff=abs(q) / p, inertial_number=5e-4,
                sigma_x=p - q / 3, sigma_y=p - q / 3, sigma_z=p + 2 * q / 3, **extra)


def write_compression(work, name, p0, drainage, rows, cols, mu_r, keys=None, E=None, direction="compression"):
    """Writes work/jobs/<name> (done, run/summary.json: one compression (direction) shear stage from p'_0 = p0 [kPa],
    run/series.csv: rows, shear_row's, in columns cols) and returns its job for study.json (keys: its stage axes'
    values, 'stage.key' -> value; E: its contact stiffness axis's)."""
    run = os.path.join(work, "jobs", name, "run")
    os.makedirs(run)
    open(os.path.join(work, "jobs", name, "done"), "w").close()
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "shear", "type": "triaxial", "b": 0, "axial_strain_rate": 0.25,
                               "drainage": drainage, "direction": direction, "p_0": p0 * 1e3, "q_0": 0}]}, f)
    with open(os.path.join(run, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage"] + cols)
        for row in rows:
            w.writerow(["shear"] + [row[k] for k in cols])
    return {"name": name, "dir": f"jobs/{name}/run", "sample": "sample_x", "mu_r": mu_r, "e0": 0, "p0": p0 * 1e3,
            "drainage": drainage, "direction": direction, "b": 0, "seed": 1, "count": 300, "csr": 0, "cycles": 0,
            "strain_amplitude": 0, "axial_strain_rate": 0.25, "rate_group": "",
            **({"stage_keys": keys} if keys else {}), **({"E": E} if E else {})}


SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts", "grainlab_plot.py")


def study_report(work, jobs, **blocks):
    """Writes work/study.json (the jobs, the critical-state block of the shipped studies, and any further top-level
    blocks given, e.g. peak) and runs `grainlab_plot.py study` on it; returns report.md. Exits if the report fails."""
    with open(os.path.join(work, "study.json"), "w") as f:
        json.dump({"study": "synthetic", "strain_stage": "",
                   "critical_state": {"window": 0.05, "qp_tol": 0.05, "p_tol": 0.05, "e_tol": 0.005}, "jobs": jobs,
                   **blocks}, f)
    out = subprocess.run([sys.executable, SCRIPT, "study", work], capture_output=True, text=True)
    print(out.stdout, out.stderr)
    if out.returncode != 0:
        sys.exit("the study report failed")
    return open(os.path.join(work, "report.md")).read()
