"""Issue 6, files people open: the ParaView indices, the pictures of a run
(fractures.png, history.png, the growth animation), `wingcrack plot` and its
bad inputs, and what `wingcrack run` prints.

One short propagation (an inclined frictionless crack in a 4 m plate under
compression: 4 steps, ~7,000 DOFs, closed faces, load factors that repeat)
is run once through the real command and read by every test.
"""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from wingcrack import cli
from wingcrack.progress import progress_text

W = 4.0   # plate side (m)
PLATE = f"""
title = "Inclined crack under compression"
[material]
E = 10e9
nu = 0.25
KIc = 1.0e6
plane = "strain"
[domain]
shape = "rectangle"
corner = [{-W / 2}, {-W / 2}]
size = [{W}, {W}]
[[fractures]]
points = [[-0.35, -0.35], [0.35, 0.35]]
faces = "frictionless"
[[bc]]
on = "top"
traction = [0.0, -1.0e6]
[[bc]]
on = "bottom"
displacement = [0.0, 0.0]
[mesh]
size = 0.5
tip_size = 0.05
[propagation]
steps = 4
length = 0.1
"""
STEPS = 4


def wingcrack(*args) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "wingcrack.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def plate_case(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("case") / "plate.toml"
    path.write_text(PLATE)
    return path


@pytest.fixture(scope="module")
def run(plate_case, tmp_path_factory):
    """(folder, completed process, summary) of `wingcrack run` (no --quiet;
    stderr is not a terminal, so no bar either)."""
    out = tmp_path_factory.mktemp("run") / "out"
    res = wingcrack("run", plate_case, "-o", out)
    assert res.returncode == 0, res.stderr
    return out, res, json.loads((out / "summary.json").read_text())


# ---------------------------------------------------------------- ParaView


@pytest.mark.parametrize("index, pattern", [("fields.pvd", "step_{:04d}.vtu"), ("faces.pvd", "faces_{:04d}.vtu")])
def test_pvd_lists_exactly_the_step_files_with_increasing_times(run, index, pattern):
    out, _, summary = run
    root = ET.parse(out / index).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    sets = root.findall("./Collection/DataSet")
    assert [d.get("file") for d in sets] == [pattern.format(k) for k in range(STEPS)]
    times = [float(d.get("timestep")) for d in sets]
    assert times == [float(s["step"]) for s in summary["steps"]]
    assert all(b > a for a, b in zip(times, times[1:]))
    assert all((out / d.get("file")).is_file() for d in sets)
    on_disk = sorted(p.name for p in out.glob(pattern.replace("{:04d}", "*")))
    assert on_disk == [d.get("file") for d in sets]


def test_pvd_refuses_times_that_do_not_increase(tmp_path):
    from wingcrack.io.pvd import read_pvd, write_pvd

    with pytest.raises(ValueError, match="increase strictly"):
        write_pvd(tmp_path / "x.pvd", ["a.vtu", "b.vtu"], times=[1.0, 1.0])
    write_pvd(tmp_path / "x.pvd", ["a.vtu", "b.vtu"], times=[0.5, 2.0])
    assert read_pvd(tmp_path / "x.pvd") == [(0.5, "a.vtu"), (2.0, "b.vtu")]


def test_load_factors_repeat_so_the_time_is_the_step(run):
    """Why the pvd time is the step number: this run's load factor repeats
    (growth without a load increase), which ParaView cannot take as time."""
    lam = [s["load_factor"] for s in run[2]["steps"]]
    assert len(set(lam)) < len(lam)


def test_step_files_hold_the_fields_and_their_load_factor(run):
    """displacement (x, y, 0); the stress as a symmetric 3 x 3 tensor with
    no out-of-plane part; von Mises of its in-plane components; the step
    and load factor as field data (what ParaView shows as global data)."""
    import meshio

    out, _, summary = run
    for k, step in enumerate(summary["steps"]):
        m = meshio.read(out / f"step_{k:04d}.vtu")
        assert m.field_data["step"][0] == k
        assert m.field_data["load_factor"][0] == step["load_factor"]
        u, s, vm = m.point_data["displacement"], m.point_data["stress"], m.point_data["von_mises"]
        assert u.shape == (len(m.points), 3) and np.all(u[:, 2] == 0)
        assert s.shape == (len(m.points), 9)
        t = s.reshape(-1, 3, 3)
        assert np.array_equal(t, t.transpose(0, 2, 1), equal_nan=True)
        assert np.all(t[:, 2, :] == 0) and np.all(t[:, :, 2] == 0)
        ok = np.isfinite(vm)   # a tip node, where the stress is singular, may be NaN
        assert ok.mean() > 0.99
        sxx, syy, sxy = t[ok, 0, 0], t[ok, 1, 1], t[ok, 0, 1]
        assert np.allclose(vm[ok], np.sqrt(sxx ** 2 - sxx * syy + syy ** 2 + 3 * sxy ** 2), rtol=1e-12)
        f = meshio.read(out / f"faces_{k:04d}.vtu")
        assert f.field_data["load_factor"][0] == step["load_factor"]
        assert {"opening", "slip", "normal_traction", "closed", "state", "tangential_traction",
                "slip_increment", "pressure"} <= set(f.point_data)
        # issue 15: a dry fracture, in the step's record and its face file alike
        assert step["pressures"] == [0.0] and not f.point_data["pressure"].any()


