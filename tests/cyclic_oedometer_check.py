#!/usr/bin/env python3
"""Known-answer test of the study report's cyclic oedometer rows (grainlab_plot.py cyclic_oedometer_rows,
cycle_increments, power_law_text) on synthetic runs whose cycles.csv is written by hand.
- Stress reversal, 20 cycles, sigma_v = 200 +- 40 kPa: the permanent strain eps_p = 0.1 N^0.4 % (a power law), so the
  fit's b is 0.400 ± 0.000; the increment per cycle over cycles 2-6 is (eps(6) - eps(1)) / 5 and over 16-20
  (eps(20) - eps(15)) / 5, worked out here from the power law, and the rate's decay exponent m over the doubling
  windows 2-4, 4-8, 8-16, 16-20 by a line fitted here; M_eq 20 -> 21.5 MPa, D_v 0.08 -> 0.02 (less the drag
  0.06 -> 0.015), K 0.75 -> 0.78; quarter 3.5 transits: "(dynamic)".
- A linear strain, eps_p = 0.05 + 0.01 (N - 1) %: the same increment 0.0100 early and late; 3 cycles: cycle 2's and 3's
  (k = 1, "(2) → ... (3)"); under 3 cycles the last one's ("(last)") and no power law ("–").
- Strain reversal (no sigma_v_amplitude in summary.json): sigma_v,0 from p'_0 and q_0 (p'_0 + 2 q_0 / 3 = 150 + 40 =
  190 kPa), the amplitude "eps_a ± 0.002", the strain columns "–".
- A cycles.csv row of the part of a cycle (complete 0) is left out, and a stage that is not a cyclic oedometer's
  (stage_type 4) gives no row.
- The strain per tenfold of cycles (log_law: c ln 10 of eps_p = a + c ln N from the second cycle), by a least-squares
  line here (the power law's 20 cycles), 0.05 ln 10 of a log law whose first cycle is off it, none under 4 cycles.
- The rate's decay exponent m (rate_decay: rate ~ N^-m over doubling windows) of laws whose m is known: a logarithmic
  law's 1, a power law's 1 - b, 1 - N^-0.5's 1.5, a constant rate's 0 (0.00, not -0.00); the windows' ends at 9, 10,
  18 and 20 cycles; "–" and why under 10 cycles and where a window's strain did not rise; a missing cycle ends them.
- Pooled over seeds (cyclic_oedometer_pooled): two tests that differ only in their seed, the strain of one twice the
  other's (a linear law over 10 cycles, 0.05 + 0.01 (N - 1) and twice that: m 0 for both): each measure's mean ± sd
  [t(1) sd / sqrt 2], worked out here; the log law's per-decade strain too; a third test at another mu_r and a strain-reversal test are no group's (a group needs two)."""
import csv
import json
import math
import os
import statistics
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import grainlab_plot as g  # noqa: E402
import numpy as np  # noqa: E402

work = sys.argv[1]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)

COLS = ["stage", "cycle", "step", "eps_a_max", "eps_v", "M_eq", "damping_v", "damping_v_less_drag", "K", "complete"]


