#!/usr/bin/env python3
"""`grainlab import` (src/import.cpp): a text packing (x y z r a line, here in mm with --scale 1e-3, lines shuffled,
comments, commas, a CRLF line) becomes a sample file whose spheres are the file's to the bit, in spatial order, with
/import/index mapping each back to its row; the box (--box, or the spheres' bounding box) as the six walls; the counts
it prints (overlapping pairs, the largest overlap and its lines, sphere-wall overlaps, solid fraction) against a
brute-force N^2 count written out here; a run starts from the file. Bad input: one error line naming the file, the line
and the allowed range, exit 1 (2 for a bad command line), and nothing written or replaced."""
import glob
import json
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

grainlab, work = sys.argv[1], sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
fails = []


def check(ok, what):
    if not ok:
        fails.append(what)


def run(*args, cwd=work):
    p = subprocess.run([grainlab, *args], cwd=cwd, capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


# An 8 x 8 x 8 grid of spheres 0.4 mm apart (radii 0.195-0.21 mm, centres jittered by up to 0.003 mm): most
# neighbours overlap, by up to an eighth of a radius, the outer layer presses walls at 0 and 3.2 mm; written in mm, in
# shuffled order.
rng = np.random.default_rng(5)
g = np.arange(8) * 0.4 + 0.2
x = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T + rng.uniform(-0.003, 0.003, (512, 3))
r = rng.uniform(0.195, 0.21, 512)
perm = rng.permutation(512)
x, r = x[perm], r[perm]
texts = [f"{a!r} {b!r} {c!r} {d!r}" for (a, b, c), d in zip(x, r)]
lines, line_of = ["# x y z r [mm]", ""], []
for k, t in enumerate(texts):
    if k % 50 == 7:
        lines.append("# a comment between spheres")
    if k % 9 == 4:
        t = t.replace(" ", ", ")
    line_of.append(len(lines) + 1)
    lines.append(t + ("\r" if k == 100 else ""))
packing = os.path.join(work, "packing.txt")
with open(packing, "w") as f:
    f.write("\n".join(lines) + "\n")
# the file's values as the C++ reads them: strtod and Python's float round alike, and both multiply by the same 1e-3
xf = np.array([[float(v) * 1e-3 for v in t.split()[:3]] for t in texts])
rf = np.array([float(t.split()[3]) * 1e-3 for t in texts])

rc, out, err = run("import", "packing.txt", "--scale", "1e-3", "--box", "0", "3.2", "0", "3.2", "0", "3.2",
                   "--density", "2500", "--density-scaling", "10", "--out", "s.h5")
check(rc == 0 and not err, f"import failed ({rc}): {err}")
print(out, end="")

# --- the brute-force oracle: every pair once
d = np.sqrt(((xf[:, None, :] - xf[None, :, :]) ** 2).sum(-1))
ov = (rf[:, None] + rf[None, :] - d) / np.minimum(rf[:, None], rf[None, :])
iu = np.triu_indices(512, 1)
touching = int((ov[iu] > 0).sum())
k_max = int(np.argmax(ov[iu]))
i_max, j_max = iu[0][k_max], iu[1][k_max]
lo, hi = np.zeros(3), np.full(3, 3.2e-3)
gaps = np.concatenate([xf - lo, hi - xf], axis=1)
wov = (rf[:, None] - gaps) / rf[:, None]
Vs = (4 / 3 * np.pi * rf ** 3).sum()
V = 3.2e-3 ** 3
want = (f"contacts: {touching} overlapping pairs (Z {2 * touching / 512:.3g}), the largest overlap "
        f"{ov[iu][k_max]:.3g} of the smaller radius (lines {min(line_of[i_max], line_of[j_max])} and "
        f"{max(line_of[i_max], line_of[j_max])}); {int((wov > 1e-12).sum())} sphere-wall overlaps, the largest "
        f"{wov.max():.3g} of the sphere's radius")
check(touching > 500 and (wov > 0).sum() > 100, f"the oracle's scene is not what the test needs ({touching} pairs)")
check(want in out, f"the contacts line differs from the N^2 count:\n  want {want}\n  got  {out}")
check(f"solid fraction {Vs / V:.4g}, void ratio e {(V - Vs) / Vs:.4g}" in out, "solid fraction or e differ")
check(f"imported 512 spheres from packing.txt: diameters {2 * rf.min() * 1e3:.4g} mm to {2 * rf.max() * 1e3:.4g} mm"
      in out, "the first line's count or diameters differ")

with h5py.File(os.path.join(work, "s.h5"), "r") as f:
    idx = f["/import/index"][()]
    sx, sr = f["/state/x"][()], f["/state/r"][()]
    check(sorted(idx.tolist()) == list(range(512)), "/import/index is not a permutation of the file's rows")
    check(np.array_equal(sx, xf[idx]) and np.array_equal(sr, rf[idx]), "the sample's spheres are not the file's bits")
    for name in ("v", "w", "f", "t"):
        check(not f[f"/state/{name}"][()].any(), f"/state/{name} is not zero")
    check(len(f["/state/pair_i"][()]) == 0, "an imported sample carries contact history")
    walls = f["/state/walls"][()].reshape(8, -1)
    check(np.array_equal(walls[:6, 3], [0, -3.2e-3, 0, -3.2e-3, 0, -3.2e-3]), f"walls not at the box: {walls[:6, 3]}")
    check(f.attrs["density"] == 2500 and f.attrs["density_scaling"] == 10, "density or its scaling not recorded")
    src = f.attrs["imported_from"]
    check((src.decode() if isinstance(src, bytes) else src).endswith("/packing.txt"), "the source is not recorded")
    # spatial order: consecutive spheres of the sample lie far closer together than the shuffled file's
    step = np.linalg.norm(np.diff(sx, axis=0), axis=1).mean()
    check(step < 0.4 * np.linalg.norm(np.diff(xf, axis=0), axis=1).mean(), f"not in spatial order ({step:.3g} m)")

# --- a shear straight from the imported sample: its p'_0 is the stress its walls' overlaps press with at this run's
# stiffness (k_w = E_wall r, SPEC §3; E 100 MPa by default), not 0 (a sample file's state records no loads until a step
# has pressed the walls: the run computes them)
with open(os.path.join(work, "shear.yaml"), "w") as f:
    f.write("sample: {file: s.h5}\nstages:\n  - {name: sh, type: triaxial, drainage: drained, axial_strain_rate: 1, "
            "max_axial_strain: 0.001}\n")
rc, out, err = run("run", "shear.yaml", "--out", "sh", "--quiet", "--threads", "1")
sig = []
for a in range(3):
    area = 3.2e-3 ** 2  # every face of the 3.2 mm cube
    lo_pen = np.clip(rf - (xf[:, a] - 0), 0, None)
    hi_pen = np.clip(rf - (3.2e-3 - xf[:, a]), 0, None)
    sig.append(0.5 * ((1e8 * rf * lo_pen).sum() + (1e8 * rf * hi_pen).sum()) / area)
p_walls = sum(sig) / 3
if rc == 0:
    p0 = json.load(open(os.path.join(work, "sh", "summary.json")))["stages"][0]["p_0"]
    check(abs(p0 - p_walls) < 1e-9 * p_walls and p_walls > 1e3, f"the shear's p'_0 {p0} Pa, the walls' {p_walls} Pa")
else:
    check(False, f"a shear straight from the imported sample failed ({rc}): {err}")

# --box FILE (the shared race's scene_32k_box.txt form): the same sample as the six numbers
with open(os.path.join(work, "box.txt"), "w") as f:
    f.write("0 3.2\n0 3.2\n0 3.2\n")
with open(os.path.join(work, "box7.txt"), "w") as f:
    f.write("0 3.2 0 3.2 0 3.2 1\n")
rc, out, err = run("import", "packing.txt", "--scale", "1e-3", "--box", "box.txt", "--density", "2500",
                   "--density-scaling", "10", "--out", "s_box.h5")
with h5py.File(os.path.join(work, "s.h5"), "r") as a, h5py.File(os.path.join(work, "s_box.h5"), "r") as b:
    check(rc == 0 and all(np.array_equal(a[k][()], b[k][()]) for k in ("/state/x", "/state/r", "/state/walls",
                                                                      "/import/index")), f"--box FILE: {rc} {err}")

# --- --crop: a box cut out of the packing (in the file's units, as --box): the spheres wholly inside it, to the bit,
# /import/index their rows of the file; the crop box the walls; the counts printed of the spheres kept (brute force)
clo, chi = np.array([0.5, 0.3, 0.9]) * 1e-3, np.array([2.7, 2.9, 3.2]) * 1e-3
keep = np.all((xf - rf[:, None] >= clo) & (xf + rf[:, None] <= chi), axis=1)
kept = np.flatnonzero(keep)
rc, out, err = run("import", "packing.txt", "--scale", "1e-3", "--crop", "0.5", "2.7", "0.3", "2.9", "0.9", "3.2",
                   "--out", "crop.h5")
check(rc == 0 and f"cropped: {len(kept)} of the file's 512 spheres lie wholly inside --crop, the walls" in out and
      "(--crop): solid fraction" in out, f"--crop: {rc} {out} {err}")
check(0 < len(kept) < 512 and not keep.all(), f"the crop keeps {len(kept)} spheres: no test")
if rc == 0:
    with h5py.File(os.path.join(work, "crop.h5"), "r") as f:
        idx = f["/import/index"][()]
        check(sorted(idx.tolist()) == kept.tolist(), "--crop: /import/index is not the rows of the spheres inside")
        check(np.array_equal(f["/state/x"][()], xf[idx]) and np.array_equal(f["/state/r"][()], rf[idx]),
              "--crop: the spheres are not the file's bits")
        walls = f["/state/walls"][()].reshape(8, -1)
        check(np.array_equal(walls[:6, 3], [clo[0], -chi[0], clo[1], -chi[1], clo[2], -chi[2]]),
              f"--crop: the walls are not the crop box: {walls[:6, 3]}")
    xk, rk = xf[kept], rf[kept]
    dk = np.sqrt(((xk[:, None, :] - xk[None, :, :]) ** 2).sum(-1))
    ik = np.triu_indices(len(kept), 1)
    ovk = (rk[:, None] + rk[None, :] - dk)[ik]
    Vk = np.prod(chi - clo)
    Vsk = (4 / 3 * np.pi * rk ** 3).sum()
    check(f"contacts: {int((ovk > 0).sum())} overlapping pairs" in out and "no sphere presses a wall" in out and
          f"solid fraction {Vsk / Vk:.4g}," in out, f"--crop: the counts are not the kept spheres': {out}")

# --- other columns: a CSV with a header of names and more fields (an id before, a label and a volume after, quoted
# as ParaView writes them) read by --columns, by numbers from 1 or by the header's names: the same sample as the text
# file, to the bit (its rows, ids aside, are the text's); and a header x y z r before four fields needs no option
csv_rows = [f"{k + 1},{a},{b},{c},{d},grain{k},{4 / 3 * 3.14159 * float(d) ** 3!r}" for k, (a, b, c, d) in
            enumerate(tx.split() for tx in texts)]
with open(os.path.join(work, "grains.csv"), "w") as f:
    f.write('"id","X [mm]","Y [mm]","Z [mm]","radius","label","volume"\n' + "\n".join(csv_rows) + "\n")
with open(os.path.join(work, "named.txt"), "w", encoding="utf-8-sig") as f:  # with a byte order mark, as Excel saves
    f.write("x y z r\n" + "\n".join(texts) + "\n")
# and diameters (doubled radii, exact in binary) with --size diameter, halved back to the same radii
with open(os.path.join(work, "diam.txt"), "w") as f:
    f.write("X Y Z D\n" + "\n".join(" ".join(tx.split()[:3] + [repr(2 * float(tx.split()[3]))]) for tx in texts) + "\n")
for name, cols in (("grains.csv", "2,3,4,5"), ("grains.csv", "X [mm],Y [mm],Z [mm],radius"), ("named.txt", None),
                   ("diam.txt", None)):
    out_h5 = f"cols{len(glob.glob(os.path.join(work, 'cols*.h5')))}.h5"
    rc, out, err = run("import", name, "--scale", "1e-3", "--box", "0", "3.2", "0", "3.2", "0", "3.2", "--density",
                       "2500", "--density-scaling", "10", *(["--columns", cols] if cols else []),
                       *(["--size", "diameter"] if name == "diam.txt" else []), "--out", out_h5)
    said = ("imported 512 spheres from grains.csv (columns 2, 3, 4, 5 as x y z r; header line 1 "
            "'\"id\",\"X [mm]\",\"Y [mm]\",\"Z [mm]\",\"radius\",\"label\",\"volume\"' skipped)" if cols else
            "imported 512 spheres from named.txt (header line 1 'x y z r' skipped)" if name == "named.txt" else
            "imported 512 spheres from diam.txt (header line 1 'X Y Z D' skipped; the fourth a diameter, halved)")
    check(rc == 0 and said in out, f"--columns {cols}: {rc} {out} {err}")
    if rc == 0:
        with h5py.File(os.path.join(work, "s.h5"), "r") as a, h5py.File(os.path.join(work, out_h5), "r") as b:
            check(all(np.array_equal(a[k][()], b[k][()]) for k in ("/state/x", "/state/r", "/state/walls",
                                                                  "/import/index")), f"--columns {cols}: not the sample")
rc, out, err = run("import", "grains.csv", "--scale", "1e-3", "--out", "g.h5")
check(rc == 1 and "grains.csv:1: the header" in err and "pick the four with --columns" in err, f"a CSV without "
      f"--columns: {rc} {err}")

# --- a LAMMPS / LIGGGHTS dump: its last snapshot, its box bounds as the walls, its atom ids kept
def dump_snapshot(step, cols, rows, box=("0 3.2", "0 3.2", "0 3.2"), bounds="ff ff ff"):
    return (f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(rows)}\nITEM: BOX BOUNDS {bounds}\n" +
            "\n".join(box) + f"\nITEM: ATOMS {cols}\n" + "\n".join(rows) + "\n")


