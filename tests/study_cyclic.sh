#!/usr/bin/env bash
# tests/data/tiny-cyclic-study.yaml end to end: a study whose base loads cyclically. One sample prepared once, a
# cyclic test at CSR 0.1 and 0.3 (q_amplitude = 2 CSR p'_0 = 38 and 114 kPa in each job's config), the report's
# cyclic section and its CSR - N figure. The stronger loading liquefies (2 % double-amplitude axial strain) in fewer
# cycles.
set -u
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
# validate: a stress-reversal test's length is unknown before it runs; the plan gives its cap as a cap
. "$here"/study_setup.sh
study_setup study_cyclic tiny-cyclic-study.yaml tiny-cyclic-base.yaml
printf '%s\n' "$plan" | grep -q "cyclic tests reversing at q: 2, at most 1000000 steps each (max_steps;" ||
  fail "validate does not give the cyclic tests' cap as one: $plan"
printf '%s\n' "$plan" | grep -q "shear tests:" && fail "validate counts the cyclic tests' cap as their length: $plan"
out=$("$bin" study tiny-cyclic-study.yaml --out sc --jobs 2 2>&1) || fail "the study failed: $out"
printf '%s\n' "$out" | grep -q "1 sample, 2 shears; 3 to run" || fail "unexpected plan: $out"
[ "$(ls sc/jobs/*/done | wc -l)" -eq 3 ] || fail "expected 3 finished jobs: $(ls sc/jobs)"
lo=sc/jobs/shear_undrained_mur0_ebase_pbase_s3_n300_csr0.1 hi=sc/jobs/shear_undrained_mur0_ebase_pbase_s3_n300_csr0.3
grep -q "q_amplitude: 38000" $lo/job.yaml || fail "$lo/job.yaml: q_amplitude is not 2 x 0.1 x 190 kPa"
grep -q "q_amplitude: 114000" $hi/job.yaml || fail "$hi/job.yaml: q_amplitude is not 2 x 0.3 x 190 kPa"
grep -q "## Cyclic tests" sc/report.md || fail "report.md lacks its cyclic section"
grep -qE '^\| sample_mur0_ebase_pbase_s[0-9]+_n300 \| 300 \| [0-9.]+ \|' sc/report.md ||
  fail "report.md lacks its Samples section (a cyclic study's report has one too)"
[ "$(grep -c '^| shear_undrained_.*_csr0\.[13] | 0 | undrained |' sc/report.md)" -eq 2 ] || fail "report.md: not 2 cyclic rows"
# the load by size class at each test's end: four classes of equal mass (a power-law base) for each of the 2 tests
[ "$(grep -cE '^\| shear_undrained_.*_csr0\.[13] \| [0-9.]+-[0-9.]+ mm \| ' sc/report.md)" -eq 8 ] ||
  fail "report.md: not 4 size classes for each of the 2 tests"
# N at the double-amplitude criterion (liquefaction_da_strain: 2 % in the base), from each run's summary.json; the
# report lists the same numbers
nda() { grep -o '"n_da": [-0-9.e]*' "$1"/run/summary.json | awk '{print $2}'; }
da_lo=$(nda $lo) da_hi=$(nda $hi)
[ -n "$da_lo" ] && [ -n "$da_hi" ] || fail "a test did not reach 2 % double amplitude: $(cat $lo/run/summary.json $hi/run/summary.json)"
awk -v a="$da_hi" -v b="$da_lo" 'BEGIN { exit !(a < b) }' || fail "CSR 0.3 met 2 % DA at N = $da_hi, not before CSR 0.1 ($da_lo)"
grep -q "^| .*_csr0\.3 | 0 | undrained | 0.3 | .* | $(printf '%.3g' "$da_hi") | " sc/report.md ||
  fail "report.md does not give CSR 0.3's N at 2 % DA ($da_hi): $(cat sc/report.md)"
[ -f sc/figures/liquefaction.png ] || fail "no figures/liquefaction.png"
# Each test's first-cycle quarter in wave transits: summary.json's, in the report's last column; CSR 0.3 flows to
# |eps_a| = 2 % within its first cycle, so it has none (null; "–" in the report).
for t in $lo $hi; do
  tq=$(grep -o '"quarter_cycle_transits": [^,}]*' $t/run/summary.json | awk '{print $2}')
  [ -n "$tq" ] || fail "$t/run/summary.json gives no quarter_cycle_transits: $(cat $t/run/summary.json)"
  if [ "$t" = "$hi" ]; then
    [ "$tq" = null ] && grep -qE "^\| $(basename $t) \|.* \| – \|\$" sc/report.md ||
      fail "$(basename $t) has no complete cycle, but its quarter cycle is $tq"
  else
    grep -qE "^\| $(basename $t) \|.* \| $(printf '%.3g' "$tq")( \(dynamic\))? \|\$" sc/report.md ||
      fail "report.md does not give $(basename $t)'s quarter cycle ($tq transits)"
  fi
done
# N reached, from the last row of each cyclic test (the series' cycle column, found by its name)
cyc() { awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "cycle") c = i; next } END { print $c }' "$1"/run/series.csv; }
n_lo=$(cyc $lo) n_hi=$(cyc $hi)
[ -n "$n_lo" ] && [ -n "$n_hi" ] || fail "no cycle column in series.csv"
awk -v a="$n_hi" -v b="$n_lo" 'BEGIN { exit !(a < b) }' || fail "CSR 0.3 reached N = $n_hi, not fewer than CSR 0.1's $n_lo"
echo "study_cyclic: ok (N = $n_lo at CSR 0.1, $n_hi at CSR 0.3; 2 % double amplitude at N = $da_lo and $da_hi)"
