"""Sphinx configuration of wingcrack's documentation (`make docs`)."""
import json
import shutil
import sys
from pathlib import Path

import nbformat
from sphinx.errors import ExtensionError

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
# The notebooks are stored without outputs (tests/command_line/test_notebooks.py checks that);
# the site shows them with their outputs, from the executed copies in build/notebooks/ that
# the notebook test keeps and docs/executed_notebooks.py completes (docs/notebooks/*.nblink
# point there), so nothing is executed here.
nbsphinx_execute = "never"
nbsphinx_custom_formats = {".nblink": lambda text: nbformat.reads(text, as_version=4)}
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
html_theme = "alabaster"
html_theme_options = {"page_width": "1100px", "sidebar_width": "230px"}
html_static_path = ["_static"]   # custom.css
# The site needs no network (it reads as well from a file:// URL): the formulas
# are typeset by MathJax 2 from Debian's libjs-mathjax (APT_PACKAGES), whose
# files the build copies into the site (copy_mathjax); require.js, which nbsphinx
# fetches from a CDN for notebook widgets, is left out (the notebooks show none).
MATHJAX = Path("/usr/share/javascript/mathjax")
# TeX input, HTML output (CommonHTML), the menu and the AMS extensions in one file; a
# path without a scheme is one inside the site's _static/
mathjax_path = "mathjax/MathJax.js?config=TeX-AMS_CHTML"
mathjax2_config = {}   # MathJax 2 (not 3): nbsphinx adds its tex2jax settings here (math and
myst_update_mathjax = False   # notebook outputs only); MyST would add MathJax 3 settings
nbsphinx_requirejs_path = ""
# What MathJax.js loads for the configuration above: its components, TeX fonts in
# woff (every browser of the last decade reads them) and the English messages.
MATHJAX_PARTS = ("MathJax.js", "config/TeX-AMS_CHTML.js", "extensions", "jax/input/TeX",
                 "jax/output/CommonHTML", "jax/element", "fonts/HTML-CSS/TeX/woff", "localization/en")
nitpicky = True
# Types named in signatures that have no page of their own here.
nitpick_ignore_regex = [(r"py:.*", r"(meshing|dataclasses|wingcrack\.results|wingcrack\.fem|numpy|np|dolfinx|pathlib|os|typing|collections|petsc4py|mpi4py)\..*"),
                        (r"py:.*", r"(Path|ndarray|Any|Callable|Iterable|Sequence|Mapping|Optional|Union|TextIO|IO|PathLike|Function|MPI\..*|optional|callable|array.*|float.*|int.*|str.*|bool.*|dict.*|list.*|tuple.*|None.*)")]
# wingcrack.case re-exports its records; types named by their defining submodule
# (wingcrack.case.<module>.<Name>) are documented under wingcrack.case.<Name>.
nitpick_ignore_regex.append((r"py:.*", r"wingcrack\.case\.\w+\.\w+"))
suppress_warnings = ["myst.header"]


def copy_mathjax(app, exception):
    """MATHJAX_PARTS into the site's _static/mathjax/ (mathjax_path points there)."""
    if exception is not None or app.builder.format != "html":
        return
    if not (MATHJAX / "MathJax.js").is_file():
        raise RuntimeError(f"MathJax is not installed at {MATHJAX}: `make setup` installs libjs-mathjax")
    out = Path(app.outdir) / "_static" / "mathjax"
    for part in MATHJAX_PARTS:
        src, dst = MATHJAX / part, out / part
        if src.is_dir():
            shutil.copytree(src, dst, dirs_exist_ok=True)
        else:
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)


def executed_notebook(app, docname, source):
    """A notebook page (.nblink: {"path": the executed copy, from the link}) reads as
    that notebook, and is read again when the copy changes."""
    link = Path(app.env.doc2path(docname))
    if link.suffix != ".nblink":
        return
    path = (link.parent / json.loads(source[0])["path"]).resolve()
    if not path.is_file():
        raise ExtensionError(f"{path} is missing: `make docs` executes the notebooks "
                             "(docs/executed_notebooks.py) before the build")
    app.env.note_dependency(str(path))
    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        for output in cell.get("outputs", []):
            gif = output.get("data", {}).get("image/gif")
            if gif and "text/html" not in output.data:   # nbsphinx shows no GIF, HTML it does
                output.data["text/html"] = f'<img src="data:image/gif;base64,{gif.strip()}" alt="animation">'
    source[0] = nbformat.writes(nb)


def setup(app):
    app.connect("source-read", executed_notebook)
    app.connect("build-finished", copy_mathjax)