ids = rng.permutation(512) + 1
t = [tx.split() for tx in texts]
first = dump_snapshot(0, "id type x y z radius", [f"{i} 1 1.6 1.6 1.6 0.2" for i in ids])  # not the one read
last = dump_snapshot(5000, "id type x y z radius vx", [f"{i} 1 {a} {b} {c} {d} 0.5" for i, (a, b, c, d) in zip(ids, t)])
with open(os.path.join(work, "packed.dump"), "w") as f:
    f.write(first + last)
rc, out, err = run("import", "packed.dump", "--scale", "1e-3", "--density", "2500", "--density-scaling", "10")
check(rc == 0 and "(timestep 5000, the last of 2 snapshots)" in out and "(the dump's box bounds)" in out and
      want.split(" (lines")[0] + f" (lines {531 + min(i_max, j_max)} and {531 + max(i_max, j_max)})" in out,
      f"the dump: {rc} {out} {err}")  # the second snapshot's atoms start at line 531
with h5py.File(os.path.join(work, "s.h5"), "r") as a, h5py.File(os.path.join(work, "packed.h5"), "r") as b:
    check(all(np.array_equal(a[k][()], b[k][()]) for k in ("/state/x", "/state/r", "/state/walls", "/import/index")),
          "the dump's sample is not the text file's")
    check(np.array_equal(b["/import/id"][()], ids[b["/import/index"][()]]), "the dump's atom ids are not kept")
