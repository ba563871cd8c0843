#!/usr/bin/env bash
# Concurrent A/B of two race_bench binaries (two builds of grainlab) on the shared race scene.
#
#   perf/ab.sh A/perf/race_bench B/perf/race_bench [PAIRS=4] [race_bench options...]
#   e.g. perf/ab.sh build-float/perf/race_bench build/perf/race_bench 4 --steps 1000
#   A_ARGS / B_ARGS: options for one side only (one binary, two settings), e.g.
#   A_ARGS="--inner 0.1" B_ARGS="--inner 0" perf/ab.sh build/perf/race_bench build/perf/race_bench 4 --steps 1000
#   An environment setting for one side: a wrapper script as that side's binary, e.g. for the glibc tunable
#   (perf/NOTES.md session 15): printf '#!/bin/sh\nGLIBC_TUNABLES=glibc.malloc.hugetlb=1 exec %s "$@"\n' \
#   "$PWD/build/perf/race_bench" > /tmp/tun.sh; chmod +x /tmp/tun.sh; perf/ab.sh /tmp/tun.sh build/perf/race_bench 6
#
# Why concurrent: this project's VM is a shared host whose speed drifts by up to 20 % from minute to
# minute, so two builds timed one after the other differ by more than the effects we measure (5-15 %).
# Here A and B run at the same time, one thread each, pinned to different cores, and then again with
# the cores swapped; each pair gives one ratio A/B under the same host conditions. Both runs share the
# L3 and the memory bus, so the rates are lower than a lone run's: quote the ratio, not the rates.
# Prints one line per run pair, then `median_ratio=X.XXX`, and checks that A and B end with the same
# kinetic energy (a speed-up that changes the dynamics is reported as such).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[ $# -ge 2 ] || { sed -n 2,7p "$0"; exit 2; }
A=$1 B=$2
shift 2
PAIRS=4
if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then PAIRS=$1; shift; fi
PEERS_DIR=${PEERS_DIR:-$ROOT/../shared/bench/peers}
[ -s "$PEERS_DIR/scene_32k.txt" ] || { echo "ab.sh: no scene at $PEERS_DIR/scene_32k.txt (set PEERS_DIR)"; exit 1; }
for b in "$A" "$B"; do [ -x "$b" ] || { echo "ab.sh: $b is not an executable"; exit 1; }; done
[ "$(nproc)" -ge 2 ] || { echo "ab.sh: needs 2 cores"; exit 1; }
args=(--scene "$PEERS_DIR/scene_32k.txt" --box "$PEERS_DIR/scene_32k_box.txt" "$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
field() { grep -oE "$1=[^ ]+" "$2" | cut -d= -f2; }
ratios=()
for ((k = 0; k < PAIRS; ++k)); do
  ca=$((k % 2)) cb=$((1 - k % 2))
  # shellcheck disable=SC2086
  OMP_NUM_THREADS=1 OMP_PROC_BIND=false taskset -c "$ca" "$A" "${args[@]}" ${A_ARGS:-} > "$tmp/a" &
  pa=$!
  # shellcheck disable=SC2086
  OMP_NUM_THREADS=1 OMP_PROC_BIND=false taskset -c "$cb" "$B" "${args[@]}" ${B_ARGS:-} > "$tmp/b" &
  pb=$!
  wait "$pa" "$pb"
  ra=$(field particle_steps_per_s "$tmp/a") rb=$(field particle_steps_per_s "$tmp/b")
  ka=$(field kinetic_J "$tmp/a") kb=$(field kinetic_J "$tmp/b")
  ratio=$(python3 -c "print('%.3f' % ($ra / $rb))")
  ratios+=("$ratio")
  echo "pair $((k + 1)): A on core $ca $ra, B on core $cb $rb, A/B $ratio, kinetic_J A $ka B $kb"
  [ "$ka" = "$kb" ] || echo "  note: A and B end with different kinetic energies (different dynamics)"
done
python3 -c "import statistics, sys; print('median_ratio=%.3f' % statistics.median(map(float, sys.argv[1:])))" "${ratios[@]}"
