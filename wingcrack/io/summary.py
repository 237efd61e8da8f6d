"""summary.json, written atomically after every step (see the case contract)."""
from __future__ import annotations

import json
import math
from pathlib import Path

from .atomic import write_atomic


def _clean(obj):
    """JSON-safe copy: numpy scalars/arrays to Python; NaN/inf are refused."""
    import numpy as np

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
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, json.dumps(_clean(summary), indent=1).encode())
