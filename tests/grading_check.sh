#!/usr/bin/env bash
# Sample grading (StageResult::e_core, kGradedCore = 0.015): data/graded.yaml consolidated by its walls alone ends with
# a core (the central eighth of the box) looser than its interior by more than 0.015 and the run warns, naming
# `affine`; the same stage with `affine: true` ends within 0.015 and says nothing. Both summaries give e_inner and
# e_core (measured: +0.030 and +0.012; 10 000 and 20 000 spheres: +0.037, +0.042 against +0.005, -0.002).
set -u
bin=$1; cfg=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
sed 's/ufr_tolerance: 0.02}/ufr_tolerance: 0.02, affine: true}/' "$cfg" > "$work/affine.yaml"
grep -q "affine: true" "$work/affine.yaml" || { echo "could not make the affine config"; exit 1; }
"$bin" run "$cfg" --out "$work/walls" --quiet 2> "$work/walls.err" || { cat "$work/walls.err"; exit 1; }
"$bin" run "$work/affine.yaml" --out "$work/affine" --quiet 2> "$work/affine.err" || { cat "$work/affine.err"; exit 1; }
diff_of() {  # e_core - e_inner from a run's summary.json
  "${GRAINLAB_PYTHON:-/usr/bin/python3}" -c 'import json, sys; s = json.load(open(sys.argv[1]))["stages"][0]; print("%.4f" % (s["e_core"] - s["e_inner"]))' "$1/summary.json"
}
dw=$(diff_of "$work/walls") && da=$(diff_of "$work/affine") || { echo "summary.json lacks e_inner or e_core"; exit 1; }
echo "e_core - e_inner: walls $dw, affine $da"
awk -v w="$dw" -v a="$da" 'BEGIN { exit !(w > 0.015 && a < 0.015 && a > -0.015) }' || { echo "grading not as measured"; exit 1; }
grep -q "the sample is graded.*affine: true" "$work/walls.err" || { echo "no grading warning:"; cat "$work/walls.err"; exit 1; }
if grep -q "graded" "$work/affine.err"; then echo "warned of a homogeneous sample:"; cat "$work/affine.err"; exit 1; fi
echo "grading ok"
