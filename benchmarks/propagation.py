"""A propagation run of a case for the benchmarks (not a test): the case
runs as its own `wingcrack run` process (so that its peak memory is its
own), and the summary it writes gives steps, solves, DOFs and the seconds
of every phase of every step. benchmarks/cases.py reports them.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WINGCRACK = Path(sys.executable).with_name("wingcrack")


def run_case(name: str, out: Path, case: Path | None = None, wingcrack: Path = WINGCRACK, plots: bool = False) -> dict:
    """`wingcrack run` of the case `name` (cases/<name>.toml, or the file
    `case`) into `out` as its own process, with the `wingcrack` program of
    this checkout (or another's: benchmarks/cases.py --base): exit code,
    process wall (s, start-up included), its CPU seconds (user + system, its
    gmsh worker's included: less moved by a shared machine than the wall),
    its peak RSS (MiB), the summary (empty when none was written), the tail
    of stderr, out. plots: with the pictures (benchmarks/pictures_cost.py)."""
    case = case or ROOT / "cases" / f"{name}.toml"
    out.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    err = out.with_suffix(".stderr")
    with open(err, "w") as stderr:
        # --no-plots by default: the wall time is the computation's (pictures_cost.py weighs the pictures)
        proc = subprocess.Popen([str(wingcrack), "run", str(case), "-o", str(out), "--quiet"]
                                + ([] if plots else ["--no-plots"]),
                                stdout=subprocess.DEVNULL, stderr=stderr)
        _, status, usage = os.wait4(proc.pid, 0)   # this child's own peak memory
    wall = time.perf_counter() - t0
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    return {"name": name, "exit": os.waitstatus_to_exitcode(status), "wall": wall,
            "cpu": usage.ru_utime + usage.ru_stime, "peak_mib": usage.ru_maxrss / 1024, "summary": summary, "stderr": err.read_text().strip()[-300:],
            "out": out}


def table_runs(names, runs: dict | None, base: Path):
    """(name, run) for the rows of a case table: each of `names` taken from
    `runs` ({name: run_case result}, as benchmarks/cases.py made them; a
    name not among them is left out), or run now into base/name when
    `runs` is None. A run that crashed (exit neither 0 nor 1) gets its
    failure row printed here and is not yielded."""
    for name in names:
        if runs is not None and name not in runs:
            continue
        r = runs[name] if runs is not None else run_case(name, base / name)
        if r["exit"] not in (0, 1):
            print(f"| `{name}` | exit {r['exit']}: {r['stderr']} |")
            continue
        yield name, r
