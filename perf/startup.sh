#!/usr/bin/env bash
# Reproduces two numbers the README and the code quote about a run's start, as medians of REPS runs:
#   placement: `grainlab validate` of a generated sample of N spheres (the default sample spec at 0.3 solid fraction),
#     which places it as the run will (src/packing.cpp: 2e5 spheres in 0.52-0.77 s on the 2-core VM in session 43,
#     flat cells; 0.82 s in session 42 with a heap block per cell, 1.53 s before the cells kept their spheres'
#     coordinates);
#   threads: the tests' 300-sphere smoke run (tests/data/smoke.yaml) at 1 .. MAX threads, to see what threads beyond
#     the cores cost (src/main.cpp's warning; session 42 on the 2-core VM, medians of 3: 0.60 s at 1 thread, 0.47 s at
#     2, 5.6 s at 3, 6.0 s at 4; session 70's 2-core VM, medians of 5: 0.51 s at 1 thread, 0.77 s at 2).
#   start: a run of N spheres to its step-0 checkpoint (default 1e6: 7.0 s, placement half of it; 14.9 s with session
#     42's placement; session 43);
#   import: `grainlab import` of the shared race scene tiled K^3 times (race_bench --write-scene; default K = 3: 864 000
#     spheres, 66 MiB of text), its time and peak memory (session 64, 2-core VM: median of 3 1.89 s, 403 MB);
#   validate: the smallest commands, `grainlab validate` of a config refused at its first key and of the tests' smoke
#     config, with their page faults (fuzz_configs runs 1 300 such commands; session 70, 2-core VM, medians of 11,
#     /usr/bin/time's start included: 57 and 58 ms, ~2 720 faults, when a config was read into a zeroed 4 MiB string;
#     34 and 36 ms, 670 and 696 faults, read in blocks; session 71, HDF5's static archive: 41 and 44 -> 24 and 25 ms,
#     670 and 697 -> 228 and 257 faults).
#   sizes: 1 against 2 threads on samples of 250 to 8 000 spheres (an isotropic stage of 4 000 steps, whole process),
#     the measurement behind a run's default thread count (a thread a 1 000 spheres; session 71, 2-core VM, medians of
#     3, 2 threads / 1: 1.35, 1.24, 1.06, 0.87, 0.68, 0.58).
#   bound: a two-job study under OpenMP binding, on one place and unbound (study.cpp's JobPlaces; session 73).
# Usage: [GRAINLAB_BIN=other/grainlab] perf/startup.sh [placement N | start N | threads MAX | import K] [REPS], or
#   perf/startup.sh validate [REPS], sizes - [REPS] or bound - [REPS]   (build/ first; default: placement 200000, 3
#   reps; validate 11)
set -eu
what=${1:-placement}; arg=${2:-}; reps=${3:-3}
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${GRAINLAB_BIN:-$root/build/grainlab}  # GRAINLAB_BIN: another build (a base to compare with)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2)}'; }
seconds() { local s e; s=$(date +%s.%N); "$@" > /dev/null 2>&1 || true; e=$(date +%s.%N); echo "$e - $s" | bc; }
echo "machine: $(nproc) cores usable, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
if [ "$what" = placement ]; then
  n=${arg:-200000}
  printf 'sample: {count: %s}\nstages: [{type: isotropic, max_steps: 1}]\n' "$n" > "$work/p.yaml"
  t=$(for _ in $(seq "$reps"); do seconds "$bin" validate "$work/p.yaml"; done | median)
  "$bin" validate "$work/p.yaml" | head -1
  echo "placement of $n spheres (validate, median of $reps): $t s"
elif [ "$what" = start ]; then
  # a run's start past validate's placement limit (kPlaceCheckMax, 2e5): placement, the first neighbour list and
  # the step-0 checkpoint
  n=${arg:-1000000}
  printf 'sample: {count: %s}\nstages: [{type: isotropic, max_steps: 1}]\n' "$n" > "$work/s.yaml"
  t=$(for k in $(seq "$reps"); do seconds "$bin" run "$work/s.yaml" --out "$work/s$k" --stop-after-steps 0 --quiet; \
        rm -rf "$work/s$k"; done | median)
  echo "start of a run of $n spheres (to its step-0 checkpoint, median of $reps): $t s"
elif [ "$what" = threads ]; then
  max=${arg:-4}
  for t in $(seq 1 "$max"); do
    s=$(for k in $(seq "$reps"); do
          seconds "$bin" run "$root/tests/data/smoke.yaml" --out "$work/t${t}_$k" --threads "$t" --quiet
        done | median)
    echo "smoke run at $t thread(s) (median of $reps): $s s"
  done
