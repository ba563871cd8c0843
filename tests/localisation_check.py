#!/usr/bin/env python3
"""scripts/localisation.py against known answers:
  1. an affine motion (stretch, shear and a translation): every particle's G is F - I and its eta the von Mises
     invariant of F's Green-Lagrange strain written out here by hand, D2min 0, the whole cloud's fit the same, and
     a uniform field's band contrast exactly 1;
  2. a band: a slab 8 diameters thick, dipping 60 deg toward azimuth 210 (the conjugate of 30), sheared along its
     dip with the two blocks beside it moving rigidly, plus noise: found at its dip, azimuth and place;
  3. noise alone on an affine motion: no band (contrast well below BAND_CONTRAST);
  4. a sample about one band width across: "too small", no contrast;
  4b. the band search (directions a chunk at a time) gives, to the bit, what a search of one direction at a time
     written out here gives: on a band, on noise, on a uniform field, with the chunks' edges inside the directions;
  5. the increments of a run: which snapshot pairs (a triaxial stage's, from the previous stage's end or the sample
     file; not a cyclic stage's), with their eps_a; the increment over a critical-state window (extension's eps_a < 0);
  6. given a run (the smoke run: undrained to 1 %), its localisation.csv: the cloud's fitted eps_zz is the walls'
     strain within the boundary layer's d/(H - d), its volume change small, every column present; localisation.h5
     holds the fields as recomputed, localisation.xdmf points at them.
Usage: localisation_check.py [SMOKE_RUN_DIR FIGURES_DIR]"""
import csv
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import localisation as L  # noqa: E402

rng = np.random.default_rng(7)
# Round-off of a least-squares fit over 30 neighbours (condition number of sum dX dX^T ~ 10 for uniform points)
EXACT = 1e-10

# 1. affine
XA = rng.uniform(0, 16, (3000, 3))
F = np.array([[1.04, 0.015, 0.02], [0.0, 1.05, -0.01], [0.01, 0.0, 0.9]])  # every E_ij nonzero
XB = XA @ F.T + np.array([0.3, -0.2, 0.5])
G, eta, d2 = L.local_strain(XA, XB, 1.0)
assert np.abs(G - (F - np.eye(3))).max() < EXACT, "an affine motion's local G is not F - I"
C = F.T @ F
E = 0.5 * (C - np.eye(3))
want = math.sqrt(E[0, 1] ** 2 + E[0, 2] ** 2 + E[1, 2] ** 2
                 + ((E[0, 0] - E[1, 1]) ** 2 + (E[0, 0] - E[2, 2]) ** 2 + (E[1, 1] - E[2, 2]) ** 2) / 6)
assert np.abs(eta - want).max() < EXACT, f"eta {eta[:3]} against {want} by hand"
assert d2.max() < EXACT ** 2, f"an affine motion has D2min {d2.max()}"
row, _, _ = L.analyse(XA, XB, 1.0)
assert abs(row["eps_zz_fit"] - (F[2, 2] - 1)) < EXACT and abs(row["eps_v_fit"] - (np.linalg.det(F) - 1)) < EXACT
assert abs(row["eta_fit"] - want) < EXACT and row["nonaffine_rms"] < EXACT
assert abs(row["band_contrast"] - 1) < 1e-9 and row["localised"] == "no", row
print(f"affine: G = F - I, eta = {want:.6f} as by hand, D2min 0, contrast {row['band_contrast']:.12f}")


# 2. a band
def unit(dip, az):
    t, a = math.radians(dip), math.radians(az)
    return np.array([math.sin(t) * math.cos(a), math.sin(t) * math.sin(a), math.cos(t)])


dip, az, width, offset = 60.0, 210.0, 8.0, 1.5
XA = rng.uniform(0, 24, (12000, 3))
n = unit(dip, az)
t = unit(dip - 90.0, az)  # in the plane, along its dip (perpendicular to n)
s = (XA - XA.mean(0)) @ n - offset
XB = XA + 0.2 * np.outer(np.clip(s, -width / 2, width / 2), t) + rng.normal(0, 0.005, XA.shape)
row, eta, _ = L.analyse(XA, XB, 1.0)
got = unit(row["band_dip"], row["band_azimuth"])
assert row["localised"] == "yes" and row["band_contrast"] > 3, row
assert abs(row["band_dip"] - dip) <= L.DIP_STEP and abs(row["band_azimuth"] - az) <= L.AZIMUTH_STEP, row
assert abs(row["band_offset"] - offset) <= 1.0, row  # positions in steps of a diameter
assert abs(row["band_share"] - 6 / 24 * 1.2) < 0.1, row  # a 6-diameter slab of a 24-diameter box, ~1.2 x its width
print(f"band: dip {row['band_dip']:.0f} (60), azimuth {row['band_azimuth']:.0f} (210), offset {row['band_offset']:.1f} "
      f"(1.5), contrast {row['band_contrast']:.1f}, normals {np.degrees(np.arccos(abs(got @ n))):.1f} deg apart")

