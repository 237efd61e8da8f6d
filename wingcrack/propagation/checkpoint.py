"""Checkpoint of a propagation run after every finished step, for
`wingcrack run --resume`.

OUT/checkpoint.npz holds what the next step needs and nothing it can
recompute: the fracture set (polylines, pre-existing range, end states,
the face law by its field names beside them, its fluid pressure the one
after connection, and what each joined end met), the load factor, the
finished steps' records, the error-estimate size field of the next mesh
(so that a resumed run meshes exactly as an uninterrupted one) and, with a
pump, its state (the injected network, the fluid it held without the pump,
the last step's time and pressure: propagation.injection.Pump.to_dict). It is written
atomically (temporary file, fsync, rename): a kill leaves the previous
checkpoint or the new one, never half of one. A fingerprint of the case
(everything but propagation.steps, so a run may also be resumed with more
steps, and the file's path) guards against resuming another case. A
checkpoint of another format VERSION (version 1 held no friction, 2 no
pressure) is refused, naming both versions.
"""
from __future__ import annotations

import dataclasses
import hashlib
import io
import json
import math
from pathlib import Path

import numpy as np

from ..contact.slip_history import SlipHistory
from ..face_law import FaceLaw
from ..io.atomic import write_atomic
from .fracture_set import FractureSet, GrowingFracture

NAME = "checkpoint.npz"
#: 2: the fractures' friction and cohesion; 3: their fluid pressure and joined_to; 4: the case's keys
#: (case_keys), the title out of the fingerprint; 5: the pump's state (and the case's [injection]).
VERSION = 5


def _case_text(case) -> str:
    """The case as JSON without what a resumed run may change: its title,
    propagation.steps and the path it was read from (the same file named
    another way is the same case)."""
    d = dataclasses.asdict(dataclasses.replace(case, title="", source=None,
                                               propagation=dataclasses.replace(case.propagation, steps=0)))
    return json.dumps(d, sort_keys=True, default=_plain)


def fingerprint(case) -> str:
    """sha256 of _case_text(case)."""
    return hashlib.sha256(_case_text(case).encode()).hexdigest()


def case_keys(case) -> dict:
    """{dotted key: value} of _case_text(case): "material.E",
    "fractures[1].friction", ... (lists of records by index, other values whole)."""
    out = {}

    def walk(x, where):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, f"{where}.{k}" if where else str(k))
        elif isinstance(x, list) and x and all(isinstance(v, dict) for v in x):
            for i, v in enumerate(x):
                walk(v, f"{where}[{i}]")
        else:
            out[where] = x

    walk(json.loads(_case_text(case)), "")
    return out


def _differing(theirs: dict, ours: dict) -> str:
    """The keys whose values differ between two case_keys, in words."""
    keys = sorted(set(theirs) | set(ours), key=lambda k: (k not in ours, k))
    diff = [k for k in keys if theirs.get(k, _MISSING) != ours.get(k, _MISSING)]

    def said(v):
        return "absent" if v is _MISSING else json.dumps(v)[:60]

    words = [f"{k} is {said(ours.get(k, _MISSING))} here, {said(theirs.get(k, _MISSING))} there" for k in diff[:3]]
    more = f" (and {len(diff) - 3} more keys)" if len(diff) > 3 else ""
    return "; ".join(words) + more


_MISSING = object()


