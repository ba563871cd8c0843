#!/usr/bin/env bash
# A study whose base starts from a saved sample (sample.file, here the smoke run's sample_consolidate.h5, 300 spheres):
# its sample job consolidates that sample again (at the base's pressure and mu_r) and its shears run on the result.
# The study wrote the base's seed and count into the sample job beside sample.file, which the job's config refused
# ("sample.count: cannot be combined with sample.file"). Now: validate names the file and counts its spheres (the job
# names carry n300, and _file where a drawn sample names its seed), the sample job's config keeps sample.file as an absolute path and nothing else under sample, both
# shears finish, and a seed or count axis on such a base is an error naming the file.
# The sample each job started from is recorded (its checkpoints' sample_digest): a base sample file replaced by another
# stops the rerun before anything is written, `grainlab run --resume` of the job refuses it too, and shears that ran on
# a sample job since run again on the new file keep the report from being rewritten with them. These went unnoticed:
# the done jobs were skipped and the report mixed or kept the former sample's results.
set -u
bin=$1; smoke=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
fail() { echo "study_from_sample: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
[ -f "$smoke/sample_consolidate.h5" ] || fail "no smoke sample at $smoke"
# relative to this base's directory, as a user writes it (a copy: replaced below)
mkdir smoke && cp "$smoke/sample_consolidate.h5" smoke/ || exit 1
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
job=st/jobs/sample_mur0_ebase_pbase_file_n300
[ -f "$job/done" ] || fail "no finished sample job named for the file's 300 spheres: $(ls st/jobs)"
sample=$("${GRAINLAB_PYTHON:-/usr/bin/python3}" -c "import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))['sample'])" "$job/job.yaml")
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
# Another sample under the base's file name: the study's sample job made another 300-sphere sample from it.
cp "$job/run/sample_again.h5" other.h5 && cp other.h5 smoke/sample_consolidate.h5 || exit 1
cp st/report.md report_before.md
"$here"/expect_error.sh "st/jobs/sample_mur0_ebase_pbase_file_n300/job.yaml: this job ran on another sample than $PWD/smoke/sample_consolidate.h5 holds now \(sample [0-9a-f]{16} then, [0-9a-f]{16} now; 1 job\(s\) so\): put that sample back" \
  "$bin" study study.yaml --out st --jobs 2 --threads 2 || fail "a replaced base sample was not noticed"
"$here"/expect_error.sh "$PWD/smoke/sample_consolidate.h5 \(sample.file\): not the sample this run started from \(its checkpoints record sample [0-9a-f]{16}, the file holds [0-9a-f]{16}\)" \
  "$bin" run "$job/run/config.yaml" --resume || fail "the job's own resume did not notice the replaced sample"
# Its sample job run again (its directory deleted) on the new file: the shears ran on the former one.
rm -rf "$job"
err=$("$bin" study study.yaml --out st --jobs 2 --threads 2 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 1 ] || fail "expected exit 1 with shears of a former sample, got $rc: $err"
printf '%s\n' "$err" | grep -q "st/jobs/shear_drained_mur0_ebase_pbase_file_n300: this job ran on another sample than $PWD/st/jobs/sample_mur0_ebase_pbase_file_n300/run/sample_again.h5 holds now (sample [0-9a-f]* then, [0-9a-f]* now; 2 job(s) so): .*the report was not rewritten" ||
  fail "shears of a former sample not named: $err"
cmp -s st/report.md report_before.md || fail "the report was rewritten with the shears of a former sample"
echo "study_from_sample: ok"
