"""Where a shear deforms: the local strain between a run's snapshots, and whether it localises in a band.

For each increment between two snapshots of a triaxial stage (the first from the stage's start: the previous stage's
end snapshot, or the sample file a run sheared from), every particle gets the displacement gradient G of its
neighbourhood, fitted by least squares to the displacements of its K_NEIGHBOURS nearest particles (itself included):
u = a + G (X - X_bar) over the neighbourhood, X the positions at the increment's start. The fit carries its own
intercept a (unlike OVITO's atomic strain, which fits the neighbours' displacements relative to the centre's), so a
rattler at the centre does not make its neighbourhood's strain: the field is the skeleton's, smoothed over about
three diameters. From F = I + G:
  - the Green-Lagrange strain E = (F^T F - I)/2 and its von Mises shear invariant
    eta = sqrt(E_xy^2 + E_xz^2 + E_yz^2 + ((E_xx - E_yy)^2 + (E_xx - E_zz)^2 + (E_yy - E_zz)^2)/6)
    (Shimizu, Ogata & Li 2007, Mater. Trans. 48, eq. 4; OVITO's "von Mises shear strain");
  - D2min, the mean squared residual of the fit, the non-affine motion of Falk & Langer 1998 (Phys. Rev. E 57,
    eq. 2.11) over the neighbourhood, in mean diameters squared.
The whole cloud's best affine fit (same least squares over every particle) gives the sample's own strain, against
which the mean local one is checked, and the rms non-affine displacement about it.

A band is searched as the slab of BAND_WIDTH mean diameters, over every orientation of its normal (dip 0-90 deg in
DIP_STEP, azimuth 0-360 deg in AZIMUTH_STEP) and every position (steps of one diameter, the slab holding between
BAND_MIN_SHARE and BAND_MAX_SHARE of the particles), whose mean eta exceeds the rest's the most: the contrast. A
sample deforming homogeneously still has a noisy field (eta's coefficient of variation 0.25-0.36 in the quick study's
5 000-sphere drained shears) whose best slab reaches a contrast of 1.1-1.3 there, at the box's edges; a slab that deforms
BAND_CONTRAST times faster than the rest is called a band. The dip is the band plane's angle to the horizontal
(the plane of the lateral stresses in a triaxial test; Coulomb's band lies at 45 + phi/2 deg to it, Roscoe's at
45 + psi/2).
"""
import glob
import math
import os

import numpy as np

# Neighbourhood of the local fit: the particle and its 29 nearest, two coordination shells (about 12 spheres within
# 1.2 diameters in these packings), a sphere of about 1.5 diameters: enough to fit 12 unknowns with the rattlers of a
# neighbourhood outvoted, small enough that a band of 6-10 diameters (DEM bands, e.g. Iwashita & Oda 1998) is resolved.
K_NEIGHBOURS = 30
# The band search (module docstring): a slab of 6 mean diameters, thinner than DEM bands so that a band fills it.
BAND_WIDTH = 6.0
# The slab holds between a tenth and half of the particles: a band is a part of the sample, beside a rest to compare
# it with (a sample about one band width across has no such slab in any direction: "too small" to tell).
BAND_MIN_SHARE, BAND_MAX_SHARE = 0.10, 0.50
DIP_STEP, AZIMUTH_STEP = 2.0, 10.0
# A band deforms at least twice as fast as the rest of the sample: above the 1.1-1.3 that noise reaches in a
# homogeneous 5 000-sphere shear (module docstring), below the several-fold contrasts of formed bands.
BAND_CONTRAST = 2.0


def von_mises(E):
    """The von Mises shear invariant of symmetric strain tensors E (..., 3, 3)."""
    xx, yy, zz = E[..., 0, 0], E[..., 1, 1], E[..., 2, 2]
    return np.sqrt(E[..., 0, 1] ** 2 + E[..., 0, 2] ** 2 + E[..., 1, 2] ** 2
                   + ((xx - yy) ** 2 + (xx - zz) ** 2 + (yy - zz) ** 2) / 6)


def green_lagrange(G):
    F = G + np.eye(3)
    return 0.5 * (np.swapaxes(F, -1, -2) @ F - np.eye(3))


