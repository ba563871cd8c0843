"""The contact network of a snapshot: force distribution and the orientation roses behind the anisotropies.

From a snapshot's contacts (normal n from i to j, normal force f_n, tangential force f_t on j, positions for the branch
vectors), recomputed here on the host exactly as SPEC §7 defines them (the device's series columns a_c, a_d, a_n, a_t
at the same instant are the same numbers: tests/contacts_check.py), and drawn the way the micromechanics literature
reads them:
  - P(f_n / <f_n>): the normal-force distribution; above the mean it decays exponentially, P ~ exp(-beta f/<f>)
    (Radjai, Jean, Moreau & Roux 1996, Phys. Rev. Lett. 77, 274: beta ~ 1.4 in 2-D), the strong network's signature;
    beta is fitted over f/<f> from 1 to the first bin with fewer than TAIL_MIN_COUNT contacts;
  - roses in the x-z plane (the axial plane of a triaxial test), each averaged over the azimuth: the density of contact
    normals E(n) 4 pi against its second-order fit 1 + a^c : nn (Rothenburg & Bathurst 1989, Geotechnique 39, eq. 4
    in 3-D form), the mean normal force of the contacts in a direction over f_0 against 1 + a^n : nn, and the mean
    tangential force along the meridian over f_0 against e_theta . a^t n (Ouadfel & Rothenburg 2001, Mech. Mater. 33):
    where the measured roses leave the fits, the anisotropies (and the stress-force-fabric sum built on them) miss
    part of the distribution;
  - roses in the three coordinate planes x-z, y-z and x-y (contacts_planes.png): the normals within PLANE_BAND of a
    plane, by their angle in it, against the same fits averaged over the band. The azimuth average above is the whole
    story of an axisymmetric test (a triaxial compression or extension, an oedometer); a true triaxial test (b > 0)
    orders its contacts in the x-y plane too (Thornton 2000, Geotechnique 50, 43), which only the plane roses show.
"""
import glob
import math
import os

import numpy as np

# Bins of P(f / <f>) and of the roses: the distribution in BIN_WIDTH of f/<f>; the roses in ROSE_BINS bands of equal
# solid angle (equal steps of cos theta) from the z axis to the equator, the two hemispheres folded (n and -n are the
# same contact seen from its other particle).
BIN_WIDTH, ROSE_BINS = 0.2, 9
# The exponential tail is fitted where a bin holds at least this many contacts (a Poisson count's log has a standard
# error of 1/sqrt(count): 0.45 here).
TAIL_MIN_COUNT = 5
# The plane roses: the normals with |n . e_3| < PLANE_BAND (e_3 the plane's normal; sin 15 deg: a quarter of the
# contacts, whose band-averaged fit departs from the plane's own value by s^2/3 = 2 % of a) in PLANE_BINS bins of
# its angle over 180 deg (n and -n folded).
PLANE_BAND, PLANE_BINS = math.sin(math.radians(15)), 12
# A plane rose's bin enters the report's departures (plane_departure) from this many contacts (a Poisson count's
# relative error 1/sqrt(30) = 18 %: below it a bin's own standard error is too rough to divide by).
PLANE_MIN_COUNT = 30
# (name, horizontal axis e_1, vertical axis e_2, normal axis e_3) of each plane; an angle psi from e_2 toward e_1.
PLANES = (("x-z", 0, 2, 1), ("y-z", 1, 2, 0), ("x-y", 0, 1, 2))


def load(path):
    """A snapshot's contacts: n, f_n, f_t, branch vectors d = x_j - x_i and their lengths, the step and tag."""
    import h5py

    with h5py.File(path, "r") as f:
        x = f["particles/x"][:]
        i, j = f["contacts/i"][:], f["contacts/j"][:]
        c = dict(n=f["contacts/n"][:], fn=f["contacts/f_n"][:], ft=f["contacts/f_t"][:], d=x[j] - x[i],
                 step=float(f.attrs.get("step", float("nan"))))
        tag = f.attrs.get("tag", "")
        c["tag"] = tag.decode() if isinstance(tag, bytes) else str(tag)
    c["l"] = np.linalg.norm(c["d"], axis=1) if len(c["fn"]) else np.zeros(0)
    return c


def _dev(a):
    return a - np.trace(a) / 3 * np.eye(3)


