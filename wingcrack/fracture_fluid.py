"""The fluid in the fractures as one step's discretisation sees it: each
fracture's pressure at a load factor, the opening of its faces (the volume
the fluid fills), and the residual aperture of the pairs on pre-existing
faces."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contact.constraints import least_apertures, pre_existing_pairs
from .fem.nodal_functionals import NodalFunctionals
from .loads import opening_functionals


@dataclass
class FractureFluid:
    """cm: the crack mesh (meshing.CrackMesh); problem: its elastic problem
    (the load factor's pressure factor, the displacement); given: (n,) each
    fracture's given pressure at load factor 1 (Pa, cm.pair_fracture's
    indices); network: with load = "injection", (n,) bool, the injected
    network, whose pressure is the load factor (None otherwise); residual:
    (p,) each pair's residual aperture (m; a pumped case's pre-existing
    faces), or None."""
    cm: object
    problem: object
    given: np.ndarray
    network: np.ndarray | None = None
    residual: np.ndarray | None = None
    #: (p,) each pair's least aperture for the flow along the fractures (m;
    #: contact.constraints.least_apertures), or None without the flow
    least: np.ndarray | None = None
    #: with the flow along the fractures (injection.viscosity): (pressure (p,), flux (p,) at each pair, and
    #: (n,) each fracture's largest pressure) of the step's state, set by the flow; None otherwise
    flow: tuple | None = None
    _openings: object = field(default=None, repr=False)

    @classmethod
    def of(cls, case, cm, problem, fractures, network=None) -> FractureFluid:
        """The fluid of `fractures` (case Fracture or GrowingFracture, their
        face laws' pressures) meshed as `cm`; network as above."""
        residual = least = None
        if case.injection is not None and case.injection.residual_aperture:
            residual = case.injection.residual_aperture * pre_existing_pairs(cm, fractures)
            if case.injection.viscosity is not None:
                least = least_apertures(cm, fractures, case.injection.residual_aperture)
        return cls(cm, problem, np.array([float(f.law.pressure) for f in fractures]),
                   None if network is None else np.asarray(network, bool), residual, least=least)

    def pressures(self, load_factor: float) -> np.ndarray:
        """(n,) the fluid pressure of each fracture at `load_factor` (Pa; the
        given pressures times the factor that multiplies them; with
        load = "injection" the factor itself on the injected network; with
        the flow along the fractures each fracture's largest pressure)."""
        if self.flow is not None:
            return self.flow[2]
        if self.network is not None:
            return np.where(self.network, float(load_factor), self.given)
        return self.given * self.problem.loads.pressure_factor(load_factor)

    def openings(self) -> np.ndarray:
        """(n,) the integral of the normal opening [u].n over each
        fracture's faces, wings included, at the current solution (m^2 per
        metre; loads.opening_functionals: the consistent P2 integral, the
        pressure's work per unit pressure). Collective."""
        if self._openings is None:
            self._openings = NodalFunctionals(self.problem, opening_functionals(self.cm, len(self.given)))
        return self._openings.values()
