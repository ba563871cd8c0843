#!/usr/bin/env python3
"""Summarise an Nsight Compute CSV (`ncu --metrics gpu__time_duration.sum --csv --print-units base`) by kernel.

usage: kernels.py NCU_CSV STEPS

Kokkos kernels carry the lambda's type in their name, which names the grainlab function that launched it;
that function and the pattern (ParallelFor / ParallelReduce, RangePolicy / TeamPolicy) name a row here. The
kernels launched about STEPS times or more (STEPS = warm-up + timed steps) are the step's; their mean durations
times round(launches / STEPS) add up to the GPU's busy time per
step, which perf/gpu/device.sh's `profile` prints next to the step's wall time.
"""
import csv
import re
import sys
from collections import OrderedDict


def short(name):
    pattern = re.search(r"Parallel(For|Reduce|Scan)", name)
    policy = re.search(r"(RangePolicy|TeamPolicy|MDRangePolicy)", name)
    # The first grainlab function or functor named after the pattern: the launching function of a lambda
    # (e.g. grainlab::<unnamed>::pair_forces_pairs_impl<1, 1>) or a named functor (DeterministicSum::ChunkSums).
    tail = name[pattern.end():] if pattern else name
    m = re.search(r"(?:grainlab::|DeterministicSum::|Engine::)(?:<unnamed>::|\(anonymous namespace\)::)?"
                  r"(?!View\b)([A-Za-z_]\w*(?:<[^<>()]*>)?)", tail)
    where = m.group(1) if m else re.sub(r"\s+", " ", name)[:60]
    return f"{where} [{pattern.group(0) if pattern else '?'}, {policy.group(1) if policy else '?'}]"


def main():
    path, steps = sys.argv[1], int(sys.argv[2])
    rows = OrderedDict()
    with open(path, newline="") as fh:
        lines = [ln for ln in fh if ln.startswith('"')]  # ncu prints its own progress lines before the CSV
    for rec in csv.DictReader(lines):
        if rec.get("Metric Name") != "gpu__time_duration.sum":
            continue
        key = short(rec["Kernel Name"])
        ns = float(rec["Metric Value"].replace(",", ""))
        n, tot = rows.get(key, (0, 0.0))
        rows[key] = (n + 1, tot + ns)
    busy = 0.0
    print(f"{'kernel':70s} {'launches':>8s} {'mean_us':>9s}")
    for key, (n, tot) in sorted(rows.items(), key=lambda kv: -kv[1][1]):
        print(f"{key[:70]:70s} {n:8d} {tot / n / 1e3:9.2f}")
        per_step = round(n / steps)
        busy += tot / n * per_step / 1e3
    print(f"gpu_busy_us_per_step={busy:.1f} (mean duration x round(launches / {steps}))")


if __name__ == "__main__":
    main()
