"""Issue 16's targets 1-3 for `make bench` (not a test; figures of this
machine at this time, next to today's of benchmarks/baseline.json):

1. the open 45-degree disc, 34 steps: process wall <= 8 s, >= 30x the
   published code (255 s for its 34 steps), at no fewer DOFs than today;
2. the same disc on a fine uniform mesh (mesh.size 0.8 mm, adaptive off,
   ~85k DOFs), 8 steps: a growth step after the first costs <= 35 % of the
   first (the reuse ratio), per phase too; each step's median over
   REPEATS runs (--repeats);
3. (--large) one growth step at 1.10M DOFs (benchmarks/scaling.py's 1M
   mesh, contact) on 1 and 2 processes: <= 10 s, no more memory than
   today, two processes faster than one.

    python benchmarks/targets.py [--large] [--only 1 2 3] [--keep DIR] [--base CHECKOUT] [--repeats N]
"""
from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import phases
from case_variant import write_variant
from propagation import ROOT, WINGCRACK, run_case
from ratios import figures, load_baseline

OPEN_DISC = ROOT / "cases" / "brazilian_disc_45_open.toml"
#: the published code's process wall for the disc's 34 steps (issue 16)
PUBLISHED_34_S = 255.0
DISC_34 = {"propagation.steps": 34}
DISC_34_WALL_S = 8.0
FINE_DISC = {"propagation.steps": 8, "mesh.size": 0.0008, "mesh.adaptive": False}
REUSE_TARGET = 0.35
LARGE_DOFS = 1_000_000   # scaling.py's target; its mesh has 1.10M DOFs
LARGE_STEP_S = 10.0
LINE = "=" * 100


def _x(a, b) -> str:
    return f"{a / b:.2f}x" if a and b else "-"


def disc_34(tmp: Path, base: dict, wingcrack: Path = WINGCRACK, label: str = "") -> dict:
    """Target 1: the open disc, 34 steps, its process wall against 8 s, the
    published code and today's; run by `wingcrack` (another checkout's with
    --base, its name in `label`)."""
    case = write_variant(OPEN_DISC, DISC_34, tmp / "disc_34.toml")
    fig = figures(run_case("disc_34", tmp / f"disc_34{label and '_base'}", case=case, wingcrack=wingcrack))
    b = base.get("disc_34", {})
    print(f"\nTarget 1: open 45-degree disc, 34 steps ({OPEN_DISC.name} with propagation.steps = 34){label}")
    dofs = f"{fig['dofs'][0]:,}/{fig['dofs'][1]:,}" if fig["dofs"] else "-"
    print(f"  {fig['steps']} steps, {fig['status']}; DOFs first/last {dofs}; the steps' own seconds "
          f"{fig['phases'].get('total', 0.0):.1f} s; CPU {fig['cpu']:.1f} s; peak RSS {fig['rss_mib']:.0f} MiB")
    print(f"  process wall {fig['wall']:.1f} s: target <= {DISC_34_WALL_S:g} s "
          f"({'met' if fig['wall'] <= DISC_34_WALL_S else 'not met'}); "
          f"{PUBLISHED_34_S / fig['wall']:.1f}x the published code ({PUBLISHED_34_S:g} s; target >= 30x)")
    if b:
        fewer = fig["dofs"] and b.get("dofs") and any(x < y for x, y in zip(fig["dofs"], b["dofs"]))
        print(f"  today: {b['wall']:.1f} s ({b.get('note', '')}), DOFs {b['dofs'][0]:,}/{b['dofs'][1]:,}: "
              f"{_x(b['wall'], fig['wall'])} faster{'; FEWER DOFs than today' if fewer else ''}")
    return fig


def reuse(steps: list) -> dict:
    """The reuse ratio of target 2 from a run's steps: `fractions`, each
    growth step's seconds after the first over the first step's; `phases`,
    {issue phase: (first step s, mean of the later steps s, later / first)}.
    Empty with fewer than two steps."""
    if len(steps) < 2:
        return {}
    first, later = steps[0]["seconds"], steps[1:]
    fractions = [st["seconds"]["total"] / first["total"] for st in later]
    p0 = phases.of_seconds(first)
    pl = [phases.of_seconds(st["seconds"]) for st in later]
    by_phase = {}
    for name, t0 in p0.items():
        ts = [p[name] for p in pl if p[name] is not None]
        if t0 is None and not ts:
            continue
        mean = statistics.fmean(ts) if ts else None
        by_phase[name] = (t0, mean, mean / t0 if t0 and mean is not None else None)
    return {"fractions": fractions, "phases": by_phase}