# 3. noise alone
XA = rng.uniform(0, 20, (6000, 3))
XB = XA @ F.T + rng.normal(0, 0.2, XA.shape)  # eta's CV ~0.25, as in a homogeneous DEM shear
row, _, _ = L.analyse(XA, XB, 1.0)
assert row["localised"] == "no" and row["band_contrast"] < 1.5, row
print(f"noise: contrast {row['band_contrast']:.2f}, eta CV {row['eta_cv']:.2f}: no band")

# 4. too small
XA = rng.uniform(0, 6, (300, 3))
row, _, _ = L.analyse(XA, XA @ F.T, 1.0)
assert row["localised"] == "too small" and math.isnan(row["band_contrast"]), row
print("a 6-diameter sample: too small to tell")



# 4b. the band search against one direction at a time (the module docstring's definition, written out): each
# direction's slabs in turn, a slab that does not qualify counting as contrast 0, the first of the largest
def slabs_one_at_a_time(X, eta, d, width=L.BAND_WIDTH):
    c, total, n, w = X.mean(0), eta.sum(), len(eta), int(round(width))
    rows = []
    for dip, az, normal in L.band_directions():
        s = (X - c) @ normal / d
        lo = math.floor(s.min())
        b = np.floor(s - lo).astype(int)
        cnt, sm = np.bincount(b), np.bincount(b, weights=eta)
        row, any_ok = (math.nan,) * 3, False
        if len(cnt) >= w:
            kc, ks = np.convolve(cnt, np.ones(w), "valid"), np.convolve(sm, np.ones(w), "valid")
            top = None
            for i in range(len(kc)):
                ok = L.BAND_MIN_SHARE * n <= kc[i] <= L.BAND_MAX_SHARE * n
                any_ok |= ok
                outside = (total - ks[i]) / max(n - kc[i], 1) if ok else 0.0
                con = ks[i] / max(kc[i], 1) / outside if ok and outside > 0 else 0.0
                if top is None or con > top[0]:
                    top = (con, lo + i + w / 2, kc[i] / n)
            row = top if any_ok else row
        rows.append(row)
    return np.array(rows)


