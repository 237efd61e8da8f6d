"""Issue 5 test 3: the 45-degree Brazilian disc is point-symmetric (geometry
and loads mirror through the centre), so its two wings must be too.

Reference: the exact symmetry p -> -p. An unstructured mesh of the whole disc
is not symmetric: the two tips saw slightly different discretisations, their
KII differed by 2e-4..2e-3 of K_eq and the wings parted by 2-3e-3 of the step
after 10 steps (measured with both displacement correlation and the
interaction integral driving the kinks: mesh noise, not SIF noise). Since
meshing/point_symmetry.py meshes half of a point-symmetric geometry and glues
its half-turn image, the mesh maps onto itself node for node, and the two
tips' SIFs agree to round-off (measured 4e-13 of K). Kink angles and
advances are rounded to 1e-8 grids (propagation.loop.ANGLE_GRID): two values
1e-13 apart round to the same grid point unless they straddle a grid line,
so the paths are identical (measured mirror error 0.0) or, on such a tie,
1e-8 of a step apart. Bound: 1e-6 of the step, far inside the issue's 1e-3.
"""
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from wingcrack.api import run
from wingcrack.case import Case

TARGET = 1e-3        # the bound, in step lengths
MIRROR_BOUND = 1e-6  # ours: round-off plus at most one 1e-8 grid tie (see above); measured 0.0
SIF_BOUND = 1e-9     # the two tips' SIFs, of K_eq: round-off on a mirrored mesh (measured 4e-13)
CASES = Path(__file__).resolve().parents[2] / "cases"


@pytest.mark.parametrize("name", ["brazilian_disc_45_open", "brazilian_disc_45"])
def test_wings_mirror_through_the_centre(name):
    case = Case.from_toml(CASES / f"{name}.toml")
    case = dataclasses.replace(case, propagation=dataclasses.replace(case.propagation, steps=10))
    steps_seen = []

    def check(k, step):
        tips = step["tips"]
        assert len(tips) == 2
        a, b = tips
        for key in ("KI", "KII", "K_eq"):
            assert abs(a[key] - b[key]) <= SIF_BOUND * max(a["K_eq"], b["K_eq"]), (k, key)
        steps_seen.append(k)

    r = run(case, progress=check)
    assert r.status == "finished" and len(steps_seen) == 10
    pts = r.fractures.fractures[0].points
    assert len(pts) == 2 + 2 * 10            # both tips grew at every step
    step = case.propagation.length
    mirror = np.abs(pts + pts[::-1]).max()   # point i mirrors point n-1-i through (0, 0)
    assert mirror < MIRROR_BOUND * step <= TARGET * step, f"mirror error {mirror / step:.2e} of the step"
    # and every step's tips mirror too (the per-step record, not only the end)
    for s in r.steps:
        a, b = s["tips"]
        assert max(abs(a["x"] + b["x"]), abs(a["y"] + b["y"])) < MIRROR_BOUND * step
