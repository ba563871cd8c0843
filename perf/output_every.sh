#!/usr/bin/env bash
# What a dense series costs a run: configs/quick.yaml (3 000 spheres, consolidation and a 5 % shear, ~82 000 steps)
# at output.every = each EVERY given, wall seconds as medians of REPS runs at 2 threads, and the rows and bytes written
# (series.csv, run.h5). A row measures the micromechanics (SPEC §7) once; the run rewrites series.csv and run.h5 whole
# (atomically) as it goes (src/simulation.cpp, output_flush_due). Session 45 on the 2-core VM: every 1000 / 100 / 10 =
# 84 / 819 / 8 170 rows, times in perf/NOTES.md (before the text of each row was kept and the writes paced, every 10
# took 70.3 s against 16.1 s at every 1000, GRAINLAB_BIN of 954da91: each write formatted every row again).
# Usage: [GRAINLAB_BIN=other/grainlab] perf/output_every.sh [REPS] [EVERY...]   (build/ first; default: 3 1000 100 10)
set -eu
reps=${1:-3}
shift || true
everies=${*:-1000 100 10}
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${GRAINLAB_BIN:-$root/build/grainlab}  # GRAINLAB_BIN: another build (a base to compare with)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }
echo "machine: $(nproc) cores usable, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
for every in $everies; do
  sed "s/^  every: .*/  every: $every/" "$root/configs/quick.yaml" > "$work/e$every.yaml"
  grep -q "^  every: $every\$" "$work/e$every.yaml" || { echo "configs/quick.yaml has no output.every line" >&2; exit 1; }
  t=$(for k in $(seq "$reps"); do
        s=$(date +%s.%N)
        "$bin" run "$work/e$every.yaml" --out "$work/r$k" --threads 2 --quiet > /dev/null
        e=$(date +%s.%N)
        echo "$e - $s" | bc
        rows=$(($(wc -l < "$work/r$k/series.csv") - 1))
        echo "$rows rows, series.csv $(stat -c %s "$work/r$k/series.csv") B, run.h5 $(stat -c %s "$work/r$k/run.h5") B" \
          > "$work/rows"
        rm -rf "$work/r$k"
      done | median)
  echo "output.every $every: $(cat "$work/rows"), $t s (median of $reps)"
done
