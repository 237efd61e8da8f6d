"""What a step of a pumped run (load = "injection") costs against a step of
the same case under a given pressure (load = "pressure"): `make bench` reads
it from its runs of every case; alone it runs each pair alternately, N
pairs, so that both see the same load of a shared machine (the ratio is that
of the medians).

For each pair: seconds per step (the summary's step totals over its steps;
the phases: the solves, the critical-load search and the pump's balance
among them, in `solve`), solves per step, and the ratio pumped / given;
and that ratio with the pumped step's other phases taken as the given
one's (mesh, assembly, factorisation, SIFs, files: the same work a step,
which a shared machine's load moves by 1.5x between two runs), the pump's
extra work alone.
The pumped run's extra work is the balance at each step's start (a few
contact solves on the step's factorisation and pair compliance) and a
search to 1e-7 of KIc.

    python benchmarks/injection_cost.py [--pairs N] [--cases GIVEN:PUMPED ...]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from propagation import run_case

#: (the given-pressure case, its pumped variant)
PAIRS = [("three_fractures_injection", "three_fractures_injection_rate"),
         ("stimulation_network", "stimulation_network_rate")]


def per_step(summary: dict) -> dict:
    """{phase: seconds per step} (total among them) and solves per step of a summary."""
    steps = summary.get("steps") or []
    if not steps:
        return {}
    phases = {}
    for st in steps:
        for k, v in st["seconds"].items():
            phases[k] = phases.get(k, 0.0) + v / len(steps)
    phases["solves"] = sum(st.get("solves", 1) for st in steps) / len(steps)
    return phases


def report(measured: dict) -> None:
    """measured: {(given, pumped): ([per_step of given runs], [per_step of pumped runs])}."""
    print("| case (given pressure / pumped) | runs | s per step | solve s per step | solves per step | "
          "pumped / given: s per step (solve) | the same, other phases as given |")
    print("|---|---|---|---|---|---|---|")
    for (given, pumped), (a, b) in measured.items():
        if not a or not b:
            continue
        def med(runs, key):
            return statistics.median(r.get(key, 0.0) for r in runs)
        ratio, ratio_solve = med(b, "total") / med(a, "total"), med(b, "solve") / med(a, "solve")
        extra = (med(a, "total") - med(a, "solve") + med(b, "solve")) / med(a, "total")
        print(f"| `{given}` / `{pumped}` | {len(a)} | {med(a, 'total'):.3f} / {med(b, 'total'):.3f} | "
              f"{med(a, 'solve'):.3f} / {med(b, 'solve'):.3f} | {med(a, 'solves'):.1f} / {med(b, 'solves'):.1f} | "
              f"{ratio:.2f}x ({ratio_solve:.2f}x) | {extra:.2f}x |", flush=True)


def main(argv=None, runs: dict | None = None) -> None:
    """With `runs` ({name: propagation.run_case result}, as benchmarks/cases.py
    made them) the table of those runs; otherwise each pair run now,
    alternately (the order turned every pair)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--pairs", type=int, default=1)
    ap.add_argument("--cases", nargs="+", help="GIVEN:PUMPED names of cases/ (default: the shipped pairs)")
    a = ap.parse_args([] if argv is None and runs is not None else argv)
    pairs = [tuple(c.split(":")) for c in a.cases] if a.cases else PAIRS
    measured = {}
    if runs is not None:
        for given, pumped in pairs:
            if given in runs and pumped in runs:
                measured[(given, pumped)] = ([per_step(runs[given]["summary"])], [per_step(runs[pumped]["summary"])])
        report(measured)
        return
    with tempfile.TemporaryDirectory() as tmp:
        for given, pumped in pairs:
            a_runs, b_runs = [], []
            for i in range(a.pairs):
                order = [(given, a_runs), (pumped, b_runs)]
                for name, into in (order if i % 2 == 0 else order[::-1]):
                    r = run_case(name, Path(tmp) / f"{name}_{i}")
                    into.append(per_step(r["summary"]))
            measured[(given, pumped)] = (a_runs, b_runs)
    report(measured)


if __name__ == "__main__":
    sys.exit(main())
