#!/usr/bin/env python3
"""Checks a smoke run's series.csv: the columns exist, consolidation reached p'_0 within 1 %, and the
undrained stage kept the box volume constant (eps_v at round-off: the lateral walls are placed exactly)."""
import csv, sys

rows = list(csv.DictReader(open(sys.argv[1])))
need = ["time", "step", "stage", "eps_a", "eps_v", "e", "p", "q", "u", "z", "ufr", "dt", "density_scaling"]
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
print(f"smoke ok: {len(rows)} rows, p_end = {p_end:.1f} Pa, max |eps_v| = {ev:.2e}")
