"""The records of a result, typed: a tip, the contact of a step, a step, and
the summary of a whole result (`sif` or `run`), each with .to_dict() giving
exactly its part of summary.json (see docs/case-format.md); and what the
result objects of wingcrack.sif and wingcrack.run offer beyond their fields:
tables of the tips, and the last solve's DOLFINx objects."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields

#: the mesh statistics a step record keeps (meshing.CrackMesh.stats)
MESH_STATS = ("min_quality", "min_jacobian", "nodes", "tips", "gmsh_retried", "symmetric", "far_field")


@dataclass
class TipValues:
    """A tip and its SIFs where they were computed (m, Pa m^0.5, J/m^2, rad).
    KI, KII: displacement correlation; KI_M, KII_M: the interaction integral
    (None where it had no room); G, theta, K_eq: of the SIFs that drive
    growth (propagation.sif)."""
    fracture: int
    end: int
    x: float
    y: float
    KI: float
    KII: float
    KI_M: float | None
    KII_M: float | None
    G: float
    theta: float
    K_eq: float


TIP_COLUMNS = tuple(f.name for f in fields(TipValues))


@dataclass
class TipRecord(TipValues):
    """One tip of a step in summary.json: its values (TipValues), and what
    the step did to it. state: "growing", "arrested", "joined" or
    "boundary"; advance: how far the step moved the tip (m)."""
    advance: float = 0.0
    state: str = "arrested"

    @classmethod
    def of(cls, sif: TipValues, state: str = "arrested", advance: float = 0.0) -> "TipRecord":
        """The record of a tip's values (a tip_sifs.TipSIF)."""
        return cls(**{k: getattr(sif, k) for k in TIP_COLUMNS}, advance=advance, state=state)

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class ContactRecord:
    """Contact of a step: face-node pairs, constraint rows, closed normal
    rows (closed = stick + slip), the pairs in contact that stick and that
    slip, the contact solver's iterations, the relative KKT residuals (only
    when there are rows), the relative friction residuals (only with
    coulomb rows: {bound, at_bound, direction, stick_increment, touch}),
    whether the solver fell back (contact.friction), the pairs whose cohesive
    bond broke where no state satisfies the law (broken) and the rigid
    motions of pieces no face holds and no load drives (loose; placed in
    the middle of their opening: wingcrack.floating)."""
    pairs: int
    rows: int
    closed: int = 0
    iterations: int = 0
    kkt: dict | None = None
    stick: int = 0
    slip: int = 0
    friction: dict | None = None
    fallback: bool = False
    broken: int = 0
    loose: int = 0

    def to_dict(self) -> dict:
        out = {"pairs": self.pairs, "rows": self.rows, "closed": self.closed, "stick": self.stick,
               "slip": self.slip, "iterations": self.iterations, "fallback": self.fallback}
        if self.broken:
            out["broken"] = self.broken
        if self.loose:
            out["loose"] = self.loose
        if self.kkt is not None:
            out["kkt"] = self.kkt
        if self.friction is not None:
            out["friction"] = self.friction
        return out

    @classmethod
    def from_dict(cls, c: dict) -> "ContactRecord":
        """The record as summary.json holds it; a summary written before
        friction (no stick, slip, friction, fallback) counts every closed
        pair as slipping, as frictionless and prescribed-slip pairs are."""
        closed = c.get("closed", 0)
        return cls(c["pairs"], c.get("rows", 0), closed, c.get("iterations", 0), c.get("kkt"),
                   c.get("stick", 0), c.get("slip", closed - c.get("stick", 0)), c.get("friction"),
                   bool(c.get("fallback", False)), int(c.get("broken", 0)), int(c.get("loose", 0)))


