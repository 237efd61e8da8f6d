"""The run's patch (wingcrack/propagation/patch.py): the circle that a run on
a fixed mesh remeshes step after step, checked against the geometry by hand
(distances of the fractures to its centre), and kept across a resume."""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from wingcrack.case import Case
from wingcrack.propagation import checkpoint
from wingcrack.propagation import patch as P
from wingcrack.propagation.fracture_set import FractureSet

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "cases" / "brazilian_disc_45_open.toml"


def load_case(path):
    return Case.from_toml(path)


def fixed(case, **mesh):
    return dataclasses.replace(case, mesh=dataclasses.replace(case.mesh, adaptive=False, **mesh))


@pytest.fixture
def disc():
    return fixed(load_case(DISC), size=0.0008)   # the fine disc of issue 16, target 2


def test_the_disc_patch_is_centred_on_its_centre_and_leaves_room_for_the_steps_ahead(disc):
    fset = FractureSet.from_case(disc)
    patch = P.choose(disc, fset)
    # the crack is point-symmetric about the origin: the bounding box's centre is it exactly,
    # which the mesher needs to keep the half-meshed symmetry
    assert np.array_equal(patch.center, [0.0, 0.0])
    a = np.linalg.norm(disc.fractures[0].points[0])
    assert patch.radius == pytest.approx(a + P.clearance(disc) + P.STEPS_AHEAD * disc.propagation.length, rel=1e-12)
    assert P.holds(patch, disc, fset)


def test_a_patch_holds_until_a_growing_fracture_comes_within_the_clearance_of_its_circle(disc):
    fset = FractureSet.from_case(disc)
    patch = P.choose(disc, fset)
    f = fset.fractures[0]
    d = f.points[-1] / np.linalg.norm(f.points[-1])
    room = patch.radius - P.clearance(disc)
    f.extend(1, room * 0.999 * d)     # still clear inside
    assert P.holds(patch, disc, fset) and P.next_patch(patch, disc, fset) is patch
    f.move_tip(1, room * 1.001 * d)   # within the clearance: a new, wider patch
    assert not P.holds(patch, disc, fset)
    wider = P.next_patch(patch, disc, fset)
    assert wider is not None and wider.radius > patch.radius and P.holds(wider, disc, fset)


def test_a_fracture_near_the_circle_is_taken_in_whole_and_one_far_away_stays_outside(disc):
    fset = FractureSet.from_case(disc)
    alone = P.choose(disc, fset)
    near = dataclasses.replace(fset.fractures[0], points=np.array([[alone.radius, 0.0], [alone.radius + 0.004, 0.0]]),
                               grow=False, ends=["tip", "tip"])
    far = dataclasses.replace(near, points=np.array([[0.0, -0.036], [0.004, -0.036]]))
    two = FractureSet([fset.fractures[0], near])
    patch = P.choose(disc, two)
    assert patch.radius == pytest.approx(alone.radius + 0.004 + P.clearance(disc), rel=1e-12)
    assert P.holds(patch, disc, two)
    three = FractureSet([fset.fractures[0], far])
    assert P.choose(disc, three).radius == alone.radius and P.holds(alone, disc, three)


def test_no_patch_on_an_adaptive_mesh_or_where_the_circle_does_not_fit(disc):
    fset = FractureSet.from_case(disc)
    adaptive = dataclasses.replace(disc, mesh=dataclasses.replace(disc.mesh, adaptive=True))
    assert P.next_patch(None, adaptive, fset) is None
    assert P.next_patch(None, disc, fset) is not None
    f = fset.fractures[0]
    f.extend(1, np.array([-0.004, 0.038]))   # a wing towards the rim: no circle fits about the middle
    assert P.choose(disc, fset) is None
    assert P.next_patch(None, dataclasses.replace(disc, propagation=dataclasses.replace(disc.propagation, steps=1)),
                        FractureSet.from_case(disc)) is None   # one step: nothing to reuse


def test_the_checkpoint_keeps_the_patch(tmp_path, disc):
    fset = FractureSet.from_case(disc)
    patch = P.choose(disc, fset)
    steps = [{"step": 0, "load_factor": 1.0}]
    checkpoint.save(tmp_path, disc, 0, fset, 1.0, steps, None, None, patch)
    assert checkpoint.load(tmp_path, disc)["patch"] == patch
    checkpoint.save(tmp_path, disc, 0, fset, 1.0, steps, None, None, None)
    assert checkpoint.load(tmp_path, disc)["patch"] is None
