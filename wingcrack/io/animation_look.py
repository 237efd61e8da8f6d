"""The settings every frame of a run's growth animation shares (its Look),
from what each step's files bring (StepLook), and the title of a step's
frame (io.animation says how they are chosen and why)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .faces import STATE_NAMES
from .pictures import FACE_BANDS


@dataclass(frozen=True)
class StepLook:
    """What one step's files bring to the run's Look and to its frame's
    title: the 1st and 99.5th percentiles of its positive finite von Mises
    values (None without any: non-finite values are left out; the step
    files of this version hold none, those of earlier ones NaN at the
    crack-tip nodes, which `wingcrack plot` still draws), its mesh's box,
    its fracture lines' box (None without fractures), the face states it
    shows, the face edges per state as the title says them and the highest
    edge pressure (Pa; 0 dry)."""
    low: float | None
    top: float | None
    mesh_box: tuple
    lines_box: tuple | None
    states: tuple
    counts: str
    p_max: float

    @classmethod
    def of(cls, fields, faces) -> StepLook:
        v = fields.von_mises[np.isfinite(fields.von_mises) & (fields.von_mises > 0)]
        low, top = (float(np.percentile(v, 1.0)), float(np.percentile(v, 99.5))) if len(v) else (None, None)
        pts = faces.lines.reshape(-1, 2)
        lines_box = (tuple(pts.min(axis=0)), tuple(pts.max(axis=0))) if len(pts) else None
        states = tuple(s for s in FACE_BANDS if np.any(faces.state == s))
        counts = ", ".join(f"{int(np.sum(faces.state == s))} {STATE_NAMES[s]}" for s in states)
        p = faces.pressure
        return cls(low, top, (tuple(fields.x.min(axis=0)), tuple(fields.x.max(axis=0))), lines_box, states, counts,
                   float(p.max()) if len(p) and p.max() > 0 else 0.0)


@dataclass(frozen=True)
class Reach:
    """How far the fractures can grow in the run: from the first step's
    tips (x, y), `distance` in any direction (m)."""
    tips: tuple
    distance: float

    @classmethod
    def of(cls, propagation: dict | None, first_step: dict | None) -> Reach | None:
        """From summary.json's "propagation" ({"steps", "length"}) and its
        first step record; None without either."""
        if not propagation or first_step is None:
            return None
        return cls(tuple((float(t["x"]), float(t["y"])) for t in first_step["tips"]),
                   float(propagation["steps"]) * float(propagation["length"]))


def reach_of(summary: dict) -> Reach | None:
    steps = summary["steps"]
    return Reach.of(summary.get("propagation"), steps[0] if steps else None)


@dataclass(frozen=True)
class Look:
    """What every frame of a run shares: the colour scale (Pa), the view's
    corners, the top of the pressure scale (Pa; 0: no fluid, no pressure
    bar) and the face states of the legend."""
    vmin: float
    vmax: float
    lo: tuple
    hi: tuple
    p_top: float
    shown: tuple

    @classmethod
    def of(cls, steps: list, reach: Reach | None) -> Look:
        """The Look of a run whose steps so far gave `steps` (StepLook)."""
        vmin, vmax = colour_range(steps)
        lo, hi = view_box(steps, reach)
        shown = tuple(s for s in FACE_BANDS if any(s in step.states for step in steps))
        return cls(vmin, vmax, tuple(map(float, lo)), tuple(map(float, hi)),
                   max((step.p_max for step in steps), default=0.0), shown)


def colour_range(steps: list) -> tuple[float, float]:
    """(vmin, vmax) of the run's logarithmic colour scale (Pa) over its
    steps (StepLook)."""
    seen = [s for s in steps if s.top is not None]
    if not seen:
        return 1.0, 10.0
    top = max(s.top for s in seen)
    return max(min(s.low for s in seen), 1e-4 * top), top


def view_box(steps: list, reach: Reach | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(lower-left, upper-right) corners of the view of a run whose steps
    (StepLook) can reach `reach` (see the module doc; None: the last step's
    fractures)."""
    if reach is None:
        lo_mesh = np.min([s.mesh_box[0] for s in steps], axis=0)
        hi_mesh = np.max([s.mesh_box[1] for s in steps], axis=0)
        boxes = [steps[-1].lines_box]
    else:
        first = steps[0]
        lo_mesh, hi_mesh = np.array(first.mesh_box[0]), np.array(first.mesh_box[1])
        d = reach.distance
        boxes = [first.lines_box] + [((x - d, y - d), (x + d, y + d)) for x, y in reach.tips]
    boxes = [b for b in boxes if b is not None]
    if not boxes:
        return lo_mesh, hi_mesh
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    pad = 0.5 * max(hi - lo) + 1e-12
    return np.maximum(lo - pad, lo_mesh), np.minimum(hi + pad, hi_mesh)


def frame_title(title: str, step: dict, look: StepLook) -> str:
    """The title of a step's frame: the run's title, the step's number and
    load factor (a pumped run: its time), its highest pressure and its face
    edges per state."""
    # with fluid the face counts go to a line of their own: the stress scale would cut a long one
    injection = f"; p max {look.p_max / 1e6:.4g} MPa\n" if look.p_max > 0 else "; "
    # a pumped run's load factor is the network's pressure in Pa: its time says more
    load = f"t = {step['time']:.5g} s" if "time" in step else f"load factor {step['load_factor']:.5g}"
    return (f"{title}\nstep {step['step']}: {load}"
            + (injection + f"face edges {look.counts}" if look.counts else injection.rstrip("; \n")))


def step_files_key(result, k: int) -> tuple:
    """What identifies step k's two files as they are (inode, size,
    modification time): a frame drawn from them holds while it is the same."""
    key = []
    for path in (result.fields[k], result.faces[k]):
        st = Path(path).stat()
        key.append((st.st_ino, st.st_size, st.st_mtime_ns))
    return tuple(key)
