"""What a command's start-up imports before its first mesh is sent (wingcrack/startup.py): the FE
stack (ffcx, DOLFINx; 0.3 s and more) and scipy.optimize (0.3 s, the pump's root) load later or
never, so that a run overlaps them with gmsh and a run with no step never pays for them; and the
form compiler's build lines stay out of the terminal although the filter is set without importing
ffcx. Each in a fresh interpreter: what this test process imported says nothing."""
import os
import subprocess
import sys

LATE = ("ffcx", "dolfinx", "ufl", "petsc4py", "scipy.optimize")


def test_importing_the_api_loads_neither_the_fe_stack_nor_the_optimiser():
    code = ("import sys; import wingcrack.api, wingcrack.cli, wingcrack.propagation.loop; "
            f"print([k for k in {LATE!r} if k in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert out.strip() == "[]"


def test_a_form_compiled_in_a_fresh_cache_prints_no_build_lines(tmp_path):
    """setuptools logs each kernel's build (gcc's command lines) at INFO on the root logger, whose
    handler ffcx's import makes; the fem package drops those records on the root logger itself.
    A fresh cache (XDG_CACHE_HOME) forces the build; without the filter the same script prints
    'INFO:root:running build_ext' (checked by clearing it)."""
    code = ("import logging, sys; import wingcrack.fem as f; f.preload(); "
            "clear = sys.argv[1] == 'clear'; "
            "_ = clear and logging.getLogger().filters.clear(); "
            "import dolfinx, ufl; from mpi4py import MPI; "
            "m = dolfinx.mesh.create_unit_square(MPI.COMM_SELF, 2, 2); "
            "V = dolfinx.fem.FunctionSpace(m, ('Lagrange', 2)); "
            "u, v = ufl.TrialFunction(V), ufl.TestFunction(V); "
            "dolfinx.fem.form(1.25 * ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx)")
    runs = {}
    for mode in ("kept", "clear"):
        env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / mode))
        runs[mode] = subprocess.run([sys.executable, "-c", code, mode], check=True, capture_output=True,
                                    text=True, env=env)
    assert "INFO:root" not in runs["kept"].stderr + runs["kept"].stdout
    assert "INFO:root:running build_ext" in runs["clear"].stderr   # the test can see what it guards
