"""A flowing step (injection.viscosity: the fluid flows along the
fractures), as the loop sees it: the loading (loading.Fixed's face) whose
steps are states in time. On the step's geometry the flow marches
(flow_march.py) until a growing tip arrives (K_eq at KIc, or at the
apparent toughness of a moving tip, viscous_tip.py: the step grows there), a
frame time (the step is recorded, nothing grows, and the next step goes on
on the same geometry: `Found.frame`) or the end (the run stops there,
recorded). The load factor is 1: the faces carry the flow's pressure field.

A step's record holds its time, the injection {injected, stored, leaked,
pressure and opening at the point, history of its time steps [t, p, injected, stored,
leaked, slip front], steps, solves} and the network's fractures with the
pressure at the point and their volume. A committed step that grew leaves
the fluid along the fractures (flow.transfer.Samples) for the next
geometry, and the fractures its wings joined enter the network, dry (or
with their given pressure's fluid).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import wingcrack_kernels as K
from .. import progress, sifs
from ..material import e_prime
from ..flow.transfer import Samples
from .flow_march import FlowDrive, Geometry, march
from .loading import Fixed, Found, largest_keq
from .viscous_tip import TipMotion, driving_ratio


class Flowing(Fixed):
    """The flow's loading: drive (flow_march.FlowDrive, what the run carries
    from step to step and its checkpoint keeps); geo: the flow on the
    current geometry (flow_march.Geometry), kept while the geometry is."""
    unreached = None
    #: the run goes on in time where no tip may grow (frames up to the end)
    timed = True

    def __init__(self, case):
        super().__init__(case)
        self.drive = FlowDrive.of(case)
        self.geo = None
        self.out = None

    @property
    def network(self):
        return self.drive.network

    def mask(self, n: int):
        out = np.zeros(n, bool)
        out[self.drive.network] = True
        return out

    def find(self, disc, fset, grow) -> Found:
        case = self.case
        if self.geo is None or self.geo.disc is not disc:
            progress.doing("the flow on the step's faces")
            self.geo = Geometry.of(self.drive, case, disc, fset.fractures)
        polylines = fset.polylines()
        m = case.material
        Ep, mup = e_prime(m.E, m.nu, m.plane), 12.0 * self.drive.fluid.viscosity

        def keq(t):   # KIc K_eq / K_app(V): the tips' arrival (viscous_tip.py) at KIc
            KI, KII = sifs.driving(case, disc, polylines)
            keq_all = np.zeros(len(KI))
            keq_all[grow] = K.equivalent_k(KI[grow], KII[grow], K.mts_angle(KI[grow], KII[grow]))
            k = m.KIc * driving_ratio(keq_all, disc.cm.tips, grow, self.drive.motion, t, m.KIc, Ep, mup)
            sifs.require_finite("K_eq", k)
            return k

        progress.doing(f"the flow in time from {self.drive.time:.6g} s")
        self.out = out = march(self.drive, self.geo, keq if grow else None, case.material.KIc)
        self.geo.publish()
        stop = None
        if out.kind == "end":
            stop = lambda tips: self._ended(tips, grow)   # noqa: E731 - the loop calls it with the step's tips
        return Found(1.0, out.solves, stop=stop, frame=out.kind == "frame")

    def _ended(self, tips, grow) -> str:
        p = self.geo.injection_pressure()
        below = f"; the largest K_eq is {largest_keq(tips, grow, self.case.material.KIc)} KIc" if grow else ""
        return f"stopped: end_time reached: at {self.drive.end:g} s the pressure at the injection point is " \
            f"{p:.6g} Pa{below}"

    def fluid(self, disc, fset) -> FlowRecord:
        return FlowRecord.of(self, fset)

    def commit(self, fluid, done, fset) -> None:
        """done: the fractures as the step solved them. After growth the fluid
        goes on to the next geometry by arc length,
        and the fractures joined enter the network; a frame keeps both."""
        geo = self.geo
        self.drive.samples = geo.samples(done)
        if self.out is None or self.out.kind != "growth":
            return
        self.drive.motion = TipMotion.after_growth(geo.disc.cm.tips, fset, self.drive.time)
        self.geo = None
        if self.drive.connect:
            group = next(g for g in fset.connected_groups() if self.drive.fracture in g)
            self.drive.network = sorted(set(self.drive.network) | set(group))

    def state(self) -> dict:
        d = self.drive
        return {"network": list(d.network), "time": d.time, "dt": d.dt,
                "samples": None if d.samples is None else d.samples.to_dict(), "motion": d.motion.to_list()}

    def restore(self, state) -> None:
        d = self.drive
        d.network, d.time, d.dt = [int(i) for i in state["network"]], float(state["time"]), state["dt"]
        d.samples = None if state["samples"] is None else Samples.from_dict(state["samples"])
        d.motion = TipMotion.from_list(state.get("motion"))
        self.geo = None


@dataclass
class FlowRecord:
    """A flowing step's fluid for its record (its time, injection and
    network), taken at its solution before growth."""
    time: float
    injection: dict
    networks: list

    @classmethod
    def of(cls, loading: Flowing, fset) -> FlowRecord:
        geo, out = loading.geo, loading.out
        s = geo.state
        lengths = [float(np.linalg.norm(np.diff(f.points, axis=0), axis=1).sum()) for f in fset.fractures]
        p = geo.injection_pressure()
        volume = float(np.sum(geo.lub.volumes(geo.faces.w)))
        injection = {"injected": float(s.injected), "stored": float(s.stored), "leaked": float(s.leaked),
                     "pressure": p, "opening": geo.injection_opening(), "volume": volume, "held": float(s.initial),
                     "unstable": bool(out.unstable),
                     "stopped": out.kind == "end", "partly_filled": False, "steps": int(out.steps),
                     "solves": int(out.solves),
                     "history": [[float(x) for x in h] for h in out.history]}
        net = sorted(int(i) for i in loading.drive.network)
        networks = [{"fractures": net, "pressure": p, "volume": volume,
                     "length": float(sum(lengths[i] for i in net))}]
        return cls(float(s.time), injection, networks)

    def record(self) -> dict:
        return {"time": self.time, "injection": self.injection, "networks": self.networks}
