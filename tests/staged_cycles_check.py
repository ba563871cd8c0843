#!/usr/bin/env python3
"""Known-answer test of grainlab plot's reading of a staged cyclic run (grainlab_plot.py load: cycle_run, p_c) on a
synthetic series.csv:
- stages consolidate (isotropic), cyc1 (cyclic undrained, N 0 -> 2), cyc2 (cyclic undrained, N 0 -> 1.5), post
  (triaxial undrained), cyc3 (cyclic drained, N 0 -> 1). Each stage's N counts from its own start (the run's series),
  so the cyclic figure drew cyc2 back over cyc1 from N = 0. cycle_run goes on from the N the cyclic stages before
  reached: cyc2 2 -> 3.5, cyc3 3.5 -> 4.5; the others' rows as they are.
- r_u's reference p_c: the p' at the first row of the undrained stages in a row (cyc1, cyc2, post: one run of them,
  100 kPa, the p' where the undrained loading began: the run keeps their pore pressure, Laboratory::start_stage);
  NaN in the isotropic and the drained stage. Against each stage's own first row (cyc2's 92 kPa) r_u of cyc2's last
  row would read 30/92, not 30/100.
- fig_cyclic draws the run (figures/cyclic.png).
- the study report's cyclic section (cyclic_section) has a row for each cyclic stage, each with its own summary.json
  entry (N, criteria, cycles, drainage) and its own p' and r_u from p_c: cyc2's min p'/p'_0 is 70/100 and max r_u
  30/100, not 70/92 nor cyc1's; cyc3 drained, from its first row. One row for the run (the last stage's criteria and
  N, every cyclic row's p' and r_u) was the report before: it lost the first stage's N, a virgin sample's.
- a run that reconsolidates after undrained cycles (consolidate, shake, recon: summary.json e 0.72 at shake's end,
  0.69 at recon's, p' 100 kPa): the section's reconsolidation table gives eps_v = 0.03/1.72 = 1.744 %, the cycles'
  max r_u 0.6 and max |eps_a| 3.00 %; the interior's from e_inner, series 0.66 at shake's last row (0.67 on the row
  before: not the stage's end) and summary.json 0.65 after recon, 0.01/1.66 = 0.602 %; "–" where the series has no
  e_inner (a build before it)."""
import csv
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import grainlab_plot  # noqa: E402

work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/staged_cycles_check"
shutil.rmtree(work, ignore_errors=True)
run = os.path.join(work, "staged")
os.makedirs(run)
# stage, stage_type, cycle, p [kPa], u [kPa]
ROWS = [("consolidate", 0, 0, 100, 0), ("consolidate", 0, 0, 100, 0),
        ("cyc1", 3, 0, 100, 0), ("cyc1", 3, 0.5, 95, 5), ("cyc1", 3, 1.0, 90, 10), ("cyc1", 3, 2.0, 92, 8),
        ("cyc2", 3, 0, 92, 8), ("cyc2", 3, 1.0, 80, 20), ("cyc2", 3, 1.5, 70, 30),
        ("post", 1, 0, 65, 35),
        ("cyc3", 4, 0, 65, 0), ("cyc3", 4, 1.0, 66, 0)]