def _sym(a):
    return 0.5 * (a + a.T)


def anisotropy(n, fn, ft, d, l):
    """SPEC §7 for one network: the tensors a^c, a^d, a^n, a^t (3x3), f_0, d_0, and each one's signed scalar (its
    sign that of a : s, s the deviator of the Christoffersen stress sum f (x) d of these contacts)."""
    nc = len(fn)
    if nc == 0:
        return None
    f = fn[:, None] * n + ft
    s = _dev(_sym(np.einsum("ci,cj->ij", f, d)))
    ac = 7.5 * _dev(np.einsum("ci,cj->ij", n, n) / nc)
    w = 1 / (1 + np.einsum("ij,ci,cj->c", ac, n, n))
    dd = np.einsum("c,ci,cj->ij", w * l, n, n) / nc
    chn = np.einsum("c,ci,cj->ij", w * fn, n, n) / nc
    cht = _sym(np.einsum("c,ci,cj->ij", w, ft, n) / nc)
    d0, f0 = np.trace(dd), np.trace(chn)
    out = dict(ac=ac, ad=7.5 * _dev(dd) / d0, an=7.5 * _dev(chn) / f0, at=5.0 * _dev(cht) / f0, f0=f0, d0=d0)
    for k in ("ac", "ad", "an", "at"):
        a = out[k]
        mag = math.sqrt(1.5 * float((a * a).sum()))
        out["a_" + k[1]] = -mag if float((a * s).sum()) < 0 else mag
    return out


def exponential_tail(x):
    """beta, its standard error and the line's ln(count) at x = 0, of P(x) ~ exp(-beta x) over x >= 1 (x = f/<f>), the
    counts in bins of BIN_WIDTH from 1: weighted least squares of ln(count)
    on the bins' centres, each weighted by its count (the inverse variance of a Poisson count's log), up to the last
    bin before the first with fewer than TAIL_MIN_COUNT contacts; NaN where fewer than three bins qualify."""
    edges = np.arange(1.0, max(1.0 + 3 * BIN_WIDTH, x.max() + BIN_WIDTH), BIN_WIDTH)
    cnt, _ = np.histogram(x, edges)
    # up to the first bin below TAIL_MIN_COUNT: the sparse bins beyond, kept only where not empty, would bias the
    # tail up
    low = np.nonzero(cnt < TAIL_MIN_COUNT)[0]
    k = np.arange(low[0] if len(low) else len(cnt))
    if len(k) < 3:
        return float("nan"), float("nan"), float("nan")
    xc, y, wt = 0.5 * (edges[k] + edges[k + 1]), np.log(cnt[k]), cnt[k].astype(float)
    A = np.stack([np.ones_like(xc), xc], 1)
    cov = np.linalg.inv(A.T @ (wt[:, None] * A))
    coef = cov @ A.T @ (wt * y)
    res = y - A @ coef
    dof = len(k) - 2
    # the residuals' scatter about the line, beyond Poisson's, widens the error when it is larger (reduced chi^2 > 1)
    scale = max(1.0, float((wt * res ** 2).sum()) / dof) if dof > 0 else 1.0
    return float(-coef[1]), float(math.sqrt(cov[1, 1] * scale)), float(coef[0])


def beta_text(row):
    """beta and its standard error as printed, or "-" where the tail has fewer than three bins of TAIL_MIN_COUNT
    contacts (exponential_tail's NaN): a small sample's console line, legend and report row say the same."""
    return "-" if row["beta"] != row["beta"] else f"{row['beta']:.2f} ± {row['beta_se']:.2f}"


def _bin_forces(k, nbins, f, f0):
    """Per bin k of nbins: the count, the mean f / f_0 (NaN in an empty bin) and its standard error (the bin's
    standard deviation / sqrt(count))."""
    cnt = np.bincount(k, minlength=nbins).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.bincount(k, weights=f, minlength=nbins) / cnt / f0
        sq = np.bincount(k, weights=f * f, minlength=nbins) / cnt / f0 ** 2
        return cnt, mean, np.sqrt(np.maximum(sq - mean ** 2, 0) / cnt)


