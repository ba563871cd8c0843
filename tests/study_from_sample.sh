#!/usr/bin/env bash
# A study whose base starts from a saved sample (sample.file, here the smoke run's sample_consolidate.h5, 300 spheres):
# its sample job consolidates that sample again (at the base's pressure and mu_r) and its shears run on the result.
# The study wrote the base's seed and count into the sample job beside sample.file, which the job's config refused
# ("sample.count: cannot be combined with sample.file"). Now: validate names the file and counts its spheres (the job
# names carry n300), the sample job's config keeps sample.file as an absolute path and nothing else under sample, both
# shears finish, and a seed or count axis on such a base is an error naming the file.
set -u
bin=$1; smoke=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "study_from_sample: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
[ -f "$smoke/sample_consolidate.h5" ] || fail "no smoke sample at $smoke"
# relative to this base's directory, as a user writes it
ln -s "$smoke" smoke
cat > base.yaml <<'YAML'
sample: {file: smoke/sample_consolidate.h5}
material: {mu: 0.5}
numerics: {damping: 0.2}
stages:
  - {name: again, type: isotropic, pressure: 190e3, max_steps: 40000, ufr_tolerance: 0.02}
  - {name: shear, type: triaxial, axial_strain_rate: 1.0, max_axial_strain: 0.004}
output: {every: 200}
YAML
printf 'base: base.yaml\naxes: {drainage: [drained, undrained]}\n' > study.yaml
plan=$("$bin" validate study.yaml 2>&1) || fail "validate failed: $plan"
printf '%s\n' "$plan" | grep -q "study: 1 sample, 2 shear tests" || fail "validate: $plan"
printf '%s\n' "$plan" | grep -q "sample: the base's sample.file .*/smoke/sample_consolidate.h5, consolidated again" ||
  fail "validate does not name the sample file: $plan"
out=$("$bin" study study.yaml --out st --jobs 2 --threads 2 2>&1) || fail "the study failed: $out"
job=st/jobs/sample_mur0_ebase_pbase_s1_n300
[ -f "$job/done" ] || fail "no finished sample job named for the file's 300 spheres: $(ls st/jobs)"
sample=$(/usr/bin/python3 -c "import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))['sample'])" "$job/job.yaml")
[ "$sample" = "{'file': '$PWD/smoke/sample_consolidate.h5'}" ] || fail "the sample job's sample block: $sample"
[ "$(ls st/jobs/shear_*/done | wc -l)" -eq 2 ] || fail "expected 2 finished shears: $(ls st/jobs)"
[ -f st/report.md ] || fail "no report"
for axis in "seed: [1, 2]" "count: [300]"; do
  printf 'base: base.yaml\naxes: {%s}\n' "$axis" > bad.yaml
  "$here"/expect_error.sh "bad.yaml: axes.${axis%%:*}: the base starts from sample.file \(.*/smoke/sample_consolidate.h5\), whose spheres are the file's: no seed or count to set$" \
    "$bin" validate bad.yaml || fail "axis $axis"
done
# a base from a file still needs its isotropic stage (the sample job's): the error says so
sed '/name: again/d' base.yaml > noiso.yaml
printf 'base: noiso.yaml\naxes: {drainage: [drained]}\n' > bad.yaml
"$here"/expect_error.sh "bad.yaml: base: its stages must include an isotropic stage .*; a base from sample.file too: its isotropic stage consolidates the saved sample again" \
  "$bin" validate bad.yaml || fail "a file base without an isotropic stage"
echo "study_from_sample: ok"
