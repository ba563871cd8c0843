#!/usr/bin/env python3
"""Checks a smoke run's series.csv: the columns exist, consolidation reached p'_0 within 1 %, and the
undrained stage kept the box volume constant (eps_v at round-off: the lateral walls are placed exactly).
With the run's stdout (second argument): the shear's stage-end line gives the damping's drag as a share of the walls'
q and q/p' of the walls with and without it, from the stage's last row (series q, p, q_drag, p_drag), as printed."""
import csv, re, sys

rows = list(csv.DictReader(open(sys.argv[1])))
need = ["time", "step", "stage", "eps_a", "eps_v", "e", "p", "q", "u", "z", "ufr", "dt", "density_scaling", "p_drag",
        "q_drag"]
missing = [c for c in need if c not in rows[0]]
assert not missing, f"missing columns {missing}"
cons = [r for r in rows if r["stage"] == "consolidate"]
shear = [r for r in rows if r["stage"] == "shear"]
assert cons and shear, "both stages must write rows"
p_end = float(cons[-1]["p"])
assert abs(p_end - 190e3) < 0.01 * 190e3, f"consolidation ended at p = {p_end}"
ev = max(abs(float(r["eps_v"])) for r in shear)
assert ev < 1e-12, f"undrained volume changed: max |eps_v| = {ev}"
assert float(shear[-1]["eps_a"]) >= 0.01, "shear stopped early"
assert float(shear[-1]["density_scaling"]) == 1000.0
if len(sys.argv) > 2:
    out = open(sys.argv[2]).read()
    m = re.search(r"^stage shear: the damping's drag is (\S+) % of the walls' q at its end \(q/p' (\S+) of the walls, "
                  r"(\S+) less the drag;", out, re.M)
    assert m, f"no stage-end line on the damping's drag in {sys.argv[2]}:\n{out}"
    last = {k: float(shear[-1][k]) for k in ("q", "p", "q_drag", "p_drag")}
    want = (f"{100 * last['q_drag'] / last['q']:.1f}", f"{abs(last['q'] / last['p']):.3f}",
            f"{abs((last['q'] - last['q_drag']) / (last['p'] - last['p_drag'])):.3f}")
    assert m.groups() == want, f"the drag line says {m.groups()}, the last row {want}"
    assert last["q_drag"] != 0, "a damped shear with no drag"
    assert "stage consolidate: the damping's drag" not in out, "an isotropic stage has no drag line"
    print(f"drag line ok: {m.group(0)}")
print(f"smoke ok: {len(rows)} rows, p_end = {p_end:.1f} Pa, max |eps_v| = {ev:.2e}")
