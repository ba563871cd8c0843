#!/usr/bin/python3
"""Speed against error (issue 5): one command writes perf/SPEED_VS_ERROR.md and perf/speed_vs_error.png.

    perf/speed_vs_error            (the wrapper: builds nothing, needs `make build` first)

For dt safety factor f in {0.05, 0.1, 0.2, 0.3, 0.5}, skin in {0.05, 0.1, 0.2} mm (double) and float storage of
the per-pair history and forces (CMake GRAINLAB_PAIR_FLOAT, skin 0.1 mm; configured and built in BUILD_FLOAT
incrementally by perf/build_float.sh):
  1. undrained triaxial test on a small sample (800 spheres, mu_r = 0.1, p'_0 = 190 kPa) to 5 % axial
     strain with `grainlab run`: error = max |q - q_ref| / p'_0 over the strain range, against a run at
     f = 0.02 (skin 0.1 mm), q_ref interpolated at the same axial strains; rate = particle-steps/s of
     the shear stage (whole process wall time, sample loading included);
  2. energy drift over 1e4 steps of a frictionless undamped packing (perf/energy_drift: a corner of the
     race scene, E = 100 MPa): |<E> last tenth - <E> first tenth| / E_0, and the rate of step() alone.
The sample is prepared once (consolidation at f = 0.2) and shared by every shear.
Rates are medians of REPS rounds over all cases (default 3); the errors must repeat bitwise in every round.
Environment: REPS, BUILD (default build), BUILD_FLOAT (default build-float), OMP_NUM_THREADS (default 2), SVE_OUT (work dir,
default /tmp/grainlab-sve), SVE_REPORT_DIR (where the report goes, default perf/).
"""
import csv
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from atomic_write import write_atomically, write_text_atomically  # noqa: E402

BUILD = os.environ.get("BUILD", os.path.join(ROOT, "build"))
BUILD_FLOAT = os.environ.get("BUILD_FLOAT", os.path.join(ROOT, "build-float"))
GRAINLAB = os.path.join(BUILD, "grainlab")
DRIFT = os.path.join(BUILD, "perf", "energy_drift")
WORK = os.environ.get("SVE_OUT", "/tmp/grainlab-sve")
REPORT = os.environ.get("SVE_REPORT_DIR", os.path.join(ROOT, "perf"))  # where SPEED_VS_ERROR.md and the PNG go
PEERS = os.environ.get("PEERS_DIR", os.path.join(ROOT, "..", "shared", "bench", "peers"))
FACTORS = [0.05, 0.1, 0.2, 0.3, 0.5]
SKINS = [0.05e-3, 0.1e-3, 0.2e-3]
F_REF = 0.02
REPS_TEXT = os.environ.get("REPS", "3")
REPS = int(REPS_TEXT) if REPS_TEXT.strip().isdigit() else 0  # not a whole number: refused in main()
ENV = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "2"), OMP_PROC_BIND="spread",
           OMP_PLACES="threads")

SAMPLE = """sample:
  count: 800
  seed: 11
  density_scaling: 1000
material:
  E: 100e6
  mu: 0.5
  mu_r: 0.1
numerics:
  dt_factor: 0.2
stages:
  - name: consolidate
    type: isotropic
    pressure: 190e3
    mu: 0.3
    mu_r: 0.1
    max_steps: 300000
output:
  every: 5000
  checkpoint_every: 0
  checkpoint_minutes: 0
  snapshot_strain: 0
"""

SHEAR = """sample:
  file: {sample}
material:
  E: 100e6
  mu: 0.5
  mu_r: 0.1
numerics:
  dt_factor: {f}
  skin: {skin}
stages:
  - name: shear
    type: triaxial
    drainage: undrained
    mu: 0.5
    mu_r: 0.1
    damping: 0.2
    axial_strain_rate: 0.3
    max_axial_strain: 0.05
    max_steps: 10000000
output:
  every: {every}
  checkpoint_every: 0
  checkpoint_minutes: 0
  snapshot_strain: 0
"""


