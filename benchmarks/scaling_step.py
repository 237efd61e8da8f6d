"""The propagation steps of a case, for benchmarks/scaling.py and
targets.py; run under mpirun. Rank 0 prints one JSON line: the first
step's DOFs and seconds per phase (and every step's, "steps"), and every
rank's peak resident memory (its own, and its children's: gmsh meshes in a
forked child on rank 0)."""
from __future__ import annotations

import json
import resource
import sys
from pathlib import Path


def main(case_path: str, out: str) -> None:
    from mpi4py import MPI

    import wingcrack
    from wingcrack.case import Case

    result = wingcrack.run(Case.from_toml(case_path), out=Path(out), plots=False, force=True)
    mib = [resource.getrusage(who).ru_maxrss / 1024 for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)]
    peaks = MPI.COMM_WORLD.gather(mib, root=0)
    if MPI.COMM_WORLD.rank == 0:
        step = result.steps[0]
        print(json.dumps({"ranks": MPI.COMM_WORLD.size, "dofs": step["dofs"], "cells": step["cells"],
                          "pairs": step["contact"]["pairs"], "seconds": step["seconds"],
                          "peak_mib": [p[0] for p in peaks], "gmsh_peak_mib": peaks[0][1],
                          "steps": [{"dofs": st["dofs"], "seconds": st["seconds"]} for st in result.steps]}))


if __name__ == "__main__":
    main(*sys.argv[1:3])
