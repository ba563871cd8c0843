#!/usr/bin/python3
"""scripts/atomic_write.py keeps the data-safety rule for the Python tools (grainlab plot / csl / study reports,
perf reports): a write that fails part-way leaves the previous file byte for byte and no temporary file; a write
that succeeds replaces it whole. Usage: atomic_write_check.py WORKDIR"""
import os
import shutil
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts"))
from atomic_write import write_atomically, write_text_atomically  # noqa: E402

work = sys.argv[1]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
path = os.path.join(work, "report.md")
write_text_atomically(path, "old report\n")


def half_then_fail(tmp):
    # What a Ctrl-C or a full disk does in the middle of savefig or a long write: part of the file is out.
    with open(tmp, "w") as fh:
        fh.write("new rep")
    raise KeyboardInterrupt


try:
    write_atomically(path, half_then_fail)
    sys.exit("atomic_write_check: the failing writer's exception was swallowed")
except KeyboardInterrupt:
    pass
failures = []
if open(path).read() != "old report\n":
    failures.append(f"the previous file was changed: {open(path).read()!r}")
if sorted(os.listdir(work)) != ["report.md"]:
    failures.append(f"left behind: {sorted(os.listdir(work))}")
write_text_atomically(path, "new report\n")
if open(path).read() != "new report\n":
    failures.append("a successful write did not replace the file")
if failures:
    sys.exit("atomic_write_check: " + "; ".join(failures))
print("atomic_write_check: ok (interrupted write left the old file, successful write replaced it)")
