#!/usr/bin/env python3
"""GPU section of perf/RESULTS.md from a device run's bench.txt (perf/gpu/device.sh bench).

    perf/gpu/results.py perf/gpu/runs/<run>/bench.txt > perf/gpu/RESULTS_GPU.md

Medians over the repetitions of each (size, rolling, list) row. Bytes per particle-step is the step's
compulsory traffic model (perf/traffic.hpp); achieved = bytes x rate; the floor is the rate at which that
traffic would move at the measured deep-copy bandwidth (cudaMemcpy device to device, same process family,
same run)."""
import os, re, statistics, sys

path = sys.argv[1]
run_dir = os.path.dirname(path)
text = open(path).read()
copy = re.search(r"copy_kernel_bytes_per_s=(\S+) deep_copy_bytes_per_s=(\S+) backend=(\S+)", text)
kernel_bw, deep_bw, backend = float(copy.group(1)), float(copy.group(2)), copy.group(3)
device = open(os.path.join(run_dir, "device.txt")).read().splitlines()
gpu = device[1].split(",")[0] if len(device) > 1 else "?"
rows = {}
for line in text.splitlines():
    m = re.match(r"tile=(\d+) particle_steps_per_s=(\S+) .*particles=(\d+) .*rolling=(\d) .*Z=(\S+) .*kinetic_J=(\S+) "
                 r".*listed_pairs=(\d+) verlet_pairs=(\d+) inner_skin=(\S+) .*bytes_per_particle_step=(\d+)", line)
    if not m:
        continue
    tile, rate, n, rolling, z, ke, listed, verlet, inner, bpps = m.groups()
    key = (int(n), int(rolling), float(inner))
    r = rows.setdefault(key, {"rates": [], "ke": set(), "z": z, "bpps": int(bpps), "listed": int(listed)})
    r["rates"].append(float(rate))
    r["ke"].add(ke)

commit_file = os.path.join(run_dir, "commit.txt")
commit = open(commit_file).read().strip() if os.path.exists(commit_file) else "?"
print(f"## GPU: {gpu} ({backend} backend), binaries built at commit `{commit}`\n")
print(f"Raw output: `{path}` (with the device's `nvidia-smi` line in `device.txt`). Reproduce on a machine with")
print("a CUDA GPU: `make gpu && perf/gpu/pack.sh && perf/gpu/device.sh bench 3` (on the lent-GPU tool: carry")
print("`.gpucarry`), then `perf/gpu/results.py <run>/bench.txt > perf/gpu/RESULTS_GPU.md`. Build: `make gpu`")
print("(Kokkos 3.4.01 CUDA, sm_80 PTX + sm_90 machine code, `--fmad=false`), double precision throughout.\n")
print(f"Copy bandwidth in the same run (2 x 256 MB, read + write, median of 20): `Kokkos::deep_copy` "
      f"{deep_bw / 1e12:.2f} TB/s, a one-element-per-thread copy kernel {kernel_bw / 1e12:.2f} TB/s.\n")
print("Scene: the race scene (32 000 spheres) tiled K^3 (`race_bench --tile K`), the race's work otherwise (walls")
print("closing at 0.01 m/s each, dt = 1e-7 s, 200 warm-up + 2 000 timed steps, fenced), the engine's default lists")
print("(inner list 0.1 of the skin) unless the list column says Verlet. Medians of "
      f"{min(len(r['rates']) for r in rows.values())} runs.\n")
print("| particles | rolling | list | particle-steps/s (median) | ns per particle-step | B / particle-step "
      "(model) | achieved GB/s | floor at deep-copy bandwidth | of floor | kinetic energy equal in every run |")
print("|---|---|---|---|---|---|---|---|---|---|")
for (n, rolling, inner), r in sorted(rows.items(), key=lambda kv: (kv[0][0], -kv[0][1], -kv[0][2])):
    rate = statistics.median(r["rates"])
    bw = rate * r["bpps"]
    floor = deep_bw / r["bpps"]
    print(f"| {n:,} | {'on' if rolling else 'off'} | {'inner' if inner > 0 else 'Verlet'} | {rate:.3g} | "
          f"{1e9 / rate:.2f} | {r['bpps']} | {bw / 1e9:.0f} | {floor:.3g} | {rate / floor:.0%} | "
          f"{'yes' if len(r['ke']) == 1 else 'NO'} |")
print()
notes = os.path.join(run_dir, "NOTES.md")  # the run's hand-written part: tests, UR1, what the numbers mean
if os.path.exists(notes):
    print(open(notes).read().rstrip())
    print()