def affine_fit(XA, U):
    """Least squares u = a + G (X - X_bar) over the rows of XA, U (..., n, 3): G (..., 3, 3) and the residuals."""
    dX = XA - XA.mean(-2, keepdims=True)
    dU = U - U.mean(-2, keepdims=True)
    C = np.swapaxes(dX, -1, -2) @ dX        # sum dX dX^T
    Y = np.swapaxes(dU, -1, -2) @ dX        # sum dU dX^T
    G = Y @ np.linalg.inv(C)
    return G, dU - dX @ np.swapaxes(G, -1, -2)


def local_strain(XA, XB, d, k=K_NEIGHBOURS):
    """Per particle: G of its neighbourhood, eta, and D2min in mean diameters squared (module docstring)."""
    from scipy.spatial import cKDTree

    k = min(k, len(XA))
    _, nb = cKDTree(XA).query(XA, k=k)
    G, res = affine_fit(XA[nb], (XB - XA)[nb])
    eta = von_mises(green_lagrange(G))
    return G, eta, (res ** 2).sum(-1).mean(-1) / d ** 2


def band_directions():
    """The band search's normals in the order searched: (dip deg, azimuth deg, unit normal) each. Dip in [0, 90] and
    azimuth in [0, 360) give every plane once (a band and its conjugate differ in azimuth)."""
    for dip in np.arange(0.0, 90.0 + 1e-9, DIP_STEP):
        for az in (np.arange(0.0, 360.0, AZIMUTH_STEP) if dip > 0 else [0.0]):
            t, a = math.radians(dip), math.radians(az)
            yield float(dip), float(az), np.array([math.sin(t) * math.cos(a), math.sin(t) * math.sin(a), math.cos(t)])


# The band search bins this many (direction, particle) pairs at once: a few MB of scratch, within a core's cache.
BAND_CHUNK = 250_000


