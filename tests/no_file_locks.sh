#!/usr/bin/env bash
# no_file_locks.sh GRAINLAB PRELOAD SMOKE DIR: on a filesystem without file locks (PRELOAD, tests/no_flock.c: flock
# fails with ENOSYS as on Lustre without -o flock, or ENOLCK as on NFS without its lock daemon) a run starts, says once
# that its directory is not locked, writes its HDF5 files and resumes from them; a study the same. Before, every run
# there was refused as "in use by another grainlab process", and under ENOLCK HDF5 failed to open every checkpoint.
set -u
bin=$1 preload=$2 smoke=$3 dir=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
for e in ENOSYS ENOLCK; do
  # shellcheck disable=SC2097,SC2098
  run() { NO_FLOCK_ERRNO=$e LD_PRELOAD=$preload "$bin" run "$smoke" --out "$e" --quiet "$@"; }
  run --stop-after-steps 300 2> "$e.err"; rc=$?
  [ "$rc" -eq 130 ] || { cat "$e.err"; fail "$e: the run exited $rc, not 130 (stopped at step 300)"; }
  [ "$(grep -c "^grainlab: warning: $e/.lock: this filesystem does not lock files (flock: " "$e.err")" -eq 1 ] ||
    { cat "$e.err"; fail "$e: not one warning naming the unlocked directory"; }
  run --resume 2> "$e.err2" || { cat "$e.err2"; fail "$e: the resumed run failed"; }
  grep -q "^grainlab: warning: $e/.lock: this filesystem does not lock files" "$e.err2" ||
    fail "$e: the resumed run did not warn"
  h5dump -H "$e/run.h5" > /dev/null 2>&1 || fail "$e: run.h5 does not read back"
done
# without the preload: the lock is taken, and nothing is said
"$bin" run "$smoke" --out locked --quiet --stop-after-steps 100 2> locked.err
grep -q "does not lock files" locked.err && fail "a warning where the filesystem locks: $(cat locked.err)"
# a study's own lock (its jobs' runs warn in their logs)
printf 'base: %s\naxes: {mu_r: [0.1]}\n' "$smoke" > study.yaml
LD_PRELOAD=$preload "$bin" study study.yaml --out st --jobs 1 --quiet > st.out 2> st.err ||
  { cat st.err; fail "the study failed without file locks"; }
grep -q "^grainlab: warning: st/.lock: this filesystem does not lock files" st.err ||
  fail "the study did not warn: $(cat st.err)"
echo "ok: runs (ENOSYS, ENOLCK) and a study without file locks start, warn once, write and resume"
