"""The viscosity-dominated KGD verification (tests/verification/
test_flow_kgd_viscous.py) with the tip size and the growth step: the
largest error of l(t), of the opening w0 and of the net pressure p0 at the
injection point from 60 s on (a decade of time and more), against the
M-vertex (tests/references.py KGDViscosity); the figures
docs/theory/fluid-pressure.md quotes.

    python benchmarks/kgd_viscous_convergence.py [--json OUT.json]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests"), str(ROOT / "tests" / "verification")]

import wingcrack  # noqa: E402
from references import KGDViscosity  # noqa: E402
from test_flow_kgd_viscous import EP, ETA, Q, errors, viscous_kgd  # noqa: E402
from wingcrack.case import Case  # noqa: E402

#: (tip_size, growth step) (m), each run to l = 14 m
RUNS = [(0.2, 0.5), (0.2, 0.25), (0.1, 0.5), (0.4, 0.5)]


def measure(ref, tip: float, dl: float) -> dict:
    """One run of RUNS: its largest errors from 60 s on, printed as a row."""
    t0 = time.perf_counter()
    run = wingcrack.run(Case.from_dict(viscous_kgd(steps=int(round(13.5 / dl)), tip_size=tip, length=dl)),
                        plots=False)
    t, el, ew, ep = errors(run, ref)
    largest = [float(np.abs(e).max()) if len(e) else float("nan") for e in (el, ew, ep)]
    row = {"tip_size": tip, "step": dl, "status": run.status, "times": [float(t[0]), float(t[-1])] if len(t) else [],
           "l": largest[0], "w0": largest[1], "p0": largest[2], "seconds": time.perf_counter() - t0}
    span = f"{row['times'][0]:.0f}-{row['times'][1]:.0f}" if row["times"] else "-"
    print(f"| {tip:g} | {dl:g} | {run.status[:40]} | {span} | {row['l']:.2%} | {row['w0']:.2%} | {row['p0']:.2%} | "
          f"{row['seconds']:.0f} |", flush=True)
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    ref = KGDViscosity(EP, ETA, Q)
    print("| tip_size (m) | step (m) | status | t (s) | l(t) | w0 | p0 | s |\n|---|---|---|---|---|---|---|---|")
    rows = [measure(ref, tip, dl) for tip, dl in RUNS]
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
