#!/usr/bin/env bash
# Scaling with N of grainlab and of the peers, on the same machine and the same spheres: is the rise of the
# time per particle-step from ~1e4 to ~1e6 a property of grainlab or of the machine's caches?
#
#   perf/scaling_peers.sh                       grainlab, LIGGGHTS, LAMMPS (granular) at 2 threads/ranks,
#                                               rolling on, 10k / 32k / 256k / 864k spheres, REPS=3 rounds
#   PEERS=liggghts SPECS="--crop 0.70;--tile 2" REPS=5 NWARM=50 NSTEPS=400 perf/scaling_peers.sh
#
# The scenes are race_bench's (`--crop F`: the spheres wholly inside a corner cube of the shared scene,
# `--tile K`: K^3 copies side by side), written by `race_bench --write-scene` so that the peers' inputs
# (../shared/bench/peers/*/bench.in, unchanged: 0.1 mm skin, walls at the scene's box) read the very spheres
# grainlab runs. Every code: NWARM warm-up steps, then NSTEPS timed (the peers' second `Loop time`,
# grainlab's fenced timed run), in rounds over sizes and codes (this host's speed drifts over minutes).
# Peers missing here are installed from Debian unless SKIP_INSTALL=1 (perf/peers_install.sh).
# Writes $OUT/scaling_peers.txt (one line per run: code, spec, particles, particle-steps/s) and prints a table
# of medians; perf/results.sh puts that table into perf/RESULTS.md.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEERS_DIR=${PEERS_DIR:-$ROOT/../shared/bench/peers}
PEERS=${PEERS-"liggghts lammps"}
REPS=${REPS:-3}
NWARM=${NWARM:-50}
NSTEPS=${NSTEPS:-400}
SPECS=${SPECS:-"--crop 0.70;--tile 1;--tile 2;--tile 3"}
BUILD=${BUILD:-$ROOT/build}
OUT=${OUT:-$ROOT/perf/race-out}
# shellcheck source=perf/env_check.sh
. "$ROOT/perf/env_check.sh"
env_check_peers scaling_peers.sh && env_check_whole scaling_peers.sh REPS NSTEPS NWARM || exit 1
PY=/usr/bin/python3
MPI2="mpirun -np 2 --allow-run-as-root --oversubscribe"

[ -s "$PEERS_DIR/scene_32k.txt" ] || { echo "scaling_peers.sh: no scene at $PEERS_DIR/scene_32k.txt (set PEERS_DIR)"; exit 1; }
[ -x "$BUILD/perf/race_bench" ] || { echo "scaling_peers.sh: $BUILD/perf/race_bench missing: run 'make build' first"; exit 1; }
[[ $REPS =~ ^[1-9][0-9]*$ && $NSTEPS =~ ^[1-9][0-9]*$ && $NWARM =~ ^[0-9]+$ ]] \
  || { echo "scaling_peers.sh: REPS and NSTEPS must be >= 1, NWARM >= 0 (got REPS=$REPS NSTEPS=$NSTEPS NWARM=$NWARM)"; exit 2; }
mkdir -p "$OUT"
# shellcheck source=perf/peers_install.sh
. "$ROOT/perf/peers_install.sh"
install_peers scaling_peers.sh "$OUT" || exit 1

# ---- one work dir per size: the scene as race_bench builds it, and the peers' data file and meshes
IFS=';' read -r -a specs <<< "$SPECS"
WORK="$OUT/scaling-work"
mkdir -p "$WORK"
tag() { echo "$1" | tr -d ' -' | tr '.' 'p'; }  # "--crop 0.70" -> crop0p70
for spec in "${specs[@]}"; do
  d="$WORK/$(tag "$spec")"
  mkdir -p "$d"
  # shellcheck disable=SC2086
  "$BUILD/perf/race_bench" --scene "$PEERS_DIR/scene_32k.txt" --box "$PEERS_DIR/scene_32k_box.txt" $spec \
    --write-scene "$d/scene" > /dev/null
  if [ -n "$PEERS" ]; then
    ( cd "$d" && $PY "$PEERS_DIR/tools/scene_to_data.py" scene.txt scene_box.txt scene_32k.data > /dev/null &&
      $PY "$PEERS_DIR/tools/make_stl.py" scene_box.txt > /dev/null )
  fi
done

# ---- the runs, round robin; results appended as they come (a stopped run keeps what it measured)
RES="$OUT/scaling_peers.txt"
: > "$RES"
for ((rep = 1; rep <= REPS; ++rep)); do
  for spec in "${specs[@]}"; do
    d="$WORK/$(tag "$spec")"
    for code in grainlab $PEERS; do
      log="$d/${code}_rep$rep.log"
      echo ">>> $code $spec rep=$rep"
      case $code in
        grainlab)
          # shellcheck disable=SC2086
          OMP_NUM_THREADS=2 OMP_PROC_BIND=spread OMP_PLACES=threads "$BUILD/perf/race_bench" --scene "$d/scene.txt" \
            --box "$d/scene_box.txt" --warmup "$NWARM" --steps "$NSTEPS" > "$log" 2>&1 || { echo "!!! failed, see $log"; continue; }
          rate=$(grep -oE 'particle_steps_per_s=[^ ]+' "$log" | cut -d= -f2)
          n=$(grep -oE ' particles=[0-9]+' "$log" | cut -d= -f2) ;;
        liggghts|lammps)
          exe=lmp; [ "$code" = liggghts ] && exe=liggghts
          # shellcheck disable=SC2086  # $MPI2 is a command line
          ( cd "$d" && OMP_NUM_THREADS=1 timeout 1800 $MPI2 $exe -in "$PEERS_DIR/$code/bench.in" -log none -var roll 1 \
              -var nwarm "$NWARM" -var nsteps "$NSTEPS" ) > "$log" 2>&1 || { echo "!!! failed, see $log"; continue; }
          # "Loop time of T on 2 procs for S steps with N atoms": the last one is the timed run
          read -r t s n < <(grep -E '^Loop time of' "$log" | tail -1 | awk '{print $4, $9, $12}')
          [ "$s" = "$NSTEPS" ] || { echo "!!! no timed run in $log"; continue; }
          rate=$($PY -c "print('%.4g' % ($n * $s / $t))") ;;
        *) echo "scaling_peers.sh: peer '$code' has no scaling run here (liggghts lammps)"; exit 1 ;;
      esac
      echo "code=$code spec=${spec// /_} particles=$n particle_steps_per_s=$rate" | tee -a "$RES"
    done
  done
done

$PY "$ROOT/perf/scaling_peers_table.py" "$RES"
