"""The command line (wingcrack/cli.py): exit codes and messages of the contract.

0 done; 2 invalid case, ONE line `wingcrack: error: <key>: <reason>` on stderr
and no traceback; 1 computation failed. Every invalid row of test_case.py is
run through the real command (a subprocess), and `check` through every file
in cases/.
"""
from __future__ import annotations

import importlib.util
import json
import math
import subprocess
import sys
import types
from pathlib import Path

import pytest

from wingcrack import cli
from wingcrack.errors import CaseError, ComputationError

ROOT = Path(__file__).resolve().parents[2]
CASES = sorted((ROOT / "cases").glob("*.toml"))

# test_case.py holds the table of invalid inputs; load it by path so this does
# not depend on how pytest puts tests/ on sys.path.
_spec = importlib.util.spec_from_file_location("_wingcrack_case_table", Path(__file__).parents[1] / "unit" / "test_case.py")
case_table = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(case_table)


# ---------------------------------------------------------------- helpers


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def to_toml(d: dict) -> str:
    """Enough TOML for case tables: scalars, arrays, tables, arrays of tables."""
    lines = [f"{k} = {_toml_value(v)}" for k, v in d.items() if not isinstance(v, (dict, list)) or
             (isinstance(v, list) and not (v and all(isinstance(x, dict) for x in v)))]
    for k, v in d.items():
        if isinstance(v, dict):
            lines.append(f"[{k}]")
            lines += [f"{kk} = {_toml_value(vv)}" for kk, vv in v.items()]
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            for item in v:
                lines.append(f"[[{k}]]")
                lines += [f"{kk} = {_toml_value(vv)}" for kk, vv in item.items()]
    return "\n".join(lines) + "\n"


def wingcrack(*args, cwd=None) -> subprocess.CompletedProcess:
    """Run the command line in a fresh interpreter."""
    return subprocess.run([sys.executable, "-m", "wingcrack.cli", *map(str, args)],
                          capture_output=True, text=True, cwd=cwd, timeout=120)


def assert_case_error(res: subprocess.CompletedProcess, key: str, reason: str) -> None:
    assert res.returncode == 2, res.stderr
    assert "Traceback" not in res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert lines[0].startswith(f"wingcrack: error: {key}: "), lines[0]
    assert reason in lines[0], lines[0]


# ---------------------------------------------------------------- check


@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_check_accepts_every_shipped_case(path):
    res = wingcrack("check", path)
    assert res.returncode == 0, res.stderr
    assert res.stderr == ""
    assert "ok: the case is valid" in res.stdout
    for word in ("domain:", "material:", "fractures:", "bc:", "mesh:", "propagation:"):
        assert word in res.stdout


def test_there_are_cases():
    names = {p.stem for p in CASES}
    assert {"brazilian_disc_45", "brazilian_disc_45_open", "brazilian_disc_30", "brazilian_disc_60",
            "griffith_inclined", "edge_crack_tension", "interacting_cracks"} <= names


@pytest.mark.parametrize("changes, key, reason", case_table.INVALID)
def test_invalid_case_exits_2_with_one_line(tmp_path, changes, key, reason):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(case_table.patched(*changes)))
    assert_case_error(wingcrack("check", path), key, reason)


def test_toml_writer_round_trips_the_base_case(tmp_path):
    import tomllib

    assert tomllib.loads(to_toml(case_table.BASE)) == case_table.BASE


def test_invalid_case_exits_2_for_sif_and_run_too(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(case_table.patched(("mesh", {"size": 0.2, "tip_sise": 0.05}))))
    for command in ("sif", "run"):
        res = wingcrack(command, path, "-o", tmp_path / "out")
        assert_case_error(res, "mesh.tip_sise", "did you mean tip_size?")
        assert not (tmp_path / "out").exists()


