#!/usr/bin/env bash
# The shared peer race (../shared/bench/peers, RESULTS.md §3): grainlab and the peers from Debian, one
# after another, on the same scene and the same timed work (200 warm-up + 2000 timed steps).
#
#   perf/race.sh                      grainlab + LIGGGHTS + LAMMPS (granular), rolling on and off,
#                                     1 and 2 threads/ranks, REPS=3, medians
#   PEERS=liggghts perf/race.sh       only these peers (liggghts lammps lammpsclassic yade; "" = none)
#   REPS=5 ROLLS="1" MODES="2" NSTEPS=2000 NWARM=200 PEERS_DIR=... BUILD=build
#   PEER_SKINS_UM="10 5"              the peers' extra runs at these neighbour skins (micrometres; "" = none)
#
# Peers missing on the machine are installed from Debian (apt-get, as root) unless SKIP_INSTALL=1.
# The last line is `speedup_vs_fastest_peer=X.XX`: grainlab as it runs by default, at 2 threads with rolling
# on, against the fastest peer at 2 processes with rolling on, each peer at its fastest skin (medians). Logs
# and a table go to $OUT (default perf/race-out/).
#
# Each code at its best list setting, same physics and same timed work:
# - `grainlab_inner` is the engine's default: the Verlet list with the race's 0.1 mm skin, and the kernels
#   stream an inner list filtered from it (EngineParams::inner_skin, perf/NOTES.md attempt 18): the same bits
#   as streaming the Verlet list, fewer listed non-touching pairs.
# - The peers run at the race's 0.1 mm skin (`liggghts`, `lammps`) and, rolling on, at smaller skins
#   (`liggghts_skin10um`, ...: the input file with its `neighbor` line changed, nothing else). A smaller skin
#   lists fewer non-touching pairs and costs a few rebuilds (LIGGGHTS 2 ranks, perf/RESULTS.md at 0e60db1: 0.1 mm
#   6.56e6, 10 um 7.86e6 particle-steps/s): the peers' own version of what the inner list does.
# - `grainlab` streams the Verlet list itself (--inner 0): the same list as the peers at 0.1 mm. Against those
#   it is printed as `speedup_vs_fastest_peer_verlet` (like for like, list included).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PEERS_DIR=${PEERS_DIR:-$ROOT/../shared/bench/peers}
PEERS=${PEERS-"liggghts lammps"}
REPS=${REPS:-3}
ROLLS=${ROLLS:-"1 0"}
MODES=${MODES:-"1 2"}
NSTEPS=${NSTEPS:-2000}
NWARM=${NWARM:-200}
BUILD=${BUILD:-$ROOT/build}
OUT=${OUT:-$ROOT/perf/race-out}
PY=/usr/bin/python3
MPI2="mpirun -np 2 --allow-run-as-root --oversubscribe"
PEER_SKINS_UM=${PEER_SKINS_UM-"10 5"}

