#!/usr/bin/env python3
"""The figures of `grainlab plot`, `csl` and the study report are written by forked children (grainlab_plot.save with
FIGURE_JOBS > 1, as the command sets it from GRAINLAB_FIGURE_JOBS; without it they are written in turn; a bad value is
one error line naming the variable): the same PNG as a figure written in the process itself; an error of a
child comes back to the parent when it waits (figures_done): an OSError as raised (the one-line message naming the
file), anything else as a RuntimeError carrying the child's traceback; every child is waited for, none left running
or unreaped, no temporary file left; no line the parent printed before a fork is printed twice; a child whose command is
killed ends at once, writing nothing. The files of a figure: PNG and PDF, or GRAINLAB_FIGURE_FORMATS's list (a bad one
is one error line naming the variable)."""
import os
import shutil
import signal
import subprocess
import sys
import time

work = sys.argv[1]
os.makedirs(work, exist_ok=True)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import grainlab_plot as g  # noqa: E402

plt = g.plt
fails = []


def figure(title):
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1, 2], [1, 0, 2], label=title)
    ax.set(title=title)
    return fig


class Broken(g.matplotlib.artist.Artist):
    """An artist whose drawing fails: the child's error that is not a file system's."""

    def draw(self, renderer):
        raise ValueError("this artist cannot be drawn")