def slab_contrasts(X, eta, d, width=BAND_WIDTH):
    """Each band direction's (band_directions, in order) slab of largest contrast (module docstring): an array (n_dir,
    3) of (contrast, offset from the cloud's centre along the normal in diameters, share of the particles in it), the
    first such slab along the normal where several tie, and whether the direction has a qualifying slab (NaN rows
    where not).

    The directions are searched a chunk at a time, each chunk's bins counted in one bincount and its slabs compared in
    whole arrays: one direction at a time, ~15 small array operations for each of 1 621 directions, the search took
    1.6 of the 2.9 s the quick study's report spent outside its figures (perf/NOTES.md, session 63). Every number is
    the one the direction's own arithmetic gave (the same projections, sums in the same order, the same slab sums by
    np.convolve), so the result is the same to the bit (tests/localisation_check.py: against one direction at a
    time)."""
    Y = X - X.mean(0)
    total, n = eta.sum(), len(eta)
    w = int(round(width))
    ones = np.ones(w)
    dirs = list(band_directions())
    out = np.full((len(dirs), 3), np.nan)
    found = np.zeros(len(dirs), bool)
    step = max(1, BAND_CHUNK // max(n, 1))
    for j0 in range(0, len(dirs), step):
        chunk = dirs[j0:j0 + step]
        m = len(chunk)
        S = np.empty((m, n))
        for k, (_, _, normal) in enumerate(chunk):
            S[k] = Y @ normal / d  # a matrix-vector product per direction, as before: a chunk's gemm might round apart
        # particles binned by whole diameters along each normal; a slab is `w` consecutive bins
        lo = np.floor(S.min(1))
        B = np.floor(S - lo[:, None]).astype(int)
        nb = B.max(1) + 1  # each direction's number of bins
        L = int(nb.max())
        # direction by direction, the particles in order (so each bin sums its particles in the order it did)
        flat = (B + (np.arange(m) * L)[:, None]).ravel()
        cnt = np.bincount(flat, minlength=m * L).reshape(m, L)
        sm = np.bincount(flat, weights=np.tile(eta, m), minlength=m * L).reshape(m, L)
        # each direction's slabs from the left; past its last one (a direction with fewer bins) kc stays 0
        V = max(L - w + 1, 1)
        kc, ks = np.zeros((m, V)), np.zeros((m, V))
        for k in range(m):
            if nb[k] >= w:
                kc[k, :nb[k] - w + 1] = np.convolve(cnt[k, :nb[k]], ones, "valid")
                ks[k, :nb[k] - w + 1] = np.convolve(sm[k, :nb[k]], ones, "valid")
        ok = (kc >= BAND_MIN_SHARE * n) & (kc <= BAND_MAX_SHARE * n)
        inside = np.where(ok, ks / np.maximum(kc, 1), 0)
        outside = np.where(ok, (total - ks) / np.maximum(n - kc, 1), 1)
        # A slab that does not qualify counts as contrast 0, as it always has. eta >= 0 (a norm), so every contrast is
        # >= 0 and the first largest of a direction lies before the zeros past its last slab.
        con = np.where(ok & (outside > 0), inside / np.where(outside > 0, outside, 1), 0)
        for k in np.flatnonzero(ok.any(axis=1)):
            i = int(np.argmax(con[k]))
            out[j0 + k] = (con[k, i], lo[k] + i + w / 2, kc[k, i] / n)
            found[j0 + k] = True
    return out, found


def band_search(X, eta, d, width=BAND_WIDTH):
    """The slab (module docstring) of largest contrast over the directions (slab_contrasts): (contrast, dip deg,
    azimuth deg, offset from the cloud's centre along the normal in diameters, share of the particles in it); the first
    direction where several tie; contrast 1 for a uniform eta, NaN where no slab qualifies (a sample too small)."""
    nan = float("nan")
    best = (nan, nan, nan, nan, nan)
    rows, found = slab_contrasts(X, eta, d, width)
    for (dip, az, _), (con, off, share), f in zip(band_directions(), rows, found):
        if f and not con <= best[0]:  # the first, or a larger one (NaN compares false)
            best = (float(con), dip, az, float(off), float(share))
    return best


def _stage_of(tag, stages):
    """The stage (its config entry) that wrote a snapshot of this tag: NAME_end, NAME_epsK or NAME_peakK."""
    for s in stages:
        name = s.get("name", "")
        if tag == name + "_end" or tag.startswith(name + "_eps") or tag.startswith(name + "_peak"):
            return s
    return None


def snapshots(run):
    """A run's positions in the order written: (label, stage config entry or None, X, eps_a of its stage or None, mean
    diameter, radii, time or None); first ("sample", None, X, 0.0, d, r, None) where the run sheared a sample file.
    Empty without snapshots."""
    import h5py
    import yaml

    snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
    cfg_path = os.path.join(run, "config.yaml")
    if not snaps or not os.path.isfile(cfg_path):
        return []
    with open(cfg_path) as f:
        cfg = yaml.safe_load(f) or {}
    stages = cfg.get("stages") or []
    eps = {}
    try:
        with h5py.File(os.path.join(run, "run.h5"), "r") as f:
            files = f["snapshots/files"][:].tobytes().decode().split("\n") if "snapshots/files" in f else []
            vals = f["snapshots/eps_a"][:] if "snapshots/eps_a" in f else []
            eps = {os.path.basename(p): float(v) for p, v in zip(files, vals)}
    except OSError:
        pass
    out = []
    sample = (cfg.get("sample") or {}).get("file")
    if sample and stages:
        path = sample if os.path.isabs(sample) else os.path.join(run, sample)
        try:
            with h5py.File(path, "r") as f:
                r = f["state/r"][:]
                out.append(("sample", None, f["state/x"][:], 0.0, 2 * float(r.mean()), r, None))
        except (OSError, KeyError):
            pass
    for p in snaps:
        with h5py.File(p, "r") as f:
            tag = f.attrs["tag"]
            tag = tag.decode() if isinstance(tag, bytes) else str(tag)
            X, r = f["particles/x"][:], f["particles/r"][:]
            time = float(f.attrs["time"]) if "time" in f.attrs else None
        label = os.path.basename(p)
        out.append((label, _stage_of(tag, stages), X, eps.get(label), 2 * float(r.mean()), r, time))
    return out


def _pair(a, b):
    """The increment from position set a to b (entries of snapshots()), b in a triaxial stage: (stage name, a's label,
    b's label, eps_a at each end, XA, XB, mean diameter, b's radii, b's time). Within b's stage a's eps_a; from the
    stage's start (another stage's end snapshot, or the sample file), 0."""
    st = b[1]
    e0 = a[3] if a[1] is not None and a[1].get("name") == st["name"] else 0.0
    return (st["name"], a[0], b[0], e0, b[3], a[2], b[2], b[4], b[5], b[6])


def _triaxial(snap):
    return snap[1] is not None and snap[1].get("type") == "triaxial"


def increments(run):
    """The increments between consecutive snapshots of a run's triaxial stages (_pair), in the order written."""
    snaps = snapshots(run)
    return [_pair(a, b) for a, b in zip(snaps, snaps[1:]) if _triaxial(b) and len(a[2]) == len(b[2])]


def window_increment(run, window):
    """The increment over which a run's critical state is judged: from the last snapshot at least `window` of axial
    strain before the run's last snapshot (or its stage's start) to that last one, which must be a triaxial stage's;
    None otherwise."""
    snaps = snapshots(run)
    if len(snaps) < 2 or not _triaxial(snaps[-1]) or snaps[-1][3] is None:
        return None
    b, name = snaps[-1], snaps[-1][1]["name"]
    ref = None
    for k in range(len(snaps) - 2, -1, -1):
        a = snaps[k]
        ref = a
        if a[1] is None or a[1].get("name") != name:  # the stage's start
            break
        if a[3] is not None and abs(b[3] - a[3]) >= window:
            break
    return _pair(ref, b) if ref is not None and len(ref[2]) == len(b[2]) else None


COLUMNS = ["stage", "from", "to", "eps_a_from", "eps_a_to", "eps_zz_fit", "eps_v_fit", "eta_fit", "eta_mean",
           "eta_cv", "eta_p90", "nonaffine_rms", "d2min_mean", "band_contrast", "band_dip", "band_azimuth",
           "band_offset", "band_share", "localised"]


def analyse(XA, XB, d):
    """One increment's row (COLUMNS from eps_zz_fit on) and its per-particle eta and D2min."""
    Gg, res = affine_fit(XA, XB - XA)
    F = Gg + np.eye(3)
    _, eta, d2 = local_strain(XA, XB, d)
    mean = float(eta.mean())
    con, dip, az, off, share = band_search(XA, eta, d)
    row = {
        "eps_zz_fit": float(Gg[2, 2]), "eps_v_fit": float(np.linalg.det(F) - 1),
        "eta_fit": float(von_mises(green_lagrange(Gg))), "eta_mean": mean,
        "eta_cv": float(eta.std() / mean) if mean > 0 else 0.0,
        "eta_p90": float(np.percentile(eta, 90) / mean) if mean > 0 else 0.0,
        "nonaffine_rms": float(np.sqrt((res ** 2).sum(-1).mean()) / d), "d2min_mean": float(d2.mean()),
        "band_contrast": con, "band_dip": dip, "band_azimuth": az, "band_offset": off, "band_share": share,
        "localised": "too small" if math.isnan(con) else "yes" if con >= BAND_CONTRAST else "no",
    }
    return row, eta, d2


def write_fields(out, fields, write_atomically, write_text_atomically):
    """localisation.h5 (/increments/K/{x, radius, eta, d2min, vertex}, K from 0) and localisation.xdmf: every
    increment's particles at its end as vertex cells with their eta and D2min [mean diameters^2], at the end snapshot's
    time (the increment's number where it has none), for ParaView (Point Gaussian or Glyph by radius, coloured by eta).
    `vertex` (0 .. n-1) is the Polyvertex topology's connectivity: without one VTK's Xdmf3 reader makes no cells."""
    import h5py

    def fill(tmp):
        with h5py.File(tmp, "w") as f:
            for k, fl in enumerate(fields):
                g = f.create_group(f"increments/{k}")
                g["x"], g["radius"], g["eta"], g["d2min"] = fl["XB"], fl["r"], fl["eta"], fl["d2"]
                g["vertex"] = np.arange(len(fl["XB"]), dtype=np.int32)

    write_atomically(os.path.join(out, "localisation.h5"), fill)
    x = ['<?xml version="1.0" ?>', '<Xdmf Version="3.0">', "<Domain>",
         '<Grid Name="localisation" GridType="Collection" CollectionType="Temporal">']
    for k, fl in enumerate(fields):
        n, t = len(fl["XB"]), fl["t"]
        x += [f' <Grid Name="i{k}"><Time Value="{t if t is not None else k!r}"/>',
              f'  <Topology TopologyType="Polyvertex" NodesPerElement="1" NumberOfElements="{n}"><DataItem '
              f'Dimensions="{n} 1" NumberType="Int" Precision="4" Format="HDF">localisation.h5:/increments/{k}/vertex'
              '</DataItem></Topology>',
              f'  <Geometry GeometryType="XYZ"><DataItem Dimensions="{n} 3" NumberType="Float" Precision="8" '
              f'Format="HDF">localisation.h5:/increments/{k}/x</DataItem></Geometry>']
        for name in ("radius", "eta", "d2min"):
            x.append(f'  <Attribute Name="{name}" Center="Node"><DataItem Dimensions="{n}" NumberType="Float" '
                     f'Precision="8" Format="HDF">localisation.h5:/increments/{k}/{name}</DataItem></Attribute>')
        x.append(" </Grid>")
    write_text_atomically(os.path.join(out, "localisation.xdmf"), "\n".join(x + ["</Grid>", "</Domain>", "</Xdmf>", ""]))
    print(f"ParaView: open {os.path.join(out, 'localisation.xdmf')} (local strain eta, D2min)")


def fig_localisation(run, out, save, plt, max_panels=6):
    """figures/localisation.csv (a row per increment), localisation.png (eta / its mean on a mid slab, y within 15 % of
    the width of the centre, at the increment's end, for up to max_panels increments, evenly spaced, the last included;
    the band's trace where there is one) and, for ParaView, localisation.h5 + localisation.xdmf (every increment's
    particles at its end with eta and D2min, one time step each). Nothing without a triaxial increment."""
    from atomic_write import write_atomically, write_text_atomically

    incs = increments(run)
    if not incs:
        return []
    n = len(incs[0][5])
    if n <= K_NEIGHBOURS:  # each sphere's strain is fitted over its K_NEIGHBOURS nearest: fewer leave no field
        print(f"localisation: none ({n} spheres: a local strain needs {K_NEIGHBOURS + 1} or more)")
        return []
    rows, fields = [], []
    for stage, a, b, ea, eb, XA, XB, d, r, t in incs:
        row, eta, d2 = analyse(XA, XB, d)
        row.update({"stage": stage, "from": a, "to": b, "eps_a_from": ea, "eps_a_to": eb})
        rows.append(row)
        fields.append(dict(XB=XB, eta=eta, row=row, d=d, d2=d2, r=r, t=t))

    def fmt(v):
        return f"{v:.6g}" if isinstance(v, float) else ("" if v is None else str(v))

    write_text_atomically(os.path.join(out, "localisation.csv"),
                          ",".join(COLUMNS) + "\n" + "".join(",".join(fmt(r[c]) for c in COLUMNS) + "\n"
                                                             for r in rows))
    write_fields(out, fields, write_atomically, write_text_atomically)
    pick = sorted(set(np.linspace(0, len(fields) - 1, min(max_panels, len(fields))).round().astype(int)))
    fig, axes = plt.subplots(1, len(pick) + 1, figsize=(3.2 * len(pick) + 0.8, 3.9), squeeze=False,
                             gridspec_kw={"width_ratios": [1.0] * len(pick) + [0.06]})
    for ax, k in zip(axes[0], pick):
        XB, eta, row, d = (fields[k][key] for key in ("XB", "eta", "row", "d"))
        y0, y1 = XB[:, 1].min(), XB[:, 1].max()
        yc = 0.5 * (y0 + y1)
        m = np.abs(XB[:, 1] - yc) < 0.15 * (y1 - y0)
        sc = ax.scatter(XB[m, 0], XB[m, 2], c=eta[m] / row["eta_mean"], s=9, cmap="magma", vmin=0, vmax=3,
                        linewidths=0)
        if row["localised"] == "yes":
            # the band's mid-plane where it cuts y = yc: found in the start positions, drawn about the end positions'
            # centre (a guide; the numbers are in localisation.csv)
            t, az = math.radians(row["band_dip"]), math.radians(row["band_azimuth"])
            nrm = np.array([math.sin(t) * math.cos(az), math.sin(t) * math.sin(az), math.cos(t)])
            c = XB.mean(0) + row["band_offset"] * d * nrm
            xs = np.linspace(XB[:, 0].min(), XB[:, 0].max(), 2)
            if abs(nrm[2]) > 1e-6:
                ax.plot(xs, c[2] - (nrm[0] * (xs - c[0]) + nrm[1] * (yc - c[1])) / nrm[2], "c--", lw=1)
        ea = row["eps_a_from"]
        eb = row["eps_a_to"]
        span = f"eps_a {ea:.3g} to {eb:.3g}" if eb is not None else row["to"]
        ax.set_title(f"{row['stage']}: {span}\nCV {row['eta_cv']:.2f}, band contrast {row['band_contrast']:.2f}",
                     fontsize=8)
        ax.set(aspect="equal", xticks=[], yticks=[])
        ax.set_ylim(XB[:, 2].min(), XB[:, 2].max())
    fig.colorbar(sc, cax=axes[0][-1], label="local shear strain eta / its mean")
    save(fig, out, "localisation")
    top = max(rows, key=lambda r: -1.0 if math.isnan(r["band_contrast"]) else r["band_contrast"])
    print(f"local strain: {len(rows)} increment(s); eta's CV {min(r['eta_cv'] for r in rows):.2f}-"
          f"{max(r['eta_cv'] for r in rows):.2f}; largest band contrast {top['band_contrast']:.2f} ({top['to']}): "
          + ("localised" if any(r["localised"] == "yes" for r in rows) else
             "too small to tell" if all(r["localised"] == "too small" for r in rows) else "no band"))
    return rows


def report_section(tests, window):
    """A study report's section: each monotonic test's local strain over its critical-state window (window_increment);
    tests are (name, run directory). Empty where no test has the snapshots."""
    rows = []
    for name, run in tests:
        inc = window_increment(run, window)
        if inc is None:
            continue
        ea, eb, XA, XB, d = inc[3:8]
        row, _, _ = analyse(XA, XB, d)
        band = ("-" if math.isnan(row["band_contrast"]) else
                f"{row['band_contrast']:.2f} ({row['band_dip']:.0f}° / {row['band_azimuth']:.0f}°)")
        rows.append(f"| {name} | {100 * ea:.1f} to {100 * eb:.1f} | {row['eta_mean']:.3f} | {row['eta_cv']:.2f} | "
                    f"{row['nonaffine_rms']:.3f} | {row['d2min_mean']:.4f} | {band} | {row['localised']} |")
    if not rows:
        return []
    return ["## Where the critical state is measured: local strain and localisation", "",
            f"Each test's local strain from the last snapshot at least {window:g} of axial strain before its end (or its "
            "stage's start) to its end (scripts/localisation.py): every particle's displacement gradient fitted over its "
            f"{K_NEIGHBOURS} nearest particles, eta its von Mises shear strain (Green-Lagrange), CV eta's coefficient of "
            "variation over the particles, the rms displacement about the sample's best affine motion and D2min (Falk & "
            "Langer's non-affine residual of each neighbourhood) in mean diameters. Band: the largest ratio of the mean "
            f"eta in a slab {BAND_WIDTH:g} diameters thick (any orientation: dip from the horizontal / azimuth) to the "
            f"rest's; localised from {BAND_CONTRAST:g} (a homogeneous shear's noise reaches 1.1-1.3). A localised test's "
            "critical state is the band's, not the sample's: its e_c and p'_c average a band and the blocks beside it. "
            "`grainlab plot` on a test's run draws the fields of every increment (figures/localisation.png).", "",
            "| test | eps_a [%] | eta mean | CV | non-affine rms [d] | D2min [d^2] | band contrast (dip / azimuth) | "
            "localised |",
            "|---|---|---|---|---|---|---|---|", *rows, ""]
