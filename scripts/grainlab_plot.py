#!/usr/bin/env python3
"""Figures and critical-state fits for grainlab runs (called by `grainlab plot` and `grainlab csl`).

  grainlab_plot.py plot RUN_DIR [RUN_DIR ...] [--out DIR]
  grainlab_plot.py csl  RUN_DIR [RUN_DIR ...] [--out DIR] [--window 0.05]

Reads each run's series.csv (and its last snapshot for the force-chain picture); writes PNG and PDF.
Several runs are overlaid with a legend (e.g. the mu_r study).
"""
import argparse
import csv
import glob
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(run):
    path = os.path.join(run, "series.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"grainlab plot: {path}: no rows")
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0] if k != "stage"}
    cols["stage"] = np.array([r["stage"] for r in rows])
    cols["shear"] = cols["stage_type"] > 0  # triaxial rows (0 isotropic, 1 undrained, 2 drained)
    return cols


def label(run, s):
    mur = s["mu_r"][s["shear"]][-1] if s["shear"].any() else s["mu_r"][-1]
    return f"{os.path.basename(os.path.normpath(run))} (mu_r={mur:g})"


def save(fig, out, name):
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out, f"{name}.{ext}"), dpi=130, bbox_inches="tight")
    plt.close(fig)
    print(os.path.join(out, name + ".png"))


def fig_stress(runs, out):
    fig, ax = plt.subplots(2, 2, figsize=(10, 8))
    for run, s in runs:
        m = s["shear"]
        lab = label(run, s)
        ax[0, 0].plot(100 * s["eps_a"][m], s["q"][m] / 1e3, label=lab)
        ax[0, 1].plot(s["p"][m] / 1e3, s["q"][m] / 1e3, label=lab)
        ax[1, 0].plot(100 * s["eps_a"][m], s["u"][m] / 1e3, label=lab)
        ax[1, 1].plot(s["p"] / 1e3, s["e"], label=lab)
    ax[0, 0].set(xlabel="axial strain eps_a [%]", ylabel="q [kPa]", title="deviator stress")
    ax[0, 1].set(xlabel="p' [kPa]", ylabel="q [kPa]", title="stress path")
    ax[1, 0].set(xlabel="axial strain eps_a [%]", ylabel="u [kPa]", title="excess pore pressure (undrained)")
    ax[1, 1].set(xlabel="p' [kPa]", ylabel="void ratio e", title="e - p' (consolidation and shear)")
    for a in ax.flat:
        a.grid(alpha=0.3)
    ax[0, 0].legend(fontsize=8)
    save(fig, out, "stress")


def fig_anisotropy(runs, out):
    fig, ax = plt.subplots(1, 4, figsize=(16, 4), sharey=False)
    for k, key in enumerate(["a_c", "a_d", "a_n", "a_t"]):
        for run, s in runs:
            m = s["shear"]
            e = 100 * s["eps_a"][m]
            (ln,) = ax[k].plot(e, s[key][m], label=label(run, s) + " total")
            ax[k].plot(e, s[key + "_strong"][m], "--", color=ln.get_color(), label="strong")
            ax[k].plot(e, s[key + "_weak"][m], ":", color=ln.get_color(), label="weak")
        ax[k].set(xlabel="eps_a [%]", title=key)
        ax[k].grid(alpha=0.3)
    ax[0].legend(fontsize=7)
    save(fig, out, "anisotropy")


def fig_sff(runs, out):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for run, s in runs:
        m = s["shear"]
        e = 100 * s["eps_a"][m]
        (ln,) = ax[0].plot(e, s["q_p"][m], label=label(run, s) + ": q/p' (contacts)")
        ax[0].plot(e, s["sff"][m], "--", color=ln.get_color(), label="2/5 (a_c + a_d + a_n + 3/2 a_t)")
    ax[0].set(xlabel="eps_a [%]", ylabel="q/p'", title="stress-force-fabric")
    ax[0].legend(fontsize=7)
    run, s = runs[0]
    m = s["shear"]
    shares = [s["sff_share_" + k][m] for k in "cdnt"]
    ax[1].stackplot(100 * s["eps_a"][m], *shares, labels=["a_c", "a_d", "a_n", "3/2 a_t"], alpha=0.8)
    ax[1].set(xlabel="eps_a [%]", ylabel="share of the sum", title=f"term shares: {label(run, s)}")
    ax[1].legend(fontsize=8, loc="upper right")
    for a in ax:
        a.grid(alpha=0.3)
    save(fig, out, "sff")


