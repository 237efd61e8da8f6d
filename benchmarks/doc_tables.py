"""Writes the performance page's tables (docs/_generated/bench.md) from the
newest results file of `make bench` (benchmarks/*.json; today
benchmarks/baseline.json), what the pictures cost from
benchmarks/pictures_cost.json (benchmarks/pictures_cost.py --json), and the
1,000-fracture network's table (docs/_generated/network.md) from
benchmarks/grid_network.json (`benchmarks/grid_network.py --sif OUT --base
CHECKOUT --record`), the code's structure before and after the
renovation (docs/_generated/structure.md) from benchmarks/structure.json
(`benchmarks/structure.py --before CHECKOUT --record`), and what a time step
of the flow along the fractures costs from benchmarks/flow_cost.json
(benchmarks/flow_cost.py --json), so that the page shows what the files hold
and no figure is copied by hand. `make docs` runs it.

    python benchmarks/doc_tables.py [RESULTS.json] [-o OUT.md]
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import flow_cost

ROOT = Path(__file__).resolve().parents[1]
PHASES = ["mesh", "to_dolfinx", "assemble", "factorize", "contact", "solve", "sif",
          "growth", "estimate", "output"]
#: the network's paired runs (not a `make bench` results file)
NETWORK = ROOT / "benchmarks" / "grid_network.json"
NETWORK_PHASES = ["mesh", "to_dolfinx", "assemble", "contact", "solve", "sif", "output"]


#: what the pictures cost (its own section, whatever the newest results file)
PICTURES = ROOT / "benchmarks" / "pictures_cost.json"
#: what a time step of the flow costs (its own section too)
FLOW = ROOT / "benchmarks" / "flow_cost.json"
#: the code's structure measured before and after (not a `make bench` results file)
STRUCTURE = ROOT / "benchmarks" / "structure.json"


def newest_results() -> Path:
    files = sorted((p for p in ROOT.glob("benchmarks/*.json") if p not in (PICTURES, NETWORK, STRUCTURE, FLOW)),
                   key=lambda p: p.stat().st_mtime)
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


def render_pictures(data: dict, source: str) -> str:
    """The pictures' cost: each pair, the medians, and where the time goes."""
    out = ["## What the pictures cost", "", f"Read from `{source}`: {data['about']}; load average (1 min) "
           f"{data['load'][0]} before and {data['load'][1]} after, on {data['cores']} cores.", "",
           f"*How:* {data['how']}.", "",
           "| pair | wall with pictures s | wall --no-plots s | wall ratio | CPU with s | CPU --no-plots s | CPU ratio |",
           "|---|---|---|---|---|---|---|"]
    for i, p in enumerate(data["pairs"], 1):
        out.append(f"| {i} | {p['wall_with']} | {p['wall_without']} | {p['wall_with'] / p['wall_without']:.2f} | "
                   f"{p['cpu_with']} | {p['cpu_without']} | {p['cpu_with'] / p['cpu_without']:.2f} |")
    out += ["", f"Median wall ratio {data['wall_ratio']:.2f}x, CPU ratio {data['cpu_ratio']:.2f}x "
            f"(the bound: {data['bound']}x).", "",
            f"Where the pictures' time goes, CPU seconds ({data['phases']['steps']} steps; `during`: in the drawing "
            "process while the run computes, `end`: after its last step):", "",
            "| phase | CPU s |", "|---|---|"]
    out += [f"| {name} | {s} |" for name, s in data["phases"]["seconds"].items()]
    out += ["", "Counted: " + ", ".join(f"{k} {v}" for k, v in data["phases"]["counts"].items()) + ".", ""]
    return "\n".join(out)


def render_flow(data: dict, source: str) -> str:
    """A time step of the flow against the elastic solve of its mesh: each
    case's row (benchmarks/flow_cost.py's own table) and the largest ratio."""
    worst = max(c["ratio"] for c in data["cases"])
    out = ["## A time step of the flow along the fractures", "", f"Read from `{source}`: {data['about']}; load "
           f"average (1 min) {data['load'][0]} before and {data['load'][1]} after, on {data['cores']} cores.", "",
           f"*How:* {data['how']}.", ""] + flow_cost.HEADER + [flow_cost.row(c) for c in data["cases"]]
    out += ["", f"The largest time step / elastic solve: {worst:.3f} (the bound: {data['bound']:g}).", ""]
    return "\n".join(out)


def render_structure(data: dict, source: str) -> str:
    """The structure's figures, one row each, before and after."""
    b, a = data["before"], data["after"]

    def places(v):
        return "<br>".join(f"{path} {n}" for n, path in v)

    def cycles(v):
        return "<br>".join(" <-> ".join(c) for c in v) or "none"

    rows = [("largest files (lines)", "largest files", places),
            ("longest functions (lines)", "longest functions", places),
            ("imports inside functions", "imports inside functions", str), ("import cycles", "import cycles", cycles),
            ("comment and docstring share", "comment share", str),
            ("lines of wingcrack/, meshing/, procs/", "lines", str), ("README.md lines", "README.md lines", str)]
    out = [f"Read from `{source}` (`benchmarks/structure.py --before CHECKOUT --record`).", "",
           f"| figure | before ({b['commit']}) | after ({a['commit']}) |", "|---|---|---|"]
    out += [f"| {label} | {fmt(b[key])} | {fmt(a[key])} |" for label, key, fmt in rows]
    return "\n".join(out + [""])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("results", nargs="?", type=Path)
    ap.add_argument("-o", "--out", type=Path, default=ROOT / "docs" / "_generated" / "bench.md")
    a = ap.parse_args(argv)
    path = a.results or newest_results()
    data = json.loads(path.read_text())
    a.out.parent.mkdir(parents=True, exist_ok=True)
    text = render(data, path.relative_to(ROOT).as_posix() if path.is_relative_to(ROOT) else str(path))
    if PICTURES.exists():
        text += "\n" + render_pictures(json.loads(PICTURES.read_text()), PICTURES.relative_to(ROOT).as_posix())
    if FLOW.exists():
        text += "\n" + render_flow(json.loads(FLOW.read_text()), FLOW.relative_to(ROOT).as_posix())
    a.out.write_text(text)
    if STRUCTURE.exists():
        (a.out.parent / "structure.md").write_text(render_structure(json.loads(STRUCTURE.read_text()),
                                                                    STRUCTURE.relative_to(ROOT).as_posix()))
    if NETWORK.exists():
        (a.out.parent / "network.md").write_text(render_network(json.loads(NETWORK.read_text()),
                                                                NETWORK.relative_to(ROOT).as_posix()))


if __name__ == "__main__":
    main()
