"""The mesh of the 45-degree Brazilian disc (tests/unit/test_meshing.py's disc:
R 42 mm, crack 2a = 10 mm, size 4 mm, tip_size 0.5 mm): crack_mesh's best
wall-clock time of REPEAT after a warm-up (imports, page faults), with the
gmsh share. Moved here from the test suite: a time is a measurement of the
machine, not a property of the code."""
from __future__ import annotations

import time

import numpy as np

R, A = 0.042, 0.005


def main(repeat: int = 3) -> None:
    from meshing.mesher import crack_mesh
    from meshing.domain import Domain

    c = A / np.sqrt(2.0)
    args = (Domain("disc", center=[0.0, 0.0], radius=R), [np.array([[-c, -c], [c, c]])], [[0.0, R], [0.0, -R]])
    kw = dict(size=0.004, tip_size=0.0005)
    crack_mesh(*args, **kw)
    best, mesh = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        mesh = crack_mesh(*args, **kw)
        best = min(best, time.perf_counter() - t)
    print(f"\ncrack_mesh, 45-degree disc: {mesh.stats['nodes']} nodes, {mesh.stats['cells']} cells, "
          f"best of {repeat} {best:.3f} s (gmsh {mesh.stats['seconds_gmsh']:.3f} s of the last)")


if __name__ == "__main__":
    main()
