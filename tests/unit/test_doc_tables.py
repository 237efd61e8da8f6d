"""The performance page's tables (benchmarks/doc_tables.py) carry the figures of
the results file they are read from: every case's wall, steps and phase total,
and every target; every pair and phase of what the pictures cost; every
case of what a time step of the flow costs; with nothing typed by hand."""
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
import doc_tables  # noqa: E402


def test_tables_carry_every_figure_of_the_results_file(tmp_path):
    data = json.loads((ROOT / "benchmarks" / "baseline.json").read_text())
    out = tmp_path / "bench.md"
    doc_tables.main([str(ROOT / "benchmarks" / "baseline.json"), "-o", str(out)])
    text = out.read_text()
    rows = {}   # the first table's row of each name (the phase table repeats the names)
    for line in text.splitlines():
        if line.startswith("| "):
            rows.setdefault(line.split("|")[1].strip(), line)
    for name, case in data["cases"].items():
        row = rows[name]
        assert f"| {case['wall']} |" in row and f"| {case['steps']} |" in row, row
        if case["steps"]:
            # s per step = the summary's phase total over the steps, to the 3 decimals printed
            assert f"{case['phases']['total'] / case['steps']:.3f}" in row
    for name in data["targets"]:
        assert name in rows


def test_the_network_table_carries_every_run_and_the_ratio(tmp_path):
    """benchmarks/grid_network.json's paired runs (made up here): each run's wall and solve phase, its
    factorisations and updates counted, the medians and their ratio."""
    run = {"wall": 180.5, "phases": {"mesh": 55.1, "solve": 70.2, "total": 170.0}, "factorisations": [30.1, 18.2],
           "updates": [[5.0, 37]], "peak_gb": 9.5, "load": [2.25, 3.0]}
    base = dict(run, wall=243.25, phases={"mesh": 56.0, "solve": 129.4}, factorisations=[33.0, 18.5, 18.4],
                updates=[])
    data = {"runs": {"this": [run], "base": [base]}, "median_wall": {"this": 180.5, "base": 243.25},
            "ratio": 0.742, "commits": {"this": "aaaaaaa", "base": "bbbbbbb"}}
    text = doc_tables.render_network(data, "x.json")
    rows = [line for line in text.splitlines() if line.startswith("| aaaaaaa") or line.startswith("| bbbbbbb")]
    assert len(rows) == 2
    assert "| 180.5 |" in rows[0] and "| 70.2 |" in rows[0] and "| 2 | 1 | 9.5 | 2.2 |" in rows[0], rows[0]
    assert "| 243.2 |" in rows[1] and "| 129.4 |" in rows[1] and "| 3 | 0 |" in rows[1], rows[1]
    assert "ratio 0.74" in text and "solve phase 70.2 s against 129.4 s: ratio 0.54" in text


def test_the_pictures_cost_carries_every_pair_and_phase():
    data = json.loads((ROOT / "benchmarks" / "pictures_cost.json").read_text())
    text = doc_tables.render_pictures(data, "benchmarks/pictures_cost.json")
    rows = [line.split("|")[1:-1] for line in text.splitlines() if line.startswith("| ")]
    pairs = {r[0].strip(): [c.strip() for c in r[1:]] for r in rows if r[0].strip().isdigit()}
    assert len(pairs) == len(data["pairs"])
    for i, p in enumerate(data["pairs"], 1):
        # the columns in their order: a swapped pair of columns fails
        assert pairs[str(i)] == [str(p["wall_with"]), str(p["wall_without"]), f"{p['wall_with'] / p['wall_without']:.2f}",
                                 str(p["cpu_with"]), str(p["cpu_without"]), f"{p['cpu_with'] / p['cpu_without']:.2f}"]
    phases = {r[0].strip(): r[1].strip() for r in rows if not r[0].strip().isdigit()}
    for name, seconds in data["phases"]["seconds"].items():
        assert phases[name] == str(seconds)
    assert f"Median wall ratio {data['wall_ratio']:.2f}x, CPU ratio {data['cpu_ratio']:.2f}x" in text


def test_the_flow_cost_carries_every_case_and_the_largest_ratio():
    data = json.loads((ROOT / "benchmarks" / "flow_cost.json").read_text())
    text = doc_tables.render_flow(data, "benchmarks/flow_cost.json")
    rows = {line.split("|")[1].strip(): [c.strip() for c in line.split("|")[2:-1]]
            for line in text.splitlines() if line.startswith("| ")}
    for c in data["cases"]:
        # the columns in their order: a swapped pair of columns fails
        assert rows[c["name"]] == [str(c["dofs"]), str(c["pairs"]), str(c["elastic"]), str(c["setup"]),
                                   f"{c['step']} ({c['steps']})", str(c["faces"]), str(c["solves"]),
                                   f"{c['ratio']:.3f}", f"{c['first_ratio']:.3f}"], rows[c["name"]]
        # the ratio is the time step's over the elastic solve's (to the 4 digits kept)
        assert c["ratio"] == pytest.approx(c["step"] / c["elastic"], abs=2e-4)
    assert f"time step / elastic solve: {max(c['ratio'] for c in data['cases']):.3f}" in text
