"""A result folder: which files a wingcrack result holds, its name, its
lock, getting it ready for a new result or for resuming the run it holds,
and reading a result back. Under a launcher (parallel.launched) rank 0 does
the folder's work and every rank raises its refusal.

`wingcrack run` writes summary.json, step_XXXX.vtu and faces_XXXX.vtu (one
of each per step), fields.pvd and faces.pvd (their ParaView indices),
fractures.png and, unless --no-plots, history.png and growth.gif
(growth.mp4 when ffmpeg is on PATH). `wingcrack sif` writes the same layout
for its one step (step 0) and fractures.png. (fields.vtu and faces.vtu are
what `sif` wrote before: still a previous result, that --force deletes.)

A new result never replaces a previous one unless forced. Without force, a
folder holding any of these files is refused; with force, exactly these
files are deleted first (nothing else in the folder is touched), so no step
file of a longer earlier run is left next to the new ones.

One command at a time per folder (locked): `run`, `sif`, `run --resume` and
`plot` (and api.run, sif from Python) hold an exclusive advisory lock
(flock) on the folder itself for the whole command, so a second one into the same folder is refused at once
instead of mixing its files with the first's. The lock is on the folder's
own inode, not on a lock file: nothing is added to the folder (a refused or
foreign folder stays as it was, and --force and read_result see only the
result's files), and nothing stale is left after a kill: the kernel drops
the lock with the process that held it. Under mpirun rank 0 holds it.
"""
from __future__ import annotations

import contextlib
import errno
import fcntl
import json
import math
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import interrupt
from ..errors import FolderError
from ..parallel import launched

SUMMARY = "summary.json"
FIELDS_PVD, FACES_PVD = "fields.pvd", "faces.pvd"
OLD_SIF_FILES = ("fields.vtu", "faces.vtu")   # a `sif` result of earlier versions
PICTURES = ("fractures.png", "history.png", "growth.gif", "growth.mp4")
CHECKPOINT = "checkpoint.npz"   # propagation/checkpoint.py: what `run --resume` needs
_NAMES = frozenset((SUMMARY, FIELDS_PVD, FACES_PVD, *OLD_SIF_FILES, CHECKPOINT, *PICTURES))
_STEP_FILE = re.compile(r"(step|faces)_\d{4,}\.vtu")


def fields_name(step: int) -> str:
    """The field file of a run's step (displacement, stress, von Mises)."""
    return f"step_{step:04d}.vtu"


def faces_name(step: int) -> str:
    """The fracture-face file of a run's step (opening, slip, tractions,
    contact state open / stick / slip, slip increment: io/faces.py)."""
    return f"faces_{step:04d}.vtu"


def result_files(folder) -> list[Path]:
    """The files of a wingcrack result that `folder` holds (sorted)."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.iterdir() if p.name in _NAMES or _STEP_FILE.fullmatch(p.name))


def leftovers(folder) -> list[Path]:
    """The temporary files of result files that a killed run was writing
    (io/atomic.py): never part of a result, removed when a result is made."""
    from .atomic import temporary_of

    folder = Path(folder)
    if not folder.is_dir():
        return []
    stems = {Path(n).stem for n in _NAMES}
    return sorted(p for p in folder.iterdir() if (stem := temporary_of(p.name)) is not None
                  and (stem in stems or _STEP_FILE.fullmatch(stem + ".vtu")))


def _names(files) -> str:
    steps = [p for p in files if _STEP_FILE.fullmatch(p.name)]
    named = [p.name for p in files if p not in steps]
    return ", ".join(named + ([f"{len(steps)} step files"] if steps else []))


def check_folder_name(out) -> None:
    """FolderError for an output folder named by an empty or blank string:
    Path("") is the current folder, where the result would land among
    whatever is there."""
    if isinstance(out, str) and not out.strip():
        raise FolderError(repr(out), "an empty folder name (it would mean the current folder; say . for that)")


def folder_path(text: str) -> Path:
    """The folder a command line names, as a Path: FolderError for a name
    that is empty or only blanks (check_folder_name) or that the system
    refuses outright."""
    check_folder_name(str(text))
    try:
        os.stat(text)
    except (FileNotFoundError, NotADirectoryError):
        pass   # a new folder, or one below a file: prepare() says which
    except OSError as err:   # a name too long, a symlink loop: no file operation on it can work
        raise FolderError(text, f"cannot use the path ({err.strerror or err})") from None
    return Path(text)


def _world():
    """MPI.COMM_WORLD where the folder's work is collective (launched), else None."""
    if not launched():
        return None
    from mpi4py import MPI   # here: a serial command never starts MPI

    return MPI.COMM_WORLD


