"""The logic of the benchmark report (benchmarks/phases.py, ratios.py,
case_variant.py, targets.reuse), on made-up summaries: no timing is run
or asserted here (speed is measured by `make bench`, not tested)."""
from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.append(str(ROOT / "benchmarks"))   # the benchmarks import each other as scripts do

import phases  # noqa: E402
import ratios  # noqa: E402
import targets  # noqa: E402
from case_variant import variant_text, write_variant  # noqa: E402

from wingcrack.case import Case  # noqa: E402


def step(**seconds) -> dict:
    seconds["total"] = sum(seconds.values())
    return {"dofs": 1000, "seconds": seconds}


def test_every_phase_the_code_times_has_an_issue_phase():
    """The laps of wingcrack/step.py, solver.py and propagation/loop.py (the keys of a
    step's seconds in summary.json) each map onto one of the issue's phases;
    a new lap has to be placed in phases.ISSUE_PHASES (until then the report
    shows it under "other")."""
    laps = set()
    for src in ("wingcrack/step.py", "wingcrack/solver.py", "wingcrack/propagation/loop.py"):
        laps |= set(re.findall(r"\blap\(\"(\w+)\"\)", (ROOT / src).read_text()))
    assert {"mesh", "factorize", "solve", "sif", "output"} <= laps   # the regex still reads the sources
    mapped = [k for keys in phases.ISSUE_PHASES.values() for k in keys]
    assert len(mapped) == len(set(mapped)), "a key in two issue phases would count twice"
    assert laps <= set(mapped), f"not in benchmarks/phases.py ISSUE_PHASES: {sorted(laps - set(mapped))}"
    assert list(phases.ISSUE_PHASES) == ["mesh", "patch", "factorise", "contact", "solve", "SIFs", "output"]


def test_the_issue_phases_of_a_step_add_up_to_its_total():
    st = step(mesh=0.2, to_dolfinx=0.01, assemble=0.03, factorize=0.09, contact=0.02, solve=0.05,
              sif=0.01, growth=0.002, estimate=0.04, output=0.06, overlap_wait=0.5)
    p = phases.of_seconds(st["seconds"])
    assert p["mesh"] == pytest.approx(0.25) and p["factorise"] == pytest.approx(0.12)
    assert p["SIFs"] == pytest.approx(0.012) and p["other"] == pytest.approx(0.5)
    assert p["patch"] is None   # not measured: printed "-", not 0 s
    assert sum(v for v in p.values() if v is not None) == pytest.approx(st["seconds"]["total"])
    assert phases.unknown_keys([st]) == ["overlap_wait"]
    assert phases.of_seconds({"mesh": 1.0, "patch": 0.3})["patch"] == 0.3

    two = phases.per_step([st, step(mesh=0.4, solve=0.15)])
    assert two["mesh"] == pytest.approx((0.25 + 0.4) / 2) and two["solve"] == pytest.approx(0.1)
    assert two["total"] == pytest.approx((st["seconds"]["total"] + 0.55) / 2)
    assert phases.per_step([]) == {}


def run(wall, status="finished", n=10, dofs=(9000, 15000), exit=0) -> dict:
    """A made-up propagation.run_case result of n steps of 1 s each."""
    steps = [dict(step(mesh=0.5, solve=0.5), dofs=dofs[0] if k == 0 else dofs[1]) for k in range(n)]
    return {"exit": exit, "wall": wall, "peak_mib": 300.0, "stderr": "",
            "summary": {"status": status, "steps": steps}}


