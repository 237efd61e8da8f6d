"""The pictures of a result folder, drawn: fractures.png, history.png and
the growth animation from its summary and step files (io.pictures,
io.history, io.animation), each picture that cannot be drawn a warning or
an error as the caller asks. The one place that orchestrates them: the
public `wingcrack.plot` and the drawing process (wingcrack/drawing.py)
both call it, so a picture drawn either way is the same file with the
same warnings."""
from __future__ import annotations

import contextlib

from .. import interrupt
from ..errors import FolderError, WriteError
from . import animation as animations, fonts, history as histories, pictures
from .outdir import check_folder_name, check_writable, read_result


def draw_pictures(out, summary: dict, history: bool, animation: bool, beside=None) -> tuple[dict, list]:
    """({name: path}, warnings) of the pictures drawn here (fractures.png, history.png, the animation as asked): a picture that
    cannot be drawn is a warning, one the folder refuses (WriteError) raises. beside: see plot."""
    warnings = []
    try:
        drawn = plot(out, history=history, animation=animation, summary=summary, failed=warnings, beside=beside)
    except WriteError:   # a picture not written: the run fails (loop.run), not a warning
        raise
    except Exception as err:  # noqa: BLE001 - reading the result back failed: no picture at all
        if (stop := interrupt.cause(err)) is not None:
            raise stop from None
        drawn = {}
        warnings.append(not_drawn("the pictures", err, out))
    return drawn, warnings


def not_drawn(what: str, err: BaseException, out) -> str:
    detail = " ".join(str(err).split())[:300] or "(no message)"
    return f"{what} could not be drawn ({type(err).__name__}: {detail}); the data are complete (" \
           f"`wingcrack plot {out}` tries again)"


def plot(folder, history: bool = True, animation: bool = True, fmt: str | None = None, summary: dict | None = None,
         failed: list | None = None, beside=None) -> dict:
    """Draw the pictures of a result folder (a run, finished, stopped or
    failed, or a solve) from its summary.json and step files, and return
    {name: path}: fractures.png always; with at least one step, history.png
    (load factor, K_eq of every tip, DOFs; with fluid, the injection
    pressure and the slipping length) and growth.gif / growth.mp4
    (`fmt`, default mp4 when ffmpeg is on PATH), unless switched off.
    summary: draw this summary instead of the folder's summary.json (a run
    draws before it writes its final status). failed: a list that gets a
    warning for each picture that cannot be drawn, the others still drawn
    (without it, the first failure raises).

    Only these pictures are (re)written: they are views of the data, which
    is never touched. Raises FolderError when `folder` is missing, is not a
    wingcrack result or cannot be written.

    beside: a function that starts a picture's drawing (a function of no
    arguments) in another process and returns a handle whose result() is
    its value (procs.forked.start): fractures.png is drawn there while the
    others are drawn here. For the drawing process alone (a fork of a
    process that holds MPI is not allowed)."""
    check_folder_name(folder)   # not locked here: run and sif call it on rank 0 only, inside their lock
    result = read_result(folder, summary=summary)
    folder = check_writable(folder)
    files, said = {}, {}

    def draw(name, what, make):
        try:
            files[name] = make() if callable(make) else make.result()
        except Exception as err:  # noqa: BLE001 - reported, and the other pictures still drawn
            stop = interrupt.cause(err)
            if stop is not None:   # an error that a stop caused: the stop
                raise stop from None
            if failed is None or isinstance(err, WriteError):   # a picture not written: the folder is at fault
                raise
            said[name] = not_drawn(what, err, folder)

    def fractures():
        pictures.fractures_of_result(folder / "fractures.png", result)
        return folder / "fractures.png"

    def history_png():
        histories.plot_history(folder / "history.png", result.summary, result)
        return folder / "history.png"

    def growth():
        return animations.animate_growth(folder, result, fmt)

    drawings = [("picture", "fractures.png", fractures)]
    if result.steps and history:
        drawings.append(("history", "history.png", history_png))
    if result.steps and animation:
        drawings.append(("animation", "the growth animation", growth))
    with fonts.quiet_glyphs():   # said once below, not a warning a glyph
        if beside is None or len(drawings) == 1:
            for drawing in drawings:
                draw(*drawing)
        else:
            # the longest picture on the other core (the animation's frames are mostly drawn already)
            child = beside(fractures)
            try:
                for drawing in drawings[1:]:
                    draw(*drawing)
            except BaseException:
                with contextlib.suppress(Exception):   # collected, whatever it says: the first failure is the news
                    child.result()
                raise
            draw("picture", "fractures.png", child)
    files = {name: files[name] for name, _, _ in drawings if name in files}   # in their order, wherever drawn
    if failed is not None:
        failed.extend(said[name] for name, _, _ in drawings if name in said)
    said = fonts.title_warning(result.summary.get("title", ""))
    if said is not None and failed is not None and said not in failed:
        failed.append(said)
    return files
