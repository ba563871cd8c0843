#!/usr/bin/env bash
# tests/data/tiny-study.yaml end to end: the study driver (jobs forked and waited for, samples reused, report,
# rerun, a study extended, the direction axis, a b extra job) on 300 spheres, fast enough to run under AddressSanitizer + UBSan in make check, where
# study_quick's 5 000-sphere shears to 40 % outran its 900 s limit. study_quick checks the rest (signals, report
# contents) in make test.
set -u
# numpy's RuntimeWarnings (a NaN slice, a mean of nothing) fail the report here: each was a case the report's code did
# not handle (an All-NaN slice in the stress-dilatancy figure of a shear too short for a rate), printed into the
# study's output.
export PYTHONWARNINGS=error::RuntimeWarning
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
. "$here"/study_setup.sh
study_setup study_tiny tiny-study.yaml tiny-study-base.yaml
printf '%s\n' "$plan" | grep -q "seeds: 2 (tests that differ only in their seed" || fail "validate does not count 2 seeds: $plan"
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the study failed: $out"
# `grainlab study ... | head -n 1`: the reader leaves after the study's first line; the study's next line meets a
# closed pipe. SIGPIPE stops it like Ctrl-C (its jobs stop at a checkpoint, exit 130, a closing line naming the
# pipe); by default it killed the study (exit 141) and PR_SET_PDEATHSIG then stopped the jobs, unannounced.
"$bin" study tiny-study.yaml --out st_pipe --jobs 2 2>st_pipe.err | head -n 1 >/dev/null
rc=${PIPESTATUS[0]}
[ "$rc" -eq 130 ] || fail "a study whose output pipe closed exited $rc, not 130: $(cat st_pipe.err)"
grep -qE "^grainlab study: interrupted by the reader of its output closing the pipe \([0-9]+ job\(s\) stopped at a checkpoint, [0-9]+ of 11 done\); rerun the same command to resume$" st_pipe.err ||
  fail "no closing line naming the closed pipe: $(cat st_pipe.err)"
[ "$(ls st_pipe/jobs/*/done 2>/dev/null | wc -l)" -lt 11 ] || fail "the study with a closed pipe ran every job"
printf '%s\n' "$out" | grep -q "3 samples, 8 shears; 11 to run" || fail "unexpected plan: $out"
[ "$(ls st/jobs/*/done | wc -l)" -eq 11 ] || fail "expected 11 finished jobs: $(ls st/jobs)"
grep -q "## Critical states" st/report.md || fail "report.md lacks its critical-state section"
# The report's peak settings reach study.json (defaults: single rows, every row) and the report says so.
grep -q '"peak": {"window": 0, "max_ke_ratio": 0}' st/study.json || fail "study.json lacks the default peak block"
grep -q "Peaks are the largest of single rows;" st/report.md || fail "report.md does not say how its peaks are taken"
# The direction axis: one extension shear per sample (named _ext, job.yaml says so), q < 0 at its peak, and its
# mobilised friction angle from the extension relation (3M / (6 - M)), recomputed here from the row's own M.
[ "$(ls -d st/jobs/shear_*_ext | wc -l)" -eq 2 ] || fail "expected 2 extension shears: $(ls st/jobs)"
for s in st/jobs/shear_*_ext; do
  grep -q "direction: extension" "$s/job.yaml" || fail "$s/job.yaml does not say direction: extension"
done
rows=$(grep -E '^\| shear_.*_ext \| [0-9.]+ \| drained \| extension \| -' st/report.md)
[ "$(printf '%s\n' "$rows" | grep -c .)" -eq 2 ] || fail "expected 2 extension peak rows with q < 0: $(cat st/report.md)"
printf '%s\n' "$rows" | awk -F'|' '{ split($10, a, /[ (°)]+/); M = a[2]; phi = a[3];
  s = 3 * M / (6 - M); want = atan2(s, sqrt(1 - s * s)) * 180 / 3.141592653589793;
  if (!(M > 0) || (phi - want) > 0.051 || (want - phi) > 0.051) { print "bad phi: " $0; exit 1 } }' ||
  fail "an extension row's friction angle is not Mohr-Coulomb's of its M"
