"""Files rewritten while a run goes on (summary.json, the .pvd indices) and
the step files the indices name are written atomically: a reader never
sees, and a run stopped half-way never leaves, half a file."""
from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

# the temporary name of write_atomic's `path`: "." + path's stem + "." + tempfile's eight characters
_TEMPORARY = re.compile(r"\.(.+)\.[a-z0-9_]{8}")


def write_atomic(path, data) -> Path:
    """Write `data` (bytes, or pieces of bytes written one after the
    other: a list or a generator, which may raise) to `path` through a
    temporary file in the same folder, synced and then renamed over
    `path`."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            if isinstance(data, (bytes, bytearray, memoryview)):
                fh.write(data)
            else:
                fh.writelines(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def temporary_of(name: str) -> str | None:
    """The stem of the file that write_atomic was writing under the
    temporary name `name` (left behind by a process killed outright), or
    None when `name` is no such name."""
    m = _TEMPORARY.fullmatch(name)
    return m.group(1) if m else None
