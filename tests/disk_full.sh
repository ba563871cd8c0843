#!/usr/bin/env bash
# Disk full: writes beyond a file-size limit fail (EFBIG, as on a full disk; SIGXFSZ ignored). The run stops
# with a clear one-line error, exit != 0; files written before are intact (the checkpoints still load);
# with space again, --resume finishes with the same series as an uninterrupted run.
# Read-only output: a read-only file system gives a clear error too (skipped if none is available).
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
"$bin" run "$cfg" --out "$work/ref" --quiet || { echo "reference run failed"; exit 1; }
trap '' XFSZ
# A limit just above the reference's step-0 checkpoint: that file fits, the later, larger ones (sample,
# later checkpoints) do not. bash counts ulimit -f in 1024-byte blocks.
ck0=$(stat -c %s "$work"/ref/checkpoints/ckpt_000000000000.h5) || { echo "reference has no step-0 checkpoint"; exit 1; }
blocks=$(( (ck0 + 2048 + 1023) / 1024 ))
err=$( (ulimit -f "$blocks"; "$bin" run "$cfg" --out "$work/full" --quiet) 2>&1 >/dev/null ); rc=$?
trap - XFSZ
echo "exit $rc: $err"
[ "$rc" -eq 1 ] || { echo "expected exit 1 (a clean error) when the disk is full, got $rc"; exit 1; }
[ "$(printf '%s\n' "$err" | grep -c .)" -eq 1 ] || { echo "expected one error line"; exit 1; }
printf '%s\n' "$err" | grep -qE "disk full" || { echo "unclear message"; exit 1; }
ls "$work"/full/checkpoints/ckpt_*.h5 >/dev/null 2>&1 || { echo "no checkpoint survived"; exit 1; }
ls "$work"/full/*.tmp.* "$work"/full/checkpoints/*.tmp.* 2>/dev/null && { echo "temporary files left behind"; exit 1; }
"${GRAINLAB_PYTHON:-/usr/bin/python3}" - "$work/full" <<'PY' || exit 1
import glob, sys, h5py
for f in glob.glob(sys.argv[1] + "/checkpoints/ckpt_*.h5"):
    with h5py.File(f, "r") as h:
        assert h["state/x"].shape[1] == 3
print("earlier checkpoints intact")
PY
"$bin" run "$cfg" --out "$work/full" --resume --quiet || { echo "resume after freeing space failed"; exit 1; }
cmp "$work/ref/series.csv" "$work/full/series.csv" || { echo "series differ after resume"; exit 1; }
# Read-only file system (e.g. /sys in a container).
ro=""
for d in /sys /proc/sys; do
  if ! touch "$d/.grainlab_probe" 2>/dev/null; then ro=$d; break; fi
  rm -f "$d/.grainlab_probe"
done
if [ -n "$ro" ]; then
  err=$("$bin" run "$cfg" --out "$ro/grainlab_out" --quiet 2>&1 >/dev/null); rc=$?
  echo "read-only: exit $rc: $err"
  [ "$rc" -eq 1 ] && printf '%s\n' "$err" | grep -q "$ro/grainlab_out" || { echo "unclear read-only error"; exit 1; }
else
  echo "read-only check skipped: no read-only file system found"
fi
echo "disk-full ok"
