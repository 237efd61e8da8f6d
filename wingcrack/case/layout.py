"""The layouts that are not a record's: the top level, `[domain]` (one set
of keys per shape) and `[[bc]]` (one place and one condition), and
`DESCRIPTION`, every table of a case in reading order."""
from __future__ import annotations

from wingcrack.case.bounds import MAX_ITEMS, MAX_STRAIN, SHAPES
from wingcrack.case.keys import NUMBER, POINT, POINTS, POSITIVE, STRING, TABLE, TABLES, Key, Limit, keys_of
from wingcrack.case.records import SMALL, Body, Fracture, Injection, Material, MeshOptions, Propagation, Stress

TOP_KEYS = (
    Key("title", STRING, "", default_doc="the file name without `.toml` (`Case.from_dict` gives `\"\"`)",
        doc="The name shown in `check`, in pictures and in `summary.json`.",
        limit=Limit(hi=200, why="one line of a picture's title"),
        rule="no control characters (newline, tab, NUL)"),
    Key("material", TABLE, doc="See below."),
    Key("domain", TABLE, doc="See below."),
    Key("fractures", TABLES, None, default_doc="none", doc="Pre-existing fractures. A case with no fractures is valid.",
        rule=f"at most {MAX_ITEMS} entries"),
    Key("bc", TABLES, None, default_doc="none", rule=f"at most {MAX_ITEMS} entries",
        doc="Boundary conditions, in file order. Without displacement conditions the case is statically "
            "undetermined."),
    Key("body", TABLE, None, default_doc="gravity 0", doc="Body force."),
    Key("stress", TABLE, None, default_doc="all 0", doc="Initial (in-situ) stress."),
    Key("mesh", TABLE, doc="Mesh sizes."),
    Key("propagation", TABLE, None, default_doc="all defaults", doc="Growth control. Only `run` reads it."),
    Key("injection", TABLE, None, default_doc="none", rule="only with `propagation.load = \"injection\"`, which "
        "needs it", doc="A pump: the injected volume drives the run in time (`run` only)."),
)

SHAPE = Key("shape", STRING, choices=SHAPES, doc="Which of the keys below the table takes.")
SHAPE_KEYS = {
    "disc": (Key("center", POINT, unit="m", doc="The centre."),
             Key("radius", NUMBER, unit="m", range=POSITIVE, doc="The radius.")),
    "rectangle": (Key("corner", POINT, unit="m", doc="The lower left corner [x0, y0]."),
                  Key("size", POINT, unit="m", range=POSITIVE, parts=("width", "height"), doc="[width, height].")),
    "polygon": (Key("points", POINTS, unit="m", min_points=3, noun="a polygon",
                    doc="The vertices, counter-clockwise.", rule=f"at most {MAX_ITEMS} points"),),
}

_BC_VALUE = "Global x and y components."
BC_KEYS = (
    Key("at", POINT, None, "m", doc="A boundary point. It becomes a mesh node, and duplicate points share one node.",
        rule="within 1e-9 L of the boundary, and not on a fracture (a mouth): that would be ambiguous"),
    Key("on", STRING, None, doc="A boundary name of the domain (see `[domain]`). An unknown name gets a list of the "
                                "names and a suggestion."),
    Key("force", POINT, None, "N/m", doc=_BC_VALUE, rule="only with `at`",
        limit=Limit(hi=MAX_STRAIN, of="E L", why=SMALL)),
    Key("traction", POINT, None, "Pa", doc=_BC_VALUE, rule="only with `on`",
        limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL)),
    Key("displacement", POINT, None, "m", doc="Both components prescribed. Works with `at` or `on`.",
        limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL)),
    Key("displacement_x", NUMBER, None, "m", doc="One component prescribed. Giving both equals `displacement`. "
        "Neither may be combined with `displacement`.", limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL)),
    Key("displacement_y", NUMBER, None, "m", doc="As `displacement_x`.",
        limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL)),
)
BC_PLACES = ("at", "on")
BC_CONDITIONS = tuple(k.name for k in BC_KEYS if k.name not in BC_PLACES)

#: Every table of a case, in reading order: what the reader reads and the
#: reference documents ([domain]: every shape's keys).
DESCRIPTION = {
    "top": TOP_KEYS, "material": keys_of(Material),
    "domain": (SHAPE,) + tuple(k for keys in SHAPE_KEYS.values() for k in keys),
    "fractures": keys_of(Fracture), "bc": BC_KEYS, "body": keys_of(Body), "stress": keys_of(Stress),
    "mesh": keys_of(MeshOptions), "propagation": keys_of(Propagation), "injection": keys_of(Injection),
}
