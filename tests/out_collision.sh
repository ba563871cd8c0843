#!/usr/bin/env bash
# A run that starts afresh never replaces a file it did not write (README "What grainlab guarantees"):
#  1. --out into a folder that holds the user's own config.yaml: one error line naming it, exit 1, the file
#     byte for byte as before, and nothing created there (no .lock, no checkpoints/);
#  2. the same with --resume (nothing to resume, so it would start afresh);
#  3. a folder holding particles.xdmf, or a sample file of one of the config's stages: refused the same way;
#  4. a run killed before its first checkpoint (its own config.yaml, .lock, empty checkpoints/) starts again,
#     with and without --resume: its config.yaml is the same text, so replacing it loses nothing.
#  5. a study's directory (its study.json) and its jobs folder are not a run's, nor a run's directory a study's: each
#     refused with one line, nothing created there; `plot` of a study's directory says where its figures and runs are.
#  6. a run's own config.yaml records its directory and runs there: `grainlab run RUN/config.yaml --resume` resumes RUN.
# Bad counts on the command line (--threads, --jobs, --stop-after-steps) get one line with the range, exit 2.
# A sample too large for the memory is refused before anything is written.
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
# expect RC REGEX CMD...: exit code RC and exactly one stderr line matching REGEX.
expect() {
  local want=$1 regex=$2; shift 2
  local err rc
  err=$("$@" 2>&1 >/dev/null); rc=$?
  [ "$rc" -eq "$want" ] || fail "expected exit $want, got $rc: $* -> $err"
  [ "$(printf '%s\n' "$err" | grep -c .)" -eq 1 ] || fail "expected one error line: $err"
  printf '%s\n' "$err" | grep -qE -- "$regex" || fail "error does not match '$regex': $err"
  echo "ok (exit $rc): $err"
}

# 1 and 2: the user's own config.yaml.
mkdir "$work/mine"
printf 'my notes: keep me\n' > "$work/mine/config.yaml"
before=$(md5sum < "$work/mine/config.yaml")
for resume in "" --resume; do
  expect 1 "mine: already holds config.yaml, which this run would overwrite" \
    "$bin" run "$cfg" --out "$work/mine" --quiet $resume
  [ "$(md5sum < "$work/mine/config.yaml")" = "$before" ] || fail "config.yaml changed ($resume)"
done
[ "$(ls -A "$work/mine")" = "config.yaml" ] || fail "the refused run created files: $(ls -A "$work/mine")"

# 3: other names a run writes.
mkdir "$work/xdmf" "$work/sample"
echo '<Xdmf/>' > "$work/xdmf/particles.xdmf"
echo 'not a sample' > "$work/sample/sample_consolidate.h5"
expect 1 "xdmf: already holds particles.xdmf" "$bin" run "$cfg" --out "$work/xdmf" --quiet
expect 1 "sample: already holds sample_consolidate.h5" "$bin" run "$cfg" --out "$work/sample" --quiet
[ "$(cat "$work/sample/sample_consolidate.h5")" = "not a sample" ] || fail "sample_consolidate.h5 changed"