# ---------------------------------------------------------------- pictures


def test_run_prints_only_where_the_results_are(run):
    out, res, summary = run
    assert res.stderr == ""
    lines = res.stdout.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"wingcrack: finished; results in {out}/: ")
    for name in ("summary.json", "fields.pvd", "faces.pvd", "fractures.png", "history.png", "growth."):
        assert name in lines[0]


def _animation(out: Path) -> tuple[Path, int]:
    """The animation and its number of frames (PIL for a GIF, ffprobe for an MP4)."""
    gif = out / "growth.gif"
    if gif.exists():
        from PIL import Image

        with Image.open(gif) as im:
            return gif, im.n_frames
    mp4 = out / "growth.mp4"
    if not shutil.which("ffprobe"):
        pytest.skip("growth.mp4 written (ffmpeg on PATH) but no ffprobe to count its frames")
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=nb_read_frames", "-of", "csv=p=0", str(mp4)], capture_output=True, text=True)
    return mp4, int(probe.stdout.strip())


def test_pictures_exist_and_the_animation_has_a_frame_per_step(run):
    from PIL import Image

    out, _, summary = run
    for name in ("fractures.png", "history.png"):
        with Image.open(out / name) as im:
            assert im.format == "PNG" and min(im.size) > 300
    path, frames = _animation(out)
    assert path.suffix == (".mp4" if shutil.which("ffmpeg") else ".gif")
    assert frames == len(summary["steps"]) == STEPS


def test_history_draws_the_values_of_summary_json(run, tmp_path):
    from wingcrack.io.history import plot_history

    summary = run[2]
    drawn = plot_history(tmp_path / "history.png", summary)
    steps = np.arange(STEPS, dtype=float)
    x, y = drawn["load factor"]
    assert np.array_equal(x, steps) and np.array_equal(y, [s["load_factor"] for s in summary["steps"]])
    x, y = drawn["DOFs"]
    assert np.array_equal(y, [s["dofs"] for s in summary["steps"]])
    tips = {(t["fracture"], t["end"]) for s in summary["steps"] for t in s["tips"]}
    assert len(tips) == 2
    for f, e in tips:
        x, y = drawn[f"fracture {f} end {e}"]
        want = [next(t["K_eq"] for t in s["tips"] if (t["fracture"], t["end"]) == (f, e)) for s in summary["steps"]]
        assert np.array_equal(y, want)


def test_the_run_records_its_toughness_and_history_draws_it(run, tmp_path):
    """summary.json of a real run holds the case's KIc (1.0e6 in PLATE), and history.png's KIc line is
    drawn at it: the line the tips' K_eq is held against comes from the result, not from a guess."""
    from wingcrack.io.history import plot_history

    summary = run[2]
    assert summary["KIc"] == 1.0e6
    drawn = plot_history(tmp_path / "history.png", summary)
    assert np.all(drawn["KIc"][1] == 1.0e6)
    # the run is searched and frictionless: each step records its own critical load factor, at most the held one
    for s in summary["steps"]:
        assert s["critical_load_factor"] <= s["load_factor"] * (1 + 1e-9)


def test_k_eq_is_computed_when_a_summary_lacks_it(run):
    """A contract summary need not hold K_eq: eq. (10) from KI, KII, theta."""
    from wingcrack.io.history import history

    summary = json.loads(json.dumps(run[2]))
    want = history(summary)["k_eq"]
    for s in summary["steps"]:
        for t in s["tips"]:
            del t["K_eq"]
    got = history(summary)["k_eq"]
    for key in want:
        assert np.allclose(got[key], want[key], rtol=1e-12)


def test_growth_segments_are_the_advances_of_each_step(run):
    """Each coloured segment joins a tip's position in a step to where that
    step took it: its length is the tip's `advance`, one per growing tip."""
    from wingcrack.io.pictures import growth_segments

    summary = run[2]
    segs = growth_segments(summary)
    grown = [(k, t["advance"]) for k, s in enumerate(summary["steps"]) for t in s["tips"] if t["advance"] > 0]
    assert len(segs) == len(grown) >= STEPS
    for (p0, p1, k), (k2, adv) in zip(segs, grown):
        assert k == k2
        assert abs(np.hypot(p1[0] - p0[0], p1[1] - p0[1]) - adv) < 1e-12 * max(adv, 1.0)


