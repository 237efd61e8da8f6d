"""The rules across keys and the geometric admissibility of a case: the
mesher's rules (meshing/admissibility.py) speak in the case file's keys, so
a problem they find is the case's error; and what ties keys together (mesh
sizes against the domain, slip fractures that meet, displacement conditions
that conflict where their places meet, Lmax against the rosettes, injection
with a pressure, the pump against the load mode and the fractures)."""
from __future__ import annotations

import math

import numpy as np

import wingcrack_kernels as _kernels  # geometry predicates (C++)
from meshing import admissibility
from wingcrack.case.bounds import MAX_ELEMENTS
from wingcrack.case.bounds import REL_TOL
from wingcrack.case.records import BC, Injection, MeshOptions, Propagation
from wingcrack.errors import CaseError
from wingcrack.shortest_advance import length_problem

def refuse(problem: admissibility.Problem | None) -> None:
    """The mesher's rules speak in the case file's keys: a problem is the case's error."""
    if problem is not None:
        raise CaseError(problem.key, problem.message)


def check_scale(size: float, offset: float, size_key: str, offset_key: str) -> None:
    refuse(admissibility.scale(size, offset, size_key, offset_key))


def check_polygon(pts: np.ndarray, key: str) -> None:
    refuse(admissibility.polygon(pts, key))


def check_mesh_against_domain(mesh: MeshOptions, domain) -> None:
    """Sizes the mesher can honour in this domain: not too many triangles, a
    rosette well above the geometric tolerance."""
    cells = domain.area() / (math.sqrt(3) / 4 * mesh.size**2)
    if cells > MAX_ELEMENTS:
        raise CaseError("mesh.size", f"{mesh.size:g} m asks for about {cells:.2g} elements in this domain of "
                                     f"{domain.area():.4g} m^2 (at most {MAX_ELEMENTS:.2g}): use a larger size")
    refuse(admissibility.tip_size(mesh.tip_size, domain))


def check_slip_junctions(fractures, domain) -> None:
    """Two fractures with prescribed slip do not meet: at their junction the
    node copies' jumps sum to zero around it, so the slip rows of both
    fix more components than the copies have (the pair system is singular)."""
    slip = [i for i, f in enumerate(fractures) if f.faces == "slip"]
    if len(slip) < 2:
        return
    net = admissibility.joined(domain, [f.points for f in fractures])
    for members in net.nodes.values():
        met = sorted({f for f, _ in members if fractures[f].faces == "slip"})
        if len(met) > 1:
            f, v = members[0]
            x = net.polylines[f][v]
            raise CaseError(f"fractures[{met[1]}].faces", f'"slip" fractures[{met[1]}] meets "slip" '
                            f"fractures[{met[0]}] at ({x[0]:.6g}, {x[1]:.6g}): two prescribed slips over-determine "
                            "the faces' jumps at a junction; give one of them other faces")


def _on_named_boundary(domain, name: str, p, tol: float) -> bool:
    if domain.shape == "disc":
        return bool(domain.on_boundary(np.asarray(p, dtype=float), tol))
    v = domain.vertices()
    i = domain.edge_names().index(name)
    return _kernels.point_segment_distance(np.asarray(p, dtype=float), v[i], v[(i + 1) % len(v)])[0] <= tol


def _meeting_place(a: BC, b: BC, domain, tol: float) -> str | None:
    """Where the places of two conditions meet, as text, or None when apart:
    two points, a point on a named boundary, one boundary twice, or two
    boundaries sharing a corner."""
    if a.at is not None and b.at is not None:
        return "at the same place" if math.dist(a.at, b.at) <= tol else None
    if a.at is not None or b.at is not None:
        p, name = (a.at, b.on) if a.at is not None else (b.at, a.on)
        return f"at ({p[0]:g}, {p[1]:g})" if _on_named_boundary(domain, name, p, tol) else None
    if a.on == b.on:
        return "at the same place"
    if domain.shape == "disc":
        return None
    names, v = domain.edge_names(), domain.vertices()
    i, j = names.index(a.on), names.index(b.on)
    n = len(v)
    shared = [k for k in ((i + 1) % n, i) if k in ((j + 1) % n, j)]  # edge k runs from vertex k to k+1
    if not shared:
        return None
    x, y = v[shared[0]]
    return f"at the corner ({x:g}, {y:g})"


def check_bc_conflicts(bcs, domain, tol: float) -> None:
    """Two displacement conditions prescribing one component differently at a
    place they share: a point, a point on a boundary, a boundary's corner."""
    seen: list[tuple[int, BC]] = []
    for j, bc in enumerate(bcs):
        if bc.kind != "displacement":
            continue
        for i, other in seen:
            differ = [name for c, name in enumerate("xy")
                      if bc.components[c] and other.components[c] and bc.value[c] != other.value[c]]
            if not differ:
                continue
            where = _meeting_place(bc, other, domain, tol)
            if where is not None:
                raise CaseError(f"bc[{j}]", f"displacement {differ[0]} conflicts with bc[{i}] {where}")
        seen.append((j, bc))


def check_step_length(propagation: Propagation, mesh: MeshOptions) -> None:
    """Lmax at least L_min: the growth law's rule (wingcrack/shortest_advance.py)."""
    problem = length_problem(propagation.length, mesh.tip_size)
    if problem is not None:
        raise CaseError("propagation.length", problem)


def check_pressure_load(propagation: Propagation, fractures) -> None:
    """Injection (`load = "pressure"`) scales the fracture pressures: one must be above 0."""
    if propagation.load == "pressure" and not any(f.pressure > 0 for f in fractures):
        raise CaseError("propagation.load", '"pressure" scales the fracture pressures, but no fracture has a '
                                            "pressure above 0 (give fractures[i].pressure)")