def test_syntax_error_exits_2(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text("[material\n")
    assert_case_error(wingcrack("check", path), str(path), "not valid TOML")


def test_missing_file_exits_2(tmp_path):
    assert_case_error(wingcrack("check", tmp_path / "none.toml"), str(tmp_path / "none.toml"), "cannot read")


def test_check_quiet_prints_nothing():
    res = wingcrack("check", CASES[0], "--quiet")
    assert (res.returncode, res.stdout, res.stderr) == (0, "", "")
    res = wingcrack("--quiet", "check", CASES[0])
    assert (res.returncode, res.stdout, res.stderr) == (0, "", "")


def test_check_does_not_import_dolfinx():
    code = ("import sys; from wingcrack.cli import main; rc = main(['check', '--quiet', sys.argv[1]]); "
            "assert rc == 0, rc; assert 'dolfinx' not in sys.modules")
    res = subprocess.run([sys.executable, "-c", code, str(CASES[0])], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr


def test_check_summary_of_brazilian_disc():
    res = wingcrack("check", ROOT / "cases" / "brazilian_disc_45.toml")
    out = res.stdout
    assert "disc, center (0, 0), radius 0.042 m" in out
    assert "fractures: 1, tips: 2" in out
    assert "faces frictionless" in out
    assert "tip_size 0.0005 m" in out
    assert "100 steps" in out


def test_check_accepts_coulomb_faces_and_prints_their_law(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(case_table.patched(("fractures.0.faces", "coulomb"), ("fractures.0.friction", 0.6),
                                               ("fractures.0.cohesion", 1e5))))
    res = wingcrack("check", path)
    assert res.returncode == 0, res.stderr
    assert res.stderr == "" and "ok: the case is valid" in res.stdout
    assert "faces coulomb, friction 0.6, cohesion 100000 Pa" in res.stdout
    assert "faces open, grows" in res.stdout   # fracture 1: no friction shown where there is none


def test_check_prints_fracture_pressures_and_the_load_mode(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(to_toml(case_table.patched(("fractures.1.pressure", 2.5e6),
                                               ("propagation", {"load": "pressure", "max_load_factor": 50}))))
    res = wingcrack("check", path)
    assert res.returncode == 0, res.stderr
    assert res.stderr == "" and "ok: the case is valid" in res.stdout
    lines = res.stdout.splitlines()
    frac = [line for line in lines if line.startswith("  [")][:2]
    assert "pressure" not in frac[0]                        # fracture 0 is dry: no pressure shown
    assert "faces open, pressure 2.5e+06 Pa, grows" in frac[1]
    assert "fracture pressures scaled (injection, at most x50), connected fractures share their pressure" in \
        res.stdout
    path.write_text(to_toml(case_table.patched(("fractures.0.pressure", 1e6),
                                               ("propagation", {"load": "fixed", "connect_pressure": False}))))
    res = wingcrack("check", path)
    assert res.returncode == 0, res.stderr
    assert "load fixed, each fracture keeps its own pressure" in res.stdout


def test_console_script_when_installed():
    exe = Path(sys.executable).with_name("wingcrack")
    if not exe.exists():
        pytest.skip("the wingcrack console script is not installed (make setup)")
    res = subprocess.run([str(exe), "check", str(CASES[0])], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr


def test_usage_errors_are_argparse_exit_2(tmp_path):
    res = wingcrack("sif", CASES[0])  # -o is required
    assert res.returncode == 2 and "-o" in res.stderr and "Traceback" not in res.stderr
    res = wingcrack("grow", CASES[0])
    assert res.returncode == 2 and "Traceback" not in res.stderr


# ---------------------------------------------------------------- sif / run through a stand-in api


@pytest.fixture
def fake_api(monkeypatch):
    """Replace wingcrack.api with a recorder whose behaviour the test sets."""
    api = types.ModuleType("wingcrack.api")
    api.calls = []
    api.behaviour = None

    api.result = None

    def make(name):
        def command(case, out, **options):
            api.calls.append((name, case, out, options.pop("progress", "none given")))
            api.options = options
            if api.behaviour is not None:
                raise api.behaviour
            return api.result

        return command

    api.sif, api.run = make("sif"), make("run")
    monkeypatch.setitem(sys.modules, "wingcrack.api", api)
    import wingcrack

    monkeypatch.setattr(wingcrack, "api", api, raising=False)
    return api


@pytest.mark.parametrize("command", ["sif", "run"])
def test_sif_and_run_call_the_api(fake_api, tmp_path, command, capsys):
    out = tmp_path / "out"
    assert cli.main([command, str(CASES[0]), "-o", str(out), "--quiet"]) == 0
    ((name, case, got_out, progress),) = fake_api.calls
    assert (name, got_out) == (command, out)
    assert case.source == CASES[0] and case.fractures
    # --quiet only hides run's progress bar; sif has none
    assert progress == (None if command == "run" else "none given")
    assert cli.main([command, str(CASES[0]), "-o", str(out)]) == 0
    assert (fake_api.calls[1][3] is not None) if command == "run" else fake_api.calls[1][3] == "none given"


def test_warnings_of_a_result_are_printed_once_each(fake_api, tmp_path, capsys):
    """summary.json's "warnings" (a picture not drawn, SIF methods that
    disagree) reach stderr, one line each, after the line on stdout."""
    fake_api.result = types.SimpleNamespace(files={}, summary={"status": "finished",
                                                                "warnings": ["fractures.png could not be drawn", "b"]})
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path / "out")]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("wingcrack: finished; results in ")
    assert captured.err == "wingcrack: warning: fractures.png could not be drawn\nwingcrack: warning: b\n"


def test_force_and_no_plots_reach_the_api(fake_api, tmp_path):
    out = str(tmp_path / "out")
    assert cli.main(["run", str(CASES[0]), "-o", out, "--quiet"]) == 0
    assert fake_api.options == {"plots": True, "force": False, "resume": False}
    assert cli.main(["run", str(CASES[0]), "-o", out, "--quiet", "--no-plots", "--force"]) == 0
    assert fake_api.options == {"plots": False, "force": True, "resume": False}
    assert cli.main(["run", str(CASES[0]), "-o", out, "--quiet", "--resume"]) == 0
    assert fake_api.options == {"plots": True, "force": False, "resume": True}
    assert cli.main(["sif", str(CASES[0]), "-o", out, "--quiet", "--force"]) == 0
    assert fake_api.options == {"force": True}


def test_computation_error_exits_1(fake_api, tmp_path, capsys):
    fake_api.behaviour = ComputationError("step 3: contact did not converge")
    assert cli.main(["run", str(CASES[0]), "-o", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err == "wingcrack: error: step 3: contact did not converge\n"


def test_case_error_from_the_computation_exits_2(fake_api, tmp_path, capsys):
    fake_api.behaviour = CaseError("mesh.tip_size", "too large for the mesher")
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path)]) == 2
    assert capsys.readouterr().err == "wingcrack: error: mesh.tip_size: too large for the mesher\n"


def test_unexpected_error_exits_1_in_one_line(fake_api, tmp_path, capsys):
    fake_api.behaviour = ZeroDivisionError("division by zero\nsecond line")
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert err.startswith("wingcrack: error: unexpected ZeroDivisionError: division by zero second line")
    assert "--debug" in err


def test_debug_shows_the_traceback(fake_api, tmp_path, capsys):
    fake_api.behaviour = ZeroDivisionError("division by zero")
    assert cli.main(["--debug", "sif", str(CASES[0]), "-o", str(tmp_path)]) == 1
    assert "Traceback" in capsys.readouterr().err
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path), "--debug"]) == 1
    assert "Traceback" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["sif", "run", "crosscheck", "plot"])
