"""Issue 12, promise 4: the growth of one step (wingcrack/propagation/growth.py)
on its own, without a solve: a tip that the growth law advances does advance
unless the mesher could not mesh the result, and the rule for Lmax.

References: joining.place_tip (what the step did before: it joins a tip
within 1.5 tip_size of its own polyline, and the tip then does not grow),
and meshing.crack_mesh itself, which refuses a rosette that does not fit."""
import numpy as np
import pytest

from meshing import Domain, admissibility, crack_mesh
from wingcrack.case import Case, CaseError
from wingcrack.propagation import growth
from wingcrack.face_law import FaceLaw
from wingcrack.propagation.fracture_set import FractureSet, GrowingFracture
from wingcrack.propagation.joining import place_tip
from wingcrack.shortest_advance import L_MIN, length_problem

H = 0.1                      # mesh.tip_size
DOMAIN = Domain("rectangle", corner=[-2.0, -2.0], size=[4.0, 4.0])


def fset_of(points):
    pts = np.asarray(points, float)
    return FractureSet([GrowingFracture(pts, (0, 1), ["tip", "tip"], FaceLaw("open"))])


def candidate_at_end_1(fset, theta, K_eq=1.0):
    pts = fset.fractures[0].points
    ex = (pts[-1] - pts[-2]) / np.linalg.norm(pts[-1] - pts[-2])
    return growth.Candidate(0, 0, 1, K_eq, theta, ex, np.array([-ex[1], ex[0]]))


def rule(length):
    return growth.Rule(KIc=1.0, Eprime=1.0, length=length, alpha=0.35, tip_size=H)


def kinked_wing(L1):
    """A pre-existing crack (-1, 0)-(0, 0) and a wing of length L1 from
    (0, 0) kinked 70 degrees down, as after a first step of L1."""
    a = np.radians(-70.0)
    return [[-1.0, 0.0], [0.0, 0.0], [L1 * np.cos(a), L1 * np.sin(a)]]


def test_a_short_step_after_a_kink_grows():
    """The 45-degree disc with length = tip_size / 2 sat at K_eq = 1.11 KIc,
    "arrested", for 66 steps. Why: after the first kinked step of L, the
    next step's end lies about 2 L from the kink point, within the join
    distance 1.5 tip_size of the tip's own pre-existing crack whenever
    L < 0.75 tip_size; place_tip joined it there, and a join onto its own
    fracture is refused, so nothing grew, step after step. Now the tip goes
    straight to its proposed point, which the mesher meshes."""
    L = 0.5 * H
    fs = fset_of(kinked_wing(L))
    c = candidate_at_end_1(fs, theta=np.radians(15.0))
    a = fs.fractures[0].tip(1).copy()
    d = np.cos(c.theta) * c.ex + np.sin(c.theta) * c.ey
    p, state = place_tip(fs.copy(), 0, 1, d, L, DOMAIN, growth.REACH * H)
    assert state == "joined" and growth.on_own_fracture(fs.fractures[0], 1, p)   # the old dead end
    g = growth.grow(fs, [c], 1, rule(L), DOMAIN)
    assert g.grew and g.tips[0].state == "growing"
    assert abs(g.tips[0].advance - L) < 1e-8 * L          # the law's L (rounded to its 1e-8 grid)
    new = fs.fractures[0].points
    assert len(new) == 4 and np.allclose(new[-1], a + L * d, atol=1e-9 * L)
    crack_mesh(DOMAIN, [new], [], size=0.5, tip_size=H)   # the mesher takes it


@pytest.mark.parametrize("turn, L", [(70.0, 0.5 * H), (70.0, H), (60.0, 0.45 * H)])
def test_a_tip_curling_back_onto_its_own_crack_does_not_grow(turn, L):
    """A wing that turned back towards its own crack: the next step would
    end too close to it for a rosette (or cross it). The tip stays, and the
    mesher confirms that the step could not have been meshed."""
    pts = np.array([[-1.0, 0.0], [0.0, 0.0], [0.0, 0.06], [-0.06, 0.06]])   # up, then back to the left
    fs = fset_of(pts)
    c = candidate_at_end_1(fs, theta=np.radians(turn))      # turning further, down towards y = 0
    g = growth.grow(fs, [c], 1, rule(L), DOMAIN)
    assert not g.grew and g.tips[0].why == growth.FOLDS_BACK
    assert np.array_equal(fs.fractures[0].points, pts)
    d = np.cos(c.theta) * c.ex + np.sin(c.theta) * c.ey
    if not growth.crossing_pair([pts, np.array([pts[-1], pts[-1] + L * d])]):
        with pytest.raises(ValueError, match="reaches"):
            crack_mesh(DOMAIN, [np.vstack([pts, pts[-1] + L * d])], [], size=0.5, tip_size=H)


