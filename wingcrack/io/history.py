"""history.png: how a run went, step by step: the load factor, K_eq of
every tip (Pa m^0.5, eq. 10 of the paper) and the number of DOFs."""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np


def history(summary: dict) -> dict:
    """The series drawn, from a summary (as in summary.json):
    step (s,), load_factor (s,), dofs (s,) and k_eq {(fracture, end): (s,)}
    with NaN where that tip does not exist (not yet grown, joined, at the
    boundary). K_eq is computed from KI, KII, theta when a summary lacks it."""
    steps = summary["steps"]
    keys = sorted({(t["fracture"], t["end"]) for st in steps for t in st["tips"]})
    k_eq = {key: np.full(len(steps), np.nan) for key in keys}
    for k, st in enumerate(steps):
        for t in st["tips"]:
            k_eq[(t["fracture"], t["end"])][k] = t["K_eq"] if "K_eq" in t else _k_eq(t)
    return {"step": np.array([st["step"] for st in steps], float),
            "load_factor": np.array([st["load_factor"] for st in steps], float),
            "dofs": np.array([st["dofs"] for st in steps], float),
            "k_eq": k_eq}


def _k_eq(t: dict) -> float:
    import wingcrack_kernels as K

    return float(K.equivalent_k(np.array([t["KI"]]), np.array([t["KII"]]), np.array([t["theta"]]))[0])


def plot_history(path: Path, summary: dict) -> dict:
    """Write history.png and return what was drawn: {label: (x, y)} read
    back from the figure's lines (labels "load factor", "DOFs" and
    "fracture F end E" for K_eq)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = history(summary)
    fig, (ax_load, ax_k, ax_dofs) = plt.subplots(3, 1, figsize=(7, 7.5), sharex=True)
    marker = "o" if len(h["step"]) <= 60 else None
    ax_load.plot(h["step"], h["load_factor"], marker=marker, ms=3, color="black", label="load factor")
    ax_load.set_ylabel("load factor")
    for (f, e), y in h["k_eq"].items():
        ax_k.plot(h["step"], y, marker=marker, ms=3, label=f"fracture {f} end {e}")
    ax_k.set_ylabel("K_eq (Pa m$^{1/2}$)")
    if h["k_eq"]:
        ax_k.legend(fontsize=7, ncol=2 if len(h["k_eq"]) > 4 else 1, loc="best")
    ax_dofs.plot(h["step"], h["dofs"], marker=marker, ms=3, color="tab:gray", label="DOFs")
    ax_dofs.set_ylabel("DOFs")
    ax_dofs.set_xlabel("step")
    ax_dofs.xaxis.get_major_locator().set_params(integer=True)
    status = "" if summary["status"] == "finished" else "\n" + textwrap.shorten(summary["status"], 80)
    ax_load.set_title(f"{summary['title']}: {len(h['step'])} steps{status}", fontsize=10)
    for ax in (ax_load, ax_k, ax_dofs):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    drawn = {line.get_label(): (np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
             for ax in (ax_load, ax_k, ax_dofs) for line in ax.get_lines()}
    fig.savefig(Path(path), dpi=110)
    plt.close(fig)
    return drawn
