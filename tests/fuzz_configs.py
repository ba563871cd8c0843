#!/usr/bin/env python3
"""Config fuzzing (issue 7): >= N mutated configs made from the shipped ones (deleted keys, wrong types,
huge/negative/NaN numbers, unicode, deep nesting, truncation, empty and binary files) through
`grainlab validate`. Every one must end with exit 0, or exit 1 and exactly one error line naming the
file; no crash (signal), no hang (10 s; an optional 4th argument gives another limit: the sanitized build runs
15-20x slower, and validate's placement of UR1's 32 000 spheres takes 0.8 s in the release build, 12.8 s under
ASan + UBSan, so a valid mutation of UR1 would read as a hang at 10 s; this seed's 300 pass at 10 s too), no sanitizer
report."""
import glob, os, random, subprocess, sys, tempfile

binary, src, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
hang = float(sys.argv[4]) if len(sys.argv) > 4 else 10.0
seeds = sorted(glob.glob(os.path.join(src, "configs", "**", "*.yaml"), recursive=True))
seeds += sorted(glob.glob(os.path.join(src, "tests", "data", "*.yaml")))
texts = [open(p, encoding="utf-8").read() for p in seeds]
rng = random.Random(20261122)
hostile = ["-1", "0", "1e308", "-1e308", ".nan", ".inf", "-.inf", "NaN", "abc", "ü漢字😀", "[1, 2, 3]", "{a: 1}",
           "''", "null", "~", "true", "0x1F", "1e-320", "99999999999999999999999", "'1'", '""', "!!binary aGVsbG8=",
           "-0", "1_000", "0o17", "&a 5", "*a", "[", "{", "]", "'unterminated", "- 1", "? x", "|\n  block",
           "9.3e18", "2e9", "-2e9", "1e-300", "4.9e-324", "\t", "\\x00", "\u202e", "a: b: c"]
keys = ["count", "D", "r_min", "r_max", "seed", "mu", "mu_r", "E", "dt", "dt_factor", "skin", "inner_skin", "type", "stages",
        "pressure", "target_e0", "drainage", "file", "dir", "every", "sample", "material", "numerics", "output",
        "ключ", "😀", "", "max_steps", "max_axial_strain", "axial_strain_rate", "keep_checkpoints",
        "cycles", "q_amplitude", "strain_amplitude", "liquefaction_ru", "liquefaction_da_strain", "b", "direction",
        "servo_gain", "servo_integral", "stress_path", "max_servo_error", "csr", "grading", "diameter", "passing",
        "sigma_v_amplitude", "sigma_v", "ocr", "k_ratio", "lateral_slope", "stress_direction", "stress_increment"]


def mutate(text):
    op = rng.randrange(12)
    lines = text.splitlines()
    if op == 0 and lines:  # delete lines
        for _ in range(rng.randint(1, 4)):
            if lines:
                del lines[rng.randrange(len(lines))]
    elif op in (1, 2, 3):  # hostile value for a key
        idx = [i for i, l in enumerate(lines) if ":" in l and not l.lstrip().startswith("#")]
        for _ in range(rng.randint(1, 3)):
            if idx:
                i = rng.choice(idx)
                head = lines[i].split(":", 1)[0]
                lines[i] = f"{head}: {rng.choice(hostile)}"
    elif op == 4 and lines:  # duplicate a line
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif op == 5:  # insert a key at a random place and indentation
        lines.insert(rng.randint(0, len(lines)), " " * rng.choice([0, 2, 4, 6]) + f"{rng.choice(keys)}: {rng.choice(hostile)}")
    elif op == 6:  # truncate
        return text[: rng.randrange(len(text) + 1)]
    elif op == 7:
        return rng.choice(["", " ", "\n\n", "#only a comment\n", "---\n...\n", "null", "[]", "{}", "- a\n- b\n"])
    elif op == 8:  # deep nesting
        d = rng.choice([10, 63, 65, 200, 5000, 100000])
        kind = rng.randrange(3)
        if kind == 0:
            return "stages: " + "[" * d + "]" * d + "\n"
        if kind == 1:
            return "sample: " + "{a: " * d + "1" + "}" * d + "\n"
        return "".join(" " * (2 * k) + f"k{k}:\n" for k in range(min(d, 3000))) + " " * 6000 + "x: 1\n"
    elif op == 9:  # binary junk
        return "".join(chr(rng.randrange(1, 256)) for _ in range(rng.randint(1, 400)))
    elif op == 10:  # unicode in keys and values
        for _ in range(2):
            if lines:
                i = rng.randrange(len(lines))
                lines[i] = lines[i].replace("a", "ä").replace("e", "é") + " 漢字"
    else:  # re-indent a line
        if lines:
            i = rng.randrange(len(lines))
            lines[i] = " " * rng.randint(0, 9) + lines[i].lstrip()
    return "\n".join(lines) + ("\n" if rng.random() < 0.9 else "")


env = dict(os.environ, ASAN_OPTIONS="detect_leaks=0:abort_on_error=0:exitcode=99", UBSAN_OPTIONS="halt_on_error=1:exitcode=98")
fails, ok, errors = [], 0, 0
with tempfile.TemporaryDirectory() as tmp:
    for k in range(count):
        base = rng.choice(texts)
        text = mutate(base)
        if rng.random() < 0.3:
            text = mutate(text)
        path = os.path.join(tmp, f"fuzz_{k:05d}.yaml")
        with open(path, "w", encoding="utf-8", errors="surrogatepass") as f:
            f.write(text)
        try:
            r = subprocess.run([binary, "validate", path], capture_output=True, timeout=hang, env=env)
        except subprocess.TimeoutExpired:
            fails.append((path, f"hang ({hang:g} s)", text[:200]))
            continue
        err = r.stderr.decode("utf-8", "replace")
        bad = None
        if r.returncode < 0:
            bad = f"crashed with signal {-r.returncode}"
        elif "Sanitizer" in err or "runtime error" in err:
            bad = "sanitizer report"
        elif r.returncode == 0:
            ok += 1
        elif r.returncode == 1:
            lines = [l for l in err.splitlines() if l.strip()]
            if len(lines) != 1 or not lines[0].startswith(f"grainlab: error: {path}:"):
                bad = f"error is not one line naming the file: {err!r}"
            else:
                errors += 1
        else:
            bad = f"exit code {r.returncode}"
        if bad:
            fails.append((path, bad, err[:300] + " | config: " + text[:200]))
print(f"{count} mutated configs: {ok} valid, {errors} rejected with one clear line, {len(fails)} failures")
for f in fails[:10]:
    print("FAIL", f)
sys.exit(1 if fails else 0)
