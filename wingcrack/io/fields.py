"""Field files that ParaView opens: XDMF with displacement and von Mises stress.

The mesh is P2 (curved rim, quarter points), so the fields are written as P2
functions on it; von Mises stress (of the total stress) is interpolated into
P2 for display only.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.io import XDMFFile


def von_mises(problem) -> fem.Function:
    msh = problem.fm.mesh
    S = fem.FunctionSpace(msh, ("Lagrange", 2))
    s = problem.stress(problem.u, total=True)
    # in-plane von Mises (plane stress form): sqrt(sxx^2 - sxx syy + syy^2 + 3 sxy^2)
    vm = ufl.sqrt(s[0, 0] ** 2 - s[0, 0] * s[1, 1] + s[1, 1] ** 2 + 3 * s[0, 1] ** 2)
    expr = fem.Expression(vm, S.element.interpolation_points())
    f = fem.Function(S, name="von_mises")
    f.interpolate(expr)
    return f


def write_fields(path: Path, problem, time: float = 0.0) -> Path:
    """Write mesh, displacement and von Mises stress to `path` (.xdmf + .h5)."""
    path = Path(path)
    msh = problem.fm.mesh
    vm = von_mises(problem)
    with XDMFFile(msh.comm, str(path), "w") as xf:
        xf.write_mesh(msh)
        xf.write_function(problem.u, time)
        xf.write_function(vm, time)
    return path
