"""Issue 7: randomised fracture networks (tests/networks.py), 10 steps each.

Every run must end `finished`, `stopped: ...` or `failed: <reason>` with
exit 0 or 1 (never a hang: each runs under a time limit; never a traceback),
summary.json must hold no NaN or infinity, no two fractures may cross at any
step, and the mesh of every step must pass the quality checks (positive
Jacobians, no degenerate cell). `make test` runs 20 seeds; `make soak` sets
WINGCRACK_SOAK_SEEDS=200.
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
    assert proc.returncode in (0, 1), f"seed {seed}: exit {proc.returncode}: {proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
    text = (out / "summary.json").read_text()
    _no_nan(text)
    summary = json.loads(text)
    status = summary["status"]
    assert status == "finished" or status.startswith(("stopped: ", "failed: ")), status
    assert (proc.returncode == 1) == status.startswith("failed: ")
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
