"""Propagation runs of the paper's cases for `make bench` (not a test).

Each case runs as its own `wingcrack run` process (so that its peak memory
is its own), and the summary it writes gives steps, solves, DOFs and the
seconds of every phase of every step.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
WINGCRACK = Path(sys.executable).with_name("wingcrack")

#: (case, what the issue asks of it)
CASES = [
    ("brazilian_disc_45_open", "to the rim, 77 steps, in ~30 s (published code: 255 s for 34 steps)"),
    ("brazilian_disc_45", "with frictionless contact"),
    ("brazilian_disc_45_friction", "with Coulomb friction 0.5: solves per step of the search <= 8"),
    ("multi_fractures_shear", "35 steps under 120 s and 1.5 GB (published code: 16 steps in 1,426 s, 7.1 GB)"),
    ("three_fractures_slip", "slip on the middle fracture"),
    ("three_fractures_injection", "4.3 driven by injection into the middle fracture, mu = 0.6 on all"),
    ("stimulation_network", "the showcase: injection into a 16-fracture network, 50 steps in under 3 minutes"),
]
PHASES = ["mesh", "to_dolfinx", "assemble", "factorize", "contact", "solve", "sif", "growth", "estimate", "output"]


def run_case(name: str, out: Path) -> dict:
    t0 = time.perf_counter()
    err = out.with_suffix(".stderr")
    with open(err, "w") as stderr:
        # --no-plots: the wall time is the computation's (the pictures add ~0.2 s a step)
        proc = subprocess.Popen([str(WINGCRACK), "run", str(ROOT / "cases" / f"{name}.toml"), "-o", str(out),
                                 "--quiet", "--no-plots"], stdout=subprocess.DEVNULL, stderr=stderr)
        _, status, usage = os.wait4(proc.pid, 0)   # this child's own peak memory
    wall = time.perf_counter() - t0
    summary = json.loads((out / "summary.json").read_text()) if (out / "summary.json").exists() else {}
    return {"name": name, "exit": os.waitstatus_to_exitcode(status), "wall": wall,
            "peak_mib": usage.ru_maxrss / 1024, "summary": summary, "stderr": err.read_text().strip()[-300:]}


def report(r: dict, target: str) -> None:
    s = r["summary"]
    steps = s.get("steps", [])
    print(f"\n{r['name']}: {target}")
    print(f"  status: {s.get('status', '?')} (exit {r['exit']}); {len(steps)} steps, "
          f"{sum(st.get('solves', 1) for st in steps)} solves")
    if not steps:
        print(f"  {r['stderr']}")
        return
    print(f"  DOFs first/last: {steps[0]['dofs']:,} / {steps[-1]['dofs']:,}; "
          f"wall {r['wall']:.1f} s (process, with start-up and form compilation); "
          f"peak RSS {r['peak_mib']:.0f} MiB")
    total = sum(st["seconds"].get("total", 0.0) for st in steps)
    print(f"  per step: {total / len(steps):.3f} s")
    for p in PHASES:
        t = sum(st["seconds"].get(p, 0.0) for st in steps)
        if t > 0:
            print(f"    {p:11s} {t / len(steps):7.3f} s  {100 * t / total:5.1f} %")


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        for name, target in CASES:
            report(run_case(name, Path(tmp) / name), target)


if __name__ == "__main__":
    main()