# a dump names its columns: --columns is refused, nothing written
rc, out, err = run("import", "packed.dump", "--columns", "3,4,5,6", "--out", "bc.h5")
check(rc == 1 and "packed.dump: a LAMMPS dump, which names its columns itself: --columns is for a text packing" in err
      and not os.path.exists(os.path.join(work, "bc.h5")), f"--columns on a dump: {rc} {err}")
rc, out, err = run("import", "packed.dump", "--size", "diameter", "--out", "bc.h5")
check(rc == 1 and "packed.dump: a LAMMPS dump, which names its columns itself: --size is for a text packing" in err
      and not os.path.exists(os.path.join(work, "bc.h5")), f"--size on a dump: {rc} {err}")
# A periodic box (BOX BOUNDS pp ff pp, as LAMMPS and LIGGGHTS pack): spheres across its faces press the walls, and
# the import says so with the --crop that keeps the spheres wholly inside; that crop then leaves none pressing a wall.
# Not said of a box of walls (ff), nor where no sphere crosses a periodic face.
per = ["1 1 0.1 1.6 1.6 0.2", "2 1 1.0 1.0 1.0 0.2", "3 1 2.0 2.0 2.0 0.2", "4 1 1.6 1.6 3.1 0.2"]
for name, bounds, rows, said in (("per", "pp ff pp", per, True), ("walled", "ff ff ff", per, False),
                                 ("inside", "pp pp pp", per[1:3], False)):
    with open(os.path.join(work, f"{name}.dump"), "w") as f:
        f.write(dump_snapshot(7, "id type x y z radius", rows, bounds=bounds))
    rc, out, err = run("import", f"{name}.dump", "--scale", "1e-3")
    note = ("note: the dump's box is periodic in x, z (pp): its spheres across those faces press the walls here; "
            "--crop 0 3.2 0 3.2 0 3.2 (its box) keeps those wholly inside it")
    check(rc == 0 and (note in out) == said and ("note:" in out) == said, f"periodic {name}: {rc} {out} {err}")
