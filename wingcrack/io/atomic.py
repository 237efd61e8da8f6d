"""Files rewritten while a run goes on (summary.json, the .pvd indices) and
the step files the indices name are written atomically: a reader never
sees, and a run stopped half-way never leaves, half a file."""
from __future__ import annotations

import os
import tempfile
from pathlib import Path


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