# The b extra job: named _b1, b: 1 in its job.yaml and summary.json, in the failure-criteria section beside its
# sample's b = 0 test, with its measured b at the largest obliquity near 1 (the x walls' servo lags a few %).
tt=st/jobs/shear_drained_mur0_ebase_p100k_s3_n300_b1
grep -q "b: 1" "$tt/job.yaml" || fail "$tt/job.yaml does not say b: 1"
grep -q '"b": 1,' "$tt/run/summary.json" || fail "$tt/run/summary.json does not say b = 1"
grep -q '"servo_error": [0-9]' "$tt/run/summary.json" || fail "$tt/run/summary.json gives no servo_error"
grep -q "## Failure criteria (true triaxial and extension)" st/report.md ||
  fail "report.md lacks its failure-criteria section"
row=$(sed -n '/## Failure criteria/,$p' st/report.md | grep -E '^\| shear_drained_mur0_ebase_p100k_s3_n300_b1 \|')
printf '%s\n' "$row" | awk -F'|' '{ exit !($5 > 0.9 && $5 <= 1) }' || fail "b = 1 row without a measured b near 1: $row"
# the same sample's extension: the Lode angle of b = 1 the other way, its lateral walls held equal (b measured ~1)
row=$(sed -n '/## Failure criteria/,$p' st/report.md | grep -E '^\| shear_drained_mur0_ebase_p100k_s3_n300_ext \|')
printf '%s\n' "$row" | awk -F'|' '{ exit !($4 == " 1 (extension) " && $5 > 0.9 && $5 <= 1) }' ||
  fail "the extension's failure-criteria row without b = 1 (extension) and a measured b near 1: $row"
# The rate extra job: named _rate2, its rate in job.yaml and summary.json, its rate group in study.json, and a row of
# the report's rate section, whose series also holds the grid's test of that name at the base's 1/s: two tests.
rt=st/jobs/shear_drained_mur0_ebase_p100k_s3_n300_rate2
grep -q "axial_strain_rate: 2" "$rt/job.yaml" || fail "$rt/job.yaml does not say axial_strain_rate: 2"
grep -q '"axial_strain_rate": 2,' "$rt/run/summary.json" || fail "$rt/run/summary.json does not give the rate"
grep -q '"axial_strain_rate": 2, "rate_group": "shear_drained_mur0_ebase_p100k_s3_n300", "max_axial_strain": 0, "grading": "", "cu": 0, "specimen": "", "specimen_file": "", "E": 0}' st/study.json ||
  fail "study.json lacks the rate job's group"
grep -q "## Rate dependence" st/report.md || fail "report.md lacks its rate section"
grep -qE '^\| shear_drained_mur0_ebase_p100k_s3_n300_rate2 \| 2 \| [0-9.]+e-0[0-9] \|' st/report.md ||
  fail "no rate-section row with the test's inertial number"
# The seed extra job: the grid's compression on seed 4 beside seed 3's, in the sample-scatter section (mean ± sd
# [95 %] from two seeds) and in the rate series, which pools both seeds at 1/s with seed 3's at 2/s: three tests.
grep -q "## Sample-to-sample scatter (seed axis)" st/report.md || fail "report.md lacks its sample-scatter section"
grep -qE '^\| shear_drained_mur0_ebase_p100k_s\*_n300 \| 2 \(3, 4\) \| [0-9.]+ ± [0-9.]+ \[[0-9.]+\] \|' st/report.md ||
  fail "no sample-scatter row for seeds 3 and 4"