#: target 2's runs: its verdict is on each step's median over them (one run's
#: single steps move by up to a third with the machine's momentary load, the
#: first step and the later ones alike; the median of three drops a spike
#: that hits one run, as benchmarks/cases.py takes the medians of its pairs)
REPEATS = 3


def median_steps(runs: list) -> list:
    """Steps whose seconds are, phase by phase, the medians over `runs` (lists
    of summary steps of the same run repeated, the same number of steps)."""
    out = []
    for same in zip(*runs):
        names = set().union(*(st["seconds"] for st in same))
        out.append({"seconds": {n: statistics.median(st["seconds"].get(n, 0.0) for st in same) for n in names}})
    return out


def fine_disc(tmp: Path, base: dict, wingcrack: Path = WINGCRACK, label: str = "", repeats: int = REPEATS) -> dict:
    """Target 2: the fine uniform disc, 8 steps, run `repeats` times; each
    growth step against the first, on the medians over the runs step by
    step (`wingcrack`, `label`: as for disc_34)."""
    case = write_variant(OPEN_DISC, FINE_DISC, tmp / "fine_disc.toml")
    results = [run_case("fine_disc", tmp / f"fine_disc{label and '_base'}{i and f'_{i}' or ''}", case=case,
                        wingcrack=wingcrack) for i in range(repeats)]
    r = results[0]
    runs = [x["summary"].get("steps", []) for x in results]
    steps = runs[0]
    print("\nTarget 2: the reuse ratio, open disc on a fine uniform mesh (mesh.size = 0.0008, "
          f"mesh.adaptive = false), 8 steps, {repeats} run(s){label}")
    if len(steps) < 2 or any(len(st) != len(steps) for st in runs):
        print(f"  {[len(st) for st in runs]} step(s): no growth steps to compare "
              f"({r['summary'].get('status', r['stderr'][-200:])})")
        return {}
    for i, st in enumerate(runs):
        fr = reuse(st)["fractions"]
        print(f"  run {i + 1}: first step {st[0]['seconds']['total']:.2f} s, growth steps / first: "
              f"mean {100 * statistics.fmean(fr):.0f} %, {100 * min(fr):.0f}-{100 * max(fr):.0f} %; "
              f"process wall {results[i]['wall']:.1f} s")
    ru = reuse(median_steps(runs))
    fr = ru["fractions"]
    print(f"  {len(steps)} steps, {r['summary']['status']}; DOFs {steps[0]['dofs']:,} ... {steps[-1]['dofs']:,}; "
          f"peak RSS {r['peak_mib']:.0f} MiB")
    print(f"  a growth step after the first / the first (each step's median over the runs): mean "
          f"{100 * statistics.fmean(fr):.0f} %, {100 * min(fr):.0f}-{100 * max(fr):.0f} %: target <= "
          f"{100 * REUSE_TARGET:.0f} % ({'met' if max(fr) <= REUSE_TARGET else 'not met'})")
    b = base.get("fine_disc", {})
    if b:
        print(f"  today: mean {100 * b['mean_fraction']:.0f} % ({b.get('note', '')})")
    print(f"  {'phase':9s} {'first s':>8s} {'later s':>8s} {'later/first':>11s}   (medians over the runs)")
    for name, (t0, tl, q) in ru["phases"].items():
        print(f"  {name:9s} {t0 if t0 is not None else float('nan'):8.3f} "
              f"{tl if tl is not None else float('nan'):8.3f} {'-' if q is None else f'{100 * q:.0f} %':>11s}")
    return dict(ru, wall=statistics.median(x["wall"] for x in results),
                cpu=statistics.median(x["cpu"] for x in results))


