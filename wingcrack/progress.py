"""The progress bar of a propagation run: a tqdm bar over the steps showing
the load factor, the DOFs, the closed contact pairs and the slowest phase;
and, while a step takes longer than SLOW_STEP seconds, what it is doing
(the bar's words, or a line on stderr every SLOW_STEP seconds where there is
no bar: a log, a pipe)."""
from __future__ import annotations

import os
import sys
import threading
import time

from . import parallel

#: a step running longer than this (s) says what it is doing (WINGCRACK_SLOW_STEP overrides it: the tests)
SLOW_STEP = float(os.environ.get("WINGCRACK_SLOW_STEP", "5"))
_NOW = {"step": None, "since": None, "what": None}


def step_started(k: int) -> None:
    """Step k of a run begins (the propagation loop)."""
    _NOW.update(step=k, since=time.monotonic(), what="meshing")


def doing(what: str) -> None:
    """What the running step does now, in a few words (cheap: a dict entry)."""
    _NOW["what"] = what


def step_ended() -> None:
    _NOW.update(step=None, since=None, what=None)


def slow_text() -> str | None:
    """'step k, N s: <what>' while a step has run longer than SLOW_STEP, else None."""
    k, since, what = _NOW["step"], _NOW["since"], _NOW["what"]
    if k is None or since is None:
        return None
    spent = time.monotonic() - since
    return f"step {k}, {spent:.0f} s: {what}" if spent >= SLOW_STEP else None


class ProgressBar:
    """Context manager giving a `progress(k, step)` callback (or None when
    hidden). `show`: None = only when stderr is a terminal (the CLI), True =
    always (wingcrack.run(progress=True), notebooks), False = never."""

    def __init__(self, total: int, show: bool | None = None):
        self.total = total
        self.show = show
        self.bar = None

    def __enter__(self):
        self._stop = threading.Event()
        self._watch = None
        if self.show is not False and parallel.world_rank() == 0:   # one bar under mpirun
            if self.show:
                from tqdm.auto import tqdm   # a widget in notebooks, text elsewhere; here: `check` loads no tqdm
            else:
                from tqdm import tqdm   # here: `check` imports this module, never a bar
            self.bar = tqdm(total=self.total, unit="step", file=sys.stderr, dynamic_ncols=True,
                            disable=None if self.show is None else False)
            self._last = ""
            self._watch = threading.Thread(target=self._slow_steps, daemon=True)
            self._watch.start()
        return self if self.bar is not None else None

    def _slow_steps(self):
        """Say what a slow step does: in the bar, or as a line where the bar is disabled."""
        period = max(min(SLOW_STEP, 1.0), 0.05)
        printed = 0.0
        while not self._stop.wait(period):
            text = slow_text()
            if text is None:
                continue
            if not self.bar.disable:
                self.bar.set_postfix_str(text, refresh=True)
            elif time.monotonic() - printed >= SLOW_STEP:
                print(f"wingcrack: {text}", file=sys.stderr, flush=True)
                printed = time.monotonic()

    def __call__(self, k, step):
        self.bar.set_postfix_str(progress_text(step), refresh=False)
        self.bar.update(1)

    def __exit__(self, *exc):
        self._stop.set()
        if self._watch is not None:
            self._watch.join(timeout=2.0)
        if self.bar is not None:
            self.bar.close()
        return False


def progress_text(step: dict) -> str:
    """The bar's words for a finished step (a summary.json step)."""
    secs = {p: v for p, v in step.get("seconds", {}).items() if p != "total"}
    slow = max(secs, key=secs.get) if secs else None
    slowest = f"slowest {slow} {secs[slow]:.2f} s" if slow else "slowest -"
    load = f"load {step['load_factor']:.4g}" if "time" not in step else \
        f"t {step['time']:.4g} s, p {step['injection']['pressure'] / 1e6:.4g} MPa"
    return f"{load}, {step['dofs']} DOFs, {step['contact']['closed']} closed pairs, {slowest}"


class Heartbeat:
    """Lines on stderr while a step is slow (slow_text), for a command with no
    bar (`sif`); nothing when quiet or off rank 0."""

    def __init__(self, quiet: bool = False):
        self.quiet = quiet
        self._stop = threading.Event()
        self._thread = None

    def __enter__(self):
        if not self.quiet and parallel.world_rank() == 0:
            self._thread = threading.Thread(target=self._beat, daemon=True)
            self._thread.start()
        return self

    def _beat(self):
        printed = 0.0
        while not self._stop.wait(max(min(SLOW_STEP, 1.0), 0.05)):
            text = slow_text()
            if text is not None and time.monotonic() - printed >= SLOW_STEP:
                print(f"wingcrack: {text}", file=sys.stderr, flush=True)
                printed = time.monotonic()

    def __exit__(self, *exc):
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=2.0)
        return False
