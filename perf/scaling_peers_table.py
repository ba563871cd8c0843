#!/usr/bin/python3
"""The table of perf/scaling_peers.sh's runs (its scaling_peers.txt): per size and code the median time per
particle-step, each code's spread over the sizes (slowest / fastest median), and grainlab's speed-up over the
fastest peer at each size. Prints Markdown; perf/results.sh includes it in perf/RESULTS.md."""
import re
import statistics
import sys


def table(path):
    runs = {}  # (code, spec) -> rates
    n = {}
    codes = []
    for line in open(path):
        m = re.match(r"code=(\S+) spec=(\S+) particles=(\d+) particle_steps_per_s=(\S+)", line)
        if not m:
            continue
        code, spec = m.group(1), m.group(2)
        runs.setdefault((code, spec), []).append(float(m.group(4)))
        n[spec] = int(m.group(3))
        if code not in codes:
            codes.append(code)
    if not runs:
        return "(no runs in %s)\n" % path
    specs = sorted(n, key=n.get)
    peers = [c for c in codes if c != "grainlab"]
    med = {k: statistics.median(v) for k, v in runs.items()}
    head = "| scene | particles | " + " | ".join(f"{c} ns / particle-step (runs)" for c in codes)
    head += " | grainlab / fastest peer |" if peers and "grainlab" in codes else " |"
    rows = [head, "|" + "---|" * (head.count("|") - 1)]
    for s in specs:
        cells = []
        for c in codes:
            r = med.get((c, s))
            cells.append(f"{1e9 / r:.0f} ({len(runs[(c, s)])})" if r else "-")
        row = f"| `{s.replace('_', ' ')}` | {n[s]} | " + " | ".join(cells) + " |"
        if peers and "grainlab" in codes:
            pr = [med[(p, s)] for p in peers if (p, s) in med]
            g = med.get(("grainlab", s))
            row += f" {g / max(pr):.2f} |" if pr and g else " - |"
        rows.append(row)
    spread = []
    for c in codes:
        v = [med[(c, s)] for s in specs if (c, s) in med]
        spread.append(f"{c} **{max(v) / min(v):.2f}**")
    rows.append("")
    rows.append("Spread over these sizes (slowest median / fastest median): " + ", ".join(spread) + ".")
    return "\n".join(rows) + "\n"


if __name__ == "__main__":
    sys.stdout.write(table(sys.argv[1] if len(sys.argv) > 1 else "perf/race-out/scaling_peers.txt"))
