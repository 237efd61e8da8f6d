"""The progress bar of a propagation run: a tqdm bar over the steps showing
the load factor, the DOFs, the closed contact pairs and the slowest phase."""
from __future__ import annotations

import sys


class ProgressBar:
    """Context manager giving a `progress(k, step)` callback (or None when
    hidden). `show`: None = only when stderr is a terminal (the CLI), True =
    always (wingcrack.run(progress=True), notebooks), False = never."""

    def __init__(self, total: int, show: bool | None = None):
        self.total = total
        self.show = show
        self.bar = None

    def __enter__(self):
        from .parallel import world_rank

        if self.show is not False and world_rank() == 0:   # one bar under mpirun
            if self.show:
                from tqdm.auto import tqdm   # a widget in notebooks, text elsewhere
            else:
                from tqdm import tqdm
            self.bar = tqdm(total=self.total, unit="step", file=sys.stderr, dynamic_ncols=True,
                            disable=None if self.show is None else False)
        return self if self.bar is not None else None

    def __call__(self, k, step):
        self.bar.set_postfix_str(progress_text(step), refresh=False)
        self.bar.update(1)

    def __exit__(self, *exc):
        if self.bar is not None:
            self.bar.close()
        return False


def progress_text(step: dict) -> str:
    """The bar's words for a finished step (a summary.json step)."""
    secs = {p: v for p, v in step.get("seconds", {}).items() if p != "total"}
    slow = max(secs, key=secs.get) if secs else None
    slowest = f"slowest {slow} {secs[slow]:.2f} s" if slow else "slowest -"
    return (f"load {step['load_factor']:.4g}, {step['dofs']} DOFs, "
            f"{step['contact']['closed']} closed pairs, {slowest}")
