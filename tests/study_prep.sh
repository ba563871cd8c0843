#!/usr/bin/env bash
# A preparation study end to end (a base without a shear stage: the samples are the jobs): tests/data/tiny-prep-study.yaml,
# 4 samples of 300 and 500 spheres. study.json lists them; report.md has the Samples section and the Preparation
# section, whose means and standard deviations over the seeds are recomputed here from each sample's summary.json
# (tests/prep_check.py); a rerun runs nothing; a stage appended to the base (a reloading) extends every sample, which
# resumes and goes on to it, and the report gains its isotropic compression section; a shear axis on such a base is an
# error naming it; a test whose own reconsolidation runs out of steps is warned of and marked.
set -u
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
. "$here"/study_setup.sh
study_setup study_prep tiny-prep-study.yaml tiny-prep-base.yaml
printf '%s\n' "$plan" | grep -q "4 samples, 0 shear tests; a preparation study" || fail "validate: $plan"
out=$("$bin" study tiny-prep-study.yaml --out st --jobs 2 2>&1) || fail "the study failed: $out"
printf '%s\n' "$out" | grep -q "4 samples, 0 shears; 4 to run" || fail "unexpected plan: $out"
[ "$(ls st/jobs/*/done | wc -l)" -eq 4 ] || fail "expected 4 finished jobs: $(ls st/jobs)"
[ -f st/figures/preparation.png ] || fail "no figures/preparation.png"
"${GRAINLAB_PYTHON:-/usr/bin/python3}" "$here"/prep_check.py st || fail "the report's preparation section does not match the samples"
out=$("$bin" study tiny-prep-study.yaml --out st --jobs 2 2>&1) || fail "the rerun failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" || fail "the rerun did not skip the finished jobs: $out"
grep -q "## Isotropic compression" st/report.md && fail "a compression section from single-stage samples"
# A loading path taken further: a stage appended to the base extends the samples (not a changed job).
printf '  - {name: reload, type: isotropic, mu: 0.5, max_steps: 20000, ufr_tolerance: 0.05, pressure: 400e3}\n' > stage.txt
sed -i '/^output:/e cat stage.txt' tiny-prep-base.yaml
out=$("$bin" study tiny-prep-study.yaml --out st --jobs 2 2>&1) || fail "the extended study failed: $out"
printf '%s\n' "$out" | grep -q "4 sample(s) extended" || fail "the samples were not extended: $out"
printf '%s\n' "$out" | grep -q "; 4 to run" || fail "not exactly the 4 samples rerun: $out"
for s in st/jobs/sample_*; do
  [ -f "$s/done" ] || fail "$s did not finish"
  grep -q '"name": "reload"' "$s/run/summary.json" || fail "$s/run/summary.json lacks the appended stage"
done
[ "$(grep -cE '^\| sample_mur0_ebase_pbase_s[34]_n[35]00 \| 190 → 400 \| [0-9.]+ \| ' st/report.md)" -eq 4 ] ||
  fail "no compression row 190 → 400 kPa for each sample: $(sed -n '/## Isotropic/,$p' st/report.md)"
"${GRAINLAB_PYTHON:-/usr/bin/python3}" "$here"/prep_check.py st || fail "the extended report's preparation section does not match the samples"
# The study moved to a directory whose name has a quote and a space: the rerun runs nothing and rewrites the report
# (started through a shell, a quote in the --out broke its command).
mv st "Bob's st" && rm "Bob's st/report.md"
out=$("$bin" study tiny-prep-study.yaml --out "Bob's st" --jobs 2 2>&1) || fail "the study in Bob's st failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" && [ -f "Bob's st/report.md" ] || fail "no report in Bob's st: $out"
printf 'base: tiny-prep-base.yaml\naxes: {drainage: [drained, undrained]}\n' > bad.yaml
"$here"/expect_error.sh "bad.yaml: axes.drainage: sets the drainage of the base's shear stages, and the base \(.*\) has none" \
  "$bin" validate bad.yaml || fail "a drainage axis on a preparation base is not refused"