rc, out, err = run("import", "per.dump", "--scale", "1e-3", "--crop", "0", "3.2", "0", "3.2", "0", "3.2", "--out",
                   "per_crop.h5")
check(rc == 0 and "cropped: 2 of the file's 4 spheres" in out and "no sphere presses a wall" in out,
      f"the periodic dump's crop: {rc} {out} {err}")

# ITEM: UNITS and ITEM: TIME (dump_modify units / time yes) before the timestep: skipped
with open(os.path.join(work, "timed.dump"), "w") as f:
    f.write("ITEM: UNITS\nsi\nITEM: TIME\n0.0005\n" + last)
rc, out, err = run("import", "timed.dump", "--scale", "1e-3")
with h5py.File(os.path.join(work, "packed.h5"), "r") as a, h5py.File(os.path.join(work, "timed.h5"), "r") as b:
    check(rc == 0 and np.array_equal(a["/state/x"][()], b["/state/x"][()]), f"ITEM: UNITS / TIME: {rc} {err}")
# scaled coordinates (xs ys zs) and diameters: the same spheres within a rounding
rows = [f"{i} {float(a) / 3.2!r} {float(b) / 3.2!r} {float(c) / 3.2!r} {2 * float(d)!r}"
        for i, (a, b, c, d) in zip(ids, t)]
