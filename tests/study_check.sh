#!/usr/bin/env bash
# configs/quick-study.yaml end to end: every sample prepared exactly once and reused by its shear; the report
# has its sections and a critical-state verdict for every test, each mu_r's critical-state lines are
# fitted from at least three critical states; a rerun skips every finished job. On the way: a relative
# --out, one study per directory, SIGKILL and SIGTERM of the study (no job outlives it, the rerun resumes),
# each output line once, and an edited study over finished jobs refused.
set -u
bin=$1; study=$2; work=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work"
# The README's form: a relative --out, from a working directory that is neither the study's nor the sources'.
# (A sample path written relative to the working directory broke every shear this way; see the reuse check.)
mkdir -p "$(dirname "$work")" && cd "$(dirname "$work")" || exit 1
rel=$(basename "$work")
jobs_gone() {  # no job of this study may outlive it (a rerun would add a second writer to a run directory)
  for _ in $(seq 1 60); do pgrep -f -- "--out $rel/jobs/" > /dev/null || return 0; sleep 0.5; done
  echo "jobs still running 30 s after the study was stopped ($1):"; pgrep -fa -- "--out $rel/jobs/"; return 1
}
# 1. SIGKILL of the study while its first jobs run: no handler can run, so the jobs learn it from
#    PR_SET_PDEATHSIG (SIGTERM) and stop at a checkpoint.
"$bin" study "$study" --out "$rel" --jobs 2 --quiet > /dev/null 2>&1 &
sid=$!
sleep 1
# A second study on the same directory while the first runs: refused with one line, the first undisturbed.
err=$("$bin" study "$study" --out "$rel" --jobs 2 --quiet 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 1 ] && printf '%s\n' "$err" | grep -q "^grainlab: error: $rel: in use by another grainlab study" ||
  { echo "a second study on the same --out was not refused (exit $rc): $err"; exit 1; }
sleep 2
kill -KILL "$sid"
wait "$sid" 2> /dev/null
jobs_gone SIGKILL || exit 1
ls "$work"/jobs/*/done > /dev/null 2>&1 && { echo "a job finished within 3 s: the interruption test tested nothing"; exit 1; }
grep -l "interrupted at step" "$work"/jobs/*/log.txt > /dev/null || { echo "no job said it was interrupted (SIGKILL)"; exit 1; }
# 2. SIGTERM (as Ctrl-C): the study forwards it to the jobs it resumed, waits for their checkpoints and exits
#    130 with one closing line.
"$bin" study "$study" --out "$rel" --jobs 2 --quiet > /dev/null 2> "$work.term" &
sid=$!
sleep 2
kill -TERM "$sid"
wait "$sid" 2> /dev/null; rc=$?
[ "$rc" -eq 130 ] || { echo "a study stopped by SIGTERM exited $rc, not 130"; cat "$work.term"; exit 1; }
grep -qE "^grainlab study: interrupted \([12] job\(s\) stopped at a checkpoint, [0-9]+ of 12 done\); rerun the same command to resume$" \
  "$work.term" || { echo "no closing line for the interrupted study:"; cat "$work.term"; exit 1; }
