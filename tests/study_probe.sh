#!/usr/bin/env bash
# A probe study end to end (configs/probe-study.yaml in miniature): a base that loads to q/p' = 0.3, rests, then probes;
# a stage axis over the probe's stress_direction (four directions) is a shear of the one sample each, named by it, the
# angle in its job.yaml and study.json; the report is the response envelope (no section per direction): a row per probe
# whose reached direction lies within 3 degrees of the one asked (the servo's lag turns it; 0.5-1.9 measured), and the
# figure. The probes' q_0 is the rest's last row's (they start from the rest), the same for all four.
set -u
bin=$1; work=$2
fail() { echo "study_probe: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
cat > base.yaml <<YAML
sample: {count: 300, seed: 3, density_scaling: 1000, initial_solid_fraction: 0.40}
stages:
  - {name: consolidate, type: isotropic, pressure: 100e3, mu: 0.5, max_steps: 20000, ufr_tolerance: 0.05}
  - {name: load, type: triaxial, drainage: drained, mu: 0.5, stress_ratio: 0.3, axial_strain_rate: 0.5, damping: 0.2, servo_integral: 0.1}
  - {name: rest, type: triaxial, drainage: drained, mu: 0.5, axial_strain_rate: 0, max_steps: 3000, damping: 0.2, servo_integral: 0.1}
  - {name: probe, type: triaxial, drainage: drained, mu: 0.5, stress_direction: 90, stress_increment: 5e3, axial_strain_rate: 0.5, damping: 0.2, servo_integral: 0.1}
output: {every: 10}
YAML
printf 'base: base.yaml\naxes: {stages.probe.stress_direction: [60, 125.26, 240, 305.26]}\n' > study.yaml
out=$("$bin" study study.yaml --out st --jobs 2 --threads 1 2>&1) || fail "the study failed: $out"
for th in 60 125.26 240 305.26; do
  job=st/jobs/shear_drained_mur0_ebase_pbase_s3_n300_probe-stress_direction$th
  [ -f "$job/done" ] || fail "$job did not finish: $(ls st/jobs)"
  grep -q "stress_direction: $th" "$job/job.yaml" || fail "$job/job.yaml does not set stress_direction $th"
  grep -q "\"stage_keys\": {\"probe.stress_direction\": $th}" st/study.json || fail "study.json lacks $th"
  row=$(grep "^| shear_drained_mur0_ebase_pbase_s3_n300_probe-stress_direction$th |" st/report.md) ||
    fail "no envelope row for $th: $(cat st/report.md)"
  reached=$(printf '%s\n' "$row" | awk -F'|' '{ print $5 + 0 }')
  awk -v a="$reached" -v b="$th" 'BEGIN { d = a - b; exit !(d < 3 && d > -3) }' ||
    fail "probe $th reached the direction $reached"
  # the probe starts where the rest ended: its q_0 within a step's change of the rest's last row's q
  "${GRAINLAB_PYTHON:-/usr/bin/python3}" - "$job/run" <<'PY' || fail "$job: the probe does not start from the rest"
import csv, json, sys
d = sys.argv[1]
st = json.load(open(d + "/summary.json"))["stages"]
rows = [r for r in csv.DictReader(open(d + "/series.csv")) if r["stage"] == "rest"]
q_rest, q0 = float(rows[-1]["q"]), st[-1]["q_0"]
sys.exit(0 if abs(q0 - q_rest) < 0.002 * st[-1]["p_0"] else f"q_0 {q0} against the rest's {q_rest}")
PY
done
grep -c "^### " st/report.md | grep -qx 1 || fail "expected one state's section: $(grep '^#' st/report.md)"
grep -q "^## Response envelopes" st/report.md || fail "no response-envelope section"
grep -q "^Stiffest along theta_sigma" st/report.md || fail "no stiffest / softest line"
[ -f st/figures/response_envelopes.png ] || fail "no figures/response_envelopes.png"
q0s=$(grep -ho '"q_0": [-0-9.e+]*' st/jobs/shear_*/run/summary.json | awk 'NR % 3 == 0' | sort -u | wc -l)
[ "$q0s" -eq 1 ] || fail "the probes do not start from one state: $(grep -ho '"q_0": [-0-9.e+]*' st/jobs/shear_*/run/summary.json)"
echo "study_probe: ok"