def test_ratios_and_flags_against_a_base():
    base = ratios.figures(run(30.0))
    assert base["dofs"] == [9000, 15000] and base["steps"] == 10 and base["phases"]["total"] == pytest.approx(10)

    fast = ratios.compare(ratios.figures(run(15.0)), base)
    assert fast["ratio"] == pytest.approx(2.0) and fast["step_ratio"] == pytest.approx(1.0)
    assert fast["flags"] == []
    assert ratios.compare(ratios.figures(run(25.0)), base)["flags"] == ["under 1.5x"]
    assert ratios.compare(ratios.figures(run(20.0)), base)["flags"] == []   # 1.5x exactly meets it
    assert ratios.compare(ratios.figures(run(31.0)), base)["flags"] == ["SLOWER"]

    other = ratios.compare(ratios.figures(run(10.0, status="stopped: no tip", n=4, dofs=(8000, 15000))), base)
    assert other["ratio"] == pytest.approx(3.0)
    assert other["step_ratio"] == pytest.approx(1.0)   # the same seconds per step over fewer steps
    assert other["flags"] == ["status was 'finished'", "steps were 10", "fewer DOFs (were 9,000/15,000)"]

    failed = ratios.figures({"exit": 2, "wall": 1.0, "peak_mib": 50.0, "stderr": "mesh.size: must be > 0",
                             "summary": {}})
    assert failed["steps"] == 0 and failed["dofs"] is None
    flags = ratios.compare(failed, base)["flags"]
    assert flags[0] == "FAILED" and "status was 'finished'" in flags
    assert ratios.compare(ratios.figures(run(5.0)), None) == {"ratio": None, "step_ratio": None,
                                                              "cpu_ratio": None, "flags": ["no baseline"]}
    assert fast["cpu_ratio"] is None   # today's figures have no CPU seconds
    with_cpu = ratios.compare(dict(ratios.figures(run(15.0)), cpu=8.0), dict(base, cpu=24.0))
    assert with_cpu["cpu_ratio"] == pytest.approx(3.0)


def test_the_committed_baseline_is_of_cases_that_exist():
    """benchmarks/baseline.json: today's figures of cases still in cases/
    (a case added later has none and the report says "no baseline")."""
    base = ratios.load_baseline()
    names = {p.stem for p in (ROOT / "cases").glob("*.toml")}
    assert base["cases"] and set(base["cases"]) <= names
    for fig in base["cases"].values():
        assert fig["wall"] > 0 and fig["status"]
        assert (fig["dofs"] is None) == (fig["steps"] == 0) and ("total" in fig["phases"]) == (fig["steps"] > 0)


def test_the_reuse_ratio_of_made_up_steps():
    steps = [step(mesh=0.25, factorize=0.5, solve=0.25), step(mesh=0.25, factorize=0.05, solve=0.2),
             step(mesh=0.15, factorize=0.05, solve=0.1)]
    ru = targets.reuse(steps)
    assert ru["fractions"] == pytest.approx([0.5, 0.3])
    t0, later, q = ru["phases"]["factorise"]
    assert (t0, later, q) == pytest.approx((0.5, 0.05, 0.1))
    assert ru["phases"]["mesh"] == pytest.approx((0.25, 0.2, 0.8))
    assert "patch" not in ru["phases"]   # measured on no step
    assert targets.reuse(steps[:1]) == {}


def test_target_2_takes_each_steps_median_over_the_runs():
    """median_steps: phase by phase and step by step, the median over the
    runs (the spike in the second run's second step drops out); the reuse
    ratio then of those medians."""
    runs = [[step(mesh=0.25, factorize=0.5, solve=0.25), step(mesh=0.25, factorize=0.05, solve=0.2)],
            [step(mesh=0.3, factorize=0.6, solve=0.3), step(mesh=0.9, factorize=0.05, solve=0.1)],
            [step(mesh=0.2, factorize=0.4, solve=0.2), step(mesh=0.2, factorize=0.08, solve=0.3)]]
    med = targets.median_steps(runs)
    assert med[0]["seconds"]["mesh"] == 0.25 and med[0]["seconds"]["factorize"] == 0.5
    assert med[1]["seconds"]["mesh"] == 0.25 and med[1]["seconds"]["factorize"] == 0.05
    # the total too is a median (of the runs' step totals 0.5, 1.05, 0.58), not the medians' sum
    assert med[1]["seconds"]["solve"] == 0.2 and med[1]["seconds"]["total"] == pytest.approx(0.58)
    assert targets.reuse(med)["fractions"] == pytest.approx([0.58])