def _on_root(work, comm):
    """work() on rank 0 of comm (None: here); every rank raises its FolderError."""
    problem = None
    if comm is None or comm.rank == 0:
        try:
            work()
        except FolderError as err:
            problem = (err.path, err.reason)
    if comm is not None and comm.size > 1:
        problem = comm.bcast(problem, root=0)
    if problem is not None:
        raise FolderError(*problem)


def prepare_for_result(out, force: bool = False) -> Path:
    """prepare(out, force) on rank 0, the previous result deleted whole or
    not at all (a Ctrl-C waits for it); every rank raises its FolderError."""
    def work():
        with interrupt.deferred():
            prepare(out, force)

    _on_root(work, _world())
    return Path(out)


def prepare(out, force: bool = False) -> Path:
    """Make `out` ready for a new result and return it as a Path.

    Raises FolderError when `out` is a file, cannot be created or written,
    or holds a previous result and `force` is false. With `force`, the
    previous result's files are deleted; the temporary files that a killed
    run left (leftovers) are deleted in any case."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise FolderError(out, "is a file, not a folder")
    previous = result_files(out)
    if previous and not force:
        raise FolderError(out, f"holds a previous result ({_names(previous)}); replace it with --force (force=True from Python)")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise FolderError(out, f"cannot create the folder ({err.strerror or err})") from None
    check_writable(out)
    try:
        for p in previous + leftovers(out):
            p.unlink()
    except OSError as err:
        raise FolderError(out, f"cannot replace the previous result ({err.strerror or err})") from None
    return out


@contextlib.contextmanager
def locked(folder, create: bool = False):
    """Hold the lock of `folder` within (see the module doc); FolderError
    "is in use by another wingcrack run (pid N)" at once when another process
    holds it. Re-entrant within a process (the CLI holds it for the command,
    the api may take it again). `create`: make the folder first if it is
    missing (a new result's folder). A folder that is missing (and not to be
    created), is not a folder, or cannot be opened or locked is not locked
    here: the command itself then reports why it cannot use it. Under a
    launcher rank 0 takes the lock and every rank raises its refusal."""
    comm = _world()
    rank = 0 if comm is None else comm.rank
    key, holder = None, None
    if rank == 0:
        key, holder = _lock(Path(folder), create)
    if comm is not None and comm.size > 1:
        holder = comm.bcast(holder, root=0)
    if holder is not None:
        raise FolderError(folder, "is in use by another wingcrack run" + (f" (pid {holder})" if holder > 0 else "")
                          + "; wait for it to end or use another folder")
    try:
        yield Path(folder)
    finally:
        if key is not None:
            _held[key][1] -= 1
            if _held[key][1] == 0:
                os.close(_held.pop(key)[0])   # closing the only descriptor releases the lock


_held: dict = {}   # (st_dev, st_ino) of a folder this process locks -> [descriptor, depth]


def _lock(folder: Path, create: bool):
    """(key of the lock now held, or None; pid of another holder, or None; 0 when unknown)."""
    try:
        if create:
            folder.mkdir(parents=True, exist_ok=True)
        fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return None, None
    st = os.fstat(fd)
    key = (st.st_dev, st.st_ino)
    if key in _held:
        os.close(fd)   # a second descriptor's flock would conflict with our own
        _held[key][1] += 1
        return key, None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as err:
        holder = _lock_holder(fd) if err.errno in (errno.EWOULDBLOCK, errno.EAGAIN) else None
        os.close(fd)
        return None, holder   # other errors: a file system without flock, run unlocked as before
    _held[key] = [fd, 1]
    return key, None


def _lock_holder(fd) -> int:
    """The pid that holds the flock on fd's file, from /proc/locks (0 if unknown)."""
    st = os.fstat(fd)
    inode = f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"
    try:
        with open("/proc/locks", encoding="ascii", errors="replace") as fh:
            for line in fh:
                f = line.split()
                # "1: FLOCK  ADVISORY  WRITE 12672 fe:00:260072 0 EOF" (a waiter's line has "->")
                if len(f) >= 6 and f[1] == "FLOCK" and f[5] == inode and f[4].isdigit():
                    return int(f[4])
    except OSError:
        pass
    return 0


