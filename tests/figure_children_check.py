#!/usr/bin/env python3
"""The figures of `grainlab plot`, `csl` and the study report are written by forked children (grainlab_plot.save with
FIGURES_IN_CHILDREN, as the command sets it): the same PNG as a figure written in the process itself; an error of a
child comes back to the parent when it waits (figures_done): an OSError as raised (the one-line message naming the
file), anything else as a RuntimeError carrying the child's traceback; every child is waited for, none left running
or unreaped, no temporary file left; no line the parent printed before a fork is printed twice."""
import os
import subprocess
import sys

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


if g._figure_slots() != 1:
    fails.append("a module importing grainlab_plot must get its figures written in turn")
g.FIGURES_IN_CHILDREN = True
if len(os.sched_getaffinity(0)) > 1 and g._figure_slots() < 2:
    fails.append("the command's figures are not written by children on a machine with several cores")
# Where the machine lends one core only, the test still runs every figure through a child (two slots).
g._figure_slots = lambda: 2

# 1. The same bytes as written in the process itself; several children at once (more figures than slots).
g.FIGURES_IN_CHILDREN = False
g.save(figure("a"), work, "inline")
g.FIGURES_IN_CHILDREN = True
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
code = ("import sys; sys.path.insert(0, %r); import grainlab_plot as g; g.FIGURES_IN_CHILDREN = True; "
        "g._figure_slots = lambda: 2; print('before the figures'); fig = g.plt.figure(); "
        "g.save(fig, %r, 'one'); g.save(g.plt.figure(), %r, 'two'); g.figures_done()") % (
            os.path.dirname(g.__file__), work, work)
with open(os.path.join(work, "stdout.txt"), "w") as f:
    rc = subprocess.run([sys.executable, "-c", code], stdout=f).returncode
lines = open(os.path.join(work, "stdout.txt")).read().splitlines()
if rc != 0 or lines.count("before the figures") != 1 or len(lines) != 3:
    fails.append(f"the command printed (exit {rc}): {lines}")

if fails:
    sys.exit("figure_children_check:\n  " + "\n  ".join(fails))
print("figure children ok")
