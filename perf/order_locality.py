#!/usr/bin/python3
"""How far apart in memory a sphere's neighbours lie, for three particle orders (perf/NOTES.md attempt 47).

For each listed pair (i, j) (centre distance < r_i + r_j + skin) the index distance |i - j| after sorting the
spheres by: cells in z, y, x order (our generated packings), Morton order (perf/scene.hpp, the race's order) and
a Hilbert curve (Skilling 2004, "Programming the Hilbert curve"), all on cubic cells of edge 2 r_mean. Prints
the median and the share of pairs farther apart than 1k, 4k, 16k and 64k particles: a j beyond the window of
particles whose state is still in a cache is a miss the kernel waits for.

Usage: perf/order_locality.py SCENE [skin_m]. SCENE is a scene in the shared `x y z r` format (e.g. one written by
build/perf/race_bench --tile 2 --write-scene PREFIX), or a grainlab state file (a run's sample_<stage>.h5 or
checkpoints/ckpt_<step>.h5, read with python3-h5py). For a state file an "as stored" row gives the run's own
order at that instant (perf/NOTES.md session 19: how the order decays under shear). Needs python3-numpy and
python3-scipy (Debian)."""
import sys

try:
    import numpy as np
    from scipy.spatial import cKDTree
except ImportError:
    sys.exit("order_locality.py: needs numpy and scipy (Debian: apt-get install python3-numpy python3-scipy)")


def spread_bits(v):
    """Bits of a 21-bit integer spaced three apart (as spatial_order in src/packing.cpp)."""
    v = v & 0x1FFFFF
    v = (v | v << 32) & 0x1F00000000FFFF
    v = (v | v << 16) & 0x1F0000FF0000FF
    v = (v | v << 8) & 0x100F00F00F00F00F
    v = (v | v << 4) & 0x10C30C30C30C30C3
    v = (v | v << 2) & 0x1249249249249249
    return v


def hilbert_key(c, bits):
    """Skilling's transform of the cell coordinates to the Hilbert index's transposed form, then interleaved."""
    X = c.T.astype(np.int64).copy()
    n = 3
    Q = 1 << (bits - 1)
    while Q > 1:  # inverse undo excess work
        P = Q - 1
        for i in range(n):
            hit = (X[i] & Q) != 0
            X[0] = np.where(hit, X[0] ^ P, X[0])
            t = np.where(hit, 0, (X[0] ^ X[i]) & P)
            X[0] ^= t
            X[i] ^= t
        Q >>= 1
    for i in range(1, n):  # Gray encode
        X[i] ^= X[i - 1]
    t = np.zeros_like(X[0])
    Q = 1 << (bits - 1)
    while Q > 1:
        t = np.where((X[n - 1] & Q) != 0, t ^ (Q - 1), t)
        Q >>= 1
    for i in range(n):
        X[i] ^= t
    key = np.zeros(X.shape[1], dtype=np.int64)
    for b in range(bits - 1, -1, -1):
        for i in range(n):
            key = (key << 1) | ((X[i] >> b) & 1)
    return key


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    skin = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-4
    keys = {}
    if sys.argv[1].endswith(".h5"):
        try:
            import h5py
        except ImportError:
            sys.exit("order_locality.py: a state file needs h5py (Debian: apt-get install python3-h5py)")
        with h5py.File(sys.argv[1], "r") as f:
            x, r = f["state/x"][:], f["state/r"][:]
        keys["as stored"] = np.arange(len(x))
    else:
        d = np.loadtxt(sys.argv[1], ndmin=2)
        x, r = d[:, :3], d[:, 3]
    c = ((x - x.min(0)) / (2 * r.mean())).astype(np.int64)
    keys |= {
        "cells z,y,x": (c[:, 2] * (c[:, 1].max() + 1) + c[:, 1]) * (c[:, 0].max() + 1) + c[:, 0],
        "Morton": spread_bits(c[:, 0]) | spread_bits(c[:, 1]) << 1 | spread_bits(c[:, 2]) << 2,
        "Hilbert": hilbert_key(c, max(1, int(c.max()).bit_length())),
    }
    pairs = cKDTree(x).query_pairs(2 * r.max() + skin, output_type="ndarray")
    dist = np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1)
    pairs = pairs[dist < r[pairs[:, 0]] + r[pairs[:, 1]] + skin]
    print(f"{len(x)} spheres, {len(pairs)} pairs within r_i + r_j + {skin:g} m")
    print("| order | median abs(i - j) | > 1k | > 4k | > 16k | > 64k |")
    print("|---|---|---|---|---|---|")
    for name, key in keys.items():
        order = np.argsort(key, kind="stable")
        rank = np.empty_like(order)
        rank[order] = np.arange(len(order))
        gap = np.abs(rank[pairs[:, 0]] - rank[pairs[:, 1]])
        shares = " | ".join(f"{(gap > w).mean():.4f}" for w in (1000, 4000, 16000, 64000))
        print(f"| {name} | {int(np.median(gap))} | {shares} |")


if __name__ == "__main__":
    main()
