"""The issue's phases of a step (issue 16, "Report": mesh, patch, factorise,
contact, solve, SIFs, output) from the timer keys that summary.json records
per step (wingcrack/step.py and solver.py lap them in `discretise` and `finish`,
propagation/loop.py in the loop)."""
from __future__ import annotations

#: issue phase <- the summary keys it sums. "mesh" holds the DOLFINx mesh and
#: the error estimate (the next mesh's size field) too: both are the price of a
#: new mesh. "factorise" is assembly and factorisation. "contact" is the pair
#: compliance (ContactProblem: the Schur complement on the pair dofs); "solve"
#: every solve of the step (the critical load search and the active set);
#: "SIFs" the SIFs and the growth rule. "patch" (local remeshing) is a key of
#: its own once it exists.
ISSUE_PHASES: dict[str, tuple[str, ...]] = {
    "mesh": ("mesh", "to_dolfinx", "estimate"),
    "patch": ("patch",),
    "factorise": ("assemble", "factorize"),
    "contact": ("contact",),
    "solve": ("solve",),
    "SIFs": ("sif", "growth"),
    "output": ("output",),
}
#: the column of keys that no issue phase names (a new lap is seen, not lost)
OTHER = "other"
KNOWN = {key for keys in ISSUE_PHASES.values() for key in keys} | {"total"}


def mapping_text() -> str:
    """One line per issue phase: `mesh = mesh + to_dolfinx + estimate`."""
    return "\n".join(f"{name:9s} = {' + '.join(keys)}" for name, keys in ISSUE_PHASES.items()) + \
        f"\n{OTHER:9s} = any other key of a step's seconds"


def of_seconds(seconds: dict) -> dict:
    """{issue phase: seconds} of one step's (or a sum of steps') summary
    seconds; None for a phase none of whose keys is there (printed "-": not
    measured, which is not 0 s), the unknown keys summed under OTHER."""
    out = {}
    for name, keys in ISSUE_PHASES.items():
        present = [seconds[k] for k in keys if k in seconds]
        out[name] = sum(present) if present else None
    extra = [v for k, v in seconds.items() if k not in KNOWN]
    out[OTHER] = sum(extra) if extra else None
    return out


def unknown_keys(steps: list) -> list[str]:
    """The keys of the steps' seconds that ISSUE_PHASES does not map."""
    return sorted({k for st in steps for k in st.get("seconds", {}) if k not in KNOWN})


def summed(steps: list) -> dict:
    """{summary key: seconds summed over the steps} (with "total")."""
    out: dict[str, float] = {}
    for st in steps:
        for k, v in st.get("seconds", {}).items():
            out[k] = out.get(k, 0.0) + v
    return out


def per_step(steps: list) -> dict:
    """{issue phase: mean seconds per step} over the steps, and "total"
    (the steps' own timer total: the process wall without start-up and the
    summary and checkpoint writes)."""
    if not steps:
        return {}
    s = summed(steps)
    out = {name: (None if v is None else v / len(steps)) for name, v in of_seconds(s).items()}
    out["total"] = s.get("total", 0.0) / len(steps)
    return out
