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
cat > c.yaml <<'YAML'
sample: {count: 800, seed: 12, density_scaling: 1000}
material: {mu_r: 0.1}
stages:
  - {name: consolidate, type: isotropic, mu: 0.3, max_steps: 60000, ufr_tolerance: 0.02}
  - {name: shear, type: triaxial, drainage: undrained, axial_strain_rate: 1.0, max_axial_strain: 0.06, damping: 0.2}
output: {every: 500, checkpoint_every: 0, checkpoint_minutes: 0, keep_checkpoints: 5}
YAML
t0=$(date +%s.%N)
"$bin" run c.yaml --out ref --quiet --threads 2 2> ref.err || { cat ref.err; fail "the reference run"; }
wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
"$bin" run c.yaml --out sig --quiet --threads 2 2> sig.err &
pid=$!
sleep "$(awk -v w="$wall" 'BEGIN { print w / 3 }')"
kill -USR1 "$pid" 2> /dev/null || fail "the run ended within a third of the reference's $wall s: nothing signalled"
wait "$pid"; rc=$?
[ "$rc" -eq 0 ] || { cat sig.err; fail "the signalled run exited $rc, not 0"; }
line=$(grep -E "^checkpoint at step [0-9]+ \(SIGUSR1\): sig/checkpoints/ckpt_[0-9]+\.h5; the run goes on$" sig.err) ||
  { cat sig.err; fail "no line saying where the SIGUSR1 checkpoint is"; }
ckpt=${line#*: }; ckpt=${ckpt%%;*}
[ -f "$ckpt" ] || fail "the SIGUSR1 checkpoint $ckpt is not there"
cmp ref/series.csv sig/series.csv || fail "the signalled run's series differs from the unsignalled one's"
# resumed from that checkpoint alone: the same end
mkdir -p res/checkpoints || exit 1
cp sig/config.yaml res/ || fail "copying the config"
cp "$ckpt" res/checkpoints/ || fail "copying the checkpoint"
"$bin" run res/config.yaml --out res --resume --quiet --threads 2 2> res.err || { cat res.err; fail "the resume"; }
cmp ref/series.csv res/series.csv || fail "resumed from the SIGUSR1 checkpoint, the series differs"
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
echo "ok: SIGUSR1 checkpoint ($ckpt), the run unchanged and resumable from it; a study passes it on"
