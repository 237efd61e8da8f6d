"""A run on a fixed mesh reuses the far field outside its patch
(propagation.patch, fem.far_field): against the same run with every step
factorised whole (the independent reference: the same meshes, since the
patch is the mesher's either way, and MUMPS on the whole K), and across a
resume.

Tolerances: the condensed solve and the whole one are two exact
eliminations of the same K, so u differs by round-off amplified by K's
conditioning (~1e-12 relative here); SIFs are linear in u, and the load
factor and the kink follow from them smoothly: 1e-9 relative leaves three
orders of magnitude. Tip positions are sums of advances along those kinks:
1e-9 of the disc's diameter, as tests/command_line/test_resume.py asks of a resume.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import wingcrack
from wingcrack.fem import far_field

ROOT = Path(__file__).resolve().parents[2]
DISC = ROOT / "cases" / "brazilian_disc_45_open.toml"
CONTACT_DISC = ROOT / "cases" / "brazilian_disc_45.toml"
DIAMETER = 0.084
STEPS = 4


def variant(src: Path, path: Path, steps: int = STEPS) -> Path:
    """The case on a fixed 2 mm mesh (the patch's clearance then fits well
    inside the disc), `steps` steps."""
    import sys
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from case_variant import write_variant
    write_variant(src, {"mesh.size": 0.002, "mesh.adaptive": False, "propagation.steps": steps}, path)
    return wingcrack.Case.from_toml(path)


def tips(steps):
    return np.array([[t["x"], t["y"], t["KI"], t["KII"]] for st in steps for t in st["tips"]])


def agree(a, b):
    assert a.status == b.status and len(a.steps) == len(b.steps)
    for sa, sb in zip(a.steps, b.steps):
        assert sa["dofs"] == sb["dofs"]   # the same meshes
        assert abs(sa["load_factor"] - sb["load_factor"]) <= 1e-9 * abs(sb["load_factor"])
    ta, tb = tips(a.steps), tips(b.steps)
    K = np.abs(tb[:, 2:]).max()
    assert np.abs(ta[:, :2] - tb[:, :2]).max() <= 1e-9 * DIAMETER
    assert np.abs(ta[:, 2:] - tb[:, 2:]).max() <= 1e-9 * K
    for p, q in zip(a.polylines, b.polylines):
        assert p.shape == q.shape and np.abs(p - q).max() <= 1e-9 * DIAMETER


@pytest.mark.parametrize("src", [DISC, CONTACT_DISC], ids=["open", "contact"])
def test_a_fixed_mesh_run_reuses_the_far_field_and_gives_the_whole_factorisations_answers(tmp_path, monkeypatch,
                                                                                          src):
    case = variant(src, tmp_path / "case.toml")
    reused = wingcrack.run(case, out=tmp_path / "reused", plots=False)
    kinds = [st["mesh"]["far_field"] for st in reused.steps]
    assert kinds[0] == "factorised" and kinds.count("reused") >= 2, kinds
    assert all(st["mesh"]["symmetric"] for st in reused.steps)   # the patch keeps the half-meshing
    with monkeypatch.context() as m:
        m.setattr(far_field.FarField, "start", classmethod(lambda cls, problem, cm: None))
        whole = wingcrack.run(case, out=tmp_path / "whole", plots=False)
    assert [st["mesh"]["far_field"] for st in whole.steps] == [None] * len(whole.steps)
    agree(reused, whole)


def test_a_resumed_fixed_mesh_run_ends_on_the_uninterrupted_runs_geometry(tmp_path):
    case = variant(DISC, tmp_path / "case.toml")
    whole = wingcrack.run(case, out=tmp_path / "whole", plots=False)

    def stop_after_two(k, step):
        if k == 1:
            raise KeyboardInterrupt

    out = tmp_path / "resumed"
    with pytest.raises(KeyboardInterrupt):
        wingcrack.run(case, out=out, plots=False, progress=stop_after_two)
    saved = json.loads((out / "summary.json").read_text())
    assert [s["step"] for s in saved["steps"]] == [0, 1]
    resumed = wingcrack.run(case, out=out, plots=False, resume=True)
    # the resumed run meshes with the checkpoint's patch: the same meshes, its far field factorised anew
    assert [st["mesh"]["far_field"] for st in resumed.steps][2] == "factorised"
    agree(resumed, whole)
