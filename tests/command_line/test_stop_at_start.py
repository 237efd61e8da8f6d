"""Ctrl-C (SIGINT) or SIGTERM while `wingcrack run` starts: exit 130 / 143
(128 + the signal's number, what a shell reports for a process the signal
ended), one line, no traceback, nothing half-written, at every moment of
the start-up.

The moments are found by watching the process's memory map (/proc/PID/maps)
rather than by the clock, so that each signal lands in the phase it is
meant for on a loaded machine too: numpy's extension module mapped = the
command imports its CLI (numpy comes with it); DOLFINx's extension module
mapped = DOLFINx initialises, where a signal's exception comes out of the
module's initialisation as an ImportError ("initialization failed").
Each process is killed within about 1.5 s of its start.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from wingcrack.io.outdir import leftovers, result_files
from wingcrack import interrupt

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "brazilian_disc_45.toml"

# the extension modules whose loading marks a phase of the start-up
DURING_CLI_IMPORT = "_multiarray_umath"   # numpy's core, imported with the CLI
DURING_DOLFINX_IMPORT = "dolfinx/cpp."    # DOLFINx's pybind11 module


def _command() -> list[str]:
    exe = Path(sys.executable).with_name("wingcrack")
    if exe.exists():
        return [str(exe)]   # the console script: what a user starts
    return [sys.executable, "-m", "wingcrack"]


def _stopped_when_mapped(tmp_path, mark: str, signum: int) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp_path / "out"
    p = subprocess.Popen(_command() + ["run", str(CASE), "-o", str(out), "--force"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    try:
        deadline = time.monotonic() + 60
        while True:
            assert p.poll() is None, f"the run ended before {mark} was loaded: {p.communicate()}"
            assert time.monotonic() < deadline, f"{mark} was never loaded"
            try:
                if mark in Path(f"/proc/{p.pid}/maps").read_text():
                    break
            except OSError:
                pass
            time.sleep(0.001)
        p.send_signal(signum)
        stdout, stderr = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    return subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr), out


@pytest.mark.parametrize("mark", [DURING_CLI_IMPORT, DURING_DOLFINX_IMPORT], ids=["cli-import", "dolfinx-import"])
@pytest.mark.parametrize("signum, code, word", [(signal.SIGINT, 130, "interrupted"),
                                                (signal.SIGTERM, 143, "terminated")],
                         ids=["SIGINT", "SIGTERM"])
def test_a_stop_during_the_start_up_exits_with_the_signal_code(tmp_path, mark, signum, code, word):
    res, out = _stopped_when_mapped(tmp_path, mark, signum)
    assert res.returncode == code == 128 + signum, res.stderr
    # one line, a clean stop (no traceback, no "unexpected ImportError"); the command line is read before
    # numpy and DOLFINx load, so the run says that it has nothing to resume
    line = f"wingcrack: stopped ({word}): no step was finished, so nothing to resume: run it again"
    assert res.stderr.strip().splitlines() == [line]
    # nothing of a result before the first step was computed; no temporary file
    assert result_files(out) == [] and leftovers(out) == []
    assert not out.exists() or [p.name for p in out.iterdir()] == []


def test_a_stop_is_recognised_behind_the_error_it_caused():
    """What a signal's exception becomes in an extension module's
    initialisation: pybind11 raises ImportError from it (chained), numpy's
    C API replaces it by an ImportError without the chain; either is the
    stop once a handler here received the signal, and an error with no
    signal behind it is its own."""
    with interrupt.terminate_raises():
        assert interrupt.cause(ValueError("a real failure")) is None
        try:
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as ki:
                raise ImportError("initialization failed") from ki
        except ImportError as err:
            chained = err
        assert isinstance(interrupt.cause(chained), KeyboardInterrupt)
        assert interrupt.cause(ImportError("PyCapsule_Import could not import module")) is None
        with pytest.raises(interrupt.Terminated):
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):   # bytecodes: the handler runs here
                pass
        assert isinstance(interrupt.cause(ImportError("PyCapsule_Import could not import module")),
                          interrupt.Terminated)
    with interrupt.terminate_raises():   # a new command: the last one's stop is past
        assert interrupt.cause(RuntimeError("a real failure")) is None


def test_a_stop_during_a_form_compilation_leaves_the_compiler_cache_usable(tmp_path, monkeypatch):
    """FFCx claims a module of its cache by creating its C file and gives the
    claim up on an Exception only: Ctrl-C inside the compilation left the
    empty C file, and every later process waited 10 s for the module and
    failed ("JIT compilation timed out"). Here Ctrl-C comes once FFCx has
    claimed the module (in an empty cache of its own): the compilation
    finishes, the stop follows, and the next compilation of the form loads
    it from the cache."""
    import ffcx.codegeneration.jit as ffcx_jit
    import numpy as np
    import ufl
    from dolfinx import jit, mesh
    from mpi4py import MPI

    from wingcrack.fem import compiled

    cache = tmp_path / "fenics"
    monkeypatch.setitem(jit.DOLFINX_DEFAULT_JIT_PARAMETERS, "cache_dir", (cache, "a cache of the test's own"))
    compile_objects = ffcx_jit._compile_objects

    def interrupted(*args, **kwargs):
        assert any(cache.glob("*.c")), "FFCx claims the module before it compiles it"
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):   # bytecodes: the handler runs here (a KeyboardInterrupt unless held)
            pass
        return compile_objects(*args, **kwargs)

    monkeypatch.setattr(ffcx_jit, "_compile_objects", interrupted)
    msh = mesh.create_unit_square(MPI.COMM_SELF, 2, 2)
    x = ufl.SpatialCoordinate(msh)
    a = (1.0 + x[0] * x[1] * 0.123456789) * ufl.dx(domain=msh)   # a form no other test compiles
    recipe = ("test_stop_at_start.interrupted", 0.123456789)
    with interrupt.watching():
        with pytest.raises(KeyboardInterrupt):
            compiled.form(a, recipe)
    claimed = [p.name for p in cache.glob("*.c") if not p.with_suffix(".c.cached").exists()]
    assert claimed == []   # every module claimed was compiled (or given up)
    monkeypatch.setattr(ffcx_jit, "_compile_objects", compile_objects)
    start = time.perf_counter()
    form = compiled.form(a, recipe)
    assert time.perf_counter() - start < 5.0   # FFCx's wait for a claimed module is 10 s
    from dolfinx.fem import assemble_scalar

    # the integral of 1 + 0.123456789 x y over the unit square: 1 + 0.123456789 / 4
    assert np.isclose(assemble_scalar(form), 1 + 0.123456789 / 4, rtol=1e-12)
