#!/usr/bin/env bash
# core_share.sh GRAINLAB TASKSET DIR: a 2-thread run that shares its two cores with a busy process is told so
# (Laboratory::watch_core_share: two 5 s windows in a row under 0.75 of its threads' CPU time), and the same run alone
# is not (where the machine gave it 1.6 cores or more; measured 1.92 alone, 1.12 beside the busy loop). Both are
# pinned to the first two CPUs this process may use (the run's --threads 2 fills them; the busy loop takes the first
# from it), so a machine of more cores cannot move the busy loop elsewhere. Each run is stopped (SIGINT: a checkpoint,
# exit 130) at the warning or after `seconds`; the run alone goes 12 s, past the two windows the warning needs.
set -u
g=$1 taskset=$2 dir=$3
rm -rf "$dir" && mkdir -p "$dir" || exit 1
# The first two CPUs of this process's affinity (Cpus_allowed_list: "0-1", "2,5-7", ...)
pair=$(awk '/^Cpus_allowed_list/ { print $2 }' /proc/self/status | tr ',' '\n' |
  awk -F- '{ if (NF == 2) for (i = $1; i <= $2; ++i) print i; else print $1 }' | head -2 | paste -sd, -)
case "$pair" in
  *,*) first=${pair%%,*} ;;
  *) echo "FAIL: this test needs two CPUs, and this process may use $pair"; exit 1 ;;
esac
# A slow shear (6.5e6 steps, about 4 min alone) after a consolidation (1 s): as many steps as the time allows.
cat > "$dir/c.yaml" <<'EOF'
sample: {count: 300, seed: 5, density_scaling: 1000}
stages:
  - {name: consolidate, type: isotropic, pressure: 100e3, mu: 0.3}
  - {name: shear, type: triaxial, drainage: drained, axial_strain_rate: 0.01, max_axial_strain: 0.5, max_steps: 1000000000}
output: {every: 200, checkpoint_every: 0, checkpoint_minutes: 0}
EOF
warning="grainlab: warning: over the last [0-9.]+ s this run's 2 threads had [0-9.]+ cores' worth of CPU time: other processes .*are using its cores"
cores=  # the cores' worth of CPU time the last run_for's process had (/proc/PID/stat utime + stime over its wall time)
run_for() {  # run_for OUT SECONDS: the run until the warning or SECONDS
  "$taskset" -c "$pair" "$g" run "$dir/c.yaml" --out "$dir/$1" --threads 2 --quiet 2> "$dir/$1.err" &
  local pid=$! t0 ticks rc
  t0=$(date +%s.%N)
  while kill -0 "$pid" 2> /dev/null && awk -v a="$t0" -v b="$(date +%s.%N)" -v s="$2" 'BEGIN { exit !(b - a < s) }'; do
    grep -qE "$warning" "$dir/$1.err" && break
    sleep 0.2
  done
  ticks=$(awk '{ print $14 + $15 }' "/proc/$pid/stat" 2> /dev/null)
  cores=$(awk -v t="${ticks:-0}" -v hz="$(getconf CLK_TCK)" -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", t / hz / (b - a) }')
  kill -INT "$pid" 2> /dev/null
  wait "$pid"
  rc=$?
  echo "$1: exit $rc, $cores cores' worth of CPU time"
}
run_for alone 12
# The machine's own load (another guest on a virtual machine's cores) could take the cores from the run alone as the
# busy loop does: then it is no control, and says so.
if awk -v c="$cores" 'BEGIN { exit !(c < 1.6) }'; then
  echo "the run alone had only $cores cores of 2 (the machine is busy): no control of the warning's absence"
elif grep -qE "$warning" "$dir/alone.err"; then
  echo "FAIL: the run alone ($cores cores) was warned of sharing its cores:"; cat "$dir/alone.err"; exit 1
fi
"$taskset" -c "$first" sh -c 'while :; do :; done' &
busy=$!
trap 'kill $busy 2> /dev/null' EXIT
run_for shared 60
if ! grep -qE "$warning" "$dir/shared.err"; then
  echo "FAIL: no warning in 60 s beside a busy loop on one of its two cores:"; cat "$dir/shared.err"; exit 1
fi
grep -E "$warning" "$dir/shared.err"
echo ok