jobs_gone SIGTERM || exit 1
# 3. The rerun resumes the interrupted jobs and runs the rest.
# Not quiet, stdout to a file (block-buffered): each line once, though every job is a forked child.
"$bin" study "$study" --out "$rel" --jobs 2 > "$work.stdout" || { echo "study failed"; cat "$work.stdout"; exit 1; }
dups=$(sort "$work.stdout" | uniq -d)
[ -z "$dups" ] || { echo "the study printed lines twice (stdio buffers flushed by its children):"; echo "$dups"; exit 1; }
grep -q '^\[[0-9]*/12\] shear_' "$work.stdout" || { echo "no progress line for a shear"; cat "$work.stdout"; exit 1; }
n_samples=$(ls -d "$work"/jobs/sample_* | wc -l)
n_shears=$(ls -d "$work"/jobs/shear_* | wc -l)
[ "$n_samples" -eq 6 ] && [ "$n_shears" -eq 6 ] || { echo "expected 6 samples and 6 shears"; exit 1; }
for s in "$work"/jobs/shear_*; do
  f=$(grep -o 'file: .*h5' "$s/job.yaml" | head -1 | cut -d' ' -f2)
  case "$f" in /*) ;; *) f="$s/$f" ;; esac  # a relative sample path is relative to the job.yaml
  [ -f "$f" ] || { echo "$s does not reuse a prepared sample ($f)"; exit 1; }
  [ -f "$s/done" ] || { echo "$s did not finish"; exit 1; }
done
for sec in "## Peak states" "## Critical states" "## Critical-state lines" "## Stress-force-fabric shares" \
           "## Where the critical state is measured" "## Stress and dilatancy" "## State parameter (drained compression)" \
           "## Contact network at the end"; do
  grep -q "$sec" "$work/report.md" || { echo "report.md lacks '$sec'"; exit 1; }
done
verdicts=$(grep -cE '^\| shear_.* \| (yes|no: )' "$work/report.md")
[ "$verdicts" -eq 6 ] || { echo "expected a critical-state verdict for each of 6 tests, got $verdicts"; exit 1; }
# Each critical state's I is the mean inertial_number of its series over the window (recomputed here), and the
# critical-state lines name the largest; so are its q/p' of the walls' stress (q, p), of the walls' less the damping's
# drag ((q - q_drag) / (p - p_drag)) and of the interior's (q_inner, p_inner: the engine's own columns, measured in
# every row of this build). The line under the table gives, over those states, how far the walls' less the drag lies
# from the contacts' (q_p), in %: each state's value goes to drag.pct, their range is checked below.
win=$(grep -o 'over the last [0-9.]* of axial strain' "$work/report.md" | head -1 | cut -d' ' -f4)
: > "$work/drag.pct"
grep -E '^\| shear_.* \| yes \|' "$work/report.md" | while IFS='|' read -r _ name _ _ _ _ _ _ _ _ _ I _ _ Mw Md Mi _; do
  name=$(echo $name); got="$(echo $I) $(echo $Mw) $(echo $Md) $(echo $Mi)"
  want=$(awk -F, -v w="$win" 'function abs(x) { return x < 0 ? -x : x }
    NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    $c["stage_type"] == 1 || $c["stage_type"] == 2 { n++; ea[n] = $c["eps_a"]; v[n] = $c["inertial_number"]
      mw[n] = abs($c["q"] / $c["p"]); mi[n] = abs($c["q_inner"] / $c["p_inner"]); qp[n] = $c["q_p"]
      md[n] = abs(($c["q"] - $c["q_drag"]) / ($c["p"] - $c["p_drag"])) }
    END { for (i = 1; i <= n; ++i)
            if (ea[i] >= ea[n] - w) { s += v[i]; sw += mw[i]; sd += md[i]; si += mi[i]; sq += qp[i]; k++ }
          printf "%.1e %.3f %.3f %.3f %.17g", s / k, sw / k, sd / k, si / k, 100 * ((sd / k) / abs(sq / k) - 1) }' \
    "$work/jobs/$name/run/series.csv")
  echo "${want##* }" >> "$work/drag.pct"
  [ -n "$win" ] && [ "$got" = "${want% *}" ] || {
    echo "$name: I, q/p' walls, walls less drag, interior = $got in the critical-state table, ${want% *} from its series"
    exit 1; }
done || exit 1
range=$(sort -g "$work/drag.pct" | awk 'NR == 1 { lo = $1 } { hi = $1 } END { printf "%+.0f to %+.0f %%", lo, hi }')
grep -qF "the walls' less the damping's drag $range" "$work/report.md" || {
  echo "the walls' q/p' less the drag, against the contacts': $range from the series, not in the report's line:"
  grep -F "Over the critical states" "$work/report.md"; exit 1; }
# Each peak row's I is the inertial_number of its series' first row at the largest q_p of the shear, and its q_peak
# less drag the largest q - q_drag of the shear's rows [kPa] (the quick study takes its peaks from single rows; all
# compression).
grep -q "Peaks are the largest of single rows;" "$work/report.md" || { echo "the quick study's peaks are not single rows"; exit 1; }
n=0
while IFS='|' read -r _ name _ _ _ _ qld _ _ _ I _; do
  name=$(echo $name); got="$(echo $I) $(echo $qld)"; n=$((n + 1))
  want=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    $c["stage_type"] > 0 && (!seen || $c["q_p"] + 0 > best) { seen = 1; best = $c["q_p"] + 0; v = $c["inertial_number"] }
    $c["stage_type"] > 0 && (!sd || $c["q"] - $c["q_drag"] > qd) { sd = 1; qd = $c["q"] - $c["q_drag"] }
    END { printf "%.1e %.1f", v, qd / 1e3 }' "$work/jobs/$name/run/series.csv")
  [ "$got" = "$want" ] || { echo "$name: I at max q/p', q_peak less drag = $got in the peak table, $want from its series"; exit 1; }
done < <(sed -n '/^## Peak states/,/^## Critical states/p' "$work/report.md" | grep -E '^\| shear_') || exit 1
[ "$n" -eq 6 ] || { echo "expected 6 peak rows, read $n"; exit 1; }
# Critical-state lines: one fitted row per mu_r (all compression), each from at least three critical states, with the
# e_c - p' slope negative (a CSL that rises with p' would mean the steadiness test or the fit is broken), the same
# states' e_c - ln p' line (lambda > 0 likewise) and both lines' misfits, the interior's line (series e_inner) fitted
# too, and M with its friction angle.
lines=$(sed -n '/^## Critical-state lines/,/^## /p' "$work/report.md" | grep -E '^\| [0-9.]+ \| compression \| [0-9]+ \|')
[ "$(printf '%s\n' "$lines" | grep -c .)" -eq 2 ] || { echo "expected a critical-state line row for each of 2 mu_r: $lines"; exit 1; }
printf '%s\n' "$lines" | awk -F'|' '{
  n = $4 + 0
  if (n < 3 || $5 !~ /a = [-0-9.e+]+ ± [0-9.e+-]+, b = -[0-9.e+-]+ ±/ ||
      $6 !~ /e_Γ = [0-9.]+ ± [0-9.]+, λ = [0-9.]+ ±/ || $7 !~ /^ [0-9.]+, [0-9.]+ $/ ||
      $8 !~ /a = [-0-9.e+]+ ± [0-9.e+-]+, b = / || $9 !~ /c = [-0-9.e+]+ ± / ||
      $10 !~ /[0-9.]+ ± [0-9.]+ \([0-9.]+°\)/) {
    print "critical-state line not fitted from >= 3 critical states (or e_c rises with p\x27): " $0; bad = 1 }
} END { exit bad }' || exit 1
[ -f "$work/figures/stress_paths.png" ] || { echo "no stress-path figure"; exit 1; }
"$here/pdf_beside_png.sh" "$work/figures" || exit 1  # the default formats: each figure in PNG and PDF
# A job.yaml that names its sample by an absolute path (as older versions wrote it) is the same config: the
# rerun must not take it for an edit.
s1=$(ls -d "$work"/jobs/shear_* | head -1)
sed -i "s|file: \.\./|file: $work/jobs/|" "$s1/job.yaml"
grep -q "file: $work/jobs/" "$s1/job.yaml" || { echo "could not rewrite $s1/job.yaml"; exit 1; }
out=$("$bin" study "$study" --out "$work" --jobs 2 2>&1)
printf '%s\n' "$out" | grep -q "; 0 to run" || { echo "rerun did not skip finished jobs: $out"; exit 1; }
# An edited base with the same --out: the finished jobs ran with another config, so the study stops with one
# line before it writes anything (rather than reporting stale results as the edited study's).
mkdir -p "$work.edit"
cp "$(dirname "$study")/quick-study-base.yaml" "$work.edit/"
sed 's/damping: 0.2}/damping: 0.3}/' "$(dirname "$study")/quick-study-base.yaml" > "$work.edit/quick-study-base.yaml"
cp "$study" "$work.edit/study.yaml"
grep -q 'damping: 0.3}' "$work.edit/quick-study-base.yaml" || { echo "could not edit the base"; exit 1; }
before=$(cat "$work"/jobs/*/job.yaml | md5sum)
err=$("$bin" study "$work.edit/study.yaml" --out "$rel" --jobs 2 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 1 ] && [ "$(printf '%s\n' "$err" | grep -c .)" -eq 1 ] && printf '%s\n' "$err" | grep -q "ran with another config" ||
  { echo "an edited study over finished jobs was not refused (exit $rc): $err"; exit 1; }
