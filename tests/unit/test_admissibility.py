"""The mesher's rules (meshing/admissibility.py), shared by `wingcrack check`,
the mesher, meshing.Domain and the growth of tips, and the promises of
issue 12 that come from geometry.

References: the mesher itself. At a threshold's 1e-3 the check refuses and
the mesher refuses with the same words; just above it the mesh's worst
triangle is a rosette sector, whose quality is known in closed form; with
the rule switched off, at the geometry the rule exists for, the mesher
breaks (the measurements behind the thresholds, in admissibility.py).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import wingcrack
from meshing import Domain, admissibility, crack_mesh
from meshing.admissibility import Inadmissible
from wingcrack import cli
from wingcrack.errors import CaseError

from admissibility_cases import H, THRESHOLD, base, family, place, to_toml


def sector_quality(sectors: int) -> float:
    """triangle_quality of a rosette sector (sides h, h and the chord): sqrt(3) sin a / (1 + 2 sin^2(a/2))."""
    a = 2 * math.pi / sectors
    return math.sqrt(3) * math.sin(a) / (1 + 2 * math.sin(a / 2) ** 2)


def mesh_of(case: wingcrack.Case, **kw):
    return crack_mesh(case.domain, case.fracture_points(), case.bc_points(), case.mesh.size, case.mesh.tip_size,
                      sectors=case.mesh.sectors, timeout=60.0, **kw)


def crossing(a, b) -> bool:
    """Do two polylines cross (meet inside both segments, not at an end)?"""
    import wingcrack_kernels as K

    for s in range(len(a) - 1):
        for r in range(len(b) - 1):
            hit, t, u, _ = K.segment_intersection(a[s], a[s + 1], b[r], b[r + 1], 1e-12)
            if hit and 1e-9 < t < 1 - 1e-9 and 1e-9 < u < 1 - 1e-9:
                return True
    return False


def refusal(d: dict) -> CaseError:
    with pytest.raises(CaseError) as info:
        wingcrack.Case.from_dict(d)
    return info.value


ROSETTE_FAMILIES = ["boundary", "corner", "T", "tiptip", "short", "kink", "uturn", "sidebyside"]


@pytest.mark.parametrize("name", ROSETTE_FAMILIES)
def test_on_either_side_of_a_rosette_rule_check_and_mesher_agree(name):
    """1e-3 above the threshold: accepted, and the worst triangle of the mesh
    is a rosette sector (nothing squeezed; 1e-3 of it: the graded layers are
    better). 1e-3 below: refused by the check, and by the mesher with the
    same text."""
    k = THRESHOLD[name]
    case = wingcrack.Case.from_dict(family(name, k * (1 + 1e-3)))
    mesh = mesh_of(case)
    assert mesh.stats["min_quality"] == pytest.approx(sector_quality(32), rel=1e-3)

    d = family(name, k * (1 - 1e-3))
    err = refusal(d)
    assert err.key == "mesh.tip_size"
    raw = base([f["points"] for f in d["fractures"]])
    with pytest.raises(Inadmissible) as info:
        crack_mesh(Domain("rectangle", corner=[-1, -1], size=[2, 2]), [np.asarray(f["points"]) for f in raw["fractures"]],
                   [np.array([-1.0, 0.0]), np.array([1.0, 0.0])], 0.2, H, sectors=32)
    assert str(info.value) == f"{err.key}: {err.reason}"


@pytest.mark.parametrize("name, k", [("boundary", 1.0), ("T", 1.0), ("tiptip", 2.0), ("short", 2.0),
                                     ("kink", 0.5), ("doubleback", 0.5)])
def test_without_the_rule_the_mesher_breaks(monkeypatch, name, k):
    """The geometry each rule is for: with admissibility.rosettes switched
    off the mesh is invalid (an inverted cell, faces that do not split) or
    gmsh aborts (its worker dies)."""
    monkeypatch.setattr(admissibility, "rosettes", lambda *a, **kw: None)
    d = family(name, k)
    with pytest.raises((RuntimeError, ValueError)):
        crack_mesh(Domain("rectangle", corner=[-1, -1], size=[2, 2]), [np.asarray(f["points"]) for f in d["fractures"]],
                   [np.array([-1.0, 0.0]), np.array([1.0, 0.0])], 0.2, H, sectors=32, timeout=60.0)


# ---------------------------------------------------------------- issue 12, one by one


def run_cli(argv, capfd):
    rc = cli.main(argv)
    out, err = capfd.readouterr()
    return rc, out, err


def write(tmp_path, d: dict, name="case.toml"):
    path = tmp_path / name
    path.write_text(to_toml(d))
    return path


@pytest.mark.parametrize("command", ["sif", "crosscheck"])
def test_overlapping_rosettes_are_refused_not_a_gmsh_abort(tmp_path, capfd, command):
    """A fracture 0.021 long with tip_size 0.02 made gmsh abort (exit 134):
    its two rosettes (radius 0.75 x 0.021) overlap."""
    path = write(tmp_path, base([[(0.0, 0.013), (0.021, 0.013)]]))
    out = tmp_path / "out"
    rc, _, err = run_cli([command, str(path), "-o", str(out)] if command == "sif" else [command, str(path)], capfd)
    assert rc == 2, err
    assert err.startswith("wingcrack: error: mesh.tip_size: the rosettes of fractures[0] end 0 and fractures[0] end 1")
    assert "overlap" in err and "Traceback" not in err
    assert not out.exists()


def test_a_domain_2e_9_m_across_is_computed(tmp_path, capfd):
    """The base case scaled to 2e-9 m across (gmsh alone aborts: it cannot
    recover edges that small). KI scales as sqrt(length): against the base
    case, 1e-4 (the two meshes differ only by the rounding of the scaled
    input: measured 2e-6)."""
    s = 1e-9
    K0 = np.array([[t.KI, t.KII] for t in wingcrack.sif(wingcrack.Case.from_dict(base())).tips])
    K = np.array([[t.KI, t.KII] for t in wingcrack.sif(wingcrack.Case.from_dict(place(base(), scale=s))).tips])
    np.testing.assert_allclose(K / math.sqrt(s), K0, rtol=1e-4)
    rc, out, err = run_cli(["crosscheck", str(write(tmp_path, place(base(), scale=s)))], capfd)
    assert rc == 0, err
    assert "agrees" in out


def test_a_domain_far_from_the_origin_is_computed():
    """1e5 domain sizes from the origin: the point-symmetric mesh's divider
    no longer mirrored ("unexpected RuntimeError"). The SIFs are the base
    case's to 1e-4 (the coordinates are rounded at 1e-16 of 5.7e5 m: measured 5e-6)."""
    K0 = np.array([[t.KI, t.KII] for t in wingcrack.sif(wingcrack.Case.from_dict(base())).tips])
    r = wingcrack.sif(wingcrack.Case.from_dict(place(base(), offset=1e5)))
    assert r.mesh.stats["symmetric"]
    np.testing.assert_allclose(np.array([[t.KI, t.KII] for t in r.tips]), K0, rtol=1e-4)