def test_closed_faces_come_from_the_face_files(run):
    """Every step of this run has faces in contact (summary.json), and the
    face files mark closed edges where fractures.png draws them."""
    from wingcrack.io.outdir import read_result

    out, _, summary = run
    result = read_result(out)
    for k, s in enumerate(summary["steps"]):
        assert s["contact"]["closed"] > 0
        assert result.faces_of(k).closed.any()


def test_frictionless_faces_in_contact_slip(run):
    """Issue 14 on a frictionless run: every pair in contact slips (t_t = 0
    is its Coulomb bound for mu = c = 0), none sticks, in summary.json and
    in the face files alike; no tangential row, so no tangential traction,
    and no slip increment (no friction law acted)."""
    import meshio

    from wingcrack.io.faces import OPEN, SLIP

    out, _, summary = run
    for k, s in enumerate(summary["steps"]):
        c = s["contact"]
        assert (c["stick"], c["slip"], c["fallback"]) == (0, c["closed"], False) and "friction" not in c
        d = meshio.read(out / f"faces_{k:04d}.vtu").point_data
        assert set(np.unique(d["state"])) == {OPEN, SLIP}
        assert np.array_equal(d["state"] == SLIP, d["closed"] > 0.5)
        assert np.sum(d["state"] == SLIP) == c["slip"]   # one fracture, no junction: a + node is one pair
        assert not d["tangential_traction"].any() and not d["slip_increment"].any()


def test_the_picture_bands_the_last_steps_faces_by_state(run, tmp_path):
    """fractures.png of the run draws the last step's face edges, each in
    the band of its state read from the face file: slipping where closed,
    open elsewhere, no stick band and no stick legend entry."""
    from wingcrack.io.outdir import read_result
    from wingcrack.io.pictures import fractures_of_result

    result = read_result(run[0])
    faces = result.faces_of(STEPS - 1)
    drawn = fractures_of_result(tmp_path / "fractures.png", result)
    assert np.array_equal(drawn["faces slip"], faces.lines[faces.closed])
    assert np.array_equal(drawn["faces open"], faces.lines[~faces.closed])
    assert "faces stick" not in drawn and "faces stick" not in drawn["legend"]
    assert {"faces open", "faces slip", "pre-existing", "wing (colour: step)"} <= set(drawn["legend"])


def test_the_pictures_legend_covers_no_fracture_and_stays_in_the_image(run, tmp_path, monkeypatch):
    """fractures.png's legend lies outside both panels (inside the domain's panel it covered fractures
    wherever a network had them: the 1,000-fracture network's legend sat on its corner), and the saved
    image holds it and both titles whole (saved "tight": every artist's box within the image)."""
    from matplotlib.figure import Figure
    from matplotlib.transforms import Bbox

    from wingcrack.io.outdir import read_result
    from wingcrack.io.pictures import fractures_of_result

    figures = []
    save = Figure.savefig
    monkeypatch.setattr(Figure, "savefig", lambda self, *a, **k: (figures.append((self, k)), save(self, *a, **k))[1])
    fractures_of_result(tmp_path / "fractures.png", read_result(run[0]))
    (fig, kwargs), = figures
    assert kwargs.get("bbox_inches") == "tight"
    renderer = fig.canvas.get_renderer()
    legend = fig.axes[0].get_legend()
    box = legend.get_window_extent(renderer)
    for ax in fig.axes:
        assert not box.overlaps(ax.get_window_extent(renderer)), ax.get_title()
    every = Bbox.union([a.get_window_extent(renderer) for a in [legend, *(ax.title for ax in fig.axes)]])
    assert fig.get_tightbbox(renderer).transformed(fig.dpi_scale_trans).contains(every.x0 + 1, every.y0 + 1)


def test_the_animation_bands_each_steps_faces_by_state(run, tmp_path):
    """Every frame of the growth animation bands its step's face edges in
    the state the face file holds: on a copy of the run whose face file of
    step 1 marks the closed nodes of one half of the fracture (x < 0) as
    sticking (this frictionless run has none), that frame shows all three
    states; the others open and slip only, read back from the figure. The
    legend is one for the run: the states some frame shows."""
    import meshio

    from wingcrack.io.animation import animate_growth
    from wingcrack.io.faces import SLIP, STICK
    from wingcrack.io.outdir import read_result

    out = tmp_path / "out"
    shutil.copytree(run[0], out)
    path = out / "faces_0001.vtu"
    m = meshio.read(path)
    state = np.asarray(m.point_data["state"]).copy()
    state[(state == SLIP) & (m.points[:, 0] < 0)] = STICK
    m.point_data["state"] = state
    m.write(path)
    result = read_result(out)
    drawn = []
    animate_growth(out, result, "gif", drawn=drawn)
    assert len(drawn) == STEPS
    for k, frame in enumerate(drawn):
        faces = result.faces_of(k)
        assert faces.closed.any()
        for code, label in ((0, "faces open"), (STICK, "faces stick"), (SLIP, "faces slip")):
            want = faces.lines[faces.state == code]
            if len(want):
                assert np.array_equal(frame[label], want), (k, label)
            else:
                assert label not in frame, (k, label)
        assert frame["legend"] == ["fracture", "faces open", "faces stick", "faces slip"]
    # the doctored step: its stick and slip bands split the closed edges at x = 0
    assert set(drawn[1]) == {"faces open", "faces stick", "faces slip", "legend"}
    assert np.all(drawn[1]["faces stick"][:, :, 0].max(axis=1) < 1e-12)
    assert "faces stick" not in drawn[0]