def large(tmp: Path, base: dict, ranks=(1, 2)) -> dict:
    """Target 3: two steps at 1.10M DOFs (scaling.py's mesh) on 1 and 2
    processes; step 1 is the growth step after the first."""
    import scaling

    size = scaling.sizes_for([LARGE_DOFS])[0]
    print(f"\nTarget 3: 1.10M DOFs, brazilian_disc_45 (contact) on a uniform mesh of size {size:.3e} m, "
          "2 steps (benchmarks/scaling.py's 1M mesh)")
    names = list(phases.ISSUE_PHASES) + [phases.OTHER]
    print(f"  {'ranks':5s} {'step':>4s} {'DOFs':>10s} {'total s':>8s} " + " ".join(f"{p:>9s}" for p in names)
          + "   peak MiB per rank (gmsh worker)")
    results = {}
    for n in ranks:
        r = scaling.run(size, n, tmp, steps=2)
        results[n] = r
        if "error" in r:
            print(f"  {n:5d} failed: {r['error']}")
            continue
        for k, st in enumerate(r.get("steps", [r])):
            ps = phases.of_seconds(st["seconds"])
            print(f"  {n:5d} {k:4d} {st['dofs']:10,} {st['seconds']['total']:8.2f} "
                  + " ".join(f"{'-':>9s}" if ps[p] is None else f"{ps[p]:9.2f}" for p in names)
                  + (f"   {', '.join(f'{m:.0f}' for m in r['peak_mib'])} ({r['gmsh_peak_mib']:.0f})" if k == 0 else ""),
                  flush=True)
    b = base.get("large", {})
    ok = {n: r for n, r in results.items() if "error" not in r}
    if 1 in ok:
        growth = ok[1]["steps"][-1]["seconds"]["total"]
        peak = max(ok[1]["peak_mib"])
        print(f"  growth step on 1 process {growth:.1f} s: target <= {LARGE_STEP_S:g} s "
              f"({'met' if growth <= LARGE_STEP_S else 'not met'}); today {b.get('step_s', '?')} s "
              f"({b.get('note', '')})")
        if b.get("rss_mib"):
            print(f"  peak memory {peak:.0f} MiB, today {b['rss_mib']:.0f} MiB: "
                  f"{'no more' if peak <= b['rss_mib'] else 'MORE'} than today")
    if 1 in ok and 2 in ok:
        t1, t2 = (ok[n]["steps"][-1]["seconds"]["total"] for n in (1, 2))
        print(f"  two processes {t2:.1f} s against one {t1:.1f} s: "
              f"{'faster' if t2 < t1 else 'NOT faster'} ({t1 / t2:.2f}x; today {b.get('step_s_2_ranks', '?')} s "
              f"against {b.get('step_s', '?')} s)")
    return results


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--large", action="store_true", help="target 3 too (1.10M DOFs: minutes, ~3 GB)")
    ap.add_argument("--only", type=int, nargs="+", choices=(1, 2, 3), help="these targets only")
    ap.add_argument("--keep", type=Path, help="keep the results in this folder")
    ap.add_argument("--base", type=Path, help="targets 1-2 with this checkout too (its .venv), run just before")
    ap.add_argument("--repeats", type=int, default=REPEATS, help=f"target 2's runs (default {REPEATS})")
    args = ap.parse_args(argv)
    which = set(args.only or ([1, 2, 3] if args.large else [1, 2]))
    base = load_baseline()
    print(f"\n{LINE}\nBENCHMARK (issue 16): targets {', '.join(map(str, sorted(which)))}"
          f"\n  {base.get('about', '?')}\n{LINE}")
    targets = base.get("targets", {})
    with tempfile.TemporaryDirectory() as tmp:
        out = args.keep or Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        for k, run in ((1, disc_34), (2, fine_disc)):
            if k not in which:
                continue
            more = {"repeats": max(1, args.repeats)} if k == 2 else {}
            if args.base:
                label = f" [base: {args.base}]"
                b = run(out, targets, wingcrack=args.base.resolve() / ".venv" / "bin" / "wingcrack", label=label,
                        **more)
            n = run(out, targets, **more)
            if args.base and b.get("wall") and n.get("wall"):
                print(f"  this checkout against the base run just before: {b['wall'] / n['wall']:.2f}x faster "
                      f"(wall), {b['cpu'] / n['cpu']:.2f}x (cpu)")
        if 3 in which:
            large(out, targets)


if __name__ == "__main__":
    main()
