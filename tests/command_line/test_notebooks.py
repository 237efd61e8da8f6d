"""The teaching notebooks in notebooks/ run top to bottom without an error,
and are kept in git without outputs.

They run in the Jupyter kernel "wingcrack" that `make setup` installs into
the venv (.venv/share/jupyter/kernels/wingcrack: it starts .venv/bin/python,
which sees DOLFINx and wingcrack). Measured here: 01 about 10 s, 02 about
6 s, 03 about 50 s (34 propagation steps), 04 about 10 s, 05 about 12 s (eleven solves, a
101-increment load path, a 10-step run); each must stay under 2 minutes,
and a cell that hangs fails at CELL_TIMEOUT.

A notebook that ran without an error is kept with its outputs in
build/notebooks/ (docs/executed_notebooks.py): the site shows those, and
`make docs` executes only a notebook whose copy is missing or stale.
"""
import sys
from pathlib import Path

import nbformat
import pytest
from jupyter_client.kernelspec import KernelSpecManager, NoSuchKernel

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs"))
from executed_notebooks import FOLDER, KERNEL, NOTEBOOKS, digest, execute, keep  # noqa: E402


def test_the_notebooks_are_there():
    assert sorted(p.stem for p in FOLDER.glob("*.ipynb")) == NOTEBOOKS


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_is_committed_without_outputs(name):
    nb = nbformat.read(FOLDER / f"{name}.ipynb", as_version=4)
    nbformat.validate(nb)
    assert nb.metadata.kernelspec.name == KERNEL
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None, f"cell {i} has outputs: strip them"


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_runs(name, tmp_path, monkeypatch):
    """Every cell runs without an exception (nbclient raises
    CellExecutionError naming the cell). Files the notebook writes go to
    tmp_path (the kernel inherits the environment)."""
    try:
        KernelSpecManager().get_kernel_spec(KERNEL)
    except NoSuchKernel:
        pytest.fail(f"no Jupyter kernel {KERNEL!r} in the venv: run `make setup`")
    monkeypatch.setenv("WINGCRACK_NOTEBOOK_OUT", str(tmp_path))
    source_digest = digest(name)
    nb = execute(name)
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"]
    assert not errors, errors
    keep(name, nb, source_digest)   # for the site
