"""history.png: how a run went, step by step: the load factor, K_eq of
every tip (Pa m^0.5, eq. 10 of the paper) and the number of DOFs; when a
fracture holds fluid in some step, a panel more: the injection pressure
(the highest fracture pressure of the step, MPa) and, from the face files,
the slipping length (m, the face edges in state SLIP). A run driven by a
pump (its steps have a time) shows instead, against time, the injection
pressure (the breakdown curve: every state the steps solved, the drop after
each growth) and the fractures' length, then K_eq and the DOFs by step."""
from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np
import wingcrack_kernels as K

from . import fonts
from .atomic import replacing
from .faces import SLIP
from ..schedule import Schedule


def history(summary: dict) -> dict:
    """The series drawn, from a summary (as in summary.json):
    step (s,), load_factor (s,), critical (s,): each step's own critical
    load factor (NaN where not recorded), dofs (s,), k_eq {(fracture, end): (s,)}
    with NaN where that tip does not exist (not yet grown, joined, at the
    boundary), and injection (s,): the highest fracture pressure of each
    step (Pa; 0 for a step without pressures). K_eq is computed from KI,
    KII, theta when a summary lacks it."""
    steps = summary["steps"]
    keys = sorted({(t["fracture"], t["end"]) for st in steps for t in st["tips"]})
    k_eq = {key: np.full(len(steps), np.nan) for key in keys}
    for k, st in enumerate(steps):
        for t in st["tips"]:
            k_eq[(t["fracture"], t["end"])][k] = t["K_eq"] if "K_eq" in t else _k_eq(t)
    return {"step": np.array([st["step"] for st in steps], float),
            "load_factor": np.array([st["load_factor"] for st in steps], float),
            "critical": np.array([st.get("critical_load_factor", np.nan) for st in steps], float),
            "dofs": np.array([st["dofs"] for st in steps], float),
            "k_eq": k_eq,
            "injection": np.array([max(st.get("pressures") or [0.0]) for st in steps], float)}


def slipping_lengths(result) -> np.ndarray:
    """(s,) the slipping length of every step of a result folder (an
    io.outdir.StoredResult), m: the summed lengths of its face edges in
    state SLIP (the + faces, io.outdir.StepFaces.lengths), from its face file."""
    out = np.zeros(len(result.steps))
    for k in range(len(out)):
        faces = result.faces_of(k)
        out[k] = float(faces.lengths[faces.state == SLIP].sum())
    return out


def _k_eq(t: dict) -> float:
    return float(K.equivalent_k(np.array([t["KI"]]), np.array([t["KII"]]), np.array([t["theta"]]))[0])


