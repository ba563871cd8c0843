#!/usr/bin/env bash
# Alternating 2-thread A/B of two race_bench binaries on the shared race scene.
#
#   perf/ab2.sh A/perf/race_bench B/perf/race_bench [RUNS=12] [race_bench options...]
#   A_ARGS / B_ARGS: options for one side only, as in perf/ab.sh.
#
# perf/ab.sh runs A and B at the same time, one thread each; that cannot measure what only shows with two
# threads (load balance, barriers). Here A and B each take both cores, one after the other (the order swapped
# every run), RUNS times; each
# pair of neighbouring runs gives one ratio A/B, and the median of the ratios is printed as
# `median_ratio=X.XXX`. This host's 2-thread speed swings by up to 1.6x within minutes, so use short runs
# (e.g. --steps 500 --warmup 100) and >= 10 pairs. Also checks that A and B end with the same kinetic energy.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[ $# -ge 2 ] || { sed -n 2,5p "$0"; exit 2; }
A=$1 B=$2
shift 2
RUNS=12
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then RUNS=$1; shift; fi
PEERS_DIR=${PEERS_DIR:-$ROOT/../shared/bench/peers}
[ -s "$PEERS_DIR/scene_32k.txt" ] || { echo "ab2.sh: no scene at $PEERS_DIR/scene_32k.txt (set PEERS_DIR)"; exit 1; }
for b in "$A" "$B"; do [ -x "$b" ] || { echo "ab2.sh: $b is not an executable"; exit 1; }; done
args=(--scene "$PEERS_DIR/scene_32k.txt" --box "$PEERS_DIR/scene_32k_box.txt" "$@")
export OMP_NUM_THREADS=2 OMP_PROC_BIND=spread OMP_PLACES=threads
field() { grep -oE "$1=[^ ]+" <<<"$2" | cut -d= -f2; }
ratios=()
for ((k = 1; k <= RUNS; ++k)); do
  # A first on odd runs, B first on even ones: the order bias cancels (an A/A check of 2 runs of 100 steps
  # with A always first gave 0.93).
  # shellcheck disable=SC2086
  if ((k % 2)); then
    a=$("$A" "${args[@]}" ${A_ARGS:-}); b=$("$B" "${args[@]}" ${B_ARGS:-})
  else
    b=$("$B" "${args[@]}" ${B_ARGS:-}); a=$("$A" "${args[@]}" ${A_ARGS:-})
  fi
  ra=$(field particle_steps_per_s "$a") rb=$(field particle_steps_per_s "$b")
  ka=$(field kinetic_J "$a") kb=$(field kinetic_J "$b")
  r=$(/usr/bin/python3 -c "print('%.3f' % ($ra / $rb))")
  ratios+=("$r")
  echo "run $k: A $ra, B $rb, A/B $r, kinetic_J A $ka B $kb"
  [ "$ka" = "$kb" ] || echo "ab2.sh: A and B end with different kinetic energies (different dynamics)"
done
/usr/bin/python3 -c "import statistics, sys; print('median_ratio=%.3f' % statistics.median(map(float, sys.argv[1:])))" "${ratios[@]}"
