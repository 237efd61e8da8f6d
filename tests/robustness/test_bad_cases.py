"""The bad-input corpus tests/bad_cases/: every file is a malformed case,
and both `wingcrack check` and `wingcrack sif -o OUT` must refuse it the way
the contract says (/work/shared/spec/case-format.md, "Exit status"): status
2, exactly one line on stderr naming the key (or the file, for what is not
TOML) and the reason, no traceback, nothing on stdout, no output folder.

Each file starts with a comment saying what is wrong with it;
tests/bad_cases/expected.tsv maps its name to the key the message must name
and a fragment of the reason. The 10 MB file is made at run time.

The table runs through `wingcrack.cli.main`, the function behind the console
script, in this process (a subprocess per file would cost ~0.45 s each), with
capfd so that anything written to the stderr file descriptor counts and with
warnings turned into errors so that a RuntimeWarning (an overflow the checks
let through) fails the row instead of printing a second line. A sample of
files, and the 10 MB one, also go through the installed console script.
"""
from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from wingcrack import cli
from wingcrack.case import MAX_FILE_BYTES, Case

HERE = Path(__file__).resolve().parents[1]   # tests/
CORPUS = HERE / "bad_cases"
CASES = HERE.parent / "cases"


def _table() -> dict[str, tuple[str, str]]:
    rows = {}
    for line in (CORPUS / "expected.tsv").read_text().splitlines():
        if line and not line.startswith("#"):
            name, key, reason = line.split("\t")
            rows[name] = (key, reason)
    return rows


EXPECTED = _table()


def base_text() -> str:
    """The valid case every corpus file breaks: missing_E.toml with E put back
    (its first line still says that E is missing)."""
    return (CORPUS / "missing_E.toml").read_text().replace("nu = 0.25", "E = 1.0e10\nnu = 0.25")


def _expected(path: Path) -> tuple[str, str]:
    key, reason = EXPECTED[path.stem]
    return key.replace("{file}", str(path)), reason


def assert_refused(rc: int, out: str, err: str, key: str, reason: str) -> None:
    assert rc == 2, err
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"wingcrack: error: {key}"), lines[0]
    assert reason in lines[0], lines[0]
    assert out == ""


def run_main(argv: list[str], capfd) -> tuple[int, str, str]:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rc = cli.main(argv)
    out, err = capfd.readouterr()
    return rc, out, err


# ---------------------------------------------------------------- the corpus itself


def test_corpus_and_table_agree():
    files = {p.stem for p in CORPUS.glob("*.toml")}
    assert files == set(EXPECTED), (files ^ set(EXPECTED))
    assert len(files) >= 50


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_each_file_says_what_is_wrong_on_its_first_line(name):
    raw = (CORPUS / f"{name}.toml").read_bytes()
    text = raw.decode("utf-16") if raw.startswith((b"\xff\xfe", b"\xfe\xff")) else raw.decode("utf-8", "replace")
    first = text.splitlines()[0] if text else ""
    assert first.startswith("# ") and len(first) > 10, first


def test_the_base_of_the_corpus_is_valid(tmp_path):
    path = tmp_path / "base.toml"
    path.write_text(base_text())
    assert len(Case.from_toml(path).tips()) == 2


# ---------------------------------------------------------------- check and sif on every file


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_check_refuses(name, capfd):
    path = CORPUS / f"{name}.toml"
    assert_refused(*run_main(["check", str(path)], capfd), *_expected(path))


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_sif_refuses_and_writes_nothing(name, tmp_path, capfd):
    path = CORPUS / f"{name}.toml"
    out = tmp_path / "out"
    assert_refused(*run_main(["sif", str(path), "-o", str(out)], capfd), *_expected(path))
    assert not out.exists()


# ---------------------------------------------------------------- the real console script


def console(*args) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).with_name("wingcrack")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "wingcrack.cli"]
    return subprocess.run(cmd + [str(a) for a in args], capture_output=True, text=True, timeout=120)


SAMPLE = ["syntax_nul_byte", "not_utf8", "deeply_nested_array", "coordinates_huge", "fractures_crossing_flat",
          "conflicting_corner"]


@pytest.mark.parametrize("name", SAMPLE)
def test_console_script_refuses(name, tmp_path):
    path = CORPUS / f"{name}.toml"
    for args in (["check", path], ["sif", path, "-o", tmp_path / "out"]):
        res = console(*args)
        assert_refused(res.returncode, res.stdout, res.stderr, *_expected(path))
    assert not (tmp_path / "out").exists()


def test_ten_megabyte_file_is_refused_unread(tmp_path):
    # A valid case followed by a fracture of ~400,000 points: 10 MB, which the
    # quadratic geometry checks would take minutes over. Refused by its size.
    head = base_text()
    point = "[1.5, 0.8], "
    count = (10 * 2**20) // len(point)
    path = tmp_path / "huge.toml"
    with open(path, "w") as fh:
        fh.write(head + "\n[[fractures]]\npoints = [" + point * count + "[2.5, 1.2]]\n")
    assert path.stat().st_size > 10 * 2**20 > MAX_FILE_BYTES
    out = tmp_path / "out"
    for args in (["check", path], ["sif", path, "-o", out]):
        res = console(*args)
        assert_refused(res.returncode, res.stdout, res.stderr, str(path), "too large")
    assert not out.exists()


def test_half_a_megabyte_title_is_refused(tmp_path, capfd):
    # The reproduction: 500,000 characters overflowed matplotlib's
    # raster when fractures.png was drawn, after the solve. The corpus holds
    # a 1,000-character one (title_huge.toml).
    path = tmp_path / "case.toml"
    path.write_text(base_text().replace('title = "plate with an inclined crack"', 'title = "' + "x" * 500_000 + '"'))
    for argv in (["check", str(path)], ["sif", str(path), "-o", str(tmp_path / "out")]):
        assert_refused(*run_main(argv, capfd), "title", "got 500000")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("kind", ["fifo", "directory", "dev-zero"])
