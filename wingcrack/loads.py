"""From the case's [[bc]], [body] and [stress] tables to Loads, the record the
fem layer assembles."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import sparse

from .contact.constraints import edge_integrals


@dataclass
class Loads:
    """What loads the body, in CrackMesh node indices and boundary tags.

    Entries of the first four lists are multiplied by the load factor; the
    body force and in-situ stress are not. face_forces, the fluid pressure
    of the fractures on their faces, is multiplied by the load factor with
    `load = "scale"` and "pressure"; with "pressure" nothing else is
    (mode: bc_factor, pressure_factor). With "injection" face_forces are
    those of a unit pressure on the injected network's fractures, so that
    the load factor is the network's pressure (Pa), and fixed_face_forces
    the given pressures of the others; nothing else is scaled.
    """
    point_forces: list = field(default_factory=list)          # (node, fx, fy) N/m
    point_displacements: list = field(default_factory=list)   # (node, comp, value) m
    tractions: list = field(default_factory=list)             # (tag, tx, ty) Pa
    boundary_displacements: list = field(default_factory=list)  # (tag, comp, value) m
    body_force: tuple = (0.0, 0.0)                             # rho g, N/m^3
    sigma0: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))  # Pa
    outer_tags: tuple = ()                                     # every outer boundary tag
    face_forces: np.ndarray = None                             # (n_nodes, 2) N/m of the pressures
    fixed_face_forces: np.ndarray = None                       # (n_nodes, 2) N/m of pressures not scaled, or None
    mode: str = "scale"                                        # propagation.load
    gauge: list = field(default_factory=list)                  # (node, comp): zero displacements that fix the
    # rigid modes of pieces only contact holds (wingcrack.floating); no reaction: their equilibrium is the contact's

    def bc_factor(self, load_factor: float) -> float:
        """What multiplies the bc values and prescribed slip."""
        return 1.0 if self.mode in ("pressure", "injection") else float(load_factor)

    def pressure_factor(self, load_factor: float) -> float:
        """What multiplies the fracture pressures (of face_forces)."""
        return float(load_factor)

    def face_forces_at(self, load_factor: float) -> np.ndarray | None:
        """(n_nodes, 2) the fluid's forces on the faces at `load_factor`, or
        None where there are none."""
        out = None
        if self.face_forces is not None and np.any(self.face_forces):
            out = self.pressure_factor(load_factor) * self.face_forces
        if self.fixed_face_forces is not None and np.any(self.fixed_face_forces):
            out = self.fixed_face_forces if out is None else out + self.fixed_face_forces
        return out


def face_pressure_forces(cm, pressures) -> np.ndarray:
    """(n_nodes, 2) nodal forces (N/m) of the fluid pressure p_f of each
    fracture f on its faces, wings included (cm.crack_fracture): +p n int N_i ds
    on the + face nodes, -p n int N_i ds on the - face nodes, n the pairs'
    normal (the left normal of the fracture direction, from the - face into
    the + side): the pressure pushes the faces apart. The consistent P2 load
    of a constant traction, integrated on the isoparametric edge (quarter
    points included)."""
    p = np.asarray(pressures, float)
    if not np.any(p):
        return np.zeros((len(cm.x), 2))
    return np.asarray(opening_functionals(cm, len(p)) @ p).reshape(-1, 2)


def opening_functionals(cm, n_fractures: int):
    """(2 n_nodes, n_fractures) sparse: column f holds the nodal forces of a
    unit pressure on fracture f's faces (face_pressure_forces; row 2 node +
    component). Its product with the nodal displacements is the integral of
    the normal opening [u].n over the fracture's faces, m^2 per metre: the
    pressure's work per unit pressure. Exact for the P2 displacement on
    the isoparametric edges (the 3-point Gauss rule integrates N_i times the
    linear Jacobian of a quarter-point edge exactly); zero at a tip, whose
    node both faces share."""
    x = np.asarray(cm.x, float)
    size = (2 * len(x), int(n_fractures))
    plus = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    if not len(plus):
        return sparse.csr_matrix(size)
    minus = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    fracture = np.asarray(cm.crack_fracture, dtype=np.int64)
    d = x[plus[:, 1]] - x[plus[:, 0]]
    n = np.c_[-d[:, 1], d[:, 0]] / np.linalg.norm(d, axis=1)[:, None]
    # orient each edge's normal as the pair normal of its mid node (a mid node is never a tip)
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    pn = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    order = np.argsort(pairs[:, 0])
    ref = pn[order[np.searchsorted(pairs[order, 0], plus[:, 2])]]
    n *= np.sign(np.sum(n * ref, axis=1))[:, None]
    w = edge_integrals(x, plus)                               # (k, 3) int N_i ds
    rows, vals = [], []
    for side, edges in ((1.0, plus), (-1.0, minus)):
        for comp in (0, 1):
            rows.append(2 * edges + comp)
            vals.append(side * w * n[:, comp][:, None])
    cols = np.broadcast_to(fracture[:, None], plus.shape)
    return sparse.csr_matrix((np.concatenate([v.ravel() for v in vals]),
                              (np.concatenate([r.ravel() for r in rows]), np.tile(cols.ravel(), 4))), shape=size)


def case_loads(case, cm, fractures=None, network=None) -> Loads:
    """Loads on the CrackMesh `cm`; its `point_nodes` follow `case.bc_points()`.
    fractures: what was meshed (case Fracture or GrowingFracture, in mesh
    order; default the case's), whose face law's pressure loads the faces;
    network: with load = "injection", (n_fractures,) bool, the injected
    network's fractures (their pressure is the load factor)."""
    loads = Loads()
    fractures = case.fractures if fractures is None else fractures
    given = np.array([float(f.law.pressure) for f in fractures])
    loads.mode = case.propagation.load
    if loads.mode == "injection":
        inside = np.asarray(network, bool)
        loads.face_forces = face_pressure_forces(cm, inside.astype(float))
        loads.fixed_face_forces = face_pressure_forces(cm, np.where(inside, 0.0, given))
    else:
        loads.face_forces = face_pressure_forces(cm, given)
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
