#!/usr/bin/python3
"""The fines' mass scaling (numerics.fines_mass_radius) against its error: one wide-graded sample per seed, prepared
once with SPEC §1's masses, then sheared drained from the same sample file with the fines made heavier at each radius
asked (0: off, the reference). A dense granular run is chaotic (perf/SPEED_VS_ERROR.md): any change of the masses
gives another, equally valid trajectory, so the scaling's error is judged against the seeds' scatter, not one run.

Usage: perf/fines_scaling.py [--seeds 11,12,13,14] [--radii 0,0.15e-3,0.2e-3,0.3e-3] [--count 3000] [--strain 0.25]
                             [--rate 1] [--bin build/grainlab] [--out FILE.md] [--keep]
Prints (and writes to --out) a table: per radius, the step, the steps and wall time of the shear, and over the seeds
mean +- sd of phi'_max, the strain at the peak, q/p' and e over the last 5 % of strain, the largest inertial number;
and each quantity's mean difference from the reference against the reference's seed-to-seed sd.
"""
import argparse
import atexit
import csv
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# configs/grading-study.yaml's widest curves are Cu 2.5; this is the Cu 3 curve its notes give (0.2-1.8 mm, one
# interval straight on semi-log paper), prepared as configs/grading-base.yaml on a ramp and sheared as
# configs/grading-shear-base.yaml, at its E = 1 GPa: at SPEC's 100 MPa the drained shear at 100 kPa squeezes a fine
# past numerics.max_overlap near 20 % strain (seed 11, step 86 799).
PREP = """sample: {{count: {count}, seed: {seed}, density_scaling: 1000, initial_solid_fraction: 0.30,
         grading: {{diameter: [0.2e-3, 1.8e-3], passing: [0, 100]}}}}
material: {{E: 1e9}}
stages:
  - {{name: consolidate, type: isotropic, pressure: 100e3, mu: 0.5, max_steps: 400000, ufr_tolerance: 0.02,
     affine: true, pressure_ramp_steps: 20000}}
output: {{every: 1000, checkpoint_minutes: 0}}
"""
SHEAR = """sample: {{file: {sample}}}
material: {{E: 1e9}}
numerics: {{fines_mass_radius: {radius}}}
stages:
  - {{name: shear, type: triaxial, drainage: drained, mu: 0.5, axial_strain_rate: {rate}, max_axial_strain: {strain},
     damping: 0.2, servo_integral: 0.1, max_steps: 1e9}}
output: {{every: 500, snapshot_strain: 0, checkpoint_minutes: 0}}
"""


