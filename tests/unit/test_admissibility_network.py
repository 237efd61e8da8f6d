"""The rules for pre-existing fractures that meet (meshing/admissibility.py:
fractures_meet, ends_on_or_apart, junctions_apart), shared by `wingcrack
check` and the mesher, and what the case and the run make of a network.

References: each rule's threshold, on both sides of it (1e-3 above:
accepted and meshed, the worst cell the rosette's own sector, whose quality
is known in closed form; 1e-3 below: refused, naming the key); the node
copies and tips the mesher makes (test_meshing_network.py counts them);
the ends growth would have left (a T end "joined" to its host, a mouth
"boundary").
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import wingcrack
from meshing import Domain, admissibility, crack_mesh
from meshing.admissibility import Inadmissible
from wingcrack.errors import CaseError
from wingcrack.propagation.fracture_set import FractureSet
from wingcrack.propagation.growth import crossing_pair

from admissibility_cases import H, THRESHOLD, Y0, base, family
from test_admissibility import mesh_of, refusal, sector_quality

JUNCTION_FAMILIES = ["X", "T_angle", "star", "through", "XX", "T_kink", "T_mouth"]


@pytest.mark.parametrize("name", JUNCTION_FAMILIES)
def test_on_either_side_of_a_junction_rule(name):
    """1e-3 above the threshold (15 degrees between rays, 1 tip_size
    between a junction and the next point, the boundary, another junction):
    accepted, meshed, and the worst cell is the rosette's own sector (the
    junction's cells are better); 1e-3 below: refused with the fracture's key."""
    k = THRESHOLD[name]
    case = wingcrack.Case.from_dict(family(name, k * (1 + 1e-3)))
    mesh = mesh_of(case)
    assert mesh.stats["min_quality"] == pytest.approx(sector_quality(32), rel=1e-3)
    assert len(mesh.tips) == len(case.tips())
    err = refusal(family(name, k * (1 - 1e-3)))
    assert err.key.startswith("fractures[")
    assert ("degrees or more" if THRESHOLD[name] == admissibility.MIN_JUNCTION_ANGLE else "1 tip_size") in err.reason


def test_junction_angles_below_the_rule_are_slivers():
    """The rule's reason, measured: an X at 10 degrees (accepted by the
    mesher, which applies only what it must) has a cell of the wedge's
    closed-form quality sqrt(3) sin a / (1 + 2 sin^2(a/2)), below the
    rosette's own; at 15.015 degrees its cells are above that."""
    def wedge(a):
        a = math.radians(a)
        return math.sqrt(3) * math.sin(a) / (1 + 2 * math.sin(a / 2) ** 2)

    d = family("X", 10.0)
    mesh = crack_mesh(Domain("rectangle", corner=[-1, -1], size=[2, 2]),
                      [np.asarray(f["points"]) for f in d["fractures"]], [np.array([-1.0, 0.0]), np.array([1.0, 0.0])],
                      0.2, H, sectors=32, timeout=60.0)
    assert mesh.stats["min_quality"] == pytest.approx(wedge(10.0), rel=0.02)   # 0.296 measured, 0.2962 exact
    assert wedge(10.0) < sector_quality(32) < wedge(15.0)


