"""From the case's [[bc]], [body] and [stress] tables to Loads, the record the
fem layer assembles."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contact.constraints import edge_integrals


@dataclass
class Loads:
    """What loads the body, in CrackMesh node indices and boundary tags.

    Entries of the first four lists are multiplied by the load factor; the
    body force and in-situ stress are not. face_forces, the fluid pressure
    of the fractures on their faces, is multiplied by the load factor with
    `load = "scale"` and "pressure"; with "pressure" nothing else is
    (mode: bc_factor, pressure_factor).
    """
    point_forces: list = field(default_factory=list)          # (node, fx, fy) N/m
    point_displacements: list = field(default_factory=list)   # (node, comp, value) m
    tractions: list = field(default_factory=list)             # (tag, tx, ty) Pa
    boundary_displacements: list = field(default_factory=list)  # (tag, comp, value) m
    body_force: tuple = (0.0, 0.0)                             # rho g, N/m^3
    sigma0: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))  # Pa
    outer_tags: tuple = ()                                     # every outer boundary tag
    face_forces: np.ndarray = None                             # (n_nodes, 2) N/m of the pressures
    mode: str = "scale"                                        # propagation.load
    gauge: list = field(default_factory=list)                  # (node, comp): zero displacements that fix the
    # rigid modes of pieces only contact holds (wingcrack.floating); no reaction: their equilibrium is the contact's

    def bc_factor(self, load_factor: float) -> float:
        """What multiplies the bc values and prescribed slip."""
        return 1.0 if self.mode == "pressure" else float(load_factor)

    def pressure_factor(self, load_factor: float) -> float:
        """What multiplies the fracture pressures."""
        return float(load_factor)


def face_pressure_forces(cm, pressures) -> np.ndarray:
    """(n_nodes, 2) nodal forces (N/m) of the fluid pressure p_f of each
    fracture f on its faces, wings included (cm.crack_fracture): +p n int N_i ds
    on the + face nodes, -p n int N_i ds on the - face nodes, n the pairs'
    normal (the left normal of the fracture direction, from the - face into
    the + side): the pressure pushes the faces apart. The consistent P2 load
    of a constant traction, integrated on the isoparametric edge (quarter
    points included)."""
    x = np.asarray(cm.x, float)
    F = np.zeros((len(x), 2))
    p = np.asarray(pressures, float)
    plus = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    if not len(plus) or not np.any(p):
        return F
    minus = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    pe = p[np.asarray(cm.crack_fracture, dtype=np.int64)]
    d = x[plus[:, 1]] - x[plus[:, 0]]
    n = np.c_[-d[:, 1], d[:, 0]] / np.linalg.norm(d, axis=1)[:, None]
    # orient each edge's normal as the pair normal of its mid node (a mid node is never a tip)
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    pn = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    order = np.argsort(pairs[:, 0])
    ref = pn[order[np.searchsorted(pairs[order, 0], plus[:, 2])]]
    n *= np.sign(np.sum(n * ref, axis=1))[:, None]
    w = edge_integrals(x, plus) * pe[:, None]                # (k, 3) p int N_i ds
    for side, edges in ((1.0, plus), (-1.0, minus)):
        np.add.at(F, edges.ravel(), side * (w[:, :, None] * n[:, None, :]).reshape(-1, 2))
    return F


def case_loads(case, cm, fractures=None) -> Loads:
    """Loads on the CrackMesh `cm`; its `point_nodes` follow `case.bc_points()`.
    fractures: what was meshed (case Fracture or GrowingFracture, in mesh
    order; default the case's), whose face law's pressure loads the faces."""
    loads = Loads()
    fractures = case.fractures if fractures is None else fractures
    loads.face_forces = face_pressure_forces(cm, [float(f.law.pressure) for f in fractures])
    loads.mode = case.propagation.load
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