def write_run(name, stage_type, cycles, summary):
    d = os.path.join(work, name)
    os.makedirs(d)
    with open(os.path.join(d, "series.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stage", "step", "eps_a", "eps_v", "p", "q", "u", "sigma_x", "sigma_y", "sigma_z", "stage_type", "cycle"])
        for k in range(5):
            w.writerow(["load", k, 0.001 * k, 0.001 * k, 150e3, 50e3, 0, 130e3, 130e3, 190e3, 5, 0])
        for k in range(5):
            w.writerow(["cyc", 5 + k, 0.001 * k, 0.001 * k, 150e3, 50e3, 0, 130e3, 130e3, 190e3, stage_type, k])
    with open(os.path.join(d, "cycles.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLS)
        for r in cycles:
            w.writerow([r.get(c, "cyc" if c == "stage" else 1) for c in COLS])
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump({"stages": [{"name": "load", "type": "triaxial"}, {"name": "cyc", "type": "cyclic", **summary}]}, f)
    return d


def rows_of(name, stage_type, cycles, summary):
    d = write_run(name, stage_type, cycles, summary)
    return g.cyclic_oedometer_rows({"name": name}, d, g.load(d))


def lin(a, b, n, k):  # a -> b linearly over cycles 1..n
    return a + (b - a) * (k - 1) / (n - 1)


fails = []


def expect(got, want, what):
    if got != want:
        fails.append(f"{what}:\n  got  {got!r}\n  want {want!r}")


# stress reversal, 20 cycles on a power law
n = 20
eps = [0.1 * N ** 0.4 for N in range(1, n + 1)]  # [%]
cyc = [dict(cycle=N, eps_v=eps[N - 1] / 100, M_eq=lin(20e6, 21.5e6, n, N), damping_v=lin(0.08, 0.02, n, N),
            damping_v_less_drag=lin(0.06, 0.015, n, N), K=lin(0.75, 0.78, n, N), eps_a_max=0.003) for N in range(1, n + 1)]
cyc.append(dict(cycle=21, eps_v=0.5, M_eq=1, damping_v=float("nan"), damping_v_less_drag=float("nan"), K=0.9,
                complete=0))  # the part of a cycle the stage ended in: not a row's
early, late = (eps[5] - eps[0]) / 5, (eps[19] - eps[14]) / 5
# the rate's decay exponent, worked out here: doubling windows 2-4, 4-8, 8-16 and 16-20 (the last, 4 cycles, not
# shorter than half the 8 before it), each window's rate at N_m = (b - a) / ln(b / a), ln rate on ln N_m
win = [(2, 4), (4, 8), (8, 16), (16, 20)]
m20 = -np.polyfit([math.log((b - a) / math.log(b / a)) for a, b in win],
                  [math.log((eps[b - 1] - eps[a - 1]) / (b - a)) for a, b in win], 1)[0]


def per_decade(eps):  # eps_p = a + c ln N over cycles 2..n by least squares: c ln 10 and its standard error
    x, y = np.log(np.arange(2, len(eps) + 1)), np.asarray(eps[1:])
    c, a = np.polyfit(x, y, 1)
    se = math.sqrt(np.sum((y - a - c * x) ** 2) / (len(x) - 2) / np.sum((x - x.mean()) ** 2))
    return c * math.log(10), se * math.log(10)


expect(rows_of("power", 6, cyc, {"sigma_v_amplitude": 40e3, "sigma_v_0": 200e3, "quarter_cycle_transits": 3.5}),
       [f"| power | cyc | 200.0 | 40.0 (0.20) | 20 | 0.100 | {eps[-1]:.3f} | {early:.4f} (2–6) → {late:.4f} (16–20) | "
        f"0.400 ± 0.000 | {m20:.2f} ± 0.00 (4 windows) | {'%.3f ± %.3f' % per_decade(eps)} | 20.0 → 21.5 | 0.080 → 0.020 | 0.060 → 0.015 | 0.750 → 0.780 | 3.50 (dynamic) |"],
       "stress reversal, 20 cycles")
# the increments and the power law alone
expect(g.cycle_increments([0.05 + 0.01 * k for k in range(20)]), "0.0100 (2–6) → 0.0100 (16–20)", "linear, 20 cycles")
expect(g.cycle_increments([0.05, 0.07, 0.08]), "0.0200 (2) → 0.0100 (3)", "3 cycles")
expect(g.cycle_increments([0.05, 0.07]), "0.0200 (last)", "2 cycles")
expect(g.power_law_text([1, 2], [0.05, 0.07]), "–", "power law of 2 cycles")
expect(g.power_law_text([1, 2, 3], [0.05, 0.0, 0.08]), "–", "power law through a strain of 0")
# the rate's decay exponent m (rate ~ N^-m) of laws whose m is known: the logarithmic law's 1 (exact at every window's
# N_m, the last window 128-200 too), a power law's 1 - b (exact over doubling windows: 128 cycles), a bounded strain's
# 1.5 (eps = 1 - N^-0.5: not a power law, but its differences over doubling windows scale as one: 128 cycles too), a
# constant rate's 0; src/rate_decay.hpp's C++ twin is checked on the same laws (test_cycle_loop RateDecay.*)
N200, N128 = np.arange(1, 201), np.arange(1, 129)
expect(g.rate_decay_text(N200, 0.1 + 0.05 * np.log(N200)), "1.00 ± 0.00 (7 windows)", "log law, 200 cycles")
expect(g.rate_decay_text(N128, 0.1 * N128 ** 0.3), "0.70 ± 0.00 (6 windows)", "power law b = 0.3, 128 cycles")
expect(g.rate_decay_text(N128, 1 - N128 ** -0.5), "1.50 ± 0.00 (6 windows)", "bounded strain, 128 cycles")
expect(g.rate_decay_text(N200, 0.01 * N200), "0.00 ± 0.00 (7 windows)", "constant rate, 200 cycles")
# the windows: where the last one ends, and which cycles they need
for n, want in ((9, [(2, 4), (4, 9)]), (10, [(2, 4), (4, 8), (8, 10)]), (18, [(2, 4), (4, 8), (8, 18)]),
                (20, [(2, 4), (4, 8), (8, 16), (16, 20)])):
    expect([(a, b) for a, b, _, _ in g.rate_windows(range(1, n + 1), np.arange(n) * 0.01)], want, f"windows of {n}")
expect(g.rate_decay_text(range(1, 10), np.arange(9) * 0.01), "– (under 10 cycles)", "9 cycles")
fall = 0.01 * np.arange(1, 21.0)
fall[15] = fall[7]  # the strain at cycle 16 back to cycle 8's: no rise over 8-16
expect(g.rate_decay_text(range(1, 21), fall), "– (no rise over cycles 8–16)", "a window the strain fell over")
expect([(a, b) for a, b, _, _ in g.rate_windows([1, 2, 3, 4, 5, 6, 7, 8, 10, 11], np.arange(10.0))], [(2, 4), (4, 8)],
       "a missing cycle ends the windows")
# the strain per tenfold of cycles: the log law's c ln 10 (0.05 ln 10 = 0.115), fitted from the second cycle (a first
# cycle off the law changes nothing); none under 4 cycles
log_eps = 0.1 + 0.05 * np.log(N200)
log_eps[0] = 5.0
expect(g.log_law_text(N200, log_eps), "0.115 ± 0.000", "log law per decade")
expect(g.log_law_text([1, 2, 3], [0.1, 0.2, 0.3]), "–", "log law of 3 cycles")
# strain reversal: sigma_v,0 from p'_0 and q_0, no strain columns
expect(rows_of("strain", 6, cyc[:3], {"p_0": 150e3, "q_0": 60e3, "quarter_cycle_transits": 6.2}),
       ["| strain | cyc | 190.0 | eps_a ± 0.003 | 3 | – | – | – | – | – | – | 20.0 → 20.2 | 0.080 → 0.074 | 0.060 → 0.055 | "
        "0.750 → 0.753 | 6.20 |"], "strain reversal")
# a drained triaxial cycle (stage_type 4): not a cyclic oedometer
expect(rows_of("triaxial", 4, cyc, {"q_amplitude": 40e3}), [], "a triaxial cycle")

# pooled over seeds
def linear_run(name, scale, A=40e3):
    cyc = [dict(cycle=N, eps_v=scale * (0.05 + 0.01 * (N - 1)) / 100, M_eq=20e6 * scale, damping_v=0.02 * scale,
                damping_v_less_drag=0.015 * scale, K=0.75 * scale, eps_a_max=0.003) for N in range(1, 11)]
    summary = {"sigma_v_amplitude": A, "sigma_v_0": 200e3} if A else {"p_0": 150e3, "q_0": 60e3}
    return write_run(name, 6, cyc, summary)


def spread(a, b, digits):
    m, sd = (a + b) / 2, statistics.stdev([a, b])
    return f"{m:.{digits}f} ± {sd:.{digits}f} [{12.706 * sd / 2 ** 0.5:.{digits}f}]"


tests = []
for name, seed, mu_r, scale, A in (("s1", 1, 0.0, 1.0, 40e3), ("s2", 2, 0.0, 2.0, 40e3), ("mu", 1, 0.3, 1.0, 40e3),
                                   ("strain1", 1, 0.0, 1.0, None), ("strain2", 2, 0.0, 1.0, None)):
    d = linear_run("pool_" + name, scale, A)
    tests.append(({"name": name, "seed": seed, "mu_r": mu_r, "dir": d, "sample": f"sample_{seed}"}, d, g.load(d)))
e1, e10 = 0.05, 0.05 + 0.09
b = g.power_law(range(1, 11), [0.05 + 0.01 * k for k in range(10)])[0]  # the same b for twice the strain
dec = per_decade([0.05 + 0.01 * k for k in range(10)])[0]  # and per tenfold N: twice for twice
expect(g.cyclic_oedometer_pooled(tests, lambda j: "v"),  # a linear law's m: 0 for both seeds
       [f"| v | 2 | cyc | 40.0 | 10 | {spread(e1, 2 * e1, 3)} | {spread(e10, 2 * e10, 3)} | {spread(0.01, 0.02, 4)} | "
        f"{spread(0.01, 0.02, 4)} | {b:.3f} ± 0.000 [0.000] | 0.00 ± 0.00 [0.00] | {spread(dec, 2 * dec, 3)} | "
        f"{spread(20, 40, 1)} | {spread(0.02, 0.04, 3)} | "
        f"{spread(0.015, 0.03, 3)} | {spread(0.75, 1.5, 3)} |"], "pooled over seeds")

if fails:
    sys.exit("cyclic_oedometer_check: " + "\n".join(fails))
print("cyclic_oedometer_check: ok")
