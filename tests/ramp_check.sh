#!/usr/bin/env bash
# pressure_ramp_steps (isotropic stages): the loose rolling-resistant gas of data/ramp.yaml consolidates
# to 200 kPa (it blows up without the ramp); the measured pressure follows the ramp (within 10 % of the
# target at 25 %, 50 % and 75 % of it: the servo tracks a slowly moving target); and a run stopped
# mid-ramp and resumed gives the uninterrupted series byte for byte (the target is a function of the
# stage step only).
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "consolidation with the ramp failed"; exit 1; }
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "step") s = i; if ($i == "p") p = i }; next }
  $s == 5000 || $s == 10000 || $s == 15000 {
    target = 200e3 * $s / 20000; n++
    if ($p < 0.9 * target || $p > 1.1 * target) { print "step " $s ": p = " $p " Pa, ramp target " target; bad = 1 } }
  END { if (n != 3) { print "series lacks the ramp rows"; bad = 1 }; exit bad }' "$work/ref/series.csv" || exit 1
"$bin" run "$cfg" --out "$work/int" --quiet --stop-after-steps 7000 > /dev/null 2>&1
[ $? -eq 130 ] || { echo "expected the stopped run to exit 130"; exit 1; }
"$bin" run "$cfg" --out "$work/int" --resume --quiet || { echo "resume failed"; exit 1; }
cmp "$work/ref/series.csv" "$work/int/series.csv" || { echo "resumed series differs from the uninterrupted one"; exit 1; }
echo "ramp ok"
