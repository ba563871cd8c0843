#!/usr/bin/env bash
# CTest `race_write_scene` (perf/CMakeLists.txt): `race_bench --write-scene` writes the spheres it would run,
# so that the peers' scaling runs (perf/scaling_peers.sh) get the very same scene:
# 1. a generated scene written and read back runs to the same kinetic energy, bit for bit, as the scene itself;
# 2. an unwritable prefix fails with a non-zero status and leaves no file behind;
# 3. perf/scaling_peers_table.py turns a run file into the table with each code's spread.
set -euo pipefail
RB=$1
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$RB" --generate 2000 --write-scene "$tmp/s" > "$tmp/w.out"
grep -q "spheres" "$tmp/w.out" || fail "no 'wrote ...' line: $(cat "$tmp/w.out")"
[ "$(wc -l < "$tmp/s.txt")" -gt 1000 ] || fail "too few spheres in $tmp/s.txt"
[ ! -e "$tmp/s.txt.tmp" ] || fail "temporary file left behind"
ke() { grep -oE 'kinetic_J=[^ ]+' "$1" | cut -d= -f2; }
"$RB" --generate 2000 --warmup 5 --steps 20 > "$tmp/a.out"
"$RB" --scene "$tmp/s.txt" --box "$tmp/s_box.txt" --warmup 5 --steps 20 > "$tmp/b.out"
[ -n "$(ke "$tmp/a.out")" ] || fail "no kinetic_J in $(cat "$tmp/a.out")"
[ "$(ke "$tmp/a.out")" = "$(ke "$tmp/b.out")" ] || fail "written scene runs differently: $(ke "$tmp/a.out") vs $(ke "$tmp/b.out")"

if "$RB" --generate 2000 --write-scene "$tmp/no/such/dir/s" > /dev/null 2> "$tmp/err"; then
  fail "an unwritable prefix succeeded"
fi
grep -qE "cannot (write|commit)" "$tmp/err" || fail "no clear error: $(cat "$tmp/err")"
[ -z "$(ls "$tmp/no" 2>/dev/null)" ] || fail "files left after a failed write"

cat > "$tmp/runs.txt" <<'RUNS'
code=grainlab spec=--crop_0.70 particles=10000 particle_steps_per_s=2.0e7
code=peer spec=--crop_0.70 particles=10000 particle_steps_per_s=5.0e6
code=grainlab spec=--tile_2 particles=256000 particle_steps_per_s=1.6e7
code=peer spec=--tile_2 particles=256000 particle_steps_per_s=4.0e6
code=grainlab spec=--tile_2 particles=256000 particle_steps_per_s=1.0e7
RUNS
out=$(/usr/bin/python3 "$HERE/scaling_peers_table.py" "$tmp/runs.txt")
# grainlab at 256k: median of 1.6e7 and 1.0e7 = 1.3e7, so spread 2.0e7 / 1.3e7 = 1.54; the peer 1.25;
# the speed-up at 256k 1.3e7 / 4e6 = 3.25
echo "$out" | grep -q "grainlab \*\*1.54\*\*, peer \*\*1.25\*\*" || fail "spread line: $out"
echo "$out" | grep -q "| \`--tile 2\` | 256000 | 77 (2) | 250 (1) | 3.25 |" || fail "256k row: $out"
echo "race_write_scene: ok"
