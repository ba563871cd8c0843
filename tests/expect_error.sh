#!/usr/bin/env bash
# expect_error.sh REGEX CMD ARGS...: CMD must exit non-zero and write exactly one line to stderr that
# matches REGEX (one clear error line, naming file and key).
set -u
regex=$1; shift
err=$("$@" 2>&1 >/dev/null); rc=$?
[ "$rc" -ne 0 ] || { echo "expected a non-zero exit, got 0"; exit 1; }
lines=$(printf '%s\n' "$err" | grep -c .)
[ "$lines" -eq 1 ] || { echo "expected one error line, got $lines:"; printf '%s\n' "$err"; exit 1; }
printf '%s\n' "$err" | grep -qE -- "$regex" || { echo "error does not match '$regex': $err"; exit 1; }
echo "ok (exit $rc): $err"
