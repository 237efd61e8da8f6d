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

from dataclasses import dataclass, field, replace

import numpy as np

from meshing import admissibility


@dataclass
class GrowingFracture:
    """One fracture of the network. faces, gap, slip, slip_profile, grow,
    friction (Coulomb mu) and cohesion (Pa) are the case fracture's; the
    wings take wing_faces() with the same friction and cohesion.

    pressure: the fluid pressure (Pa, at load factor 1) in the fracture and
    its wings: the case's, raised by FractureSet.connect_pressures once it is
    connected to a fracture with a higher one. joined_to: per end, the index
    of the fracture that end met ("joined": as a T-junction on it, or tip to
    tip with one of its ends), else None."""

    points: np.ndarray
    pre: tuple[int, int]
    ends: list          # [state of end 0, state of end 1]
    faces: str
    gap: float
    slip: float
    slip_profile: str
    grow: bool
    friction: float = 0.0
    cohesion: float = 0.0
    pressure: float = 0.0
    joined_to: list = field(default_factory=lambda: [None, None])

    @property
    def pre_points(self) -> np.ndarray:
        return self.points[self.pre[0]:self.pre[1] + 1]

    def wing_faces(self) -> str:
        """Wings are tensile cracks (paper eq. 8); where the fracture has
        contact, they get non-penetration too, never a prescribed slip: on a
        coulomb fracture with its friction and cohesion (friction acts on
        every face, wings included), frictionless otherwise."""
        if self.faces in ("open", "coulomb"):
            return self.faces
        return "frictionless"

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
            pts = np.asarray(f.points, float).copy()
            ends = ["boundary" if case.domain.on_boundary(p, tol) else "joined" if (i, e) in joined else "tip"
                    for e, p in enumerate((pts[0], pts[-1]))]
            out.append(GrowingFracture(pts, (0, len(pts) - 1), ends, f.faces, f.gap, f.slip,
                                       f.slip_profile, f.grow, f.friction, f.cohesion, f.pressure,
                                       joined_to=[joined.get((i, e)) for e in (0, 1)]))
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
            p = max(self.fractures[i].pressure for i in group)
            for i in group:
                if self.fractures[i].pressure != p:
                    self.fractures[i].pressure = p
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
