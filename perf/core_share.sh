#!/usr/bin/env bash
# Reproduces what the README and src/simulation.cpp (Laboratory::watch_core_share) quote about runs that share their
# cores with other processes, as medians of REPS rounds: a 400-sphere isotropic stage (8 800 steps) at 2 threads
#   alone, two of them started together, and one beside a busy loop (session 48 on the 2-core VM, single rounds:
#   0.26-0.30 s alone, 37 s each together, 3.0 s beside the busy loop),
# and with `bench`, two 10 000-sphere race_bench runs at once against one alone (2.2e6 particle-steps/s each against
#   7-9e6; one round of this script: 3.4e6 against 9.3e6). Wall seconds of each run; GOMP_SPINCOUNT or OMP_WAIT_POLICY in the environment pass through (perf/NOTES.md
#   session 48 compares them).
# Usage: [GRAINLAB_BIN=other/grainlab] perf/core_share.sh [run | bench] [REPS]   (build/ first; default: run, 1 round:
#   the pair alone takes ~80 s)
set -eu
what=${1:-run}; reps=${2:-1}
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${GRAINLAB_BIN:-$root/build/grainlab}
work=$(mktemp -d)
busy=
trap '[ -n "$busy" ] && kill $busy 2> /dev/null; rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }
echo "machine: $(nproc) cores usable, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
if [ "$what" = run ]; then
  printf 'sample: {count: 400, seed: 3, density_scaling: 1000}\nstages:\n  - {name: consolidate, type: isotropic, pressure: 200e3, mu: 0.3}\noutput: {every: 500, checkpoint_every: 0, checkpoint_minutes: 0}\n' > "$work/c.yaml"
  one() {  # one OUT: a run's wall seconds
    local s e
    s=$(date +%s.%N)
    "$bin" run "$work/c.yaml" --out "$work/$1" --threads 2 --quiet > /dev/null 2>&1 || true
    e=$(date +%s.%N)
    rm -rf "$work/$1"
    echo "$e - $s" | bc
  }
  alone=$(for k in $(seq "$reps"); do one a$k; done | median)
  echo "alone (median of $reps): $alone s"
  together=$(for k in $(seq "$reps"); do one p$k > "$work/t1" & one q$k > "$work/t2"; wait; cat "$work/t1" "$work/t2"; done | median)
  echo "two at once (median of the $((2 * reps)) runs): $together s each"
  sh -c 'while :; do :; done' &
  busy=$!
  beside=$(for k in $(seq "$reps"); do one b$k; done | median)
  kill $busy
  busy=
  echo "beside a busy loop (median of $reps): $beside s"
elif [ "$what" = bench ]; then
  rb=$(dirname "$bin")/perf/race_bench
  rate() { "$rb" --generate 10000 --steps 300 --reps 3 2>&1 | tail -3 | sed 's/.*particle_steps_per_s=\([^ ]*\).*/\1/' | median; }
  alone=$(for _ in $(seq "$reps"); do rate; done | median)
  echo "race_bench 10 000 spheres alone (median): $alone particle-steps/s"
  together=$(for _ in $(seq "$reps"); do rate > "$work/r1" & rate > "$work/r2"; wait; cat "$work/r1" "$work/r2"; done | median)
  echo "two at once (median): $together particle-steps/s each"
else
  echo "usage: perf/core_share.sh [run | bench] [REPS]" >&2
  exit 2
fi