with open(os.path.join(run, "series.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["stage", "time", "step", "eps_a", "p", "q", "u", "e", "mu_r", "stage_type", "cycle"])
    for k, (st, ty, n, p, u) in enumerate(ROWS):
        w.writerow([st, k * 1e-3, k, 1e-4 * k if ty else 0, p * 1e3, 0, u * 1e3, 0.7, 0, ty, n])

s = grainlab_plot.load(run)
fails = []
want_run = [0, 0, 0, 0.5, 1.0, 2.0, 2.0, 3.0, 3.5, 0, 3.5, 4.5]
if list(s["cycle_run"]) != want_run:
    fails.append(f"cycle_run {list(s['cycle_run'])}, wanted {want_run}")
want_pc = [math.nan] * 2 + [100e3] * 8 + [math.nan] * 2
got_pc = list(s["p_c"])
if any((math.isnan(a) != math.isnan(b)) or (not math.isnan(a) and a != b) for a, b in zip(got_pc, want_pc)):
    fails.append(f"p_c {got_pc}, wanted {want_pc}")
figs = os.path.join(work, "figs")
os.makedirs(figs)
grainlab_plot.fig_cyclic([(run, s)], figs)
if not os.path.isfile(os.path.join(figs, "cyclic.png")):
    fails.append("fig_cyclic drew nothing")


# The study report's cyclic section: the run's summary.json as the run writes it (only what the section reads)
def entry(name, drainage, cycles, cycle, n_ru, n_da, quarter):
    return {"name": name, "type": "cyclic", "drainage": drainage, "cycles": cycles, "cycle": cycle,
            "liquefaction_ru": 0.95, "n_ru": n_ru, "liquefaction_da_strain": 0.05, "n_da": n_da,
            "quarter_cycle_transits": quarter}


with open(os.path.join(run, "summary.json"), "w") as f:
    json.dump({"stages": [{"name": "consolidate", "type": "isotropic"},
                          entry("cyc1", "undrained", 2, 2.0, None, 0.75, 5.5),
                          entry("cyc2", "undrained", 3, 1.5, 1.25, 1.125, None),
                          {"name": "post", "type": "triaxial"},
                          entry("cyc3", "drained", 1, 1.0, None, None, 6.0)]}, f)
job = {"name": "staged", "mu_r": 0.0, "csr": 0.1, "drainage": "undrained", "cycles": 1}
lines = grainlab_plot.cyclic_section([(job, run, s)], figs, {0.0: "C0"})
want_rows = ["| staged (cyc1) | 0 | undrained | 0.1 | 2 | 2 cycles done | not met | 0.75 | 0.900 | 0.100 | 5.5 |",
             "| staged (cyc2) | 0 | undrained | 0.1 | 1.5 | \\|eps_a\\| = 0.08 % | 1.25 | 1.12 | 0.700 | 0.300 | – |",
             "| staged (cyc3) | 0 | drained | 0.1 | 1 | 1 cycles done | – (drained) | not met | 1.000 | – | 6 |"]
got_rows = [x for x in lines if x.startswith("| staged")]
if got_rows != want_rows:
    fails.append("cyclic_section rows\n" + "\n".join(got_rows) + "\nwanted\n" + "\n".join(want_rows))
if not any("A staged test has a row for each cyclic stage" in x for x in lines):
    fails.append("cyclic_section does not say a staged test has a row a stage")
if not os.path.isfile(os.path.join(figs, "liquefaction.png")):
    fails.append("cyclic_section drew no liquefaction.png")
# Without a csr axis (the job's csr 0) each row's CSR is its stage's summary.json csr (A / (2 p'_c), whichever of
# q_amplitude and csr the stage gave); a stage without one (strain reversal, an older build) has none
with open(os.path.join(run, "summary.json")) as f:
    summ = json.load(f)
for st, v in (("cyc1", 0.125), ("cyc2", 0.25)):
    next(x for x in summ["stages"] if x["name"] == st)["csr"] = v
with open(os.path.join(run, "summary.json"), "w") as f:
    json.dump(summ, f)
got = [x.split(" | ")[3] for x in grainlab_plot.cyclic_section([(dict(job, csr=0), run, s)], figs, {0.0: "C0"})
       if x.startswith("| staged")]
if got != ["0.125", "0.25", "nan"]:
    fails.append(f"the stages' CSR without a csr axis {got}, wanted ['0.125', '0.25', 'nan']")
# grainlab plot's legend gives them too (cyclic.png), and nothing for a run whose summary.json has no csr
if grainlab_plot.cyclic_ratio_text(run) != ", CSR 0.125/0.25":
    fails.append(f"the cyclic figure's legend CSR {grainlab_plot.cyclic_ratio_text(run)!r}, wanted ', CSR 0.125/0.25'")
if grainlab_plot.cyclic_ratio_text(work) != "":
    fails.append("a legend CSR for a directory without summary.json")
# With a csr axis whose value the run's differs from by more than 1 % (a q_amplitude stage that started from another
# p' than the preparation's: after a K0 stage), the run's, the axis's beside it; within 1 % (a servo's), the axis's
got = [x.split(" | ")[3] for x in grainlab_plot.cyclic_section([(dict(job, csr=0.2), run, s)], figs, {0.0: "C0"})
       if x.startswith("| staged")]
if got != ["0.125 (axis 0.2)", "0.25 (axis 0.2)", "0.2"]:
    fails.append(f"the stages' CSR beside a csr axis of 0.2 {got}, wanted ['0.125 (axis 0.2)', '0.25 (axis 0.2)', '0.2']")
got = [x.split(" | ")[3] for x in grainlab_plot.cyclic_section([(dict(job, csr=0.126), run, s)], figs, {0.0: "C0"})
       if x.startswith("| staged")][0]
if got != "0.126":
    fails.append(f"a run's CSR 0.8 % from the axis's shown as {got!r}, wanted the axis's '0.126'")

# Reconsolidation after undrained cycling
rrun = os.path.join(work, "recon")
os.makedirs(rrun)
with open(os.path.join(rrun, "series.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["stage", "time", "step", "eps_a", "p", "q", "u", "e", "mu_r", "stage_type", "cycle", "e_inner"])
    for k, (st, ty, n, ea, p, u, ei) in enumerate([("consolidate", 0, 0, 0, 100, 0, 0.68),
                                                   ("shake", 3, 0, 0, 100, 0, 0.68),
                                                   ("shake", 3, 0.5, 0.01, 70, 30, 0.68),
                                                   ("shake", 3, 1.0, -0.03, 40, 60, 0.67),
                                                   ("shake", 3, 1.2, 0.02, 45, 55, 0.66),
                                                   ("recon", 0, 0, 0, 100, 0, 0.65)]):
        w.writerow([st, k * 1e-3, k, ea, p * 1e3, 0, u * 1e3, 0.7, 0, ty, n, ei])
with open(os.path.join(rrun, "summary.json"), "w") as f:
    json.dump({"stages": [{"name": "consolidate", "type": "isotropic", "e": 0.72, "p": 1e5},
                          dict(entry("shake", "undrained", 2, 1.2, None, 1.0, 6.0), e=0.72, p=45e3),
                          {"name": "recon", "type": "isotropic", "e": 0.69, "p": 1e5, "e_inner": 0.65}]}, f)
rjob = {"name": "rec", "mu_r": 0.0, "csr": 0.1, "drainage": "undrained", "cycles": 2}
rs = grainlab_plot.load(rrun)
rlines = grainlab_plot.cyclic_section([(rjob, rrun, rs)], figs, {0.0: "C0"})
want = f"| rec | recon | 0.600 | 3.00 | 100 | {100 * 0.03 / 1.72:.3f} | {100 * 0.01 / 1.66:.3f} |"
if want not in rlines:
    fails.append(f"no reconsolidation row {want!r} in\n" + "\n".join(rlines))
older = {k: v for k, v in rs.items() if k != "e_inner"}  # a run of a build before the series' e_inner
want = f"| rec | recon | 0.600 | 3.00 | 100 | {100 * 0.03 / 1.72:.3f} | – |"
if want not in grainlab_plot.cyclic_section([(rjob, rrun, older)], figs, {0.0: "C0"}):
    fails.append(f"no reconsolidation row {want!r} without the series' e_inner")
if any(x.startswith("| staged") and "| recon |" in x for x in lines) or \
        any("Reconsolidation after undrained cycling" in x for x in lines):
    fails.append("a reconsolidation table for the staged run, which has no isotropic stage after a cyclic one")
if fails:
    sys.exit("staged_cycles_check: " + "; ".join(fails))
print("staged_cycles_check: ok")