def test_a_case_that_is_not_a_regular_file_is_refused(kind, tmp_path, capfd):
    """A FIFO blocked `check` forever (open waits for a writer); a directory
    and /dev/zero are no case either. Refused before reading, naming the file;
    the alarm turns a hang into a failure."""
    import os
    import signal

    path = {"fifo": tmp_path / "case.toml", "directory": tmp_path / "dir.toml", "dev-zero": Path("/dev/zero")}[kind]
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "directory":
        path.mkdir()

    def hung(signum, frame):
        raise TimeoutError(f"{kind}: the CLI blocked")

    old = signal.signal(signal.SIGALRM, hung)
    signal.setitimer(signal.ITIMER_REAL, 20.0)
    try:
        for argv in (["check", str(path)], ["sif", str(path), "-o", str(tmp_path / "out")]):
            assert_refused(*run_main(argv, capfd), str(path), "not a regular file")
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)
    assert not (tmp_path / "out").exists()


# ---------------------------------------------------------------- valid neighbours of the new checks


def _neighbour(tmp_path, old: str, new: str) -> Case:
    text = base_text()
    assert old in text
    path = tmp_path / "case.toml"
    path.write_text(text.replace(old, new))
    return Case.from_toml(path)


BCS = "[[bc]]\nat = [4.0, 1.0]\ndisplacement_y = 0.0\n"


@pytest.mark.parametrize("extra", [
    # a point of a held side, held at the same value
    '[[bc]]\non = "left"\ndisplacement_y = 0.0\n[[bc]]\nat = [0.0, 0.5]\ndisplacement_y = 0.0\n',
    # two sides meeting at a corner, holding different components
    '[[bc]]\non = "right"\ndisplacement_x = 0.0\n[[bc]]\non = "bottom"\ndisplacement_y = 0.001\n',
    # opposite sides (no common point) at different values
    '[[bc]]\non = "left"\ndisplacement_x = 0.0\n[[bc]]\non = "right"\ndisplacement_x = 0.001\n',
])
def test_conditions_that_do_not_conflict(tmp_path, extra):
    assert _neighbour(tmp_path, BCS, BCS + extra).bcs


def test_edge_crack_with_one_end_on_the_boundary_is_valid(tmp_path):
    case = _neighbour(tmp_path, "points = [[1.5, 0.8], [2.5, 1.2]]", "points = [[0.0, 0.5], [1.0, 0.7]]")
    assert len(case.tips()) == 1


@pytest.mark.parametrize("scale", [1e-9 / 4, 1e9 / 4])
def test_domain_at_the_ends_of_the_verified_range(tmp_path, scale):
    text = base_text()
    for old, new in [("size = [4.0, 2.0]", "size = [{}, {}]".format(4 * scale, 2 * scale)),
                     ("[[1.5, 0.8], [2.5, 1.2]]", "[[{}, {}], [{}, {}]]".format(1.5 * scale, 0.8 * scale,
                                                                               2.5 * scale, 1.2 * scale)),
                     ("at = [0.0, 1.0]", f"at = [0.0, {scale}]"), ("at = [4.0, 1.0]", f"at = [{4 * scale}, {scale}]"),
                     ("size = 0.2", f"size = {0.2 * scale}"), ("tip_size = 0.05", f"tip_size = {0.05 * scale}")]:
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "case.toml"
    path.write_text(text)
    assert len(Case.from_toml(path).tips()) == 2


# E and the loads at the two ends of what `check` accepts: the case of the
# issue's reproductions (a 2 m plate, a 0.28 m crack at 45 degrees, tractions
# sigma on top and bottom) with E at 1 kPa and sigma = 0.1 E, and with E at
# 1e13 Pa and sigma = 0.1 E; the middle one is the base case.
LIMITS_BASE = """
[material]
E = {E}
nu = 0.25
KIc = {KIc}
[domain]
shape = "rectangle"
corner = [-1.0, -1.0]
size = [2.0, 2.0]
[[fractures]]
points = [[-0.1, -0.1], [0.1, 0.1]]
[[bc]]
on = "top"
traction = [0.0, {s}]
[[bc]]
on = "bottom"
traction = [0.0, -{s}]
[[bc]]
at = [-1.0, 0.0]
displacement = [0.0, 0.0]
[[bc]]
at = [1.0, 0.0]
displacement_y = 0.0
[mesh]
size = 0.2
tip_size = 0.02
"""


def test_the_magnitude_limits_solve_cleanly(tmp_path, capfd):
    """With traction loads K does not depend on E and is linear in sigma, and
    the geometry, hence the mesh, is the same: K / sigma must agree across 13
    orders of magnitude of E up to the solve's rounding (measured 1e-10
    relative; 1e-8 allowed). A NaN, an overflow or an exit other than 0 fails."""
    import json

    ratios = []
    for E, KIc in ((1e3, 1.0), (1e10, 1e6), (1e13, 1e9)):
        path, out = tmp_path / f"E{E:g}.toml", tmp_path / f"out{E:g}"
        path.write_text(LIMITS_BASE.format(E=E, KIc=KIc, s=0.1 * E))
        rc, _, err = run_main(["-q", "sif", str(path), "-o", str(out)], capfd)
        assert rc == 0, err
        summary = json.loads((out / "summary.json").read_text())
        assert summary["status"] == "finished"
        ratios.append([t[k] / (0.1 * E) for t in summary["steps"][0]["tips"] for k in ("KI", "KII")])
    for r in ratios[::2]:
        assert r == pytest.approx(ratios[1], rel=1e-8)
