"""fractures.png: the outer boundary, every fracture, the tips and their
rosettes; for a run, the wings coloured by the step that grew them; and the
contact state of the faces at the last step, open, stick or slip, as a
thick translucent band under the fracture lines (one colour and one legend
entry per state present); and the fractures that hold fluid (pressure > 0
at the last step) with a blue rim around their bands, darker the higher
the pressure (a legend entry "pressurised: p = X MPa" per pressure, or a
colour bar when there are more than PRESSURE_LEGEND_MAX). Drawn from a
result folder (fractures_of_result), for `sif`, `run` and `wingcrack plot`
alike."""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from . import fonts
from .atomic import replacing
from .faces import OPEN, SLIP, STICK

#: the band of each face state: colour (Okabe-Ito, told apart by colour-blind
#: readers and kept off viridis' step colours by the band's width) and legend label
FACE_BANDS = {OPEN: ("#56B4E9", "faces open"), STICK: ("#009E73", "faces stick"), SLIP: ("#D55E00", "faces slip")}
#: width (points) of the face-state bands of fractures.png
BAND_WIDTH = 7.0
#: width (points) of the pressure rim: the band of a pressurised fracture,
#: under a white band of BAND_WIDTH that keeps the state bands' colours as
#: they are on paper, so that a rim of 2.5 points shows on either side
RIM_WIDTH = BAND_WIDTH + 5.0
#: the part of matplotlib's Blues the pressures span (0 to the highest):
#: from its middle on, off the light blue of open faces and dark on paper
PRESSURE_BLUES = (0.5, 1.0)
#: up to this many distinct pressures get a legend entry each; more, a colour bar
PRESSURE_LEGEND_MAX = 4
PRESSURE_BAR = "fracture pressure (MPa)"


def pressure_colours(top: float):
    """(cmap, norm) of the pressure rims: Pa in [0, top] to PRESSURE_BLUES."""
    import matplotlib.pyplot as plt   # lazy: start-up
    from matplotlib.colors import ListedColormap

    cmap = ListedColormap(plt.get_cmap("Blues")(np.linspace(*PRESSURE_BLUES, 256)), name="pressure")
    return cmap, plt.Normalize(0.0, top if top > 0 else 1.0)


def pressure_label(p: float) -> str:
    """The legend entry of the fractures at pressure p (Pa)."""
    return f"pressurised: p = {p / 1e6:.3g} MPa"


def fracture_pressures(summary: dict) -> dict:
    """{fracture index: pressure (Pa)} of the fractures that hold fluid
    (p > 0) at the last step of a summary: the pressures it was solved with
    (steps[].pressures); {} before fluid pressure or without a step."""
    steps = summary["steps"]
    if not steps:
        return {}
    return {i: float(p) for i, p in enumerate(steps[-1].get("pressures", [])) if p > 0}


