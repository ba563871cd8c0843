#!/usr/bin/env bash
# Ctrl-C on a real process: SIGINT writes a checkpoint and exits with 130; --resume completes the run,
# and its series equals that of an uninterrupted run, byte for byte.
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "reference run failed"; exit 1; }
"$bin" run "$cfg" --out "$work/int" --quiet &
pid=$!
# Wait until the run is under way (its config.yaml is written at start), then interrupt it.
for _ in $(seq 1 200); do [ -f "$work/int/config.yaml" ] && break; sleep 0.02; done
sleep 0.3
kill -INT "$pid"
wait "$pid"; rc=$?
if [ "$rc" -eq 0 ]; then echo "run finished before the signal: make the config longer"; exit 1; fi
[ "$rc" -eq 130 ] || { echo "expected exit 130 after SIGINT, got $rc"; exit 1; }
ls "$work"/int/checkpoints/ckpt_*.h5 >/dev/null 2>&1 || { echo "no checkpoint after SIGINT"; exit 1; }
"$bin" run "$cfg" --out "$work/int" --resume --quiet || { echo "resume failed"; exit 1; }
cmp "$work/ref/series.csv" "$work/int/series.csv" || { echo "resumed series differs"; exit 1; }
echo "sigint ok: interrupted, checkpointed, resumed, identical series"
