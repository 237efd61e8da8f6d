"""The growth animation's frames drawn fast (io/frames.py) and written
(io/movie.py).

References: matplotlib's own drawing of the whole figure with the same
artists (Agg is deterministic: the same figure gives the same pixels, so
the tolerance is none); the nearest palette colour by brute force; the
bytes ffmpeg is given, counted by a stand-in on PATH."""
import os
import stat
import sys
import zlib

import numpy as np
import pytest

from wingcrack.io import frames
from wingcrack.io.animation_look import Look
from wingcrack.io.faces import OPEN, SLIP, STICK
from wingcrack.io.outdir import StepFaces, StepFields, edge_states


def step(seed=0, wet=False):
    """A plate [-1, 1]^2 of 800 triangles with a von Mises field over four
    decades, and a fracture of 12 face edges along y = 0.1 whose nodes are
    open, stick and slip in turn (pressurised at 1-2 MPa when `wet`)."""
    import matplotlib.tri as mtri

    rng = np.random.default_rng(seed)
    g = np.linspace(-1.0, 1.0, 21)
    x = np.array(np.meshgrid(g, g)).reshape(2, -1).T
    tri = mtri.Triangulation(x[:, 0], x[:, 1]).triangles
    cells = np.hstack([tri, np.zeros_like(tri)])
    vm = 10.0 ** (5 + 4 * rng.random(len(x)))
    ends = np.linspace(-0.6, 0.6, 13)
    lines = np.stack([np.c_[ends[:-1], np.full(12, 0.1)], np.c_[(ends[:-1] + ends[1:]) / 2, np.full(12, 0.1)],
                      np.c_[ends[1:], np.full(12, 0.1)]], axis=1)
    nodes = np.repeat(np.array([OPEN, OPEN, STICK, STICK, SLIP, SLIP]), 2)
    node_states = np.stack([nodes, nodes, nodes], axis=1).astype(np.int8)
    pressure = np.full((12, 3), 1e6 * (1 + rng.random()) if wet else 0.0)
    faces = StepFaces(lines, node_states[:, 0] != OPEN, edge_states(node_states),
                      {"pressure": pressure, "state": node_states})
    return StepFields(x, cells, vm), faces


def look(wet=False):
    return Look(1e5, 1e9, (-1.0, -1.0), (1.0, 1.0), 2e6 if wet else 0.0, (OPEN, STICK, SLIP))


@pytest.mark.parametrize("wet", [False, True])
def test_a_frame_is_the_figure_drawn_whole(monkeypatch, wet):
    """Each frame drawn over the figure's fixed parts has the pixels of
    matplotlib's drawing of the whole figure with the frame's artists in it
    (the order of what lies over the field: bands, lines, axes frame,
    legend, title), for three frames in a row of one figure, with the three
    face states, and with the pressure rims and their colour bar."""
    pairs = []
    real = frames.Frame.of

    def both(rgba, fmt):
        drawn = np.array(rgba)   # the canvas itself: copied before the whole drawing overwrites it
        fig = drawer.fig
        for artist in drawer.over:
            artist.set_animated(False)
        fig.canvas.draw()
        for artist in drawer.over:
            artist.set_animated(True)
        pairs.append((drawn, np.array(fig.canvas.buffer_rgba())))
        return real(drawn, fmt)

    monkeypatch.setattr(frames.Frame, "of", both)
    drawer = frames.FrameDrawer(look(wet), "gif")
    try:
        for k in range(3):
            drawer.draw(*step(k, wet), f"plate\nstep {k}: load factor {1 + k / 10:.5g}; face edges 4 open")
    finally:
        drawer.close()
    assert len(pairs) == 3
    for fast, whole in pairs:
        assert fast.shape == whole.shape and np.array_equal(fast, whole)
    assert not np.array_equal(pairs[0][0], pairs[1][0])   # the frames differ: their fields do


def test_a_frame_keeps_its_pixels_in_the_palette_or_as_they_are():
    """A GIF frame decodes to the palette colour of each pixel; an MP4
    frame to its pixels as drawn."""
    drawer = frames.FrameDrawer(look(), "gif")
    try:
        gif = drawer.draw(*step(), "t")
    finally:
        drawer.close()
    index = np.frombuffer(zlib.decompress(gif.pixels), np.uint8).reshape(gif.size[1], gif.size[0])
    palette = np.frombuffer(frames._gif_palette()[0], np.uint8).reshape(256, 3)
    assert np.array_equal(np.asarray(gif.image().convert("RGB")), palette[index])
    rgba = np.random.default_rng(1).integers(0, 256, (6, 5, 4), dtype=np.uint8)
    rgba[:, :, 3] = 255
    mp4 = frames.Frame.of(rgba, "mp4")
    assert mp4.size == (5, 6) and mp4.rgba() == rgba.tobytes()


