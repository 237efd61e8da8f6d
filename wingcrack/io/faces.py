"""The fracture faces as a polyline file (VTU, io/vtu.py): at every face
node of the + face, the opening, slip, tractions, contact state, slip
increment and fluid pressure of its face-node pair.

Point data of faces_XXXX.vtu (zero at the tips, which are not pairs):

    opening              w = [u].n (m, > 0 open)
    slip                 s = [u].t (m)
    normal_traction      t_n = sigma_nn = n.sigma.n (Pa, <= 0 in contact; 0 without
                         a normal row)
    tangential_traction  t_t = sigma_nt = t.sigma.n (Pa; 0 without a tangential
                         row): the shear stress on the face plane, signed as the
                         slip it drives; the - side's friction on the + face,
                         -t_t t, opposes the slip increment, so t_t has its sign
    slip_increment       s - s_reference (m): the slip since the last converged
                         state, what the friction law acted on (0 on non-coulomb pairs)
    state                OPEN = 0, STICK = 1, SLIP = 2 (Int8), the codes of
                         wingcrack.contact.friction; the file's field data
                         repeat them as state_open, state_stick, state_slip
    closed               1.0 where the pair is in contact (stick or slip), else 0.0
    pressure             p (Pa, >= 0): the fluid pressure of the pair's fracture
                         at the step's load, pushing both faces apart (total
                         face traction = contact traction - p n)
    aperture             w + g + w_r (m): the space the fluid fills, the opening
                         plus the initial gap g of contact faces plus the
                         residual aperture w_r of a pumped case (its
                         injection.residual_aperture); the integral of it
                         along a fracture is its volume

[u] = u(+) - u(-), n the pair normal (left normal of the fracture direction
d), t = d (docs/architecture.md). Frictionless and prescribed-slip pairs in
contact are SLIP (their tangential traction is 0, the bound, or prescribed);
pairs without a contact row are OPEN.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import vtu

#: the contact state of a pair (the codes of wingcrack.contact.friction)
OPEN, STICK, SLIP = 0, 1, 2
STATE_NAMES = {OPEN: "open", STICK: "stick", SLIP: "slip"}
#: what a face file's field data say about the state codes
STATE_CODES = {f"state_{name}": code for code, name in STATE_NAMES.items()}
#: the face values (step.Discretisation.face_values) a face file holds per node
FLOAT_FIELDS = ("opening", "slip", "normal_traction", "tangential_traction", "slip_increment", "closed",
                "pressure", "aperture")


def face_state(cm, values: dict) -> dict:
    """Per pair of `cm` (a CrackMesh): position, opening w = [u].n, slip
    s = [u].t (m), normal and tangential traction (Pa), slip increment (m),
    state (int8), closed (bool), fluid pressure (Pa) and aperture (m), from
    the face values of step.Discretisation.face_values: {"jump": (p, 2) [u],
    "normal_traction", "tangential_traction", "state", "slip_increment",
    "closed", "pressure", "aperture": (p,)} (values without "pressure": no
    fracture is pressurised; without "aperture": the opening)."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    n = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    t = np.c_[n[:, 1], -n[:, 0]]
    jump = np.asarray(values["jump"], float).reshape(-1, 2)
    state = np.asarray(values["state"], dtype=np.int8)
    if state.size and not np.isin(state, list(STATE_NAMES)).all():
        raise ValueError(f"face states must be {OPEN} (open), {STICK} (stick) or {SLIP} (slip), "
                         f"not {sorted(set(state.tolist()) - set(STATE_NAMES))}")
    opening = np.sum(jump * n, axis=1)
    return {"position": np.asarray(cm.x)[pairs[:, 0]], "opening": opening,
            "aperture": np.asarray(values.get("aperture", opening), float),
            "slip": np.sum(jump * t, axis=1), "normal_traction": np.asarray(values["normal_traction"], float),
            "tangential_traction": np.asarray(values["tangential_traction"], float),
            "slip_increment": np.asarray(values["slip_increment"], float), "state": state,
            "closed": np.asarray(values["closed"], bool),
            "pressure": np.asarray(values.get("pressure", np.zeros(len(pairs))), float), "plus": pairs[:, 0]}


def write_faces(path: Path, cm, values: dict, field_data: dict | None = None) -> Path:
    """line3 cells of the + faces of `cm`; point data at the + face nodes
    (see the module doc; zero, OPEN, at tips, which are not pairs) from the
    pair values of face_state; `field_data` ({name: number}) as in
    write_field_arrays, and the state codes."""
    st = face_state(cm, values)
    edges = np.asarray(cm.crack_edges, dtype=np.int64)
    nodes, local = np.unique(edges, return_inverse=True)
    # the + node of each pair among the face nodes (every + node is one)
    where = np.minimum(np.searchsorted(nodes, st["plus"]), max(len(nodes) - 1, 0))
    on_face = (nodes[where] == st["plus"]) if len(nodes) else np.zeros(len(st["plus"]), bool)
    data = {k: np.zeros(len(nodes)) for k in FLOAT_FIELDS}
    for k in data:
        data[k][where[on_face]] = st[k][on_face]
    data["state"] = np.full(len(nodes), OPEN, dtype=np.int8)
    data["state"][where[on_face]] = st["state"][on_face]
    pts = np.c_[np.asarray(cm.x)[nodes], np.zeros(len(nodes))]
    frac = np.asarray(cm.crack_fracture, dtype=np.int64)
    return vtu.write_vtu(path, pts, [("line3", local.reshape(-1, 3))], data, cell_data={"fracture": [frac]},
                     field_data={**(field_data or {}), **STATE_CODES})
