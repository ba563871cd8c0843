#!/usr/bin/env bash
# Ctrl-C on a real process: SIGINT (and SIGHUP, and SIGPIPE: the reader of its lines gone) writes a checkpoint and
# exits with 130; --resume completes the run, and its series equals that of an uninterrupted run, byte for byte.
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "reference run failed"; exit 1; }
# Ctrl-C (INT) and a closed terminal or SSH session (HUP) alike.
for sig in INT HUP; do
  "$bin" run "$cfg" --out "$work/$sig" --quiet &
  pid=$!
  # Wait until the run is under way (its config.yaml is written at start), then interrupt it.
  for _ in $(seq 1 200); do [ -f "$work/$sig/config.yaml" ] && break; sleep 0.02; done
  sleep 0.3
  kill -"$sig" "$pid"
  wait "$pid"; rc=$?
  if [ "$rc" -eq 0 ]; then echo "run finished before SIG$sig: make the config longer"; exit 1; fi
  [ "$rc" -eq 130 ] || { echo "expected exit 130 after SIG$sig, got $rc"; exit 1; }
  ls "$work/$sig"/checkpoints/ckpt_*.h5 >/dev/null 2>&1 || { echo "no checkpoint after SIG$sig"; exit 1; }
  "$bin" run "$cfg" --out "$work/$sig" --resume --quiet || { echo "resume after SIG$sig failed"; exit 1; }
  cmp "$work/ref/series.csv" "$work/$sig/series.csv" || { echo "series resumed after SIG$sig differs"; exit 1; }
done
# `grainlab run ... | head -n 1`: head exits after the first line, and the run's next progress line meets a closed
# pipe. By default SIGPIPE killed the run there (exit 141) with nothing saved since its step-0 checkpoint.
"$bin" run "$cfg" --out "$work/PIPE" 2>"$work/pipe_err.txt" | head -n 1 >/dev/null
rc=${PIPESTATUS[0]}
[ "$rc" -eq 130 ] || { echo "expected exit 130 after SIGPIPE, got $rc"; cat "$work/pipe_err.txt"; exit 1; }
grep -q "interrupted at step [1-9][0-9]* (the reader of its output closed the pipe)" "$work/pipe_err.txt" ||
  { echo "no interruption line naming the closed pipe:"; cat "$work/pipe_err.txt"; exit 1; }
# Resumed with another checkpoint cadence (checkpoints every 700 steps where the run had none by steps): the same
# run, said once, recorded in config.yaml; the series as uninterrupted.
sed 's/checkpoint_every: 0/checkpoint_every: 700/' "$cfg" > "$work/cadence.yaml"
out=$("$bin" run "$work/cadence.yaml" --out "$work/PIPE" --resume) || { echo "resume after SIGPIPE failed: $out"; exit 1; }
printf '%s\n' "$out" | grep -q "PIPE: checkpoints now every 700 steps and 0 minutes (0: off), the newest 2 kept; config.yaml records it" ||
  { echo "the new checkpoint cadence was not said: $out"; exit 1; }
grep -q "checkpoint_every: 700" "$work/PIPE/config.yaml" || { echo "config.yaml does not record the new cadence"; exit 1; }
cmp "$work/ref/series.csv" "$work/PIPE/series.csv" || { echo "series resumed after SIGPIPE differs"; exit 1; }
echo "sigint ok: INT, HUP and PIPE interrupted, checkpointed, resumed, identical series"