def open_to_resume(out) -> Path:
    """`out` as a Path, ready for `run --resume` to read its checkpoint:
    FolderError when there is no folder to resume, or it cannot be written;
    the temporary files a run stopped while the folder refused removals
    left are removed."""
    if out is None:
        raise FolderError(Path("."), "--resume needs the output folder of the run (-o)")
    out = Path(out)
    if not out.is_dir():
        raise FolderError(out, "does not exist: nothing to resume")
    check_writable(out)
    for p in leftovers(out):
        p.unlink(missing_ok=True)
    return out


def no_checkpoint(out) -> str | None:
    """Why a folder that holds a result but no checkpoint cannot be resumed:
    its run ended before committing a step (a step that stops the run is
    recorded, not checkpointed). None when that is not the case."""
    if (Path(out) / CHECKPOINT).exists():
        return None
    try:
        status = json.loads((Path(out) / SUMMARY).read_text())["status"]
    except Exception:  # noqa: BLE001 - no readable summary: the generic message
        return None
    return (f"holds a result (\"{status}\") without checkpoint.npz: no step of a run was committed there (a `sif` "
            "result, or a run that stopped in its first step), so nothing to resume; run it again without --resume "
            "(with --force)")


def check_resumable(out: Path, done: int, asked: int) -> None:
    """FolderError unless the run in `out`, whose checkpoint holds `done`
    finished steps, can go on to `asked` (the case's propagation.steps):
    fewer asked, it would end at once and call `asked` steps "finished"
    with `done` of them (as many: it finishes what a stop left, the pictures
    and the final status); and every finished step's files must be there,
    or the resumed result would have a hole."""
    if asked < done:
        raise FolderError(out, f"holds {done} finished step{'' if done == 1 else 's'}, more than the case's "
                               f"propagation.steps = {asked}: nothing to resume; ask for more steps to go on")
    for k in range(done):
        for name in (fields_name(k), faces_name(k)):
            if not (out / name).is_file():
                raise FolderError(out, f"{name} of finished step {k} is missing: the result cannot be "
                                       "completed; start the run again without --resume (with --force)")


def resumable_steps(out: Path) -> int:
    """The finished steps of the run in `out` that --resume goes on from:
    summary.json's, where the checkpoint exists (0 without one)."""
    try:
        if not (out / CHECKPOINT).is_file():
            return 0
        return len(json.loads((out / SUMMARY).read_text(encoding="utf-8"))["steps"])
    except (OSError, ValueError, KeyError, TypeError):
        return 0


def check_writable(folder) -> Path:
    """`folder` as a Path if a file can be created in it, else FolderError."""
    folder = Path(folder)
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as err:
        raise FolderError(folder, f"cannot write into the folder ({err.strerror or err})") from None
    return folder


