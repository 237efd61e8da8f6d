"""The pictures of a result folder, drawn: fractures.png, history.png and
the growth animation from its summary and step files (io.pictures,
io.history, io.animation), each picture that cannot be drawn a warning or
an error as the caller asks. The one place that orchestrates them: the
public `wingcrack.plot` and the drawing process (wingcrack/drawing.py)
both call it, so a picture drawn either way is the same file with the
same warnings."""
from __future__ import annotations

from .. import interrupt
from ..errors import FolderError, WriteError
from . import animation as animations, fonts, history as histories, pictures
from .outdir import check_folder_name, check_writable, read_result


def draw_pictures(out, summary: dict, history: bool, animation: bool) -> tuple[dict, list]:
    """({name: path}, warnings) of the pictures drawn here (fractures.png, history.png, the animation as asked): a picture that
    cannot be drawn is a warning, one the folder refuses (WriteError) raises."""
    warnings = []
    try:
        drawn = plot(out, history=history, animation=animation, summary=summary, failed=warnings)
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
         failed: list | None = None) -> dict:
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
    wingcrack result or cannot be written."""
    check_folder_name(folder)   # not locked here: run and sif call it on rank 0 only, inside their lock
    result = read_result(folder, summary=summary)
    folder = check_writable(folder)
    files = {}

    def draw(name, what, make):
        try:
            files[name] = make()
        except Exception as err:  # noqa: BLE001 - reported, and the other pictures still drawn
            stop = interrupt.cause(err)
            if stop is not None:   # an error that a stop caused: the stop
                raise stop from None
            if failed is None or isinstance(err, WriteError):   # a picture not written: the folder is at fault
                raise
            failed.append(not_drawn(what, err, folder))

    def fractures():
        pictures.fractures_of_result(folder / "fractures.png", result)
        return folder / "fractures.png"

    def history_png():
        histories.plot_history(folder / "history.png", result.summary, result)
        return folder / "history.png"

    def growth():
        return animations.animate_growth(folder, result, fmt)

    with fonts.quiet_glyphs():   # said once below, not a warning a glyph
        draw("picture", "fractures.png", fractures)
        if result.steps and history:
            draw("history", "history.png", history_png)
        if result.steps and animation:
            draw("animation", "the growth animation", growth)
    said = fonts.title_warning(result.summary.get("title", ""))
    if said is not None and failed is not None and said not in failed:
        failed.append(said)
    return files
