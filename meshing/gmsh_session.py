"""One gmsh session of the mesher: gmsh initialised with this module's
options and a scratch folder of its own, the whole domain or the patched
one meshed, gmsh finalised; gmsh's bare Exception raised as RuntimeError."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import time

from meshing.far_cache import CacheMiss
from meshing.gmsh_geometry import mesh_with_gmsh
from meshing.patch import mesh_patched
from meshing.records import RawMesh


def gmsh_session(domain, plan, size, tip_size, sectors, sizes, half, mirror_sizes, algorithm,
                 circle=None) -> RawMesh:
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    with _scratch() as scratch:
        gmsh.initialize(readConfigFiles=False)
        try:
            _session_options()
            if circle is not None:
                args = (domain, plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes, scratch, circle)
                try:
                    return mesh_patched(*args)
                except CacheMiss:  # a fresh session, the far field meshed too
                    gmsh.finalize()
                    gmsh.initialize(readConfigFiles=False)
                    _session_options()
                    return mesh_patched(*args, reuse=False)
            return mesh_with_gmsh(domain, plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes,
                                  scratch)
        except Exception as error:  # gmsh raises bare Exception
            raise RuntimeError(f"gmsh could not mesh the domain: {error}") from error
        finally:
            gmsh.finalize()


# gmsh's relative precision when it integrates 1 / h along a curve to place the
# curve's nodes. Its default 1e-9 spends a third of gmsh's time in the 1D pass
# on meshes with a fine size grid (each kink of the grid resolved to it along
# every curve). 1e-7 places the nodes as 1e-9 does for every shipped case's
# path; at 1e-6 the nodes move enough that a tip standing just above KIc can
# take another path.
LC_INTEGRATION_PRECISION = 1e-7


def _session_options() -> None:
    """The options every session of this module starts with."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.LcIntegrationPrecision", LC_INTEGRATION_PRECISION)


_SCRATCH_PREFIX = "wingcrack-sizes-"
_SCRATCH_STALE = 3600.0


@contextlib.contextmanager
def _scratch():
    """A directory of this session's own for the size grid that gmsh reads
    (every process and session its own, so parallel runs never share one),
    removed when the session ends. A session killed on timeout (the meshing
    worker is SIGKILLed) cannot remove its own: each session first removes
    those of processes that are gone (the pid is in the name) and that are
    older than _SCRATCH_STALE seconds (a process of another pid namespace
    sharing /tmp looks gone; gmsh would silently mesh without the grid if
    its file vanished mid-session)."""
    base = tempfile.gettempdir()
    now = time.time()
    for name in os.listdir(base):
        if not name.startswith(_SCRATCH_PREFIX):
            continue
        pid, path = name[len(_SCRATCH_PREFIX):].split("-", 1)[0], os.path.join(base, name)
        try:
            aged = now - os.stat(path).st_mtime > _SCRATCH_STALE
        except OSError:
            continue
        if aged and pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(path, ignore_errors=True)
    with tempfile.TemporaryDirectory(prefix=f"{_SCRATCH_PREFIX}{os.getpid()}-") as path:
        yield path


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True
