#!/usr/bin/env bash
# tests/data/tiny-strain-study.yaml end to end: a modulus-reduction study. Two samples (mu_r 0 and 0.3), each loaded
# in strain-controlled undrained cycles at eps_a = +-1e-4, 1e-3 and 5e-3, one job per amplitude with the rate scaled
# so every quarter cycle lasts the base's 5 ms; the report's modulus-reduction section gives each job's last cycle
# from its cycles.csv and a hyperbolic fit per sample, and draws figures/modulus_reduction.png.
set -u
bin=$1; src=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
# validate: strain-controlled tests have a known length (8 quarter cycles of A / (rate dt) steps each)
. "$here"/study_setup.sh
study_setup study_strain tiny-strain-study.yaml tiny-strain-base.yaml
printf '%s\n' "$plan" | grep -q "study: 2 samples, 6 shear tests" || fail "validate: not 2 samples and 6 tests: $plan"
printf '%s\n' "$plan" | grep -q "shear tests: [0-9]* to [0-9]* steps each" || fail "validate gives no test length: $plan"
out=$("$bin" study tiny-strain-study.yaml --out ss --jobs 2 2>&1) || fail "the study failed: $out"
printf '%s\n' "$out" | grep -q "2 samples, 6 shears; 8 to run" || fail "unexpected plan: $out"
[ "$(ls ss/jobs/*/done | wc -l)" -eq 8 ] || fail "expected 8 finished jobs: $(ls ss/jobs)"
job() { echo "ss/jobs/shear_undrained_mur$1_ebase_pbase_s3_n300_ea$2"; }
grep -q "strain_amplitude: 1.0e-04, axial_strain_rate: 0.02," "$(job 0 0.0001)"/job.yaml ||
  fail "$(job 0 0.0001)/job.yaml: not 1e-4 at 0.2 x 1e-4 / 1e-3 = 0.02/s: $(grep loops "$(job 0 0.0001)"/job.yaml)"
grep -q "strain_amplitude: 0.005, axial_strain_rate: 1," "$(job 0.3 0.005)"/job.yaml ||
  fail "$(job 0.3 0.005)/job.yaml: not 5e-3 at 1/s: $(grep loops "$(job 0.3 0.005)"/job.yaml)"
grep -q "## Modulus reduction and damping" ss/report.md || fail "report.md lacks its modulus-reduction section"
[ "$(grep -c '^| shear_undrained_.*_ea0\.0*[15] | mu_r=' ss/report.md)" -eq 6 ] || fail "report.md: not 6 rows: $(cat ss/report.md)"
# each row: the job's last cycle in cycles.csv (cycle 2): its shear strain amplitude (gamma_max - gamma_min)/2 in %,
# E_eq and G_eq in MPa (columns 8, 13, 14 and 15); G_eq/G_0 = 1 at the smallest amplitude
for mur in 0 0.3; do
  for ea in 0.0001 0.001 0.005; do
    d=$(job $mur $ea)
    last=$(tail -1 "$d"/run/cycles.csv)
    [ "$(echo "$last" | cut -d, -f2)" = 2 ] || fail "$d/run/cycles.csv: the last row is not cycle 2: $last"
    want=$(echo "$last" | awk -F, '{printf "%.4g | 2 | %.4g | %.4g", 50 * ($13 - $14), $8 / 1e6, $15 / 1e6}')
    grep -q "^| ${d#ss/jobs/} | mu_r=$mur | [0-9.]* | [0-9.]* | $want | " ss/report.md ||
      fail "report.md: ${d#ss/jobs/} does not give cycle 2's gamma, E_eq, G_eq = $want: $(grep "${d#ss/jobs/}" ss/report.md)"
    # then G_eq/G_0, and D and D less the damping's drag (columns 9 and 18), the latter below D (the drag's area)
    want=$(echo "$last" | awk -F, '{printf "%.3f | %.3f", $9, $18}')
    grep -q "^| ${d#ss/jobs/} | .* | [0-9.]* | $want | [0-9.]* | " ss/report.md ||
      fail "report.md: ${d#ss/jobs/} does not give cycle 2's D, D less drag = $want: $(grep "${d#ss/jobs/}" ss/report.md)"
    echo "$last" | awk -F, '{exit !($18 > 0 && $18 < $9)}' || fail "$d/run/cycles.csv: D less drag not in (0, D): $last"
  done
  grep -q "^| $(job $mur 0.0001 | sed 's|ss/jobs/||') | .* | 1.000 | " ss/report.md || fail "mu_r $mur: G_eq/G_0 is not 1 at 1e-4"
  # the fit: E_max, eps_r, G_max, gamma_r, rms, D_min, D_max, the two less the drag, and Darendeli's gamma_r at p'_0
  grep -q "^| mu_r=$mur | 3 | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* | -*[0-9.]* | [0-9.]* | -*[0-9.]* | [0-9.]* | [0-9.]* |$" ss/report.md ||
    fail "report.md: no hyperbolic fit for mu_r $mur: $(grep "^| mu_r=$mur | 3" ss/report.md)"
done
[ -f ss/figures/modulus_reduction.png ] || fail "no figures/modulus_reduction.png"
grep -q "figures/modulus_reduction.png" ss/report.md || fail "report.md does not name figures/modulus_reduction.png"
grep -q "## Cyclic tests" ss/report.md && fail "report.md gives the strain-controlled tests a liquefaction section"
echo "study_strain: ok"; sed -n '/^| group/,$p' ss/report.md
