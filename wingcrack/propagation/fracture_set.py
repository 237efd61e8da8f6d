"""The evolving fracture network: polylines that grow at their ends.

Each fracture keeps its pre-existing polyline as points[pre[0]:pre[1]+1];
wings are the parts before pre[0] (grown from end 0) and after pre[1]
(grown from end 1). An end's state: "tip" (may grow), "joined" (ended on
another fracture as a T), "boundary" (on the outer boundary: an edge-crack
mouth or a wing that reached it). A joined end records the fracture it
met in `joined_to`; fractures linked that way, and those that cross (the
set's `links`), are hydraulically connected (connect_pressures).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from meshing import admissibility

from ..face_law import FaceLaw


@dataclass
class GrowingFracture:
    """One fracture of the network. law: its face law (wingcrack.face_law;
    the wings take law.wings()), whose pressure is the case's, raised by
    FractureSet.connect_pressures once the fracture is connected to one with
    a higher pressure. grow: whether its tips may grow. joined_to: per end,
    the index of the fracture that end met ("joined": as a T-junction on
    it, or tip to tip with one of its ends), else None."""

    points: np.ndarray
    pre: tuple[int, int]
    ends: list          # [state of end 0, state of end 1]
    law: FaceLaw = FaceLaw()
    grow: bool = True
    joined_to: list = field(default_factory=lambda: [None, None])

    @classmethod
    def of(cls, fracture, ends: list, joined_to: list) -> GrowingFracture:
        """The case's `fracture` (case.Fracture) as it starts to grow: its
        polyline (a copy) all pre-existing, its face law and whether it
        grows."""
        points = np.asarray(fracture.points, float).copy()
        return cls(points, (0, len(points) - 1), ends, law=fracture.law, grow=fracture.grow, joined_to=joined_to)

    def __getattr__(self, name):
        """The face law's fields by their former names (f.pressure is
        f.law.pressure), for code that read them from a run's
        fractures (RunResult.fractures), with a DeprecationWarning."""
        if name in FaceLaw.names():
            warnings.warn(f"GrowingFracture.{name} is deprecated: read GrowingFracture.law.{name}",
                          DeprecationWarning, stacklevel=2)
            return getattr(self.law, name)
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __setattr__(self, name, value):
        if name in FaceLaw.names():   # it would be a second value beside the law's, read by nothing
            raise AttributeError(f"GrowingFracture.{name} is the face law's: set law = "
                                 f"dataclasses.replace(law, {name}=...)")
        super().__setattr__(name, value)

    @property
    def pre_points(self) -> np.ndarray:
        return self.points[self.pre[0]:self.pre[1] + 1]

    def tip(self, end: int) -> np.ndarray:
        return self.points[-1] if end == 1 else self.points[0]

    def extend(self, end: int, p) -> None:
        p = np.asarray(p, float)[None, :]
        if end == 1:
            self.points = np.vstack([self.points, p])
        else:
            self.points = np.vstack([p, self.points])
            self.pre = (self.pre[0] + 1, self.pre[1] + 1)

    def move_tip(self, end: int, p) -> None:
        """Move the tip node (straight growth shorter than L_min)."""
        i = -1 if end == 1 else 0
        self.points = self.points.copy()
        self.points[i] = np.asarray(p, float)

    def pieces(self) -> list:
        """[(points, origin)] for the summary: wing at end 0, the
        pre-existing part, wing at end 1 (wings only if grown)."""
        out = []
        if self.pre[0] > 0:
            out.append((self.points[:self.pre[0] + 1], "wing"))
        out.append((self.pre_points, "pre-existing"))
        if self.pre[1] < len(self.points) - 1:
            out.append((self.points[self.pre[1]:], "wing"))
        return out


@dataclass
class FractureSet:
    """The fractures; links: pairs (i, j) of fractures whose given parts cross
    or touch away from an end (an X, a vertex on the other; crossings(): the
    case's), hydraulically connected as the fractures that joined_to links."""
    fractures: list = field(default_factory=list)
    links: list = field(default_factory=list)

    @classmethod
    def from_case(cls, case) -> "FractureSet":
        """The case's fractures, each end as growth would have left it: on the
        boundary "boundary", on a fracture "joined" (a T-junction, or met end
        to end; joined_to the fracture met: meshing.admissibility.joined_ends,
        the mesher's own reading), else "tip"."""
        tol = 1e-9 * case.length_scale
        net = admissibility.joined(case.domain, [np.asarray(f.points, float) for f in case.fractures])
        joined = net.joined_ends()
        out = []
        for i, f in enumerate(case.fractures):
            pts = np.asarray(f.points, float)
            ends = ["boundary" if case.domain.on_boundary(p, tol) else "joined" if (i, e) in joined else "tip"
                    for e, p in enumerate((pts[0], pts[-1]))]
            out.append(GrowingFracture.of(f, ends, [joined.get((i, e)) for e in (0, 1)]))
        return cls(out, crossings(net))

    @staticmethod
    def case_links(case) -> list:
        """The links of the case's fractures (crossings), as from_case makes them."""
        return crossings(admissibility.joined(case.domain, [np.asarray(f.points, float) for f in case.fractures]))

    def polylines(self) -> list:
        return [f.points for f in self.fractures]

    def active_tips(self) -> list:
        """(fracture, end) of every end that may still grow."""
        return [(i, e) for i, f in enumerate(self.fractures) if f.grow
                for e in (0, 1) if f.ends[e] == "tip"]

    def copy(self) -> "FractureSet":
        return FractureSet([replace(f, points=f.points.copy(), ends=list(f.ends), joined_to=list(f.joined_to))
                            for f in self.fractures], list(self.links))

    def connected_groups(self) -> list:
        """The hydraulically connected groups: sorted lists of fracture
        indices, linked through joined_to in either direction and
        transitively (a fracture on its own is a group of one)."""
        n = len(self.fractures)
        parent = list(range(n))

        def root(i):
            while parent[i] != i:
                parent[i] = parent[parent[i]]
                i = parent[i]
            return i

        for i, f in enumerate(self.fractures):
            for g in f.joined_to:
                if g is not None:
                    parent[root(i)] = root(g)
        for i, g in self.links:
            parent[root(i)] = root(g)
        groups: dict = {}
        for i in range(n):
            groups.setdefault(root(i), []).append(i)
        return sorted(groups.values())

    def connect_pressures(self, exclude=()) -> bool:
        """Every connected group takes the highest pressure among its
        fractures (the injected fluid floods what it reaches; nothing drains
        it), but a group holding a fracture of `exclude` (a pumped network,
        whose pressure is its fluid balance's). Returns whether any pressure
        changed."""
        changed = False
        for group in self.connected_groups():
            if set(group) & set(exclude):
                continue
            p = max(self.fractures[i].law.pressure for i in group)
            for i in group:
                f = self.fractures[i]
                if f.law.pressure != p:
                    f.law = replace(f.law, pressure=p)
                    changed = True
        return changed

    def summary(self) -> list:
        """summary.json's fractures: [{points, origin, fracture}], each case
        fracture's pieces (wing at end 0, pre-existing part, wing at end 1)."""
        return [{"points": np.asarray(p, float).tolist(), "origin": o, "fracture": i}
                for i, f in enumerate(self.fractures) for p, o in f.pieces()]


def crossings(net) -> list:
    """Sorted pairs (i, j), i < j, of the fractures that meet at a point where
    neither has an end (an X; a vertex of one on the other) in the joined
    network `net` (meshing.network.Joined)."""
    out = set()
    for members in net.nodes.values():
        inner = sorted({f for f, v in members if 0 < v < len(net.polylines[f]) - 1})
        for a in range(len(inner)):
            for b in range(a + 1, len(inner)):
                out.add((inner[a], inner[b]))
    return sorted(out)