def plot_history(path: Path, summary: dict, result=None) -> dict:
    """Write history.png and return what was drawn: {label: (x, y)} read
    back from the figure's lines (labels "load factor", "critical load
    factor of the step" where a step's own fell below the held load,
    "peak <value> (step <k>)" where the load changed, "DOFs",
    "fracture F end E" for K_eq and "KIc" for its line where the summary
    holds KIc; when some step has a fracture pressure
    above 0, "injection pressure" in MPa and, with `result` (the folder's
    io.outdir.StoredResult, whose face files give it), "slipping length"
    in m)."""
    import matplotlib   # lazy: start-up
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = history(summary)
    if any("time" in st for st in summary["steps"]):
        return _plot_pumped(path, summary, h, plt)
    wet = bool(np.any(h["injection"] > 0))
    # constrained layout keeps a legend beside its axes inside the figure (tight_layout leaves it out
    # and warns when it cannot fit: the warning reached the terminal raw)
    fig, axes = plt.subplots(4 if wet else 3, 1, figsize=(8.5, 9.5 if wet else 7.5), sharex=True,
                             layout="constrained")
    ax_load, ax_k, ax_dofs = axes[0], axes[-2], axes[-1]
    marker = "o" if len(h["step"]) <= 60 else None
    ax_load.plot(h["step"], h["load_factor"], marker=marker, ms=3, color="black", label="load factor")
    _critical_and_peak(ax_load, h, marker)
    ax_load.set_ylabel("load factor")
    extra = []
    if wet:
        extra = _injection_panel(axes[1], h, None if result is None else slipping_lengths(result), marker)
    _k_eq_panel(ax_k, h, summary, marker)
    ax_dofs.plot(h["step"], h["dofs"], marker=marker, ms=3, color="tab:gray", label="DOFs")
    ax_dofs.set_ylabel("DOFs")
    ax_dofs.set_xlabel("step")
    ax_dofs.xaxis.get_major_locator().set_params(integer=True)
    status = "" if summary["status"] == "finished" else "\n" + textwrap.shorten(summary["status"], 80)
    fonts.set_title(ax_load, f"{summary['title']}: {len(h['step'])} steps{status}", fontsize=10)
    for ax in (*axes, *extra):
        ax.grid(alpha=0.3)
        # no offset notation ("1e-6 + 2e5"): it makes round-off jitter between steps look like a spike
        ax.ticklabel_format(axis="y", useOffset=False)
    drawn = {line.get_label(): (np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
             for ax in (*axes, *extra) for line in ax.get_lines()}
    try:
        with replacing(path, Path(path).suffix) as tmp:   # the format by the suffix
            fig.savefig(tmp, dpi=110)
    finally:   # a file not written leaves no figure open (a long-lived drawing process draws the next)
        plt.close(fig)
    return drawn


def _critical_and_peak(ax, h: dict, marker) -> None:
    """Each step's own critical load factor (where recorded: after the peak
    it falls below the load the run holds, the paper's load against wing
    length), and the peak of the held load; a legend when either is drawn."""
    crit = h["critical"]
    drawn = False
    if np.any(np.isfinite(crit)) and np.any(crit[np.isfinite(crit)] < h["load_factor"][np.isfinite(crit)]
                                            * (1 - 1e-9)):
        ax.plot(h["step"], crit, marker=marker, ms=3, ls="--", color="tab:blue",
                label="critical load factor of the step")
        drawn = True
    if len(h["step"]) > 1 and np.ptp(h["load_factor"]) > 0:
        k = int(np.argmax(h["load_factor"]))
        peak = h["load_factor"][k]
        ax.plot([h["step"][k]], [peak], marker="*", ms=10, ls="none", color="tab:red",
                label=f"peak {peak:.5g} (step {int(h['step'][k])})")
        drawn = True
    if drawn:
        ax.legend(fontsize=7, loc="best")


#: tips named one by one in the K_eq legend; past this the growing tips (those that ever grew) are
#: coloured and the others grey, with one legend entry each group: a legend of 40 tips covered the
#: panels below and ran off the image
LEGEND_TIPS = 8


def _k_eq_panel(ax, h: dict, summary: dict, marker) -> None:
    """K_eq of every tip (a line each, labelled "fracture F end E") and
    KIc as a dashed line when the summary holds it; the legend beside the
    axes."""
    tips = h["k_eq"]
    grew = {(t["fracture"], t["end"]) for st in summary["steps"] for t in st["tips"]
            if t.get("state") == "growing"}
    few = len(tips) <= LEGEND_TIPS
    handles, group = [], {}   # group: the first line of the growing tips and of the others
    colours = _tip_colours(sorted(grew) if not few else sorted(tips))
    for key, y in tips.items():
        f, e = key
        if few or key in grew:
            line, = ax.plot(h["step"], y, marker=marker, ms=3, color=colours[key], label=f"fracture {f} end {e}")
            if few:
                handles.append(line)
            else:
                group.setdefault("growing", (line, f"growing tips ({len(grew & set(tips))}), a colour each"))
        else:
            line, = ax.plot(h["step"], y, lw=0.8, color="0.72", zorder=1, label=f"fracture {f} end {e}")
            group.setdefault("other", (line, f"other tips ({len(tips) - len(grew & set(tips))})"))
    handles += [group[g] for g in ("growing", "other") if g in group]
    KIc = summary.get("KIc")
    if KIc is not None and tips:
        handles.append(ax.axhline(float(KIc), color="black", ls="--", lw=1.0, label="KIc"))
    ax.set_ylabel("K_eq (Pa m$^{1/2}$)")
    if handles:
        pairs = [(hd, hd.get_label()) if not isinstance(hd, tuple) else hd for hd in handles]
        ax.legend([p[0] for p in pairs], [p[1] for p in pairs], fontsize=7, loc="upper left",
                  bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)


def _tip_colours(keys) -> dict:
    """A colour per tip key, by its fracture (the fractures spread over a
    qualitative map, both ends of one fracture alike but for a shade)."""
    import matplotlib   # lazy: start-up

    cmap = matplotlib.colormaps["tab10" if len({k[0] for k in keys}) <= 10 else "tab20"]
    fractures = sorted({k[0] for k in keys})
    where = {f: i for i, f in enumerate(fractures)}
    out = {}
    for f, e in keys:
        r, g, b, _ = cmap(where[f] % cmap.N)
        shade = 1.0 if e == 0 else 0.75
        out[(f, e)] = (r * shade, g * shade, b * shade)
    return out


def _injection_panel(ax, h: dict, slipping, marker) -> list:
    """The injection pressure (MPa) on `ax` and, when known, the slipping
    length (m) on a second axis at its right: [that axis] or []."""
    ax.plot(h["step"], h["injection"] / 1e6, marker=marker, ms=3, color="#0072B2", label="injection pressure")
    ax.set_ylabel("injection pressure (MPa)", color="#0072B2")
    ax.set_ylim(bottom=0.0)
    if slipping is None:
        return []
    # the slip band's colour of fractures.png
    right = ax.twinx()
    right.plot(h["step"], slipping, marker=marker, ms=3, color="#D55E00", ls="--", label="slipping length")
    right.set_ylabel("slipping length (m)", color="#D55E00")
    right.set_ylim(bottom=0.0)   # the axis labels, in the lines' colours, say which is which: no legend over them
    return [right]


def pumped(summary: dict) -> dict:
    """The series of a pumped run (steps with a time), from its summary:
    curve (t (n,), p (n,)): every state its steps solved in time order (each
    step's balance, the search's states below the critical pressure, the
    critical point; the drop after growth is the next step's balance at the
    same time), Pa; critical (t, p) of each step's record, unstable (s,)
    bool and stopped (s,) bool (the state the run stopped in: no critical
    point); length (t (2s,), m (2s,)): the fractures' total length over each
    step's interval, from its start to its time; front (t, m): with the
    flow along the fractures, the slip front's distance from the injection
    point at each time step (else None)."""
    steps = [st for st in summary["steps"] if "time" in st]
    points = [pt for st in steps for pt in st["injection"]["history"]]
    t = np.array([pt[0] for pt in points], float)
    p = np.array([pt[1] for pt in points], float)
    front = None
    if points and len(points[0]) >= 6:   # the flow along the fractures: each time step's slip front too
        front = (t, np.array([pt[5] for pt in points], float))
    schedule = summary.get("propagation", {}).get("schedule")
    if schedule is not None:
        t, p = _through_the_schedule(t, p, Schedule.from_dict(schedule))
    lengths = [sum(n["length"] for n in st["networks"]) for st in steps]
    starts = [st["injection"]["history"][0][0] for st in steps]
    ends = [st["time"] for st in steps]
    return {"curve": (t, p), "front": front,
            "critical": (np.array(ends, float), np.array([st["injection"]["pressure"] for st in steps], float)),
            "unstable": np.array([bool(st["injection"].get("unstable")) for st in steps]),
            "stopped": np.array([bool(st["injection"].get("stopped")) for st in steps]),
            "length": (np.array([x for a, b in zip(starts, ends) for x in (a, b)], float),
                       np.array([x for m in lengths for x in (m, m)], float))}


def _through_the_schedule(t: np.ndarray, p: np.ndarray, schedule: Schedule):
    """The curve (t, p) with a point more at each time the pump's rate
    changes between two of its states (a shut-in holds the pressure, a start
    raises it from there): between two states solved on one geometry the
    pressure follows the fluid pumped, Q(t), so it is interpolated in Q,
    exact at the states and at rest while nothing is pumped. States at one
    time (the drop after growth) are kept as they are."""
    out_t, out_p = [t[:1]], [p[:1]]
    for i in range(1, len(t)):
        t1, t2 = t[i - 1], t[i]
        knots = schedule.times[(schedule.times > t1) & (schedule.times < t2)]
        q1, q2 = schedule.injected(t1), schedule.injected(t2)
        if len(knots) and q2 > q1:
            q = np.array([schedule.injected(k) for k in knots])
            out_t.append(knots)
            out_p.append(p[i - 1] + (p[i] - p[i - 1]) * (q - q1) / (q2 - q1))
        out_t.append(t[i:i + 1])
        out_p.append(p[i:i + 1])
    return np.concatenate(out_t), np.concatenate(out_p)


def _plot_pumped(path: Path, summary: dict, h: dict, plt) -> dict:
    """history.png of a pumped run: the breakdown curve and the fractures'
    length against time, K_eq and the DOFs by step (labels "injection
    pressure", "critical pressure of the step", "unstable growth (no time
    passes)", "where the run stopped (no tip at KIc)", "fracture length", "fracture F end E", "KIc", "DOFs")."""
    pm = pumped(summary)
    fig, axes = plt.subplots(4, 1, figsize=(8.5, 10.5), layout="constrained",
                             gridspec_kw={"height_ratios": [1.4, 1.0, 1.1, 0.7]})
    ax_p, ax_l, ax_k, ax_dofs = axes
    marker = "o" if len(h["step"]) <= 60 else None
    t, p = pm["curve"]
    ax_p.plot(t, p / 1e6, lw=1.2, color="#0072B2", label="injection pressure")
    tc, pc = pm["critical"]
    unstable, stopped = pm["unstable"], pm["stopped"]
    stable = ~unstable & ~stopped   # the state a run stopped in is no critical one
    flowing = pm["front"] is not None   # the flow along the fractures: a step is a growth or a frame
    if stable.any():
        ax_p.plot(tc[stable], pc[stable] / 1e6, ls="none", marker="o", ms=3.5, color="black",
                  label="the steps' states" if flowing else "critical pressure of the step")
    if unstable.any():
        ax_p.plot(tc[unstable], pc[unstable] / 1e6, ls="none", marker="x", ms=5, color="#D55E00",
                  label="unstable growth (no time passes)")
    if stopped.any():
        ax_p.plot(tc[stopped], pc[stopped] / 1e6, ls="none", marker="s", ms=4, mfc="none", color="black",
                  label="where the run stopped (no tip at KIc)")
    ax_p.set_ylabel("injection pressure (MPa)")
    ax_p.set_ylim(bottom=0.0)
    ax_p.legend(fontsize=7, loc="best")
    tl, ml = pm["length"]
    ax_l.plot(tl, ml, color="#009E73", label="fracture length")
    if flowing:
        ax_l.plot(*pm["front"], color="#CC79A7", label="slip front (from the injection point)")
        ax_l.legend(fontsize=7, loc="best")
    ax_l.set_ylabel("length (m)" if flowing else "fracture length (m)")
    ax_l.set_xlabel("time (s)")
    ax_p.sharex(ax_l)
    _k_eq_panel(ax_k, h, summary, marker)
    ax_dofs.plot(h["step"], h["dofs"], marker=marker, ms=3, color="tab:gray", label="DOFs")
    ax_dofs.set_ylabel("DOFs")
    ax_dofs.set_xlabel("step")
    ax_k.sharex(ax_dofs)
    ax_dofs.xaxis.get_major_locator().set_params(integer=True)
    status = "" if summary["status"] == "finished" else "\n" + textwrap.shorten(summary["status"], 80)
    fonts.set_title(ax_p, f"{summary['title']}: {len(h['step'])} steps{status}", fontsize=10)
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.ticklabel_format(axis="y", useOffset=False)
    drawn = {line.get_label(): (np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
             for ax in axes for line in ax.get_lines()}
    try:
        with replacing(path, Path(path).suffix) as tmp:
            fig.savefig(tmp, dpi=110)
    finally:
        plt.close(fig)
    return drawn