# ---------------------------------------------------------------- fluid pressure (issue 15)


@pytest.fixture(scope="module")
def wet_run(run, tmp_path_factory):
    """A copy of the run as if fracture 0 held fluid at 1 MPa times the step
    number (step 0 dry): each step's pressures in summary.json and the
    pressure in its face file (every node), what a pressurised run writes."""
    import meshio

    out = tmp_path_factory.mktemp("wet") / "out"
    shutil.copytree(run[0], out)
    summary = json.loads((out / "summary.json").read_text())
    for k, s in enumerate(summary["steps"]):
        s["pressures"] = [1e6 * k]
        path = out / f"faces_{k:04d}.vtu"
        m = meshio.read(path)
        m.point_data["pressure"] = np.full(len(m.points), 1e6 * k)
        m.write(path)
    (out / "summary.json").write_text(json.dumps(summary))
    return out, summary


def test_the_picture_rims_the_pressurised_fracture_from_the_summary(wet_run, tmp_path):
    """fractures.png of the wet copy: one rim along fracture 0, its wings
    and its pre-existing part chained as summary["fractures"] lists them, at
    the last step's pressure, named in the legend; the state bands as dry."""
    from wingcrack.io.outdir import read_result
    from wingcrack.io.pictures import fractures_of_result

    out, summary = wet_run
    drawn = fractures_of_result(tmp_path / "fractures.png", read_result(out))
    pieces = [np.asarray(f["points"], float) for f in summary["fractures"] if f["fracture"] == 0]
    assert len(pieces) == 3   # both wings and the pre-existing part
    want = np.vstack([pieces[0]] + [p[1:] for p in pieces[1:]])
    assert len(drawn["pressurised"]["lines"]) == 1 and np.array_equal(drawn["pressurised"]["lines"][0], want)
    last = summary["steps"][-1]["pressures"][0]
    assert np.array_equal(drawn["pressurised"]["pressure"], [last])
    assert drawn["legend"][-1] == f"pressurised: p = {last / 1e6:.3g} MPa" == "pressurised: p = 3 MPa"
    faces = read_result(out).faces_of(STEPS - 1)
    assert np.array_equal(drawn["faces slip"], faces.lines[faces.closed])


def test_the_animation_rims_each_steps_wet_edges_from_its_face_file(wet_run, tmp_path):
    """Every frame rims the edges whose face-file pressure is above 0, at
    that pressure; the dry step 0 none; one legend entry for the run."""
    from wingcrack.io.animation import animate_growth
    from wingcrack.io.outdir import read_result

    result = read_result(wet_run[0])
    drawn = []
    animate_growth(tmp_path, result, "gif", drawn=drawn)
    assert "pressurised" not in drawn[0]
    for k, frame in enumerate(drawn[1:], start=1):
        faces = result.faces_of(k)
        assert np.array_equal(frame["pressurised"]["lines"], faces.lines)
        assert np.array_equal(frame["pressurised"]["pressure"], np.full(len(faces.lines), 1e6 * k))
        assert frame["legend"][-1] == "pressurised (colour: p)"


def test_history_of_the_wet_copy_draws_injection_and_slipping_length(wet_run, tmp_path):
    """The injection pressure per step (MPa) from summary.json; the slipping
    length from the face files. Step 0 checks it against the geometry: all
    of the crack, 0.7 sqrt(2) m, slips (frictionless, closed) but its two
    tip edges, whose tip node is no pair; the rosette's first ring, where
    they end, is at mesh.tip_size = 0.05 m from the tip."""
    from wingcrack.io.history import plot_history
    from wingcrack.io.outdir import read_result

    out, summary = wet_run
    result = read_result(out)
    drawn = plot_history(tmp_path / "history.png", summary, result)
    assert np.array_equal(drawn["injection pressure"][1], [0.0, 1.0, 2.0, 3.0])
    x, slipping = drawn["slipping length"]
    assert np.array_equal(x, np.arange(STEPS, dtype=float))
    assert abs(slipping[0] - (0.7 * np.sqrt(2.0) - 2 * 0.05)) < 1e-9
    assert np.all(slipping > 0)


def test_the_dry_run_draws_no_pressure(run, tmp_path):
    """This run's fracture holds no fluid: no rim, no pressure panel."""
    from wingcrack.io.history import plot_history
    from wingcrack.io.outdir import read_result
    from wingcrack.io.pictures import fractures_of_result

    result = read_result(run[0])
    assert "pressurised" not in fractures_of_result(tmp_path / "f.png", result)
    assert "injection pressure" not in plot_history(tmp_path / "h.png", run[2], result)


