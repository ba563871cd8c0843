#!/usr/bin/env python3
"""Known-answer test of the study report's modulus-reduction fits (scripts/grainlab_plot.py): points on a prescribed
Hardin-Drnevich hyperbola E = E_max / (1 + eps/eps_r) and damping D = D_min + (D_max - D_min)(1 - E/E_max) must give
E_max, eps_r, D_min and D_max back; a misfit of +-x % on alternate points gives an rms misfit near x %; an E that
does not fall with strain, or one amplitude, gives no fit."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from grainlab_plot import damping_fit, hyperbolic_fit  # noqa: E402

fails = []


def check(what, got, want, rel):
    if not abs(got - want) <= rel * abs(want):
        fails.append(f"{what}: {got:.9g}, expected {want:.9g} (relative tolerance {rel:g})")


eps = np.array([1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 5e-3])
E_max, eps_r, D_min, D_max = 52e6, 2.5e-4, 0.02, 0.31
E = E_max / (1 + eps / eps_r)
D = D_min + (D_max - D_min) * (1 - E / E_max)
# exact data: the least squares reproduce it to round-off (1e-9: the normal equations of a 6 x 2 system)
e_max, e_r, rms = hyperbolic_fit(eps, E)
check("E_max", e_max, E_max, 1e-9)
check("eps_r", e_r, eps_r, 1e-9)
if rms > 1e-9:
    fails.append(f"rms misfit of exact data {rms:g}")
d0, d1 = damping_fit(E / e_max, D)
check("D_min", d0, D_min, 1e-9)
check("D_max", d1, D_max, 1e-9)
# +-3 % on alternate points: a weighted fit's rms relative misfit lies near 3 % (the fit absorbs a little of it)
noisy = E * (1 + 0.03 * np.array([1, -1, 1, -1, 1, -1]))
_, _, rms = hyperbolic_fit(eps, noisy)
if not 0.02 < rms <= 0.03:
    fails.append(f"rms misfit of +-3 % data: {rms:.4f}, expected in (0.02, 0.03]")
# two amplitudes: the hyperbola through both
e_max, e_r, rms = hyperbolic_fit(eps[[1, 4]], E[[1, 4]])
check("E_max from two amplitudes", e_max, E_max, 1e-9)
check("eps_r from two amplitudes", e_r, eps_r, 1e-9)
for what, x, y in (("E rising with strain", eps, E[::-1]), ("one amplitude", eps[:1], E[:1]),
                   ("one amplitude twice", eps[[2, 2]], E[[2, 2]])):
    if hyperbolic_fit(x, y) is not None:
        fails.append(f"{what}: a fit, expected none")
if damping_fit(np.ones(3), D[:3]) is not None:
    fails.append("damping of one E/E_max: a fit, expected none")
if fails:
    sys.exit("modulus_fit_check: " + "; ".join(fails))
print("modulus_fit_check: ok (E_max, eps_r, D_min, D_max back to 1e-9; +-3 % data rms in (2, 3] %)")