def run(cmd, **kw):
    r = subprocess.run(cmd, env=ENV, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"speed_vs_error: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}")
    return r


def series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    eps = np.array([float(r["eps_a"]) for r in rows])
    q = np.array([float(r["q"]) for r in rows])
    p = np.array([float(r["p"]) for r in rows])
    step = np.array([float(r["step"]) for r in rows])
    return eps, q, p, step


def exes(precision):
    b = BUILD if precision == "double" else BUILD_FLOAT
    return os.path.join(b, "grainlab"), os.path.join(b, "perf", "energy_drift")


def build_float():
    """The float-storage build next to the default one (same Kokkos, same flags, one option more); an
    incremental build, so it is never stale."""
    print("building the float-storage variant in", BUILD_FLOAT, flush=True)
    run([os.path.join(ROOT, "perf", "build_float.sh"), "grainlab", "energy_drift"])


def shear(sample, f, skin, n, precision="double"):
    tag = f"f{f}_s{skin * 1e3:g}_{precision}"
    d = os.path.join(WORK, tag)
    cfg = os.path.join(WORK, tag + ".yaml")
    # ~200 rows per test whatever f is: every = steps / 200 with steps ~ 55 000 x 0.2 / f
    every = max(20, int(55000 * 0.2 / f / 200))
    with open(cfg, "w") as fh:
        fh.write(SHEAR.format(sample=sample, f=f, skin=skin, every=every))
    subprocess.run(["rm", "-rf", d])
    t0 = time.monotonic()
    run([exes(precision)[0], "run", cfg, "--out", d, "--quiet"])
    wall = time.monotonic() - t0
    eps, q, p, step = series(os.path.join(d, "series.csv"))
    steps = step[-1] - step[0]
    return dict(eps=eps, q=q, p=p, rate=n * steps / wall, wall=wall, steps=steps, inner_skin=inner_skin(d))


def inner_skin(run_dir):
    """The inner-list fraction the run used, from the effective config grainlab writes into its run directory
    (the report states the run's own setting, not a remembered default)."""
    with open(os.path.join(run_dir, "config.yaml")) as fh:
        m = re.search(r"^\s*inner_skin:\s*([0-9.eE+-]+)\s*$", fh.read(), re.M)
    if not m:
        sys.exit(f"speed_vs_error: no numerics.inner_skin in {run_dir}/config.yaml")
    return float(m.group(1))


def drift(f, skin, precision="double"):
    r = run([exes(precision)[1], "--scene", os.path.join(PEERS, "scene_32k.txt"), "--box", os.path.join(PEERS, "scene_32k_box.txt"),
             "--crop", "0.5", "--dt-factor", str(f), "--skin", str(skin), "--steps", "10000"])
    m = dict(re.findall(r"(\w+)=([0-9.eE+-]+)", r.stdout))
    # Cost of simulated time: wall seconds per simulated millisecond of this packing (particles / rate / dt).
    cost = float(m["particles"]) / float(m["particle_steps_per_s"]) / float(m["dt"]) * 1e-3
    return float(m["drift"]), float(m["band"]), float(m["particle_steps_per_s"]), cost


def main():
    for exe in (GRAINLAB, DRIFT):
        if not os.access(exe, os.X_OK):
            sys.exit(f"speed_vs_error: {exe} missing: run `make build` first")
    if not os.path.exists(os.path.join(PEERS, "scene_32k.txt")):
        sys.exit(f"speed_vs_error: no race scene under {PEERS} (set PEERS_DIR)")
    if REPS < 1:
        sys.exit(f"speed_vs_error: REPS={REPS_TEXT!r} is outside the allowed range (a whole number >= 1)")
    os.makedirs(WORK, exist_ok=True)
    build_float()
    prep = os.path.join(WORK, "prep")
    sample = os.path.join(prep, "sample_consolidate.h5")
    if not os.path.exists(sample):
        with open(os.path.join(WORK, "prep.yaml"), "w") as fh:
            fh.write(SAMPLE)
        print("preparing the sample (800 spheres, 190 kPa)", flush=True)
        run([GRAINLAB, "run", os.path.join(WORK, "prep.yaml"), "--out", prep, "--quiet"])
    n = 800
    print(f"reference: f = {F_REF}, skin 0.1 mm", flush=True)
    ref = shear(sample, F_REF, 0.1e-3, n)
    write_report(measure(sample, n, ref, REPS), ref, ref["p"][0])