elif [ "$what" = sizes ]; then
  # 1 against 2 threads by sample size: an isotropic stage of 4 000 steps, whole process, alternating (main.cpp's
  # default thread count, kSpheresPerThread)
  for n in 250 500 1000 2000 4000 8000; do
    printf 'sample: {count: %s, seed: 3, density_scaling: 1000}\nmaterial: {mu_r: 0.1}\n' "$n" > "$work/n.yaml"
    printf 'stages:\n  - {name: c, type: isotropic, mu: 0.3, max_steps: 4000, ufr_tolerance: 1e-12}\n' >> "$work/n.yaml"
    : > "$work/n1"; : > "$work/n2"
    for k in $(seq "$reps"); do
      for t in 1 2; do
        seconds "$bin" run "$work/n.yaml" --out "$work/n${t}_$k" --threads "$t" --quiet >> "$work/n$t"
        rm -rf "$work/n${t}_$k"
      done
    done
    m1=$(median < "$work/n1"); m2=$(median < "$work/n2")
    echo "$n spheres (medians of $reps): 1 thread $m1 s, 2 threads $m2 s, 2/1 $(echo "scale=3; $m2 / $m1" | bc)"
  done
elif [ "$what" = bound ]; then
  # A study of two 2 000-sphere preparations (15 000 steps of configs/quick.yaml's consolidation, mu_r 0.1 and 0.2),
  # --jobs 2, whole command, under OpenMP binding (OMP_PROC_BIND=true: each job on its own places, study.cpp's
  # JobPlaces), bound to one place (OMP_PLACES={0}: what every job inherited before), and unbound; rounds alternate
  # (session 73, 2-core VM, two rounds by hand: 2.83 / 2.61, 4.97 / 4.80, 2.88 / 2.95 s).
  sed -e '/^  - name: shear/,/^output:/{/^output:/!d}' -e 's/max_steps: 200000/max_steps: 15000/' \
      -e 's/count: 3000/count: 2000/' "$root/configs/quick.yaml" > "$work/base.yaml"
  printf 'base: base.yaml\naxes:\n  mu_r: [0.1, 0.2]\n' > "$work/study.yaml"
  for mode in bound one unbound; do : > "$work/b.$mode"; done
  for k in $(seq "$reps"); do
    for mode in bound one unbound; do
      case $mode in bound) e=OMP_PROC_BIND=true ;; one) e="OMP_PLACES={0}" ;; *) e=OMP_PROC_BIND=false ;; esac
      seconds env "$e" GRAINLAB_FIGURE_FORMATS=png "$bin" study "$work/study.yaml" --out "$work/st_${mode}_$k" \
        --jobs 2 --quiet >> "$work/b.$mode"
      rm -rf "$work/st_${mode}_$k"
    done
  done
  for mode in bound one unbound; do echo "two-job study, $mode (median of $reps): $(median < "$work/b.$mode") s"; done
elif [ "$what" = import ]; then
  k=${arg:-3}
  peers=${PEERS_DIR:-$root/../shared/bench/peers}
  "$root/build/perf/race_bench" --scene "$peers/scene_32k.txt" --box "$peers/scene_32k_box.txt" --tile "$k" \
    --write-scene "$work/scene" > /dev/null
  for r in $(seq "$reps"); do
    /usr/bin/time -f "%e %M" -o "$work/time$r" "$bin" import "$work/scene.txt" --box "$work/scene_box.txt" \
      --out "$work/s$r.h5" > "$work/import.txt"
    rm -f "$work/s$r.h5"
  done
  head -1 "$work/import.txt"
  echo "import of the race scene tiled ${k}^3 ($(du -m "$work/scene.txt" | cut -f1) MiB of text, median of $reps):" \
       "$(cat "$work"/time* | cut -d' ' -f1 | median) s, peak $(cat "$work"/time* | cut -d' ' -f2 | median) kB"
elif [ "$what" = validate ]; then
  reps=${arg:-11}
  printf 'sample: {cuont: 10}\nstages: [{type: isotropic}]\n' > "$work/bad.yaml"
  for cfg in "$work/bad.yaml" "$root/tests/data/smoke.yaml"; do
    for r in $(seq "$reps"); do  # the wall time in ms (time's %e has 10 ms steps), its page faults
      s=$(date +%s%N)
      /usr/bin/time -f "%R" -o "$work/faults" "$bin" validate "$cfg" > /dev/null 2>&1 || true
      echo "$(( ($(date +%s%N) - s) / 1000000 )) $(tail -1 "$work/faults")" >> "$work/v.$(basename "$cfg")"
    done
    echo "validate $(basename "$cfg") (median of $reps): $(cut -d' ' -f1 "$work/v.$(basename "$cfg")" | median) ms," \
         "$(cut -d' ' -f2 "$work/v.$(basename "$cfg")" | median) page faults"
  done
else
  echo "usage: perf/startup.sh [placement N | start N | threads MAX | import K] [REPS], or validate [REPS], or" \
       "sizes - [REPS], or bound - [REPS]" >&2
  exit 2
fi
