#!/usr/bin/env bash
# configs/quick-study.yaml end to end: every sample prepared exactly once and reused by its shear; the report
# has its sections and a critical-state verdict for every test; a rerun skips every finished job.
set -u
bin=$1; study=$2; work=$3
rm -rf "$work"
"$bin" study "$study" --out "$work" --jobs 2 --quiet || { echo "study failed"; exit 1; }
n_samples=$(ls -d "$work"/jobs/sample_* | wc -l)
n_shears=$(ls -d "$work"/jobs/shear_* | wc -l)
[ "$n_samples" -eq 6 ] && [ "$n_shears" -eq 6 ] || { echo "expected 6 samples and 6 shears"; exit 1; }
for s in "$work"/jobs/shear_*; do
  f=$(grep -o 'file: .*h5' "$s/job.yaml" | head -1 | cut -d' ' -f2)
  [ -f "$f" ] || { echo "$s does not reuse a prepared sample ($f)"; exit 1; }
  [ -f "$s/done" ] || { echo "$s did not finish"; exit 1; }
done
for sec in "## Peak states" "## Critical states" "## Critical-state lines" "## Stress-force-fabric shares"; do
  grep -q "$sec" "$work/report.md" || { echo "report.md lacks '$sec'"; exit 1; }
done
verdicts=$(grep -cE '^\| shear_.* \| (yes|no: )' "$work/report.md")
[ "$verdicts" -eq 6 ] || { echo "expected a critical-state verdict for each of 6 tests, got $verdicts"; exit 1; }
[ -f "$work/figures/stress_paths.png" ] || { echo "no stress-path figure"; exit 1; }
out=$("$bin" study "$study" --out "$work" --jobs 2 2>&1)
printf '%s\n' "$out" | grep -q "; 0 to run" || { echo "rerun did not skip finished jobs: $out"; exit 1; }
echo "study ok"
