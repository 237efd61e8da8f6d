"""From the case's [[bc]], [body] and [stress] tables to Loads, the record the
fem layer assembles."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Loads:
    """What loads the body, in CrackMesh node indices and boundary tags.

    Entries of the first four lists are multiplied by the load factor; the
    body force and in-situ stress are not.
    """
    point_forces: list = field(default_factory=list)          # (node, fx, fy) N/m
    point_displacements: list = field(default_factory=list)   # (node, comp, value) m
    tractions: list = field(default_factory=list)             # (tag, tx, ty) Pa
    boundary_displacements: list = field(default_factory=list)  # (tag, comp, value) m
    body_force: tuple = (0.0, 0.0)                             # rho g, N/m^3
    sigma0: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))  # Pa
    outer_tags: tuple = ()                                     # every outer boundary tag


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
