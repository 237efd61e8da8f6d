"""What the result objects of wingcrack.sif and wingcrack.run offer beyond
their fields: tables of the tips, and the last solve's DOLFINx objects."""
from __future__ import annotations

TIP_COLUMNS = ("fracture", "end", "x", "y", "KI", "KII", "KI_M", "KII_M", "G", "theta", "K_eq")


def tip_rows(steps) -> list[dict]:
    """One plain dict per (step, tip): the step's number, load factor, DOFs,
    and the tip's values (KI, KII: displacement correlation; KI_M, KII_M:
    interaction integral, None where it had no room; theta in rad)."""
    rows = []
    for s in steps:
        for t in s["tips"]:
            row = {"step": s["step"], "load_factor": s["load_factor"], "dofs": s["dofs"]}
            row.update({k: t.get(k) for k in TIP_COLUMNS + ("state", "advance") if k in t})
            rows.append(row)
    return rows


def dataframe(rows):
    """A pandas DataFrame of `rows` (pandas is optional: ImportError says so)."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError("to_dataframe() needs pandas (pip install pandas); "
                          "the same rows are available as plain dicts") from None
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
