"""What Coulomb friction changes, case by case (docs/theory/contact.md, "What friction
changes"; `make bench` runs it, not a test): each friction case and its
frictionless original run as `wingcrack run`, and one row each of the
initiation load, the kink at step 0, which tips grew, how far, the solves
per step, and the lengths of the faces open, sticking and slipping at
step 0 and at the last step (from the face files).

    python benchmarks/friction_cases.py [OUT]      (OUT: keep the results there)
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

from propagation import table_runs


#: (frictionless original, its friction version)
PAIRS = [("brazilian_disc_45", "brazilian_disc_45_friction"),
         ("three_fractures_slip", "three_fractures_friction"),
         ("multi_fractures_shear", "multi_fractures_friction")]


def lengths(result, k: int) -> tuple:
    """(open, stick, slip) face length (m) of step k."""
    from wingcrack.io.faces import OPEN, SLIP, STICK

    faces = result.faces_of(k)
    seg = np.linalg.norm(np.diff(faces.lines, axis=1), axis=2).sum(axis=1)
    return tuple(float(seg[faces.state == s].sum()) for s in (OPEN, STICK, SLIP))


def grown(summary) -> str:
    """Which tips grew (fracture.end, by the summary's 1-based fracture
    numbers as the case comments use them) and the total wing length."""
    wings = [np.asarray(f["points"]) for f in summary["fractures"] if f["origin"] == "wing"]
    total = sum(float(np.linalg.norm(np.diff(w, axis=0), axis=1).sum()) for w in wings)
    tips = sorted({(t["fracture"] + 1, t["end"]) for s in summary["steps"] for t in s["tips"]
                   if t.get("advance", 0) > 0})
    return f"{len(tips)} tips ({', '.join(f'{f}.{e}' for f, e in tips)}), wings {total:.3g} m"


def row(name: str, out: Path) -> str:
    from wingcrack.io.outdir import read_result

    r = read_result(out)
    s = r.summary
    steps = s["steps"]
    first = steps[0]
    theta = ", ".join(f"{np.degrees(t['theta']):.1f}" for t in first["tips"])
    o0, k0, s0 = lengths(r, 0)
    o1, k1, s1 = lengths(r, len(steps) - 1)
    solves = [st["solves"] for st in steps]
    return (f"| `{name}` | {first['load_factor']:.4g} | {theta} | {grown(s)} | {len(steps)}: {s['status']} | "
            f"{o0:.3g} / {k0:.3g} / {s0:.3g} | {o1:.3g} / {k1:.3g} / {s1:.3g} | "
            f"{np.mean(solves):.1f} (max {max(solves)}) |")


def main(argv=None, runs: dict | None = None) -> None:
    """The table; with `runs` ({name: propagation.run_case result}, as
    benchmarks/cases.py made them) the table of those runs, read, not run
    again (a case of the table not among them is left out)."""
    argv = sys.argv[1:] if argv is None else argv
    keep = Path(argv[0]) if argv else None
    with tempfile.TemporaryDirectory() as tmp:
        base = keep or Path(tmp)
        print("\n| case | initiation load factor | kink at step 0 (deg) | tips grown | steps: status | "
              "faces open / stick / slip at step 0 (m) | at the last step (m) | solves per step |")
        print("|---|---|---|---|---|---|---|---|")
        for name, r in table_runs([name for pair in PAIRS for name in pair], runs, base):
            print(row(name, r["out"]), flush=True)


if __name__ == "__main__":
    main()