with open(os.path.join(work, "scaled.dump"), "w") as f:
    f.write(dump_snapshot(7, "id xs ys zs diameter", rows))
rc, out, err = run("import", "scaled.dump", "--scale", "1e-3")
with h5py.File(os.path.join(work, "scaled.h5"), "r") as b:
    check(rc == 0 and np.allclose(b["/state/x"][()], xf[b["/import/index"][()]], rtol=0, atol=1e-18) and
          np.allclose(b["/state/r"][()], rf[b["/import/index"][()]], rtol=1e-15, atol=0), f"xs ys zs, diameter: {err}")

# --- a run starts from it, as from any sample file
with open(os.path.join(work, "run.yaml"), "w") as f:
    f.write("sample: {file: s.h5}\nstages:\n  - {name: c, type: isotropic, pressure: 50e3, max_steps: 400}\n"
            "  - {name: c2, type: isotropic, pressure: 60e3, max_steps: 200}\noutput: {every: 100}\n")
rc, out, err = run("run", "run.yaml", "--out", "r", "--quiet", "--threads", "1")
check(rc == 0, f"a run from the imported sample failed ({rc}): {err}")
if rc == 0:
    s = json.load(open(os.path.join(work, "r", "summary.json")))
    check(s["sample"]["spheres"] == 512 and s["stages"][0]["steps"] > 0, f"the run's summary: {s['sample']}")

# --- export, the other way: x y z r and the box read back by import to the bit; a LAMMPS data file
rc, out, err = run("export", "s.h5")
check(rc == 0 and "grainlab import s.txt --box s_box.txt reads them back to the bit" in out, f"export: {rc} {err}")
rc, out, err = run("import", "s.txt", "--box", "s_box.txt", "--density", "2500", "--density-scaling", "10",
                   "--out", "round.h5")
with h5py.File(os.path.join(work, "s.h5"), "r") as a, h5py.File(os.path.join(work, "round.h5"), "r") as b:
    check(rc == 0 and all(np.array_equal(a[k][()], b[k][()]) for k in ("/state/x", "/state/r", "/state/walls")) and
          np.array_equal(b["/import/index"][()], np.arange(512)), f"export then import is not the sample: {rc} {err}")
rc, out, err = run("export", "s.h5", "--format", "lammps")
with open(os.path.join(work, "s.data")) as f:
    data = f.read().split("\n")
atoms = np.array([[float(v) for v in line.split()] for line in data[data.index("Atoms # sphere") + 2:] if line])
with h5py.File(os.path.join(work, "s.h5"), "r") as a:
    check(rc == 0 and "512 atoms" in data and "0 0.0032000000000000002 zlo zhi" in data and
          np.array_equal(atoms[:, 0], np.arange(1, 513)) and (atoms[:, 1] == 1).all() and
          np.array_equal(atoms[:, 2], 2 * a["/state/r"][()]) and (atoms[:, 3] == 2500).all() and
          np.array_equal(atoms[:, 4:7], a["/state/x"][()]), f"the LAMMPS data file: {rc} {err}")
# the data file read back (read_data's format in, as LAMMPS and LIGGGHTS write it): the sample, its density the atoms'
rc, out, err = run("import", "s.data", "--density-scaling", "10", "--out", "s_data.h5")
with h5py.File(os.path.join(work, "s.h5"), "r") as a, h5py.File(os.path.join(work, "s_data.h5"), "r") as b:
    check(rc == 0 and "(a LAMMPS data file, density 2500 kg/m^3)" in out and "(the data file's box)" in out and
          all(np.array_equal(a[k][()], b[k][()]) for k in ("/state/x", "/state/r", "/state/walls")) and
          b.attrs["density"] == 2500 and np.array_equal(b["/import/id"][()], np.arange(1, 513)),
          f"a LAMMPS data file read back: {rc} {out} {err}")
