#!/usr/bin/env python3
"""Oracle of a shear study's report over several gradings (tests/study_grading.sh): each curve's section of report.md
is the report of a study of that curve alone (its headings one level down, its figures in figures/g_<curve>/): the same
jobs give the same bits, so the two texts must agree line for line past their titles. The tables across the curves
give each monotonic shear's phi'_max (and a critical state's p', e) and each liquefaction-resistance fit's CRR as its
section does. And every figure either report names in backquotes exists.
  grading_report_check.py STUDY_DIR CURVE ONE_CURVE_STUDY_DIR"""
import os
import re
import sys

out, curve, one = sys.argv[1], sys.argv[2], sys.argv[3]
fails = []
lines = open(os.path.join(out, "report.md")).read().split("\n")
alone = open(os.path.join(one, "report.md")).read().split("\n")
heads = [k for k, x in enumerate(lines) if x.startswith("## Grading ")]
mine = [k for k in heads if lines[k].startswith(f"## Grading {curve}: ")]
if len(heads) < 2 or len(mine) != 1:
    fails.append(f"sections {[lines[k] for k in heads]}: expected one of {curve} among two or more")
else:
    end = next((k for k in heads if k > mine[0]), len(lines))
    part = lines[mine[0] + 1:end]
    while part and part[-1] == "":
        part.pop()
    want = [x for x in alone[1:]]
    while want and want[-1] == "":
        want.pop()
    got = [x[1:] if x.startswith("##") else x for x in part]
    got = [x.replace(f"`figures/g_{curve}/", "`figures/") for x in got]
    if got != want:
        k = next((i for i, (a, b) in enumerate(zip(got, want)) if a != b), min(len(got), len(want)))
        fails.append(f"{curve}'s section differs from its study alone at its line {k + 1} ({len(got)} lines against "
                     f"{len(want)}):\n  section: {got[k] if k < len(got) else '(end)'}\n  alone:   "
                     f"{want[k] if k < len(want) else '(end)'}")
    if not any(f"`figures/g_{curve}/" in x for x in part):
        fails.append(f"{curve}'s section names no figure of figures/g_{curve}/")


def table(text, column):
    """{test: cells} of the table in text whose header has `column`, with that column's index."""
    for k, x in enumerate(text):
        if x.startswith("| ") and column in x.split(" | "):
            head = [c.strip() for c in x.strip("|").split("|")]
            rows = {}
            for y in text[k + 2:]:
                if not y.startswith("| "):
                    break
                cells = [c.strip() for c in y.strip("|").split("|")]
                rows[cells[head.index("test")]] = cells
            return rows, head.index(column)
    return {}, None


# The table across the gradings: one row a monotonic shear, its phi'_max and (where critical) end state as its section
# gives them.
across = lines[lines.index("## Across the gradings"):heads[0]] if "## Across the gradings" in lines and heads else []
rows, k_max = table(across, "max q/p' (phi'_max)")
n_peaks = 0
crr_want = []
for k in heads:
    end = next((h for h in heads if h > k), len(lines))
    sec = lines[k:end]
    peaks, k_peak = table(sec, "max q/p' (phi'_max)")
    crit, k_crit = table(sec, "critical")
    n_peaks += len(peaks)
    # the section's liquefaction-resistance fits, as the table across the curves must give them
    fit_head = next((x for x in sec if x.startswith("| mu_r |") and "| CRR (N = " in x), None)
    if fit_head:
        head = [c.strip() for c in fit_head.strip("|").split("|")]
        at = sec.index(fit_head)
        cu = lines[k].split(": Cu = ")[1]
        for y in sec[at + 2:]:
            if not y.startswith("| "):
                break
            c = dict(zip(head, [v.strip() for v in y.strip("|").split("|")]))
            crr_want.append(f"| {lines[k][len('## Grading '):].split(':')[0]} | {cu} | {c['mu_r']} | "
                            f"{c.get('conditions', '–')} | {c['criterion']} | {c['tests']} | {c[head[head.index('b') + 1]]} |")
    for test, cells in peaks.items():
        if test not in rows:
            fails.append(f"{test} is not in the table across the gradings")
            continue
        if rows[test][k_max] != cells[k_peak]:
            fails.append(f"{test}: phi'_max {rows[test][k_max]} across, {cells[k_peak]} in its section")
        c = crit.get(test)
        if c and c[k_crit] == "yes" and rows[test][4:6] != [c[k_crit + 1], c[k_crit + 3]]:
            fails.append(f"{test}: end p', e {rows[test][4:6]} across, critical state {c[k_crit + 1]}, {c[k_crit + 3]}")
if len(rows) != n_peaks:
    fails.append(f"the table across the gradings has {len(rows)} rows for the sections' {n_peaks} peak rows")
crr_got = []
if "## Liquefaction resistance across the gradings" in lines:
    at = next(k for k in range(lines.index("## Liquefaction resistance across the gradings"), len(lines))
              if lines[k].startswith("| grading |"))
    crr_got = lines[at + 2:next((k for k in range(at + 2, len(lines)) if not lines[k].startswith("| ")), len(lines))]
if crr_got != crr_want:
    fails.append("the liquefaction resistance across the gradings:\n  got    " + "\n         ".join(crr_got)
                 + "\n  wanted " + "\n         ".join(crr_want))
for d, text in ((out, lines), (one, alone)):
    for f in sorted(set(re.findall(r"`(figures/[^`]+\.png)`", "\n".join(text)))):
        if not os.path.isfile(os.path.join(d, f)):
            fails.append(f"{d}/report.md names {f}, which is not there")
print("\n".join(fails) or f"the {curve} section is its study's report alone")
sys.exit(1 if fails else 0)