@pytest.mark.parametrize("name, fractures, tips", [
    ("end to end", [[(-0.3, Y0), (0.0, Y0)], [(0.0, Y0), (0.2, 0.2)]], 2),
    ("T", [[(-0.3, Y0), (0.3, Y0)], [(0.05, 0.3), (0.05, Y0)]], 3),
    ("X", [[(-0.3, Y0), (0.3, Y0)], [(-0.1, -0.3), (0.1, 0.3)]], 4),
    ("T on an X", [[(-0.3, Y0), (0.3, Y0)], [(0.0, -0.3), (0.0, 0.3)], [(0.25, 0.3), (0.0, Y0)]], 5),
    ("triangle", [[(-0.2, -0.1), (0.2, -0.1)], [(0.2, -0.1), (0.0, 0.25)], [(0.0, 0.25), (-0.2, -0.1)]], 0),
    ("ring", [[(-0.2, -0.1), (0.2, -0.1), (0.0, 0.25), (-0.2, -0.1)]], 0),
    ("X on a kink", [[(-0.3, Y0), (0.0, Y0), (0.3, 0.1)], [(0.0, -0.25), (0.0, 0.25)]], 4),
    ("edge crack crossed", [[(-1.0, 0.3), (-0.4, 0.3)], [(-0.7, 0.0), (-0.6, 0.6)]], 3),
    ("boundary to boundary", [[(-1.0, 0.5), (1.0, 0.4)], [(0.0, 0.2), (0.1, 0.7)]], 2),
])
def test_networks_check_accepts(name, fractures, tips):
    """What users' networks hold: check accepts it, its tips are the free
    ends, and the mesher meshes it with as many tips."""
    case = wingcrack.Case.from_dict(base(fractures))
    assert len(case.tips()) == tips
    mesh = mesh_of(case)
    assert len(mesh.tips) == tips and mesh.stats["min_jacobian"] > 0


@pytest.mark.parametrize("fractures, key, reason", [
    ([[(-0.3, Y0), (0.3, Y0)], [(0.1, Y0), (0.5, Y0)]], "fractures[1].points",
     "runs along fractures[0] from (0.1, 0.013) to (0.3, 0.013)"),
    ([[(-0.3, Y0), (0.3, Y0)], [(-0.3, Y0), (0.3, Y0)][::-1]], "fractures[1].points", "runs along fractures[0]"),
    ([[(-0.3, Y0), (0.3, Y0)], [(0.05, 0.3), (0.05, Y0 + 1e-5)]], "fractures[1].points[1]",
     "1e-05 m from fractures[0]: an end on a fracture lies on it"),
    ([[(-1.0, 0.3), (-0.5, 0.3)], [(-1.0, 0.3), (-0.7, 0.6)]], "fractures[1].points[0]",
     "on the boundary lies on fractures[0]"),
    ([[(-1.0, 0.3), (-0.5, 0.3)], [(-0.9, 0.0), (-1.0, 0.3)]], "fractures[1].points[1]",
     "on the boundary lies on fractures[0]"),
    ([[(-0.2, -0.1), (0.2, -0.1), (0.0, 0.25), (0.1, -0.1)]], "fractures[0].points", "intersects itself"),
    ([[(-0.3, Y0), (0.3, Y0)], [(-0.4, Y0 - 0.4 * math.tan(math.radians(14.9))),
                                (0.4, Y0 + 0.4 * math.tan(math.radians(14.9)))]],
     "fractures[1].points", "at 14.9 degrees"),
])
def test_what_no_mesh_holds_is_refused(fractures, key, reason):
    """A common stretch, an end a hair off a fracture, a meeting on the
    boundary, a ring that crosses itself, a flat crossing: one message
    naming the key, through the check; the common stretch and the meeting
    on the boundary also through the mesher (which cannot mesh them)."""
    d = base(fractures)
    err = refusal(d)
    assert err.key == key and reason in err.reason, (err.key, err.reason)
    if "runs along" in reason or "on the boundary" in reason:
        with pytest.raises(Inadmissible, match="runs along|on the boundary"):
            crack_mesh(Domain("rectangle", corner=[-1, -1], size=[2, 2]), [np.asarray(f, float) for f in fractures],
                       [], 0.2, H)


def test_a_junction_near_a_fracture_not_through_it():
    """An X 0.5 tip sizes from a third fracture (a V in one of its sectors,
    its apex nearest): refused, named; 1.01 tip sizes: accepted."""
    x = np.array([0.0, Y0])
    b = math.atan2(0.6, 0.2)   # the second fracture's direction

    def network(gap):
        def ray(a, r):
            return x + r * np.array([math.cos(a), math.sin(a)])
        return base([[(-0.3, Y0), (0.3, Y0)], [(-0.1, Y0 - 0.3), (0.1, Y0 + 0.3)],
                     [ray(math.radians(10), 0.3), ray(b / 2, gap * H), ray(b - math.radians(10), 0.3)]])

    err = refusal(network(0.5))
    assert err.key == "fractures[1].points" and "0.01 m from fractures[2] without it" in err.reason, err
    wingcrack.Case.from_dict(network(1.01))


