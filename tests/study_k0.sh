#!/usr/bin/env bash
# A study of K0-consolidated shears (CK0D, CK0U): its base consolidates isotropically, then K0 (an oedometric stage),
# then shears. The study's shear values (drainage, direction, end strain) set the shear and leave the K0 stage as the
# base gives it: they set every non-isotropic stage, so the K0 stage became a drained, undrained or extension shear
# (and with no drainage axis, the jobs' default drainage was the K0 stage's: every shear oedometric). Likewise a K path
# (CAU, CAD: a drained stage with k_ratio, ended at sigma_v) before the shear: the drainage axis refused the base, its
# shear stages' drainages not one (before K paths counted as consolidations).
set -u
bin=$1; work=$2
fail() { echo "study_k0: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
stages() { "${GRAINLAB_PYTHON:-/usr/bin/python3}" -c "import sys, yaml
for s in yaml.safe_load(open(sys.argv[1]))['stages']:
    print(s['name'], s.get('drainage'), s.get('direction', '-'), s.get('max_axial_strain'), s.get('axial_strain_rate'))" "$1"; }
# $1: the consolidation stage (named k0), $2: the line each job's job.yaml must give it
check_base() {
  rm -rf st
  cat > base.yaml <<YAML
sample: {count: 300, seed: 3, density_scaling: 1000, initial_solid_fraction: 0.40}
stages:
  - {name: consolidate, type: isotropic, mu: 0.5, max_steps: 20000, ufr_tolerance: 0.05}
  - $1
  - {name: shear, type: triaxial, drainage: undrained, mu: 0.5, axial_strain_rate: 1.0, max_axial_strain: 0.005, damping: 0.2}
output: {every: 100}
YAML
  printf 'base: base.yaml\naxes: {drainage: [drained, undrained]}\nextra:\n  - {direction: extension, max_axial_strain: 0.004, axial_strain_rate: 2}\n' > study.yaml
  out=$("$bin" study study.yaml --out st --jobs 2 --threads 2 2>&1) || fail "the study failed: $out"
  n=0
  for job in st/jobs/shear_*; do
    n=$((n + 1))
    [ -f "$job/done" ] || fail "$job did not finish"
    got=$(stages "$job/job.yaml")
    printf '%s\n' "$got" | grep -qx "$2" || fail "$job: the consolidation stage was changed ($2): $got"
    case $job in
      *_ext_rate2) want="shear undrained extension 0.004 2" ;;  # the extra job: the base's drainage, its own direction, end, rate
      *shear_drained_*) want="shear drained - 0.005 1.0" ;;
      *) want="shear undrained - 0.005 1.0" ;;
    esac
    printf '%s\n' "$got" | grep -qx "$want" || fail "$job: the shear is not the job's ($want): $got"
  done
  [ "$n" -eq 3 ] || fail "expected 3 shears: $(ls st/jobs)"
  [ -f st/report.md ] || fail "no report"
}
check_base "{name: k0, type: triaxial, drainage: oedometric, mu: 0.5, axial_strain_rate: 1.0, max_axial_strain: 0.004, damping: 0.2}" \
  "k0 oedometric - 0.004 1.0"
check_base "{name: k0, type: triaxial, drainage: drained, k_ratio: 0.7, sigma_v: 3.0e5, mu: 0.5, axial_strain_rate: 1.0, max_axial_strain: 0.05, damping: 0.2}" \
  "k0 drained - 0.05 1.0"
# A stage axis over that K path's k_ratio (CAU at two K): a shear of the one sample each, named by it, the value in its
# job.yaml and study.json; the report a section per value, after a table across them.
rm -rf st
printf 'base: base.yaml\naxes: {stages.k0.k_ratio: [0.6, 0.8]}\n' > study.yaml
out=$("$bin" study study.yaml --out st --jobs 2 --threads 2 2>&1) || fail "the stage-axis study failed: $out"
for k in 0.6 0.8; do
  job=st/jobs/shear_undrained_mur0_ebase_pbase_s3_n300_k0-k_ratio$k
  [ -f "$job/done" ] || fail "$job did not finish: $(ls st/jobs)"
  grep -q "k_ratio: $k" "$job/job.yaml" || fail "$job/job.yaml does not set k_ratio $k"
  grep -q "\"stage_keys\": {\"k0.k_ratio\": $k}" st/study.json || fail "study.json lacks k_ratio $k"
  grep -qx "## stages.k0.k_ratio = $k" st/report.md || fail "no report section for k_ratio $k"
  [ -f "st/figures/k0.k_ratio_$k/stress_paths.png" ] || fail "no figures/k0.k_ratio_$k/"
done
# validate counts the K path (ended at sigma_v) to its strain cap: an upper bound, and says so
"$bin" validate study.yaml | grep -q "in all (at most: a stage that ends at a stress is counted to its strain cap)" ||
  fail "validate does not call the stress-ended shears' steps an upper bound: $("$bin" validate study.yaml)"
rows=$(sed -n '/^## Across the values/,/^## stages/p' st/report.md | grep -c '^| k0.k_ratio = ')
[ "$rows" -eq 2 ] || fail "the table across the values has $rows rows, not 2"
echo "study_k0: ok"