def test_outer_boundary_of_the_cracked_mesh_is_the_plate(run):
    """The mesh's free edges less the (paired) crack faces: the 4 x 4 plate,
    perimeter 16 m, every edge on a side."""
    from wingcrack.io.outdir import read_result
    from wingcrack.io.pictures import outer_boundary

    result = read_result(run[0])
    mesh = result.fields_of(STEPS - 1)
    b = outer_boundary(mesh.x, mesh.triangles)
    assert abs(np.linalg.norm(b[:, 1] - b[:, 0], axis=1).sum() - 4 * W) < 1e-9
    assert np.all(np.isclose(np.abs(b), W / 2).any(axis=2))


def test_plot_redraws_the_pictures_and_leaves_the_data(run, tmp_path, capsys):
    """`wingcrack plot` on a copy of the result: the three pictures again,
    the data files byte for byte unchanged, one line on stdout."""
    out = tmp_path / "copy"
    shutil.copytree(run[0], out)
    data = {p.name: p.read_bytes() for p in out.iterdir() if p.suffix in (".json", ".vtu", ".pvd")}
    pictures = ("fractures.png", "history.png", _animation(out)[0].name)
    for name in pictures:
        (out / name).unlink()
    assert cli.main(["plot", str(out)]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    assert captured.out == f"wingcrack: pictures in {out}/: " + ", ".join(sorted(pictures)) + "\n"
    assert all((out / name).is_file() for name in pictures)
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.name in data} == data
    assert _animation(out)[1] == STEPS


def test_plot_of_a_failed_run_draws_its_finished_steps(run, tmp_path):
    """A run that failed at step 2 keeps steps 0 and 1: plot draws them."""
    from PIL import Image

    from wingcrack import api

    out = tmp_path / "failed"
    shutil.copytree(run[0], out)
    summary = json.loads((out / "summary.json").read_text())
    summary["status"] = "failed: step 2: gmsh could not mesh (simulated)"
    summary["steps"] = summary["steps"][:2]
    (out / "summary.json").write_text(json.dumps(summary))
    files = api.plot(out, fmt="gif")
    assert {"picture", "history", "animation"} <= set(files)
    with Image.open(files["animation"]) as im:
        assert im.n_frames == 2


# ---------------------------------------------------------------- bad input


def one_error_line(capsys) -> str:
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err, captured.err
    assert captured.out == ""
    return lines[0]


def test_plot_a_missing_folder_exits_2(tmp_path, capsys):
    assert cli.main(["plot", str(tmp_path / "none")]) == 2
    assert one_error_line(capsys) == f"wingcrack: error: {tmp_path / 'none'}: no such folder"


def test_plot_a_folder_without_summary_exits_2(tmp_path, capsys):
    (tmp_path / "notes.txt").write_text("not a result")
    assert cli.main(["plot", str(tmp_path)]) == 2
    assert one_error_line(capsys) == f"wingcrack: error: {tmp_path}: not a wingcrack result (no summary.json)"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


@pytest.mark.parametrize("text, reason", [
    ("{not json", "not readable as JSON"),
    ('["a", "list"]', "not a JSON object"),
    ('{"name": "another program", "steps": []}', "no 'title' text"),
    ('{"title": "t", "version": "1", "status": "finished", "steps": [{"step": 3}], "fractures": []}',
     "steps[0] is not step 0"),
    ('{"title": "t", "version": "1", "status": "finished", "steps": [{"step": 0, "load_factor": 1.0}],'
     ' "fractures": []}', "lacks 'load_factor', 'dofs' or 'tips'"),
    ('{"title": "t", "version": "1", "status": "finished", "steps": [{"step": 0, "load_factor": 1.0, "dofs": 9,'
     ' "tips": [], "pressures": [1e6, -2.0]}], "fractures": []}',
     "steps[0].pressures is not a list of fracture pressures (Pa, numbers >= 0)"),
])
def test_plot_a_summary_that_is_not_ours_exits_2(tmp_path, capsys, text, reason):
    (tmp_path / "summary.json").write_text(text)
    assert cli.main(["plot", str(tmp_path)]) == 2
    line = one_error_line(capsys)
    assert line.startswith(f"wingcrack: error: {tmp_path / 'summary.json'}: not a wingcrack summary (")
    assert reason in line


def test_plot_with_a_step_file_missing_exits_2(run, tmp_path, capsys):
    out = tmp_path / "copy"
    shutil.copytree(run[0], out)
    (out / "step_0002.vtu").unlink()
    assert cli.main(["plot", str(out)]) == 2
    assert one_error_line(capsys) == f"wingcrack: error: {out / 'step_0002.vtu'}: missing (summary.json lists 4 steps)"


