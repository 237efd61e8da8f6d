"""Files rewritten while a run goes on (summary.json, the .pvd indices),
the step files the indices name, the checkpoint and the pictures are
written atomically: a reader never sees, and a run stopped half-way never
leaves, half a file. A file that cannot be written (the disk full, the
folder read-only or no longer writable, a folder in the file's place) is a
WriteError naming the file, and its temporary file is removed (where the
folder still allows it: otherwise the next run, or `--resume`, removes it
through io.outdir.leftovers)."""
from __future__ import annotations

import contextlib
import os
import re
import tempfile
from pathlib import Path

from ..errors import WriteError

# the temporary name of `path` here: "." + path's stem + "." + tempfile's eight characters
# (+ path's suffix, for writers that choose the format by it: the animation's)
_TEMPORARY = re.compile(r"\.(.+)\.[a-z0-9_]{8}(\.[a-z0-9]+)?")


def unwritable(path, err: OSError) -> WriteError:
    """The WriteError of `path` for the system's error `err`."""
    return WriteError(path, err.strerror or str(err) or type(err).__name__)


@contextlib.contextmanager
def replacing(path, suffix: str = ""):
    """Within: the path of a new temporary file in `path`'s folder (its name
    ends with `suffix`) for the caller to write; on leaving, it is synced
    and renamed over `path`, or removed if anything was raised. An OSError
    within or on the way is a WriteError naming `path`."""
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=suffix, dir=path.parent)
        os.close(fd)
    except OSError as err:
        raise unwritable(path, err) from None
    try:
        yield Path(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException as err:
        with contextlib.suppress(OSError):   # a folder that allows no more removes it either: leftovers()
            os.unlink(tmp)
        if isinstance(err, OSError):
            raise unwritable(path, err) from None
        raise


def write_atomic(path, data) -> Path:
    """Write `data` (bytes, or pieces of bytes written one after the
    other: a list or a generator, which may raise) to `path` through a
    temporary file in the same folder, synced and then renamed over
    `path` (replacing)."""
    path = Path(path)
    with replacing(path) as tmp:
        with open(tmp, "wb") as fh:
            if isinstance(data, (bytes, bytearray, memoryview)):
                fh.write(data)
            else:
                fh.writelines(data)
    return path


def temporary_of(name: str) -> str | None:
    """The stem of the file that write_atomic was writing under the
    temporary name `name` (left behind by a process killed outright), or
    None when `name` is no such name."""
    m = _TEMPORARY.fullmatch(name)
    return m.group(1) if m else None