def test_the_34_step_disc_is_read_back_by_the_case_reader(tmp_path):
    src = Case.from_toml(targets.OPEN_DISC)
    path = write_variant(targets.OPEN_DISC, targets.DISC_34, tmp_path / "d34.toml")
    case = Case.from_toml(path)
    assert case.propagation.steps == 34 and src.propagation.steps != 34
    # nothing else moved: the tables are the committed case's but for the steps
    got, want = (tomllib.loads(p.read_text()) for p in (path, targets.OPEN_DISC))
    assert got["propagation"].pop("steps") == 34
    want["propagation"].pop("steps")
    assert got == want

    fine = Case.from_toml(write_variant(targets.OPEN_DISC, targets.FINE_DISC, tmp_path / "fine.toml"))
    assert (fine.mesh.size, fine.mesh.adaptive, fine.propagation.steps) == (0.0008, False, 8)
    assert fine.mesh.tip_size == src.mesh.tip_size and fine.mesh.sectors == src.mesh.sectors


def test_a_variant_adds_missing_keys_and_tables():
    text = "title = 'x'  # a comment\n[mesh]  # sizes\nsize = 0.1\n\n[[fractures]]\nsteps = 'not this one'\n"
    got = tomllib.loads(variant_text(text, {"mesh.adaptive": False, "mesh.size": 0.2, "propagation.steps": 3,
                                            "propagation.load": "fixed"}))
    assert got == {"title": "x", "mesh": {"size": 0.2, "adaptive": False},
                   "fractures": [{"steps": "not this one"}], "propagation": {"steps": 3, "load": "fixed"}}
    with pytest.raises(ValueError, match="fractures.points.x"):
        variant_text(text, {"fractures.points.x": 1})


def test_the_identity_check_drops_timings_and_finds_every_other_difference(tmp_path):
    """benchmarks/identical.py (the renovation's check that results stay bitwise the same): timings
    ("seconds", wherever they sit) are dropped; a step file's arrays compared decoded, so the same data
    compressed otherwise is the same file; a changed number, a changed coordinate, a file that appeared
    and a changed exit code are each reported, and a re-run that only timed differently is not."""
    import meshio
    import numpy as np

    import identical

    def vtu(path, x, compression="zlib"):
        points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, x, 0.0]])
        meshio.Mesh(points, [("triangle", np.array([[0, 1, 2]]))], point_data={"u": points[:, :2]}).write(
            path, file_format="vtu", compression=compression)

    def folder(name, x=1.0, extra=False, compression="zlib"):
        d = tmp_path / name
        d.mkdir()
        vtu(d / "step_0000.vtu", x, compression)
        (d / "fields.pvd").write_text("<pvd/>")
        (d / "fractures.png").write_bytes(b"picture")   # pictures are not compared
        if extra:
            vtu(d / "faces_0000.vtu", x)
        return d

    summary = {"title": "t", "steps": [{"step": 0, "load_factor": 1.25, "seconds": {"mesh": 0.5}}]}
    slower = {"title": "t", "steps": [{"step": 0, "load_factor": 1.25, "seconds": {"mesh": 0.9}}]}
    moved = {"title": "t", "steps": [{"step": 0, "load_factor": 1.2500000000000002, "seconds": {"mesh": 0.5}}]}
    a = identical.manifest_of(folder("a"), {"exit": 0, "summary": summary})
    assert a["summary"] == {"title": "t", "steps": [{"step": 0, "load_factor": 1.25}]}
    assert set(a["files"]) == {"step_0000.vtu", "fields.pvd"}
    b = folder("b", compression=None)
    assert (b / "step_0000.vtu").read_bytes() != (tmp_path / "a" / "step_0000.vtu").read_bytes()
    same = identical.manifest_of(b, {"exit": 0, "summary": slower})
    assert identical.differences({"c": a}, {"c": same}) == []
    other = identical.manifest_of(folder("c", x=1.0 + 2 ** -52, extra=True), {"exit": 1, "summary": moved})
    lines = identical.differences({"c": a}, {"c": other})
    assert lines == ["c: exit 0 -> 1",
                     "c: summary.json differs (steps[0].load_factor: 1.25 -> 1.2500000000000002)",
                     "c: faces_0000.vtu only in the check",
                     "c: step_0000.vtu differs"]
    assert identical.differences({"c": a}, {}) == ["c: only in the manifest"]
