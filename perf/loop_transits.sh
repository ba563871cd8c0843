#!/usr/bin/env bash
# Reproduces configs/README.md's table of cyclic loops against their quarter cycle in wave transits: +-1e-4 undrained
# strain cycles, the second cycle's E_eq and D from cycles.csv (and D less the local damping's drag: the contacts' loop),
# at several quarter-cycle times t_q, on
#   small: the tests' 250-sphere sample (test_lab's kSmall: seed 5, mu_r 0.2, consolidated at mu 0.3), damping 0.2;
#   quick: configs/modulus-study-base.yaml's 3 000-sphere sample at mu_r 0.3, damping 0.1.
# Usage: perf/loop_transits.sh [small|quick] [WORK_DIR]   (small ~3 s, quick ~15 s on 2 cores; build/ first)
set -eu
which=${1:-small}; work=${2:-/tmp/grainlab_loop_transits}
bin=$(cd "$(dirname "$0")/.." && pwd)/build/grainlab
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work/$which" && cd "$work/$which"
if [ "$which" = small ]; then
  mur=0.2 damping=0.2 tqs="0.25 0.5 1 2 3 5 10 20" extra=""
  printf '%s\n' "sample: {count: 250, seed: 5, density_scaling: 1000}" "material: {mu_r: 0.2}" "stages:" \
    "  - {name: consolidate, type: isotropic, mu: 0.3, max_steps: 60000, ufr_tolerance: 0.02}" \
    "output: {every: 500, checkpoint_every: 0, checkpoint_minutes: 0}" > sample.yaml
else
  mur=0.3 damping=0.1 tqs="0.7 1.4 3 6 12.5 25" extra=", mu: 0.5"
  sed -e '/name: loops/d' -e 's/mu_r: 0.1/mu_r: 0.3/' "$src"/configs/modulus-study-base.yaml > sample.yaml
fi
[ -f sample/sample_consolidate.h5 ] || { rm -rf sample; "$bin" run sample.yaml --out sample --quiet; }
echo "| t_q [ms] | transits | E_eq [MPa] | D | D less drag |"
echo "|---|---|---|---|---|"
for tq in $tqs; do
  rate=$(awk -v t="$tq" 'BEGIN { printf "%.12g", 1e-4 / (t * 1e-3) }')
  printf '%s\n' "sample: {file: sample/sample_consolidate.h5}" "material: {mu_r: $mur}" "stages:" \
    "  - {name: cyc, type: cyclic, drainage: undrained, strain_amplitude: 1.0e-4, cycles: 2, axial_strain_rate: $rate, damping: $damping$extra}" \
    "output: {every: 1000, checkpoint_every: 0, checkpoint_minutes: 0}" > "loop$tq.yaml"
  transits=$("$bin" validate "loop$tq.yaml" 2>/dev/null | grep -o "= [0-9.e+-]* wave transits" | awk '{print $2}')
  rm -rf "loop$tq"; "$bin" run "loop$tq.yaml" --out "loop$tq" --quiet 2>/dev/null
  tail -1 "loop$tq/cycles.csv" | awk -F, -v t="$tq" -v n="$transits" '{ printf "| %s | %s | %.1f | %.3f | %.3f |\n", t, n, $8 / 1e6, $9, $18 }'
done
