"""fractures.png: the domain, every fracture, the tips and their rosettes."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def _outline(domain) -> np.ndarray:
    if domain.shape == "disc":
        t = np.linspace(0.0, 2.0 * np.pi, 361)
        c = np.asarray(domain.center, float)
        return np.c_[c[0] + domain.radius * np.cos(t), c[1] + domain.radius * np.sin(t)]
    if domain.shape == "rectangle":
        (x0, y0), (w, h) = domain.corner, domain.size
        return np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h], [x0, y0]], float)
    pts = np.asarray(domain.points, float)
    return np.vstack([pts, pts[:1]])


def plot_fractures(path: Path, domain, fractures, tips=(), rosette: float = 0.0,
                   closed_segments=(), title: str = "", mesh=None) -> Path:
    """Draw the domain and fractures.

    fractures: list of dicts {"points": (n,2), "origin": "pre-existing"|"wing"};
    tips: list of dicts with "x", "y", "state"; closed_segments: list of
    ((x0,y0),(x1,y1)) drawn over the fractures where the faces are in contact.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_full, ax_zoom) = plt.subplots(1, 2, figsize=(11, 5.2))
    if mesh is not None:
        # the straight-sided vertex triangles show the rosettes and grading
        ax_zoom.triplot(mesh.x[:, 0], mesh.x[:, 1], np.asarray(mesh.cells)[:, :3], color="0.8", lw=0.3)
    all_pts = np.vstack([np.asarray(f["points"], float) for f in fractures]) if fractures else np.zeros((0, 2))
    for ax in (ax_full, ax_zoom):
        o = _outline(domain)
        ax.plot(o[:, 0], o[:, 1], color="0.35", lw=1.2)
        for f in fractures:
            p = np.asarray(f["points"], float)
            pre = f.get("origin", "pre-existing") == "pre-existing"
            ax.plot(p[:, 0], p[:, 1], color="black" if pre else "tab:red", lw=1.8 if pre else 1.4,
                    label="pre-existing" if pre else "wing")
        for (a, b) in closed_segments:
            ax.plot([a[0], b[0]], [a[1], b[1]], color="tab:blue", lw=3.5, alpha=0.5, label="closed faces")
        for t in tips:
            ax.plot(t["x"], t["y"], "o", ms=4, color="tab:orange")
            if rosette > 0:
                ax.add_patch(plt.Circle((t["x"], t["y"]), rosette, fill=False, color="tab:orange", lw=0.8))
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    ax_full.set_title(title or "domain and fractures", fontsize=10)
    if len(all_pts):
        lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
        pad = 0.15 * max(hi - lo) + 3 * rosette + 1e-12
        ax_zoom.set_xlim(lo[0] - pad, hi[0] + pad)
        ax_zoom.set_ylim(lo[1] - pad, hi[1] + pad)
        ax_zoom.set_title("fractures and mesh (zoom); circles: tip rosettes", fontsize=10)
    handles, labels = ax_full.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    if uniq:
        ax_full.legend(uniq.values(), uniq.keys(), loc="upper right", fontsize=8)
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
