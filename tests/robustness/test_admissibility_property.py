"""Property: every case `wingcrack check` accepts, `wingcrack sif` computes.

Hypothesis (derandomised: the same examples every run) builds geometries on
the edge of every rule of meshing/admissibility.py (tests/admissibility_cases.py:
a tip near the boundary, a corner, another fracture, another tip, its own
earlier segments; short segments and short fractures; edge cracks at
grazing angles; pins and mouths near each other and near corners;
polylines of up to 200 points; fractures that meet: X's, T's and three
fractures through one point at angles near the least junction angle, a
fracture from boundary to boundary crossed by another, junctions near
each other, a kink and a mouth), each a relative delta from the rule's
threshold, then turned, scaled from 1e-10 to 1e10 and moved up to 2e6
domain sizes from the origin. The one allowed outcomes: the check refuses
(CaseError, the CLI's exit 2) with a key, or the mesher meshes it and the
solve gives finite SIFs at every tip (exit 0). Anything else (another
exception, gmsh aborting, a NaN) fails.

The mesher runs first in its worker process (`timeout`), so that a gmsh
abort fails the example instead of killing pytest; then `wingcrack.sif`
runs in this process. WINGCRACK_PROPERTY_EXAMPLES sets the number of
examples (`make test`: 50, `make soak`: 500); WINGCRACK_PROPERTY_LOG names
a file that gets one line per example (family, k, outcome), to see how the
examples split between refused and computed. A few fixed examples also go
through the installed console script, as a user runs it.
"""
from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

import wingcrack  # noqa: E402
from meshing import crack_mesh  # noqa: E402
from wingcrack.errors import CaseError  # noqa: E402

from admissibility_cases import THRESHOLD, family, place, to_toml  # noqa: E402

EXAMPLES = int(os.environ.get("WINGCRACK_PROPERTY_EXAMPLES", "50"))
DELTAS = [-0.1, -1e-3, -1e-6, -1e-9, 0.0, 1e-9, 1e-6, 1e-3, 1e-2, 0.1, 0.5]
#: grazing angles of an edge crack (degrees) and the crack's turns
GRAZE = [1e-3, 0.01, 0.1, 1.0, 3.0, 10.0, 45.0]


@st.composite
def cases(draw):
    name = draw(st.sampled_from(sorted(THRESHOLD)))
    delta = draw(st.sampled_from(DELTAS))
    phi = draw(st.sampled_from([0.0, 0.3, -1.0, 1.4, 1e-6]))
    n = draw(st.sampled_from([3, 10, 40, 200]))
    if name == "graze":
        k = draw(st.sampled_from(GRAZE)) * (1 + delta)
    elif name == "zigzag":
        k = 1.2 * (1 + delta)   # the zigzag's segments are k tip sizes long: room for n points
    else:
        k = THRESHOLD[name] * (1 + delta)
    case = family(name, k, phi=phi, n=n if name == "zigzag" else 3)
    if name == "zigzag":
        case["mesh"]["tip_size"] = case["mesh"]["tip_size"] * min(1.0, 40.0 / n)   # fit the zigzag
        case["fractures"][0]["points"] = (np.asarray(case["fractures"][0]["points"]) * min(1.0, 40.0 / n)).tolist()
    angle = draw(st.sampled_from([0.0, 0.0, 1e-7, 0.3, math.pi / 4]))
    exponent = draw(st.sampled_from([0.0, 0.0, 0.0, -9.6, -9.0, -8.7, -3.0, 4.0, 8.6, 9.0]))
    offset = draw(st.sampled_from([0.0, 0.0, 0.0, 1e3, 1e5, 1e6 * 0.99, 1e6 * 1.01, 2e6]))
    return name, k, place(case, angle=angle, scale=10.0**exponent, offset=offset)


def check_or_compute(d: dict):
    """'refused' with the key, or the SIFs of an accepted case (raises on anything else)."""
    try:
        case = wingcrack.Case.from_dict(d)
    except CaseError as err:
        assert err.key, err
        return "refused", err.key
    mesh = crack_mesh(case.domain, case.fracture_points(), case.bc_points(), case.mesh.size, case.mesh.tip_size,
                      sectors=case.mesh.sectors, timeout=120.0)
    assert mesh.stats["min_jacobian"] > 0.0
    result = wingcrack.sif(case)
    K = np.array([[t.KI, t.KII] for t in result.tips])
    assert len(result.tips) == len(case.tips()) and np.all(np.isfinite(K)), K
    return "computed", K


@settings(max_examples=EXAMPLES, derandomize=True, deadline=None, database=None, print_blob=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(cases())
def test_check_refuses_or_sif_computes(example):
    name, k, d = example
    outcome = check_or_compute(d)
    if os.environ.get("WINGCRACK_PROPERTY_LOG"):
        with open(os.environ["WINGCRACK_PROPERTY_LOG"], "a") as log:
            print(name, f"{k:.9g}", d["mesh"]["tip_size"], d["domain"], outcome[0],
                  outcome[1] if outcome[0] == "refused" else "", file=log)


@pytest.mark.parametrize("name, k, where", [
    ("short", 2.5 * (1 - 1e-6), {}), ("short", 2.5 * (1 + 1e-3), {"scale": 1e-9}),
    ("boundary", 1.5 * (1 + 1e-6), {"offset": 1e5, "angle": 0.3}), ("pin", 1e-5, {}),
])
def test_the_console_script_refuses_with_2_or_computes_with_0(tmp_path, name, k, where):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(place(family(name, k), **where)))
    exe = Path(sys.executable).with_name("wingcrack")
    check = subprocess.run([str(exe), "check", str(path)], capture_output=True, text=True)
    assert check.returncode in (0, 2) and "Traceback" not in check.stderr, check.stderr
    if check.returncode == 2:
        assert len(check.stderr.splitlines()) == 1 and check.stderr.startswith("wingcrack: error: ")
        return
    sif = subprocess.run([str(exe), "sif", str(path), "-o", str(tmp_path / "out"), "--quiet"], capture_output=True,
                         text=True)
    assert sif.returncode == 0 and "Traceback" not in sif.stderr, sif.stderr