grep -qE '^\| shear_drained_mur0_ebase_p100k_s3_n300 \| 1 \| [0-9.]+e-0[0-9] \|' st/report.md &&
  grep -qE '^\| shear_drained_mur0_ebase_p100k_s4_n300 \| 1 \| [0-9.]+e-0[0-9] \|' st/report.md &&
  grep -qE '^\| shear_drained_mur0_ebase_p100k_s\*_n300 \| 3 \| [0-9.]+ ± [0-9.]+ \([0-9.]+°\) \|' st/report.md ||
  fail "the base-rate tests of both seeds are not in the rate series, or the series has no line to I = 0"
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the rerun failed: $out"
printf '%s\n' "$out" | grep -q "; 0 to run" || fail "the rerun did not skip the finished jobs: $out"
# A study extended: the shears taken from 2 % to 3 % (along the loading) resume from their checkpoints; the undrained
# extra job keeps its own end, 2.5 % (its max_axial_strain; resumed too, since its step cap, scaled from the base's
# end, changed with it), until that is raised to 3.5 %: the same job (the end is not in its name) resumed, not a new
# one beside it.
sed -i 's/max_axial_strain: 0.02/max_axial_strain: 0.03/' tiny-study-base.yaml
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the extended study failed: $out"
printf '%s\n' "$out" | grep -q "8 shear(s) extended" || fail "the shears were not extended: $out"
printf '%s\n' "$out" | grep -q "; 8 to run" || fail "not exactly the 8 shears rerun: $out"
un=st/jobs/shear_undrained_mur0.3_ebase_p100k_s3_n300
awk -v e="$(tail -1 "$un/run/series.csv" | cut -d, -f4)" 'BEGIN { exit !(e >= 0.025 && e < 0.026) }' ||
  fail "$un did not end at its own max_axial_strain 0.025"
# With it, the base's checkpoint cadence changed: no other job is stale or extended by that (a cadence changes
# nothing a run computes), and this one is extended all the same.
sed -i 's/checkpoint_every: 1000}/checkpoint_every: 5000, keep_checkpoints: 3}/' tiny-study-base.yaml
sed -i 's/undrained, max_axial_strain: 0.025}/undrained, max_axial_strain: 0.035}/' tiny-study.yaml
out=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1) || fail "the extended extra job failed: $out"
grep -q "checkpoint_every: 5000" "$un/job.yaml" || fail "$un/job.yaml does not take the new cadence"
printf '%s\n' "$out" | grep -q "1 shear(s) extended" && printf '%s\n' "$out" | grep -q "; 1 to run" ||
  fail "the extra job's raised end did not extend it alone: $out"
[ "$(ls -d st/jobs/shear_undrained_* | wc -l)" -eq 1 ] || fail "a second job beside $un: $(ls st/jobs)"
# Its end then lowered below the 3.5 % it reached: the study's comparison of configs sees an extension, but the run
# would refuse (it has passed the new end). Refused up front by the run's own check, nothing changed: job.yaml as it
# was, `done` kept (the job had failed in the study, its `done` removed, and the report dropped it).
before=$(md5sum < "$un/job.yaml")
sed -i 's/undrained, max_axial_strain: 0.035}/undrained, max_axial_strain: 0.01}/' tiny-study.yaml
err=$("$bin" study tiny-study.yaml --out st --jobs 2 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 1 ] || fail "an end moved before a finished job's was not refused (exit $rc): $err"
printf '%s\n' "$err" | grep -qE "^grainlab: error: $un/job.yaml: the edited tiny-study.yaml extends this job, but its run refuses: .*moves stages\[0\]\.max_axial_strain from 0\.035 to 0\.01, which the run has passed .*\(nothing was changed" ||
  fail "not the run's refusal, naming the job: $err"
[ "$(md5sum < "$un/job.yaml")" = "$before" ] && [ -f "$un/done" ] || fail "the refused edit changed $un"
ls "$un"/job.yaml.check.* >/dev/null 2>&1 && fail "the check's temporary config was left: $(ls "$un")"
sed -i 's/undrained, max_axial_strain: 0.01}/undrained, max_axial_strain: 0.035}/' tiny-study.yaml
for s in st/jobs/shear_*; do
  [ -f "$s/done" ] || fail "$s did not finish"
  [ "$(head -1 "$s/run/series.csv" | cut -d, -f4)" = eps_a ] || fail "series.csv column 4 is not eps_a"
  eps=$(tail -1 "$s/run/series.csv" | cut -d, -f4)
  case $s in *_ext) along=-1 ;; *) along=1 ;; esac
  awk -v e="$eps" -v a="$along" 'BEGIN { exit !(a * e >= 0.03) }' || fail "$s ended at eps_a = $eps, not $along x 0.03"
done
echo "study_tiny: ok"