def plot_fractures(path: Path, fractures, tips=(), rosette: float = 0.0, face_lines=(), face_states=(),
                   title: str = "", mesh=None, growth=(), boundary=None, pressures=None) -> dict:
    """Draw the outer boundary and the fractures, and return what was drawn:
    {"faces open" / "faces stick" / "faces slip": (k, 3, 2) the face edges
    banded in that state, read back from the figure (only states present),
    "pressurised": {"lines": [(n, 2)] the pieces drawn with a pressure rim,
    "pressure": (n,) their pressures (Pa)} (only when some fracture holds
    fluid), "legend": the labels of the legend, in order, "colour bars":
    the labels of the colour bars}.

    boundary: (k, 2, 2) segments of the outer boundary; fractures: list of dicts {"points": (n,2), "origin":
    "pre-existing"|"wing"}; tips: list of dicts with "x", "y";
    face_lines: (k, 3, 2) face edges as 3-point polylines and face_states
    (k,) their OPEN / STICK / SLIP (io.outdir.StepFaces), drawn as bands
    under the fractures; mesh: anything with x (n, 2) and cells (m, >=3),
    drawn in the zoom; growth: [((x0,y0), (x1,y1), step)], what each step
    grew, coloured by step; pressures: {fracture index: Pa}, the pieces of a
    fracture (their "fracture") above 0 drawn with a pressure rim.
    """
    import matplotlib   # lazy: start-up
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.ticker import MaxNLocator

    # constrained layout: room for the legend below the domain, so that it covers no fracture
    fig, (ax_full, ax_zoom) = plt.subplots(1, 2, figsize=(11, 6.0), layout="constrained")
    if mesh is not None:
        # the straight-sided vertex triangles show the rosettes and grading
        ax_zoom.triplot(mesh.x[:, 0], mesh.x[:, 1], np.asarray(mesh.cells)[:, :3], color="0.8", lw=0.3)
    all_pts = np.vstack([np.asarray(f["points"], float) for f in fractures]) if fractures else np.zeros((0, 2))
    steps = np.array([g[2] for g in growth], float)
    n = int(steps.max()) + 1 if len(growth) else 1
    colours = plt.get_cmap("viridis", n)   # one colour a step
    face_lines = np.asarray(face_lines, float).reshape(-1, 3, 2)
    face_states = np.asarray(face_states).reshape(-1)
    if len(face_states) != len(face_lines):
        raise ValueError(f"{len(face_lines)} face edges but {len(face_states)} states")
    wet = wet_lines(fractures, pressures or {})
    p_cmap, p_norm = pressure_colours(max((pressure for _, pressure in wet), default=0.0))
    bands = {}   # label -> the band's collection in ax_full
    rim = None   # the pressure rims' collection in ax_full
    for ax in (ax_full, ax_zoom):
        if boundary is not None and len(boundary):
            ax.add_collection(LineCollection(boundary, colors="0.35", linewidths=1.2))
        if wet:
            rims = ax.add_collection(LineCollection([p for p, _ in wet], cmap=p_cmap, norm=p_norm,
                                                    linewidths=RIM_WIDTH, capstyle="butt", joinstyle="round",
                                                    zorder=1.2))
            rims.set_array(np.array([pressure for _, pressure in wet]))
            ax.add_collection(LineCollection([p for p, _ in wet], colors="white", linewidths=BAND_WIDTH,
                                             capstyle="butt", joinstyle="round", zorder=1.3))
            rim = rims if ax is ax_full else rim
        for state, (colour, label) in FACE_BANDS.items():
            edges = face_lines[face_states == state]
            if len(edges):
                # under the fracture lines (zorder 2), wide enough to show past them
                band = ax.add_collection(LineCollection(edges, colors=colour, linewidths=BAND_WIDTH, alpha=0.5,
                                                        capstyle="butt", zorder=1.5, label=label))
                if ax is ax_full:
                    bands[label] = band
        for f in fractures:
            p = np.asarray(f["points"], float)
            pre = f.get("origin", "pre-existing") == "pre-existing"
            wing = "tab:red" if not len(growth) else "0.55"
            ax.plot(p[:, 0], p[:, 1], color="black" if pre else wing, lw=1.8 if pre else 1.4,
                    label="pre-existing" if pre else ("wing" if not len(growth) else "wing (colour: step)"))
        if len(growth):
            lines = LineCollection([(g[0], g[1]) for g in growth], cmap=colours, linewidths=2.0,
                                   norm=plt.Normalize(-0.5, n - 0.5))
            lines.set_array(steps)
            ax.add_collection(lines)
        for t in tips:
            ax.plot(t["x"], t["y"], "o", ms=4, color="tab:orange")
            if rosette > 0:
                ax.add_patch(plt.Circle((t["x"], t["y"]), rosette, fill=False, color="tab:orange", lw=0.8))
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    ax_full.autoscale_view()
    fonts.set_title(ax_full, title or "domain and fractures", fontsize=10)
    bars = []
    if len(growth):
        bars.append(fig.colorbar(lines, ax=ax_zoom, label="step", fraction=0.05, ticks=MaxNLocator(integer=True)))
    if len(all_pts):
        lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
        pad = 0.15 * max(hi - lo) + 3 * rosette + 1e-12
        ax_zoom.set_xlim(lo[0] - pad, hi[0] + pad)
        ax_zoom.set_ylim(lo[1] - pad, hi[1] + pad)
        ax_zoom.set_title("fractures and mesh (zoom); circles: tip rosettes", fontsize=10)
        # a tall, narrow zoom (fractures along the load) would crowd its x labels into each other
        narrow = (hi[0] - lo[0]) < 0.5 * (hi[1] - lo[1])
        ax_zoom.xaxis.set_major_locator(MaxNLocator(2 if narrow else 4))
    handles, labels = ax_full.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    uniq = {k: uniq[k] for k in sorted(uniq, key=lambda k: k in bands)}   # the fractures first, then the faces
    uniq.update(_pressure_entries(fig, ax_full, wet, p_cmap, p_norm, bars))
    # below the domain's axes, outside them: inside, a legend covers fractures wherever a network has them
    legend = ax_full.legend(uniq.values(), uniq.keys(), loc="upper center", bbox_to_anchor=(0.5, -0.13),
                            ncol=min(3, len(uniq)), fontsize=8, frameon=False) if uniq else None
    drawn = {label: np.asarray(band.get_segments(), float).reshape(-1, 3, 2) for label, band in bands.items()}
    if rim is not None:
        drawn["pressurised"] = {"lines": [np.asarray(s, float) for s in rim.get_segments()],
                                "pressure": np.asarray(rim.get_array(), float)}
    drawn["legend"] = [t.get_text() for t in legend.get_texts()] if legend is not None else []
    drawn["colour bars"] = [b.ax.get_ylabel() for b in bars]
    try:
        with replacing(path, Path(path).suffix) as tmp:   # the format by the suffix
            # "tight": the image holds every artist, the legend below the axes and the titles included
            fig.savefig(tmp, dpi=110, bbox_inches="tight", pad_inches=0.1)
    finally:   # a file not written leaves no figure open (a long-lived drawing process draws the next)
        plt.close(fig)
    return drawn