def test_plot_a_broken_step_file_exits_2(run, tmp_path, capsys):
    out = tmp_path / "copy"
    shutil.copytree(run[0], out)
    (out / "step_0001.vtu").write_text("<VTKFile")
    assert cli.main(["plot", str(out)]) == 2
    assert one_error_line(capsys) == f"wingcrack: error: {out / 'step_0001.vtu'}: cannot read it as VTU"


def test_plot_a_file_exits_2(run, capsys):
    assert cli.main(["plot", str(run[0] / "summary.json")]) == 2
    assert one_error_line(capsys).endswith("summary.json: is a file, not a result folder")


# ---------------------------------------------------------------- progress


STEP = {"step": 3, "load_factor": 1.2345678, "dofs": 7042, "contact": {"pairs": 44, "closed": 37},
        "seconds": {"mesh": 0.31, "factorize": 0.12, "solve": 0.05, "total": 0.6}}


def test_progress_shows_load_dofs_closed_pairs_and_the_slowest_phase():
    assert progress_text(STEP) == "load 1.235, 7042 DOFs, 37 closed pairs, slowest mesh 0.31 s"


class _Terminal:
    """A stderr that says it is a terminal, so that tqdm draws."""

    def __init__(self):
        self.text = []

    def write(self, s):
        self.text.append(s)

    def flush(self):
        pass

    def isatty(self):
        return True


def test_progress_bar_on_a_terminal_and_none_with_quiet(monkeypatch):
    from wingcrack.case import Case

    term = _Terminal()
    monkeypatch.setattr(sys, "stderr", term)
    case = Case.from_toml(ROOT_CASE)
    with cli._progress(case, quiet=True) as progress:
        assert progress is None
    assert term.text == []
    with cli._progress(case, quiet=False) as progress:
        progress(0, STEP)
    shown = "".join(term.text)
    assert "1/100" in shown and progress_text(STEP) in shown


ROOT_CASE = Path(__file__).resolve().parents[2] / "cases" / "brazilian_disc_45.toml"


def test_the_picture_marks_the_tips_after_the_last_step():
    """fractures.png marks where the tips are at the end: a tip that grew in
    the last step sits at its fracture's final end (summary["fractures"]), not
    where the step started; one that reached the boundary or joined a fracture
    in it is no tip any more (the 45-degree disc ends with both wings on the rim)."""
    from wingcrack.io.pictures import _tips_at_end

    tip = lambda end, x, state: {"fracture": 0, "end": end, "x": x, "y": 0.0, "state": state, "advance": 0.1}
    summary = {
        "steps": [{"tips": [tip(0, -1.0, "growing"), tip(1, 1.0, "growing")]},
                  {"tips": [tip(0, -1.1, "boundary"), tip(1, 1.1, "growing")]}],
        "fractures": [{"points": [[-1.2, 0.0], [-1.0, 0.0]], "origin": "wing", "fracture": 0},
                      {"points": [[-1.0, 0.0], [1.0, 0.0]], "origin": "pre-existing", "fracture": 0},
                      {"points": [[1.0, 0.0], [1.1, 0.0], [1.2, 0.0]], "origin": "wing", "fracture": 0}],
    }
    assert _tips_at_end(summary) == [{"x": 1.2, "y": 0.0}]
    summary["steps"][-1]["tips"][1]["state"] = "joined"
    assert _tips_at_end(summary) == []


def test_the_rosette_radius_is_the_median_farthest_vertex_at_the_tips_of_a_network():
    """fractures.png's rosette circles: at each tip the farthest vertex of the triangles at its
    node (nearest node to the tip), the median over the tips; computed by definition, tip by tip,
    on a 120 x 120 grid of 28,800 triangles with 600 tips (two at one node). The network issue's
    1,000 fractures (2,000 tips, 1.9M nodes) once asked the drawing for a 56 GB array of tip-node
    distances: fractures.png was not drawn."""
    from types import SimpleNamespace

    from wingcrack.io.pictures import _rosette

    rng = np.random.default_rng(5)
    k = 121
    X, Y = np.meshgrid(np.linspace(0, 1, k), np.linspace(0, 1, k), indexing="ij")
    x = np.column_stack([X.ravel(), Y.ravel()]) + rng.uniform(-0.002, 0.002, (k * k, 2))
    i, j = np.meshgrid(np.arange(k - 1), np.arange(k - 1), indexing="ij")
    a, b, c, d = (i * k + j).ravel(), ((i + 1) * k + j).ravel(), ((i + 1) * k + j + 1).ravel(), (i * k + j + 1).ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    mesh = SimpleNamespace(x=x, triangles=tri)
    at = rng.choice(k * k, 599, replace=False)
    tips = [{"x": float(p[0]) + 1e-4, "y": float(p[1])} for p in x[np.append(at, at[0])]]
    r = []
    for t in tips:
        n = int(np.argmin(np.linalg.norm(x - [t["x"], t["y"]], axis=1)))
        r.append(np.linalg.norm(x[tri[np.any(tri == n, axis=1)]] - x[n], axis=2).max())
    assert _rosette(mesh, tips) == float(np.median(r))
    assert _rosette(mesh, []) == 0.0 and _rosette(None, tips) == 0.0


