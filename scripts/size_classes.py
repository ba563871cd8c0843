"""How the load is shared between the sizes of a polydisperse sample: a snapshot's spheres in size classes, and for
each class its share of the solids, its contacts per sphere, its rattlers and its share of the mean stress p'.

Each sphere's stress moment is its Love-Weber sum over its contacts, S_i = sum_c (x_c - x_i) (x) f_c (compression
positive; x_c the contact point, r_i - delta/2 from the centre along n), and the spheres' moments add up to the
contacts' sum d (x) f that SPEC §7's stress is (Christoffersen et al. 1981: d = x_j - x_i splits at the contact point).
Its trace is (r_i - delta/2) f_n per contact (the tangential force is normal to the lever), so the class k carries
p'_k share = sum over its spheres' contacts of (r - delta/2) f_n / sum over every contact of |d| f_n of p'.
alpha_k = that share / the class's share of the solid volume: 1 where a class carries the stress in proportion to its
volume, below 1 where it is under-loaded, as the fines between a coarse skeleton (the stress-reduction factor of
Shire, O'Sullivan, Hanley & Fannin 2014, Geotechnique 64(8), 613-625: alpha = p'_fines / p', ~0.1-0.6 in their
gap-graded samples, 1 once the fines are part of the skeleton).

Classes: the sieve intervals of the run's `sample.grading` that hold mass (a gap grading's fines and coarse fractions
apart), else (no grading, or one interval holding all the mass) four classes of equal mass (the sample's mass
quartiles of diameter).
"""
import glob
import os

import numpy as np

# A class's Z and alpha are reported from this many spheres (a class of 5 spheres' alpha is one or two contacts' force).
MIN_SPHERES = 20


def grading_of(config_path, depth=3):
    """A run's config.yaml sample.grading ({diameter, passing}), or None. A run from a saved sample (sample.file, a
    sample_<stage>.h5 in the run directory that made it: a study's shear job) takes that run's, up to `depth` runs back."""
    import yaml

    try:
        with open(config_path) as f:
            sample = yaml.safe_load(f).get("sample") or {}
    except (OSError, AttributeError, yaml.YAMLError):
        return None
    if sample.get("grading"):
        return sample["grading"]
    if sample.get("file") and depth > 0:
        return grading_of(os.path.join(os.path.dirname(str(sample["file"])), "config.yaml"), depth - 1)
    return None


def grading_classes(config_path):
    """The non-empty sieve intervals [(d_lo, d_hi)] of a run's sample.grading (grading_of); None without one, or where
    one interval holds all the mass (a curve straight from its first sieve to its last: one class would say nothing of
    which sizes carry the load, its mass quartiles do)."""
    g = grading_of(config_path)
    if not g:
        return None
    d, p = list(map(float, g["diameter"])), list(map(float, g["passing"]))
    held = [(d[k], d[k + 1]) for k in range(len(d) - 1) if p[k + 1] > p[k]]
    return held if len(held) > 1 else None


def quartile_classes(r):
    """Four classes of equal solid volume: edges at the sample's mass quartiles of diameter."""
    d = np.sort(2 * np.asarray(r, float))
    v = np.cumsum(d ** 3) / np.sum(d ** 3)
    edges = [d[0]] + [float(d[np.searchsorted(v, q)]) for q in (0.25, 0.5, 0.75)] + [d[-1]]
    return [(edges[k], edges[k + 1]) for k in range(4) if edges[k + 1] > edges[k]] or [(d[0], d[-1])]  # equal: one


def class_of(d, classes):
    """Each diameter's class index: the interval holding it (d_lo, d_hi] (the first [d_lo, d_hi]); the ends clamp."""
    hi = np.array([c[1] for c in classes])
    return np.minimum(np.searchsorted(hi, d, side="left"), len(classes) - 1)


def load_share(x, r, i, j, fn, classes):
    """The classes' rows: d_lo, d_hi, spheres, volume_share, z (contacts per sphere), rattler_share (spheres with
    fewer than 2 contacts), p_share of p' and alpha = p_share / volume_share (NaN for an empty class)."""
    x, r, fn = np.asarray(x, float), np.asarray(r, float), np.asarray(fn, float)
    i, j = np.asarray(i), np.asarray(j)
    k = class_of(2 * r, classes)
    dist = np.linalg.norm(x[j] - x[i], axis=1)
    delta = r[i] + r[j] - dist
    mom_i, mom_j = (r[i] - delta / 2) * fn, (r[j] - delta / 2) * fn  # the trace of each sphere's moment
    total = float(np.sum(dist * fn))
    deg = np.bincount(i, minlength=len(r)) + np.bincount(j, minlength=len(r))
    mom = np.bincount(i, weights=mom_i, minlength=len(r)) + np.bincount(j, weights=mom_j, minlength=len(r))
    vol = r ** 3
    rows = []
    for c, (lo, hi) in enumerate(classes):
        m = k == c
        n = int(m.sum())
        vs = float(vol[m].sum() / vol.sum())
        ps = float(mom[m].sum() / total) if total > 0 else float("nan")
        rows.append(dict(d_lo=lo, d_hi=hi, spheres=n, volume_share=vs,
                         z=float(deg[m].mean()) if n else float("nan"),
                         rattler_share=float((deg[m] < 2).mean()) if n else float("nan"),
                         p_share=ps, alpha=ps / vs if vs > 0 else float("nan")))
    return rows


