"""The command line: `wingcrack check|sif|run|crosscheck CASE [-o OUTDIR] [--quiet] [--debug]`
and `wingcrack plot OUTDIR`.

Exit status (case contract): 0 done; 2 the case is invalid, or a folder
cannot be used (an output folder that cannot be written, holds a previous
result without --force, or is in use by another wingcrack command; an empty
-o; a folder to plot that is missing or not a wingcrack result): one line
``wingcrack: error: <key or path>: <reason>`` on stderr, no traceback; 1 the
computation failed; 130 stopped by Ctrl-C, 143 by SIGTERM (a run keeps
every finished step and can be resumed). Only this module parses arguments
and prints.
"""
from __future__ import annotations

import argparse
import sys
import traceback
from pathlib import Path

from wingcrack.version import __version__
from wingcrack.errors import CaseError, ComputationError, FolderError
from wingcrack.parallel import world_rank
from wingcrack.progress import ProgressBar
from wingcrack import interrupt

PROG = "wingcrack"
EXIT_OK, EXIT_FAILED, EXIT_INVALID = 0, 1, 2
#: modules that `make setup` installs (the compiled kernels) or takes from
#: Debian: missing, the installation is incomplete, not the case wrong
INSTALLED_BY_SETUP = {"wingcrack_kernels", "dolfinx", "ufl", "basix", "petsc4py", "mpi4py", "gmsh", "meshio",
                      "matplotlib", "scipy"}


