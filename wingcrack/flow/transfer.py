"""The fluid carried from one mesh of the fractures to the next (remeshing
after growth) and through a checkpoint: by arc length along each fracture.

A fracture's arc length s is measured from its first pre-existing point
(negative along the wing grown from its first end): growth adds points at
the ends, so s of a point of the faces does not change from mesh to mesh.
The fluid is sampled per fracture as its pressure, its fluid per metre of
fracture (a node's fluid over the length it stands for) and the time fluid
first reached it (Carter's), at the nodes of its edges. On the next mesh
each node takes the samples' linear interpolation along its fractures (the
mean where fractures meet); beyond the last sample (the new crack a tip
grew) no fluid yet and the time now. The fluid is then scaled to the total
it was: the network's fluid is conserved exactly. The pressure, a shape for
the caller to balance against the new geometry's mechanics, is the samples'
stretched over the new extent (the old tips' pressure at the new tips).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import wingcrack_kernels as K

from .lubrication import FlowState
from .network import FlowNetwork


@dataclass
class Samples:
    """The fluid along the fractures, free of any mesh: {fracture: (s, p,
    fluid per metre, exposed)} arrays sorted by s, the time, the totals
    injected and leaked and the fluid held at the start."""
    along: dict
    time: float
    injected: float
    leaked: float
    initial: float

    @property
    def total(self) -> float:
        """The fluid held now (m^2 per metre at rho0)."""
        return self.initial + self.injected - self.leaked

    def to_dict(self) -> dict:
        return {"along": {str(f): [a.tolist() for a in arrays] for f, arrays in self.along.items()},
                "time": self.time, "injected": self.injected, "leaked": self.leaked, "initial": self.initial}

    @classmethod
    def from_dict(cls, d: dict) -> "Samples":
        along = {int(f): tuple(np.asarray(a, float) for a in arrays) for f, arrays in d["along"].items()}
        return cls(along, float(d["time"]), float(d["injected"]), float(d["leaked"]), float(d["initial"]))


def arc_lengths(net: FlowNetwork, fractures) -> np.ndarray:
    """(k, 3) the arc length s of each edge node along its edge's fracture
    (fractures: anything with .points and, for a growing one, .pre, the
    indices of its first and last pre-existing points)."""
    out = np.zeros((net.num_edges, 3))
    for f in np.unique(net.fracture):
        fr = fractures[int(f)]
        pts = np.asarray(fr.points, float)
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        cum = np.r_[0.0, np.cumsum(seg)]
        anchor = cum[getattr(fr, "pre", (0, 0))[0]]
        rows = np.flatnonzero(net.fracture == f)
        nodes = np.unique(net.edges[rows])
        s = np.empty(len(nodes))
        for j, node in enumerate(nodes):
            _, _, k, t = K.closest_point_on_polyline(net.x[node], pts)
            s[j] = cum[k] + t * seg[k] - anchor
        lookup = dict(zip(nodes.tolist(), s))
        out[rows] = np.vectorize(lookup.get)(net.edges[rows])
    return out


def sample(net: FlowNetwork, state: FlowState, fractures, lengths: np.ndarray) -> Samples:
    """The state's fluid along the fractures of `net` (lengths: the nodes'
    tributary lengths, Lubrication.lengths)."""
    s = arc_lengths(net, fractures)
    along = {}
    density = state.fluid / np.maximum(lengths, 1e-300)
    for f in np.unique(net.fracture):
        rows = np.flatnonzero(net.fracture == f)
        nodes, first = np.unique(net.edges[rows].ravel(), return_index=True)
        sf = s[rows].ravel()[first]
        order = np.argsort(sf)
        n = nodes[order]
        along[int(f)] = (sf[order], state.pressure[n], density[n], state.exposed[n])
    return Samples(along, state.time, state.injected, state.leaked, state.initial)


def carry(samples: Samples, net: FlowNetwork, fractures, lengths: np.ndarray) -> FlowState:
    """The state on `net` (a new mesh of the fractures) that the samples
    give (module doc): its fluid totals those of the samples."""
    s = arc_lengths(net, fractures)
    n = net.num_nodes
    p, rho, exposed, count = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    for f in np.unique(net.fracture):
        rows = np.flatnonzero(net.fracture == f)
        nodes, first = np.unique(net.edges[rows].ravel(), return_index=True)
        sf = s[rows].ravel()[first]
        if int(f) in samples.along:
            s0, p0, r0, e0 = samples.along[int(f)]
            outside = (sf < s0[0] - 1e-12 * max(1.0, abs(s0[0]))) | (sf > s0[-1] + 1e-12 * max(1.0, abs(s0[-1])))
            # the pressure's shape stretched over the new extent (the old tips' to the new tips)
            lo, hi = min(sf.min(), s0[0]), max(sf.max(), s0[-1])
            stretched = s0[0] + (sf - lo) * (s0[-1] - s0[0]) / (hi - lo) if hi > lo else sf
            p[nodes] += np.interp(stretched, s0, p0)
            rho[nodes] += np.where(outside, 0.0, np.interp(sf, s0, r0))
            exposed[nodes] += np.where(outside, samples.time, np.interp(sf, s0, e0))
        else:   # a fracture the fluid has not reached
            exposed[nodes] += samples.time
        count[nodes] += 1
    count = np.maximum(count, 1)
    p, rho, exposed = p / count, rho / count, exposed / count
    fluid = rho * lengths
    total = float(fluid.sum())
    if total > 0:
        fluid *= samples.total / total
    return FlowState(samples.time, p, fluid, samples.injected, samples.leaked, exposed, samples.initial)