def run(binary, cfg, out, threads):
    t0 = time.monotonic()
    p = subprocess.run([binary, "run", cfg, "--out", out, "--quiet", "--threads", str(threads)],
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit(f"{cfg}: exit {p.returncode}: {p.stderr.strip()}")
    return wall


def shear_stats(series):
    rows = [r for r in csv.DictReader(open(series)) if r["stage"] == "shear"]
    eps = [float(r["eps_a"]) for r in rows]
    eta = [float(r["q"]) / float(r["p"]) for r in rows]
    k = max(range(len(eta)), key=lambda i: eta[i])
    end = eps[-1]
    last = [i for i in range(len(rows)) if eps[i] >= end - 0.05]
    phi = math.degrees(math.asin(3 * eta[k] / (6 + eta[k])))  # compression: sin phi = 3 eta / (6 + eta)
    return {
        "phi_max": phi,
        "eps_peak": 100 * eps[k],
        "qp_end": statistics.fmean(eta[i] for i in last),
        "e_end": statistics.fmean(float(rows[i]["e"]) for i in last),
        "inertial": max(float(r["inertial_number"]) for r in rows),
        "steps": int(rows[-1]["step"]) - int(rows[0]["step"]),
        "dt": float(rows[-1]["dt"]),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", default="11,12,13,14")
    ap.add_argument("--radii", default="0,0.15e-3,0.2e-3,0.3e-3")
    ap.add_argument("--count", type=int, default=3000)
    ap.add_argument("--strain", type=float, default=0.25)
    ap.add_argument("--rate", type=float, default=1.0, help="the shear's axial_strain_rate (1/s)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "grainlab"))
    ap.add_argument("--out", default="")
    ap.add_argument("--keep", action="store_true", help="keep the runs (their folder is printed)")
    a = ap.parse_args()
    seeds = [int(s) for s in a.seeds.split(",")]
    radii = [float(r) for r in a.radii.split(",")]
    if radii[0] != 0:
        radii.insert(0, 0.0)
    work = tempfile.mkdtemp(prefix="fines_scaling.")
    if a.keep:
        print(f"runs in {work}")
    else:
        atexit.register(shutil.rmtree, work, True)
    res = {r: [] for r in radii}
    walls = {r: [] for r in radii}
    for s in seeds:
        prep = os.path.join(work, f"prep{s}.yaml")
        open(prep, "w").write(PREP.format(count=a.count, seed=s))
        run(a.bin, prep, os.path.join(work, f"prep{s}"), a.threads)
        sample = os.path.join(work, f"prep{s}", "sample_consolidate.h5")
        for r in radii:
            cfg = os.path.join(work, f"shear{s}_{r:g}.yaml")
            open(cfg, "w").write(SHEAR.format(sample=sample, radius=r, strain=a.strain, rate=a.rate))
            out = os.path.join(work, f"shear{s}_{r:g}")
            walls[r].append(run(a.bin, cfg, out, a.threads))
            st = shear_stats(os.path.join(out, "series.csv"))
            res[r].append(st)
            print(f"seed {s}, fines_mass_radius {r:g}: {walls[r][-1]:.1f} s, " +
                  ", ".join(f"{k} {v:.4g}" for k, v in st.items()), flush=True)
    cpu = ""
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    keys = [("phi_max", "phi'_max (deg)", 2), ("eps_peak", "eps_a at the peak (%)", 2),
            ("qp_end", "q/p' last 5 %", 3), ("e_end", "e last 5 %", 4), ("inertial", "max inertial number", 5)]

    def ms(v, d):
        return f"{statistics.fmean(v):.{d}f} ± {statistics.stdev(v):.{d}f}" if len(v) > 1 else f"{v[0]:.{d}f}"

    lines = [f"Generated by `perf/fines_scaling.py --seeds {a.seeds} --radii {a.radii} --count {a.count} --strain "
             f"{a.strain} --rate {a.rate:g}` ({a.threads} OpenMP threads, {cpu}, {os.cpu_count()} cores).",
             "",
             f"Cu 3 curve (0.2-1.8 mm), {a.count} spheres, E = 1 GPa, prepared at 100 kPa with SPEC §1's masses, then sheared "
             f"drained at {a.rate:g}/s to {100 * a.strain:g} % from the same sample file per seed; mean ± sd over seeds "
             f"{a.seeds}; wall: median over the seeds of the shear's `grainlab run`.",
             "",
             "| fines_mass_radius (mm) | dt (s) | shear steps | wall s | speed-up | " +
             " | ".join(k[1] for k in keys) + " |",
             "|---" * (5 + len(keys)) + "|"]
    ref_wall = statistics.median(walls[0.0])
    for r in radii:
        v = res[r]
        w = statistics.median(walls[r])
        lines.append(f"| {r * 1e3:g}{' (off)' if r == 0 else ''} | {v[0]['dt']:.3g} | {v[0]['steps']} | {w:.1f} | "
                     f"{ref_wall / w:.2f}x | " + " | ".join(ms([x[k] for x in v], d) for k, _, d in keys) + " |")
    lines += ["", "Each quantity's mean over the seeds less the reference's, against the reference's seed-to-seed sd "
              "(the paired difference per seed in brackets: the same sample, sheared with and without the scaling):", "",
              "| fines_mass_radius (mm) | " + " | ".join(k[1] for k in keys[:4]) + " |", "|---" * 5 + "|"]
    for r in radii[1:]:
        cells = []
        for k, _, d in keys[:4]:
            ref = [x[k] for x in res[0.0]]
            got = [x[k] for x in res[r]]
            diff = statistics.fmean(got) - statistics.fmean(ref)
            sd = statistics.stdev(ref) if len(ref) > 1 else float("nan")
            paired = [g - f for g, f in zip(got, ref)]
            cells.append(f"{diff:+.{d}f} (sd {sd:.{d}f}; per seed " + ", ".join(f"{p:+.{d}f}" for p in paired) + ")")
        lines.append(f"| {r * 1e3:g} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    print()
    print(text)
    if a.out:
        open(a.out, "w").write(text)


if __name__ == "__main__":
    main()