@pytest.mark.parametrize("clearance", [1.4, 1.6])
def test_the_room_for_a_rosette_is_the_meshers(clearance):
    """clear_of_own_fracture accepts a point exactly when crack_mesh can put
    a rosette there: a new tip `clearance` rosette radii (0.75 L) from its
    own crack, beyond the join distance, straight above it."""
    L = 0.5 * H
    r = admissibility.ROSETTE_IN_SEGMENT * L
    y = clearance * r
    pts = np.array([[-1.0, 0.0], [0.0, 0.0], [0.0, y - L]])   # straight up, the new point L further
    fs = fset_of(pts)
    p = np.array([0.0, y])
    new = np.vstack([pts, p])
    ok = growth.clear_of_own_fracture(fs, 0, 1, new, rule(L), DOMAIN)
    assert ok == (clearance > admissibility.TIP_CLEARANCE)
    if ok:
        crack_mesh(DOMAIN, [new], [], size=0.5, tip_size=H)
    else:
        with pytest.raises(ValueError, match="reaches"):
            crack_mesh(DOMAIN, [new], [], size=0.5, tip_size=H)


def test_why_no_tip_grew():
    """Below KIc, or an advance under L_min: said in the run's status."""
    fs = fset_of(kinked_wing(H))
    c = candidate_at_end_1(fs, theta=0.3, K_eq=0.5)
    g = growth.grow(fs, [c], 1, rule(H), DOMAIN)
    assert not g.grew and g.why_none() == growth.BELOW_KIC
    g = growth.grow(fs, [candidate_at_end_1(fs, theta=0.3)], 1, rule(0.3 * H), DOMAIN)
    assert not g.grew and g.why_none() == growth.UNDER_L_MIN


def test_length_under_l_min_is_refused_up_front(tmp_path):
    """propagation.length < L_min = 0.4 tip_size cannot work (a kinked tip
    never advances less than L_min): refused naming the key; L_min itself
    works."""
    assert length_problem(L_MIN * H, H) is None and length_problem(H, H) is None
    assert length_problem(0.02, 0.05) is None     # 0.4 * 0.05 is 0.020000000000000004: round-off is no reason
    assert "L_min" in length_problem(0.39 * H, H)
    d = {"title": "t", "material": {"E": 1e10, "nu": 0.25, "KIc": 1e6},
         "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
         "fractures": [{"points": [[-0.1, -0.1], [0.1, 0.1]]}],
         "bc": [{"on": "top", "traction": [0.0, 1e6]}, {"on": "bottom", "traction": [0.0, -1e6]},
                {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [1.0, 0.0], "displacement_y": 0.0}],
         "mesh": {"size": 0.2, "tip_size": 0.02}, "propagation": {"steps": 3, "length": 0.005}}
    with pytest.raises(CaseError, match=r"^propagation\.length: .*under L_min") as err:
        Case.from_dict(d)
    assert "0.008" in str(err.value)   # the smallest length that works
    d["propagation"]["length"] = 0.008
    assert Case.from_dict(d).propagation.length == 0.008


def test_length_beyond_the_domain_is_refused():
    """A step longer than the domain cannot happen (the tip reaches the
    boundary first), and 1e300 m overflowed the geometry: the reader's
    limit (at most L, the domain's length scale) refuses it naming the key."""
    d = {"title": "t", "material": {"E": 1e10, "nu": 0.25, "KIc": 1e6},
         "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
         "fractures": [{"points": [[-0.1, -0.1], [0.1, 0.1]]}],
         "bc": [{"on": "top", "traction": [0.0, 1e6]}, {"on": "bottom", "traction": [0.0, -1e6]},
                {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [1.0, 0.0], "displacement_y": 0.0}],
         "mesh": {"size": 0.2, "tip_size": 0.02}, "propagation": {"steps": 3, "length": 1e300}}
    with pytest.raises(CaseError, match=r"^propagation\.length: .*at most"):
        Case.from_dict(d)
    L = float(Case.from_dict({**d, "propagation": {"steps": 3}}).domain.length_scale())
    d["propagation"]["length"] = L
    assert Case.from_dict(d).propagation.length == L
