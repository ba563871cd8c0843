"""The study report of a synthetic study: shared by the report's known-answer tests (failure_criteria_check.py,
rate_check.py), which write their jobs' series by hand."""
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
