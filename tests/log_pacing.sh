#!/usr/bin/env bash
# Progress lines in a log (stdout not a terminal): each stage's first row at once, then at most one a second. The
# smoke config at output.every 10 writes ~1 700 series rows in about a second; every one of them was a log line.
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
sed 's/every: 200/every: 10/' "$cfg" > "$work/dense.yaml"
grep -q "every: 10}" "$work/dense.yaml" || { echo "the smoke config no longer says every: 200"; exit 1; }
t0=$(date +%s.%N)
"$bin" run "$work/dense.yaml" --out "$work/run" > "$work/log.txt" || { echo "the run failed"; exit 1; }
t1=$(date +%s.%N)
rows=$(($(wc -l < "$work/run/series.csv") - 1))
lines=$(grep -cE "^[A-Za-z0-9_.-]+ \| step [0-9]+ \|" "$work/log.txt")
stages=$(grep -c "^stage .*: done" "$work/log.txt")
# At most: each stage's first, plus one for every whole second the run took, plus one.
limit=$(awk -v a="$t0" -v b="$t1" -v s="$stages" 'BEGIN { printf "%d", s + (b - a) + 1 }')
echo "rows $rows, progress lines $lines (limit $limit), stages $stages"
[ "$rows" -ge 1000 ] || { echo "expected a dense series"; exit 1; }
[ "$stages" -eq 2 ] || { echo "expected 2 stages done"; cat "$work/log.txt"; exit 1; }
[ "$lines" -ge "$stages" ] || { echo "each stage's first row must be logged"; cat "$work/log.txt"; exit 1; }
[ "$lines" -le "$limit" ] || { echo "more progress lines than one a second"; exit 1; }
for s in consolidate shear; do
  grep -q "^$s | step" "$work/log.txt" || { echo "no progress line of stage $s"; exit 1; }
done
echo "log pacing ok"
