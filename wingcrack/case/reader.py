"""The reader: a case file to its parsed table (`load`), and a parsed table
to the checked parts of a Case (`read_case`), read in the file's order so
that the first offending key is the one reported. Each table is read by its
Keys (values.py); the rules across keys follow each part (checks.py), the
rigid-body check comes last (rigid_motions.py)."""
from __future__ import annotations

import difflib
import math
import os
import stat
import tomllib
import unicodedata
from pathlib import Path

import numpy as np

from meshing import admissibility
from meshing.domain import Domain  # pure numpy: `check` needs neither gmsh nor DOLFINx
from wingcrack.case.bounds import MAX_FILE_BYTES, NOT_YET, REL_TOL
from wingcrack.case.checks import (check_bc_conflicts, check_injection, check_mesh_against_domain, check_polygon,
                                   check_pressure_load, check_scale, check_slip_junctions, check_step_length,
                                   refuse)
from wingcrack.case.layout import BC_CONDITIONS, BC_PLACES, DESCRIPTION, SHAPE, SHAPE_KEYS
from wingcrack.case.records import BC, Body, Fracture, Injection, Material, MeshOptions, Propagation, Stress
from wingcrack.case.rigid_motions import check_statically_determined
from wingcrack.case.values import Table
from wingcrack.errors import CaseError