def snapshot_rows(path, classes=None):
    """A snapshot's classes (load_share), its tag and step; classes None: the sample's mass quartiles."""
    import h5py

    with h5py.File(path, "r") as f:
        x, r = f["particles/x"][:], f["particles/r"][:]
        i, j, fn = f["contacts/i"][:], f["contacts/j"][:], f["contacts/f_n"][:]
        tag = f.attrs.get("tag", "")
        step = float(f.attrs.get("step", float("nan")))
    tag = tag.decode() if isinstance(tag, bytes) else str(tag)
    return load_share(x, r, i, j, fn, classes or quartile_classes(r)), tag, step


def class_text(row):
    """A class's sizes as text: '0.425-0.5 mm'."""
    return f"{row['d_lo'] * 1e3:.3g}-{row['d_hi'] * 1e3:.3g} mm"


def alpha_text(row):
    """A class's alpha, '-' below MIN_SPHERES spheres."""
    return f"{row['alpha']:.2f}" if row["spheres"] >= MIN_SPHERES and row["alpha"] == row["alpha"] else "-"


COLUMNS = ["snapshot", "tag", "step", "d_lo", "d_hi", "spheres", "volume_share", "z", "rattler_share", "p_share", "alpha"]


def write_csv(run, out, config=None):
    """figures/size_classes.csv: a row per snapshot and class; prints the last snapshot's classes. config: the
    config.yaml whose sample.grading gives the classes (default the run's own). Returns the last snapshot's rows."""
    from atomic_write import write_text_atomically

    snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
    if not snaps:
        return []
    classes = grading_classes(config or os.path.join(run, "config.yaml"))
    lines, last = [], []
    for p in snaps:
        rows, tag, step = snapshot_rows(p, classes)
        for row in rows:
            lines.append(",".join([os.path.basename(p), tag, f"{step:.0f}"] +
                                  [f"{row[c]:.6g}" if isinstance(row[c], float) else str(row[c]) for c in COLUMNS[3:]]))
        last = rows
        last_tag = f"{os.path.basename(p)} ({tag})"
    write_text_atomically(os.path.join(out, "size_classes.csv"), ",".join(COLUMNS) + "\n" + "\n".join(lines) + "\n")
    print(f"size classes at {last_tag}: " + "; ".join(
        f"{class_text(row)}: {100 * row['volume_share']:.1f} % of the solids, Z {row['z']:.2f}, "
        f"{100 * row['p_share']:.1f} % of p' (alpha {alpha_text(row)})" for row in last))
    return last


def report_section(tests):
    """A study report's section: each test's load by size class at its end (last snapshot). tests: (name, run
    directory, config.yaml whose sample.grading gives the classes or None). Empty where none has a snapshot."""
    rows = []
    for name, run, config in tests:
        snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
        if not snaps:
            continue
        got, _, _ = snapshot_rows(snaps[-1], grading_classes(config) if config else None)
        for row in got:
            rows.append(f"| {name} | {class_text(row)} | {row['spheres']} | {100 * row['volume_share']:.1f} | "
                        f"{row['z']:.2f} | {100 * row['rattler_share']:.1f} | {100 * row['p_share']:.1f} | "
                        f"{alpha_text(row)} |")
    if not rows:
        return []
    return ["## Load by size class at the end of each test", "",
            "From each test's last snapshot (scripts/size_classes.py): the spheres in classes (the sieve intervals of "
            "the sample's `sample.grading` that hold mass, else four classes of equal mass), each class's share of the solids, its "
            "contacts per sphere Z, its rattlers (under 2 contacts; wall contacts not counted), its share of the "
            "contacts' p' (each sphere's Love-Weber moment, r - delta/2 of each contact's |d| f_n) and alpha = that "
            "share over its volume share (Shire et al. 2014's stress-reduction factor: below 1, a class the skeleton "
            f"carries less than its volume; '-' under {MIN_SPHERES} spheres). `grainlab plot` writes every snapshot's "
            "classes to figures/size_classes.csv.", "",
            "| test | class | spheres | % of solids | Z | % rattlers | % of p' | alpha |", "|---|---|---|---|---|---|---|---|",
            *rows, ""]
