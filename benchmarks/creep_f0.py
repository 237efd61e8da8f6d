"""The published code's 1 % load creep, applied after the fact to a run's
critical load factors (docs/paper.md, section 4.2's f0 rows).

    python benchmarks/creep_f0.py OUT [OUT ...]     # folders written by `wingcrack run`

For a positively homogeneous case (traction and force loads only, no gap,
no in-situ stress, no gravity: the discs) the kink angles and each tip's
share of Lmax do not depend on the load, so the path is the same under any
load rule; the creeping load of a step is then the smallest
lam0 (1 + c)^m at or above that step's critical factor, never lowered.
Prints the peak creeping load for two starting loads lam0 against the
run's own peak critical factor.
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

CREEP = 0.01


def creeping_peak(critical: list[float], start: float, creep: float = CREEP) -> float:
    lam, peak = start, start
    for c in critical:
        while lam < c * (1 - 1e-12):
            lam *= 1 + creep
        peak = max(peak, lam)
    return peak


def main(folders) -> None:
    for folder in folders:
        steps = json.loads((Path(folder) / "summary.json").read_text())["steps"]
        critical = [s["load_factor"] for s in steps]
        for start in (1.0, 0.5):
            peak = creeping_peak(critical, start)
            print(f"{folder}: creep from {start}: peak {peak:.4f} (critical {max(critical):.4f}, "
                  f"ratio {peak / max(critical):.4f})")


if __name__ == "__main__":
    main(sys.argv[1:])
