"""Issue 5 test 3: the 45-degree Brazilian disc is point-symmetric (geometry
and loads mirror through the centre), so its two wings must be too.

Reference: the exact symmetry p -> -p. The mesh is not symmetric, so the
two tips see slightly different discretisations. The displacement
correlation's KII carries ~0.1 % of KI of mesh noise (its accuracy limit on
a 32-sector rosette), which turns each kink by ~0.1 degree (theta ~ -2
KII/KI) and moves the next tip sideways by ~2e-3 of the step. Measured
mirror errors over 10 steps of 0.5 mm: 2.2e-3 (open) and 1.4e-3 (contact)
of the step; 64 sectors or a second structured ring did not reduce them
(noise from the unstructured mesh beyond the rosette). Since kink angles and
advances are rounded to 1e-8 grids (propagation.loop.ANGLE_GRID, for
identical paths on any number of processes) gmsh meets slightly different
inputs and the same runs measure 2.9e-3 (open) and 2.2e-3 (contact): the
mirror error is mesh noise and moves with the mesh sequence. Per step the
two tips' DC KII differ by 2e-4..2e-3 of K_eq (growing with the steps), the
advances by <= 2e-4 of the step. (The interaction integral cannot take over
here: a wing's last segment leaves it no room for a domain after step 0.)

The issue asks for 1e-3 of the step: NOT met yet (see the issue note).
MIRROR_BOUND is the regression guard (1.5x the first measurement; the
open disc now sits at 0.97 of it), kept separate so that the target stays
visible.
"""
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from wingcrack.api import run
from wingcrack.case import Case

TARGET = 1e-3        # the bound, in step lengths (not met: see above)
MIRROR_BOUND = 3e-3  # regression guard: measured 2.2e-3 / 1.4e-3, 2.9e-3 / 2.2e-3 with the grids
CASES = Path(__file__).resolve().parent.parent / "cases"


@pytest.mark.parametrize("name", ["brazilian_disc_45_open", "brazilian_disc_45"])
def test_wings_mirror_through_the_centre(name):
    case = Case.from_toml(CASES / f"{name}.toml")
    case = dataclasses.replace(case, propagation=dataclasses.replace(case.propagation, steps=10))
    steps_seen = []

    def check(k, step):
        tips = step["tips"]
        assert len(tips) == 2
        steps_seen.append(k)

    r = run(case, progress=check)
    assert r.status == "finished" and len(steps_seen) == 10
    pts = r.fractures.fractures[0].points
    assert len(pts) == 2 + 2 * 10            # both tips grew at every step
    step = case.propagation.length
    mirror = np.abs(pts + pts[::-1]).max()   # point i mirrors point n-1-i through (0, 0)
    assert mirror < MIRROR_BOUND * step, f"mirror error {mirror / step:.2e} of the step"
    # and every step's tips mirror too (the per-step record, not only the end)
    for s in r.steps:
        a, b = s["tips"]
        assert max(abs(a["x"] + b["x"]), abs(a["y"] + b["y"])) < MIRROR_BOUND * step
