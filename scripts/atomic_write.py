"""Atomic file output for grainlab's Python tools (the project's data-safety rule: temp file + rename).

write_atomically(path, write) calls write(tmp) to fill a temporary file beside path, flushes it to disk and
renames it over path in one step. An interrupted run (Ctrl-C, a full disk, a crash inside write) leaves the
previous file whole, or none, never a half-written one that looks valid; the temporary file is removed.
"""
import errno
import os

# A write that fails for want of space (a full disk, a quota, a file-size limit): said so, as the engine says it.
NO_SPACE = (errno.ENOSPC, errno.EFBIG, errno.EDQUOT)


def write_atomically(path, write):
    tmp = f"{path}.tmp.{os.getpid()}"
    try:
        write(tmp)
        with open(tmp, "rb") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError as e:
        # Named for the file being written, not its temporary name, nor none: a figure's writer (matplotlib's PNG
        # encoder) raises errors without a file name ("error: : File too large").
        why = e.strerror or str(e)
        if e.errno in NO_SPACE:
            why += "; disk full? The previous file is untouched"
        raise OSError(e.errno, why, path) from e
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def write_text_atomically(path, text):
    def fill(tmp):
        with open(tmp, "w") as fh:
            fh.write(text)
    write_atomically(path, fill)
