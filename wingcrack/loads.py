"""From the case's [[bc]], [body] and [stress] tables to the fem layer's Loads."""
from __future__ import annotations

import numpy as np

from .fem.elasticity import Loads


def case_loads(case, cm) -> Loads:
    """Loads on the CrackMesh `cm`; its `point_nodes` follow `case.bc_points()`."""
    loads = Loads()
    points = np.asarray(case.bc_points(), float).reshape(-1, 2)
    for bc in case.bcs:
        comps = [c for c in (0, 1) if bc.components[c]]
        if bc.at is not None:
            node = int(cm.point_nodes[int(np.argmin(np.linalg.norm(points - np.asarray(bc.at), axis=1)))])
            if bc.kind == "force":
                loads.point_forces.append((node, float(bc.value[0]), float(bc.value[1])))
            elif bc.kind == "displacement":
                loads.point_displacements += [(node, c, float(bc.value[c])) for c in comps]
        else:
            tag = int(cm.boundary_names[bc.on])
            if bc.kind == "traction":
                loads.tractions.append((tag, float(bc.value[0]), float(bc.value[1])))
            elif bc.kind == "displacement":
                loads.boundary_displacements += [(tag, c, float(bc.value[c])) for c in comps]
    rho = float(case.material.density)
    g = case.body.gravity
    loads.body_force = (rho * float(g[0]), rho * float(g[1]))
    loads.sigma0 = np.asarray(case.stress.tensor(), float)
    loads.outer_tags = tuple(int(t) for t in sorted(set(cm.boundary_names.values())))
    return loads
