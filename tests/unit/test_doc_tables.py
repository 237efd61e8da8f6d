"""The performance page's tables (benchmarks/doc_tables.py) carry the figures of
the results file they are read from: every case's wall, steps and phase total,
and every target, with nothing typed by hand."""
import json
import sys
from pathlib import Path

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
