#!/usr/bin/env python3
"""Figures and critical-state fits for grainlab runs (called by `grainlab plot` and `grainlab csl`).

  grainlab_plot.py plot RUN_DIR [RUN_DIR ...] [--out DIR]
  grainlab_plot.py csl  RUN_DIR [RUN_DIR ...] [--out DIR] [--window 0.05]

Reads each run's series.csv (its last snapshot for the force-chain picture, its snapshots' contacts for the force
distribution and the anisotropy roses: scripts/contacts.py, and for the local strain between them:
scripts/localisation.py); writes PNG and PDF.
Several runs are overlaid with a legend (e.g. the mu_r study).
"""
import argparse
import csv
import ctypes
import importlib.util
import json
import glob
import math
import os
import signal
import sys
import threading
import time
import traceback

# The modules plot, csl and the study report need, checked before any is imported: an interpreter without one (a
# virtual environment, GRAINLAB_PYTHON set to another python) ended in an ImportError's traceback.
_NEEDED = (("numpy", "numpy"), ("matplotlib", "matplotlib"), ("h5py", "h5py"), ("scipy", "scipy"), ("yaml", "pyyaml"))
_missing = [pip for mod, pip in _NEEDED if importlib.util.find_spec(mod) is None]
if _missing:
    sys.exit(f"grainlab {sys.argv[1] if len(sys.argv) > 1 else ''}: {sys.executable} lacks {', '.join(_missing)}: "
             f"install them (pip install {' '.join(_missing)}; scripts/setup-deps.sh installs them for /usr/bin/python3) "
             "or set GRAINLAB_PYTHON to an interpreter that has them")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atomic_write import write_atomically, write_text_atomically  # noqa: E402
from contacts import fig_contacts, report_section as contacts_section  # noqa: E402
import dilatancy  # noqa: E402
from localisation import fig_localisation, report_section as localisation_section  # noqa: E402
import size_classes  # noqa: E402

# The quasi-static limit of the inertial number (GDR MiDi 2004, Eur. Phys. J. E 14: I < 1e-3), as
# kQuasiStaticInertial in src/simulation.hpp: above it the stress ratio of a steady flow rises with I (the mu(I)
# rheology, Jop, Forterre & Pouliquen 2006, Nature 441, eq. 2), so a critical state reached there is rate-dependent.
QUASI_STATIC_I = 1e-3
# A consolidated sample is graded when its core's void ratio exceeds its interior's by more than GRADED_CORE, told
# from samples of GRADED_MIN_COUNT spheres or more: kGradedCore and kGradedMinCount in src/simulation.hpp (measured there).
GRADED_CORE, GRADED_MIN_COUNT = 0.015, 5000
# The rate section's line in I is mu(I)'s first order, mu_s + (mu_2 - mu_s) I / I_0, with I_0 ~ 0.3 (Jop et al. 2006:
# 0.279 for glass beads): its second-order term is I / I_0 ~ 3 % of the first at I = 1e-2, past which the section
# says the line no longer holds.
LINEAR_I = 1e-2
# A cyclic loop measures the material when its quarter cycle lasts at least this many transits of a compression wave
# across the sample (kQuasiStaticTransits, src/simulation.hpp; measured in configs/README.md).
QUASI_STATIC_TRANSITS = 4
# The cycles a liquefaction-resistance curve is read at: the equivalent uniform cycles of a magnitude 7.5 earthquake
# (Seed et al. 1975; Idriss & Boulanger 2008, CRR_M7.5), the CRR that the field's charts and correlations give.
CRR_CYCLES = 15


def strain_across_stages(eps_a, stage, shear):
    """The axial strain of consecutive shear stages from the first one's start. Each stage's eps_a counts from its
    own start (its H0), so a staged test (a K0 consolidation then a shear, a loading then an unloading) drew its
    stages over one another in a run's strain figures, joined by lines back across them. Heights compose exactly:
    1 - eps = (1 - eps_before)(1 - eps_stage); an isotropic stage between shears starts the count again."""
    run = eps_a.copy()
    before = 0.0
    for k in range(len(eps_a)):
        if k and stage[k] != stage[k - 1]:
            before = run[k - 1] if shear[k - 1] and shear[k] else 0.0
        if shear[k] and before != 0.0:
            run[k] = 1 - (1 - before) * (1 - eps_a[k])
    return run


def cycles_across_stages(cycle, stage, cyclic):
    """The cycle number N counted over a run's cyclic stages: each stage's N counts from 0 at its start (its cycles and
    liquefaction criteria are its own), so a staged cyclic test (amplitudes in turn, stages of `cycles` each) drew its
    stages over one another against N, joined by lines back across the figure. Each cyclic stage goes on from the N
    the ones before it reached."""
    run = np.array(cycle, dtype=float)
    before = 0.0
    for k in range(1, len(run)):
        if stage[k] != stage[k - 1] and cyclic[k - 1]:
            before += cycle[k - 1]  # the stage's last row: the N it reached
        if cyclic[k]:
            run[k] = before + cycle[k]
    return run


def ru_reference(p, undrained):
    """r_u's reference p'_c per row: the effective mean stress at the first row of the undrained stages in a row that
    it belongs to (NaN elsewhere). An undrained stage right after an undrained one goes on with the pore pressure that
    stage left (Laboratory::start_stage: the drainage stays closed), so a post-cyclic shear's or a staged cyclic
    test's r_u = u/p'_c counts from where the undrained loading began, as the run's own criterion does."""
    ref = np.full(len(p), np.nan)
    for k in range(len(p)):
        if undrained[k]:
            ref[k] = ref[k - 1] if k and undrained[k - 1] else p[k]
    return ref


def load(run, prog="grainlab plot"):
    path = os.path.join(run, "series.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        # A run writes its series every 20 rows or a minute and at its checkpoints (output_flush_due): one stopped
        # (or looked at) before that has the header alone.
        sys.exit(f"{prog}: {path}: no rows yet: the run stopped, or is running, before writing its first rows "
                 f"(resume a stopped run: grainlab run {os.path.join(run, 'config.yaml')} --resume)")
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0] if k != "stage"}
    cols["stage"] = np.array([r["stage"] for r in rows])
    # 0 isotropic, 1 triaxial undrained, 2 triaxial drained, 3 cyclic undrained, 4 cyclic drained, 5 triaxial
    # oedometric, 6 cyclic oedometric
    cols["shear"] = cols["stage_type"] > 0  # every sheared row (the stress figures draw cyclic loops too)
    cols["monotonic"] = (cols["stage_type"] > 0) & (cols["stage_type"] < 3)  # critical states come from these
    cols["cyclic"] = ((cols["stage_type"] >= 3) & (cols["stage_type"] <= 4)) | (cols["stage_type"] == 6)
    cols["cyclic_oedometric"] = cols["stage_type"] == 6  # the cyclic oedometer: its own figure, no liquefaction
    cols["oedometric"] = cols["stage_type"] == 5  # K0 tests: no peak, no critical state
    cols["eps_a_run"] = strain_across_stages(cols["eps_a"], cols["stage"], cols["shear"])
    if "cycle" in cols:  # a series of a build before cyclic stages, or a synthetic one, has none (nor cyclic rows)
        cols["cycle_run"] = cycles_across_stages(cols["cycle"], cols["stage"], cols["cyclic"])
    cols["p_c"] = ru_reference(cols["p"], (cols["stage_type"] == 1) | (cols["stage_type"] == 3))
    # the walls' p and q less the local damping's drag (series p_drag, q_drag, Laboratory::drag_stress: both linear in
    # the wall stresses, so the difference is the walls' stress without the drag): STRESS_MEASURES_TEXT
    if "p_drag" in cols and "q_drag" in cols:
        cols["p_less_drag"], cols["q_less_drag"] = cols["p"] - cols["p_drag"], cols["q"] - cols["q_drag"]
    # a true-triaxial stage's b (summary.json; 0 where it has none, or for a run of a build before b): its friction
    # angles come from the principal stresses, not from M's axisymmetric relations (critical_state)
    # and the largest lateral servo error of its drained shear stages (summary.json servo_error; None: not given)
    # and its stress path (constant_p where a triaxial stage held p' = p'_0; constant_sigma3 otherwise and before it)
    # and its triaxial stages' axial strain rate (the largest; 0: not given, a build before it or no triaxial stage)
    cols["b"], cols["servo_error"], cols["stress_path"], cols["rate"] = 0.0, None, "constant_sigma3", 0.0
    try:
        with open(os.path.join(run, "summary.json")) as f:
            stages = json.load(f).get("stages", [])
        cols["b"] = max([float(st.get("b", 0)) for st in stages if st.get("type") == "triaxial"] or [0.0])
        cols["rate"] = max([float(st.get("axial_strain_rate", 0)) for st in stages if st.get("type") == "triaxial"]
                           or [0.0])
        if any(st.get("stress_path") == "constant_p" for st in stages if st.get("type") == "triaxial"):
            cols["stress_path"] = "constant_p"
        if any(st.get("stress_path") == "plane_strain" for st in stages if st.get("type") == "triaxial"):
            cols["stress_path"] = "plane_strain"
        errs = [float(st["servo_error"]) for st in stages if st.get("servo_error") is not None]
        cols["servo_error"] = max(errs) if errs else None
    except (OSError, ValueError, TypeError):
        pass
    # Plane strain (stress_path: plane_strain, the x walls held): b is the test's result, not its setting. Its b is the
    # mean measured over the second half of the shear, to 0.01 (its critical states one group), so that its angles come
    # from the principal stresses as a true-triaxial test's do and the axisymmetric sections (dilatancy, state
    # parameter) leave it out; the failure-criteria and flow sections place it in its sample's b series there.
    cols["plane_strain"] = cols["stress_path"] == "plane_strain"
    if cols["plane_strain"] and {"sigma_x", "sigma_y", "sigma_z"} <= set(cols):
        rows = np.flatnonzero(cols["monotonic"])
        if len(rows):
            cols["b"] = round(float(np.nanmean(principal_b(cols)[rows[len(rows) // 2:]])), 2)
    return cols


def run_name(run):
    """A run's name for a legend: its directory's, or for a study job's run directory, jobs/<job>/run, the job's."""
    name = os.path.basename(os.path.normpath(run))
    return os.path.basename(os.path.dirname(os.path.normpath(run))) if name == "run" else name


def label(run, s):
    mur = s["mu_r"][s["shear"]][-1] if s["shear"].any() else s["mu_r"][-1]
    return f"{run_name(run)} (mu_r={mur:g})"


# The files each figure is written as: the command's figure_formats (GRAINLAB_FIGURE_FORMATS, else PNG and PDF).
FIGURE_FORMATS = ("png", "pdf")
_KNOWN_FORMATS = ("png", "pdf", "svg")


def figure_formats(cmd):
    """The formats each figure is written in: GRAINLAB_FIGURE_FORMATS, a comma-separated list of png, pdf and svg in
    the order written (exits naming it otherwise), else PNG and PDF. Each format is a render of its own: a report of
    PNGs alone took 0.76-0.83 of the time (perf/report_time.sh DIR formats; perf/NOTES.md session 70)."""
    env = os.environ.get("GRAINLAB_FIGURE_FORMATS")
    if env is None or env.strip() == "":
        return ("png", "pdf")
    fmts = [f.strip().lower() for f in env.split(",")]
    if any(f not in _KNOWN_FORMATS for f in fmts) or len(set(fmts)) != len(fmts):
        sys.exit(f"grainlab {cmd}: error: GRAINLAB_FIGURE_FORMATS = '{env}': the figures' file formats, a "
                 f"comma-separated list of {', '.join(_KNOWN_FORMATS)}, each once (default png,pdf)")
    return tuple(fmts)


def _write_figure(fig, out, name):
    fig.tight_layout()  # keeps a row's axis labels off the titles of the row below
    # The tight box once for every file: bbox_inches="tight" draws the figure a second time in each savefig to find
    # it, a fifth of a report's time (study_tiny's report: 9.2 -> 7.2 s). Its padding is savefig's default.
    box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(plt.rcParams["savefig.pad_inches"])
    for ext in FIGURE_FORMATS:
        # format= because the temporary name does not end in .png / .pdf / .svg
        write_atomically(os.path.join(out, f"{name}.{ext}"),
                         lambda tmp, e=ext: fig.savefig(tmp, dpi=130, bbox_inches=box, format=e))


# Figures being written by forked children: (pid, read end of the pipe that brings back the child's error, path).
# Laying a figure out and rendering it (PNG and PDF) is most of a report's time and needs nothing of what follows,
# so each figure can be written by a child of its own while the parent goes on (perf/NOTES.md, sessions 63 and 69).
# The figures are the same files. FIGURE_JOBS children at most: the command's figure_jobs (GRAINLAB_FIGURE_JOBS, else
# 1). Its figures come in bursts (a section's several at its end), during which the parent mostly waits, so it is not
# counted. 1, the default: each figure written in turn by the command itself, as for a module that imports this one.
# Why in turn: a child writes its figure into memory it has not touched yet (the renderer's buffers; the parent's
# heap, copied on its first write), a page fault a page, where the parent writing in turn reuses what it has. On the
# 2-core VM of session 63 two children took the quick study's report from 5.7-6.5 s to 4.5-5.3 s; on the one of
# session 69, where a page fault costs 14-16 us (perf/fault_cost.sh), they took it from 6.93 to 8.02 s (medians of 5,
# perf/report_time.sh) with 2.3 times the faults.
_FIGURE_CHILDREN = []
FIGURE_JOBS = 1


def figure_jobs(cmd):
    """The figures the command writes at once: GRAINLAB_FIGURE_JOBS (a whole number >= 1; exits naming it otherwise),
    else 1 (in turn)."""
    env = os.environ.get("GRAINLAB_FIGURE_JOBS")
    if env is None or env == "":
        return 1
    try:
        n = int(env)
    except ValueError:
        n = 0
    if n < 1:
        sys.exit(f"grainlab {cmd}: error: GRAINLAB_FIGURE_JOBS = '{env}': the figures written at once, a whole "
                 "number >= 1 (1: each in turn)")
    return n if hasattr(os, "fork") else 1  # not POSIX: no forked writers


def _reap_figure():
    """Waits for the oldest figure child; raises its error in the parent (an OSError as it was raised: the one-line
    message naming the file; anything else as a RuntimeError carrying the child's traceback)."""
    pid, r, path = _FIGURE_CHILDREN.pop(0)
    with os.fdopen(r, "rb") as f:
        msg = f.read()  # to EOF: the child has exited (or closed it) by then; read before waitpid (a full pipe)
    _, status = os.waitpid(pid, 0)
    if msg:
        kind, *what = json.loads(msg)
        if kind == "os":
            raise OSError(*what)
        raise RuntimeError(f"the figure {path} failed:\n{what[0]}")
    if status != 0:
        raise RuntimeError(f"the figure {path} failed (its writer's wait status {status})")


def figures_done():
    """Waits for every figure child; raises the first error among them once all have ended (none left running to
    leave a temporary file behind the error)."""
    first = None
    while _FIGURE_CHILDREN:
        try:
            _reap_figure()
        except (OSError, RuntimeError) as e:
            first = first or e
    if first is not None:
        raise first


def write_report(out, lines):
    """out/report.md from its lines, once every figure is written: a figure that failed stops the report before it,
    as when they were written in turn."""
    figures_done()
    write_text_atomically(os.path.join(out, "report.md"), "\n".join(lines))


def _watch_parent(parent):
    """A daemon thread that sends this process a SIGTERM once its parent is no longer `parent` (polled every 0.2 s):
    the end of a killed command's child made certain. PR_SET_PDEATHSIG alone left the child running in about one
    full-suite run in five of cli_figure_children (session 67: the child reparented to PID 1, its SIGTERM handler
    installed, no signal pending: the kernel's signal never came; why was not found)."""
    def watch():
        while os.getppid() == parent:
            time.sleep(0.2)
        os.kill(os.getpid(), signal.SIGTERM)
    threading.Thread(target=watch, daemon=True).start()


def _die_with_parent():
    """A SIGTERM to this process when its parent ends (Linux's PR_SET_PDEATHSIG; nothing where there is none)."""
    # prctl is variadic and the kernel reads arguments 2-5 as unsigned longs: passed as ctypes' default C ints their
    # registers' upper halves are unspecified by the x86-64 calling convention (the kernel refuses a signal number
    # with bits above 64 set). Whole unsigned longs.
    ul = ctypes.c_ulong
    try:
        ctypes.CDLL(None, use_errno=True).prctl(ctypes.c_int(1), ul(int(signal.SIGTERM)), ul(0), ul(0), ul(0))
    except (AttributeError, OSError):
        pass


def save(fig, out, name):
    """Writes fig as out/name.png and .pdf (or FIGURE_FORMATS) atomically, in a forked child where FIGURE_JOBS > 1
    (figures_done waits for them), closes it and prints the first file's path."""
    path = os.path.join(out, f"{name}.{FIGURE_FORMATS[0]}")
    if FIGURE_JOBS < 2:
        _write_figure(fig, out, name)
    else:
        while len(_FIGURE_CHILDREN) >= FIGURE_JOBS:
            _reap_figure()
        # The child leaves by os._exit, which writes no buffer; anything it prints itself (a warning) then follows
        # the parent's lines instead of carrying them along.
        sys.stdout.flush()
        sys.stderr.flush()
        r, w = os.pipe()
        parent = os.getpid()
        pid = os.fork()
        if pid == 0:  # the child: write the figure, report an error through the pipe, exit without Python's cleanup
            code = 1
            try:
                os.close(r)
                # A SIGTERM ends the child through write_atomically's cleanup (no temporary file left), and the
                # child gets one when the report ends before it (killed, or stopped with its study): no figure is
                # written after the command has gone.
                signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
                _die_with_parent()
                if os.getppid() != parent:  # gone already, before the line above
                    sys.exit(143)
                _watch_parent(parent)
                _write_figure(fig, out, name)
                code = 0
            except BaseException as e:  # noqa: B902 - anything, reported to the parent
                msg = (["os", e.errno, e.strerror, e.filename] if isinstance(e, OSError)
                       else ["tb", traceback.format_exc()])
                os.write(w, json.dumps(msg).encode())  # a parent that has gone: EPIPE, and the exit below all the same
            finally:
                os._exit(code)  # never back into the parent's code, whatever was raised
        os.close(w)
        _FIGURE_CHILDREN.append((pid, r, path))
    plt.close(fig)
    print(path)


def finish(fig, ax, legend_ax, fontsize, out, name):
    """The close of a figure of line plots: a grid on every axes, the legend on one, saved (PNG and PDF)."""
    for a in np.ravel(ax):
        a.grid(alpha=0.3)
    legend(legend_ax, fontsize=fontsize)
    save(fig, out, name)


def fig_stress(runs, out):
    fig, ax = plt.subplots(2, 2, figsize=(10, 8))
    for run, s in runs:
        m = s["shear"]
        lab = label(run, s)
        ax[0, 0].plot(100 * s["eps_a_run"][m], s["q"][m] / 1e3, label=lab)
        ax[0, 1].plot(s["p"][m] / 1e3, s["q"][m] / 1e3, label=lab)
        ax[1, 0].plot(100 * s["eps_a_run"][m], s["u"][m] / 1e3, label=lab)
        ax[1, 1].plot(s["p"] / 1e3, s["e"], label=lab)
    ax[0, 0].set(xlabel="axial strain eps_a [%]", ylabel="q [kPa]", title="deviator stress")
    ax[0, 1].set(xlabel="p' [kPa]", ylabel="q [kPa]", title="stress path")
    ax[1, 0].set(xlabel="axial strain eps_a [%]", ylabel="u [kPa]", title="excess pore pressure (undrained)")
    ax[1, 1].set(xlabel="p' [kPa]", ylabel="void ratio e", title="e - p' (consolidation and shear)")
    finish(fig, ax, ax[0, 0], 8, out, "stress")


def fig_anisotropy(runs, out):
    fig, ax = plt.subplots(1, 4, figsize=(16, 4), sharey=False)
    for k, key in enumerate(["a_c", "a_d", "a_n", "a_t"]):
        for run, s in runs:
            m = s["shear"]
            e = 100 * s["eps_a_run"][m]
            (ln,) = ax[k].plot(e, s[key][m], label=label(run, s) + " total")
            ax[k].plot(e, s[key + "_strong"][m], "--", color=ln.get_color(), label="strong")
            ax[k].plot(e, s[key + "_weak"][m], ":", color=ln.get_color(), label="weak")
        ax[k].set(xlabel="eps_a [%]", title=key)
        ax[k].grid(alpha=0.3)
    legend(ax[0], fontsize=7)
    save(fig, out, "anisotropy")


def fig_sff(runs, out):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for run, s in runs:
        m = s["shear"]
        e = 100 * s["eps_a_run"][m]
        (ln,) = ax[0].plot(e, s["q_p"][m], label=label(run, s) + ": q/p' (contacts)")
        ax[0].plot(e, s["sff"][m], "--", color=ln.get_color(), label="2/5 (a_c + a_d + a_n + 3/2 a_t)")
        # The same ratio of the walls' stress and of the interior's (STRESS_MEASURES_TEXT), where the series has them
        for qcol, pcol, style, what in (("q", "p", ":", "walls"), ("q_less_drag", "p_less_drag", (0, (4, 1, 1, 1, 1, 1)),
                                                                   "walls less drag"),
                                        ("q_inner", "p_inner", "-.", "interior")):
            if qcol in s and pcol in s:
                with np.errstate(divide="ignore", invalid="ignore"):
                    ratio = np.abs(s[qcol][m] / s[pcol][m])
                if np.isfinite(ratio).any():
                    ax[0].plot(e, ratio, linestyle=style, color=ln.get_color(), lw=0.8, label=f"q/p' ({what})")
    ax[0].set(xlabel="eps_a [%]", ylabel="q/p'", title="stress-force-fabric; q/p' of contacts, walls, interior")
    legend(ax[0], fontsize=7)
    run, s = runs[0]
    m = s["shear"]
    # The shares divide by the sum, which starts near zero (isotropic state): there they spike to +-1e2 and
    # say nothing. Only the points where the sum is at least kMeaningful of its largest magnitude are drawn.
    kMeaningful = 0.1
    total = s["sff"][m]
    keep = np.abs(total) >= kMeaningful * np.max(np.abs(total)) if len(total) else np.zeros(0, bool)
    shares = [s["sff_share_" + k][m][keep] for k in "cdnt"]
    ax[1].stackplot(100 * s["eps_a_run"][m][keep], *shares, labels=["a_c", "a_d", "a_n", "3/2 a_t"], alpha=0.8)
    ax[1].set(xlabel="eps_a [%]", ylabel="share of the sum",
              title=f"term shares where |sum| >= {kMeaningful:g} max: {label(run, s)}")
    legend(ax[1], fontsize=8, loc="upper right")
    for a in ax:
        a.grid(alpha=0.3)
    save(fig, out, "sff")


def fig_fractions(runs, out):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for run, s in runs:
        m = s["shear"]
        e = 100 * s["eps_a_run"][m]
        (ln,) = ax[0].plot(e, s["weak_frac"][m], label=label(run, s))
        ax[1].plot(e, s["sliding_frac"][m], color=ln.get_color(), label=label(run, s) + " sliding")
        ax[1].plot(e, s["sliding_weak_frac"][m], "--", color=ln.get_color(), label="sliding within weak")
        ax[1].plot(e, s["rolling_sliding_frac"][m], ":", color=ln.get_color(), label="rolling-sliding")
    ax[0].set(xlabel="eps_a [%]", ylabel="N_weak / N_c", title="weak contacts")
    ax[1].set(xlabel="eps_a [%]", ylabel="fraction of contacts", title="sliding contacts")
    for a in ax:
        a.grid(alpha=0.3)
        legend(a, fontsize=7)
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
    from matplotlib.collections import LineCollection

    fig, ax = plt.subplots(figsize=(7, 7))
    for strong in (False, True):  # the strong network drawn over the weak
        m = keep & ((fn > fbar) == strong)
        # one collection, not a line each: a 32 000-sphere slab has ~10^4 contacts
        segs = np.stack([x[i[m]][:, [0, 2]], x[j[m]][:, [0, 2]]], axis=1)
        ax.add_collection(LineCollection(segs, colors="black" if strong else "0.7",
                                         linewidths=0.3 + 3.0 * fn[m] / fn.max(), capstyle="round"))
    ax.autoscale_view()
    ax.set(aspect="equal", xlabel="x [m]", ylabel="z [m]",
           title=f"force chains, {os.path.basename(snaps[-1])} (mid slab)")
    save(fig, out, "forcechains")
    print(f"ParaView: open {os.path.join(run, 'particles.xdmf')}")


def sieve_curve(r):
    """A sample's grading by mass: its distinct diameters d (sorted) and the percent of the solids' volume in spheres
    of diameter <= each, P. As the run's plan reads it (packing.cpp grading_indices)."""
    d = np.sort(2 * np.asarray(r, dtype=float))
    P = 100 * np.cumsum(d ** 3) / np.sum(d ** 3)
    last = np.append(d[1:] != d[:-1], True)  # one point per distinct diameter, with every sphere of it passing
    return d[last], P[last]


def sieve_diameter(d, P, percent):
    """D_x of a curve (d, P): the diameter it passes `percent` at, interpolated in ln d (below its first point: d[0])."""
    return float(np.exp(np.interp(percent, P, np.log(d))))


def grading_indices(d, P):
    """D10, D30, D50, D60, Cu = D60/D10 and Cc = D30^2/(D10 D60) of a curve (d, P)."""
    d10, d30, d50, d60 = (sieve_diameter(d, P, x) for x in (10, 30, 50, 60))
    return {"d10": d10, "d30": d30, "d50": d50, "d60": d60, "cu": d60 / d10, "cc": d30 * d30 / (d10 * d60)}


def asked_grading(run):
    """The sieve curve a run's config.yaml asked for (sample.grading: diameters in m, percent passing; of the run that
    made its sample.file, size_classes.grading_of), or None."""
    g = size_classes.grading_of(os.path.join(run, "config.yaml"))
    try:
        return (np.array(g["diameter"], dtype=float), np.array(g["passing"], dtype=float)) if g else None
    except (KeyError, TypeError, ValueError):
        return None


def fig_grading(runs, out):
    """figures/grading.png: each run's sample as a sieve curve (percent passing by mass against d on a log axis, from its
    first snapshot's radii) with its D50 and Cu, and where its config gives sample.grading, the asked curve (markers).
    Prints one line a run with the indices (and the largest miss at the asked sieves). Returns {run: indices}."""
    import h5py

    fig, ax = plt.subplots(figsize=(7, 4.5))
    found = {}
    for k, run in enumerate(runs):
        snaps = sorted(glob.glob(os.path.join(run, "snapshots", "snap_*.h5")))
        if not snaps:
            continue
        with h5py.File(snaps[0], "r") as f:
            r = f["particles/r"][:]
        d, P = sieve_curve(r)
        x = found[run] = grading_indices(d, P)
        name = run_name(run)
        color = f"C{k % 10}"
        ax.plot(np.concatenate(([d[0]], d)) * 1e3, np.concatenate(([0.0], P)), drawstyle="steps-post", color=color,
                label=f"{name}: {len(r)} spheres, D50 {x['d50'] * 1e3:.3g} mm, Cu {x['cu']:.2f}, Cc {x['cc']:.2f}")
        line = (f"grading: {name}: {len(r)} spheres, D50 = {x['d50'] * 1e3:.3g} mm, Cu = {x['cu']:.3g}, "
                f"Cc = {x['cc']:.3g} (by mass)")
        asked = asked_grading(run)
        if asked is not None:
            ds, ps = asked
            ax.plot(ds * 1e3, ps, "o--", color=color, mfc="none", label=f"{name}: sample.grading (asked)")
            got = np.array([P[d <= s][-1] if np.any(d <= s) else 0.0 for s in ds])
            miss = got - ps
            w = int(np.argmax(np.abs(miss)))
            line += f"; against sample.grading: {miss[w]:+.2f} points at {ds[w] * 1e3:.3g} mm (the largest miss)"
        print(line)
    if not found:
        plt.close(fig)
        return found
    ax.set(xscale="log", xlabel="diameter d [mm]", ylabel="percent passing by mass [%]", ylim=(0, 100),
           title="grading of the samples (first snapshot's spheres)")
    # plain numbers (0.6, 1) on the log axis: a sand's range is under a decade, where the default writes 6 x 10^-1;
    # over a wider one the minor ticks stay unlabelled (eight a decade would run into each other)
    lo, hi = ax.get_xlim()
    ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g") if hi / lo < 10
                                 else matplotlib.ticker.NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, out, "grading")
    return found


def oedometric_stages(s):
    """The oedometric stages of a run's series (stage_type 5: lateral walls held, zero lateral strain), in order: per
    stage its name, whether it loads (compression) or unloads (extension), and its rows' sigma_v = sigma_z and sigma_h =
    (sigma_x + sigma_y) / 2 of the walls, eps_a from the stage's start and e; with K0 = sigma_h / sigma_v at its end,
    OCR = the largest sigma_v of the run's rows up to there over sigma_v at its end (summary.json's), and, over the
    second half of its axial strain (past the turn from the isotropic or loaded state), the tangent
    K0 = d sigma_h / d sigma_v, the constrained modulus M = d sigma_v / d eps_a and the oedometer's index
    C = -de / d log10 sigma_v (least squares): the compression index Cc on loading, the swelling index Cs on
    unloading; "fabric": the last row's anisotropies a_c, a_d, a_n, a_t, contact q/p' and stress-force-fabric sum
    (those of the columns the series has)."""
    out = []
    m = s.get("oedometric")
    if m is None or not m.any():
        return out
    for name in dict.fromkeys(s["stage"][m]):  # in order of appearance
        r = m & (s["stage"] == name)
        sv, sh = s["sigma_z"][r], 0.5 * (s["sigma_x"][r] + s["sigma_y"][r])
        ea, e = s["eps_a"][r], s["e"][r]
        span = ea[-1] - ea[0]
        late = np.abs(ea - ea[0]) >= 0.5 * abs(span)
        # OCR as summary.json's: the largest sigma_v of the run's rows up to the stage's last over that row's
        end = int(np.nonzero(r)[0][-1])
        st = {"name": name, "loading": span > 0, "sv": sv, "sh": sh, "eps_a": ea, "e": e, "K0": sh[-1] / sv[-1],
              "OCR": float(np.nanmax(s["sigma_z"][:end + 1]) / sv[-1]) if sv[-1] > 0 else None, "K0_t": None, "M": None,
              "C": None, "fabric": {k: float(s[k][r][-1]) for k in ("a_c", "a_d", "a_n", "a_t", "q_p", "sff")
                                    if k in s}}
        if late.sum() >= 2 and np.ptp(sv[late]) > 0 and np.ptp(ea[late]) > 0:
            st["K0_t"] = float(np.polyfit(sv[late], sh[late], 1)[0])
            st["M"] = float(np.polyfit(ea[late], sv[late], 1)[0])
            if np.all(sv[late] > 0):
                st["C"] = -float(np.polyfit(np.log10(sv[late]), e[late], 1)[0])
        out.append(st)
    return out


def job_label(j, s, seed=False):
    """A study job's curve in the study figures: mu_r, drainage (and extension: the job's direction, not the sign of
    its last strain, which an unloading stage turns), then p'_0 and e_0 where the job sets them (0 in study.json: the
    base's, left out) and, with seed, the sample's seed."""
    m = s["shear"]
    ext = j["direction"] == "extension" if "direction" in j else bool(m.any() and s["eps_a"][m][-1] < 0)
    return (f"mu_r={j['mu_r']:g} {j['drainage']}" + (" extension" if ext else "")
            + (f" p0={j['p0'] / 1e3:g}k" if j.get("p0") else "") + (f" e0={j['e0']:g}" if j.get("e0") else "")
            + (f" seed {j['seed']}" if seed and j.get("seed") is not None else ""))


def fig_oedometric(runs, out):
    """Oedometric (K0) stages: the stress path sigma_h - sigma_v (with the lines K0 = 0.5 and 1 for reference),
    K0 = sigma_h / sigma_v against the axial strain, and the compression curve e - log sigma_v (whose slopes are the
    report's Cc and Cs); nothing where no run has such a stage."""
    drawn = [(run, s, oedometric_stages(s)) for run, s in runs]
    drawn = [d for d in drawn if d[2]]
    if not drawn:
        return
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.5))
    top = 0
    for run, s, stages in drawn:
        ln = None
        for st in stages:
            kw = {"color": ln.get_color()} if ln is not None else {"label": label(run, s)}
            style = "-" if st["loading"] else "--"
            (ln,) = ax[0].plot(st["sv"] / 1e3, st["sh"] / 1e3, style, **kw)
            ax[1].plot(100 * st["eps_a"], st["sh"] / st["sv"], style, color=ln.get_color())
            pos = st["sv"] > 0  # a log axis: a row of a stage that left its walls (sigma_v <= 0) is not drawn
            ax[2].plot(st["sv"][pos] / 1e3, st["e"][pos], style, color=ln.get_color())
            top = max(top, float(np.max(st["sv"])) / 1e3)
    for k0 in (0.5, 1.0):
        ax[0].plot([0, top], [0, k0 * top], ":", color="0.6", lw=0.8)
    ax[0].set(xlabel="sigma_v [kPa]", ylabel="sigma_h [kPa]", title="oedometric stress path (dotted: K0 = 0.5, 1)")
    ax[1].set(xlabel="eps_a of the stage [%] (dashed: unloading)", ylabel="K0 = sigma_h / sigma_v", title="K0")
    ax[2].set(xscale="log", xlabel="sigma_v [kPa]", ylabel="e", title="compression curve (slopes: Cc, Cs)")
    finish(fig, ax, ax[0], 8, out, "oedometric")


def drained_friction(j, mono, cs, peak):
    """The drained triaxial compressions (b = 0) of K0 test j's prepared sample (study job "sample") among the study's
    monotonic shears mono: per test its name, phi'_max at the largest stress ratio (as in the peak table) and phi'_cs
    at critical state (as in the critical-state table; None where the shear reached none). cs: (window, qp_tol,
    p_tol, e_tol); peak: peak_settings."""
    out = []
    for jd, _, sd in mono:
        if jd.get("sample") != j.get("sample") or jd["drainage"] != "drained":
            continue
        ps = peak_state(sd, peak)
        if ps["ext"] or ps["b"] > 0 or "M" not in ps:
            continue
        c = critical_state(sd, *cs)
        out.append((jd["name"], ps["phi"], c["phi"] if c is not None and c["ok"] else None))
    return out


def jaky_rows(oed, mono, cs, peak):
    """K0 against Jaky's K0 = 1 - sin phi' of the same sample: for each oedometric test, its first loading stage's K0
    at the end and tangent K0, beside every drained triaxial compression of the same prepared sample in the study
    (drained_friction), with that shear's largest mobilised friction angle and its critical-state one (when the
    shear reached a critical state) and 1 - sin of each; the phi' for which Jaky's formula gives the tangent K0,
    asin(1 - K0_t); and the friction angle the K0 line mobilises, asin((1 - K0_t) / (1 + K0_t)). [] without such
    pairs."""
    def jaky(phi):
        return None if phi is None else 1 - math.sin(math.radians(phi))

    rows = []
    for j, _, s in oed:
        loading = [st for st in oedometric_stages(s) if st["loading"]]
        if not loading:
            continue
        st = loading[0]
        k = st["K0_t"]
        need = math.degrees(math.asin(1 - k)) if k is not None and 0 < 1 - k <= 1 else None
        mob = math.degrees(math.asin((1 - k) / (1 + k))) if k is not None and 0 < k <= 1 else None
        for name, phi_max, phi_cs in drained_friction(j, mono, cs, peak):
            rows.append(f"| {j['name']} | {st['name']} | {name} | {st['K0']:.3f} | {number_text(k, '.3f')} | "
                        f"{phi_max:.1f} | {jaky(phi_max):.3f} | {number_text(phi_cs, '.1f')} | "
                        f"{number_text(jaky(phi_cs), '.3f')} | {number_text(need, '.1f')} | {number_text(mob, '.1f')} |")
    if not rows:
        return []
    return ["Against Jaky's K0 = 1 - sin phi' of the same sample: each K0 test's first loading stage beside the drained "
            "compression tests of its sample (phi'_max at the largest stress ratio, as in the peak table; phi'_cs at "
            "critical state, as in the critical-state table, where the shear reached one), the phi' that Jaky's "
            "formula would need to give the tangent K0, asin(1 - tangent K0), and the friction angle the loading "
            "mobilises, asin((1 - K0) / (1 + K0)) of the tangent K0 (the K0 line's stress ratio sigma_1 / sigma_3 = "
            "1 / K0, read as a Mohr-Coulomb angle), to set beside phi'_max and phi'_cs.", "",
            "| K0 test | stage | drained test | K0 at end | tangent K0 | phi'_max [°] | 1 - sin phi'_max | phi'_cs [°] | "
            "1 - sin phi'_cs | phi' for the tangent K0 [°] | phi' mobilised on the tangent [°] |",
            "|---|---|---|---|---|---|---|---|---|---|---|", *rows, ""]


def unloading_rows(oed, mono, cs, peak):
    """Unloading against Mayne & Kulhawy (1982), K0 = K0,nc OCR^(sin phi'): for each unloading stage of a K0 test that
    follows a loading stage, its OCR (oedometric_stages: the largest sigma_v of the run up to its end over sigma_v
    there), K0,nc the K0 at the end of the last loading stage before it, and the exponent
    alpha = ln(K0 / K0,nc) / ln OCR at its end; beside sin phi'_max and sin phi'_cs of each drained compression of
    the same sample (drained_friction; none where mono is empty), the exponent of Mayne & Kulhawy's relation.
    [] without such stages."""
    def sin(phi):
        return None if phi is None else math.sin(math.radians(phi))

    rows = []
    for j, _, s in oed:
        k0_nc = None
        for st in oedometric_stages(s):
            if st["loading"]:
                k0_nc = st["K0"]
                continue
            if k0_nc is None or st["OCR"] is None:
                continue
            ocr = st["OCR"]
            alpha = math.log(st["K0"] / k0_nc) / math.log(ocr) if ocr > 1 and st["K0"] > 0 and k0_nc > 0 else None
            cells = (f"| {j['name']} | {st['name']} | {ocr:.2f} | {k0_nc:.3f} | {st['K0']:.3f} | "
                     f"{number_text(alpha, '.2f')} |")
            for name, phi_max, phi_cs in (drained_friction(j, mono, cs, peak) if mono else []) or [("-", None, None)]:
                rows.append(f"{cells} {name} | {number_text(sin(phi_max), '.3f')} | {number_text(sin(phi_cs), '.3f')} |")
    if not rows:
        return []
    return ["Unloading against Mayne & Kulhawy (1982), K0 = K0,nc OCR^(sin phi'): each unloading stage's OCR = "
            "sigma_v,max / sigma_v at its end, K0,nc at the end of the loading before it, and the exponent "
            "alpha = ln(K0 / K0,nc) / ln OCR at its end, beside sin phi'_max and sin phi'_cs of the drained compression "
            "tests of its sample (as in the table against Jaky; '-' where the study has none).", "",
            "| K0 test | stage | OCR at end | K0,nc | K0 at end | alpha | drained test | sin phi'_max | sin phi'_cs |",
            "|---|---|---|---|---|---|---|---|---|", *rows, ""]


def oedometric_section(oed, figs, mono=(), cs=None, peak=None):
    """The study report's oedometric tests: per stage of each, sigma_v from its start to its end, K0 at its end, the
    tangent K0, constrained modulus M and Cc / Cs over its second half (oedometric_stages), and e at its end; with the
    figure (figures/oedometric.png). Tests that differ only in their seed: each stage's K0, tangent K0, M and Cc / Cs
    as mean ± sd [95 % half-width] over the seeds. With the study's monotonic shears (mono, and cs, peak as jaky_rows
    takes them): K0 against Jaky's estimate from the drained compression tests of the same samples. Unloading stages
    against Mayne & Kulhawy's OCR relation (unloading_rows), with those tests' angles where the study has them."""
    rows, groups = [], {}
    for j, d, s in oed:
        for st in oedometric_stages(s):
            groups.setdefault((seedless(j["name"], j), st["name"]), []).append((j.get("seed"), st))
            rows.append(f"| {j['name']} | {j['mu_r']:g} | {st['name']} | {'loading' if st['loading'] else 'unloading'} | "
                        f"{st['sv'][0] / 1e3:.1f} → {st['sv'][-1] / 1e3:.1f} | {st['K0']:.3f} | "
                        f"{number_text(st['K0_t'], '.3f')} | {number_text(None if st['M'] is None else st['M'] / 1e6, '.1f')} | "
                        f"{number_text(st['C'], '.4f')} | {st['e'][-1]:.4f} |")
    fig_oedometric([(d, s) for _, d, s in oed], figs)
    seeds_rows = []
    for (name, stage), g in sorted(groups.items()):
        if len({seed for seed, _ in g}) < 2:
            continue
        g = sorted(g, key=lambda t: t[0])
        seeds_rows.append(f"| {name} | {stage} | {len(g)} ({', '.join(str(seed) for seed, _ in g)}) | "
                          f"{seed_spread([st['K0'] for _, st in g], 3)} | {seed_spread([st['K0_t'] for _, st in g], 3)} | "
                          f"{seed_spread([None if st['M'] is None else st['M'] / 1e6 for _, st in g], 1)} | "
                          f"{seed_spread([st['C'] for _, st in g], 4)} |")
    if seeds_rows:
        seeds_rows = ["| tests (all seeds) | stage | seeds | K0 at end | tangent K0 | M [MPa] | Cc / Cs |",
                      "|---|---|---|---|---|---|---|", *seeds_rows, ""]
    keys = ("a_c", "a_d", "a_n", "a_t", "q_p", "sff")
    fabric_rows = [f"| {j['name']} | {st['name']} | " + " | ".join(f"{st['fabric'][k]:.3f}" for k in keys) + " |"
                   for j, _, s in oed for st in oedometric_stages(s) if all(k in st["fabric"] for k in keys)]
    if fabric_rows:
        fabric_rows = ["What carries the K0 stress ratio, at each stage's end (SPEC §7, signed anisotropies of the whole "
                       "network; q/p' of the contacts' stress): q/p' ≈ 2/5 (a_c + a_d + a_n + 3/2 a_t).", "",
                       "| test | stage | a_c | a_d | a_n | a_t | q/p' | 2/5 sum |", "|---|---|---|---|---|---|---|---|",
                       *fabric_rows, ""]
    return ["## Oedometric (K0) tests", "",
            "Lateral walls held (zero lateral strain), axial walls moving: sigma_v = sigma_z and sigma_h = (sigma_x + "
            "sigma_y) / 2 of the walls; K0 = sigma_h / sigma_v at the stage's end, and over the second half of its axial "
            "strain the tangent d sigma_h / d sigma_v (the K0 of the normally consolidated line, on loading), the "
            "constrained modulus M = d sigma_v / d eps_a and the index -de / d log10 sigma_v of the e - log sigma_v "
            "curve, the compression index Cc on loading and the swelling index Cs on unloading (least squares). "
            "Jaky's K0 = 1 - sin phi' is the usual reference for loading, Mayne & Kulhawy's K0 = K0,nc OCR^(sin phi') "
            "for unloading. Figure: `figures/oedometric.png`.", "",
            "| test | mu_r | stage | | sigma_v [kPa] | K0 at end | tangent K0 | M [MPa] | Cc / Cs | e at end |",
            "|---|---|---|---|---|---|---|---|---|---|", *rows, "", *seeds_rows, *fabric_rows,
            *(jaky_rows(oed, mono, cs, peak) if mono else []), *unloading_rows(oed, mono, cs, peak)]


def cyclic_ratio_text(run):
    """The CSR of a run's stress-reversal cyclic stages as it applied them (summary.json csr: q_amplitude / (2 p'_c)),
    for a legend: ", CSR 0.15" (staged: "0.1/0.15"); "" for strain reversal or a build before summary.json's csr."""
    try:
        with open(os.path.join(run, "summary.json")) as f:
            v = [st["csr"] for st in json.load(f).get("stages", []) if st.get("csr") is not None]
    except (OSError, ValueError, TypeError, AttributeError):
        return ""
    return f", CSR {'/'.join(f'{x:.3g}' for x in v)}" if v else ""


def fig_cyclic(runs, out):
    """Cyclic stages against the cycle number N: p'/p'_0 (p'_0 at the stage's first row), the excess pore pressure
    ratio r_u = u/p'_c of undrained tests (liquefaction as r_u -> 1; p'_c where the undrained loading began,
    ru_reference), and the axial strain."""
    runs = [(run, s) for run, s in runs if s["cyclic"].any()]
    if not runs:
        return
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for run, s in runs:
        m = s["cyclic"]
        n, p = s["cycle_run"][m], s["p"][m]
        lab = label(run, s) + cyclic_ratio_text(run)
        und = m & (s["stage_type"] == 3)
        with np.errstate(divide="ignore", invalid="ignore"):  # p'_0 = 0 (a sample without contacts) draws nothing
            ax[0].plot(n, p / p[0], label=lab)
            if und.any():
                ax[1].plot(s["cycle_run"][und], s["u"][und] / s["p_c"][und], label=lab)
        ax[2].plot(n, 100 * s["eps_a_run"][m], label=lab)
    ax[0].set(xlabel="cycle N", ylabel="p' / p'_0", title="mean effective stress")
    ax[1].set(xlabel="cycle N", ylabel="r_u = u / p'_0", title="excess pore pressure ratio (undrained)")
    ax[2].set(xlabel="cycle N", ylabel="eps_a [%]", title="axial strain")
    finish(fig, ax, ax[0], 8, out, "cyclic")


def complete_cycles(rows):
    """cycles.csv's rows of whole cycles: not the part of one a stage ended in (complete 0; a file of an older build
    has no such rows, nor the column)."""
    return [r for r in rows if r.get("complete", "1") != "0"]


def modulus_curves(run, s):
    """A run's cycles.csv as modulus-reduction curves (None without rows): every cycle's single-amplitude axial strain
    amp [%] = 50 (eps_a_max - eps_a_min), E [MPa], D, Dn (D less the damping's drag, cycle_damping_less_drag), and
    single-amplitude shear strain ga [%] with G [MPa]
    (cycle_shear; nan for a drained cycle of a build before gamma); `last`, each stage's last cycle in order of
    amplitude (the curve), `known` those of them with a gamma; hf = (E_max [MPa], eps_r, rms) and gf = (G_max [MPa],
    gamma_r, rms), the Hardin-Drnevich hyperbolas through the curves (hyperbolic_fit), or None."""
    # cyclic oedometers: not a modulus-reduction test (a series load() did not read, a test's, may not mark them)
    oedometer = set(s["stage"][s["cyclic_oedometric"]]) if "cyclic_oedometric" in s else set()
    with open(os.path.join(run, "cycles.csv")) as f:
        rows = [r for r in complete_cycles(csv.DictReader(f)) if r["stage"] not in oedometer]
    if not rows:
        return None
    # each stage's drainage, for cycle_shear's fallback on rows without gamma (stage_type 3: cyclic undrained)
    drainage = {st: "undrained" if ty == 3 else "drained" for st, ty in zip(s["stage"], s["stage_type"])}
    amp = np.array([50 * (float(r["eps_a_max"]) - float(r["eps_a_min"])) for r in rows])
    E, D = np.array([float(r["E_eq"]) / 1e6 for r in rows]), np.array([float(r["damping"]) for r in rows])
    Dn = np.array([cycle_damping_less_drag(r) for r in rows])
    ga, G = np.array([cycle_shear(r, drainage.get(r["stage"], "drained")) for r in rows]).T
    ga, G = 100 * ga, G / 1e6
    last = sorted({r["stage"]: k for k, r in enumerate(rows)}.values(), key=lambda k: amp[k])
    known = [k for k in last if ga[k] == ga[k]]
    return dict(amp=amp, E=E, D=D, Dn=Dn, ga=ga, G=G, last=last, known=known, hf=hyperbolic_fit(amp[last] / 100, E[last]),
                gf=hyperbolic_fit(ga[known] / 100, G[known]) if known else None)


def fig_modulus_damping(runs, out):
    """Modulus reduction and damping from each run's cycles.csv (modulus_curves), one colour per run: the equivalent
    Young's modulus E_eq against the single-amplitude axial strain, and the equivalent shear modulus G_eq and the
    damping ratio D against the single-amplitude shear strain, the G - gamma curve a site-response code takes. Every
    cycle a faint point, the curve through each stage's last cycle, and (dotted, the fit in the legend) the hyperbola
    of Hardin & Drnevich fitted to that curve; D also less the local damping's drag (dashed, x), where cycles.csv has
    it."""
    runs = [(run, s) for run, s in runs if os.path.isfile(os.path.join(run, "cycles.csv"))]
    curves = [(run, s, modulus_curves(run, s)) for run, s in runs]
    curves = [x for x in curves if x[2] is not None]  # (a run of cyclic oedometers alone has none)
    if not curves:
        return
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))
    for i, (run, s, c) in enumerate(curves):
        color = f"C{i % 10}"
        amp, E, D, ga, G, last, known, hf, gf = (c[k] for k in ("amp", "E", "D", "ga", "G", "last", "known", "hf", "gf"))
        ax[0].plot(amp, E, "o", color=color, alpha=0.35, markersize=4)
        ax[1].plot(ga, G, "o", color=color, alpha=0.35, markersize=4)
        ax[2].plot(ga, D, "o", color=color, alpha=0.35, markersize=4)
        fit = f", E_max {hf[0]:.3g} MPa, eps_r {100 * hf[1]:.2g} %" if hf else ""
        ax[0].plot(amp[last], E[last], "o-", color=color, label=label(run, s) + fit)
        gfit = f", G_max {gf[0]:.3g} MPa, gamma_r {100 * gf[1]:.2g} %" if gf else ""
        ax[1].plot(ga[known], G[known], "o-", color=color, label=label(run, s) + gfit)
        ax[2].plot(ga[known], D[known], "o-", color=color)
        Dn = c["Dn"]
        if np.isfinite(Dn[known]).any():
            ax[2].plot(ga[known], Dn[known], "x--", color=color, label=label(run, s) + ", less the damping's drag")
        for a, x, h in ((ax[0], amp[last], hf), (ax[1], ga[known], gf)):
            if h:
                xs = np.geomspace(x.min() / 3, x.max() * 3, 100)
                a.plot(xs, h[0] / (1 + xs / 100 / h[1]), ":", color=color)
    ax[0].set(xscale="log", xlabel="single-amplitude eps_a [%]", ylabel="E_eq [MPa]", title="equivalent Young's modulus")
    ax[1].set(xscale="log", xlabel="single-amplitude gamma [%]", ylabel="G_eq [MPa]", title="equivalent shear modulus")
    ax[2].set(xscale="log", xlabel="single-amplitude gamma [%]", ylabel="D", title="damping ratio")
    for a in np.ravel(ax):
        a.grid(alpha=0.3)
    legend(ax[0], fontsize=8)
    legend(ax[1], fontsize=8)
    legend(ax[2], fontsize=8)
    save(fig, out, "modulus_damping")


def oedometer_cycles(run, s):
    """A run's cyclic oedometer stages (series stage_type 6) as {stage: dict(N, eps [%], M [MPa], D, K)} from the whole
    cycles of its cycles.csv: N the cycle, eps the permanent axial strain at its end (eps_v: the held lateral walls make
    it eps_a), M_eq, D_v, Dn (D_v less the damping's drag) and K = sigma_h / sigma_v at its end; {} where there are
    none."""
    stages = list(dict.fromkeys(s["stage"][s["cyclic_oedometric"]]))
    path = os.path.join(run, "cycles.csv")
    if not stages or not os.path.isfile(path):
        return {}
    with open(path) as f:
        rows = [r for r in complete_cycles(csv.DictReader(f)) if r["stage"] in stages and "M_eq" in r]
    out = {}
    for st in stages:
        rs = [r for r in rows if r["stage"] == st]
        if rs:
            def col(k, scale=1.0, rs=rs):
                return np.array([scale * float(r[k]) for r in rs])
            out[st] = dict(N=col("cycle"), eps=col("eps_v", 100.0), M=col("M_eq", 1e-6), D=col("damping_v"), K=col("K"),
                           Dn=col("damping_v_less_drag"), emax=col("eps_a_max"))
    return out


def fig_cyclic_oedometer(runs, out):
    """Cyclic oedometer stages (the lateral walls held, sigma_v reversing about sigma_v,0): the sigma_v - eps_a loops
    (the series' rows), the permanent axial strain at each cycle's end against N (log N: ratcheting is a line that
    keeps rising, shakedown one that levels off), the constrained modulus M_eq and damping ratio D_v of each cycle's
    sigma_v loop (and D_v less the damping's drag), K = sigma_h / sigma_v at each cycle's end (sigma_v back at
    sigma_v,0: the lateral stress the cycles leave locked in), and the strain's rate per cycle over doubling windows
    (rate_windows) on log-log axes beside a slope of -1 (the logarithmic law: steeper dies away, shakedown; flatter
    keeps on, ratcheting); nothing where no run has such a stage."""
    drawn = [(run, s, oedometer_cycles(run, s)) for run, s in runs]
    drawn = [d for d in drawn if d[1]["cyclic_oedometric"].any()]
    if not drawn:
        return
    fig, ax = plt.subplots(1, 5, figsize=(25, 4.5))
    damp = ax[2].twinx()
    anchor = None  # the m = 1 guide through the first window drawn
    for i, (run, s, stages) in enumerate(drawn):
        color = f"C{i % 10}"
        m = s["cyclic_oedometric"]
        ax[0].plot(100 * s["eps_a_run"][m], s["sigma_z"][m] / 1e3, color=color, lw=0.8)
        for n, c in enumerate(stages.values()):  # the legend on the strain panel, whose upper left a rising curve leaves free
            ax[1].plot(c["N"], c["eps"], "o-", color=color, markersize=3, label=label(run, s) if n == 0 else None)
            ax[2].plot(c["N"], c["M"], "o-", color=color, markersize=3)
            damp.plot(c["N"], c["D"], "x--", color=color, markersize=3)
            damp.plot(c["N"], c["Dn"], "+:", color=color, markersize=4)
            ax[3].plot(c["N"], c["K"], "o-", color=color, markersize=3)
            w = [(x[3], x[2]) for x in rate_windows(c["N"], c["eps"]) if x[2] > 0]  # a log axis: rising windows
            if w:
                ax[4].plot(*zip(*w), "o-", color=color, markersize=4)
                anchor = anchor or w[0]
    if anchor:
        n_end = max(c["N"][-1] for _, _, stages in drawn for c in stages.values())
        ax[4].plot([anchor[0], n_end], [anchor[1], anchor[1] * anchor[0] / n_end], "k--", lw=0.8,
                   label="m = 1 (eps_p = a + c ln N): steeper is shakedown")
        legend(ax[4], fontsize=8)
    damp.set_ylabel("D_v (dashed; dotted: less the damping's drag)")
    ax[0].set(xlabel="eps_a [%] (across the run's shear stages)", ylabel="sigma_v [kPa]", title="sigma_v - eps_a loops")
    ax[1].set(xscale="log", xlabel="cycle N", ylabel="permanent eps_a at the cycle's end [%]",
              title="accumulated strain (ratcheting / shakedown)")
    ax[2].set(xscale="log", xlabel="cycle N", ylabel="M_eq [MPa] (solid)", title="constrained modulus and damping")
    ax[3].set(xscale="log", xlabel="cycle N", ylabel="K = sigma_h / sigma_v at sigma_v,0", title="lateral stress ratio")
    ax[4].set(xscale="log", yscale="log", xlabel="cycle N (each window's 1/N mean: 2-4, 4-8, ...)",
              ylabel="permanent strain per cycle [%]", title="rate ~ N^-m (m > 1 bounded: shakedown)")
    finish(fig, ax, ax[1], 8, out, "cyclic_oedometer")


def legend(ax, **kw):
    """ax.legend(**kw) where the axes hold labelled artists; matplotlib warns on stderr otherwise (a csl or
    study without a critical state has nothing to label)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(**kw)


def critical_state(s, window, qp_tol=0.05, p_tol=0.05, e_tol=0.005):
    """Final state of the shear stage, and whether it is critical: over the last `window` of axial strain,
    q/p', p' and e must each be steady: the drift of a fitted line over the window below qp_tol (q/p'),
    p_tol (p' relative) and e_tol (e). The reported state is the mean over the window. A triaxial extension
    (eps_a < 0 at the end) counts its window along -eps_a; its state says ext=True; M = |q/p'| (friction_angle)."""
    m = s["monotonic"]
    if not m.any():
        return None
    ext = bool(s["eps_a"][m][-1] < 0)
    ea = -s["eps_a"][m] if ext else s["eps_a"][m]  # strain along the loading
    w = ea >= ea[-1] - window
    if ea[-1] - ea[0] < window or w.sum() < 3:
        return dict(ok=False, why="shear shorter than the window")
    qp, p, e = s["q_p"][m][w], s["p"][m][w], s["e"][m][w]
    # Steady = no trend: the drift of a least-squares line over the window (slope x window), so that the
    # fluctuations of a small sample do not count as change. p' relative to its mean.
    x = ea[w]
    pm = max(np.mean(p), 1e-30)
    spread = {k: drift_and_error(x, y) for k, y in (("qp", qp), ("p", p / pm), ("e", e))}
    tols = dict(qp=qp_tol, p=p_tol, e=e_tol)
    ok = all(spread[k][0] < tols[k] for k in tols)
    why = ""
    if not ok:
        why = "drifting over the last %g of strain: q/p' by %.3f ± %.3f (< %g), p' by %.3f ± %.3f (< %g), e by %.4f ± %.4f (< %g)" % (
            window, *spread["qp"], qp_tol, *spread["p"], p_tol, *spread["e"], e_tol)
        # A drift past its tolerance by less than twice its standard error may be the sample's slow fluctuation, not a
        # trend: the verdict stands (the tolerances are the study's), but the reader learns that a longer window or
        # shear would decide it.
        if all(spread[k][0] < tols[k] + 2 * spread[k][1] for k in tols):
            why += "; within two standard errors of the tolerances: a longer window would tell"
    last = {k: s[k][m][-1] for k in ("a_c", "a_d", "a_n", "a_t", "sff_share_c", "sff_share_d", "sff_share_n",
                                      "sff_share_t", "q", "sff") if k in s}
    M, b = abs(float(np.mean(qp))), float(s.get("b", 0.0))
    # phi_cs: M's relation, or for a true-triaxial test (b > 0) the principal stresses' mean angle over the window
    phi = float(np.mean(principal_angle(s)[m][w])) if b > 0 else friction_angle(M, ext)
    # How quasi-static the state is (SPEC §6, step 3): the mean inertial number and skeleton kinetic / elastic energy over
    # the window (None where the series has no such column, or none finite).
    kc = ke_column(s)
    I, ke = (window_mean(s, col, m, w) if col else None for col in ("inertial_number", kc))
    # and the interior's void ratio (series e_inner: the whole box's e counts the looser layer along the walls)
    return dict(ok=ok, why=why, p=np.mean(p), e=np.mean(e), mu_r=s["mu_r"][m][-1], qp=np.mean(qp), ext=ext,
                M=M, b=PLANE_STRAIN if s.get("plane_strain") else b, phi=phi, I=I, ke=ke,
                rate=float(s.get("rate", 0.0)),
                e_inner=window_mean(s, "e_inner", m, w), M_walls=window_ratio(s, "q", "p", m, w),
                M_inner=window_ratio(s, "q_inner", "p_inner", m, w),
                M_less_drag=window_ratio(s, "q_less_drag", "p_less_drag", m, w), **last)


def window_ratio(s, qcol, pcol, m, w):
    """The mean of |q/p'| from columns qcol, pcol over the rows `w` of the rows `m` (the stress ratio of another
    stress than the contacts' q_p: the walls', the interior's), NaN rows left out; None where not measured."""
    if qcol not in s or pcol not in s:
        return None
    q, p = s[qcol][m][w], s[pcol][m][w]
    ok = np.isfinite(q) & np.isfinite(p) & (p > 0)
    return float(np.mean(np.abs(q[ok] / p[ok]))) if ok.any() else None


# Which stress the stress ratio is of (the report's critical-state sections): SPEC §7's contact stress sums the
# sphere-sphere contacts over the whole box; the walls' stress is the boundary's; the interior's (series p_inner,
# q_inner) is that of the spheres two mean diameters or more from the walls. Measured on configs/size-study.yaml
# (mu_r 0, 100 kPa, 2 000 / 5 000 / 10 000 spheres, 3 seeds, critical-state window 35-41 %): q/p' of the contacts
# 0.630 / 0.695 / 0.713, of the interior 0.751 / 0.793 / 0.781, of the contacts with the sphere-wall contacts
# (q_contacts_walls) 0.750 / 0.781 / 0.783, of the walls 0.804 / 0.868 / 0.902. The walls' excess over the contacts
# with wall contacts is the local damping's drag (SPEC §4) on the flowing sample, a body force whose moment grows
# with the sample's length: at 5-10 % strain q_contacts_walls / q = 0.958 (2 000) and 0.913 (10 000) at damping 0.2,
# 0.988 and 0.970 at 0.05. Measured since as series p_drag, q_drag (configs/damping-drag.yaml, 5-10 %): at damping 0.2
# the walls' q/p' 0.781, less the drag 0.744, the contacts' with the wall contacts 0.747 (0.727, 0.714, 0.720 at 0.05);
# what is left between the last two is the spheres' inertia, row by row.
STRESS_MEASURES_TEXT = (
    "q/p' is SPEC §7's contact stress (every sphere-sphere contact over the box's volume), as are M, phi_cs and the "
    "stress-force-fabric sum; it leaves out the sphere-wall contacts, whose share falls with the sample's size "
    "against its grains. q/p' interior is that of the spheres whose centres lie in e_c interior's box (series "
    "p_inner, q_inner): the material without the layers along the walls. q/p' walls is the walls' own: besides the "
    "contacts it carries the local damping's drag on the flowing sample, which grows with the sample's size and its "
    "damping (configs/README.md). The drag is measured (series p_drag, q_drag: the damping forces' first moment about "
    "the box's centre over its volume), and the walls' stress less it is what the contacts, with the sphere-wall "
    "contacts, and the spheres' inertia carry.")


def stress_measures_note(states):
    """One line on how far the walls' (as measured, and less the damping's drag) and the interior's critical stress
    ratios are from the contacts' (states: critical states of critical_state); empty where none was measured."""
    parts = []
    for key, what in (("M_walls", "the walls'"), ("M_less_drag", "the walls' less the damping's drag"),
                      ("M_inner", "the interior's")):
        d = [100 * (c[key] / c["M"] - 1) for c in states if c.get(key) is not None and c["M"] > 0]
        if d:
            parts.append(f"{what} {min(d):+.0f} to {max(d):+.0f} %")
    return ("Over the critical states, q/p' of the walls, of the walls less the damping's drag and of the interior "
            "against the contacts': " +
            ", ".join(parts) + ".") if parts else ""


def drift_and_error(x, y):
    """The drift of y over the window x (|slope| of a least-squares line times the window) and its standard error. Series
    rows are serially correlated (a fluctuation lasts many rows), so the ordinary error, which takes them as independent,
    is widened by sqrt((1 + rho) / (1 - rho)) for the lag-1 autocorrelation rho of the residuals (an AR(1) model;
    rho clipped to [0, 0.9])."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n, span = len(x), x[-1] - x[0]
    b, a = np.polyfit(x, y, 1)
    r = y - (a + b * x)
    sxx = float(np.sum((x - x.mean()) ** 2))
    if n < 4 or sxx <= 0:
        return abs(b) * span, float("nan")
    rr = float(np.sum(r * r))
    rho = float(np.sum(r[1:] * r[:-1]) / rr) if rr > 0 else 0.0
    rho = min(max(rho, 0.0), 0.9)
    se = math.sqrt(rr / (n - 2) / sxx) * math.sqrt((1 + rho) / (1 - rho))
    return abs(b) * span, se * span


def window_mean(s, col, m, w):
    """The mean of column `col` over the rows `w` of the rows `m`, its NaN rows (restored from a checkpoint of a build
    before the column) left out; None where the series has no such column or no finite value there."""
    if col not in s:
        return None
    y = s[col][m][w]
    y = y[np.isfinite(y)]
    return float(np.mean(y)) if len(y) else None


def number_text(x, fmt):
    """A measure as a table cell: '-' where not measured (None, or NaN: rows of a build before the column)."""
    return "-" if x is None or not math.isfinite(x) else format(x, fmt)


def quasi_static_text(I, ke):
    """A critical state's inertial number and kinetic / elastic energy as table cells ("-" where not measured)."""
    return number_text(I, ".1e") + " | " + number_text(ke, ".3f")


def inertial_note(states):
    """A line for the critical states reached above the quasi-static inertial number (none: empty)."""
    fast = [c["I"] for c in states if c.get("I") is not None and c["I"] > QUASI_STATIC_I]
    if not fast:
        return ""
    return (f"{len(fast)} of {len(states)} critical states were reached at an inertial number above the quasi-static "
            f"limit I < {QUASI_STATIC_I:g} (up to {max(fast):.1e}; GDR MiDi 2004): the stress ratio of a steady flow "
            "rises with I (mu(I) rheology, Jop et al. 2006), so their q/p', M and e_c are those of a slow dense flow, "
            "above the rate-independent values. Lower the shear's axial_strain_rate (or density_scaling, which I "
            "counts) to measure those, or give the study an axial_strain_rate axis, whose report extrapolates them to "
            "I -> 0 (configs/rate-study.yaml).")


def peak_inertial_note(Is):
    """A line for the largest stress ratios reached above the quasi-static inertial number (Is: each test's I there;
    none above: empty). A peak rises with I as the critical state does (mu(I)), and in a dense sample the peak comes
    at small strain, where the walls' start-up may still be felt."""
    fast = [I for I in Is if I > QUASI_STATIC_I]
    if not fast:
        return ""
    return (f"{len(fast)} of {len(Is)} largest stress ratios were reached at an inertial number above the quasi-static "
            f"limit I < {QUASI_STATIC_I:g} (up to {max(fast):.1e}): their max q/p' and phi'_max include a rate effect "
            "(mu(I), Jop et al. 2006) and are upper bounds of the rate-independent peak; an axial_strain_rate axis "
            "extrapolates them to I -> 0 (section Rate dependence, configs/rate-study.yaml).")


def principal_angle(s):
    """The mobilised Mohr-Coulomb angle [deg] of each series row from the wall stresses' principal values,
    sin(phi) = (sigma_1 - sigma_3) / (sigma_1 + sigma_3): any b, where friction_angle's relations of M hold at b = 0
    (compression) and b = 1 (extension) only."""
    st = np.vstack([s["sigma_x"], s["sigma_y"], s["sigma_z"]])
    s1, s3 = st.max(axis=0), st.min(axis=0)
    return np.degrees(np.arcsin(np.clip((s1 - s3) / np.maximum(s1 + s3, 1e-300), 0, 1)))


def principal_b(s):
    """The intermediate principal stress ratio b = (sigma_2 - sigma_3) / (sigma_1 - sigma_3) of each series row from
    the wall stresses (0 where sigma_1 = sigma_3): what a true-triaxial stage held, against its target."""
    s3, s2, s1 = np.sort(np.vstack([s["sigma_x"], s["sigma_y"], s["sigma_z"]]), axis=0)
    d = s1 - s3
    return np.where(d > 0, (s2 - s3) / np.where(d > 0, d, 1.0), 0.0)


def peak_settings(idx):
    """(window, max_ke) of a study's `peak` block (study.json): the axial strain each stress measure is averaged over,
    about each row, before its largest is taken (0: single rows), and the kinetic / elastic energy above which a row
    is left out (None: no row is). A study.json of an older build has no block: single rows, every row."""
    pk = idx.get("peak", {})
    return float(pk.get("window", 0) or 0), (float(pk["max_ke_ratio"]) if pk.get("max_ke_ratio") else None)


def ke_column(s):
    """The series' quasi-static measure: ke_fluct_ratio, the skeleton's kinetic energy about its best-fit affine motion
    over the elastic energy (the walls' imposed deformation left out), or ke_ratio in a run of a build before it."""
    return "ke_fluct_ratio" if "ke_fluct_ratio" in s else "ke_ratio" if "ke_ratio" in s else None


def peak_rows(s, m, max_ke):
    """The rows (indices) of mask m that a peak is taken over: those whose kinetic / elastic energy (ke_column) is
    at most max_ke; all of m where there is no threshold or no such column. A row that did not measure it (NaN: rows
    a checkpoint of an older build restored) is kept."""
    col = ke_column(s)
    if max_ke is not None and col:
        m = m & ~(s[col] > max_ke)
    return np.flatnonzero(m)


def running_mean(s, rows, y, window):
    """y at each of `rows` averaged over those of `rows` within window / 2 of its axial strain (y[rows] itself at
    window 0). A few thousand spheres' stress ratio fluctuates from row to row (the 5 000-sphere constant-p' study:
    standard deviation 0.25 deg at b <= 0.25, 1.1-1.4 deg at b = 1, single steps of up to 15 deg at b = 1 past 30 %
    strain), and the largest single row is then the largest fluctuation, not the material's peak."""
    y = np.asarray(y, dtype=float)[rows]
    if window <= 0 or len(rows) == 0:
        return y
    e = np.abs(s["eps_a"][rows])  # along the loading, in either direction
    order = np.argsort(e, kind="stable")
    es, c = e[order], np.concatenate([[0.0], np.cumsum(y[order])])
    lo = np.searchsorted(es, es - window / 2, "left")
    hi = np.searchsorted(es, es + window / 2, "right")
    out = np.empty_like(y)
    out[order] = (c[hi] - c[lo]) / (hi - lo)
    return out


def peak_state(s, peak):
    """The peak table's measures of a shear (peak: the study's (window, max_ke), peak_settings), over its sheared rows
    but a K0 consolidation's (oedometric rows before a shear): its direction (ext,
    b), every row's mobilised friction angle `ang` (from the principal wall stresses at b > 0, else from the contacts'
    q_p = sqrt(3/2 s:s) / p', SPEC §7, >= 0 in either direction, as critical_state reads it, by Mohr-Coulomb's relation
    of the direction), the rows the peak is taken over, and where there are any: the peak of |q| along the loading
    (q_peak < 0 in extension, its strain eps_peak and q/p' there, qp_peak) and the largest stress ratio (maximum
    obliquity: past the peak of q in an undrained test, where p' still grows along the failure line) M with its angle
    phi (the angles' own largest at b > 0) and the inertial number there, I (None where the series has no such column
    or its rows there did not measure it: a checkpoint of an older build); and the peak of the walls' |q| less the
    local damping's drag (series q_drag), q_peak_less_drag (None without the column). Each measure is a running mean
    over the peak window."""
    # A K0 loading and unloading before a shear (a SHANSEP or CK0U test) are its consolidation: their q (up to
    # (1 - K0) sigma_v) is no peak of the shear's; a K0 test's own oedometric rows stay (no other sheared rows)
    m = s["shear"] & ~s["oedometric"] if (s["shear"] & ~s["oedometric"]).any() else s["shear"]
    ext = bool(s["eps_a"][m][-1] < 0)  # as critical_state tells it: older study.json files have no direction
    b = float(s.get("b", 0.0))
    ang = principal_angle(s) if b > 0 else np.array([friction_angle(M, ext) for M in s["q_p"]])
    rows = peak_rows(s, m, peak[1])
    out = dict(ext=ext, b=b, ang=ang, m=m, rows=rows)
    if not len(rows):
        return out
    window, sign = peak[0], (-1 if ext else 1)  # |q| along the loading
    along, qp = running_mean(s, rows, sign * s["q"], window), running_mean(s, rows, s["q_p"], window)
    k, kq = int(np.argmax(along)), int(np.argmax(qp))
    I = float(running_mean(s, rows, s["inertial_number"], window)[kq]) if "inertial_number" in s else None
    if "q_less_drag" in s:
        less = running_mean(s, rows, sign * s["q_less_drag"], window)
        # (NaN rows: restored from a checkpoint of a build before the column)
        out["q_peak_less_drag"] = float(sign * np.nanmax(less)) if np.isfinite(less).any() else None
    out.update(q_peak=float(sign * along[k]), eps_peak=float(s["eps_a"][rows[k]]), qp_peak=float(qp[k]),
               M=float(qp[kq]), phi=float(np.max(running_mean(s, rows, ang, window))) if b > 0
               else friction_angle(qp[kq], ext), I=I if I is not None and math.isfinite(I) else None)
    return out


def single_row_note(s, m, rows, ang, max_ke):
    """The peak tables' last column: the largest angle of a single row of the loading m (ang: every row's angle), its
    strain and kinetic / elastic energy, and how many rows the ke_ratio threshold left out (rows: those kept)."""
    k = int(np.argmax(np.where(m, ang, -np.inf)))
    note = f"{ang[k]:.1f}° at {100 * abs(s['eps_a'][k]):.1f} %"
    col = ke_column(s)
    if col:
        note += f" ({col} {s[col][k]:.3f})"
    n = int(np.count_nonzero(m)) - len(rows)
    if n > 0:
        note += f"; {n} row{'s' if n > 1 else ''} above {col} {max_ke:g} left out"
    return note


def failure_criteria(phi_tc, b):
    """The Mohr-Coulomb angles [deg] at b that two three-invariant failure criteria predict, each calibrated on the
    triaxial-compression angle phi_tc [deg] (b = 0): Matsuoka-Nakai, I1 I2 / I3 constant (Matsuoka & Nakai 1974,
    the spatially mobilised plane), and Lade-Duncan, I1^3 / I3 constant (Lade & Duncan 1975). Returns (phi_MN,
    phi_LD). Solved for N = sigma_1 / sigma_3 with sigma_2 = sigma_3 + b (sigma_1 - sigma_3) by bisection: at fixed b
    both ratios grow with N from their isotropic values 9 and 27. Matsuoka-Nakai gives phi_tc back at b = 1 (its
    ratio is symmetric in the principal stresses, and b = 1 is compression with sigma_1 and sigma_3 swapped in
    rank); Lade-Duncan gives more there; Mohr-Coulomb, phi_tc at every b."""
    def ratios(N, bb):
        s1, s2, s3 = N, 1 + bb * (N - 1), 1.0
        i1, i2, i3 = s1 + s2 + s3, s1 * s2 + s2 * s3 + s3 * s1, s1 * s2 * s3
        return i1 * i2 / i3, i1 ** 3 / i3
    sn = math.sin(math.radians(phi_tc))
    targets = ratios((1 + sn) / (1 - sn), 0.0)
    out = []
    for k in range(2):
        lo, hi = 1.0, 1e8
        for _ in range(200):  # on log N: 200 halvings of ln(1e8) reach double precision
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if ratios(mid, b)[k] < targets[k] else (lo, mid)
        N = math.sqrt(lo * hi)
        out.append(math.degrees(math.asin((N - 1) / (N + 1))))
    return tuple(out)


def peak_text(window, max_ke):
    """How the report's peaks were taken, in words (peak_settings)."""
    how = (f"each measure averaged over {100 * window:g} % of axial strain about each row before its largest is "
           f"taken (the study's peak.window)" if window > 0 else "the largest of single rows")
    keep = (f", over the rows whose kinetic energy about the specimen's affine motion over the elastic energy "
            f"(ke_fluct_ratio; ke_ratio in runs of older builds) is at most {max_ke:g} (peak.max_ke_ratio)"
            if max_ke is not None else "")
    return (f"Peaks are {how}{keep}; the last column gives the largest angle of a single row, with its strain and "
            "kinetic / elastic energy" + (" and the rows left out." if max_ke is not None else "."))


def failure_section(mono, window, tol, figs, peak=(0.0, None)):
    """The true-triaxial series: per sample and drainage, the drained compression tests at several b, and the drained
    triaxial extensions (the Lode angle of b = 1, reached by unloading the axis: the lateral stresses the major pair),
    against the failure criteria calibrated on its b = 0 compression, at the largest obliquity and at the critical
    state. Every angle here is the wall stresses' (principal_angle), the b = 0 test's too, so that the criteria compare
    like with like; the b of each state is the measured one (principal_b), which the criteria are evaluated at. Empty
    without such a series."""
    groups = {}
    for j, d, s in mono:
        m = s["monotonic"]
        ext = bool(s["eps_a"][m][-1] < 0)
        if j["drainage"] != "drained" or not {"sigma_x", "sigma_y", "sigma_z"} <= set(s):
            continue
        ang_all, bm_all = principal_angle(s), principal_b(s)
        rows_k = peak_rows(s, m, peak[1])  # the largest obliquity as the study's peak block takes it
        top = None
        if len(rows_k):
            a_w, b_w = running_mean(s, rows_k, ang_all, peak[0]), running_mean(s, rows_k, bm_all, peak[0])
            k = int(np.argmax(a_w))
            top = (float(a_w[k]), float(b_w[k]))
        row = series_row(j, s, ext, peak=top, cs=None, servo=s.get("servo_error"),
                         single=single_row_note(s, m, rows_k, ang_all, peak[1]))
        ang, bm = ang_all[m], bm_all[m]
        c = critical_state(s, window, *tol)  # the study's steadiness test, as its critical-state table
        if c is not None and c["ok"]:
            ea = -s["eps_a"][m] if ext else s["eps_a"][m]  # along the loading, as critical_state's window
            w = ea >= ea[-1] - window
            row["cs"] = (float(np.mean(ang[w])), float(np.mean(bm[w])))
        # one calibration per stress path: a constant-p' series (stress_path: constant_p) has its own b = 0 test; a
        # plane-strain test holds sigma_3 constant as the standard series does, and joins it at the b it develops
        groups.setdefault((j["sample"], j["drainage"], series_path(s)), []).append(row)
    series = {k: sorted(g, key=lambda r: (r["b"], r["ext"])) for k, g in groups.items()
              if any(r["b"] == 0 for r in g) and any(r["b"] > 0 for r in g)}
    if not series:
        return []
    rows, dev = [], {("peak", c): [] for c in range(3)}
    dev.update({("cs", c): [] for c in range(3)})
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    bs = np.linspace(0, 1, 51)
    paths = {k[2] for k in series}
    for (sample, _, path), g in sorted(series.items()):
        at = " at constant p'" if path == "constant_p" else ""
        ref = next(r for r in g if r["b"] == 0)
        cells = {}
        for i, state in enumerate(("peak", "cs")):
            if ref[state] is None:  # no b = 0 critical state to calibrate on: the measured angles alone
                for r in g:
                    if r[state] is not None:
                        cells[(r["name"], state)] = f"{r[state][1]:.2f} | {r[state][0]:.1f} | - | - | -"
                continue
            phi0 = ref[state][0]
            line = ax[i].plot([r[state][1] for r in g if r[state] and not r["ext"]],
                              [r[state][0] for r in g if r[state] and not r["ext"]], "o",
                              label=f"mu_r = {ref['mu_r']:g} ({sample}){at}")
            col = line[0].get_color()
            # extensions (triaxial at b = 1, plane strain at its b) as squares of the series' colour, as csl draws them
            ext_pts = [r[state] for r in g if r[state] and r["ext"]]
            if ext_pts:
                ax[i].plot([v[1] for v in ext_pts], [v[0] for v in ext_pts], "s", mfc="none", color=col,
                           label=f"mu_r = {ref['mu_r']:g} ({sample}){at}, extension")
            pred = np.array([failure_criteria(phi0, b) for b in bs])
            ax[i].plot(bs, pred[:, 0], "-", color=col, lw=1)
            ax[i].plot(bs, pred[:, 1], ":", color=col, lw=1)
            ax[i].axhline(phi0, color=col, lw=0.6, ls="--")
            for r in g:
                if r[state] is None:
                    continue
                phi, bm = r[state]
                mc, mn, ld = phi0, *failure_criteria(phi0, bm)
                cells[(r["name"], state)] = f"{bm:.2f} | {phi:.1f} | {mc:.1f} | {mn:.1f} | {ld:.1f}"
                if r["b"] > 0:
                    for c, p in enumerate((mc, mn, ld)):
                        dev[(state, c)].append(phi - p)
        for r in g:
            servo = "-" if r["servo"] is None else f"{100 * r['servo']:.2f}"
            rows.append(f"| {r['name']}{at} | {r['mu_r']:g} | {b_text(r)} | "
                        + " | ".join(cells.get((r["name"], st), "| | | |") for st in ("peak", "cs")) + f" | {servo} | "
                        + r["single"] + " |")
    for i, title in enumerate(("largest obliquity (phi'_max)", "critical state (phi_cs)")):
        ax[i].set(xlabel="b measured", ylabel="phi [deg] (wall stresses)",
                  title=title + "\n-- Mohr-Coulomb, - Matsuoka-Nakai, : Lade-Duncan")
        ax[i].grid(alpha=0.3)
    legend(ax[0], fontsize=7)
    save(fig, figs, "failure_criteria")

    def rms(v):
        return f"{math.sqrt(np.mean(np.square(v))):.2f}° ({len(v)})" if v else "-"
    members = [r for g in series.values() for r in g if r["b"] > 0]
    true_tx, exts = any(not r["ext"] and not r["ps"] for r in members), any(r["ext"] and not r["ps"] for r in members)
    kinds = (["true triaxial"] if true_tx else []) + (["plane strain"] if any(r["ps"] for r in members) else []) + (
        ["extension"] if exts else [])
    title = ", ".join(kinds[:-1]) + " and " + kinds[-1] if len(kinds) > 1 else kinds[0]
    return [f"## Failure criteria ({title})", "",
            "Drained compression tests of one sample at several b = (sigma_2 - sigma_3) / (sigma_1 - sigma_3), against "
            "three criteria calibrated on the sample's b = 0 test: Mohr-Coulomb (phi independent of b), Matsuoka-Nakai "
            "(I1 I2 / I3 constant) and Lade-Duncan (I1^3 / I3 constant), each evaluated at the measured b. " +
            ("A triaxial extension of the sample ('1 (extension)': the axial walls moved apart at constant lateral "
             "stress, so the lateral pair are sigma_1 = sigma_2 and the axis sigma_3) is the Lode angle of b = 1 "
             "reached the other way: Mohr-Coulomb and Matsuoka-Nakai give it the compression's phi, Lade-Duncan more "
             "(Lade & Duncan 1975). " if exts else "") +
            ("A plane-strain test of the sample ('(plane strain)': stress_path: plane_strain, the x walls held at zero "
             "strain and sigma_3 at p'_0) joins the series at the b it develops, its b column the mean measured over "
             "the second half of the shear. " if any(r["ps"] for r in members) else "") +
            ("A plane-strain extension ('(plane strain extension)': the axial walls moved apart, the x walls held and "
             "the y walls at their start's stress, then sigma_1; the axis sigma_3) joins it the same way: a Lode angle "
             "reached by unloading the axis, where the compressions load it. "
             if any(r["ps"] and r["ext"] for r in members) else "") + "Every angle "
            "is sin phi = (sigma_1 - sigma_3) / (sigma_1 + sigma_3) of the wall stresses, the b = 0 test's too (the "
            "peak table takes that one from the contacts' q/p'); the critical state's is the mean over the window. "
            "The last column is the largest distance of a lateral wall stress from its servo target over the shear "
            "(summary.json servo_error: sigma_3 from p'_0, sigma_2 from p'_0 + b (sigma_1 - p'_0)), in % of the target. "
            + peak_text(*peak) + " "
            + ("Tests marked at constant p' (stress_path: constant_p) hold p' = p'_0, sigma_3 falling as sigma_1 rises "
               "(their servo targets are those of that path); each path is calibrated on its own b = 0 test. "
               if "constant_p" in paths else "")
            + "Figure: `figures/failure_criteria.png`.", "",
            "| test | mu_r | b | b at phi'_max | phi'_max [°] | MC | MN | LD | b at c.s. | phi_cs [°] | MC | MN | LD | "
            "servo error [%] | largest single row |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", *rows, "",
            "Root-mean-square of measured minus predicted over the b > 0 tests (count):", "",
            "| state | Mohr-Coulomb | Matsuoka-Nakai | Lade-Duncan |", "|---|---|---|---|",
            *(f"| {lab} | " + " | ".join(rms(dev[(st, c)]) for c in range(3)) + " |"
              for st, lab in (("peak", "largest obliquity"), ("cs", "critical state"))), ""]


def series_row(j, s, ext, **fields):
    """A b series' row (failure_section, flow_section) of job j with series s, and the section's own fields. A
    triaxial extension's b is 1 (sigma_2 = sigma_1, the lateral pair): its nominal b for the series, measured by the
    sections; a plane-strain test's, in extension too, is the b it develops (load())."""
    ps = bool(s.get("plane_strain"))
    return dict(name=j["name"], mu_r=j["mu_r"], b=1.0 if ext and not ps else float(s.get("b", 0.0)), ext=ext, ps=ps,
                **fields)


def triaxial_extension(r):
    """A b series' row (failure_section, flow_section) of a triaxial extension: b = 1 by its symmetry, not measured
    (a plane-strain extension's b is the one it develops)."""
    return r["ext"] and not r["ps"]


def b_text(r):
    """A b series' row's b column: 1 for a triaxial extension, the setting or (plane strain) the measured b."""
    if triaxial_extension(r):
        return "1 (extension)"
    return f"{r['b']:g}" + ((" (plane strain extension)" if r["ext"] else " (plane strain)") if r["ps"] else "")


def series_path(s):
    """The b series a test belongs to by its lateral control: constant sigma_3 (a plane-strain test's too: its y walls
    hold sigma_3 and its x walls' stress is the b it develops) or constant p'."""
    return "constant_sigma3" if s["stress_path"] == "plane_strain" else s["stress_path"]


def criterion_stresses(phi0, bs, c):
    """Principal stresses (3, len(bs)) on failure criterion c (0: Matsuoka-Nakai, 1: Lade-Duncan) calibrated on the
    compression angle phi0 [deg], sigma_3 = 1, at each b of bs: where flow_section draws each surface's normal flow."""
    phis = np.radians([failure_criteria(phi0, b)[c] for b in bs])
    N = (1 + np.sin(phis)) / (1 - np.sin(phis))
    return np.vstack([N, 1 + np.asarray(bs) * (N - 1), np.ones_like(N)])


def flow_section(mono, window, tol, figs, peak=(0.0, None)):
    """The flow in the deviatoric plane and Rowe's energy ratio of a true-triaxial series (scripts/dilatancy.py's
    deviatoric_flow): per sample and stress path with a drained test at 0 < b, every drained test of the series whose
    series has each axis's strain (eps_x, eps_y: builds since session 67), at its largest obliquity (failure_section's
    row) and at critical state: b, b_eps and the normal flows of Matsuoka-Nakai and Lade-Duncan; the largest dilation
    and Rowe's K across b. figures/deviatoric_flow.png. Empty without such a series."""
    groups = {}
    for j, _, s in mono:
        if j["drainage"] != "drained" or not {"sigma_x", "sigma_y", "sigma_z", "eps_x", "eps_y"} <= set(s):
            continue
        m = s["monotonic"]
        if not np.isfinite(s["eps_x"][m]).all():  # resumed from a checkpoint of a build before them (NaN rows)
            continue
        ext = bool(s["eps_a"][m][-1] < 0)
        sig = np.vstack([s["sigma_x"][m], s["sigma_y"][m], s["sigma_z"][m]])
        f = dilatancy.deviatoric_flow(sig, np.vstack([s["eps_x"][m], s["eps_y"][m], s["eps_a"][m]]), s["eps_v"][m],
                                      ext)
        row = series_row(j, s, ext, f=f, peak=None, cs=None, phi_cs=None, phi_max=None)
        rows_k = peak_rows(s, m, peak[1])  # the largest obliquity as failure_section takes it
        if len(rows_k):
            angles = running_mean(s, rows_k, principal_angle(s), peak[0])
            k = int(np.argmax(angles))
            row["phi_max"] = float(angles[k])
            st = np.array([[running_mean(s, rows_k, s[c], peak[0])[k]] for c in ("sigma_x", "sigma_y", "sigma_z")])
            st = st[f["order"]]
            pos = int(np.searchsorted(np.flatnonzero(m), rows_k[k]))  # the row among the shear's
            row["peak"] = (float(dilatancy.b_of(st)[0]), float(f["b_eps"][pos]),
                           float(dilatancy.normal_b(st, "MN")[0]), float(dilatancy.normal_b(st, "LD")[0]))
        c = critical_state(s, window, *tol)
        if c is not None and c["ok"]:
            ea = -s["eps_a"][m] if ext else s["eps_a"][m]  # along the loading, as critical_state's window
            w = (ea >= ea[-1] - window) & np.isfinite(f["b_eps"])  # the rates stop WINDOW / 2 short of the end
            if w.any():
                row["cs"] = tuple(float(np.mean(f[key][w])) for key in ("b", "b_eps", "b_mn", "b_ld"))
                row["phi_cs"] = float(np.mean(principal_angle(s)[m][w]))  # the walls' angle, as the table's stresses
        groups.setdefault((j["sample"], series_path(s)), []).append(row)
    series = {k: sorted(g, key=lambda r: (r["b"], r["ext"])) for k, g in groups.items()
              if any(0 < r["b"] < 1 and not triaxial_extension(r) for r in g)}
    if not series:
        return []
    rows, dev, spreads, ps_lines = [], {(st, c): [] for st in ("peak", "cs") for c in range(3)}, [], []
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    bs = np.linspace(0, 1, 51)
    ax[0].plot(bs, bs, "--", color="0.5", lw=0.8, label="radial (b_eps = b)")
    drawn = False
    for (sample, path), g in sorted(series.items()):
        at = " at constant p'" if path == "constant_p" else ""
        color = None  # one colour a series: its peaks open, its critical states filled
        for i, state in enumerate(("peak", "cs")):
            pts = [r[state] for r in g if r[state] is not None]
            lab = f"mu_r = {g[0]['mu_r']:g} ({sample}){at}, " + ("critical state" if i else "peak")
            line = ax[0].plot([p[0] for p in pts], [p[1] for p in pts], "o" if i else "^",
                              mfc="none" if i == 0 else None, color=color, label=lab)
            color = line[0].get_color()
            ref = next((r for r in g if r["b"] == 0 and not r["ext"] and r[state] is not None), None)
            if i == 1 and ref is not None and not drawn:  # each surface's normal flow, calibrated on a b = 0 test
                phi0 = ref["phi_cs"]
                if phi0 is not None:
                    for cc, (crit, ls) in enumerate((("MN", "-"), ("LD", ":"))):
                        ax[0].plot(bs, dilatancy.normal_b(criterion_stresses(phi0, bs, cc), crit), ls,
                                   color=line[0].get_color(), lw=1,
                                   label=f"{'Matsuoka-Nakai' if crit == 'MN' else 'Lade-Duncan'} normal "
                                         f"(phi_cs {phi0:.1f}°)")
                    drawn = True
        Ks = []
        for r in g:
            f = r["f"]
            k0 = f["turn"]
            pl = ax[1].plot(f["w_out"][k0:], f["w_in"][k0:], ".", ms=2)
            if math.isfinite(f["K"]):
                # From the origin, as fitted: an extension's W_out / sigma_3 is 1 on every row (only the axis of
                # sigma_3 lengthens, by the unit loading strain), so a line over the rows' own range was a point.
                xs = np.array([0.0, np.nanmax(f["w_out"][k0:])])
                ax[1].plot(xs, f["K"] * xs, "-", lw=1, color=pl[0].get_color(),
                           label=f"{r['name']}: K {f['K']:.2f}")
                Ks.append(f["phi_f"])
            cells = []
            for state in ("peak", "cs"):
                v = r[state]
                cells.append("- | - | - | -" if v is None else
                             f"{v[0]:.2f} | {number_text(v[1], '.2f')} | {v[2]:.2f} | {v[3]:.2f}")
                if v is not None and 0 < r["b"] < 1 and not triaxial_extension(r) and math.isfinite(v[1]):
                    for cc, pred in enumerate((v[0], v[2], v[3])):
                        dev[(state, cc)].append(v[1] - pred)
            dil = (f"{f['neg_d_max']:.3f} ± {f['se']:.3f} ({100 * abs(f['eps_max']):.1f})"
                   if math.isfinite(f["neg_d_max"]) else "-")
            rows.append(f"| {r['name']}{at} | {r['mu_r']:g} | {b_text(r)} | {dil} | {cells[0]} | {cells[1]} | "
                        f"{number_text(f['K'], '.3f')} | {number_text(f['phi_f'], '.1f')} "
                        f"({number_text(f['rms'], '.3f')}) |")
        for r in g:  # plane strain: its dilation angle, and Bolton's relation where it reached critical state
            if r["ps"]:
                psi, bolton = r["f"]["psi_ps"], None
                if math.isfinite(psi) and psi > 0 and r["phi_cs"] is not None and r.get("phi_max") is not None:
                    bolton = (r["phi_max"] - r["phi_cs"]) / psi
                ps_lines.append(f"{r['name']}{at}: psi_max {number_text(psi, '.1f')}°, (phi'_max - phi'_cs) / psi_max "
                                f"{number_text(bolton, '.2f')}")
        if len(Ks) > 1:
            spreads.append(f"mu_r = {g[0]['mu_r']:g} ({sample}){at}: phi_f {min(Ks):.1f} to {max(Ks):.1f}° over "
                           f"{len(Ks)} tests")
    ax[0].set(xlabel="b (wall stresses)", ylabel="b_eps of the strain increments",
              title="flow in the deviatoric plane: ^ largest obliquity, o critical state")
    ax[1].set(xlabel="W_out / sigma_3 (axes lengthening)", ylabel="W_in / sigma_3 (axes shortening)",
              title="Rowe's energy ratio W_in = K W_out, from the largest contraction on")
    legend(ax[0], fontsize=6)
    legend(ax[1], fontsize=6)
    for a in ax:
        a.grid(alpha=0.3)
    save(fig, figs, "deviatoric_flow")

    def rms(v):
        return f"{math.sqrt(np.mean(np.square(v))):.3f} ({len(v)})" if v else "-"
    members = [r for g in series.values() for r in g if 0 < r["b"] < 1 and not triaxial_extension(r)]
    kinds = (["true triaxial"] if any(not r["ps"] for r in members) else []) + (
        ["plane strain"] if any(r["ps"] for r in members) else [])
    return [f"## Flow in the deviatoric plane ({' and '.join(kinds)})", "",
            "The drained tests of each true-triaxial series, from each axis's strain (series eps_x, eps_y, eps_a) and "
            "the walls' principal stresses. Strain increments are natural (d lambda = -dL/L per axis, adding up to the "
            "volume's at any strain), per unit strain along the loading, each the slope of a line through the rows "
            f"within {dilatancy.WINDOW / 2:g} of it either side. b_eps = (d lambda_2 - d lambda_3) / (d lambda_1 - d "
            "lambda_3), the increments of the axes of sigma_1, sigma_2 and sigma_3 (the order of each test's mean "
            "stresses), is to the strain increment what b is to the stress: b_eps = b is radial flow (the strain "
            "increment's deviator along the stress's: a circular plastic potential in the deviatoric plane, "
            "Drucker-Prager's); MN and LD give the b_eps of flow normal to Matsuoka-Nakai's and Lade-Duncan's surfaces "
            "through the measured stresses (associated in the deviatoric plane). At the largest obliquity (the row of "
            "the failure criteria section; its b and the normals from the stresses averaged as its angle is) and over "
            "the critical-state window (where the stress is steady, so the total increments are the plastic ones). "
            "(-d)_max is the largest dilation rate -d lambda_v / d lambda_l (natural strains; the compression "
            "section's is engineering) with its standard error and strain. Rowe's stress-dilatancy as an energy "
            "ratio: the work of the stresses whose axes shorten over that done against those whose axes lengthen, "
            "W_in / W_out = K = tan^2(45 + phi_f / 2), fitted through the origin from the largest contraction on (Rowe "
            "1962; at b = 0 his triaxial relation, in extension Rowe, Barden & Lee's, in plane strain his plane-strain "
            "one), with the rms of the relative residuals: Rowe's theory claims one K, whatever b. "
            "Figure: `figures/deviatoric_flow.png`.", "",
            "| test | mu_r | b | (-d)_max ± se (eps_a %) | b at phi'_max | b_eps | MN | LD | b at c.s. | b_eps | MN "
            "| LD | Rowe K | phi_f [°] (rms) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", *rows, "",
            "Root-mean-square of the measured b_eps minus each flow's over the tests at 0 < b < 1 (count):", "",
            "| state | radial | Matsuoka-Nakai normal | Lade-Duncan normal |", "|---|---|---|---|",
            *(f"| {lab} | " + " | ".join(rms(dev[(st, c)]) for c in range(3)) + " |"
              for st, lab in (("peak", "largest obliquity"), ("cs", "critical state"))), "",
            *([("Rowe's phi_f across b: " + "; ".join(spreads) + "."), ""] if spreads else []),
            *([("Plane strain (d lambda_2 = 0), the dilation angle of its Mohr circle of strain increments at the "
                "largest dilation, sin psi = -(d lambda_1 + d lambda_3) / (d lambda_1 - d lambda_3) ('-' within "
                f"{dilatancy.SIGNIFICANT:g} standard errors of 0), and Bolton's (1986) plane-strain relation "
                "phi'_max - phi'_cs = 0.8 psi_max, measured as the ratio ('-' without the test's own critical state): "
                + "; ".join(ps_lines) + "."), ""] if ps_lines else [])]


# critical_state's b of a plane-strain test: the critical-state lines group the plane-strain tests of a mu_r as one
# loading direction, whatever b each develops (their b ~0.3 differs in the second decimal from test to test)
PLANE_STRAIN = -1.0


def direction_text(ext, bv, sep=", "):
    """A critical-state group's loading direction (csl_groups' ext and b): compression or extension, the true-triaxial
    b, or plane strain."""
    if bv == PLANE_STRAIN:
        return ("extension" if ext else "compression") + f"{sep}plane strain"
    return ("extension" if ext else "compression") + (f"{sep}b = {bv:g}" if bv > 0 else "")


def friction_angle(M, ext):
    """The Mohr-Coulomb friction angle [deg] of a triaxial state at M = |q/p'|: sin(phi) = 3 M / (6 + M) in
    compression, 3 M / (6 - M) in extension (where the axial stress is the minor principal one)."""
    return math.degrees(math.asin(min(1.0, 3 * M / ((6 - M) if ext else (6 + M)))))


def rate_text(rate, sep):
    """A critical-state line's rate in its label: summary.json's axial_strain_rate (0: a run of a build before it)."""
    return sep + (f"{rate:g}/s" if rate > 0 else "rate not recorded")


def fit(x, y):
    """Least-squares line with standard errors (needs >= 3 points)."""
    A = np.vstack([x, np.ones_like(x)]).T
    coef, res, *_ = np.linalg.lstsq(A, y, rcond=None)
    n = len(x)
    s2 = float(np.sum((y - A @ coef) ** 2)) / (n - 2)
    cov = s2 * np.linalg.inv(A.T @ A)
    return coef[0], coef[1], math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])


# A critical-state line needs critical states at three pressures at least this far apart (relative): replicates of one
# test (seeds: p'_c within ~1 % on 5 000 spheres, configs/seed-study.yaml) or one p'_0 at several rates are one level,
# and a line through them is their scatter (the seed study's slope came out positive, 1.5e-4 ± 1.9e-3 per kPa).
CSL_LEVEL_GAP = 0.1


def pressure_levels(p):
    """How many levels the pressures p make: sorted, a value more than CSL_LEVEL_GAP above the last level's first
    starts a new one."""
    levels, first = 0, None
    for x in sorted(p):
        if first is None or x > first * (1 + CSL_LEVEL_GAP):
            levels, first = levels + 1, x
    return levels


def csl_groups(states):
    """The critical states (run, state) of csl() as its lines are fitted: per (mu_r, extension, b, rate)."""
    groups = {}
    for _, cs in states:
        groups.setdefault((cs["mu_r"], cs["ext"], cs["b"], cs["rate"]), []).append(cs)
    return groups


def line_at(x, y, x0):
    """The least-squares line through (x, y) (three points or more) at x0, with the standard error of the line there
    (the fitted mean's, s sqrt(1/n + (x0 - mean x)^2 / Sxx): the line's own uncertainty, not a new point's scatter)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    slope, icpt, _, _ = fit(x, y)
    s2 = float(np.sum((y - icpt - slope * x) ** 2)) / (len(x) - 2)
    sxx = float(np.sum((x - x.mean()) ** 2))
    return icpt + slope * x0, math.sqrt(s2 * (1 / len(x) + (x0 - x.mean()) ** 2 / sxx))


def directions_line(groups, several_rates, draw=None):
    """Whether the loading directions' critical states lie on one line (csl_groups' groups; one_line_rows): per mu_r
    (and rate) with two directions or more (compression, extension, a true-triaxial b), e_c = a + b p' through all
    their critical states and each direction's mean offset from it: a blank line, the text and the table. Empty where
    no mu_r qualifies. draw: as one_line_rows'."""
    by_mu = {}
    for (mur, ext, bv, rate), g in sorted(groups.items()):
        label = f"mu_r {mur:g}" + (rate_text(rate, ", ") if several_rates else "")
        member = direction_text(ext, bv)
        by_mu.setdefault((mur, rate), (label, []))[1].extend((member, c["p"] / 1e3, c["e"]) for c in g)
    rows = one_line_rows({label: st for _, (label, st) in sorted(by_mu.items())}, draw)
    if not rows:
        return []
    return ["", "One critical-state line through the critical states of every loading direction of a mu_r (e_c = a + "
            "b p', as the critical-state lines are fitted per direction), with each direction's mean offset from it: "
            "the stress "
            "ratio at critical state depends on the direction (M_c, M_e, the Lode angle of a b > 0), the void ratio "
            "need not (Been, Jefferies & Hachey 1991 found one line in e - p' for the compressions and extensions of "
            "a sand); a direction more than two standard errors off it (the scatter about the line once each "
            "direction's mean offset is taken out, over the root of its states) ends at another density.", "",
            "| group | the line through every direction's critical states | direction | states | mean offset in e | "
            "standard error | |", "|---|---|---|---|---|---|---|", *rows]


def csl(runs, out, window, tol=(0.05, 0.05, 0.005), quiet=False):
    states = []
    for run, s in runs:
        cs = critical_state(s, window, *tol)
        if cs is None:
            print(f"{run}: no triaxial (monotonic) shear stage")
        elif not cs["ok"]:
            print(f"{run}: not at critical state ({cs['why']}); not fitted")
        else:
            states.append((run, cs))
    # per mu_r and direction: compression and extension reach the critical state at other stress ratios (M_c, M_e) and
    # fabric anisotropies (a_c is signed against the stress deviator, SPEC §7, so > 0 in both: its size differs), so
    # their lines are fitted apart; so are the rates of a rate series (the same p'_0 at several I: a line through them
    # would be a rate effect, or singular), named where the runs have more than one
    groups = csl_groups(states)
    several_rates = len({k[3] for k in groups}) > 1
    lines = ["| mu_r | direction | n | e_c = a + b p' [p' in kPa] | e_c = e_Γ - λ ln(p'/1 kPa) | rms misfit of e_c: "
             "linear, ln | interior e_c = a + b p' | a_c = c + d ln(p'/1 kPa) | M = abs(q/p') (phi_cs) | largest I | "
             "M walls, less drag, interior |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    fitted = False
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for (mur, ext, bv, rate), g in sorted(groups.items()):
        p = np.array([c["p"] for c in g]) / 1e3
        e = np.array([c["e"] for c in g])
        ac = np.array([c["a_c"] for c in g])
        M = np.array([c["M"] for c in g])
        direction = direction_text(ext, bv) + (rate_text(rate, ", ") if several_rates else "")
        # the principal stresses' angle where M's axisymmetric relations do not hold (b > 0, plane strain)
        phi = float(np.mean([c["phi"] for c in g])) if bv != 0 else friction_angle(M.mean(), ext)
        m_txt = f"{M.mean():.3f}" + (f" ± {M.std(ddof=1):.3f}" if len(M) > 1 else "") + f" ({phi:.1f}°)"
        Is = [c["I"] for c in g if c.get("I") is not None]
        m_txt += " | " + (f"{max(Is):.1e}" if len(Is) == len(g) else "-")  # a group with an unmeasured I: unknown
        # M of the walls' stress, of the walls' less the damping's drag and of the interior's (STRESS_MEASURES_TEXT),
        # where every state measured it
        m_txt += " | " + ", ".join(
            f"{np.mean([c[k] for c in g]):.3f}" if all(c.get(k) is not None for c in g) else "-"
            for k in ("M_walls", "M_less_drag", "M_inner"))
        tag = (f"mu_r = {mur:g}" + (" extension" if ext else "")
               + (" plane strain" if bv == PLANE_STRAIN else f" b = {bv:g}" if bv > 0 else "")
               + (rate_text(rate, " ") if several_rates else ""))
        (ln,) = ax[0].plot(p, e, "s" if ext else "o", label=tag)
        ax[1].plot(np.log(p), ac, "s" if ext else "o", color=ln.get_color(), label=tag)
        if pressure_levels(p) >= 3:
            b, a, sb, sa = fit(p, e)
            # Schofield & Wroth's form of the same states, e_c = e_Gamma - lambda ln p' (their Gamma is the specific
            # volume 1 + e_Gamma at 1 kPa): the lambda a reader compares with the isotropic compression's
            mlam, eg, slam, seg = fit(np.log(p), e)
            misfit = [math.sqrt(float(np.sum((e - y) ** 2)) / (len(e) - 2)) for y in (a + b * p, eg + mlam * np.log(p))]
            d, c, sd, sc = fit(np.log(p), ac)
            xs = np.linspace(p.min(), p.max(), 20)
            ax[0].plot(xs, a + b * xs, "-", color=ln.get_color())
            ax[0].plot(xs, eg + mlam * np.log(xs), ":", color=ln.get_color())
            fitted = True
            ax[1].plot(np.log(xs), c + d * np.log(xs), "-", color=ln.get_color())
            # The interior's line (series e_inner, without the looser layer along the walls: the material's rather
            # than a walled specimen's), where every state measured it; dashed, its states hollow
            ei = [cs.get("e_inner") for cs in g]
            inner = "-"
            if all(v is not None for v in ei):
                bi, ai, sbi, sai = fit(p, np.array(ei))
                ax[0].plot(p, ei, "s" if ext else "o", mfc="none", color=ln.get_color())
                ax[0].plot(xs, ai + bi * xs, "--", color=ln.get_color())
                inner = f"a = {ai:.4f} ± {sai:.4f}, b = {bi:.3e} ± {sbi:.1e}"
            lines.append(f"| {mur:g} | {direction} | {len(g)} | a = {a:.4f} ± {sa:.4f}, b = {b:.3e} ± {sb:.1e} | "
                         f"e_Γ = {eg:.4f} ± {seg:.4f}, λ = {-mlam:.4f} ± {slam:.4f} | "
                         f"{misfit[0]:.4f}, {misfit[1]:.4f} | {inner} | "
                         f"c = {c:.4f} ± {sc:.4f}, d = {d:.4f} ± {sd:.4f} | {m_txt} |")
        else:
            lines.append(f"| {mur:g} | {direction} | {len(g)} | fewer than 3 critical states {100 * CSL_LEVEL_GAP:g} % "
                         "apart in p'_c: no fit | | | | | "
                         f"{m_txt} |")

    def draw_across(label, a, b, p):  # the line through every direction's states (directions_line), grey
        xs = np.linspace(p.min(), p.max(), 20)
        ax[0].plot(xs, a + b * xs, "-.", color="0.4", lw=1, label=f"{label}, every direction")
    across = directions_line(groups, several_rates, draw_across)
    ax[0].set(xlabel="p'_c [kPa]", ylabel="e_c",
              title="critical-state line e_c - p' (dotted: in ln p'; hollow, dashed: interior)")
    ax[1].set(xlabel="ln p'_c [kPa]", ylabel="a_c at critical state", title="a_c - ln p'")
    for a_ in ax:
        a_.grid(alpha=0.3)
        legend(a_, fontsize=8)
    save(fig, out, "csl")
    if not groups:
        lines.append(f"| – | – | 0 | no run at critical state: nothing to fit ({len(runs)} examined) | | | | | | | |")
    if fitted:
        lines += ["", "e_Γ, λ: the same critical states on Schofield & Wroth's (1968) e_c = e_Γ - λ ln(p'/1 kPa) "
                  "(their Γ is the specific volume 1 + e_Γ), whose λ "
                  "compares with the isotropic compression index (the "
                  "compression section). The rms misfit of e_c is each line's residual standard error (both have two "
                  "parameters): the smaller describes these states better over their range of p'_c (dotted in the "
                  "figure: the ln line). The state parameter is measured from the linear line (SPEC §7)."]
    lines += across
    note = inertial_note([c for _, c in states])
    text = "\n".join(lines + (["", note] if note else []))
    if not quiet:
        print(text)
    figures_done()  # csl.png first, as when the figures were written in turn
    write_text_atomically(os.path.join(out, "csl.md"), text + "\n")
    return text, states


def size_tests(out, runs):
    """The size-class section's tests of a study: (name, run directory, its sample job's config.yaml, whose
    sample.grading gives the classes; None for a job without a sample job)."""
    return [(j["name"], d, os.path.join(out, "jobs", j["sample"], "run", "config.yaml") if j.get("sample") else None)
            for j, d, _ in runs]


# The stage key whose values are a response envelope's directions (StageConfig::stress_direction): a study with a stage
# axis over it is a probe study, whose report is the envelopes (probe_report), not a section per direction.
PROBE_KEY = "stress_direction"


def rendulic_angle(x, y):
    """The direction of (x, y) = (sqrt2 d_r, d_a) in the Rendulic plane, in degrees in [0, 360): 90 axial loading."""
    return math.degrees(math.atan2(y, x)) % 360.0


def probe_increments(run_dir):
    """A stress probe's increments: the run's last stage (a linear path), summary.json's dsigma_rendulic (sqrt2 dsigma_r,
    dsigma_a) from the stresses it started at and deps_rendulic (sqrt2 deps_r, deps_a) from its start, at its last series
    row (the run's arithmetic, Laboratory::probe_increments). The drag: the change of the local damping's drag (series
    p_drag, q_drag) from the stage's first row to its last, whose share of the walls' increment the report gives (the
    walls' stress includes it). None where the run's last stage is not a linear path or has no row."""
    with open(os.path.join(run_dir, "summary.json")) as f:
        st = json.load(f)["stages"][-1]
    if st.get("stress_path") != "linear" or st.get("dsigma_rendulic") is None:
        return None
    s = load(run_dir)
    rows = np.flatnonzero(s["stage"] == st["name"])
    if len(rows) == 0:
        return None
    k0, k = rows[0], rows[-1]
    p0, q0 = st["p_0"], st["q_0"]
    ds, de = tuple(st["dsigma_rendulic"]), tuple(st["deps_rendulic"])
    dsr, dsa, er, ea = ds[0] / math.sqrt(2), ds[1], de[0] / math.sqrt(2), de[1]
    nds, nde = math.hypot(*ds), math.hypot(*de)
    drag = None
    if "p_drag" in s and "q_drag" in s:
        dp, dq = s["p_drag"][k] - s["p_drag"][k0], s["q_drag"][k] - s["q_drag"][k0]
        drag = math.hypot(math.sqrt(2) * (dp - dq / 3), dp + 2 * dq / 3) / max(nds, 1e-300)
    return {"theta": st.get("stress_direction"), "slope": st.get("lateral_slope"), "p0": p0, "q0": q0,
            "e": s["e"][rows[0]], "dsa": dsa, "dsr": dsr, "dea": ea, "der": er, "ds": ds, "de": de,
            "theta_s": rendulic_angle(*ds), "theta_e": rendulic_angle(*de),
            "modulus": nds / nde if nde > 0 else float("inf"),
            "work": (ds[0] * de[0] + ds[1] * de[1]) / (nds * nde) if nds > 0 and nde > 0 else float("nan"),
            "drag": drag}


# The response envelope's incremental law (probe_fit): a linear part and one plastic mechanism, Rendulic coordinates.
ENVELOPE_LINEAR_TOL = 0.05  # an elastic (linear) fit within this rms share of the mean |deps|: incrementally linear


def rendulic_to_pq():
    """A, B with (p, q) = A (sqrt2 s_r, s_a) and (eps_v, eps_q) = B (sqrt2 e_r, e_a) (eps_q = 2/3 (e_a - e_r))."""
    r2 = math.sqrt(2)
    return np.array([[r2 / 3, 1 / 3], [-1 / r2, 1.0]]), np.array([[r2, 1.0], [-r2 / 3, 2 / 3]])


def elastic_constants(C):
    """K, G [Pa] and the coupling dp -> deps_q over dp -> deps_v (0 for isotropic elasticity) of a compliance C in
    Rendulic coordinates: (deps_v, deps_q) = D (dp, dq), D = B C A^-1, K = 1/D_pp, G = 1/(3 D_qq)."""
    A, B = rendulic_to_pq()
    D = B @ C @ np.linalg.inv(A)
    coupling = D[1, 0] / D[0, 0]
    return 1 / D[0, 0], 1 / (3 * D[1, 1]), coupling if abs(coupling) >= 5e-4 else 0.0  # printed to 3 digits: no -0.000


def probe_fit(ds, de):
    """Least squares of the probes' responses de (n x 2) to their increments ds (n x 2), Rendulic coordinates: a
    symmetric linear compliance C (elasticity), and C plus one plastic mechanism h <n . ds> m (n the loading direction,
    m the flow direction, unit vectors at angles a_n, a_m; h >= 0, 1/h the plastic modulus): the elastoplastic law of
    one yield surface (Darve 1990's incrementally bilinear class), non-associated where m != n. Returns the linear fit
    (C, rms) and, where the linear fit misses by more than ENVELOPE_LINEAR_TOL of the mean |de|, the elastoplastic one
    (C, a_n, a_m, h, rms); rms relative to the mean |de|. Several starts of a_n (every 30 deg), the best kept."""
    from scipy.optimize import least_squares

    ds, de = np.asarray(ds, float), np.asarray(de, float)
    scale = np.mean(np.hypot(de[:, 0], de[:, 1]))
    # linear: de = C ds with C symmetric (c11, c12, c22): linear least squares
    M = np.zeros((2 * len(ds), 3))
    M[0::2, 0], M[0::2, 1] = ds[:, 0], ds[:, 1]
    M[1::2, 1], M[1::2, 2] = ds[:, 0], ds[:, 1]
    c, *_ = np.linalg.lstsq(M, de.reshape(-1), rcond=None)
    C_lin = np.array([[c[0], c[1]], [c[1], c[2]]])
    rms_lin = math.sqrt(np.mean(np.sum((ds @ C_lin.T - de) ** 2, axis=1))) / scale
    out = {"linear": (C_lin, rms_lin), "plastic": None}
    if rms_lin <= ENVELOPE_LINEAR_TOL:
        return out
    c_scale = np.max(np.abs(c))

    def model(x):
        C = np.array([[x[0], x[1]], [x[1], x[2]]]) * c_scale
        n = np.array([math.cos(x[3]), math.sin(x[3])])
        m = np.array([math.cos(x[4]), math.sin(x[4])])
        load = np.maximum(ds @ n, 0.0)
        return ds @ C.T + (x[5] * c_scale) * load[:, None] * m[None, :]

    best = None
    for a0 in np.radians(np.arange(0, 360, 30)):
        # start: the softest probes' response direction for m, the linear fit for C, h from the largest excess
        x0 = [c[0] / c_scale, c[1] / c_scale, c[2] / c_scale, a0, a0, 1.0]
        r = least_squares(lambda x: ((model(x) - de) / scale).reshape(-1), x0,
                          bounds=([-np.inf] * 5 + [0.0], [np.inf] * 6), x_scale="jac", max_nfev=4000)
        if best is None or r.cost < best.cost:
            best = r
    x = best.x
    C = np.array([[x[0], x[1]], [x[1], x[2]]]) * c_scale
    rms = math.sqrt(np.mean(np.sum((model(x) - de) ** 2, axis=1))) / scale
    out["plastic"] = (C, math.degrees(x[3]) % 360, math.degrees(x[4]) % 360, x[5] * c_scale, rms)
    return out


PLASTIC_FIT_MIN_PROBES = 7  # the elastoplastic law has 6 parameters: more probes than that, 2 equations each
# A plastic mechanism's fit is given where it misses by at most this share of the mean |deps|; beyond, the envelope is
# not one yield surface's and its n, m and H would describe nothing (configs/probe-study.yaml's: 46-78 %)
PLASTIC_FIT_TOL = 0.2


def probe_fit_text(probes):
    """The report's lines on a state's incremental law (probe_fit), the flow direction to draw (None: none) and whether
    the state is incrementally linear (its envelope an ellipse: no loading sector to speak of)."""
    ds = [c["ds"] for _, c in probes]
    de = [c["de"] for _, c in probes]
    f = probe_fit(ds, de) if len(probes) >= 3 else None
    if f is None:
        return "Too few probes (3 or more) for an incremental law.", None, False
    C, rms = f["linear"]
    K, G, cpl = elastic_constants(C)
    text = (f"Incremental law (least squares over the {len(probes)} probes): a linear one, deps = C dsigma (elasticity, "
            f"C symmetric), misses by {100 * rms:.1f} % of the mean |deps| (K = {K / 1e6:.1f} MPa, G = {G / 1e6:.1f} "
            f"MPa, coupling {cpl:+.3f})")
    if f["plastic"] is None:
        return text + f": within {100 * ENVELOPE_LINEAR_TOL:g} %, incrementally linear (elastic).", None, True
    if len(probes) < PLASTIC_FIT_MIN_PROBES:
        return text + f"; {PLASTIC_FIT_MIN_PROBES} probes or more would fit a plastic mechanism.", None, False
    Cp, an, am, h, rms_p = f["plastic"]
    if h > 0 and rms_p > PLASTIC_FIT_TOL:
        return (text + f"; with one plastic mechanism, deps = C dsigma + <n . dsigma> m / H, it still misses by "
                f"{100 * rms_p:.1f} % (more than {100 * PLASTIC_FIT_TOL:g} %): the envelope is not one yield surface's "
                "(its plastic part does not grow as <n . dsigma> across the loading half), and no such law is given."), None, False
    Kp, Gp, cplp = elastic_constants(Cp)
    gap = (am - an + 180) % 360 - 180
    return (text + f"; with one plastic mechanism, deps = C dsigma + <n . dsigma> m / H, it fits to {100 * rms_p:.1f} %: "
            f"K = {Kp / 1e6:.1f} MPa, G = {Gp / 1e6:.1f} MPa, coupling {cplp:+.3f}, loading direction n at "
            f"{an:.1f}°, flow direction m at {am:.1f}° ({'associated' if abs(gap) < 0.5 else f'non-associated by {gap:+.1f}°'}"
            f"), plastic modulus H = {1 / h / 1e6:.2f} MPa." if h > 0 else
            text + f"; one plastic mechanism does no better ({100 * rms_p:.1f} %)."), (am if h > 0 else None), False


def soft_sectors(probes):
    """The loading sectors of an envelope: the runs of consecutive probes (by direction, around the circle) whose
    |dsigma|/|deps| lies below the geometric mean of the stiffest's and the softest's, as (first, last) theta_sigma.
    Plastic loading softens a half-plane's probes by an order of magnitude or more; the sector is that half, its
    middle the yield surface's normal to within the probes' spacing (what one mechanism's n would be, fitted or not)."""
    th = [c["theta_s"] for _, c in probes]
    mod = [c["modulus"] for _, c in probes]
    order = sorted(range(len(th)), key=lambda i: th[i])
    cut = math.sqrt(max(mod) * min(mod))
    soft = [mod[i] < cut for i in order]
    if all(soft) or not any(soft):
        return []
    start = soft.index(False)  # walk the circle from a stiff probe, so no run is split at the wrap
    runs, cur = [], None
    for k in range(1, len(order) + 1):
        i = (start + k) % len(order)
        if soft[i]:
            cur = [order[i], order[i]] if cur is None else [cur[0], order[i]]
        elif cur is not None:
            runs.append((th[cur[0]], th[cur[1]]))
            cur = None
    return runs


def probe_report(out, idx):
    """Report of a probe study (a stage axis over PROBE_KEY): per state the probes start from (the jobs that differ in
    the probe's direction alone), the response envelope: each probe's stress increment and strain response in the
    Rendulic plane, the stiffness along it, the second-order work, and figures/response_envelopes.png."""
    def state_key(j):
        sk = tuple(sorted((k, v) for k, v in j.get("stage_keys", {}).items() if k.rsplit(".", 1)[-1] != PROBE_KEY))
        # the sizes: a grading axis's curve, or a sample_file axis's file, by name
        sizes = (f"grading {j['grading']}" if j.get("grading") else
                 f"sample file {j['specimen']}" if j.get("specimen") else "")
        return (j.get("E", 0), sk, j["mu_r"], j.get("p0", 0), j.get("e0", 0), j.get("seed"), j.get("count"), sizes)

    states, missing = {}, []
    for j in idx["jobs"]:
        d = os.path.join(out, j["dir"])
        inc = None
        if os.path.isfile(os.path.join(out, "jobs", j["name"], "done")) and os.path.isfile(os.path.join(d, "series.csv")):
            inc = probe_increments(d)
        if inc is None:
            missing.append(j["name"])
            continue
        states.setdefault(state_key(j), []).append((j, inc))
    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    several = len(states) > 1
    lines = [f"# Study report: {idx['study']}", "",
             f"{sum(len(v) for v in states.values())} stress probes from {len(states)} state(s)"
             + (f"; not (yet) finished, or without a probe's increments in its summary.json (a build before them): "
                f"{', '.join(missing)}" if missing else "") + ". Figure: "
             "`figures/response_envelopes.png`.", "",
             "## Response envelopes", "",
             "Each probe is a drained stage on a linear stress path (stress_direction: theta, the direction of (sqrt2 "
             "dsigma_r, dsigma_a) in the Rendulic plane, counterclockwise from the sqrt2 sigma_r axis: 90 axial loading at "
             "constant sigma_3, 270 axial unloading, 35.26 isotropic loading, 125.26 constant p'), ended at a stress "
             "increment |sigma - sigma_0|, from the state the base's stages before it leave (the same for every probe "
             "of a state: they differ in the probe alone). Increments are of the walls' stresses from the probe's start "
             "(summary.json p_0, q_0: sigma_a,0 = p_0 + 2 q_0/3, sigma_r,0 = p_0 - q_0/3) to its last row, strains from "
             "its start (eps_r from H and V). theta_sigma is the direction the probe reached (the servo's lag turns it "
             "from theta), theta_eps the strain response's, (sqrt2 deps_r, deps_a) (compression positive); "
             "|dsigma|/|deps| the stiffness along the probe; d2W = dsigma : deps / (|dsigma| |deps|), the normalised "
             "second-order work, the cosine between the two: <= 0 is a direction in which the state is unstable "
             "(Hill's condition; Darve & Laouafa 2000, Nicot et al. 2007); drag the share of |dsigma| that the local "
             "damping's drag changed by over the probe (series p_drag, q_drag): the walls' increment overstates the "
             "material's by up to it. An elastic state's envelope is an ellipse about the origin; plastic loading "
             "stretches the half that loads it (incremental non-linearity: Darve 1990). Each state's incremental law "
             "is fitted to its probes: first linear (deps = C dsigma, C symmetric: drained elasticity, given as K, G "
             "and the coupling of dp into deps_q, 0 where isotropic), then, where that misses by more than "
             f"{100 * ENVELOPE_LINEAR_TOL:g} % of the mean |deps|, with one plastic mechanism, deps = C dsigma + "
             "<n . dsigma> m / H, the elastoplastic law of one yield surface: its loading direction n (the yield "
             "surface's normal), flow direction m (dashed in the figure) and plastic modulus H; m != n is a "
             "non-associated flow rule (Calvetti et al. 2003 found it so in their envelopes).", ""]
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    ax[1].remove()
    ax[1] = fig.add_subplot(1, 2, 2, projection="polar")
    colors = plt.cm.viridis(np.linspace(0, 0.9, max(1, len(states))))
    for n, (key, probes) in enumerate(sorted(states.items(), key=lambda kv: str(kv[0]))):
        probes.sort(key=lambda t: t[1]["theta"] if t[1]["theta"] is not None else t[1]["theta_s"])
        E, sk, mu_r, p0, e0, seed, count, sizes = key
        first = probes[0][1]
        name = (", ".join([f"stages.{k} = {v:g}" for k, v in sk] + [f"mu_r = {mu_r:g}"]
                          + ([f"E = {E:g} Pa"] if E else []) + ([f"p0 = {p0 / 1e3:g} kPa"] if p0 else [])
                          + ([f"e0 = {e0:g}"] if e0 else []) + ([sizes] if sizes else [])))
        eta = first["q0"] / first["p0"] if first["p0"] else float("nan")
        rows = []
        for j, c in probes:
            rows.append(f"| {j['name']} | {number_text(c['theta'], '.1f')} | {number_text(c['slope'], '.3f')} | "
                        f"{c['theta_s']:.1f} | {c['dsa'] / 1e3:.2f} | {math.sqrt(2) * c['dsr'] / 1e3:.2f} | "
                        f"{1e4 * c['dea']:.3f} | {1e4 * math.sqrt(2) * c['der']:.3f} | {c['theta_e']:.1f} | "
                        f"{c['modulus'] / 1e6:.1f} | {c['work']:+.3f} | "
                        f"{number_text(100 * c['drag'] if c['drag'] is not None else None, '.1f')} |")
        mods = [(c["modulus"], c["theta_s"], c["theta_e"], c["dea"], c["der"]) for _, c in probes]
        hi, lo = max(mods), min(mods)
        # the softest probe's response: the flow direction, and its dilatancy deps_v / deps_q (< 0 dilates)
        dev, deq = lo[3] + 2 * lo[4], 2 / 3 * (lo[3] - lo[4])
        unstable = [f"{c['theta_s']:.1f}" for _, c in probes if not c["work"] > 0]
        lines += [f"### {name}" if several else f"### State: {name}", "",
                  f"The probes start at p'_0 = {first['p0'] / 1e3:.2f} kPa, q_0 = {first['q0'] / 1e3:.2f} kPa (q/p' "
                  f"{eta:.3f}), e = {first['e']:.4f} (the first probe's; every probe of the state starts there).", "",
                  "| test | theta [°] | lateral_slope | theta_sigma [°] | dsigma_a [kPa] | sqrt2 dsigma_r [kPa] | "
                  "deps_a [1e-4] | sqrt2 deps_r [1e-4] | theta_eps [°] | |dsigma|/|deps| [MPa] | d2W | drag [%] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|", *rows, "",
                  f"Stiffest along theta_sigma = {hi[1]:.1f}° ({hi[0] / 1e6:.1f} MPa), softest along {lo[1]:.1f}° "
                  f"({lo[0] / 1e6:.1f} MPa): {hi[0] / lo[0]:.1f}x; the softest strains along theta_eps = {lo[2]:.1f}° "
                  f"(deps_v/deps_q = {number_text(dev / deq if deq else None, '+.3f')}). "
                  + (f"d2W <= 0 along {', '.join(unstable)}°: the state is unstable there (a stress probe in such a "
                     "direction is not controllable: the strain runs on)." if unstable
                     else "d2W > 0 in every direction probed: stable (Hill's condition) along each."), ""]
        law, flow, linear = probe_fit_text(probes)
        sectors = [] if linear else soft_sectors(probes)
        if sectors:
            law += (" Soft sector(s), |dsigma|/|deps| below the geometric mean of the stiffest and the softest: "
                    + ", ".join(f"theta_sigma {a:.1f}° to {b:.1f}° (middle {((a + ((b - a) % 360) / 2) % 360):.1f}°)"
                                for a, b in sectors) + ".")
        lines += [law, ""]
        col = colors[n]
        x = [1e4 * c["de"][0] for _, c in probes]
        y = [1e4 * c["de"][1] for _, c in probes]
        ax[0].plot(x + x[:1], y + y[:1], "-o", color=col, ms=4, label=name)
        for xi, yi in zip(x, y):
            ax[0].plot([0, xi], [0, yi], ":", color=col, lw=0.6)
        if flow is not None:  # the fitted flow direction m through the origin
            r = max(math.hypot(a, b) for a, b in zip(x, y))
            ax[0].plot([0, r * math.cos(math.radians(flow))], [0, r * math.sin(math.radians(flow))], "--", color=col, lw=1)
        th = [math.radians(c["theta_s"]) for _, c in probes]
        mv = [c["modulus"] / 1e6 for _, c in probes]
        ax[1].plot(th + th[:1], mv + mv[:1], "-o", color=col, ms=4)
    ax[0].axhline(0, color="0.7", lw=0.5)
    ax[0].axvline(0, color="0.7", lw=0.5)
    ax[0].set(xlabel="sqrt2 deps_r [1e-4]", ylabel="deps_a [1e-4]", title="strain response envelopes (Rendulic)")
    ax[0].set_aspect("equal", adjustable="datalim")
    ax[1].set_title("|dsigma|/|deps| [MPa] against theta_sigma", fontsize=10)
    legend(ax[0], fontsize=7)
    save(fig, figs, "response_envelopes")
    lines += samples_section(out, idx["jobs"], idx.get("samples"))
    write_report(out, lines)
    print(os.path.join(out, "report.md"))


def study(out):
    """Report of a `grainlab study` directory: report.md + figures/ (stress paths, peaks, critical states,
    critical-state lines per mu_r, stress-force-fabric shares). A study over several gradings (the grading axis) gets
    one such report per curve, each a section of report.md with its figures in figures/g_<name>/: every fit of the
    report (critical-state lines, failure, dilatancy, rates, seeds, liquefaction curves) groups its tests by mu_r and
    the loading, and would pool the curves; each curve's section is the report a study of that curve alone writes."""
    import json

    idx = json.load(open(os.path.join(out, "study.json")))
    if not idx["jobs"] and idx.get("samples"):  # a preparation study: its base has no shear stage
        preparation_report(out, idx)
        return
    if any(k.rsplit(".", 1)[-1] == PROBE_KEY for j in idx["jobs"] for k in j.get("stage_keys", {})):
        probe_report(out, idx)  # a probe study: response envelopes
        return
    def split_key(j):
        """What the report's fits may not pool: the contact stiffness (the E axis) and the stage axes' values."""
        return j.get("E", 0), tuple(sorted(j.get("stage_keys", {}).items()))

    keys = sorted({split_key(j) for j in idx["jobs"]})
    stiffs = sorted({k[0] for k in keys})
    if len(keys) < 2:
        lines = grading_lines(out, idx, "figures")
    else:
        # The E axis (material.E, the contact stiffness) and the stage axes (a key of one stage: a K path's k_ratio, a
        # loop's stress_ratio): a section per value (per combination), as the gradings' below; across them the
        # sections' tables say what the value moves.
        if len(stiffs) > 1:
            lines = [f"# Study report: {idx['study']}", "",
                     f"{len(idx['jobs'])} tests at {len(stiffs)} contact stiffnesses E (material.E; k_n = E rbar, SPEC §2): " +
                     ", ".join(f"{E:g} Pa" if E else "the base's" for E in stiffs) +
                     ". Each E's tests have a section of their own below, as the report of a study at that E alone (its "
                     "headings one level down), with their figures in `figures/E_<E>/` (`figures/E_1e9/`; `figures/E_base/` for the base's): "
                     "the report's fits group tests by mu_r and the loading, and would pool the stiffnesses, which move "
                     "the states (a softer packing overlaps more: denser, and more of its strain elastic)."
                     + (" Each section is one E and one value of the stage axes (a key of one stage of the base, set in "
                        "each job), its figures in `figures/E_<E>_<stage>.<key>_<value>/`."
                        if any(sk for _, sk in keys) else ""), ""]
        else:
            labels = sorted({lab for _, sk in keys for lab, _ in sk})
            lines = [f"# Study report: {idx['study']}", "",
                     f"{len(idx['jobs'])} tests over the stage axes " + ", ".join(f"stages.{lab}" for lab in labels) +
                     " (a key of one stage of the base, set in each job). Each value's tests have a section of their "
                     "own below, as the report of a study at that value alone (its headings one level down), with their "
                     "figures in `figures/<stage>.<key>_<value>/`: the report's fits group tests by mu_r and the "
                     "loading, and would pool the values, which change the test.", ""]
        heads = {}
        for j in idx["jobs"]:
            E, sk = split_key(j)
            heads[j["name"]] = ", ".join(([f"E = {E:g} Pa" if E else "base E"] if len(stiffs) > 1 else [])
                                         + [f"{lab} = {v:g}" for lab, v in sk]) or "-"
        if any(sk for _, sk in keys):
            lines += across_values_section(out, idx, heads)
        for key in keys:
            E, sk = key
            jobs = [j for j in idx["jobs"] if split_key(j) == key]
            # the samples these tests shear (a preparation stage's axis gives each value samples of its own)
            used = {j.get("sample") for j in jobs}
            sub_idx = dict(idx, jobs=jobs, samples=[s for s in idx.get("samples", []) if s["name"] in used])
            name = f"{E:g}".replace("e+0", "e").replace("e+", "e")  # as the jobs' names: 1e9
            heads, dirs = [], []
            if len(stiffs) > 1:
                heads.append(f"Contact stiffness E = {E:g} Pa" if E else "The base's contact stiffness")
                dirs.append(f"E_{name}" if E else "E_base")
            heads += [f"stages.{lab} = {v:g}" for lab, v in sk]
            dirs += [f"{lab}_{v:g}".replace("e+0", "e").replace("e+", "e") for lab, v in sk]
            part = grading_lines(out, sub_idx, "figures/" + "_".join(dirs))
            lines += ["## " + ", ".join(heads)]
            lines += ["#" + x if x.startswith("#") else x for x in part[1:]] + [""]
    write_report(out, lines)
    print(os.path.join(out, "report.md"))


def grading_lines(out, idx, figs_rel):
    """The report of the jobs in idx (a study's, or its part at one E), figures under out/figs_rel: one study's report,
    or over several gradings one such report per curve (study's docstring), or over several sample files (the
    sample_file axis) one per file."""
    if any(j.get("specimen") for j in idx["jobs"]):
        return specimen_lines(out, idx, figs_rel)
    gradings = sorted({j.get("grading", "") for j in idx["jobs"]})
    if len(gradings) < 2:
        lines = study_lines(out, idx, figs_rel)
    else:
        cu = {j.get("grading", ""): j.get("cu", 0) for j in idx["jobs"]}
        lines = [f"# Study report: {idx['study']}", "",
                 f"{len(idx['jobs'])} shear tests on {len(gradings)} gradings: " +
                 ", ".join(f"{g} (Cu {cu[g]:.3g})" if g else "the base's sizes" for g in gradings) +
                 ". Each grading's tests have a section of their own below, as the report of a study of that grading "
                 f"alone (its headings one level down), with their figures in `{figs_rel}/g_<grading>/` (`{figs_rel}/base/` "
                 "for the base's sizes): the report's fits group tests by mu_r and the loading, and would pool the "
                 "gradings.", ""]
        os.makedirs(os.path.join(out, figs_rel), exist_ok=True)
        if gradings_figure(out, idx.get("samples", []), os.path.join(out, figs_rel)):
            lines += [f"Figure: `{figs_rel}/grading.png` (each curve, asked and drawn: one sample of each).", ""]
        lines += across_gradings_section(out, idx, os.path.join(out, figs_rel))
        crr, parts = group_sections(
            out, idx, "grading", gradings, lambda g: f"{figs_rel}/g_{g}" if g else f"{figs_rel}/base",
            lambda g: f"## Grading {g}: Cu = {cu[g]:.3g}" if g else "## The base's sizes",
            lambda g: f"{g or 'the base'} | {cu[g]:.3g}", ("gradings", "curve", "grading | Cu"))
        lines += crr + parts
    return lines


def group_sections(out, idx, key, groups, rel_of, title_of, cells_of, names):
    """The sections of a study split by study.json's key (grading, specimen) over its values groups: of each value g
    the report of its tests alone (study_lines) under title_of(g), its headings one level down and its figures in
    out/rel_of(g); and the table of the values' liquefaction-resistance fits side by side, each row's first cells
    cells_of(g). names: (the values, one value, the table's first column heads). Returns (that table's lines or [],
    the sections' lines)."""
    parts, rows = [], []
    for g in groups:
        sub_idx = dict(idx, jobs=[j for j in idx["jobs"] if j.get(key, "") == g],
                       samples=[s for s in idx.get("samples", []) if s.get(key, "") == g])
        fits = []
        part = study_lines(out, sub_idx, rel_of(g), fits)
        parts += [title_of(g)] + ["#" + x if x.startswith("#") else x for x in part[1:]] + [""]
        rows += [f"| {cells_of(g)} | {f['mu_r']:g} | {f['cond'] or '–'} | {f['what']} | {f['tests']} | {f['crr']} |"
                 for f in fits]
    if not rows:
        return [], parts
    return [f"## Liquefaction resistance across the {names[0]}", "",
            f"Each {names[1]}'s liquefaction-resistance fits (its section's table: CSR = a N^-b per mu_r, the "
            "conditions that vary and criterion) side by side, CRR the CSR that meets the criterion in "
            f"{CRR_CYCLES} cycles.", "",
            f"| {names[2]} | mu_r | conditions | criterion | tests | CRR (N = {CRR_CYCLES}) |",
            "|" + "---|" * (names[2].count("|") + 6), *rows, ""], parts


def specimen_lines(out, idx, figs_rel):
    """grading_lines over the sample_file axis's files: one study's report per file, each a section with its figures in
    figs_rel/f_<name>/ (figs_rel/base/ for the base's sample, an extra job's), after the tests' end states side by side
    (across_gradings_section by file) and the files' sieve curves. A file's spheres may be another material's (a
    packing from another code, another grading), and the report's fits would pool them as one; the table across them
    says where dense and loose specimens of one material meet (one critical state)."""
    files = sorted({j.get("specimen", "") for j in idx["jobs"]})
    where = {j.get("specimen", ""): (j.get("specimen_file", ""), j.get("count", 0)) for j in idx["jobs"]}

    def what(f):
        return f"{f} ({os.path.basename(where[f][0])}, {where[f][1]} spheres)" if f else "the base's sample"
    lines = [f"# Study report: {idx['study']}", "",
             f"{len(idx['jobs'])} shear tests on {len(files)} sample file(s): " + ", ".join(what(f) for f in files) +
             ". Each file's tests have a section of their own below, as the report of a study of that file alone (its "
             f"headings one level down), with their figures in `{figs_rel}/f_<name>/` (`{figs_rel}/base/` for the "
             "base's sample): the report's fits group tests by mu_r and the loading, and would pool the files, whose "
             "spheres may be another material's.", ""]
    os.makedirs(os.path.join(out, figs_rel), exist_ok=True)
    if gradings_figure(out, idx.get("samples", []), os.path.join(out, figs_rel), "specimen"):
        lines += [f"Figure: `{figs_rel}/grading.png` (each file's sieve curve: one sample of each).", ""]
    lines += across_gradings_section(out, idx, os.path.join(out, figs_rel), "specimen")
    crr, parts = group_sections(
        out, idx, "specimen", files, lambda f: f"{figs_rel}/f_{f}" if f else f"{figs_rel}/base",
        lambda f: f"## Sample file {f}: {where[f][0]}" if f else "## The base's sample",
        lambda f: f or "the base", ("sample files", "file", "sample file"))
    return lines + crr + parts


def isotropic_ocr(out, j):
    """The isotropic overconsolidation ratio of job j's sample, R = p'_max / p'_0: the largest of its isotropic stages'
    end pressures over its last one's (summary.json's p; a stage ends within its pressure_tolerance of its target, the
    pressure a lab would call the preconsolidation), where it consolidated in two stages or more (a preloading, or
    one at the same pressure: R = 1, the normally consolidated reference); None for a sample of one stage, or none."""
    p = [float(x["p"]) for x in isotropic_stages(out, j.get("sample", "")) if x.get("p")]
    return max(p) / p[-1] if len(p) >= 2 and p[-1] > 0 else None


def one_way_anova(groups):
    """One-way analysis of variance (scipy's f_oneway): whether the means of the groups (a dict of lists) differ by more
    than the values scatter within them. (F, p, k - 1, n - k); None with fewer than two groups, no replicate in any
    (n = k), or no scatter within them (F undefined)."""
    g = [np.asarray(v, dtype=float) for v in groups.values() if len(v)]
    n, k = sum(len(v) for v in g), len(g)
    ss_w = sum(float(np.sum((v - v.mean()) ** 2)) for v in g)  # the scatter within the groups
    if k < 2 or n <= k or ss_w <= 1e-12 * max(1.0, sum(float(np.sum(v ** 2)) for v in g)):
        return None
    from scipy.stats import f_oneway
    r = f_oneway(*g)
    return float(r.statistic), float(r.pvalue), k - 1, n - k


def end_states_verdict(crit):
    """The line under the drained tests' end states: over their critical states (crit: (section, p', e, q/p') each),
    if those are at one pressure level (pressure_levels: p'_c within CSL_LEVEL_GAP, so the critical-state line's own
    slope cannot separate them), whether the stage axis moves e_c and q/p' by more than the seeds scatter within a
    value (one_way_anova). Empty otherwise."""
    if len(crit) < 3 or pressure_levels([c[1] for c in crit]) != 1:
        return []
    out = []
    for col, what, digits in ((2, "e_c", 4), (3, "q/p'", 3)):
        groups = {}
        for c in crit:
            groups.setdefault(c[0], []).append(c[col])
        a = one_way_anova(groups)
        if a is None:
            continue
        vals = [c[col] for c in crit]
        out.append(f"{what} {min(vals):.{digits}f}–{max(vals):.{digits}f} (F = {a[0]:.2f} on {a[2]} and {a[3]} "
                   f"degrees of freedom, p = {a[1]:.3f})")
    if not out:
        return []
    p = [c[1] for c in crit]
    return [f"Over the {len(crit)} critical states, at one pressure level (p'_c {min(p) / 1e3:.1f}–"
            f"{max(p) / 1e3:.1f} kPa), a one-way analysis of variance asks whether the sections' values move them "
            "by more than the tests of one value (the seeds) scatter: " + "; ".join(out) + ". p < 0.05: the value "
            "moves it; larger: within the seeds' scatter.", ""]


def across_values_section(out, idx, heads):
    """The tests of a study over stage axes side by side (the sections after it report each value apart): per test its
    section's value(s) (heads: the job's name -> its section heading), the stress its last stage (the test) started
    from, p'_0 and q_0 (summary.json), that stage's peak of |q| and largest q/p' of the walls, and for an undrained
    test its strength s_u = |q_peak| / 2 over the consolidation's vertical stress sigma'_v0 = p'_0 + 2 q_0 / 3 (the
    ratio of SHANSEP and of the CAU against CIU comparison), beside the OCR the stage before it left (summary.json's, an
    oedometric unloading's) or, for a shear that starts from its sample, the sample's isotropic one (isotropic_ocr: a
    preloading's, p'_max / p'_0). Per mu_r, over three undrained tests or more at two OCRs or more, SHANSEP's s_u /
    sigma'_v0 = S OCR^m (Ladd & Foott 1974), least squares in the logarithms (per E too, over the E axis, and per
    strain rate, over an axial_strain_rate axis: rate_section extrapolates s_u to I -> 0). Empty without
    such a test. Cyclic oedometer tests get a table of their own (cyclic_oedometer_rows): the strain their cycles
    accumulate against the amplitude. Drained tests get their end state side by side too, as their critical-state
    tables measure it (the window's means, steady or not): whether tests that started apart (another OCR, e_0) end on
    one state, as a unique critical-state line has them."""
    rows, shansep, coed_rows, coed, quasi, ends, crit, dropped, mono = [], {}, [], [], {}, [], [], [], []
    cs_cfg = idx.get("critical_state", {"window": 0.05, "qp_tol": 0.05, "p_tol": 0.05, "e_tol": 0.005})
    for j in idx["jobs"]:
        d = os.path.join(out, j["dir"])
        if not (os.path.isfile(os.path.join(d, "series.csv")) and os.path.isfile(os.path.join(out, "jobs", j["name"], "done"))):
            continue
        try:
            with open(os.path.join(d, "summary.json")) as f:
                stages = json.load(f).get("stages", [])
            k_st = max(k for k, x in enumerate(stages) if x.get("type") != "isotropic")
        except (OSError, ValueError):
            continue
        st = stages[k_st]
        ocr = stages[k_st - 1].get("OCR") if k_st > 0 else None  # an oedometric stage's, the one before the shear
        if k_st == 0:  # the shear starts from its sample: an isotropic preloading's OCR, if the sample has one
            ocr = isotropic_ocr(out, j)
        s = load(d)
        if s["cyclic_oedometric"].any():
            coed_rows += cyclic_oedometer_rows(j, d, s, heads[j["name"]])
            coed.append((j, d, s))
            continue
        pk = shear_peak(s, st)
        if st.get("type") != "triaxial" or pk is None:
            continue
        if s["monotonic"].any():
            mono.append((j, d, s, st["name"]))
        m, k = pk
        p0, q0 = float(st["p_0"]), float(st["q_0"])
        undrained = st.get("drainage") == "undrained"
        su = abs(float(s["q"][m][k])) / 2
        ratio = su / vertical_stress_0(st)
        if undrained and ocr is not None and ocr > 0:
            shansep.setdefault((j.get("E", 0), j["mu_r"], float(st.get("axial_strain_rate", 0))), []).append(
                (float(ocr), ratio))
            if (u := undrained_strength(s, st)) is not None:  # (I, s_u / sigma'_v0) at the q peak: SHANSEP at I -> 0
                quasi.setdefault((j.get("E", 0), j["mu_r"]), {}).setdefault(f"{float(ocr):.3g}", []).append(
                    (float(ocr), *u, float(st.get("axial_strain_rate", 0))))
        M = float(np.max(np.abs(s["q"][m] / s["p"][m])))
        if st.get("drainage") == "drained":
            c = critical_state(s, cs_cfg["window"], cs_cfg["qp_tol"], cs_cfg["p_tol"], cs_cfg["e_tol"])
            ocr_txt = number_text(float(ocr) if ocr is not None else None, '.3g')
            ends.append(f"| {heads[j['name']]} | {j['name']} | {ocr_txt} | {float(s['e'][m][0]):.4f} | "
                        + (f"{c['p'] / 1e3:.1f} | {c['e']:.4f} | {c['qp']:.3f} | {'yes' if c['ok'] else 'no'} |"
                           if c is not None and "e" in c else "- | - | - | - |"))
            if c is not None and c.get("ok"):
                crit.append((heads[j["name"]], float(c["p"]), float(c["e"]), float(c["qp"])))
        rising = " (rising)" if k == int(m.sum()) - 1 else ""  # no peak: q still rose at the stage's end
        rows.append(f"| {heads[j['name']]} | {j['name']} | {st.get('drainage')} | "
                    f"{number_text(float(ocr) if ocr is not None else None, '.3g')} | {p0 / 1e3:.1f} | {q0 / 1e3:.1f} | "
                    f"{float(s['e'][m][0]):.4f} | {float(s['q'][m][k]) / 1e3:.1f}{rising} | "
                    f"{f'{su / 1e3:.1f} ({ratio:.3f})' if undrained else '-'} | {M:.3f} |")
    pooled = cyclic_oedometer_pooled(coed, lambda j: heads[j["name"]])
    coed_lines = (["Cyclic oedometer tests (each value's section below has them too). " + CYCLIC_OEDOMETER_TEXT, "",
                   "| section " + CYCLIC_OEDOMETER_HEAD, "|---" * 17 + "|", *coed_rows, "",
                   *([CYCLIC_OEDOMETER_POOLED_TEXT, "", "| section " + CYCLIC_OEDOMETER_POOLED_HEAD, "|---" * 16 + "|",
                      *pooled, ""] if pooled else [])] if coed_rows else [])
    if not rows:
        return ["## Across the values", "", *coed_lines] if coed_rows else []
    fits, drawn = [], []
    several_E = len({E for E, _, _ in shansep}) > 1  # the E axis too: a fit per E (the stiffness moves the swelling)
    # and per strain rate (an axial_strain_rate axis): s_u carries a rate term, which pooling would mix into m
    several_rates = len({r for _, _, r in shansep}) > 1
    for (E, mu_r, rate), pts in sorted(shansep.items()):
        x = np.array([t[0] for t in pts])
        if len(pts) < 3 or pressure_levels(x) < 2:
            continue
        m_, c, sm, sc = fit(np.log(x), np.log([t[1] for t in pts]))
        label = (f"{mu_r:g}{(f', E = {E:g} Pa' if E else ', base E') if several_E else ''}"
                 f"{f', rate {rate:g}/s' if several_rates else ''}")
        fits.append(f"| {label} | {len(pts)} | "
                    f"{x.min():.3g}–{x.max():.3g} | {math.exp(c):.3f} ± {math.exp(c) * sc:.3f} | {m_:.3f} ± {sm:.3f} |")
        drawn.append((label, x, np.array([t[1] for t in pts]), math.exp(c), m_))
    # SHANSEP at I -> 0 (an axial_strain_rate axis): each OCR's tests (all rates, all seeds) on a line in the inertial
    # number at their q peak, as each section's rate table takes it (rate_section), and S, m through those limits; and
    # where every OCR has three rates or more, through the limits of lines in sqrt(I) too (LIMIT_FORMS: the limit's
    # form, which two rates cannot tell)
    for (E, mu_r), by_ocr in sorted(quasi.items()):
        for name, form in LIMIT_FORMS:
            need = 2 if name == "I" else 3  # distinct rates per OCR
            if name != "I" and any(len({t[3] for t in pts}) < need for pts in by_ocr.values()):
                continue
            lim, below = [], []
            label = f"{mu_r:g}{(f', E = {E:g} Pa' if E else ', base E') if several_E else ''}, {name} -> 0"
            for pts in by_ocr.values():
                f = line_to_zero(form([t[1] for t in pts]), [t[2] for t in pts]) if len({t[3] for t in pts}) >= need \
                    else None
                if f is not None and f[0] > 0:
                    lim.append((float(np.mean([t[0] for t in pts])), f[0], len(pts)))
                elif f is not None:  # a strength at or below zero: that form does not describe these tests
                    below.append(f"OCR {float(np.mean([t[0] for t in pts])):.3g} ({f[0]:.3f})")
            if below:
                dropped.append(f"'{label}': the line in {name} takes s_u / sigma'_v0 to zero or below at I -> 0 for "
                               + ", ".join(below) + " (that form does not describe those tests; they are left out"
                               + (")" if len(lim) >= 2 else ", and too few OCRs remain for the row)"))
            if len(lim) < 2 or pressure_levels(np.array([t[0] for t in lim])) < 2:
                continue
            x, y = np.log([t[0] for t in lim]), np.log([t[1] for t in lim])
            n_txt = f"{len(lim)} OCRs ({sum(t[2] for t in lim)} tests)"
            ocr_txt = f"{min(t[0] for t in lim):.3g}–{max(t[0] for t in lim):.3g}"
            if len(lim) == 2:  # the line meets both: no standard error
                m_ = (y[1] - y[0]) / (x[1] - x[0])
                fits.append(f"| {label} | {n_txt} | {ocr_txt} | {math.exp(y[0] - m_ * x[0]):.3f} | {m_:.3f} |")
            else:
                m_, c, sm, sc = fit(x, y)
                fits.append(f"| {label} | {n_txt} | {ocr_txt} | {math.exp(c):.3f} ± {math.exp(c) * sc:.3f} | "
                            f"{m_:.3f} ± {sm:.3f} |")
    if drawn:  # figures/shansep.png: each test's s_u / sigma'_v0 against its OCR and each fit's line, log-log
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for n, (label, x, y, S, m_) in enumerate(drawn):
            xs = np.geomspace(x.min(), x.max(), 50)
            ax.loglog(x, y, "o", color=f"C{n % 10}", label=f"mu_r {label}")
            ax.loglog(xs, S * xs ** m_, "-", color=f"C{n % 10}", label=f"S = {S:.3f}, m = {m_:.3f}")
        ax.set(xlabel="OCR", ylabel="s_u / sigma'_v0", title="SHANSEP: s_u / sigma'_v0 = S OCR^m")
        # the tests' OCRs as numbers, to 3 digits (a preloading's measured OCR is 1.99998, 2.00003, ...)
        ax.set_xticks(sorted({float(f"{v:.3g}") for _, x, _, _, _ in drawn for v in x}))
        plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
        ax.xaxis.set_major_formatter(plain)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.yaxis.set_major_formatter(plain)
        ax.yaxis.set_minor_formatter(plain)  # a decade or less of s_u / sigma'_v0: the minor ticks are the labels
        ax.grid(alpha=0.3, which="both")
        legend(ax, fontsize=7)
        os.makedirs(os.path.join(out, "figures"), exist_ok=True)
        save(fig, os.path.join(out, "figures"), "shansep")
    return ["## Across the values", "",
            "Each test's last stage (the shear: a K path or an oedometer before it is its consolidation): the stress it "
            "started from (p'_0, q_0; summary.json) and its void ratio there (e_0, the stage's first row), its peak of |q| ('(rising)': q still rose at the stage's end, a "
            "dilating sample's undrained q, so the 'peak' is its end's) and largest |q|/p' of the walls, and an undrained "
            "test's s_u = |q_peak| / 2 with s_u / sigma'_v0, sigma'_v0 = p'_0 + 2 q_0 / 3 the vertical stress it was "
            "consolidated to; OCR: the one an oedometric stage before the shear left (summary.json), or for a shear of "
            "a sample consolidated in isotropic stages, the largest of their pressures over the last (p'_max / p'_0: "
            "an isotropic preloading's). Each value's "
            "section below has its tests' full report.", "",
            "| section | test | drainage | OCR | p'_0 [kPa] | q_0 [kPa] | e_0 | q_peak [kPa] | s_u [kPa] (s_u / sigma'_v0) | "
            "max q/p' (abs) |",
            "|---|---|---|---|---|---|---|---|---|---|", *rows, "",
            *(["SHANSEP (Ladd & Foott 1974): s_u / sigma'_v0 = S OCR^m per mu_r (and E, and strain rate: s_u grows with "
               "the rate, so tests at several rates are fitted apart, and a row 'I -> 0' fits the limits of each "
               "OCR's tests on a line in the inertial number at their q peak, as each section's Rate dependence takes "
               "them: the rate-independent S and m; and where each OCR has three rates or more, a row 'sqrt(I) -> 0' "
               "through the limits of lines in sqrt(I), the other form of the limit that Rate dependence compares: the "
               "two rows differ by what the limit's form leaves open), least squares in ln(s_u / sigma'_v0) "
               "against ln OCR over the undrained tests, ± one standard error (`figures/shansep.png`: the tests and the "
               "lines).", "",
               "| mu_r | tests | OCR | S | m |", "|---|---|---|---|---|", *fits, "",
               *([("Not fitted: " + "; ".join(dropped) + "."), ""] if dropped else [])] if fits else []),
            *([f"The drained tests' end state: p', e and q/p' averaged over the last {cs_cfg['window']:g} of axial "
               "strain, as each section's critical-state table measures them, steady there (critical: yes) or still "
               "drifting (no; the section says by how much), beside the OCR and e_0 they started from: tests that "
               "start apart and end at one e at one p' have forgotten their history, as a unique critical-state line "
               "has it.", "",
               "| section | test | OCR | e_0 | p' at end [kPa] | e at end | q/p' at end | critical |",
               "|---|---|---|---|---|---|---|---|", *ends, "", *end_states_verdict(crit)] if ends else []),
            *pooled_state_parameter(out, idx, mono, heads), *coed_lines]


# The state-parameter section's lines: (measure, the psi it is set against, the fits table's name, format)
STATE_PARAMETER_FITS = (("dphi", "psi0", "phi'_max - phi'_cs [°] on psi_0", ".2f"),
                        ("d", "psi0", "(-d)_max on psi_0", ".3f"),
                        ("d", "psi_d", "(-d)_max on psi at it", ".3f"))


# A stage axis on the shear stage's own end moves where a test stops, not what it is: its values' tests may be pooled
SHEAR_END_KEYS = ("max_axial_strain", "max_steps")


def pooled_state_parameter(out, idx, mono, heads):
    """The state-parameter section (state_parameter_section) over the values of a study's stage axes together: one
    critical-state line through the critical states of every value's tests (the sections below fit each value's
    apart), so that samples prepared apart (a preparation stage's friction or preload, a K path) are set against one
    line, as Been & Jefferies's state parameter has it. Pooled only where nothing but the sample or the test's
    consolidation differs: tests of another E, sphere count or grading, or whose shear stage a stage axis sets (but
    its end), are pooled apart (mono: (job, run directory, series, its shear stage's name))."""
    cs_cfg = idx.get("critical_state", {"window": 0.05, "qp_tol": 0.05, "p_tol": 0.05, "e_tol": 0.005})
    tol = (cs_cfg["qp_tol"], cs_cfg["p_tol"], cs_cfg["e_tol"])
    pools = {}
    for j, d, s, shear in mono:
        own = tuple(sorted((k, v) for k, v in j.get("stage_keys", {}).items()
                           if k.split(".")[0] == shear and k.split(".", 1)[-1] not in SHEAR_END_KEYS))
        pools.setdefault((j.get("E", 0), j.get("count", 0), j.get("grading", ""), own), []).append((j, d, s))
    lines = []
    os.makedirs(os.path.join(out, "figures"), exist_ok=True)
    for n, (key, runs) in enumerate(sorted(pools.items(), key=lambda kv: str(kv[0]))):
        states = [(d, c) for _, d, s in runs if (c := critical_state(s, cs_cfg["window"], *tol)) and c["ok"]]
        what = ", ".join(x for x in ([f"E = {key[0]:g} Pa" if key[0] else "base E"]
                                     if len({k[0] for k in pools}) > 1 else [])
                         + ([f"{key[1]} spheres"] if len({k[1] for k in pools}) > 1 else [])
                         + ([f"grading {key[2]}"] if len({k[2] for k in pools}) > 1 else [])
                         + [f"{k} = {v:g}" for k, v in key[3]])
        groups = csl_groups(states)
        across = directions_line(groups, len({k[3] for k in groups}) > 1)
        if across:  # the directions' critical states of every value on one line
            lines += ["### One critical-state line across the values and directions" + (f": {what}" if what else ""),
                      "", "The critical states of every value together. " + across[1], *across[2:], ""]
        for ext in (False, True):
            way, tag = ("extensions", " (extension)") if ext else ("compressions", "")
            lines += state_parameter_section(
                runs, states, cs_cfg["window"], tol, os.path.join(out, "figures"), peak_settings(idx), heads,
                f"### State parameter across the values{tag}" + (f": {what}" if what else ""),
                "state_parameter" + (f"_{n + 1}" if len(pools) > 1 else ""),
                f"The drained {way} of every value together, on one critical-state line through all their critical "
                "states (each value's section below fits its own). ", ext)
            lines += undrained_state_section(
                runs, states, cs_cfg["window"], tol, os.path.join(out, "figures"), peak_settings(idx), heads,
                f"### Undrained state parameter across the values{tag}" + (f": {what}" if what else ""),
                "state_parameter_undrained" + (f"_{n + 1}" if len(pools) > 1 else ""),
                f"The undrained {way} of every value together, on the line of the section above. ", ext)
    return lines


def across_gradings_section(out, idx, figs, kind="grading"):
    """The monotonic shears of a study over several curves side by side (the sections after it fit each curve apart):
    per test its curve, max q/p' (phi'_max) as its section's peak table gives it, and its end state as its critical-state
    table measures it (the means over the window, whether or not they are steady, and which are), and
    figures/gradings_e_p.png, that end e against ln p' for each curve: how far the curve moves the states. Empty
    without such a test. kind "specimen": the same over the sample_file axis's files, each test with its sample's e_0
    (the file's density after the sample job's consolidation) where the curve's Cu was, in figures/files_e_p.png."""
    cs_cfg = idx["critical_state"]
    tol = (cs_cfg["qp_tol"], cs_cfg["p_tol"], cs_cfg["e_tol"])
    peak = peak_settings(idx)
    files = kind == "specimen"
    rows, pts = [], {}
    for j in sorted(idx["jobs"], key=lambda j: (j.get("cu", 0), j.get(kind, ""), j.get("p0", 0), j["name"])):
        d = os.path.join(out, j["dir"])
        if not (os.path.isfile(os.path.join(d, "series.csv")) and os.path.isfile(os.path.join(out, "jobs", j["name"], "done"))):
            continue
        s = load(d)
        if not s["monotonic"].any():
            continue
        ps = peak_state(s, peak)
        c = critical_state(s, cs_cfg["window"], *tol)
        g = j.get(kind, "")
        end = c is not None and "e" in c
        # a file's sample: its e_0 and its interior's (a packing cut out of a larger one keeps a looser layer along
        # its walls, which the box's e counts), where a grading's curve gives its Cu
        cs0 = consolidated(out, j.get("sample", "")) or {}
        second = (f"{number_text(cs0.get('e'), '.4f')} | {number_text(cs0.get('e_inner'), '.4f')}" if files else
                  f"{j.get('cu', 0):.3g}")
        rows.append(f"| {g or 'the base'} | {second} | {j['name']} | "
                    + (f"{ps['M']:.3f} ({ps['phi']:.1f}°)" if "M" in ps else "-") + " | "
                    + (f"{c['p'] / 1e3:.1f} | {c['e']:.4f} | {c['qp']:.3f} | {'yes' if c['ok'] else 'no'} |" if end
                       else "- | - | - | - |"))
        if end:
            m = s["monotonic"]
            pts.setdefault(g, []).append((c["p"], c["e"], c["ok"], s["p"][m], s["e"][m], c))
    if not rows:
        return []
    name = "files_e_p" if files else "gradings_e_p"
    drawn = (f"`{os.path.relpath(figs, out)}/{name}.png` draws that e against p' for each "
             f"{'file' if files else 'curve'} (filled: critical), each test's path to it a thin line"
             + ("; specimens of one material, dense and loose, end on one critical-state line" if files else "")
             if pts else "No test is longer than the window yet: no end state, and no figure")
    for k, g in enumerate(sorted(pts)):
        if k == 0:
            fig, ax = plt.subplots(figsize=(7, 4.5))
        ends = sorted(pts[g], key=lambda t: t[:3])
        for t in ends:  # the shear's path: dense samples dilate to the end state, loose ones contract
            ax.plot(t[3] / 1e3, t[4], "-", color=f"C{k % 10}", lw=0.5, alpha=0.6)
        p_, e_, ok = (np.array([t[i] for t in ends]) for i in range(3))
        ok = ok.astype(bool)
        ax.plot(p_ / 1e3, e_, "-", color=f"C{k % 10}", lw=0.8)
        ax.plot(p_[ok] / 1e3, e_[ok], "o", color=f"C{k % 10}", label=f"{g or 'the base'} (filled: critical)")
        ax.plot(p_[~ok] / 1e3, e_[~ok], "o", color=f"C{k % 10}", mfc="none")
    if pts:
        ax.set(xscale="log", xlabel="p' [kPa]", ylabel="e",
               title="each shear's path and end (the critical-state window's means)")
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.grid(True, which="both", alpha=0.3)
        legend(ax, fontsize=8)
        save(fig, figs, name)
    return [f"## Across the {'sample files' if files else 'gradings'}", "",
            "Each monotonic shear: its "
            + ("sample file and its sample's e_0 (the file consolidated by the sample job), of the box and of its "
               "interior (inset by two mean diameters: a packing cut out of a larger one keeps a looser layer along its "
               "walls)" if files else "curve and Cu")
            + ", max q/p' (phi'_max) as its section's peak table gives it, and its end "
            f"state: p', e and q/p' averaged over the last {cs_cfg['window']:g} of axial strain, as its critical-state "
            "table measures them, steady there (critical: yes) or still drifting (no; its section says by how much). "
            f"{drawn}.", "",
            "| " + ("sample file | e_0 | e_0 interior" if files else "grading | Cu")
            + " | test | max q/p' (phi'_max) | p' at end [kPa] | e at end | q/p' at end | critical |",
            "|---" * (9 if files else 8) + "|", *rows, "", *(files_line(pts) if files else [])]


def one_line_rows(groups, draw=None):
    """The table rows of one critical-state line through several members' critical states (groups: the group's label ->
    (member, p'_c [kPa], e_c) each, in the order given; the member "" is named the base): per group with two members
    or more and three states or more at three pressure levels or more, e_c = a + b p' through all of them (the rms
    of its residuals, n - 2 degrees of freedom), and per member (sorted) its states' mean residual from that line
    against the scatter about the line once each member's mean residual is taken out (the pooled within-member rms,
    n - 2 - (members - 1) degrees of freedom: a member's own offset must not widen the yardstick it is judged by)
    over the root of the member's states: 'off the line' past two of those standard errors. A group without a degree
    of freedom left is skipped. draw(label, a, b, p), where given, is called with each line fitted (p: its states'
    p'_c [kPa]), to draw it."""
    rows = []
    for what, st in groups.items():
        p = np.array([x[1] for x in st])
        e = np.array([x[2] for x in st])
        members = sorted({x[0] for x in st})
        dof = len(st) - 2 - (len(members) - 1)
        if len(members) < 2 or dof < 1 or pressure_levels(p) < 3:
            continue
        b, a, sb, sa = fit(p, e)
        if draw is not None:
            draw(what, a, b, p)
        res = e - (a + b * p)
        rms = math.sqrt(float(np.sum(res ** 2)) / (len(st) - 2))
        mine = {f: np.array([res[i] for i, x in enumerate(st) if x[0] == f]) for f in members}
        within = math.sqrt(sum(float(np.sum((r - r.mean()) ** 2)) for r in mine.values()) / dof)
        for f in members:
            r = mine[f]
            se, off = within / math.sqrt(len(r)), float(np.mean(r))
            rows.append(f"| {what} | e_c = {a:.4f} ± {sa:.4f} + ({b:.3e} ± {sb:.1e}) p' [kPa] ({len(st)} states, "
                        f"rms {rms:.4f}) | {f or 'the base'} | {len(r)} | {round(off, 4) + 0.0:+.4f} | {se:.4f} | "
                        f"{'off the line' if abs(off) > max(2 * se, 1e-12) else 'on it'} |")  # 1e-12: round-off
    return rows


def files_line(pts):
    """Whether the sample files' critical states lie on one line (across_gradings_section's pts: per file its tests'
    (p', e, critical, path p', path e, state)): per group of critical states a critical-state line joins (mu_r,
    extension, b, rate: csl_groups), with states of two files or more at three pressure levels or more (as a file's own
    line needs), e_c = a + b p' through all of them and each file's mean offset from it against the line's scatter
    (one_line_rows): specimens of one material, whatever their density, reach one
    critical-state line (Roscoe et al. 1958; Been & Jefferies 1985), so an offset past two of those is a file whose
    spheres or contact law differ, or whose tests are not at their critical state. Empty where no group qualifies."""
    groups = {}
    for g in sorted(pts):
        for t in pts[g]:
            c = t[5]
            if c["ok"]:
                groups.setdefault((c["mu_r"], c["ext"], c["b"], c["rate"]), []).append((g, c["p"] / 1e3, c["e"]))
    rows = one_line_rows({(f"mu_r {k[0]:g}" + (", extension" if k[1] else "")
                           + (", plane strain" if k[2] == PLANE_STRAIN else f", b {k[2]:g}" if k[2] else "")
                           + rate_text(k[3], ", ")): groups[k] for k in sorted(groups)})
    if not rows:
        return []
    return ["One critical-state line through the files' critical states (e_c = a + b p', as each file's section fits "
            "its own), per mu_r and loading, with each file's mean offset from it: specimens of one material reach "
            "one critical-state line whatever their density, so a file more than two standard errors off it (the "
            "scatter about the line once each file's mean offset is taken out, over the root of its states) has "
            "other spheres or contacts, or tests not yet critical.", "",
            "| group | the line through every file's critical states | file | states | mean offset in e | standard "
            "error | |", "|---|---|---|---|---|---|---|", *rows, ""]


def study_lines(out, idx, figs_rel, fits=None):
    """The lines of a study's report of the jobs in idx (study.json's, or its part of one grading), its figures saved
    in out/figs_rel and named so in the text. fits: a list that gets the liquefaction-resistance curves it fits
    (cyclic_section)."""
    cs_cfg = idx["critical_state"]
    tol = (cs_cfg["qp_tol"], cs_cfg["p_tol"], cs_cfg["e_tol"])
    runs, missing = [], []
    for j in idx["jobs"]:
        d = os.path.join(out, j["dir"])
        if os.path.isfile(os.path.join(d, "series.csv")) and os.path.isfile(os.path.join(out, "jobs", j["name"], "done")):
            runs.append((j, d, load(d)))
        else:
            missing.append(j["name"])
    figs = os.path.join(out, figs_rel)
    os.makedirs(figs, exist_ok=True)
    murs = sorted({j["mu_r"] for j, _, _ in runs})
    colors = {m: plt.cm.viridis(i / max(1, len(murs) - 1)) for i, m in enumerate(murs)}
    fig, ax = plt.subplots(1, 3, figsize=(17, 4.8))
    several_seeds = len({j.get("seed") for j, _, _ in runs}) > 1
    for j, d, s in runs:
        m = s["shear"]
        ls = "-" if j["drainage"] == "undrained" else "--"
        lab = job_label(j, s, several_seeds)
        ax[0].plot(100 * s["eps_a_run"][m], s["q"][m] / 1e3, ls, color=colors[j["mu_r"]], label=lab)
        ax[1].plot(s["p"][m] / 1e3, s["q"][m] / 1e3, ls, color=colors[j["mu_r"]])
        ax[2].plot(s["p"][m] / 1e3, s["e"][m], ls, color=colors[j["mu_r"]])
    ax[0].set(xlabel="eps_a [%]", ylabel="q [kPa]", title="deviator stress (solid undrained, dashed drained)")
    ax[1].set(xlabel="p' [kPa]", ylabel="q [kPa]", title="stress paths")
    ax[2].set(xlabel="p' [kPa]", ylabel="e", title="e - p'")
    finish(fig, ax, ax[0], 6, figs, "stress_paths")
    # Peaks and critical states: the monotonic shears; cyclic ones have their own section.
    mono = [r for r in runs if r[2]["monotonic"].any()]
    # strain_amplitude axis: the modulus-reduction section; the other cyclic tests: the liquefaction section
    # (cyclic oedometers, lateral walls held: neither a modulus-reduction nor a liquefaction test; their own section)
    coed = [r for r in runs if r[2]["cyclic_oedometric"].any()]
    amp = [r for r in runs if r[2]["cyclic"].any() and r[0].get("strain_amplitude", 0) > 0 and r not in coed]
    cyc = [r for r in runs if r[2]["cyclic"].any() and r[0].get("strain_amplitude", 0) <= 0 and r not in coed]
    oed = [r for r in runs if r[2]["oedometric"].any()]  # K0 tests: their own section
    peak = peak_settings(idx)  # how the peaks are taken (the study's peak block)
    peak_lines, cs_rows, share_rows, peak_I, cs_ok = [], [], [], [], []
    for j, d, s in mono:
        ps = peak_state(s, peak)
        direction = ("extension" if ps["ext"] else "compression") + (
            f", plane strain (b {ps['b']:g})" if s.get("plane_strain") else f", b = {ps['b']:g}" if ps["b"] > 0 else "")
        note = single_row_note(s, ps["m"], ps["rows"], ps["ang"], peak[1])
        if "M" not in ps:
            peak_lines.append(f"| {j['name']} | {j['mu_r']:g} | {j['drainage']} | {direction} | - | - | - | - | - | - | "
                              f"{note} |")
        else:
            # The inertial number at the largest stress ratio: a peak taken in a dense flow, I > QUASI_STATIC_I,
            # overstates the rate-independent one.
            if ps["I"] is not None:
                peak_I.append(ps["I"])
            qld = ps.get("q_peak_less_drag")
            peak_lines.append(f"| {j['name']} | {j['mu_r']:g} | {j['drainage']} | {direction} | "
                              f"{ps['q_peak'] / 1e3:.1f} | {number_text(qld / 1e3 if qld is not None else None, '.1f')} | "
                              f"{100 * ps['eps_peak']:.2f} | {ps['qp_peak']:.3f} | "
                              f"{ps['M']:.3f} ({ps['phi']:.1f}°) | {number_text(ps['I'], '.1e')} | "
                              f"{note} |")
        c = critical_state(s, cs_cfg["window"], *tol)
        if c is None:
            continue
        if c["ok"]:
            cs_rows.append(f"| {j['name']} | {j['mu_r']:g} | {direction} | yes | {c['p'] / 1e3:.1f} | {c['q'] / 1e3:.1f} | "
                           f"{c['e']:.4f} | {c['qp']:.3f} | {c['phi']:.1f} | {c['a_c']:.3f} | "
                           f"{quasi_static_text(c['I'], c['ke'])} | {number_text(c['e_inner'], '.4f')} | "
                           f"{number_text(c['M_walls'], '.3f')} | {number_text(c['M_less_drag'], '.3f')} | "
                           f"{number_text(c['M_inner'], '.3f')} |")
            cs_ok.append(c)
            share_rows.append(f"| {j['name']} | {j['mu_r']:g} | {c['sff_share_c']:.2f} | {c['sff_share_d']:.2f} | "
                              f"{c['sff_share_n']:.2f} | {c['sff_share_t']:.2f} | {c['qp']:.3f} | {c['sff']:.3f} |")
        else:
            cs_rows.append(f"| {j['name']} | {j['mu_r']:g} | {direction} | no: {c['why']} | | | | | | | | | | | | |")
    measures_note = stress_measures_note(cs_ok)
    csl_text, states = csl([(d, s) for _, d, s in mono], figs, cs_cfg["window"], tol, quiet=True)
    cyc_lines = cyclic_section(cyc, figs, colors, fits) if cyc else []
    fail_lines = failure_section(mono, cs_cfg["window"], tol, figs, peak)
    fail_lines += flow_section(mono, cs_cfg["window"], tol, figs, peak)
    rate_lines = rate_section(mono, cs_cfg["window"], tol, figs, peak)
    seed_lines = seed_section(mono, cs_cfg["window"], tol, figs, peak)
    more_figs = ["`figures/liquefaction.png`"] if cyc else []
    # the samples' isotropic compression and swelling (a base that consolidates in several stages); in a study.json of
    # a build before its samples list, the samples its jobs name
    sample_jobs = idx.get("samples") or list({j["sample"]: {"name": j["sample"], "seed": j.get("seed")}
                                              for j in idx["jobs"] if j.get("sample")}.values())
    comp_lines, comp_fig = compression_section(out, sample_jobs, figs)
    if comp_fig:
        more_figs.append("`figures/compression.png`")
    oed_lines = oedometric_section(oed, figs, mono, (cs_cfg["window"], *tol), peak) if oed else []
    if oed:
        more_figs.append("`figures/oedometric.png`")
    if amp:
        cyc_lines += modulus_section(amp, idx.get("strain_stage", ""), figs)
        more_figs.append("`figures/modulus_reduction.png`")
    if coed:
        cyc_lines += cyclic_oedometer_section(coed, figs)
        more_figs.append("`figures/cyclic_oedometer.png`")
    # Shares at critical state, per mu_r, direction and rate (mean over its critical states), as the critical-state
    # lines are grouped: compression and extension need not share the stress ratio out alike between fabric and
    # forces, and a rate series must show how the shares move with I, not pool them.
    if states:
        fig, ax = plt.subplots(figsize=(7, 4))
        keys = sorted({(c["mu_r"], c["ext"], c["b"], c["rate"]) for _, c in states})
        several_rates = len({k[3] for k in keys}) > 1
        bottom = np.zeros(len(keys))
        for key, lab in zip("cdnt", ["a_c", "a_d", "a_n", "3/2 a_t"]):
            vals = [np.mean([c["sff_share_" + key] for _, c in states if (c["mu_r"], c["ext"], c["b"], c["rate"]) == k])
                    for k in keys]
            ax.bar([f"{mu:g}" + (" ext." if ext else "")
                    + (" p.s." if bv == PLANE_STRAIN else f" b={bv:g}" if bv > 0 else "")
                    + (rate_text(rate, " ") if several_rates else "") for mu, ext, bv, rate in keys], vals,
                   bottom=bottom, label=lab)
            bottom += np.array(vals)
        ps_txt = "; p.s.: plane strain" if any(k[2] == PLANE_STRAIN for k in keys) else ""
        ax.set(xlabel=f"mu_r (ext.: triaxial extension{ps_txt})" + (", axial strain rate" if several_rates else ""),
               ylabel="share of 2/5 (a_c + a_d + a_n + 3/2 a_t)",
               title="stress-force-fabric shares at critical state")
        legend(ax, fontsize=8)
        save(fig, figs, "sff_shares")
    head = [f"# Study report: {idx['study']}", "",
            f"{len(runs)} shear tests finished" + (f"; not (yet) finished: {', '.join(missing)}" if missing else "") + ".",
            ""]
    # A test's own isotropic stage (a reconsolidation between its shears; its sample's stages are the sample job's,
    # marked in the Samples section) that ran out of steps: the shears after it start out of equilibrium.
    if unconv := [f"{j['name']} ({', '.join(left)})" for j, _, _ in runs if (left := unconverged(out, j["name"]))]:
        head += [f"**NOT converged:** {len(unconv)} of {len(runs)} tests: {', '.join(unconv)}: an isotropic stage of "
                 "the test (a reconsolidation between its shears) ran out of steps: it reached its max_steps before the "
                 "pressure, unbalanced-force and kinetic-energy criteria held (summary.json done: false), so the shears "
                 "after it start from a sample not in equilibrium at its pressure; raise that stage's max_steps.", ""]
    if (cyc or amp or oed or coed) and not mono:  # a cyclic or K0 study: peaks and critical states are those of monotonic shears
        lines = (head + ["Figures: " + ", ".join(["`figures/stress_paths.png`"] + more_figs) + ".", ""]
                 + samples_section(out, idx["jobs"], idx.get("samples")) + comp_lines
                 + oed_lines + cyc_lines + size_classes.report_section(size_tests(out, runs)))
    else:
        # sff_shares.png is drawn of the critical states only (none: not drawn, not named)
        lines = [*head, "Figures: `figures/stress_paths.png`, `figures/csl.png`"
             + (", `figures/sff_shares.png`" if states else "") + "".join(", " + f for f in more_figs) + ".", "",
             "## Peak states", "",
             "The peak of |q| along the loading (q from the walls, < 0 in extension); the stress ratio M = q/p' of the "
             "contact stress (q = sqrt(3/2 s:s) >= 0) there and at its largest, with the mobilised friction angle "
             "(Mohr-Coulomb: sin phi' = 3M / (6 + M) in compression, 3M / (6 - M) in extension; a true-triaxial test, b > 0: "
             "sin phi' = (sigma_1 - sigma_3) / (sigma_1 + sigma_3) of the wall stresses). q_peak less drag is the peak "
             "of the walls' q less the local damping's drag (series q_drag; the drag grows with the strain rate and "
             "the damping, the walls' q overstates the material's by it), \"-\" where the series did not measure it. "
             + peak_text(*peak), "",
             "| test | mu_r | drainage | direction | q_peak [kPa] | q_peak less drag [kPa] | eps_a at peak [%] "
             "| q/p' at peak | max q/p' (phi'_max) | I at max q/p' | largest single row |",
             "|---|---|---|---|---|---|---|---|---|---|---|", *peak_lines, "",
             *([peak_inertial_note(peak_I), ""] if peak_inertial_note(peak_I) else []),
             "## Critical states", "",
             f"A test is at critical state when, over the last {cs_cfg['window']:g} of axial strain, the drift of q/p' (slope of a least-squares line times the window) is below "
             f"{tol[0]:g}, of p'/p'_end below {tol[1]:g} and of e below {tol[2]:g}; other tests are listed but not fitted, "
             "each drift ± its standard error (widened for the rows' serial correlation), and marked where every drift "
             "is within two standard errors of its tolerance: a longer window would tell. "
             "I is the mean inertial number eps_dot d_mean sqrt(rho / p') over the window (quasi-static below "
             f"{QUASI_STATIC_I:g}) and KE/E_el the mean kinetic energy of the skeleton about its affine motion over "
             "its elastic energy (ke_fluct_ratio; ke_ratio, with the imposed motion, in runs of older builds). e_c "
             "interior is the window's mean void ratio of the box inset by two mean diameters (series e_inner): e_c "
             "counts the looser layer along the walls, whose share falls as count^(-1/3) (configs/size-study.yaml). "
             + STRESS_MEASURES_TEXT, "",
             "| test | mu_r | direction | critical | p'_c [kPa] | q_c [kPa] | e_c | q/p' | phi_cs [°] | a_c | I | KE/E_el "
             "| e_c interior | q/p' walls | q/p' walls less drag | q/p' interior |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
             *cs_rows, "", *([measures_note, ""] if measures_note else []), "## Critical-state lines (least squares, ± one standard error)", "", csl_text, "",
             "## Stress-force-fabric shares at critical state", "",
             "| test | mu_r | a_c | a_d | a_n | 3/2 a_t | q/p' | 2/5 sum |", "|---|---|---|---|---|---|---|---|", *share_rows, "",
             *localisation_section([(j["name"], d) for j, d, _ in mono], cs_cfg["window"]),
             *(x for ext in (False, True) for x in dilatancy_section(mono, cs_cfg["window"], tol, figs, peak, ext)),
             *(x for ext in (False, True) for x in state_parameter_section(mono, states, cs_cfg["window"], tol, figs,
                                                                             peak, ext=ext)),
             *(x for ext in (False, True) for x in undrained_state_section(mono, states, cs_cfg["window"], tol, figs,
                                                                             peak, ext=ext)),
             *stiffness_section(mono, figs),
             *contacts_section([(j["name"], d) for j, d, _ in mono]),
             *size_classes.report_section(size_tests(out, mono)),
             *fail_lines, *rate_lines, *seed_lines, *samples_section(out, idx["jobs"], idx.get("samples")), *comp_lines, *oed_lines, *cyc_lines]
    if figs_rel == "figures":
        return lines
    # the text names the study's figures (in backquotes) where this part of the study saved them; a run's own
    # figures/ (`grainlab plot` on a test's run: "(figures/localisation.png)") stay as they are
    return [x.replace("`figures/", f"`{figs_rel}/") for x in lines]


def dilatancy_section(mono, window, tol, figs, peak=(0.0, None), ext=False):
    """Stress and dilatancy of the drained compression (ext: extension) tests (b = 0; scripts/dilatancy.py): each
    test's largest dilation rate and angle against its peak and critical-state friction angles (Bolton's triaxial
    relation), and Rowe's K and phi_f beside phi'_cs and the grains' friction; figures/stress_dilatancy.png
    (stress_dilatancy_extension.png). Empty without such tests."""
    rows, fits, figdata = [], [], []
    for j, d, s in mono:
        ps = peak_state(s, peak)
        if j["drainage"] != "drained" or ps["ext"] != ext or ps["b"] > 0 or "M" not in ps or "eps_v" not in s:
            continue
        m = s["monotonic"]
        a = dilatancy.analyse(s["eps_a"][m], s["eps_v"][m], s["q_p"][m], extension=ext)
        c = critical_state(s, window, *tol)
        cs = c["phi"] if c is not None and c["ok"] else None
        phi_mu = math.degrees(math.atan(float(s["mu"][m][-1]))) if "mu" in s else None
        sig = a["psi_max"] == a["psi_max"]
        bolton = (ps["phi"] - cs) / a["neg_d_max"] if cs is not None and sig and a["neg_d_max"] > 0 else None
        rows.append(f"| {j['name']} | {j['mu_r']:g} | {ps['phi']:.1f} | {number_text(cs, '.1f')} | "
                    f"{a['neg_d_max']:.3f} ± {a['se']:.3f} ({100 * a['eps_max']:.1f}) | "
                    f"{number_text(a['psi_max'], '.1f')} | {number_text(bolton, '.1f')} | {a['K']:.3f} | "
                    f"{a['phi_f']:.1f} ({a['rms']:.3f}) | {number_text(phi_mu, '.1f')} |")
        if cs is not None and a["phi_f"] == a["phi_f"]:
            fits.append(a["phi_f"] - cs)
        figdata.append((j, s, m, a))
    if not rows:
        return []
    # along the loading: eps_l = eps_a in compression, -eps_a in extension (dilatancy.py)
    sign, eps_l = (-1, "-eps_a") if ext else (1, "eps_a")
    figname = "stress_dilatancy" + ("_extension" if ext else "")
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.4))
    for j, s, m, a in figdata:
        line, = ax[0].plot(100 * sign * s["eps_a"][m], -a["d"], label=j["name"])
        R, D = dilatancy.principal_ratio(s["q_p"][m], ext), dilatancy.rowe_dilatancy(a["d"], ext)
        k0 = a["turn"]  # Rowe's fit starts there
        ax[1].plot(D[k0:], R[k0:], ".", ms=3, color=line.get_color())
        if np.isfinite(D[k0:]).any():  # a shear too short for a rate has no fit to draw (numpy warned here)
            xs = np.array([np.nanmin(D[k0:]), np.nanmax(D[k0:])])
            ax[1].plot(xs, a["K"] * xs, "-", lw=1, color=line.get_color())
    ax[0].axhline(0, color="0.5", lw=0.8)
    d_txt = "d eps_v / d(-eps_a)" if ext else "d eps_v / d eps_a"
    ax[0].set(xlabel=f"{eps_l} [%]", ylabel=f"-{d_txt} (> 0 dilating)", title="dilatancy rate")
    ax[1].set(xlabel="1 / (1 + d)" if ext else "1 - d eps_v / d eps_a", ylabel="sigma_1 / sigma_3 (contact stress)",
              title=f"Rowe: sigma_1/sigma_3 = K {'/ (1 + d)' if ext else '(1 - d)'}, from the largest contraction on")
    finish(fig, ax, ax[0], 6, figs, figname)
    note = (f"Over the tests that reached critical state, phi_f - phi'_cs is {min(fits):+.1f} to {max(fits):+.1f}°."
            if fits else "")
    if ext:
        text = ("The drained extensions (the axial walls move apart at constant sigma_3: eps_a < 0, q < 0). The "
                f"dilatancy rate d = {d_txt} along the loading (compression positive; < 0 dilating), as in "
                "compression the slope of a line through the rows within "
                f"{dilatancy.WINDOW / 2:g} of axial strain either side, with its standard error; its largest dilation, "
                "(-d)_max, at the axial strain given, and the dilation angle of triaxial extension there, sin psi = "
                "-d / (2 + d) (the two lateral strain increments the major ones; '-' where (-d)_max is within "
                f"{dilatancy.SIGNIFICANT:g} standard errors of 0). (phi'_max - phi'_cs) / (-d)_max: Bolton's (1986) "
                "10 is for triaxial compression; the ratio is given to compare with the compression section. Rowe's "
                "stress-dilatancy in extension (Rowe, Barden & Lee 1964), sigma_1/sigma_3 = K (-d eps_3 / 2 d eps_1) "
                "= K / (1 + d), fitted from the largest contraction to the end (the principal stress ratio (3 + q/p') "
                "/ (3 - 2 q/p') of the contact stress, q/p' = |q|/p'), gives phi_f = asin((K - 1)/(K + 1)) with the "
                f"rms of the relative residuals. `figures/{figname}.png` draws d against -eps_a and each test's Rowe "
                "line. ")
    else:
        text = ("The dilatancy rate d = d eps_v / d eps_a (compression positive; < 0 dilating) is the slope of a line "
                f"through the rows within {dilatancy.WINDOW / 2:g} of axial strain either side (wider where the rows "
                "are sparser), with its standard error; its largest dilation, (-d)_max, at the strain given, and the "
                "dilation angle of triaxial strain there, sin psi = -d / (2 - d) ('-' where (-d)_max is within "
                f"{dilatancy.SIGNIFICANT:g} standard errors of 0: no dilatancy to speak of). Bolton (1986) gives for "
                "triaxial strain phi'_max - phi'_cs = 10 (-d)_max degrees: the column gives the measured ratio, to "
                "read against 10. Rowe's stress-dilatancy sigma_1/sigma_3 = K (1 - d), fitted from the largest "
                "contraction to the end (the principal stress ratio (3 + 2 q/p') / (3 - q/p') of the contact "
                "stress), gives phi_f = asin((K - 1)/(K + 1)), with the rms of the relative residuals; Rowe read "
                "phi_f between the grains' friction phi_mu = atan(mu) and phi'_cs. `figures/stress_dilatancy.png` "
                "draws d against eps_a and each test's Rowe line. ")
    return ["## Stress and dilatancy (drained " + ("extension)" if ext else "compression)"), "", text + note, "",
            "| test | mu_r | phi'_max [°] | phi'_cs [°] | (-d)_max ± se (eps_a %) | psi_max [°] | (phi'_max - phi'_cs) / "
            "(-d)_max [°] | Rowe K | phi_f [°] (rms) | phi_mu [°] |",
            "|---|---|---|---|---|---|---|---|---|---|", *rows, ""]


def line_groups(states):
    """csl_groups' groups of critical states (per mu_r, direction, b and rate) with a line: three pressure levels or
    more (pressure_levels)."""
    return {k: g for k, g in csl_groups(states).items() if pressure_levels([c["p"] for c in g]) >= 3}


def line_tests(mono, groups, peak, drainage, usable, ext=False):
    """The compression (ext: extension) tests (b = 0) of a drainage in mono ((job, run directory, series) each) whose
    group has a line (line_groups: an extension's is the line of the extensions) and which usable(series, peak_state)
    accepts: (job, series, its peak_state, its monotonic rows, the group's key, the line's p'_c [kPa] and e_c, the
    shear's p'_0 [kPa] and e_0 at its first row) each."""
    for j, _, s in mono:
        ps = peak_state(s, peak)
        if j["drainage"] != drainage or ps["ext"] != ext or ps["b"] > 0 or not usable(s, ps):
            continue
        m = s["monotonic"]
        key = (s["mu_r"][m][-1], ext, ps["b"], float(s.get("rate", 0.0)))
        if key not in groups:
            continue
        r0 = int(np.flatnonzero(ps["m"])[0])  # the shear's first row: its e_0 and p'_0
        yield (j, s, ps, m, key, [c["p"] / 1e3 for c in groups[key]], [c["e"] for c in groups[key]],
               float(s["p"][r0]) / 1e3, float(s["e"][r0]))


def line_text(groups, key, several_rates):
    """(label, text) of a group's line in the state-parameter sections: its mu_r (and rate, where the tests have
    several), and e_c = a + b p' with standard errors through its critical states (their count and pressures)."""
    label = f"{key[0]:g}" + (rate_text(key[3], ", ") if several_rates else "")
    pc = np.array([c["p"] / 1e3 for c in groups[key]])
    b, a, sb, sa = fit(pc, np.array([c["e"] for c in groups[key]]))
    return label, (f"mu_r {label}: e_c = {a:.4f} ± {sa:.4f} + ({b:.3e} ± {sb:.1e}) p' [kPa] through {len(pc)} "
                   f"critical states at p'_c {pc.min():.0f}–{pc.max():.0f} kPa")


def psi_fit(label, name, fmt, x, y, e0):
    """A measure y (its table name and format) on a least-squares line in a state parameter x over the tests where both
    are finite, three or more with x and e_0 spread: (the line's value at x = 0, its slope, and the row of the state
    tables: both ± one standard error, the rms of its residuals and, beside it, the rms about a line in e_0 alone);
    None with too few."""
    ok = np.isfinite(y) & np.isfinite(x)
    if ok.sum() < 3 or np.ptp(x[ok]) <= 0 or np.ptp(e0[ok]) <= 0:
        return None
    B, A, sB, sA = fit(x[ok], y[ok])
    rms = float(np.sqrt(np.mean((y[ok] - A - B * x[ok]) ** 2)))
    Be, Ae, _, _ = fit(e0[ok], y[ok])
    rms_e = float(np.sqrt(np.mean((y[ok] - Ae - Be * e0[ok]) ** 2)))
    return A, B, (f"| {label} | {int(ok.sum())} | {name} | {A:{fmt}} ± {sA:{fmt}} | {B:{fmt}} ± {sB:{fmt}} | "
                  f"{rms:{fmt}} | {rms_e:{fmt}} |")


def state_parameter_section(mono, states, window, tol, figs, peak=(0.0, None), heads=None, title=None, figname=None,
                            lead="", ext=False):
    """The state parameter psi_0 = e_0 - e_c(p'_0) (Been & Jefferies 1985) of the drained compression tests (b = 0):
    the void ratio at the start of the shear less the critical-state line's at the same p' (csl's line e_c = a + b p',
    per mu_r and rate, through the study's own critical states at three pressure levels or more, dense and loose
    tests alike), beside the test's peak friction over the line's phi'_cs and its largest dilatancy (-d)_max
    (dilatancy.analyse, as the stress-dilatancy table); over three tests or more of a line, each measure's line in
    psi_0 and, for comparison, in e_0 alone: whether psi_0 gathers density and pressure into one relation (Been &
    Jefferies's finding for sands), which e_0 cannot where the pressures differ. psi_end: the end window's e less the
    line's at its p' (about 0 on the line). Empty without such a test in a group with a line. heads: the test's name ->
    its section's heading (a column of its own: the table across a stage axis's values, which pools them); title, the
    figure's name and a lead sentence for that use. ext: the drained extensions (b = 0) instead, on the line of the
    extensions' critical states (csl's groups: M_e is not M_c), their dilatancy along -eps_a (dilatancy.py)."""
    direction = "extension" if ext else "compression"
    title = title or f"## State parameter (drained {direction})"
    figname = (figname or "state_parameter") + ("_extension" if ext else "")
    groups = line_groups(states)
    tests = {}
    for j, s, ps, m, key, pc, ec, p0, e0 in line_tests(mono, groups, peak, "drained",
                                                       lambda s, ps: "M" in ps and "eps_v" in s, ext):
        e_line, se_line = line_at(pc, ec, p0)
        c = critical_state(s, window, *tol)
        psi_end = (float(c["e"]) - line_at(pc, ec, float(c["p"]) / 1e3)[0], c["ok"]) if c and "e" in c else None
        a = dilatancy.analyse(s["eps_a"][m], s["eps_v"][m], s["q_p"][m], extension=ext)
        phi_cs = friction_angle(float(np.mean([x["M"] for x in groups[key]])), ext)
        # psi where the test dilates fastest (the row of (-d)_max): Nor-Sand's D_min = chi psi is in the current state
        # (Jefferies 1993), which a sample that contracts first reaches denser than it started
        psi_d, outside_d = float("nan"), False
        if np.isfinite(a["d"]).any():
            k_d = int(np.nanargmin(a["d"]))
            p_d = float(s["p"][m][k_d]) / 1e3
            psi_d, outside_d = float(s["e"][m][k_d]) - line_at(pc, ec, p_d)[0], not min(pc) <= p_d <= max(pc)
        tests.setdefault(key, []).append(dict(
            name=j["name"], mu_r=j["mu_r"], p0=p0, e0=e0, e_line=e_line, se_line=se_line, psi0=e0 - e_line,
            outside=not min(pc) <= p0 <= max(pc), psi_end=psi_end, phi=ps["phi"], dphi=ps["phi"] - phi_cs,
            phi_cs=phi_cs, d=a["neg_d_max"], d_se=a["se"], psi_d=psi_d, outside_psi_d=outside_d))
    if not tests:
        return []
    several_rates = len({k[3] for k in tests}) > 1
    rows, fit_rows, outside, lines_txt = [], [], False, []
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.4))
    for key, g in sorted(tests.items()):
        label, line_txt = line_text(groups, key, several_rates)
        lines_txt.append(f"{line_txt}, phi'_cs {g[0]['phi_cs']:.1f}°")
        for t in g:
            outside |= t["outside"]
            end = ("-" if t["psi_end"] is None else
                   f"{t['psi_end'][0]:+.4f}" + ("" if t["psi_end"][1] else " (not critical)"))
            rows.append(("" if heads is None else f"| {heads[t['name']]} ") +
                        f"| {t['name']} | {label} | {t['p0']:.1f} | {t['e0']:.4f} | {t['e_line']:.4f} ± "
                        f"{t['se_line']:.4f}{' *' if t['outside'] else ''} | {t['psi0']:+.4f} | {end} | "
                        f"{t['phi']:.1f} | {t['phi_cs']:.1f} | "
                        f"{t['dphi']:+.1f} | {number_text(t['d'], '.3f')} ± {number_text(t['d_se'], '.3f')} | "
                        f"{number_text(t['psi_d'], '+.4f')} |")
        e0 = np.array([t["e0"] for t in g])
        for k_ax, (col, xcol, name, fmt) in enumerate(STATE_PARAMETER_FITS):
            x, y = np.array([t[xcol] for t in g]), np.array([t[col] for t in g])
            ok = np.isfinite(y) & np.isfinite(x)
            pts = ax[k_ax].plot(x[ok], y[ok], "o", label=f"mu_r = {label}")[0]
            for t in g:  # a psi from the line beyond its critical states' pressures: hollow
                if t["outside" if xcol == "psi0" else "outside_psi_d"] and math.isfinite(t[col]) and \
                        math.isfinite(t[xcol]):
                    ax[k_ax].plot([t[xcol]], [t[col]], "o", mfc="white", color=pts.get_color())
            line = psi_fit(label, name, fmt, x, y, e0)
            if line is not None:
                xs = np.linspace(x[ok].min(), x[ok].max(), 2)
                ax[k_ax].plot(xs, line[0] + line[1] * xs, "-", lw=1, color=pts.get_color())
                fit_rows.append(line[2])
    for a_, (_, xcol, yl, _) in zip(ax, STATE_PARAMETER_FITS):
        a_.axhline(0, color="0.5", lw=0.8)
        a_.axvline(0, color="0.5", lw=0.8)
        a_.set(xlabel="psi_0 = e_0 - e_c(p'_0)" if xcol == "psi0" else "psi at (-d)_max", ylabel=yl.split(" on ")[0])
        a_.grid(alpha=0.3)
        legend(a_, fontsize=8)
    save(fig, figs, figname)
    return [title, "", lead +
            ("Extensions (b = 0) on the line of the extensions' critical states (the lines are fitted per direction: "
             "extension reaches the critical state at another stress ratio); their dilatancy d = d eps_v / "
             "d(-eps_a), along the loading. " if ext else "") +
            "The state parameter psi_0 = e_0 - e_c(p'_0) (Been & Jefferies 1985; not the dilation angle psi_max "
            "above): the void ratio at the start of the shear less the critical-state line's (the section above: "
            "e_c = a + b p', through the critical states of the tests of its mu_r and rate, dense and loose alike) at "
            "the same p', with the line's standard error there; < 0 denser than critical (the test dilates to reach "
            "the line), > 0 looser. psi_end: the end window's e less the line's at its p' (about 0 on the line; "
            "'(not critical)': the end window drifted). phi'_cs: the line's (its critical states' mean q/p'); "
            "phi'_max and (-d)_max as in the tables above; psi at (-d)_max: e less the line's e_c at the p' of the "
            "row where the test dilates fastest, the current state that Nor-Sand's D_min = chi psi takes (Jefferies "
            f"1993; its D = d eps_v / d eps_q, here d = d eps_v / d {'(-eps_a)' if ext else 'eps_a'}): a sample that "
            "contracts first reaches it denser than it started." +
            (" *: p'_0 outside the pressures of the line's critical states (e_c extrapolated along the line; a drained "
             f"shear at constant sigma_3 ends at a {'lower' if ext else 'higher'} p' than it starts)." if outside
             else "") +
            f" `figures/{figname}.png` draws the three lines below (hollow: a psi from the line beyond its critical "
            "states' pressures). The line" +
            ("s: " if len(lines_txt) > 1 else ": ") + "; ".join(lines_txt) + ".",
            "", ("" if heads is None else "| section ") + "| test | mu_r | p'_0 [kPa] | e_0 | e_c(p'_0) | psi_0 "
            "| psi_end | phi'_max [°] | phi'_cs [°] | phi'_max - phi'_cs [°] | (-d)_max ± se | psi at (-d)_max |",
            "|---" * (12 if heads is None else 13) + "|", *rows, "",
            *(["Each measure on a least-squares line in a psi (its value at psi = 0, where the line puts the critical "
               "state, and its slope, ± one standard error) and the rms of its residuals beside the rms about a line "
               "in e_0 alone: one relation in psi for density and pressure together leaves the smaller residuals "
               "where the tests' pressures differ.", "",
               "| mu_r | tests | measure | at psi = 0 | slope | rms | rms about a line in e_0 |",
               "|---|---|---|---|---|---|---|", *fit_rows, ""] if fit_rows else [])]


# The share of p'_0 that r_u = u / p'_0 must reach for a monotonic undrained test to count as liquefied: a cyclic
# stage's default liquefaction_ru (src/config.hpp), initial liquefaction (Seed & Lee 1966), p' at 5 % of p'_0 or less.
LIQUEFIED_RU = 0.95
# How far p' must rise after its least (single rows) in an undrained test for that least to be a phase transformation
# (contraction turning into dilation, Ishihara, Tatsuoka & Yasuda 1975) rather than a fluctuation: by PT_RISE of the
# least and PT_REGAIN of p'_0 both. configs/state-parameter-undrained-study.yaml (5 000 spheres): p' at a steady end
# fluctuates by a standard deviation of 1.5-5 % (a range of 5-15 %) of itself, far below PT_RISE; a liquefied
# sample's p' (below 1 % of p'_0) by about 40 % of itself, within a range under 1 % of p'_0, far below PT_REGAIN;
# the medium samples' transformations rise 1.7 to 73 times their least, and the loose ones re-jam by 19-25 % of p'_0
# within 40 % of strain.
PT_RISE = 0.5
PT_REGAIN = 0.1


def undrained_response(s, rows, ext=False):
    """The shape of an undrained compression (ext: extension, q taken along the loading, -q, and the q returned < 0)
    over its rows (in time order, single rows: a loose sample's instability
    peaks within the first per cent of strain, which the peak window, 2 % in the studies that set one, would smear): the
    largest fall of q below its running maximum relative to that maximum, which a contractive sample's instability
    makes, up to the least p' (q_pk at eps_pk, the trough q_min at eps_min after it, and the brittleness index I_B =
    (q_pk - q_min) / q_pk, Bishop 1967 with the trough for his residual: 0 where q never falls, 1 where it falls to
    nothing; a few per cent are a contracting sample's fluctuation; eta_pk: the contacts' q/p' at q_pk, Lade's
    instability line); the least p' (p_min at eps_pmin) and whether p' rises past it after it (PT_RISE, PT_REGAIN), a
    phase transformation (pt: the contacts' q/p' there; None where p' falls to the end or rises from the first row, or
    where the least is liquefied, r_u >= LIQUEFIED_RU: regains, a re-jamming); r_u = u / p'_0 at its largest (ru_max, u
    the series' pore pressure; None without the column)."""
    sign = -1.0 if ext else 1.0
    q, p, ea = sign * s["q"][rows], s["p"][rows], s["eps_a"][rows]
    k_pt = int(np.argmin(p))
    # q falls in an undrained compression only while p' does (a contraction): the fall is sought up to the least p',
    # past which a dilating sample's q rises toward, and then fluctuates about, its critical state (by up to 15 % on
    # 5 000 spheres near 300 kPa, configs/state-parameter-undrained-study.yaml), which is no instability
    top = np.maximum.accumulate(q[:k_pt + 1])
    fall = np.where(top > 0, (top - q[:k_pt + 1]) / np.where(top > 0, top, 1.0), 0.0)
    k_min = int(np.argmax(fall))
    k_pk = int(np.argmax(q[:k_min + 1]))
    pt = None
    rise = float(np.max(p[k_pt:]) - p[k_pt])
    regains = False
    if 0 < k_pt and rise > PT_RISE * p[k_pt] and rise > PT_REGAIN * p[0]:
        # past r_u = LIQUEFIED_RU the skeleton has gone: a few contacts' q/p' is no transformation's stress ratio, and
        # the rise is the sample's re-jamming at constant volume
        regains = bool(p[k_pt] <= (1 - LIQUEFIED_RU) * p[0])
        pt = None if regains else float(s["q_p"][rows][k_pt])
    p0 = float(p[0])
    ru = float(np.nanmax(s["u"][rows])) / p0 if "u" in s and p0 > 0 else None
    return dict(q_pk=sign * float(q[k_pk]), eps_pk=float(ea[k_pk]), eta_pk=float(s["q_p"][rows][k_pk]),
                q_min=sign * float(q[k_min]),
                eps_min=float(ea[k_min]), ib=float(fall[k_min]), p_min=float(p[k_pt]), eps_pmin=float(ea[k_pt]), pt=pt,
                regains=regains,
                ru_max=ru if ru is not None and math.isfinite(ru) else None)


UNDRAINED_STATE_FITS = (("ib", "I_B on psi_0", ".3f"), ("p_min_p0", "p'_min / p'_0 on psi_0", ".3f"))


def undrained_state_section(mono, states, window, tol, figs, peak=(0.0, None), heads=None, title=None, figname=None,
                            lead="", ext=False):
    """The undrained compression tests (b = 0) against the critical-state line of their mu_r and rate (csl's e_c =
    a + b p', through the critical states of every test of the group, drained and undrained: SPEC §7 fits one line
    through both, the critical state's uniqueness): each test's state parameter psi_0 = e_0 - e_c(p'_0) (Been &
    Jefferies 1985) and the p' at which the line says it ends, the line's p' at its void ratio (a constant-volume test
    keeps e_0): (e_0 - a) / b, less than p'_0 for psi_0 > 0, none (liquefaction) where e_0 >= a with b < 0, the line
    below e_0 at every p' > 0; beside the measured end (critical_state's window), the instability (undrained_response:
    q's first peak, its trough and the brittleness I_B), the phase transformation and r_u at its largest. Over three
    tests or more of a line, I_B and p'_min / p'_0 on a line in psi_0 and, for comparison, in e_0 alone. heads, title,
    figname and lead as state_parameter_section's; ext: the undrained extensions (b = 0) on the extensions' line, q
    along the loading (its peak and trough < 0). Empty without such a test in a group with a line."""
    direction = "extension" if ext else "compression"
    title = title or f"## State parameter (undrained {direction})"
    figname = (figname or "state_parameter_undrained") + ("_extension" if ext else "")
    groups = line_groups(states)
    tests = {}
    for j, s, ps, _, key, pc, ec, p0, e0 in line_tests(mono, groups, peak, "undrained", lambda s, ps: len(ps["rows"]),
                                                       ext):
        b_, a_, _, _ = fit(np.array(pc), np.array(ec))
        e_line, se_line = line_at(pc, ec, p0)
        # the line's p' at e_0, with the line's standard error there carried along it (se_e / |b|)
        p_pred, se_pred = None, None
        if b_ < 0:
            p_pred = max((e0 - a_) / b_, 0.0)
            se_pred = line_at(pc, ec, p_pred)[1] / abs(b_)
        c = critical_state(s, window, *tol)
        end = None
        if c and "e" in c:
            end = dict(p=float(c["p"]) / 1e3, ok=c["ok"], psi=float(c["e"]) - line_at(pc, ec, float(c["p"]) / 1e3)[0])
        r = undrained_response(s, ps["rows"], ext)
        tests.setdefault(key, []).append(dict(
            name=j["name"], p0=p0, e0=e0, e_line=e_line, se_line=se_line, psi0=e0 - e_line,
            outside=not min(pc) <= p0 <= max(pc), p_pred=p_pred, se_pred=se_pred,
            pred_outside=p_pred is not None and not min(pc) <= p_pred <= max(pc), end=end,
            ib=r["ib"], p_min_p0=r["p_min"] / 1e3 / p0, r=r,
            path=(s["p"][ps["rows"]] / 1e3 / p0, s["q"][ps["rows"]] / 1e3 / p0), M=float(np.mean(
                [x["M"] for x in groups[key]])), M_walls=float(np.mean([x["M_walls"] for x in groups[key]]))
            if all(x.get("M_walls") is not None for x in groups[key]) else None))
    if not tests:
        return []
    several_rates = len({k[3] for k in tests}) > 1
    rows, fit_rows, lines_txt, resid = [], [], [], []
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.4))
    for key, g in sorted(tests.items()):
        label, line_txt = line_text(groups, key, several_rates)
        lines_txt.append(f"{line_txt}, M = {g[0]['M']:.3f}")
        for t in sorted(g, key=lambda t: (t["p0"], t["e0"])):
            r, end = t["r"], t["end"]
            if t["p_pred"] is None:
                pred = "-"
            elif t["p_pred"] <= 0:
                pred = "0 (liquefies)"
            else:
                pred = f"{t['p_pred']:.0f} ± {t['se_pred']:.0f}" + (" *" if t["pred_outside"] else "")
            if end is not None and end["ok"] and t["p_pred"] is not None:
                resid.append(end["p"] - t["p_pred"])
            end_txt = "- | -" if end is None else (f"{end['p']:.1f}" + ("" if end["ok"] else " (not critical)") +
                                                   f" | {end['psi']:+.4f}")
            soft = r["ib"] > 0
            ru = r["ru_max"]
            rows.append(("" if heads is None else f"| {heads[t['name']]} ") +
                        f"| {t['name']} | {label} | {t['p0']:.1f} | {t['e0']:.4f} | {t['psi0']:+.4f}"
                        f"{' *' if t['outside'] else ''} | {pred} | {end_txt} | "
                        + (f"{r['q_pk'] / 1e3 / t['p0']:.3f} ({100 * r['eps_pk']:.1f}) | {r['eta_pk']:.3f} | "
                           f"{r['q_min'] / 1e3 / t['p0']:.3f} ({100 * r['eps_min']:.1f})" if soft else "- | - | -") +
                        f" | {r['ib']:.3f} | {t['p_min_p0']:.3f} ({100 * r['eps_pmin']:.1f}) | " +
                        ("- (regains)" if r["regains"] else "-" if r["pt"] is None else f"{r['pt']:.3f}") + " | " +
                        ("- |" if ru is None else f"{ru:.3f}{' (liquefied)' if ru >= LIQUEFIED_RU else ''} |"))
        (ln,) = ax[1].plot([], [])
        for t in g:
            ax[0].plot(*t["path"], "-", lw=1, label=f"p'_0 {t['p0']:.0f} kPa, psi_0 {t['psi0']:+.3f}")
            if t["end"] is not None and t["p_pred"] is not None:
                ax[1].plot([t["p_pred"]], [t["end"]["p"]], "o", color=ln.get_color(),
                           mfc=ln.get_color() if t["end"]["ok"] else "white")
        ax[1].plot([], [], "o", color=ln.get_color(), label=f"mu_r = {label}")
        pts = ax[2].plot([t["psi0"] for t in g], [t["ib"] for t in g], "o", color=ln.get_color(),
                         label=f"I_B, mu_r = {label}")[0]
        ax[2].plot([t["psi0"] for t in g], [t["p_min_p0"] for t in g], "s", mfc="white", color=ln.get_color(),
                   label=f"p'_min / p'_0, mu_r = {label}")
        e0 = np.array([t["e0"] for t in g])
        for col, name, fmt in UNDRAINED_STATE_FITS:
            x, y = np.array([t["psi0"] for t in g]), np.array([t[col] for t in g])
            line = psi_fit(label, name, fmt, x, y, e0)
            if line is not None:
                xs = np.linspace(np.nanmin(x), np.nanmax(x), 2)
                ax[2].plot(xs, line[0] + line[1] * xs, "-" if col == "ib" else ":", lw=1, color=pts.get_color())
                fit_rows.append(line[2])
        xs = np.linspace(0, max(max(float(np.max(t["path"][0])) for t in g), 1.0), 2)
        # the paths are the walls' p' and q (series p, q): their line is the walls' M at critical state
        # (STRESS_MEASURES_TEXT), the contacts' M where the states did not measure it
        ax[0].plot(xs, (-1 if ext else 1) * (g[0]["M_walls"] or g[0]["M"]) * xs, "--", color="0.4", lw=1)
    lim = max([1.0] + [v for a_ in ax[1].lines for v in (*a_.get_xdata(), *a_.get_ydata())])
    ax[1].plot([0, lim], [0, lim], "-", color="0.5", lw=0.8)
    ax[0].set(xlabel="p' / p'_0 (walls)", ylabel="q / p'_0 (walls)", title="stress paths (dashed: the walls' M)")
    ax[1].set(xlabel="p'_c from the line at e_0 [kPa]", ylabel="p' at the end [kPa]",
              title="end against the line (hollow: not critical)")
    ax[2].set(xlabel="psi_0 = e_0 - e_c(p'_0)", ylabel="I_B; p'_min / p'_0",
              title="brittleness I_B (filled), least p' (hollow)")
    for a_ in ax:
        a_.grid(alpha=0.3)
        legend(a_, fontsize=7)
    save(fig, figs, figname)
    resid_txt = ""
    if resid:
        resid_txt = (f" Of the {len(resid)} tests at critical state, the measured p'_end less the line's p'_c: " +
                     ", ".join(f"{int(round(x)):+d}" for x in resid) + " kPa.")
    return [title, "", lead +
            ("The undrained (constant-volume) extensions (b = 0: the axial walls move apart, q < 0; q's peak and "
             "trough below are taken along the loading, the largest |q| before its largest fall: q_pk and q_min < 0, "
             "I_B = (q_pk - q_min) / q_pk) against the critical-state line of the extensions of their mu_r and rate "
             if ext else "The undrained (constant-volume) compressions against the critical-state line of their mu_r "
             "and rate ") +
            "(the section above: e_c = a + b p' through the critical states of the group's tests, drained and "
            "undrained, as SPEC §7 fits it): psi_0 = e_0 - e_c(p'_0) (Been & Jefferies 1985), and the p' at which the "
            "line says the test ends: the line's p' at the test's void ratio, which a constant-volume test keeps, "
            "p'_c = (e_0 - a) / b ± the line's standard error there over |b|; below p'_0 where psi_0 > 0 (the loose "
            "sample contracts, its pore pressure rises), '0 (liquefies)' where the line lies below e_0 at every "
            "p' > 0 (e_0 >= a). p'_end and psi_end: the end window's p' and e less the line's at that p' (about 0 "
            "on the line; '(not critical)': the window drifted). The instability, on single rows (a loose sample's "
            "peak lies within the first per cent of strain, narrower than a peak window): q at the peak q_pk before "
            "its largest fall relative to the running maximum up to the least p' (past it the sample dilates: q rises "
            "toward its critical state and fluctuates there), and at the trough q_min of that fall, over p'_0 (axial "
            "strain in %), with the contacts' q/p' at q_pk (the instability line's stress ratio, Lade 1992), and the "
            "brittleness I_B = (q_pk - q_min) / q_pk (Bishop 1967, the trough for his residual: 1 where q falls to "
            "nothing; 0: q never falls, '-' for the peak and trough; a few hundredths: a fluctuation). p'_min: the "
            "least p' over p'_0 (its axial strain in %), and q/p' there "
            f"where p' rises after it by more than {100 * PT_RISE:g} % of it and {100 * PT_REGAIN:g} % of p'_0 (the "
            "phase transformation, Ishihara, Tatsuoka & Yasuda 1975, where contraction turns into dilation; '-' "
            "where p' falls to the end, or rises from the start, or only fluctuates about its least; '- (regains)' "
            f"where its least is liquefied, below {100 * (1 - LIQUEFIED_RU):.3g} % of p'_0: a few contacts' q/p' is no "
            "transformation's, and the rise a re-jamming at constant volume); r_u,max = u / "
            "p'_0 at its largest (u the series' pore pressure, SPEC §6; "
            f"'(liquefied)' from {LIQUEFIED_RU:g}, a cyclic stage's default liquefaction_ru)." +
            " *: p'_0 or p'_c outside the pressures of the line's critical states (the line extrapolated)." +
            f" `figures/{figname}.png`: the stress paths over p'_0 (the walls' p' and q, dashed "
            "their M at critical state), the measured end against the line's p'_c, and "
            "I_B and p'_min / p'_0 against psi_0. The line" + ("s: " if len(lines_txt) > 1 else ": ") +
            "; ".join(lines_txt) + "." +
            resid_txt,
            "", ("" if heads is None else "| section ") + "| test | mu_r | p'_0 [kPa] | e_0 | psi_0 | p'_c from the "
            "line [kPa] | p'_end [kPa] | psi_end | q_pk / p'_0 (eps_a %) | q/p' at q_pk | q_min / p'_0 (eps_a %) | I_B "
            "| p'_min / p'_0 (eps_a %) | q/p' at PT | r_u,max |",
            "|---" * (15 if heads is None else 16) + "|", *rows, "",
            *(["I_B and p'_min / p'_0 on a least-squares line in psi_0 (its value at psi = 0 and slope, ± one "
               "standard error), the rms of its residuals beside the rms about "
               "a line in e_0 alone.", "",
               "| mu_r | tests | measure | at psi = 0 | slope | rms | rms about a line in e_0 |",
               "|---|---|---|---|---|---|---|", *fit_rows, ""] if fit_rows else [])]


# The reference pressure of the stiffness fits E = E_ref (sigma'_3 / P_REF)^m: the hardening-soil model's p_ref
# (Schanz, Vermeer & Bonnier 1999, "The hardening soil model"), at which its E50_ref and E_ur_ref are given.
P_REF = 100e3


def drained_triaxial(st, direction):
    """A summary.json stage that is a drained triaxial test at constant sigma_3 (b = 0) in that direction."""
    return (st.get("type") == "triaxial" and st.get("drainage") == "drained" and st.get("direction") == direction
            and float(st.get("b", 0) or 0) == 0 and st.get("stress_path", "constant_sigma3") == "constant_sigma3")


def stiffness_state(d, s):
    """The drained triaxial stiffnesses of a run (d its directory, s its series; stages from summary.json). None without a
    first loading: the first drained compression stage at constant sigma_3 that starts from an isotropic stress (the
    first stage, from a sample file, or one after an isotropic stage: where the run's q_0 is 0). Else its p'_0 (=
    sigma'_3), q_peak: the largest q of the walls over the drained compressions from it to the next non-triaxial stage
    (a reloading goes on to the peak), `rising` where that is their last row (no peak: q still rose), E50 = (q_peak/2) /
    eps_a50 with eps_a50 where the first loading's q first reaches q_peak/2, between the rows about it (None where the
    loading stopped below it: a loop turned earlier), and `loops`: each drained extension stage right after a
    compression one, with E_ur (summary.json's E_sec, (q - q_0)/eps_a over the stage; from its last row for a build
    before it), nu_ur = -eps_r/eps_a over the stage (eps_r from its eps_v and eps_a as the run measures it: (1 - eps_v)
    = (1 - eps_a) (1 - eps_r)^2) and the q it unloaded from and to."""
    try:
        with open(os.path.join(d, "summary.json")) as f:
            stages = json.load(f).get("stages", [])
    except (OSError, ValueError):
        return None
    k0 = next((k for k, st in enumerate(stages) if drained_triaxial(st, "compression")
               and (k == 0 or stages[k - 1].get("type") == "isotropic")), None)
    if k0 is None:
        return None
    end = next((k for k in range(k0, len(stages)) if stages[k].get("type") != "triaxial"), len(stages))
    comp = np.zeros(len(s["q"]), dtype=bool)
    for st in stages[k0:end]:
        if drained_triaxial(st, "compression"):
            comp |= s["stage"] == st["name"]
    rows = np.flatnonzero(comp)
    if not len(rows):
        return None
    k_peak = rows[int(np.argmax(s["q"][rows]))]
    q_peak = float(s["q"][k_peak])
    first = s["stage"] == stages[k0]["name"]
    q1, e1 = s["q"][first], s["eps_a"][first]
    hit = np.flatnonzero(q1 >= q_peak / 2)
    E50 = None
    if len(hit) and q_peak > 0:
        k = int(hit[0])
        eps = e1[k] if k == 0 else e1[k - 1] + (e1[k] - e1[k - 1]) * (q_peak / 2 - q1[k - 1]) / (q1[k] - q1[k - 1])
        E50 = q_peak / 2 / eps if eps > 0 else None
    loops = []
    for k in range(k0 + 1, end):
        st = stages[k]
        if not (drained_triaxial(st, "extension") and drained_triaxial(stages[k - 1], "compression")):
            continue
        r = np.flatnonzero(s["stage"] == st["name"])
        if not len(r):
            continue
        ea = float(s["eps_a"][r[-1]])
        ev = float(s["eps_v"][r[-1]]) if "eps_v" in s else float("nan")
        E = st.get("E_sec")
        E = float(E) if E is not None else ((float(s["q"][r[-1]]) - float(st["q_0"])) / ea if ea else None)
        er = 1 - math.sqrt((1 - ev) / (1 - ea)) if math.isfinite(ev) else float("nan")
        # less the damping's drag (series q_drag): the loading's last row's at the turn, the unloading's last row's at
        # its end (the drag turns with the walls, so the walls' Δq counts both; NaN: a series without the column)
        r0 = np.flatnonzero(s["stage"] == stages[k - 1]["name"])
        less = float("nan")
        if "q_drag" in s and len(r0) and ea:
            less = ((float(s["q"][r[-1]]) - float(s["q_drag"][r[-1]])) - (float(st["q_0"]) - float(s["q_drag"][r0[-1]]))) / ea
        loops.append(dict(E=E, nu=-er / ea if ea else float("nan"), q_from=float(st["q_0"]), q_to=float(st["q"]),
                          E_less=less))
    return dict(p0=float(stages[k0]["p_0"]), q_peak=q_peak, rising=bool(k_peak == rows[-1]), E50=E50, loops=loops)


def power_fit(p, E):
    """ln E = ln E_ref + m ln(p / P_REF), least squares: (E_ref, its standard error, m, its standard error); None with
    fewer than 3 points or pressure levels below 2 (no slope; fit's standard errors need 3 points)."""
    p, E = np.asarray(p, dtype=float), np.asarray(E, dtype=float)
    if len(p) < 3 or pressure_levels(p) < 2:
        return None
    m, c, sm, sc = fit(np.log(p / P_REF), np.log(E))
    return math.exp(c), math.exp(c) * sc, m, sm


def stiffness_section(mono, figs):
    """The stiffness of the drained compression tests (stiffness_state): E50 of each first loading, E_ur and nu_ur of
    each unload-reload loop (a drained extension stage after a compression, ended by a q or stress_ratio end), and per
    mu_r the power laws E = E_ref (sigma'_3 / p_ref)^m of the hardening-soil model over the confining pressures;
    figures/stiffness.png. Empty without such tests."""
    rows, pts = [], {}
    for j, d, s in mono:
        st = stiffness_state(d, s)
        if st is None:
            continue
        loop = st["loops"][0] if st["loops"] else None
        ratio = loop["E"] / st["E50"] if loop and st["E50"] and loop["E"] else None
        E50 = number_text(st["E50"] / 1e6 if st["E50"] else None, ".2f")
        peak = f"{st['q_peak'] / 1e3:.1f}" + (" (rising)" if st["rising"] else "")
        if loop:
            # E_ur (q from -> to); round gives an int: an unloading that ended at q = -0.07 kPa reads 0, not -0
            def span(lp):
                return (f"{number_text(lp['E'] / 1e6 if lp['E'] else None, '.2f')} ({round(lp['q_from'] / 1e3)} → "
                        f"{round(lp['q_to'] / 1e3)})")
            more = ", ".join(span(lp) for lp in st["loops"][1:]) or "-"
            ur = (f"{span(loop)} | {number_text(loop['E_less'] / 1e6, '.2f')} | {number_text(loop['nu'], '.3f')} | "
                  f"{number_text(ratio, '.2f')} | {more}")
        else:
            ur = "- | - | - | - | -"
        rows.append(f"| {j['name']} | {j['mu_r']:g} | {st['p0'] / 1e3:.1f} | {peak} | {E50} | {ur} |")
        g = pts.setdefault(j["mu_r"], {"E50": [], "E_ur": []})
        if st["E50"]:
            g["E50"].append((st["p0"], st["E50"]))
        if loop and loop["E"] and loop["E"] > 0:
            g["E_ur"].append((st["p0"], loop["E"]))
    if not rows:
        return []
    fit_rows = []
    fig, ax = plt.subplots(figsize=(6.5, 4.6))
    murs = sorted(pts)
    for i, mu_r in enumerate(murs):
        color = plt.cm.viridis(i / max(1, len(murs) - 1))
        for key, marker in (("E50", "o"), ("E_ur", "s")):
            v = pts[mu_r][key]
            if not v:
                continue
            p, E = np.array([x[0] for x in v]), np.array([x[1] for x in v])
            ax.loglog(p / 1e3, E / 1e6, marker, color=color, mfc="none" if key == "E50" else color,
                      label=f"{key}, mu_r = {mu_r:g}")
            f = power_fit(p, E)
            if f is None:
                fit_rows.append(f"| {mu_r:g} | {key} | {len(v)} | not fitted: needs 3 tests at 2 pressures or more | | |")
                continue
            E_ref, sE, m, sm = f
            xs = np.array([p.min(), p.max()])
            ax.loglog(xs / 1e3, E_ref * (xs / P_REF) ** m / 1e6, "-" if key == "E_ur" else "--", color=color, lw=1)
            fit_rows.append(f"| {mu_r:g} | {key} | {len(v)} | {E_ref / 1e6:.2f} ± {sE / 1e6:.2f} | {m:.3f} ± {sm:.3f} | "
                            f"{p.min() / 1e3:.0f}–{p.max() / 1e3:.0f} |")
    ax.set(xlabel="sigma'_3 = p'_0 [kPa]", ylabel="E [MPa]", title="E50 (open) and E_ur (filled) against the confinement")
    # plain numbers (kPa, MPa), not powers of ten, on the log axes: the tests' pressures on x
    ax.set_xticks(sorted({round(x[0] / 1e3) for g in pts.values() for v in g.values() for x in v}))
    ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    legend(ax, fontsize=7)
    save(fig, figs, "stiffness")
    return ["## Stiffness (drained triaxial)", "",
            "The drained compressions at constant sigma_3 that start from an isotropic stress (their first loading): "
            "E50 = (q_peak/2) / eps_a where the first loading's q (of the walls) first reaches half the test's peak "
            "(q_peak: the largest q over the test's compressions, a reloading included; '(rising)': q still rose at the "
            "end, so q_peak is the last q, not a peak; '-' where the loading turned below q_peak/2); and the first "
            "unload-reload loop's E_ur = Δq / Δeps_a of its unloading (a drained extension stage after a compression, "
            "ended by a `q` or `stress_ratio` end: summary.json's E_sec, from the q it turned at to the q it ended at) "
            "and nu_ur = -Δeps_r / Δeps_a over it (E_ur less drag: of the walls' q less the damping's drag, series "
            "q_drag, at the turn and at the unloading's end; the drag turns with the walls, so the walls' Δq holds "
            "both), and the E_ur of any further loops (the hardening-soil model takes "
            "E_ur as independent of the stress level the loop turns at: loops at several levels test it). Per mu_r, the hardening-soil model's power laws E = E_ref "
            f"(sigma'_3 / p_ref)^m with p_ref = {P_REF / 1e3:g} kPa (Schanz et al. 1999; c = 0), least squares in "
            "ln E against ln sigma'_3, ± one standard error; `figures/stiffness.png`. q is the walls', drag included "
            "(E_ur less drag, and the peak table's q less drag, say how much it adds).", "",
            "| test | mu_r | p'_0 [kPa] | q_peak [kPa] | E50 [MPa] | E_ur [MPa] (q from → to, kPa) | E_ur less drag [MPa] "
            "| nu_ur | E_ur / E50 | further loops: E_ur [MPa] (q from → to) |",
            "|---|---|---|---|---|---|---|---|---|---|", *rows, "",
            *(["| mu_r | modulus | tests | E_ref [MPa] | m | sigma'_3 [kPa] |", "|---|---|---|---|---|---|", *fit_rows, ""]
              if fit_rows else [])]


def sample_count(run_dir):
    """The sphere count a run's resolved config.yaml gives (sample: count: N), or for a sample read from a file its
    summary.json's (sample: spheres); None where neither can be read."""
    import re
    try:
        text = open(os.path.join(run_dir, "config.yaml")).read()
    except OSError:
        return None
    m = re.search(r"^sample:\n(?: .*\n)*?  count: (\d+)$", text, re.M)
    n = sample_sizes(run_dir).get("spheres") if m is None else None
    return int(m.group(1)) if m else int(n) if n else None


def isotropic_stages(out, name):
    """Every isotropic stage of job `name` (its summary.json: a shear job's own stages only), in order; [] where it has no summary."""
    try:
        stages = json.load(open(os.path.join(out, "jobs", name, "run", "summary.json")))["stages"]
    except (OSError, ValueError, KeyError):
        return []
    return [s for s in stages if s.get("type") == "isotropic"]


def unconverged(out, name):
    """The isotropic stages of job `name` (a sample's preparation, or a test's reconsolidation) that ran out of steps:
    summary.json's done false, the stage ended at its max_steps before its pressure, unbalanced-force and
    kinetic-energy criteria held (the sample not in equilibrium at that stage's pressure)."""
    return [s.get("name", "?") for s in isotropic_stages(out, name) if s.get("done") is False]


def ends_unconverged(out, name):
    """Whether job `name`'s last isotropic stage ran out of steps: the sample ends out of equilibrium, its e_0 no
    equilibrium's. An earlier stage that ran out, then a later one that converged (a seat, then a preloading and an
    unloading), leaves a sample in equilibrium at its end whose path passed that stage's pressure out of it."""
    stages = isotropic_stages(out, name)
    return bool(stages) and stages[-1].get("done") is False


UNCONVERGED_NOTE = ("ran out of steps: the last isotropic stage reached its max_steps before the pressure, "
                    "unbalanced-force and kinetic-energy criteria held (summary.json done: false), so the sample's e_0 "
                    "is not an equilibrium's; raise that stage's max_steps (a frictionless or nearly frictionless "
                    "preparation settles slowest)")
UNCONVERGED_EARLIER_NOTE = ("ran out of steps in an earlier isotropic stage (summary.json done: false) and converged in a "
                            "later one: each ends in equilibrium, but its path passed the earlier stage's pressure out of "
                            "equilibrium; raise that stage's max_steps for a path through equilibria")


def consolidated(out, name):
    """Sample job `name`'s last isotropic stage in its summary.json (the sample as consolidated), with the job's run
    directory as "dir"; None where it has none (not run yet, or failed)."""
    iso = isotropic_stages(out, name)
    return {**iso[-1], "dir": os.path.join(out, "jobs", name, "run")} if iso else None


def sample_sizes(run_dir):
    """A run's sample sizes by mass (summary.json's `sample`: d50 in m, cu, ...); {} where its build wrote none."""
    try:
        return json.load(open(os.path.join(run_dir, "summary.json"))).get("sample") or {}
    except (OSError, ValueError, AttributeError):
        return {}


def search_trial_e(run_dir, stage):
    """The void ratios a target_e0 search's trials reached, from the sample file its stage saved (/search/trial_e);
    [] where there are none (no search, no sample file, a build before them)."""
    try:
        import h5py
        with h5py.File(os.path.join(run_dir, f"sample_{stage}.h5"), "r") as f:
            return [float(x) for x in f["/search/trial_e"][()]]
    except (OSError, KeyError, ImportError):
        return []


def samples_section(out, jobs, samples=None):
    """The study's samples as consolidated (their summary.json's last isotropic stage): D50 and Cu of their spheres (by
    mass), e of the box, of its interior and of its core (the central eighth), and whether the sample is graded
    (GRADED_CORE). The samples are study.json's
    list (`samples`), or, in a study.json of a build before it, those its jobs name. Empty where no sample job has a
    summary."""
    rows, graded, unconv, earlier, missed = [], [], [], [], []
    names = {j["name"] for j in samples} if samples else {j["sample"] for j in jobs if j.get("sample")}
    for name in sorted(names, key=lambda k: (sample_count(os.path.join(out, "jobs", k, "run")) or 0, k)):  # by size
        s = consolidated(out, name)
        if s is None:
            continue
        n = sample_count(s["dir"])
        e_in, e_core = s.get("e_inner"), s.get("e_core")
        diff = e_core - e_in if e_in is not None and e_core is not None else None  # null in a build before them
        if diff is None:
            verdict = "-"
        elif n is None or n < GRADED_MIN_COUNT:
            verdict = f"too few spheres to tell (< {GRADED_MIN_COUNT})"
        elif diff > GRADED_CORE:
            verdict = "graded"
            graded.append(name)
        else:
            verdict = "homogeneous"
        if ends_unconverged(out, name):
            unconv.append(name)
            verdict = f"NOT converged ({', '.join(unconverged(out, name))}: max_steps); {verdict}"
        elif left := unconverged(out, name):
            earlier.append(name)
            verdict = f"{', '.join(left)} ran out of steps, later stages converged; {verdict}"
        # a target_e0 search that missed (summary.json: its stage's target and tolerance against its e)
        for st in isotropic_stages(out, name):
            t, tol = st.get("target_e0"), st.get("target_e0_tolerance")
            if t is not None and tol is not None and st.get("e") is not None and abs(st["e"] - t) > tol:
                # the void ratios its trials did reach (their frictions 0 to mu_max): where a target could lie
                te = search_trial_e(s["dir"], st["name"])
                missed.append(name + (f" (its {len(te)} trials' e {min(te):.4f} to {max(te):.4f})" if te else ""))
                verdict = f"target_e0 {t:g} NOT reached ({st['name']}: e {st['e']:.4f}); {verdict}"
        sizes = sample_sizes(s["dir"])
        d50 = sizes.get("d50")
        rows.append(f"| {name} | {n if n is not None else '-'} | {number_text(d50 * 1e3 if d50 else None, '.3f')} | "
                    f"{number_text(sizes.get('cu'), '.2f')} | {number_text(s.get('e'), '.4f')} | "
                    f"{number_text(e_in, '.4f')} | {number_text(e_core, '.4f')} | {number_text(diff, '+.4f')} | {verdict} |")
    if not rows:
        return []
    note = (f"{len(graded)} of {len(rows)} samples are graded: a crust along the walls around a looser core, which a "
            "frictional gas compacted by its walls alone forms; such a sample is no element test. `affine: true` on "
            "the isotropic stage compacts it homogeneously (configs/README.md)." if graded else "")
    if unconv:
        note += (" " if note else "") + f"{len(unconv)} of {len(rows)} samples " + UNCONVERGED_NOTE + "."
    if earlier:
        note += (" " if note else "") + f"{len(earlier)} of {len(rows)} samples " + UNCONVERGED_EARLIER_NOTE + "."
    if missed:
        note += ((" " if note else "") + f"{len(missed)} of {len(rows)} samples did not reach their target_e0 (the "
                 "e0 axis's, or the base's): their search's frictions, 0 to the stage's mu_max, do not make that void "
                 "ratio of this sample at this pressure, and their tests, named by the target, start from the e_0 "
                 "given here: " + ", ".join(missed) + ".")
    return ["## Samples", "",
            "Each sample at the end of its consolidation: its spheres' D50 and Cu = D60/D10 by mass, e of the wall box, of its interior (inset by two mean "
            "diameters) and of its core (the central eighth of the box). A sample is graded when its core is looser than "
            f"its interior by more than {GRADED_CORE:g} (told from {GRADED_MIN_COUNT} spheres up: a smaller core "
            "scatters as much).", "",
            "| sample | spheres | D50 [mm] | Cu | e_0 | e_0 interior | e_0 core | core - interior | |",
            "|---|---|---|---|---|---|---|---|---|",
            *rows, "", *([note, ""] if note else [])]


# The axes of a preparation study's figure: study.json's key, its label, and whether its scale is logarithmic. cu: the
# grading axis's curve's Cu = D60/D10 (0: the base's sizes, or a study.json from before the axis).
PREP_AXES = (("count", "spheres", True), ("p0", "p'_0 [kPa]", True), ("mu_r", "mu_r", False),
             ("e0", "target e_0", False), ("cu", "Cu = D60/D10 of the grading asked", False),
             ("E", "contact stiffness E [Pa]", True))


def gas_fraction(run_dir):
    """The solid fraction of a run's interior as its series' first row found it (1 / (1 + e_inner)): for a sample job,
    the gas as placed; None where the series or the column is missing."""
    try:
        with open(os.path.join(run_dir, "series.csv")) as f:
            first = next(csv.DictReader(f))
        return 1 / (1 + float(first["e_inner"]))
    except (OSError, StopIteration, KeyError, ValueError):
        return None


def preparation_section(out, samples, figs):
    """A preparation study's samples grouped over their seeds (the same mu_r, e0, p0 and count): each void ratio as mean
    ± sd [95 % half-width of the mean], the friction a target_e0 search settled on and the stage's steps; for a count
    axis whether the interior's e_0 still changes between the two largest sizes (by more than two standard errors of
    the difference of their means); and figures/preparation.png, e_0 against each swept axis. `samples`: the finished
    ones. Empty where none has a summary."""
    # A group's key: the PREP_AXES values, the preparation stages' stage axes (study.json's stage_keys, e.g. a
    # preloading's pressure: nan where a sample has none of that key), then the grading's or sample file's name (two
    # curves of one Cu are two samples)
    stage_axes = sorted({k for j in samples for k in j.get("stage_keys", {})})
    axes = PREP_AXES + tuple((k, k, False) for k in stage_axes)
    groups = {}
    for j in samples:
        s = consolidated(out, j["name"])
        if s is not None:
            sk = j.get("stage_keys", {})
            groups.setdefault(tuple(j.get(k, 0) for k, _, _ in PREP_AXES) + tuple(sk.get(k, math.nan) for k in stage_axes)
                              + (j.get("grading", "") or j.get("specimen", ""),), []).append((j, s))
    if not groups:
        return [], False
    rows, stats, unconv, earlier = [], {}, [], []
    # mu_r, p0, e0, grading, E, the stage axes, size
    for key in sorted(groups, key=lambda k: (k[1], k[2], k[3], k[4], k[-1], k[5], *k[6:-1], k[0])):
        g = sorted(groups[key], key=lambda t: t[0]["seed"])
        col = {c: measured([s.get(c) for _, s in g]) for c in ("e", "e_inner", "e_core", "mu", "steps")}
        col["diff"] = measured([s["e_core"] - s["e_inner"] for _, s in g
                                if s.get("e_core") is not None and s.get("e_inner") is not None])
        col["gas"] = measured([gas_fraction(s["dir"]) for _, s in g])
        stats[key] = col
        name = seedless(g[0][0]["name"], g[0][0])
        # the stage's friction: one value unless a target_e0 search settled on one per seed
        mu_txt = f"{col['mu'][0]:.3f}" if len(set(col["mu"])) == 1 else seed_spread(col["mu"], 3)
        left = [j["name"] for j, _ in g if ends_unconverged(out, j["name"])]
        unconv += left
        passed = [j["name"] for j, _ in g if unconverged(out, j["name"]) and j["name"] not in left]
        earlier += passed
        # a sample file's spheres were not drawn here: no seed to name
        seeds = "file" if g[0][0].get("specimen") else ", ".join(str(j["seed"]) for j, _ in g)
        rows.append(f"| {name} | {key[0]} | {len(g)} ({seeds}) | "
                    f"{seed_spread(col['e'], 4)} | {seed_spread(col['e_inner'], 4)} | {seed_spread(col['e_core'], 4)} | "
                    f"{seed_spread(col['diff'], 4)} | {mu_txt} | "
                    f"{int(round(np.mean(col['steps']))) if col['steps'] else '-'}"
                    f"{f' ({len(left)} of {len(g)} NOT converged)' if left else ''}"
                    f"{f' ({len(passed)} of {len(g)}: an earlier stage ran out of steps)' if passed else ''} | "
                    f"{seed_spread(col['gas'], 4)} |")
    lines = ["## Preparation", "",
             "The samples that differ only in their seed, together: each void ratio at the end of the consolidation as "
             "mean ± standard deviation [95 % half-width of the mean] over the seeds, the friction the stage ended at "
             "(a target_e0 search's last trial), its steps (mean; 'NOT converged': seeds whose last stage ran out of them; "
             "'an earlier stage ran out of steps': one before it did, the last converged; both named below), and the solid fraction of the gas's interior as "
             "placed (the series' first row): random placement keeps every centre a radius from the walls, so the gas "
             "is thinner along them and denser inside than `initial_solid_fraction`, the more so the smaller the box, "
             "and a frictional gas compacted affinely jams denser the denser it starts.", "",
             "| samples (all seeds) | spheres | seeds | e_0 | e_0 interior | e_0 core | core - interior | mu | steps | "
             "gas interior solid fraction |",
             "|---|---|---|---|---|---|---|---|---|---|", *rows, "",
             *([f"{len(unconv)} sample(s) {UNCONVERGED_NOTE}: {', '.join(unconv)}.", ""] if unconv else []),
             *([f"{len(earlier)} sample(s) {UNCONVERGED_EARLIER_NOTE}: {', '.join(earlier)}.", ""] if earlier else [])]
    # Is the sample big enough? Per series of sizes (the same mu_r, e0, p0), the interior's e_0 of the two largest.
    series = {}
    for key in stats:
        series.setdefault(key[1:], []).append(key)
    conv = []
    for _, keys in sorted(series.items()):
        keys = sorted(keys)
        if len(keys) < 2:
            continue
        a, b = stats[keys[-2]]["e_inner"], stats[keys[-1]]["e_inner"]
        name = seedless(groups[keys[-1]][0][0]["name"], groups[keys[-1]][0][0]).replace(f"_n{keys[-1][0]}", "")
        trend = ", ".join(f"{np.mean(stats[k]['e_inner']):.4f}" if stats[k]["e_inner"] else "-" for k in keys)
        head = f"- {name}: interior e_0 at {', '.join(str(k[0]) for k in keys)} spheres: {trend}"
        if len(a) < 2 or len(b) < 2:
            conv.append(head + " (two seeds a size at least tell a change from the scatter)")
            continue
        d = float(np.mean(b) - np.mean(a))
        se = math.sqrt(np.var(a, ddof=1) / len(a) + np.var(b, ddof=1) / len(b))
        verdict = ("within two standard errors: no change from the seeds' scatter" if abs(d) <= 2 * se
                   else "more than two standard errors: still changing with size")
        conv.append(head + f"; from {keys[-2][0]} to {keys[-1][0]} {d:+.4f} ± {se:.4f}, {verdict}.")
    if conv:
        lines += ["Does the interior's e_0 still depend on the size? (the difference of the two largest sizes' means "
                  "± its standard error)", "", *conv, ""]
    # e_0 against each swept axis: the interior's mean ± sd over the seeds (solid), the box's and the core's means.
    swept = [(i, k, lab, log) for i, (k, lab, log) in enumerate(axes) if len({key[i] for key in stats}) > 1]
    named = len({key[-1] for key in stats}) > 1  # several gradings: their names tell the other panels' lines apart
    if not swept:
        return lines, False

    def key_of(t):
        return [t[m_] for m_, _, _, _ in swept]

    fig, ax = plt.subplots(1, len(swept), figsize=(6 * len(swept), 4.5), squeeze=False)
    for a_, (i, k, lab, log) in zip(ax[0], swept):
        lines_of = {}
        for key in stats:
            # on the Cu panel one line runs through the gradings (the name left out of what tells lines apart)
            lines_of.setdefault(key[:i] + key[i + 1:(-1 if k == "cu" else None)], []).append(key)
        for n, (rest, keys) in enumerate(sorted(lines_of.items())):
            keys = sorted(keys, key=lambda t: t[i])
            x = np.array([t[i] / (1e3 if k == "p0" else 1) for t in keys])
            c = f"C{n % 10}"
            # the other swept axes' values: what tells the lines apart
            other = ", ".join([f"p'_0 = {v / 1e3:g} kPa" if kk == "p0" else f"{v:g} spheres" if kk == "count"
                               else f"{kk} = {v:g}" for (m_, kk, _, _), v in zip(swept, key_of(keys[0]))
                               if m_ != i and kk != "cu"] + ([keys[0][-1]] if named and k != "cu" else []))
            for colname, style, what in (("e_inner", "o-", "interior"), ("e", "s--", "box"), ("e_core", "^:", "core")):
                ok = [bool(stats[t][colname]) for t in keys]
                if not any(ok):
                    continue
                m = np.array([np.mean(stats[t][colname]) for t, o in zip(keys, ok) if o])
                sd = np.array([np.std(stats[t][colname], ddof=1) if len(stats[t][colname]) > 1 else 0
                               for t, o in zip(keys, ok) if o])
                a_.errorbar(x[ok], m, yerr=sd if colname == "e_inner" else None, fmt=style, color=c, capsize=3,
                            label=f"{what} ({other})" if other else what)
        a_.set(xlabel=lab, ylabel="e_0", title=f"e_0 against {lab} (interior: mean ± sd over the seeds)")
        if log and all(t[i] > 0 for t in stats):  # (E = 0: the base's, beside an extra job's)
            a_.set_xscale("log")
            # the values as numbers (1e+09 for E: a ScalarFormatter wrote "1.0" and an offset "1e9")
            a_.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
            a_.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            a_.set_xticks(sorted({t[i] / (1e3 if k == "p0" else 1) for t in stats}))
        a_.grid(alpha=0.3)
        legend(a_, fontsize=7)
    save(fig, figs, "preparation")
    return lines, True


# Two isotropic stages are at different pressures when their measured p' differ by more than this (relative): a stage
# ends within its pressure_tolerance (default 1 %) of its target, so stages at one target (configs/paper/study-base.yaml
# prepares and then consolidates at 190 kPa) measure a few 0.1 % apart, and a slope through them would be noise.
PATH_GAP = 0.05


def compression_branches(stages):
    """The isotropic compression and swelling branches of a sample's isotropic stages: loading, the stages from the first
    while p' rises (by more than PATH_GAP); unloading, from the largest p' while it falls (likewise; a reloading after
    it is not fitted). Each a list of (p', e, e_inner)."""
    pts = [(s["p"], s["e"], s.get("e_inner")) for s in stages if s.get("p", 0) > 0]
    k = 0
    while k + 1 < len(pts) and pts[k + 1][0] > pts[k][0] * (1 + PATH_GAP):
        k += 1
    u = k
    while u + 1 < len(pts) and pts[u + 1][0] < pts[u][0] * (1 - PATH_GAP):
        u += 1
    return pts[:k + 1], pts[k:u + 1]


def log_slope(pts, col):
    """-de/d ln p' by least squares through the points' column col (1: e, 2: e_inner) with its standard error (None
    from two points, which the line meets); None where fewer than two points or a column not measured."""
    if len(pts) < 2 or any(p[col] is None for p in pts):
        return None
    x, y = np.log([p[0] for p in pts]), np.array([p[col] for p in pts], dtype=float)
    if len(pts) == 2:
        return -(y[1] - y[0]) / (x[1] - x[0]), None
    slope, _, s_slope, _ = fit(x, y)
    return -slope, s_slope


def slope_text(v):
    """A compression index as a table cell: 'value ± se', the value alone from two points, '-' where not fitted."""
    if v is None:
        return "-"
    return f"{v[0]:.4f}" + (f" ± {v[1]:.4f}" if v[1] is not None else "")


def compression_section(out, samples, figs):
    """Samples consolidated in several isotropic stages (a base whose stages load to rising p'_0 and unload): the
    isotropic compression index lambda = -de/d ln p' of the loading branch and the swelling index kappa of the
    unloading one (Roscoe & Burland's e = N - lambda ln p', the normal compression and swelling lines of critical-state
    soil mechanics), of the box's e and of the interior's, by least squares over each branch's stage ends, with the
    samples that differ only in their seed together; figures/compression.png draws e against p' (log). Empty where no
    sample has two isotropic stages at different pressures."""
    rows, per_group, drawn = [], {}, []
    for j in sorted(samples, key=lambda j: j["name"]):
        name = j["name"]
        load, unload = compression_branches(isotropic_stages(out, name))
        if len(load) < 2 and len(unload) < 2:
            continue
        f = {"lam": log_slope(load, 1), "lam_in": log_slope(load, 2), "kap": log_slope(unload, 1),
             "kap_in": log_slope(unload, 2)}
        path = " → ".join(f"{p / 1e3:.3g}" for p, _, _ in load + unload[1:])
        rows.append(f"| {name} | {path} | {slope_text(f['lam'])} | {slope_text(f['lam_in'])} | {slope_text(f['kap'])} | "
                    f"{slope_text(f['kap_in'])} |")
        per_group.setdefault(seedless(name, j), []).append(f)
        drawn.append((name, load, unload))
    if not rows:
        return [], False
    lines = ["## Isotropic compression", "",
             "Samples consolidated in several isotropic stages: lambda = -de/d ln p' through the stage ends of the loading "
             "branch (p' rising from the first stage), kappa through those of the unloading branch (falling from the "
             "largest p'), of the wall box's e and of the interior's (± the standard error of the least-squares slope; "
             "a value alone from two stages). With a linear contact law much of the loading branch is the contacts' "
             "elastic compression, which the unloading branch gives back (lambda - kappa is the plastic part), and "
             "that part is linear in p', so e curves down against ln p' (`figures/compression.png`): lambda is the "
             "secant over the stages' range, and its standard error says how far the points are from a line.", "",
             "| sample | p' of the stages [kPa] | lambda | lambda interior | kappa | kappa interior |",
             "|---|---|---|---|---|---|", *rows, ""]
    groups = {k: g for k, g in per_group.items() if len(g) > 1}
    if groups:
        lines += ["| samples (all seeds) | seeds | lambda | lambda interior | kappa | kappa interior |",
                  "|---|---|---|---|---|---|"]
        for k, g in sorted(groups.items()):
            cells = [seed_spread([f[c][0] for f in g if f[c] is not None], 4) for c in ("lam", "lam_in", "kap", "kap_in")]
            lines.append(f"| {k} | {len(g)} | " + " | ".join(cells) + " |")
        lines.append("")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for n, (name, load, unload) in enumerate(drawn):
        c = f"C{n % 10}"
        for pts, style, what in ((load, "o-", "loading"), (unload, "s--", "unloading")):
            if len(pts) > 1:
                ax.plot([p[0] / 1e3 for p in pts], [p[1] for p in pts], style, color=c,
                        label=f"{name} {what}" if len(drawn) <= 6 else None)
                if all(p[2] is not None for p in pts):
                    ax.plot([p[0] / 1e3 for p in pts], [p[2] for p in pts], style, color=c, alpha=0.45, mfc="none")
    ax.set(xscale="log", xlabel="p' [kPa]", ylabel="e",
           title="isotropic compression: box (filled), interior (hollow)")
    finish(fig, ax, ax, 7, figs, "compression")
    return lines, True


def gradings_figure(out, samples, figs, kind="grading"):
    """figures/grading.png of a study over several curves (the grading axis): of each curve its finished sample job of the
    lowest seed, as drawn against as asked (fig_grading, its printed lines kept out of the study's output). False where
    fewer than two curves have a finished sample. kind "specimen": of each file of the sample_file axis."""
    import contextlib
    import io

    first = {}
    for j in sorted(samples, key=lambda j: (j.get("seed", 0), j["name"])):
        g = j.get(kind, "")
        if g and g not in first and os.path.isfile(os.path.join(out, "jobs", j["name"], "done")):
            first[g] = os.path.join(out, j["dir"])
    if len(first) < 2:
        return False
    with contextlib.redirect_stdout(io.StringIO()):
        return bool(fig_grading([first[g] for g in sorted(first)], figs))


def preparation_report(out, idx):
    """report.md of a preparation study (a base without a shear stage: its jobs are the samples alone): the Samples
    and Preparation sections."""
    samples = idx["samples"]
    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    done = [j["name"] for j in samples if os.path.isfile(os.path.join(out, "jobs", j["name"], "done"))]
    missing = [j["name"] for j in samples if j["name"] not in done]
    finished = [j for j in samples if j["name"] in done]
    prep, fig = preparation_section(out, finished, figs)
    comp, comp_fig = compression_section(out, finished, figs)
    shown = [f for f, on in (("`figures/preparation.png`", fig), ("`figures/compression.png`", comp_fig),
                             ("`figures/grading.png` (each curve, asked and drawn)", gradings_figure(out, samples, figs)))
             if on]
    lines = [f"# Study report: {idx['study']}", "",
             f"{len(done)} samples prepared (a preparation study: its base has no shear stage)"
             + (f"; not (yet) finished: {', '.join(missing)}" if missing else "") + ".", "",
             *([f"Figures: {', '.join(shown)}.", ""] if shown else []),
             *samples_section(out, [], finished), *prep, *comp]
    write_report(out, lines)
    print(os.path.join(out, "report.md"))


def line_to_zero(x, y):
    """The intercept at x = 0 of the least-squares line through (x, y), with its standard error (None with two points,
    which the line meets exactly), and the slope; None where fewer than two distinct x."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if len(x) < 2 or np.ptp(x) <= 0:
        return None
    if len(x) == 2:
        slope = (y[1] - y[0]) / (x[1] - x[0])
        return y[0] - slope * x[0], None, slope
    slope, icpt, _, s_icpt = fit(x, y)
    return icpt, s_icpt, slope


def lack_of_fit(x, y, groups):
    """The lack-of-fit F test of the least-squares line through (x, y) (Draper & Smith 1998, sec. 2.1): the scatter of
    the groups' means about the line (k - 2 degrees of freedom, k groups) over the scatter within the groups (pure
    error, n - k): the p value of that ratio, small where the line misses the means by more than the replicates
    scatter. groups: each point's replicate group (the tests of one rate). None without pure error (one test per
    group, or replicates that agree exactly) or with fewer than three groups."""
    x, y, groups = np.asarray(x, dtype=float), np.asarray(y, dtype=float), list(groups)
    keys = sorted(set(groups))
    n, k = len(y), len(keys)
    if k < 3 or n <= k:
        return None
    icpt, _, slope = line_to_zero(x, y)  # (k >= 3 groups: x spans a range)
    yh = icpt + slope * x
    member = [np.array([g == key for g in groups]) for key in keys]
    ss_pe = sum(float(np.sum((y[m] - y[m].mean()) ** 2)) for m in member)
    ss_lof = sum(int(m.sum()) * float(y[m].mean() - yh[m].mean()) ** 2 for m in member)
    if ss_pe <= 1e-12 * max(1.0, float(np.sum(y ** 2))):
        return None
    from scipy.stats import f as f_dist
    return float(f_dist.sf((ss_lof / (k - 2)) / (ss_pe / (n - k)), k - 2, n - k))


# The forms of the extrapolation to I -> 0 that the rate section compares: a line in I (the low-I form of mu(I)) and a
# line in sqrt(I), which stands for the power of I below one that a dense packing's excess friction has been found to
# follow in the quasi-static range (Hatano 2007, Phys. Rev. E 75, 060301(R)). Both are straight in their variable, so
# line_to_zero and lack_of_fit serve both.
LIMIT_FORMS = (("I", lambda i: np.asarray(i, dtype=float)), ("sqrt(I)", lambda i: np.sqrt(np.asarray(i, dtype=float))))


def limit_forms_row(series, measure, pts, col, digits):
    """A row of the rate section's table of the limit's form, for the points pts (I first, the rate last) of one series
    and one measure (column col): per form of LIMIT_FORMS its value at I -> 0 and its lack-of-fit p. None with fewer
    than three rates (two rates: either form meets their means exactly, and the form cannot be told)."""
    rates = [q[-1] for q in pts]
    if len(set(rates)) < 3:
        return None
    cells = [f"| {series} | {measure} | {len(set(rates))} ({len(pts)}) |"]
    for _, form in LIMIT_FORMS:
        x = form([q[0] for q in pts])
        f = line_to_zero(x, [q[col] for q in pts])
        if f is None:  # the rates' tests at one I (a degenerate series): no line
            return None
        p = lack_of_fit(x, [q[col] for q in pts], rates)
        cells.append(f" {f[0]:.{digits}f}{f' ± {f[1]:.{digits}f}' if f[1] is not None else ''} | "
                     f"{'-' if p is None else f'{p:.3f}'} |")
    return "".join(cells)


def rate_section(mono, window, tol, figs, peak=(0.0, None)):
    """Tests of an axial_strain_rate axis (study.json: rate_group, the test's name without its rate): per series of
    the same test at several rates (with the test of that name at the base's rate, where the study has it: an extra
    job's rate beside the grid's), the largest stress ratio and the critical state against the inertial number I,
    each extrapolated to I -> 0 by a line in I: the low-I form of the mu(I) rheology, mu_s + (mu_2 - mu_s) I / I_0
    for I << I_0 ~ 0.3 (Jop, Forterre & Pouliquen 2006, Nature 441, eq. 2). The slowest rate's distance from that
    limit says whether the study's rates are slow enough. Over three rates or more, each limit by a line in sqrt(I) too,
    with both lines' lack-of-fit p (LIMIT_FORMS): the form the limit depends on. Peaks as the peak table takes them
    (`peak`)."""
    groups = {}  # replicates of one test over seeds share a series: the line goes through every one of them
    for j, d, s in mono:
        if j.get("rate_group"):
            groups.setdefault(seedless(j["rate_group"], j), []).append((j, s, test_stage(d)))
    if not groups:
        return []
    for j, d, s in mono:
        if not j.get("rate_group") and seedless(j["name"], j) in groups and s["rate"] > 0:  # the base's rate (summary.json)
            groups[seedless(j["name"], j)].append((j, s, test_stage(d)))

    def rate(t):
        """The test's rate: its shear stage's (a K0 consolidation before it keeps the base's), else the series'."""
        own = float(t[2].get("axial_strain_rate", 0)) if t[2] else 0.0
        return own if own > 0 else t[1]["rate"] if t[1]["rate"] > 0 else t[0].get("axial_strain_rate", 0)

    rows_out = ["| test | axial_strain_rate [1/s] | I at max q/p' | max q/p' (phi'_max) | I at critical state | "
                "q/p' at critical state (phi_cs) | e_c |", "|---|---|---|---|---|---|---|"]
    fits = ["| rate series | tests | max q/p' at I -> 0 (phi'_max) | slowest rate's max q/p' above it | "
            "critical q/p' at I -> 0 (phi_cs) | e_c at I -> 0 | slowest rate's critical q/p' above it |",
            "|---|---|---|---|---|---|---|"]
    su_rows = ["| test | axial_strain_rate [1/s] | I at q_peak | s_u / sigma'_v0 |", "|---|---|---|---|"]
    su_fits = ["| rate series | tests | s_u / sigma'_v0 at I -> 0 | slowest rate's s_u / sigma'_v0 above it |",
               "|---|---|---|---|"]
    forms = []  # the limit in each form of LIMIT_FORMS, per series and measure over three rates or more
    fig, ax = plt.subplots(1, 3, figsize=(17, 4.5))
    fast = []  # series whose line reaches past the low-I range
    for g, tests in sorted(groups.items()):
        seeds = {t[0].get("seed") for t in tests}
        if len(seeds) == 1:  # one seed: the series is named as its tests are
            g = g.replace("_s*_", f"_s{seeds.pop()}_", 1)
        # (I, M, phi, rate) at the largest stress ratio; (I, M, phi, e, rate) at critical state
        pk, cs, su = [], [], []  # su: (I at q_peak, s_u / sigma'_v0, rate) of the undrained tests
        for t in sorted(tests, key=rate):
            j, s, st = t
            ps = peak_state(s, peak)
            if j.get("drainage") == "undrained" and (u := undrained_strength(s, st)) is not None:
                su.append((*u, rate(t)))
                su_rows.append(f"| {j['name']} | {rate(t):g} | {u[0]:.1e} | {u[1]:.3f} |")
            cells = [f"| {j['name']} | {rate(t):g} |"]
            if ps.get("I") is not None:
                pk.append((ps["I"], ps["M"], ps["phi"], rate(t)))
                cells.append(f" {ps['I']:.1e} | {ps['M']:.3f} ({ps['phi']:.1f}°) |")
            else:
                cells.append(" - | - |")
            c = critical_state(s, window, *tol)
            if c is not None and c["ok"] and c["I"] is not None:
                cs.append((c["I"], c["M"], c["phi"], c["e"], rate(t)))
                cells.append(f" {c['I']:.1e} | {c['M']:.3f} ({c['phi']:.1f}°) | {c['e']:.4f} |")
            else:
                cells.append(" - | not at critical state | - |")
            rows_out.append("".join(cells))
        ext, b = bool(tests[0][1]["eps_a"][tests[0][1]["shear"]][-1] < 0), float(tests[0][1].get("b", 0.0))

        def limit(pts, col, digits, angle=False):
            """Column col of pts at I -> 0 as 'value ± se' (with its angle: Mohr-Coulomb's of M at b = 0, the angles'
            own line at b > 0), and the slowest rate's excess over it (the mean of its tests: one per seed)."""
            f = line_to_zero([q[0] for q in pts], [q[col] for q in pts])
            if f is None:
                return f"fewer than 2 tests ({len(pts)})", "-"
            v, se, _ = f
            txt = f"{v:.{digits}f}" + (f" ± {se:.{digits}f}" if se is not None else "")
            if angle:
                phi0 = friction_angle(v, ext) if b <= 0 else line_to_zero([q[0] for q in pts], [q[2] for q in pts])[0]
                txt += f" ({phi0:.1f}°)"
            slow = [q for q in pts if q[-1] == min(q[-1] for q in pts)]
            n = f", mean of {len(slow)}" if len(slow) > 1 else ""
            return txt, (f"{np.mean([q[col] for q in slow]) - v:+.{digits}f} (I = {np.mean([q[0] for q in slow]):.1e}"
                         f"{n})")

        pk_txt, pk_gap = limit(pk, 1, 3, True)
        cs_txt, cs_gap = limit(cs, 1, 3, True)
        fits.append(f"| {g} | {len(tests)} | {pk_txt} | {pk_gap} | {cs_txt} | {limit(cs, 3, 4)[0]} | {cs_gap} |")
        if su:
            su_txt, su_gap = limit(su, 1, 3)
            su_fits.append(f"| {g} | {len(su)} | {su_txt} | {su_gap} |")
        # an undrained series by its strength alone: its stress ratio is taken where it has collapsed, its e is e_0
        forms += [r for r in ((limit_forms_row(g, "s_u / sigma'_v0", su, 1, 3),) if su else
                              (limit_forms_row(g, "max q/p'", pk, 1, 3), limit_forms_row(g, "critical q/p'", cs, 1, 3),
                               limit_forms_row(g, "e_c", cs, 3, 4)))
                  if r is not None]
        I_top = max([q[0] for q in pk + cs], default=0.0)
        if I_top > LINEAR_I:
            fast.append(f"{g} (I up to {I_top:.1e})")
        for a_, pts, col, lab in ((ax[0], pk, 1, "max q/p'"), (ax[1], cs, 1, "critical q/p'"), (ax[2], cs, 3, "e_c")):
            if not pts:
                continue
            (ln,) = a_.plot([q[0] for q in pts], [q[col] for q in pts], "o", label=g)
            xs = np.linspace(0, max(q[0] for q in pts), 200)
            for (_, form), style in zip(LIMIT_FORMS, ("-", "--")):  # the line in sqrt(I) over three rates or more
                f = line_to_zero(form([q[0] for q in pts]), [q[col] for q in pts])
                if f is not None and (style == "-" or len({q[-1] for q in pts}) >= 3):
                    a_.plot(xs, f[0] + f[2] * form(xs), style, color=ln.get_color(), lw=1 if style == "-" else 0.8)
            a_.set(xlabel="inertial number I", ylabel=lab,
                   title=lab + " against I (to I = 0: line in I; dashed: in sqrt(I))")
    for a_ in ax:
        a_.grid(alpha=0.3)
        a_.set_xlim(left=0)
        legend(a_, fontsize=7)
    save(fig, figs, "rate")
    return ["## Rate dependence", "",
            "The same test at several axial strain rates (the study's axial_strain_rate axis; tests that differ only "
            "in their seed share a series, named with s*, and its line goes through every one). Per test the inertial "
            "number I = eps_dot d_mean sqrt(rho / p') at its largest stress ratio (as the peak table takes it) and its "
            "mean over the critical-state window; per series each measure extrapolated to I -> 0 by a least-squares "
            "line in I (± one standard error from three tests on), the low-I form of the mu(I) rheology, mu_s + "
            "(mu_2 - mu_s) I / I_0 for I << I_0 (Jop et al. 2006, eq. 2). The slowest rate's excess over that limit (the mean of its tests, one per seed) "
            f"is what its rate still adds (quasi-static is commonly taken as I < {QUASI_STATIC_I:g}). "
            "Figure: `figures/rate.png` (dashed: the line in sqrt(I), over three rates or more; see the limit's "
            "form below).", "", *rows_out, "", *fits, "",
            *([f"Past I = {LINEAR_I:g} the stress ratio bends below the line (mu(I) saturates towards mu_2 as I nears "
               "I_0), so a line through such tests understates the slope at small I and overstates the limit (a chord "
               "of a concave curve): "
               + ", ".join(fast) + ". Extrapolate from rates below it.", ""] if fast else []),
            *(["Undrained strength: s_u = |q_peak| / 2 of the test's own stage (the last that is not isotropic: a K0 "
               "loading and unloading before it are its consolidation, at the base's rate) over the vertical stress it "
               "was consolidated to, sigma'_v0 = p'_0 + 2 q_0 / 3, as the table across the values takes them, against "
               "the inertial number of that row, and per series its line to I -> 0 (the same "
               "low-I line: a rate term that grows in proportion to the rate). The stress ratio's columns above take an "
               "undrained test where it has collapsed (a small p', a large I); its strength is taken at the peak of q.",
               "", *su_rows, "", *su_fits, ""] if len(su_fits) > 2 else []),
            *(["The limit's form: the line in I above is the low-I form of mu(I); a dense packing's excess friction "
               "has also been found to grow as a power of I below one in the quasi-static range (Hatano 2007, Phys. "
               "Rev. E 75, 060301), which a line in sqrt(I) stands for: a limit that differs between the two is as "
               "uncertain as their difference. Per series and measure over three rates or more (an undrained series by "
               "its s_u alone): each form's value at I -> 0 (± one standard error) and its lack-of-fit p, an F "
               "test of the scatter of the rates' means about the "
               "line against the scatter of the tests at one rate (the seeds; '-' with one test per rate): p < 0.05 "
               "rejects that form at those rates. With two rates either form meets both exactly and the form cannot be "
               "told.", "",
               "| rate series | measure | rates (tests) | at I -> 0, line in I | lack-of-fit p | at I -> 0, line in "
               "sqrt(I) | lack-of-fit p |", "|---|---|---|---|---|---|---|", *forms, ""] if forms else [])]


def test_stage(run_dir):
    """A test's own stage: its summary.json's last stage that is not isotropic (the shear; a K0 loading and unloading
    before it are its consolidation, as across_values_section takes them); None without one."""
    try:
        with open(os.path.join(run_dir, "summary.json")) as f:
            stages = json.load(f).get("stages", [])
        return [x for x in stages if x.get("type") != "isotropic"][-1]
    except (OSError, ValueError, IndexError, AttributeError):
        return None


def shear_peak(s, st):
    """(m, k) of a shear stage st (summary.json's) in its series s: m the stage's rows, k the row among them of the
    largest q along its loading (-q in extension): the peak of |q| as a single row, which across_values_section's
    table and undrained_strength both take. None where the series has no row of the stage."""
    m = s["stage"] == st.get("name")
    if not m.any():
        return None
    q = -s["q"][m] if st.get("direction") == "extension" else s["q"][m]
    return m, int(np.argmax(q))


def vertical_stress_0(st):
    """sigma'_v0 = p'_0 + 2 q_0 / 3 of a stage st (summary.json's): the vertical stress it started from, which s_u is
    normalised by (SHANSEP; CAU against CIU). KeyError/TypeError/ValueError without its start stress."""
    return float(st["p_0"]) + 2 * float(st.get("q_0", 0)) / 3


def undrained_strength(s, st):
    """(I, s_u / sigma'_v0) of an undrained test's shear stage st (test_stage) in its series s: s_u = |q_peak| / 2 at
    the stage's shear_peak over the vertical stress it was consolidated to (vertical_stress_0), and the inertial
    number of that row. None without the stage, its start stress or the inertial number."""
    try:
        v0 = vertical_stress_0(st)
    except (KeyError, TypeError, ValueError):
        return None
    pk = shear_peak(s, st)
    if v0 <= 0 or pk is None or "inertial_number" not in s:
        return None
    m, k = pk
    I = float(s["inertial_number"][m][k])
    return (I, abs(float(s["q"][m][k])) / 2 / v0) if math.isfinite(I) else None


# Student's t at 97.5 % (a two-sided 95 % interval) for 1..30 degrees of freedom.
T975 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def t975(dof):
    """Student's t quantile 0.975 for dof >= 1 degrees of freedom: the table to 30, beyond it the Cornish-Fisher
    expansion about the normal quantile (Abramowitz & Stegun 26.7.5): 2.0422 at 30 against the exact 2.0423, within
    1e-4 beyond."""
    if dof <= len(T975):
        return T975[dof - 1]
    z = 1.959964
    return z + (z ** 3 + z) / (4 * dof) + (5 * z ** 5 + 16 * z ** 3 + 3 * z) / (96 * dof ** 2)


def measured(v):
    """The values of v that were measured (not None, not NaN: rows of a build before the column)."""
    return [x for x in v if x is not None and math.isfinite(x)]


def seed_spread(v, digits):
    """A sample of one measure over seeds as a table cell: 'mean ± sd [95 % half-width of the mean]' from two
    measured values on, the value alone from one, '-' from none."""
    v = measured(v)
    if not v:
        return "-"
    if len(v) == 1:
        return f"{v[0]:.{digits}f} (1 seed)"
    sd = float(np.std(v, ddof=1))
    return f"{np.mean(v):.{digits}f} ± {sd:.{digits}f} [{t975(len(v) - 1) * sd / math.sqrt(len(v)):.{digits}f}]"


SEED_PHI_TARGET = 0.5  # [deg]: the half-width a friction angle is asked to, for the seeds it would take


def seeds_needed(v, target=SEED_PHI_TARGET):
    """The fewest seeds n >= 2 whose 95 % interval of the mean, t975(n - 1) sd / sqrt(n), is within +-target, with
    sd the spread of the seeds at hand (an estimate: it assumes that spread); '-' from fewer than two values."""
    v = measured(v)
    if len(v) < 2:
        return "-"
    sd = float(np.std(v, ddof=1))
    n = 2
    while t975(n - 1) * sd / math.sqrt(n) > target:
        n += 1
    return str(n)


def seedless(name, j):
    """A job's name (or rate group) with job j's seed as '*' (`_s11_` -> `_s*_`): the name of the test that several
    seeds replicate."""
    return name.replace(f"_s{j.get('seed')}_", "_s*_", 1)


def ensemble(series, col, n=200):
    """Column col of several shears (one per seed) against the axial strain along the loading from the shear's start,
    each interpolated onto one grid of n points from 0 to the shortest shear's end: (grid, mean, standard deviation)."""
    curves = []
    for s in series:
        m = s["monotonic"]
        curves.append((np.abs(s["eps_a"][m] - s["eps_a"][m][0]), s[col][m]))
    x = np.linspace(0, min(ea[-1] for ea, _ in curves), n)
    ys = np.array([np.interp(x, ea, y) for ea, y in curves])
    return x, ys.mean(axis=0), ys.std(axis=0, ddof=1)


def seed_section(mono, window, tol, figs, peak=(0.0, None)):
    """Tests that differ only in the packing's random seed (the seed axis; study.json's jobs equal but for name, dir,
    sample and seed): per group the spread over the seeds of the density after consolidation, the peak (as the peak
    table takes it) and the critical state (of the seeds that reach one), each as mean ± standard deviation with the
    95 % interval of the mean (Student t), and the seeds a friction angle would need for +-SEED_PHI_TARGET. A single
    sample's result carries this scatter (a dense assembly is chaotic: a change of one rounding gives another, equally
    valid trajectory; perf/SPEED_VS_ERROR.md), so it is the error bar of every other table's single-seed numbers."""
    groups = {}
    for j, d, s in mono:
        key = tuple(sorted((k, json.dumps(seedless(v, j) if k == "rate_group" else v)) for k, v in j.items()
                           if k not in ("name", "dir", "sample", "seed")))
        groups.setdefault(key, []).append((j, s))
    # (a study.json without seeds, none of this build's, has no replicates to find)
    groups = {k: sorted(g, key=lambda t: t[0]["seed"]) for k, g in groups.items()
              if len({t[0].get("seed") for t in g}) > 1 and all("seed" in t[0] for t in g)}
    if not groups:
        return []
    pk_rows = ["| test (all seeds) | seeds | e_0 | e_0 interior | q_peak [kPa] | max q/p' | phi'_max [°] | seeds for ±"
               f"{SEED_PHI_TARGET:g}° |", "|---|---|---|---|---|---|---|---|"]
    cs_rows = ["| test (all seeds) | at critical state | p'_c [kPa] | q/p' | phi_cs [°] | e_c | e_c interior | a_c | "
               f"seeds for ±{SEED_PHI_TARGET:g}° |", "|---|---|---|---|---|---|---|---|---|"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    fig_c, ax_c = plt.subplots(1, 2, figsize=(12, 4.5))
    names = []
    for i, g in enumerate(sorted(groups.values(), key=lambda g: g[0][0]["name"])):
        j0 = g[0][0]
        name = seedless(j0["name"], j0)
        names.append(name)
        for a_, col in zip(ax_c, ("q_p", "e")):  # the seeds' mean curve with a band of one standard deviation
            x, mean, sd = ensemble([s for _, s in g], col)
            (ln,) = a_.plot(100 * x, mean, label=f"{name} ({len(g)} seeds)")
            a_.fill_between(100 * x, mean - sd, mean + sd, color=ln.get_color(), alpha=0.25, lw=0)
        seeds = ", ".join(str(j["seed"]) for j, _ in g)
        ps = [peak_state(s, peak) for _, s in g]
        cs = [critical_state(s, window, *tol) for _, s in g]
        cs = [c for c in cs if c is not None and c["ok"]]
        e0 = [float(s["e"][s["monotonic"]][0]) for _, s in g]
        e0_in = [float(s["e_inner"][s["monotonic"]][0]) if "e_inner" in s else None for _, s in g]
        phi_pk = [p["phi"] for p in ps if "phi" in p]
        pk_rows.append(f"| {name} | {len(g)} ({seeds}) | {seed_spread(e0, 4)} | {seed_spread(e0_in, 4)} | "
                       f"{seed_spread([p['q_peak'] / 1e3 for p in ps if 'M' in p], 1)} | "
                       f"{seed_spread([p['M'] for p in ps if 'M' in p], 3)} | {seed_spread(phi_pk, 2)} | "
                       f"{seeds_needed(phi_pk)} |")
        phi_cs = [c["phi"] for c in cs]
        cs_rows.append(f"| {name} | {len(cs)} of {len(g)} | {seed_spread([c['p'] / 1e3 for c in cs], 1)} | "
                       f"{seed_spread([c['M'] for c in cs], 3)} | {seed_spread(phi_cs, 2)} | "
                       f"{seed_spread([c['e'] for c in cs], 4)} | {seed_spread([c['e_inner'] for c in cs], 4)} | "
                       f"{seed_spread([c.get('a_c') for c in cs], 3)} | "
                       f"{seeds_needed(phi_cs)} |")
        for a_, v in zip(ax, ([p["M"] for p in ps if "M" in p], [c["M"] for c in cs], [c["e"] for c in cs])):
            if not v:
                continue
            a_.plot(np.full(len(v), i), v, "o", color="0.6", ms=4)
            if len(v) > 1:
                a_.errorbar([i + 0.15], [np.mean(v)], yerr=[t975(len(v) - 1) * np.std(v, ddof=1) / math.sqrt(len(v))],
                            fmt="s", color="k", capsize=4)
    for a_, lab in zip(ax, ("max q/p'", "critical q/p'", "e_c")):
        a_.set(ylabel=lab, title=lab + ": seeds (grey), mean and 95 % interval")
        a_.set_xticks(range(len(names)))
        a_.set_xlim(-0.5, len(names) - 0.5)
        a_.set_xticklabels(names, rotation=20, ha="right", fontsize=6)
        a_.grid(alpha=0.3)
    save(fig, figs, "seeds")
    for a_, lab in zip(ax_c, ("q/p'", "e")):
        a_.set(xlabel="axial strain along the loading [%]", ylabel=lab, title=lab + ": mean over the seeds ± one sd")
        a_.grid(alpha=0.3)
    legend(ax_c[0], fontsize=6)
    save(fig_c, figs, "seeds_curves")
    return ["## Sample-to-sample scatter (seed axis)", "",
            "Tests that differ only in the random seed of their packing. Each cell: the mean over the seeds ± their "
            "standard deviation (the scatter of one sample of this size) [the half-width of the mean's 95 % "
            "confidence interval, Student t with n - 1 degrees of freedom]. A dense packing is chaotic, so a single "
            "sample's peak or critical state is one draw: the standard deviation is the error bar of every single-seed "
            "number in this report. e_0 is the void ratio at the start of the shear (interior: of the box inset by "
            "two mean diameters, series e_inner, without the looser layer along the walls); peaks as the peak table takes "
            "them; critical states over the seeds that reach one. 'seeds for ±"
            f"{SEED_PHI_TARGET:g}°': the fewest seeds whose 95 % interval of the mean friction angle is within ±"
            f"{SEED_PHI_TARGET:g}°, if the seeds scatter as these do. Figures: `figures/seeds.png` (each seed, the mean and its 95 % "
            "interval), `figures/seeds_curves.png` (q/p' and e against strain: the seeds' mean ± one standard "
            "deviation).", "",
            *pk_rows, "", *cs_rows, ""]


def cyclic_stages(s, d):
    """A run's cyclic stages in order: (name, its rows' mask, its summary.json entry or None, the entry of an
    isotropic stage right after it or None). A staged test (cycles, a reconsolidation, cycles again: re-liquefaction;
    or amplitudes in turn) has several, each with its own N, criteria and quarter cycle. A run of a build before
    summary.json: its cyclic rows as one stage, without an entry."""
    stages = []
    if os.path.isfile(os.path.join(d, "summary.json")):
        stages = json.load(open(os.path.join(d, "summary.json")))["stages"]
    entries = {x["name"]: x for x in stages if x["type"] == "cyclic"}
    after = {a["name"]: b for a, b in zip(stages, stages[1:]) if a["type"] == "cyclic" and b["type"] == "isotropic"}
    if not entries:
        return [(None, s["cyclic"], None, None)]
    names = list(dict.fromkeys(s["stage"][s["cyclic"]]))  # in the order the rows give them
    return [(n, s["cyclic"] & (s["stage"] == n), entries.get(n), after.get(n)) for n in names]


def liquefaction_fit(points):
    """The liquefaction-resistance curve CSR = a N^-b through a group's (N, CSR) points, N the cycles to a criterion,
    by least squares on log CSR = log a - b log N (the power law of laboratory CSR - N curves: Idriss & Boulanger
    2008, b = 0.34 for clean sand), and CRR = a CRR_CYCLES^-b, the CSR that meets the criterion in 15 cycles. Returns
    a dict (a, b, crr, tests, n_min, n_max, rms: the root mean square of the residuals of log CSR), or None with fewer
    than two distinct N, or where the CSR does not fall as N rises (b <= 0: no resistance curve)."""
    n = np.array([x[0] for x in points], float)
    c = np.array([x[1] for x in points], float)
    if len(set(n.tolist())) < 2:
        return None
    slope, intercept = np.polyfit(np.log(n), np.log(c), 1)
    if not -slope > 0:
        return None
    resid = np.log(c) - (intercept + slope * np.log(n))
    a, b = math.exp(intercept), -slope
    return {"a": a, "b": b, "crr": a * CRR_CYCLES ** -b, "tests": len(n), "n_min": float(n.min()),
            "n_max": float(n.max()), "rms": float(np.sqrt(np.mean(resid ** 2)))}


# A study's conditions besides mu_r and the CSR that set a cyclic test's resistance (the job's study.json keys; 0:
# the base's value), each with its text: the liquefaction-resistance curves are fitted per mu_r and per value of
# each that differs among the tests (a curve through tests at two confining pressures, or drained and undrained,
# would mix two materials' responses)
CYCLIC_CONDITIONS = (("e0", lambda v: f"e0 {v:g}" if v else "e0 base"),
                     ("p0", lambda v: f"p'_0 {v / 1e3:g} kPa" if v else "p'_0 base"),
                     ("drainage", str),
                     ("count", lambda v: f"{v:g} spheres" if v else "base count"),
                     ("axial_strain_rate", lambda v: f"{v:g}/s" if v else "base rate"))


def stages_by_name(d):
    """A run's summary.json stages by name ({} where it has none or cannot be read)."""
    try:
        with open(os.path.join(d, "summary.json")) as f:
            return {st["name"]: st for st in json.load(f).get("stages", [])}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def cyclic_oedometer_rows(j, d, s, head=None):
    """A study test's cyclic oedometer stages as report rows (oedometer_cycles, summary.json): its section value where
    head is given, then the test, stage, sigma_v,0 and the amplitude (and its ratio), the cycles done, the permanent
    axial strain after the first and the last cycle, the mean increment per cycle early and late (cycle_increments),
    the power law's b, the rate's decay exponent m (rate_decay) and the strain per tenfold of cycles (log_law), M_eq,
    D_v and K of the first and the last cycle, the first cycle's quarter in wave transits. A strain-reversal stage's
    strain columns are "–" (eps_a comes back to 0 every cycle by construction; the run's closing line gives the sigma_v
    its cycles end at), its amplitude "eps_a ± A"."""
    summ = stages_by_name(d)
    rows = []
    for name, c in oedometer_cycles(d, s).items():
        st = summ.get(name, {})
        A = st.get("sigma_v_amplitude")
        sv0 = st.get("sigma_v_0")
        if sv0 is None and st.get("p_0") is not None:  # a strain reversal's start, as the run takes it
            sv0 = vertical_stress_0(st)
        amp = f"{A / 1e3:.1f} ({A / sv0:.2f})" if A and sv0 else f"eps_a ± {c['emax'][0]:.3g}"
        strain = (f"{c['eps'][0]:.3f} | {c['eps'][-1]:.3f} | {cycle_increments(c['eps'])} | "
                  f"{power_law_text(c['N'], c['eps'])} | {rate_decay_text(c['N'], c['eps'])} | "
                  f"{log_law_text(c['N'], c['eps'])}") if A else "– | – | – | – | – | –"
        qt = st.get("quarter_cycle_transits")
        dyn = "" if qt is None or qt >= QUASI_STATIC_TRANSITS else " (dynamic)"
        rows.append(("" if head is None else f"| {head} ") +
                    f"| {j['name']} | {name} | {number_text(sv0 / 1e3 if sv0 else None, '.1f')} | {amp} | "
                    f"{int(c['N'][-1])} | {strain} | "
                    f"{c['M'][0]:.1f} → {c['M'][-1]:.1f} | {c['D'][0]:.3f} → {c['D'][-1]:.3f} | "
                    f"{c['Dn'][0]:.3f} → {c['Dn'][-1]:.3f} | "
                    f"{c['K'][0]:.3f} → {c['K'][-1]:.3f} | {number_text(qt, '.2f')}{dyn} |")
    return rows


def power_law(N, eps):
    """The permanent strain's power law eps_p = eps_1 N^b (Monismith et al. 1975, the pavement and ballast literature's
    model), least squares in ln eps_p - ln N over the whole cycles: (b, its standard error), None under 3 cycles or with
    a strain not above 0."""
    N, eps = np.asarray(N, dtype=float), np.asarray(eps, dtype=float)
    if len(N) < 3 or not np.all(eps > 0):
        return None
    b, _, sb, _ = fit(np.log(N), np.log(eps))
    return b, sb


def power_law_text(N, eps):
    """power_law as a cell: "b ± se" (the fit's own standard error), "–" where there is none."""
    p = power_law(N, eps)
    return "–" if p is None else f"{p[0]:.3f} ± {p[1]:.3f}"


def rate_windows(N, eps):
    """The permanent strain's rate per cycle over doubling windows of cycles from the second (the first, the virgin
    loading's, apart): [2, 4], [4, 8], [8, 16], ..., the last ending at the last cycle (one shorter than half the
    window before it joins that one). Each window (a, b, rate, N_m): rate = (eps_b - eps_a) / (b - a) [%/cycle], N_m =
    (b - a) / ln(b / a), the cycle at which 1/N is the window's mean, so that a logarithmic law's rate c / N is exact
    at N_m; doubling windows make a power law's rates exact in slope too (each window the one before scaled by 2).
    Cycles missing from N end the windows there."""
    at = {int(n): float(e) for n, e in zip(N, eps)}
    n = 1
    while n + 1 in at:
        n += 1
    edges = [2]
    while edges[-1] * 2 <= n:
        edges.append(edges[-1] * 2)
    if edges[-1] < n:
        if len(edges) > 1 and n - edges[-1] < (edges[-1] - edges[-2]) / 2:
            edges[-1] = n
        else:
            edges.append(n)
    return [(a, b, (at[b] - at[a]) / (b - a), (b - a) / math.log(b / a)) for a, b in zip(edges, edges[1:])]


def rate_decay(N, eps):
    """How the permanent strain's rate per cycle dies away: rate ~ N^-m fitted by least squares in ln rate - ln N_m
    over rate_windows' windows (three at least: 10 cycles). m > 1: the strain bounded (its sum converges:
    shakedown); m = 1: the logarithmic law eps_p = a + c ln N (Barksdale 1972), each doubling of N adding the same
    strain; 0 < m < 1: growth as a power of N (Monismith's b = 1 - m for a pure power law); m = 0: a constant rate,
    ratcheting. dict(m, se (the fit's own standard error), windows) or dict(why) where it cannot be taken: too few
    cycles, or a window the strain did not rise over (no power of N describes it)."""
    w = rate_windows(N, eps)
    if len(w) < 3:
        return dict(why="under 10 cycles", windows=w)
    flat = [(a, b) for a, b, r, _ in w if not r > 0]
    if flat:
        return dict(why=f"no rise over cycles {flat[0][0]}–{flat[0][1]}", windows=w)
    slope, _, se, _ = fit(np.log([x[3] for x in w]), np.log([x[2] for x in w]))
    # a constant rate's slope comes out +-1e-17: rounded at 1e-12 (and -0.0 made 0.0) so that it prints, and pools
    # over seeds, as 0.00 rather than -0.00
    return dict(m=round(-slope, 12) + 0.0, se=se, windows=w)


def rate_decay_text(N, eps):
    """rate_decay as a cell: "m ± se (w windows)", or "– (why)"."""
    d = rate_decay(N, eps)
    return f"– ({d['why']})" if "why" in d else f"{d['m']:.2f} ± {d['se']:.2f} ({len(d['windows'])} windows)"


def log_law(N, eps):
    """The permanent strain per tenfold of cycles: eps_p = a + c ln N (Barksdale 1972) fitted by least squares over
    the cycles from the second (the first, the virgin loading's, apart, as rate_windows'), (c ln 10, its standard
    error ln 10) [% per decade]: the strain ten times the cycles add where m = 1 (on 2 000 spheres cycled 200 times
    about 200 kPa, cycles 2-20 and 20-200 added the same within the seeds' scatter:
    configs/cyclic-oedometer-long-study.yaml); None under 4 cycles."""
    N, eps = np.asarray(N, dtype=float)[1:], np.asarray(eps, dtype=float)[1:]
    if len(N) < 3:
        return None
    c, _, sc, _ = fit(np.log(N), eps)
    return c * math.log(10), sc * math.log(10)


def log_law_text(N, eps):
    """log_law as a cell: "c ± se", "–" where there is none."""
    p = log_law(N, eps)
    return "–" if p is None else f"{p[0]:.3f} ± {p[1]:.3f}"


def increments_early_late(eps):
    """cycle_increments' numbers: (early, late) [%/cycle], None under 3 cycles."""
    n = len(eps)
    if n < 3:
        return None
    k = max(1, n // 4)
    return (eps[k] - eps[0]) / k, (eps[-1] - eps[-1 - k]) / k


def cycle_increments(eps):
    """The permanent strain's mean increment per cycle [%] early and late, as the run's closing line gives it: over
    cycles 2 to 1 + k and over the last k, k a quarter of the n cycles (at least 1; the first, the virgin loading's,
    apart), "0.0077 (2–6) → 0.0013 (16–20)"; under 3 cycles the last cycle's."""
    n = len(eps)
    if n < 3:
        return f"{eps[-1] - (eps[-2] if n > 1 else 0):.4f} (last)"
    k = max(1, n // 4)

    def span(a, b):
        return f"{a}" if a == b else f"{a}–{b}"
    return f"{(eps[k] - eps[0]) / k:.4f} ({span(2, 1 + k)}) → {(eps[-1] - eps[-1 - k]) / k:.4f} ({span(n - k + 1, n)})"


CYCLIC_OEDOMETER_TEXT = (
    "The lateral walls held, sigma_v = sigma_z of the walls reversing at sigma_v,0 ± A (the stage's sigma_v_amplitude; "
    "sigma_v,0 where the stage began, summary.json) or eps_a at ± strain_amplitude. Per whole cycle (cycles.csv): the "
    "permanent axial strain at its end (eps_v there: the held walls make it eps_a), its mean increment per cycle early "
    "and late (over cycles 2 to 1 + k and the last k, k a quarter of the cycles: one that holds is ratcheting, one "
    "falling towards nothing shakedown), the exponent b of the power law eps_p = eps_1 N^b fitted to it (Monismith "
    "et al. 1975; least squares in the logarithms, ± the fit's standard error, which the cycles' serial correlation "
    "makes optimistic), the exponent m of the strain's rate per cycle, rate ~ N^-m, fitted over doubling windows of "
    "cycles from the second (2-4, 4-8, 8-16, ...; ± the fit's standard error): m > 1 the strain is bounded "
    "(shakedown), m = 1 the logarithmic law eps_p = a + c ln N (Barksdale 1972: each doubling of N adds the same "
    "strain), 0 < m < 1 a power of N (a pure power law's m is 1 - b), m = 0 a constant rate (ratcheting); '–' with the "
    "reason where a window's strain did not rise or there are under 10 cycles; the strain per tenfold of cycles, c ln "
    "10 of eps_p = a + c ln N fitted from the second cycle (± the fit's standard error): what ten times the cycles add "
    "where m = 1. The constrained modulus M_eq = (sigma_v,max - "
    "sigma_v,min) / (eps_max - eps_min) and damping ratio D_v of the sigma_v - eps_a loop (the first cycle's is not "
    "closed: its plastic strain counts as area; its area about the cycle's first sigma_v), D_v less the local "
    "damping's drag (the contacts' loop; cycles.csv damping_v_less_drag), and K = sigma_h / sigma_v at the cycle's "
    "end (at sigma_v,0: the "
    "lateral stress the cycles lock in); first → last cycle. The quarter cycle in wave transits as the liquefaction "
    "table's (below 4: dynamic). A strain-reversal test's strain columns are '–': its eps_a comes back to 0 every "
    "cycle, and the stress moves instead (the run's closing line gives sigma_v at the cycles' ends).")
CYCLIC_OEDOMETER_HEAD = ("| test | stage | sigma_v,0 [kPa] | A [kPa] (A / sigma_v,0) | cycles | eps_a after 1 [%] | "
                         "after the last [%] | per cycle early → late [%] (cycles) | b of eps_p = eps_1 N^b | "
                         "m of rate ~ N^-m | per tenfold N [%] (a + c ln N) | "
                         "M_eq [MPa] | D_v | "
                         "D_v less drag | K | "
                         "quarter cycle [transits] |")


def cyclic_oedometer_pooled(coed, head_of=None):
    """The tests of coed ((job, run dir, series)) that differ only in their seed, pooled: per group of two or more, one
    row of each measure's mean ± sd [95 % half-width of the mean] over the seeds (seed_spread): the permanent strain
    after the first and the last cycle, the increment per cycle early and late, the power law's b, the rate's decay
    exponent m (of the seeds that have one), the strain per tenfold of cycles, and the last
    cycle's M_eq, D_v, D_v less the drag and K. head_of: job name -> its section's value (a first column). A group is
    the stage, the amplitude, the cycles done and every job key but the seed's (and the names it sets)."""
    groups = {}
    for j, d, s in coed:
        cyc, summ = oedometer_cycles(d, s), stages_by_name(d)
        rest = tuple(sorted((k, json.dumps(v, sort_keys=True)) for k, v in j.items()
                            if k not in ("name", "dir", "seed", "sample")))
        for name, c in cyc.items():
            A = summ.get(name, {}).get("sigma_v_amplitude")
            if not A:  # strain reversal: no strain to pool
                continue
            key = (head_of(j) if head_of else None, name, A, int(c["N"][-1]), rest)
            groups.setdefault(key, []).append((j, c))
    rows = []
    for (head, name, A, n, _), tests in groups.items():
        if len(tests) < 2:
            continue
        cs = [c for _, c in tests]
        inc = [increments_early_late(c["eps"]) for c in cs]
        law = [power_law(c["N"], c["eps"]) for c in cs]
        decay = [rate_decay(c["N"], c["eps"]) for c in cs]
        decade = [log_law(c["N"], c["eps"]) for c in cs]
        cells = [seed_spread([c["eps"][0] for c in cs], 3), seed_spread([c["eps"][-1] for c in cs], 3),
                 seed_spread([x[0] for x in inc if x], 4), seed_spread([x[1] for x in inc if x], 4),
                 seed_spread([x[0] for x in law if x], 3), seed_spread([x["m"] for x in decay if "m" in x], 2),
                 seed_spread([x[0] for x in decade if x], 3),
                 seed_spread([c["M"][-1] for c in cs], 1),
                 seed_spread([c["D"][-1] for c in cs], 3), seed_spread([c["Dn"][-1] for c in cs], 3),
                 seed_spread([c["K"][-1] for c in cs], 3)]
        rows.append(("" if head is None else f"| {head} ") + f"| {len(tests)} | {name} | {A / 1e3:.1f} | {n} | "
                    + " | ".join(cells) + " |")
    return rows


CYCLIC_OEDOMETER_POOLED_TEXT = (
    "Over the seeds: the tests that differ only in their seed, each measure's mean ± sd [95 % half-width of the "
    "mean] (the last cycle's M_eq, D_v and K).")
CYCLIC_OEDOMETER_POOLED_HEAD = ("| seeds | stage | A [kPa] | cycles | eps_a after 1 [%] | after the last [%] | "
                                "per cycle early [%] | late [%] | b | m | per tenfold N [%] | M_eq [MPa] | D_v | "
                                "D_v less drag | K |")


def cyclic_oedometer_section(coed, figs):
    """Cyclic oedometer tests of a study (cyclic_oedometer_rows), pooled over seeds (cyclic_oedometer_pooled), and
    figures/cyclic_oedometer.png."""
    rows = [r for j, d, s in coed for r in cyclic_oedometer_rows(j, d, s)]
    pooled = cyclic_oedometer_pooled(coed)
    fig_cyclic_oedometer([(d, s) for _, d, s in coed], figs)
    return ["## Cyclic oedometer tests", "", CYCLIC_OEDOMETER_TEXT + " Figure: `figures/cyclic_oedometer.png`.", "",
            CYCLIC_OEDOMETER_HEAD, "|---" * 16 + "|", *rows, "",
            *([CYCLIC_OEDOMETER_POOLED_TEXT, "", CYCLIC_OEDOMETER_POOLED_HEAD, "|---" * 15 + "|", *pooled, ""]
              if pooled else [])]


def cyclic_section(cyc, figs, colors, fits=None):
    """Cyclic tests of a study: the cycle number N each reached, N at each liquefaction criterion (from the run's
    summary.json: r_u = u/p'_0 reaching the stage's liquefaction_ru, the double-amplitude axial strain reaching its
    liquefaction_da_strain; both caught on the step), a row for each cyclic stage of a staged test, and the
    liquefaction-resistance curve CSR - N per mu_r of each test's first cyclic stage (figures/liquefaction.png; filled:
    N at a criterion, hollow: still standing after N cycles). fits: a list that gets each fitted curve's mu_r, conditions
    (its row's text, "" where none vary), criterion, tests and CRR as its row gives them."""
    rows = []
    fig, ax = plt.subplots(figsize=(7, 4.5))
    crits = set()
    staged = False
    met_at = {}  # (mu_r, conditions, criterion key): the (N, CSR) of each test's first cyclic stage that met it
    recon_rows = []  # undrained cyclic stages reconsolidated by the isotropic stage after them
    varying = [(k, text) for k, text in CYCLIC_CONDITIONS if len({r[0].get(k) for r in cyc}) > 1]

    def conditions(j, but=None):
        return ", ".join(text(j[k]) for k, text in varying if k != but)
    p0_of = {(r[0]["mu_r"], conditions(r[0])): r[0].get("p0", 0) for r in cyc}  # each group's p'_0 (0: the base's)
    rest_of = {(r[0]["mu_r"], conditions(r[0])): conditions(r[0], "p0") for r in cyc}  # its conditions less p'_0
    # a colour and a legend entry per curve: mu_r's, or with other conditions varying, one of each (mu_r, conditions)
    groups = sorted({(r[0]["mu_r"], conditions(r[0])) for r in cyc})
    color_of = {g: (colors[g[0]] if not varying else f"C{k % 10}") for k, g in enumerate(groups)}

    def label_of(mu_r, cond):
        return f"mu_r = {mu_r:g}" + (f", {cond}" if varying else "")
    for j, d, s in sorted(cyc, key=lambda r: (r[0]["mu_r"], r[0]["csr"])):
        stages = cyclic_stages(s, d)
        staged = staged or len(stages) > 1
        for k, (name, m, st, recon) in enumerate(stages):
            drainage = st["drainage"] if st is not None else j["drainage"]  # a staged test may mix them
            und = drainage == "undrained"
            n_end, p = s["cycle"][m][-1], s["p"][m]
            # r_u and p' from where the undrained loading began (p_c: the cyclic stage's start, or an undrained
            # stage's before it); drained, from the stage's first row
            ref = s["p_c"][m] if und else p[0]
            ru = f"{np.nanmax(s['u'][m] / s['p_c'][m]):.3f}" if und else "–"
            # the first cycle's quarter in wave transits (summary.json; a build before it, or no complete cycle: "–")
            tq = st.get("quarter_cycle_transits") if st is not None else None
            quarter = "–" if tq is None else f"{tq:.3g}" + (" (dynamic)" if tq < QUASI_STATIC_TRANSITS else "")
            if st is None:  # a run of a build before summary.json: no criteria to read
                n_ru = n_da = "– (no summary.json)"
            else:
                crits.add((st["liquefaction_ru"], st["liquefaction_da_strain"]))
                n_ru = ("not met" if st["n_ru"] is None else f"{st['n_ru']:.3g}") if und else "– (drained)"
                n_da = "not met" if st["n_da"] is None else f"{st['n_da']:.3g}"
            cycles = st["cycles"] if st is not None else j["cycles"]
            end = (f"\\|eps_a\\| = {100 * abs(s['eps_a'][m][-1]):.2f} %" if n_end < cycles
                   else f"{cycles} cycles done")
            # the stage's CSR as the run applied it (summary.json csr = q_amplitude / (2 p'_c): each stage of a staged
            # test its own), else the study's csr axis (a build before summary.json's csr). Where the two differ by more
            # than 1 % (the axis's q_amplitude = 2 csr p'_0 is of the preparation's pressure, and a q_amplitude stage
            # after a K0 or drained stage starts from another p': the study warned) the run's, the axis's beside it
            run_csr = float(st["csr"]) if st is not None and st.get("csr") is not None else float("nan")
            csr, csr_text = (run_csr, f"{run_csr:g}") if not j["csr"] > 0 else (j["csr"], f"{j['csr']:g}")
            if j["csr"] > 0 and abs(run_csr - j["csr"]) > 0.01 * j["csr"]:
                csr, csr_text = run_csr, f"{run_csr:.3g} (axis {j['csr']:g})"
            test = j["name"] + (f" ({name})" if len(stages) > 1 else "")
            rows.append(f"| {test} | {j['mu_r']:g} | {drainage} | {csr_text} | {n_end:.3g} | {end} | {n_ru} | "
                        f"{n_da} | {np.nanmin(p / ref):.3f} | {ru} | {quarter} |")
            if k == 0:
                first = (n_end, st, csr)
            if recon is not None and und and "e" in st and "e" in recon:
                # the volume the sample loses reconsolidated after undrained cycling, as a lab measures it: the box's
                # void ratio at the two stages' ends (summary.json)
                eps_v = (st["e"] - recon["e"]) / (1 + st["e"])
                # and the interior's (series e_inner at the cycles' last row, the reconsolidated e_inner of
                # summary.json): the box's strain less the looser layer along the walls, which a DEM sample has and
                # a lab specimen's membrane does not; "–" for a run of a build before e_inner
                ei_c = s["e_inner"][m][-1] if "e_inner" in s else float("nan")
                ei_r = recon.get("e_inner")
                eps_in = (f"{100 * (ei_c - ei_r) / (1 + ei_c):.3f}" if ei_r is not None and np.isfinite(ei_c)
                          else "–")
                recon_rows.append(f"| {test} | {recon['name']} | {ru} | {100 * np.max(np.abs(s['eps_a'][m])):.2f} | "
                                  f"{recon['p'] / 1e3:.4g} | {100 * eps_v:.3f} | {eps_in} |")
        n_end, st, csr = first
        if not csr > 0:
            continue
        g = (j["mu_r"], conditions(j))
        c = color_of[g]
        met = False
        for key, marker in (("n_da", "o"), ("n_ru", "s")):
            if st is not None and st[key] is not None:
                ax.plot([max(st[key], 1e-2)], [csr], marker, color=c, label=label_of(*g))
                met = True
                if st[key] > 0:
                    met_at.setdefault((j["mu_r"], conditions(j), key), []).append((st[key], csr))
        if not met:
            ax.plot([max(n_end, 1e-2)], [csr], ">", color=c, markerfacecolor="none", label=label_of(*g))
    crit = next(iter(crits)) if len(crits) == 1 else None  # the tests' thresholds, where they share them
    fit_rows, unfitted, fitted = [], [], set()
    by_p0 = {}  # (mu_r, the other conditions, criterion): [(p'_0, CRR)] of the curves fitted at each p'_0
    for (mu_r, cond, key), pts in sorted(met_at.items()):
        what = (f"{100 * crit[1]:g} % DA strain" if crit else "DA strain") if key == "n_da" else \
            (f"r_u = {crit[0]:g}" if crit else "r_u")
        f = liquefaction_fit(pts)
        if f is None:
            unfitted.append(f"mu_r {mu_r:g}{', ' + cond if varying else ''}, {what} "
                            f"({len(pts)} test{'s' if len(pts) != 1 else ''})")
            continue
        crr = f"{f['crr']:.4g}" + ("" if f["n_min"] <= CRR_CYCLES <= f["n_max"] else " (extrapolated)")
        fit_rows.append(f"| {mu_r:g} | {cond + ' | ' if varying else ''}{what} | {f['tests']} | {f['a']:.4g} | "
                        f"{f['b']:.4g} | {crr} | {f['n_min']:.3g}–{f['n_max']:.3g} | {f['rms']:.3g} |")
        if fits is not None:
            fits.append(dict(mu_r=mu_r, cond=cond if varying else "", what=what, tests=f["tests"], crr=crr))
        if p0_of[(mu_r, cond)] > 0:  # the CRR of each confining pressure, for K_sigma
            by_p0.setdefault((mu_r, rest_of[(mu_r, cond)], what), []).append((p0_of[(mu_r, cond)], f["crr"]))
        fitted.add((mu_r, key))
        nn = np.geomspace(f["n_min"], f["n_max"], 50)
        ax.plot(nn, f["a"] * nn ** -f["b"], "--" if key == "n_da" else ":", color=color_of[(mu_r, cond)], lw=1)
    # the markers' meaning as legend entries (grey), after one entry per mu_r
    for marker, text, face in (("o", f"{100 * crit[1]:g} % double amplitude" if crit else "DA strain criterion", "grey"),
                               ("s", f"r_u = {crit[0]:g}" if crit else "r_u criterion", "grey"),
                               (">", "standing at N reached", "none")):
        ax.plot([], [], marker, color="grey", markerfacecolor=face, linestyle="none", label=text)
    for style, key, text in (("--", "n_da", "a N^-b, DA strain"), (":", "n_ru", "a N^-b, r_u")):
        if any(k == key for (_, k) in fitted):
            ax.plot([], [], style, color="grey", lw=1, label=text)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    if uniq:
        ax.legend(uniq.values(), uniq.keys(), fontsize=8)
    ax.set(xscale="log", xlabel="cycles to liquefaction N", ylabel="CSR = q_amp / (2 p'_0)",
           title="liquefaction resistance")
    ax.grid(alpha=0.3, which="both")
    save(fig, figs, "liquefaction")
    return ["## Cyclic tests", "",
            "N is the cycle number, continuous: the k-th load reversal at N = (2k - 1)/4. A test ends when its cycles "
            "are done or |eps_a| reaches the stage's max_axial_strain. Liquefaction is the first N at which r_u = "
            "u/p'_0 (u/p'_c after an undrained stage) reached the stage's liquefaction_ru (initial liquefaction; "
            "undrained tests), or the double-amplitude axial strain (peak-to-peak eps_a of a half cycle) reached its liquefaction_da_strain (ASTM D5311), "
            "checked at every step" + (f" (here r_u {crit[0]:g} and {100 * crit[1]:g} %)" if crit else "") + ". " +
            ("A staged test has a row for each cyclic stage (test (stage)), each counting its N, criteria and quarter "
             "cycle from its own start, its p' and r_u from p'_c, where the undrained loading began; the figure is of "
             "each test's first cyclic stage (the later ones load a sample the first has sheared). " if staged else "") +
            "The quarter cycle is the first cycle's duration over 4 in transits of a compression wave across the sample "
            f"(summary.json); below {QUASI_STATIC_TRANSITS} the loops carry the sample's inertia (dynamic): load slower "
            "for the material's response. CSR is the study's csr, or the stage's q_amplitude / (2 p'_c) as the run "
            "applied it (summary.json) where there is none or the two differ by more than 1 % (the axis's beside it: "
            "a q_amplitude stage that starts where a K0 or drained stage left the sample).", "",
            "| test | mu_r | drainage | CSR | N reached | end | N at r_u | N at DA strain | min p'/p'_0 | max r_u "
            "| quarter cycle [transits] |",
            "|---|---|---|---|---|---|---|---|---|---|---|", *rows, "",
            *fit_section(fit_rows, unfitted, ", ".join(k for k, _ in varying)), *overburden_section(by_p0),
            *(["Reconsolidation after undrained cycling (an isotropic stage right after a cyclic one): the volumetric "
               "strain eps_v the sample takes as its pore pressure dissipates, from the box's void ratio at the two "
               "stages' ends, (e_cyclic - e_reconsolidated)/(1 + e_cyclic): the post-liquefaction settlement, which "
               "Ishihara & Yoshimine (1992) relate to the largest strain the cycles reached. The interior's eps_v is "
               "the same from e_inner (the box inset by two mean diameters: series at the cycles' last row, "
               "summary.json after): where it is well under the box's, the walls' looser layer takes much of the "
               "settlement, which a lab specimen's membrane would not.", "",
               "| test | reconsolidation stage | max r_u in the cycles | max \\|eps_a\\| in the cycles [%] | p' after "
               "[kPa] | eps_v [%] | eps_v interior [%] |", "|---|---|---|---|---|---|---|", *recon_rows, ""]
             if recon_rows else [])]


def overburden_factor(points):
    """K_sigma of a material's CRR at several confining pressures (Seed & Harder 1990): K = CRR(p'_0) / CRR at the
    lowest p'_0, and C_sigma of K = 1 - C_sigma ln(p'_0 / p'_ref) by least squares through K(p'_ref) = 1 (Idriss &
    Boulanger 2008's form, their p'_ref one atmosphere; here the lowest p'_0 tested). points: [(p'_0, CRR)] at two
    distinct p'_0 or more. Returns ([(p'_0, CRR, K)] by p'_0, C_sigma)."""
    pts = sorted(points)
    p_ref, crr_ref = pts[0]
    rows = [(p, c, c / crr_ref) for p, c in pts]
    x = np.array([math.log(p / p_ref) for p, _, _ in rows])
    k = np.array([kk for _, _, kk in rows])
    return rows, float(-np.sum(x * (k - 1)) / np.sum(x * x))


ATMOSPHERE = 101.325e3  # Pa: one atmosphere, p_a (Idriss & Boulanger's reference pressure; Darendeli's)


def at_one_atmosphere(rows, c_sigma):
    """overburden_factor's line K = 1 - C ln(p'/p'_ref) referred to one atmosphere: CRR(p_a) = CRR_ref (1 - C
    ln(p_a/p'_ref)), and as CRR(p')/CRR(p_a) = 1 - C' ln(p'/p_a) exactly with C' = C / (1 - C ln(p_a/p'_ref)). Returns
    (CRR at p_a, C', whether p_a lies outside the pressures tested), or None where the line reaches p_a at CRR <= 0."""
    p_ref, crr_ref = rows[0][0], rows[0][1]
    f = 1 - c_sigma * math.log(ATMOSPHERE / p_ref)
    if not f > 0:
        return None
    return crr_ref * f, c_sigma / f, not rows[0][0] <= ATMOSPHERE <= rows[-1][0]


def overburden_section(by_p0):
    """The report's K_sigma table (overburden_factor) for each material and criterion whose CRR was fitted at two
    confining pressures or more (a p0 axis); nothing otherwise."""
    rows = []
    for (mu_r, rest, what), pts in sorted(by_p0.items()):
        if len({p for p, _ in pts}) < 2:
            continue
        r, c_sigma = overburden_factor(pts)
        atm = at_one_atmosphere(r, c_sigma)
        atm_text = "– | –" if atm is None else \
            f"{atm[0]:.4g}{' (extrapolated)' if atm[2] else ''} | {atm[1]:.3f}"
        rows.append(f"| {mu_r:g} | {rest or '–'} | {what} | " + ", ".join(f"{p / 1e3:g}" for p, _, _ in r) + " | " +
                    ", ".join(f"{c:.4g}" for _, c, _ in r) + " | " + ", ".join(f"{kk:.3f}" for _, _, kk in r) +
                    f" | {c_sigma:.3f} | {atm_text} |")
    if not rows:
        return []
    return ["Overburden correction: K_sigma = CRR(p'_0) / CRR at the lowest p'_0 of each material and criterion "
            "(Seed & Harder 1990), and C_sigma of K_sigma = 1 - C_sigma ln(p'_0 / p'_0,lowest) by least squares (the "
            "form of Idriss & Boulanger 2008, who give C_sigma up to 0.3 for sands, rising with density). CRR as in the "
            "table above (extrapolated ones included). The lab's K_sigma compares one relative density: samples a p0 "
            "axis prepares from one gas are each consolidated to their own p'_0, so denser at the higher one (see the "
            "Samples section's e), which raises their CRR; an e0 axis (target_e0) prepares them at one void ratio. "
            "Referred to one atmosphere (p_a = 101.325 kPa, Idriss & Boulanger's reference) along the same line: CRR at "
            "p_a, and C_sigma of K_sigma = CRR(p'_0)/CRR(p_a) = 1 - C_sigma ln(p'_0/p_a) (extrapolated where p_a lies "
            "outside the pressures tested).", "",
            "| mu_r | other conditions | criterion | p'_0 [kPa] | CRR (N = 15) | K_sigma | C_sigma | CRR at 1 atm | "
            "C_sigma (1 atm) |",
            "|---|---|---|---|---|---|---|---|---|", *rows, ""]


def fit_section(fit_rows, unfitted, by=""):
    """The liquefaction-resistance curves of cyclic_section (liquefaction_fit): a table, and the groups left unfitted;
    `by`: the study's other conditions that differ among the tests (CYCLIC_CONDITIONS), a curve per value of each."""
    if not fit_rows and not unfitted:
        return []
    lines = [f"Liquefaction-resistance curves CSR = a N^-b per mu_r{', ' + by if by else ''} and criterion (least "
             f"squares in log-log over the "
             f"tests that met it; the figure's dashed (DA strain) and dotted (r_u) lines), and CRR, the CSR that meets "
             f"it in {CRR_CYCLES} cycles (a magnitude 7.5 earthquake's equivalent cycles, Seed et al. 1975; "
             f"extrapolated where the tests' N do not span {CRR_CYCLES}). Clean sands give b near 0.34 (Idriss & "
             f"Boulanger 2008).", ""]
    if fit_rows:
        lines += [f"| mu_r | {'conditions | ' if by else ''}criterion | tests | a | b | CRR (N = {CRR_CYCLES}) | N of "
                  f"the tests | rms of log CSR |", "|---|---|---|---|---|---|---|---|" + ("---|" if by else ""),
                  *fit_rows, ""]
    if unfitted:
        lines += ["Not fitted (fewer than two tests meeting the criterion at different N, or a CSR that does not fall as "
                  "N rises): " + "; ".join(unfitted) + ".", ""]
    return lines


def hyperbolic_fit(eps, E):
    """The hyperbola of Hardin & Drnevich (1972), E = E_max / (1 + eps/eps_r), fitted by least squares on its
    linear form 1/E = a + b eps with each residual weighted by E: the residual E (a + b eps) - 1 = E/E_fit - 1 is
    the relative misfit, so a 1e-5 and a 5e-3 amplitude weigh alike. Returns (E_max, eps_r, rms relative misfit),
    or None with fewer than two amplitudes, or where E does not fall with strain (a or b <= 0)."""
    eps, E = np.asarray(eps, float), np.asarray(E, float)
    if len(set(eps.tolist())) < 2:
        return None
    (a, b), *_ = np.linalg.lstsq(np.column_stack([E, E * eps]), np.ones_like(E), rcond=None)
    if not (a > 0 and b > 0):
        return None
    e_max, eps_r = 1 / a, a / b
    return e_max, eps_r, float(np.sqrt(np.mean((E * (a + b * eps) - 1) ** 2)))


def damping_fit(E_ratio, D):
    """Hardin & Drnevich's damping, D = D_min + (D_max - D_min)(1 - E/E_max), by least squares in x = 1 - E/E_max:
    returns (D_min, D_max), or None with fewer than two distinct x. (The same for G/G_max.) A damping ratio is not
    negative: where the free line's D_min is (measured: -0.002 for configs/modulus-study.yaml's mu_r 0), the least
    squares under D_min >= 0, which for a convex quadratic in two unknowns lie on the bound: D_min = 0 and
    D_max = sum(x D) / sum(x^2)."""
    x, D = 1 - np.asarray(E_ratio, float), np.asarray(D, float)
    if len(set(x.tolist())) < 2:
        return None
    (d0, slope), *_ = np.linalg.lstsq(np.column_stack([np.ones_like(x), x]), D, rcond=None)
    if d0 < 0:
        return 0.0, float(np.dot(x, D) / np.dot(x, x))
    return float(d0), float(d0 + slope)


# Darendeli (2001), the modulus reduction of soils from resonant-column and torsional-shear tests:
# G/G_max = 1 / (1 + (gamma/gamma_r)^a), a = 0.919, gamma_r [%] = (0.0352 + 0.0010 PI OCR^0.3246) (sigma'_0/p_a)^0.3483.
# For clean sand (PI = 0) OCR drops out. A reference for the DEM's curve, not a fit: real grains are not spheres.
DARENDELI_A, DARENDELI_PA = 0.919, ATMOSPHERE


def darendeli_gamma_r(p):
    """Darendeli's reference shear strain (single amplitude, as a fraction) of clean sand at mean effective stress p [Pa]."""
    return 0.0352e-2 * (p / DARENDELI_PA) ** 0.3483


def darendeli_modulus(gamma, p):
    """Darendeli's G/G_max of clean sand at shear strain gamma (single amplitude) and mean effective stress p [Pa]."""
    return 1 / (1 + (np.asarray(gamma, float) / darendeli_gamma_r(p)) ** DARENDELI_A)


def cycle_shear(row, drainage):
    """A cycles.csv row's single-amplitude shear strain (gamma_max - gamma_min)/2 and G_eq; from a build before those
    columns, or a cycle a pre-gamma checkpoint left without them (nan): the undrained values gamma = 1.5 eps_a and
    G = E_eq/3 (constant volume), and (nan, nan) drained, where they depend on the lateral strain it did not record."""
    g = float(row.get("G_eq") or "nan")
    if g == g:
        return (float(row["gamma_max"]) - float(row["gamma_min"])) / 2, g
    if drainage == "undrained":
        return 0.75 * (float(row["eps_a_max"]) - float(row["eps_a_min"])), float(row["E_eq"]) / 3
    return float("nan"), float("nan")


def cycle_damping_less_drag(row):
    """A cycles.csv row's damping ratio of the walls' q less the local damping's drag (CycleLoop): the contacts' loop,
    where the walls' D carries the drag's area too; nan from a build before the column, or where it was not known."""
    v = row.get("damping_less_drag")
    return float(v) if v not in (None, "") else float("nan")


def modulus_section(amp, stage, figs):
    """Tests of a strain_amplitude axis: each test's last complete cycle of the strain-controlled stage (cycles.csv),
    its equivalent moduli E_eq and G_eq and damping ratio D against the measured single-amplitude strains, per group
    of tests that differ only in the amplitude (a sample, a drainage); per group the hyperbolic fits (hyperbolic_fit,
    damping_fit) and figures/modulus_reduction.png: G/G_0 and D against gamma, with Darendeli's clean sand."""
    groups = {}
    for j, d, s in amp:
        key = tuple((k, j[k]) for k in ("mu_r", "e0", "p0", "seed", "count", "drainage", "csr"))
        groups.setdefault(key, []).append((j, d, s))
    varying = [k for k in ("mu_r", "e0", "p0", "seed", "count", "drainage")
               if len({dict(g)[k] for g in groups}) > 1] or ["mu_r"]

    def name(key):
        g = dict(key)
        return " ".join(f"{k}={g[k]:g}" if isinstance(g[k], (int, float)) else g[k] for k in varying)

    def pct(x, fmt):
        return "–" if x != x else f"{100 * x:{fmt}}"

    rows, fits, notes = [], [], []
    refs, span = set(), (np.inf, 0)  # the groups' p'_0 (3 digits) and the strains the figure spans
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, (key, tests) in enumerate(sorted(groups.items())):
        pts = []  # (test, its last cycle's cycles.csv row, p'_0)
        for j, d, s in sorted(tests, key=lambda r: r[0]["strain_amplitude"]):
            path = os.path.join(d, "cycles.csv")
            cyc = []
            if os.path.isfile(path):
                with open(path) as f:
                    cyc = [r for r in complete_cycles(csv.DictReader(f)) if not stage or r["stage"] == stage]
            if cyc:
                pts.append((j, cyc[-1], s["p"][s["cyclic"]][0]))  # p'_0: the stage's first row
            else:
                rows.append(f"| {j['name']} | {name(key)} | {100 * j['strain_amplitude']:.3g} | no complete cycle "
                            "| | | | | | | | | |")
        if not pts:
            continue
        ea = np.array([(float(r["eps_a_max"]) - float(r["eps_a_min"])) / 2 for _, r, _ in pts])  # single amplitude
        E, D = (np.array([float(r[k]) for _, r, _ in pts]) for k in ("E_eq", "damping"))
        Dn = np.array([cycle_damping_less_drag(r) for _, r, _ in pts])
        ga, G = np.array([cycle_shear(r, j["drainage"]) for j, r, _ in pts]).T
        # G_0: the group's smallest amplitude (the lab's small-strain modulus); where that test has no complete
        # cycle, the smallest that has one, and the report says so (every G_eq/G_0 of the group is relative to it)
        G0, p0 = G[0], float(np.mean([p for _, _, p in pts]))
        smallest = min(j["strain_amplitude"] for j, _, _ in tests)
        if pts[0][0]["strain_amplitude"] > smallest:
            notes.append(f"Group {name(key)}: G_0 is the {100 * pts[0][0]['strain_amplitude']:.3g} % test's G_eq, since "
                         f"the group's smallest amplitude ({100 * smallest:.3g} %) has no complete cycle.")
        for (j, r, p0j), a, g, e, gm, dmp, dn in zip(pts, ea, ga, E, G, D, Dn):
            ru = f"{float(r['r_u_max']):.3f}" if j["drainage"] == "undrained" else "–"
            rows.append(f"| {j['name']} | {name(key)} | {100 * j['strain_amplitude']:.3g} | {100 * a:.4g} | "
                        f"{pct(g, '.4g')} | {r['cycle']} | {e / 1e6:.4g} | {gm / 1e6:.4g} | {gm / G0:.3f} | {dmp:.3f} | "
                        + ("–" if dn != dn else f"{dn:.3f}") + f" | {float(r['p']) / p0j:.3f} | {ru} |")
        c = f"C{i % 10}"
        ok = ga == ga  # cycles with a shear strain (all but a drained pre-gamma build's)
        ax[0].plot(100 * ga[ok], G[ok] / G0, "o", color=c, label=name(key))
        ax[1].plot(100 * ga[ok], D[ok], "o", color=c)
        known_n = ok & (Dn == Dn)
        if known_n.any():
            ax[1].plot(100 * ga[known_n], Dn[known_n], "x", color=c)
        xs = np.geomspace(max(ga[ok].min(), 1e-7) / 3, ga[ok].max() * 3, 100) if ok.any() else None
        if xs is not None:
            span = (min(span[0], xs[0]), max(span[1], xs[-1]))
            refs.add(float(f"{p0:.3g}"))
        hf_e, hf = hyperbolic_fit(ea, E), hyperbolic_fit(ga[ok], G[ok])
        e_txt = f"{hf_e[0] / 1e6:.4g} | {100 * hf_e[1]:.3g}" if hf_e else "– | –"
        dar = f"{100 * darendeli_gamma_r(p0):.3g}"
        if hf is None:
            fits.append(f"| {name(key)} | {len(pts)} | {e_txt} | no fit: G_eq does not fall with strain | | | | | | | "
                        f"{dar} |")
            continue
        g_max, g_r, rms = hf
        df = damping_fit(G[ok] / g_max, D[ok])
        # the same fit to D less the drag, where every test of the group has it (an older build's cycles.csv has not)
        dfn = damping_fit(G[ok] / g_max, Dn[ok]) if np.isfinite(Dn[ok]).all() else None
        ax[0].plot(100 * xs, g_max / (1 + xs / g_r) / G0, "--", color=c)
        if df is not None:
            ax[1].plot(100 * xs, df[0] + (df[1] - df[0]) * (1 - 1 / (1 + xs / g_r)), "--", color=c)
        fits.append(f"| {name(key)} | {len(pts)} | {e_txt} | {g_max / 1e6:.4g} | {100 * g_r:.3g} | {100 * rms:.1f} | "
                    + (f"{df[0]:.3f} | {df[1]:.3f}" if df else "– | –") + " | "
                    + (f"{dfn[0]:.3f} | {dfn[1]:.3f}" if dfn else "– | –") + f" | {dar} |")
    for k, p in enumerate(sorted(refs)):  # Darendeli's clean sand, once per p'_0 (groups often share it)
        xs = np.geomspace(*span, 100)
        ax[0].plot(100 * xs, darendeli_modulus(xs, p), ":", color=str(0.2 + 0.5 * k / max(1, len(refs) - 1)),
                   label=f"Darendeli (2001) clean sand, p'_0 = {p / 1e3:g} kPa")
    ax[0].set(xscale="log", xlabel="single-amplitude gamma = eps_a - eps_r [%]", ylabel="G_eq / G_0",
              title="modulus reduction (dashed: hyperbola)")
    ax[1].set(xscale="log", xlabel="single-amplitude gamma [%]", ylabel="D",
              title="damping ratio (x: less the damping's drag)")
    finish(fig, ax, ax[0], 8, figs, "modulus_reduction")
    return ["## Modulus reduction and damping", "",
            "One test per strain amplitude, each on its own specimen of the sample, at one loading frequency (every "
            "quarter cycle as long as the base's). Each row is the test's last complete cycle"
            + (f" of stage `{stage}`" if stage else "") + " in cycles.csv: its measured single amplitudes of axial "
            "strain (eps_a_max - eps_a_min)/2 and of shear strain gamma = eps_a - eps_r (gamma_max - gamma_min)/2, the "
            "equivalent moduli E_eq = (q_max - q_min)/(eps_a_max - eps_a_min) and G_eq = (tau_max - tau_min)/(gamma_max "
            "- gamma_min) with tau = q/2, G_eq/G_0 with G_0 at the group's smallest amplitude, the damping ratio D = loop "
            "area / (2 pi q_a eps_a) (ASTM D3999) of the walls' q and of the walls' q less the local damping's drag "
            "(cycles.csv damping_less_drag: the drag opposes the straining both ways, so it adds area to the walls' loop; "
            "less it, the loop is the contacts'. It matters most at small strains, where the contacts dissipate least: "
            "30-60 % of D at eps_a = 1e-5 on configs/modulus_damping.yaml; \"–\" from a build before the column), "
            "p'/p'_0 at the cycle's end and its largest r_u.", "",
            "| test | group | eps_a amplitude [%] | measured eps_a [%] | gamma [%] | cycle | E_eq [MPa] | G_eq [MPa] | "
            "G_eq/G_0 | D | D less drag | p'/p'_0 | max r_u |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|", *rows, "", *(notes + [""] if notes else []),
            "Per group, the hyperbolas of Hardin & Drnevich (1972), E_eq = E_max / (1 + eps_a/eps_r) and G_eq = G_max / "
            "(1 + gamma/gamma_r), fitted to the relative misfit (rms given for G), and D = D_min + (D_max - D_min)(1 - "
            "G_eq/G_max), by least squares with D_min >= 0 (a D_min of 0 is the bound), to D and to D less the drag. "
            "Darendeli's gamma_r is that of clean sand at the group's p'_0 (Darendeli "
            "2001: 0.0352 % (p'_0/p_a)^0.3483; dotted in the figure, with its curvature 0.919), a reference for real "
            "sands, not a fit.", "",
            "| group | tests | E_max [MPa] | eps_r [%] | G_max [MPa] | gamma_r [%] | rms misfit of G [%] | D_min | D_max | "
            "D_min less drag | D_max less drag | Darendeli gamma_r [%] |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|", *fits, ""]


def main():
    # One parser per command, named as the user typed it ("grainlab plot"), with only its own options: one parser for
    # all three printed "usage: grainlab {plot,csl,study} runs" (study is the study report's internal entry) and took
    # --window for plot without a word.
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd not in ("plot", "csl", "study"):
        sys.exit("usage: grainlab_plot.py {plot,csl} RUN_DIR [RUN_DIR ...] [--out DIR] (csl: [--window W]); "
                 "study STUDY_DIR")
    ap = argparse.ArgumentParser(prog=f"grainlab {cmd}")
    ap.add_argument("runs", nargs=1 if cmd == "study" else "+", metavar="STUDY_DIR" if cmd == "study" else "RUN_DIR")
    if cmd != "study":
        ap.add_argument("--out", default=None, help="figure directory (default: the first run's figures/)")
    if cmd == "csl":
        ap.add_argument("--window", type=float, default=0.05, help="axial-strain window of the steadiness test")
    a = ap.parse_args(sys.argv[2:])
    a.cmd = cmd
    a.window = getattr(a, "window", 0.05)
    if not 0 < a.window < 1:  # as a study's critical_state.window
        sys.exit(f"grainlab {a.cmd}: --window must be in (0, 1) (a span of axial strain), got {a.window:g}")
    if a.cmd == "study":
        study(a.runs[0])
        return
    runs = []
    seen = {}
    for r in a.runs:
        if not os.path.isfile(os.path.join(r, "series.csv")):
            if os.path.isfile(os.path.join(r, "study.json")):
                # a study's own: its report has the figures of all its tests; its runs are each job's run/
                sys.exit(f"grainlab {a.cmd}: {r}: a study's directory, not a run's: its figures are in "
                         f"{os.path.join(r, 'figures')} (grainlab study remakes them), its runs are "
                         f"{os.path.join(r, 'jobs', '*', 'run')}")
            sys.exit(f"grainlab {a.cmd}: {r}: no series.csv (not a run directory)")
        # The same run twice (runs/a and runs/a/, a link, a shell glob that overlaps) would count its critical state
        # twice in csl's fits and draw its curves twice.
        real = os.path.realpath(r)
        if real in seen:
            sys.exit(f"grainlab {a.cmd}: {r}: the same run as {seen[real]}, given earlier")
        seen[real] = r
        runs.append((r, load(r, f"grainlab {a.cmd}")))
    out = a.out or os.path.join(a.runs[0], "figures")
    if os.path.exists(out) and not os.path.isdir(out):  # makedirs would say "File exists"
        sys.exit(f"grainlab {a.cmd}: error: {out}: a file, not a directory (--out names the folder of the figures)")
    os.makedirs(out, exist_ok=True)
    if a.cmd == "plot":
        fig_stress(runs, out)
        fig_anisotropy(runs, out)
        fig_sff(runs, out)
        fig_fractions(runs, out)
        fig_cyclic(runs, out)
        fig_cyclic_oedometer(runs, out)
        fig_oedometric(runs, out)
        fig_modulus_damping(runs, out)
        fig_grading(a.runs, out)
        fig_forcechains(a.runs[0], out)
        fig_contacts(a.runs[0], out, save, plt)
        size_classes.write_csv(a.runs[0], out)
        fig_localisation(a.runs[0], out, save, plt)
    else:
        csl(runs, out, a.window)


class _Console:
    """The standard output, outliving its reader: `grainlab plot RUN | head -n 1` stopped at the first figure with
    "error: : Broken pipe". The figures are the product and the lines only name them, so once the reader has gone the
    lines go to /dev/null and the figures are all made."""

    def __init__(self, f):
        self.f = f

    def _drop(self):
        os.dup2(os.open(os.devnull, os.O_WRONLY), self.f.fileno())

    def write(self, s):
        try:
            return self.f.write(s)
        except BrokenPipeError:
            self._drop()
            return len(s)

    def flush(self):
        try:
            self.f.flush()
        except BrokenPipeError:
            self._drop()

    def __getattr__(self, name):
        return getattr(self.f, name)


if __name__ == "__main__":
    sys.stdout = _Console(sys.stdout)
    FIGURE_JOBS = figure_jobs(sys.argv[1] if len(sys.argv) > 1 else "")
    FIGURE_FORMATS = figure_formats(sys.argv[1] if len(sys.argv) > 1 else "")
    # A file-system error (an --out that cannot be created, a full disk, no permission) is one line naming the
    # path, like the engine's errors; what was written before stays whole (scripts/atomic_write.py).
    try:
        try:
            main()
            figures_done()
        finally:
            # an error of the parent's own: the figures being written end first (their errors second to it)
            while _FIGURE_CHILDREN:
                try:
                    _reap_figure()
                except (OSError, RuntimeError):
                    pass
        sys.stdout.flush()
    except OSError as e:
        where = f"{e.filename}: " if e.filename else ""
        sys.exit(f"grainlab {sys.argv[1] if len(sys.argv) > 1 else ''}: error: {where}{e.strerror or e}")