printf 'base: tiny-prep-base.yaml\naxes: {direction: [extension]}\n' > bad.yaml
"$here"/expect_error.sh "bad.yaml: axes.direction: sets the loading direction of the base's triaxial stages" \
  "$bin" validate bad.yaml || fail "a direction axis on a preparation base is not refused"
# Over the contact stiffness (the E axis): a Preparation row per E, its seeds together (the rows pooled the two E's
# seeds into one), as prep_check.py recomputes them; the figure's panel against E.
printf 'base: tiny-prep-base.yaml\naxes: {E: [1.0e8, 1.0e9], seed: [3, 4]}\n' > stiff.yaml
out=$("$bin" study stiff.yaml --out st_E --jobs 2 2>&1) || fail "the E study failed: $out"
"${GRAINLAB_PYTHON:-/usr/bin/python3}" "$here"/prep_check.py st_E || fail "the E study's preparation rows do not match the samples"
[ "$(grep -cE '^\| sample_mur0_ebase_pbase_s\*_n300_E1e[89] \| 300 \| 2 \(3, 4\) \|' st_E/report.md)" -eq 2 ] ||
  fail "no Preparation row per E: $(sed -n '/## Preparation/,$p' st_E/report.md)"
# Over a preparation stage's key (a stage axis on a preparation study: the compaction's friction set directly, where
# e0 would search for it): a sample and a Preparation row per value, named by it, that stage run at it, and the lower
# friction compacted denser (SPEC §6.2) for each seed.
# (on the base without the appended reloading: the section's friction is the last stage's)
sed '/name: reload/d' tiny-prep-base.yaml > mu-base.yaml
printf 'base: mu-base.yaml\naxes: {stages.consolidate.mu: [0.1, 0.5], seed: [3, 4]}\n' > mu.yaml
out=$("$bin" study mu.yaml --out st_mu --jobs 2 2>&1) || fail "the mu study failed: $out"
"${GRAINLAB_PYTHON:-/usr/bin/python3}" "$here"/prep_check.py st_mu || fail "the mu study's preparation rows do not match the samples"
for m in 0.1 0.5; do
  grep -qE "^\| sample_mur0_ebase_pbase_s\*_n300_consolidate-mu$m \| 300 \| 2 \(3, 4\) \|.* \| ${m}00 \| [0-9]+ \|" st_mu/report.md ||
    fail "no Preparation row at mu = $m: $(sed -n '/## Preparation/,$p' st_mu/report.md)"
done
"${GRAINLAB_PYTHON:-/usr/bin/python3}" - st_mu <<'PY' || fail "the lower preparation friction did not compact denser"
import json, sys
e = {}
for j in json.load(open(sys.argv[1] + "/study.json"))["samples"]:
    st = json.load(open(f"{sys.argv[1]}/{j['dir']}/summary.json"))["stages"][-1]
    assert st["mu"] == j["stage_keys"]["consolidate.mu"], (j["name"], st["mu"])
    e[j["seed"], st["mu"]] = st["e"]
print(e)
sys.exit(not all(e[s, 0.1] < e[s, 0.5] for s in (3, 4)))
PY
# A preparation that runs out of steps (a stage axis over its max_steps, 300: far short of equilibrium): the study warns
# on stderr, naming the sample and the stage, and the report marks it NOT converged.
printf 'base: mu-base.yaml\naxes: {stages.consolidate.max_steps: [300]}\n' > short.yaml
"$bin" study short.yaml --out st_short --jobs 2 --quiet > /dev/null 2> short.err || fail "the short study failed: $(cat short.err)"
grep -q "^grainlab study: warning: sample_mur0_ebase_pbase_s3_n300_consolidate-max_steps300: stage consolidate ran out of steps" \
  short.err || fail "no warning of the unconverged stage: $(cat short.err)"