def test_the_palette_is_the_nearest_colour_within_its_cell():
    """A pixel takes the palette entry nearest to its colour's 6-bit cell:
    no farther from the pixel than the nearest entry (brute force) plus the
    cell's diameter (3 channels of 3 levels: 2 * 1.5 * sqrt(3)), and
    exactly the colours the pictures draw as they are: white, black, the
    face-state bands."""
    palette = np.frombuffer(frames._gif_palette()[0], np.uint8).reshape(256, 3).astype(float)
    rng = np.random.default_rng(7)
    rgb = rng.integers(0, 256, (4000, 3)).astype(np.uint8)
    exact = np.array([[255, 255, 255], [0, 0, 0], [0x56, 0xB4, 0xE9], [0x00, 0x9E, 0x73], [0xD5, 0x5E, 0x00]],
                     np.uint8)
    rgb = np.vstack([rgb, exact])
    rgba = np.concatenate([rgb, np.full((len(rgb), 1), 255, np.uint8)], axis=1)[None]
    got = np.frombuffer(zlib.decompress(frames.Frame.of(rgba, "gif").pixels), np.uint8)
    dist = np.linalg.norm(palette[got] - rgb, axis=1)
    best = np.linalg.norm(palette[None, :, :] - rgb[:, None, :].astype(float), axis=2).min(axis=1)
    assert np.all(dist <= best + 3.0 * np.sqrt(3.0) + 1e-9)
    assert np.all(dist[-len(exact):] == 0.0)


def test_a_gif_holds_every_frame_in_one_palette(tmp_path):
    """growth.gif of three frames: three frames decoded as they were kept
    (one palette, no frame cut to another), each shown 1 / FPS."""
    from PIL import Image

    from wingcrack.io import movie
    from wingcrack.io.movie import FPS

    drawer = frames.FrameDrawer(look(), "gif")
    try:
        kept = [drawer.draw(*step(k), f"step {k}") for k in range(3)]
    finally:
        drawer.close()
    movie.write(tmp_path / "growth.gif", "gif", kept)
    with Image.open(tmp_path / "growth.gif") as im:
        assert im.n_frames == 3
        for k, f in enumerate(kept):
            im.seek(k)
            assert np.array_equal(np.asarray(im.convert("RGB")), np.asarray(f.image().convert("RGB"))), k
            assert im.info["duration"] == 1000 // FPS


def test_an_mp4_gets_every_frame_through_ffmpeg(tmp_path, monkeypatch):
    """With ffmpeg on PATH (a stand-in that keeps its arguments and counts
    what it is given), growth.mp4 is ffmpeg's from the frames' RGBA pixels
    at their size and FPS, libx264 in yuv420p."""
    from wingcrack.io import movie
    from wingcrack.io.movie import FPS

    bin_ = tmp_path / "bin"
    bin_.mkdir()
    said = tmp_path / "said"
    fake = bin_ / "ffmpeg"
    fake.write_text(f"#!{sys.executable}\nimport sys\nn = len(sys.stdin.buffer.read())\n"
                    f"open({str(said)!r}, 'w').write(repr((sys.argv[1:], n)))\n"
                    "open(sys.argv[-1], 'wb').write(b'mp4')\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{bin_}{os.pathsep}{os.environ['PATH']}")
    rgba = np.zeros((6, 8, 4), np.uint8)
    kept = [frames.Frame.of(rgba + k, "mp4") for k in range(5)]
    path = movie.write(tmp_path / "growth.mp4", "mp4", kept)
    args, n = eval(said.read_text())
    assert path.read_bytes() == b"mp4" and n == 5 * 6 * 8 * 4
    assert args[args.index("-s") + 1] == "8x6" and args[args.index("-r") + 1] == str(FPS)
    assert args[args.index("-pix_fmt") + 1] == "rgba" and "libx264" in args and "yuv420p" in args


def test_a_failing_ffmpeg_says_why(tmp_path, monkeypatch):
    from wingcrack.io import movie

    bin_ = tmp_path / "bin"
    bin_.mkdir()
    fake = bin_ / "ffmpeg"
    fake.write_text(f"#!{sys.executable}\nimport sys\nsys.stderr.write('Unknown encoder libx264')\nsys.exit(1)\n")
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{bin_}{os.pathsep}{os.environ['PATH']}")
    with pytest.raises(RuntimeError, match="ffmpeg failed \\(exit 1\\): Unknown encoder libx264"):
        movie.write(tmp_path / "growth.mp4", "mp4", [frames.Frame.of(np.zeros((4, 4, 4), np.uint8), "mp4")])
    assert not list(tmp_path.glob("*.mp4"))
