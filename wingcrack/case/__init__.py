"""The case: what one case file describes, read and checked.

docs/case-format.md is the reference of the format. `Case.from_toml(path)`
reads a file, `Case.from_dict(d)` a parsed table; both return a `Case` whose every part
has been checked, or raise `CaseError(key, reason)` naming the first offending
key by its full path (``mesh.tip_size``, ``fractures[1].points[0]``, ``bc[2].at``).

Every key is described once as a `Key` (keys.py: type, unit, default, the
range its meaning allows, the magnitude a case may ask for, documentation):
on the field of the record that holds it (records.py, `Material.E`), or,
where the file's layout is not the record's (`[domain]`, `[[bc]]`, the top
level), in a tuple of Keys (layout.py); bounds.py holds the choices and
bounds they name. One reader, `values.Table.read`, checks a table against
its Keys; reader.py reads the tables in the file's order, and the rules that
tie keys together (checks.py) and the rigid-body check (rigid_motions.py)
follow. docs/case-format.md's key tables are rendered from the Keys
(`python -m wingcrack.case_doc`).

Units are SI throughout (m, Pa, N; a point force is N per metre of thickness).
Points are (x, y) float64. Load scaling (done by the solver, not here): with
propagation.load = "scale" every bc force, traction and displacement, every
prescribed fracture slip and every fracture pressure is multiplied by the load
factor; with "pressure" only the fracture pressures are; the initial stress
and gravity never are. With "injection" nothing is scaled: the [injection]
table's pump sets the injected network's pressure in time.
"""
from wingcrack.case.bounds import (FACES, LENGTH_RANGE, LOADS, MAX_ELEMENTS, MAX_FILE_BYTES, MAX_FRICTION,
                                   MAX_ITEMS, MAX_OFFSET, MAX_SECTORS, MAX_STRAIN, MIN_TIP_FRACTION, PLANES,
                                   REL_TOL, SHAPES, SIFS, SLIP_PROFILES)
from wingcrack.case.keys import (BOOLEAN, INTEGER, NON_NEGATIVE, NUMBER, NUMBERS, POINT, POINTS, POSITIVE, REQUIRED,
                                 STRING, TABLE, TABLES, Key, Limit, Range, Ref, key, keys_of)
from wingcrack.case.layout import BC_CONDITIONS, BC_KEYS, BC_PLACES, DESCRIPTION, SHAPE, SHAPE_KEYS, TOP_KEYS
from wingcrack.case.model import Case
from wingcrack.case.records import BC, Body, Fracture, Injection, Material, MeshOptions, Propagation, Stress, Tip
from wingcrack.errors import CaseError

__all__ = [
    "BC", "BC_CONDITIONS", "BC_KEYS", "BC_PLACES", "BOOLEAN", "Body", "Case", "CaseError", "DESCRIPTION", "FACES",
    "Fracture", "INTEGER", "Injection", "Key", "LENGTH_RANGE", "LOADS", "Limit", "MAX_ELEMENTS", "MAX_FILE_BYTES",
    "MAX_FRICTION", "MAX_ITEMS", "MAX_OFFSET", "MAX_SECTORS", "MAX_STRAIN", "MIN_TIP_FRACTION", "Material",
    "MeshOptions", "NON_NEGATIVE", "NUMBER", "NUMBERS", "PLANES", "POINT", "POINTS", "POSITIVE", "Propagation", "REL_TOL",
    "REQUIRED", "Range", "Ref", "SHAPE", "SHAPES", "SHAPE_KEYS", "SIFS", "SLIP_PROFILES", "STRING", "Stress",
    "TABLE", "TABLES", "TOP_KEYS", "Tip", "key", "keys_of",
]
