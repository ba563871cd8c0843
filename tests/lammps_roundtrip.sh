#!/usr/bin/env bash
# grainlab -> LAMMPS -> grainlab: a sample exported as a LAMMPS data file (`grainlab export --format lammps`) is read by
# LAMMPS itself (`lmp`, Debian's `lammps` package), which dumps it back at 17 digits; `grainlab import` of that dump is
# the sample again, to the bit (spheres, walls; each atom id the sphere's row of the sample, plus 1). Then LAMMPS
# moves the spheres 300 steps between granular walls at the box faces and dumps them in its default format, with more
# columns, its units and times, and four snapshots: imported, its last one. Skipped (exit 77) where no `lmp` is on the
# PATH (`apt-get install lammps`).
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
echo "lammps_roundtrip: ok"
