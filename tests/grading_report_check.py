#!/usr/bin/env python3
"""Oracle of a shear study's report over several gradings (tests/study_grading.sh): each curve's section of report.md
is the report of a study of that curve alone (its headings one level down, its figures in figures/g_<curve>/): the same
jobs give the same bits, so the two texts must agree line for line past their titles. And every figure either report
names in backquotes exists.
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
for d, text in ((out, lines), (one, alone)):
    for f in sorted(set(re.findall(r"`(figures/[^`]+\.png)`", "\n".join(text)))):
        if not os.path.isfile(os.path.join(d, f)):
            fails.append(f"{d}/report.md names {f}, which is not there")
print("\n".join(fails) or f"the {curve} section is its study's report alone")
sys.exit(1 if fails else 0)