def test_a_case_without_fractures_gets_its_pictures(plate_case, tmp_path, capsys):
    """A case with no fractures is valid: its sif result has a face file
    without cells (meshio cannot read one back), and fractures.png was not
    drawn ("could not be drawn" warning) while `wingcrack plot` exited 2."""
    case = tmp_path / "plain.toml"
    case.write_text(plate_case.read_text().replace(
        '[[fractures]]\npoints = [[-0.35, -0.35], [0.35, 0.35]]\nfaces = "frictionless"\n', ""))
    out = tmp_path / "out"
    assert cli.main(["-q", "sif", str(case), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert captured.err == "", captured.err
    assert "warnings" not in json.loads((out / "summary.json").read_text())
    assert (out / "fractures.png").is_file()
    assert cli.main(["plot", str(out)]) == 0
    assert capsys.readouterr().err == ""


def test_a_title_the_font_lacks_draws_without_warnings(plate_case, tmp_path):
    """An emoji in the title is valid Unicode text: the pictures draw it as a
    box, and matplotlib's "Glyph ... missing from current font" warnings
    (four lines on stderr, even with --quiet) are not printed: one line says
    it (where no installed font has the emoji). A subprocess: pytest would
    catch the warnings itself."""
    from wingcrack.io import fonts

    case = tmp_path / "rocket.toml"
    case.write_text(plate_case.read_text().replace('title = "Inclined crack under compression"',
                                                   'title = "\U0001F680 crack"'))
    out = tmp_path / "out"
    res = wingcrack("-q", "sif", case, "-o", out)
    assert res.returncode == 0, res.stderr
    said = fonts.title_warning("\U0001F680 crack")
    assert res.stderr == ("" if said is None else f"wingcrack: warning: {said}\n")
    assert (out / "fractures.png").is_file()


def _network_summary(fractures: int, steps: int, growing: set, KIc=1e6, jitter=0.0) -> dict:
    """A made-up summary of `fractures` fractures over `steps` steps, the tips in `growing` growing."""
    rng = np.random.default_rng(3)
    tip = lambda f, e, k: {"fracture": f, "end": e, "x": f, "y": e, "KI": 0.0, "KII": 0.0, "theta": 0.0,
                           "K_eq": 2e5 + jitter * rng.standard_normal() if jitter else KIc * rng.uniform(0.2, 1.0),
                           "advance": 0.0, "state": "growing" if (f, e) in growing else "arrested"}
    return {"title": f"{fractures} fractures", "status": "finished", "KIc": KIc, "fractures": [],
            "steps": [{"step": k, "load_factor": 1.0 + 0.01 * k, "dofs": 1000 + k,
                       "tips": [tip(f, e, k) for f in range(fractures) for e in (0, 1)]} for k in range(steps)]}


@pytest.mark.parametrize("fractures", [2, 40])
def test_history_stays_readable_at_any_number_of_tips(fractures, tmp_path, monkeypatch):
    """history.png of 2 and of 40 fractures (80 tips): the legend lies inside the figure, beside the
    K_eq panel and off every panel; past LEGEND_TIPS tips it has one entry for the growing tips and
    one for the rest (not one a tip); KIc is drawn at its value; and nothing is printed (matplotlib's
    "Tight layout not applied" warning reached the terminal raw with 16 fractures)."""
    import warnings

    from matplotlib.figure import Figure

    from wingcrack.io import history

    figures = []
    save = Figure.savefig
    monkeypatch.setattr(Figure, "savefig", lambda self, *a, **k: (figures.append(self), save(self, *a, **k))[1])
    summary = _network_summary(fractures, 6, growing={(0, 1), (1, 0)})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        drawn = history.plot_history(tmp_path / "history.png", summary)
    assert [str(w.message) for w in caught] == []
    fig, = figures
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    for ax in fig.axes:   # every legend (the load panel's marks the peak) inside the figure
        if ax.get_legend() is not None:
            box = ax.get_legend().get_window_extent(renderer)
            assert page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0 and box.y1 <= page.y1
    k_eq, = [ax.get_legend() for ax in fig.axes
             if ax.get_legend() is not None and "KIc" in [t.get_text() for t in ax.get_legend().get_texts()]]
    box = k_eq.get_window_extent(renderer)
    for ax in fig.axes:   # the tips' legend beside the panels, over none
        assert not box.overlaps(ax.get_window_extent(renderer))
    entries = [t.get_text() for t in k_eq.get_texts()]
    if 2 * fractures <= history.LEGEND_TIPS:
        assert entries == [f"fracture {f} end {e}" for f in range(fractures) for e in (0, 1)] + ["KIc"]
    else:
        assert entries == ["growing tips (2), a colour each", f"other tips ({2 * fractures - 2})", "KIc"]
    for f in range(fractures):
        for e in (0, 1):
            want = [next(t["K_eq"] for t in s["tips"] if (t["fracture"], t["end"]) == (f, e)) for s in summary["steps"]]
            assert np.array_equal(drawn[f"fracture {f} end {e}"][1], want)
    assert np.all(drawn["KIc"][1] == summary["KIc"])


def test_history_axes_show_values_not_an_offset(tmp_path, monkeypatch):
    """K_eq that differs between steps by round-off (2e5 +- 1e-6): the axis labels the values, with no
    offset ("1e-6 + 2e5") that makes the jitter look like a spike."""
    from matplotlib.figure import Figure

    from wingcrack.io.history import plot_history

    figures = []
    save = Figure.savefig
    monkeypatch.setattr(Figure, "savefig", lambda self, *a, **k: (figures.append(self), save(self, *a, **k))[1])
    summary = _network_summary(1, 5, set(), jitter=1e-6)
    del summary["KIc"]   # a summary of before KIc was recorded: no KIc line widens the axis either
    plot_history(tmp_path / "history.png", summary)
    fig, = figures
    fig.canvas.draw()
    for ax in fig.axes:
        assert ax.yaxis.get_major_formatter().offset == 0


def test_a_title_beyond_the_font_falls_back_or_is_said_once(plate_case, tmp_path):
    """Characters the pictures' font (DejaVu Sans) lacks are drawn from an installed font that has them
    (matplotlib's family fallback: here STIXGeneral's U+1D81, which DejaVu lacks), and characters no
    installed font has (CJK, an emoji, on a machine without such fonts) are said once in summary.json's
    warnings and on stderr, instead of a matplotlib warning per glyph."""
    import matplotlib.font_manager as fm
    from matplotlib.ft2font import FT2Font

    from wingcrack.io import fonts

    families, missing = fonts.fallback("a\u1d81 b")
    assert families[0] == fonts.BASE and len(families) == 2 and missing == ""
    assert 0x1D81 in FT2Font(fm.findfont(fm.FontProperties(family=families[1]))).get_charmap()
    assert fonts.fallback("plain title") == ((fonts.BASE,), "")
    title = "\u88c2\u7f1d \U0001f642 plate"
    nowhere = "".join(dict.fromkeys(c for c in title if not c.isspace() and not c.isascii() and not any(
        ord(c) in FT2Font(f.fname).get_charmap() for f in fm.fontManager.ttflist)))
    case = tmp_path / "case.toml"
    case.write_text(plate_case.read_text().replace('title = "Inclined crack under compression"', f'title = "{title}"'))
    res = subprocess.run([sys.executable, "-m", "wingcrack.cli", "sif", str(case), "-o", str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    assert "Glyph" not in res.stderr
    warned = [w for w in json.loads((tmp_path / "out" / "summary.json").read_text()).get("warnings", [])
              if "no installed font" in w]
    if nowhere:
        assert warned == [fonts.title_warning(title)] and f"characters {nowhere} are" in warned[0]
        assert res.stderr.count("no installed font") == 1
    else:   # fonts that have them are installed: drawn, nothing to say
        assert warned == []


def test_history_shows_each_steps_critical_load_and_the_peak(tmp_path):
    """The 45-degree disc (frictionless, its response proportional to the load): each step's own
    critical load factor, recorded as lam KIc / K_eq(lam). Where the held load rose it is the critical
    load search's root (Illinois, to K_eq = KIc within 1e-6): the two routes agree to 1e-6; after the
    peak (step 9, 1.2303) the step's own falls below the held load, as in the paper's load against wing
    length (Figs. 14, 16); history.png draws it dashed and marks the peak."""
    from dataclasses import replace

    import wingcrack
    from wingcrack.case import Case
    from wingcrack.io.history import plot_history

    case = Case.from_toml(Path(__file__).resolve().parents[2] / "cases" / "brazilian_disc_45.toml")
    r = wingcrack.run(replace(case, propagation=replace(case.propagation, steps=13)), plots=False)
    lam = np.array([s["load_factor"] for s in r.steps])
    crit = np.array([s["critical_load_factor"] for s in r.steps])
    rose = np.r_[True, lam[1:] > lam[:-1]]
    np.testing.assert_allclose(crit[rose], lam[rose], rtol=1e-6)
    peak = int(np.argmax(lam))
    after = np.arange(len(lam)) > peak + 1
    assert after.sum() >= 2 and np.all(crit[after] < lam[after]) and np.all(np.diff(crit[after]) < 0)
    drawn = plot_history(tmp_path / "history.png", r.summary)
    np.testing.assert_array_equal(drawn["critical load factor of the step"][1], crit)
    (x, y), = [v for k, v in drawn.items() if k.startswith("peak ")]
    assert x[0] == peak and y[0] == lam.max()
