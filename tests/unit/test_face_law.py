"""A fracture's face law (wingcrack/face_law.py): one record from the case
to the constraint rows and the checkpoint, built by field name, with the
wings' law and the checkpoint's reading of it."""
import dataclasses
import math

import numpy as np
import pytest

from wingcrack.case import Case
from wingcrack.face_law import FACES, FaceLaw
from wingcrack.propagation.fracture_set import FractureSet, GrowingFracture

CASE = {
    "material": {"E": 1.0e10, "nu": 0.25, "KIc": 1.0e6},
    "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [4.0, 2.0]},
    "fractures": [
        {"points": [[0.5, 0.5], [1.0, 0.8]], "faces": "coulomb", "friction": 0.6, "cohesion": 2.0e5, "gap": 1e-6,
         "pressure": 3e5},
        {"points": [[2.5, 0.5], [3.0, 0.8]], "faces": "slip", "slip": 1e-5, "slip_profile": "elliptic",
         "grow": False},
    ],
    "bc": [{"on": "bottom", "displacement": [0.0, 0.0]}, {"on": "top", "traction": [0.0, -1.0e6]}],
    "mesh": {"size": 0.2, "tip_size": 0.05},
}


def test_the_case_fracture_builds_its_law_from_its_keys_by_name():
    f0, f1 = Case.from_dict(CASE).fractures
    assert f0.law == FaceLaw("coulomb", gap=1e-6, friction=0.6, cohesion=2e5, pressure=3e5)
    assert f1.law == FaceLaw("slip", slip=1e-5, slip_profile="elliptic")
    # every field of the law is a key of the case's fracture, with the same default
    keys = {f.name: f.default for f in dataclasses.fields(type(f0))}
    assert all(keys[f.name] == f.default for f in dataclasses.fields(FaceLaw))


def test_a_growing_fracture_takes_the_law_and_the_rest_by_field():
    case = Case.from_dict(CASE)
    fs = FractureSet.from_case(case)
    for f, g in zip(case.fractures, fs.fractures):
        assert g.law == f.law and g.grow == f.grow and g.pre == (0, len(f.points) - 1)
        assert np.array_equal(g.points, f.points) and g.points is not f.points


@pytest.mark.parametrize("faces, wings", [("open", "open"), ("frictionless", "frictionless"),
                                          ("slip", "frictionless"), ("coulomb", "coulomb")])
def test_the_wings_law(faces, wings):
    """The paper's eq. 8 for the wings (tensile cracks: no gap, no prescribed
    slip), non-penetration where the fracture has contact, the fracture's
    friction and cohesion on a coulomb fracture's wings, and its fluid."""
    law = FaceLaw(faces, gap=1e-6, slip=2e-5, friction=0.6, cohesion=1e5, pressure=7e5)
    assert law.wings() == FaceLaw(wings, friction=0.6, cohesion=1e5, pressure=7e5)
    assert set(FACES) == {"open", "frictionless", "slip", "coulomb"}


def test_a_changing_pressure_is_a_new_law():
    """The record is frozen: a connected network's pressure is replaced,
    never written into a law another fracture may share."""
    law = FaceLaw("coulomb", friction=0.6)
    with pytest.raises(dataclasses.FrozenInstanceError):
        law.pressure = 1.0
    f = GrowingFracture(np.array([[0.0, 0.0], [1.0, 0.0]]), (0, 1), ["tip", "tip"], law)
    g = GrowingFracture(np.array([[0.0, 1.0], [1.0, 1.0]]), (0, 1), ["tip", "tip"], law, joined_to=[None, 0])
    fs = FractureSet([f, g])
    fs.fractures[0].law = dataclasses.replace(law, pressure=2e6)
    assert fs.connect_pressures() and [h.law.pressure for h in fs.fractures] == [2e6, 2e6]
    assert law.pressure == 0.0


def test_the_former_names_read_the_law_with_a_warning_and_refuse_a_write():
    f = GrowingFracture(np.array([[0.0, 0.0], [1.0, 0.0]]), (0, 1), ["tip", "tip"], FaceLaw(pressure=5.0))
    with pytest.warns(DeprecationWarning, match=r"GrowingFracture.pressure .* GrowingFracture.law.pressure"):
        assert f.pressure == 5.0
    with pytest.raises(AttributeError, match="face law"):
        f.pressure = 1.0
    with pytest.raises(AttributeError):
        f.no_such_field   # noqa: B018 - other names are no attributes


def test_the_checkpoint_form_round_trips_and_refuses_what_the_case_would():
    law = FaceLaw("slip", gap=1e-6, slip=-2e-5, slip_profile="elliptic", pressure=1)
    d = {"pre": [0, 1], **law.to_dict(), "grow": True}   # a checkpoint's fracture: the law's fields beside others
    back = FaceLaw.from_dict(d)
    assert back == law and all(type(getattr(back, k)) is float for k in ("gap", "slip", "pressure"))
    for name, value, words in [("friction", -0.1, "friction -0.1 is not a finite number >= 0"),
                               ("cohesion", math.nan, "cohesion nan is not a finite number >= 0"),
                               ("pressure", "1e6", "pressure '1e6' is not a finite number >= 0"),
                               ("gap", True, "gap True is not a finite number >= 0"),
                               ("slip", math.inf, "slip inf is not a finite number"),
                               ("faces", "closed", "faces 'closed' is none of open, frictionless, slip, coulomb"),
                               ("slip_profile", "cosine", "slip_profile 'cosine' is none of uniform, elliptic")]:
        with pytest.raises(ValueError, match=f"^{words}$".replace("(", r"\(").replace("+", r"\+")):
            FaceLaw.from_dict({**d, name: value})
    with pytest.raises(KeyError):
        FaceLaw.from_dict({k: v for k, v in d.items() if k != "cohesion"})