def fig_fractions(runs, out):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for run, s in runs:
        m = s["shear"]
        e = 100 * s["eps_a"][m]
        (ln,) = ax[0].plot(e, s["weak_frac"][m], label=label(run, s))
        ax[1].plot(e, s["sliding_frac"][m], color=ln.get_color(), label=label(run, s) + " sliding")
        ax[1].plot(e, s["sliding_weak_frac"][m], "--", color=ln.get_color(), label="sliding within weak")
        ax[1].plot(e, s["rolling_sliding_frac"][m], ":", color=ln.get_color(), label="rolling-sliding")
    ax[0].set(xlabel="eps_a [%]", ylabel="N_weak / N_c", title="weak contacts")
    ax[1].set(xlabel="eps_a [%]", ylabel="fraction of contacts", title="sliding contacts")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    save(fig, out, "fractions")


def fig_forcechains(run, out):
    snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
    if not snaps:
        return
    import h5py

    with h5py.File(snaps[-1], "r") as f:
        x = f["particles/x"][:]
        i = f["contacts/i"][:]
        j = f["contacts/j"][:]
        fn = f["contacts/f_n"][:]
    if len(fn) == 0:
        return
    # A slab through the middle (normal y, 30 % of the width): contacts with both ends inside it, projected
    # on x-z; line width ~ f_n, strong (f_n > mean) dark, weak light.
    y0, y1 = x[:, 1].min(), x[:, 1].max()
    lo, hi = y0 + 0.35 * (y1 - y0), y0 + 0.65 * (y1 - y0)
    keep = (x[i, 1] > lo) & (x[i, 1] < hi) & (x[j, 1] > lo) & (x[j, 1] < hi)
    fbar = fn.mean()
    fig, ax = plt.subplots(figsize=(7, 7))
    for strong in (False, True):
        m = keep & ((fn > fbar) == strong)
        for a, b, f in zip(i[m], j[m], fn[m]):
            ax.plot([x[a, 0], x[b, 0]], [x[a, 2], x[b, 2]], color="black" if strong else "0.7",
                    lw=0.3 + 3.0 * f / fn.max(), solid_capstyle="round")
    ax.set(aspect="equal", xlabel="x [m]", ylabel="z [m]",
           title=f"force chains, {os.path.basename(snaps[-1])} (mid slab)")
    save(fig, out, "forcechains")
    print(f"ParaView: open {os.path.join(run, 'particles.xdmf')}")


def critical_state(s, window):
    """Final state of the shear stage, and whether it is critical: over the last `window` of axial strain,
    q/p', p' and e must each be steady: spread of q/p' < 0.05, of p'/p'_end < 5 %, of e < 0.005."""
    m = s["shear"]
    if not m.any():
        return None
    ea = s["eps_a"][m]
    w = ea >= ea[-1] - window
    if ea[-1] - ea[0] < window or w.sum() < 3:
        return dict(ok=False, why="shear shorter than the window")
    qp, p, e = s["q_p"][m][w], s["p"][m][w], s["e"][m][w]
    spread = dict(qp=np.ptp(qp), p=np.ptp(p) / max(p[-1], 1e-30), e=np.ptp(e))
    ok = spread["qp"] < 0.05 and spread["p"] < 0.05 and spread["e"] < 0.005
    return dict(ok=ok, why="" if ok else f"not steady: {spread}", p=p[-1], e=e[-1], a_c=s["a_c"][m][-1],
                mu_r=s["mu_r"][m][-1], qp=qp[-1])


