"""Sphinx configuration of wingcrack's documentation (`make docs`)."""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

project = "wingcrack"
author = "wingcrack developers"
copyright = "wingcrack developers; method after Dang-Trung, Keilegavlen & Berre, IJSS 204-205 (2020)"
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "nbsphinx"]
source_suffix = {".md": "markdown"}
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "_generated", "**.ipynb_checkpoints"]
# The notebooks are stored without outputs (tests/command_line/test_notebooks.py checks that):
# the site shows their code and text; `make test` runs them.
nbsphinx_execute = "never"
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
html_theme = "alabaster"
html_theme_options = {"page_width": "1100px", "sidebar_width": "230px"}
html_static_path = []
nitpicky = True
# Types named in signatures that have no page of their own here.
nitpick_ignore_regex = [(r"py:.*", r"(meshing|dataclasses|wingcrack\.results|wingcrack\.fem|numpy|np|dolfinx|pathlib|os|typing|collections|petsc4py|mpi4py)\..*"),
                        (r"py:.*", r"(Path|ndarray|Any|Callable|Iterable|Sequence|Mapping|Optional|Union|TextIO|IO|PathLike|Function|MPI\..*|optional|callable|array.*|float.*|int.*|str.*|bool.*|dict.*|list.*|tuple.*|None.*)")]
# wingcrack.case re-exports its records; types named by their defining submodule
# (wingcrack.case.<module>.<Name>) are documented under wingcrack.case.<Name>.
nitpick_ignore_regex.append((r"py:.*", r"wingcrack\.case\.\w+\.\w+"))
suppress_warnings = ["myst.header"]
