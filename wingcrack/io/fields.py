"""Field files that ParaView opens: VTU (meshio) of the P2 mesh with nodal
displacement (x, y, 0), total stress as a 3 x 3 tensor (nine components,
which ParaView treats as a tensor: sxx, sxy, 0, sxy, syy, 0, 0, 0, 0; the
out-of-plane stress is not computed and is written as 0) and the von Mises
stress of the in-plane components.

The stress is singular at a crack tip (1/sqrt(r)): what a tip node holds is
a convention, finite (fem/nodal_fields.py): the mean over the tip's rosette
cells of the stress at each cell's Gauss point nearest the tip (about h/9
from it, h the rosette radius). Every value written is finite (io/vtu.py
refuses a file with a NaN or inf).

DOLFINx 0.5's XDMF writer pulls mesh nodes back to the reference cell with a
Newton iteration, which cannot converge in quarter-point cells (their
Jacobian vanishes at the tip); writing the CrackMesh nodes directly avoids
that and keeps the file in the mesh's own node numbering. The fem layer
gathers the values on rank 0 (fem/nodal_fields.py), which writes the file
(io/vtu.py: meshio's layout, with the field data, in one pass).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import vtu


def stress_tensor(s: np.ndarray) -> np.ndarray:
    """(n, 9) row-major 3 x 3 tensors from (n, 3) rows (sxx, syy, sxy)."""
    t = np.zeros((len(s), 9))
    t[:, 0], t[:, 4] = s[:, 0], s[:, 1]
    t[:, 1] = t[:, 3] = s[:, 2]
    return t


def write_field_arrays(path: Path, cm, fields: dict | None, field_data: dict | None = None) -> Path:
    """Write the CrackMesh `cm` with `fields` ({"displacement": (n, 2) m,
    "stress": (n, 3) (sxx, syy, sxy) Pa, "von_mises": (n,) Pa} by node) to
    `path` (.vtu); `field_data` ({name: number}, e.g. the step and its load
    factor) goes into the file's field data. Nothing is written where
    `fields` is None (the ranks but 0 of a parallel run)."""
    path = Path(path)
    if fields is not None:
        points = np.c_[cm.x, np.zeros(len(cm.x))]
        disp = np.c_[fields["displacement"], np.zeros(len(cm.x))]
        vtu.write_vtu(path, points, [("triangle6", np.asarray(cm.cells))],
                  {"displacement": disp, "stress": stress_tensor(fields["stress"]), "von_mises": fields["von_mises"]},
                  field_data=field_data)
    return path
