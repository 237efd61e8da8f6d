"""Issue 6: the Python API a user scripts with (wingcrack.sif / wingcrack.run
and their results). References: the summary.json the same run writes, and
the DOLFINx displacement evaluated against the nodal values wingcrack's own
SIF code uses."""
import json

import numpy as np
import pytest

import wingcrack
from builders import square_plate_with_cracks


def plate(steps=2):
    d = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.1}
    return wingcrack.Case.from_dict(d)


def test_run_result_is_plain_python_and_matches_summary(tmp_path, capsys):
    r = wingcrack.run(plate(), out=tmp_path / "o", progress=True, plots=False)
    assert r.status == "finished" and len(r.steps) == 2
    saved = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert r.steps == saved["steps"]
    assert r.tips == saved["steps"][-1]["tips"] and all(isinstance(t["KI"], float) for t in r.tips)
    assert len(r.polylines) == 1 and r.polylines[0].shape[1] == 2
    # the polyline runs from the end-0 tip to the end-1 tip of the summary's last state
    ends = [p for f in saved["fractures"] for p in (f["points"][0], f["points"][-1])]
    assert min(np.linalg.norm(np.array(ends) - r.polylines[0][0], axis=1)) < 1e-12
    # DOLFINx objects of the last step, for users who compute more
    assert r.dolfinx_mesh is r.problem.fm.mesh and r.displacement is r.problem.u
    assert np.all(np.isfinite(r.displacement.x.array))
    assert "step" in capsys.readouterr().err   # progress=True shows the bar


def test_to_dataframe_with_or_without_pandas(tmp_path):
    r = wingcrack.sif(plate(), out=tmp_path / "s")
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="needs pandas"):
            r.to_dataframe()
        from wingcrack.results import tip_rows
        rows = tip_rows(r.summary["steps"])
        assert [row["KI"] for row in rows] == [t.KI for t in r.tips]
        return
    df = r.to_dataframe()
    assert list(df["KI"]) == [t.KI for t in r.tips]


def test_help_reads_well():
    for f in (wingcrack.run, wingcrack.sif, wingcrack.plot, wingcrack.Case.from_toml, wingcrack.Case.from_dict):
        assert f.__doc__ and len(f.__doc__.split()) > 10, f
    assert "progress" in wingcrack.run.__doc__ and "resume" in wingcrack.run.__doc__


def test_case_errors_are_exceptions_naming_the_key():
    bad = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 1e5, 0.0), size=0.5, tip_size=0.05)
    bad["material"]["nu"] = 0.7
    with pytest.raises(wingcrack.CaseError, match="material.nu"):
        wingcrack.Case.from_dict(bad)