[ "$(cat "$work"/jobs/*/job.yaml | md5sum)" = "$before" ] || { echo "the refused study rewrote job.yaml files"; exit 1; }
# A base edited only to take the shears further (max_axial_strain 0.40 -> 0.41): not stale but an extension. The
# finished shears resume from their checkpoints (no sample is prepared again) and end at the new strain.
mkdir -p "$work.ext"
sed 's/max_axial_strain: 0.40/max_axial_strain: 0.41/' "$(dirname "$study")/quick-study-base.yaml" > "$work.ext/quick-study-base.yaml"
cp "$study" "$work.ext/study.yaml"
grep -q 'max_axial_strain: 0.41' "$work.ext/quick-study-base.yaml" || { echo "could not extend the base"; exit 1; }
out=$("$bin" study "$work.ext/study.yaml" --out "$rel" --jobs 2 2>&1) || { echo "the extended study failed: $out"; exit 1; }
printf '%s\n' "$out" | grep -q "6 shear(s) extended by the edited study" && printf '%s\n' "$out" | grep -q "; 6 to run" ||
  { echo "the extended study did not resume the 6 shears (and only them): $out"; exit 1; }
for s in "$work"/jobs/shear_*; do
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "eps_a") c = i; next } { e = $c } END { exit !(e >= 0.41) }' \
    "$s/run/series.csv" || { echo "$s did not reach eps_a = 0.41"; exit 1; }
done
echo "study ok"