def roses(n, fn, ft, f0, errors=False):
    """The azimuth-averaged roses over ROSE_BINS bands of theta (from z), both hemispheres folded: the bands' centres
    theta [rad], the normals' density 4 pi E, the mean f_n / f_0, the mean f_t . e_theta / f_0 (NaN in an empty band);
    with errors, also the sampling standard errors of the density (a Poisson count's, density / sqrt(count)) and of
    the mean f_n / f_0 (the band's standard deviation / sqrt(count))."""
    flip = n[:, 2] < 0  # n -> -n, and the force on the other particle: f_t -> -f_t
    m = np.where(flip[:, None], -n, n)
    t = np.where(flip[:, None], -ft, ft)
    cz = np.clip(m[:, 2], 0, 1)
    edges = np.linspace(1, 0, ROSE_BINS + 1)  # cos theta from the pole to the equator
    k = np.minimum((((1 - cz) * ROSE_BINS)).astype(int), ROSE_BINS - 1)
    theta = np.arccos(m[:, 2].clip(-1, 1))
    phi = np.arctan2(m[:, 1], m[:, 0])
    e_theta = np.stack([np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi), -np.sin(theta)], 1)
    cnt, fnm, se_f = _bin_forces(k, ROSE_BINS, fn, f0)
    with np.errstate(invalid="ignore", divide="ignore"):
        dens = cnt / (len(fn) * (edges[:-1] - edges[1:]))
        ftm = np.bincount(k, weights=(t * e_theta).sum(1), minlength=ROSE_BINS) / cnt / f0
        se_d = dens / np.sqrt(cnt)
    centres = np.arccos(0.5 * (edges[:-1] + edges[1:]))
    if not errors:
        return centres, dens, fnm, ftm
    return centres, dens, fnm, ftm, se_d, se_f


def plane_roses(n, fn, f0, plane, errors=False):
    """The roses in one of PLANES: the bins' centre angles psi [rad] from e_2 toward e_1 in [0, pi), the density of
    normals 4 pi E (the band's share of an isotropic distribution is PLANE_BAND dpsi / pi a bin) and the mean f_n / f_0
    (NaN in an empty bin); with errors, their sampling standard errors as roses() gives them and the bins' counts."""
    _, i1, i2, i3 = plane
    band = np.abs(n[:, i3]) < PLANE_BAND
    psi = np.mod(np.arctan2(n[band, i1], n[band, i2]), np.pi)  # n and -n: the same contact, psi and psi + pi
    k = np.minimum((psi / np.pi * PLANE_BINS).astype(int), PLANE_BINS - 1)
    cnt, fnm, se_f = _bin_forces(k, PLANE_BINS, fn[band], f0)
    dens = cnt / (len(fn) * PLANE_BAND / PLANE_BINS)
    centres = (np.arange(PLANE_BINS) + 0.5) * np.pi / PLANE_BINS
    if not errors:
        return centres, dens, fnm
    with np.errstate(divide="ignore", invalid="ignore"):  # an empty bin (0 / 0 there): NaN, as its mean f_n
        return centres, dens, fnm, dens / np.sqrt(cnt), se_f, cnt


def plane_fit(a, psi, plane):
    """a : nn averaged over a plane rose's band at the angle psi (for the density and normal-force roses: 1 + this):
    n = sqrt(1 - u^2) m + u e_3, m = sin psi e_1 + cos psi e_2, u uniform in (-PLANE_BAND, PLANE_BAND) (the solid
    angle's measure), so <1 - u^2> = 1 - s^2/3, <u^2> = s^2/3 and the terms odd in u vanish."""
    _, i1, i2, i3 = plane
    s1, c1 = np.sin(psi), np.cos(psi)
    mm = a[i1, i1] * s1 ** 2 + 2 * a[i1, i2] * s1 * c1 + a[i2, i2] * c1 ** 2
    w = PLANE_BAND ** 2 / 3
    return (1 - w) * mm + w * a[i3, i3]


def rose_fit(a, theta):
    """The azimuth average of a : nn at polar angle theta (for the density and normal-force roses: 1 + this) and of
    e_theta . a n (the tangential rose), for a symmetric tensor a."""
    c2, s2 = np.cos(theta) ** 2, np.sin(theta) ** 2
    lat = 0.5 * (a[0, 0] + a[1, 1])
    return a[2, 2] * c2 + lat * s2, np.sin(theta) * np.cos(theta) * (lat - a[2, 2])


