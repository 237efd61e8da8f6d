"""What injection changes against the imposed slip of paper 4.3, and the
showcase network (docs/theory/fluid-pressure.md, "Injection"; `make bench` runs it, not a test):
each case runs as `wingcrack run`, and one row each gives the load at which
the first wings start (the imposed slip u0, or the injection pressure), the
kink at step 0 of the tips that grew, which tips grew, which joined what and
when, which fractures carry the pressure at the end, the steps and the
solves per step, and the wall time of the run.

    python benchmarks/pressure_cases.py [OUT] [CASE ...]   (OUT: keep the results there)
"""
from __future__ import annotations

import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from propagation import table_runs

ROOT = Path(__file__).resolve().parents[1]

#: the table of docs/theory/fluid-pressure.md: 4.3 with its imposed slip, with friction, driven by injection
#: (at a given pressure, and by a pump)
CASES = ["three_fractures_slip", "three_fractures_friction", "three_fractures_injection",
         "three_fractures_injection_rate"]


def load_at(case: dict, factor: float) -> str:
    """The physical load at a load factor: the imposed slip (mm) or the injection pressure (MPa; a
    pump's load factor is its network's pressure in Pa)."""
    fr = case["fractures"]
    if case.get("propagation", {}).get("load") == "injection":
        return f"p = {factor / 1e6:.4g} MPa"
    if case.get("propagation", {}).get("load") == "pressure":
        p = max(f.get("pressure", 0.0) for f in fr)
        return f"p = {factor * p / 1e6:.4g} MPa"
    slip = max(abs(f.get("slip", 0.0)) for f in fr)
    return f"u0 = {factor * slip * 1e3:.4g} mm"


def joins(summary) -> list[tuple[int, int, int, int | None]]:
    """(fracture, end, step, host) of each tip that joined: host is the
    fracture whose pieces lie nearest the tip's last point (None: the boundary
    or its own wing)."""
    out = []
    last = {}
    for st in summary["steps"]:
        for t in st["tips"]:
            key = (t["fracture"], t["end"])
            if t.get("state") == "joined" and key not in last:
                last[key] = st["step"]
                x = np.array([t["x"], t["y"]])
                best, host = np.inf, None
                for f in summary["fractures"]:
                    if f["fracture"] == t["fracture"]:
                        continue
                    p = np.asarray(f["points"], dtype=float)
                    a, ab = p[:-1], np.diff(p, axis=0)
                    u = np.clip(np.einsum("ij,ij->i", x - a, ab) / np.einsum("ij,ij->i", ab, ab), 0, 1)
                    d = float(np.min(np.linalg.norm(x - a - u[:, None] * ab, axis=1)))
                    if d < best:
                        best, host = d, f["fracture"]
                out.append((t["fracture"], t["end"], st["step"], host))
    return out


def row(name: str, out: Path, wall: float, number: int) -> str:
    """One table row; fracture numbers are the case's index + `number`
    (1 for the 4.3 cases, whose comments count from 1)."""
    import json

    case = tomllib.loads((ROOT / "cases" / f"{name}.toml").read_text())
    s = json.loads((out / "summary.json").read_text())
    steps = s["steps"]
    if not steps:
        return f"| `{name}` | {s['status']} |"
    first = next((st for st in steps if any(t.get("advance", 0) > 0 for t in st["tips"])), steps[0])
    started = {}   # (fracture, end): the first step it advanced
    for st in steps:
        for t in st["tips"]:
            if t.get("advance", 0) > 0:
                started.setdefault((t["fracture"], t["end"]), st["step"])
    theta = ", ".join(f"{t['fracture'] + number}.{t['end']}: {round(np.degrees(t['theta']), 1) + 0.0:+.1f}"
                      for t in first["tips"] if t.get("advance", 0) > 0)
    wings = [np.asarray(f["points"]) for f in s["fractures"] if f["origin"] == "wing"]
    total = sum(float(np.linalg.norm(np.diff(w, axis=0), axis=1).sum()) for w in wings)
    linked = "; ".join(f"{f + number}.{e} -> {'edge' if h is None else h + number} (step {k})"
                       for f, e, k, h in joins(s)) or "none"
    pressed = ""
    if any(steps[-1].get("pressures") or [0.0]):
        p = np.asarray(steps[-1]["pressures"], dtype=float)
        pressed = ", ".join(str(i + number) for i in np.flatnonzero(p > 0))
        peak = max(st["load_factor"] for st in steps)
        pressed += f" (peak {load_at(case, peak)})"
    solves = [st.get("solves", 1) for st in steps]
    return (f"| `{name}` | {load_at(case, first['load_factor'])} (step {first['step']}) | {theta} | "
            f"{len(started)}: {', '.join(f'{f + number}.{e} ({k})' for (f, e), k in sorted(started.items()))}; "
            f"wings {total:.3g} m | {linked} | "
            f"{pressed or '-'} | {len(steps)}: {s['status']} | {np.mean(solves):.1f} (max {max(solves)}) | "
            f"{wall:.0f} s |")


def main(argv=None, runs: dict | None = None) -> None:
    """The table; with `runs` ({name: propagation.run_case result}, as
    benchmarks/cases.py made them) the table of those runs, read, not run
    again (a case of the table not among them is left out)."""
    argv = sys.argv[1:] if argv is None else argv
    keep = Path(argv[0]) if argv else None
    names = argv[1:] or CASES
    with tempfile.TemporaryDirectory() as tmp:
        base = keep or Path(tmp)
        print("\n| case | first wings at | kink (deg) | tips grown (from step) | joined (tip -> fracture) | "
              "pressurised at the end | steps: status | solves per step | wall |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name, r in table_runs(names, runs, base):
            print(row(name, r["out"], r["wall"], 0 if name == "stimulation_network" else 1), flush=True)


if __name__ == "__main__":
    main()