def _parser() -> argparse.ArgumentParser:
    # --quiet/--debug are accepted before or after the command; in the
    # sub-parsers they default to SUPPRESS so they do not undo the main ones.
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS,
                        help="hide progress output")
    common.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                        help="show the traceback of an unexpected error")

    p = argparse.ArgumentParser(prog=PROG, description="Wing-crack growth from pre-existing fractures, with contact.")
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    p.add_argument("--quiet", "-q", action="store_true", help="hide progress output")
    p.add_argument("--debug", action="store_true", help="show the traceback of an unexpected error")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    check = sub.add_parser("check", parents=[common], help="validate a case, print what would run")
    check.add_argument("case", type=Path, metavar="CASE", help="case file (TOML)")
    for name, text in (("sif", "one solve of the initial geometry, no growth"), ("run", "full propagation")):
        c = sub.add_parser(name, parents=[common], help=text)
        c.add_argument("case", type=Path, metavar="CASE", help="case file (TOML)")
        c.add_argument("-o", "--out", type=str, required=True, metavar="OUTDIR", help="output directory")
        c.add_argument("--force", action="store_true",
                       help="replace a previous result in OUTDIR (its files are deleted first)")
        if name == "run":
            c.add_argument("--no-plots", dest="plots", action="store_false",
                           help="skip history.png and the growth animation (fractures.png is always drawn)")
            c.add_argument("--resume", action="store_true",
                           help="continue the run in OUTDIR from its last finished step (after a kill or Ctrl-C)")
    pl = sub.add_parser("plot", parents=[common],
                        help="draw fractures.png, history.png and growth.gif of a result folder")
    pl.add_argument("folder", type=str, metavar="OUTDIR", help="a folder written by `wingcrack run` or `sif`")
    x = sub.add_parser("crosscheck", parents=[common],
                       help="solve with open faces by wingcrack and by scikit-fem on the same mesh, compare")
    x.add_argument("case", type=Path, metavar="CASE", help="case file (TOML)")
    x.add_argument("-o", "--out", type=str, metavar="OUTDIR", help="also write OUTDIR/crosscheck.json")
    x.add_argument("--tol", type=_positive, default=None, metavar="TOL",
                   help="largest relative difference of displacements and SIFs accepted (default 1e-6)")
    return p


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def _error(message: str, every_rank: bool = False) -> None:
    """One line on stderr. Under mpirun the ranks share the news of a bad
    case or a failed computation (rank 0 tells it); an unexpected error may
    be one rank's own, so each rank tells it, naming itself."""
    rank = world_rank()
    if rank != 0 and not every_rank:
        return
    where = f" (rank {rank})" if rank else ""
    print(f"{PROG}: error{where}: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    args = None
    try:
        with interrupt.terminate_raises():   # SIGTERM ends a command as Ctrl-C does
            args = _parser().parse_args(argv)
            return _command(args)
    except KeyboardInterrupt as err:   # Ctrl-C, or SIGTERM (interrupt.Terminated)
        return _stopped(err, args)
    except Exception as err:  # noqa: BLE001 - the CLI is the last line of defence
        stop = interrupt.cause(err)
        if stop is not None:   # an error that a stop caused (an import it interrupted): the stop
            return _stopped(stop, args)
        if isinstance(err, (CaseError, FolderError)):
            _error(str(err))
            return EXIT_INVALID
        if isinstance(err, ComputationError):
            _error(str(err) or "the computation failed")
            return EXIT_FAILED
        if isinstance(err, ModuleNotFoundError) and err.name in INSTALLED_BY_SETUP:
            # an environment made before the module was needed (the kernels' own
            # module, after a pull without `make setup`): no case can be checked
            _error(f"this Python environment lacks the module {err.name}, which `make setup` installs: run "
                   "`make setup` in the wingcrack checkout (an environment made for an older checkout needs it "
                   "again)", every_rank=True)
            return EXIT_FAILED
        debug = args is not None and args.debug
        if debug:
            traceback.print_exc()
        detail = " ".join(str(err).split()) or "(no message)"
        hint = "" if debug else " (run with --debug for the traceback)"
        _error(f"unexpected {type(err).__name__}: {detail}{hint}", every_rank=True)
        return EXIT_FAILED


def _stopped(err: BaseException, args=None) -> int:
    """Tell a stop by Ctrl-C or SIGTERM (`err`, a KeyboardInterrupt) and
    return its exit status (130, 143): of a `run`, the steps its folder
    keeps for --resume (those its checkpoint holds)."""
    kept = None
    if args is not None and args.command == "run" and getattr(args, "out", None) is not None:
        from wingcrack.io.outdir import resumable_steps   # numpy's import: not for --help or a usage error

        kept = resumable_steps(Path(args.out))
    if world_rank() == 0:
        print(f"{PROG}: {interrupt.stop_line(err, kept)}", file=sys.stderr)
    return interrupt.exit_code(err)


def _command(args) -> int:
    from wingcrack.io.outdir import folder_path, locked   # numpy's import: not for --help or a usage error

    if getattr(args, "out", None) is not None:
        args.out = folder_path(args.out)
    if args.command == "plot":
        args.folder = folder_path(args.folder)
        with locked(args.folder, create=False):
            return _plot(args)
    from wingcrack.case import Case

    case = Case.from_toml(args.case)
    if args.command == "check":
        if not args.quiet:
            print(describe(case))
        return EXIT_OK
    if args.command == "crosscheck":
        return _crosscheck(case, args)
    from wingcrack import api  # DOLFINx is imported only for sif/run

    with locked(args.out, create=not getattr(args, "resume", False)):
        if args.command == "run":
            with _progress(case, args.quiet) as progress:
                result = api.run(case, args.out, progress=progress, plots=args.plots, force=args.force,
                                 resume=args.resume)
        else:
            from wingcrack.progress import Heartbeat

            with Heartbeat(args.quiet):
                result = api.sif(case, args.out, force=args.force)
    if result is not None and world_rank() == 0:  # where the results are, even with --quiet
        print(f"{PROG}: {result.summary['status']}; results in {args.out}/: " + _names(result.files))
        for warning in result.summary.get("warnings", []):   # each once: summary.json keeps them
            print(f"{PROG}: warning: {warning}", file=sys.stderr)
    return EXIT_OK


def _names(files: dict) -> str:
    return ", ".join(sorted(Path(p).name for p in files.values()))


def _plot(args) -> int:
    from wingcrack import api

    files = api.plot(args.folder)
    print(f"{PROG}: pictures in {args.folder}/: {_names(files)}")
    return EXIT_OK


def _crosscheck(case, args) -> int:
    from wingcrack.crosscheck import TOLERANCE, crosscheck

    tol = args.tol or TOLERANCE
    result = crosscheck(case)
    report = dict(result.as_dict(), tolerance=tol, agree=result.agrees(tol))
    if args.out is not None:
        from wingcrack.io.summary import write_summary

        write_summary(args.out / "crosscheck.json", report)
    if not args.quiet:
        print(crosscheck_text(report))
    if not report["agree"]:
        _error(f"crosscheck: scikit-fem and wingcrack differ by more than {tol:g} (displacements "
               f"{result.u_rel:.2e}, SIFs {result.sif_rel:.2e} relative)")
        return EXIT_FAILED
    print(f"{PROG}: crosscheck agrees within {tol:g}" + (f"; report in {args.out}/crosscheck.json" if args.out else ""))
    return EXIT_OK


def crosscheck_text(r: dict) -> str:
    """The `crosscheck` report (a CrossCheck.as_dict() with tolerance, agree)."""
    s = r["seconds"]
    wc = sum(v for k, v in s.items() if k not in ("mesh", "total") and not k.startswith("skfem"))
    sk = sum(v for k, v in s.items() if k.startswith("skfem"))
    lines = [
        f"crosscheck: {r['title']}",
        f"same mesh: {r['cells']} P2 cells, {r['dofs']} DOFs; wingcrack (DOLFINx, MUMPS) against "
        "scikit-fem (MeshTri2 isoparametric, SciPy SuperLU)",
        f"loads at load factor {r['load_factor']:g}: " + ("; ".join(r["loads"]) or "none"),
        r["left_out"],
        f"displacement: max |du| {_g(r['u_diff'])} m, max |u| {_g(r['u_max'])} m, relative {r['u_rel']:.2e}",
        f"SIFs (displacement correlation): relative {r['sif_rel']:.2e}",
    ]
    for t in r["tips"]:
        lines.append(f"  fracture {t['fracture']} end {t['end']}: KI {_g(t['KI'])} / {_g(t['KI_skfem'])}, "
                     f"KII {_g(t['KII'])} / {_g(t['KII_skfem'])} Pa m^0.5 (wingcrack / scikit-fem)")
    lines.append(f"time: mesh {s.get('mesh', 0.0):.2f} s, wingcrack {wc:.2f} s, scikit-fem {sk:.2f} s")
    lines.append(f"{'agree' if r['agree'] else 'DISAGREE'} within {r['tolerance']:g}")
    return "\n".join(lines)


class _progress(ProgressBar):
    """The CLI's bar: on stderr when it is a terminal; nothing with --quiet."""

    def __init__(self, case, quiet: bool):
        super().__init__(case.propagation.steps, show=False if quiet else None)


# ---------------------------------------------------------------- `check` output


def _g(x: float) -> str:
    return f"{x:.6g}"


def _pt(p) -> str:
    return f"({_g(p[0])}, {_g(p[1])})"


def describe(case) -> str:
    """A short human summary of what `sif`/`run` would compute for `case`."""
    m, geo, msh, pr = case.material, case.domain, case.mesh, case.propagation
    lines = [f"case: {case.title}" + (f"  [{case.source}]" if case.source else "")]
    lines.append(f"domain: {_domain_text(case)}; boundaries: {', '.join(geo.boundary_names())}")
    lines.append(
        f"material: E {_g(m.E)} Pa, nu {_g(m.nu)}, KIc {_g(m.KIc)} Pa m^0.5, plane {m.plane}, "
        f"thickness {_g(m.thickness)} m" + (f", density {_g(m.density)} kg/m^3" if m.density else "")
    )
    tips = case.tips()
    from wingcrack.case import REL_TOL

    tol = REL_TOL * case.length_scale
    mouths = sum(bool(geo.on_boundary(p, tol)) for f in case.fractures for p in (f.points[0], f.points[-1]))
    on_fractures = 2 * len(case.fractures) - len(tips) - mouths
    junctions = case.junctions()
    lines.append(
        f"fractures: {len(case.fractures)}, tips: {len(tips)}" + (f", edge-crack mouths: {mouths}" if mouths else "")
        + (f", ends on fractures: {on_fractures}" if on_fractures else "")
    )
    if junctions:
        shown = ", ".join(_pt(p) for p in junctions[:6]) + (", ..." if len(junctions) > 6 else "")
        lines.append(f"junctions (fractures meet, no tips): {len(junctions)} at {shown}")
    for i, f in enumerate(case.fractures):
        extra = f", slip {_g(f.slip)} m ({f.slip_profile})" if f.faces == "slip" else ""
        extra += f", friction {_g(f.friction)}, cohesion {_g(f.cohesion)} Pa" if f.faces == "coulomb" else ""
        extra += f", gap {_g(f.gap)} m" if f.gap else ""
        extra += f", pressure {_g(f.pressure)} Pa" if f.pressure else ""
        lines.append(
            f"  [{i}] {len(f.points)} points {_pt(f.points[0])} .. {_pt(f.points[-1])}, length {_g(f.length)} m, "
            f"faces {f.faces}{extra}, {'grows' if f.grow else 'does not grow'}"
        )
    lines.append(f"bc: {len(case.bcs)}")
    for i, bc in enumerate(case.bcs):
        place = f"at {_pt(bc.at)}" if bc.at is not None else f"on {bc.on}"
        if bc.kind == "displacement" and not all(bc.components):
            c = 0 if bc.components[0] else 1
            cond = f"displacement_{'xy'[c]} = {_g(bc.value[c])} m"
        else:
            unit = {"force": "N/m", "traction": "Pa", "displacement": "m"}[bc.kind]
            cond = f"{bc.kind} {_pt(bc.value)} {unit}"
        lines.append(f"  [{i}] {place}: {cond}")
    if any(case.body.gravity):
        lines.append(f"gravity: {_pt(case.body.gravity)} m/s^2")
    s = case.stress
    if s.sxx or s.syy or s.sxy:
        lines.append(f"initial stress: sxx {_g(s.sxx)}, syy {_g(s.syy)}, sxy {_g(s.sxy)} Pa")
    lines.append(
        f"mesh: size {_g(msh.size)} m, tip_size {_g(msh.tip_size)} m, {msh.sectors} sectors per rosette, "
        f"{'adaptive' if msh.adaptive else 'fixed'}"
    )
    load = {"scale": f"load scaled (at most x{_g(pr.max_load_factor)})",
            "pressure": f"fracture pressures scaled (injection, at most x{_g(pr.max_load_factor)})",
            "fixed": "load fixed", "injection": "driven by the pump below (every other load fixed)"}[pr.load]
    if any(f.pressure for f in case.fractures):
        load += ", connected fractures share their pressure" if pr.connect_pressure else \
            ", each fracture keeps its own pressure"
    lines.append(
        f"propagation: at most {pr.steps} steps of at most {_g(pr.length)} m, alpha {_g(pr.alpha)}, {load}"
    )
    if case.injection is not None:
        lines += _injection_text(case)
    lines.append("ok: the case is valid")
    return "\n".join(lines)


def _injection_text(case) -> list:
    """`check`'s lines on the pump: where, the schedule, the fluid."""
    from wingcrack.schedule import Schedule

    inj = case.injection
    at = inj.point if inj.point is not None else case.fractures[inj.fracture].midpoint
    joins = "the fractures its wings join enter the network" if case.propagation.connect_pressure else \
        "its wings' joins do not connect it (connect_pressure = false)"
    return [f"injection: into fracture {inj.fracture} at {_pt(at)}; {joins}",
            f"  schedule: {Schedule.of(inj).describe()}",
            f"  fluid: compressibility {_g(inj.compressibility)} 1/Pa, initial pressure {_g(inj.initial_pressure)} "
            f"Pa, residual aperture {_g(inj.residual_aperture)} m"]


def _domain_text(case) -> str:
    d = case.domain
    shape = getattr(d, "shape", "?")
    if shape == "disc":
        return f"disc, center {_pt(d.center)}, radius {_g(d.radius)} m"
    if shape == "rectangle":
        return f"rectangle, corner {_pt(d.corner)}, size {_g(d.size[0])} x {_g(d.size[1])} m"
    if shape == "polygon":
        return f"polygon with {len(d.points)} points"
    return str(shape)


if __name__ == "__main__":
    sys.exit(main())