def network(c):
    """One snapshot's numbers: (row for contacts.csv, anisotropy dict, x = f_n / <f_n>); None without contacts."""
    if len(c["fn"]) == 0:
        return None
    A = anisotropy(c["n"], c["fn"], c["ft"], c["d"], c["l"])
    x = c["fn"] / c["fn"].mean()
    beta, se, ln0 = exponential_tail(x)
    row = dict(contacts=len(x), f_mean=float(c["fn"].mean()), strong_frac=float((x > 1).mean()), beta=beta,
               beta_se=se, tail_ln0=ln0, a_c=A["a_c"], a_d=A["a_d"], a_n=A["a_n"], a_t=A["a_t"])
    return row, A, x


COLUMNS = ["snapshot", "tag", "step", "contacts", "f_mean", "strong_frac", "beta", "beta_se", "a_c", "a_d", "a_n", "a_t"]


def fig_contacts(run, out, save, plt):
    """figures/contacts.csv (a row per snapshot) and contacts.png: P(f_n/<f_n>) and the three roses for the run's
    last snapshot and, where the last stage has a snapshot before it, the previous stage's end (the shear's start)."""
    from atomic_write import write_text_atomically

    snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
    if not snaps:
        return []
    rows, nets = [], {}
    for p in snaps:
        c = load(p)
        got = network(c)
        if got is None:
            continue
        row, A, x = got
        row.update(snapshot=os.path.basename(p), tag=c["tag"], step=c["step"])
        rows.append(row)
        nets[p] = (c, A, x, row)
    if not rows:
        return []

    def fmt(v):
        return f"{v:.6g}" if isinstance(v, float) else str(v)

    write_text_atomically(os.path.join(out, "contacts.csv"), ",".join(COLUMNS) + "\n"
                          + "".join(",".join(fmt(r[k]) for k in COLUMNS) + "\n" for r in rows))
    last = max(nets)
    stage = nets[last][0]["tag"].rsplit("_", 1)[0]
    before = [p for p in nets if p < last and not nets[p][0]["tag"].startswith(stage + "_")]
    show = ([max(before)] if before else []) + [last]
    fig = plt.figure(figsize=(16, 4.2))
    ax0 = fig.add_subplot(1, 4, 1)
    axr = [fig.add_subplot(1, 4, k, projection="polar") for k in (2, 3)]
    ax3 = fig.add_subplot(1, 4, 4)
    full = np.linspace(0, 2 * np.pi, 361)
    for p, style in zip(show, ["--", "-"][-len(show):]):
        c, A, x, row = nets[p]
        lab = f"{row['tag']}"
        edges = np.arange(0, x.max() + BIN_WIDTH, BIN_WIDTH)
        cnt, _ = np.histogram(x, edges)
        pdf = cnt / (len(x) * BIN_WIDTH)
        line, = ax0.semilogy(0.5 * (edges[:-1] + edges[1:])[cnt > 0], pdf[cnt > 0], "o" + style, ms=3,
                             label=f"{lab}: beta {beta_text(row)}")
        if row["beta"] == row["beta"]:
            xs = np.linspace(1, x.max(), 50)
            # the fitted line, its counts in bins of BIN_WIDTH as a density
            ax0.semilogy(xs, np.exp(row["tail_ln0"] - row["beta"] * xs) / (len(x) * BIN_WIDTH), ":",
                         color=line.get_color())
        th, dens, fnm, ftm = roses(c["n"], c["fn"], c["ft"], A["f0"])
        # each band drawn at its theta in the four quadrants of the x-z plane (polar angle from z: theta = 0 at the top)
        quads = np.concatenate([th, np.pi - th[::-1], np.pi + th, 2 * np.pi - th[::-1]])
        for ax, val, a in ((axr[0], dens, A["ac"]), (axr[1], fnm, A["an"])):
            v = np.concatenate([val, val[::-1], val, val[::-1]])
            ax.plot(quads, v, "o", ms=3, color=line.get_color())
            ax.plot(full, 1 + rose_fit(a, full)[0], style, color=line.get_color(), lw=1)
        ax3.plot(np.degrees(th), ftm, "o", ms=3, color=line.get_color())
        tf = np.linspace(0, np.pi / 2, 91)
        ax3.plot(np.degrees(tf), rose_fit(A["at"], tf)[1], style, color=line.get_color(), lw=1,
                 label=f"{lab}: a_c {row['a_c']:.3f}, a_n {row['a_n']:.3f}, a_t {row['a_t']:.3f}")
    ax0.set(xlabel="f_n / <f_n>", ylabel="probability density", title="normal forces (dotted: exponential tail)")
    for ax, t in zip(axr, ["contact normals 4 pi E(n) (line: 1 + a_c:nn)", "mean f_n / f_0 (line: 1 + a_n:nn)"]):
        ax.set_theta_zero_location("N")
        ax.set_title(t, fontsize=9)
    ax3.set(xlabel="angle from the axial direction z [deg]", ylabel="mean f_t . e_theta / f_0",
            title="tangential forces (line: e_theta . a_t n)")
    ax0.legend(fontsize=7)
    ax3.legend(fontsize=7)
    ax0.grid(alpha=0.3)
    ax3.grid(alpha=0.3)
    save(fig, out, "contacts")
    fig_planes([nets[p] for p in show], out, save, plt)
    r = nets[last][3]
    print(f"contacts at {r['snapshot']} ({r['tag']}): {r['contacts']}, beta {beta_text(r)}, "
          f"a_c {r['a_c']:.3f}, a_d {r['a_d']:.3f}, a_n {r['a_n']:.3f}, a_t {r['a_t']:.3f}")
    return rows