# 4: killed before the first checkpoint. --stop-after-steps 0 stops at once with the step-0 checkpoint written
# (exit 130, like Ctrl-C). The series and run.h5 are written after each checkpoint, so removing those three
# leaves what a kill during the first checkpoint's write leaves.
killed_early() { rm -f "$work/killed"/checkpoints/* "$work/killed/series.csv" "$work/killed/run.h5"; }
"$bin" run "$cfg" --out "$work/killed" --quiet --stop-after-steps 0 2>/dev/null
[ $? -eq 130 ] || fail "--stop-after-steps 0 did not stop the run with exit 130"
killed_early
"$bin" run "$cfg" --out "$work/killed" --quiet --stop-after-steps 0 2>/dev/null
[ $? -eq 130 ] || fail "a run killed before its first checkpoint could not start again"
killed_early
"$bin" run "$cfg" --out "$work/killed" --quiet --resume --stop-after-steps 0 2>/dev/null
[ $? -eq 130 ] || fail "a run killed before its first checkpoint could not start again with --resume"

# 5: a study's directory and a run's are each the other's no place.
mkdir -p "$work/st/jobs"
echo '{}' > "$work/st/study.json"
expect 1 "st: holds a study \(grainlab study --out\); a run's --out is a directory of its own \(nothing was changed\)" \
  "$bin" run "$cfg" --out "$work/st" --quiet
expect 1 "st/jobs/: the jobs folder of a study; a run's --out is a directory of its own" \
  "$bin" run "$cfg" --out "$work/st/jobs/" --quiet
[ "$(ls -A "$work/st" | tr '\n' ' ')" = "jobs study.json " ] && [ -z "$(ls -A "$work/st/jobs")" ] ||
  fail "a refused run wrote into the study: $(ls -AR "$work/st")"
# plot and csl name a study's directory as such (its figures, its runs) rather than "not a run directory"
expect 1 "st: a study's directory, not a run's: its figures are in .*/st/figures \(grainlab study remakes them\), its runs are .*/st/jobs/\*/run$" \
  "$bin" plot "$work/st" --out "$work/st_figures"
[ ! -e "$work/st_figures" ] || fail "a refused plot made its --out"
printf 'base: %s\naxes: {mu_r: [0]}\n' "$cfg" > "$work/study.yaml"
before=$(ls -A "$work/killed")
expect 1 "killed: holds a run \(grainlab run --out\); a study's --out is a directory of its own \(nothing was changed\)" \
  "$bin" study "$work/study.yaml" --out "$work/killed" --quiet
[ "$(ls -A "$work/killed")" = "$before" ] || fail "a refused study wrote into the run: $(ls -A "$work/killed")"
# --out naming a file: one line each (the study's was std::filesystem's own text, plot's "File exists")
echo 'a file' > "$work/afile"
expect 1 "^grainlab: error: .*/afile: cannot create the study's directory \(Not a directory\)$" \
  "$bin" study "$work/study.yaml" --out "$work/afile" --quiet
expect 1 "^grainlab plot: error: .*/afile: a file, not a directory \(--out names the folder of the figures\)$" \
  "$bin" plot "$work/killed" --out "$work/afile"
[ "$(cat "$work/afile")" = "a file" ] || fail "the file named by --out changed"

# 6: a run's own config.yaml runs in its directory (from any working directory) and records it: it recorded the
# config's output.dir (here none, so runs/smoke), where `grainlab run RUN/config.yaml --resume` then went.
grep -q "^  dir: $work/killed\$" "$work/killed/config.yaml" || fail "config.yaml does not record --out: $(grep dir: "$work/killed/config.yaml")"
out=$(cd / && "$bin" run "$work/killed/config.yaml" --resume --stop-after-steps 0 2>/dev/null); rc=$?
[ "$rc" -eq 130 ] || fail "resuming from the run's own config.yaml: exit $rc: $out"
printf '%s\n' "$out" | head -1 | grep -q "^resuming from $work/killed/checkpoints/ckpt_" ||
  fail "the run's own config.yaml did not resume its run: $out"
expect 1 "killed: already holds a run \(series.csv\); continue it with --resume" \
  "$bin" run "$work/killed/config.yaml" --quiet

# Counts on the command line.
expect 2 "^grainlab: --threads must be an integer in \[1, 512\], got 'abc'$" \
  "$bin" run "$cfg" --out "$work/t" --threads abc
expect 2 "^grainlab: --jobs must be an integer in \[1, 4096\], got '0'$" \
  "$bin" study "$cfg" --out "$work/s" --jobs 0
expect 2 "^grainlab: --threads must be an integer in \[1, 512\], got '2.5'$" \
  "$bin" study "$cfg" --out "$work/s" --threads 2.5
expect 2 "^grainlab: --stop-after-steps must be an integer in \[0, 1000000000000\], got '-3'$" \
  "$bin" run "$cfg" --out "$work/t" --stop-after-steps -3
expect 2 "^grainlab: --out needs a value$" "$bin" run "$cfg" --out
# An unknown command or option: its own line first, then the usage (which is not one line).
err=$("$bin" frobnicate 2>&1 >/dev/null); rc=$?
[ "$rc" -eq 2 ] && [ "$(printf '%s\n' "$err" | head -1)" = "grainlab: unknown command 'frobnicate'" ] ||
  fail "unknown command: exit $rc, $err"
[ ! -e "$work/t" ] && [ ! -e "$work/s" ] || fail "a refused command line created its output directory"

# A run that cannot fit in memory is refused before anything is written (the limit set here, so that the test
# reads the same on any machine: 1e8 spheres need ~143 GiB, 8e9 bytes is 7.5 GiB).
sed 's/count: 300,/count: 100000000,/' "$cfg" > "$work/huge.yaml"
grep -q 'count: 100000000' "$work/huge.yaml" || fail "could not write the huge config"
expect 1 "huge.yaml: sample.count = 100000000 spheres needs about 143.1 GiB of memory \(1.5 kB a sphere\), but [0-9.]+ GiB is available" \
  env GRAINLAB_MEMORY_LIMIT=8e9 "$bin" run "$work/huge.yaml" --out "$work/huge" --quiet
[ ! -e "$work/huge" ] || fail "the run refused for memory created its output directory"
# A limit with a binary unit, as a batch system writes it: 100K = 102 400 bytes, 0.1 MiB, below the 0.4 MiB needed.
expect 1 "needs about 0.4 MiB of memory \(1.5 kB a sphere\), but 0.1 MiB is available \(GRAINLAB_MEMORY_LIMIT\)" \
  env GRAINLAB_MEMORY_LIMIT=100K "$bin" run "$cfg" --out "$work/units" --quiet
expect 1 "GRAINLAB_MEMORY_LIMIT = 'lots': must be a number of bytes > 0, or with a unit K, M, G or T" \
  env GRAINLAB_MEMORY_LIMIT=lots "$bin" run "$cfg" --out "$work/lots" --quiet
echo "out_collision ok"
