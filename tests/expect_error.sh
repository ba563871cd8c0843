#!/usr/bin/env bash
# expect_error.sh [--ignore REGEX0] REGEX CMD ARGS...: CMD must exit non-zero and write exactly one line to stderr
# that matches REGEX (one clear error line, naming file and key). --ignore drops the lines matching REGEX0 first, and
# they must be there: a library's own line printed before grainlab runs (libgomp reads OMP_NUM_THREADS at load).
set -u
ignore=
if [ "$1" = --ignore ]; then ignore=$2; shift 2; fi
regex=$1; shift
err=$("$@" 2>&1 >/dev/null); rc=$?
if [ -n "$ignore" ]; then
  printf '%s\n' "$err" | grep -qE -- "$ignore" || { echo "expected a line matching '$ignore' before the error: $err"; exit 1; }
  err=$(printf '%s\n' "$err" | grep -vE -- "$ignore" | grep .)
fi
[ "$rc" -ne 0 ] || { echo "expected a non-zero exit, got 0"; exit 1; }
lines=$(printf '%s\n' "$err" | grep -c .)
[ "$lines" -eq 1 ] || { echo "expected one error line, got $lines:"; printf '%s\n' "$err"; exit 1; }
printf '%s\n' "$err" | grep -qE -- "$regex" || { echo "error does not match '$regex': $err"; exit 1; }
echo "ok (exit $rc): $err"