def check_injection(injection: Injection | None, propagation: Propagation, fractures, domain) -> None:
    """The [injection] table against the load mode, the fractures and
    itself: a pump drives the run only with load = "injection", which needs
    one; the injected fracture exists, and it and the fractures it meets
    have no given pressure (theirs is the balance's); one of `rate` or
    `times` with `rates`; the schedule increasing and before `end_time`;
    the point on the fracture."""
    if injection is None or injection.viscosity is None:
        _check_without_flow(injection, fractures)
    if injection is None:
        if propagation.load == "injection":
            raise CaseError("propagation.load", '"injection" is driven by a pump: give an [injection] table '
                                                "(fracture, and rate or times and rates)")
        return
    if propagation.load != "injection":
        raise CaseError("injection", f'a pump drives the run only with propagation.load = "injection" (it is '
                                     f'"{propagation.load}"): set it, or leave the [injection] table out')
    i = injection.fracture
    if i >= len(fractures):
        have = f"fractures 0 .. {len(fractures) - 1}" if fractures else "no fractures"
        raise CaseError("injection.fracture", f"no fracture {i}: the case has {have}")
    network = admissibility.joined(domain, [f.points for f in fractures]).group_of(i)
    for j in network:
        if fractures[j].pressure:
            met = "is injected" if j == i else f"meets the injected fractures[{i}]"
            raise CaseError(f"fractures[{j}].pressure", f"fractures[{j}] {met}: its pressure is the injected "
                                                        "network's (injection.initial_pressure at t = 0, then its "
                                                        "fluid balance); leave its pressure out")
    _check_schedule(injection)
    if injection.viscosity is not None and propagation.sif == "interaction":
        # a viscous tip grows when the displacement correlation's K reaches what the correlation reads on
        # the viscous tip asymptote (propagation.viscous_tip): the interaction integral is not that reading
        raise CaseError("propagation.sif", '"interaction" cannot drive a tip the viscous fluid moves: its growth '
                                           "criterion is the displacement correlation's reading of the tip "
                                           'asymptote; leave sif = "correlation" (the default)')
    if injection.point is not None:
        tol = REL_TOL * float(domain.length_scale())
        p = np.asarray(injection.point, float)
        d = float(_kernels.point_polyline_distance(p, np.asarray(fractures[i].points, float)))
        if d > tol:
            raise CaseError("injection.point", f"({p[0]:g}, {p[1]:g}) is {d:.6g} m from fractures[{i}], the "
                                               "injected fracture: the fluid enters on it")


def _check_without_flow(injection: Injection | None, fractures) -> None:
    """The keys of the flow along the fractures need the fluid's viscosity."""
    for i, f in enumerate(fractures):
        if f.hydraulic_aperture is not None:
            raise CaseError(f"fractures[{i}].hydraulic_aperture", "a hydraulic aperture is the flow's: it needs "
                                                                  "injection.viscosity (without it one pressure "
                                                                  "fills each network)")
    if injection is None:
        return
    defaults = Injection.__dataclass_fields__
    for name in ("leak_off", "pressure", "frames"):
        if getattr(injection, name) != defaults[name].default:
            raise CaseError(f"injection.{name}", "needs injection.viscosity: without it the fluid does not flow "
                                                 "along the fractures (one pressure fills each network)")


def _check_schedule(injection: Injection) -> None:
    """`rate`, or `times` with as many `rates` (not all 0), strictly
    increasing and before `end_time`; or, with viscosity, `pressure`; and
    with viscosity an `end_time`."""
    times, rates = injection.times, injection.rates
    if injection.viscosity is not None and injection.end_time is None:
        raise CaseError("injection.end_time", "missing: the flow along the fractures runs in time (required with "
                                              "injection.viscosity)")
    if injection.pressure is not None:
        for name in ("rate", "times", "rates"):
            if getattr(injection, name) is not None:
                raise CaseError(f"injection.{name}", "give a pressure at the point or a rate (or a schedule), "
                                                     "not both")
        return
    if injection.rate is not None:
        for name, v in (("times", times), ("rates", rates)):
            if v is not None:
                raise CaseError(f"injection.{name}", "give rate (constant) or times with rates (a schedule), "
                                                     "not both")
        return
    if times is None and rates is None:
        also = ", or (with viscosity) a pressure" if injection.viscosity is not None else ""
        raise CaseError("injection.rate", f"missing: give rate (m^3/s per m), or times and rates (a schedule){also}")
    for name, v, other in (("times", times, "rates"), ("rates", rates, "times")):
        if v is None:
            raise CaseError(f"injection.{name}", f"missing (required with injection.{other})")
        if not v:
            raise CaseError(f"injection.{name}", "empty: a schedule needs at least one interval")
    if len(rates) != len(times):
        raise CaseError("injection.rates", f"{len(rates)} rates for {len(times)} times: one rate for each "
                                           "interval that a time starts")
    for k in range(1, len(times)):
        if not times[k] > times[k - 1]:
            raise CaseError(f"injection.times[{k}]", f"the times must increase strictly ({times[k]:g} s "
                                                     f"after {times[k - 1]:g} s)")
    if not any(rates):
        raise CaseError("injection.rates", "every rate is 0: nothing is ever injected")
    end = injection.end_time
    if end is not None and times[-1] >= end:
        k = next(k for k, t in enumerate(times) if t >= end)
        raise CaseError(f"injection.times[{k}]", f"{times[k]:g} s is not before end_time {end:g} s: the run never "
                                                 "reaches that interval")
