"""What the friction solve costs, case by case (`make bench` runs it; not a
test, no timing asserted): every case of cases/ with Coulomb faces, run in
this process with contact.friction.solve_friction timed, and for each of its
solves the frictionless contact solve of the same pair system (the normal
rows alone: contact.active_set on S_nn, the same jumps and gaps) timed right
after it; and the whole contact solve (ContactProblem.solve: the elastic
solve, the pair problem, the pair forces' response) against the same with
the frictionless pair solve in place of the friction one. Per case: the
friction solves, their worst and median ratio to the frictionless ones (the
pair problem alone, and the whole contact solve), how many fell back, and the
steps' median and the worst step over it (the issue's bounds: a solve within
10x the frictionless one, a step within 5x the run's median).

    python benchmarks/friction_solve.py [--cases NAME ...]
"""
from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def coulomb_cases() -> list[str]:
    from wingcrack.case import Case

    return sorted(p.stem for p in (ROOT / "cases").glob("*.toml")
                  if any(f.faces == "coulomb" for f in Case.from_toml(p).fractures))


class Timing:
    """solve_friction wrapped: (friction s, frictionless s, fallback) of every solve with Coulomb rows."""

    def __init__(self):
        import wingcrack.fem.contact_problem as cp
        from wingcrack.contact import friction

        self.solves = []   # (friction pair solve, frictionless pair solve, fell back, whole contact solve)
        self._module, self._orig = cp, cp.solve_friction
        self._solve = cp.ContactProblem.solve
        active_set = friction.solve_active_set
        pending = []

        def timed(S, jump0, target, normal, law, **kw):
            t = time.perf_counter()
            res = self._orig(S, jump0, target, normal, law, **kw)
            spent = time.perf_counter() - t
            if np.any(law.coulomb):
                n = np.flatnonzero(normal)
                t = time.perf_counter()
                active_set(S[np.ix_(n, n)], jump0[n], target[n], np.ones(len(n), bool))
                pending.append((spent, time.perf_counter() - t, bool(res.fallback)))
            return res

        def whole(problem, *args, **kw):
            t = time.perf_counter()
            out = self._solve(problem, *args, **kw)
            spent = time.perf_counter() - t
            if pending:
                self.solves.append(pending.pop() + (spent,))
            return out

        cp.solve_friction = timed
        cp.ContactProblem.solve = whole

    def close(self):
        self._module.solve_friction = self._orig
        self._module.ContactProblem.solve = self._solve


def measure(name: str, out: Path) -> dict:
    import wingcrack
    from wingcrack.case import Case

    timing = Timing()
    try:
        result = wingcrack.run(Case.from_toml(ROOT / "cases" / f"{name}.toml"), out=out, plots=False)
    finally:
        timing.close()
    steps = [s["seconds"]["total"] for s in result.steps]
    ratios = [f / max(c, 1e-9) for f, c, _, _ in timing.solves]
    # the whole contact solve with the frictionless pair solve in place of the friction one
    wholes = [w / max(w - f + c, 1e-9) for f, c, _, w in timing.solves]
    med = statistics.median(steps) if steps else float("nan")
    nan = float("nan")
    return {"name": name, "status": result.status, "steps": len(steps), "solves": len(ratios),
            "worst": max(ratios, default=nan), "median": statistics.median(ratios) if ratios else nan,
            "whole_worst": max(wholes, default=nan), "whole_median": statistics.median(wholes) if wholes else nan,
            "fallbacks": sum(fb for _, _, fb, _ in timing.solves),
            "step_median": med, "step_worst": max(steps, default=float("nan")) / med if steps else float("nan")}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+", help="these cases of cases/ only (default: those with Coulomb faces)")
    args = ap.parse_args(argv)
    names = args.cases or coulomb_cases()
    print("\n| case | steps: status | friction solves | friction / frictionless, the pair problem: worst, median | "
          "the whole contact solve: worst, median | fell back | median step (s) | worst step / median |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            r = measure(name, Path(tmp) / name)
            print(f"| `{r['name']}` | {r['steps']}: {r['status'][:40]} | {r['solves']} | {r['worst']:.2f}x, "
                  f"{r['median']:.2f}x | {r['whole_worst']:.2f}x, {r['whole_median']:.2f}x | {r['fallbacks']} | "
                  f"{r['step_median']:.3g} | {r['step_worst']:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