def fig_planes(nets, out, save, plt):
    """contacts_planes.png: the density of normals (top) and the mean f_n / f_0 (bottom) in the x-z, y-z and x-y
    planes (points; line: the band-averaged fit 1 + a:nn) for each (contacts, anisotropies, x, row) of nets, the last
    solid, the one before it dashed. Each plane is drawn with its vertical axis up and its horizontal axis right."""
    fig, axes = plt.subplots(2, 3, figsize=(12, 8), subplot_kw={"projection": "polar"})
    full = np.linspace(0, 2 * np.pi, 361)
    for k, ((c, A, _, row), style) in enumerate(zip(nets, ["--", "-"][-len(nets):])):
        colour = f"C{k}"
        for j, plane in enumerate(PLANES):
            psi, dens, fnm = plane_roses(c["n"], c["fn"], A["f0"], plane)
            both = np.concatenate([psi, psi + np.pi])
            for ax, val, a in ((axes[0, j], dens, A["ac"]), (axes[1, j], fnm, A["an"])):
                ax.plot(both, np.concatenate([val, val]), "o", ms=3, color=colour)
                ax.plot(full, 1 + plane_fit(a, full, plane), style, color=colour, lw=1,
                        label=row["tag"] if ax is axes[0, 0] else None)
    names = "xyz"
    for j, (name, i1, i2, i3) in enumerate(PLANES):
        for i, what in enumerate(("contact normals 4 pi E(n)", "mean f_n / f_0")):
            ax = axes[i, j]
            ax.set_theta_zero_location("N")
            ax.set_theta_direction(-1)  # psi from the vertical axis toward the horizontal one, drawn to the right
            ax.set_xticks(np.radians([0, 90, 180, 270]), [names[i2], names[i1], "", ""])
            ax.set_title(f"{what}, {name} plane (|n_{names[i3]}| < {PLANE_BAND:.2f})", fontsize=9)
    fig.legend(fontsize=8, loc="lower center", ncol=2)
    fig.suptitle("roses in the coordinate planes (lines: 1 + a_c:nn, 1 + a_n:nn averaged over the band)", fontsize=10)
    save(fig, out, "contacts_planes")


def rose_departure(c, A):
    """What the second-order fits (and the stress-force-fabric sum built on them) leave: for the normals' density
    against 1 + a_c:nn and the mean normal force against 1 + a_n:nn, the largest departure over the rose bands and the
    largest in units of its band's sampling standard error (z; the largest of ROSE_BINS |z| of pure sampling noise
    is below 2.5 nine times in ten)."""
    th, dens, fnm, _, se_d, se_f = roses(c["n"], c["fn"], c["ft"], A["f0"], errors=True)
    out = []
    for val, se, a in ((dens, se_d, A["ac"]), (fnm, se_f, A["an"])):
        off = val - 1 - rose_fit(a, th)[0]
        out += [float(np.nanmax(np.abs(off))), float(np.nanmax(np.abs(off) / se))]
    return tuple(out)