for what, n_pts in (("band", 3000), ("noise", 700), ("uniform", 1100)):
    XA = rng.uniform(0, 16, (n_pts, 3))
    eta = {"band": np.where(np.abs(XA @ np.array([0.6, 0.0, 0.8]) - 9) < 3, 5.0, 1.0) + rng.uniform(0, 0.3, n_pts),
           "noise": rng.uniform(0, 1, n_pts), "uniform": np.full(n_pts, 0.25)}[what]
    (got, found), want = L.slab_contrasts(XA, eta, 1.0), slabs_one_at_a_time(XA, eta, 1.0)
    assert len(list(L.band_directions())) % max(1, L.BAND_CHUNK // n_pts) != 0, "no partial chunk"
    assert got.shape == want.shape and np.array_equal(got, want, equal_nan=True), \
        f"{what}: {np.sum(~((got == want) | np.isnan(want)))} directions' slabs differ from one direction at a time"
    assert np.array_equal(found, ~np.isnan(want[:, 0])) and found.sum() > 0.9 * len(want), f"{what}: {found.sum()}"
print("band search: the same to the bit as one direction at a time (band, noise, uniform)")

# 5. a run's increments
import h5py  # noqa: E402


def make_run(run, stages, tags, eps, n=50):
    """A run directory as grainlab writes it, with snapshots of these tags and eps_a (n random positions)."""
    os.makedirs(os.path.join(run, "snapshots"))
    with open(os.path.join(run, "config.yaml"), "w") as f:
        f.write("sample: {file: s.h5}\nstages:\n" + "".join(f"  - {{name: {n}, type: {t}}}\n" for n, t in stages))
    X = {tag: rng.uniform(0, 5, (n, 3)) for tag in tags}
    for k, tag in enumerate(tags):
        with h5py.File(os.path.join(run, "snapshots", f"snap_{k:05d}.h5"), "w") as f:
            f.attrs["tag"] = tag
            f["particles/x"] = X[tag]
            f["particles/r"] = np.full(n, 0.25)
    with h5py.File(os.path.join(run, "s.h5"), "w") as f:
        f["state/x"] = rng.uniform(0, 5, (n, 3))
        f["state/r"] = np.full(n, 0.25)
    with h5py.File(os.path.join(run, "run.h5"), "w") as f:
        names = "\n".join(f"snapshots/snap_{k:05d}.h5" for k in range(len(tags)))
        f["snapshots/files"] = np.frombuffer(names.encode(), dtype=np.int8)
        f["snapshots/eps_a"] = np.array(eps)
    return X


with tempfile.TemporaryDirectory() as tmp:
    run = os.path.join(tmp, "a")
    tags = ["cons_end", "shear_eps0", "shear_end", "shake_peak1", "shake_end", "shear_2_end"]
    X = make_run(run, [("cons", "isotropic"), ("shear", "triaxial"), ("shake", "cyclic"), ("shear_2", "triaxial")],
                 tags, [0.003, 0.01, 0.015, 0.001, 0.004, 0.02])  # a stage's own eps_a; the next stage's starts at 0
    inc = L.increments(run)
    got = [(i[0], i[1], i[2], i[3], i[4]) for i in inc]
    want = [("shear", "snap_00000.h5", "snap_00001.h5", 0.0, 0.01), ("shear", "snap_00001.h5", "snap_00002.h5", 0.01, 0.015),
            ("shear_2", "snap_00004.h5", "snap_00005.h5", 0.0, 0.02)]
    assert got == want, got
    assert np.array_equal(inc[0][5], X["cons_end"]) and np.array_equal(inc[2][6], X["shear_2_end"]) and inc[0][7] == 0.5
    assert L.window_increment(run, 0.001)[:5] == want[-1]  # the last stage's start is nearer than the window
    # a run sheared from a sample file: its first increment starts there
    os.remove(os.path.join(run, "snapshots", "snap_00000.h5"))
    inc = L.increments(run)
    assert (inc[0][0], inc[0][1], inc[0][2], inc[0][3]) == ("shear", "sample", "snap_00001.h5", 0.0), inc[0][:4]
    # the critical state's window: from the last snapshot at least `window` of eps_a before the end, or the stage's start
    run = os.path.join(tmp, "b")
    make_run(run, [("cons", "isotropic"), ("shear", "triaxial")],
             ["cons_end", "shear_eps0", "shear_eps1", "shear_eps2", "shear_end"], [0.003, -0.01, -0.02, -0.03, -0.034])
    assert L.window_increment(run, 0.01)[:5] == ("shear", "snap_00002.h5", "snap_00004.h5", -0.02, -0.034)
    assert L.window_increment(run, 0.014)[:5] == ("shear", "snap_00002.h5", "snap_00004.h5", -0.02, -0.034)
    assert L.window_increment(run, 0.0141)[:5] == ("shear", "snap_00001.h5", "snap_00004.h5", -0.01, -0.034)
    assert L.window_increment(run, 0.05)[:5] == ("shear", "snap_00000.h5", "snap_00004.h5", 0.0, -0.034)
    run = os.path.join(tmp, "c")
    make_run(run, [("shear", "triaxial"), ("shake", "cyclic")], ["shear_end", "shake_end"], [0.01, 0.0])
    assert L.window_increment(run, 0.01) is None  # the run ends in a cyclic stage
    # a run of fewer spheres than a neighbourhood (one sphere: the fits were singular, a traceback) has no field
    run = os.path.join(tmp, "d")
    make_run(run, [("cons", "isotropic"), ("shear", "triaxial")], ["cons_end", "shear_end"], [0.0, 0.01],
             n=L.K_NEIGHBOURS)
    assert len(L.increments(run)) == 1 and L.fig_localisation(run, run, None, None) == []
    assert not os.path.exists(os.path.join(run, "localisation.csv"))
print("increments: a triaxial stage's pairs from the previous stage's end or the sample file; a cyclic stage's none")

# 6. a run's localisation.csv
if len(sys.argv) > 2:
    run, figs = sys.argv[1], sys.argv[2]
    rows = list(csv.DictReader(open(os.path.join(figs, "localisation.csv"))))
    assert rows and list(rows[0]) == L.COLUMNS, rows[:1]
    r = rows[-1]
    with h5py.File(os.path.join(run, "snapshots", r["to"]), "r") as f:
        X, rad = f["particles/x"][:], f["particles/r"][:]
    d, H = 2 * rad.mean(), X[:, 2].max() - X[:, 2].min() + 2 * rad.mean()
    ea, eb = float(r["eps_a_from"]), float(r["eps_a_to"])
    walls = -(eb - ea) / (1 - ea)
    fit = float(r["eps_zz_fit"])
    assert walls < 0 and 0 <= fit / walls - 1 <= d / (H - d), (fit, walls, d / (H - d))
    assert abs(float(r["eps_v_fit"])) < 0.1 * abs(walls), r  # undrained: the walls keep the volume
    # the fields for ParaView: the last increment's eta and D2min as recomputed from its snapshots, and the XDMF that
    # points at them
    import xml.etree.ElementTree as ET

    inc = L.increments(run)[-1]
    _, eta, d2 = L.local_strain(inc[5], inc[6], inc[7])
    with h5py.File(os.path.join(figs, "localisation.h5"), "r") as f:
        k = str(len(rows) - 1)
        assert np.array_equal(f[f"increments/{k}/eta"][:], eta) and np.array_equal(f[f"increments/{k}/d2min"][:], d2)
        assert np.array_equal(f[f"increments/{k}/x"][:], X) and np.array_equal(f[f"increments/{k}/radius"][:], rad)
    items = [e.text for e in ET.parse(os.path.join(figs, "localisation.xdmf")).iter("DataItem")]
    assert f"localisation.h5:/increments/{k}/eta" in items and f"localisation.h5:/increments/{k}/x" in items, items
    print(f"run: eps_zz {fit:.5f} fitted, {walls:.5f} from the walls (boundary layer bound {d / (H - d):.3f}); "
          f"eps_v {float(r['eps_v_fit']):.2e}; {r['localised']}")
print("localisation ok")
