#!/usr/bin/env bash
# checkpoint_signal.sh GRAINLAB DATA DIR: SIGUSR1 (a batch system's warning before its time limit: SLURM
# --signal=B:USR1@300) makes a run write a checkpoint at the next step boundary and go on: it says where (even with
# --quiet), the file is there, it finishes with exit 0, and its series is the same bytes as an unsignalled run's (the
# extra checkpoint changes nothing). Resumed from that checkpoint, the run ends the same too. A study passes SIGUSR1 on
# to its running jobs and goes on. Before, SIGUSR1's default action ended the run with nothing saved.
set -u
bin=$1 data=$2 dir=$3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$dir" && mkdir -p "$dir" && cd "$dir" || exit 1
# signalled CONFIG NAME PATTERN [SIGNAL EXIT]: runs CONFIG into NAME (its console in NAME.out and NAME.err) and sends
# it SIGNAL (USR1) once a line of its console matches PATTERN (the line is written and flushed then, so the signal lands
# where the pattern says, whatever the host's speed: a third of a reference run's time fell in either stage under
# load); it must exit EXIT (0).
signalled() {
  "$bin" run "$1" --out "$2" --threads 2 > "$2.out" 2> "$2.err" &
  local pid=$! rc
  for _ in $(seq 1 1200); do grep -q "$3" "$2.out" && break; sleep 0.05; done
  kill -"${4:-USR1}" "$pid" 2> /dev/null || fail "$2 ended before it was signalled"
  wait "$pid"; rc=$?
  [ "$rc" -eq "${5:-0}" ] || { cat "$2.err"; fail "$2, signalled, exited $rc, not ${5:-0}"; }
}
# resumed_from CKPT NAME: the run of CKPT's directory resumed from CKPT alone (its config and snapshots copied: a
# resume finds those its checkpoint lists) into NAME
resumed_from() {
  local from=${1%/checkpoints/*}
  mkdir -p "$2/checkpoints" || exit 1
  if ! { cp "$from/config.yaml" "$2/" && cp "$1" "$2/checkpoints/" && cp -r "$from/snapshots" "$2/"; }; then
    fail "copying $from"
  fi
  "$bin" run "$2/config.yaml" --out "$2" --resume --quiet --threads 2 2> "$2.err" || { cat "$2.err"; fail "$2's resume"; }
}
cat > c.yaml <<'YAML'
sample: {count: 800, seed: 12, density_scaling: 1000}
material: {mu_r: 0.1}
stages:
  - {name: consolidate, type: isotropic, mu: 0.3, max_steps: 60000, ufr_tolerance: 0.02}
  - {name: shear, type: triaxial, drainage: undrained, axial_strain_rate: 1.0, max_axial_strain: 0.06, damping: 0.2}
output: {every: 500, checkpoint_every: 0, checkpoint_minutes: 0, keep_checkpoints: 5}
YAML
"$bin" run c.yaml --out ref --quiet --threads 2 2> ref.err || { cat ref.err; fail "the reference run"; }
signalled c.yaml sig "^shear | step "  # early in the shear: its first progress line
line=$(grep -E "^checkpoint at step [0-9]+ \(SIGUSR1\): sig/checkpoints/ckpt_[0-9]+\.h5; the run goes on$" sig.err) ||
  { cat sig.err; fail "no line saying where the SIGUSR1 checkpoint is"; }
ckpt=${line#*: }; ckpt=${ckpt%%;*}
[ -f "$ckpt" ] || fail "the SIGUSR1 checkpoint $ckpt is not there"
cmp ref/series.csv sig/series.csv || fail "the signalled run's series differs from the unsignalled one's"
resumed_from "$ckpt" res
cmp ref/series.csv res/series.csv || fail "resumed from the SIGUSR1 checkpoint, the series differs"
# During a target_e0 search the checkpoint is the stage's start and the trials finished (what a resume takes up),
# written from the stage start while the trial runs on untouched: the same end, and a resume from it alone ends the
# same. Before, the signal waited for the search's end. The signal is sent once trial 1's line is out (the log is
# flushed at each trial's end): trial 2 (mu = mu_max, the longest) runs then. A tolerance no trial meets makes all
# four trials run.
cat > s.yaml <<'YAML'
sample: {count: 200, seed: 12, density_scaling: 1000}
stages:
  - {name: prepare, type: isotropic, target_e0: 0.75, target_e0_tolerance: 1e-9, max_trials: 4, max_steps: 60000,
     ufr_tolerance: 0.02}
output: {every: 500, checkpoint_every: 0, checkpoint_minutes: 0}
YAML
"$bin" run s.yaml --out sref --quiet --threads 2 2> sref.err || { cat sref.err; fail "the search's reference run"; }
signalled s.yaml ssig "^prepare: target_e0 0.7500: trial 1 mu = "
grep -qE "^checkpoint at step 0 \(SIGUSR1\): ssig/checkpoints/ckpt_000000000000\.h5, the start of stage prepare and its 1 finished target_e0 trial\(s\): a resume repeats trial 2 \(at its step [0-9]+ now\); the run goes on$" ssig.err ||
  { cat ssig.err; fail "no line saying the SIGUSR1 checkpoint holds the search's start and its finished trials"; }
for f in series.csv summary.json; do cmp sref/$f ssig/$f || fail "the signalled search's $f differs"; done
resumed_from ssig/checkpoints/ckpt_000000000000.h5 sres
cmp sref/series.csv sres/series.csv || fail "resumed from the search's checkpoint, the series differs"
# the summary less its line naming the config file (s.yaml, sres/config.yaml): the trials' mu and e, the stage's end
cmp <(grep -v '^  "config": ' sref/summary.json) <(grep -v '^  "config": ' sres/summary.json) ||
  fail "resumed from the search's checkpoint, summary.json differs"
# Interrupted in the search (SIGINT): the line names the trial that ran, and that a resume runs it again
signalled s.yaml sint "^prepare: target_e0 0.7500: trial 1 mu = " INT 130
grep -qE "^interrupted at step 0, in stage prepare's target_e0 search at step [0-9]+ of trial 2 \(1 finished; a resume runs trial 2 again\): checkpoint sint/checkpoints/ckpt_000000000000\.h5; continue with --resume$" sint.err ||
  { cat sint.err; fail "the interruption's line does not name the search's trial"; }
"$bin" run s.yaml --out sint --resume --threads 2 > sint2.out 2> sint2.err || { cat sint2.err; fail "the search's resume"; }
grep -qE "^prepare: target_e0 0.7500: trial 1 mu = 0.0000 -> e = 0\.[0-9]{4} \(run before the resume\)$" sint2.out ||
  { cat sint2.out; fail "the resumed search does not show the trial its checkpoint holds"; }
cmp sref/series.csv sint/series.csv || fail "the search interrupted and resumed: its series differs"
# a study: passed on to its running jobs, which write a checkpoint each and go on
cp "$data"/tiny-study.yaml "$data"/tiny-study-base.yaml .
GRAINLAB_FIGURE_FORMATS=png "$bin" study tiny-study.yaml --out st --jobs 2 --quiet > st.out 2> st.err &
sid=$!
for _ in $(seq 1 100); do ls st/jobs/*/run/series.csv > /dev/null 2>&1 && break; sleep 0.05; done
kill -USR1 "$sid" 2> /dev/null || fail "the study ended before its jobs started"
wait "$sid"; rc=$?
[ "$rc" -eq 0 ] || { cat st.err; fail "the signalled study exited $rc, not 0"; }
grep -qE "^grainlab study: SIGUSR1: [12] running job\(s\) asked for a checkpoint; the study goes on$" st.err ||
  { cat st.err; fail "the study did not say it passed SIGUSR1 on"; }
grep -lE "^checkpoint at step [0-9]+ \(SIGUSR1\)" st/jobs/*/log.txt > /dev/null ||
  fail "no job wrote a checkpoint on the study's SIGUSR1"
echo "ok: SIGUSR1 checkpoint ($ckpt), the run unchanged and resumable from it, in a target_e0 search too; a study passes it on"