@dataclass
class StoredResult:
    """A result read back from its folder: the summary (as in summary.json)
    and, per step, the field file and the fracture-face file."""
    folder: Path
    summary: dict
    fields: list
    faces: list

    @property
    def steps(self) -> list:
        return self.summary["steps"]

    def fields_of(self, k: int) -> "StepFields":
        """The mesh and von Mises stress of step k (from its field file)."""
        mesh = _read(self.fields[k])
        tri6 = _cells(mesh, "triangle6", self.fields[k])
        if "von_mises" not in mesh.point_data:
            raise FolderError(self.fields[k], "not a wingcrack field file (no von_mises)")
        return StepFields(np.asarray(mesh.points)[:, :2], tri6, np.asarray(mesh.point_data["von_mises"], float))

    def faces_of(self, k: int) -> "StepFaces":
        """The fracture faces of step k (from its face file). A face file
        written before friction has no state, tangential traction or slip
        increment: its pairs in contact are SLIP (frictionless or prescribed
        slip, as they were), the others OPEN, and the two fields are absent.
        One written before fluid pressure reads with pressure 0."""
        from .faces import FLOAT_FIELDS, OPEN, SLIP, STATE_NAMES

        if not self.summary.get("fractures"):
            # a case without fractures: its face file has no cells, which meshio writes but cannot read
            return StepFaces(np.zeros((0, 3, 2)), np.zeros(0, dtype=bool), np.zeros(0, dtype=np.int8),
                             {"state": np.zeros((0, 3), dtype=np.int8), "pressure": np.zeros((0, 3))})
        mesh = _read(self.faces[k])
        line3 = _cells(mesh, "line3", self.faces[k])[:, [0, 2, 1]]   # line3 nodes are [a, b, mid]: a -> mid -> b
        x = np.asarray(mesh.points)[:, :2]
        data = mesh.point_data
        closed = np.asarray(data.get("closed", np.zeros(len(x))), float) > 0.5
        if "state" in data:
            state = np.rint(np.asarray(data["state"], float)).astype(np.int8)
            if not np.isin(state, list(STATE_NAMES)).all():
                raise FolderError(self.faces[k], "not a wingcrack face file (a state that is not 0, 1 or 2)")
        else:
            state = np.where(closed, SLIP, OPEN).astype(np.int8)
        values = {name: np.asarray(data[name], float)[line3] for name in FLOAT_FIELDS if name in data}
        values.setdefault("pressure", np.zeros(line3.shape))   # a file from before fluid pressure: none
        values["state"] = state[line3]
        return StepFaces(x[line3], closed[line3[:, 0]] & closed[line3[:, 2]], edge_states(state[line3]), values)


def edge_states(node_states: np.ndarray) -> np.ndarray:
    """(k,) state of each face edge from the states (k, 3) of its nodes: OPEN
    unless both end nodes are in contact (a tip node never is); then SLIP
    when a node of it slips, else STICK (a sticking edge has no slip
    increment anywhere)."""
    from .faces import OPEN, SLIP, STICK

    s = np.asarray(node_states).reshape(-1, 3)
    closed = (s[:, 0] != OPEN) & (s[:, 2] != OPEN)
    return np.where(closed, np.where(np.any(s == SLIP, axis=1), SLIP, STICK), OPEN).astype(np.int8)


@dataclass
class StepFields:
    """x (n, 2) nodes; cells (m, 6) P2 triangles (vertices first);
    von_mises (n,) in Pa."""
    x: np.ndarray
    cells: np.ndarray
    von_mises: np.ndarray

    @property
    def triangles(self) -> np.ndarray:
        """The vertex triangles (m, 3), straight-sided, for drawing."""
        return self.cells[:, :3]


@dataclass
class StepFaces:
    """lines (k, 3, 2): each face edge (+ side) as a 3-point polyline (end,
    mid, end); closed (k,): both end nodes in contact; state (k,): the
    edge's OPEN / STICK / SLIP (io.faces; edge_states); values: the face
    file's point data at the lines' nodes, {name: (k, 3)}: "state" (int8)
    and "pressure" (Pa; 0 in a file without it) always, and opening, slip,
    normal_traction, tangential_traction, slip_increment, closed as far as
    the file holds them (io/faces.py)."""
    lines: np.ndarray
    closed: np.ndarray
    state: np.ndarray
    values: dict

    @property
    def pressure(self) -> np.ndarray:
        """(k,) the fluid pressure of each edge's fracture (Pa): the largest
        at its nodes (a tip node, which is no pair, holds 0)."""
        p = self.values["pressure"]
        return p.max(axis=1) if len(p) else np.zeros(0)

    @property
    def lengths(self) -> np.ndarray:
        """(k,) the length of each edge (m), end -> mid -> end."""
        return np.linalg.norm(np.diff(self.lines, axis=1), axis=2).sum(axis=1)


