"""The `wingcrack` command's entry point: the console script calls main()
(and `python -m wingcrack` runs it), before anything else of wingcrack runs.

Ctrl-C or SIGTERM at any moment of the command stops it with one line and
exit status 130 or 143, never a traceback, including while it imports its
modules: wingcrack.cli brings numpy, and a signal during an import is
raised inside it (numpy's and DOLFINx's extension modules then raise an
ImportError instead: interrupt.cause). So the handlers are
installed here first, with only the interrupt and parallel modules imported
(the standard library's alone: a few milliseconds after Python's own
start-up), and the CLI is imported inside them.
"""
import sys

from wingcrack import interrupt
from wingcrack.parallel import world_rank


def main(argv=None) -> int:
    try:
        with interrupt.terminate_raises():
            from wingcrack import cli  # inside the handlers: a stop during its imports is told too

            return cli.main(argv)
    except KeyboardInterrupt as err:   # before or after the CLI's own handling
        return _stopped(err)
    except Exception as err:
        stop = interrupt.cause(err)
        if stop is None:
            raise   # the CLI cannot be imported at all: an installation without it
        return _stopped(stop)


def _stopped(err: BaseException) -> int:
    if world_rank() == 0:   # what the CLI says for a stop (rank 0 tells it)
        print(f"wingcrack: {interrupt.stop_line(err)}", file=sys.stderr)
    return interrupt.exit_code(err)


if __name__ == "__main__":
    sys.exit(main())
