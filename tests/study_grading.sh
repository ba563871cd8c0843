#!/usr/bin/env bash
# Studies over sieve curves (the grading axis). A preparation study, tests/data/tiny-grading-study.yaml, two curves x two
# seeds of 300 spheres: each sample job draws from its own curve (tests/grading_study_check.py), the report's
# preparation section and figure take the curves (prep_check.py recomputes its rows from the samples), a rerun runs
# nothing. A shear study over the same curves (tiny-grading-shear-study.yaml): each curve's section of the report is
# the report of a study of that curve alone, and the table across the curves gives each shear's numbers as its section
# does (tests/grading_report_check.py); likewise cyclic tests over the curves (tiny-grading-cyclic-study.yaml), their
# liquefaction-resistance fits across the curves as each section gives them. A bad curve, a bad name and a list for a
# mapping are one-line errors naming the key.
set -u
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
. "$here"/study_setup.sh
study_setup study_grading tiny-grading-study.yaml tiny-grading-base.yaml
py=${GRAINLAB_PYTHON:-/usr/bin/python3}
printf '%s\n' "$plan" | grep -q "4 samples, 0 shear tests; a preparation study" || fail "validate: $plan"
# each curve's Cu as worked out by hand (linear in ln d): narrow D60/D10 = 0.8 1.25^0.2 / (0.6 (4/3)^0.2) = 1.316
printf '%s\n' "$plan" | grep -qE "gradings: 2 curves in place of the base's sizes \(narrow: Cu 1.32, dt ([0-9.e-]+) s; wide: Cu 1.99, dt ([0-9.e-]+) s\)$" ||
  fail "validate does not list the curves: $plan"
# the wide curve's finest spheres (0.3 mm against 0.6 mm) step shorter: dt ~ sqrt(m_min / k_max) ~ d_min^1.5 / d_max^0.5
dts=$(printf '%s\n' "$plan" | sed -nE 's/.*narrow: Cu 1.32, dt ([0-9.e-]+) s; wide: Cu 1.99, dt ([0-9.e-]+) s.*/\1 \2/p')
awk -v a="${dts% *}" -v b="${dts#* }" 'BEGIN { exit !(b + 0 < a + 0) }' || fail "the wide curve's dt is not the shorter: $dts"
out=$("$bin" study tiny-grading-study.yaml --out st --jobs 2 2>&1) || fail "the study failed: $out"
[ "$(ls st/jobs/*_g*/done | wc -l)" -eq 4 ] || fail "expected 4 finished jobs named _g<grading>: $(ls st/jobs)"
[ -f st/figures/preparation.png ] || fail "no figures/preparation.png"
grep -q '`figures/grading.png` (each curve, asked and drawn)' st/report.md && [ -f st/figures/grading.png ] ||
  fail "no figures/grading.png of the curves named and drawn"
"$py" "$here"/grading_study_check.py tiny-grading-study.yaml st || fail "the samples are not their curves'"
"$py" "$here"/prep_check.py st || fail "the report's preparation section does not match the samples"
out=$("$bin" study tiny-grading-study.yaml --out st --jobs 2 2>&1) || fail "the rerun failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" || fail "the rerun did not skip the finished jobs: $out"
# Shear tests over the two curves: each curve's section of the report is the report of a study of that curve alone.
cp "$src"/tiny-grading-shear-base.yaml "$src"/tiny-grading-shear-study.yaml .
out=$("$bin" study tiny-grading-shear-study.yaml --out sh --jobs 2 2>&1) || fail "the shear study failed: $out"
[ "$(ls sh/jobs/shear_drained_*_g*/done | wc -l)" -eq 4 ] || fail "expected 4 finished shears named _g<grading>: $(ls sh/jobs)"
grep -q '"grading": "wide", "cu": 1.99' sh/study.json || fail "study.json's shears lack their grading: $(cat sh/study.json)"
sed '/^    wide:/d' tiny-grading-shear-study.yaml > narrow-alone.yaml
out=$("$bin" study narrow-alone.yaml --out alone --jobs 2 2>&1) || fail "the one-curve study failed: $out"
"$py" "$here"/grading_report_check.py sh narrow alone || fail "a curve's section is not its study's report"
grep -q '`figures/grading.png`' sh/report.md || fail "the shear study's report names no figure of its curves"
grep -q "^## Across the gradings" sh/report.md || fail "the shear study's report has no table across the gradings"
# Cyclic tests over the curves: each curve's section is its study alone, its liquefaction-resistance fit across.
cp "$src"/tiny-grading-cyclic-base.yaml "$src"/tiny-grading-cyclic-study.yaml .
out=$("$bin" study tiny-grading-cyclic-study.yaml --out cy --jobs 2 2>&1) || fail "the cyclic study failed: $out"
sed '/^    wide:/d' tiny-grading-cyclic-study.yaml > narrow-cyclic.yaml
out=$("$bin" study narrow-cyclic.yaml --out cy-alone --jobs 2 2>&1) || fail "the one-curve cyclic study failed: $out"
grep -q "^| narrow | 1.32 | 0 | – | 2 % DA strain | 2 | " cy/report.md ||
  fail "no liquefaction-resistance fit of the narrow curve across the gradings: $(sed -n '/## Liquefaction resistance across/,/## Grading/p' cy/report.md)"
"$py" "$here"/grading_report_check.py cy narrow cy-alone || fail "a curve's cyclic section is not its study's report"
printf 'base: tiny-grading-base.yaml\naxes: {grading: {ok: {diameter: [1e-3, 2e-3], passing: [0, 100]}, bad: {diameter: [1e-3, 2e-3], passing: [10, 100]}}}\n' > bad.yaml
"$here"/expect_error.sh "^grainlab: error: bad.yaml: axes.grading.bad.passing\[0\]" "$bin" validate bad.yaml || fail "a bad curve is not named by its key"
printf 'base: tiny-grading-base.yaml\naxes: {grading: {"a/b": {diameter: [1e-3, 2e-3], passing: [0, 100]}}}\n' > bad.yaml
"$here"/expect_error.sh "^grainlab: error: bad.yaml: axes.grading.a/b: a grading's name ends its sample job's directory name" \
  "$bin" validate bad.yaml || fail "a name that is no file name is not refused"
printf 'base: tiny-grading-base.yaml\naxes: {grading: [1, 2]}\n' > bad.yaml
"$here"/expect_error.sh "^grainlab: error: bad.yaml: axes.grading: must name each sieve curve" "$bin" validate bad.yaml ||
  fail "a list for the curves' mapping is not refused"
echo "study_grading: ok"
