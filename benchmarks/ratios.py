"""A run against today's: the figures of a case run in the form of
benchmarks/baseline.json, the ratio base/new of their process walls ("x
faster") and the flags the report prints (issue 16, target 4: every case at
least 1.5x faster end to end than today, none slower)."""
from __future__ import annotations

import json
from pathlib import Path

from phases import summed

BASELINE = Path(__file__).with_name("baseline.json")
#: target 4: every case at least this much faster end to end than today
TARGET_RATIO = 1.5


def load_baseline(path: Path = BASELINE) -> dict:
    """The baseline file (`cases`: figures per case, `targets`: those of
    targets 1-3, `about`: how and when they were measured); empty tables
    when there is none."""
    if not path.exists():
        return {"about": f"no baseline ({path})", "cases": {}, "targets": {}}
    return json.loads(path.read_text())


def figures(run: dict) -> dict:
    """A run of propagation.run_case as baseline.json holds a case: process
    wall (s), peak RSS (MiB), status, steps, DOFs [first, last], phases (the
    summary's seconds summed over the steps), cpu (s, None when not measured)."""
    s = run.get("summary", {})
    steps = s.get("steps", [])
    status = s.get("status") or f"exit {run.get('exit')}: {run.get('stderr', '')[-120:]}"
    return {"wall": run["wall"], "rss_mib": run["peak_mib"], "status": status, "steps": len(steps),
            "dofs": [steps[0]["dofs"], steps[-1]["dofs"]] if steps else None, "phases": summed(steps),
            "cpu": run.get("cpu")}


def per_step_total(fig: dict) -> float | None:
    """The steps' own seconds per step (no start-up), None without steps."""
    return fig["phases"].get("total", 0.0) / fig["steps"] if fig.get("steps") else None


def compare(new: dict, base: dict | None, target: float = TARGET_RATIO) -> dict:
    """`ratio`: base wall / new wall (> 1: faster than today); `step_ratio`
    the same of the seconds per step, `cpu_ratio` of the CPU seconds (None
    unless both have them); `flags`: what the report marks (a
    failed run, slower than base, under the target ratio, another status,
    other step counts, fewer DOFs than today). None ratios without a base."""
    flags = []
    if new["status"].startswith(("failed", "exit")):
        flags.append("FAILED")
    if base is None:
        return {"ratio": None, "step_ratio": None, "cpu_ratio": None, "flags": flags + ["no baseline"]}
    ratio = base["wall"] / new["wall"] if new["wall"] > 0 else None
    b, n = per_step_total(base), per_step_total(new)
    step_ratio = b / n if b and n else None
    cpu_ratio = base["cpu"] / new["cpu"] if base.get("cpu") and new.get("cpu") else None
    if ratio is not None and ratio < 1.0:
        flags.append("SLOWER")
    elif ratio is not None and ratio < target:
        flags.append(f"under {target:g}x")
    if new["status"] != base["status"]:
        flags.append(f"status was {base['status']!r}")
    if new["steps"] != base["steps"]:
        flags.append(f"steps were {base['steps']}")
    if new.get("dofs") and base.get("dofs") and any(x < y for x, y in zip(new["dofs"], base["dofs"])):
        flags.append(f"fewer DOFs (were {base['dofs'][0]:,}/{base['dofs'][1]:,})")
    return {"ratio": ratio, "step_ratio": step_ratio, "cpu_ratio": cpu_ratio, "flags": flags}
