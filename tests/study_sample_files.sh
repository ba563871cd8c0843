#!/usr/bin/env bash
# A study over sample files (axes.sample_file: named files, each a sample job of its own that consolidates it at the
# job's p0 and mu_r, in place of the base's sample): one study compares packings prepared apart (here the smoke run's
# sample and the same spheres spread apart by 5 % about the box's centre, imported with `grainlab import`). Checks:
# validate names each file and counts its spheres; the sample jobs are named _f<name>_n<count> and their configs hold
# sample: {file: <absolute path>} alone (the base's drawn sample replaced); the shears run on their own file's sample;
# study.json names each job's file; the report has one section per file holding that file's tests only, and a table
# across the files whose e_0 is each sample job's own (summary.json) and whose end states are the ones each file's
# section measures; a preparation study over the files keeps them apart (no seeds pooled); an extra job picks a file by
# name; a file replaced after its jobs ran is refused; and the axis's refusals name the key and the file.
set -u
bin=$1; smoke=$2; work=$3; here=$(cd "$(dirname "$0")" && pwd)
py=${GRAINLAB_PYTHON:-/usr/bin/python3}
fail() { echo "study_sample_files: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
[ -f "$smoke/sample_consolidate.h5" ] || fail "no smoke sample at $smoke"
mkdir packings && cp "$smoke/sample_consolidate.h5" packings/a.h5 || exit 1
# b: a's spheres and box spread apart by 5 % about the box's centre (no contact left: a looser start)
"$bin" export packings/a.h5 --out a.txt > /dev/null || fail "export"
read -r x0 x1 y0 y1 z0 z1 < a_box.txt
awk -v x0="$x0" -v x1="$x1" -v y0="$y0" -v y1="$y1" -v z0="$z0" -v z1="$z1" 'BEGIN {
  cx = (x0 + x1) / 2; cy = (y0 + y1) / 2; cz = (z0 + z1) / 2
  printf "%.17g %.17g %.17g %.17g %.17g %.17g\n", cx + 1.05 * (x0 - cx), cx + 1.05 * (x1 - cx), cy + 1.05 * (y0 - cy),
         cy + 1.05 * (y1 - cy), cz + 1.05 * (z0 - cz), cz + 1.05 * (z1 - cz) > "b_box.txt" }
  /^[^#]/ { printf "%.17g %.17g %.17g %s\n", cx + 1.05 * ($1 - cx), cy + 1.05 * ($2 - cy), cz + 1.05 * ($3 - cz), $4 }' a.txt > b.txt
"$bin" import b.txt --box b_box.txt --out packings/b.h5 > import.log || fail "import: $(cat import.log)"
grep -q "imported 300 spheres" import.log || fail "import: $(cat import.log)"
# the base draws its own sample (200 spheres), which the axis replaces
cat > base.yaml <<'YAML'
sample: {count: 200, seed: 3}
material: {mu: 0.5}
numerics: {damping: 0.2}
stages:
  - {name: again, type: isotropic, pressure: 190e3, max_steps: 40000, ufr_tolerance: 0.02}
  - {name: shear, type: triaxial, axial_strain_rate: 1.0, max_axial_strain: 0.02}
output: {every: 200}
YAML
cat > study.yaml <<'YAML'
base: base.yaml
axes:
  drainage: [drained, undrained]
  sample_file: {a: packings/a.h5, b: packings/b.h5}
critical_state: {window: 0.01}
YAML
plan=$("$bin" validate study.yaml 2>&1) || fail "validate failed: $plan"
printf '%s\n' "$plan" | grep -q "study: 2 samples, 4 shear tests" || fail "validate: $plan"
# each file's e in its walls: b's as its import printed it, a's from the smoke run's sample file (python, h5py)
e_b=$(sed -n 's/.*void ratio e \([0-9.]*\)$/\1/p' import.log)
e_a=$("$py" - packings/a.h5 <<'PY'
import sys
import h5py
import numpy as np
with h5py.File(sys.argv[1], "r") as f:
    off, r = f["/state/walls"][()].reshape(8, -1)[:6, 3], f["/state/r"][()]  # walls 2a at lo (offset lo), 2a+1 at -hi
V = np.prod([-off[2 * a + 1] - off[2 * a] for a in range(3)])
print(f"{V / (4 / 3 * np.pi * (r ** 3).sum()) - 1:.4g}")
PY
)
[ -n "$e_a" ] && [ -n "$e_b" ] || fail "the files' e: a '$e_a', b '$e_b'"
printf '%s\n' "$plan" | grep -qF "sample files: 2, each consolidated again by its sample jobs in place of the base's sample (a: 300 spheres, e $e_a, $PWD/packings/a.h5; b: 300 spheres, e $e_b, $PWD/packings/b.h5)" ||
  fail "validate does not name the files with their e (a $e_a, b $e_b): $plan"
out=$("$bin" study study.yaml --out st --jobs 2 --threads 1 2>&1) || fail "the study failed: $out"
for f in a b; do
  job=st/jobs/sample_mur0_ebase_pbase_f${f}_n300
  [ -f "$job/done" ] || fail "no finished sample job $job: $(ls st/jobs)"
  sample=$("$py" -c "import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))['sample'])" "$job/job.yaml")
  [ "$sample" = "{'file': '$PWD/packings/$f.h5'}" ] || fail "$job's sample block: $sample"
  for d in drained undrained; do
    sh=st/jobs/shear_${d}_mur0_ebase_pbase_f${f}_n300
    [ -f "$sh/done" ] || fail "no finished shear $sh: $(ls st/jobs)"
    sample=$("$py" -c "import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))['sample'])" "$sh/job.yaml")
    [ "$sample" = "{'file': '../sample_mur0_ebase_pbase_f${f}_n300/run/sample_again.h5'}" ] || fail "$sh's sample block: $sample"
  done
done
[ "$(ls st/jobs | wc -l)" -eq 6 ] || fail "expected 6 jobs: $(ls st/jobs)"
"$py" - st <<'PY' || fail "the report"
import csv, json, os, re, sys
out = sys.argv[1]
idx = json.load(open(os.path.join(out, "study.json")))
for j in idx["jobs"] + idx["samples"]:
    f = re.search(r"_f([ab])_n300$", j["name"]).group(1)
    assert j["specimen"] == f and j["specimen_file"] == os.path.abspath(f"packings/{f}.h5"), j
    assert j["count"] == 300, j
text = open(os.path.join(out, "report.md")).read()
assert "4 shear tests on 2 sample file(s): a (a.h5, 300 spheres), b (b.h5, 300 spheres)." in text, text[:600]
# each file's section: its own tests, none of the other's
parts = re.split(r"^## ", text, flags=re.M)
sec = {p[len("Sample file ") ]: p for p in parts if p.startswith("Sample file ")}
assert sorted(sec) == ["a", "b"], [p[:40] for p in parts]
for f, p in sec.items():
    other = "b" if f == "a" else "a"
    assert p.startswith(f"Sample file {f}: {os.path.abspath('packings/' + f + '.h5')}\n"), p[:100]
    assert f"_f{f}_n300" in p and f"_f{other}_n300" not in p, f
    assert os.path.isfile(os.path.join(out, "figures", f"f_{f}", "stress_paths.png")), f
assert os.path.isfile(os.path.join(out, "figures", "files_e_p.png"))
assert os.path.isfile(os.path.join(out, "figures", "grading.png"))
# the table across the files: e_0 is the sample job's consolidated e (its summary.json), the end state the means of
# the walls' p' and of e over the shear's last 0.01 of axial strain (the study's window), from its series.csv
across = [p for p in parts if p.startswith("Across the sample files")]
assert len(across) == 1, "no table across the files"
rows = [r.split(" | ") for r in across[0].splitlines() if r.startswith("| a |") or r.startswith("| b |")]
assert len(rows) == 4, across[0]
for r in rows:
    f, e0, e0_in, name, p_end, e_end = r[0][2:], r[1], r[2], r[3], r[5], r[6]
    summ = json.load(open(os.path.join(out, "jobs", f"sample_mur0_ebase_pbase_f{f}_n300", "run", "summary.json")))
    iso = [s for s in summ["stages"] if s["type"] == "isotropic"][-1]
    assert e0 == f"{iso['e']:.4f}" and e0_in == f"{iso['e_inner']:.4f}", (r, iso["e"], iso["e_inner"])
    with open(os.path.join(out, "jobs", name, "run", "series.csv")) as fh:
        shear = [x for x in csv.DictReader(fh) if 0 < int(x["stage_type"]) < 3]
    last = [x for x in shear if float(x["eps_a"]) >= float(shear[-1]["eps_a"]) - 0.01]
    assert len(last) >= 3 and float(shear[-1]["eps_a"]) > 0.019, name
    p_mean = sum(float(x["p"]) for x in last) / len(last)
    e_mean = sum(float(x["e"]) for x in last) / len(last)
    assert (p_end, e_end) == (f"{p_mean / 1e3:.1f}", f"{e_mean:.4f}"), (r, p_mean, e_mean)
    assert name in sec[f], (name, f)
print("report ok")
PY
# A preparation study over the files: each file's samples a row of their own, not two seeds of one sample.
sed '/name: shear/d' base.yaml > prepbase.yaml
printf 'base: prepbase.yaml\naxes: {sample_file: {a: packings/a.h5, b: packings/b.h5}}\n' > prep.yaml
out=$("$bin" study prep.yaml --out pr --jobs 2 --threads 1 2>&1) || fail "the preparation study failed: $out"
for f in a b; do
  grep -q "^| sample_mur0_ebase_pbase_f${f}_n300 | 300 | 1 (file) | " pr/report.md ||
    fail "no preparation row of file $f: $(grep -A5 '^## Preparation' pr/report.md)"
done
# One critical-state line through both files' critical states (three pressures each; the study's own loose
# tolerances make each 2 % shear count as critical): the line and each file's mean offset from it as numpy fits them
# to the window means of the shears' series.
cat > lines.yaml <<'YAML'
base: base.yaml
axes:
  drainage: [drained]
  p0: [60e3, 100e3, 170e3]
  sample_file: {a: packings/a.h5, b: packings/b.h5}
critical_state: {window: 0.01, qp_tol: 0.5, p_tol: 0.5, e_tol: 0.05}
YAML
out=$("$bin" study lines.yaml --out stl --jobs 2 --threads 1 2>&1) || fail "the study over three pressures failed: $out"
"$py" - stl <<'PY' || fail "the line through the files"
import csv, json, os, re, sys
import numpy as np
out = sys.argv[1]
text = open(os.path.join(out, "report.md")).read()
crit = [r.split(" | ") for r in text.splitlines() if re.match(r"\| [ab] \| ", r)]
assert len(crit) == 6 and all(r[8] == "yes |" for r in crit), crit
states = []
for r in crit:
    with open(os.path.join(out, "jobs", r[3], "run", "series.csv")) as fh:
        sh = [x for x in csv.DictReader(fh) if 0 < int(x["stage_type"]) < 3]
    w = [x for x in sh if float(x["eps_a"]) >= float(sh[-1]["eps_a"]) - 0.01]
    states.append((r[0][2:], np.mean([float(x["p"]) for x in w]) / 1e3, np.mean([float(x["e"]) for x in w])))
p = np.array([s[1] for s in states])
e = np.array([s[2] for s in states])
b, a = np.polyfit(p, e, 1)
res = e - (a + b * p)
rms = float(np.sqrt(np.sum(res ** 2) / (len(p) - 2)))
# the yardstick: the scatter about the line once each file's mean residual is taken out (6 - 2 - 1 degrees of freedom)
mine = {f: np.array([res[i] for i, s in enumerate(states) if s[0] == f]) for f in "ab"}
within = float(np.sqrt(sum(np.sum((r - r.mean()) ** 2) for r in mine.values()) / 3))
rows = [r for r in text.splitlines() if r.startswith("| mu_r 0, 1/s | e_c = ")]
assert len(rows) == 2, rows
for f, row in zip("ab", rows):
    c = row.split(" | ")
    off = float(mine[f].mean())
    se = within / np.sqrt(3)
    want = (f"e_c = {a:.4f} ± ", f"+ ({b:.3e} ± ", f"(6 states, rms {rms:.4f})")
    assert all(w in c[1] for w in want), (c[1], want)
    assert c[2:6] == [f, "3", f"{round(off, 4) + 0.0:+.4f}", f"{se:.4f}"], (c, off, se)
    assert c[6] == ("off the line |" if abs(off) > 2 * se else "on it |"), c
print("line ok")
PY
# A pattern in place of the mapping: its files named by their stems, the same jobs as the mapping's
printf 'base: base.yaml\naxes:\n  drainage: [drained, undrained]\n  sample_file: "packings/*.h5"\n' > glob.yaml
plan=$("$bin" validate glob.yaml 2>&1) || fail "validate of a pattern failed: $plan"
printf '%s\n' "$plan" | grep -qF "sample files: 2, each consolidated again by its sample jobs in place of the base's sample (a: 300 spheres, e $e_a, $PWD/packings/a.h5; b: 300 spheres, e $e_b, $PWD/packings/b.h5)" ||
  fail "the pattern's files: $plan"
# A target e_0 the file cannot reach here (b's spheres consolidate no looser than e 0.77 at 190 kPa, even at mu_max 1):
# the study warns as the sample job ends (with the e its trials reached), summary.json records the target, the report
# marks the sample.
printf 'base: base.yaml\naxes:\n  e0: [0.8]\n  sample_file: {b: packings/b.h5}\n' > e0.yaml
err=$("$bin" study e0.yaml --out ste0 --jobs 2 --threads 1 2>&1 >/dev/null) || fail "the e0 study failed: $err"
printf '%s\n' "$err" | grep -qE "^grainlab study: warning: sample_mur0_e0.8_pbase_fb_n300: target_e0 NOT reached \(again: e 0\.7[0-9]* against target_e0 0.8 \(tolerance 0.003\)\): .* here \(its [2-9] trials reached e 0\.[0-9]{4} to 0\.7[0-9]{3}\); the report" ||
  fail "no warning of the missed target: $err"
grep -q '"target_e0": 0.8, "target_e0_tolerance": 0.003}' ste0/jobs/sample_mur0_e0.8_pbase_fb_n300/run/summary.json ||
  fail "summary.json lacks the target"
grep -q "^| sample_mur0_e0.8_pbase_fb_n300 | 300 | .* | target_e0 0.8 NOT reached (again: e 0\.7[0-9]*); " ste0/report.md &&
  grep -q "^1 of 1 samples did not reach their target_e0" ste0/report.md || fail "the report does not mark the missed target"
# and the void ratios its trials did reach (the sample file's /search/trial_e): from mu = 0 (the densest) to mu_max
grep -qE "start from the e_0 given here: sample_mur0_e0.8_pbase_fb_n300 \(its [2-9] trials' e 0\.[0-9]{4} to 0\.7[0-9]{3}\)\.$" ste0/report.md ||
  fail "the report does not give the e the search's trials reached: $(grep 'did not reach' ste0/report.md)"
# An extra job on one file by its name (and the base's own drawn sample beside it)
printf 'base: base.yaml\naxes: {sample_file: {a: packings/a.h5}}\nextra: [{sample_file: a, drainage: drained}, {drainage: drained}]\n' > extra.yaml
plan=$("$bin" validate extra.yaml 2>&1) || fail "validate of extra jobs failed: $plan"
printf '%s\n' "$plan" | grep -q "study: 2 samples, 3 shear tests" || fail "extra jobs: $plan"
# Refusals: each names the study, the key and what is allowed; nothing is written.
# (a pattern's odd matches: a stem that is no job name, two files of one stem)
mkdir -p odd && cp packings/a.h5 "odd/a b.h5" && cp packings/a.h5 odd/c.h5 && cp packings/a.h5 odd/c.hdf5 || exit 1
: > bad.yaml
before=$(ls -R)
t() {
  printf 'base: base.yaml\n%s\n' "$1" > bad.yaml
  "$here"/expect_error.sh "^grainlab: error: bad.yaml: $2" "$bin" validate bad.yaml || fail "refusal of: $1"
}
t 'axes: {sample_file: [packings/a.h5]}' 'axes.sample_file: must name each sample file: \{dense: dense.h5, loose: loose.h5\}.*or be a pattern, "packings/\*.h5", whose files are named by their stems$'
t 'axes: {sample_file: {}}' 'axes.sample_file: must name each sample file'
t 'axes: {sample_file: {"a b": packings/a.h5}}' "axes.sample_file.a b: a sample file's name ends its sample job's directory name: 1-40 letters"
t 'axes: {sample_file: {a: [packings/a.h5]}}' 'axes.sample_file.a: must be the path of a sample file'
t 'axes: {sample_file: {a: packings/a.h5, c: ./packings/a.h5}}' "axes.sample_file.c: is a's file \($PWD/packings/a.h5\) again: each sample file once"
t 'axes: {sample_file: {a: packings/none.h5}}' "axes.sample_file.a: $PWD/packings/none.h5: no such file$"
t 'axes: {sample_file: {a: b.txt}}' "axes.sample_file.a: $PWD/b.txt: text, not an HDF5 file .*grainlab import $PWD/b.txt"
t 'axes: {sample_file: {a: packings/a.h5}, seed: [1, 2]}' "axes.seed: axes.sample_file gives each sample the spheres of its file: no seed, count or grading to set$"
t 'axes: {sample_file: {a: packings/a.h5}, count: [100]}' "axes.count: axes.sample_file gives each sample"
t 'axes: {sample_file: {a: packings/a.h5}, grading: {x: {diameter: [1e-3, 2e-3], passing: [0, 100]}}}' "axes.grading: axes.sample_file gives each sample"
t 'axes: {sample_file: {a: packings/a.h5}}
extra: [{sample_file: c}]' "extra\[0\].sample_file: 'c' is not a name of axes.sample_file \(a\)$"
t 'extra: [{sample_file: a}]' "extra\[0\].sample_file: names a file of axes.sample_file, and the study has no such axis$"
t 'axes: {sample_file: "packings/*.hdf5"}' "axes.sample_file: 'packings/\*.hdf5' matches no file \($PWD/packings/\*.hdf5\)$"
t 'axes: {sample_file: "odd/*.h5"}' "axes.sample_file.a b: a sample file's name ends its sample job's directory name"
t 'axes: {sample_file: "odd/c.*"}' "axes.sample_file.c: names two files, $PWD/odd/c.h5 and $PWD/odd/c.hdf5: a sample file's name is its job's$"
[ "$(ls -R)" = "$before" ] || fail "a refused study wrote: $(diff <(printf '%s\n' "$before") <(ls -R))"
# A file replaced after its jobs ran (b's spheres under a's name): the rerun stops before anything is written.
cp st/report.md report_before.md && cp packings/b.h5 packings/a.h5 || exit 1
"$here"/expect_error.sh "st/jobs/sample_mur0_ebase_pbase_fa_n300/job.yaml: this job ran on another sample than $PWD/packings/a.h5 holds now" \
  "$bin" study study.yaml --out st --jobs 2 --threads 1 || fail "a replaced sample file was not noticed"
cmp -s st/report.md report_before.md || fail "the report was rewritten"
echo "study_sample_files: ok"
