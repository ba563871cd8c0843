#!/usr/bin/env bash
# A preparation study end to end (a base without a shear stage: the samples are the jobs): tests/data/tiny-prep-study.yaml,
# 8 samples of 300 and 500 spheres. study.json lists them; report.md has the Samples section and the Preparation
# section, whose means and standard deviations over the seeds are recomputed here from each sample's summary.json
# (tests/prep_check.py); a rerun runs nothing; a shear axis on such a base is an error naming it.
set -u
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work" || exit 1
cp "$src"/tiny-prep-study.yaml "$src"/tiny-prep-base.yaml "$work"/ || exit 1
cd "$work" || exit 1
fail() { echo "study_prep: $*"; exit 1; }
plan=$("$bin" validate tiny-prep-study.yaml 2>&1) || fail "validate failed: $plan"
printf '%s\n' "$plan" | grep -q "8 samples, 0 shear tests; a preparation study" || fail "validate: $plan"
out=$("$bin" study tiny-prep-study.yaml --out st --jobs 2 2>&1) || fail "the study failed: $out"
printf '%s\n' "$out" | grep -q "8 samples, 0 shears; 8 to run" || fail "unexpected plan: $out"
[ "$(ls st/jobs/*/done | wc -l)" -eq 8 ] || fail "expected 8 finished jobs: $(ls st/jobs)"
[ -f st/figures/preparation.png ] || fail "no figures/preparation.png"
/usr/bin/python3 "$here"/prep_check.py st || fail "the report's preparation section does not match the samples"
out=$("$bin" study tiny-prep-study.yaml --out st --jobs 2 2>&1) || fail "the rerun failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" || fail "the rerun did not skip the finished jobs: $out"
printf 'base: tiny-prep-base.yaml\naxes: {drainage: [drained, undrained]}\n' > bad.yaml
"$here"/expect_error.sh "bad.yaml: axes.drainage: sets the drainage of the base's shear stages, and the base \(.*\) has none" \
  "$bin" validate bad.yaml || fail "a drainage axis on a preparation base is not refused"
printf 'base: tiny-prep-base.yaml\naxes: {direction: [extension]}\n' > bad.yaml
"$here"/expect_error.sh "bad.yaml: axes.direction: sets the loading direction of the base's triaxial stages" \
  "$bin" validate bad.yaml || fail "a direction axis on a preparation base is not refused"
echo "study_prep: ok"