def _read(path):
    # meshio.vtu.read, not meshio.read: the latter prints and exits on a broken file
    from meshio import vtu

    try:
        return vtu.read(str(path))
    except Exception as err:  # noqa: BLE001 - meshio raises anything on a broken file
        detail = " ".join(str(err).split())
        raise FolderError(path, "cannot read it as VTU" + (f" ({detail})" if detail else "")) from None


def _cells(mesh, kind, path) -> np.ndarray:
    blocks = [np.asarray(c.data) for c in mesh.cells if c.type == kind]
    if not blocks:
        raise FolderError(path, f"not a wingcrack step file (no {kind} cells)")
    return np.vstack(blocks)


def read_result(folder, summary: dict | None = None) -> StoredResult:
    """Read summary.json of a result (a run, finished, stopped or failed, or
    a `sif`: one step), and find its step files. With `summary`, take that
    one instead of the folder's summary.json (a run that has written its
    steps but not yet its final status). Raises FolderError when `folder` is
    missing, is not a wingcrack result, or lacks a step file that the
    summary lists."""
    folder = Path(folder)
    if not folder.exists():
        raise FolderError(folder, "no such folder")
    if not folder.is_dir():
        raise FolderError(folder, "is a file, not a result folder")
    path = folder / SUMMARY
    if summary is None:
        if not path.is_file():
            raise FolderError(folder, f"not a wingcrack result (no {SUMMARY})")
        try:
            summary = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError) as err:
            raise FolderError(path, f"not a wingcrack summary (not readable as JSON: {err})") from None
    problem = _summary_problem(summary)
    if problem:
        raise FolderError(path, f"not a wingcrack summary ({problem})")
    steps = summary["steps"]
    fields = [folder / fields_name(s["step"]) for s in steps]
    faces = [folder / faces_name(s["step"]) for s in steps]
    missing = [p for p in fields + faces if not p.is_file()]
    if missing:
        raise FolderError(missing[0], f"missing ({SUMMARY} lists {len(steps)} steps)")
    return StoredResult(folder, summary, fields, faces)


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _summary_problem(s) -> str | None:
    """What makes `s` not a summary of the case contract (None if it is one)."""
    if not isinstance(s, dict):
        return "not a JSON object"
    for key in ("title", "version", "status"):
        if not isinstance(s.get(key), str):
            return f"no '{key}' text"
    if not isinstance(s.get("steps"), list):
        return "no 'steps' list"
    if not isinstance(s.get("fractures"), list):
        return "no 'fractures' list"
    for f in s["fractures"]:
        if not (isinstance(f, dict) and isinstance(f.get("points"), list) and isinstance(f.get("origin"), str)):
            return "a fracture without 'points' and 'origin'"
    for k, st in enumerate(s["steps"]):
        if not isinstance(st, dict) or st.get("step") != k:
            return f"steps[{k}] is not step {k}"
        if not (_number(st.get("load_factor")) and isinstance(st.get("dofs"), int)
                and isinstance(st.get("tips"), list)):
            return f"steps[{k}] lacks 'load_factor', 'dofs' or 'tips'"
        for t in st["tips"]:
            if not (isinstance(t, dict) and all(_number(t.get(q)) for q in ("fracture", "end", "x", "y", "KI", "KII", "theta"))):
                return f"steps[{k}]: a tip without 'fracture', 'end', 'x', 'y', 'KI', 'KII' and 'theta'"
        p = st.get("pressures", [])
        if not (isinstance(p, list) and all(_number(v) and v >= 0 for v in p)):
            return f"steps[{k}].pressures is not a list of fracture pressures (Pa, numbers >= 0)"
    return None