# shellcheck source=perf/env_check.sh
. "$ROOT/perf/env_check.sh"
env_check_peers race.sh && env_check_whole race.sh REPS NSTEPS NWARM || exit 1
for r in $ROLLS; do case $r in 0|1) ;; *) echo "race.sh: ROLLS='$ROLLS': each must be 0 or 1"; exit 1 ;; esac; done
for m in $MODES; do case $m in 1|2) ;; *) echo "race.sh: MODES='$MODES': each must be 1 or 2 (threads or ranks)"; exit 1 ;; esac; done
[ -s "$PEERS_DIR/scene_32k.txt" ] || { echo "race.sh: no scene at $PEERS_DIR/scene_32k.txt (set PEERS_DIR)"; exit 1; }
[ -x "$BUILD/perf/race_bench" ] || { echo "race.sh: $BUILD/perf/race_bench missing: run 'make build' first"; exit 1; }
mkdir -p "$OUT"
rm -f "$OUT"/*.log

# ---- peers from Debian, on demand
# shellcheck source=perf/peers_install.sh
. "$ROOT/perf/peers_install.sh"
install_peers race.sh "$OUT" || exit 1

# ---- the peers' work dir (data file, wall planes, STL meshes), as their run_all.sh makes it
WORK="$OUT/work"
if [ -n "$PEERS" ]; then
  mkdir -p "$WORK"
  cp "$PEERS_DIR/scene_32k.txt" "$PEERS_DIR/scene_32k_box.txt" "$WORK/"
  ( cd "$WORK" && $PY "$PEERS_DIR/tools/scene_to_data.py" >/dev/null && $PY "$PEERS_DIR/tools/make_stl.py" >/dev/null )
  # The LAMMPS-family inputs at each extra skin: only the `neighbor SKIN bin` line differs.
  for um in $PEER_SKINS_UM; do
    for p in liggghts lammps; do
      src="$PEERS_DIR/$p/bench.in" dst="$WORK/${p}_skin${um}um.in"
      grep -q '^neighbor  *1.0e-4 bin' "$src" || { echo "race.sh: no 'neighbor 1.0e-4 bin' line in $src"; exit 1; }
      sed "s/^neighbor  *1.0e-4 bin/neighbor        ${um}e-6 bin/" "$src" > "$dst"
    done
  done
fi

run_one() {  # code roll mode rep -> log
  local code=$1 roll=$2 mode=$3 rep=$4 log
  log="$OUT/${code}_roll${roll}_p${mode}_rep${rep}.log"
  case "$code" in
    grainlab|grainlab_inner)
      local inner=(--inner 0); [ "$code" = grainlab_inner ] && inner=()
      OMP_NUM_THREADS=$mode OMP_PROC_BIND=spread OMP_PLACES=threads "$BUILD/perf/race_bench" \
        --scene "$PEERS_DIR/scene_32k.txt" --box "$PEERS_DIR/scene_32k_box.txt" --rolling "$roll" \
        --warmup "$NWARM" --steps "$NSTEPS" "${inner[@]}" > "$log" 2>&1 ;;
    liggghts*|lammps*)
      local exe=lmp in="$PEERS_DIR/lammps/bench.in" extra=""
      [ "$code" = liggghts ] && { exe=liggghts; in="$PEERS_DIR/liggghts/bench.in"; }
      case "$code" in
        liggghts_skin*) exe=liggghts; in="$WORK/$code.in" ;;
        lammps_skin*) in="$WORK/$code.in" ;;
      esac
      [ "$code" = lammpsclassic ] && extra="-var classic 1"
      local launch=""; [ "$mode" = 2 ] && launch=$MPI2
      ( cd "$WORK" && OMP_NUM_THREADS=1 timeout 900 $launch $exe -in "$in" -log none -var roll "$roll" $extra \
          -var nwarm "$NWARM" -var nsteps "$NSTEPS" ) > "$log" 2>&1 ;;
    yade)
      ( cd "$WORK" && timeout 1800 yade -n -x -j"$mode" "$PEERS_DIR/yade/bench.py" "$roll" "$NWARM" "$NSTEPS" ) \
        > "$log" 2>&1 ;;
  esac || echo "!!! $code roll=$roll p=$mode rep=$rep failed, see $log"
}

skinned=""  # the extra-skin runs of the peers that have a `neighbor` line (not YADE), rolling on
for p in $PEERS; do
  case $p in liggghts|lammps) for um in $PEER_SKINS_UM; do skinned="$skinned ${p}_skin${um}um"; done ;; esac
done
for rep in $(seq 1 "$REPS"); do
  for code in grainlab grainlab_inner $PEERS $skinned; do
    for roll in $ROLLS; do
      [ "$code" = lammpsclassic ] && [ "$roll" = 1 ] && continue  # no rolling model there
      case "$code" in *_skin*) [ "$roll" = 1 ] || continue ;; esac
      for mode in $MODES; do
        echo ">>> $code rolling=$roll processes/threads=$mode rep=$rep"
        run_one "$code" "$roll" "$mode" "$rep"
      done
    done
  done
done

$PY - "$OUT" "$NSTEPS" <<'PY'
import glob, os, re, statistics, sys
out, nsteps = sys.argv[1], int(sys.argv[2])
N = 32000
runs = {}
for fn in glob.glob(os.path.join(out, "*.log")):
    m = re.match(r"(\w+?)_roll(\d)_p(\d)_rep(\d+)\.log$", os.path.basename(fn))
    if not m:
        continue
    code, roll, p = m.group(1), int(m.group(2)), int(m.group(3))
    txt = open(fn, errors="replace").read()
    rate = None
    if code.startswith("grainlab"):
        mm = re.search(r"particle_steps_per_s=([0-9.eE+-]+)", txt)
        rate = float(mm.group(1)) if mm else None
    elif code == "yade":
        mm = re.search(r"YADE_RESULT .*?steps=(\d+) wall_s=([0-9.]+)", txt)
        rate = N * int(mm.group(1)) / float(mm.group(2)) if mm else None
    else:
        loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps", txt)
        if len(loops) >= 2 and "BENCH_DONE" in txt:
            rate = N * int(loops[-1][2]) / float(loops[-1][0])
    if rate:
        runs.setdefault((code, roll, p), []).append(rate)
med = {k: statistics.median(v) for k, v in runs.items()}
lines = ["| code | rolling | threads/ranks | runs | particle-steps/s (median) | min-max | grainlab / this "
         "| grainlab_inner / this |", "|---|---|---|---|---|---|---|---|"]
for k in sorted(med, key=lambda k: (k[1] == 0, k[2], -med[k])):
    code, roll, p = k
    g = med.get(("grainlab", roll, p))
    gi = med.get(("grainlab_inner", roll, p))
    ratio = f"{g / med[k]:.2f}" if g else "-"
    ratio_i = f"{gi / med[k]:.2f}" if gi else "-"
    lines.append(f"| {code} | {'on' if roll else 'off'} | {p} | {len(runs[k])} | {med[k]:.3g} | "
                 f"{min(runs[k]):.3g}-{max(runs[k]):.3g} | {ratio} | {ratio_i} |")
table = "\n".join(lines)
open(os.path.join(out, "table.md"), "w").write(table + "\n")
print(table)
def peers(p, any_skin):  # the peers' medians at p processes, rolling on (any skin, or the race's 0.1 mm only)
    return {c: v for (c, r, q), v in med.items()
            if not c.startswith("grainlab") and r == 1 and q == p and (any_skin or "_skin" not in c)}
def line(name, row, g, pool):
    if g and pool:
        best = max(pool, key=pool.get)
        print(f"# {name}: {row} {g:.3g} against {best} {pool[best]:.3g} particle-steps/s")
        print(f"{name}={g / pool[best]:.2f}")
# grainlab's default against each peer at its fastest skin, then like for like on the 0.1 mm Verlet list.
line("speedup_vs_fastest_peer_1proc", "grainlab_inner", med.get(("grainlab_inner", 1, 1)), peers(1, True))
line("speedup_vs_fastest_peer_verlet_1proc", "grainlab", med.get(("grainlab", 1, 1)), peers(1, False))
line("speedup_vs_fastest_peer_verlet", "grainlab", med.get(("grainlab", 1, 2)), peers(2, False))
d2, p2 = med.get(("grainlab_inner", 1, 2)), peers(2, True)
if d2 and p2:
    line("speedup_vs_fastest_peer", "grainlab_inner", d2, p2)
elif d2:
    print("no peer ran at 2 processes with rolling on")
    print("speedup_vs_fastest_peer=nan")
PY
