"""summary.json, written atomically after every step (see the case contract)."""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from .atomic import unwritable, write_atomic

#: where the steps go in the text of the rest of a summary (SummaryWriter): no case text holds NULs
_STEPS_MARK = "\0steps of the summary\0"


def _clean(obj):
    """JSON-safe copy: numpy scalars/arrays to Python; NaN/inf are refused."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        raise ValueError("refusing to write a NaN/inf into summary.json")
    return obj


def write_summary(path: Path, summary: dict) -> None:
    """Write `summary` as JSON to `path` atomically (temporary file + rename)."""
    path = Path(path)
    _folder_of(path)
    write_atomic(path, json.dumps(_clean(summary), indent=1).encode())


def _folder_of(path: Path) -> None:
    """Make the folder of `path` (WriteError naming `path` when it cannot be made)."""
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise unwritable(path, err) from None


class StepTexts:
    """The text of each step record by `encode(record)`, made once per
    record: a committed step's record does not change, and a run rewrites its
    summary and checkpoint after every step, which would otherwise encode
    all the steps again each time (quadratic in the steps)."""

    def __init__(self, encode):
        self._encode = encode
        self._made = {}   # id(record) -> (record, text); the record is held so that its id stays its own

    def __call__(self, records) -> list:
        made, texts = {}, []
        for r in records:
            hit = self._made.get(id(r))
            if hit is None or hit[0] is not r:
                hit = (r, self._encode(r))
            made[id(r)] = hit
            texts.append(hit[1])
        self._made = made
        return texts


class SummaryWriter:
    """summary.json of a run, rewritten after every step at the cost of that
    step: the text is the one write_summary writes for summary.to_dict(),
    each step record's part encoded once (StepTexts)."""

    def __init__(self, path):
        self.path = Path(path)
        # a step is an item of the list "steps" of the top-level object: two levels of indent=1
        self._steps = StepTexts(lambda r: json.dumps(_clean(r.to_dict()), indent=1).replace("\n", "\n  "))

    def write(self, summary) -> None:
        """summary: results.Summary (its steps StepRecord)."""
        head = dataclasses.replace(summary, steps=[]).to_dict()
        head["steps"] = _STEPS_MARK
        texts = self._steps(summary.steps)
        steps = "[\n  " + ",\n  ".join(texts) + "\n ]" if texts else "[]"
        text = json.dumps(_clean(head), indent=1)
        mark = json.dumps(_STEPS_MARK)
        if text.count(mark) != 1:   # the case's own text holds the mark: encoded whole instead
            text = json.dumps(_clean(summary.to_dict()), indent=1)
        else:
            text = text.replace(mark, steps)
        _folder_of(self.path)
        write_atomic(self.path, text.encode())