# What each round times, per case: the shear's rate and wall time, step()'s rate and its cost per simulated ms.
TIMED = ("q_rate", "q_wall", "d_rate", "d_cost")


def measure(sample, n, ref, reps):
    """Every case (skin, f, precision) `reps` rounds over: one row per case with its errors against `ref` (round 1's,
    which every later round must reproduce bit for bit) and the median and min-max of each TIMED rate."""
    p0 = ref["p"][0]
    cases = [(skin, f, "double") for skin in SKINS for f in FACTORS] + [(0.1e-3, f, "float") for f in FACTORS]
    # reps rounds over all cases (not reps runs of one case in a row), so a slow hour of the shared host slows
    # every case alike; the rates are medians over the rounds. The errors are deterministic: every round must
    # reproduce round 1's q series and drift to the last bit, or the report is not written.
    first, timed = {}, {case: {k: [] for k in TIMED} for case in cases}
    for rnd in range(reps):
        for case in cases:
            skin, f, prec = case
            s = shear(sample, f, skin, n, prec)
            d, band, drate, dcost = drift(f, skin, prec)
            for k, v in zip(TIMED, (s["rate"], s["wall"], drate, dcost)):
                timed[case][k].append(v)
            if rnd == 0:
                first[case] = (s, d, band)
            elif not (np.array_equal(s["q"], first[case][0]["q"]) and d == first[case][1]):
                sys.exit(f"speed_vs_error: round {rnd + 1} of f={f} skin={skin} {prec} differs from round 1:"
                         " same config, backend and thread count must give the same bits")
            print(f"round {rnd + 1}/{reps} f={f:<5} skin={skin * 1e3:.2f} mm {prec:6s} shear {s['rate']:.3g} p-steps/s"
                  f"  step() {drate:.3g} p-steps/s", flush=True)
    rows = []
    for case in cases:
        skin, f, prec = case
        s, d, band = first[case]
        lo, hi = max(s["eps"][0], ref["eps"][0]), min(s["eps"][-1], ref["eps"][-1])
        keep = (s["eps"] >= lo) & (s["eps"] <= hi)
        dq = np.abs(s["q"][keep] - np.interp(s["eps"][keep], ref["eps"], ref["q"])) / p0
        err = float(np.max(dq))
        early = s["eps"][keep] - s["eps"][0] <= 0.01
        err1 = float(np.max(dq[early])) if early.any() else float("nan")
        t = timed[case]
        rows.append(dict(f=f, skin=skin, prec=prec, q_err=err, q_err1=err1, steps=s["steps"], drift=d, band=band,
                         q_span=(min(t["q_rate"]), max(t["q_rate"])), d_span=(min(t["d_rate"]), max(t["d_rate"])),
                         **{k: float(np.median(v)) for k, v in t.items()}))
        print(f"f={f:<5} skin={skin * 1e3:.2f} mm {prec:6s} q error {err:.2e} p'0 (first 1 %: {err1:.2e})  shear {rows[-1]['q_rate']:.3g} p-steps/s"
              f"  drift {d:.2e}  band {band:.2e}  step() {rows[-1]['d_rate']:.3g} p-steps/s (medians of {reps})", flush=True)
    return rows


