"""A fracture's face law: what its faces do and the fluid inside it.

One record from the case to the constraint rows: the case's fracture builds
it (case.Fracture.law), a growing fracture holds it
(propagation.fracture_set.GrowingFracture.law), the checkpoint writes and
reads it by its field names, and the constraint rows
(contact.constraints) and the face loads (loads) read it whole. It is
frozen: what changes in a run (a connected network's pressure) is a new
record, dataclasses.replace(law, pressure=p).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

FACES = ("open", "frictionless", "slip", "coulomb")
SLIP_PROFILES = ("uniform", "elliptic")


@dataclass(frozen=True)
class FaceLaw:
    """faces: "open" (traction free, no contact condition), "frictionless"
    (non-penetration w + gap >= 0), "slip" (non-penetration and the
    tangential jump prescribed: slip (m, at load factor 1) along the
    fracture, shaped by slip_profile) or "coulomb" (non-penetration, and
    the magnitude of the shear traction t_t at most cohesion + friction
    (-t_n): friction the Coulomb coefficient, cohesion in Pa). gap: the initial normal gap (m). pressure: the fluid
    pressure (Pa, at load factor 1) pushing both faces apart on every kind
    of face. The case file's keys of the same names say more."""

    faces: str = "open"
    gap: float = 0.0
    slip: float = 0.0
    slip_profile: str = "uniform"
    friction: float = 0.0
    cohesion: float = 0.0
    pressure: float = 0.0

    def wings(self) -> FaceLaw:
        """The law of the wings the fracture grows: tensile cracks (the
        paper's eq. 8) with no gap and no prescribed slip; where the fracture
        has contact they get non-penetration too, never a prescribed slip:
        a coulomb fracture's wings with its friction and cohesion (friction
        acts on every face, wings included), frictionless otherwise. The
        fluid fills them: the same pressure."""
        faces = self.faces if self.faces in ("open", "coulomb") else "frictionless"
        return FaceLaw(faces, friction=self.friction, cohesion=self.cohesion, pressure=self.pressure)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The field names, in order."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def of(cls, record) -> FaceLaw:
        """The law of anything that has these fields by name (a case
        fracture's keys)."""
        return cls(**{name: getattr(record, name) for name in cls.names()})

    def to_dict(self) -> dict:
        """{field name: value}: what a checkpoint writes."""
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> FaceLaw:
        """The law written by to_dict (other keys of `d` are ignored);
        ValueError naming the field whose value the case reader would
        refuse (a NaN would pass into the friction bound or the face loads
        unseen), KeyError for a missing one."""
        faces, profile = d["faces"], d["slip_profile"]
        if faces not in FACES:
            raise ValueError(f"faces {faces!r} is none of {', '.join(FACES)}")
        if profile not in SLIP_PROFILES:
            raise ValueError(f"slip_profile {profile!r} is none of {', '.join(SLIP_PROFILES)}")
        numbers = {name: _number(d, name, least=None if name == "slip" else 0.0)
                   for name in ("gap", "slip", "friction", "cohesion", "pressure")}
        return cls(faces, slip_profile=profile, **numbers)


def _number(d: dict, name: str, least: float | None) -> float:
    """d[name] as a float: finite, and >= least unless least is None."""
    v = d[name]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
            or (least is not None and not v >= least):
        raise ValueError(f"{name} {v!r} is not a finite number" + ("" if least is None else f" >= {least:g}"))
    return float(v)
