"""Every case in cases/ end to end, for `make bench` (issue 16, "Report";
not a test): each case runs as its own `wingcrack run` process
(propagation.run_case), and the report gives per case the steps, the DOFs
of the first and the last step, the process wall (start-up included), the
peak RSS, the status, the seconds per step by the issue's phases
(phases.py), and the ratio to today's figures (benchmarks/baseline.json)
with the flags of target 4 (ratios.py).

    python benchmarks/cases.py [--cases NAME ...] [--keep DIR] [--json FILE]
    python benchmarks/cases.py --base CHECKOUT [--pairs N] [--cases NAME ...]
    CHECKOUT/.venv/bin/python benchmarks/cases.py --json FILE   (another checkout's figures, these case files)

With --base, each case runs alternately with the other checkout (its own
.venv/bin/wingcrack and its own case file of that name) and with this one,
N pairs (the order turned every pair), and the ratio is that of the
medians: on a shared machine the honest measurement, since both see the
same load.
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

import phases
from propagation import ROOT, WINGCRACK, run_case
from ratios import TARGET_RATIO, compare, figures, load_baseline, per_step_total

LINE = "=" * 100


def case_names(root: Path = ROOT) -> list[str]:
    """Every case of root/cases/ (a new case is in the report without a list to edit)."""
    return sorted(p.stem for p in (root / "cases").glob("*.toml"))


def run_all(names, out: Path) -> dict:
    """{name: run_case result}, each case into out/<name>, printing a line as each ends."""
    runs = {}
    for name in names:
        runs[name] = r = run_case(name, out / name)
        print(f"  ran {name}: {r['wall']:.1f} s, exit {r['exit']}", flush=True)
    return runs


def _f(v, width=7, digits=3) -> str:
    return f"{'-':>{width}s}" if v is None else f"{v:{width}.{digits}f}"


def _ratio(v) -> str:
    return f"{'-':>6s}" if v is None else f"{v:5.2f}x"


def header(about: str) -> None:
    print("Phases: the issue's names from the summary's per-step seconds (benchmarks/phases.py):")
    for line in phases.mapping_text().splitlines():
        print("  " + line)
    print("  (\"-\": no such key was recorded; \"patch\", local remeshing, does not exist yet)")
    print("wall: the process's, start-up and form compilation included; cpu: its CPU seconds (user + system); "
          "rest = wall - the steps' own seconds (start-up, summary and checkpoint writes)")
    print(f"faster = base wall / wall; /step = the same of the steps' own seconds per step. "
          f"Base: {about}")


def report(runs: dict, baseline: dict) -> dict:
    """Print the per-case tables of `runs` ({name: run_case result}) against
    baseline["cases"]; returns {name: (figures, comparison)}."""
    base = baseline.get("cases", {})
    header(baseline.get("about", "?"))
    rows = {}
    print(f"\n{'case':28s} {'status':9s} {'steps':>5s} {'DOFs first/last':>17s} {'wall s':>7s} {'cpu s':>6s} "
          f"{'rest s':>6s} {'RSS MiB':>7s} | {'base s':>6s} {'faster':>6s} {'/step':>6s} | flags")
    for name, r in runs.items():
        fig = figures(r)
        cmp = compare(fig, base.get(name))
        rows[name] = (fig, cmp)
        dofs = f"{fig['dofs'][0]:,}/{fig['dofs'][1]:,}" if fig["dofs"] else "-"
        rest = fig["wall"] - fig["phases"].get("total", 0.0)
        b = base.get(name)
        print(f"{name:28s} {fig['status'].split(':')[0][:9]:9s} {fig['steps']:5d} {dofs:>17s} {fig['wall']:7.1f} "
              f"{_f(fig['cpu'], 6, 1)} {rest:6.1f} {fig['rss_mib']:7.0f} | {_f(b and b['wall'], 6, 1)} {_ratio(cmp['ratio'])} "
              f"{_ratio(cmp['step_ratio'])} | {', '.join(cmp['flags'])}")
    names = list(phases.ISSUE_PHASES) + [phases.OTHER]
    print(f"\nseconds per step by phase\n{'case':28s} {'total':>7s} " + " ".join(f"{p:>9s}" for p in names))
    for name, r in runs.items():
        ps = phases.per_step(r["summary"].get("steps", []))
        if not ps:
            print(f"{name:28s} no steps: {r['summary'].get('status') or r['stderr'][-200:]}")
            continue
        print(f"{name:28s} {ps['total']:7.3f} " + " ".join(_f(ps[p], 9) for p in names))
    unknown = sorted({k for r in runs.values() for k in phases.unknown_keys(r["summary"].get("steps", []))})
    if unknown:
        print(f"  other = {', '.join(unknown)}")
    slow = [n for n, (_, c) in rows.items() if c["ratio"] is not None and c["ratio"] < TARGET_RATIO]
    slower = [n for n, (_, c) in rows.items() if c["ratio"] is not None and c["ratio"] < 1.0]
    no_base = [n for n, (_, c) in rows.items() if c["ratio"] is None]
    verdict = "met" if not slow and not no_base else \
        f"not met: {len(slow)} of {len(rows)} case(s) under {TARGET_RATIO:g}x, {len(slower)} slower than today" + \
        (f", {len(no_base)} without a baseline" if no_base else "")
    print(f"\ntarget 4 (every case >= {TARGET_RATIO:g}x faster than today end to end, none slower): {verdict}")
    print("  (one run each against figures of another hour on a shared machine; cpu / wall is the share of a "
          "core a run got. Ratios of runs side by side: `benchmarks/cases.py --base CHECKOUT --pairs N`)")
    return rows


def paired(names, base_root: Path, pairs: int, out: Path) -> None:
    """Each case alternately with `base_root`'s checkout and this one, `pairs`
    times; prints the medians of the walls and of the seconds per step, and
    their ratios base/new."""
    base_wc = base_root / ".venv" / "bin" / "wingcrack"
    if not base_wc.exists():
        sys.exit(f"--base: {base_wc} does not exist (run `make setup` in {base_root})")
    print(f"Paired: each case {pairs} time(s) with {base_root} (base) and {ROOT} (new), alternately; "
          "ratios of the medians (base / new: > 1 is faster than the base) of the process wall (faster), "
          "the steps' own seconds per step (/step) and the CPU seconds (cpu)")
    print(f"\n{'case':28s} {'base s':>7s} {'new s':>7s} {'faster':>6s} {'/step':>6s} {'cpu':>6s} "
          f"{'RSS base/new MiB':>17s} | pairs (base/new s) | flags")
    for name in names:
        base_case = base_root / "cases" / f"{name}.toml"
        if not base_case.exists():
            print(f"{name:28s} not a case of the base")
            continue
        runs = {"base": [], "new": []}
        for i in range(pairs):
            order = [("base", base_wc, base_case), ("new", WINGCRACK, ROOT / "cases" / f"{name}.toml")]
            for side, wc, case in (order if i % 2 == 0 else order[::-1]):
                runs[side].append(figures(run_case(name, out / f"{side}{i}" / name, case=case, wingcrack=wc)))
        med = {side: median_figures(figs) for side, figs in runs.items()}
        cmp = compare(med["new"], med["base"])
        if base_case.read_text() != (ROOT / "cases" / f"{name}.toml").read_text():
            cmp["flags"].append("case files differ")
        walls = ", ".join(f"{b['wall']:.1f}/{n['wall']:.1f}" for b, n in zip(runs["base"], runs["new"]))
        print(f"{name:28s} {med['base']['wall']:7.1f} {med['new']['wall']:7.1f} {_ratio(cmp['ratio'])} "
              f"{_ratio(cmp['step_ratio'])} {_ratio(cmp['cpu_ratio'])} {med['base']['rss_mib']:8.0f}/{med['new']['rss_mib']:<8.0f} | {walls} | "
              f"{', '.join(cmp['flags'])}", flush=True)


def median_figures(figs: list) -> dict:
    """The figures of repeated runs of one case: medians of wall, RSS and the
    seconds summed per phase; status, steps and DOFs of the first run (a run
    is deterministic in those)."""
    keys = sorted({k for f in figs for k in f["phases"]})
    cpu = [f["cpu"] for f in figs if f.get("cpu") is not None]
    return dict(figs[0], wall=statistics.median(f["wall"] for f in figs),
                cpu=statistics.median(cpu) if cpu else None,
                rss_mib=statistics.median(f["rss_mib"] for f in figs),
                phases={k: statistics.median(f["phases"].get(k, 0.0) for f in figs) for k in keys})


def main(argv=None) -> dict | None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", nargs="+", help="these cases of cases/ only (default: every one)")
    ap.add_argument("--keep", type=Path, help="keep the results in this folder")
    ap.add_argument("--base", type=Path, help="another checkout to run alternately with this one")
    ap.add_argument("--pairs", type=int, default=1, help="with --base: runs of each side per case")
    ap.add_argument("--json", type=Path, help="also write the figures per case here (baseline.json's \"cases\")")
    args = ap.parse_args(argv)
    names = args.cases or case_names()
    unknown = [n for n in names if not (ROOT / "cases" / f"{n}.toml").exists()]
    if unknown:
        ap.error(f"--cases: no such case in cases/: {', '.join(unknown)}")
    print(f"\n{LINE}\nBENCHMARK (issue 16): every case of cases/ end to end, {len(names)} case(s)\n{LINE}")
    with tempfile.TemporaryDirectory() as tmp:
        out = args.keep or Path(tmp)
        if args.base:
            return paired(names, args.base.resolve(), args.pairs, out)
        rows = report(run_all(names, out), load_baseline())
    if args.json:
        args.json.write_text(json.dumps({n: fig for n, (fig, _) in rows.items()}, indent=1) + "\n")
    return rows


if __name__ == "__main__":
    main()