def ended(pid):
    """Whether pid has exited: gone, or a zombie. The killed command's child is reaped by PID 1, whenever that gets to
    it (a container's init may take seconds on a loaded machine); its exit is what is tested, not the reaping."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] in "ZX"
    except (FileNotFoundError, ProcessLookupError):
        return True


def within(seconds, done):
    """Whether done() holds within seconds of wall time (polled; a loaded machine's sleeps overrun)."""
    end = time.monotonic() + seconds
    while not done():
        if time.monotonic() > end:
            return False
        time.sleep(0.05)
    return True


if g.FIGURE_JOBS != 1:
    fails.append("a module importing grainlab_plot must get its figures written in turn")
os.environ.pop("GRAINLAB_FIGURE_JOBS", None)
if g.figure_jobs("plot") != 1:
    fails.append("without GRAINLAB_FIGURE_JOBS the command does not write its figures in turn")
os.environ["GRAINLAB_FIGURE_JOBS"] = "3"
if g.figure_jobs("plot") != 3:
    fails.append("GRAINLAB_FIGURE_JOBS=3 not taken")
for bad in ("0", "two", "-1", "1.5"):
    os.environ["GRAINLAB_FIGURE_JOBS"] = bad
    out = subprocess.run([sys.executable, g.__file__, "plot", work], capture_output=True, text=True)
    want = f"grainlab plot: error: GRAINLAB_FIGURE_JOBS = '{bad}': the figures written at once, a whole number >= 1"
    if out.returncode != 1 or not out.stderr.startswith(want) or out.stderr.count("\n") != 1:
        fails.append(f"GRAINLAB_FIGURE_JOBS={bad}: exit {out.returncode}, {out.stderr!r}")
del os.environ["GRAINLAB_FIGURE_JOBS"]
# The files of a figure: PNG and PDF without GRAINLAB_FIGURE_FORMATS, its list otherwise (the first format's path is the
# one printed), nothing else; a bad list is one error line naming the variable.
os.environ.pop("GRAINLAB_FIGURE_FORMATS", None)
if g.FIGURE_FORMATS != ("png", "pdf") or g.figure_formats("plot") != ("png", "pdf"):
    fails.append("without GRAINLAB_FIGURE_FORMATS the figures are not PNG and PDF")
os.environ["GRAINLAB_FIGURE_FORMATS"] = " SVG,pdf "
if g.figure_formats("plot") != ("svg", "pdf"):
    fails.append(f"GRAINLAB_FIGURE_FORMATS=' SVG,pdf ' read as {g.figure_formats('plot')}")
for bad in ("jpg", "png,png", "png,", ",", "png pdf"):
    os.environ["GRAINLAB_FIGURE_FORMATS"] = bad
    out = subprocess.run([sys.executable, g.__file__, "csl", work], capture_output=True, text=True)
    want = (f"grainlab csl: error: GRAINLAB_FIGURE_FORMATS = '{bad}': the figures' file formats, "
            "a comma-separated list of png, pdf, svg, each once")
    if out.returncode != 1 or not out.stderr.startswith(want) or out.stderr.count("\n") != 1:
        fails.append(f"GRAINLAB_FIGURE_FORMATS={bad}: exit {out.returncode}, {out.stderr!r}")
del os.environ["GRAINLAB_FIGURE_FORMATS"]
magic = {"png": b"\x89PNG", "pdf": b"%PDF", "svg": b"<?xml"}
for fmts in (("png", "pdf"), ("svg",), ("pdf", "png")):
    d = os.path.join(work, "formats_" + "_".join(fmts))
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    g.FIGURE_FORMATS = fmts
    g.save(figure("f"), d, "fig")
    if sorted(os.listdir(d)) != sorted(f"fig.{f}" for f in fmts) or \
            any(not open(os.path.join(d, f"fig.{f}"), "rb").read().startswith(magic[f]) for f in fmts):
        fails.append(f"formats {fmts}: wrote {sorted(os.listdir(d))}")
g.FIGURE_FORMATS = ("png", "pdf")
# Whatever the machine lends, the test runs every figure through a child, two at a time.

# 1. The same bytes as written in the process itself; several children at once (more figures than slots).
g.save(figure("a"), work, "inline")
g.FIGURE_JOBS = 2
for k in range(5):
    g.save(figure("a"), work, f"child{k}")
if len(g._FIGURE_CHILDREN) > 2:
    fails.append(f"{len(g._FIGURE_CHILDREN)} children at once, above the 2 slots")
g.figures_done()
if g._FIGURE_CHILDREN:
    fails.append("figures_done left children")
want = open(os.path.join(work, "inline.png"), "rb").read()
for k in range(5):
    if open(os.path.join(work, f"child{k}.png"), "rb").read() != want:
        fails.append(f"child{k}.png differs from the figure written in the process")

# 2. An OSError in a child (a directory that is not there): raised by figures_done as the child raised it.
g.save(figure("b"), os.path.join(work, "missing"), "nowhere")
g.save(figure("c"), work, "after")  # a figure after the failing one is still written, and waited for
try:
    g.figures_done()
    fails.append("a child's OSError was not raised in the parent")
except OSError as e:
    if e.filename != os.path.join(work, "missing", "nowhere.png") or not e.strerror:
        fails.append(f"the child's OSError came back as {e!r} (filename {e.filename})")
if g._FIGURE_CHILDREN or not os.path.isfile(os.path.join(work, "after.png")):
    fails.append("figures_done raised before every child had ended")

# 3. Any other error: a RuntimeError naming the figure, with the child's traceback.
fig = figure("d")
fig.axes[0].add_artist(Broken())
g.save(fig, work, "broken")
try:
    g.figures_done()
    fails.append("a child's failed drawing was not raised in the parent")
except RuntimeError as e:
    if "broken.png failed" not in str(e) or "this artist cannot be drawn" not in str(e):
        fails.append(f"the child's error came back as {e!r}")
left = [f for f in os.listdir(work) if ".tmp." in f]
if left:
    fails.append(f"temporary files left: {left}")
try:
    os.waitpid(-1, os.WNOHANG)
    fails.append("a child left unreaped")
except ChildProcessError:
    pass

# 4. The command: a line printed before the forks once in its output (stdout a file: block-buffered).
code = ("import sys; sys.path.insert(0, %r); import grainlab_plot as g; g.FIGURE_JOBS = 2; "
        "print('before the figures'); fig = g.plt.figure(); "
        "g.save(fig, %r, 'one'); g.save(g.plt.figure(), %r, 'two'); g.figures_done()") % (
            os.path.dirname(g.__file__), work, work)
with open(os.path.join(work, "stdout.txt"), "w") as f:
    rc = subprocess.run([sys.executable, "-c", code], stdout=f).returncode
lines = open(os.path.join(work, "stdout.txt")).read().splitlines()
if rc != 0 or lines.count("before the figures") != 1 or len(lines) != 3:
    fails.append(f"the command printed (exit {rc}): {lines}")

# 5. The command killed (SIGKILL: no cleanup of its own) while a child writes its figure's temporary file (slowly):
# the child ends within seconds (a SIGTERM at its parent's death), removes the temporary file, writes no figure and
# runs none of the command's code (nothing on stderr: it once went on with the parent's program). The stand-in writer
# sleeps 30 s in 0.1 s slices, as a figure's writer returns to the interpreter continually (CPython runs a Python
# signal handler between bytecodes).
slow = os.path.join(work, "slow")
shutil.rmtree(slow, ignore_errors=True)  # an earlier failed run's leftovers would pass for this child's file
os.makedirs(slow)
code = ("import sys, os, time; sys.path.insert(0, %r); import grainlab_plot as g; g.FIGURE_JOBS = 2\n"
        "def slow(tmp):\n"
        "    open(tmp, 'w').write('half a figure')\n"
        "    for _ in range(300):\n"
        "        time.sleep(0.1)\n"
        "g._write_figure = lambda fig, out, name: g.write_atomically(os.path.join(out, name + '.png'), slow)\n"
        "g.save(g.plt.figure(), %r, 'slow')\n"
        "print(g._FIGURE_CHILDREN[0][0], flush=True); time.sleep(60)\n") % (os.path.dirname(g.__file__), slow)
cmd = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
cmd.stdout.readline()  # save's line naming the figure
child = int(cmd.stdout.readline())
# The child in its writing: without its temporary file the kill below would not test the cleanup. It opens the file
# at once; 20 s leaves a loaded machine room.
if not within(20, lambda: os.listdir(slow)):
    fails.append("the slow figure's child wrote no temporary file within 20 s")
cmd.kill()
cmd.wait()
# Left alone the child sleeps 30 s: an end within 10 s is the SIGTERM of its parent's death (PR_SET_PDEATHSIG), with
# room for a loaded machine (the bound was 2 s, and a full `make test` once overran it).
if not within(10, lambda: ended(child)):
    os.kill(child, signal.SIGKILL)
    fails.append("a figure's child outlived its killed command by 10 s")
if os.listdir(slow):
    fails.append(f"the killed command's child left {os.listdir(slow)}")
err = cmd.stderr.read()
if err:
    fails.append(f"the killed command's child wrote to stderr: {err}")

if fails:
    sys.exit("figure_children_check:\n  " + "\n  ".join(fails))
print("figure children ok")
