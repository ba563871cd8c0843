#!/usr/bin/env bash
# lab_threads.sh GRAINLAB CONFIG DIR: the config's run at 1 and at 2 threads ends in the same state bit for bit: the
# final checkpoint's /state (positions, velocities, spins, forces, contact pairs and their tangential and rolling
# histories, walls, scalars) and /lab (the series and stage results to the bit, e_inner and e_core among them) by
# h5diff, run.h5's /series, and the same series.csv and cycles.csv. Each stage must have run (a row in the series), and
# each run with the threads asked for (summary.json's build line) on a host backend; on a GPU the two runs are two
# runs on the device.
set -u
bin=$1 cfg=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
for t in 1 2; do
  "$bin" run "$cfg" --out "$dir/t$t" --threads "$t" --quiet 2> "$dir/t$t.err" ||
    { cat "$dir/t$t.err"; fail "the run at $t threads"; }
  build=$(grep -o '"build": "[^"]*"' "$dir/t$t/summary.json")
  case "$build" in
    *"OpenMP x"*) printf '%s\n' "$build" | grep -q "OpenMP x $t;" || fail "asked for $t threads, ran $build" ;;
  esac
done
stages=$(grep -oE '^ *- \{name: [a-z0-9_]+' "$cfg" | sed 's/.*name: //')
for s in $stages; do
  grep -q "^$s," "$dir/t1/series.csv" || fail "stage $s has no row in the series: it did not run"
done
last=$(ls "$dir/t1/checkpoints" | tail -1) last2=$(ls "$dir/t2/checkpoints" | tail -1)
[ "$last" = "$last2" ] || fail "the runs' last checkpoints differ: $last, $last2"
for g in /state /lab; do
  h5diff "$dir/t1/checkpoints/$last" "$dir/t2/checkpoints/$last" $g $g > "$dir/diff.txt" ||
    { head -20 "$dir/diff.txt"; fail "$last's $g at 1 and 2 threads differs"; }
done
h5diff "$dir/t1/run.h5" "$dir/t2/run.h5" /series /series > "$dir/diff.txt" ||
  { head -20 "$dir/diff.txt"; fail "run.h5's /series at 1 and 2 threads differs"; }
for f in series.csv cycles.csv; do
  cmp "$dir/t1/$f" "$dir/t2/$f" || fail "$f differs between 1 and 2 threads"
done
echo "lab_threads ok: $(echo $stages | wc -w) stages, $last the same state at 1 and 2 threads"