@pytest.mark.parametrize("name", ["", "  "])
def test_an_empty_output_folder_name_exits_2(fake_api, tmp_path, monkeypatch, capsys, command, name):
    """Issue 12.9: `-o ""` is Path("") = the current folder; refused (one
    line, exit 2) before anything is written there (`plot ""` too)."""
    monkeypatch.chdir(tmp_path)
    args = ["plot", name] if command == "plot" else [command, str(CASES[0]), "-o", name]
    assert cli.main(args) == 2
    assert capsys.readouterr().err == (f"wingcrack: error: {name!r}: an empty folder name (it would mean "
                                       "the current folder; say . for that)\n")
    assert fake_api.calls == [] and list(tmp_path.iterdir()) == []


def test_sigterm_and_ctrl_c_exit_128_plus_the_signal(fake_api, tmp_path, capsys):
    """A command stopped by SIGTERM (interrupt.Terminated) exits 143, by
    Ctrl-C 130: the codes a shell reports for a process ended by them."""
    from wingcrack.interrupt import Terminated

    fake_api.behaviour = Terminated()
    assert cli.main(["run", str(CASES[0]), "-o", str(tmp_path / "a")]) == 143
    # a clean stop, not an error; a run says what --resume has (here: nothing)
    assert capsys.readouterr().err == "wingcrack: stopped (terminated): no step was finished, so nothing to " \
                                      "resume: run it again\n"
    fake_api.behaviour = KeyboardInterrupt()
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path / "b")]) == 130
    assert capsys.readouterr().err == "wingcrack: stopped (interrupted)\n"