def test_gmsh_meshes_a_scaled_geometry_exactly_as_the_original():
    """The mesher's frame: a power-of-two scale is exact, so gmsh sees the
    original's input bit for bit and the mesh is the original's, scaled."""
    s = 2.0**-40
    a = mesh_of(wingcrack.Case.from_dict(base()))
    pts = [f.points * s for f in wingcrack.Case.from_dict(base()).fractures]
    b = crack_mesh(Domain("rectangle", corner=[-s, -s], size=[2 * s, 2 * s]), pts,
                   [np.array([-s, 0.0]), np.array([s, 0.0])], 0.2 * s, H * s, sectors=32, timeout=60.0)
    np.testing.assert_array_equal(b.cells, a.cells)
    np.testing.assert_array_equal(b.x, a.x * s)
    assert [t.h for t in b.tips] == [t.h * s for t in a.tips]


def test_a_tip_a_hair_off_the_rosette_clearance_is_refused(tmp_path, capfd):
    """A tip 1.000001 tip_size from the boundary: check accepted, the mesher
    (which asks 1.5) refused ("unexpected ValueError")."""
    path = write(tmp_path, base([[(0.5, 0.013), (1 - 1.000001 * H, 0.013)]]))
    rc, _, err = run_cli(["sif", str(path), "-o", str(tmp_path / "out")], capfd)
    assert rc == 2
    assert err.startswith("wingcrack: error: mesh.tip_size: the rosette of fractures[0] end 1 (radius 0.02) "
                          "reaches the boundary")


def test_a_polyline_doubling_back_onto_itself_is_refused():
    err = refusal(base([[(-0.1, 0.0), (0.1, 0.0), (-0.05, 1e-4)]]))
    assert err.key == "mesh.tip_size" and "reaches segment 0 of its own fracture" in err.reason