_FILE_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
               (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _read_bytes(path: Path) -> bytes:
    """At most MAX_FILE_BYTES + 1 bytes of a regular file. Opened without
    blocking and checked before reading: a FIFO would wait for a writer
    forever, a device never ends."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as err:
        raise CaseError(str(path), f"cannot read: {err.strerror or err}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        kind = next((name for test, name in _FILE_KINDS if test(mode)), "not a file")
        raise CaseError(str(path), f"not a regular file ({kind}): a case is a TOML file")
    with os.fdopen(fd, "rb") as fh:
        try:
            raw = fh.read(MAX_FILE_BYTES + 1)
        except OSError as err:
            raise CaseError(str(path), f"cannot read: {err.strerror or err}") from None
    if len(raw) > MAX_FILE_BYTES:
        raise CaseError(str(path), f"too large for a case file (over {MAX_FILE_BYTES} bytes)")
    return raw


def load(path: Path) -> dict:
    """The parsed table of a case file. A file that is not a regular one (a
    directory, a FIFO, a device), unreadable files, text that is not UTF-8
    and TOML syntax errors are CaseError, keyed by the file name."""
    raw = _read_bytes(path)
    try:
        # "utf-8-sig": a byte-order mark (Windows editors write one) is not TOML, but not the
        # user's text either: dropped, not refused as an invalid statement at line 1, column 1
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = raw.count(b"\n", 0, err.start) + 1
        column = err.start - (raw.rfind(b"\n", 0, err.start) + 1) + 1
        raise CaseError(str(path), f"not UTF-8 text: byte 0x{raw[err.start]:02x} "
                                   f"at line {line}, column {column}") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise CaseError(str(path), f"not valid TOML: {err}") from None
    except RecursionError:
        raise CaseError(str(path), "not valid TOML: arrays or tables nested too deeply") from None
    except ValueError as err:  # an integer over Python's 4300-digit limit of int(str)
        raise CaseError(str(path), f"not valid TOML: {str(err).split(';')[0]}") from None


def _parse_domain(t: Table):
    """Check the domain table and build the meshing.Domain."""
    t.refuse_unknown(DESCRIPTION["domain"])
    shape = t.value(SHAPE)
    keys = SHAPE_KEYS[shape]
    for k in t.data:
        if k != "shape" and k not in [s.name for s in keys]:
            raise CaseError(t.key(k), f'not a key of shape "{shape}" (it takes {", ".join(s.name for s in keys)})')
    geo = t.read((SHAPE,) + keys)
    del geo["shape"]
    if shape == "disc":
        check_scale(2 * geo["radius"], np.abs(geo["center"]).max(), t.key("radius"), t.key("center"))
    elif shape == "rectangle":
        check_scale(max(geo["size"]), np.abs(geo["corner"]).max(), t.key("size"), t.key("corner"))
    else:
        pts = geo["points"]
        # before check_polygon, whose products would overflow
        with np.errstate(over="ignore"):
            extent = float(np.ptp(pts, axis=0).max())
        check_scale(extent, np.abs(pts).max(), t.key("points"), t.key("points"))
        check_polygon(pts, t.key("points"))
    try:
        return Domain(shape, **geo)
    except ValueError as err:  # anything meshing refuses that the checks above let through
        raise CaseError(t.path, str(err)) from None


def _parse_bc(t: Table, boundary_names, known: dict) -> BC:
    """One place and one condition; displacement_x and displacement_y
    together are one displacement condition."""
    t.refuse_unknown(DESCRIPTION["bc"])
    if all(p in t.data for p in BC_PLACES):
        raise CaseError(t.path, "give one place: either at (a point) or on (a boundary), not both")
    if not any(p in t.data for p in BC_PLACES):
        raise CaseError(t.path, "missing place: give at = [x, y] or on = \"<boundary>\"")
    given = [c for c in BC_CONDITIONS if c in t.data]
    if "displacement" in t.data:
        for c in ("displacement_x", "displacement_y"):
            if c in t.data:
                raise CaseError(t.key(c), "conflicts with displacement (give displacement, or displacement_x / displacement_y)")
    kinds = {c.split("_")[0] for c in given}
    if not given:
        raise CaseError(t.path, "no condition: give one of " + ", ".join(BC_CONDITIONS))
    if len(kinds) > 1:
        raise CaseError(t.path, "two conditions (" + " and ".join(given) + "): each [[bc]] holds one")
    kind = kinds.pop()
    v = t.read(DESCRIPTION["bc"], known)
    at, on = v["at"], v["on"]
    if on is not None:
        names = list(boundary_names)
        if on not in names:
            near = difflib.get_close_matches(on, names, n=1)
            hint = f"; did you mean {near[0]}?" if near else ""
            raise CaseError(t.key("on"), f'no boundary named "{on}" (this domain has {", ".join(names)}{hint})')
    if kind == "force" and on is not None:
        raise CaseError(t.key("force"), "a force (N/m) acts at a point: use at = [x, y], or traction on a boundary")
    if kind == "traction" and at is not None:
        raise CaseError(t.key("traction"), "a traction (Pa) acts on a boundary: use on = \"<boundary>\", or force at a point")
    if kind in ("force", "traction"):
        return BC(kind, v[kind], at=at, on=on)
    if v["displacement"] is not None:
        return BC("displacement", v["displacement"], at=at, on=on)
    ux, uy = v["displacement_x"], v["displacement_y"]
    return BC("displacement", (ux or 0.0, uy or 0.0), at=at, on=on, components=(ux is not None, uy is not None))


def _parse_mesh(t: Table, known: dict) -> MeshOptions:
    mesh = MeshOptions(**t.read(DESCRIPTION["mesh"], known))
    if mesh.tip_size >= mesh.size:
        raise CaseError(t.key("tip_size"), f"must be smaller than mesh.size ({mesh.tip_size:g} >= {mesh.size:g})")
    return mesh


def _scales(material: Material, domain) -> dict:
    """What Limits scale by: E, L (the domain's length scale) and their products."""
    E, L = material.E, float(domain.length_scale())
    weight = material.density * L  # may underflow to 0: no body force then
    return {"E": E, "L": L, "E L": E * L, "E / (density L)": E / weight if weight > 0 else math.inf,
            "L^2": L * L, "E^-1": 1.0 / E}


def _refuse_not_yet(t: Table, name: str) -> None:
    """A key of the flow along the fractures (bounds.NOT_YET) is refused by
    name: it is no typo, and this version does not read it."""
    for k in t.data:
        if k in NOT_YET[name]:
            raise CaseError(t.key(k), f"not yet supported: {NOT_YET[name][k]} needs the flow along the "
                                      "fractures, which this version does not model (one pressure per connected "
                                      "network); leave it out")


def read_case(d: dict) -> tuple:
    """The parts of a Case (title, material, domain, fractures, bcs, body,
    stress, mesh, propagation, injection), each checked, from a parsed case
    table."""
    top = Table(d, "")
    top.refuse_unknown(DESCRIPTION["top"])
    section = {k.name: k for k in DESCRIPTION["top"]}  # each read in its turn: errors in reading order
    title = top.value(section["title"])
    bad = next((c for c in title if unicodedata.category(c) in ("Cc", "Zl", "Zp")), None)
    if bad is not None:
        raise CaseError("title", f"one line of text, without control characters (it holds {ascii(bad)} at "
                                 f"character {title.index(bad) + 1})")

    material = Material(**top.value(section["material"]).read(DESCRIPTION["material"]))
    domain = _parse_domain(top.value(section["domain"]))
    L = float(domain.length_scale())
    tol = REL_TOL * L
    known = _scales(material, domain)

    fr_tables = top.value(section["fractures"])
    for ft in fr_tables:
        _refuse_not_yet(ft, "fractures")
    parsed = [ft.read(DESCRIPTION["fractures"], known) for ft in fr_tables]
    for ft, f in zip(fr_tables, parsed):
        refuse(admissibility.fracture(f["points"], ft.key("points"), domain))
    refuse(admissibility.fractures_meet(domain, [f["points"] for f in parsed]))
    for f in parsed:
        f["points"].setflags(write=False)
    fractures = tuple(Fracture(**f) for f in parsed)
    check_slip_junctions(fractures, domain)

    bc_tables = top.value(section["bc"])
    bcs = tuple(_parse_bc(bt, domain.boundary_names(), known) for bt in bc_tables)
    for bt, bc in zip(bc_tables, bcs):
        if bc.at is not None:
            refuse(admissibility.bc_point(bc.at, bt.key("at"), domain, [f.points for f in fractures]))
    check_bc_conflicts(bcs, domain, tol)

    # gravity with density 0 (the contract's example) is no body force: allowed
    body = Body(**top.value(section["body"]).read(DESCRIPTION["body"], known))
    stress = Stress(**top.value(section["stress"]).read(DESCRIPTION["stress"], known))

    mesh = _parse_mesh(top.value(section["mesh"]), known)
    check_mesh_against_domain(mesh, domain)
    at = [(bt.key("at"), bc.at) for bt, bc in zip(bc_tables, bcs) if bc.at is not None]
    refuse(admissibility.case_geometry(domain, [f.points for f in fractures], [p for _, p in at],
                                        [k for k, _ in at], mesh.tip_size))
    known["mesh.tip_size"] = mesh.tip_size  # a Ref: the default of propagation.length
    propagation = Propagation(**top.value(section["propagation"]).read(DESCRIPTION["propagation"], known))
    check_step_length(propagation, mesh)
    check_pressure_load(propagation, fractures)
    it = top.value(section["injection"])
    _refuse_not_yet(it, "injection")
    injection = Injection(**it.read(DESCRIPTION["injection"], known)) if "injection" in d else None
    check_injection(injection, propagation, fractures, domain)

    check_statically_determined(bcs, domain)

    return title, material, domain, fractures, bcs, body, stress, mesh, propagation, injection
