#!/usr/bin/env python3
"""Known-answer test of the study report's samples section (grainlab_plot.py samples_section): synthetic sample jobs
whose summary.json give e, e_inner and e_core at the end of consolidation, and whose config.yaml gives the count.
- 5 000 spheres, core - interior = +0.0300: graded; 12 000, +0.0151: graded (just above GRADED_CORE = 0.015);
  10 000, +0.0149: homogeneous (just below); 2 000, +0.0500: too few spheres to tell; 5 000 of a build before
  e_inner / e_core (null): '-'. Rows ordered by size; the note counts 2 of 5 graded and names `affine: true`. Each
  row's D50 (mm) and Cu are its summary's `sample` (d50 0.7 mm + 0.01 mm a row, cu 1.5); '-' for a build before it
  (s_e, which has none).
- A study whose samples are all homogeneous has the section but no note.
- A sample whose isotropic stage ran out of steps (summary.json done: false) is marked NOT converged in its row, naming
  the stage, and counted in the note; in a preparation study's Preparation row too, beside its seeds' mean steps
  ("(1 of 2 NOT converged)"), and named below the table. A sample of a build without `done` is not marked. One whose
  earlier isotropic stage ran out of steps and whose last converged (a seat, then a consolidation) ends in equilibrium:
  marked apart ("seat ran out of steps, later stages converged"; "(1 of 3: an earlier stage ran out of steps)"), and
  one whose last stage ran out after a converged one is NOT converged."""
import json
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from synthetic_study import study_report  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/samples_check"
fails = []


def make(root, samples, prep=False):
    """Sample jobs (name, count, e, e_inner, e_core[, done]) and a drained shear of each; with prep, the samples alone
    (a preparation study: the seeds 1, 2, ... of one sample)."""
    shutil.rmtree(root, ignore_errors=True)
    jobs, listed = [], []
    for name, count, e, e_in, e_core, *done in samples:
        d = os.path.join(root, "jobs", name, "run")
        os.makedirs(d)
        with open(os.path.join(d, "config.yaml"), "w") as f:
            f.write(f"sample:\n  count: {count}\n  D: 3.63\n  seed: 11\nmaterial:\n  E: 1.0e+08\n")
        stage = {"name": "consolidate", "type": "isotropic", "done": done[0] if done else True, "steps": 100, "mu": 0.5,
                 "p": 1e5, "q": 0, "e": e, "e_inner": e_in, "e_core": e_core}
        if done and done[0] is None:
            del stage["done"]
        stages = [stage]
        if done and isinstance(done[0], tuple):  # (seat's done, consolidate's done): two isotropic stages
            stages = [dict(stage, name="seat", done=done[0][0], p=5e4, e=e + 0.01), dict(stage, done=done[0][1])]
        summary = {"config": "x", "stages": stages}
        if e_in is not None:
            summary["sample"] = {"spheres": count, "d50": 0.7e-3 + 1e-5 * len(jobs), "cu": 1.5}
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump(summary, f)
        jobs.append({"name": "shear_" + name, "dir": f"jobs/shear_{name}/run", "sample": name, "mu_r": 0, "e0": 0,
                     "p0": 1e5, "drainage": "drained"})
        listed.append({"name": name, "dir": f"jobs/{name}/run", "mu_r": 0, "e0": 0, "p0": 1e5, "seed": len(listed) + 1,
                       "count": count, "grading": "", "cu": 0, "E": 0})
        if prep:
            open(os.path.join(root, "jobs", name, "done"), "w").close()
    return study_report(root, [], samples=listed) if prep else study_report(root, jobs)


text = make(os.path.join(work, "mixed"), [
    ("s_a", 5000, 0.70, 0.6500, 0.6800), ("s_b", 12000, 0.69, 0.6400, 0.6551), ("s_c", 10000, 0.69, 0.6400, 0.6549),
    ("s_d", 2000, 0.72, 0.6500, 0.7000), ("s_e", 5000, 0.70, None, None, None), ("s_f", 5000, 0.70, 0.6300, 0.6400, False),
    ("s_g", 5000, 0.70, 0.6300, 0.6400, (False, True)), ("s_h", 5000, 0.70, 0.6300, 0.6400, (True, False))])
