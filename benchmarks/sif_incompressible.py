"""Displacement correlation against the interaction integral as plane
strain approaches incompressibility (not a test; docs/theory/method.md quotes it).

A Griffith crack (2a = 2 m, at 45 degrees to a uniaxial remote tension of
1 MPa in a plate 100a wide, plane strain, the mesh of
tests/verification/test_sif_griffith.py) is solved once for each Poisson ratio. Exact:
KI = KII = sigma sqrt(pi a) / 2. Printed: the relative errors of both
methods against it, and their disagreement max(|KI - KI_M|, |KII - KII_M|)
/ K_M, the quantity wingcrack warns about above 1 %.

    .venv/bin/python benchmarks/sif_incompressible.py
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

NUS = (0.25, 0.4, 0.45, 0.49, 0.495, 0.497, 0.499, 0.4999)
SIGMA, A, BETA = 1.0e6, 1.0, 45.0


def case(nu):
    from builders import square_plate_with_cracks

    from wingcrack.case import Case

    t = np.array([np.sin(np.radians(BETA)), np.cos(np.radians(BETA))])
    return Case.from_dict(square_plate_with_cracks(100 * A, [[-A * t, A * t]], (0.0, SIGMA, 0.0), size=10 * A,
                                                   tip_size=0.05 * A, nu=nu))


def measure(nu) -> dict:
    from wingcrack.step import solve_initial

    k = SIGMA * np.sqrt(np.pi * A)
    KI, KII = k * np.sin(np.radians(BETA)) ** 2, k * np.sin(np.radians(BETA)) * np.cos(np.radians(BETA))
    tips = solve_initial(case(nu)).tips
    dc = max(max(abs(t.KI - KI), abs(t.KII - KII)) for t in tips) / k
    m = max(max(abs(t.KI_M - KI), abs(t.KII_M - KII)) for t in tips) / k
    off = max(max(abs(t.KI - t.KI_M), abs(t.KII - t.KII_M)) / np.hypot(t.KI_M, t.KII_M) for t in tips)
    return {"nu": nu, "dc": dc, "m": m, "off": off}


def main() -> None:
    print("Griffith crack at 45 degrees, plane strain: error of each method against the exact K (of K),")
    print("and their disagreement (of K_M)")
    print(f"{'nu':>7s} {'correlation':>12s} {'interaction':>12s} {'disagree':>9s}")
    for nu in NUS:
        r = measure(nu)
        print(f"{r['nu']:7g} {100 * r['dc']:11.2f}% {100 * r['m']:11.2f}% {100 * r['off']:8.2f}%")


if __name__ == "__main__":
    main()