def test_sigterm_during_a_command_raises_terminated(fake_api, tmp_path, capsys):
    """The CLI turns SIGTERM into Terminated for the whole command (not only
    inside a run's loop): the api here is killed while it works."""
    import os
    import signal

    def work(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        for _ in range(1000):
            pass
        raise AssertionError("SIGTERM did not stop the command")

    fake_api.sif = work
    assert cli.main(["sif", str(CASES[0]), "-o", str(tmp_path / "out")]) == 143
    assert capsys.readouterr().err == "wingcrack: stopped (terminated)\n"


@pytest.mark.parametrize("command", ["sif", "run", "resume", "plot"])
@pytest.mark.parametrize("problem", ["too long", "loop"])
def test_an_unusable_output_path_exits_2(fake_api, tmp_path, capsys, command, problem):
    """Degenerate -o the system refuses before any file is made: a name over
    NAME_MAX (255 bytes) or a symlink loop; one line naming the path, not
    "unexpected OSError"."""
    if problem == "loop":
        path = tmp_path / "loop"
        path.symlink_to(path)
        reason = "Too many levels of symbolic links"
    else:
        path = tmp_path / ("a" * 300)
        reason = "File name too long"
    args = {"plot": ["plot", str(path)], "resume": ["run", str(CASES[0]), "-o", str(path), "--resume"]}.get(
        command, [command, str(CASES[0]), "-o", str(path)])
    assert cli.main(args) == 2
    assert capsys.readouterr().err == f"wingcrack: error: {path}: cannot use the path ({reason})\n"
    assert fake_api.calls == []


@pytest.mark.parametrize("command", ["sif", "run"])
def test_a_slow_step_says_what_it_is_doing(command, tmp_path):
    """A step slower than progress.SLOW_STEP (5 s; 0.2 s here through WINGCRACK_SLOW_STEP) says on
    stderr what it is doing, where no bar shows it (stderr is a pipe here); --quiet says nothing."""
    import os

    env = dict(os.environ, WINGCRACK_SLOW_STEP="0.2")
    case = tmp_path / "case.toml"
    # a step of the stimulation network (400 pairs, friction) takes seconds, so that the 0.2 s tick
    # falls inside it however fast the machine (the five-fracture case's sif step could end within 0.2 s
    # of its start: no line, and the test failed)
    case.write_text((ROOT / "cases" / "stimulation_network.toml").read_text().replace("steps = 50", "steps = 2"))
    extra = ["--no-plots"] if command == "run" else []
    cli = [sys.executable, "-m", "wingcrack.cli", command, str(case)]
    loud = subprocess.run([*cli, "-o", str(tmp_path / "a"), *extra], capture_output=True, text=True, timeout=600,
                          env=env)
    assert loud.returncode == 0, loud.stderr
    lines = [ln for ln in loud.stderr.splitlines() if ln.startswith("wingcrack: step ")]
    # which step and phase a 0.2 s tick falls in depends on the machine's speed (step 0's mesh is made
    # during the start-up and the step may take under 0.2 s; meshing took under 0.2 s on a quiet
    # machine): each line names one of the steps' phases (progress.doing's texts)
    phases = ("meshing", "factorising", "the critical-load search", "contact", "the stress intensity factors",
              "the solve", "growth")
    assert lines and all(any(f" s: {p}" in ln for p in phases) for ln in lines), loud.stderr
    quiet = subprocess.run([*cli, "-o", str(tmp_path / "b"), "--quiet", *extra], capture_output=True, text=True,
                           timeout=600, env=env)
    assert quiet.returncode == 0 and "wingcrack: step" not in quiet.stderr, quiet.stderr
