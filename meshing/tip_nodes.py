"""The nodes of each crack tip after the faces are split (TipNodes): the
tip, and the quarter-point and corner node of the spoke on the crack on
each face."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from meshing.plan import Plan
from meshing.records import RawMesh, SplitMesh


@dataclass
class TipNodes:
    """The nodes of one crack tip. `upper` is the face on the +y' side of the
    tip frame (the + face at end 1, the - face at end 0); each face gives
    (quarter-point node, corner node) along the spoke on the crack, at
    distances h/4 and h from the tip."""

    fracture: int
    end: int
    node: int
    x: np.ndarray
    ex: np.ndarray
    ey: np.ndarray
    h: float
    upper: tuple[int, int]
    lower: tuple[int, int]


def tip_nodes(plan: Plan, raw: RawMesh, split: SplitMesh) -> list[TipNodes]:
    out = []
    orig = raw.crack_edges
    for t, tip, corner in zip(plan.tips, raw.tip_node.tolist(), raw.tip_corner.tolist()):
        # the spoke on the crack: the crack edge joining the tip and its corner node
        ends = np.sort(orig[:, :2], axis=1)
        k = int(np.flatnonzero(np.all(ends == sorted((tip, corner)), axis=1))[0])
        plus, minus = (_quarter_and_corner(edges[k], tip) for edges in (split.crack_edges, split.crack_edges_minus))
        ex = -t.back
        out.append(
            TipNodes(
                fracture=t.fracture,
                end=t.end,
                node=int(tip),
                x=split.x[tip].copy(),
                ex=ex,
                ey=np.array([-ex[1], ex[0]]),
                h=float(np.linalg.norm(split.x[plus[1]] - split.x[tip])),
                upper=plus if t.end == 1 else minus,
                lower=minus if t.end == 1 else plus,
            )
        )
    return out


def _quarter_and_corner(edge, tip) -> tuple[int, int]:
    a, b, mid = (int(v) for v in edge)
    return mid, (a if b == tip else b)
