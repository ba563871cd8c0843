#!/usr/bin/env bash
# tests/data/tiny-study.yaml end to end: the study driver (jobs forked and waited for, samples reused, report,
# rerun, extension) on 300 spheres, fast enough to run under AddressSanitizer + UBSan in make check, where
# study_quick's 5 000-sphere shears to 40 % outran its 900 s limit. study_quick checks the rest (signals, report
# contents) in make test.
set -u
bin=$1; src=$2; work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
cp "$src"/tiny-study.yaml "$src"/tiny-study-base.yaml "$work"/ || exit 1
cd "$work" || exit 1
fail() { echo "study_tiny: $*"; exit 1; }
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the study failed: $out"
printf '%s\n' "$out" | grep -q "2 samples, 2 shears; 4 to run" || fail "unexpected plan: $out"
[ "$(ls st/jobs/*/done | wc -l)" -eq 4 ] || fail "expected 4 finished jobs: $(ls st/jobs)"
grep -q "## Critical states" st/report.md || fail "report.md lacks its critical-state section"
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the rerun failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" || fail "the rerun did not skip the finished jobs: $out"
# An extension: the shears taken from 2 % to 3 % resume from their checkpoints.
sed -i 's/max_axial_strain: 0.02/max_axial_strain: 0.03/' tiny-study-base.yaml
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the extended study failed: $out"
printf '%s\n' "$out" | grep -q "2 shear(s) extended" || fail "the shears were not extended: $out"
printf '%s\n' "$out" | grep -q "; 2 to run" || fail "not exactly the 2 shears rerun: $out"
for s in st/jobs/shear_*; do
  [ -f "$s/done" ] || fail "$s did not finish"
  [ "$(head -1 "$s/run/series.csv" | cut -d, -f4)" = eps_a ] || fail "series.csv column 4 is not eps_a"
  eps=$(tail -1 "$s/run/series.csv" | cut -d, -f4)
  awk -v e="$eps" 'BEGIN { exit !(e >= 0.03) }' || fail "$s ended at eps_a = $eps, not 0.03"
done
echo "study_tiny: ok"