def wet_lines(fractures, pressures: dict) -> list:
    """[((n, 2) points, pressure)] of the fractures that hold fluid: the
    pieces of each (summary["fractures"], wing, pre-existing part, wing, by
    their "fracture") with pressures[fracture] > 0, chained into one
    polyline where a piece starts at the end of the one before, so that
    the rim turns round the kinks instead of breaking there."""
    out = []
    for f in fractures:
        p = np.asarray(f["points"], float)
        pressure = float(pressures.get(f.get("fracture"), 0.0))
        if pressure <= 0:
            continue
        if out and out[-1][2] == f.get("fracture") and np.array_equal(out[-1][0][-1], p[0]):
            out[-1][0] = np.vstack([out[-1][0], p[1:]])
        else:
            out.append([p, pressure, f.get("fracture")])
    return [(p, pressure) for p, pressure, _ in out]


def _pressure_entries(fig, ax, wet, cmap, norm, bars) -> dict:
    """{label: legend handle} of the pressurised fractures: one per distinct
    pressure (as the label shows it), highest first; with more than
    PRESSURE_LEGEND_MAX, one entry and a colour bar on `ax` (added to bars)."""
    import matplotlib.pyplot as plt   # lazy: start-up
    from matplotlib import patheffects
    from matplotlib.lines import Line2D

    def handle(p):
        # the rim as drawn: the pressure's blue around white
        rim = [patheffects.Stroke(linewidth=7.0, foreground=cmap(norm(p))), patheffects.Normal()]
        return Line2D([], [], color="white", lw=3.0, solid_capstyle="butt", path_effects=rim)

    shown = {}
    for p in sorted((p for _, p in wet), reverse=True):
        shown.setdefault(pressure_label(p), p)
    if len(shown) <= PRESSURE_LEGEND_MAX:
        return {label: handle(p) for label, p in shown.items()}
    mpa = plt.Normalize(norm.vmin / 1e6, norm.vmax / 1e6)
    bars.append(fig.colorbar(plt.cm.ScalarMappable(norm=mpa, cmap=cmap), ax=ax, label=PRESSURE_BAR, fraction=0.05))
    return {"pressurised (colour: p)": handle(max(shown.values()))}


def fractures_of_result(path: Path, result) -> dict:
    """fractures.png of a result folder (an io.outdir.StoredResult): the
    final fractures from summary.json, the wings coloured by step, and, from
    the last step's files, the mesh, the outer boundary and the faces' open,
    stick and slip parts; the fractures that hold fluid at the last step
    (its pressures) with a pressure rim; what plot_fractures drew."""
    s = result.summary
    steps = s["steps"]
    mesh = boundary = None
    lines, states, tips = np.zeros((0, 3, 2)), np.zeros(0, np.int8), []
    if steps:
        mesh = result.fields_of(len(steps) - 1)
        faces = result.faces_of(len(steps) - 1)
        boundary = outer_boundary(mesh.x, mesh.triangles)
        lines, states = faces.lines, faces.state
        tips = [{"x": t["x"], "y": t["y"]} for t in steps[-1]["tips"]]
    rosette = _rosette(mesh, tips)   # measured on the last step's mesh, at its tips
    # wrapped to the domain panel's width: longer, it ran over the zoom beside it
    title = textwrap.fill(f"{s['title']}: {len(steps)} step{'s' if len(steps) != 1 else ''}", 60)
    if s["status"] != "finished":
        title += "\n" + textwrap.shorten(s["status"], 70)
    return plot_fractures(path, s["fractures"], tips=_tips_at_end(s), rosette=rosette, face_lines=lines,
                          face_states=states, title=title, mesh=mesh, growth=growth_segments(s), boundary=boundary,
                          pressures=fracture_pressures(s))