head = "title\n\n2 atoms\n1 atom types\n\n0 3 xlo xhi\n0 3 ylo yhi\n0 3 zlo zhi\n\n"
for k, (text, part) in enumerate([
        (head + "Atoms # sphere\n\n1 1 0.4 2650 1 1 1\n2 1 0.4 2500 2 2 2\n",
         "data0.data: the atoms' densities differ (lines 12 and 13): a sample has one density, give it with --density"),
        (head + "Atoms # atomic\n\n1 1 1 1 1\n2 1 2 2 2\n",
         "data1.data:10: atom_style atomic: only sphere or granular"),
        (head + "Atoms\n\n1 1 0.4 2650 1 1\n",
         "data2.data:12: '1 1 0.4 2650 1 1' is not an atom_style sphere row"),
        (head + "Atoms\n\n1 1 0.4 2650 1 1 1\n",
         "data3.data: 1 Atoms rows for the header's 2 atoms (a file cut short?)"),
        (head.replace("0 3 zlo zhi", "0 3 zlo zhi\n0 0 0 xy xz yz") + "Atoms\n", "data4.data:9: a triclinic box")]):
    with open(os.path.join(work, f"data{k}.data"), "w") as f:
        f.write(text)
    rc, out, err = run("import", f"data{k}.data", "--scale", "1e-3")
    check(rc == 1 and part in err and not os.path.exists(os.path.join(work, f"data{k}.h5")),
          f"data case {k}: exit {rc}, stderr {err!r}, want '{part}'")
rc, out, err = run("import", "data0.data", "--scale", "1e-3", "--density", "2600")
check(rc == 0 and "density 2600 kg/m^3" in out, f"--density over the atoms' densities: {rc} {err}")
snaps = sorted(glob.glob(os.path.join(work, "r", "snapshots", "*.h5")))
snap = snaps[-1]
rc, out, err = run("export", snap, "--out", "snap.txt")
with h5py.File(snap, "r") as a:
    back = np.loadtxt(os.path.join(work, "snap.txt"))
    box = np.loadtxt(os.path.join(work, "snap_box.txt"))
    check(rc == 0 and np.array_equal(back, np.column_stack([a["/particles/x"][()], a["/particles/r"][()]])) and
          np.array_equal(box, a["/walls/box"][()]), f"a snapshot: {err}")
# --format dump: a frame per snapshot of the run (OVITO's input), its box the walls'; import takes the last frame
rc, out, err = run("export", "r/", "--format", "dump")
check(rc == 0 and f"exported {len(snaps)} frames of 512 spheres to r.dump" in out and len(snaps) >= 2,
      f"--format dump of a run: {rc} {out} {err}")
with open(os.path.join(work, "r.dump")) as f:
    frames = f.read().count("ITEM: TIMESTEP")
rc, out, err = run("import", "r.dump", "--out", "r_dump.h5")
with h5py.File(snap, "r") as a, h5py.File(os.path.join(work, "r_dump.h5"), "r") as b:
    idx = b["/import/index"][()]
    walls = b["/state/walls"][()].reshape(8, -1)[:6, 3] * [1, -1, 1, -1, 1, -1]
    check(rc == 0 and frames == len(snaps) and np.array_equal(b["/state/x"][()], a["/particles/x"][()][idx]) and
          np.array_equal(b["/import/id"][()], idx + 1) and np.array_equal(walls, a["/walls/box"][()]),
          f"the dump's last frame is not the last snapshot: {rc} {err}")
# a snapshot written before the walls were recorded: its frame's box is the spheres' bounding box, said
with h5py.File(snap, "r") as a, h5py.File(os.path.join(work, "old_snap.h5"), "w") as b:
    for k in ("/particles/x", "/particles/v", "/particles/w", "/particles/r"):
        b[k] = a[k][()]
    for k, v in a.attrs.items():
        b.attrs[k] = v
rc, out, err = run("export", "old_snap.h5", "--format", "dump")
check(rc == 0 and "note: 1 of them without walls recorded (snapshots before session 64)" in out,
      f"an old snapshot: {rc} {out} {err}")
before = open(os.path.join(work, "s.txt"), "rb").read()
for args, code, part in [(["s.h5"], 1, "s.txt: exists; export never replaces a file"),
                         ([snap, "--format", "lammps", "--out", "x.data"], 1, "a snapshot that records no density"),
                         (["s.h5", "--format", "vtk"], 2, "--format must be xyzr, lammps or dump, got 'vtk'"),
                         (["r", "--out", "x.txt"], 1, "r: a directory: --format dump writes a run's snapshots"),
                         (["r/run.h5", "--out", "x.txt"], 1, "r/run.h5: a run's series (run.h5)")]:
    rc, out, err = run("export", *args)
    check(rc == code and part in err and len(err.strip().splitlines()) == 1, f"export {args}: {rc} {err!r}")
