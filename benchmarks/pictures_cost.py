"""What the pictures cost (not a test): the 45-degree disc
(cases/brazilian_disc_45.toml with propagation.steps = 34) run with its
pictures and with --no-plots, in turn (with, without, with, ...), each
run its own `wingcrack run` process; the ratio with / without of each
pair's process walls, so that a machine whose speed drifts moves both
runs of a pair alike, and of their CPU seconds (the drawing process's
included), which is what the wall ratio tends to when no core is free
(a machine shared with other work). The issue's bound: at most 1.2x.

Then where the pictures' time goes, measured here (CPU seconds) on the last
run's folder by the code the drawing process runs: the steps read and the
frames drawn as the steps come (io.growing_animation, in the drawing
process while the run computes), then the pictures at the end (the
animation from the frames kept, history.png; fractures.png, drawn with
--no-plots too, beside them on the other core).

    python benchmarks/pictures_cost.py [--repeat N] [--json FILE]
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import results_file
from case_variant import write_variant
from propagation import ROOT, run_case

DISC = ROOT / "cases" / "brazilian_disc_45.toml"
STEPS = {"propagation.steps": 34}
#: the bound on a run with pictures over one without
BOUND = 1.2


def phases(out: Path) -> dict:
    """{phase: CPU seconds, "frames ...": counts} of the pictures of the run
    in `out`, drawn here as the drawing process draws them (see the doc)."""
    import matplotlib
    matplotlib.use("Agg")
    from wingcrack.io import animation, frames, growing_animation, history, movie, outdir, pictures

    seconds, counts = defaultdict(float), defaultdict(int)
    where = ["during"]

    def timed(owner, name, label, count=None):
        real = getattr(owner, name)

        def wrapper(*args, **kwargs):
            t = time.process_time()
            try:
                return real(*args, **kwargs)
            finally:
                seconds[f"{where[0]}: {label}"] += time.process_time() - t
                if count:
                    counts[f"{where[0]}: {count}"] += 1
        setattr(owner, name, wrapper)

    timed(outdir.StoredResult, "fields_of", "read the step files")
    timed(outdir.StoredResult, "faces_of", "read the step files")
    timed(frames.FrameDrawer, "__init__", "figures made", "figures")
    timed(frames.FrameDrawer, "draw", "frames drawn", "frames")
    timed(movie, "write", "GIF written")
    result = outdir.read_result(out)
    frames._gif_palette()   # made once a process, at its first run's start (growing_animation.begin)
    t = time.process_time()
    growing_animation.begin(out, result.summary["title"], result.summary["propagation"], True)
    for k, record in enumerate(result.steps):
        growing_animation.add(out, [(k, record)])
    seconds["during: total"] = time.process_time() - t
    where[0] = "end"
    t = time.process_time()
    animation.animate_growth(out, result, "gif")
    seconds["end: the animation"] = time.process_time() - t
    t = time.process_time()
    history.plot_history(out / "history.png", result.summary, result)
    seconds["end: history.png"] = time.process_time() - t
    t = time.process_time()
    pictures.fractures_of_result(out / "fractures.png", result)
    seconds["end: fractures.png (with --no-plots too; beside the others)"] = time.process_time() - t
    return {"seconds": {k: round(v, 3) for k, v in seconds.items()}, "counts": dict(counts), "steps": len(result.steps)}


def main(argv=None) -> list:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3, help="pairs of runs (default 3)")
    ap.add_argument("--json", type=Path, help="also write the figures here (benchmarks/pictures_cost.json)")
    args = ap.parse_args(argv)
    pairs = []
    load = [results_file.load()]
    with tempfile.TemporaryDirectory() as tmp:
        case = write_variant(DISC, STEPS, Path(tmp) / "disc_34_pictures.toml")
        for i in range(args.repeat):
            with_ = run_case("with", Path(tmp) / f"with_{i}", case=case, plots=True)
            without = run_case("without", Path(tmp) / f"without_{i}", case=case)
            for r in (with_, without):
                if r["exit"] != 0:
                    print(f"  run {r['name']} {i}: exit {r['exit']}: {r['stderr']}")
            pairs.append({k: round(r[f], 2) for k, r, f in (("wall_with", with_, "wall"), ("wall_without", without, "wall"),
                                                          ("cpu_with", with_, "cpu"), ("cpu_without", without, "cpu"))})
            p = pairs[-1]
            print(f"  pair {i + 1}: wall with pictures {p['wall_with']:.1f} s, without {p['wall_without']:.1f} s: "
                  f"{p['wall_with'] / p['wall_without']:.2f}x; CPU {p['cpu_with']:.1f} s / {p['cpu_without']:.1f} s: "
                  f"{p['cpu_with'] / p['cpu_without']:.2f}x", flush=True)
        load.append(results_file.load())
        spent = phases(Path(tmp) / f"with_{args.repeat - 1}")
    wall = [p["wall_with"] / p["wall_without"] for p in pairs]
    cpu = [p["cpu_with"] / p["cpu_without"] for p in pairs]
    med, med_cpu = statistics.median(wall), statistics.median(cpu)
    print(f"  pictures' cost on the disc ({DISC.name}, 34 steps): with / without {med:.2f}x wall (median of "
          f"{len(wall)} pairs, {min(wall):.2f}-{max(wall):.2f}), {med_cpu:.2f}x CPU; load average (1 min) "
          f"{load[0]:g} before, {load[1]:g} after, on {os.cpu_count()} cores; bound <= {BOUND:g}x: "
          f"{'met' if med <= BOUND else 'not met'}")
    print(f"  where the pictures' time goes (CPU s, drawn here from the last run's folder, {spent['steps']} steps):")
    for name, s in spent["seconds"].items():
        print(f"    {name:66s} {s:7.3f}")
    print("    counted: " + ", ".join(f"{k} {v}" for k, v in spent["counts"].items()))
    if args.json:
        results_file.write(
            args.json, f"the 45-degree disc at 34 steps, `wingcrack run` with its pictures and with --no-plots, "
                       f"alternating, {len(pairs)} pairs",
            "benchmarks/pictures_cost.py: wall and CPU seconds of each run's process (os.wait4, its workers "
            "included); phases: CPU seconds of the drawing process's code replayed on the last run's folder",
            load, pairs=pairs, wall_ratio=round(med, 3), cpu_ratio=round(med_cpu, 3), bound=BOUND, phases=spent)
    return wall


if __name__ == "__main__":
    main(sys.argv[1:])
