#!/usr/bin/env bash
# A cyclic oedometer study end to end (configs/cyclic-oedometer-study.yaml in miniature): a base that loads
# oedometrically to sigma_v = 200 kPa, then cycles sigma_v about it with the lateral walls held; a stage axis over
# sigma_v_amplitude (20 and 60 kPa), one shear each. The report's tables (across the values, and each value's section)
# are recomputed from each job's cycles.csv and summary.json (the permanent strain after the first and the last cycle,
# its increment early and late: cycle 2's and 3's of 3, the power law's exponent (fitted here by hand), no rate decay
# exponent (3 cycles: under the 10 its three windows need) nor strain per tenfold N (under 4), M_eq, D_v, D_v
# less the drag, K first and last, sigma_v,0 and A); every whole cycle's sigma_v extremes lie
# at or past sigma_v,0 +- A; neither the liquefaction nor the modulus-reduction section takes these tests; `grainlab
# plot`'s figures of one job (its two cycle figures, called as plot calls them: the whole plot takes 10 s) draw
# cyclic_oedometer.png and no modulus_damping.png (not a modulus-reduction test).
set -u
bin=$1; work=$2
fail() { echo "study_cyclic_oedometer: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
cat > base.yaml <<YAML
sample: {count: 300, seed: 3, density_scaling: 1000, initial_solid_fraction: 0.40}
stages:
  - {name: consolidate, type: isotropic, mu: 0.5, max_steps: 20000, ufr_tolerance: 0.05, pressure: 100e3}
  - {name: load, type: triaxial, drainage: oedometric, sigma_v: 200e3, axial_strain_rate: 0.5, damping: 0.2}
  - {name: cyc, type: cyclic, drainage: oedometric, sigma_v_amplitude: 30e3, cycles: 3, axial_strain_rate: 0.5, damping: 0.2}
output: {every: 100}
YAML
printf 'base: base.yaml\naxes: {stages.cyc.sigma_v_amplitude: [20e3, 60e3]}\n' > study.yaml
out=$("$bin" study study.yaml --out st --jobs 2 --threads 1 2>&1) || fail "the study failed: $out"
for A in 20000 60000; do
  job=st/jobs/shear_oedometric_mur0_ebase_pbase_s3_n300_cyc-sigma_v_amplitude$A
  [ -f "$job/done" ] || fail "$job did not finish: $(ls st/jobs)"
  grep -q "sigma_v_amplitude: $A" "$job/job.yaml" || fail "$job/job.yaml does not set sigma_v_amplitude $A"
done
grep -q "^## Across the values" st/report.md || fail "no across-the-values section"
[ "$(grep -c '^### Cyclic oedometer tests' st/report.md)" -eq 2 ] || fail "expected a cyclic oedometer section per value"
! grep -q "^### Cyclic tests\|^### Modulus" st/report.md || fail "a liquefaction or modulus section took the oedometer tests"
for A in 20000 60000; do
  [ -f "st/figures/cyc.sigma_v_amplitude_$A/cyclic_oedometer.png" ] || fail "no cyclic_oedometer.png for $A"
done
"${GRAINLAB_PYTHON:-/usr/bin/python3}" - st <<'PY' || fail "the report's rows are not the runs'"
import csv, json, math, os, sys
st = sys.argv[1]
report = open(os.path.join(st, "report.md")).read().splitlines()
for A in (20000, 60000):
    name = f"shear_oedometric_mur0_ebase_pbase_s3_n300_cyc-sigma_v_amplitude{A}"
    run = os.path.join(st, "jobs", name, "run")
    summ = {s["name"]: s for s in json.load(open(os.path.join(run, "summary.json")))["stages"]}["cyc"]
    sv0 = summ["sigma_v_0"]
    assert summ["sigma_v_amplitude"] == A, summ
    rows = [r for r in csv.DictReader(open(os.path.join(run, "cycles.csv"))) if r["complete"] == "1"]
    assert len(rows) == 3, rows
    for r in rows:
        assert float(r["sigma_v_max"]) >= sv0 + A and float(r["sigma_v_min"]) <= sv0 - A, (r, sv0)
        assert float(r["sigma_v_max"]) < sv0 + 1.01 * A and float(r["sigma_v_min"]) > sv0 - 1.01 * A, (r, sv0)
    f = lambda r, k, s=1.0: s * float(r[k])
    eps = [f(r, "eps_v", 100) for r in rows]
    # eps_p = eps_1 N^b through the 3 cycles: least squares in the logarithms, b's standard error from the residual
    x, y = [math.log(n) for n in (1, 2, 3)], [math.log(e) for e in eps]
    xm, ym = sum(x) / 3, sum(y) / 3
    sxx = sum((v - xm) ** 2 for v in x)
    b = sum((u - xm) * (v - ym) for u, v in zip(x, y)) / sxx
    sb = math.sqrt(sum((v - ym - b * (u - xm)) ** 2 for u, v in zip(x, y)) / (3 - 2) / sxx)
    want = (f"| {name} | cyc | {sv0 / 1e3:.1f} | {A / 1e3:.1f} ({A / sv0:.2f}) | 3 | {eps[0]:.3f} | {eps[-1]:.3f} | "
            f"{eps[1] - eps[0]:.4f} (2) → {eps[2] - eps[1]:.4f} (3) | {b:.3f} ± {sb:.3f} | – (under 10 cycles) | – | {f(rows[0], 'M_eq', 1e-6):.1f} → {f(rows[-1], 'M_eq', 1e-6):.1f} | "
            f"{f(rows[0], 'damping_v'):.3f} → {f(rows[-1], 'damping_v'):.3f} | "
            f"{f(rows[0], 'damping_v_less_drag'):.3f} → {f(rows[-1], 'damping_v_less_drag'):.3f} | "
            f"{f(rows[0], 'K'):.3f} → {f(rows[-1], 'K'):.3f} | ")
    hits = [l for l in report if want in l]
    # once in the value's section, once across the values (after its section column)
    assert len(hits) == 2, (want, [l for l in report if name in l])
    assert any(l.startswith(f"| cyc.sigma_v_amplitude = {A} | {name} |") for l in hits), hits
PY
job=st/jobs/shear_oedometric_mur0_ebase_pbase_s3_n300_cyc-sigma_v_amplitude60000/run
scripts=$(dirname "$0")/../scripts
plot=$(MPLBACKEND=Agg "${GRAINLAB_PYTHON:-/usr/bin/python3}" - "$scripts" "$job" figs <<'PY' 2>&1
import os, sys
sys.path.insert(0, sys.argv[1])
import grainlab_plot as g
runs = [(sys.argv[2], g.load(sys.argv[2]))]
os.makedirs(sys.argv[3], exist_ok=True)
g.fig_cyclic_oedometer(runs, sys.argv[3])
g.fig_modulus_damping(runs, sys.argv[3])
PY
) || fail "the plot's figures failed: $plot"
[ -f figs/cyclic_oedometer.png ] || fail "plot drew no cyclic_oedometer.png: $plot"
[ ! -f figs/modulus_damping.png ] || fail "plot drew modulus_damping.png of a cyclic oedometer"
echo "study_cyclic_oedometer: ok"
