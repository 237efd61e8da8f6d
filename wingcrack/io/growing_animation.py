"""The growth animation drawn as a run goes, in the drawing process
(wingcrack/drawing.py): each step read once it is committed, and its frame
drawn when the run's Look (io.animation) has held for HOLD steps, with
that Look; kept with it, the title it was drawn under and its step files'
identity. At the end io.animation.animate_growth takes every kept frame
whose Look, title and files are the finished run's, and draws the others
(from the steps read here where their files are still those), so that the
movie is the one `wingcrack plot` draws from the folder (tested byte for
byte).

A frame is drawn with the Look of the latest step, the best guess of the
finished run's, and only once that Look has held: where the colour scale
keeps rising to the last step (a crack that grows under a held load
concentrates more stress at each step), no frame is drawn before the end,
which then draws them all, as it would without this; where it settles (the
load peaks and is held), the frames are drawn as the steps come, and those
drawn with a Look that did not last are drawn again once the new one has
held for SETTLED steps, so that the end finds them done.

The frames are a cache in this process's memory: a run stopped, killed or
failed leaves its folder as without them (`wingcrack plot OUT` draws
everything from the step files), and a resumed run draws the frames of the
steps it found again, as they come back in its first call.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .animation_look import Look, Reach, StepLook, frame_title, step_files_key
from .frames import Frame, FrameDrawer, warm
from .movie import animation_format
from .outdir import StoredResult, faces_name, fields_name

#: a frame is drawn once the Look has held (been the same) for this many steps after the one that set it
HOLD = 2
#: after the Look has held for this many steps, the frames drawn with an earlier one are drawn again with it
SETTLED = 4
#: the bytes of the steps read and not yet drawn kept in memory, the latest first (the others are read again)
WAITING_BYTES = 256 << 20

#: the run being drawn here (one at a time: the drawing process serves one run)
_growing: GrowingAnimation | None = None


@dataclass(frozen=True)
class Seen:
    """A committed step read here: its StepLook, the identity of its step
    files, its frame's title; its frame (with the Look it was drawn with),
    or its files' content while it waits (within WAITING_BYTES), or neither."""
    step: StepLook
    files: tuple
    title: str
    frame: Frame | None = None
    look: Look | None = None
    data: tuple | None = None


class GrowingAnimation:
    """The frames of the run writing `folder` (titled `title`, its
    propagation {"steps", "length"} as summary.json will say it; whether
    its case has fractures, `fractured`), in `fmt` (see the module doc)."""

    def __init__(self, folder, title: str, propagation: dict | None, fractured: bool, fmt: str):
        self.folder, self.title, self.propagation, self.fmt = Path(folder).resolve(), title, propagation, fmt
        # what io.outdir reads a step by: a case without fractures has face files of no cells
        self.summary = {"steps": [], "fractures": [{}] if fractured else []}
        self.seen: dict[int, Seen] = {}
        self.first = None   # the first step's record: its tips are where the reach starts
        self.look, self.held = None, 0   # the latest Look, and for how many steps after its own it has held
        self.drawer: FrameDrawer | None = None

    def _read(self, k: int) -> tuple:
        """(files key, fields, faces) of step k."""
        result = StoredResult(self.folder, self.summary, [self.folder / fields_name(k)], [self.folder / faces_name(k)])
        return step_files_key(result, 0), result.fields_of(0), result.faces_of(0)

    def add(self, k: int, record: dict, hurry=lambda: False) -> None:
        """Step k committed (its record as summary.json holds it, its files in
        the folder): read, and frames drawn as the module doc says, until
        hurry() (the frames left are drawn later, or at the end)."""
        self.seen.pop(k, None)
        files, fields, faces = self._read(k)
        step = StepLook.of(fields, faces)
        if k == 0:
            self.first = record
        self.seen[k] = Seen(step, files, frame_title(self.title, record, step), data=(fields, faces))
        look = Look.of([self.seen[j].step for j in sorted(self.seen) if j <= k], Reach.of(self.propagation, self.first))
        self.held = self.held + 1 if look == self.look else 0
        self.look = look
        if self.held >= HOLD:   # the steps waiting in memory
            for j in sorted(j for j, s in self.seen.items() if s.data is not None):
                if hurry():
                    break
                self._draw(j)
        if self.held >= SETTLED:   # and every other not drawn with this Look, read again
            for j in sorted(j for j, s in self.seen.items() if s.look != look):
                if hurry():
                    break
                self._draw(j)
        kept = 0
        for j in sorted((j for j, s in self.seen.items() if s.data is not None), reverse=True):
            kept += sum(a.nbytes for a in _arrays(self.seen[j].data))
            if kept > WAITING_BYTES:   # the oldest read again when drawn
                self.seen[j] = Seen(self.seen[j].step, self.seen[j].files, self.seen[j].title)

    def _draw(self, k: int) -> None:
        s = self.seen[k]
        data = s.data
        if data is None:
            files, *data = self._read(k)
            if files != s.files:   # rewritten since: the end reads it as it is
                return
        self.seen[k] = Seen(s.step, s.files, s.title, self.drawer_for(self.look, keep=True).draw(*data, s.title),
                            self.look)

    def drawer_for(self, look: Look, keep: bool = False) -> FrameDrawer | None:
        """The figure of `look`: the one in use when it is that Look (None
        otherwise, unless `keep`: then a new one, which replaces it)."""
        if self.drawer is not None and self.drawer.look == look:
            return self.drawer
        if not keep:
            return None
        self.close()
        self.drawer = FrameDrawer(look, self.fmt)
        return self.drawer

    def step(self, k: int, files: tuple) -> Seen | None:
        """Step k as read here, while its files are still those it was read from."""
        s = self.seen.get(k)
        return s if s is not None and s.files == files else None

    def close(self) -> None:
        if self.drawer is not None:
            self.drawer.close()
            self.drawer = None


def _arrays(data: tuple) -> list:
    """The arrays of a step's (io.outdir.StepFields, StepFaces)."""
    fields, faces = data
    return [fields.x, fields.cells, fields.von_mises, faces.lines, faces.closed, faces.state, *faces.values.values()]


def begin(folder, title: str, propagation: dict | None, fractured: bool) -> None:
    """A run into `folder` begins (see GrowingAnimation): the frames of any
    other are dropped."""
    global _growing
    end()
    _growing = GrowingAnimation(folder, title, propagation, fractured, animation_format())
    warm(_growing.fmt)


def add(folder, records: list, hurry=lambda: False) -> None:
    """Read and draw the steps committed in `folder`: records [(k, step
    record)], in step order, until hurry() (those left are read at the
    end). Nothing for a folder no run began in."""
    if _growing is None or _growing.folder != Path(folder).resolve():
        return
    for k, record in records:
        if hurry():
            return
        try:
            _growing.add(k, record, hurry)
        except Exception:  # noqa: BLE001 - a frame not drawn now is drawn at the end, or says there why not
            _growing.seen.pop(k, None)


def taken(folder, fmt: str) -> GrowingAnimation | None:
    """The steps read and drawn for `folder` in `fmt`, handed over (they
    are no longer kept here); None when there are none."""
    global _growing
    grown = _growing
    if grown is None or grown.folder != Path(folder).resolve():
        return None
    _growing = None
    if grown.fmt != fmt:
        grown.close()
        return None
    return grown


def end() -> None:
    """Drop the frames kept here."""
    global _growing
    if _growing is not None:
        _growing.close()
        _growing = None