check(open(os.path.join(work, "s.txt"), "rb").read() == before and not os.path.exists(os.path.join(work, "x.data"))
      and not os.path.exists(os.path.join(work, "x.txt")), "a refused export wrote or changed a file")

# --- the packing itself as sample.file: one line naming the command that makes a sample of it
with open(os.path.join(work, "text_sample.yaml"), "w") as f:
    f.write("sample: {file: packing.txt}\nstages:\n  - {name: c, type: isotropic, pressure: 50e3}\n")
rc, out, err = run("validate", "text_sample.yaml")
check(rc == 1 and "packing.txt: text, not an HDF5 file (a sample is one): a packing of x y z r lines or a "
      "LAMMPS/LIGGGHTS dump becomes a sample with `grainlab import " in err,
      f"a text packing as sample.file: {rc} {err}")

# --- the default box: the spheres' bounding box, the default out beside the packing
rc, out, err = run("import", "packing.txt", "--scale", "1e-3")
check(rc == 0 and "(the spheres' bounding box)" in out and "no sphere presses a wall" in out and
      os.path.exists(os.path.join(work, "packing.h5")), f"the default box or out: {rc} {out} {err}")
with h5py.File(os.path.join(work, "packing.h5"), "r") as f:
    walls = f["/state/walls"][()].reshape(8, -1)
    blo, bhi = (xf - rf[:, None]).min(0), (xf + rf[:, None]).max(0)
    check(np.array_equal(walls[:6, 3], [blo[0], -bhi[0], blo[1], -bhi[1], blo[2], -bhi[2]]),
          "the walls are not the bounding box")

# --- bad input: one line, the exit code, nothing written
ok_line = texts[0]
cases = [  # (file text, extra args, exit code, message part)
    (ok_line + "\n1 2 3\n", [], 1, "bad.txt:2: 3 numbers in '1 2 3', four expected"),
    (ok_line + "\n1 2 3 0\n", [], 1, "bad.txt:2: r = 0 must be > 0"),
    (ok_line + "\n1 nan 3 0.2\n", [], 1, "bad.txt:2: y = nan is not a finite number"),
    (ok_line + "\nx y z r\n", [], 1, "bad.txt:2: 'x y z r' is not four numbers"),
    ("r x y z\n" + ok_line + "\n", [], 1, "bad.txt:1: the header 'r x y z' does not name x y z r in that order: pick "
                                          "the four with --columns"),
    ("id x y z d\n" + ok_line + " 1\n", [], 1, "bad.txt:1: the header 'id x y z d' does not name x y z r"),
    (ok_line + "\n", ["--columns", "1,2,3"], 2, "--columns needs four columns X,Y,Z,R"),
    (ok_line + "\n", ["--size", "d"], 2, "--size must be radius or diameter, got 'd'"),
    ("x y z d\n" + ok_line + "\n", [], 1, "the header 'x y z d' does not name x y z r in that order: pick the four "
                                          "with --columns X,Y,Z,R (numbers from 1, or these names); a diameter with "
                                          "--size diameter"),
    (ok_line + "\n", ["--columns", "1,2,3,0"], 1, "--columns: '0' is not a column number in [1, 1000] or a name"),
    (ok_line + "\n", ["--columns", "1,2,3,radius"], 1, "--columns: 'radius' is a name, and bad.txt has no header line"),
    ("x y z r\n" + ok_line + "\n", ["--columns", "x,y,z,radius"], 1,
     "--columns: 'radius' is not a name of bad.txt's header (line 1: x, y, z, r)"),
    (ok_line + "\n", ["--columns", "1,2,3,5"], 1, "bad.txt:1: 4 fields in"),
    (ok_line + " abc\n", ["--columns", "1,2,3,5"], 1, "bad.txt:1: field 5 (r) 'abc' is not a number"),
    ("# nothing\n\n", [], 1, "bad.txt: no spheres in it"),
    ("1 1 1 2000\n", [], 1, "bad.txt:1: r = 2 m (after --scale 0.001) is above 1 m (sample.r_max's range is (0, 1])"),
    (ok_line + "\n3.3 1 1 0.2\n", ["--box", "0", "3.2", "0", "3.2", "0", "3.2"], 1,
     "bad.txt:2: the centre's x = 0.0033 m is outside the box's [0, 0.0032] m"),
    (ok_line + "\n", ["--box", "0", "3.2", "1", "1", "0", "3.2"], 1, "--box: ylo = 0.001 must be below yhi = 0.001"),
    (ok_line + "\n", ["--box", "0", "3.2", "0"], 2, "--box needs six numbers"),
    (ok_line + "\n", ["--box", "box7.txt"], 2, "--box box7.txt: holds more than six numbers"),
    (ok_line + "\n", ["--box", "packing.txt"], 2, "--box packing.txt: not six numbers xlo xhi ylo yhi zlo zhi"),
    (ok_line + "\n", ["--crop", "0", "3.2", "0", "3.2", "0", "3.2", "--box", "0", "3.2", "0", "3.2", "0", "3.2"], 1,
     "--box and --crop: the crop box is the walls; give one of them"),
    (ok_line + "\n", ["--crop", "0", "0.01", "0", "0.01", "0", "0.01"], 1,
     "bad.txt: no sphere of its 1 lies wholly inside --crop [0, 1e-05] x [0, 1e-05] x [0, 1e-05] m"),
    (ok_line + "\n", ["--crop", "2", "1", "0", "3.2", "0", "3.2"], 1, "--crop: xlo = 0.002 must be below xhi = 0.001"),
    (ok_line + "\n", ["--crop", "0", "3.2"], 2, "--crop needs six numbers"),
    (ok_line + "\n", ["--density", "0"], 1, "--density = 0 kg/m^3 is outside sample.density's range (0, 1e6]"),
    (ok_line + "\n", ["--density-scaling", "0.5"], 1, "--density-scaling = 0.5 is outside sample.density_scaling's"),
    (ok_line + "\n", ["--scale", "abc"], 2, "--scale must be a number, got 'abc'"),
]
for k, (text, extra, code, part) in enumerate(cases):
    with open(os.path.join(work, "bad.txt"), "w") as f:
        f.write(text)
    rc, out, err = run("import", "bad.txt", "--scale", "1e-3", *extra, "--out", f"bad{k}.h5")
    check(rc == code and part in err and len(err.strip().splitlines()) == 1 and not out,
          f"case {k}: exit {rc} (want {code}), stderr {err!r}, want '{part}'")
    check(not os.path.exists(os.path.join(work, f"bad{k}.h5")), f"case {k} wrote its output")