def fit(x, y):
    """Least-squares line with standard errors (needs >= 3 points)."""
    A = np.vstack([x, np.ones_like(x)]).T
    coef, res, *_ = np.linalg.lstsq(A, y, rcond=None)
    n = len(x)
    s2 = float(np.sum((y - A @ coef) ** 2)) / (n - 2)
    cov = s2 * np.linalg.inv(A.T @ A)
    return coef[0], coef[1], math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])


def csl(runs, out, window):
    states = []
    for run, s in runs:
        cs = critical_state(s, window)
        if cs is None:
            print(f"{run}: no shear stage")
        elif not cs["ok"]:
            print(f"{run}: not at critical state ({cs['why']}); not fitted")
        else:
            states.append((run, cs))
    groups = {}
    for run, cs in states:
        groups.setdefault(cs["mu_r"], []).append(cs)
    lines = ["| mu_r | n | e_c = a + b p' [p' in kPa] | a_c = c + d ln(p'/1 kPa) |", "|---|---|---|---|"]
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    results = {}
    for mur, g in sorted(groups.items()):
        p = np.array([c["p"] for c in g]) / 1e3
        e = np.array([c["e"] for c in g])
        ac = np.array([c["a_c"] for c in g])
        (ln,) = ax[0].plot(p, e, "o", label=f"mu_r = {mur:g}")
        ax[1].plot(np.log(p), ac, "o", color=ln.get_color(), label=f"mu_r = {mur:g}")
        if len(g) >= 3:
            b, a, sb, sa = fit(p, e)
            d, c, sd, sc = fit(np.log(p), ac)
            xs = np.linspace(p.min(), p.max(), 20)
            ax[0].plot(xs, a + b * xs, "-", color=ln.get_color())
            ax[1].plot(np.log(xs), c + d * np.log(xs), "-", color=ln.get_color())
            lines.append(f"| {mur:g} | {len(g)} | a = {a:.4f} ± {sa:.4f}, b = {b:.3e} ± {sb:.1e} | "
                         f"c = {c:.4f} ± {sc:.4f}, d = {d:.4f} ± {sd:.4f} |")
            results[mur] = dict(n=len(g), a=a, b=b, sa=sa, sb=sb, c=c, d=d, sc=sc, sd=sd)
        else:
            lines.append(f"| {mur:g} | {len(g)} | fewer than 3 critical states: no fit | |")
    ax[0].set(xlabel="p'_c [kPa]", ylabel="e_c", title="critical-state line e_c - p'")
    ax[1].set(xlabel="ln p'_c [kPa]", ylabel="a_c at critical state", title="a_c - ln p'")
    for a_ in ax:
        a_.grid(alpha=0.3)
        a_.legend(fontsize=8)
    save(fig, out, "csl")
    text = "\n".join(lines)
    print(text)
    with open(os.path.join(out, "csl.md"), "w") as f:
        f.write(text + "\n")
    return results


def main():
    ap = argparse.ArgumentParser(prog="grainlab")
    ap.add_argument("cmd", choices=["plot", "csl"])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--out", default=None, help="figure directory (default: the first run's figures/)")
    ap.add_argument("--window", type=float, default=0.05, help="csl: axial-strain window of the steadiness test")
    a = ap.parse_args()
    runs = []
    for r in a.runs:
        if not os.path.isfile(os.path.join(r, "series.csv")):
            sys.exit(f"grainlab {a.cmd}: {r}: no series.csv (not a run directory)")
        runs.append((r, load(r)))
    out = a.out or os.path.join(a.runs[0], "figures")
    os.makedirs(out, exist_ok=True)
    if a.cmd == "plot":
        fig_stress(runs, out)
        fig_anisotropy(runs, out)
        fig_sff(runs, out)
        fig_fractions(runs, out)
        fig_forcechains(a.runs[0], out)
    else:
        csl(runs, out, a.window)


if __name__ == "__main__":
    main()
