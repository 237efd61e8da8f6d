"""The Brazilian-disc SIF table of docs/verification/index.md (paper Table 2), reproducible:

    .venv/bin/python benchmarks/disc_table.py

N = K sqrt(pi) R / (f0 sqrt a), R = 42 mm, a = 5 mm, open faces, rosette
h = a/20 with 32 sectors; DC = displacement correlation, M = interaction
integral.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from builders import brazilian_disc  # noqa: E402
from references import PAPER_TABLE2, atkinson  # noqa: E402

from wingcrack.api import sif  # noqa: E402
from wingcrack.case import Case  # noqa: E402

R, A, F0 = 0.042, 0.005, 1.0e6
NORM = np.sqrt(np.pi) * R / (F0 * np.sqrt(A))

print("| phi | N_I DC | N_I M | N_I paper | N_I Atkinson | N_II DC | N_II M | N_II paper | N_II Atkinson | DOFs |")
print("|---|---|---|---|---|---|---|---|---|---|")
for phi in (0, 15, 30, 45, 60, 75, 90):
    r = sif(Case.from_dict(brazilian_disc(phi, tip_size=0.00025)))
    t = r.tips[1]
    pI, pII = PAPER_TABLE2[phi]
    aI, aII = atkinson(phi, A, R)
    print(f"| {phi} | {t.KI*NORM:.4f} | {t.KI_M*NORM:.4f} | {pI:.4f} | {aI:.4f} | "
          f"{t.KII*NORM:.4f} | {t.KII_M*NORM:.4f} | {pII:.4f} | {aII:.4f} | {r.dofs} |")
