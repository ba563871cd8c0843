#!/usr/bin/env bash
# kill -9 at random moments, >= 20 times, each time resuming: the run always completes, and its series
# and final state equal those of an uninterrupted run, bitwise. The moments are drawn as shares of the uninterrupted
# run's wall time (0.5-3 % of it into each resume: all the kills land before the run can end, on any machine's speed;
# fixed 30-330 ms delays let a machine that runs the config in 2.5 s, not the 9 s it once took, finish after 14).
set -u
bin=$1; cfg=$2; work=$3; trials=${4:-20}
rm -rf "$work"; mkdir -p "$work"
t0=$(date +%s%N)
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "reference run failed"; exit 1; }
ref_ms=$((($(date +%s%N) - t0) / 1000000))
RANDOM=4242  # reproducible kill times (as shares of ref_ms)
killed=0
for t in $(seq 1 "$trials"); do
  "$bin" run "$cfg" --out "$work/int" --resume --quiet &
  pid=$!
  ms=$((ref_ms * (5 + RANDOM % 26) / 1000))
  delay=$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))
  sleep "$delay"
  if kill -9 "$pid" 2>/dev/null; then killed=$((killed + 1)); fi
  wait "$pid" 2>/dev/null
done
echo "killed $killed of $trials attempts (the uninterrupted run: $ref_ms ms)"
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