@dataclass
class StepRecord:
    """One solved step: its number, load factor, DOFs, cells, tips, contact,
    seconds per phase, mesh statistics, the solves the critical load took,
    warnings (strings: the tips where the two SIF methods disagree) and
    pressures: the fluid pressure of every fracture (Pa, by fracture index),
    the actual one the step was solved with (at its load factor, after the
    connected fractures took their group's highest); [] in a record written
    before fluid pressure, which to_dict then leaves out as it was."""
    step: int
    load_factor: float
    dofs: int
    cells: int
    tips: list            # TipRecord
    contact: ContactRecord
    seconds: dict
    mesh: dict
    solves: int = 1
    warnings: list = field(default_factory=list)
    pressures: list = field(default_factory=list)
    #: the load factor at which this step's first growing tip reaches KIc (None where not known: a fixed
    #: load, or a path-dependent response held above it); below load_factor once the held load has peaked
    critical_load_factor: float | None = None
    #: with a pump (load = "injection"): the step's time (s), its injection {injected, stored, leaked,
    #: pressure, volume, held, unstable, partly_filled, stopped, history} and its networks [{fractures, pressure,
    #: volume, length}] (propagation.injection.step_record); None otherwise
    time: float | None = None
    injection: dict | None = None
    networks: list | None = None

    def to_dict(self) -> dict:
        out = {"step": self.step, "load_factor": self.load_factor, "dofs": self.dofs, "cells": self.cells,
               "tips": [t.to_dict() for t in self.tips], "contact": self.contact.to_dict(),
               "seconds": dict(self.seconds), "mesh": dict(self.mesh), "solves": self.solves}
        if self.critical_load_factor is not None:
            out["critical_load_factor"] = float(self.critical_load_factor)
        if self.time is not None:
            out.update(time=float(self.time), injection=dict(self.injection), networks=list(self.networks))
        if self.pressures:
            out["pressures"] = [float(p) for p in self.pressures]
        if self.warnings:
            out["warnings"] = list(self.warnings)
        return out

    @classmethod
    def from_dict(cls, d: dict) -> "StepRecord":
        """The record of a step as summary.json (or a checkpoint) holds it."""
        contact = ContactRecord.from_dict(d["contact"])
        tips = [TipRecord(**{k: t[k] for k in TIP_COLUMNS}, advance=t.get("advance", 0.0),
                          state=t.get("state", "arrested")) for t in d["tips"]]
        return cls(d["step"], d["load_factor"], d["dofs"], d["cells"], tips, contact, dict(d["seconds"]),
                   dict(d.get("mesh", {})), d.get("solves", 1), list(d.get("warnings", [])),
                   [float(p) for p in d.get("pressures", [])], d.get("critical_load_factor"), d.get("time"),
                   d.get("injection"), d.get("networks"))


@dataclass
class Summary:
    """summary.json of a result: title, version, status, the finished steps
    (StepRecord), the fractures ([{points, origin, fracture}]) and warnings,
    strings about the whole result (a picture that failed, SIF methods that
    disagree) that the command line prints once each."""
    title: str
    version: str
    status: str
    steps: list           # StepRecord
    fractures: list
    warnings: list = field(default_factory=list)
    KIc: float | None = None   # the material's toughness (Pa m^0.5): the line K_eq is held against
    #: a run's: {"steps": asked, "length": the longest advance of a step (m)}, how far its tips can go
    propagation: dict | None = None

    def to_dict(self) -> dict:
        out = {"title": self.title, "version": self.version, "status": self.status,
               "steps": [s.to_dict() for s in self.steps], "fractures": self.fractures}
        if self.KIc is not None:
            out["KIc"] = float(self.KIc)
        if self.propagation is not None:
            out["propagation"] = dict(self.propagation)
        if self.warnings:
            out["warnings"] = list(self.warnings)
        return out


def tip_rows(steps) -> list[dict]:
    """One plain dict per (step, tip): the step's number, load factor, DOFs,
    and the tip's values (KI, KII: displacement correlation; KI_M, KII_M:
    interaction integral, None where it had no room; theta in rad). With a
    pump also the step's time (s) and injected volume (m^3/m), and the
    pressure (Pa), volume (m^3/m) and number of the network of the tip's
    fracture (its index in the step's networks)."""
    rows = []
    for s in steps:
        where = {f: n for n, net in enumerate(s.get("networks") or []) for f in net["fractures"]}
        for t in s["tips"]:
            row = {"step": s["step"], "load_factor": s["load_factor"], "dofs": s["dofs"]}
            if "time" in s:
                net = s["networks"][where[t["fracture"]]]
                row.update(time=s["time"], injected=s["injection"]["injected"], network=where[t["fracture"]],
                           network_pressure=net["pressure"], network_volume=net["volume"])
            row.update({k: t.get(k) for k in TIP_COLUMNS + ("state", "advance") if k in t})
            rows.append(row)
    return rows


def dataframe(rows):
    """A pandas DataFrame of `rows` (pandas is optional: ImportError says so)."""
    try:
        import pandas as pd  # optional: not a dependency of wingcrack
    except ImportError:
        raise ImportError("to_dataframe() needs pandas (pip install pandas); the same rows as plain dicts: "
                          "wingcrack.results.tip_rows(result.summary['steps'])") from None
    return pd.DataFrame(rows)


class LastSolve:
    """The last solve's DOLFINx mesh and displacement (None without a solve)."""

    problem = None

    @property
    def dolfinx_mesh(self):
        """The DOLFINx mesh of the last solve (cracks split, quarter points in place)."""
        return None if self.problem is None else self.problem.fm.mesh

    @property
    def displacement(self):
        """The last solve's displacement, a DOLFINx Function (P2 vector)."""
        return None if self.problem is None else self.problem.u