def plane_departure(c, A):
    """rose_departure for the roses in the coordinate planes (PLANES): the largest departure of the normals' density
    from 1 + a_c:nn and of the mean f_n / f_0 from 1 + a_n:nn over the three planes' 3 x PLANE_BINS bins, and the
    largest in standard errors (of 36 bins of pure sampling noise, below 3.0 nine times in ten). Bins of fewer than
    PLANE_MIN_COUNT contacts are left out: their standard error is itself too uncertain for a z (a bin of two similar
    forces has a tiny one)."""
    out = [math.nan] * 4  # NaN: no bin has PLANE_MIN_COUNT contacts
    for plane in PLANES:
        psi, dens, fnm, se_d, se_f, cnt = plane_roses(c["n"], c["fn"], A["f0"], plane, errors=True)
        for k, (val, se, a) in enumerate(((dens, se_d, A["ac"]), (fnm, se_f, A["an"]))):
            off = np.where(cnt >= PLANE_MIN_COUNT, np.abs(val - 1 - plane_fit(a, psi, plane)), np.nan)
            with np.errstate(invalid="ignore", divide="ignore"):
                z = off / se
            if np.isfinite(z).any():
                out[2 * k] = float(np.nanmax([out[2 * k], np.nanmax(off)]))
                out[2 * k + 1] = float(np.nanmax([out[2 * k + 1], np.nanmax(z)]))
    return tuple(out)


def report_section(tests):
    """A study report's section: each test's contact network at its end (its last snapshot); tests are (name, run
    directory). Empty where none has a snapshot with contacts."""
    rows = []
    for name, run in tests:
        snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
        c = load(snaps[-1]) if snaps else None
        got = network(c) if c is not None else None
        if got is None:
            continue
        row, A, _ = got
        dn, zn, df, zf = rose_departure(c, A)
        pn, pzn, pf, pzf = plane_departure(c, A)
        planes = "-" if pn != pn else f"{pn:.3f} (z {pzn:.1f}), {pf:.3f} (z {pzf:.1f})"
        rows.append(f"| {name} | {row['contacts']} | {row['strong_frac']:.3f} | {beta_text(row)} | {dn:.3f} (z {zn:.1f}) | "
                    f"{df:.3f} (z {zf:.1f}) | {planes} |")
    if not rows:
        return []
    return ["## Contact network at the end of each test", "",
            "From each test's last snapshot (scripts/contacts.py): the contacts, the share carrying more than the mean "
            "normal force (the strong network), beta of the exponential tail P(f_n/<f_n>) ~ exp(-beta f_n/<f_n>) above "
            "the mean (Radjai et al. 1996) with its standard error, and how far the measured roses (azimuth-averaged, "
            f"{ROSE_BINS} bands of equal solid angle) depart at most from the second-order fits the anisotropies make: "
            "the density of contact normals 4 pi E(n) from 1 + a_c:nn, the mean normal force over f_0 from 1 + a_n:nn, "
            "each with z, the largest departure in units of its band's sampling standard error (sampling noise alone "
            "keeps the largest of the bands' |z| below 2.5 nine times in ten: above ~3 the fit misses a real part of "
            "the distribution). What they leave, the stress-force-fabric sum 2/5 (a_c + a_d + a_n + 3/2 a_t) cannot "
            "hold. The azimuth average is the whole rose of an axisymmetric test; the last column takes the same "
            f"departures over the roses in the x-z, y-z and x-y planes (the contacts within 15 degrees of each, "
            f"{PLANE_BINS} bins of 15 degrees, those of {PLANE_MIN_COUNT} contacts or more: pure noise keeps the largest "
            "of the 36 |z| below 3.0 nine times in ten; '-': no such bin), where a true triaxial test (b > 0) also "
            "orders its contacts between x and y. "
            "`grainlab plot` on a test's run draws the distribution and the roses (figures/contacts.png, "
            "contacts_planes.png).", "",
            "| test | contacts | strong share | beta | normals' rose off 1 + a_c:nn | f_n rose off 1 + a_n:nn | "
            "in the planes: normals', f_n rose |",
            "|---|---|---|---|---|---|---|", *rows, ""]