def test_collinear_tips_whose_rosettes_overlap_are_refused():
    """2.01 tip sizes apart: `sif` solved, `run` failed with "fractures 0 and 1 cross"."""
    gap = 2.01 * H
    err = refusal(base([[(-0.2, 0.0), (-gap / 2, 0.0)], [(gap / 2, 0.0), (0.2, 0.0)]]))
    assert err.key == "mesh.tip_size" and "overlap" in err.reason


def test_collinear_tips_that_meet_in_one_step_link_end_to_end():
    """3 tip sizes apart and a step of 2: the first tip reaches the second and
    they link end to end; the second, joined by then, must not grow over
    the first (that was "fractures 0 and 1 cross")."""
    gap = 3 * H
    d = base([[(-0.2, 0.0), (-gap / 2, 0.0)], [(gap / 2, 0.0), (0.2, 0.0)]])
    d["propagation"] = {"steps": 2, "length": 2 * H}
    r = wingcrack.run(wingcrack.Case.from_dict(d), plots=False)
    assert r.status.startswith(("finished", "stopped")), r.status
    f0, f1 = r.fractures.fractures
    assert f0.ends[1] == "joined" and f1.ends[0] == "joined"
    np.testing.assert_array_equal(f0.points[-1], f1.points[0])   # the same point, bit for bit
    np.testing.assert_array_equal(f1.points[0], [gap / 2, 0.0])   # the joined end did not grow
    assert not crossing(*r.polylines)


def test_a_second_pin_a_hair_from_the_first_is_refused():
    """1e-7 m from the first pin: the boundary triangle between them had
    quality 2e-6 and the solve "a fracture cuts off a piece"."""
    d = base()
    d["bc"][3] = {"at": [-1.0, 1e-7], "displacement_x": 0.0}
    err = refusal(d)
    assert err.key == "bc[3].at" and "from bc[2].at" in err.reason


@pytest.mark.parametrize("name", ["pin", "pin_corner", "mouth"])
def test_boundary_nodes_coincide_or_keep_a_tip_size_apart(name):
    assert refusal(family(name, 0.5)).key in ("bc[4].at", "fractures[0].points[0]")
    wingcrack.Case.from_dict(family(name, 1.01))
    wingcrack.Case.from_dict(family("pin", 0.0))   # the same place: one node


def test_domain_polygons_follow_the_checks_rule():
    clockwise = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]])
    with pytest.raises(Inadmissible) as info:
        Domain("polygon", points=clockwise)
    assert info.value.problem == admissibility.polygon(clockwise, "points")
    assert "counter-clockwise" in str(info.value)


def test_a_tip_growing_beside_another_tip_meets_it():
    """A new tip 2 rosette radii from another fracture's tip (over the 1.5 of
    the join distance, under the 2.5 that two rosettes need) would leave a
    geometry the next mesh refuses: it meets that tip instead."""
    from wingcrack.face_law import FaceLaw
    from wingcrack.propagation.fracture_set import FractureSet, GrowingFracture
    from wingcrack.propagation.joining import place_tip

    h = H
    a = GrowingFracture(np.array([[-0.3, 0.0], [-0.1, 0.0]]), (0, 1), ["tip", "tip"], FaceLaw("open"))
    b = GrowingFracture(np.array([[-0.1 + 2.2 * h, 1.6 * h], [0.3, 1.6 * h]]), (0, 1), ["tip", "tip"], FaceLaw("open"))
    domain = Domain("rectangle", corner=[-1, -1], size=[2, 2])
    fset = FractureSet([a, b])
    # growing straight on by h: 2 h below b's tip and 2 h from its polyline
    p, state = place_tip(fset, 0, 1, np.array([1.0, 0.0]), h, domain, admissibility.TIP_CLEARANCE * h)
    assert state == "joined"
    np.testing.assert_array_equal(p, b.points[0])
    # the geometry a plain step would have made: the mesher refuses it
    with pytest.raises(Inadmissible, match="overlap"):
        crack_mesh(domain, [np.vstack([a.points, [-0.1 + h, 0.0]]), b.points], [], 0.2, h)


def test_every_case_in_cases_is_still_accepted():
    from pathlib import Path

    for path in sorted((Path(__file__).resolve().parents[2] / "cases").glob("*.toml")):
        wingcrack.Case.from_toml(path)
