"""Issue 7: randomised fracture networks (tests/networks.py), 10 steps each.

Every run must end `finished` or `stopped: ...` with exit 0 (never a hang:
each runs under a time limit; never a traceback; never `failed`: every
generated network is a valid case, so a failure is a bug), summary.json must
hold no NaN or infinity, no two fractures may cross at any step, and the mesh
of every step must pass the quality checks (positive Jacobians, no degenerate
cell). The seeds of `make test` must end as measured (issue 12.10: a
regression that stops or fails networks early must not pass): 19 of 20 run
all 10 steps; seed 2's load never brings a tip to KIc. `make test` runs 20
seeds; `make soak` sets WINGCRACK_SOAK_SEEDS=200 (those past the measured
ones are held to the rules above).
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from networks import random_case, to_toml
from wingcrack.propagation.growth import crossing_pair

SEEDS = range(int(os.environ.get("WINGCRACK_SOAK_FIRST", "0")),
               int(os.environ.get("WINGCRACK_SOAK_FIRST", "0")) + int(os.environ.get("WINGCRACK_SOAK_SEEDS", "20")))
LIMIT = 300.0  # seconds a run may take (they take 2-20 s here)
WINGCRACK = Path(sys.executable).with_name("wingcrack")
STEPS = 10   # networks.random_case's propagation.steps
# (status, steps in summary.json) of seeds 0-19 as measured; every other one: ("finished", STEPS)
MEASURED = range(20)
# seed 2: step 0 recorded at the limit, no tip grown
EXPECTED = {2: ("stopped: no tip reaches KIc below the load factor limit 100 (there the largest K_eq is 0.48 KIc)", 1)}


def _no_nan(text: str) -> None:
    def refuse(c):
        raise AssertionError(f"summary.json holds {c}")
    json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_network(seed, tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(to_toml(random_case(seed)))
    out = tmp_path / "out"
    try:
        proc = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet"],
                              capture_output=True, text=True, timeout=LIMIT)
    except subprocess.TimeoutExpired:
        pytest.fail(f"seed {seed}: no result within {LIMIT:g} s (a hang)")
    assert proc.returncode == 0, f"seed {seed}: exit {proc.returncode}: {proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
    text = (out / "summary.json").read_text()
    _no_nan(text)
    summary = json.loads(text)
    status = summary["status"]
    assert status == "finished" or status.startswith("stopped: "), f"seed {seed}: {status}"
    if seed in MEASURED:
        assert (status, len(summary["steps"])) == EXPECTED.get(seed, ("finished", STEPS)), f"seed {seed}"
    # fractures of the last state never cross (the loop checks every step too)
    by_fracture = {}
    for piece in summary.get("fractures", []):
        by_fracture.setdefault(piece["fracture"], []).append(np.asarray(piece["points"], float))
    polys = [np.concatenate([p if k == 0 else p[1:] for k, p in enumerate(pieces)])
             for pieces in by_fracture.values()]
    assert crossing_pair(polys) is None, f"seed {seed}: fractures cross"
    for step in summary["steps"]:
        mesh = step.get("mesh")
        if mesh:
            assert mesh["min_jacobian"] > 0 and mesh["min_quality"] > 0.1, (seed, step["step"], mesh)
    print(f"seed {seed}: {status} after {len(summary['steps'])} steps")


def test_crossing_pair_tells_crossing_from_touching():
    """The check used above and after every step: an X crosses, a T or two
    ends meeting only touch."""
    h = np.array([[-1.0, 0.0], [1.0, 0.0]])
    assert crossing_pair([h, np.array([[0.0, -1.0], [0.0, 1.0]])]) == (0, 1)
    assert crossing_pair([h, np.array([[0.0, 0.0], [0.0, 1.0]])]) is None      # a T
    assert crossing_pair([h, np.array([[1.0, 0.0], [2.0, 1.0]])]) is None      # end to end
