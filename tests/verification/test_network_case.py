"""cases/intersecting_fractures.toml: an X, a T and a fracture from boundary
to boundary, Coulomb faces, every piece held. `check` lists the junctions
and the five free tips; `run` solves and grows from free ends only.

References: the case's own geometry (the free ends are the ends on no
fracture and off the boundary; the crossing of fractures 1 and 2 and the
T at (0.55, 0.5) are where the lines meet, solved here by hand), and the
growth rule: a wing starts at a tip of the step before.
"""
from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import wingcrack

CASE = Path(__file__).resolve().parents[2] / "cases" / "intersecting_fractures.toml"


@pytest.fixture(scope="module")
def case():
    return wingcrack.Case.from_toml(CASE)


def crossing(p, q):
    """Where the lines through segments p and q meet (by hand: Cramer's rule)."""
    (a, b), (c, d) = np.asarray(p, float), np.asarray(q, float)
    r, s = b - a, d - c
    t = ((c - a)[0] * s[1] - (c - a)[1] * s[0]) / (r[0] * s[1] - r[1] * s[0])
    return a + t * r


def test_check_lists_the_junctions_and_the_free_tips(case):
    exe = Path(sys.executable).with_name("wingcrack")
    res = subprocess.run([str(exe), "check", str(CASE)], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and res.stderr == "", res.stderr
    assert "tips: 5, edge-crack mouths: 2, ends on fractures: 1" in res.stdout
    assert "junctions (fractures meet, no tips): 2" in res.stdout
    f = [fr.points for fr in case.fractures]
    x, t = crossing(f[1], f[2]), crossing(f[0], f[3])
    np.testing.assert_allclose(sorted(case.junctions()), sorted([tuple(x), tuple(t)]), atol=1e-12)
    np.testing.assert_allclose(t, f[3][-1], atol=1e-15)   # fracture 3's end lies on fracture 0
    assert [(tip.fracture, tip.end) for tip in case.tips()] == [(1, 0), (1, 1), (2, 0), (2, 1), (3, 0)]


def test_run_grows_from_the_free_ends_only(case, tmp_path):
    short = dataclasses.replace(case, propagation=dataclasses.replace(case.propagation, steps=2))
    run = wingcrack.run(short, out=tmp_path / "run", plots=False)
    assert run.status == "finished" or run.status.startswith("stopped"), run.status
    assert len(run.steps) == 2
    free = {(tip.fracture, tip.end) for tip in case.tips()}
    for step in run.steps:
        assert {(t["fracture"], t["end"]) for t in step["tips"]} == free
        assert all(np.isfinite([t["KI"], t["KII"]]).all() for t in step["tips"])
    grown = [(t["fracture"], t["end"]) for s in run.steps for t in s["tips"] if t["advance"] > 0]
    assert grown, "a wing grew"
    fs = run.fractures.fractures
    assert [f.ends for f in fs][:1] == [["boundary", "boundary"]] and fs[3].ends[1] == "joined"
    assert fs[3].joined_to[1] == 0
    for i, (f, case_f) in enumerate(zip(fs, case.fractures)):   # the given parts as given; wings at free ends only
        np.testing.assert_array_equal(f.pre_points, case_f.points)
        for e in (0, 1):
            if (f.pre[0] > 0 if e == 0 else f.pre[1] < len(f.points) - 1):
                assert (i, e) in free