def _plain(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if hasattr(obj, "__dict__"):
        return {k: v for k, v in vars(obj).items() if not k.startswith("_")}
    return repr(obj)


def save(out, case, k: int, fset: FractureSet, lam: float, steps: list, sizes, history=None, patch=None,
         pump=None) -> None:
    """steps: the finished steps' records (dicts); history: the converged
    slip of the Coulomb faces (SlipHistory, or None); patch: the run's
    propagation.patch.Patch (None: none), so that a resumed run meshes as
    the uninterrupted one; pump: the pump's state (a dict, or None)."""
    _save(out, (fingerprint(case), case_keys(case)), k, fset, lam, steps, None, sizes, history, patch, pump)


class Writer:
    """The checkpoints of one run: save() after every step, at the cost of
    that step (the case's fingerprint once, each step record's text once);
    the file is the one `save` writes."""

    def __init__(self, out, case):
        from ..io.summary import StepTexts

        self.out, self.case = out, (fingerprint(case), case_keys(case))
        self._texts = StepTexts(lambda r: json.dumps(r.to_dict(), default=_plain))

    def save(self, k: int, fset: FractureSet, lam: float, records: list, sizes, history=None, patch=None,
             pump=None) -> None:
        """records: the finished steps (results.StepRecord)."""
        _save(self.out, self.case, k, fset, lam, None, self._texts(records), sizes, history, patch, pump)


#: where the steps' texts go in the meta's text (no case text holds NULs)
_STEPS_MARK = "\0steps of the checkpoint\0"


def _save(out, case_print, k, fset, lam, steps, step_texts, sizes, history, patch=None, pump=None) -> None:
    """case_print: (fingerprint, case_keys) of the case."""
    from ..version import __version__

    meta = {
        "version": VERSION, "case": case_print[0], "case_keys": case_print[1], "wingcrack": __version__,
        "step": k, "load_factor": lam,
        "patch": None if patch is None else patch.to_list(),
        "pump": pump,
        "steps": steps if step_texts is None else _STEPS_MARK,
        "fractures": [{"pre": list(f.pre), "ends": list(f.ends), **f.law.to_dict(), "grow": f.grow,
                       "joined_to": list(f.joined_to)} for f in fset.fractures],
    }
    arrays = {f"points_{i}": f.points for i, f in enumerate(fset.fractures)}
    if sizes is not None:
        arrays["size_triangles"], arrays["size_values"] = sizes
    if history is not None:
        arrays.update(history.to_arrays())
    text = json.dumps(meta, default=_plain)
    if step_texts is not None:   # the same text as json.dumps of the records' dicts in the meta
        mark = json.dumps(_STEPS_MARK)
        if text.count(mark) != 1:
            raise ValueError("a fracture's text holds the checkpoint's steps mark")
        text = text.replace(mark, "[" + ", ".join(step_texts) + "]")
    buf = io.BytesIO()   # built in memory: an interrupt here leaves no file and no open zip on disk
    np.savez(buf, meta=np.array(text), **arrays)
    write_atomic(Path(out) / NAME, buf.getvalue())


def _patch(values):
    """The Patch of a checkpoint's "patch" ([x, y, radius]; absent or null
    in one written without a patch)."""
    if values is None:
        return None
    from .patch import Patch

    v = np.asarray(values, dtype=np.float64)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or not v[2] > 0.0:
        raise ValueError(f"patch is {values!r}, not [x, y, radius > 0]")
    return Patch.from_list(v)


def load(out, case) -> dict:
    """{'step', 'load_factor', 'steps', 'fset', 'sizes', 'history', 'patch', 'pump'} of the checkpoint in
    `out`; ValueError naming the file and the reason when there is none, it
    cannot be read (truncated, empty, not a checkpoint, keys missing) or it
    belongs to another case."""
    path = Path(out) / NAME
    if not path.is_file():
        if path.exists():   # a folder, a FIFO: np.load would block on a FIFO
            raise ValueError(f"{path} is not a regular file: it cannot be a checkpoint; "
                             "start the run again without --resume (with --force)")
        raise ValueError(f"{path} does not exist: nothing to resume (was the run started with this -o?)")
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            points = [np.array(data[f"points_{i}"]) for i in range(len(meta["fractures"]))]
            sizes = (np.array(data["size_triangles"]), np.array(data["size_values"])) \
                if "size_triangles" in data else None
            slip = {name: np.array(data[name]) for name in data.files if name.startswith("slip_")}
            history = SlipHistory.from_arrays(slip) if slip else None
    except Exception as err:  # noqa: BLE001 - a damaged file fails in numpy, zipfile, zlib or json in any way
        raise ValueError(f"{path} cannot be read as a checkpoint ({_reason(err)}); "
                         "start the run again without --resume (with --force)") from None
    if isinstance(meta, dict) and meta.get("version") != VERSION:
        raise ValueError(f"{path} was written by another wingcrack version (checkpoint format "
                         f"{meta.get('version')!r}, this one reads {VERSION}); "
                         "start the run again without --resume (with --force)")
    if not isinstance(meta, dict) or meta.get("case") != fingerprint(case):
        theirs = meta.get("case_keys") if isinstance(meta, dict) else None
        differ = _differing(theirs, case_keys(case)) if isinstance(theirs, dict) else ""
        if differ:
            raise ValueError(f"{path} was written for another case: {differ}; resume with the case it was "
                             "written for, or start the run again without --resume (with --force)")
        from ..version import __version__

        raise ValueError(f"{path} was written by wingcrack {meta.get('wingcrack', '(unknown)')}, which records the "
                         f"case otherwise than this {__version__} (no key of the case differs); start the run "
                         "again without --resume (with --force)")
    try:
        fractures = [GrowingFracture(_points(p), tuple(m["pre"]), list(m["ends"]), law=FaceLaw.from_dict(m),
                                     grow=m["grow"], joined_to=_joined_to(m, len(meta["fractures"])))
                     for p, m in zip(points, meta["fractures"])]
        state = {"step": int(meta["step"]), "load_factor": float(meta["load_factor"]), "steps": list(meta["steps"]),
                 "fset": FractureSet(fractures, FractureSet.case_links(case)), "sizes": sizes, "history": history,
                 "patch": _patch(meta.get("patch")), "pump": _pump(meta.get("pump"), case, len(fractures))}
        _consistent(state)
    except (KeyError, TypeError, ValueError) as err:
        raise ValueError(f"{path} cannot be read as a checkpoint (damaged: {_reason(err)}); "
                         "start the run again without --resume (with --force)") from None
    return state


def _consistent(state) -> None:
    """The records are steps 0 ... step, and the load factor is the last one's
    (finite, >= 0): otherwise a resumed run would repeat or skip steps, or
    start from a factor no step reached."""
    steps, k, lam = state["steps"], state["step"], state["load_factor"]
    for i, rec in enumerate(steps):
        if not isinstance(rec, dict) or rec.get("step") != i:
            raise ValueError(f"steps[{i}] is not the record of step {i}")
    if k != len(steps) - 1:
        raise ValueError(f"the last finished step is {k}, but it holds {len(steps)} step records")
    if not (math.isfinite(lam) and lam >= 0) or lam != steps[-1].get("load_factor"):
        raise ValueError(f"the load factor {lam!r} is not that of step {k}")


def _pump(d, case, n: int):
    """The pump's state (Pump.to_dict) of a pumped case's checkpoint,
    checked: the network a list of fractures holding the injected one, time
    and pressure finite and >= 0, held finite (below 0 where "open" faces,
    which no contact keeps apart, overlap at the initial pressure: the
    balance counts that volume as the run did), closing a number or None;
    None for a case without a pump."""
    if case.injection is None:
        return None
    if not isinstance(d, dict):
        raise ValueError(f"pump {d!r} is no pump's state")
    net = d.get("network")
    if not isinstance(net, list) or case.injection.fracture not in net or \
            not all(isinstance(i, int) and not isinstance(i, bool) and 0 <= i < n for i in net):
        raise ValueError(f"the pump's network {net!r} is not one of these fractures")
    for key in ("time", "pressure"):
        _coefficient(d, key)
    for key, what in (("held", "fluid held"), ("closing", "closing pressure")):
        v = d.get(key)
        if (v is not None or key == "held") and not (isinstance(v, (int, float)) and not isinstance(v, bool)
                                                     and math.isfinite(v)):
            raise ValueError(f"the pump's {what} {v!r} is not a number")
    return d


def _points(p) -> np.ndarray:
    p = np.asarray(p, float)
    if p.ndim != 2 or p.shape[1] != 2 or len(p) < 2 or not np.all(np.isfinite(p)):
        raise ValueError(f"a polyline of shape {p.shape}")
    return p


def _coefficient(m: dict, name: str) -> float:
    """A number of the pump's state: finite and >= 0 (a NaN would pass into
    the balance unseen)."""
    v = m[name]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v >= 0):
        raise ValueError(f"{name} {v!r} is not a finite number >= 0")
    return float(v)


def _joined_to(m: dict, n: int) -> list:
    """A fracture's joined_to: per end None or the index of one of the n
    fractures (a stray index would connect pressures to nothing, or fail
    later far from its cause)."""
    v = m["joined_to"]
    if not isinstance(v, list) or len(v) != 2:
        raise ValueError(f"joined_to {v!r} is not a pair")
    for g in v:
        if g is not None and (isinstance(g, bool) or not isinstance(g, int) or not 0 <= g < n):
            raise ValueError(f"joined_to {v!r} names no fracture of the {n}")
    return list(v)


def _reason(err: BaseException) -> str:
    detail = " ".join(str(err).split())
    return f"{type(err).__name__}: {detail}" if detail else type(err).__name__
