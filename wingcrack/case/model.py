"""`Case`, a checked case: its parts, how it is built from a file or a
parsed table, and what the solver asks of it (length scale, tips,
junctions, the points of point conditions)."""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from meshing import admissibility
from meshing.domain import Domain
from wingcrack.case import reader
from wingcrack.case.bounds import REL_TOL
from wingcrack.case.records import BC, Body, Fracture, Injection, Material, MeshOptions, Propagation, Stress, Tip


@dataclass(frozen=True, eq=False)
class Case:
    """A checked case. Build it with `Case.from_toml(path)` or `Case.from_dict(d)`.

    Fields: title, material, domain (meshing.Domain), fractures (tuple of
    Fracture), bcs (tuple of BC, in file order), body, stress, mesh
    (MeshOptions), propagation, injection (Injection, or None without a
    pump), source (the file, or None).
    """

    title: str
    material: Material
    domain: Domain
    fractures: tuple[Fracture, ...]
    bcs: tuple[BC, ...]
    body: Body
    stress: Stress
    mesh: MeshOptions
    propagation: Propagation
    injection: Injection | None = None
    source: Path | None = field(default=None, compare=False)

    @classmethod
    def from_toml(cls, path) -> Case:
        """Read and check a case file. A file that is not a regular one (a
        directory, a FIFO, a device), unreadable files and TOML syntax errors
        are CaseError too, keyed by the file name."""
        path = Path(path)
        data = reader.load(path)
        case = cls.from_dict(data, source=path)
        if "title" not in data:
            case = replace(case, title=path.stem)
        return case

    @classmethod
    def from_dict(cls, d: dict, source: Path | None = None) -> Case:
        """Check a parsed case table (as tomllib returns it) and build the Case."""
        return cls(*reader.read_case(d), source)

    # ---- accessors the solver needs

    @property
    def length_scale(self) -> float:
        """The domain's length scale (m); tolerances are relative to it."""
        return float(self.domain.length_scale())

    def fracture_points(self) -> list[np.ndarray]:
        """Each fracture's polyline, (n, 2) float64, in case order."""
        return [f.points for f in self.fractures]

    def tips(self) -> list[Tip]:
        """Fracture ends strictly inside the domain and on no fracture (an end
        on the boundary is an edge crack's mouth, an end on a fracture a
        junction: neither is a tip), in fracture order, end 0 before end 1."""
        tol = REL_TOL * self.length_scale
        joined = admissibility.joined_ends(self.domain, self.fracture_points())
        out = []
        for i, f in enumerate(self.fractures):
            for end, p in ((0, f.points[0]), (1, f.points[-1])):
                if not self.domain.on_boundary(p, tol) and (i, end) not in joined:
                    out.append(Tip(i, end, (float(p[0]), float(p[1]))))
        return out

    def junctions(self) -> list[tuple[float, float]]:
        """The points where fractures meet (an end on a fracture, ends met end
        to end, a crossing), as the mesher joins them."""
        net = admissibility.joined(self.domain, self.fracture_points())
        return sorted((float(x), float(y)) for x, y in net.node_points())

    def network_at_start(self) -> np.ndarray:
        """(n_fractures,) bool: the injected fracture and every fracture it
        meets (at a T, end to end, at an X), directly or through others: the
        network the pump fills at t = 0. All False without a pump."""
        out = np.zeros(len(self.fractures), bool)
        if self.injection is not None:
            net = admissibility.joined(self.domain, self.fracture_points())
            out[net.group_of(self.injection.fracture)] = True
        return out

    def at_start(self) -> Case:
        """The case as `sif` solves it: with a pump, its network at the
        initial pressure and every load as given (load = "fixed"); the case
        itself without one."""
        if self.injection is None:
            return self
        p0 = self.injection.initial_pressure
        inside = self.network_at_start()
        fractures = tuple(replace(f, pressure=p0) if inside[i] else f for i, f in enumerate(self.fractures))
        return replace(self, fractures=fractures, propagation=replace(self.propagation, load="fixed"), injection=None)

    def bc_points(self) -> list[np.ndarray]:
        """The distinct points of point conditions (`at`), to embed in the mesh."""
        tol = REL_TOL * self.length_scale
        pts: list[np.ndarray] = []
        for bc in self.bcs:
            if bc.at is None:
                continue
            p = np.array(bc.at, dtype=float)
            if all(np.linalg.norm(p - q) > tol for q in pts):
                pts.append(p)
        return pts