def _tips_at_end(summary: dict) -> list:
    """The crack tips after the last step: where its free tips went (their
    fracture's final ends); a tip that joined a fracture or reached the
    boundary in it is no tip any more."""
    steps = summary["steps"]
    if not steps:
        return []
    final = _final_ends(summary)
    out = []
    for t in steps[-1]["tips"]:
        if t.get("state") in ("joined", "boundary"):
            continue
        x, y = final.get((t["fracture"], t["end"]), (t["x"], t["y"]))
        out.append({"x": float(x), "y": float(y)})
    return out


def _final_ends(summary: dict) -> dict:
    """{(fracture, end): (x, y)} of every fracture's ends in summary["fractures"]
    (its pieces: wing at end 0, pre-existing part, wing at end 1)."""
    pieces = {}
    for f in summary["fractures"]:
        if "fracture" in f:
            pieces.setdefault(f["fracture"], []).append(np.asarray(f["points"], float))
    final = {}
    for i, p in pieces.items():
        final[(i, 0)], final[(i, 1)] = p[0][0], p[-1][-1]
    return final


def growth_segments(summary: dict) -> list:
    """[((x0, y0), (x1, y1), step)]: the straight advance of every tip that
    grew in each step, from its position in that step to its position in
    the next (or, after the last step or once it joined or reached the
    boundary, to its fracture's final end in summary["fractures"])."""
    final = _final_ends(summary)
    steps = summary["steps"]
    out = []
    for k, step in enumerate(steps):
        later = {(t["fracture"], t["end"]): (t["x"], t["y"]) for t in steps[k + 1]["tips"]} if k + 1 < len(steps) else {}
        for t in step["tips"]:
            key = (t["fracture"], t["end"])
            end = later.get(key, final.get(key))
            if t.get("advance", 0.0) > 0 and end is not None:
                out.append(((t["x"], t["y"]), tuple(map(float, end)), k))
    return out


def outer_boundary(x: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(k, 2, 2) edges of the outer boundary of a cracked mesh: the edges of
    one triangle only, less the crack faces, which come in coinciding pairs
    (the faces are split into two copies of each node)."""
    e = np.sort(np.vstack([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    edges, count = np.unique(e, axis=0, return_counts=True)
    edges = edges[count == 1]
    scale = float(np.ptp(x, axis=0).max()) or 1.0
    key = np.round(x / scale * 1e9).astype(np.int64)[edges]          # (k, 2, 2)
    swap = (key[:, 0, 0] > key[:, 1, 0]) | ((key[:, 0, 0] == key[:, 1, 0]) & (key[:, 0, 1] > key[:, 1, 1]))
    key[swap] = key[swap][:, ::-1]
    _, where, count = np.unique(key.reshape(-1, 4), axis=0, return_inverse=True, return_counts=True)
    outer = count[where.ravel()] == 1
    return x[edges[outer]]


def _rosette(mesh, tips) -> float:
    """The rosette radius: the farthest vertex of the triangles at a tip
    (the median over the tips). Linear in tips + cells: a network of 1,000
    fractures has 2,000 tips on a mesh of 1.9M nodes."""
    if mesh is None or not tips:
        return 0.0
    t = np.array([[p["x"], p["y"]] for p in tips])
    node, tip_node = np.unique(cKDTree(mesh.x).query(t)[1], return_inverse=True)
    which = np.full(len(mesh.x), -1, np.int64)
    which[node] = np.arange(len(node))
    tri = np.asarray(mesh.triangles)
    r = np.zeros(len(node))
    for k in range(tri.shape[1]):   # each triangle with a tip node at corner k
        at = np.flatnonzero(which[tri[:, k]] >= 0)
        i = which[tri[at, k]]
        d = np.linalg.norm(mesh.x[tri[at]] - mesh.x[node[i]][:, None, :], axis=2).max(axis=1)
        np.maximum.at(r, i, d)
    return float(np.median(r[tip_node]))