# a dump's errors
for k, (text, part) in enumerate([
        (dump_snapshot(1, "id x y z", ["1 1 1 1"]), "bad.dump:9: ITEM: ATOMS has no x y z (or xs ys zs, xu yu zu) and "
                                                    "radius (or diameter) columns"),
        (dump_snapshot(1, "id x y z radius", ["1 1 1 1 0.2"], bounds="xy xz yz pp pp pp"),
         "bad.dump:5: a triclinic box"),
        (dump_snapshot(1, "id x y z radius", ["1 1 1 1 0.2", "2 2 2 2 0.2"])[:-13], "bad.dump: ends after line 10, an "
                                                                                  "atom line expected"),
        (dump_snapshot(1, "id x y z radius", ["1 1 1 0.2"]), "bad.dump:10: '1 1 1 0.2' is not 5 numbers")]):
    with open(os.path.join(work, "bad.dump"), "w") as f:
        f.write(text)
    rc, out, err = run("import", "bad.dump", "--out", f"bad_dump{k}.h5")
    check(rc == 1 and part in err and not os.path.exists(os.path.join(work, f"bad_dump{k}.h5")),
          f"dump case {k}: exit {rc}, stderr {err!r}, want '{part}'")
# an overlap past numerics.max_overlap's default: imported, with a warning that a run would stop at once
with open(os.path.join(work, "deep.txt"), "w") as f:
    f.write("1 1 1 0.2\n1.34 1 1 0.2\n")
rc, out, err = run("import", "deep.txt", "--scale", "1e-3", "--out", "deep.h5")
check(rc == 0 and "the largest overlap 0.3 of the smaller radius (lines 1 and 2)" in out and
      "warning: an overlap of 0.3 is past numerics.max_overlap's default 0.2" in out, f"a deep overlap: {rc} {out}")
rc, out, err = run("import", "gone.txt", "--out", "g.h5")
check(rc == 1 and "gone.txt: cannot read it" in err, f"a missing packing: {rc} {err}")
# an existing file is never replaced
before = open(os.path.join(work, "s.h5"), "rb").read()
rc, out, err = run("import", "packing.txt", "--scale", "1e-3", "--out", "s.h5")
check(rc == 1 and "s.h5: exists; import never replaces a file" in err, f"an existing out: {rc} {err}")
check(open(os.path.join(work, "s.h5"), "rb").read() == before, "an existing sample file was changed")
left = glob.glob(os.path.join(work, "*tmp*"))
check(not left, f"temporary files left: {left}")

if fails:
    print("FAIL:\n  " + "\n  ".join(fails))
    sys.exit(1)
print("import_check: ok")
