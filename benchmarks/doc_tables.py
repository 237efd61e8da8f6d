"""Writes the performance page's tables (docs/_generated/bench.md) from the
newest results file of `make bench` (benchmarks/*.json; today
benchmarks/baseline.json), and the 1,000-fracture network's table
(docs/_generated/network.md) from benchmarks/grid_network.json (written by
`benchmarks/grid_network.py --sif OUT --base CHECKOUT --record`), so that the
page shows what the files hold and no figure is copied by hand. `make docs`
runs it.

    python benchmarks/doc_tables.py [RESULTS.json] [-o OUT.md]
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PHASES = ["mesh", "to_dolfinx", "assemble", "factorize", "contact", "solve", "sif",
          "growth", "estimate", "output"]
#: the network's paired runs (not a `make bench` results file)
NETWORK = ROOT / "benchmarks" / "grid_network.json"
NETWORK_PHASES = ["mesh", "to_dolfinx", "assemble", "contact", "solve", "sif", "output"]


def newest_results() -> Path:
    files = sorted((p for p in ROOT.glob("benchmarks/*.json") if p != NETWORK), key=lambda p: p.stat().st_mtime)
    if not files:
        raise SystemExit("benchmarks/doc_tables.py: no results file in benchmarks/")
    return files[-1]


def render(data: dict, source: str) -> str:
    out = [f"Read from `{source}`.", ""]
    if "about" in data:
        out += [f"*What was measured:* {data['about']}", ""]
    if "how" in data:
        out += [f"*How:* {data['how']}", ""]
    cases = data.get("cases", {})
    if cases:
        out += ["| case | status | steps | DOFs first-last | wall s | peak RSS MiB | s per step |",
                "|---|---|---|---|---|---|---|"]
        for name, c in cases.items():
            dofs = c.get("dofs") or ["", ""]
            steps = c.get("steps") or 0
            per = c["phases"]["total"] / steps if steps and "phases" in c else None
            out.append(f"| {name} | {c.get('status', '')} | {steps} | {dofs[0]}-{dofs[-1]} | "
                       f"{c.get('wall', '')} | {c.get('rss_mib', '')} | "
                       f"{'' if per is None else f'{per:.3f}'} |")
        out += ["", "Seconds summed over the steps, by phase:", "",
                "| case | " + " | ".join(PHASES) + " | total |",
                "|---|" + "---|" * (len(PHASES) + 1)]
        for name, c in cases.items():
            ph = c.get("phases", {})
            out.append(f"| {name} | " + " | ".join(f"{ph.get(k, 0):.2f}" for k in PHASES)
                       + f" | {ph.get('total', 0):.2f} |")
        out.append("")
    targets = data.get("targets", {})
    if targets:
        out += ["Targets:", "", "| target | figures | note |", "|---|---|---|"]
        for name, t in targets.items():
            figs = ", ".join(f"{k} = {v}" for k, v in t.items() if k != "note")
            out.append(f"| {name} | {figs} | {t.get('note', '')} |")
        out.append("")
    return "\n".join(out)


def render_network(data: dict, source: str) -> str:
    """The network's paired runs: one row a run, its phases, the saddle-point
    sets factorised and updated, the peak memory and the load average at its
    start; then the medians and their ratio."""
    c = data["commits"]
    out = [f"Read from `{source}`: `benchmarks/grid_network.py --sif` (1,000 Coulomb fractures, one process), "
           f"{c['this']} against {c['base']}, each run its own process, alternately.", "",
           "| run | wall s | " + " | ".join(NETWORK_PHASES) + " | factorised | updated | peak GB | load |",
           "|---|---|" + "---|" * (len(NETWORK_PHASES) + 4)]
    for name in ("this", "base"):
        for k, r in enumerate(data["runs"][name]):
            ph = r["phases"]
            out.append(f"| {c[name]} #{k + 1} | {r['wall']:.1f} | " + " | ".join(f"{ph.get(p, 0):.1f}" for p in NETWORK_PHASES)
                       + f" | {len(r['factorisations'])} | {len(r['updates'])} | {r['peak_gb']:.1f} | {r['load'][0]:.1f} |")
    med = data["median_wall"]
    solve = {name: statistics.median(r["phases"]["solve"] for r in data["runs"][name]) for name in ("this", "base")}
    out += ["", f"Median wall {med['this']:.1f} s against {med['base']:.1f} s: ratio {data['ratio']:.2f}; median "
                f"solve phase {solve['this']:.1f} s against {solve['base']:.1f} s: ratio "
                f"{solve['this'] / solve['base']:.2f}.", ""]
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("results", nargs="?", type=Path)
    ap.add_argument("-o", "--out", type=Path, default=ROOT / "docs" / "_generated" / "bench.md")
    a = ap.parse_args(argv)
    path = a.results or newest_results()
    data = json.loads(path.read_text())
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(render(data, path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path)))
    if NETWORK.exists():
        (a.out.parent / "network.md").write_text(render_network(json.loads(NETWORK.read_text()),
                                                                NETWORK.relative_to(ROOT).as_posix()))


if __name__ == "__main__":
    main()
