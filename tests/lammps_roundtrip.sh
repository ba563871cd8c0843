#!/usr/bin/env bash
# grainlab -> LAMMPS -> grainlab: a sample exported as a LAMMPS data file (`grainlab export --format lammps`) is read by
# LAMMPS itself (`lmp`, Debian's `lammps` package), which dumps it back at 17 digits; `grainlab import` of that dump is
# the sample again, to the bit (spheres, walls; each atom id the sphere's row of the sample, plus 1). Then LAMMPS
# moves the spheres 300 steps between granular walls at the box faces and dumps them in its default format, with more
# columns, its units and times, and four snapshots: imported, its last one. Skipped (exit 77) where no `lmp` is on the
# PATH (`apt-get install lammps`). Last, a periodic box (LAMMPS's own packings): import's note and its --crop.
set -u
bin=$1; work=$2
command -v lmp > /dev/null ||
  { echo "lammps_roundtrip: skipped: no lmp on the PATH (apt-get install lammps)"; exit 77; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
py=/usr/bin/python3
# a small sample of grainlab's own: 300 spheres consolidated (the smoke config's first stage)
cat > prep.yaml <<'YAML'
sample: {count: 300, seed: 3, density_scaling: 1000}
stages:
  - {name: c, type: isotropic, pressure: 100e3, mu: 0.3, max_steps: 20000}
YAML
"$bin" run prep.yaml --out prep --quiet --threads 1 > /dev/null || { echo "the preparation failed"; exit 1; }
"$bin" export prep/sample_c.h5 --format lammps --out s.data > /dev/null || { echo "export failed"; exit 1; }
cat > in.back <<'LMP'
units           si
atom_style      sphere
boundary        f f f
read_data       s.data
dump            d all custom 1 back.dump id x y z radius
dump_modify     d sort id format float %.17g
run             0
LMP
lmp -in in.back -log none > lmp_back.txt 2>&1 ||
  { echo "LAMMPS could not read the exported data file:"; tail -5 lmp_back.txt; exit 1; }
"$bin" import back.dump --out back.h5 > /dev/null || { echo "import of LAMMPS's dump failed"; exit 1; }
$py - <<'PY' || exit 1
import h5py, numpy as np, sys
a, b = h5py.File("prep/sample_c.h5", "r"), h5py.File("back.h5", "r")
# import puts the spheres in its spatial order: sphere k of back.h5 is the dump's row index[k], atom id index[k] + 1,
# which the data file gave sample row index[k]
idx = b["/import/index"][()]
same = [k for k in ("/state/x", "/state/r") if np.array_equal(a[k][()][idx], b[k][()])]
planes = [f["/state/walls"][()].reshape(8, -1)[:6, :4] for f in (a, b)]  # normals and offsets (not the servo state)
if np.array_equal(*planes):
    same.append("walls")
if len(same) != 3 or not np.array_equal(b["/import/id"][()], idx + 1):
    sys.exit(f"grainlab -> LAMMPS -> grainlab is not the sample: equal {same}")
PY
cat > in.run <<'LMP'
units           si
atom_style      sphere
atom_modify     map array
boundary        f f f
comm_modify     vel yes
read_data       s.data
neighbor        1.0e-4 bin
pair_style      granular
pair_coeff      * * hooke 2.0e4 4.0e4 damping mass_velocity tangential linear_history 2.0e4 0.0 0.5
variable        w string "granular hooke 2.0e4 4.0e4 damping mass_velocity tangential linear_nohistory 0.0 0.0"
fix             wx all wall/gran ${w} xplane $(xlo) $(xhi)
fix             wy all wall/gran ${w} yplane $(ylo) $(yhi)
fix             wz all wall/gran ${w} zplane $(zlo) $(zhi)
fix             int all nve/sphere
timestep        1.0e-8
dump            d all custom 100 run.dump id type x y z radius vx vy vz
dump_modify     d time yes units yes
run             300
LMP
lmp -in in.run -log none > lmp_run.txt 2>&1 ||
  { echo "LAMMPS could not run the exported sample:"; tail -5 lmp_run.txt; exit 1; }
out=$("$bin" import run.dump --out run.h5) || { echo "import of LAMMPS's run dump failed"; exit 1; }
printf '%s\n' "$out" | grep -q "^imported 300 spheres from run.dump (timestep 300, the last of 4 snapshots)" ||
  { echo "not the dump's last snapshot: $out"; exit 1; }
# A periodic box, as LAMMPS packs: the same sample shifted by half a box in p p p (LAMMPS wraps the atoms, so spheres
# straddle every face). The import says the box is periodic and gives the --crop of its box; that crop keeps exactly
# the spheres wholly inside the dump's box (counted here from the dump) and leaves none pressing a wall.
cat > in.per <<'LMP'
units           si
atom_style      sphere
boundary        p p p
read_data       s.data
displace_atoms  all move $(0.5*lx) $(0.5*ly) $(0.5*lz) units box
dump            d all custom 1 per.dump id x y z radius
dump_modify     d sort id format float %.17g
run             0
LMP
lmp -in in.per -log none > lmp_per.txt 2>&1 ||
  { echo "LAMMPS could not shift the sample in a periodic box:"; tail -5 lmp_per.txt; exit 1; }
out=$("$bin" import per.dump --out per.h5) || { echo "import of LAMMPS's periodic dump failed: $out"; exit 1; }
crop=$(printf '%s\n' "$out" | sed -n 's/^note: the dump.s box is periodic in x, y, z (pp): its spheres across those faces press the walls here; --crop \(.*\) (its box) keeps those wholly inside it$/\1/p')
[ -n "$crop" ] || { echo "no periodic note with a --crop: $out"; exit 1; }
# shellcheck disable=SC2086
out=$("$bin" import per.dump --crop $crop --out per_crop.h5) || { echo "the note's --crop failed: $out"; exit 1; }
want=$($py - <<'PY'
import numpy as np
lines = open("per.dump").read().splitlines()
b = np.array([[float(v) for v in lines[k].split()] for k in range(5, 8)])
a = np.array([[float(v) for v in l.split()] for l in lines[9:]])
x, r = a[:, 1:4], a[:, 4]
print(int(np.all((x - r[:, None] >= b[:, 0]) & (x + r[:, None] <= b[:, 1]), axis=1).sum()))
PY
)
printf '%s\n' "$out" | grep -q "^cropped: $want of the file's 300 spheres lie wholly inside --crop, the walls$" &&
  printf '%s\n' "$out" | grep -q "no sphere presses a wall" && [ "$want" -gt 100 ] && [ "$want" -lt 300 ] ||
  { echo "the periodic dump's crop (want $want spheres): $out"; exit 1; }
echo "lammps_roundtrip: ok"