grep -q "| 300 (1 of 1 NOT converged) |" st_short/report.md || fail "the report does not mark it: $(cat st_short/report.md)"
[ "$(grep -c 'ran out of steps' short.err)" -eq 1 ] || fail "warned more than once: $(cat short.err)"
# The same stage run out of steps, then a later one that converges (the reload to 400 kPa appended above): the sample
# ends in equilibrium, so the warning and the report say that only its path did not pass through one.
printf 'base: tiny-prep-base.yaml\naxes: {stages.consolidate.max_steps: [300]}\n' > early.yaml
"$bin" study early.yaml --out st_early --jobs 2 --quiet > /dev/null 2> early.err || fail "the early study failed: $(cat early.err)"
grep -q "^grainlab study: warning: sample_mur0_ebase_pbase_s3_n300_consolidate-max_steps300: stage consolidate ran out of steps (its max_steps) before equilibrium: a later isotropic stage converged, so the sample ends in equilibrium" \
  early.err || fail "no warning of the earlier stage's steps: $(cat early.err)"
grep -q "| 4[0-9]* (1 of 1: an earlier stage ran out of steps) |" st_early/report.md && ! grep -qE "NOT converged \(|of [0-9]+ NOT converged" st_early/report.md ||
  fail "the report does not tell an earlier stage's steps from an unconverged sample: $(cat st_early/report.md)"
# A test's own reconsolidation (an isotropic stage after its first shear, run by the shear job) that runs out of steps:
# the study warns of the shear job, once (its sample converged), and the report's head marks that test.
sed '/^output:/i\  - {name: shear, type: triaxial, drainage: drained, axial_strain_rate: 1.0, max_axial_strain: 0.002, damping: 0.2}\n  - {name: recon, type: isotropic, pressure: 200e3, max_steps: 50}' \
  mu-base.yaml > recon-base.yaml
printf 'base: recon-base.yaml\naxes: {seed: [3]}\n' > recon.yaml
"$bin" study recon.yaml --out st_recon --jobs 2 --quiet > /dev/null 2> recon.err || fail "the recon study failed: $(cat recon.err)"
[ "$(grep -c 'ran out of steps' recon.err)" -eq 1 ] &&
  grep -q "^grainlab study: warning: shear_drained_mur0_ebase_pbase_s3_n300: stage recon ran out of steps" recon.err ||
  fail "not one warning of the shear job's reconsolidation: $(cat recon.err)"
grep -q '^\*\*NOT converged:\*\* 1 of 1 tests: shear_drained_mur0_ebase_pbase_s3_n300 (recon): ' st_recon/report.md ||
  fail "the report does not mark the test: $(head -n 8 st_recon/report.md)"
# A shear of an unconverged sample (300 steps: p' ~2 kPa of 190) fails at its first step; the study names the sample
# as the cause and a new sample as the remedy, not a rerun (which would resume it and fail again).
sed 's/max_steps: 20000/max_steps: 300/' recon-base.yaml > unconv-base.yaml
printf 'base: unconv-base.yaml\naxes: {seed: [3]}\n' > unconv.yaml
"$bin" study unconv.yaml --out st_unconv --jobs 2 --quiet > /dev/null 2> unconv.err && fail "the study of an unconverged sample's shear passed"
grep -q "^grainlab study: shear_drained_mur0_ebase_pbase_s3_n300 failed (exit [0-9]*); see .*; its sample sample_mur0_ebase_pbase_s3_n300 is not in equilibrium (stage consolidate ran out of steps): raise its max_steps and run the study into another --out" \
  unconv.err || fail "the shear's failure does not name its unconverged sample: $(cat unconv.err)"
grep -q "rerun the study to resume it" unconv.err && fail "advises a rerun that would fail again: $(cat unconv.err)"
echo "study_prep: ok"
