"""The KGD verification's mesh (tests/verification/test_injection_kgd.py):
the largest error of l(t) and p over the tenfold growth, for plate sizes
and rosettes, against the closed form; the table its docstring quotes.

    python benchmarks/kgd_convergence.py [--json OUT.json]
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
from references import KGDToughness  # noqa: E402
from test_injection_kgd import EP, KIC, L0, Q, errors, kgd_dict  # noqa: E402
from wingcrack.case import Case  # noqa: E402

#: (W, tip_size), mesh.size = W / 10, no far stress
MESHES = [(1000.0, 0.4), (1000.0, 0.2), (1000.0, 0.1), (1000.0, 0.05), (200.0, 0.1), (500.0, 0.1), (2000.0, 0.1)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", type=Path)
    a = ap.parse_args(argv)
    ref = KGDToughness(EP, KIC, Q, L0)
    rows = []
    print("| W (m) | tip_size (m) | l(t) | p | DOFs | s |\n|---|---|---|---|---|---|")
    for W, tip in MESHES:
        t0 = time.perf_counter()
        run = wingcrack.run(Case.from_dict(kgd_dict(W=W, size=W / 10, tip=tip)), plots=False)
        el, ep = errors(run, ref)
        row = {"W": W, "tip_size": tip, "l": float(np.abs(el).max()), "p": float(np.abs(ep).max()),
               "dofs": [run.steps[0]["dofs"], run.steps[-1]["dofs"]], "seconds": time.perf_counter() - t0}
        rows.append(row)
        print(f"| {W:g} | {tip:g} | {row['l']:.1e} | {row['p']:.1e} | {row['dofs'][0]}-{row['dofs'][1]} | "
              f"{row['seconds']:.1f} |", flush=True)
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