sec = text.split("## Samples")[1].split("\n## ")[0] if "## Samples" in text else ""
rows = [l for l in sec.splitlines() if l.startswith("| s_")]
want = ["| s_d | 2000 | 0.730 | 1.50 | 0.7200 | 0.6500 | 0.7000 | +0.0500 | too few spheres to tell (< 5000) |",
        "| s_a | 5000 | 0.700 | 1.50 | 0.7000 | 0.6500 | 0.6800 | +0.0300 | graded |",
        "| s_e | 5000 | - | - | 0.7000 | - | - | - | - |",
        "| s_f | 5000 | 0.750 | 1.50 | 0.7000 | 0.6300 | 0.6400 | +0.0100 | NOT converged (consolidate: max_steps); "
        "homogeneous |",
        "| s_g | 5000 | 0.760 | 1.50 | 0.7000 | 0.6300 | 0.6400 | +0.0100 | seat ran out of steps, later stages converged; "
        "homogeneous |",
        "| s_h | 5000 | 0.770 | 1.50 | 0.7000 | 0.6300 | 0.6400 | +0.0100 | NOT converged (consolidate: max_steps); "
        "homogeneous |",
        "| s_c | 10000 | 0.720 | 1.50 | 0.6900 | 0.6400 | 0.6549 | +0.0149 | homogeneous |",
        "| s_b | 12000 | 0.710 | 1.50 | 0.6900 | 0.6400 | 0.6551 | +0.0151 | graded |"]
if rows != want:
    fails.append("rows:\n" + "\n".join(rows) + "\nwanted:\n" + "\n".join(want))
if "2 of 8 samples are graded" not in sec or "`affine: true`" not in sec or "2 of 8 samples ran out of steps: " not in sec \
        or "1 of 8 samples ran out of steps in an earlier isotropic stage" not in sec:
    fails.append("the note does not count 2 of 8 graded samples, name affine, count 2 unconverged at their end and 1 "
                 "in an earlier stage: " + sec)
# a preparation study: seeds 1 and 2 of one sample (s_1 ran out of steps, s_2 converged)
text = make(os.path.join(work, "prep"), [("sample_x_s1_n5000", 5000, 0.70, 0.6300, 0.6400, False),
                                         ("sample_x_s2_n5000", 5000, 0.70, 0.6300, 0.6400, True),
                                         ("sample_x_s3_n5000", 5000, 0.70, 0.6300, 0.6400, (False, True))], prep=True)
sec = text.split("## Preparation")[1].split("\n## ")[0] if "## Preparation" in text else ""
row = [l for l in sec.splitlines() if l.startswith("| sample_x_s*_n5000 |")]
if len(row) != 1 or "| 100 (1 of 3 NOT converged) (1 of 3: an earlier stage ran out of steps) |" not in row[0] or \
        "1 sample(s) ran out of steps: " not in sec or ": sample_x_s1_n5000.\n" not in sec or \
        "1 sample(s) ran out of steps in an earlier isotropic stage" not in sec or \
        not sec.rstrip().endswith(": sample_x_s3_n5000."):
    fails.append("unconverged samples of a preparation study: " + sec)
text = make(os.path.join(work, "homogeneous"), [("s_a", 5000, 0.70, 0.6300, 0.6400)])
sec = text.split("## Samples")[1].split("\n## ")[0] if "## Samples" in text else ""
if "| s_a | 5000 | 0.700 | 1.50 | 0.7000 | 0.6300 | 0.6400 | +0.0100 | homogeneous |" not in sec or "graded:" in sec:
    fails.append("a homogeneous study: " + sec)
if fails:
    sys.exit("\n".join(fails))
print("samples ok")
