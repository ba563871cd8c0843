#!/usr/bin/env bash
# kill -9 at random moments, >= 20 times, each time resuming: the run always completes, and its series
# and final state equal those of an uninterrupted run, bitwise.
set -u
bin=$1; cfg=$2; work=$3; trials=${4:-20}
rm -rf "$work"; mkdir -p "$work"
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "reference run failed"; exit 1; }
RANDOM=4242  # reproducible kill times
killed=0
for t in $(seq 1 "$trials"); do
  "$bin" run "$cfg" --out "$work/int" --resume --quiet &
  pid=$!
  delay=$(printf '0.%03d' $((30 + RANDOM % 300)))
  sleep "$delay"
  if kill -9 "$pid" 2>/dev/null; then killed=$((killed + 1)); fi
  wait "$pid" 2>/dev/null
done
echo "killed $killed of $trials attempts"
[ "$killed" -ge "$trials" ] || { echo "the run finished before all kills: make the config longer"; exit 1; }
"$bin" run "$cfg" --out "$work/int" --resume --quiet || { echo "final resume failed"; exit 1; }
cmp "$work/ref/series.csv" "$work/int/series.csv" || { echo "series differ"; exit 1; }
"${GRAINLAB_PYTHON:-/usr/bin/python3}" - "$work" <<'PY' || exit 1
import glob, sys, h5py, numpy as np
w = sys.argv[1]
a = h5py.File(sorted(glob.glob(w + "/ref/checkpoints/ckpt_*.h5"))[-1], "r")
b = h5py.File(sorted(glob.glob(w + "/int/checkpoints/ckpt_*.h5"))[-1], "r")
for d in ["state/x", "state/v", "state/w", "state/ft", "state/mr", "state/walls", "state/scalars"]:
    if a[d][:].tobytes() != b[d][:].tobytes():
        sys.exit(f"final {d} differs")
print("final state bitwise identical")
PY
echo "kill/resume ok"
