"""The paper's Table 1 (section 4.1) and the u = 0 columns of Tables B1 and
B2 (Appendix B), as wingcrack computes them, for docs/paper.md:

    .venv/bin/python benchmarks/paper_numbers.py [table1] [tableB]

Table 1: the edge crack of Fig. 9 with L/b = 2, b/a = 2 (strip b = 1 m wide
and L = 2 m high, crack a = 0.5 m, tension on the ends), uniform refinement
h = b/4 ... b/64 with a 16-sector rosette of radius h/2 (as in the
strain-energy test, tests/verification/test_sif_edge_crack.py). Errors: KI against Tada's
F(a/b) (accurate to 0.5 % for a/b <= 0.6, h/b >= 1), the strain energy
against its extrapolation from the two finest meshes with the fitted rate.

Tables B1/B2, u = 0: two collinear cracks of length a, inner tips 2b apart,
in a square plate of side 100 (a + b), remote tension (B1) or shear (B2);
K at an inner tip over K of the crack alone, against the exact two-crack
solution (complete elliptic integrals; the same ratio for modes I and II).
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from builders import edge_crack_strip, square_plate_with_cracks  # noqa: E402
from references import collinear_cracks, tada_edge_crack_F  # noqa: E402

from wingcrack.api import sif  # noqa: E402
from wingcrack.case import Case  # noqa: E402

PAPER_B1 = {0.02: 1.9253, 0.05: 1.4974, 0.1: 1.2854, 0.2: 1.1568, 0.5: 1.0542, 1.0: 1.0266, 1.5: 1.0153}
KACHANOV_B1 = {0.02: 1.905, 0.05: 1.473, 0.1: 1.255, 0.2: 1.112}
PAPER_B2 = {0.02: 1.8777, 0.05: 1.4968, 0.1: 1.2905, 0.2: 1.1571, 0.5: 1.0544, 1.0: 1.0242, 1.5: 1.0190}
PAPER_T1 = {4: (214, 44), 8: (678, 152), 16: (1454, 340), 32: (4970, 1196), 64: (17742, 4348)}
PAPER_T1_UNIFORM = {4: (330, 68), 8: (1106, 248), 16: (4290, 1016), 32: (16802, 4088), 64: (66402, 16376)}


def table1():
    sigma, s = 1.0e6, 0.5
    K = sigma * np.sqrt(np.pi * s) * tada_edge_crack_F(s)
    rows, U = [], []
    for k in (4, 8, 16, 32, 64):
        h = 1.0 / k
        d = edge_crack_strip(s, sigma=sigma, size=h, tip_size=0.5 * h, height=2.0)
        d["mesh"]["sectors"] = 16
        r = sif(Case.from_dict(d))
        (t,) = r.tips
        U.append(r.problem.strain_energy())
        rows.append((k, r.dofs, r.cells, t.KI / K - 1, t.KI_M / K - 1))
    U = np.array(U)
    dU = np.diff(U)
    p = np.log2(dU[-2] / dU[-1])
    U_inf = U[-1] + dU[-1] / (2 ** p - 1)
    print(f"Table 1 (edge crack L/b = 2, b/a = 2); energy rate of the last meshes {p:.2f}")
    print("| b/h | paper DOFs FEM(-QPE) / ARM | paper cells FEM / ARM | wingcrack DOFs | wingcrack cells "
          "| energy error | KI DC error | KI M error |")
    print("|---|---|---|---|---|---|---|---|")
    for (k, dofs, cells, eDC, eM), u in zip(rows, U):
        pu, pa = PAPER_T1_UNIFORM[k], PAPER_T1[k]
        print(f"| {k} | {pu[0]:,} / {pa[0]:,} | {pu[1]:,} / {pa[1]:,} | {dofs:,} | {cells:,} "
              f"| {100 * (u / U_inf - 1):.3f} % | {100 * eDC:+.2f} % | {100 * eM:+.2f} % |")


def tableB():
    print("Tables B1/B2, u = 0 (collinear cracks): K_int/K_iso at the inner tip")
    print("| b/a | B1 paper | B1 Kachanov (paper) | exact | tension DC | tension M | B2 paper | shear DC | shear M |")
    print("|---|---|---|---|---|---|---|---|---|")
    for q in (0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 1.5):
        a = 1.0
        b, c = q * a, (q + 1.0) * a
        cracks = [[[b, 0.0], [c, 0.0]], [[-c, 0.0], [-b, 0.0]]]
        kw = dict(size=10.0, tip_size=min(0.05, 0.25 * b), nu=0.25)
        exact = collinear_cracks(b, c)[0] / np.sqrt(np.pi * a / 2)
        out = []
        for load, KI in (((0.0, 1.0, 0.0), True), ((0.0, 0.0, 1.0), False)):
            pair = sif(Case.from_dict(square_plate_with_cracks(100 * c, cracks, load, **kw)))
            alone = sif(Case.from_dict(square_plate_with_cracks(100 * c, cracks[:1], load, **kw)))
            tp = [t for t in pair.tips if abs(t.x - b) < 1e-9][0]
            ta = [t for t in alone.tips if abs(t.x - b) < 1e-9][0]
            if KI:
                out += [tp.KI / ta.KI, tp.KI_M / ta.KI_M]
            else:
                out += [tp.KII / ta.KII, tp.KII_M / ta.KII_M]
        ka = KACHANOV_B1.get(q)
        print(f"| {q} | {PAPER_B1[q]:.4f} | {ka if ka else '-'} | {exact:.4f} | {out[0]:.4f} | {out[1]:.4f} "
              f"| {PAPER_B2[q]:.4f} | {out[2]:.4f} | {out[3]:.4f} |")


if __name__ == "__main__":
    which = sys.argv[1:] or ["table1", "tableB"]
    for w in which:
        {"table1": table1, "tableB": tableB}[w]()
