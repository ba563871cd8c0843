#!/usr/bin/env bash
# numerics.fines_mass_radius end to end on the smoke run (data/smoke.yaml: radii 0.2-0.6 mm, mu_r 0.1):
#  - a radius under every sphere scales nothing: the run warns so, and its series is the run without the key's, byte
#    for byte (a feature that is off costs nothing, not even a rounding);
#  - 0.3 mm makes the spheres under it heavier: the plan says how many, the step (the series' dt) is the unscaled
#    run's times the plan's factor, summary.json's sample and the resolved config.yaml record the radius.
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
"$bin" run "$cfg" --out "$work/spec" --quiet || { echo "the reference run failed"; exit 1; }
sed 's/^stages:/numerics: {fines_mass_radius: 0.1e-3}\nstages:/' "$cfg" > "$work/none.yaml"
"$bin" run "$work/none.yaml" --out "$work/none" --quiet 2> "$work/none.err" || { echo "the run failed"; exit 1; }
grep -q "warning: .*numerics.fines_mass_radius = 0.0001 m is not above the smallest radius" "$work/none.err" ||
  { echo "expected the warning that nothing is scaled"; cat "$work/none.err"; exit 1; }
cmp "$work/spec/series.csv" "$work/none/series.csv" || { echo "a radius under every sphere changed the run"; exit 1; }
sed 's/^stages:/numerics: {fines_mass_radius: 0.3e-3}\nstages:/' "$cfg" > "$work/fines.yaml"
"$bin" validate "$work/fines.yaml" > "$work/plan.txt" || { echo "validate failed"; exit 1; }
grep "fines: " "$work/plan.txt" || { echo "the plan has no fines line"; cat "$work/plan.txt"; exit 1; }
factor=$(grep -o "with SPEC §1's masses (x [0-9.]*)" "$work/plan.txt" | grep -o "[0-9.]*)$" | tr -d ')')
"$bin" run "$work/fines.yaml" --out "$work/fines" --quiet 2> "$work/fines.err" || { echo "the scaled run failed"; exit 1; }
[ ! -s "$work/fines.err" ] || { echo "the scaled run warned"; cat "$work/fines.err"; exit 1; }
awk -F, -v f="$factor" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "dt") c = i; next }
  FNR == 2 && FILENAME == ARGV[1] { a = $c } FNR == 2 && FILENAME == ARGV[2] { b = $c }
  END { r = b / a; printf "dt %g against %g: x %.4g (plan: x %s)\n", b, a, r, f; exit !(c && f > 1 && r > f * 0.995 && r < f * 1.005) }' \
  "$work/spec/series.csv" "$work/fines/series.csv" || { echo "the step is not the plan's"; exit 1; }
grep -q '"fines_mass_radius": 0.0003' "$work/fines/summary.json" || { echo "summary.json lacks the radius"; exit 1; }
grep -q "fines_mass_radius: 3.0e-04" "$work/fines/config.yaml" || { echo "config.yaml lacks the radius"; exit 1; }
! grep -q "fines_mass_radius" "$work/spec/summary.json" "$work/spec/config.yaml" || { echo "an unscaled run records a radius"; exit 1; }
echo "fines scaling ok"
