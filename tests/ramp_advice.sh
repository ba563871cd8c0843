#!/usr/bin/env bash
# A squeeze that stops an isotropic stage which loads a loose gas at once (data/wide_gas.yaml) names a pressure ramp,
# pressure_ramp_steps: N, and that ramp consolidates the same gas without a warning (the deepest overlap stays under
# three quarters of numerics.max_overlap); a gas too soft for its target pressure (data/soft.yaml, E = 2 MPa, which
# the plan already warns of) is not told to ramp: no ramp helps there. Nor is a gas that stops after reaching its
# pressure (data/wide_loaded.yaml): the line says so, and names the squeezed pair's radii.
set -u
bin=$1; cfg=$2; soft=$3; work=$4; loaded=$5
rm -rf "$work" && mkdir -p "$work" || exit 1
"$bin" run "$cfg" --out "$work/once" --quiet 2> "$work/once.err"
rc=$?
[ $rc -eq 3 ] || { echo "expected the gas loaded at once to stop (exit 3), got $rc"; cat "$work/once.err"; exit 1; }
[ "$(wc -l < "$work/once.err")" -eq 1 ] || { echo "expected one stderr line"; cat "$work/once.err"; exit 1; }
grep -q "a slow squeeze" "$work/once.err" || { echo "expected a squeeze"; cat "$work/once.err"; exit 1; }
grep -q "so its walls reach the gas's jamming at full speed" "$work/once.err" ||
  { echo "expected the walls at full speed (p' below the target)"; cat "$work/once.err"; exit 1; }
n=$(grep -o "stages\[0\]\.pressure_ramp_steps: [0-9]*" "$work/once.err" | grep -o "[0-9]*$")
[ -n "$n" ] || { echo "the stop names no ramp"; cat "$work/once.err"; exit 1; }
step=$(grep -o "blow-up at step [0-9]*" "$work/once.err" | grep -o "[0-9]*$")
echo "stopped at step $step; advised pressure_ramp_steps: $n"
# Five times the steps of the stage (step + 1: the stage's step count), rounded up to two significant digits.
[ "$n" -ge $((5 * (step + 1))) ] && [ "$n" -lt $((6 * (step + 1))) ] ||
  { echo "the advice is not five times the stage's $((step + 1)) steps"; exit 1; }
sed "s/affine: true}/affine: true, pressure_ramp_steps: $n}/" "$cfg" > "$work/ramped.yaml"
grep -q "pressure_ramp_steps: $n}" "$work/ramped.yaml" || { echo "the data file no longer ends its stage with affine"; exit 1; }
"$bin" run "$work/ramped.yaml" --out "$work/ramped" --quiet 2> "$work/ramped.err" ||
  { echo "the advised ramp did not consolidate the gas"; cat "$work/ramped.err"; exit 1; }
[ ! -s "$work/ramped.err" ] || { echo "the ramped run warned"; cat "$work/ramped.err"; exit 1; }
grep -q '"done": true' "$work/ramped/summary.json" || { echo "the ramped stage did not converge"; exit 1; }
awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "overlap_max") c = i; next }
  { if ($c > m) m = $c } END { printf "ramped: deepest overlap %.3g of the smaller radius\n", m; exit !(c && m < 0.15) }' \
  "$work/ramped/series.csv" || { echo "the ramped run's overlaps reach three quarters of the limit"; exit 1; }
"$bin" run "$soft" --out "$work/soft" --quiet > /dev/null 2> "$work/soft.err"
[ $? -eq 3 ] || { echo "expected the soft gas to stop"; exit 1; }
grep -q "error: .*a slow squeeze" "$work/soft.err" || { echo "expected the soft gas's squeeze"; cat "$work/soft.err"; exit 1; }
! grep -q "pressure_ramp_steps" "$work/soft.err" || { echo "a ramp advised where the contacts are too soft"; exit 1; }
"$bin" run "$loaded" --out "$work/loaded" --quiet > /dev/null 2> "$work/loaded.err"
[ $? -eq 3 ] || { echo "expected the wide gas at its pressure to stop"; cat "$work/loaded.err"; exit 1; }
grep -q "error: .*normal force [0-9.e+-]* N (radii [0-9.e+-]* and [0-9.e+-]* mm).*a slow squeeze" "$work/loaded.err" ||
  { echo "expected the squeeze, with the pair's radii"; cat "$work/loaded.err"; exit 1; }
grep -q "had reached its pressure (p' = [0-9.]* of 190 kPa), so a slower ramp will not help" "$work/loaded.err" ||
  { echo "expected the stop at full pressure to say no ramp helps"; cat "$work/loaded.err"; exit 1; }
! grep -q "pressure_ramp_steps:\|ramp it in slower" "$work/loaded.err" ||
  { echo "a ramp advised where the stage had reached its pressure"; cat "$work/loaded.err"; exit 1; }
echo "ramp advice ok"