def test_the_run_starts_with_junction_ends_joined():
    """FractureSet.from_case: an end on a fracture is "joined" (joined_to
    the fracture it lies on; ends met end to end each to the other), a mouth
    "boundary", the rest "tip"; so the run grows from the free ends only."""
    case = wingcrack.Case.from_dict(base([
        [(-1.0, 0.3), (-0.4, 0.3)],               # 0: edge crack
        [(-0.7, 0.6), (-0.7, 0.3)],               # 1: T onto 0
        [(0.0, Y0), (0.3, 0.2)], [(0.3, 0.2), (0.6, Y0)],   # 2, 3: end to end
        [(0.0, -0.4), (0.3, -0.1)], [(0.3, -0.4), (0.0, -0.1)],   # 4, 5: an X
    ]))
    fset = FractureSet.from_case(case)
    assert [f.ends for f in fset.fractures] == [["boundary", "tip"], ["tip", "joined"], ["tip", "joined"],
                                                ["joined", "tip"], ["tip", "tip"], ["tip", "tip"]]
    assert [f.joined_to for f in fset.fractures] == [[None, None], [None, 0], [None, 3], [2, None],
                                                     [None, None], [None, None]]
    assert sorted(fset.active_tips()) == sorted((t.fracture, t.end) for t in case.tips())
    # the X is no crossing growth made: the run's check lets it be, and finds one a wing makes
    assert crossing_pair(fset.polylines(), [f.pre for f in fset.fractures]) is None
    assert crossing_pair(fset.polylines()) == (4, 5)
    grown = fset.copy()
    grown.fractures[1].extend(0, [-0.5, 0.2])    # a wing from end 0 across fracture 0
    assert crossing_pair(grown.polylines(), [f.pre for f in grown.fractures]) == (0, 1)


def test_the_mesher_refuses_what_it_cannot_mesh_with_the_checks_words():
    """The mesher applies joins() itself: a common stretch given straight to
    crack_mesh is refused with the text the check gives."""
    fractures = [[(-0.3, Y0), (0.3, Y0)], [(0.1, Y0), (0.5, Y0)]]
    err = refusal(base(fractures))
    with pytest.raises(Inadmissible) as info:
        crack_mesh(Domain("rectangle", corner=[-1, -1], size=[2, 2]), [np.asarray(f, float) for f in fractures],
                   [], 0.2, H)
    assert str(info.value) == f"{err.key}: {err.reason}"


def test_two_slip_fractures_may_not_meet():
    d = base([[(-0.3, Y0), (0.3, Y0)], [(-0.1, -0.3), (0.1, 0.3)]])
    for f in d["fractures"]:
        f.update(faces="slip", slip=1e-4)
    with pytest.raises(CaseError, match=r'fractures\[1\].faces: "slip" fractures\[1\] meets "slip" fractures\[0\]'):
        wingcrack.Case.from_dict(d)
    d["fractures"][1]["faces"] = "frictionless"
    d["fractures"][1].pop("slip")
    wingcrack.Case.from_dict(d)


def test_crossing_fractures_share_their_pressure():
    """Fractures that cross are connected as joined ones are
    (propagation.connect_pressure): the X's two take the higher pressure; a
    fracture apart keeps its own. A checkpoint's set gets the same links."""
    d = base([[(-0.3, Y0), (0.3, Y0)], [(-0.1, -0.3), (0.1, 0.3)], [(0.5, 0.5), (0.7, 0.6)]])
    d["fractures"][1]["pressure"] = 2e5
    d["fractures"][2]["pressure"] = 1e5
    case = wingcrack.Case.from_dict(d)
    fset = FractureSet.from_case(case)
    assert fset.links == [(0, 1)] == FractureSet.case_links(case) and fset.copy().links == [(0, 1)]
    assert fset.connected_groups() == [[0, 1], [2]]
    assert fset.connect_pressures()
    assert [f.law.pressure for f in fset.fractures] == [2e5, 2e5, 1e5]
