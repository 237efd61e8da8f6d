"""The terms of the geometric rules (meshing.admissibility and its junction
rules): the tolerances and clearances they measure against, each with the
measurement behind it, and the Problem a rule answers with (the key in the
case file's terms and the reason), which the case check raises as a
CaseError and the mesher as Inadmissible."""
from __future__ import annotations

from dataclasses import dataclass

#: Relative tolerance (times the domain's length scale) for "on the
#: boundary", "touching" and "zero length".
REL_TOL = 1e-9
#: The domain sizes (m across) the mesher and solver take. The mesher hands
#: gmsh the geometry in a frame where the domain is 1e-3 to 1e3 units across
#: (frame.Frame): gmsh alone fails to recover edges ("Unable to
#: recover the edge", then aborts) at 6e-9 m and below.
LENGTH_RANGE = (1e-9, 1e9)
#: Coordinates at most this many domain sizes from the origin: beyond it the
#: rounding of a coordinate (|x| 2.2e-16) nears the geometric tolerance REL_TOL.
#: (gmsh itself sees the domain near its origin: frame.Frame.)
MAX_OFFSET = 1e6
#: mesh.tip_size at least this fraction of the domain size: a smaller rosette
#: lies within 1000 geometric tolerances of its tip.
MIN_TIP_FRACTION = 1e3 * REL_TOL

#: The room, in rosette radii, between a rosette disc and anything else (the
#: boundary, another fracture, a non-adjacent segment of its own, another
#: rosette). Measured: a tip 1.0 h from the boundary or another fracture
#: gives an inverted cell, 1.001 h quality 0.009, 1.01 h 0.09, 1.05 h the
#: rosette's own 0.33; two rosettes (of two fractures, or the two tips of
#: one short fracture) 2.0 h apart: gmsh aborts or an inverted cell, 2.01 h
#: quality 0.09, 2.05 h 0.33. Half a rosette leaves a graded layer of
#: triangles there, and is the join distance of growth (joining.py): a tip
#: that comes this close to something joins it.
GAP = 0.5
#: A tip's distance to the boundary, to other fractures and to the
#: non-adjacent segments of its own, in rosette radii.
TIP_CLEARANCE = 1.0 + GAP
#: A tip's distance to the segment before its own (they share the kink point,
#: so the disc need only stay off it). Measured: 1.0 h quality 0.016, 1.02 h
#: 0.23, 1.05 h 0.33; 0.5 h (a wing folding back onto its crack) invalid.
NEIGHBOUR_CLEARANCE = 1.05
#: A tip's rosette radius is at most this fraction of its last segment.
ROSETTE_IN_SEGMENT = 0.75
#: ... and at least this fraction of tip_size (else the segment is too short).
MIN_ROSETTE = 0.1
#: Points of the boundary that become mesh nodes (bc points, crack mouths,
#: corners) coincide (within REL_TOL) or are at least this many tip sizes
#: apart. Measured: a pin 1e-7 m from another (tip_size 0.02) makes a
#: boundary triangle of quality 2e-6 and MUMPS a null pivot; quality grows
#: as distance / size (0.1 at 0.005 m). tip_size is the finest element the
#: mesher makes anywhere else.
ANCHOR_GAP = 1.0
#: The least angle (degrees) between two fractures where they meet (an X, a
#: T, ends met end to end): every sector between two neighbouring fracture
#: rays at a junction is at least this wide. The worst cell of a sector of
#: angle a is the isosceles triangle at its apex, of quality
#: sqrt(3) sin a / (1 + 2 sin^2(a/2)); measured (an X, a T and a V at the
#: mesher's defaults): 20 deg 0.51, 15 deg 0.42, 10 deg 0.30, 5 deg 0.15,
#: 1 deg 0.03, 0.1 deg 0.003. 15 degrees keeps the sector's cells above
#: the rosette's own (0.33 at the default 32 sectors).
MIN_JUNCTION_ANGLE = 15.0
#: Points where fractures meet (junctions) coincide (REL_TOL) or keep this
#: many tip sizes from each other, from the boundary, from the vertices next
#: to them along the fractures through them and from the fractures not
#: through them (tip_size is the finest element the mesher makes away from
#: the rosettes). Measured: the worst cell's quality falls as distance /
#: tip_size below half a tip size (two X's 0.3 tip sizes apart 0.26, an X
#: 0.1 tip sizes from the boundary 0.08, 0.01 from a third fracture 0.005);
#: from 1 tip size on it is that of the mesh away from junctions (0.60 to
#: 0.72). The value of ANCHOR_GAP, for the same reason.
JUNCTION_GAP = 1.0
#: A fracture end that is no junction keeps at least this many tip sizes
#: from every fracture it does not lie on (to REL_TOL): an end nearer reads
#: as a junction missed by a little and is refused as such (a tip there
#: would be refused anyway: its rosette keeps TIP_CLEARANCE radii from
#: every other fracture).
NEAR_MISS = 0.1


@dataclass(frozen=True)
class Problem:
    """Why a geometry cannot be meshed: the key it is about (``mesh.tip_size``,
    ``fractures[1].points``, ``bc[3].at``) and the reason."""

    key: str
    message: str

    def __str__(self) -> str:
        return f"{self.key}: {self.message}"


class Inadmissible(ValueError):
    """The mesher's refusal of a geometry that breaks a rule of this module."""

    def __init__(self, problem: Problem):
        super().__init__(str(problem))
        self.problem = problem


def require(problem: Problem | None) -> None:
    """Raise Inadmissible for a problem; nothing for None."""
    if problem is not None:
        raise Inadmissible(problem)


def fracture_key(f: int) -> str:
    return f"fractures[{f}].points"


def short_of(d: float, need: float, digits: int) -> str:
    """d (< need, or <= need) with `digits` digits, or as many more as it takes
    not to read as `need` or beyond ("is 0.0005 m from ..., at least 0.0005 m")."""
    text = f"{d:.{digits}g}"
    while float(text) >= need and d < need and digits < 17:
        digits += 1
        text = f"{d:.{digits}g}"
    return text
