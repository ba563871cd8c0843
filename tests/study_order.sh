#!/usr/bin/env bash
# The study starts its longest jobs first (Graham's LPT rule, run_study): on tests/data/tiny-study-base.yaml, mu_r 0
# and 0.3 at 100 kPa (the mu_r 0.3 shear takes ~2.6x the steps, the rolling time-step limit) and the mu_r 0.3 sample
# sheared again at a quarter of the rate (an extra job: 4x the steps again). One job at a time, so jobs end in the
# order they start: the samples by their longest shear (mu_r 0.3's first), then the shears by planned work. In the
# study's own order mu_r 0's sample and shear would come first. The shears' steps as run confirm the plan's order.
set -u
bin=$1; src=$2; work=$3
fail() { echo "study_order: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cp "$src/tiny-study-base.yaml" "$work"/ && cd "$work" || exit 1
cat > order.yaml <<'YAML'
base: tiny-study-base.yaml
axes:
  mu_r: [0.0, 0.3]
  p0: [100e3]
extra:
  - {mu_r: 0.3, p0: 100e3, axial_strain_rate: 0.25}
YAML
plan=$("$bin" validate order.yaml 2>&1) || fail "validate failed: $plan"
out=$("$bin" study order.yaml --out st --jobs 1 2>&1) || fail "the study failed: $out"
got=$(printf '%s\n' "$out" | sed -n 's/^\[[0-9]*\/[0-9]*\] \([^ ]*\) done in .*$/\1/p' | tr '\n' ' ')
want="sample_mur0.3_ebase_p100k_s3_n300 sample_mur0_ebase_p100k_s3_n300 "
want+="shear_drained_mur0.3_ebase_p100k_s3_n300_rate0.25 shear_drained_mur0.3_ebase_p100k_s3_n300 "
want+="shear_drained_mur0_ebase_p100k_s3_n300 "
[ "$got" = "$want" ] || fail "jobs ended in the order: $got; longest first is: $want"
# Each progress line says the job's wall time; once a shear has finished, the estimate of the shears left (none after
# the last; the samples' preparations are not estimated: they end at equilibrium).
progress=$(printf '%s\n' "$out" | grep '^\[')
[ "$(printf '%s\n' "$progress" | grep -cE '^\[[1-5]/5\] [^ ]+ done in [0-9.]+ s$')" -eq 3 ] &&
  [ "$(printf '%s\n' "$progress" |
       grep -cE '^\[[34]/5\] shear_[^ ]+ done in [0-9.]+ s; the shears left: about [0-9.]+ s$')" -eq 2 ] &&
  printf '%s\n' "$progress" | grep -qE '^\[5/5\] shear_[^ ]+ done in [0-9.]+ s$' ||
  fail "progress lines without their wall time or the shears' estimate: $progress"
# the steps behind that order: the mu_r 0.3 shear's over twice mu_r 0's at the same strain, its slow twin's more
steps() { awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "step") c = i; next } { s = $c } END { print s }' \
            "st/jobs/$1/run/series.csv"; }
s0=$(steps shear_drained_mur0_ebase_p100k_s3_n300); s3=$(steps shear_drained_mur0.3_ebase_p100k_s3_n300)
s6=$(steps shear_drained_mur0.3_ebase_p100k_s3_n300_rate0.25)
[ "$s3" -gt $((2 * s0)) ] && [ "$s6" -gt "$s3" ] ||
  fail "the shears' steps (mu_r 0: $s0, mu_r 0.3: $s3, at a quarter of the rate: $s6) do not make that order" \
       "the longest first"
# The study's base edited to take the shears further (0.02 -> 0.025): every shear resumes from its checkpoint, and a
# resumed shear's wall time is not its planned work's (part was done before), so no line estimates the shears left.
sed -i 's/max_axial_strain: 0.02,/max_axial_strain: 0.025,/' tiny-study-base.yaml
grep -q 'max_axial_strain: 0.025,' tiny-study-base.yaml || fail "could not extend the base"
out=$("$bin" study order.yaml --out st --jobs 1 2>&1) || fail "the extended study failed: $out"
progress=$(printf '%s\n' "$out" | grep '^\[')
[ "$(printf '%s\n' "$progress" | grep -cE '^\[[345]/5\] shear_[^ ]+ done in [0-9.]+ s$')" -eq 3 ] ||
  fail "resumed shears paced the estimate of the shears left: $progress"
echo "study_order: ok ($got)"