def write_report(rows, ref, p0):
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    cpu = ""
    try:
        cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")][0]
    except (OSError, IndexError):
        pass
    lines = [
        "# Speed against error",
        "",
        f"Generated by `perf/speed_vs_error` (commit {commit}, {ENV['OMP_NUM_THREADS']} OpenMP threads, {cpu},"
        f" {os.cpu_count()} cores). Rates: medians of {REPS} rounds over all cases (min-max beside them; single runs on"
        " this shared VM swing by up to 2x). The errors are deterministic: every round reproduced them to the last bit.",
        "",
        f"- **q error**: undrained triaxial test, 800 spheres, mu = 0.5, mu_r = 0.1, p'_0 = {p0 / 1e3:.1f} kPa,"
        f" to 5 % axial strain: max |q - q_ref| / p'_0 against f = {F_REF} (skin 0.1 mm,"
        f" {int(ref['steps'])} steps, peak q = {ref['q'].max() / 1e3:.1f} kPa). Rate: the shear's"
        " particle-steps/s (the whole `grainlab run` process: output and analysis rows included).",
        "- **energy drift**: frictionless, undamped packing (3 650 spheres of the race scene's corner, E = 100 MPa,"
        " random 0.01 m/s velocities) over 10^4 steps: |<E> of the last tenth - <E> of the first tenth| / E_0;"
        " band = (max - min) / E_0. Rate: step() alone, fenced.",
        "- **precision**: double, or float storage of the per-pair history and per-pair forces with every"
        " operation in double (`-DGRAINLAB_PAIR_FLOAT=ON`, kernels/types.hpp), skin 0.1 mm. The reference is"
        " always double.",
        f"- **lists**: every run uses the engine's default inner list (`numerics.inner_skin` = {ref['inner_skin']:g} of the skin,"
        " perf/NOTES.md attempts 18 and 29): it changes no error (the same bits with it off), only the rate.",
        "",
        "Speed is given twice: as a rate (particle-steps/s, the same work per step whatever f is) and as the cost"
        " of the answer (wall seconds for the 5 % test; wall seconds per simulated millisecond of the packing),"
        " which is what f buys: a step costs the same, a larger f needs fewer of them.",
        "",
        "| f | skin mm | precision | q error / p'_0, 5 % | q error / p'_0, 1 % | steps | shear wall s | shear rate (p-steps/s), min-max | energy drift | energy band | wall s per simulated ms | step rate (p-steps/s), min-max |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        mark = " **(default)**" if (r["f"] == 0.2 and abs(r["skin"] - 0.1e-3) < 1e-9 and r["prec"] == "double") else ""
        lines.append(f"| {r['f']}{mark} | {r['skin'] * 1e3:g} | {r['prec']} | {r['q_err']:.2e} | {r['q_err1']:.2e} | {int(r['steps'])} |"
                     f" {r['q_wall']:.1f} | {r['q_rate']:.3g}, {r['q_span'][0]:.3g}-{r['q_span'][1]:.3g} | {r['drift']:.2e} | {r['band']:.2e} |"
                     f" {r['d_cost']:.3g} | {r['d_rate']:.3g}, {r['d_span'][0]:.3g}-{r['d_span'][1]:.3g} |")
    lines += ["", "![speed against error](speed_vs_error.png)", ""]
    default = [r for r in rows if r["f"] == 0.2 and abs(r["skin"] - 0.1e-3) < 1e-9 and r["prec"] == "double"][0]
    fl = {r["f"]: r for r in rows if r["prec"] == "float"}
    db = {r["f"]: r for r in rows if r["prec"] == "double" and abs(r["skin"] - 0.1e-3) < 1e-9}
    lines += [
        "## Reading the table",
        "",
        "- The energy drift is the discretisation error: it grows roughly as f^2 (leapfrog) and is the clean"
        " speed-against-accuracy curve. The skin changes no error at all: every error column is bitwise the same"
        " for the three skins, because the list holds every touching pair for any skin and rows are sorted, so"
        " a rebuild never changes the dynamics (tests/test_determinism checks this); the skin only moves the rate.",
        "- The q error over 5 % strain is not: a dense granular assembly is chaotic (a perturbation of one"
        " rounding in one contact grows until the contact network differs), so any change of dt gives a"
        " different, equally valid trajectory after a fraction of a percent of strain, and the 5 % column measures that sample-level scatter (flat in f), not the truncation error. The"
        " 1 % column is closer to the deterministic regime. Statistical answers (peak and critical-state q/p',"
        " fabric) must be judged across seeds, not against one reference trajectory.",
        "",
        "- Float storage against double at the same f and skin, energy drift:"
        + ",".join(f" {fl[f]['drift']:.1e} vs {db[f]['drift']:.1e} (f = {f})" for f in FACTORS if f in fl)
        + ". Rounding the stored history and pair forces to 24 bits each step adds a random walk to the"
        " energy that stays below the truncation error at the default f (and at f = 0.05, 0.1); compare"
        " f = 0.3 and 0.5 across rows. The rates in this table are short runs on a shared VM; the concurrent A/B of the two builds on the race scene (`perf/ab.sh`) gives float 1.05x faster"
        " at 32k spheres and 1.12x at 256k, where the step streams from memory, and 23 % less memory per particle"
        " (perf/NOTES.md attempt 8 and session 13). The q columns are again chaotic scatter"
        " (the float rows' 1 % errors are the double rows' size). Default: double (bitwise-reproducible"
        " restarts and the tested oracles are double); float halves the per-pair memory, which matters most for 10^7-sphere runs in a GPU's memory (not measured here: no GPU).",
        "",
        "## The default and why",
        "",
        f"f = 0.2 with a 0.1 mm skin: energy drift {default['drift']:.1e} over 10^4 steps"
        f" ({max(r['drift'] for r in rows if r['f'] == 0.5) / max(default['drift'], 1e-300):.0f}x below f = 0.5),"
        " q within the chaotic scatter of the smaller f, at a cost per simulated second"
        f" {db[0.05]['d_cost'] / default['d_cost']:.1f}x below f = 0.05 (measured; 4x by the step count alone). f = 0.5 gives up that factor in energy accuracy and sits near the stability edge of"
        " the rolling spring; below 0.2 the gain in accuracy is invisible in q. The 0.1 mm skin"
        " (~0.35 of the mean radius) sets how often the Verlet list is rebuilt by a cell search; the force kernel"
        " streams the inner list filtered from it, so the skin no longer sets how many non-touching pairs the"
        " kernel visits.",
        "",
    ]
    write_text_atomically(os.path.join(REPORT, "SPEED_VS_ERROR.md"), "\n".join(lines))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
        for skin, prec in [(s_, "double") for s_ in SKINS] + [(0.1e-3, "float")]:
            rs = [r for r in rows if r["skin"] == skin and r["prec"] == prec]
            ax[0].loglog([r["q_wall"] for r in rs], [max(r["q_err1"], 1e-16) for r in rs], "o-",
                         label=f"skin {skin * 1e3:g} mm, {prec}")
            ax[1].loglog([r["d_cost"] for r in rs], [max(r["drift"], 1e-16) for r in rs], "o-",
                         label=f"skin {skin * 1e3:g} mm, {prec}")
            for r in rs:
                ax[0].annotate(f"f={r['f']}", (r["q_wall"], max(r["q_err1"], 1e-16)), fontsize=7)
                ax[1].annotate(f"f={r['f']}", (r["d_cost"], max(r["drift"], 1e-16)), fontsize=7)
        ax[0].set_xlabel("undrained shear to 5 %: wall s (median)")
        ax[0].set_ylabel("max |q - q_ref| / p'_0, first 1 % of strain")
        ax[1].set_xlabel("step(): wall s per simulated ms (median)")
        ax[1].set_ylabel("relative energy drift, 1e4 steps")
        for a in ax:
            a.legend()
            a.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        write_atomically(os.path.join(REPORT, "speed_vs_error.png"),
                         lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    except ImportError:
        print("matplotlib missing: no PNG")
    print("wrote", os.path.join(REPORT, "SPEED_VS_ERROR.md"))


if __name__ == "__main__":
    main()
